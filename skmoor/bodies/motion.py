"""Prescribed motions of line ends, with their velocities and batched evaluation.

A :class:`~skmoor.coupling.system.System` takes any ``motion(t) -> (n, 3)`` displacements (m) of
its prescribed ends and differentiates it numerically. A :class:`Motion` says more: its
exact velocity and acceleration, and (``vectorized``) that they accept an array of m times
and return (m, n, 3), so that the compiled time step gets a batch of steps' inputs in one
call instead of three calls per step. The acceleration drives the inertia the ends share
with their lines (consistent mass, bending lines) and the inertia in their reactions.

A line at rest whose end starts moving at speed v sends an axial shock of about
v sqrt(EA m) along it (the impedance of its axial wave): 68 kN for a 1 m / 12 s heave of
the lazy-wave cable of ``examples/09_lazy_wave.py``, seven times its tension.
:func:`fade_in` starts a motion from rest instead.
"""
from __future__ import annotations

import numpy as np

SECOND_DIFFERENCE = 1e-4  # s: the default step of an acceleration's central differences


def acceleration_of(motion, t, step=SECOND_DIFFERENCE):
    """(n, 3) accelerations (m/s2) of ``motion`` (a function of t, or a :class:`Motion`)
    at t (s, or (m,) times: (m, n, 3)): its own ``acceleration``, else central
    differences of its velocity over +-step (s), else central second differences of its
    position over step. :func:`~skmoor.solvers.dynamics.integrate` takes its time step for step
    (the mean acceleration over a step at a kink of a tabulated motion, not a spike)."""
    t = np.asarray(t, float)
    acceleration = getattr(motion, "acceleration", None)
    if acceleration is not None:
        return np.asarray(acceleration(t), float)
    velocity = getattr(motion, "velocity", None)
    if velocity is not None:
        ahead, behind = np.asarray(velocity(t + step), float), np.asarray(velocity(t - step), float)
        return (ahead - behind) / (2 * step)
    return (np.asarray(motion(t + step), float) - 2 * np.asarray(motion(t), float)
            + np.asarray(motion(t - step), float)) / step**2


class Motion:
    """position(t) -> (n, 3) displacements (m) of the prescribed ends; velocity(t) ->
    (n, 3) m/s (None: central differences of position); acceleration(t) -> (n, 3) m/s2
    (None: central differences of the velocity); vectorized: all three also take an
    array of m times and return (m, n, 3)."""

    def __init__(self, position, velocity=None, acceleration=None, *, vectorized=False):
        for name, f, optional in (("position", position, False), ("velocity", velocity, True),
                                  ("acceleration", acceleration, True)):
            if not (callable(f) or (optional and f is None)):
                raise ValueError(f"Motion {name}: expected a function of t"
                                 f"{' or None' if optional else ''}, got {type(f).__name__}")
        if acceleration is not None and velocity is None:
            raise ValueError("Motion acceleration: give the velocity too (an acceleration "
                             "without it would be differentiated from the position)")
        self.position, self.velocity, self.vectorized = position, velocity, bool(vectorized)
        self.acceleration = acceleration

    def __call__(self, t):
        return self.position(t)

    def at_times(self, times, dt=1e-6, accelerations=False, step=SECOND_DIFFERENCE):
        """(positions, velocities) at the m ``times`` (s), (m, n, 3) each (m, m/s), and
        with ``accelerations`` the accelerations (m/s2) too, as :func:`acceleration_of`
        gives them (over ``step``, s); a function's shifted times go in one call."""
        times = np.asarray(times, float)
        m = len(times)
        if self.vectorized:
            def at(f, shifts):
                t = np.concatenate([times + shift for shift in shifts])
                return np.asarray(f(t), float).reshape(len(shifts), m, -1, 3)
        else:
            def at(f, shifts):
                return np.array([[np.asarray(f(t + shift), float).reshape(-1, 3)
                                  for t in times] for shift in shifts])
        if self.velocity is None:
            shifts = (0.0, dt, -dt) + ((step, -step) if accelerations else ())
            y = at(self.position, shifts)
            out = (y[0], (y[1] - y[2]) / (2 * dt))
            if accelerations:
                out += ((y[3] - 2 * y[0] + y[4]) / step**2,)
            return out
        positions = at(self.position, (0.0,))[0]
        if not accelerations:
            return positions, at(self.velocity, (0.0,))[0]
        if self.acceleration is not None:
            return (positions, at(self.velocity, (0.0,))[0],
                    at(self.acceleration, (0.0,))[0])
        v = at(self.velocity, (0.0, step, -step))
        return positions, v[0], (v[1] - v[2]) / (2 * step)


def quintic_ramp(tau):
    """(r, dr/dtau, d2r/dtau2) of the C2 ramp r = 10 tau^3 - 15 tau^4 + 6 tau^5 from 0 at
    tau <= 0 to 1 at tau >= 1 (smoothstep of order 2: r' = r'' = 0 at both ends)."""
    tau = np.clip(np.asarray(tau, float), 0.0, 1.0)
    return (tau**3 * (10 - 15 * tau + 6 * tau**2), 30 * tau**2 * (1 - tau) ** 2,
            60 * tau * (1 - tau) * (1 - 2 * tau))


def fade_in(motion, ramp):
    """``motion`` (a function of t, s, or a :class:`Motion`) faded in over the first
    ``ramp`` s by :func:`quintic_ramp`: r(t / ramp) motion(t), which starts with zero
    displacement, velocity and acceleration. A Motion keeps its exact velocity
    (r' motion + r velocity, m/s), its acceleration (r'' motion + 2 r' velocity + r
    acceleration, m/s2, from differences where it has none) and its vectorization."""
    ramp = float(ramp)
    if not (np.isfinite(ramp) and ramp > 0):
        raise ValueError(f"fade_in ramp: must be a positive time (s), got {ramp}")
    if not callable(motion):
        raise ValueError(f"fade_in motion: expected a function of t or a Motion, got "
                         f"{type(motion).__name__}")

    def scaled(factor, y):
        """factor (scalar, or one per time) times the motion's values y."""
        factor = np.asarray(factor)
        return factor.reshape(factor.shape + (1,) * (y.ndim - factor.ndim)) * y

    def position(t):
        return scaled(quintic_ramp(np.asarray(t, float) / ramp)[0],
                      np.asarray(motion(t), float))

    if not isinstance(motion, Motion):
        return position

    def velocity(t, dt=1e-6):
        t = np.asarray(t, float)
        r, dr, _ = quintic_ramp(t / ramp)
        y = np.asarray(motion.position(t), float)
        v = (np.asarray(motion.velocity(t), float) if motion.velocity is not None else
             (np.asarray(motion.position(t + dt), float)
              - np.asarray(motion.position(t - dt), float)) / (2 * dt))
        return scaled(dr / ramp, y) + scaled(r, v)

    def acceleration(t):
        t = np.asarray(t, float)
        r, dr, ddr = quintic_ramp(t / ramp)
        y = np.asarray(motion.position(t), float)
        dt = 1e-6
        v = (np.asarray(motion.velocity(t), float) if motion.velocity is not None else
             (np.asarray(motion.position(t + dt), float)
              - np.asarray(motion.position(t - dt), float)) / (2 * dt))
        return (scaled(ddr / ramp**2, y) + scaled(2 * dr / ramp, v)
                + scaled(r, acceleration_of(motion, t)))

    return Motion(position, velocity, acceleration, vectorized=motion.vectorized)
