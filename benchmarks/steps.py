"""The benchmarks' step search: the largest step 2^k that keeps a run within a tolerance
of the same code's run at a small step (benchmarks/scaling.py, benchmarks/volturnus.py)."""
from __future__ import annotations

import numpy as np


def find_step(run, error, start, reference, tolerance, repeats=3, label="", report=None):
    """Halve the step from 2^start s until ``error`` of the run is within ``tolerance``.

    run(dt) -> (wall s, outputs or None when the run failed); error(dt, outputs, ref_dt,
    ref) -> float. The reference is the run at 2^reference s, or at the next larger step
    when that one fails. report(dt, wall, error), if given, is called after every tried
    step. Returns dict(dt, error, wall (the best of ``repeats`` runs at dt), ref, ref_dt,
    tried [(dt, error)]); dt, error and wall are nan when no step holds."""
    for k_ref in range(reference, start):
        ref_dt = 2.0**k_ref
        _, ref = run(ref_dt)
        if ref is not None:
            break
    else:
        raise RuntimeError(f"{label}: no reference run completed")
    tried = []
    for k in range(start, k_ref, -1):
        dt = 2.0**k
        wall, outputs = run(dt)
        err = error(dt, outputs, ref_dt, ref)
        tried.append((dt, err))
        if report is not None:
            report(dt, wall, err)
        if err <= tolerance:
            walls = [wall] + [run(dt)[0] for _ in range(repeats - 1)]
            return dict(dt=dt, error=err, wall=min(walls), ref=ref, ref_dt=ref_dt, tried=tried)
    return dict(dt=np.nan, error=np.nan, wall=np.nan, ref=ref, ref_dt=ref_dt, tried=tried)
