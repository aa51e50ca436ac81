"""The analytic catenary (skmoor.lines.catenary) against numbers worked by hand, beside
test_catenary.py and test_catenary_limits.py: the elastic catenary's end offsets (Irvine:
x = H [asinh(V_F / H) - asinh(V_A / H)] / w + H L / EA, z = (T_F - T_A) / w +
(V_A L + w L^2 / 2) / EA; with a laid part L_b = -v / w carrying H, x = L_b + H asinh(V_F /
H) / w + H L / EA, z = (T_F - H) / w + V_F^2 / (2 w EA)) checked by MoorPy, the Newton
Jacobian of those offsets against central differences, and Newton converging on its own
(hand offsets, MoorPy) on steep, stretched and slack lines; a vertical line hanging down
from its anchor (V_A = (L - D) EA / L - w L / 2 from D = L - int V ds / EA) and one
standing on the seabed, which take no H and no sag ratio; the laid part appearing
continuously as the line lengthens past the length whose lowest point just reaches the
seabed; the longest taut line on a bed (hanging part h with h + w h^2 / (2 EA) = rise, or
h + int_0^{w h} e(T) dT / w = rise on a tension-strain table); a level taut line given H
(L from span = 2 H asinh(w L / 2 H) / w + H L / EA); the sag-ratio limits span / (2 |rise|)
and min(span / rise, rise / span) / 2, a ratio at the limit refused, large ratios and
stretchy lines meeting theirs (measured on the sampled profile); the Peyrot-Goulois first
guess H = w X / (2 lambda), lambda = sqrt(3 ((L^2 - Z^2) / X^2 - 1)) or 0.2 when L <=
chord; a line too weak for its weight (w chord / (2 EA) >= 2 forces a strain of 1: e (1 +
e) >= w chord / (2 EA)); a line on a three-slope table stretching by the table's strain
(profile slope (1 + e(T)) t by central differences, stretched length); the named linear
laws giving the line of EA; the seabed's checks (a line dipping below it within its first
metre, an anchor within the tolerance below it, a fairlead on or below it)."""
import math

import numpy as np
import pytest
from moorpy.Catenary import catenary as moorpy_catenary
from scipy.integrate import quad
from test_catenary import measured_sag_ratio

from skmoor import laws
from skmoor.lines.catenary import (
    _horizontal_tension_guess,
    _linear_offsets_and_jacobian,
    _Problem,
    solve_catenary,
)


def suspended_offsets(L, H, VA, w, EA):
    """Span and rise (m) of a fully suspended elastic catenary, by hand."""
    VF = VA + w * L
    x = H / w * (math.asinh(VF / H) - math.asinh(VA / H)) + H * L / EA
    z = (math.hypot(H, VF) - math.hypot(H, VA)) / w + (VA * L + 0.5 * w * L * L) / EA
    return x, z


def laid_offsets(L, H, laid, w, EA):
    """Span and rise (m) of a line lying straight on the bed for `laid` m (tension H), then
    hanging from the touchdown point where its vertical tension is zero, by hand."""
    VF = w * (L - laid)
    x = laid + H / w * math.asinh(VF / H) + H * L / EA
    z = (math.hypot(H, VF) - H) / w + VF * VF / (2 * w * EA)
    return x, z


def moorpy_anchor_force(x, z, L, EA, w, touchdown):
    fAH, fAV, _, _, info = moorpy_catenary(x, z, L, EA, w, CB=0.0 if touchdown else -1e4,
                                           Tol=1e-12, MaxIter=500)
    return fAH, fAV, info["LBot"]


# (L, H, v, w, EA): v as in _Problem.split, EA low enough that H L / EA matters
OFFSET_CASES = [
    (100.0, 5e3, -2e3, 100.0, 1e6),  # suspended, dipping below the anchor
    (100.0, 5e3, 3e3, 100.0, 1e6),  # suspended, pulled up at the anchor
    (120.0, 8e3, -5e3, 100.0, 2e6),  # laid over 50 m (with touchdown)
]


@pytest.mark.parametrize("L, H, v, w, EA", OFFSET_CASES)
def test_newton_offsets_are_the_elastic_catenary_s_and_moorpy_s(L, H, v, w, EA):
    """The end offsets the Newton fast path uses are the hand formulas, and MoorPy given
    those offsets finds the same H and anchor force (and laid length)."""
    touchdown = v < 0 and L > 110.0
    x, z, _ = _linear_offsets_and_jacobian(L, H, v, w, 1.0 / EA, touchdown)
    expected = laid_offsets(L, H, -v / w, w, EA) if touchdown else \
        suspended_offsets(L, H, v, w, EA)
    assert (x, z) == pytest.approx(expected, rel=1e-13)
    fAH, fAV, laid = moorpy_anchor_force(x, z, L, EA, w, touchdown)
    assert fAH == pytest.approx(H, rel=1e-8)
    assert fAV == pytest.approx(0.0 if touchdown else v, abs=1e-8 * H)
    assert laid == pytest.approx(-v / w if touchdown else 0.0, abs=1e-8 * L)


@pytest.mark.parametrize("L, H, v, w, EA", OFFSET_CASES)
def test_newton_jacobian_is_the_central_difference_of_the_offsets(L, H, v, w, EA):
    """[[x_H, x_v], [z_H, z_v]] in closed form against central differences, stretch terms
    (H L / EA in x, v L / EA or V_F^2 / (2 w EA) in z) included."""
    touchdown = v < 0 and L > 110.0
    c = 1.0 / EA
    _, _, J = _linear_offsets_and_jacobian(L, H, v, w, c, touchdown)
    dH, dv = 1e-4 * H, 1e-4 * H

    def offsets(H, v):
        return np.array(_linear_offsets_and_jacobian(L, H, v, w, c, touchdown)[:2])

    by_H = (offsets(H + dH, v) - offsets(H - dH, v)) / (2 * dH)
    by_v = (offsets(H, v + dv) - offsets(H, v - dv)) / (2 * dv)
    np.testing.assert_allclose(np.array(J), np.column_stack([by_H, by_v]), rtol=1e-6,
                               atol=1e-9 * np.abs(np.array(J)).max())
    assert c * L > 1e-3 * np.abs(np.array(J)).max()  # the stretch terms are resolved


@pytest.mark.parametrize("D, L, w, EA", [(50.0, 49.9, 100.0, 1e7), (0.6, 0.5, 0.5, 10.0),
                                         (30.0, 25.0, 2.0, 200.0)])
def test_vertical_line_hanging_down_from_its_anchor(D, L, w, EA):
    """Fairlead D below the anchor, L < D: the line hangs straight, its vertical tension
    V_A + w s negative all along, so its stretched length is L - (V_A L + w L^2 / 2) / EA
    = D, which gives V_A; the fairlead is pulled down by the rest."""
    line = solve_catenary([1.0, 2.0, 0.0], [1.0, 2.0, -D], w, EA, length=L)
    VA = (L - D) * EA / L - 0.5 * w * L
    assert line.H == 0.0 and line.laid_length == 0.0
    assert line.V_anchor == pytest.approx(VA, rel=1e-12)
    assert line.V_fairlead == pytest.approx(VA + w * L, rel=1e-12)
    assert line.V_fairlead < 0.0
    s = np.linspace(0.0, L, 11)
    stretched = s - (VA * s + 0.5 * w * s * s) / EA
    np.testing.assert_allclose(line.position(s)[:, 2], -stretched, rtol=0, atol=1e-12 * D)
    np.testing.assert_allclose(line.stretched_arclength(s), stretched, rtol=1e-12)


@pytest.mark.parametrize("D, L, w, EA", [(50.0, 49.9, 100.0, 1e7), (0.6, 0.5, 0.5, 10.0)])
def test_vertical_line_standing_on_the_seabed(D, L, w, EA):
    """Anchor on the seabed, fairlead D straight above, L < D: nothing lies on the bed and
    D = L + (V_A L + w L^2 / 2) / EA gives V_A = (D - L) EA / L - w L / 2."""
    line = solve_catenary([0.0, 0.0, -D], [0.0, 0.0, 0.0], w, EA, length=L, seabed_z=-D)
    assert line.H == 0.0 and line.laid_length == 0.0
    assert line.V_anchor == pytest.approx((D - L) * EA / L - 0.5 * w * L, rel=1e-12)


def test_laid_part_appears_continuously_past_the_touchdown_length():
    """Built by hand from its vertex at the anchor (V_A = 0, H = 2e5 N), the line of length
    L* just touches the seabed there. A line 0.5 N of anchor pull short of it (V_A = 0.5 N,
    hand offsets) lies nowhere on the bed; longer lines lay a part whose length grows from
    zero while V_A stays 0, with H and V_A - w L_b continuous through L*."""
    w, EA, H, L_star = 1000.0, 5e8, 2e5, 300.0
    x, z = laid_offsets(L_star, H, 0.0, w, EA)
    anchor, fairlead = [0.0, 0.0, -z], [x, 0.0, 0.0]
    at = solve_catenary(anchor, fairlead, w, EA, length=L_star, seabed_z=-z)
    assert at.H == pytest.approx(H, rel=1e-9)
    assert abs(at.V_anchor) < 1e-6 * H and at.laid_length < 1e-6 * L_star

    # the same span and rise reached with V_A = 0.5 N: a slightly shorter line
    VA = 0.5
    xs, zs = suspended_offsets(L_star, H, VA, w, EA)
    short = solve_catenary([0.0, 0.0, -zs], [xs, 0.0, 0.0], w, EA, length=L_star,
                           seabed_z=-zs)
    assert short.laid_length == 0.0
    assert short.V_anchor == pytest.approx(VA, rel=1e-6)
    assert short.H == pytest.approx(H, rel=1e-9)

    # v = V_A - w L_b runs smoothly through L*: the laid length a little longer line lays
    # is the V_A / w a little shorter one loses
    dL = 1e-3
    longer = solve_catenary(anchor, fairlead, w, EA, length=L_star + dL, seabed_z=-z)
    shorter = solve_catenary(anchor, fairlead, w, EA, length=L_star - dL, seabed_z=-z)
    assert longer.V_anchor == 0.0 and longer.laid_length > 0.0
    assert shorter.laid_length == 0.0 and shorter.V_anchor > 0.0
    assert longer.laid_length == pytest.approx(shorter.V_anchor / w, rel=1e-3)
    for near in (longer, shorter):
        assert near.H == pytest.approx(H, rel=1e-4)


def test_longest_taut_line_on_a_bed_hangs_its_stretched_height():
    """A stretchy line (2 w rise / EA = 1): the longest taut line is laid along the span and
    hangs h with h + w h^2 / (2 EA) = rise (h = 2 rise / (1 + sqrt 2) here); a line just
    shorter is solved (and nearly all laid), the L-shape itself and longer lines are refused
    as slack."""
    w, EA, span, rise = 1000.0, 2e5, 300.0, 100.0
    problem = _Problem.between(np.array([0.0, 0.0, -rise]), np.array([span, 0.0, 0.0]), w,
                               EA, True)
    h = problem.longest_length() - span
    assert h + w * h * h / (2 * EA) == pytest.approx(rise, rel=1e-13)
    assert h == pytest.approx(2 * rise / (1 + math.sqrt(2.0)), rel=1e-13)
    line = solve_catenary([0.0, 0.0, -rise], [span, 0.0, 0.0], w, EA, length=span + h - 1e-3,
                          seabed_z=-rise)
    assert line.laid_length == pytest.approx(span, abs=0.01)
    assert line.V_fairlead == pytest.approx(w * h, rel=1e-3)
    for slack in (problem.longest_length(), span + h + 1e-3):  # the L-shape, and longer
        with pytest.raises(ValueError, match="^length:"):
            solve_catenary([0.0, 0.0, -rise], [span, 0.0, 0.0], w, EA, length=slack,
                           seabed_z=-rise)


def test_level_taut_line_given_its_horizontal_tension():
    """Level ends, H = 5 kN, w = 1 N/m, EA = 1 MN: the 100 m line spans
    2 H asinh(w L / 2 H) / w + H L / EA (its stretch, 0.5 m, outgrows its sag), with
    V_A = -w L / 2; given H, the solve finds L = 100 m back."""
    w, EA, H, L = 1.0, 1e6, 5e3, 100.0
    span = 2 * H / w * math.asinh(w * L / (2 * H)) + H * L / EA
    assert span > L
    line = solve_catenary([0.0, 0.0, -10.0], [span, 0.0, -10.0], w, EA,
                          horizontal_tension=H)
    assert line.L == pytest.approx(L, rel=1e-12)
    assert line.V_anchor == pytest.approx(-0.5 * w * L, rel=1e-9)
    assert line.V_fairlead == pytest.approx(0.5 * w * L, rel=1e-9)


@pytest.mark.parametrize("anchor, fairlead, touchdown, limit", [
    ([0.0, 0.0, -100.0], [20.0, 0.0, 0.0], False, 0.1),  # span / (2 rise)
    ([0.0, 0.0, 0.0], [30.0, 40.0, -200.0], False, 0.125),  # span / (2 |rise|), rise < 0
    ([0.0, 0.0, -10.0], [100.0, 0.0, -10.0], False, math.inf),  # level: no limit
    ([0.0, 0.0, -20.0], [60.0, 80.0, 0.0], True, 0.1),  # rise / (2 span)
    ([0.0, 0.0, -300.0], [60.0, 80.0, 0.0], True, 1 / 6),  # span / (2 rise)
])
def test_sag_ratio_limit_of_the_vertical_branches_or_the_l_shape(anchor, fairlead,
                                                                 touchdown, limit):
    problem = _Problem.between(np.array(anchor), np.array(fairlead), 100.0, 1e9, touchdown)
    assert problem.sag_ratio_limit() == pytest.approx(limit, rel=1e-15)


def test_sag_ratio_at_the_limit_is_refused():
    """On a flat bed (span 100 m, rise 20 m) the limit rise / (2 span) = 0.1 is approached by
    ever longer lines but never reached."""
    with pytest.raises(ValueError, match="^sag_ratio:"):
        solve_catenary([0.0, 0.0, -20.0], [100.0, 0.0, 0.0], 100.0, 1e9, sag_ratio=0.1,
                       seabed_z=-20.0)


def test_large_sag_ratio_on_a_bed_at_45_degrees():
    """Span = rise = 100 m on a bed: limit 1/2; a sag of 0.45 chord needs a line longer
    than the parabola's estimate would allow below the L-shape (span + rise), and is met."""
    anchor, fairlead = [0.0, 0.0, -100.0], [100.0, 0.0, 0.0]
    line = solve_catenary(anchor, fairlead, 1000.0, 1e9, sag_ratio=0.45, seabed_z=-100.0)
    chord = math.hypot(100.0, 100.0)
    assert line.sag() / chord == pytest.approx(0.45, rel=1e-9)
    assert chord < line.L < 200.0 and line.laid_length > 0.0


@pytest.mark.parametrize("L, X, Z, lam", [
    (5.0, 3.0, 4.0, 0.2),  # L = chord: taut, the fixed 0.2
    (4.0, 3.0, 4.0, 0.2),  # shorter than the chord
    (6.0, 3.0, 4.0, math.sqrt(3 * ((36 - 16) / 9 - 1))),
    (150.0, 100.0, -50.0, math.sqrt(3 * ((150**2 - 50**2) / 100**2 - 1))),
])
def test_first_guess_of_the_horizontal_tension_is_peyrot_goulois(L, X, Z, lam):
    w = 300.0
    problem = _Problem.between(np.zeros(3), np.array([X, 0.0, Z]), w, 1e9, False)
    assert _horizontal_tension_guess(problem, L) == pytest.approx(0.5 * w * X / lam,
                                                                  rel=1e-14)


@pytest.mark.parametrize("given, value", [("sag_ratio", 0.02), ("sag_ratio", 0.3),
                                          ("sag_ratio", 0.45), ("length", 100.0),
                                          ("horizontal_tension", 1e3)])
def test_line_too_weak_for_its_own_weight_is_refused(given, value):
    """EA = w chord / 4: the ends' vertical forces carry w L, so the largest tension is at
    least w L / 2 and the strain e there at least w L / (2 EA); spanning the chord needs
    L (1 + e) >= chord, so e (1 + e) >= w chord / (2 EA) = 2 and e >= 1: no line exists."""
    anchor, fairlead, w = [0.0, 0.0, -50.0], [80.0, 0.0, 0.0], 200.0
    EA = w * math.hypot(80.0, 50.0) / 4
    with pytest.raises(ValueError, match=f"^{given}:"):
        solve_catenary(anchor, fairlead, w, EA, **{given: value})


def test_suspended_line_dipping_below_the_seabed_within_its_first_metre():
    """Anchor 5 mm above the seabed (so not on it), the lowest point 0.9 m along the line
    (V_A = -0.9 w): with H = 10 kN it lies about w s^2 / (2 H) = 40 mm below the anchor,
    35 mm into the seabed, and the line is refused; a seabed at the lowest point's height
    only touches it."""
    w, EA, H, L = 1000.0, 1e9, 1e4, 50.0
    VA = -0.9 * w
    x, z = suspended_offsets(L, H, VA, w, EA)
    dip = (math.hypot(H, VA) - H) / w  # rigid sag of the first 0.9 m, by hand
    assert dip == pytest.approx(w * 0.81 / (2 * H), rel=1e-2)
    anchor = [0.0, 0.0, -100.0 + 0.005]
    fairlead = [x, 0.0, anchor[2] + z]
    free = solve_catenary(anchor, fairlead, w, EA, length=L)
    assert free.V_anchor == pytest.approx(VA, rel=1e-6)
    with pytest.raises(ValueError, match="^seabed_z:"):
        solve_catenary(anchor, fairlead, w, EA, length=L, seabed_z=-100.0)
    lowest = float(free.position([-free.V_anchor / w])[0, 2])
    assert lowest == pytest.approx(anchor[2] - dip, abs=1e-6)
    touching = solve_catenary(anchor, fairlead, w, EA, length=L, seabed_z=lowest)
    assert touching.V_anchor == free.V_anchor  # touching the seabed is not dipping below


@pytest.mark.parametrize("span, rise, w, EA, L", [
    (10.0, -250.0, 500.0, 4e5, 250.0),  # hanging down, steep, stretched 29 %
    (10.0, 120.0, 500.0, 1e8, 205.0),  # steep, slack
    (200.0, -25.0, 500.0, 4e5, 343.0),  # slack, stretched 23 %
    (10.0, -120.0, 50.0, 2e6, 205.0),  # hanging down, slack
    (50.0, 250.0, 50.0, 4e5, 306.0),  # steep, stretched
])
def test_newton_converges_on_its_own_on_steep_stretched_and_slack_lines(span, rise, w, EA,
                                                                        L):
    """From the Peyrot-Goulois start (halving a step that would make H negative), Newton
    on both end offsets converges without the fallback; the hand offsets of its (H, V_A)
    are the span and rise, and MoorPy finds the same forces."""
    problem = _Problem.between(np.zeros(3), np.array([span, 0.0, rise]), w, EA, False)
    solved = problem._newton_length(L, _horizontal_tension_guess(problem, L))
    assert solved is not None
    H, VA = solved
    assert suspended_offsets(L, H, VA, w, EA) == pytest.approx((span, rise), rel=1e-12,
                                                               abs=1e-12 * L)
    fAH, fAV, _ = moorpy_anchor_force(span, rise, L, EA, w, False)
    assert (H, VA) == pytest.approx((fAH, fAV), rel=1e-9)


# a tension-strain table (MoorDyn's curve): slopes 1.2e7, 4e6 and 1e7 N between its points
CURVE_STRAIN, CURVE_TENSION = [0.01, 0.03, 0.05], [1.2e5, 2e5, 4e5]


def curve_strain(T):
    """The table's strain at tension T, by linear interpolation (the last slope beyond)."""
    return np.interp(T, [0.0, *CURVE_TENSION], [0.0, *CURVE_STRAIN])


@pytest.mark.parametrize("anchor, fairlead, L, seabed_z", [
    ([0.0, 0.0, -100.0], [300.0, 0.0, 0.0], 330.0, -100.0),  # laid part at H
    ([0.0, 0.0, -20.0], [150.0, 0.0, 0.0], 165.0, None),  # dips below the anchor
    ([0.0, 0.0, 0.0], [120.0, 0.0, -150.0], 195.0, None),  # fairlead below, V < 0 at both
])
def test_curve_law_profile_stretches_by_the_table_s_strain(anchor, fairlead, L, seabed_z):
    """A line on a three-slope tension-strain table whose tensions cross its kinks: the
    profile's slope is (1 + e(T)) times the unit tangent (central differences, e from the
    table by hand), at the lowest point too (horizontal, 1 + e(H) long), the stretched
    arclength grows at 1 + e(T) and is the length of the profile, and the profile ends at
    the fairlead."""
    law = laws.Curve(CURVE_STRAIN, CURVE_TENSION)
    w = 1000.0
    line = solve_catenary(anchor, fairlead, w, 5e7, length=L, seabed_z=seabed_z, law=law)
    tensions = line.tension(np.linspace(0.0, L, 101))
    assert any(tensions.min() < kink < tensions.max() for kink in CURVE_TENSION)
    np.testing.assert_allclose(line.position([L])[0], fairlead, rtol=0, atol=1e-9 * L)
    s = np.linspace(0.01, 0.99, 60) * L
    s = s[np.abs(s - line.laid_length) > 1e-3 * L]
    h = 1e-5 * L
    slope = (line.position(s + h) - line.position(s - h)) / (2 * h)
    stretch = 1.0 + curve_strain(line.tension(s))
    np.testing.assert_allclose(slope, stretch[:, None] * line.tangent(s), rtol=0, atol=1e-7)
    rate = (line.stretched_arclength(s + h) - line.stretched_arclength(s - h)) / (2 * h)
    np.testing.assert_allclose(rate, stretch, rtol=1e-7)
    fine = np.linspace(0.0, L, 20001)
    polyline = np.sum(np.linalg.norm(np.diff(line.position(fine), axis=0), axis=1))
    assert line.stretched_arclength([L])[0] == pytest.approx(polyline, rel=1e-8)
    np.testing.assert_allclose(line.strain(line.tension(s)), stretch - 1.0, rtol=1e-12)
    s_low = -line.V_anchor / line.w  # the lowest point, where V = 0 and T = H
    if 0.0 < s_low < L:
        h = 1e-4  # m: 0.1 N of vertical tension either side
        slope = (line.position([s_low + h]) - line.position([s_low - h]))[0] / (2 * h)
        expected = (1.0 + curve_strain(line.H)) * line.direction
        np.testing.assert_allclose(slope, expected, rtol=0, atol=1e-8)


@pytest.mark.parametrize("span, rise, EA, ratio, seabed", [
    (80.0, 50.0, 1e4, 0.3, True),  # stretched 40 %, on a bed
    (50.0, -30.0, 1e4, 0.15, False),  # stretched, fairlead below: shorter than the chord
    (80.0, 50.0, 1e5, 0.05, False),
    (300.0, 100.0, 1e5, 0.45, False),
])
def test_sag_ratio_of_a_stretchy_line_is_met(span, rise, EA, ratio, seabed):
    """Lines whose stretch moves them far from the inextensible parabola's length
    l (1 + 8/3 (d/l)^2): the sag ratio measured on the sampled profile is the one asked."""
    anchor = [0.0, 0.0, -max(rise, 0.0)]
    fairlead = [span, 0.0, anchor[2] + rise]
    line = solve_catenary(anchor, fairlead, 200.0, EA, sag_ratio=ratio,
                          seabed_z=anchor[2] if seabed else None)
    assert measured_sag_ratio(line) == pytest.approx(ratio, rel=1e-6)
    assert (line.laid_length > 0.0) == seabed
    assert line.strain(max(line.T_anchor, line.T_fairlead)) < 1.0


def test_longest_taut_line_on_a_table_hangs_its_stretched_height():
    """On the three-slope table, the longest taut line on a bed hangs h with
    h + int_0^{w h} e(T) dT / w = rise (its top tension 1.5e5 N past the first kink; the
    integral of the interpolated table by quadrature); that L-shaped line itself is refused
    as slack, one 1 cm shorter is solved."""
    law = laws.Curve(CURVE_STRAIN, CURVE_TENSION)
    w, span, rise = 1000.0, 200.0, 150.0
    problem = _Problem.between(np.array([0.0, 0.0, -rise]), np.array([span, 0.0, 0.0]), w,
                               5e7, True, law)
    h = problem.longest_length() - span
    assert w * h > CURVE_TENSION[0]
    stretch, _ = quad(curve_strain, 0.0, w * h, points=CURVE_TENSION[:1], epsabs=1e-12)
    assert h + stretch / w == pytest.approx(rise, rel=1e-12)
    anchor, fairlead = [0.0, 0.0, -rise], [span, 0.0, 0.0]
    with pytest.raises(ValueError, match="^length:"):
        solve_catenary(anchor, fairlead, w, 5e7, length=problem.longest_length(),
                       seabed_z=-rise, law=law)
    line = solve_catenary(anchor, fairlead, w, 5e7, length=span + h - 0.01, seabed_z=-rise,
                          law=law)
    assert line.laid_length == pytest.approx(span, abs=0.5)


@pytest.mark.parametrize("law", ["engineering", "paper"])
def test_named_linear_laws_give_the_line_of_ea(law):
    """'engineering' and 'paper' both have tension = EA x engineering strain in statics:
    the line is the one without a law (end forces, laid length)."""
    args = ([0.0, 0.0, -100.0], [300.0, 0.0, 0.0], 1000.0, 5e8)
    named = solve_catenary(*args, length=350.0, seabed_z=-100.0, law=law)
    plain = solve_catenary(*args, length=350.0, seabed_z=-100.0)
    assert (named.H, named.V_fairlead, named.laid_length) == pytest.approx(
        (plain.H, plain.V_fairlead, plain.laid_length), rel=1e-12)


def test_anchor_within_the_tolerance_below_the_seabed_lies_on_it():
    """The anchor 1e-7 m below the seabed, within 1e-9 of the chord (300 m; the depth and
    the ends' mean height are near zero), counts as on the seabed: the line is the one
    anchored on it exactly; a millimetre below is refused, naming the anchor."""
    args = ([150.0, 0.0, 10.0], 1000.0, 5e8)
    on = solve_catenary([-150.0, 0.0, -10.0], *args, length=310.0, seabed_z=-10.0)
    near = solve_catenary([-150.0, 0.0, -10.0 - 1e-7], *args, length=310.0, seabed_z=-10.0)
    assert on.laid_length > 0.0
    assert (near.H, near.laid_length) == pytest.approx((on.H, on.laid_length), rel=1e-5)
    with pytest.raises(ValueError, match="^anchor:"):
        solve_catenary([-150.0, 0.0, -10.001], *args, length=310.0, seabed_z=-10.0)


@pytest.mark.parametrize("fairlead_z", [-50.0, -60.0])
def test_fairlead_on_or_below_the_seabed_is_refused(fairlead_z):
    """Touchdown is modelled at the anchor only: a fairlead on the seabed, or below it, is
    an error naming the fairlead."""
    with pytest.raises(ValueError, match="^fairlead:"):
        solve_catenary([0.0, 0.0, -20.0], [100.0, 0.0, fairlead_z], 100.0, 1e8,
                       length=120.0, seabed_z=-50.0)


def test_unknown_law_name_is_refused_naming_the_law():
    with pytest.raises(ValueError, match="^law:"):
        solve_catenary([0.0, 0.0, -50.0], [80.0, 0.0, 0.0], 200.0, 1e8, length=100.0,
                       law="rubber")


def test_sag_near_the_branch_limit_needs_a_line_too_long_for_its_stiffness():
    """Span 20 m, rise 100 m: the sag ratio limit is 0.1, approached by ever longer lines
    (11 km of nearly inextensible line for 0.0999). With EA = 1e5 N and w = 200 N/m, 500 m
    of hanging line already reach a strain of 1: 0.09 is met, 0.0999 is refused."""
    anchor, fairlead, w, EA = [0.0, 0.0, -100.0], [20.0, 0.0, 0.0], 200.0, 1e5
    line = solve_catenary(anchor, fairlead, w, EA, sag_ratio=0.09)
    assert measured_sag_ratio(line) == pytest.approx(0.09, rel=1e-6)
    with pytest.raises(ValueError, match="^sag_ratio:"):
        solve_catenary(anchor, fairlead, w, EA, sag_ratio=0.0999)


@pytest.mark.parametrize("given, value", [("horizontal_tension", 1e3), ("sag_ratio", 0.1)])
def test_vertical_line_takes_only_its_length(given, value):
    """Fairlead straight above the anchor: H = 0 and there is no sag to ask for; giving
    either is an error naming it."""
    with pytest.raises(ValueError, match=f"^{given}:"):
        solve_catenary([3.0, 4.0, -100.0], [3.0, 4.0, 0.0], 100.0, 1e7, **{given: value})
