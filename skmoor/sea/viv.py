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

The lift is written once as forms on nodal quadrature (:func:`vortex_lift` and
:func:`vortex_lift_update`, run by :class:`VortexLiftForm`); :class:`VortexLift` is their
hand-written kernels, faster in the time loop and run by default.

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
from skfem import LinearForm

from ..fem import ops
from ..fem.form_compiler import compiled_when_asked
from ..fem.native_calls import advanced, call_form
from ..fem.terms import HAS_JAX, PATHS, Term, state_part
from .hydro import (
    SeaTerm,
    _set_water,
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
    mean square is 0), rad (NumPy or traced arrays)."""
    scaled = (yd_rms > 0) & (ydd_rms > 0)
    y = ops.where(scaled, -ydd / ops.where(scaled, ydd_rms, 1.0), -ydd)
    x = ops.where(scaled, yd / ops.where(scaled, yd_rms, 1.0), yd)
    return ops.mod(ops.arctan2(y, x), 2 * np.pi)


def phase_rate(phase, phase_motion, normal_speed, diameter, cF, dF):
    """dphi/dt = 2 pi (cF + dF sin(phi_y - phi)) |v_p| / d, rad/s (NumPy or traced
    arrays)."""
    return 2 * np.pi * (cF + dF * ops.sin(phase_motion - phase)) * normal_speed / diameter


# --- the lift and its memory written as forms (the definition), on nodal quadrature.
# Fields: lift = 1/2 rho d Cl per reference length (0 at the lines' end nodes and where
# Cl = 0), d, cF, dF, rms_time at the points; DOF fields: X the reference positions, qn the
# node's chord r_{i+1} - r_{i-1}, eta the surface elevation (each component), uw the
# water's velocity at the displaced node. Memory: phase, rate, yd_ms, ydd_ms, the node's
# velocity (vx, vy, vz), lifting (1 after the first commit) and t_commit (its time).

def node_flow(w):
    """(q, v_p, |v_p|) at the points of a :class:`VortexLiftForm`'s w: the node's unit
    tangent (its chord's direction), the relative flow's part normal to it (m/s) and its
    size."""
    q = ops.value(w.qn) / ops.norm(w.qn)
    flow = ops.value(w.uw) - ops.value(w.du)
    normal = flow - ops.dot(flow, q) * q
    return q, normal, ops.norm(normal)


@LinearForm
def vortex_lift(v, w):
    # -F_L . du, F_L = 1/2 rho d Cl |v_p| cos(phi) (q x v_p) times the wet fraction
    q, normal, speed = node_flow(w)
    phase = w.phase + w.rate * (w.t - w.t_commit)  # extrapolated within the step
    z = ops.value(w.X)[2] + ops.value(w.u)[2]
    wet = ops.clip(0.5 - (z - ops.value(w.eta)[2]) / w.d, 0.0, 1.0)
    size = w.lifting * w.lift * wet * speed * ops.cos(phase)
    return -size * ops.dot(ops.cross(q, normal), v)


def vortex_lift_update(w):
    """The lift's memory at an accepted step: the phase advanced by its rate over the
    step dt, the cross-flow velocity yd and acceleration ydd (from the last step's
    velocity) in running mean squares of time constant rms_time, the motion's phase and
    the new rate (:func:`motion_phase`, :func:`phase_rate`); the first commit starts the
    lift (ydd 0, weight 1 / RMS_STEPS), a second one at the same time keeps it."""
    fresh = w.lifting < 0.5
    held = (w.lifting > 0.5) & (w.dt <= 0.0)
    phase = ops.where(fresh, w.phase, ops.mod(w.phase + w.rate * w.dt, 2 * np.pi))
    q, normal, speed = node_flow(w)
    velocity = ops.value(w.du)
    before = ops.xp(velocity).stack([w.vx, w.vy, w.vz])
    acceleration = ops.where(fresh, 0.0, (velocity - before) / ops.where(w.dt > 0.0, w.dt, 1.0))
    across = ops.cross(q, normal) / ops.where(speed > 0.0, speed, 1.0)
    yd, ydd = ops.dot(velocity, across), ops.dot(acceleration, across)
    weight = ops.where(fresh, 1.0 / RMS_STEPS, ops.minimum(1.0, w.dt / w.rms_time))
    yd_ms = w.yd_ms + weight * (yd * yd - w.yd_ms)
    ydd_ms = w.ydd_ms + weight * (ydd * ydd - w.ydd_ms)
    phase_y = motion_phase(yd, ydd, ops.sqrt(yd_ms), ops.sqrt(ydd_ms))
    new = dict(phase=phase, rate=phase_rate(phase, phase_y, speed, w.d, w.cF, w.dF),
               yd_ms=yd_ms, ydd_ms=ydd_ms, vx=velocity[0], vy=velocity[1], vz=velocity[2],
               lifting=1.0 + 0.0 * phase, t_commit=w.t + 0.0 * phase)
    return {name: ops.where(held, getattr(w, name), value) for name, value in new.items()}


class VortexLift(Term):
    """The VIV lift on the internal nodes of every line whose LineType has Cl > 0 (its
    ``Cl``, ``viv_dF``, ``viv_cF``), the hand-written kernels of :func:`vortex_lift` and
    its memory's update (:class:`VortexLiftForm`; held equal to them by tests, faster in
    the time loop); sea: the water (currents), None for still water;
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
    if t == state[0]:  # a second commit at the same time keeps the state
        return
    n = X.shape[1]
    u, v = carray(u_p, (ndofs,)), carray(ud_p, (ndofs,))
    d, cF, dF = coefficients[1], coefficients[3], coefficients[4]
    _flow_at(u, v, t, dofs, X, d, heading, heights, speeds, water, scratch)
    restart = math.isnan(state[0]) or t < state[0]
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


class VortexLiftForm(SeaTerm):
    """The VIV lift as :func:`vortex_lift` with its memory :func:`vortex_lift_update`, a
    :class:`~skmoor.sea.hydro.SeaTerm` on nodal quadrature (each node's lift from its two
    elements' ends, half an element's length each): the same lift as
    :class:`VortexLift`, and its tangents by automatic differentiation. lines, sea,
    rms_time as VortexLift's; path: the form's (:class:`~skmoor.fem.terms.LineForm`;
    'compiled' runs in the compiled time step, the node tangents and the surface
    filled in by :func:`_lift_form_packed`).

    lift, update, state: another lift model on the same fields (``w.qn`` the node's
    chord, ``w.eta`` the surface, ``w.uw`` the water, ``w.X`` the reference positions and
    the point fields ``lift``, ``d``, ``cF``, ``dF``, ``rms_time``): its load (a
    LinearForm), its memory's rule (a function of w returning every state value by
    name) and its memory beyond the built-in one (name -> initial value)."""

    def __init__(self, lines, sea=None, rms_time=RMS_STEPS * 1e-4, path="compiled", *,
                 lift=vortex_lift, update=vortex_lift_update, state=None):
        if not rms_time > 0:
            raise ValueError(f"VortexLiftForm rms_time: {rms_time!r} s must be positive")
        nodes, node_cells = lines.mesh.t, lines.line_of_cell  # (2, nel): a cell's end nodes
        types = [line.line_type for line in lines.lines]
        if not any(t.Cl > 0 for t in types):
            raise ValueError("VortexLiftForm: no line type has Cl > 0")

        def per_cell(name):
            return np.array([getattr(t, name) for t in types], float)[node_cells]

        ends = np.zeros(len(lines.points), bool)
        ends[lines.anchor_nodes] = ends[lines.fairlead_nodes] = True
        first_phase = np.zeros(len(lines.points))  # MoorDyn's start, 2 pi i / n on a line
        for a, b in zip(lines.anchor_nodes, lines.fairlead_nodes):
            first_phase[a:b + 1] = 2 * np.pi * np.arange(b - a + 1) / (b - a)
        per_reference = lines.cable_fields["m"][:, 0] / per_cell("mass")  # 1 / stretch
        lifting = per_cell("Cl") > 0
        size = 0.5 * per_cell("rho_water") * per_cell("diameter") * per_cell("Cl") * per_reference
        points = nodes.T  # (nel, 2): the node at each nodal quadrature point

        def at_points(per_cell_values):
            return np.repeat(per_cell_values[:, None], 2, axis=1)

        fields = dict(lift=np.where(ends[points], 0.0, size[:, None]),
                      d=at_points(np.where(lifting, per_cell("diameter"), 1.0)),
                      cF=at_points(per_cell("viv_cF")), dF=at_points(per_cell("viv_dF")),
                      rms_time=np.full(points.shape, float(rms_time)),
                      X=lines.reference_dofs.copy())
        # the chord of each node: its neighbours', at a line's end its element's
        self._before = np.arange(len(ends)) - 1
        self._before[lines.anchor_nodes] = lines.anchor_nodes
        self._after = np.arange(len(ends)) + 1
        self._after[lines.fairlead_nodes] = lines.fairlead_nodes
        memory = dict(phase=first_phase[points], rate=0.0, yd_ms=0.0, ydd_ms=0.0, vx=0.0,
                      vy=0.0, vz=0.0, lifting=0.0, t_commit=0.0)
        super().__init__(lift, sea=sea, quadrature="nodal", fields=fields,
                         state=dict(memory, **(state or {})), update=update, path=path,
                         lines=lines)

    @property
    def rms_time(self) -> float:
        """The running mean squares' time constant, s (fixed when the form is made)."""
        return float(self.fields["rms_time"][0, 0])

    def fields_at(self, t, u):
        lines = self.lines
        r = lines.points + u[lines.nodal_dofs]
        chord, surface = np.zeros(lines.ndofs), np.zeros(lines.ndofs)
        chord[lines.nodal_dofs] = r[self._after] - r[self._before]
        if self.sea is not None:
            surface[lines.nodal_dofs] = np.asarray(self.sea.elevation(r, t), float)[:, None]
        return dict(super().fields_at(t, u), qn=chord, eta=surface)

    def fields_vary(self) -> bool:
        return True  # the node tangents move with the lines

    def _more_ints(self, dof_names, D_start):
        """Where the chord, surface and reference-position fields start in the floats,
        then each node's neighbours (before, after)."""
        ndofs = self.lines.ndofs
        return np.concatenate([[D_start + dof_names.index(name) * ndofs
                                for name in ("qn", "eta", "X")], self._before, self._after])

    def _packed_steps(self):
        return _lift_form_step(), _lift_commit_step()


def vortex_lift_term(lines, sea=None, *, rms_time=RMS_STEPS * 1e-4, path="auto"):
    """The VIV lift of a System on ``lines``: the hand-written kernels
    (:class:`VortexLift`) on path 'auto', else the forms (:class:`VortexLiftForm`) on
    ``path`` ('assembly': 'compiled' with JAX, else 'fd')."""
    if path not in PATHS:
        raise ValueError(f"vortex_lift_term path: {path!r} is not one of {PATHS}")
    if path == "auto":
        return VortexLift(lines, sea, rms_time)
    if path == "assembly":
        path = "compiled" if HAS_JAX else "fd"
    return VortexLiftForm(lines, sea, rms_time, path=path)


@njit(cache=True)
def _set_chords(u, t, ints, at, floats, ndofs):
    """The chords r_after - r_before and the surface elevation at the displaced nodes set
    in a :class:`VortexLiftForm`'s DOF fields (its ``_more_ints`` from ints[at]; the water's
    packed after ``SeaTerm._water_step_kernel``'s header); returns where the generated
    kernel's ints start."""
    nnodes, axes = ints[2], 3 if ints[5] else 1
    dofs = carray(advanced(ints, 9 + axes * nnodes), (nnodes, 3))
    chord = carray(advanced(floats, ints[at]), (ndofs,))
    surface = carray(advanced(floats, ints[at + 1]), (ndofs,))
    X = carray(advanced(floats, ints[at + 2]), (ndofs,))
    before = carray(advanced(ints, at + 3), (nnodes,))
    after = carray(advanced(ints, at + 3 + nnodes), (nnodes,))
    _, _, _, components, fields, _ = unpacked_water(floats, ints[1] + axes * nnodes, ints[3],
                                                    ints[4])
    for p in range(nnodes):
        for c in range(3):
            a, b = dofs[after[p], c], dofs[before[p], c]
            chord[dofs[p, c]] = (X[a] + u[a]) - (X[b] + u[b])
        x, y = X[dofs[p, 0]] + u[dofs[p, 0]], X[dofs[p, 1]] + u[dofs[p, 1]]
        eta = wave_elevation(x, y, t, components, fields)
        for c in range(3):
            surface[dofs[p, c]] = eta
    return at + 3 + 2 * nnodes


def _lift_form_packed(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """A :class:`VortexLiftForm`'s generated kernel (the C function at ints[0]) after its
    water, chord and surface fields (:func:`~skmoor.sea.hydro._set_water`,
    :func:`_set_chords`)."""
    u = carray(u_p, (ndofs,))
    start = _set_chords(u, t, ints, _set_water(u, t, ints, floats, ndofs), floats, ndofs)
    call_form(ints[0], u_p, ud_p, ndofs, t, advanced(ints, start), floats, R_p, K_p, C_p,
              tangent)


def _lift_commit_packed(u_p, ud_p, ndofs, t, ints, floats, R_p, K_p, C_p, tangent):
    """A :class:`VortexLiftForm`'s generated commit (the C function at ints[8]) after its
    fields, as :func:`_lift_form_packed`."""
    u = carray(u_p, (ndofs,))
    start = _set_chords(u, t, ints, _set_water(u, t, ints, floats, ndofs), floats, ndofs)
    call_form(ints[8], u_p, ud_p, ndofs, t, advanced(ints, start), floats, R_p, K_p, C_p,
              tangent)


_lift_form_step = compiled_when_asked(_lift_form_packed)  # (its C function when asked)


_lift_commit_step = compiled_when_asked(_lift_commit_packed)  # (its C function when asked)
