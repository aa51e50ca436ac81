"""A bracketed scalar root: Brent's method (inverse quadratic interpolation, secant and
bisection), as in R. P. Brent, *Algorithms for Minimization without Derivatives* (1973),
ch. 4. Written here so that ``import skmoor`` need not load scipy.optimize (0.5 s)."""
from __future__ import annotations

import math

_EPS = 2.220446049250313e-16


def brent(f, a: float, b: float, xtol: float = 2e-12, rtol: float = 4 * _EPS,
          maxiter: int = 200) -> float:
    """A root of f in [a, b], where f(a) and f(b) differ in sign (or one is zero).

    The root is within xtol + rtol |x| of the returned x (scipy.optimize.brentq's test). Raises ValueError when f(a) f(b) > 0, RuntimeError when it has
    not converged in maxiter iterations."""
    fa, fb = f(a), f(b)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if (fa > 0.0) == (fb > 0.0):
        raise ValueError(f"brent: f({a:g}) = {fa:g} and f({b:g}) = {fb:g} have the same sign")
    c, fc = a, fa  # b is the best guess, c the previous one, [b, c] brackets the root
    d = e = b - a
    for _ in range(maxiter):
        if (fb > 0.0) == (fc > 0.0):  # keep the root between b and c
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        tol = 0.5 * (xtol + rtol * abs(b))
        half = 0.5 * (c - b)
        if abs(half) <= tol or fb == 0.0:
            return b
        if abs(e) >= tol and abs(fa) > abs(fb):
            s = fb / fa
            if a == c:  # secant
                p, q = 2.0 * half * s, 1.0 - s
            else:  # inverse quadratic interpolation
                q, r = fa / fc, fb / fc
                p = s * (2.0 * half * q * (q - r) - (b - a) * (r - 1.0))
                q = (q - 1.0) * (r - 1.0) * (s - 1.0)
            if p > 0.0:
                q = -q
            p = abs(p)
            if 2.0 * p < min(3.0 * half * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q  # the interpolation is accepted
            else:
                d = e = half  # bisection
        else:
            d = e = half
        a, fa = b, fb
        b += d if abs(d) > tol else math.copysign(tol, half)
        fb = f(b)
    raise RuntimeError(f"brent: no convergence in {maxiter} iterations (bracket [{b:g}, {c:g}])")
