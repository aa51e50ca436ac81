"""Rods as MoorDyn v2 has them: rigid cylinders carried by a rigid body.

A rod (:class:`RodType`: diameter, mass per length, Cd, Ca, CdEnd, CaEnd) runs from end A
to end B. skmoor models it on its body machinery: a free or pinned rod is a dynamic
:class:`~skmoor.coupling.network.Body` of its own (reference point at end A, the mass and inertia
of a uniform cylinder, :func:`rod_body`), a rod on a body adds its mass to that body
(:func:`mount_rod`), and its distributed loads are a :class:`~skmoor.bodies.loads.BodyLoad` on
whichever body carries it (:class:`RodLoad`): weight and buoyancy (exact at any attitude:
the submerged length of the axis below z = 0, its centre of buoyancy halfway along it),
transverse Morison drag and fluid inertia (1 + Ca) rho A a_n at the NumSegs segment
midpoints, drag, fluid inertia and added mass on the submerged end caps (MoorDyn's
CdEnd with the cap area, CaEnd with the volume of a hemisphere of the rod's radius,
axial), the transverse added mass Ca rho A of the
submerged length (a constant matrix of the reference attitude, as a body's added mass),
and MoorDyn's sea-bed springs. The water surface is z = 0 (wave elevation not followed).
Loads on a moving body point go through its Jacobian, F_q = J(q, r)^T f.

A pinned rod's end A is held by a stiff spring-damper (:class:`PinLoad`: deflection
1e-6 of its centre of mass's distance from the pin, at least 1e-6 m, under its weight;
the pin's own mode critically damped) to a fixed place or a prescribed motion. A free rod has 5 DOF in MoorDyn (no spin about its axis); its sixth,
the spin, which no load of an axisymmetric rod drives, is held by a torsional spring
(:class:`SpinLoad`) so that the statics stay regular.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..bodies.body import RigidBody, attachment_jacobian, combined_mass
from ..bodies.loads import BodyLoad

PIN_DEFLECTION = 1e-6  # pin deflection under the body's weight, per metre of its size


SPRING_GRAVITY = 9.80665  # m/s2: the weight that sizes the pin and spin springs when g = 0


def spring_weight(mass, g) -> float:
    """The weight (N) that sizes a pin or spin spring: m g, or m times standard gravity
    in a weightless model (g = 0), where the springs must still hold."""
    return mass * (g if g > 0 else SPRING_GRAVITY)


@dataclass
class RodType:
    """A ROD TYPES entry: diameter (m), mass per length (kg/m), transverse drag and added
    mass coefficients Cd, Ca, and the end caps' axial CdEnd, CaEnd (-)."""

    name: str
    diameter: float
    mass: float
    Cd: float = 0.0
    Ca: float = 0.0
    CdEnd: float = 0.0
    CaEnd: float = 0.0

    def __post_init__(self):
        for key in ("diameter", "mass", "Cd", "Ca", "CdEnd", "CaEnd"):
            value = getattr(self, key)
            positive = key in ("diameter", "mass")
            if not (isinstance(value, (int, float)) and math.isfinite(value)
                    and (value > 0 if positive else value >= 0)):
                raise ValueError(f"rod type {self.name} {key}: must be a finite number "
                                 f"{'> 0' if positive else '>= 0'}, got {value!r}")

    @property
    def area(self) -> float:
        """Cross-section, m2."""
        return math.pi * self.diameter ** 2 / 4


def rod_axis(a, b, name):
    a, b = np.asarray(a, float), np.asarray(b, float)
    length = float(np.linalg.norm(b - a))
    if length == 0:
        raise ValueError(f"rod {name}: ends A and B at the same place {a.tolist()}")
    return a, b, length


def rod_inertia(rod_type: RodType, a, b, name="rod"):
    """(mass kg, centre of mass (3,) m, inertia about it (3, 3) kg m2) of a uniform
    cylinder from a to b: m L^2 / 12 + m r^2 / 4 across, m r^2 / 2 along its axis."""
    a, b, length = rod_axis(a, b, name)
    mass = rod_type.mass * length
    t = (b - a) / length
    r2 = (rod_type.diameter / 2) ** 2
    across, along = mass * (length ** 2 / 12 + r2 / 4), mass * r2 / 2
    return mass, (a + b) / 2, across * (np.eye(3) - np.outer(t, t)) + along * np.outer(t, t)


def rod_body(rod_type: RodType, a, b, *, g=9.81, name="rod", rotations="small") -> RigidBody:
    """The RigidBody of a free or pinned rod from a to b (global, m): reference point
    end A, no hydrostatics (buoyancy is in its :class:`RodLoad`); ``rotations`` as
    :class:`~skmoor.bodies.body.RigidBody`'s."""
    mass, com, inertia = rod_inertia(rod_type, a, b, name)
    return RigidBody(mass, com, inertia, reference_point=np.asarray(a, float), g=g,
                     rotations=rotations)


def mount_rod(rigid: RigidBody | None, rod_type: RodType, a, b, *, reference_point,
              g=9.81, name="rod", rotations="small") -> RigidBody:
    """A body's RigidBody with a rod from a to b (global, m) fixed on it: masses added,
    the centre of mass and the inertia combined (parallel axes), its rotations and hull
    kept. ``rigid`` None: a body of no mass of its own (MoorDyn allows it when rods give
    it mass), with ``rotations``."""
    mass, com, inertia = rod_inertia(rod_type, a, b, name)
    if rigid is None:
        return RigidBody(mass, com, inertia, reference_point=reference_point, g=g,
                         rotations=rotations)
    total, centre, combined = combined_mass([(rigid.mass, rigid.center_of_mass, rigid.inertia),
                                             (mass, com, inertia)])
    return RigidBody(total, centre, combined,
                     reference_point=rigid.reference_point, hydrostatics=rigid.hydrostatics,
                     added_mass=rigid.added_mass, linear_damping=rigid.linear_damping,
                     rho=rigid.rho, g=rigid.g, box_size=rigid.box_size,
                     box_center=rigid.box_center, rotations=rigid.rotations, hull=rigid.hull)


def _submerged(za, zb):
    """(start, end) of the submerged part (z < 0) of an axis from za to zb, as
    fractions 0..1 of its length from end A."""
    if za < 0 and zb < 0:
        return 0.0, 1.0
    if za >= 0 and zb >= 0:
        return 0.0, 0.0
    cross = za / (za - zb)
    return (0.0, cross) if za < 0 else (cross, 1.0)


class RodLoad(BodyLoad):
    """The water and gravity loads on a rod fixed on a body (MoorDyn v2's Rod.cpp
    conventions), a :class:`~skmoor.bodies.loads.BodyLoad` with its constant added mass.

    a, b: the rod's ends relative to the body's reference point at q = 0 (global axes,
    m); reference_point: that point (global, m); n_segments: where the drag and the bed
    contact are evaluated (segment midpoints); sea: a :class:`~skmoor.sea.waves.Sea` (its
    current and wave velocities drag the rod) or None; bed: (depth m, stiffness N/m3,
    damping N s/m3) of MoorDyn's sea bed, a vertical spring-damper per unit of d ds
    below z = -depth (Rod.cpp), or None. The body's RigidBody holds the rod's mass (see
    :func:`rod_body`, :func:`mount_rod`), so the System carries its weight: linearly
    about q = 0 on a 'small' body, which this load replaces by the exact one; at the
    pose on an 'exact' body, where this load adds none."""

    frame_aware = True  # the rod's ends from self.body_motion: re-based frames included

    def __init__(self, rod_type: RodType, a, b, *, reference_point, n_segments=1,
                 rho=1025.0, g=9.81, sea=None, bed=None, body=0, name="rod"):
        a, b, length = rod_axis(a, b, name)
        if isinstance(n_segments, bool) or not isinstance(n_segments, (int, np.integer)) \
                or n_segments < 1:
            raise ValueError(f"rod {name} NumSegs: must be an integer >= 1, got {n_segments!r}")
        self.rod_type, self.a, self.b, self.length = rod_type, a, b, length
        self.reference_point = np.asarray(reference_point, float)
        self.rho, self.g, self.sea, self.bed, self.name = float(rho), float(g), sea, bed, name
        self.fractions = (np.arange(n_segments) + 0.5) / n_segments  # segment midpoints
        self.ends = np.ascontiguousarray([a, b])
        self.segment = length / n_segments
        self.mass, com, inertia = rod_inertia(rod_type, a + self.reference_point,
                                              b + self.reference_point, name)
        alone = RigidBody(self.mass, com, inertia, reference_point=self.reference_point, g=g)
        self._linear = (alone.static_force(), alone.hydrostatic_stiffness(generalized=True))
        super().__init__(self.forces, body=body, added_mass=self.added_mass_matrix(),
                         tangent=self._central)

    def forces(self, q, qdot, t):
        """Generalized load (6,), N and N m: J^T f summed over the rod's loads. Positions
        and Jacobians are linear along the rod: those of its ends, interpolated. On an
        'exact' body the System weighs the rod (in the body's mass) at the pose: no
        weight here."""
        lt, rho, g = self.rod_type, self.rho, self.g
        q, qdot = np.asarray(q, float), np.asarray(qdot, float)
        motion = self.body_motion(q, qdot)
        moved, J = motion.points(self.ends)
        (A, B), (JA, JB) = self.reference_point + moved, J.reshape(2, 3, 6)

        def at(s):  # (position, Jacobian) a fraction s along the rod from end A
            return A + s * (B - A), JA + s * (JB - JA)

        axis = (B - A) / self.length
        F = np.zeros(6)
        if not motion.exact:
            F += at(0.5)[1].T @ np.array([0.0, 0.0, -self.mass * g])
            F0, K = self._linear  # the body model's linear weight of the rod, replaced
            F -= F0 - K @ q
        start, end = _submerged(A[2], B[2])
        if end > start:  # rho g A L_sub at the centre of the submerged length
            F += at(0.5 * (start + end))[1].T @ np.array(
                [0.0, 0.0, rho * g * lt.area * (end - start) * self.length])
        s = self.fractions
        X = A + s[:, None] * (B - A)  # segment midpoints
        Js = JA + s[:, None, None] * (JB - JA)  # (n, 3, 6)
        if self.bed is not None:  # ((-h - z) kb - z' cb) d ds up, below the bed
            depth, kb, cb = self.bed
            low = X[:, 2] < -depth
            if np.any(low):
                lift = ((-depth - X[low, 2]) * kb - (Js[low] @ qdot)[:, 2] * cb) \
                    * lt.diameter * self.segment
                F += Js[low][:, 2, :].T @ lift
        wet = X[:, 2] < 0
        if np.any(wet):  # at the wet segment midpoints, w = U - v the relative velocity
            water, fluid = self._water(X[wet], t)
            w = water - Js[wet] @ qdot
            normal = w - (w @ axis)[:, None] * axis
            speed = np.linalg.norm(normal, axis=1)
            # 1/2 rho Cd d ds |w_n| w_n + rho (1 + Ca) A ds a_n (a: the water's acceleration)
            f = 0.5 * rho * lt.Cd * lt.diameter * self.segment * speed[:, None] * normal
            f += rho * (1 + lt.Ca) * lt.area * self.segment * (
                fluid - (fluid @ axis)[:, None] * axis)
            F += np.einsum("nka,nk->a", Js[wet], f)
        cap = rho * lt.CaEnd * (2 / 3) * math.pi * (lt.diameter / 2) ** 3
        for X_end, J_end in ((A, JA), (B, JB)):
            if X_end[2] < 0 and (lt.CdEnd or lt.CaEnd):
                water, fluid = (x[0] for x in self._water(X_end[None], t))
                w_axial = ((water - J_end @ qdot) @ axis) * axis
                # 1/2 rho CdEnd A |w_a| w_a + CaEnd rho (2/3) pi r^3 a_a on the end cap
                F += J_end.T @ (0.5 * rho * lt.CdEnd * lt.area * np.linalg.norm(w_axial)
                                * w_axial + cap * (fluid @ axis) * axis)
        return F

    def _water(self, points, t):
        """The water's velocity (m/s) and acceleration (m/s2) at points (n, 3)."""
        if self.sea is None or self.sea.still:
            return np.zeros_like(points), np.zeros_like(points)
        return self.sea.kinematics(points, t)

    def _added_mass_points(self, A, B):
        """[(r, m)]: body points r (from the reference point, built attitude, m) and their
        added mass (3, 3) (kg) for the rod from A to B (global, m) as it is: Ca rho A
        (I - t t^T) over the submerged length (two-point Gauss, exact for the straight
        rod) and CaEnd rho (2/3) pi r^3 t t^T at each submerged end (MoorDyn's Rod.cpp)."""
        lt, rho = self.rod_type, self.rho
        axis = (B - A) / self.length
        start, end = _submerged(A[2], B[2])
        out = []
        if lt.Ca and end > start:
            transverse = lt.Ca * rho * lt.area * (np.eye(3) - np.outer(axis, axis))
            half = 0.5 * (end - start) * self.length
            along = (self.b - self.a) / self.length  # the axis as built
            for xi in (-1 / math.sqrt(3), 1 / math.sqrt(3)):
                s = 0.5 * (start + end) * self.length + xi * half
                out.append((self.a + s * along, half * transverse))
        if lt.CaEnd:
            cap = lt.CaEnd * rho * (2 / 3) * math.pi * (lt.diameter / 2) ** 3
            for r, z in ((self.a, A[2]), (self.b, B[2])):
                if z < 0:
                    out.append((r, cap * np.outer(axis, axis)))
        return out

    def added_mass_matrix(self) -> np.ndarray:
        """Added mass (6, 6) about the reference point at q = 0 (kg, kg m, kg m2): that of
        :meth:`_added_mass_points` at the built attitude."""
        zero = np.zeros(6)
        M = np.zeros((6, 6))
        for r, m in self._added_mass_points(self.reference_point + self.a,
                                            self.reference_point + self.b):
            J = attachment_jacobian(zero, r)
            M += J.T @ m @ J
        return 0.5 * (M + M.T)

    def inertia_load(self, q, qdot, qddot) -> np.ndarray:
        """The load (6,) (N, N m) of the rod's added mass as it turns (an 'exact' body:
        :meth:`skmoor.coupling.system.System.inertia`): J^T m a at the points of
        :meth:`_added_mass_points` for the rod where it is, a their accelerations."""
        motion = self.body_motion(q, qdot)
        moved, _ = motion.points(self.ends)
        A, B = self.reference_point + moved
        pairs = self._added_mass_points(A, B)
        if not pairs:
            return np.zeros(6)
        acceleration, J = motion.accelerations(np.array([r for r, _ in pairs]), qddot)
        J = J.reshape(len(pairs), 3, 6)
        return sum(J[k].T @ m @ acceleration[k] for k, (_, m) in enumerate(pairs))

    def inertia_tangents(self, q, qdot, qddot):
        """Derivatives (6, 6 each) of :meth:`inertia_load` in qddot, qdot and q (central
        differences; the load is linear in qddot)."""
        q, qdot, qddot = (np.asarray(x, float) for x in (q, qdot, qddot))
        out = []
        for which in range(3):
            state = [q, qdot, qddot]
            step = 1e-6 * (1 + np.max(np.abs(state[which])))
            D = np.empty((6, 6))
            for k, e in enumerate(np.eye(6)):
                plus, minus = list(state), list(state)
                plus[which], minus[which] = state[which] + step * e, state[which] - step * e
                D[:, k] = (self.inertia_load(*plus) - self.inertia_load(*minus)) / (2 * step)
            out.append(D)
        by_q, by_qdot, by_qddot = out
        return by_qddot, by_qdot, by_q

    def _central(self, q, qdot, t):
        """dF/dq and dF/dqdot (6, 6) by central differences (the loads are smooth:
        |w| w is once differentiable)."""
        q, qdot = np.asarray(q, float), np.asarray(qdot, float)
        dq, dv = 1e-6 * (1 + np.max(np.abs(q))), 1e-6 * (1 + np.max(np.abs(qdot)))
        by_q, by_v = np.empty((6, 6)), np.empty((6, 6))
        for k, e in enumerate(np.eye(6)):
            by_q[:, k] = (self.forces(q + dq * e, qdot, t) - self.forces(q - dq * e, qdot, t)) / (2 * dq)
            by_v[:, k] = (self.forces(q, qdot + dv * e, t) - self.forces(q, qdot - dv * e, t)) / (2 * dv)
        return by_q, by_v


def _cross(a, b) -> np.ndarray:
    """a x b of two 3-vectors (numpy's cross costs 20 times more on one pair)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


class PinLoad(BodyLoad):
    """A pin holding a body's reference point at a fixed place or on a prescribed motion
    (pinned rods): F = -k (q[:3] - d(t)) - c (qdot[:3] - d'(t)), with k = m g / (1e-6 L)
    (the pin gives 1e-6 L under the weight m g, standard gravity when g = 0; L a length
    of the body, m) and
    c = 2 sqrt(k m) (its mode critically damped). motion(t) -> (d, d'): the pin's
    displacement (m) and velocity (m/s) from where it starts, or None (fixed)."""

    frame_aware = True  # it reads the reference point's translation only

    def __init__(self, mass, length, *, g=9.81, motion=None, body=0):
        self.stiffness = spring_weight(mass, g) / (PIN_DEFLECTION * length)  # N/m
        self.damping = 2 * math.sqrt(self.stiffness * mass)  # N s/m
        self.motion = motion
        k, c = self.stiffness, self.damping
        by_q, by_v = np.zeros((6, 6)), np.zeros((6, 6))
        by_q[:3, :3], by_v[:3, :3] = -k * np.eye(3), -c * np.eye(3)
        super().__init__(self.forces, body=body, tangent=lambda q, qdot, t: (by_q, by_v))

    def forces(self, q, qdot, t):
        d, v = (np.zeros(3), np.zeros(3)) if self.motion is None else self.motion(t)
        F = np.zeros(6)
        F[:3] = -self.stiffness * (np.asarray(q[:3]) - d) - self.damping * (np.asarray(qdot[:3]) - v)
        return F


class SpinLoad(BodyLoad):
    """A torsional spring on a rod's spin psi about its own axis (the rotation left after
    the least rotation that turns the axis from t0 to its present direction t): a couple
    -k (1 + t0.t) / 2 psi t, applied as two opposite forces one metre apart across the
    axis; k in N m/rad. The factor fades the spring out where the rod points opposite to
    t0 and the least rotation is undefined (no load of an axisymmetric rod drives the
    spin: the spring only keeps the statics regular)."""

    frame_aware = True  # the attitude from self.body_motion: re-based frames included

    def __init__(self, a, b, stiffness, *, body=0):
        a, b, length = rod_axis(a, b, "spin")
        self.a, self.t0 = a, (b - a) / length
        helper = np.eye(3)[int(np.argmin(np.abs(self.t0)))]
        n0 = np.cross(self.t0, helper)
        self.n0 = n0 / np.linalg.norm(n0)
        self.points = np.ascontiguousarray([a + self.n0, a])
        self.stiffness = float(stiffness)
        super().__init__(self.forces, body=body, tangent=self._central)

    def _spin(self, axis, n) -> float:
        """psi (rad) of the rod's present axis and cross-axis direction n = R n0 (0
        where it points opposite to t0)."""
        v, c = _cross(self.t0, axis), float(self.t0 @ axis)
        if c <= -1 + 1e-12:
            return 0.0
        # least rotation (Rodrigues): n0 + v x n0 + v x (v x n0) / (1 + c)
        turned = _cross(v, self.n0)
        least = self.n0 + turned + _cross(v, turned) / (1 + c)
        return math.atan2(float(axis @ _cross(least, n)), float(least @ n))

    def spin(self, q) -> float:
        """psi (rad) of body DOFs q (0 where the rod points opposite to t0)."""
        R = self.body_motion(np.asarray(q, float)).rotation
        return self._spin(R @ self.t0, R @ self.n0)

    def forces(self, q, qdot, t):
        motion = self.body_motion(np.asarray(q, float), qdot)
        R = motion.rotation
        axis, n = R @ self.t0, R @ self.n0
        fade = 0.5 * (1 + float(self.t0 @ axis))
        f = -self.stiffness * fade * self._spin(axis, n) * _cross(axis, n)  # n x f = -k' psi t
        _, J = motion.points(self.points)
        return (J[:3] - J[3:]).T @ f

    def _central(self, q, qdot, t):
        q = np.asarray(q, float)
        h = 1e-6
        by_q = np.empty((6, 6))
        for k, e in enumerate(np.eye(6)):
            by_q[:, k] = (self.forces(q + h * e, qdot, t) - self.forces(q - h * e, qdot, t)) / (2 * h)
        return by_q, None
