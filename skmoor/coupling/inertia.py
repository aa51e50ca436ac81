"""Exact-body inertia of a :class:`~skmoor.coupling.system.System`: the Newton-Euler load
(N, N m) of each body with ``rotations='exact'`` beyond the constant mass matrix M, with
the lumped masses (kg) of its line ends carried as point masses on it and its added
masses that turn with it; added by the time integrator.
"""
from __future__ import annotations

import numpy as np

from ..bodies import body as rigid
from ..bodies.large_rotations import added_mass_load, added_mass_tangents


class ExactBodyInertia:
    """The exact-body inertia part of :class:`~skmoor.coupling.system.System` (a mixin on
    its ``dofs``, ``bodies``, ``frames``, ``end_masses`` and body terms)."""

    def _split_added_masses(self, k):
        """Body k's added mass (6, 6; kg, kg m, kg m2) that M holds: its own and its
        terms' constant in global axes, plus those of the terms that turn with it (an
        ``inertia_load``: rods), which :meth:`inertia` corrects on an exact body."""
        added, turning = self.bodies[k].added_mass, []
        for term in self._terms["bodies"]:
            if term.body == k and term.mass_matrix() is not None:
                if callable(getattr(term, "inertia_load", None)):
                    turning.append(term)
                else:
                    added = added + term.mass_matrix()
        self._added_masses.append(added)
        self._turning_masses.append(turning)
        self._with_added.append(bool(added.any() or turning))
        return added + sum(term.mass_matrix() for term in turning)

    @property
    def nonlinear_inertia(self) -> bool:
        """True when a body has rotations='exact': its inertia beyond the constant M
        comes from :meth:`inertia` (the time integrator asks for it)."""
        return any(body.rotations == "exact" for body in self.bodies)

    def inertia(self, x, v, a, tangent=False, layout="sparse", previous=None):
        """G = Q_inertia - M0 qddot of the 'exact' bodies with their lumped line-end masses
        (N, N m; M0 their rigid mass at q = 0, which M holds), plus their added masses
        beyond the constant A qddot (:meth:`_added_inertia`), and with ``tangent`` its
        derivatives (dG/da, dG/dv, dG/dx) in ``layout``; (G, None, None, None) without. Q_inertia is the Newton-Euler load
        at (x, v, a), or with ``previous`` = (x0, v0, a0, G0, h, gamma) (a time step's
        start) its momentum form over the step (:meth:`RigidBody.step_inertia_load`)."""
        G = np.zeros(self.n)
        blocks = [np.zeros((self.nb, self.nb)) for _ in range(3)] if tangent else None
        for k, body in enumerate(self.bodies):
            if body.rotations != "exact":
                continue
            block = self.dofs.blocks[k]
            G[block], slopes = self._body_inertia(k, x[block], v[block], a[block], tangent,
                                                  previous)
            if tangent:
                b = slice(6 * k, 6 * k + 6)
                for out, value in zip(blocks, slopes):
                    out[b, b] = value
        if not tangent:
            return G, None, None, None
        if layout == "dense":
            embedded = []
            for A in blocks:
                full = np.zeros((self.n, self.n))
                full[self.nf:, self.nf:] = A
                embedded.append(full)
            return (G, *embedded)
        return (G, *(self.dofs.embed_bodies(A) for A in blocks))

    def _body_inertia(self, k, q, qdot, qddot, tangent, previous):
        """:meth:`inertia` of exact body k at its DOFs (q, qdot, qddot): its load (6,) and
        with ``tangent`` its derivatives in qddot, qdot and q (None without)."""
        carrier, M0 = self.carrying_body(k)
        frame = self.frames[k]
        with_added = self._with_added[k]
        block = self.dofs.blocks[k]
        if previous is None:
            G = carrier.inertia_load(q, qdot, qddot, frame) - M0 @ qddot
        else:
            x0, v0, a0, G0, h, gamma = previous
            load0 = G0[block] + M0 @ a0[block]  # the rigid body's inertia at the start
            if with_added:  # G0 less its added-mass part
                load0 = load0 - self._added_inertia(k, x0[block], v0[block], a0[block])[0]
            start = (x0[block], v0[block], load0, h, gamma)
            G = carrier.step_inertia_load(q, qdot, *start, frame) - M0 @ qddot
        if with_added:
            added, added_slopes = self._added_inertia(k, q, qdot, qddot, tangent)
            G = G + added
        if not tangent:
            return G, None
        if previous is None:
            d_acc, d_rate, d_pose = carrier.inertia_tangents(q, qdot, qddot, frame)
        else:
            d_acc = np.zeros((6, 6))
            d_rate, d_pose = carrier.step_inertia_tangents(q, qdot, *start, frame)
        if with_added:
            d_acc, d_rate, d_pose = (d_acc + added_slopes[0], d_rate + added_slopes[1],
                                     d_pose + added_slopes[2])
        return G, (d_acc - M0, d_rate, d_pose)

    def _added_inertia(self, k, q, qdot, qddot, tangent=False):
        """(load (6,), its derivatives in qddot, qdot, q or None): exact body k's added mass
        beyond the constant A qddot that M holds (N, N m): the constant one on [a_ref,
        alpha] in global axes (:func:`~skmoor.bodies.large_rotations.added_mass_load`) and the
        terms' that turn with the body (``term.inertia_load``: a rod's)."""
        added = self._added_masses[k]
        parts = []  # (constant A, load, its derivatives or None)
        if added.any():
            parts.append((added, added_mass_load(q, qdot, qddot, added),
                          added_mass_tangents(q, qdot, qddot, added) if tangent else None))
        for term in self._turning_masses[k]:
            parts.append((term.mass_matrix(), term.inertia_load(q, qdot, qddot),
                          term.inertia_tangents(q, qdot, qddot) if tangent else None))
        load = sum((value - constant @ qddot for constant, value, _ in parts), np.zeros(6))
        if not tangent:
            return load, None
        slopes = [sum((d[i] for _, _, d in parts), np.zeros((6, 6))) for i in range(3)]
        slopes[0] -= sum((constant for constant, _, _ in parts), np.zeros((6, 6)))
        return load, slopes

    def carrying_body(self, k):
        """(body k with the lumped masses of its line ends as point masses fixed on it, its
        mass matrix M0 at q = 0): the rigid body whose exact inertia :meth:`inertia`
        takes; M0 is the body's plus the ends' reduction P0^T M P0, which M holds."""
        if k not in self._carrying:
            body, rows = self.bodies[k], self.dofs.body_rows[k]
            if self.end_masses is None or not len(rows) or not self.end_masses[rows].any():
                carrier = body
            else:
                masses = self.end_masses[rows]
                points = body.reference_point + self.dofs.r_local0[k]
                mass = body.mass + masses.sum()
                center = (body.mass * body.center_of_mass + masses @ points) / mass
                inertia = body.inertia.copy()  # about the common centre: parallel axes
                for m, p in zip(np.r_[body.mass, masses],
                                np.vstack([body.center_of_mass, points])):
                    d = p - center
                    inertia += m * (d @ d * np.eye(3) - np.outer(d, d))
                carrier = rigid.RigidBody(mass, center, inertia,
                                          reference_point=body.reference_point,
                                          rotations="exact")
            self._carrying[k] = (carrier, carrier.mass_matrix())
        return self._carrying[k]
