"""Where a time step's cost goes: skmoor's time loop under cProfile, its internal time
grouped into the compiled element kernels, the linear algebra (factorizations and solves),
the Python glue of the residual and of Newton, and the recording of the outputs.

Each with the Python step and with the compiled Newton step (``skmoor.solvers.compiled_step``,
the default where it covers the system). Two systems: the paper's case (4 lines x 11 elements and the box: 126 unknowns, dense LU)
and the VolturnUS-S chain mooring of benchmarks/volturnus.py (3 x 50 segments, prescribed
fairleads, banded LU) at the paper's default step (50 ms) and at the step 1 % accuracy
needs in benchmarks/volturnus.py (0.25 s). cProfile adds its own cost per Python call, so the Python shares are
upper bounds; the kernels' and LAPACK's shares are what the compiled parts take.

Run: ``python benchmarks/step_profile.py [--duration 60] [--write-docs]``.
"""
from __future__ import annotations

import argparse
import cProfile
import pstats
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _cases import ROOT, write_block

import skmoor

GROUPS = {  # (file stem, function) prefixes -> group; the first match wins
    "compiled Newton step": [("compiled_step", "_run")],
    "compiled kernels": [("cable_kernel", "_cable"), ("hydro", "_morison"),
                         ("seabed", "_seabed"), ("patterns", "_scatter"),
                         ("banded", "_matvec"), ("body", "_rotation"),
                         ("body", "attachment_state")],
    "LU factor + solve": [("newton", "update"), ("newton", "solve"),
                          ("banded", "factorize"), ("banded", "__call__"), ("", "getrf"),
                          ("", "getrs"), ("", "gbtrf"), ("", "gbtrs")],
    "recording": [("recorder", ""), ("reactions", ""), ("cable_kernel", "element_tension"),
                  ("cable_kernel", "_element_tension"), ("line", "element_")],
    "Newton and scheme (Python)": [("dynamics", ""), ("newton", ""), ("compiled_step", "")],
    "residual assembly (Python)": [(stem, "") for stem in (
        "system", "dofs", "frames", "prescribed", "inertia", "build", "motion",
        "cable_kernel", "cable", "hydro", "seabed", "terms", "restoring", "loads",
        "banded", "patterns", "body", "large_rotations")],
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
    """Print the profile and return it as one line of the speed page."""
    print(f"\n{name}: {steps} steps, {1e3 * total / steps:.3f} ms per step under cProfile")
    shares = sorted(totals.items(), key=lambda kv: -kv[1])
    for group, seconds in shares:
        print(f"  {group:28s} {100 * seconds / total:5.1f} %  {1e6 * seconds / steps:8.1f} us/step")
    return (f"- {name}: {1e3 * total / steps:.2f} ms per step under cProfile: "
            + ", ".join(f"{group} {100 * seconds / total:.0f} %" for group, seconds in shares
                        if seconds >= 0.01 * total) + ".")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--duration", type=float, default=60.0)
    parser.add_argument("--write-docs", action="store_true",
                        help="write the profiles into docs/speed.md")
    args = parser.parse_args(argv)
    paper = skmoor.build(skmoor.paper_case())
    eq = skmoor.equilibrium(paper)
    lines = []
    for compiled, how in ((False, "Python step"), (True, "compiled step")):
        lines.append(report(f"paper case ({paper.system.n} unknowns, dt 50 ms, Rayleigh "
                            f"damping), {how}", *profile(paper, eq, 0.05, args.duration,
                                                          compiled)))
    import volturnus

    with tempfile.TemporaryDirectory() as workdir:
        model, eq = volturnus.skmoor_model(50, workdir)
        for compiled, how in ((False, "Python step"), (True, "compiled step")):
            lines.append(report(f"VolturnUS-S, 3 x 50 segments ({model.system.n} unknowns, "
                                f"dt 0.25 s), {how}",
                                *profile(model, eq, 0.25, args.duration, compiled)))
    if args.write_docs:
        write_block(ROOT / "docs" / "speed.md", "step_profile.py profile", "\n".join(lines))


if __name__ == "__main__":
    main()
