"""What an exact body costs: the paper's case with its box at rotations='exact' against
the same case at rotations='small', side by side in one process.

The run: the paper's case from its static state, F_x = 1e5 sin(1.6 t) N, ``--duration``
s at the case's step (50 ms). Each pair runs small then exact (interleaved, so that a
change of the machine's load hits both), best of ``--repeats`` pairs by process time
(everything from the built model to the recorded results: static solve, modes, time
loop). Printed: the two times and their ratio exact / small.

Run: python benchmarks/exact_bodies.py [--duration 100] [--repeats 3] [--write-docs]
(against another source tree: PYTHONPATH=that/tree python benchmarks/exact_bodies.py,
the script imports skmoor from PYTHONPATH first).
"""
from __future__ import annotations

import argparse
import os
import sys
import time
import warnings
from pathlib import Path

if not os.environ.get("PYTHONPATH"):  # skmoor from this source tree
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import skmoor  # noqa: E402
from skmoor.io.case import paper_case  # noqa: E402
from skmoor.run.recorder import PythonStepWarning  # noqa: E402


def timed_run(rotations: str, duration: float) -> tuple[float, bool]:
    """Process time (s) of one run of the paper's case at ``rotations``, and whether its
    step ran in Python (a PythonStepWarning) rather than compiled."""
    model = skmoor.build(paper_case())
    model.system.bodies[0].rotations = rotations  # the box: its hull is set
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", PythonStepWarning)
        started = time.process_time()
        results = skmoor.simulate(model, duration=duration, progress=False)
        elapsed = time.process_time() - started
    if results.meta["stopped"] is not None:
        raise RuntimeError(f"{rotations}: {results.meta['stopped']}")
    return elapsed, any(issubclass(w.category, PythonStepWarning) for w in caught)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=100.0, help="simulated s")
    parser.add_argument("--repeats", type=int, default=3, help="interleaved pairs")
    parser.add_argument("--write-docs", action="store_true",
                        help="write the ratio into docs/speed.md")
    args = parser.parse_args(argv)
    timed_run("exact", 1.0)  # compile and warm the caches first
    best = {"small": float("inf"), "exact": float("inf")}
    python_step = {}
    for _ in range(args.repeats):
        for rotations in ("small", "exact"):
            elapsed, python_step[rotations] = timed_run(rotations, args.duration)
            best[rotations] = min(best[rotations], elapsed)
    steps = {k: "Python" if v else "compiled" for k, v in python_step.items()}
    print(f"skmoor {skmoor.__file__}")
    print(f"paper case, {args.duration:g} s: small {best['small']:.3f} s, exact "
          f"{best['exact']:.3f} s (process time, best of {args.repeats})")
    ratio = best["exact"] / best["small"]
    print(f"ratio exact / small: {ratio:.2f} (steps: exact {steps['exact']}, small "
          f"{steps['small']})")
    if args.write_docs:
        from _cases import write_block

        write_block(Path(__file__).resolve().parents[1] / "docs" / "speed.md",
                    "exact_bodies.py ratio",
                    f"A body with exact large rotations costs {ratio:.1f} times the "
                    f"small-rotation model on the paper's case ({args.duration:g} s from the "
                    f"built model, best of {args.repeats} interleaved pairs; the exact body's "
                    f"step runs {steps['exact']}, the small one's {steps['small']}).")


if __name__ == "__main__":
    main()
