"""A body's pose and velocities as the terms on it read them: one place for the rotation.

A dynamic body's DOFs are q = [x, y, z, rx, ry, rz] (m, rad) of its reference point. The
angles of a body with ``rotations='exact'`` may be counted from a turned frame F of its
own (:meth:`skmoor.coupling.system.System.rebase`, no gimbal lock), so a term that reads the
attitude or the angular velocity off q[3:] is wrong after a re-base. It reads them here:

    R = Rz Ry Rx(q[3:]) F                        (F = I as built)
    omega = E(q[3:]) qdot[3:]                    ('exact'; E of large_rotations)
    p - x_ref0 = q[:3] + Rz Ry Rx(q[3:]) F r     (a body point r at the built attitude)
    Q = [force, E^T moment]                      (the load conjugate to q)

A 'small' body keeps the linear model's reading: omega = qdot[3:] and Q = [force,
moment] (E = I), F = I; its body points move with the exact kinematics as before.
"""
from __future__ import annotations

import numpy as np

from .body import attachment_state, attachment_velocity_slope, rotation_and_slopes
from .large_rotations import rate_matrix

__all__ = ["BodyMotion"]


class BodyMotion:
    """Pose and velocities of one body at DOFs q (6,) and rates qdot (6,) (m, rad, m/s,
    rad/s): frame (3, 3) the turned frame its angles count from (None: the global frame);
    exact: rotations='exact' (the angle rates map to the angular velocity through E) or
    the small-rotation model."""

    __slots__ = ("_E", "_R", "exact", "frame", "q", "qdot")

    def __init__(self, q, qdot=None, *, frame=None, exact=False):
        self.q = np.asarray(q, float)
        self.qdot = np.zeros(6) if qdot is None else np.asarray(qdot, float)
        self.frame, self.exact = frame, bool(exact)
        self._R = self._E = None

    @property
    def rotation(self) -> np.ndarray:
        """R (3, 3): body axes (the built attitude's) to global axes."""
        if self._R is None:
            R = rotation_and_slopes(self.q[3:])[0]
            self._R = R if self.frame is None else R @ self.frame
        return self._R

    @property
    def rate_map(self) -> np.ndarray:
        """E (3, 3): omega = E qdot[3:] (the identity for a small body)."""
        if self._E is None:
            self._E = rate_matrix(self.q[3:])[0] if self.exact else np.eye(3)
        return self._E

    @property
    def velocity(self) -> np.ndarray:
        """The reference point's velocity (m/s)."""
        return self.qdot[:3]

    @property
    def angular_velocity(self) -> np.ndarray:
        """omega (global, rad/s)."""
        return self.rate_map @ self.qdot[3:]

    def points(self, r) -> tuple[np.ndarray, np.ndarray]:
        """Where body points r (n, 3) are, q[:3] + R r (n, 3), from the reference point as
        built (r from it at the built attitude, global axes, m), and their Jacobian d/dq
        (3 n, 6): their velocities are J qdot, a force f on them is the load J^T f."""
        r = np.ascontiguousarray(r, dtype=float)
        turned = r if self.frame is None else np.ascontiguousarray(r @ self.frame.T)
        moved, J = attachment_state(self.q, turned)
        return turned + moved, J

    def accelerations(self, r, qddot) -> tuple[np.ndarray, np.ndarray]:
        """Accelerations (n, 3) (m/s2) of body points r (as :meth:`points`) at DOF
        accelerations qddot, J qddot + d(J qdot)/dq qdot, and their Jacobian J (3 n, 6)."""
        r = np.ascontiguousarray(r, dtype=float)
        turned = r if self.frame is None else np.ascontiguousarray(r @ self.frame.T)
        _, J = attachment_state(self.q, turned)
        slope = attachment_velocity_slope(self.q, turned, self.qdot)
        return (J @ qddot + slope @ self.qdot).reshape(-1, 3), J

    def generalized(self, force, moment) -> np.ndarray:
        """[force, E^T moment] (N, N m): a force and a moment about the reference point
        (global) as the load conjugate to q."""
        return np.concatenate([force, self.rate_map.T @ np.asarray(moment, float)])
