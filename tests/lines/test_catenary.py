"""The analytic elastic catenary against MoorPy, its own differential equations and the paper's resolved case."""
import math

import numpy as np
import pytest
from moorpy.Catenary import catenary as moorpy_catenary
from scipy.optimize import brentq

from skmoor.lines.catenary import solve_catenary

# The paper's case (docs/paper.md): steel line, D = 0.1 m, in water.
G = 9.81
RHO_WATER = 1025.0
AREA = math.pi / 4 * 0.1**2
PAPER_EA = 2e11 * AREA
PAPER_W = (8000.0 - RHO_WATER) * G * AREA
DEPTH = 100.0
THETA = math.radians(50.0)


def paper_line(draft, sag_ratio=1 / 60, EA=PAPER_EA):
    """A line of the paper's case: anchor on the seabed, chord at 50 deg to the fairlead."""
    rise = DEPTH - draft
    return solve_catenary([0.0, 0.0, -DEPTH], [rise / math.tan(THETA), 0.0, -draft],
                          PAPER_W, EA, sag_ratio=sag_ratio, seabed_z=-DEPTH)


# name: (anchor, fairlead, w, EA, L, seabed_z)
CASES = {
    "slack": ([0, 0, -50], [80, 0, 0], 200.0, 1e8, 100.0, None),
    "near_taut": ([0, 0, -50], [80, 0, 0], 200.0, 1e8, 94.3, None),
    "low_point_below_ends": ([0, 0, -20], [50, 0, 0], 100.0, 1e7, 120.0, None),
    "fairlead_below_anchor": ([5, -3, 0], [45, 27, -30], 100.0, 1e7, 80.0, None),
    "touchdown": ([0, 0, -100], [300, 0, 0], 1000.0, 5e8, 350.0, -100.0),
    "touchdown_3d": ([10, 5, -200], [400, -20, -5], 1500.0, 1e9, 520.0, -200.0),
    "vertical": ([3, 4, -100], [3, 4, 0], 100.0, 1e7, 99.0, None),
}


def case_line(name):
    anchor, fairlead, w, EA, L, seabed_z = CASES[name]
    return solve_catenary(anchor, fairlead, w, EA, length=L, seabed_z=seabed_z)


@pytest.fixture(scope="module")
def paper():
    return paper_line(0.9)


@pytest.fixture(params=[*CASES, "paper"])
def line(request, paper):
    return paper if request.param == "paper" else case_line(request.param)


def moorpy_forces(line, seabed_z):
    """MoorPy's (fAH, fAV, fBH, fBV, info) for the same line; seabed far below if none."""
    span = float(np.dot(line.fairlead - line.anchor, line.direction))
    rise = float(line.fairlead[2] - line.anchor[2])
    CB = 0.0 if seabed_z is not None else -1e4
    return moorpy_catenary(span, rise, line.L, line.EA, line.w, CB=CB, Tol=1e-10, MaxIter=500)


def assert_forces_match_moorpy(line, seabed_z):
    fAH, fAV, fBH, fBV, info = moorpy_forces(line, seabed_z)
    scale = line.T_fairlead
    ours = [line.anchor_force() @ line.direction, line.anchor_force()[2],
            line.fairlead_force() @ line.direction, line.fairlead_force()[2]]
    np.testing.assert_allclose(ours, [fAH, fAV, fBH, fBV], rtol=1e-6, atol=1e-9 * scale)
    assert line.laid_length == pytest.approx(info["LBot"], rel=1e-6, abs=1e-9 * line.L)


@pytest.mark.parametrize("name", CASES)
def test_end_forces_match_moorpy(name):
    assert_forces_match_moorpy(case_line(name), CASES[name][-1])


def test_paper_case_matches_moorpy(paper):
    assert paper.laid_length == 0.0
    assert_forces_match_moorpy(paper, -DEPTH)


def test_cases_have_the_intended_shapes():
    assert case_line("near_taut").L < math.hypot(80, 50)
    low = case_line("low_point_below_ends")
    assert low.V_anchor < 0 and low.position(np.linspace(0, low.L, 201))[:, 2].min() < -20
    for name in ("touchdown", "touchdown_3d"):
        touchdown = case_line(name)
        assert touchdown.laid_length > 0 and touchdown.V_anchor == 0
    vertical = case_line("vertical")
    assert vertical.H == 0 and np.array_equal(vertical.direction, [1, 0, 0])


def test_profile_ends_at_anchor_and_fairlead(line):
    ends = line.position([0.0, line.L])
    chord = np.linalg.norm(line.fairlead - line.anchor)
    np.testing.assert_allclose(ends[0], line.anchor, rtol=0, atol=1e-12 * chord)
    np.testing.assert_allclose(ends[1], line.fairlead, rtol=0, atol=1e-9 * chord)


def test_position_derivative_is_stretched_tangent(line):
    s = np.linspace(0.013, 0.987, 40) * line.L
    s = s[np.abs(s - line.laid_length) > 1e-3 * line.L]  # away from the touchdown kink
    h = 1e-5 * line.L
    derivative = (line.position(s + h) - line.position(s - h)) / (2 * h)
    expected = (1 + line.tension(s) / line.EA)[:, None] * line.tangent(s)
    np.testing.assert_allclose(derivative, expected, rtol=0, atol=1e-8)
    np.testing.assert_allclose(np.linalg.norm(line.tangent(s), axis=1), 1.0, rtol=1e-14)


def test_tension_components(line):
    s = np.linspace(0, line.L, 101)
    force = line.tension(s)[:, None] * line.tangent(s)
    T = line.T_fairlead
    np.testing.assert_allclose(force @ line.direction, line.H, rtol=0, atol=1e-12 * T)
    hanging = np.maximum(s - line.laid_length, 0)
    np.testing.assert_allclose(force[:, 2], line.V_anchor + line.w * hanging,
                               rtol=0, atol=1e-12 * T)
    np.testing.assert_allclose(line.tension([0, line.L]), [line.T_anchor, line.T_fairlead],
                               rtol=1e-14)


def test_end_forces_balance_the_suspended_weight(line):
    suspended_weight = line.w * (line.L - line.laid_length)
    np.testing.assert_allclose(line.anchor_force() + line.fairlead_force(),
                               [0, 0, -suspended_weight], rtol=0, atol=1e-9 * line.T_fairlead)


def test_stretched_arclength_is_the_profile_length(line):
    s = np.linspace(0, line.L, 20001)
    segments = np.linalg.norm(np.diff(line.position(s), axis=0), axis=1)
    polyline = np.concatenate([[0], np.cumsum(segments)])
    np.testing.assert_allclose(line.stretched_arclength(s), polyline, rtol=0, atol=1e-8 * line.L)
    h = 1e-5 * line.L
    mid = np.linspace(0.1, 0.9, 9) * line.L
    rate = (line.stretched_arclength(mid + h) - line.stretched_arclength(mid - h)) / (2 * h)
    np.testing.assert_allclose(rate, 1 + line.tension(mid) / line.EA, rtol=1e-9)


def measured_sag_ratio(line):
    """d/l from sampled positions: where the line crosses the perpendicular at mid-chord."""
    chord_vector = line.fairlead - line.anchor
    chord = np.linalg.norm(chord_vector)
    along = chord_vector / chord
    # normal to the chord in the vertical plane of the line, pointing below the chord
    below = np.cross(along, np.cross([0, 0, -1.0], along))
    below /= np.linalg.norm(below)
    points = line.position(np.linspace(0, line.L, 200001)) - line.anchor
    a, d = points @ along, points @ below
    return np.interp(0.5 * chord, a, d) / chord


@pytest.mark.parametrize("sag_ratio, seabed_z",
                         [(1 / 60, -DEPTH), (1 / 45, None), (0.2, -DEPTH), (0.3, None)])
def test_sag_ratio_is_met(sag_ratio, seabed_z):
    rise = DEPTH - 0.9
    line = solve_catenary([0, 0, -DEPTH], [rise / math.tan(THETA), 0, -0.9], PAPER_W, PAPER_EA,
                          sag_ratio=sag_ratio, seabed_z=seabed_z)
    assert (line.laid_length > 0) == (sag_ratio == 0.2)
    assert measured_sag_ratio(line) == pytest.approx(sag_ratio, rel=1e-8)
    chord = np.linalg.norm(line.fairlead - line.anchor)
    assert line.sag() / chord == pytest.approx(sag_ratio, rel=1e-12)


@pytest.mark.parametrize("name",
                         ["slack", "low_point_below_ends", "touchdown_3d", "fairlead_below_anchor"])
def test_horizontal_tension_input_gives_the_same_line(name):
    anchor, fairlead, w, EA, L, seabed_z = CASES[name]
    line = solve_catenary(anchor, fairlead, w, EA, horizontal_tension=case_line(name).H,
                          seabed_z=seabed_z)
    assert line.L == pytest.approx(L, rel=1e-10)


def test_draft_of_the_paper_case():
    """The paper's case resolved (docs/paper.md): rho_s g h_s (26 x 10) = M g + 4 V_fairlead gives h_s = 0.8975 m."""
    def vertical_imbalance(draft):
        return RHO_WATER * G * draft * 26 * 10 - 1.2e5 * G - 4 * paper_line(draft).V_fairlead

    assert brentq(vertical_imbalance, 0.5, 1.5, xtol=1e-9) == pytest.approx(0.8975, abs=1e-3)


GOOD = dict(anchor=[0, 0, -50], fairlead=[80, 0, 0], w=200.0, EA=1e8, length=100.0)


@pytest.mark.parametrize("change, field", [
    (dict(EA=0.0), "EA"),
    (dict(EA=-1e8), "EA"),
    (dict(EA=math.inf), "EA"),
    (dict(w=0.0), "w"),
    (dict(w=-200.0), "w"),
    (dict(w=math.nan), "w"),
    (dict(length=0.0), "length"),
    (dict(length=-100.0), "length"),
    (dict(length=math.nan), "length"),
    (dict(anchor=[0, math.nan, -50]), "anchor"),
    (dict(anchor=[0, 0]), "anchor"),
    (dict(fairlead=[math.inf, 0, 0]), "fairlead"),
    (dict(fairlead=[0, 0, -50]), "fairlead"),  # coincides with the anchor
    (dict(length=None, horizontal_tension=math.nan), "horizontal_tension"),
    (dict(length=None, horizontal_tension=-1.0), "horizontal_tension"),
    (dict(length=None, horizontal_tension=2e8), "horizontal_tension"),  # above EA
    (dict(length=None, sag_ratio=0.0), "sag_ratio"),
    (dict(length=None, sag_ratio=0.5), "sag_ratio"),
    (dict(length=None, sag_ratio=-0.1), "sag_ratio"),
    (dict(length=None, sag_ratio=math.nan), "sag_ratio"),
    (dict(length=None), "length, horizontal_tension, sag_ratio"),  # none given
    (dict(sag_ratio=0.1), "length, horizontal_tension, sag_ratio"),  # two given
    (dict(length=40.0), "length"),  # too short: would need a strain above 1
    (dict(seabed_z=-40.0), "anchor"),  # anchor below the seabed
    (dict(seabed_z=math.nan), "seabed_z"),
    (dict(seabed_z=-50.0, length=200.0), "length"),  # too long: slack on the seabed
    (dict(seabed_z=-50.5, length=200.0), "seabed_z"),  # suspended line dips below the seabed
])
def test_bad_input_names_the_field(change, field):
    with pytest.raises(ValueError, match=f"^{field}:"):
        solve_catenary(**GOOD | change)


def test_too_short_message_explains_the_strain_limit():
    with pytest.raises(ValueError, match="^length:.*above EA.*strain above 1"):
        solve_catenary(**GOOD | dict(length=40.0))
