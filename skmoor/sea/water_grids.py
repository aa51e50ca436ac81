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

The compiled kernels read the fields packed into one float buffer (:func:`packed_fields`)
and evaluate them at a point (:func:`field_kinematics`, :func:`field_elevation`) with the
same numbers as the classes' ``kinematics`` and ``elevation``.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

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


# --- the fields as the compiled kernels read them
CURRENT_GRID, SPECTRUM_WAVES, WAVE_GRID = 1.0, 2.0, 3.0  # a packed field's kind


def fields_lower(fields) -> bool:
    """Whether :func:`packed_fields` packs ``fields`` (every one a :class:`CurrentGrid`, a
    :class:`SpectrumWaves` or a :class:`WaveGrid` whose currents are current grids),
    without packing them."""
    return all(type(field) in (CurrentGrid, SpectrumWaves)
               or (type(field) is WaveGrid
                   and all(type(current) is CurrentGrid for current in field.currents))
               for field in fields)


def packed_fields(fields):
    """The fields as one float buffer for :func:`field_kinematics` and
    :func:`field_elevation`, or None when one is not a :class:`CurrentGrid`,
    :class:`SpectrumWaves` or :class:`WaveGrid` (with CurrentGrid currents): [count, then
    each field's kind and length and its numbers (see :func:`_packed_field`)]; [0] for none."""
    if not fields_lower(fields):
        return None
    return np.concatenate([[float(len(fields))], *map(_packed_field, fields)]).astype(float)


def _packed_field(field):
    """[kind, length of what follows, the field's numbers] of a field :func:`fields_lower`
    takes."""
    if type(field) is CurrentGrid:
        body = [[field.px.size, field.py.size, field.pz.size, field.nt, field.dt],
                field.px, field.py, field.pz, field.velocity.ravel()]
    elif type(field) is SpectrumWaves:
        body = [[field.omega.size], _packed_stretching(field.stretching), field.omega,
                field.k, field.a, field.phi, np.cos(field.beta), np.sin(field.beta)]
    else:  # a WaveGrid, its currents current grids
        currents = [_packed_field(current) for current in field.currents]
        body = [[field.omega.size, field.px.size, field.py.size, field.pz.size, field.nt,
                 field.dt, field.depth], _packed_stretching(field.stretching), field.px,
                field.py, field.pz, field.omega, field.k, field.c.real, field.c.imag,
                np.cos(field.beta), np.sin(field.beta), [len(currents)], *currents]
    body = np.concatenate([np.ravel(np.asarray(part, float)) for part in body])
    kind = {CurrentGrid: CURRENT_GRID, SpectrumWaves: SPECTRUM_WAVES, WaveGrid: WAVE_GRID}
    return np.concatenate([[kind[type(field)], body.size], body])


def _packed_stretching(stretching):
    """[mean depth h_m, nx, ny, the bed's x (nx), y (ny), heights (nx ny)] (nx = ny = 0:
    a flat bed at -h_m)."""
    grid = stretching.bathymetry
    if grid is None:
        return [stretching.depth, 0, 0]
    return np.concatenate([[stretching.depth, grid.x.size, grid.y.size], grid.x, grid.y,
                           np.ravel(grid.heights)])


@njit(cache=True)
def cell(axis, x):
    """:func:`interpolation` of one value: (i0, i1, f), held at the axis' ends."""
    if axis.size == 1:
        return 0, 0, 0.0
    i1 = min(max(np.searchsorted(axis, x), 1), axis.size - 1)
    f = min(max((x - axis[i1 - 1]) / (axis[i1] - axis[i1 - 1]), 0.0), 1.0)
    return i1 - 1, i1, f


@njit(cache=True)
def _time_cell(nt, dt, t):
    """:func:`time_interpolation` (i0, i1, f)."""
    if nt == 1:
        return 0, 0, 0.0
    q = t / dt
    step = math.floor(q)
    i1 = int((step + 1) % nt)
    return (i1 - 1 if i1 > 0 else 0), i1, q - step


@njit(cache=True)
def _factors(k, z, depth):
    """:func:`linear_factors` (ch, sh) of one component."""
    if k <= 0.0:
        return 0.0, 1.0
    scale = 1.0 / (1.0 - math.exp(-2.0 * k * depth))
    up, down = math.exp(k * z), math.exp(-k * (z + 2.0 * depth))
    return (up + down) * scale, (up - down) * scale


@njit(cache=True, inline="always")
def _stretching_end(F, at):
    """Where the packed :class:`Stretching` in F from ``at`` ends."""
    nx, ny = int(F[at + 1]), int(F[at + 2])
    return at + 3 + nx + ny + nx * ny


@njit(cache=True)
def _stretched(F, at, x, y, z, zeta):
    """:class:`Stretching`'s z_s (m) of (x, y, z) under the elevation zeta, its numbers in
    F from ``at``."""
    depth, nx, ny = F[at], int(F[at + 1]), int(F[at + 2])
    end = _stretching_end(F, at)
    bed = -depth
    if nx > 0:
        gx, gy = F[at + 3:at + 3 + nx], F[at + 3 + nx:at + 3 + nx + ny]
        heights = F[at + 3 + nx + ny:end].reshape(nx, ny)
        i0, i1, fx = cell(gx, x)
        j0, j1, fy = cell(gy, y)
        bed = ((1 - fx) * ((1 - fy) * heights[i0, j0] + fy * heights[i0, j1])
               + fx * ((1 - fy) * heights[i1, j0] + fy * heights[i1, j1]))
    return min(depth * (z - bed) / (zeta - bed) - depth, 0.0)


@njit(cache=True)
def _current_grid(F, at, x, y, z, t, weight, out):
    """out[0:3] += weight times :class:`CurrentGrid`'s velocity at (x, y, z), time t."""
    nx, ny, nz, nt, dt = int(F[at]), int(F[at + 1]), int(F[at + 2]), int(F[at + 3]), F[at + 4]
    at += 5
    px, py, pz = F[at:at + nx], F[at + nx:at + nx + ny], F[at + nx + ny:at + nx + ny + nz]
    velocity = F[at + nx + ny + nz:at + nx + ny + nz + nx * ny * nz * nt * 3].reshape(
        nx, ny, nz, nt, 3)
    t0, t1, ft = _time_cell(nt, dt, t)
    i0, i1, fx = cell(px, x)
    j0, j1, fy = cell(py, y)
    k0, k1, fz = cell(pz, z)
    for a in range(2):
        wa, i = _side(a, fx, i0, i1)
        for b in range(2):
            wb, j = _side(b, fy, j0, j1)
            for c in range(2):
                wc, k = _side(c, fz, k0, k1)
                w = weight * wa * wb * wc
                for d in range(3):
                    out[d] += w * ((1 - ft) * velocity[i, j, k, t0, d]
                                   + ft * velocity[i, j, k, t1, d])


@njit(cache=True)
def _spectrum(F, at, x, y, z, t, out, elevation_only):
    """:class:`SpectrumWaves` at (x, y, z), time t: its elevation returned and, unless
    ``elevation_only``, its velocity and acceleration added into out[0:6]."""
    n = int(F[at])
    stretch = at + 1
    at = _stretching_end(F, stretch)
    omega, k, a, phi = F[at:at + n], F[at + n:at + 2 * n], F[at + 2 * n:at + 3 * n], \
        F[at + 3 * n:at + 4 * n]
    cb, sb = F[at + 4 * n:at + 5 * n], F[at + 5 * n:at + 6 * n]
    zeta = 0.0
    for i in range(n):
        zeta += a[i] * math.sin(omega[i] * t - k[i] * (x * cb[i] + y * sb[i]) + phi[i])
    if elevation_only:
        return zeta
    z_s = _stretched(F, stretch, x, y, z, zeta)
    depth = F[stretch]
    for i in range(n):
        theta = omega[i] * t - k[i] * (x * cb[i] + y * sb[i]) + phi[i]
        ch, sh = _factors(k[i], z_s, depth)
        sin, cos = math.sin(theta), math.cos(theta)
        aw, aw2 = a[i] * omega[i], a[i] * omega[i] ** 2
        out[0] += ch * sin * aw * cb[i]
        out[1] += ch * sin * aw * sb[i]
        out[2] += sh * cos * aw
        out[3] += ch * cos * aw2 * cb[i]
        out[4] += ch * cos * aw2 * sb[i]
        out[5] -= sh * sin * aw2
    return zeta


@njit(cache=True)
def _wave_grid(F, at, x, y, z, t, out, elevation_only):
    """:class:`WaveGrid` at (x, y, z), time t: its elevation returned and, unless
    ``elevation_only``, its velocity and acceleration (its currents' included) added into
    out[0:6]."""
    n, nx, ny, nz, nt = int(F[at]), int(F[at + 1]), int(F[at + 2]), int(F[at + 3]), \
        int(F[at + 4])
    dt, depth = F[at + 5], F[at + 6]
    stretch = at + 7
    at = _stretching_end(F, stretch)
    px, py, pz = F[at:at + nx], F[at + nx:at + nx + ny], F[at + nx + ny:at + nx + ny + nz]
    at += nx + ny + nz
    omega, k = F[at:at + n], F[at + n:at + 2 * n]
    cr, ci = F[at + 2 * n:at + 3 * n], F[at + 3 * n:at + 4 * n]
    cb, sb = F[at + 4 * n:at + 5 * n], F[at + 5 * n:at + 6 * n]
    currents = at + 6 * n
    i0, i1, fx = cell(px, x)
    j0, j1, fy = cell(py, y)
    t0, t1, ft = _time_cell(nt, dt, t)
    # c e^{i theta} (real, imaginary) at the grid's nodes and samples around the point,
    # corner = 4 (x side) + 2 (y side) + (t side), and the corners' weights
    modes, weights, zeta = np.empty((8, n, 2)), np.empty(8), 0.0
    for corner in range(8):
        wa, xa = _side(corner >> 2, fx, px[i0], px[i1])
        wb, yb = _side((corner >> 1) & 1, fy, py[j0], py[j1])
        wt, td = _side(corner & 1, ft, t0 * dt, t1 * dt)
        weights[corner] = wa * wb * wt
        for i in range(n):
            theta = omega[i] * td - k[i] * (xa * cb[i] + yb * sb[i])
            modes[corner, i, 0] = cr[i] * math.cos(theta) - ci[i] * math.sin(theta)
            modes[corner, i, 1] = cr[i] * math.sin(theta) + ci[i] * math.cos(theta)
            zeta += weights[corner] * modes[corner, i, 0]
    if elevation_only:
        return zeta
    z_s = _stretched(F, stretch, x, y, z, zeta)
    k0, k1, fz = cell(pz, z_s)
    for c in range(2):
        wc, zc = _side(c, fz, pz[k0], pz[k1])
        for corner in range(8):
            w = weights[corner] * wc
            for i in range(n):
                # u_h = Re(w m ch) e, u_z = Re(i w m sh), their rates Re(i w .)
                mr, mi = modes[corner, i, 0], modes[corner, i, 1]
                ch, sh = _factors(k[i], zc, depth)
                wo, wo2 = w * omega[i], w * omega[i] ** 2
                out[0] += wo * ch * mr * cb[i]
                out[1] += wo * ch * mr * sb[i]
                out[2] -= wo * sh * mi
                out[3] -= wo2 * ch * mi * cb[i]
                out[4] -= wo2 * ch * mi * sb[i]
                out[5] -= wo2 * sh * mr
            record = currents + 1
            for _ in range(int(F[currents])):  # each current at the node and sample
                _current_grid(F, record + 2, _side(corner >> 2, fx, px[i0], px[i1])[1],
                              _side((corner >> 1) & 1, fy, py[j0], py[j1])[1], zc,
                              _side(corner & 1, ft, t0 * dt, t1 * dt)[1], w, out)
                record += 2 + int(F[record + 1])
    return zeta


@njit(cache=True, inline="always")
def _side(side, f, lower, upper):
    """(weight, coordinate) of a cell's ``side`` (0: lower, 1: upper) at fraction f."""
    return (1.0 - f, lower) if side == 0 else (f, upper)


@njit(cache=True)
def fields_accelerate(F):
    """Whether any of the packed fields F has an acceleration (waves: all but current
    grids), the fields' ``has_acceleration``."""
    at = 1
    for _ in range(int(F[0])):
        if F[at] != CURRENT_GRID:
            return True
        at += 2 + int(F[at + 1])
    return False


@njit(cache=True)
def _fields(x, y, z, t, F, out, elevation_only):
    """The packed fields' elevation at (x, y), time t, returned and, unless
    ``elevation_only``, their velocity and acceleration at (x, y, z) added into out[0:6]."""
    at, zeta = 1, 0.0
    for _ in range(int(F[0])):
        kind, length = F[at], int(F[at + 1])
        if kind == CURRENT_GRID:
            if not elevation_only:
                _current_grid(F, at + 2, x, y, z, t, 1.0, out)
        elif kind == SPECTRUM_WAVES:
            zeta += _spectrum(F, at + 2, x, y, z, t, out, elevation_only)
        else:
            zeta += _wave_grid(F, at + 2, x, y, z, t, out, elevation_only)
        at += 2 + length
    return zeta


@njit(cache=True)
def field_kinematics(x, y, z, t, F, out):
    """Adds the velocity (out[0:3], m/s) and acceleration (out[3:6], m/s2) of the packed
    fields F (:func:`packed_fields`) at (x, y, z) (m) and time t (s) into out: the
    fields' ``kinematics``."""
    _fields(x, y, z, t, F, out, False)


@njit(cache=True)
def field_elevation(x, y, t, F):
    """The free surface's elevation (m) of the packed fields F at (x, y) (m), time t (s)."""
    return _fields(x, y, 0.0, t, F, F[:0], True)
