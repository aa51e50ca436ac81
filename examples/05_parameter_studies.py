"""The paper's two parameter studies (its Figs. 7 and 8): steady-state amplitudes of
surge, heave, pitch and the maximum tension against the sag-to-span ratio d/l (at
theta = 50 deg) and against the chord angle theta (at d/l = 1/60).

Points run in parallel processes (or on a Dask cluster: run_sweep(..., scheduler=ADDR));
finished points are kept in studies/sweep-points/, so a rerun does only missing ones.

Run: python examples/05_parameter_studies.py   (writes studies/sweep.csv and two PNGs)
"""
import os

from skmoor.run.sweep import paper_studies, run_sweep

N_POINTS = int(os.environ.get("SKMOOR_EXAMPLE_POINTS", 8))
DURATION = float(os.environ.get("SKMOOR_EXAMPLE_DURATION", 200.0))
OUT = os.environ.get("SKMOOR_EXAMPLE_OUT", "studies")

rows = run_sweep(paper_studies(N_POINTS), OUT, duration=DURATION, progress=False)
by_study = {}
for row in rows:
    by_study.setdefault(row["study"], []).append(row)

if __name__ == "__main__":
    for name, points in by_study.items():
        print(name)
        for r in sorted(points, key=lambda r: r["value"]):
            print(f"  {r['value']:10.5g}  surge {r['surge']:.4f} m  heave {r['heave']:.4f} m  "
                  f"pitch {r['pitch']:.4f} rad  steady max tension {r['max_tension_steady'] / 1e3:.1f} kN")
