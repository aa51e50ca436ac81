"""MoorDyn's sea decks in time, skmoor and MoorDyn v2 side by side.

The decks of MoorDyn's own set (read at run time from a local mirror of
FloatingArrayDesign/MoorDyn, as tests/sea/test_sea_moordyn.py; skipped without it) for each
sea option not compared in time there: WaveKin 1 (the caller's kinematics), WaveKin 2
(frequency components on a grid), Currents 2 (a current profile in time), Currents 5 (a
4D current grid) and a SeafloorFile. Both codes run the same deck files: the deck's
line(s) cut into fewer segments (and, for the default tests, WaveKin 2's water grid
thinned to every 10 m along the line, y = 0), so that a test takes a few seconds.

Start. MoorDyn's initial-condition (IC) solve has neither waves nor currents (its log:
"Water kinematics for IC gen: No Waves or Currents"; its IC state is the same to the
last bit with Currents 0 and 5), so both codes start from their still-water static
state (skmoor.io.sea_files.still_water; MoorDyn's IC run until static, threshIC 1e-7: the
decks' own settings leave it ringing by up to 3 kN) and the water comes on at t = 0.
That, and not the reading of the current, is the 11.8 % of the earlier static survey on
the two Currents 5 decks: skmoor's static state was in the deck's current at t = 0,
MoorDyn's in still water. In still water the two agree (0.1 % at the decks' 82
segments, 0.6 % at 20), and once MoorDyn's current has set in its tension is skmoor's.
WaveKin 1: the caller's kinematics (a current and an Airy wave) go to MoorDyn at its
nodes (ExternalWaveKinSet) and to skmoor as its sea.

Measure, over 5-20 s (MoorDyn's explicit start rings first), the worst over the deck's
lines, of the end-segment tension at the fairlead (end B; the fixed top, end A, of the
hanging lines): the offset |mean(skmoor - MoorDyn)| / mean(MoorDyn), mostly the two
static states' difference, and the change: the rms difference of the two codes'
tension changes from their own static states, over the rms of MoorDyn's (what the
water does to the tension). The codes discretise the line differently (P1 finite
elements, lumped masses): the tolerances are the measured differences at the test's
segments with a margin, and the slow test shows them shrink at twice the segments.
"""
import os
import re
import sys
from pathlib import Path, PurePosixPath

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import moordyn_decks as md  # noqa: E402

moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) is the peer")

import skmoor  # noqa: E402
from skmoor.io.deck import read_deck
from skmoor.io.sea_files import deck_bathymetry, deck_sea, still_water
from skmoor.sea.waves import AiryWave, Current, Sea

try:
    MIRROR = md.Mirror(md.mirror_path())
    NO_MIRROR = ""
except md.MirrorMissing as err:
    MIRROR, NO_MIRROR = None, str(err)

pytestmark = pytest.mark.skipif(MIRROR is None, reason=NO_MIRROR)

STEP = 0.05  # s, MoorDyn's coupling step and skmoor's time step
IC = dict(TmaxIC="300.0", threshIC="1e-7")  # MoorDyn's IC solve run until it is static


def thin_water_grid(path, spacing=10.0):
    """Rewrite a water_grid.txt with its x's every ``spacing`` m (same ends) and the
    single y = 0 (kind 0); z's kept."""
    lines = path.read_text().splitlines()
    x = [float(w) for w in lines[4].split()]
    lines[4] = " ".join(f"{v:g}" for v in np.arange(x[0], x[-1] + 1e-9, spacing))
    lines[5], lines[6] = "0", "0"
    path.write_text("\n".join(lines) + "\n")


def keep_lines(text, keep):
    """Deck text with only the LINES rows numbered in ``keep`` and the POINTS they join,
    both renumbered from 1 (MoorDyn wants IDs counting up)."""
    out, section, points, lines = [], None, {}, {}
    rows = text.splitlines()
    for row in rows:  # first pass: which points the kept lines join
        words = row.split()
        if row.startswith("---"):
            section = "LINES" if "LINES" in row else None
        elif section == "LINES" and words and words[0].isdigit() and int(words[0]) in keep:
            lines[int(words[0])] = len(lines) + 1
            for w in words[2:4]:
                points.setdefault(int(w), len(points) + 1)
    for row in rows:
        words = row.split()
        if row.startswith("---"):
            section = next((name for name in ("POINTS", "POINT PROPERTIES", "LINES")
                            if name in row), None)
        elif section and words and words[0].isdigit():
            number = int(words[0])
            if section == "LINES":
                if number not in lines:
                    continue
                words[0], words[2], words[3] = (str(lines[number]), str(points[int(words[2])]),
                                                str(points[int(words[3])]))
            else:
                if number not in points:
                    continue
                words[0] = str(points[number])
            row = " ".join(words)
        out.append(row)
    return "\n".join(out) + "\n"


def deck_copy(deck, root, segments=None, thin_grid=False, lines=None, **options):
    """MoorDyn's deck ``deck`` (its path in the repository) and its folder's files written
    under root, each line in ``segments`` segments (only the ``lines`` numbered, if
    given), OPTIONS values replaced ({name: text}); the working folder becomes the one
    MoorDyn's tests run in. Returns the deck's path."""
    folder = PurePosixPath(deck).parent
    for path in MIRROR.sizes():
        if PurePosixPath(path).parent == folder or "seafloor_profile" in path:
            target = root / path
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(MIRROR.read(path))
    text = (root / deck).read_text()
    for option, value in options.items():
        text, n = re.subn(rf"(?m)^\S+(\s+{option}\b)", rf"{value}\g<1>", text)
        assert n == 1, option
    if segments:  # LINES rows: ID LineType AttachA AttachB UnstrLen NumSegs Outputs
        text = re.sub(r"(?m)^(\s*\d+\s+[A-Za-z]\S*\s+\d+\s+\d+\s+\S+\s+)\d+(?=\s)",
                      rf"\g<1>{segments}", text)
    if lines:
        text = keep_lines(text, lines)
    (root / deck).write_text(text)
    if thin_grid:
        thin_water_grid(root / folder / "water_grid.txt")
    os.chdir(root / md.run_folder(deck))
    return root / deck


def coupled(deck):
    return [c for p in deck.points if p.kind == "coupled" for c in p.position]


def moordyn_run(path, duration, end="B", external=None):
    """(t, end-segment tension of every line (nt, nlines) from t = 0, IC end-B force of
    line 1 (the line's pull on its end point, as skmoor's fairlead_tension)) in MoorDyn
    every STEP s; ``external``: a Sea whose kinematics MoorDyn gets at its nodes
    (WaveKin 1), at the middle of each step (MoorDyn holds them over the step)."""
    deck = read_deck(path)
    system = moordyn.Create(str(path))
    try:
        x = coupled(deck)
        assert moordyn.Init(system, x, [0.0] * len(x)) == 0
        lines = [moordyn.GetLine(system, k + 1) for k in range(len(deck.lines))]
        node = [0 if end == "A" else moordyn.GetLineN(line) for line in lines]
        ic = np.linalg.norm(moordyn.GetLineNodeForce(lines[0], moordyn.GetLineN(lines[0])))
        if external is not None:
            moordyn.ExternalWaveKinInit(system)

        def tensions():
            return [np.linalg.norm(moordyn.GetLineNodeTen(line, n))
                    for line, n in zip(lines, node)]

        out, t = [tensions()], 0.0
        while t < duration - 1e-9:
            if external is not None:
                r = np.array(moordyn.ExternalWaveKinGetCoordinates(system))
                u, du = external.kinematics(r, t + 0.5 * STEP)
                moordyn.ExternalWaveKinSet(system, u.tolist(), du.tolist(), t)
            moordyn.Step(system, x, [0.0] * len(x), t, STEP)
            t += STEP
            out.append(tensions())
    finally:
        moordyn.Close(system)
    return STEP * np.arange(len(out)), np.array(out), ic


def skmoor_run(path, duration, end="B", sea=None):
    """(t, end-segment tension of every line (nt, nlines)) from skmoor's still-water
    equilibrium, the deck's water (or ``sea``) on from t = 0."""
    deck = read_deck(path)
    still = skmoor.build(path, sea=still_water(deck, deck_bathymetry(deck)))
    eq = skmoor.equilibrium(still)
    model = skmoor.build(path, sea=sea)
    results = skmoor.simulate(model, duration=duration, dt=STEP, output_interval=STEP,
                              progress=False, eq=eq)
    assert results.meta["stopped"] is None, results.meta["stopped"]
    cells = [np.nonzero(results.line_of_cell == k)[0] for k in range(len(deck.lines))]
    pick = [c[0] if end == "A" else c[-1] for c in cells]
    return results.t, results.tension[:, pick]


class SurfaceAtRest:
    """A wave's velocity and acceleration with the free surface left at z = 0: what a
    caller gives MoorDyn under WaveKin 1 (it sets the nodes' kinematics, not the
    surface)."""

    has_acceleration = True

    def __init__(self, wave):
        self.wave = wave

    def kinematics(self, points, t=0.0):
        return self.wave.kinematics(points, t)

    def elevation(self, xy, t=0.0):
        return np.zeros(np.asarray(xy).shape[:-1])

    def steady_parts(self):
        return []


def test_currents5_hand_values_and_still_water_start(tmp_path, monkeypatch):
    """tests/Mooring/wavekin_2/wavekin_3_curr5.txt's 4D current (Currents 5, on its own
    grid: UnifyCurrentGrid 0) at the anchor (-400, 0, -50): beyond the grid's x (-50 m)
    and z (-30 m) ends, held there; at t = 0 the file gives ux = -5 m/s at (-50, 2, -30)
    and none at (-50, -2, -30) (its line 6, which MoorDyn-C reads as a header: zero), so
    y = 0 sees their mean, -2.5 m/s; at t = 7.5 s half-way to the t = 15 s values (-3.5
    at both): -3.0 m/s; at (-5, 0, -3) (x between -10 and 0, all given): ux = -0.5 m/s
    at t = 0. The steady part (statics) is the t = 0 field. MoorDyn's IC state (no
    currents) against skmoor's still-water static state, end-B force at 20 segments:
    within 1 % (0.59 %, the lumped line's static error; 0.11 % at the deck's 82
    segments, docs/moordyn_decks.md)."""
    monkeypatch.chdir(tmp_path)
    path = deck_copy("tests/Mooring/wavekin_2/wavekin_3_curr5.txt", tmp_path, segments=20,
                     dtM="0.005", **IC)
    deck = read_deck(path)
    sea = deck_sea(deck)
    points = np.array([[-400.0, 0.0, -50.0], [-5.0, 0.0, -3.0]])
    current = sea.fields[1]
    assert np.allclose(current.kinematics(points, 0.0)[0][:, 0], [-2.5, -0.5], atol=1e-12)
    assert np.isclose(current.kinematics(points[:1], 7.5)[0][0, 0], -3.0, atol=1e-12)
    with sea.steady():
        assert np.allclose(sea.kinematics(points, 0.0)[0][:, 0], [-2.5, -0.5], atol=1e-12)
    _, _, ic = moordyn_run(path, STEP)
    still = skmoor.build(path, sea=still_water(deck))
    static = skmoor.static_results(still, skmoor.equilibrium(still)).fairlead_tension[0]
    assert abs(static - ic) < 1e-2 * ic, (static, ic)


def wavekin1_sea(deck):
    """What the caller gives both codes under WaveKin 1: a 1 m/s current along +x (MoorDyn's
    tests/wavekin.cpp) and a 3 m, 15 s Airy wave along +x, the surface left at z = 0."""
    wave = AiryWave(3.0, 15.0, deck.depth, g=deck.g)
    return Sea(deck.depth, rho=deck.rho, g=deck.g, current=Current(speed=1.0),
               fields=[SurfaceAtRest(wave)])


# name: deck, deck_copy arguments, end. Measured (offset %, change %) over 5-20 s at the
# segments given (20; the hanging lines 5) and at twice as many: WaveKin1 0.60, 6.1 / 0.14,
# 3.2; WaveKin2-Currents1 0.54, 15.9 / 0.21, 5.8; WaveKin2-Currents2 0.61, 2.8 / 0.13, 3.1;
# WaveKin2-Currents5 0.022, 12.9 / 0.021, 4.2; WaveKin3-Currents2-apart 0.61, 3.3 / 0.14,
# 2.3; WaveKin3-Currents5-apart 0.017, 17.8 / 0.016, 9.6; SeafloorFile 0.046, 16.4 / 0.016,
# 15.5 (3 segments: 0.10, 47)
DECKS = {
    "WaveKin1": ("tests/Mooring/wavekin_wave_1.txt", dict(segments=20, dtM="0.005"), "B"),
    "WaveKin2-Currents1": ("tests/Mooring/wavekin_2/wavekin_2.txt",
                           dict(segments=20, dtM="0.005", thin_grid=True), "B"),
    "WaveKin2-Currents2": ("tests/Mooring/wavekin_2/wavekin_2_curr2.txt",
                           dict(segments=20, dtM="0.005", thin_grid=True), "B"),
    "WaveKin2-Currents5": ("tests/Mooring/wavekin_2/wavekin_2_curr5.txt",
                           dict(segments=20, dtM="0.005", thin_grid=True), "B"),
    "WaveKin3-Currents2-apart": ("tests/Mooring/wavekin_2/wavekin_3_curr2.txt",
                                 dict(segments=20, dtM="0.005"), "B"),
    "WaveKin3-Currents5-apart": ("tests/Mooring/wavekin_2/wavekin_3_curr5.txt",
                                 dict(segments=20, dtM="0.005"), "B"),
    "SeafloorFile": ("tests/Mooring/3D_seafloor/hanging_lines.txt",
                     dict(segments=5, lines=(1, 10), dtM="0.0005", dtIC="1.0", TmaxIC="60.0",
                          threshIC="1e-9"), "A"),
}
# in the default suite: WaveKin 1, WaveKin 2 with Currents 5 (the static survey's 11.8 %),
# the SeafloorFile; WaveKin 2, 3 and Currents 1, 2 have fast analytic tests in
# tests/sea/test_sea_files.py
SLOW = {"WaveKin2-Currents1", "WaveKin2-Currents2", "WaveKin3-Currents2-apart",
        "WaveKin3-Currents5-apart"}


def run_deck(name, root, refine=1, duration=20.0, start=5.0):
    """(offset, change) of deck ``name`` (DECKS) with its segments times ``refine``,
    the worst over its lines over start <= t <= duration: offset |mean(skmoor -
    MoorDyn)| / mean(MoorDyn) of the end tension; change rms of the difference between
    the two codes' tension changes from their own static states, over the rms of
    MoorDyn's change (what the water does to the tension, the static states' own
    difference taken out)."""
    deck_name, arguments, end = DECKS[name]
    arguments = dict(IC, **arguments)
    arguments["segments"] *= refine
    if "dtM" in arguments:
        arguments["dtM"] = f"{float(arguments['dtM']) / refine:g}"
    path = deck_copy(deck_name, root, **arguments)
    deck = read_deck(path)
    sea = wavekin1_sea(deck) if name == "WaveKin1" else None
    t_md, theirs, _ = moordyn_run(path, duration, end, external=sea)
    t_sk, ours = skmoor_run(path, duration, end, sea)
    keep = t_sk >= start - 1e-9
    worst = np.zeros(2)
    for k in range(theirs.shape[1]):
        reference = np.interp(t_sk[keep], t_md, theirs[:, k])
        change_md, change_sk = reference - theirs[0, k], ours[keep, k] - ours[0, k]
        worst = np.maximum(worst, [abs(np.mean(ours[keep, k] - reference)) / reference.mean(),
                                   np.sqrt(np.mean((change_sk - change_md) ** 2)
                                           / np.mean(change_md**2))])
    return worst


@pytest.mark.parametrize("name", [pytest.param(name, marks=pytest.mark.slow)
                                  if name in SLOW else name for name in DECKS])
def test_sea_deck_tension_in_time_matches_moordyn(tmp_path, monkeypatch, name):
    """End tension over 20 s, both codes from still water: the offset within 1 % of the
    mean (the lumped and FE static states differ by 0.6 % at 20 segments, 0.14 % at 40),
    the water's change of the tension within 20 % of MoorDyn's (measured 3-18 %, see
    DECKS). On WaveKin2-Currents5, skmoor's current doubled gives (offset, change) =
    (250 %, 1800 %), line 6 of the 4D file read as a point (63 %, 480 %), the grid not
    held at its first sample after 15 s (the deck's jump back) (0.1 %, 25 %); on
    SeafloorFile, the waves stretched over a flat bed of the mean depth instead of the
    bathymetry (0.3 %, 128 %)."""
    monkeypatch.chdir(tmp_path)
    offset, change = run_deck(name, tmp_path)
    assert offset < 1e-2 and change < 0.2, (offset, change)


@pytest.mark.slow
@pytest.mark.parametrize("name", list(DECKS))
def test_sea_deck_agreement_improves_with_segments(tmp_path, monkeypatch, name):
    """Twice the segments (and half MoorDyn's dtM): the offset at most half of it at the
    test's segments (or below 0.05 %: the current decks' offsets are not the static
    states'), and the water's change within 10 % of MoorDyn's (the hanging lines: 20 %,
    measured 15.5 %, no better at 10 segments than at 5)."""
    monkeypatch.chdir(tmp_path)
    (coarse, _), (fine, change) = (run_deck(name, tmp_path / f"x{k}", refine=k)
                                   for k in (1, 2))
    assert fine < max(0.5 * coarse, 5e-4), (coarse, fine)
    assert change < (0.2 if name == "SeafloorFile" else 0.1), change
