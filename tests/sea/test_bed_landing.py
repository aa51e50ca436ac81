"""The sea bed in the time step's Newton iteration (skmoor.sea.seabed): the Newton matrix's
normal slope (newton_slope) against the exact one by hand, the kernel's Newton blocks
against the tangent plus that difference assembled by hand, the landing of a correction
that carries a node across the bed (land_on_bed) on a plane and on a bathymetry, and runs
of a heaved chain with and without them (same states, fewer iterations, no split steps)."""
import dataclasses

import numpy as np
import pytest
from test_seabed import CHAIN, DEPTH, touchdown

from skmoor.coupling.system import System
from skmoor.lines.line import Line, LineSet
from skmoor.sea.hydro import line_hydrodynamics
from skmoor.sea.seabed import Seabed, land_on_bed, newton_slope, seabed_term
from skmoor.solvers.dynamics import Scheme, integrate
from skmoor.solvers.statics import solve_static

K, C, ONSET = 1.3e6, 2.8e4, 1e-4  # N/m2, N s/m2, m


def exact_slope(vn, g):
    """d/dg of k g - c vn Hc(g), Hc = clip(g / onset, 0, 1) (g > 0)."""
    return K - C * vn * (1.0 / ONSET if g < ONSET else 0.0)


@pytest.mark.parametrize("vn, g, expected", [
    (-0.2, 0.5 * ONSET, K + C * 0.2 / ONSET),  # sinking in the fade-in: the exact slope
    (-0.2, 3.0 * ONSET, K + C * 0.2 / (3.0 * ONSET)),  # sinking past it: the secant
    (0.2, 0.5 * ONSET, K),  # rising: without the fade-in's negative slope
    (0.0, 0.5 * ONSET, K),  # at rest: the exact slope
])
def test_newton_slope_is_the_damping_secant_never_below_the_exact_slope(vn, g, expected):
    """k + c max(-vn, 0) / max(g, onset): equal to the exact slope while a node sinks in
    the fade-in and at rest, above it otherwise."""
    slope = newton_slope(K, C, vn, g, ONSET)
    assert slope == pytest.approx(expected, rel=1e-14)
    assert slope >= exact_slope(vn, g) * (1 - 1e-14)
    if vn == 0.0 or (vn < 0 and g < ONSET):
        assert slope == pytest.approx(exact_slope(vn, g), rel=1e-14)


def laid_chain(velocity):
    """A straight chain on a flat bed, its nodes 0-3 onsets deep (inside and past the
    fade-in), moving normal to the bed at ``velocity`` m/s times alternating signs."""
    n = 12
    X = np.c_[np.linspace(0.0, 60.0, n + 1), np.zeros(n + 1), np.full(n + 1, -DEPTH)]
    lines = LineSet([Line.from_polyline(X, CHAIN)], law="engineering")
    bed = Seabed(DEPTH, stiffness=K, damping=C, damping_onset=ONSET)
    rng = np.random.default_rng(1)
    u, ud = np.zeros(lines.ndofs), np.zeros(lines.ndofs)
    z = lines.nodal_dofs[:, 2]
    u[z] = -rng.uniform(0.05, 3.0, n + 1) * ONSET
    ud[z] = velocity * np.where(np.arange(n + 1) % 2, 1.0, -1.0)
    return lines, bed, u, ud


def element_blocks(term, u, ud, newton):
    nel = term.lines.mesh.t.shape[1]
    R, Ke, Ce = np.zeros(term.lines.ndofs), np.zeros((nel, 6, 6)), np.zeros((nel, 6, 6))
    term.add_to(u, ud, 0.0, R, Ke, Ce, newton=newton)
    return R, Ke, Ce


def test_newton_blocks_are_the_tangent_plus_the_slope_difference():
    """With newton=True the kernel's residual and damping blocks are unchanged and its
    stiffness blocks differ from the exact tangent by W (newton_slope - exact) n n^T at
    each element end in contact (W = h / 2, n = e_z), summed here by hand; at rest they
    are the tangent."""
    lines, bed, u, ud = laid_chain(0.3)
    term = seabed_term(lines, bed)
    R, Ke, Ce = element_blocks(term, u, ud, newton=False)
    Rn, Ken, Cen = element_blocks(term, u, ud, newton=True)
    assert np.array_equal(R, Rn) and np.array_equal(Ce, Cen)
    expected = np.zeros_like(Ke)
    t = lines.mesh.t
    for e in range(t.shape[1]):
        h = np.linalg.norm(lines.points[t[1, e]] - lines.points[t[0, e]])
        for end in range(2):
            node = t[end, e]
            g = -DEPTH - (lines.points[node, 2] + u[lines.nodal_dofs[node, 2]])
            vn = ud[lines.nodal_dofs[node, 2]]
            if g > 0:
                expected[e, 3 * end + 2, 3 * end + 2] = 0.5 * h * (
                    newton_slope(K, C, vn, g, ONSET) - exact_slope(vn, g))
    assert np.max(np.abs(expected)) > 0.1 * K  # the secant does change some blocks
    assert np.max(np.abs(Ken - Ke - expected)) <= 1e-9 * np.max(np.abs(Ke))
    _, Ke0, _ = element_blocks(term, u, 0 * ud, newton=False)
    _, Ken0, _ = element_blocks(term, u, 0 * ud, newton=True)
    assert np.array_equal(Ke0, Ken0)


def plane_landing(normal, offset, depth):
    """Three nodes at reference points, their DOFs scattered in a reduced vector of 12."""
    columns = np.array([[7, 2, 11], [0, 5, 9], [3, 10, 1]], np.int64)
    points = np.array([[0.0, 0.0, -99.9], [5.0, 0.0, -100.05], [9.0, 1.0, -99.5]])
    normal = np.tile(np.asarray(normal, float), (3, 1))
    empty = np.zeros(0)
    return columns, points, normal, np.full(3, offset), depth, empty, empty, np.zeros((0, 0))


def largest(dx):
    return float(np.max(np.abs(dx)))


def penetration(y, dx, landing, i):
    columns, points, normal, offset = landing[:4]
    return offset[i] - normal[i] @ (points[i] + y[columns[i]] + dx[columns[i]])


def test_landing_on_a_plane_by_hand():
    """On the bed z = -100: node 0 (0.1 m above) sent 0.4 m into the bed lands at the
    depth below its surface; node 1 (5 cm in contact) sent 0.3 m above it stops at the
    depth above; node 2 (0.5 m above) moving 0.3 m down is left alone, and so are all
    with depth 0; whether any landed is returned."""
    depth = 1e-3
    landing = plane_landing([0.0, 0.0, 1.0], -100.0, depth)
    columns = landing[0]
    y = np.zeros(12)
    dx = np.zeros(12)
    dx[columns[0, 2]], dx[columns[1, 2]], dx[columns[2, 2]] = -0.5, 0.35, -0.3
    dx[columns[0, 0]] = 0.2  # along the bed: kept
    original = dx.copy()
    assert land_on_bed(y, dx, largest(dx), *landing[:4], 0.0, *landing[5:]) is False
    assert np.array_equal(dx, original)
    assert land_on_bed(y, dx, largest(dx), *landing)
    assert penetration(y, dx, landing, 0) == pytest.approx(depth, abs=1e-12)
    assert penetration(y, dx, landing, 1) == pytest.approx(-depth, abs=1e-12)
    assert dx[columns[2, 2]] == -0.3 and dx[columns[0, 0]] == 0.2


def test_landing_skips_only_corrections_that_cannot_reach_the_depth():
    """On a bed whose normal is (1, 1, 1) / sqrt(3), a node at its surface moved by -s (1, 1,
    1) goes sqrt(3) s into it: with s = 0.9 depth (no component as large as the depth) it
    is landed, at the depth; with s just under depth / sqrt(3) it is not (the skip's bound
    is the node's whole move, not one component)."""
    depth = 1e-3
    normal = np.ones(3) / np.sqrt(3.0)
    landing = plane_landing(normal, normal @ [0.0, 0.0, -99.9], depth)
    columns = landing[0]
    y = np.zeros(12)
    for s, lands in ((0.9 * depth, True), (0.999 * depth / np.sqrt(3.0), False)):
        dx = np.zeros(12)
        dx[columns[0]] = -s
        assert land_on_bed(y, dx, largest(dx), *landing) is lands
        expected = depth if lands else np.sqrt(3.0) * s
        assert penetration(y, dx, landing, 0) == pytest.approx(expected, rel=1e-9)


def test_landing_on_a_bathymetry_by_hand():
    """On the plane z = -100 + 0.1 x - 0.05 y given as grid heights, a node sent from
    above through it lands at the depth along the plane's normal: its distance to the
    plane, (z_b(x, y) - z) / sqrt(1 + 0.1^2 + 0.05^2), is the depth."""
    gx, gy = np.linspace(-10.0, 20.0, 4), np.linspace(-5.0, 5.0, 3)
    heights = -100.0 + 0.1 * gx[:, None] - 0.05 * gy[None, :]
    columns = np.array([[0, 1, 2]], np.int64)
    points = np.array([[3.0, 1.0, -99.0]])
    depth = 2e-3
    landing = (columns, points, np.zeros((1, 3)), np.zeros(1), depth, gx, gy, heights)
    y, dx = np.array([0.5, -0.2, 0.1]), np.array([0.3, 0.1, -2.0])
    assert land_on_bed(y, dx, largest(dx), *landing)
    x, yy, z = points[0] + y + dx
    distance = (-100.0 + 0.1 * x - 0.05 * yy - z) / np.sqrt(1 + 0.1**2 + 0.05**2)
    assert distance == pytest.approx(depth, abs=1e-12)
    assert dx[0] != 0.3  # moved back along the normal, not straight up


def heaved_chain(amplitude, land):
    """The 500 m chain of test_seabed (50 elements, Morison drag) lying 352 m on the bed,
    its fairlead heaved at ``amplitude`` m, 10 s, ramped in over 10 s; ``land``: the bed's
    Newton matrix and landing on (the default), else its exact tangent."""
    chain = dataclasses.replace(CHAIN, Cd_n=2.4, Cd_t=1.15, Ca_n=1.0)
    lines = LineSet([Line.from_catenary(touchdown(), chain, 50)], law="engineering")
    bed = seabed_term(lines, Seabed(DEPTH))
    if not land:
        bed.newton_depth = 0.0

    def heave(t):
        ramp = 0.5 * (1 - np.cos(np.pi * t / 10.0)) if t < 10.0 else 1.0
        return [[0.0, 0.0, amplitude * ramp * np.sin(2 * np.pi * t / 10.0)]]

    system = System(lines, fairleads="prescribed", terms=[bed, line_hydrodynamics(lines)],
                    motion=heave)
    return system, solve_static(system).x


def run(system, x0, t_end, compiled):
    return list(integrate(system, x0, np.zeros(system.n), 0.25, t_end, compiled=compiled,
                          scheme=Scheme.generalized_alpha(0.5)))


def test_landing_changes_the_path_not_the_states():
    """The chain heaved 1.5 m (the touchdown nodes slap the bed): with the bed's Newton
    matrix and landing the states are those of the exact tangent to Newton's tolerance
    (1e-5 of a step's change) over 16 s, nodes do land, and Newton needs fewer iterations;
    the compiled step lands as the Python step does (to round-off)."""
    system, x0 = heaved_chain(1.5, land=True)
    landed = []
    limit = system.limit_correction
    system.limit_correction = lambda x, dx: landed.append(limit(x, dx)) or landed[-1]
    landing = run(system, x0, 16.0, compiled=False)
    exact = run(*heaved_chain(1.5, land=False), 16.0, compiled=False)
    assert any(landed)
    difference = max(np.max(np.abs(a.x - b.x)) for a, b in zip(landing, exact))
    assert difference < 1e-5
    assert sum(s.iterations for s in landing) < sum(s.iterations for s in exact) - 5
    compiled = run(*heaved_chain(1.5, land=True), 16.0, compiled=True)
    assert max(np.max(np.abs(a.x - b.x)) for a, b in zip(landing, compiled)) < 1e-9
    assert [s.iterations for s in compiled] == [s.iterations for s in landing]


def test_landing_needs_no_split_steps_where_the_exact_tangent_does():
    """Heaved 2 m, the exact tangent's Newton cycles across the bed's kink and splits
    steps; landed, no step is split."""
    assert run(*heaved_chain(2.0, land=True), 40.0, compiled=True)[-1].subdivided == 0
    assert run(*heaved_chain(2.0, land=False), 40.0, compiled=True)[-1].subdivided > 0
