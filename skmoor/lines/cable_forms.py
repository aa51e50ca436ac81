"""The cable's weak forms (Wang, Er & Iu, Eqs. 3-23) as scikit-fem forms.

The line lives on a ``MeshLine1`` in s, the arclength of the reference (static)
configuration, with a vector P1 basis for the displacement u(s) (3 components). The
reference state enters as fields at quadrature points:

- ``Xp``  (3, nel, nqp)  unit tangent X'(s) of the reference configuration
- ``T``   (nel, nqp)     reference tension, N
- ``EA``  (nel, nqp)     axial stiffness, N
- ``m``   (nel, nqp)     mass per length (structural + added), kg/m
- ``w``   (nel, nqp)     submerged weight per length, N/m (acts along -z)
- ``BA``  (nel, nqp)     axial internal damping, N s
- the strain law's parameters (:mod:`skmoor.lines.laws`): ``green``, ``tension_only``, ``T0``,
  ``e0``, ``k``, ``e_ref`` (nel, nqp) and the hinges ``knots``, ``coef`` (m, nel, nqp)

The current displacement is passed as the DOF vector ``u``. A residual is
``internal - external``; tangents are its exact derivatives.

Strain laws (:mod:`skmoor.lines.laws`, one per line type): the stress resultant S(eps)
conjugate to the strain of Eq. 3, added to T: the paper's ``S = EA eps`` (Eq. 6), or a
tension N(e) of the engineering strain e = (1 + e_ref) lambda - 1, lambda =
sqrt(1 + 2 eps), as in Irvine's elastic catenary, MoorPy and MoorDyn (EA times e, a
tension-strain curve, polyester's static / dynamic stiffness): S = N(e) / lambda - T.
Cables are tension-only by default (T + S >= 0: a slack cable carries no compression).

The displacement-dependent cable terms (Eqs. 11, 17) are integrated at the element
mid-point (``LineSet.cable_basis``): with P1 displacements and a curved reference
tangent, Gauss points would see a rigid rotation of a chord as strain (membrane
locking, 6 % too stiff in-plane at 11 elements). The reference force and the weight
keep full quadrature, so the reference state stays an exact equilibrium.

The cable forms are written with :mod:`skmoor.fem.ops`, so that automatic differentiation
can trace them. Write a new term as a ``LinearForm`` (its contribution to the residual)
and, for Newton, a ``BilinearForm`` (its derivative with respect to u, or to the
velocity); see :class:`skmoor.coupling.system.Term` and ``examples/03_weak_form_drag.py``.
"""
from skfem import BilinearForm, LinearForm

from ..fem import ops
from ..fem.ops import d_ds, dot
from . import laws


def strain(Xp, up):
    """Eq. 3 in 3D: eps = X'.u' + |u'|^2 / 2, -."""
    return dot(Xp, up) + 0.5 * dot(up, up)


def stress_resultant(eps, w):
    """(S, dS/deps), N: the law's axial force added to T by the strain eps (Eq. 6 for the
    paper's law); w holds T and the law's parameters (see the module docstring)."""
    return laws.stress_resultant(eps, w["T"], w)


@LinearForm
def cable_force(v, w):
    # Eq. 11: dPi' = int [ S(eps) (X' + u').du' + T u'.du' ] ds
    up = d_ds(w.u)
    S, _ = stress_resultant(strain(w.Xp, up), w)
    return S * dot(w.Xp + up, d_ds(v)) + w.T * dot(up, d_ds(v))


@LinearForm
def axial_damping(v, w):
    # Kelvin-Voigt line damping (MoorDyn's BA): int BA deps/dt (X' + u').du' ds, deps/dt = r'.udot'
    rp = w.Xp + d_ds(w.u)
    return w.BA * dot(rp, d_ds(w.du)) * dot(rp, d_ds(v))


@BilinearForm
def axial_damping_rate(dud, v, w):
    # d(axial_damping)/d(udot) = int BA (r'.dudot')(r'.v') ds
    rp = w.Xp + d_ds(w.u)
    return w.BA * dot(rp, d_ds(dud)) * dot(rp, d_ds(v))


@BilinearForm
def axial_damping_tangent(du, v, w):
    # d(axial_damping)/du = int BA [(du'.udot')(r'.v') + (r'.udot') du'.v'] ds
    rp = w.Xp + d_ds(w.u)
    return w.BA * (dot(d_ds(du), d_ds(w.du)) * dot(rp, d_ds(v))
                   + dot(rp, d_ds(w.du)) * dot(d_ds(du), d_ds(v)))


@LinearForm
def reference_force(v, w):
    # Eq. 9 at u = 0: int T X'.du' ds, in equilibrium with the weight in the reference state
    return w.T * dot(w.Xp, d_ds(v))


@BilinearForm
def cable_tangent(du, v, w):
    # Eq. 17, exact: d(Eq. 11)/du = int [ S' (r'.du')(r'.v') + (T + S) du'.v' ] ds, r' = X' + u'
    up = d_ds(w.u)
    S, dS = stress_resultant(strain(w.Xp, up), w)
    rp = w.Xp + up
    return dS * dot(rp, d_ds(du)) * dot(rp, d_ds(v)) + (w.T + S) * dot(d_ds(du), d_ds(v))


@BilinearForm
def unit_tension_stiffness(du, v, w):
    # the T u'.du' term of Eq. 11 with T = 1 N: geometric stiffness of a unit tension
    return dot(d_ds(du), d_ds(v))


@LinearForm
def weight(v, w):
    # Eq. 8: gravity on the submerged line, int w (-e_z).du ds
    return -w.w * v[2]


@LinearForm
def distributed_load(v, w):
    # Eq. 12: int f.du ds, with f (3, nel, nqp) in N/m
    return dot(w.f, v)


@BilinearForm
def mass(du, v, w):
    # Eq. 19 (consistent) on Gauss points; Eq. 20 (lumped) on nodal quadrature
    return w.m * dot(du, v)


@BilinearForm
def line_damping(du, v, w):
    # Eq. 12: int c udot.du ds, with c (nel, nqp) in N s/m2
    return w.c * dot(du, v)


def tension(Xp, up, w, rate=None):
    """Tension in the deformed line, N: (T + S + BA deps/dt) |X' + u'|, w holding T, BA
    and the law's parameters; ``rate`` the strain rate deps/dt = r'.udot' (1/s, None: 0).
    With the rate this is the axial force the line transmits, as MoorDyn reports
    T + BA x strain rate (Kelvin-Voigt damping in the reported tension)."""
    S, _ = stress_resultant(strain(Xp, up), w)
    axial = w["T"] + S
    if rate is not None:
        axial = axial + w["BA"] * rate
    return axial * ops.norm(Xp + up)
