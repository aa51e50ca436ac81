"""MoorDyn's Python interface on skmoor: a host written for MoorDyn runs on skmoor by
changing its import (``import moordyn`` -> ``from skmoor import moordyn``).

A host (OpenFAST, WEC-Sim, a CFD code, a wave-energy model in Python) integrates its own
bodies and calls, each coupling step::

    md = moordyn.Create("lines.dat")
    moordyn.Init(md, x, xd)                 # the coupled DOFs' positions and velocities
    f = moordyn.Step(md, x, xd, t, dt)      # the lines' forces on the coupled DOFs at t + dt
    moordyn.Close(md)

x and xd follow MoorDyn's order of coupled DOFs (6 per coupled body: x, y, z, roll,
pitch, yaw; 3 per coupled pinned body or rod; then 3 per coupled point), absolute
positions (m, rad), as MoorDyn takes them.

Differences from MoorDyn:

- **Implicit steps at the coupling step**: skmoor takes the coupling step dt as its time
  step (its generalized-alpha or Newmark step, the deck's or the model's scheme), or
  ``substeps`` equal steps per call (``Create(path, substeps=5)``), no explicit substeps
  at dtM. On a chain heaved and surged at 10 s, a 0.05 s coupling step needs 5 substeps
  to follow MoorDyn's tension swing within 0.6 % (one step: 4 %; tests/run/test_host.py,
  docs/host.md); the substeps of a call run in one call of the compiled step. Over the step the coupled DOFs move as MoorDyn moves them:
  x + xd (s - t) from the values given at the step's start t, at the constant velocity
  xd. A coupling step coarser than the lines' dynamics need (a tenth of the shortest
  period of interest) is the host's choice, as with any implicit code.
- **Init** solves the static equilibrium with the coupled DOFs at x (MoorDyn's
  initial-condition relaxation, TmaxIC, reaches the same state up to threshIC); the
  lines start at rest.
- **The forces** are the lines' end forces on the coupled points and bodies (skmoor's
  :meth:`~skmoor.coupling.system.System.end_forces` less the end nodes' inertia; on a
  coupled body also the moments about its reference point,
  :func:`~skmoor.coupling.rods.coupled_reaction`). A coupled point's own mass, volume
  and drag in the deck are not added (MoorDyn adds their weight and buoyancy).
- **Line failures**: a deck's FAILURE entries fire in :func:`Step` (at a time, or at a
  line end's tension, MoorDyn having no tension trigger), and :func:`BreakLine` detaches
  a line from a point now; the host's list of them is ``instance.line_failures``.
- **Checkpoints**: :func:`SaveState` / :func:`LoadState` keep the whole state in memory
  (no path) or in a file; :func:`Serialize` / :func:`Deserialize` give and take bytes,
  :func:`Save` / :func:`Load` a file (unlike MoorDyn's SaveState / LoadState, which
  write and read initial conditions). A run continued from a checkpoint repeats the
  uninterrupted one to round-off (the kept Newton matrices and the memory terms'
  history are part of it). A file or bytes is Python's pickle: load only your own.

Functions of MoorDyn's wrapper not listed in ``__all__`` are not offered.
"""
from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np

from .bodies.motion import Motion
from .coupling.network import Point, coupled_offsets, coupled_size
from .coupling.rods import coupled_reaction
from .model.model import build
from .run import failures
from .run.equilibrium import equilibrium
from .run.recorder import Recorder
from .solvers.dynamics import Scheme, Stepping, checkpoint_bytes

__all__ = ["Create", "Init", "Step", "Close", "BreakLine", "NCoupledDOF", "GetNumberLines",
           "GetLine", "GetLineN", "GetLineNumberNodes", "GetLineFairTen", "GetLineNodePos",
           "GetLineNodeVel", "GetLineNodeTen", "GetNumberPoints", "GetPoint",
           "GetPointPos", "GetPointVel", "GetPointForce", "GetNumberBodies", "SaveState",
           "LoadState", "Serialize", "Deserialize", "Save", "Load", "Host"]

ERRCODE_SUCCESS = 0


class _HostMotion:
    """The coupled DOFs' displacements from the deck's positions over the present step:
    y0 + yd (t - t0), MoorDyn's constant-velocity motion over a coupling step."""

    def __init__(self, n):
        self.t0, self.y0, self.yd = 0.0, np.zeros(n), np.zeros(n)

    def set(self, t0, y0, yd):
        self.t0, self.y0, self.yd = float(t0), np.array(y0, float), np.array(yd, float)

    def position(self, t):
        t = np.asarray(t, float)
        return self.y0 + np.multiply.outer(t - self.t0, self.yd)

    def velocity(self, t):
        return np.broadcast_to(self.yd, np.shape(t) + self.yd.shape).copy()

    def acceleration(self, t):
        return np.zeros(np.shape(t) + self.yd.shape)

    def motion(self) -> Motion:
        return Motion(self.position, self.velocity, self.acceleration, vectorized=True)


class Host:
    """A deck stepped by a host: what :func:`Create` returns. ``model`` (the built
    :class:`~skmoor.model.model.Model`), ``stepping`` (the
    :class:`~skmoor.solvers.dynamics.Stepping`, after :func:`Init`)."""

    def __init__(self, deck, scheme=None, rho_inf=None, substeps=1):
        self.path, self.substeps = deck, int(substeps)
        if self.substeps < 1:
            raise ValueError(f"moordyn.Create substeps: must be 1 or more, got {substeps}")
        self._motion = None
        self.model = build(deck, motion=self._host_motion())
        network = self.model.network
        self.n = network.n_coupled_dofs
        self._motion.set(0.0, np.zeros(self.n), np.zeros(self.n))
        self.reference = network.coupled_positions()
        solver = self.model.solver
        self.scheme = Scheme.named(scheme or solver["scheme"],
                                   solver.get("rho_inf", 0.8) if rho_inf is None else rho_inf)
        self.stepping = None
        self._last = None  # (u, ud, (fairlead forces, anchor forces)) at the present state
        lines = self.model.lines
        self._nodes = [np.arange(a, b + 1) for a, b in zip(lines.anchor_nodes,
                                                           lines.fairlead_nodes)]
        self._ends = self._point_ends()
        self._offsets = coupled_offsets(network)
        # MoorDyn's points, numbered as it does: the deck's POINTS (the network also holds
        # the rods' ends), then the points a failure adds
        names = [p.name for p in network.points]
        self.points = [names.index(f"point{p.id}") for p in self.model.source.points]
        self._rayleigh = (0.0, 0.0)
        self._watch = failures.watch(self.model)  # the deck's FAILURE entries
        self.line_failures = []  # the deck's failures so far: failures.Event.as_dict() each
        self._releases = 0  # line ends let go so far (FAILURE entries and BreakLine calls)
        self._placer = None  # a Recorder of the present model: where line-less points are

    def _host_motion(self):
        self._motion = _HostMotion(0)
        return self._motion.motion()

    def _point_ends(self):
        """{point index (0-based): [(line k, side 0: B end / 1: A end), ...]}."""
        network = self.model.network
        names = [p.name for p in network.points]
        ends = {}
        for k, line in enumerate(network.lines):
            for side, end in enumerate((line.b, line.a)):
                ends.setdefault(names.index(end), []).append((k, side))
        return ends

    # --- the coupling
    def _set_motion(self, t, x, xd):
        x, xd = np.asarray(x, float).ravel(), np.asarray(xd, float).ravel()
        if x.size != self.n or xd.size != self.n:
            raise ValueError(f"moordyn: expected {self.n} coupled DOFs, got {x.size} "
                             f"positions and {xd.size} velocities")
        self._motion.set(t, x - self.reference, xd)
        self.model.system.forget_prescribed()
        self.model.system._acceleration_cache = (None, None)

    def init(self, x, xd):
        self._set_motion(0.0, x, np.zeros(self.n))
        eq = equilibrium(self.model, n_modes=2) if _needs_modes(self.model) else _static(self.model)
        self._set_motion(0.0, x, xd)
        system = self.model.system
        solver = self.model.solver
        self.stepping = Stepping(system, eq.x, np.zeros(system.n), C=eq.C, scheme=self.scheme,
                                 compiled=solver.get("compiled", True))
        self._rayleigh = eq.rayleigh
        u, ud = system.full_state(eq.x, self.stepping.v, 0.0)
        self._last = (u, ud, system.end_forces(u, ud, 0.0, self.stepping.a))
        return ERRCODE_SUCCESS

    def step(self, x, xd, t, dt):
        if self.stepping is None:
            raise RuntimeError("moordyn.Step: call moordyn.Init first")
        self._set_motion(t, x, xd)
        self.stepping.t = float(t)
        state = self.stepping.advance(float(dt) / self.substeps, self.substeps, report=True)
        (u, ud), ends = state.full_state, state.reactions
        self._last = (u, ud, ends)
        try:
            if self._watch is not None:
                self._watch(state)
        except failures.Released as fired:  # the deck's FAILURE entry: go on released
            failure = fired.event.failure
            self.release(failure.point, failure.lines,
                         failures.still_to_come(self.model, failure))
            self.line_failures.append(fired.event.as_dict())
        return self.coupled_forces()

    def release(self, point, lines, remaining=None):
        """Release the ends of ``lines`` (names) from ``point`` (a name) at the present
        state (:func:`skmoor.run.failures.released`): the run goes on with the new model,
        its positions and velocities carried over."""
        st = self.stepping
        why_not = failures.refused(self.model, False)
        if why_not:
            raise ValueError(f"moordyn: {why_not}")
        self.model, x, v, C = failures.release(self.model, point, lines, st.x, st.v, st.t,
                                               self._rayleigh, remaining)
        system = self.model.system
        self.stepping = Stepping(system, x, v, t0=st.t, C=C, scheme=self.scheme,
                                 compiled=self.model.solver.get("compiled", True))
        u, ud = system.full_state(x, v, st.t)
        self._last = (u, ud, system.end_forces(u, ud, st.t, self.stepping.a))
        self._ends = self._point_ends()
        self.points.append(len(self.model.network.points) - 1)
        self._watch = failures.watch(self.model)
        self._releases += 1

    def coupled_forces(self) -> np.ndarray:
        """The lines' forces (N) and moments (N m) on the coupled DOFs, MoorDyn's order."""
        network, st = self.model.network, self.stepping
        forces = np.zeros(self.n)
        names = [p.name for p in network.points]
        for obj in network.coupled:
            size = coupled_size(obj)
            if isinstance(obj, Point):
                forces[self._offsets[("Point", obj.name)]] = self.point_force(
                    names.index(obj.name))
                continue
            F, M = coupled_reaction(self.model, st.x, st.v, st.t, obj.name, st.a)
            forces[self._offsets[("Body", obj.name)]] = np.r_[F, M][:size]
        return forces

    # --- what the host reads
    def node_positions(self, k):
        lines, u = self.model.lines, self._last[0]
        nodes = self._nodes[k]
        return lines.points[nodes] + u[lines.nodal_dofs[nodes]]

    def node_velocities(self, k):
        lines, ud = self.model.lines, self._last[1]
        if ud is None:
            return np.zeros((len(self._nodes[k]), 3))
        return ud[lines.nodal_dofs[self._nodes[k]]]

    def point_force(self, i):
        ends = self._last[2]
        return sum((ends[side][k] for k, side in self._ends.get(i, [])), np.zeros(3))

    def point_positions(self):
        """(network points, 3) positions (m) at the present state."""
        if self._placer is None or self._placer.model is not self.model:
            self._placer = Recorder(self.model)
        return self._placer.point_positions(self.stepping.x, self.stepping.t)

    def point_node(self, i):
        """(line, node) of a line end on point i, or None."""
        for k, side in self._ends.get(i, []):
            return k, (len(self._nodes[k]) - 1 if side == 0 else 0)
        return None

    # --- checkpoints
    def checkpoint(self):
        m = self._motion
        return {"stepping": self.stepping.checkpoint(), "last": self._last,
                "motion": (m.t0, m.y0.copy(), m.yd.copy()),
                "released": self._releases}

    def restore(self, saved):
        if saved.get("released", 0) != self._releases:
            raise ValueError("moordyn: this checkpoint was taken before a line failure of "
                             "this run; restoring across a release is not supported")
        self.stepping.restore(saved["stepping"])
        self._last = saved["last"]
        self._motion.set(*saved["motion"])
        self.model.system.forget_prescribed()


def _needs_modes(model) -> bool:
    damping = model.damping
    return any(damping.get(k) for k in ("ratio", "alpha", "beta"))


def _static(model):
    """The static state without modes (no Rayleigh damping asked for)."""
    from .run.equilibrium import Equilibrium, static_state, steady_water

    with steady_water(model):
        x = static_state(model.system).x
    return Equilibrium(x, None, None, None, (0.0, 0.0))


class _Line:
    def __init__(self, host, k):
        self.host, self.k = host, k


class _Point:
    def __init__(self, host, i):
        self.host, self.i = host, i


# --- MoorDyn's functions
def Create(filepath="", *, scheme=None, rho_inf=None, substeps=1) -> Host:
    """The deck at ``filepath`` built for a host (MoorDyn's default path when "": a
    Mooring/lines.txt). scheme, rho_inf: the time-integration scheme (default: the
    model's, generalized-alpha with rho_inf 0.9 for a deck); substeps: implicit steps
    per Step call (1: the coupling step is skmoor's time step)."""
    path = Path(filepath or "Mooring/lines.txt")
    return Host(path, scheme, rho_inf, substeps)


def Init(instance: Host, x, v) -> int:
    """Static equilibrium with the coupled DOFs at x (m, rad), their velocities v; 0."""
    return instance.init(x, v)


def Step(instance: Host, x, v, t, dt) -> np.ndarray:
    """One implicit step from t to t + dt with the coupled DOFs at x + v (s - t): the
    lines' forces (N, N m) on the coupled DOFs at t + dt."""
    return instance.step(x, v, t, dt)


def Close(instance: Host) -> int:
    instance.stepping = None
    return ERRCODE_SUCCESS


def NCoupledDOF(instance: Host) -> int:
    return instance.n


def GetNumberLines(instance: Host) -> int:
    return len(instance.model.network.lines)


def GetLine(instance: Host, line: int) -> _Line:
    """Line ``line`` (from 1, MoorDyn's numbering)."""
    return _Line(instance, _index("GetLine", "line", line, GetNumberLines(instance)))


def GetLineN(instance: _Line) -> int:
    """Segments of the line."""
    return len(instance.host._nodes[instance.k]) - 1


def GetLineNumberNodes(instance: _Line) -> int:
    return GetLineN(instance) + 1


def GetLineFairTen(instance: _Line) -> float:
    """Tension (N) at the fairlead (end B): the size of the line's pull there."""
    return float(np.linalg.norm(instance.host._last[2][0][instance.k]))


def GetLineNodePos(instance: _Line, i: int) -> np.ndarray:
    """Position (m) of node i (0 at end A)."""
    return instance.host.node_positions(instance.k)[i]


def GetLineNodeVel(instance: _Line, i: int) -> np.ndarray:
    return instance.host.node_velocities(instance.k)[i]


def GetLineNodeTen(instance: _Line, i: int) -> float:
    """Tension (N) at node i: the ends' forces at the ends, else the mean of the two
    adjacent segments' tensions."""
    host, k = instance.host, instance.k
    if i == 0:
        return float(np.linalg.norm(host._last[2][1][k]))
    if i == GetLineN(instance):
        return GetLineFairTen(instance)
    lines = host.model.lines
    tension, _ = lines.element_tension_and_strain(host._last[0], host._last[1])
    cells = np.nonzero(lines.line_of_cell == k)[0]
    return float(0.5 * (tension[cells[i - 1]] + tension[cells[i]]))


def BreakLine(instance: Host, point: _Point, line: _Line) -> None:
    """Detach ``line`` from ``point`` now: its end goes on, on a new free point of no
    mass where the point is (added after the others, as MoorDyn adds it)."""
    network = instance.model.network
    p, ln = network.points[point.i], network.lines[line.k]
    if p.name not in (ln.a, ln.b):
        raise ValueError(f"moordyn.BreakLine: line {line.k + 1} does not end at point "
                         f"{point.i + 1}")
    instance.release(p.name, [ln.name])


def GetNumberPoints(instance: Host) -> int:
    """The deck's points and those line failures added (MoorDyn's count)."""
    return len(instance.points)


def GetPoint(instance: Host, point: int) -> _Point:
    """Point ``point`` (from 1, MoorDyn's numbering: the deck's POINTS IDs)."""
    index = _index("GetPoint", "point", point, GetNumberPoints(instance))
    return _Point(instance, instance.points[index])


def _index(call, what, number, count) -> int:
    """The 0-based index of MoorDyn's 1-based ``number`` of ``count`` objects."""
    if not 1 <= number <= count:
        raise ValueError(f"moordyn.{call}: no {what} {number} (have 1 to {count})")
    return number - 1


def GetPointPos(instance: _Point) -> np.ndarray:
    """Position (m): a line end's on it; a point without lines where its body, its
    coupled motion or its own DOFs put it (the deck's before Init)."""
    host = instance.host
    found = host.point_node(instance.i)
    if found is not None:
        return host.node_positions(found[0])[found[1]]
    if host.stepping is None:
        return np.asarray(host.model.network.points[instance.i].position, float)
    return host.point_positions()[instance.i]


def GetPointVel(instance: _Point) -> np.ndarray:
    host = instance.host
    found = host.point_node(instance.i)
    return np.zeros(3) if found is None else host.node_velocities(found[0])[found[1]]


def GetPointForce(instance: _Point) -> np.ndarray:
    """The lines' force (N) on the point."""
    return instance.host.point_force(instance.i)


def GetNumberBodies(instance: Host) -> int:
    return len(instance.model.network.bodies)


def SaveState(instance: Host, filepath=None):
    """The whole state: returned (no path: kept in memory, for hosts that step back and
    forth) or written to ``filepath``."""
    saved = instance.checkpoint()
    if filepath is None:
        return saved
    Path(filepath).write_bytes(checkpoint_bytes(saved))
    return None


def LoadState(instance: Host, filepath_or_state) -> None:
    """Back to a state from :func:`SaveState` (the object, or its file)."""
    saved = filepath_or_state
    if isinstance(saved, (str, Path)):
        saved = pickle.loads(Path(saved).read_bytes())
    instance.restore(saved)


def Serialize(instance: Host) -> bytes:
    return checkpoint_bytes(instance.checkpoint())


def Deserialize(instance: Host, data: bytes) -> None:
    instance.restore(pickle.loads(data))


def Save(instance: Host, filepath) -> None:
    SaveState(instance, filepath)


def Load(instance: Host, filepath) -> None:
    LoadState(instance, filepath)
