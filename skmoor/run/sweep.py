"""Parameter studies: one case run many times with one value changed, on local processes
or on a Dask cluster.

    from skmoor.run.sweep import paper_studies, run_sweep
    rows = run_sweep(paper_studies(), out="skmoor-out")            # all local cores
    rows = run_sweep(paper_studies(), scheduler="tcp://host:8786")  # a Dask cluster

A :class:`Study` is a base case, a dotted parameter path (``"mooring.sag_ratio"``) and
its values; each value is one point, ``base_case.replace(parameter, value)``, which is
built, simulated and summarised by :func:`run_point`. :func:`grid_study` gives all
combinations of several parameters, :func:`read_studies` reads a TOML study file,
:meth:`Study.from_spec` a command-line spec (``"path=v1,v2,v3"`` or
``"path=start:stop:n"``).

:func:`run_sweep` writes into ``out``:

- ``sweep-points/``: one small JSON per finished point, named by a hash of the study,
  parameter, value, the point's whole case and the run settings. A rerun (after Ctrl-C,
  a crash or adding values) computes only the points that have no file. Failed points
  are not kept, so they are tried again. Delete the folder to recompute everything.
- ``sweep.csv``: one row per point: study, parameter, value, surge, heave, pitch
  (steady-state amplitudes over the case's last ``solver.steady_periods`` forcing
  periods; m, m, rad), max_tension_steady (largest element tension over that window, N) and error
  (empty when the point succeeded).
- ``sweep-<study>.png``: the amplitudes and the maximum tension against the parameter
  (the paper's Figs. 7 and 8), one figure per study.

Dask workers must be able to import the same skmoor (install it on every worker).
"""
from __future__ import annotations

import contextlib
import csv
import difflib
import hashlib
import itertools
import json
import math
import multiprocessing
import os
import re
import socket
import sys
import time
import warnings
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

import numpy as np

from ..io.case import PAPER_CASE, Case, paper_case
from ..model.model import build
from .outputs import summary
from .simulate import simulate

COLUMNS = ("study", "parameter", "value", "surge", "heave", "pitch", "max_tension_steady", "error")
AMPLITUDES = ("surge", "heave", "pitch")
MAX_POINTS = 100_000  # points of one sweep (more is a typo: 1e8 points would take years)


# ---------------------------------------------------------------- studies

@dataclass
class Study:
    """Points ``base_case.replace(parameter, value)`` for each of ``values``.

    name        names the study in the CSV, the point files and the figure
    parameter   dotted path into the case (``"mooring.chord_angle_deg"``)
    values      the values of the parameter, one point each
    base_case   a :class:`~skmoor.io.case.Case` (default: the paper's case)
    fixed       other dotted paths set to one value for every point (grid studies)
    label       x-axis label of the figure (default: the parameter path)
    """

    name: str
    parameter: str
    values: list
    base_case: Case | None = None
    fixed: dict = field(default_factory=dict)
    label: str | None = None

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name.strip():
            raise ValueError(f"study name: must be a non-empty string, got {self.name!r}")
        if not isinstance(self.parameter, str) or not self.parameter.strip():
            raise ValueError(f"study {self.name!r}: parameter must be a dotted path such as "
                             f"'mooring.sag_ratio', got {self.parameter!r}")
        values = self.values
        if isinstance(values, str):
            values = parse_values(values)
        elif isinstance(values, np.ndarray):
            values = values.ravel().tolist()
        elif isinstance(values, (int, float)):
            values = [values]
        self.values = [_plain(v) for v in values]
        if not self.values:
            raise ValueError(f"study {self.name!r}: no values")
        if len(self.values) > MAX_POINTS:
            raise ValueError(f"study {self.name!r}: {len(self.values)} values, more than a "
                             f"sweep runs (at most {MAX_POINTS} points)")
        if self.base_case is None:
            self.base_case = paper_case()
        elif not isinstance(self.base_case, Case):
            raise TypeError(f"study {self.name!r}: base_case must be a skmoor Case, "
                            f"got {type(self.base_case).__name__}")
        self.fixed = {str(k): _plain(v) for k, v in dict(self.fixed).items()}
        for path in (self.parameter, *self.fixed):
            _check_path(self.base_case, path, self.name)
        _check_numbers(self.base_case, self.parameter, self.values, self.name)
        for path, value in self.fixed.items():
            _check_numbers(self.base_case, path, [value], self.name)
        if self.label is None:
            self.label = self.parameter

    def case(self, value) -> Case:
        """The case of the point ``value`` (raises ValueError if the case rejects it)."""
        case = self.base_case
        for path, v in self.fixed.items():
            case = case.replace(path, v)
        return case.replace(self.parameter, value)

    @classmethod
    def from_spec(cls, spec: str, base_case: Case | None = None, name: str | None = None,
                  label: str | None = None) -> Study:
        """A study from ``"path=v1,v2,v3"`` or ``"path=start:stop:n"`` (n values evenly
        spaced, ends included). Values may be numbers, fractions (``1/60``), true/false
        or words."""
        path, values = parse_spec(spec)
        return cls(name or path.rsplit(".", 1)[-1], path, values, base_case, label=label)


def grid_study(name: str, parameters: dict, base_case: Case | None = None,
               label: str | None = None) -> list[Study]:
    """All combinations of several parameters (``{path: values, ...}``), as one study
    per combination of the second and further parameters, each varying the first one
    (so each is one curve in its figure). Values may also be spec strings
    (``"40:54:8"``)."""
    items = [(path, parse_values(v) if isinstance(v, str) else list(v))
             for path, v in dict(parameters).items()]
    if not items:
        raise ValueError(f"grid {name!r}: give at least one parameter")
    (first, values), rest = items[0], items[1:]
    total = math.prod(len(v) for _, v in items)
    if total > MAX_POINTS:
        raise ValueError(f"grid {name!r}: {total} points, more than a sweep runs (at most "
                         f"{MAX_POINTS})")
    if not rest:
        return [Study(name, first, values, base_case, label=label)]
    studies = []
    for combo in itertools.product(*(v for _, v in rest)):
        fixed = {path: v for (path, _), v in zip(rest, combo)}
        tag = ",".join(f"{p.rsplit('.', 1)[-1]}={_short(v)}" for p, v in fixed.items())
        studies.append(Study(f"{name}[{tag}]", first, values, base_case, fixed=fixed,
                             label=label))
    return studies


def paper_studies(n_points: int = 8, base_case: Case | None = None) -> list[Study]:
    """The paper's two studies (Wang, Er & Iu, Figs. 7 and 8; resolved in docs/paper.md):
    sag ratio d/l from 1/45 to 1/80 at theta = 50 deg (evenly spaced in l/d), and chord
    angle theta from 40 to 54 deg at d/l = 1/60."""
    if not (isinstance(n_points, int) and n_points >= 2):
        raise ValueError(f"n_points: need an integer >= 2, got {n_points!r}")
    base = base_case or paper_case()
    ratios = [1.0 / x for x in np.linspace(45.0, 80.0, n_points)]
    return [
        Study("sag-ratio", "mooring.sag_ratio", ratios, base,
              fixed={"mooring.chord_angle_deg": 50.0}, label="sag-to-span ratio d/l [-]"),
        Study("chord-angle", "mooring.chord_angle_deg", np.linspace(40.0, 54.0, n_points),
              base, fixed={"mooring.sag_ratio": 1 / 60}, label="chord angle theta [deg]"),
    ]


def studies_from_args(params=(), study_file=None, case=None) -> list[Study]:
    """Studies from command-line arguments: ``params`` spec strings (``"path=v1,v2"``,
    ``"path=start:stop:n"``; several make a grid), a TOML ``study_file`` and a base
    ``case`` file (for the params, and for the file's studies that name none)."""
    base = _base_case(case, "--case") if case else None
    studies = read_studies(study_file, base) if study_file else []
    if params:
        parsed = [parse_spec(p) for p in params]
        paths = [path for path, _ in parsed]
        if len(set(paths)) < len(paths):
            raise ValueError(f"--param: a path is given twice: {paths}")
        if len(parsed) == 1:
            studies.append(Study(paths[0].rsplit(".", 1)[-1], *parsed[0], base))
        else:
            studies += grid_study("grid", dict(parsed), base)
    if not studies:
        raise ValueError("give at least one parameter spec or a study file")
    return studies


def read_studies(path, base_case: Case | None = None) -> list[Study]:
    """Studies from a TOML file::

        base_case = "my_case.toml"          # optional; default: the paper's case

        [[study]]
        name = "sag"
        parameter = "mooring.sag_ratio"
        values = [0.0222, 0.0167, 0.0125]   # or a spec string "1/45:1/80:8"
        label = "d/l"                       # optional
        base_case = "other.toml"            # optional, per study

        [[study]]
        name = "grid"
        grid = { "mooring.sag_ratio" = "1/45,1/80", "mooring.chord_angle_deg" = [40, 50] }

    Case file paths are relative to the study file; ``base_case`` is the default for
    studies that name none (otherwise the paper's case)."""
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"study file {path} does not exist")
    try:
        data = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as err:
        raise ValueError(f"{path.name}: not valid TOML ({err})") from None
    entries = data.get("study")
    if not isinstance(entries, list) or not entries:
        raise ValueError(f"{path.name}: define at least one [[study]] table")
    cases = {}

    def base(name):
        if name is None:
            return base_case
        file = (path.parent / name).resolve()
        if file not in cases:
            cases[file] = _base_case(file, f"{path.name}: base_case")
        return cases[file]

    allowed = {"name", "parameter", "values", "grid", "base_case", "label"}
    studies = []
    for i, entry in enumerate(entries):
        where = f"{path.name}: study[{i}]"
        unknown = sorted(set(entry) - allowed)
        if unknown:
            raise ValueError(f"{where}: unknown key(s) {unknown}; allowed: {sorted(allowed)}")
        if "name" not in entry:
            raise ValueError(f"{where}.name: missing")
        try:
            case = base(entry.get("base_case", data.get("base_case")))
            if "grid" in entry:
                if "parameter" in entry or "values" in entry:
                    raise ValueError("give either grid or parameter and values")
                studies += grid_study(entry["name"], _flatten(entry["grid"]), case,
                                      label=entry.get("label"))
            else:
                for key in ("parameter", "values"):
                    if key not in entry:
                        raise ValueError(f"{key}: missing")
                studies.append(Study(entry["name"], entry["parameter"], entry["values"], case,
                                     label=entry.get("label")))
        except (ValueError, FileNotFoundError) as err:
            raise ValueError(f"{where} ({entry['name']}): {err}") from None
    return studies


def parse_spec(spec: str) -> tuple[str, list]:
    """``"path=v1,v2,v3"`` or ``"path=start:stop:n"`` -> (path, values)."""
    path, sep, rhs = str(spec).partition("=")
    path, rhs = path.strip(), rhs.strip()
    if not sep or not path or not rhs:
        raise ValueError(f"{spec!r}: expected 'path=v1,v2,...' or 'path=start:stop:n'")
    try:
        return path, parse_values(rhs)
    except ValueError as err:
        raise ValueError(f"{spec!r}: {err}") from None


def parse_values(text: str) -> list:
    """``"v1,v2,v3"`` or ``"start:stop:n"`` (n evenly spaced values, ends included)."""
    text = text.strip()
    if ":" in text and "," not in text:
        parts = [p.strip() for p in text.split(":")]
        if len(parts) != 3 or not re.fullmatch(r"\d+", parts[2]) or int(parts[2]) < 1:
            raise ValueError(f"range {text!r}: expected start:stop:n with an integer n >= 1")
        start, stop, n = _scalar(parts[0]), _scalar(parts[1]), int(parts[2])
        if n > MAX_POINTS:
            raise ValueError(f"range {text!r}: {n} points, more than a sweep runs (at most "
                             f"{MAX_POINTS})")
        if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (start, stop)):
            raise ValueError(f"range {text!r}: start and stop must be numbers")
        values = np.linspace(start, stop, n)
        if isinstance(start, int) and isinstance(stop, int) and np.all(values == np.round(values)):
            return [int(v) for v in values]
        return [float(v) for v in values]
    if text.count(",") >= MAX_POINTS:
        raise ValueError(f"{text.count(',') + 1} values, more than a sweep runs (at most "
                         f"{MAX_POINTS})")
    values = [_scalar(p) for p in text.split(",")]
    return values


# ---------------------------------------------------------------- one point

def run_point(task: dict) -> dict:
    """Build, simulate and summarise one point (the picklable work function sent to the
    processes or the Dask workers). ``task``: ``case`` (the case's data dict),
    ``duration`` and ``dt`` (s). Returns the numbers of the CSV row (error text instead
    of an exception when the point fails), the full summary and the wall time."""
    started = time.perf_counter()
    host = socket.gethostname()
    try:
        results, notes = with_warnings(lambda: simulate(
            build(Case(task["case"])), duration=task["duration"], dt=task["dt"],
            progress=False))
        info = summary(results)
    except Exception as err:  # reported in the point's row; the other points go on
        return {"error": _describe(err), "wall_time": time.perf_counter() - started,
                "host": host}
    if info["interrupted"]:
        raise KeyboardInterrupt      # simulate() keeps a Ctrl-C to itself; stop the sweep
    problems = []
    if info.get("stopped"):
        problems.append(f"run stopped at t = {info['simulated_time']:.6g} s: {info['stopped']}")
    amplitude = info.get("amplitude") or {}
    if not amplitude:
        problems.append(f"no steady-state amplitudes: no periodic load, or the run "
                        f"({info['simulated_time']:g} s) is shorter than the case's "
                        f"solver.steady_periods forcing periods")
    row = {name: float(amplitude.get(name, math.nan)) for name in AMPLITUDES}
    steady = info.get("max_tension_steady")
    row["max_tension_steady"] = math.nan if steady is None else float(steady)
    row["error"] = "; ".join(problems)
    return {**row, "summary": info, "notes": notes, "wall_time": time.perf_counter() - started,
            "host": host}


# ---------------------------------------------------------------- the sweep

def run_sweep(studies, out="skmoor-out", *, workers=None, scheduler=None, duration=None,
              dt=None, progress=True) -> list[dict]:
    """Run every point of ``studies`` (a Study or a list of them); returns the rows of
    ``out/sweep.csv`` (dicts with keys :data:`COLUMNS`).

    workers     local processes (default ``os.cpu_count()``); 1 runs the points one
                after another in this process (no subprocess: for debugging)
    scheduler   a Dask scheduler address (``"tcp://host:8786"``) or a
                ``dask.distributed.Client``: run the points on that cluster instead
                (``workers`` is then ignored)
    duration, dt  run settings for every point (s); default: each case's solver settings
    progress    a progress bar of finished points

    Finished points are kept in ``out/sweep-points/`` as they complete and reused by a
    rerun; a failed point gets its error in the ``error`` column (and printed) while
    the others go on. Ends with a summary line giving the wall time."""
    started = time.perf_counter()
    studies = [studies] if isinstance(studies, Study) else list(studies)
    _check_studies(studies, duration, dt)
    total = sum(len(study.values) for study in studies)
    if total > MAX_POINTS:
        raise ValueError(f"studies: {total} points, more than a sweep runs (at most "
                         f"{MAX_POINTS})")
    if workers is not None and not (isinstance(workers, int) and workers >= 1):
        raise ValueError(f"workers: need an integer >= 1, got {workers!r}")
    out = Path(out)
    points_dir = out / "sweep-points"
    points_dir.mkdir(parents=True, exist_ok=True)

    points = [(study, value) for study in studies for value in study.values]
    rows, pending, reused, errors = _plan(points, points_dir, duration, dt)
    _check_long_enough(points, pending)

    from tqdm.auto import tqdm  # (imported here: it pulls in asyncio, ~40 ms)

    bar = tqdm(total=len(points), initial=len(points) - len(pending), unit="point",
               desc="sweep", disable=not progress)
    for row in errors:
        bar.write(_error_line(row))
    failed = len(errors)
    computed, ran, point_time = 0, 0, 0.0
    by_index = {i: (task, key, file) for i, task, key, file in pending}

    def interrupted():
        done = write_csv([row for row in rows if row is not None], out / "sweep.csv")
        print(f"sweep interrupted: {reused + computed} of {len(points)} points are kept in "
              f"{points_dir} (and in {done}); run again to compute the rest", file=sys.stderr)

    outcomes = []  # the runs' results, for their warnings
    with collecting(run_batch(pending, run_point, workers=workers, scheduler=scheduler),
                    bar, interrupted) as finished:
        for i, result in finished:
            outcomes.append(result)
            task, key, file = by_index[i]
            study, value = points[i]
            rows[i] = _row({"study": study.name, "parameter": study.parameter, "value": value},
                           result)
            ran += 1
            point_time += result.get("wall_time") or 0.0
            if rows[i]["error"]:
                failed += 1
                bar.write(_error_line(rows[i]))
            else:
                computed += 1
                _write_json(file, {"key": key, "task": {k: v for k, v in task.items()
                                                        if k != "case"},
                                   "case": task["case"], "result": result})
            bar.update(1)
    say_once(outcomes, len(points), "sweep points")

    csv_path = write_csv(rows, out / "sweep.csv")
    figures = []
    for study in studies:
        figure = _plot(study, [r for r in rows if r["study"] == study.name], out)
        if figure is not None:
            figures.append(figure)
    wall = time.perf_counter() - started
    per_point = f", {point_time / ran:.1f} s per point run" if ran else ""
    print(f"sweep: {len(points)} points in {len(studies)} "
          f"stud{'y' if len(studies) == 1 else 'ies'}: {computed} computed, {reused} reused, "
          f"{failed} failed; wall time {wall:.1f} s{per_point}; wrote {csv_path}"
          + (f" and {len(figures)} figure{'s' * (len(figures) != 1)}" if figures else ""))
    return rows


def _plan(points, points_dir, duration, dt):
    """(rows, pending, reused, errors) of the sweep's points: each point's case built, the
    finished ones read from ``points_dir`` into their rows, the others pending as
    (index, task, key, point file); a point whose case is refused is an error row."""
    rows: list[dict | None] = [None] * len(points)
    pending = []                      # (index, task, key, point file)
    reused = 0
    errors = []
    for i, (study, value) in enumerate(points):
        head = {"study": study.name, "parameter": study.parameter, "value": value}
        try:
            case = study.case(value)
        except Exception as err:
            rows[i] = _row(head, {"error": f"case rejected: {_describe(err)}"})
            errors.append(rows[i])
            continue
        task = {"study": study.name, "parameter": study.parameter, "value": value,
                "fixed": study.fixed, "case": case.data,
                "duration": float(duration if duration is not None else case.solver["duration"]),
                "dt": float(dt if dt is not None else case.solver["dt"]),
                "skmoor": _version()}
        key = hashlib.sha256(json.dumps(task, sort_keys=True, default=_jsonable)
                             .encode()).hexdigest()[:20]
        file = points_dir / f"{_slug(study.name)}-{key}.json"
        kept = _load_point(file, key)
        if kept is not None:
            rows[i] = _row(head, kept["result"])
            reused += 1
        else:
            pending.append((i, task, key, file))
    return rows, pending, reused, errors


def write_csv(rows, path) -> Path:
    """Write sweep rows (dicts with keys :data:`COLUMNS`) as CSV; returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        writer.writeheader()
        for row in rows:
            writer.writerow({k: row.get(k, "") for k in COLUMNS})
    return path


def with_warnings(run):
    """(run(), the warnings it gave as distinct "Category: message" texts): a batch's
    runs keep theirs for :func:`say_once` instead of printing them one run at a time."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        value = run()
    return value, list(dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught))


def say_once(results, total, what):
    """Print each warning of a batch's results (their "notes") once, with the number of
    runs that gave it."""
    said = {}
    for result in results:
        for note in (result or {}).get("notes", ()):
            said[note] = said.get(note, 0) + 1
    for note, count in said.items():
        print(f"{what}: {count} of {total} warned: {note}", file=sys.stderr)


def run_batch(pending, work, *, workers=None, scheduler=None):
    """(index, result) of each pending (index, task, key, file) as ``work(task)``
    finishes: on the Dask cluster ``scheduler``, in this process (``workers=1``), or on
    ``workers`` local processes (default: one per core)."""
    if scheduler is not None:
        return _on_dask(pending, scheduler, work)
    if workers == 1:
        return ((i, work(task)) for i, task, _, _ in pending)
    return _on_processes(pending, min(workers or os.cpu_count() or 1, max(len(pending), 1)),
                         work)


@contextlib.contextmanager
def collecting(finished, bar, interrupted):
    """Gather the results of a batch: the progress bar and the results' iterator closed
    however the loop ends; on Ctrl-C, ``interrupted()`` says what is kept, then it goes
    on up."""
    try:
        yield finished
    except KeyboardInterrupt:
        bar.close()
        interrupted()
        raise
    finally:
        bar.close()
        if hasattr(finished, "close"):
            finished.close()


def _on_processes(pending, workers, work=None):
    """(index, result) of each pending point as it finishes, on local processes;
    ``work(task)`` runs a point (default :func:`run_point`)."""
    work = work or run_point
    if not pending:
        return
    # JAX (user forms) runs threads: forking a process that imported it may deadlock, so
    # its workers come from a fresh fork server instead
    context = multiprocessing.get_context("forkserver") if "jax" in sys.modules else None
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=context)
    complete = False
    try:
        futures = {pool.submit(work, task): i for i, task, _, _ in pending}
        for future in as_completed(futures):
            try:
                result = future.result()
            except Exception as err:  # a worker process died (BrokenProcessPool) ...
                result = {"error": _describe(err)}
            yield futures[future], result
        complete = True
    finally:
        pool.shutdown(wait=complete, cancel_futures=not complete)


def _on_dask(pending, scheduler, work=None):
    """(index, result) of each pending point as it finishes, on a Dask cluster;
    ``work(task)`` runs a point (default :func:`run_point`)."""
    work = work or run_point
    if not pending:
        return
    try:
        from dask.distributed import Client
        from dask.distributed import as_completed as dask_completed
    except ImportError:
        raise ImportError("scheduler= needs dask.distributed: "
                          "pip install 'dask[distributed]'") from None
    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    futures, complete = {}, False
    try:
        # a worker that cannot import skmoor answers with its error; one that is lost
        # meanwhile (its comm closed) is left to the scheduler, which moves its work
        versions = client.run(_worker_version, on_error="return")
        broken = {addr: v for addr, v in versions.items() if isinstance(v, ImportError)}
        if broken or not any(isinstance(v, str) for v in versions.values()):
            err = next(iter(broken.values()), None) or next(iter(versions.values()), None)
            why = "no workers" if err is None else _describe(err)
            raise RuntimeError(f"the Dask workers cannot run skmoor ({why}); install "
                               "skmoor on every worker")
        other = {addr: v for addr, v in versions.items()
                 if isinstance(v, str) and v != _version()}
        if other:
            print(f"sweep: warning: workers run other skmoor versions than {_version()}: "
                  f"{other}", file=sys.stderr)
        futures = {client.submit(work, task, key=f"skmoor-point-{key}"): i
                   for i, task, key, _ in pending}
        for future in dask_completed(futures):
            try:
                result = future.result()
            except Exception as err:  # e.g. KilledWorker
                result = {"error": _describe(err)}
            yield futures[future], result
            future.release()
        complete = True
    finally:
        if futures and not complete:
            client.cancel(list(futures))
        if own:
            client.close()


def _worker_version():
    return _version()


# ---------------------------------------------------------------- figures

def _plot(study, rows, out):
    good = [r for r in rows if not r["error"]
            and isinstance(r["value"], (int, float)) and not isinstance(r["value"], bool)
            and all(math.isfinite(r[k]) for k in (*AMPLITUDES, "max_tension_steady"))]
    if not good:
        return None
    from ..post.plots import plot_study
    title = study.name + (" (" + ", ".join(f"{p.rsplit('.', 1)[-1]} = {_short(v)}"
                                          for p, v in study.fixed.items()) + ")"
                          if study.fixed else "")
    try:
        return plot_study(good, out / f"sweep-{_slug(study.name)}.png", study.label,
                          title=title)
    except Exception as err:  # a figure is not worth losing the sweep for
        print(f"sweep: warning: no figure for study {study.name!r}: {_describe(err)}",
              file=sys.stderr)
        return None


# ---------------------------------------------------------------- helpers

def _base_case(file, where):
    """The Case of a base case file; a MoorDyn deck is refused naming it (a sweep varies a
    case file's values)."""
    from ..io.deck import is_deck

    if is_deck(file):
        raise ValueError(f"{where} {file}: is a MoorDyn deck, not a case file (a sweep "
                         "varies the values of a case file, .toml)")
    return Case.from_toml(file)


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _check_numbers(case, path, values, study):
    """Refuse a value that is not a number where the base case has a number."""
    node = case.data
    for key in path.split("."):
        if isinstance(node, list) and key.lstrip("-").isdigit() and -len(node) <= int(key) < len(node):
            node = node[int(key)]
        elif isinstance(node, dict) and key in node:
            node = node[key]
        else:
            node = PAPER_CASE.get("solver", {}).get(key) if path == f"solver.{key}" else None
            break
    if not _is_number(node):
        return
    for v in values:
        if not _is_number(v):
            raise ValueError(f"study {study!r}: parameter {path!r}: value {v!r} is not a "
                             f"number (the base case has {node!r})")


def _check_long_enough(points, pending):
    """Refuse, before any point runs, a sweep whose runs are too short for steady-state
    amplitudes (the last solver.steady_periods forcing periods)."""
    for i, task, _, _ in pending:
        case = task["case"]
        omega = (case.get("load") or {}).get("omega")
        if not omega:
            continue
        periods = int(case.get("solver", {}).get("steady_periods", 5))
        need = periods * 2 * math.pi / float(omega)
        if task["duration"] < need:
            study, value = points[i]
            raise ValueError(f"duration: {task['duration']:g} s is shorter than "
                             f"solver.steady_periods = {periods} forcing periods "
                             f"({need:.4g} s) of point {study.name} {study.parameter} = "
                             f"{value!r}: no steady-state amplitudes (a longer --duration, "
                             "or fewer steady_periods)")


def _check_studies(studies, duration, dt):
    if not studies:
        raise ValueError("studies: give at least one Study")
    for study in studies:
        if not isinstance(study, Study):
            raise TypeError(f"studies: expected Study objects, got {type(study).__name__}")
    names = [s.name for s in studies]
    slugs = [_slug(n) for n in names]
    for seen in (names, slugs):
        dup = sorted({n for n in seen if seen.count(n) > 1})
        if dup:
            raise ValueError(f"studies: names must be distinct (also as file names), "
                             f"repeated: {dup}")
    for name, value in (("duration", duration), ("dt", dt)):
        if value is not None and not (isinstance(value, (int, float)) and value > 0):
            raise ValueError(f"{name}: must be a positive number of seconds, got {value!r}")
        if value is not None:
            for study in studies:
                if f"solver.{name}" in (study.parameter, *study.fixed):
                    raise ValueError(f"study {study.name!r} varies solver.{name}; do not "
                                     f"also pass {name}= to run_sweep")


def _check_path(case, path, study):
    """Refuse a path whose first missing key looks like a typo of an existing one."""
    node, keys = case.data, path.split(".")
    for depth, key in enumerate(keys):
        if isinstance(node, list):
            if not (key.lstrip("-").isdigit() and -len(node) <= int(key) < len(node)):
                raise ValueError(f"study {study!r}: parameter {path!r}: "
                                 f"{'.'.join(keys[:depth]) or 'case'} has {len(node)} entries, "
                                 f"{key!r} is not an index of one")
            node = node[int(key)]
        elif isinstance(node, dict):
            if key not in node:
                known = list(node) + (list(PAPER_CASE["solver"]) if keys[:depth] == ["solver"]
                                      else [])
                if key in known:
                    return
                close = difflib.get_close_matches(key, [str(k) for k in known], n=1)
                if close:
                    raise ValueError(f"study {study!r}: parameter {path!r} is not in the base "
                                     f"case; did you mean "
                                     f"{'.'.join(keys[:depth] + close)!r}?")
                return                # a new key: the case's validation will judge it
            node = node[key]
        else:
            raise ValueError(f"study {study!r}: parameter {path!r}: "
                             f"{'.'.join(keys[:depth])} is a value, not a table")


def _row(head, result):
    row = {**head}
    for name in (*AMPLITUDES, "max_tension_steady"):
        row[name] = float(result.get(name, math.nan))
    row["error"] = result.get("error") or ""
    return row


def _error_line(row):
    return (f"sweep: point {row['study']} {row['parameter']} = {row['value']!r} "
            f"failed: {row['error']}")


def _load_point(file, key):
    try:
        record = json.loads(file.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(record, dict) or record.get("key") != key or "result" not in record:
        return None
    return record


def _write_json(file, record):
    tmp = file.with_name(f".{file.name}.{os.getpid()}.tmp")
    tmp.write_text(json.dumps(record, indent=1, default=_jsonable))
    os.replace(tmp, file)


def _scalar(text):
    text = text.strip()
    if not text:
        raise ValueError("empty value")
    if re.fullmatch(r"[+-]?\d+", text):
        return int(text)
    try:
        return float(text)
    except ValueError:
        pass
    if re.fullmatch(r"[+-]?\d+\s*/\s*\d+", text):
        return float(Fraction(text.replace(" ", "")))
    if text.lower() in ("true", "false"):
        return text.lower() == "true"
    return text.strip("'\"")


def _plain(v):
    """Numpy scalars to Python numbers (JSON, TOML-like case data)."""
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, np.ndarray):
        return v.tolist()
    return v


def _flatten(table, prefix=""):
    """{"mooring": {"sag_ratio": [...]}} -> {"mooring.sag_ratio": [...]} (TOML dotted keys)."""
    flat = {}
    for key, value in table.items():
        path = f"{prefix}{key}"
        if isinstance(value, dict):
            flat.update(_flatten(value, path + "."))
        else:
            flat[path] = value
    return flat


def _short(v):
    return f"{v:.6g}" if isinstance(v, float) else str(v)


def _slug(name):
    return re.sub(r"[^A-Za-z0-9._-]+", "_", name).strip("_") or "study"


def _describe(err):
    return f"{type(err).__name__}: {err}"


def _version():
    import skmoor
    return skmoor.__version__


def _jsonable(x):
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, np.generic):
        return x.item()
    return str(x)
