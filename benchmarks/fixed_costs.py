"""Fixed costs of a process: from the interpreter's start to the paper case's static state.

Each stage runs in a fresh interpreter (best of ``--repeats``), so that nothing is cached
in memory; skmoor's bytecode and numba's compiled machine code are on disk first (as after an
install: pip writes the bytecode; a shell with PYTHONDONTWRITEBYTECODE set, as this
project's machines have, would otherwise compile skmoor's sources in every process):

- python: the interpreter alone (``python -c pass``);
- design stack: numpy, scipy.sparse and scikit-fem imported (the packages the design
  card binds the project to, before anything is computed);
- stack: with scipy.linalg and numba, skmoor's floor;
- import skmoor: the package on top of its stack;
- build: ``skmoor.build(skmoor.paper_case())`` (the case's validation, the lines, the
  System; the first call of a compiled kernel loads numba's typing context and its
  cached machine code);
- statics: ``skmoor.equilibrium(model)``.

Printed: each stage's time and its increment; skmoor's own share (import, build and
statics less the stack's import) against the stack's floor; and, side by side, MoorDyn's
Python package from the interpreter's start to its initialized paper case (import,
Create and Init of the same four lines: benchmarks/paper_case.py's deck).

Run: ``python benchmarks/fixed_costs.py [--repeats 5] [--write-docs]``
"""
from __future__ import annotations

import argparse
import compileall
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _cases import ROOT, write_block

STACK = "import numpy, scipy.sparse, scipy.linalg, numba, skfem"
STAGES = {
    "python": "pass",
    "design stack": "import numpy, scipy.sparse, skfem",
    "stack": STACK,
    "import skmoor": "import skmoor",
    "build": "import skmoor; skmoor.build(skmoor.paper_case())",
    "statics": "import skmoor; skmoor.equilibrium(skmoor.build(skmoor.paper_case()))",
}


def wall(code):
    """Wall time (s) of a fresh interpreter running ``code`` (its output discarded)."""
    started = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - started


def best_walls(codes, repeats):
    """{name: best wall time (s)} of each code, run in turn ``repeats`` times (rounds
    interleave the stages, so that a busy moment of the machine does not fall on one)."""
    best = dict.fromkeys(codes, float("inf"))
    for _ in range(repeats):
        for name, code in codes.items():
            best[name] = min(best[name], wall(code))
    return best


def moordyn_code(workdir):
    """Code for a fresh interpreter: MoorDyn's paper deck created and initialized."""
    deck = Path(workdir) / "paper.txt"
    # the deck and the fairlead positions, written once by this process
    sys.path.insert(0, str(ROOT / "benchmarks"))
    sys.path.insert(0, str(ROOT / "tests"))
    import numpy as np
    from paper_case import CoupledBody, Scenario, moordyn_deck
    from peers import chain_length_for

    scenario = Scenario("moordyn-damping")
    body = CoupledBody(scenario)
    model = scenario.model
    static = np.linalg.norm(model.system.reactions(scenario.eq.x)[0], axis=1)
    n = len(model.lines.lines[0].s) - 1
    lengths = [chain_length_for(cat, n, T) for cat, T in zip(model.catenaries, static)]
    moordyn_deck(deck, model, body, lengths, 2.5e-3)
    position, velocity, _ = body.fairleads(body.q0, np.zeros(6))
    return (f"import moordyn; md = moordyn.Create({str(deck)!r}); "
            f"moordyn.Init(md, {position.ravel().tolist()!r}, {velocity.ravel().tolist()!r}); "
            "moordyn.Close(md)")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--write-docs", action="store_true",
                        help="write the table into docs/speed.md")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as workdir:
        codes = {**STAGES, "moordyn": moordyn_code(workdir)}
        compileall.compile_dir(ROOT / "skmoor", quiet=1)  # the bytecode, as pip writes it
        wall(codes["statics"])  # numba's disk cache written, if it is not yet
        times = best_walls(codes, args.repeats)
    moordyn = times.pop("moordyn")
    print(f"fresh interpreters, best of {args.repeats}:")
    previous = None
    for name, t in times.items():
        step = "" if previous is None else f"  (+{t - times[previous]:.3f} s)"
        print(f"  {name:14s} {t:6.3f} s{step}")
        previous = name
    start = times["python"]
    design, stack = times["design stack"] - start, times["stack"] - start
    own, total = times["statics"] - times["stack"], times["statics"] - start
    moordyn -= start
    print(f"\nnumpy + scipy.sparse + scikit-fem alone:              {design:.3f} s")
    print(f"the stack's import (numpy, scipy, numba, scikit-fem): {stack:.3f} s")
    print(f"skmoor's own (import + build + statics on top):    {own:.3f} s")
    print(f"import + build + statics, all:                      {total:.3f} s")
    print(f"\nMoorDyn (import moordyn, Create, Init of the paper's deck): {moordyn:.3f} s")
    print(f"ratio skmoor/MoorDyn, interpreter start to static state: {total / moordyn:.2f}")
    if args.write_docs:
        rows = "\n".join(f"| {name} | {times[name] - start:.2f} s | "
                         f"{times[name] - times[before]:+.2f} s |"
                         for before, name in zip(list(times)[1:], list(times)[2:]))
        write_block(ROOT / "docs" / "speed.md", "fixed_costs.py table",
                    f"| stage (a fresh interpreter, best of {args.repeats}) | from the "
                    "interpreter's start | on the stage before |\n|---|---|---|\n"
                    f"| design stack (numpy, scipy.sparse, scikit-fem) | {design:.2f} s | |\n"
                    f"{rows}\n\nskmoor's own share (its import, build and statics on top of "
                    f"the stack): {own:.2f} s of {total:.2f} s. MoorDyn's Python package "
                    f"imports, creates and initializes the same four lines in {moordyn:.3f} s "
                    "(a compiled library).")


if __name__ == "__main__":
    main()
