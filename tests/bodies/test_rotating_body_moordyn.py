"""MoorDyn's tests/Mooring/body_tests/rotatingBody.txt (g = 0): skmoor with
rotations='exact' and MoorDyn v2 side by side while a line drags a body point over the top
(pitch -90 deg, the gimbal lock of skmoor's angles), then sideways and back.

The deck is read from the local mirror of MoorDyn's repository (skipped without it) and
changed, the same for both codes, in its line type only: its drag and added-mass
coefficients set to 0 (everything sits at z = 5 m, above the water, where MoorDyn's lines
have no hydrodynamics and skmoor's dry lines keep their added mass: with them the two
part by 0.2 m and 157 deg). Its eleventh column, the VIV lift coefficient Cl = 0.05, is
kept: both codes read it and give the dry lines no lift (skmoor.sea.viv). Its body: 10 kg, inertia 5 kg m2,
held at its centre by six taut lines; line 7 (13.76 kg/m, 1 m) from the body point 8 at
(1, 0, 0) to the coupled point 9.

The path of point 9 is MoorDyn's test's (tests/bodies.cpp "Rotating body": radius 2 m
about the body centre, +x -> +z -> +y -> +x, each quarter in 2 s, then 0.5 s held), with
a cosine ramp on each quarter in place of its constant rate and without its 5 cm jumps
at the holds. Both start from the deck's positions at rest (TmaxIC = 0; skmoor's
start='given'). What is compared: point 8's position and the body's orientation (angle
of R_skmoor^T R_MoorDyn, MoorDyn's attitude read as R = Rx Ry Rz) every 50 ms.

Measured: point 8 within 3 mm and the orientation within 0.3 deg over the 7.5 s (skmoor at
dt 5 or 10 ms; MoorDyn coupled every 1 ms); the small-rotation model 0.5 m and 110 deg.
The line end's 6.9 kg at 1 m is more inertia than the body's own 5 kg m2: with the end
masses as a constant matrix (the body's mass matrix at q = 0, as before they were
carried by the exact body) skmoor was 20 cm and 170 deg off after the first quarter.
"""
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import moordyn_decks as md  # noqa: E402

moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) is the "
                              "lumped-mass dynamic peer")

import skmoor  # noqa: E402
from skmoor.bodies.body import rotation_matrix
from skmoor.coupling.network import moordyn_rotation

try:
    MIRROR, NO_MIRROR = md.Mirror(md.mirror_path()), ""
except md.MirrorMissing as err:
    MIRROR, NO_MIRROR = None, str(err)
pytestmark = pytest.mark.skipif(MIRROR is None, reason=NO_MIRROR)

DECK = "tests/Mooring/body_tests/rotatingBody.txt"
LINE_TYPE = ("nylon      0.124      13.76    25152.0     -0.4      0.0   0.0   1.0   0.0  1.6"
             "   0.05")
NO_HYDRO = ("nylon      0.124      13.76    25152.0     -0.4      0.0   0.0   0.0   0.0  0.0"
            "   0.05")
CENTER, RADIUS = np.array([0.0, 0.0, 5.0]), 2.0
QUARTER, HOLD = 2.0, 0.5
T_END = 3 * (QUARTER + HOLD)


def deck_copy(folder):
    text = MIRROR.read(DECK).decode()
    assert LINE_TYPE in text
    text = text.replace(LINE_TYPE, NO_HYDRO)
    text = text.replace("2        writeLog", "0        writeLog")
    path = Path(folder) / "rotatingBody.txt"
    path.write_text(text)
    return path


def ramp(t, duration, total):
    """Cosine ramp 0 -> total over [0, duration] and its rate."""
    s = np.clip(t / duration, 0.0, 1.0)
    rate = total * np.pi / (2 * duration) * np.sin(np.pi * s) if 0 < t < duration else 0.0
    return total * (1 - np.cos(np.pi * s)) / 2, rate


def hook(t):
    """Position (m) and velocity (m/s) of the coupled point 9."""
    leg = min(int(t // (QUARTER + HOLD)), 2)
    a, da = ramp(t - leg * (QUARTER + HOLD), QUARTER, np.pi / 2)
    c, s = np.cos(a), np.sin(a)
    direction, rate = [([c, 0, s], [-s, 0, c]), ([0, s, c], [0, c, -s]),
                       ([s, c, 0], [c, -s, 0])][leg]
    return CENTER + RADIUS * np.array(direction), RADIUS * da * np.array(rate)


def run_moordyn(path, coupling=1e-3, sample=0.05):
    """t (s), body attitude R (nt, 3, 3) and point 8 (nt, 3) (m) every ``sample`` s."""
    system = moordyn.Create(str(path))
    try:
        x, v = hook(0.0)
        assert moordyn.Init(system, list(x), list(v)) == 0
        body, point = moordyn.GetBody(system, 1), moordyn.GetPoint(system, 8)
        every = round(sample / coupling)
        t, R, P = [], [], []
        for k in range(round(T_END / coupling)):
            x, v = hook(k * coupling)
            moordyn.Step(system, list(x), list(v), k * coupling, coupling)
            if (k + 1) % every == 0:
                t.append((k + 1) * coupling)
                R.append(moordyn_rotation(np.array(moordyn.GetBodyState(body)[0][3:6])))
                P.append(moordyn.GetPointPos(point))
    finally:
        moordyn.Close(system)
    return np.array(t), np.array(R), np.array(P)


def run_skmoor(path, rotations, dt):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the six lines start stretched: by design
        model = skmoor.build(str(path), motion=lambda t: hook(t)[0] - hook(0.0)[0],
                             rotations=rotations)
    results = skmoor.simulate(model, duration=T_END, dt=dt, output_interval=0.05,
                              progress=False, start="given")
    assert results.meta["stopped"] is None, results.meta["stopped"]
    R = np.array([rotation_matrix(angles) for angles in results.bodies[:, 0, 3:]])
    k = results.point_names.index("point8")
    return results.t, R, results.point_reference[k] + results.point_displacement[:, k]


def angle_between(Ra, Rb):
    """Rotation angle (rad) of Ra^T Rb for stacks of matrices."""
    trace = np.einsum("nij,nij->n", Ra, Rb)
    return np.arccos(np.clip((trace - 1) / 2, -1.0, 1.0))


def test_rotating_body_against_moordyn(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    path = deck_copy(tmp_path)
    t_md, R_md, P_md = run_moordyn(path)
    # MoorDyn's own checks (tests/bodies.cpp): the point where the hook held it, and
    # the end attitude a quarter turn about -x
    for when, expected in ((2.5, [0, 0, 1]), (5.0, [0, 1, 0]), (7.5, [1, 0, 0])):
        assert np.allclose(P_md[np.searchsorted(t_md, when - 1e-9)] - CENTER, expected,
                           atol=0.15)
    assert np.degrees(angle_between(R_md[-1:], rotation_matrix([-np.pi / 2, 0, 0])[None])
                      )[0] < 10
    for rotations, dt in (("exact", 0.01), ("small", 0.01)):
        t, R, P = run_skmoor(path, rotations, dt)
        at = np.searchsorted(t, t_md - 1e-9)
        worst = np.degrees(angle_between(R[at], R_md)).max()
        gap = np.linalg.norm(P[at] - P_md, axis=1).max()
        print(rotations, f"point 8 within {gap:.4f} m, attitude within {worst:.3f} deg")
        if rotations == "exact":
            assert gap < 0.01
            assert worst < 1.0
        else:  # the contrast: small rotations cannot follow
            assert gap > 0.2


BODY = ("1       free      0     0      5     0       0      0      1e1     0    5        0"
        "       0      0")
DRAG_AREAS = "0.8|0.4|0.2|0.02|0.01|0.004"  # m2 along the body axes, then m5 about them


def test_rotating_body_with_drag_against_moordyn(tmp_path, monkeypatch):
    """The same deck with a body drag of different areas along the body's axes (MoorDyn's
    R diag(CdA) R^T, on the angular velocity for the rotational part): point 8 and the
    attitude again side by side through the lock. Measured: within 0.5 mm and 0.03 deg
    (dt 10 ms), where the drag moves point 8 by 16 cm and turns the body by 9.7 deg; drag
    areas in global axes, or the angle rates taken for the angular velocity, miss by more."""
    monkeypatch.chdir(tmp_path)
    path = deck_copy(tmp_path)
    text = path.read_text()
    assert BODY in text
    path.write_text(text.replace(BODY, BODY[:-8] + DRAG_AREAS + "      0"))
    t_md, R_md, P_md = run_moordyn(path)
    t, R, P = run_skmoor(path, "exact", 0.01)
    at = np.searchsorted(t, t_md - 1e-9)
    assert np.linalg.norm(P[at] - P_md, axis=1).max() < 0.005
    assert np.degrees(angle_between(R[at], R_md)).max() < 0.3
