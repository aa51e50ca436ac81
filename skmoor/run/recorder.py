"""Recording a run: the time loop's states turned into Results (body motion, line tensions
and shapes, free points) at the output interval, written out as it goes.
"""
from __future__ import annotations

import functools
import sys
import threading
import time
import warnings

import numpy as np

from ..bodies import body as rigid
from ..coupling.network import coupled_size
from ..coupling.rods import coupled_reaction
from ..model.model import Model
from ..post.results import Results
from ..post.strength import line_strength_meta
from ..solvers.compiled_step import lowered_terms
from ..solvers.dynamics import State, Stepping, integrate
from ..solvers.newton import DivergenceError
from .equilibrium import Equilibrium, equilibrium, steady_water

INTERRUPTED = "interrupted (Ctrl-C)"


BLOWN_UP_STRAIN = 0.5  # no mooring material stretches by half (nylon breaks at 20-30 %)


def run_meta(model: Model, eq: Equilibrium) -> dict:
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
               progress=True, label="", done=None, compiled=True, checkpoint_every=0,
               on_checkpoint=None, restart=None, t0=0.0, v0=None, first_step=0, watch=None,
               report_every=None) -> tuple:
    """Integrate ``system`` from rest at x0 for ``duration`` s with step dt, calling
    ``record(state)`` every ``every`` steps, under a progress bar. Returns (why it stopped
    early or None, the steps done): Ctrl-C or a diverging step keep what was recorded.
    ``done``: a dict whose "steps" follows the steps done (read it after a crash) and
    "subdivided" the steps split in halves on a failed Newton; compiled: the compiled
    Newton step where it covers the system (:func:`~skmoor.solvers.dynamics.integrate`).
    checkpoint_every (steps, 0: none): ``on_checkpoint(checkpoint, state)`` every that
    many steps, checkpoint {"stepping": a :meth:`~skmoor.solvers.dynamics.Stepping.checkpoint`,
    "report": the step's (full state, end forces)}; restart: such a checkpoint to go on
    from (its state recorded first). Either runs the steps one call
    at a time (:class:`~skmoor.solvers.dynamics.Stepping`), so that a restarted run
    repeats the uninterrupted one to round-off. t0, v0, first_step: go on from (x0, v0)
    at t0, the run's step ``first_step`` (its state not recorded again; ``duration`` is
    still the run's end time). watch: called with every step's state (it may raise to
    stop the loop, e.g. :class:`~skmoor.run.failures.Released`); report_every: the steps
    whose states carry the end forces (default ``every``)."""
    n_steps = int(np.ceil(duration / dt - 1e-9))
    done = {} if done is None else done
    split_before = done.get("subdivided", 0) if first_step else 0
    done["steps"], done["subdivided"] = first_step, split_before
    from tqdm.auto import tqdm  # (imported here: it pulls in asyncio, ~40 ms)

    if compiled:
        why, _ = lowered_terms(system)
        if why is not None:
            warnings.warn(f"the time step runs in Python, not compiled: {why} (a Python step "
                          "costs several times a compiled one)", PythonStepWarning,
                          stacklevel=3)
    bar = tqdm(total=n_steps, initial=first_step, disable=not progress, unit="step",
               desc=label[:30])
    compiling = _CompileNotice(bar, label[:30])
    if not first_step:
        system.reset_frames()  # x0 has its angles from the global frame
    v0 = np.zeros(system.n) if v0 is None else v0
    try:
        states = (integrate(system, x0, v0, dt, duration, C=C, t0=t0, scheme=scheme,
                            compiled=compiled, report_every=report_every or every)
                  if not (checkpoint_every or restart) else
                  _stepped(system, x0, dt, n_steps, C, scheme, compiled, every,
                           checkpoint_every, on_checkpoint, restart))
        for state in states:
            step = first_step + state.step
            done["steps"], done["subdivided"] = step, split_before + state.subdivided
            if step % every == 0 and not (first_step and not state.step):
                record(state)
            if watch is not None:
                watch(state)
            if state.step and compiling.waiting:
                compiling.first_step(step)
            bar.update(1 if state.step else 0)
    except KeyboardInterrupt:
        return INTERRUPTED, done["steps"]
    except DivergenceError as err:
        return str(err), done["steps"]
    finally:
        compiling.cancel()
        bar.close()
        system.reset_frames()  # the model as built for what comes next (statics, modes)
    return None, done["steps"]


class PythonStepWarning(UserWarning):
    """The run's time step is evaluated in Python: a term has no compiled kernel."""


COMPILE_NOTICE = 3.0  # s before the first step: the bar says it is compiling


class _CompileNotice:
    """The progress bar while numba compiles the time step on its first use after an
    install (minutes; cached on disk for the runs after): after ``COMPILE_NOTICE`` s
    without a step the bar says so, and once the first steps are done its clock starts
    again (an ETA from the steps, not from the compilation) with a line of how long the
    compilation took."""

    def __init__(self, bar, label):
        self.bar, self.label, self.waiting = bar, label, True
        self.started = time.perf_counter()
        self.timer = threading.Timer(COMPILE_NOTICE, self._notice)
        self.timer.daemon = True
        self.timer.start()

    def _notice(self):
        if self.waiting:
            self.bar.set_description_str(f"{self.label} compiling the step (once, cached)"
                                         .strip())

    def first_step(self, step):
        self.cancel()
        seconds = time.perf_counter() - self.started
        if seconds > COMPILE_NOTICE:
            if not self.bar.disable:
                self.bar.write(f"the time step was compiled in {seconds:.0f} s, once: later "
                               "runs read it from numba's cache", file=sys.stderr)
            self.bar.set_description_str(self.label)
            self.bar.reset(total=self.bar.total)
            self.bar.update(step - 1)

    def cancel(self):
        self.waiting = False
        self.timer.cancel()


def _stepped(system, x0, dt, n_steps, C, scheme, compiled, every, checkpoint_every,
             on_checkpoint, restart):
    """:func:`integrate`'s states, one :class:`Stepping` call a step, with checkpoints
    (the state, and the report of its step: the restart records it as it was)."""
    stepping = Stepping(system, x0, np.zeros(system.n), C=C, scheme=scheme,
                        compiled=compiled)
    if restart is not None:
        stepping.restore(restart["stepping"])
        report = restart["report"]
    else:
        u, ud = system.full_state(stepping.x, stepping.v, stepping.t)
        report = (u, ud), system.end_forces(u, ud, stepping.t, stepping.a)
    yield State(stepping.t, stepping.steps, stepping.x, stepping.v, stepping.a, 0,
                stepping.subdivided, *report)
    while stepping.steps < n_steps:
        number = stepping.steps + 1
        saving = bool(checkpoint_every) and number % checkpoint_every == 0
        state = stepping.step(dt, report=saving or number % every == 0, to=number * dt)
        if saving and on_checkpoint is not None:
            on_checkpoint({"stepping": stepping.checkpoint(),
                           "report": (state.full_state, state.reactions)}, state)
        yield state


class Recorder:
    """Collects sampled states into arrays for :class:`Results`: the lines, every body
    and every point of the network."""

    def __init__(self, model: Model):
        self.rows = {k: [] for k in ("t", "bodies", "points", "u", "v", "tension", "strain",
                                     "fair", "anchor", "curvature", "moment", "coupled")}
        self.points = list(model.network.points)
        self.follow(model)

    def follow(self, model: Model):
        """Record ``model`` from now on: the model after a line failure
        (:func:`~skmoor.run.failures.released`), same lines and bodies. The points stay
        those recorded so far (a released end is its line's end node)."""
        self.model = model
        network = model.network
        self._dynamic = {b.name: k for k, b in enumerate(
            b for b in network.bodies if b.kind == "dynamic")}
        self._coupled, start = {}, 0
        for obj in network.coupled:
            size = coupled_size(obj)
            self._coupled[obj.name] = slice(start, start + size)
            start += size
        self._point_reference = np.array([model.positions[p.name] for p in self.points]
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
        for i, p in enumerate(self.points):
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

    def point_positions(self, x, t) -> np.ndarray:
        """(points, 3) positions (m) of the recorded points at the state x (the system's
        unknowns) and time t (s): free points, points on bodies, coupled and fixed ones."""
        y = self._coupled_displacements(t)
        return self._point_reference + self._points(x, y, self._bodies(x, y))

    def _coupled_displacements(self, t) -> np.ndarray:
        """The coupled DOFs' displacements (the network's motion) at time t (s)."""
        motion = self.model.network.motion
        return (np.zeros(self._n_coupled) if motion is None
                else np.asarray(motion(t), float).ravel())

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
        y = self._coupled_displacements(state.t)
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
                "point_kinds": [p.kind for p in self.points],
                "body_kinds": [b.kind for b in network.bodies],
                "point_masses": [p.mass for p in self.points],
                **line_strength_meta(lines.lines)}
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
                       bodies=bodies, point_names=[p.name for p in self.points],
                       point_reference=self._point_reference,
                       point_displacement=r["points"].reshape(nt, len(self.points), 3),
                       curvature=r["curvature"] if bending else None,
                       bending_moment=r["moment"] if bending else None,
                       coupled_loads=r["coupled"].reshape(nt, len(network.bodies), 6))


def static_results(model: Model, eq: Equilibrium | None = None) -> Results:
    """The static equilibrium as a one-sample :class:`Results` (for export and renders),
    in the sea's steady part."""
    eq = eq or equilibrium(model)
    recorder = Recorder(model)
    zero = np.zeros(model.system.n)
    with steady_water(model):
        recorder.record(State(0.0, 0, eq.x, zero, zero))
    return recorder.results({**run_meta(model, eq), "static": True})
