"""Exact bodies turned through pitch 90 deg (the gimbal lock of R = Rz Ry Rx): their angles
re-based on the way (System.rebase), against the invariants of a free rigid body and the
closed-form motion of a torque-free symmetric top."""
import numpy as np
from scipy.spatial.transform import Rotation
from test_large_rotations import ASYMMETRIC, lone_body_system, weightless

from skmoor.bodies.body import RigidBody
from skmoor.bodies.large_rotations import rate_matrix, zyx_angles
from skmoor.bodies.loads import BodyLoad
from skmoor.coupling.system import Ends, System
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.solvers.dynamics import integrate


def spin(inertia, omega0, dt, duration):
    """(t, R, omega) of a free weightless body spun at omega0 (rad/s) from q = 0, each
    state read while the integration is at it (the body's frame may be re-based later)."""
    body = RigidBody(1.0, [0.0, 0.0, 0.0], inertia, rotations="exact")
    system = lone_body_system(body, weightless(body))
    v0 = np.zeros(6)
    v0[3:] = omega0
    out = []
    for state in integrate(system, np.zeros(6), v0, dt, duration, tol=1e-10):
        q, qdot = system.q(state.x), system.q(state.v)
        out.append((state.t, system.body_rotation(state.x), rate_matrix(q[3:])[0] @ qdot[3:]))
    t, R, omega = (np.array(column) for column in zip(*out))
    return t, R, omega


def test_zyx_angles_invert_the_rotation_also_at_the_lock():
    for angles in ([0.3, -0.7, 2.5], [2.9, 0.2, -3.0], [0.4, np.pi / 2, 0.0],
                   [-1.1, -np.pi / 2, 0.0]):
        R = Rotation.from_euler("ZYX", np.array(angles)[::-1]).as_matrix()  # Rz Ry Rx
        assert np.allclose(zyx_angles(R), angles, atol=1e-12)


def test_free_spin_about_a_horizontal_axis_through_the_lock():
    """Spun about y (the smallest axis: stable) with a little wobble: the body x axis goes
    over the top twice in two turns. The angular momentum (inertial frame) stays to
    Newton's tolerance, the energy error falls as dt^2 (a wrong velocity map at the
    re-base breaks both at O(dt); without the re-base the step stops at 90 deg)."""
    omega0 = np.array([0.02, 1.0, 0.03])
    period = 2 * np.pi / np.linalg.norm(omega0)
    errors = []
    for steps in (40, 80):
        _, R, omega = spin(ASYMMETRIC, omega0, period / steps, 2 * period)
        spatial = R @ ASYMMETRIC @ R.transpose(0, 2, 1)
        momentum = np.einsum("nij,nj->ni", spatial, omega)
        energy = 0.5 * np.einsum("ni,ni->n", omega, momentum)
        pitch = np.arcsin(np.clip(-R[:, 2, 0], -1, 1))
        assert np.abs(pitch).max() > np.radians(88)  # it went through the lock
        assert np.cos(pitch).min() < 0.05
        errors.append((np.abs(energy / energy[0] - 1).max(),
                       np.linalg.norm(momentum - momentum[0], axis=1).max()
                       / np.linalg.norm(momentum[0])))
    (e1, h1), (e2, h2) = errors
    assert h1 < 1e-7 and h2 < 1e-7
    assert e2 < 2e-4
    assert 3.0 < e1 / e2 < 5.0


def test_torque_free_symmetric_top_through_the_lock_matches_its_closed_form():
    """Symmetric about body y, spun mostly about it (horizontal): R(t) = Rot(h, |H| t /
    I_perp) Rot(e_y, omega_y (I_perp - I_axis) / I_perp t); the body x axis sweeps past
    the vertical. Orientation error at second order in dt (a dropped gyroscopic term
    gives O(1))."""
    i_perp, i_axis = 2.0, 1.0
    inertia = np.diag([i_perp, i_axis, i_perp])
    omega0 = np.array([0.3, 2.0, 0.2])
    H = inertia @ omega0
    worst = []
    for dt in (0.04, 0.02):
        t, R, _ = spin(inertia, omega0, dt, 6.0)
        precession = Rotation.from_rotvec(np.outer(t * np.linalg.norm(H) / i_perp,
                                                   H / np.linalg.norm(H))).as_matrix()
        body_spin = Rotation.from_rotvec(np.outer(t * omega0[1] * (i_perp - i_axis) / i_perp,
                                                  [0.0, 1.0, 0.0])).as_matrix()
        expected = precession @ body_spin
        trace = np.einsum("nij,nij->n", expected, R)
        worst.append(np.arccos(np.clip((trace - 1) / 2, -1, 1)).max())
        assert np.abs(R[:, 2, 0]).max() > np.sin(np.radians(85))  # x axis near vertical
    assert worst[1] < 3e-3
    assert 3.5 < worst[0] / worst[1] < 4.5


def tethered_body():
    """An exact body on two lines, one from the origin to the body point (5, 0, 0) and
    one from (0, 0, 5) to (0, 0, 1) on the body, each with two elements."""
    lines = [Line.from_polyline([[20.0, 0.0, 0.0], [12.0, 0.0, 0.0], [5.0, 0.0, 0.0]], CABLE),
             Line.from_polyline([[0.0, 0.0, 9.0], [0.0, 0.0, 5.0], [0.0, 0.0, 1.0]], CABLE)]
    body = RigidBody(10.0, [0.0, 0.0, 0.0], np.diag([3.0, 2.0, 1.0]), rotations="exact",
                     g=1.0)
    return System(LineSet(lines), ends=Ends([("fixed",), ("fixed",)], [("body", 0)] * 2),
                  bodies=[body])


CABLE = LineType(EA=1e4, mass=1.0, diameter=0.05)


def test_rebase_keeps_the_pose_the_line_ends_and_the_loads():
    """A re-based state is the same body state: attitude, angular velocity, where the
    line ends sit and the generalized load (through E^T at the new angles: the moment
    itself unchanged). A missing end offset or an unturned end arm moves the ends."""
    system = tethered_body()
    x = np.zeros(system.n)
    x[system.nf:] = [0.1, -0.2, 0.05, 0.4, np.radians(75), -0.3]
    v = np.zeros(system.n)
    v[system.nf:] = [0.0, 0.1, 0.0, 0.3, -0.5, 0.2]
    x[: system.nf] = 0.01 * np.sin(np.arange(system.nf))
    R0, u0 = system.body_rotation(x), system.full_displacement(x)
    E0 = rate_matrix(x[-3:])[0]
    omega0 = E0 @ v[-3:]
    load0 = system.residual(x, v, tangent=False)[0]
    x1, v1 = system.rebase(x, v)
    assert np.allclose(x1[-3:], 0.0) and np.allclose(x1[: system.nf + 3], x[: system.nf + 3])
    assert np.allclose(system.body_rotation(x1), R0, atol=1e-14)
    assert np.allclose(v1[-3:], omega0)  # E(0) = I
    assert np.allclose(system.full_displacement(x1), u0, atol=1e-12)
    assert np.allclose(system.body_pose(x1)[0, 3:], x[-3:], atol=1e-12)
    load1 = system.residual(x1, v1, tangent=False)[0]
    assert np.allclose(load1[: system.nf + 3], load0[: system.nf + 3], atol=1e-9)
    # the moment about the reference point: M = E^-T Q
    assert np.allclose(load1[-3:], np.linalg.solve(E0.T, load0[-3:]), atol=1e-9)
    system.reset_frames()
    assert np.allclose(system.full_displacement(x), u0, atol=1e-14)


def test_a_body_with_a_user_body_load_term_is_not_rebased():
    """A user's BodyLoad reads q as it comes (not frame-aware): the re-base leaves the body
    alone (it stops at the lock with the error that says so; tests/bodies/test_rebased_body_terms.py
    has the frame-aware terms)."""
    system = tethered_body()
    x = np.zeros(system.n)
    x[-2] = np.radians(70)
    assert system.rebase(x, np.zeros(system.n)) is not None
    system.reset_frames()
    system.add_term(BodyLoad(lambda q, qdot, t: np.zeros(6)))
    assert system.rebase(x, np.zeros(system.n)) is None
