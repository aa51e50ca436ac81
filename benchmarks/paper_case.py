"""The paper's case in skmoor and in MoorDyn v2, side by side: wall time at equal accuracy.

The system: the paper's box on its four steel lines (11 elements / segments each),
F_x = 1e5 sin(1.6 t) N, 200 s from static rest. Both codes get the same physics:

- lines: EA times the engineering strain (skmoor's 'engineering' law; the paper's S = EA eps
  differs by O(T/EA) = 3e-4), lumped mass, no drag, no added mass on the lines;
- body: the same 6x6 mass + added mass, hydrostatic stiffness, buoyancy - weight and load.
  MoorDyn has no hydrostatic stiffness for bodies, so its lines are attached to four
  'Coupled' points and this script integrates the body (velocity Verlet at a coupling
  step of 10, 5 or 2.5 ms, the largest that meets the accuracy criterion below, MoorDyn
  sub-stepping at its own dtM inside);
- damping, two variants (both printed; the last line is the paper's):
  'moordyn-damping': the same explicit damping in both codes, MoorDyn's customary line
  damping BA = -0.8 (zeta (L/N) sqrt(EA m), skmoor's LineType.BA) and a 6x6 body damping
  (below), no Rayleigh damping;
  'paper': skmoor's Rayleigh C = a0 M + a1 K of the paper's case (3 % at the first two
  modes). MoorDyn gets its equivalent: BA = a1 EA (the axial part of a1 K) and
  a0 M_body + a1 (K_body + the mooring's condensed stiffness) on the body. That BA is
  large, and MoorDyn's explicit RK2 then needs a far smaller step (the damping's own
  stability limit), which is the paper case's cost in an explicit code.
- static state: MoorDyn's fairleads sit where skmoor's static solve puts them, and its line
  lengths are set so that its segmented chain has skmoor's static fairlead tension
  (tests/peers.py). It starts from its own catenary initial state (TmaxIC = 0): its
  dynamic relaxation, not converged in 60 s, leaves a state that depends on dtM (0.16 %
  in tension between 2 and 0.1 ms), which would blur the step search.

Accuracy: each code is run at a converged reference step (skmoor dt = 2.5 ms; MoorDyn
dtM = 0.025 ms with a 2 ms coupling step) and then at every step of its list, from large
to small; the step used is the largest whose fairlead tensions (all four lines, sampled
every 0.1 s), and those of every smaller step of the list, stay within 1 % of the tension
range of that code's own reference over the whole run (the error need not fall
monotonically with the step). The timed run is then repeated at that step, and the wall
times (everything from the built model to the tension histories: skmoor's static solve,
modes and time loop; MoorDyn's own time, Create, Init and its Step calls, with this
script's body integrator between the calls printed apart, not counted; the best of
three rounds that run both codes in turn) give the ratio.

Whole processes beside them (best of two interleaved rounds): skmoor in a new Python
process that imports it, builds the case, and simulates (static solve, modes, time
loop; numba's cache warm, its first compile is benchmarks/first_run.py's); MoorDyn in a
new process that imports it, reads the deck, and runs Init and its Step calls along the
fairlead motion its coupled run recorded (so without the body integrator it cannot do
itself).
The distance between the two codes' references is printed as a check of the physics; a
variant whose references differ by more than 5 % (the 'paper' one) compares different
physics, and its ratio is printed as such, not as a speed claim.

Run: python benchmarks/paper_case.py [--duration 200] [--variant both|paper|moordyn-damping]
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import moordyn  # noqa: E402
from _cases import ROOT, write_block  # noqa: E402

# skmoor and its test helpers are imported where they are used: MoorDyn's whole process
# does not import them

TOLERANCE = 0.01  # of the reference's fairlead tension range
SAMPLE = 0.1  # s, comparison grid
SKMOOR_STEPS = (0.2, 0.1, 0.075, 0.05, 0.04, 1 / 30, 0.025, 0.02, 0.0125)  # s
SKMOOR_REFERENCE = 0.0025  # s
MOORDYN_STEPS = (5e-3, 1e-2 / 3, 2.5e-3, 2e-3, 1e-3, 8e-4, 6.25e-4, 5e-4, 4e-4, 2.5e-4, 2e-4,
                 1.25e-4, 1e-4, 5e-5)  # s (the first divide the coupling steps)
MOORDYN_REFERENCE = (2.5e-5, 2e-3)  # s: dtM, coupling step
COUPLINGS = (0.01, 0.005, 0.0025)  # s, body coupling steps tried for MoorDyn


LINE_ZETA = 0.8  # MoorDyn's customary BA = -0.8: damping ratio of a segment's axial mode
TMAX_IC = 0.0  # s: MoorDyn starts from its own catenary state, the same for every dtM


class Scenario:
    """One system in both codes: skmoor's model, and the damping MoorDyn gets for it.

    'paper': the paper's case with its Rayleigh damping C = a0 M + a1 K; MoorDyn's lines
    get BA = a1 EA (the axial part of a1 K), its body a0 M_body + a1 (K_body + the
    mooring's condensed stiffness). 'moordyn-damping': both codes get the same explicit
    damping, MoorDyn's customary line damping BA = -0.8 (80 % of a segment's critical
    axial damping) and that body matrix, and no Rayleigh damping.
    """

    def __init__(self, name):
        from peers import condensed_line_stiffness

        import skmoor
        from skmoor.model.from_case import line_type

        self.name = name
        paper = skmoor.build(skmoor.paper_case(mooring__strain_law="engineering"))
        eq = skmoor.equilibrium(paper)
        a0, a1 = eq.rayleigh
        body = paper.body
        mass = body.mass_matrix() + body.added_mass
        stiffness = paper.system.K_body + condensed_line_stiffness(paper.system, eq.x)
        self.body_damping = a0 * mass + a1 * stiffness
        EA = line_type(paper.case, "steel").EA
        if name == "paper":
            self.model, self.BA = paper, a1 * EA
            self.description = (f"the paper's Rayleigh damping (MoorDyn: BA = a1 EA = "
                                f"{a1 * EA:.3g} N s and the body's share)")
        else:  # MoorDyn's -zeta convention: BA = zeta (L / N) sqrt(EA m)
            lt, line = line_type(paper.case, "steel"), paper.lines.lines[0]
            self.BA = LINE_ZETA * line.length / (len(line.s) - 1) * np.sqrt(EA * lt.mass)
            self.model = variant_model(name, self.BA, self.body_damping)
            self.description = (f"MoorDyn's line damping in both, BA = -{LINE_ZETA:g} "
                                f"(= {self.BA:.3g} N s), and the same body damping")
        self.eq = skmoor.equilibrium(self.model)


def variant_model(name, BA, body_damping):
    """skmoor's model of a variant (``BA`` N s and ``body_damping`` (6, 6) N s/m, N m s
    for 'moordyn-damping'), as a user builds it."""
    import skmoor

    if name == "paper":
        return skmoor.build(skmoor.paper_case(mooring__strain_law="engineering"))
    model = skmoor.build(skmoor.paper_case(mooring__strain_law="engineering",
                                           damping__ratio=0.0, line_types__steel__BA=BA))
    model.body.linear_damping = body_damping
    return model


# ------------------------------------------------------------------------------ skmoor

def run_skmoor(scenario, dt, duration):
    """(sample times, fairlead tensions (n, 4) N, wall time s) of skmoor at step dt."""
    import skmoor

    started = time.perf_counter()
    results = skmoor.simulate(scenario.model, duration=duration, dt=dt,
                              output_interval=max(dt, SAMPLE), progress=False)
    wall = time.perf_counter() - started
    if results.meta["stopped"]:
        return None, None, wall
    return results.t, results.fairlead_tension, wall


# ------------------------------------------------------------------------------ MoorDyn

class CoupledBody:
    """The paper's body for the MoorDyn run: its 6x6 matrices from skmoor's model."""

    def __init__(self, scenario):
        model, eq = scenario.model, scenario.eq
        system, body = model.system, model.body
        self.mass = body.mass_matrix() + body.added_mass
        self.inverse_mass = np.linalg.inv(self.mass)
        self.K = system.K_body
        self.F0 = system.F_bodies0[0]
        self.C = scenario.body_damping
        self.load = system.body_load
        self.r_local = system.r_local
        self.reference = body.reference_point
        self.q0 = system.q(eq.x).copy()
        self.BA = scenario.BA

    def fairleads(self, q, qdot):
        """Fairlead positions (4, 3) and velocities, m and m/s, and the Jacobians."""
        from skmoor.bodies.body import rotation_and_slopes

        R, dR = rotation_and_slopes(q[3:])
        J = np.zeros((len(self.r_local), 3, 6))
        J[:, :, :3] = np.eye(3)
        J[:, :, 3:] = np.einsum("akl,nl->nka", dR, self.r_local)
        position = self.reference + q[:3] + self.r_local @ R.T
        return position, J @ qdot, J

    def acceleration(self, q, qdot, t, line_forces, J):
        """Body acceleration from the lines' forces on the fairlead (4, 3), N."""
        force = np.einsum("nki,nk->i", J, line_forces) - self.K @ q + self.F0 - self.C @ qdot
        if self.load is not None:
            force += self.load(t, q, qdot)
        return self.inverse_mass @ force


def moordyn_deck(path, model, body, lengths, dtM):
    """A MoorDyn v2 deck of the paper's lines: fixed anchors, coupled fairleads."""
    from skmoor.model.from_case import line_type

    lt = line_type(model.case, "steel")
    num = lambda v: repr(float(v))  # noqa: E731
    fair, _, _ = body.fairleads(body.q0, np.zeros(6))
    points, lines = [], []
    for k, (cat, length) in enumerate(zip(model.catenaries, lengths)):
        a = cat.anchor
        points.append(f"{2 * k + 1} Fixed {num(a[0])} {num(a[1])} {num(a[2])} 0 0 0 0")
        f = fair[k]
        points.append(f"{2 * k + 2} Coupled {num(f[0])} {num(f[1])} {num(f[2])} 0 0 0 0")
        lines.append(f"{k + 1} steel {2 * k + 1} {2 * k + 2} {num(length)} "
                     f"{len(model.lines.lines[k].s) - 1} -")
    water = model.case.water
    Path(path).write_text(f"""skmoor benchmarks/paper_case.py: the paper's four lines
---------------------- LINE TYPES ----------------------------------
TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx
(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
steel {num(lt.diameter)} {num(lt.mass)} {num(lt.EA)} {num(body.BA)} 0 0 0 0 0
---------------------- POINTS --------------------------------------
ID Attachment X Y Z Mass Volume CdA Ca
(#) (word) (m) (m) (m) (kg) (m^3) (m^2) (-)
{chr(10).join(points)}
---------------------- LINES ---------------------------------------
ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs
(#) (name) (#) (#) (m) (-) (-)
{chr(10).join(lines)}
---------------------- OPTIONS -------------------------------------
0 writeLog
{num(dtM)} dtM
{num(water['gravity'])} g
{num(water['density'])} rho
{num(water['depth'])} WtrDpth
{TMAX_IC:g} TmaxIC
1e-9 threshIC
1 disableOutput
1 disableOutTime
---------------------- OUTPUTS -------------------------------------
---------------------- END -----------------------------------------
""")
    return path


def coupled_moordyn(md, body, duration, coupling, clock=None, motion=None):
    """Initialise the created MoorDyn system md at the body's static rest and step it with
    the body integrated here by velocity Verlet at the coupling step (s): yields (t,
    fairlead forces (4, 3) N, body displacement q) at the end of every step. clock: a
    dict whose "moordyn" entry gathers the time (s) spent inside Init and Step; motion: a
    list that gets the fairleads' (positions, velocities) given at Init and every Step."""
    clock = {} if clock is None else clock
    motion = [] if motion is None else motion
    clock.setdefault("moordyn", 0.0)
    q, qdot = body.q0.copy(), np.zeros(6)
    position, velocity, _ = body.fairleads(q, qdot)
    motion.append((position.ravel(), velocity.ravel()))
    started = time.perf_counter()
    if moordyn.Init(md, position.ravel().tolist(), velocity.ravel().tolist()) != 0:
        raise RuntimeError("MoorDyn: Init failed")
    clock["moordyn"] += time.perf_counter() - started
    acc = np.zeros(6)  # static rest, and the load is zero at t = 0
    for k in range(int(round(duration / coupling))):
        t = k * coupling
        # MoorDyn takes the coupled points' state at the start of the step and
        # extrapolates it with the velocity over the step
        position, velocity, _ = body.fairleads(q, qdot)
        motion.append((position.ravel(), velocity.ravel()))
        r, u = position.ravel().tolist(), velocity.ravel().tolist()
        started = time.perf_counter()
        out = moordyn.Step(md, r, u, t, coupling)
        clock["moordyn"] += time.perf_counter() - started
        forces = np.reshape(out, (-1, 3))
        half = qdot + 0.5 * coupling * acc
        q = q + coupling * half
        _, _, J = body.fairleads(q, half)
        acc = body.acceleration(q, half, t + coupling, forces, J)
        qdot = half + 0.5 * coupling * acc
        yield t + coupling, forces, q


GLUE = {}  # (dtM, coupling) -> s of this script's Python (the body integrator) in a run


def run_moordyn(model, body, lengths, dtM, duration, coupling, workdir=".", motion=None):
    """(sample times, fairlead tensions (n, 4) N, MoorDyn's own time s: Create, Init and
    the Step calls) of MoorDyn at step dtM; the script's body integrator and glue between
    the calls is kept in GLUE, not counted (MoorDyn cannot integrate a body under the
    paper's harmonic load itself); motion: see :func:`coupled_moordyn`."""
    deck = moordyn_deck(Path(workdir) / "paper.txt", model, body, lengths, dtM)
    whole = time.perf_counter()
    md = moordyn.Create(str(deck))
    clock = {"moordyn": time.perf_counter() - whole}

    def own():
        GLUE[(dtM, coupling)] = time.perf_counter() - whole - clock["moordyn"]
        return clock["moordyn"]

    try:
        every = int(round(SAMPLE / coupling))
        times, tensions = [], []
        for k, (t, forces, _) in enumerate(coupled_moordyn(md, body, duration, coupling,
                                                           clock, motion)):
            if not np.all(np.isfinite(forces)) or np.abs(forces).max() > 1e12:
                return None, None, own()
            if (k + 1) % every == 0:
                times.append(t)
                tensions.append(np.linalg.norm(forces, axis=1))
    finally:
        moordyn.Close(md)
    return np.array(times), np.array(tensions), own()


# ------------------------------------------------------------------------------ search

def error(t, tension, t_ref, tension_ref):
    """max |T - T_ref| over the run and the lines, over the reference's tension range."""
    if t is None or not np.all(np.isfinite(tension)):
        return np.inf
    ref = np.column_stack([np.interp(t, t_ref, tension_ref[:, k])
                           for k in range(tension_ref.shape[1])])
    return float(np.abs(tension - ref).max() / np.ptp(tension_ref))


def largest_step(label, steps, run, reference):
    """The largest step (s) of ``steps`` (from large to small) whose run, and the run at
    every smaller step of the list, is within TOLERANCE of the reference, and its error;
    (None, the least error) when none is, or when the error stops falling with the step
    before any step holds (a floor set by something else, e.g. MoorDyn's body coupling
    step)."""
    best, tried = np.inf, []
    for dt in steps:
        t, tension, wall = run(dt)
        err = error(t, tension, *reference)
        print(f"  {label} dt = {dt * 1e3:8.4g} ms: error {err:9.2%} of the tension range "
              f"({wall:6.2f} s)", flush=True)
        tried.append((dt, err))
        held = any(e <= TOLERANCE for _, e in tried)
        if not held and np.isfinite(best) and err > 0.95 * best:
            break
        best = min(best, err)
    picked = None
    for dt, err in reversed(tried):  # from the smallest step up: stop at the first failure
        if not err <= TOLERANCE:
            break
        picked = (dt, err)
    return picked if picked is not None else (None, best)


def compare(scenario, duration):
    """Search both codes' steps for one scenario and time them at theirs: a row of the
    table (steps, time loops, whole processes)."""
    from peers import chain_length_for

    model = scenario.model
    body = CoupledBody(scenario)
    static = np.linalg.norm(model.system.reactions(scenario.eq.x)[0], axis=1)
    n_segments = len(model.lines.lines[0].s) - 1
    lengths = [chain_length_for(cat, n_segments, T) for cat, T in zip(model.catenaries, static)]
    workdir = tempfile.mkdtemp(prefix="skmoor-bench-")

    print(f"\n== {scenario.name}: {scenario.description}")
    print("skmoor (implicit, the case's scheme):")
    t_ref, T_ref, wall = run_skmoor(scenario, SKMOOR_REFERENCE, duration)
    print(f"  reference dt = {SKMOOR_REFERENCE * 1e3:g} ms ({wall:.1f} s)")
    dt_sk, err_sk = largest_step("skmoor", SKMOOR_STEPS,
                                 lambda dt: run_skmoor(scenario, dt, duration), (t_ref, T_ref))
    if dt_sk is None:
        raise SystemExit(f"skmoor: no step within {TOLERANCE:.0%}; extend SKMOOR_STEPS")
    print("MoorDyn v2 (explicit RK2, lines) + the body integrated here:")
    dtM, coupling_ref = MOORDYN_REFERENCE
    with quiet():
        tm_ref, Tm_ref, wall = run_moordyn(model, body, lengths, dtM, duration, coupling_ref,
                                           workdir)
    print(f"  reference dtM = {dtM * 1e3:g} ms, coupling {coupling_ref * 1e3:g} ms "
          f"({wall:.1f} s)")
    for coupling in COUPLINGS:
        def moordyn_run(dt, coupling=coupling):
            with quiet():
                return run_moordyn(model, body, lengths, dt, duration, coupling, workdir)

        steps = [dt for dt in MOORDYN_STEPS if dt <= coupling]
        print(f"  body coupling step {coupling * 1e3:g} ms:")
        dt_md, err_md = largest_step("MoorDyn", steps, moordyn_run, (tm_ref, Tm_ref))
        if dt_md is not None:
            break
    else:
        raise SystemExit(f"MoorDyn: no step within {TOLERANCE:.0%}; extend the steps")
    between = error(t_ref, T_ref, tm_ref, Tm_ref)
    print(f"  the two references differ by {between:.1%} of MoorDyn's tension range")
    walls = [(run_skmoor(scenario, dt_sk, duration)[2], moordyn_run(dt_md)[2])
             for _ in range(3)]  # interleaved: a load that comes and goes falls on both
    wall_sk, wall_md = (min(w) for w in zip(*walls))
    motion = []  # MoorDyn's fairlead motion at its step, for its whole process
    with quiet():
        run_moordyn(model, body, lengths, dt_md, duration, coupling, workdir, motion)
    whole_sk, whole_md = whole_processes(scenario, dt_sk, dt_md, coupling, duration, model,
                                         body, lengths, motion, workdir)
    print(f"  skmoor:  dt  = {dt_sk * 1e3:g} ms, error {err_sk:.2%}, wall {wall_sk:.2f} s")
    print(f"  MoorDyn: dtM = {dt_md * 1e3:g} ms (coupling {coupling * 1e3:g} ms), error "
          f"{err_md:.2%}, wall {wall_md:.2f} s (Create, Init and Step; this script's body "
          f"integrator between the calls, not counted: {GLUE[(dt_md, coupling)]:.2f} s)")
    if between > 0.05:  # not the same system: a ratio of two systems, not a speed claim
        print(f"  {scenario.name}: wall-time ratio skmoor/moordyn = {wall_sk / wall_md:.3f} "
              f"between different physics (references {between:.0%} apart): not a speed "
              "claim")
    else:
        print(f"  {scenario.name}: ratio skmoor/moordyn = {wall_sk / wall_md:.3f}")
    print(f"  whole processes: skmoor {whole_sk:.2f} s, MoorDyn {whole_md:.2f} s "
          f"(ratio {whole_sk / whole_md:.3f})")
    return dict(variant=scenario.name, dt_sk=dt_sk, dt_md=dt_md, coupling=coupling,
                between=between, wall_sk=wall_sk, wall_md=wall_md,
                glue=GLUE[(dt_md, coupling)], whole_sk=whole_sk, whole_md=whole_md)


# ------------------------------------------------------------------------------ whole processes

def whole_processes(scenario, dt_sk, dt_md, coupling, duration, model, body, lengths,
                    motion, workdir, rounds=2):
    """(skmoor's, MoorDyn's) whole process, s: the best of ``rounds`` interleaved rounds
    of new Python processes (:func:`one_process`)."""
    deck = moordyn_deck(Path(workdir) / "whole.txt", model, body, lengths, dt_md)
    np.savez(Path(workdir) / "whole.npz", r=np.array([m[0] for m in motion]),
             u=np.array([m[1] for m in motion]),
             body_damping=getattr(scenario, "body_damping", np.zeros((6, 6))))
    children = {
        "skmoor": ["skmoor", scenario.name, repr(float(scenario.BA)), repr(dt_sk),
                   repr(duration), str(workdir)],
        "moordyn": ["moordyn", str(deck), repr(coupling), repr(duration), str(workdir)]}
    walls = {code: [] for code in children}
    for _ in range(rounds):
        for code, args in children.items():
            started = time.perf_counter()
            out = subprocess.run([sys.executable, __file__, "--one", *args],
                                 capture_output=True, text=True, check=False)
            if out.returncode or not out.stdout.strip():
                raise RuntimeError(f"{code}'s whole process failed: {out.stderr[-800:]}")
            walls[code].append(time.perf_counter() - started)
    return min(walls["skmoor"]), min(walls["moordyn"])


def one_process(code, *args):
    """The child of :func:`whole_processes`: one code's run as a user makes it in a new
    process; prints its time loop's wall time (s) as JSON."""
    if code == "skmoor":
        import skmoor

        name, BA, dt, duration, workdir = args
        saved = np.load(Path(workdir) / "whole.npz")
        model = variant_model(name, float(BA), saved["body_damping"])
        results = skmoor.simulate(model, duration=float(duration), dt=float(dt),
                                  output_interval=max(float(dt), SAMPLE), progress=False)
        print(json.dumps({"loop": results.meta["wall_time"]}))
        return
    deck, coupling, duration, workdir = args
    saved = np.load(Path(workdir) / "whole.npz")
    r, u = saved["r"].tolist(), saved["u"].tolist()
    coupling = float(coupling)
    md = moordyn.Create(deck)
    started = time.perf_counter()
    moordyn.Init(md, r[0], u[0])
    for k in range(int(round(float(duration) / coupling))):
        moordyn.Step(md, r[k + 1], u[k + 1], k * coupling, coupling)
    loop = time.perf_counter() - started
    moordyn.Close(md)
    print(json.dumps({"loop": loop}))


def markdown_table(rows) -> str:
    """The variants' steps, times and ratios as a markdown table."""
    lines = ["| damping | skmoor dt | MoorDyn dtM / coupling | references apart | skmoor "
             "[s] | MoorDyn [s] (script's body integrator, not counted) | skmoor/MoorDyn | "
             "whole process skmoor / MoorDyn [s] | whole skmoor/MoorDyn |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        same = r["between"] <= 0.05
        ratio, whole = r["wall_sk"] / r["wall_md"], r["whole_sk"] / r["whole_md"]
        ratio, whole = ((f"**{ratio:.2f}**", f"{whole:.2f}") if same else
                        (f"{ratio:.3f}: different physics, not a speed claim", f"{whole:.3f}"))
        lines.append(f"| {r['variant']} | {r['dt_sk'] * 1e3:g} ms | {r['dt_md'] * 1e3:g} ms / "
                     f"{r['coupling'] * 1e3:g} ms | {r['between']:.1%} | {r['wall_sk']:.2f} | "
                     f"{r['wall_md']:.2f} ({r['glue']:.2f}) | {ratio} | "
                     f"{r['whole_sk']:.2f} / {r['whole_md']:.2f} | {whole} |")
    return "\n".join(lines)


class quiet:
    """Silence MoorDyn's console output (it writes to the C-level stdout)."""

    def __enter__(self):
        sys.stdout.flush()
        self.saved = os.dup(1)
        self.null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(self.null, 1)

    def __exit__(self, *exc):
        sys.stdout.flush()
        os.dup2(self.saved, 1)
        os.close(self.null)
        os.close(self.saved)


def main(argv=None):
    if argv is None and sys.argv[1:2] == ["--one"]:  # a whole process's child
        one_process(*sys.argv[2:])
        return
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--duration", type=float, default=200.0, help="simulated time, s")
    parser.add_argument("--variant", choices=("both", "paper", "moordyn-damping"),
                        default="both", help="damping variant(s) to run (default: both)")
    parser.add_argument("--write-docs", action="store_true", help="write the table into "
                        "docs/speed.md")
    args = parser.parse_args(argv)
    print(f"the paper's case, {args.duration:g} s simulated, 11 segments per line; step "
          f"criterion: fairlead tensions within {TOLERANCE:.0%} of the reference's range")
    os.chdir(tempfile.mkdtemp(prefix="skmoor-bench-"))  # MoorDyn may write files here
    rows = [compare(Scenario(name), args.duration) for name in ("moordyn-damping", "paper")
            if args.variant in ("both", name)]
    table = markdown_table(rows)
    print("\n" + table)
    if args.write_docs:
        write_block(ROOT / "docs" / "speed.md", "paper_case.py table", table)


if __name__ == "__main__":
    main()
