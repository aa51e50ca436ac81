"""The coupling block: exact rigid-body kinematics and a consistent coupled tangent."""
import numpy as np
import pytest

import skmoor
from skmoor.bodies.body import rotation_matrix


@pytest.fixture(scope="module")
def model():
    return skmoor.build(skmoor.paper_case())


def rotated_state(model, angles=(0.2, -0.15, 0.25)):
    """A reduced state with the body rotated by ~0.2 rad and the lines perturbed."""
    system = model.system
    x = np.zeros(system.n)
    rng = np.random.default_rng(3)
    x[: system.nf] = 0.05 * rng.standard_normal(system.nf)
    x[system.nf:] = [0.3, -0.2, 0.1, *angles]
    return x


def test_rigid_rotation_moves_fairleads_where_geometry_says(model):
    """Fairlead = body position + R r_local, checked against an independent rotation."""
    system = model.system
    x = rotated_state(model)
    q = x[system.nf:]
    rx, ry, rz = q[3:]
    c, s = np.cos, np.sin
    Rx = np.array([[1, 0, 0], [0, c(rx), -s(rx)], [0, s(rx), c(rx)]])
    Ry = np.array([[c(ry), 0, s(ry)], [0, 1, 0], [-s(ry), 0, c(ry)]])
    Rz = np.array([[c(rz), -s(rz), 0], [s(rz), c(rz), 0], [0, 0, 1]])
    R = Rz @ Ry @ Rx
    np.testing.assert_allclose(rotation_matrix(q[3:]), R, atol=1e-14)
    center = model.body.reference_point
    fair = model.lines.points[model.lines.fairlead_nodes]
    expected = center + q[:3] + (fair - center) @ R.T
    u = system.full_displacement(x)
    moved = fair + u[model.lines.nodal_dofs[model.lines.fairlead_nodes]]
    np.testing.assert_allclose(moved, expected, atol=1e-12)
    # distances between fairleads are kept (a rigid motion)
    d0 = np.linalg.norm(fair[:, None] - fair[None], axis=-1)
    d1 = np.linalg.norm(moved[:, None] - moved[None], axis=-1)
    np.testing.assert_allclose(d1, d0, atol=1e-10)


@pytest.mark.parametrize("law", ["paper", "engineering"])
def test_coupled_tangent_is_derivative_of_residual_at_rotated_state(law):
    """Central differences of the reduced residual match the reduced tangent."""
    model = skmoor.build(skmoor.paper_case(mooring__strain_law=law))
    system = model.system
    x = rotated_state(model)
    _, K, _ = system.residual(x)
    K = K.toarray()
    rng = np.random.default_rng(7)
    cols = list(rng.choice(system.nf, 6, replace=False)) + list(range(system.nf, system.n))
    for j in cols:
        h = 1e-6
        e = np.zeros(system.n)
        e[j] = h
        fd = (system.residual(x + e, tangent=False)[0]
              - system.residual(x - e, tangent=False)[0]) / (2 * h)
        scale = np.abs(K[:, j]).max()
        assert np.abs(fd - K[:, j]).max() < 1e-5 * scale, f"column {j}"


def test_reference_state_is_equilibrium_of_paper_case(model):
    """With the draft of Eq. 1 and the lines on their catenaries, the reduced residual is ~0."""
    R, _, _ = model.system.residual(np.zeros(model.system.n))
    weight = model.body.mass * model.body.g
    assert np.abs(R).max() < 1e-9 * weight


def test_draft_matches_paper(model):
    """Paper: h_s = 0.896 m (the exact catenary: 0.8975 m)."""
    assert model.draft == pytest.approx(0.896, rel=5e-3)
    assert model.draft == pytest.approx(0.8975, abs=5e-4)


def test_static_solve_from_displaced_body_finds_same_equilibrium(model):
    """Newton from a body displaced by 1 m and 0.05 rad returns to the draft of Eq. 1."""
    system = model.system
    x0 = np.zeros(system.n)
    x0[system.nf:] = [1.0, -0.5, 0.3, 0.05, -0.05, 0.05]
    sol = skmoor.solve_static(system, x0)
    np.testing.assert_allclose(sol.x[system.nf:], 0.0, atol=1e-6)
