"""Tabulated water kinematics, as MoorDyn-C v2 holds them (source/Waves/WaveGrid.cpp,
source/Waves/SpectrumKin.cpp): a rectilinear grid of velocities and accelerations over
one period of time, and a sum of frequency components evaluated at the points.

Both are fields of a :class:`~skmoor.sea.waves.Sea` (``Sea(..., fields=[...])``): objects with
``kinematics(points, t) -> (velocity, acceleration)`` ((..., 3) each, m/s and m/s2),
``elevation(xy, t)`` (m), ``has_acceleration`` (whether the field's acceleration is
ever non-zero, i.e. whether the lines see fluid inertia from it) and ``steady_parts()``
(the fields a static solve sees: its currents, no waves; :meth:`skmoor.sea.waves.Sea.steady`).

Interpolation is MoorDyn's: linear in x, y, z and t, held at the grid's first / last
value beyond its ends; in time the grid repeats with period nt dt, the sample index
being floor(t / dt) + 1 wrapped into [0, nt) and interpolated from the sample before it
(from sample 0 to itself in the last interval). Waves are stretched to the free surface
(Wheeler): a point at height z sees the grid at z_s = h_m (z - z_b) / (zeta - z_b) - h_m,
with z_b the bed's height there, h_m the mean depth and zeta the grid's elevation there,
clipped to z_s <= 0. Currents are not stretched.
"""
from __future__ import annotations

import numpy as np

from ..numerics.validation import check_finite, check_positive


def _axis(name, values):
    values = np.atleast_1d(np.asarray(values, float))
    check_finite(name, values)
    if values.ndim != 1 or values.size < 1:
        raise ValueError(f"{name}: need a 1-D list of coordinates, got shape {values.shape}")
    if np.any(np.diff(values) <= 0):
        raise ValueError(f"{name}: coordinates must increase strictly, got {values.tolist()}")
    return values


def interpolation(axis, x):
    """MoorDyn's interp_factor on an increasing axis: (i0, i1, f) with the value
    (1 - f) v[i0] + f v[i1], held at the ends (i0 = i1 = 0 on a one-point axis)."""
    x = np.asarray(x, float)
    if axis.size == 1:
        zero = np.zeros(x.shape, int)
        return zero, zero, np.zeros(x.shape)
    i1 = np.clip(np.searchsorted(axis, x, side="left"), 1, axis.size - 1)
    f = np.clip((x - axis[i1 - 1]) / (axis[i1] - axis[i1 - 1]), 0.0, 1.0)
    return i1 - 1, i1, f


def time_interpolation(nt, dt, t):
    """(i0, i1, f) in a periodic record of nt samples dt apart, MoorDyn's way (see the
    module docstring); a scalar t."""
    if nt == 1:
        return 0, 0, 0.0
    q = float(t) / dt
    step = int(np.floor(q))
    i1 = (step + 1) % nt
    return (i1 - 1 if i1 > 0 else 0), i1, q - step


def _trilinear(values, ix, iy, iz):
    """values (nx, ny, nz, ...) at points with the (i0, i1, f) of each axis."""
    out = 0.0
    for a, wa in ((ix[0], 1 - ix[2]), (ix[1], ix[2])):
        for b, wb in ((iy[0], 1 - iy[2]), (iy[1], iy[2])):
            for c, wc in ((iz[0], 1 - iz[2]), (iz[1], iz[2])):
                w = wa * wb * wc
                out = out + w.reshape(w.shape + (1,) * (values.ndim - 3)) * values[a, b, c]
    return out


def linear_factors(k, z, depth):
    """(..., n) cosh k(z+h) / sinh kh and sinh k(z+h) / sinh kh for z in [-h, 0] (k = 0:
    0 and 1, as MoorDyn's zero-frequency component, whose velocity vanishes)."""
    k = np.asarray(k, float)
    z = np.asarray(z, float)[..., None]
    safe = np.where(k > 0, k, 1.0)
    scale = 1.0 / (1.0 - np.exp(-2.0 * safe * depth))
    up, down = np.exp(safe * z), np.exp(-safe * (z + 2.0 * depth))
    ch = np.where(k > 0, (up + down) * scale, 0.0)
    sh = np.where(k > 0, (up - down) * scale, 1.0)
    return ch, sh


class Stretching:
    """Wheeler stretching onto the mean water column: bed heights z_b(x, y) (m, from a
    :class:`~skmoor.sea.seabed.Bathymetry` or flat at -depth) and mean depth h_m (m)."""

    def __init__(self, depth, bathymetry=None):
        check_positive("Stretching depth", depth)
        self.bathymetry = bathymetry
        self.depth = float(-bathymetry.mean_height if bathymetry is not None else depth)

    def bed(self, xy):
        xy = np.asarray(xy, float)
        if self.bathymetry is None:
            return np.full(xy.shape[:-1], -self.depth)
        return self.bathymetry.height(xy[..., :2])

    def __call__(self, points, zeta):
        """z_s (m) of points (..., 3) under the elevation zeta (...)."""
        bed = self.bed(points)
        z_s = self.depth * (points[..., 2] - bed) / (zeta - bed) - self.depth
        return np.minimum(z_s, 0.0)


class WaveGrid:
    """Waves tabulated on a grid (MoorDyn's WaveKin 2 and 3) from evenly spaced frequency
    components: omega_i = i dw (rad/s, i = 0..n-1), complex amplitudes c_i (m), headings
    beta_i (rad). The grid holds, at its nodes px x py x pz (m) and at nt = 2 (n - 1)
    samples dt = 2 pi / (dw nt) apart, the elevation Re sum w_i c_i exp(i theta_i),
    theta_i = omega_i t - k_i (x cos beta_i + y sin beta_i), w_i = 1 but 1/2 for the
    first and last components (MoorDyn's inverse real FFT of the record), and its linear
    kinematics in depth h (m); ``currents`` (fields) are added at the nodes and samples
    (MoorDyn's UnifyCurrentGrid). The node values are summed when asked for, at the 16
    nodes and samples around each point, rather than stored: the same numbers as the
    tabulated grid without its memory."""

    has_acceleration = True

    def __init__(self, components, px, py, pz, depth, stretching, g=9.81, currents=()):
        from .waves import wavenumber

        omega, c, beta = (np.asarray(a) for a in components)
        if omega.size < 2 or omega[0] != 0 or np.any(np.abs(np.diff(omega, 2)) >
                                                     1e-9 * omega[-1]):
            raise ValueError("WaveGrid components: need evenly spaced frequencies from 0 "
                             f"rad/s, got {omega.tolist()}")
        self.px, self.py, self.pz = (_axis(f"WaveGrid {name}", axis) for name, axis in
                                     zip("xyz", (px, py, pz)))
        check_positive("WaveGrid depth", depth)
        self.omega, self.beta, self.depth = omega.astype(float), beta.astype(float), float(depth)
        weight = np.ones(omega.size)
        weight[[0, -1]] = 0.5
        self.c = np.asarray(c, complex) * weight
        self.k = np.zeros(omega.size)
        self.k[1:] = wavenumber(self.omega[1:], self.depth, g)
        self.nt = 2 * (omega.size - 1)
        self.dt = 2 * np.pi / (omega[1] * self.nt)
        self.stretching, self.currents = stretching, list(currents)
        active = self.c != 0  # the zero components add nothing (WaveKin 3's above 0.5 Hz)
        self.omega, self.beta, self.c, self.k = (a[active] for a in
                                                 (self.omega, self.beta, self.c, self.k))

    def steady_parts(self):
        """The steady part: the currents added to the grid, each on its own grid."""
        return list(self.currents)

    def _modes(self, x, y, t):
        """c_i exp(i theta_i) (..., n) at nodes x, y (...) and time t."""
        along = x[..., None] * np.cos(self.beta) + y[..., None] * np.sin(self.beta)
        return self.c * np.exp(1j * (self.omega * t - self.k * along))

    def _corners(self, points, t):
        """The (i0, i1, f) of x, y and t and the modes at the nodes and samples around
        each point, (P, 2, 2, 2, n) over the x, y and t corners."""
        ix, iy = interpolation(self.px, points[:, 0]), interpolation(self.py, points[:, 1])
        it = time_interpolation(self.nt, self.dt, t)
        x = np.stack([self.px[ix[0]], self.px[ix[1]]], axis=-1)[:, :, None]
        y = np.stack([self.py[iy[0]], self.py[iy[1]]], axis=-1)[:, None, :]
        x, y = np.broadcast_arrays(x, y)
        modes = np.stack([self._modes(x, y, it[0] * self.dt),
                          self._modes(x, y, it[1] * self.dt)], axis=3)
        return ix, iy, it, modes

    @staticmethod
    def _weights(ix, iy, it, iz=None):
        """(P, 2, 2, [2,] 2) interpolation weights over the x, y, [z,] t corners."""
        w = lambda i: np.stack([1 - i[2], i[2]], axis=-1)  # noqa: E731
        wt = np.array([1 - it[2], it[2]])
        out = w(ix)[:, :, None] * w(iy)[:, None, :]
        if iz is None:
            return out[..., None] * wt
        return out[..., None, None] * w(iz)[:, None, None, :, None] * wt

    def elevation(self, xy, t=0.0):
        xy = np.asarray(xy, float)
        flat = xy.reshape(-1, xy.shape[-1])
        ix, iy, it, modes = self._corners(flat, t)
        zeta = np.sum(self._weights(ix, iy, it) * modes.real.sum(-1), axis=(1, 2, 3))
        return zeta.reshape(xy.shape[:-1])

    def kinematics(self, points, t=0.0):
        points = np.asarray(points, float)
        flat = points.reshape(-1, 3)
        ix, iy, it, modes = self._corners(flat, t)
        zeta = np.sum(self._weights(ix, iy, it) * modes.real.sum(-1), axis=(1, 2, 3))
        iz = interpolation(self.pz, self.stretching(flat, zeta))
        z = np.stack([self.pz[iz[0]], self.pz[iz[1]]], axis=-1)  # (P, 2)
        ch, sh = linear_factors(self.k, z, self.depth)  # (P, 2, n)
        u = modes[:, :, :, None, :, :] * self.omega  # (P, 2x, 2y, 1, 2t, n)
        ch, sh = ch[:, None, None, :, None, :], sh[:, None, None, :, None, :]
        # u_h = Re(w c e^{i theta} ch) e, u_z = Re(i w c e^{i theta} sh), du/dt = Re(i w u)
        horizontal, vertical = u * ch, 1j * u * sh
        e = np.stack([np.cos(self.beta), np.sin(self.beta)], axis=-1)  # (n, 2)
        w = self._weights(ix, iy, it, iz)
        velocity = np.empty(flat.shape)
        acceleration = np.empty(flat.shape)
        velocity[:, :2] = np.einsum("pabzt,pabztn,nc->pc", w, horizontal.real, e)
        velocity[:, 2] = np.einsum("pabzt,pabztn->p", w, vertical.real)
        acceleration[:, :2] = np.einsum("pabzt,pabztn,nc->pc", w,
                                        (1j * self.omega * horizontal).real, e)
        acceleration[:, 2] = np.einsum("pabzt,pabztn->p", w, (1j * self.omega * vertical).real)
        for current in self.currents:
            self._add_current(current, flat, ix, iy, iz, it, w, velocity, acceleration)
        return velocity.reshape(points.shape), acceleration.reshape(points.shape)

    def _add_current(self, current, flat, ix, iy, iz, it, w, velocity, acceleration):
        """A current sampled at the grid's nodes around each point and at its samples."""
        nodes = np.empty(flat.shape[:1] + (2, 2, 2, 3))
        for a in range(2):
            for b in range(2):
                for c in range(2):
                    nodes[:, a, b, c] = np.stack([self.px[ix[a]], self.py[iy[b]],
                                                  self.pz[iz[c]]], axis=-1)
        for d in range(2):
            v, acc = current.kinematics(nodes, it[d] * self.dt)
            velocity += np.einsum("pabz,pabzc->pc", w[..., d], v)
            acceleration += np.einsum("pabz,pabzc->pc", w[..., d], acc)


def evenly_spaced(omega, amplitude, beta):
    """MoorDyn's interpEvenlySpaced: components at i dw, dw the smallest spacing of the
    given (increasing) omegas, up to the last, amplitude and heading linear in between."""
    dw = np.min(np.diff(omega))
    grid = np.arange(int(np.floor(omega[-1] / dw)) + 1) * dw
    i0, i1, f = interpolation(omega, grid)
    return (grid, (1 - f) * amplitude[i0] + f * amplitude[i1], (1 - f) * beta[i0] + f * beta[i1])


def elevation_spectrum(times, elevations, dt):
    """Frequency components (omega, c, beta) of an elevation record resampled every dt
    (s) up to its last time (an even number of samples), as MoorDyn's WaveKin 3: the
    forward FFT scaled by 2 / n (so that :class:`WaveGrid` returns the record),
    components above 0.5 Hz dropped, all travelling along +x."""
    n = int(np.floor(times[-1] / dt)) + 1
    n -= n % 2
    samples = np.interp(np.arange(n) * dt, times, elevations)
    c = np.fft.rfft(samples) * (2.0 / n)
    omega = np.arange(c.size) * 2 * np.pi / (n * dt)
    c[omega > np.pi] = 0.0
    return omega, c, np.zeros(c.size)


class SpectrumWaves:
    """Waves summed from frequency components at the points (MoorDyn's WaveKin 7):
    elevation sum a_i sin(omega_i t - k_i l_i + phi_i), a_i = |c_i|, phi_i = arg c_i,
    l_i = x cos beta_i + y sin beta_i; linear kinematics in the mean depth, stretched."""

    has_acceleration = True

    def __init__(self, omega, amplitude, beta, stretching, g=9.81):
        from .waves import wavenumber

        self.omega = np.asarray(omega, float)
        c = np.asarray(amplitude, complex)
        self.a, self.phi = np.abs(c), np.angle(c)
        self.beta = np.asarray(beta, float)
        self.stretching = stretching
        depth = stretching.depth
        positive = self.omega > 0
        self.k = np.where(positive, wavenumber(np.where(positive, self.omega, 1.0), depth, g),
                          0.0)

    def steady_parts(self):
        """No steady part."""
        return []

    def _phase(self, xy, t):
        along = xy[..., 0, None] * np.cos(self.beta) + xy[..., 1, None] * np.sin(self.beta)
        return self.omega * t - self.k * along + self.phi

    def elevation(self, xy, t=0.0):
        return np.sin(self._phase(np.asarray(xy, float), t)) @ self.a

    def kinematics(self, points, t=0.0):
        # u_h = a w ch sin(theta) e, w = a w sh cos(theta); du_h/dt = a w^2 ch cos(theta) e,
        # dw/dt = -a w^2 sh sin(theta)  (theta the phase of the elevation a sin(theta))
        points = np.asarray(points, float)
        theta = self._phase(points, t)
        sin, cos = np.sin(theta), np.cos(theta)
        zeta = sin @ self.a
        ch, sh = linear_factors(self.k, self.stretching(points, zeta), self.stretching.depth)
        aw, aw2 = self.a * self.omega, self.a * self.omega**2
        e = np.stack([np.cos(self.beta), np.sin(self.beta)], axis=-1)  # (n, 2)
        vel = np.empty(points.shape)
        acc = np.empty(points.shape)
        vel[..., :2] = (ch * sin * aw) @ e
        vel[..., 2] = (sh * cos) @ aw
        acc[..., :2] = (ch * cos * aw2) @ e
        acc[..., 2] = -((sh * sin) @ aw2)
        return vel, acc


class CurrentGrid:
    """A current tabulated on a grid (MoorDyn's Currents 1, 2 and 5): axes px, py, pz (m),
    nt samples dt (s) apart of the velocity (nx, ny, nz, nt, 3); not stretched, no
    acceleration (MoorDyn's current grids carry none)."""

    has_acceleration = False

    def __init__(self, px, py, pz, dt, velocity):
        self.px, self.py, self.pz = _axis("CurrentGrid x", px), _axis("CurrentGrid y", py), \
            _axis("CurrentGrid z", pz)
        check_positive("CurrentGrid dt", dt)
        self.dt = float(dt)
        self.velocity = np.asarray(velocity, float)
        self.nt = self.velocity.shape[3] if self.velocity.ndim == 5 else 0
        if self.velocity.shape != (self.px.size, self.py.size, self.pz.size, self.nt, 3) \
                or self.nt < 1:
            raise ValueError(f"CurrentGrid: velocity of shape {self.velocity.shape} does not "
                             f"fit the grid ({self.px.size}, {self.py.size}, {self.pz.size}, "
                             "nt, 3)")

    def steady_parts(self):
        """The current itself (time-varying ones too: MoorDyn's IC solve sees them)."""
        return [self]

    def elevation(self, xy, t=0.0):
        return np.zeros(np.asarray(xy).shape[:-1])

    def kinematics(self, points, t=0.0):
        points = np.asarray(points, float)
        i0, i1, f = time_interpolation(self.nt, self.dt, t)
        values = (1 - f) * self.velocity[..., i0, :] + f * self.velocity[..., i1, :]
        vel = _trilinear(values, interpolation(self.px, points[..., 0]),
                         interpolation(self.py, points[..., 1]),
                         interpolation(self.pz, points[..., 2]))
        return vel, np.zeros(points.shape)


def resampled_current(px, py, pz, times, velocity):
    """A :class:`CurrentGrid` from velocities (nx, ny, nz, len(times), 3) at increasing
    times (s), resampled as MoorDyn does: every dt (the smallest time step) from 0 to the
    last time, linear in between, held before the first."""
    times = _axis("current times", times)
    if times.size == 1:
        return CurrentGrid(px, py, pz, 1.0, velocity)
    dt = float(np.min(np.diff(times)))
    samples = np.arange(int(np.floor(times[-1] / dt)) + 1) * dt
    i0, i1, f = interpolation(times, samples)
    f = f[:, None]
    return CurrentGrid(px, py, pz, dt, (1 - f) * velocity[..., i0, :] + f * velocity[..., i1, :])
