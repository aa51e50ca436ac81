"""Driven (prescribed) line ends in dynamics: the inertia they share with their lines.

Independent numbers, from the equivalence principle: a line whose two ends accelerate
together at a constant a, in no gravity and no water, moves rigidly in the static shape it
takes under a gravity of -a (a line hanging between its ends under a weight m |a| per
metre, solved by statics) -- every node accelerates at a, and the forces the line exerts
on its two drivers add up to -m_total a (Newton's second law for the whole line). Dropping
the consistent mass the ends share with their neighbours (M_fp a_p) makes the nodes next
to the ends lag; dropping an end node's own inertia from its reaction (M_pp a_p + M_pf a_f)
breaks the momentum balance by that node's mass share. Lumped P1, consistent P1 and
bending (Hermite) lines; the Python step and the compiled one. Also: a taut line stroked
slowly along itself pulls its drivers with its whole mass (m_total a(t), to the small
ringing of its axial mode); a network's driven end on a surging, yawing ship moves with
the rigid body's velocity and acceleration written by hand, from a Motion's own rates.
"""
import numpy as np
import pytest

import skmoor
from skmoor.coupling.system import Ends
from skmoor.lines.catenary import solve_catenary
from skmoor.solvers.dynamics import Scheme, integrate

SPAN, LENGTH, ELEMENTS = 40.0, 50.0, 10  # m, m, -
MASS, EA, DIAMETER = 80.0, 5e7, 0.1  # kg/m, N, m
LIFT = 2.0  # m/s2: the ends' upward acceleration (the equivalent gravity, downward)


def line_type(g, EI=0.0):
    return skmoor.LineType(EA=EA, mass=MASS, diameter=DIAMETER, rho_water=0.0, g=g, EI=EI)


def lines_under(g, EI=0.0):
    """The line between (0, 0, 0) and (SPAN, 0, 0) under gravity g (m/s2), its reference
    the catenary it hangs in under LIFT."""
    kind = line_type(g, EI)
    cat = solve_catenary([0.0, 0.0, 0.0], [SPAN, 0.0, 0.0], MASS * LIFT, EA, length=LENGTH)
    return skmoor.LineSet([skmoor.Line.from_catenary(cat, kind, ELEMENTS)],
                          law="engineering")


def up(z):
    """(..., 2, 3): both ends moved z (a value per time) up."""
    z = np.asarray(z, float)
    out = np.zeros(z.shape + (2, 3))
    out[..., 2] = z[..., None]
    return out


def lifted(t):
    """Both ends' displacement: 0.5 a t^2 up (vectorized over t)."""
    return up(0.5 * LIFT * np.asarray(t, float) ** 2)


def rate(t):
    return up(LIFT * np.asarray(t, float))


def lift(t):
    return up(np.full(np.shape(t), LIFT))


MOTIONS = {"exact": skmoor.Motion(lifted, rate, lift, vectorized=True),
           "velocity only": skmoor.Motion(lifted, rate, vectorized=True),
           "plain function": lifted}


def driven_line(EI=0.0, lumped=True, motion="exact"):
    """(system in no gravity with both ends driven by ``motion``, the static state under
    the gravity LIFT it starts from)."""
    ends = Ends(a=[("prescribed", 0)], b=[("prescribed", 1)])
    hanging = skmoor.System(lines_under(LIFT, EI), fairleads="fixed", lumped_mass=lumped)
    x0 = skmoor.solve_static(hanging).x
    system = skmoor.System(lines_under(0.0, EI), ends=ends, motion=MOTIONS[motion],
                           lumped_mass=lumped)
    assert system.n == hanging.n  # the same free DOFs, numbered alike
    return system, x0


CASES = {"lumped P1": {}, "consistent P1": {"lumped": False}, "Hermite": {"EI": 2e4}}


def free_acceleration(system, a):
    """(nnodes - 2, 3) accelerations (m/s2) of the interior nodes from reduced a."""
    full = np.zeros(system.lines.ndofs)
    full[system.free] = a[system.dofs.columns]
    return full[system.lines.nodal_dofs[1:-1]]


@pytest.mark.parametrize("compiled", [True, False])
@pytest.mark.parametrize("case", list(CASES))
def test_a_line_lifted_by_both_ends_moves_rigidly_with_its_momentum_balanced(case, compiled):
    """Every interior node accelerates at a and keeps its place in the static shape under
    -a; the pulls on the drivers add up to -m_total a at every reported step."""
    system, x0 = driven_line(**CASES[case])
    total, up = MASS * LENGTH, np.array([0.0, 0.0, 1.0])
    inner = system.lines.nodal_dofs[1:-1]
    start = system.full_displacement(x0, 0.0)[inner]
    reported = 0
    for state in integrate(system, x0, np.zeros(system.n), 0.05, 1.0, compiled=compiled,
                           scheme=Scheme.generalized_alpha(0.8), tol=1e-10, report_every=5):
        assert np.allclose(free_acceleration(system, state.a), LIFT * up, atol=1e-7 * LIFT)
        moved = system.full_displacement(state.x, state.t)[inner] - start
        assert np.allclose(moved, 0.5 * LIFT * state.t**2 * up, atol=1e-8)
        if state.reactions is not None:
            on_b, on_a = state.reactions
            assert np.allclose(on_a[0] + on_b[0], -total * LIFT * up, atol=1e-6 * total)
            reported += 1
    assert reported == 5


@pytest.mark.parametrize("motion", ["velocity only", "plain function"])
def test_an_acceleration_from_differences_moves_the_line_as_the_exact_one(motion):
    """Without the Motion's acceleration (differences of its velocity, or second
    differences of a plain function's positions) the consistent line lifts as with it."""
    system, x0 = driven_line(lumped=False, motion=motion)
    final = list(integrate(system, x0, np.zeros(system.n), 0.05, 0.5))[-1]
    assert np.allclose(free_acceleration(system, final.a), [0.0, 0.0, LIFT], atol=1e-5 * LIFT)


STROKE, OMEGA, RAMP = 0.5, 1.0, 3.0  # m, rad/s, s: a slow in-line stroke (axial mode: 50 rad/s)


def stroke(t):
    """Both ends of the taut straight line moved along it by A sin(w t): (2, 3)."""
    out = np.zeros((2, 3))
    out[:, 0] = STROKE * np.sin(OMEGA * t)
    return out


def stroke_acceleration(t):
    """d2/dt2 of r(t / T) A sin(w t), the quintic ramp r written out (m/s2)."""
    tau = min(max(t / RAMP, 0.0), 1.0)
    r = tau**3 * (10 - 15 * tau + 6 * tau**2)
    dr = 30 * tau**2 * (1 - tau) ** 2 / RAMP
    ddr = 60 * tau * (1 - tau) * (1 - 2 * tau) / RAMP**2
    s, c = np.sin(OMEGA * t), np.cos(OMEGA * t)
    return STROKE * (ddr * s + 2 * dr * OMEGA * c - r * OMEGA**2 * s)


@pytest.mark.parametrize("case", list(CASES))
def test_a_slow_stroke_along_a_taut_line_pulls_its_drivers_with_its_whole_mass(case):
    """A taut straight line (no gravity, no water) stroked along itself by both ends
    (faded in from rest, ``fade_in`` with the Motion's exact velocity), 50 times slower
    than its axial mode, moves nearly as a rigid body: the pulls on the two drivers add up
    to -m_total a(t) within 2.5 % of the peak m_total A w^2 (1.2-1.5 % found: the ramp's
    jerk rings the axial mode); the end nodes' inertia left out of the reactions shows as
    16 %, the mass shared with their neighbours (M_fp a_p) left out as 4-6 %."""
    params = CASES[case]
    kind = line_type(0.0, params.get("EI", 0.0))
    points = np.linspace([0.0, 0.0, 0.0], [LENGTH, 0.0, 0.0], ELEMENTS + 1)
    lines = skmoor.LineSet([skmoor.Line.from_polyline(points, kind, tension=1e5)],
                           law="engineering")
    motion = skmoor.fade_in(skmoor.Motion(stroke, lambda t: np.array(
        [[STROKE * OMEGA * np.cos(OMEGA * t), 0, 0]] * 2)), RAMP)
    system = skmoor.System(lines, ends=Ends(a=[("prescribed", 0)], b=[("prescribed", 1)]),
                           motion=motion, lumped_mass=params.get("lumped", True))
    total, peak = MASS * LENGTH, MASS * LENGTH * STROKE * OMEGA**2
    worst = 0.0
    for state in integrate(system, np.zeros(system.n), np.zeros(system.n), 0.05, 8.0,
                           report_every=2):
        if state.reactions is not None:
            on_b, on_a = state.reactions
            worst = max(worst, abs(on_a[0, 0] + on_b[0, 0]
                                   + total * stroke_acceleration(state.t)))
    assert worst < 2.5e-2 * peak


SURGE, W, YAW_RATE = 2.0, 0.5, 0.1  # m, rad/s, rad/s
ARM = np.array([10.0, 0.0, -5.0])  # m: the fairlead on the coupled body (body frame)


def network_on_a_turning_ship(motion):
    from skmoor.coupling.network import Body, MooringLine, Network, Point

    chain = skmoor.LineType(EA=7.5e8, mass=140.0, diameter=0.09)
    points = [Point("anchor", "fixed", [-290.0, 0.0, -100.0]),
              Point("fairlead", "body", ARM, body="ship")]
    lines = [MooringLine("leg", chain, "anchor", "fairlead", 320.0, 10)]
    return Network(points, lines, [Body("ship", "coupled", np.zeros(3))], depth=100.0,
                   motion=motion)


def ship(t):
    """Surge X sin(w t) and yaw at a constant rate: the 6 coupled DOFs."""
    return np.array([SURGE * np.sin(W * t), 0, 0, 0, 0, YAW_RATE * t])


def ship_rate(t):
    return np.array([SURGE * W * np.cos(W * t), 0, 0, 0, 0, YAW_RATE])


def ship_acceleration(t):
    return np.array([-SURGE * W**2 * np.sin(W * t), 0, 0, 0, 0, 0.0])


@pytest.mark.parametrize("with_acceleration", [True, False])
def test_a_network_honours_its_motions_velocity_and_acceleration(with_acceleration):
    """A fairlead on a coupled ship that surges and yaws: the driven end's velocity and
    acceleration are the rigid body's, written by hand (the surge's plus the turning arm's
    tangential speed and centripetal acceleration), from a Motion's velocity (and
    acceleration, or differences of the velocity); a velocity given with a wrong factor
    is the one used (not a difference of the positions)."""
    from skmoor.coupling.build import build_system

    motion = skmoor.Motion(ship, ship_rate, ship_acceleration if with_acceleration else None)
    system = build_system(network_on_a_turning_ship(motion))[0]
    for t in (0.0, 1.3, 7.0):
        psi = YAW_RATE * t
        radial = np.array([np.cos(psi), np.sin(psi), 0.0]) * ARM[0]
        speed = (SURGE * W * np.cos(W * t) * np.array([1.0, 0, 0])
                 + YAW_RATE * np.array([-radial[1], radial[0], 0.0]))
        acceleration = (-SURGE * W**2 * np.sin(W * t) * np.array([1.0, 0, 0])
                        - YAW_RATE**2 * radial)
        _, rate = system.prescribed_state(t)
        assert np.allclose(rate[0], speed, atol=1e-8)
        assert np.allclose(system.prescribed_acceleration(t)[0], acceleration, atol=1e-6)
    wrong = skmoor.Motion(ship, lambda t: 2 * ship_rate(t))
    system = build_system(network_on_a_turning_ship(wrong))[0]
    doubled = 2 * np.array([SURGE * W, YAW_RATE * ARM[0], 0.0])
    assert np.allclose(system.prescribed_state(0.0)[1][0], doubled)
