"""Linear modes about a static state: K phi = omega^2 M phi."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse.linalg as spla


@dataclass
class Modes:
    """omega (k,) rad/s ascending; shapes (n, k) mass-normalized reduced vectors."""

    omega: np.ndarray
    shapes: np.ndarray

    @property
    def periods(self) -> np.ndarray:
        """Natural periods, s."""
        return 2 * np.pi / self.omega

    @property
    def frequencies(self) -> np.ndarray:
        """Natural frequencies, Hz."""
        return self.omega / (2 * np.pi)


def eigenmodes(K, M, k: int = 10, dense_below: int = 2000) -> Modes:
    """The k lowest modes of the pencil (K, M) (sparse or dense, symmetric parts used).

    Dense LAPACK below ``dense_below`` unknowns; above, shift-invert subspace iteration
    (:func:`subspace_modes`: a block, so repeated eigenvalues, as of identical platforms
    in a farm, cost no more than distinct ones), and shift-invert ``eigsh`` where that
    does not converge.
    """
    n = K.shape[0]
    k = min(int(k), n - 1 if n >= dense_below else n)
    if k < 1:
        raise ValueError(f"eigenmodes k: must be >= 1, got {k}")
    if n < dense_below:
        Kd = _dense(K)
        Md = _dense(M)
        w2, phi = sla.eigh(0.5 * (Kd + Kd.T), 0.5 * (Md + Md.T), subset_by_index=(0, k - 1))
    else:
        Ks = (0.5 * (K + K.T)).tocsc()
        found = subspace_modes(Ks, M.tocsc(), k)
        if found is None:
            w2, phi = spla.eigsh(Ks, k=k, M=M.tocsc(), sigma=0.0, which="LM")
            order = np.argsort(w2)
            w2, phi = w2[order], phi[:, order]
        else:
            w2, phi = found
    if np.any(w2 <= 0):
        raise ValueError(f"eigenmodes: {int(np.sum(w2 <= 0))} non-positive eigenvalues: the "
                         "state is not a stable equilibrium (or a DOF is unrestrained)")
    return Modes(np.sqrt(w2), phi)


def subspace_modes(K, M, k, *, extra=8, tol=1e-9, maxiter=200, seed=0, cluster=1e-4):
    """(omega^2 (k,), shapes (n, k) mass-normalized) of the k lowest modes of sparse K, M
    by subspace iteration on K^-1 M (one sparse LU of K) with a block of k + ``extra``
    vectors and Rayleigh-Ritz each iteration, converged when every mode's residual
    |K phi - omega^2 M phi| / |K phi| < tol; None when K is singular, the Ritz problem
    is not definite or it does not converge in ``maxiter`` iterations.

    A cluster of more close modes than the block (the lines of a farm's identical
    platforms, a few 1e-6 apart) is never resolved: each residual stops at about the
    cluster's spread, and the Ritz values creep down inside it by ~1e-10 an iteration.
    Once they move by less than 1e-9 (relative) in an iteration with every residual below
    ``cluster``, that is returned: each frequency is a mode's of the cluster (its error is
    about the residual squared), the k lowest to within the cluster's spread, the shapes a
    basis of it."""
    n = K.shape[0]
    p = min(n, k + extra)
    try:
        lu = spla.splu(K)
    except RuntimeError:  # singular: not a stable equilibrium (eigsh will say)
        return None
    X = np.random.default_rng(seed).standard_normal((n, p))
    previous = None
    for _ in range(maxiter):
        Y, _ = np.linalg.qr(lu.solve(M @ X))
        KY, MY = K @ Y, M @ Y
        try:
            w2, Q = sla.eigh(Y.T @ KY, Y.T @ MY)
        except (np.linalg.LinAlgError, ValueError):
            return None
        X = Y @ Q  # M-orthonormal Ritz vectors, ascending
        KX, MX = KY @ Q[:, :k], MY @ Q[:, :k]
        scale = np.maximum(np.linalg.norm(KX, axis=0), np.finfo(float).tiny)
        residual = np.max(np.linalg.norm(KX - MX * w2[:k], axis=0) / scale)
        still = previous is not None and np.all(np.abs(w2[:k] - previous) <= 1e-9 * np.abs(w2[:k]))
        if residual < tol or (still and residual < cluster):
            return w2[:k], X[:, :k]
        previous = w2[:k].copy()
    return None


def _dense(A):
    return A.toarray() if hasattr(A, "toarray") else np.asarray(A)
