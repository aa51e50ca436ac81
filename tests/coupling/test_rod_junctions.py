"""Rods that join lines: MoorDyn's zero-length Free rods (NumSegs 0, its 6-DOF connection
node), read as a massless junction of their lines, and a free body on one rod with
every attachment on the rod's axis (MoorDyn's riser decks), whose spin about that axis
nothing holds in statics.

Independent numbers: the elastic catenary of the uncut line (a massless junction must
not change it), and the buoy's net lift in closed form (Archimedes on the body and on
the rod, halved between its two vertical ropes). The decks are in tests/decks/rods/.
"""
import re
from pathlib import Path

import numpy as np
import pytest

import skmoor
from skmoor.io.deck import read_deck
from skmoor.lines.catenary import solve_catenary
from skmoor.run.equilibrium import equilibrium
from skmoor.run.recorder import static_results

DECKS = Path(__file__).parents[1] / "decks" / "rods"
G, RHO = 9.80665, 1025.0


def statics(path):
    model = skmoor.build(path)
    return model, static_results(model, equilibrium(model, n_modes=1))


def test_zero_length_rod_is_a_massless_junction():
    """zero_length_junction.dat: 60 m + 70 m of chain joined at a zero-length Free rod
    hang as one 130 m elastic catenary (w = (60 - rho pi 0.1^2 / 4) g, EA = 4e8 N):
    fairlead and anchor tensions within 1e-4, the junction on the catenary at 60 m of
    unstretched length within 2 cm (the deck gives it 0.4 m off; given 8 m off, the FE
    solve's move from the parts' reference catenaries costs 1.3e-3). A rod end left
    unjoined, or the rod's 25 kg/m counted on a node, fails."""
    deck = read_deck(DECKS / "zero_length_junction.dat")
    assert deck.rods[0].n_segments == 0
    model, st = statics(DECKS / "zero_length_junction.dat")
    assert [p.name for p in model.network.points if p.kind == "free"] == ["rod1"]
    w = (60.0 - RHO * np.pi * 0.1**2 / 4) * G
    whole = solve_catenary([-80.0, 0.0, -100.0], [0.0, 0.0, -5.0], w, 4e8, length=130.0)
    assert st.fairlead_tension[0][1] == pytest.approx(whole.T_fairlead, rel=1e-4)
    assert st.anchor_tension[0][0] == pytest.approx(whole.T_anchor, rel=1e-4)
    assert st.fairlead_tension[0][0] == pytest.approx(st.anchor_tension[0][1], rel=1e-9)
    eq = equilibrium(model, n_modes=1)
    u = model.system.full_displacement(eq.x)
    lines = model.lines
    junction = lines.points[lines.fairlead_nodes[0]] + u[lines.nodal_dofs[lines.fairlead_nodes[0]]]
    assert np.linalg.norm(junction - whole.position(60.0)) < 0.02


def test_body_on_one_rod_axis_hangs_on_its_ropes():
    """buoy_on_a_rod.dat: a free body (200 kg, 1.5 m3) on a 4 m rod (0.3 m, 40 kg/m),
    held by two vertical ropes at the rod's ends; every attachment on the rod's axis.
    Each rope's top pulls half of the net lift (rho V_body - m + (rho pi d^2 / 4 -
    m_rod) L) g = 7194.6 N, its anchor that less the rope's submerged weight, both within
    1e-6 (without the spin spring there is no statics: nothing holds the body about the
    axis)."""
    _, st = statics(DECKS / "buoy_on_a_rod.dat")
    lift = (RHO * 1.5 - 200.0 + (RHO * np.pi * 0.3**2 / 4 - 40.0) * 4.0) * G
    rope = (3.0 - RHO * np.pi * 0.05**2 / 4) * G * 29.99
    np.testing.assert_allclose(st.fairlead_tension[0], [lift / 2] * 2, rtol=1e-6)
    np.testing.assert_allclose(st.anchor_tension[0], [lift / 2 - rope] * 2, rtol=1e-6)


@pytest.mark.parametrize("old, new, message", [
    ("1  conn  Free  -32  0  -67  -32  0  -67  0", "1  conn  Fixed  -32  0  -67  -32  0  -67  0",
     "NumSegs: 0 makes a zero-length rod (MoorDyn's 6-DOF connection node), supported as a "
     "Free rod only (this one is Fixed)"),
    ("1  conn  Free  -32  0  -67  -32  0  -67  0", "1  conn  Free  -32  0  -67  -32  0  -66  0",
     "NumSegs: 0 (a zero-length rod) needs ends A and B at the same place"),
])
def test_bad_zero_length_rods_name_the_deck_line(tmp_path, old, new, message):
    text = (DECKS / "zero_length_junction.dat").read_text()
    assert old in text
    (tmp_path / "bad.dat").write_text(text.replace(old, new))
    with pytest.raises(ValueError, match=r"bad\.dat line 16: RODS .*" + re.escape(message)):
        read_deck(tmp_path / "bad.dat")
