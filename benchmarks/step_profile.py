"""Where a time step's cost goes: skmoor's time loop under cProfile, its internal time
grouped into the compiled element kernels, the linear algebra (factorizations and solves),
the Python glue of the residual and of Newton, and the recording of the outputs.

Each with the Python step and with the compiled Newton step (``skmoor.solvers.compiled_step``,
the default where it covers the system). Two systems: the paper's case (4 lines x 11 elements and the box: 126 unknowns, dense LU)
and the VolturnUS-S chain mooring of benchmarks/volturnus.py (3 x 50 segments, prescribed
fairleads, banded LU) at the paper's default step (50 ms) and at the step 1 % accuracy
needs in benchmarks/volturnus.py (0.25 s). cProfile adds its own cost per Python call, so the Python shares are
upper bounds; the kernels' and LAPACK's shares are what the compiled parts take.

Run: ``python benchmarks/step_profile.py [--duration 60]``.
"""
from __future__ import annotations

import argparse
import cProfile
import pstats
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import skmoor

GROUPS = {  # (file stem, function) prefixes -> group; the first match wins
    "compiled Newton step": [("compiled_step", "_run")],
    "compiled kernels": [("kernels", "_cable"), ("hydro", "_morison"), ("seabed", "_seabed"),
                         ("kernels", "_scatter"), ("banded", "_matvec"),
                         ("body", "_rotation"), ("body", "attachment_state")],
    "LU factor + solve": [("dynamics", "update"), ("dynamics", "solve"),
                          ("banded", "factorize"), ("banded", "<lambda>"), ("", "getrf"),
                          ("", "getrs"), ("", "gbtrf"), ("", "gbtrs")],
    "recording": [("run", "record"), ("coupling", "reactions"), ("line", "element_")],
    "Newton and scheme (Python)": [("dynamics", "")],
    "residual assembly (Python)": [("coupling", ""), ("kernels", ""), ("hydro", ""),
                                   ("seabed", ""), ("terms", ""), ("banded", ""),
                                   ("model", ""), ("body", "")],
}


def group_of(filename, function):
    stem = Path(filename).stem
    for group, keys in GROUPS.items():
        for file_key, function_key in keys:
            if (not file_key or stem == file_key) and function.startswith(function_key):
                return group
    return "numpy, scipy and the rest"


def profile(model, eq, dt, duration, compiled):
    """{group: internal seconds}, steps, total seconds of simulate under cProfile, with
    the compiled Newton step or without (the Python step)."""
    model.solver["compiled"] = compiled
    skmoor.simulate(model, duration=min(duration, 10 * dt), dt=dt, progress=False, eq=eq)
    prof = cProfile.Profile()
    prof.enable()
    results = skmoor.simulate(model, duration=duration, dt=dt, progress=False, eq=eq)
    prof.disable()
    totals = {}
    for (filename, _, function), (_, _, internal, _, _) in pstats.Stats(prof).stats.items():
        group = group_of(filename, function)
        totals[group] = totals.get(group, 0.0) + internal
    return totals, results.meta["steps"], sum(totals.values())


def report(name, totals, steps, total):
    print(f"\n{name}: {steps} steps, {1e3 * total / steps:.3f} ms per step under cProfile")
    for group, seconds in sorted(totals.items(), key=lambda kv: -kv[1]):
        print(f"  {group:28s} {100 * seconds / total:5.1f} %  {1e6 * seconds / steps:8.1f} us/step")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--duration", type=float, default=60.0)
    args = parser.parse_args(argv)
    paper = skmoor.build(skmoor.paper_case())
    eq = skmoor.equilibrium(paper)
    for compiled, how in ((False, "Python step"), (True, "compiled step")):
        report(f"paper case (its default run: dt 50 ms, Rayleigh damping), {how}",
               *profile(paper, eq, 0.05, args.duration, compiled))
    import volturnus

    with tempfile.TemporaryDirectory() as workdir:
        model, eq = volturnus.skmoor_model(50, workdir)
        for compiled, how in ((False, "Python step"), (True, "compiled step")):
            report(f"VolturnUS-S, 3 x 50 segments (dt 0.25 s), {how}",
                   *profile(model, eq, 0.25, args.duration, compiled))


if __name__ == "__main__":
    main()
