"""Banded matrices: LAPACK's band storage with the arithmetic the time loop needs.

Lines without a body couple each node to its neighbours only, so with node-major DOFs
their matrices are banded (half-bandwidth 5 for one line); LAPACK's banded LU then costs
O(n) per factorization and per solve, against O(n^3) dense and SuperLU's overhead.
"""
import numpy as np
import scipy.sparse as sp
from numba import njit
from scipy.linalg import lapack


class Band:
    """An (n, n) matrix with kl sub- and ku super-diagonals in LAPACK's ``gbtrf`` storage:
    A[i, j] is ``ab[kl + ku + i - j, j]`` (the first kl rows are the factorization's
    workspace), ab Fortran-ordered."""

    __array_ufunc__ = None  # numpy scalars defer to __rmul__

    def __init__(self, ab, kl, ku):
        self.ab, self.kl, self.ku = ab, kl, ku
        self.shape = (ab.shape[1], ab.shape[1])

    @staticmethod
    def rows(kl, ku):
        """Rows of the band storage for kl, ku."""
        return 2 * kl + ku + 1

    @classmethod
    def from_matrix(cls, A, kl, ku):
        """A sparse or dense matrix in band storage; entries outside the band raise."""
        A = sp.coo_matrix(A)
        offset = A.col - A.row
        outside = (offset > ku) | (-offset > kl)
        if np.any(outside & (A.data != 0)):
            raise ValueError(f"Band: the matrix has entries outside kl = {kl}, ku = {ku}")
        ab = np.zeros((cls.rows(kl, ku), A.shape[1]), order="F")
        keep = ~outside
        np.add.at(ab, (kl + ku - offset[keep], A.col[keep]), A.data[keep])
        return cls(ab, kl, ku)

    def toarray(self):
        n, out = self.shape[0], np.zeros(self.shape)
        for d in range(-self.kl, self.ku + 1):  # d = j - i
            i = np.arange(max(0, -d), min(n, n - d))
            out[i, i + d] = self.ab[self.kl + self.ku - d, i + d]
        return out

    def __add__(self, other):
        if isinstance(other, Band) and (other.kl, other.ku) == (self.kl, self.ku):
            return Band(self.ab + other.ab, self.kl, self.ku)
        return NotImplemented

    def __mul__(self, scalar):
        return Band(self.ab * float(scalar), self.kl, self.ku)

    __rmul__ = __mul__

    def __matmul__(self, x):
        return _matvec(self.ab, self.kl, self.ku, np.asarray(x, float))

    def factorize(self):
        """A solver b -> A^-1 b (LAPACK gbtrf, then gbtrs per call), or None when A is
        singular."""
        if self.shape[0] == 0:  # no unknowns (a network of coupled objects alone)
            return lambda b: np.asarray(b, float)
        lu, piv, info = lapack.dgbtrf(self.ab, self.kl, self.ku)
        if info > 0:
            return None
        return BandSolver(lu, piv, self.kl, self.ku)


class BandSolver:
    """b -> A^-1 b from a band LU (LAPACK gbtrs); an object, so that a checkpoint of the
    Newton matrix it belongs to can be written (pickled)."""

    def __init__(self, lu, piv, kl, ku):
        self.lu, self.piv, self.kl, self.ku = lu, piv, kl, ku

    def __call__(self, b):
        return lapack.dgbtrs(self.lu, self.kl, self.ku, b, self.piv)[0]


LAYOUTS = ("sparse", "dense", "band")


def as_layout(A, layout, bandwidth=None):
    """A sparse or dense matrix as ``layout``: 'sparse' (CSR), 'dense' (an array) or
    'band' (a :class:`Band` with kl = ku = bandwidth)."""
    if layout == "dense":
        return A.toarray() if sp.issparse(A) else np.asarray(A)
    if layout == "band":
        return Band.from_matrix(A, bandwidth, bandwidth)
    if layout == "sparse":
        return sp.csr_matrix(A)
    raise ValueError(f"layout: {layout!r} is not one of {LAYOUTS}")


@njit(cache=True)
def _matvec(ab, kl, ku, x):
    n = x.size
    y = np.zeros(n)
    for j in range(n):
        for i in range(max(0, j - ku), min(n, j + kl + 1)):
            y[i] += ab[kl + ku + i - j, j] * x[j]
    return y
