"""Cost against the number of segments at equal accuracy: skmoor, MoorDyn and CableDyn.

The case (benchmarks/_cases.py): the 50 m chain of the OrcaFlex chain set, 410 m from an
anchor 400 m away, its fairlead driven in heave 2 m / 10 s (amplitude ramped in over the
first period), 20 s simulated, split into 10 ... 200 segments. Same physics in the three
codes, as a MoorDyn deck says it: tension EA x engineering strain, lumped mass, no
bending, Morison drag (Cd 1.37, CdAx 0.64) and added mass (Ca 1) on the relative velocity
in still water, a penalty sea bed (kBot 1e5 Pa/m, cBot 1e4 Pa s/m, no friction; skmoor's
Seabed fades the bed's damping in over the first 1.3 cm of penetration by default, or
Newton cycles where a node touches down) and a small internal (Kelvin-Voigt) axial
damping BA = BETA EA, the same for all segment counts (MoorDyn's -zeta would change it
with the segment length).

Accuracy: the fairlead tension history within 1 % of its range (the peak-to-peak of the
reference history over the whole run) at every output time (every 1/16 s, or every step
when the step is longer). The reference is each code's own run at a small step (2^-9 s
for the implicit codes, 2^-14 s for MoorDyn) on the same segments: the codes discretize
the line differently (FE with mid-point quadrature, lumped mass, CableDyn's elements), so
a common reference would charge those spatial differences to the time step; what is
measured here is the step each code needs to converge in time on its own mesh. The
codes' references are compared with each other as well (last columns of the table).

Each code's step is found by halving from a large one (1 s for the implicit codes,
2^-6 s for MoorDyn) until the run is finite and within 1 %. Wall times are
time.perf_counter around the time loop only (no deck parsing, statics or initial
conditions), the best of three runs at the found step, all in this one process.

Run: ``python benchmarks/scaling.py [--segments 10 20 50 100 200] [--no-plot]``
(about 5 min on 2 cores); prints the table, the log-log slope of skmoor's cost and a
cProfile of skmoor's largest case, and writes docs/images/scaling.png.
"""
from __future__ import annotations

import os

# One core per code, as MoorDyn runs: a threaded BLAS on a shared 2-core machine makes
# the dense LU of a few hundred unknowns 10-100 times slower at random.
for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

import argparse  # noqa: E402
import cProfile  # noqa: E402
import functools  # noqa: E402
import io  # noqa: E402
import pstats  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import steps  # noqa: E402
from _cases import (  # noqa: E402
    CBOT,
    CHAIN,
    DEPTH,
    KBOT,
    ROOT,
    chain_catenary,
    chain_type,
    heave,
    heave_at,
    inside,
    line_deck,
    quiet,
)

from skmoor.bodies.motion import Motion
from skmoor.coupling.system import System
from skmoor.lines.line import Line, LineSet
from skmoor.sea.hydro import line_hydrodynamics
from skmoor.sea.seabed import Seabed, seabed_term
from skmoor.solvers.dynamics import Scheme, integrate
from skmoor.solvers.newton import DivergenceError
from skmoor.solvers.statics import solve_static

SEGMENTS = (10, 20, 50, 100, 200)
DURATION = 20.0  # s
BETA = 1e-4  # s, internal axial damping BA = BETA EA
RHO_INF = 0.9  # generalized-alpha spectral radius of both implicit codes (skmoor's default)
OUTPUT = 2.0**-4  # s, output (and MoorDyn coupling) interval
TOLERANCE = 0.01  # of the reference's tension range
START = {"skmoor": 0, "cabledyn": 0, "moordyn": -6}  # log2 of the first (largest) step
REFERENCE = {"skmoor": -9, "cabledyn": -9, "moordyn": -14}  # log2 of the reference step
CODES = ("skmoor", "moordyn", "cabledyn")


def output_stride(dt):
    """Steps between recorded outputs: every OUTPUT seconds, or every step if longer."""
    return max(1, int(round(OUTPUT / dt)))


# ------------------------------------------------------------------ the three codes

def skmoor_system(n):
    """One-line System with a prescribed (heaving) fairlead, the sea bed, the line's drag
    and added mass, and its static state."""
    lt = chain_type(BA=BETA * CHAIN["EA"])
    lines = LineSet([Line.from_catenary(chain_catenary(), lt, n)], law="engineering")
    bed = Seabed.from_moordyn(DEPTH, lt.diameter, kBot=KBOT, cBot=CBOT)
    def along_z(value):  # (m,) or () -> (m, 1, 3) or (1, 3)
        value = np.asarray(value, float)
        out = np.zeros(value.shape + (1, 3))
        out[..., 0, 2] = value
        return out

    motion = Motion(lambda t: along_z(heave_at(t)[0]), lambda t: along_z(heave_at(t)[1]),
                    vectorized=True)  # the exact velocity, a batch of times in one call
    system = System(lines, fairleads="prescribed", motion=motion,
                    terms=[seabed_term(lines, bed),
                           line_hydrodynamics(lines)])
    return system, solve_static(system).x


def run_skmoor(n, dt, profile=None):
    """(wall time s, fairlead tension at the output times N)."""
    system, x0 = skmoor_system(n)
    stride = output_stride(dt)
    tension = []
    started = time.perf_counter()
    if profile is not None:
        profile.enable()
    for state in integrate(system, x0, np.zeros(system.n), dt, DURATION,
                           scheme=Scheme.generalized_alpha(RHO_INF), report_every=stride):
        if state.step % stride == 0:  # the end forces computed with the step
            tension.append(np.linalg.norm(state.reactions[0][0]))
    if profile is not None:
        profile.disable()
    return time.perf_counter() - started, np.array(tension)


def _deck(code, n, dt, workdir):
    return line_deck(Path(workdir) / f"{code}_{n}.dat", code=code,
                     catenary=chain_catenary(), line_type=chain_type(BA=BETA * CHAIN["EA"]),
                     n_segments=n, dt=dt, duration=DURATION, depth=DEPTH, rho_inf=RHO_INF)


IC_STEP = 2.0**-13  # s, MoorDyn's step while it settles the initial state (stable to 200 segments)


@functools.cache
def moordyn_initial_state(n, workdir):
    """MoorDyn's settled initial state of the n-segment line, computed once at IC_STEP and
    saved to a file (its initial-condition solver does not converge fully here, and what
    it returns depends on the step it runs at): (state file, fairlead tension N)."""
    import moordyn

    path = Path(workdir) / f"moordyn_{n}_ic.bin"
    with quiet():
        md = moordyn.Create(str(_deck("moordyn", n, IC_STEP, workdir)))
        moordyn.Init(md, list(chain_catenary().fairlead), [0.0, 0.0, 0.0])
        tension = float(np.linalg.norm(moordyn.GetPointForce(moordyn.GetPoint(md, 2))))
        moordyn.SaveState(md, str(path))
        moordyn.Close(md)
    return str(path), tension


def run_moordyn(n, dt, workdir):
    """MoorDyn v2 (RK2 at dtM = dt) from the saved initial state, coupled every OUTPUT s:
    the fairlead moves from its position at the start of each coupling step with the
    mean velocity over it."""
    import moordyn

    state, static = moordyn_initial_state(n, workdir)
    fairlead = chain_catenary().fairlead
    with quiet():
        md = moordyn.Create(str(_deck("moordyn", n, dt, workdir)))
        moordyn.Init_NoIC(md, list(fairlead), [0.0, 0.0, 0.0])
        moordyn.LoadState(md, state)
    try:
        tension = [static]
        started = time.perf_counter()
        with quiet(), np.errstate(over="ignore", invalid="ignore"):
            for k in range(int(round(DURATION / OUTPUT))):
                z0, z1 = heave(k * OUTPUT)[0], heave((k + 1) * OUTPUT)[0]
                force = moordyn.Step(md, list(fairlead + [0.0, 0.0, z0]),
                                     [0.0, 0.0, (z1 - z0) / OUTPUT], k * OUTPUT, OUTPUT)
                tension.append(np.linalg.norm(force))
        wall = time.perf_counter() - started
    finally:
        with quiet():
            moordyn.Close(md)
    return wall, np.array(tension)


def run_cabledyn(n, dt, workdir):
    """CableDyn (implicit generalized-alpha, rhoInf = RHO_INF) through its in-process C
    interface: step(dt, q, v, a) with the fairlead kinematics at the end of the step."""
    import cabledyn

    model = cabledyn.CableDyn(_deck("cabledyn", n, dt, workdir))
    try:
        q, v, a = model.get_coupled_motion()
        heave_dof = model.host_dofs()[2]
        fairlead = model.host_dofs()
        stride = output_stride(dt)
        tension = [np.linalg.norm(model.calc_output()[fairlead])]
        started = time.perf_counter()
        for k in range(1, int(round(DURATION / dt)) + 1):
            q[heave_dof], v[heave_dof], a[heave_dof] = heave(k * dt)
            model.step(dt, q, v, a)
            if k % stride == 0:
                tension.append(np.linalg.norm(model.calc_output()[fairlead]))
        wall = time.perf_counter() - started
    finally:
        model.close()
    return wall, np.array(tension)


def run(code, n, dt, workdir):
    """(wall time, tension at the output times), or (nan, None) when the run fails."""
    try:
        if code == "skmoor":
            wall, tension = run_skmoor(n, dt)
        elif code == "moordyn":
            wall, tension = run_moordyn(n, dt, workdir)
        else:
            wall, tension = run_cabledyn(n, dt, workdir)
    except (DivergenceError, RuntimeError, ValueError) as error:
        print(f"    {code} n={n} dt={dt:g}: failed ({type(error).__name__}: {error})")
        return np.nan, None
    return wall, tension


# ------------------------------------------------------------------ accuracy and step

def output_times(code, dt):
    """Times of the recorded outputs of a run with step dt."""
    spacing = OUTPUT if code == "moordyn" else output_stride(dt) * dt
    return np.arange(int(round(DURATION / spacing)) + 1) * spacing


def history_error(code, dt, tension, ref_dt, ref):
    """Largest |T - T_ref| over the run's output times, as a fraction of the
    reference's range (inf for a failed or non-finite run)."""
    if tension is None or not np.all(np.isfinite(tension)):
        return np.inf
    t, t_ref = output_times(code, dt), output_times(code, ref_dt)
    at = np.searchsorted(t_ref, t - 1e-9)  # the times coincide: steps are powers of 2
    return float(np.max(np.abs(tension - ref[at])) / np.ptp(ref))


def find_step(code, n, workdir):
    """Halve the step from START until the run is within TOLERANCE of the reference (the
    run at 2^REFERENCE s, or at the next larger step if that run fails). Returns
    dict(dt, error, wall (best of 3), ref, ref_dt, tried)."""
    return steps.find_step(lambda dt: run(code, n, dt, workdir),
                           lambda dt, tension, ref_dt, ref: history_error(code, dt, tension,
                                                                          ref_dt, ref),
                           START[code], REFERENCE[code], TOLERANCE, label=code)


def reference_difference(results, a, b):
    """Largest difference between the references of codes a and b over a's tension
    range, at their common output times: do the codes compute the same physics?"""
    t_a = output_times(a, results[a]["ref_dt"])
    t_b = output_times(b, results[b]["ref_dt"])
    common = np.intersect1d(np.round(t_a, 9), np.round(t_b, 9))
    T_a = results[a]["ref"][np.searchsorted(t_a, common - 1e-9)]
    T_b = results[b]["ref"][np.searchsorted(t_b, common - 1e-9)]
    return float(np.max(np.abs(T_a - T_b)) / np.ptp(results[a]["ref"]))


# ------------------------------------------------------------------ report

def profile_skmoor(n, dt, top=15):
    """cProfile of skmoor's time loop: the top entries by internal time, as text."""
    profile = cProfile.Profile()
    run_skmoor(n, dt, profile=profile)
    out = io.StringIO()
    pstats.Stats(profile, stream=out).sort_stats("tottime").print_stats(top)
    return out.getvalue()


def plot(table, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = np.array([row["n"] for row in table])
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    for code, marker in zip(CODES, "osd"):
        wall = [row[code]["wall"] for row in table]
        line, = left.loglog(n, wall, marker=marker, label=code)
        for x, y, row in zip(n, wall, table):  # the step each code needed
            left.annotate(f"{row[code]['dt']:.2g}", (x, y), textcoords="offset points",
                          xytext=(4, -10), fontsize=7, color=line.get_color())
    left.set(xlabel="segments", ylabel="wall time [s]",
             title=f"{DURATION:g} s simulated, tension within 1 % of range (labels: dt, s)")
    left.grid(True, which="both", alpha=0.3)
    left.legend()
    for code, marker in (("moordyn", "s"), ("cabledyn", "d")):
        right.loglog(n, [row["skmoor"]["wall"] / row[code]["wall"] for row in table],
                     marker=marker, label=f"skmoor / {code}")
    right.axhline(1.0, color="k", lw=0.8)
    right.set(xlabel="segments", ylabel="wall-time ratio", title="skmoor's time over the peer's")
    right.grid(True, which="both", alpha=0.3)
    right.legend()
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--segments", type=int, nargs="+", default=list(SEGMENTS))
    parser.add_argument("--no-plot", action="store_true")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "images" / "scaling.png")
    args = parser.parse_args(argv)

    table = []
    with tempfile.TemporaryDirectory() as workdir, inside(workdir):
        for n in args.segments:
            row = {"n": n}
            for code in CODES:
                row[code] = find_step(code, n, workdir)
                found = row[code]
                tried = ", ".join(f"{dt:g}: " + (f"{e:.1%}" if e < 10 else "blew up")
                                  for dt, e in found["tried"])
                print(f"  n={n:4d} {code:9s} dt={found['dt']:.3g} s  error={found['error']:.2%}"
                      f"  wall={found['wall']:.3f} s  reference dt={found['ref_dt']:g} s"
                      f"  (tried {tried})", flush=True)
            row["sk-md"] = reference_difference(row, "skmoor", "moordyn")
            row["sk-cd"] = reference_difference(row, "skmoor", "cabledyn")
            row["md-cd"] = reference_difference(row, "moordyn", "cabledyn")
            table.append(row)

    print(f"\nfairlead tension within {TOLERANCE:.0%} of the reference's range, "
          f"{DURATION:g} s simulated; wall time of the time loop (best of 3); 'refs': largest "
          "difference between two codes' references over the first's tension range\n")
    head = (f"{'segments':>8} | {'skmoor dt':>9} {'wall':>8} | {'MoorDyn dt':>10} {'wall':>8} | "
            f"{'CableDyn dt':>11} {'wall':>8} | {'sk/MD':>6} {'sk/CD':>6} | "
            f"{'refs sk-MD':>10} {'sk-CD':>6} {'MD-CD':>6}")
    print(head)
    print("-" * len(head))
    for row in table:
        sk, md, cd = row["skmoor"], row["moordyn"], row["cabledyn"]
        print(f"{row['n']:>8} | {sk['dt']:>9.4g} {sk['wall']:>8.3f} | {md['dt']:>10.3g} "
              f"{md['wall']:>8.3f} | {cd['dt']:>11.4g} {cd['wall']:>8.3f} | "
              f"{sk['wall'] / md['wall']:>6.2f} {sk['wall'] / cd['wall']:>6.2f} | "
              f"{row['sk-md']:>10.1%} {row['sk-cd']:>6.1%} {row['md-cd']:>6.1%}")
    n = np.array([row["n"] for row in table], float)
    wall = np.array([row["skmoor"]["wall"] for row in table])
    if len(n) > 1:
        slope = np.polyfit(np.log(n), np.log(wall), 1)[0]
        print(f"\nskmoor: wall time ~ segments^{slope:.2f} (log-log fit over {n.astype(int)})")
    if not args.no_plot:
        plot(table, args.out)
        print(f"wrote {args.out}")
    largest = table[-1]
    print(f"\nwhere skmoor's time goes at {largest['n']} segments, dt = "
          f"{largest['skmoor']['dt']:g} s (cProfile, by internal time):")
    print(profile_skmoor(largest["n"], largest["skmoor"]["dt"]))
    return table


if __name__ == "__main__":
    main()
