"""The IEA 15 MW VolturnUS-S chain mooring's static strength (skipped without the local
mirror of IEA-15-240-RWT, like test_volturnus.py): its 185 mm R3 studless chain (the deck's
volume-equivalent 0.333 m is 1.8 times it) breaks at 0.0223 d^2 (44 - 0.08 d) kN with d in
mm (DNV-OS-E302's grade R3), 22 286 kN; against MoorDyn's published static fairlead
tension, 2439 kN, the safety factor is 9.14."""
import argparse
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import volturnus  # noqa: E402

import skmoor  # noqa: E402
from skmoor.cli import _line_data  # noqa: E402
from skmoor.post.strength import strength  # noqa: E402
from skmoor.run.outputs import summary  # noqa: E402
from skmoor.run.recorder import static_results  # noqa: E402

pytestmark = pytest.mark.skipif(not volturnus.mirror_path().exists(),
                                reason="no local mirror of IEA-15-240-RWT")

D_NOM_MM = 185.0
MBL = 0.0223 * D_NOM_MM**2 * (44 - 0.08 * D_NOM_MM) * 1e3     # N, R3 grade


def test_static_safety_factor_of_each_line(tmp_path):
    model = skmoor.build(volturnus.write_deck("skmoor", 50, 1e-3, tmp_path))
    _line_data(model, argparse.Namespace(mbl=[repr(MBL)], fatigue_curve=["studless-chain"],
                                         d_nom=[repr(D_NOM_MM / 1e3)]))
    r = static_results(model)
    assert MBL == pytest.approx(22.286e6, rel=1e-4)
    rows = strength(r)
    assert len(rows) == 3
    for row in rows.values():
        assert row["where"] == "fairlead"
        assert row["safety_factor"] == pytest.approx(MBL / 2439e3, rel=0.01)
    assert summary(r)["strength"] == rows
