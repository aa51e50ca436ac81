"""Fatigue curves of mooring lines: the number of cycles ``N`` a line survives at one
range, ``N = a_D s^-m``.

T-N curves of DNV-OS-E301 (Offshore standard *Position mooring*, Ch. 2 Sec. 2, the
fatigue limit state's table of ``a_D`` and ``m``): ``s`` is the stress range in MPa, the
tension range (double amplitude) over the nominal section ``pi d_nom^2 / 4`` for chain
and steel wire rope; for polyester rope ``s`` is the tension range over the minimum
breaking load (``R``, dimensionless).

S-N curves of DNV-RP-C203 (*Fatigue design of offshore steel structures*, tables 2-1, 2-2
and 2-4): two slopes, ``log N = log a1 - m1 log S`` above the switch at ``N = 1e7``
cycles in air (``1e6`` in seawater with cathodic protection), ``log a2 - m2 log S``
below it; a single slope in free corrosion. ``S`` in MPa, the thickness effect left out.

A line type chooses its curve by name (``LineType.fatigue_curve``, a case file's
``fatigue_curve``); :data:`CURVES` lists them.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class FatigueCurve:
    """One T-N or S-N curve. slopes: ((m1, log10 a1), (m2, log10 a2)) or one pair;
    switch: the number of cycles where the second slope takes over (None: one slope);
    per: 'area' (s = tension range / nominal section, MPa) or 'MBL' (s = tension range
    / minimum breaking load); source: the standard and table."""

    name: str
    slopes: tuple
    switch: float | None = None
    per: str = "area"
    source: str = ""

    @property
    def m(self) -> float:
        """The (first) Wöhler exponent."""
        return self.slopes[0][0]

    def cycles(self, s) -> np.ndarray:
        """Cycles to failure ``N`` at the range(s) ``s`` (MPa, or a fraction of MBL);
        infinite at ``s = 0``."""
        s = np.asarray(s, float)
        with np.errstate(divide="ignore", over="ignore"):
            m1, a1 = self.slopes[0]
            n = 10.0**a1 * s**-m1
            if self.switch is not None and len(self.slopes) > 1:
                m2, a2 = self.slopes[1]
                n = np.where(n > self.switch, 10.0**a2 * s**-m2, n)
        return n


def _tn(name, a_D, m, per="area"):
    return FatigueCurve(name, ((m, float(np.log10(a_D))),), None, per,
                        "DNV-OS-E301 Ch.2 Sec.2, T-N curves")


def _sn(name, m1, a1, a2, switch, table, m2=5.0):
    slopes = ((m1, a1),) if a2 is None else ((m1, a1), (m2, a2))
    return FatigueCurve(name, slopes, switch if a2 is not None else None, "area",
                        f"DNV-RP-C203 table {table}")


#: The curves by name: DNV-OS-E301's T-N curves (chain, wire rope, polyester) and
#: DNV-RP-C203's S-N curves (``dnv-c203-X-air``, ``-X-seawater-cp``, ``-X-free-corrosion``).
CURVES = {c.name: c for c in (
    _tn("studlink-chain", 1.2e11, 3.0),
    _tn("studless-chain", 6.0e10, 3.0),
    _tn("kenter-shackle", 1.2e10, 3.0),
    _tn("six-strand-rope", 3.4e14, 4.0),
    _tn("spiral-strand-rope", 1.7e17, 4.8),
    _tn("polyester-rope", 0.259, 13.46, per="MBL"),
    _sn("dnv-c203-B1-air", 4.0, 15.117, 17.146, 1e7, "2-1"),
    _sn("dnv-c203-C-air", 3.0, 12.592, 16.320, 1e7, "2-1"),
    _sn("dnv-c203-D-air", 3.0, 12.164, 15.606, 1e7, "2-1"),
    _sn("dnv-c203-E-air", 3.0, 12.010, 15.350, 1e7, "2-1"),
    _sn("dnv-c203-F-air", 3.0, 11.855, 15.091, 1e7, "2-1"),
    _sn("dnv-c203-D-seawater-cp", 3.0, 11.764, 15.606, 1e6, "2-2"),
    _sn("dnv-c203-F-seawater-cp", 3.0, 11.455, 15.091, 1e6, "2-2"),
    _sn("dnv-c203-D-free-corrosion", 3.0, 11.687, None, None, "2-4"),
    _sn("dnv-c203-F-free-corrosion", 3.0, 11.378, None, None, "2-4"),
)}


def curve(name, where="fatigue curve") -> FatigueCurve:
    """The curve ``name`` (a :class:`FatigueCurve` passes through); ValueError naming the
    known ones otherwise."""
    if isinstance(name, FatigueCurve):
        return name
    if name not in CURVES:
        raise ValueError(f"{where}: unknown curve {name!r}; one of {', '.join(CURVES)}")
    return CURVES[name]
