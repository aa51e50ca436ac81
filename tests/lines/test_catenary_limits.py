"""The analytic catenary (skmoor.lines.catenary) at the edges of its solves, against MoorPy
and geometry: a piecewise law that is linear over the line's tensions gives MoorPy's
linear line (laid part included), a taut line hanging downwards from its anchor, a nearly
vertical line (H below 1 N) still reaching its fairlead, the sag unchanged by a horizontal
shift, the documented sag-ratio limits, and a suspended line above a far seabed."""
import math

import numpy as np
import pytest
from moorpy.Catenary import catenary as moorpy_catenary

from skmoor import laws
from skmoor.lines.catenary import _horizontal_tension_guess, _Problem, solve_catenary


def moorpy_line(span, rise, L, EA, w, touchdown):
    """MoorPy's (H_anchor, V_anchor, H_fairlead, V_fairlead, laid length)."""
    fAH, fAV, fBH, fBV, info = moorpy_catenary(span, rise, L, EA, w, CB=0.0 if touchdown
                                               else -1e4, Tol=1e-10, MaxIter=500)
    return np.array([fAH, fAV, fBH, fBV]), info["LBot"]


def our_forces(line):
    return np.array([line.anchor_force() @ line.direction, line.anchor_force()[2],
                     line.fairlead_force() @ line.direction, line.fairlead_force()[2]])


@pytest.mark.parametrize("L", [330.0, 340.0])
def test_curve_linear_over_the_line_tensions_gives_moorpy_s_linear_line(L):
    """A two-slope tension-strain curve whose kink (5e7 N) lies far above the line's
    tensions takes the piecewise path (its laid part stretched by e(H)); MoorPy's
    linear line with the first slope as EA is the reference (end forces, laid length)."""
    EA, w = 5e8, 1000.0
    curve = laws.Curve([0.1, 0.2], [0.1 * EA, 0.1 * EA + 0.1 * 2e9])
    line = solve_catenary([0.0, 0.0, -100.0], [300.0, 0.0, 0.0], w, EA, length=L,
                          seabed_z=-100.0, law=curve)
    assert line.laid_length > 0 and line.T_fairlead < 0.01 * EA
    forces, laid = moorpy_line(300.0, 100.0, L, EA, w, touchdown=True)
    assert np.allclose(our_forces(line), forces, rtol=1e-8, atol=1e-6 * line.T_fairlead)
    assert line.laid_length == pytest.approx(laid, rel=1e-8)
    linear = solve_catenary([0.0, 0.0, -100.0], [300.0, 0.0, 0.0], w, EA, length=L,
                            seabed_z=-100.0)
    s = np.linspace(0.0, L, 41)
    assert np.allclose(line.position(s), linear.position(s), rtol=0, atol=1e-9 * L)


def test_taut_line_hanging_down_from_its_anchor_matches_moorpy():
    """Fairlead 50 m below the anchor, line 1 % short of the chord: the tension points
    down all along (V_anchor < -w L, outside the laid-line bracket of a seabed line);
    given MoorPy's H instead of L, the solve finds L back."""
    line = solve_catenary([0.0, 0.0, 0.0], [10.0, 0.0, -50.0], 100.0, 1e7, length=50.5)
    assert line.V_anchor < -line.w * line.L
    forces, _ = moorpy_line(10.0, -50.0, 50.5, 1e7, 100.0, touchdown=False)
    assert np.allclose(our_forces(line), forces, rtol=1e-8)
    given_H = solve_catenary([0.0, 0.0, 0.0], [10.0, 0.0, -50.0], 100.0, 1e7,
                             horizontal_tension=forces[0])  # solved for L: the same line
    assert given_H.L == pytest.approx(50.5, rel=1e-9)
    assert given_H.V_anchor == pytest.approx(forces[1], rel=1e-8)


def test_nearly_vertical_line_with_a_small_horizontal_tension_reaches_its_fairlead():
    """1 mm of span over 100 m of rise: H is a fraction of a newton, and the profile,
    H asinh(V / H) / w included, still ends at the fairlead; the horizontal reach is
    H (asinh(V_F / H) - asinh(V_A / H)) / w + H L / EA written out."""
    w, EA, L = 100.0, 1e7, 99.9
    line = solve_catenary([0.0, 0.0, -100.0], [1e-3, 0.0, 0.0], w, EA, length=L)
    assert 0.0 < line.H < 1.0
    end = line.position([L])[0]
    assert np.allclose(end, line.fairlead, rtol=0, atol=1e-12)
    H, VA, VF = line.H, line.V_anchor, line.V_fairlead
    reach = H * (math.asinh(VF / H) - math.asinh(VA / H)) / w + H * L / EA
    assert reach == pytest.approx(1e-3, rel=1e-9)


def test_sag_does_not_change_with_a_horizontal_shift_of_both_ends():
    line = solve_catenary([0.0, 0.0, -50.0], [80.0, 0.0, 0.0], 200.0, 1e8, length=100.0)
    moved = solve_catenary([500.0, -300.0, -50.0], [580.0, -300.0, 0.0], 200.0, 1e8,
                           length=100.0)
    assert moved.sag() == pytest.approx(line.sag(), rel=1e-12)
    assert line.sag() > 1.0


@pytest.mark.parametrize("anchor, fairlead, seabed_z, limit", [
    ([0.0, 0.0, -100.0], [20.0, 0.0, 0.0], None, 0.1),  # steep, hanging: span / (2 rise)
    ([0.0, 0.0, -20.0], [100.0, 0.0, 0.0], -20.0, 0.1),  # flat, on the bed: rise / (2 span)
    ([0.0, 0.0, -100.0], [20.0, 0.0, 0.0], -100.0, 0.1),  # steep, on the bed: span / (2 rise)
])
def test_sag_ratio_limit_is_the_documented_one(anchor, fairlead, seabed_z, limit):
    """A ratio above the limit is refused, one below it is met (the sag measured from
    the profile's mid-chord perpendicular)."""
    w, EA = 100.0, 1e9
    with pytest.raises(ValueError):
        solve_catenary(anchor, fairlead, w, EA, sag_ratio=1.2 * limit, seabed_z=seabed_z)
    line = solve_catenary(anchor, fairlead, w, EA, sag_ratio=0.8 * limit, seabed_z=seabed_z)
    chord = np.linalg.norm(np.subtract(fairlead, anchor))
    assert line.sag() / chord == pytest.approx(0.8 * limit, rel=1e-9)


def test_level_ends_have_no_sag_ratio_limit_below_one_half():
    """Ends at one height: the two vertical branches never meet the mid-chord normal,
    so any ratio below 1/2 has a line."""
    line = solve_catenary([0.0, 0.0, -10.0], [100.0, 0.0, -10.0], 100.0, 1e9,
                          sag_ratio=0.45)
    assert line.sag() / 100.0 == pytest.approx(0.45, rel=1e-9)


def test_one_metre_span_takes_a_horizontal_tension_and_a_sag_ratio():
    """A span of exactly 1 m is not vertical: H and a sag ratio are valid inputs, and
    the line found from H has that H (MoorPy gives the same end forces)."""
    anchor, fairlead = [0.0, 0.0, -0.5], [1.0, 0.0, 0.0]
    line = solve_catenary(anchor, fairlead, 10.0, 1e7, horizontal_tension=40.0)
    assert line.H == pytest.approx(40.0, rel=1e-12)
    forces, _ = moorpy_line(1.0, 0.5, line.L, 1e7, 10.0, touchdown=False)
    assert np.allclose(our_forces(line), forces, rtol=1e-7)
    sagged = solve_catenary(anchor, fairlead, 10.0, 1e7, sag_ratio=0.1)
    assert sagged.sag() / math.hypot(1.0, 0.5) == pytest.approx(0.1, rel=1e-9)


def test_suspended_line_dipping_below_its_anchor_but_above_a_far_seabed_is_accepted():
    """The low point lies inside the line (V_anchor < 0) but 80 m above the seabed: the
    seabed only checks, the line is the one without it."""
    free = solve_catenary([0.0, 0.0, -20.0], [50.0, 0.0, 0.0], 100.0, 1e7, length=120.0)
    assert free.V_anchor < 0
    checked = solve_catenary([0.0, 0.0, -20.0], [50.0, 0.0, 0.0], 100.0, 1e7,
                             length=120.0, seabed_z=-100.0)
    assert np.allclose(our_forces(checked), our_forces(free), rtol=1e-12)
    with pytest.raises(ValueError):
        solve_catenary([0.0, 0.0, -20.0], [50.0, 0.0, 0.0], 100.0, 1e7, length=120.0,
                       seabed_z=-25.0)


# (anchor, fairlead, w, EA, L, touchdown): slack, near taut, dipping below the anchor,
# fairlead below the anchor, laid on the bed (2D and 3D)
NEWTON_CASES = [
    ([0, 0, -50], [80, 0, 0], 200.0, 1e8, 100.0, False),
    ([0, 0, -50], [80, 0, 0], 200.0, 1e8, 94.3, False),
    ([0, 0, -20], [50, 0, 0], 100.0, 1e7, 120.0, False),
    ([5, -3, 0], [45, 27, -30], 100.0, 1e7, 80.0, False),
    ([0, 0, -100], [300, 0, 0], 1000.0, 5e8, 350.0, True),
    ([10, 5, -200], [400, -20, -5], 1500.0, 1e9, 520.0, True),
]


@pytest.mark.parametrize("anchor, fairlead, w, EA, L, touchdown", NEWTON_CASES)
def test_newton_on_both_end_offsets_converges_to_moorpy_s_line(anchor, fairlead, w, EA, L,
                                                               touchdown):
    """The linear law's fast path (Newton on span and rise with the closed-form Jacobian,
    from the Peyrot-Goulois guess, as MoorPy and FAST solve it) converges on its own (no
    fallback to the nested bracketed solves) to MoorPy's H and anchor force."""
    anchor, fairlead = np.array(anchor, float), np.array(fairlead, float)
    problem = _Problem.between(anchor, fairlead, w, EA, touchdown)
    solved = problem._newton_length(L, _horizontal_tension_guess(problem, L))
    assert solved is not None
    H, v = solved
    forces, laid = moorpy_line(problem.span, problem.rise, L, EA, w, touchdown)
    assert H == pytest.approx(forces[0], rel=1e-8)
    V_anchor, laid_length = problem.split(L, v)
    assert V_anchor == pytest.approx(forces[1], rel=1e-8, abs=1e-8 * H)
    assert laid_length == pytest.approx(laid, rel=1e-8, abs=1e-9 * L)


@pytest.mark.parametrize("L", [360.0, 395.0])
def test_curve_reaches_as_long_a_line_as_its_linear_law(L):
    """The longest taut line (laid along the span, then hanging straight up: its hanging
    part h solves h + w h^2 / (2 EA) = rise for a linear law) is the same for a curve that
    is linear over the line's tensions: lines between span + rise / 2 and span + rise are
    solved (their forces and laid length are MoorPy's), longer ones refused as slack."""
    EA, w = 5e8, 1000.0
    curve = laws.Curve([0.1, 0.2], [0.1 * EA, 0.1 * EA + 0.1 * 2e9])
    line = solve_catenary([0.0, 0.0, -100.0], [300.0, 0.0, 0.0], w, EA, length=L,
                          seabed_z=-100.0, law=curve)
    forces, laid = moorpy_line(300.0, 100.0, L, EA, w, touchdown=True)
    assert np.allclose(our_forces(line), forces, rtol=1e-6, atol=1e-6 * line.T_fairlead)
    assert line.laid_length == pytest.approx(laid, rel=1e-6)
    hanging = 2 * 100.0 / (1 + math.sqrt(1 + 2 * w * 100.0 / EA))
    with pytest.raises(ValueError, match="too long"):
        solve_catenary([0.0, 0.0, -100.0], [300.0, 0.0, 0.0], w, EA,
                       length=300.0 + hanging + 0.01, seabed_z=-100.0, law=curve)
