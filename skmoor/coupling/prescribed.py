"""Prescribed (coupled) line ends of a :class:`~skmoor.coupling.system.System`: their
displacements (m), velocities (m/s) and accelerations (m/s2) from ``motion(t)`` at time t
(s), in the order of the DOF map's ``prescribed_slots``; the last time's are kept (Newton
revisits it).
"""
from __future__ import annotations

import numpy as np

from ..bodies.motion import SECOND_DIFFERENCE, acceleration_of


class PrescribedEnds:
    """The prescribed-end part of :class:`~skmoor.coupling.system.System` (a mixin on its
    ``motion`` and ``dofs``). ``acceleration_step`` (s): the difference step of the ends'
    accelerations when the motion has none (integrate sets its time step)."""

    def _init_prescribed(self):
        self._prescribed_cache = (None, None, None)
        self._acceleration_cache = (None, None)
        self.acceleration_step = SECOND_DIFFERENCE

    def prescribed_state(self, t, dt=1e-6):
        """Displacements (m) and velocities (``motion.velocity``, or central differences
        over dt, m/s) of the prescribed ends at time t, (n, 3) each; the last time's are
        kept (Newton revisits it)."""
        if self._prescribed_cache[0] != (t, dt):
            slots = self.dofs.prescribed_slots

            def at(f, time):
                return np.asarray(f(time), float).reshape(-1, 3)[slots]
            velocity = getattr(self.motion, "velocity", None)
            rate = (at(velocity, t) if velocity is not None else
                    (at(self.motion, t + dt) - at(self.motion, t - dt)) / (2 * dt))
            self._prescribed_cache = ((t, dt), at(self.motion, t), rate)
        return self._prescribed_cache[1:]

    def forget_prescribed(self):
        """Drop the kept prescribed-end displacements and velocities (after ``motion`` was
        changed in place at a time already asked for)."""
        self._prescribed_cache = (None, None, None)

    def prescribed_acceleration(self, t):
        """(n, 3) accelerations (m/s2) of the prescribed ends at t (s): the motion's
        ``acceleration``, else differences of its velocity or position over
        ``acceleration_step`` (:func:`~skmoor.bodies.motion.acceleration_of`); the last time's is
        kept."""
        key = (t, self.acceleration_step)
        if self._acceleration_cache[0] != key:
            rate = acceleration_of(self.motion, t, self.acceleration_step)
            rate = np.asarray(rate, float).reshape(-1, 3)
            self._acceleration_cache = (key, rate[self.dofs.prescribed_slots])
        return self._acceleration_cache[1]

    def prescribed_at(self, times, accelerations=False):
        """Displacements (m) and velocities (m/s) of the prescribed ends at each of the m
        ``times``, (m, 3 n) each, and with ``accelerations`` their accelerations (m/s2):
        one call of ``motion.at_times`` when the motion has it (a
        :class:`~skmoor.bodies.motion.Motion`), else :meth:`prescribed_state` time by time."""
        at_times = getattr(self.motion, "at_times", None)
        m = len(times)
        if at_times is None:
            pairs = [self.prescribed_state(t) for t in times]
            out = (np.array([d.ravel() for d, _ in pairs]).reshape(m, -1),
                   np.array([r.ravel() for _, r in pairs]).reshape(m, -1))
            if accelerations:
                out += (np.array([self.prescribed_acceleration(t).ravel() for t in times]
                                 ).reshape(m, -1),)
            return out
        values = at_times(times, accelerations=accelerations, step=self.acceleration_step)
        return tuple(value[:, self.dofs.prescribed_slots].reshape(m, -1) for value in values)
