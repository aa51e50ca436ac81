"""Cubic Hermite shape functions of the C1 line element.
"""
from __future__ import annotations

import numpy as np


def hermite_shapes(xi, h):
    """The cubic Hermite shape functions on elements of length h (m) at the reference
    points xi in [0, 1], for the DOFs [u_i, u_i', u_j, u_j']: values, d/ds (1/m) and
    d2/ds2 (1/m2), each (nel, nqp, 4)."""
    x = np.asarray(xi, float)[None, :]
    h = np.asarray(h, float)[:, None]
    one = np.ones_like(h)
    N = np.stack([(1 - 3 * x**2 + 2 * x**3) * one, h * (x - 2 * x**2 + x**3),
                  (3 * x**2 - 2 * x**3) * one, h * (x**3 - x**2)], axis=-1)
    dN = np.stack([(6 * x**2 - 6 * x) / h, (1 - 4 * x + 3 * x**2) * one,
                   (6 * x - 6 * x**2) / h, (3 * x**2 - 2 * x) * one], axis=-1)
    d2N = np.stack([(12 * x - 6) / h**2, (6 * x - 4) / h, (6 - 12 * x) / h**2,
                    (6 * x - 2) / h], axis=-1)
    return N, dN, d2N
