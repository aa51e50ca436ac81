"""The axial force of lines with a creep state (MoorDyn's viscoelastic and Syrope ropes).

Each element of such a line is a creep element (spring F_1(z), damper BA) in series with
a dynamic element (spring of slope a, damper BA_D), z the creep element's strain (-), e
the element's engineering strain (-); the law (:class:`skmoor.lines.laws.Viscoelastic`,
:class:`skmoor.lines.syrope.SyropeCreep`) gives F_1(z) and the drive a e - b (the dynamic
spring's tension less the creep spring's) at z. Force balance through the two elements
(MoorDyn's Line.cpp, Line::getStateDeriv):

    dz/dt = (a e - b + BA_D de/dt) / (BA + BA_D),    tension N = F_1(z) + BA dz/dt

(F_1 counted only while e >= 0: a slack segment carries its dampers' force only, as in
MoorDyn). Over a step of h from an accepted state (z_n, zdot_n) the creep state follows
the trapezoidal rule, the drive's and F_1's z-dependence linearized at z_n:

    zdot = (a e - b + G_z h/2 zdot_n + BA_D de/dt) / (BA + BA_D - G_z h/2)
    N    = F_1(z_n) + F_1'(z_n) h/2 (zdot_n + zdot) + BA zdot

linear in (e, de/dt) within the step: its tangent is exact, and the scheme is the
trapezoidal rule itself when F_1 and the drive are linear in z (``EA_s|EA_d``). The
accepted state is kept by ``commit`` (:mod:`skmoor.fem.terms`); h = t - t_n, so statics and
modes (t = t_n) see the instantaneous stiffness a BA / (BA + BA_D).

The term acts on the lines whose law has a creep state, in time only: the statics solve
with their static laws (``LineSet.use_static_laws``) and the term adds nothing there. In
time the cable kernel keeps each such element's mean tension T_mean along it (the law's
dynamic parameters, which balance the reference part of Eq. 9), and the term adds
N - T_mean along r'.
It runs in Python (vectorized over the elements): the compiled step leaves a model with
it to the Python step.
"""
from __future__ import annotations

import numpy as np

from ..fem.terms import Term

__all__ = ["CreepTerm", "has_creep", "relaxed_creep"]

RELAX_STEPS = 2000  # steps of the held-ends relaxation at t = 0 (MoorDyn's IC stage)


def has_creep(law) -> bool:
    """True for a law whose axial force needs a creep state (a CreepTerm)."""
    return callable(getattr(law, "creep_drive", None))


def relaxed_creep(law, e, EA, memory=None, iterations=80):
    """The creep strain z (-) in creep equilibrium at strain e (a e = b), by bisection
    on [min(e, 0), max(e, 0)] (the drive falls as z rises)."""
    e = np.asarray(e, float)
    lo, hi = np.minimum(e, 0.0), np.maximum(e, 0.0)
    for _ in range(iterations):
        z = 0.5 * (lo + hi)
        a, b = law.creep_drive(z, EA, memory)
        rising = a * e - b > 0
        lo, hi = np.where(rising, z, lo), np.where(rising, hi, z)
    return 0.5 * (lo + hi)


class CreepTerm(Term):
    """The axial force of every element whose line's law has a creep state (see the
    module docstring), with its creep state z integrated over the accepted steps."""

    acts_on = "lines"

    def __init__(self, lineset):
        self.lines = lineset
        cells = np.zeros(lineset.line_of_cell.shape, bool)
        self.groups = []  # (law, element indices, EA) of each creep line
        for k, (law, line) in enumerate(zip(lineset.laws, lineset.lines)):
            if has_creep(law):
                idx = np.nonzero(lineset.line_of_cell == k)[0]
                self.groups.append((law, idx, line.line_type.EA))
                cells[idx] = True
        if not self.groups:
            raise ValueError("CreepTerm: no line has a law with a creep state")
        self.cells = np.nonzero(cells)[0]
        f = lineset.cable_fields
        self.Xp = f["Xp"][:, self.cells, 0].T  # (n, 3) reference tangents
        self.grow = 1.0 + f["e_ref"][self.cells, 0]  # 1 + e_ref: stretch from unstretched
        self.h = lineset.element_lengths[self.cells]
        t = lineset.mesh.t
        nodal = lineset.nodal_dofs
        self.dofs_i, self.dofs_j = nodal[t[0]][self.cells], nodal[t[1]][self.cells]
        self.t_n = None  # the accepted state: time, z, dz/dt, the laws' memories
        self.z = self.zdot = None
        self.memory = [None] * len(self.groups)

    # --- kinematics of the elements
    def _strains(self, u, v):
        """(e, de/dt, r' / |r'|, |r'|, (v' - lamdot r^) / |r'|) of the elements."""
        up = (u[self.dofs_j] - u[self.dofs_i]) / self.h[:, None]
        rp = self.Xp + up
        lam = np.linalg.norm(rp, axis=1)
        unit = rp / lam[:, None]
        if v is None:
            vp = np.zeros_like(rp)
        else:
            vp = (v[self.dofs_j] - v[self.dofs_i]) / self.h[:, None]
        lamdot = np.einsum("ij,ij->i", unit, vp)
        turn = (vp - lamdot[:, None] * unit) / lam[:, None]
        return self.grow * lam - 1.0, self.grow * lamdot, unit, lam, turn

    def _law_values(self, z):
        """F_1, dF_1/dz, a, b, dG/dz (G = a e - b at the committed strain) at z, per element."""
        F1, dF1, a, b, dG = (np.empty_like(z) for _ in range(5))
        for (law, idx, EA), memory in zip(self.groups, self.memory):
            where = np.searchsorted(self.cells, idx)
            zk = z[where]
            dz = 1e-7 * np.maximum(np.abs(zk), 1e-3)
            F1[where] = law.creep_spring(zk, EA, memory)
            dF1[where] = (law.creep_spring(zk + dz, EA, memory)
                          - law.creep_spring(zk - dz, EA, memory)) / (2 * dz)
            a[where], b[where] = law.creep_drive(zk, EA, memory)
            e = self._e_n[where]
            up, down = law.creep_drive(zk + dz, EA, memory), law.creep_drive(zk - dz, EA, memory)
            dG[where] = ((up[0] - down[0]) * e - (up[1] - down[1])) / (2 * dz)
        return F1, dF1, a, b, dG

    def _dampers(self):
        BA, BA_D = np.empty(self.cells.size), np.empty(self.cells.size)
        for law, idx, _ in self.groups:
            where = np.searchsorted(self.cells, idx)
            BA[where], BA_D[where] = law.creep_damping, law.dynamic_damping
        return BA, BA_D

    def _step(self, e, edot, h):
        """(N, dN/de, dN/d(de/dt), zdot) over a step of h (s) from the accepted state."""
        F1, dF1, a, b, dG = self._values
        BA, BA_D = self._damping
        D = BA + BA_D - 0.5 * h * dG
        zdot = (a * e - b + 0.5 * h * dG * self.zdot + BA_D * edot) / D
        held = np.where(e >= 0.0, 1.0, 0.0)  # a slack segment: its dampers only
        spring = held * (F1 + 0.5 * h * dF1 * (self.zdot + zdot))
        gain = held * 0.5 * h * dF1 + BA  # dN/dzdot
        return spring + BA * zdot, gain * a / D, gain * BA_D / D, zdot

    # --- the accepted states
    def commit(self, t, u, v):
        e, edot, *_ = self._strains(u, v)
        if self.t_n is None or t < self.t_n:  # a (new) start
            self._start(e)
        else:
            h = t - self.t_n
            zdot = self._step(e, edot, h)[3]
            self.z = self.z + 0.5 * h * (self.zdot + zdot)
            self.memory = [law.creep_update(self.z[np.searchsorted(self.cells, idx)], EA, m)
                           for (law, idx, EA), m in zip(self.groups, self.memory)]
        self.t_n, self._e_n = t, e
        self._refresh()
        self.zdot = self._step(e, edot, 0.0)[3]  # the rate at the accepted state

    def _start(self, e):
        """The creep state at t = 0 from the laws (``creep_start``; None: relaxed at e),
        then relaxed over the law's ``relax`` s with the ends held (MoorDyn's IC stage)."""
        self._damping = self._dampers()
        z, relax = np.empty_like(e), np.zeros_like(e)
        T = self.lines.cable_fields["T"][self.cells, 0]
        for k, (law, idx, EA) in enumerate(self.groups):
            where = np.searchsorted(self.cells, idx)
            start, self.memory[k] = law.creep_start(e[where], T[where], EA)
            z[where] = (relaxed_creep(law, e[where], EA, self.memory[k]) if start is None
                        else start)
            relax[where] = getattr(law, "relax", None) or 0.0
        self.z, self._e_n, rest = z, e, np.zeros_like(e)
        self.zdot = rest
        for duration in np.unique(relax[relax > 0]):
            held, h = relax == duration, duration / RELAX_STEPS
            for _ in range(RELAX_STEPS):
                self._refresh()
                self.zdot = self._step(e, rest, 0.0)[3]
                zdot = self._step(e, rest, h)[3]
                self.z = np.where(held, self.z + 0.5 * h * (self.zdot + zdot), self.z)
        self.zdot = rest

    def _refresh(self):
        self._values = self._law_values(self.z)

    # --- the residual
    def add_to(self, u, v, t, R, K=None, C=None):
        if getattr(self.lines, "_static", False):
            return  # statics: the static laws carry the axial force
        if self.t_n is None or t < self.t_n:  # before a run's first state: start at this one
            self.commit(t, u, v)
        e, edot, unit, lam, turn = self._strains(u, v)
        N, dN_de, dN_drate, _ = self._step(e, edot, max(t - self.t_n, 0.0))
        N = N - self.lines.cable_fields["T0"][self.cells, 0]  # the kernel keeps T0 along r'
        force = N[:, None] * unit
        np.add.at(R, self.dofs_j, force)
        np.add.at(R, self.dofs_i, -force)
        if K is None:
            return
        # g = N r^: dg/dr' = r^ (dN/dr')^T + N (I - r^ r^^T) / lam, dN/dr' from e and de/dt
        dN_drp = ((dN_de * self.grow)[:, None] * unit
                  + (dN_drate * self.grow)[:, None] * turn)
        eye = np.eye(3)[None]
        k = (unit[:, :, None] * dN_drp[:, None, :]
             + (N / lam)[:, None, None] * (eye - unit[:, :, None] * unit[:, None, :]))
        c = (dN_drate * self.grow)[:, None, None] * unit[:, :, None] * unit[:, None, :]
        for blocks, slope in ((K, k), (C, c)):
            slope = slope / self.h[:, None, None]
            blocks[self.cells, :3, :3] += slope
            blocks[self.cells, :3, 3:] -= slope
            blocks[self.cells, 3:, :3] -= slope
            blocks[self.cells, 3:, 3:] += slope
