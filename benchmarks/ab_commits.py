"""Two commits' skmoor side by side in one process: is a change slower?

On a shared or virtual machine the speed drifts by 10 % within minutes, so timing one
commit after the other (even interleaved processes) cannot resolve a few per cent. Here
both commits' ``skmoor`` are imported into one interpreter under their own names (the
package's imports are relative; each copy, from ``git archive``, keeps its own numba
cache), and their runs alternate pair by pair: the ratio of each pair's wall times shares
the machine's state of that moment. Printed: the median paired ratio new / old with its
quartiles, for

- scaling: ``benchmarks/scaling.py``'s skmoor run (one chain, fairlead heaved, the
  compiled step, end forces every step) at ``--segments``;
- paper: ``skmoor.simulate`` of the built-in paper case, 200 s at 25 ms.

Run: ``python benchmarks/ab_commits.py OLD [NEW] [--case scaling|paper] [--pairs 200]
[--segments 10]`` (NEW: the working tree's HEAD by default; commits as git names them).
A ratio above 1 with its lower quartile above 1 is a slowdown.
"""
from __future__ import annotations

import argparse
import importlib
import io
import re
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
FILES = ("skmoor", "benchmarks/scaling.py", "benchmarks/_cases.py")


def checkout(commit, tag, into):
    """The commit's skmoor as package ``skm_<tag>`` and its scaling benchmark as module
    ``scaling_<tag>`` under ``into`` (a folder to put on sys.path)."""
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", "--format=tar", commit,
                              *FILES], check=True, capture_output=True).stdout
    work = into / f"tree_{tag}"
    work.mkdir()
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(work, filter="data")
    (work / "skmoor").rename(into / f"skm_{tag}")
    for name in ("scaling", "_cases"):
        text = (work / "benchmarks" / f"{name}.py").read_text()
        text = re.sub(r"\bskmoor\.", f"skm_{tag}.", text)
        text = text.replace("from _cases import", f"from _cases_{tag} import")
        text = re.sub(r"^import steps .*$", "", text, flags=re.M)  # the step search only
        (into / f"{name}_{tag}.py").write_text(text)


def runner(case, tag, segments):
    """A function timing one run of ``case`` with commit ``tag`` (s)."""
    if case == "scaling":
        scaling = importlib.import_module(f"scaling_{tag}")
        return lambda: scaling.run_skmoor(segments, 0.05)[0]
    skm = importlib.import_module(f"skm_{tag}")
    model = skm.build(skm.paper_case())

    def run():
        started = time.perf_counter()
        skm.simulate(model, duration=200, dt=0.025, output_interval=0.1, progress=False)
        return time.perf_counter() - started
    return run


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old")
    parser.add_argument("new", nargs="?", default="HEAD")
    parser.add_argument("--case", choices=("scaling", "paper"), default="scaling")
    parser.add_argument("--pairs", type=int, default=200)
    parser.add_argument("--segments", type=int, default=10)
    args = parser.parse_args(argv)
    if args.pairs < 1 or args.segments < 1:
        parser.error("--pairs and --segments: must be positive")
    with tempfile.TemporaryDirectory() as tmp:
        into = Path(tmp)
        for tag, commit in (("old", args.old), ("new", args.new)):
            checkout(commit, tag, into)
        sys.path.insert(0, str(into))
        runs = {tag: runner(args.case, tag, args.segments) for tag in ("old", "new")}
        for run in runs.values():  # numba compiles each copy once
            run()
        times = {tag: [] for tag in runs}
        for pair in range(args.pairs):
            for tag in (("old", "new") if pair % 2 else ("new", "old")):
                times[tag].append(runs[tag]())
    old, new = (np.array(times[tag]) for tag in ("old", "new"))
    ratio = new / old
    q1, median, q3 = np.percentile(ratio, (25, 50, 75))
    print(f"{args.case}{f' ({args.segments} segments)' if args.case == 'scaling' else ''}, "
          f"{args.pairs} pairs: {args.old} median {np.median(old) * 1e3:.2f} ms, "
          f"{args.new} median {np.median(new) * 1e3:.2f} ms")
    print(f"paired ratio {args.new} / {args.old}: {median:.3f} (quartiles {q1:.3f}, {q3:.3f})")


if __name__ == "__main__":
    main()
