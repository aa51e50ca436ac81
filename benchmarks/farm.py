"""A farm's fixed costs: build, statics and modes of N platforms' moorings, peak memory.

Each platform is held by three catenary chains as VolturnUS-S is (850 m of R3 chain,
685 kg/m, EA 3.27e9 N, in 200 m of water, anchors 837.6 m from the centre, fairleads
58 m out at 14 m draft, 50 segments each); the platforms stand 2 km apart on a square
grid and their fairleads are coupled points (the platforms' motions are the host's). The
deck is written to a temporary folder and built as ``skmoor run`` builds it.

Printed: the unknowns, the time of ``skmoor.build`` and of ``skmoor.equilibrium`` (the
static solve and the 12 lowest modes: the lines of identical platforms make one cluster
of close modes, 3 per platform), the lowest periods and the process's peak memory.

Run: ``python benchmarks/farm.py [--platforms 100] [--segments 50]``
"""
from __future__ import annotations

import argparse
import resource
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

import skmoor

HEAD = """farm of {n} platforms, three chains each, driven fairleads
---------------------- LINE TYPES ----------------------------------
TypeName  Diam   Mass/m  EA      BA/-zeta  EI  Cd    Ca    CdAx  CaAx
(name)    (m)    (kg/m)  (N)     (N-s/-)   (-) (-)   (-)   (-)   (-)
chain     0.333  685.0   3.27e9  -1.0      0   1.11  0.82  0.2   0.27
---------------------- POINTS --------------------------------------
ID  Attachment  X  Y  Z  Mass  Volume  CdA  Ca
(#) (word)  (m)  (m)  (m)  (kg)  (m^3)  (m^2)  (-)"""
ANCHOR_RADIUS, FAIRLEAD_RADIUS, DRAFT, DEPTH, LENGTH, SPACING = 837.6, 58.0, 14.0, 200.0, 850.0, 2000.0


def farm_deck(platforms: int, segments: int, folder: Path) -> Path:
    """A MoorDyn deck of ``platforms`` moorings on a square grid; its path."""
    rows, lines = [HEAD.format(n=platforms)], []
    side = int(np.ceil(np.sqrt(platforms)))
    for k in range(platforms):
        cx, cy = SPACING * (k % side), SPACING * (k // side)
        for j in range(3):
            angle = 2 * np.pi * j / 3
            c, s = np.cos(angle), np.sin(angle)
            anchor, fairlead = 2 * len(lines) + 1, 2 * len(lines) + 2
            rows.append(f"{anchor} Fixed {cx + ANCHOR_RADIUS * c:.3f} "
                        f"{cy + ANCHOR_RADIUS * s:.3f} {-DEPTH} 0 0 0 0")
            rows.append(f"{fairlead} Coupled {cx + FAIRLEAD_RADIUS * c:.3f} "
                        f"{cy + FAIRLEAD_RADIUS * s:.3f} {-DRAFT} 0 0 0 0")
            lines.append((anchor, fairlead))
    rows += ["---------------------- LINES ---------------------------------------",
             "ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs",
             "(#) (name) (#) (#) (m) (-) (-)"]
    rows += [f"{i + 1} chain {a} {b} {LENGTH} {segments} -" for i, (a, b) in enumerate(lines)]
    rows += ["---------------------- OPTIONS -------------------------------------",
             f"{DEPTH} WtrDpth", "------------------------- END --------------------------------"]
    path = folder / "farm.dat"
    path.write_text("\n".join(rows) + "\n")
    return path


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--platforms", type=int, default=100)
    parser.add_argument("--segments", type=int, default=50)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        deck = farm_deck(args.platforms, args.segments, Path(folder))
        started = time.perf_counter()
        model = skmoor.build(deck)
        built = time.perf_counter() - started
        started = time.perf_counter()
        eq = skmoor.equilibrium(model)
        solved = time.perf_counter() - started
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB on Linux
    print(f"{args.platforms} platforms, {3 * args.platforms} lines of {args.segments} "
          f"segments: {model.system.n} unknowns")
    print(f"build {built:.1f} s, statics and 12 modes {solved:.1f} s, peak memory {peak:.0f} MB")
    print("lowest periods: " + ", ".join(f"{T:.4f}" for T in eq.modes.periods[:3]) + " s")


if __name__ == "__main__":
    main()
