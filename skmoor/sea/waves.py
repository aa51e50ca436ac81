"""Water kinematics: currents, linear (Airy) waves, JONSWAP seas, and their sum.

Axes: z up, z = 0 the mean free surface, the seabed at z = -depth. A heading is the
direction the water moves (current) or the waves travel, in degrees from +x towards +y.
Points are arrays (..., 3) in m, times in s; velocities come back as (..., 3) in m/s,
accelerations in m/s2, elevations as (...) in m.

Linear wave kinematics are those of the mean water column: above z = 0 they are taken
at z = 0 (no stretching), below the seabed at z = -depth.
"""
from __future__ import annotations

from contextlib import contextmanager
from functools import lru_cache

import numpy as np

from ..numerics.validation import check_finite, check_positive

G = 9.81


def wavenumber(omega, depth, g=G):
    """k (rad/m) of the linear dispersion relation omega^2 = g k tanh(k h), solved by
    Newton on x tanh x = omega^2 h / g (x = k h) from Eckart's estimate, to round-off."""
    omega = np.asarray(omega, float)
    y = omega**2 * depth / g
    x = y / np.sqrt(np.tanh(y))  # Eckart (1952), within 5 %
    for _ in range(50):
        th = np.tanh(x)
        step = (x * th - y) / (th + x * (1.0 - th**2))
        x = x - step
        if np.all(np.abs(step) <= 1e-15 * x):
            break
    return x / depth


def _heading(name, heading_deg):
    check_finite(name, heading_deg)
    angle = np.radians(heading_deg)
    return np.array([np.cos(angle), np.sin(angle)])


def _points(name, points):
    points = np.asarray(points, float)
    if points.shape[-1:] != (3,):
        raise ValueError(f"{name}: points must have shape (..., 3), got {points.shape}")
    return points


class Current:
    """A steady horizontal current: uniform (``speed``, m/s) or a depth profile
    ``profile=[(z, speed), ...]`` (z in m, up; linear in between, constant beyond the
    ends). Give one of the two. ``heading_deg``: the direction the water flows to."""

    def __init__(self, speed=None, heading_deg=0.0, profile=None):
        if (speed is None) == (profile is None):
            raise ValueError("Current: give either speed (uniform, m/s) or "
                             "profile=[(z, speed), ...], not both and not neither")
        self.direction = _heading("Current heading_deg", heading_deg)
        if profile is None:
            check_finite("Current speed", speed)
            self.z, self.speeds = np.array([0.0]), np.array([float(speed)])
        else:
            table = np.asarray(profile, float)
            if table.ndim != 2 or table.shape[1] != 2 or len(table) < 1:
                raise ValueError(f"Current profile: need [(z, speed), ...] pairs, got shape "
                                 f"{table.shape}")
            check_finite("Current profile", table)
            order = np.argsort(table[:, 0])
            self.z, self.speeds = table[order, 0], table[order, 1]
            if np.any(np.diff(self.z) <= 0):
                raise ValueError("Current profile: two entries at the same z")

    def speed(self, z):
        """Current speed (m/s) at heights z (m)."""
        return np.interp(z, self.z, self.speeds)

    def velocity(self, points, t=0.0):
        """(..., 3) water velocity at points (..., 3), m/s (steady: t is unused)."""
        points = _points("Current.velocity", points)
        out = np.zeros(points.shape)
        out[..., :2] = self.speed(points[..., 2])[..., None] * self.direction
        return out


class _Components:
    """A long-crested sum of Airy components: amplitudes a (m), circular frequencies
    omega (rad/s), phases (rad), all travelling along one heading in depth h."""

    def _setup(self, amplitudes, omegas, phases, depth, heading_deg, g, name):
        check_positive(f"{name} depth", depth)
        check_positive(f"{name} g", g)
        self.depth, self.g = float(depth), float(g)
        self.direction = _heading(f"{name} heading_deg", heading_deg)
        self.a = np.atleast_1d(np.asarray(amplitudes, float))
        self.omega = np.atleast_1d(np.asarray(omegas, float))
        self.phi = np.atleast_1d(np.asarray(phases, float))
        self.k = wavenumber(self.omega, self.depth, self.g)
        # 1 / (1 - exp(-2 k h)): the depth factors' scale (cosh k(z+h) / sinh kh =
        # (exp(kz) + exp(-k(z+2h))) depth_scale), per component
        self.depth_scale = 1.0 / (1.0 - np.exp(-2.0 * self.k * self.depth))

    def _phase(self, xy, t):
        """(..., n) phase k (x cos b + y sin b) - omega t + phi (t a scalar or an array
        broadcasting with xy[..., 0])."""
        along = xy[..., 0] * self.direction[0] + xy[..., 1] * self.direction[1]
        return along[..., None] * self.k - np.asarray(t, float)[..., None] * self.omega + self.phi

    def _depth_factors(self, z):
        """(..., n) cosh k(z+h) / sinh kh and sinh k(z+h) / sinh kh, z clipped to
        [-h, 0]; written with exp(-2 k h) so deep water does not overflow."""
        z = np.clip(z, -self.depth, 0.0)[..., None]
        up = np.exp(self.k * z)
        down = np.exp(-self.k * (z + 2.0 * self.depth))
        return (up + down) * self.depth_scale, (up - down) * self.depth_scale

    def elevation(self, xy, t=0.0):
        """Free-surface elevation (m) at horizontal positions xy (..., 2 or 3) and times t."""
        xy = np.asarray(xy, float)
        return np.cos(self._phase(xy, t)) @ self.a

    def kinematics(self, points, t=0.0):
        """Water particle velocity (m/s) and local acceleration (m/s2), (..., 3) each, at
        points (..., 3): u = a w ch cos(theta) e, w = a w sh sin(theta);
        du/dt = a w^2 ch sin(theta) e, dw/dt = -a w^2 sh cos(theta)."""
        points = _points(type(self).__name__, points)
        theta = self._phase(points, t)
        ch, sh = self._depth_factors(points[..., 2])
        cos, sin = np.cos(theta), np.sin(theta)
        aw, aw2 = self.a * self.omega, self.a * self.omega**2
        velocity = np.empty(theta.shape[:-1] + (3,))
        acceleration = np.empty_like(velocity)
        velocity[..., :2] = ((ch * cos) @ aw)[..., None] * self.direction
        velocity[..., 2] = (sh * sin) @ aw
        acceleration[..., :2] = ((ch * sin) @ aw2)[..., None] * self.direction
        acceleration[..., 2] = -((sh * cos) @ aw2)
        return velocity, acceleration

    def velocity(self, points, t=0.0):
        """(..., 3) water particle velocity at points (..., 3), m/s."""
        return self.kinematics(points, t)[0]

    def acceleration(self, points, t=0.0):
        """(..., 3) water particle acceleration (local, linear) at points (..., 3), m/s2."""
        return self.kinematics(points, t)[1]


class AiryWave(_Components):
    """A linear regular wave of height H (m, crest to trough) and period T (s) in water
    of depth h (m): elevation (H/2) cos(k x' - omega t + phase), x' along the heading,
    k from the finite-depth dispersion relation (:func:`wavenumber`)."""

    def __init__(self, height, period, depth, heading_deg=0.0, phase=0.0, g=G):
        check_positive("AiryWave height", height)
        check_positive("AiryWave period", period)
        check_finite("AiryWave phase", phase)
        self.height, self.period = float(height), float(period)
        self._setup(0.5 * height, 2 * np.pi / period, phase, depth, heading_deg, g, "AiryWave")

    @property
    def wavenumber(self) -> float:
        """k, rad/m."""
        return float(self.k[0])

    @property
    def wavelength(self) -> float:
        """2 pi / k, m."""
        return 2 * np.pi / self.wavenumber


def jonswap_spectrum(f, Hs, Tp, gamma=3.3):
    """JONSWAP variance density S(f), m2/Hz, at frequencies f (Hz):
    S ~ f^-5 exp(-5/4 (fp/f)^4) gamma^r, r = exp(-(f - fp)^2 / (2 sigma^2 fp^2)),
    sigma = 0.07 (f <= fp) or 0.09, fp = 1/Tp, scaled so that 4 sqrt(m0) = Hs."""
    check_positive("jonswap_spectrum Hs", Hs)
    check_positive("jonswap_spectrum Tp", Tp)
    check_positive("jonswap_spectrum gamma", gamma)
    f = np.asarray(f, float)
    fp = 1.0 / Tp
    x = np.where(f > 0, f, 1.0) / fp
    shape = np.where(f > 0, _jonswap_shape(x, gamma), 0.0)
    return Hs**2 / 16.0 * shape / (fp * _jonswap_area(float(gamma)))


def _jonswap_shape(x, gamma):
    """Dimensionless JONSWAP shape at x = f / fp."""
    sigma = np.where(x <= 1.0, 0.07, 0.09)
    r = np.exp(-((x - 1.0) ** 2) / (2.0 * sigma**2))
    return x**-5.0 * np.exp(-1.25 * x**-4.0) * gamma**r


@lru_cache(maxsize=64)
def _jonswap_area(gamma):
    """int_0^inf shape(x) dx (1/5 for gamma = 1)."""
    from scipy.integrate import quad  # here: scipy.integrate is slow to import

    parts = [quad(_jonswap_shape, a, b, args=(gamma,), epsabs=0.0, epsrel=1e-13, limit=200)[0]
             for a, b in ((0.0, 1.0), (1.0, 2.0))]
    return sum(parts) + quad(_jonswap_shape, 2.0, np.inf, args=(gamma,), epsabs=0.0,
                             epsrel=1e-13, limit=200)[0]


class JonswapWave(_Components):
    """An irregular long-crested sea from the JONSWAP spectrum, as a sum of Airy components.

    n_components frequencies at the centres of equal bins over f_range (Hz; default
    0.5 / Tp to 5 / Tp), amplitudes sqrt(2 S(f) df), phases uniform in [0, 2 pi) from
    ``numpy.random.default_rng(seed)``: the same seed gives the same sea. The component
    frequencies are df apart, so records longer than 1 / df seconds repeat themselves
    (up to a common phase shift): raise n_components for longer records.
    """

    def __init__(self, Hs, Tp, depth, gamma=3.3, heading_deg=0.0, seed=0, n_components=200,
                 f_range=None, g=G):
        check_positive("JonswapWave Hs", Hs)
        check_positive("JonswapWave Tp", Tp)
        check_positive("JonswapWave gamma", gamma)
        if int(n_components) != n_components or n_components < 1:
            raise ValueError(f"JonswapWave n_components: must be a positive integer, "
                             f"got {n_components!r}")
        lo, hi = (0.5 / Tp, 5.0 / Tp) if f_range is None else map(float, f_range)
        if not 0.0 < lo < hi or not np.isfinite(hi):
            raise ValueError(f"JonswapWave f_range: need 0 < f_min < f_max (Hz), got {f_range!r}")
        self.Hs, self.Tp, self.gamma, self.seed = float(Hs), float(Tp), float(gamma), seed
        self.df = (hi - lo) / int(n_components)
        self.f = lo + self.df * (np.arange(int(n_components)) + 0.5)
        amplitudes = np.sqrt(2.0 * jonswap_spectrum(self.f, Hs, Tp, gamma) * self.df)
        phases = np.random.default_rng(seed).uniform(0.0, 2 * np.pi, int(n_components))
        self._setup(amplitudes, 2 * np.pi * self.f, phases, depth, heading_deg, g, "JonswapWave")


class Sea:
    """The water: depth (m), density rho (kg/m3; 0: in air, no buoyancy, drag or added
    mass), gravity g (m/s2), an optional
    :class:`Current`, any number of waves (:class:`AiryWave`, :class:`JonswapWave`) and
    of tabulated fields (:mod:`skmoor.sea.water_grids`: MoorDyn's wave and current files),
    superposed linearly."""

    def __init__(self, depth, rho=1025.0, g=G, current=None, waves=(), fields=()):
        check_positive("Sea depth", depth)
        check_finite("Sea rho", rho)
        if rho < 0:
            raise ValueError(f"Sea rho: must be >= 0 (0: no water: in air), got {rho!r}")
        check_finite("Sea g", g)
        if g < 0:
            raise ValueError(f"Sea g: must be >= 0 (0: no gravity, no waves), got {g!r}")
        self.depth, self.rho, self.g = float(depth), float(rho), float(g)
        if current is not None and not isinstance(current, Current):
            raise ValueError(f"Sea current: expected a Current or None, "
                             f"got {type(current).__name__}")
        self.current = current
        waves = [waves] if isinstance(waves, _Components) else list(waves)
        for i, wave in enumerate(waves):
            if not isinstance(wave, _Components):
                raise ValueError(f"Sea waves[{i}]: expected an AiryWave or JonswapWave, "
                                 f"got {type(wave).__name__}")
            if not np.isclose(wave.depth, self.depth, rtol=1e-12, atol=0.0):
                raise ValueError(f"Sea waves[{i}]: depth {wave.depth} m differs from the "
                                 f"sea's depth {self.depth} m")
            if not np.isclose(wave.g, self.g, rtol=1e-12, atol=0.0):
                raise ValueError(f"Sea waves[{i}]: g {wave.g} differs from the sea's g {self.g}")
        self.waves = waves
        self.fields = list(fields)
        for i, item in enumerate(self.fields):
            if not all(hasattr(item, name) for name in
                       ("kinematics", "elevation", "has_acceleration", "steady_parts")):
                raise ValueError(f"Sea fields[{i}]: a {type(item).__name__} is no water field "
                                 "(needs kinematics, elevation, has_acceleration and "
                                 "steady_parts)")

    @contextmanager
    def steady(self):
        """Within this context the sea is its steady part: the current and the current
        fields (each on its own grid), no waves; what a static solve sees (MoorDyn's
        initial-condition solve has its currents on and its waves off)."""
        saved = self.waves, self.fields
        self.waves = []
        self.fields = [part for item in saved[1] for part in item.steady_parts()]
        try:
            yield self
        finally:
            self.waves, self.fields = saved

    @property
    def has_waves(self) -> bool:
        """True when the water accelerates (waves or an accelerating field)."""
        return bool(self.waves) or any(item.has_acceleration for item in self.fields)

    @property
    def still(self) -> bool:
        """True without current, waves and fields."""
        return self.current is None and not self.waves and not self.fields

    def kinematics(self, points, t=0.0):
        """Water velocity (current + waves, m/s) and acceleration (m/s2) at points
        (..., 3), in one pass over the wave components."""
        points = _points("Sea.kinematics", points)
        velocity = (np.zeros(points.shape) if self.current is None
                    else self.current.velocity(points, t))
        acceleration = np.zeros(points.shape)
        for wave in self.waves + self.fields:
            v, a = wave.kinematics(points, t)
            velocity, acceleration = velocity + v, acceleration + a
        return velocity, acceleration

    def velocity(self, points, t=0.0):
        """(..., 3) water velocity at points (..., 3): current + waves + fields, m/s."""
        points = _points("Sea.velocity", points)
        out = np.zeros(points.shape) if self.current is None else self.current.velocity(points, t)
        for wave in self.waves:
            out = out + wave.velocity(points, t)
        for item in self.fields:
            out = out + item.kinematics(points, t)[0]
        return out

    def acceleration(self, points, t=0.0):
        """(..., 3) water acceleration at points (..., 3) (the current is steady), m/s2."""
        points = _points("Sea.acceleration", points)
        out = np.zeros(points.shape)
        for wave in self.waves:
            out = out + wave.acceleration(points, t)
        for item in self.fields:
            out = out + item.kinematics(points, t)[1]
        return out

    def elevation(self, xy, t=0.0):
        """Free-surface elevation (m) at horizontal positions xy (..., 2 or 3) and times t."""
        xy = np.asarray(xy, float)
        out = np.zeros(np.broadcast_shapes(xy.shape[:-1], np.shape(t)))
        for wave in self.waves + self.fields:
            out = out + wave.elevation(xy, t)
        return out
