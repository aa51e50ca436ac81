"""Array functions for forms that automatic differentiation can trace.

A form written with these (instead of ``numpy`` and ``skfem.helpers``) runs on NumPy
arrays in scikit-fem's assembly and on JAX arrays in the automatic tangents and the
compiled path of :class:`skmoor.fem.terms.LineForm`: each function picks ``jax.numpy`` when
one of its arguments is a JAX array or tracer, ``numpy`` otherwise.
"""
import numpy as np


def _jax(*args):
    """jax.numpy if an argument is a JAX array or tracer, else None."""
    for a in args:
        if type(a).__module__.startswith("jax"):
            import jax.numpy as jnp
            return jnp
    return None


def _values(*args):
    """Plain arrays of fields: a JAX field's value (a NumPy DiscreteField is an array)."""
    return [a.value if hasattr(a, "grad") and not isinstance(a, np.ndarray) else a
            for a in args]


def xp(*args):
    """The array namespace of the arguments: jax.numpy or numpy."""
    return _jax(*_values(*args)) or np


def value(field):
    """The values of a field at the quadrature points, as a plain array."""
    return _values(field)[0]


def dot(a, b):
    """Sum over the first axis: a . b for vectors of shape (3, ...)."""
    a, b = _values(a, b)
    return xp(a, b).einsum("i...,i...", a, b)


def matvec(A, b):
    """(A b) for a matrix field A (3, 3, ...) and a vector field b (3, ...)."""
    A, b = _values(A, b)
    return xp(A, b).einsum("ij...,j...->i...", A, b)


def d_ds(field):
    """d/ds of a vector field in a form, shape (3, nel, nqp)."""
    return field.grad[:, 0]


def sqrt(a):
    a = value(a)
    return xp(a).sqrt(a)


def norm(a):
    """|a| over the first axis, with derivative 0 (not NaN) at a = 0 (for |v| v terms)."""
    squared = dot(a, a)
    positive = squared > 0
    return where(positive, sqrt(where(positive, squared, 1.0)), 0.0)


def abs(a):  # noqa: A001 - the form-side name of |.|
    a = value(a)
    return xp(a).abs(a)


def exp(a):
    a = value(a)
    return xp(a).exp(a)


def log(a):
    a = value(a)
    return xp(a).log(a)


def tanh(a):
    a = value(a)
    return xp(a).tanh(a)


def where(condition, a, b):
    condition, a, b = _values(condition, a, b)
    return xp(condition, a, b).where(condition, a, b)


def maximum(a, b):
    a, b = _values(a, b)
    return xp(a, b).maximum(a, b)


def minimum(a, b):
    a, b = _values(a, b)
    return xp(a, b).minimum(a, b)


def clip(a, low, high):
    a, low, high = _values(a, low, high)
    return xp(a, low, high).clip(a, low, high)


def interp(x, xs, ys):
    """Piecewise-linear interpolation of the table (xs, ys) at x (held constant outside)."""
    x = value(x)
    return xp(x).interp(x, xs, ys)
