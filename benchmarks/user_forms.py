"""A user's form against the built-in kernel: Morison drag written as a LineForm.

The term: Morison drag on a line in still water, the true follower drag on the CURRENT
unit tangent tau = (X' + u') / |X' + u'|, normal and tangential (MoorDyn's conventions,
as skmoor.sea.hydro has them): per unit unstretched length

    f = -1/2 rho Cd_n d |v_n| v_n - 1/2 rho Cd_t (pi d) |v_t| v_t,   v = udot,

written below as a plain scikit-fem ``LinearForm`` with ``skmoor.fem.ops`` (its residual
alone; per unit reference length, so times w.m / mass, the reference stretch's inverse,
as hydro.coefficients does). It is evaluated (residual + d/du + d/dudot, into the element
blocks, ``term.add_to``) on

- 'assembly': scikit-fem's assembly with the hand-written tangents below;
- 'fd': NumPy element residuals, tangents by central differences;
- 'autodiff': scikit-fem's skfem.autodiff (JAX linearization on its assembly);
- 'compiled': the integrand traced by JAX, written out and compiled by numba,

against the built-in numba kernel (skmoor.sea.hydro.LineHydroKernel, same Cd_n, Cd_t, the
same Gauss points) on the paper's steel line (analytic catenary, d/l = 1/60) cut into
11 ... 10,000 elements, at a random state (u ~ 1 mm, udot ~ 0.5 m/s). Times are the best
of nine rounds (timeit), the paths and the built-in alternated in each round, after a
first call (tracing, compiling or loading the kernel from the disk cache), all in this
one process; a path whose time per call, extrapolated from the sizes before, would pass
SLOW seconds is left out at that size (said so in the table). Every path's R, K, C
are compared with the built-in's (largest difference over the largest entry).

Then the paper's case (skmoor.build(skmoor.paper_case())) run 200 s three ways, each
user term against its built-in equivalent: the user drag above added by
``model.add(LineForm(..., path='compiled'))`` against the line type's Cd_n, Cd_t (the
built-in Morison kernel); the engineering strain law written as a ``skmoor.UserLaw``
against the built-in Engineering law; a small distributed load in time (1 N/m) written as a
LineForm against the case without it (what evaluating the term costs). Wall time of the
time loop only (the static state and modes computed before, ``simulate(..., eq=eq)``), in
PAIRS pairs after an untimed run of each, the order alternating from pair to pair: the
median of the pairs' ratios and its quartiles (one run's time on a shared 2-core machine
varies by 10-20 %, a pair's ratio much less); the two runs' fairlead tension and surge
histories compared.

Run: ``python benchmarks/user_forms.py [--quick] [--out docs/user_forms.md]``
(about 5 min; --quick: 11 and 100 elements, 20 s of the paper's case, under a minute
once the kernel is cached); prints the tables, and writes the report to --out when given.
"""
from __future__ import annotations

import os

# One core, as the other benchmarks: a threaded BLAS on a shared 2-core VM is erratic.
for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

import argparse  # noqa: E402
import time  # noqa: E402
import timeit  # noqa: E402
from pathlib import Path  # noqa: E402

import _cases  # noqa: E402
import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402
from skfem import BilinearForm, LinearForm  # noqa: E402

import skmoor  # noqa: E402
from skmoor.fem import ops
from skmoor.fem.ops import d_ds, dot
from skmoor.fem.terms import LineForm
from skmoor.lines.catenary import solve_catenary
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.sea.hydro import LineHydroKernel

ELEMENTS = (11, 100, 1_000, 10_000)
PATHS = ("assembly", "fd", "autodiff", "compiled")
CD_N, CD_T = 1.2, 0.008  # MoorDyn's Cd and CdAx
SLOW = 10.0  # s: a path predicted slower than this per call is left out at that size
DURATION = 200.0  # s of the paper's case
PAIRS = 15  # of the paper case's runs, per user term
SWAY = 1.0  # N/m: the user's load, small so that the motion and Newton's work stay the case's


# ------------------------------------------------------------------ the user's form

@LinearForm
def drag(v, w):
    """+ int [k_n |v_n| v_n + k_t |v_t| v_t] . du ds (drag is external: + in the residual)."""
    rp = w.Xp + d_ds(w.u)  # r' = X' + u'
    tau = rp / ops.norm(rp)  # the current unit tangent
    along = dot(w.du, tau)
    vn = w.du - along * tau
    per_reference = w.m / w.mass  # 1 / stretch of the reference state
    return per_reference * (w.k_n * ops.norm(vn) * dot(vn, v)
                            + w.k_t * ops.abs(along) * along * dot(tau, v))


def _state(w):
    rp = w.Xp + d_ds(w.u)
    length = ops.norm(rp)
    tau = rp / length
    along = dot(w.du, tau)
    vn = w.du - along * tau
    speed = ops.norm(vn)
    return length, tau, along, vn, speed, ops.where(speed > 0, speed, 1.0)


@BilinearForm
def drag_rate(d, v, w):
    """d/dudot of drag: k_n (|v_n| P d + (v_n . d) v_n / |v_n|) + 2 k_t |v_t| (tau . d) tau."""
    _, tau, along, vn, speed, safe = _state(w)
    dn = d - dot(d, tau) * tau
    return (w.m / w.mass) * (w.k_n * (speed * dot(dn, v) + dot(vn, d) * dot(vn, v) / safe)
                             + 2.0 * w.k_t * ops.abs(along) * dot(tau, d) * dot(tau, v))


@BilinearForm
def drag_stiffness(d, v, w):
    """d/du of drag, through tau only: dtau = P d' / |r'|, d(v.tau) = v_n . dtau,
    dv_n = -d(v.tau) tau - (v.tau) dtau, d|v_n| = v_n . dv_n / |v_n|."""
    length, tau, along, vn, speed, safe = _state(w)
    dp = d_ds(d)
    dtau = (dp - dot(dp, tau) * tau) / length
    dalong = dot(vn, dtau)
    dvn = -dalong * tau - along * dtau
    dspeed = dot(vn, dvn) / safe
    normal = dspeed * vn + speed * dvn
    axial = 2.0 * ops.abs(along) * dalong * tau + ops.abs(along) * along * dtau
    return (w.m / w.mass) * dot(w.k_n * normal + w.k_t * axial, v)


def drag_fields(line_type: LineType) -> dict:
    """The form's constants: 1/2 rho Cd_n d, 1/2 rho Cd_t pi d (N s2/m3 per m), mass (kg/m)."""
    rho, d = line_type.rho_water, line_type.diameter
    return {"k_n": 0.5 * rho * CD_N * d, "k_t": 0.5 * rho * CD_T * np.pi * d,
            "mass": line_type.mass}


def user_drag(line_type: LineType, path: str, lines=None) -> LineForm:
    """The user's drag as a LineForm on ``path`` (hand tangents on 'assembly')."""
    hand = dict(stiffness=drag_stiffness, damping=drag_rate) if path == "assembly" else {}
    return LineForm(drag, fields=drag_fields(line_type), path=path, lines=lines,
                    name="user_drag", **hand)


# ------------------------------------------------------------------ per term

def paper_line(n: int) -> tuple[LineSet, LineType]:
    """The paper's steel line (d = 0.1 m, 50 deg chord, d/l = 1/60) with n elements,
    with the drag coefficients set (for the built-in kernel)."""
    steel = LineType.steel_rod(0.1, Cd_n=CD_N, Cd_t=CD_T)
    anchor = np.array([-100.0 / np.tan(np.radians(50.0)), 0.0, -100.0])
    cable = solve_catenary(anchor, [0.0, 0.0, 0.0], steel.weight, steel.EA, sag_ratio=1 / 60)
    return LineSet([Line.from_catenary(cable, steel, n)]), steel


def best_times(calls, budget=1.0, repeat=9):
    """Best time of one call of each of ``calls`` ({name: function}), s. The calls are
    timed in alternating rounds (the load of a shared machine then hits them alike), each
    round enough calls to fill ~budget / repeat; a call slower than that: two rounds."""
    timers = {name: timeit.Timer(call) for name, call in calls.items()}
    best = {name: timer.timeit(1) for name, timer in timers.items()}
    number = {name: max(1, int(budget / repeat / max(once, 1e-9))) for name, once in best.items()}
    slow = {name for name, once in best.items() if once > budget / repeat}
    for round_ in range(repeat):
        for name, timer in timers.items():
            if name not in slow or round_ < 2:
                best[name] = min(best[name], timer.timeit(number[name]) / number[name])
    return best


def difference(a, b):
    """Largest |a - b| over the largest |b| (arrays or sparse matrices)."""
    if sp.issparse(b):
        return float(abs(a - b).max() / max(abs(b).max(), 1e-300))
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


def per_term(n: int, paths=PATHS, budget=1.0, predicted=None):
    """One size: {'builtin': s per call, path: (s per call, first call s, difference to
    the built-in's R, K, C, backend) or None where left out}. paths: those to run;
    predicted: {path: expected s per call}, to leave out paths slower than SLOW."""
    lines, steel = paper_line(n)
    rng = np.random.default_rng(0)
    u = 1e-3 * rng.standard_normal(lines.ndofs)
    v = 0.5 * rng.standard_normal(lines.ndofs)
    nel = lines.mesh.t.shape[1]
    R, K, C = np.zeros(lines.ndofs), np.zeros((nel, 6, 6)), np.zeros((nel, 6, 6))
    builtin = LineHydroKernel(lines)
    reference = builtin.evaluate(u, v, 0.0, True, "sparse")
    calls, out = {"builtin": lambda: builtin.add_to(u, v, 0.0, R, K, C)}, {}
    for path in PATHS:
        if path not in paths or (predicted and (predicted.get(path) or 0.0) > SLOW):
            out[path] = None
            continue
        term = user_drag(steel, path, lines)
        started = time.perf_counter()
        term.add_to(u, v, 0.0, R, K, C)  # first call: trace, compile or load
        first = time.perf_counter() - started
        got = term.evaluate(u, v, 0.0, True, "sparse")
        error = max(difference(g, r) for g, r in zip(got, reference))
        calls[path] = lambda term=term: term.add_to(u, v, 0.0, R, K, C)
        out[path] = (first, error, getattr(term, "backend", ""))
    seconds = best_times(calls, budget)
    return {"builtin": seconds["builtin"],
            **{path: None if entry is None else (seconds[path], *entry)
               for path, entry in out.items()}}


def predict(history, n):
    """Time per call at n elements from [(n, seconds), ...] of the sizes before: a + b n
    through the last two (b >= 0), or None with fewer (a fixed cost may dominate)."""
    if len(history) < 2:
        return None
    (n0, t0), (n1, t1) = history[-2:]
    return t1 + max((t1 - t0) / (n1 - n0), 0.0) * (n - n1)


def term_table(sizes=ELEMENTS, budget=1.0):
    """Rows (n, per_term) per size; a path is left out at a size where its time per call,
    extrapolated from the sizes before (:func:`predict`), exceeds SLOW."""
    rows, history = [], {path: [] for path in PATHS}
    for n in sizes:
        predicted = {path: predict(h, n) for path, h in history.items()}
        row = per_term(n, budget=budget, predicted=predicted)
        rows.append((n, row))
        print(f"  {n:,} elements done", flush=True)
        for path in PATHS:
            history[path] = history[path] + [(n, row[path][0])] if row[path] else [(n, np.inf)]
    return rows


# ------------------------------------------------------------------ the paper's case

@LinearForm
def swaying_load(v, w):
    """- q0 sin(omega t) e_y . du: a distributed load in time on every line (N/m)."""
    return -w.q0 * ops.sin(w.omega * w.t) * v.value[1]


def linear_steel(EA):
    """The user's law: tension EA e of the engineering strain (the built-in Engineering)."""
    def steel(strain, rate):
        return EA * strain
    return steel


def paper_models():
    """{name: (built-in model, user model, the user's term or law)}: the paper's case with

    - drag: line type steel's Cd_n, Cd_t set (the built-in Morison kernel) / the user's
      drag form added (compiled path);
    - law: the engineering strain law (built-in) / the same tension as a UserLaw;
    - load: no load / the user's swaying distributed load of SWAY N/m (what evaluating
      it costs: the motion, and Newton's iterations, stay nearly those of the case)."""
    case = skmoor.paper_case()
    builtin = skmoor.build(case.replace("line_types.steel.Cd_n", CD_N)
                           .replace("line_types.steel.Cd_t", CD_T))
    user = skmoor.build(case)
    steel = user.lines.lines[0].line_type
    drag_term = user.add(user_drag(steel, "compiled"))
    engineering = case.replace("mooring.strain_law", "engineering")
    law = skmoor.UserLaw(linear_steel(steel.EA))
    loaded = skmoor.build(case)
    load = loaded.add(LineForm(swaying_load, fields={"q0": SWAY, "omega": 0.5},
                               path="compiled", name="swaying_load"))
    return {"drag": (builtin, user, drag_term),
            "law": (skmoor.build(engineering), skmoor.build(engineering, law=law), law),
            "load": (skmoor.build(case), loaded, load)}


def histories(results):
    """(surge (nt,), fairlead tensions (nt, nlines)) of a run."""
    return results.body_series("surge"), results.fairlead_tension


def paper_case_comparison(duration=DURATION, repeat=PAIRS, models=None):
    """Per user term: the two time loops run in ``repeat`` pairs (after an untimed run of
    each that loads or compiles its kernels; the order within a pair alternating), the
    median and quartiles of the pairs' ratios user / built-in, and the distance between
    the two runs' histories (largest difference over the range), whether the user's run
    took the compiled step."""
    from skmoor.solvers.compiled_step import lowered_terms

    out = {}
    for name, (builtin, user, term) in (models or paper_models()).items():
        eqs = [skmoor.equilibrium(m) for m in (builtin, user)]
        ratios, runs = [], [None, None]
        for model, eq in zip((builtin, user), eqs):
            skmoor.simulate(model, duration=min(duration, 1.0), eq=eq, progress=False)
        for pair in range(repeat):
            wall = [0.0, 0.0]
            for k in ((0, 1) if pair % 2 == 0 else (1, 0)):
                model, eq = (builtin, user)[k], eqs[k]
                started = time.perf_counter()
                runs[k] = skmoor.simulate(model, duration=duration, eq=eq, progress=False)
                wall[k] = time.perf_counter() - started
            ratios.append(wall[1] / wall[0])
        (surge_b, tension_b), (surge_u, tension_u) = (histories(r) for r in runs)
        agree = {"surge": float(np.max(np.abs(surge_u - surge_b)) / np.ptp(surge_b)),
                 "fairlead tension": float(np.max(np.abs(tension_u - tension_b))
                                           / np.ptp(tension_b))}
        out[name] = {"ratio": float(np.median(ratios)),
                     "quartiles": tuple(float(q) for q in np.quantile(ratios, [0.25, 0.75])),
                     "pairs": repeat, "agree": agree,
                     "compiled": lowered_terms(user.system)[0] is None,
                     "steps": runs[0].meta["steps"], "duration": duration}
    return out


# ------------------------------------------------------------------ report

def environment():
    """Date, commit, versions, machine."""
    return _cases.environment(("numpy", "scikit-fem", "numba", "jax"), load=True)


def format_terms(rows) -> str:
    head = ("| elements | built-in [us / call] | " + " | ".join(f"{p} / built-in" for p in PATHS)
            + " | difference of R, K, C: compiled / other paths |")
    lines = [head, "|---" * (3 + len(PATHS)) + "|"]
    for n, row in rows:
        cells = [f"{n:,}", f"{row['builtin'] * 1e6:.0f}"]
        errors = []
        for path in PATHS:
            entry = row[path]
            if entry is None:
                cells.append(f"left out (> {SLOW:g} s per call)")
                continue
            ratio = entry[0] / row["builtin"]
            cells.append(f"**{ratio:.2f}**" if path == "compiled" else
                         f"{ratio:,.0f}" if ratio >= 100 else f"{ratio:.3g}")
            if path != "compiled":
                errors.append(entry[2])
        compiled = row["compiled"][2] if row["compiled"] else float("nan")
        cells.append(f"{compiled:.1e} / {max(errors, default=float('nan')):.1e}")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


ROWS = {"drag": ("user drag form, `model.add(LineForm(drag))`",
                 f"built-in drag (line type Cd_n = {CD_N}, Cd_t = {CD_T})"),
        "law": ("user law, `build(case, law=UserLaw(steel))`", "built-in Engineering law"),
        "load": ("user distributed load, `model.add(LineForm(swaying_load))`",
                 "the case without the load (what evaluating it costs)")}


def format_case(case) -> str:
    lines = ["| user term | compared with | time loop / the other's (quartiles) | compiled step "
             "| histories apart (surge, fairlead tension) |", "|---|---|---|---|---|"]
    for name, row in case.items():
        user, builtin = ROWS[name]
        apart = f"{row['agree']['surge']:.1e}, {row['agree']['fairlead tension']:.1e}"
        apart += f" (the {SWAY:g} N/m load)" if name == "load" else ""
        low, high = row["quartiles"]
        lines.append(f"| {user} | {builtin} | **{row['ratio']:.2f}** ({low:.2f}-{high:.2f}) | "
                     f"{'yes' if row['compiled'] else 'no'} | {apart} |")
    first = next(iter(case.values()))
    lines += ["", f"{first['duration']:g} s of the paper's case, {first['steps']} steps; "
              "histories apart: the largest difference over the history's range."]
    return "\n".join(lines)


def report(rows, case, env, quick, seconds) -> str:
    first = {p: max(r[p][1] for _, r in rows if r[p] is not None) for p in PATHS
             if any(r[p] is not None for _, r in rows)}
    backend = next((r["compiled"][3] for _, r in rows if r["compiled"]), "")
    return "\n".join([
        "# A user's form against the built-in kernel",
        "",
        f"Generated by `python benchmarks/user_forms.py{' --quick' if quick else ''} "
        "--out docs/user_forms.md`; "
        "do not edit by hand. Every number below comes from that run (the script's "
        "docstring has the method).",
        "",
        *(f"- {k}: {v}" for k, v in env.items()),
        f"- run time: {seconds:.0f} s",
        "",
        "The Morison drag (normal and tangential, on the current tangent) written as a "
        "user's `LineForm` (its residual alone on 'fd', 'autodiff', 'compiled'; with "
        "hand-written tangents on 'assembly'), residual + both tangents per call, time over "
        "the built-in numba kernel `LineHydroKernel.add_to` (same physics; its own time per "
        "call is given for scale). Goal: compiled within 3.",
        "",
        format_terms(rows),
        "",
        f"Compiled path: backend {backend}. First call (trace and compile, or load from the "
        "disk cache), at most over the sizes: "
        + ", ".join(f"{p} {s:.1f} s" for p, s in first.items()) + ".",
        "",
        "## The paper's case with a user's drag, law and load",
        "",
        f"Wall time of the time loop with each user term over the built-in equivalent (the "
        f"load: over the case without it): the median of {PAIRS} pairs' ratios (quartiles "
        "in brackets), after an untimed run of each, the order alternating from pair to "
        "pair. Goal: within 1.3 (1.1), histories equal to 1e-10." if not quick
        else "Wall time of the time loop (one run).",
        "",
        format_case(case),
        "",
    ])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="11 and 100 elements, 20 s of the paper's case")
    parser.add_argument("--out", type=Path, default=None,
                        help="write the report there (docs/user_forms.md); default: print only")
    args = parser.parse_args(argv)
    started, env = time.perf_counter(), environment()
    sizes = ELEMENTS[:2] if args.quick else ELEMENTS
    rows = term_table(sizes, budget=0.3 if args.quick else 2.0)
    print(format_terms(rows), flush=True)
    case = paper_case_comparison(20.0 if args.quick else DURATION,
                                 repeat=1 if args.quick else PAIRS)
    print()
    print(format_case(case))
    text = report(rows, case, env, args.quick, time.perf_counter() - started)
    if args.out is not None:
        args.out.write_text(text)
        print(f"\nwritten: {args.out}")


if __name__ == "__main__":
    main()
