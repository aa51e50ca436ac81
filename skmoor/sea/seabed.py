"""Sea-bed contact: a penalty spring-damper normal to a flat or sloped plane and
regularised Coulomb friction, as scikit-fem forms and as a compiled kernel.

The bed is the plane through (0, 0, -depth) rising at ``slope_deg`` towards
``slope_heading_deg``, with upward unit normal n, or a :class:`Bathymetry` z_b(x, y),
whose tangent plane under each node (normal n, point P0 = (x, y, z_b)) stands in for
the plane there (the compiled kernel only; the tangents neglect the bed's curvature).
At a point x = X + u of the line (X reference position, u displacement, m) the
penetration is g = n.(P0 - x) (m, > 0 in contact). While g > 0 the bed pushes along n with k g - c (n.udot) Hc(g) per unit
length (k in N/m2, c in N s/m2; MoorDyn-C's linear spring-damper, which, as there, may
pull while the line lifts off quickly), its damping faded in over the first
``damping_onset`` m of penetration: Hc(g) = clip(g / onset, 0, 1). MoorDyn's damping
(Hc = H, onset 0) jumps by c |n.udot| where a moving node touches the bed: an explicit
code steps over the jump, but the implicit step's equations then have no root and
Newton cycles between its two sides; with the fade-in the force is continuous.
Friction takes the spring part N = k g as its normal force and opposes the slip
velocity v_t = P udot (P = I - n n^T) along the line's current tangent projected on
the bed, a = P r' / |P r'| (r' = X' + u'), and across it:

    f = -N [mu_a phi(v_a) a + mu_l v_l / sqrt(|v_l|^2 + v0^2)],  phi(s) = s / sqrt(s^2 + v0^2),
    v_a = a.v_t,  v_l = v_t - v_a a.

The square-root regularisation (rather than MoorDyn's linear ramp with a kink where it
saturates) keeps the residual smooth, so Newton keeps converging quadratically in the
implicit integrator; the force is 99.5 % of mu N at a slip of 10 v0. Friction acts on
velocities only: a static solve (udot = 0) sees none.

Quadrature is nodal (Gauss-Lobatto: points 0 and 1 of each element, weights 1/2), i.e.
lumped contact as MoorDyn's: each node is one spring-damper carrying its share of the
two elements' lengths, as the lumped mass. With Gauss points a P1 element that is partly
on the bed couples its nodes, giving pulling (negative) nodal reactions next to the
touchdown and a contact status that switches inside elements; nodal points give pushing
nodal reactions, one contact decision per node and a node-diagonal normal tangent.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import carray, njit
from skfem import BilinearForm, LinearForm

from ..fem import ops
from ..fem.form_compiler import compiled_when_asked
from ..fem.native_calls import advanced
from ..fem.ops import d_ds, dot
from ..fem.patterns import NO_BLOCKS
from ..fem.terms import LineForm, Term
from ..numerics.validation import check_finite, check_positive
from .water_grids import cell, interpolation

DEFAULT_PENETRATION = 1e-3  # m: the default stiffness lets the heaviest line sink this far
STATIC_FRICTION = (None, "as-laid", "reference")  # Seabed.static_friction
_VERTICAL = 1e-12  # |P r'| below which an element stands on the bed: no axial direction


class Bathymetry:
    """A sea bed of heights z_b(x, y) (m, up) on a rectilinear grid: increasing x (nx,)
    and y (ny,) in m, heights (nx, ny); bilinear in each cell and held at the edge values
    beyond the grid (MoorDyn's seafloor file, source/Seafloor.cpp). Its normal at (x, y)
    is (-dz_b/dx, -dz_b/dy, 1) normalised, of the cell's bilinear patch (slopes zero
    along an axis beyond the grid's ends)."""

    def __init__(self, x, y, heights, source="Bathymetry"):
        self.x, self.y = np.asarray(x, float), np.asarray(y, float)
        self.heights = np.asarray(heights, float)
        for name, axis in (("x", self.x), ("y", self.y)):
            if axis.ndim != 1 or axis.size < 1:
                raise ValueError(f"{source}: {name} must be a list of coordinates")
            check_finite(f"{source} {name}", axis)
            if np.any(np.diff(axis) <= 0):
                raise ValueError(f"{source}: the {name} coordinates must increase strictly, "
                                 f"got {axis.tolist()}")
        if self.heights.shape != (self.x.size, self.y.size):
            raise ValueError(f"{source}: heights of shape {self.heights.shape}, expected "
                             f"({self.x.size}, {self.y.size})")
        check_finite(f"{source} heights", self.heights)
        if np.any(self.heights >= 0):
            raise ValueError(f"{source}: the bed must lie below the still water line (z < 0)")
        self.mean_height = float(self.heights.mean())

    def _cells(self, xy):
        xy = np.asarray(xy, float)
        return interpolation(self.x, xy[..., 0]), interpolation(self.y, xy[..., 1]), xy

    def height(self, xy) -> np.ndarray:
        """z_b (m) at horizontal positions xy (..., 2 or 3)."""
        (i0, i1, fx), (j0, j1, fy), _ = self._cells(xy)
        z = self.heights
        return ((1 - fx) * ((1 - fy) * z[i0, j0] + fy * z[i0, j1])
                + fx * ((1 - fy) * z[i1, j0] + fy * z[i1, j1]))

    def slopes(self, xy) -> np.ndarray:
        """(..., 2) dz_b/dx, dz_b/dy of the bilinear patch under xy."""
        (i0, i1, fx), (j0, j1, fy), xy = self._cells(xy)
        z = self.heights
        out = np.zeros(xy.shape[:-1] + (2,))
        if self.x.size > 1:
            inside = (xy[..., 0] > self.x[0]) & (xy[..., 0] < self.x[-1])
            out[..., 0] = inside * ((1 - fy) * (z[i1, j0] - z[i0, j0]) + fy * (
                z[i1, j1] - z[i0, j1])) / (self.x[i1] - self.x[i0])
        if self.y.size > 1:
            inside = (xy[..., 1] > self.y[0]) & (xy[..., 1] < self.y[-1])
            out[..., 1] = inside * ((1 - fx) * (z[i0, j1] - z[i0, j0]) + fx * (
                z[i1, j1] - z[i1, j0])) / (self.y[j1] - self.y[j0])
        return out

    def normal(self, xy) -> np.ndarray:
        """(..., 3) upward unit normal under xy."""
        s = self.slopes(xy)
        n = np.concatenate([-s, np.ones(s.shape[:-1] + (1,))], axis=-1)
        return n / np.linalg.norm(n, axis=-1, keepdims=True)

    def plane(self, points):
        """The bed's tangent plane under points (..., 3): its normal n (..., 3) and n.P
        (...), P = (x, y, z_b(x, y)): the penetration is n.P - n.x = n_z (z_b - z)."""
        points = np.asarray(points, float)
        n = self.normal(points)
        offset = (n[..., 0] * points[..., 0] + n[..., 1] * points[..., 1]
                  + n[..., 2] * self.height(points))
        return np.ascontiguousarray(n), np.ascontiguousarray(offset)


@dataclass
class Seabed:
    """A plane sea bed with penalty contact and friction.

    depth: m below z = 0 at x = y = 0. stiffness: normal force per unit line length (of
    the reference arclength s) per metre of penetration, N/m2 (default: the heaviest line's submerged weight per length
    over 1 mm). damping: N s/m2 per unit length (default: critical, 2 sqrt(k m) with the
    heaviest line's mass per length). mu_axial, mu_lateral: friction coefficients along
    and across the line. slope_deg: rise of the plane, degrees, towards the horizontal
    heading slope_heading_deg (degrees from +x towards +y). friction_velocity: slip
    velocity v0 of the regularisation, m/s. damping_onset: penetration over which the
    damping fades in, m (default: a tenth of the largest static penetration w / k;
    0: MoorDyn's jump at touchdown). per_diameter: stiffness and damping are pressures
    (Pa/m, Pa s/m) on each line's diameter, as MoorDyn's kBot and cBot.
    static_friction: the friction of a static solve, which has no velocities: None (no
    friction in statics), 'as-laid' (each node's slip counted from the line laid on the
    bed without tension, straight from its end A along the bed to where the node lies
    in the reference: MoorPy's catenary with CB = mu_axial, the laid part's tension
    falling by mu w per metre from the touchdown towards the anchor, down to 0) or
    'reference' (the slip counted from the reference state as built). The static
    friction is the dynamic one with the slip (m) in place of the slip velocity and
    static_slip (m) in place of friction_velocity: the force is 99.5 % of mu N at a slip
    of 10 static_slip.
    """

    depth: float
    stiffness: float | None = None
    damping: float | None = None
    mu_axial: float = 0.0
    mu_lateral: float = 0.0
    slope_deg: float = 0.0
    slope_heading_deg: float = 0.0
    friction_velocity: float = 1e-3
    damping_onset: float | None = None
    per_diameter: bool = False
    bathymetry: Bathymetry | None = None
    static_friction: str | None = None
    static_slip: float = 1e-5

    def __post_init__(self):
        check_positive("Seabed.depth", self.depth)
        if self.bathymetry is not None:
            if not isinstance(self.bathymetry, Bathymetry):
                raise ValueError(f"Seabed.bathymetry: expected a Bathymetry or None, got "
                                 f"{type(self.bathymetry).__name__}")
            if self.slope_deg != 0:
                raise ValueError("Seabed.slope_deg: give a slope or a bathymetry, not both")
        if self.stiffness is not None:
            check_positive("Seabed.stiffness", self.stiffness)
        for name in ("damping", "mu_axial", "mu_lateral", "damping_onset"):
            value = getattr(self, name)
            if value is not None:
                check_finite(f"Seabed.{name}", value)
                if value < 0:
                    raise ValueError(f"Seabed.{name}: must not be negative, got {value!r}")
        check_finite("Seabed.slope_heading_deg", self.slope_heading_deg)
        check_finite("Seabed.slope_deg", self.slope_deg)
        if not 0.0 <= self.slope_deg < 90.0:
            raise ValueError(f"Seabed.slope_deg: must lie in [0, 90), got {self.slope_deg!r}")
        check_positive("Seabed.friction_velocity", self.friction_velocity)
        check_positive("Seabed.static_slip", self.static_slip)
        if self.static_friction not in STATIC_FRICTION:
            raise ValueError(f"Seabed.static_friction: {self.static_friction!r} is not one of "
                             f"{', '.join(map(repr, STATIC_FRICTION))}")

    @classmethod
    def from_moordyn(cls, depth, diameter, kBot=3.0e6, cBot=3.0e5, FrictionCoefficient=0.0,
                     **kw):
        """MoorDyn v2's bottom: pressures kBot (Pa/m) and cBot (Pa s/m) on the area d l of
        each node in contact (MoorDyn-C source/Line.cpp: B_z = ((depth - z) kBot - z' cBot)
        d l; defaults 3e6 and 3e5), i.e. stiffness kBot d (N/m2) and damping cBot d
        (N s/m2) for a line of diameter d (m); FrictionCoefficient in both directions
        (MoorDyn-F's MU_KA and MU_KT are mu_axial and mu_lateral)."""
        check_positive("Seabed.from_moordyn.diameter", diameter)
        return cls(depth, stiffness=kBot * diameter, damping=cBot * diameter,
                   mu_axial=FrictionCoefficient, mu_lateral=FrictionCoefficient, **kw)

    def cell_coefficients(self, lines):
        """(nel,) stiffness (N/m2) and damping (N s/m2) of each element of a LineSet."""
        k, c = self.coefficients(lines)
        if not self.per_diameter:
            return np.full(len(lines.line_of_cell), k), np.full(len(lines.line_of_cell), c)
        d = np.array([line.line_type.diameter for line in lines.lines])[lines.line_of_cell]
        return k * d, c * d

    @property
    def normal(self) -> np.ndarray:
        """(3,) upward unit normal of the plane bed."""
        if self.bathymetry is not None:
            raise ValueError("Seabed.normal: a bathymetry bed has a normal per point "
                             "(Bathymetry.normal)")
        a, h = np.radians(self.slope_deg), np.radians(self.slope_heading_deg)
        return np.array([-np.sin(a) * np.cos(h), -np.sin(a) * np.sin(h), np.cos(a)])

    @property
    def offset(self) -> float:
        """n.P0 (m), P0 = (0, 0, -depth) a point of the bed: penetration g = offset - n.x."""
        return -self.depth * self.normal[2]

    def height(self, xy) -> np.ndarray:
        """z of the bed (m) at horizontal positions xy (..., 2), m."""
        xy = np.asarray(xy, float)
        if self.bathymetry is not None:
            return self.bathymetry.height(xy)
        a, h = np.radians(self.slope_deg), np.radians(self.slope_heading_deg)
        return -self.depth + np.tan(a) * (xy[..., 0] * np.cos(h) + xy[..., 1] * np.sin(h))

    def penetration(self, points) -> np.ndarray:
        """Depth of points (..., 3) below the bed, normal to it, m (negative above; on a
        bathymetry n_z (z_b - z), the distance to the bed's tangent plane)."""
        points = np.asarray(points, float)
        if self.bathymetry is not None:
            n, offset = self.bathymetry.plane(points)
            return offset - np.sum(n * points, axis=-1)
        return self.offset - points @ self.normal

    def coefficients(self, lines):
        """(stiffness N/m2, damping N s/m2) with the defaults resolved for a LineSet."""
        k = self.stiffness
        if k is None:
            weight = max(abs(line.line_type.weight) for line in lines.lines)
            if weight == 0:
                raise ValueError("Seabed.stiffness: the lines are weightless; give a stiffness")
            k = weight / DEFAULT_PENETRATION
        c = self.damping
        if c is None:
            c = 2.0 * np.sqrt(k * max(line.line_type.mass for line in lines.lines))
        return float(k), float(c)

    def onset(self, lines) -> float:
        """The damping onset (m) with the default resolved for a LineSet: a tenth of the
        largest static penetration w / k of its lines."""
        if self.damping_onset is not None:
            return float(self.damping_onset)
        return self._tenth_of_penetration(lines)

    def newton_depth(self, lines) -> float:
        """The depth (m) the time step's Newton lands a node arriving on the bed at
        (:func:`land_on_bed`) and the floor of its matrix's damping secant
        (:func:`newton_slope`): the damping onset, or without one a tenth of the largest
        static penetration w / k (the default onset)."""
        onset = self.onset(lines)
        return onset if onset > 0 else self._tenth_of_penetration(lines)

    def _tenth_of_penetration(self, lines) -> float:
        k, _ = self.cell_coefficients(lines)
        w = np.array([abs(line.line_type.weight) for line in lines.lines])[lines.line_of_cell]
        return float(0.1 * np.max(w / k))


# --- the pointwise physics, component axis first: x, rp, ud (3, ...), n (3, 1, ...)
def _slip(rp, ud, n, v0):
    """Axial direction a, 1/|P r'| (0 for an element standing on the bed), axial slip v_a,
    lateral slip v_l and the regularisation roots sqrt(v_a^2 + v0^2), sqrt(|v_l|^2 + v0^2)."""
    b = rp - dot(n, rp) * n
    length = ops.norm(b)
    inv = ops.where(length > _VERTICAL, 1.0 / ops.maximum(length, _VERTICAL), 0.0)
    a = b * inv
    vt = ud - dot(n, ud) * n
    va = dot(a, vt)
    vl = vt - va * a
    return a, inv, va, vl, ops.sqrt(va**2 + v0**2), ops.sqrt(dot(vl, vl) + v0**2)


def _state(w):
    """Penetration g (m), contact indicator H(g), current tangent r' = X' + u' (the P1
    chord) and velocity udot (m/s) at the quadrature points of a form."""
    x = w.X + w.u
    g = w.bed_offset - dot(w.bed_n, x)
    return g, (g > 0).astype(float), d_ds(w.X) + d_ds(w.u), w.du


def _fade(g, onset):
    """Hc(g) = clip(g / onset, 0, 1), the damping's share (H(g) for onset 0), and dHc/dg
    (1/m, 0 outside 0 < g < onset)."""
    if onset == 0:
        return (g > 0).astype(float), 0.0 * g
    return ops.clip(g / onset, 0.0, 1.0), ((g > 0) & (g < onset)) / onset


def _friction_direction(a, va, vl, ra, rho, mu_a, mu_l):
    """F = mu_a phi(v_a) a + mu_l v_l / rho: friction per unit normal force, against slip."""
    return mu_a * (va / ra) * a + mu_l * vl / rho


def normal_residual(v, w):
    # contact: int -(k g H(g) - c (n.udot) Hc(g)) n.du ds, g = n.(P0 - X - u)
    g, H, _, ud = _state(w)
    Hc, _ = _fade(g, w.bed_onset)
    return -(w.k_bed * g * H - w.c_bed * dot(w.bed_n, ud) * Hc) * dot(w.bed_n, v)


def friction_residual(v, w):
    # friction: int k g H [mu_a phi(v_a) a + mu_l v_l / sqrt(|v_l|^2 + v0^2)].du ds
    g, H, rp, ud = _state(w)
    a, _, va, vl, ra, rho = _slip(rp, ud, w.bed_n, w.v0)
    return w.k_bed * g * H * dot(_friction_direction(a, va, vl, ra, rho, w.mu_a, w.mu_l), v)


def normal_stiffness(du, v, w):
    # d(contact)/du: int (k H - c (n.udot) dHc/dg) (n.du)(n.v) ds
    g, H, _, ud = _state(w)
    _, dHc = _fade(g, w.bed_onset)
    return (w.k_bed * H - w.c_bed * dot(w.bed_n, ud) * dHc) * dot(w.bed_n, du) * dot(w.bed_n, v)


def normal_damping(du, v, w):
    # d(contact)/dudot: int c Hc (n.du)(n.v) ds
    g, _, _, _ = _state(w)
    Hc, _ = _fade(g, w.bed_onset)
    return w.c_bed * Hc * dot(w.bed_n, du) * dot(w.bed_n, v)


def friction_stiffness(du, v, w):
    # d(friction)/du: through N = k g (dg = -n.du) and a (da = Q du' / |P r'|, Q = P - a a^T)
    g, H, rp, ud = _state(w)
    n = w.bed_n
    a, inv, va, vl, ra, rho = _slip(rp, ud, n, w.v0)
    F = _friction_direction(a, va, vl, ra, rho, w.mu_a, w.mu_l)
    N = w.k_bed * g * H
    dup = d_ds(du)
    Qdup_v = dot(dup, v) - dot(n, dup) * dot(n, v) - dot(a, dup) * dot(a, v)
    vl_dup, a_v, vl_v = dot(vl, dup), dot(a, v), dot(vl, v)
    axial = w.mu_a * (w.v0**2 / ra**3 * vl_dup * a_v + va / ra * Qdup_v)
    lateral = w.mu_l * (-(vl_dup * a_v + va * Qdup_v) / rho + va * vl_dup * vl_v / rho**3)
    return -w.k_bed * H * dot(n, du) * dot(F, v) + N * inv * (axial + lateral)


def friction_damping(du, v, w):
    # d(friction)/dudot: int N [mu_a phi'(v_a) (a.du)(a.v)
    #                            + mu_l ((Q du).v / rho - (v_l.du)(v_l.v) / rho^3)] ds
    g, H, rp, ud = _state(w)
    n = w.bed_n
    a, _, _va, vl, ra, rho = _slip(rp, ud, n, w.v0)
    Qdu_v = dot(du, v) - dot(n, du) * dot(n, v) - dot(a, du) * dot(a, v)
    axial = w.mu_a * w.v0**2 / ra**3 * dot(a, du) * dot(a, v)
    lateral = w.mu_l * (Qdu_v / rho - dot(vl, du) * dot(vl, v) / rho**3)
    return w.k_bed * g * H * (axial + lateral)


@LinearForm
def seabed_residual(v, w):
    # bed reaction and friction as internal - external: int -(f_n + f_f).du ds
    return normal_residual(v, w) + friction_residual(v, w)


@BilinearForm
def seabed_stiffness(du, v, w):
    # d(seabed_residual)/du
    return normal_stiffness(du, v, w) + friction_stiffness(du, v, w)


@BilinearForm
def seabed_damping(du, v, w):
    # d(seabed_residual)/dudot
    return normal_damping(du, v, w) + friction_damping(du, v, w)


def _reference_positions(lines):
    """(ndofs,) reference geometry as a DOF vector: node positions, m (and on Hermite
    the nodal tangents)."""
    return lines.reference_dofs.copy()


def seabed_term(lines, seabed, *, path="auto"):
    """The sea bed as a line term of a System: the compiled :class:`SeabedKernel`; on a
    bending (Hermite) LineSet with ``path`` other than 'auto', :func:`form_term` on it."""
    if lines.hermite and path != "auto":
        return form_term(lines, seabed, path=path)
    return SeabedKernel(lines, seabed)


def form_term(lines, seabed, *, path="auto"):
    """The sea bed as a :class:`~skmoor.fem.terms.LineForm` on the forms above with nodal
    quadrature (the definition; the same numbers as the kernel to round-off). path:
    'auto' uses the hand-written tangents on scikit-fem's assembly."""
    if seabed.bathymetry is not None:
        raise ValueError("seabed form_term: a bathymetry bed is the compiled kernel only "
                         "(seabed_term); the forms take a plane bed")
    k, c = seabed.cell_coefficients(lines)
    nqp = lines.nodal_basis.X.shape[1]
    fields = dict(X=_reference_positions(lines), bed_n=seabed.normal[:, None, None],
                  bed_offset=seabed.offset, k_bed=np.repeat(k[:, None], nqp, axis=1),
                  c_bed=np.repeat(c[:, None], nqp, axis=1), bed_onset=seabed.onset(lines),
                  mu_a=float(seabed.mu_axial), mu_l=float(seabed.mu_lateral),
                  v0=float(seabed.friction_velocity))
    hand = path in ("auto", "assembly")
    moving = np.any(c > 0) or seabed.mu_axial > 0 or seabed.mu_lateral > 0
    return SeabedForm(seabed, seabed_residual, stiffness=seabed_stiffness if hand else None,
                      damping=seabed_damping if hand and moving else None, fields=fields,
                      quadrature="nodal", path=path, lines=lines, name="seabed")


def landing(lines, seabed, position, newton_depth):
    """:func:`land_on_bed`'s arrays after y and dx for the line nodes whose three DOFs are
    free (``position``: each full DOF's reduced column, -1 held): their columns (m, 3),
    reference positions (m, 3; m), the bed's normal (m, 3) and offset n.P (m,) under each
    (a bathymetry's taken at each call), the Newton depth (m) and the bathymetry's x, y
    and heights (empty on a plane)."""
    columns = np.asarray(position, np.int64)[lines.nodal_dofs]
    free = columns.min(axis=1) >= 0
    points = lines.points[free]
    m = len(points)
    if seabed.bathymetry is None:
        normal = np.empty((m, 3))
        normal[:] = seabed.normal
        offset = np.full(m, float(seabed.offset))
        grid = (np.zeros(0), np.zeros(0), np.zeros((0, 0)))
    else:
        normal, offset = np.zeros((m, 3)), np.zeros(m)
        grid = tuple(np.ascontiguousarray(a, float) for a in
                     (seabed.bathymetry.x, seabed.bathymetry.y, seabed.bathymetry.heights))
    return (columns[free], np.ascontiguousarray(points, float), normal, offset,
            newton_depth, *grid)


class SeabedForm(LineForm):
    """The seabed's LineForm, skipped while no node touches the bed (every term of the
    forms carries the contact H(g) or the normal force, so all are zero there); the
    Newton iteration lands on the bed as with the kernel (:meth:`landing`)."""

    def __init__(self, seabed, residual, **kw):
        super().__init__(residual, **kw)
        self.seabed = seabed

    def landing(self, position):
        """:func:`land_on_bed`'s arrays (:func:`landing`)."""
        return landing(self.lines, self.seabed, position, self.seabed.newton_depth(self.lines))

    def add_to(self, u, v, t, R, K=None, C=None):
        if np.any(self.seabed.penetration(self.lines.points + u[self.lines.nodal_dofs]) > 0):
            super().add_to(u, v, t, R, K, C)


class SeabedKernel(Term):
    """Compiled fast path of the seabed forms (see :mod:`skmoor.lines.cable_kernel`), a line
    :class:`~skmoor.fem.terms.Term`, at the nodal quadrature points (2 per element: node i of
    element e with weight h_e / 2). On a bending (Hermite) LineSet it acts on the node
    positions with each element's chord as the tangent of the friction (MoorDyn's lumped
    contact; :func:`form_term` takes the C1 tangent), its blocks placed on the position
    DOFs of the 12 x 12 element blocks (``stride``: where node j's position DOFs start in
    an element block, 3 on P1, 6 on Hermite)."""

    newton_matrix = True

    def __init__(self, lines, seabed):
        self.lines = lines
        self.k, self.c = seabed.cell_coefficients(lines)
        self.onset = seabed.onset(lines)
        self.newton_depth = seabed.newton_depth(lines)
        self.mu_a, self.mu_l = float(seabed.mu_axial), float(seabed.mu_lateral)
        self.v0 = float(seabed.friction_velocity)
        t = lines.mesh.t  # (2, nel)
        self.h = lines.element_lengths
        self.ends = np.ascontiguousarray(lines.nodal_dofs[t])  # (2, nel, 3) DOFs of each end
        self.X = np.ascontiguousarray(lines.points[t])  # (2, nel, 3)
        self.bathymetry = seabed.bathymetry
        self.n = self.offset = None  # a bathymetry's follow the nodes
        if self.bathymetry is None:  # a plane: one normal and offset for every node
            self.n = np.ascontiguousarray(np.broadcast_to(seabed.normal, self.X.shape))
            self.offset = np.full(self.X.shape[:2], float(seabed.offset))
        self.friction = self.mu_a > 0 or self.mu_l > 0
        self.moving = bool(np.any(self.c > 0)) or self.friction
        self.static_friction = seabed.static_friction if self.friction else None
        self.static_slip = float(seabed.static_slip)
        self._seabed = seabed
        self._laid = None  # the as-laid displacement (ndofs,), made when first asked for
        self._resting = {}  # held end nodes -> (their half element lengths, springs)
        self._no_velocity = np.zeros(lines.ndofs)
        self.stride = 6 if lines.hermite else 3

    def lowered(self):
        return "form"

    @property
    def step_kernel(self):
        """(C function, ints, floats): :func:`_seabed` as the compiled time step calls a
        user's LineForm (by address, :data:`~skmoor.fem.form_compiler.STEP_SIGNATURE`;
        compiled when first asked for), its arrays packed: ints [nel, stride, friction,
        the bathymetry's nx and ny (0 on a plane), each end's DOFs (2, nel, 3)], floats
        [X (2, nel, 3), h, normals (2, nel, 3), offsets (2, nel) (on a bathymetry: room
        for the planes under the displaced ends), k, c, onset, mu_axial, mu_lateral, v0,
        the Newton depth (its tangent is the Newton matrix's: the compiled step asks
        for no other), the bathymetry's x (nx), y (ny) and heights (nx, ny)]."""
        grid = self.bathymetry
        nx, ny = (0, 0) if grid is None else (grid.x.size, grid.y.size)
        n = np.zeros(self.X.shape) if grid is not None else self.n
        offset = np.zeros(self.X.shape[:2]) if grid is not None else self.offset
        ints = np.concatenate([[len(self.h), self.stride, int(self.friction), nx, ny],
                               self.ends.ravel()]).astype(np.int64)
        floats = np.concatenate(
            [np.ravel(a) for a in (self.X, self.h, n, offset, self.k, self.c)]
            + [[self.onset, self.mu_a, self.mu_l, self.v0, self.newton_depth]]
            + ([] if grid is None else [grid.x, grid.y, grid.heights.ravel()])).astype(float)
        return _seabed_step(), ints, floats

    def add_to(self, u, ud, t, R, Ke=None, Ce=None, newton=False):
        """Adds the residual into R and, with Ke, Ce, its derivatives into the element
        blocks (the term protocol, :mod:`skmoor.fem.terms`; with ``newton``, Ke is the
        time step's Newton matrix's: :func:`newton_slope`); in a static solve with
        ``Seabed.static_friction``, the friction of the slip from the as-laid (or the
        reference) state."""
        if self.static_friction is not None and self.lines.static_mode:
            self._add_static(u, R, Ke)
            return
        if Ke is not None and Ce is None:
            Ce = np.zeros_like(Ke)
        self._run(u, ud, R, NO_BLOCKS if Ke is None else Ke, NO_BLOCKS if Ce is None else Ce,
                  newton=newton)

    def _run(self, u, ud, R, Ke, Ce, c=None, v0=None, newton=False):
        n, offset = self.n, self.offset
        if self.bathymetry is not None:  # the bed's normal and height under each node
            n, offset = self.bathymetry.plane(self.X + u[self.ends])
        _seabed(self.X, self.ends, self.h, n, offset, self.k, self.c if c is None else c,
                self.onset, self.mu_a, self.mu_l, self.v0 if v0 is None else v0,
                self.friction, u, self._no_velocity if ud is None else ud, R, Ke, Ce,
                self.stride, self.newton_depth if newton else 0.0)

    def _add_static(self, u, R, Ke):
        """The bed in a static solve: its spring, and the friction of the slip s = u -
        u_laid (m) with the regularization static_slip, whose derivative d/ds is d/du."""
        slip = u - self.laid_displacement()
        zero = np.zeros_like(self.c)  # no damping: the slip is no velocity
        blocks = NO_BLOCKS if Ke is None else Ke
        self._run(u, slip, R, blocks, blocks, zero, self.static_slip)  # d/ds is d/du

    def landing(self, position):
        """:func:`land_on_bed`'s arrays (:func:`landing`)."""
        return landing(self.lines, self._seabed, position, self.newton_depth)

    def resting_support(self, u, weight, nodes) -> np.ndarray:
        """(len(nodes), 3) support (N) the bed gives the held line-end ``nodes`` resting
        on it beyond its spring (u (ndofs,) m; or (m, ndofs): m states, (m, len(nodes),
        3)): the part of the node's lumped weight (``weight``, the lines' weight load
        (ndofs,), N) pressing into the bed that the spring k g does not carry, along the
        bed's normal; zero for a node above the bed (by more than 1e-6 m) or pulled
        upwards. A held node on the bed at its surface (an anchor at the depth) would
        otherwise pass its share of the line's weight, w h / 2, into its reaction: half an
        element's weight, an error in the anchor tension of first order in the element
        length that the bed, not the anchor, carries."""
        return self.resting_plan(weight, nodes)(u)

    def _share_and_spring(self, nodes):
        """(half element lengths at each node (m), its stiffest bed spring (N/m2)), kept."""
        key = nodes.tobytes()
        if key not in self._resting:
            t = self.lines.mesh.t
            share, k = np.zeros(len(nodes)), np.zeros(len(nodes))
            for end in range(2):  # the elements at each node: their half lengths, springs
                at = t[end][None, :] == nodes[:, None]  # (n, nel)
                share += at @ (0.5 * self.h)
                k = np.maximum(k, np.max(np.where(at, self.k[None, :], 0.0), axis=1))
            self._resting[key] = share, k
        return self._resting[key]

    def resting_plan(self, weight, nodes):
        """:meth:`resting_support` of held ``nodes`` as a function of u alone, its
        constant parts computed once: a :class:`RestingSupport` (arrays the compiled step
        takes too)."""
        nodes = np.asarray(nodes, int)
        share, k = self._share_and_spring(nodes)
        dofs = self.lines.nodal_dofs[nodes]
        if self.bathymetry is None:
            normal = np.broadcast_to(np.asarray(self._seabed.normal, float), (len(nodes), 3))
            offset = np.full(len(nodes), float(self._seabed.offset))
            grid = (np.zeros(0), np.zeros(0), np.zeros((0, 0)))
        else:  # (the planes under the displaced nodes, made at each call)
            normal, offset = np.zeros((len(nodes), 3)), np.zeros(len(nodes))
            b = self.bathymetry
            grid = (b.x, b.y, b.heights)
        return RestingSupport(dofs, self.lines.points[nodes], weight[dofs], k * share,
                              np.ascontiguousarray(normal), offset, grid)

    def laid_displacement(self) -> np.ndarray:
        """(ndofs,) displacement (m) of the state the static friction counts the slip
        from: zero ('reference'), or ('as-laid') for the nodes from each line's end A
        that touch the bed in the reference, the line laid straight along the bed from end
        A without tension (a node at unstretched arclength s from end A sits at s along
        the chord from end A to the node's reference position)."""
        if self._laid is not None:
            return self._laid
        lines = self.lines
        laid = np.zeros(lines.ndofs)
        if self.static_friction == "as-laid":
            points = lines.points
            dofs = lines.nodal_dofs
            touching = self._seabed.penetration(points) > -1e-6
            for a, b in zip(lines.anchor_nodes, lines.fairlead_nodes):
                if not touching[a]:
                    continue
                s = np.concatenate([[0.0], np.cumsum(self._node_spacing(a, b))])
                for k, node in enumerate(range(a, b + 1)):
                    if not touching[node]:
                        break
                    chord = points[node] - points[a]
                    length = np.linalg.norm(chord)
                    if length > 0:
                        laid[dofs[node]] = (s[k] / length - 1.0) * chord
        self._laid = laid
        return laid

    def _node_spacing(self, a, b):
        """Unstretched lengths (m) of the elements between nodes a and b of a line: their
        reference lengths over the reference stretch at their middles."""
        lines = self.lines
        t = lines.mesh.t
        cells = np.flatnonzero((t[0] >= a) & (t[1] <= b))
        cells = cells[np.argsort(t[0, cells])]
        k = int(lines.line_of_cell[cells[0]])
        middle = 0.5 * (lines.mesh.p[0, t[0, cells]] + lines.mesh.p[0, t[1, cells]])
        return self.h[cells] / lines.lines[k].stretch(middle - lines._offsets[k])


@njit(cache=True)
def _seabed(X, ends, h, normals, offsets, k, c, onset, mu_a, mu_l, v0, friction, u, ud, R, Ke,
            Ce, stride, newton_depth):
    """Adds seabed_residual into R and seabed_stiffness / seabed_damping into Ke, Ce at
    the two ends of each element (weights h / 2), the bed's upward unit normal and n.P
    (P a point of the bed) at each end in normals (2, nel, 3) and offsets (2, nel); node j's
    position DOFs start at ``stride`` in the element blocks. newton_depth (m) > 0: Ke is
    the time step's Newton matrix's, the normal slope the damping's secant
    (:func:`newton_slope`); 0: the exact derivative."""
    tangent = Ke.shape[0] > 0
    scratch = np.zeros(15)  # one allocation for the five 3-vectors
    vel, rp, a, vl, F = scratch[:3], scratch[3:6], scratch[6:9], scratch[9:12], scratch[12:]
    for e in range(h.size):
        W = 0.5 * h[e]
        for end in range(2):
            g = offsets[end, e]
            for i in range(3):
                g -= normals[end, e, i] * (X[end, e, i] + u[ends[end, e, i]])
            if g <= 0.0:  # off the bed: no force, no derivative
                continue
            n = normals[end, e]
            vn = 0.0
            for i in range(3):
                vel[i] = ud[ends[end, e, i]]
                vn += n[i] * vel[i]
            if onset == 0:  # the damping's share Hc(g) and dHc/dg (_fade)
                Hc, dHc = 1.0, 0.0
            else:
                Hc = min(g / onset, 1.0)
                dHc = 1.0 / onset if g < onset else 0.0
            push = -(k[e] * g - c[e] * vn * Hc)
            N = k[e] * g
            if friction:  # _slip and _friction_direction
                for i in range(3):
                    rp[i] = (X[1, e, i] + u[ends[1, e, i]] - X[0, e, i] - u[ends[0, e, i]]) / h[e]
                n_rp = n[0] * rp[0] + n[1] * rp[1] + n[2] * rp[2]
                length = 0.0
                for i in range(3):
                    a[i] = rp[i] - n_rp * n[i]
                    length += a[i] ** 2
                length = np.sqrt(length)
                inv = 1.0 / length if length > _VERTICAL else 0.0
                va = 0.0
                for i in range(3):
                    a[i] *= inv
                    va += a[i] * (vel[i] - vn * n[i])
                rho = 0.0
                for i in range(3):
                    vl[i] = vel[i] - vn * n[i] - va * a[i]
                    rho += vl[i] ** 2
                ra, rho = np.sqrt(va**2 + v0**2), np.sqrt(rho + v0**2)
                for i in range(3):
                    F[i] = mu_a * va / ra * a[i] + mu_l * vl[i] / rho
            else:
                F[:] = 0.0
            for i in range(3):
                R[ends[end, e, i]] += W * (push * n[i] + N * F[i])
            if not tangent:
                continue
            o = stride * end
            # d/dg of the push: the spring and the damping's fade-in
            slope = (k[e] - c[e] * vn * dHc if newton_depth == 0.0
                     else newton_slope(k[e], c[e], vn, g, newton_depth))
            for p in range(3):
                for q in range(3):
                    # through the penetration: the spring, the damping's fade-in, the
                    # friction's normal force; the damping's rate
                    Ke[e, o + p, o + q] += W * (slope * n[p] * n[q] - k[e] * F[p] * n[q])
                    Ce[e, o + p, o + q] += W * c[e] * Hc * n[p] * n[q]
            if not friction:
                continue
            # d/du through a, per unit change of the chord (du_1 - du_0) / h, and d/dudot
            scale = W * N * inv / h[e]
            for p in range(3):
                for q in range(3):
                    Q = (1.0 if p == q else 0.0) - n[p] * n[q] - a[p] * a[q]
                    G = (mu_a * (v0**2 / ra**3 * a[p] * vl[q] + va / ra * Q)
                         + mu_l * (-(a[p] * vl[q] + va * Q) / rho + va / rho**3 * vl[p] * vl[q]))
                    Ke[e, o + p, q] -= scale * G
                    Ke[e, o + p, stride + q] += scale * G
                    Ce[e, o + p, o + q] += W * N * (mu_a * v0**2 / ra**3 * a[p] * a[q]
                                                    + mu_l * (Q / rho - vl[p] * vl[q] / rho**3))


@njit(cache=True, inline="always")
def land_on_bed(y, dx, size, columns, points, normal, offset, depth, x_grid, y_grid, heights):
    """Stops the nodes that the time step's Newton correction dx (reduced, m; changed in
    place; ``size``: its largest component, m) carries across the bed's surface from y
    (none when no node moves as far as ``depth``: sqrt(3) size <= depth), one arriving from above at ``depth``
    (m) below the surface, one leaving it at ``depth`` above (not on the surface, where
    round-off would decide the contact), each moved back along the bed's normal; whether
    any was (arrays: :meth:`SeabedKernel.landing`). A Newton matrix made
    with the node off the bed has no bed in it: it sends an arriving node as deep as the
    line lets it (centimetres into a spring meant for millimetres) and a node on the bed
    whose contact force it does not expect as high; the matrix made there sends it back,
    and Newton cycles across the kink. Stopped there, the next matrix is the right side's
    (:func:`newton_slope` on the bed). The root is not changed, only the path to it."""
    if depth <= 0.0 or math.sqrt(3.0) * size <= depth:
        return False
    landed = False
    for i in range(columns.shape[0]):
        px = points[i, 0] + y[columns[i, 0]]
        py = points[i, 1] + y[columns[i, 1]]
        pz = points[i, 2] + y[columns[i, 2]]
        if x_grid.size:  # the bathymetry's plane under the node
            offset[i] = bed_plane(px, py, x_grid, y_grid, heights, normal[i])
        n = normal[i]
        g = offset[i] - (n[0] * px + n[1] * py + n[2] * pz)  # penetration, m
        g1 = g - (n[0] * dx[columns[i, 0]] + n[1] * dx[columns[i, 1]]
                  + n[2] * dx[columns[i, 2]])
        if g <= 0.0 and g1 > depth:  # arriving: at the depth
            excess = g1 - depth
        elif g > 0.0 and g1 < -depth:  # leaving: as high above it
            excess = g1 + depth
        else:
            continue
        for c in range(3):
            dx[columns[i, c]] += excess * n[c]
        landed = True
    return landed


@njit(cache=True, inline="always")
def newton_slope(k, c, vn, g, depth):
    """The bed's normal slope (N/m2) in the time step's Newton matrix at penetration g > 0
    (m) and normal velocity vn (m/s): k + c max(-vn, 0) / max(g, depth), the damping's
    secant from g = 0, never below its exact slope k - c vn dHc/dg (equal inside the
    fade-in while the node sinks; depth: the onset). From the contact side Newton then
    cannot step a sinking node off the bed past its root (the exact slope, 0 past the
    fade-in, sends it up and the next matrix down again: a two-cycle across the kink);
    for a rising node the fade-in's negative slope is left out. Zero difference at rest:
    statics and modes see the exact derivative."""
    return k + c * max(-vn, 0.0) / max(g, depth)


@njit(cache=True)
def bed_plane(x, y, gx, gy, heights, normal):
    """``Bathymetry.plane`` at the point (x, y) (m) of the grid gx (nx,), gy (ny,),
    heights (nx, ny): the bed's upward unit normal into normal (3,), and n.P returned."""
    i0, i1, fx = cell(gx, x)
    j0, j1, fy = cell(gy, y)
    z = heights
    sx = sy = 0.0
    if gx.size > 1 and gx[0] < x < gx[-1]:
        sx = ((1 - fy) * (z[i1, j0] - z[i0, j0]) + fy * (z[i1, j1] - z[i0, j1])) / (
            gx[i1] - gx[i0])
    if gy.size > 1 and gy[0] < y < gy[-1]:
        sy = ((1 - fx) * (z[i0, j1] - z[i0, j0]) + fx * (z[i1, j1] - z[i1, j0])) / (
            gy[j1] - gy[j0])
    size = math.sqrt(sx * sx + sy * sy + 1.0)
    normal[0], normal[1], normal[2] = -sx / size, -sy / size, 1.0 / size
    height = ((1 - fx) * ((1 - fy) * z[i0, j0] + fy * z[i0, j1])
              + fx * ((1 - fy) * z[i1, j0] + fy * z[i1, j1]))
    return normal[0] * x + normal[1] * y + normal[2] * height


def _seabed_packed(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """:func:`_seabed` on the buffers of ``SeabedKernel.step_kernel`` (on a bathymetry,
    the planes under the displaced ends first, as ``SeabedKernel._run``)."""
    nel, stride, friction, nx, ny = ints[0], ints[1], ints[2] > 0, ints[3], ints[4]
    ends = carray(advanced(ints, 5), (2, nel, 3))
    X = carray(floats, (2, nel, 3))
    h = carray(advanced(floats, 6 * nel), (nel,))
    normals = carray(advanced(floats, 7 * nel), (2, nel, 3))
    offsets = carray(advanced(floats, 13 * nel), (2, nel))
    k, c = carray(advanced(floats, 15 * nel), (nel,)), carray(advanced(floats, 16 * nel), (nel,))
    at = 17 * nel
    onset, mu_a, mu_l, v0 = floats[at], floats[at + 1], floats[at + 2], floats[at + 3]
    newton_depth = floats[at + 4]
    at += 5
    u = carray(u_p, (ndofs,))
    if nx > 0:
        gx, gy = carray(advanced(floats, at), (nx,)), carray(advanced(floats, at + nx), (ny,))
        heights = carray(advanced(floats, at + nx + ny), (nx, ny))
        for end in range(2):
            for e in range(nel):
                offsets[end, e] = bed_plane(X[end, e, 0] + u[ends[end, e, 0]],
                                            X[end, e, 1] + u[ends[end, e, 1]], gx, gy,
                                            heights, normals[end, e])
    nloc, blocks = 2 * stride, nel if tangent else 0
    _seabed(X, ends, h, normals, offsets, k, c, onset, mu_a, mu_l, v0, friction,
            u, carray(ud_p, (ndofs,)), carray(R_p, (ndofs,)),
            carray(K_p, (blocks, nloc, nloc)), carray(C_p, (blocks, nloc, nloc)), stride,
            newton_depth)


_seabed_step = compiled_when_asked(_seabed_packed)  # (its C function, when first asked for)


class RestingSupport:
    """The bed's support (N) of held line-end nodes resting on it
    (:meth:`SeabedKernel.resting_support`; the compiled step's report holds the same
    arithmetic, :func:`resting_support`), from their DOFs ``dofs`` (n, 3), reference
    positions ``points`` (n, 3; m), weights ``weights`` (n, 3; N), spring stiffness times
    half element lengths ``stiffness`` (N/m) and the bed: a plane's normal (n, 3) and
    offset n.P (n,) under each, or a bathymetry ``grid`` (x, y, heights) whose planes
    under the displaced nodes are taken at each call (into normal and offset)."""

    def __init__(self, dofs, points, weights, stiffness, normal, offset, grid):
        self.dofs, self.points, self.weights, self.stiffness = dofs, points, weights, stiffness
        self.normal, self.offset, self.grid = normal, offset, grid

    def arrays(self):
        """(dofs, points, weights, stiffness, normal, offset, grid x, y, heights)."""
        return (self.dofs, self.points, self.weights, self.stiffness, self.normal,
                self.offset, *self.grid)

    def __call__(self, u):
        """(n, 3) support at u (ndofs,), or (m, n, 3) at m states u (m, ndofs)."""
        u = np.asarray(u)
        states = u.reshape(-1, u.shape[-1])
        out = np.empty((len(states), len(self.dofs), 3))
        arrays = tuple(np.array(a) for a in self.arrays())  # (normal, offset: scratch)
        for state, support in zip(states, out):
            resting_support(state, *arrays, support)
        return out.reshape(u.shape[:-1] + (len(self.dofs), 3))


@njit(cache=True, inline="always")  # (in the compiled report: no call)
def resting_support(u, dofs, points, weights, stiffness, normal, offset, x, y, heights, out):
    """out[i] <- the support (N) of held node i at u (:class:`RestingSupport`): the weight
    pressing into the bed that its spring does not carry, along the bed's normal; none
    where the node is above the bed by more than 1e-6 m or pulled upwards."""
    for i in range(dofs.shape[0]):
        if x.size:  # the bathymetry's plane under the displaced node
            offset[i] = bed_plane(points[i, 0] + u[dofs[i, 0]], points[i, 1] + u[dofs[i, 1]],
                                  x, y, heights, normal[i])
        g, pressing = offset[i], 0.0
        for c in range(3):
            g -= normal[i, c] * (points[i, c] + u[dofs[i, c]])
            pressing -= weights[i, c] * normal[i, c]
        carried = max(pressing - stiffness[i] * max(g, 0.0), 0.0) if g >= -1e-6 else 0.0
        for c in range(3):
            out[i, c] = carried * normal[i, c]
