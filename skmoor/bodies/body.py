"""Rigid body: mass, inertia, attachment kinematics and hydrostatics.

Conventions: SI units, global frame with z up and z = 0 at the still water line. The
body displacement is ``q = [x, y, z, rx, ry, rz]`` (m, rad) of the body's reference
point, with the rotation ``R = Rz(rz) @ Ry(ry) @ Rx(rx)``; at ``q = 0`` the body frame is
the global frame. A point fixed in the body at ``r`` (relative to the reference point)
moves to ``reference_point + q[:3] + R r``.

Two conventions of rotational load exist and must not be mixed in one model:

- *moment*: the moment about the displaced reference point, in global axes. The
  standard hydrostatic matrix (WAMIT, Newman) is its derivative; it is not symmetric
  (K46, K56 != 0 = K64, K65).
- *generalized*: the load conjugate to ``q``, ``J^T f`` for a force ``f`` at a body
  point (:func:`attachment_jacobian`), whose derivative at fixed ``f`` is
  :func:`attachment_hessian`. Hydrostatics and weight derive from a potential that does
  not depend on yaw, so their generalized stiffness is symmetric with K46 = K56 = 0.

Both agree at ``q = 0`` on the loads; the stiffnesses differ by terms in the static
moment of each load, which cancel in a model whose total static moment is zero.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numba import njit

from . import large_rotations as exact
from .large_rotations import box_triangles

__all__ = [
    "rotation_matrix",
    "attachment_displacement",
    "attachment_jacobian",
    "attachment_hessian",
    "uniform_box_inertia",
    "combined_mass",
    "point_mass_matrix",
    "Hydrostatics",
    "box_hydrostatics",
    "hull_hydrostatics",
    "hull_triangles",
    "RigidBody",
]


# --------------------------------------------------------------------------- checks

def _finite_array(name: str, value, shape: tuple) -> np.ndarray:
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected numbers of shape {shape}, got {value!r}") from None
    if arr.shape != shape:
        raise ValueError(f"{name}: expected shape {shape}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name}: contains NaN or inf")
    return arr


def _positive(name: str, value) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected a positive number, got {value!r}") from None
    if not (np.isfinite(value) and value > 0.0):
        raise ValueError(f"{name}: must be a positive finite number, got {value}")
    return value


# --------------------------------------------------------------------------- kinematics

def _axis_rotation(angle: float, axis: int) -> np.ndarray:
    """Rotation by ``angle`` about a coordinate axis and its first two derivatives, (3, 3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    i, j = (axis + 1) % 3, (axis + 2) % 3  # cyclic, so that R[i, j] = -sin
    out = np.zeros((3, 3, 3))
    out[0, axis, axis] = 1.0
    # (cos, sin) -> (-sin, cos) -> (-cos, -sin): successive derivatives
    for n, (cn, sn) in enumerate([(c, s), (-s, c), (-c, -s)]):
        out[n, i, i] = out[n, j, j] = cn
        out[n, i, j], out[n, j, i] = -sn, sn
    return out


def _rotation_derivatives(angles) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """R, dR/dangle_a (3, 3, 3) and d2R/dangle_a dangle_b (3, 3, 3, 3) of R = Rz Ry Rx."""
    return _rotation_derivatives_cached(tuple(_finite_array("angles", angles, (3,))))


@lru_cache(maxsize=8)
def _rotation_derivatives_cached(angles):
    rx, ry, rz = (_axis_rotation(angles[k], k) for k in range(3))
    # every product Rz^(c) Ry^(b) Rx^(a) of derivative orders a, b, c at once
    D = np.einsum("cij,bjk,akl->abcil", rz, ry, rx)
    d1 = np.array([D[1, 0, 0], D[0, 1, 0], D[0, 0, 1]])
    orders = np.eye(3, dtype=int)
    d2 = np.array([[D[tuple(orders[a] + orders[b])] for b in range(3)] for a in range(3)])
    for arr in (D, d1, d2):
        arr.flags.writeable = False
    return D[0, 0, 0], d1, d2


@njit(cache=True)
def rotation_and_slopes(angles):
    """R = Rz Ry Rx and dR/dangle_a (3, 3, 3) for finite ``angles`` (3,) (rad), written
    out, without input checks or caching: the time loop's fast path (compiled)."""
    ca, sa = math.cos(angles[0]), math.sin(angles[0])
    cb, sb = math.cos(angles[1]), math.sin(angles[1])
    cc, sc = math.cos(angles[2]), math.sin(angles[2])
    out = np.array((  # (a tuple: numba types it far faster than a list)
        cb * cc, sa * sb * cc - ca * sc, ca * sb * cc + sa * sc,  # R
        cb * sc, sa * sb * sc + ca * cc, ca * sb * sc - sa * cc,
        -sb, sa * cb, ca * cb,
        0.0, ca * sb * cc + sa * sc, ca * sc - sa * sb * cc,  # dR/drx
        0.0, ca * sb * sc - sa * cc, -sa * sb * sc - ca * cc,
        0.0, ca * cb, -sa * cb,
        -sb * cc, sa * cb * cc, ca * cb * cc,  # dR/dry
        -sb * sc, sa * cb * sc, ca * cb * sc,
        -cb, -sa * sb, -ca * sb,
        -cb * sc, -sa * sb * sc - ca * cc, sa * cc - ca * sb * sc,  # dR/drz
        cb * cc, sa * sb * cc - ca * sc, ca * sb * cc + sa * sc,
        0.0, 0.0, 0.0)).reshape(4, 3, 3)
    return out[0], out[1:]


@njit(cache=True)
def attachment_state(q, r):
    """Displacements q[:3] + R r - r (n, 3) of body points r (n, 3) and their stacked
    Jacobians d/dq (3 n, 6), for finite q (6,): the time loop's fast path of
    :func:`attachment_displacement` and :func:`attachment_jacobian`."""
    R, dR = rotation_and_slopes(q[3:])
    n = r.shape[0]
    displacement = np.empty((n, 3))
    J = np.zeros((3 * n, 6))
    for p in range(n):
        for k in range(3):
            moved = 0.0
            for l in range(3):
                moved += R[k, l] * r[p, l]
                for a in range(3):
                    J[3 * p + k, 3 + a] += dR[a, k, l] * r[p, l]
            displacement[p, k] = q[k] + moved - r[p, k]
            J[3 * p + k, k] = 1.0
    return displacement, J


def rotation_matrix(angles) -> np.ndarray:
    """Rotation matrix R = Rz(rz) @ Ry(ry) @ Rx(rx) for ``angles = (rx, ry, rz)`` in rad."""
    return _rotation_derivatives(angles)[0]


def attachment_displacement(q, r) -> np.ndarray:
    """Displacement (m) of body point(s) ``r`` (3,) or (n, 3): ``q[:3] + R r - r``."""
    q = _finite_array("q", q, (6,))
    r = np.asarray(r, dtype=float)
    return q[:3] + r @ rotation_matrix(q[3:]).T - r


def attachment_jacobian(q, r) -> np.ndarray:
    """Derivative of :func:`attachment_displacement` w.r.t. ``q``: (3, 6), or (n, 3, 6)."""
    q = _finite_array("q", q, (6,))
    r = np.asarray(r, dtype=float)
    d1 = _rotation_derivatives(q[3:])[1]
    jac = np.zeros(r.shape[:-1] + (3, 6))
    jac[..., :, :3] = np.eye(3)
    jac[..., :, 3:] = np.einsum("akl,...l->...ka", d1, r)
    return jac


def attachment_hessian(q, r, f) -> np.ndarray:
    """sum_k f_k d2p_k/dq dq (6, 6): derivative of ``J(q, r)^T f`` w.r.t. ``q`` at fixed ``f``.

    ``r`` and ``f`` (N) are (3,) or (n, 3); the terms of all points are summed. Only
    the rotation block is non-zero (units N m).
    """
    q = _finite_array("q", q, (6,))
    r = np.asarray(r, dtype=float).reshape(-1, 3)
    f = np.asarray(f, dtype=float).reshape(-1, 3)
    d2 = _rotation_derivatives(q[3:])[2]
    hess = np.zeros((6, 6))
    hess[3:, 3:] = np.einsum("abkl,kl->ab", d2, f.T @ r)
    return hess


def attachment_velocity_slope(q, r, qdot) -> np.ndarray:
    """d(J(q, r) qdot)/dq (3 n, 6): how the velocities of body points r (n, 3) change with
    the body DOFs q at fixed qdot (only the rotation columns are non-zero, m/s per rad)."""
    r = np.asarray(r, dtype=float).reshape(-1, 3)
    d2 = _rotation_derivatives(q[3:])[2]  # d2R/da db, (3, 3, 3, 3)
    W = np.tensordot(np.asarray(qdot, float)[3:], d2, axes=(0, 0))  # (b, k, l)
    out = np.zeros((r.shape[0], 3, 6))
    out[:, :, 3:] = (W @ r.T).transpose(2, 1, 0)  # (p, k, b)
    return out.reshape(-1, 6)


def _skew(v) -> np.ndarray:
    """Matrix S with S @ a = v x a."""
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def uniform_box_inertia(mass: float, length: float, width: float, height: float) -> np.ndarray:
    """Inertia (kg m2) about the centre of a uniform box, length along x, width along y."""
    return mass / 12.0 * np.diag(
        [width**2 + height**2, length**2 + height**2, length**2 + width**2]
    )


def combined_mass(parts):
    """(mass kg, centre of mass (3,) m, inertia about it (3, 3) kg m2) of rigidly joined
    parts, each (mass, centre (3,), own inertia about its centre (3, 3)): the masses
    summed, the inertias moved to the common centre by the parallel-axis theorem
    (I = sum I_i + m_i (|d_i|^2 E - d_i d_i^T)). A point mass has a zero own inertia."""
    parts = [(float(m), np.asarray(c, float), np.asarray(i, float)) for m, c, i in parts]
    mass = sum(m for m, _, _ in parts)
    centre = (sum(m * c for m, c, _ in parts) / mass if mass > 0 else np.zeros(3))
    inertia = np.zeros((3, 3))
    for m, c, own in parts:
        d = c - centre
        inertia += own + m * (d @ d * np.eye(3) - np.outer(d, d))
    return mass, centre, 0.5 * (inertia + inertia.T)


def point_mass_matrix(mass: float, offset) -> np.ndarray:
    """(6, 6) mass matrix (kg, kg m, kg m2) about a reference point of a point mass (kg)
    at ``offset`` (m) from it: [[m E, -m S], [m S, -m S S]], S = skew(offset)
    (Sadeghi and Incecik's translation of a 3x3 mass, MoorDyn's translateMass)."""
    s = _skew(np.asarray(offset, float))
    return mass * np.block([[np.eye(3), -s], [s, -s @ s]])


# --------------------------------------------------------------------------- hydrostatics

def _vertical_load_stiffness(weight: float, r, generalized: bool) -> np.ndarray:
    """Stiffness (6, 6) of the load -weight e_z (N) at ``r`` (m) from the reference point."""
    k = np.zeros((6, 6))
    k[3, 3] = k[4, 4] = -weight * r[2]
    if not generalized:
        k[3, 5], k[4, 5] = weight * r[0], weight * r[1]
    return k


@dataclass
class Hydrostatics:
    """Hydrostatic properties of a hull in its floating position (still water, z = 0).

    reference_point            (3,)  point (global, m) about which moments are taken
    volume                     float displaced volume V, m3
    center_of_buoyancy         (3,)  centre of the displaced volume, global, m
    waterplane_area            float Awp, m2
    waterplane_first_moments   (2,)  [int x dA, int y dA], m3
    waterplane_second_moments  (3,)  [int x^2 dA, int y^2 dA, int x y dA], m4
    x, y in the waterplane integrals are measured from the reference point.
    """

    reference_point: np.ndarray
    volume: float
    center_of_buoyancy: np.ndarray
    waterplane_area: float
    waterplane_first_moments: np.ndarray
    waterplane_second_moments: np.ndarray

    def __post_init__(self):
        for name, shape in [("reference_point", (3,)), ("center_of_buoyancy", (3,)),
                            ("waterplane_first_moments", (2,)),
                            ("waterplane_second_moments", (3,))]:
            setattr(self, name, _finite_array(f"Hydrostatics.{name}", getattr(self, name), shape))
        self.volume = _positive("Hydrostatics.volume", self.volume)
        self.waterplane_area = float(self.waterplane_area)
        if not (math.isfinite(self.waterplane_area) and self.waterplane_area >= 0):
            raise ValueError("Hydrostatics.waterplane_area: must be a finite number >= 0 m2 "
                             f"(0 for a submerged body), got {self.waterplane_area}")

    @classmethod
    def submerged(cls, volume: float, center_of_buoyancy, reference_point) -> "Hydrostatics":
        """A fully submerged body of ``volume`` (m3) buoyant at ``center_of_buoyancy``
        (global, m): no waterplane (MoorDyn's and MoorPy's body Volume)."""
        return cls(reference_point, volume, center_of_buoyancy, 0.0, np.zeros(2), np.zeros(3))

    def stiffness(self, mass: float, center_of_mass, rho: float = 1025.0, g: float = 9.81,
                  generalized: bool = False) -> np.ndarray:
        """Linear hydrostatic + gravity restoring matrix K (6, 6) about the reference point.

        ``mass`` in kg, ``center_of_mass`` global (m), ``rho`` kg/m3, ``g`` m/s2. With
        ``generalized=False`` K is the WAMIT / Newman matrix (moments about the displaced
        reference point); with ``generalized=True`` it is the derivative of the load
        conjugate to ``q`` (K46 = K56 = 0), consistent with :func:`attachment_hessian`.
        """
        sx, sy = self.waterplane_first_moments
        ixx, iyy, ixy = self.waterplane_second_moments  # int x^2, int y^2, int xy
        k = np.zeros((6, 6))
        k[2, 2] = self.waterplane_area
        k[2, 3] = k[3, 2] = sy
        k[2, 4] = k[4, 2] = -sx
        k[3, 3], k[4, 4] = iyy, ixx
        k[3, 4] = k[4, 3] = -ixy
        k *= rho * g
        r_b = self.center_of_buoyancy - self.reference_point
        r_g = np.asarray(center_of_mass, dtype=float) - self.reference_point
        k += _vertical_load_stiffness(-rho * g * self.volume, r_b, generalized)
        k += _vertical_load_stiffness(mass * g, r_g, generalized)
        return k


def box_hydrostatics(length: float, width: float, height: float, draft: float,
                     reference_point=(0.0, 0.0, 0.0), center_xy=(0.0, 0.0)) -> Hydrostatics:
    """Analytic hydrostatics of an axis-aligned box (m) floating upright.

    Length along x, width along y, bottom at z = -draft, plan centre at ``center_xy``.
    """
    length = _positive("length", length)
    width = _positive("width", width)
    height = _positive("height", height)
    draft = _positive("draft", draft)
    if draft >= height:
        raise ValueError(f"draft: {draft} m must be less than the box height {height} m")
    ref = _finite_array("reference_point", reference_point, (3,))
    cx, cy = _finite_array("center_xy", center_xy, (2,)) - ref[:2]
    area = length * width
    return Hydrostatics(
        reference_point=ref,
        volume=area * draft,
        center_of_buoyancy=np.array([cx + ref[0], cy + ref[1], -draft / 2]),
        waterplane_area=area,
        waterplane_first_moments=area * np.array([cx, cy]),
        waterplane_second_moments=area * np.array(
            [cx**2 + length**2 / 12, cy**2 + width**2 / 12, cx * cy]
        ),
    )


def _as_polydata(mesh):
    """A pyvista PolyData from a PolyData, a meshio.Mesh, a pyvista grid or a file path."""
    import pyvista as pv

    if isinstance(mesh, (str, os.PathLike)):
        if not os.path.isfile(mesh):
            raise FileNotFoundError(f"mesh: no such file: {os.fspath(mesh)}")
        mesh = pv.read(mesh)
    else:
        mesh = pv.wrap(mesh)
    if isinstance(mesh, pv.PolyData):
        return mesh
    if isinstance(mesh, pv.UnstructuredGrid):
        faces = [np.column_stack([np.full(len(conn), conn.shape[1]), conn]).ravel()
                 for kind, conn in mesh.cells_dict.items()
                 if kind in (pv.CellType.TRIANGLE, pv.CellType.QUAD, pv.CellType.POLYGON)]
        if faces:
            return pv.PolyData(mesh.points, np.concatenate(faces))
    raise ValueError(f"mesh: expected a triangulated surface, got {type(mesh).__name__}")


def _hull_surface(mesh, offset):
    """The closed hull surface moved by ``offset`` (m): triangulated, duplicate points
    merged, faces oriented outward (ValueError when it is not watertight)."""
    surf = _as_polydata(mesh).triangulate()  # a new mesh: the input is left as it is
    if surf.n_cells == 0:
        raise ValueError("mesh: the surface has no faces")
    surf.points = np.asarray(surf.points, dtype=float) + offset
    if not np.all(np.isfinite(surf.points)):
        raise ValueError("mesh: point coordinates contain NaN or inf")
    surf = surf.clean()
    bad = surf.extract_feature_edges(boundary_edges=True, non_manifold_edges=True,
                                     feature_edges=False, manifold_edges=False).n_cells
    if bad:
        raise ValueError(f"mesh: the hull surface is not closed ({bad} open or non-manifold "
                         "edges); hydrostatics need a watertight surface")
    return surf.compute_normals(cell_normals=True, point_normals=False,
                                consistent_normals=True, auto_orient_normals=True)


def hull_hydrostatics(mesh, reference_point=(0.0, 0.0, 0.0),
                      offset=(0.0, 0.0, 0.0)) -> Hydrostatics:
    """Hydrostatics of a closed hull surface (pyvista PolyData, meshio.Mesh or file path).

    The surface is moved by ``offset`` (m, done in double precision) into its floating
    position; duplicate points are merged and the faces oriented outward. It is clipped at
    z = 0, and the displaced volume, its centroid and the waterplane integrals are computed
    exactly for the triangulated surface (divergence theorem on the wetted faces; the
    waterplane cap at z = 0 needs no triangulation).
    """
    ref = _finite_array("reference_point", reference_point, (3,))
    surf = _hull_surface(mesh, _finite_array("offset", offset, (3,)))
    zmin, zmax = surf.bounds[4], surf.bounds[5]
    if zmin >= 0.0:
        raise ValueError(f"mesh: the hull does not reach below the waterline (lowest z = {zmin} m)")
    if zmax <= 0.0:
        raise ValueError(f"mesh: the hull is fully submerged (highest z = {zmax} m), "
                         "it has no waterplane")
    wet = surf.clip(normal="z", origin=(0.0, 0.0, 0.0), invert=True).triangulate()

    pts = np.asarray(wet.points, dtype=float) - np.array([ref[0], ref[1], 0.0])
    tri = pts[wet.faces.reshape(-1, 4)[:, 1:]]  # (n, 3 vertices, 3 coords)
    area_z = 0.5 * np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])[:, 2]  # n_z dS
    x, y, z = tri[..., 0], tri[..., 1], tri[..., 2]
    one = np.ones_like(x)

    def integral(a, b):
        """Exact sum over faces of int a b n_z dS for a, b linear on each face."""
        return area_z @ (np.einsum("ij,ij->i", a, b) + a.sum(1) * b.sum(1)) / 12.0

    # int_V div(F) = oint F.n with F = (0, 0, z * phi); the cap at z = 0 adds nothing.
    volume = integral(z, one)
    # oint phi n_z dS = 0 over the closed wetted volume: cap integrals = -wetted ones.
    area = -integral(one, one)
    if volume <= 0.0 or area <= 0.0:
        raise ValueError(f"mesh: degenerate wetted part (volume {volume} m3, waterplane "
                         f"area {area} m2)")
    centroid = np.array([integral(x, z), integral(y, z), integral(z, z) / 2.0]) / volume
    return Hydrostatics(
        reference_point=ref,
        volume=volume,
        center_of_buoyancy=centroid + np.array([ref[0], ref[1], 0.0]),
        waterplane_area=area,
        waterplane_first_moments=-np.array([integral(x, one), integral(y, one)]),
        waterplane_second_moments=-np.array([integral(x, x), integral(y, y), integral(x, y)]),
    )


def hull_triangles(mesh, reference_point, offset=(0.0, 0.0, 0.0)) -> np.ndarray:
    """The closed hull surface moved by ``offset`` as outward triangles (n, 3, 3) relative
    to ``reference_point`` (m): :attr:`RigidBody.hull`."""
    hull = _hull_surface(mesh, _finite_array("offset", offset, (3,)))
    points = np.asarray(hull.points, float)[hull.faces.reshape(-1, 4)[:, 1:]]
    return points - _finite_array("reference_point", reference_point, (3,))


# --------------------------------------------------------------------------- rigid body

_NEEDS_HULL = ("rotations: 'exact' needs the hull geometry of a surface-piercing body "
               "(build it with RigidBody.box or RigidBody.from_hull, or give hull)")


@dataclass
class RigidBody:
    """A 6-DOF rigid body.

    mass             kg
    center_of_mass   (3,) global position at q = 0, m
    inertia          (3, 3) about the centre of mass, global axes, kg m2
    reference_point  (3,) global, m; the point whose motion q describes (default: CoM)
    hydrostatics     Hydrostatics about ``reference_point``, or None (no buoyancy)
    added_mass       (6, 6) about the reference point, kg / kg m / kg m2 (kept apart
                     from :meth:`mass_matrix`)
    linear_damping   (6, 6) about the reference point, N s/m, N s, N m s
    rho, g           water density kg/m3, gravity m/s2
    box_size         (3,) box dimensions (m) for drawing, or None
    box_center       (3,) box centre relative to the reference point (m), for drawing
    rotations        'small': the constant mass matrix at q = 0 and the linear
                     hydrostatic stiffness (the paper's model); 'exact': the inertia,
                     gyroscopic terms and hydrostatics at the current pose
                     (:mod:`skmoor.bodies.large_rotations`)
    hull             (n, 3, 3) closed hull as outward triangles relative to the
                     reference point at q = 0 (m): the geometry 'exact' clips at z = 0
                     (set by :meth:`box` and :meth:`from_hull`)
    line_of_masses   True: the inertia may be zero about one axis (all the body's mass on
                     one line; a term must hold its rotation about it, as the deck reader's
                     spring does), else it must be positive definite
    """

    mass: float
    center_of_mass: np.ndarray
    inertia: np.ndarray
    reference_point: np.ndarray | None = None
    hydrostatics: Hydrostatics | None = None
    added_mass: np.ndarray | None = None
    linear_damping: np.ndarray | None = None
    rho: float = 1025.0
    g: float = 9.81
    box_size: np.ndarray | None = None
    box_center: np.ndarray | None = None
    rotations: str = "small"
    hull: np.ndarray | None = None
    line_of_masses: bool = False

    def __post_init__(self):
        self.mass = _positive("mass", self.mass)
        self.rho = _positive("rho", self.rho) if self.rho != 0 else 0.0  # 0: in air
        self.g = _positive("g", self.g) if self.g != 0 else 0.0  # 0: no gravity
        self.center_of_mass = _finite_array("center_of_mass", self.center_of_mass, (3,))
        self.reference_point = (self.center_of_mass.copy() if self.reference_point is None
                                else _finite_array("reference_point", self.reference_point, (3,)))
        inertia = _finite_array("inertia", self.inertia, (3, 3))
        if not np.allclose(inertia, inertia.T, rtol=1e-10, atol=0.0):
            raise ValueError("inertia: must be symmetric")
        principal = np.linalg.eigvalsh(inertia)
        if self.line_of_masses:  # one principal inertia zero (to round-off), no more
            if principal[0] < -1e-12 * principal[-1] or principal[1] <= 0.0:
                raise ValueError("inertia: must be positive semi-definite with one zero "
                                 "principal inertia at most (line_of_masses)")
        elif principal[0] <= 0.0:
            raise ValueError("inertia: must be positive definite")
        self.inertia = inertia
        for name in ("added_mass", "linear_damping"):
            value = getattr(self, name)
            setattr(self, name, np.zeros((6, 6)) if value is None
                    else _finite_array(name, value, (6, 6)))
        if self.box_size is not None:
            self.box_size = _finite_array("box_size", self.box_size, (3,))
        self.box_center = (np.zeros(3) if self.box_center is None
                           else _finite_array("box_center", self.box_center, (3,)))
        if self.hydrostatics is not None and not np.allclose(
                self.hydrostatics.reference_point, self.reference_point):
            raise ValueError(f"hydrostatics: computed about {self.hydrostatics.reference_point}, "
                             f"but the body's reference_point is {self.reference_point}")
        self._check_rotations()

    def _check_rotations(self):
        if self.rotations not in ("small", "exact"):
            raise ValueError(f"rotations: {self.rotations!r} is not 'small' or 'exact'")
        if self.hull is not None:
            hull = np.array(self.hull, dtype=float)
            if hull.ndim != 3 or hull.shape[1:] != (3, 3) or not np.all(np.isfinite(hull)):
                raise ValueError(f"hull: expected finite triangles of shape (n, 3, 3), got "
                                 f"shape {hull.shape}")
            self.hull = hull
        if (self.rotations == "exact" and self.hull is None and self.hydrostatics is not None
                and self.hydrostatics.waterplane_area > 0):
            raise ValueError(_NEEDS_HULL)

    @classmethod
    def box(cls, length: float, width: float, height: float, mass: float, draft: float,
            reference_point=None, **kwargs) -> "RigidBody":
        """Uniform box (m, kg), length along x, bottom at z = -draft, centred on x = y = 0.

        Centre of mass at the box centre; the reference point defaults to it. Other
        keyword arguments (added_mass, linear_damping, rho, g) go to :class:`RigidBody`.
        """
        center = np.array([0.0, 0.0, _positive("height", height) / 2 - _positive("draft", draft)])
        ref = center if reference_point is None else _finite_array(
            "reference_point", reference_point, (3,))
        return cls(
            mass=mass,
            center_of_mass=center,
            inertia=uniform_box_inertia(mass, length, width, height),
            reference_point=ref,
            hydrostatics=box_hydrostatics(length, width, height, draft, reference_point=ref),
            box_size=np.array([length, width, height], dtype=float),
            box_center=center - ref,
            hull=box_triangles([length, width, height], center - ref),
            **kwargs,
        )

    @classmethod
    def from_hull(cls, mesh, mass: float, center_of_mass, inertia, reference_point=None,
                  offset=(0.0, 0.0, 0.0), **kwargs) -> "RigidBody":
        """Body with hydrostatics of a closed hull surface (see :func:`hull_hydrostatics`).

        ``center_of_mass`` and ``reference_point`` are global (after ``offset``); other
        keyword arguments go to :class:`RigidBody`.
        """
        ref = _finite_array("reference_point", center_of_mass if reference_point is None
                            else reference_point, (3,))
        return cls(mass=mass, center_of_mass=center_of_mass, inertia=inertia,
                   reference_point=ref,
                   hydrostatics=hull_hydrostatics(mesh, reference_point=ref, offset=offset),
                   hull=hull_triangles(mesh, ref, offset), **kwargs)

    def mass_matrix(self) -> np.ndarray:
        """Rigid-body mass matrix (6, 6) about the reference point (small rotations)."""
        s = _skew(self.center_of_mass - self.reference_point)
        m = np.zeros((6, 6))
        m[:3, :3] = self.mass * np.eye(3)
        m[:3, 3:] = -self.mass * s
        m[3:, :3] = self.mass * s
        m[3:, 3:] = self.inertia - self.mass * s @ s
        return m

    def hydrostatic_stiffness(self, generalized: bool = False) -> np.ndarray:
        """Hydrostatic + gravity restoring matrix (6, 6), see :meth:`Hydrostatics.stiffness`."""
        if self.hydrostatics is None:
            return _vertical_load_stiffness(self.mass * self.g,
                                            self.center_of_mass - self.reference_point,
                                            generalized)
        return self.hydrostatics.stiffness(self.mass, self.center_of_mass, self.rho, self.g,
                                           generalized)

    def static_force(self) -> np.ndarray:
        """Buoyancy + weight at q = 0: [F, M] (N, N m), moments about the reference point."""
        weight = np.array([0.0, 0.0, -self.mass * self.g])
        load = np.zeros(6)
        load[:3] = weight
        load[3:] = np.cross(self.center_of_mass - self.reference_point, weight)
        if self.hydrostatics is not None:
            buoyancy = np.array([0.0, 0.0, self.rho * self.g * self.hydrostatics.volume])
            load[:3] += buoyancy
            load[3:] += np.cross(self.hydrostatics.center_of_buoyancy - self.reference_point,
                                 buoyancy)
        return load

    # --- large rotations (rotations='exact'), see skmoor.bodies.large_rotations
    def rotation(self, q, frame=None) -> np.ndarray:
        """R(q) = Rz Ry Rx(q[3:]) @ frame (3, 3): the attitude of a body whose angles are
        counted from ``frame`` (the turned start frame of a re-based body; None: the
        global frame, the body's frame at q = 0)."""
        R = rotation_and_slopes(q[3:])[0]
        return R if frame is None else R @ frame

    def restoring_load(self, q, frame=None) -> np.ndarray:
        """Buoyancy + weight at pose ``q`` (angles from ``frame``, :meth:`rotation`) as the
        load conjugate to q (N, N m): the hull clipped at z = 0 (a submerged body without
        a hull: its volume at its body-fixed centre of buoyancy)."""
        R = self.rotation(q, frame)
        origin = self.reference_point + q[:3]
        weight = np.array([0.0, 0.0, -self.mass * self.g])
        force = weight.copy()
        moment = exact.cross3(R @ (self.center_of_mass - self.reference_point), weight)
        if self.hydrostatics is not None:
            if self.hull is not None:
                volume, centroid = exact.submerged_volume(origin + self.hull @ R.T)
                arm = centroid - origin
            elif self.hydrostatics.waterplane_area > 0:  # rotations set after construction
                raise ValueError(_NEEDS_HULL)
            else:
                volume = self.hydrostatics.volume
                arm = R @ (self.hydrostatics.center_of_buoyancy - self.reference_point)
            buoyancy = np.array([0.0, 0.0, self.rho * self.g * volume])
            force += buoyancy
            moment += exact.cross3(arm, buoyancy)
        return exact.generalized_load(q[3:], force, moment)

    def restoring_stiffness(self, q, frame=None) -> np.ndarray:
        """-d(restoring_load)/dq (6, 6), exact: a rigid motion u(p) = dx + dtheta x (p -
        x_ref), dtheta = E dphi, changes the displaced volume by -int_WP u_z dA and its
        first moment about x_ref by dtheta x (V a_B) - int_WP (p - x_ref) u_z dA (the
        waterplane WP at the pose; a submerged body without a hull: by the rotation
        only); a horizontal shift moves buoyancy, weight and x_ref together."""
        R = self.rotation(q, frame)
        origin = self.reference_point + q[:3]
        weight = np.array([0.0, 0.0, -self.mass * self.g])
        arm_G = R @ (self.center_of_mass - self.reference_point)
        volume, arm_B, plane = 0.0, np.zeros(3), np.zeros(6)  # no buoyancy
        if self.hydrostatics is not None:
            if self.hull is not None:
                volume, centroid, plane = exact.submerged_hull(origin + self.hull @ R.T)
                arm_B = centroid - origin if volume > 0 else np.zeros(3)
            elif self.hydrostatics.waterplane_area > 0:
                raise ValueError(_NEEDS_HULL)
            else:
                volume = self.hydrostatics.volume
                arm_B = R @ (self.hydrostatics.center_of_buoyancy - self.reference_point)
        rho_g = self.rho * self.g
        xr, yr, zr = origin
        area, sx, sy, sxx, syy, sxy = plane
        ax, ay = sx - area * xr, sy - area * yr  # waterplane moments about x_ref
        axx = sxx - 2 * xr * sx + area * xr * xr
        ayy = syy - 2 * yr * sy + area * yr * yr
        axy = sxy - yr * sx - xr * sy + area * xr * yr
        moment_y = np.array([axy, ayy, -zr * ay])  # int (p - x_ref) (y - y_ref) dA
        moment_x = np.array([axx, axy, -zr * ax])  # int (p - x_ref) (x - x_ref) dA
        lift = np.array([0.0, 0.0, 1.0])
        E, dE_dry, dE_drz = exact.rate_matrix(q[3:])
        moment = (exact.cross3(arm_B, rho_g * volume * lift)
                  + exact.cross3(arm_G, weight))  # about x_ref, global
        dQ = np.zeros((6, 6))
        # heave: the waterplane rises through the hull
        d_first = -np.array([ax, ay, -zr * area])  # d(V a_B)/dz
        dQ[2, 2] = -rho_g * area
        dQ[3:, 2] = E.T @ exact.cross3(rho_g * d_first, lift)
        for a, dE in enumerate((np.zeros((3, 3)), dE_dry, dE_drz)):
            turn = E[:, a]  # dtheta per unit dphi_a
            d_volume = -(turn[0] * ay - turn[1] * ax)
            d_first = (exact.cross3(turn, volume * arm_B)
                       - (turn[0] * moment_y - turn[1] * moment_x))
            d_moment = (exact.cross3(rho_g * d_first, lift)
                        + exact.cross3(exact.cross3(turn, arm_G), weight))
            dQ[2, 3 + a] = rho_g * d_volume
            dQ[3:, 3 + a] = dE.T @ moment + E.T @ d_moment
        return -dQ

    def inertia_load(self, q, qdot, qddot, frame=None) -> np.ndarray:
        """Exact inertia + gyroscopic load conjugate to q (N, N m) at pose q, DOF rates
        qdot and accelerations qddot (:func:`skmoor.bodies.large_rotations.inertia_load`)."""
        return exact.inertia_load(self.rotation(q, frame), q, qdot, qddot, self.mass,
                                  self.inertia, self.center_of_mass - self.reference_point)

    def inertia_tangents(self, q, qdot, qddot, frame=None, step: float = 1e-6):
        """Derivatives of :meth:`inertia_load` (6, 6 each): d/dqddot (the exact mass
        matrix), d/dqdot (gyroscopic; exact central differences, the load is quadratic
        in qdot) and d/dq (central differences of ``step`` rad in the angles)."""
        arm = self.center_of_mass - self.reference_point
        mass = exact.exact_mass_matrix(self.rotation(q, frame), q, self.mass, self.inertia, arm)
        d_rate = np.zeros((6, 6))
        d_pose = np.zeros((6, 6))
        scale = 1.0 + np.max(np.abs(qdot[3:]))
        for k in range(3, 6):
            e = np.zeros(6)
            e[k] = scale
            d_rate[:, k] = (self.inertia_load(q, qdot + e, qddot, frame)
                            - self.inertia_load(q, qdot - e, qddot, frame)) / (2 * scale)
            e[k] = step
            d_pose[:, k] = (self.inertia_load(q + e, qdot, qddot, frame)
                            - self.inertia_load(q - e, qdot, qddot, frame)) / (2 * step)
        return mass, d_rate, d_pose

    def step_inertia_load(self, q1, qdot1, q0, qdot0, load0, h, gamma, frame=None) -> np.ndarray:
        """Inertia load (N, N m) at the end of a time step of h (s) from (q0, qdot0) with
        inertia load ``load0``, in momentum form
        (:func:`skmoor.bodies.large_rotations.momentum_inertia_load`)."""
        return exact.momentum_inertia_load(
            self.rotation(q1, frame), q1, qdot1, self._step_start(q0, qdot0, load0, frame),
            h, gamma, self.mass, self.inertia, self.center_of_mass - self.reference_point)

    def _step_start(self, q0, qdot0, load0, frame):
        """:func:`skmoor.bodies.large_rotations.step_start`, kept for the step's iterations."""
        key = (q0.tobytes(), qdot0.tobytes(), load0.tobytes(),
               None if frame is None else frame.tobytes())
        cached = getattr(self, "_start_cache", (None, None))
        if cached[0] != key:
            cached = (key, exact.step_start(
                self.rotation(q0, frame), q0, qdot0, load0, self.mass, self.inertia,
                self.center_of_mass - self.reference_point))
            self._start_cache = cached
        return cached[1]

    def step_inertia_tangents(self, q1, qdot1, q0, qdot0, load0, h, gamma, frame=None):
        """Derivatives (6, 6 each) of :meth:`step_inertia_load` in qdot1 and in q1
        (:func:`skmoor.bodies.large_rotations.momentum_inertia_tangents`)."""
        return exact.momentum_inertia_tangents(
            self.rotation(q1, frame), q1, qdot1, self._step_start(q0, qdot0, load0, frame),
            h, gamma, self.mass, self.inertia, self.center_of_mass - self.reference_point)
