"""A pin joining two dynamic bodies: MoorDyn's Body<N>Pinned rod on a free body.

The pinned body's reference point (a rod's end A) is held at a point of the carrier body
by a stiff spring-damper, as :class:`~skmoor.bodies.rod_loads.PinLoad` holds a pinned rod in place:
both bodies turn freely about the pin, which carries force and no moment. With p the
pin's place on the carrier (its reference point plus R(q_c) r - r, Jacobian J_c) and
x the pinned body's reference point (q_p[:3]),

    f = -k (x - p) - c (x' - p')    on the pinned body at x, -f on the carrier at p,

k = m g / (1e-6 L) (the pin gives 1e-6 L under the pinned body's weight m g, standard
gravity when g = 0; L a length of it) and c = 2 sqrt(k mu), mu = m m_c / (m + m_c) the pair's reduced mass (the pin's
own mode critically damped). The term acts on both bodies' 12 DOFs, with its exact
tangent: the generalized force is G^T f with G = [-J_c | I 0], so
d(-G^T f)/dq = G^T (k G + c S) - H_c(k gap + c rate), S = d(rate)/dq, H_c the carrier
point's second derivative (:func:`~skmoor.bodies.body.attachment_hessian`).
"""
from __future__ import annotations

import math

import numpy as np

from ..bodies.body import (
    attachment_hessian,
    attachment_state,
    attachment_velocity_slope,
)
from ..bodies.rod_loads import PIN_DEFLECTION, spring_weight
from ..fem.terms import Term

__all__ = ["BodyPin"]


class BodyPin(Term):
    """A pin from a point of a carrier body to a pinned body's reference point.

    point: the pin on the carrier, relative to the carrier's reference point at q = 0
    (global axes, m); mass, carrier_mass: the pinned body's and the carrier's (kg);
    length: the pinned body's length scale (m, the pin's stiffness, see the module
    docstring); bodies: (carrier, pinned), indices among the dynamic bodies. Acts on
    ``"body pairs"``: q, qdot the carrier's 6 DOFs then the pinned body's 6."""

    acts_on = "body pairs"

    def __init__(self, point, *, mass, carrier_mass, length, g=9.81, bodies=(0, 1)):
        self.point = np.asarray(point, float).reshape(1, 3)
        self.stiffness = spring_weight(mass, g) / (PIN_DEFLECTION * length)  # N/m
        reduced = mass * carrier_mass / (mass + carrier_mass)
        self.damping = 2 * math.sqrt(self.stiffness * reduced)  # N s/m
        self.bodies = tuple(bodies)

    def gap(self, q) -> np.ndarray:
        """How far the pinned body's reference point is from the pin (3,), m."""
        q = np.asarray(q, float)
        return q[6:9] - attachment_state(q[:6], self.point)[0][0]

    def add_to(self, q, qdot, t, R, K=None, C=None):
        q, qdot = np.asarray(q, float), np.asarray(qdot, float)
        moved, J = attachment_state(q[:6], self.point)
        G = np.zeros((3, 12))
        G[:, :6], G[:, 6:9] = -J, np.eye(3)
        gap, rate = q[6:9] - moved[0], G @ qdot
        w = self.stiffness * gap + self.damping * rate  # -f, N
        R += G.T @ w
        if K is None:
            return
        S = np.zeros((3, 12))
        S[:, :6] = -attachment_velocity_slope(q[:6], self.point, qdot[:6])
        K += G.T @ (self.stiffness * G + self.damping * S)
        K[:6, :6] -= attachment_hessian(q[:6], self.point, w)
        C += self.damping * G.T @ G
