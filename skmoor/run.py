"""Run a case: static equilibrium -> modes -> damping -> time integration -> Results.

:func:`simulate` returns a :class:`~skmoor.results.Results`; :func:`run_case` also
writes ``summary.json``, ``timeseries.csv`` and ``results.npz`` into an output folder.
A Ctrl-C or a diverging step keeps what was computed: the results up to the last
recorded sample are returned (and written) with ``meta["stopped"]`` saying why.
"""
from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from tqdm.auto import tqdm

from .dynamics import DivergenceError, Scheme, State, integrate, rayleigh_coefficients
from .model import Model, build
from .modes import Modes, eigenmodes
from .results import Results
from .statics import solve_static


INTERRUPTED = "interrupted (Ctrl-C)"


@dataclass
class Equilibrium:
    """Static equilibrium of a model: state x, tangent K, modes, damping matrix C."""

    x: np.ndarray
    K: object
    modes: Modes
    C: object
    rayleigh: tuple


def equilibrium(model: Model, n_modes: int = 12) -> Equilibrium:
    """Static solve from the reference state, modes about it and Rayleigh damping
    (case ``damping.ratio`` at the first two natural frequencies, or given
    ``damping.alpha`` / ``damping.beta``)."""
    system = model.system
    static = solve_static(system)
    _, K, _ = system.residual(static.x)
    modes = eigenmodes(K, system.M, k=n_modes)
    damping = model.case.damping
    if "alpha" in damping or "beta" in damping:
        a0, a1 = float(damping.get("alpha", 0.0)), float(damping.get("beta", 0.0))
    else:
        a0, a1 = rayleigh_coefficients(float(damping.get("ratio", 0.0)), *modes.omega[:2])
    return Equilibrium(static.x, K, modes, a0 * system.M + a1 * K, (a0, a1))


def simulate(model: Model, *, duration=None, dt=None, output_interval=None,
             progress=True, eq: Equilibrium | None = None) -> Results:
    """Time history of ``model`` from static rest; settings default to the case's."""
    solver = model.case.solver
    duration = float(duration or solver["duration"])
    dt = float(dt or solver["dt"])
    every = max(1, int(round(float(output_interval or solver["output_interval"]) / dt)))
    scheme = Scheme.named(solver["scheme"], solver.get("rho_inf", 0.8))
    started = time.perf_counter()
    eq = eq or equilibrium(model)
    recorder = _Recorder(model)
    n_steps = int(np.ceil(duration / dt - 1e-9))
    stopped = record_run(model.system, eq.x, dt=dt, duration=duration, every=every,
                         record=recorder.record, C=eq.C, scheme=scheme, progress=progress,
                         label=model.case.name)
    meta = {"case": model.case.name, "draft": model.draft, "dt": dt, "scheme": solver["scheme"],
            "natural_periods": eq.modes.periods.tolist(), "rayleigh": list(eq.rayleigh),
            "wall_time": time.perf_counter() - started, "steps": n_steps,
            "stopped": stopped, "interrupted": stopped == INTERRUPTED,
            "forcing_period": model.forcing_period,
            "steady_periods": solver.get("steady_periods", 5),
            "fairlead_tension_static": [c.T_fairlead for c in model.catenaries]}
    return recorder.results(meta)


def record_run(system, x0, *, dt, duration, every, record, C=None, scheme=None,
               progress=True, label="") -> str | None:
    """Integrate ``system`` from rest at x0 for ``duration`` s with step dt, calling
    ``record(state)`` every ``every`` steps, under a progress bar. Returns None, or why it
    stopped early: Ctrl-C or a diverging step keep what was recorded."""
    n_steps = int(np.ceil(duration / dt - 1e-9))
    bar = tqdm(total=n_steps, disable=not progress, unit="step", desc=label[:30])
    try:
        for state in integrate(system, x0, np.zeros(system.n), dt, duration, C=C,
                               scheme=scheme):
            if state.step % every == 0:
                record(state)
            bar.update(1 if state.step else 0)
    except KeyboardInterrupt:
        return INTERRUPTED
    except DivergenceError as err:
        return str(err)
    finally:
        bar.close()
    return None


def static_results(model: Model, eq: Equilibrium | None = None) -> Results:
    """The static equilibrium as a one-sample :class:`Results` (for export and renders)."""
    eq = eq or equilibrium(model)
    recorder = _Recorder(model)
    zero = np.zeros(model.system.n)
    recorder.record(State(0.0, 0, eq.x, zero, zero))
    return recorder.results({"case": model.case.name, "draft": model.draft, "static": True,
                             "natural_periods": eq.modes.periods.tolist()})


class _Recorder:
    """Collects sampled states into arrays for :class:`Results`."""

    def __init__(self, model: Model):
        self.model = model
        self.rows = {k: [] for k in ("t", "body", "u", "v", "tension", "strain", "fair", "anchor")}

    def record(self, state):
        system, lines = self.model.system, self.model.lines
        u = system.full_displacement(state.x, state.t)
        ud = system.full_velocity(state.x, state.v, state.t)
        fair, anchor = system.reactions(state.x, state.v, state.t)
        nodes = lines.nodal_dofs
        self.rows["t"].append(state.t)
        self.rows["body"].append(system.q(state.x).copy())
        self.rows["u"].append(u[nodes])
        self.rows["v"].append(ud[nodes])
        tension, strain = lines.element_tension_and_strain(u)
        self.rows["tension"].append(tension)
        self.rows["strain"].append(strain)
        self.rows["fair"].append(np.linalg.norm(fair, axis=1))
        self.rows["anchor"].append(np.linalg.norm(anchor, axis=1))

    def results(self, meta) -> Results:
        r, model = {k: np.array(v) for k, v in self.rows.items()}, self.model
        body = model.body
        return Results(t=r["t"], body=r["body"], points=model.lines.points,
                       cells=model.lines.mesh.t.T.copy(), line_of_cell=model.lines.line_of_cell,
                       line_names=[line.name for line in model.lines.lines],
                       displacement=r["u"], velocity=r["v"], tension=r["tension"],
                       strain=r["strain"], fairlead_tension=r["fair"], anchor_tension=r["anchor"],
                       body_center=body.reference_point.copy(),
                       body_box=np.zeros(3) if body.box_size is None else body.box_size,
                       body_box_center=body.box_center, depth=model.case.water["depth"],
                       meta=meta)


def summary(results: Results) -> dict:
    """The run's key numbers (SI, angles in rad), as written to ``summary.json``."""
    meta = results.meta
    period = meta.get("forcing_period")
    n = int(meta.get("steady_periods", 5))
    amplitude, steady_max = {}, None
    if period and results.t[-1] - results.t[0] >= n * period:
        amplitude = {name: results.amplitude(results.body_series(name), period, n)
                     for name in ("surge", "heave", "pitch")}
        steady_max = float(results.max_tension[results.t >= results.t[-1] - n * period].max())
    return {"case": meta.get("case"), "draft": meta.get("draft"),
            "fairlead_tension_static": meta.get("fairlead_tension_static"),
            "natural_periods": meta.get("natural_periods"), "amplitude": amplitude,
            "max_tension": float(results.max_tension.max()),
            "max_tension_steady": steady_max,
            "wall_time": meta.get("wall_time"), "simulated_time": float(results.t[-1]),
            "steps": meta.get("steps"), "dt": meta.get("dt"), "stopped": meta.get("stopped"),
            "interrupted": bool(meta.get("interrupted"))}


def write_outputs(results: Results, out) -> dict:
    """Write results.npz, summary.json and timeseries.csv into folder ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    results.save(out / "results.npz")
    info = summary(results)
    (out / "summary.json").write_text(json.dumps(info, indent=2))
    body = results.meta.get("has_body", True)  # a deck with coupled points only: no body
    header = ["t"] + (["surge", "sway", "heave", "roll", "pitch", "yaw"] if body else [])
    header += ["max_tension"] + [f"fairlead_tension_{n}" for n in results.line_names]
    header += [f"anchor_tension_{n}" for n in results.line_names]
    table = np.column_stack([results.t] + ([results.body] if body else [])
                            + [results.max_tension, results.fairlead_tension,
                               results.anchor_tension])
    np.savetxt(out / "timeseries.csv", table, delimiter=",", header=",".join(header),
               comments="", fmt="%.9g")
    return info


def run_case(case, out="skmoor-out", *, progress=True, **settings) -> tuple[Results, dict]:
    """Build, solve and write ``case``; returns (results, summary)."""
    results = simulate(build(case), progress=progress, **settings)
    return results, write_outputs(results, out)
