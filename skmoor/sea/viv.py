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

import math

import numpy as np
from numba import carray, njit

from ..fem.form_compiler import compiled_when_asked
from ..fem.native_calls import advanced
from ..fem.terms import Term, state_part
from .hydro import (
    unpacked_water,
    water_arrays,
    water_kinematics,
    water_lowers,
    wave_elevation,
)

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
    rms_time: the running mean square's time constant, s. Its state (the last committed
    time, each node's phase, phase rate, mean squares and velocity) is one array, which
    the compiled time step advances in place with :attr:`step_commit` (still water, a
    current and Airy waves; the Python step with :meth:`commit`)."""

    acts_on = "lines"
    why_python = "VIV lift in a water field of a kind the compiled kernels lack"

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
        n = self.nodes.size
        # [t, phase (n), rate (n), yd_ms (n), ydd_ms (n), velocity (n, 3)]; t NaN: no
        # committed state yet (no lift)
        self._state = np.full(1 + 7 * n, np.nan)

    _phase, _rate, _yd_ms, _ydd_ms = (state_part(k) for k in range(4))
    _velocity = state_part(4, 3)

    @property
    def _per_block(self):
        return self.nodes.size

    @property
    def _t(self):
        """The last committed time (s), None before the first commit."""
        return None if math.isnan(self._state[0]) else float(self._state[0])

    @property
    def compiled_water(self) -> bool:
        """Whether the compiled kernels evaluate the water
        (:func:`~skmoor.sea.hydro.water_lowers`)."""
        return water_lowers(self.sea)

    def lowered(self):
        return "form" if self.compiled_water else None

    @property
    def step_kernel(self):
        """(C function, ints, floats): the lift (:func:`_lift_packed`) as the compiled time
        step calls a LineForm, by address; ints [nodes, profile points, wave components,
        the nodes' DOFs and their neighbours' (3 x (n, 3))], floats [the reference
        positions of the nodes and their neighbours (3 x (n, 3), m), rho, d, Cl, cF, dF,
        length (6 x n), the first phases (n, rad), the current's heading (2) and profile
        (heights m, speeds m/s), the Airy components (:func:`~skmoor.sea.hydro.wave_components`),
        the packed fields, rms_time (s), the state (:attr:`step_state`), scratch (10 n)]."""
        lines, n = self.lines, self.nodes.size
        heading, heights, speeds, waves, fields = water_arrays(self.sea)
        nodal = lines.nodal_dofs
        ints = np.concatenate([[n, len(heights), len(waves)],
                               *(nodal[self.nodes + k].ravel() for k in (0, -1, 1))])
        floats = np.concatenate([
            *(lines.points[self.nodes + k].ravel() for k in (0, -1, 1)),
            self.rho, self.d, self.Cl, self.cF, self.dF, self.length, self.first_phase,
            heading, heights, speeds, waves.ravel(), fields, [self.rms_time], self._state,
            np.zeros(10 * n)])
        return _lift_step(), ints.astype(np.int64), floats.astype(float)

    @property
    def step_commit(self):
        """The C function that advances the state in the buffers of :attr:`step_kernel` to
        an accepted step (:func:`_commit_packed`; the compiled step calls it, by address)."""
        return _commit_step()

    def step_state(self):
        """(the state array, its offset from the end of :attr:`step_kernel`'s floats)."""
        return self._state, self._state.size + 10 * self.nodes.size

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

    def carry_memory(self, other):
        """Take ``other``'s state (the lift of the same lines in another model: a line
        failure's rebuilt one) as this term's."""
        if other._state.shape != self._state.shape:
            raise ValueError("VortexLift.carry_memory: the other term has other nodes")
        self._state[:] = other._state

    def commit(self, t, u, v):
        """Advance the phases to the accepted step (t, s; u m, v m/s on the lines' DOFs);
        a time before the last one starts anew (a new run), the last one's keeps it (a
        run going on from it)."""
        if self._t is not None and t == self._t:
            return
        q, v_normal, velocity, _ = self._flow(u, v, t)
        if self._t is None or t < self._t:
            self._phase[:] = self.first_phase
            acceleration = np.zeros_like(velocity)
            self._yd_ms[:] = self._ydd_ms[:] = 0.0
            weight = 1.0 / RMS_STEPS
        else:
            h = t - self._t
            self._phase[:] = np.mod(self._phase + self._rate * h, 2 * np.pi)
            acceleration = (velocity - self._velocity) / h
            weight = min(1.0, h / self.rms_time)
        speed = np.linalg.norm(v_normal, axis=1)
        y = np.cross(q, v_normal) / np.where(speed > 0, speed, 1.0)[:, None]
        yd, ydd = np.sum(velocity * y, axis=1), np.sum(acceleration * y, axis=1)
        self._yd_ms[:] = self._yd_ms + weight * (yd ** 2 - self._yd_ms)
        self._ydd_ms[:] = self._ydd_ms + weight * (ydd ** 2 - self._ydd_ms)
        phase_y = motion_phase(yd, ydd, np.sqrt(self._yd_ms), np.sqrt(self._ydd_ms))
        self._rate[:] = phase_rate(self._phase, phase_y, speed, self.d, self.cF, self.dF)
        self._state[0] = t
        self._velocity[:] = velocity


# --- the compiled kernels: add_to and commit above on the packed buffers of step_kernel

@njit(cache=True)
def _unpacked(ints, floats):
    """The buffers of ``VortexLift.step_kernel`` as arrays: (node DOFs (3, n, 3): the
    node's and its neighbours', reference positions (3, n, 3), coefficients (6, n),
    first phases, heading, heights, speeds, (wave components, packed fields), rms_time
    (1,), state, scratch (10, n))."""
    n, nprofile, ncomponents = ints[0], ints[1], ints[2]
    dofs = carray(advanced(ints, 3), (3, n, 3))
    X = carray(floats, (3, n, 3))
    at = 9 * n
    coefficients = carray(advanced(floats, at), (6, n))
    first = carray(advanced(floats, at + 6 * n), (n,))
    heading, heights, speeds, waves, fields, at = unpacked_water(floats, at + 7 * n, nprofile,
                                                                 ncomponents)
    rms_time = carray(advanced(floats, at), (1,))
    state = carray(advanced(floats, at + 1), (1 + 7 * n,))
    scratch = carray(advanced(floats, at + 2 + 7 * n), (10, n))
    return (dofs, X, coefficients, first, heading, heights, speeds, (waves, fields), rms_time,
            state, scratch)


@njit(cache=True)
def _flow_at(u, v, t, dofs, X, d, heading, heights, speeds, water, scratch):
    """``VortexLift._flow`` into the scratch rows: q (0-2), v_p (3-5), the node velocity
    (6-8) and the wet fraction (9), per node at time t (s) (the current and the Airy
    waves at the displaced node; z = 0 the still surface)."""
    kinematics = np.zeros(6)  # the water's velocity and acceleration at a node
    for k in range(X.shape[1]):
        length = 0.0
        for c in range(3):
            q = (X[2, k, c] + u[dofs[2, k, c]]) - (X[1, k, c] + u[dofs[1, k, c]])
            scratch[c, k] = q
            length += q * q
        length = math.sqrt(length)
        x, y = X[0, k, 0] + u[dofs[0, k, 0]], X[0, k, 1] + u[dofs[0, k, 1]]
        z = X[0, k, 2] + u[dofs[0, k, 2]]
        waves, fields = water
        water_kinematics(x, y, z, t, heading, heights, speeds, waves, fields, kinematics)
        eta = wave_elevation(x, y, t, waves, fields)
        along = 0.0
        for c in range(3):
            scratch[c, k] /= length
            scratch[6 + c, k] = v[dofs[0, k, c]]
            flow = kinematics[c] - scratch[6 + c, k]
            scratch[3 + c, k] = flow
            along += flow * scratch[c, k]
        for c in range(3):
            scratch[3 + c, k] -= along * scratch[c, k]
        scratch[9, k] = min(max(0.5 - (z - eta) / d[k], 0.0), 1.0)


def _lift_packed(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """``VortexLift.add_to`` on the buffers of its ``step_kernel`` (no tangents)."""
    dofs, X, coefficients, first, heading, heights, speeds, water, rms_time, state, scratch = (
        _unpacked(ints, floats))
    if math.isnan(state[0]):
        return
    n = X.shape[1]
    u, v, R = carray(u_p, (ndofs,)), carray(ud_p, (ndofs,)), carray(R_p, (ndofs,))
    rho, d, Cl = coefficients[0], coefficients[1], coefficients[2]
    _flow_at(u, v, t, dofs, X, d, heading, heights, speeds, water, scratch)
    for k in range(n):
        phase = state[1 + k] + state[1 + n + k] * (t - state[0])
        speed = math.sqrt(scratch[3, k] ** 2 + scratch[4, k] ** 2 + scratch[5, k] ** 2)
        size = 0.5 * rho[k] * d[k] * Cl[k] * speed * math.cos(phase) * (
            scratch[9, k] * coefficients[5, k])
        qx, qy, qz = scratch[0, k], scratch[1, k], scratch[2, k]
        px, py, pz = scratch[3, k], scratch[4, k], scratch[5, k]
        R[dofs[0, k, 0]] -= size * (qy * pz - qz * py)
        R[dofs[0, k, 1]] -= size * (qz * px - qx * pz)
        R[dofs[0, k, 2]] -= size * (qx * py - qy * px)


def _commit_packed(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """``VortexLift.commit`` on the buffers of its ``step_kernel`` (R, K, C unused)."""
    dofs, X, coefficients, first, heading, heights, speeds, water, rms_time, state, scratch = (
        _unpacked(ints, floats))
    n = X.shape[1]
    u, v = carray(u_p, (ndofs,)), carray(ud_p, (ndofs,))
    d, cF, dF = coefficients[1], coefficients[3], coefficients[4]
    _flow_at(u, v, t, dofs, X, d, heading, heights, speeds, water, scratch)
    restart = math.isnan(state[0]) or t <= state[0]
    h = 0.0 if restart else t - state[0]
    weight = 1.0 / RMS_STEPS if restart else min(1.0, h / rms_time[0])
    phase, rate = state[1: 1 + n], state[1 + n: 1 + 2 * n]
    yd_ms, ydd_ms = state[1 + 2 * n: 1 + 3 * n], state[1 + 3 * n: 1 + 4 * n]
    velocity = state[1 + 4 * n:]
    for k in range(n):
        if restart:
            phase[k] = first[k]
            yd_ms[k] = ydd_ms[k] = 0.0
        else:
            phase[k] = (phase[k] + rate[k] * h) % (2 * np.pi)
        px, py, pz = scratch[3, k], scratch[4, k], scratch[5, k]
        speed = math.sqrt(px * px + py * py + pz * pz)
        scale = speed if speed > 0 else 1.0
        qx, qy, qz = scratch[0, k], scratch[1, k], scratch[2, k]
        y = ((qy * pz - qz * py) / scale, (qz * px - qx * pz) / scale,
             (qx * py - qy * px) / scale)
        yd = ydd = 0.0
        for c in range(3):
            now = scratch[6 + c, k]
            yd += now * y[c]
            if not restart:
                ydd += (now - velocity[3 * k + c]) / h * y[c]
            velocity[3 * k + c] = now
        yd_ms[k] += weight * (yd * yd - yd_ms[k])
        ydd_ms[k] += weight * (ydd * ydd - ydd_ms[k])
        yd_rms, ydd_rms = math.sqrt(yd_ms[k]), math.sqrt(ydd_ms[k])
        if yd_rms > 0 and ydd_rms > 0:
            phase_y = math.atan2(-ydd / ydd_rms, yd / yd_rms) % (2 * np.pi)
        else:
            phase_y = math.atan2(-ydd, yd) % (2 * np.pi)
        rate[k] = 2 * np.pi * (cF[k] + dF[k] * math.sin(phase_y - phase[k])) * speed / d[k]
    state[0] = t


_lift_step = compiled_when_asked(_lift_packed)  # (its C function, when first asked for)


_commit_step = compiled_when_asked(_commit_packed)  # (its C function, when first asked for)
