"""Run settings, the output folder and outputs written as the run goes (issue: nothing
silent, nothing lost): bad settings refused by name, a coarse step warned about with the
numbers, the folder checked before the solve, a crash or Ctrl-C keeps the rows computed."""
import json
import math
from pathlib import Path

import numpy as np
import pytest

import skmoor
from skmoor import cli
from skmoor.post.export import export
from skmoor.run.outputs import prepare_output
from skmoor.run.simulate import ResolutionWarning


@pytest.fixture(scope="module")
def paper():
    model = skmoor.build(skmoor.paper_case())
    return model, skmoor.equilibrium(model)


@pytest.mark.parametrize("name", ["duration", "dt", "output_interval"])
@pytest.mark.parametrize("value", [0, -5.0, math.inf, math.nan, "10", True])
def test_bad_run_settings_are_refused_by_name(paper, name, value):
    model, eq = paper
    with pytest.raises(ValueError, match=f"^{name}: must be a"):
        skmoor.simulate(model, eq=eq, progress=False, **{name: value})


@pytest.mark.parametrize("flag, value", [("--duration", "0"), ("--duration", "-5"),
                                         ("--duration", "inf"), ("--dt", "0"),
                                         ("--dt", "nan"), ("--output-interval", "0")])
def test_bad_run_settings_on_the_command_line(tmp_path, capsys, monkeypatch, flag, value):
    def no_run(*args, **kwargs):
        raise AssertionError("ran before refusing the setting")

    monkeypatch.setattr("skmoor.run.simulate._starting_equilibrium", no_run)
    code = cli.main(["run", "--out", str(tmp_path / "out"), flag, value, "--quiet"])
    assert code == 2
    err = capsys.readouterr().err
    assert flag.lstrip("-").replace("-", "_") in err and "must be a finite number" in err
    assert not (tmp_path / "out" / "summary.json").exists()


def test_step_longer_than_the_run_is_refused(paper):
    model, eq = paper
    with pytest.raises(ValueError, match="dt: the step .* longer than the duration"):
        skmoor.simulate(model, eq=eq, duration=1.0, dt=2.0, progress=False)


def test_a_step_too_coarse_for_the_forcing_is_warned_with_the_numbers(paper):
    """The paper's forcing period is 2 pi / 1.6 = 3.93 s: dt = 1 s cannot resolve it."""
    model, eq = paper
    with pytest.warns(ResolutionWarning, match=r"dt = 1 s .* forcing period \(3\.927 s\)"):
        results = skmoor.simulate(model, eq=eq, duration=4.0, dt=1.0, progress=False)
    assert any("forcing period" in note for note in results.meta["notes"])
    with warnings_as_errors():
        skmoor.simulate(model, eq=eq, duration=0.2, dt=0.05, progress=False)


class warnings_as_errors:
    def __enter__(self):
        import warnings
        self._catch = warnings.catch_warnings()
        self._catch.__enter__()
        warnings.simplefilter("error", ResolutionWarning)

    def __exit__(self, *exc):
        return self._catch.__exit__(*exc)


def test_output_folder_is_checked_before_the_solve(tmp_path, monkeypatch):
    a_file = tmp_path / "taken"
    a_file.write_text("not a folder")
    for out, why in ((a_file, "is a file"), (a_file / "below", "is a file"),
                     ("/proc/skmoor-cannot-be-here", "cannot write there")):
        with pytest.raises(ValueError, match=why):
            prepare_output(out)

    def no_run(*args, **kwargs):
        raise AssertionError("ran before refusing the output folder")

    monkeypatch.setattr("skmoor.run.simulate._starting_equilibrium", no_run)
    assert cli.main(["run", "--out", str(a_file), "--quiet"]) == 2


def test_a_reused_folder_is_left_clean(tmp_path):
    out = tmp_path / "run"
    (out / "motion").mkdir(parents=True)
    for stale in ("animation.gif", "snapshot.png", "motion.pvd", "motion/lines_9999.vtu"):
        (out / stale).write_text("from an earlier run")
    (out / "notes.txt").write_text("the user's own file")
    prepare_output(out)
    assert sorted(p.name for p in out.rglob("*") if p.is_file()) == ["notes.txt"]


def _paper_with(load_at):
    """The paper's model whose body load calls load_at(t) first (to stop a run)."""
    model = skmoor.build(skmoor.paper_case())
    load = model.system.body_load

    def stopping(t, q, qdot):
        load_at(t)
        return load(t, q, qdot)

    model.system.body_load = stopping
    return model


def _rows(out):
    return np.loadtxt(out / "timeseries.csv", delimiter=",", skiprows=1, ndmin=2)


def test_ctrl_c_keeps_the_rows_and_counts_the_steps_done(tmp_path):
    def interrupt(t):
        if t > 2.0:
            raise KeyboardInterrupt

    out = tmp_path / "run"
    results = skmoor.simulate(_paper_with(interrupt), duration=6.0, dt=0.05,
                              output_interval=0.05, progress=False, out=out)
    info = json.loads((out / "summary.json").read_text())
    assert info["interrupted"] and info["steps_planned"] == 120
    assert 38 <= info["steps"] <= 41 and info["steps"] < info["steps_planned"]
    rows = _rows(out)
    np.testing.assert_allclose(rows[:, 0], results.t)  # every recorded sample is on disk
    assert rows[-1, 0] <= 2.05 and len(rows) == len(results.t)


def test_a_crash_keeps_the_rows_computed_and_reraises(tmp_path):
    def crash(t):
        if t > 3.0:
            raise RuntimeError("a bug in a user's load")

    out = tmp_path / "run"
    with pytest.raises(RuntimeError, match="a bug"):
        skmoor.simulate(_paper_with(crash), duration=6.0, dt=0.05, output_interval=0.05,
                        progress=False, out=out)
    info = json.loads((out / "summary.json").read_text())
    assert info["stopped"].startswith("crashed: RuntimeError")
    rows = _rows(out)
    assert 2.9 <= rows[-1, 0] <= 3.05 and len(rows) >= 59
    assert skmoor.Results.load(out / "results.npz").t[-1] == rows[-1, 0]


def test_paraview_series_have_at_most_a_thousand_frames_by_default(paper, tmp_path):
    from types import SimpleNamespace

    from skmoor.post.export import frames

    long_run = SimpleNamespace(t=np.arange(100_001) * 0.05)  # 5000 s sampled at 0.05 s
    picked = frames(long_run)
    assert 500 <= len(picked) <= 1001 and picked[0] == 0 and picked[-1] == 100_000
    assert len(frames(long_run, None)) == 100_001
    with pytest.raises(ValueError, match="max_frames"):
        frames(long_run, 0)
    model, eq = paper
    results = skmoor.simulate(model, eq=eq, duration=2.0, dt=0.05, output_interval=0.05,
                              progress=False)
    _, pvd = export(results, tmp_path / "some", max_frames=10)
    written = sorted((tmp_path / "some" / "motion").glob("lines_*.vtu"))
    assert len(written) == 9 and written[-1].name == "lines_0040.vtu"
    times = [float(line.split('timestep="')[1].split('"')[0])
             for line in pvd.read_text().splitlines() if 'part="0"' in line]
    assert times[0] == 0.0 and times[-1] == pytest.approx(2.0) and len(times) == 9
    export(results, tmp_path / "some")  # rewritten: every sample, the old frames replaced
    assert len(list((tmp_path / "some" / "motion").glob("lines_*.vtu"))) == 41


def test_an_interrupted_command_line_run_skips_the_long_exports(tmp_path, capsys, monkeypatch):
    """After Ctrl-C the CLI keeps the results and leaves the ParaView files and the
    animations for `skmoor export` / `skmoor render` (exit status 1: stopped early)."""
    import skmoor.model.from_case as model_module

    paper_load = model_module.body_load

    def interrupting(case, load=None):
        applied = paper_load(case, load)

        def load_at(t, q, qdot):
            if t > 1.0:
                raise KeyboardInterrupt
            return applied(t, q, qdot)
        return load_at

    monkeypatch.setattr(model_module, "body_load", interrupting)
    out = tmp_path / "run"
    assert cli.main(["run", "--out", str(out), "--duration", "5", "--quiet"]) == 1
    assert "interrupted: ParaView files and animations skipped" in capsys.readouterr().out
    assert (out / "timeseries.csv").exists() and (out / "summary.json").exists()
    assert not (out / "motion.pvd").exists() and not (out / "animation.gif").exists()


def test_a_step_past_the_bed_contact_period_without_numerical_damping_is_warned(tmp_path):
    """The VolturnUS-like chains of tests/decks/seabed/chain_semi.dat on MoorDyn's bed: a
    resting node is a spring kBot d under the chain's mass and transverse added mass,
    period 2 pi sqrt((685 + 0.82 rho pi d^2 / 4) / (3e6 d)) = 0.173 s (d = 0.333 m). A 0.25
    s Newmark step there chatters at touchdown (benchmarks/volturnus.py): warned with the
    period; not with generalized-alpha at rho_inf 0.5, nor at a step below the period."""
    deck = Path(__file__).parents[1] / "decks" / "seabed" / "chain_semi.dat"
    path = tmp_path / "chain_semi.dat"
    path.write_text(deck.read_text().replace("850.0     50", "850.0     10"))
    model = skmoor.build(path)
    eq = skmoor.equilibrium(model)
    d = 0.333
    period = 2 * np.pi * np.sqrt((685.0 + 0.82 * 1025.0 * np.pi * d**2 / 4) / (3e6 * d))
    assert skmoor.run.simulate.bed_contact_period(model) == pytest.approx(period, rel=1e-3)
    with pytest.warns(ResolutionWarning, match=rf"sea bed's contact period \({period:.3g} s"):
        skmoor.simulate(model, eq=eq, duration=0.5, dt=0.25, progress=False)
    with warnings_as_errors():
        skmoor.simulate(model, eq=eq, duration=0.3, dt=0.1, progress=False)
        model.solver.update(scheme="generalized-alpha", rho_inf=0.5)
        skmoor.simulate(model, eq=eq, duration=0.5, dt=0.25, progress=False)


def test_a_deck_without_ic_solve_starts_from_its_given_state():
    """pendulum.dat sets TmaxIC = 0: its model's default start is the reference as built
    (start='reference', no static solve: the run's notes say so), the clump at rest where
    the deck puts it (x = 10 m, z = -100 m) in the first sample; a start that is not one
    of the three is refused naming the setting."""
    model = skmoor.build(Path(__file__).parents[1] / "decks" / "free_points" / "pendulum.dat")
    assert model.solver["start"] == "reference"
    results = skmoor.simulate(model, duration=0.02, dt=0.01, progress=False)
    assert any("no static solve" in note for note in results.meta["notes"])
    clump = results.point_reference + results.point_displacement[0]
    assert np.abs(clump[results.point_names.index("point2")] - [10.0, 0.0, -100.0]).max() < 1e-9
    with pytest.raises(ValueError, match="simulate start: 'rest' is not one of"):
        skmoor.simulate(model, duration=0.02, dt=0.01, progress=False, start="rest")


def test_the_first_steps_compile_time_is_said_and_kept_out_of_the_eta(monkeypatch, capsys):
    """While the first step takes longer than COMPILE_NOTICE (numba compiling it after an
    install), the bar says it is compiling; after it, one line says how long that took
    and the bar's clock restarts (its rate counts the steps, not the compilation)."""
    import time as clock
    from types import SimpleNamespace

    from skmoor.run import recorder

    seen = {}

    def slow_first(system, x0, v0, dt, duration, **kwargs):
        clock.sleep(0.3)  # the compilation
        seen["description"] = bar_of["bar"].desc
        for step in range(int(round(duration / dt)) + 1):
            yield SimpleNamespace(step=step, subdivided=0)

    bar_of = {}
    real_notice = recorder._CompileNotice

    def keep_bar(bar, label):
        bar_of["bar"] = bar
        return real_notice(bar, label)

    monkeypatch.setattr(recorder, "integrate", slow_first)
    monkeypatch.setattr(recorder, "COMPILE_NOTICE", 0.05)
    monkeypatch.setattr(recorder, "_CompileNotice", keep_bar)
    system = SimpleNamespace(n=1, reset_frames=lambda: None)
    why, steps = recorder.record_run(system, np.zeros(1), dt=0.1, duration=1.0, every=1,
                                     record=lambda state: None, progress=True, label="run",
                                     compiled=False)
    assert why is None and steps == 10
    assert "compiling" in seen["description"]
    err = capsys.readouterr().err
    assert "compiled in" in err and bar_of["bar"].desc == "run"
    assert bar_of["bar"].format_dict["elapsed"] < 0.25  # the clock restarted after it


def test_a_run_says_once_which_term_keeps_its_step_in_python():
    """The paper case compiles its step: no PythonStepWarning; with a user's body load
    written in NumPy (JAX cannot trace it), one warning names the term and why."""
    import warnings

    from skmoor.run.recorder import PythonStepWarning

    model = skmoor.build(skmoor.paper_case())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        skmoor.simulate(model, duration=0.1, dt=0.05, progress=False)
    assert not [w for w in caught if issubclass(w.category, PythonStepWarning)]
    model.add(skmoor.BodyLoad(lambda q, qdot, t: -1e3 * np.asarray(qdot), body=0))
    with pytest.warns(PythonStepWarning, match="BodyLoad on the bodies: the load does not "
                                               "trace with JAX") as caught:
        skmoor.simulate(model, duration=0.1, dt=0.05, progress=False)
    assert len([w for w in caught if issubclass(w.category, PythonStepWarning)]) == 1
