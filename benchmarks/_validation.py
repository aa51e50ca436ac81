"""A validation check's row and the sources the checks cite (benchmarks/validate.py and
the check modules it gathers)."""
from __future__ import annotations

from dataclasses import dataclass

from _cases import version

IRVINE = "elastic catenary (Irvine, Cable Structures, 1981)"
IRVINE_MODES = ("sagged-cable theory (Irvine & Caughey 1974, Proc. R. Soc. A 341; "
                "Irvine 1981, ch. 3)")
STRING = "taut string: omega_n = n pi / L sqrt(T / m)"
FE_ORDER = "P1 finite elements: error ~ h^2"
TIME_ORDER = "generalized-alpha / Newmark: error ~ dt^2 (Chung & Hulbert 1993)"


MOORPY = f"MoorPy {version('moorpy')}, run side by side"
MOORDYN = f"MoorDyn {version('moordyn')}, run side by side"
ORCAFLEX = "OrcaFlex, as published in MoorDyn's validation"
PAPER = "Wang, Er & Iu (the paper): h_s = 0.896 m"


@dataclass
class Row:
    """One check. error: |value / reference - 1| ('rel') or |value - reference| ('abs')."""

    check: str
    reference: float
    source: str
    value: float
    tolerance: float
    kind: str = "rel"
    unit: str = ""

    @property
    def error(self):
        if self.kind == "rel":
            return abs(self.value / self.reference - 1)
        return abs(self.value - self.reference)

    @property
    def status(self):
        return "pass" if self.error <= self.tolerance else "FAIL"


class NotRun(Exception):
    """A check whose input is missing on this machine (a mirror, an optional package): the
    report names it and the reason instead of its rows."""
