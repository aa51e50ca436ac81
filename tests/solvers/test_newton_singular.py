"""A Newton iterate that leaves the residual's domain (NaN forces, as a line folded by a
step far longer than its axial period) on the sparse iteration matrix: SuperLU finds
the NaN matrix singular, which is a failed Newton as on the dense layout, so the step is
subdivided (skmoor.solvers.dynamics.integrate), not a RuntimeError out of the run.

Independent number: the static root of the hardening spring the system settles on.
"""
import numpy as np
import pytest
import scipy.sparse as sp

from skmoor.solvers.dynamics import integrate
from skmoor.solvers.newton import DENSE_BELOW

N, K, K3, F, DAMPING = DENSE_BELOW, 1.0, 100.0, 20.0, 5.0  # N / m, N / m3, N, N s / m


class Springs:
    """N unit masses on hardening springs k x + k3 x^3 under a constant F, whose forces
    are NaN beyond |x| = 1 m (the residual's domain), with a sparse mass matrix."""

    M = sp.identity(N, format="csr")

    def residual(self, x, v=None, t=0.0, tangent=True, layout="sparse"):
        outside = np.abs(x) >= 1.0
        R = np.where(outside, np.nan, K * x + K3 * x**3 - F)
        if not tangent:
            return R, None, None
        return R, sp.diags(np.where(outside, np.nan, K + 3 * K3 * x**2), format="csr"), None


def test_a_step_into_nan_forces_is_subdivided():
    """From rest, 0.5 s steps (the first step's Newton goes beyond 1 m): the first step is
    subdivided, the run goes on and settles on the root of k x + k3 x^3 = F within 1e-6 m
    (the dynamic overshoot stays below 0.9 m)."""
    C = DAMPING * sp.identity(N, format="csr")
    states = list(integrate(Springs(), np.zeros(N), np.zeros(N), 0.5, 40.0, C=C,
                            compiled=False))
    assert states[-1].t == pytest.approx(40.0)
    assert states[1].subdivided == 1
    root = [r.real for r in np.roots([K3, 0.0, K, -F]) if abs(r.imag) < 1e-12][0]
    np.testing.assert_allclose(states[-1].x, root, atol=1e-6)
