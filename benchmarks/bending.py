"""Bending lines at equal accuracy: skmoor against CableDyn on a lazy-wave power cable.

The case: the Gulf of Maine 200 m lazy-wave cable of examples/09_lazy_wave.py (Lozon et
al. 2025: three sections with bending stiffness, the middle one buoyant, 64 elements
31 / 11 / 22), its hang-off heaved 3 m / 12 s for 60 s, the amplitude faded in over the
first 12 s by the quintic ramp (CableDyn's own example motion), in still water with the
drag and added mass of CableDyn's case L3-6 (Cd_n 1.2, Cd_t 0.1, Ca_n 1), on CableDyn's
penalty bed (kBot 1e5 Pa/m, cBot 1e4 Pa s/m). Both codes integrate in time with generalized-alpha at rho_inf = RHO_INF on
the same elements (CableDyn is given skmoor's mesh); CableDyn's deck is the one the test
suite runs it from (tests/lines/test_lazy_wave.py). Both are given the hang-off's exact
position, velocity and acceleration at each step's end.

Accuracy: the hang-off tension within TOLERANCE of the same code's converged reference
(its run at 2^-9 s) at every output time (every 1/16 s, or every step when the step is
longer), as a share of the reference tension there. Each code's step: the largest 2^k
whose run, and every smaller step's run, holds that (benchmarks/steps.py). The drag
matters here: without it the cable keeps an undamped mode near 0.67 Hz that the heave
excites, and two runs at any two steps (2^-8 and 2^-9 s alike, in either code) drift
apart by up to 2 % of the tension by t = 50 s: no step converges the history.

Times, each code at its step, the best of three runs in this one process:

- time loop: skmoor's ``integrate`` loop (the compiled step, the end forces at the
  outputs); CableDyn's ``step`` and ``calc_output`` calls alone (the script's Python
  between them, the motion's values, is printed apart);
- the run as a user makes it: ``skmoor.simulate`` (static state, loop, every output
  recorded: node positions, tensions, curvature) against CableDyn's model made from its
  deck (its static solve) plus its loop.

Run: ``python benchmarks/bending.py [--write-docs]`` (a few minutes; CableDyn: ``pip
install ".[bench]"``). Ratios are printed last; with --write-docs the table goes into
docs/speed.md.
"""
from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")  # one core per code

import argparse  # noqa: E402
import importlib.util  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import steps  # noqa: E402
from _cases import ROOT, environment, quiet, write_block  # noqa: E402

SITE = "200m"
ELEMENTS = 64  # CableDyn's example mesh size
AMPLITUDE, PERIOD, RAMP, DURATION = 3.0, 12.0, 12.0, 60.0  # m, s, s, s
RHO_INF = 0.9
DRAG = {"Cd_n": 1.2, "Cd_t": 0.1, "Ca_n": 1.0}  # CableDyn's L3-6 (Ca_t 0)
OUTPUT = 2.0**-4  # s
TOLERANCE = 0.005  # of the reference tension at each output
START, REFERENCE = -1, -9  # log2 of the largest step tried and of the reference step
CABLEDYN_OPTIONS = ("9.80665 g\n1025.0 rhoW\n{depth} WtrDpth\n1.0e5 kBot\n1.0e4 cBot\n"
                    f"{RHO_INF} rhoInf\n{{dt}} dtM\n{DURATION} TMax\n")


def heave(t):
    """(z, dz/dt, d2z/dt2) of the hang-off at t (s, or an array): A sin(2 pi t / T) faded in
    over RAMP s by the quintic ramp (m, m/s, m/s2)."""
    from skmoor.bodies.motion import quintic_ramp

    t = np.asarray(t, float)
    omega = 2 * math.pi / PERIOD
    r, dr, ddr = (value / RAMP**k for k, value in enumerate(quintic_ramp(t / RAMP)))
    s, c = np.sin(omega * t), np.cos(omega * t)
    return (AMPLITUDE * r * s, AMPLITUDE * (dr * s + r * omega * c),
            AMPLITUDE * (ddr * s + 2 * dr * omega * c - r * omega**2 * s))


def output_stride(dt):
    return max(1, int(round(OUTPUT / dt)))


def load_example(workdir):
    """examples/09_lazy_wave.py at SITE with ELEMENTS elements (its figure into workdir)."""
    os.environ.update(SKMOOR_EXAMPLE_ELEMENTS=str(ELEMENTS), SKMOOR_EXAMPLE_SITES=SITE,
                      SKMOOR_EXAMPLE_OUT=str(workdir))
    spec = importlib.util.spec_from_file_location("lazy_wave", ROOT / "examples" / "09_lazy_wave.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def skmoor_model(example, form_path="auto"):
    """The cable at SITE, its hang-off a coupled point moved by :func:`heave` (form_path:
    the bed's and Morison's, ``Network.form_path``)."""
    import skmoor

    def along_z(k):
        def f(t):
            value = np.asarray(heave(t)[k], float)
            out = np.zeros(value.shape + (1, 3))
            out[..., 0, 2] = value
            return out
        return f

    network = example.lazy_wave(example.SITES[SITE], ELEMENTS)
    for line in network.lines:
        for name, value in DRAG.items():
            setattr(line.line_type, name, value)
    network.hydro, network.form_path = True, form_path
    network.points[0] = skmoor.Point("hang_off", "coupled", example.SITES[SITE].hang_off)
    network.motion = skmoor.Motion(along_z(0), along_z(1), along_z(2), vectorized=True)
    model = skmoor.from_network(network)
    model.solver.update(scheme="generalized-alpha", rho_inf=RHO_INF)
    return model


def run_skmoor(example, dt, form_path="auto"):
    """(time loop s, hang-off tension at the output times N): ``integrate`` from the static
    state, the end forces computed by the step at the outputs."""
    import skmoor
    from skmoor.solvers.dynamics import Scheme, integrate

    model = skmoor_model(example, form_path)
    system, x0 = model.system, skmoor.equilibrium(model).x
    stride = output_stride(dt)
    tension = []
    started = time.perf_counter()
    for state in integrate(system, x0, np.zeros(system.n), dt, DURATION,
                           scheme=Scheme.generalized_alpha(RHO_INF), report_every=stride):
        if state.step % stride == 0:
            tension.append(np.linalg.norm(state.reactions[1][0]))  # end A: the hang-off
    return time.perf_counter() - started, np.array(tension)


def simulate_skmoor(example, dt):
    """Wall time (s) of ``skmoor.simulate`` as a user calls it (static state, loop, every
    output recorded), and its hang-off tension at the outputs (N)."""
    import skmoor

    model = skmoor_model(example)
    started = time.perf_counter()
    results = skmoor.simulate(model, duration=DURATION, dt=dt,
                              output_interval=output_stride(dt) * dt, progress=False)
    return time.perf_counter() - started, results.anchor_tension[:, 0]


def run_cabledyn(example, dt, workdir, whole=False):
    """(CableDyn's time s, hang-off tension at the output times N, the script's own time s
    between its calls): its step and calc_output calls alone, or with ``whole`` the model
    made from its deck (its static solve) and the loop."""
    import cabledyn
    from test_lazy_wave import cabledyn_deck

    options = CABLEDYN_OPTIONS.format(depth=example.SITES[SITE].depth, dt=dt)
    deck = cabledyn_deck(example, ELEMENTS, Path(workdir), options,
                         "{Cd_n} {Cd_t} {Ca_n} 0.0".format(**DRAG), site=SITE)
    own = glue = 0.0
    started = time.perf_counter()
    with quiet():
        model = cabledyn.CableDyn(str(deck))
    made = time.perf_counter()
    try:
        q, v, a = model.get_coupled_motion()
        dofs = model.host_dofs()
        z0 = q[dofs[2]]
        stride = output_stride(dt)
        steps_count = int(round(DURATION / dt))
        z, vz, az = heave(dt * np.arange(1, steps_count + 1))
        tension = [np.linalg.norm(model.calc_output()[dofs])]
        for k in range(steps_count):
            before = time.perf_counter()
            q[dofs[2]], v[dofs[2]], a[dofs[2]] = z0 + z[k], vz[k], az[k]
            inside = time.perf_counter()
            model.step(dt, q, v, a)
            if (k + 1) % stride == 0:
                tension.append(np.linalg.norm(model.calc_output()[dofs]))
            after = time.perf_counter()
            own += after - inside
            glue += inside - before
    finally:
        model.close()
    return (made - started if whole else 0.0) + own, np.array(tension), glue


def error(tension, dt, reference, ref_dt):
    """Largest |T - T_ref| / T_ref over the run's output times (inf for a failed run)."""
    if tension is None or not np.all(np.isfinite(tension)):
        return np.inf
    t = np.arange(len(tension)) * output_stride(dt) * dt
    t_ref = np.arange(len(reference)) * output_stride(ref_dt) * ref_dt
    at = np.searchsorted(t_ref, t - 1e-9)
    return float(np.max(np.abs(tension - reference[at]) / reference[at]))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--tolerance", type=float, default=TOLERANCE,
                        help="accuracy: share of the reference tension (default 0.005)")
    parser.add_argument("--write-docs", action="store_true",
                        help="write the table into docs/speed.md")
    args = parser.parse_args(argv)
    sys.path.insert(0, str(ROOT / "tests" / "lines"))  # the CableDyn deck of the tests
    workdir = tempfile.mkdtemp(prefix="skmoor-bending-")
    example = load_example(workdir)
    glue = {}

    def cabledyn(dt):
        try:
            wall, tension, glue[dt] = run_cabledyn(example, dt, workdir)
        except Exception as failure:  # noqa: BLE001 (a diverging run is a failed step)
            print(f"    CableDyn dt={dt:g}: failed ({type(failure).__name__}: {failure})")
            return np.nan, None
        return wall, tension

    def ours(dt):
        try:
            return run_skmoor(example, dt)
        except (RuntimeError, ValueError) as failure:
            print(f"    skmoor dt={dt:g}: failed ({type(failure).__name__}: {failure})")
            return np.nan, None

    def report(dt, wall, err):
        print(f"    dt = {dt:<10g} loop {wall:8.3f} s   error {err:.2e}")

    found = {}
    for name, run in (("skmoor", ours), ("CableDyn", cabledyn)):
        print(f"{name}: steps 2^{START} ... 2^{REFERENCE + 1} s against 2^{REFERENCE} s")
        found[name] = steps.find_step(run, lambda dt, T, ref_dt, ref: error(T, dt, ref, ref_dt),
                                      START, REFERENCE, args.tolerance, label=name,
                                      report=report)
    sk, cd = found["skmoor"], found["CableDyn"]
    if not (np.isfinite(sk["dt"]) and np.isfinite(cd["dt"])):
        print("no step holds the tolerance for one of the codes: no ratio")
        return
    same = error(sk["ref"], sk["ref_dt"], cd["ref"], cd["ref_dt"])
    simulated = min(simulate_skmoor(example, sk["dt"])[0] for _ in range(3))
    whole = min(run_cabledyn(example, cd["dt"], workdir, whole=True)[0] for _ in range(3))
    print()
    print(f"references: skmoor's within {same:.2%} of CableDyn's (tension at the outputs)")
    for name, row in found.items():
        print(f"{name:>8}: step {row['dt']:g} s, error {row['error']:.2%} of the reference, "
              f"time loop {row['wall']:.3f} s")
    print(f"CableDyn's glue (the script between its calls, not counted): "
          f"{glue.get(cd['dt'], np.nan):.3f} s")
    print(f"skmoor.simulate (statics, loop, outputs) {simulated:.3f} s; CableDyn made "
          f"from its deck and its loop {whole:.3f} s")
    print()
    print(f"time loop skmoor / CableDyn: {sk['wall'] / cd['wall']:.2f}")
    print(f"whole run skmoor / CableDyn: {simulated / whole:.2f}")
    if args.write_docs:
        facts = environment(["numpy", "numba", "cabledyn"])
        rows = [f"- commit {facts['commit']}; {facts['versions']}; {facts['machine']}", "",
                "| code | step (s) | largest difference from its reference | time loop "
                "skmoor / CableDyn | whole run skmoor / CableDyn |", "|---|---|---|---|---|",
                f"| skmoor | {sk['dt']:g} | {sk['error']:.2%} | **{sk['wall'] / cd['wall']:.2f}** "
                f"| {simulated / whole:.2f} |",
                f"| CableDyn | {cd['dt']:g} | {cd['error']:.2%} | | |", "",
                f"The two references within {same:.2%} of each other."]
        write_block(ROOT / "docs" / "speed.md", "bending.py table", "\n".join(rows))


if __name__ == "__main__":
    main()
