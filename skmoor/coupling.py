"""The coupling block: lines + rigid body reduced to one nonlinear system.

Unknowns x = [free cable DOFs, body DOFs q = (x, y, z, rx, ry, rz)]. Anchors are fixed;
each fairlead either follows the body with exact rigid-body kinematics
(position = body position + R(rotation) r_local), is fixed, or follows a prescribed
motion. With u(x) the full cable displacement and P = du/dx:

    R_red = P^T R_lines(u) + R_body(q),
    K_red = P^T K_lines P + sum_k f_k . d2p_k/dq2 + K_hydrostatic,
    M_red = P0^T M_lines P0 + M_body + added mass (P0 = P at q = 0, constant);
    the body residual adds hydrostatics, its linear damping and the applied loads.

(``skfem.mpc`` drops the slave equations, so the reduction is written out here.)
"""
from __future__ import annotations

from dataclasses import dataclass, field

import math

import numpy as np
import scipy.sparse as sp
from skfem import asm

from . import body as rigid
from .banded import LAYOUTS, as_layout
from .kernels import CableKernel, ElementPattern


@dataclass
class Term:
    """A term added to the cable residual, written as scikit-fem forms.

    residual: LinearForm of (v, w) with w.u (displacement, m), w.du (velocity, m/s),
    w.t (time, s) and the LineSet's reference fields available, plus ``fields``; its
    value is added to internal - external forces (N). stiffness / damping: BilinearForms,
    its derivatives with respect to u and to the velocity (None when zero). mass:
    BilinearForm of a constant extra mass (e.g. added mass, kg), assembled once at u = 0.
    fields: a dict, or a function t -> dict for time-dependent data (waves, currents).
    quadrature: 'gauss' (``LineSet.basis``), 'midpoint' (``LineSet.cable_basis``) or
    'nodal' (``LineSet.nodal_basis``).

    Anything with the method ``evaluate`` below (and optionally ``mass_matrix``) can be
    a term; a compiled kernel of the same forms also has ``add_to`` (see
    :mod:`skmoor.kernels`), which the System calls instead.
    """

    residual: object
    stiffness: object = None
    damping: object = None
    mass: object = None
    fields: object = field(default_factory=dict)
    quadrature: str = "gauss"

    def __post_init__(self):
        if self.quadrature not in ("gauss", "midpoint", "nodal"):
            raise ValueError(f"Term quadrature: {self.quadrature!r} is not 'gauss', "
                             "'midpoint' or 'nodal'")

    def _basis_and_fields(self, lines, t):
        if self.quadrature == "midpoint":
            basis, base = lines.cable_basis, lines.cable_fields
        elif self.quadrature == "nodal":
            basis, base = lines.nodal_basis, lines.nodal_fields
        else:
            basis, base = lines.basis, lines.fields
        extra = self.fields(t) if callable(self.fields) else self.fields
        return basis, dict(base, t=t, **extra)

    def evaluate(self, lines, u, ud, t, tangent=True, layout="sparse"):
        """(R, K, Kv) on the full cable DOFs: residual (N), d/du and d/dudot (None when
        zero or not asked for) as ``layout`` ('sparse', 'dense' or 'band', see
        :func:`~skmoor.banded.as_layout`)."""
        basis, w = self._basis_and_fields(lines, t)
        w.update(u=u, du=np.zeros_like(u) if ud is None else ud)
        R = asm(self.residual, basis, **w)
        K = Kv = None
        if tangent and self.stiffness is not None:
            K = as_layout(asm(self.stiffness, basis, **w), layout, lines.bandwidth)
        if tangent and self.damping is not None:
            Kv = as_layout(asm(self.damping, basis, **w), layout, lines.bandwidth)
        return R, K, Kv

    def mass_matrix(self, lines):
        """The constant extra mass (sparse, kg), or None."""
        if self.mass is None:
            return None
        basis, w = self._basis_and_fields(lines, 0.0)
        return asm(self.mass, basis, u=np.zeros(lines.ndofs), du=np.zeros(lines.ndofs), **w)


@dataclass
class BodyTerm:
    """A load on the rigid body: ``evaluate(q, qdot, t) -> (F, K, Kv)`` with F the
    6-vector of loads on the body (N, N m) and K = -dF/dq, Kv = -dF/dqdot (6x6 or None);
    ``added_mass``: a constant 6x6 (kg, kg m, kg m2) added to the body's mass."""

    load: object
    added_mass: object = None

    def evaluate(self, q, qdot, t):
        return self.load(q, qdot, t)


class System:
    """Lines (a :class:`~skmoor.line.LineSet`) and an optional rigid body, reduced.

    fairleads: 'body' (attached to ``body``), 'fixed', or 'prescribed' with
    ``motion(t) -> (nlines, 3)`` fairlead displacements, m.
    body_load(t, q, qdot) -> 6-vector of applied body loads (N, N m), optional.
    terms: extra cable terms (:class:`Term` or anything with its ``evaluate``);
    body_terms: extra body loads with tangents (:class:`BodyTerm`).
    Add terms after construction with :meth:`add_term` (it updates the mass matrix).
    """

    def __init__(self, lines, body=None, *, fairleads="body", motion=None,
                 body_load=None, terms=(), body_terms=(), lumped_mass=True):
        if fairleads not in ("body", "fixed", "prescribed"):
            raise ValueError(f"System fairleads: {fairleads!r} is not 'body', 'fixed' or 'prescribed'")
        if fairleads == "body" and body is None:
            raise ValueError("System body: fairleads='body' needs a RigidBody")
        if fairleads == "prescribed" and not callable(motion):
            raise ValueError("System motion: fairleads='prescribed' needs motion(t) -> (nlines, 3)")
        self.lines, self.body, self.mode = lines, (body if fairleads == "body" else None), fairleads
        self.motion, self.body_load = motion, body_load
        self.terms, self.body_terms = list(terms), list(body_terms)
        self.kernel = CableKernel(lines)
        self._block_shape = (self.kernel.pattern.nel, 6, 6)
        self._damped = lines.damped
        dofs = lines.nodal_dofs
        self.fairlead_dofs = dofs[lines.fairlead_nodes]  # (nlines, 3)
        self._fairlead_flat = self.fairlead_dofs.ravel()
        held = np.concatenate([dofs[lines.anchor_nodes].ravel(), self.fairlead_dofs.ravel()])
        self.free = np.setdiff1d(np.arange(lines.ndofs), held)
        self.nf = len(self.free)
        self.nb = 6 if self.body is not None else 0
        self.n = self.nf + self.nb
        self._free_pattern = None if self.nb else ElementPattern(lines, keep=self.free)
        if self.body is not None:
            self.r_local = lines.points[lines.fairlead_nodes] - self.body.reference_point
            self.K_body = self.body.hydrostatic_stiffness(generalized=True)
            self.F_body0 = self.body.static_force()
        self._attachment_cache = (None, None, None)
        self._prescribed_cache = (None, None, None)
        self.weight = lines.weight_load()
        self.M_lines = lines.mass_matrix(lumped=lumped_mass).tocsr()
        self._free_block = sp.csr_matrix((np.ones(self.nf), (self.free, np.arange(self.nf))),
                                         shape=(lines.ndofs, self.n))
        self._assemble_mass()

    def add_term(self, term):
        """Add a cable :class:`Term` or a :class:`BodyTerm` (and its mass)."""
        (self.body_terms if isinstance(term, BodyTerm) else self.terms).append(term)
        self._assemble_mass()

    def _assemble_mass(self):
        """M_red = P0^T (M_lines + term masses) P0 + body mass + added masses, kg."""
        M_lines = self.M_lines
        for term in self.terms:
            extra = term.mass_matrix(self.lines) if hasattr(term, "mass_matrix") else None
            if extra is not None:
                M_lines = M_lines + extra
        self.M = self._reduce_constant(M_lines)
        if self.body is not None:
            body_mass = self.body.mass_matrix() + self.body.added_mass
            for term in self.body_terms:
                if term.added_mass is not None:
                    body_mass = body_mass + np.asarray(term.added_mass, float)
            self.M = (self.M + self._embed_body(body_mass)).tocsr()

    # --- maps between reduced and full cable DOFs
    def q(self, x):
        """Body DOFs of a reduced vector (zeros without a body)."""
        return x[self.nf:] if self.nb else np.zeros(6)

    def full_displacement(self, x, t=0.0):
        """(ndofs,) cable displacement for reduced state x at time t, m."""
        return self._displacement(x, self.fairlead_displacement(x, t))

    def _displacement(self, x, fairleads):
        """(ndofs,) cable displacement from the free DOFs of x and (nlines, 3) fairlead
        displacements."""
        u = np.zeros(self.lines.ndofs)
        u[self.free] = x[: self.nf]
        u[self._fairlead_flat] = fairleads.ravel()
        return u

    def _attachment(self, x):
        """Fairlead displacements (nlines, 3) and stacked Jacobians (3 nlines, 6) at the
        body DOFs of x, computed once per state."""
        q = x[self.nf:]
        key = q.tobytes()
        if self._attachment_cache[0] != key:
            if not math.isfinite(q.sum()):
                raise ValueError(f"System: body DOFs are not finite: {q}")
            self._attachment_cache = (key, *rigid.attachment_state(q, self.r_local))
        return self._attachment_cache[1], self._attachment_cache[2]

    def fairlead_displacement(self, x, t=0.0):
        """(nlines, 3) fairlead displacements, m."""
        if self.mode == "body":
            return self._attachment(x)[0]
        if self.mode == "prescribed":
            return self._prescribed(t)[0]
        return np.zeros(self.fairlead_dofs.shape)

    def _prescribed(self, t, dt=1e-6):
        """Prescribed fairlead displacements (m) and velocities (central differences over
        dt, m/s) at time t, (nlines, 3) each; the last time's are kept (Newton revisits it)."""
        if self._prescribed_cache[0] != (t, dt):
            def at(time):
                return np.asarray(self.motion(time), float).reshape(-1, 3)
            self._prescribed_cache = ((t, dt), at(t), (at(t + dt) - at(t - dt)) / (2 * dt))
        return self._prescribed_cache[1:]

    def full_velocity(self, x, v, t=0.0, dt=1e-6):
        """(ndofs,) cable velocity, m/s."""
        return self._velocity(x, v, t, self._jacobian(x), dt)

    def _velocity(self, x, v, t, J, dt=1e-6):
        ud = self._expand(v, J)
        if self.mode == "prescribed":
            ud[self.fairlead_dofs] = self._prescribed(t, dt)[1]
        return ud

    def _jacobian(self, x):
        """(3 nlines, 6) fairlead Jacobians stacked, or None without a body."""
        if not self.nb:
            return None
        return self._attachment(x)[1]

    def _expand(self, y, J):
        """P y for a reduced vector y, without forming P."""
        out = np.zeros(self.lines.ndofs)
        out[self.free] = y[: self.nf]
        if J is not None:
            out[self._fairlead_flat] = J @ y[self.nf:]
        return out

    def _reduce(self, R_full, J):
        """P^T R_full, without forming P."""
        out = np.empty(self.n)
        out[: self.nf] = R_full[self.free]
        if J is not None:
            out[self.nf:] = J.T @ R_full[self._fairlead_flat]
        return out

    def _reduce_dense(self, A, J):
        """P^T A P for a dense (ndofs, ndofs) A, without forming P."""
        free, fair = self.free, self._fairlead_flat
        out = np.empty((self.n, self.n))
        out[: self.nf, : self.nf] = A[np.ix_(free, free)]
        if J is not None:
            out[: self.nf, self.nf:] = A[np.ix_(free, fair)] @ J
            out[self.nf:, : self.nf] = J.T @ A[np.ix_(fair, free)]
            out[self.nf:, self.nf:] = J.T @ A[np.ix_(fair, fair)] @ J
        return out

    def _reduce_sparse(self, A, x):
        """P^T A P for a sparse A (a row and column selection without a body)."""
        if not self.nb:
            return A[self.free][:, self.free]
        P = self.P(x)
        return (P.T @ A @ P).tocsr()

    def P(self, x):
        """du/dx (ndofs, n): identity on free DOFs, attachment Jacobians at fairleads."""
        if not self.nb:
            return self._free_block
        J = rigid.attachment_jacobian(self.q(x), self.r_local)  # (nlines, 3, 6)
        rows = np.repeat(self.fairlead_dofs.ravel(), 6)
        cols = np.tile(self.nf + np.arange(6), self.fairlead_dofs.size)
        body = sp.csr_matrix((J.ravel(), (rows, cols)), shape=self._free_block.shape)
        return self._free_block + body

    def _reduce_constant(self, A):
        P0 = self.P(np.zeros(self.n))
        return (P0.T @ A @ P0).tocsr()

    def _embed_body(self, A6, dense=False):
        """A 6x6 body block in an (n, n) matrix."""
        out = np.zeros((self.n, self.n))
        out[self.nf:, self.nf:] = A6
        return out if dense else sp.csr_matrix(out)

    @property
    def _needs_velocity(self):
        return bool(self.terms) or self._damped

    # --- the nonlinear system
    def line_residual(self, u, ud, t=0.0, load_factor=1.0, tangent=True, layout="sparse"):
        """Full cable residual internal - external (N) and its u- and v-derivatives in
        ``layout`` ('sparse', 'dense' or 'band')."""
        R, Ke, Ce, assembled = self._line_blocks(u, ud, t, load_factor, tangent, layout)
        if not tangent:
            return R, None, None
        return (R, *self._sum(self.kernel.pattern, Ke, Ce, assembled, layout,
                              self.lines.bandwidth))

    def _line_blocks(self, u, ud, t, load_factor, tangent, layout):
        """The cable residual (N) with the element blocks of its derivatives (d/du, d/dv;
        None without ``tangent``) that the kernels add into, and the (K, Kv) pairs the
        form terms assemble themselves (full DOFs, sparse unless ``layout`` is dense)."""
        R = -load_factor * self.weight
        Ke = Ce = None
        if tangent:
            Ke, Ce = np.zeros(self._block_shape), np.zeros(self._block_shape)
        self.kernel.add_to(u, ud if self._damped else None, R, Ke, Ce)
        assembled = []
        for term in self.terms:
            if hasattr(term, "add_to"):
                term.add_to(self.lines, u, ud, t, R, Ke, Ce)
            else:
                Rt, Kt, Cv = term.evaluate(self.lines, u, ud, t, tangent,
                                           "dense" if layout == "dense" else "sparse")
                R += Rt
                assembled.append((Kt, Cv))
        return R, Ke, Ce, assembled

    def _sum(self, pattern, Ke, Ce, assembled, layout, bandwidth, reduce=None):
        """K, Kv in ``layout``: the element blocks assembled on ``pattern`` plus the form
        terms' matrices (passed through ``reduce`` first when given)."""
        K = pattern.assemble(Ke, layout)
        Kv = pattern.assemble(Ce, layout) if self._needs_velocity else None
        for Kt, Cv in assembled:
            if Kt is not None:
                K = K + as_layout(Kt if reduce is None else reduce(Kt), layout, bandwidth)
            if Cv is not None:
                Cv = as_layout(Cv if reduce is None else reduce(Cv), layout, bandwidth)
                Kv = Cv if Kv is None else Kv + Cv
        return K, Kv

    @property
    def bandwidth(self):
        """Half-bandwidth of the reduced matrices without a body (None with one: its
        rows and columns couple all fairleads)."""
        return None if self.nb else self._free_pattern.bandwidth

    def residual(self, x, v=None, t=0.0, load_factor=1.0, tangent=True, layout="sparse"):
        """Reduced residual R(x, v, t) (no inertia, no Rayleigh damping) and its
        derivatives K = dR/dx and Kv = dR/dv (None when zero) in ``layout``: 'sparse'
        (CSR), 'dense' (arrays, faster below a few hundred unknowns) or, without a body,
        'band' (:class:`~skmoor.banded.Band`, half-bandwidth :attr:`bandwidth`)."""
        if layout not in LAYOUTS:
            raise ValueError(f"System.residual layout: {layout!r} is not one of {LAYOUTS}")
        if layout == "band" and self.nb:
            raise ValueError("System.residual layout: 'band' needs a System without a body")
        v = np.zeros(self.n) if v is None else v
        if self.nb:
            fairleads, J = self._attachment(x)
        else:
            fairleads, J = self.fairlead_displacement(x, t), None
        u = self._displacement(x, fairleads)
        ud = self._velocity(x, v, t, J) if self._needs_velocity else None
        if self.nb or not tangent:
            R_full, K_full, Kv_full = self.line_residual(u, ud, t, load_factor, tangent, layout)
        else:  # no body: the element blocks go straight into the free-DOF matrices
            R_full, Ke, Ce, assembled = self._line_blocks(u, ud, t, load_factor, True, layout)
        R = self._reduce(R_full, J)
        if self.nb:
            q = self.q(x)
            R[self.nf:] += self.K_body @ q - load_factor * self.F_body0
            R[self.nf:] += self.body.linear_damping @ v[self.nf:]
            if self.body_load is not None:
                R[self.nf:] -= self.body_load(t, q, v[self.nf:])
            body_K = body_Kv = 0.0
            for term in self.body_terms:
                F, Kb, Kvb = term.evaluate(q, v[self.nf:], t)
                R[self.nf:] -= F
                body_K = body_K if Kb is None else body_K + Kb
                body_Kv = body_Kv if Kvb is None else body_Kv + Kvb
        if not tangent:
            return R, None, None
        dense = layout == "dense"
        if not self.nb:
            reduce = self._reduce_dense if dense else self._reduce_sparse
            K, Kv = self._sum(self._free_pattern, Ke, Ce, assembled, layout, self.bandwidth,
                              reduce=lambda A: reduce(A, None))
            return R, K, Kv
        if dense:
            K = self._reduce_dense(K_full, J)
            Kv = None if Kv_full is None else self._reduce_dense(Kv_full, J)
        else:
            K, Kv = (None if A is None else self._reduce_sparse(A, x) for A in (K_full, Kv_full))
        H = rigid.attachment_hessian(self.q(x), self.r_local, R_full[self.fairlead_dofs])
        K = K + self._embed_body(H + self.K_body + body_K, dense)
        if np.any(self.body.linear_damping) or np.any(body_Kv):
            D = self._embed_body(self.body.linear_damping + body_Kv, dense)
            Kv = D if Kv is None else Kv + D
        return R, K, Kv

    def reactions(self, x, v=None, t=0.0):
        """(nlines, 3) forces the lines exert on their fairleads, and (nlines, 3) on their
        anchors, N (quasi-static: internal force minus loads at the end node)."""
        v = np.zeros(self.n) if v is None else v
        u = self.full_displacement(x, t)
        ud = self.full_velocity(x, v, t) if self._needs_velocity else None
        R_full, _, _ = self.line_residual(u, ud, t, tangent=False)
        dofs = self.lines.nodal_dofs
        return -R_full[self.fairlead_dofs], -R_full[dofs[self.lines.anchor_nodes]]
