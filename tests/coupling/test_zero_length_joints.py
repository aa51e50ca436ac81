"""Bending lines joined by MoorDyn's zero-length Free rods (NumSegs 0): MoorDyn clamps
both lines to the node's direction and turns it to balance their end moments, so the
joint carries the bending moment (skmoor: a smooth joint of the two lines, one shared
end tangent).

Independent numbers: Euler-Bernoulli's cantilever (tip and mid-span deflection, the
root and mid-span moments, the first natural frequency with a tip mass). A joint that
pinned the lines (a hinge at mid-span) makes the outer half a mechanism: no static
state, and a first frequency of zero. The deck is tests/decks/rods/jointed_cantilever.dat.
"""
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

import skmoor
from skmoor.run.equilibrium import equilibrium

DECK = Path(__file__).parents[1] / "decks" / "rods" / "jointed_cantilever.dat"
G, EI, L, MASS, TIP = 9.80665, 1e8, 10.0, 100.0, 50.0  # N m2, m, kg/m, kg


def deflection(x):
    """Euler-Bernoulli cantilever under its weight w and the tip load P at x (m)."""
    w, P = MASS * G, TIP * G
    return (w * x**2 * (6 * L**2 - 4 * L * x + x**2) / (24 * EI)
            + P * x**2 * (3 * L - x) / (6 * EI))


def moment(x):
    w, P = MASS * G, TIP * G
    return w * (L - x) ** 2 / 2 + P * (L - x)


@pytest.mark.filterwarnings("ignore:point rod1")
@pytest.mark.parametrize("wiring", ["A to B", "B to A"])
def test_cantilever_across_a_zero_length_rod_bends_as_one_beam(wiring, tmp_path):
    """Two 5 m bending lines (4 elements each) clamped on a fixed rod, joined at mid-span
    by a zero-length Free rod, a 50 kg tip mass, in air: the tip and the joint sag as
    one Euler-Bernoulli beam's w x^2 (6L^2 - 4Lx + x^2) / 24EI + P x^2 (3L - x) / 6EI
    within 3e-4 (the elastica's O(theta^2) at a tip slope of 0.019 rad: 1.9e-4), the
    clamp's moment w L^2/2 + P L and the joint's w (L/2)^2/2 + P L/2, each line's moment
    on the joint equal and opposite, within 1e-4; the first bending frequency (in and
    out of plane) that of a cantilever with a tip mass, 1 + cos bL cosh bL + (M / mL) bL
    (cos bL sinh bL - sin bL cosh bL) = 0, within 3e-4. Wired either way through the
    rod: the first line onto its end A and the second off its end B (both along the
    rod's direction q in MoorDyn), or onto B and off A (both along -q)."""
    deck = DECK
    if wiring == "B to A":
        deck = tmp_path / DECK.name
        text = DECK.read_text()
        for old, new in (("R1B      R2A", "R1B      R2B"), ("R2B      1 ", "R2A      1 ")):
            assert old in text
            text = text.replace(old, new)
        deck.write_text(text)
    model = skmoor.build(deck)
    assert {p.name: p.smooth for p in model.network.points}["rod2"]
    eq = equilibrium(model, n_modes=2)
    system, lines = model.system, model.lines
    u = system.full_displacement(eq.x)

    def sag(node):
        return lines.points[node][2] - (lines.points[node] + u[lines.nodal_dofs[node]])[2]

    assert sag(lines.fairlead_nodes[1]) == pytest.approx(deflection(L), rel=3e-4)
    assert sag(lines.fairlead_nodes[0]) == pytest.approx(deflection(L / 2), rel=3e-4)
    on_b, on_a = system.end_moments(u, None)
    assert np.abs(on_a[0]) == pytest.approx([0.0, moment(0.0), 0.0], rel=1e-4, abs=1e-6)
    assert np.abs(on_b[0]) == pytest.approx([0.0, moment(L / 2), 0.0], rel=1e-4, abs=1e-6)
    np.testing.assert_allclose(on_b[0], -on_a[1], rtol=1e-9, atol=1e-6)
    ratio = TIP / (MASS * L)
    bL = brentq(lambda b: 1 + np.cos(b) * np.cosh(b)
                + ratio * b * (np.cos(b) * np.sinh(b) - np.sin(b) * np.cosh(b)), 0.5, 1.875)
    omega = bL**2 * np.sqrt(EI / (MASS * L**4))
    np.testing.assert_allclose(eq.modes.omega, [omega, omega], rtol=3e-4)
