"""A 200-case design-load-case matrix on a local Dask cluster that loses a worker and is
interrupted, then resumed, into one dataset.

    python benchmarks/load_cases.py [--out DIR] [--duration S] [--workers N]

The matrix: the spar buoy network (examples/network_buoy.toml) in 5 sea states of a
scatter diagram x 4 headings x 5 seeds x 2 conditions (intact, leg 1's top chain released
at 1 s) = 200 runs of --duration s. A LocalCluster of --workers processes runs it; one
worker is killed (SIGKILL) a few seconds in, and the run is interrupted (SIGINT, as Ctrl-C)
once about half of the cases are kept; a second call on the same folder computes only the
rest. Prints each stage's counts and the dataset's lifetime damage per line.
"""
from __future__ import annotations

import argparse
import os
import signal
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import skmoor  # noqa: E402
from skmoor.run.load_cases import Condition, LoadCaseMatrix, SeaState, run_load_cases  # noqa: E402

SCATTER = [(1.0, 6.0, 0.25), (2.0, 8.0, 0.35), (3.0, 9.0, 0.2), (4.5, 10.5, 0.15),
           (6.0, 12.0, 0.05)]  # Hs (m), Tp (s), share of the time


def the_matrix() -> LoadCaseMatrix:
    base = skmoor.Case.from_toml(ROOT / "examples" / "network_buoy.toml")
    broken = Condition("leg1 broken", [{"point": "leg1.fairlead", "lines": ["leg1.top"],
                                        "time": 1.0}])
    return LoadCaseMatrix([SeaState(*s) for s in SCATTER], headings_deg=[0, 30, 60, 90],
                          seeds=[1, 2, 3, 4, 5], conditions=[Condition("intact"), broken],
                          base_case=base, transient=2.0, n_components=20)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", help="output folder (default: a new temporary one)")
    p.add_argument("--duration", type=float, default=6.0, help="simulated time per case, s")
    p.add_argument("--workers", type=int, default=2, help="Dask worker processes")
    args = p.parse_args(argv)
    from dask.distributed import Client, LocalCluster

    out = Path(args.out or tempfile.mkdtemp(prefix="skmoor-load-cases-"))
    matrix = the_matrix()
    settings = dict(duration=args.duration, dt=0.2, progress=False)
    kept = out / "load-cases"
    with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        victim = sorted(client.run(os.getpid).values())[0]

        def kill_then_interrupt():
            time.sleep(5.0)
            os.kill(victim, signal.SIGKILL)
            print(f"killed worker process {victim}", flush=True)
            while len(list(kept.glob("case-*.json"))) < matrix.size // 2:
                time.sleep(0.5)
            print(f"interrupting (SIGINT) at {len(list(kept.glob('case-*.json')))} cases kept",
                  flush=True)
            os.kill(os.getpid(), signal.SIGINT)

        threading.Thread(target=kill_then_interrupt, daemon=True).start()
        try:
            run_load_cases(matrix, out, scheduler=client, **settings)
            print("first call: finished before the interrupt")
        except KeyboardInterrupt:
            print(f"first call interrupted: {len(list(kept.glob('case-*.json')))} cases kept")
        started = time.perf_counter()
        data = run_load_cases(matrix, out, scheduler=client, **settings)
        print(f"second call: {time.perf_counter() - started:.1f} s")
    failed = int((data["error"].values != "").sum())
    print(f"dataset: {dict(data.sizes)}; {failed} failed cases; {out / 'load_cases.nc'}")
    print("lifetime damage over", data.attrs["design_life_years"], "years:")
    print(data["lifetime_damage"].to_pandas().T.to_string(float_format="{:.3g}".format))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
