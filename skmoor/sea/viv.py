"""Vortex-induced vibration (VIV): MoorDyn v2's cross-flow lift with Thorsen's
synchronization model (MoorDyn source/Line.cpp, ``Line::getStateDeriv``, v2.7;
M. J. Thorsen, S. Saevik, C. M. Larsen, J. Fluids Struct. 49 (2014) 1-25).

At an internal node of a line with lift coefficient Cl > 0, with the relative flow
v = u_water - rdot, its part normal to the node's tangent q, v_p = v - (v.q) q, and the
cross-flow direction y = q x v_p / |v_p| (per unit unstretched length, N/m):

- lift            F_L = 1/2 rho d Cl |v_p| cos(phi) (q x v_p)
- phase rate      dphi/dt = 2 pi f_hat |v_p| / d,  f_hat = cF + dF sin(phi_y - phi)
- motion's phase  phi_y = atan2(-ydd / rms(ydd), yd / rms(yd)) in [0, 2 pi),
  yd = rdot.y and ydd = rddot.y the node's cross-flow velocity and acceleration, rms a
  running mean square of time constant ``rms_time`` (MoorDyn: 500 steps dtM).

The phase phi is a state of each node, advanced explicitly between accepted steps (the
term's ``commit``: phi += dphi/dt h, the acceleration from the velocities of the last two
steps); within a step the lift reads phi extrapolated to the step's time. The lift acts
from the first commit on (the integration's start): statics and modes see none, as
MoorDyn's initial-condition solve. Its tangents are left out (the Newton matrix has
none: the lift is small against the mass and drag terms over a step). End nodes carry
no lift (MoorDyn's choice). A node's lift is scaled by its wet fraction, clip(1/2 - (z -
eta) / d, 0, 1) with eta the free surface (:mod:`skmoor.sea.surface`'s rule; MoorDyn: the
wetted share of its segments).
"""
from __future__ import annotations

import numpy as np

from ..fem.terms import Term

RMS_STEPS = 500  # MoorDyn's n_m: steps dtM in the running mean square


def lift_per_length(rho, diameter, Cl, v_normal, tangent, phase):
    """F_L = 1/2 rho d Cl |v_p| cos(phi) (q x v_p), N/m; v_normal, tangent (n, 3)."""
    speed = np.linalg.norm(v_normal, axis=-1)
    return (0.5 * rho * diameter * Cl * speed * np.cos(phase))[..., None] * np.cross(tangent, v_normal)


def motion_phase(yd, ydd, yd_rms, ydd_rms):
    """phi_y = atan2(-ydd / rms(ydd), yd / rms(yd)) in [0, 2 pi) (unscaled where a
    mean square is 0), rad."""
    scaled = (yd_rms > 0) & (ydd_rms > 0)
    y = np.where(scaled, -ydd / np.where(scaled, ydd_rms, 1.0), -ydd)
    x = np.where(scaled, yd / np.where(scaled, yd_rms, 1.0), yd)
    return np.mod(np.arctan2(y, x), 2 * np.pi)


def phase_rate(phase, phase_motion, normal_speed, diameter, cF, dF):
    """dphi/dt = 2 pi (cF + dF sin(phi_y - phi)) |v_p| / d, rad/s."""
    return 2 * np.pi * (cF + dF * np.sin(phase_motion - phase)) * normal_speed / diameter


class VortexLift(Term):
    """The VIV lift on the internal nodes of every line whose LineType has Cl > 0 (its
    ``Cl``, ``viv_dF``, ``viv_cF``); sea: the water (currents), None for still water;
    rms_time: the running mean square's time constant, s."""

    acts_on = "lines"

    def __init__(self, lines, sea=None, rms_time=RMS_STEPS * 1e-4):
        if not rms_time > 0:
            raise ValueError(f"VortexLift rms_time: {rms_time!r} s must be positive")
        self.lines, self.sea, self.rms_time = lines, sea, float(rms_time)
        nodes, first_phase, coefficients = [], [], []
        stretch = lines.cable_fields["m"][:, 0]
        for k, line in enumerate(lines.lines):
            t = line.line_type
            if not t.Cl > 0:
                continue
            a, b = lines.anchor_nodes[k], lines.fairlead_nodes[k]
            inner = np.arange(a + 1, b)
            n_segments = b - a
            nodes.append(inner)
            first_phase.append(2 * np.pi * (inner - a) / n_segments)  # MoorDyn's start
            cells = slice(a - k, b - k)  # a line's cells: its nodes less one
            cell_length = lines.element_lengths[cells] * stretch[cells] / t.mass
            length = 0.5 * (cell_length[:-1] + cell_length[1:])  # unstretched, m
            coefficients.append(np.stack([np.full(inner.size, t.rho_water),
                                          np.full(inner.size, t.diameter),
                                          np.full(inner.size, t.Cl),
                                          np.full(inner.size, t.viv_cF),
                                          np.full(inner.size, t.viv_dF), length]))
        if not nodes:
            raise ValueError("VortexLift: no line type has Cl > 0")
        self.nodes = np.concatenate(nodes)
        self.first_phase = np.concatenate(first_phase)
        self.rho, self.d, self.Cl, self.cF, self.dF, self.length = np.concatenate(coefficients, axis=1)
        self.dofs = lines.nodal_dofs[self.nodes]
        self._t = None  # no committed state yet: no lift

    def _flow(self, u, v, t):
        """(node tangents q, normal relative flow v_p, node velocities, wet fractions) at
        (u, v, t)."""
        dofs = self.lines.nodal_dofs
        r = self.lines.points + u[dofs]
        q = r[self.nodes + 1] - r[self.nodes - 1]
        q /= np.linalg.norm(q, axis=1, keepdims=True)
        velocity = v[self.dofs]
        flow = -velocity
        if self.sea is not None and not self.sea.still:
            flow = flow + self.sea.velocity(r[self.nodes], t)
        v_normal = flow - np.sum(flow * q, axis=1, keepdims=True) * q
        x = r[self.nodes]
        eta = 0.0 if self.sea is None else self.sea.elevation(x, t)
        wet = np.clip(0.5 - (x[:, 2] - eta) / self.d, 0.0, 1.0)
        return q, v_normal, velocity, wet

    def add_to(self, u, v, t, R, K=None, C=None):
        if self._t is None:
            return
        q, v_normal, _, wet = self._flow(u, v, t)
        phase = self._phase + self._rate * (t - self._t)
        force = lift_per_length(self.rho, self.d, self.Cl, v_normal, q, phase)
        np.subtract.at(R, self.dofs, force * (wet * self.length)[:, None])

    def commit(self, t, u, v):
        """Advance the phases to the accepted step (t, s; u m, v m/s on the lines' DOFs);
        a time at or before the last one starts anew (a new run)."""
        q, v_normal, velocity, _ = self._flow(u, v, t)
        if self._t is None or t <= self._t:
            self._phase = self.first_phase.copy()
            acceleration = np.zeros_like(velocity)
            self._yd_ms = self._ydd_ms = np.zeros(self.nodes.size)
            weight = 1.0 / RMS_STEPS
        else:
            h = t - self._t
            self._phase = np.mod(self._phase + self._rate * h, 2 * np.pi)
            acceleration = (velocity - self._velocity) / h
            weight = min(1.0, h / self.rms_time)
        speed = np.linalg.norm(v_normal, axis=1)
        y = np.cross(q, v_normal) / np.where(speed > 0, speed, 1.0)[:, None]
        yd, ydd = np.sum(velocity * y, axis=1), np.sum(acceleration * y, axis=1)
        self._yd_ms = self._yd_ms + weight * (yd ** 2 - self._yd_ms)
        self._ydd_ms = self._ydd_ms + weight * (ydd ** 2 - self._ydd_ms)
        phase_y = motion_phase(yd, ydd, np.sqrt(self._yd_ms), np.sqrt(self._ydd_ms))
        self._rate = phase_rate(self._phase, phase_y, speed, self.d, self.cF, self.dF)
        self._t, self._velocity = t, velocity
