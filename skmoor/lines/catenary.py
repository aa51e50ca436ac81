"""Analytic elastic catenary of a mooring line (Irvine), with frictionless seabed touchdown.

A line of unstretched length L (m), submerged weight w per unstretched length (N/m) and
axial stiffness EA (N) hangs from an anchor to a fairlead; its tension is T = EA * strain
(engineering strain), or any static strain law of :mod:`skmoor.lines.laws` (``law=``: a
tension-strain curve, ...), whose strain e(T) is piecewise linear in the tension, so that
the profile stays in closed form piece by piece. The line lies in the vertical plane through both ends. In that plane
x runs horizontally from the anchor towards the fairlead and z is up. With s the
unstretched arclength from the anchor (m), the tension has a constant horizontal component
H (N) and a vertical component V(s) = V_anchor + w s (N) along the suspended part. When the
anchor lies on the seabed, a part of length ``laid_length`` from the anchor may lie on it,
straight and without friction, carrying tension H; the suspended part starts at the
touchdown point with V = 0 (MoorPy's ``CB=0`` behaviour).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..numerics.roots import brent as brentq

__all__ = ["Catenary", "solve_catenary"]

_UP = np.array([0.0, 0.0, 1.0])
_RTOL = 4 * np.finfo(float).eps


@dataclass(frozen=True, eq=False)
class Catenary:
    """Static equilibrium of one elastic line between an anchor and a fairlead.

    anchor, fairlead   (3,) end positions, m
    direction          (3,) unit horizontal vector from anchor to fairlead ([1, 0, 0] if vertical)
    L                  unstretched length, m
    EA                 axial stiffness, N
    w                  submerged weight per unstretched length, N/m
    H                  horizontal component of the tension, N
    V_anchor           vertical component of the tension at the anchor, N (> 0: pulls the anchor up)
    laid_length        unstretched length lying on the seabed from the anchor, m
    law                the static strain law (:mod:`skmoor.lines.laws`; None: tension = EA x strain)
    """

    anchor: np.ndarray
    fairlead: np.ndarray
    direction: np.ndarray
    L: float
    EA: float
    w: float
    H: float
    V_anchor: float
    laid_length: float
    law: object = None

    def __post_init__(self):
        object.__setattr__(self, "_elastic", _Elasticity.of(self.law, self.EA))

    def strain(self, T) -> np.ndarray:
        """Engineering strain (-) of the law at tension T (N)."""
        return self._elastic.strain(np.asarray(T, float))

    @property
    def V_fairlead(self) -> float:
        """Vertical component of the tension at the fairlead, N: the upward pull it needs there."""
        return self.V_anchor + self.w * (self.L - self.laid_length)

    @property
    def T_anchor(self) -> float:
        """Tension at the anchor, N."""
        return math.hypot(self.H, self.V_anchor)

    @property
    def T_fairlead(self) -> float:
        """Tension at the fairlead, N."""
        return math.hypot(self.H, self.V_fairlead)

    def vertical_force(self, s) -> np.ndarray:
        """Vertical component of the tension (N) at unstretched arclengths s (m), (n,)."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        return self.V_anchor + self.w * np.maximum(s - self.laid_length, 0.0)

    def tension(self, s) -> np.ndarray:
        """Tension (N) at unstretched arclengths s (m), (n,)."""
        return np.hypot(self.H, self.vertical_force(s))

    def tangent(self, s) -> np.ndarray:
        """Unit tangent towards the fairlead at unstretched arclengths s (m), (n, 3)."""
        V = self.vertical_force(s)
        T = np.hypot(self.H, V)
        return (self.H * self.direction + V[:, None] * _UP) / T[:, None]

    def position(self, s) -> np.ndarray:
        """Positions (m) of the points at unstretched arclengths s (m), (n, 3)."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        x, z = _plane_offsets(s, self.H, self.V_anchor, self.laid_length, self.w,
                              self._elastic)
        return self.anchor + x[:, None] * self.direction + z[:, None] * _UP

    def stretched_arclength(self, s) -> np.ndarray:
        """Stretched length (m) from the anchor to arclengths s (m): int (1 + e(T)) ds, (n,)."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        el = self._elastic
        on_bed = np.minimum(s, self.laid_length)
        stretch = (el.strain(np.array([self.H]))[0] * on_bed
                   + (el.s_integral(self.H, self.vertical_force(s))
                      - el.s_integral(self.H, np.array([self.V_anchor]))) / self.w)
        return s + stretch

    def fairlead_force(self) -> np.ndarray:
        """Force the line exerts on the body at the fairlead, (3,) N."""
        return -(self.H * self.direction + self.V_fairlead * _UP)

    def anchor_force(self) -> np.ndarray:
        """Force the line exerts on the anchor, (3,) N."""
        return self.H * self.direction + self.V_anchor * _UP

    def sag(self) -> float:
        """Sag (m): distance from the mid-chord point to the line, perpendicular to the chord.

        Measured in the vertical plane of the line, positive below the chord.
        """
        span = float(np.dot(self.fairlead - self.anchor, self.direction))
        rise = float(self.fairlead[2] - self.anchor[2])
        chord = math.hypot(span, rise)

        def chord_coordinates(s):
            x, z = _plane_offsets(s, self.H, self.V_anchor, self.laid_length, self.w,
                                  self._elastic)
            return (x * span + z * rise) / chord, (x * rise - z * span) / chord

        s_mid = brentq(lambda s: chord_coordinates(s)[0] - 0.5 * chord, 0.0, self.L,
                       xtol=1e-15 * self.L, rtol=_RTOL)
        return float(chord_coordinates(s_mid)[1])


def solve_catenary(anchor, fairlead, w, EA, *, length=None, horizontal_tension=None,
                   sag_ratio=None, seabed_z=None, law=None) -> Catenary:
    """Static shape and forces of an elastic catenary between ``anchor`` and ``fairlead``.

    anchor, fairlead     3-vectors, m
    w                    submerged weight per unstretched length, N/m (> 0)
    EA                   axial stiffness, N (> 0)
    Give exactly one of:
      length             unstretched length L, m
      horizontal_tension horizontal component H of the tension, N
      sag_ratio          d/l in (0, 0.5): sag d perpendicular to the chord at mid-chord over
                         the chord length l (L is found by a 1-D root find)
    seabed_z             seabed height, m. When the anchor lies on it (within 1e-9 of the
                         depth), part of the line may lie on the seabed (no friction). Without
                         it the line is fully suspended and may dip below both ends.
    law                  the static strain law (a :class:`skmoor.lines.laws.Law`; None or
                         'engineering'/'paper': tension = EA x engineering strain)

    The strain must stay below 1; a line that would need more is "too short" and
    raises ValueError, as does any invalid input (the message names it).
    """
    anchor = _point("anchor", anchor)
    fairlead = _point("fairlead", fairlead)
    w = _positive("w", w)
    EA = _positive("EA", EA)
    if isinstance(law, str):
        from .laws import as_law
        law = as_law(law, "law")
    problem = _Problem.between(anchor, fairlead, w, EA, _touchdown(anchor, fairlead, seabed_z),
                               law)
    given = [name for name, value in [("length", length),
                                      ("horizontal_tension", horizontal_tension),
                                      ("sag_ratio", sag_ratio)] if value is not None]
    if len(given) != 1:
        raise ValueError("length, horizontal_tension, sag_ratio: give exactly one, "
                         f"got {given or 'none'}")
    if length is not None:
        line = problem.with_length(_positive("length", length))
    elif horizontal_tension is not None:
        line = problem.with_tension(_positive("horizontal_tension", horizontal_tension))
    else:
        line = problem.with_sag(_sag_ratio(sag_ratio))
    _check_strain(given[0], line)
    if seabed_z is not None and not problem.touchdown:
        _check_above_seabed(line, float(seabed_z))
    return line


@dataclass(frozen=True)
class _Problem:
    """The line's ends, span and rise (m) in its vertical plane, and its properties."""

    anchor: np.ndarray
    fairlead: np.ndarray
    direction: np.ndarray
    span: float
    rise: float
    w: float
    EA: float
    touchdown: bool
    law: object = None

    @cached_property
    def elastic(self):
        return _Elasticity.of(self.law, self.EA)

    @classmethod
    def between(cls, anchor, fairlead, w, EA, touchdown, law=None):
        offset = fairlead - anchor
        span = math.hypot(offset[0], offset[1])
        chord = math.hypot(span, offset[2])
        if chord == 0.0:
            raise ValueError("fairlead: coincides with the anchor")
        if span <= 1e-12 * chord:
            span, direction = 0.0, np.array([1.0, 0.0, 0.0])
        else:
            direction = np.array([offset[0] / span, offset[1] / span, 0.0])
        return cls(anchor, fairlead, direction, span, float(offset[2]), w, EA, touchdown, law)

    @property
    def chord(self) -> float:
        return math.hypot(self.span, self.rise)

    def split(self, L, v):
        """(V_anchor, laid_length) of a line whose tension would have vertical component
        v + w s (N) if it were fully suspended: with touchdown, v < 0 means a laid part."""
        if self.touchdown and v < 0.0:
            return 0.0, min(-v / self.w, L)
        return v, 0.0

    def end_offsets(self, L, H, v):
        """Span and rise (m) reached at s = L."""
        return _plane_offsets(L, H, *self.split(L, v), self.w, self.elastic)

    def anchor_vertical_force(self, L, H):
        """v (see split) for which the line of length L (m) reaches the rise, given H (N).

        The rise grows monotonically with v, which is bracketed by bounding T_fairlead -
        T_anchor to [-w L, w L] (suspended) or by a fully laid line (touchdown), EA the
        law's stiffest slope."""
        w, EA = self.w, self.elastic.stiffest
        high = max((self.rise + L) * EA / L - 0.5 * w * L, 0.0)
        low = -w * L if self.touchdown else (self.rise - L) * EA / L - 0.5 * w * L
        return brentq(lambda v: float(self.end_offsets(L, H, v)[1]) - self.rise, low, high,
                      xtol=1e-15 * w * L, rtol=_RTOL)

    def longest_length(self) -> float:
        """Longest unstretched length (m) that stays taut; infinite without touchdown.

        With touchdown it is the L-shaped line: laid along the whole span, then hanging
        vertically (unstretched hanging length h solves h + int e(w s) ds = rise)."""
        if not self.touchdown:
            return math.inf
        if self.elastic.linear:
            EA = self.elastic.stiffest
            hanging = 2.0 * self.rise / (1.0 + math.sqrt(1.0 + 2.0 * self.w * self.rise / EA))
        else:
            def reach(h):  # the hanging part's rise, h + int e, less the fairlead's
                return float(_plane_offsets(h, 0.0, 0.0, 0.0, self.w, self.elastic)[1]) - self.rise
            hanging = brentq(reach, 0.0, self.rise, xtol=1e-15 * self.rise, rtol=_RTOL)
        return self.span + hanging

    def build(self, L, H, v) -> Catenary:
        V_anchor, laid_length = self.split(L, v)
        return Catenary(self.anchor, self.fairlead, self.direction, L, self.EA, self.w,
                        H, V_anchor, laid_length, self.law)

    def with_length(self, L) -> Catenary:
        """Solve for H: the span reached grows with H (from the shortest, at H -> 0)."""
        if L >= self.longest_length():
            raise ValueError(f"length: {L:g} m is too long: the line would lie slack on the "
                             f"seabed (it must be shorter than {self.longest_length():g} m)")
        if self.span == 0.0:
            return self.build(L, 0.0, self.anchor_vertical_force(L, 0.0))

        H0 = _horizontal_tension_guess(self, L)
        if self.elastic.linear:
            solved = self._newton_length(L, H0)
            if solved is not None:
                return self.build(L, *solved)

        def span_error(H):
            return float(self.end_offsets(L, H, self.anchor_vertical_force(L, H))[0]) - self.span

        H = _root_of_increasing(span_error, H0, 10.0)
        return self.build(L, H, self.anchor_vertical_force(L, H))

    def _newton_length(self, L, H, iterations=60):
        """(H, v) of the linear-law line of length L by Newton on both end offsets at once
        (the Jacobian in closed form, as MoorPy / FAST solve it), from H (N); None when it
        does not converge (the nested bracketed solves then take over)."""
        w, c, X, Z = self.w, self.elastic.compliance, self.span, self.rise
        lam = math.sqrt(3.0 * ((L * L - Z * Z) / (X * X) - 1.0)) if L > self.chord else 0.2
        v = 0.5 * w * (Z / math.tanh(lam) + L) - w * L
        for _ in range(iterations):
            x, z, J = _linear_offsets_and_jacobian(L, H, v, w, c, self.touchdown)
            ex, ez = x - X, z - Z
            det = J[0][0] * J[1][1] - J[0][1] * J[1][0]
            if not det or not math.isfinite(det):
                return None
            dH = -(J[1][1] * ex - J[0][1] * ez) / det
            dv = -(-J[1][0] * ex + J[0][0] * ez) / det
            step = 1.0
            while H + step * dH <= 0.0 or (self.touchdown and v + step * dv <= -w * L):
                step *= 0.5  # H stays positive, some of the line hanging
            H, v = H + step * dH, v + step * dv
            if step == 1.0 and abs(dH) <= 1e-12 * H and abs(dv) <= 1e-12 * (abs(v) + w * L):
                return H, v
        return None

    def with_tension(self, H) -> Catenary:
        """Solve for L: at fixed H the span reached grows with L."""
        if self.span == 0.0:
            raise ValueError("horizontal_tension: a vertical line has H = 0; give length")
        if self.elastic.strain(np.array([H]))[0] >= 1.0:
            raise ValueError(f"horizontal_tension: {H:g} N would strain the line by 1 or "
                             f"more (EA = {self.EA:g} N)")

        def span_error(L):
            return float(self.end_offsets(L, H, self.anchor_vertical_force(L, H))[0]) - self.span

        L = _root_of_increasing(span_error, self.chord, 2.0)
        return self.build(L, H, self.anchor_vertical_force(L, H))

    def with_sag(self, ratio) -> Catenary:
        """Solve for L: the sag grows with L, from the strain limit towards sag_ratio_limit."""
        if self.span == 0.0:
            raise ValueError("sag_ratio: a vertical line has no sag; give length")
        if ratio >= self.sag_ratio_limit():
            raise ValueError(f"sag_ratio: {ratio:g} is too large for this geometry: no line "
                             f"length reaches it (the limit is {self.sag_ratio_limit():g})")
        shortest, longest = 0.5 * self.chord, self.longest_length()
        target = ratio * self.chord
        # A parabola of sag d over a chord l has length l (1 + 8/3 (d/l)^2).
        low = high = min(self.chord * (1.0 + 8.0 / 3.0 * ratio ** 2), 0.5 * (shortest + longest))
        while (line := self.with_length(low)).sag() >= target:
            _check_strain("sag_ratio", line)
            low = 0.5 * (low + shortest)
        while (line := self.with_length(high)).sag() <= target:
            _check_strain("sag_ratio", line)
            high = 0.5 * (high + longest) if self.touchdown else 2.0 * high
        L = brentq(lambda L: self.with_length(L).sag() - target, low, high,
                   xtol=1e-15 * low, rtol=_RTOL)
        return self.with_length(L)

    def sag_ratio_limit(self) -> float:
        """Sag ratio approached by ever longer lines, never reached.

        Suspended, the line tends to two vertical branches below the ends, which the
        mid-chord perpendicular meets at sag ratio span / (2 |rise|). With touchdown it tends
        to the L-shape laid along the span, then vertical, met at min(span/rise, rise/span) / 2.
        """
        branches = 0.5 * self.span / abs(self.rise) if self.rise else math.inf
        return min(branches, 0.5 * self.rise / self.span) if self.touchdown else branches


def _linear_offsets_and_jacobian(L, H, v, w, c, touchdown):
    """End offsets (x, z) (m) of a line of length L with tension = EA x strain (c = 1/EA)
    and their derivatives [[x_H, x_v], [z_H, z_v]] (m/N); v as in _Problem.split."""
    VF = v + w * L
    TF = math.hypot(H, VF)
    aF = math.asinh(VF / H)
    if touchdown and v < 0.0:  # laid length -v / w, no vertical force at touchdown
        x = -v / w + H * aF / w + c * H * L
        z = (TF - H) / w + 0.5 * c * VF * VF / w
        xv = (H / TF - 1.0) / w
        return x, z, (((aF - VF / TF) / w + c * L, xv), (xv, VF / (TF * w) + c * VF / w))
    TA = math.hypot(H, v)
    aA = math.asinh(v / H)
    x = H * (aF - aA) / w + c * H * L
    z = (TF - TA) / w + c * (v + 0.5 * w * L) * L
    xv = (H / TF - H / TA) / w
    return x, z, (((aF - VF / TF - aA + v / TA) / w + c * L, xv),
                  (xv, (VF / TF - v / TA) / w + c * L))


def _plane_offsets(s, H, V_anchor, laid_length, w, elastic):
    """Horizontal and vertical offsets (m) from the anchor at unstretched arclengths s (m)."""
    on_bed = np.minimum(s, laid_length)
    hanging = np.maximum(s - laid_length, 0.0)
    V = V_anchor + w * hanging
    rigid_x = on_bed + (_h_asinh(H, V) - _h_asinh(H, V_anchor)) / w
    rigid_z = (np.hypot(H, V) - math.hypot(H, V_anchor)) / w
    if elastic.linear:  # tension = EA x strain: H s / EA and (V_A + w h / 2) h / EA
        return (rigid_x + elastic.compliance * H * s,
                rigid_z + elastic.compliance * (V_anchor + 0.5 * w * hanging) * hanging)
    Va = np.array([V_anchor])
    x = (rigid_x + on_bed * elastic.strain(np.array([H]))[0]
         + (elastic.x_integral(H, V) - elastic.x_integral(H, Va)[0]) / w)
    z = rigid_z + (elastic.z_integral(H, V) - elastic.z_integral(H, Va)[0]) / w
    return x, z


class _Elasticity:
    """A static law's strain e(T) = a_k + b_k T on T_k <= T < T_k+1 and the integrals of
    the elastic catenary along V (the vertical tension, T = hypot(H, V)), in closed form
    piece by piece: x: int e H/T dV, z: int e V/T dV, s: int e dV (from V = 0)."""

    def __init__(self, T_k, a, b):
        self.T_k, self.a, self.b = (np.asarray(v, float) for v in (T_k, a, b))
        self.linear = len(self.T_k) == 1 and self.a[0] == 0.0
        self.compliance = float(self.b[0])  # 1 / EA of a linear law
        self.stiffest = float(1.0 / np.min(self.b))

    @classmethod
    def of(cls, law, EA):
        if law is None:
            return cls([0.0], [0.0], [1.0 / EA])
        return cls(*law.static_pieces(EA))

    def strain(self, T):
        if self.linear:
            return self.compliance * T
        piece = np.clip(np.searchsorted(self.T_k, T, side="right") - 1, 0, len(self.T_k) - 1)
        return self.a[piece] + self.b[piece] * T

    def _integral(self, G, V, H, odd):
        """sum over the pieces of G(c) - G(low), c = |V| clipped to each piece, V's shape."""
        V = np.asarray(V, float)
        low = np.sqrt(np.maximum(self.T_k**2 - H * H, 0.0))
        c = np.clip(np.abs(V)[..., None], low, np.r_[low[1:], np.inf])
        total = np.sum(G(c) - G(low), axis=-1)
        return np.sign(V) * total if odd else total

    def x_integral(self, H, V):
        return self._integral(lambda c: self.a * _h_asinh(H, c) + self.b * H * c, V, H, True)

    def z_integral(self, H, V):
        return self._integral(lambda c: self.a * np.hypot(H, c) + 0.5 * self.b * c * c,
                              V, H, False)

    def s_integral(self, H, V):
        if self.linear:
            return self.b[0] * _tension_antiderivative(H, np.asarray(V, float))
        return self._integral(lambda c: self.a * c + self.b * _tension_antiderivative(H, c),
                              V, H, True)


def _h_asinh(H, V):
    """H asinh(V / H), N, with its limit 0 at H = 0."""
    return H * np.arcsinh(V / H) if H > 0.0 else np.zeros_like(V)


def _tension_antiderivative(H, V):
    """Integral of sqrt(H^2 + V^2) dV, N^2: (V T + H^2 asinh(V / H)) / 2."""
    return 0.5 * (V * np.hypot(H, V) + H * _h_asinh(H, V))


def _horizontal_tension_guess(problem, L):
    """Initial H (N) of Peyrot & Goulois (as in FAST / MoorPy)."""
    X, Z = problem.span, problem.rise
    if L <= problem.chord:
        lam = 0.2
    else:
        lam = math.sqrt(3.0 * ((L * L - Z * Z) / (X * X) - 1.0))
    return 0.5 * problem.w * X / lam


def _root_of_increasing(f, x0, factor):
    """Root of an increasing function f of x > 0, bracketed by scaling x0 by factor."""
    low = high = x0
    while f(high) < 0.0:
        low, high = high, high * factor
    while f(low) > 0.0:
        low, high = low / factor, low
    return brentq(f, low, high, xtol=1e-15 * low, rtol=_RTOL)


def _max_tension(line: Catenary) -> float:
    """Largest tension (N), at one of the ends since |V| is monotonic along the line."""
    return max(line.T_anchor, line.T_fairlead)


def _check_strain(field, line: Catenary):
    strain = line.strain(np.array([_max_tension(line)]))[0]
    if strain > 1.0:
        limit = (f"above EA = {line.EA:g} N" if line.law is None or line._elastic.linear
                 else f"a strain of {strain:g} on the law's curve")
        raise ValueError(f"{field}: the line would need a tension of {_max_tension(line):g} N, "
                         f"{limit} (strain above 1; too short a line stretches "
                         "that much to span the anchor-fairlead distance)")


def _check_above_seabed(line: Catenary, seabed_z):
    s_low = -line.V_anchor / line.w
    if 0.0 < s_low < line.L and line.position(s_low)[0, 2] < seabed_z:
        raise ValueError("seabed_z: the suspended line would dip below the seabed; "
                         "touchdown is modelled only with the anchor on the seabed")


def _touchdown(anchor, fairlead, seabed_z):
    """Whether the anchor lies on the seabed (within 1e-9 of the depth |seabed_z|, or of the
    chord length if larger); raises if an end is below the seabed or the fairlead is on it."""
    if seabed_z is None:
        return False
    seabed_z = _finite("seabed_z", seabed_z)
    tol = 1e-9 * max(abs(seabed_z), float(np.linalg.norm(fairlead - anchor)))
    for name, point in (("anchor", anchor), ("fairlead", fairlead)):
        if point[2] < seabed_z - tol:
            raise ValueError(f"{name}: below the seabed "
                             f"(z = {point[2]:g} m < seabed_z = {seabed_z:g} m)")
    if fairlead[2] <= seabed_z + tol:
        raise ValueError("fairlead: lies on the seabed; touchdown is modelled at the anchor "
                         "only (swap anchor and fairlead if the anchor is above the seabed)")
    return anchor[2] <= seabed_z + tol


def _point(field, value):
    point = np.asarray(value, dtype=float)
    if point.shape != (3,) or not np.all(np.isfinite(point)):
        raise ValueError(f"{field}: must be 3 finite coordinates (m), got {value!r}")
    return point


def _finite(field, value):
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{field}: must be finite, got {value!r}")
    return value


def _positive(field, value):
    value = _finite(field, value)
    if value <= 0.0:
        raise ValueError(f"{field}: must be positive, got {value!r}")
    return value


def _sag_ratio(value):
    value = _finite("sag_ratio", value)
    if not 0.0 < value < 0.5:
        raise ValueError(f"sag_ratio: must lie in (0, 0.5), got {value!r}")
    return value
