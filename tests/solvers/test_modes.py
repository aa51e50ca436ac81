"""Modes of large pencils: the shift-invert subspace iteration against closed forms, with
the repeated eigenvalues of identical platforms (a farm) and distinct ones of one chain."""
import numpy as np
import pytest
import scipy.sparse as sp

from skmoor.solvers.modes import eigenmodes, subspace_modes

STIFFNESS, MASS = 1e5, 100.0  # N/m per spring, kg per node


def chain(nodes):
    """A chain of ``nodes`` masses between two walls: K = k tridiag(-1, 2, -1), M = m I."""
    ones = np.ones(nodes)
    K = sp.diags([-ones[1:], 2 * ones, -ones[1:]], [-1, 0, 1]) * STIFFNESS
    return K.tocsc(), (sp.identity(nodes) * MASS).tocsc()


def chain_omega(nodes, j):
    """omega_j (rad/s) of the chain: omega^2 = k/m (2 - 2 cos(j pi / (nodes + 1)))."""
    return np.sqrt(STIFFNESS / MASS * (2 - 2 * np.cos(j * np.pi / (nodes + 1))))


def test_identical_platforms_share_their_lowest_mode():
    """64 identical chains of 450 nodes (28,800 unknowns, past the dense limit): the 12
    lowest modes all have the chain's first frequency, mass-normalized (a 64-fold
    eigenvalue, on which ARPACK's shift-invert Lanczos restarts for tens of seconds)."""
    K1, M1 = chain(450)
    K, M = sp.block_diag([K1] * 64).tocsc(), sp.block_diag([M1] * 64).tocsc()
    modes = eigenmodes(K, M, k=12)
    assert np.allclose(modes.omega, chain_omega(450, 1), rtol=1e-9)
    assert np.allclose(modes.shapes.T @ (M @ modes.shapes), np.eye(12), atol=1e-8)


def test_nearly_identical_platforms_more_than_the_block():
    """300 chains whose stiffness differs by 1e-8 from one to the next (a farm's lines,
    their static states a little apart): 300 first modes within 3e-6 of each other, more
    than the block of 20 can resolve, so each Ritz residual stops at ~1e-6. The frequencies
    are still returned (not left to ARPACK, which takes minutes on such a cluster): the
    12 lowest of the closed form to within the cluster's spread, mass-normalized."""
    nodes, chains = 60, 300
    K1, M1 = chain(nodes)
    factors = 1.0 + 1e-8 * np.arange(chains)
    K = sp.block_diag([K1 * f for f in factors]).tocsc()
    M = sp.block_diag([M1] * chains).tocsc()
    found = subspace_modes(K, M, 12)
    assert found is not None
    omega = np.sqrt(found[0])
    exact = chain_omega(nodes, 1) * np.sqrt(factors[:12])
    spread = chain_omega(nodes, 1) * (np.sqrt(factors[-1]) - 1)
    assert np.all(np.abs(omega - exact) <= spread)
    assert np.allclose(found[1].T @ (M @ found[1]), np.eye(12), atol=1e-8)
    second = chain_omega(nodes, 2)  # the next distinct mode is far: none of it leaks in
    assert np.all(omega < chain_omega(nodes, 1) + 0.01 * (second - chain_omega(nodes, 1)))


def test_distinct_modes_of_one_long_chain():
    K, M = chain(2500)
    modes = eigenmodes(K, M, k=6)
    assert modes.omega == pytest.approx(chain_omega(2500, np.arange(1, 7)), rel=1e-9)
    phi = modes.shapes[:, 0]  # the first mode: a half sine
    sine = np.sin(np.pi * np.arange(1, 2501) / 2501)
    assert abs(phi @ sine) / (np.linalg.norm(phi) * np.linalg.norm(sine)) == pytest.approx(1, abs=1e-9)


def test_a_singular_stiffness_is_left_to_arpack():
    K, M = chain(50)
    K = K.tolil()
    K[0, :] = 0.0
    K[:, 0] = 0.0
    assert subspace_modes(K.tocsc(), M, 3) is None
