"""Cummins' equation: a body's wave radiation and excitation in the time domain.

Cummins (1962), for the body DOFs q (m, rad) about the reference point:

    (M + A_inf) qddot + int_0^t K(t - s) qdot(s) ds + C q = F_exc(t) + (mooring, ...)

with the retardation kernel (Ogilvie 1964)

    K(t) = (2 / pi) int_0^inf B(omega) cos(omega t) d omega

so that for qdot = Re(V exp(-i omega t)) the memory is Re([B(omega) - i omega (A(omega) -
A_inf)] V exp(-i omega t)): A(omega) = A_inf - (1/omega) int_0^inf K(t) sin(omega t) dt.

- B(omega) is taken as linear between the computed frequencies (B(0) = 0) and beyond the
  highest one as B(omega_max) (omega_max / omega)^3 up to ``tail_factor`` omega_max; the
  cosine transform of that piecewise-linear curve is exact (:func:`retardation_kernel`).
- The convolution is the trapezoidal rule over the accepted steps (``commit``) within the
  last ``memory`` seconds; its part over the current step, K(0) h / 2 qdot(t), is implicit
  through the damping tangent, so the memory sits in the same Newton step as the lines.
- The excitation of every wave component of a :class:`~skmoor.sea.waves.Sea` (the sea that
  loads the lines: same amplitudes, phases, seed) is F(t) = Re(sum_j a_j X(omega_j)
  exp(i (phi_j + k_j x'_ref - omega_j t))), x'_ref the reference point along the heading,
  X per metre of amplitude from :class:`~skmoor.bodies.bem.Hydrodynamics`; faded in over
  ``ramp`` seconds by (1 - cos(pi t / ramp)) / 2 (0: none; the static state sees F(0)).

The body's hydrostatics stay the body's own (:mod:`skmoor.bodies.body`; on an 'exact' body the
hull clipped at the pose): this term adds A_inf, the memory and the excitation only.

On a body with ``rotations='exact'`` the term works in the global frame (see
docs/bodies.md): the kernel convolves the body's velocity V = [v_ref, omega] (not the
angle rates, which change meaning when the angles are re-based), the memory and the
excitation are a force and a moment about the reference point (global axes) applied as
[F, E^T M], and the excitation is taken where the reference point is now (the phase
k . (x_ref + q[:3]) of each wave component). A_inf acts on [a_ref, alpha] in global axes,
as the body's added mass (:meth:`skmoor.coupling.system.System.inertia`).
"""
from __future__ import annotations

import numpy as np

from .bem import Hydrodynamics
from .loads import BodyTerm

TAIL_POWER = 3  # B ~ omega^-3 beyond the computed frequencies


def extended_damping(hydro: Hydrodynamics, tail_factor=4.0, n_tail=200):
    """(omega (rad/s), B (n, 6, 6)) from omega = 0 (B = 0) through the computed
    frequencies and the omega^-3 tail up to tail_factor * omega_max."""
    w, B = hydro.omega, hydro.damping
    tail = np.linspace(w[-1], tail_factor * w[-1], n_tail + 1)[1:] if tail_factor > 1 else []
    omega = np.concatenate([[0.0], w, tail])
    B_tail = B[-1] * ((w[-1] / np.asarray(tail)) ** TAIL_POWER)[:, None, None]
    return omega, np.concatenate([np.zeros((1, 6, 6)), B, B_tail.reshape(-1, 6, 6)])


def retardation_kernel(omega, B, t):
    """K(t) (len(t), 6, 6) = (2/pi) int B cos(omega t) d omega for B (n, 6, 6) linear
    between the frequencies omega (n,) (rad/s) and zero beyond: exact per segment,
    int (b0 + s (w - w0)) cos(w t) dw = [B sin(w t) / t + s cos(w t) / t^2]."""
    t = np.asarray(t, float)
    w0, w1 = omega[:-1], omega[1:]
    b0, b1 = B[:-1].reshape(len(w0), -1), B[1:].reshape(len(w0), -1)
    slope = (b1 - b0) / (w1 - w0)[:, None]
    out = np.empty((len(t), b0.shape[1]))
    small = np.abs(t) * omega[-1] < 1e-3  # the t -> 0 limit: the trapezoid of B
    out[small] = (0.5 * (b0 + b1) * (w1 - w0)[:, None]).sum(0)
    ts = t[~small][:, None]
    if len(ts):
        sin1, sin0 = np.sin(w1 * ts), np.sin(w0 * ts)
        cos1, cos0 = np.cos(w1 * ts), np.cos(w0 * ts)
        out[~small] = ((sin1 / ts) @ b1 - (sin0 / ts) @ b0
                       + ((cos1 - cos0) / ts**2) @ slope)
    return (2.0 / np.pi) * out.reshape(len(t), 6, 6)


def memory_response(kernel_t, kernel, omega):
    """A(omega) - A_inf and B(omega) (6, 6 each) that a kernel sampled at kernel_t
    (uniform from 0, s) implies at omega (rad/s): -(1/w) int K sin(w t), int K cos(w t)
    (trapezoidal rule): the check of a kernel against the coefficients it came from."""
    weights = np.full(len(kernel_t), kernel_t[1] - kernel_t[0])
    weights[[0, -1]] *= 0.5
    sin, cos = np.sin(omega * kernel_t) * weights, np.cos(omega * kernel_t) * weights
    return (-np.tensordot(sin, kernel, 1) / omega, np.tensordot(cos, kernel, 1))


class PotentialFlow(BodyTerm):
    """Cummins' equation on a dynamic body (see the module docstring): A_inf in the
    mass, the radiation memory and, with a ``sea``, the wave excitation, from a
    :class:`~skmoor.bodies.bem.Hydrodynamics` ``hydro``. memory: the kernel's length (s);
    dt_kernel: its sampling (s); ramp: the excitation's fade-in (s); heading of every
    wave in the sea must be one of ``hydro.headings``. body: name or index. The body's
    reference point is ``hydro.reference_point``. added_mass_inf: 'bem' (the BEM's
    A(inf)) or 'fit' (the A_inf with which the kernel reproduces A(omega) best, least
    squares over the computed frequencies); ``fit_error`` reports how well the kernel
    reproduces A(omega) and B(omega) (see :meth:`_consistency`)."""

    acts_on = "bodies"
    frame_aware = True  # on an exact body: V, R and E from self.body_motion

    def __init__(self, hydro: Hydrodynamics, sea=None, *, body=0, memory=60.0,
                 dt_kernel=0.01, ramp=0.0, tail_factor=4.0, added_mass_inf="fit"):
        if not isinstance(hydro, Hydrodynamics):
            raise ValueError(f"PotentialFlow hydro: expected skmoor.bodies.bem.Hydrodynamics, got "
                             f"{type(hydro).__name__}")
        for name, value in (("memory", memory), ("dt_kernel", dt_kernel)):
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"PotentialFlow {name}: must be a positive number of s, got {value}")
        if added_mass_inf not in ("bem", "fit"):
            raise ValueError(f"PotentialFlow added_mass_inf: {added_mass_inf!r} is not 'bem' "
                             "or 'fit'")
        if not (np.isfinite(ramp) and ramp >= 0):
            raise ValueError(f"PotentialFlow ramp: must be >= 0 s, got {ramp}")
        self.hydro, self.sea, self.body, self.ramp = hydro, sea, body, float(ramp)
        self.kernel_t = np.arange(0.0, memory + 0.5 * dt_kernel, dt_kernel)
        self.kernel = retardation_kernel(*extended_damping(hydro, tail_factor), self.kernel_t)
        self._flat = self.kernel.reshape(len(self.kernel_t), 36)
        self._dt_kernel = float(dt_kernel)
        self.added_mass_inf, self.fit_error = self._consistency(added_mass_inf)
        self._components = self._excitation_components(sea)
        self._t, self._v, self._count = np.zeros(256), np.zeros((256, 6)), 0  # the history
        self._past = (None, None)  # (t, memory over the committed history) of the last call
        rows, cols = np.nonzero(np.abs(self.kernel).max(axis=0))  # the coupled DOF pairs
        self._pairs, self._flat_pairs = (rows, cols), self._flat[:, rows * 6 + cols].copy()

    def _excitation_components(self, sea):
        """(omega (n,), complex coefficients (n, 6), wave-number vectors (n, 2) (rad/m)):
        F(t) = Re(c exp(-i omega t)) at the reference point, times exp(i kvec . dx) a
        horizontal shift dx from it."""
        if sea is None or not sea.waves:
            return np.zeros(0), np.zeros((0, 6), complex), np.zeros((0, 2))
        omegas, coefficients, wavenumbers = [], [], []
        point = self.hydro.reference_point
        for i, wave in enumerate(sea.waves):
            heading = np.degrees(np.arctan2(wave.direction[1], wave.direction[0]))
            try:
                X = self.hydro.excitation_force(wave.omega, heading)
            except ValueError as error:
                raise ValueError(f"PotentialFlow sea.waves[{i}]: {error}") from None
            along = point[0] * wave.direction[0] + point[1] * wave.direction[1]
            phase = np.exp(1j * (wave.phi + wave.k * along))
            omegas.append(wave.omega)
            coefficients.append((wave.a * phase)[:, None] * X)
            wavenumbers.append(np.outer(wave.k, np.asarray(wave.direction, float)[:2]))
        return np.concatenate(omegas), np.concatenate(coefficients), np.concatenate(wavenumbers)

    def _consistency(self, choice):
        """A_inf (the BEM's, or the least-squares one that makes the kernel reproduce
        A(omega) best) and the kernel's fit error: the largest |A_kernel - A| and
        |B_kernel - B| over the computed frequencies, each relative to the largest
        |A(omega)| and |B(omega)| of that DOF, per DOF (dict of (6,) arrays)."""
        hydro = self.hydro
        dA, B = zip(*(memory_response(self.kernel_t, self.kernel, w) for w in hydro.omega))
        dA, B = np.array(dA), np.array(B)
        A_inf = (hydro.added_mass_inf if choice == "bem"
                 else (hydro.added_mass - dA).mean(axis=0))
        diagonal = np.arange(6)
        scale = lambda X: np.maximum(np.abs(X[:, diagonal, diagonal]).max(0), 1e-300)
        error = {"added_mass": np.abs(A_inf + dA - hydro.added_mass)[:, diagonal, diagonal].max(0)
                 / scale(hydro.added_mass),
                 "damping": np.abs(B - hydro.damping)[:, diagonal, diagonal].max(0)
                 / scale(hydro.damping)}
        return A_inf, error

    def mass_matrix(self):
        return self.added_mass_inf

    def excitation(self, t, shift=None) -> np.ndarray:
        """Wave excitation (6,) at time t (s): N, N m; ``shift`` (3,): the reference
        point's displacement (m), whose horizontal part moves the waves' phase (None: at
        the reference point)."""
        omega, c, wavenumbers = self._components
        if not len(omega):
            return np.zeros(6)
        fade = 1.0 if self.ramp == 0 or t >= self.ramp else 0.5 * (1 - np.cos(np.pi * t / self.ramp))
        phase = -omega * t if shift is None else wavenumbers @ shift[:2] - omega * t
        return fade * (c.T @ np.exp(1j * phase)).real

    def _K(self, lags, flat=None):
        """K at lags (k,) (s) by linear interpolation of the sampled kernel, (k, 36) (or
        of the columns ``flat`` of it)."""
        flat = self._flat if flat is None else flat
        position = np.minimum(lags, self.kernel_t[-1]) / self._dt_kernel
        j = np.minimum(position.astype(int), len(self.kernel_t) - 2)
        f = (position - j)[:, None]
        return (1 - f) * flat[j] + f * flat[j + 1]

    def _history(self, t):
        """Memory (6,) at t from the committed steps, all but the open last interval:
        sum_k w_k K(t - t_k) qdot_k, w_k the trapezoidal weights of the steps."""
        n = self._count
        start = max(int(np.searchsorted(self._t[:n], t - self.kernel_t[-1])) - 1, 0)
        if n - start < 2:
            return np.zeros(6)
        tk, vk = self._t[start:n], self._v[start:n]
        w = np.empty(len(tk))
        w[0], w[-1] = 0.5 * (tk[1] - tk[0]), 0.5 * (tk[-1] - tk[-2])
        w[1:-1] = 0.5 * (tk[2:] - tk[:-2])
        rows, cols = self._pairs
        Kv = self._K(t - tk, self._flat_pairs) * vk[:, cols]
        return np.bincount(rows, w @ Kv, minlength=6)

    def memory(self, t, qdot) -> tuple:
        """(mu (6,), d mu / d qdot (6, 6)): the convolution int_0^t K(t - s) qdot(s) ds
        (N, N m) with qdot the velocity at t after the committed history (at the last
        committed time: the history's own, qdot the committed one; before it: zeros)."""
        if not self._count or t < self._t[self._count - 1]:
            return np.zeros(6), np.zeros((6, 6))
        if self._past[0] != t:
            self._past = (t, self._history(t))
        last = self._count - 1
        h = t - self._t[last]
        if h == 0:  # at the last committed step (a restart there): the history is all of it
            return self._past[1].copy(), np.zeros((6, 6))
        K0 = self.kernel[0]
        K_last = self._K(np.array([h]))[0].reshape(6, 6)
        mu = self._past[1] + 0.5 * h * (K_last @ self._v[last] + K0 @ qdot)
        return mu, 0.5 * h * K0

    def add_to(self, q, qdot, t, R, K=None, C=None):
        motion = self.body_motion(q, qdot)
        if motion.exact:
            self._add_exact(motion, t, R, K, C)
            return
        mu, slope = self.memory(t, qdot)
        R += mu - self.excitation(t)
        if C is not None:
            C += slope

    @staticmethod
    def _velocity(motion) -> np.ndarray:
        """What the kernel convolves (6,): [v_ref, omega] (m/s, rad/s, global) on an
        exact body, the DOF rates on a small one."""
        if not motion.exact:
            return motion.qdot
        return np.concatenate([motion.velocity, motion.angular_velocity])

    def _exact_load(self, q, qdot, t) -> np.ndarray:
        """The residual part (6,) on an exact body: [F, E^T M] of memory - excitation."""
        motion = self.body_motion(q, qdot)
        wrench = self.memory(t, self._velocity(motion))[0] - self.excitation(t, motion.q[:3])
        return motion.generalized(wrench[:3], wrench[3:])

    def _add_exact(self, motion, t, R, K, C):
        """add_to on an exact body (global frame); d/dqdot exact (T^T (h/2) K(0) T,
        T = diag(I, E)), d/dq by central differences (E and the excitation's phase)."""
        q, qdot = motion.q, motion.qdot
        R += self._exact_load(q, qdot, t)
        if C is not None:
            T = np.eye(6)
            T[3:, 3:] = motion.rate_map
            C += T.T @ self.memory(t, self._velocity(motion))[1] @ T
        if K is not None:
            step = 1e-6
            for k in range(6):
                e = np.zeros(6)
                e[k] = step
                K[:, k] += (self._exact_load(q + e, qdot, t)
                            - self._exact_load(q - e, qdot, t)) / (2 * step)

    def carry_memory(self, other):
        """Take ``other``'s history (the same body's term in another model: a line
        failure's rebuilt one) as this term's."""
        self._count = other._count
        if self._count:
            self._t, self._v = other._t.copy(), other._v.copy()
        self._past = (None, None)

    def commit(self, t, q, qdot):
        """Keep the accepted step (t, velocity: qdot, or on an exact body [v_ref, omega])
        for the convolution; a time before the last one starts a new history (a new run),
        the last one's keeps it (a run going on from it)."""
        if self._count and t == self._t[self._count - 1]:
            return
        qdot = self._velocity(self.body_motion(q, qdot))
        if self._count and t < self._t[self._count - 1]:
            self._count = 0
        if self._count == 0:  # a new history in its own arrays (copies of a term share none)
            self._t, self._v = np.zeros(256), np.zeros((256, 6))
        horizon = t - self.kernel_t[-1]
        if self._count == len(self._t):  # full: drop what has run out, else grow
            keep = self._count - max(int(np.searchsorted(self._t, horizon)) - 1, 0)
            if keep > len(self._t) // 2:
                self._t, self._v = (np.concatenate([a, np.zeros_like(a)]) for a in (self._t, self._v))
            else:
                self._t[:keep], self._v[:keep] = self._t[-keep:], self._v[-keep:]
                self._count = keep
        self._t[self._count], self._v[self._count] = t, qdot
        self._count += 1
        self._past = (None, None)
