"""Natural frequencies of a taut string and of a shallow sagging cable (skmoor.solvers.modes on the
System's tangent and mass) against the taut-string formula and Irvine's cable theory."""
import numpy as np
import pytest
from scipy.optimize import brentq

from skmoor.coupling.system import System
from skmoor.lines.catenary import solve_catenary
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.solvers.modes import eigenmodes


def modes_about_reference(line, k):
    """System with fixed ends, tangent at u = 0, lumped mass: (system, modes, shapes) with
    shapes (k, nnodes, 3) the nodal displacements of each mode."""
    system = System(LineSet([line]), fairleads="fixed")
    _, K, _ = system.residual(np.zeros(system.n))
    modes = eigenmodes(K, system.M, k=k)
    nodal = system.lines.nodal_dofs
    shapes = np.array([system.full_displacement(phi)[nodal] for phi in modes.shapes.T])
    return system, modes, shapes


def test_taut_string_frequencies():
    """Weightless string, tension T: omega_n = n pi / L sqrt(T / m), n = 1, 2, 3, each twice
    (two transverse planes), within 0.5 % at 50 elements."""
    T, m, L = 1e5, 10.0, 100.0
    string = LineType(EA=1e9, mass=m, diameter=0.05, weight=0.0)
    direction = np.array([1.0, 2.0, 2.0]) / 3.0  # not along an axis
    points = np.linspace([0.0, 0.0, -50.0], [0.0, 0.0, -50.0] + L * direction, 51)
    _, modes, shapes = modes_about_reference(Line.from_polyline(points, string, tension=T), 8)
    expected = np.repeat(np.arange(1, 4) * np.pi / L * np.sqrt(T / m), 2)
    np.testing.assert_allclose(modes.omega[:6], expected, rtol=5e-3)
    # transverse: no motion along the string
    assert np.abs(shapes[:6] @ direction).max() < 1e-8 * np.abs(shapes[:6]).max()


@pytest.fixture(scope="module")
def sagging():
    """A horizontal 200 m span of rope with sag / span 1/50 (Irvine's lambda^2 ~ 20)."""
    rope = LineType(EA=4e8, mass=50.0, diameter=0.1)
    span = 200.0
    cable = solve_catenary([0.0, 0.0, 0.0], [span, 0.0, 0.0], rope.weight, rope.EA,
                           sag_ratio=1 / 50)
    _system, modes, shapes = modes_about_reference(Line.from_catenary(cable, rope, 40), 6)
    return rope, span, cable, modes, shapes


def irvine_lambda2(cable, span):
    """Irvine's lambda^2 = (8 d / l)^2 l / (H L_e / EA), L_e = l (1 + 8 (d / l)^2)."""
    d = cable.sag()
    return (8 * d / span) ** 2 * span / (cable.H * span * (1 + 8 * (d / span) ** 2) / cable.EA)


def test_sagging_cable_out_of_plane_and_antisymmetric_modes(sagging):
    """Irvine: first out-of-plane mode pi / l sqrt(H / m), first antisymmetric in-plane
    mode 2 pi / l sqrt(H / m), within 1 %."""
    rope, span, cable, modes, shapes = sagging
    base = np.pi / span * np.sqrt(cable.H / rope.mass)
    size = np.abs(shapes).max(axis=(1, 2))
    out_of_plane = np.abs(shapes[:, :, 1]).max(axis=1) > 0.99 * size
    assert modes.omega[out_of_plane][0] == pytest.approx(base, rel=1e-2)

    vertical = shapes[:, :, 2]
    antisymmetric = ~out_of_plane & np.all(np.isclose(vertical, -vertical[:, ::-1],
                                                      atol=1e-6 * np.abs(vertical).max()), axis=1)
    assert modes.omega[antisymmetric][0] == pytest.approx(2 * base, rel=1e-2)


def test_sagging_cable_symmetric_in_plane_mode(sagging):
    """Irvine: first symmetric in-plane mode from tan(w/2) = w/2 - 4/lambda^2 (w/2)^3,
    w = omega l / sqrt(H / m), within 1 %."""
    rope, span, cable, modes, shapes = sagging
    lam2 = irvine_lambda2(cable, span)
    assert 10 < lam2 < 4 * np.pi**2  # below the crossover: the mode is the second one
    half = brentq(lambda x: np.tan(x) - x + 4 / lam2 * x**3, np.pi / 2 + 1e-6, 3 * np.pi / 2 - 1e-6)
    expected = 2 * half / span * np.sqrt(cable.H / rope.mass)

    vertical = shapes[:, :, 2]
    symmetric = np.all(np.isclose(vertical, vertical[:, ::-1],
                                  atol=1e-6 * np.abs(vertical).max()), axis=1)
    symmetric &= np.abs(vertical).max(axis=1) > 0.5 * np.abs(shapes).max(axis=(1, 2))
    assert modes.omega[symmetric][0] == pytest.approx(expected, rel=1e-2)
