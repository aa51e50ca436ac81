"""Rods in a network, as MoorDyn v2 has them: a free or pinned rod is a dynamic
:class:`~skmoor.coupling.network.Body` of its own with two body points at its ends
(:func:`rod`), a coupled rod a prescribed one (:func:`coupled_rod`); the reaction a coupled
rod's motion needs is :func:`coupled_reaction`. Their physics (the rod type, its mass and
its loads) is :mod:`skmoor.bodies.rod_loads`.
"""
from __future__ import annotations

import numpy as np

from ..bodies.rod_loads import (
    PinLoad,
    RodLoad,
    RodType,
    SpinLoad,
    mount_rod,
    rod_axis,
    rod_body,
    rod_inertia,
    spring_weight,
)
from .network import Body, Point

__all__ = ["RodType", "rod", "rod_body", "rod_inertia", "mount_rod", "RodLoad", "PinLoad",
           "SpinLoad", "spring_weight", "coupled_rod", "coupled_reaction"]


def rod(name, rod_type: RodType, a, b, *, pin=None, n_segments=1, rho=1025.0, g=9.81,
        sea=None, bed=None, rotations="small"):
    """(Body, [end A, end B]) of a free (``pin`` None) or pinned rod (``pin`` 'fixed' or
    'coupled', see :class:`~skmoor.coupling.network.Body`) from a to b (global, m): a dynamic
    body ``name`` at end A with the rod's RodLoad and spin spring, and its end points
    ``name.A``, ``name.B`` for lines to end on. ``rotations``: its body's ('exact': the
    rod may turn through any attitude); other keywords as :class:`RodLoad`'s."""
    a, b, length = rod_axis(a, b, name)
    rigid = rod_body(rod_type, a, b, g=g, name=name, rotations=rotations)
    terms = [RodLoad(rod_type, np.zeros(3), b - a, reference_point=a, n_segments=n_segments,
                     rho=rho, g=g, sea=sea, bed=bed, name=name),
             SpinLoad(np.zeros(3), b - a, spring_weight(rigid.mass, g) * length)]
    body = Body(name, "dynamic", a, rigid=rigid, terms=terms, pin=pin)
    return body, [Point(f"{name}.A", "body", np.zeros(3), body=name),
                  Point(f"{name}.B", "body", b - a, body=name)]


def coupled_rod(name, rod_type: RodType, a, b, *, n_segments=1, rho=1025.0, g=9.81,
                sea=None, bed=None):
    """(Body, [end A, end B]) of a Coupled rod from a to b (global, m): a coupled body
    ``name`` at end A whose 6 coupled DOFs are end A's displacement (m) and MoorDyn's
    angles Rx Ry Rz (rad) turning the rod's axis from a -> b, its end points ``name.A``,
    ``name.B``, and its :class:`RodLoad` among the body's terms (what
    :func:`coupled_reaction` adds to the lines' loads; nothing else reads it)."""
    a, b, _ = rod_axis(a, b, name)
    load = RodLoad(rod_type, np.zeros(3), b - a, reference_point=a, n_segments=n_segments,
                   rho=rho, g=g, sea=sea, bed=bed, name=name)
    load.body_motion = _exact_motion  # in no System: its pose read as an exact body's
    body = Body(name, "coupled", a, terms=[load])
    return body, [Point(f"{name}.A", "body", np.zeros(3), body=name),
                  Point(f"{name}.B", "body", b - a, body=name)]


COUPLED_STEP = 1e-4  # s: the central differences of the coupled motion


def _exact_motion(q, qdot=None):
    """The BodyMotion of an exact body at (q, qdot) about the global frame."""
    from ..bodies.body_motion import BodyMotion

    return BodyMotion(q, qdot, exact=True)


def coupled_reaction(model, x, v, t, body, a=None):
    """(force (3,) N, moment (3,) N m about the reference point, global axes) that coupled
    body ``body`` (a name; a Coupled rod's: end A) passes to the caller at the reduced
    state (x, v) and accelerations a (m/s2; None: zero) at time t: MoorDyn's getFnet.
    The lines' end forces and clamp moments on its points less their end nodes' inertia
    (:meth:`~skmoor.coupling.system.System.end_forces`, ``end_moments`` with a: M_ef a_f +
    M_ep a_p, the mass the ends share with the free nodes included on consistent-mass
    and bending lines) and, on a Coupled rod, its RodLoad (weight, buoyancy, drag, fluid
    inertia, bed at its pose) less its own inertia, m a_c at the centre, I alpha +
    omega x I omega about it, and its added mass on its points' accelerations. A body
    pinned on 3 coupled DOFs (a CoupledPinned rod or body) passes its pin's force (the
    -f of its :class:`PinLoad`) and no moment."""
    network, system = model.network, model.system
    coupled = network.body(body)
    if coupled.kind == "dynamic" and coupled.pin == "coupled":
        return _pin_reaction(network, system, x, v, t, body)
    if coupled.kind != "coupled":
        raise ValueError(f"coupled_reaction body: {body!r} is a {coupled.kind} body, not "
                         "a coupled one or one pinned on coupled DOFs")
    from .network import coupled_offsets, coupled_vector

    where = coupled_offsets(network)[("Body", body)]

    def pose(time):  # (reference point m, rotation) of the body at time
        y = coupled_vector(network, time)[where]
        return coupled.position + y[:3], coupled.rotation_matrix(coupled.attitude + y[3:])

    R = pose(t)[1]

    F, M = np.zeros(3), np.zeros(3)
    ends = [(k, side, network.point(end)) for k, line in enumerate(network.lines)
            for side, end in enumerate((line.b, line.a))
            if network.point(end).kind == "body" and network.point(end).body == body]
    if ends:  # the lines' loads on it, less their end nodes' inertia
        u, ud = system.full_state(x, v, t)
        a = np.zeros(system.n) if a is None else a
        forces, moments = system.end_forces(u, ud, t, a), system.end_moments(u, ud, t, a)
        for k, side, point in ends:
            f = forces[side][k]
            F += f
            M += np.cross(R @ point.position, f) + moments[side][k]
    loads = [term for term in coupled.terms if isinstance(term, RodLoad)]
    for load in loads:
        rod_F, rod_M = _rod_reaction(load, pose, R, t, COUPLED_STEP)
        F, M = F + rod_F, M + rod_M
    return F, M


def _pin_reaction(network, system, x, v, t, body):
    """(force, zero moment) the PinLoad of dynamic body ``body`` takes from the caller."""
    k = [b.name for b in network.bodies if b.kind == "dynamic"].index(body)
    block = system.dofs.blocks[k]
    pin = next(term for term in system.body_terms
               if isinstance(term, PinLoad) and term.body == k)
    return -pin.forces(x[block], v[block], t)[:3], np.zeros(3)


def _rod_reaction(load: RodLoad, pose, R, t, h):
    """(force, moment about end A) of a coupled rod's own loads less its inertia at time
    t: its RodLoad read on an exact body (moment E^-T Q), its weight, and -d(momentum)."""
    from ..bodies.large_rotations import rate_matrix, zyx_angles

    def q_at(time):
        A, Rt = pose(time)
        return np.r_[A - load.reference_point, zyx_angles(Rt)]

    q0, q, q1 = q_at(t - h), q_at(t), q_at(t + h)
    qdot, qddot = (q1 - q0) / (2 * h), (q1 - 2 * q + q0) / h ** 2
    Q = load.forces(q, qdot, t)  # [F, E^T M] (an exact body's reading: coupled_rod)
    E, dE_dry, dE_drz = rate_matrix(q[3:])
    F, M = Q[:3].copy(), np.linalg.solve(E.T, Q[3:])
    omega = E @ qdot[3:]
    alpha = E @ qddot[3:] + (dE_dry * qdot[4] + dE_drz * qdot[5]) @ qdot[3:]
    acceleration = qddot[:3]
    centre = R @ (0.5 * (load.a + load.b))  # from end A
    inertia = R @ rod_inertia(load.rod_type, load.a, load.b, load.name)[2] @ R.T

    def point_acceleration(r):
        return acceleration + np.cross(alpha, r) + np.cross(omega, np.cross(omega, r))

    weight = np.array([0.0, 0.0, -load.mass * load.g])
    inertial = -load.mass * point_acceleration(centre)
    F += weight + inertial
    M += np.cross(centre, weight + inertial) - inertia @ alpha - np.cross(omega, inertia @ omega)
    A_now = pose(t)[0]
    for r, m in load._added_mass_points(A_now, A_now + R @ (load.b - load.a)):
        f = -m @ point_acceleration(R @ r)
        F += f
        M += np.cross(R @ r, f)
    return F, M
