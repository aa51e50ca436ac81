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


class Record(Motion):
    """A :class:`Motion` through a table of m times (s, increasing) and (m, k) values: a
    cubic spline through every column (not-a-knot ends, C2: its velocity and acceleration
    are the spline's own derivatives, continuous), held at the first / last row outside
    the table (velocity and acceleration zero there). A call finds the interval of each
    time once for all k columns (a binary search, or the interval of the time before when
    it still holds) and evaluates the interval's cubic: a record of any length costs what
    a short one does. Vectorized: position, velocity and acceleration take a time (-> (k,))
    or an array of times (-> (times, k))."""

    def __init__(self, times, values):
        t = np.asarray(times, float)
        y = np.asarray(values, float)
        y = y.reshape(len(t), -1) if y.ndim != 2 else y
        if t.ndim != 1 or len(t) < 2 or len(y) != len(t):
            raise ValueError(f"Record: expected m >= 2 times and m rows of values, got "
                             f"{t.shape} and {np.shape(values)}")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(y))):
            raise ValueError("Record: the times and values must be finite")
        if np.any(np.diff(t) <= 0):
            raise ValueError("Record: the times must increase row by row")
        from scipy.interpolate import CubicSpline

        spline = CubicSpline(t, y, axis=0, bc_type="not-a-knot" if len(t) > 3 else "natural")
        c = spline.c  # (4, m - 1, k): value = sum c[j] s^(3 - j), s = time - t[i]
        self.times, self.values = t, y
        self._c = np.ascontiguousarray(np.moveaxis(c, 1, 0))  # (m - 1, 4, k)
        self._last = 0  # the interval found last
        super().__init__(lambda time: self._at(time, 0), lambda time: self._at(time, 1),
                         lambda time: self._at(time, 2), vectorized=True)

    def _interval(self, time):
        """(interval index, offset s = clip(time) - its start, outside the table) of a
        scalar time."""
        t = self.times
        i = self._last
        if not t[i] <= time < t[i + 1]:
            i = min(max(int(np.searchsorted(t, time, side="right")) - 1, 0), len(t) - 2)
            self._last = i
        clipped = min(max(time, t[0]), t[-1])
        return i, clipped - t[i], clipped != time

    def _at(self, time, order):
        if np.ndim(time) == 0:
            i, s, outside = self._interval(float(time))
            c = self._c[i]
            if order == 0:
                return ((c[0] * s + c[1]) * s + c[2]) * s + c[3]
            if outside:
                return np.zeros(c.shape[1])
            if order == 1:
                return (3 * c[0] * s + 2 * c[1]) * s + c[2]
            return 6 * c[0] * s + 2 * c[1]
        t = self.times
        times = np.ravel(np.asarray(time, float))
        clipped = np.clip(times, t[0], t[-1])
        i = np.clip(np.searchsorted(t, clipped, side="right") - 1, 0, len(t) - 2)
        s = (clipped - t[i])[:, None]
        c = self._c[i]  # (times, 4, k): one search for all the times and columns
        if order == 0:
            out = ((c[:, 0] * s + c[:, 1]) * s + c[:, 2]) * s + c[:, 3]
        elif order == 1:
            out = (3 * c[:, 0] * s + 2 * c[:, 1]) * s + c[:, 2]
        else:
            out = 6 * c[:, 0] * s + 2 * c[:, 1]
        if order and np.any(clipped != times):
            out[clipped != times] = 0.0
        return out.reshape(np.shape(time) + (c.shape[2],))
