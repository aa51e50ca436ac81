"""Body frames of a :class:`~skmoor.coupling.system.System`: where the line ends on each
rigid body are at its DOFs q (m, rad), and the re-based frames of 'exact' bodies, whose
angles are counted from a past attitude past a pitch of ``REBASE_PITCH`` (rad) so that
they never reach the gimbal lock (see :mod:`skmoor.bodies.large_rotations`).
"""
from __future__ import annotations

import math

import numpy as np

from ..bodies import body as rigid
from ..bodies.body_motion import BodyMotion
from ..bodies.large_rotations import rate_matrix, zyx_angles

REBASE_PITCH = math.radians(60.0)  # |ry| past which an 'exact' body's angles are re-based


class BodyFrames:
    """The body-frame part of :class:`~skmoor.coupling.system.System` (a mixin on its
    ``dofs``, ``bodies``, ``nf``, ``nb`` and terms): ``frames`` holds each body's re-based
    frame (a rotation (3, 3), None: the global frame) and ``frame_r_local`` where its line
    ends sit from its reference point in that frame (m, (n_k, 3) per body)."""

    def _init_frames(self):
        self.frames = [None] * len(self.bodies)
        self.frame_r_local = [r.copy() for r in self.dofs.r_local0]
        self._end_offsets = np.zeros((len(self.dofs.body_of_end), 3))  # m, R0 r0 - r0
        self._attachment_cache = (None, None, None)

    def rebase(self, x, v):
        """Re-base the angles of every 'exact' body whose pitch passed ``REBASE_PITCH``:
        its angles are then counted from its present attitude (R = Rz Ry Rx(q) @ frame,
        the new q angles 0, their rates the angular velocity). Returns the new (x, v), or
        None when no body was re-based. A body with a term that reads its angles off q
        (not ``frame_aware``: a user's BodyLoad) is not re-based: it stops at the gimbal
        lock with an error."""
        turned = None
        for k, body in enumerate(self.bodies):
            block = self.dofs.blocks[k]
            q = x[block]
            if (body.rotations != "exact" or abs(q[4]) < REBASE_PITCH
                    or any(term.body == k and not term.frame_aware
                           for term in self._terms["bodies"])
                    or any(k in term.bodies for term in self._terms["body pairs"])):
                continue
            if turned is None:
                turned = (x.copy(), v.copy())
                self._attachment_cache = (None, None, None)
            x1, v1 = turned
            E = rate_matrix(q[3:])[0]
            v1[block.start + 3: block.stop] = E @ v[block][3:]  # omega (global)
            x1[block.start + 3: block.stop] = 0.0
            self.frames[k] = body.rotation(q, self.frames[k])
            rows = self.dofs.body_rows[k]
            if len(rows):  # line ends on the body: R0 r0 - r0 of the turn stays constant
                r0 = self.dofs.r_local0[k]
                self.frame_r_local[k] = r0 @ self.frames[k].T
                self._end_offsets[rows] = self.frame_r_local[k] - r0
        return turned

    def reset_frames(self):
        """Count every body's angles from the global frame again (as built)."""
        self._init_frames()

    def use_frames(self, frames):
        """Count the bodies' angles from ``frames`` (per body a rotation (3, 3) or None,
        as :attr:`frames` holds them; another system's of the same bodies, e.g. before a
        line failure), the line ends on them placed as :meth:`rebase` places them."""
        self._init_frames()
        for k, frame in enumerate(frames):
            if frame is None:
                continue
            self.frames[k] = np.array(frame, float)
            rows = self.dofs.body_rows[k]
            if len(rows):
                r0 = self.dofs.r_local0[k]
                self.frame_r_local[k] = r0 @ self.frames[k].T
                self._end_offsets[rows] = self.frame_r_local[k] - r0

    def body_rotation(self, x, body=0) -> np.ndarray:
        """The attitude R (3, 3) of body ``body`` in the reduced state x (its angles
        counted from its re-based frame, :meth:`rebase`)."""
        return self.bodies[body].rotation(self.q(x, body), self.frames[body])

    def body_motion(self, q, qdot=None, body=0) -> BodyMotion:
        """The :class:`~skmoor.bodies.body_motion.BodyMotion` of body ``body`` at its DOFs q and
        rates qdot: what its terms read of its attitude (re-based frame included)."""
        return BodyMotion(q, qdot, frame=self.frames[body],
                          exact=self.bodies[body].rotations == "exact")

    def global_rates(self, q, qdot, k):
        """(q, qdot) of re-based body k with its angles (and their rates) counted from the
        global frame: what its ``body_load`` sees (at the gimbal lock the rates are the
        least-squares ones)."""
        angles = zyx_angles(self.bodies[k].rotation(q, self.frames[k]))
        omega = rate_matrix(q[3:])[0] @ qdot[3:]
        rates = np.linalg.lstsq(rate_matrix(angles)[0], omega, rcond=None)[0]
        return np.r_[q[:3], angles], np.r_[qdot[:3], rates]

    def body_pose(self, x) -> np.ndarray:
        """(nbodies, 6) displacement and angles Rz Ry Rx from the global frame of every
        body in the reduced state x (m, rad): x's own body DOFs unless re-based."""
        out = x[self.nf:].reshape(-1, 6).copy()
        for k, frame in enumerate(self.frames):
            if frame is not None:
                out[k, 3:] = zyx_angles(self.body_rotation(x, k))
        return out

    def _attachment(self, x):
        """Body-end displacements (n, 3) and their Jacobian (3 n, 6 nbodies) at the body
        DOFs of x, computed once per state."""
        q = x[self.nf:]
        key = q.tobytes()
        if self._attachment_cache[0] != key:
            if not math.isfinite(q.sum()):
                raise ValueError(f"System: body DOFs are not finite: {q}")
            dofs = self.dofs
            if len(self.bodies) == 1:
                state = rigid.attachment_state(q, self.frame_r_local[0])
            else:
                disp = np.zeros((len(dofs.body_of_end), 3))
                J = np.zeros((3 * len(dofs.body_of_end), self.nb))
                for k, rows in enumerate(dofs.body_rows):
                    if len(rows):
                        d, Jk = rigid.attachment_state(q[6 * k: 6 * k + 6],
                                                       self.frame_r_local[k])
                        disp[rows] = d
                        J[3 * rows[0]: 3 * rows[-1] + 3, 6 * k: 6 * k + 6] = Jk
                state = (disp, J)
            if len(dofs.directions):  # clamped tangents: the rotation's part only
                disp, J = state
                disp[dofs.directions] -= q.reshape(-1, 6)[dofs.body_of_end[dofs.directions], :3]
                J[dofs.direction_translation] = 0.0
            if any(frame is not None for frame in self.frames):
                state = (state[0] + self._end_offsets, state[1])
            self._attachment_cache = (key, *state)
        return self._attachment_cache[1], self._attachment_cache[2]

    def _jacobian(self, x):
        """(3 n, 6 nbodies) Jacobian of the body ends, or None without bodies."""
        if not self.nb:
            return None
        return self._attachment(x)[1]
