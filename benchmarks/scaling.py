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

Each code's step: every step 2^k from a large one (1 s for the implicit codes, 2^-6 s for
MoorDyn) down to the reference is run, and the largest step is picked whose run and every
smaller step's run are finite and within 1 % (benchmarks/steps.py: the error need not fall
monotonically with the step).

Times, each code at its step:

- time loop: time.perf_counter around the loop only (no deck parsing, statics or initial
  conditions), the best of eight runs in this one process: three in the step search and
  ROUNDS in rounds that run the three codes in turn at their steps (a load that comes and
  goes on the machine then falls on all of them); MoorDyn's is its Step calls
  alone, the script's Python between them (the fairlead's position and velocity) is
  printed apart;
- whole process: a new Python process that imports the code, makes the line, its static
  state (MoorDyn: its settled initial state) and runs the loop, timed from start to exit,
  with its peak memory (skmoor's first compile after an install, with an empty numba
  cache: ``benchmarks/first_run.py``).

Run: ``python benchmarks/scaling.py [--segments 10 20 50 100 200] [--no-plot]
[--write-docs]`` (about 15 min on 2 cores); prints the tables, the log-log slope of
skmoor's cost and a cProfile of skmoor's largest case, writes docs/images/scaling.png and,
with --write-docs, the tables into README.md and docs/speed.md.
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
import json  # noqa: E402
import pstats  # noqa: E402
import resource  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import steps  # noqa: E402
from _cases import (  # noqa: E402
    CBOT,
    CHAIN,
    DEPTH,
    FAIRLEAD,
    KBOT,
    ROOT,
    chain_catenary,
    chain_type,
    heave,
    heave_at,
    inside,
    line_deck,
    quiet,
    write_block,
)

SEGMENTS = (10, 20, 50, 100, 200)
DURATION = 20.0  # s
BETA = 1e-4  # s, internal axial damping BA = BETA EA
RHO_INF = 0.9  # generalized-alpha spectral radius of both implicit codes (skmoor's default)
OUTPUT = 2.0**-4  # s, output (and MoorDyn coupling) interval
TOLERANCE = 0.01  # of the reference's tension range
ROUNDS = 5  # rounds of the three codes at their steps, for the time loop's wall
START = {"skmoor": 0, "cabledyn": 0, "moordyn": -6}  # log2 of the first (largest) step
REFERENCE = {"skmoor": -9, "cabledyn": -9, "moordyn": -14}  # log2 of the reference step
CODES = ("skmoor", "moordyn", "cabledyn")
MOORDYN_GLUE = {}  # (segments, dt) -> s of the script's Python between MoorDyn's Step calls


def output_stride(dt):
    """Steps between recorded outputs: every OUTPUT seconds, or every step if longer."""
    return max(1, int(round(OUTPUT / dt)))


# ------------------------------------------------------------------ the three codes

def skmoor_system(n):
    """One-line System with a prescribed (heaving) fairlead, the sea bed, the line's drag
    and added mass, and its static state."""
    # skmoor's imports here and in run_skmoor: a peer's whole process does not import it
    from skmoor.bodies.motion import Motion
    from skmoor.coupling.system import System
    from skmoor.lines.line import Line, LineSet
    from skmoor.sea.hydro import line_hydrodynamics
    from skmoor.sea.seabed import Seabed, seabed_term
    from skmoor.solvers.statics import solve_static

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
    from skmoor.solvers.dynamics import Scheme, integrate

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
    """The code's deck of the n-segment line at step dt in workdir (written once: a whole
    process reads the one its parent wrote)."""
    path = Path(workdir) / f"{code}_{n}_{dt!r}.dat"
    if path.exists():
        return path
    return line_deck(path, code=code,
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
        moordyn.Init(md, list(FAIRLEAD), [0.0, 0.0, 0.0])
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
    fairlead = FAIRLEAD
    with quiet():
        md = moordyn.Create(str(_deck("moordyn", n, dt, workdir)))
        moordyn.Init_NoIC(md, list(fairlead), [0.0, 0.0, 0.0])
        moordyn.LoadState(md, state)
    try:
        tension, wall, glue = [static], 0.0, 0.0
        with quiet(), np.errstate(over="ignore", invalid="ignore"):
            for k in range(int(round(DURATION / OUTPUT))):
                started = time.perf_counter()
                z0, z1 = heave(k * OUTPUT)[0], heave((k + 1) * OUTPUT)[0]
                r, u = list(fairlead + [0.0, 0.0, z0]), [0.0, 0.0, (z1 - z0) / OUTPUT]
                before = time.perf_counter()
                force = moordyn.Step(md, r, u, k * OUTPUT, OUTPUT)
                after = time.perf_counter()
                tension.append(np.linalg.norm(force))
                wall += after - before  # MoorDyn's own time: its Step calls
                glue += before - started + time.perf_counter() - after
    finally:
        with quiet():
            moordyn.Close(md)
    MOORDYN_GLUE[(n, dt)] = glue
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
    except (RuntimeError, ValueError) as error:  # skmoor's DivergenceError among them
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
    dict(dt, error, wall (best of 3; main adds the rounds'), ref, ref_dt, tried)."""
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


# ------------------------------------------------------------------ whole processes

def one_process(code, n, dt, workdir):
    """The child of :func:`whole_process`: this case as a user runs it in a new process
    (imports, the line, its static state or MoorDyn's settled start, the time loop) from
    the deck its parent wrote in workdir; prints the loop's time and the peak memory as
    JSON."""
    with inside(workdir):
        wall, tension = run(code, n, dt, workdir)
    print(json.dumps({"loop": wall, "peak_mb": peak_memory(), "ok": tension is not None}))


def peak_memory() -> float:
    """This process's peak resident memory, MB: VmHWM of its own address space (getrusage's
    maxrss would start from the parent's at the fork)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return float(line.split()[1]) / 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def whole_process(code, n, dt, workdir):
    """dict(whole (s: the process from start to exit), loop (s), peak_mb) of the case in a
    new process that imports only its code."""
    if code != "skmoor":  # the peer's decks, written here (their set-up uses skmoor)
        _deck(code, n, dt, workdir)
        _deck(code, n, IC_STEP, workdir)
    env = dict(os.environ)
    started = time.perf_counter()
    out = subprocess.run([sys.executable, __file__, "--one", code, str(n), repr(dt),
                          str(workdir)],
                         capture_output=True, text=True, env=env, check=False)
    whole = time.perf_counter() - started
    try:
        info = json.loads(out.stdout.strip().splitlines()[-1])
    except (IndexError, ValueError):
        raise RuntimeError(f"{code} n={n} dt={dt}: the process failed: {out.stderr[-800:]}")
    return dict(whole=whole, loop=info["loop"], peak_mb=info["peak_mb"])


# ------------------------------------------------------------------ report

def markdown_table(table, short=False):
    """The table as markdown: each code's step, time loop and whole process, the ratios
    (short: segments and the ratios only, for the README)."""
    names = {"skmoor": "skmoor", "moordyn": "MoorDyn", "cabledyn": "CableDyn"}
    if short:
        rows = ["| segments | time loop skmoor/MoorDyn | skmoor/CableDyn | whole process "
                "skmoor/MoorDyn | skmoor/CableDyn |", "|---|---|---|---|---|"]
        for row in table:
            sk, md, cd = row["skmoor"], row["moordyn"], row["cabledyn"]
            rows.append(f"| {row['n']} | **{sk['wall'] / md['wall']:.2f}** | "
                        f"**{sk['wall'] / cd['wall']:.2f}** | "
                        f"{sk['whole'] / md['whole']:.2f} | {sk['whole'] / cd['whole']:.2f} |")
        return "\n".join(rows)
    head = "| segments | " + " | ".join(
        f"{names[c]} dt / loop / whole [s] / peak [MB]" for c in CODES) + (
        " | loop sk/MD | loop sk/CD | whole sk/MD | whole sk/CD |")
    rows = [head, "|" + "---|" * (len(CODES) + 5)]
    for row in table:
        cells = [f"{row[c]['dt']:.3g} / {row[c]['wall']:.3f} / {row[c]['whole']:.2f} / "
                 f"{row[c]['peak_mb']:.0f}" for c in CODES]
        sk, md, cd = row["skmoor"], row["moordyn"], row["cabledyn"]
        cells += [f"**{sk['wall'] / md['wall']:.2f}**", f"**{sk['wall'] / cd['wall']:.2f}**",
                  f"{sk['whole'] / md['whole']:.2f}", f"{sk['whole'] / cd['whole']:.2f}"]
        rows.append(f"| {row['n']} | " + " | ".join(cells) + " |")
    return "\n".join(rows)


def write_tables(table):
    """The tables into README.md (short) and docs/speed.md, between their markers."""
    write_block(ROOT / "README.md", "scaling.py table", markdown_table(table, short=True))
    write_block(ROOT / "docs" / "speed.md", "scaling.py table", markdown_table(table))



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
    parser.add_argument("--write-docs", action="store_true", help="write the tables into "
                        "README.md and docs/speed.md")
    parser.add_argument("--one", nargs=4, metavar=("CODE", "N", "DT", "WORKDIR"),
                        help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.one:  # the child of whole_process
        code, n, dt, workdir = args.one
        return one_process(code, int(n), float(dt), workdir)

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
            best = steps.interleaved_walls({code: row[code]["dt"] for code in CODES},
                                           lambda code, dt: run(code, n, dt, workdir), ROUNDS)
            for code in CODES:  # the search's best of 3 and the rounds'
                row[code]["wall"] = min(row[code]["wall"], best[code])
            for code in CODES:  # the whole process at the step found, peak memory
                row[code].update(whole_process(code, n, row[code]["dt"], workdir))
                print(f"  n={n:4d} {code:9s} whole process {row[code]['whole']:.2f} s (its "
                      f"time loop {row[code]['loop']:.3f} s), peak memory "
                      f"{row[code]['peak_mb']:.0f} MB"
                      + (f"; the script's glue between Step calls "
                         f"{MOORDYN_GLUE.get((n, row[code]['dt']), 0.0):.3f} s, not counted"
                         if code == "moordyn" else ""), flush=True)
            row["sk-md"] = reference_difference(row, "skmoor", "moordyn")
            row["sk-cd"] = reference_difference(row, "skmoor", "cabledyn")
            row["md-cd"] = reference_difference(row, "moordyn", "cabledyn")
            table.append(row)

    print(f"\nfairlead tension within {TOLERANCE:.0%} of the reference's range, "
          f"{DURATION:g} s simulated; wall time of the time loop (best of {3 + ROUNDS}, "
          f"{ROUNDS} of them in rounds of the three codes); 'refs': largest "
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
    print("\ntime loop (MoorDyn: its Step calls alone) / whole process (interpreter start, "
          "imports, the line, its static state or settled start, the loop) / peak memory:\n")
    print(markdown_table(table))
    if args.write_docs:
        write_tables(table)
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
