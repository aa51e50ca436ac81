"""MoorDyn's own deck set (benchmarks/moordyn_decks.py): every deck runs in skmoor or is
refused properly, and the static tensions agree with MoorDyn's.

The decks are read at run time from a local mirror of FloatingArrayDesign/MoorDyn
($SKMOOR_MOORDYN_MIRROR, default /work/.mirror/FloatingArrayDesign+MoorDyn/repo); without
it the tests are skipped. One test per deck:

- test_deck_runs_or_is_refused (default suite, ~20 s for the ~45 decks outside SLOW_DECKS,
  skmoor only; those in the slow suite):
  ``skmoor.build(deck)`` + ``equilibrium`` + ``static_results`` either run, or raise a
  ValueError whose message names the deck file, the deck line ('<file> line N') and the
  missing feature; any other exception, or a refusal without the deck line, fails.
- test_static_tension_matches_moordyn (slow: MoorDyn's initial-condition solves take
  2-4 min for the set): for a deck that runs in both, and whose state MoorDyn's IC solve
  leaves settled (see moordyn_decks.SETTLED), the static tension at each line's end B is
  within 2 % of MoorDyn's (same segment counts: ~0.5 % expected); decks with Currents
  in still water on both sides (MoorDyn's IC solve has no currents:
  skmoor.io.sea_files.still_water); the decks of KNOWN_DIFFERENCES are expected failures,
  with the reason.
- test_census_counts_match_moordyn (slow): the survey's own reading of each deck counts
  the lines, points, bodies and rods MoorDyn counts.
- test_deck_runs_through_the_cli (the three decks that once failed, in the default suite, ~30 s;
  every other deck slow, ~8 min): ``skmoor run DECK`` for 5 steps, from the folder
  MoorDyn's tests run it in with its companion files, ends with status 0 and a summary
  (or a one-line refusal naming the deck line), never a traceback; seafloor.txt, whose
  static solve finds no state, starts from MoorDyn's dynamic relaxation with a
  one-line warning.
"""
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import moordyn_decks as md  # noqa: E402

try:
    MIRROR = md.Mirror(md.mirror_path())
    DECKS = [d.path for d in md.find_decks(MIRROR)[0]]
    NO_MIRROR = ""
except md.MirrorMissing as err:
    MIRROR, DECKS, NO_MIRROR = None, [], str(err)

pytestmark = pytest.mark.skipif(MIRROR is None, reason=NO_MIRROR)
PARAMS = DECKS or [pytest.param("(no mirror)", marks=pytest.mark.skip(reason=NO_MIRROR))]


def by_deck(outcomes):
    return {o.name: o for o in outcomes}


# decks whose skmoor statics take 5-40 s each (network settling of ten free points, or
# 82-segment chains in a current; the tripod's eleven bending lines finding no
# equilibrium; the risers' bending lines; complex_system's free body finding none):
# checked in the slow suite only; the default suite keeps at least one deck per
# sea-input option (WaveKin 1, 2, 3, 7; Currents 1, 2; SeafloorFile), and
# tests/coupling/test_rod_junctions.py has the risers' zero-length rods and clamp body
SLOW_DECKS = ("tests/Mooring/3D_seafloor/hanging_lines.txt",
              "tests/Mooring/tripod.txt", "tests/Mooring/riser/",
              "tests/Mooring/local_euler/complex_system.txt",
              "tests/Mooring/wavekin_4/hanging_lines.txt",
              "tests/Mooring/wave_surface/wave_surface.txt",
              "tests/Mooring/wavekin_2/wavekin_2_curr", "tests/Mooring/wavekin_2/wavekin_3_curr",
              "tests/Mooring/wavekin_wave_1.txt", "bench/Mooring/wavekin_2/wavekin_2.txt",
              "bench/Mooring/wavekin_7/wavekin_7.txt")

# decks whose static tensions differ from MoorDyn's for a known reason
KNOWN_DIFFERENCES = {
    "tests/Mooring/body_tests/pinnedBody.txt": "its one line, a dummy of one segment, "
    "hangs between two fixed points 5 m apart vertically at exactly its length, in air: "
    "skmoor's exact catenary hangs it from the top (end A 1716 N = its weight, end B 0); "
    "MoorDyn's one segment lumps half the weight on each end node (858 N at both)",
}


def slow_deck(path):
    return any(path.startswith(prefix) for prefix in SLOW_DECKS)


RUN_PARAMS = [pytest.param(deck, marks=pytest.mark.slow) if slow_deck(deck) else deck
              for deck in DECKS] or PARAMS
STATIC_PARAMS = [pytest.param(deck, marks=pytest.mark.xfail(reason=KNOWN_DIFFERENCES[deck],
                                                            strict=True))
                 if deck in KNOWN_DIFFERENCES else deck for deck in DECKS] or PARAMS


@pytest.fixture(scope="module")
def skmoor_side():
    outcomes, _ = md.survey(MIRROR, sides=("skmoor",), keep=lambda path: not slow_deck(path))
    return by_deck(outcomes)


@pytest.fixture(scope="module")
def skmoor_slow_side():
    outcomes, _ = md.survey(MIRROR, sides=("skmoor",), keep=slow_deck)
    return by_deck(outcomes)


@pytest.fixture(scope="module")
def both_sides():
    pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) is the peer")
    outcomes, _ = md.survey(MIRROR)
    return by_deck(outcomes)


def test_the_set_is_there():
    """The mirror holds MoorDyn's set: ~50 decks under the three folders."""
    assert len(DECKS) >= 40, DECKS
    assert {"tests/Mooring/lines.txt", "tests/Mooring/pendulum.txt",
            "example/lines.txt"} <= set(DECKS)


@pytest.mark.parametrize("deck", RUN_PARAMS)
def test_deck_runs_or_is_refused(request, deck):
    side = "skmoor_slow_side" if slow_deck(deck) else "skmoor_side"
    o = request.getfixturevalue(side)[deck]
    status = o.skmoor_status
    message = o.skmoor.get("message", "")
    assert status != "error", (
        f"{deck}: skmoor raised {o.skmoor.get('type')} (only a ValueError naming the deck "
        f"line may refuse a deck): {message}\n{o.skmoor.get('traceback', '')}")
    assert status != "refused badly", (
        f"{deck}: refused, but the message {o.refusal_problem()}: {message}")
    if status == "no equilibrium":  # a statics that cannot exist must say what is free
        assert "unrestrained at the given state" in message, (deck, message)
        return
    assert status in ("runs", "refused"), (deck, o.skmoor)
    if status == "runs":
        names = [f"line{k}" for k in range(1, o.deck.census["lines"] + 1)]
        assert o.skmoor["line_names"] == names, deck
        assert all(t >= 0 for t in o.skmoor["end_b"] + o.skmoor["end_a"]), deck


@pytest.mark.slow
@pytest.mark.parametrize("deck", STATIC_PARAMS)
def test_static_tension_matches_moordyn(both_sides, deck):
    o = both_sides[deck]
    if not o.moordyn_runs:
        pytest.skip(f"MoorDyn does not run it: {o.moordyn.get('message')}")
    if o.skmoor_status != "runs":
        pytest.skip(f"skmoor does not run it ({o.skmoor_status})")
    if not o.comparison():
        pytest.skip("no lines")
    if not o.moordyn_settled:
        pytest.skip("MoorDyn's IC solve leaves it moving (residual "
                    f"{o.moordyn.get('ic_error')} m/s2 after {o.moordyn.get('ic_time')} s)")
    worst = o.largest_difference()
    lines = "; ".join(f"line {k}: skmoor {sk / 1e3:.5g} kN, MoorDyn {force / 1e3:.5g} kN "
                      f"({diff:.2%})" if sk is not None else f"line {k}: missing in skmoor"
                      for k, sk, force, _, diff in o.comparison())
    assert worst <= md.TOLERANCE, f"{deck}: static end-B tension differs: {lines}"


@pytest.mark.slow
@pytest.mark.parametrize("deck", PARAMS)
def test_census_counts_match_moordyn(both_sides, deck):
    o = both_sides[deck]
    if not o.moordyn_runs:
        pytest.skip("MoorDyn does not run it")
    c = o.deck.census
    mine = {key: c[key] for key in ("lines", "points", "bodies", "rods")}
    assert mine == o.moordyn["counts"], deck


# ------------------------------------------------------------------ `skmoor run DECK`

# decks that once ended in a traceback through the CLI: the static solve of
# seafloor.txt (a pendulum on a slack, weightless line over a sloped 3D sea bed) finds no
# state and MoorDyn's dynamic relaxation starts it; wavekin_7's waves had no velocity
# at rest for the surface term
CLI_DECKS = ("tests/Mooring/BodiesAndRods.dat", "tests/Mooring/seafloor.txt",
             "bench/Mooring/wavekin_7/wavekin_7.txt")
CLI_PARAMS = ([deck if deck in CLI_DECKS else pytest.param(deck, marks=pytest.mark.slow)
               for deck in DECKS] or PARAMS)


def run_cli(deck, tmp_path, capsys, *options):
    """`skmoor run DECK` in this process from the folder MoorDyn's tests run the deck
    from, its companion files extracted from the mirror beside it: (exit status, stderr,
    summary.json or None). An exception escaping the CLI fails the test."""
    import json
    import os

    from skmoor import cli

    entry = next(d for d in md.find_decks(MIRROR)[0] if d.path == deck)
    local = md.extract(MIRROR, entry, tmp_path / "repo")
    out = tmp_path / "out"
    here = os.getcwd()
    os.chdir(tmp_path / "repo" / md.run_folder(deck))
    try:
        status = cli.main(["run", str(local), "--out", str(out), "--no-export",
                           "--no-animation", "--quiet", *options])
    finally:
        os.chdir(here)
    err = capsys.readouterr().err
    summary = out / "summary.json"
    return status, err, json.loads(summary.read_text()) if summary.exists() else None


@pytest.mark.parametrize("deck", CLI_PARAMS)
def test_deck_runs_through_the_cli(deck, tmp_path, capsys):
    """`skmoor run DECK` (a short run) ends with status 0 and its summary, or refuses the
    deck in one line naming the deck line (status 2); never a traceback. A deck whose
    static solve finds no state starts as MoorDyn's does, from a dynamic relaxation,
    with a one-line warning."""
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        status, err, summary = run_cli(deck, tmp_path, capsys, "--duration", "0.05",
                                       "--dt", "0.01")
    if status == 2:
        assert md.refusal_problem(deck, err) is None, err
        assert deck in CLI_DECKS or len(err.strip().splitlines()) == 1, err
        assert deck not in CLI_DECKS, f"{deck}: refused: {err}"
        return
    assert status == 0, (deck, err)
    assert summary is not None and summary["stopped"] is None, deck
    assert summary["steps"] == 5, deck
    relaxed = [str(w.message) for w in caught
               if type(w.message).__name__ == "InitialConditionWarning"]
    assert all("\n" not in note for note in relaxed), relaxed
    if deck == "tests/Mooring/seafloor.txt":  # no static state: MoorDyn's relaxation
        assert relaxed and "dynamic relaxation" in relaxed[0], relaxed
        assert any("dynamic relaxation" in note for note in summary["notes"]), summary
