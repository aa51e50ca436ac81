"""The exact body's terms against independent numbers: the momentum-form tangents and
the hydrostatic stiffness at a pose against central differences of their loads (also in
a re-based frame), and the body that carries its line ends' lumped masses against the
kinetic energy of the body plus those point masses moving with it."""
import numpy as np
from test_gimbal_lock import tethered_body

from skmoor.bodies.body import Hydrostatics, RigidBody, rotation_matrix
from skmoor.bodies.large_rotations import rate_matrix

INERTIA = np.array([[4.0, 0.3, -0.2], [0.3, 2.5, 0.1], [-0.2, 0.1, 1.5]])


def test_momentum_form_tangents_are_the_load_derivatives():
    """Exact chain-rule tangents (a dropped term in dR/dphi, a sign, a missing shift term
    show as O(1) relative differences)."""
    body = RigidBody(2.0, [0.3, -0.2, 0.5], INERTIA, reference_point=[0.0, 0.1, -0.2],
                     rotations="exact")
    rng = np.random.default_rng(1)
    q0, v0, load0 = 0.5 * rng.normal(size=6), rng.normal(size=6), rng.normal(size=6)
    q1, v1 = q0 + 0.05 * rng.normal(size=6), v0 + 0.1 * rng.normal(size=6)
    h, gamma, step = 0.05, 0.6, 1e-6
    for frame in (None, rotation_matrix([0.4, -1.1, 2.0])):
        def load(q, v):
            return body.step_inertia_load(q, v, q0, v0, load0, h, gamma, frame)

        d_rate, d_pose = body.step_inertia_tangents(q1, v1, q0, v0, load0, h, gamma, frame)
        fd_rate = np.column_stack([(load(q1, v1 + step * e) - load(q1, v1 - step * e))
                                   / (2 * step) for e in np.eye(6)])
        fd_pose = np.column_stack([(load(q1 + step * e, v1) - load(q1 - step * e, v1))
                                   / (2 * step) for e in np.eye(6)])
        assert np.abs(d_rate - fd_rate).max() < 1e-8 * np.abs(fd_rate).max()
        assert np.abs(d_pose - fd_pose).max() < 1e-8 * np.abs(fd_pose).max()


def central_differences(load, q, step=1e-6):
    """-dload/dq (6, 6) by central differences."""
    return np.column_stack([(load(q - step * e) - load(q + step * e)) / (2 * step)
                            for e in np.eye(6)])


def test_hydrostatic_stiffness_at_a_pose_is_the_restoring_load_derivative():
    """The waterplane at the pose (clipped hull) and the turning arms: a wrong sign of a
    waterplane moment or a missing dE/dphi term show as O(1) differences."""
    box = RigidBody.box(26.0, 10.0, 5.0, 1.2e5, 0.45, rotations="exact",
                        reference_point=[1.0, -0.5, 0.3])
    submerged = RigidBody(1e3, [0.0, 0.1, -5.2], np.diag([3.0, 2.0, 1.0]),
                          reference_point=[0.0, 0.0, -5.0], rotations="exact",
                          hydrostatics=Hydrostatics.submerged(2.0, [0.2, 0.0, -4.9],
                                                              [0.0, 0.0, -5.0]))
    poses = (np.zeros(6), np.array([0.3, -0.2, -0.4, 0.35, -0.1, 0.8]),
             np.array([0.1, 0.2, 0.3, 1.2, 0.5, -2.0]))
    for body in (box, submerged):
        for frame in (None, rotation_matrix([0.3, 0.9, -0.4])):
            for q in poses:
                K = central_differences(lambda q: body.restoring_load(q, frame), q)
                assert np.abs(body.restoring_stiffness(q, frame) - K).max() \
                    < 1e-8 * np.abs(K).max()


def test_carried_line_end_masses_give_the_kinetic_energy_of_the_ends():
    """The carrier's 1/2 qdot^T M(q) qdot is the body's plus 1/2 m_e |v_e|^2 of each line
    end's lumped mass m_e at its body point (wrong parallel axes show at O(1))."""
    system = tethered_body()
    body = system.bodies[0]
    carrier, M0 = system.carrying_body(0)
    ends = body.reference_point + system.dofs.r_local0[0]
    masses = system.end_masses[system.dofs.body_rows[0]]
    assert np.all(masses > 0)
    assert np.allclose(M0, system.M.toarray()[system.nf:, system.nf:])  # what M holds
    q = np.array([0.2, -0.1, 0.3, 0.7, -0.4, 1.2])
    qdot = np.array([0.3, 0.1, -0.2, 0.5, 0.9, -0.6])
    R = rotation_matrix(q[3:])
    omega = rate_matrix(q[3:])[0] @ qdot[3:]

    def energy_of(mass, points):
        v = qdot[:3] + np.cross(omega, (points - body.reference_point) @ R.T)
        return 0.5 * np.sum(mass * np.sum(v * v, axis=-1))

    arm = R @ (body.center_of_mass - body.reference_point)
    v_G = qdot[:3] + np.cross(omega, arm)
    expected = (0.5 * body.mass * v_G @ v_G + 0.5 * omega @ R @ body.inertia @ R.T @ omega
                + energy_of(masses, ends))
    mass_matrix = carrier.inertia_tangents(q, qdot, np.zeros(6))[0]  # M(q)
    assert np.isclose(0.5 * qdot @ mass_matrix @ qdot, expected, rtol=1e-12)
