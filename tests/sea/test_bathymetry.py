"""A sea bed z_b(x, y) (skmoor.sea.seabed.Bathymetry): its bilinear heights and normals,
contact along the local normal against the analytic equilibrium on an inclined plane, and
the same kernel numbers as the plane bed of the same slope."""
import numpy as np
import pytest
from test_seabed import line_along_slope

from skmoor.lines.line import Line, LineSet, LineType
from skmoor.sea.seabed import Bathymetry, Seabed, seabed_term

CHAIN = LineType(EA=6e8, mass=150.0, diameter=0.15)  # w = 1294 N/m
DEPTH = 100.0


def tilted(slope_deg, x=(-200.0, 0.0, 300.0), y=(-100.0, 50.0, 100.0)):
    """A Bathymetry of the plane z = -DEPTH + tan(slope) y on a coarse grid (bilinear is
    exact on a plane), and the plane Seabed rising the same way (towards +y)."""
    _, Y = np.meshgrid(x, y, indexing="ij")
    heights = -DEPTH + np.tan(np.radians(slope_deg)) * Y
    return Bathymetry(x, y, heights), Seabed(DEPTH, slope_deg=slope_deg, slope_heading_deg=90.0)


def test_heights_slopes_and_normals():
    """Bilinear heights between the grid points (the cell's mean at its centre), held
    beyond the grid; the normal of the patch, upward, unit, flat beyond the grid."""
    bathymetry = Bathymetry([0.0, 10.0], [0.0, 20.0], [[-10.0, -12.0], [-14.0, -20.0]])
    assert bathymetry.height(np.array([5.0, 10.0])) == pytest.approx(-14.0)
    assert bathymetry.height(np.array([-5.0, 0.0])) == pytest.approx(-10.0)
    slopes = bathymetry.slopes(np.array([5.0, 10.0]))
    np.testing.assert_allclose(slopes, [(-4.0 - 8.0) / 2 / 10.0, (-2.0 - 6.0) / 2 / 20.0])
    n = bathymetry.normal(np.array([5.0, 10.0]))
    np.testing.assert_allclose(n, np.array([-slopes[0], -slopes[1], 1.0]) /
                               np.linalg.norm([slopes[0], slopes[1], 1.0]))
    np.testing.assert_allclose(bathymetry.normal(np.array([20.0, 30.0])), [0.0, 0.0, 1.0])
    assert bathymetry.mean_height == pytest.approx(-14.0)


def test_bad_grids_are_refused():
    for args, reason in ((([0.0, 0.0], [0.0], [[-1.0], [-1.0]]), "increase strictly"),
                         (([0.0, 1.0], [0.0], [[-1.0]]), "shape"),
                         (([0.0], [0.0], [[np.nan]]), "finite"),
                         (([0.0], [0.0], [[2.0]]), "below the still water line")):
        with pytest.raises(ValueError, match=reason):
            Bathymetry(*args, source="bed.txt")
    with pytest.raises(ValueError, match="slope or a bathymetry"):
        Seabed(DEPTH, slope_deg=5.0, bathymetry=tilted(5.0)[0])


def test_tilted_bathymetry_is_the_sloped_plane():
    """A tilted Bathymetry and the plane Seabed of the same slope give the same residual
    and tangents (to round-off) at a line crossing the bed: same normal, same offset."""
    bathymetry, _ = tilted(12.0)
    points = np.linspace([-150.0, -60.0, -DEPTH - 20.0], [250.0, 80.0, -DEPTH + 30.0], 21)
    lines = LineSet([Line.from_polyline(points, CHAIN)], law="engineering")
    rng = np.random.default_rng(3)
    u, v = rng.normal(scale=0.5, size=lines.ndofs), rng.normal(scale=0.1, size=lines.ndofs)
    on_grid = seabed_term(lines, Seabed(DEPTH, bathymetry=bathymetry, mu_axial=0.3,
                                        mu_lateral=0.6))
    flat = seabed_term(lines, Seabed(DEPTH, slope_deg=12.0, slope_heading_deg=90.0,
                                     mu_axial=0.3, mu_lateral=0.6))
    on_grid.bind(type("S", (), {"lines": lines})())
    flat.bind(type("S", (), {"lines": lines})())
    for a, b in zip(on_grid.evaluate(u, v, layout="dense"), flat.evaluate(u, v, layout="dense")):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-9 * np.max(np.abs(b)))
    assert np.any(on_grid.evaluate(u, v)[0])  # the line does touch the bed


def test_line_across_a_bathymetry_slope_is_an_in_plane_catenary():
    """A line laid along a contour of a frictionless 20 deg bathymetry slope, both ends
    held on the bed: the bed carries w cos(slope) per length along its normal (the nodes'
    penetration w cos(slope) / k), the downslope part w sin(slope) makes an in-plane
    catenary whose H the FE solve matches to 0.2 %. A vertical-only contact (MoorDyn's)
    would carry all of w and leave H at the line's elastic pretension; a normal of the
    wrong sign would push the line into the bed."""
    alpha = np.radians(20.0)
    bed = Seabed(DEPTH, bathymetry=tilted(20.0)[0])
    normal = np.array([0.0, -np.sin(alpha), np.cos(alpha)])
    position, rest, (fairlead, anchor), planar, _, _ = line_along_slope(bed, normal)
    assert bed.penetration(position[1:-1]) == pytest.approx(rest, rel=1e-6)
    assert -fairlead[0][0] == pytest.approx(planar.H, rel=2e-3)
    assert anchor[0][0] == pytest.approx(planar.H, rel=2e-3)


def test_the_compiled_kernel_takes_the_planes_under_the_displaced_nodes():
    """The bed kernel as the compiled time step calls it (its C function on the packed
    buffers, SeabedKernel.step_kernel) gives the Python kernel's residual and element
    blocks on a ridged bathymetry with friction, at a state whose nodes have moved 3 m
    along x across the ridge: the bed's plane under each displaced node (planes under the
    reference nodes would differ by the ridge's slope change, checked below)."""
    from numba import njit

    from skmoor.fem.native_calls import call_form

    @njit
    def compiled(address, u, ud, t, ints, floats, R, K, C, tangent):
        call_form(address, u.ctypes.data, ud.ctypes.data, u.size, t, ints.ctypes.data,
                  floats.ctypes.data, R.ctypes.data, K.ctypes.data, C.ctypes.data, tangent)

    x, y = np.array([-200.0, -20.0, 0.0, 300.0]), np.array([-100.0, 100.0])
    X, _ = np.meshgrid(x, y, indexing="ij")
    ridge = Bathymetry(x, y, -DEPTH + 3.0 * (X == 0.0) + 0.0 * X)
    points = np.linspace([-150.0, -5.0, -DEPTH - 0.5], [150.0, 5.0, -DEPTH + 1.0], 31)
    lines = LineSet([Line.from_polyline(points, CHAIN)], law="engineering")
    term = seabed_term(lines, Seabed(DEPTH, bathymetry=ridge, mu_axial=0.3, mu_lateral=0.6))
    term.bind(type("S", (), {"lines": lines})())
    rng = np.random.default_rng(4)
    u = rng.normal(scale=0.05, size=lines.ndofs)
    u[0::3] += 3.0
    v = rng.normal(scale=0.1, size=lines.ndofs)
    nel = lines.mesh.t.shape[1]
    expected = [np.zeros(lines.ndofs), np.zeros((nel, 6, 6)), np.zeros((nel, 6, 6))]
    term.add_to(u, v, 0.0, *expected, newton=True)  # (the compiled step's blocks)
    function, ints, floats = term.step_kernel
    got = [np.zeros(lines.ndofs), np.zeros((nel, 6, 6)), np.zeros((nel, 6, 6))]
    compiled(function.address, u, v, 0.0, ints, floats, *got, 1)
    for a, b in zip(got, expected):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-9 * np.abs(b).max())
    from skmoor.fem.patterns import NO_BLOCKS
    from skmoor.sea.seabed import _seabed

    normals, offsets = ridge.plane(term.X)  # the planes under the reference nodes
    at_reference = np.zeros(lines.ndofs)
    _seabed(term.X, term.ends, term.h, normals, offsets, term.k, term.c, term.onset,
            term.mu_a, term.mu_l, term.v0, term.friction, u, v, at_reference, NO_BLOCKS,
            NO_BLOCKS, term.stride, 0.0)
    assert np.abs(at_reference - expected[0]).max() > 0.01 * np.abs(expected[0]).max()
