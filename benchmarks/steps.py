"""The benchmarks' step search: the largest step 2^k that keeps a run within a tolerance
of the same code's run at a small step, checked at every smaller step too, and the codes'
wall times at their steps in interleaved rounds (benchmarks/scaling.py,
benchmarks/volturnus.py)."""
from __future__ import annotations

import numpy as np


def find_step(run, error, start, reference, tolerance, repeats=3, label="", report=None):
    """The largest step 2^k <= 2^start s whose run, and the run at every smaller step
    above the reference, is within ``tolerance``: the error need not fall monotonically
    with the step (a touchdown node can ring at one step and not at the next), so every
    step down to the reference is run and a step is picked only if no smaller one fails.

    run(dt) -> (wall s, outputs or None when the run failed); error(dt, outputs, ref_dt,
    ref) -> float. The reference is the run at 2^reference s, or at the next larger step
    when that one fails. report(dt, wall, error), if given, is called after every tried
    step. Returns dict(dt, error, wall (the best of ``repeats`` runs at dt), ref, ref_dt,
    tried [(dt, error)] from the largest step down); dt, error and wall are nan when no
    step holds."""
    for k_ref in range(reference, start):
        ref_dt = 2.0**k_ref
        _, ref = run(ref_dt)
        if ref is not None:
            break
    else:
        raise RuntimeError(f"{label}: no reference run completed")
    tried, walls = [], {}
    for k in range(start, k_ref, -1):
        dt = 2.0**k
        wall, outputs = run(dt)
        err = error(dt, outputs, ref_dt, ref)
        tried.append((dt, err))
        walls[dt] = wall
        if report is not None:
            report(dt, wall, err)
    picked = None
    for dt, err in reversed(tried):  # from the smallest step up: stop at the first failure
        if not err <= tolerance:
            break
        picked = (dt, err)
    if picked is None:
        return dict(dt=np.nan, error=np.nan, wall=np.nan, ref=ref, ref_dt=ref_dt, tried=tried)
    dt, err = picked
    times = [walls[dt]] + [run(dt)[0] for _ in range(repeats - 1)]
    return dict(dt=dt, error=err, wall=min(times), ref=ref, ref_dt=ref_dt, tried=tried)


def interleaved_walls(steps, run, rounds):
    """{code: its best wall time (s)} at its step ``steps[code]`` (s; not finite: none,
    nan), from ``rounds`` rounds that run every code once in turn (a load that comes and
    goes on the machine then falls on all of them); run(code, dt) -> (wall, ...)."""
    walls = {code: [] for code in steps}
    for _ in range(rounds):
        for code, dt in steps.items():
            if np.isfinite(dt):
                walls[code].append(run(code, dt)[0])
    return {code: min(w) if w else np.nan for code, w in walls.items()}
