"""A real mooring side by side: the IEA 15 MW VolturnUS-S chain mooring in skmoor, MoorDyn
and CableDyn, each at the largest step that meets the same accuracy criterion.

The system: the MoorDyn deck of the IEA-15-240-RWT repository
(``OpenFAST/IEA-15-240-RWT-UMaineSemi/IEA-15-240-RWT-UMaineSemi_MoorDyn.dat``: three 850 m
studless chains, 0.333 m, 685 kg/m, EA 3.27e9 N, Cd 2.0, Ca 0.82, CdAx 0.4, CaAx 0.27,
BA/-zeta -1, kBot 3e6 Pa/m, cBot 3e5 Pa s/m), read at run time from a local mirror
($SKMOOR_IEA_MIRROR, default /work/.mirror/IEAWindTask37+IEA-15-240-RWT/repo; bring it with
``git clone`` of IEAWindTask37/IEA-15-240-RWT), with the water depth of 200 m added (the
deck leaves it to the host code) and each line split into 50, 100 or 200 segments. The
fairleads (the deck's 'Vessel' points) are driven together, 5 m / 90 s in surge and
2 m / 12 s in heave, faded in over the first 12 s, for 300 s, from static rest.

Each code is run the way it runs in a host: skmoor ``build(deck, motion=...)`` and
``simulate`` (generalized-alpha with rho_inf 0.5, as CableDyn is set; no Rayleigh
damping, as a deck has none); MoorDyn v2
(its RK2 at dtM, coupled at every step: the fairleads move from the start of each step at
its mean velocity) from its own settled initial state; CableDyn (implicit generalized-alpha) through its in-process interface,
the fairlead kinematics given at the end of every step. Time-loop wall times are
time.perf_counter around the time loop only (no parsing, statics or initial conditions);
whole-process times are those of a new Python process that imports only its code, reads
the deck, finds its start (skmoor's static solve, MoorDyn's own initial-condition stage
at the run's step, CableDyn's) and runs the loop, the parent timing it from start to exit
(numba's cache warm: skmoor's first compile is benchmarks/first_run.py's).

Why rho_inf 0.5: a chain node resting on MoorDyn's bed is a spring of period ~0.17 s
(kBot d over the node's mass and added mass; the bed's damping fades in with penetration),
far below the steps of an implicit code. With Newmark (no numerical damping) or rho_inf 0.8
skmoor's runs at 0.25 s pick up a spurious bed chatter near touchdown (12 % in the peak
tension at rho_inf 0.8); rho_inf 0.5 damps it and leaves the 12-90 s motion alone (its
reference agrees with the rho_inf 0.8 one within 0.4 % in std and peak).

Accuracy (the issue's criterion): the standard deviation and the peak of each fairlead's
tension over the run within 1 % of the same code's converged reference (its run at a
small step: REFERENCE). A code's step is found by halving from START until the criterion
holds; the timed run at that step is the best of REPEATS rounds run after every code's
search, each round running every code once (so that a varying load on the machine falls
on all codes alike; ``--steps`` re-times at steps an earlier search found). The three
references are also
compared with each other (std and peak), which says whether the codes compute the same
physics.

Run: ``python benchmarks/volturnus.py [--segments 50 100 200] [--codes skmoor moordyn
cabledyn] [--duration 300] [--steps CODE=DT | CODE@N=DT ...] [--write-docs]`` prints the
table and the ratios. MoorDyn's explicit step
falls with the segment length: at 200 segments its reference run alone takes tens of
minutes on this machine.
"""
from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")  # one core per code, as MoorDyn runs

import argparse  # noqa: E402
import copy  # noqa: E402
import functools  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))

import steps  # noqa: E402
from _cases import ROOT, quiet, write_block  # noqa: E402

# skmoor is imported where it is used: a peer's whole process does not import it

DECK_PATH = "OpenFAST/IEA-15-240-RWT-UMaineSemi/IEA-15-240-RWT-UMaineSemi_MoorDyn.dat"
DEPTH = 200.0  # m
DURATION = 300.0  # s
FADE = 12.0  # s
SURGE, SURGE_PERIOD = 5.0, 90.0  # m, s
HEAVE, HEAVE_PERIOD = 2.0, 12.0  # m, s
OUTPUT = 0.125  # s, output interval
TOLERANCE = 0.01  # of the reference's tension std and peak
REPEATS = 3
WHOLE_ROUNDS = 2  # of the whole processes, interleaved
CODES = ("skmoor", "moordyn", "cabledyn")
SEGMENTS = (50, 100, 200)
START = {"skmoor": -1, "cabledyn": -1, "moordyn": -6}  # log2 of the first (largest) step
REFERENCE = {"skmoor": -6, "cabledyn": -6, "moordyn": -12}  # log2 of the reference step
MOORDYN_REFERENCE = {100: -13, 200: -14}  # finer segments, finer explicit reference
RHO_INF = 0.5  # generalized-alpha spectral radius of both implicit codes


def mirror_path() -> Path:
    return Path(os.environ.get("SKMOOR_IEA_MIRROR",
                               "/work/.mirror/IEAWindTask37+IEA-15-240-RWT/repo"))


@functools.cache
def iea_deck():
    """The IEA deck as skmoor reads it (a skmoor.io.deck.Deck)."""
    import skmoor

    text = subprocess.run(["git", "-C", str(mirror_path()), "show", f"HEAD:{DECK_PATH}"],
                          capture_output=True, text=True, check=False)
    if text.returncode:
        raise SystemExit(f"volturnus: cannot read {DECK_PATH} from the mirror "
                         f"{mirror_path()} (set SKMOOR_IEA_MIRROR): {text.stderr.strip()}")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "iea.dat"
        path.write_text(text.stdout)
        return skmoor.read_deck(path)


def write_deck(code, n, dt, workdir) -> Path:
    """The IEA deck for ``code`` on n segments per line at step dt (s): the water depth
    added, the outputs cleared, the options each code needs (written once: a whole
    process reads the one its parent wrote)."""
    path = Path(workdir) / f"{code}_{n}_{dt:g}.dat"
    if path.exists():
        return path
    import skmoor

    deck = copy.deepcopy(iea_deck())
    for line in deck.lines:
        line.n_segments = n
    options = {"dtM": repr(dt), "kBot": deck.options["kBot"], "cBot": deck.options["cBot"],
               "WtrDpth": repr(DEPTH)}
    if code == "moordyn":
        options.update(TmaxIC="200.0", threshIC="1e-6", dtIC="1.0", CdScaleIC="4.0",
                       writeLog="0", disableOutput="1", disableOutTime="1")
    elif code == "cabledyn":
        options.update(TMax=repr(DURATION), rhoInf=repr(RHO_INF))
    deck.options, deck.outputs = options, []
    deck.option_lines = {}
    return skmoor.write_deck(deck, path)


def fade(t):
    return 0.5 * (1 - np.cos(np.pi * min(t / FADE, 1.0)))


def fairlead_offset(t):
    """(surge, heave) of every fairlead at t, m."""
    f = fade(t)
    return (SURGE * f * np.sin(2 * np.pi * t / SURGE_PERIOD),
            HEAVE * f * np.sin(2 * np.pi * t / HEAVE_PERIOD))


def skmoor_motion(t):
    """skmoor's prescribed displacements of the three coupled points (9,)."""
    x, z = fairlead_offset(t)
    y = np.zeros(9)
    y[0::3], y[2::3] = x, z
    return y


def fairleads(workdir):
    """(3, 3) the deck's fairlead positions, in its order of coupled points (kept in
    workdir for the whole processes)."""
    path = Path(workdir) / "fairleads.npy"
    if not path.exists():
        np.save(path, np.array([p.position for p in iea_deck().points
                                if p.kind.lower() in ("coupled", "vessel")], float))
    return np.load(path)


# ------------------------------------------------------------------ the three codes

@functools.cache
def skmoor_model(n, workdir):
    import skmoor

    model = skmoor.build(write_deck("skmoor", n, 1e-3, workdir), motion=skmoor_motion)
    model.solver.update(scheme="generalized-alpha", rho_inf=RHO_INF)  # as CableDyn's
    return model, skmoor.equilibrium(model)


def run_skmoor(n, dt, workdir):
    """(wall s, fairlead tensions (samples, 3) N every OUTPUT s or every step)."""
    import skmoor

    model, eq = skmoor_model(n, workdir)
    started = time.perf_counter()
    results = skmoor.simulate(model, duration=DURATION, dt=dt,
                              output_interval=max(dt, OUTPUT), progress=False, eq=eq)
    wall = time.perf_counter() - started
    if results.meta["stopped"] is not None:
        raise RuntimeError(results.meta["stopped"])
    return wall, np.asarray(results.fairlead_tension)


@functools.cache
def moordyn_initial_state(n, workdir):
    """MoorDyn's settled initial state on n segments, saved once: its state file."""
    import moordyn

    path = Path(workdir) / f"moordyn_{n}_ic.bin"
    with quiet():
        md = moordyn.Create(str(write_deck("moordyn", n, 2.0**-13, workdir)))
        moordyn.Init(md, list(fairleads(workdir).ravel()), [0.0] * 9)
        moordyn.SaveState(md, str(path))
        moordyn.Close(md)
    return str(path)


def run_moordyn(n, dt, workdir, settle=False):
    """MoorDyn v2 (RK2 at dtM = dt) from its settled state, coupled at every one of its
    steps (the fairleads from the start of the step at its mean velocity; coupling every
    0.125 s instead lowers the std of its tensions by 4-8 % here, 0.8-1.7 % every 1/32 s);
    the tension is the end node's net force (the line's pull on the fairlead, as skmoor's).
    With ``settle`` (a whole process) it finds its start itself, with its initial-condition
    stage at dt, instead of loading the state settled at a small step."""
    import moordyn

    base = fairleads(workdir)
    stride = max(1, int(round(OUTPUT / dt)))
    state = None if settle else moordyn_initial_state(n, workdir)
    with quiet():
        md = moordyn.Create(str(write_deck("moordyn", n, dt, workdir)))
        if settle:
            moordyn.Init(md, list(base.ravel()), [0.0] * 9)
        else:
            moordyn.Init_NoIC(md, list(base.ravel()), [0.0] * 9)
            moordyn.LoadState(md, state)
    lines = [moordyn.GetLine(md, k) for k in (1, 2, 3)]
    offsets = np.array([fairlead_offset(k * dt) for k in range(int(round(DURATION / dt)) + 1)])
    try:
        tensions = []
        started = time.perf_counter()
        with quiet(), np.errstate(over="ignore", invalid="ignore"):
            for k in range(len(offsets) - 1):
                (x0, z0), (x1, z1) = offsets[k], offsets[k + 1]
                r = (base + [x0, 0.0, z0]).ravel().tolist()
                u = [(x1 - x0) / dt, 0.0, (z1 - z0) / dt] * 3
                moordyn.Step(md, r, u, k * dt, dt)
                if (k + 1) % stride == 0:
                    tensions.append([np.linalg.norm(moordyn.GetLineNodeForce(line, n))
                                     for line in lines])
        wall = time.perf_counter() - started
    finally:
        with quiet():
            moordyn.Close(md)
    return wall, np.array(tensions)


def run_cabledyn(n, dt, workdir):
    """CableDyn through its in-process interface: step(dt, q, v, a), the fairlead
    kinematics at the end of each step."""
    import cabledyn

    model = cabledyn.CableDyn(write_deck("cabledyn", n, dt, workdir))
    try:
        q, v, a = model.get_coupled_motion()
        dofs = model.host_dofs().reshape(3, 3)  # [point, x y z] -> index in q
        base = q[dofs].copy()
        stride = max(1, int(round(OUTPUT / dt)))
        tensions = []
        started = time.perf_counter()
        for k in range(1, int(round(DURATION / dt)) + 1):
            t = k * dt
            h = 1e-4
            x, z = fairlead_offset(t)
            xp, zp = fairlead_offset(t + h)
            xm, zm = fairlead_offset(t - h)
            for p in range(3):
                q[dofs[p]] = base[p] + [x, 0.0, z]
                v[dofs[p]] = [(xp - xm) / (2 * h), 0.0, (zp - zm) / (2 * h)]
                a[dofs[p]] = [(xp - 2 * x + xm) / h**2, 0.0, (zp - 2 * z + zm) / h**2]
            model.step(dt, q, v, a)
            if k % stride == 0:
                force = model.calc_output()[dofs]
                tensions.append(np.linalg.norm(force, axis=1))
        wall = time.perf_counter() - started
    finally:
        model.close()
    return wall, np.array(tensions)


RUNNERS = {"skmoor": run_skmoor, "moordyn": run_moordyn, "cabledyn": run_cabledyn}


def run(code, n, dt, workdir):
    """(wall, tensions) or (nan, None) when the run fails."""
    from skmoor.solvers.newton import DivergenceError

    try:
        return RUNNERS[code](n, dt, workdir)
    except (DivergenceError, RuntimeError, ValueError) as error:
        print(f"    {code} n={n} dt={dt:g}: failed ({type(error).__name__}: {error})",
              flush=True)
        return np.nan, None


def one_process(code, n, dt, workdir):
    """The child of :func:`whole_process`: the run as a user makes it in a new process
    (imports, the deck, the start, the time loop) from the deck its parent wrote in
    workdir; prints the loop's time as JSON."""
    if code == "moordyn":
        wall, tensions = run_moordyn(n, dt, workdir, settle=True)
    else:
        wall, tensions = RUNNERS[code](n, dt, workdir)
    print(json.dumps({"loop": wall, "ok": tensions is not None}))


def whole_process(code, n, dt, workdir):
    """(s from the process's start to its exit, s of its time loop) of the run in a new
    Python process (:func:`one_process`); nan where it fails."""
    write_deck(code, n, 1e-3 if code == "skmoor" else dt, workdir)  # (skmoor: its deck)
    fairleads(workdir)
    started = time.perf_counter()
    out = subprocess.run([sys.executable, __file__, "--one", code, str(n), repr(dt),
                          str(workdir)], capture_output=True, text=True, check=False)
    whole = time.perf_counter() - started
    try:
        info = json.loads(out.stdout.strip().splitlines()[-1])
    except (IndexError, ValueError):
        print(f"    {code} n={n} dt={dt:g}: the whole process failed: {out.stderr[-600:]}",
              flush=True)
        return np.nan, np.nan
    return whole, info["loop"]


# ------------------------------------------------------------------ accuracy and step

def statistics(tensions):
    """(std, peak) of each fairlead's tension over the run, N, (2, 3)."""
    return np.array([tensions.std(axis=0), tensions.max(axis=0)])


def error(tensions, ref):
    """Largest relative difference of the std and the peak from the reference's."""
    if tensions is None or not np.all(np.isfinite(tensions)):
        return np.inf
    a, b = statistics(tensions), statistics(ref)
    return float(np.max(np.abs(a - b) / b))


def find_step(code, n, workdir):
    """The largest step 2^k (k from START down) within TOLERANCE of the reference."""
    first = MOORDYN_REFERENCE.get(n, REFERENCE[code]) if code == "moordyn" else REFERENCE[code]

    def report(dt, wall, err):
        print(f"    {code} n={n} dt={dt:g}: wall {wall:.2f} s, error {err:.4f}", flush=True)

    return steps.find_step(lambda dt: run(code, n, dt, workdir),
                           lambda dt, tensions, ref_dt, ref: error(tensions, ref),
                           START[code], first, TOLERANCE, 1, label=code, report=report)


def given_steps(items, segments, codes):
    """{(code, n): dt} of --steps items CODE=DT (every segment count) and CODE@N=DT."""
    given = {}
    for item in items:
        key, dt = item.split("=")
        code, _, n = key.partition("@")
        for m in ([int(n)] if n else segments):
            given[(code, m)] = float(dt)
    missing = [f"{c}@{n}" for n in segments for c in codes if (c, n) not in given]
    if given and missing:
        raise SystemExit(f"--steps: no step for {', '.join(missing)}")
    return given


def main(argv=None):
    global DURATION
    if argv is None and sys.argv[1:2] == ["--one"]:  # a whole process's child
        code, n, dt, workdir = sys.argv[2:6]
        one_process(code, int(n), float(dt), workdir)
        return
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--segments", type=int, nargs="+", default=list(SEGMENTS))
    parser.add_argument("--codes", nargs="+", default=list(CODES), choices=CODES)
    parser.add_argument("--duration", type=float, default=DURATION)
    parser.add_argument("--write-docs", action="store_true", help="write the table into "
                        "docs/speed.md (after the last segment count)")
    parser.add_argument("--steps", nargs="+", default=(), metavar="CODE=DT",
                        help="time each code at these steps (s) without the search (steps "
                             "an earlier search found; CODE@N=DT for one segment count; the "
                             "references column then compares the runs at these steps)")
    args = parser.parse_args(argv)
    DURATION = args.duration
    given = given_steps(args.steps, args.segments, args.codes)
    rows = []
    with tempfile.TemporaryDirectory() as workdir:
        for n in args.segments:
            results = {}
            for code in args.codes:
                print(f"{code}, {n} segments per line", flush=True)
                results[code] = (dict(dt=given[(code, n)],
                                      ref=run(code, n, given[(code, n)], workdir)[1])
                                 if given else find_step(code, n, workdir))
            chosen = {code: res["dt"] for code, res in results.items()}
            best = steps.interleaved_walls(chosen, lambda code, dt: run(code, n, dt, workdir),
                                           REPEATS)
            whole = steps.interleaved_walls(
                chosen, lambda code, dt: whole_process(code, n, dt, workdir), WHOLE_ROUNDS)
            for code, res in results.items():
                res["wall"], res["whole"] = best[code], whole[code]
                print(f"    {code} n={n} dt={res['dt']:g}: time loop {res['wall']:.2f} s (best "
                      f"of {REPEATS}, interleaved), whole process {res['whole']:.2f} s (best "
                      f"of {WHOLE_ROUNDS})", flush=True)
            rows.append((n, results))
            report(rows, args.codes, bool(given), args.write_docs and n == args.segments[-1])


NAMES = {"skmoor": "skmoor", "moordyn": "MoorDyn", "cabledyn": "CableDyn"}


def report(rows, codes, given=False, write_docs=False):
    """Print the table (and with write_docs, write it into docs/speed.md)."""
    head = " | ".join(f"{NAMES[c]} step / loop / whole" for c in codes)
    peers = [c for c in codes if c != "skmoor"] if "skmoor" in codes else []
    ratios = " | ".join(f"skmoor/{NAMES[c]} loop | whole" for c in peers)
    lines = [f"| segments | {head} | {ratios} | references apart: "
             + ", ".join(f"skmoor-{NAMES[c]}" for c in peers) + " |",
             "|---" * (2 + len(codes) + 2 * len(peers)) + "|"]
    for n, res in rows:
        cells = [f"{1e3 * res[c]['dt']:g} ms / {res[c]['wall']:.2f} s / {res[c]['whole']:.1f} s"
                 for c in codes]
        sk = res["skmoor"] if peers else None
        for c in peers:
            cells += [f"**{sk['wall'] / res[c]['wall']:.2f}**", f"{sk['whole'] / res[c]['whole']:.2f}"]
        cells.append(", ".join(f"{error(sk['ref'], res[c]['ref']):.4f}" for c in peers))
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    lines += ["", ("Steps: " + ("given (found by an earlier run of the full search)" if given
                               else "each code's own search") + f"; {DURATION:g} s of motion; "
                   "loop: the time loop alone, best of "
                   f"{REPEATS} interleaved rounds; whole: the whole process, best of "
                   f"{WHOLE_ROUNDS}; references apart: the largest relative difference in "
                   "fairlead-tension std and peak between the codes' runs.")]
    print("\n" + "\n".join(lines))
    sys.stdout.flush()
    if write_docs:
        write_block(ROOT / "docs" / "speed.md", "volturnus.py table", "\n".join(lines))


if __name__ == "__main__":
    main()
