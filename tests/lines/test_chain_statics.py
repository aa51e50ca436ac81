"""The quasi-static chain set MoorDyn validates against OrcaFlex (MoorDyn-C
tests/quasi_static_chain.cpp and tests/Mooring/WD0050_Chain.txt, WD0200_Chain.txt,
WD0600_Chain.txt): a 0.252 m (volume-equivalent) chain, 390 kg/m, EA = 1.674e9 N, in
water of 1025 kg/m3, anchor on the sea bed, fairlead at z = 0. The input files do not
set g, so MoorDyn uses its default 9.80665 m/s2 (source/MoorDyn2.cpp), OrcaFlex's
default too. skmoor's static FE solve with the sea-bed term, from a stress-free L-shaped
line (laid straight from the anchor, then straight up to the fairlead), is held against
OrcaFlex's static fairlead and anchor tensions (2 %) and against the analytic elastic
catenary with touchdown (0.1 %)."""
import numpy as np
import pytest
from scipy.optimize import brentq

from skmoor.coupling.system import System
from skmoor.lines.catenary import solve_catenary
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.sea.seabed import Seabed, seabed_term
from skmoor.solvers.statics import solve_static

CHAIN = LineType(EA=1.674e9, mass=390.0, diameter=0.252, rho_water=1025.0, g=9.80665)
# depth (m), anchor distance (m), length (m), OrcaFlex static fairlead / anchor tension (kN)
CASES = {"WD0050": (50.0, 400.0, 410.0, 991.6, 826.2),
         "WD0200": (200.0, 700.0, 760.0, 2065.4, 1402.2),
         "WD0600": (600.0, 1500.0, 1700.0, 5232.6, 3244.2)}


def l_shaped(depth, span, length, n):
    """n + 1 points: straight along the bed from the anchor (x = span), then straight up to
    the fairlead at the origin, the corner a node, total length ``length``."""
    laid = brentq(lambda b: b + np.hypot(span - b, depth) - length, 0.0, span)
    n_laid = round(n * laid / length)
    corner = [span - laid, 0.0, -depth]
    return np.concatenate([np.linspace([span, 0.0, -depth], corner, n_laid + 1),
                           np.linspace(corner, [0.0, 0.0, 0.0], n - n_laid + 1)[1:]])


@pytest.mark.parametrize("case", CASES)
def test_chain_matches_orcaflex_and_catenary(case):
    depth, span, length, fair_kN, anchor_kN = CASES[case]
    line = Line.from_polyline(l_shaped(depth, span, length, 100), CHAIN)
    lines = LineSet([line], law="engineering")
    system = System(lines, fairleads="fixed", terms=[seabed_term(lines, Seabed(depth))])
    x = solve_static(system, pretension=CHAIN.weight * length).x
    fairlead, anchor = (np.linalg.norm(f[0]) for f in system.reactions(x))
    assert fairlead == pytest.approx(fair_kN * 1e3, rel=0.02)
    assert anchor == pytest.approx(anchor_kN * 1e3, rel=0.02)
    exact = solve_catenary([span, 0.0, -depth], np.zeros(3), CHAIN.weight, CHAIN.EA,
                           length=length, seabed_z=-depth)
    assert fairlead == pytest.approx(exact.T_fairlead, rel=1e-3)
    assert anchor == pytest.approx(exact.T_anchor, rel=1e-3)
