"""The validation report (benchmarks/validate.py) and the benchmarks' shared set-up.

The report must hold one row per comparison, every one passing; a row outside its
tolerance must read FAIL. Its run time is the report's own line, never asserted here.
"""
import re
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest

import skmoor

pytest.importorskip("moorpy", reason="the report runs MoorPy side by side")
pytest.importorskip("moordyn", reason="the report runs MoorDyn side by side")

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))

import _cases  # noqa: E402
import validate  # noqa: E402

ROW = re.compile(r"^\| (?!check \||---)(.+) \|$")


def report(quick):
    """(rows per check function, rows, markdown, seconds) of a run of the checks."""
    started = time.perf_counter()
    per_check, rows = {}, []
    for section, check, fast in validate.CHECKS:
        if quick and not fast:
            continue
        try:
            result = check()
        except validate.NotRun:  # its input (a mirror) is not on this machine
            continue
        result = result if isinstance(result, list) else [result]
        per_check[check] = result
        rows += [(section, row) for row in result]
    seconds = time.perf_counter() - started
    text = validate.markdown(rows, seconds, validate.environment(), quick)
    return per_check, rows, text, seconds


def assert_complete_and_passing(per_check, rows, text):
    table = [line for line in text.splitlines() if ROW.match(line)]
    assert len(table) == len(rows)  # one table row per check row, nothing dropped
    for check, result in per_check.items():
        assert result, f"{check.__name__} gave no row"
    for line, (_, row) in zip(table, rows):
        result = line.rsplit("|", 2)[1].strip()
        assert result == "pass", (row.check, row.reference, row.value, row.error, row.tolerance)
        assert np.isfinite(row.value) and np.isfinite(row.reference)


def test_quick_report_has_every_check_passing():
    per_check, rows, text, _ = report(quick=True)
    assert len(rows) >= 40
    assert_complete_and_passing(per_check, rows, text)
    for heading in ("commit", "versions", "machine"):
        assert f"- {heading}: " in text
    assert "MoorDyn 2.7" in text and "MoorPy 1.3" in text


@pytest.mark.slow
def test_full_report_has_every_check_passing():
    per_check, rows, text, _ = report(quick=False)
    assert_complete_and_passing(per_check, rows, text)


def test_a_row_outside_its_tolerance_fails():
    rel = validate.Row("x", 100.0, "source", 101.5, 1e-2, unit="N")
    assert rel.error == pytest.approx(0.015) and rel.status == "FAIL"
    absolute = validate.Row("order", 2.0, "source", 1.85, 0.1, "abs")
    assert absolute.error == pytest.approx(0.15) and absolute.status == "FAIL"
    assert validate.Row("x", 100.0, "source", 100.5, 1e-2).status == "pass"
    text = validate.markdown([("S", rel)], 0.0, validate.environment(), True)
    assert "| FAIL |" in text and "1 fail" in text


def test_heave_velocity_and_acceleration_are_derivatives():
    """The benchmarks' fairlead heave: velocity and acceleration are the central
    differences of the motion, all three start from zero, full amplitude after the ramp."""
    h = 1e-5
    for t in (0.3, 4.0, 9.9, 10.1, 13.7):
        _z, v, a = _cases.heave(t)
        assert v == pytest.approx((_cases.heave(t + h)[0] - _cases.heave(t - h)[0]) / (2 * h),
                                  rel=1e-6, abs=1e-9)
        assert a == pytest.approx((_cases.heave(t + h)[1] - _cases.heave(t - h)[1]) / (2 * h),
                                  rel=1e-5, abs=1e-8)
    assert _cases.heave(0.0) == pytest.approx((0.0, 0.0, 0.0), abs=1e-15)
    peak = _cases.RAMP + _cases.PERIOD / 4
    assert _cases.heave(peak)[0] == pytest.approx(_cases.HEAVE)


def test_paper_case_benchmark_sets_up_both_codes_on_one_body():
    """benchmarks/paper_case.py's set-up runs on the current API, and MoorDyn's body gets
    skmoor's static load balance: at the equilibrium the body's buoyancy - weight that
    CoupledBody carries equals the lines' vertical pull (a renamed System attribute or a
    dropped term would break it)."""
    import paper_case

    scenario = paper_case.Scenario("moordyn-damping")
    body = paper_case.CoupledBody(scenario)
    fair, _ = scenario.model.system.reactions(scenario.eq.x)
    assert body.F0[2] - (body.K @ body.q0)[2] == pytest.approx(-fair[:, 2].sum(), rel=1e-6)


def test_user_forms_benchmark_sets_up_the_drag_on_every_path():
    """benchmarks/user_forms.py's set-up runs on the current API: the user's drag form on
    scikit-fem's assembly (hand tangents), central differences and the compiled path gives
    the built-in kernel's residual and tangents (an independent implementation), its hand
    tangents pass the Taylor test, and the paper's case with the form added runs the same
    history as with the built-in drag; the report formats."""
    pytest.importorskip("jax", reason="the benchmark's compiled path needs JAX")
    import user_forms

    row = user_forms.per_term(11, paths=("assembly", "fd", "compiled"), budget=1e-3)
    assert row["autodiff"] is None and row["builtin"] > 0
    for path, tolerance in (("assembly", 1e-12), ("fd", 1e-6), ("compiled", 1e-12)):
        seconds, _, difference, _ = row[path]
        assert seconds > 0 and difference < tolerance, (path, difference)
    models = user_forms.paper_models()
    builtin, user, term = models["drag"]
    assert [type(t).__name__ for t in builtin.system.terms] == ["LineHydroKernel"]
    assert user.system.terms == (term,) and term.path == "compiled"
    steel = user.lines.lines[0].line_type
    assert skmoor.check_tangent(user, user_forms.user_drag(steel, "assembly")).ok
    case = user_forms.paper_case_comparison(duration=12.0, repeat=1, models=models)
    for name in ("drag", "law"):  # the same physics as the built-in: the same history
        assert case[name]["agree"]["surge"] < 1e-10, name
        assert case[name]["agree"]["fairlead tension"] < 1e-10, name
    assert case["load"]["agree"]["surge"] > 1e-8  # the small load does move the body
    assert all(row["compiled"] for row in case.values())
    text = user_forms.report([(11, row)], case, user_forms.environment(), True, 0.0)
    assert "| 11 | " in text and "left out" in text and "user law" in text


def test_farm_benchmark_builds_the_farm_it_says(capsys):
    """benchmarks/farm.py on 4 platforms of 10-segment lines: 4 x 3 lines x 9 inner nodes
    x 3 DOFs unknowns; the 12 lowest modes are the 12 lines' first modes: one platform's
    three lowest periods, each four times (its lines differ by the deck's mm rounding)."""
    import farm

    farm.main(["--platforms", "4", "--segments", "10"])
    out = capsys.readouterr().out
    assert "4 platforms, 12 lines of 10 segments (0 shared), 12 anchors: 324 unknowns" in out
    farm.main(["--platforms", "4", "--segments", "10", "--shared"])
    out = capsys.readouterr().out  # 2 x 2 platforms: one shared line in each row
    assert "4 platforms, 14 lines of 10 segments (2 shared), 12 anchors: 378 unknowns" in out
    farm.main(["--platforms", "4", "--segments", "10", "--shared-anchors"])
    out = capsys.readouterr().out  # two pairs share an anchor each
    assert "4 platforms, 12 lines of 10 segments (0 shared), 10 anchors: 324 unknowns" in out
    with tempfile.TemporaryDirectory() as folder:
        one = skmoor.equilibrium(skmoor.build(farm.farm_deck(1, 10, Path(folder))))
        four = skmoor.equilibrium(skmoor.build(farm.farm_deck(4, 10, Path(folder))))
    lowest = np.sort(np.repeat(one.modes.periods[:3], 4))  # each line's first mode, 4 times
    np.testing.assert_allclose(np.sort(four.modes.periods), lowest, rtol=1e-8)
    assert one.modes.periods[3] < 0.99 * one.modes.periods[2]  # the next mode is apart


def test_step_search_checks_every_smaller_step():
    """The benchmarks' step search picks the largest step whose run and every smaller
    step's run are within the tolerance: with errors 5 %, 0.5 %, 2 %, 0.3 %, 0.2 % at
    1, 1/2, 1/4, 1/8, 1/16 s it picks 1/8 s (halving alone would stop at 1/2 s), runs
    every step once and the pick three times; no step when the smallest fails."""
    import steps

    errors = {1.0: 0.05, 0.5: 0.005, 0.25: 0.02, 0.125: 0.003, 0.0625: 0.002}
    runs = []

    def run(dt):
        runs.append(dt)
        return 10.0 / dt, dt  # (wall, outputs)

    found = steps.find_step(run, lambda dt, out, ref_dt, ref: errors[dt], start=0,
                            reference=-5, tolerance=0.01)
    assert found["dt"] == 0.125 and found["error"] == 0.003 and found["wall"] == 80.0
    assert [dt for dt, _ in found["tried"]] == [1.0, 0.5, 0.25, 0.125, 0.0625]
    assert runs == [2.0**-5, 1.0, 0.5, 0.25, 0.125, 0.0625, 0.125, 0.125]
    errors[0.0625] = 0.5
    none = steps.find_step(run, lambda dt, out, ref_dt, ref: errors[dt], start=0,
                           reference=-5, tolerance=0.01)
    assert np.isnan(none["dt"])


def test_scaling_peers_processes_do_not_import_skmoor():
    """A peer's whole process (benchmarks/scaling.py --one) imports its own code only:
    importing the benchmark leaves skmoor out (its imports sit in the skmoor functions),
    so MoorDyn's and CableDyn's start-up and memory are not charged with skmoor's."""
    import subprocess

    out = subprocess.run([sys.executable, "-c", "import sys; import scaling; "
                          "print(any(m.split('.')[0] == 'skmoor' for m in sys.modules))"],
                         cwd=BENCHMARKS, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_scaling_tables_show_the_ratios():
    """The tables scaling.py writes: each code's step, loop, whole process and memory, and
    the ratios of skmoor's times to each peer's."""
    import scaling

    def code(dt, wall, whole):
        return dict(dt=dt, wall=wall, whole=whole, peak_mb=100.0)

    table = [dict(n=10, skmoor=code(0.0625, 1.0, 3.0), moordyn=code(0.002, 4.0, 2.0),
                  cabledyn=code(0.0625, 2.0, 6.0))]
    full, short = scaling.markdown_table(table), scaling.markdown_table(table, short=True)
    assert "| 10 | 0.0625 / 1.000 / 3.00 / 100 | 0.002 / 4.000 / 2.00 / 100 |" in full
    assert full.endswith("| **0.25** | **0.50** | 1.50 | 0.50 |")
    assert short.splitlines()[-1] == "| 10 | **0.25** | **0.50** | 1.50 | 0.50 |"


def test_write_block_replaces_only_its_block(tmp_path):
    """A script's table goes between its own markers; the rest of the page stays, and a
    page without the markers is left alone."""
    page = tmp_path / "page.md"
    page.write_text("intro\n<!-- t -->\nold\n<!-- end of t -->\nafter\n")
    assert _cases.write_block(page, "t", "| new |\n")
    assert page.read_text() == "intro\n<!-- t -->\n| new |\n<!-- end of t -->\nafter\n"
    assert not _cases.write_block(page, "other", "x")
    assert page.read_text().count("| new |") == 1
