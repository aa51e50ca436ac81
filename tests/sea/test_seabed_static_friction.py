"""Static sea-bed friction as MoorPy defines it (``Seabed(static_friction='as-laid')``)
and the anchor tension of a line laid on the bed under mesh refinement.

MoorPy's catenary with CB > 0 (moorpy.Catenary.catenary): the laid part's tension falls
by CB w per metre from the touchdown towards the anchor, down to zero; its own tests
(MoorPy tests/test_catenary.py: XF = 400 m, ZF = 200 m, L = 500 m, EA = 7.51e12 N,
w = 800 N/m) give an anchor tension of 96.64 kN at CB = 0, 80.42 kN at CB = 0.1 and 0 at
CB = 5, the fairlead's unchanged. skmoor's FE statics with the slip counted from the
line laid on the bed without tension reach them; MoorPy runs side by side where it is
installed, its published numbers are asserted either way.
"""
import numpy as np
import pytest

from skmoor.coupling.system import System
from skmoor.lines.catenary import solve_catenary
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.sea.seabed import Seabed, seabed_term
from skmoor.solvers.statics import solve_static

SPAN, RISE, LENGTH, W = 400.0, 200.0, 500.0, 800.0  # MoorPy's test_catenary cases 1-3
MOORPY_EA = 7.51e12
# MoorPy's desired results there (fAH = anchor tension, the line laid: fAV = 0)
MOORPY_ANCHOR = {0.0: 96643.42815934008, 0.1: 80418.60434855078, 5.0: 0.0}
MOORPY_FAIRLEAD = np.hypot(96643.43, 237751.76)


def static_line(cb, nel, EA=MOORPY_EA, slip=1e-9, static_friction="as-laid"):
    """(anchor tension, fairlead tension) N of the FE statics: the line of MoorPy's
    cases, anchored on a stiff bed (0.1 mm penetration), with friction coefficient cb."""
    line_type = LineType(EA=EA, mass=100.0, diameter=0.1, weight=W)
    anchor = np.array([-SPAN, 0.0, -RISE])
    cat = solve_catenary(anchor, np.zeros(3), W, EA, length=LENGTH, seabed_z=-RISE)
    lines = LineSet([Line.from_catenary(cat, line_type, nel)], law="engineering")
    bed = Seabed(RISE, stiffness=W / 1e-4, mu_axial=cb, mu_lateral=cb,
                 static_friction=static_friction if cb else None, static_slip=slip)
    system = System(lines, fairleads="fixed", terms=[seabed_term(lines, bed)])
    fb, fa = system.reactions(solve_static(system).x)
    return float(np.linalg.norm(fa[0])), float(np.linalg.norm(fb[0]))


def moorpy_tensions(cb, EA):
    catenary = pytest.importorskip("moorpy.Catenary").catenary
    fAH, fAV, fBH, fBV, _ = catenary(SPAN, RISE, LENGTH, EA, W, CB=cb)
    return float(np.hypot(fAH, fAV)), float(np.hypot(fBH, fBV))


@pytest.mark.parametrize("cb", [0.0, 0.1])
def test_anchor_tension_matches_moorpys_catenary_cases(cb):
    """MoorPy's own cases (EA = 7.51e12 N, 400 elements, slip scale 1 nm): the anchor
    tension within 0.1 % of MoorPy's (96.64 kN without friction, 80.42 kN at CB = 0.1,
    the friction relieving the anchor by CB w L_bed = 16.2 kN), the fairlead tension
    within 0.05 %."""
    anchor, fairlead = static_line(cb, 400)
    assert anchor == pytest.approx(MOORPY_ANCHOR[cb], rel=1e-3)
    assert fairlead == pytest.approx(MOORPY_FAIRLEAD, rel=5e-4)
    if cb:
        assert MOORPY_ANCHOR[0.0] - anchor == pytest.approx(cb * W * 202.81, rel=1e-2)


def test_friction_that_holds_the_whole_pull_leaves_no_anchor_tension():
    """CB = 5 (MoorPy's case 1, here EA = 7.51e9 N and a 10 um slip scale): the friction
    of the first metres of laid chain takes the whole pull; the anchor tension is below
    0.05 % of the frictionless one (MoorPy: 0), the fairlead's unchanged within 0.05 %."""
    anchor, fairlead = static_line(5.0, 400, EA=7.51e9, slip=1e-5)
    assert anchor < 5e-4 * MOORPY_ANCHOR[0.0]
    assert fairlead == pytest.approx(MOORPY_FAIRLEAD, rel=5e-4)


@pytest.mark.parametrize("cb", [0.1, 5.0])
def test_side_by_side_with_moorpy(cb):
    """A chain of EA = 7.51e9 N (a 1 mm stretch on the bed, 10 um slip scale) against
    MoorPy's catenary of the same line run here: anchor tension within 0.15 % of the
    frictionless tension, fairlead within 0.05 %."""
    md_anchor, md_fairlead = moorpy_tensions(cb, 7.51e9)
    _, _ = moorpy_tensions(0.0, 7.51e9)
    anchor, fairlead = static_line(cb, 400, EA=7.51e9, slip=1e-5)
    assert abs(anchor - md_anchor) < 1.5e-3 * MOORPY_ANCHOR[0.0]
    assert fairlead == pytest.approx(md_fairlead, rel=5e-4)


def test_reference_start_and_no_static_friction_keep_the_catenary():
    """Without static friction (the default), or with the slip counted from the
    reference catenary (nothing slides from there), the anchor keeps the frictionless
    tension (MoorPy's CB = 0) within 0.1 %."""
    for kind in (None, "reference"):
        anchor, _ = static_line(5.0, 400, EA=7.51e9, slip=1e-5, static_friction=kind)
        assert anchor == pytest.approx(MOORPY_ANCHOR[0.0], rel=1e-3), kind


def test_anchor_tension_converges_with_the_mesh():
    """The anchor tension of the frictionless line (EA = 7.51e12 N) against the analytic
    catenary's H (MoorPy's 96.64 kN) on 50 to 800 elements: the bed carries the anchor
    node's share of the weight (w h / 2: a vertical pull of 2.1 % of the tension at 100
    elements when the anchor carried it), so the anchor force is horizontal (its
    vertical part below 1e-3 of it) and its error is below 0.1 % at 50 elements and
    below 2e-5 from 200 on."""
    errors = {}
    for nel in (50, 100, 200, 800):
        line_type = LineType(EA=MOORPY_EA, mass=100.0, diameter=0.1, weight=W)
        anchor = np.array([-SPAN, 0.0, -RISE])
        cat = solve_catenary(anchor, np.zeros(3), W, MOORPY_EA, length=LENGTH,
                             seabed_z=-RISE)
        lines = LineSet([Line.from_catenary(cat, line_type, nel)], law="engineering")
        system = System(lines, fairleads="fixed",
                        terms=[seabed_term(lines, Seabed(RISE, stiffness=W / 1e-4))])
        _, fa = system.reactions(solve_static(system).x)
        assert abs(fa[0][2]) < 1e-3 * np.linalg.norm(fa[0]), nel
        errors[nel] = abs(np.linalg.norm(fa[0]) - cat.H) / cat.H
    assert errors[50] < 1e-3 and errors[100] < 1e-3, errors
    assert errors[200] < 2e-5 and errors[800] < 2e-5, errors


def test_static_friction_input_is_checked():
    with pytest.raises(ValueError, match="static_friction"):
        Seabed(100.0, static_friction="laid")
    with pytest.raises(ValueError, match="static_slip"):
        Seabed(100.0, static_slip=0.0)


def test_a_model_says_when_its_static_state_leaves_the_friction_out():
    """A bed with friction and frictionless statics (static_friction None, the default)
    puts a note in the model (and so in summary.json); with 'as-laid', or without
    friction, there is none."""
    import warnings

    import skmoor

    def friction_notes(**change):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model = skmoor.build(skmoor.paper_case(**change))
        return [note for note in model.notes if "frictionless" in note]

    assert len(friction_notes(seabed__mu_axial=0.3)) == 1
    assert friction_notes(seabed__mu_axial=0.3, seabed__static_friction="as-laid") == []
    assert friction_notes() == []


def test_static_residual_alone_equals_the_one_with_its_tangent():
    """In a static solve the bed's residual is evaluated alone (line search) and with its
    tangent (Newton): the two must be one residual, friction of the slip from the as-laid
    line included, and the tangent its derivative (central differences). A residual-only
    path that drops the friction, or gets the state wrong, fails."""
    line_type = LineType(EA=1e9, mass=100.0, diameter=0.1, weight=W)
    anchor = np.array([-SPAN, 0.0, -RISE])
    cat = solve_catenary(anchor, np.zeros(3), W, 1e9, length=LENGTH, seabed_z=-RISE)
    lines = LineSet([Line.from_catenary(cat, line_type, 40)], law="engineering")
    bed = Seabed(RISE, stiffness=W / 1e-2, mu_axial=0.5, mu_lateral=0.5,
                 static_friction="as-laid", static_slip=1e-3)
    term = seabed_term(lines, bed)
    System(lines, fairleads="fixed", terms=[term])
    rng = np.random.default_rng(3)
    u = 0.05 * rng.standard_normal(lines.ndofs)
    v = np.zeros(lines.ndofs)
    lines.use_static_laws(True)
    try:
        alone = term.evaluate(u, v, 0.0, False)[0]
        with_tangent, K, _ = term.evaluate(u, v, 0.0, True, "sparse")
        K = K.toarray() if hasattr(K, "toarray") else np.asarray(K)
        du = 1e-7 * rng.standard_normal(lines.ndofs)
        slope = (term.evaluate(u + du, v, 0.0, False)[0]
                 - term.evaluate(u - du, v, 0.0, False)[0]) / 2
        lines.use_static_laws(False)
        without_friction = term.evaluate(u, v, 0.0, False)[0]
    finally:
        lines.use_static_laws(False)
    np.testing.assert_allclose(alone, with_tangent, rtol=1e-12, atol=1e-9)
    assert np.abs(alone - without_friction).max() > 1e-3 * np.abs(alone).max()
    np.testing.assert_allclose(slope, K @ du, rtol=1e-4, atol=1e-6 * np.abs(K @ du).max())
