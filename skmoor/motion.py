"""Prescribed motions of line ends, with their velocities and batched evaluation.

A :class:`~skmoor.coupling.System` takes any ``motion(t) -> (n, 3)`` displacements (m) of
its prescribed ends and differentiates it numerically. A :class:`Motion` says more: its
exact velocity, and (``vectorized``) that position and velocity accept an array of m times
and return (m, n, 3), so that the compiled time step gets a batch of steps' inputs in one
call instead of three calls per step.
"""
from __future__ import annotations

import numpy as np


class Motion:
    """position(t) -> (n, 3) displacements (m) of the prescribed ends; velocity(t) ->
    (n, 3) m/s (None: central differences of position); vectorized: both also take an
    array of m times and return (m, n, 3)."""

    def __init__(self, position, velocity=None, *, vectorized=False):
        if not callable(position):
            raise ValueError(f"Motion position: expected a function of t, got "
                             f"{type(position).__name__}")
        if velocity is not None and not callable(velocity):
            raise ValueError(f"Motion velocity: expected a function of t or None, got "
                             f"{type(velocity).__name__}")
        self.position, self.velocity, self.vectorized = position, velocity, bool(vectorized)

    def __call__(self, t):
        return self.position(t)

    def at_times(self, times, dt=1e-6):
        """(positions, velocities) at the m ``times`` (s), (m, n, 3) each (m, m/s)."""
        times = np.asarray(times, float)
        if self.vectorized:
            def at(f, t):
                return np.asarray(f(t), float).reshape(len(times), -1, 3)
        else:
            def at(f, t):
                return np.array([np.asarray(f(s), float).reshape(-1, 3) for s in t])
        if self.velocity is not None:
            return at(self.position, times), at(self.velocity, times)
        return (at(self.position, times),
                (at(self.position, times + dt) - at(self.position, times - dt)) / (2 * dt))
