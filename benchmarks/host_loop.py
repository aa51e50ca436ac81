"""A host loop on skmoor's MoorDyn interface against MoorDyn's own, in one process.

The host (tests/run/test_host.py's): a floating body integrated in Python (symplectic
Euler at the coupling step dt) on a deck's coupled point, a 10 s force of 2 MN in surge
and heave. The same loop runs on ``import moordyn`` (MoorDyn v2.7, RK2 at the deck's
dtM = 1 ms) and on ``from skmoor import moordyn`` (implicit steps, ``substeps`` per
coupling step). Printed per deck and setting: each code's wall time per simulated second
(the host's Python included: the whole loop from the first Step to the last, Init
excluded), their ratio (skmoor / MoorDyn, below 1: skmoor faster) and the accuracy it
buys: max |difference| of the fairlead tension's swing T(t) - T(0) over MoorDyn's range
(see test_host.py for why the swing).

Measured (30 s, dt = 0.05 s, a 2-core machine shared with other jobs: the ratios move by
about 0.1 from run to run):

    deck                 substeps  MoorDyn s/s  skmoor s/s  ratio  swing diff / range
    buoy_chain (38)      1         0.0104       0.0048      0.46   4.42 %
    buoy_chain (38)      5         0.0104       0.0056      0.54   0.59 %
    chain_600m (170)     1         0.0360       0.0063      0.18   1.84 %
    chain_600m (170)     5         0.0360       0.0171      0.48   0.15 %

(Init apart: MoorDyn's relaxation 0.3 s / 3.0 s, skmoor's static solve 0.01-0.05 s.) A
Step call runs its substeps in one call of the compiled step; coupled points' motion
reaches it without per-time Python.

Run: ``python benchmarks/host_loop.py [--duration 60] [--dt 0.05]``
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "run"))
sys.path.insert(0, str(ROOT))  # this checkout's skmoor

import moordyn  # noqa: E402
from test_host import START, host_loop  # noqa: E402

from skmoor import moordyn as skmoordyn  # noqa: E402

DECKS = {"buoy_chain (38 segments)": ROOT / "tests" / "decks" / "host" / "buoy_chain.dat",
         "chain_600m (170 segments)": ROOT / "examples" / "decks" / "chain_600m.dat"}


class _InitApart:
    """The library with its Init timed apart (the loop's time is the stepping's)."""

    def __init__(self, lib):
        self.lib, self.init_time = lib, 0.0

    def __getattr__(self, name):
        return getattr(self.lib, name)

    def Init(self, md, x, v):
        started = time.perf_counter()
        out = self.lib.Init(md, x, v)
        self.init_time += time.perf_counter() - started
        return out


def timed(lib, md, duration, dt):
    """(t, tension, wall seconds of the loop less Init, Init's seconds)."""
    proxy = _InitApart(lib)
    started = time.perf_counter()
    t, T, _ = host_loop(proxy, md, duration, dt)
    return t, T, time.perf_counter() - started - proxy.init_time, proxy.init_time


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=60.0)
    parser.add_argument("--dt", type=float, default=0.05, help="the coupling step, s")
    args = parser.parse_args(argv)
    os.chdir(tempfile.mkdtemp())  # MoorDyn writes next to the deck / in the cwd
    print(f"host loop, {args.duration:g} s at a coupling step of {args.dt:g} s "
          f"(wall s per simulated s; ratio skmoor / MoorDyn)")
    print("| deck | MoorDyn | skmoor substeps | skmoor | ratio | swing diff / range | "
          "Init MoorDyn / skmoor (s) |")
    print("|---|---|---|---|---|---|---|")
    warm = skmoordyn.Create(DECKS["buoy_chain (38 segments)"], substeps=2)
    timed(skmoordyn, warm, 1.0, args.dt)  # compiled code loaded before the timings
    for name, deck in DECKS.items():
        copy = Path.cwd() / deck.name  # MoorDyn writes its outputs next to its deck
        copy.write_text(deck.read_text())
        md = moordyn.Create(str(copy))
        t, T_md, wall_md, init_md = timed(moordyn, md, args.duration, args.dt)
        moordyn.Close(md)
        span = np.ptp(T_md)
        for substeps in (1, 2, 5):
            sk = skmoordyn.Create(deck, substeps=substeps)
            _, T_sk, wall_sk, init_sk = timed(skmoordyn, sk, args.duration, args.dt)
            skmoordyn.Close(sk)
            swing = np.max(np.abs((T_sk - T_sk[0]) - (T_md - T_md[0]))) / span
            print(f"| {name} | {wall_md / args.duration:.4f} | {substeps} | "
                  f"{wall_sk / args.duration:.4f} | {wall_sk / wall_md:.2f} | {swing:.2%} | "
                  f"{init_md:.2f} / {init_sk:.2f} |")
    print(f"(Init apart: MoorDyn's initial-condition relaxation, skmoor's static solve; "
          f"the host starts at {START.tolist()})")


if __name__ == "__main__":
    main()
