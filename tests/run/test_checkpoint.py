"""Checkpoints of a run (skmoor.simulate / `skmoor run` with checkpoint_every and restart):
a run restarted from a checkpoint file repeats the uninterrupted run to 1e-12.

The 50 m chain deck heaved 2 m at 10 s (examples/decks/chain_50m.dat: the sea bed,
drag, added mass) and a viscoelastic rope (its creep strain: a term that keeps its
history, checkpointed with it). Compared at every sample after the
restart: the fairlead tensions and the whole line state (u), against the uninterrupted
run with checkpoints and against the plain run (the batched compiled step)."""
from pathlib import Path

import numpy as np
import pytest

import skmoor
from skmoor.io.deck import read_deck
from skmoor.model.from_deck import heave_motion

DECK = Path(__file__).parents[2] / "examples" / "decks" / "chain_50m.dat"


def chain(motion=None):
    if motion is None:
        motion, _ = heave_motion(read_deck(DECK), 2.0, 10.0)
    return skmoor.build(DECK, motion=motion)


def after(results, t0):
    keep = results.t >= t0 - 1e-9
    return results.t[keep], results.fairlead_tension[keep], results.displacement[keep]


def test_restart_repeats_the_run(tmp_path):
    settings = dict(dt=0.05, output_interval=0.1, progress=False)
    first = skmoor.simulate(chain(), duration=3.0, checkpoint_every=1.5,
                            checkpoint=tmp_path / "c.bin", **settings)
    assert first.meta["stopped"] is None
    whole = skmoor.simulate(chain(), duration=6.0, checkpoint_every=3.0,
                            checkpoint=tmp_path / "whole.bin", **settings)
    plain = skmoor.simulate(chain(), duration=6.0, **settings)
    again = skmoor.simulate(chain(), duration=6.0, restart=tmp_path / "c.bin", **settings)
    assert again.t[0] == pytest.approx(3.0, abs=1e-12) and again.t[-1] == pytest.approx(6.0)
    t, T, u = after(whole, 3.0)
    scale = np.max(T)
    assert np.array_equal(again.t, t)
    assert np.max(np.abs(again.fairlead_tension - T)) <= 1e-12 * scale
    assert np.max(np.abs(again.displacement - u)) <= 1e-12 * np.max(np.abs(u))
    _, T_plain, _ = after(plain, 3.0)  # the batched compiled step: the same arithmetic
    assert np.max(np.abs(again.fairlead_tension - T_plain)) <= 1e-12 * scale
    swing = np.ptp(T)
    assert swing > 5e4  # the heave moves the tension (about 90 kN from 3 to 6 s)


def test_restart_refuses_another_model(tmp_path):
    skmoor.simulate(chain(), duration=0.5, dt=0.05, checkpoint_every=0.5,
                    checkpoint=tmp_path / "c.bin", progress=False)
    with pytest.raises(ValueError, match="dt = 0.05 s, not of this model"):
        skmoor.simulate(chain(), duration=1.0, dt=0.02, restart=tmp_path / "c.bin",
                        progress=False)
    (tmp_path / "junk.bin").write_bytes(b"not a checkpoint")
    with pytest.raises(ValueError, match="not a checkpoint"):
        skmoor.simulate(chain(), duration=1.0, dt=0.05, restart=tmp_path / "junk.bin",
                        progress=False)


def test_restart_with_a_memory_term(tmp_path):
    """A viscoelastic rope (MoorDyn's EA_s|EA_d, BA|BA_D: the creep strain a term keeps
    in time, tests/lines/test_creep.py's deck) stretched harmonically: its creep state is
    in the checkpoint, the restarted tension the uninterrupted one to 1e-12."""
    from test_creep import TAU, deck

    path = deck(tmp_path / "sine.dat", segments=2, options="")

    def rope():
        return skmoor.build(path, motion=lambda t: np.array([0.01 * (1 - np.cos(t / TAU)),
                                                             0.0, 0.0]))
    assert rope().system.committing  # the creep term keeps a history
    settings = dict(dt=0.02 * TAU, output_interval=0.02 * TAU, progress=False)
    skmoor.simulate(rope(), duration=2 * TAU, checkpoint_every=2 * TAU,
                    checkpoint=tmp_path / "c.bin", **settings)
    whole = skmoor.simulate(rope(), duration=4 * TAU, checkpoint_every=4 * TAU,
                            checkpoint=tmp_path / "w.bin", **settings)
    again = skmoor.simulate(rope(), duration=4 * TAU, restart=tmp_path / "c.bin", **settings)
    t, T, _ = after(whole, 2 * TAU)
    assert np.array_equal(again.t, t)
    assert np.ptp(T) > 1e4  # the creep moves the tension
    assert np.max(np.abs(again.fairlead_tension - T)) <= 1e-12 * np.max(np.abs(T))


def test_cli_checkpoint_and_restart(tmp_path):
    """`skmoor run DECK --checkpoint-every S` writes OUT/checkpoint.bin; `--restart FILE`
    goes on from it: its time series are the uninterrupted run's from there on."""
    from skmoor.cli import main

    common = [str(DECK), "--heave", "2", "--period", "10", "--dt", "0.05",
              "--output-interval", "0.1", "--no-export", "--no-animation", "--quiet"]
    assert main(["run", *common, "--out", str(tmp_path / "a"), "--duration", "2",
                 "--checkpoint-every", "2"]) == 0
    assert (tmp_path / "a" / "checkpoint.bin").is_file()
    assert main(["run", *common, "--out", str(tmp_path / "b"), "--duration", "4",
                 "--checkpoint-every", "4"]) == 0
    assert main(["run", *common, "--out", str(tmp_path / "c"), "--duration", "4",
                 "--restart", str(tmp_path / "a" / "checkpoint.bin")]) == 0
    whole = np.genfromtxt(tmp_path / "b" / "timeseries.csv", delimiter=",", names=True)
    again = np.genfromtxt(tmp_path / "c" / "timeseries.csv", delimiter=",", names=True)
    keep = whole["t"] >= 2.0 - 1e-9
    np.testing.assert_array_equal(again["t"], whole["t"][keep])
    column = "fairlead_tension_line1"
    assert np.max(np.abs(again[column] - whole[column][keep])) <= 1e-12 * np.max(whole[column])
    assert main(["run", *common, "--out", str(tmp_path / "d"), "--duration", "4",
                 "--restart", str(tmp_path / "nothing.bin")]) == 2
