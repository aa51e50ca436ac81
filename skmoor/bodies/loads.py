"""Loads on points and bodies written as functions F(q, qdot, t): the term protocol on
3 or 6 DOFs, tangents by JAX, by hand or by central differences.
"""
from __future__ import annotations

import numpy as np

from ..fem.terms import HAS_JAX, Term
from .body_motion import BodyMotion


class BodyTerm(Term):
    """A built-in term on a body that can also be evaluated outside a System: there its
    body's motion is the small-rotation reading of q about the origin."""

    def body_motion(self, q, qdot=None):
        if self._system is None:
            return BodyMotion(q, qdot)
        return super().body_motion(q, qdot)


class _PointwiseLoad(BodyTerm):
    """A load F(u, v, t) on a point (3 DOFs) or a body (6): the residual gets -F. Without
    a hand ``tangent``, dF/du and dF/dv come from JAX (``jax.jacfwd``, when the load is
    written with :mod:`skmoor.fem.ops` / ``jax.numpy``), else from central differences;
    ``tangent_by`` says which."""

    size = 3

    def __init__(self, load, *, added_mass=None, tangent=None):
        if not callable(load):
            raise ValueError(f"{type(self).__name__} load: need a function (q, qdot, t) -> F")
        self.load, self.tangent = load, tangent
        self.tangent_by = "hand" if tangent is not None else None
        self.added_mass = None if added_mass is None else np.asarray(added_mass, float)
        n = self.size
        if self.added_mass is not None and self.added_mass.shape not in ((n, n), ()):
            raise ValueError(f"{type(self).__name__} added_mass: need a ({n}, {n}) matrix, "
                             f"got {self.added_mass.shape}")

    def __copy__(self):
        """A copy whose load and tangent, where they are methods of this term, are the
        copy's own (a copy joins its own System: :meth:`body_motion` reads that one)."""
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        for name in ("load", "tangent"):
            method = getattr(self, name)
            if getattr(method, "__self__", None) is self:
                setattr(new, name, getattr(new, method.__name__))
        return new

    step_load = None  # the generated C function the compiled time step calls
    _lowering = None  # why it has none, once tried

    def lowered(self):
        """'point load' / 'body load' when the load traces with JAX (written with
        :mod:`skmoor.fem.ops` / ``jax.numpy``) into code the compiled step runs."""
        if self._lowering is None:
            self._lowering = self._generate()
        if self.step_load is None:
            return None
        return "point load" if self.acts_on == "points" else "body load"

    def _generate(self):
        """Generates the load's compiled kernel (F and both Jacobians from one trace);
        returns '' or why not."""
        if type(self) not in (PointLoad, BodyLoad):  # skmoor's own: Python, as written
            return f"{type(self).__name__} has no compiled kernel"
        if self.tangent_by == "hand":
            return "a hand-written tangent (Python)"
        self.step_load, why = generated_load(lambda q, qdot, t: self.load(q, qdot, t),
                                             self.size, f"{type(self).__name__} {named(self.load)}")
        return why

    @property
    def why_python(self):
        return self._lowering or "no compiled kernel (a user term)"

    def add_to(self, u, v, t, R, K=None, C=None):
        F = np.asarray(self.load(u, v, t), float)
        R -= F
        if K is None:
            return
        if self.tangent is None:
            self.tangent = self._automatic(u, v, t)
        dF_du, dF_dv = self.tangent(u, v, t)
        if dF_du is not None:
            K -= dF_du
        if dF_dv is not None:
            C -= dF_dv

    def _automatic(self, u, v, t):
        """jax.jacfwd of the load where it traces, else central differences."""
        if HAS_JAX:
            import jax
            import skfem.autodiff  # noqa: F401 - turns on float64 in JAX

            jacobian = jax.jit(jax.jacfwd(lambda a, b, time: self.load(a, b, time), (0, 1)))
            try:
                jacobian(u, v, float(t))
                self.tangent_by = "jax"
                return lambda a, b, time: tuple(np.asarray(m) for m in
                                                jacobian(a, b, float(time)))
            except Exception:  # NumPy-only code does not trace
                pass
        self.tangent_by = "central differences"
        return lambda a, b, time: _central(self.load, a, b, time)

    def mass_matrix(self):
        if self.added_mass is None:
            return None
        return self.added_mass * np.eye(self.size) if self.added_mass.ndim == 0 else self.added_mass


def named(function):
    """A function's module and qualified name: a label that stays the same from run to
    run (its repr's address would make the generated source, and its compile, new in
    every process)."""
    return (f"{getattr(function, '__module__', None) or ''}."
            f"{getattr(function, '__qualname__', type(function).__name__)}")


def generated_load(load, n, label, slopes=True):
    """(the compiled kernel the time step calls, '') of load(q, qdot, t) -> F (n,) on n
    DOFs written with :mod:`skmoor.fem.ops` / ``jax.numpy``: F and, with ``slopes``, its
    Jacobians from one JAX trace (zero without: an explicit load); (None, why not) where
    it does not trace or JAX is missing."""
    if not HAS_JAX:
        return None, "JAX is not installed (pip install 'skmoor[autodiff]')"
    import jax
    import jax.numpy as jnp
    import skfem.autodiff  # noqa: F401 - turns on float64 in JAX

    from ..fem.form_compiler import Unsupported, build_pointwise

    def value(q, qdot, t):
        return jnp.asarray(load(q, qdot, t), float).reshape(n)

    def outputs(z):
        q, qdot, t = z[:n], z[n:2 * n], z[2 * n]
        if not slopes:
            return jnp.concatenate([value(q, qdot, t), jnp.zeros(2 * n * n)])
        dq, dv = jax.jacfwd(lambda a, b: value(a, b, t), (0, 1))(q, qdot)
        return jnp.concatenate([value(q, qdot, t), dq.ravel(), dv.ravel()])

    try:
        traced = jax.make_jaxpr(outputs)(jnp.zeros(2 * n + 1))
    except Exception as error:  # NumPy-only code does not trace
        return None, f"the load does not trace with JAX ({type(error).__name__})"
    try:
        return build_pointwise(traced.jaxpr, traced.consts, 2 * n + 1, label), ""
    except Unsupported as why:
        return None, f"the code generator lacks {why}"


def _central(load, u, v, t):
    """dF/du and dF/dv of a pointwise load by central differences."""
    n = len(u)
    du = 1e-6 * (1.0 + np.max(np.abs(u)))
    dv = 1e-6 * (1.0 + np.max(np.abs(v)))
    A, B = np.empty((n, n)), np.empty((n, n))
    for k, e in enumerate(np.eye(n)):
        A[:, k] = (np.asarray(load(u + du * e, v, t)) - np.asarray(load(u - du * e, v, t))) / (2 * du)
        B[:, k] = (np.asarray(load(u, v + dv * e, t)) - np.asarray(load(u, v - dv * e, t))) / (2 * dv)
    return A, B


class PointLoad(_PointwiseLoad):
    """A load on a free point: load(x, v, t) -> F (3,), N, with x, v the point's
    displacement (m) and velocity (m/s); tangent(x, v, t) -> (dF/dx, dF/dv) (3x3 each,
    None for zero; default: automatic, see :class:`_PointwiseLoad`); added_mass: (3, 3) or a scalar, kg.
    point: the free point's name (resolved by ``model.add``) or index."""

    acts_on = "points"
    size = 3

    def __init__(self, load, point=0, **kw):
        super().__init__(load, **kw)
        self.point = point


class BodyLoad(_PointwiseLoad):
    """A load on a dynamic body: load(q, qdot, t) -> F (6,), N and N m (about its
    reference point, global axes); tangent(q, qdot, t) -> (dF/dq, dF/dqdot) (6x6 each,
    None for zero; default: automatic, see :class:`_PointwiseLoad`); added_mass: (6, 6) (kg, kg m, kg m2).
    body: the body's name (resolved by ``model.add``) or index among the dynamic bodies."""

    acts_on = "bodies"
    size = 6

    def __init__(self, load, body=0, **kw):
        super().__init__(load, **kw)
        self.body = body
