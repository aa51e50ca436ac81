"""Bending stiffness on the C1 line element: the cable's forms plus one bending form.

A line with EI > 0 (N m2) lives on scikit-fem's Hermite line element, vector-valued
(``ElementVector(ElementLineHermite(), 3)``): at each node the displacement u and its
arclength derivative u' (the change of the tangent), so that the position r = X + u has a
continuous tangent and a square-integrable second derivative. With s the reference
arclength, the bending energy of the absolute-nodal-coordinate cable element (Gerstmayr &
Shabana 2006, Nonlinear Dyn. 45, Eq. 11; Dufva, Sopanen & Mikkola 2005) is

    U_b = 1/2 int EI |r''|^2 ds,    r'' = X'' + u'',

whose first variation is the internal virtual work int EI (X'' + u'') . du'' ds (the form
:func:`bending_force`); it is linear in u, with the tangent int EI du'' . v''
(:func:`bending_tangent`). For a line of unit stretch |r''| is its curvature, so the
unstressed shape is straight (MoorDyn's convention) and a reference state that is curved
(a catenary) starts with the bending moment EI |X''|. The cable forms (Eqs. 11, 17 of
:mod:`skmoor.lines.cable_forms`), the weight, the mass, the hydrodynamic and sea-bed forms are the
same integrands on this element.

Reported along the line: the curvature kappa = |r' x r''| / |r'|^3 (1/m) and the bending
moment EI kappa (N m) at the element mid-points.

Line ends are pinned (the end tangent free) unless clamped (the end's slope DOFs held at
the reference tangent; see :class:`skmoor.coupling.system.Ends`).

:class:`HermiteKernel` evaluates the cable, axial damping and bending forms element by
element, vectorized over elements and Gauss points, into (nel, 12, 12) element blocks
(DOFs [node i x, y, z, x', y', z', node j ...]); the tests hold it equal to the forms'
assembly.
"""
from __future__ import annotations

import numpy as np
from skfem import Basis, BilinearForm, LinearForm

from ..fem.hermite import hermite_shapes
from ..fem.ops import dot
from . import laws


def d2_ds2(field):
    """d2/ds2 of a vector field in a form on the Hermite element, shape (3, nel, nqp)."""
    return field.hess[:, 0, 0]


@LinearForm
def bending_force(v, w):
    # delta U_b, U_b = 1/2 int EI |X'' + u''|^2 ds (Gerstmayr & Shabana 2006, Eq. 11)
    return w.EI * dot(w.Xpp + d2_ds2(w.u), d2_ds2(v))


@BilinearForm
def bending_tangent(du, v, w):
    # d(bending_force)/du = int EI du'' . v'' ds
    return w.EI * dot(d2_ds2(du), d2_ds2(v))


class HermiteKernel:
    """Internal force and tangent of all lines of a Hermite :class:`~skmoor.lines.line.LineSet`:
    ``forms.cable_force`` + the reference force (Eq. 9), ``forms.axial_damping`` and
    :func:`bending_force`, with their exact derivatives, on the LineSet's Gauss points
    (the kernel protocol of :mod:`skmoor.lines.cable_kernel`, blocks (nel, 12, 12))."""

    def __init__(self, lineset):
        from ..fem.patterns import ElementPattern

        if not lineset.hermite:
            raise ValueError("HermiteKernel: the LineSet is on P1 elements (no EI > 0)")
        self.lineset = lineset
        basis, f = lineset.basis, lineset.fields
        self.h = lineset.element_lengths
        self.edofs = lineset.element_dofs  # (nel, 12)
        _, self.dN, self.d2N = hermite_shapes(basis.X[0], self.h)
        self.dx = basis.dx  # (nel, nqp)
        self.Xp = np.moveaxis(f["Xp"], 0, -1)  # (nel, nqp, 3)
        self.Xpp = np.moveaxis(f["Xpp"], 0, -1)
        self.T, self.EI, self.BA = f["T"], f["EI"], f["BA"]
        self.fields = f
        self.ndofs = lineset.ndofs
        self.pattern = ElementPattern(lineset)
        self.constant = lineset.reference_force()
        lineset._kernels.append(self)
        _, dNm, d2Nm = hermite_shapes(np.array([0.5]), self.h)
        self._midpoint = (dNm, d2Nm)
        middle = Basis(lineset.mesh, lineset.basis.elem,
                       quadrature=(np.array([[0.5]]), np.array([1.0])))
        self._middle_fields = {k: v[..., 0] for k, v in lineset._fields(middle).items()}
        # constant parts: the weighted test slopes, the pairs of slopes per point and the
        # bending form (linear in u): its blocks and its force at u = 0, EI X'' . v''
        nel, nqp = self.dx.shape
        self._wdN = np.ascontiguousarray((self.dx[..., None] * self.dN).transpose(0, 2, 1))
        self._pairs = np.ascontiguousarray(
            (self.dx[..., None, None] * self.dN[..., :, None] * self.dN[..., None, :])
            .reshape(nel, nqp, 16).transpose(0, 2, 1))
        weights = np.einsum("eq,eqi,eqj->eij", self.dx * self.EI, self.d2N, self.d2N)
        self._bending_blocks = np.einsum("eij,cd->eicjd", weights, np.eye(3)).reshape(nel, 12, 12)
        self._bending_force = np.einsum("eq,eqb,eqc->ebc", self.dx * self.EI, self.d2N, self.Xpp)

    def refresh_laws(self):
        """The law parameters are read from the LineSet's fields at each call."""

    def _slopes(self, u, dN):
        """(nel, nqp, 3) d/ds (or d2/ds2 with d2N) of the field u at the points of dN."""
        U = u[self.edofs].reshape(-1, 4, 3)
        return np.einsum("eqb,ebc->eqc", dN, U)

    def add_to(self, u, ud, R, Ke=None, Ce=None):
        """Add the internal force (Eq. 9 + bending) and, given the velocity ud, the axial
        damping into R (N); with Ke their u-derivatives (N/m), with Ce the ud-derivatives."""
        up = self._slopes(u, self.dN)
        rp = self.Xp + up
        eps = np.einsum("eqc,eqc->eq", self.Xp + 0.5 * up, up)  # Eq. 3
        S, dS = laws.stress_resultant(eps, self.T, self.fields)
        damped = ud is not None
        if damped:
            rate_slopes = self._slopes(ud, self.dN)
            rate = np.einsum("eqc,eqc->eq", rp, rate_slopes)
            axial = S + self.BA * rate
        else:
            axial = S
        flux = axial[..., None] * rp + self.T[..., None] * up  # Eq. 11 (+ damping)
        # int (flux . v' + EI r'' . v'') ds; the bending part is linear: K_b u + f_b
        Re = (np.matmul(self._wdN, flux) + self._bending_force).reshape(-1, 12)
        Re += np.matmul(self._bending_blocks, u[self.edofs][..., None])[..., 0]
        R += self.constant
        np.add.at(R, self.edofs, Re)
        if Ke is None:
            return
        # d flux / du' (Eq. 17): S' r' r'^T + (T + S + BA rate) I + BA r' rate'^T
        k = dS[..., None, None] * rp[..., :, None] * rp[..., None, :]
        k[..., [0, 1, 2], [0, 1, 2]] += (self.T + axial)[..., None]
        if damped:
            k += self.BA[..., None, None] * rp[..., :, None] * rate_slopes[..., None, :]
        Ke += self._slope_blocks(k) + self._bending_blocks
        if damped and Ce is not None:
            Ce += self._slope_blocks(self.BA[..., None, None] * rp[..., :, None] * rp[..., None, :])

    def _slope_blocks(self, k):
        """(nel, 12, 12) blocks of int v'^T k du' ds for k (nel, nqp, 3, 3) at the points."""
        nel, nqp = self.dx.shape
        pairs = np.matmul(self._pairs, k.reshape(nel, nqp, 9))  # (nel, 16, 9)
        return pairs.reshape(nel, 4, 4, 3, 3).transpose(0, 1, 3, 2, 4).reshape(nel, 12, 12)

    def evaluate(self, u, ud=None, tangent=True, layout="sparse"):
        """(R, K, Kv) as :meth:`skmoor.lines.cable_kernel.CableKernel.evaluate`."""
        return self.pattern.evaluate(lambda R, Ke, Ce: self.add_to(u, ud, R, Ke, Ce),
                                     tangent, layout, rate=ud is not None)

    def midpoint_slopes(self, u):
        """(r', r'') at the element mid-points, (nel, 3) each (r = X + u, 1 and 1/m)."""
        dN, d2N = self._midpoint
        U = (self.lineset.reference_dofs + u)[self.edofs].reshape(-1, 4, 3)
        return (np.einsum("eqb,ebc->eqc", dN, U)[:, 0],
                np.einsum("eqb,ebc->eqc", d2N, U)[:, 0])

    def element_tension_and_strain(self, u, ud=None):
        """(nel,) tension (N; with ud, plus BA x strain rate) and strain of Eq. 3 (-) at
        the element mid-points."""
        point = self._middle_fields  # the reference fields at the mid-points, (nel,) each
        dN, _ = self._midpoint
        Xp, up = point["Xp"].T, self._slopes(u, dN)[:, 0]
        rp = Xp + up
        eps = np.einsum("ec,ec->e", Xp + 0.5 * up, up)  # Eq. 3
        S, _ = laws.stress_resultant(eps, point["T"], point)
        axial = point["T"] + S
        if ud is not None:
            axial = axial + point["BA"] * np.einsum("ec,ec->e", rp, self._slopes(ud, dN)[:, 0])
        return axial * np.linalg.norm(rp, axis=1), eps

    def curvature(self, u):
        """(nel,) curvature |r' x r''| / |r'|^3 at the element mid-points, 1/m."""
        rp, rpp = self.midpoint_slopes(u)
        return (np.linalg.norm(np.cross(rp, rpp), axis=1)
                / np.linalg.norm(rp, axis=1) ** 3)
