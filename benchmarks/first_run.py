"""The first run after an install: ``skmoor run`` with an empty numba cache against a warm one.

skmoor's compiled kernels (the cable, the sea bed, the compiled time step) are compiled by
numba on their first call and written to its disk cache; every later process loads them.
This times the paper case's default run (``skmoor run --no-animation --quiet``: build,
statics, modes, the time loop, outputs, export) in fresh processes, in pairs: one with an
empty numba cache (a new ``NUMBA_CACHE_DIR``), one with the cache the previous cold run
filled. The pairs interleave, so that the machine's load falls on both alike; printed: each
pair's cold and warm wall times and the median of their differences, the first run's extra
cost (``skmoor run`` shares that compile with a helper process:
:mod:`skmoor.run.first_compile`).

Run: ``python benchmarks/first_run.py [--pairs 3] [--write-docs]`` (about a minute a pair
on 2 cores; --write-docs: the result into docs/speed.md)
"""
from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

from _cases import ROOT, write_block

COMMAND = [sys.executable, "-c", "import sys, skmoor.cli; sys.exit(skmoor.cli.main())", "run",
           "--no-animation", "--quiet"]


def wall(cache, workdir):
    """Wall time (s) of ``skmoor run`` in a fresh process with numba's cache in ``cache``."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache,
               PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    started = time.perf_counter()
    subprocess.run(COMMAND + ["--out", os.path.join(workdir, "out")], check=True, cwd=workdir,
                   env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - started


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=3, help="cold/warm pairs (default: 3)")
    parser.add_argument("--write-docs", action="store_true", help="the result into "
                        "docs/speed.md")
    args = parser.parse_args()
    extra, walls = [], []
    with tempfile.TemporaryDirectory(prefix="skmoor-first-run-") as workdir:
        for k in range(args.pairs):
            cache = tempfile.mkdtemp(prefix="numba-", dir=workdir)
            cold = wall(cache, workdir)
            warm = wall(cache, workdir)
            shutil.rmtree(cache)
            extra.append(cold - warm)
            walls.append((cold, warm))
            print(f"pair {k + 1}: cold {cold:.1f} s, warm {warm:.1f} s, "
                  f"first-run cost {cold - warm:.1f} s", flush=True)
    pairs = "; ".join(f"{c:.0f} s against {w:.0f} s" for c, w in walls)
    result = (f"The first `skmoor run` after an install (an empty numba cache) takes "
              f"{statistics.median(extra):.0f} s more than a warm one (median of "
              f"{len(extra)} pairs of the paper's case without animation, cold against warm: "
              f"{pairs}).")
    print("\n" + result)
    if args.write_docs:
        write_block(ROOT / "docs" / "speed.md", "first_run.py", result)


if __name__ == "__main__":
    main()
