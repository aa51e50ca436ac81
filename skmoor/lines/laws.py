"""Constitutive laws of the cables: the axial force as a function of the stretch.

A law is a small object chosen per line type (``LineType(law=...)``; a LineSet's or a
Network's ``law`` / ``strain_law`` is the default for line types without one). The same
law drives the cable forms (:mod:`skmoor.lines.cable_forms`), the compiled kernel
(:mod:`skmoor.lines.cable_kernel`) and the static reference state (the elastic catenary of
:mod:`skmoor.lines.catenary`, :func:`skmoor.coupling.build.reference_line`).

Strains. ``e`` is the engineering strain of the unstretched line (stretched length over
unstretched length, minus 1), as MoorDyn and MoorPy use it; ``eps = X'.u' + |u'|^2/2`` is
the paper's strain (Eq. 3) of the displacement from the reference state, whose stretch is
``lambda = sqrt(1 + 2 eps)``. A reference state of tension T and strain ``e_ref`` (with
``law.tension(e_ref) = T``) stretched by lambda has ``e = (1 + e_ref) lambda - 1``.

Laws (all tension-only by default: a slack cable carries no compression, as in MoorDyn;
``tension_only=False`` lets it push):

- :class:`Paper`: the paper's Eq. 6, ``S = EA eps`` added to T (tension (T + S) lambda);
- :class:`Engineering`: tension = EA e (Irvine's elastic catenary, MoorDyn, MoorPy);
- :class:`Curve`: a piecewise-linear tension-strain table (MoorDyn's EA curve files),
  extended beyond its last point with its last slope;
- :class:`StaticDynamic`: polyester's static and dynamic stiffness (MoorDyn's
  ``EA_s|EA_d`` and ``EA_s|alphaMBL|beta``): the static state is solved with the static
  law, the motion about it sees the dynamic stiffness EA_d (or alphaMBL + beta T_mean).

Every law is one pointwise function of per-element parameters (:func:`axial_force`),
written with :mod:`skmoor.fem.ops` so that automatic differentiation can trace it, and held
equal to the kernel's compiled copy by the tests:

    N(e) = T0 + k (e - e0) + sum_j c_j max(e - x_j, 0)     (tension, N)

with Paper marked apart (``green = 1``: S = EA eps). The reported tension of a line adds
the internal damping (MoorDyn's ``T + BA * strain rate``); see ``docs/laws.md``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..fem import ops

__all__ = ["Law", "Paper", "Engineering", "Curve", "StaticDynamic", "Viscoelastic", "as_law",
           "LAWS",
           "axial_force", "stress_resultant", "read_curve"]


def _value(a):
    """The array of a scikit-fem DiscreteField, the argument itself otherwise."""
    return np.asarray(a) if hasattr(a, "grad") else a


# ------------------------------------------------------------ the pointwise functions

def axial_force(e, p):
    """(N, dN/de): tension (N) and its slope (N) at engineering strain e (-) for the
    parameters p (mapping of arrays shaped like e: T0, e0, k, tension_only; hinges
    ``knots`` and ``coef`` with a leading axis of their count). A compressive N is kept
    times 1 - tension_only: 0 for a tension-only cable (1: it pushes; in between: the
    soft compression of a static solve's continuation)."""
    e = _value(e)
    T0, e0, k = _value(p["T0"]), _value(p["e0"]), _value(p["k"])
    N = T0 + k * (e - e0)
    dN = k + 0.0 * e
    knots, coef = _value(p["knots"]), _value(p["coef"])
    if knots.shape[0]:
        beyond = ops.xp(e).asarray(e)[None] - knots  # (a float e too)
        N = N + ops.dot(coef, ops.maximum(beyond, 0.0))
        dN = dN + ops.dot(coef, ops.where(beyond > 0, 1.0, 0.0))
    keep = ops.where(N < 0, 1.0 - _value(p["tension_only"]), 1.0)  # 0: a slack cable
    return keep * N, keep * dN


def stress_resultant(eps, T, p):
    """(S, dS/deps), N: the axial force added to the reference tension T (N) by the
    strain eps of Eq. 3, the internal force being (T + S) r' (Eq. 11).

    Paper (Eq. 6): S = EA eps. Others: S = N(e) / lambda - T with e = (1 + e_ref) lambda - 1,
    lambda = sqrt(1 + 2 eps). Tension-only: T + S >= 0."""
    eps, T = _value(eps), _value(T)
    lam = ops.sqrt(1.0 + 2.0 * eps)
    e_ref = _value(p["e_ref"])
    N, dN = axial_force((1.0 + e_ref) * lam - 1.0, p)
    S = N / lam - T
    dS = (dN * (1.0 + e_ref) / lam - N / lam**2) / lam
    EA = _value(p["EA"])
    keep = ops.where(T + EA * eps < 0, 1.0 - _value(p["tension_only"]), 1.0)
    S_paper = keep * (T + EA * eps) - T
    dS_paper = keep * EA + 0.0 * eps
    green = _value(p["green"]) > 0
    return ops.where(green, S_paper, S), ops.where(green, dS_paper, dS)


# ------------------------------------------------------------ the law objects

PARAMETERS = ("green", "tension_only", "T0", "e0", "k", "e_ref")


@dataclass(frozen=True)
class Law:
    """Base of the laws. tension_only: a slack cable carries no compression (default)."""

    tension_only: bool = True
    name = "law"

    # --- statics: the reference state
    def static_pieces(self, EA):
        """(T_k, a_k, b_k): the static strain e(T) = a_k + b_k T on T_k <= T < T_k+1 (the
        last piece unbounded), for the catenary; EA (N) is the line type's."""
        return np.array([0.0]), np.array([0.0]), np.array([1.0 / EA])

    def static_strain(self, T, EA=None):
        """Engineering strain (-) of the static law at tension T (N) >= 0."""
        T = np.asarray(T, float)
        T_k, a, b = self.static_pieces(EA)
        piece = np.maximum(np.searchsorted(T_k, T, side="right") - 1, 0)
        return a[piece] + b[piece] * T

    def static_tension(self, e, EA=None):
        """Tension (N) of the static law at engineering strain e (-) (0 when slack)."""
        T_k, a, b = self.static_pieces(EA)
        e_k = a + b * T_k
        e = np.asarray(e, float)
        piece = np.maximum(np.searchsorted(e_k, e, side="right") - 1, 0)
        T = (e - a[piece]) / b[piece]
        return np.maximum(T, 0.0) if self.tension_only else T

    def nominal_EA(self, EA):
        """The EA (N) that stands for the law where one number is needed (time steps,
        brackets): the line type's."""
        return EA

    # --- dynamics: the per-element parameters of axial_force / stress_resultant
    def parameters(self, EA, T, e_ref, static=False):
        """Per-point parameters (dict of arrays shaped like T) of the law for line-type
        EA (N), reference tension T (N) and strain e_ref (-); ``static``: those of the
        static law (StaticDynamic)."""
        ones = np.ones_like(T)
        return dict(green=0.0 * ones, tension_only=float(self.tension_only) * ones,
                    T0=0.0 * ones, e0=0.0 * ones, k=EA * ones, e_ref=e_ref * ones), None

    def tension(self, e, EA=None):
        """Tension (N) of the (static) law at engineering strain e (-) from a stress-free
        state; EA (N) the line type's where the law uses it. Traceable (skmoor.fem.ops)."""
        return self._pointwise(e, EA)[0]

    def slope(self, e, EA=None):
        """dT/de (N) at engineering strain e (-)."""
        return self._pointwise(e, EA)[1]

    def _pointwise(self, e, EA):
        shape = np.shape(_value(e))
        zeros = np.zeros(shape)
        p, hinges = self.parameters(1.0 if EA is None else EA, zeros, zeros, static=True)
        p.update(_hinges(hinges, shape))
        return axial_force(e, p)


@dataclass(frozen=True)
class Paper(Law):
    """The paper's law (Eq. 6): S = EA eps added to the reference tension, eps of Eq. 3;
    the reference state stretches as EA (T / EA strain)."""

    name = "paper"

    def parameters(self, EA, T, e_ref, static=False):
        p, _ = super().parameters(EA, T, e_ref)
        p["green"] = np.ones_like(T)
        return p, None

    def _pointwise(self, e, EA):
        # from a stress-free state: N = EA eps lambda, lambda = 1 + e, eps = (lambda^2 - 1) / 2
        lam = 1.0 + _value(e)
        eps = 0.5 * (lam * lam - 1.0)
        N, dN = EA * eps * lam, EA * (lam * lam + eps)
        if self.tension_only:
            return ops.where(N < 0, 0.0, N), ops.where(N < 0, 0.0, dN)
        return N, dN


@dataclass(frozen=True)
class Engineering(Law):
    """Tension = EA x engineering strain (N), EA the line type's (Irvine, MoorDyn)."""

    name = "engineering"


@dataclass(frozen=True)
class Curve(Law):
    """A tension-strain table: strain (-) and tension (N), both strictly increasing from
    (0, 0) (prepended when absent), linear in between and beyond the last point with the
    last slope (MoorDyn holds the last tension there). MoorDyn's EA curve files."""

    strain: tuple = ()
    tension_values: tuple = ()
    source: str = "Curve"  # names the curve in messages (a file, a deck line)
    name = "curve"

    def __init__(self, strain, tension, tension_only=True, source="Curve"):
        e, T = _check_curve(strain, tension, source)
        object.__setattr__(self, "tension_only", bool(tension_only))
        object.__setattr__(self, "strain", tuple(e))
        object.__setattr__(self, "tension_values", tuple(T))
        object.__setattr__(self, "source", source)

    @property
    def slopes(self) -> np.ndarray:
        """(n - 1,) slopes of the table's pieces, N."""
        return np.diff(self.tension_values) / np.diff(self.strain)

    def static_pieces(self, EA=None):
        e, T, s = np.array(self.strain), np.array(self.tension_values), self.slopes
        return T[:-1], e[:-1] - T[:-1] / s, 1.0 / s

    def nominal_EA(self, EA=None):
        """The last point's secant, N (MoorDyn's EA of a curve)."""
        return self.tension_values[-1] / self.strain[-1]

    def parameters(self, EA, T, e_ref, static=False):
        p, _ = super().parameters(EA, T, e_ref)
        s = self.slopes
        p["k"] = s[0] * np.ones_like(T)
        return p, (np.array(self.strain[1:-1]), np.diff(s))


@dataclass(frozen=True)
class StaticDynamic(Law):
    """Polyester's static and dynamic stiffness. The static state (catenary, FE statics)
    is solved with ``static`` (default: Engineering, the line type's EA as EA_s); the
    motion about it has tension T_mean + EA_d (e - e_mean), (T_mean, e_mean) the static
    state of each element, EA_d = ``EA_dynamic`` (N, MoorDyn's ``EA_s|EA_d``) or
    ``alpha_MBL + beta T_mean`` (MoorDyn's ``EA_s|alphaMBL|beta``: alpha_MBL in N, beta
    dimensionless). This is the limit of MoorDyn's viscoelastic model in which the mean
    stretch is held over the motion (motions faster than its creep time)."""

    EA_dynamic: float | None = None
    alpha_MBL: float | None = None
    beta: float = 0.0
    static: Law = field(default_factory=Engineering)
    name = "static-dynamic"

    def __post_init__(self):
        if (self.EA_dynamic is None) == (self.alpha_MBL is None):
            raise ValueError("StaticDynamic: give EA_dynamic or alpha_MBL (and beta), "
                             "not both / neither")
        for name in ("EA_dynamic", "alpha_MBL", "beta"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value >= 0):
                raise ValueError(f"StaticDynamic.{name}: must be a finite number >= 0, "
                                 f"got {value!r}")
        if self.EA_dynamic is not None and not self.EA_dynamic > 0:
            raise ValueError(f"StaticDynamic.EA_dynamic: must be > 0 N, got {self.EA_dynamic}")
        if isinstance(self.static, StaticDynamic):
            raise ValueError("StaticDynamic.static: must be a static law (Engineering, Curve)")
        object.__setattr__(self, "tension_only", self.static.tension_only and self.tension_only)

    def static_pieces(self, EA):
        return self.static.static_pieces(EA)

    def nominal_EA(self, EA):
        return self.static.nominal_EA(EA)

    def dynamic_EA(self, T_mean):
        """EA_d (N) at mean tension T_mean (N)."""
        if self.EA_dynamic is not None:
            return self.EA_dynamic + 0.0 * np.asarray(T_mean, float)
        return self.alpha_MBL + self.beta * np.asarray(T_mean, float)

    def parameters(self, EA, T, e_ref, static=False):
        if static:
            p, hinges = self.static.parameters(EA, T, e_ref)
            p["tension_only"] = float(self.tension_only) * np.ones_like(T)
            return p, hinges
        p, _ = super().parameters(EA, T, e_ref)
        p.update(T0=np.asarray(T, float) * 1.0, e0=e_ref * np.ones_like(T),
                 k=self.dynamic_EA(T))
        return p, None


@dataclass(frozen=True)
class Viscoelastic(StaticDynamic):
    """MoorDyn's viscoelastic polyester (``EA_s|EA_d`` or ``EA_s|alphaMBL|beta`` with
    ``BA|BA_D``): a creep element, spring EA_1 = EA_d EA_s / (EA_d - EA_s) and damper
    ``creep_damping`` BA (N s), in series with the dynamic element, spring EA_d and damper
    ``dynamic_damping`` BA_D (N s). With z the creep element's strain (its creep state):

        tension = EA_1 z + BA dz/dt = EA_d (e - z) + BA_D (de/dt - dz/dt)

    so that a slow stretch sees EA_s, a fast one EA_d. EA_d = alphaMBL + beta T_1 with
    T_1 = EA_1 z the creep spring's tension (MoorDyn's closed form of it). The static
    state is solved with ``static`` (EA_s); in time the cable kernel keeps each element's
    mean tension T_mean along it and :class:`skmoor.lines.creep.CreepTerm` adds the rest of the
    axial force, N - T_mean, integrating z.
    ``relax``: the creep state at t = 0: None, relaxed at the static strain (tension
    EA_s e); a time (s), MoorDyn's start, z = e, relaxed that long with the ends held
    (MoorDyn's initial-condition stage)."""

    creep_damping: float = 0.0
    dynamic_damping: float = 0.0
    relax: float | None = None
    name = "viscoelastic"

    def __post_init__(self):
        super().__post_init__()
        for name in ("creep_damping", "dynamic_damping"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"Viscoelastic.{name}: must be a finite number >= 0 N s, "
                                 f"got {value!r}")
        if not self.creep_damping + self.dynamic_damping > 0:
            raise ValueError("Viscoelastic: creep_damping + dynamic_damping must be > 0 N s "
                             "(the creep rate divides by it)")
        if self.relax is not None and not (math.isfinite(self.relax) and self.relax >= 0):
            raise ValueError(f"Viscoelastic.relax: must be None or a time >= 0 s, got "
                             f"{self.relax!r}")

    def parameters(self, EA, T, e_ref, static=False):
        if static:
            return super().parameters(EA, T, e_ref, static)
        # the cable kernel keeps the mean tension T along the line (its reference part
        # balanced); skmoor.lines.creep.CreepTerm adds the rest of the axial force
        p, _ = Law.parameters(self, EA, T, e_ref)
        p.update(T0=np.asarray(T, float) * 1.0, e0=e_ref * np.ones_like(T), k=0.0 * p["k"])
        return p, None

    # --- the creep element, for skmoor.lines.creep.CreepTerm (arrays of the elements)
    def stiffnesses(self, z, EA):
        """(EA_1, EA_d), N, at creep strain z (-); EA: the line type's EA (EA_s)."""
        EA_s = self.static.nominal_EA(EA)
        z = np.asarray(z, float)
        if self.EA_dynamic is not None:
            EA_d = self.EA_dynamic + 0.0 * z
        else:  # MoorDyn's Line.cpp: EA_d = alpha + beta EA_1 z solved with EA_1 of EA_d
            a, b = self.alpha_MBL, self.beta * np.maximum(z, 0.0) * EA_s
            EA_d = 0.5 * (a + b + EA_s + np.sqrt(a * a + 2 * a * (b - EA_s)
                                                  + (b + EA_s) ** 2))
        if np.any(EA_d <= EA_s):
            raise ValueError(f"Viscoelastic: the dynamic stiffness {np.min(EA_d):g} N must "
                             f"exceed the static one EA_s = {EA_s:g} N")
        return EA_d * EA_s / (EA_d - EA_s), EA_d

    def creep_spring(self, z, EA, memory=None):
        """The creep spring's tension EA_1 z (N) at creep strain z."""
        return self.stiffnesses(z, EA)[0] * z

    def creep_drive(self, z, EA, memory=None):
        """(a, b), N: the dynamic spring's tension less the creep spring's is a e - b at
        strain e, so that dz/dt = (a e - b + BA_D de/dt) / (BA + BA_D)."""
        EA_1, EA_d = self.stiffnesses(z, EA)
        return EA_d, (EA_1 + EA_d) * z

    def creep_start(self, e, T, EA):
        """(creep strain z, memory) at t = 0 before any relaxation, for the static strain
        e (-) and tension T (N): MoorDyn's z = e when ``relax`` is a time, else None
        (relaxed: the creep term solves a e = b)."""
        return (None if self.relax is None else np.array(e, float)), None

    def creep_update(self, z, EA, memory):
        """The memory after an accepted step (none here; Syrope's highest tension)."""
        return memory


LAWS = {"paper": Paper, "engineering": Engineering}


def as_law(law, where="law") -> Law:
    """A Law from a Law or a shorthand name ('paper', 'engineering'), tension-only."""
    if isinstance(law, Law):
        return law
    if isinstance(law, str) and law in LAWS:
        return LAWS[law]()
    raise ValueError(f"{where}: unknown strain law {law!r}, use one of {list(LAWS)} or a "
                     "skmoor.lines.laws.Law (Paper, Engineering, Curve, StaticDynamic, or "
                     "skmoor.UserLaw for a law of your own)")


def _hinges(hinges, shape):
    """The knots / coef fields (m, *shape) of a law's hinges (x_j, c_j), or none."""
    if hinges is None:
        return dict(knots=np.zeros((0,) + shape), coef=np.zeros((0,) + shape))
    x, c = hinges
    return dict(knots=np.broadcast_to(x.reshape((-1,) + (1,) * len(shape)), (len(x),) + shape),
                coef=np.broadcast_to(c.reshape((-1,) + (1,) * len(shape)), (len(c),) + shape))


def _check_curve(strain, tension, source):
    """Validated (strain, tension) arrays with (0, 0) first."""
    try:
        e = np.asarray(strain, float).ravel()
        T = np.asarray(tension, float).ravel()
    except (TypeError, ValueError):
        raise ValueError(f"{source}: strain and tension must be numbers") from None
    if e.shape != T.shape or e.size < 1:
        raise ValueError(f"{source}: need as many strains as tensions (at least one point), "
                         f"got {e.size} and {T.size}")
    if not (np.all(np.isfinite(e)) and np.all(np.isfinite(T))):
        raise ValueError(f"{source}: strain and tension must be finite")
    if e[0] < 0 or T[0] < 0:
        raise ValueError(f"{source}: the curve starts at strain {e[0]:g}, tension {T[0]:g} N; "
                         "give strains >= 0 and tensions >= 0 (a cable in tension)")
    if e[0] == 0 and T[0] != 0:
        raise ValueError(f"{source}: the tension at zero strain must be 0 N, got {T[0]:g}")
    if e[0] > 0:
        e, T = np.r_[0.0, e], np.r_[0.0, T]
    for name, values in (("strain", e), ("tension", T)):
        bad = np.nonzero(np.diff(values) <= 0)[0]
        if bad.size:
            i = int(bad[0])
            raise ValueError(f"{source}: the {name} must increase point by point; point "
                             f"{i + 1} ({values[i + 1]:g}) does not exceed point {i} "
                             f"({values[i]:g})")
    return e, T


def read_curve(path, source=None) -> Curve:
    """A :class:`Curve` from a MoorDyn curve file: three header lines, then one point a
    line, strain (-) and tension (N) separated by blanks (or commas)."""
    path = Path(path)
    name = source or str(path)
    if not path.is_file():
        raise ValueError(f"{name}: curve file {path} does not exist")
    rows = []
    lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    for number, text in enumerate(lines[3:], start=4):
        words = text.replace(",", " ").split()
        if not words:
            continue
        try:
            rows.append((float(words[0]), float(words[1])))
        except (ValueError, IndexError):
            raise ValueError(f"{name}: curve file {path.name} line {number}: "
                             f"{text.strip()!r} is not two numbers (strain, tension)") from None
    if not rows:
        raise ValueError(f"{name}: curve file {path.name} has no points after its three "
                         "header lines")
    e, T = np.array(rows).T
    return Curve(e, T, source=f"{name} (curve file {path.name})")
