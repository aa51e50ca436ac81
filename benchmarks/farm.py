"""A farm: build, statics and modes of N platforms' moorings, peak memory, and the time
loop beside MoorDyn's on the same deck.

Each platform is held by three catenary chains as VolturnUS-S is (850 m of R3 chain,
685 kg/m, EA 3.27e9 N, in 200 m of water, anchors 837.6 m from the centre, fairleads
58 m out at 14 m draft, 50 segments each); the platforms stand 2 km apart on a square
grid and their fairleads are coupled points (the platforms' motions are the host's). With
``--shared`` each platform is also joined to its neighbour in x by a shared line (FAST.Farm's
shared moorings): 1900 m of a polyester-like rope (20 kg/m, EA 1e8 N) between facing
fairleads, sagging about 100 m; with ``--shared-anchors`` every other column is turned by
180 deg and a platform's east leg and its neighbour's west leg end on one anchor midway. The deck is written to a temporary folder and built as
``skmoor run`` builds it.

Printed: the unknowns, the time of ``skmoor.build`` and of ``skmoor.equilibrium`` (the
static solve and the 12 lowest modes: the lines of identical platforms make one cluster
of close modes, 3 per platform), the lowest periods and the process's peak memory.

With ``--run S``: every fairlead surges 5 m / 90 s and heaves 2 m / 12 s (faded in over
12 s) for S s, in skmoor (generalized-alpha, rho_inf 0.5, 250 ms steps) and MoorDyn v2
(RK2 at dtM 7.8 ms, from its own initial catenaries without its dynamic relaxation,
coupled every 1/32 s): the steps each code needs for 1 % of the fairlead tension on one
platform's chains at 50 segments (``benchmarks/volturnus.py``). Timed: skmoor's
``simulate`` after a short run that compiles (its first-compile cost printed apart, ~0
with a warm cache); MoorDyn's ``Step`` calls alone (the script's list building between
them timed apart). The codes run in ``--rounds`` rounds, each round running both (so that
a varying load on a shared machine falls on both alike), one BLAS thread each; each
code's time is its best round, and every round's ratio is printed beside it. Printed:
each code's wall time, the ratio, both codes' mean fairlead tension of the first line
over the last 10 s (a check that they run the same system) and the peak memory. Beside
the time loops, each code's whole run from the deck (the imports apart): skmoor's build,
statics and modes and time loop; MoorDyn's Create, Init and Step calls.

Run: ``python benchmarks/farm.py [--platforms 100] [--segments 50] [--shared]
[--shared-anchors] [--run 60] [--rounds 2] [--write-docs]``
"""
from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")  # one core per code, as MoorDyn runs

import argparse
import resource
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
from _cases import ROOT, quiet, write_block

import skmoor

HEAD = """farm of {n} platforms, three chains each, driven fairleads
---------------------- LINE TYPES ----------------------------------
TypeName  Diam   Mass/m  EA      BA/-zeta  EI  Cd    Ca    CdAx  CaAx
(name)    (m)    (kg/m)  (N)     (N-s/-)   (-) (-)   (-)   (-)   (-)
chain     0.333  685.0   3.27e9  -1.0      0   1.11  0.82  0.2   0.27
rope      0.15   20.0    1.0e8   -1.0      0   1.2   1.0   0.008 0.0
---------------------- POINTS --------------------------------------
ID  Attachment  X  Y  Z  Mass  Volume  CdA  Ca
(#) (word)  (m)  (m)  (m)  (kg)  (m^3)  (m^2)  (-)"""
ANCHOR_RADIUS, FAIRLEAD_RADIUS, DRAFT, DEPTH, LENGTH, SPACING = 837.6, 58.0, 14.0, 200.0, 850.0, 2000.0
SHARED_LENGTH = 1900.0  # m of rope between facing fairleads 1884 m apart
SHARED_ANCHOR_LENGTH = LENGTH + (SPACING / 2 - ANCHOR_RADIUS)  # m: 162.4 m more on the bed
MOORDYN_DT, SKMOOR_DT, COUPLING_DT = 2.0**-7, 0.25, 1 / 32  # s


def farm_deck(platforms: int, segments: int, folder: Path, shared=False, dtM=None,
              shared_anchors=False) -> Path:
    """A MoorDyn deck of ``platforms`` moorings on a square grid (with ``shared``: a
    shared rope from each platform to its neighbour in x; with ``shared_anchors``: every
    other column turned by 180 deg, so that a platform's east leg and its neighbour's west
    leg end on one anchor midway, both 1012.4 m long: the others' suspended length plus
    the longer reach on the bed); its path."""
    rows, lines = [HEAD.format(n=platforms)], []
    side = int(np.ceil(np.sqrt(platforms)))
    midway = {}  # platform -> the anchor it shares with its neighbour to the east
    rope_start = None  # the fairlead of the rope that waits for its end at the next platform

    def point(kind, x, y, z):
        rows.append(f"{len(rows)} {kind} {x:.3f} {y:.3f} {z} 0 0 0 0")
        return len(rows) - 1

    for k in range(platforms):
        column = k % side
        cx, cy = SPACING * column, SPACING * (k // side)
        turned = shared_anchors and column % 2 == 1
        east = None  # the platform's fairlead facing +x, if it has one
        for j in range(3):
            angle = 2 * np.pi * j / 3 + (np.pi if turned else 0.0)
            c, s = np.cos(angle), np.sin(angle)
            length = LENGTH
            if shared_anchors and j == 0 and not turned and column + 1 < side and k + 1 < platforms:
                anchor = midway[k] = point("Fixed", cx + SPACING / 2, cy, -DEPTH)
                length = SHARED_ANCHOR_LENGTH
            elif shared_anchors and j == 0 and turned:
                anchor, length = midway[k - 1], SHARED_ANCHOR_LENGTH
            else:
                anchor = point("Fixed", cx + ANCHOR_RADIUS * c, cy + ANCHOR_RADIUS * s, -DEPTH)
            fairlead = point("Coupled", cx + FAIRLEAD_RADIUS * c, cy + FAIRLEAD_RADIUS * s,
                             -DRAFT)
            lines.append(("chain", anchor, fairlead, length))
            if abs(c - 1.0) < 1e-9:
                east = fairlead
        if shared and column:  # the rope from the west ends on a point facing it
            incoming = lines.index(("rope", rope_start, None, SHARED_LENGTH))
            lines[incoming] = ("rope", rope_start, point("Coupled", cx - FAIRLEAD_RADIUS, cy,
                                                         -DRAFT), SHARED_LENGTH)
        if shared and column + 1 < side and k + 1 < platforms:  # a rope to the east
            rope_start = east if east is not None else point("Coupled", cx + FAIRLEAD_RADIUS,
                                                             cy, -DRAFT)
            lines.append(("rope", rope_start, None, SHARED_LENGTH))  # ends at the neighbour
    rows += ["---------------------- LINES ---------------------------------------",
             "ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs",
             "(#) (name) (#) (#) (m) (-) (-)"]
    rows += [f"{i + 1} {kind} {a} {b} {length} {segments} -"
             for i, (kind, a, b, length) in enumerate(lines)]
    rows += ["---------------------- OPTIONS -------------------------------------",
             f"{DEPTH} WtrDpth"] + ([f"{dtM} dtM"] if dtM else []) + [
             "------------------------- END --------------------------------"]
    path = folder / "farm.dat"
    path.write_text("\n".join(rows) + "\n")
    return path


def fairlead_offset(t):
    """(surge, heave) of every fairlead at t (s), m: 5 m / 90 s and 2 m / 12 s, faded in."""
    fade = 0.5 * (1 - np.cos(np.pi * np.minimum(t / 12.0, 1.0)))
    return 5.0 * fade * np.sin(2 * np.pi * t / 90.0), 2.0 * fade * np.sin(2 * np.pi * t / 12.0)


def motion(n_points):
    """skmoor's coupled-point displacements (3 n_points,) at t."""
    def displacements(t):
        x, z = fairlead_offset(t)
        y = np.zeros(3 * n_points)
        y[0::3], y[2::3] = x, z
        return y
    return displacements


def peak_memory() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # MB (kB on Linux)


def run_skmoor(model, eq, duration):
    """(first-compile s, time loop s, fairlead tension of line 1 over the last 10 s, N)."""
    started = time.perf_counter()
    skmoor.simulate(model, duration=2 * SKMOOR_DT, dt=SKMOOR_DT, progress=False, eq=eq)
    compiled = time.perf_counter() - started
    started = time.perf_counter()
    results = skmoor.simulate(model, duration=duration, dt=SKMOOR_DT, output_interval=0.5,
                              progress=False, eq=eq)
    wall = time.perf_counter() - started
    if results.meta["stopped"]:
        raise RuntimeError(f"skmoor: {results.meta['stopped']}")
    last = results.t >= results.t[-1] - 10.0
    return compiled, wall, float(results.fairlead_tension[last, 0].mean())


def run_moordyn(deck_path, duration):
    """(Step calls s, the script's glue s, fairlead tension of line 1 over the last 10 s,
    Create and Init s)."""
    import moordyn

    deck = skmoor.read_deck(deck_path)
    base = np.array([p.position for p in deck.points if p.kind == "coupled"], float)
    stepping, glue, tension = 0.0, 0.0, []
    with quiet():  # MoorDyn prints its set-up and each step's time
        started = time.perf_counter()
        md = moordyn.Create(str(deck_path))
        try:
            moordyn.Init_NoIC(md, base.ravel().tolist(), [0.0] * base.size)
            setup = time.perf_counter() - started
            line = moordyn.GetLine(md, 1)
            n = moordyn.GetLineN(line)
            for k in range(int(round(duration / COUPLING_DT))):
                started = time.perf_counter()
                t0, t1 = k * COUPLING_DT, (k + 1) * COUPLING_DT
                (x0, z0), (x1, z1) = fairlead_offset(t0), fairlead_offset(t1)
                r = (base + [x0, 0.0, z0]).ravel().tolist()
                u = np.tile([(x1 - x0) / COUPLING_DT, 0.0, (z1 - z0) / COUPLING_DT],
                            len(base)).tolist()
                between = time.perf_counter()
                moordyn.Step(md, r, u, t0, COUPLING_DT)
                stepped = time.perf_counter()
                if t1 >= duration - 10.0:
                    tension.append(np.linalg.norm(moordyn.GetLineNodeForce(line, n)))
                glue += between - started + time.perf_counter() - stepped
                stepping += stepped - between
        finally:
            moordyn.Close(md)
    return stepping, glue, float(np.mean(tension)), setup


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--platforms", type=int, default=100)
    parser.add_argument("--segments", type=int, default=50)
    parser.add_argument("--shared", action="store_true", help="shared lines between neighbours")
    parser.add_argument("--shared-anchors", action="store_true", help="neighbours in x share "
                        "an anchor midway")
    parser.add_argument("--run", type=float, metavar="S", help="also time S s of motion in "
                        "skmoor and MoorDyn")
    parser.add_argument("--rounds", type=int, default=2, help="with --run: rounds of both "
                        "codes (each code's best is its time)")
    parser.add_argument("--write-docs", action="store_true", help="with --run: write the "
                        "table into docs/speed.md")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        deck = farm_deck(args.platforms, args.segments, Path(folder), args.shared,
                         dtM=MOORDYN_DT, shared_anchors=args.shared_anchors)
        anchors = sum(p.kind == "fixed" for p in skmoor.read_deck(deck).points)
        n_points = sum(p.kind == "coupled" for p in skmoor.read_deck(deck).points)
        started = time.perf_counter()
        model = skmoor.build(deck, motion=motion(n_points))
        built = time.perf_counter() - started
        started = time.perf_counter()
        eq = skmoor.equilibrium(model)
        solved = time.perf_counter() - started
        lines = len(model.lines.lines)
        print(f"{args.platforms} platforms, {lines} lines of {args.segments} segments "
              f"({lines - 3 * args.platforms} shared), {anchors} anchors: "
              f"{model.system.n} unknowns")
        print(f"build {built:.1f} s, statics and 12 modes {solved:.1f} s, peak memory "
              f"{peak_memory():.0f} MB")
        print("lowest periods: " + ", ".join(f"{T:.4f}" for T in eq.modes.periods[:3]) + " s")
        if args.run:
            model.solver.update(scheme="generalized-alpha", rho_inf=0.5)
            walls, steppings, setups = [], [], []
            for k in range(args.rounds):
                compiled, wall, tension = run_skmoor(model, eq, args.run)
                stepping, glue, md_tension, setup = run_moordyn(deck, args.run)
                walls.append(wall)
                steppings.append(stepping)
                setups.append(setup)
                print(f"round {k + 1}: skmoor time loop {wall:.1f} s (first compile "
                      f"{compiled:.1f} s apart), MoorDyn Step calls {stepping:.1f} s (the "
                      f"script's glue {glue:.1f} s apart): {wall / stepping:.2f}", flush=True)
            wall, stepping = min(walls), min(steppings)
            print(f"skmoor : {args.run:g} s at {SKMOOR_DT * 1e3:g} ms: time loop {wall:.1f} s "
                  f"(best of {args.rounds}); line 1 fairlead tension {tension / 1e3:.0f} kN")
            print(f"MoorDyn: {args.run:g} s at {MOORDYN_DT * 1e3:g} ms: Step calls "
                  f"{stepping:.1f} s (best of {args.rounds}); line 1 fairlead tension "
                  f"{md_tension / 1e3:.0f} kN; peak memory {peak_memory():.0f} MB")
            print(f"time loop skmoor/MoorDyn = {wall / stepping:.2f} (rounds: "
                  + ", ".join(f"{w / m:.2f}" for w, m in zip(walls, steppings)) + ")")
            whole_sk, whole_md = built + solved + wall, min(setups) + stepping
            print(f"from the deck: skmoor build + statics and modes + time loop {whole_sk:.1f} "
                  f"s, MoorDyn Create + Init + Step calls {whole_md:.1f} s: "
                  f"{whole_sk / whole_md:.2f}")
            shared = lines - 3 * args.platforms
            table = ("| farm | unknowns | build | statics + 12 modes | time loop skmoor / "
                     "MoorDyn, best of the rounds | whole run from the deck skmoor / MoorDyn "
                     "| line 1 fairlead tension skmoor / MoorDyn | peak memory |\n"
                     "|---|---|---|---|---|---|---|---|\n"
                     f"| {args.platforms} platforms, {3 * args.platforms} chains + {shared} "
                     f"shared ropes, {anchors} anchors, {args.segments} segments, "
                     f"{args.run:g} s | "
                     f"{model.system.n:,} | {built:.1f} s | {solved:.1f} s | {wall:.1f} s / "
                     f"{stepping:.1f} s = **{wall / stepping:.2f}** (rounds "
                     + ", ".join(f"{w / m:.2f}" for w, m in zip(walls, steppings))
                     + f") | {whole_sk:.1f} s / {whole_md:.1f} s = {whole_sk / whole_md:.2f} "
                     f"| {tension / 1e3:.0f} / "
                     f"{md_tension / 1e3:.0f} kN | {peak_memory():.0f} MB |")
            if args.write_docs:
                write_block(ROOT / "docs" / "speed.md", "farm.py table", table)


if __name__ == "__main__":
    main()
