"""skmoor against MoorPy (quasi-static catenary), run side by side on the paper's case.

MoorPy is built from skmoor's numbers: depth, water, the line type from E, D and rho
(MoorPy computes the submerged weight itself), anchors and fairleads at the catenaries'
positions, unstretched lengths L, a coupled body at the box's centre of mass.

Conventions: MoorPy's rotation is R = Rz Ry Rx as skmoor's, its moments are about the
body reference point (the CoM here) in global axes, its stiffness the derivative of
those moments; skmoor's rotational loads are generalized (J^T f). The two stiffness
matrices differ by terms in the lines' total static moment about the CoM, which is zero
in this symmetric case, so they are compared entry by entry.
"""
import numpy as np
import pytest

mp = pytest.importorskip("moorpy", reason="MoorPy (pip install moorpy) is the quasi-static peer")

from peers import condensed_fairlead_stiffness, condensed_line_stiffness, moorpy_system  # noqa: E402

from skmoor.coupling.system import System
from skmoor.io.case import paper_case
from skmoor.lines.catenary import solve_catenary
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.model.from_case import line_type
from skmoor.model.model import build
from skmoor.solvers.statics import solve_static

# the entries that carry the mooring stiffness of this symmetric layout
SIGNIFICANT = [(0, 0), (1, 1), (2, 2), (3, 3), (4, 4), (5, 5), (0, 4), (4, 0), (1, 3), (3, 1)]
NAMES = ["surge", "sway", "heave", "roll", "pitch", "yaw", "surge-pitch", "pitch-surge",
         "sway-roll", "roll-sway"]


def static_state(n_elements):
    model = build(paper_case(mooring__n_elements=n_elements))
    x = solve_static(model.system).x
    return model, x


def stiffness_errors(n_elements):
    """Relative differences (skmoor - MoorPy) / MoorPy of the significant entries, the
    two matrices, and the largest insignificant entries of each (scaled)."""
    model, x = static_state(n_elements)
    K_sk = condensed_line_stiffness(model.system, x)
    ms, _ = moorpy_system(model, q=model.system.q(x))
    K_mp = ms.getCoupledStiffnessA(lines_only=True)
    errors = np.array([K_sk[i, j] / K_mp[i, j] - 1 for i, j in SIGNIFICANT])
    return errors, K_sk, K_mp


@pytest.fixture(scope="module")
def paper():
    return static_state(11)


def test_moorpy_weight_is_skmoor_weight(paper):
    model, _ = paper
    ms, _ = moorpy_system(model)
    lt = line_type(model.case, "steel")
    assert ms.lineTypes["steel"]["w"] == pytest.approx(lt.weight, rel=1e-12)
    assert ms.lineTypes["steel"]["EA"] == pytest.approx(lt.EA, rel=1e-12)


def test_fairlead_and_anchor_forces(paper):
    """(a) End forces: MoorPy's catenary, skmoor's catenary and skmoor's FE static
    reactions (11 elements) agree within 1e-4 (measured: ~1e-10)."""
    model, x = paper
    ms, _ = moorpy_system(model, q=model.system.q(x))
    fair, anchor = model.system.reactions(x)
    for k, (line, cat) in enumerate(zip(ms.lineList, model.catenaries)):
        T = cat.T_fairlead
        assert line.TB == pytest.approx(T, rel=1e-4)
        assert np.linalg.norm(fair[k]) == pytest.approx(T, rel=1e-4)
        np.testing.assert_allclose(line.fB, fair[k], rtol=0, atol=1e-4 * T)
        np.testing.assert_allclose(line.fB, cat.fairlead_force(), rtol=0, atol=1e-4 * T)
        assert line.TA == pytest.approx(cat.T_anchor, rel=1e-4)
        np.testing.assert_allclose(line.fA, anchor[k], rtol=0, atol=1e-4 * T)


def test_draft_balances_moorpy_forces(paper):
    """The draft from Eq. 1 balances weight, buoyancy and MoorPy's line pulls."""
    model, x = paper
    _ms, body = moorpy_system(model, q=model.system.q(x))
    rho, g = model.case.water["density"], model.case.water["gravity"]
    length, width, _ = model.case.body["size"]
    volume = length * width * model.draft
    lines = body.getForces(lines_only=True)
    weight = model.body.mass * g
    assert (rho * g * volume - weight + lines[2]) / weight == pytest.approx(0.0, abs=1e-8)
    np.testing.assert_allclose(lines[[0, 1, 3, 4, 5]], 0.0, atol=1e-6 * weight)


def test_mooring_stiffness_matches_moorpy():
    """(b) The 6x6 line stiffness at equilibrium within 1 % on the significant entries.

    At the paper's 11 elements skmoor is 6 % too stiff (see
    test_mooring_stiffness_at_paper_elements), so this uses 40 elements: measured
    errors +0.45 % (surge), +0.44 % (sway), +0.46 % (heave), +0.44 % (roll), +0.45 %
    (pitch), +0.46 % (surge-pitch, sway-roll), below 1e-6 (yaw)."""
    errors, K_sk, K_mp = stiffness_errors(40)
    worst = int(np.argmax(np.abs(errors)))
    assert np.all(np.abs(errors) < 0.01), (
        f"{NAMES[worst]}: skmoor {K_sk[SIGNIFICANT[worst]]:.6g}, MoorPy "
        f"{K_mp[SIGNIFICANT[worst]]:.6g} ({errors[worst]:+.2%})")
    # the other entries vanish in both (symmetric layout, zero static moment)
    others = np.ones((6, 6), bool)
    for i, j in SIGNIFICANT:
        others[i, j] = False
    scale = np.abs(np.diag(K_mp))
    bound = 1e-6 * np.sqrt(np.outer(scale, scale))[others]
    assert np.all(np.abs(K_sk[others]) < bound) and np.all(np.abs(K_mp[others]) < bound)


def test_mooring_stiffness_converges_to_moorpy_at_second_order():
    """The FE stiffness tends to MoorPy's exact catenary stiffness as h^2: the error
    falls fourfold from 20 to 40 elements (yaw, whose error is round-off, aside)."""
    e20 = stiffness_errors(20)[0]
    e40 = stiffness_errors(40)[0]
    keep = [k for k, name in enumerate(NAMES) if name != "yaw"]
    ratio = e20[keep] / e40[keep]
    assert np.all((ratio > 3.6) & (ratio < 4.4)), dict(zip(np.array(NAMES)[keep], ratio))
    assert np.all(e40[keep] > 0)  # approached from above: the discrete line is stiffer


def test_mooring_stiffness_at_paper_elements():
    """The paper's 11 elements within 1 % of MoorPy (mid-point cable quadrature)."""
    errors = stiffness_errors(11)[0]
    assert np.all(np.abs(errors) < 0.01), dict(zip(NAMES, errors))


@pytest.mark.parametrize("law", ["paper", "engineering"])
def test_strain_law_tangent_on_a_stretchy_line(law):
    """Fairlead stiffness of one line strained 4 % (T/EA = 0.04) against MoorPy's
    analytic catenary stiffness (line.KB), within 0.1 %: both of skmoor's laws reproduce
    the elastic catenary's incremental stiffness about its own state (the engineering
    law's S = EA (1 - 1/lambda) keeps EA per unstretched length; measured 2e-5, the
    discretization at 40 elements)."""
    K_sk, line, cat = stretchy_line_stiffness(law)
    assert cat.T_fairlead / cat.EA == pytest.approx(0.04, abs=0.005)
    assert np.linalg.norm(line.fB - cat.fairlead_force()) < 1e-8 * cat.T_fairlead
    np.testing.assert_allclose(K_sk, line.KB, rtol=0, atol=1e-3 * np.abs(line.KB).max())


def stretchy_line_stiffness(law, n_elements=40):
    """(skmoor's 3x3 fairlead stiffness N/m, MoorPy's solved Line, the catenary) of a
    soft line (EA 5e6 N) strained about 4 %, side by side."""
    import moorpy as mp

    anchor, fairlead = np.array([0.0, 0.0, -100.0]), np.array([60.0, 0.0, -10.0])
    lt = LineType(EA=5e6, mass=50.0, diameter=0.1)
    cat = solve_catenary(anchor, fairlead, lt.weight, lt.EA, sag_ratio=1 / 60, seabed_z=-100.0)
    system = System(LineSet([Line.from_catenary(cat, lt, n_elements)], law=law),
                    fairleads="fixed")
    K_sk = condensed_fairlead_stiffness(system, solve_static(system).x)
    ms = mp.System(depth=100.0, rho=lt.rho_water, g=lt.g)
    ms.setLineType(name="stretchy", lineType=dict(m=lt.mass, d_vol=lt.diameter, EA=lt.EA))
    ms.addPoint(1, anchor)
    ms.addPoint(1, fairlead)
    ms.addLine(cat.L, "stretchy", pointA=1, pointB=2)
    ms.initialize()
    line = ms.lineList[0]
    line.staticSolve(tol=1e-12)
    return K_sk, line, cat
