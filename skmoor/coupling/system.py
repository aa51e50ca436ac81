"""The coupling block: a network of lines, points and rigid bodies reduced to one
nonlinear system.

Each line end sits on a fixed point, a prescribed (coupled) point, a free point (its own
3 DOFs, shared by every line that ends there) or a dynamic body, with exact rigid-body
kinematics (position = body position + R(rotation) r_local). With u(x) the full cable
displacement and P = du/dx:

    R_red = P^T R_lines(u) + R_points + R_bodies(q),
    K_red = P^T K_lines P + sum_k f_k . d2p_k/dq2 + K_hydrostatic,
    M_red = P0^T M_lines P0 + point masses + body masses (P0 = P at q = 0, constant);
    the body residual adds hydrostatics, its linear damping and the applied loads; a
    free point's, its net buoyancy (rho V - m) g and its drag.

A body with ``rotations='exact'`` takes its buoyancy and weight at the current pose (hull
clipped at z = 0) and its applied moments through E^T (:mod:`skmoor.bodies.large_rotations`);
its inertia beyond the constant M (which holds its mass matrix at q = 0) is
:meth:`System.inertia`, added by the time integrator.

(``skfem.mpc`` drops the slave equations, so the reduction is written out here.)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..bodies import body as rigid
from ..bodies.body_motion import BodyMotion
from ..bodies.large_rotations import (
    added_mass_load,
    added_mass_tangents,
    generalized_load,
    rate_matrix,
    zyx_angles,
)
from ..bodies.motion import SECOND_DIFFERENCE, acceleration_of
from ..fem.patterns import ElementPattern
from ..fem.terms import Term
from ..lines.cable_kernel import CableKernel
from ..numerics.banded import LAYOUTS, as_layout
from .no_lines import EmptyPattern, NoLineKernel

REBASE_PITCH = math.radians(60.0)  # |ry| past which an 'exact' body's angles are re-based


@dataclass
class PointMass:
    """What acts on a free point of the network (MoorDyn's and MoorPy's point): mass (kg),
    volume (m3, its buoyancy rho g V), CdA (m2: drag 0.5 rho CdA |U - v| (U - v), U the
    current at the point) and Ca (added mass rho V Ca)."""

    mass: float = 0.0
    volume: float = 0.0
    CdA: float = 0.0
    Ca: float = 0.0
    rho: float = 1025.0
    g: float = 9.81

    def __post_init__(self):
        for name in ("mass", "volume", "CdA", "Ca", "rho", "g"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float, np.floating)) and math.isfinite(value)
                    and value >= 0):
                raise ValueError(f"point {name}: must be a finite number >= 0, got {value!r}")


@dataclass
class Ends:
    """What each line end of a :class:`System` is held by, one entry per line for end A
    (the first node) and end B (the last):

    ``("fixed",)``; ``("prescribed", slot)`` (moved by ``motion(t)[slot]``); ``("point", p)``
    (free point p: its own 3 DOFs); ``("body", b)`` (on dynamic body b, where the line's
    reference state puts the end).

    clamped: the ends of bending (Hermite) lines whose tangent is held, as
    ``(line index, "a" or "b")`` pairs (the others are pinned: the end tangent free): on a
    fixed end at the reference tangent t0; on a body it turns with the body, R(q) t0; on
    a prescribed end at t0, or with a third entry ``slot``, ``(k, end, slot)``, at
    t0 + motion(t)[slot] (a clamp on a coupled body that turns: R(t) t0 - t0 there).
    MoorDyn clamps a line by ending it on a rod; here the line end says so itself.

    smooth: C1 joints of bending lines, as ``(k, j)`` pairs: end B of line k and end A of
    line j sit on the same free point and share their tangent DOFs (the same d/ds of
    the displacement, so r' is continuous when their reference tangents there are
    equal): the joint carries the bending moment. Without it a free point is a hinge.
    """

    a: list
    b: list
    clamped: tuple = ()
    smooth: tuple = ()

    def __post_init__(self):
        if len(self.a) != len(self.b):
            raise ValueError(f"Ends: {len(self.a)} A ends and {len(self.b)} B ends")
        self.clamped = tuple((int(c[0]), str(c[1]), *(int(slot) for slot in c[2:3]))
                             for c in self.clamped)
        for k, end, *slot in self.clamped:
            if end not in ("a", "b") or not 0 <= k < len(self.a):
                raise ValueError(f"Ends clamped: ({k}, {end!r}) is not a (line index, 'a' "
                                 f"or 'b') of the {len(self.a)} lines")
            held = (self.a if end == "a" else self.b)[k]
            if held[0] not in ("fixed", "prescribed", "body"):
                raise ValueError(f"Ends clamped: end {end.upper()} of line {k} is on a "
                                 f"{held[0]!r}; only fixed, prescribed or body ends can be "
                                 "clamped")
            if slot and held[0] != "prescribed":
                raise ValueError(f"Ends clamped: end {end.upper()} of line {k} is on a "
                                 f"{held[0]!r}; only a prescribed end's tangent has a slot")
        self.smooth = tuple((int(k), int(j)) for k, j in self.smooth)
        joined = [end for pair in self.smooth for end in ((pair[0], "b"), (pair[1], "a"))]
        for k, j in self.smooth:
            if not (0 <= k < len(self.a) and 0 <= j < len(self.a)) or k == j:
                raise ValueError(f"Ends smooth: ({k}, {j}) is not a pair of two of the "
                                 f"{len(self.a)} lines")
            if self.b[k][0] != "point" or self.b[k] != self.a[j]:
                raise ValueError(f"Ends smooth: end B of line {k} ({self.b[k]}) and end A of "
                                 f"line {j} ({self.a[j]}) are not on the same free point")
        repeated = sorted({end for end in joined if joined.count(end) > 1})
        if repeated:
            k, end = repeated[0]
            raise ValueError(f"Ends smooth: end {end.upper()} of line {k} is in two joints")
        for end in self.a + self.b:
            if end[0] not in ("fixed", "prescribed", "point", "body"):
                raise ValueError(f"Ends: {end[0]!r} is not 'fixed', 'prescribed', 'point' "
                                 "or 'body'")

    @classmethod
    def anchor_fairlead(cls, nlines, fairleads):
        """Every line from a fixed anchor (end A) to a fairlead (end B) that is 'fixed',
        'prescribed' (slot = line index) or on 'body' 0."""
        if fairleads == "body":
            b = [("body", 0)] * nlines
        elif fairleads == "prescribed":
            b = [("prescribed", k) for k in range(nlines)]
        else:
            b = [("fixed",)] * nlines
        return cls([("fixed",)] * nlines, b)


def _compact(A, dense_below=20000):
    """A sparse matrix as a dense array when it has fewer than ``dense_below`` entries
    (a small product costs less so), as CSR else; None when it is zero."""
    A = sp.csr_matrix(A)
    A.eliminate_zeros()
    if not A.nnz:
        return None
    return A.toarray() if A.shape[0] * A.shape[1] < dense_below else A


class System:
    """The network's equations: lines (one :class:`~skmoor.lines.line.LineSet`) whose ends sit
    on fixed, prescribed or free points or on rigid bodies, reduced to one nonlinear system.

    Unknowns x = [line DOFs | 6 DOFs per body]: the line DOFs are the free line nodes and
    the free points (3 each, numbered where a line first reaches them, so that a chain of
    lines keeps a narrow band), and on a bending (Hermite) LineSet every node's 3 tangent
    DOFs but those of clamped ends (``Ends.clamped``; the two ends of a smooth joint,
    ``Ends.smooth``, share theirs). ends: an :class:`Ends`; or the anchor -> fairlead shorthand
    ``fairleads`` = 'body' (on ``body``), 'fixed' or 'prescribed' (by ``motion``).
    bodies: dynamic :class:`~skmoor.bodies.body.RigidBody` objects (``body`` alone: one).
    points: a :class:`PointMass` per free point. motion(t) -> (nslots, 3) displacements of
    the prescribed ends, m; with a ``motion.velocity(t)`` (m/s, same shape) the ends'
    velocities are that, else central differences of motion. body_load(t, q, qdot) ->
    6-vector (N, N m) on body 0, or a list with one (or None) per body (q, qdot with the
    angles from the global frame, also on a re-based body: the true pose; on an 'exact'
    body the load's moment is global). terms: :class:`~skmoor.fem.terms.Term` objects on the
    lines, the free points or the bodies (add more with :meth:`add_term`). sea: the water
    whose current drags the free points (None: still).
    """

    def __init__(self, lines, body=None, *, fairleads="body", motion=None,
                 body_load=None, terms=(), lumped_mass=True, ends=None,
                 bodies=None, points=(), sea=None):
        if ends is None:
            if fairleads not in ("body", "fixed", "prescribed"):
                raise ValueError(f"System fairleads: {fairleads!r} is not 'body', 'fixed' "
                                 "or 'prescribed'")
            if fairleads == "body" and body is None:
                raise ValueError("System body: fairleads='body' needs a RigidBody")
            bodies = [body] if fairleads == "body" else []
            ends = Ends.anchor_fairlead(len(lines.lines), fairleads)
        else:
            bodies = list(bodies if bodies is not None else ([body] if body else []))
        if len(ends.a) != len(lines.lines):
            raise ValueError(f"System ends: {len(ends.a)} entries for {len(lines.lines)} lines")
        self.lines, self.ends, self.bodies = lines, ends, bodies
        self.body = bodies[0] if bodies else None
        self.point_masses = list(points)
        self.motion, self.sea = motion, sea
        if any(e[0] == "prescribed" for e in ends.a + ends.b) and not callable(motion):
            raise ValueError("System motion: prescribed line ends need motion(t) -> (n, 3)")
        self.body_loads = (list(body_load) if isinstance(body_load, (list, tuple))
                           else [body_load] + [None] * (len(bodies) - 1) if bodies else [])
        self._terms = {"lines": [], "points": [], "bodies": [], "body pairs": []}
        if not lines.lines:
            self.kernel = NoLineKernel()
        elif lines.hermite:
            from ..lines.bending import HermiteKernel
            self.kernel = HermiteKernel(lines)
        else:
            self.kernel = CableKernel(lines)
        nloc = self.kernel.pattern.nloc
        self._block_shape = (self.kernel.pattern.nel, nloc, nloc)
        self._damped = lines.damped
        self._number_dofs()
        self._attachment_cache = (None, None, None)
        self._prescribed_cache = (None, None, None)
        self._acceleration_cache = (None, None)
        # s: the difference step of the prescribed ends' accelerations when the motion has
        # none (integrate sets its time step)
        self.acceleration_step = SECOND_DIFFERENCE
        self.K_bodies = [b.hydrostatic_stiffness(generalized=True) for b in bodies]
        self.F_bodies0 = [b.static_force() for b in bodies]
        self.K_body = self.K_bodies[0] if bodies else None
        self.weight = lines.weight_load()
        self.M_lines = lines.mass_matrix(lumped=lumped_mass).tocsr()
        # lumped line-end masses on the bodies (kg; None: consistent, not point masses)
        self._end_masses = (self.M_lines.diagonal()[self.body_end_dofs[:, 0]]
                            if lumped_mass and not lines.hermite else None)
        self._carrying = {}  # exact bodies with their line-end masses (_carrying_body)
        self._free_pattern = (None if self.nb else EmptyPattern(self.nf) if not lines.lines
                              else ElementPattern(lines, position=self._position))
        self._committing = []  # terms with a history (commit(t, u, v))
        for term in terms:
            self._join(term)
        self._assemble_mass()

    def _number_dofs(self):
        """Reduced numbering: line DOFs node by node (a free point where a line first
        reaches it), then 6 per body; where each held end goes."""
        lines, ends = self.lines, self.ends
        dofs = lines.nodal_dofs
        held = {}
        for k, (a, b) in enumerate(zip(ends.a, ends.b)):
            held[int(lines.anchor_nodes[k])] = a
            held[int(lines.fairlead_nodes[k])] = b
        slopes = lines.slope_dofs  # Hermite: each node's tangent DOFs, free unless clamped
        if ends.clamped and slopes is None:
            raise ValueError("System ends: clamped ends need bending lines (a LineType "
                             "with EI > 0); cables are pinned")
        clamped = {int((lines.anchor_nodes if end == "a" else lines.fairlead_nodes)[k]):
                   slot[0] if slot else None for k, end, *slot in ends.clamped}
        if ends.smooth and slopes is None:
            raise ValueError("System ends: smooth joints need bending lines (a LineType "
                             "with EI > 0); cables are hinged at their points")
        joint = {}  # node -> its smooth joint's number: one set of tangent columns each
        for number, (k, j) in enumerate(ends.smooth):
            joint[int(lines.fairlead_nodes[k])] = joint[int(lines.anchor_nodes[j])] = number
        joint_columns = {}
        npoints = len(self.point_masses)
        position = np.full(lines.ndofs, -1)
        self.point_columns = np.full((npoints, 3), -1)
        self.point_reference = np.zeros((npoints, 3))  # m
        columns = 0
        body_ends, prescribed_ends = [], []
        for node in range(len(dofs)):
            end = held.get(node)
            if end is None:
                position[dofs[node]] = np.arange(columns, columns + 3)
                columns += 3
            elif end[0] == "point":
                p = end[1]
                if not 0 <= p < npoints:
                    raise ValueError(f"System ends: free point {p} does not exist "
                                     f"({npoints} points given)")
                if self.point_columns[p, 0] < 0:
                    self.point_columns[p] = np.arange(columns, columns + 3)
                    self.point_reference[p] = lines.points[node]
                    columns += 3
                elif np.linalg.norm(lines.points[node] - self.point_reference[p]) > 1e-6:
                    raise ValueError(f"System ends: the lines at free point {p} start from "
                                     f"different positions ({self.point_reference[p]} and "
                                     f"{lines.points[node]}, m)")
                position[dofs[node]] = self.point_columns[p]
            elif end[0] == "body":
                if not 0 <= end[1] < len(self.bodies):
                    raise ValueError(f"System ends: body {end[1]} does not exist "
                                     f"({len(self.bodies)} dynamic bodies given)")
                body_ends.append((end[1], dofs[node],
                                  lines.points[node] - self.bodies[end[1]].reference_point,
                                  False))
                if node in clamped:  # the end tangent t0 turns with the body: R(q) t0
                    body_ends.append((end[1], slopes[node],
                                      lines.reference_dofs[slopes[node]], True))
            elif end[0] == "prescribed":
                prescribed_ends.append((int(end[1]), dofs[node]))
                if clamped.get(node) is not None:  # the end tangent moved by its slot
                    prescribed_ends.append((clamped[node], slopes[node]))
            if slopes is not None and node not in clamped:
                if joint.get(node) in joint_columns:
                    position[slopes[node]] = joint_columns[joint[node]]
                    continue
                position[slopes[node]] = np.arange(columns, columns + 3)
                if node in joint:
                    joint_columns[joint[node]] = position[slopes[node]]
                columns += 3
        unused = np.flatnonzero(self.point_columns[:, 0] < 0)
        if len(unused):
            raise ValueError(f"System points: free point {int(unused[0])} has no line")
        self._position = position
        self.free = np.flatnonzero(position >= 0)
        self._columns = position[self.free]
        self.nf = columns
        self._identity = len(self.free) == columns  # no two DOFs share a column
        self.nb = 6 * len(self.bodies)
        self.n = self.nf + self.nb
        self._blocks = [slice(self.nf + 6 * k, self.nf + 6 * k + 6)
                        for k in range(len(self.bodies))]
        body_ends.sort(key=lambda e: e[0])
        self._body_of_end = np.array([b for b, *_ in body_ends], int)
        self.body_end_dofs = np.array([d for _, d, _, _ in body_ends], int).reshape(-1, 3)
        self._body_flat = self.body_end_dofs.ravel()
        # clamped end tangents among the body ends: directions, R(q) t0 - t0 (no translation)
        self._directions = np.flatnonzero([turning for *_, turning in body_ends])
        rows = 3 * self._directions[:, None] + np.arange(3)
        columns = 6 * self._body_of_end[self._directions][:, None] + np.arange(3)
        self._direction_translation = (rows[:, :, None], columns[:, None, :])
        self._r_local = [np.array([r for b, _, r, _ in body_ends if b == k]).reshape(-1, 3)
                         for k in range(len(self.bodies))]
        self._body_rows = [np.flatnonzero(self._body_of_end == k) for k in range(len(self.bodies))]
        self.r_local = self._r_local[0] if self.bodies else None
        self._r_local0 = [r.copy() for r in self._r_local]
        self._frames = [None] * len(self.bodies)  # re-based frames (rebase), None: global
        self._end_offsets = np.zeros((len(body_ends), 3))
        self._prescribed_slots = np.array([slot for slot, _ in prescribed_ends], int)
        self._prescribed_dofs = np.array([d for _, d in prescribed_ends], int).reshape(-1, 3)
        self._prescribed_flat = self._prescribed_dofs.ravel()
        self._has_prescribed = len(self._prescribed_flat) > 0
        self._ndofs = lines.ndofs
        self.fairlead_dofs = dofs[lines.fairlead_nodes]  # (nlines, 3), end B
        self.anchor_dofs = dofs[lines.anchor_nodes]  # (nlines, 3), end A
        self._free_block = sp.csr_matrix((np.ones(len(self.free)), (self.free, self._columns)),
                                         shape=(lines.ndofs, self.n))
        self._selection = None if self._identity else sp.csr_matrix(
            (np.ones(len(self.free)), (self._columns, np.arange(len(self.free)))),
            shape=(self.nf, len(self.free)))

    @property
    def body_load(self):
        """The applied load on body 0: f(t, q, qdot) -> 6-vector (N, N m), or None."""
        return self.body_loads[0] if self.body_loads else None

    @body_load.setter
    def body_load(self, load):
        if not self.bodies:
            raise ValueError("System body_load: the system has no dynamic body")
        self.body_loads[0] = load

    @property
    def terms(self) -> tuple:
        """Every term of the system (lines, points, bodies, body pairs); add with
        :meth:`add_term`."""
        return tuple(self._terms["lines"] + self._terms["points"] + self._terms["bodies"]
                     + self._terms["body pairs"])

    @property
    def line_terms(self) -> tuple:
        return tuple(self._terms["lines"])

    @property
    def point_terms(self) -> tuple:
        return tuple(self._terms["points"])

    @property
    def body_terms(self) -> tuple:
        """The terms on one body and on pairs of bodies (joints)."""
        return tuple(self._terms["bodies"] + self._terms["body pairs"])

    def add_term(self, term):
        """Add a :class:`~skmoor.fem.terms.Term` (lines, a free point or a body) with its mass."""
        self._join(term)
        self._assemble_mass()

    def _join(self, term):
        if not isinstance(term, Term):
            raise ValueError(f"System term: {type(term).__name__} is not a skmoor.fem.terms.Term "
                             "(see skmoor.LineForm, PointLoad, BodyLoad)")
        kind = term.acts_on
        if kind not in self._terms:
            raise ValueError(f"System term {term!r}: acts_on {kind!r} is not 'lines', "
                             "'points', 'bodies' or 'body pairs'")
        if kind == "body pairs":
            pair = tuple(getattr(term, "bodies", ()))
            if not (len(pair) == 2 and pair[0] != pair[1] and all(
                    isinstance(k, (int, np.integer)) and 0 <= k < len(self.bodies) for k in pair)):
                raise ValueError(f"System term {type(term).__name__}: bodies {pair!r} is not "
                                 f"two different dynamic bodies ({len(self.bodies)} in the system)")
            exact = [k for k in pair if self.bodies[k].rotations == "exact"]
            if exact:
                raise ValueError(f"System term {type(term).__name__}: dynamic body {exact[0]} "
                                 "has rotations='exact'; joints are built for rotations='small'")
        count = {"points": len(self.point_masses), "bodies": len(self.bodies)}.get(kind)
        if count is not None:
            index = term.point if kind == "points" else term.body
            if not (isinstance(index, (int, np.integer)) and 0 <= index < count):
                what = "free point" if kind == "points" else "dynamic body"
                raise ValueError(f"System term {type(term).__name__}: {what} {index!r} does "
                                 f"not exist ({count} in the system)")
        term.bind(self)
        self._terms[kind].append(term)
        if callable(getattr(term, "commit", None)):
            self._committing.append(term)

    def _assemble_mass(self):
        """M_red = P0^T (M_lines + term masses) P0 + point and body masses, kg."""
        M_lines = self.M_lines
        for term in self._terms["lines"]:
            extra = term.mass_matrix()
            if extra is not None:
                M_lines = M_lines + extra
        M = self._reduce_constant(M_lines).tolil()
        for p, point in enumerate(self.point_masses):
            block = np.diag(np.full(3, point.mass + point.rho * point.volume * point.Ca))
            for term in self._terms["points"]:
                if term.point == p and term.mass_matrix() is not None:
                    block = block + term.mass_matrix()
            cols = self.point_columns[p]
            M[np.ix_(cols, cols)] = M[np.ix_(cols, cols)].toarray() + block
        # each body's added mass: constant in global axes (its own, its terms'), or turning
        # with it (terms with an inertia_load: rods); on exact bodies see inertia()
        self._added_masses, self._turning_masses, self._with_added = [], [], []
        for k, body in enumerate(self.bodies):
            added, turning = body.added_mass, []
            for term in self._terms["bodies"]:
                if term.body == k and term.mass_matrix() is not None:
                    if callable(getattr(term, "inertia_load", None)):
                        turning.append(term)
                    else:
                        added = added + term.mass_matrix()
            self._added_masses.append(added)
            self._turning_masses.append(turning)
            self._with_added.append(bool(added.any() or turning))
            constant = added + sum(term.mass_matrix() for term in turning)
            block = slice(self.nf + 6 * k, self.nf + 6 * k + 6)
            M[block, block] = M[block, block].toarray() + body.mass_matrix() + constant
        self.M = M.tocsr()
        self._held_masses(M_lines)

    def _held_masses(self, M_lines):
        """The mass the held (fixed and prescribed) ends share with the rest, kg:
        ``_M_driven`` = P0^T M[:, p], whose product with the prescribed ends' accelerations
        joins the free DOFs' balance (M_fp a_p), and ``_end_mass`` = (M[e] P0, M[e, p]) of
        the held ends' rows e, their own inertia in the reactions (M_ef a_f + M_ep a_p), and
        ``_end_slope_mass`` the same of their tangent rows (bending lines: the inertia in
        the clamp moments); each None when zero (lumped P1 lines: no M_fp; fixed ends
        only: no acceleration)."""
        M_lines = sp.csr_matrix(M_lines)
        P0 = self.P(np.zeros(self.n))
        driven = self._prescribed_flat
        self._M_driven = None
        if self._has_prescribed:
            coupling = (P0.T @ M_lines[:, driven]).tocsr()
            coupling.eliminate_zeros()
            self._M_driven = coupling if coupling.nnz else None
        rows = [(side, k) for side, ends in enumerate((self.ends.b, self.ends.a))
                for k, end in enumerate(ends) if end[0] in ("fixed", "prescribed")]
        self._end_mass = self._end_slope_mass = None
        if not rows:
            return

        def shares(dofs):  # (rows, M[e] P0, M[e, p]) of the rows e, or None when zero
            on_free, on_driven = (_compact(A) for A in (M_lines[dofs] @ P0,
                                                        M_lines[dofs][:, driven]))
            if on_free is None and on_driven is None:
                return None
            return np.array(rows, int), on_free, on_driven

        self._end_mass = shares(np.array([(self.fairlead_dofs, self.anchor_dofs)[side][k]
                                          for side, k in rows]).ravel())
        slopes = self.lines.slope_dofs
        if slopes is not None:
            nodes = [(self.lines.fairlead_nodes, self.lines.anchor_nodes)[side][k]
                     for side, k in rows]
            self._end_slope_mass = shares(slopes[nodes].ravel())

    def commit(self, t, x, v):
        """An accepted time level (t, s; x, v reduced): passed to the terms that keep a
        history, each on its own DOFs (see :mod:`skmoor.fem.terms`)."""
        for term in self._committing:
            if term.acts_on == "bodies":
                block = self._body_block(term.body)
                term.commit(t, x[block], v[block])
            elif term.acts_on == "points":
                columns = self.point_columns[term.point]
                term.commit(t, x[columns], v[columns])
            else:
                term.commit(t, self.full_displacement(x, t), self.full_velocity(x, v, t))

    # --- re-based frames of exact bodies (no gimbal lock), see skmoor.bodies.large_rotations
    def rebase(self, x, v):
        """Re-base the angles of every 'exact' body whose pitch passed ``REBASE_PITCH``:
        its angles are then counted from its present attitude (R = Rz Ry Rx(q) @ frame,
        the new q angles 0, their rates the angular velocity). Returns the new (x, v), or
        None when no body was re-based. A body with a term that reads its angles off q
        (not ``frame_aware``: a user's BodyLoad) is not re-based: it stops at the gimbal
        lock with an error."""
        turned = None
        for k, body in enumerate(self.bodies):
            block = self._body_block(k)
            q = x[block]
            if (body.rotations != "exact" or abs(q[4]) < REBASE_PITCH
                    or any(term.body == k and not term.frame_aware
                           for term in self._terms["bodies"])
                    or any(k in term.bodies for term in self._terms["body pairs"])):
                continue
            if turned is None:
                turned = (x.copy(), v.copy())
                self._attachment_cache = (None, None, None)
            x1, v1 = turned
            E = rate_matrix(q[3:])[0]
            v1[block.start + 3: block.stop] = E @ v[block][3:]  # omega (global)
            x1[block.start + 3: block.stop] = 0.0
            self._frames[k] = body.rotation(q, self._frames[k])
            rows = self._body_rows[k]
            if len(rows):  # line ends on the body: R0 r0 - r0 of the turn stays constant
                turn = self._frames[k]
                self._r_local[k] = self._r_local0[k] @ turn.T
                self._end_offsets[rows] = self._r_local[k] - self._r_local0[k]
        return turned

    def reset_frames(self):
        """Count every body's angles from the global frame again (as built)."""
        self._frames = [None] * len(self.bodies)
        self._r_local = [r.copy() for r in self._r_local0]
        self._end_offsets = np.zeros((len(self._body_of_end), 3))
        self._attachment_cache = (None, None, None)

    def body_rotation(self, x, body=0) -> np.ndarray:
        """The attitude R (3, 3) of body ``body`` in the reduced state x (its angles
        counted from its re-based frame, :meth:`rebase`)."""
        return self.bodies[body].rotation(self.q(x, body), self._frames[body])

    def body_motion(self, q, qdot=None, body=0) -> BodyMotion:
        """The :class:`~skmoor.bodies.body_motion.BodyMotion` of body ``body`` at its DOFs q and
        rates qdot: what its terms read of its attitude (re-based frame included)."""
        return BodyMotion(q, qdot, frame=self._frames[body],
                          exact=self.bodies[body].rotations == "exact")

    def _global_rates(self, q, qdot, k):
        """(q, qdot) of re-based body k with its angles (and their rates) counted from the
        global frame: what its ``body_load`` sees (at the gimbal lock the rates are the
        least-squares ones)."""
        angles = zyx_angles(self.bodies[k].rotation(q, self._frames[k]))
        omega = rate_matrix(q[3:])[0] @ qdot[3:]
        rates = np.linalg.lstsq(rate_matrix(angles)[0], omega, rcond=None)[0]
        return np.r_[q[:3], angles], np.r_[qdot[:3], rates]

    def body_pose(self, x) -> np.ndarray:
        """(nbodies, 6) displacement and angles Rz Ry Rx from the global frame of every
        body in the reduced state x (m, rad): x's own body DOFs unless re-based."""
        out = x[self.nf:].reshape(-1, 6).copy()
        for k, frame in enumerate(self._frames):
            if frame is not None:
                out[k, 3:] = zyx_angles(self.body_rotation(x, k))
        return out

    # --- maps between reduced and full cable DOFs
    def q(self, x, body=0):
        """DOFs of body ``body`` in a reduced vector (zeros without bodies), m / rad."""
        if not self.nb:
            return np.zeros(6)
        return x[self.nf + 6 * body: self.nf + 6 * body + 6]

    def point_displacement(self, x):
        """(npoints, 3) free-point displacements in a reduced vector, m."""
        return x[self.point_columns] if len(self.point_columns) else np.zeros((0, 3))

    def full_displacement(self, x, t=0.0):
        """(ndofs,) cable displacement for reduced state x at time t, m."""
        return self._displacement(x, self._attachment(x)[0] if self.nb else None, t)

    def _displacement(self, x, body_ends, t):
        """(ndofs,) cable displacement from x, the (n, 3) displacements of the body ends
        and the prescribed ends at time t."""
        u = np.zeros(self._ndofs)
        u[self.free] = x[: self.nf] if self._identity else x[self._columns]
        if body_ends is not None:
            u[self._body_flat] = body_ends.ravel()
        if self._has_prescribed:
            u[self._prescribed_flat] = self._prescribed(t)[0].ravel()
        return u

    def _attachment(self, x):
        """Body-end displacements (n, 3) and their Jacobian (3 n, 6 nbodies) at the body
        DOFs of x, computed once per state."""
        q = x[self.nf:]
        key = q.tobytes()
        if self._attachment_cache[0] != key:
            if not math.isfinite(q.sum()):
                raise ValueError(f"System: body DOFs are not finite: {q}")
            if len(self.bodies) == 1:
                state = rigid.attachment_state(q, self._r_local[0])
            else:
                disp = np.zeros((len(self._body_of_end), 3))
                J = np.zeros((3 * len(self._body_of_end), self.nb))
                for k, rows in enumerate(self._body_rows):
                    if len(rows):
                        d, Jk = rigid.attachment_state(q[6 * k: 6 * k + 6], self._r_local[k])
                        disp[rows] = d
                        J[3 * rows[0]: 3 * rows[-1] + 3, 6 * k: 6 * k + 6] = Jk
                state = (disp, J)
            if len(self._directions):  # clamped tangents: the rotation's part only
                disp, J = state
                disp[self._directions] -= q.reshape(-1, 6)[self._body_of_end[self._directions], :3]
                J[self._direction_translation] = 0.0
            if any(frame is not None for frame in self._frames):
                state = (state[0] + self._end_offsets, state[1])
            self._attachment_cache = (key, *state)
        return self._attachment_cache[1], self._attachment_cache[2]

    def fairlead_displacement(self, x, t=0.0):
        """(nlines, 3) displacements of the lines' B ends, m."""
        return self.full_displacement(x, t)[self.fairlead_dofs]

    def _prescribed(self, t, dt=1e-6):
        """Displacements (m) and velocities (``motion.velocity``, or central differences
        over dt, m/s) of the prescribed ends at time t, (n, 3) each; the last time's are
        kept (Newton revisits it)."""
        if self._prescribed_cache[0] != (t, dt):
            slots = self._prescribed_slots

            def at(f, time):
                return np.asarray(f(time), float).reshape(-1, 3)[slots]
            velocity = getattr(self.motion, "velocity", None)
            rate = (at(velocity, t) if velocity is not None else
                    (at(self.motion, t + dt) - at(self.motion, t - dt)) / (2 * dt))
            self._prescribed_cache = ((t, dt), at(self.motion, t), rate)
        return self._prescribed_cache[1:]

    def prescribed_acceleration(self, t):
        """(n, 3) accelerations (m/s2) of the prescribed ends at t (s): the motion's
        ``acceleration``, else differences of its velocity or position over
        ``acceleration_step`` (:func:`~skmoor.bodies.motion.acceleration_of`); the last time's is
        kept."""
        key = (t, self.acceleration_step)
        if self._acceleration_cache[0] != key:
            rate = acceleration_of(self.motion, t, self.acceleration_step)
            rate = np.asarray(rate, float).reshape(-1, 3)
            self._acceleration_cache = (key, rate[self._prescribed_slots])
        return self._acceleration_cache[1]

    def driven_inertia(self, t):
        """M_fp a_p(t) (N, reduced): the inertia the prescribed ends' accelerations put on
        the free DOFs through the mass they share (consistent mass, bending lines), a
        load of the dynamic balance; None when they share none (lumped P1 lines)."""
        if self._M_driven is None:
            return None
        return self._M_driven @ self.prescribed_acceleration(t).ravel()

    def end_inertia(self, a, t=0.0):
        """(nlines, 3) inertia (N) of the B and of the A ends held fixed or prescribed,
        M_ef a_f + M_ep a_p (a: reduced accelerations, m/s2, at t, s): the end nodes'
        own mass share and the one they share with their neighbours; zeros at ends on
        free points and bodies (the end's mass moves with them). None when zero."""
        if self._end_mass is None:
            return None
        driven = self.prescribed_acceleration(t).ravel() if self._has_prescribed else None
        out = self.end_inertias(np.asarray(a)[None], None if driven is None else driven[None])
        return out[0, 0], out[0, 1]

    def end_inertias(self, a, driven, slopes=False):
        """(m, 2, nlines, 3) :meth:`end_inertia` (N; B ends, then A ends) at m states: a
        (m, n) reduced accelerations, driven (m, 3 n_prescribed) the prescribed ends'
        (m/s2; None without prescribed ends); with ``slopes`` that of the ends' tangent
        rows instead (N m per unit of tangent, bending lines)."""
        rows, on_free, on_driven = self._end_slope_mass if slopes else self._end_mass
        values = np.zeros((len(a), 3 * len(rows)))
        if on_free is not None:
            values += (on_free @ a.T).T
        if driven is not None and on_driven is not None:
            values += (on_driven @ driven.T).T
        out = np.zeros((len(a), 2, len(self.lines.lines), 3))
        out[:, rows[:, 0], rows[:, 1]] = values.reshape(len(a), -1, 3)
        return out

    def prescribed_at(self, times, accelerations=False):
        """Displacements (m) and velocities (m/s) of the prescribed ends at each of the m
        ``times``, (m, 3 n) each, and with ``accelerations`` their accelerations (m/s2):
        one call of ``motion.at_times`` when the motion has it (a
        :class:`~skmoor.bodies.motion.Motion`), else :meth:`_prescribed` time by time."""
        at_times = getattr(self.motion, "at_times", None)
        m = len(times)
        if at_times is None:
            pairs = [self._prescribed(t) for t in times]
            out = (np.array([d.ravel() for d, _ in pairs]).reshape(m, -1),
                   np.array([r.ravel() for _, r in pairs]).reshape(m, -1))
            if accelerations:
                out += (np.array([self.prescribed_acceleration(t).ravel() for t in times]
                                 ).reshape(m, -1),)
            return out
        values = at_times(times, accelerations=accelerations, step=self.acceleration_step)
        return tuple(value[:, self._prescribed_slots].reshape(m, -1) for value in values)

    def full_state(self, x, v, t=0.0):
        """(ndofs,) cable displacement (m) and velocity (m/s) of the reduced state (x, v)
        at time t, the bodies' kinematics computed once."""
        ends, J = self._attachment(x) if self.nb else (None, None)
        return self._displacement(x, ends, t), self._velocity(x, v, t, J)

    def full_velocity(self, x, v, t=0.0, dt=1e-6):
        """(ndofs,) cable velocity, m/s."""
        return self._velocity(x, v, t, self._jacobian(x), dt)

    def _velocity(self, x, v, t, J, dt=1e-6):
        ud = self._expand(v, J)
        if self._has_prescribed:
            ud[self._prescribed_flat] = self._prescribed(t, dt)[1].ravel()
        return ud

    def _jacobian(self, x):
        """(3 n, 6 nbodies) Jacobian of the body ends, or None without bodies."""
        if not self.nb:
            return None
        return self._attachment(x)[1]

    def _expand(self, y, J):
        """P y for a reduced vector y, without forming P."""
        out = np.zeros(self._ndofs)
        out[self.free] = y[: self.nf] if self._identity else y[self._columns]
        if J is not None:
            out[self._body_flat] = J @ y[self.nf:]
        return out

    def _reduce(self, R_full, J):
        """P^T R_full, without forming P."""
        out = np.empty(self.n)
        if self._identity:
            out[: self.nf] = R_full[self.free]
        else:
            out[: self.nf] = np.bincount(self._columns, R_full[self.free], minlength=self.nf)
        if J is not None:
            out[self.nf:] = J.T @ R_full[self._body_flat]
        return out

    def _select(self, A):
        """S A S^T: rows and columns of free DOFs summed into their reduced columns."""
        if self._identity:
            return A
        return (self._selection @ (self._selection @ A).T).T

    def _reduce_dense(self, A, J):
        """P^T A P for a dense (ndofs, ndofs) A, without forming P."""
        free, ends = self.free, self._body_flat
        out = np.empty((self.n, self.n))
        out[: self.nf, : self.nf] = self._select(A[np.ix_(free, free)])
        if J is not None:
            S = (lambda B: B) if self._identity else (lambda B: self._selection @ B)
            out[: self.nf, self.nf:] = S(A[np.ix_(free, ends)] @ J)
            out[self.nf:, : self.nf] = S((J.T @ A[np.ix_(ends, free)]).T).T
            out[self.nf:, self.nf:] = J.T @ A[np.ix_(ends, ends)] @ J
        return out

    def _reduce_sparse(self, A, x):
        """P^T A P for a sparse A (a row and column selection without bodies)."""
        if not self.nb and self._identity:
            return A[self.free][:, self.free]
        P = self.P(x)
        return (P.T @ A @ P).tocsr()

    def P(self, x):
        """du/dx (ndofs, n): the free DOFs' columns, the body ends' Jacobians."""
        if not self.nb:
            return self._free_block
        J = self._jacobian(x)
        rows = np.repeat(self._body_flat, self.nb)
        cols = np.tile(self.nf + np.arange(self.nb), len(self._body_flat))
        body = sp.csr_matrix((J.ravel(), (rows, cols)), shape=self._free_block.shape)
        return self._free_block + body

    def _reduce_constant(self, A):
        P0 = self.P(np.zeros(self.n))
        return (P0.T @ A @ P0).tocsr()

    def _body_block(self, k):
        return self._blocks[k]

    @property
    def _needs_velocity(self):
        return bool(self._terms["lines"]) or self._damped

    # --- the nonlinear system
    def line_residual(self, u, ud, t=0.0, load_factor=1.0, tangent=True, layout="sparse"):
        """Full cable residual internal - external (N) and its u- and v-derivatives in
        ``layout`` ('sparse', 'dense' or 'band')."""
        R, Ke, Ce = self._line_blocks(u, ud, t, load_factor, tangent)
        if not tangent:
            return R, None, None
        return R, *self._sum(self.kernel.pattern, Ke, Ce, layout)

    def _line_blocks(self, u, ud, t, load_factor, tangent):
        """The cable residual (N) with the element blocks (nel, 6, 6) of its derivatives
        d/du and d/dv (None without ``tangent``): the cable kernel and every line term."""
        R = -load_factor * self.weight
        Ke = Ce = None
        if tangent:
            Ke, Ce = np.zeros(self._block_shape), np.zeros(self._block_shape)
        self.kernel.add_to(u, ud if self._damped else None, R, Ke, Ce)
        for term in self._terms["lines"]:
            term.add_to(u, ud, t, R, Ke, Ce)
        return R, Ke, Ce

    def _sum(self, pattern, Ke, Ce, layout):
        """K, Kv in ``layout``: the element blocks assembled on ``pattern``."""
        K = pattern.assemble(Ke, layout)
        Kv = pattern.assemble(Ce, layout) if self._needs_velocity else None
        return K, Kv

    @property
    def bandwidth(self):
        """Half-bandwidth of the reduced matrices without bodies (None with one: its
        rows and columns couple all its line ends)."""
        return None if self.nb else self._free_pattern.bandwidth

    def _points(self, x, v, t, load_factor, R, tangent):
        """Adds the free points' loads into R (net buoyancy (rho V - m) g, drag on the
        velocity relative to the current, and their terms); returns their derivative
        blocks d/dx, d/dv (npoints, 3, 3) or None without ``tangent``."""
        npoints = len(self.point_masses)
        K = np.zeros((npoints, 3, 3)) if tangent else None
        C = np.zeros((npoints, 3, 3)) if tangent else None
        for p, point in enumerate(self.point_masses):
            cols = self.point_columns[p]
            R[cols[2]] -= load_factor * (point.rho * point.volume - point.mass) * point.g
            if point.CdA:
                relative = -v[cols]
                if self.sea is not None and not self.sea.still:
                    relative = relative + self.sea.velocity(self.point_reference[p] + x[cols], t)
                speed = np.linalg.norm(relative)
                k = 0.5 * point.rho * point.CdA
                R[cols] -= k * speed * relative
                if tangent and speed > 0:  # the residual's d/dv of -k |w| w, w = U - v
                    C[p] += k * (speed * np.eye(3) + np.outer(relative, relative) / speed)
        for term in self._terms["points"]:
            cols = self.point_columns[term.point]
            Rp = np.zeros(3)
            term.add_to(x[cols], v[cols], t, Rp, None if K is None else K[term.point],
                        None if C is None else C[term.point])
            R[cols] += Rp
        return K, C

    def residual(self, x, v=None, t=0.0, load_factor=1.0, tangent=True, layout="sparse"):
        """Reduced residual R(x, v, t) (no inertia, no Rayleigh damping) and its
        derivatives K = dR/dx and Kv = dR/dv (None when zero) in ``layout``: 'sparse'
        (CSR), 'dense' (arrays, faster below a few hundred unknowns) or, without bodies,
        'band' (:class:`~skmoor.numerics.banded.Band`, half-bandwidth :attr:`bandwidth`)."""
        if layout not in LAYOUTS:
            raise ValueError(f"System.residual layout: {layout!r} is not one of {LAYOUTS}")
        if layout == "band" and self.nb:
            raise ValueError("System.residual layout: 'band' needs a System without bodies")
        v = np.zeros(self.n) if v is None else v
        if self.nb:
            ends, J = self._attachment(x)
        else:
            ends, J = None, None
        u = self._displacement(x, ends, t)
        ud = self._velocity(x, v, t, J) if self._needs_velocity else None
        if self.nb or not tangent:
            R_full, K_full, Kv_full = self.line_residual(u, ud, t, load_factor, tangent, layout)
        else:  # no body: the element blocks go straight into the reduced matrices
            R_full, Ke, Ce = self._line_blocks(u, ud, t, load_factor, True)
        R = self._reduce(R_full, J)
        point_K = point_C = None
        if self.point_masses:
            point_K, point_C = self._points(x, v, t, load_factor, R, tangent)
        body_K, body_Kv = [], []
        for k, body in enumerate(self.bodies):
            block = self._body_block(k)
            q, qdot = x[block], v[block]
            if body.rotations == "exact":  # at the pose; (1 - load_factor) F0 as K q - lf F0
                R[block] -= (body.restoring_load(q, self._frames[k])
                             - (1 - load_factor) * self.F_bodies0[k])
            else:
                R[block] += self.K_bodies[k] @ q - load_factor * self.F_bodies0[k]
            R[block] += body.linear_damping @ qdot
            if self.body_loads[k] is not None:
                load = self.body_loads[k](t, q, qdot) if self._frames[k] is None else \
                    self.body_loads[k](t, *self._global_rates(q, qdot, k))
                if body.rotations == "exact":  # force and moment (global) -> [F, E^T M]
                    load = generalized_load(q[3:], load[:3], load[3:])
                R[block] -= load
            Kk, Ck = (np.zeros((6, 6)), np.zeros((6, 6))) if tangent else (None, None)
            Rk = np.zeros(6)
            for term in self._terms["bodies"]:
                if term.body == k:
                    term.add_to(q, qdot, t, Rk, Kk, Ck)
            R[block] += Rk
            body_K.append(Kk)
            body_Kv.append(Ck)
        pair_K, pair_Kv = self._body_pairs(x, v, t, R, tangent)
        if not tangent:
            return R, None, None
        dense = layout == "dense"
        if not self.nb:
            K, Kv = self._sum(self._free_pattern, Ke, Ce, layout)
            return (R, *self._add_point_blocks(K, Kv, point_K, point_C, layout))
        if dense:
            K = self._reduce_dense(K_full, J)
            Kv = None if Kv_full is None else self._reduce_dense(Kv_full, J)
        else:
            K, Kv = (None if A is None else self._reduce_sparse(A, x) for A in (K_full, Kv_full))
        K_bodies = np.zeros((self.nb, self.nb))
        D_bodies = np.zeros((self.nb, self.nb))
        end_forces = R_full[self.body_end_dofs]
        for k, body in enumerate(self.bodies):
            b = slice(6 * k, 6 * k + 6)
            rows = self._body_rows[k]
            H = (rigid.attachment_hessian(x[self._body_block(k)], self._r_local[k],
                                          end_forces[rows]) if len(rows) else 0.0)
            restoring = (body.restoring_stiffness(x[self._body_block(k)], self._frames[k])
                         if body.rotations == "exact" else self.K_bodies[k])
            K_bodies[b, b] = H + restoring + body_K[k]
            D_bodies[b, b] = body.linear_damping + body_Kv[k]
        if pair_K is not None:
            K_bodies += pair_K
            D_bodies += pair_Kv
        slope = (self._velocity_slope(Kv_full, x, v, J)
                 if Kv_full is not None and np.any(v[self.nf:]) else None)
        damped = np.any(D_bodies)
        if dense:  # K and Kv are fresh arrays: add in place
            K[self.nf:, self.nf:] += K_bodies
            if slope is not None:
                K[:, self.nf:] += slope
            if damped:
                if Kv is None:
                    Kv = np.zeros((self.n, self.n))
                Kv[self.nf:, self.nf:] += D_bodies
        else:
            K = K + self._embed_bodies(K_bodies)
            if slope is not None:
                rows, cols = np.nonzero(slope)
                K = K + sp.csr_matrix((slope[rows, cols], (rows, cols + self.nf)),
                                      shape=(self.n, self.n))
            if damped:
                D = self._embed_bodies(D_bodies)
                Kv = D if Kv is None else Kv + D
        return (R, *self._add_point_blocks(K, Kv, point_K, point_C, layout))

    def _body_pairs(self, x, v, t, R, tangent):
        """Adds the terms on pairs of bodies (joints) into R; returns their derivative
        blocks d/dx, d/dv on the bodies' DOFs (6 nbodies, 6 nbodies), or None (none
        of them, or no ``tangent``)."""
        terms = self._terms["body pairs"]
        if not terms:
            return None, None
        K = np.zeros((self.nb, self.nb)) if tangent else None
        C = np.zeros((self.nb, self.nb)) if tangent else None
        for term in terms:
            rows = np.r_[[np.arange(6 * k, 6 * k + 6) for k in term.bodies]].ravel()
            Rp = np.zeros(12)
            Kp, Cp = (np.zeros((12, 12)), np.zeros((12, 12))) if tangent else (None, None)
            term.add_to(x[self.nf + rows], v[self.nf + rows], t, Rp, Kp, Cp)
            R[self.nf + rows] += Rp
            if tangent:
                K[np.ix_(rows, rows)] += Kp
                C[np.ix_(rows, rows)] += Cp
        return K, C

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
            block = self._body_block(k)
            q, qdot, qddot = x[block], v[block], a[block]
            rigid, M0 = self._carrying_body(k)
            frame = self._frames[k]
            with_added = self._with_added[k]
            if previous is None:
                G[block] = rigid.inertia_load(q, qdot, qddot, frame) - M0 @ qddot
            else:
                x0, v0, a0, G0, h, gamma = previous
                load0 = G0[block] + M0 @ a0[block]  # the rigid body's inertia at the start
                if with_added:  # G0 less its added-mass part
                    load0 = load0 - self._added_inertia(k, x0[block], v0[block], a0[block])[0]
                start = (x0[block], v0[block], load0, h, gamma)
                G[block] = rigid.step_inertia_load(q, qdot, *start, frame) - M0 @ qddot
            if with_added:
                added, slopes = self._added_inertia(k, q, qdot, qddot, tangent)
                G[block] += added
            if tangent:
                if previous is None:
                    d_acc, d_rate, d_pose = rigid.inertia_tangents(q, qdot, qddot, frame)
                else:
                    d_acc = np.zeros((6, 6))
                    d_rate, d_pose = rigid.step_inertia_tangents(q, qdot, *start, frame)
                if with_added:
                    d_acc, d_rate, d_pose = (d_acc + slopes[0], d_rate + slopes[1],
                                             d_pose + slopes[2])
                b = slice(6 * k, 6 * k + 6)
                for out, value in zip(blocks, (d_acc - M0, d_rate, d_pose)):
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
        return (G, *(self._embed_bodies(A) for A in blocks))

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

    def _carrying_body(self, k):
        """(body k with the lumped masses of its line ends as point masses fixed on it, its
        mass matrix M0 at q = 0): the rigid body whose exact inertia :meth:`inertia`
        takes; M0 is the body's plus the ends' reduction P0^T M P0, which M holds."""
        if k not in self._carrying:
            body, rows = self.bodies[k], self._body_rows[k]
            if self._end_masses is None or not len(rows) or not self._end_masses[rows].any():
                carrier = body
            else:
                masses = self._end_masses[rows]
                points = body.reference_point + self._r_local0[k]
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

    def _velocity_slope(self, Kv_full, x, v, J):
        """(n, 6 nbodies) P^T Kv_full d(udot)/dq: the body ends' velocity J(q) v changes
        with q (the body columns of K)."""
        slopes = np.zeros((len(self._body_flat), self.nb))
        for k, rows in enumerate(self._body_rows):
            if len(rows):
                block = self._body_block(k)
                slopes[3 * rows[0]: 3 * rows[-1] + 3, 6 * k: 6 * k + 6] = \
                    rigid.attachment_velocity_slope(x[block], self._r_local[k], v[block])
        B = Kv_full[:, self._body_flat] @ slopes  # (ndofs, nb)
        B = B.toarray() if hasattr(B, "toarray") else np.asarray(B)
        out = np.empty((self.n, self.nb))
        out[: self.nf] = B[self.free] if self._identity else self._selection @ B[self.free]
        out[self.nf:] = J.T @ B[self._body_flat]
        return out

    def _embed_bodies(self, A):
        """The (6 nbodies)^2 body block in a sparse (n, n) matrix (nothing of size n^2)."""
        rows, cols = np.nonzero(A)
        return sp.csr_matrix((A[rows, cols], (rows + self.nf, cols + self.nf)),
                             shape=(self.n, self.n))

    def _add_point_blocks(self, K, Kv, point_K, point_C, layout):
        """K and Kv plus the free points' (npoints, 3, 3) derivative blocks (None: none)."""
        out = []
        for A, blocks in ((K, point_K), (Kv, point_C)):
            if blocks is not None and np.any(blocks):
                cols = self.point_columns
                rows = np.repeat(cols, 3, axis=1).ravel()
                B = sp.csr_matrix((blocks.ravel(), (rows, np.tile(cols, (1, 3)).ravel())),
                                  shape=(self.n, self.n))
                B = as_layout(B, layout, self.bandwidth)
                A = B if A is None else A + B
            out.append(A)
        return out

    def reactions(self, x, v=None, t=0.0, a=None):
        """(nlines, 3) forces the lines exert on their B ends, and (nlines, 3) on their
        A ends, N: internal force minus loads at the end node, and with the reduced
        accelerations ``a`` (m/s2) less the held ends' inertia (:meth:`end_inertia`);
        without a, quasi-static."""
        v = np.zeros(self.n) if v is None else v
        u = self.full_displacement(x, t)
        return self.end_forces(u, self.full_velocity(x, v, t) if self._needs_velocity
                               else None, t, a)

    def end_forces(self, u, ud, t=0.0, a=None):
        """:meth:`reactions` from the full cable displacement u (m) and velocity ud (m/s,
        None: at rest) at time t (s), and the reduced accelerations a (m/s2, None:
        quasi-static)."""
        R_full, _, _ = self.line_residual(u, ud if self._needs_velocity else None, t,
                                          tangent=False)
        return self.less_inertia((-R_full[self.fairlead_dofs], -R_full[self.anchor_dofs]),
                                 a, t)

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
        R_full, _, _ = self.line_residual(u, ud if self._needs_velocity else None, t,
                                          tangent=False)
        inertia = np.zeros((2, len(self.lines.lines), 3))
        if a is not None and self._end_slope_mass is not None:
            driven = self.prescribed_acceleration(t).ravel() if self._has_prescribed else None
            inertia = self.end_inertias(np.asarray(a)[None], None if driven is None
                                        else driven[None], slopes=True)[0]
        r = self.lines.reference_dofs + u
        out = []
        for side, nodes in enumerate((self.lines.fairlead_nodes, self.lines.anchor_nodes)):
            dofs = slopes[nodes]
            out.append(np.cross(r[dofs], -R_full[dofs] - inertia[side]))
        return tuple(out)
