"""Run a model: static equilibrium -> modes -> damping -> time integration -> Results.

One path for every model (a case, the paper's layout, a MoorDyn deck): :func:`simulate`
returns a :class:`~skmoor.post.results.Results`; :func:`run_case` also writes
``summary.json``, ``timeseries.csv`` and ``results.npz`` into an output folder. A Ctrl-C
or a diverging step keeps what was computed: the results up to the last recorded sample
are returned (and written) with ``meta["stopped"]`` saying why.
"""
from __future__ import annotations

import contextlib
import functools
import json
import math
import os
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..bodies import body as rigid
from ..coupling.network import coupled_size
from ..coupling.rods import coupled_reaction
from ..model.model import Model, build
from ..post.results import BODY_DOFS, Results
from ..solvers.dynamics import Scheme, State, integrate, rayleigh_coefficients
from ..solvers.modes import Modes, eigenmodes
from ..solvers.newton import ConvergenceError, DivergenceError
from ..solvers.statics import solve_static

INTERRUPTED = "interrupted (Ctrl-C)"
BLOWN_UP_STRAIN = 0.5  # no mooring material stretches by half (nylon breaks at 20-30 %)
# what a run writes into its output folder (a reused folder is cleared of these first)
OUTPUTS = ("results.npz", "summary.json", "timeseries.csv", "time_histories.png",
           "snapshot.png", "animation.mp4", "animation.gif", "lines.xdmf", "lines.h5",
           "motion.pvd")


STARTS = ("equilibrium", "given", "reference")  # simulate's starting states


class ResolutionWarning(UserWarning):
    """A time step too coarse for the periods the run claims to resolve, or a prescribed
    motion that starts with a velocity jump."""


@dataclass
class Equilibrium:
    """Static equilibrium of a model: state x, tangent K, modes (None when the state has
    a free rigid mode, e.g. an unrestrained yaw), damping matrix C, Rayleigh (a0, a1)."""

    x: np.ndarray
    K: object
    modes: Modes | None
    C: object
    rayleigh: tuple


def static_state(system, x0=None, held=None):
    """The static solution of a System: Newton from the reference state, then with load
    continuation, then also with a vanishing tension stiffness (for slack lines), then as
    a pseudo-transient march on the mass matrix (networks whose Newton wanders). held:
    reduced DOFs kept where x0 has them."""
    attempts = [dict(), dict(steps=8), dict(steps=8, pretension=_pretension(system)),
                dict(relax=True, maxiter=300)]
    error = None
    for options in attempts:
        try:
            return solve_static(system, x0, held=held, **options)
        except (ConvergenceError, ValueError) as err:
            error = err
    raise ConvergenceError(f"{error}. The network has no static equilibrium near the "
                           "positions given: check the line lengths and the points' "
                           "positions, masses and volumes") from None


def unrestrained(model: Model, x=None) -> list:
    """Names of the DOFs that the static tangent at x (default: the reference state)
    does not hold (its near-null vectors), e.g. ``body1 rx``, ``point3 z``, ``line2 node 4``."""
    system, network = model.system, model.network
    if system.n > 3000:
        return []
    x = np.zeros(system.n) if x is None else x
    _, K, _ = system.residual(x, layout="dense")
    K = 0.5 * (K + K.T)
    w, V = np.linalg.eigh(K)
    scale = max(np.abs(w).max(initial=0.0), 1.0)
    names = [""] * system.n
    free = iter(p.name for p in network.points if p.kind == "free")
    for columns in system.point_columns:
        name = next(free)
        for c, axis in zip(columns, "xyz"):
            names[c] = f"{name} {axis}"
    dynamic = [b.name for b in network.bodies if b.kind == "dynamic"]
    for k, name in enumerate(dynamic):
        for j, dof in enumerate(("x", "y", "z", "rx", "ry", "rz")):
            names[system.nf + 6 * k + j] = f"{name} {dof}"
    lines = model.lines
    for column in range(system.nf):
        if not names[column]:
            dof = system.free[np.flatnonzero(system.dofs.columns == column)[0]]
            slope = lines.slope_dofs is not None and dof in lines.slope_dofs
            dofs = lines.slope_dofs if slope else lines.nodal_dofs
            node = int(np.flatnonzero((dofs == dof).any(axis=1))[0])
            line = int(np.searchsorted(lines.fairlead_nodes, node))
            names[column] = (f"{lines.lines[line].name} node {node - lines.anchor_nodes[line]}"
                             + (" tangent" if slope else ""))
    found = []
    for k in np.flatnonzero(np.abs(w) < 1e-10 * scale):
        v = np.abs(V[:, k])
        found += [names[i] for i in np.flatnonzero(v > 0.3 * v.max()) if names[i] not in found]
    return found


def _pretension(system) -> float:
    """A tension of the order of the heaviest line's weight (N), for starting Newton."""
    return max((abs(line.line_type.weight) * line.length for line in system.lines.lines),
               default=0.0) or 1.0


def steady_water(model: Model):
    """A context in which the model's sea is its steady part (:meth:`skmoor.sea.waves.Sea.steady`):
    what its static state, the static results and the stiffness about it see."""
    sea = getattr(model.network, "sea", None)
    return sea.steady() if sea is not None else contextlib.nullcontext()


def equilibrium(model: Model, n_modes: int = 12) -> Equilibrium:
    """Static solve of the whole network in the sea's steady part (its currents, no waves:
    :meth:`skmoor.sea.waves.Sea.steady`), modes about it and Rayleigh damping (the settings'
    ``damping.ratio`` at the first two natural frequencies, or ``damping.alpha`` /
    ``damping.beta``)."""
    system = model.system
    with steady_water(model):
        try:
            static = static_state(system)
        except ConvergenceError as err:
            free = unrestrained(model)
            hint = (". The deck asks for no initial-condition solve (TmaxIC = 0): "
                    "skmoor.simulate runs it from its given state (start='reference')"
                    if model.solver.get("start") == "reference" else "")
            if free:
                raise ConvergenceError(f"{err}; unrestrained at the given state: "
                                       f"{', '.join(free)} (nothing holds them statically)"
                                       f"{hint}") from None
            if hint:
                raise ConvergenceError(f"{err}{hint}") from None
            raise
        _, K, _ = system.residual(static.x)
    damping = model.damping
    ratio = float(damping.get("ratio", 0.0))
    try:
        modes = eigenmodes(K, system.M, k=n_modes)
    except ValueError:
        if ratio and "alpha" not in damping and "beta" not in damping:
            raise
        modes = None
    if "alpha" in damping or "beta" in damping:
        a0, a1 = float(damping.get("alpha", 0.0)), float(damping.get("beta", 0.0))
    elif ratio:
        a0, a1 = rayleigh_coefficients(ratio, *modes.omega[:2])
    else:
        a0 = a1 = 0.0
    C = a0 * system.M + a1 * K if (a0 or a1) else None
    return Equilibrium(static.x, K, modes, C, (a0, a1))


def released_state(model: Model) -> np.ndarray:
    """The reduced state with the free points and dynamic bodies held where the model
    gives them and the lines in static equilibrium between them (a release from rest),
    in the sea's steady part."""
    system, network = model.system, model.network
    x0 = np.zeros(system.n)
    free = [p for p in network.points if p.kind == "free"]
    for p, columns in zip(free, system.point_columns):  # given - settled reference
        x0[columns] = network.global_position(p) - model.positions[p.name]
    # first guess: each line's end displacements spread linearly along it
    lines, u = model.lines, system.full_displacement(x0)
    dofs = lines.nodal_dofs
    for a, b in zip(lines.anchor_nodes, lines.fairlead_nodes):
        share = np.linspace(0.0, 1.0, b - a + 1)[1:-1, None]
        u[dofs[a + 1:b]] = (1 - share) * u[dofs[a]] + share * u[dofs[b]]
    x0[system.dofs.columns] = u[system.free]  # (a point's column gets its own value back)
    held = np.concatenate([system.point_columns.ravel(), np.arange(system.nf, system.n)])
    if len(np.unique(held)) == system.n:  # nothing left to settle
        return x0
    with steady_water(model):
        return static_state(system, x0, held=held.astype(int)).x


def reference_state(model: Model) -> np.ndarray:
    """The reduced state of the reference as built (x = 0: the points and bodies where
    the model puts them, each line on its catenary between them), its bending lines'
    node tangents turned to rotational balance with every position held (in the sea's
    steady part): the catenary's curvature at a pinned end would otherwise be a moment
    on a tangent of almost no rotary inertia, a start shock of ~1e4 m/s2 that the
    consistent Hermite mass passes on to the points (MoorDyn's nodes have no tangents)."""
    system, lines = model.system, model.lines
    x0 = np.zeros(system.n)
    if lines.slope_dofs is None:
        return x0
    turning = np.unique(system.dofs.columns[np.isin(system.free, lines.slope_dofs)])
    if turning.size == 0:  # every tangent clamped
        return x0
    held = np.setdiff1d(np.arange(system.n), turning)
    with steady_water(model):
        return static_state(system, x0, held=held).x


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
    recorder = _Recorder(model)
    meta = _meta(model, eq)
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
        if start != "given" or rayleigh:
            raise
        model.notes.append(f"no static equilibrium ({str(err).split(';')[-1].strip()}): "
                           "released from the given state without one")
        return Equilibrium(released_state(model), None, None, None, (0.0, 0.0))


def _meta(model: Model, eq: Equilibrium) -> dict:
    """What every run reports of its model and its static state."""
    fair, anchor = model.system.reactions(eq.x)
    return {"case": model.name, "draft": model.draft,
            "natural_periods": [] if eq.modes is None else eq.modes.periods.tolist(),
            "rayleigh": list(eq.rayleigh),
            "fairlead_tension_static": np.linalg.norm(fair, axis=1).tolist(),
            "anchor_tension_static": np.linalg.norm(anchor, axis=1).tolist(),
            "fairlead_tension_catenary": [_catenary_tension(c, line, "b") for c, line
                                          in zip(model.catenaries, model.lines.lines)],
            "anchor_tension_catenary": [_catenary_tension(c, line, "a") for c, line
                                        in zip(model.catenaries, model.lines.lines)],
            "notes": list(model.notes)}


def _catenary_tension(cat, line, end):
    """The analytic catenary's tension (N) at a line's end 'a' or 'b', None without one."""
    if cat is None:
        return None
    where = line.X[-1] if end == "b" else line.X[0]
    at_fairlead = np.linalg.norm(where - cat.fairlead) < np.linalg.norm(where - cat.anchor)
    return float(cat.T_fairlead if at_fairlead else cat.T_anchor)


def record_run(system, x0, *, dt, duration, every, record, C=None, scheme=None,
               progress=True, label="", done=None, compiled=True) -> tuple:
    """Integrate ``system`` from rest at x0 for ``duration`` s with step dt, calling
    ``record(state)`` every ``every`` steps, under a progress bar. Returns (why it stopped
    early or None, the steps done): Ctrl-C or a diverging step keep what was recorded.
    ``done``: a dict whose "steps" follows the steps done (read it after a crash) and
    "subdivided" the steps split in halves on a failed Newton; compiled: the compiled
    Newton step where it covers the system (:func:`~skmoor.solvers.dynamics.integrate`)."""
    n_steps = int(np.ceil(duration / dt - 1e-9))
    done = {} if done is None else done
    done["steps"] = done["subdivided"] = 0
    from tqdm.auto import tqdm  # (imported here: it pulls in asyncio, ~40 ms)

    bar = tqdm(total=n_steps, disable=not progress, unit="step", desc=label[:30])
    system.reset_frames()  # x0 has its angles from the global frame
    try:
        for state in integrate(system, x0, np.zeros(system.n), dt, duration, C=C,
                               scheme=scheme, compiled=compiled, report_every=every):
            done["steps"], done["subdivided"] = state.step, state.subdivided
            if state.step % every == 0:
                record(state)
            bar.update(1 if state.step else 0)
    except KeyboardInterrupt:
        return INTERRUPTED, done["steps"]
    except DivergenceError as err:
        return str(err), done["steps"]
    finally:
        bar.close()
        system.reset_frames()  # the model as built for what comes next (statics, modes)
    return None, done["steps"]


def static_results(model: Model, eq: Equilibrium | None = None) -> Results:
    """The static equilibrium as a one-sample :class:`Results` (for export and renders),
    in the sea's steady part."""
    eq = eq or equilibrium(model)
    recorder = _Recorder(model)
    zero = np.zeros(model.system.n)
    with steady_water(model):
        recorder.record(State(0.0, 0, eq.x, zero, zero))
    return recorder.results({**_meta(model, eq), "static": True})


def mooring_stiffness(model: Model, eq: Equilibrium | None = None, body=None) -> np.ndarray:
    """(6, 6) stiffness of the mooring at a dynamic body's reference point about the
    static state (N/m, N/rad, N m/rad; generalized loads J^T f, q = [x, y, z, rx, ry, rz]):
    the reduced tangent condensed to that body's DOFs (every other DOF in equilibrium),
    less the body's own hydrostatics and weight, in the sea's steady part. body: its name (default: the first)."""
    eq = eq or equilibrium(model)
    system, network = model.system, model.network
    dynamic = [b.name for b in network.bodies if b.kind == "dynamic"]
    coupled = [b.name for b in network.bodies if b.kind == "coupled"]
    name = (dynamic + coupled)[0] if body is None and dynamic + coupled else body
    if name in coupled:
        with steady_water(model):
            return _coupled_stiffness(model, eq, network.body(name))
    if name not in dynamic:
        raise ValueError(f"mooring_stiffness body: {name!r} is not a dynamic or coupled "
                         f"body {dynamic + coupled}")
    k = dynamic.index(name)
    with steady_water(model):
        _, K, _ = system.residual(eq.x, layout="dense")
    keep = np.arange(system.nf + 6 * k, system.nf + 6 * k + 6)
    rest = np.setdiff1d(np.arange(system.n), keep)
    condensed = (K[np.ix_(keep, keep)]
                 - K[np.ix_(keep, rest)] @ np.linalg.solve(K[np.ix_(rest, rest)],
                                                           K[np.ix_(rest, keep)]))
    return condensed - system.K_bodies[k]


def _coupled_stiffness(model: Model, eq: Equilibrium, body, step=1e-4) -> np.ndarray:
    """-dF/dq of a coupled body by central differences: each of its DOFs moved by +-step
    (m, rad), the rest of the network solved again statically, F = sum J(q)^T f the
    generalized load of the lines' forces f on its points (J = d(point)/dq with
    R = Rz Ry Rx, as for a dynamic body)."""
    system, network = model.system, model.network
    n = network.n_coupled_dofs
    start = 0
    for obj in network.coupled:
        if obj is body:
            break
        start += coupled_size(obj)
    ends = [(k, end) for k, line in enumerate(network.lines) for end, point in
            (("a", line.a), ("b", line.b)) if network.point(point).kind == "body"
            and network.point(point).body == body.name]
    given, x = network.motion, eq.x
    K = np.zeros((6, 6))
    try:
        for j in range(6):
            loads = []
            for sign in (1.0, -1.0):
                y = np.zeros(n)
                y[start + j] = sign * step
                network.motion = lambda t, y=y: y
                system.forget_prescribed()
                x = static_state(system, x).x
                fb, fa = system.reactions(x)
                F = np.zeros(6)
                q = y[start:start + 6]
                for k, end in ends:
                    f = fb[k] if end == "b" else fa[k]
                    node = model.lines.fairlead_nodes[k] if end == "b" else model.lines.anchor_nodes[k]
                    r = model.lines.points[node] - body.position
                    F += rigid.attachment_jacobian(q, r[None, :])[0].T @ f
                loads.append(F)
            K[:, j] = -(loads[0] - loads[1]) / (2 * step)
    finally:
        network.motion = given
        system.forget_prescribed()
    return K


class _Recorder:
    """Collects sampled states into arrays for :class:`Results`: the lines, every body
    and every point of the network."""

    def __init__(self, model: Model):
        self.model = model
        network = model.network
        self.rows = {k: [] for k in ("t", "bodies", "points", "u", "v", "tension", "strain",
                                     "fair", "anchor", "curvature", "moment", "coupled")}
        self._dynamic = {b.name: k for k, b in enumerate(
            b for b in network.bodies if b.kind == "dynamic")}
        self._coupled, start = {}, 0
        for obj in network.coupled:
            size = coupled_size(obj)
            self._coupled[obj.name] = slice(start, start + size)
            start += size
        self._point_reference = np.array([model.positions[p.name] for p in network.points]
                                         ).reshape(-1, 3)
        self._system = system = model.system
        nodes = model.lines.nodal_dofs  # node-major P1 DOFs: a node's x, y, z in a row
        self._node_major = np.array_equal(nodes.ravel(), np.arange(nodes.size))
        self._n_coupled = network.n_coupled_dofs
        self._body_plan = [
            ("dynamic", self._dynamic[b.name]) if b.kind == "dynamic"
            else ("coupled", self._coupled[b.name]) if b.kind == "coupled" else ("fixed", None)
            for b in network.bodies]
        index = {b.name: k for k, b in enumerate(network.bodies)}
        free = iter(range(len(system.point_masses)))
        self._plan = []  # per point: how its displacement is found (not on dynamic bodies)
        rows, columns, on_body = [], [], {}
        for i, p in enumerate(network.points):
            body = network.body(p.body) if p.kind == "body" else None
            if p.kind == "free":
                rows.append(i)
                columns.append(system.point_columns[next(free)])
            elif p.kind == "coupled":
                self._plan.append(("coupled", i, self._coupled[p.name]))
            elif body is not None and body.kind == "dynamic":
                on_body.setdefault(index[body.name], []).append(i)
            elif body is not None and body.kind == "coupled":
                self._plan.append(("moved", i, index[body.name], body, p.position))
        self._free_rows = np.array(rows, int)
        self._free_columns = np.array(columns, int).reshape(-1, 3)
        self._on_body = [(k, np.array(i), np.ascontiguousarray(
            self._point_reference[i] - network.bodies[k].rigid.reference_point))
            for k, i in on_body.items()]

    def _bodies(self, x, y):
        out = np.zeros((len(self._body_plan), 6))
        poses = self._system.body_pose(x)  # angles from the global frame (re-based bodies)
        for k, (kind, where) in enumerate(self._body_plan):
            if kind != "fixed":
                out[k] = poses[where] if kind == "dynamic" else y[where]
        return out

    def _points(self, x, y, bodies):
        out = np.zeros((len(self._point_reference), 3))
        if len(self._free_rows):
            out[self._free_rows] = x[self._free_columns]
        for k, rows, r in self._on_body:
            out[rows] = rigid.attachment_state(bodies[k], r)[0]
        for plan in self._plan:
            if plan[0] == "coupled":
                out[plan[1]] = y[plan[2]]
            else:
                q, body, r = bodies[plan[2]], plan[3], plan[4]
                out[plan[1]] = (q[:3] + body.rotation_matrix(body.attitude + q[3:]) @ r
                                - body.rotation_matrix() @ r)
        return out

    def record(self, state):
        system, lines, network = self._system, self.model.lines, self.model.network
        if state.full_state is not None:  # computed where the step was made
            (u, ud), (fair, anchor) = state.full_state, state.reactions
        else:
            u, ud = system.full_state(state.x, state.v, state.t)
            fair, anchor = system.end_forces(u, ud, state.t, state.a)
        y = (np.zeros(self._n_coupled) if network.motion is None
             else np.asarray(network.motion(state.t), float).ravel())
        bodies = self._bodies(state.x, y)
        tension, strain = lines.element_tension_and_strain(u, ud)  # T + BA x strain rate
        self._check_blow_up(state, strain)
        nodal = (lambda w: w.reshape(-1, 3)) if self._node_major else (
            lambda w: w[lines.nodal_dofs])
        for key, value in (("t", state.t), ("bodies", bodies),
                           ("points", self._points(state.x, y, bodies)),
                           ("u", nodal(u)), ("v", nodal(ud)), ("tension", tension),
                           ("strain", strain), ("fair", np.sqrt((fair * fair).sum(axis=1))),
                           ("anchor", np.sqrt((anchor * anchor).sum(axis=1)))):
            self.rows[key].append(value)
        coupled = np.zeros((len(network.bodies), 6))  # what the coupled bodies pass on
        for k, body in enumerate(network.bodies):
            if body.kind == "coupled" or body.pin == "coupled":
                coupled[k] = np.concatenate(coupled_reaction(self.model, state.x, state.v,
                                                             state.t, body.name, state.a))
        self.rows["coupled"].append(coupled)
        if lines.hermite:  # bending lines: curvature and moment at the element mid-points
            curvature = lines.curvature(u)
            self.rows["curvature"].append(curvature)
            self.rows["moment"].append(lines.fields["EI"][:, 0] * curvature)

    @functools.cached_property
    def _rope_cells(self):
        from ..coupling.checks import carries_strain

        lines = self.model.lines
        ropes = [carries_strain(line.line_type, np.inf) for line in lines.lines]
        return np.array(ropes, bool)[lines.line_of_cell] if ropes else np.zeros(0, bool)

    def _check_blow_up(self, state, strain):
        """A DivergenceError when a line stretches beyond BLOWN_UP_STRAIN or its state is
        not finite: Newton can converge on every step of a run that has blown up. A rope
        law made for large strains (``checks.carries_strain``) is checked for finiteness."""
        if self._rope_cells.any():
            strain = np.where(self._rope_cells & np.isfinite(strain), 0.0, strain)
        if not len(strain) or strain.max() <= BLOWN_UP_STRAIN:  # (False for a NaN too)
            return
        worst = int(np.argmax(strain))
        lines = self.model.lines
        line = lines.lines[int(lines.line_of_cell[worst])].name
        what = ("a line's state is not finite" if not np.all(np.isfinite(strain)) else
                f"line {line!r} stretched by {strain[worst]:.0%} (element {worst}), more "
                "than any mooring material: the solution has blown up")
        raise DivergenceError(
            f"time integration stopped at t = {state.t:.6g} s (step {state.step}): {what}. "
            "Try a smaller time step, more damping (generalized-alpha with rho_inf < 1, "
            "the lines' drag) or check the loads and the motion for a jump.",
            state.t, state.step)

    def results(self, meta) -> Results:
        r, model = {k: np.array(v) for k, v in self.rows.items()}, self.model
        network, lines = model.network, model.lines
        nt = len(r["t"])
        bodies = r["bodies"].reshape(nt, len(network.bodies), 6)
        drawn = model.body  # the first dynamic body's RigidBody, drawn as its box
        bending = bool(lines.hermite)
        meta = {**meta, "has_body": bool(network.bodies), "bending": bending,
                "point_kinds": [p.kind for p in network.points],
                "point_masses": [p.mass for p in network.points]}
        return Results(t=r["t"], body=bodies[:, 0] if network.bodies else np.zeros((nt, 6)),
                       points=lines.points, cells=lines.mesh.t.T.copy(),
                       line_of_cell=lines.line_of_cell,
                       line_names=[line.name for line in lines.lines],
                       displacement=r["u"], velocity=r["v"], tension=r["tension"],
                       strain=r["strain"], fairlead_tension=r["fair"], anchor_tension=r["anchor"],
                       body_center=(drawn.reference_point.copy() if drawn is not None
                                    else np.zeros(3)),
                       body_box=(drawn.box_size if drawn is not None and drawn.box_size is not None
                                 else np.zeros(3)),
                       body_box_center=drawn.box_center if drawn is not None else np.zeros(3),
                       depth=model.depth, meta=meta,
                       body_names=[b.name for b in network.bodies],
                       body_reference=np.array([b.position for b in network.bodies]).reshape(-1, 3),
                       bodies=bodies, point_names=[p.name for p in network.points],
                       point_reference=self._point_reference,
                       point_displacement=r["points"].reshape(nt, len(network.points), 3),
                       curvature=r["curvature"] if bending else None,
                       bending_moment=r["moment"] if bending else None,
                       coupled_loads=r["coupled"].reshape(nt, len(network.bodies), 6))


def summary(results: Results) -> dict:
    """The run's key numbers (SI, angles in rad), as written to ``summary.json``:
    ``fairlead_tension_static`` is the FE static state's (end B of each line);
    ``fairlead_tension_catenary`` the analytic catenary's where one exists (else null)."""
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
            "max_tension": float(results.max_tension.max()),
            "max_tension_steady": steady_max,
            "wall_time": meta.get("wall_time"), "simulated_time": float(results.t[-1]),
            "steps": meta.get("steps"), "steps_planned": meta.get("steps_planned"),
            "subdivided_steps": meta.get("subdivided_steps", 0),
            "dt": meta.get("dt"), "stopped": meta.get("stopped"),
            "interrupted": bool(meta.get("interrupted")), "notes": meta.get("notes", []),
            **({"max_curvature": results.line_maxima("curvature"),
                "max_bending_moment": results.line_maxima("bending_moment")}
               if results.bending else {})}


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
    """Write results.npz, summary.json and timeseries.csv into folder ``out``.

    timeseries.csv columns: t; for each body its six DOFs ``NAME.surge`` ... ``NAME.yaw``
    (m, rad); max_tension (the largest element tension at that time, N);
    ``fairlead_tension_LINE`` (end B) and ``anchor_tension_LINE`` (end A) of each line (N);
    ``NAME.x``, ``NAME.y``, ``NAME.z`` displacements of each free point (m)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    results.save(out / "results.npz")
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
        """The last rows and the final results.npz and summary.json."""
        self._append()
        self._save(results)


def run_case(case, out="skmoor-out", *, progress=True, **settings) -> tuple[Results, dict]:
    """Build, solve and write ``case`` (a Case, a Deck or a path); returns (results, summary).
    The output folder is checked first and written as the run goes."""
    prepare_output(out)
    results = simulate(build(case), progress=progress, out=out, **settings)
    return results, summary(results)
