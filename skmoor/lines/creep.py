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
Its state (the accepted time, z, dz/dt, e, the law's values there and Syrope's highest
mean tension) is one array. On P1 lines the compiled time step runs the term
(:func:`_creep_packed`, by address) and advances that array after each step
(:func:`_commit_packed`; Syrope's working curves rebuilt there when the highest tension
rises, :func:`_working_curve`).
"""
from __future__ import annotations

import math

import numpy as np
from numba import carray, njit

from ..fem.form_compiler import compiled_when_asked
from ..fem.native_calls import advanced
from ..fem.terms import Term, state_part
from .laws import Viscoelastic
from .syrope import FORMS, SyropeCreep

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
    # the state array [t_n, then n each: z, dz/dt, e, F_1, F_1', a, b, dG/dz, the
    # highest mean tension (Syrope's memory, N; NaN for laws without one)]
    z, zdot, _e_n = (state_part(k) for k in range(3))
    _highest = state_part(8)

    @property
    def _per_block(self):
        return self.cells.size

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
        self._where = [np.searchsorted(self.cells, idx) for _, idx, _ in self.groups]
        syropes = [law.static for law, _, _ in self.groups if isinstance(law, SyropeCreep)]
        # the working curves' table width (samples + OWC points) and all OWCs' points
        self._curve_width = max([wc.points + len(wc.owc[0]) for wc in syropes] + [1])
        self._owc_points = sum(len(wc.owc[0]) for wc in syropes)
        self._state = np.full(1 + 9 * self.cells.size, np.nan)  # no accepted state yet
        self._damping = self._dampers()
        lineset.creep = self  # (its reported tension: tension_less_mean)

    def carry_memory(self, other):
        """Take ``other``'s state (the term of the same lines in another model: a line
        failure's rebuilt one) as this term's."""
        if other._state.shape != self._state.shape:
            raise ValueError("CreepTerm.carry_memory: the other term has other elements")
        self._state[:] = other._state

    @property
    def memory(self):
        """The laws' memories per group: Syrope's highest mean tension per element (N,
        views of the state), None for a law without one."""
        return [self._highest[where] if isinstance(law, SyropeCreep) else None
                for (law, _, _), where in zip(self.groups, self._where)]

    @memory.setter
    def memory(self, values):
        for where, value in zip(self._where, values):
            if value is not None:
                self._highest[where] = value

    @property
    def t_n(self):
        """The accepted state's time (s), None before the first."""
        return None if math.isnan(self._state[0]) else float(self._state[0])

    @t_n.setter
    def t_n(self, value):
        self._state[0] = np.nan if value is None else value

    @property
    def _values(self):
        """F_1, dF_1/dz, a, b, dG/dz at the accepted state, per element (views)."""
        n = self.cells.size
        return self._state[1 + 3 * n: 1 + 8 * n].reshape(5, -1)

    @_values.setter
    def _values(self, values):
        self._values[...] = values

    # --- the compiled step's kernels (Viscoelastic and SyropeCreep laws on P1 lines)
    def lowered(self):
        # (P1 lines only: a LineSet refuses static-dynamic laws, creep's too, on bending lines)
        compiled = all(type(law) in (Viscoelastic, SyropeCreep) for law, _, _ in self.groups)
        return "form" if compiled else None

    why_python = "a creep law of a kind the compiled kernels lack"

    @property
    def step_kernel(self):
        """(C function, ints, floats): :func:`_creep_packed` as the compiled time step calls
        a LineForm (by address); ints [n, the elements' node DOFs (2, n, 3), their
        indices (n), then the working curves' (:meth:`_curves`)], floats [X' (n, 3), then
        n each: 1 + e_ref, h, T0, BA, BA_D, EA_s, EA_d (NaN: alphaMBL and beta set it),
        alphaMBL, beta; the state (:meth:`step_state`); the working curves']."""
        n = self.cells.size
        params = np.zeros((4, n))  # EA_s, EA_d, alphaMBL, beta
        BA, BA_D = self._dampers()
        for law, idx, EA in self.groups:
            EA_d = law.EA_dynamic if law.EA_dynamic is not None else np.nan
            params[:, np.searchsorted(self.cells, idx)] = np.array(
                [law.static.nominal_EA(EA), EA_d, law.alpha_MBL or 0.0, law.beta or 0.0]
            )[:, None]
        curve_ints, curve_floats = self._curves()
        ints = np.concatenate([[n], self.dofs_i.ravel(), self.dofs_j.ravel(), self.cells,
                               curve_ints])
        floats = np.concatenate([
            self.Xp.ravel(), self.grow, self.h, self.lines.cable_fields["T0"][self.cells, 0],
            BA, BA_D, *params, self._state, curve_floats])
        return _creep_step(), ints.astype(np.int64), floats.astype(float)

    def _curves(self):
        """(ints, floats) of the Syrope elements' working curves for the compiled commit:
        ints [n each: 1 for Syrope, the WCType (index in FORMS), samples, first OWC point,
        OWC points; then the table width NT and the OWC points of all], floats [n each:
        k1, k2, the highest tension each element's table is built for (NaN: none yet),
        its points; the tables (n, 3, NT): strain, tension, creep strain; the OWCs'
        strains, then their tensions]."""
        n = self.cells.size
        ints, k12 = np.zeros((5, n), np.int64), np.zeros((2, n))
        strains, tensions = [], []
        for (law, _, _), where in zip(self.groups, self._where):
            if isinstance(law, SyropeCreep):
                wc = law.static
                ints[:, where] = np.array([1, FORMS.index(wc.form), wc.points,
                                           sum(map(len, strains)), len(wc.owc[0])])[:, None]
                k12[:, where] = np.array([wc.k1, wc.k2])[:, None]
                strains.append(np.asarray(wc.owc[0], float))
                tensions.append(np.asarray(wc.owc[1], float))
        width, owc = self._curve_width, self._owc_points
        return (np.concatenate([ints.ravel(), [width, owc]]),
                np.concatenate([k12.ravel(), np.full(n, np.nan), np.zeros(n),
                                np.zeros(n * 3 * width), *strains, *tensions]))

    @property
    def step_commit(self):
        """The C function that advances the state in :attr:`step_kernel`'s buffers to an
        accepted step (:func:`_commit_packed`, by address)."""
        return _commit_step()

    def step_state(self):
        """(the state array, its offset from the end of :attr:`step_kernel`'s floats)."""
        n, width = self.cells.size, self._curve_width
        return self._state, self._state.size + 4 * n + 3 * n * width + 2 * self._owc_points

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
        z, relax = np.empty_like(e), np.zeros_like(e)
        T = self.lines.cable_fields["T"][self.cells, 0]
        memories = []
        for law, idx, EA in self.groups:
            where = np.searchsorted(self.cells, idx)
            start, memory = law.creep_start(e[where], T[where], EA)
            memories.append(memory)
            z[where] = (relaxed_creep(law, e[where], EA, memory) if start is None
                        else start)
            relax[where] = getattr(law, "relax", None) or 0.0
        self.memory = memories
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

    def tension_less_mean(self, u, v=None) -> np.ndarray:
        """(nel,) the creep elements' tension at the accepted state less the mean tension
        the cable kernel reports there (N; 0 elsewhere, in statics and before a run)."""
        out = np.zeros(len(self.lines.line_of_cell))
        if self.t_n is not None and not self.lines._static:
            _tensions_less_mean(np.asarray(u, float), np.zeros_like(u) if v is None else
                                np.asarray(v, float), np.stack([self.dofs_i, self.dofs_j]),
                                self.Xp, self.grow, self.h,
                                self.lines.cable_fields["T0"][self.cells, 0], *self._damping,
                                self._state[1:].reshape(9, -1), self.cells,
                                out)
        return out

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


# --- the compiled kernels: add_to and commit above on the packed buffers of step_kernel,
# for Viscoelastic and SyropeCreep laws

@njit(cache=True)
def _unpacked(ints, floats):
    """The buffers of ``CreepTerm.step_kernel`` as arrays: (node DOFs (2, n, 3), element
    indices (n,), X' (n, 3), the parameters (9, n), the state (1 + 9 n,) and its parts
    after the time (9, n): z, dz/dt, e, F_1, F_1', a, b, dG/dz, the highest tension)."""
    n = ints[0]
    dofs = carray(advanced(ints, 1), (2, n, 3))
    cells = carray(advanced(ints, 1 + 6 * n), (n,))
    Xp = carray(floats, (n, 3))
    params = carray(advanced(floats, 3 * n), (9, n))
    state = carray(advanced(floats, 12 * n), (1 + 9 * n,))
    parts = carray(advanced(floats, 12 * n + 1), (9, n))  # the state after its time
    return dofs, cells, Xp, params, state, parts


@njit(cache=True)
def _curves_unpacked(ints, floats, n):
    """The working curves of ``CreepTerm._curves`` as arrays: (the ints (5, n), k1 and k2
    (2, n), the highest tension of each table (n,), its points (n,), the tables (n, 3,
    NT), the OWCs' strains and tensions (2, points))."""
    curve_ints = carray(advanced(ints, 1 + 7 * n), (5, n))
    width, owc = ints[1 + 12 * n], ints[2 + 12 * n]
    start = 21 * n + 1
    k12 = carray(advanced(floats, start), (2, n))
    built = carray(advanced(floats, start + 2 * n), (n,))
    counts = carray(advanced(floats, start + 3 * n), (n,))
    tables = carray(advanced(floats, start + 4 * n), (n, 3, width))
    owcs = carray(advanced(floats, start + 4 * n + 3 * n * width), (2, owc))
    return curve_ints, k12, built, counts, tables, owcs


@njit(cache=True)
def _curve_of(k, highest, curve_ints, k12, built, counts, tables, owcs, alpha, beta):
    """The points of element k's table, built for its highest tension where it is not."""
    if built[k] != highest[k]:
        first, points = curve_ints[3, k], curve_ints[4, k]
        counts[k] = _working_curve(owcs[0, first:first + points], owcs[1, first:first + points],
                                   curve_ints[1, k], k12[0, k], k12[1, k], highest[k],
                                   curve_ints[2, k], alpha[k], beta[k], tables[k])
        built[k] = highest[k]
    return int(counts[k])


@njit(cache=True)
def _interp(x, xp, fp, count):
    """np.interp(x, xp[:count], fp[:count]): linear, the end values beyond the ends."""
    if x <= xp[0]:
        return fp[0]
    if x >= xp[count - 1]:
        return fp[count - 1]
    low, high = 0, count - 1
    while high - low > 1:
        middle = (low + high) // 2
        if xp[middle] <= x:
            low = middle
        else:
            high = middle
    return fp[low] + (fp[high] - fp[low]) / (xp[high] - xp[low]) * (x - xp[low])


@njit(cache=True)
def _working_curve(owc_e, owc_T, form, k1, k2, T_max, points, alpha, beta, table):
    """``syrope.working_curve`` of highest tension T_max (N) and its creep strains
    (``syrope.slow_strain``) into table (3, NT): strain, tension, creep strain; returns
    how many points it has."""
    eps_max = _interp(T_max, owc_T, owc_e, owc_T.size)
    if form == 0 and k1 >= 1.0:  # LINEAR with the slope k1
        eps_min = eps_max - T_max / k1
    else:
        eps_min = owc_e[0] + k1 * (eps_max - owc_e[0])
    step = 1.0 / (points - 1)
    for i in range(points):
        xi = i * step if i < points - 1 else 1.0
        if form == 0 or (form == 2 and abs(math.expm1(k2)) < 1e-14):
            shape = xi
        elif form == 1:
            shape = xi * (k2 * xi + 1.0 - k2)
        else:
            shape = math.expm1(k2 * xi) / math.expm1(k2)
        table[0, i] = eps_min + (eps_max - eps_min) * xi
        table[1, i] = T_max * shape
    count = points
    for j in range(owc_T.size):  # the OWC above T_max
        if owc_T[j] > T_max * (1 + 1e-12):
            table[0, count], table[1, count] = owc_e[j], owc_T[j]
            count += 1
    for i in range(count):
        slow = (table[1, i] / alpha if beta == 0.0
                else math.log1p(beta * table[1, i] / alpha) / beta)
        table[2, i] = table[0, i] - slow
    return count


@njit(cache=True)
def _on_the_curve(z, table, count, alpha, beta):
    """(creep spring's tension F_1, a, b) of a Syrope element at creep strain z: its
    working curve's tension there, a = alpha + beta F_1, b = a e_wc(F_1)."""
    tension = _interp(z, table[2], table[1], count)
    a = alpha + beta * tension
    return tension, a, a * _interp(tension, table[1], table[0], count)


@njit(cache=True)
def _kinematics(u, v, dofs, Xp, grow, h, k, unit, turn):
    """(e, de/dt, |r'|) of element k (``CreepTerm._strains``), r' / |r'| into unit and
    (v' - lamdot r^) / |r'| into turn."""
    lam = 0.0
    for c in range(3):
        unit[c] = Xp[k, c] + (u[dofs[1, k, c]] - u[dofs[0, k, c]]) / h[k]
        lam += unit[c] * unit[c]
    lam = math.sqrt(lam)
    lamdot = 0.0
    for c in range(3):
        unit[c] /= lam
        turn[c] = (v[dofs[1, k, c]] - v[dofs[0, k, c]]) / h[k]
        lamdot += unit[c] * turn[c]
    for c in range(3):
        turn[c] = (turn[c] - lamdot * unit[c]) / lam
    return grow[k] * lam - 1.0, grow[k] * lamdot, lam


@njit(cache=True)
def _step_at(e, edot, h, F1, dF1, a, b, dG, BA, BA_D, zdot_n):
    """``CreepTerm._step`` of one element: (N, dN/de, dN/d(de/dt), zdot)."""
    D = BA + BA_D - 0.5 * h * dG
    zdot = (a * e - b + 0.5 * h * dG * zdot_n + BA_D * edot) / D
    held = 1.0 if e >= 0.0 else 0.0
    spring = held * (F1 + 0.5 * h * dF1 * (zdot_n + zdot))
    gain = held * 0.5 * h * dF1 + BA
    return spring + BA * zdot, gain * a / D, gain * BA_D / D, zdot


@njit(cache=True)
def _stiffnesses(z, EA_s, EA_d, alpha, beta):
    """``Viscoelastic.stiffnesses``: (EA_1, EA_d), N."""
    if math.isnan(EA_d):
        a, b = alpha, beta * max(z, 0.0) * EA_s
        EA_d = 0.5 * (a + b + EA_s + math.sqrt(a * a + 2 * a * (b - EA_s) + (b + EA_s) ** 2))
    return EA_d * EA_s / (EA_d - EA_s), EA_d


@njit(cache=True)
def _tensions_less_mean(u, v, dofs, Xp, grow, h, T0, BA, BA_D, parts, cells, out):
    """``CreepTerm.tension_less_mean`` into out: each element's N at the accepted state
    (parts: the state after its time, (9, n): z, dz/dt, e, F_1, F_1', a, b, dG/dz, the
    highest tension) less T0."""
    unit, turn = np.empty(3), np.empty(3)
    for k in range(cells.size):
        e, edot, _ = _kinematics(u, v, dofs, Xp, grow, h, k, unit, turn)
        out[cells[k]] = _step_at(e, edot, 0.0, parts[3, k], parts[4, k], parts[5, k],
                                 parts[6, k], parts[7, k], BA[k], BA_D[k], parts[1, k])[0] - T0[k]


def _creep_packed(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """``CreepTerm.add_to`` on the buffers of its ``step_kernel``."""
    dofs, cells, Xp, params, state, parts = _unpacked(ints, floats)
    n = cells.size
    if math.isnan(state[0]):
        return
    u, v, R = carray(u_p, (ndofs,)), carray(ud_p, (ndofs,)), carray(R_p, (ndofs,))
    blocks = carray(K_p, (0, 6, 6))
    damping = carray(C_p, (0, 6, 6))
    if tangent:
        nel = 0  # the element blocks of every element: as many as the last index needs
        for k in range(n):
            nel = max(nel, cells[k] + 1)
        blocks, damping = carray(K_p, (nel, 6, 6)), carray(C_p, (nel, 6, 6))
    grow, h, T0, BA, BA_D = params[0], params[1], params[2], params[3], params[4]
    zdot_n, F1, dF1, a, b, dG = parts[1], parts[3], parts[4], parts[5], parts[6], parts[7]
    step = max(t - state[0], 0.0)
    unit, turn = np.empty(3), np.empty(3)
    for k in range(n):
        e, edot, lam = _kinematics(u, v, dofs, Xp, grow, h, k, unit, turn)
        N, dN_de, dN_drate, _ = _step_at(e, edot, step, F1[k], dF1[k], a[k], b[k], dG[k],
                                         BA[k], BA_D[k], zdot_n[k])
        N -= T0[k]  # the kernel keeps T0 along r'
        for c in range(3):
            R[dofs[1, k, c]] += N * unit[c]
            R[dofs[0, k, c]] -= N * unit[c]
        if not tangent:
            continue
        cell = cells[k]
        for p in range(3):
            for q in range(3):
                slope = (unit[p] * (dN_de * grow[k] * unit[q] + dN_drate * grow[k] * turn[q])
                         + N / lam * ((1.0 if p == q else 0.0) - unit[p] * unit[q])) / h[k]
                rate = dN_drate * grow[k] * unit[p] * unit[q] / h[k]
                for target, value in ((blocks, slope), (damping, rate)):
                    target[cell, p, q] += value
                    target[cell, p, q + 3] -= value
                    target[cell, p + 3, q] -= value
                    target[cell, p + 3, q + 3] += value


def _commit_packed(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """``CreepTerm.commit`` on the buffers of its ``step_kernel``, after the start (a
    start, t at or before the state's time, is the Python commit's)."""
    dofs, cells, Xp, params, state, parts = _unpacked(ints, floats)
    n = cells.size
    if math.isnan(state[0]) or t <= state[0]:
        return
    u, v = carray(u_p, (ndofs,)), carray(ud_p, (ndofs,))
    grow, h, BA, BA_D = params[0], params[1], params[3], params[4]
    EA_s, EA_d, alpha, beta = params[5], params[6], params[7], params[8]
    z, zdot_n, e_n, F1, dF1, a, b, dG, highest = (
        parts[0], parts[1], parts[2], parts[3], parts[4], parts[5], parts[6], parts[7],
        parts[8])
    curve_ints, k12, built, counts, tables, owcs = _curves_unpacked(ints, floats, n)
    step = t - state[0]
    unit, turn = np.empty(3), np.empty(3)
    for k in range(n):
        e, edot, _ = _kinematics(u, v, dofs, Xp, grow, h, k, unit, turn)
        zdot = _step_at(e, edot, step, F1[k], dF1[k], a[k], b[k], dG[k], BA[k], BA_D[k],
                        zdot_n[k])[3]
        z[k] += 0.5 * step * (zdot_n[k] + zdot)
        e_n[k] = e
        # the law's values at the new z (their derivatives as the Python term's central
        # differences)
        dz = 1e-7 * max(abs(z[k]), 1e-3)
        if curve_ints[0, k]:  # Syrope: on the working curve of the highest tension
            count = _curve_of(k, highest, curve_ints, k12, built, counts, tables, owcs,
                              alpha, beta)
            passed = _on_the_curve(z[k], tables[k], count, alpha[k], beta[k])[0]
            if passed > highest[k]:  # back on the OWC: a new working curve
                highest[k] = passed
                count = _curve_of(k, highest, curve_ints, k12, built, counts, tables, owcs,
                                  alpha, beta)
            F1[k], a[k], b[k] = _on_the_curve(z[k], tables[k], count, alpha[k], beta[k])
            up_1, up_a, up_b = _on_the_curve(z[k] + dz, tables[k], count, alpha[k], beta[k])
            down_1, down_a, down_b = _on_the_curve(z[k] - dz, tables[k], count, alpha[k],
                                                   beta[k])
            dF1[k] = (up_1 - down_1) / (2 * dz)
            dG[k] = ((up_a - down_a) * e - (up_b - down_b)) / (2 * dz)
        else:  # Viscoelastic
            EA_1, EA_dk = _stiffnesses(z[k], EA_s[k], EA_d[k], alpha[k], beta[k])
            up_1, up_d = _stiffnesses(z[k] + dz, EA_s[k], EA_d[k], alpha[k], beta[k])
            down_1, down_d = _stiffnesses(z[k] - dz, EA_s[k], EA_d[k], alpha[k], beta[k])
            F1[k] = EA_1 * z[k]
            dF1[k] = (up_1 * (z[k] + dz) - down_1 * (z[k] - dz)) / (2 * dz)
            a[k], b[k] = EA_dk, (EA_1 + EA_dk) * z[k]
            dG[k] = ((up_d - down_d) * e - ((up_1 + up_d) * (z[k] + dz)
                                            - (down_1 + down_d) * (z[k] - dz))) / (2 * dz)
        zdot_n[k] = _step_at(e, edot, 0.0, F1[k], dF1[k], a[k], b[k], dG[k], BA[k], BA_D[k],
                             zdot_n[k])[3]
    state[0] = t


_creep_step = compiled_when_asked(_creep_packed)  # (its C function, when first asked for)


_commit_step = compiled_when_asked(_commit_packed)  # (its C function, when first asked for)
