"""End forces of a :class:`~skmoor.coupling.system.System`: the forces (N) and moments
(N m) the lines exert on their ends, and the inertia (N) of the ends held fixed or
prescribed (accelerations in m/s2, masses in kg) that the dynamic reactions subtract.
"""
from __future__ import annotations

import functools

import numpy as np
import scipy.sparse as sp


def _compact(A, dense_below=20000):
    """A sparse matrix as a dense array when it has fewer than ``dense_below`` entries
    (a small product costs less so), as CSR else; None when it is zero."""
    A = sp.csr_matrix(A)
    A.eliminate_zeros()
    if not A.nnz:
        return None
    return A.toarray() if A.shape[0] * A.shape[1] < dense_below else A


class EndReactions:
    """The end-force part of :class:`~skmoor.coupling.system.System` (a mixin on its
    ``dofs``, ``lines``, ``ends``, :meth:`line_residual` and prescribed motion)."""

    def _held_masses(self, M_lines, P0):
        """The mass the held (fixed and prescribed) ends share with the rest, kg:
        ``driven_mass`` = P0^T M[:, p], whose product with the prescribed ends'
        accelerations joins the free DOFs' balance (M_fp a_p), and ``end_mass`` = (rows,
        M[e] P0, M[e, p]) of the held ends' rows e ((side, line) pairs, side 0: B, 1: A),
        their own inertia in the reactions (M_ef a_f + M_ep a_p), and ``end_slope_mass``
        the same of their tangent rows (bending lines: the inertia in the clamp moments);
        each None when zero (lumped P1 lines: no M_fp; fixed ends only: no acceleration)."""
        M_lines = sp.csr_matrix(M_lines)
        driven = self.dofs.prescribed_flat
        self.driven_mass = None
        if self.dofs.has_prescribed:
            coupling = (P0.T @ M_lines[:, driven]).tocsr()
            coupling.eliminate_zeros()
            self.driven_mass = coupling if coupling.nnz else None
        rows = [(side, k) for side, ends in enumerate((self.ends.b, self.ends.a))
                for k, end in enumerate(ends) if end[0] in ("fixed", "prescribed")]
        self.end_mass = self.end_slope_mass = None
        if not rows:
            return

        def shares(dofs):  # (rows, M[e] P0, M[e, p]) of the rows e, or None when zero
            on_free, on_driven = (_compact(A) for A in (M_lines[dofs] @ P0,
                                                        M_lines[dofs][:, driven]))
            if on_free is None and on_driven is None:
                return None
            return np.array(rows, int), on_free, on_driven

        self.end_mass = shares(np.array([(self.fairlead_dofs, self.anchor_dofs)[side][k]
                                         for side, k in rows]).ravel())
        slopes = self.lines.slope_dofs
        if slopes is not None:
            nodes = [(self.lines.fairlead_nodes, self.lines.anchor_nodes)[side][k]
                     for side, k in rows]
            self.end_slope_mass = shares(slopes[nodes].ravel())

    def driven_inertia(self, t):
        """M_fp a_p(t) (N, reduced): the inertia the prescribed ends' accelerations put on
        the free DOFs through the mass they share (consistent mass, bending lines), a
        load of the dynamic balance; None when they share none (lumped P1 lines)."""
        if self.driven_mass is None:
            return None
        return self.driven_mass @ self.prescribed_acceleration(t).ravel()

    def end_inertia(self, a, t=0.0):
        """(nlines, 3) inertia (N) of the B and of the A ends held fixed or prescribed,
        M_ef a_f + M_ep a_p (a: reduced accelerations, m/s2, at t, s): the end nodes'
        own mass share and the one they share with their neighbours; zeros at ends on
        free points and bodies (the end's mass moves with them). None when zero."""
        if self.end_mass is None:
            return None
        driven = self.prescribed_acceleration(t).ravel() if self.dofs.has_prescribed else None
        out = self.end_inertias(np.asarray(a)[None], None if driven is None else driven[None])
        return out[0, 0], out[0, 1]

    def end_inertias(self, a, driven, slopes=False):
        """(m, 2, nlines, 3) :meth:`end_inertia` (N; B ends, then A ends) at m states: a
        (m, n) reduced accelerations, driven (m, 3 n_prescribed) the prescribed ends'
        (m/s2; None without prescribed ends); with ``slopes`` that of the ends' tangent
        rows instead (N m per unit of tangent, bending lines)."""
        rows, on_free, on_driven = self.end_slope_mass if slopes else self.end_mass
        values = np.zeros((len(a), 3 * len(rows)))
        if on_free is not None:
            values += (on_free @ a.T).T
        if driven is not None and on_driven is not None:
            values += (on_driven @ driven.T).T
        out = np.zeros((len(a), 2, len(self.lines.lines), 3))
        out[:, rows[:, 0], rows[:, 1]] = values.reshape(len(a), -1, 3)
        return out

    def reactions(self, x, v=None, t=0.0, a=None):
        """(nlines, 3) forces the lines exert on their B ends, and (nlines, 3) on their
        A ends, N: internal force minus loads at the end node, and with the reduced
        accelerations ``a`` (m/s2) less the held ends' inertia (:meth:`end_inertia`);
        without a, quasi-static."""
        v = np.zeros(self.n) if v is None else v
        u = self.full_displacement(x, t)
        return self.end_forces(u, self.full_velocity(x, v, t) if self.needs_velocity
                               else None, t, a)

    def end_forces(self, u, ud, t=0.0, a=None):
        """:meth:`reactions` from the full cable displacement u (m) and velocity ud (m/s,
        None: at rest) at time t (s), and the reduced accelerations a (m/s2, None:
        quasi-static)."""
        R_full, _, _ = self.line_residual(u, ud if self.needs_velocity else None, t,
                                          tangent=False)
        forces = self._resting_on_bed(u, (-R_full[self.fairlead_dofs],
                                          -R_full[self.anchor_dofs]))
        return self.less_inertia(forces, a, t)

    def _resting_on_bed(self, u, forces):
        """The (B, A) end forces with the held ends resting on the sea bed relieved of the
        weight the bed carries there (``SeabedKernel.resting_support``); u (ndofs,) with
        forces (nlines, 3) each, or m states: u (m, ndofs), forces (m, nlines, 3)."""
        plans = self.resting_plans
        if not plans:
            return forces
        out = [forces[0], forces[1]]
        for side, held, support in plans:
            f = np.array(forces[side], float, copy=True)
            f[..., held, :] += support(u)
            out[side] = f
        return out[0], out[1]

    @functools.cached_property
    def resting_plans(self) -> list:
        """(side, held line indices, support(u)) of each end side with held ends, where the
        lines have a sea bed (none: an empty list)."""
        bed = next((term for term in self._terms["lines"]
                    if hasattr(term, "resting_plan")), None)
        if bed is None:
            return []
        lines, plans = self.lines, []
        for side, (ends, nodes) in enumerate(((self.ends.b, lines.fairlead_nodes),
                                              (self.ends.a, lines.anchor_nodes))):
            held = [k for k, end in enumerate(ends) if end[0] in ("fixed", "prescribed")]
            if held:
                plans.append((side, held, bed.resting_plan(self.weight, nodes[held])))
        return plans

    def less_inertia(self, forces, a, t):
        """(B, A end forces) less the held ends' inertia at the accelerations a (a: None,
        or no inertia: the forces as given; Eq. 35's row of the end: f = -(R + M a))."""
        inertia = None if a is None else self.end_inertia(a, t)
        if inertia is None:
            return forces
        return forces[0] - inertia[0], forces[1] - inertia[1]

    def end_moments(self, u, ud, t=0.0, a=None):
        """(nlines, 3) moments (N m) the lines exert on their B ends and (nlines, 3) on
        their A ends at the full displacement u (m) and velocity ud (m/s, None: at rest):
        r' x g, g = -R at the end's tangent DOFs (the generalized force on r'), r' the end
        tangent, and with the reduced accelerations ``a`` (m/s2) g less the tangent rows'
        inertia on the held ends (M_sf a_f + M_sp a_p); zeros on cables, and on pinned
        ends in equilibrium."""
        slopes = self.lines.slope_dofs
        if slopes is None:
            zero = np.zeros((len(self.lines.lines), 3))
            return zero, zero.copy()
        R_full, _, _ = self.line_residual(u, ud if self.needs_velocity else None, t,
                                          tangent=False)
        inertia = np.zeros((2, len(self.lines.lines), 3))
        if a is not None and self.end_slope_mass is not None:
            driven = (self.prescribed_acceleration(t).ravel() if self.dofs.has_prescribed
                      else None)
            inertia = self.end_inertias(np.asarray(a)[None], None if driven is None
                                        else driven[None], slopes=True)[0]
        r = self.lines.reference_dofs + u
        out = []
        for side, nodes in enumerate((self.lines.fairlead_nodes, self.lines.anchor_nodes)):
            dofs = slopes[nodes]
            out.append(np.cross(r[dofs], -R_full[dofs] - inertia[side]))
        return tuple(out)
