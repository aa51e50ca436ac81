"""MoorDyn decks with no lines (bodies, rods and points alone), read from the local
mirror of MoorDyn's repository (skipped without it), against numbers found by hand and
MoorDyn v2 run side by side. The free rod of rod_tests/AddedMass.txt and the swinging
rods of RodPinnedFloating.txt are in tests/coupling/test_rods_moordyn.py (now run as given).

    test                           compared                          measured
    pinned_rods_static_in_current  RodPinnedFloating's rods (Cd 1.2,  the angle from the
                                   20 segments) started tilted, in a  vertical of both rods
                                   1.5 m/s current: the angle from    to 1e-15 rad
                                   the moment balance by hand
    nwu_rotations                  rotations/nwu.txt's coupled body   2e-16 m (analytic),
                                   turned as MoorDyn's own            1e-16 m (MoorDyn)
                                   test_rotations.py turns it: its
                                   points vs MoorDyn and vs the
                                   intrinsic XYZ Euler angles

body_tests/orbitalBody.txt (point masses on bodies of no mass of their own) is in
tests/bodies/test_orbital_bodies.py.
"""
import json
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import moordyn_decks as md  # noqa: E402

import skmoor  # noqa: E402

try:
    MIRROR, NO_MIRROR = md.Mirror(md.mirror_path()), ""
except md.MirrorMissing as err:
    MIRROR, NO_MIRROR = None, str(err)
pytestmark = pytest.mark.skipif(MIRROR is None, reason=NO_MIRROR)


def deck(workdir, path, replace=()):
    """A copy of MoorDyn's deck ``path`` in workdir with the (old, new) replacements."""
    text = MIRROR.read(path).decode()
    for old, new in replace:
        assert old in text, old
        text = text.replace(old, new)
    out = Path(workdir) / Path(path).name
    out.write_text(text)
    return out


def positions(results, names, k=-1):
    """(len(names), 3) positions (m) of the named points at output k."""
    i = [results.point_names.index(name) for name in names]
    return results.point_reference[i] + results.point_displacement[k, i]


def pinned_rods_in_current(workdir):
    """RodPinnedFloating.txt's two rods (Cd 1.2, 20 segments) settled in a 1.5 m/s current:
    (the angle from the vertical of the moment balance by hand, rad; the model; its
    results; each rod's end A and B at the static state)."""
    path = deck(workdir, "tests/Mooring/RodPinnedFloating.txt", [
        ("0.25     10.0      0.0    0.0     0.0      0.0",
         "0.25     10.0      1.2    0.0     0.0      0.0"),
        ("1    rod       Pinned      0     0     -5    1     0     -5   1 ",
         "1    rod       Pinned      0     0     -5    0.6   0     -4.2 20"),
        ("2    rod       Pinned      0     0     -5    0     1     -5   1 ",
         "2    rod       Pinned      0     0     -5    0     0.6   -4.2 20")])
    d, mu, rho, g, U, Cd = 0.25, 10.0, 1000.0, 9.80665, 1.5, 1.2
    sea = skmoor.Sea(10.0, rho=rho, g=g, current=skmoor.sea.waves.Current(U))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = skmoor.build(path, sea=sea)
        eq = skmoor.equilibrium(model)
        r = skmoor.simulate(model, duration=0.01, dt=0.01, eq=eq, progress=False)
    net = (rho * np.pi * d ** 2 / 4 - mu) * g
    theta = brentq(lambda a: 0.5 * rho * Cd * d * (U * np.cos(a)) ** 2 - net * np.sin(a),
                   0.0, np.pi / 2)
    ends = [positions(r, [f"rod{k}.A", f"rod{k}.B"], 0) for k in (1, 2)]
    return theta, model, r, ends


def test_pinned_rods_static_in_current(tmp_path):
    """RodPinnedFloating.txt's two buoyant rods, pinned at (0, 0, -5), given Cd 1.2 on 20
    segments and started tilted 37 deg from the vertical (one toward x, one toward y):
    in a uniform 1.5 m/s current along x both settle in the x-z plane at the angle theta
    from the vertical where the moments about the pin balance, the drag of the normal
    flow U cos(theta) against the net buoyancy, both uniform along the rod (arm L/2):
    1/2 rho Cd d (U cos theta)^2 = (rho pi d^2 / 4 - mu) g sin(theta). The axial drag
    acts through the pin and the rods carry no line."""
    theta, model, r, ends = pinned_rods_in_current(tmp_path)
    assert model.system.nf == 0 and r.tension.shape[1] == 0  # no line DOFs, no elements
    assert np.degrees(theta) == pytest.approx(35.6, abs=0.05)
    for k, (A, B) in enumerate(ends, start=1):
        axis = B - A  # the rods are 1 m long
        assert np.linalg.norm(A - [0.0, 0.0, -5.0]) < 1e-4  # on its pin (a stiff spring)
        assert abs(axis[1]) < 1e-9  # turned into the current's plane
        assert np.arctan2(axis[0], axis[2]) == pytest.approx(theta, abs=1e-9), k


def moordyn_nwu(path, angles, dt):
    """MoorDyn's points on the coupled body of nwu.txt after each turn in ``angles``
    ((n, 3) Euler increments, rad, each over one step of dt s): (n, 3 points, 3)."""
    moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) "
                                  "is the peer")
    system = moordyn.Create(str(path))
    try:
        assert moordyn.Init(system, [0.0] * 6, [0.0] * 6) == 0
        points = [moordyn.GetPoint(system, k + 1) for k in range(3)]
        pose, out = np.zeros(6), []
        for k, turn in enumerate(angles):
            moordyn.Step(system, list(pose), [0.0, 0.0, 0.0, *(turn / dt)], k * dt, dt)
            pose[3:] += turn
            out.append([moordyn.GetPointPos(p) for p in points])
    finally:
        moordyn.Close(system)
    return np.array(out)


def test_nwu_rotations(tmp_path):
    """rotations/nwu.txt: a coupled body of no mass with points 1 m along x, y and z, and
    no lines (nothing free: no unknowns at all), turned by MoorDyn's own
    test_rotations.py sequence of roll, pitch and yaw (5 deg each, back, all three, back,
    twice all three): the points where MoorDyn puts them and where the intrinsic XYZ
    Euler angles (MoorDyn's roll, pitch, yaw convention) of the summed angles put them."""
    path = deck(tmp_path, "tests/Mooring/rotations/nwu.txt")
    a, dt = np.radians(5.0), 0.1
    turns = np.array([[a, 0, 0], [-a, 0, 0], [0, a, 0], [0, -a, 0], [0, 0, a], [0, 0, -a],
                      [a, a, a], [-a, -a, -a], [a, a, a], [a, a, a]])
    moordyn_points = moordyn_nwu(path, turns, dt)
    pose = np.cumsum(turns, axis=0)
    times = dt * np.arange(len(turns) + 1)
    angles = np.vstack([np.zeros(3), pose])

    def motion(t):  # each turn at constant rate over its step, as MoorDyn moves it
        return np.r_[0.0, 0.0, 0.0, [np.interp(t, times, column) for column in angles.T]]

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = skmoor.build(path, motion=motion)
        r = skmoor.simulate(model, duration=times[-1], dt=dt, output_interval=dt,
                            start="given", progress=False, out=tmp_path / "run")
    assert model.system.n == 0
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["line_names"] == [] and summary["max_tension"] == 0.0
    names = ["point1", "point2", "point3"]
    skmoor_points = np.array([positions(r, names, k) for k in range(1, len(r.t))])
    assert len(skmoor_points) == len(turns)
    expected = np.array([Rotation.from_euler("XYZ", p).apply(np.eye(3)) for p in pose])
    assert np.max(np.abs(skmoor_points - expected)) < 1e-12
    assert np.max(np.abs(skmoor_points - moordyn_points)) < 1e-12
    assert skmoor_points[0, 1, 2] > 0  # roll: the port side (+y) up
    assert skmoor_points[2, 0, 2] < 0  # pitch: the bow (+x) down
    assert skmoor_points[4, 0, 1] > 0  # yaw: the bow to port
