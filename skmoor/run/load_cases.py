"""Design-load-case matrices: the sea states of a scatter diagram x wave headings x seeds x
conditions (intact, or damaged by line failures), each one run of a base case, on local
processes or a Dask cluster, gathered into one labelled dataset.

    from skmoor.run.load_cases import LoadCaseMatrix, SeaState, run_load_cases
    matrix = LoadCaseMatrix([SeaState(2.0, 8.0, 0.6), SeaState(4.0, 10.0, 0.4)],
                            headings_deg=[0, 45], seeds=[1, 2])
    data = run_load_cases(matrix, out="skmoor-out")        # or scheduler="tcp://host:8786"

or from a study file (``skmoor loadcases FILE``, :meth:`LoadCaseMatrix.from_toml`)::

    [load_cases]
    case = "my_case.toml"        # the base case, beside this file (default: the paper's)
    headings_deg = [0, 45, 90]
    seeds = [1, 2, 3]
    transient = 100.0            # s left out of the statistics
    design_life = 25.0           # years
    duration = 1200.0            # s (default: the case's)
    sea_states = [{Hs = 2.0, Tp = 8.0, probability = 0.6},
                  {Hs = 4.0, Tp = 10.0, probability = 0.4}]
    conditions = [{name = "intact"},
                  {name = "C1 broken", failures = [{point = "C1.fairlead", lines = ["C1"], time = 0.0}]}]

Each case is the base case with ``sea.waves`` one JONSWAP wave (Hs, Tp, gamma, heading,
seed) and, for a damaged condition, its ``failures``. Each finished case is kept in
``out/load-cases/`` (named by a hash of its case and settings), so a rerun after Ctrl-C, a
crash or a lost worker computes only the cases without a file; a failed case gets its error
and the others go on. Written: ``load_cases.nc`` (netCDF, :func:`xarray.open_dataset`) and
``load_cases.csv`` (a row per case and line).

The dataset: dimensions sea_state, heading, seed, condition, line; per case and line the
largest tension (N) and the safety factor over the window after ``transient``, the fatigue
damage per year at the fairlead (Miner, rainflow over the window, scaled by a year over the
window) and the damage-equivalent load ranges (N, m = 3 and 5, 1 Hz); over the seeds the
mean, the largest and the standard deviation of the largest tension; per condition and
line the lifetime damage ``design_life sum_s sum_h p_s w_h mean_seeds(damage per year)``,
p_s the sea states' probabilities (shares of the time), w_h the headings' (equal unless
given).
"""
from __future__ import annotations

import csv
import hashlib
import json
import math
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

import numpy as np

from ..io.case import Case, paper_case
from ..io.paths import resolve_inside
from ..model.model import build
from ..post.fatigue import fatigue
from ..post.strength import strength
from . import sweep
from .simulate import simulate

MAX_CASES = 100_000
DEL_EXPONENTS = (3.0, 5.0)
# per case and line: (units, long name)
CASE_VALUES = {"max_tension": ("N", "largest tension after the transient"),
               "safety_factor": ("1", "MBL / largest tension"),
               "damage_per_year": ("1/year", "fairlead fatigue damage per year (Miner)"),
               **{f"DEL_m{m:g}": ("N", f"damage-equivalent load range, m = {m:g}, 1 Hz")
                  for m in DEL_EXPONENTS}}

__all__ = ["SeaState", "Condition", "LoadCaseMatrix", "run_load_cases", "run_load_case",
           "lifetime_damage"]


@dataclass
class SeaState:
    """A cell of the scatter diagram: significant height Hs (m), peak period Tp (s), the
    share of the time it holds (``probability``, 0-1) and the JONSWAP peak factor."""

    Hs: float
    Tp: float
    probability: float
    gamma: float = 3.3

    def __post_init__(self):
        for name in ("Hs", "Tp", "gamma"):
            value = getattr(self, name)
            if not (_is_number(value) and value > 0):
                raise ValueError(f"sea_states: {name} must be a number > 0, got {value!r}")
        if not (_is_number(self.probability) and 0 <= self.probability <= 1):
            raise ValueError(f"sea_states: probability must lie in [0, 1], got "
                             f"{self.probability!r}")


@dataclass
class Condition:
    """A condition of the mooring: ``name`` and the line failures of the case file's
    ``[[failures]]`` tables (none: intact)."""

    name: str
    failures: list = field(default_factory=list)


@dataclass
class LoadCaseMatrix:
    """Sea states x headings (deg) x seeds x conditions of one base case (default: the
    paper's). heading_probabilities: the headings' shares (default equal); transient: s
    left out of the statistics; design_life: years of the lifetime damage; n_components:
    the JONSWAP waves' components (default: the case schema's)."""

    sea_states: list
    headings_deg: list = field(default_factory=lambda: [0.0])
    seeds: list = field(default_factory=lambda: [1])
    conditions: list = field(default_factory=lambda: [Condition("intact")])
    base_case: Case | None = None
    heading_probabilities: list | None = None
    transient: float = 0.0
    design_life: float = 25.0
    n_components: int | None = None

    def __post_init__(self):
        self.sea_states = [s if isinstance(s, SeaState) else SeaState(**_table(s, "sea_states"))
                           for s in _list(self.sea_states, "sea_states")]
        self.conditions = [c if isinstance(c, Condition) else Condition(**_table(c, "conditions"))
                           for c in _list(self.conditions, "conditions")]
        self.headings_deg = [float(h) for h in _numbers(self.headings_deg, "headings_deg")]
        self.seeds = list(_list(self.seeds, "seeds"))
        if not all(isinstance(s, int) and not isinstance(s, bool) and s >= 0 for s in self.seeds):
            raise ValueError(f"seeds: integers >= 0, got {self.seeds!r}")
        names = [c.name for c in self.conditions]
        if len(set(names)) != len(names):
            raise ValueError(f"conditions: the names must differ, got {names}")
        if len(set(self.headings_deg)) != len(self.headings_deg) or len(set(self.seeds)) != len(self.seeds):
            raise ValueError("headings_deg, seeds: each value once")
        total = sum(s.probability for s in self.sea_states)
        if total > 1 + 1e-9:
            raise ValueError(f"sea_states: the probabilities add up to {total:.6g} > 1")
        if self.heading_probabilities is None:
            self.heading_probabilities = [1.0 / len(self.headings_deg)] * len(self.headings_deg)
        weights = _numbers(self.heading_probabilities, "heading_probabilities")
        if len(weights) != len(self.headings_deg) or abs(sum(weights) - 1) > 1e-9 or min(weights) < 0:
            raise ValueError("heading_probabilities: one share >= 0 per heading, adding up to 1")
        for name in ("transient", "design_life"):
            if not (_is_number(getattr(self, name)) and getattr(self, name) >= 0):
                raise ValueError(f"{name}: a number >= 0, got {getattr(self, name)!r}")
        if self.size > MAX_CASES:
            raise ValueError(f"load cases: {self.size} cases, more than a matrix runs (at most "
                             f"{MAX_CASES})")
        self.base_case = self.base_case or paper_case()

    @property
    def shape(self) -> tuple:
        return (len(self.sea_states), len(self.headings_deg), len(self.seeds),
                len(self.conditions))

    @property
    def size(self) -> int:
        return math.prod(self.shape)

    def cases(self):
        """(index (i, j, k, l), Case) of every case: the base case with its wave (and the
        condition's failures); a case the schema refuses raises, naming the case."""
        for index in np.ndindex(*self.shape):
            i, j, k, c = index
            s, condition = self.sea_states[i], self.conditions[c]
            wave = {"type": "jonswap", "Hs": s.Hs, "Tp": s.Tp, "gamma": s.gamma,
                    "heading_deg": self.headings_deg[j], "seed": self.seeds[k]}
            if self.n_components is not None:
                wave["n_components"] = self.n_components
            sea = dict(self.base_case.data.get("sea") or {}, waves=[wave])
            try:  # each replace checks the case against the schema
                case = self.base_case.replace("sea", sea)
                if condition.failures:
                    case = case.replace("failures", list(condition.failures))
            except ValueError as err:
                raise ValueError(f"load case (Hs {s.Hs}, Tp {s.Tp}, heading "
                                 f"{self.headings_deg[j]}, seed {self.seeds[k]}, "
                                 f"{condition.name}): {err}") from None
            yield index, case

    @classmethod
    def from_toml(cls, path) -> tuple[LoadCaseMatrix, dict]:
        """(matrix, run settings {duration, dt}) from the ``[load_cases]`` table of a TOML
        file; ``case`` is read beside the file."""
        path = Path(path)
        try:
            with open(path, "rb") as f:
                data = tomllib.load(f)
        except FileNotFoundError:
            raise ValueError(f"load cases: no such file {path}") from None
        except tomllib.TOMLDecodeError as err:
            raise ValueError(f"{path.name}: not valid TOML ({err})") from None
        table = dict(data.get("load_cases") or {})
        if not table:
            raise ValueError(f"{path.name}: no [load_cases] table")
        settings = {k: table.pop(k) for k in ("duration", "dt") if k in table}
        for key, value in settings.items():
            if not (_is_number(value) and value > 0):
                raise ValueError(f"{path.name}: load_cases.{key} must be a number > 0, got "
                                 f"{value!r}")
        case_file = table.pop("case", None)
        base = paper_case() if case_file is None else Case.from_toml(
            resolve_inside(case_file, path.parent, f"{path.name}: load_cases.case"))
        known = set(cls.__dataclass_fields__) - {"base_case"}
        unknown = sorted(set(table) - known)
        if unknown:
            raise ValueError(f"{path.name}: load_cases.{unknown[0]}: unknown key (known: "
                             f"case, duration, dt, {', '.join(sorted(known))})")
        if "sea_states" not in table:
            raise ValueError(f"{path.name}: load_cases.sea_states: missing (a list of "
                             "{Hs, Tp, probability})")
        try:
            return cls(base_case=base, **table), settings
        except (TypeError, ValueError) as err:
            raise ValueError(f"{path.name}: {err}") from None


def run_load_case(task: dict) -> dict:
    """Build, simulate and reduce one case (the work sent to the processes or workers):
    per line the largest tension, the safety factor, the fairlead's damage per year and
    DELs over the window after ``transient``; an error text instead of an exception."""
    started = time.perf_counter()
    try:
        results, notes = sweep.with_warnings(lambda: simulate(  # said once for the matrix
            build(Case(task["case"])), duration=task["duration"], dt=task["dt"],
            progress=False))
        if results.meta.get("interrupted"):
            raise KeyboardInterrupt
        start = min(task["transient"], float(results.t[-1]))
        peaks = strength(results, start=start)
        tired = fatigue(results, m=DEL_EXPONENTS, start=start, where="fairlead")["lines"]
    except KeyboardInterrupt:
        raise
    except Exception as err:  # reported in the case's row; the other cases go on
        return {"error": sweep._describe(err), "wall_time": time.perf_counter() - started}
    lines = {name: {"max_tension": peaks[name]["max_tension"],
                    "safety_factor": peaks[name]["safety_factor"],
                    "damage_per_year": tired[name]["damage_per_year"],
                    **{f"DEL_m{m:g}": tired[name]["DEL"][f"{m:g}"] for m in DEL_EXPONENTS}}
             for name in results.line_names if name in peaks}
    stopped = results.meta.get("stopped")
    return {"lines": lines, "error": f"stopped: {stopped}" if stopped else "",
            "line_failures": results.meta.get("line_failures", []), "notes": notes,
            "wall_time": time.perf_counter() - started}


def run_load_cases(matrix: LoadCaseMatrix, out="skmoor-out", *, workers=None, scheduler=None,
                   duration=None, dt=None, progress=True):
    """Run every case of ``matrix`` (kept cases reused) and return the dataset (an
    :class:`xarray.Dataset`), also written to ``out/load_cases.nc`` and ``.csv``."""
    if workers is not None and not (isinstance(workers, int) and workers >= 1):
        raise ValueError(f"workers: need an integer >= 1, got {workers!r}")
    for name, value in (("duration", duration), ("dt", dt)):
        if value is not None and not (_is_number(value) and value > 0):
            raise ValueError(f"{name}: a number > 0 (s), got {value!r}")
    started = time.perf_counter()
    out = Path(out)
    kept_dir = out / "load-cases"
    kept_dir.mkdir(parents=True, exist_ok=True)
    results, pending = {}, []
    for index, case in matrix.cases():
        task = {"case": case.data,
                "duration": float(duration or case.solver["duration"]),
                "dt": float(dt or case.solver["dt"]),
                "transient": float(matrix.transient), "skmoor": sweep._version()}
        if task["transient"] >= task["duration"]:
            raise ValueError(f"transient ({matrix.transient} s) leaves nothing of the "
                             f"{task['duration']} s runs")
        key = hashlib.sha256(json.dumps(task, sort_keys=True, default=sweep._jsonable)
                             .encode()).hexdigest()[:20]
        file = kept_dir / f"case-{key}.json"
        kept = sweep._load_point(file, key)
        if kept is not None:
            results[index] = kept["result"]
        else:
            pending.append((index, task, key, file))
    reused = len(results)

    from tqdm.auto import tqdm

    bar = tqdm(total=matrix.size, initial=reused, unit="case", desc="load cases",
               disable=not progress)
    numbered = [(n, task, key, file) for n, (_, task, key, file) in enumerate(pending)]
    failed = 0

    def interrupted():
        print(f"load cases interrupted: {len(results) - failed} of {matrix.size} cases are "
              f"kept in {kept_dir}; run again to compute the rest", file=sys.stderr)

    batch = sweep.run_batch(numbered, run_load_case, workers=workers, scheduler=scheduler)
    with sweep.collecting(batch, bar, interrupted) as finished:
        for n, result in finished:
            index, task, key, file = pending[n]
            results[index] = result
            if result.get("error"):
                failed += 1
                bar.write(f"load case {_label(matrix, index)}: {result['error']}")
            else:
                sweep._write_json(file, {"key": key, "case": task["case"], "result": result})
            bar.update(1)
    sweep.say_once(results.values(), matrix.size, "load cases")
    data = dataset(matrix, results)
    data.to_netcdf(out / "load_cases.nc", engine="h5netcdf")
    _write_csv(data, out / "load_cases.csv")
    print(f"load cases: {matrix.size} ({' x '.join(map(str, matrix.shape))}): "
          f"{len(pending) - failed} computed, {reused} reused, {failed} failed; wall time "
          f"{time.perf_counter() - started:.1f} s; wrote {out / 'load_cases.nc'}")
    return data


def dataset(matrix: LoadCaseMatrix, results: dict):
    """The labelled dataset of the cases' results {index: run_load_case's result}."""
    import xarray as xr

    names = []  # the lines in the order of the first case that has them
    for index in sorted(results):
        names += [n for n in results[index].get("lines") or {} if n not in names]
    shape = matrix.shape + (len(names),)
    values = {k: np.full(shape, np.nan) for k in CASE_VALUES}
    errors = np.full(matrix.shape, "", dtype=object)
    for index, result in results.items():
        errors[index] = result.get("error") or ""
        for j, name in enumerate(names):
            row = (result.get("lines") or {}).get(name)
            for k in CASE_VALUES:
                if row is not None and row.get(k) is not None:
                    values[k][index + (j,)] = row[k]
    dims = ("sea_state", "heading", "seed", "condition", "line")
    data = xr.Dataset(
        {k: (dims, v, {"units": CASE_VALUES[k][0], "long_name": CASE_VALUES[k][1]})
         for k, v in values.items()},
        coords={"sea_state": np.arange(len(matrix.sea_states)),
                "Hs": ("sea_state", [s.Hs for s in matrix.sea_states], {"units": "m"}),
                "Tp": ("sea_state", [s.Tp for s in matrix.sea_states], {"units": "s"}),
                "probability": ("sea_state", [s.probability for s in matrix.sea_states],
                                {"units": "1"}),
                "heading": ("heading", matrix.headings_deg, {"units": "deg"}),
                "heading_probability": ("heading", list(matrix.heading_probabilities),
                                        {"units": "1"}),
                "seed": ("seed", matrix.seeds), "condition": [c.name for c in matrix.conditions],
                "line": names},
        attrs={"transient_s": matrix.transient, "design_life_years": matrix.design_life})
    data["error"] = (dims[:4], errors.astype(str))
    peaks = data["max_tension"]
    data["max_tension_mean"] = peaks.mean("seed").assign_attrs(
        units="N", long_name="largest tension, mean over the seeds")
    data["max_tension_max"] = peaks.max("seed").assign_attrs(
        units="N", long_name="largest tension, largest over the seeds")
    data["max_tension_std"] = peaks.std("seed").assign_attrs(
        units="N", long_name="largest tension, standard deviation over the seeds")
    data["lifetime_damage"] = lifetime_damage(data, matrix.design_life)
    return data


def lifetime_damage(data, design_life: float):
    """Damage over ``design_life`` years per condition and line: the damage per year of
    each sea state and heading (mean over the seeds) weighted by their probabilities."""
    weights = data["probability"] * data["heading_probability"]
    rate = data["damage_per_year"].mean("seed")
    return (design_life * (rate * weights).sum(("sea_state", "heading"), min_count=1)
            ).assign_attrs(units="1", long_name=f"fatigue damage over {design_life:g} years")


def _write_csv(data, path):
    keys = list(CASE_VALUES)
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["Hs", "Tp", "probability", "heading", "seed", "condition", "line"]
                        + keys + ["error"])
        for i, j, k, c, n in np.ndindex(*data["max_tension"].shape):
            writer.writerow([float(data.Hs[i]), float(data.Tp[i]), float(data.probability[i]),
                             float(data.heading[j]), int(data.seed[k]), str(data.condition[c].values),
                             str(data.line[n].values)]
                            + [float(data[key].values[i, j, k, c, n]) for key in keys]
                            + [str(data.error.values[i, j, k, c])])


def _label(matrix, index):
    i, j, k, c = index
    s = matrix.sea_states[i]
    return (f"Hs {s.Hs:g} m, Tp {s.Tp:g} s, heading {matrix.headings_deg[j]:g} deg, "
            f"seed {matrix.seeds[k]}, {matrix.conditions[c].name}")


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _list(value, name) -> list:
    if not isinstance(value, (list, tuple)) or not value:
        raise ValueError(f"{name}: a non-empty list, got {value!r}")
    return list(value)


def _numbers(value, name) -> list:
    items = _list(value, name)
    if not all(_is_number(v) for v in items):
        raise ValueError(f"{name}: a list of finite numbers, got {value!r}")
    return items


def _table(value, name) -> dict:
    if not isinstance(value, dict):
        raise ValueError(f"{name}: each entry a table, got {value!r}")
    return value
