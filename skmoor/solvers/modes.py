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

    Dense LAPACK below ``dense_below`` unknowns, shift-invert ``eigsh`` above.
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
        Ks = 0.5 * (K + K.T)
        w2, phi = spla.eigsh(Ks.tocsc(), k=k, M=M.tocsc(), sigma=0.0, which="LM")
        order = np.argsort(w2)
        w2, phi = w2[order], phi[:, order]
    if np.any(w2 <= 0):
        raise ValueError(f"eigenmodes: {int(np.sum(w2 <= 0))} non-positive eigenvalues: the "
                         "state is not a stable equilibrium (or a DOF is unrestrained)")
    return Modes(np.sqrt(w2), phi)


def _dense(A):
    return A.toarray() if hasattr(A, "toarray") else np.asarray(A)
