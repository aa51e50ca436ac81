"""Point masses and volumes fixed on a free body (MoorDyn's Point.cpp on a Body: its mass,
added mass and buoyancy summed into the body's 6x6 mass matrix and load), checked
against the parallel-axis theorem by hand, a free orbit with no forces, a pendulum by
hand and MoorDyn v2 run side by side.

    test                           compared                          measured
    point_and_rod_mass_matrices    orbitalBody's two bodies (one     to 1e-12 (by hand)
                                   with 2 x 20 kg points, one with
                                   a 40 kg rod, both 10 m off the
                                   reference point): 6x6 matrices
    orbit_without_forces           orbitalBody (body 1 given 1 kg    radius 3e-6 m, rate
                                   m2), MoorDyn's tests/bodies.cpp   4e-7 rad/s at dt
                                   start: spin 0.2 rad/s about the   0.025 s over 2.5 s,
                                   common centre of mass             2nd order (ratio 4.0)
    orbit_as_given                 orbitalBody as given (body 1: no  the same errors, 2nd
                                   inertia about its line of masses: order; the held spin
                                   that spin held, with a warning)   stays 0 exactly
    off_line_point_refused         body 1 with a point off its line  the error names the
                                   of masses (a moment about it)     axis
    orbit_as_given_10s (slow)      MoorDyn's own test: 10 s, radius  radius 7e-6 m, rate
                                   within 1e-6 R, rate 1e-6 omega    1e-7 rad/s (dt 12.5 ms)
    buoyant_point_pendulum         3 point masses, one buoyant, in   COM fall 2e-6 m of
                                   water: the COM falls at F/m, the  3.9, angle 1e-5 rad
                                   body swings about it (by hand)    (by hand), points
                                   and MoorDyn side by side          2 mm (MoorDyn)
    rod_mounted_on_a_body          mount_rod's combined inertia      1e-12 (by hand)
"""
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import moordyn_decks as md  # noqa: E402

import skmoor  # noqa: E402
from skmoor.solvers.dynamics import integrate

try:
    MIRROR, NO_MIRROR = md.Mirror(md.mirror_path()), ""
except md.MirrorMissing as err:
    MIRROR, NO_MIRROR = None, str(err)
needs_mirror = pytest.mark.skipif(MIRROR is None, reason=NO_MIRROR)

ORBITAL = "tests/Mooring/body_tests/orbitalBody.txt"
BODY_1 = "1       free        0      10      20      0.0       0      0       0     0|-10|0    0"
GIVEN_INERTIA = "1       free        0      10      20      0.0       0      0       0     0|-10|0    1"


def orbital_deck(folder, inertia=True):
    """orbitalBody.txt in folder; ``inertia``: body 1 given an own inertia of 1 kg m2
    (its two point masses alone give it none about their line)."""
    text = MIRROR.read(ORBITAL).decode()
    assert BODY_1 in text
    if inertia:
        text = text.replace(BODY_1, GIVEN_INERTIA)
    path = Path(folder) / "orbitalBody.txt"
    path.write_text(text)
    return path


@needs_mirror
def test_point_and_rod_mass_matrices(tmp_path):
    """About the reference point (0, 10, 20), 10 m in y from the masses: body 1's two
    20 kg points at (0, -10, -+2) m from it plus its own 1 kg m2, body 2's rod (10 kg/m,
    4 m, diameter 1 m) from (0, -10, -2) to (0, -10, 2). By hand: m = 40 kg; the
    coupling m skew(c), c = (0, -10, 0): M[3, 2] = -400, M[5, 0] = 400 (a z push 10 m
    off in -y turns about -x); Ixx = sum m (y^2 + z^2), the rod's across inertia
    m (L^2/12 + r^2/4) plus m 10^2, Izz = m 10^2 plus its axial m r^2 / 2."""
    model = skmoor.build(orbital_deck(tmp_path))
    points = model.network.bodies[0].rigid.mass_matrix()
    rod = model.network.bodies[1].rigid.mass_matrix()
    across, along = 40 * (16 / 12 + 0.25 / 4), 40 * 0.25 / 2
    for M, inertia in ((points, [40 * 104 + 1, 40 * 4 + 1, 40 * 100 + 1]),
                       (rod, [across + 4000, across, along + 4000])):
        expected = np.zeros((6, 6))
        expected[:3, :3] = 40 * np.eye(3)
        expected[3, 2] = expected[2, 3] = -400.0
        expected[5, 0] = expected[0, 5] = 400.0
        expected[3:, 3:] += np.diag(inertia)
        assert np.allclose(M, expected, rtol=0, atol=1e-12 * 4000)
    assert not model.network.bodies[0].terms  # nothing but its mass: no load of its own


def as_given(folder):
    """orbitalBody as given, built with exact rotations: body 1's spin about its line of
    masses (the z axis through (0, 0, 20)) held, with a warning naming the axis."""
    with pytest.warns(UserWarning, match=r"line 10: BODIES 1: no inertia about the axis "
                      r"\[0\.0, 0\.0, 1\.0\].*held by a torsional spring"):
        return skmoor.build(orbital_deck(folder, inertia=False), rotations="exact")


@needs_mirror
def test_off_line_point_refused(tmp_path):
    """Body 1 of orbitalBody with a third (massless) point off its line of masses: a
    line there could turn it about that line, which has no inertia: refused, naming the
    axis (the spin is held only where nothing can drive it)."""
    path = orbital_deck(tmp_path, inertia=False)
    text = path.read_text()
    second = "2         Body1      0.0       -10        2        20.0     0          0      0"
    assert second in text
    path.write_text(text.replace(second, second + "\n3         Body1      1.0       -10        "
                                 "0        0.0      0          0      0"))
    with pytest.raises(ValueError, match=r"line 10: BODIES 1: .*singular.*"
                       r"axis \[0\.0, 0\.0, 1\.0\].*a point off it"):
        skmoor.build(path, rotations="exact")


def orbit_errors(model, dt, duration=2.5, omega=0.2, radius=10.0):
    """Largest errors of the two bodies' reference points over the run: |r - r0| - 10 m
    (m) and the angle of r - r0 about x over t minus omega (rad/s), r0 = (0, 0, 20) the
    bodies' common centre of mass, started as MoorDyn's tests/bodies.cpp starts them:
    w = (omega, 0, 0), the reference point at radius * omega along z; and the largest
    motion out of that orbit (body 1's x, rotations about y and z: m, rad)."""
    system = model.system
    v0 = np.tile([0.0, 0.0, radius * omega, omega, 0.0, 0.0], 2)
    r_err = w_err = off = 0.0
    for state in integrate(system, np.zeros(12), v0, dt, duration, tol=1e-10):
        if state.t == 0:
            continue
        for k in range(2):
            d = np.array([0.0, 10.0, 0.0]) + state.x[6 * k: 6 * k + 3]
            r_err = max(r_err, abs(np.linalg.norm(d) - radius))
            w_err = max(w_err, abs(np.arctan2(d[2], d[1]) / state.t - omega))
        off = max(off, np.abs(state.x[[0, 4, 5]]).max())
    return r_err, w_err, off


@needs_mirror
def test_orbit_as_given(tmp_path):
    """orbitalBody as given: body 1 has no inertia about its line of masses and nothing
    turns it about it; its spin held, both bodies orbit as with the 1 kg m2 of
    test_orbit_without_forces (the same errors and order), body 1 not leaving its
    orbit's plane nor spinning (fails on a spin left free: a singular step, NaN)."""
    model = as_given(tmp_path)
    coarse, fine = orbit_errors(model, 0.05), orbit_errors(model, 0.025)
    assert fine[0] < 3e-6 and fine[1] < 5e-7 and fine[2] < 1e-12
    assert coarse[0] / fine[0] == pytest.approx(4.0, rel=0.05)
    assert coarse[1] / fine[1] == pytest.approx(4.0, rel=0.05)


@pytest.mark.slow
@needs_mirror
def test_orbit_as_given_10s(tmp_path):
    """MoorDyn's own check of orbitalBody (tests/bodies.cpp): over 10 s both bodies
    orbit within 1e-6 of the 10 m radius and of the 0.2 rad/s rate."""
    radius, rate, off = orbit_errors(as_given(tmp_path), 0.0125, duration=10.0)
    assert radius < 1e-6 * 10.0 and rate < 1e-6 * 0.2 and off < 1e-12


@needs_mirror
def test_orbit_without_forces(tmp_path):
    """g = 0, no lines: each body spins at 0.2 rad/s about its centre of mass 10 m from
    its reference point, which so orbits at 10 m and 0.2 rad/s (MoorDyn's test allows
    1e-6 of each, at its 0.25 s coupling and 1 ms inner step). Exact rotations carry the
    centripetal terms; Newmark's error in the orbit falls as dt^2."""
    model = skmoor.build(orbital_deck(tmp_path), rotations="exact")
    coarse, fine = orbit_errors(model, 0.05), orbit_errors(model, 0.025)
    assert fine[0] < 3e-6 and fine[1] < 5e-7
    assert coarse[0] / fine[0] == pytest.approx(4.0, rel=0.05)  # second order
    assert coarse[1] / fine[1] == pytest.approx(4.0, rel=0.05)


PENDULUM = """--------------------- MoorDyn Input File ------------------------------------
Three point masses on a free body of no mass of its own, the top one buoyant
---------------------------- BODIES -----------------------------------------
ID  Attachment  X0  Y0  Z0   r0  p0  y0  Mass  CG*  I*  Volume  CdA*  Ca
(#) (-)         (m) (m) (m)  (deg) (deg) (deg) (kg) (m) (kg-m^2) (m^3) (m^2) (-)
1   free        0   10  -20  0   0   0   0     0    0   0       0     0
----------------------- POINTS ----------------------------------------------
Node  Type   X    Y    Z    M     V     CdA  CA
(-)   (-)    (m)  (m)  (m)  (kg)  (m^3) (m^2) (-)
1     Body1  0.0  -10  -2   20.0  0     0    0
2     Body1  0.0  -10  2    20.0  0.04  0    0
3     Body1  1.0  -10  0    5.0   0     0    0
-------------------------- SOLVER OPTIONS------------------------------------
9.81     g
1025     rho
1e-3     dtM
70       WtrDpth
0        TmaxIC
--------------------------- need this line ----------------------------------
"""
MASSES = np.array([20.0, 20.0, 5.0])  # kg, the points' (PENDULUM)
OFFSETS = np.array([[0.0, -10, -2], [0.0, -10, 2], [1.0, -10, 0]])  # m, from (0, 10, -20)
RHO, G, VOLUME, DURATION = 1025.0, 9.81, 0.04, 3.0


def pendulum_by_hand(t):
    """(z of the centre of mass (m), angle (rad) about y of the line from it to the
    buoyant point 2 from the vertical) at times t: the centre falls at (B - m g) / m,
    B = rho g V; about it (its weights act there) B alone turns the body, a pendulum
    I theta'' = -B d sin(theta), I the y inertia about the centre, d the arm."""
    m, B = MASSES.sum(), RHO * G * VOLUME
    com = MASSES @ OFFSETS / m
    arms = OFFSETS - com
    inertia = MASSES @ (arms[:, 0] ** 2 + arms[:, 2] ** 2)  # all in one y plane
    d, theta0 = np.linalg.norm(arms[1]), np.arctan2(-arms[1, 0], arms[1, 2])
    swing = solve_ivp(lambda _, y: [y[1], -B * d / inertia * np.sin(y[0])], (0, t[-1]),
                      [theta0, 0.0], t_eval=t, rtol=1e-11, atol=1e-13)
    return -20.0 + 0.5 * (B - m * G) / m * t ** 2, swing.y[0]


def com_and_angle(points):
    """(nt,) z of the centre of mass and (nt,) angle from the vertical (about y) of the
    line from it to point 2, from the (nt, 3, 3) point positions (m)."""
    com = np.einsum("p,tpi->ti", MASSES, points) / MASSES.sum()
    arm = points[:, 1] - com
    return com[:, 2], np.arctan2(-arm[:, 0], arm[:, 2])


def moordyn_pendulum(path, dt=0.01):
    """MoorDyn's positions (nt, 3 points, 3) at t = dt, 2 dt, ... DURATION."""
    moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) "
                                  "is the peer")
    system = moordyn.Create(str(path))
    try:
        assert moordyn.Init(system, [], []) == 0
        points = [moordyn.GetPoint(system, k + 1) for k in range(3)]
        out = []
        for k in range(round(DURATION / dt)):
            moordyn.Step(system, [], [], k * dt, dt)
            out.append([moordyn.GetPointPos(p) for p in points])
    finally:
        moordyn.Close(system)
    return np.array(out)


def test_buoyant_point_pendulum(tmp_path, monkeypatch):
    """A body of no mass of its own, its 45 kg in three points, 0.04 m3 of buoyancy on
    the top one, released in water: weight and buoyancy at their points (their moments
    about the reference point) and the points' mass matrix drive it. By hand: the fall
    of the centre of mass at (B - m g) / m and the swing about it; and MoorDyn v2 side by
    side (its points every 10 ms over the 3 s, about one swing)."""
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "pendulum.txt"
    path.write_text(PENDULUM)
    model = skmoor.build(path, rotations="exact")
    results = skmoor.simulate(model, duration=DURATION, dt=0.01, output_interval=0.01,
                              start="given", progress=False)
    assert results.meta["stopped"] is None, results.meta["stopped"]
    k = [results.point_names.index(f"point{i}") for i in (1, 2, 3)]
    ours = results.point_reference[k] + results.point_displacement[:, k]
    z, theta = com_and_angle(ours)
    z_hand, theta_hand = pendulum_by_hand(results.t)
    assert abs(theta_hand[0]) > 0.05 and np.ptp(theta_hand) > 0.1  # it swings through
    theirs = moordyn_pendulum(path)
    assert np.abs(z - z_hand).max() < 1e-5
    assert np.abs(theta - theta_hand).max() < 5e-5
    assert np.abs(ours[1:] - theirs).max() < 4e-3  # of a 3.9 m fall


def test_rod_mounted_on_a_body():
    """mount_rod: a 10 kg body (inertia diag(1, 2, 3) kg m2 at the origin) and a 10 kg
    rod (5 kg/m, 2 m, diameter 0.2 m) from (1, 0, 0) to (3, 0, 0): 20 kg at (1, 0, 0); by
    hand about it, the body diag(1, 2, 3) + 10 (1 m)^2 across x, the rod its along
    m r^2 / 2 = 0.05 and across m (L^2/12 + r^2/4) + 10 (1 m)^2; rotations kept."""
    body = skmoor.RigidBody(10.0, np.zeros(3), np.diag([1.0, 2.0, 3.0]), rotations="exact")
    rod_type = skmoor.bodies.rod_loads.RodType("r", 0.2, 5.0, 0.0, 0.0, 0.0, 0.0)
    both = skmoor.bodies.rod_loads.mount_rod(body, rod_type, [1.0, 0, 0], [3.0, 0, 0],
                                 reference_point=np.zeros(3))
    across = 10 * (4 / 12 + 0.01 / 4)
    assert both.mass == 20.0 and np.allclose(both.center_of_mass, [1.0, 0, 0])
    assert np.allclose(both.inertia, np.diag([1 + 0.05, 2 + 10 + across + 10,
                                              3 + 10 + across + 10]), rtol=0, atol=1e-12)
    assert both.rotations == "exact"
