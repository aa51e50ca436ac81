"""What a run writes: the summary, the time-series table, the results file and the plots,
into an output folder checked before the run and kept when the run is interrupted.
"""
from __future__ import annotations

import contextlib
import dataclasses
import json
import os
import time
import zipfile
from pathlib import Path

import numpy as np

from ..post.fatigue import fatigue
from ..post.results import BODY_DOFS, Results
from ..post.strength import strength

# what a run writes into its output folder (a reused folder is cleared of these first)
OUTPUTS = ("results.npz", "summary.json", "timeseries.csv", "time_histories.png",
           "snapshot.png", "animation.mp4", "animation.gif", "lines.xdmf", "lines.h5",
           "motion.pvd", "strength.png", "fatigue.json", "results.nc", "render.log")


def summary(results: Results) -> dict:
    """The run's key numbers (SI, angles in rad), as written to ``summary.json``:
    ``fairlead_tension_static`` is the FE static state's (end B of each line);
    ``fairlead_tension_catenary`` the analytic catenary's where one exists (else null);
    ``strength`` each line's largest tension, MBL, safety factor and utilisation
    (:func:`skmoor.post.strength.strength`); ``fatigue`` each line's damage at its
    fairlead on its type's curve and the DELs for m = 3 and 5 at 1 Hz
    (:func:`skmoor.post.fatigue.fatigue`); ``line_failures`` the releases of the run
    (point, lines, trigger, time s, tension N; :mod:`skmoor.run.failures`)."""
    meta = results.meta
    period = meta.get("forcing_period")
    n = int(meta.get("steady_periods", 5))
    amplitude, steady_max = {}, None
    if period and results.t[-1] - results.t[0] >= n * period:
        if meta.get("has_body", True):
            amplitude = {name: results.amplitude(results.body_series(name), period, n)
                         for name in ("surge", "heave", "pitch")}
        steady_max = float(results.max_tension[results.t >= results.t[-1] - n * period].max())
    return {"case": meta.get("case"), "draft": meta.get("draft"),
            "fairlead_tension_static": meta.get("fairlead_tension_static"),
            "anchor_tension_static": meta.get("anchor_tension_static"),
            "fairlead_tension_catenary": meta.get("fairlead_tension_catenary"),
            "line_names": list(results.line_names), "body_names": list(results.body_names),
            "natural_periods": meta.get("natural_periods"), "amplitude": amplitude,
            "max_tension": _largest(results.max_tension, results.fairlead_tension,
                                    results.anchor_tension),
            "max_tension_steady": steady_max,
            "wall_time": meta.get("wall_time"), "simulated_time": float(results.t[-1]),
            "steps": meta.get("steps"), "steps_planned": meta.get("steps_planned"),
            "subdivided_steps": meta.get("subdivided_steps", 0),
            "dt": meta.get("dt"), "stopped": meta.get("stopped"),
            "interrupted": bool(meta.get("interrupted")), "notes": meta.get("notes", []),
            **({"line_failures": meta["line_failures"]} if "line_failures" in meta else {}),
            **({"max_curvature": results.line_maxima("curvature"),
                "max_bending_moment": results.line_maxima("bending_moment")}
               if results.bending else {}),
            "strength": strength(results) if results.line_names else {},
            "fatigue": _fatigue_summary(results)}


def _fatigue_summary(results) -> dict:
    """The fatigue at each line's fairlead (end B) on its line type's curve over the run
    (:func:`skmoor.post.fatigue.fatigue` with ``where="fairlead"``; ``skmoor fatigue``
    gives every element's); {} for a static state or without lines."""
    if not results.line_names or len(results.t) < 2 or results.t[-1] <= results.t[0]:
        return {}
    try:
        report = fatigue(results, where="fairlead")
    except ValueError as err:  # e.g. a history that is not finite: the summary still goes out
        return {"where": "fairlead", "note": f"no fatigue: {err}"}
    return {"where": "fairlead", "duration": report["duration"], "f_eq": report["f_eq"],
            "lines": report["lines"]}


def _largest(*arrays) -> float:
    """The largest of the tensions (N): the elements' and the line ends' (an end's tension,
    from its reaction, can exceed every element's)."""
    values = [np.max(a) for a in arrays if a is not None and np.size(a)]
    return float(max(values)) if values else 0.0


def _timeseries_header(body_names, line_names, free_names) -> list:
    header = ["t"] + [f"{b}.{dof}" for b in body_names for dof in BODY_DOFS]
    header += ["max_tension"] + [f"fairlead_tension_{n}" for n in line_names]
    header += [f"anchor_tension_{n}" for n in line_names]
    return header + [f"{name}.{c}" for name in free_names for c in "xyz"]


def _timeseries_table(t, bodies, max_tension, fair, anchor, free_displacement):
    nt = len(t)
    return np.column_stack([t, np.reshape(bodies, (nt, -1)), max_tension, fair, anchor,
                            np.reshape(free_displacement, (nt, -1))])


def _write_rows(path, table, header=None):
    with open(path, "a") as f:
        if header is not None:
            f.write(",".join(header) + "\n")
        np.savetxt(f, table, delimiter=",", fmt="%.9g")
        f.flush()


def write_outputs(results: Results, out) -> dict:
    """Write results.npz, results.nc (the same as netCDF, :meth:`Results.to_netcdf`),
    summary.json and timeseries.csv into folder ``out``.

    timeseries.csv columns: t; for each body its six DOFs ``NAME.surge`` ... ``NAME.yaw``
    (m, rad); max_tension (the largest element tension at that time, N);
    ``fairlead_tension_LINE`` (end B) and ``anchor_tension_LINE`` (end A) of each line (N);
    ``NAME.x``, ``NAME.y``, ``NAME.z`` displacements of each free point (m)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    results.save(out / "results.npz")
    results.to_netcdf(out / "results.nc")
    info = summary(results)
    (out / "summary.json").write_text(json.dumps(info, indent=2))
    kinds = results.meta.get("point_kinds", [])
    free = [k for k, kind in enumerate(kinds) if kind == "free"]
    header = _timeseries_header(results.body_names, results.line_names,
                                [results.point_names[k] for k in free])
    table = _timeseries_table(results.t, results.bodies, results.max_tension,
                              results.fairlead_tension, results.anchor_tension,
                              results.point_displacement[:, free])
    (out / "timeseries.csv").unlink(missing_ok=True)
    _write_rows(out / "timeseries.csv", table, header)
    return info


def prepare_output(out) -> Path:
    """Check that ``out`` is, or can be made, a folder skmoor can write into (before any
    solve: ValueError with the reason), and clear a previous run's files from it."""
    out = Path(out)
    for path in (out, *out.parents):
        if path.exists() and not path.is_dir():
            raise ValueError(f"output folder {out}: {path} is a file, not a folder")
    try:
        out.mkdir(parents=True, exist_ok=True)
        probe = out / f".skmoor-write-test-{os.getpid()}"
        probe.write_text("")
        probe.unlink()
    except OSError as err:
        raise ValueError(f"output folder {out}: cannot write there "
                         f"({err.strerror or err})") from None
    for name in OUTPUTS:
        (out / name).unlink(missing_ok=True)
    if (out / "motion").is_dir():
        for frame in (out / "motion").glob("*.vtu"):
            frame.unlink()
    return out


LOCK = ".skmoor-lock"


def _alive(pid) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True  # another user's process
    return True


@contextlib.contextmanager
def output_lock(out):
    """Hold ``out``'s lock file (the process id) while a run writes there: a second run
    into the same folder while the first is going is refused (ValueError naming the
    process); a lock left by a process that no longer runs is taken over."""
    out = Path(out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError:
        yield  # prepare_output says why the folder cannot be written
        return
    lock = out / LOCK
    for _ in range(2):
        try:
            fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
        except FileExistsError:
            try:
                pid = int(lock.read_text().strip() or 0)
            except (OSError, ValueError):
                pid = 0
            if pid and pid != os.getpid() and _alive(pid):
                raise ValueError(f"output folder {out}: another skmoor run (process {pid}) "
                                 "is writing there; give another --out, or wait for it to "
                                 "finish") from None
            lock.unlink(missing_ok=True)  # left by a run that ended without removing it
            continue
        except OSError:
            yield  # read-only: prepare_output says so
            return
        with os.fdopen(fd, "w") as f:
            f.write(str(os.getpid()))
        break
    try:
        yield
    finally:
        with contextlib.suppress(OSError, ValueError):
            if int(lock.read_text().strip() or 0) == os.getpid():
                lock.unlink()


def load_results(out) -> Results:
    """The Results in the folder ``out`` of a previous run (results.npz, else
    results.nc), or a one-line ValueError saying why not: not a folder, no results, a
    truncated file or one without an array, displacements that are not finite (a run
    that diverged)."""
    out = Path(out)
    if not out.exists():
        raise FileNotFoundError(f"folder {out} does not exist")
    if not out.is_dir():
        raise ValueError(f"{out}: is a file, not the output folder of a run (give the "
                         "folder that holds results.npz)")
    path = out / "results.npz"
    if not path.is_file():
        netcdf = out / "results.nc"
        if not netcdf.is_file():
            raise ValueError(f"{out}: has no results.npz or results.nc (not the output "
                             "folder of a run)")
        return _finite(_read_netcdf(netcdf), netcdf)
    required = [f.name for f in dataclasses.fields(Results)
                if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]
    try:
        with np.load(path, allow_pickle=False) as data:
            missing = [name for name in required if name not in data.files]
        if missing:
            raise ValueError(f"{path}: lacks the array{'s' * (len(missing) > 1)} "
                             f"{', '.join(missing)} (not a results file of this skmoor)")
        results = Results.load(path)
    except (zipfile.BadZipFile, EOFError, KeyError, TypeError, OSError, ValueError) as err:
        if isinstance(err, ValueError) and str(err).startswith(str(path)):
            raise
        raise ValueError(f"{path}: truncated or not a results file "
                         f"({type(err).__name__}: {' '.join(str(err).split())})") from None
    return _finite(results, path)


def _read_netcdf(path) -> Results:
    """Results from a results.nc, or a one-line ValueError."""
    try:
        return Results.load(path)
    except Exception as err:  # h5netcdf / xarray raise many kinds on a damaged file
        raise ValueError(f"{path}: truncated or not a results file "
                         f"({type(err).__name__}: {' '.join(str(err).split())})") from None


def _finite(results, path) -> Results:
    """results, or a one-line ValueError when its motion is not finite (a diverged run)."""
    for name in ("displacement", "bodies", "point_displacement"):
        values = getattr(results, name, None)
        if values is None or np.size(values) == 0:
            continue
        values = np.asarray(values, float)
        bad = ~np.isfinite(values.reshape(len(values), -1)).all(axis=1)
        if np.any(bad):
            k = int(np.argmax(bad))
            raise ValueError(f"{path}: {name} is not finite (NaN or inf) from t = "
                             f"{float(results.t[k]):.6g} s on (the run diverged): nothing "
                             "to draw")
    return results


class OutputWriter:
    """A run's outputs written as it goes: timeseries.csv gains its new rows every
    ``chunk`` samples; results.npz and summary.json are rewritten every ``checkpoint`` s
    of wall time and at the end (so a crash or a full disk loses at most that)."""

    def __init__(self, folder, recorder, meta, chunk=50, checkpoint=30.0):
        self.folder, self.recorder, self.meta = Path(folder), recorder, meta
        self.chunk, self.checkpoint = chunk, checkpoint
        network = recorder.model.network
        self.free = [k for k, p in enumerate(network.points) if p.kind == "free"]
        self.header = _timeseries_header([b.name for b in network.bodies],
                                         [ln.name for ln in network.lines],
                                         [network.points[k].name for k in self.free])
        self.written, self.saved = 0, time.perf_counter()

    def record(self, state):
        self.recorder.record(state)
        if len(self.recorder.rows["t"]) - self.written >= self.chunk:
            self._append()
            if time.perf_counter() - self.saved > self.checkpoint:
                self._save(self.recorder.results(self.meta))

    def _append(self):
        rows, start = self.recorder.rows, self.written
        if len(rows["t"]) == start:
            return
        points = np.array(rows["points"][start:]).reshape(len(rows["t"]) - start, -1, 3)
        tension = rows["tension"][start:]  # no lines: no tension, 0
        table = _timeseries_table(np.array(rows["t"][start:]), np.array(rows["bodies"][start:]),
                                  np.array([np.max(x) if len(x) else 0.0 for x in tension]),
                                  np.array(rows["fair"][start:]), np.array(rows["anchor"][start:]),
                                  points[:, self.free])
        _write_rows(self.folder / "timeseries.csv", table, self.header if start == 0 else None)
        self.written = len(rows["t"])

    def _save(self, results):
        results.save(self.folder / "results.npz")
        (self.folder / "summary.json").write_text(json.dumps(summary(results), indent=2))
        self.saved = time.perf_counter()

    def finish(self, results):
        """The last rows, the final results.npz and summary.json, and results.nc."""
        self._append()
        self._save(results)
        results.to_netcdf(self.folder / "results.nc")
