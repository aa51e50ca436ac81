"""Hydrodynamic terms (skmoor.sea.hydro): tangents against finite differences, the numpy
kernel against the scikit-fem forms, and the physics against closed forms: a taut
string's sag in a normal current (q L^2 / 8 T), the axial drag of a line along the
current, the drag per unstretched length of a stretched catenary, the string's natural
frequencies with added mass, and a moored body's drag in a current."""
import dataclasses

import numpy as np
import pytest

import skmoor
from skmoor.coupling.system import System
from skmoor.lines.catenary import solve_catenary
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.sea.hydro import body_hydrodynamics, form_terms, line_hydrodynamics
from skmoor.sea.waves import AiryWave, Current, JonswapWave, Sea
from skmoor.solvers.modes import eigenmodes
from skmoor.solvers.statics import solve_static

RHO = 1025.0
ROPE = LineType(EA=2e6, mass=50.0, diameter=0.12, Cd_n=1.2, Cd_t=0.3, Ca_n=1.0, Ca_t=0.4)
CHAIN = LineType(EA=5e8, mass=120.0, diameter=0.09, Cd_n=2.4, Cd_t=1.15, Ca_n=0.8, Ca_t=0.5)


@pytest.fixture(scope="module")
def lines():
    """A soft catenary (T/EA up to ~0.05, so the stretch matters) and a kinked 3D
    polyline of another line type, on one mesh."""
    rope = solve_catenary([-300.0, 0.0, -100.0], [0.0, 0.0, -5.0], ROPE.weight, ROPE.EA,
                          length=330.0)
    kinked = np.array([[0.0, 0.0, -80.0], [10.0, 5.0, -60.0], [20.0, 0.0, -40.0],
                       [22.0, 3.0, -30.0]])
    return LineSet([Line.from_catenary(rope, ROPE, 12, name="rope"),
                    Line.from_polyline(kinked, CHAIN, name="chain", tension=3e4)])


def full_sea(depth=100.0):
    return Sea(depth, current=Current(profile=[(-depth, 0.1), (0.0, 0.9)], heading_deg=25.0),
               waves=[AiryWave(5.0, 9.0, depth, heading_deg=-20.0),
                      JonswapWave(3.0, 10.0, depth, n_components=40, seed=3)])


def state(lines, seed=0):
    rng = np.random.default_rng(seed)
    return 0.5 * rng.standard_normal(lines.ndofs), 1.5 * rng.standard_normal(lines.ndofs)


def total(terms, lines, u, ud, t, layout="sparse"):
    R, K, Kv = 0.0, None, None
    for term in terms:
        r, k, kv = term.evaluate(u, ud, t, True, layout)
        R, K = R + r, k if K is None else K + k
        Kv = Kv if kv is None else (kv if Kv is None else Kv + kv)
    return R, K, Kv


@pytest.mark.parametrize("sea", [None, "current", "full"])
def test_kernel_equals_forms(lines, sea):
    sea = {None: None, "current": Sea(100.0, current=Current(0.7, 40.0)),
           "full": full_sea()}[sea]
    u, ud = state(lines)
    fast = line_hydrodynamics(lines, sea)
    forms = form_terms(lines, sea)
    assert len(forms) == (2 if sea is not None and sea.has_waves else 1)
    for layout in ("sparse", "dense", "band"):
        R1, K1, V1 = total([fast], lines, u, ud, 4.0, layout)
        R2, K2, V2 = total(forms, lines, u, ud, 4.0, layout)
        if layout != "dense":
            K1, V1, K2, V2 = (A.toarray() for A in (K1, V1, K2, V2))
        for a, b in ((R1, R2), (K1, K2), (V1, V2)):
            assert np.abs(a - b).max() <= 1e-13 * np.abs(b).max()
    for lumped in (True, False):
        M1 = line_hydrodynamics(lines, sea, lumped_mass=lumped).mass_matrix()
        M2 = form_terms(lines, sea, lumped_mass=lumped)[0].mass_matrix()
        assert abs(M1 - M2).max() <= 1e-13 * abs(M2).max()


@pytest.mark.parametrize("sea", [None, "current", "full"])
def test_kernel_equals_forms_on_bending_lines(sea):
    """The compiled kernel on the Hermite cubics (the relative velocity and the tangent r'
    from the four shape functions, the water on the value DOFs alone) against the forms
    on the same element: R, K, C and the consistent added mass to round-off (the water
    put on the slope DOFs, P1's chord for r' or the slopes' rows dropped would differ)."""
    sea = {None: None, "current": Sea(100.0, current=Current(0.7, 40.0)),
           "full": full_sea()}[sea]
    bending = dataclasses.replace(ROPE, EI=3e3)
    rope = solve_catenary([-300.0, 0.0, -100.0], [0.0, 0.0, -5.0], bending.weight,
                          bending.EA, length=330.0)
    lines = LineSet([Line.from_catenary(rope, bending, 8, name="rope")])
    assert lines.hermite
    u, ud = state(lines, seed=4)
    fast = line_hydrodynamics(lines, sea, lumped_mass=False)
    R1, K1, V1 = total([fast], lines, u, ud, 4.0, "dense")
    R2, K2, V2 = total(form_terms(lines, sea, lumped_mass=False), lines, u, ud, 4.0, "dense")
    for a, b in ((R1, R2), (K1, K2), (V1, V2)):
        assert np.abs(b).max() > 0
        assert np.abs(a - b).max() <= 1e-11 * np.abs(b).max()  # the sums' round-off
    M1 = fast.mass_matrix()
    M2 = form_terms(lines, sea, lumped_mass=False)[0].mass_matrix()
    assert abs(M1 - M2).max() <= 1e-13 * abs(M2).max()
    # left out, the added mass is the lines' kind: consistent here; lumped is refused
    assert abs(line_hydrodynamics(lines, sea).mass_matrix() - M2).max() <= 1e-13 * abs(M2).max()
    with pytest.raises(ValueError, match="lumped_mass: bending"):
        line_hydrodynamics(lines, sea, lumped_mass=True)


class UniformSea(Sea):
    """Water moving and accelerating uniformly in space (no spatial gradient, so the
    tangent must be exact)."""

    def __init__(self, velocity, acceleration):
        super().__init__(100.0, current=Current(0.0))
        self.waves = ["uniform"]
        self.u, self.a = np.asarray(velocity, float), np.asarray(acceleration, float)

    def velocity(self, points, t=0.0):
        return np.broadcast_to(self.u * (1 + 0.1 * t), np.shape(points)).copy()

    def acceleration(self, points, t=0.0):
        return np.broadcast_to(self.a, np.shape(points)).copy()

    def kinematics(self, points, t=0.0):
        return self.velocity(points, t), self.acceleration(points, t)


@pytest.mark.parametrize("fast", [True, False])
def test_tangents_are_derivatives(lines, fast):
    """K = dR/du and Kv = dR/dudot against central differences along random directions,
    in water moving and accelerating uniformly (drag and fluid inertia)."""
    sea = UniformSea([0.4, -0.3, 0.2], [0.5, 0.2, -0.7])
    terms = [line_hydrodynamics(lines, sea)] if fast else form_terms(lines, sea)
    u, ud = state(lines, 1)
    _R, K, Kv = total(terms, lines, u, ud, 2.0)
    rng = np.random.default_rng(5)
    for _ in range(3):
        d = rng.standard_normal(lines.ndofs)
        h = 1e-6
        dR_du = (total(terms, lines, u + h * d, ud, 2.0)[0]
                 - total(terms, lines, u - h * d, ud, 2.0)[0]) / (2 * h)
        dR_dv = (total(terms, lines, u, ud + h * d, 2.0)[0]
                 - total(terms, lines, u, ud - h * d, 2.0)[0]) / (2 * h)
        np.testing.assert_allclose(K @ d, dR_du, atol=1e-6 * np.abs(dR_du).max())
        np.testing.assert_allclose(Kv @ d, dR_dv, atol=1e-6 * np.abs(dR_dv).max())


def test_drag_is_per_unstretched_length_and_dissipative():
    """A stretched catenary (in the x-z plane) translating at V along y in still water:
    the drag sums to 1/2 rho Cd_n d V^2 times the UNSTRETCHED length, opposes the motion,
    and the transverse added mass sums to Ca_n rho A times the unstretched length."""
    rope = solve_catenary([-300.0, 0.0, -100.0], [0.0, 0.0, -5.0], ROPE.weight, ROPE.EA,
                          length=330.0)
    lines = LineSet([Line.from_catenary(rope, ROPE, 20)])
    assert lines.lines[0].length > rope.L * 1.02  # the reference is visibly stretched
    V = 1.3
    ud = np.zeros(lines.ndofs)
    ud[lines.nodal_dofs[:, 1]] = V
    for fast in (True, False):
        terms = [line_hydrodynamics(lines)] if fast else form_terms(lines)
        R, _, _ = total(terms, lines, np.zeros(lines.ndofs), ud, 0.0)
        drag = 0.5 * RHO * ROPE.Cd_n * ROPE.diameter * V**2 * rope.L
        assert R[lines.nodal_dofs[:, 1]].sum() == pytest.approx(drag, rel=1e-9)
        assert np.abs(R[lines.nodal_dofs[:, [0, 2]]]).max() < 1e-9 * drag
        M = terms[0].mass_matrix()
        y = lines.nodal_dofs[:, 1]
        assert M[np.ix_(y, y)].sum() == pytest.approx(ROPE.Ca_n * RHO * ROPE.area * rope.L,
                                                      rel=1e-9)


def string(line_type, L=100.0, n=40, T=1e4, direction=(1.0, 0.0, 0.0)):
    start = np.array([0.0, 0.0, -50.0])
    points = np.linspace(start, start + L * np.asarray(direction), n + 1)
    return LineSet([Line.from_polyline(points, line_type, tension=T)])


def test_taut_string_in_normal_current_sags_as_the_parabola():
    """Weightless string, tension T, span L, normal current U: mid-span deflection
    q L^2 / (8 T), q = 1/2 rho Cd d U^2, and the supports carry q L."""
    cable = LineType(EA=1e6, mass=10.0, diameter=0.1, weight=0.0, Cd_n=1.2, Cd_t=0.5)
    L, T, U = 100.0, 1e4, 0.1
    lines = string(cable, L, 40, T)
    sea = Sea(100.0, current=Current(U, heading_deg=90.0))
    system = System(lines, fairleads="fixed", terms=[line_hydrodynamics(lines, sea)])
    x = solve_static(system).x
    u = system.full_displacement(x)[lines.nodal_dofs]
    q = 0.5 * RHO * cable.Cd_n * cable.diameter * U**2
    assert u[20, 1] == pytest.approx(q * L**2 / (8 * T), rel=1e-3)
    s = lines.points[:, 0]
    np.testing.assert_allclose(u[:, 1], q * s * (L - s) / (2 * T), atol=1e-3 * q * L**2 / (8 * T))
    fair, anchor = system.reactions(x)
    # (the deflected string's slope, up to 4 sag / L ~ 3e-3, tilts the normal flow: 1e-5)
    assert fair[0, 1] + anchor[0, 1] == pytest.approx(q * L, rel=1e-5)


def test_line_along_the_current_feels_the_axial_drag():
    """Current U along a taut straight line: axial force 1/2 rho Cd_t (pi d) U^2 L
    (MoorDyn's CdAx on the surface area), carried by the supports."""
    cable = LineType(EA=1e7, mass=10.0, diameter=0.1, weight=0.0, Cd_n=1.2, Cd_t=0.5)
    L, U = 80.0, 0.8
    direction = np.array([0.6, 0.8, 0.0])
    lines = string(cable, L, 16, 1e4, direction)
    sea = Sea(100.0, current=Current(U, heading_deg=np.degrees(np.arctan2(0.8, 0.6))))
    system = System(lines, fairleads="fixed", terms=[line_hydrodynamics(lines, sea)])
    x = solve_static(system).x
    fair, anchor = system.reactions(x)
    axial = 0.5 * RHO * cable.Cd_t * np.pi * cable.diameter * U**2 * L
    np.testing.assert_allclose(fair[0] + anchor[0], axial * direction, rtol=1e-9)
    # no transverse deflection
    u = system.full_displacement(x)[lines.nodal_dofs]
    assert np.abs(np.cross(u, direction)).max() < 1e-9


def test_added_mass_lowers_string_frequencies():
    """omega_n = n pi / L sqrt(T / (m + Ca_n rho A)) for the transverse modes; the ratio
    to the dry string's is exact since both masses are lumped alike."""
    L, T, m = 50.0, 1e4, 10.0
    cable = LineType(EA=1e7, mass=m, diameter=0.1, weight=0.0, Ca_n=1.0, Ca_t=0.5)
    lines = string(cable, L, 50, T, (0.6, 0.0, 0.8))
    omegas = []
    for terms in ((), [line_hydrodynamics(lines)]):
        system = System(lines, fairleads="fixed", terms=terms)
        _, K, _ = system.residual(np.zeros(system.n))
        omegas.append(eigenmodes(K, system.M, k=6).omega)
    wet = m + cable.Ca_n * RHO * cable.area
    np.testing.assert_allclose(omegas[1] / omegas[0], np.sqrt(m / wet), rtol=1e-10)
    expected = np.repeat(np.arange(1, 4) * np.pi / L * np.sqrt(T / wet), 2)
    np.testing.assert_allclose(omegas[1], expected, rtol=2e-3)


def body_load(term, q, qdot, t=0.0):
    """(F, K, Kv) of a BodyLoad: the load (N, N m) and the residual's d/dq, d/dqdot."""
    R, K, C = np.zeros(6), np.zeros((6, 6)), np.zeros((6, 6))
    term.add_to(q, qdot, t, R, K, C)
    return -R, K, C


@pytest.fixture(scope="module")
def paper_model():
    return skmoor.build(skmoor.paper_case())


def test_body_drag_in_a_current_is_held_by_the_mooring(paper_model):
    """A moored body in a current U: at rest its drag is 1/2 rho Cd A U^2 (MoorDyn's body
    CdA), and in the static offset the lines pull it back by exactly that."""
    system = paper_model.system
    body = system.body
    U, cd, area = 1.0, 1.0, 100.0
    sea = Sea(100.0, current=Current(U))
    term = body_hydrodynamics(drag_coefficients=[cd, cd, cd], drag_areas=[area, 30.0, 40.0],
                              sea=sea, reference_point=body.reference_point)
    F, _K, _Kv = body_load(term, np.zeros(6), np.zeros(6))
    drag = 0.5 * RHO * cd * area * U**2
    np.testing.assert_allclose(F, [drag, 0, 0, 0, 0, 0], atol=1e-12)
    plain = System(system.lines, body, terms=[term])
    x = solve_static(plain).x
    fair, _ = plain.reactions(x)
    assert x[plain.nf] > 0.01  # pushed downstream
    assert -fair[:, 0].sum() == pytest.approx(drag, rel=1e-6)


def test_body_drag_rate_and_added_mass(paper_model):
    system = paper_model.system
    sea = Sea(100.0, current=Current(0.5, heading_deg=30.0))
    added = np.diag([1e5, 2e5, 3e5, 1e6, 2e6, 3e6])
    term = body_hydrodynamics(drag_coefficients=[1.0, 0.8, 1.2, 0.5, 0.5, 0.7],
                              drag_areas=[30.0, 40.0, 50.0, 1e3, 2e3, 3e3], added_mass=added,
                              sea=sea, reference_point=system.body.reference_point)
    q = np.array([1.0, 0.5, -0.2, 0.01, 0.02, -0.01])
    qdot = np.array([0.3, -0.2, 0.1, 0.05, -0.03, 0.02])
    F, _K, Kv = body_load(term, q, qdot)
    vr = sea.velocity(system.body.reference_point + q[:3]) - qdot[:3]
    np.testing.assert_allclose(F[:3], 0.5 * RHO * np.array([30.0, 32.0, 60.0]) * vr
                               * np.linalg.norm(vr), rtol=1e-12)
    h = 1e-7
    fd = np.column_stack([(body_load(term, q, qdot + h * e)[0]
                           - body_load(term, q, qdot - h * e)[0]) / (2 * h) for e in np.eye(6)])
    np.testing.assert_allclose(Kv, -fd, rtol=1e-6, atol=1e-6 * np.abs(fd).max())
    with_mass = System(system.lines, system.body, terms=[term])
    block = slice(with_mass.nf, None)
    np.testing.assert_allclose((with_mass.M - system.M).toarray()[block, block], added)


@pytest.mark.parametrize("call, field", [
    (lambda ls: line_hydrodynamics(ls, Sea(100.0, rho=1000.0)), "rho"),
    (lambda ls: line_hydrodynamics(ls, "calm"), "line_hydrodynamics sea"),
    (lambda ls: body_hydrodynamics(drag_coefficients=[1.0] * 6), "drag_coefficients, drag_areas"),
    (lambda ls: body_hydrodynamics(drag_coefficients=[1.0] * 4, drag_areas=[1.0] * 4),
     "drag_coefficients"),
    (lambda ls: body_hydrodynamics(drag_coefficients=[-1.0] * 3, drag_areas=[1.0] * 3),
     "drag_coefficients"),
    (lambda ls: body_hydrodynamics(added_mass=np.eye(3)), "added_mass"),
    (lambda ls: body_hydrodynamics(sea=Sea(50.0), rho=1000.0), "body_hydrodynamics rho"),
])
def test_bad_input_names_the_field(lines, call, field):
    with pytest.raises(ValueError, match=field):
        call(lines)


@pytest.mark.parametrize("kernel", [True, False], ids=["kernel", "forms"])
def test_froude_krylov_alone_on_a_vertical_line(kernel):
    """With Ca = CaAx = 0 the fluid inertia is Froude-Krylov alone: on a fixed vertical
    line from z1 to z2 in an Airy wave (H 4 m, T 8 s, depth 100 m) the horizontal force is
    rho A H/2 w^2 [sinh k(z+h)]_{z1}^{z2} / (k sinh kh) sin(theta), the vertical one
    -rho A H/2 w^2 [cosh k(z+h)]_{z1}^{z2} / (k sinh kh) cos(theta) (the Airy kinematics by
    hand, the dispersion relation by brentq); within 1e-3 of their amplitudes, compiled
    kernel and forms. Fails on a dropped Froude-Krylov part (no force at all)."""
    from scipy.optimize import brentq

    depth, H, T, g, d = 100.0, 4.0, 8.0, 9.81, 0.2
    omega = 2 * np.pi / T
    k = brentq(lambda q: g * q * np.tanh(q * depth) - omega ** 2, 1e-6, 10.0)
    lt = LineType(EA=1e9, mass=80.0, diameter=d, Cd_n=0.0, Cd_t=0.0, Ca_n=0.0, Ca_t=0.0,
                  rho_water=RHO, g=g)
    z1, z2, n = -50.0, -4.0, 184
    X = np.c_[np.full(n + 1, 3.0), np.zeros(n + 1), np.linspace(z1, z2, n + 1)]
    lines = LineSet([Line.from_polyline(X, lt)])
    sea = Sea(depth, rho=RHO, g=g, waves=[AiryWave(H, T, depth, g=g)])
    terms = [line_hydrodynamics(lines, sea)] if kernel else form_terms(lines, sea)
    u = np.zeros(lines.ndofs)
    times = np.linspace(0.0, T, 7)[:-1]
    force = np.array([-sum(term.evaluate(u, u, t, tangent=False)[0] for term in terms)
                      [lines.nodal_dofs].sum(axis=0) for t in times])
    area, a = np.pi * d * d / 4, H / 2
    theta = k * 3.0 - omega * times
    S = (np.sinh(k * (z2 + depth)) - np.sinh(k * (z1 + depth))) / (k * np.sinh(k * depth))
    C = (np.cosh(k * (z2 + depth)) - np.cosh(k * (z1 + depth))) / (k * np.sinh(k * depth))
    horizontal = RHO * area * a * omega ** 2 * S * np.sin(theta)
    vertical = -RHO * area * a * omega ** 2 * C * np.cos(theta)
    assert np.all(np.abs(force[:, 0] - horizontal) <= 1e-3 * np.abs(horizontal).max())
    assert np.all(np.abs(force[:, 1]) <= 1e-9 * np.abs(horizontal).max())
    assert np.all(np.abs(force[:, 2] - vertical) <= 1e-3 * np.abs(vertical).max())


def test_free_points_drag_is_half_rho_cda_speed_squared():
    """A free point's drag (MoorDyn's point CdA) is F = 1/2 rho CdA |w| w, w the water's
    velocity relative to the point: in still water at point velocity v = (1.5, -2, 0.5) m/s
    with CdA = 0.8 m2 the residual is -F, F = -1/2 1025 0.8 |v| v (numbers by hand), and
    its velocity derivative the central difference; in a 1.2 m/s current along x, a point
    at rest feels 1/2 rho CdA 1.2^2 = 590.4 N downstream. Fails on a doubled drag."""
    from skmoor.sea.hydro import PointDrag

    v = np.array([1.5, -2.0, 0.5])
    speed = np.sqrt(1.5 ** 2 + 2.0 ** 2 + 0.5 ** 2)
    F = -0.5 * 1025.0 * 0.8 * speed * v
    drag = PointDrag(0, 0.8, rho=1025.0)
    R, C = np.zeros(3), np.zeros((3, 3))
    drag.add_to(np.zeros(3), v, 0.0, R, C=C)
    assert R == pytest.approx(-F, rel=1e-12)
    h = 1e-6
    for j in range(3):
        Rp, Rm, e = np.zeros(3), np.zeros(3), np.eye(3)[j] * h
        drag.add_to(np.zeros(3), v + e, 0.0, Rp)
        drag.add_to(np.zeros(3), v - e, 0.0, Rm)
        assert C[:, j] == pytest.approx((Rp - Rm) / (2 * h), rel=1e-6)
    current = PointDrag(0, 0.8, rho=1025.0, sea=Sea(100.0, current=Current(speed=1.2)))
    current.position = np.array([0.0, 0.0, -10.0])
    R = np.zeros(3)
    current.add_to(np.zeros(3), np.zeros(3), 0.0, R)
    assert -R == pytest.approx([590.4, 0.0, 0.0], rel=1e-12, abs=1e-9)


def test_exact_body_drag_turns_its_areas_with_the_body_and_has_its_tangents():
    """A body with exact rotations, turned (24, -17, 40 deg) and moving in a current: the
    drag force is 1/2 rho R A diag(CdA) A^T R^T |v_r| v_r with R the body's rotation and A
    its axes at rest, the moment's power equals M . omega (omega from dR/dt R^T) with M
    the same law on w_r = -omega, and the residual's slopes in q and qdot are its central
    differences."""
    from scipy.spatial.transform import Rotation
    from test_large_rotations import angular_velocity, lone_body_system

    from skmoor.bodies.body import RigidBody, rotation_matrix

    body = RigidBody.box(20.0, 10.0, 6.0, 4e5, 3.0, reference_point=[0.0, 0.0, 0.0],
                         rotations="exact")
    sea = Sea(100.0, current=Current(0.7, heading_deg=25.0))
    cda = np.array([1.0, 0.8, 1.2, 0.5, 0.6, 0.7]) * np.array([30.0, 40.0, 50.0, 1e3, 2e3,
                                                                3e3])
    axes = Rotation.from_euler("z", 30.0, degrees=True).as_matrix()
    term = body_hydrodynamics(drag_coefficients=cda, drag_areas=np.ones(6), sea=sea,
                              axes=axes)
    lone_body_system(body).add_term(term)
    q = np.array([0.4, -0.3, 0.2, *np.radians([24.0, -17.0, 40.0])])
    qdot = np.array([0.3, -0.2, 0.1, 0.05, -0.03, 0.04])
    Q, K, C = body_load(term, q, qdot)
    turned = rotation_matrix(q[3:]) @ axes
    vr = sea.velocity(q[:3]) - qdot[:3]
    D_F = turned @ np.diag(0.5 * RHO * cda[:3]) @ turned.T
    np.testing.assert_allclose(Q[:3], np.linalg.norm(vr) * D_F @ vr, rtol=1e-10)
    omega = angular_velocity(q, qdot)
    D_M = turned @ np.diag(0.5 * RHO * cda[3:]) @ turned.T
    M = np.linalg.norm(omega) * D_M @ -omega
    assert Q[3:] @ qdot[3:] == pytest.approx(M @ omega, rel=1e-6)

    def residual(q, qdot):
        return -body_load(term, q, qdot)[0]

    h = 1e-6
    for slope, shifted in ((K, lambda e: (residual(q + h * e, qdot), residual(q - h * e, qdot))),
                           (C, lambda e: (residual(q, qdot + h * e), residual(q, qdot - h * e)))):
        fd = np.column_stack([(ahead - behind) / (2 * h)
                              for ahead, behind in map(shifted, np.eye(6))])
        np.testing.assert_allclose(slope, fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())
