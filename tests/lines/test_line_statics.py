"""Static FE solve of a line from its unstretched, stress-free shape, against Irvine's elastic
catenary (skmoor.lines.catenary) and the exact equilibrium of the discrete chain of links."""
from functools import cache

import numpy as np
import pytest
from scipy.optimize import brentq, fsolve

from skmoor.coupling.system import System
from skmoor.lines.catenary import solve_catenary
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.solvers.statics import solve_static

# The paper's steel line (docs/paper.md): E = 2e11 Pa, D = 0.1 m, 8000 kg/m3 in water;
# 100 m deep, chord at 50 deg. No seabed: the line hangs free between its ends.
STEEL = LineType.steel_rod(0.1)
ANCHOR = np.array([-100.0 / np.tan(np.radians(50.0)), 0.0, -100.0])
FAIRLEAD = np.zeros(3)
CHORD = np.linalg.norm(FAIRLEAD - ANCHOR)
EZ = np.array([0.0, 0.0, 1.0])


def catenary(case):
    """Irvine's solution: near-taut (sag ratio 1/60, as the paper) or slack (L = 1.2 chord)."""
    given = dict(sag_ratio=1 / 60) if case == "near_taut" else dict(length=1.2 * CHORD)
    return solve_catenary(ANCHOR, FAIRLEAD, STEEL.weight, STEEL.EA, **given)


def parabola_chain(L, n):
    """n + 1 points from ANCHOR to FAIRLEAD, equally spaced in arclength on a parabola
    that sags below the chord, whose chords add up to L."""
    chord = FAIRLEAD - ANCHOR
    down = -EZ + chord * chord[2] / CHORD**2
    down /= np.linalg.norm(down)  # in the vertical plane, normal to the chord
    t = np.linspace(0.0, 1.0, 4001)[:, None]

    def points(sag):
        curve = ANCHOR + t * chord + 4 * sag * t * (1 - t) * down
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(curve, axis=0), axis=1))])
        at = np.linspace(0.0, arc[-1], n + 1)
        return np.stack([np.interp(at, arc, curve[:, k]) for k in range(3)], axis=1)

    sag = brentq(lambda d: np.linalg.norm(np.diff(points(d), axis=0), axis=1).sum() - L,
                 1e-9 * CHORD, CHORD, xtol=1e-14)
    return points(sag)


@cache
def fe_solve(case, n, law="engineering"):
    """(stress-free Line, fairlead force, anchor force) of the static FE solve, N."""
    line = Line.from_polyline(parabola_chain(catenary(case).L, n), STEEL)
    system = System(LineSet([line], law=law), fairleads="fixed")
    sol = solve_static(system, pretension=STEEL.weight * line.length, xtol=1e-11)
    fairlead, anchor = system.reactions(sol.x)
    return line, fairlead[0], anchor[0]


def discrete_chain(h, w, EA, guess):
    """Fairlead and anchor forces (N) of the exact equilibrium of n straight elastic links
    (unstretched lengths h, tension EA * strain) from ANCHOR to FAIRLEAD, loaded by the
    consistent nodal weights w (h_left + h_right) / 2, found by shooting on (H, V_0)."""
    horizontal = (FAIRLEAD - ANCHOR) * [1, 1, 0]
    horizontal /= np.linalg.norm(horizontal)
    nodal = w * (h[:-1] + h[1:]) / 2  # interior nodes

    def links(p):
        H, V0 = p
        V = V0 + np.concatenate([[0.0], np.cumsum(nodal)])
        F = H * horizontal + V[:, None] * EZ  # tension vectors, anchor -> fairlead
        T = np.linalg.norm(F, axis=1)
        return F, (h * (1 + T / EA) / T) @ F  # link forces, reach of the chain

    scale = np.array([guess[0], guess[1] or guess[0]])
    p = fsolve(lambda q: (links(q * scale)[1] - (FAIRLEAD - ANCHOR))[[0, 2]] / CHORD, [1, 1],
               xtol=1e-12) * scale
    F, reach = links(p)
    assert np.allclose(reach, FAIRLEAD - ANCHOR, rtol=0, atol=1e-10 * CHORD)
    return -(F[-1] + w * h[-1] / 2 * EZ), F[0] - w * h[0] / 2 * EZ


def relative_errors(case, n, law="engineering"):
    """(fairlead, anchor) relative error of the FE end tensions against Irvine (signed)."""
    exact = catenary(case)
    _, fairlead, anchor = fe_solve(case, n, law)
    return np.array([np.linalg.norm(fairlead) / exact.T_fairlead - 1,
                     np.linalg.norm(anchor) / exact.T_anchor - 1])


@pytest.mark.parametrize("case", ["near_taut", "slack"])
def test_fe_solve_is_the_equilibrium_of_its_discrete_chain(case):
    """Same end forces (1e-8) as the discrete chain of links solved by shooting."""
    line, fairlead, anchor = fe_solve(case, 10)
    exact = catenary(case)
    chain_fairlead, chain_anchor = discrete_chain(
        np.diff(line.s), STEEL.weight, STEEL.EA, (exact.H, exact.V_anchor))
    scale = exact.T_fairlead
    np.testing.assert_allclose(fairlead, chain_fairlead, rtol=0, atol=1e-8 * scale)
    np.testing.assert_allclose(anchor, chain_anchor, rtol=0, atol=1e-8 * scale)


@pytest.mark.parametrize("case", ["near_taut", "slack"])
def test_end_tensions_converge_to_irvine_at_second_order(case):
    """FE end tensions -> Irvine's T_fairlead, T_anchor with error ~ h^2 (order 1.8 - 2.2)."""
    counts = np.array([10, 20, 40, 80])
    errors = np.abs([relative_errors(case, n) for n in counts])
    for end in range(2):
        order = -np.polyfit(np.log(counts), np.log(errors[:, end]), 1)[0]
        assert 1.8 < order < 2.2, (case, end, order, errors[:, end])
    # Each element's chord is shorter than its arc by kappa^2 h^3 / 24, which takes 1 / n^2 of
    # the sag slack (L - chord) of a near-taut line: its tension errs by ~1 / (2 n^2) = 0.12 %
    # at n = 20. The slack line is within 0.1 % at 20 elements, both within 0.1 % at 40.
    assert np.all(errors[counts == 20] < (1.5e-3 if case == "near_taut" else 1e-3))
    assert np.all(errors[counts == 40] < 1e-3)


@pytest.mark.parametrize("case", ["near_taut", "slack"])
def test_paper_strain_law_differs_from_irvine_by_order_T_over_EA(case):
    """Eq. 6 (S = EA eps, Green strain) vs Irvine: end tensions within 3 T/EA, both on the
    same mesh and after Richardson extrapolation of the FE to h -> 0."""
    bound = 3 * catenary(case).T_fairlead / STEEL.EA
    same_mesh = [np.linalg.norm(fe_solve(case, 20, "paper")[k])
                 / np.linalg.norm(fe_solve(case, 20, "engineering")[k]) - 1 for k in (1, 2)]
    assert np.all(np.abs(same_mesh) < bound)
    extrapolated = (4 * relative_errors(case, 40, "paper") - relative_errors(case, 20, "paper")) / 3
    assert np.all(np.abs(extrapolated) < bound), (extrapolated, bound)
