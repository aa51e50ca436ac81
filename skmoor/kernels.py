"""Fast path of the standard cable forms for the time loop.

Same physics as ``forms.cable_force`` and ``forms.cable_tangent`` on the same (mid-point)
quadrature, plus the LineSet's reference force, evaluated element by element with numpy (P1: u' is constant on an
element) and scattered into a sparse matrix whose pattern is fixed once. The tests hold it
equal to the scikit-fem assembly to round-off.
"""
import numpy as np
import scipy.sparse as sp

from . import forms


class CableKernel:
    """Internal force and tangent of all lines of a :class:`~skmoor.line.LineSet`."""

    def __init__(self, lineset):
        f = lineset.cable_fields
        self.law = lineset.law
        self.Xp = np.moveaxis(f["Xp"], 0, -1)  # (nel, nqp, 3)
        self.T, self.EA = f["T"], f["EA"]  # (nel, nqp)
        h = lineset.element_lengths
        self.dx_h = lineset.cable_basis.dx / h[:, None]  # quadrature weights / h
        self.reference = lineset.reference_force()
        self.dx_h2 = self.dx_h / h[:, None]
        t = lineset.mesh.t
        nodal = lineset.nodal_dofs
        self.node_dofs = nodal  # (nnodes, 3)
        self.dofs_i, self.dofs_j = nodal[t[0]], nodal[t[1]]  # (nel, 3)
        self.h = h
        self.ndofs = lineset.ndofs
        edofs = np.concatenate([self.dofs_i, self.dofs_j], axis=1)  # (nel, 6)
        rows = np.repeat(edofs[:, :, None], 6, axis=2).ravel()
        cols = np.repeat(edofs[:, None, :], 6, axis=1).ravel()
        keys = rows.astype(np.int64) * self.ndofs + cols
        unique = np.unique(keys)
        self._scatter = np.searchsorted(unique, keys)
        indptr = np.searchsorted(unique // self.ndofs, np.arange(self.ndofs + 1))
        self._pattern = (unique % self.ndofs, indptr)
        self.nnz = len(unique)
        self._flat = keys  # positions in a dense (ndofs, ndofs) array

    def slopes(self, u):
        """(nel, 3) u' on each element."""
        return (u[self.dofs_j] - u[self.dofs_i]) / self.h[:, None]

    def _state(self, u):
        up = self.slopes(u)[:, None, :]  # (nel, 1, 3)
        rp = self.Xp + up  # (nel, nqp, 3)
        eps = (self.Xp * up).sum(-1) + 0.5 * (up * up).sum(-1)
        S = forms.stress_resultant(eps, self.T, self.EA, self.law)
        return rp, eps, S

    def _gather(self, rp, S):
        """Nodal internal forces: Eq. 11's int [(T + S) r' - T X'] ds / h per element,
        scattered, plus the reference force."""
        flux = (self.T + S)[..., None] * rp - self.T[..., None] * self.Xp
        g = np.einsum("eq,eqk->ek", self.dx_h, flux).ravel()  # (nel*3,)
        return (np.bincount(self.dofs_j.ravel(), g, self.ndofs)
                - np.bincount(self.dofs_i.ravel(), g, self.ndofs) + self.reference)

    def force(self, u):
        """Internal force vector (Eq. 9 = Eq. 11 + reference part), N."""
        rp, _, S = self._state(u)
        return self._gather(rp, S)

    def force_and_tangent(self, u, dense=False):
        """Internal force (N) and its exact tangent (Eq. 17, N/m): CSR, or a dense array
        when ``dense`` (cheaper for small models)."""
        rp, eps, S = self._state(u)
        dS = forms.stress_resultant_slope(eps, self.T, self.EA, self.law)
        k = np.einsum("eq,eqa,eqb->eab", self.dx_h2 * dS, rp, rp)
        k += np.einsum("eq->e", self.dx_h2 * (self.T + S))[:, None, None] * np.eye(3)
        ke = np.block([[k, -k], [-k, k]])  # (nel, 6, 6)
        if dense:
            K = np.bincount(self._flat, weights=ke.ravel(), minlength=self.ndofs**2)
            return self._gather(rp, S), K.reshape(self.ndofs, self.ndofs)
        data = np.bincount(self._scatter, weights=ke.ravel(), minlength=self.nnz)
        K = sp.csr_matrix((data, *self._pattern), shape=(self.ndofs, self.ndofs))
        return self._gather(rp, S), K
