"""MoorDyn decks with g = 0 (MoorDyn's body tests have several): run in still water with
nothing weighed; refused, naming the option and its deck line, when they ask for waves.
Decks with water density 0 (MoorDyn's body_tests/pinnedBody.txt) run in air: nothing
floats, drags or adds mass."""
import warnings
from pathlib import Path

import numpy as np
import pytest

import skmoor

DECK = Path(__file__).parents[1] / "decks" / "bodies" / "turning_body.dat"
GRAVITY = "9.80665   g               gravity (m/s2)"
DENSITY = "1025.0    WtrDnsty        water density (kg/m3)"


def weightless_deck(folder, extra=""):
    text = DECK.read_text()
    assert GRAVITY in text
    path = Path(folder) / "weightless.dat"
    path.write_text(text.replace(GRAVITY, "0         g               no gravity" + extra))
    return path


def test_a_weightless_deck_weighs_nothing(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the taut lines start stretched: by design
        model = skmoor.build(weightless_deck(tmp_path))
    body = model.system.bodies[0]
    assert body.g == 0.0
    assert np.allclose(body.static_force(), 0.0)  # no weight, no buoyancy (its 0.005 m3)
    assert np.allclose(model.system.weight, 0.0)  # the lines' weight load


def test_a_weightless_deck_with_waves_is_refused(tmp_path):
    path = weightless_deck(tmp_path, "\n7         WaveKin         waves from files")
    with pytest.raises(ValueError, match=r"weightless\.dat line \d+: option g = 0: .*waves "
                       r"need gravity"):
        skmoor.build(path)


def deck_in_air(folder, rho="0.0"):
    text = DECK.read_text()
    assert DENSITY in text
    path = Path(folder) / "in_air.dat"
    path.write_text(text.replace(DENSITY, f"{rho}       WtrDnsty        in air"))
    return path


def test_a_deck_in_air_has_no_water(tmp_path):
    """rho = 0: the body weighs its mass (its 0.005 m3 lift nothing) and the lines their
    dry mass per length (MoorDyn's pinnedBody.txt runs so, tests/coupling/test_rods_moordyn.py)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = skmoor.build(deck_in_air(tmp_path))
        wet = skmoor.build(DECK)
    body = model.system.bodies[0]
    assert body.static_force()[2] == pytest.approx(-10.0 * 9.80665, rel=1e-12)
    assert wet.system.bodies[0].static_force()[2] > body.static_force()[2] + 40.0
    for line in model.lines.lines:  # weight per length: the dry one
        assert line.line_type.weight == pytest.approx(line.line_type.mass * 9.80665, rel=1e-12)
    assert np.allclose(model.system.weight.reshape(-1, 3)[:, :2], 0.0)
    assert -model.system.weight.sum() > -wet.system.weight.sum() + 1.0


def test_a_negative_density_is_refused(tmp_path):
    with pytest.raises(ValueError, match=r"in_air\.dat line \d+: option rho = -1: the "
                       r"water density must be positive, or 0"):
        skmoor.build(deck_in_air(tmp_path, "-1.0"))
