"""Tests of skmoor.bodies.body against analytic numbers and finite differences of exact loads."""
from pathlib import Path

import meshio
import numpy as np
import pytest
import pyvista as pv

from skmoor.bodies.body import (
    Hydrostatics,
    RigidBody,
    attachment_displacement,
    attachment_hessian,
    attachment_jacobian,
    box_hydrostatics,
    hull_hydrostatics,
    rotation_matrix,
    uniform_box_inertia,
)

HULL = Path(__file__).resolve().parents[2] / "meshes" / "box_hull.stl"
L, W, H = 26.0, 10.0, 5.0
RHO, G = 1025.0, 9.81
Q0 = np.array([0.4, -0.7, 0.3, 0.25, -0.3, 0.2])  # large rotations
POINTS = np.array([[13.0, 5.0, -2.5], [-13.0, 5.0, -2.5], [1.0, -2.0, 3.0]])


def hull_surface(center=(0.0, 0.0, 0.0)):
    """The box hull of meshes/box_hull.stl in double precision, centred at ``center``."""
    mesh = pv.read(HULL)
    mesh.points = np.asarray(mesh.points, dtype=float) + np.asarray(center)
    return mesh


def posed(surface, q, ref):
    """``surface`` moved as a rigid body by ``q`` about ``ref``."""
    out = surface.copy()
    out.points = ref + attachment_displacement(q, surface.points - ref) + (surface.points - ref)
    return out


# --------------------------------------------------------------------------- kinematics

def test_rotation_geometry():
    assert np.allclose(rotation_matrix([0, 0, np.pi / 2]) @ [1, 0, 0], [0, 1, 0])
    assert np.allclose(rotation_matrix([np.pi / 2, 0, 0]) @ [0, 1, 0], [0, 0, 1])
    assert np.allclose(rotation_matrix([0, np.pi / 2, 0]) @ [0, 0, 1], [1, 0, 0])
    # order R = Rz Ry Rx: x first (e_y -> e_z), then y (e_z -> e_x)
    assert np.allclose(rotation_matrix([np.pi / 2, np.pi / 2, 0]) @ [0, 1, 0], [1, 0, 0])
    r = rotation_matrix(Q0[3:])
    assert np.allclose(r @ r.T, np.eye(3)) and np.isclose(np.linalg.det(r), 1.0)
    q = np.array([1.0, 2.0, 3.0, 0.0, 0.0, np.pi / 2])
    assert np.allclose(attachment_displacement(q, [1.0, 0.0, 0.0]), [0.0, 3.0, 3.0])


def test_attachment_vectorized():
    disp = attachment_displacement(Q0, POINTS)
    jac = attachment_jacobian(Q0, POINTS)
    assert disp.shape == (3, 3) and jac.shape == (3, 3, 6)
    for k, r in enumerate(POINTS):
        assert np.allclose(disp[k], attachment_displacement(Q0, r))
        assert np.allclose(jac[k], attachment_jacobian(Q0, r))


def test_jacobian_finite_difference():
    h = 1e-6
    for r in POINTS:
        disp = lambda q: attachment_displacement(q, r)  # noqa: E731
        fd = np.column_stack([(disp(Q0 + h * e) - disp(Q0 - h * e)) / (2 * h) for e in np.eye(6)])
        assert np.allclose(attachment_jacobian(Q0, r), fd, atol=1e-8)


def test_hessian_finite_difference():
    forces = np.array([[1e5, -2e5, 3e5], [-4e5, 1e5, 2e5], [0.0, 5e4, -1e5]])

    def gen_force(q):
        return np.einsum("nki,nk->i", attachment_jacobian(q, POINTS), forces)

    h = 1e-6
    fd = np.column_stack([(gen_force(Q0 + h * e) - gen_force(Q0 - h * e)) / (2 * h)
                          for e in np.eye(6)])
    hess = attachment_hessian(Q0, POINTS, forces)
    assert np.allclose(hess, fd, rtol=0, atol=1e-7 * np.abs(hess).max())
    assert np.allclose(hess, hess.T)
    assert np.allclose(hess, sum(attachment_hessian(Q0, r, f) for r, f in zip(POINTS, forces)))


# --------------------------------------------------------------------------- hydrostatics

def test_uniform_box_inertia():
    assert np.allclose(uniform_box_inertia(1.2e5, L, W, H),
                       np.diag([1.25e6, 7.01e6, 7.76e6]))


def test_box_body_analytic():
    """The paper's box: V, Awp and the restoring terms by hand (reference = CoM = box centre)."""
    draft, mass = 0.9, 1.2e5
    body = RigidBody.box(L, W, H, mass, draft)
    zc = H / 2 - draft
    assert np.allclose(body.center_of_mass, [0, 0, zc])
    assert np.allclose(body.reference_point, body.center_of_mass)
    assert np.allclose(body.inertia, uniform_box_inertia(mass, L, W, H))
    hs = body.hydrostatics
    assert np.isclose(hs.volume, 234.0) and np.isclose(hs.waterplane_area, 260.0)
    assert np.allclose(hs.center_of_buoyancy, [0, 0, -0.45])
    k = body.hydrostatic_stiffness()
    v, zb, zg = 234.0, -0.45 - zc, 0.0
    expected = np.zeros((6, 6))
    expected[2, 2] = RHO * G * L * W
    expected[3, 3] = RHO * G * (L * W**3 / 12 + v * zb) - mass * G * zg
    expected[4, 4] = RHO * G * (W * L**3 / 12 + v * zb) - mass * G * zg
    assert np.allclose(k, expected, rtol=1e-12, atol=1e-6)
    assert np.allclose(body.static_force(), [0, 0, RHO * G * v - mass * G, 0, 0, 0])
    assert np.allclose(body.box_size, [L, W, H]) and np.allclose(body.box_center, 0.0)


def test_box_hydrostatics_offsets():
    hs = box_hydrostatics(L, W, H, 1.2, reference_point=(2.0, 1.0, 1.5), center_xy=(0.7, -0.4))
    a, cx, cy = L * W, 0.7 - 2.0, -0.4 - 1.0
    assert np.allclose(hs.center_of_buoyancy, [0.7, -0.4, -0.6])
    assert np.allclose(hs.waterplane_first_moments, [a * cx, a * cy])
    assert np.allclose(hs.waterplane_second_moments,
                       [a * (cx**2 + L**2 / 12), a * (cy**2 + W**2 / 12), a * cx * cy])


@pytest.mark.parametrize("ref, center", [((0, 0, 1.6), (0, 0, 1.6)),
                                         ((2.0, 1.0, 1.5), (0.7, -0.4, 1.6)),
                                         ((0, 0, 0), (-3.0, 2.0, 1.6))])
def test_hull_matches_box(ref, center):
    draft = 0.9
    hull = hull_hydrostatics(HULL, reference_point=ref, offset=center)
    box = box_hydrostatics(L, W, H, draft, reference_point=ref, center_xy=center[:2])
    for name in ("volume", "center_of_buoyancy", "waterplane_area",
                 "waterplane_first_moments", "waterplane_second_moments"):
        a, b = np.atleast_1d(getattr(hull, name)), np.atleast_1d(getattr(box, name))
        scale = {"volume": 234.0, "waterplane_area": 260.0, "center_of_buoyancy": 13.0,
                 "waterplane_first_moments": 260.0 * 13, "waterplane_second_moments": 260.0 * 169}
        assert np.allclose(a, b, rtol=0, atol=1e-8 * scale[name]), name
    k_hull = hull.stiffness(1.2e5, np.array(center) + [0.5, -0.3, 0.2])
    k_box = box.stiffness(1.2e5, np.array(center) + [0.5, -0.3, 0.2])
    assert np.allclose(k_hull, k_box, rtol=0, atol=1e-8 * np.abs(k_box).max())


def test_hull_inputs_agree():
    """A path, a PolyData (with inward normals), a meshio.Mesh: same result."""
    offset = (0.0, 0.0, 1.6)
    ref = hull_hydrostatics(HULL, offset=offset)
    inward = hull_surface()
    faces = inward.faces.reshape(-1, 4).copy()
    faces[:, 1:] = faces[:, :0:-1]
    inward = pv.PolyData(inward.points, faces.ravel())
    mio = meshio.Mesh(np.asarray(inward.points), [("triangle", faces[:, 1:])])
    for mesh in (str(HULL), inward, mio):
        other = hull_hydrostatics(mesh, offset=offset)
        assert np.isclose(other.volume, ref.volume, rtol=1e-12)
        assert np.allclose(other.waterplane_second_moments, ref.waterplane_second_moments)


def test_hull_yawed_and_translated():
    """Yaw and a plan translation keep V and Awp; the waterplane tensor rotates."""
    psi, shift, draft = np.radians(30.0), np.array([3.0, -2.0]), 0.9
    surface = posed(hull_surface((0, 0, H / 2 - draft)), [*shift, 0, 0, 0, psi], np.zeros(3))
    hs = hull_hydrostatics(surface)
    c, s = np.cos(psi), np.sin(psi)
    ixx0, iyy0 = L**3 * W / 12, W**3 * L / 12  # int x^2, int y^2 in the box axes
    a = L * W
    expected = [ixx0 * c**2 + iyy0 * s**2 + a * shift[0] ** 2,
                ixx0 * s**2 + iyy0 * c**2 + a * shift[1] ** 2,
                (ixx0 - iyy0) * c * s + a * shift[0] * shift[1]]
    assert np.isclose(hs.volume, a * draft, rtol=1e-10)
    assert np.isclose(hs.waterplane_area, a, rtol=1e-10)
    assert np.allclose(hs.center_of_buoyancy, [*shift, -draft / 2], atol=1e-9)
    assert np.allclose(hs.waterplane_first_moments, a * shift, rtol=1e-10)
    assert np.allclose(hs.waterplane_second_moments, expected, rtol=1e-10)


def test_hull_heeled_box_centroid():
    """Heel phi about x: the wetted section is a trapezoid (wall-sided), known in closed form."""
    phi, tz = 0.12, 1.5  # box centre at z = tz, waterline crosses both side walls
    hs = hull_hydrostatics(posed(hull_surface(), [0, 0, tz, phi, 0, 0], np.zeros(3)))
    b, c = W / 2, -tz / np.cos(phi)  # body-frame waterline: z = c - y tan(phi)
    t = np.tan(phi)
    mean_height = c + H / 2  # submerged height at y = 0
    area = 2 * b * mean_height
    yb = -t * b**2 / (3 * mean_height)
    # z centroid: int (-H/2 + h/2) h dy / area with h = mean_height - y t
    zb = -H / 2 + (mean_height**2 + t**2 * b**2 / 3) / (2 * mean_height)
    assert np.isclose(hs.volume, L * area, rtol=1e-10)
    expected = rotation_matrix([phi, 0, 0]) @ [0, yb, zb] + [0, 0, tz]
    assert np.allclose(hs.center_of_buoyancy, expected, atol=1e-9)
    closed = posed(hull_surface(), [0, 0, tz, phi, 0, 0], np.zeros(3)).clip_closed_surface(
        normal="-z", origin=(0, 0, 0))  # keeps z < 0
    assert np.isclose(closed.volume, hs.volume, rtol=1e-8)  # VTK's own mass properties


# --------------------------------------------------------------------------- restoring matrix by FD

def exact_load(surface, q, ref, mass, cog, generalized):
    """Exact buoyancy + weight of the posed hull: force and moment about the displaced
    reference point, or (generalized) the load conjugate to q."""
    q = np.asarray(q, dtype=float)
    origin = ref + q[:3]
    hs = hull_hydrostatics(posed(surface, q, ref), reference_point=origin)
    f_b = np.array([0.0, 0.0, RHO * G * hs.volume])
    f_w = np.array([0.0, 0.0, -mass * G])
    r_b = hs.center_of_buoyancy - origin  # global axes
    r_g = cog - ref  # body axes
    if generalized:
        r_b_body = rotation_matrix(q[3:]).T @ r_b
        return attachment_jacobian(q, r_b_body).T @ f_b + attachment_jacobian(q, r_g).T @ f_w
    r_g = rotation_matrix(q[3:]) @ r_g
    return np.concatenate([f_b + f_w, np.cross(r_b, f_b) + np.cross(r_g, f_w)])


@pytest.mark.parametrize("generalized", [False, True])
def test_stiffness_finite_difference(generalized):
    """-d(load)/dq of the clipped, displaced hull equals K, for a body off equilibrium
    with an offset centre of mass and a reference point above the water."""
    draft, center = 1.2, np.array([0.7, -0.4, H / 2 - 1.2])
    ref = np.array([2.0, 1.0, 1.5])
    cog = center + [0.5, -0.3, 0.2]
    mass = 0.8 * RHO * L * W * draft
    surface = hull_surface(center)
    body = RigidBody(mass, cog, uniform_box_inertia(mass, L, W, H), reference_point=ref,
                     hydrostatics=box_hydrostatics(L, W, H, draft, ref, center[:2]))
    k = body.hydrostatic_stiffness(generalized=generalized)
    h = 1e-4
    fd = -np.column_stack([
        (exact_load(surface, h * e, ref, mass, cog, generalized)
         - exact_load(surface, -h * e, ref, mass, cog, generalized)) / (2 * h)
        for e in np.eye(6)
    ])
    assert np.allclose(k, fd, rtol=0, atol=1e-7 * np.abs(k).max())
    assert np.allclose(body.static_force(), exact_load(surface, np.zeros(6), ref, mass, cog, False))
    if generalized:
        assert np.allclose(k, k.T) and np.allclose(k[:, 5], 0.0)
    else:
        assert abs(k[3, 5]) > 1e4 and abs(k[4, 5]) > 1e4  # WAMIT K46, K56 present


def test_weight_only_stiffness_is_attachment_hessian():
    cog, ref, mass = np.array([1.0, -2.0, 0.5]), np.zeros(3), 1e4
    body = RigidBody(mass, cog, np.eye(3), reference_point=ref)
    weight = [0.0, 0.0, -mass * G]
    assert np.allclose(body.hydrostatic_stiffness(generalized=True),
                       -attachment_hessian(np.zeros(6), cog - ref, weight))
    assert np.allclose(body.static_force(), [0, 0, -mass * G, *np.cross(cog, weight)])


# --------------------------------------------------------------------------- rigid body

def test_mass_matrix_kinetic_energy():
    mass, cog, ref = 1.2e5, np.array([1.0, -0.5, 0.8]), np.array([0.2, 0.3, -0.4])
    inertia = uniform_box_inertia(mass, L, W, H) + [[0, 1e4, 0], [1e4, 0, 0], [0, 0, 0]]
    m = RigidBody(mass, cog, inertia, reference_point=ref).mass_matrix()
    rng = np.random.default_rng(0)
    for _ in range(3):
        v, w = rng.normal(size=3), rng.normal(size=3)
        v_g = v + np.cross(w, cog - ref)
        energy = 0.5 * mass * v_g @ v_g + 0.5 * w @ inertia @ w
        u = np.concatenate([v, w])
        assert np.isclose(0.5 * u @ m @ u, energy, rtol=1e-12)
    xg, yg, zg = cog - ref
    assert np.isclose(m[0, 4], mass * zg) and np.isclose(m[1, 5], mass * xg)
    assert np.isclose(m[2, 3], mass * yg) and np.allclose(m, m.T)


@pytest.mark.parametrize("kwargs, field", [
    (dict(mass=-1.0), "mass"),
    (dict(mass=np.nan), "mass"),
    (dict(center_of_mass=[0, np.nan, 0]), "center_of_mass"),
    (dict(center_of_mass=[0, 0]), "center_of_mass"),
    (dict(inertia=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), "inertia"),
    (dict(inertia=np.diag([1.0, -1.0, 1.0])), "inertia"),
    (dict(added_mass=np.ones((3, 3))), "added_mass"),
    (dict(linear_damping=np.full((6, 6), np.inf)), "linear_damping"),
    (dict(hydrostatics=box_hydrostatics(L, W, H, 1.0, reference_point=(0, 0, 9))), "hydrostatics"),
])
def test_body_validation(kwargs, field):
    args = dict(mass=1.0, center_of_mass=[0, 0, 0], inertia=np.eye(3)) | kwargs
    with pytest.raises(ValueError, match=field):
        RigidBody(**args)


def test_hull_validation():
    with pytest.raises(ValueError, match="not closed"):
        hull_hydrostatics(hull_surface().extract_cells(range(100)).extract_surface(
            algorithm="dataset_surface"))
    with pytest.raises(ValueError, match="below the waterline"):
        hull_hydrostatics(HULL, offset=(0, 0, 3.0))
    with pytest.raises(ValueError, match="fully submerged"):
        hull_hydrostatics(HULL, offset=(0, 0, -3.0))
    with pytest.raises(FileNotFoundError):
        hull_hydrostatics(HULL.with_name("missing.stl"))
    with pytest.raises(ValueError, match="draft"):
        box_hydrostatics(L, W, H, 6.0)
    with pytest.raises(ValueError, match="volume"):
        Hydrostatics(np.zeros(3), 0.0, np.zeros(3), 1.0, np.zeros(2), np.zeros(3))


def test_from_hull_equals_box():
    draft, mass = 0.9, 1.2e5
    box = RigidBody.box(L, W, H, mass, draft)
    hull = RigidBody.from_hull(HULL, mass, box.center_of_mass, box.inertia,
                               offset=(0, 0, H / 2 - draft))
    assert np.allclose(hull.hydrostatic_stiffness(), box.hydrostatic_stiffness(),
                       rtol=0, atol=1e-8 * np.abs(box.hydrostatic_stiffness()).max())
    assert np.allclose(hull.static_force(), box.static_force(), atol=1e-6)


def test_fast_rotation_and_slopes_match_the_product_and_finite_differences():
    """rotation_and_slopes (the time loop's closed form): R equals Rz Ry Rx built from
    the axis rotations, and dR/dangle matches central differences (1e-8)."""
    from skmoor.bodies.body import _axis_rotation, rotation_and_slopes

    rng = np.random.default_rng(3)
    for angles in rng.normal(scale=0.7, size=(5, 3)):
        R, dR = rotation_and_slopes(angles)
        rx, ry, rz = (_axis_rotation(angles[k], k)[0] for k in range(3))
        np.testing.assert_allclose(R, rz @ ry @ rx, atol=1e-15)
        for a in range(3):
            step = np.zeros(3)
            step[a] = 1e-6
            fd = (rotation_and_slopes(angles + step)[0] - rotation_and_slopes(angles - step)[0]) / 2e-6
            np.testing.assert_allclose(dR[a], fd, atol=1e-8)


def test_fast_attachment_state_matches_the_checked_functions():
    """attachment_state (the time loop's compiled path) gives attachment_displacement and
    attachment_jacobian for several points at once."""
    from skmoor.bodies.body import (
        attachment_displacement,
        attachment_jacobian,
        attachment_state,
    )

    rng = np.random.default_rng(4)
    r = rng.normal(scale=20.0, size=(4, 3))
    q = np.concatenate([rng.normal(size=3), rng.normal(scale=0.3, size=3)])
    displacement, J = attachment_state(q, r)
    np.testing.assert_allclose(displacement, attachment_displacement(q, r), atol=1e-12)
    np.testing.assert_allclose(J, attachment_jacobian(q, r).reshape(-1, 6), atol=1e-12)
