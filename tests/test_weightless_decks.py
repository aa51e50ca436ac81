"""MoorDyn decks with g = 0 (MoorDyn's body tests have several): run in still water with
nothing weighed; refused, naming the option and its deck line, when they ask for waves."""
from pathlib import Path
import warnings

import numpy as np
import pytest

import skmoor

DECK = Path(__file__).parent / "decks" / "bodies" / "turning_body.dat"
GRAVITY = "9.80665   g               gravity (m/s2)"


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
