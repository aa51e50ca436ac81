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
    """Square root, elementwise."""
    a = value(a)
    return xp(a).sqrt(a)


def norm(a):
    """|a| over the first axis, with derivative 0 (not NaN) at a = 0 (for |v| v terms)."""
    squared = dot(a, a)
    positive = squared > 0
    return where(positive, sqrt(where(positive, squared, 1.0)), 0.0)


def abs(a):  # noqa: A001 - the form-side name of |.|
    """Absolute value, elementwise (derivative sign(a), 0 at a = 0)."""
    a = value(a)
    return xp(a).abs(a)


def exp(a):
    """Exponential, elementwise."""
    a = value(a)
    return xp(a).exp(a)


def log(a):
    """Natural logarithm, elementwise."""
    a = value(a)
    return xp(a).log(a)


def tanh(a):
    """Hyperbolic tangent, elementwise: a smooth step, e.g. a contact switched on over a
    length scale, tanh(gap / width)."""
    a = value(a)
    return xp(a).tanh(a)


def sin(a):
    """Sine, elementwise (radians): e.g. a load varying in time, sin(omega t)."""
    a = value(a)
    return xp(a).sin(a)


def cos(a):
    """Cosine, elementwise (radians)."""
    a = value(a)
    return xp(a).cos(a)


def arctan2(y, x):
    """The angle of the point (x, y), elementwise, in (-pi, pi] (radians)."""
    y, x = _values(y, x)
    return xp(y, x).arctan2(y, x)


def mod(a, b):
    """a modulo b with the sign of b, elementwise: an angle wrapped to [0, 2 pi) as
    mod(angle, 2 pi)."""
    a, b = _values(a, b)
    return xp(a, b).mod(a, b)


def cross(a, b):
    """a x b for vectors of shape (3, ...)."""
    a, b = _values(a, b)
    return xp(a, b).stack([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                           a[0] * b[1] - a[1] * b[0]])


def where(condition, a, b):
    """a where condition holds, else b, elementwise (the derivative is the chosen
    branch's: guard both branches against NaN, as :func:`norm` does)."""
    condition, a, b = _values(condition, a, b)
    return xp(condition, a, b).where(condition, a, b)


def maximum(a, b):
    """The larger of a and b, elementwise."""
    a, b = _values(a, b)
    return xp(a, b).maximum(a, b)


def minimum(a, b):
    """The smaller of a and b, elementwise."""
    a, b = _values(a, b)
    return xp(a, b).minimum(a, b)


def clip(a, low, high):
    """a limited to [low, high], elementwise."""
    a, low, high = _values(a, low, high)
    return xp(a, low, high).clip(a, low, high)


def interp(x, xs, ys):
    """Piecewise-linear interpolation of the table (xs non-decreasing, ys) at x, held at
    the end values beyond the ends (as ``numpy.interp``): the piece x lies in, chosen
    from the left by comparisons, then one division; a piece of no width is a step,
    ys[i+1] from x = xs[i] on. The table's points may be arrays shaped like x (functions
    of a state): the form compiler traces them as the rest."""
    x = value(x)
    x0 = x1 = xs[0] + 0.0 * x
    y0 = y1 = ys[0] + 0.0 * x
    for i in range(len(xs) - 1):  # the last piece that starts at or below x
        inside = x >= xs[i]
        x0, x1 = where(inside, xs[i], x0), where(inside, xs[i + 1], x1)
        y0, y1 = where(inside, ys[i], y0), where(inside, ys[i + 1], y1)
    width = x1 - x0
    ramp = clip((x - x0) / where(width > 0.0, width, 1.0), 0.0, 1.0)
    return y0 + (y1 - y0) * where(width > 0.0, ramp, 1.0)
