"""A dynamic body's built-in loads as terms: its hydrostatic restoring with its linear
damping, and the applied load f(t, q, qdot) it was given.

Restoring (Eq. 30 and the hull's exact hydrostatics): a 'small' body adds K q + D qdot
(K the generalized hydrostatic stiffness, N/m, N, N m/rad; D the linear damping); an
'exact' body adds -(Q(q) - F0) + D qdot with Q the buoyancy and weight at its pose
(:meth:`~skmoor.bodies.body.RigidBody.restoring_load`). The constant F0 (the static load
at the reference pose) is the System's dead load, scaled by the load factor.
"""
from __future__ import annotations

import numpy as np

from .large_rotations import generalized_load
from .loads import BodyTerm, generated_load, named


class BodyRestoring(BodyTerm):
    """Hydrostatic restoring and linear damping of dynamic body ``body`` (index) of a
    System, with their exact derivatives; stiffness (6, 6) and static_force (6,): the
    body's generalized hydrostatic stiffness and static load (computed when not given)."""

    acts_on = "bodies"
    frame_aware = True  # the pose from the System's frame of the body

    def __init__(self, body, rigid, stiffness=None, static_force=None):
        self.body, self.rigid = int(body), rigid
        self.exact = rigid.rotations == "exact"
        self.stiffness = (rigid.hydrostatic_stiffness(generalized=True) if stiffness is None
                          else stiffness)
        self.static_force = rigid.static_force() if static_force is None else static_force
        self.damping = rigid.linear_damping

    def lowered(self):
        return None if self.exact else "body restoring"

    why_python = "a body with rotations='exact'"

    def add_to(self, q, qdot, t, R, K=None, C=None):
        if self.exact:
            frame = None if self._system is None else self._system.frames[self.body]
            R -= self.rigid.restoring_load(q, frame) - self.static_force
            if K is not None:
                K += self.rigid.restoring_stiffness(q, frame)
        else:
            R += self.stiffness @ q
            if K is not None:
                K += self.stiffness
        R += self.damping @ qdot
        if C is not None:
            C += self.damping


class AppliedLoad(BodyTerm):
    """The applied load of dynamic body ``body`` of a System, ``system.body_loads[body]``:
    f(t, q, qdot) -> [force, moment] (N, N m; the moment global on an 'exact' body, its
    q the pose from the global frame also after a re-base). No tangent: it is explicit."""

    acts_on = "bodies"
    frame_aware = True  # a re-based body's load sees the pose from the global frame

    def __init__(self, body, rigid):
        self.body, self.exact = int(body), rigid.rotations == "exact"

    @property
    def load(self):
        return None if self._system is None else self._system.body_loads[self.body]

    step_load = None  # the generated C function the compiled time step calls
    _lowering = None  # (the load it was generated for, why it has none)

    def lowered(self):
        """'time load' for a load of time alone (the step takes its values per step),
        'body load' for one of the body's state that traces with JAX (written with
        :mod:`skmoor.fem.ops` / ``jax.numpy`` on a body with small rotations: the
        compiled step calls it at each iterate, as explicit as here)."""
        load = self.load
        if load is None or getattr(load, "time_only", False):
            return "time load"
        if self._lowering is None or self._lowering[0] is not load:
            why = "a body load of its state on a body with rotations='exact'"
            if not self.exact:  # (an exact body's step is Python: no kernel to make)
                self.step_load, why = generated_load(
                    lambda q, qdot, t: load(t, q, qdot), 6, f"AppliedLoad {named(load)}",
                    slopes=False)
            self._lowering = (load, why)
        return None if self.step_load is None else "body load"

    @property
    def why_python(self):
        why = "" if self._lowering is None else self._lowering[1]
        return f"a body load that depends on the body's state: {why}"

    def add_to(self, q, qdot, t, R, K=None, C=None):
        load = self.load
        if load is None:
            return
        system = self._system
        if system.frames[self.body] is None:
            value = load(t, q, qdot)
        else:
            value = load(t, *system.global_rates(q, qdot, self.body))
        if self.exact:  # force and moment (global) -> [F, E^T M]
            value = generalized_load(q[3:], value[:3], value[3:])
        R -= np.asarray(value, float)
