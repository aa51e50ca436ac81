"""MoorDyn's tripod deck (tests/Mooring/tripod.txt) run side by side in time with the
``moordyn`` package, both codes from the deck's given state.

The deck: 11 bending lines (EI > 0) and 12 points, 9 of them free and massless (a float,
its tether and three legs each of bridle, line and chain down to a fixed anchor); TmaxIC
= 0, so MoorDyn runs no initial-condition stage: it starts at rest with every line on its
catenary between the points as given (line 1, the float, straight: its catenary fails),
and its tests/tripod.cpp only steps it. Those positions are no equilibrium: each chain
hangs 0.2-0.5 m below the bed and every junction carries an unbalanced pull, so the
three chain junctions (points 5, 8, 11) jump 0.1-0.2 m in the first 0.1 s.

skmoor builds such a deck with ``solver["start"] = 'reference'`` and without settling
its free points: ``skmoor.simulate`` starts from the reference state as built, the same
node positions as MoorDyn's (checked to 1e-6 m), with only the Hermite node tangents
turned to rotational balance (skmoor.run.equilibrium.reference_state; MoorDyn's nodes have none).

What is compared: the free points' tracks over 0-0.1 s (before the float's tether
snaps at 0.33 s, after which both codes heave the float by metres), rms of skmoor -
MoorDyn over the window relative to MoorDyn's range there, for the coordinates that move
more than 5 cm (those of points 5, 8 and 11). Measured (skmoor Newmark-alpha dt = 1 ms,
MoorDyn RK4 at dtM = 10 us; the deck's 55 us gives the same tracks to 1e-4 m):

    segments              rms / range, points 5, 8, 11 (x, y, z where range > 5 cm)
    the deck's (NumSegs)  3.8 - 14.4 %, mean 8.9 %
    2 x NumSegs           1.3 - 4.3 %, mean 2.1 %

The two codes converge to each other as both meshes are refined (the difference falls by
about 4 per halving): at the deck's segment counts it is the lumped-mass discretization
(a junction point carries half a segment's mass of each line) against skmoor's
consistent Hermite mass, not a difference of physics. skmoor's own step is converged
(dt = 0.5 ms moves the tracks by 2e-4 m) and its mesh nearly so (2 x NumSegs moves
points 5, 8, 11 by 0.3-1.6 cm rms, 1-5 % of the range), so the refined comparison's 6 %
tolerance is the refined MoorDyn's remaining discretization, bounded by the halving.

Not compared: the end tensions. The start snaps the stiff segments (axial periods of a
few ms), and the tension histories of the two codes agree only in their 10 ms means
(to ~30 %), not sample by sample: MoorDyn's segments ring at their own frequencies under
its -0.5 zeta damping, skmoor's generalized-alpha damps those frequencies instead.

Wall time (2-core machine, shared): the default test 4 s (its two steps on scikit-fem's
assembly of the bending lines' forms); the slow one 23 s with the forms' numba kernels
cached (form_path 'compiled'; their first compile adds ~30 s per kernel).
"""
import re
import sys
from pathlib import Path

import numpy as np
import pytest

moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) is the "
                              "lumped-mass dynamic peer")

import skmoor  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import moordyn_decks as md  # noqa: E402

try:
    MIRROR = md.Mirror(md.mirror_path())
    NO_MIRROR = ""
except md.MirrorMissing as err:
    MIRROR, NO_MIRROR = None, str(err)
pytestmark = pytest.mark.skipif(MIRROR is None, reason=NO_MIRROR)

TRIPOD = "tests/Mooring/tripod.txt"
FREE = (1, 2, 3, 4, 5, 7, 8, 10, 11)  # the free points' MoorDyn IDs
JUNCTIONS = (5, 8, 11)  # line - chain junctions: the points that move (0.1-0.2 m)
WINDOW = 0.1  # s
MOORDYN_DT = 1e-5  # s: RK4 stable on the doubled mesh too (the deck's 55 us is not there)


def tripod_deck(folder, refine=1):
    """Path of tripod.txt written into folder, its NumSegs times refine, MoorDyn's step
    dtM = MOORDYN_DT."""
    text = md.deck_text(MIRROR, TRIPOD)
    head, rest = text.split("LINES", 1)
    table, tail = rest.split("SOLVER OPTIONS", 1)

    def refined(match):
        words = match.group(0).split()
        words[5] = str(refine * int(words[5]))
        return " ".join(words)

    table = re.sub(r"(?m)^\s*\d+\s+\S+\s+\d+\s+\d+\s+\S+\s+\d+\s+\S+\s*$", refined, table)
    tail = re.sub(r"(?m)^\S+(\s+dtM\b)", rf"{MOORDYN_DT}\g<1>", tail)
    path = Path(folder) / "tripod.txt"
    path.write_text(head + "LINES" + table + "SOLVER OPTIONS" + tail)
    return path


def run_moordyn(path, duration, coupling=1e-3):
    """(t, P, TA, TB): MoorDyn's free-point positions (nt, 9, 3) (m) and end-segment
    tensions at ends A, B (nt, nlines) (N) every ``coupling`` s, from t = 0 (tensions
    from the first step on: nt - 1 rows)."""
    system = moordyn.Create(str(path))
    try:
        assert moordyn.Init(system, [], []) == 0
        lines = [moordyn.GetLine(system, k + 1) for k in range(moordyn.GetNumberLines(system))]
        points = [moordyn.GetPoint(system, p) for p in FREE]
        t, P, TA, TB = [0.0], [[moordyn.GetPointPos(p) for p in points]], [], []
        for k in range(int(round(duration / coupling))):
            moordyn.Step(system, [], [], k * coupling, coupling)
            t.append((k + 1) * coupling)
            P.append([moordyn.GetPointPos(p) for p in points])
            TA.append([np.linalg.norm(moordyn.GetLineNodeTen(ln, 0)) for ln in lines])
            TB.append([np.linalg.norm(moordyn.GetLineNodeTen(ln, moordyn.GetLineN(ln)))
                       for ln in lines])
    finally:
        moordyn.Close(system)
    return np.array(t), np.array(P), np.array(TA), np.array(TB)


def moordyn_nodes(path):
    """MoorDyn's node positions of every line after Init (no step), [(n + 1, 3)] m."""
    system = moordyn.Create(str(path))
    try:
        assert moordyn.Init(system, [], []) == 0
        nodes = []
        for k in range(moordyn.GetNumberLines(system)):
            line = moordyn.GetLine(system, k + 1)
            nodes.append(np.array([moordyn.GetLineNodePos(line, i)
                                   for i in range(moordyn.GetLineN(line) + 1)]))
    finally:
        moordyn.Close(system)
    return nodes


def point_tracks(results):
    """(nt, 9, 3) positions of the free points in skmoor's results, m."""
    i = [results.point_names.index(f"point{p}") for p in FREE]
    return results.point_reference[i] + results.point_displacement[:, i]


def run_skmoor(path, duration, dt, compiled=True):
    """skmoor's run of the deck at path from its default start (the deck's 'reference'),
    generalized-alpha (rho_inf 0.5: the massless junctions' fastest modes damped) at dt;
    compiled: the bending lines' hydrodynamic, bed and surface forms as numba kernels."""
    from skmoor.model.from_deck import deck_network
    from skmoor.model.model import from_network

    network, settings = deck_network(path)
    if compiled:
        network.form_path = "compiled"
    model = from_network(network, settings=settings, settle=False)
    model.solver.update(scheme="generalized-alpha", rho_inf=0.5)
    results = skmoor.simulate(model, duration=duration, dt=dt, output_interval=dt,
                              progress=False)
    assert results.meta["stopped"] is None, results.meta["stopped"]
    return results


def relative_rms(t, values, t_md, reference):
    """rms of values - reference (interpolated at t) over the window / reference's range."""
    return (np.sqrt(np.mean((values - np.interp(t, t_md, reference)) ** 2))
            / np.ptp(reference))


def junction_errors(results, t_md, P_md):
    """{(point, axis): rms / range} for the junctions' coordinates moving > 5 cm."""
    tracks = point_tracks(results)
    errors = {}
    for p in JUNCTIONS:
        j = FREE.index(p)
        for axis in range(3):
            if np.ptp(P_md[:, j, axis]) > 0.05:
                errors[(p, "xyz"[axis])] = relative_rms(results.t, tracks[:, j, axis],
                                                        t_md, P_md[:, j, axis])
    return errors


def test_tripod_starts_where_moordyn_does(tmp_path, monkeypatch):
    """tripod.txt (TmaxIC = 0) runs from its given state, as MoorDyn does, with no static
    solve: skmoor's start is 'reference', its line nodes at t = 0 sit on MoorDyn's initial
    profiles (its catenaries, line 1 straight) to 1e-6 m, the chain junctions start where
    the deck puts them, and the first steps run. Fails if the lines were settled statically
    between the points (the chains move 0.36-0.53 m), if the free points were settled on
    catenaries, or if the run went through the statics (it has no equilibrium: 5 s spent
    finding none, then a stop or a release from settled lines)."""
    monkeypatch.chdir(tmp_path)
    path = tripod_deck(tmp_path)
    model = skmoor.build(str(path))
    assert model.solver["start"] == "reference"
    results = skmoor.simulate(model, duration=0.002, dt=0.001, output_interval=0.001,
                              progress=False)
    assert results.meta["stopped"] is None, results.meta["stopped"]
    assert any("no static solve" in note for note in results.meta["notes"])
    nodes = results.points + results.displacement[0]
    lines = model.lines
    for k, expected in enumerate(moordyn_nodes(path)):
        a, b = lines.anchor_nodes[k], lines.fairlead_nodes[k]
        assert np.abs(nodes[a:b + 1] - expected).max() < 1e-6, f"line{k + 1}"
    deck = skmoor.read_deck(str(path))
    given = {p.id: np.array(p.position) for p in deck.points}
    assert np.abs(point_tracks(results)[0] - [given[p] for p in FREE]).max() < 1e-9


@pytest.mark.slow
def test_tripod_junctions_track_moordyn_as_both_meshes_refine(tmp_path, monkeypatch):
    """The chain junctions' tracks over 0-0.1 s against MoorDyn's: within 6 % rms of the
    range with both codes on twice the deck's segments, and that difference at most half
    of the one on the deck's segments (the two discretizations converging together; see
    the module docstring). Fails on a start that is not MoorDyn's (settled lines: the
    junctions barely move), on a lost bed or bending term, or on wrong point inertia."""
    monkeypatch.chdir(tmp_path)
    errors = {}
    for refine in (1, 2):
        folder = tmp_path / f"x{refine}"
        folder.mkdir()
        path = tripod_deck(folder, refine)
        t_md, P_md, _, _ = run_moordyn(path, WINDOW)
        errors[refine] = junction_errors(run_skmoor(path, WINDOW, 1e-3), t_md, P_md)
    assert len(errors[2]) >= 6
    assert max(errors[2].values()) < 0.06, errors[2]
    assert np.mean(list(errors[2].values())) < 0.5 * np.mean(list(errors[1].values())), errors
