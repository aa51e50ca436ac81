"""The element-block pattern: per-element tangent blocks scattered into a matrix whose
sparsity is fixed once (CSR, dense or band).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numba import njit

from ..numerics.banded import Band

NO_BLOCKS = np.zeros((0, 6, 6))  # stands for "no tangent" in the compiled loops
NO_BLOCKS_12 = np.zeros((0, 12, 12))  # the same on bending (Hermite) lines


class ElementPattern:
    """The fixed sparsity pattern of per-element blocks on a LineSet (nloc x nloc, nloc
    the element's DOF count: 6 on P1, 12 on Hermite), mapped by
    ``position`` (ndofs,): the row / column each cable DOF goes to, -1 to drop it (as the
    held DOFs of a System without bodies); several DOFs may share one (line ends on one
    free point). Default: the identity."""

    def __init__(self, lineset, position=None):
        edofs = lineset.element_dofs  # (nel, nloc)
        self.nel, self.nloc = edofs.shape
        position = np.arange(lineset.ndofs) if position is None else np.asarray(position)
        self.ndofs = n = int(position.max()) + 1
        rows = position[np.repeat(edofs[:, :, None], self.nloc, axis=2).ravel()]
        cols = position[np.repeat(edofs[:, None, :], self.nloc, axis=1).ravel()]
        kept = (rows >= 0) & (cols >= 0)
        keys = np.where(kept, rows.astype(np.int64) * n + cols, -1)
        unique = np.unique(keys[kept])
        self._sparse = np.where(kept, np.searchsorted(unique, keys), -1)
        self._dense = keys  # positions in a dense (ndofs, ndofs) array
        self._pattern = (unique % n, np.searchsorted(unique // n, np.arange(n + 1)))
        self.nnz = len(unique)
        # half-bandwidth, and positions in LAPACK band storage (Fortran order, banded.Band)
        self.bandwidth = bw = int(np.max(np.abs(rows - cols)[kept], initial=0))
        self._band = np.where(kept, (2 * bw + rows - cols) + cols * Band.rows(bw, bw), -1)

    def evaluate(self, add_to, tangent=True, layout="sparse", rate=True):
        """(R, K, Kv) of a kernel's ``add_to(R, Ke, Ce)`` on the full DOFs: R (ndofs,),
        K and Kv assembled in ``layout`` (None without ``tangent``, Kv None unless
        ``rate``)."""
        R = np.zeros(self.ndofs)
        if not tangent:
            add_to(R, None, None)
            return R, None, None
        Ke, Ce = (np.zeros((self.nel, self.nloc, self.nloc)) for _ in range(2))
        add_to(R, Ke, Ce)
        return R, self.assemble(Ke, layout), self.assemble(Ce, layout) if rate else None

    def assemble(self, ke, layout="sparse"):
        """(nel, nloc, nloc) element blocks summed into a matrix: 'sparse' (CSR), 'dense' (an
        array) or 'band' (a :class:`~skmoor.numerics.banded.Band`, kl = ku = :attr:`bandwidth`)."""
        n = self.ndofs
        if layout == "dense":
            return _scatter(ke.ravel(), self._dense, n * n).reshape(n, n)
        if layout == "band":
            rows, bw = Band.rows(self.bandwidth, self.bandwidth), self.bandwidth
            ab = _scatter(ke.ravel(), self._band, rows * n).reshape((rows, n), order="F")
            return Band(ab, bw, bw)
        data = _scatter(ke.ravel(), self._sparse, self.nnz)
        return sp.csr_matrix((data, *self._pattern), shape=(n, n))


@njit(cache=True)
def _scatter(values, index, size):
    """out[index[k]] += values[k], skipping index -1."""
    out = np.zeros(size)
    for k in range(index.size):
        if index[k] >= 0:
            out[index[k]] += values[k]
    return out
