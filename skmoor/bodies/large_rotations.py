"""Exact rigid-body dynamics for large rotations: inertia, gyroscopic terms and the
hydrostatics of a hull at its current pose.

The body DOFs stay q = [x, y, z, rx, ry, rz] (m, rad) with R = Rz(rz) Ry(ry) Rx(rx)
(:mod:`skmoor.bodies.body`). Everything here is in global axes about the displaced reference
point x_ref = reference_point + q[:3]; rho = R r_G is the arm from it to the centre of
mass. Angular velocity and acceleration from the angle rates (R = Rz Ry Rx):

    omega = E(q) qdot[3:],  alpha = E qddot[3:] + Edot qdot[3:],
    E = [Rz Ry e_x, Rz e_y, e_z] = [[cy cz, -sz, 0], [cy sz, cz, 0], [-sy, 0, 1]]

Newton-Euler about the reference point (I_ref = R I_G R^T - m [rho]x^2):

    F = m (a_ref + alpha x rho + omega x (omega x rho))
    M = I_ref alpha + omega x (I_ref omega) + m rho x a_ref

and the load conjugate to q (virtual work F.dx + M.(E dq[3:])) is Q = [F, E^T M]; its
derivative in qddot is the exact mass matrix T^T M6(q) T, T = diag(1, E). A load given as
a force and a moment (global, about x_ref) enters the same way: [F, E^T M].

In a time step the same load is taken in momentum form (:func:`momentum_inertia_load`):
F = dP/dt and M = dL/dt, with the momenta P = m v_G and L advanced by the integrator's
own velocity rule, so that a free body keeps P and L exactly (to Newton's tolerance).

Hydrostatics at a pose: the hull (closed, outward triangles) is moved rigidly, clipped
at z = 0, and the displaced volume V and its centroid c_B come from the divergence
theorem on the wetted faces (the cap at z = 0 adds nothing to int z n_z dS); the
pressure -rho g z integrated over the wetted hull is the buoyancy rho g V e_z at c_B.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = [
    "rate_matrix",
    "zyx_angles",
    "inertia_load",
    "momenta",
    "momentum_inertia_load",
    "momentum_inertia_tangents",
    "step_start",
    "exact_mass_matrix",
    "added_mass_load",
    "added_mass_tangents",
    "submerged_volume",
    "submerged_hull",
    "box_triangles",
    "generalized_load",
]


def cross3(a, b) -> np.ndarray:
    """a x b of two 3-vectors (np.cross costs ten times more on one pair)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def _skew(v) -> np.ndarray:
    """[v]x: [v]x @ a = v x a."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def rate_matrix(angles) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """E (omega = E angle_rates, rad/s) of R = Rz Ry Rx and its slopes dE/dry, dE/drz."""
    ry, rz = angles[1], angles[2]
    cy, sy, cz, sz = math.cos(ry), math.sin(ry), math.cos(rz), math.sin(rz)
    E = np.array([[cy * cz, -sz, 0.0], [cy * sz, cz, 0.0], [-sy, 0.0, 1.0]])
    dE_dry = np.array([[-sy * cz, 0.0, 0.0], [-sy * sz, 0.0, 0.0], [-cy, 0.0, 0.0]])
    dE_drz = np.array([[-cy * sz, -cz, 0.0], [cy * cz, -sz, 0.0], [0.0, 0.0, 0.0]])
    return E, dE_dry, dE_drz


def zyx_angles(R) -> np.ndarray:
    """Angles (rx, ry, rz) (rad) with R = Rz(rz) Ry(ry) Rx(rx), ry in [-pi/2, pi/2]; at
    ry = +-90 deg (only rx -+ rz is defined there) rz = 0."""
    ry = math.atan2(-R[2, 0], math.hypot(R[0, 0], R[1, 0]))
    if math.hypot(R[0, 0], R[1, 0]) < 1e-12:
        return np.array([math.atan2(-R[1, 2], R[1, 1]), ry, 0.0])
    return np.array([math.atan2(R[2, 1], R[2, 2]), ry, math.atan2(R[1, 0], R[0, 0])])


def generalized_load(angles, force, moment) -> np.ndarray:
    """[F, E^T M] (N, N m): a force and a moment about x_ref (global) as the load
    conjugate to q."""
    E = rate_matrix(angles)[0]
    return np.concatenate([force, E.T @ moment])


def _rigid_state(R, mass, inertia, arm):
    """rho = R arm (m) and I_ref = R I_G R^T - m [rho]x^2 (kg m2) at rotation R."""
    rho = R @ arm
    S = _skew(rho)
    return rho, R @ inertia @ R.T - mass * S @ S


def inertia_load(R, q, qdot, qddot, mass, inertia, arm) -> np.ndarray:
    """Generalized inertia load Q = [F, E^T M] (N, N m) of a rigid body (module docstring).

    R: rotation at q; mass kg; inertia (3, 3) about the centre of mass at q = 0, global
    axes (kg m2); arm: centre of mass - reference point at q = 0 (m)."""
    E, dE_dry, dE_drz = rate_matrix(q[3:])
    rates = qdot[3:]
    omega = E @ rates
    alpha = E @ qddot[3:] + (rates[1] * dE_dry + rates[2] * dE_drz) @ rates
    rho, I_ref = _rigid_state(R, mass, inertia, arm)
    a_ref = qddot[:3]
    force = mass * (a_ref + cross3(alpha, rho) + cross3(omega, cross3(omega, rho)))
    moment = I_ref @ alpha + cross3(omega, I_ref @ omega) + mass * cross3(rho, a_ref)
    return np.concatenate([force, E.T @ moment])


def added_mass_load(q, qdot, qddot, added) -> np.ndarray:
    """A constant added mass (6, 6) (kg, kg m, kg m2; global axes, about x_ref) on the
    body's acceleration [a_ref, alpha], alpha = E qddot[3:] + Edot qdot[3:], as the load
    conjugate to q (N, N m): T^T A (T qddot + Tdot qdot), T = diag(I, E)."""
    E, dE_dry, dE_drz = rate_matrix(q[3:])
    rates = qdot[3:]
    acceleration = np.concatenate(
        [qddot[:3], E @ qddot[3:] + (rates[1] * dE_dry + rates[2] * dE_drz) @ rates])
    force = added @ acceleration
    return np.concatenate([force[:3], E.T @ force[3:]])


def added_mass_tangents(q, qdot, qddot, added, step=1e-6):
    """Derivatives (6, 6 each) of :func:`added_mass_load` in qddot (T^T A T) and qdot
    (exact), and in q (central differences of ``step`` rad in the angles)."""
    E, dE_dry, dE_drz = rate_matrix(q[3:])
    T = np.eye(6)
    T[3:, 3:] = E
    rates = qdot[3:]
    d_alpha = rates[1] * dE_dry + rates[2] * dE_drz  # d(Edot rates)/d rates
    d_alpha[:, 1] += dE_dry @ rates
    d_alpha[:, 2] += dE_drz @ rates
    by_rate = np.zeros((6, 6))
    by_rate[3:, 3:] = d_alpha
    by_pose = np.zeros((6, 6))
    for k in range(3, 6):
        e = np.zeros(6)
        e[k] = step
        by_pose[:, k] = (added_mass_load(q + e, qdot, qddot, added)
                         - added_mass_load(q - e, qdot, qddot, added)) / (2 * step)
    return T.T @ added @ T, T.T @ added @ by_rate, by_pose


def exact_mass_matrix(R, q, mass, inertia, arm) -> np.ndarray:
    """dQ/dqddot = T^T M6 T (6, 6): the mass matrix at pose q (kg, kg m, kg m2)."""
    E = rate_matrix(q[3:])[0]
    rho, I_ref = _rigid_state(R, mass, inertia, arm)
    S = _skew(rho)
    out = np.empty((6, 6))
    out[:3, :3] = mass * np.eye(3)
    out[:3, 3:] = -mass * S @ E
    out[3:, :3] = out[:3, 3:].T
    out[3:, 3:] = E.T @ I_ref @ E
    return out


def box_triangles(size, center) -> np.ndarray:
    """The 12 outward triangles (12, 3, 3) of a box of ``size`` (m) centred at ``center``."""
    half = 0.5 * np.asarray(size, float)
    corners = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], float)
    corners = corners * half + np.asarray(center, float)
    # corner index = 4 i + 2 j + k with i, j, k in {0, 1}; faces counter-clockwise seen
    # from outside
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4),
             (1, 5, 7, 3)]
    tri = [(a, b, c) for a, b, c, d in quads] + [(a, c, d) for a, b, c, d in quads]
    return corners[np.array(tri)]


@njit(cache=True)
def _product(area_z, f, g):
    """int f g n_z dS over a flat triangle for f, g linear on it (vertex values f, g):
    area_z (sum f_i g_i + sum f sum g) / 12, area_z = int n_z dS."""
    return area_z * (f[0] * g[0] + f[1] * g[1] + f[2] * g[2]
                     + (f[0] + f[1] + f[2]) * (g[0] + g[1] + g[2])) / 12.0


@njit(cache=True)
def _wet_moments(a, b, c, out):
    """Add over the triangle (a, b, c) int (1, x, y, z/2) z n_z dS to out[:4] and
    -int (1, x, y, x x, y y, x y) n_z dS to out[4:] (10,)."""
    area_z = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
    x, y, z, one = (a[0], b[0], c[0]), (a[1], b[1], c[1]), (a[2], b[2], c[2]), (1.0, 1.0, 1.0)
    out[0] += _product(area_z, z, one)
    out[1] += _product(area_z, x, z)
    out[2] += _product(area_z, y, z)
    out[3] += _product(area_z, z, z) / 2.0
    out[4] -= area_z
    out[5] -= _product(area_z, x, one)
    out[6] -= _product(area_z, y, one)
    out[7] -= _product(area_z, x, x)
    out[8] -= _product(area_z, y, y)
    out[9] -= _product(area_z, x, y)


@njit(cache=True)
def _cut(p, q):
    """The point at z = 0 on the segment p-q (p, q on either side of it)."""
    return p + (p[2] / (p[2] - q[2])) * (q - p)


@njit(cache=True)
def _wet_integrals(tri):
    """(V, V x_B, V y_B, V z_B) of the part with z <= 0 of the outward triangles
    (n, 3, 3), each triangle clipped at z = 0 (as triangles of its orientation), then the
    waterplane's (A, int x, int y, int x x, int y y, int x y) dA: on the closed surface
    (wetted faces and waterplane cap) int f(x, y) n_z dS = 0, so the cap's integrals are
    minus the wetted faces'."""
    out = np.zeros(10)
    for t in range(tri.shape[0]):
        below = 0
        for k in range(3):
            if tri[t, k, 2] <= 0.0:
                below += 1
        if below == 3:
            _wet_moments(tri[t, 0], tri[t, 1], tri[t, 2], out)
        elif below in (1, 2):  # roll the odd vertex (alone on its side) to position 0
            odd = 0
            for k in range(3):
                if (tri[t, k, 2] <= 0.0) == (below == 1):
                    odd = k
            p0, p1, p2 = tri[t, odd], tri[t, (odd + 1) % 3], tri[t, (odd + 2) % 3]
            cut01, cut02 = _cut(p0, p1), _cut(p0, p2)
            if below == 1:
                _wet_moments(p0, cut01, cut02, out)
            else:
                _wet_moments(cut01, p1, p2, out)
                _wet_moments(cut01, p2, cut02, out)
    return out


def submerged_volume(tri) -> tuple[float, np.ndarray]:
    """Volume (m3) and centroid (3,) of the part below z = 0 of a closed hull given as
    outward triangles (n, 3, 3) in global coordinates (m); (0, zeros) when dry."""
    return submerged_hull(tri)[:2]


def submerged_hull(tri) -> tuple[float, np.ndarray, np.ndarray]:
    """:func:`submerged_volume` and the waterplane's area and moments (A, int x dA,
    int y dA, int x^2 dA, int y^2 dA, int x y dA) (m2, m3, m4) at z = 0."""
    moments = _wet_integrals(np.ascontiguousarray(tri, dtype=float))
    if moments[0] <= 0.0:
        return 0.0, np.zeros(3), np.zeros(6)
    return moments[0], moments[1:4] / moments[0], moments[4:]


def momenta(R, q, qdot, mass, inertia, arm, offset) -> tuple[np.ndarray, np.ndarray]:
    """Linear momentum P = m v_G (N s) and angular momentum L = (x_G - O) x P + R I_G R^T
    omega (N m s) about the fixed point O = x_ref - ``offset``."""
    omega = rate_matrix(q[3:])[0] @ qdot[3:]
    rho = R @ arm
    linear = mass * (qdot[:3] + cross3(omega, rho))
    return linear, cross3(offset + rho, linear) + R @ inertia @ R.T @ omega


def step_start(R0, q0, v0, load0, mass, inertia, arm):
    """What a step's momentum form needs of its start: P0, L0 (about x_ref0), Pdot0 and
    the moment about x_ref0, from the start's inertia load load0 = [Pdot0, E0^T M0]."""
    if abs(math.cos(q0[4])) < 1e-6:
        raise ValueError(f"rotations: the body's ry = {math.degrees(q0[4]):.6g} deg reached "
                         "+-90 deg, the gimbal lock of the angles R = Rz Ry Rx (its x axis "
                         "vertical), and its angles were not re-based (System.rebase: a "
                         "body with a term that is not frame_aware, such as a user's BodyLoad "
                         "reading q[3:], is not): read the pose through term.body_motion and "
                         "set frame_aware, or turn the body frame so that its x axis stays "
                         "off vertical")
    E0 = rate_matrix(q0[3:])[0]
    p0, l0 = momenta(R0, q0, v0, mass, inertia, arm, np.zeros(3))
    return q0, p0, l0, load0[:3], np.linalg.solve(E0.T, load0[3:])


def momentum_inertia_load(R1, q1, v1, start, h, gamma, mass, inertia, arm) -> np.ndarray:
    """Inertia load Q1 = [Pdot1, E1^T M1] (N, N m) at the end of a step of h (s) from
    ``start`` (:func:`step_start`), the momentum rates following the scheme's velocity
    rule, as v and a do:

        P1 = P0 + h ((1 - gamma) Pdot0 + gamma Pdot1),  same for L about x_ref0,

    and M1 = Ldot1 - (x_ref1 - x_ref0) x Pdot1. Without loads P and L stay constant exactly.
    """
    return _momentum_load(R1, q1, v1, *start, h, gamma, float(mass), inertia, arm)[0]


def momentum_inertia_tangents(R1, q1, v1, start, h, gamma, mass, inertia, arm):
    """Derivatives (6, 6 each) of :func:`momentum_inertia_load` in v1 and in q1 (exact)."""
    return _momentum_tangents(R1, q1, v1, *start, h, gamma, float(mass), inertia, arm)


def _momentum_load(R1, q1, v1, q0, p0, l0, pdot0, mdot0, h, gamma, mass, inertia, arm):
    """(Q1, Pdot1, Ldot1 - s x Pdot1, P1) of :func:`momentum_inertia_load`, s = x_ref1 -
    x_ref0."""
    shift = q1[:3] - q0[:3]
    p1, l1 = momenta(R1, q1, v1, mass, inertia, arm, shift)
    pdot1 = (p1 - p0 - h * (1 - gamma) * pdot0) / (gamma * h)
    moment = (l1 - l0 - h * (1 - gamma) * mdot0) / (gamma * h) - cross3(shift, pdot1)
    out = np.empty(6)
    out[:3] = pdot1
    out[3:] = rate_matrix(q1[3:])[0].T @ moment
    return out, pdot1, moment, p1


def _momentum_tangents(R1, q1, v1, q0, p0, l0, pdot0, mdot0, h, gamma, mass, inertia, arm):
    """dQ1/dv1 and dQ1/dq1 of :func:`_momentum_load` by the chain rule, with dR/dphi_a =
    [E_a]x R (E_a the a-th column of E: the angular velocity of a unit rate of phi_a)."""
    _, pdot1, moment, p1 = _momentum_load(R1, q1, v1, q0, p0, l0, pdot0, mdot0, h, gamma,
                                          mass, inertia, arm)
    E, dE_dry, dE_drz = rate_matrix(q1[3:])
    rates = v1[3:]
    omega = E @ rates
    rho = R1 @ arm
    J = R1 @ inertia @ R1.T  # the central inertia at the pose
    s = q1[:3] - q0[:3]
    c = 1.0 / (gamma * h)
    # d/dv1: P1 = m (v + omega x rho), L1 = (s + rho) x P1 + J omega
    dp = np.zeros((3, 6))
    dp[:, :3] = mass * np.eye(3)
    dp[:, 3:] = -mass * _skew(rho) @ E
    dl = _skew(s + rho) @ dp
    dl[:, 3:] += J @ E
    d_rate = np.zeros((6, 6))
    d_rate[:3] = c * dp
    d_rate[3:] = E.T @ (c * (dl - _skew(s) @ dp))
    # d/dq1: the shift s (L1 = (s + rho) x P1, moment - s x Pdot1) and the angles
    d_pose = np.zeros((6, 6))
    d_pose[3:, :3] = E.T @ (_skew(pdot1) - c * _skew(p1))
    slopes = (np.zeros((3, 3)), dE_dry, dE_drz)
    for a in range(3):
        Ea = E[:, a]
        d_omega = slopes[a] @ rates
        d_rho = cross3(Ea, rho)
        d_p = mass * (cross3(d_omega, rho) + cross3(omega, d_rho))
        d_J_omega = cross3(Ea, J @ omega) - J @ cross3(Ea, omega)
        d_l = cross3(d_rho, p1) + cross3(s + rho, d_p) + d_J_omega + J @ d_omega
        d_pose[:3, 3 + a] = c * d_p
        d_pose[3:, 3 + a] = (slopes[a].T @ moment
                             + E.T @ (c * d_l - cross3(s, c * d_p)))
    return d_rate, d_pose
