"""The term protocol: everything added to a model's equations, on lines, points or bodies.

A term adds its part of the residual, internal - external forces (a load F enters as -F,
N or N m), and its derivatives with respect to the displacements and to the velocities:

    term.add_to(u, v, t, R, K, C)

- on lines (``acts_on = "lines"``): u, v the cable displacement (m) and velocity (m/s)
  on all DOFs of the LineSet (ndofs,), R (ndofs,), K and C element blocks (nel, 6, 6),
  DOFs [node i x, y, z, node j x, y, z] (on a bending LineSet, Hermite: (nel, 12, 12),
  DOFs ``LineSet.element_dofs``);
- on a free point (``"points"``, index ``term.point``): u, v, R (3,), K, C (3, 3);
- on a dynamic body (``"bodies"``, index ``term.body``): q, qdot, R (6,), K, C (6, 6);
  a body term that needs the attitude or the angular velocity takes them from
  ``term.body_motion(q, qdot)`` (:mod:`skmoor.bodies.body_motion`) and sets ``frame_aware = True``
  (an 'exact' body re-bases its angles only when all its terms do).
- on two dynamic bodies (``"body pairs"``, indices ``term.bodies``, a joint such as
  :class:`~skmoor.coupling.joints.BodyPin`): both bodies' DOFs one after the other, q, qdot,
  R (12,), K, C (12, 12); no mass.

K and C are None when only the residual is wanted. ``term.mass_matrix()`` is a constant
mass on the same DOFs (kg; sparse (ndofs, ndofs) on lines), or None. A term with a
memory of the past (:class:`~skmoor.bodies.radiation.PotentialFlow`) also has
``term.commit(t, u, v)``, which the time integration calls with the initial state and
after every accepted step, on the term's DOFs; within a step, ``add_to`` sees a time
later than the last committed one. A line term with ``newton_matrix = True`` also takes
``add_to(..., newton=True)`` from the time step, K then its Newton matrix's rather than
the exact derivative (the sea bed's, :func:`~skmoor.sea.seabed.newton_slope`). ``model.add(term)``
puts a term into statics, modes and dynamics alike (its mass included).

:class:`LineForm` turns a residual integrand written as a scikit-fem ``LinearForm``
(with :mod:`skmoor.fem.ops`) into a line term whose tangents come from automatic
differentiation, compiled with JAX (``pip install skmoor[autodiff]``), or from central
differences where JAX is absent. :func:`check_tangent` is the Taylor test of any term.
"""
from __future__ import annotations

import functools
import importlib.util
from dataclasses import dataclass

import numpy as np
from skfem import asm
from skfem.assembly.form.form import FormExtraParams

PATHS = ("auto", "compiled", "autodiff", "fd", "assembly")
HAS_JAX = importlib.util.find_spec("jax") is not None


class Term:
    """Base of every term (see the module docstring): subclasses set ``acts_on`` and
    implement :meth:`add_to`; :meth:`bind` is called once when the term joins a System."""

    acts_on = "lines"
    lines = None
    # a body term that reads its body's attitude only through :meth:`body_motion` (never off
    # q[3:]) lets an 'exact' body re-base its angles (System.rebase)
    frame_aware = False
    newton_matrix = False  # add_to takes newton=True (see the module docstring)
    _system = None
    why_python = "no compiled kernel (a user term)"  # why lowered() says None

    def lowered(self) -> str | None:
        """The name of the compiled kernel that evaluates this term inside the compiled
        time step ('cable', 'morison', 'seabed', 'surface', 'point drag', 'body restoring',
        'time load'), or None: the term is evaluated in Python, and the time loop with it
        (:attr:`why_python` says why)."""
        return None

    def bind(self, system):
        """Attach to a System: a line term to its LineSet, a body term to the body's
        kinematics (:meth:`body_motion`)."""
        if self.acts_on == "lines":
            if self.lines is not None and self.lines is not system.lines:
                raise ValueError(f"{type(self).__name__}: built for another LineSet")
            self.lines = system.lines
        elif self.acts_on == "bodies":
            self._system = system

    def body_motion(self, q, qdot=None):
        """A body term's :class:`~skmoor.bodies.body_motion.BodyMotion` at (q, qdot): the pose,
        rotation and angular velocity of its body, re-based frame included (the term
        must be in a System: ``model.add(term)``)."""
        if self._system is None:
            raise ValueError(f"{type(self).__name__}: a body term reads its body's motion "
                             "from the System it is added to (model.add(term) first)")
        return self._system.body_motion(q, qdot, self.body)

    def add_to(self, u, v, t, R, K=None, C=None):
        raise NotImplementedError

    # A term with a memory of the past has ``commit(t, u, v)`` (called after each accepted
    # step) and ``carry_memory(other)``: the memory of the same term in another model of
    # the same lines and bodies (a line failure's rebuilt one) taken as its own.

    def mass_matrix(self):
        """Constant mass on the term's DOFs (kg), or None."""
        return None

    def evaluate(self, u, v=None, t=0.0, tangent=True, layout="sparse"):
        """(R, K, C) of a line term assembled on its LineSet's DOFs: residual (N), d/du
        (N/m) and d/dv (N s/m) in ``layout`` ('sparse', 'dense' or 'band')."""
        from .patterns import ElementPattern

        if self.lines is None:
            raise ValueError(f"{type(self).__name__}.evaluate: not bound to a LineSet")
        pattern = getattr(self, "_pattern", None)
        if pattern is None:
            pattern = self._pattern = ElementPattern(self.lines)
        v = np.zeros_like(u) if v is None else v
        return pattern.evaluate(lambda R, K, C: self.add_to(u, v, t, R, K, C), tangent,
                                layout, rate=True)


def state_part(k, width=1):
    """A property of a term whose memory is one array ``_state`` ([its time, then blocks
    of ``_per_block`` values], what a compiled commit advances in place): blocks k to
    k + width - 1 as a view (shape (-1, width) when width > 1); assigning to it writes
    into the array (None: NaN)."""
    def view(self):
        n = self._per_block
        part = self._state[1 + k * n: 1 + (k + width) * n]
        return part if width == 1 else part.reshape(-1, width)

    def put(self, value):
        view(self)[...] = np.nan if value is None else value

    return property(view, put)


@functools.cache
def _jax_field():
    """scikit-fem's JaxDiscreteField with the operators a form may use on a field
    (-u, 1 + u, abs(u), comparisons), which it lacks."""
    from skfem.autodiff import JaxDiscreteField

    class Field(JaxDiscreteField):
        def __neg__(self):
            return -self.value

        def __pos__(self):
            return self.value

        def __abs__(self):
            return abs(self.value)

        def __radd__(self, other):
            return other + self.value

        def __rpow__(self, other):
            return other ** self.value

        def __lt__(self, other):
            return self.value < getattr(other, "value", other)

        def __le__(self, other):
            return self.value <= getattr(other, "value", other)

        def __gt__(self, other):
            return self.value > getattr(other, "value", other)

        def __ge__(self, other):
            return self.value >= getattr(other, "value", other)

    return Field


def _raw(form):
    """The integrand of a scikit-fem LinearForm (or a plain function of (v, w))."""
    return getattr(form, "form", form)


class LineForm(Term):
    """A line term from its residual integrand alone.

    residual: a scikit-fem ``LinearForm`` (or function) of (v, w), the term's part of
    internal - external forces per unit reference length (N/m) tested with v; w has the
    displacement ``w.u`` and velocity ``w.du`` (fields: ``.value`` (3, nel, nqp),
    ``.grad``; :func:`skmoor.fem.ops.d_ds`), the time ``w.t`` (s), the arclength ``w.x`` (m),
    the LineSet's reference fields (``Xp``, ``T``, ``EA``, ``m``, ``w``, ``BA``) and
    ``fields`` (a dict, or a function of t returning one; an (ndofs,) array is a field of
    the line basis, interpolated like u: P1, or Hermite on bending lines). On bending
    lines also the second derivatives ``w.u.hess[:, 0, 0]``, ``w.du.hess[:, 0, 0]`` and
    ``v.hess[:, 0, 0]`` (1/m2 times the field), and the reference curvature ``Xpp``.
    Write it with :mod:`skmoor.fem.ops` for the automatic tangents.
    stiffness, damping: hand-written BilinearForms of its d/du and d/dv (optional; given,
    they are used on scikit-fem's assembly). mass: a BilinearForm of a constant mass (kg/m).
    quadrature: 'gauss', 'midpoint' or 'nodal' (see :class:`~skmoor.lines.line.LineSet`).
    state, update: a memory of the past (both or neither): ``state`` a dict of per-point
    values (name -> initial value, a number or an (nel, nqp) array) the residual reads as
    fields, ``update`` a function of w (as the residual's, with the step ``w.dt``, s)
    returning their new values (a dict by name). The time integration calls the form's
    ``commit`` with the initial state and after each accepted step; within a step the
    residual sees the last accepted values (an explicit update, first order in dt); a
    time before the last accepted one (a new run) starts from the initial values. On
    path 'compiled' (numba) the update is generated too and the compiled time step
    advances it (``step_commit``).
    path: how the residual and its tangents are evaluated:

    - 'compiled': the integrand and its derivatives traced once by JAX and written out as
      a numba element kernel (:mod:`skmoor.fem.form_compiler`, cached on disk), or compiled with
      ``jax.jit`` where the generator lacks an operation (``backend`` says which);
    - 'autodiff': scikit-fem's ``skfem.autodiff`` on its assembly (slow; a reference);
    - 'fd': NumPy evaluation, tangents by central differences (no JAX needed);
    - 'assembly': scikit-fem's assembly with the hand-written tangents;
    - 'auto' (default): 'assembly' with hand tangents, else 'compiled' with JAX, else 'fd'.
    """

    def __init__(self, residual, *, stiffness=None, damping=None, mass=None, fields=None,
                 quadrature="gauss", path="auto", lines=None, name=None, state=None,
                 update=None):
        if quadrature not in ("gauss", "midpoint", "nodal"):
            raise ValueError(f"LineForm quadrature: {quadrature!r} is not 'gauss', "
                             "'midpoint' or 'nodal'")
        if path not in PATHS:
            raise ValueError(f"LineForm path: {path!r} is not one of {PATHS}")
        if not callable(_raw(residual)):
            raise ValueError("LineForm residual: need a LinearForm or a function of (v, w)")
        hand = stiffness is not None or damping is not None
        if path == "auto":
            path = "assembly" if hand else ("compiled" if HAS_JAX else "fd")
        if path == "assembly" and not hand:
            raise ValueError("LineForm path 'assembly': needs the hand-written stiffness "
                             "and/or damping forms (or use 'compiled' / 'fd')")
        if path in ("compiled", "autodiff") and not HAS_JAX:
            raise ValueError(f"LineForm path {path!r}: needs JAX (pip install "
                             "'skmoor[autodiff]'), or use path='fd'")
        self.residual, self.stiffness, self.damping = residual, stiffness, damping
        self.mass, self.quadrature, self.path = mass, quadrature, path
        self.fields = {} if fields is None else fields
        self.name = name or getattr(_raw(residual), "__name__", "form")
        self.state, self.update = _checked_state(self, state, update)
        self._engine = None
        self.step_kernel = None  # (C function, ints, floats) the compiled time step calls
        self.generated = None  # the generated kernel's (see _numba_engine)
        # the memory: [values, the time of the last commit (NaN: none)] (see _memory);
        # the numba engine keeps it as [P, D, that time], the state in P's columns
        self._memory, self._state_layout, self._commit_kernel = None, None, None
        self.step_commit = None  # the generated commit the compiled step calls (numba)
        if self.state:
            self.commit = self._commit  # System.committing calls it
        if lines is not None:
            self.lines = lines

    def __repr__(self):
        return f"LineForm({self.name}, path={self.path!r}, quadrature={self.quadrature!r})"

    # --- data the forms see
    def basis_and_fields(self):
        """The LineSet basis of this quadrature and its reference fields."""
        lines = self.lines
        if self.quadrature == "midpoint":
            return lines.cable_basis, lines.cable_fields
        if self.quadrature == "nodal":
            return lines.nodal_basis, lines.nodal_fields
        return lines.basis, lines.fields

    def fields_at(self, t, u):
        """The extra fields at time t and displacement u (override for u-dependent data)."""
        return self.fields(t) if callable(self.fields) else self.fields

    def fields_vary(self) -> bool:
        """Whether :meth:`fields_at` changes with t or u (then the kernel reads them at
        each call, in Python): fields given as a function, or fields_at overridden."""
        return callable(self.fields) or type(self).fields_at is not LineForm.fields_at

    def _w(self, u, v, t):
        basis, base = self.basis_and_fields()
        return basis, dict(base, **self.fields_at(t, u), **self.state_values(), t=t, u=u,
                           du=v)

    # --- the memory (state, update)
    def state_values(self) -> dict:
        """The state's last accepted values, name -> (nel, nqp) view (empty without a
        state)."""
        if not self.state:
            return {}
        if self._memory is None:  # the initial values
            shape = self._point_shape()
            try:
                values = [np.broadcast_to(np.asarray(v, float), shape)
                          for v in self.state.values()]
            except ValueError as error:
                raise ValueError(f"LineForm {self.name} state: each initial value must be a "
                                 f"number or an array of shape (nel, nqp) = {shape}") from error
            self._memory = np.append(np.ravel(values), np.nan)
        memory = self._memory
        if self._state_layout is None:
            nel, nqp = self._point_shape()
            values = memory[:-1].reshape(len(self.state), nel, nqp)
            return dict(zip(self.state, values))
        P, _ = self._packed_fields()
        return {name: P[:, :, k] for name, k in zip(self.state, self._state_layout[1])}

    def _packed_fields(self):
        """(P, D): the numba engine's per-point and DOF fields as views of the memory."""
        shape = self._state_layout[0]
        size = shape[0] * shape[1] * shape[2]
        return (self._memory[:size].reshape(shape),
                self._memory[size:-1].reshape(-1, self.lines.ndofs))

    def _point_shape(self):
        """(nel, nqp) of this form's quadrature."""
        basis, _ = self.basis_and_fields()
        return basis.dx.shape

    def _commit(self, t, u, v):
        """The state advanced to the accepted step (t, s; u, v the LineSet's
        displacement and velocity): ``update``'s values at each point."""
        if self._engine is None:
            self.add_to(u, v, t, np.zeros(self.lines.ndofs))
        self._start_again_before(t)
        memory = self._memory
        last = memory[-1]
        dt = float(t - last) if t >= last else 0.0  # the first commit: 0
        if self._commit_kernel is not None:  # the generated update (numba)
            commit, edofs, h, dx, phi, x, columns, fields_now = self._commit_kernel
            P, D = self._packed_fields()
            if fields_now is not None:  # fields of (t, u): the update reads them at the step
                P[...], D[...] = fields_now(u, v, t)
            commit(np.asarray(u, float), np.asarray(v, float), float(t), edofs, h, dx, phi,
                   x, P, D, columns, dt)
        else:
            new = _numpy_update(self, u, v, t, dt)
            for name, value in self.state_values().items():
                value[...] = new[name]
        self._memory[-1] = t

    def carry_memory(self, other):
        """Take ``other``'s memory (the same form on the same lines of another model: a
        line failure's rebuilt one) as this form's: its values by name and the time of
        its last commit."""
        mine = self.state_values()
        for name, value in other.state_values().items():
            mine[name][...] = value
        self._memory[-1] = other._memory[-1]

    def _start_again_before(self, t):
        """A time before the last accepted one is a new run: the initial values again."""
        if self._memory is not None and t < self._memory[-1]:
            for name, value in self.state_values().items():
                value[...] = self.state[name]
            self._memory[-1] = np.nan

    def step_state(self):
        """(the memory array, its offset from the end of :attr:`step_kernel`'s floats)."""
        self.state_values()
        return self._memory, self._memory.size

    # --- the protocol
    def add_to(self, u, v, t, R, K=None, C=None):
        v = np.zeros_like(u) if v is None else v  # no velocity given: at rest
        if self.state:
            self._start_again_before(t)
        try:
            if self._engine is None:
                self._engine = _ENGINES[self.path](self)
            self._engine(u, v, t, R, K, C)
        except Exception as error:  # the user's own exception, without JAX's notes
            notes = getattr(error, "__notes__", None)
            if notes:
                notes[:] = [n for n in notes if "JAX" not in n]
            if f"in the user term {self!r}" not in (notes or ()):
                error.add_note(f"in the user term {self!r}")
            raise

    def lowered(self):
        """'form' when the compiled time step can call this form's generated kernel: path
        'compiled' on the numba backend, fields that do not change in time."""
        if self.path != "compiled" or self.lines is None:
            return None
        if self._engine is None:  # (made here: a subclass's add_to may skip a state)
            self._engine = _ENGINES[self.path](self)
        return "form" if self.step_kernel is not None else None

    @property
    def why_python(self):
        if self.path != "compiled":
            return f"path {self.path!r} (only path 'compiled' runs in the compiled step)"
        if getattr(self, "backend", "numba") != "numba":
            return f"backend {self.backend}"
        return "fields given as a function of time or displacement (evaluated in Python)"

    def mass_matrix(self):
        if self.mass is None:
            return None
        basis, w = self._w(np.zeros(self.lines.ndofs), np.zeros(self.lines.ndofs), 0.0)
        return asm(self.mass, basis, **w).tocsr()


_RESERVED = ("u", "du", "t", "x", "dt")


def _checked_state(term, state, update):
    """(state, update) of a LineForm: a dict of names to initial values and a function,
    or ({}, None)."""
    if state is None and update is None:
        return {}, None
    if state is None or update is None:
        raise ValueError(f"LineForm {term.name} state, update: give both (the memory's "
                         "initial values and the function of w that returns its new ones)")
    if not isinstance(state, dict) or not state:
        raise ValueError(f"LineForm {term.name} state: need a dict of names to initial "
                         f"values, got {state!r}")
    if not callable(update):
        raise ValueError(f"LineForm {term.name} update: need a function of w returning "
                         "the state's new values by name")
    fields = {} if callable(term.fields) else term.fields
    for name in state:
        if not isinstance(name, str) or name in _RESERVED or name in fields:
            raise ValueError(f"LineForm {term.name} state: the name {name!r} is taken (by "
                             f"w.{name} or a field) or not a string")
    return dict(state), update


def _numpy_update(term, u, v, t, dt):
    """``term.update``'s new state values at each point, evaluated with NumPy."""
    local = _Local(term)
    _, w = term._w(u, v, t)
    per, dofs, const = local.split({k: x for k, x in w.items() if k not in ("u", "du", "t")})
    w = _point_fields(np, _numpy_field, u[local.edofs], v[local.edofs], t, local.h, local.x,
                      local.phi, per, dofs, const)
    w["dt"] = dt
    return _new_state(term, term.update(w), lambda value: np.broadcast_to(
        np.asarray(value, float), (local.nel, local.nqp)))


def _new_state(term, new, shaped):
    """The update's values by name (each through ``shaped``), its keys checked."""
    if not isinstance(new, dict) or set(new) != set(term.state):
        raise ValueError(f"LineForm {term.name} update: must return a dict with the "
                         f"state's names {sorted(term.state)}, got "
                         f"{sorted(new) if isinstance(new, dict) else type(new).__name__}")
    return {name: shaped(new[name]) for name in term.state}


# --- the engines: each returns f(u, v, t, R, K, C) adding into R and the element blocks

def _local_order(lines, basis):
    """Permutation from scikit-fem's local DOFs to the element blocks' order
    (``LineSet.element_dofs``: [node i x, y, z, node j x, y, z] on P1)."""
    ours = lines.element_dofs
    theirs = basis.element_dofs.T  # (nel, Nbfun)
    order = np.array([int(np.flatnonzero(theirs[0] == d)[0]) for d in ours[0]])
    if not np.array_equal(theirs[:, order], ours):
        raise ValueError("LineForm: the basis' local DOFs do not follow the element nodes")
    return order


def _blocks(coo, order):
    """Element blocks (nel, nloc, nloc) [row test, column trial] of scikit-fem's COOData."""
    local = coo.tolocal()  # (nel, trial, test)
    return np.swapaxes(local, 1, 2)[:, order][:, :, order]


def _assembly_engine(term):
    """scikit-fem assembly: the residual LinearForm and the hand-written BilinearForms."""
    from skfem import BilinearForm, LinearForm

    residual = term.residual if isinstance(term.residual, LinearForm) else LinearForm(term.residual)
    stiffness, damping = (f if f is None or isinstance(f, BilinearForm) else BilinearForm(f)
                          for f in (term.stiffness, term.damping))
    basis, _ = term.basis_and_fields()
    order = _local_order(term.lines, basis)

    def run(u, v, t, R, K, C):
        basis, w = term._w(u, v, t)
        R += asm(residual, basis, **w)
        if K is None:
            return
        if stiffness is not None:
            K += _blocks(stiffness.elemental(basis, **w), order)
        if damping is not None:
            C += _blocks(damping.elemental(basis, **w), order)

    return run


def _autodiff_engine(term):
    """scikit-fem's skfem.autodiff (JAX linearization on its assembly), d/du and d/dv."""
    from skfem import LinearForm
    from skfem.autodiff import NonlinearForm
    from skfem.element import DiscreteField

    raw, Field = _raw(term.residual), _jax_field()

    def traced(w, **state):  # every field a JAX field (with its operators)
        w = {k: Field(*x.astuple) if isinstance(x, DiscreteField) or hasattr(x, "astuple")
             else x for k, x in w.items()}
        return FormExtraParams(dict(w, **{k: Field(*x.astuple) for k, x in state.items()}))

    by_u = NonlinearForm(lambda u, v, w: raw(Field(*v.astuple), traced(w, u=u)))
    by_v = NonlinearForm(lambda du, v, w: raw(Field(*v.astuple), traced(w, du=du)))
    residual = LinearForm(raw)
    basis, _ = term.basis_and_fields()
    order = _local_order(term.lines, basis)

    def run(u, v, t, R, K, C):
        basis, w = term._w(u, v, t)
        if K is None:
            R += asm(residual, basis, **w)
            return
        w_u = {k: x for k, x in w.items() if k != "u"}
        Ku, minus_R = by_u.elemental(basis, x=u, **w_u)
        R += minus_R.todefault() * -1.0
        K += _blocks(Ku, order)
        w_v = {k: x for k, x in w.items() if k != "du"}
        Cv, _ = by_v.elemental(basis, x=v, **w_v)
        C += _blocks(Cv, order)

    return run


class _Local:
    """Element-local evaluation of a residual integrand on the lines (NumPy or JAX).

    Fields split into: per-element arrays (last two axes (nel, nqp)), DOF vectors of the
    line basis (ndofs,), and constants (scalars, broadcastable arrays, other objects).
    ``phi``: the P1 shape functions (2, nqp), or on Hermite the reference cubics and
    their d/dxi and d2/dxi2 (3, 4, nqp) (scaled by the element length in
    :func:`_hermite_field`)."""

    def __init__(self, term):
        lines = term.lines
        basis, _ = term.basis_and_fields()
        self.edofs = lines.element_dofs
        self.ndofs, (self.nel, self.nloc) = lines.ndofs, self.edofs.shape
        self.hermite = lines.hermite
        self.xi = xi = basis.X[0]
        if self.hermite:
            from .hermite import hermite_shapes
            N, dN, d2N = hermite_shapes(xi, np.ones(1))
            self.phi = np.stack([N[0].T, dN[0].T, d2N[0].T])  # (3, 4, nqp): a unit element
        else:
            self.phi = np.stack([1.0 - xi, xi])  # (2, nqp)
        self.nqp = xi.size
        self.h = lines.element_lengths  # (nel,)
        self.dx = basis.dx  # (nel, nqp)
        self.x = basis.mapping.F(basis.X)  # (1, nel, nqp), the arclength s
        self.raw = _raw(term.residual)

    def split(self, w):
        """(per_element, dof_vectors, constants) of a field dict."""
        per, dofs, const = {}, {}, {}
        for name, value in w.items():
            if isinstance(value, np.ndarray) and value.shape == (self.ndofs,):
                dofs[name] = value[self.edofs]  # (nel, nloc)
            elif (isinstance(value, np.ndarray) and value.ndim >= 2
                  and value.shape[-2:] == (self.nel, self.nqp)):
                per[name] = value
            else:
                const[name] = value
        return per, dofs, const


def _p1_field(xp, ue, h, phi):
    """The P1 field of element values ue (nel, 6): value (3, nel, nqp), grad (3, 1, nel, nqp)."""
    a, b = ue[:, :3].T, ue[:, 3:].T  # (3, nel)
    value = a[:, :, None] * phi[0] + b[:, :, None] * phi[1]
    slope = ((b - a) / h)[:, :, None] * xp.ones(phi.shape[1])
    return value, slope[:, None]


def _tests(xp, h, phi):
    """The 6 local test functions: (value (3, nel, nqp), grad (3, 1, nel, nqp)) each."""
    nel, nqp = h.shape[0], phi.shape[1]
    out = []
    for node in range(2):
        sign = -1.0 if node == 0 else 1.0
        for c in range(3):
            value = xp.zeros((3, nel, nqp))
            grad = xp.zeros((3, 1, nel, nqp))
            if xp is np:
                value[c] = phi[node]
                grad[c, 0] = sign / h[:, None]
            else:
                value = value.at[c].set(xp.broadcast_to(phi[node], (nel, nqp)))
                grad = grad.at[c, 0].set(xp.broadcast_to(sign / h[:, None], (nel, nqp)))
            out.append((value, grad))
    return out


def _hermite_scales(xp, h):
    """(nel, 4) factors of the unit-element cubics for their values, d/ds and d2/ds2."""
    one = xp.ones_like(h)
    return (xp.stack([one, h, one, h], axis=1), xp.stack([1.0 / h, one, 1.0 / h, one], axis=1),
            xp.stack([1.0 / h**2, 1.0 / h, 1.0 / h**2, 1.0 / h], axis=1))


def _hermite_field(xp, ue, h, phi):
    """The Hermite field of element DOFs ue (nel, 12) [u_i, u_i', u_j, u_j'] x 3: value
    (3, nel, nqp), grad (3, 1, nel, nqp), hess (3, 1, 1, nel, nqp)."""
    U = ue.reshape(h.shape[0], 4, 3)
    value, grad, hess = (xp.einsum("ebc,eb,bq->ceq", U, scale, phi[k])
                         for k, scale in enumerate(_hermite_scales(xp, h)))
    return value, grad[:, None], hess[:, None, None]


def _hermite_tests(xp, h, phi):
    """The 12 local test functions of the Hermite element, in the order of its DOFs:
    (value, grad, hess) each."""
    scales = _hermite_scales(xp, h)
    zero = xp.zeros((h.shape[0], phi.shape[2]))
    out = []
    for b in range(4):
        value, slope, curvature = (scale[:, b, None] * phi[k, b]
                                   for k, scale in enumerate(scales))
        for c in range(3):
            out.append(tuple(xp.stack([part if k == c else zero for k in range(3)])[index]
                             for part, index in ((value, ...), (slope, (slice(None), None)),
                                                 (curvature, (slice(None), None, None)))))
    return out


def _field_of(field, parts):
    """``field`` (a DiscreteField class) of (value, grad[, hess])."""
    return field(parts[0], parts[1], hess=parts[2] if len(parts) > 2 else None)


def _point_fields(xp, field, ue, ude, t, h, x, phi, per, dofs, const):
    """The w a residual integrand sees at the quadrature points of the elements."""
    interpolate = _hermite_field if phi.ndim == 3 else _p1_field
    w = {name: value for name, value in const.items()}
    w.update(per)
    for name, values in dofs.items():
        w[name] = _field_of(field, interpolate(xp, values, h, phi))
    w["u"] = _field_of(field, interpolate(xp, ue, h, phi))
    w["du"] = _field_of(field, interpolate(xp, ude, h, phi))
    w["t"], w["x"] = t, x
    return FormExtraParams(w)


def _element_residual(xp, field, raw, ue, ude, t, h, dx, x, phi, per, dofs, const):
    """(nel, nloc) element residual vectors of the integrand ``raw``."""
    tests = _hermite_tests if phi.ndim == 3 else _tests
    w = _point_fields(xp, field, ue, ude, t, h, x, phi, per, dofs, const)
    columns = [xp.sum(raw(_field_of(field, parts), w) * dx, axis=-1)
               for parts in tests(xp, h, phi)]
    return xp.stack(columns, axis=-1).reshape(h.shape[0], ue.shape[1])


def _numpy_field(value, grad, hess=None):
    from skfem.element import DiscreteField
    return DiscreteField(value, grad, hess=hess)


def _fd_engine(term):
    """NumPy evaluation; tangents by central differences of the element residuals."""
    local = _Local(term)

    def residual(ue, ude, t, per, dofs, const):
        return _element_residual(np, _numpy_field, local.raw, ue, ude, t, local.h, local.dx,
                                 local.x, local.phi, per, dofs, const)

    def run(u, v, t, R, K, C):
        _, w = term._w(u, v, t)
        w = {k: x for k, x in w.items() if k not in ("u", "du", "t")}
        per, dofs, const = local.split(w)
        ue, ude = u[local.edofs], v[local.edofs]
        Re = residual(ue, ude, t, per, dofs, const)
        np.add.at(R, local.edofs, Re)
        if K is None:
            return
        scale = 1e-6 * (1.0 + np.max(np.abs(ue), initial=0.0))
        vscale = 1e-6 * (1.0 + np.max(np.abs(ude), initial=0.0))
        for k in range(local.nloc):
            step = np.zeros((1, local.nloc))
            step[0, k] = 1.0
            K[:, :, k] += (residual(ue + scale * step, ude, t, per, dofs, const)
                           - residual(ue - scale * step, ude, t, per, dofs, const)) / (2 * scale)
            C[:, :, k] += (residual(ue, ude + vscale * step, t, per, dofs, const)
                           - residual(ue, ude - vscale * step, t, per, dofs, const)) / (2 * vscale)

    return run


def _compiled_engine(term):
    """The integrand and its derivatives traced by JAX once, written out as scalar code
    and compiled by numba (:mod:`skmoor.fem.form_compiler`); where the generator does not cover
    the form's operations, JAX's own compiler (:func:`_jax_engine`)."""
    from .form_compiler import Unsupported

    try:
        run = _numba_engine(term)
        term.backend = "numba"
    except Unsupported as why:
        run = _jax_engine(term)
        term.backend = f"jax.jit ({why} is not in the scalar code generator)"
    return run


def _point_layout(local, w):
    """The per-point and P1 fields of w: (names and inner shapes, P (nel, nqp, NP),
    D (ND, ndofs)) as the generated kernel reads them, and the constants."""
    per, dofs, const = {}, {}, {}
    for name, value in sorted(w.items()):
        if isinstance(value, np.ndarray) and value.shape == (local.ndofs,):
            dofs[name] = value
        elif (isinstance(value, np.ndarray) and value.ndim >= 2
              and value.shape[-2:] == (local.nel, local.nqp)):
            per[name] = value
        else:
            const[name] = value
    shapes = {name: value.shape[:-2] for name, value in per.items()}
    columns = [np.moveaxis(v.reshape(-1, local.nel, local.nqp), 0, -1) for v in per.values()]
    P = (np.ascontiguousarray(np.concatenate(columns, axis=-1), dtype=float) if columns
         else np.zeros((local.nel, local.nqp, 0)))
    D = (np.ascontiguousarray(np.stack(list(dofs.values())), dtype=float) if dofs
         else np.zeros((0, local.ndofs)))
    return shapes, list(dofs), P, D, const


def _first_derivatives_only(closed, n_inputs, second):
    """Whether a traced integrand (a, b, c at one point of a bending line) reads neither
    u'' nor udot'' (z[second:n_inputs]) and has no part in v'' (c = 0)."""
    from .form_compiler import scalar_function, zero_outputs

    _, _, used = scalar_function(closed.jaxpr, closed.consts, n_inputs, "point")
    return (not any(k >= second for k in used)
            and {6, 7, 8} <= zero_outputs(closed.jaxpr, closed.consts, n_inputs))


def _numba_engine(term):
    """The generated numba kernel of the form (see :mod:`skmoor.fem.form_compiler`)."""
    import jax
    import jax.numpy as jnp
    import skfem.autodiff  # noqa: F401 - turns on float64 in JAX

    from .form_compiler import STATE, Unsupported, build_kernel, packed
    from .patterns import NO_BLOCKS

    local = _Local(term)
    _, w0 = term._w(np.zeros(local.ndofs), np.zeros(local.ndofs), 0.0)
    w0 = {k: x for k, x in w0.items() if k not in ("u", "du", "t")}
    shapes, dof_names, P0, D0, const = _point_layout(local, w0)
    varying = term.fields_vary()
    n_inputs = 14 + P0.shape[2] + 6 * D0.shape[0]
    unit = np.eye(3).reshape(3, 3, 1, 1)
    zero_value, zero_grad = np.zeros((3, 1, 1)), np.zeros((3, 1, 1, 1))
    JaxDiscreteField = _jax_field()

    # on bending lines the inputs end with u'' and udot'' (3 each) at z[second:]
    second = n_inputs if local.hermite else None
    if local.hermite:
        n_inputs += 6

    def field(z, start, curvature=None):
        hess = None if curvature is None else z[curvature: curvature + 3].reshape(3, 1, 1, 1, 1)
        return JaxDiscreteField(z[start: start + 3].reshape(3, 1, 1),
                                z[start + 3: start + 6].reshape(3, 1, 1, 1), hess=hess)

    def point_w(z):
        # w at one point from the kernel's inputs z
        w = dict(const)
        offset = 14
        for name, shape in shapes.items():
            size = int(np.prod(shape, dtype=int))
            w[name] = z[offset: offset + size].reshape(shape + (1, 1))
            offset += size
        for name in dof_names:
            w[name] = field(z, offset)
            offset += 6
        w.update(u=field(z, 0, second), du=field(z, 6, None if second is None else second + 3),
                 t=z[12], x=z[13].reshape(1, 1, 1))
        return FormExtraParams(w)

    zero_hess = np.zeros((3, 1, 1, 1, 1))

    def flux(z):
        # (a, b): the integrand at one point is a . v + b . v' (+ c . v'' on bending lines)
        w = point_w(z)
        hess = {} if second is None else {"hess": zero_hess}
        tests = ([JaxDiscreteField(unit[c], zero_grad, **hess) for c in range(3)]
                 + [JaxDiscreteField(zero_value, unit[c][:, None], **hess) for c in range(3)])
        if second is not None:
            tests += [JaxDiscreteField(zero_value, zero_grad, hess=unit[c][:, None, None])
                      for c in range(3)]
        return jnp.stack([jnp.sum(local.raw(v, w)) for v in tests])

    def with_tangent(z):
        # the slopes in the state: u, u', udot, udot' (and u'', udot'' at the end)
        end = n_inputs if second is None else second
        slopes = jax.jacfwd(lambda s: flux(jnp.concatenate([s[:STATE], z[STATE:end],
                                                            s[STATE:]])))(
            jnp.concatenate([z[:STATE], z[end:]]))
        return jnp.concatenate([flux(z), slopes.ravel()])

    def new_state(z):
        # the memory's new values at one point; the step dt is z[n_inputs]
        w = point_w(z)
        w["dt"] = z[n_inputs]
        new = _new_state(term, term.update(w), lambda value: jnp.reshape(value, ()))
        return jnp.stack([new[name] for name in term.state])

    z0 = jnp.zeros(n_inputs)
    residual_jaxpr = jax.make_jaxpr(flux)(z0)
    if second is not None and _first_derivatives_only(residual_jaxpr, n_inputs, second):
        n_inputs, second = second, None  # the plain Hermite kernel
        z0 = jnp.zeros(n_inputs)
        residual_jaxpr = jax.make_jaxpr(flux)(z0)
    tangent_jaxpr = jax.make_jaxpr(with_tangent)(z0)
    update_jaxpr = None
    if term.state:
        traced = jax.make_jaxpr(new_state)(jnp.zeros(n_inputs + 1))
        update_jaxpr = (traced.jaxpr, traced.consts)
    module, term.source = build_kernel((residual_jaxpr.jaxpr, residual_jaxpr.consts),
                                       (tangent_jaxpr.jaxpr, tangent_jaxpr.consts), n_inputs,
                                       P0.shape[2], hermite=local.hermite,
                                       update_jaxpr=update_jaxpr, second=second)
    kernel = module.kernel
    edofs = np.ascontiguousarray(local.edofs, dtype=np.int64)
    h, dx, phi = local.h, np.ascontiguousarray(local.dx), np.ascontiguousarray(local.phi)
    if local.hermite:  # each element's cubics and their d/ds (and d2/ds2): (2 or 3, nel, nqp, 4)
        from .hermite import hermite_shapes
        phi = np.ascontiguousarray(np.stack(hermite_shapes(local.xi, h)[:2 if second is None
                                                                        else 3]))
    x = np.ascontiguousarray(local.x[0])
    try:  # compile now: a form numba cannot type goes to jax.jit instead
        zero, blocks = np.zeros(local.ndofs), np.zeros((local.nel, local.nloc, local.nloc))
        for tangent in (True, False):
            kernel(zero, zero, 0.0, edofs, h, dx, phi, x, P0, D0, zero.copy(), blocks,
                   blocks.copy(), tangent)
    except Exception as error:  # numba's typing and lowering errors
        raise Unsupported(f"numba: {str(error).strip().splitlines()[0][:120]}") from error

    def fields_now(u, v, t):
        # (P, D) of the fields at (u, v, t), the memory's values in P's state columns
        _, w = term._w(u, v, t)
        layout = _point_layout(local, {k: a for k, a in w.items() if k not in ("u", "du", "t")})
        if layout[0] != shapes or layout[1] != dof_names:
            raise ValueError(f"LineForm {term.name}: the fields changed their names or "
                             "shapes between calls")
        return layout[2], layout[3]

    if term.state:  # the memory becomes [P, D, the last commit's time], the state in P
        last = term.step_state()[0][-1]
        offsets = np.cumsum([0] + [int(np.prod(shape, dtype=int)) for shape in shapes.values()])
        columns = np.array([offsets[list(shapes).index(name)] for name in term.state], np.int64)
        term._memory = np.concatenate([P0.ravel(), D0.ravel(), [last]])
        term._state_layout = (P0.shape, columns)
        term._commit_kernel = (module.commit, edofs, h, dx, phi, x, columns,
                               fields_now if varying else None)
    ints, floats = packed(edofs, h, dx, phi, x, P0, D0)
    D_start = floats.size - D0.size
    if term.state:  # (its step_commit reads the state's columns and last time after them)
        ints, floats = np.concatenate([ints, columns]), np.append(floats, np.nan)
    # (C function, ints, floats, the DOF fields' names, where D starts in floats, the
    # commit's C function or None): what a subclass whose fields vary can call from
    # compiled code, its D filled there
    term.generated = (module.step_kernel, ints, floats, dof_names, D_start,
                      module.step_commit if term.state else None)
    if not varying:  # the compiled time step calls it with these arrays
        if term.state:
            term.step_commit = module.step_commit
        term.step_kernel = (module.step_kernel, ints, floats)

    def run(u, v, t, R, K, C):
        P, D = P0, D0
        if term.state:  # the memory's current values
            P, D = term._packed_fields()
        if varying:
            P, D = fields_now(u, v, t)
        kernel(u, v, float(t), edofs, h, dx, phi, x, P, D, R,
               NO_BLOCKS if K is None else K, NO_BLOCKS if C is None else C, K is not None)

    return run


def _jax_engine(term):
    """The integrand, its d/du and d/dv traced by JAX once and compiled with jax.jit:
    element residuals and (nloc, nloc) blocks by forward-mode differentiation (vmap over
    elements), the residual scattered inside the compiled function."""
    import jax
    import jax.numpy as jnp
    import skfem.autodiff  # noqa: F401 - turns on float64 in JAX

    JaxDiscreteField = _jax_field()
    local = _Local(term)
    _, w0 = term._w(np.zeros(local.ndofs), np.zeros(local.ndofs), 0.0)
    varying = term.fields_vary() or bool(term.state)
    static = {k: x for k, x in w0.items() if k not in ("u", "du", "t")}
    if varying:  # time- or u-dependent fields are arguments; the LineSet's are constants
        _, base = term.basis_and_fields()
        static = {k: x for k, x in static.items() if k in base}
    per0, dofs0, const = local.split(static)
    edofs = jnp.asarray(local.edofs)
    h, dx, x, phi = (jnp.asarray(a) for a in (local.h, local.dx, local.x, local.phi))

    def one(ue, ude, t, he, dxe, xe, per, dofs):
        # one element, as scikit-fem sees it with nel = 1
        per = {k: jnp.expand_dims(a, -2) for k, a in per.items()}
        dofs = {k: a[None] for k, a in dofs.items()}
        return _element_residual(jnp, JaxDiscreteField, local.raw, ue[None], ude[None], t,
                                 he[None], dxe[None], xe[:, None], phi, per, dofs, const)[0]

    jacobian = jax.jacfwd(one, argnums=(0, 1))
    axes = (0, 0, None, 0, 0, 1, -2, 0)

    def gather(u, v, per, dofs):
        per = {**{k: jnp.asarray(a) for k, a in per0.items()}, **per}
        dofs = {**{k: jnp.asarray(a) for k, a in dofs0.items()},
                **{k: a[edofs] for k, a in dofs.items()}}
        return u[edofs], v[edofs], per, dofs

    @jax.jit
    def residual(u, v, t, per, dofs):
        ue, ude, per, dofs = gather(u, v, per, dofs)
        Re = jax.vmap(one, axes)(ue, ude, t, h, dx, x, per, dofs)
        return jnp.zeros(u.shape[0]).at[edofs].add(Re)

    @jax.jit
    def with_tangent(u, v, t, per, dofs):
        ue, ude, per, dofs = gather(u, v, per, dofs)
        Re = jax.vmap(one, axes)(ue, ude, t, h, dx, x, per, dofs)
        Ke, Ce = jax.vmap(jacobian, axes)(ue, ude, t, h, dx, x, per, dofs)
        return jnp.zeros(u.shape[0]).at[edofs].add(Re), Ke, Ce

    def run(u, v, t, R, K, C):
        per, dofs = {}, {}
        if varying:
            _, w = term._w(u, v, t)
            extra = {k: a for k, a in w.items()
                     if k not in ("u", "du", "t") and k not in static}
            per, _, rest = local.split(extra)
            dofs = {k: a for k, a in extra.items()  # DOF vectors: gathered in the jit
                    if isinstance(a, np.ndarray) and a.shape == (local.ndofs,)}
            if rest:
                raise ValueError(f"LineForm {term.name}: time-dependent fields must be "
                                 f"arrays of shape (..., nel, nqp) or (ndofs,): {sorted(rest)}")
        if K is None:
            R += np.asarray(residual(u, v, float(t), per, dofs))
            return
        Rj, Ke, Ce = with_tangent(u, v, float(t), per, dofs)
        R += np.asarray(Rj)
        K += np.asarray(Ke)
        C += np.asarray(Ce)

    return run


_ENGINES = {"assembly": _assembly_engine, "autodiff": _autodiff_engine, "fd": _fd_engine,
            "compiled": _compiled_engine}


# --- loads on points and bodies


# --- the Taylor test

@dataclass
class TangentCheck:
    """Taylor test of a term: ``slope_u``, ``slope_v`` (the observed orders of the
    remainder |R(u + h du) - R(u) - h K du| in h: 2 for an exact tangent, 1 for a wrong
    one; None where the remainder sits at round-off for every h, i.e. the term is linear
    in that argument and the tangent exact), and the remainders per step."""

    steps: np.ndarray
    remainder_u: np.ndarray
    remainder_v: np.ndarray
    slope_u: float | None
    slope_v: float | None

    @property
    def ok(self) -> bool:
        return all(s is None or s > 1.8 for s in (self.slope_u, self.slope_v))

    def __str__(self):
        def fmt(s):
            return "exact (linear)" if s is None else f"{s:.2f}"
        return (f"Taylor test: slope in u {fmt(self.slope_u)}, in v {fmt(self.slope_v)} "
                f"({'exact tangent' if self.ok else 'TANGENT WRONG'}: 2 expected)")


def _slope(steps, remainder, scale):
    """Order of the remainder over the steps where it is above round-off."""
    keep = remainder > 1e-11 * scale
    if keep.sum() < 2:
        return None
    s, r = np.log(steps[keep]), np.log(remainder[keep])
    return float(np.median(np.diff(r) / np.diff(s)))


def check_tangent(model, term, u=None, v=None, t=0.0, seed=0, steps=None) -> TangentCheck:
    """The Taylor test of ``term`` (any :class:`Term`) in ``model`` (a Model or System):
    at the state (u, v) (default: a random state near the reference, with a random
    velocity of 0.5 m/s scale), along random directions, the remainder of the first-order
    expansion must fall as h^2 for an exact tangent. Prints nothing; see
    :class:`TangentCheck` (``str()`` reports the slopes)."""
    system = getattr(model, "system", model)
    if term.acts_on == "lines" and term.lines is None:
        term.bind(system)
    rng = np.random.default_rng(seed)
    if term.acts_on == "lines":
        n, scale = system.lines.ndofs, float(np.mean(system.lines.element_lengths))
    else:
        n, scale = {"points": 3, "bodies": 6, "body pairs": 12}[term.acts_on], 1.0
    u = 1e-3 * scale * rng.standard_normal(n) if u is None else np.asarray(u, float)
    v = 0.5 * rng.standard_normal(n) if v is None else np.asarray(v, float)
    du, dv = rng.standard_normal(n) * 1e-2 * scale, rng.standard_normal(n) * 0.1

    def evaluate(uu, vv, tangent):
        R = np.zeros(n)
        if term.acts_on == "lines":
            if tangent:
                Rf, K, C = term.evaluate(uu, vv, t, True, "sparse")
                return Rf, K, C
            return term.evaluate(uu, vv, t, False)[0], None, None
        K, C = (np.zeros((n, n)), np.zeros((n, n))) if tangent else (None, None)
        term.add_to(uu, vv, t, R, K, C)
        return R, K, C

    R0, K, C = evaluate(u, v, True)
    steps = np.logspace(0, -4, 9) if steps is None else np.asarray(steps, float)
    ru, rv = [], []
    Kdu = K @ du if K is not None else np.zeros(n)
    Cdv = C @ dv if C is not None else np.zeros(n)
    for h in steps:
        ru.append(np.linalg.norm(evaluate(u + h * du, v, False)[0] - R0 - h * Kdu))
        rv.append(np.linalg.norm(evaluate(u, v + h * dv, False)[0] - R0 - h * Cdv))
    ru, rv = np.array(ru), np.array(rv)
    size = max(np.linalg.norm(R0), np.linalg.norm(Kdu), np.linalg.norm(Cdv), 1e-300)
    return TangentCheck(steps, ru, rv, _slope(steps, ru, size), _slope(steps, rv, size))
