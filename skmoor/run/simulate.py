"""Run a model: static equilibrium -> modes -> damping -> time integration -> Results.

One path for every model (a case, the paper's layout, a MoorDyn deck): :func:`simulate`
returns a :class:`~skmoor.post.results.Results`; :func:`run_case` also writes
``summary.json``, ``timeseries.csv`` and ``results.npz`` into an output folder. A Ctrl-C
or a diverging step keeps what was computed: the results up to the last recorded sample
are returned (and written) with ``meta["stopped"]`` saying why.
"""
from __future__ import annotations

import math
import time
import warnings

import numpy as np

from ..model.model import Model, build
from ..post.results import Results
from ..solvers.dynamics import Scheme
from ..solvers.newton import ConvergenceError
from .equilibrium import (
    Equilibrium,
    equilibrium,
    reference_state,
    relaxed_equilibrium,
    released_state,
)
from .outputs import OutputWriter, prepare_output, summary
from .recorder import INTERRUPTED, Recorder, record_run, run_meta

STARTS = ("equilibrium", "given", "reference")  # simulate's starting states


class InitialConditionWarning(UserWarning):
    """A deck whose static solve found no state: it starts from MoorDyn's dynamic
    relaxation, or from its given state."""


class ResolutionWarning(UserWarning):
    """A time step too coarse for the periods the run claims to resolve, or a prescribed
    motion that starts with a velocity jump."""


















def run_setting(name, value, default=None) -> float:
    """A run setting in seconds (duration, dt, output_interval): ``default`` when None,
    else a finite number > 0 (ValueError naming the setting otherwise)."""
    value = default if value is None else value
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{name}: must be a number of seconds, got {value!r}")
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name}: must be a finite number of seconds > 0, got {value}")
    return float(value)


def resolution_notes(model: Model, eq: Equilibrium, dt: float) -> list:
    """Warnings for a step coarser than a tenth of the forcing period or of the two
    natural periods the Rayleigh damping is fitted to (the ones the run claims), and for
    a step longer than the sea bed's contact period without enough numerical damping (a
    0.25 s Newmark step on the VolturnUS-S chains, period 0.17 s, is 16 % off in its peak
    tension, benchmarks/volturnus.py)."""
    periods = []
    if model.forcing_period:
        periods.append(("the forcing period", model.forcing_period))
    if eq.modes is not None and any(eq.rayleigh):
        periods += [(f"natural period {k + 1}", T) for k, T in enumerate(eq.modes.periods[:2])]
    notes = [f"dt = {dt:g} s is coarser than a tenth of {what} ({T:.4g} s): the run does not "
             f"resolve it; take dt <= {T / 10:.3g} s" for what, T in periods if dt > T / 10]
    solver = model.solver
    undamped = solver["scheme"] == "newmark" or solver.get("rho_inf", 0.8) > BED_RHO_INF
    period = bed_contact_period(model)
    if undamped and period is not None and dt > period:
        notes.append(f"dt = {dt:g} s is longer than the sea bed's contact period "
                     f"({period:.3g} s: a resting node on its bed spring) with little numerical "
                     f"damping ({solver['scheme']}): nodes near touchdown may chatter; take "
                     f"generalized-alpha with rho_inf <= {BED_RHO_INF:g} "
                     "(model.solver.update(scheme='generalized-alpha', rho_inf=0.5)) or a "
                     f"smaller step")
    return notes + start_shock_notes(model.system, eq.x)


SHOCK_SHARE = 0.1  # an axial shock above this share of an end's tension is noted


def start_shock_notes(system, x) -> list:
    """Warnings for prescribed ends that start moving at t = 0 while the lines rest at x:
    such an end sends an axial shock of about v sqrt(EA m) (N; v the end's speed, m/s) into
    its line; noted where that exceeds SHOCK_SHARE of the end's static tension."""
    if not system.dofs.has_prescribed:
        return []
    _, rates = system.prescribed_state(0.0)  # (n, 3) m/s, in the order of the prescribed slots
    u = system.full_displacement(x, 0.0)
    on_b, on_a = system.end_forces(u, None, 0.0)
    notes = []
    for k, line in enumerate(system.lines.lines):
        for end, force in ((system.ends.a[k], on_a[k]), (system.ends.b[k], on_b[k])):
            if end[0] != "prescribed":
                continue
            speed = float(np.linalg.norm(rates[list(system.dofs.prescribed_slots).index(end[1])]))
            shock = speed * math.sqrt(line.line_type.EA * line.line_type.mass)
            tension = float(np.linalg.norm(force))
            if shock > SHOCK_SHARE * tension:
                notes.append(f"line {line.name!r}: its prescribed end starts at {speed:.3g} m/s "
                             f"from rest, an axial shock of about v sqrt(EA m) = "
                             f"{shock / 1e3:.4g} kN on its {tension / 1e3:.4g} kN tension that "
                             "the run does not resolve; start the motion from rest: "
                             "skmoor.fade_in(motion, ramp) with a ramp of a period or more")
    return notes


BED_RHO_INF = 0.5  # generalized-alpha spectral radius that damps the bed's chatter


def bed_contact_period(model: Model) -> float | None:
    """Shortest period (s) of a line node resting on the sea bed, 2 pi sqrt(m / k): m the
    line's mass and transverse added mass per length (kg/m), k the bed's stiffness per
    length (N/m2); None without a bed."""
    bed = getattr(model.network, "seabed", None)
    if bed is None:
        return None
    lines = model.lines
    k, _ = bed.cell_coefficients(lines)
    mass = np.array([lt.mass + lt.Ca_n * lt.rho_water * lt.area
                     for lt in (line.line_type for line in lines.lines)])[lines.line_of_cell]
    return float(np.min(2 * np.pi * np.sqrt(mass / k)))


def simulate(model: Model, *, duration=None, dt=None, output_interval=None,
             progress=True, eq: Equilibrium | None = None, start=None,
             out=None) -> Results:
    """Time history of ``model`` from rest; settings (s) default to the model's. start:
    'equilibrium' (the static state), 'given' (free points and bodies released from
    their given positions, the lines in equilibrium between them: a pendulum let go) or
    'reference' (the reference state as built, nothing solved: each line on its catenary
    between the points' reference positions, MoorDyn's start with TmaxIC = 0); default:
    'equilibrium' when ``eq`` (a static state) is given, else the model's
    ``solver["start"]``, else 'equilibrium' (a deck with TmaxIC = 0 says 'reference'). out: an output folder, checked (and cleared of a previous run's files)
    before the solve and written as the run goes (see :class:`OutputWriter`); a crash, a
    full disk or Ctrl-C keeps what was computed."""
    solver = model.solver
    if start is None:
        start = "equilibrium" if eq is not None else solver.get("start", "equilibrium")
    if start not in STARTS:
        raise ValueError(f"simulate start: {start!r} is not one of {', '.join(STARTS)}")
    duration = run_setting("duration", duration, solver["duration"])
    dt = run_setting("dt", dt, solver["dt"])
    interval = run_setting("output_interval", output_interval, solver["output_interval"])
    if dt > duration:
        raise ValueError(f"dt: the step ({dt:g} s) is longer than the duration ({duration:g} s)")
    every = max(1, int(round(interval / dt)))
    scheme = Scheme.named(solver["scheme"], solver.get("rho_inf", 0.8))
    folder = None if out is None else prepare_output(out)
    started = time.perf_counter()
    eq = eq or _starting_equilibrium(model, start)
    notes = resolution_notes(model, eq, dt)
    for note in notes:
        warnings.warn(note, ResolutionWarning, stacklevel=2)
    x0 = {"given": released_state, "reference": reference_state}.get(start)
    x0 = eq.x if x0 is None else x0(model)
    recorder = Recorder(model)
    meta = run_meta(model, eq)
    meta["notes"] += notes
    meta.update({"dt": dt, "scheme": solver["scheme"], "steps_planned":
                 int(np.ceil(duration / dt - 1e-9)), "forcing_period": model.forcing_period,
                 "steady_periods": solver.get("steady_periods", 5)})
    writer = None if folder is None else OutputWriter(folder, recorder, meta)
    outcome = {"stopped": None, "steps": 0}

    def finish():
        meta.update({"wall_time": time.perf_counter() - started, "steps": outcome["steps"],
                     "subdivided_steps": outcome.get("subdivided", 0),
                     "stopped": outcome["stopped"],
                     "interrupted": outcome["stopped"] == INTERRUPTED})
        return recorder.results(meta)

    try:
        outcome["stopped"], outcome["steps"] = record_run(
            model.system, x0, dt=dt, duration=duration, every=every,
            record=recorder.record if writer is None else writer.record, C=eq.C,
            scheme=scheme, progress=progress, label=model.name, done=outcome,
            compiled=solver.get("compiled", True))
    except BaseException as error:  # a crash: keep what was computed, then re-raise
        if writer is not None and recorder.rows["t"]:
            outcome["stopped"] = f"crashed: {type(error).__name__}: {error}"
            writer.finish(finish())
        raise
    results = finish()
    if writer is not None:
        writer.finish(results)
    return results


def _starting_equilibrium(model: Model, start: str) -> Equilibrium:
    """The model's equilibrium; for a release from the given state (``start='given'``)
    without Rayleigh damping, a model with no static equilibrium (a buoyant rod pinned
    below the surface turns over, nothing holds it horizontal) starts without one; from
    the reference state (``start='reference'``) without Rayleigh damping, no static
    state is sought (x = 0: the reference itself)."""
    damping = model.damping
    rayleigh = any(damping.get(k) for k in ("ratio", "alpha", "beta"))
    if start == "reference" and not rayleigh:
        model.notes.append("started from the reference state as built, no static solve "
                           "(start='reference'; a deck's TmaxIC = 0 asks for it)")
        return Equilibrium(np.zeros(model.system.n), None, None, None, (0.0, 0.0))
    try:
        return equilibrium(model)
    except ConvergenceError as err:
        if start == "equilibrium" and "ic" in model.solver:  # a deck: MoorDyn's IC stage
            eq, note = relaxed_equilibrium(model, str(err).split(";")[0].split(". ")[0])
            model.notes.append(note)
            warnings.warn(note, InitialConditionWarning, stacklevel=3)
            return eq
        if start != "given" or rayleigh:
            raise
        model.notes.append(f"no static equilibrium ({str(err).split(';')[-1].strip()}): "
                           "released from the given state without one")
        return Equilibrium(released_state(model), None, None, None, (0.0, 0.0))






























def run_case(case, out="skmoor-out", *, progress=True, **settings) -> tuple[Results, dict]:
    """Build, solve and write ``case`` (a Case, a Deck or a path); returns (results, summary).
    The output folder is checked first and written as the run goes."""
    prepare_output(out)
    results = simulate(build(case), progress=progress, out=out, **settings)
    return results, summary(results)
