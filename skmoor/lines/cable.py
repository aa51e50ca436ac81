"""The cable of Eqs. 11-12 as a term: the LineSet's compiled cable kernel (P1, or Hermite
with bending) entering the equations through the same term protocol as every other term.

The kernels (:class:`~skmoor.lines.cable_kernel.CableKernel`,
:class:`~skmoor.lines.bending.HermiteKernel`) add the internal force of Eq. 9 (Eq. 11 plus
the reference part), the axial damping and, on Hermite lines, the bending force, with their
derivatives; the line weight (Eq. 12's dead load) is the System's load-factor vector.
"""
from __future__ import annotations

from ..fem.terms import Term
from .bending import HermiteKernel
from .cable_kernel import CableKernel


class CableTerm(Term):
    """The cable's internal force on all lines of a :class:`~skmoor.lines.line.LineSet`
    (N; derivatives N/m and N s/m in element blocks); the velocity enters only where the
    lines have axial damping."""

    acts_on = "lines"

    def __init__(self, lines):
        self.lines = lines
        self.kernel = HermiteKernel(lines) if lines.hermite else CableKernel(lines)
        self.damped = lines.damped

    def add_to(self, u, v, t, R, K=None, C=None):
        self.kernel.add_to(u, v if self.damped else None, R, K, C)

    def lowered(self):
        return "cable"
