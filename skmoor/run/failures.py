"""Line failures in a run (MoorDyn v2's FAILURE section; the accidental limit state).

A :class:`~skmoor.coupling.network.LineFailure` releases line ends from a point at a
time or when the tension at one of them reaches a threshold. The run watches every
step (:func:`watch`); when one fires, the model is rebuilt with those ends on a new
massless free point where the point was (:func:`released`: every line keeps its
reference mesh, so the state carries over node for node, :func:`carried_state`), and
the time loop goes on from the state of that step with the acceleration of the new
balance (a release is a jump in the acceleration, not in the position or velocity).
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..coupling.build import build_system
from ..coupling.network import LineFailure, Point
from ..model.model import Model
from .equilibrium import steady_water


class Released(Exception):
    """A failure fired at ``state`` (a :class:`~skmoor.solvers.dynamics.State`): raised out
    of the time loop by :func:`watch`. ``frames``: the system's body frames then (the loop
    resets them as it ends; the state's body angles are counted from them)."""

    def __init__(self, event, state, frames):
        super().__init__(f"{event.failure.point}: released at t = {state.t:g} s")
        self.event, self.state, self.frames = event, state, frames


@dataclass
class Event:
    """A failure that happened: what fired it (``trigger``: 'time' or 'tension'), when
    (``t``, s) and the largest tension (N) of its line ends at that step."""

    failure: LineFailure
    trigger: str
    t: float
    tension: float

    def as_dict(self) -> dict:
        return {"point": self.failure.point, "lines": list(self.failure.lines),
                "trigger": self.trigger, "time": self.t, "tension": self.tension}


def end_sides(model: Model, failure: LineFailure) -> list:
    """(line index, 1 for its end A / 0 for its end B) of each of the failure's lines at
    its point."""
    lines = model.network.lines
    index = {ln.name: k for k, ln in enumerate(lines)}
    return [(index[name], int(lines[index[name]].a == failure.point)) for name in failure.lines]


def watch(model: Model):
    """A function of a State that raises :class:`Released` for the first of the model's
    failures that fires at it (its time reached, to 1e-9 s of round-off, or a line end's
    tension at or above the threshold: the end forces (fairlead, anchor) of the step's
    report, the lines' B and A ends); None when the model has none."""
    plan = [(failure, end_sides(model, failure)) for failure in model.network.failures]
    if not plan:
        return None

    def fired(event, state):
        return Released(event, state, frames_of(model.system))

    def check(state):
        for failure, sides in plan:
            largest = 0.0
            if state.reactions is not None:
                largest = max(float(np.linalg.norm(state.reactions[side][k]))
                              for k, side in sides)
            if failure.time is not None and state.t >= failure.time - 1e-9:
                raise fired(Event(failure, "time", state.t, largest), state)
            if failure.tension is not None and largest >= failure.tension:
                raise fired(Event(failure, "tension", state.t, largest), state)
    return check


def needs_tensions(model: Model) -> bool:
    """Whether a failure of the model is triggered by tension (the steps must report
    their end forces)."""
    return any(f.tension is not None for f in model.network.failures)


def released(model: Model, point: str, lines, failures=None) -> Model:
    """The model with the ends of ``lines`` (names) on ``point`` moved to a new massless
    free point at the point's reference position (named ``<point>.released``, numbered
    when several); its failures ``failures`` (default: the model's). Lines, bodies and
    their reference states are as in ``model``."""
    network = model.network
    missing = [ln for ln in lines if not any(
        n.name == ln and point in (n.a, n.b) for n in network.lines)]
    if point not in model.positions or missing:
        raise ValueError(f"release: line(s) {', '.join(map(str, missing)) or lines} do not "
                         f"end at point {point!r}")
    names = {p.name for p in network.points}
    name, k = f"{point}.released", 2
    while name in names:
        name, k = f"{point}.released{k}", k + 1
    position = np.array(model.positions[point], float)
    moved = [replace(ln, a=name if ln.name in lines and ln.a == point else ln.a,
                     b=name if ln.name in lines and ln.b == point else ln.b)
             for ln in network.lines]
    new = replace(network, points=[*network.points, Point(name, "free", position)],
                  lines=moved, notes=list(network.notes),
                  failures=list(network.failures if failures is None else failures))
    system, lineset, catenaries, positions = build_system(
        new, {**model.positions, name: position})
    if model.lines.has_static_laws:  # the dynamic laws act about the run's static state
        lineset._mean = model.lines._mean
    return Model(model.name, system, lineset, new, catenaries, model.settings, model.depth,
                 model.draft, model.source, list(model.notes), positions)


def released_damping(model: Model, rayleigh, x, t):
    """Rayleigh damping a0 M + a1 K (``rayleigh`` = (a0, a1)) of the model after a
    release, K at the state of the release (the intact equilibrium's K has other DOFs);
    None without."""
    a0, a1 = rayleigh
    if not (a0 or a1):
        return None
    C = a0 * model.system.M
    if a1:
        with steady_water(model):
            C = C + a1 * model.system.residual(x, t=t)[1]
    return C


def frames_of(system):
    """A copy of a system's re-based body frames
    (:attr:`~skmoor.coupling.frames.BodyFrames.frames`), None when no body is re-based."""
    frames = getattr(system, "frames", ())
    if not any(frame is not None for frame in frames):
        return None
    return [None if frame is None else frame.copy() for frame in frames]


def carried_state(old: Model, new: Model, x, v, t, frames=None) -> tuple:
    """(x, v) of ``new`` with every line node, point and body where ``old`` has them at
    (x, v, t); the bodies' angles counted from ``frames`` (:func:`frames_of` the old
    system at that state; default: its present ones) in both systems."""
    before, after = old.system, new.system
    frames = frames_of(before) if frames is None else frames
    if frames is not None:
        before.use_frames(frames)
    u, ud = before.full_state(x, v, t)
    x_new, v_new = np.zeros(after.n), np.zeros(after.n)
    dofs = after.dofs
    x_new[dofs.columns], v_new[dofs.columns] = u[dofs.free], ud[dofs.free]
    x_new[after.nf:], v_new[after.nf:] = x[before.nf:], v[before.nf:]
    if frames is not None:
        after.use_frames(frames)
    return x_new, v_new


def release(model: Model, point: str, lines, x, v, t, rayleigh, remaining=None,
            frames=None) -> tuple:
    """What a run goes on with after the ends of ``lines`` let go of ``point`` at the
    state (x, v, t): (the :func:`released` model, its x and v (:func:`carried_state`, the
    bodies' ``frames``), its Rayleigh damping from ``rayleigh`` = (a0, a1) or None).
    remaining: the failures still to come (default: the model's)."""
    after = released(model, point, lines, remaining)
    carry_memories(model.system, after.system)
    x, v = carried_state(model, after, x, v, t, frames)
    return after, x, v, released_damping(after, rayleigh, x, t)


def carry_memories(before, after):
    """The memories of ``before``'s terms (creep states, user laws' states, VIV phases,
    radiation memory) into their counterparts in ``after``, the same lines and bodies
    rebuilt (:func:`released`), in the order of ``System.committing``."""
    old, new = before.committing, after.committing
    if [type(term) for term in old] != [type(term) for term in new]:
        raise RuntimeError("release: the rebuilt model's terms with a memory are not the "
                           "intact one's")
    for was, term in zip(old, new):
        term.carry_memory(was)


def still_to_come(model: Model, failure: LineFailure) -> list:
    """The model's failures other than ``failure`` (the one that fired)."""
    return [f for f in model.network.failures if f is not failure]


def refused(model: Model, checkpointing: bool) -> str | None:
    """Why the model's failures cannot run (None when they can)."""
    if not model.network.failures:
        return None
    if checkpointing:
        return "line failures and checkpoints or restarts do not go together yet"
    memory = [type(term).__name__ for term in getattr(model.system, "committing", [])
              if not callable(getattr(term, "carry_memory", None))]
    if memory:
        return (f"a line failure in a model with terms that keep a history ({', '.join(memory)}) "
                "is not supported yet")
    if model.added:
        return "a line failure in a model with terms of your own is not supported yet"
    return None
