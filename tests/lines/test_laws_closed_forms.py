"""Constitutive laws (skmoor.lines.laws) against numbers worked by hand, beside
test_laws.py: the engineering and the paper's law at and just above zero strain (tension
EA e and EA eps lambda down to a fraction of a newton, stiffness EA at the unstretched
state); the paper's S = EA eps on a reference tension T, taut, at the slack point
T + EA eps = 0 and below it; a curve's tension (the table, its last slope beyond, its first
slope below zero when it pushes) and the inverse of its static law below zero; the
stress resultant of the engineering law and of a static-dynamic rope (EA_d = alpha_MBL +
beta T per point) stretched from a reference state, S = N(e) / lambda - T with e = (1 +
e_ref) lambda - 1; each law's per-point parameters (static and dynamic); the viscoelastic
rope's static law and its springs; the nominal EA of a curve (its last secant) and of a
static-dynamic rope; and the refusals of bad rope data, curves and curve files."""
import numpy as np
import pytest

from skmoor import laws
from skmoor.lines.line import LineType

EA = 2.0e6  # N
CURVE_E = (0.01, 0.02, 0.05)
CURVE_T = (5.0e3, 1.5e4, 9.0e4)  # pieces' slopes 5e5, 1e6, 2.5e6 N from (0, 0)
SLOPES = (5.0e5, 1.0e6, 2.5e6)


def with_fields(p, T, EA):
    """The parameters p of a law completed with the line type's EA and no hinges (the
    fields a LineSet hands to stress_resultant for a law without a table)."""
    shape = np.shape(T)
    return dict(p, EA=EA * np.ones(shape), knots=np.zeros((0,) + shape),
                coef=np.zeros((0,) + shape))


# ------------------------------------------------------------ tension and stiffness at 0

def test_tension_is_linear_down_to_zero_and_the_stiffness_at_zero_strain_is_EA():
    """Engineering: N = EA e, dN/de = EA; the paper's law from a stress-free state: N = EA
    eps lambda (lambda = 1 + e, eps = (lambda^2 - 1) / 2), dN/de = EA (lambda^2 + eps).
    At e = 1e-10 the tension is 2e-4 N (no threshold drops a small force), and at e = 0
    the stiffness is EA, the right-hand slope (a stress-free line's first Newton tangent
    is not zero); a compressed tension-only cable carries nothing and has no stiffness."""
    e = np.array([-1e-3, 0.0, 1e-10, 0.01])
    lam = 1.0 + e
    eps = 0.5 * (lam * lam - 1.0)
    taut = e >= 0
    engineering = laws.Engineering()
    np.testing.assert_allclose(engineering.tension(e, EA), np.where(taut, EA * e, 0.0),
                               rtol=1e-12, atol=0.0)
    np.testing.assert_array_equal(engineering.slope(e, EA), np.where(taut, EA, 0.0))
    paper = laws.Paper()
    np.testing.assert_allclose(paper.tension(e, EA), np.where(taut, EA * eps * lam, 0.0),
                               rtol=1e-6, atol=0.0)
    np.testing.assert_allclose(paper.slope(e, EA), np.where(taut, EA * (lam**2 + eps), 0.0),
                               rtol=1e-12, atol=0.0)
    assert engineering.tension(1e-10, EA) == pytest.approx(2e-4, rel=1e-12)


def test_the_unit_EA_and_a_curve_that_needs_none():
    """Without an EA, the engineering law's tension is per newton of EA (EA = 1 N), so
    tension(e, EA) = EA tension(e); a curve needs no EA and ignores one."""
    e = np.array([0.004, 0.03])
    np.testing.assert_allclose(laws.Engineering().tension(e), e, rtol=1e-15)
    np.testing.assert_allclose(laws.Engineering().tension(e, EA), EA * e, rtol=1e-15)
    curve = laws.Curve(CURVE_E, CURVE_T)
    np.testing.assert_allclose(curve.tension(e), curve.tension(e, 123.0), rtol=1e-15)


# ------------------------------------------------------------ the paper's law on T

def test_papers_stress_resultant_on_a_reference_tension():
    """Eq. 6 on a reference tension T = 1e6 N, EA = 4e6 N: S = EA eps, dS/deps = EA while
    T + EA eps >= 0; below it (eps < -T / EA = -0.25) a tension-only cable has T + S = 0
    and no stiffness. At the slack point eps = -0.25 exactly the axial force is 0 with
    the stiffness EA (the taut side's), and 2^-22 above it the axial force is 0.954 N,
    kept; eps = -0.1 leaves 6e5 N. A law that pushes keeps S = EA eps throughout."""
    EA4, T = 4.0e6, 1.0e6
    eps = np.array([-0.3, -0.25, -0.25 + 2.0**-22, -0.1, 0.0, 0.05])
    Ts = T * np.ones_like(eps)
    axial = T + EA4 * eps  # 0 at -0.25, 0.95367431640625 N just above
    assert axial[1] == 0.0 and axial[2] == pytest.approx(0.95367431640625, abs=0.0)
    for law in (laws.Paper(), laws.Paper(tension_only=False)):
        p = with_fields(law.parameters(EA4, Ts, 0.0 * Ts)[0], Ts, EA4)
        S, dS = laws.stress_resultant(eps, Ts, p)
        if law.tension_only:
            expected_axial = np.where(axial < 0, 0.0, axial)
            expected_dS = np.where(axial < 0, 0.0, EA4)
        else:
            expected_axial, expected_dS = axial, EA4 * np.ones_like(eps)
        np.testing.assert_allclose(Ts + S, expected_axial, rtol=1e-12, atol=1e-9)
        np.testing.assert_array_equal(dS, expected_dS)


# ------------------------------------------------------------ laws from a reference state

def central(f, x, h=1e-7):
    return (f(x + h) - f(x - h)) / (2 * h)


def test_engineering_stress_resultant_from_a_stretched_reference():
    """Engineering on reference tensions T (N) at their static strains e_ref = T / EA:
    stretched by lambda = sqrt(1 + 2 eps) the strain is e = (1 + e_ref) lambda - 1 and
    S = EA e / lambda - T (0 when slack), its slope the central difference of it; at
    eps = 0, S = 0 and dS/deps = EA (1 + e_ref) - T = EA, the unstretched line's too."""
    T = np.array([0.0, 1.0e4, 5.0e4, 2.0e5])
    e_ref = T / EA
    p = with_fields(laws.Engineering().parameters(EA, T, e_ref)[0], T, EA)

    def S_hand(eps):
        lam = np.sqrt(1.0 + 2.0 * eps)
        e = (1.0 + e_ref) * lam - 1.0
        return np.maximum(EA * e, 0.0) / lam - T

    S, dS = laws.stress_resultant(np.zeros(4), T, p)
    np.testing.assert_allclose(S, 0.0, atol=1e-9)
    np.testing.assert_allclose(dS, EA, rtol=1e-12)
    eps = np.array([-0.01, -0.001, 0.01, -0.02])  # the first slack, the others taut
    S, dS = laws.stress_resultant(eps, T, p)
    np.testing.assert_allclose(S, S_hand(eps), rtol=1e-10, atol=1e-6)
    assert S[0] == 0.0 and dS[0] == 0.0
    np.testing.assert_allclose(dS, central(S_hand, eps), rtol=1e-6, atol=1e-6)


def test_static_dynamic_rope_moves_about_its_mean_with_the_load_dependent_stiffness():
    """StaticDynamic(alpha_MBL, beta) about mean tensions T at strains e_ref (the static
    law's, EA_s): the dynamic tension is T + EA_d (e - e_ref), EA_d = alpha_MBL + beta T
    point by point, so S = (T + EA_d (e - e_ref)) / lambda - T with e = (1 + e_ref)
    lambda - 1; the static parameters are the static law's (tension EA_s e)."""
    alpha, beta = 3.0 * EA, 20.0
    rope = laws.StaticDynamic(alpha_MBL=alpha, beta=beta)
    T = np.array([1.0e4, 5.0e4, 2.0e5])
    e_ref = T / EA
    p = with_fields(rope.parameters(EA, T, e_ref)[0], T, EA)
    EA_d = alpha + beta * T
    np.testing.assert_allclose(p["k"], EA_d, rtol=1e-15)
    eps = np.array([0.002, -0.001, 0.004])
    lam = np.sqrt(1.0 + 2.0 * eps)
    e = (1.0 + e_ref) * lam - 1.0
    S, _ = laws.stress_resultant(eps, T, p)
    np.testing.assert_allclose(S, (T + EA_d * (e - e_ref)) / lam - T, rtol=1e-10)
    static = with_fields(rope.parameters(EA, T, e_ref, static=True)[0], T, EA)
    S, _ = laws.stress_resultant(eps, T, static)
    np.testing.assert_allclose(S, EA * e / lam - T, rtol=1e-10)


LAW_CASES = [
    # law, static parameters (T0, e0, k) and dynamic ones at reference (T, e_ref), green
    (laws.Engineering(), lambda T, e: (0 * T, 0 * T, EA + 0 * T),
     lambda T, e: (0 * T, 0 * T, EA + 0 * T), 0.0),
    (laws.Paper(), lambda T, e: (0 * T, 0 * T, EA + 0 * T),
     lambda T, e: (0 * T, 0 * T, EA + 0 * T), 1.0),
    (laws.Curve(CURVE_E, CURVE_T), lambda T, e: (0 * T, 0 * T, SLOPES[0] + 0 * T),
     lambda T, e: (0 * T, 0 * T, SLOPES[0] + 0 * T), 0.0),
    (laws.StaticDynamic(alpha_MBL=3 * EA, beta=20.0), lambda T, e: (0 * T, 0 * T, EA + 0 * T),
     lambda T, e: (T, e + 0 * T, 3 * EA + 20.0 * T), 0.0),
    (laws.Viscoelastic(EA_dynamic=3 * EA, creep_damping=1e5),
     lambda T, e: (0 * T, 0 * T, EA + 0 * T), lambda T, e: (T, e + 0 * T, 0 * T), 0.0),
]


@pytest.mark.parametrize("law, static, dynamic, green", LAW_CASES,
                         ids=[case[0].name for case in LAW_CASES])
def test_each_laws_parameters_point_by_point(law, static, dynamic, green):
    """Each law's parameters at three points of reference tension T (N) and one strain
    e_ref: arrays shaped like T (point i's alone give point i's force), with N(e) = T0 +
    k (e - e0) by hand: the static law from a stress-free state (T0 = 0, k = EA or a
    curve's first slope) and, by default, the dynamic one (StaticDynamic: T0 = T, e0 =
    e_ref, k = alpha_MBL + beta T; Viscoelastic: the mean tension held, k = 0, its creep
    term adding the rest); green marks the paper's law; tension-only."""
    T = np.array([0.0, 3.0e4, 1.0e5])
    e_ref = 0.015
    for parameters, hand in ((law.parameters(EA, T, e_ref), dynamic),
                             (law.parameters(EA, T, e_ref, static=True), static)):
        p, _ = parameters
        for name in laws.PARAMETERS:
            assert np.shape(p[name]) == T.shape, name
        T0, e0, k = hand(T, e_ref)
        np.testing.assert_allclose(p["T0"], T0, rtol=1e-15)
        np.testing.assert_allclose(p["e0"], e0, rtol=1e-15)
        np.testing.assert_allclose(p["k"], k, rtol=1e-15)
        np.testing.assert_array_equal(p["green"], green)
        np.testing.assert_array_equal(p["tension_only"], 1.0)
        np.testing.assert_array_equal(p["e_ref"], e_ref)


# ------------------------------------------------------------ curves

def test_curve_tension_is_the_table_extended_with_its_end_slopes():
    """Curve.tension: np.interp of the table (with (0, 0)) inside it, its last slope beyond
    the last point (0.08: 9e4 + 2.5e6 x 0.03 = 1.65e5 N), nothing below zero; its slope the
    piece's; the same curve allowed to push goes below zero with its first slope
    (-0.01: -5e3 N)."""
    curve = laws.Curve(CURVE_E, CURVE_T)
    e = np.array([-0.01, 0.005, 0.015, 0.03, 0.08])
    table = np.interp(e, np.r_[0.0, CURVE_E], np.r_[0.0, CURVE_T])
    expected = np.where(e > CURVE_E[-1], CURVE_T[-1] + SLOPES[-1] * (e - CURVE_E[-1]), table)
    np.testing.assert_allclose(curve.tension(e), expected, rtol=1e-12, atol=1e-9)
    assert curve.tension(np.array([0.08]))[0] == pytest.approx(1.65e5, rel=1e-12)
    np.testing.assert_allclose(curve.slope(e), [0.0, SLOPES[0], SLOPES[1], SLOPES[2],
                                                SLOPES[2]], rtol=1e-12)
    pushing = laws.Curve(CURVE_E, CURVE_T, tension_only=False)
    below = np.array([-0.01])
    assert pushing.tension(below)[0] == pytest.approx(-5.0e3, rel=1e-12)
    assert pushing.slope(below)[0] == pytest.approx(SLOPES[0], rel=1e-12)


def test_static_law_of_a_pushing_curve_inverts_below_zero():
    """A curve that pushes (tension_only=False): static_tension(-0.01) = -5e3 N (first
    slope) and static_strain(-5e3) = -0.01 on the first piece, not on the last."""
    pushing = laws.Curve(CURVE_E, CURVE_T, tension_only=False)
    assert pushing.static_tension(-0.01) == pytest.approx(-5.0e3, rel=1e-12)
    assert pushing.static_strain(-5.0e3) == pytest.approx(-0.01, rel=1e-12)
    T = np.array([-5.0e3, 0.0, 1.0e4, 9.0e4, 1.65e5])
    np.testing.assert_allclose(pushing.static_strain(T), [-0.01, 0.0, 0.015, 0.05, 0.08],
                               rtol=1e-12, atol=1e-15)


def test_one_point_curve_is_a_linear_law_and_text_numbers_are_read():
    """A single point (0.01, 100 N) with (0, 0) prepended is the linear law EA = 1e4 N; the
    numbers of a table given as text are read as numbers."""
    one = laws.Curve([0.01], [100.0])
    assert one.strain == (0.0, 0.01) and one.tension_values == (0.0, 100.0)
    assert one.tension(np.array([0.03]))[0] == pytest.approx(300.0, rel=1e-12)
    assert one.nominal_EA() == pytest.approx(1.0e4, rel=1e-15)
    text = laws.Curve(["0.01", "0.02", "0.05"], ["5e3", "1.5e4", "9e4"])
    assert text.strain == (0.0,) + CURVE_E and text.tension_values == (0.0,) + CURVE_T
    np.testing.assert_allclose(text.slopes, SLOPES, rtol=1e-12)


def test_nominal_EA_of_a_curve_is_its_last_secant():
    """A curve's nominal EA is its last point's secant, 9e4 / 0.05 = 1.8e6 N (a line type
    with the curve and no EA takes it); a static-dynamic rope's is its static law's: the
    line type's EA over Engineering, the curve's secant over a curve."""
    curve = laws.Curve(CURVE_E, CURVE_T)
    assert curve.nominal_EA() == pytest.approx(1.8e6, rel=1e-15)
    assert LineType(EA=None, mass=1.0, diameter=0.01, law=curve).EA == pytest.approx(1.8e6)
    assert laws.StaticDynamic(EA_dynamic=3 * EA).nominal_EA(EA) == EA
    over_curve = laws.StaticDynamic(EA_dynamic=3 * EA, static=curve)
    assert over_curve.nominal_EA(EA) == pytest.approx(1.8e6, rel=1e-15)


# ------------------------------------------------------------ polyester

def test_static_dynamic_over_a_pushing_static_law_pushes():
    """A static-dynamic rope is tension-only when its static law or itself is: over
    Engineering(tension_only=False) it carries -0.01 EA at e = -0.01."""
    rope = laws.StaticDynamic(EA_dynamic=3 * EA, static=laws.Engineering(tension_only=False))
    assert not rope.tension_only
    assert rope.tension(-0.01, EA) == pytest.approx(-0.01 * EA, rel=1e-12)
    cable = laws.StaticDynamic(EA_dynamic=3 * EA, static=laws.Engineering())
    assert cable.tension_only and cable.tension(-0.01, EA) == 0.0


def test_viscoelastic_rope_statics_and_springs():
    """The viscoelastic rope's static law is its static one (tension EA_s e, slope EA_s);
    with EA_s = 10 N and a fixed EA_d = 30 N the springs are EA_d = 30 N and EA_1 = EA_d
    EA_s / (EA_d - EA_s) = 15 N at any creep strain, z = 0.5 included."""
    rope = laws.Viscoelastic(EA_dynamic=3 * EA, creep_damping=1e5)
    e = np.array([0.004, 0.02])
    np.testing.assert_allclose(rope.tension(e, EA), EA * e, rtol=1e-12)
    np.testing.assert_allclose(rope.slope(e, EA), EA, rtol=1e-12)
    small = laws.Viscoelastic(EA_dynamic=30.0, creep_damping=1.0)
    EA_1, EA_d = small.stiffnesses(np.array([0.0, 0.5]), 10.0)
    np.testing.assert_array_equal(EA_d, 30.0)
    np.testing.assert_allclose(EA_1, 15.0, rtol=1e-15)


@pytest.mark.parametrize("kwargs, field", [
    (dict(alpha_MBL=1e8, beta=-1.0), "beta"),
    (dict(alpha_MBL=-1e8), "alpha_MBL"),
    (dict(alpha_MBL=np.inf), "alpha_MBL"),
    (dict(EA_dynamic=0.0), "EA_dynamic"),
    (dict(EA_dynamic=np.inf), "EA_dynamic"),
    (dict(EA_dynamic=1e8, static=laws.StaticDynamic(EA_dynamic=1e8)), r"StaticDynamic\.static"),
])
def test_bad_static_dynamic_data_is_refused_naming_the_field(kwargs, field):
    with pytest.raises(ValueError, match=field):
        laws.StaticDynamic(**kwargs)


@pytest.mark.parametrize("kwargs, field", [
    (dict(creep_damping=-1.0, dynamic_damping=1e5), "creep_damping"),
    (dict(creep_damping=1e5, dynamic_damping=np.inf), "dynamic_damping"),
    (dict(creep_damping=0.0, dynamic_damping=0.0), "creep_damping"),
    (dict(creep_damping=1e5, relax=-1.0), "relax"),
    (dict(creep_damping=1e5, relax=np.inf), "relax"),
])
def test_bad_viscoelastic_data_is_refused_naming_the_field(kwargs, field):
    with pytest.raises(ValueError, match=field):
        laws.Viscoelastic(EA_dynamic=1e8, **kwargs)


def test_small_positive_rope_data_is_accepted():
    """Any positive stiffness and damping is data (a model in kN or a small rig): EA_d =
    0.5 N, a creep damping of 0.5 N s alone, a dynamic damping alone."""
    assert laws.StaticDynamic(EA_dynamic=0.5).dynamic_EA(0.0) == 0.5
    assert laws.Viscoelastic(EA_dynamic=1e8, creep_damping=0.5).creep_damping == 0.5
    only_dynamic = laws.Viscoelastic(EA_dynamic=1e8, dynamic_damping=2e5)
    assert only_dynamic.creep_damping == 0.0 and only_dynamic.dynamic_damping == 2e5


# ------------------------------------------------------------ refusals of curves and names

def test_unknown_law_name_is_refused_naming_the_law_field():
    with pytest.raises(ValueError, match=r"^law: .*'hooke'"):
        laws.as_law("hooke")


@pytest.mark.parametrize("strain, tension, value", [
    (["a", "b"], [1.0, 2.0], None),
    ([0.01], [-5.0], "-5"),
    ([-0.01], [5.0], "-0.01"),
    ([0.0], [5.0], "5"),
    ([0.01, 0.02, 0.015], [1.0, 2.0, 3.0], "0.015"),
    ([0.01, 0.02, 0.03], [1.0, 3.0, 2.5], "2.5"),
])
def test_bad_curves_are_refused_naming_the_curve_and_the_value(strain, tension, value):
    """Refused with ValueError naming the curve's source and the offending value: text
    that is not a number, a single point with a negative tension or strain or a tension
    at zero strain, a strain or a tension that goes back."""
    with pytest.raises(ValueError, match=r"^my curve: ") as error:
        laws.Curve(strain, tension, source="my curve")
    if value is not None:
        assert value in str(error.value)


def test_a_curve_without_a_source_is_named_curve_in_its_errors():
    with pytest.raises(ValueError, match=r"^Curve: "):
        laws.Curve([0.01, 0.01], [1.0, 2.0])


def test_curve_files_are_named_by_their_path_and_read_past_a_latin_1_header(tmp_path):
    """A curve file's source is its path; a header written in Latin-1 (a degree sign, a
    micro sign) does not stop the reading of the points; a file with no points after
    its three header lines is refused naming the file."""
    path = tmp_path / "poly.txt"
    path.write_bytes(b"EA curve \xb0C\nStrain Tension\n(\xb5-) (N)\n0.01 5e3\n0.02 1.5e4\n")
    curve = laws.read_curve(path)
    assert curve.source.startswith(str(path))
    assert curve.strain == (0.0, 0.01, 0.02) and curve.tension_values == (0.0, 5e3, 1.5e4)
    empty = tmp_path / "empty.txt"
    empty.write_text("EA curve\nStrain Tension\n(-) (N)\n\n")
    with pytest.raises(ValueError, match="empty.txt"):
        laws.read_curve(empty)


def test_a_curve_takes_a_plain_float_strain():
    """A curve evaluated at a float strain, as Engineering and Paper are: between the
    points (0.02, 1e4 N) and (0.05, 5e4 N) at 0.03 the tension is 1e4 + 4e4 / 3 N and the
    slope 4e4 / 0.03 N."""
    curve = laws.Curve([0.0, 0.02, 0.05], [0.0, 1e4, 5e4])
    assert curve.tension(0.03) == pytest.approx(1e4 + 4e4 / 3, rel=1e-12)
    assert curve.slope(0.03) == pytest.approx(4e4 / 0.03, rel=1e-12)
    assert curve.tension(0.03) == pytest.approx(curve.tension(np.array([0.03]))[0], rel=1e-14)
