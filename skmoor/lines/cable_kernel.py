"""Compiled fast path of the forms for the time loop.

The scikit-fem forms (``forms``, ``hydro``, ``seabed``) define the physics; the kernels
evaluate the same integrands on the same quadrature points element by element in loops
compiled by numba, add the residual into a DOF vector and the derivatives into per-element
6x6 blocks, and :class:`ElementPattern` scatters the blocks into a matrix whose pattern is
fixed once. The tests hold every kernel equal to the assembly of its forms to round-off.

Kernel protocol (what :class:`~skmoor.coupling.system.System` calls): ``add_to(lines, u, ud, t,
R, Ke, Ce)`` adds the residual (N) into R (ndofs,) and, when Ke is not None, its
derivatives with respect to u (N/m) and to the velocity (N s/m) into the (nel, 6, 6)
blocks Ke and Ce, DOFs ordered [node i x, y, z, node j x, y, z] (on a Hermite LineSet
(nel, 12, 12), ``LineSet.element_dofs``; its cable kernel is
:class:`skmoor.lines.bending.HermiteKernel`).
"""
import numpy as np
from numba import njit

from ..fem.patterns import NO_BLOCKS, ElementPattern


class CableKernel:
    """Internal force and tangent of all lines of a :class:`~skmoor.lines.line.LineSet`: the
    forms ``cable_force`` + the reference force (Eq. 9), ``cable_tangent`` (Eq. 17) and
    ``axial_damping`` with its derivatives, on the mid-point quadrature, each element
    with its line's strain law (:mod:`skmoor.lines.laws`)."""

    _weights = None  # every element's quadrature weight, user-law elements included

    def __init__(self, lineset):
        f = lineset.cable_fields
        if f["T"].shape[1] != 1:
            raise ValueError("CableKernel: the cable basis must have one (mid-point) "
                             f"quadrature point per element, got {f['T'].shape[1]}")
        self.lineset = lineset
        self.Xp = f["Xp"][:, :, 0].T.copy()  # (nel, 3)
        self.T, self.EA, self.BA = f["T"][:, 0], f["EA"][:, 0], f["BA"][:, 0]  # (nel,)
        self.refresh_laws()
        lineset._kernels.append(self)
        self.h = lineset.element_lengths
        self.weight = lineset.cable_basis.dx[:, 0]  # quadrature weight = h
        t = lineset.mesh.t
        nodal = lineset.nodal_dofs
        # (nel, 3) each, int64 as the compiled step takes them: one compiled signature
        self.dofs_i, self.dofs_j = (np.asarray(nodal[t[k]], np.int64) for k in (0, 1))
        self.ndofs = lineset.ndofs
        self.pattern = ElementPattern(lineset)
        self._no_velocity = np.zeros(self.ndofs)
        # the displacement-free part of Eq. 9: the reference force minus int T X'.du' ds
        # on the mid-point rule (the T r' term of Eq. 11 carries +T X' at u = 0)
        self.constant = lineset.reference_force()
        self._call(np.zeros(self.ndofs), self._no_velocity, False, self.constant,
                   NO_BLOCKS, NO_BLOCKS, -1.0)
        # the elements of lines with a user's law carry no force here: its term
        # (skmoor.lines.user_law) carries all of their axial force (the constant above
        # counts them, as the term's force at u = 0 is their reference force)
        self._weights = self.weight
        self.weight = np.where(lineset.user_law_cells, 0.0, self._weights)

    def refresh_laws(self):
        """Read the strain laws' parameters from the LineSet's fields (:func:`law_table`),
        and which elements a user's law carries (in statics, a law about the static state
        leaves its elements here, with its static law)."""
        self.law, self.knots, self.coef = law_table(self.lineset.cable_fields)
        if self._weights is not None:  # (None while __init__ reads the laws first)
            self.weight = np.where(self.lineset.user_law_cells, 0.0, self._weights)

    def element_tension_and_strain(self, u, ud=None):
        """(nel,) tension (N; with ud, plus BA x strain rate) and strain of Eq. 3 (-) at
        the element mid-points (``LineSet.element_tension_and_strain``, compiled)."""
        tension, strain = np.empty(self.h.size), np.empty(self.h.size)
        _element_tension(self.Xp, self.T, self.law, self.knots, self.coef, self.BA, self.h,
                         self.dofs_i, self.dofs_j, u,
                         self._no_velocity if ud is None else ud, ud is not None,
                         tension, strain)
        return tension, strain

    def _call(self, u, ud, damped, R, Ke, Ce, sign):
        _cable(self.Xp, self.T, self.law, self.knots, self.coef, self.BA, self.h,
               self.weight, self.dofs_i, self.dofs_j, u, ud, damped, R, Ke, Ce, sign)

    def add_to(self, u, ud, R, Ke=None, Ce=None):
        """Add the internal force (Eq. 9) and, given the velocity ud, the axial damping
        into R (N); with Ke their u-derivatives (N/m), with Ce the ud-derivatives (N s/m)."""
        R += self.constant
        self._call(u, self._no_velocity if ud is None else ud, ud is not None, R,
                   NO_BLOCKS if Ke is None else Ke, NO_BLOCKS if Ce is None else Ce, 1.0)

    def evaluate(self, u, ud=None, tangent=True, layout="sparse"):
        """Internal force (Eq. 9 = Eq. 11 + reference part) plus, given the velocity ud,
        the axial damping (``forms.axial_damping``), N; with ``tangent`` its exact
        derivatives with respect to u (Eq. 17 and the damping's part, N/m) and to ud
        (N s/m, None without ud), in ``layout`` (see :meth:`ElementPattern.assemble`)."""
        return self.pattern.evaluate(lambda R, Ke, Ce: self.add_to(u, ud, R, Ke, Ce),
                                     tangent, layout, rate=ud is not None)

    def force(self, u):
        """Internal force vector (Eq. 9 = Eq. 11 + reference part), N."""
        return self.evaluate(u, tangent=False)[0]

    def force_and_tangent(self, u, layout="sparse"):
        """Internal force (N) and its exact tangent (Eq. 17, N/m)."""
        f, K, _ = self.evaluate(u, layout=layout)
        return f, K


def law_table(fields):
    """The strain laws' parameters at every quadrature point of ``fields`` (the forms'
    fields, (nel, nqp) each), point e * nqp + q in row e * nqp + q, rearranged for the
    compiled loops: law (nel nqp, 6) [green, tension_only, A, B, 1 + e_ref, EA] with S = A -
    B / lambda, dS/deps = B / lambda^3 (A = k (1 + e_ref) - T, B = k (1 + e0) - T0 of
    ``laws.axial_force``), and the hinges (nel nqp, m): knots x_j and coef c_j (each active
    hinge adds c_j (1 + e_ref) to A and c_j (1 + x_j) to B)."""
    p = {name: np.ravel(fields[name]) for name in ("green", "tension_only", "T0", "e0", "k",
                                                     "e_ref", "EA", "T")}
    grow = 1.0 + p["e_ref"]
    law = np.ascontiguousarray(np.stack(
        [p["green"], p["tension_only"], p["k"] * grow - p["T"],
         p["k"] * (1.0 + p["e0"]) - p["T0"], grow, p["EA"]], axis=1))
    shape = (len(fields["knots"]), law.shape[0])
    return (law, np.ascontiguousarray(np.reshape(fields["knots"], shape).T),
            np.ascontiguousarray(np.reshape(fields["coef"], shape).T))


@njit(cache=True)
def _stress(eps, T, law, knots, coef, e):
    """S(eps) and dS/deps of element e (``laws.stress_resultant``), N."""
    if law[e, 0] > 0.0:  # the paper's Eq. 6
        EA = law[e, 5]
        if T + EA * eps < 0.0:  # slack: compression kept times 1 - tension_only
            keep = 1.0 - law[e, 1]
            return keep * (T + EA * eps) - T, keep * EA
        return EA * eps, EA
    stretch = np.sqrt(1.0 + 2.0 * eps)
    A, B = law[e, 2], law[e, 3]
    if knots.shape[1] > 0:
        grow = law[e, 4]
        strain = grow * stretch - 1.0
        for j in range(knots.shape[1]):
            if strain > knots[e, j]:
                A += coef[e, j] * grow
                B += coef[e, j] * (1.0 + knots[e, j])
    S = A - B / stretch
    if T + S < 0.0:
        keep = 1.0 - law[e, 1]
        return keep * (T + S) - T, keep * B / stretch**3
    return S, B / stretch**3


@njit(cache=True)
def _stress_plain(eps, T, law, e):
    """``_stress`` of a law without hinges (every law but a curve; a separate loop body
    keeps the hinges' loop from slowing the element loop down by a third), N."""
    if law[e, 0] > 0.0:
        EA = law[e, 5]
        if T + EA * eps < 0.0:
            keep = 1.0 - law[e, 1]
            return keep * (T + EA * eps) - T, keep * EA
        return EA * eps, EA
    stretch = np.sqrt(1.0 + 2.0 * eps)
    S = law[e, 2] - law[e, 3] / stretch
    if T + S < 0.0:
        keep = 1.0 - law[e, 1]
        return keep * (T + S) - T, keep * law[e, 3] / stretch**3
    return S, law[e, 3] / stretch**3


@njit(cache=True)
def _element_tension(Xp, T, law, knots, coef, BA, h, dofs_i, dofs_j, u, ud, damped,
                     tension, strain):
    """tension[e] = (T + S + BA deps/dt) |r'| and strain[e] = eps at each mid-point."""
    for e in range(h.size):
        eps = 0.0
        rate = 0.0
        length = 0.0
        for c in range(3):
            up = (u[dofs_j[e, c]] - u[dofs_i[e, c]]) / h[e]
            rp = Xp[e, c] + up
            eps += (Xp[e, c] + 0.5 * up) * up
            rate += rp * (ud[dofs_j[e, c]] - ud[dofs_i[e, c]]) / h[e]
            length += rp * rp
        S, _ = _stress(eps, T[e], law, knots, coef, e)  # element-wise: not in the time loop
        tension[e] = (T[e] + S + (BA[e] * rate if damped else 0.0)) * np.sqrt(length)
        strain[e] = eps


@njit(cache=True)
def _cable(Xp, T, law, knots, coef, BA, h, weight, dofs_i, dofs_j, u, ud, damped, R, Ke,
           Ce, sign):
    """Adds sign x (Eq. 11 + axial damping) into R and their derivatives into Ke, Ce
    (when those have rows); one mid-point per element, weight[e] / h[e] = 1 for P1."""
    tangent = Ke.shape[0] > 0
    hinged = knots.shape[1] > 0
    if tangent:  # the tangent's scratch (a residual alone allocates nothing)
        rp, rate_slopes, k = np.empty(3), np.empty(3), np.empty((3, 3))
    for e in range(h.size):
        if weight[e] == 0.0:  # a user law's element (its own term)
            continue
        # the element's slopes in scalars (registers), 3-vectors only for the tangent
        i0, i1, i2, j0, j1, j2 = (dofs_i[e, 0], dofs_i[e, 1], dofs_i[e, 2],
                                  dofs_j[e, 0], dofs_j[e, 1], dofs_j[e, 2])
        he = h[e]
        ux, uy, uz = (u[j0] - u[i0]) / he, (u[j1] - u[i1]) / he, (u[j2] - u[i2]) / he
        rx, ry, rz = Xp[e, 0] + ux, Xp[e, 1] + uy, Xp[e, 2] + uz
        eps = (Xp[e, 0] + 0.5 * ux) * ux + (Xp[e, 1] + 0.5 * uy) * uy + (Xp[e, 2] + 0.5 * uz) * uz
        rate = 0.0
        if damped:
            vx, vy, vz = (ud[j0] - ud[i0]) / he, (ud[j1] - ud[i1]) / he, (ud[j2] - ud[i2]) / he
            rate = rx * vx + ry * vy + rz * vz
        if hinged:
            S, dS = _stress(eps, T[e], law, knots, coef, e)
        else:
            S, dS = _stress_plain(eps, T[e], law, e)
        axial = T[e] + S + (BA[e] * rate if damped else 0.0)
        flux = sign * weight[e] / he * axial
        R[j0] += flux * rx
        R[j1] += flux * ry
        R[j2] += flux * rz
        R[i0] -= flux * rx
        R[i1] -= flux * ry
        R[i2] -= flux * rz
        if not tangent:
            continue
        rp[0], rp[1], rp[2] = rx, ry, rz
        for c in range(3):
            rate_slopes[c] = (ud[dofs_j[e, c]] - ud[dofs_i[e, c]]) / he
        # d/du' (Eq. 17): S' r' r'^T + (T + S) I, plus the damping's BA (r' rate'^T + rate I)
        w2 = weight[e] / h[e] ** 2
        b = BA[e] if damped else 0.0
        for p in range(3):
            for q in range(3):
                k[p, q] = w2 * (dS * rp[p] * rp[q] + b * rp[p] * rate_slopes[q])
            k[p, p] += w2 * (T[e] + S + b * rate)
        _add_slope_blocks(Ke, e, k)
        if damped:
            for p in range(3):
                for q in range(3):
                    k[p, q] = w2 * b * rp[p] * rp[q]
            _add_slope_blocks(Ce, e, k)


@njit(cache=True)
def _add_slope_blocks(blocks, e, k):
    """Adds [[k, -k], [-k, k]] (a 3x3 k acting on the slope (u_j - u_i) / h) to blocks[e]."""
    for p in range(3):
        for q in range(3):
            blocks[e, p, q] += k[p, q]
            blocks[e, p, q + 3] -= k[p, q]
            blocks[e, p + 3, q] -= k[p, q]
            blocks[e, p + 3, q + 3] += k[p, q]
