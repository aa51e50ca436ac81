"""A body turned through large angles: skmoor (rotations='exact') and MoorDyn v2 side by
side on tests/decks/bodies/turning_body.dat.

The coupled point 9 runs on a circle of radius 2 m about the body's centre: from +y to -x
in 1.5 s (a quarter turn about z), then from -x up to +z in 1.5 s (a quarter turn about
y), each with a cosine ramp (no jerk at the ends), then holds for 2 s; the body (inertia
5, 3, 1 kg m2) turns through 121 deg. The seventh line drags
the body point (0, 1, 0) after it; the six taut lines at the centre hold the centre in
place and take no moment. What is compared: the body's orientation (the angle of
R_skmoor^T R_MoorDyn) and the dragged body point over the run. MoorDyn's body state is
read as its own attitude (R = Rx Ry Rz, :func:`skmoor.coupling.network.moordyn_rotation`), checked
against its position of point 8.

Measured: the dragged point within 1.2 cm, the orientation within 4.9 deg (at the end,
about the drag line's own axis, which only the weight's 9.6 N m/rad holds: the two codes'
different starts, skmoor's static equilibrium and MoorDyn's deck positions, 1.3 deg apart,
ring on there); the small-rotation model: 14 cm and 8.5 deg. skmoor at dt = 5 ms,
MoorDyn RK4 at 0.1 ms coupled every 1 ms; about 50 s under load (slow).

The dragging line is light (0.1 kg/m). With a 1 kg/m rope: exact 9.1 cm and 5.7 deg,
small 16 cm and 9.3 deg (the exact body carries its line ends' lumped masses; when they
were a constant matrix P0^T M P0 the exact model was no closer than the small one, 8.6
against 7.8 deg).
"""
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest

moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) is the "
                              "lumped-mass dynamic peer")

import skmoor  # noqa: E402
from skmoor.bodies.body import rotation_matrix
from skmoor.coupling.network import moordyn_rotation

DECK = Path(__file__).parents[1] / "decks" / "bodies" / "turning_body.dat"
CENTER = np.array([0.0, 0.0, -20.0])
RADIUS, T_YAW, T_PITCH, T_END = 2.0, 1.5, 1.5, 5.0
ARM = np.array([0.0, 1.0, 0.0])  # the dragged body point, body frame (m)


def ramp(t, duration, total):
    """Cosine ramp 0 -> total over [0, duration], and its rate."""
    s = np.clip(t / duration, 0.0, 1.0)
    inside = 0.0 < t < duration
    return (total * (1 - np.cos(np.pi * s)) / 2,
            total * np.pi / (2 * duration) * np.sin(np.pi * s) if inside else 0.0)


def hook(t):
    """Position (m) and velocity (m/s) of the coupled point 9."""
    if t < T_YAW:
        b, db = ramp(t, T_YAW, np.pi / 2)
        return (CENTER + RADIUS * np.array([-np.sin(b), np.cos(b), 0.0]),
                RADIUS * db * np.array([-np.cos(b), -np.sin(b), 0.0]))
    a, da = ramp(t - T_YAW, T_PITCH, np.pi / 2)
    return (CENTER + RADIUS * np.array([-np.cos(a), 0.0, np.sin(a)]),
            RADIUS * da * np.array([np.sin(a), 0.0, np.cos(a)]))


def run_moordyn(path, coupling=1e-3, sample=0.05):
    md = moordyn.Create(str(path))
    try:
        x, v = hook(0.0)
        assert moordyn.Init(md, list(x), list(v)) == 0
        body, point = moordyn.GetBody(md, 1), moordyn.GetPoint(md, 8)
        every = round(sample / coupling)
        t, R, P = [], [], []
        for k in range(round(T_END / coupling)):
            x, v = hook(k * coupling)
            moordyn.Step(md, list(x), list(v), k * coupling, coupling)
            if (k + 1) % every == 0:
                r, _ = moordyn.GetBodyState(body)
                t.append((k + 1) * coupling)
                R.append(moordyn_rotation(np.array(r[3:6])))
                P.append(moordyn.GetPointPos(point))
    finally:
        moordyn.Close(md)
    return np.array(t), np.array(R), np.array(P)


def run_skmoor(path, rotations, dt=5e-3):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the taut lines start stretched: by design
        model = skmoor.build(str(path), motion=lambda t: hook(t)[0] - hook(0.0)[0])
    model.system.bodies[0].rotations = rotations  # a submerged body: no hull needed
    results = skmoor.simulate(model, duration=T_END, dt=dt, output_interval=0.05,
                              progress=False, start="equilibrium")
    assert results.meta["stopped"] is None, results.meta["stopped"]
    q = results.bodies[:, 0]
    R = np.array([rotation_matrix(angles) for angles in q[:, 3:]])
    return results.t, R, CENTER + q[:, :3] + R @ ARM


def angle_between(Ra, Rb):
    """Rotation angle (rad) of Ra^T Rb for stacks of matrices."""
    trace = np.einsum("nij,nij->n", Ra, Rb)
    return np.arccos(np.clip((trace - 1) / 2, -1.0, 1.0))


@pytest.mark.slow
def test_turning_body_against_moordyn(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    deck = shutil.copy(DECK, tmp_path / DECK.name)
    t_md, R_md, P_md = run_moordyn(deck)
    # MoorDyn's attitude read as R = Rx Ry Rz puts the body point where MoorDyn has it
    assert np.allclose(CENTER + R_md @ ARM, P_md, atol=0.01)
    assert angle_between(R_md[:1], R_md[-1:])[0] > np.radians(100)  # it did turn (120 deg)
    for rotations in ("exact", "small"):
        t, R, P = run_skmoor(deck, rotations)
        R_at = R[np.searchsorted(t, t_md - 1e-9)]
        P_at = P[np.searchsorted(t, t_md - 1e-9)]
        worst = angle_between(R_at, R_md).max()
        print(rotations, "orientation", np.degrees(worst), "deg; point",
              np.abs(P_at - P_md).max(), "m")
        if rotations == "exact":
            assert worst < np.radians(6.0)
            assert np.abs(P_at - P_md).max() < 0.03
        else:
            assert np.abs(P_at - P_md).max() > 0.08
