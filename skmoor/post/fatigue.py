"""Fatigue of the lines over a run: rainflow counting of the tension ranges, Miner's
damage on T-N or S-N curves, damage-equivalent loads.

Counting: ASTM E1049-85's rainflow count by the ``rainflow`` package
(:func:`rainflow.extract_cycles`): the reversals of a tension history give ranges
``dT_i`` (N) with counts ``n_i`` of 1 (full cycles) or 0.5 (the residual's half cycles).

Damage (Palmgren-Miner): ``D = sum_i n_i / N(s_i)`` with ``N`` the line's curve
(:mod:`skmoor.lines.fatigue_curves`: DNV-OS-E301's T-N curves, DNV-RP-C203's S-N
curves); ``s_i = dT_i / (pi d_nom^2 / 4)`` in MPa, or ``dT_i / MBL`` for polyester. The
run's damage over its duration ``T`` (s, from ``start``) scales linearly to a year,
``D_year = D * 365.25 * 86400 / T``, and to a design life of ``L`` years, ``D_year * L``;
the fatigue life is ``1 / D_year`` years (the run stands for all of the year's sea).

Damage-equivalent load: the constant range that, repeated ``N_eq = f_eq T`` times
(``f_eq = 1 Hz``), does the damage of the counted cycles on a single-slope curve of
exponent ``m``: ``DEL_m = (sum_i n_i dT_i^m / N_eq)^(1/m)`` (N), half cycles counting 0.5.
"""
from __future__ import annotations

import numpy as np
import rainflow

from ..lines.fatigue_curves import curve as fatigue_curve
from .strength import line_property

__all__ = ["count_cycles", "miner_damage", "damage_equivalent_load", "fatigue",
           "YEAR", "stress_ranges"]

#: seconds in a year (365.25 days)
YEAR = 365.25 * 86400.0


def count_cycles(series) -> tuple[np.ndarray, np.ndarray]:
    """(ranges, counts) of the rainflow count of ``series`` (ASTM E1049-85): one entry per
    counted cycle, ``counts`` 1.0 for a full cycle and 0.5 for a half cycle."""
    series = np.asarray(series, float)
    if series.ndim != 1:
        raise ValueError(f"count_cycles: a 1-D series, got shape {series.shape}")
    if not np.all(np.isfinite(series)):
        raise ValueError("count_cycles: the series is not finite")
    found = [(rng, count) for rng, _mean, count, _i, _j in rainflow.extract_cycles(series)]
    if not found:
        return np.zeros(0), np.zeros(0)
    ranges, counts = np.array(found, float).T
    return ranges, counts


def stress_ranges(ranges, curve, d_nom=None, mbl=None) -> np.ndarray:
    """Tension ranges (N) as the curve's ``s``: MPa over the nominal section
    ``pi d_nom^2 / 4`` (m), or the fraction of the MBL (N) for a curve per MBL."""
    c = fatigue_curve(curve)
    ranges = np.asarray(ranges, float)
    if c.per == "MBL":
        if mbl is None:
            raise ValueError(f"curve {c.name!r} takes the tension range over the MBL: "
                             "give the line's MBL")
        return ranges / mbl
    if d_nom is None:
        raise ValueError(f"curve {c.name!r} takes the stress range: give the nominal "
                         "diameter d_nom")
    return ranges / (np.pi * d_nom**2 / 4) / 1e6


def miner_damage(ranges, counts, curve, d_nom=None, mbl=None) -> float:
    """Palmgren-Miner sum ``sum n_i / N(s_i)`` of counted tension ranges (N) on ``curve``
    (a name in :data:`skmoor.lines.fatigue_curves.CURVES` or a FatigueCurve)."""
    c = fatigue_curve(curve)
    s = stress_ranges(ranges, c, d_nom, mbl)
    return float(np.sum(np.asarray(counts, float) / c.cycles(s)))


def damage_equivalent_load(ranges, counts, m, n_eq) -> float:
    """``(sum n_i dT_i^m / n_eq)^(1/m)``: the range (N) that ``n_eq`` times does the same
    damage as the counted cycles on a curve of slope ``m``."""
    if n_eq <= 0:
        raise ValueError(f"damage_equivalent_load: n_eq must be > 0, got {n_eq}")
    ranges, counts = np.asarray(ranges, float), np.asarray(counts, float)
    return float((np.sum(counts * ranges**m) / n_eq) ** (1.0 / m))


def fatigue(results, curve=None, m=(3.0, 5.0), start=0.0, design_life=None, mbl=None,
            d_nom=None, where="elements", f_eq=1.0) -> dict:
    """Fatigue of every line over the samples from time ``start`` (s).

    curve: the fatigue curve for all lines, or {line name: curve}, over the line types'
    own (``LineType.fatigue_curve``); mbl, d_nom: likewise over the types' MBL (N) and
    nominal diameter (m). where: 'elements' (each element's tension; the line's values
    those of its most damaged element) or 'fairlead' (the tension at end B only).
    m: the Wöhler exponents of the damage-equivalent loads, at ``f_eq`` (Hz).

    Returns {"duration": T (s), "f_eq", "m", "design_life", "where", "lines": {line name:
    {"curve", "damage" (over the run), "damage_per_year", "life_years", "damage_design_life",
    "DEL": {m: N}, "element" (the most damaged, or largest DEL without a curve), and with
    where='elements' "element_damage" and "element_DEL" {m: [N ...]}}}; damage values are
    None for a line without a curve (or without the MBL its curve needs)."""
    if where not in ("elements", "fairlead"):
        raise ValueError(f"fatigue: where is 'elements' or 'fairlead', got {where!r}")
    keep = results.t >= start - 1e-12
    t = results.t[keep]
    duration = float(t[-1] - t[0]) if len(t) > 1 else 0.0
    if duration <= 0:
        raise ValueError(f"fatigue: the run from t = {start:g} s has no duration")
    m = [float(x) for x in np.atleast_1d(m)]
    curves = line_property(results, "fatigue_curve", curve)
    mbls = line_property(results, "MBL", mbl)
    d_noms = line_property(results, "d_nom", d_nom)
    n_eq = f_eq * duration
    lines = {}
    for k, name in enumerate(results.line_names):
        if where == "fairlead":
            series = results.fairlead_tension[keep][:, [k]]
        else:
            cells = np.flatnonzero(results.line_of_cell == k)
            if not len(cells):
                continue
            series = results.tension[keep][:, cells]
        c = None if curves[k] is None else fatigue_curve(curves[k], f"line {name!r}")
        usable = c is not None and (c.per != "MBL" or mbls[k] is not None) and (
            c.per != "area" or d_noms[k] is not None)
        damage, dels = [], {x: [] for x in m}
        for j in range(series.shape[1]):
            ranges, counts = count_cycles(series[:, j])
            damage.append(miner_damage(ranges, counts, c, d_noms[k], mbls[k])
                          if usable else None)
            for x in m:
                dels[x].append(damage_equivalent_load(ranges, counts, x, n_eq))
        worst = (int(np.argmax(damage)) if usable else
                 int(np.argmax(dels[m[0]])) if m else 0)
        d = damage[worst]
        row = {"curve": None if c is None else c.name, "damage": d,
               "damage_per_year": None if d is None else d * YEAR / duration,
               "life_years": (None if d is None or d == 0 else
                              duration / YEAR / d),
               "damage_design_life": (None if d is None or design_life is None
                                      else d * YEAR / duration * design_life),
               "DEL": {_key(x): dels[x][worst] for x in m}, "element": worst}
        if usable is False and c is not None:
            row["note"] = (f"curve {c.name!r} needs the line's "
                           f"{'MBL' if c.per == 'MBL' else 'd_nom'}")
        if where == "elements":
            row["element_damage"] = damage
            row["element_DEL"] = {_key(x): dels[x] for x in m}
        lines[name] = row
    return {"duration": duration, "f_eq": f_eq, "m": m, "design_life": design_life,
            "where": where, "lines": lines}


def _key(m) -> str:
    """A Wöhler exponent as a JSON key: '3' for 3.0, '4.8' for 4.8."""
    return f"{m:g}"
