"""The catalogue of bad inputs: each gets a one-line message naming the field and the
reason (case files, decks, the Python API and the command line). Run settings, output
folders and physically impossible geometry have their own tests (test_run_settings.py,
test_checks.py); fuzzed edits of cases and decks are in test_fuzz_inputs.py."""
import pytest

import skmoor
from skmoor import cli

PAPER = skmoor.paper_case()


def build_paper(path, value):
    return lambda: skmoor.build(PAPER.replace(path, value))


CATALOGUE = [
    ("a heading in words", build_paper("lines.0.heading_deg", "north"),
     r"lines\[0\]\.heading_deg: expected a number, got 'north'"),
    ("a length in words", build_paper("lines.0.length", "long"),
     r"lines\[0\]\.length: expected a number, got 'long'"),
    ("a number for a name", build_paper("lines.0.name", 42),
     r"lines\[0\]\.name: expected a string, got 42"),
    ("a negative forcing frequency", build_paper("load.omega", -1.0),
     r"load\.omega: must be positive, got -1\.0"),
    ("no elements", build_paper("mooring.n_elements", 0),
     r"mooring\.n_elements: must be an integer >= 1, got 0"),
    ("a billion elements", build_paper("mooring.n_elements", 10**9),
     r"mooring\.n_elements: must be at most"),
    ("a negative depth", build_paper("water.depth", -100.0),
     r"water\.depth: must be positive, got -100\.0"),
    ("a folder for a case file", lambda: skmoor.build("examples"),
     r"build: examples is a folder"),
    ("a folder for a case file (Case)", lambda: skmoor.Case.from_toml("examples"),
     r"case file examples: is a folder"),
    ("a folder for a deck", lambda: skmoor.read_deck("examples"),
     r"deck examples: is a folder"),
    ("a missing deck", lambda: skmoor.read_deck("no/such/deck.dat"),
     r"deck no/such/deck\.dat does not exist"),
    ("a time step in words", lambda: skmoor.simulate(skmoor.build(PAPER), dt="0.1"),
     r"dt: must be a number of seconds, got '0\.1'"),
]


@pytest.mark.parametrize("what, make, message", CATALOGUE, ids=[c[0] for c in CATALOGUE])
def test_bad_input_gets_one_line_naming_the_field(what, make, message):
    with pytest.raises((ValueError, FileNotFoundError), match=message) as info:
        make()
    assert "\n" not in str(info.value).strip()


def test_the_command_line_says_it_in_one_line(capsys, tmp_path):
    assert cli.main(["run", "examples", "--out", str(tmp_path / "o"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("skmoor run: error:") and "is a folder" in err and "\n" not in err


# ------------------------------------------------------------------ faults of a run
# Each kind of fault gets its one-line error, its refusal before the run, or its kept
# results; the command line is driven through skmoor.cli.main in this process.

import json  # noqa: E402
import os  # noqa: E402
import shutil  # noqa: E402
import signal  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from skmoor.run import sweep  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
CLUMP = ROOT / "tests" / "decks" / "network" / "clump_weight.dat"


def one_line_error(capsys, command):
    """The stderr of a command that failed: one line starting 'skmoor COMMAND: error:'."""
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"skmoor {command}: error:"), err
    assert "\n" not in err and "Traceback" not in err, err
    return err


@pytest.fixture(scope="module")
def finished_run(tmp_path_factory):
    """The folder of a short run of the paper's case (2 s)."""
    out = tmp_path_factory.mktemp("run") / "out"
    assert cli.main(["run", "--out", str(out), "--duration", "2", "--quiet", "--no-export",
                     "--no-animation"]) == 0
    return out


def copy_of(folder, tmp_path):
    target = tmp_path / "copy"
    shutil.copytree(folder, target)
    return target


@pytest.mark.parametrize("command", ["export", "render"])
def test_truncated_results_file_is_one_line(command, finished_run, tmp_path, capsys):
    out = copy_of(finished_run, tmp_path)
    data = (out / "results.npz").read_bytes()
    (out / "results.npz").write_bytes(data[: len(data) // 2])
    assert cli.main([command, str(out)]) == 2
    err = one_line_error(capsys, command)
    assert "results.npz: truncated or not a results file" in err


@pytest.mark.parametrize("command", ["export", "render"])
def test_results_file_without_an_array_is_one_line(command, finished_run, tmp_path, capsys):
    out = copy_of(finished_run, tmp_path)
    with np.load(out / "results.npz") as data:
        kept = {k: data[k] for k in data.files if k != "tension"}
    np.savez(out / "results.npz", **kept)
    assert cli.main([command, str(out)]) == 2
    assert "lacks the array tension" in one_line_error(capsys, command)


@pytest.mark.parametrize("command", ["export", "render"])
def test_a_file_for_the_folder_is_one_line(command, finished_run, capsys):
    assert cli.main([command, str(finished_run / "summary.json")]) == 2
    assert "is a file, not the output folder of a run" in one_line_error(capsys, command)


@pytest.mark.parametrize("command", ["export", "render"])
def test_nan_displacements_are_one_line(command, finished_run, tmp_path, capsys):
    out = copy_of(finished_run, tmp_path)
    results = skmoor.Results.load(out / "results.npz")
    results.displacement[3:] = np.nan
    results.save(out / "results.npz")
    assert cli.main([command, str(out)]) == 2
    err = one_line_error(capsys, command)
    assert f"displacement is not finite (NaN or inf) from t = {results.t[3]:.6g} s" in err


def test_export_target_that_cannot_be_written_is_one_line(finished_run, tmp_path, capsys):
    """The target lines.xdmf is a folder: the write fails, said in one line naming it
    (as a read-only folder or a full disk would)."""
    out = copy_of(finished_run, tmp_path)
    (out / "lines.xdmf").mkdir()
    assert cli.main(["export", str(out)]) == 2
    assert "lines.xdmf" in one_line_error(capsys, "export")


def test_a_full_disk_is_one_line(tmp_path, monkeypatch, capsys):
    """No space left while the run writes its results: one line with the file and the
    reason, no traceback."""
    def full(self, path):
        raise OSError(28, "No space left on device", str(path))

    monkeypatch.setattr(skmoor.Results, "save", full)
    out = tmp_path / "o"
    assert cli.main(["run", "--out", str(out), "--duration", "1", "--quiet", "--no-export",
                     "--no-animation"]) == 2
    err = one_line_error(capsys, "run")
    assert "results.npz: No space left on device" in err


def test_sigterm_keeps_the_summary_and_results_as_ctrl_c(tmp_path, monkeypatch, capsys):
    """A SIGTERM in the middle of a run (sent by the recorder's 5th sample here) stops it
    as Ctrl-C does: summary.json (interrupted, the time reached) and results.npz kept,
    exit status 1."""
    from skmoor.run import recorder

    record, calls = recorder.Recorder.record, []

    def record_then_terminate(self, state):
        record(self, state)
        calls.append(state.t)
        if len(calls) == 5:
            os.kill(os.getpid(), signal.SIGTERM)

    monkeypatch.setattr(recorder.Recorder, "record", record_then_terminate)
    before = signal.getsignal(signal.SIGTERM)
    out = tmp_path / "o"
    code = cli.main(["run", "--out", str(out), "--duration", "50", "--quiet", "--no-export",
                     "--no-animation"])
    assert signal.getsignal(signal.SIGTERM) == before
    assert code == 1
    info = json.loads((out / "summary.json").read_text())
    assert info["interrupted"] and info["simulated_time"] < 50
    assert len(skmoor.Results.load(out / "results.npz").t) >= 5
    assert not (out / ".skmoor-lock").exists()


def test_a_second_run_into_a_busy_folder_is_refused(tmp_path, capsys):
    """An output folder locked by a live process (here the test's parent) is refused
    before anything runs, naming the process; a lock left by a process that is gone is
    taken over."""
    out = tmp_path / "o"
    out.mkdir()
    (out / ".skmoor-lock").write_text(str(os.getppid()))
    assert cli.main(["run", "--out", str(out), "--duration", "1", "--quiet", "--no-export",
                     "--no-animation"]) == 2
    err = one_line_error(capsys, "run")
    assert f"another skmoor run (process {os.getppid()}) is writing there" in err
    assert not (out / "summary.json").exists()
    (out / ".skmoor-lock").write_text("999999999")  # no such process
    assert cli.main(["run", "--out", str(out), "--duration", "1", "--quiet", "--no-export",
                     "--no-animation"]) == 0
    assert (out / "summary.json").exists() and not (out / ".skmoor-lock").exists()


def test_network_summary_max_tension_is_not_below_any_end_tension(tmp_path, capsys):
    """On a network (a clump weight on two chain lines) the summary's max_tension is the
    largest tension of the run: not below any line end's in timeseries.csv."""
    out = tmp_path / "o"
    assert cli.main(["run", str(CLUMP), "--out", str(out), "--duration", "0.5", "--quiet",
                     "--no-export", "--no-animation"]) == 0
    info = json.loads((out / "summary.json").read_text())
    table = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)
    ends = [n for n in table.dtype.names if n.startswith(("fairlead_tension", "anchor_tension"))]
    written = 1 - 1e-8  # timeseries.csv has 9 digits
    assert info["max_tension"] >= written * max(table[n].max() for n in ends)
    assert info["max_tension"] >= written * table["max_tension"].max()


def test_warnings_on_the_command_line_are_one_line(tmp_path, capsys, monkeypatch):
    """A warning (here: a time step that does not resolve the natural periods) is one line
    naming its kind, not skmoor's own source line. (Shown as Python shows it outside
    pytest, which records warnings: formatwarning's text on stderr.)"""
    import sys
    import warnings

    def show(message, category, filename, lineno, file=None, line=None):
        sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line))

    monkeypatch.setattr(warnings, "showwarning", show)
    assert cli.main(["run", "--out", str(tmp_path / "o"), "--duration", "2", "--dt", "1",
                     "--quiet", "--no-export", "--no-animation"]) == 0
    lines = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    warned = [ln for ln in lines if "ResolutionWarning" in ln]
    assert warned and all(ln.startswith("skmoor: ResolutionWarning: ") for ln in warned)
    assert not any("warnings.warn" in ln or ".py:" in ln for ln in lines), lines


# ------------------------------------------------------------------ decks too big

def big_deck(tmp_path, segments=40, lines=2):
    text = CLUMP.read_text().replace("350.0     40 ", f"350.0     {segments} ")
    if lines > 2:
        head, rest = text.split("---------------------- OPTIONS")
        extra = "".join(f"{k}   chain      2        3        94.0      2       -\n"
                        for k in range(3, lines + 1))
        text = head + extra + "---------------------- OPTIONS" + rest
    path = tmp_path / "big.dat"
    path.write_text(text)
    return path


@pytest.mark.parametrize("segments, lines, message", [
    (1_000_000, 2, r"big\.dat line 20: LINES NumSegs: must be at most 100000 per line"),
    (40, 10_000, r"big\.dat: LINES: 10000 lines, at most 2000"),
])
def test_a_deck_too_big_is_refused_at_once(tmp_path, capsys, segments, lines, message):
    from skmoor.io import deck, schema

    assert deck.MAX_ELEMENTS_PER_LINE == schema.MAX_ELEMENTS_PER_LINE  # as the case file
    path = big_deck(tmp_path, segments, lines)
    with pytest.raises(ValueError, match=message):
        skmoor.read_deck(path)
    assert cli.main(["run", str(path), "--out", str(tmp_path / "o"), "--quiet"]) == 2
    one_line_error(capsys, "run")


# ------------------------------------------------------------------ sweeps

@pytest.mark.parametrize("spec, message", [
    ("mooring.sag_ratio=0.01:0.03:100000000", r"100000000 points, more than a sweep runs"),
    ("mooring.sag_ratio=0.02,abc", r"parameter 'mooring.sag_ratio': value 'abc' is not a "
                                   r"number \(the base case has"),
])
def test_sweep_refused_before_anything_runs(spec, message, tmp_path, capsys):
    out = tmp_path / "sweep"
    with pytest.raises(ValueError, match=message):
        sweep.studies_from_args([spec])
    assert cli.main(["sweep", "--param", spec, "--out", str(out), "--quiet"]) == 2
    one_line_error(capsys, "sweep")
    assert not out.exists()


def test_sweep_grid_too_big_is_refused():
    with pytest.raises(ValueError, match=r"grid 'g': 1000000 points, more than a sweep runs"):
        sweep.grid_study("g", {"mooring.sag_ratio": "0.01:0.03:1000",
                               "mooring.chord_angle_deg": "40:54:1000"})


def test_sweep_too_short_for_amplitudes_is_said_up_front(tmp_path, capsys, monkeypatch):
    """The paper's case needs 5 forcing periods (5 x 2 pi / 1.6 = 19.6 s) for its
    amplitudes: a 10 s sweep is refused before any point runs."""
    monkeypatch.setattr(sweep, "run_point", lambda task: pytest.fail("a point ran"))
    with pytest.raises(ValueError, match=r"duration: 10 s is shorter than "
                                         r"solver.steady_periods = 5 forcing periods \(19.63 s\)"):
        sweep.run_sweep([sweep.Study("sag", "mooring.sag_ratio", [0.02])], tmp_path,
                        workers=1, duration=10.0, progress=False)
    assert cli.main(["sweep", "--param", "mooring.sag_ratio=0.02", "--duration", "10",
                     "--workers", "1", "--out", str(tmp_path), "--quiet"]) == 2
    one_line_error(capsys, "sweep")


def test_sweep_with_a_deck_for_its_case_says_so(capsys):
    assert cli.main(["sweep", "--case", str(CLUMP), "--param", "mooring.sag_ratio=0.02"]) == 2
    err = one_line_error(capsys, "sweep")
    assert "clump_weight.dat: is a MoorDyn deck, not a case file" in err


def test_ctrl_c_in_a_sweep_writes_the_finished_points(tmp_path, monkeypatch, capsys):
    """Ctrl-C while the second of three points runs: sweep.csv holds the first."""
    done = []

    def point(task):
        if done:
            raise KeyboardInterrupt
        done.append(task["value"])
        return {"surge": 1.0, "heave": 2.0, "pitch": 0.1, "max_tension_steady": 5e5,
                "error": "", "summary": {}, "wall_time": 0.0}

    monkeypatch.setattr(sweep, "run_point", point)
    assert cli.main(["sweep", "--param", "mooring.sag_ratio=0.02,0.03,0.04", "--workers", "1",
                     "--out", str(tmp_path), "--quiet"]) == 130
    with open(tmp_path / "sweep.csv") as f:
        rows = list(__import__("csv").DictReader(f))
    assert [(r["value"], r["surge"]) for r in rows] == [("0.02", "1.0")]


# ------------------------------------------------------------------ file references

def test_file_references_leaving_the_case_folder_are_refused(tmp_path):
    """A bathymetry, a hull mesh named ../../etc/passwd in a case file is refused naming
    the field, before it is opened; a deck's curve file the same."""
    import tomllib

    case = tomllib.loads((ROOT / "examples" / "network_buoy.toml").read_text())
    case["seabed"] = {"file": "../../../../../etc/passwd"}
    folder = tmp_path / "case"
    folder.mkdir()
    with pytest.raises(ValueError, match=r"seabed: file: '\.\./\.\./\.\./\.\./\.\./etc/passwd' "
                                         r"leads out of the folder"):
        skmoor.build(skmoor.Case(case, folder))
    deck = CLUMP.read_text().replace("8.5e8    -1.0", "/etc/passwd    -1.0")
    (folder / "curve.dat").write_text(deck)
    with pytest.raises(ValueError, match=r"curve\.dat line \d+: LINE TYPES EA: '/etc/passwd' "
                                         r"leads out of the folder"):
        skmoor.read_deck(folder / "curve.dat")


# ------------------------------------------------------------------ a current in the wrong unit

def test_a_current_of_a_million_metres_a_second_is_refused_at_once(tmp_path, capsys):
    """A deck's steady current (Currents 1) of 1e6 m/s on a chain of Cd 2.4, d 0.18 m,
    350 m: its drag 1/2 1025 2.4 0.18 (1e6)^2 350 = 7.75e16 N, 9.1e7 times EA; refused
    before any solve (it ran a static solve for minutes), on the CLI in one line."""
    text = CLUMP.read_text().replace("100.0      WtrDpth",
                                     "1          Currents      steady current\n"
                                     "100.0      WtrDpth")
    (tmp_path / "deck.dat").write_text(text)
    (tmp_path / "current_profile.txt").write_text("z ux\n(m) (m/s)\n-\n-100 1e6\n0 1e6\n")
    with pytest.raises(ValueError, match=r"sea: the water's speed 1e\+06 m/s drags line line1 "
                                         r"with about 7\.75e\+16 N, 9\.12e\+07 times its axial"):
        skmoor.build(tmp_path / "deck.dat")
    assert cli.main(["run", str(tmp_path / "deck.dat"), "--out", str(tmp_path / "o"),
                     "--quiet"]) == 2
    assert "no cable holds that" in one_line_error(capsys, "run")


def test_a_warning_from_the_api_points_at_the_callers_line():
    """A warning skmoor gives (a current with nothing to act on) names the line of the
    user's code that called skmoor, not skmoor's own source."""
    case = PAPER.replace("sea", {"current_speed": 0.5})
    with pytest.warns(UserWarning, match="the current acts on nothing") as caught:
        skmoor.build(case)
    assert caught[0].filename == __file__


# ------------------------------------------------------------------ a user's terms

@pytest.mark.parametrize("path", ["compiled", "fd"])
def test_a_user_form_returning_nan_is_named(path):
    """A user's LineForm that returns NaN: the static solve says the residual is not
    finite and names the term (it said 'singular tangent ... is a line slack')."""
    pytest.importorskip("jax") if path == "compiled" else None
    from skmoor.fem import ops
    from skmoor.fem.terms import LineForm
    from skmoor.solvers.newton import ConvergenceError

    def soggy_drag(v, w):
        return np.nan * ops.dot(w.u, v)

    model = skmoor.build(PAPER)
    model.add(LineForm(soggy_drag, path=path))
    with pytest.raises(ConvergenceError, match=r"not finite \(NaN or inf\) at iteration 1: "
                                               r"an added lines term 'soggy_drag' \(LineForm\)") as info:
        skmoor.simulate(model, duration=1.0, progress=False)
    assert "slack" not in str(info.value) and "\n" not in str(info.value)


class UsersOwnError(Exception):
    pass


@pytest.mark.parametrize("path", ["compiled", "fd"])
def test_an_exception_in_a_user_form_is_the_users_own(path):
    """An exception raised in a user's form reaches the caller as that exception, its
    message the last thing said (no JAX note after it)."""
    pytest.importorskip("jax") if path == "compiled" else None
    from skmoor.fem.terms import LineForm

    def broken(v, w):
        raise UsersOwnError("the user's own words")

    model = skmoor.build(PAPER)
    model.add(LineForm(broken, path=path))
    with pytest.raises(UsersOwnError, match="the user's own words") as info:
        skmoor.simulate(model, duration=1.0, progress=False)
    assert not any("JAX" in note for note in getattr(info.value, "__notes__", []))


# ------------------------------------------------------------------ a failing static solve

def test_a_failing_static_solve_is_one_line_naming_the_line(tmp_path, capsys):
    """A case whose 330 m bottom chain is made 100 km long has no static state the solve
    finds: on the command line one line (no traceback) naming the line's nodes that nothing
    holds and what is most out of balance as built."""
    text = (Path(__file__).resolve().parents[2] / "examples" / "network_buoy.toml").read_text()
    (tmp_path / "long.toml").write_text(text.replace("length = 330.0", "length = 100000.0", 1))
    assert cli.main(["run", str(tmp_path / "long.toml"), "--out", str(tmp_path / "o"),
                     "--quiet", "--no-export", "--no-animation", "--duration", "1"]) == 2
    err = one_line_error(capsys, "run")
    assert "static solve" in err and "leg1.bottom node" in err
    assert "most out of balance as built:" in err


def test_a_deck_without_a_static_state_starts_as_moordyn_does(tmp_path, capsys):
    """The same 100 km chain in a deck: MoorDyn relaxes it dynamically instead of a static
    solve; skmoor does as well and says so in one warning line, the run goes on."""
    head, rest = CLUMP.read_text().split("---------------------- POINTS")
    options = rest.split("---------------------- OPTIONS")[1]
    (tmp_path / "span.dat").write_text(head + """---------------------- POINTS ----
ID  Attachment  X         Y         Z        Mass    Volume  CdA   Ca
(#) (word)      (m)       (m)       (m)      (kg)    (m^3)   (m^2) (-)
1   Fixed       -400.0    0.0       -100.0   0.0     0.0     0.0   0.0
2   Coupled     0.0       0.0       0.0      0.0     0.0     0.0   0.0
---------------------- LINES ----
ID  LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#) (name)     (#)      (#)      (m)       (-)      (-)
1   chain      1        2        100000.0  40       -
---------------------- OPTIONS""" + options)
    from skmoor.run.simulate import InitialConditionWarning

    with pytest.warns(InitialConditionWarning):
        assert cli.main(["run", str(tmp_path / "span.dat"), "--out", str(tmp_path / "o"),
                         "--quiet", "--no-export", "--no-animation", "--duration", "0.1"]) == 0
    assert "Traceback" not in capsys.readouterr().err
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["stopped"] is None


def test_sigterm_in_the_api_keeps_the_results(tmp_path, monkeypatch):
    """skmoor.simulate(..., out=FOLDER) stopped by SIGTERM returns its results up to
    there, marked interrupted, and keeps summary.json and results.npz."""
    from skmoor.run import recorder

    record, calls = recorder.Recorder.record, []

    def record_then_terminate(self, state):
        record(self, state)
        calls.append(state.t)
        if len(calls) == 4:
            os.kill(os.getpid(), signal.SIGTERM)

    monkeypatch.setattr(recorder.Recorder, "record", record_then_terminate)
    before = signal.getsignal(signal.SIGTERM)
    results = skmoor.simulate(skmoor.build(PAPER), duration=50.0, progress=False,
                              out=tmp_path / "o")
    assert signal.getsignal(signal.SIGTERM) == before
    assert results.meta["interrupted"] and results.t[-1] < 50.0
    assert json.loads((tmp_path / "o" / "summary.json").read_text())["interrupted"]
    assert (tmp_path / "o" / "results.npz").exists()
