"""Run a model: static equilibrium -> modes -> damping -> time integration -> Results.

One path for every model (a case, the paper's layout, a MoorDyn deck): :func:`simulate`
returns a :class:`~skmoor.post.results.Results`; :func:`run_case` also writes
``summary.json``, ``timeseries.csv`` and ``results.npz`` into an output folder. A Ctrl-C
or a diverging step keeps what was computed: the results up to the last recorded sample
are returned (and written) with ``meta["stopped"]`` saying why.
"""
from __future__ import annotations

import contextlib
import math
import signal
import threading
import time
import warnings

import numpy as np

from ..model.model import Model, build
from ..numerics.validation import user_stacklevel
from ..post.results import Results
from ..solvers.dynamics import Scheme
from ..solvers.newton import ConvergenceError
from . import failures
from .equilibrium import (
    Equilibrium,
    dof_names,
    equilibrium,
    reference_state,
    relaxed_equilibrium,
    released_state,
    steady_water,
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
             out=None, checkpoint_every=None, checkpoint=None, restart=None) -> Results:
    """Time history of ``model`` from rest; settings (s) default to the model's. start:
    'equilibrium' (the static state), 'given' (free points and bodies released from
    their given positions, the lines in equilibrium between them: a pendulum let go) or
    'reference' (the reference state as built, nothing solved: each line on its catenary
    between the points' reference positions, MoorDyn's start with TmaxIC = 0); default:
    'equilibrium' when ``eq`` (a static state) is given, else the model's
    ``solver["start"]``, else 'equilibrium' (a deck with TmaxIC = 0 says 'reference'). out: an output folder, checked (and cleared of a previous run's files)
    before the solve and written as the run goes (see :class:`OutputWriter`); a crash, a
    full disk or Ctrl-C keeps what was computed.

    checkpoint_every (s): every that much simulated time the whole state (lines, points,
    bodies, memory terms' history, the integrator's kept matrices) is written to
    ``checkpoint`` (a path; default ``out/checkpoint.bin``), replacing the one before.
    restart: such a file: the run goes on from its time (the same model and dt) and
    repeats the uninterrupted run to round-off; its results start at that time."""
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
    saving = _checkpoints(model, dt, checkpoint_every, checkpoint, folder)
    resumed = None if restart is None else read_checkpoint(restart, model, dt)
    started = time.perf_counter()
    eq = eq or _starting_equilibrium(model, start)
    notes = resolution_notes(model, eq, dt)
    for note in notes:
        warnings.warn(note, ResolutionWarning, stacklevel=user_stacklevel())
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

    why_not = failures.refused(model, bool(saving[0] or resumed))
    if why_not:
        raise ValueError(f"{model.name}: {why_not}")
    if model.network.failures:
        meta["line_failures"] = []
    running, v0, t0, first, C = model, None, 0.0, 0, eq.C
    try:
        with terminate_as_interrupt():  # SIGTERM keeps what was computed, as Ctrl-C
            while True:
                try:
                    outcome["stopped"], outcome["steps"] = record_run(
                        running.system, x0, dt=dt, duration=duration, every=every,
                        record=recorder.record if writer is None else writer.record, C=C,
                        scheme=scheme, progress=progress, label=model.name, done=outcome,
                        compiled=solver.get("compiled", True), checkpoint_every=saving[0],
                        on_checkpoint=saving[1], restart=resumed, t0=t0, v0=v0,
                        first_step=first, watch=failures.watch(running),
                        report_every=1 if failures.needs_tensions(running) else None)
                    break
                except failures.Released as fired:  # go on with the line ends released
                    state, failure = fired.state, fired.event.failure
                    running, x0, v0, C = failures.release(
                        running, failure.point, failure.lines, state.x, state.v, state.t,
                        eq.rayleigh, failures.still_to_come(running, failure), fired.frames)
                    t0, first = state.t, first + state.step
                    recorder.follow(running)
                    meta["line_failures"].append(fired.event.as_dict())
                    meta["notes"].append(
                        f"t = {state.t:.6g} s: line(s) {', '.join(fired.event.failure.lines)} "
                        f"released from {fired.event.failure.point} ({fired.event.trigger})")
    except BaseException as error:  # a crash: keep what was computed, then re-raise
        if writer is not None and recorder.rows["t"]:
            outcome["stopped"] = f"crashed: {type(error).__name__}: {error}"
            writer.finish(finish())
        raise
    results = finish()
    if writer is not None:
        writer.finish(results)
    return results


@contextlib.contextmanager
def terminate_as_interrupt():
    """SIGTERM handled as Ctrl-C (KeyboardInterrupt) inside the block, in the main thread
    and where no other handler is set: a run stops keeping its results, a sweep its
    finished points; the previous handler restored after."""
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGTERM) not in (signal.SIG_DFL, None)):
        yield
        return

    def interrupt(signum, frame):
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _out_of_balance(model: Model) -> str:
    """Where the state as built is most out of balance: the DOF with the largest residual
    force, named (``line2 node 14``, ``point3 z``), or '' when it cannot be said."""
    system = model.system
    try:
        with steady_water(model), np.errstate(all="ignore"):
            R = system.residual(np.zeros(system.n), tangent=False)[0]
        names = dof_names(model)
    except Exception:  # naming is a courtesy: never hide the solve's own error
        return ""
    if not R.size or not np.all(np.isfinite(R)):
        return ""
    k = int(np.argmax(np.abs(R)))
    return (f"most out of balance as built: {names[k] or f'DOF {k}'} "
            f"({abs(R[k]):.3g} N or N m)")


def _checkpoints(model, dt, every, path, folder):
    """(steps between checkpoints, 0: none; the function writing one)."""
    if every is None:
        return 0, None
    every = run_setting("checkpoint_every", every)
    path = path if path is not None else (None if folder is None else
                                          folder / "checkpoint.bin")
    if path is None:
        raise ValueError("checkpoint_every: give a checkpoint path or an output folder (out)")
    from pathlib import Path

    from ..solvers.dynamics import checkpoint_bytes

    path = Path(path)

    def write(saved, state):
        data = checkpoint_bytes({**saved, "n": model.system.n, "dt": dt,
                                 "model": model.name})
        partial = path.with_name(path.name + ".part")
        partial.write_bytes(data)
        partial.replace(path)  # a crash while writing keeps the checkpoint before
    return max(1, int(round(every / dt))), write


def read_checkpoint(path, model, dt) -> dict:
    """The checkpoint in the file ``path`` (written by :func:`simulate` with
    checkpoint_every: {"stepping", "report", "n", "dt", "model"}) for ``model`` run at dt
    (s); ValueError when it is another's."""
    import pickle
    from pathlib import Path

    path = Path(path)
    if not path.is_file():
        raise ValueError(f"restart: no such file {path}")
    try:
        saved = pickle.loads(path.read_bytes())
    except Exception as err:  # noqa: BLE001 - any unreadable file says so
        raise ValueError(f"restart: {path.name} is not a checkpoint ({err})") from None
    if not isinstance(saved, dict) or "stepping" not in saved:
        raise ValueError(f"restart: {path.name} is not a checkpoint")
    if saved["n"] != model.system.n or abs(saved["dt"] - dt) > 1e-12 * dt:
        raise ValueError(f"restart: {path.name} is the checkpoint of {saved['model']!r} with "
                         f"{saved['n']} DOFs at dt = {saved['dt']:g} s, not of this model "
                         f"({model.system.n} DOFs, dt = {dt:g} s)")
    return saved


def _starting_equilibrium(model: Model, start: str) -> Equilibrium:
    """The model's equilibrium; for a release from the given state (``start='given'``)
    without Rayleigh damping, a model with no static equilibrium (a buoyant rod pinned
    below the surface turns over, nothing holds it horizontal) starts without one (the
    static solve tries Newton and continuation only, not its long march: the run needs
    no static state); from
    the reference state (``start='reference'``) without Rayleigh damping, no static
    state is sought (x = 0: the reference itself)."""
    damping = model.damping
    rayleigh = any(damping.get(k) for k in ("ratio", "alpha", "beta"))
    if start == "reference" and not rayleigh:
        model.notes.append("started from the reference state as built, no static solve "
                           "(start='reference'; a deck's TmaxIC = 0 asks for it)")
        return Equilibrium(np.zeros(model.system.n), None, None, None, (0.0, 0.0))
    try:  # a release only reports the static state: no long march to find one
        return equilibrium(model, march=start != "given" or rayleigh)
    except ConvergenceError as err:
        if "not finite" in str(err):  # name the term that gives NaN at the start
            culprit = model.system.non_finite(np.zeros(model.system.n))
            if culprit is not None:
                raise ConvergenceError(f"{str(err).split(';')[0]}: {culprit} gives NaN or "
                                       "inf at the state as built") from None
        if start == "equilibrium" and "ic" in model.solver:  # a deck: MoorDyn's IC stage
            eq, note = relaxed_equilibrium(model, str(err).split(";")[0].split(". ")[0])
            model.notes.append(note)
            warnings.warn(note, InitialConditionWarning, stacklevel=3)
            return eq
        if start != "given" or rayleigh:
            worst = _out_of_balance(model)
            if worst and "out of balance" not in str(err):
                raise ConvergenceError(f"{err}; {worst}") from None
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
