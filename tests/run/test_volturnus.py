"""benchmarks/volturnus.py's system, the IEA 15 MW VolturnUS-S chain mooring read from the
IEA-15-240-RWT deck (a local mirror, $SKMOOR_IEA_MIRROR; skipped without it): its static
fairlead tension against the published ones (CableDyn 2437 kN,
OrcaFlex 2427 kN, MoorDyn 2439 kN), and the benchmark's deck as each peer gets it."""
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import volturnus  # noqa: E402

import skmoor  # noqa: E402

pytestmark = pytest.mark.skipif(not volturnus.mirror_path().exists(),
                                reason="no local mirror of IEA-15-240-RWT")


def test_static_fairlead_tension_is_the_published_one(tmp_path):
    """50 segments per line: each fairlead's static tension within 0.5 % of 2437 kN, the
    three lines alike (a wrong depth, weight or length moves it by percents)."""
    model = skmoor.build(volturnus.write_deck("skmoor", 50, 1e-3, tmp_path))
    static = skmoor.static_results(model, skmoor.equilibrium(model))
    tension = np.array([t[0] for t in static.fairlead_tension])
    np.testing.assert_allclose(tension, 2437e3, rtol=5e-3)


def test_each_peer_gets_the_deck_it_reads(tmp_path):
    """The water depth is added, the outputs cleared and each code's own options set."""
    for code, own in (("moordyn", "TmaxIC"), ("cabledyn", "rhoInf"), ("skmoor", None)):
        deck = skmoor.read_deck(volturnus.write_deck(code, 20, 0.001, tmp_path))
        assert deck.option("WtrDpth") == volturnus.DEPTH and not deck.outputs
        assert [line.n_segments for line in deck.lines] == [20, 20, 20]
        if own:
            assert own in deck.options
