"""MoorDyn's tests/Mooring/BodiesAndRods.dat: its cable (LINES 4, 200 m from the anchor
on the bed at [-200, 0, -70] to the free point at [-60, 0, -30], 146 m away) is 20 m
longer than the bed and the rise (140 m + 40 m) between its ends, so its first guess
lies on the bed and bows across its chord in plan; the deck then builds. It has no
static state (MoorDyn's IC stops at 0.12 s with 0.8 m/s2 left, skmoor's statics finds
none): both codes run it from the given state (MoorDyn with TmaxIC = 0, skmoor's
start='given'), side by side (slow). The deck is read from the local mirror of
MoorDyn's repository (skipped without it).

    test                              compared                       measured
    long_slack_line_first_guess       the cable's first guess: its   to 1e-9 m (by
                                      length, ends, the bed          hand)
    deck_builds                       the deck's network             its 6 lines and
                                                                     the body's mass
    from_given_state_against_moordyn  the body's heave over 1 s      2 % (9 cm) of the
    (slow)                                                           4.6 m heave
"""
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import moordyn_decks as md  # noqa: E402

import skmoor  # noqa: E402
from skmoor.coupling.build import reference_line
from skmoor.lines.line import LineType

try:
    MIRROR, NO_MIRROR = md.Mirror(md.mirror_path()), ""
except md.MirrorMissing as err:
    MIRROR, NO_MIRROR = None, str(err)
needs_mirror = pytest.mark.skipif(MIRROR is None, reason=NO_MIRROR)

DECK = "tests/Mooring/BodiesAndRods.dat"
ANCHOR, FREE_END, LENGTH, BED = np.array([-200.0, 0, -70]), np.array([-60.0, 0, -30]), 200.0, -70.0


def test_long_slack_line_first_guess():
    """The cable (40 kg/m, 751 MN) between its ends, 12 elements, the bed at -70 m: a
    sag alone cannot take up 200 m (it lies on the bed from 140 m of plan and 40 m of
    rise at most), so it also bows across in plan: its length 200 m, its ends where
    given, nothing below the bed, part of it on the bed, off the chord's plane."""
    cable = LineType(EA=751e6, mass=40.0, diameter=0.175)
    line, catenary = reference_line("line4", cable, LENGTH, 12, ANCHOR, FREE_END, BED)
    assert catenary is None  # no planar catenary lays it
    X = line.X
    assert np.linalg.norm(np.diff(X, axis=0), axis=1).sum() == pytest.approx(LENGTH, abs=1e-9)
    assert np.allclose(X[0], ANCHOR, atol=1e-12) and np.allclose(X[-1], FREE_END, atol=1e-12)
    assert X[:, 2].min() >= BED - 1e-12 and np.sum(X[:, 2] == BED) >= 3
    assert np.abs(X[:, 1]).max() > 10.0  # bowed across, in plan


def deck_copy(folder, replace=()):
    text = MIRROR.read(DECK).decode()
    for old, new in replace:
        assert old in text, old
        text = text.replace(old, new)
    path = Path(folder) / "BodiesAndRods.dat"
    path.write_text(text)
    return path


@needs_mirror
def test_deck_builds(tmp_path):
    """The deck as given builds: its 6 lines, the body of 1e6 kg with its fixed can
    (13 m of 1 t/m) in its mass, the pinned can a body of its own."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = skmoor.build(deck_copy(tmp_path))
    network = model.network
    assert [line.name for line in network.lines] == [f"line{k}" for k in range(1, 7)]
    assert network.bodies[0].rigid.mass == pytest.approx(1e6 + 13e3, rel=1e-12)
    assert len(network.bodies) == 2


def moordyn_run(path, duration, dt=0.01):
    """MoorDyn's body position (nt, 3) every dt s."""
    moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) "
                                  "is the peer")
    system = moordyn.Create(str(path))
    try:
        assert moordyn.Init(system, [], []) == 0
        body = moordyn.GetBody(system, 1)
        bodies = []
        for k in range(round(duration / dt)):
            moordyn.Step(system, [], [], k * dt, dt)
            bodies.append(moordyn.GetBodyState(body)[0][:3])
    finally:
        moordyn.Close(system)
    return np.array(bodies)


@pytest.mark.slow
@needs_mirror
def test_from_given_state_against_moordyn(tmp_path, monkeypatch):
    """From the given state (the cans above the water: the body sinks, 4.6 m in 1 s),
    skmoor (dt 10 ms) and MoorDyn (TmaxIC 0, its lines from its own first layout) side
    by side: the body's heave (measured 2 %, 9 cm). The cable's free points 8 and 9 are
    not compared: MoorDyn's catenary fails for the cable and starts it straight (point 8
    then 0.9 m apart after 1 s), skmoor starts it on the bed, bowed across."""
    monkeypatch.chdir(tmp_path)
    path = deck_copy(tmp_path, [("100.0    TmaxIC", "0.0      TmaxIC"),
                                ("2        writeLog", "0        writeLog")])
    duration = 1.0
    theirs_body = moordyn_run(path, duration)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = skmoor.build(path)
        r = skmoor.simulate(model, duration=duration, dt=0.01, output_interval=0.01,
                            start="given", progress=False)
    assert r.meta["stopped"] is None, r.meta["stopped"]
    ours_body = r.bodies[1:, 0, :3]
    heave = np.abs(theirs_body[:, 2]).max()
    assert heave > 4.0
    assert np.abs(ours_body[:, 2] - theirs_body[:, 2]).max() < 0.03 * heave
