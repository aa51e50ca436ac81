"""Sea-bed contact (skmoor.sea.seabed): the plane's geometry, tangents against central finite
differences, the compiled kernel against the scikit-fem forms, the normal force's continuity
at touchdown (damping onset), the static touchdown against the analytic catenary, a line
on a slope against the in-plane catenary and w cos(slope), and friction against mu w L of
a line dragged along and across itself."""
import dataclasses

import numpy as np
import pytest
from scipy.optimize import brentq

from skmoor.coupling.system import System
from skmoor.lines.catenary import solve_catenary
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.sea.seabed import DEFAULT_PENETRATION, Seabed, form_term, seabed_term
from skmoor.solvers.dynamics import Scheme, integrate
from skmoor.solvers.statics import solve_static

CHAIN = LineType(EA=6e8, mass=150.0, diameter=0.15)  # w = 1294 N/m
DEPTH = 100.0
ANCHOR = np.array([450.0, 0.0, -DEPTH])
FAIRLEAD = np.zeros(3)
LENGTH = 500.0  # 352 m of it on the bed


def touchdown(fairlead=FAIRLEAD):
    return solve_catenary(ANCHOR, fairlead, CHAIN.weight, CHAIN.EA, length=LENGTH,
                          seabed_z=-DEPTH)


def test_plane_geometry_and_input_checks():
    """The sloped plane passes through (0, 0, -depth), rises at the slope towards the
    heading, and its normal is the unit upward normal; bad input names its field."""
    bed = Seabed(50.0, slope_deg=10.0, slope_heading_deg=30.0)
    heading = np.array([np.cos(np.radians(30.0)), np.sin(np.radians(30.0))])
    xy = np.array([[0.0, 0.0], [100.0 * heading[0], 100.0 * heading[1]], [-20.0, 35.0]])
    z = bed.height(xy)
    assert z[0] == pytest.approx(-50.0)
    assert z[1] == pytest.approx(-50.0 + 100.0 * np.tan(np.radians(10.0)))
    on_bed = np.column_stack([xy, z])
    assert bed.penetration(on_bed) == pytest.approx(np.zeros(3), abs=1e-12)
    assert bed.penetration(on_bed + 2.0 * bed.normal) == pytest.approx(np.full(3, -2.0))
    assert np.linalg.norm(bed.normal) == pytest.approx(1.0)
    assert bed.normal[2] == pytest.approx(np.cos(np.radians(10.0)))
    moordyn = Seabed.from_moordyn(50.0, 0.252, kBot=1e5, cBot=1e4, FrictionCoefficient=0.5)
    assert (moordyn.stiffness, moordyn.damping) == pytest.approx((1e5 * 0.252, 1e4 * 0.252))
    assert moordyn.mu_axial == moordyn.mu_lateral == 0.5
    for kw, field in ((dict(depth=-1.0), "depth"), (dict(depth=10.0, slope_deg=90.0), "slope_deg"),
                      (dict(depth=10.0, mu_lateral=-0.1), "mu_lateral"),
                      (dict(depth=10.0, friction_velocity=0.0), "friction_velocity"),
                      (dict(depth=10.0, damping_onset=-1e-3), "damping_onset"),
                      (dict(depth=10.0, damping_onset=np.inf), "damping_onset")):
        with pytest.raises(ValueError, match=field):
            Seabed(**kw)


def contact_state(seed=0, friction=True, line_type=CHAIN):
    """Two lines on one mesh, partly in the bed of a sloped, frictional (or frictionless)
    sea bed, moving; several nodes inside the damping's fade-in 0 < g < onset."""
    lines = LineSet([Line.from_catenary(touchdown(), line_type, 16, name="a"),
                     Line.from_catenary(touchdown([20.0, 30.0, -10.0]), line_type, 9, name="b")],
                    law="engineering")
    onset = 6.0  # m: the slope buries the laid chain 2-12 m deep
    mu = (0.4, 0.9) if friction else (0.0, 0.0)
    bed = Seabed(DEPTH, damping=3e4, mu_axial=mu[0], mu_lateral=mu[1], slope_deg=2.0,
                 slope_heading_deg=40.0, friction_velocity=0.02, damping_onset=onset)
    rng = np.random.default_rng(seed)
    u = rng.normal(scale=0.05, size=lines.ndofs)  # m, against ~ 0.6 m to the slope
    ud = rng.normal(scale=0.03, size=lines.ndofs)  # m/s, about v0: the curved part of friction
    g = bed.penetration(lines.points + u[lines.nodal_dofs])
    assert 10 < np.sum(g > 0) < len(g) - 5 and np.sum((g > 0) & (g < onset)) >= 3
    assert np.min(np.abs(g)) > 1e-4 and np.min(np.abs(g - onset)) > 1e-4  # clear of kinks
    return lines, bed, u, ud


@pytest.mark.parametrize("friction", [True, False])
@pytest.mark.parametrize("fast", [True, False])
def test_tangents_are_central_differences(fast, friction):
    """K = dR/du and Kv = dR/dudot of contact and friction (both directions, sloped bed;
    and without friction) match central differences of the residual to 1e-6."""
    lines, bed, u, ud = contact_state(friction=friction)
    term = (seabed_term(lines, bed) if fast else form_term(lines, bed))
    _, K, Kv = term.evaluate(u, ud, 0.0, True)
    rng = np.random.default_rng(5)
    e = 1e-6
    for _ in range(3):
        d = rng.normal(size=lines.ndofs)
        dR_du = (term.evaluate(u + e * d, ud, 0.0, False)[0]
                 - term.evaluate(u - e * d, ud, 0.0, False)[0]) / (2 * e)
        dR_dv = (term.evaluate(u, ud + e * d, 0.0, False)[0]
                 - term.evaluate(u, ud - e * d, 0.0, False)[0]) / (2 * e)
        assert np.max(np.abs(K @ d - dR_du)) < 1e-6 * np.max(np.abs(dR_du))
        assert np.max(np.abs(Kv @ d - dR_dv)) < 1e-6 * np.max(np.abs(dR_dv))


@pytest.mark.parametrize("friction", [True, False])
@pytest.mark.parametrize("layout", ["sparse", "dense", "band"])
def test_kernel_equals_forms(layout, friction):
    """The compiled kernel gives the scikit-fem assembly of the forms to round-off (with and
    without friction: the kernel skips the friction terms when both mu are zero)."""
    lines, bed, u, ud = contact_state(seed=3, friction=friction)
    fast = seabed_term(lines, bed).evaluate(u, ud, 0.0, True, layout)
    forms = form_term(lines, bed).evaluate(u, ud, 0.0, True, layout)
    for a, b in zip(fast, forms):
        a, b = (m.toarray() if hasattr(m, "toarray") else m for m in (a, b))
        assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(b))


@pytest.mark.parametrize("layout", ["sparse", "dense", "band"])
def test_system_without_body_assembles_the_free_dofs_directly(layout):
    """A System with fixed fairleads puts its kernels' element blocks straight into the
    free-DOF matrices (and reduces a form term's matrices): K = dR/dx and Kv = dR/dv match
    central differences of the reduced residual, with the cable's axial damping, the bed,
    the compiled drag and the drag as forms all on."""
    from skmoor.sea.hydro import form_terms, line_hydrodynamics

    damped = dataclasses.replace(CHAIN, BA=1e-3 * CHAIN.EA, Cd_n=1.2, Cd_t=0.4)
    lines, bed, u, ud = contact_state(seed=4, line_type=damped)
    assert lines.damped
    system = System(lines, fairleads="fixed",
                    terms=[seabed_term(lines, bed), line_hydrodynamics(lines),
                           *form_terms(lines)])
    x, v = u[system.free], ud[system.free]
    _, K, Kv = system.residual(x, v, layout=layout)
    K, Kv = (A if layout == "dense" else A.toarray() for A in (K, Kv))
    rng = np.random.default_rng(2)
    e = 1e-6
    for _ in range(3):
        d = rng.normal(size=system.n)
        dR_dx = (system.residual(x + e * d, v, tangent=False)[0]
                 - system.residual(x - e * d, v, tangent=False)[0]) / (2 * e)
        dR_dv = (system.residual(x, v + e * d, tangent=False)[0]
                 - system.residual(x, v - e * d, tangent=False)[0]) / (2 * e)
        assert np.max(np.abs(K @ d - dR_dx)) < 1e-6 * np.max(np.abs(dR_dx))
        assert np.max(np.abs(Kv @ d - dR_dv)) < 1e-6 * np.max(np.abs(dR_dv))


@pytest.mark.parametrize("fast", [True, False])
def test_normal_force_is_continuous_at_touchdown(fast):
    """A node of a straight line above a flat bed, moving into it at 0.3 m/s: the bed
    force on it changes by less than 1e-6 c W v (W = its 10 m share of line length)
    between penetrations -1e-9 and +1e-9 m (MoorDyn's law, onset 0, jumps by c W v), and
    beyond the onset it is the full W (k g - c n.udot)."""
    k, c, onset, v = 1e5, 2e4, 0.01, -0.3  # N/m2, N s/m2, m, m/s
    z = -DEPTH + 1.0
    line = Line.from_polyline(np.linspace([0.0, 0.0, z], [100.0, 0.0, z], 11), CHAIN)
    lines = LineSet([line], law="engineering")
    node = lines.nodal_dofs[5]  # interior: W = 10 m
    ud = np.zeros(lines.ndofs)
    ud[node[2]] = v

    def bed_force(g, bed_onset):  # N, z-component on the node, at penetration g (m)
        bed = Seabed(DEPTH, stiffness=k, damping=c, damping_onset=bed_onset)
        u = np.zeros(lines.ndofs)
        u[node[2]] = bed.penetration(lines.points[5]) - g
        return -(seabed_term(lines, bed) if fast else form_term(lines, bed)).evaluate(u, ud, 0.0, False)[0][node[2]]

    W = 10.0
    assert abs(bed_force(1e-9, onset) - bed_force(-1e-9, onset)) < 1e-6 * c * W * abs(v)
    assert bed_force(1e-9, 0.0) - bed_force(-1e-9, 0.0) == pytest.approx(-c * W * v, rel=1e-6)
    for g in (onset, 2.0 * onset):
        assert bed_force(g, onset) == pytest.approx(W * (k * g - c * v), rel=1e-12)
    assert bed_force(0.5 * onset, onset) == pytest.approx(W * (k - c * v / onset) * 0.5 * onset,
                                                          rel=1e-12)


def laid_length(system, bed, x, s0):
    """FE laid length, m of unstretched line from the anchor: where the suspended part
    lifts off, i.e. where the parabola through its first three nodes past the last node
    in the bed (height above the bed against s0, a catenary near its lowest point) is
    horizontal."""
    lines = system.lines
    u = system.full_displacement(x)
    g = bed.penetration(lines.points + u[lines.nodal_dofs])
    i = np.nonzero(g > 0)[0].max()
    c2, c1, _ = np.polyfit(s0[i + 1:i + 4], -g[i + 1:i + 4], 2)
    return -c1 / (2 * c2)


@pytest.mark.parametrize("shift", [0.0, -5.0, 5.0])
def test_static_touchdown_matches_catenary(shift):
    """Static FE solve with a stiff frictionless bed, reference = the analytic catenary;
    the fairlead then moved 5 m away (-x) or closer (+x) as a prescribed motion and
    compared with the analytic catenary of the moved fairlead (tension +13 % / -9 %,
    laid length -4 % / +3 %): fairlead tension and laid length within 0.5 %."""
    tension, laid, exact = touchdown_solution(shift)
    assert tension == pytest.approx(exact.T_fairlead, rel=5e-3)
    assert laid == pytest.approx(exact.laid_length, rel=5e-3)


def touchdown_solution(shift, nel=150):
    """Static FE solve of the chain on a stiff frictionless bed (0.1 mm penetration), its
    fairlead moved by ``shift`` m along x from the catenary's: (fairlead tension N, laid
    length m, the analytic catenary of the moved fairlead)."""
    lines = LineSet([Line.from_catenary(touchdown(), CHAIN, nel)], law="engineering")
    bed = Seabed(DEPTH, stiffness=CHAIN.weight / 1e-4)
    system = System(lines, fairleads="prescribed", motion=lambda t: [[shift, 0.0, 0.0]],
                    terms=[seabed_term(lines, bed)])
    x = solve_static(system).x
    fairlead, _ = system.reactions(x)
    laid = laid_length(system, bed, x, np.linspace(0.0, LENGTH, nel + 1))
    return float(np.linalg.norm(fairlead[0])), float(laid), touchdown(FAIRLEAD + [shift, 0.0, 0.0])


def parabola_on_plane(a, b, down, length, n):
    """n + 1 points from a to b on a parabola bulging along the unit vector ``down``,
    equally spaced in arclength, whose chords add up to ``length``."""
    t = np.linspace(0.0, 1.0, 4001)[:, None]

    def points(sag):
        curve = a + t * (b - a) + 4 * sag * t * (1 - t) * down
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(curve, axis=0), axis=1))])
        at = np.linspace(0.0, arc[-1], n + 1)
        return np.stack([np.interp(at, arc, curve[:, k]) for k in range(3)], axis=1)

    span = np.linalg.norm(b - a)
    sag = brentq(lambda d: np.linalg.norm(np.diff(points(d), axis=0), axis=1).sum() - length,
                 1e-9 * span, span, xtol=1e-13)
    return points(sag)


def line_along_slope(bed, normal, slope=20.0, span=100.0, length=106.0, nel=40):
    """A line laid along a contour of ``bed``'s slope (deg; ``normal`` its unit normal),
    both ends held on the bed at the rest penetration, solved statically from a
    stress-free parabola. Returns the static node positions, the rest penetration w
    cos(slope) / k (m), the (fairlead, anchor) reactions, the in-plane catenary of weight
    w sin(slope), the end a and the downslope unit vector."""
    alpha = np.radians(slope)
    k, _ = bed.coefficients(LineSet([Line.from_polyline([[0, 0, 0], [1, 0, 0]], CHAIN)]))
    rest = CHAIN.weight * np.cos(alpha) / k  # m: the penetration that carries w cos(slope)
    a = np.array([0.0, 0.0, -DEPTH]) - rest * np.asarray(normal)
    b = a + [span, 0.0, 0.0]
    downslope = -np.array([0.0, np.cos(alpha), np.sin(alpha)])
    line = Line.from_polyline(parabola_on_plane(a, b, downslope, length, nel), CHAIN)
    lines = LineSet([line], law="engineering")
    system = System(lines, fairleads="fixed", terms=[seabed_term(lines, bed)])
    x = solve_static(system, pretension=CHAIN.weight * length).x
    position = lines.points + system.full_displacement(x)[lines.nodal_dofs]
    planar = solve_catenary(np.zeros(3), [span, 0.0, 0.0], CHAIN.weight * np.sin(alpha),
                            CHAIN.EA, length=length)
    return position, rest, system.reactions(x), planar, a, downslope


def test_line_across_a_slope_is_an_in_plane_catenary():
    """A line laid along a contour of a frictionless 20 deg slope, both ends held on the
    bed, from a stress-free parabola: the bed carries w cos(slope) per length normal to
    it, the downslope part w sin(slope) makes an in-plane catenary, whose H and sag
    (skmoor.lines.catenary with weight w sin(slope)) the FE solve matches to 0.2 %."""
    bed = Seabed(DEPTH, slope_deg=20.0, slope_heading_deg=90.0)  # rises towards +y
    position, rest, (fairlead, anchor), planar, a, downslope = line_along_slope(bed, bed.normal)
    assert bed.penetration(position[1:-1]) == pytest.approx(rest, rel=1e-6)
    assert -fairlead[0][0] == pytest.approx(planar.H, rel=2e-3)
    assert anchor[0][0] == pytest.approx(planar.H, rel=2e-3)
    sag = (position[len(position) // 2] - a) @ downslope
    assert sag == pytest.approx(planar.sag(), rel=2e-3)


def drag(direction, mu_axial, mu_lateral, stretch, t_end):
    """A 100 m line lying straight on a flat bed (at its rest penetration), anchor fixed,
    pre-stretched by ``stretch`` m, its far end then dragged along ``direction`` at
    0.2 m/s (reached smoothly over 2 s). Returns the drag force at t_end (the pull on
    the dragged end plus the anchor's, along the direction, N) and the sliding laid
    length (the anchor node's half element does not slide), m."""
    length, nel, speed, ramp = 100.0, 20, 0.2, 2.0
    bed = Seabed(DEPTH, mu_axial=mu_axial, mu_lateral=mu_lateral)
    z = -DEPTH - DEFAULT_PENETRATION  # the default stiffness carries w at 1 mm
    line = Line.from_polyline(np.linspace([0.0, 0.0, z], [length, 0.0, z], nel + 1), CHAIN)
    lines = LineSet([line], law="engineering")
    direction = np.array([*direction, 0.0])

    def moved(t):  # velocity speed (1 - cos(pi t / ramp)) / 2, then speed
        if t < ramp:
            return speed * (t / 2 - ramp / (2 * np.pi) * np.sin(np.pi * t / ramp))
        return speed * (t - ramp / 2)

    system = System(lines, fairleads="prescribed", terms=[seabed_term(lines, bed)],
                    motion=lambda t: [[stretch, 0.0, 0.0] + moved(t) * direction])
    x0 = solve_static(system, pretension=1e5).x
    for state in integrate(system, x0, np.zeros(system.n), 0.02, t_end,
                           scheme=Scheme.generalized_alpha(0.5)):
        pass
    fairlead, anchor = system.reactions(state.x, state.v, state.t)
    return -(fairlead[0] + anchor[0]) @ direction, length - 0.5 * length / nel


@pytest.mark.parametrize("mu_lateral", [0.9, 0.0])
def test_axial_drag_needs_mu_axial_w_laid_length(mu_lateral):
    """Dragged along itself (all of it slides, the speed growing from the anchor), the line
    needs mu_axial w L_laid (1 %); the lateral coefficient plays no part, none at all
    included (a bed with axial friction alone still has friction)."""
    force, laid = drag([1.0, 0.0], mu_axial=0.3, mu_lateral=mu_lateral, stretch=0.01,
                       t_end=4.0)
    assert force == pytest.approx(0.3 * CHAIN.weight * laid, rel=1e-2)


def test_lateral_drag_needs_mu_lateral_w_laid_length():
    """Taut (1 % stretch) and swung sideways about its anchor (every point moving across
    the line), the line needs mu_lateral w L_laid (1 %); the axial coefficient plays no
    part."""
    force, laid = drag([0.0, 1.0], mu_axial=0.1, mu_lateral=0.8, stretch=1.0, t_end=6.0)
    assert force == pytest.approx(0.8 * CHAIN.weight * laid, rel=1e-2)


def test_default_bed_damping_is_critical_for_a_laid_line():
    """The default damping is critical (docstring: 2 sqrt(k m)): a straight chain laid
    flat, sunk twice its static penetration (past the damping's onset), has the total
    normal stiffness k_z and damping c_z of the assembled kernel such that the heave of
    the laid line as a mass-spring-damper, m L z'' + c_z z' + k_z z = 0, has damping ratio
    c_z / (2 sqrt(k_z m L)) = 1, with m the chain's mass per length; and k_z = w L / 1 mm.
    Fails on a halved (ratio 0.5) or doubled default."""
    L, n = 40.0, 20
    w, mass = CHAIN.weight, CHAIN.mass
    z = -DEPTH - 2.0 * DEFAULT_PENETRATION
    X = np.c_[np.linspace(0.0, L, n + 1), np.zeros(n + 1), np.full(n + 1, z)]
    lines = LineSet([Line.from_polyline(X, CHAIN)])
    bed = Seabed(DEPTH)
    u = np.zeros(lines.ndofs)
    _, K, Kv = seabed_term(lines, bed).evaluate(u, u, 0.0, True)
    K, Kv = (np.asarray(A.toarray() if hasattr(A, "toarray") else A) for A in (K, Kv))
    zdofs = lines.nodal_dofs[:, 2]
    k_z = K[np.ix_(zdofs, zdofs)].sum()
    c_z = Kv[np.ix_(zdofs, zdofs)].sum()
    assert k_z == pytest.approx(w * L / 1e-3, rel=1e-9)
    assert c_z / (2.0 * np.sqrt(k_z * mass * L)) == pytest.approx(1.0, rel=1e-9)


def test_default_damping_onset_is_a_tenth_of_the_static_penetration():
    """Without damping_onset the damping fades in over a tenth of the largest static
    penetration w / k (w the line's submerged weight per length, k the bed's stiffness per
    length): the kernel and the forms both take it, and a node moving into the bed at half
    that depth is damped by c (g / onset) n.udot over its share of the line."""
    lines = LineSet([Line.from_catenary(touchdown(), CHAIN, 16)], law="engineering")
    bed = Seabed(DEPTH, damping=3e4)
    k, c = (values[0] for values in bed.cell_coefficients(lines))
    onset = 0.1 * CHAIN.weight / k
    assert bed.onset(lines) == pytest.approx(onset, rel=1e-12)
    node = int(np.argmin(np.abs(lines.points[:, 0] - 200.0)))  # on the bed
    z = lines.nodal_dofs[node][2]
    share = 0.5 * sum(np.linalg.norm(lines.points[node + side] - lines.points[node])
                      for side in (-1, 1))  # m of line at the node (nodal quadrature)
    u, ud = np.zeros(lines.ndofs), np.zeros(lines.ndofs)
    u[z] = lines.points[node, 2] + DEPTH - 0.5 * onset  # its node half the onset deep
    ud[z] = -0.2  # moving down, m/s
    for term in (seabed_term(lines, bed), form_term(lines, bed)):
        moving = term.evaluate(u, ud, 0.0, False)[0][z]
        resting = term.evaluate(u, 0 * ud, 0.0, False)[0][z]
        assert moving - resting == pytest.approx(-c * share * 0.5 * 0.2, rel=1e-9)
