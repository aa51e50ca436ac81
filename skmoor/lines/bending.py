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
element in a compiled loop (:func:`_hermite`, which the compiled time step calls too) into
(nel, 12, 12) element blocks (DOFs [node i x, y, z, x', y', z', node j ...]); the tests
hold it equal to the forms' assembly.
"""
from __future__ import annotations

import math

import numpy as np
from numba import carray, njit
from skfem import BilinearForm, LinearForm, asm

from ..fem.form_compiler import compiled_when_asked
from ..fem.hermite import hermite_shapes
from ..fem.ops import dot
from ..fem.patterns import NO_BLOCKS_12, ElementPattern
from .cable_forms import reference_force
from .cable_kernel import _stress, _stress_plain, law_table


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
    (the kernel protocol of :mod:`skmoor.lines.cable_kernel`, blocks (nel, 12, 12)),
    compiled (:func:`_hermite`); the compiled time step calls the same loop."""

    def __init__(self, lineset):
        if not lineset.hermite:
            raise ValueError("HermiteKernel: the LineSet is on P1 elements (no EI > 0)")
        self.lineset = lineset
        basis, f = lineset.basis, lineset.fields
        self.h = lineset.element_lengths
        self.edofs = np.ascontiguousarray(lineset.element_dofs, np.int64)  # (nel, 12)
        _, dN, d2N = hermite_shapes(basis.X[0], self.h)
        # each Gauss point's shape-function slopes N_a' (1/m) and weight (m): (nel, nqp, 5)
        self.shapes = np.ascontiguousarray(np.concatenate([dN, basis.dx[..., None]], axis=-1))
        self.Xp = np.ascontiguousarray(np.moveaxis(f["Xp"], 0, -1).reshape(-1, 3))  # per point
        self.Xpp = np.moveaxis(f["Xpp"], 0, -1)
        self.fields = f
        self.ndofs = lineset.ndofs
        self.pattern = ElementPattern(lineset)
        self.refresh_laws()
        lineset._kernels.append(self)
        self.constant = lineset.reference_force()
        users = lineset.user_law_cells
        if users.any():  # a user's law: its term (skmoor.lines.user_law) carries the whole
            # axial force of its elements, their reference part with it
            self.shapes[users, :, 4] = 0.0
            self.constant -= asm(reference_force, basis, Xp=f["Xp"],
                                 T=f["T"] * users[:, None])
        _, dNm, d2Nm = hermite_shapes(np.array([0.5]), self.h)
        self._midpoint = (dNm, d2Nm)
        self._middle_fields = lineset.midpoint_fields()
        # the bending form is linear in u: its 4 x 4 weights (the same on x, y and z) and
        # its force at u = 0, EI X'' . v'', side by side (nel, 4, 7)
        weighted = basis.dx * f["EI"]
        self.bending = np.ascontiguousarray(np.concatenate(
            [np.einsum("eq,eqi,eqj->eij", weighted, d2N, d2N),
             np.einsum("eq,eqb,eqc->ebc", weighted, d2N, self.Xpp)], axis=-1))
        self._no_velocity = np.zeros(self.ndofs)
        self._middle = None  # _at_midpoints' arrays

    def refresh_laws(self):
        """Read the strain laws' parameters and the reference fields from the LineSet's
        fields, one row per Gauss point (:func:`~skmoor.lines.cable_kernel.law_table`)."""
        f = self.fields
        self.T, self.BA = (np.ascontiguousarray(np.ravel(f[name])) for name in ("T", "BA"))
        self.law, self.knots, self.coef = law_table(f)

    def step_arrays(self):
        """The arrays :func:`_hermite` reads before the state, in its order."""
        return (self.shapes, self.Xp, self.T, self.law, self.knots, self.coef, self.BA,
                self.bending, self.edofs)

    @property
    def step_kernel(self):
        """(C function, ints, floats): this loop as the compiled time step calls a user's
        LineForm (:data:`~skmoor.fem.form_compiler.STEP_SIGNATURE`, by address), its arrays
        packed in two buffers: ints [nel, nqp, hinges, damped, element DOFs], floats
        [shapes, X', T, BA, law, knots, coef, bending]."""
        nel, nqp = self.shapes.shape[:2]
        ints = np.concatenate([[nel, nqp, self.knots.shape[1], int(self.lineset.damped)],
                               self.edofs.ravel()]).astype(np.int64)
        floats = np.concatenate([np.ravel(a) for a in (self.shapes, self.Xp, self.T, self.BA,
                                                       self.law, self.knots, self.coef,
                                                       self.bending)]).astype(float)
        return _hermite_step(), ints, floats

    def add_to(self, u, ud, R, Ke=None, Ce=None):
        """Add the internal force (Eq. 9 + bending) and, given the velocity ud, the axial
        damping into R (N); with Ke their u-derivatives (N/m), with Ce the ud-derivatives."""
        R += self.constant
        _hermite(*self.step_arrays(), u, self._no_velocity if ud is None else ud,
                 ud is not None, R, NO_BLOCKS_12 if Ke is None else Ke,
                 NO_BLOCKS_12 if Ce is None else Ce)

    def evaluate(self, u, ud=None, tangent=True, layout="sparse"):
        """(R, K, Kv) as :meth:`skmoor.lines.cable_kernel.CableKernel.evaluate`."""
        return self.pattern.evaluate(lambda R, Ke, Ce: self.add_to(u, ud, R, Ke, Ce),
                                     tangent, layout, rate=ud is not None)

    def _at_midpoints(self, u, ud=None):
        """(tension N, strain -, curvature 1/m), (nel,) each, at the element mid-points."""
        if self._middle is None:  # the reference fields and laws there, made once
            point = self._middle_fields
            dN, d2N = self._midpoint
            self._middle = (np.ascontiguousarray(dN[:, 0]), np.ascontiguousarray(d2N[:, 0]),
                            np.ascontiguousarray(point["Xp"].T), point["T"], point["BA"],
                            *law_table(point))
        out = np.empty((3, len(self.h)))
        _midpoints(*self._middle, self.lineset.reference_dofs, self.edofs, u,
                   self._no_velocity if ud is None else ud, ud is not None, out)
        return out

    def element_tension_and_strain(self, u, ud=None):
        """(nel,) tension (N; with ud, plus BA x strain rate) and strain of Eq. 3 (-) at
        the element mid-points."""
        tension, strain, _ = self._at_midpoints(u, ud)
        return tension, strain

    def curvature(self, u):
        """(nel,) curvature |r' x r''| / |r'|^3 at the element mid-points, 1/m."""
        return self._at_midpoints(u)[2]


@njit(cache=True)
def _midpoints(dN, d2N, Xp, T, BA, law, knots, coef, reference, edofs, u, ud, damped, out):
    """Into out[0], out[1], out[2] (nel,): the tension (T + S + BA deps/dt) |r'| (N), the
    strain eps of Eq. 3 and the curvature |r' x r''| / |r'|^3 (1/m) at the mid-points,
    where dN, d2N (nel, 4) are the shape functions' d/ds and d2/ds2 and Xp, T, BA the
    reference fields."""
    up, vp, rp, rpp = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    for e in range(edofs.shape[0]):
        for c in range(3):
            up[c] = vp[c] = rpp[c] = 0.0
            for b in range(4):
                g = edofs[e, 3 * b + c]
                up[c] += dN[e, b] * u[g]
                vp[c] += dN[e, b] * ud[g]
                rpp[c] += d2N[e, b] * (reference[g] + u[g])
            rp[c] = Xp[e, c] + up[c]
        eps = 0.0
        rate = 0.0
        for c in range(3):
            eps += (Xp[e, c] + 0.5 * up[c]) * up[c]  # Eq. 3
            rate += rp[c] * vp[c]
        S, _ = _stress(eps, T[e], law, knots, coef, e)
        length = math.sqrt(rp[0] ** 2 + rp[1] ** 2 + rp[2] ** 2)
        out[0, e] = (T[e] + S + (BA[e] * rate if damped else 0.0)) * length
        out[1, e] = eps
        bent = ((rp[1] * rpp[2] - rp[2] * rpp[1]) ** 2 + (rp[2] * rpp[0] - rp[0] * rpp[2]) ** 2
                + (rp[0] * rpp[1] - rp[1] * rpp[0]) ** 2)
        out[2, e] = math.sqrt(bent) / length**3


# (over 60 lines: the cable, damping and bending forms at every Gauss point, one pass)
@njit(cache=True)
def _hermite(shapes, Xp, T, law, knots, coef, BA, bending, edofs, u, ud, damped, R, Ke, Ce):
    """Adds Eq. 11 (as S r' + T u', the reference force being added apart), the axial
    damping BA deps/dt r' and the bending form (:func:`bending_force`) into R, and their
    derivatives into Ke, Ce (when those have rows): ``HermiteKernel.add_to``'s loop.
    shapes (nel, nqp, 5): the shape functions' d/ds and the Gauss weight (m) at each point;
    Xp, T, BA, law, knots, coef: a row per point (e nqp + q); bending (nel, 4, 7): int EI
    N_a'' N_b'' ds in [..., :4] and int EI N_a'' X'' ds in [..., 4:]."""
    tangent = Ke.shape[0] > 0
    hinged = knots.shape[1] > 0  # a curve law's hinges (a loop of its own, as in _cable)
    nel, nqp = shapes.shape[0], shapes.shape[1]
    U, V = np.empty((4, 3)), np.empty((4, 3))  # the element's nodal values and slopes
    up, rp, vp, flux = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    k = np.empty((3, 3))
    for e in range(nel):
        for b in range(4):
            for c in range(3):
                U[b, c] = u[edofs[e, 3 * b + c]]
                V[b, c] = ud[edofs[e, 3 * b + c]]
        for a in range(4):  # bending: int EI (X'' + u'') . v'' ds, linear in u
            for c in range(3):
                s = bending[e, a, 4 + c]
                for b in range(4):
                    s += bending[e, a, b] * U[b, c]
                R[edofs[e, 3 * a + c]] += s
                if tangent:
                    for b in range(4):
                        Ke[e, 3 * a + c, 3 * b + c] += bending[e, a, b]
        for q in range(nqp):
            point = e * nqp + q
            eps = 0.0
            rate = 0.0
            for c in range(3):
                s = 0.0
                t = 0.0
                for b in range(4):
                    s += shapes[e, q, b] * U[b, c]
                    t += shapes[e, q, b] * V[b, c]
                up[c], vp[c] = s, t
                rp[c] = Xp[point, c] + s
                eps += (Xp[point, c] + 0.5 * s) * s  # Eq. 3
                rate += rp[c] * t
            if hinged:
                S, dS = _stress(eps, T[point], law, knots, coef, point)
            else:
                S, dS = _stress_plain(eps, T[point], law, point)
            damping = BA[point] if damped else 0.0
            axial = S + damping * rate
            for c in range(3):  # Eq. 11 less its reference part, plus the damping
                flux[c] = axial * rp[c] + T[point] * up[c]
            for a in range(4):
                w = shapes[e, q, 4] * shapes[e, q, a]
                for c in range(3):
                    R[edofs[e, 3 * a + c]] += w * flux[c]
            if not tangent:
                continue
            # d flux / du' (Eq. 17): S' r' r'^T + (T + S + BA rate) I + BA r' rate'^T
            for c in range(3):
                for d in range(3):
                    k[c, d] = dS * rp[c] * rp[d] + damping * rp[c] * vp[d]
                k[c, c] += T[point] + axial
            _add_pairs(Ke, e, shapes[e, q], k)
            if damped:
                for c in range(3):
                    for d in range(3):
                        k[c, d] = damping * rp[c] * rp[d]
                _add_pairs(Ce, e, shapes[e, q], k)


@njit(cache=True)
def _add_pairs(blocks, e, point, k):
    """blocks[e] += w N_a' N_b' k (k 3 x 3 acting on the slope u'; point: N_0' ... N_3', w)."""
    for a in range(4):
        for b in range(4):
            w = point[4] * point[a] * point[b]
            for c in range(3):
                for d in range(3):
                    blocks[e, 3 * a + c, 3 * b + d] += w * k[c, d]


def _hermite_packed(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """:func:`_hermite` on the buffers of ``HermiteKernel.step_kernel``."""
    nel, nqp, hinges, damped = ints[0], ints[1], ints[2], ints[3]
    points = nel * nqp
    edofs = carray(ints, (4 + 12 * nel,))[4:].reshape((nel, 12))
    flat = carray(floats, (points * (5 + 3 + 2 + 6 + 2 * hinges) + 28 * nel,))
    shapes = flat[:5 * points].reshape((nel, nqp, 5))
    start = 5 * points
    Xp = flat[start:start + 3 * points].reshape((points, 3))
    start += 3 * points
    T, BA = flat[start:start + points], flat[start + points:start + 2 * points]
    start += 2 * points
    law = flat[start:start + 6 * points].reshape((points, 6))
    start += 6 * points
    knots = flat[start:start + hinges * points].reshape((points, hinges))
    start += hinges * points
    coef = flat[start:start + hinges * points].reshape((points, hinges))
    start += hinges * points
    bending = flat[start:start + 28 * nel].reshape((nel, 4, 7))
    blocks = nel if tangent else 0
    _hermite(shapes, Xp, T, law, knots, coef, BA, bending, edofs, carray(u_p, (ndofs,)),
             carray(ud_p, (ndofs,)), damped != 0, carray(R_p, (ndofs,)),
             carray(K_p, (blocks, 12, 12)), carray(C_p, (blocks, 12, 12)))


_hermite_step = compiled_when_asked(_hermite_packed)  # (its C function, when first asked for)
