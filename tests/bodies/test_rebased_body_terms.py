"""Exact bodies with terms of their own (drag, rods, pins, spin springs, added mass,
potential flow) re-based past 60 deg pitch (System.rebase): the terms read the pose from
one place (skmoor.bodies.body_motion), checked against hand-computed drag loads, a spin-down, a
compound pendulum and a spin with added mass in closed form, the frequency-domain
response of the box in waves, and the invariance of the loads and of the motion under a
re-base.

    test                                   compared with                       measured
    drag_moment_of_a_spinning_body         1/2 rho CdA |w| w by hand, E^T M    1e-12
    drag_areas_turn_with_an_exact_body     1/2 rho CdA v^2 on the body axis     1e-12
    spin_down_through_the_lock             w0 / (1 + k w0 t / I), R(t) about    omega 4e-6, attitude
                                           the fixed axis, x(t) in closed form  1.5e-4 rad (dt 0.02 s)
    pinned_rod_swings_through_the_lock     4 K(sin^2 45 deg) / w0 (90 deg)      5e-5
    rebase_keeps_the_loads_of_the_terms    the same state before / after       1e-9
    excitation_is_taken_where_...          the wave's phase k dx                1e-9
    added_mass_acts_on_the_angular_...     R(t) = Rot(n, w t) (I + a) alpha = 0   3.8e-4 rad, 2nd order
    rebase_leaves_the_motion_of_a_body_... re-based at 45 or 60 deg: the same   2e-5 rad, 2nd order
    a_tilted_rod_rises_along_its_...       a = M^-1 F, M with the present axis   1e-14 m
    exact_box_in_regular_waves             frequency-domain response            0.25 %
"""
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from scipy.special import ellipk
from test_gimbal_lock import CABLE, tethered_body
from test_large_rotations import lone_body_system

import skmoor
from skmoor.bodies.bem import Hydrodynamics
from skmoor.bodies.body import RigidBody, rotation_matrix
from skmoor.bodies.large_rotations import (
    added_mass_load,
    added_mass_tangents,
    rate_matrix,
    zyx_angles,
)
from skmoor.bodies.radiation import PotentialFlow
from skmoor.bodies.rod_loads import RodLoad, RodType, SpinLoad
from skmoor.coupling.system import Ends, System
from skmoor.fem.terms import check_tangent
from skmoor.lines.line import Line, LineSet
from skmoor.sea.hydro import body_hydrodynamics
from skmoor.solvers.dynamics import integrate

RHO, G = 1025.0, 9.80665
DECKS = Path(__file__).parents[1] / "decks" / "rods"
BOX_BEM = Path(__file__).parents[2] / "meshes" / "box_hull_bem.npz"


def drag(translational, rotational, **kw):
    """body_hydrodynamics with 1/2 rho CdA = ``translational`` (kg/m) and ``rotational``
    (kg m2), three values each."""
    areas = 2 * np.r_[translational, rotational] / RHO
    return body_hydrodynamics(drag_coefficients=np.ones(6), drag_areas=areas, rho=RHO, **kw)


def body_load(system, term, q, qdot, t=0.0):
    """The load conjugate to q (6,) a body term puts on body 0 at time t (minus its
    residual)."""
    R = np.zeros(6)
    term.add_to(np.asarray(q, float), np.asarray(qdot, float), t, R)
    return -R


def test_drag_moment_of_a_spinning_body():
    """Pitched by beta, turning at a rate w of rx: omega = w (cos beta, 0, -sin beta)
    (E's first column), so the drag moment -k |omega| omega with k = 1/2 rho CdA_r enters
    as E^T M = k w^2 (-1, 0, sin beta). Taking the angle rates for omega (the bug this
    fixes) gives k w^2 (-1, 0, 0)."""
    body = RigidBody(2.0, [0.0, 0.0, 0.0], np.eye(3), rotations="exact", g=0.0)
    system = lone_body_system(body)
    term = drag([0.0] * 3, [0.7] * 3)
    system.add_term(term)
    beta, w, k = 0.5, 1.3, 0.7
    Q = body_load(system, term, [0.0, 0.0, 0.0, 0.2, beta, 0.0], [0.0, 0.0, 0.0, w, 0.0, 0.0])
    np.testing.assert_allclose(Q, [0.0, 0.0, 0.0, -k * w**2, 0.0, k * w**2 * np.sin(beta)],
                               atol=1e-12)
    body.rotations = "small"  # the linear model keeps omega = qdot[3:]
    Q = body_load(system, term, [0.0, 0.0, 0.0, 0.2, beta, 0.0], [0.0, 0.0, 0.0, w, 0.0, 0.0])
    np.testing.assert_allclose(Q, [0.0, 0.0, 0.0, -k * w**2, 0.0, 0.0], atol=1e-12)


def test_drag_areas_turn_with_an_exact_body():
    """Drag area on the body's x axis only: yawed 90 deg, the body drags along global y
    (1/2 rho CdA v^2) and not along x; spun about its (turned) x axis it brakes, about
    its y axis not (MoorDyn's R diag(CdA) R^T)."""
    body = RigidBody(2.0, [0.0, 0.0, 0.0], np.eye(3), rotations="exact", g=0.0)
    system = lone_body_system(body)
    term = drag([3.0, 0.0, 0.0], [2.0, 0.0, 0.0])
    system.add_term(term)
    yawed = [0.0, 0.0, 0.0, 0.0, 0.0, np.pi / 2]
    v = 1.5
    np.testing.assert_allclose(body_load(system, term, yawed, [0.0, v, 0, 0, 0, 0]),
                               [0.0, -3.0 * v**2, 0, 0, 0, 0], atol=1e-12)
    np.testing.assert_allclose(body_load(system, term, yawed, [v, 0, 0, 0, 0, 0]), 0.0,
                               atol=1e-12)
    # omega = E qdot[3:]; at yaw 90 deg a unit rx rate turns the body about global y,
    # which is its own x axis
    np.testing.assert_allclose(body_load(system, term, yawed, [0, 0, 0, v, 0, 0]),
                               [0, 0, 0, -2.0 * v**2, 0, 0], atol=1e-12)
    np.testing.assert_allclose(body_load(system, term, yawed, [0, 0, 0, 0, v, 0]), 0.0,
                               atol=1e-12)
    # a body built yawed 90 deg (a deck body's start attitude, ``axes``): the same at q = 0,
    # on the small model too
    for rotations in ("exact", "small"):
        body.rotations = rotations
        built = drag([3.0, 0.0, 0.0], [2.0, 0.0, 0.0], axes=rotation_matrix([0, 0, np.pi / 2]))
        system.add_term(built)
        np.testing.assert_allclose(body_load(system, built, np.zeros(6), [0.0, v, 0, 0, 0, 0]),
                                   [0.0, -3.0 * v**2, 0, 0, 0, 0], atol=1e-12)
    with pytest.raises(ValueError, match="body_hydrodynamics axes"):
        drag([1.0] * 3, [1.0] * 3, axes=2 * np.eye(3))


def spin_down(dt, duration=6.0):
    """A weightless body of isotropic inertia I, translational and rotational drag
    k_t, k_r (1/2 rho CdA), launched at v0 along d and spinning at w0 about
    n = (1, 1, 1)/sqrt(3): its x axis passes the vertical (the gimbal lock) after
    120 deg. (t, R, omega, position, pitch from the global frame) of each state."""
    body = RigidBody(3.0, [0.0, 0.0, 0.0], 2.0 * np.eye(3), rotations="exact", g=0.0)
    system = lone_body_system(body)
    system.add_term(drag([1.5] * 3, [0.5] * 3))
    v = np.zeros(system.n)
    v[-6:-3] = 1.0 * SPIN_D
    v[-3:] = 2.0 * SPIN_N
    out = []
    for state in integrate(system, np.zeros(system.n), v, dt, duration, tol=1e-10):
        q, qdot = system.q(state.x), system.q(state.v)
        out.append((state.t, system.body_rotation(state.x), rate_matrix(q[3:])[0] @ qdot[3:],
                    q[:3].copy(), system.body_pose(state.x)[0, 4]))
    return [np.array(column) for column in zip(*out)]


SPIN_N = np.ones(3) / np.sqrt(3)
SPIN_D = np.array([1.0, -2.0, 0.5]) / np.linalg.norm([1.0, -2.0, 0.5])


def test_spin_down_through_the_lock():
    """I omega' = -k_r |omega| omega keeps the axis and gives omega = w0 / (1 + k_r w0 t
    / I), the turn (I / k_r) ln(1 + k_r w0 t / I) about n (318 deg in 6 s); the same for
    the translation, x = (m / k_t) ln(1 + k_t v0 t / m) d. Second order in dt. A drag on
    the angle rates, a frame-blind term or no re-base (it stops at the lock) fail."""
    errors = []
    for dt in (0.04, 0.02):
        t, R, omega, position, pitch = spin_down(dt)
        w = 2.0 / (1 + 0.5 * 2.0 * t / 2.0)
        turn = 2.0 / 0.5 * np.log(1 + 0.5 * 2.0 * t / 2.0)
        travel = 3.0 / 1.5 * np.log(1 + 1.5 * 1.0 * t / 3.0)
        expected = Rotation.from_rotvec(np.outer(turn, SPIN_N)).as_matrix()
        trace = np.einsum("nij,nij->n", expected, R)
        errors.append((np.abs(omega - np.outer(w, SPIN_N)).max() / 2.0,
                       np.arccos(np.clip((trace - 1) / 2, -1, 1)).max(),
                       np.abs(position - np.outer(travel, SPIN_D)).max()))
        assert np.abs(pitch).max() > np.radians(89)  # through the lock
    (w1, a1, x1), (w2, a2, x2) = errors
    assert w2 < 1e-5 and a2 < 3e-4 and x2 < 3e-5
    for coarse, fine in ((w1, w2), (a1, a2), (x1, x2)):
        assert 3.5 < coarse / fine < 4.5


def test_pinned_rod_swings_through_the_lock(tmp_path):
    """MoorDyn's pinned rod (tests/decks/rods/pinned_pendulum.dat) released from the
    horizontal: a compound pendulum of 90 deg amplitude, T = 4 K(sin^2 45 deg) / w0,
    w0^2 = (m - rho V) g L/2 / I_pin, through the vertical (the body's x axis vertical:
    the lock) twice a period. The rod's buoyancy, its spin spring and the pin are terms
    of the body: a rod load that read the re-based angles as global ones would buoy the
    rod where it started."""
    text = (DECKS / "pinned_pendulum.dat").read_text()
    text = text.replace("0.87155742747  0  -14.96194698", "10  0  -5")
    (tmp_path / "horizontal.dat").write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = skmoor.build(tmp_path / "horizontal.dat", rotations="exact")
        results = skmoor.simulate(model, duration=5.2, dt=0.025, output_interval=0.025,
                                  start="given", progress=False)
    assert results.meta["stopped"] is None
    i = results.point_names.index("rod1.B")
    tip = results.point_reference[i] + results.point_displacement[:, i]
    L, d, mu = 10.0, 0.2, 250.0
    mass, buoyant = mu * L, RHO * np.pi * d**2 / 4 * L
    w0 = np.sqrt((mass - buoyant) * G * L / 2 / (mass * (L**2 / 3 + (d / 2) ** 2 / 4)))
    period = 4 * ellipk(0.5) / w0
    x = tip[:, 0]
    k = np.flatnonzero(np.sign(x[:-1]) * np.sign(x[1:]) < 0)
    crossings = results.t[k] - x[k] * (results.t[k + 1] - results.t[k]) / (x[k + 1] - x[k])
    assert len(crossings) == 2
    np.testing.assert_allclose(crossings, [period / 4, 3 * period / 4], rtol=2e-4)
    assert np.abs(np.linalg.norm(tip - [0.0, 0.0, -5.0], axis=1) - L).max() < 1e-4
    assert np.abs(results.bodies[:, 0, 4]).max() > np.radians(88)


def deep_body(depth=20.0):
    """An exact body at (0, 0, -depth) on two lines, one from (20, 0, -depth) to its point
    (5, 0, 0), one from (0, 0, 9 - depth) to its point (0, 0, 1), two elements each."""
    down = np.array([0.0, 0.0, depth])
    lines = [Line.from_polyline(np.array(points) - down, CABLE) for points in
             ([[20.0, 0.0, 0.0], [12.0, 0.0, 0.0], [5.0, 0.0, 0.0]],
              [[0.0, 0.0, 9.0], [0.0, 0.0, 5.0], [0.0, 0.0, 1.0]])]
    body = RigidBody(10.0, [0.0, 0.0, -depth], np.diag([3.0, 2.0, 1.0]), rotations="exact",
                     g=1.0)
    return System(LineSet(lines), ends=Ends([("fixed",), ("fixed",)], [("body", 0)] * 2),
                  bodies=[body])


def rod_body_system():
    """deep_body() with a rod on it (buoyancy, drag and end caps in a current), body drag
    and a spin spring: the terms of an exact body."""
    system = deep_body()
    sea = skmoor.Sea(depth=100.0, current=skmoor.Current(0.6, heading_deg=30.0))
    rod = RodType("r", 0.3, 20.0, Cd=1.2, Ca=0.0, CdEnd=0.8, CaEnd=0.0)
    a, b = np.array([-2.0, 0.5, 0.0]), np.array([3.0, -0.5, 1.0])
    ref = system.bodies[0].reference_point
    terms = [RodLoad(rod, a, b, reference_point=ref, n_segments=3, sea=sea),
             drag([30.0, 20.0, 10.0], [5.0, 6.0, 7.0], sea=sea, reference_point=ref),
             SpinLoad(a, b, 50.0)]
    for term in terms:
        system.add_term(term)
    return system, terms


def rebased(system):
    """The body of ``system`` pitched to 75 deg, moving, and its angles re-based: (x, v)
    before, (x1, v1) after; the frames are re-based then."""
    x = np.zeros(system.n)
    x[system.nf:] = [0.1, -0.2, 0.05, 0.4, np.radians(75), -0.3]
    x[: system.nf] = 0.01 * np.sin(np.arange(system.nf))
    v = np.zeros(system.n)
    v[system.nf:] = [0.2, 0.1, -0.1, 0.3, -0.5, 0.2]
    return x, v, system.rebase(x, v)


def test_rebase_keeps_the_loads_of_the_terms():
    """The same state counted from the re-based frame gives every term the same force and
    moment (E^T M: the generalized moment through the new E), and their tangents are the
    derivatives of their loads there (Taylor test). A term reading q[3:] as global angles
    (the rod back at its start, the drag areas turned back) breaks the first check."""
    system, terms = rod_body_system()
    system.reset_frames()
    x, v, turned = rebased(system)
    assert turned is not None  # all its terms are frame-aware
    x1, v1 = turned
    E0 = rate_matrix(x[-3:])[0]
    block = slice(system.nf, None)
    for term in terms:
        before_frames = system.frames
        system.frames = [None]
        Q0 = body_load(system, term, x[block], v[block])
        system.frames = before_frames
        Q1 = body_load(system, term, x1[block], v1[block])
        np.testing.assert_allclose(Q1[:3], Q0[:3], atol=1e-9 * np.abs(Q0).max())
        np.testing.assert_allclose(Q1[3:], np.linalg.solve(E0.T, Q0[3:]),
                                   atol=1e-9 * np.abs(Q0).max())
        check = check_tangent(system, term, x1[block] + 0.01, v1[block])
        assert check.ok, (type(term).__name__, str(check))


def test_body_load_sees_the_global_pose_of_a_rebased_body():
    """A body_load gets the angles from the global frame (and their rates) also after a
    re-base: R of what it sees is the attitude, E of it times the rates the angular
    velocity (the frame's angles would give the identity at the re-base)."""
    seen = []
    system = tethered_body()
    system.body_load = lambda t, q, qdot: seen.append((q.copy(), qdot.copy())) or np.zeros(6)
    x, _, (x1, v1) = rebased(system)
    system.residual(x1, v1, tangent=False)
    q, qdot = seen[-1]
    np.testing.assert_allclose(rotation_matrix(q[3:]), system.body_rotation(x1), atol=1e-12)
    np.testing.assert_allclose(q[3:], x[-3:], atol=1e-12)
    np.testing.assert_allclose(rate_matrix(q[3:])[0] @ qdot[3:], v1[-3:], atol=1e-12)
    np.testing.assert_allclose(zyx_angles(system.body_rotation(x1)), x[-3:], atol=1e-12)


@pytest.fixture(scope="module")
def box():
    return Hydrodynamics.load(BOX_BEM)


def test_potential_flow_memory_is_in_the_global_frame(box):
    """PotentialFlow on an exact body convolves [v, omega] (global): the memory and the
    excitation of a re-based state are the same force and moment (a kernel on the angle
    rates would jump at the re-base), and a small body turning at the same omega as its
    rates gets the same memory."""
    system = deep_body(0.5)
    sea = skmoor.Sea(depth=100.0, waves=[skmoor.AiryWave(0.5, 8.0, 100.0)])
    term = PotentialFlow(box, sea)
    system.add_term(term)
    block = slice(system.nf, None)
    x, v, (x1, v1) = rebased(system)
    frames = system.frames
    system.frames = [None]
    for t in np.arange(0.0, 3.0, 0.1):  # a history of turning
        term.commit(t, x[block], v[block] * np.cos(0.7 * t))
    Q0 = body_load(system, term, x[block], v[block], t=3.05)
    system.frames = frames
    Q1 = body_load(system, term, x1[block], v1[block], t=3.05)
    E0 = rate_matrix(x[-3:])[0]
    scale = np.abs(Q0).max()
    np.testing.assert_allclose(Q1[:3], Q0[:3], atol=1e-9 * scale)
    np.testing.assert_allclose(Q1[3:], np.linalg.solve(E0.T, Q0[3:]), atol=1e-9 * scale)
    check = check_tangent(system, term, x1[block] + 0.01, v1[block], t=3.05)
    assert check.ok, str(check)
    # a small body whose rates are that omega: the same memory (its excitation at the
    # reference point, the exact body's where it is: compared without waves)
    still = PotentialFlow(box)
    small = deep_body(0.5)
    small.bodies[0].rotations = "small"
    small.add_term(still)
    exact = deep_body(0.5)
    twin = PotentialFlow(box)
    exact.add_term(twin)
    omega = rate_matrix(x[-3:])[0] @ v[-3:]
    for t in np.arange(0.0, 3.0, 0.1):
        twin.commit(t, x[block], v[block] * np.cos(0.7 * t))
        still.commit(t, x[block], np.r_[v[block][:3], omega] * np.cos(0.7 * t))
    Q_small = body_load(small, still, x[block], np.r_[v[block][:3], omega], t=3.05)
    Q_exact = body_load(exact, twin, x[block], v[block], t=3.05)
    np.testing.assert_allclose(Q_exact[:3], Q_small[:3], atol=1e-12 * scale)
    np.testing.assert_allclose(np.linalg.solve(E0.T, Q_exact[3:]), Q_small[3:],
                               atol=1e-9 * scale)


def test_excitation_is_taken_where_the_exact_body_is(box):
    """A regular head wave reaches a body moved dx down-wave k dx / omega later: the exact
    body's excitation there is the small body's at t - k dx / omega (the small body's
    stays at the reference point, linear theory)."""
    sea = skmoor.Sea(depth=100.0, waves=[skmoor.AiryWave(1.0, 8.0, 100.0)])
    wave = sea.waves[0]
    shift = 7.0
    q = np.array([shift, 0.0, 0.0, 0.0, 0.0, 0.0])
    loads = {}
    for rotations in ("exact", "small"):
        system = deep_body(0.5)
        system.bodies[0].rotations = rotations
        term = PotentialFlow(box, sea)
        system.add_term(term)
        loads[rotations] = [body_load(system, term, q, np.zeros(6), t) for t in (3.0, 5.5)]
    lag = float(wave.k[0]) * shift / float(wave.omega[0])
    for t, exact in zip((3.0, 5.5), loads["exact"]):
        np.testing.assert_allclose(exact, term.excitation(t - lag), rtol=1e-9,
                                   atol=1e-9 * np.abs(exact).max())
    assert np.abs(loads["exact"][0] - loads["small"][0]).max() > 0.1 * np.abs(loads["small"][0]).max()


def test_added_mass_acts_on_the_angular_acceleration():
    """A weightless body of isotropic inertia I with an isotropic added mass a (its own
    and a term's), spun about n = (1, 1, 1)/sqrt(3): (I + a) alpha = 0, so it turns at a
    constant rate, R(t) = Rot(n, w t), its x axis through the vertical; second order in
    dt (3.8e-4 rad at 0.02 s, as without the added mass). An added mass on the angle
    accelerations (as M alone holds it) turns it 1.24 rad off."""
    errors = []
    for dt in (0.04, 0.02):
        body = RigidBody(2.0, [0.0, 0.0, 0.0], 1.5 * np.eye(3), rotations="exact", g=0.0,
                         added_mass=np.diag([1.0, 1.0, 1.0, 0.5, 0.5, 0.5]))
        system = lone_body_system(body)
        term = skmoor.BodyLoad(lambda q, qdot, t: np.zeros(6),
                               added_mass=np.diag([0.0, 0.0, 0.0, 0.7, 0.7, 0.7]))
        term.frame_aware = True  # it reads nothing
        system.add_term(term)
        v = np.zeros(system.n)
        v[-6:-3], v[-3:] = 0.3 * SPIN_D, 2.0 * SPIN_N
        worst, pitch = 0.0, 0.0
        for state in integrate(system, np.zeros(system.n), v, dt, 2.5, tol=1e-10):
            expected = Rotation.from_rotvec(2.0 * state.t * SPIN_N).as_matrix()
            R = system.body_rotation(state.x)
            worst = max(worst, np.arccos(np.clip((np.trace(expected.T @ R) - 1) / 2, -1, 1)))
            pitch = max(pitch, abs(system.body_pose(state.x)[0, 4]))
            np.testing.assert_allclose(system.q(state.x)[:3], 0.3 * SPIN_D * state.t,
                                       atol=1e-9)
        assert pitch > np.radians(88)  # sampled every dt: through the lock
        errors.append(worst)
    assert errors[1] < 5e-4
    assert 3.5 < errors[0] / errors[1] < 4.5


def test_a_tilted_rod_rises_along_its_added_mass():
    """A buoyant free rod (Ca 1, CaEnd 1, no drag) built vertical and released at rest
    tilted 45 deg: buoyancy, weight and added mass all act at or symmetric about its
    centre, so it rises without turning at a = M^-1 (rho V - m) g e_z, M = m I + Ca rho V
    (I - t t^T) + 2 CaEnd rho (2/3) pi r^3 t t^T with t its axis now (Newmark: exact for
    a constant acceleration). The rod's added mass as built (vertical), which a small
    body keeps, turns it over and misses by metres."""
    from skmoor.bodies.rod_loads import rod_body

    rod = RodType("r", 0.5, 100.0, Cd=0.0, Ca=1.0, CdEnd=0.0, CaEnd=1.0)
    a, b = np.array([0.0, 0.0, -20.0]), np.array([0.0, 0.0, -18.0])
    body = rod_body(rod, a, b, g=G, rotations="exact")
    system = lone_body_system(body)
    system.add_term(RodLoad(rod, np.zeros(3), b - a, reference_point=a, n_segments=4,
                            rho=RHO, g=G))
    system.add_term(SpinLoad(np.zeros(3), b - a, body.mass * G * 2.0))
    tilt = np.radians(45)
    x0 = np.zeros(system.n)
    x0[-2] = tilt
    axis = np.array([np.sin(tilt), 0.0, np.cos(tilt)])
    volume, cap = rod.area * 2.0, RHO * 2 / 3 * np.pi * 0.25**3
    M = (body.mass * np.eye(3) + RHO * volume * (np.eye(3) - np.outer(axis, axis))
         + 2 * cap * np.outer(axis, axis))
    acceleration = np.linalg.solve(M, [0.0, 0.0, (RHO * volume - body.mass) * G])
    for state in integrate(system, x0, np.zeros(system.n), 0.05, 1.5):
        q = system.q(state.x)
        np.testing.assert_allclose(q[:3], 0.5 * acceleration * state.t**2, atol=1e-9)
        np.testing.assert_allclose(q[3:], [0.0, tilt, 0.0], atol=1e-9)


def test_inertia_tangents_with_added_masses_are_its_derivatives():
    """System.inertia of an exact body with a rod's turning added mass and a constant one:
    d/da, d/dv, d/dx against central differences at a random state."""
    from skmoor.bodies.rod_loads import rod_body

    rod = RodType("r", 0.5, 100.0, Ca=1.0, CaEnd=1.0)
    a, b = np.array([0.0, 0.0, -20.0]), np.array([1.0, 0.5, -18.0])
    body = rod_body(rod, a, b, g=G, rotations="exact")
    body.added_mass = np.diag([10.0, 20.0, 30.0, 5.0, 6.0, 7.0])
    system = lone_body_system(body)
    system.add_term(RodLoad(rod, np.zeros(3), b - a, reference_point=a, rho=RHO, g=G))
    rng = np.random.default_rng(0)
    state = [np.zeros(system.n) for _ in range(3)]
    for k, scale in enumerate((0.3, 0.3, 1.0)):
        state[k][-6:] = scale * rng.standard_normal(6)
    state[0][-2] += 0.7
    _, *tangents = system.inertia(*state, tangent=True, layout="dense")
    h = 1e-6
    for which, D in zip((2, 1, 0), tangents):  # d/da, d/dv, d/dx
        numeric = np.empty((6, 6))
        for k in range(6):
            plus, minus = [x.copy() for x in state], [x.copy() for x in state]
            plus[which][-6 + k] += h
            minus[which][-6 + k] -= h
            numeric[:, k] = (system.inertia(*plus)[0] - system.inertia(*minus)[0])[-6:] / (2 * h)
        np.testing.assert_allclose(D[-6:, -6:], numeric, atol=1e-6 * np.abs(numeric).max())


def test_added_mass_tangents_are_the_load_derivatives():
    """d/dqddot = T^T A T and d/dqdot (exact) of the added mass's load on [a, alpha]
    against central differences; the load is T^T A [a, alpha] with alpha from E and its
    rate (a dropped Edot term breaks the second)."""
    rng = np.random.default_rng(3)
    B = rng.standard_normal((6, 6))
    added = B @ B.T
    q, qdot, qddot = (rng.standard_normal(6) for _ in range(3))
    d_acc, d_rate, d_pose = added_mass_tangents(q, qdot, qddot, added)

    def differences(f, x, h=1e-6):
        return np.column_stack([(f(x + h * e) - f(x - h * e)) / (2 * h) for e in np.eye(6)])

    np.testing.assert_allclose(d_acc, differences(lambda a: added_mass_load(q, qdot, a, added),
                                                  qddot), atol=1e-7)
    np.testing.assert_allclose(d_rate, differences(lambda v: added_mass_load(q, v, qddot, added),
                                                   qdot), atol=1e-6)
    np.testing.assert_allclose(d_pose, differences(lambda x: added_mass_load(x, qdot, qddot, added),
                                                   q), atol=1e-6)
    h = 1e-6  # alpha = d omega / dt along the motion
    alpha = (rate_matrix(q[3:] + h * qdot[3:])[0] @ (qdot[3:] + h * qddot[3:])
             - rate_matrix(q[3:] - h * qdot[3:])[0] @ (qdot[3:] - h * qddot[3:])) / (2 * h)
    force = added @ np.r_[qddot[:3], alpha]
    E = rate_matrix(q[3:])[0]
    np.testing.assert_allclose(added_mass_load(q, qdot, qddot, added),
                               np.r_[force[:3], E.T @ force[3:]], atol=1e-7)


def test_rebase_leaves_the_motion_of_a_body_in_potential_flow(box, monkeypatch):
    """The box's hydrodynamics on a submerged, weightless body spun mostly about y (its x
    axis up to 85 deg from the horizontal): re-based at 45 or at 60 deg of pitch, the
    attitude is the same to the time step's error (second order: 2e-5 rad at dt 0.025 s).
    The memory on [v, omega] and A_inf on [a, alpha] make the motion independent of the
    angles' frame; the memory lost at the restart after a re-base, or A_inf on the angle
    accelerations, give O(dt) (7e-3 rad) and O(1) (0.13 rad) differences."""
    from skmoor.bodies.body import uniform_box_inertia
    from skmoor.coupling import frames as coupling

    def attitudes(pitch, dt):
        monkeypatch.setattr(coupling, "REBASE_PITCH", np.radians(pitch))
        body = RigidBody(1.2e5, box.reference_point, uniform_box_inertia(1.2e5, 26, 10, 5),
                         rotations="exact", g=0.0)
        system = lone_body_system(body)
        system.add_term(PotentialFlow(box))
        v = np.zeros(system.n)
        v[-3:] = [0.05, 0.6, 0.02]
        return {round(s.t / dt): system.body_rotation(s.x)
                for s in integrate(system, np.zeros(system.n), v, dt, 5.0, tol=1e-8)}

    gaps = []
    for dt in (0.05, 0.025):
        a, b = attitudes(60, dt), attitudes(45, dt)
        gaps.append(max(np.arccos(np.clip((np.trace(a[k].T @ b[k]) - 1) / 2, -1, 1))
                        for k in a))
    assert gaps[1] < 1e-4
    assert 3.0 < gaps[0] / gaps[1] < 5.5


def test_exact_box_in_regular_waves(box):
    """The paper's box with rotations='exact' in small head waves at 1.6 rad/s: surge,
    heave and pitch amplitudes within 1 % of the frequency-domain response of the same
    coefficients (the exact body's memory on [v, omega], its excitation where it is and
    its hydrostatics at the pose all reduce to the linear model at small motions)."""
    import copy

    import test_radiation

    paper = test_radiation._paper_model

    def exact_model():
        model = copy.deepcopy(paper())
        model.system.bodies[0].rotations = "exact"
        return model

    test_radiation._paper_model = exact_model
    try:
        time_domain, full, _ = test_radiation.box_in_waves(box, 1.6, periods=16)
    finally:
        test_radiation._paper_model = paper
    np.testing.assert_allclose(time_domain, full, rtol=0.01)
