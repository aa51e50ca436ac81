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

The parts: DOF numbering and reduction (:mod:`skmoor.coupling.dofs`), body frames
(:mod:`skmoor.coupling.frames`), exact-body inertia (:mod:`skmoor.coupling.inertia`), end
forces (:mod:`skmoor.coupling.reactions`) and prescribed ends (:mod:`skmoor.coupling.prescribed`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..bodies import body as rigid
from ..bodies.restoring import AppliedLoad, BodyRestoring
from ..fem.patterns import ElementPattern
from ..fem.terms import Term
from ..lines.cable import CableTerm
from ..lines.creep import CreepTerm, has_creep
from ..lines.user_law import law_terms
from ..numerics.banded import LAYOUTS, as_layout
from ..sea.hydro import PointDrag
from ..sea.seabed import land_on_bed
from .dofs import DofMap
from .frames import BodyFrames
from .inertia import ExactBodyInertia
from .no_lines import EmptyPattern, NoLineKernel
from .prescribed import PrescribedEnds
from .reactions import EndReactions


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


TERM_KINDS = ("lines", "points", "bodies", "body pairs")  # what a term acts on


def _check_target(term, n_points, bodies):
    """Refuse a term that is not a :class:`~skmoor.fem.terms.Term` or acts on what the
    system does not have (its ``acts_on``, free point, dynamic body or pair of them)."""
    if not isinstance(term, Term):
        raise ValueError(f"System term: {type(term).__name__} is not a skmoor.fem.terms.Term "
                         "(see skmoor.LineForm, PointLoad, BodyLoad)")
    kind = term.acts_on
    if kind not in TERM_KINDS:
        raise ValueError(f"System term {term!r}: acts_on {kind!r} is not 'lines', "
                         "'points', 'bodies' or 'body pairs'")
    if kind == "body pairs":
        pair = tuple(getattr(term, "bodies", ()))
        if not (len(pair) == 2 and pair[0] != pair[1] and all(
                isinstance(k, (int, np.integer)) and 0 <= k < len(bodies) for k in pair)):
            raise ValueError(f"System term {type(term).__name__}: bodies {pair!r} is not "
                             f"two different dynamic bodies ({len(bodies)} in the system)")
        exact = [k for k in pair if bodies[k].rotations == "exact"]
        if exact:
            raise ValueError(f"System term {type(term).__name__}: dynamic body {exact[0]} "
                             "has rotations='exact'; joints are built for rotations='small'")
    count = {"points": n_points, "bodies": len(bodies)}.get(kind)
    if count is not None:
        index = term.point if kind == "points" else term.body
        if not (isinstance(index, (int, np.integer)) and 0 <= index < count):
            what = "free point" if kind == "points" else "dynamic body"
            raise ValueError(f"System term {type(term).__name__}: {what} {index!r} does "
                             f"not exist ({count} in the system)")


class System(BodyFrames, ExactBodyInertia, EndReactions, PrescribedEnds):
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

    Its parts: ``dofs`` (a :class:`~skmoor.coupling.dofs.DofMap`: the numbering and the
    reduction), the body frames (:class:`~skmoor.coupling.frames.BodyFrames`), the exact
    bodies' inertia (:class:`~skmoor.coupling.inertia.ExactBodyInertia`), the end forces
    (:class:`~skmoor.coupling.reactions.EndReactions`) and the prescribed ends' motion
    (:class:`~skmoor.coupling.prescribed.PrescribedEnds`).
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
        self._terms = {kind: [] for kind in TERM_KINDS}
        self.cable = CableTerm(lines) if lines.lines else None
        self.kernel = self.cable.kernel if lines.lines else NoLineKernel()
        nloc = self.kernel.pattern.nloc
        self._block_shape = (self.kernel.pattern.nel, nloc, nloc)
        self.damped = lines.damped
        self.dofs = dofs = DofMap(lines, ends, bodies, len(self.point_masses))
        self.free, self.nf, self.nb, self.n = dofs.free, dofs.nf, dofs.nb, dofs.n
        self.point_columns, self.point_reference = dofs.point_columns, dofs.point_reference
        self.body_end_dofs = dofs.body_end_dofs
        self.fairlead_dofs, self.anchor_dofs = dofs.fairlead_dofs, dofs.anchor_dofs
        self.r_local = dofs.r_local0[0] if bodies else None
        self._init_frames()
        self._init_prescribed()
        self.K_bodies = [b.hydrostatic_stiffness(generalized=True) for b in bodies]
        self.F_bodies0 = [b.static_force() for b in bodies]
        self.K_body = self.K_bodies[0] if bodies else None
        self.weight = lines.weight_load()
        self.M_lines = lines.mass_matrix(lumped=lumped_mass).tocsr()
        # lumped line-end masses on the bodies (kg; None: consistent, not point masses)
        self.end_masses = (self.M_lines.diagonal()[self.body_end_dofs[:, 0]]
                           if lumped_mass and not lines.hermite else None)
        self._carrying = {}  # exact bodies with their line-end masses (carrying_body)
        self._free_pattern = (None if self.nb else EmptyPattern(self.nf) if not lines.lines
                              else ElementPattern(lines, position=dofs.position))
        self.committing = []  # terms with a history (commit(t, u, v))
        self.dead_load = self._dead_load()
        self.built_in_terms = tuple(self._built_in_terms())
        for term in self.built_in_terms:
            self._join(term)
        for term in terms:
            self._join(term)
        self._assemble_mass()

    def _built_in_terms(self):
        """The physics every System has, as terms: the cable (with the creep laws' and
        the users' laws' terms), the free points' drag, the bodies' restoring and applied
        loads (their dead loads: :attr:`dead_load`)."""
        terms = [self.cable] if self.cable is not None else []
        if self.lines.lines and any(has_creep(law) for law in self.lines.laws):
            terms.append(CreepTerm(self.lines))  # viscoelastic, Syrope ropes
        terms += law_terms(self.lines) if self.lines.lines else []  # the users' laws
        terms += [PointDrag(p, point.CdA, point.rho, self.sea)
                  for p, point in enumerate(self.point_masses) if point.CdA]
        for k, body in enumerate(self.bodies):
            terms += [BodyRestoring(k, body, self.K_bodies[k], self.F_bodies0[k]),
                      AppliedLoad(k, body)]
        return terms

    @property
    def memory_in_tension(self) -> bool:
        """Whether the lines' reported tension reads a memory (a creep state, a user
        law's state) that the time step advances."""
        lines = self.lines
        return lines.creep is not None or any(
            getattr(law, "initial_state", ()) for law in lines.laws)

    def _dead_load(self):
        """(n,) the constant loads on the free points and bodies that the load factor
        scales (N, N m; the residual gets -load_factor times it): the points' net
        buoyancy (rho V - m) g up, the bodies' static load at the reference pose."""
        dead = np.zeros(self.n)
        for p, point in enumerate(self.point_masses):
            dead[self.point_columns[p][2]] += (point.rho * point.volume - point.mass) * point.g
        for k, block in enumerate(self.dofs.blocks):
            dead[block] += self.F_bodies0[k]
        return dead

    @property
    def body_load(self):
        """The applied load on body 0: f(t, q, qdot) -> 6-vector (N, N m), or None."""
        return self.body_loads[0] if self.body_loads else None

    @body_load.setter
    def body_load(self, load):
        if not self.bodies:
            raise ValueError("System body_load: the system has no dynamic body")
        self.body_loads[0] = load

    def _added(self, *kinds) -> tuple:
        built_in = {id(term) for term in self.built_in_terms}
        return tuple(term for kind in kinds for term in self._terms[kind]
                     if id(term) not in built_in)

    @property
    def terms(self) -> tuple:
        """The terms added to the system's own physics (lines, points, bodies, body
        pairs): the model's options and a user's terms; add with :meth:`add_term`. Its own
        physics, joined the same way, is :attr:`built_in_terms`."""
        return self._added("lines", "points", "bodies", "body pairs")

    @property
    def line_terms(self) -> tuple:
        return self._added("lines")

    @property
    def point_terms(self) -> tuple:
        return self._added("points")

    @property
    def body_terms(self) -> tuple:
        """The added terms on one body and on pairs of bodies (joints)."""
        return self._added("bodies", "body pairs")

    def add_term(self, term):
        """Add a :class:`~skmoor.fem.terms.Term` (lines, a free point or a body) with its mass."""
        self._join(term)
        self._assemble_mass()
        self.__dict__.pop("resting_plans", None)  # a sea bed may have come with it

    def _join(self, term):
        _check_target(term, len(self.point_masses), self.bodies)
        term.bind(self)
        self._terms[term.acts_on].append(term)
        if callable(getattr(term, "commit", None)):
            self.committing.append(term)

    def _assemble_mass(self):
        """M_red = P0^T (M_lines + term masses) P0 + point and body masses, kg."""
        M_lines = self.M_lines
        for term in self._terms["lines"]:
            extra = term.mass_matrix()
            if extra is not None:
                M_lines = M_lines + extra
        P0 = self.P(np.zeros(self.n))
        M = (P0.T @ M_lines @ P0).tocsr().tolil()
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
            constant = self._split_added_masses(k)
            block = self.dofs.blocks[k]
            M[block, block] = M[block, block].toarray() + body.mass_matrix() + constant
        self.M = M.tocsr()
        self._held_masses(M_lines, P0)

    def commit(self, t, x, v):
        """An accepted time level (t, s; x, v reduced): passed to the terms that keep a
        history, each on its own DOFs (see :mod:`skmoor.fem.terms`)."""
        for term in self.committing:
            if term.acts_on == "bodies":
                block = self.dofs.blocks[term.body]
                term.commit(t, x[block], v[block])
            elif term.acts_on == "points":
                columns = self.point_columns[term.point]
                term.commit(t, x[columns], v[columns])
            else:
                term.commit(t, self.full_displacement(x, t), self.full_velocity(x, v, t))

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
        dofs = self.dofs
        u = np.zeros(dofs.ndofs)
        u[dofs.free] = x[: dofs.nf] if dofs.identity else x[dofs.columns]
        if body_ends is not None:
            u[dofs.body_flat] = body_ends.ravel()
        if dofs.has_prescribed:
            u[dofs.prescribed_flat] = self.prescribed_state(t)[0].ravel()
        return u

    def fairlead_displacement(self, x, t=0.0):
        """(nlines, 3) displacements of the lines' B ends, m."""
        return self.full_displacement(x, t)[self.fairlead_dofs]

    def full_state(self, x, v, t=0.0):
        """(ndofs,) cable displacement (m) and velocity (m/s) of the reduced state (x, v)
        at time t, the bodies' kinematics computed once."""
        ends, J = self._attachment(x) if self.nb else (None, None)
        return self._displacement(x, ends, t), self._velocity(x, v, t, J)

    def full_velocity(self, x, v, t=0.0, dt=1e-6):
        """(ndofs,) cable velocity, m/s."""
        return self._velocity(x, v, t, self._jacobian(x), dt)

    def _velocity(self, x, v, t, J, dt=1e-6):
        ud = self.dofs.expand(v, J)
        if self.dofs.has_prescribed:
            ud[self.dofs.prescribed_flat] = self.prescribed_state(t, dt)[1].ravel()
        return ud


    def P(self, x):
        """du/dx (ndofs, n): the free DOFs' columns, the body ends' Jacobians."""
        return self.dofs.P(self._jacobian(x))

    def reduce_constant(self, A):
        """P0^T A P0 (CSR) of a full (ndofs, ndofs) matrix A, P0 = P at x = 0."""
        P0 = self.P(np.zeros(self.n))
        return (P0.T @ A @ P0).tocsr()

    @property
    def needs_velocity(self):
        """True when the line residual reads the cable velocity (damping, line terms)."""
        return bool(self._terms["lines"]) or self.damped

    # --- the nonlinear system
    def line_residual(self, u, ud, t=0.0, load_factor=1.0, tangent=True, layout="sparse",
                      newton=False):
        """Full cable residual internal - external (N) and its u- and v-derivatives in
        ``layout`` ('sparse', 'dense' or 'band'; ``newton``: as :meth:`residual`)."""
        R, Ke, Ce = self._line_blocks(u, ud, t, load_factor, tangent, newton)
        if not tangent:
            return R, None, None
        return R, *self._sum(self.kernel.pattern, Ke, Ce, layout)

    def _line_blocks(self, u, ud, t, load_factor, tangent, newton=False):
        """The cable residual (N) with the element blocks (nel, 6, 6) of its derivatives
        d/du and d/dv (None without ``tangent``): the cable kernel and every line term
        (with ``newton``, the Newton matrix's blocks of the terms that have one)."""
        R = -load_factor * self.weight
        Ke = Ce = None
        if tangent:
            Ke, Ce = np.zeros(self._block_shape), np.zeros(self._block_shape)
        for term in self._terms["lines"]:
            if newton and tangent and term.newton_matrix:
                term.add_to(u, ud, t, R, Ke, Ce, newton=True)
            else:
                term.add_to(u, ud, t, R, Ke, Ce)
        return R, Ke, Ce

    @property
    def bed_landing(self):
        """The sea bed's :meth:`~skmoor.sea.seabed.SeabedKernel.landing` arrays on this
        system's columns, or None (no bed); made once per bed term."""
        bed = next((term for term in self._terms["lines"] if hasattr(term, "landing")), None)
        if bed is None:
            return None
        kept = getattr(self, "_landing", (None, None))
        if kept[0] is not bed:
            kept = self._landing = (bed, bed.landing(self.dofs.position))
        return kept[1]

    def limit_correction(self, x, dx) -> bool:
        """Stops the line nodes that the time step's Newton correction dx (reduced, m;
        changed in place) carries across the bed's surface from x at the bed's Newton
        depth (:func:`~skmoor.sea.seabed.land_on_bed`); whether it stopped any."""
        landing = self.bed_landing
        return landing is not None and land_on_bed(x, dx, np.max(np.abs(dx), initial=0.0),
                                                   *landing)

    def _sum(self, pattern, Ke, Ce, layout):
        """K, Kv in ``layout``: the element blocks assembled on ``pattern``."""
        K = pattern.assemble(Ke, layout)
        Kv = pattern.assemble(Ce, layout) if self.needs_velocity else None
        return K, Kv

    @property
    def bandwidth(self):
        """Half-bandwidth of the reduced matrices without bodies (None with one: its
        rows and columns couple all its line ends)."""
        return None if self.nb else self._free_pattern.bandwidth

    def _points(self, x, v, t, R, tangent):
        """Adds the free points' terms into R; returns their derivative blocks d/dx, d/dv
        (npoints, 3, 3) or None without ``tangent``."""
        npoints = len(self.point_masses)
        K = np.zeros((npoints, 3, 3)) if tangent else None
        C = np.zeros((npoints, 3, 3)) if tangent else None
        for term in self._terms["points"]:
            cols = self.point_columns[term.point]
            Rp = np.zeros(3)
            term.add_to(x[cols], v[cols], t, Rp, None if K is None else K[term.point],
                        None if C is None else C[term.point])
            R[cols] += Rp
        return K, C


    def non_finite(self, x, v=None, t=0.0) -> str | None:
        """The first term (its name, and whether it is the system's own or added) whose
        residual or derivatives are not finite (NaN, inf) at the state (x, v, t), or None:
        each term evaluated alone."""
        v = np.zeros(self.n) if v is None else v
        ends, J = self._attachment(x) if self.nb else (None, None)
        u = self._displacement(x, ends, t)
        ud = self._velocity(x, v, t, J)
        built_in = {id(term) for term in self.built_in_terms}
        states = {"lines": lambda term: (u, ud, np.zeros(self.lines.ndofs),
                                         np.zeros(self._block_shape)),
                  "points": lambda term: (x[self.point_columns[term.point]],
                                          v[self.point_columns[term.point]], np.zeros(3),
                                          np.zeros((3, 3))),
                  "bodies": lambda term: (x[self.dofs.blocks[term.body]],
                                          v[self.dofs.blocks[term.body]], np.zeros(6),
                                          np.zeros((6, 6)))}
        for kind, state in states.items():
            for term in self._terms[kind]:
                a, b, R, K = state(term)
                C = np.zeros_like(K)
                with np.errstate(all="ignore"):
                    term.add_to(a, b, t, R, K, C)
                if not all(np.all(np.isfinite(z)) for z in (R, K, C)):
                    name = getattr(term, "name", None) or type(term).__name__
                    whose = "skmoor's own" if id(term) in built_in else "an added"
                    return f"{whose} {kind} term {name!r} ({type(term).__name__})"
        return None

    def residual(self, x, v=None, t=0.0, load_factor=1.0, tangent=True, layout="sparse",
                 newton=False):
        """Reduced residual R(x, v, t) (no inertia, no Rayleigh damping) and its
        derivatives K = dR/dx and Kv = dR/dv (None when zero) in ``layout``: 'sparse'
        (CSR), 'dense' (arrays, faster below a few hundred unknowns) or, without bodies,
        'band' (:class:`~skmoor.numerics.banded.Band`, half-bandwidth :attr:`bandwidth`).
        newton: K is the time step's Newton matrix's (the sea bed's slope stabilized,
        :func:`~skmoor.sea.seabed.newton_slope`; the same as dR/dx at rest)."""
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
        ud = self._velocity(x, v, t, J) if self.needs_velocity else None
        if self.nb or not tangent:
            R_full, K_full, Kv_full = self.line_residual(u, ud, t, load_factor, tangent, layout,
                                                         newton)
        else:  # no body: the element blocks go straight into the reduced matrices
            R_full, Ke, Ce = self._line_blocks(u, ud, t, load_factor, True, newton)
        R = self.dofs.reduce(R_full, J)
        if self.point_masses or self.nb:
            R -= load_factor * self.dead_load
        point_K = point_C = None
        if self.point_masses:
            point_K, point_C = self._points(x, v, t, R, tangent)
        body_K, body_Kv = self._bodies(x, v, t, R, tangent)
        pair_K, pair_Kv = self._body_pairs(x, v, t, R, tangent)
        if not tangent:
            return R, None, None
        if not self.nb:
            K, Kv = self._sum(self._free_pattern, Ke, Ce, layout)
            return (R, *self._add_point_blocks(K, Kv, point_K, point_C, layout))
        K, Kv = self._body_tangents(x, v, J, R_full, K_full, Kv_full, (body_K, body_Kv),
                                    (pair_K, pair_Kv), layout)
        return (R, *self._add_point_blocks(K, Kv, point_K, point_C, layout))

    def _bodies(self, x, v, t, R, tangent):
        """Adds the bodies' terms into R (their restoring and applied loads among them);
        returns the (6, 6) blocks of their d/dx and d/dv, one per body (None each without
        ``tangent``)."""
        body_K, body_Kv = [], []
        for k in range(len(self.bodies)):
            block = self.dofs.blocks[k]
            q, qdot = x[block], v[block]
            Kk, Ck = (np.zeros((6, 6)), np.zeros((6, 6))) if tangent else (None, None)
            Rk = np.zeros(6)
            for term in self._terms["bodies"]:
                if term.body == k:
                    term.add_to(q, qdot, t, Rk, Kk, Ck)
            R[block] += Rk
            body_K.append(Kk)
            body_Kv.append(Ck)
        return body_K, body_Kv

    def _body_tangents(self, x, v, J, R_full, K_full, Kv_full, terms, pairs, layout):
        """K, Kv (n, n) in ``layout`` with bodies: the line matrices reduced, each body's
        block (the line ends' attachment Hessian, its restoring stiffness and damping, its
        terms' blocks ``terms`` = (d/dx, d/dv) lists) and the joints' ``pairs`` ((nb, nb)
        each, or None), and the body columns of the velocity-dependent line forces."""
        dofs, dense = self.dofs, layout == "dense"
        if dense:
            K = dofs.reduce_dense(K_full, J)
            Kv = None if Kv_full is None else dofs.reduce_dense(Kv_full, J)
        else:
            K, Kv = (None if A is None else dofs.reduce_sparse(A, J) for A in (K_full, Kv_full))
        K_bodies = np.zeros((self.nb, self.nb))
        D_bodies = np.zeros((self.nb, self.nb))
        end_forces = R_full[self.body_end_dofs]
        for k in range(len(self.bodies)):
            b, q, rows = slice(6 * k, 6 * k + 6), x[dofs.blocks[k]], dofs.body_rows[k]
            H = (rigid.attachment_hessian(q, self.frame_r_local[k], end_forces[rows])
                 if len(rows) else 0.0)
            K_bodies[b, b] = H + terms[0][k]
            D_bodies[b, b] = terms[1][k]
        if pairs[0] is not None:
            K_bodies += pairs[0]
            D_bodies += pairs[1]
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
            K = K + dofs.embed_bodies(K_bodies)
            if slope is not None:
                rows, cols = np.nonzero(slope)
                K = K + sp.csr_matrix((slope[rows, cols], (rows, cols + self.nf)),
                                      shape=(self.n, self.n))
            if damped:
                D = dofs.embed_bodies(D_bodies)
                Kv = D if Kv is None else Kv + D
        return K, Kv

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


    def _velocity_slope(self, Kv_full, x, v, J):
        """(n, 6 nbodies) P^T Kv_full d(udot)/dq: the body ends' velocity J(q) v changes
        with q (the body columns of K)."""
        slopes = np.zeros((len(self.dofs.body_flat), self.nb))
        for k, rows in enumerate(self.dofs.body_rows):
            if len(rows):
                block = self.dofs.blocks[k]
                slopes[3 * rows[0]: 3 * rows[-1] + 3, 6 * k: 6 * k + 6] = \
                    rigid.attachment_velocity_slope(x[block], self.frame_r_local[k], v[block])
        B = Kv_full[:, self.dofs.body_flat] @ slopes  # (ndofs, nb)
        B = B.toarray() if hasattr(B, "toarray") else np.asarray(B)
        out = np.empty((self.n, self.nb))
        out[: self.nf] = B[self.free] if self.dofs.identity else self.dofs.selection @ B[self.free]
        out[self.nf:] = J.T @ B[self.dofs.body_flat]
        return out

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
