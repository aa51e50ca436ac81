"""MoorDyn's sea input side by side with MoorDyn v2, on the decks of MoorDyn's own set.

The decks and their files are read at run time from a local mirror of
FloatingArrayDesign/MoorDyn (as tests/io/test_moordyn_deck_set.py; skipped without it) and
written, with the folder tree MoorDyn's tests run them in, into a temporary folder.

- Kinematics: the water velocity, acceleration and elevation that skmoor reads from a
  deck's files (skmoor.io.sea_files.deck_sea) against MoorDyn's own (moordyn.GetWavesKin
  after stepping MoorDyn to the time), at points along and beside the line, on and off
  the grids, for WaveKin 2, 3, 7 with Currents 1, 2, 5 (unified on the wave grid and
  not) and a SeafloorFile: within 1e-6 m/s, m/s2, m (measured: 1e-9; 5e-7 with WaveKin 3,
  MoorDyn's wavenumber being a 7-digit approximation). MoorDyn's IC solve is skipped
  (TmaxIC = 0): it does not touch the water.
- Tensions in time: tests/Mooring/wavekin_7 (82-segment light chain from an anchor on
  the bed to a point at the surface, two 1 m components of 15.7 s and 18 s, one along
  x, one along y; bed friction 0.5) run in both codes from their static states (MoorDyn's
  IC solve, currents on and waves off, TmaxIC raised to 60 s; skmoor's equilibrium in the
  sea's steady part), MoorDyn stepped every 50 ms. After the first 5 s (both codes
  switch the waves on at t = 0 from rest; MoorDyn's explicit start rings for ~2 s) the
  end tensions agree within 2 % of MoorDyn's standard deviation rms and 1 % of its
  range at most (measured over 5-40 s: 1.2 % / 2.6 % of the std, 0.6 % of the range).

- Tensions in time with grid waves and a current: tests/Mooring/wavekin_2/wavekin_3.txt
  (WaveKin 3, Currents 1), 60 s: a steady offset within 0.1 % of the mean tension and
  fluctuations within 5 % of MoorDyn's standard deviation (measured: 0.05 %; 2.0 % and
  3.8 % at ends B and A).

Default suite: the WaveKin 7 kinematics (4 s; MoorDyn tabulates the wave grids of the
other decks for 10-50 s); the rest is marked slow (MoorDyn's IC solve and 40 s of
dynamics take 1-2 min).
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
from skmoor.io.sea_files import deck_bathymetry, deck_sea
from skmoor.sea.waves import Sea

try:
    MIRROR = md.Mirror(md.mirror_path())
    NO_MIRROR = ""
except md.MirrorMissing as err:
    MIRROR, NO_MIRROR = None, str(err)

pytestmark = pytest.mark.skipif(MIRROR is None, reason=NO_MIRROR)


def extract(deck, root, **options):
    """Write MoorDyn's deck ``deck`` (its path in the repository) and the files of its
    folder under root (the repository's tree), OPTIONS values replaced ({name: text});
    returns the deck's path; the working folder becomes the one MoorDyn's tests run in."""
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
    (root / deck).write_text(text)
    os.chdir(root / md.run_folder(deck))
    return root / deck


def coupled(deck):
    return [c for p in deck.points if p.kind == "coupled" for c in p.position]


KINEMATICS = [pytest.param("tests/Mooring/wavekin_7/wavekin_7.txt", id="WaveKin7")] + [
    pytest.param(deck, id=name, marks=pytest.mark.slow) for deck, name in (
        ("tests/Mooring/wavekin_2/wavekin_2.txt", "WaveKin2-Currents1"),
        ("tests/Mooring/wavekin_2/wavekin_3.txt", "WaveKin3-Currents1"),
        ("tests/Mooring/wavekin_2/wavekin_2_curr2.txt", "WaveKin2-Currents2"),
        ("tests/Mooring/wavekin_2/wavekin_2_curr5.txt", "WaveKin2-Currents5"),
        ("tests/Mooring/wavekin_2/wavekin_3_curr2.txt", "WaveKin3-Currents2-apart"),
        ("tests/Mooring/wavekin_2/wavekin_3_curr5.txt", "WaveKin3-Currents5-apart"),
        ("tests/Mooring/3D_seafloor/hanging_lines.txt", "WaveKin3-SeafloorFile"),
        ("bench/Mooring/wavekin_7/wavekin_7.txt", "WaveKin7-bench"))]


def kinematics_difference(name, root):
    """Largest |skmoor - MoorDyn| of the water velocity, acceleration and elevation of deck
    ``name`` (written under root) at points on and off its grids at 0.5, 1.37 and 2.9 s
    (m/s, m/s2, m), and whether skmoor's sea holds fields from the deck's files."""
    path = extract(name, root, TmaxIC="0.0")
    deck = read_deck(path)
    bathymetry = deck_bathymetry(deck)
    sea = deck_sea(deck, bathymetry)
    system = moordyn.Create(str(path))
    try:
        x = coupled(deck)
        assert moordyn.Init(system, x, [0.0] * len(x)) == 0
        waves = moordyn.GetWaves(system)
        floor = (moordyn.GetSeafloor(system),) if bathymetry is not None else ()
        points = np.array([[-400.0, 0.0, -49.0], [-200.0, 0.0, -20.0], [-123.4, 0.7, -10.3],
                           [-31.0, -1.3, -27.5], [0.0, 0.0, -2.0], [0.0, 0.0, -0.5],
                           [10.0, 1.0, -30.0]])
        t, step, worst = 0.0, 0.1, 0.0
        for target in (0.5, 1.37, 2.9):
            while t < target - 1e-9:
                moordyn.Step(system, x, [0.0] * len(x), t, step)
                t += step
            velocity, acceleration = sea.kinematics(points, t)
            elevation = sea.elevation(points, t)
            for p, v, a, z in zip(points, velocity, acceleration, elevation):
                u, ud, zeta, _ = moordyn.GetWavesKin(waves, *p, *floor)
                worst = max(worst, np.max(np.abs(np.subtract(u, v))),
                            np.max(np.abs(np.subtract(ud, a))), abs(zeta - z))
    finally:
        moordyn.Close(system)
    return worst, bool(sea.fields)


@pytest.mark.parametrize("name", KINEMATICS)
def test_water_kinematics_match_moordyn(tmp_path, monkeypatch, name):
    monkeypatch.chdir(tmp_path)
    worst, has_fields = kinematics_difference(name, tmp_path)
    assert has_fields and worst < 1e-6, worst


def moordyn_tensions(path, duration, step=0.05):
    """(t, end-A, end-B tension) of line 1 in MoorDyn, every ``step`` s."""
    deck = read_deck(path)
    system = moordyn.Create(str(path))
    try:
        x = coupled(deck)
        assert moordyn.Init(system, x, [0.0] * len(x)) == 0
        line = moordyn.GetLine(system, 1)
        n = moordyn.GetLineN(line)
        out, t = [], 0.0
        while t < duration - 1e-9:
            moordyn.Step(system, x, [0.0] * len(x), t, step)
            t += step
            out.append([t, np.linalg.norm(moordyn.GetLineNodeTen(line, 0)),
                        np.linalg.norm(moordyn.GetLineNodeTen(line, n))])
    finally:
        moordyn.Close(system)
    return np.array(out).T


def tension_differences(path, duration, dt, start, eq=None):
    """[(skmoor - MoorDyn end-segment tension over t >= start (N), MoorDyn's there (N))]
    at ends A and B; skmoor from ``eq`` (default: its own equilibrium)."""
    t_md, *ends_md = moordyn_tensions(path, duration)
    model = skmoor.build(path)
    results = skmoor.simulate(model, duration=duration, dt=dt, output_interval=dt,
                              progress=False, eq=eq)
    assert results.meta["stopped"] is None, results.meta["stopped"]
    cells = np.nonzero(results.line_of_cell == 0)[0]
    keep, window = results.t >= start, t_md >= start
    return [(results.tension[keep, cell] - np.interp(results.t[keep], t_md, theirs),
             theirs[window]) for theirs, cell in zip(ends_md, (cells[0], cells[-1]))]


def compare_in_time(path, duration, dt, start=5.0):
    """(rms / std, max / range) of the end-segment tension differences, both ends."""
    return [(np.sqrt(np.mean(d**2)) / np.std(md_), np.max(np.abs(d)) / np.ptp(md_))
            for d, md_ in tension_differences(path, duration, dt, start)]


@pytest.mark.slow
def test_wavekin7_tensions_in_time_match_moordyn(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    path = extract("tests/Mooring/wavekin_7/wavekin_7.txt", tmp_path, TmaxIC="60.0")
    for rms, peak in compare_in_time(path, 40.0, 0.02):
        assert rms < 0.02 and peak < 0.01, (rms, peak)


@pytest.mark.slow
def test_wavekin3_grid_waves_and_current_in_time_match_moordyn(tmp_path, monkeypatch):
    """tests/Mooring/wavekin_2/wavekin_3.txt (WaveKin 3 on a grid, Wheeler-stretched,
    Currents 1 unified onto it; the 82-segment chain between two fixed points), 60 s, both
    codes from still water: MoorDyn's IC solve leaves its current off the lines
    (docs/api/waves.md), so skmoor starts from its still-water equilibrium too. From
    10 s on (the current's drag has set in) the tensions differ by a steady offset within
    0.1 % of the mean tension (the FE and lumped-mass static states differ by 0.1 %) and,
    about it, by at most 5 % of MoorDyn's standard deviation rms (measured: offsets 0.05 %,
    fluctuations 2.0 % at end B and 3.8 % at end A)."""
    monkeypatch.chdir(tmp_path)
    path = extract("tests/Mooring/wavekin_2/wavekin_3.txt", tmp_path, TmaxIC="60.0")
    deck = read_deck(path)
    still = skmoor.build(path, sea=Sea(deck.depth, rho=deck.rho, g=deck.g))
    for difference, theirs in tension_differences(path, 60.0, 0.02, 10.0,
                                                  eq=skmoor.equilibrium(still)):
        assert abs(difference.mean()) < 1e-3 * theirs.mean(), difference.mean()
        assert difference.std() < 0.05 * theirs.std(), (difference.std(), theirs.std())
