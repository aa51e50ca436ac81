"""Hydrodynamic terms (skmoor.sea.hydro) against numbers worked by hand, beside
test_hydro.py: the added mass of a straight line as the P1 (lumped and consistent) and
cubic Hermite element matrices of rho A [Ca_n (I - e e^T) + Ca_t e e^T], with either
coefficient zero; the drag of a line towed along its axis (no normal flow at all) with its
rate and its follower stiffness in closed form; the consistent load of a normal current on
a Hermite line; the water the lines see (Airy kinematics by hand); the hand tangents of the
forms in accelerating water against central differences; a rigid body's and a free
point's quadratic drag in still water and in an Airy wave at a displaced position and a
time t > 0, with their slopes against central differences."""
import numpy as np
import pytest
from scipy.optimize import brentq

from skmoor.coupling.system import PointMass, System
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.sea.hydro import (
    LineHydroKernel,
    PointDrag,
    added_mass_matrix,
    body_hydrodynamics,
    form_terms,
    line_hydrodynamics,
    line_terms,
    nodal_water,
)
from skmoor.sea.waves import AiryWave, Current, Sea

RHO = 1025.0
G = 9.81
DEPTH = 80.0
H, PERIOD, HEADING = 3.0, 9.0, 35.0
OMEGA = 2 * np.pi / PERIOD
K = brentq(lambda k: G * k * np.tanh(k * DEPTH) - OMEGA ** 2, 1e-6, 10.0, xtol=1e-15)
WAVE_DIRECTION = np.array([np.cos(np.radians(HEADING)), np.sin(np.radians(HEADING)), 0.0])


def airy(x, t):
    """(velocity, acceleration) of the Airy wave (H, PERIOD, HEADING, phase 0) at points x
    (..., 3) below the still water level (Dean & Dalrymple ch. 3-4): u = a w ch cos(theta)
    along the heading, w = a w sh sin(theta); du/dt = a w^2 ch sin(theta), dw/dt =
    -a w^2 sh cos(theta); ch, sh = cosh, sinh k(z + h) / sinh kh."""
    x = np.asarray(x, float)
    theta = K * (x[..., :2] @ WAVE_DIRECTION[:2]) - OMEGA * t
    ch = np.cosh(K * (x[..., 2] + DEPTH)) / np.sinh(K * DEPTH)
    sh = np.sinh(K * (x[..., 2] + DEPTH)) / np.sinh(K * DEPTH)
    a = H / 2
    velocity = (a * OMEGA * ch * np.cos(theta))[..., None] * WAVE_DIRECTION
    velocity[..., 2] = a * OMEGA * sh * np.sin(theta)
    acceleration = (a * OMEGA ** 2 * ch * np.sin(theta))[..., None] * WAVE_DIRECTION
    acceleration[..., 2] = -a * OMEGA ** 2 * sh * np.cos(theta)
    return velocity, acceleration


def wave_sea(current=None):
    return Sea(DEPTH, rho=RHO, g=G, current=current,
               waves=[AiryWave(H, PERIOD, DEPTH, heading_deg=HEADING, g=G)])


LENGTHS = np.array([3.0, 5.0, 4.0, 6.0])  # unequal elements: lumped != consistent anywhere


def straight(line_type, direction=(0.6, 0.0, 0.8), start=(2.0, -1.0, -60.0), element=None):
    """A stress-free straight line along ``direction`` on the elements LENGTHS; returns
    (LineSet, unit direction)."""
    e = np.asarray(direction, float) / np.linalg.norm(direction)
    s = np.concatenate([[0.0], np.cumsum(LENGTHS)])
    points = np.asarray(start, float) + s[:, None] * e
    return LineSet([Line.from_polyline(points, line_type)], element=element), e


def line_type(Ca_n=1.0, Ca_t=0.4, Cd_n=1.1, Cd_t=0.2):
    return LineType(EA=1e7, mass=20.0, diameter=0.15, Cd_n=Cd_n, Cd_t=Cd_t, Ca_n=Ca_n,
                    Ca_t=Ca_t, rho_water=RHO, g=G)


def added_block(lt, e):
    """rho A [Ca_n (I - e e^T) + Ca_t e e^T] (kg/m): the added mass per unit length of a
    cylinder along e (MoorDyn's Ca, CaAx)."""
    return RHO * lt.area * (lt.Ca_n * (np.eye(3) - np.outer(e, e)) + lt.Ca_t * np.outer(e, e))


def p1_added_mass(lt, e, lumped):
    """The P1 element matrices by hand: consistent h/6 [[2, 1], [1, 2]], lumped (row sums)
    h/2 I, each times added_block; node-major DOFs (node, x/y/z)."""
    n = len(LENGTHS) + 1
    W = np.zeros((n, n))
    for i, h in enumerate(LENGTHS):
        W[i:i + 2, i:i + 2] += h / 2 * np.eye(2) if lumped else h / 6 * np.array([[2, 1], [1, 2]])
    return np.kron(W, added_block(lt, e))


def on_nodes(M, lines, dofs=None):
    dofs = lines.nodal_dofs.ravel() if dofs is None else dofs
    return M.toarray()[np.ix_(dofs, dofs)]


MASS_ENTRY_POINTS = {
    "added_mass_matrix": (lambda ls: added_mass_matrix(ls), True),
    "added_mass_matrix consistent": (lambda ls: added_mass_matrix(ls, lumped=False), False),
    "kernel": (lambda ls: line_hydrodynamics(ls).mass_matrix(), True),
    "kernel consistent": (lambda ls: line_hydrodynamics(ls, lumped_mass=False).mass_matrix(),
                          False),
    "kernel class": (lambda ls: LineHydroKernel(ls).mass_matrix(), True),
    "forms": (lambda ls: form_terms(ls)[0].mass_matrix(), True),
    "forms consistent": (lambda ls: form_terms(ls, lumped_mass=False)[0].mass_matrix(), False),
    "line_terms": (lambda ls: line_terms(ls)[0].mass_matrix(), True),
    "line_terms consistent": (lambda ls: line_terms(ls, lumped_mass=False)[0].mass_matrix(),
                              False),
}


@pytest.mark.parametrize("Ca_n, Ca_t", [(1.0, 0.4), (0.9, 0.0), (0.0, 0.6)],
                         ids=["both", "normal only", "axial only"])
@pytest.mark.parametrize("entry", list(MASS_ENTRY_POINTS))
def test_added_mass_of_a_straight_line_is_the_element_matrix(entry, Ca_n, Ca_t):
    """A stress-free straight line along (0.6, 0, 0.8) on unequal elements: the added mass
    is the P1 element matrix (consistent h/6 [[2, 1], [1, 2]], or its row sums h/2 where
    lumped: the default everywhere, as the System lumps the line's own mass) times
    rho A [Ca_n (I - e e^T) + Ca_t e e^T], built here by hand, to 1e-12; a rigid
    translation along e then carries Ca_t rho A L, across it Ca_n rho A L. Fails on the
    axial added mass dropped or mis-scaled (Ca_t / rho), on a line with Ca_n = 0 or
    Ca_t = 0 left without added mass (an 'and' for an 'or'), and on a consistent matrix
    where the lumped one is the default (or the other way round)."""
    lt = line_type(Ca_n, Ca_t)
    lines, e = straight(lt)
    build, lumped = MASS_ENTRY_POINTS[entry]
    M = on_nodes(build(lines), lines)
    expected = p1_added_mass(lt, e, lumped)
    np.testing.assert_allclose(M, expected, rtol=0, atol=1e-12 * np.abs(expected).max())
    rigid = np.tile(e, len(LENGTHS) + 1)
    assert rigid @ M @ rigid == pytest.approx(Ca_t * RHO * lt.area * LENGTHS.sum(), rel=1e-12,
                                              abs=1e-12)


def test_no_added_mass_without_coefficients():
    """Ca_n = Ca_t = 0: no added mass at all (None, not a zero matrix), on every entry
    point. Fails when a zero matrix (or a mass) is reported for a massless coating."""
    lines, _ = straight(line_type(0.0, 0.0))
    for build, _ in MASS_ENTRY_POINTS.values():
        assert build(lines) is None


def hermite_added_mass(lt, e):
    """The cubic Hermite (beam) consistent mass matrix h/420 [[156, 22h, 54, -13h], [22h,
    4h^2, 13h, -3h^2], [54, 13h, 156, -22h], [-13h, -3h^2, -22h, 4h^2]] on (value, d/ds)
    per node, times added_block; DOFs (node, value/slope, x/y/z)."""
    n = len(LENGTHS) + 1
    W = np.zeros((2 * n, 2 * n))
    for i, h in enumerate(LENGTHS):
        W[2 * i:2 * i + 4, 2 * i:2 * i + 4] += h / 420 * np.array(
            [[156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
             [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]])
    return np.kron(W, added_block(lt, e))


def test_hermite_line_terms_are_the_consistent_forms():
    """On a bending (Hermite) LineSet, ``line_terms`` gives the forms: (1) the added mass
    is the cubic beam mass matrix (h/420 [156, 22h, ...]) times rho A [Ca_n P + Ca_t e e^T]
    on values and slopes, consistent whatever lumped_mass says (row-sum lumping has no
    meaning for slope DOFs); (2) a uniform current U normal to the line, line at rest,
    loads it with q = 1/2 rho Cd_n d U^2 per unit length as the consistent Hermite load:
    q (h_l + h_r) / 2 on a node's value DOF and q (h_r^2 - h_l^2) / 12 on its slope DOF
    (the residual is minus that). Fails on a lumped Hermite mass, on the sea or the lines
    not passed on, and on a wrong default path."""
    lt = line_type()
    lines, e = straight(lt, element="hermite")
    assert lines.hermite
    U = 0.8
    normal = np.array([0.0, 1.0, 0.0])  # e has no y component: the current is normal
    sea = Sea(DEPTH, rho=RHO, g=G, current=Current(U, heading_deg=90.0))
    dofs = np.concatenate([lines.nodal_dofs, lines.slope_dofs], axis=1).ravel()
    expected = hermite_added_mass(lt, e)
    for lumped_mass in (True, False):
        terms = line_terms(lines, sea, lumped_mass=lumped_mass)
        masses = [term.mass_matrix() for term in terms if term.mass_matrix() is not None]
        assert len(masses) == 1
        np.testing.assert_allclose(on_nodes(masses[0], lines, dofs), expected, rtol=0,
                                   atol=1e-12 * np.abs(expected).max())
    u = np.zeros(lines.ndofs)
    R = sum(term.evaluate(u, u, 0.0, tangent=False)[0] for term in line_terms(lines, sea))
    q = 0.5 * RHO * lt.Cd_n * lt.diameter * U ** 2
    h_left, h_right = np.r_[0.0, LENGTHS], np.r_[LENGTHS, 0.0]
    scale = q * LENGTHS.max()
    np.testing.assert_allclose(R[lines.nodal_dofs] @ normal, -q * (h_left + h_right) / 2,
                               rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(R[lines.slope_dofs] @ normal, -q * (h_right ** 2 - h_left ** 2) / 12,
                               rtol=0, atol=1e-12 * scale * LENGTHS.max())
    along = np.concatenate([R[lines.nodal_dofs] @ e, R[lines.slope_dofs] @ e])
    assert np.abs(along).max() < 1e-12 * scale


@pytest.mark.parametrize("kernel", [True, False], ids=["kernel", "forms"])
def test_line_towed_along_its_axis(kernel):
    """A stress-free line along x towed along its axis at V (still water): the normal
    relative flow is exactly zero. By hand, with k_t = 1/2 rho Cd_t pi d: the residual is
    +k_t V^2 (h_l + h_r)/2 on each node's x DOF (the drag opposes the motion) and zero
    across; its rate d/dudot is 2 k_t V times the consistent P1 matrix h/6 [[2, 1], [1, 2]]
    on x and exactly zero across (the normal drag is quadratic: no slope at zero normal
    flow, and no 0/0); its stiffness d/du is the axial drag turning with the tangent,
    k_t V^2 int phi_i dphi_j/ds = k_t V^2 [[-1/2, 1/2], [-1/2, 1/2]] per element on y and
    z, zero on x. Fails on NaN where the normal speed vanishes, a factor 2 in the axial
    rate, or a follower term of the wrong sign."""
    lt = line_type(Cd_n=1.3, Cd_t=0.4)
    lines, _ = straight(lt, direction=(1.0, 0.0, 0.0))
    V = 0.7
    ud = np.zeros(lines.ndofs)
    ud[lines.nodal_dofs[:, 0]] = V
    terms = [line_hydrodynamics(lines)] if kernel else form_terms(lines)
    R, Kx, C = (sum(parts) for parts in zip(*(term.evaluate(np.zeros(lines.ndofs), ud, 0.0,
                                                             layout="dense") for term in terms)))
    k_t = 0.5 * RHO * lt.Cd_t * np.pi * lt.diameter
    n = len(LENGTHS) + 1
    h_left, h_right = np.r_[0.0, LENGTHS], np.r_[LENGTHS, 0.0]
    x, y, z = lines.nodal_dofs.T
    np.testing.assert_allclose(R[x], k_t * V ** 2 * (h_left + h_right) / 2, rtol=1e-12)
    assert np.abs(R[lines.nodal_dofs[:, 1:]]).max() < 1e-12 * np.abs(R).max()
    consistent = np.zeros((n, n))
    follower = np.zeros((n, n))
    for i, h in enumerate(LENGTHS):
        consistent[i:i + 2, i:i + 2] += h / 6 * np.array([[2, 1], [1, 2]])
        follower[i:i + 2, i:i + 2] += np.array([[-0.5, 0.5], [-0.5, 0.5]])
    assert np.all(np.isfinite(C)) and np.all(np.isfinite(Kx))
    scale = 2 * k_t * V * LENGTHS.max()
    np.testing.assert_allclose(C[np.ix_(x, x)], 2 * k_t * V * consistent, rtol=0, atol=1e-12 * scale)
    across = np.concatenate([y, z])
    assert np.abs(C[np.ix_(across, range(lines.ndofs))]).max() < 1e-12 * scale
    assert np.abs(C[np.ix_(range(lines.ndofs), across)]).max() < 1e-12 * scale
    for side in (y, z):
        np.testing.assert_allclose(Kx[np.ix_(side, side)], k_t * V ** 2 * follower, rtol=0,
                                   atol=1e-12 * k_t * V ** 2)
    assert np.abs(Kx[x]).max() < 1e-12 * k_t * V ** 2


def test_forms_count_the_added_mass_once_in_waves():
    """form_terms in waves are two terms (drag with the added mass, fluid inertia without),
    on the compiled path one (both in one form): the System's mass grows by the lumped
    added mass alone, sum over interior nodes of (h_l + h_r)/2 times the entries of
    rho A [Ca_n P + Ca_t e e^T], not twice that. Fails when the fluid-inertia term also
    reports the added mass."""
    lt = line_type()
    lines, e = straight(lt)
    dry = System(lines, fairleads="fixed").M
    interior = (LENGTHS[:-1] + LENGTHS[1:]) / 2
    expected = interior.sum() * added_block(lt, e).sum()
    for path, count in (("auto", 2), ("compiled", 1)):
        terms = form_terms(lines, wave_sea(), path=path)
        assert len(terms) == count
        wet = System(lines, fairleads="fixed", terms=terms).M
        assert (wet - dry).sum() == pytest.approx(expected, rel=1e-12), path


def test_kernel_without_a_velocity_is_a_line_at_rest():
    """The compiled kernel called without a velocity (ud None: a static evaluation) in a
    normal current U sees the line at rest: the residual is minus the consistent load of
    q = 1/2 rho Cd_n d U^2, q (h_l + h_r)/2 per node across the line, nothing along it."""
    lt = line_type()
    lines, e = straight(lt)
    U = 0.9
    sea = Sea(DEPTH, rho=RHO, g=G, current=Current(U, heading_deg=90.0))
    term = line_hydrodynamics(lines, sea)
    R = np.zeros(lines.ndofs)
    term.add_to(np.zeros(lines.ndofs), None, 0.0, R)
    q = 0.5 * RHO * lt.Cd_n * lt.diameter * U ** 2
    h_left, h_right = np.r_[0.0, LENGTHS], np.r_[LENGTHS, 0.0]
    f = R[lines.nodal_dofs]
    np.testing.assert_allclose(f[:, 1], -q * (h_left + h_right) / 2, rtol=1e-12)
    assert np.abs(f @ e).max() < 1e-12 * q * LENGTHS.max()


def test_nodal_water_is_the_current_and_the_airy_wave_at_the_displaced_nodes():
    """The water the lines see, at the displaced nodes X + u and time t: by default the
    velocity (a uniform 0.4 m/s current at 30 deg plus the Airy particle velocity, worked
    here), with kind='acceleration' the Airy acceleration alone (the current is steady).
    Fails on the default kind being anything but the velocity, or the water taken at X."""
    lines, _ = straight(line_type())
    sea = wave_sea(Current(0.4, heading_deg=30.0))
    rng = np.random.default_rng(2)
    u = rng.standard_normal(lines.ndofs)
    t = 2.3
    x = lines.points + u[lines.nodal_dofs]
    velocity, acceleration = airy(x, t)
    current = 0.4 * np.array([np.cos(np.radians(30.0)), np.sin(np.radians(30.0)), 0.0])
    np.testing.assert_allclose(nodal_water(lines, sea, u, t)[lines.nodal_dofs],
                               velocity + current, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(nodal_water(lines, sea, u, t, "acceleration")[lines.nodal_dofs],
                               acceleration, rtol=1e-12, atol=1e-14)


class UniformWater(Sea):
    """Water moving and accelerating uniformly (no spatial gradient, which the line
    tangents leave out: there they are exact)."""

    def __init__(self, velocity, acceleration):
        super().__init__(DEPTH, rho=RHO, g=G, current=Current(0.0))
        self.waves = ["uniform"]
        self.u, self.a = np.asarray(velocity, float), np.asarray(acceleration, float)

    def velocity(self, points, t=0.0):
        return np.broadcast_to(self.u, np.shape(points)).copy()

    def acceleration(self, points, t=0.0):
        return np.broadcast_to(self.a, np.shape(points)).copy()

    def kinematics(self, points, t=0.0):
        return self.velocity(points, t), self.acceleration(points, t)


def test_forms_on_the_assembly_path_have_their_derivatives_in_accelerating_water():
    """path='assembly' (scikit-fem's assembly with the hand-written tangents of the drag,
    its rate and the fluid inertia): in water moving and accelerating uniformly, K and Kv
    of the drag and fluid-inertia forms together are the central differences of their
    residual along random directions, on a kinked 3D line in a displaced, moving state.
    Fails when a hand tangent is not handed to the forms (the path then has none)."""
    lt = line_type()
    points = np.array([[0.0, 0.0, -50.0], [6.0, 2.0, -46.0], [10.0, -1.0, -40.0],
                       [13.0, 1.0, -37.0]])
    lines = LineSet([Line.from_polyline(points, lt)])
    sea = UniformWater([0.4, -0.3, 0.2], [0.5, 0.2, -0.7])
    terms = form_terms(lines, sea, path="assembly")
    assert len(terms) == 2
    rng = np.random.default_rng(7)
    u, ud = 0.3 * rng.standard_normal(lines.ndofs), rng.standard_normal(lines.ndofs)

    def residual(u, ud):
        return sum(term.evaluate(u, ud, 1.0, tangent=False)[0] for term in terms)

    parts = [term.evaluate(u, ud, 1.0, layout="dense") for term in terms]
    K = sum(part[1] for part in parts)
    C = sum(part[2] for part in parts if part[2] is not None)
    h = 1e-6
    for _ in range(3):
        d = rng.standard_normal(lines.ndofs)
        dR_du = (residual(u + h * d, ud) - residual(u - h * d, ud)) / (2 * h)
        dR_dv = (residual(u, ud + h * d) - residual(u, ud - h * d)) / (2 * h)
        np.testing.assert_allclose(K @ d, dR_du, atol=1e-6 * np.abs(dR_du).max())
        np.testing.assert_allclose(C @ d, dR_dv, atol=1e-6 * np.abs(dR_dv).max())


@pytest.mark.parametrize("build", [
    lambda ls, sea: line_hydrodynamics(ls, sea),
    lambda ls, sea: form_terms(ls, sea),
    lambda ls, sea: line_terms(ls, sea),
    lambda ls, sea: body_hydrodynamics(sea=sea, rho=RHO),
], ids=["line_hydrodynamics", "form_terms", "line_terms", "body_hydrodynamics"])
def test_one_water_density(build):
    """The line's (or body's) density and the sea's are one water: a sea of 1025.001
    kg/m3 against 1025 (a typed-in mismatch, 1e-6 relative) is refused by every entry
    point, the same density accepted. Fails when an entry point skips the check or
    accepts a visible mismatch."""
    lines, _ = straight(line_type())
    build(lines, Sea(DEPTH, rho=RHO, g=G))
    with pytest.raises(ValueError):
        build(lines, Sea(DEPTH, rho=RHO + 0.001, g=G))


# ------------------------------------------------------------------ bodies

def body_load(term, q, qdot, t=0.0):
    """(F, K, C) of a body term: the load (N, N m) and the residual's d/dq, d/dqdot."""
    R, Kq, C = np.zeros(6), np.zeros((6, 6)), np.zeros((6, 6))
    term.add_to(q, qdot, t, R, Kq, C)
    return -R, Kq, C


def test_body_drag_in_still_water_by_hand():
    """A small body in still water (no sea), moving at v = (0.3, -0.4, 0) m/s (|v| = 0.5)
    and turning at omega = (0.06, 0, 0.08) rad/s (|omega| = 0.1): F = -1/2 rho CdA |v| v per
    axis, M = -1/2 rho CdA_rot |omega| omega; with zero rotational coefficients (a body
    without rotational drag) M = 0. Numbers by hand. Fails on drag in still water
    refused, a sign (drag feeding the motion), or zero coefficients refused."""
    q = np.array([1.0, -2.0, 0.5, 0.01, 0.02, -0.03])
    qdot = np.array([0.3, -0.4, 0.0, 0.06, 0.0, 0.08])
    cd = np.array([1.0, 0.8, 1.2, 0.5, 0.6, 0.7])
    area = np.array([30.0, 40.0, 50.0, 1e3, 2e3, 3e3])
    F, _, C = body_load(body_hydrodynamics(drag_coefficients=cd, drag_areas=area), q, qdot)
    force = -0.5 * RHO * np.array([30.0, 32.0, 60.0]) * 0.5 * np.array([0.3, -0.4, 0.0])
    moment = -0.5 * RHO * np.array([500.0, 1200.0, 2100.0]) * 0.1 * np.array([0.06, 0.0, 0.08])
    np.testing.assert_allclose(F, np.r_[force, moment], rtol=1e-12, atol=1e-12)
    # d/dqdot of the residual 1/2 rho D (|w| I + w w^T / |w|), w = -qdot (translation)
    w = -qdot[:3]
    np.testing.assert_allclose(
        C[:3, :3], 0.5 * RHO * np.diag([30.0, 32.0, 60.0]) @ (0.5 * np.eye(3) + np.outer(w, w) / 0.5),
        rtol=1e-12, atol=1e-9)
    no_turning = body_hydrodynamics(drag_coefficients=np.r_[cd[:3], 0.0, 0.0, 0.0],
                                    drag_areas=area)
    F, _, C = body_load(no_turning, q, qdot)
    np.testing.assert_allclose(F, np.r_[force, 0.0, 0.0, 0.0], rtol=1e-12, atol=1e-12)
    assert np.all(C[3:, 3:] == 0.0)


def test_body_with_added_mass_alone():
    """A body term with an added mass and no drag: no load and no slope at any motion,
    its mass the given (6, 6) matrix. Fails when the drag-free body's coefficients are not
    the six zeros of its three forces and three moments."""
    added = np.diag([1e5, 2e5, 3e5, 1e6, 2e6, 3e6])
    term = body_hydrodynamics(added_mass=added)
    F, Kq, C = body_load(term, np.full(6, 0.1), np.array([0.5, -0.2, 0.1, 0.02, 0.01, -0.03]))
    assert np.all(F == 0.0) and np.all(C == 0.0) and np.all(Kq == 0.0)
    np.testing.assert_array_equal(term.mass_matrix(), added)


def test_body_drag_in_an_airy_wave_at_its_displaced_position():
    """A small body whose reference point (5, -3, -12) is displaced by q[:3] = (1.5, 0.5,
    -2), moving at qdot[:3], in an Airy wave (H 3 m, T 9 s, heading 35 deg, depth 80 m) at
    t = 3.7 s: F = 1/2 rho D |v_r| v_r with v_r = u_w(x_ref + q[:3], t) - qdot[:3], u_w the
    Airy particle velocity worked here; dF/dqdot the central differences at that t. Fails
    on the water taken at t = 0, at x_ref - q, or at the reference point."""
    point = np.array([5.0, -3.0, -12.0])
    cda = np.array([30.0, 40.0, 50.0])
    term = body_hydrodynamics(drag_coefficients=[1.0, 1.0, 1.0], drag_areas=cda,
                              sea=wave_sea(), reference_point=point)
    q = np.array([1.5, 0.5, -2.0, 0.01, -0.02, 0.03])
    qdot = np.array([0.2, -0.1, 0.3, 0.0, 0.0, 0.0])
    t = 3.7
    F, _, C = body_load(term, q, qdot, t)
    vr = airy(point + q[:3], t)[0] - qdot[:3]
    np.testing.assert_allclose(F[:3], 0.5 * RHO * cda * np.linalg.norm(vr) * vr, rtol=1e-10)
    h = 1e-6
    fd = np.column_stack([(body_load(term, q, qdot + h * e, t)[0]
                           - body_load(term, q, qdot - h * e, t)[0]) / (2 * h) for e in np.eye(6)])
    np.testing.assert_allclose(C, -fd, rtol=1e-6, atol=1e-6 * np.abs(fd).max())


def test_exact_body_angle_slopes_in_an_airy_wave():
    """A body with exact rotations turned (20, -10, 30 deg) and moving in the Airy wave
    at t = 2.1 s: the residual's slopes in its three angles are its central differences
    at that time (the water at the body's position and time t, on both sides). Fails on a
    slope taken at another time."""
    from test_large_rotations import lone_body_system

    from skmoor.bodies.body import RigidBody

    body = RigidBody.box(20.0, 10.0, 6.0, 4e5, 3.0, reference_point=[0.0, 0.0, -10.0],
                         rotations="exact")
    term = body_hydrodynamics(drag_coefficients=[1.0, 0.8, 1.2, 0.5, 0.6, 0.7],
                              drag_areas=[30.0, 40.0, 50.0, 1e3, 2e3, 3e3], sea=wave_sea(),
                              reference_point=[0.0, 0.0, -10.0])
    lone_body_system(body).add_term(term)
    q = np.array([0.4, -0.3, 0.2, *np.radians([20.0, -10.0, 30.0])])
    qdot = np.array([0.3, -0.2, 0.1, 0.05, -0.03, 0.04])
    t = 2.1
    _, Kq, _ = body_load(term, q, qdot, t)
    h = 1e-6
    for k in range(3, 6):
        e = np.eye(6)[k] * h
        fd = -(body_load(term, q + e, qdot, t)[0] - body_load(term, q - e, qdot, t)[0]) / (2 * h)
        np.testing.assert_allclose(Kq[:, k], fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())


@pytest.mark.parametrize("axes", [2.0 * np.eye(3), [[1.0, 0.3, 0.0], [0.0, 1.0, 0.0],
                                                    [0.0, 0.0, 1.0]]],
                         ids=["scaled", "sheared"])
def test_body_axes_must_be_a_rotation(axes):
    """The body's axes turn its drag areas (R A diag(CdA) A^T R^T): a scaled or sheared
    matrix would silently scale or mix them, and is refused. Fails when only the shape
    of the matrix is checked, or its orthogonality to a loose tolerance."""
    with pytest.raises(ValueError):
        body_hydrodynamics(drag_coefficients=[1.0] * 3, drag_areas=[1.0] * 3, axes=axes)


# ------------------------------------------------------------------ free points

def test_point_drag_in_an_airy_wave_at_its_displaced_position():
    """A free point at (4, 2, -15) displaced by u = (1, -0.5, -2), moving at v, in the
    Airy wave at t = 5.2 s: R = -1/2 rho CdA |w| w, w = u_w(x + u, t) - v with the Airy
    velocity worked here. Fails on the water taken at t = 0 or at x - u."""
    sea = wave_sea()
    drag = PointDrag(0, 0.8, rho=RHO, sea=sea)
    drag.position = np.array([4.0, 2.0, -15.0])
    u, v, t = np.array([1.0, -0.5, -2.0]), np.array([0.2, 0.1, -0.3]), 5.2
    R = np.zeros(3)
    drag.add_to(u, v, t, R)
    w = airy(drag.position + u, t)[0] - v
    np.testing.assert_allclose(R, -0.5 * RHO * 0.8 * np.linalg.norm(w) * w, rtol=1e-12)


def test_point_drag_slope_at_low_and_zero_speed():
    """The free point's drag is quadratic: at rest in still water no force and no slope
    (finite: no 0/0); at 0.5 m/s (below 1) the slope d/dv is k (|w| I + w w^T / |w|), the
    central differences of the residual. Fails on a NaN slope at rest or a slope left out
    at low speed."""
    drag = PointDrag(0, 0.8, rho=RHO)
    R, C = np.zeros(3), np.zeros((3, 3))
    drag.add_to(np.zeros(3), np.zeros(3), 0.0, R, C=C)
    assert np.all(R == 0.0) and np.all(C == 0.0)
    v = np.array([0.3, 0.0, -0.4])  # |v| = 0.5
    C = np.zeros((3, 3))
    drag.add_to(np.zeros(3), v, 0.0, np.zeros(3), C=C)
    h = 1e-7
    fd = np.zeros((3, 3))
    for j in range(3):
        Rp, Rm, e = np.zeros(3), np.zeros(3), np.eye(3)[j] * h
        drag.add_to(np.zeros(3), v + e, 0.0, Rp)
        drag.add_to(np.zeros(3), v - e, 0.0, Rm)
        fd[:, j] = (Rp - Rm) / (2 * h)
    np.testing.assert_allclose(C, fd, rtol=1e-6, atol=1e-9)
    w = -v
    np.testing.assert_allclose(C, 0.5 * RHO * 0.8 * (0.5 * np.eye(3) + np.outer(w, w) / 0.5),
                               rtol=1e-12, atol=1e-12)


def test_point_drag_default_water_is_the_lines_water():
    """Without a density, a point's drag is in the same seawater as a free point's
    (PointMass) and a line type's default: 1/2 rho CdA |v| v with that rho. Fails on a
    default density of its own."""
    rho = PointMass().rho
    assert rho == LineType(EA=1.0, mass=1.0, diameter=0.1).rho_water
    v = np.array([0.6, 0.0, 0.8])
    R = np.zeros(3)
    PointDrag(0, 0.5).add_to(np.zeros(3), v, 0.0, R)
    np.testing.assert_allclose(R, 0.5 * rho * 0.5 * 1.0 * v, rtol=1e-12)
