"""A whole time step's Newton iteration in compiled code, for the systems it covers.

:func:`skmoor.solvers.dynamics.integrate` solves each step's alpha-level balance by modified
Newton; written in Python around compiled element kernels, an iteration of a small system
costs ~0.1 ms of Python glue against a few us of kernels. Here the same iteration -- the
cable kernel and the line terms, the reduction to the bodies and free points (Eq. 35's
coupling), the Newton matrix, its factorization (:mod:`skmoor.numerics.bordered`) and the solve --
is one numba function, so that a step costs what its arithmetic costs.

It covers P1 and bending (Hermite: 12 x 12 element blocks) lines with any built-in strain
law or a user's (:mod:`skmoor.lines.user_law`), MoorDyn-style or skmoor's Morison terms
in still water, a current and Airy waves (at the displaced nodes), a sea bed, plane or a
bathymetry grid (its plane under each displaced node; these three called by address as a
user's LineForm is, their ``step_kernel``, each compiled only when a run has it), the dry
part of the lines under a flat surface or Airy waves (``SurfaceTerm``: zero while every
node stays half a diameter under it; a step that brings one up is handed to the Python
step), fixed, prescribed and free points (buoyancy, drag in still water, a current and
Airy waves), small-rotation rigid bodies with quadratic drag (in the same water) and
an applied load of time alone (``load.time_only``; ``load.at_times(times)`` -> (m, 6),
if it has one, gives a batch's loads in one call) or of their state written with
``jax.numpy`` (called at each iterate), and the users' LineForms, point and body loads
whose code is generated (:mod:`skmoor.fem.form_compiler`), called by address
(:mod:`skmoor.fem.native_calls`) with the step's time. :func:`build` asks every term of
the System which kernel it lowers to (:meth:`~skmoor.fem.terms.Term.lowered`); the first
that lowers to none (a form on another path or with fields given as a function, water
fields, a load in NumPy, radiation memory, exact
rotations) makes it return None, its name and reason in :data:`last_refusal`, and the
step then runs in Python. When modified Newton does not converge the step retries with
the line search here, as the Python step does; a step that fails that too goes to the
Python step, which splits it. Results are the same as the Python step's to round-off.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from numba import cfunc, njit, typeof
from numba.core import types
from numba.experimental import structref

from ..bodies.body import rotation_and_slopes
from ..fem.form_compiler import POINTWISE_SIGNATURE, STEP_SIGNATURE
from ..fem.native_calls import (
    argument_types,
    call_compiled,
    call_form,
    call_load,
    compiled_address,
)
from ..fem.patterns import ElementPattern
from ..lines.bending import HermiteKernel
from ..lines.cable_kernel import _cable
from ..numerics import bordered
from ..sea.hydro import water_kinematics, wave_elevation
from ..sea.seabed import land_on_bed, resting_support
from . import newton

# numba freezes these into the cached step, whose cache follows this file's source only
# (touching it is not enough): written here, and checked against the Python step's
CONTRACTION, STALL, LINE_SEARCH = 0.2, 0.5, 6
BROYDEN_CONTRACTION, BROYDEN_HISTORY, BROYDEN_SCALING = 0.3, 8, 2.0
if (CONTRACTION, STALL, LINE_SEARCH, BROYDEN_CONTRACTION, BROYDEN_HISTORY, BROYDEN_SCALING) != (
        newton.CONTRACTION, newton.STALL, newton.LINE_SEARCH, newton.BROYDEN_CONTRACTION,
        newton.BROYDEN_HISTORY, newton.BROYDEN_SCALING):
    raise ImportError("skmoor.solvers.compiled_step: its Newton constants differ from "
                      "skmoor.solvers.newton's; change them in both files")

last_refusal = ""  # why the last build() returned None
# the step's compile units, each calling the others by address (compiled_address): those
# :func:`_run` calls through ``callees``, in that array's order, and _run itself
CALLEES = ("balance", "residual", "assemble", "factor", "cable", "solve", "commit")
PARTS = CALLEES + ("run",)
_shared = None  # (a process compiling some PARTS, their names): share_compile
TO_PYTHON = "the step is the Python step's"  # a step handed back (a line at the surface)
SOLVED, SINGULAR, SURFACE = 1, 0, 2  # what _balance returns
_CALLEES = {}  # the addresses of the step's parts by the numba type of its model (_find_callees)


@structref.register
class _StepDataType(types.StructRef):
    """numba's type of :class:`_StepData`."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(kind)) for name, kind in fields)


class _StepData(structref.StructRefProxy):
    """The model, scratch and factors of one compiled step, passed by reference: the
    functions of the step take this one pointer, not their hundreds of arrays (a tuple of
    arrays is passed member by member, and numba's compile time grows with that)."""


# the model's parts (each function reads its own) and the addresses of the step's parts
FIELDS = ("topology", "cable", "points", "bodies", "prescribed", "products", "M", "C",
          "damped", "width", "forms", "work", "factors", "callees", "water")
structref.define_proxy(_StepData, _StepDataType, FIELDS)


@njit(cache=True)
def _step_data(topology, cable, points, bodies, prescribed, products, M, C, damped, width,
               forms, work, factors, callees, water):
    """A :class:`_StepData` made in compiled code (numba's own Python constructor of a
    structref is compiled again in every process: this one is cached)."""
    return _StepData(topology, cable, points, bodies, prescribed, products, M, C, damped,
                     width, forms, work, factors, callees, water)


# stand-ins for an absent term (the compiled loop gets the same argument types)
NO_P1 = (np.zeros((0, 3)), np.zeros(0), np.zeros((0, 6)), np.zeros((0, 0)), np.zeros((0, 0)),
         np.zeros(0), np.zeros(0), np.zeros(0), np.zeros((0, 3), np.int64),
         np.zeros((0, 3), np.int64))  # bending lines: no P1 element (their loop is a form's)


def _refuse(why):
    global last_refusal
    last_refusal = why


def cached():
    """Whether numba's disk cache holds the compiled step for this source (False: the
    first run after an install or a change compiles it)."""
    try:
        return bool(_run._cache._cache_file._load_index())
    except (AttributeError, OSError):  # another numba's cache: assume it is there
        return True


def share_compile(process, parts):
    """``process`` (a ``subprocess.Popen``) compiles the step's ``parts`` (names in
    :data:`PARTS`) into numba's disk cache: the first step of this process compiles the
    other parts, waits for it, then reads these from the cache instead of compiling them
    too (:mod:`skmoor.run.first_compile`)."""
    global _shared
    _shared = (process, tuple(parts))


def compiling_elsewhere():
    """Whether another process compiles parts of the step for this one (share_compile)."""
    return _shared is not None


def _wait_for_shared():
    """The parts another process was compiling (share_compile), once it has ended
    (compiled into the cache, or failed: then they compile here)."""
    global _shared
    if _shared is None:
        return ()
    (process, parts), _shared = _shared, None
    try:
        process.wait(timeout=600)
    except Exception:  # noqa: BLE001 (a process that hangs or cannot be waited for)
        process.kill()
    return parts


# the kernels a term may lower to (Term.lowered), and those the step holds one of
LOWERED = ("cable", "surface", "point drag", "body drag", "body restoring", "time load",
           "form", "point load", "body load")
ONCE = ("cable", "surface")
FORMS = 8  # LineForms the compiled step calls by address (the Morison terms, the bed, the
# bending lines' loop and the users' generated kernels), at most
LOADS = 4  # user point and body loads likewise


@cfunc(STEP_SIGNATURE, cache=True)
def _no_form(u, ud, ndofs, t, ints, floats, R, K, C, tangent):
    """An empty slot of the kernels called by address."""


@cfunc(POINTWISE_SIGNATURE, cache=True)
def _no_load(z, out):
    """An empty slot of the user point and body loads."""


def _pointwise(terms):
    """The user point and body loads as the compiled loop takes them: (their C functions'
    addresses (LOADS,), the count, each load's [0 point / 1 body, its index] (LOADS, 2),
    their derivatives (LOADS, 2, 6, 6) as the last residual left them)."""
    functions = np.array([t.step_load.address for t in terms]
                         + [_no_load.address] * (LOADS - len(terms)), np.int64)
    targets = np.zeros((LOADS, 2), np.int64)
    for k, term in enumerate(terms):
        targets[k] = (0, term.point) if term.acts_on == "points" else (1, term.body)
    return functions, len(terms), targets, np.zeros((LOADS, 2, 6, 6))


def _forms(terms):
    """The kernels called by address (the Morison terms, the bed, the bending lines' loop
    and the users' LineForms) as the compiled loop takes them: (their C functions'
    addresses (FORMS,), the count, their packed ints and floats (one buffer each), each
    form's start in both (FORMS, 2))."""
    kernels = [term.step_kernel for term in terms]
    functions = np.array([k[0].address for k in kernels]
                         + [_no_form.address] * (FORMS - len(kernels)), np.int64)
    starts = np.zeros((FORMS, 2), np.int64)
    for i, (_, ints, floats) in enumerate(kernels[:-1]):
        starts[i + 1] = starts[i] + (ints.size, floats.size)
    ints = np.concatenate([k[1] for k in kernels] or [np.zeros(1, np.int64)])
    floats = np.concatenate([k[2] for k in kernels] or [np.zeros(1)])
    return functions, len(kernels), ints.astype(np.int64), floats.astype(float), starts


def _commits(terms):
    """The commits of the kernels called by address (a term with a memory of the past
    advances it in the compiled step, ``step_commit``): (their C functions' addresses
    (FORMS,), 0 where a kernel has none; how many have one)."""
    commits = [getattr(term, "step_commit", None) for term in terms]
    addresses = [0 if c is None else c.address for c in commits] + [0] * (FORMS - len(terms))
    return np.array(addresses, np.int64), sum(c is not None for c in commits)


def lowered_terms(system):
    """(why not, kinds): why the compiled step cannot take ``system``'s terms (the first
    term that lowers to no compiled kernel, named, with its reason) or None, and the
    lowered kinds with their terms."""
    kinds = {"form": [], "load": [], "body drag": []}  # each lowered kind: its term(s)
    for term in system.built_in_terms + system.terms:
        kind = term.lowered()
        name = getattr(term, "name", None) or type(term).__name__
        if kind is None:
            return f"{name} on the {term.acts_on}: {term.why_python}", kinds
        if kind not in LOWERED:
            return f"{name}: a '{kind}' kernel is not in the compiled step", kinds
        if kind in ONCE and kind in kinds:
            return f"{name}: a second '{kind}' term", kinds
        if kind == "form":
            kinds["form"].append(term)
            if len(kinds["form"]) > FORMS:
                return (f"{name}: more than {FORMS} kernels called by address (the Morison "
                        "terms, the bed, bending lines and the users' LineForms)"), kinds
        if kind in ("point load", "body load"):
            kinds["load"].append(term)
            if len(kinds["load"]) > LOADS:
                return f"{name}: more than {LOADS} user point and body loads", kinds
        if kind == "body drag":
            kinds["body drag"].append(term)
        kinds.setdefault(kind, term)
    if "cable" not in kinds:
        return "no lines", kinds
    if isinstance(system.kernel, HermiteKernel):  # bending lines: their loop as a form's
        kinds["form"].insert(0, system.kernel)
        if len(kinds["form"]) > FORMS:
            return (f"bending lines and {len(kinds['form']) - 1} other kernels called by "
                    f"address: at most {FORMS} in all"), kinds
    for term in system.committing:  # a memory the compiled step cannot advance
        if getattr(term, "step_commit", None) is None or term.lowered() != "form":
            name = getattr(term, "name", None) or type(term).__name__
            return f"{name}: a memory of the past with no compiled commit", kinds
    if system.nonlinear_inertia:
        return "a body with rotations='exact'", kinds
    seas = {None if term.sea is None or term.sea.still else id(term.sea)
            for term in system.built_in_terms + system.terms
            if hasattr(term, "step_water")}  # the points' and bodies' drag
    if len(seas) > 1:  # (the step holds one sea's water)
        return "drag on points and bodies in different seas", kinds
    return None, kinds


def build(system, C, scheme, tol, maxiter):
    """A :class:`CompiledStep` for ``system`` (C: its constant damping matrix, sparse, or
    None; scheme: a :class:`~skmoor.solvers.dynamics.Scheme`; tol, maxiter: Newton's), or
    None when the system has something the compiled step does not cover (reason in
    :data:`last_refusal`)."""
    lines = system.lines
    why, kinds = lowered_terms(system)
    if why is not None:
        return _refuse(why)
    surface = kinds.get("surface")
    width = 0
    if system.nf:  # (without bodies, the system's own pattern's)
        width = (system.bandwidth if not system.nb
                 else ElementPattern(lines, position=system.dofs.position).bandwidth)
    width = max(width, 1)
    try:
        M = bordered.split(system.M, system.nf, width)
        Cs = bordered.split(C, system.nf, width, system.n)
    except ValueError:
        return _refuse("mass or damping coupling line DOFs beyond the lines' band")
    damped = C is not None and C.count_nonzero() > 0
    return CompiledStep(system, surface, kinds, M, Cs, C, damped, width,
                        scheme, tol, maxiter)


def _contiguous(arrays):
    """The tuple with every array C-contiguous and integers int64: one compiled
    signature for all systems."""
    return tuple(np.ascontiguousarray(a, np.int64 if a.dtype.kind in "iu" else None)
                 if isinstance(a, np.ndarray) else a for a in arrays)


def _csr(A, shape=None):
    """(data, indices, indptr) of a sparse matrix, int64 indices (A None: zero, ``shape``)."""
    if A is None:
        return np.zeros(0), np.zeros(0, np.int64), np.zeros(shape[0] + 1, np.int64)
    if isinstance(A, np.ndarray):  # (row-major nonzeros: the rows come sorted)
        rows, columns = np.nonzero(A)
        return (np.ascontiguousarray(A[rows, columns], float), columns.astype(np.int64),
                np.searchsorted(rows, np.arange(A.shape[0] + 1)).astype(np.int64))
    A = sp.csr_matrix(A)
    A.eliminate_zeros()
    return (np.ascontiguousarray(A.data, float), A.indices.astype(np.int64),
            A.indptr.astype(np.int64))


class CompiledStep:
    """The arrays of a System the compiled step reads, and its Newton matrix's factors
    (kept across steps: modified Newton)."""

    handed_back = TO_PYTHON  # the failure of a step that is the Python step's to take

    def __init__(self, system, surface, kinds, M, C, C_matrix, damped, width,
                 scheme, tol, maxiter):
        self.system = system
        self.forms = (_forms(kinds["form"]) + _pointwise(kinds["load"])
                      + _commits(kinds["form"]))
        # the terms whose memory the step advances: (term, its state's start in the
        # packed floats), copied in before a batch of steps and out after it
        count, floats, starts = self.forms[1], self.forms[3], self.forms[4]
        ends = [*starts[1:count, 1], floats.size]  # where each form's floats end
        self.memories = [(term, ends[k] - term.step_state()[1])
                         for k, term in enumerate(kinds["form"])
                         if getattr(term, "step_commit", None) is not None]
        self._kept = kinds["form"] + kinds["load"]  # their C functions stay while called
        self.M, self.C, self.damped, self.width = M, C, damped, width
        self.products = (_csr(system.M), _csr(C_matrix, system.M.shape))
        self.scheme = (scheme.alpha_m, scheme.alpha_f, scheme.beta, scheme.gamma)
        self.tol, self.maxiter = float(tol), int(maxiter)
        lines, n = system.lines, system.n
        ndofs = lines.ndofs
        end_row = np.full(ndofs, -1, np.int64)
        end_row[system.dofs.body_flat] = np.arange(len(system.dofs.body_flat))
        r_local = (np.concatenate([r for r in system.frame_r_local]) if system.bodies
                   else np.zeros((0, 3)))
        self.topology = (np.asarray(system.dofs.position, np.int64), end_row,
                         np.asarray(system.dofs.body_of_end, np.int64),
                         np.asarray(system.body_end_dofs, np.int64).reshape(-1, 3),
                         np.ascontiguousarray(r_local, float),
                         np.ascontiguousarray(lines.element_dofs, np.int64), system.nf,
                         # the nodes' DOFs (n, 3), reference positions (n, 3; m) and the
                         # depth (m) under the surface a SurfaceTerm needs them below
                         # (none: no term)
                         np.zeros((0, 3), np.int64) if surface is None
                         else np.asarray(lines.nodal_dofs, np.int64).reshape(-1, 3),
                         np.zeros((0, 3)) if surface is None
                         else np.asarray(lines.points, float).reshape(-1, 3),
                         0.0 if surface is None else float(surface.deepest_reach))
        self.prescribed_dofs = np.asarray(system.dofs.prescribed_flat, np.int64)
        self.report_dofs = np.concatenate([np.ravel(system.fairlead_dofs),
                                           np.ravel(system.anchor_dofs)]).astype(np.int64)
        self.held = _held_inertia(system)
        self.resting = _resting(system)
        self.landing = _landing(system)
        lift = np.array([(p.rho * p.volume - p.mass) * p.g for p in system.point_masses])
        npoints, nbodies = len(system.point_masses), len(system.bodies)
        drag = np.zeros(npoints)
        body_drag = np.zeros((nbodies, 2, 3, 3))
        water = (np.zeros(2), np.zeros(0), np.zeros(0), np.zeros((0, 8)), np.zeros(1))  # still
        references = np.zeros((npoints + nbodies, 3))
        references[:npoints] = np.asarray(system.point_reference, float).reshape(-1, 3)
        for term in system.built_in_terms:
            if term.acts_on == "points":  # the free points' drag
                drag[term.point] += term.k
                water = term.step_water()
        for term in kinds["body drag"]:
            body_drag[term.body] += term.step_drag()
            references[npoints + term.body] = term.point
            water = term.step_water()
        if surface is not None:  # (its waves' elevation)
            water = surface.step_water()
        heading, heights, speeds, waves, fields = water
        self.points = (np.asarray(system.point_columns, np.int64).reshape(-1, 3),
                       lift.reshape(-1), drag.reshape(-1))
        # the water at the free points and the bodies with drag (a field of its own: read
        # only where a point or body has drag), a row each (the bodies' after the
        # points'): the reference positions (m), room for the water's velocity there, the
        # current's heading, profile (heights, speeds), the waves' components and the
        # packed fields (skmoor.sea.hydro.water_arrays)
        self.water = (references, np.zeros((npoints + nbodies, 6)),
                      np.ascontiguousarray(heading, float),
                      np.ascontiguousarray(np.stack([heights, speeds]), float),
                      np.ascontiguousarray(waves, float).reshape(-1, 8),
                      np.ascontiguousarray(fields, float))
        # the bodies' hydrostatics, static load, linear damping and drag matrices
        # 1/2 rho D(CdA) of force and moment (BodyDrag)
        self.bodies = (np.array(system.K_bodies).reshape(nbodies, 6, 6),
                       np.array(system.F_bodies0).reshape(nbodies, 6),
                       np.array([b.linear_damping for b in system.bodies]).reshape(nbodies, 6, 6),
                       body_drag)
        nf, nb, (nel, nloc) = system.nf, system.nb, lines.element_dofs.shape
        self.factors = (bordered.band_storage(width, nf), np.zeros((nf, nb)),
                        np.zeros((nb, nf)), np.zeros((nb, nb)), np.zeros(nf + 1, np.int64),
                        np.zeros(nb, np.int64))
        # the step's scratch (made once, not per step): the lines' u, ud, full residual and
        # element blocks, the body ends' J and S; R, B, a1, v1, M a, C v, the line search's
        # trial and correction, the predictors x_pred, v_pred, the old inertia, the iterate
        ends = len(system.dofs.body_flat)
        self.work = ((np.zeros(ndofs), np.zeros(ndofs), np.zeros(ndofs),
                      np.zeros((nel, nloc, nloc)), np.zeros((nel, nloc, nloc)),
                      np.zeros((ends, 6)), np.zeros((ends, 6)))
                     + tuple(np.zeros(n) for _ in range(12)))
        # Broyden's corrections and their squared norms (apart from work, which every call
        # of the residual carries)
        self.broyden = (np.zeros((BROYDEN_HISTORY, n)), np.zeros(BROYDEN_HISTORY))
        self.state = np.zeros(3)  # [factorized (0 / 1), its step h, factorizations made]
        # (the arrays' ids, the arrays as compiled code takes them)
        self._terms_cache = (None, None)
        self.callees = np.zeros(len(CALLEES), np.int64)  # (_find_callees)
        self._step_data = (None, None)  # (the cable's arrays, the step's data made with them)

    def _terms(self):
        """The kernels' current arrays (a strain law may be refreshed between steps)."""
        k = self.system.kernel
        elements = NO_P1 if isinstance(k, HermiteKernel) else (
            k.Xp, k.T, k.law, k.knots, k.coef, k.BA, k.h, k.weight, k.dofs_i, k.dofs_j)
        cable = (*elements, bool(self.system.damped), k.constant, self.system.weight)
        key = tuple(map(id, cable))
        if self._terms_cache[0] != key:
            arrays = _contiguous(cable)
            # kept while the kernel holds these very arrays, unless a conversion copied a
            # float one (a change in place would not show in the copy; index arrays are
            # the mesh's, never changed)
            same = all(a is b or a.dtype.kind in "iub" for a, b in zip(cable, arrays)
                       if isinstance(a, np.ndarray))
            self._terms_cache = (key if same else None, arrays)
        return self._terms_cache[1]

    def _data(self):
        """The model, scratch and factors as the compiled functions take them (one
        reference, :class:`_StepData`), made again when the cable's arrays change."""
        terms = self._terms()
        if self._step_data[0] is not terms:
            self._step_data = (terms, _step_data(
                self.topology, terms, self.points, self.bodies, self.prescribed_dofs,
                self.products, self.M, self.C, self.damped, self.width, self.forms, self.work,
                self.factors, self.callees, self.water))
        return self._step_data[1]

    def _data_type(self):
        """numba's type of :meth:`_data`, made without compiling :func:`_step_data` (it
        is the same for every model: one compiled step serves all)."""
        values = (self.topology, self._terms(), self.points, self.bodies,
                  self.prescribed_dofs, self.products, self.M, self.C, self.damped,
                  self.width, self.forms, self.work, self.factors, self.callees, self.water)
        return _StepDataType([(name, typeof(value)) for name, value in zip(FIELDS, values)])

    def _part_arguments(self, part, data):
        """(function, arguments) of the step's compile unit ``part`` (in :data:`PARTS`),
        its arguments of the types a run calls it with (``data``: a :class:`_StepData` or
        its numba type)."""
        work, factors, cable = self.work, self.factors, self._terms()
        y = np.zeros(self.system.n)
        inputs = (np.zeros((len(self.system.bodies), 6)), np.zeros(len(self.prescribed_dofs)),
                  np.zeros(len(self.prescribed_dofs)), 0.0)
        if part == "run":
            return _run, self._run_arguments(y, y, y, y, np.zeros(1), 0.1, None, None, data)[0]
        return {"balance": (_balance, (work[18], work[15], work[16], work[17], 0.1,
                                       self.scheme, data, inputs, True, self.state, work[8])),
                "residual": (_residual, (y, y, data, inputs, True, work[7])),
                "assemble": (_assemble, (work[18], work[10], data, 0.1, 0.1, 0.1)),
                "factor": (bordered.factor, (factors[0], self.width, *factors[1:])),
                "cable": (_cable, (*cable[:10], work[0], work[1], cable[10], work[2],
                                   work[3], work[4], 1.0)),  # (statics' overload too)
                "solve": (_solve, (work[8], factors, self.width)),
                "commit": (_commit_forms, (y, y, data, inputs))}[part]

    def compile(self, parts, data=None):
        """The step's compile units ``parts`` (names in :data:`PARTS`) compiled for the
        types a run calls them with (numba's disk cache keeps them; data: as
        :meth:`_part_arguments`, None: its type): {part: its address}."""
        data = self._data_type() if data is None else data
        addresses = {}
        for part in parts:
            function, arguments = self._part_arguments(part, data)
            if part == "run":
                function.compile(argument_types(arguments))
            else:
                addresses[part] = compiled_address(function, *arguments)
        return addresses

    def _find_callees(self, data):
        """``callees`` <- the addresses of :data:`CALLEES` compiled for the types they are
        called with (each called by address,
        :func:`~skmoor.fem.native_calls.call_compiled`: numba optimizes and emits each
        one's code once, not again in every caller), and :func:`_run` compiled. Found
        once per model type (the types follow from it); numba's disk cache keeps the code.
        Parts another process compiles (:func:`share_compile`) are read from the cache
        once it is done, the others compiled here meanwhile."""
        if self.callees[0]:
            return
        key = data._numba_type_
        if key not in _CALLEES:
            shared = _shared[1] if _shared is not None else ()
            addresses = self.compile([p for p in PARTS if p not in shared], data)
            addresses.update(self.compile(_wait_for_shared(), data))
            _CALLEES[key] = tuple(addresses[p] for p in CALLEES)
        self.callees[:] = _CALLEES[key]

    def _run_arguments(self, x, v, a, force_old, times, h, report, trend, data):
        """(:func:`_run`'s arguments for :meth:`steps`, (out, iterations, report, lines_out,
        ends_out): its outputs)."""
        system, count = self.system, len(times)
        nbodies, m = len(system.bodies), len(self.prescribed_dofs)
        pres_u, pres_v = np.zeros((count, m)), np.zeros((count, m))
        loads = np.zeros((count, nbodies, 6))
        driven = np.zeros((count, 0))  # M_fp a_p of each step (none: lumped P1 lines)
        pres_a = pres_u  # the prescribed ends' accelerations, where something needs them
        if system.dofs.has_prescribed:  # the time-only inputs of each step
            needed = system.driven_mass is not None or (
                self.held[2][0].size and report is not None and np.any(report))
            pres_u, pres_v, *pres_a = (np.ascontiguousarray(p, float) for p in
                                       system.prescribed_at(times, accelerations=needed))
            pres_a = pres_a[0] if pres_a else pres_u
            if system.driven_mass is not None:
                driven = np.ascontiguousarray((system.driven_mass @ pres_a.T).T, float)
        for k, load in enumerate(system.body_loads):
            if load is None or not getattr(load, "time_only", False):
                continue  # (a load of the state: a body load's kernel, called at each iterate)
            at_times = getattr(load, "at_times", None)  # all the times in one call
            if at_times is not None:
                loads[:, k] = at_times(times)
                continue
            block = system.dofs.blocks[k]
            for i, t1 in enumerate(times):
                loads[i, k] = load(t1, x[block], v[block])
        out = np.empty((4, count, len(x)))
        iterations = np.zeros(count, np.int64)
        report = np.zeros(count, np.int64) if report is None else np.array(report, np.int64)
        lines_out = np.empty((2, count, system.lines.ndofs))
        ends_out = np.empty((count, 2, len(system.fairlead_dofs), 3))
        arguments = (x, v, a, force_old, h, np.asarray(times, float), self.scheme, self.tol,
                     self.maxiter, data, loads, pres_u, pres_v, driven, pres_a, self.state,
                     out, iterations, report, self.report_dofs, self.resting, self.held,
                     lines_out, ends_out.reshape(count, -1),
                     np.zeros(len(x)) if trend is None else np.array(trend[0], float),
                     0.0 if trend is None else float(trend[1]), self.broyden, self.landing)
        return arguments, (out, iterations, report, lines_out, ends_out)

    def steps(self, x, v, a, force_old, times, h, report=None, trend=None):
        """Steps of h (s) to each of ``times`` in turn from level 0 (x, v, a, C v + R),
        ``trend`` the acceleration a step before and that step, (a_prev, h_prev) (None: none):
        (a list of ((x1, v1, a1, C v1 + R1, None), iterations, report), None), or with
        fewer steps than ``times`` and why Newton failed at the step after the last.
        report: a bool per step; at those steps the report is ((u, ud), (fairlead forces,
        anchor forces)) as ``System.full_state`` and ``System.end_forces`` give them (m,
        m/s; (nlines, 3) N each), computed here; None at the others."""
        count = len(times)
        if not count:
            return [], None
        data = self._data()
        self._find_callees(data)
        arguments, (out, iterations, report, lines_out, ends_out) = self._run_arguments(
            x, v, a, force_old, times, h, report, trend, data)
        floats = self.forms[3]
        for term, start in self.memories:  # the memories as the Python steps left them
            state = term.step_state()[0]
            floats[start:start + state.size] = state
        done, code = _run(*arguments)
        for term, start in self.memories:  # ... and as the compiled steps leave them
            state = term.step_state()[0]
            state[:] = floats[start:start + state.size]
        failure = (None if code == 1 else TO_PYTHON if code == -2 else
                   f"Newton did not converge in {self.maxiter} iterations" if code == 0
                   else "the Newton step is not finite")
        xs, vs, accelerations, forces = out
        us, uds = lines_out
        used, reported = iterations.tolist(), report.tolist()
        return [((xs[i], vs[i], accelerations[i], forces[i], None), used[i],
                 ((us[i], uds[i]), tuple(ends_out[i])) if reported[i] > 0 else None)
                for i in range(done)], failure


@njit(cache=True)
def _run(x, v, a, force, h, times, scheme, tol, maxiter, data, loads, pres_u, pres_v,
         driven, pres_a, state, out, iterations, report, report_dofs, resting,
         held, lines_out, ends_out, a_prev, h_prev, broyden, landing):
    """Steps of h from (x, v, a, force = C v + R) of the model ``data`` (a
    :class:`_StepData`), step i to times[i] (s) with the inputs loads[i], pres_u[i],
    pres_v[i], driven[i] (the prescribed ends' inertia on the free DOFs, N; empty rows:
    none): (x1, v1, a1, force1) of step i into out[:, i], its Newton
    iterations into iterations[i]; where report[i], the lines' full displacement and
    velocity into lines_out[:, i] and the end forces (minus the full residual at
    report_dofs, minus the held ends' inertia ``held`` with the prescribed ends'
    accelerations pres_a[i]) into ends_out[i] (report[i] set to 0 when a line is at the
    surface: the caller computes them). a_prev: the acceleration one step (h_prev s) before
    (x, v, a), for the first guess (h_prev 0: none; overwritten); broyden: the scratch of
    :func:`_broyden`; landing: the sea bed's (:func:`_landing`). Returns (the steps done,
    the failed step's code: 0 Newton did not converge, -1 a correction not finite, -2 a line
    at the surface, 1 none failed).

    Each step is ``dynamics.integrate``'s (its ``advance``), with the prescribed ends'
    inertia on the free DOFs: modified Newton from constant acceleration plus the trend of
    a_prev (:meth:`dynamics._Stepper.first_guess`), and when that fails Newton with the
    backtracking line search from constant velocity (one function with the loop over the
    steps: a calling level less for numba to compile)."""
    am, af, beta, gamma = scheme
    n = x.size
    Ma0, Ma1 = np.empty(n), np.empty(n)
    work, factors, mass = data.work, data.factors, data.products[0]
    width = data.width
    B, trial, dx = work[8], work[13], work[14]
    x_pred, v_pred, inertia_old, y = work[15], work[16], work[17], work[18]
    history, squares = broyden
    bed_columns, bed_points, bed_normal, bed_offset, bed_depth, bed_x, bed_y, bed_z = landing
    yes, no = n >= 0, n < 0  # plain bools: literal ones would compile _balance again
    balance_at, residual_at, solve_at = data.callees[0], data.callees[1], data.callees[5]
    memories, commit_at = data.forms[10], data.callees[6]  # kernels with a compiled commit
    for i in range(out.shape[1]):
        x1, v1, a1, force1 = out[0, i], out[1, i], out[2, i], out[3, i]
        inputs = (loads[i], pres_u[i], pres_v[i], times[i])
        _product(mass, a, Ma0)  # M a of the step's start (for inertia_old and force1)
        for j in range(n):  # (into work arrays: no allocation per step)
            x_pred[j] = x[j] + h * v[j] + h * h * (0.5 - beta) * a[j]
            v_pred[j] = v[j] + h * (1 - gamma) * a[j]
            inertia_old[j] = am * Ma0[j] + af * force[j]
        for j in range(driven.shape[1]):  # M_fp a_p at t1: a load given in time, at the
            inertia_old[j] += (1 - af) * driven[i, j]  # alpha_f level as R (constant)
        if state[1] != h:  # a factorization of another step's matrix: make a new one
            state[0] = 0.0
            state[1] = h
        # modified Newton on the kept factors, its corrections Broyden's (newton.broyden),
        # the factors made new when a correction shrinks slower than BROYDEN_CONTRACTION
        for j in range(n):
            y[j] = x[j] + h * v[j] + 0.5 * h * h * a[j]
            if h_prev > 0.0:  # the acceleration's trend over the last step (first_guess)
                y[j] += h**3 / (6.0 * h_prev) * (a[j] - a_prev[j])
        tangent = state[0] == 0.0
        previous = before = scale = np.inf
        used = maxiter  # iterations of the modified attempt (dynamics: maxiter on a failure)
        it = stalls = stored = 0  # it: the step's iterations once solved
        for k in range(1, maxiter + 1):
            code = call_compiled(_balance, balance_at, (
                y, x_pred, v_pred, inertia_old, h, scheme, data, inputs, tangent, state, B),
                SOLVED)
            if code == SURFACE:
                return i, -2
            if code == SINGULAR:
                used = k
                break
            if tangent:
                stored = 0
            size = call_compiled(_solve, solve_at, (B, factors, width), 0.0)
            if math.isfinite(size) and stored > 0:
                size = _broyden(B, history, squares, stored + 0)  # (+ 0: an int64 even
                # where stored is a literal 0, which would compile _broyden again)
                if size < 0.0:  # the secant update is degenerate: a new matrix at y
                    tangent, stored = True, 0
                    continue
            if not math.isfinite(size):
                used = k
                break
            landed = land_on_bed(y, B, size, bed_columns, bed_points, bed_normal, bed_offset,
                                 bed_depth, bed_x, bed_y, bed_z)  # (System.limit_correction)
            for j in range(n):
                y[j] += B[j]
            if k == 1:  # the step's change, to scale the tolerance
                scale = _distance(y, x)
            if not landed and (size <= tol * scale + 1e-12
                               or _error_below(size, previous, before, tol * scale)):
                _copy(x1, y)
                it = k
                break
            if tangent and k > 1 and size > STALL * previous:
                stalls += 1
                if stalls == 2:
                    used = k  # cycling across a kink (a node at the bed): the line search
                    break
            else:
                stalls = 0
            _copy(history[stored], B)
            squares[stored] = _dot(B, B)
            stored += 1
            tangent = (size > BROYDEN_CONTRACTION * previous or stored == BROYDEN_HISTORY
                       or landed)
            before, previous = previous, size
        if it == 0:  # Newton with the line search (dynamics._newton with full=True)
            for j in range(n):
                y[j] = x[j] + h * v[j]
            previous = np.inf
            code = call_compiled(_balance, balance_at, (
                y, x_pred, v_pred, inertia_old, h, scheme, data, inputs, yes, state, B), SOLVED)
            norm = _norm(B)
            for k in range(1, maxiter + 1):
                if code == SURFACE:
                    return i, -2
                if code == SINGULAR:
                    return i, -1
                _copy(dx, B)
                size = call_compiled(_solve, solve_at, (dx, factors, width), 0.0)
                if not math.isfinite(size):
                    return i, -1
                for j in range(n):
                    trial[j] = y[j] + dx[j]
                if k == 1:
                    scale = _distance(trial, x)
                if size <= tol * scale + 1e-12:
                    _copy(x1, trial)
                    it = used + k
                    break
                length = 1.0
                for halving in range(LINE_SEARCH + 1):
                    code = call_compiled(_balance, balance_at, (
                        trial, x_pred, v_pred, inertia_old, h, scheme, data, inputs, no, state,
                        B), SOLVED)
                    if code == SURFACE:
                        return i, -2
                    norm_try = _norm(B)
                    if (norm_try <= (1 - 1e-4 * length) * norm or not math.isfinite(norm_try)
                            or halving == LINE_SEARCH):
                        break
                    length *= 0.5
                    for j in range(n):
                        trial[j] = y[j] + length * dx[j]
                _copy(y, trial)
                slow = halving == LINE_SEARCH or size > CONTRACTION * previous
                previous = size
                if slow and math.isfinite(norm_try):  # a new matrix where the search stopped
                    code = call_compiled(_balance, balance_at, (
                        y, x_pred, v_pred, inertia_old, h, scheme, data, inputs, yes, state,
                        B), SOLVED)
                norm = norm_try
            if it == 0:
                return i, 0
        iterations[i] = it
        for j in range(n):  # the scheme's update, as dynamics.integrate's
            a1[j] = (x1[j] - (x[j] + h * v[j] + h * h * (0.5 - beta) * a[j])) / (beta * h * h)
            v1[j] = v[j] + h * (1 - gamma) * a[j] + gamma * h * a1[j]
        _product(mass, a1, Ma1)
        for j in range(n):
            force1[j] = -((1 - am) * Ma1[j] + am * Ma0[j] + af * force[j]) / (1 - af)
        if memories:  # the memories advance to the accepted step (by address: its code
            call_compiled(_commit_forms, commit_at, (x1, v1, data, inputs), None)  # not here)
        if report[i] > 0:  # (the residual called here, not in _report: a level less to compile)
            if call_compiled(_residual, residual_at, (x1, v1, data, inputs, no, work[7]),
                             True):
                _report(work, report_dofs, resting, lines_out[0, i], lines_out[1, i],
                        ends_out[i])
                _less_held_inertia(held, a1, pres_a[i], ends_out[i])
            else:  # a line at the surface: the caller computes them
                report[i] = 0
        _copy(a_prev, a)
        h_prev = h
        x, v, a, force = x1, v1, a1, force1
    return out.shape[1], 1


def _resting(system):
    """The held ends' bed support (``system.resting_plans``) for :func:`_report`: the end
    rows (side x lines + line), :meth:`~skmoor.sea.seabed.RestingSupport.arrays` of all
    held nodes and room for their supports; no rows without a bed or held ends."""
    nlines = len(system.fairlead_dofs)
    rows, parts = [], []
    for side, held, plan in system.resting_plans:
        rows += [side * nlines + k for k in held]
        parts.append(plan.arrays())
    if not parts:
        return (np.zeros(0, np.int64), np.zeros((0, 3), np.int64), np.zeros((0, 3)),
                np.zeros((0, 3)), np.zeros(0), np.zeros((0, 3)), np.zeros(0), np.zeros(0),
                np.zeros(0), np.zeros((0, 0)), np.zeros((0, 3)))
    joined = [np.ascontiguousarray(np.concatenate([p[k] for p in parts]),
                                   np.int64 if k == 0 else float) for k in range(6)]
    return (np.asarray(rows, np.int64), *joined,
            *(np.ascontiguousarray(a, float) for a in parts[0][6:]),
            np.zeros((len(rows), 3)))  # (room for the supports)


def _landing(system):
    """The sea bed's :func:`~skmoor.sea.seabed.land_on_bed` arrays
    (``System.bed_landing``); no nodes and depth 0 without a bed."""
    landing = system.bed_landing
    if landing is not None:
        return landing
    return (np.zeros((0, 3), np.int64), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), 0.0,
            np.zeros(0), np.zeros(0), np.zeros((0, 0)))


def _held_inertia(system):
    """The held (fixed, prescribed) ends' own inertia M_ef a_f + M_ep a_p that
    ``System.end_forces`` takes from their reactions, as the compiled report takes it:
    (the flat slots of the (2, nlines, 3) end forces it lands in, M[e] P0 and M[e, p] in
    CSR); no slots when the system has none."""
    if system.end_mass is None:
        return np.zeros(0, np.int64), _csr(None, (0, 0)), _csr(None, (0, 0))
    rows, on_free, on_driven = system.end_mass
    slots = ((rows[:, 0] * len(system.fairlead_dofs) + rows[:, 1])[:, None] * 3
             + np.arange(3)).ravel().astype(np.int64)
    shapes = ((len(slots), system.n), (len(slots), len(system.dofs.prescribed_flat)))
    return (slots, *(_csr(A, shape)
                     for A, shape in zip((on_free, on_driven), shapes)))


@njit(cache=True, no_cpython_wrapper=True)
def _less_held_inertia(held, a, driven, ends):
    """ends[slots] -= M[e] P0 a + M[e, p] driven (N) for held = (slots, M[e] P0, M[e, p])
    in CSR (a: reduced accelerations, driven: the prescribed ends', m/s2)."""
    slots, (free, free_columns, free_rows), (held_on, held_columns, held_rows) = held
    for j in range(slots.size):
        s = 0.0
        for k in range(free_rows[j], free_rows[j + 1]):
            s += free[k] * a[free_columns[k]]
        for k in range(held_rows[j], held_rows[j + 1]):
            s += held_on[k] * driven[held_columns[k]]
        ends[slots[j]] -= s


@njit(cache=True, no_cpython_wrapper=True)
def _report(work, report_dofs, resting, u, ud, ends):
    """The full line state (u, ud) and the end forces -R_full[report_dofs] (N) from the
    residual :func:`_residual` left in ``work``, plus the bed's support of held ends
    resting on it (``resting``, from :func:`_resting`)."""
    _copy(u, work[0])
    _copy(ud, work[1])
    for k in range(report_dofs.size):
        ends[k] = -work[2][report_dofs[k]]
    rows, dofs, points, weights, stiffness, normal, offset, x, y, heights, out = resting
    if rows.size:  # the bed's support of the held ends (seabed.RestingSupport's)
        resting_support(u, dofs, points, weights, stiffness, normal, offset, x, y, heights,
                        out)
        for i in range(rows.size):
            for c in range(3):
                ends[3 * rows[i] + c] += out[i, c]


@njit(cache=True, no_cpython_wrapper=True)
def _line_forms(forms, u, ud, t, tangent, full, blocks_K, blocks_C):
    """Adds the kernels called by address (:func:`_forms`) into the full residual and
    the element blocks."""
    functions, count, ints, floats, starts = forms[:5]
    for k in range(count):  # (each form's buffers from their starts: 8-byte items)
        call_form(functions[k], u.ctypes.data, ud.ctypes.data, u.size, t,
                  ints.ctypes.data + 8 * starts[k, 0], floats.ctypes.data + 8 * starts[k, 1],
                  full.ctypes.data, blocks_K.ctypes.data, blocks_C.ctypes.data,
                  1 if tangent else 0)


@njit(cache=True, no_cpython_wrapper=True)
def _user_loads(forms, x, v, t, tangent, columns, nf, R):
    """R -= F of the user point and body loads (their C functions, by address) and, with
    ``tangent``, their dF/dq, dF/dqdot into the forms' slopes for :func:`_assemble`."""
    loads_at, count, targets, slopes = forms[5:9]
    z, out = np.empty(13), np.empty(78)
    for k in range(count):
        n = 3 if targets[k, 0] == 0 else 6
        for c in range(n):
            g = columns[targets[k, 1], c] if n == 3 else nf + 6 * targets[k, 1] + c
            z[c] = x[g]
            z[n + c] = v[g]
        z[2 * n] = t
        call_load(loads_at[k], z.ctypes.data, out.ctypes.data)
        for c in range(n):
            g = columns[targets[k, 1], c] if n == 3 else nf + 6 * targets[k, 1] + c
            R[g] -= out[c]
            if tangent:
                for d in range(n):
                    slopes[k, 0, c, d] = out[n + n * c + d]
                    slopes[k, 1, c, d] = out[n + n * n + n * c + d]


@njit(cache=True, no_cpython_wrapper=True)
def _user_load_slopes(forms, columns, wK, wV, kv, ab, D):
    """-(wK dF/dq + wV dF/dqdot) of the user point and body loads into the Newton
    matrix: a point's into the band ``ab`` (kv: its diagonal row), a body's into D."""
    _, count, targets, slopes = forms[5:9]
    for k in range(count):
        n = 3 if targets[k, 0] == 0 else 6
        for c in range(n):
            for d in range(n):
                value = -(wK * slopes[k, 0, c, d] + wV * slopes[k, 1, c, d])
                if n == 3:
                    rc, rd = columns[targets[k, 1], c], columns[targets[k, 1], d]
                    ab[kv + rc - rd, rd] += value
                else:
                    D[6 * targets[k, 1] + c, 6 * targets[k, 1] + d] += value


@njit(cache=True, no_cpython_wrapper=True)
def _rotation_second_slopes(angles):
    """d2R / d angle_a d angle_b (3, 3, 3, 3) of R = Rz Ry Rx (rad)."""
    axes = np.zeros((3, 3, 3, 3))  # [axis, derivative order, 3, 3]
    for axis in range(3):
        c, s = math.cos(angles[axis]), math.sin(angles[axis])
        i, j = (axis + 1) % 3, (axis + 2) % 3
        axes[axis, 0, axis, axis] = 1.0
        for order, (cn, sn) in enumerate(((c, s), (-s, c), (-c, -s))):
            axes[axis, order, i, i] = cn
            axes[axis, order, j, j] = cn
            axes[axis, order, i, j] = -sn
            axes[axis, order, j, i] = sn
    out = np.zeros((3, 3, 3, 3))
    for a in range(3):
        for b in range(3):
            nx = (a == 0) + (b == 0)
            ny = (a == 1) + (b == 1)
            nz = (a == 2) + (b == 2)
            for i in range(3):  # Rz^(nz) Ry^(ny) Rx^(nx), written out (no BLAS on 3x3)
                for j in range(3):
                    s = 0.0
                    for k in range(3):
                        zy = 0.0
                        for m in range(3):
                            zy += axes[2, nz, i, m] * axes[1, ny, m, k]
                        s += zy * axes[0, nx, k, j]
                    out[a, b, i, j] = s
    return out


@njit(cache=True, no_cpython_wrapper=True)
def _body_ends(x, v, nf, end_body, end_dofs, r_local, J, u, ud):
    """The body ends' displacements q[:3] + R r - r and velocities into u, ud, their
    Jacobian d/dq into J (one body per 6 DOFs from nf; at least one end)."""
    last = end_body[0]  # ends come body by body
    first = nf + 6 * last
    rotation, slopes = rotation_and_slopes(x[first + 3: first + 6])
    for p in range(r_local.shape[0]):
        k = end_body[p]
        base = nf + 6 * k
        if k != last:
            rotation, slopes = rotation_and_slopes(x[base + 3: base + 6])
            last = k
        for c in range(3):
            g = end_dofs[p, c]
            moved = x[base + c] - r_local[p, c]
            for j in range(6):
                J[3 * p + c, j] = 0.0
            J[3 * p + c, c] = 1.0
            for l in range(3):
                moved += rotation[c, l] * r_local[p, l]
                for a in range(3):
                    J[3 * p + c, 3 + a] += slopes[a, c, l] * r_local[p, l]
            u[g] = moved
            s = 0.0
            for j in range(6):
                s += J[3 * p + c, j] * v[base + j]
            ud[g] = s


# (over 100 lines: the residual of every lowered kind in one compiled pass over the state)
@njit(cache=True, no_cpython_wrapper=True, inline="always")
def _expand(x, v, topology, prescribed_dofs, pres_u, pres_v, u, ud, J):
    """The lines' full displacement and velocity at (x, v) with the step's prescribed
    ones into u, ud (and the body ends' J into J). Inlined where it is called: a call
    counts references to every array it is passed, a cost per residual."""
    position, _, end_body, end_dofs, r_local, _, nf = topology[:7]
    u[:] = 0.0
    ud[:] = 0.0
    for g in range(u.size):
        if position[g] >= 0:
            u[g] = x[position[g]]
            ud[g] = v[position[g]]
    if r_local.shape[0]:
        _body_ends(x, v, nf, end_body, end_dofs, r_local, J, u, ud)
    for m in range(prescribed_dofs.size):
        u[prescribed_dofs[m]] = pres_u[m]
        ud[prescribed_dofs[m]] = pres_v[m]


@njit(cache=True, no_cpython_wrapper=True)
def _commit_forms(x, v, data, inputs):
    """The kernels with a memory of the past (their ``step_commit``, by address) advance
    it to the accepted step (x, v) at the inputs' time."""
    work = data.work
    u, ud = work[0], work[1]
    _expand(x, v, data.topology, data.prescribed, inputs[1], inputs[2], u, ud, work[5])
    functions, count, ints, floats, starts = data.forms[:5]
    commits = data.forms[9]
    for k in range(count):
        if commits[k]:
            call_form(commits[k], u.ctypes.data, ud.ctypes.data, u.size, inputs[3],
                      ints.ctypes.data + 8 * starts[k, 0], floats.ctypes.data + 8 * starts[k, 1],
                      work[2].ctypes.data, work[3].ctypes.data, work[4].ctypes.data, 0)


@njit(cache=True, inline="always")
def _water_at(dx, dy, dz, t, at_points, row):
    """Whether the water moves; if so its velocity (current, waves and fields, as
    ``Sea.velocity``) at time t (s) at the reference position of ``row`` of the step
    data's ``water`` (``at_points``: a free point's, or a body's after them) displaced by
    (dx, dy, dz) (m), into at_points[1][row, :3]."""
    reference, water, heading, profile, waves, fields = at_points
    if profile.shape[1] == 0 and waves.shape[0] == 0 and fields[0] == 0.0:
        return False
    water_kinematics(reference[row, 0] + dx, reference[row, 1] + dy, reference[row, 2] + dz,
                     t, heading, profile[0], profile[1], waves, fields, water[row])
    return True


@njit(cache=True, no_cpython_wrapper=True)
def _body_drag(x, v, t, data, k, R):
    """R -= body k's quadratic drag (:class:`~skmoor.sea.hydro.BodyDrag` on a small body):
    the force |v_r| D_F v_r, v_r = u_w - qdot[:3] with the water at the displaced reference
    point (left in the step data's water row for the tangent), and the moment
    |w_r| D_M w_r, w_r = -qdot[3:]."""
    drag, water, nf = data.bodies[3][k], data.water, data.topology[6]
    base, row = nf + 6 * k, data.points[0].shape[0] + k
    _water_at(x[base], x[base + 1], x[base + 2], t, water, row)
    ux, uy, uz = water[1][row, 0], water[1][row, 1], water[1][row, 2]  # (0: still water)
    for part in range(2):  # the force on the water's velocity, the moment on none
        at = base + 3 * part
        wx = (ux if part == 0 else 0.0) - v[at]
        wy = (uy if part == 0 else 0.0) - v[at + 1]
        wz = (uz if part == 0 else 0.0) - v[at + 2]
        speed = math.sqrt(wx * wx + wy * wy + wz * wz)
        for i in range(3):
            R[at + i] -= speed * (drag[part, i, 0] * wx + drag[part, i, 1] * wy
                                  + drag[part, i, 2] * wz)


@njit(cache=True, no_cpython_wrapper=True)
def _residual(x, v, data, inputs, tangent, R):
    """R(x, v, t) reduced (N, N m) into R, with the inputs (body loads, prescribed
    displacements and velocities, the time t) of the step; with ``tangent`` the element
    blocks d/du, d/dv in
    work[3], work[4] and the body ends' J, d(J qdot)/dq in work[5], work[6]; the full
    cable residual in work[2] (``coupling.System.residual``, one body per 6 DOFs). False
    (nothing computed) when a node of a line with a SurfaceTerm comes within half a
    diameter of the surface: the step is then Python's."""
    topology, cable, points, bodies = data.topology, data.cable, data.points, data.bodies
    forms, work = data.forms, data.work
    loads, pres_u, pres_v, t = inputs
    position, end_row, end_body, end_dofs, r_local, _, nf = topology[:7]
    u, ud, full, Ke, Ce, J, S = work[0], work[1], work[2], work[3], work[4], work[5], work[6]
    _expand(x, v, topology, data.prescribed, pres_u, pres_v, u, ud, J)
    nends = r_local.shape[0]
    surface_dofs, surface_nodes, surface_reach = topology[7], topology[8], topology[9]
    if surface_dofs.shape[0]:  # SurfaceTerm is zero while the lines stay this deep under
        waves, fields = data.water[4], data.water[5]  # the surface (its waves' and fields'
        for i in range(surface_dofs.shape[0]):  # elevation at the displaced nodes)
            height = surface_nodes[i, 2] + u[surface_dofs[i, 2]]
            if waves.shape[0] or fields[0] > 0.0:
                height -= wave_elevation(surface_nodes[i, 0] + u[surface_dofs[i, 0]],
                                         surface_nodes[i, 1] + u[surface_dofs[i, 1]], t, waves,
                                         fields)
            if height > surface_reach:
                return False
    Xp, T, law, knots, coef, BA, h, weight, dofs_i, dofs_j, damped, constant, gravity = cable
    for g in range(full.size):
        full[g] = constant[g] - gravity[g]
    if tangent:
        Ke[:] = 0.0
        Ce[:] = 0.0
    blocks_K = Ke if tangent else Ke[:0]  # no blocks: a view (the residual allocates nothing)
    blocks_C = Ce if tangent else Ce[:0]
    # (bending lines: no P1 element here; their loop is called as a form's, below)
    call_compiled(_cable, data.callees[4], (Xp, T, law, knots, coef, BA, h, weight, dofs_i,
                                            dofs_j, u, ud, damped, full, blocks_K, blocks_C, 1.0),
                  None)
    if forms[1]:  # the LineForms called by address (Morison, the bed, bending, the users')
        _line_forms(forms, u, ud, t, tangent, full, blocks_K, blocks_C)
    R[:] = 0.0
    for g in range(full.size):
        if position[g] >= 0:
            R[position[g]] += full[g]
        elif end_row[g] >= 0:
            p = end_row[g]
            k = end_body[p // 3]
            for j in range(6):
                R[nf + 6 * k + j] += J[p, j] * full[g]
    columns, lift, drag = points
    for p in range(columns.shape[0]):
        R[columns[p, 2]] -= lift[p]
        if drag[p] > 0.0:
            at_points = data.water
            if _water_at(x[columns[p, 0]], x[columns[p, 1]], x[columns[p, 2]], t, at_points,
                         p):  # moving water: -k |w| w, w = U - v
                water = at_points[1]
                speed = 0.0
                for c in range(3):
                    speed += (water[p, c] - v[columns[p, c]]) ** 2
                speed = math.sqrt(speed)
                for c in range(3):
                    R[columns[p, c]] -= drag[p] * speed * (water[p, c] - v[columns[p, c]])
                continue
            speed = 0.0
            for c in range(3):
                speed += v[columns[p, c]] ** 2
            speed = math.sqrt(speed)
            for c in range(3):
                R[columns[p, c]] += drag[p] * speed * v[columns[p, c]]
    K_body, F0, D_body, body_drag = bodies
    for k in range(K_body.shape[0]):
        base = nf + 6 * k
        for i in range(6):
            s = -F0[k, i] - loads[k, i]
            for j in range(6):
                s += K_body[k, i, j] * x[base + j] + D_body[k, i, j] * v[base + j]
            R[base + i] += s
        if body_drag[k, 0, 0, 0] + body_drag[k, 0, 1, 1] + body_drag[k, 0, 2, 2] + \
                body_drag[k, 1, 0, 0] + body_drag[k, 1, 1, 1] + body_drag[k, 1, 2, 2] > 0.0:
            _body_drag(x, v, t, data, k, R)  # (D(CdA) positive semi-definite: a trace)
    if forms[6]:  # the user point and body loads' generated kernels
        _user_loads(forms, x, v, t, tangent, columns, nf, R)
    if tangent and nends:
        for p in range(nends):
            k = end_body[p]
            base = nf + 6 * k
            d2 = _rotation_second_slopes(x[base + 3: base + 6])
            for c in range(3):
                for b in range(3):
                    s = 0.0
                    for a in range(3):
                        for l in range(3):
                            s += v[base + 3 + a] * d2[a, b, c, l] * r_local[p, l]
                    S[3 * p + c, 3 + b] = s
                    S[3 * p + c, b] = 0.0
    return True


@njit(cache=True, no_cpython_wrapper=True)
def _product(matrix, x, out):
    """out = A x for A = (data, indices, indptr) in CSR."""
    data, indices, indptr = matrix
    for i in range(out.size):
        s = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            s += data[k] * x[indices[k]]
        out[i] = s


@njit(cache=True, no_cpython_wrapper=True)
def _combine(out, a, A, b, B):
    """out = a A + b B (2-D arrays of one shape)."""
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = a * A[i, j] + b * B[i, j]


@njit(cache=True, no_cpython_wrapper=True)
def _assemble(x, v, data, cx, cv, af):
    """The Newton matrix cx M + (1 - af)(cv (C + Kv) + K) into the factor arrays, from
    the blocks and Jacobians :func:`_residual` left in ``work``."""
    work, factors = data.work, data.factors
    topology, points, bodies, forms = data.topology, data.points, data.bodies, data.forms
    M, C, damped, width = data.M, data.C, data.damped, data.width
    position, end_row, end_body, end_dofs, r_local, edofs, nf = topology[:7]
    full, Ke, Ce, J, S = work[2], work[3], work[4], work[5], work[6]
    ab, E, F, D = factors[0], factors[1], factors[2], factors[3]
    abM, EM, FM, DM = M
    abC, EC, FC, DC = C
    wC = (1 - af) * cv if damped else 0.0
    _combine(ab.T, cx, abM.T, wC, abC.T)  # (column-major band storage: its rows in order)
    _combine(E, cx, EM, wC, EC)
    _combine(F, cx, FM, wC, FC)
    _combine(D, cx, DM, wC, DC)
    kv = 2 * width
    wK, wV = 1.0 - af, (1.0 - af) * cv
    nloc = edofs.shape[1]  # an element's DOFs: 6 (P1), 12 (Hermite)
    rows, ends_at = np.empty(nloc, np.int64), np.empty(nloc, np.int64)
    for e in range(edofs.shape[0]):
        free = True  # every DOF of the element a free one: the band alone
        for a in range(nloc):
            rows[a] = position[edofs[e, a]]
            ends_at[a] = end_row[edofs[e, a]]
            free = free and rows[a] >= 0
        if free:
            for b in range(nloc):
                rb = rows[b]
                for a in range(nloc):
                    ab[kv + rows[a] - rb, rb] += wK * Ke[e, a, b] + wV * Ce[e, a, b]
            continue
        for a in range(nloc):
            ra, pa = rows[a], ends_at[a]
            if ra < 0 and pa < 0:
                continue
            for b in range(nloc):
                rb, pb = rows[b], ends_at[b]
                if rb < 0 and pb < 0:
                    continue
                kab = wK * Ke[e, a, b] + wV * Ce[e, a, b]
                if rb >= 0:
                    if ra >= 0:
                        ab[kv + ra - rb, rb] += kab
                    else:
                        ka = 6 * end_body[pa // 3]
                        for i in range(6):
                            F[ka + i, rb] += J[pa, i] * kab
                    continue
                kb = 6 * end_body[pb // 3]
                slope = wK * Ce[e, a, b]
                for j in range(6):
                    value = kab * J[pb, j] + slope * S[pb, j]
                    if ra >= 0:
                        E[ra, kb + j] += value
                    else:
                        ka = 6 * end_body[pa // 3]
                        for i in range(6):
                            D[ka + i, kb + j] += J[pa, i] * value
    # the bodies: sum f . d2p/dq2 of their line ends, hydrostatics, linear damping
    K_body, _, D_body, body_drag = bodies
    nrow = points[0].shape[0]
    for k in range(K_body.shape[0]):
        for i in range(6):
            for j in range(6):
                D[6 * k + i, 6 * k + j] += wK * K_body[k, i, j] + wV * D_body[k, i, j]
        # the drag's d/dqdot: D (|w| I + w w^T / |w|) per part, w the relative velocity
        # the residual left (v_r with the water in its row, w_r); none with respect to q
        water = data.water[1]
        for part in range(2):
            at = nf + 6 * k + 3 * part
            wx = (water[nrow + k, 0] if part == 0 else 0.0) - v[at]
            wy = (water[nrow + k, 1] if part == 0 else 0.0) - v[at + 1]
            wz = (water[nrow + k, 2] if part == 0 else 0.0) - v[at + 2]
            speed = math.sqrt(wx * wx + wy * wy + wz * wz)
            if speed == 0.0:
                continue
            for i in range(3):
                dw = (body_drag[k, part, i, 0] * wx + body_drag[k, part, i, 1] * wy
                      + body_drag[k, part, i, 2] * wz) / speed
                for j, wj in enumerate((wx, wy, wz)):
                    value = speed * body_drag[k, part, i, j] + dw * wj
                    D[6 * k + 3 * part + i, 6 * k + 3 * part + j] += wV * value
    for p in range(r_local.shape[0]):
        k = end_body[p]
        base = nf + 6 * k
        d2 = _rotation_second_slopes(x[base + 3: base + 6])
        f = np.zeros(3)
        for c in range(3):
            f[c] = full[end_dofs[p, c]]
        for a in range(3):
            for b in range(3):
                s = 0.0
                for c in range(3):
                    for l in range(3):
                        s += d2[a, b, c, l] * f[c] * r_local[p, l]
                D[6 * k + 3 + a, 6 * k + 3 + b] += wK * s
    if forms[6]:  # the user point and body loads: -(dF/dq, dF/dqdot)
        _user_load_slopes(forms, points[0], wK, wV, kv, ab, D)
    columns, _, drag = points
    for p in range(columns.shape[0]):
        if drag[p] > 0.0:
            water = data.water[1]  # the water's velocity as the residual left it (or zero)
            speed = 0.0
            for c in range(3):
                speed += (water[p, c] - v[columns[p, c]]) ** 2
            speed = math.sqrt(speed)
            if speed > 0.0:
                for c in range(3):
                    wc = water[p, c] - v[columns[p, c]]
                    for d in range(3):
                        wd = water[p, d] - v[columns[p, d]]
                        value = drag[p] * (wc * wd / speed + (speed if c == d else 0.0))
                        rc, rd = columns[p, c], columns[p, d]
                        ab[kv + rc - rd, rd] += wV * value


@njit(cache=True, no_cpython_wrapper=True)
def _balance(y, x_pred, v_pred, inertia_old, h, scheme, data, inputs, tangent, state, B):
    """-(the alpha-level balance at x1 = y) into B (``dynamics.integrate``'s balance), and
    with ``tangent`` its Newton matrix into ``factors``, factorized. Returns SOLVED,
    SINGULAR (the matrix) or SURFACE (a line reached the free surface: Python's step)."""
    am, af, beta, gamma = scheme
    work, factors = data.work, data.factors
    products, damped, width = data.products, data.damped, data.width
    R, a1, v1, Ma, Cv = work[7], work[9], work[10], work[11], work[12]
    for i in range(y.size):
        a1[i] = (y[i] - x_pred[i]) / (beta * h * h)
        v1[i] = v_pred[i] + gamma * h * a1[i]
    residual_at, assemble_at, factor_at = data.callees[1], data.callees[2], data.callees[3]
    if not call_compiled(_residual, residual_at, (y, v1, data, inputs, tangent, R), True):
        return SURFACE
    _product(products[0], a1, Ma)
    if damped:
        _product(products[1], v1, Cv)
    for i in range(y.size):
        B[i] = -((1 - am) * Ma[i] + (1 - af) * (R[i] + (Cv[i] if damped else 0.0))
                 + inertia_old[i])
    if not tangent:
        return SOLVED
    call_compiled(_assemble, assemble_at, (y, v1, data, (1 - am) / (beta * h * h),
                                           gamma / (beta * h), af), None)
    ab, E, F, D, piv_band, piv_schur = factors
    state[2] += 1.0
    if not call_compiled(bordered.factor, factor_at, (ab, width, E, F, D, piv_band, piv_schur),
                         True):
        state[0] = 0.0
        return SINGULAR
    state[0] = 1.0
    return SOLVED


@njit(cache=True, no_cpython_wrapper=True)
def _solve(B, factors, width):
    """B <- A^-1 B with the factorized Newton matrix: the largest entry, inf when one is
    not finite."""
    ab, E, F, D, piv_band, piv_schur = factors
    bordered.solve(ab, width, E, F, D, piv_band, piv_schur, B)
    size = 0.0
    for i in range(B.size):
        if not math.isfinite(B[i]):
            return np.inf
        size = max(size, abs(B[i]))
    return size


@njit(cache=True, no_cpython_wrapper=True)
def _broyden(dx, history, squares, stored):
    """dx <- Broyden's correction from the kept matrix's one (:func:`newton.broyden`) with
    the ``stored`` corrections made on that matrix; returns max |dx| (inf if not finite),
    -1 when the update would scale the correction by more than BROYDEN_SCALING either way."""
    for j in range(stored - 1):
        c = _dot(history[j], dx) / squares[j]
        for i in range(dx.size):
            dx[i] += c * history[j + 1, i]
    scale = 1.0 / (1.0 - _dot(history[stored - 1], dx) / squares[stored - 1])
    if not 1.0 / BROYDEN_SCALING <= abs(scale) <= BROYDEN_SCALING:
        return -1.0
    size = 0.0
    for i in range(dx.size):
        dx[i] *= scale
        size = max(size, abs(dx[i]))
    return size if math.isfinite(size) else np.inf


_error_below = njit(cache=True, no_cpython_wrapper=True)(newton.error_below)


@njit(cache=True, no_cpython_wrapper=True)
def _copy(out, a):
    """out[:] = a, for arrays of one size (without the slice's shape check and its message)."""
    for i in range(out.size):
        out[i] = a[i]


@njit(cache=True, no_cpython_wrapper=True)
def _dot(a, b):
    s = 0.0
    for i in range(a.size):
        s += a[i] * b[i]
    return s


@njit(cache=True, no_cpython_wrapper=True)
def _distance(a, b):
    """max |a - b|."""
    out = 0.0
    for i in range(a.size):
        out = max(out, abs(a[i] - b[i]))
    return out


@njit(cache=True, no_cpython_wrapper=True)
def _norm(b):
    return math.sqrt(_dot(b, b))
