"""Band storage (skmoor.numerics.banded) against dense numpy, and the time loop's three matrix
layouts against each other on a line without a body."""
import numpy as np
import pytest
import scipy.sparse as sp

from skmoor.coupling.system import System
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.numerics.banded import Band, as_layout
from skmoor.sea.hydro import line_hydrodynamics
from skmoor.sea.seabed import Seabed, seabed_term
from skmoor.solvers import dynamics
from skmoor.solvers.dynamics import Scheme, integrate


def banded_matrix(n, kl, ku, seed=0):
    rng = np.random.default_rng(seed)
    A = np.triu(np.tril(rng.normal(size=(n, n)), ku), -kl)
    return A + 10.0 * np.eye(n)  # diagonally dominant: no pivoting trouble


@pytest.mark.parametrize("kl, ku", [(2, 2), (1, 3), (5, 5)])
def test_band_storage_arithmetic_and_solve_match_dense(kl, ku):
    """from_matrix / toarray round trip, sums, scalar products, A @ x and the LU solve
    equal numpy's dense results; entries outside the band are refused."""
    A, B = banded_matrix(30, kl, ku, 1), banded_matrix(30, kl, ku, 2)
    a, b = Band.from_matrix(sp.csr_matrix(A), kl, ku), Band.from_matrix(B, kl, ku)
    np.testing.assert_array_equal(a.toarray(), A)
    np.testing.assert_allclose((2.0 * a + b * np.float64(3.0)).toarray(), 2 * A + 3 * B)
    x = np.random.default_rng(3).normal(size=30)
    np.testing.assert_allclose(a @ x, A @ x, rtol=1e-13)
    np.testing.assert_allclose(a.factorize()(x), np.linalg.solve(A, x), rtol=1e-11)
    assert Band.from_matrix(np.zeros((4, 4)), 1, 1).factorize() is None  # singular
    with pytest.raises(ValueError, match="outside kl = 1"):
        Band.from_matrix(A, 1, 1)
    with pytest.raises(ValueError, match="layout"):
        as_layout(A, "banded")


def heaving_chain(n=24):
    """A chain from an anchor on the bed to a heaving fairlead, with drag, added mass,
    the sea bed and axial damping: every term of a line without a body."""
    chain = LineType(EA=1e9, mass=200.0, diameter=0.2, Cd_n=1.2, Cd_t=0.4, Ca_n=1.0,
                     BA=1e6)
    line = Line.from_polyline(np.linspace([-180.0, 0.0, -60.0], [0.0, 0.0, 0.0], n + 1),
                              chain)
    lines = LineSet([line], law="engineering")
    bed = Seabed(60.0)
    return System(lines, fairleads="prescribed",
                  motion=lambda t: np.array([[0.0, 0.0, 2.0 * np.sin(0.6 * t)]]),
                  terms=[seabed_term(lines, bed), line_hydrodynamics(lines)])


def test_layouts_give_the_same_motion(monkeypatch):
    """The banded, dense and sparse time loops integrate the same line to round-off (the
    band is what integrate picks for a line without a body)."""
    system = heaving_chain()
    assert system.bandwidth == 5 and dynamics.matrix_layout(system) == "band"
    finals = {}
    for layout in ("band", "dense", "sparse"):
        monkeypatch.setattr(dynamics, "matrix_layout", lambda _, layout=layout: layout)
        states = list(integrate(system, np.zeros(system.n), np.zeros(system.n), 0.05, 3.0,
                                scheme=Scheme.generalized_alpha(0.9)))
        finals[layout] = states[-1].x
    scale = np.abs(finals["dense"]).max()
    assert scale > 0.1  # the line moved
    for layout in ("band", "sparse"):
        assert np.abs(finals[layout] - finals["dense"]).max() < 1e-8 * scale
