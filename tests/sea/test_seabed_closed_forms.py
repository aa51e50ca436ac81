"""Sea-bed contact (skmoor.sea.seabed) against numbers worked by hand, beside
test_seabed.py: the lumped spring, damping and regularised Coulomb friction of a straight
line lying in a flat bed (nodal shares (h_l + h_r) / 2 of unequal elements), with one
friction coefficient zero at a time and without bed damping; the damping's fade-in and its
derivative at small penetrations; a call without a velocity; the compiled kernel's element
blocks on P1 and on bending (Hermite) lines; a bathymetry's kinked bed under a displaced
node; the support the bed gives held ends resting on it; the as-laid reference of the
static friction (a catenary's laid part shortened by its stretch); the coefficients'
defaults and MoorDyn's; and a bathymetry grid's edges and refusals."""
import dataclasses

import numpy as np
import pytest

from skmoor.lines.catenary import solve_catenary
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.sea.seabed import Bathymetry, Seabed, form_term, seabed_term

CHAIN = LineType(EA=6e8, mass=150.0, diameter=0.15)  # w = 1294 N/m
DEPTH = 100.0
LENGTHS = np.array([3.0, 5.0, 4.0, 6.0])  # unequal elements: each node its own share
SHARE = (np.r_[0.0, LENGTHS] + np.r_[LENGTHS, 0.0]) / 2  # m of line at each node
E = np.array([0.6, 0.8, 0.0])  # the line's direction, on the flat bed
UP = np.array([0.0, 0.0, 1.0])


def dense(A):
    return np.zeros((0, 0)) if A is None else (A.toarray() if hasattr(A, "toarray")
                                              else np.asarray(A))


def straight(line_type=CHAIN, element=None, z=-DEPTH):
    """A stress-free straight line along E at height z on the elements LENGTHS."""
    s = np.concatenate([[0.0], np.cumsum(LENGTHS)])
    points = np.array([5.0, -3.0, z]) + s[:, None] * E
    return LineSet([Line.from_polyline(points, line_type)], law="engineering",
                   element=element)


def terms(lines, bed):
    """The compiled kernel and the scikit-fem forms of one bed (the same definition)."""
    return {"kernel": seabed_term(lines, bed), "forms": form_term(lines, bed)}


def hand_residual(bed, g, vel, onset):
    """The residual (N, (nodes, 3)) of a straight line along E lying g (m, per node) deep
    in a flat bed with node velocities vel (nodes, 3), by hand: each node carries
    W = SHARE; the bed pushes along +z with W (k g - c v_z Hc), Hc = clip(g / onset, 0, 1),
    and the friction, of normal force N = W k g, is -N [mu_a phi(v_a) E + mu_l v_l /
    sqrt(|v_l|^2 + v0^2)], phi(s) = s / sqrt(s^2 + v0^2), v_a = E.v, v_l = (v_x, v_y, 0) -
    v_a E; the residual is minus the force on the line."""
    k, c, v0 = bed.stiffness, bed.damping, bed.friction_velocity
    R = np.zeros((len(g), 3))
    for i, (gi, v) in enumerate(zip(g, vel)):
        if gi <= 0:
            continue
        fade = 1.0 if onset == 0 else min(gi / onset, 1.0)
        push = SHARE[i] * (k * gi - c * v[2] * fade)
        va = E @ v
        vl = np.array([v[0], v[1], 0.0]) - va * E
        N = SHARE[i] * k * gi
        friction = N * (bed.mu_axial * va / np.hypot(va, v0) * E
                        + bed.mu_lateral * vl / np.sqrt(vl @ vl + v0 ** 2))
        R[i] = -push * UP + friction
    return R


@pytest.mark.parametrize("mu", [(0.4, 0.0), (0.0, 0.7), (0.3, 0.9)],
                         ids=["axial only", "lateral only", "both"])
@pytest.mark.parametrize("kind", ["kernel", "forms"])
def test_friction_of_a_straight_line_without_bed_damping(kind, mu):
    """A straight line lying in a flat bed without damping (c = 0), its nodes sunk to
    different depths and sliding at speeds about v0 in every direction: the residual is
    hand_residual's spring and regularised friction (1e-12), and d/dudot, the friction's
    alone here, is the central difference of that hand residual (1e-7). Fails on a bed
    with one coefficient zero left frictionless (an 'and' for an 'or', or a threshold
    mu > 1), or on friction reported without its rate when the bed has no damping."""
    bed = Seabed(DEPTH, stiffness=2e5, damping=0.0, mu_axial=mu[0], mu_lateral=mu[1],
                 friction_velocity=0.05)
    lines = straight()
    term = terms(lines, bed)[kind]
    g = np.array([0.01, 0.02, 0.005, 0.015, 0.03])
    u = np.zeros(lines.ndofs)
    u[lines.nodal_dofs[:, 2]] = -g
    rng = np.random.default_rng(1)
    vel = rng.normal(scale=0.05, size=(len(g), 3))
    ud = np.zeros(lines.ndofs)
    ud[lines.nodal_dofs] = vel
    R, _, C = term.evaluate(u, ud, 0.0, True, "dense")
    expected = hand_residual(bed, g, vel, 0.0)
    np.testing.assert_allclose(R[lines.nodal_dofs], expected, rtol=0,
                               atol=1e-12 * np.abs(expected).max())
    C = dense(C)
    assert C.shape == (lines.ndofs, lines.ndofs)
    e = 1e-7
    for node in range(len(g)):
        for q in range(3):
            step = np.zeros_like(vel)
            step[node, q] = e
            column = (hand_residual(bed, g, vel + step, 0.0)
                      - hand_residual(bed, g, vel - step, 0.0)) / (2 * e)
            np.testing.assert_allclose(C[lines.nodal_dofs, lines.nodal_dofs[node, q]],
                                       column, rtol=0, atol=1e-6 * np.abs(column).max())


@pytest.mark.parametrize("onset, g", [(1.0, 0.25), (0.01, 0.004), (0.0, 0.003)],
                         ids=["onset 1 m", "onset 1 cm", "onset 0"])
@pytest.mark.parametrize("kind", ["kernel", "forms"])
def test_damping_fade_in_and_its_slope_by_hand(kind, onset, g):
    """A node of a straight line on a flat frictionless bed, g deep and moving down at
    v = 0.2 m/s, its neighbour exactly on the bed's surface (g = 0: an end laid at the
    depth): the bed pushes W (k g - c v Hc) with Hc = g / onset (1 for onset 0), and
    d/du_z of the residual is W (k - c v dHc/dg), dHc/dg = 1 / onset inside the fade-in
    (0 for onset 0). Every entry of the tangent is finite (a 0 / g at the surface node
    would be NaN). Fails on a fade that ignores onset = 1 m, on the fade's slope dropped
    below 1 m of penetration, and on a slope g instead of 0 without fade-in."""
    k, c, vz = 2e5, 3e4, -0.2
    bed = Seabed(DEPTH, stiffness=k, damping=c, damping_onset=onset)
    lines = straight()
    node = 2
    u, ud = np.zeros(lines.ndofs), np.zeros(lines.ndofs)
    z = lines.nodal_dofs[node, 2]
    u[z], ud[z] = -g, vz
    u[lines.nodal_dofs[[0, 1, 3, 4], 2]] = [1.0, 0.0, 1.0, 1.0]  # node 1 on the surface
    R, K, C = (dense(A) if i else A
               for i, A in enumerate(terms(lines, bed)[kind].evaluate(u, ud, 0.0, True,
                                                                      "dense")))
    W = SHARE[node]
    fade, slope = (1.0, 0.0) if onset == 0 else (g / onset, 1.0 / onset)
    assert -R[z] == pytest.approx(W * (k * g - c * vz * fade), rel=1e-9)
    assert np.all(np.isfinite(K)) and np.all(np.isfinite(C))
    assert K[z, z] == pytest.approx(W * (k - c * vz * slope), rel=1e-9)
    assert C[z, z] == pytest.approx(W * c * fade, rel=1e-9)
    others = np.delete(np.arange(lines.ndofs), z)
    assert np.abs(R[others]).max() == 0.0


def test_kernel_without_a_velocity_and_its_element_blocks():
    """The compiled kernel called as a static evaluation (velocity None) with stiffness
    blocks but no damping blocks: the residual is the spring alone, -W k g along +z at
    each sunk node, however the bed damps and rubs (the line is at rest); each element's
    6 x 6 block holds (h / 2) k n n^T at each sunk end (lumped, no coupling of the two
    ends). Fails on a missing at-rest velocity or damping block."""
    k = 2e5
    bed = Seabed(DEPTH, stiffness=k, damping=4e4, mu_axial=0.5, mu_lateral=0.8)
    lines = straight()
    term = seabed_term(lines, bed)
    g = np.array([0.01, 0.0, 0.02, 0.0, 0.03])
    u = np.zeros(lines.ndofs)
    u[lines.nodal_dofs[:, 2]] = -g + (g == 0) * 0.5  # nodes 1 and 3 above the bed
    R = np.zeros(lines.ndofs)
    Ke = np.zeros((len(LENGTHS), 6, 6))
    term.add_to(u, None, 0.0, R, Ke)
    np.testing.assert_allclose(R[lines.nodal_dofs], -(SHARE * k * g)[:, None] * UP,
                               rtol=1e-12, atol=0)
    expected = np.zeros_like(Ke)
    for e, h in enumerate(LENGTHS):
        for end in range(2):
            if g[e + end] > 0:
                expected[e, 3 * end + 2, 3 * end + 2] = h / 2 * k
    np.testing.assert_allclose(Ke, expected, rtol=1e-12, atol=1e-9)


def test_bending_line_bed_acts_on_the_node_positions():
    """A straight bending (Hermite) line lying g deep in a flat bed, sliding along itself
    at 2 v0 and across it: the bed's residual on each node's position is hand_residual's
    (lumped spring and friction), nothing on the slope DOFs; the stiffness is W k on each
    node's z and the rate W c on z plus the friction's on x, y, all on position DOFs
    (the element blocks' node 2 starts at entry 6), none on slopes. The forms asked for
    by path (C1 tangent: the chord on a straight line) give the same residual."""
    k, c = 2e5, 3e4
    bed = Seabed(DEPTH, stiffness=k, damping=c, damping_onset=0.0, mu_axial=0.4,
                 mu_lateral=0.6, friction_velocity=0.05)
    lines = straight(LineType(EA=6e8, mass=150.0, diameter=0.15, EI=1e4))
    assert lines.hermite
    g = np.array([0.01, 0.02, 0.005, 0.015, 0.03])
    vel = np.tile([0.08, -0.03, 0.0], (len(g), 1))
    u, ud = np.zeros(lines.ndofs), np.zeros(lines.ndofs)
    u[lines.nodal_dofs[:, 2]] = -g
    ud[lines.nodal_dofs] = vel
    R, K, C = seabed_term(lines, bed).evaluate(u, ud, 0.0, True, "dense")
    K, C = dense(K), dense(C)
    expected = hand_residual(bed, g, vel, 0.0)
    np.testing.assert_allclose(R[lines.nodal_dofs], expected, rtol=0,
                               atol=1e-12 * np.abs(expected).max())
    forms = seabed_term(lines, bed, path="assembly").evaluate(u, ud, 0.0, False)[0]
    np.testing.assert_allclose(forms[lines.nodal_dofs], expected, rtol=0,
                               atol=1e-9 * np.abs(expected).max())
    slopes = lines.slope_dofs.ravel()
    assert np.abs(R[slopes]).max() == 0.0
    for A in (K, C):
        assert np.abs(A[slopes]).max() == 0.0 and np.abs(A[:, slopes]).max() == 0.0
    zs = lines.nodal_dofs[:, 2]
    np.testing.assert_allclose(np.diag(K)[zs], SHARE * k, rtol=1e-12)
    np.testing.assert_allclose(np.diag(C)[zs], SHARE * c, rtol=1e-12)
    assert np.all(np.diag(C)[lines.nodal_dofs[:, :2].ravel()] > 0)  # friction's rate


def kinked_bathymetry():
    """Flat at -DEPTH up to x = 100 m, then rising at 1 in 10 to x = 200 m."""
    x, y = np.array([0.0, 100.0, 200.0]), np.array([-50.0, 50.0])
    heights = np.array([[-DEPTH] * 2, [-DEPTH] * 2, [-DEPTH + 10.0] * 2])
    return Bathymetry(x, y, heights)


def test_bed_under_a_displaced_node_is_the_bathymetry_there():
    """A line whose middle node sits at x = 90 m (over the flat part) and is displaced
    20 m onto the 1-in-10 rise (x = 110 m, the bed at z_b = -99 m), 0.2 m below the bed:
    the bed pushes along the rise's normal n = (-0.1, 0, 1) / sqrt(1.01) with W k g,
    g = n_z (z_b - z), taken where the node is (X + u), not where it was; and
    Seabed.penetration of the single point (3,) says the same g."""
    k = 2e5
    bed = Seabed(DEPTH, stiffness=k, bathymetry=kinked_bathymetry())
    points = np.array([[70.0, 0.0, -90.0], [90.0, 0.0, -90.0], [130.0, 0.0, -80.0]])
    lines = LineSet([Line.from_polyline(points, CHAIN)], law="engineering")
    u = np.zeros(lines.ndofs)
    node = lines.nodal_dofs[1]
    z = -DEPTH + 1.0 - 0.2
    u[node] = [20.0, 0.0, z - points[1, 2]]
    n = np.array([-0.1, 0.0, 1.0]) / np.sqrt(1.01)
    g = n[2] * 0.2
    assert bed.penetration(np.array([110.0, 0.0, z])) == pytest.approx(g, rel=1e-12)
    R, _, _ = seabed_term(lines, bed).evaluate(u, np.zeros(lines.ndofs), 0.0, False)
    W = 0.5 * (20.0 + np.linalg.norm(points[2] - points[1]))
    np.testing.assert_allclose(R[node], -W * k * g * n, rtol=1e-12)


def polylines(bed):
    """Two straight lines' nodes on unequal elements, on the bed's surface, each along its
    own direction (a: along E from (5, -3), b: along -x from (60, 40))."""
    s = np.concatenate([[0.0], np.cumsum(LENGTHS)])
    out = []
    for start, d in (((5.0, -3.0), E), ((60.0, 40.0), np.array([-1.0, 0.0, 0.0]))):
        xy = np.array(start) + s[:, None] * d[:2]
        out.append(np.column_stack([xy, bed.height(xy)]))
    return out


def resting_line(bed):
    return LineSet([Line.from_polyline(points, CHAIN) for points in polylines(bed)],
                   law="engineering")


@pytest.mark.parametrize("grid", [False, True], ids=["plane", "bathymetry"])
def test_resting_support_is_the_weight_the_spring_leaves(grid):
    """Held ends resting on a 3-degree slope (a plane, or a bathymetry grid of it): the
    bed carries, along its normal n, the part of the node's lumped weight pressing into
    it, P = -W_node . n (W_node = -w h/2 e_z, h the end element's length along the
    slope), that the spring k g h/2
    does not: max(P - k (h/2) max(g, 0), 0); none for a node more than 1e-6 m above the
    bed or pulled away from it. Both lines' anchors and fairleads (shares 1.5, 3, 1.5,
    3 m), at two states at once and at each alone. Fails on the wrong share (the other
    end's element, both ends' sum, twice it), on k / share, on a spring that adds, on a
    support that pulls, on a node above the bed carried, on the gap counted with -u, and
    on one node set's shares kept for another."""
    slope = 3.0
    if grid:
        x, y = np.array([-100.0, 0.0, 200.0]), np.array([-100.0, 100.0])
        X, _ = np.meshgrid(x, y, indexing="ij")
        bed = Seabed(DEPTH, stiffness=1e4, bathymetry=Bathymetry(
            x, y, -DEPTH + np.tan(np.radians(slope)) * X))
    else:
        bed = Seabed(DEPTH, stiffness=1e4, slope_deg=slope)
    lines = resting_line(bed)
    normal = np.array([-np.sin(np.radians(slope)), 0.0, np.cos(np.radians(slope))])
    term = seabed_term(lines, bed)
    w = CHAIN.weight
    anchors, fairleads = lines.anchor_nodes, lines.fairlead_nodes
    weight = np.zeros(lines.ndofs)
    weight[lines.nodal_dofs[:, 2]] = -w * 1.0  # N: only the held nodes' entries count
    a, _ = polylines(bed)  # line a's end elements' lengths along the slope
    ends = ((anchors, np.linalg.norm(a[1] - a[0])), (fairleads, np.linalg.norm(a[-1] - a[-2])))
    for nodes, h in ends:
        share = h / 2
        weight[lines.nodal_dofs[nodes, 2]] = -w * share
        pressing = w * share * normal[2]
        spring = bed.stiffness * share
        # states: on the surface; half the weight's depth; twice it; 0.5 um and 1 mm above
        depths = np.array([0.0, 0.5, 2.0, -5e-7 * spring / pressing,
                           -1e-3 * spring / pressing]) * pressing / spring
        carried = np.array([pressing, 0.5 * pressing, 0.0, pressing, 0.0])
        u = np.zeros((len(depths), lines.ndofs))
        u[:, lines.nodal_dofs[nodes[0]]] = -depths[:, None] * normal  # line a's end
        u[:, lines.nodal_dofs[nodes[1]]] = 0.4 * normal  # line b's: above the bed
        support = term.resting_support(u, weight, nodes)
        assert support.shape == (len(depths), 2, 3)
        np.testing.assert_allclose(support[:, 0], carried[:, None] * normal, rtol=1e-9,
                                   atol=1e-9 * pressing)
        assert np.abs(support[:, 1]).max() == 0.0
        for state, expected in zip(u, carried):
            np.testing.assert_allclose(term.resting_support(state, weight, nodes)[0],
                                       expected * normal, rtol=1e-9, atol=1e-9 * pressing)
    pulled = -weight  # buoyant: nothing presses into the bed
    assert np.abs(term.resting_support(np.zeros(lines.ndofs), pulled, anchors)).max() == 0.0


def test_resting_support_takes_each_nodes_own_spring():
    """Two lines of diameters 0.1 and 0.2 m on a per-diameter bed (k = kBot d): each held
    anchor, 0.1 * its weight's depth into the bed, is carried 0.9 of its pressing weight,
    its own spring k d h/2 taking the rest; the stiffer line's spring given to the other
    line's end would carry 0.2 of it there."""
    kBot = 1e6
    bed = Seabed(DEPTH, stiffness=kBot, per_diameter=True)
    thin = LineType(EA=6e8, mass=150.0, diameter=0.1)
    thick = LineType(EA=6e8, mass=150.0, diameter=0.2)
    lines = LineSet([Line.from_polyline(points, lt)
                     for points, lt in zip(polylines(bed), (thin, thick))], law="engineering")
    term = seabed_term(lines, bed)
    anchors = lines.anchor_nodes
    share = LENGTHS[0] / 2
    weight = np.zeros(lines.ndofs)
    weight[lines.nodal_dofs[anchors, 2]] = -share * np.array([thin.weight, thick.weight])
    u = np.zeros(lines.ndofs)
    for node, lt in zip(anchors, (thin, thick)):
        u[lines.nodal_dofs[node, 2]] = -0.1 * lt.weight / (kBot * lt.diameter)
    support = term.resting_support(u, weight, anchors)
    np.testing.assert_allclose(support[:, 2], 0.9 * share * np.array([thin.weight,
                                                                        thick.weight]),
                               rtol=1e-9)



def test_as_laid_reference_is_the_catenary_laid_part_unstretched():
    """Static friction 'as-laid' on two lines: a short line hanging clear of the bed (its
    anchor 5 m up: no laid reference at all) and a soft chain (EA = 5e6 N) on a catenary
    with 150 m on the bed. Laid straight along the bed without tension, a node at
    unstretched arclength s from the anchor sits at s along the chord, while the catenary
    stretches the laid part uniformly by H / EA: the laid displacement of each node on the
    bed is -(H / EA) / (1 + H / EA) times its chord from the anchor (0 at the anchor); the
    suspended nodes and the hanging line's keep zero. Fails on the arclength counted from
    1 m, or from the first line's start, on the stretch taken at the wrong place or line,
    on the nodes just above the bed counted as laid, on a NaN at the anchor, and on the
    hanging line's end stopping the others."""
    soft = LineType(EA=5e6, mass=150.0, diameter=0.15)
    anchor = np.array([-400.0, 0.0, -DEPTH])
    cat = solve_catenary(anchor, np.zeros(3), soft.weight, soft.EA, length=450.0,
                         seabed_z=-DEPTH)
    hanging = Line.from_polyline(np.linspace([50.0, 50.0, -DEPTH + 5.0], [50.0, 50.0, -20.0],
                                             4), soft)
    lines = LineSet([hanging, Line.from_catenary(cat, soft, 45)], law="engineering")
    bed = Seabed(DEPTH, stiffness=soft.weight / 1e-3, mu_axial=0.5, mu_lateral=0.5,
                 static_friction="as-laid")
    laid = seabed_term(lines, bed).laid_displacement()[lines.nodal_dofs]
    g = bed.penetration(lines.points)
    a = lines.anchor_nodes[1]
    on_bed = np.flatnonzero(g > -1e-9)
    assert on_bed[0] == a and np.all(np.diff(on_bed) == 1) and 10 < len(on_bed) < 40
    strain = cat.H / soft.EA
    assert strain > 0.005
    chord = lines.points[on_bed] - lines.points[a]
    np.testing.assert_allclose(laid[on_bed], -strain / (1 + strain) * chord, rtol=1e-6,
                               atol=1e-9)
    assert np.all(np.isfinite(laid))
    rest = np.setdiff1d(np.arange(len(laid)), on_bed)
    assert np.abs(laid[rest]).max() == 0.0
    assert np.any((g[rest] > -1.0) & (g[rest] < 0.0))  # nodes just above the bed: not laid


def test_as_laid_reference_of_a_line_laid_in_an_l():
    """A line stretched 5 % in its reference lying on the bed in an L, 0.5 m
    then 9.5 m along x, then 10 m along y: each node at unstretched arclength s = S / 1.05
    (S its reference arclength) is laid at s along its chord from the anchor, its laid
    displacement (s / |chord| - 1) chord; the node 0.5 m from the anchor too. The same L
    as a second line stretched 1 + 0.01 S: each element's unstretched length is its
    length over the stretch at its middle (S counted from its own anchor)."""
    lt = LineType(EA=1e6, mass=150.0, diameter=0.15)
    points = np.array([[0.0, 0.0], [0.5, 0.0], [10.0, 0.0], [10.0, 4.0], [10.0, 10.0]])
    points = np.column_stack([points, np.full(len(points), -DEPTH)])
    line = dataclasses.replace(Line.from_polyline(points, lt, tension=0.05 * lt.EA),
                               stretch=lambda s: np.full(np.shape(s), 1.05))
    lines = LineSet([line], law="engineering")
    bed = Seabed(DEPTH, stiffness=1e5, mu_axial=0.3, static_friction="as-laid")
    laid = seabed_term(lines, bed).laid_displacement()[lines.nodal_dofs]
    S = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    s = S / 1.05
    # the same L as a second line, stretched 1 + 0.01 S (S from its own anchor): each
    # element's unstretched length is its length over the stretch at its middle
    varying = dataclasses.replace(Line.from_polyline(points, lt),
                                  stretch=lambda S: 1.0 + 0.01 * np.asarray(S))
    first = Line.from_polyline(points + [0.0, 50.0, 0.0], lt)
    two = LineSet([first, varying], law="engineering")
    laid2 = seabed_term(two, bed).laid_displacement()[two.nodal_dofs[two.anchor_nodes[1]:]]
    h = np.diff(S)
    s2 = np.concatenate([[0.0], np.cumsum(h / (1.0 + 0.01 * (S[:-1] + S[1:]) / 2))])
    chord = points - points[0]
    expected2 = np.zeros_like(chord)
    expected2[1:] = (s2[1:] / np.linalg.norm(chord[1:], axis=1) - 1)[:, None] * chord[1:]
    np.testing.assert_allclose(laid2, expected2, rtol=1e-9, atol=1e-12)
    chord = points - points[0]
    length = np.linalg.norm(chord, axis=1)
    expected = np.zeros_like(chord)
    expected[1:] = (s[1:] / length[1:] - 1)[:, None] * chord[1:]
    np.testing.assert_allclose(laid, expected, rtol=1e-9, atol=1e-12)
    reference = Seabed(DEPTH, stiffness=1e5, mu_axial=0.3, static_friction="reference")
    assert np.abs(seabed_term(lines, reference).laid_displacement()).max() == 0.0


def test_coefficients_defaults_and_moordyns():
    """The default stiffness is the heaviest line's |w| over 1 mm (a buoyant line's
    weight counted by its size), the default damping 2 sqrt(k m) with the heaviest mass;
    per_diameter makes stiffness and damping pressures on each element's line diameter
    (k d, c d), and the default onset a tenth of the largest w / (k d); weightless lines
    have no default. MoorDyn's defaults are kBot = 3e6 Pa/m and cBot = 3e5 Pa s/m, no
    friction, other settings passed on."""
    heavy = LineType(EA=1e9, mass=150.0, diameter=0.1)
    light = LineType(EA=1e9, mass=40.0, diameter=0.3, weight=-2500.0)  # buoyant, bigger
    lines = LineSet([Line.from_polyline([[0, 0, -90], [10, 0, -90], [20, 0, -90]], heavy),
                     Line.from_polyline([[0, 5, -90], [10, 5, -90]], light)])
    k, c = Seabed(DEPTH).coefficients(lines)
    assert k == pytest.approx(2500.0 / 1e-3, rel=1e-12)
    assert c == pytest.approx(2 * np.sqrt(k * 150.0), rel=1e-12)
    bed = Seabed(DEPTH, stiffness=1e6, damping=1e4, per_diameter=True)
    kd, cd = bed.cell_coefficients(lines)
    np.testing.assert_allclose(kd, [1e5, 1e5, 3e5], rtol=1e-12)
    np.testing.assert_allclose(cd, [1e3, 1e3, 3e3], rtol=1e-12)
    assert bed.onset(lines) == pytest.approx(
        0.1 * max(heavy.weight / 1e5, 2500.0 / 3e5), rel=1e-12)
    weightless = LineType(EA=1e9, mass=10.0, diameter=0.1, weight=0.0)
    with pytest.raises(ValueError):
        Seabed(DEPTH).coefficients(LineSet([Line.from_polyline([[0, 0, -90], [1, 0, -90]],
                                                               weightless)]))
    md = Seabed.from_moordyn(50.0, 0.2, slope_deg=2.0)
    assert (md.stiffness, md.damping) == pytest.approx((3e6 * 0.2, 3e5 * 0.2), rel=1e-12)
    assert md.mu_axial == md.mu_lateral == 0.0 and md.slope_deg == 2.0


def test_bathymetry_grid_edges_and_refusals():
    """A grid of three x's: the slope of the last cell is its own (x = 150 m: 10 m over
    100 m), of the first cell zero; a grid of a single x has no x slope (not 0 / 0), its
    heights from y alone (and likewise a single y); a bed at the still water line (z = 0) or a coordinate table
    that is not a list is refused."""
    bathymetry = kinked_bathymetry()
    np.testing.assert_allclose(bathymetry.slopes(np.array([[150.0, 20.0], [50.0, -20.0],
                                                           [250.0, 0.0]])),
                               [[0.1, 0.0], [0.0, 0.0], [0.0, 0.0]], atol=1e-15)
    np.testing.assert_allclose(bathymetry.normal(np.array([150.0, 20.0])),
                               np.array([-0.1, 0.0, 1.0]) / np.sqrt(1.01), rtol=1e-12)
    line = Bathymetry([5.0], [0.0, 10.0, 30.0], [[-50.0, -51.0, -55.0]])
    np.testing.assert_allclose(line.slopes(np.array([[-3.0, 20.0], [9.0, 5.0]])),
                               [[0.0, -0.2], [0.0, -0.1]], rtol=1e-12)
    assert line.height(np.array([100.0, 20.0])) == pytest.approx(-53.0)
    with pytest.raises(ValueError):
        Bathymetry([0.0, 1.0], [0.0], [[-1.0], [0.0]])
    with pytest.raises(ValueError):
        Bathymetry([[0.0, 1.0]], [0.0], [[-1.0], [-1.0]])
    row = Bathymetry([0.0, 10.0], [3.0], [[-50.0], [-52.0]])
    np.testing.assert_allclose(row.slopes(np.array([5.0, 7.0])), [-0.2, 0.0], rtol=1e-12)
