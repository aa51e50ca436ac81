"""A constitutive law written by the user: the tension of a line type as a function of
its strain and strain rate, N(e, de/dt).

The law is one function written with :mod:`skmoor.fem.ops` (or plain arithmetic), so that
JAX can trace it; skmoor derives what the cable needs from it:

- the static state: the catenary and the reference strain ``e_ref`` of each point from
  N(e, 0) (the law inverted at the reference tension);
- the time loop: the axial force of Eq. 11 with the user's tension, written as a line
  form (:func:`law_residual`) whose tangents come from automatic differentiation and whose
  kernel is generated (:mod:`skmoor.fem.form_compiler`), so that it runs in the compiled
  time step like a built-in law;
- the reported tension (``LineSet.element_tension``).

Which strain the law sees: ``e`` is the engineering strain of the UNSTRETCHED line
(stretched length over unstretched length, minus 1), as the built-in laws and MoorDyn
use it, so a threshold written in the law (a kink at 1 % strain) is at 1 % from the
unstretched line, not from the static state: at a point of reference (static) stretch
1 + e_ref stretched further by lambda = sqrt(1 + 2 eps) (eps the strain of Eq. 3 from the
reference state; lambda = |X' + u'| where |X'| = 1), e = (1 + e_ref) lambda - 1, and
de/dt = (1 + e_ref) (r' . udot') / lambda. A line type's BA (internal damping) still
adds BA de/dt in the cable kernel; a law with its own rate term can leave BA at 0.

A law of the reference state (``reference=True``: the paper's Eq. 6, a tension added to
the reference's) reads the strain and tension of the state the line was built in at each
point; a built-in static law (``static``) makes that state. With ``reference='static'``
it reads each element's static state instead (polyester's dynamic stiffness about its
mean tension): the statics run the static law, and the law acts about their solution.

A law with a memory (a permanent stretch, the largest strain seen, a spring in series
with a dashpot) is N(e, de/dt, state) with either its update state_new = update(e, de/dt,
state, dt), explicit: within a step the tension sees the last accepted state; or its rate
d(state)/dt = state_rate(e, de/dt, state), which skmoor integrates within the step by the
trapezoidal rule linearized at the last accepted state s_n (its rate sdot_n and the slopes
J = d rate/d state and N_z = dN/d state frozen there; h = t - t_n):

    (I - h/2 J) sdot = rate(e, de/dt, s_n) + h/2 J sdot_n,   ds = h/2 (sdot_n + sdot)
    N = N(e, de/dt, s_n) + N_z . ds

(:class:`~skmoor.lines.creep.CreepTerm`'s scheme for MoorDyn's creep laws, so that they can
be written this way); or both: the rate integrated over the step, then the update applied
to the result (a part of the state that only the update moves has a rate of 0, such as
Syrope's highest mean tension, raised when the tension passes it). The state is kept at
each quadrature point of the law's lines, starts at the given values (for a law of a
reference state, a function of that state's strain and tension) and advances after each
accepted time step (generated and compiled like the tension). Statics use the initial
state.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..fem import ops
from ..fem.native_calls import call_load
from ..fem.ops import d_ds, dot
from ..fem.terms import HAS_JAX, LineForm
from .laws import Law

__all__ = ["UserLaw", "law_terms"]


@dataclass(frozen=True, eq=False)
class UserLaw(Law):
    """A law from its tension function ``tension(strain, rate)`` (N; strain e -, rate
    de/dt 1/s, arrays), written with :mod:`skmoor.fem.ops`. The static law N(e, 0) must
    start at 0 N and increase over [0, max_strain]; the catenary uses it sampled at
    ``samples`` strains there (beyond: the last slope). tension_only: a slack cable
    carries no compression (N < 0 is cut to 0). state and update and/or state_rate: a
    memory (see the module docstring; for a law of a reference state the initial state
    may be a function ``state(e_ref, T_ref)`` of the reference's strain and tension; with
    ``balanced=False`` it need not balance the reference's tension, as MoorDyn's start of
    a creep state, and the line then moves from its static state at t = 0). reference:
    the function reads a reference state's strain and tension at each point,
    ``tension(strain, rate[, state], (e_ref, T_ref))``: True or 'line', the state the line
    is built in; 'static', each element's static state (as
    :class:`~skmoor.lines.laws.StaticDynamic`: cable lines). ``static`` (a built-in law)
    makes that state, the catenary and the statics with it; at its reference the law
    must give the reference's tension."""

    function: object = None
    label: str = "user law"
    max_strain: float = 0.3
    samples: int = 301
    initial_state: tuple = ()
    update: object = None
    state_rate: object = None
    start: object = None
    balanced: bool = True
    reference: str = ""
    static: Law | None = None
    name = "user"

    def __init__(self, tension, *, name=None, tension_only=True, max_strain=0.3,
                 samples=301, state=None, update=None, state_rate=None, reference=False,
                 static=None, balanced=True):
        label = name or getattr(tension, "__name__", "user law")
        if not callable(tension):
            raise ValueError(f"UserLaw {label} tension: need a function tension(strain, "
                             "rate) -> N (with a state: tension(strain, rate, state))")
        reference = {False: "", None: "", True: "line"}.get(reference, reference)
        if reference not in ("", "line", "static"):
            raise ValueError(f"UserLaw {label} reference: True or 'line' (the state the "
                             "line is built in) or 'static' (its static state), got "
                             f"{reference!r}")
        if reference and not (isinstance(static, Law) and not isinstance(static, UserLaw)):
            raise ValueError(f"UserLaw {label} static: a law of the reference state needs "
                             "the built-in law that makes that state (such as "
                             f"skmoor.Engineering()), got {static!r}")
        if callable(state) and not reference:
            raise ValueError(f"UserLaw {label} state: initial values as a function of the "
                             "reference's (strain, tension) need a law of a reference state "
                             "(reference=True or 'static'); give numbers")
        if not balanced and not callable(state):
            raise ValueError(f"UserLaw {label} balanced: False is for an initial state given "
                             "as a function state(e_ref, T_ref) of the reference")
        if not (np.isfinite(max_strain) and max_strain > 0):
            raise ValueError(f"UserLaw {label} max_strain: must be a strain > 0, got "
                             f"{max_strain!r}")
        if int(samples) < 2:
            raise ValueError(f"UserLaw {label} samples: need at least 2, got {samples!r}")
        initial, start = _initial_state(label, state, update, state_rate, static)
        for key, value in dict(function=tension, label=label, tension_only=bool(tension_only),
                               max_strain=float(max_strain), samples=int(samples),
                               initial_state=initial, update=update, state_rate=state_rate,
                               start=start, balanced=bool(balanced), reference=reference,
                               static=static if reference else None).items():
            object.__setattr__(self, key, value)
        e = np.linspace(0.0, self.max_strain, self.samples)
        signature = "tension(strain, rate" + (", state" if initial else "") + (
            ", reference" if reference else "") + ")"
        try:
            with np.errstate(all="ignore"):  # a NaN or inf is named below
                T = np.asarray(self._evaluate(e, np.zeros_like(e)), float) * np.ones_like(e)
        except Exception as error:
            raise ValueError(f"UserLaw {label}: {signature} failed on arrays of "
                             f"strains: {error}") from error
        if initial:
            _check_memory(self, e)
        if not np.all(np.isfinite(T)):
            raise ValueError(f"UserLaw {label}: tension(strain, 0) is not finite at strain "
                             f"{e[~np.isfinite(T)][0]:g}")
        if self.reference and self.start is None:  # (a state of the reference's: on its
            self.check_reference()                  # lines, where their EA is known)
        if not self.reference and abs(T[0]) > 1e-9 * max(np.max(np.abs(T)), 1.0):
            raise ValueError(f"UserLaw {label}: the tension at zero strain must be 0 N, got "
                             f"{T[0]:g}")
        bad = np.nonzero(np.diff(T) <= 0)[0]
        if bad.size and not self.reference:  # (a static law of its own: not sampled here)
            raise ValueError(f"UserLaw {label}: the static tension must increase with the "
                             f"strain; it does not between strains {e[bad[0]]:g} and "
                             f"{e[bad[0] + 1]:g}")
        object.__setattr__(self, "_table", (e, T))

    def __repr__(self):
        return f"UserLaw({self.label})"

    def check_reference(self, EA=1.0, where=""):
        """Raise ValueError unless the law at its own reference (strain e, the static
        law's tension there at the line type's EA, N) gives that tension."""
        e = np.linspace(0.0, self.max_strain, self.samples)
        reference = (e, np.asarray(self.static.static_tension(e, EA), float))
        with np.errstate(all="ignore"):
            T = np.asarray(self._evaluate(e, np.zeros_like(e), reference=reference),
                           float) * np.ones_like(e)
        made = reference[1]
        off = ~(np.abs(T - made) <= 1e-9 * max(np.max(np.abs(made)), 1.0))
        if off.any():
            raise ValueError(
                f"UserLaw {self.label}{where}: tension(strain, rate"
                + (", state" if self.initial_state else "") + ", reference) at the reference "
                "(strain e, tension the static law's at e"
                + (", the initial state there" if self.initial_state else "") + ") must be "
                f"that tension; it is {T[off][0]:g} N, not {made[off][0]:g} N, at strain "
                f"{e[off][0]:g} (EA {EA:g} N)")

    def _evaluate(self, e, rate, state=None, reference=None, function=None):
        """The user's tension (N; or ``function``'s values, such as the state's rate) at
        strains e, rates de/dt, the state (its initial values where None) and, for a law
        of the reference state, that state's (strain, tension) (None: e itself and the
        static law's tension there at EA 1 N)."""
        if self.reference and reference is None:
            reference = self._own_reference(e)
        arguments = [e, rate]
        if self.initial_state:
            if state is None:
                state = self.start_state(e, reference)
            arguments.append(tuple(state))
        if self.reference:
            arguments.append(tuple(reference))
        return (function or self.function)(*arguments)

    def _own_reference(self, e):
        """A reference state at the strains e: (e, the static law's tension there at EA
        1 N)."""
        return e, self.static.static_tension(e, 1.0)

    def start_state(self, e, reference=None):
        """The initial state (a tuple of arrays shaped as the strains e): the given
        values, or for a law of a reference state its function of that state's (strain,
        tension) (None: :meth:`_own_reference`)."""
        if self.start is None:
            return tuple(value + 0.0 * e for value in self.initial_state)
        return tuple(value + 0.0 * e for value in self.start(*(reference or
                                                              self._own_reference(e))))

    # --- statics (a law of the reference state: its static law's)
    def static_pieces(self, EA=None):
        if self.reference:
            return self.static.static_pieces(EA)
        e, T = self._table
        s = np.diff(T) / np.diff(e)
        return T[:-1], e[:-1] - T[:-1] / s, 1.0 / s

    def nominal_EA(self, EA=None):
        """The secant at max_strain, N (a law of the reference state: its static law's)."""
        if self.reference:
            return self.static.nominal_EA(EA)
        e, T = self._table
        return float(T[-1] / e[-1])

    def static_tension(self, e, EA=None):
        if self.reference:
            return self.static.static_tension(e, EA)
        e = np.asarray(e, float)
        T = np.asarray(self._evaluate(e, np.zeros_like(e)), float) * np.ones_like(e)
        return np.maximum(T, 0.0) if self.tension_only else T

    def static_strain(self, T, EA=None):
        """The strain e >= 0 with N(e, 0) = T: the sampled table's strain refined by
        safeguarded Newton steps on the law itself."""
        if self.reference:
            return self.static.static_strain(T, EA)
        T = np.asarray(T, float)
        e = super().static_strain(T)
        low, high = np.zeros_like(e), np.maximum(2.0 * e, self.max_strain)
        for _ in range(60):
            f = self.static_tension(e) - T
            low, high = np.where(f < 0, e, low), np.where(f > 0, e, high)
            step = 1e-7 * np.maximum(e, 1e-3)
            slope = (self.static_tension(e + step) - self.static_tension(e - step)) / (2 * step)
            trial = e - f / np.where(slope > 0, slope, np.inf)
            e_new = np.where((trial > low) & (trial < high), trial, 0.5 * (low + high))
            if np.all(np.abs(e_new - e) <= 1e-15 * np.maximum(e, 1.0)):
                return e_new
            e = e_new
        return e

    def tension(self, e, EA=None):
        return self.static_tension(e, EA)

    def slope(self, e, EA=None):
        e = np.asarray(e, float)
        step = 1e-7 * np.maximum(np.abs(e), 1e-3)
        return (self.tension(e + step, EA) - self.tension(e - step, EA)) / (2 * step)

    # --- dynamics: the cable kernel skips this law's elements (law_terms carries their
    # axial force); its parameters keep the reference tension T along the line for the
    # kernel's reference part and its reported tension (law_tension adds N - T)
    def parameters(self, EA, T, e_ref, static=False):
        if static and self.reference == "static":  # statics: the kernel, its static law
            p, hinges = self.static.parameters(EA, T, e_ref)
            p["tension_only"] = float(self.tension_only) * np.ones_like(T)
            return p, hinges
        p, _ = super().parameters(EA, T, e_ref)
        p.update(T0=np.asarray(T, float) * 1.0, e0=e_ref * np.ones_like(T), k=0.0 * p["k"])
        return p, None

    def axial(self, e, rate, state=None, reference=None):
        """The tension N(e, de/dt, state, reference) (N; the last two where the law has
        them) as the cable sees it (cut at 0 when tension-only; the initial state where
        None)."""
        N = self._evaluate(e, rate, state, reference)
        return ops.maximum(N, 0.0) if self.tension_only else N

    def compiled(self):
        """The generated C function z = [e, de/dt, the state, the reference's strain and
        tension] -> [N] of :meth:`axial` (its ``address`` for compiled callers), or None
        where JAX or the generator cannot take the law (then NumPy evaluates it)."""
        if "_compiled" not in self.__dict__:
            object.__setattr__(self, "_compiled", None)
            if HAS_JAX:
                import jax
                import jax.numpy as jnp
                import skfem.autodiff  # noqa: F401 - turns on float64 in JAX

                from ..fem.form_compiler import build_pointwise
                try:
                    m = 2 + len(self.initial_state)  # where the reference starts
                    n = m + 2 * bool(self.reference)
                    traced = jax.make_jaxpr(lambda z: jnp.reshape(self.axial(
                        z[0], z[1], tuple(z[2:m]) if m > 2 else None,
                        (z[m], z[m + 1]) if self.reference else None), (1,)))(jnp.zeros(n))
                    object.__setattr__(self, "_compiled", build_pointwise(
                        traced.jaxpr, traced.consts, n, f"UserLaw {self.label}"))
                except Exception:  # JAX cannot trace it, or Unsupported: NumPy evaluates it
                    pass
        return self._compiled


def _initial_state(label, state, update, state_rate, static):
    """(the law's initial state as a tuple of floats (() without a memory; NaNs, one per
    value, where it is a function), that function or None)."""
    if state is None and update is None and state_rate is None:
        return (), None
    if state is None or (update is None and state_rate is None) or not all(
            callable(f) for f in (update, state_rate) if f is not None):
        raise ValueError(f"UserLaw {label} state, update / state_rate: a law with a memory "
                         "needs the initial values and update(strain, rate, state, dt) -> "
                         "new values or state_rate(strain, rate, state) -> d(state)/dt (or "
                         "both: the rate integrated, then the update)")
    if callable(state):
        e = np.linspace(0.0, 0.01, 3)
        try:
            with np.errstate(all="ignore"):
                values = state(e, static.static_tension(e, 1.0))
            count = len(tuple(values))
        except Exception as error:
            raise ValueError(f"UserLaw {label} state: state(e_ref, T_ref) failed on arrays "
                             f"of strains and tensions: {error}") from error
        if not count:
            raise ValueError(f"UserLaw {label} state: state(e_ref, T_ref) returned no values")
        return (math.nan,) * count, state
    values = tuple(np.atleast_1d(np.asarray(state, float)).ravel())
    if not values or not all(np.isfinite(values)):
        raise ValueError(f"UserLaw {label} state: need one or more finite initial values, "
                         f"got {state!r}")
    return values, None


def _check_memory(law, e):
    """The initial state, the update and the state's rate evaluated once on arrays: as
    many finite values as the state."""
    with np.errstate(all="ignore"):
        try:
            state = [np.asarray(value, float) for value in law.start_state(e)]
        except Exception as error:
            raise ValueError(f"UserLaw {law.label} state: failed on arrays of strains: "
                             f"{error}") from error
    if not all(np.all(np.isfinite(value)) for value in state):
        raise ValueError(f"UserLaw {law.label} state: the initial state is not finite at "
                         f"reference strains in [0, {law.max_strain:g}]")
    checks = [("update", "update(strain, rate, state, dt)",
               lambda: law.update(e, np.zeros_like(e), tuple(state), 0.1)),
              ("state_rate", "state_rate(strain, rate, state"
               + (", reference)" if law.reference else ")"),
               lambda: law._evaluate(e, np.zeros_like(e), tuple(state),
                                     function=law.state_rate))]
    for name, signature, evaluate in checks:
        if getattr(law, name) is None:
            continue
        try:
            with np.errstate(all="ignore"):
                new = [np.asarray(value, float) * np.ones_like(e) for value in evaluate()]
        except Exception as error:
            raise ValueError(f"UserLaw {law.label}: {signature} failed on arrays of strains: "
                             f"{error}") from error
        if len(new) != len(state):
            raise ValueError(f"UserLaw {law.label} {name}: returned {len(new)} values for a "
                             f"state of {len(state)}")
        if not all(np.all(np.isfinite(value)) for value in new):
            raise ValueError(f"UserLaw {law.label} {name}: not finite at strains in [0, "
                             f"{law.max_strain:g}] (dt 0.1 s, the initial state)")


def _state_names(law):
    return [f"law_state_{k}" for k in range(len(law.initial_state))]


def _initial_memory(law, on, e_ref, T_ref) -> dict:
    """The law's form's state, name -> initial values (a number or (nel, nqp)): the law's
    state (its function of the reference's strain e_ref and tension T_ref on the law's
    points, ``on``; 0 elsewhere) and, for a law with a state's rate, the last accepted
    rate, its slopes and time (0 until the first commit)."""
    names = _state_names(law)
    if law.start is None:
        memory = dict(zip(names, law.initial_state))
    else:
        memory, mask = {}, on > 0
        for name, value in zip(names, law.start_state(e_ref[mask], (e_ref[mask],
                                                                      T_ref[mask]))):
            memory[name] = np.zeros(on.shape)
            memory[name][mask] = value
    if law.state_rate is not None:
        n = len(names)
        memory.update({f"law_rate_{k}": 0.0 for k in range(n)})
        memory.update({f"law_rate_slope_{k}_{j}": 0.0 for k in range(n) for j in range(n)})
        memory.update({f"law_tension_slope_{k}": 0.0 for k in range(n)})
        memory["law_time"] = 0.0
    return memory


def _strain_and_rate(w):
    """(e, de/dt, |r'|, r' . udot'): the law's strain from the unstretched line and its
    rate at the points of w (see the module docstring)."""
    up = d_ds(w.u)
    rp = w.Xp + up
    stretch = ops.sqrt(1.0 + 2.0 * dot(w.Xp + 0.5 * up, up))  # from the reference (Eq. 3)
    grow = 1.0 + w.e_ref
    green_rate = dot(rp, d_ds(w.du))  # d/dt of the strain of Eq. 3
    return grow * stretch - 1.0, grow * green_rate / stretch, stretch, green_rate


def _reference(w):
    """The reference state's (strain, tension) the law reads at the points of w."""
    kind = w.law.reference
    return ((w.e_static, w.T_static) if kind == "static" else (w.e_ref, w.T)
            if kind == "line" else None)


def _solved(A, b):
    """x with A x = b for a small system (lists of arrays; Gaussian elimination written
    out, no pivoting: A is near the identity)."""
    n = len(b)
    A, b = [list(row) for row in A], list(b)
    for k in range(n):
        for i in range(k + 1, n):
            factor = A[i][k] / A[k][k]
            A[i] = [A[i][j] - factor * A[k][j] for j in range(n)]
            b[i] = b[i] - factor * b[k]
    x = [None] * n
    for k in reversed(range(n)):
        x[k] = (b[k] - sum(A[k][j] * x[j] for j in range(k + 1, n))) / A[k][k]
    return x


def _state_change(w, strain, rate, reference, h):
    """(the last accepted state, its change over a step of h (s)) by the linearized
    trapezoidal rule (module docstring)."""
    law, names = w.law, _state_names(w.law)
    n, half = len(names), 0.5 * h
    state = tuple(w[name] for name in names)
    rate_n = [w[f"law_rate_{k}"] for k in range(n)]
    J = [[w[f"law_rate_slope_{k}_{j}"] for j in range(n)] for k in range(n)]
    f = law._evaluate(strain, rate, state, reference, function=law.state_rate)
    new_rate = _solved([[float(k == j) - half * J[k][j] for j in range(n)] for k in range(n)],
                       [f[k] + half * sum(J[k][j] * rate_n[j] for j in range(n))
                        for k in range(n)])
    return state, [half * (rate_n[k] + new_rate[k]) for k in range(n)]


def _slope(function, state, j):
    """d function(state) / d state[j] (function: a tuple of arrays): forward-mode automatic
    differentiation on JAX arrays, else central differences (as CreepTerm's)."""
    def moved(value):
        return tuple(function(tuple(value if k == j else s for k, s in enumerate(state))))

    if ops.xp(*state) is not np:
        import jax
        return jax.jvp(moved, (state[j],), (ops.xp(state[j]).ones_like(state[j]),))[1]
    step = 1e-7 * np.maximum(np.abs(state[j]), 1e-3)
    up, down = moved(state[j] + step), moved(state[j] - step)
    return tuple((a - b) / (2.0 * step) for a, b in zip(up, down))


def law_residual(v, w):
    # Eq. 11 with the user's tension, and the line type's axial damping BA as the cable
    # kernel has it: int [N(e, de/dt) / |r'| + BA r' . udot'] r' . dv' ds on its lines
    strain, rate, stretch, green_rate = _strain_and_rate(w)
    law, reference = w.law, _reference(w)
    if law.state_rate is None:
        state = tuple(w[name] for name in _state_names(law)) or None
        N = law.axial(strain, rate, state, reference)
    else:  # the state integrated within the step: N(s_n) + N_z . ds
        state, change = _state_change(w, strain, rate, reference,
                                      ops.maximum(w.t - w.law_time, 0.0))
        N = law._evaluate(strain, rate, state, reference) + sum(
            w[f"law_tension_slope_{k}"] * ds for k, ds in enumerate(change))
        N = ops.maximum(N, 0.0) if law.tension_only else N
    axial = N / stretch + w.BA * green_rate
    return w.on * axial * dot(w.Xp + d_ds(w.u), d_ds(v))


def law_update(w):
    """The law's state after the step w.dt (s), at the points of w (with a state's rate:
    also the rate, its slopes and the time there)."""
    strain, rate, _, _ = _strain_and_rate(w)
    law, names = w.law, _state_names(w.law)
    if law.state_rate is None:
        new = law.update(strain, rate, tuple(w[name] for name in names), w.dt)
        return dict(zip(names, new))
    reference = _reference(w)
    state, change = _state_change(w, strain, rate, reference, w.dt)
    state = tuple(s + ds for s, ds in zip(state, change))
    if law.update is not None:  # (a law with both: the update after the rate's step)
        state = tuple(law.update(strain, rate, state, w.dt))
    new = dict(zip(names, state), law_time=w.t + 0.0 * strain)
    new.update({f"law_rate_{k}": value for k, value in enumerate(law._evaluate(
        strain, rate, state, reference, function=law.state_rate))})
    for j in range(len(names)):
        slopes = _slope(lambda s: law._evaluate(strain, rate, s, reference,
                                                function=law.state_rate), state, j)
        new.update({f"law_rate_slope_{k}_{j}": value for k, value in enumerate(slopes)})
        new[f"law_tension_slope_{j}"] = _slope(
            lambda s: (law._evaluate(strain, rate, s, reference),), state, j)[0]
    return new


class _LawForm(LineForm):
    """The line form of a user's law (:func:`law_residual`); for a law about the static
    state, silent while the static laws are in force (the cable kernel then carries its
    elements with the static law) and reading each element's static strain and tension
    (``LineSet._mean``) once they are set: its kernel made again when they change."""

    _static_state = None  # the LineSet's static state the fields were set from

    def _follow_the_static_state(self):
        """False in statics; the fields set from a new static state (kernel made anew)."""
        lines = self.lines
        if self.fields["law"].reference != "static":
            return True
        if lines._static:
            return False
        if lines._mean is not None and lines._mean is not self._static_state:
            self._static_state = lines._mean
            T_mean, e_mean = lines._mean
            on = self.fields["on"]
            self.fields["T_static"][...] = T_mean[:, None] * on
            self.fields["e_static"][...] = e_mean[:, None] * on
            self._engine, self.step_kernel = None, None
            if self.state and self.fields["law"].start is not None:  # starts from them
                self.state.update(_initial_memory(self.fields["law"], on,
                                                  self.fields["e_static"],
                                                  self.fields["T_static"]))
                self._memory = self._state_layout = self._commit_kernel = None
                self.step_commit = None
        return True

    def add_to(self, u, v, t, R, K=None, C=None):
        if self._follow_the_static_state():
            super().add_to(u, v, t, R, K, C)

    def carry_memory(self, other):
        self._follow_the_static_state()  # (its start from the static state made first)
        super().carry_memory(other)

    def lowered(self):
        if self.lines is not None and not self._follow_the_static_state():
            return None
        return super().lowered()


def law_terms(lines) -> list:
    """One line form per user law of ``lines`` (a LineSet), on that law's lines, at the
    element mid-points as the cable kernel; none without user laws. A law with a memory
    keeps it in its form (registered on ``lines`` for the reported tension)."""
    terms, seen = [], []
    for law in lines.laws:
        if isinstance(law, UserLaw) and not any(law is s for s in seen):
            seen.append(law)
            cells = np.isin(lines.line_of_cell,
                            [k for k, other in enumerate(lines.laws) if other is law])
            on = np.repeat(cells.astype(float)[:, None],
                           lines.cable_fields["T"].shape[1], axis=1)
            memory = (dict(state=_initial_memory(law, on, lines.cable_fields["e_ref"] * on,
                                                 lines.cable_fields["T"] * on),
                           update=law_update)
                      if law.initial_state else {})
            fields = {"on": on, "law": law}
            if law.reference == "static":  # until the statics: the state it is built in
                fields.update(e_static=lines.cable_fields["e_ref"] * on,
                              T_static=lines.cable_fields["T"] * on)
            term = _LawForm(law_residual, fields=fields,
                            quadrature="gauss" if lines.hermite else "midpoint",
                            lines=lines, name=law.label, **memory)
            if memory:
                lines.__dict__.setdefault("_law_memories", {})[id(law)] = term
            terms.append(term)
    return terms


def law_tension(lines, u, ud=None) -> np.ndarray:
    """(nel,) the user laws' tension at the element mid-points less the reference
    tension the cable kernel reports there (N; 0 on other lines)."""
    plan = lines.__dict__.get("_user_law_plan")
    if plan is None:  # per law: its elements' mid-point slope, X', 1 + e_ref and T
        weights, dofs = lines.midpoint_slope()
        f = lines.midpoint_fields()
        laws = []  # each law once, with all its lines' elements
        for law in lines.laws:
            if isinstance(law, UserLaw) and not any(law is seen for seen in laws):
                laws.append(law)
        plan = lines.__dict__["_user_law_plan"] = [
            (law, cells, np.ascontiguousarray(weights[cells]),
             np.ascontiguousarray(dofs[cells]), np.ascontiguousarray(f["Xp"][:, cells].T),
             1.0 + f["e_ref"][cells], np.ascontiguousarray(f["T"][cells]))
            for law, cells in ((law, np.nonzero(np.isin(lines.line_of_cell, [
                k for k, other in enumerate(lines.laws) if other is law]))[0])
                for law in laws)]
    out = np.zeros(len(lines.line_of_cell))
    for law, cells, weights, dofs, Xp, grow, T in plan:
        if law.reference == "static" and lines._static:
            continue  # statics: the kernel reports these elements, with their static law
        T_ref, e_ref = ((T, grow - 1.0) if law.reference == "line" or lines._mean is None
                        else (lines._mean[0][cells], lines._mean[1][cells]))
        states = _element_states(lines, law, cells, (e_ref, T_ref))  # (ncells, nstate)
        if law.reference:  # the reference's strain and tension after the state
            states = np.column_stack([states, e_ref, T_ref])
        compiled = law.compiled()
        if compiled is not None:
            _tensions(compiled.address, u, u if ud is None else ud, ud is not None, cells,
                      weights, dofs, Xp, grow, T, states, out)
            continue
        up = np.einsum("eb,ebc->ec", weights, u[dofs])
        rp = Xp + up
        stretch = np.sqrt(1.0 + 2.0 * np.einsum("ij,ij->i", Xp + 0.5 * up, up))
        rate = (np.zeros_like(stretch) if ud is None else grow * np.einsum(
            "ij,ij->i", rp, np.einsum("eb,ebc->ec", weights, ud[dofs])) / stretch)
        count = len(law.initial_state)
        out[cells] = law.axial(grow * stretch - 1.0, rate, tuple(states[:, :count].T) or None,
                               tuple(states[:, count:].T) or None) - T
    return out


def _element_states(lines, law, cells, reference) -> np.ndarray:
    """(ncells, nstate) the law's last accepted state on the elements (the mean over
    their quadrature points; before its form is in a model, the initial state at the
    elements' reference (strain, tension))."""
    term = lines.__dict__.get("_law_memories", {}).get(id(law))
    if term is None:
        return np.stack(law.start_state(reference[0], reference), axis=1) if (
            law.initial_state) else np.zeros((cells.size, 0))
    values = term.state_values()
    return np.stack([values[name][cells].mean(axis=1) for name in _state_names(law)],
                    axis=1) if values else np.zeros((cells.size, 0))


@njit(cache=True)
def _tensions(address, u, ud, moving, cells, weights, dofs, Xp, grow, T, states, out):
    """out[cells] = N(e, de/dt, state) - T at the elements' mid-points, N by the law's C
    function at ``address`` (de/dt 0 unless ``moving``); the slopes there sum_b
    weights[k, b] u[dofs[k, b]] (``LineSet.midpoint_slope``)."""
    z, N = np.empty(2 + states.shape[1]), np.empty(1)
    for k in range(cells.size):
        z[2:] = states[k]
        eps = rate = 0.0
        for c in range(3):
            up = vp = 0.0
            for b in range(weights.shape[1]):
                up += weights[k, b] * u[dofs[k, b, c]]
                vp += weights[k, b] * ud[dofs[k, b, c]]
            eps += (Xp[k, c] + 0.5 * up) * up  # Eq. 3
            rate += (Xp[k, c] + up) * vp
        stretch = math.sqrt(1.0 + 2.0 * eps)
        z[0] = grow[k] * stretch - 1.0
        z[1] = grow[k] * rate / stretch if moving else 0.0
        call_load(address, z.ctypes.data, N.ctypes.data)
        out[cells[k]] = N[0] - T[k]
