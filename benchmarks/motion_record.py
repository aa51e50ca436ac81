"""A 12,000-row motion record against the same motion as a function, in one process.

The deck: tests/decks/seabed/chain_semi.dat (a semisubmersible's three chains, their
fairleads three coupled points: 9 coupled DOFs). The motion: surge 2 sin(2 pi t / 10) m
and heave 1 sin(2 pi t / 10) m of the three fairleads, faded in over the first period,
given (a) as a :class:`skmoor.Motion` with its closed-form velocity and acceleration and
(b) as a record of 12,000 rows (0.01 s) read by :func:`skmoor.read_motion` (a cubic
spline, :class:`skmoor.Record`). Printed: each run's wall time (best of ``--repeats``),
their ratio (record / function; the target: within 1.2) and the largest
difference of the fairlead tensions over the swing.

Measured (30 s, best of 3, a 2-core machine shared with other jobs): function 0.086 s,
record 0.089 s, ratio 1.03; tensions 1.5e-7 of the swing apart.

Run: ``python benchmarks/motion_record.py [--duration 30] [--repeats 3]``
"""
from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # this checkout's skmoor

import skmoor  # noqa: E402

DECK = ROOT / "tests" / "decks" / "seabed" / "chain_semi.dat"
PERIOD, SURGE, HEAVE = 10.0, 2.0, 1.0


def analytic():
    """The motion as a vectorized Motion: position, velocity, acceleration (9 DOFs)."""
    w = 2 * np.pi / PERIOD
    shape = np.tile([SURGE, 0.0, HEAVE], 3)

    def scaled(f):
        return lambda t: np.multiply.outer(f(np.asarray(t, float)), shape)
    motion = skmoor.Motion(scaled(lambda t: np.sin(w * t)), scaled(lambda t: w * np.cos(w * t)),
                           scaled(lambda t: -w * w * np.sin(w * t)), vectorized=True)
    return skmoor.fade_in(motion, PERIOD)


def run(motion, duration):
    model = skmoor.build(DECK, motion=motion)
    eq = skmoor.equilibrium(model)
    started = time.perf_counter()
    results = skmoor.simulate(model, duration=duration, dt=0.05, progress=False, eq=eq)
    return time.perf_counter() - started, results


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=30.0)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    function = analytic()
    times = np.arange(12_000) * 0.01
    table = np.column_stack([times, function(times)])
    path = Path(tempfile.mkdtemp()) / "motion.csv"
    np.savetxt(path, table, delimiter=",")
    record = skmoor.read_motion(path, 9)
    run(function, 1.0)  # compile and warm up
    best = {}
    for name, motion in (("function", function), ("record", record)):
        walls = []
        for _ in range(args.repeats):
            wall, results = run(motion, args.duration)
            walls.append(wall)
        best[name] = (min(walls), results.fairlead_tension)
    swing = np.ptp(best["function"][1], axis=0).max()
    diff = np.max(np.abs(best["record"][1] - best["function"][1])) / swing
    print(f"{args.duration:g} s of {DECK.name}, dt = 0.05 s, best of {args.repeats}:")
    print(f"  motion as a function:        {best['function'][0]:.3f} s")
    print(f"  12,000-row record (spline):  {best['record'][0]:.3f} s")
    print(f"  ratio record / function:     {best['record'][0] / best['function'][0]:.2f}")
    print(f"  fairlead tensions differ by  {diff:.2e} of the swing")


if __name__ == "__main__":
    main()
