"""Rods (skmoor.coupling.rods, MoorDyn v2's ROD TYPES / RODS) against analytic numbers.

The decks are in tests/decks/rods/ (each says what it holds). Newmark's period error
(omega dt)^2 / 12 is the only discretisation error of these rigid-body motions; the
tolerances sit a few times above it.

    test                          compared with                       measured
    pinned_rod_pendulum_period    compound pendulum, 5 deg amplitude  4e-5 (dt 0.02 s)
    floating_spar_archimedes      Archimedes' draft; heave period     2e-7 m; 6e-5
    rising_rods_added_mass        z(t) = z0 + a t^2 / 2, a from the   1e-13 m
                                  transverse / end-cap added mass
    rod_on_a_body_rises_...       the same, the rod on a massless body 1e-13 m
    coupled_pinned_rod_three_ways the rod Body1Pinned on a coupled    1e-13 m
                                  body, Body1 on a pinned body
    rod_settles_on_the_bed        weight / (kBot d L)                 1e-10 m
    rod_drag_conventions          1/2 rho Cd d L v^2, 1/2 rho CdEnd A v^2 per end
    rod_morison_load_in_a_wave    Morison integral of Airy kinematics  < 1e-4
"""
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.special import ellipk

import skmoor
from skmoor.bodies.rod_loads import RodLoad, RodType
from skmoor.io.deck import read_deck, write_deck

DECKS = Path(__file__).parents[1] / "decks" / "rods"
G, RHO = 9.80665, 1025.0


def build(name, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return skmoor.build(DECKS / name, **kw)


def run(model, duration, dt):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return skmoor.simulate(model, duration=duration, dt=dt, output_interval=dt,
                               start="given", progress=False)


def point_track(results, name):
    """(nt, 3) positions of network point ``name``, m."""
    i = results.point_names.index(name)
    return results.point_reference[i] + results.point_displacement[:, i]


def crossings(t, x):
    """Times where x crosses zero (either way), linearly interpolated."""
    idx = np.flatnonzero(np.sign(x[:-1]) * np.sign(x[1:]) < 0)
    return t[idx] - x[idx] * (t[idx + 1] - t[idx]) / (x[idx + 1] - x[idx])


def test_pinned_rod_pendulum_period():
    """A rod pinned at its end A swings as a compound pendulum: T = 4 K(sin(a/2)) / w0
    with w0^2 = (m - rho V) g L/2 / (m (L^2/3 + r^2/4)). Fails if the inertia about
    the pin, the buoyancy or the pin itself is wrong (a 2 % period error for a free
    end instead of a pin, 7 % without buoyancy)."""
    model = build("pinned_pendulum.dat")
    r = run(model, 7.5, 0.025)
    tip = point_track(r, "rod1.B")
    L, d, mu = 10.0, 0.2, 250.0
    mass, buoyant = mu * L, RHO * np.pi * d ** 2 / 4 * L
    inertia = mass * (L ** 2 / 3 + (d / 2) ** 2 / 4)
    w0 = np.sqrt((mass - buoyant) * G * L / 2 / inertia)
    period = 4 * ellipk(np.sin(np.radians(5) / 2) ** 2) / w0
    half = np.diff(crossings(r.t, tip[:, 0]))
    assert len(half) >= 2
    assert np.mean(2 * half) == pytest.approx(period, rel=3e-4)
    pin = point_track(r, "rod1.A")
    assert np.max(np.abs(pin - [0.0, 0.0, -5.0])) < 1e-4  # 1e-6 L/2 under the weight


def test_floating_spar_archimedes():
    """A free vertical rod released below its draft heaves about Archimedes' draft
    m L / (rho A) (its restoring force is linear: the mean of the swing is the
    equilibrium) with the period 2 pi sqrt((m L + CaEnd rho 2/3 pi r^3) / (rho g A))
    (one submerged end cap's added mass)."""
    model = build("floating_spar.dat")
    r = run(model, 10.0, 0.02)
    z = point_track(r, "rod1.A")[:, 2]
    d, mu, L = 0.5, 100.0, 10.0
    area = np.pi * d ** 2 / 4
    draft = mu * L / (RHO * area)
    assert (z.max() + z.min()) / 2 == pytest.approx(-draft, abs=1e-5)
    added = RHO * 2 / 3 * np.pi * (d / 2) ** 3
    period = 2 * np.pi * np.sqrt((mu * L + added) / (RHO * G * area))
    up = crossings(r.t, z + draft)[::2]
    assert np.mean(np.diff(up)) == pytest.approx(period, rel=3e-4)
    assert np.max(np.abs(r.bodies[:, 0, [0, 1, 3, 4, 5]])) < 1e-9  # it stays upright


def test_rising_rods_added_mass():
    """Two buoyant rods rise from rest at a = (rho V - m) g / (m + m_a): m_a = Ca rho V
    for the horizontal one, 2 CaEnd rho 2/3 pi r^3 (two submerged end caps) for the
    vertical one (until its top reaches the surface, after 1.64 s). Newmark integrates
    a constant acceleration exactly."""
    model = build("rising_rods.dat")
    r = run(model, 1.5, 0.05)
    d, mu, L = 0.5, 100.0, 2.0
    volume, mass = np.pi * d ** 2 / 4 * L, mu * L
    for name, z0, added in (("rod1.A", -10.0, RHO * volume),
                            ("rod2.B", -10.0, 2 * RHO * 2 / 3 * np.pi * (d / 2) ** 3)):
        a = (RHO * volume - mass) * G / (mass + added)
        z = point_track(r, name)[:, 2]
        assert np.max(np.abs(z - (z0 + 0.5 * a * r.t ** 2))) < 1e-9, name


def test_rod_on_a_body_rises_as_a_free_rod():
    """A rod on a free body of no mass of its own (mounted: its mass, inertia and loads
    on the body, the body's attitude turning it) rises as the free rod does."""
    r = run(build("body_rod.dat"), 1.5, 0.05)
    d, mu, L = 0.5, 100.0, 2.0
    volume, mass = np.pi * d ** 2 / 4 * L, mu * L
    a = (RHO * volume - mass) * G / (mass + RHO * volume)
    for name, start in (("rod1.A", [0.0, -1.0, -10.0]), ("rod1.B", [0.0, 1.0, -10.0])):
        track = point_track(r, name)
        assert track[0] == pytest.approx(start, abs=1e-12)
        assert np.max(np.abs(track[:, 2] - (-10 + 0.5 * a * r.t ** 2))) < 1e-9, name
        assert np.max(np.abs(track[:, :2] - start[:2])) < 1e-9


def test_coupled_pinned_rod_three_ways(tmp_path):
    """hung_rod.dat's CoupledPinned rod; the same rod Body1Pinned on a coupled body (end
    A at the body's point (0, 0, -1), the body turned 30 deg in yaw); and the same rod
    Body1 on a CoupledPinned body of no mass (the path MoorDyn's pinnedBody.txt checks in
    test_rods_moordyn.py: MoorDyn's own CoupledPinned rod does not turn at all), all
    moved 1 m in x and 0.5 m in z: the rods swing alike (drag and added mass on)."""
    text = (DECKS / "hung_rod.dat").read_text()
    rod_line = "1  hung  CoupledPinned  0  0  -5  0  0  -13  4  -"
    bodies = ("---------------------- BODIES ------\n"
              "ID  Attachment  X0  Y0  Z0  r0  p0  y0  Mass  CG*  I*  Volume  CdA*  Ca*\n"
              "(#)  (word)  (m)  (m)  (m)  (deg)  (deg)  (deg)  (kg)  (m)  (kg-m^2)  (m^3)  "
              "(m^2)  (-)\n{}\n---------------------- RODS")
    variants = {
        "on_coupled_body.dat": ("1  hung  Body1Pinned  0  0  -1  0  0  -9  4  -",
                                "1  Coupled  0  0  -4  0  0  30  0  0  0  0  0  0"),
        "on_pinned_body.dat": ("1  hung  Body1  0  0  0  0  0  -8  4  -",
                               "1  CoupledPinned  0  0  -5  0  0  0  0  0  0  0  0  0")}

    def shift(t):
        return (1 - np.cos(np.pi * min(t, 2.0) / 2.0)) / 2 * np.array([1.0, 0.0, 0.5])

    def six(t):  # a coupled or pinned body takes 6 coupled DOFs (MoorDyn's vector)
        return np.r_[shift(t), 0.0, 0.0, 0.0]

    pinned = run(build("hung_rod.dat", motion=shift), 3.0, 0.05)
    tip = point_track(pinned, "rod1.B")
    assert np.ptp(tip[:, 0]) > 0.5  # it swings
    assert np.max(np.abs(point_track(pinned, "rod1.A")[-1] - [1.0, 0.0, -4.5])) < 1e-4
    for name, (rod, body) in variants.items():
        (tmp_path / name).write_text(text.replace(rod_line, rod).replace(
            "---------------------- RODS", bodies.format(body)))
        other = run(build(tmp_path / name, motion=six), 3.0, 0.05)
        assert np.max(np.abs(point_track(other, "rod1.B") - tip)) < 1e-5, name


def test_weightless_pin_holds(tmp_path):
    """hung_rod.dat with g = 0 (nothing weighs): the pin is sized by the rod's weight
    at standard gravity, so end A still follows the coupled point 1 m away (a spring
    sized by m g alone would be zero: the rod left where it was)."""
    text = (DECKS / "hung_rod.dat").read_text()
    assert "9.80665  g" in text
    path = tmp_path / "weightless.dat"
    path.write_text(text.replace("9.80665  g", "0  g"))

    def shift(t):
        return (1 - np.cos(np.pi * min(t, 2.0) / 2.0)) / 2 * np.array([1.0, 0.0, 0.5])

    r = run(build(path, motion=shift), 3.0, 0.05)
    assert np.max(np.abs(point_track(r, "rod1.A")[-1] - [1.0, 0.0, -4.5])) < 1e-4
    assert np.ptp(point_track(r, "rod1.B")[:, 0]) > 0.5  # dragged along, in still water


def test_bad_pin_is_refused_by_name():
    spar = RodType("spar", diameter=0.5, mass=100.0)
    for pin, message in (("anchor", "'anchor' is not a coupled point or a point on a coupled"),
                         (3, "is not one of")):
        with pytest.raises(ValueError, match=f"body spar pin: .*{message}"):
            body, ends = skmoor.coupling.rods.rod("spar", spar, [0, 0, -6], [0, 0, 4], pin=pin)
            anchor = skmoor.Point("anchor", "fixed", [50.0, 0.0, -20.0])
            skmoor.Network([anchor, *ends], [], [body])


def test_rod_settles_on_the_bed():
    """MoorDyn's bed under a rod: ((-h - z) kBot - z' cBot) d ds per segment; a rod
    laid on it sinks in by its submerged weight over kBot d L (overdamped: settled in
    1 s). Fails without the contact (the rod falls through) or with it on d^2 or L/2."""
    model = build("rod_on_bed.dat")
    r = run(model, 2.0, 0.02)
    d, mu, L = 0.3, 200.0, 6.0
    net = (mu - RHO * np.pi * d ** 2 / 4) * L * G
    for end in ("rod1.A", "rod1.B"):
        assert point_track(r, end)[-1, 2] == pytest.approx(-20.0 - net / (3e6 * d * L),
                                                           abs=1e-8)


def test_rod_drag_conventions():
    """MoorDyn's rod drag: transverse 1/2 rho Cd d L |v| v over the length, axial
    1/2 rho CdEnd (pi d^2 / 4) |v| v on each submerged end cap, none above the water.
    At q = 0 the load is the buoyancy rho g V alone (the body model holds the weight
    there)."""
    rod = RodType("r", diameter=0.3, mass=50.0, Cd=1.2, CdEnd=0.8)
    L, v = 4.0, 1.5
    load = RodLoad(rod, np.zeros(3), np.array([L, 0.0, 0.0]), reference_point=[0.0, 0.0, -20.0],
                   n_segments=3, rho=RHO, g=G)
    q = np.zeros(6)
    at_rest = load.forces(q, np.zeros(6), 0.0)
    cap = np.pi * 0.3 ** 2 / 4
    assert at_rest[:3] == pytest.approx([0.0, 0.0, RHO * cap * L * G])
    across = load.forces(q, np.array([0.0, v, 0.0, 0.0, 0.0, 0.0]), 0.0) - at_rest
    assert across[:3] == pytest.approx([0.0, -0.5 * RHO * 1.2 * 0.3 * L * v ** 2, 0.0])
    along = load.forces(q, np.array([v, 0.0, 0.0, 0.0, 0.0, 0.0]), 0.0) - at_rest
    assert along[:3] == pytest.approx([-2 * 0.5 * RHO * 0.8 * cap * v ** 2, 0.0, 0.0])
    dry = RodLoad(rod, np.zeros(3), np.array([L, 0.0, 0.0]), reference_point=[0.0, 0.0, 1.0],
                  rho=RHO, g=G)
    assert dry.forces(q, np.array([0.0, v, v, 0.0, 0.0, 0.0]), 0.0) == pytest.approx(np.zeros(6))


def test_rod_morison_load_in_a_wave():
    """A vertical rod held still 10 - 20 m deep under an Airy wave: the horizontal force
    and its moment about end A are the integrals of 1/2 rho Cd d |u| u + rho (1 + Ca) A a
    along it, with u, a from linear wave theory written out here (the dispersion
    relation solved anew); the bottom cap adds CaEnd rho 2/3 pi r^3 a_z. Fails if the
    fluid inertia lacks its 1 (Froude-Krylov) or its Ca, or takes the axial part."""
    from scipy.integrate import quad
    from scipy.optimize import brentq

    depth, H, T, t = 50.0, 2.0, 9.0, 1.3
    sea = skmoor.Sea(depth, rho=RHO, g=G, waves=[skmoor.AiryWave(H, T, depth, g=G)])
    rod = RodType("r", diameter=0.4, mass=80.0, Cd=1.1, Ca=0.9, CaEnd=0.7)
    load = RodLoad(rod, np.zeros(3), np.array([0.0, 0.0, 10.0]), reference_point=[2.0, 0.0, -20.0],
                   n_segments=200, rho=RHO, g=G, sea=sea)
    still = RodLoad(rod, np.zeros(3), np.array([0.0, 0.0, 10.0]), reference_point=[2.0, 0.0, -20.0],
                    n_segments=200, rho=RHO, g=G)
    F = load.forces(np.zeros(6), np.zeros(6), t) - still.forces(np.zeros(6), np.zeros(6), t)
    w = 2 * np.pi / T
    k = brentq(lambda k: G * k * np.tanh(k * depth) - w ** 2, 1e-6, 10.0)
    phase = k * 2.0 - w * t

    def u(z):
        return H / 2 * w * np.cosh(k * (z + depth)) / np.sinh(k * depth) * np.cos(phase)

    def a(z):
        return H / 2 * w ** 2 * np.cosh(k * (z + depth)) / np.sinh(k * depth) * np.sin(phase)

    def f(z):
        return 0.5 * RHO * 1.1 * 0.4 * abs(u(z)) * u(z) + RHO * 1.9 * np.pi * 0.04 * a(z)

    assert F[0] == pytest.approx(quad(f, -20.0, -10.0)[0], rel=1e-4)
    assert F[4] == pytest.approx(quad(lambda z: (z + 20.0) * f(z), -20.0, -10.0)[0], rel=1e-4)
    a_z = -H / 2 * w ** 2 * np.sinh(k * (-20.0 + depth)) / np.sinh(k * depth) * np.cos(phase)
    cap = RHO * 0.7 * 2 / 3 * np.pi * 0.2 ** 3
    top = -H / 2 * w ** 2 * np.sinh(k * (-10.0 + depth)) / np.sinh(k * depth) * np.cos(phase)
    assert F[2] == pytest.approx(cap * (a_z + top), rel=1e-6)


def test_rod_weight_is_exact_at_any_angle():
    """The System holds a body's weight linearly about q = 0; the rod load corrects it:
    the total moment of a pinned rod's weight turned by 60 deg about y is m g L/2
    sin(60 deg), not the linear m g L/2 x 60 deg."""
    system = build("pinned_pendulum.dat").system
    L, d, mu = 10.0, 0.2, 250.0
    net = (mu - RHO * np.pi * d ** 2 / 4) * L * G  # N, weight less buoyancy
    x = np.zeros(system.n)
    for angle in (5.0, 60.0, 120.0):  # the deck's rod hangs 5 deg off the vertical (ry = 0)
        x[system.nf + 4] = -np.radians(angle - 5.0)  # ry < 0 turns it further away
        R, _, _ = system.residual(x, tangent=False)
        # residual = dV/d(ry), V = net L/2 (1 - cos(angle)), d(angle) = -d(ry)
        assert R[system.nf + 4] == pytest.approx(-net * L / 2 * np.sin(np.radians(angle)),
                                                 rel=1e-9)


@pytest.mark.parametrize("deck", ["rod_on_bed.dat", "pinned_pendulum.dat"])
def test_rod_tangents_pass_the_taylor_test(deck):
    """The rod, spin and pin loads' tangents (central differences, or exact for the
    pin) fall off at second order: a wrong one would stall Newton."""
    model = build(deck)
    state = np.array([0.1, -0.05, -0.02, 0.05, -0.1, 0.2])  # wet, on the bed, turned
    for term in model.system.body_terms:
        check = skmoor.check_tangent(model, term, u=state)
        assert check.ok, (type(term).__name__, str(check))


def test_spin_is_the_turn_about_the_axis():
    """SpinLoad's psi: a turn of 0.4 rad about the rod's own axis reads 0.4; a swing of
    1.2 rad about an axis across the rod reads 0 (its spring must not hold the swing)."""
    from scipy.spatial.transform import Rotation

    from skmoor.bodies.rod_loads import SpinLoad

    axis = np.array([1.0, 0.2, -0.3]) / np.linalg.norm([1.0, 0.2, -0.3])
    spin = SpinLoad(np.zeros(3), axis, stiffness=10.0)

    def angles(rotvec):  # skmoor's body angles: R = Rz Ry Rx
        return Rotation.from_rotvec(rotvec).as_euler("ZYX")[::-1]

    assert spin.spin(np.r_[0.0, 0.0, 0.0, angles(0.4 * axis)]) == pytest.approx(0.4)
    across = np.cross(axis, [0.0, 0.0, 1.0])
    swing = np.r_[0.0, 0.0, 0.0, angles(1.2 * across / np.linalg.norm(across))]
    assert spin.spin(swing) == pytest.approx(0.0, abs=1e-12)
    assert spin.forces(swing, np.zeros(6), 0.0) == pytest.approx(np.zeros(6), abs=1e-9)


# ------------------------------------------------------------------ deck reading

def test_deck_reads_and_writes_rods(tmp_path):
    """ROD TYPES, RODS and R<N>A / R<N>B line ends read, and written back the same."""
    deck = read_deck(DECKS / "floating_spar.dat")
    assert deck.rod_types["spar"].diameter == 0.5 and deck.rod_types["spar"].CaEnd == 1.0
    rod = deck.rods[0]
    assert (rod.kind, rod.a, rod.b, rod.n_segments) == ("free", (0.0, 0.0, -6.0),
                                                        (0.0, 0.0, 4.0), 5)
    text = (DECKS / "floating_spar.dat").read_text().replace(
        "1  dummy  1  2  1.0  1  -", "1  dummy  1  R1A  8.0  4  -")
    (tmp_path / "ends.dat").write_text(text)
    ends = read_deck(tmp_path / "ends.dat")
    assert (ends.lines[0].a, ends.lines[0].b) == (1, "R1A")
    again = read_deck(write_deck(ends, tmp_path / "again.dat"))
    assert again.rods == ends.rods and again.rod_types == ends.rod_types
    assert again.lines == ends.lines


@pytest.mark.parametrize("old, new, message", [
    ("1  spar  Free ", "1  spar2  Free ", "RodType: 'spar2' is not in ROD TYPES"),
    ("1  spar  Free ", "1  spar  Wobbly ", "Attachment: 'Wobbly' is not Fixed, Pinned"),
    ("1  spar  Free ", "1  spar  Body1 ", "names no body of the BODIES section"),
    ("0  0  4  5  -", "0  0  4  0  -", "NumSegs: 0 (a zero-length rod) needs ends A and B "
     "at the same place"),
    ("0  0  4  5  -", "0  0  4  -2  -", "NumSegs: must be >= 0"),
    ("0  0  -6  0  0  4", "0  0  4  0  0  4", "ends A and B at the same place need NumSegs = 0"),
    ("spar  0.5  100.0", "spar  -0.5  100.0", "Diam: must be positive"),
    ("1  dummy  1  2  1.0", "1  dummy  1  R2B  1.0", "AttachB: rod 2 is not in RODS"),
    ("1  dummy  1  2  1.0", "1  dummy  1  R1C  1.0", "is not a rod end R<N>A or R<N>B"),
])
def test_bad_rod_input_names_the_deck_line(tmp_path, old, new, message):
    text = (DECKS / "floating_spar.dat").read_text()
    assert old in text
    (tmp_path / "bad.dat").write_text(text.replace(old, new))
    with pytest.raises(ValueError, match=r"bad\.dat line \d+: (ROD TYPES|RODS|LINES) .*"
                       + re.escape(message)):
        read_deck(tmp_path / "bad.dat")
