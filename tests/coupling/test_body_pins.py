"""A pin joining two dynamic bodies (skmoor.coupling.joints.BodyPin, MoorDyn's Body<N>Pinned rod
on a free body) against analytic numbers.

    test                              compared with                          measured
    pendulum_on_a_free_body           T = 4 K(sin(a/2)) / w, w^2 = K / I_eff,  8e-5
                                      I_eff = I_A - m^2 (L/2)^2 / (M + m)
                                      (the carrier recoils; a fixed pin: +26 %)
                                      the pair's centre of mass in x, at rest  3e-5 m
    body_pin_tangent                  Taylor test of the 12-DOF tangent      slope 2

The deck is tests/decks/rods/pendulum_on_a_free_body.dat (it says what it holds);
MoorDyn's BodiesAndRods deck side by side is in tests/coupling/test_rods_moordyn.py.
"""
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.special import ellipk

import skmoor
from skmoor.bodies.rod_loads import RodType
from skmoor.coupling.joints import BodyPin
from skmoor.coupling.network import Body, MooringLine, Network, Point
from skmoor.coupling.rods import rod
from skmoor.fem.terms import check_tangent

DECKS = Path(__file__).parents[1] / "decks" / "rods"
G, RHO = 9.80665, 1025.0


def track(results, name):
    i = results.point_names.index(name)
    return results.point_reference[i] + results.point_displacement[:, i]


def test_pendulum_on_a_free_body():
    """A buoyant rod pinned by its end A to a free body at the body's centre of mass,
    2 deg off the vertical; the body weighs the rod's net lift. Horizontal momentum makes
    the body recoil, so the swing is faster than on a fixed pin: w^2 = K / I_eff with
    K = (rho A L - m) g L/2 and I_eff = I_A - m^2 (L/2)^2 / (M + m). Fails if the pin
    does not act on both bodies equally and oppositely (the fixed-pin period is 26 %
    longer) or if it lets the rod's end leave the body."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # no static equilibrium: released as given
        model = skmoor.build(DECKS / "pendulum_on_a_free_body.dat")
        r = skmoor.simulate(model, duration=5.5, dt=0.0125, output_interval=0.0125,
                            start="given", progress=False)
    L, d, mu = 4.0, 0.5, 100.0
    m, lift = mu * L, RHO * np.pi * d ** 2 / 4 * L
    M = lift - m  # the body's mass: the pair is neutrally buoyant
    I_A = m * (L ** 2 / 3 + (d / 2) ** 2 / 4)
    I_eff = I_A - m ** 2 * (L / 2) ** 2 / (M + m)
    w = np.sqrt((lift - m) * G * L / 2 / I_eff)
    A, B = track(r, "rod1.A"), track(r, "rod1.B")
    x = B[:, 0] - A[:, 0]
    k = np.flatnonzero(np.sign(x[:-1]) * np.sign(x[1:]) < 0)
    upright = r.t[k] - x[k] * (r.t[k + 1] - r.t[k]) / (x[k + 1] - x[k])
    assert len(upright) >= 4
    assert 2 * np.mean(np.diff(upright)) == pytest.approx(
        4 * ellipk(np.sin(np.radians(1.0)) ** 2) / w, rel=1e-3)
    body = r.bodies[:, 0, :3] + [0.0, 0.0, -10.0]
    assert np.max(np.linalg.norm(A - body, axis=1)) < 1e-5  # the pin holds (1e-6 L/2)
    centre = (M * body[:, 0] + m * (A[:, 0] + B[:, 0]) / 2) / (M + m)
    assert np.ptp(centre) < 1e-4  # momentum: the pair's centre stays (0.14 m swing)
    assert np.ptp(body[:, 0]) > 0.1 * 0.14 * m / (M + m)  # and the body did recoil


def test_body_pin_tangent():
    """The pin's 12 x 12 tangent (d/dq with the carrier's rotation and velocity terms,
    d/dqdot) against its residual: the Taylor remainder falls as h^2."""
    pin = BodyPin([2.0, 0.5, -1.0], mass=100.0, carrier_mass=1000.0, length=5.0)
    rng = np.random.default_rng(1)
    check = check_tangent(None, pin, u=0.1 * rng.standard_normal(12),
                          v=rng.standard_normal(12))
    assert check.ok, str(check)


def _pinned_network(pin_point):
    carrier = Body("raft", "dynamic", [0.0, 0.0, -10.0],
                   rigid=skmoor.RigidBody(500.0, [0.0, 0.0, -10.0], 100.0 * np.eye(3)))
    body, ends = rod("mast", RodType("mast", 0.5, 100.0), [0.0, 0.0, -10.0],
                     [0.0, 0.0, -6.0], pin=pin_point)
    points = [Point("deck", "body", [0.0, 0.0, 0.0], body="raft"),
              Point("side", "body", [1.0, 0.0, 0.0], body="raft"),
              Point("a", "fixed", [50.0, 0.0, -1.0]), Point("b", "fixed", [50.0, 0.0, -2.0]),
              *ends]
    line = MooringLine("dummy", skmoor.LineType(EA=1e6, mass=1.0, diameter=0.01), "a", "b",
                       length=1.0, n_elements=1)
    return Network(points, [line], [carrier, body], depth=30.0)


def test_bad_body_pins_are_refused():
    """A pin on a point away from the pinned body's reference point, or on the body
    itself, is refused by name."""
    _pinned_network("deck")  # the pin where the mast's end A is
    with pytest.raises(ValueError, match="body mast pin: point 'side' is 1 m from"):
        _pinned_network("side")
    with pytest.raises(ValueError, match="body mast pin: 'mast.B' is on the body itself"):
        _pinned_network("mast.B")


def test_model_add_takes_a_pins_bodies_by_name():
    """Model.add resolves a BodyPin's bodies given by name to their indices among the
    dynamic bodies (the network's order: west 0, east 1, either way round); an unknown
    name is refused with the names there are."""
    from test_network import network_two_bodies

    model = skmoor.from_network(network_two_bodies())
    for names, indices in ((("west", "east"), (0, 1)), (("east", "west"), (1, 0))):
        pin = BodyPin([1.0, 0.0, -1.5], mass=1e3, carrier_mass=4e4, length=2.0, bodies=names)
        assert model.add(pin).bodies == indices
        assert pin in model.system.terms
    with pytest.raises(ValueError, match=r"BodyPin.bodies: no dynamic body 'north' \(have "
                                         r"\['west', 'east'\]\)"):
        model.add(BodyPin([0.0, 0.0, 0.0], mass=1.0, carrier_mass=1.0, length=1.0,
                          bodies=("west", "north")))
