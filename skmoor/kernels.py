"""Fast path of the standard cable forms for the time loop.

Same physics as ``forms.cable_force`` and ``forms.cable_tangent`` on the same (mid-point)
quadrature, plus the LineSet's reference force, evaluated element by element with numpy
(P1: u' is constant on an element, one quadrature point) and scattered into a sparse
matrix whose pattern is fixed once. The tests hold it
equal to the scikit-fem assembly to round-off.
"""
import numpy as np
import scipy.sparse as sp

from . import forms


class ElementPattern:
    """The fixed sparsity pattern of per-element 6x6 blocks on a LineSet, DOFs ordered
    [node i x, y, z, node j x, y, z] (i, j the element's ends). Every kernel of the time
    loop (cable, hydrodynamics, sea bed) scatters into it."""

    def __init__(self, lineset):
        nodal, t = lineset.nodal_dofs, lineset.mesh.t
        self.ndofs = n = lineset.ndofs
        self.edofs = np.concatenate([nodal[t[0]], nodal[t[1]]], axis=1)  # (nel, 6)
        rows = np.repeat(self.edofs[:, :, None], 6, axis=2).ravel()
        cols = np.repeat(self.edofs[:, None, :], 6, axis=1).ravel()
        keys = rows.astype(np.int64) * n + cols
        unique = np.unique(keys)
        self._scatter = np.searchsorted(unique, keys)
        self._pattern = (unique % n, np.searchsorted(unique // n, np.arange(n + 1)))
        self.nnz = len(unique)
        self._flat = keys  # positions in a dense (ndofs, ndofs) array

    def assemble(self, ke, dense=False):
        """(nel, 6, 6) element blocks summed into a CSR matrix, or a dense array."""
        if dense:
            return np.bincount(self._flat, ke.ravel(), self.ndofs**2).reshape(self.ndofs,
                                                                             self.ndofs)
        data = np.bincount(self._scatter, ke.ravel(), self.nnz)
        return sp.csr_matrix((data, *self._pattern), shape=(self.ndofs, self.ndofs))


class CableKernel:
    """Internal force and tangent of all lines of a :class:`~skmoor.line.LineSet`."""

    def __init__(self, lineset):
        f = lineset.cable_fields
        if f["T"].shape[1] != 1:
            raise ValueError("CableKernel: the cable basis must have one (mid-point) "
                             f"quadrature point per element, got {f['T'].shape[1]}")
        self.law = lineset.law
        self.Xp = f["Xp"][:, :, 0].T.copy()  # (nel, 3)
        self.T, self.EA, self.BA = f["T"][:, 0], f["EA"][:, 0], f["BA"][:, 0]  # (nel,)
        h = lineset.element_lengths
        self.dx_h = lineset.cable_basis.dx[:, 0] / h  # quadrature weight / h = 1
        self.dx_h2 = self.dx_h / h
        t = lineset.mesh.t
        nodal = lineset.nodal_dofs
        self.node_dofs = nodal  # (nnodes, 3)
        self.dofs_i, self.dofs_j = nodal[t[0]], nodal[t[1]]  # (nel, 3)
        self.h = h
        self.ndofs = lineset.ndofs
        self.pattern = ElementPattern(lineset)
        # the displacement-free part of Eq. 9: the reference force minus int T X'.du' ds
        # on the mid-point rule (the T r' term of Eq. 11 carries +T X' at u = 0)
        self.constant = lineset.reference_force() - self._scatter_flux(
            ((self.dx_h * self.T)[:, None] * self.Xp).ravel())

    def slopes(self, u):
        """(nel, 3) u' on each element."""
        return (u[self.dofs_j] - u[self.dofs_i]) / self.h[:, None]

    def evaluate(self, u, ud=None, tangent=True, dense=False):
        """Internal force (Eq. 9 = Eq. 11 + reference part) plus, given the velocity ud,
        the axial damping (``forms.axial_damping``), N; with ``tangent`` its exact
        derivatives with respect to u (Eq. 17 and the damping's part, N/m) and to ud
        (N s/m, None without ud): CSR, or dense arrays when ``dense``."""
        if not tangent:
            return self._force(u, ud)[0], None, None
        f, K, Kv = self.element_blocks(u, ud)
        return (f, self.pattern.assemble(K, dense),
                None if Kv is None else self.pattern.assemble(Kv, dense))

    def element_blocks(self, u, ud=None):
        """As :meth:`evaluate` with the derivatives as (nel, 6, 6) element blocks on
        :attr:`pattern`, for summing with other kernels' before one assembly."""
        f, (up, rp, eps, S, rate_slopes, rate) = self._force(u, ud)
        dS = forms.stress_resultant_slope(eps, self.T, self.EA, self.law)
        rr = rp[:, :, None] * rp[:, None, :]
        k = (self.dx_h2 * dS)[:, None, None] * rr
        k += (self.dx_h2 * (self.T + S))[:, None, None] * np.eye(3)
        if ud is None:
            return f, _slope_blocks(k), None
        b = (self.dx_h2 * self.BA)[:, None, None]
        k += b * (rp[:, :, None] * rate_slopes[:, None, :] + rate[:, None, None] * np.eye(3))
        return f, _slope_blocks(k), _slope_blocks(b * rr)

    def _force(self, u, ud):
        """The force (N) and the element state it was computed from."""
        up = self.slopes(u)
        rp = self.Xp + up  # (nel, 3)
        eps = ((self.Xp + 0.5 * up) * up).sum(-1)
        S = forms.stress_resultant(eps, self.T, self.EA, self.law)
        axial = self.T + S
        rate_slopes = rate = None
        if ud is not None:
            rate_slopes = self.slopes(ud)
            rate = (rp * rate_slopes).sum(-1)  # strain rate, 1/s
            axial = axial + self.BA * rate
        f = self._scatter_flux(((self.dx_h * axial)[:, None] * rp).ravel()) + self.constant
        return f, (up, rp, eps, S, rate_slopes, rate)

    def _scatter_flux(self, g):
        """Nodal forces of per-element axial fluxes g (nel*3,): +g at the end node, -g at
        the start node."""
        return (np.bincount(self.dofs_j.ravel(), g, self.ndofs)
                - np.bincount(self.dofs_i.ravel(), g, self.ndofs))

    def force(self, u):
        """Internal force vector (Eq. 9 = Eq. 11 + reference part), N."""
        return self.evaluate(u, tangent=False)[0]

    def force_and_tangent(self, u, dense=False):
        """Internal force (N) and its exact tangent (Eq. 17, N/m)."""
        f, K, _ = self.evaluate(u, dense=dense)
        return f, K


def _slope_blocks(k):
    """(nel, 6, 6) element blocks of per-element 3x3 blocks k acting on the slopes
    (u_j - u_i) / h: [[k, -k], [-k, k]]."""
    return np.block([[k, -k], [-k, k]])
