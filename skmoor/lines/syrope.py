"""The Syrope model of polyester ropes (MoorDyn's ``SYROPE:`` line types): working curves.

A polyester rope loaded for the first time follows its original working curve (OWC, a
tension-strain table). Once it has seen a highest mean tension T_max, it is unloaded and
reloaded along a working curve (WC) that ends on the OWC at (eps_max, T_max),
eps_max = OWC strain at T_max, and starts slack at eps_min:

    eps_min = e_0 + k1 (eps_max - e_0)       (e_0: the OWC's first strain)
              eps_max - T_max / k1           (LINEAR with k1 >= 1: k1 is the slope, N)
    xi = (e - eps_min) / (eps_max - eps_min)
    LINEAR:    T = T_max xi
    QUADRATIC: T = T_max xi (k2 xi + 1 - k2)
    EXP:       T = T_max (exp(k2 xi) - 1) / (exp(k2) - 1)

(MoorDyn's Line::setWorkingCurve; Wei, Bingham & Shao, ESOMOOR D5.1, DTU 2026). Above
T_max the rope is back on the OWC. Waves stretch it about its mean with the dynamic
stiffness EA_d = alpha_MBL + beta T_mean (N), as MoorDyn's ``EA_s|alphaMBL|beta``.

:func:`syrope_law` gives the law skmoor runs, :class:`Syrope` (a
:class:`~skmoor.lines.laws.StaticDynamic`) whose static law is the :class:`WorkingCurve` of the
line's T_max (MoorDyn's ``SYROPE IC`` Tmax0): the static state on the working curve, the
motion about a mean state on it, tension T_mean + EA_d(T_mean) (e - e_wc(T_mean)), T_mean
the IC's Tmean0 (MoorDyn's initial creep state) or, without it, the element's static
tension. This is the limit of MoorDyn's Syrope model for motions faster than its creep
time (BA / EA_d times 1 - EA_wc / EA_d) that stay below T_max: the mean tension and T_max
held (MoorDyn integrates each segment's creep strain and raises T_max; skmoor does not).
The working curve is sampled at ``points`` strains as MoorDyn does (30), linear between.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..fem import ops
from . import laws

__all__ = ["FORMS", "working_curve_tension", "working_curve", "WorkingCurve", "Syrope",
           "SyropeCreep", "slow_strain", "syrope_law", "read_syrope_file", "read_owc"]

FORMS = ("linear", "quadratic", "exp")


def _shape(form, xi, k2):
    """T / T_max (-) of a working curve at xi in [0, 1]."""
    if form == "linear":
        return xi
    if form == "quadratic":
        return xi * (k2 * xi + 1.0 - k2)
    if abs(math.expm1(k2)) < 1e-14:  # exp with k2 -> 0: the straight line
        return xi
    return np.expm1(k2 * xi) / math.expm1(k2)


def _strain_range(owc_strain, owc_tension, form, k1, T_max):
    """(eps_min, eps_max), strains (-) where the working curve of T_max (N) is slack / meets
    the OWC."""
    eps_max = float(np.interp(T_max, owc_tension, owc_strain))
    e_0 = float(owc_strain[0])
    if form == "linear" and k1 >= 1.0:
        return eps_max - T_max / k1, eps_max
    return e_0 + k1 * (eps_max - e_0), eps_max


def working_curve_tension(e, owc_strain, owc_tension, form, k1, k2, T_max):
    """Tension (N) of the working curve of highest mean tension T_max (N) at strain e (-):
    0 below eps_min, the curve's formula up to eps_max, the OWC (strain, tension table)
    beyond."""
    e = np.asarray(e, float)
    eps_min, eps_max = _strain_range(np.asarray(owc_strain, float), owc_tension, form, k1, T_max)
    xi = np.clip((e - eps_min) / (eps_max - eps_min), 0.0, 1.0)
    on_owc = np.interp(e, owc_strain, owc_tension)
    return np.where(e > eps_max, on_owc, T_max * _shape(form, xi, k2))


def working_curve(owc_strain, owc_tension, form, k1, k2, T_max, points=30):
    """(strain, tension) table of the working curve: ``points`` samples from (eps_min, 0)
    to (eps_max, T_max), then the OWC points above T_max."""
    owc_strain, owc_tension = np.asarray(owc_strain, float), np.asarray(owc_tension, float)
    eps_min, eps_max = _strain_range(owc_strain, owc_tension, form, k1, T_max)
    xi = np.linspace(0.0, 1.0, points)
    above = owc_tension > T_max * (1 + 1e-12)
    return (np.r_[eps_min + (eps_max - eps_min) * xi, owc_strain[above]],
            np.r_[T_max * _shape(form, xi, k2), owc_tension[above]])


@dataclass(frozen=True)
class WorkingCurve(laws.Law):
    """The static law of a Syrope rope: its working curve for the highest mean tension
    T_max (N), a piecewise-linear table (:func:`working_curve`), slack below eps_min and
    extended beyond the OWC's last point with its last slope. ``owc``: the OWC's
    (strain, tension) points as MoorDyn reads them; form 'linear' | 'quadratic' | 'exp'."""

    owc: tuple = ((), ())
    form: str = "linear"
    k1: float = 0.0
    k2: float = 0.0
    T_max: float = 0.0
    points: int = 30
    source: str = "Syrope"  # names the rope in messages
    name = "syrope working curve"

    def __post_init__(self):
        e, T = (np.asarray(v, float) for v in self.owc)
        where = self.source
        if e.shape != T.shape or e.size < 2 or not (np.all(np.diff(e) > 0)
                                                    and np.all(np.diff(T) > 0)):
            raise ValueError(f"{where}: the original working curve needs at least two points "
                             "with strain and tension increasing point by point")
        if self.form not in FORMS:
            raise ValueError(f"{where}: WCType {self.form!r}: use one of LINEAR, QUADRATIC, EXP")
        if not T[0] <= self.T_max <= T[-1]:
            raise ValueError(f"{where}: Tmax0 = {self.T_max:g} N is outside the original "
                             f"working curve's tensions [{T[0]:g}, {T[-1]:g}] N")
        if not (math.isfinite(self.k1) and self.k1 >= 0):
            raise ValueError(f"{where}: k1 must be a finite number >= 0, got {self.k1!r}")
        strain, tension = self.table
        if not (np.all(np.diff(strain) > 0) and np.all(np.diff(tension) > 0)):
            raise ValueError(f"{where}: the {self.form.upper()} working curve of k1 = {self.k1:g}, "
                             f"k2 = {self.k2:g} does not rise with strain from 0 to Tmax0 "
                             f"{self.T_max:g} N (QUADRATIC needs 0 <= k2 <= 1, LINEAR k1 < 1 "
                             "or a slope k1 >= Tmax0 / eps_max)")

    @property
    def table(self):
        """(strain (-), tension (N)) arrays of the sampled working curve."""
        return working_curve(*self.owc, self.form, self.k1, self.k2, self.T_max, self.points)

    def _slopes(self):
        e, T = self.table
        return e, T, np.diff(T) / np.diff(e)

    def static_pieces(self, EA=None):
        e, T, s = self._slopes()
        return T[:-1], e[:-1] - T[:-1] / s, 1.0 / s

    def nominal_EA(self, EA=None):
        """The OWC's last secant, N (MoorDyn's EA of a Syrope line)."""
        return self.owc[1][-1] / self.owc[0][-1]

    def parameters(self, EA, T, e_ref, static=False):
        p, _ = super().parameters(EA, T, e_ref)
        e, _, s = self._slopes()
        ones = np.ones_like(T)
        p.update(e0=e[0] * ones, k=s[0] * ones)  # from (eps_min, 0); slack below
        return p, (e[1:-1], np.diff(s))


@dataclass(frozen=True)
class Syrope(laws.StaticDynamic):
    """A Syrope rope: the static law ``static`` (a :class:`WorkingCurve`), the motion about
    the mean tension T_mean (N; None: each element's static tension) on it with
    EA_d = alpha_MBL + beta T_mean."""

    T_mean: float | None = None
    name = "syrope"

    def parameters(self, EA, T, e_ref, static=False):
        if static or self.T_mean is None:
            return super().parameters(EA, T, e_ref, static)
        ones = np.ones_like(T)
        p, _ = super().parameters(EA, self.T_mean * ones,
                                  self.static.static_strain(self.T_mean) * ones)
        p["e_ref"] = e_ref * ones  # the element's reference strain, as the others
        return p, None


def slow_strain(strain, tension, alpha_MBL, beta):
    """The creep (slow) strain z (-) of a point (strain, tension N) of a working curve: the
    strain less the dynamic spring's, int_0^T dT / (alpha_MBL + beta T) (MoorDyn's
    Line::setWorkingCurve: z = e - ln(1 + beta T / alpha_MBL) / beta)."""
    tension = np.asarray(tension, float)
    if beta == 0:
        return np.asarray(strain, float) - tension / alpha_MBL
    return np.asarray(strain, float) - np.log1p(beta * tension / alpha_MBL) / beta


@dataclass(frozen=True)
class SyropeCreep(laws.Viscoelastic):
    """MoorDyn's Syrope model in full (``SYROPE:`` with ``BA|BA_D``): a creep element,
    the working curve's tension T(z) at creep strain z and the damper ``creep_damping``
    BA (N s), in series with the dynamic spring EA_d = alpha_MBL + beta T and the damper
    ``dynamic_damping`` BA_D (N s) (MoorDyn's Line.cpp, Line::getStateDeriv):

        BA dz/dt = EA_d(T) (e - e_wc(T)) + BA_D (de/dt - dz/dt),   tension T(z) + BA dz/dt

    e_wc(T) the working curve's strain at T. The working curve is that of each element's
    highest mean tension T_max (``static.T_max`` at the start, raised when T(z) passes
    it: the rope back on its original working curve). The creep state at t = 0: the
    slow strain of ``T_mean`` (N, MoorDyn's SYROPE IC Tmean0) on the curve, or relaxed
    at the static strain when None; then relaxed ``relax`` s with the ends held."""

    T_mean: float | None = None
    name = "syrope creep"

    def __post_init__(self):
        super().__post_init__()
        if not self.alpha_MBL > 0:
            raise ValueError(f"SyropeCreep: EA_Dc (alpha_MBL) must be > 0 N, got {self.alpha_MBL!r}")
        for T_max in (self.static.T_max, self.static.owc[1][-1]):
            strain, tension = self._tables(T_max)[:2]
            z = slow_strain(strain, tension, self.alpha_MBL, self.beta)
            if not np.all(np.diff(z) > 0):
                raise ValueError(f"{self.static.source}: the creep strains of the working "
                                 f"curve of Tmax {T_max:g} N do not rise with its strain "
                                 "(the dynamic stiffness EA_Dc + EA_D_Lm T is too soft for "
                                 "it; MoorDyn refuses it too)")

    @functools.lru_cache(maxsize=256)
    def _tables(self, T_max):
        """(strain, tension, creep strain) of the working curve of T_max (N)."""
        wc = self.static
        strain, tension = working_curve(*wc.owc, wc.form, wc.k1, wc.k2, float(T_max), wc.points)
        return strain, tension, slow_strain(strain, tension, self.alpha_MBL, self.beta)

    def _each(self, z, memory, fn):
        out = np.empty((2,) + np.shape(z))
        for i, (zi, T_max) in enumerate(zip(np.atleast_1d(z), memory)):
            out[:, i] = fn(zi, *self._tables(float(T_max)))
        return out

    def creep_spring(self, z, EA, memory=None):
        return self._each(z, memory, lambda zi, e, T, zs: (np.interp(zi, zs, T), 0.0))[0]

    def creep_drive(self, z, EA, memory=None):
        def drive(zi, e, T, zs):
            tension = np.interp(zi, zs, T)
            a = self.alpha_MBL + self.beta * tension
            return a, a * np.interp(tension, T, e)  # EA_d (e - e_wc(T)) = a e - b

        return tuple(self._each(z, memory, drive))

    def creep_start(self, e, T, EA):
        memory = np.full(np.shape(e), float(self.static.T_max))
        if self.T_mean is None:
            return None, memory
        _, tension, zs = self._tables(self.static.T_max)
        return np.full(np.shape(e), np.interp(self.T_mean, tension, zs)), memory

    def creep_update(self, z, EA, memory):
        return np.maximum(memory, self.creep_spring(z, EA, memory))

    def user_law(self):
        """This law written as a :class:`~skmoor.lines.user_law.UserLaw` with the state
        (z, T_max): z by its rate, T_max by an update after each step (its working curve
        traced as a function of T_max, :func:`skmoor.fem.ops.interp`). Needs T_mean (its
        creep state's start) and no ``relax``."""
        from .user_law import UserLaw

        if self.T_mean is None or self.relax:
            raise ValueError(f"{self.static.source}: as a user law the Syrope rope needs "
                             "Tmean0 (T_mean) and no relax")
        alpha, beta, wc = self.alpha_MBL, self.beta, self.static
        BA, BA_D = self.creep_damping, self.dynamic_damping
        owc_e, owc_T = (list(v) for v in wc.owc)
        shapes = [float(_shape(wc.form, xi, wc.k2)) for xi in np.linspace(0, 1, wc.points)]

        def curve(T_max):
            # the working curve of T_max (strains, tensions, creep strains): from eps_min
            # to eps_max on the OWC, then the OWC above T_max (its points below stand on
            # the curve's last one)
            eps_max = ops.interp(T_max, owc_T, owc_e)
            eps_min = (eps_max - T_max / wc.k1 if wc.form == "linear" and wc.k1 >= 1.0 else
                       owc_e[0] + wc.k1 * (eps_max - owc_e[0]))
            e = [eps_min + (eps_max - eps_min) * xi for xi in np.linspace(0, 1, wc.points)]
            T = [T_max * shape for shape in shapes]
            for e_j, T_j in zip(owc_e, owc_T):
                above = T_j > T_max * (1.0 + 1e-12)
                e.append(ops.where(above, e_j, e[wc.points - 1]))
                T.append(ops.where(above, T_j, T[wc.points - 1]))
            return e, T, [e_k - (T_k / alpha if beta == 0 else
                                 ops.log(1.0 + beta * T_k / alpha) / beta)
                          for e_k, T_k in zip(e, T)]

        def spring(z, T_max):  # (F_1(z), the dynamic stiffness a, the drive's b)
            e, T, zs = curve(T_max)
            F_1 = ops.interp(z, zs, T)
            a = alpha + beta * F_1
            return F_1, a, a * ops.interp(F_1, T, e)

        def rate(strain, strain_rate, state, reference):
            z, T_max = state
            _, a, b = spring(z, T_max)
            return (a * strain - b + BA_D * strain_rate) / (BA + BA_D), 0.0 * z

        def tension(strain, strain_rate, state, reference):
            z, T_max = state
            return (ops.where(strain >= 0.0, spring(z, T_max)[0], 0.0)
                    + BA * rate(strain, strain_rate, state, reference)[0])

        def update(strain, strain_rate, state, dt):
            z, T_max = state
            return z, ops.maximum(T_max, spring(z, T_max)[0])

        def start(e_static, T_static):  # z of Tmean0 on the curve of Tmax0
            _, T, zs = curve(wc.T_max)
            return (ops.interp(self.T_mean, T, zs) + 0.0 * e_static,
                    wc.T_max + 0.0 * e_static)

        return UserLaw(tension, name=f"{wc.source} as a user law", state=start,
                       state_rate=rate, update=update, reference="static", static=wc,
                       tension_only=False, balanced=False)


def syrope_law(owc, form, k1, k2, T_max, alpha_MBL, beta, T_mean=None, points=30,
               source="Syrope", creep_damping=None, dynamic_damping=None, relax=None):
    """The law of a Syrope line: static state on the working curve of T_max (N); in time
    a :class:`SyropeCreep` with its creep state from T_mean (N) when the dampers are
    given (BA ``creep_damping``, BA_D ``dynamic_damping``, N s; ``relax`` s), else the
    fast limit :class:`Syrope`, motion about T_mean (N, or the static tension) with
    EA_d = alpha_MBL (N) + beta T_mean (MoorDyn's SYROPE:file|EA_Dc|EA_D_Lm, BA|BA_D and
    SYROPE IC Tmax0, Tmean0)."""
    static = WorkingCurve(owc=tuple(tuple(map(float, v)) for v in owc), form=form.lower(),
                          k1=float(k1), k2=float(k2), T_max=float(T_max), points=points,
                          source=source)
    if T_mean is not None and not 0 <= T_mean <= T_max:
        raise ValueError(f"{source}: Tmean0 must be within [0, Tmax0 = {T_max:g}] N, "
                         f"got {T_mean:g}")
    T_mean = None if T_mean is None else float(T_mean)
    try:
        if dynamic_damping is not None:
            return SyropeCreep(alpha_MBL=alpha_MBL, beta=beta, static=static, T_mean=T_mean,
                               creep_damping=float(creep_damping),
                               dynamic_damping=float(dynamic_damping), relax=relax)
        return Syrope(alpha_MBL=alpha_MBL, beta=beta, static=static, T_mean=T_mean)
    except ValueError as err:  # (named once)
        raise ValueError(str(err) if str(err).startswith(source) else f"{source}: {err}") \
            from None


def read_syrope_file(path, source=None):
    """(owc path, form, k1, k2) of a Syrope settings file: ``value name`` lines naming OWC
    (the table's path, relative to the deck), WCType, k1 and k2."""
    path = Path(path)
    name = source or str(path)
    if not path.is_file():
        raise ValueError(f"{name}: Syrope file {path} does not exist")
    found = {}
    for number, text in enumerate(path.read_text(encoding="utf-8", errors="replace")
                                  .splitlines(), start=1):
        words = text.split()
        if len(words) < 2 or words[1].lower() not in ("owc", "wctype", "k1", "k2"):
            continue
        key, value = words[1].lower(), words[0]
        if key in ("k1", "k2"):
            try:
                value = float(value)
            except ValueError:
                raise ValueError(f"{name}: Syrope file {path.name} line {number}: {key} "
                                 f"{words[0]!r} is not a number") from None
        elif key == "wctype":
            value = value.lower()
            if value not in FORMS:
                raise ValueError(f"{name}: Syrope file {path.name} line {number}: WCType "
                                 f"{words[0]!r}: use LINEAR, QUADRATIC or EXP")
        found[key] = value
    missing = [k for k in ("owc", "wctype", "k1", "k2") if k not in found]
    if missing:
        spelled = {"owc": "OWC", "wctype": "WCType", "k1": "k1", "k2": "k2"}
        raise ValueError(f"{name}: Syrope file {path.name} does not give "
                         f"{', '.join(spelled[m] for m in missing)}")
    return found["owc"], found["wctype"], found["k1"], found["k2"]


def read_owc(path, source=None):
    """(strain, tension) arrays of an original working curve file as MoorDyn reads it:
    three header lines, then strain (-) and tension (N) a line (no (0, 0) added)."""
    path = Path(path)
    name = source or str(path)
    if not path.is_file():
        raise ValueError(f"{name}: OWC file {path} does not exist")
    rows = []
    lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    for number, text in enumerate(lines[3:], start=4):
        words = text.replace(",", " ").split()
        if not words:
            continue
        try:
            rows.append((float(words[0]), float(words[1])))
        except (ValueError, IndexError):
            raise ValueError(f"{name}: OWC file {path.name} line {number}: {text.strip()!r} "
                             "is not two numbers (strain, tension)") from None
    if len(rows) < 2:
        raise ValueError(f"{name}: OWC file {path.name} has fewer than two points after its "
                         "three header lines")
    return tuple(np.array(rows).T)
