"""Bending lines clamped on bodies that move and turn: the end tangent is R(body) t0.

- a cantilever clamped on a coupled body turned by an angle a (statics): its tip
  deflection in the body's frame is Euler-Bernoulli's w cos(a) L^4 / 8 EI, w cos(a) the
  weight's component normal to the beam (a tangent that does not turn leaves the beam
  along x, L sin(a) off in the body's frame; one turned the wrong way bends it the other
  way); the reaction on the body (force and moment about the root) is the beam's weight
  w L and the root moment w cos(a) L^2 / 2;
- a beam clamped on a dynamic body pinned at the root (free to turn) hangs straight
  down: the body turns until the tangent R t0 is vertical (a tangent held at t0 leaves
  the body's attitude unrestrained);
- the same body, held 5 deg off the vertical and released, swings at the compound
  pendulum's period (dynamics; 5e-5 measured);
- the exact tangent of the reduced residual with a clamped end on a turning body
  (Taylor test: the remainder falls as h^2).
"""
import numpy as np
import pytest

from skmoor.bodies.body import RigidBody
from skmoor.bodies.loads import BodyLoad
from skmoor.coupling.build import build_system
from skmoor.coupling.network import Body, MooringLine, Network, Point
from skmoor.coupling.rods import coupled_reaction
from skmoor.lines.laws import Engineering
from skmoor.lines.line import LineType
from skmoor.solvers.statics import solve_static

L, EI, EA, W = 10.0, 1e8, 1e10, 100.0  # m, N m2, N, N/m: a stiff beam (deflection ~1e-4 L)
ROOT = np.array([0.0, 0.0, -5.0])


def beam_type(EI=EI, EA=EA):
    return LineType(EA=EA, mass=W / 9.81, diameter=0.1, weight=W, EI=EI,
                    law=Engineering(tension_only=False))


class Built:
    """What coupled_reaction reads of a model: the network and its System."""

    def __init__(self, network, positions):
        self.network = network
        self.system, self.lines, _, _ = build_system(network, positions)


def turned_cantilever(angle):
    """A cantilever clamped on a coupled body at ROOT (along x as given), the body turned
    by ``angle`` (rad) about y by the coupled motion; its tip a free point."""
    hub = Body("hub", "coupled", ROOT)
    points = [Point("root", "body", np.zeros(3), body="hub"),
              Point("tip", "free", ROOT + [L, 0.0, 0.0])]
    beam = MooringLine("beam", beam_type(), "root", "tip", L, 8, clamp_a=True)
    network = Network(points, [beam], [hub], depth=50.0, hydro=False,
                      motion=lambda t: np.array([0.0, 0.0, 0.0, 0.0, angle, 0.0]))
    return Built(network, {"root": ROOT, "tip": ROOT + [L, 0.0, 0.0]})


@pytest.mark.parametrize("degrees", [30.0, -50.0])
def test_cantilever_on_a_turned_body(degrees):
    a = np.radians(degrees)
    model = turned_cantilever(a)
    system, lines = model.system, model.lines
    x = solve_static(system, t=0.0).x
    u = system.full_displacement(x, 0.0)
    tip = lines.points[-1] + u[lines.nodal_dofs[-1]] - ROOT
    turn = np.array([[np.cos(a), 0.0, np.sin(a)], [0.0, 1.0, 0.0],
                     [-np.sin(a), 0.0, np.cos(a)]])  # MoorDyn's Ry(a)
    local = turn.T @ tip  # in the body's frame
    deflection = W * np.cos(a) * L ** 4 / (8 * EI)
    assert local[2] == pytest.approx(-deflection, rel=1e-3)
    assert abs(local[0] - L) < 1e-5 and abs(local[1]) < 1e-12
    force, moment = coupled_reaction(model, x, np.zeros(system.n), 0.0, "hub")
    np.testing.assert_allclose(force, [0.0, 0.0, -W * L], atol=1e-6 * W * L)
    # the root moment w cos(a) L^2 / 2, about y: the weight pulls the beam's tip down
    np.testing.assert_allclose(moment, [0.0, W * np.cos(a) * L ** 2 / 2, 0.0],
                               atol=1e-3 * W * L ** 2 / 2)


def test_cantilever_on_a_body_not_turned_keeps_its_moment():
    """The same beam on the body at rest: w L^4 / 8 EI and w L^2 / 2 (the slot adds 0)."""
    model = turned_cantilever(0.0)
    x = solve_static(model.system, t=0.0).x
    u = model.system.full_displacement(x, 0.0)
    assert u[model.lines.nodal_dofs[-1]][2] == pytest.approx(-W * L ** 4 / (8 * EI), rel=1e-4)
    _, moment = coupled_reaction(model, x, np.zeros(model.system.n), 0.0, "hub")
    assert moment[1] == pytest.approx(W * L ** 2 / 2, rel=1e-4)


def pinned_hub(tilt, EI=1e6, rotations="small"):
    """A beam (EI in N m2) clamped on a dynamic body pinned at ROOT, leaving it ``tilt`` (rad)
    below the horizontal in the y-z plane; a torsion spring holds the body's yaw."""
    k = 1e4  # N m/rad
    spin = BodyLoad(lambda q, qd, t: np.r_[0.0, 0.0, 0.0, 0.0, 0.0, -k * q[5]],
                    tangent=lambda q, qd, t: (np.diag([0.0, 0, 0, 0, 0, -k]), None))
    rigid = RigidBody(100.0, ROOT, 10.0 * np.eye(3), reference_point=ROOT, rotations=rotations)
    hub = Body("hub", "dynamic", ROOT, rigid=rigid, terms=[spin], pin="fixed")
    tip = ROOT + L * np.array([0.0, np.cos(tilt), -np.sin(tilt)])
    points = [Point("root", "body", np.zeros(3), body="hub"), Point("tip", "free", tip)]
    beam = MooringLine("beam", beam_type(EI=EI, EA=1e9), "root", "tip", L, 8, clamp_a=True)
    network = Network(points, [beam], [hub], depth=50.0, hydro=False)
    return Built(network, {"root": ROOT, "tip": tip})


@pytest.mark.parametrize("rotations", ["small", "exact"])
def test_beam_clamped_on_a_pinned_body_hangs_it_vertical(rotations):
    tilt = np.radians(80.0)
    model = pinned_hub(tilt, rotations=rotations)
    system, lines = model.system, model.lines
    x = solve_static(system).x
    q = system.q(x)
    # R t0 vertical: the body turned by -(90 deg - tilt) about x
    assert q[3] == pytest.approx(-(np.pi / 2 - tilt), abs=1e-9)
    u = system.full_displacement(x)
    tip = lines.points[-1] + u[lines.nodal_dofs[-1]]
    np.testing.assert_allclose(tip[:2], ROOT[:2], atol=1e-9)
    assert tip[2] == pytest.approx(ROOT[2] - L, abs=1e-4)  # straight: its stretch only


def test_clamped_tangent_on_a_turning_body_is_exact():
    model = pinned_hub(np.radians(45.0))
    system = model.system
    rng = np.random.default_rng(1)
    x = np.r_[1e-3 * rng.standard_normal(system.nf), 0.02 * rng.standard_normal(6)]
    dx = rng.standard_normal(system.n)
    R, K, _ = system.residual(x, layout="dense")
    remainders = [np.linalg.norm(system.residual(x + h * dx, tangent=False)[0] - R
                                 - h * K @ dx) for h in (1e-3, 1e-4)]
    assert np.log10(remainders[0] / remainders[1]) == pytest.approx(2.0, abs=0.1)


def test_body_swinging_a_clamped_beam_keeps_the_compound_pendulum_period():
    """Dynamics: the pinned body with the stiff beam hanging from it (EI 1e8: its first
    bending mode 90 times the swing's frequency), held 5 deg off the vertical by a
    spring and released, swings at the compound pendulum's period 4 K(sin(a/2)) /
    omega_0, omega_0^2 = (w L^2 / 2) / (I_body + m L^3 / 3) (a clamp that does not turn
    the tangent leaves the body to spin alone at its own small inertia)."""
    from scipy.special import ellipk

    from skmoor.solvers.dynamics import integrate

    model = pinned_hub(np.radians(80.0), EI=1e8)
    system = model.system
    hanging = solve_static(system).x
    vertical = system.q(hanging)[3]  # -10 deg: the beam straight down
    stiffness = 1e5  # N m/rad: the spring holding the body off the vertical until t = 0
    on = lambda t: t <= 0
    held = BodyLoad(lambda q, qd, t: np.r_[0.0, 0, 0, on(t) * stiffness
                                           * (vertical + np.radians(5.0) - q[3]), 0, 0],
                    tangent=lambda q, qd, t: (np.diag([0.0, 0, 0, -on(t) * stiffness, 0, 0]),
                                              None))
    held.body = 0
    system.add_term(held)
    x0 = solve_static(system, hanging, t=0.0).x
    t, swing = [0.0], [system.q(x0)[3] - vertical]
    for state in integrate(system, x0, np.zeros(system.n), 0.02, 7.0):
        t.append(state.t)
        swing.append(system.q(state.x)[3] - vertical)
    t, swing = np.array(t), np.array(swing)
    k = np.flatnonzero(np.diff(np.sign(swing)) != 0)
    crossings = t[k] - swing[k] * (t[k + 1] - t[k]) / (swing[k + 1] - swing[k])
    period = 2 * float(np.mean(np.diff(crossings)))
    omega0 = np.sqrt(W * L ** 2 / 2 / (10.0 + W / 9.81 * L ** 3 / 3))
    expected = 4 * ellipk(np.sin(abs(swing[0]) / 2) ** 2) / omega0
    assert abs(swing[0]) > np.radians(4.0) and len(crossings) >= 3
    assert period == pytest.approx(expected, rel=1e-3)


def test_bad_clamps_are_refused_by_name():
    from skmoor.coupling.system import Ends

    points = [Point("a", "fixed", ROOT), Point("mid", "free", ROOT + [L, 0.0, 0.0]),
              Point("b", "fixed", ROOT + [2 * L, 0.0, 0.0])]
    lines = [MooringLine("left", beam_type(), "a", "mid", L, 4, clamp_b=True),
             MooringLine("right", beam_type(), "mid", "b", L, 4)]
    with pytest.raises(ValueError, match="line left clamp_b: point mid is free"):
        build_system(Network(points, lines, depth=50.0, hydro=False),
                     {p.name: p.position for p in points})
    with pytest.raises(ValueError, match="only a prescribed end's tangent has a slot"):
        Ends([("fixed",)], [("body", 0)], clamped=[(0, "b", 1)])
