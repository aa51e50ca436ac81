"""The bodies' built-in terms (skmoor.bodies.restoring) as statics and the Python step
evaluate them: a floating box's restoring against its closed-form hydrostatics (small
rotations: the stiffness; exact: the wall-sided righting moment), the tangents against
central differences of the residual, and the applied load's generalized moment against
the power of the force and moment (omega from dR/dt R^T)."""
import numpy as np
from scipy.spatial.transform import Rotation
from test_large_rotations import angular_velocity, lone_body_system

from skmoor.bodies.body import RigidBody
from skmoor.bodies.restoring import AppliedLoad, BodyRestoring

RHO, G = 1025.0, 9.81
L, W, H, DRAFT = 26.0, 10.0, 5.0, 2.0
DAMPING = np.diag([1e4, 2e4, 3e4, 4e5, 5e5, 6e5]) + np.diag([7e3] * 5, 1)  # not symmetric


def floating_box(rotations="small", mass=None, **kwargs):
    """The uniform box floating at its draft (mass: the displaced water unless given),
    reference point at the centre of its waterplane (the origin)."""
    mass = RHO * L * W * DRAFT if mass is None else mass
    return RigidBody.box(L, W, H, mass, DRAFT, reference_point=[0.0, 0.0, 0.0],
                         rotations=rotations, linear_damping=DAMPING, rho=RHO, g=G, **kwargs)


def box_stiffness(mass):
    """Closed-form hydrostatic + gravity stiffness of the box about its waterplane
    centre: rho g A in heave, rho g I_wp + rho g V z_B - m g z_G in roll and pitch."""
    volume = L * W * DRAFT
    z_b, z_g = -DRAFT / 2, H / 2 - DRAFT
    K = np.zeros((6, 6))
    K[2, 2] = RHO * G * L * W
    K[3, 3] = RHO * G * (L * W**3 / 12 + volume * z_b) - mass * G * z_g
    K[4, 4] = RHO * G * (W * L**3 / 12 + volume * z_b) - mass * G * z_g
    return K


def roll_moment(phi):
    """Righting moment (N m, about x, at the waterplane centre) of the floating wall-sided
    box heeled by phi (deck edge dry, bottom wetted): -rho g V sin(phi) (GM + BM tan^2/2)."""
    volume = L * W * DRAFT
    bm = W**2 / (12 * DRAFT)
    gm = DRAFT / 2 + bm - (H / 2)  # KB + BM - KG
    return -RHO * G * volume * np.sin(phi) * (gm + 0.5 * bm * np.tan(phi) ** 2)


def evaluate(term, q, qdot, t=0.0, tangents=True):
    """(R, K, C) that ``term`` adds to arbitrary start arrays (the term must add, not
    overwrite), minus those arrays."""
    rng = np.random.default_rng(7)
    R0, K0, C0 = rng.normal(size=6), rng.normal(size=(6, 6)), rng.normal(size=(6, 6))
    R, K, C = R0.copy(), K0.copy(), C0.copy()
    if tangents:
        term.add_to(q, qdot, t, R, K, C)
        return R - R0, K - K0, C - C0
    term.add_to(q, qdot, t, R)
    return R - R0, None, None


def residual_derivatives(term, q, qdot, step=1e-6):
    """dR/dq and dR/dqdot of ``term`` by central differences."""
    def R(a, b):
        return evaluate(term, a, b, tangents=False)[0]

    dq = np.column_stack([(R(q + step * e, qdot) - R(q - step * e, qdot)) / (2 * step)
                          for e in np.eye(6)])
    dv = np.column_stack([(R(q, qdot + step * e) - R(q, qdot - step * e)) / (2 * step)
                          for e in np.eye(6)])
    return dq, dv


def test_small_rotation_restoring_is_the_box_stiffness_plus_damping():
    """K q + D qdot with K the box's closed-form stiffness (a wrong sign, a transposed
    damping or an overwritten instead of added array show at O(1))."""
    mass = 0.9 * RHO * L * W * DRAFT  # lighter than its displacement: a net lift F0
    body = floating_box(mass=mass)
    term = BodyRestoring(0, body)
    assert np.allclose(term.stiffness, box_stiffness(mass), rtol=1e-12, atol=1e-6)
    q = np.array([0.3, -0.2, 0.1, 0.02, -0.03, 0.05])
    qdot = np.array([0.5, 0.4, -0.3, 0.02, 0.01, -0.04])
    R, K, C = evaluate(term, q, qdot)
    assert np.allclose(R, box_stiffness(mass) @ q + DAMPING @ qdot, rtol=1e-12, atol=1e-6)
    assert np.allclose(K, box_stiffness(mass), rtol=1e-12, atol=1e-6)
    assert np.allclose(C, DAMPING, rtol=0, atol=1e-9)
    R_only = evaluate(term, q, qdot, tangents=False)[0]
    assert np.allclose(R_only, R, rtol=0, atol=1e-9)
    dq, dv = residual_derivatives(term, q, qdot)
    assert np.allclose(dq, K, rtol=1e-6, atol=1e-3) and np.allclose(dv, C, atol=1e-3)
    assert term.lowered() == "body restoring"  # the compiled step has it


def test_small_rotation_stiffness_is_the_linearized_exact_restoring_load():
    """About a reference point off the box's vertical axis (and a body lighter than its
    displacement, so that weight and buoyancy moments differ) the default stiffness is
    the generalized one: -dQ/dq at q = 0 of the exact load conjugate to the angles, by
    central differences (the moment-derivative form has yaw couplings (m - rho V) g x)."""
    mass, ref = 0.9 * RHO * L * W * DRAFT, [3.0, -1.0, 0.5]
    small = RigidBody.box(L, W, H, mass, DRAFT, reference_point=ref, rho=RHO, g=G)
    exact = RigidBody.box(L, W, H, mass, DRAFT, reference_point=ref, rho=RHO, g=G,
                          rotations="exact")
    step = 1e-6
    linearized = np.column_stack([(exact.restoring_load(-step * e)
                                   - exact.restoring_load(step * e)) / (2 * step)
                                  for e in np.eye(6)])
    stiffness = BodyRestoring(0, small).stiffness
    assert np.abs(stiffness - linearized).max() < 1e-9 * np.abs(linearized).max()
    assert np.abs(linearized[3:, 5]).max() < 1e-9 * np.abs(linearized).max()


def test_given_stiffness_and_static_load_are_the_ones_used():
    """A stiffness handed in replaces the body's (a System's K_bodies); the static load
    handed in is F0 of the exact body: R = -(Q(q) - F0) + D qdot."""
    body = floating_box()
    stiffness = np.diag([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    small = BodyRestoring(0, body, stiffness=stiffness)
    q, qdot = np.array([1.0, -1.0, 2.0, 0.5, -0.5, 0.25]), np.zeros(6)
    assert np.allclose(evaluate(small, q, qdot)[0], stiffness @ q, atol=1e-9)
    exact = BodyRestoring(0, floating_box("exact"), static_force=np.arange(1.0, 7.0))
    R = evaluate(exact, np.zeros(6), np.zeros(6))[0]  # Q(0) = 0: floating, G over B
    assert np.allclose(R, np.arange(1.0, 7.0), rtol=1e-9, atol=1e-3)


def test_exact_restoring_of_a_heaved_and_heeled_box_is_the_wall_sided_closed_form():
    """Heave z: rho g A z; heel phi: the wall-sided righting moment (deck edge dry, bottom
    wet: phi < atan(2 draft / W)), the static load F0 of the reference pose taken off
    (a body lighter than its displacement); the tangents are the residual's derivatives."""
    mass = 0.95 * RHO * L * W * DRAFT
    body = floating_box("exact", mass=mass)
    term = BodyRestoring(0, body)
    assert term.lowered() is None  # the exact hydrostatics run in Python
    qdot = np.array([0.2, -0.1, 0.3, 0.01, 0.02, -0.03])
    R = evaluate(term, np.array([0.0, 0.0, -0.3, 0.0, 0.0, 0.0]), qdot)[0]
    assert np.allclose(R, [0.0, 0.0, -RHO * G * L * W * 0.3, 0, 0, 0] + DAMPING @ qdot,
                       rtol=1e-10, atol=1e-3)
    phi = 0.3
    q = np.array([0.0, 0.0, 0.0, phi, 0.0, 0.0])
    R, K, C = evaluate(term, q, qdot)
    # the weight's moment about the waterplane centre (G at z_g, arm -z_g sin phi in y)
    # exceeds the one of the displaced water's weight in roll_moment by (m - rho V) g
    z_g = H / 2 - DRAFT
    extra_weight_moment = (mass - RHO * L * W * DRAFT) * G * z_g * np.sin(phi)
    expected = np.zeros(6)
    expected[3] = -(roll_moment(phi) + extra_weight_moment)
    assert np.allclose(R, expected + DAMPING @ qdot, rtol=1e-9, atol=1e-3)
    assert np.allclose(C, DAMPING, atol=1e-9)
    dq, dv = residual_derivatives(term, q + [0.1, -0.2, 0.05, 0.0, 0.02, 0.3], qdot)
    K = evaluate(term, q + [0.1, -0.2, 0.05, 0.0, 0.02, 0.3], qdot)[1]
    assert np.abs(dq - K).max() < 1e-6 * np.abs(K).max()
    assert np.allclose(dv, DAMPING, atol=1e-3)


def test_exact_restoring_counts_the_angles_from_the_system_frame():
    """A body re-based to heel phi1 and turned by phi2 more is heeled by phi1 + phi2:
    its righting moment is the wall-sided one at the sum (the frame ignored: at phi2), its
    tangent the derivative of that residual."""
    system = lone_body_system(floating_box("exact"))
    term = next(t for t in system.built_in_terms if isinstance(t, BodyRestoring))
    phi1, phi2 = 0.15, 0.1
    system.use_frames([Rotation.from_euler("x", phi1).as_matrix()])
    q = np.array([0.0, 0.0, 0.0, phi2, 0.0, 0.0])
    R, K, _ = evaluate(term, q, np.zeros(6))
    assert np.allclose(R, [0, 0, 0, -roll_moment(phi1 + phi2), 0, 0], rtol=1e-9, atol=1e-3)
    q = q + [0.1, -0.2, 0.05, 0.0, 0.02, 0.3]  # also the tangent, in the same frame
    K = evaluate(term, q, np.zeros(6))[1]
    assert np.abs(residual_derivatives(term, q, np.zeros(6))[0] - K).max() \
        < 1e-6 * np.abs(K).max()


def zyx_rates_matrix(angles):
    """E with omega = E d(angles)/dt for R = Rz Ry Rx, written out: the x rate turns about
    Rz Ry e_x, the y rate about Rz e_y, the z rate about e_z."""
    rx, ry, rz = angles
    Rz = Rotation.from_euler("z", rz).as_matrix()
    Ry = Rotation.from_euler("y", ry).as_matrix()
    return np.column_stack([Rz @ Ry @ [1.0, 0, 0], Rz @ [0, 1.0, 0], [0, 0, 1.0]])


def test_applied_load_on_a_small_body_is_taken_off_the_residual_as_given():
    """R gets -f(t, q, qdot), f seeing the body's own q (angles not wrapped: 4 rad) and
    qdot; no tangent (the load is explicit); no load, nothing."""
    seen = []

    def load(t, q, qdot):
        seen.append((t, q.copy(), qdot.copy()))
        return np.array([t, 2 * q[0], 3 * qdot[1], q[3], qdot[5], -1.0])

    system = lone_body_system(floating_box(), load)
    term = next(t for t in system.built_in_terms if isinstance(t, AppliedLoad))
    assert term.lowered() is None  # of the state, in NumPy (JAX cannot trace it): Python
    q = np.array([0.1, 0.2, 0.3, 4.0, -0.5, 0.6])
    qdot = np.array([1.0, -2.0, 0.5, 0.1, 0.2, 0.3])
    R, K, C = evaluate(term, q, qdot, t=2.5)
    assert np.allclose(R, -np.array([2.5, 0.2, -6.0, 4.0, 0.3, -1.0]), rtol=0, atol=1e-12)
    assert not K.any() and not C.any()
    t, q_seen, qdot_seen = seen[-1]
    assert t == 2.5 and np.array_equal(q_seen, q) and np.array_equal(qdot_seen, qdot)
    load.time_only = True
    assert term.lowered() == "time load"
    system.body_loads[0] = None
    assert term.lowered() == "time load"
    assert not evaluate(term, q, qdot)[0].any()


def test_applied_moment_on_an_exact_body_is_conjugate_to_its_angles():
    """[F, E^T M]: F . v + M . omega = value . qdot for every qdot (omega from dR/dt R^T
    by central differences), E also written out from the rotation axes."""
    force, moment = np.array([1e3, -2e3, 5e2]), np.array([3e4, 1e4, -2e4])
    system = lone_body_system(floating_box("exact"),
                              lambda t, q, qdot: np.r_[force, moment])
    term = next(t for t in system.built_in_terms if isinstance(t, AppliedLoad))
    q = np.array([0.1, 0.2, 0.3, 0.4, -0.7, 1.1])
    rng = np.random.default_rng(3)
    value = -evaluate(term, q, np.zeros(6))[0]
    assert np.allclose(value[:3], force, rtol=1e-12)
    assert np.allclose(value[3:], zyx_rates_matrix(q[3:]).T @ moment, rtol=1e-12)
    for qdot in rng.normal(size=(3, 6)):
        power = force @ qdot[:3] + moment @ angular_velocity(q, qdot)
        assert np.isclose(value @ qdot, power, rtol=1e-7)


def test_applied_load_on_a_rebased_body_sees_the_global_pose_and_rates():
    """A re-based body's load gets the angles of its attitude from the global frame
    (R = Rz Ry Rx(q) @ frame) and the angle rates of the same angular velocity; its
    moment is then taken back onto the body's own angles (E^T M at q)."""
    seen = []
    moment = np.array([1e4, -3e4, 2e4])

    def load(t, q, qdot):
        seen.append((t, q.copy(), qdot.copy()))
        return np.r_[0.0, 0.0, 0.0, moment]

    system = lone_body_system(floating_box("exact"), load)
    term = next(t for t in system.built_in_terms if isinstance(t, AppliedLoad))
    frame = Rotation.from_euler("ZYX", [0.5, 1.2, -0.4]).as_matrix()
    system.use_frames([frame])
    q = np.array([0.3, -0.1, 0.2, 0.2, 0.1, -0.3])
    qdot = np.array([0.1, 0.2, 0.3, 0.05, -0.04, 0.02])
    value = -evaluate(term, q, qdot, t=1.5)[0]
    t, q_global, qdot_global = seen[-1]
    assert t == 1.5
    assert np.allclose(q_global[:3], q[:3]) and np.allclose(qdot_global[:3], qdot[:3])
    attitude = Rotation.from_euler("ZYX", q[3:][::-1]).as_matrix() @ frame
    assert np.allclose(Rotation.from_euler("ZYX", q_global[3:][::-1]).as_matrix(), attitude,
                       atol=1e-12)
    omega = zyx_rates_matrix(q[3:]) @ qdot[3:]
    assert np.allclose(zyx_rates_matrix(q_global[3:]) @ qdot_global[3:], omega, atol=1e-12)
    assert np.allclose(value[3:], zyx_rates_matrix(q[3:]).T @ moment, rtol=1e-12)
