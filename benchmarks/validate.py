"""Every comparison skmoor has, run now, written as one table: docs/validation.md.

Each check is a small function returning rows: what is compared, the reference value and
where it comes from (an analytic formula with its citation, MoorPy, MoorDyn, OrcaFlex as
published, the paper), skmoor's value, the error, the tolerance, pass or fail. The
set-ups are the test suite's own (imported from tests/), so the report and the tests
measure the same thing; the numbers in the report come from this run only. The checks
of lines, statics and dynamics are here; those of the tension laws in validate_laws.py,
of bending lines, rods and rigid bodies in validate_structures.py, of bodies in waves,
sea input and VolturnUS-S in validate_sea.py. A check whose input is not on the machine
(MoorDyn's or the IEA repository's mirror) is listed as not run.

Run: ``python benchmarks/validate.py [--quick] [--out docs/validation.md]``
(--quick leaves out the slow checks: about 12 s instead of about 4.5 min on 2 cores). Exit
status 1 if a check fails.
"""
from __future__ import annotations

import argparse
import itertools
import sys
import tempfile
import time
from pathlib import Path

import _cases
import numpy as np
from _cases import ROOT, inside, quiet
from _validation import (
    FE_ORDER,
    IRVINE,
    IRVINE_MODES,
    MOORDYN,
    MOORPY,
    ORCAFLEX,
    PAPER,
    STRING,
    TIME_ORDER,
    NotRun,
    Row,
)
from scipy.optimize import brentq
from validate_laws import (
    check_curve_catenary,
    check_slack_and_snap,
    check_viscoelastic_polyester,
)
from validate_sea import (
    check_bed_damping,
    check_box_in_regular_waves,
    check_capytaine_long_waves,
    check_paper_case_against_moordyn,
    check_radiation_memory,
    check_retardation_kernel,
    check_sea_decks_in_time,
    check_volturnus_static,
    check_wavekin3_record,
    check_wavekin7_against_moordyn,
)
from validate_structures import (
    check_beams_euler_bernoulli,
    check_floating_spar_rod,
    check_free_spin,
    check_large_roll,
    check_lazy_wave,
    check_lazy_wave_dynamics_orcaflex,
    check_lowe_langley_jumper,
    check_moordyn_beam_decks,
    check_pendulum_on_a_free_body,
    check_pinned_rod_pendulum,
    check_pinned_rods_in_current,
    check_rising_rods,
    check_squat_spar_periods,
    check_symmetric_top,
)


def _number(value, unit=""):
    text = f"{value:.6g}"
    return f"{text} {unit}".strip()


def _error(row):
    error = row.error
    if row.kind == "abs":
        return f"{error:.3g} {row.unit}".strip()
    return f"{error:.2%}" if error >= 1e-4 else f"{error:.1e}"


# ------------------------------------------------------------------ statics

def check_catenary_vs_moorpy():
    """skmoor's analytic catenary against MoorPy's catenary(): fairlead tension of the
    test suite's lines (slack, near-taut, touchdown, ...), laid length with touchdown."""
    from test_catenary import CASES, case_line, moorpy_forces, paper_line

    rows = []
    for name in [*CASES, "paper"]:
        line = paper_line(0.9) if name == "paper" else case_line(name)
        seabed = -100.0 if name == "paper" else CASES[name][-1]
        *_, fBH, fBV, info = moorpy_forces(line, seabed)
        rows.append(Row(f"analytic catenary '{name}': fairlead tension", np.hypot(fBH, fBV),
                        MOORPY + " (Catenary.catenary)", line.T_fairlead, 1e-6, unit="N"))
        if line.laid_length > 0:
            rows.append(Row(f"analytic catenary '{name}': laid length", info["LBot"],
                            MOORPY + " (Catenary.catenary)", line.laid_length, 1e-6, unit="m"))
    return rows


def check_fe_statics_vs_irvine():
    """Static FE solve from the stress-free line (40 elements) against the elastic
    catenary: end tensions of the paper's steel line (sag 1/60) and of a slack line."""
    from test_line_statics import catenary, fe_solve

    rows = []
    for case in ("near_taut", "slack"):
        exact = catenary(case)
        _, fairlead, anchor = fe_solve(case, 40)
        label = ("paper steel line (d/l = 1/60)" if case == "near_taut"
                 else "slack line (L = 1.2 chord)")
        rows.append(Row(f"FE statics, {label}, 40 el.: fairlead tension", exact.T_fairlead,
                        IRVINE, float(np.linalg.norm(fairlead)), 1e-3, unit="N"))
        rows.append(Row(f"FE statics, {label}, 40 el.: anchor tension", exact.T_anchor,
                        IRVINE, float(np.linalg.norm(anchor)), 1e-3, unit="N"))
    return rows


def check_fe_convergence_order():
    """Observed order of the FE end tensions' error against the elastic catenary over
    10, 20, 40, 80 elements."""
    from test_line_statics import relative_errors

    counts = np.array([10, 20, 40, 80])
    rows = []
    for case in ("near_taut", "slack"):
        errors = np.abs([relative_errors(case, n) for n in counts])
        for end, name in enumerate(("fairlead", "anchor")):
            order = -np.polyfit(np.log(counts), np.log(errors[:, end]), 1)[0]
            rows.append(Row(f"FE statics convergence order, {case}, {name} tension", 2.0,
                            FE_ORDER + f", error against {IRVINE}", float(order), 0.2, "abs"))
    return rows


def check_fe_is_its_discrete_chain():
    """The FE static solve (10 elements) is the exact equilibrium of its chain of elastic
    links, solved independently by shooting."""
    from test_line_statics import STEEL, catenary, discrete_chain, fe_solve

    line, fairlead, _ = fe_solve("near_taut", 10)
    exact = catenary("near_taut")
    chain, _ = discrete_chain(np.diff(line.s), STEEL.weight, STEEL.EA, (exact.H, exact.V_anchor))
    return Row("FE statics = discrete chain of links (10 el.): fairlead tension",
               float(np.linalg.norm(chain)), "exact equilibrium of the link chain (shooting)",
               float(np.linalg.norm(fairlead)), 1e-8, unit="N")


def check_paper_draft():
    """The paper's draft from Eq. 1 (weight, buoyancy, four lines' pull)."""
    from test_catenary import RHO_WATER, G, paper_line

    from skmoor.io.case import paper_case
    from skmoor.model.model import build

    draft = build(paper_case()).draft

    def vertical_imbalance(h):
        return RHO_WATER * G * h * 26 * 10 - 1.2e5 * G - 4 * paper_line(h).V_fairlead

    exact = brentq(vertical_imbalance, 0.5, 1.5, xtol=1e-10)
    return [Row("paper case: draft", 0.896, PAPER + " (flat-sag lines give 0.8963 m)", draft,
                5e-3, unit="m"),
            Row("paper case: draft, Eq. 1 with the catenary solved alone", exact,
                IRVINE + ", Eq. 1 solved by brentq", draft, 1e-4, unit="m")]


# ------------------------------------------------------------------ frequencies

def check_taut_string():
    """Weightless string (50 elements), T = 1e5 N, m = 10 kg/m, L = 100 m, askew."""
    from test_string_modes import modes_about_reference

    from skmoor.lines.line import Line, LineType

    T, m, L = 1e5, 10.0, 100.0
    string = LineType(EA=1e9, mass=m, diameter=0.05, weight=0.0)
    direction = np.array([1.0, 2.0, 2.0]) / 3.0
    points = np.linspace([0.0, 0.0, -50.0], [0.0, 0.0, -50.0] + L * direction, 51)
    _, modes, _ = modes_about_reference(Line.from_polyline(points, string, tension=T), 8)
    rows = []
    for k in (1, 2, 3):
        exact = k * np.pi / L * np.sqrt(T / m)
        pair = modes.omega[2 * k - 2: 2 * k]  # one mode per transverse plane
        worst = pair[np.argmax(np.abs(pair / exact - 1))]
        rows.append(Row(f"taut string, 50 el.: omega_{k} (the worse of its two planes)",
                        exact, STRING, float(worst), 5e-3, unit="rad/s"))
    return rows


def check_sagging_cable():
    """A horizontal 200 m span of rope, sag / span 1/50 (lambda^2 ~ 20), 40 elements:
    first out-of-plane, antisymmetric and symmetric in-plane frequencies."""
    from test_string_modes import irvine_lambda2, modes_about_reference

    from skmoor.lines.catenary import solve_catenary
    from skmoor.lines.line import Line, LineType

    rope, span = LineType(EA=4e8, mass=50.0, diameter=0.1), 200.0
    cable = solve_catenary([0.0, 0.0, 0.0], [span, 0.0, 0.0], rope.weight, rope.EA,
                           sag_ratio=1 / 50)
    _, modes, shapes = modes_about_reference(Line.from_catenary(cable, rope, 40), 6)
    base = np.pi / span * np.sqrt(cable.H / rope.mass)
    size = np.abs(shapes).max(axis=(1, 2))
    vertical = shapes[:, :, 2]
    scale = 1e-6 * np.abs(vertical).max()
    out_of_plane = np.abs(shapes[:, :, 1]).max(axis=1) > 0.99 * size
    antisymmetric = ~out_of_plane & np.all(np.isclose(vertical, -vertical[:, ::-1], atol=scale), 1)
    symmetric = (np.all(np.isclose(vertical, vertical[:, ::-1], atol=scale), 1)
                 & (np.abs(vertical).max(axis=1) > 0.5 * size))
    lam2 = irvine_lambda2(cable, span)
    half = brentq(lambda x: np.tan(x) - x + 4 / lam2 * x**3, np.pi / 2 + 1e-6,
                  3 * np.pi / 2 - 1e-6)
    label = f"sagged cable (lambda^2 = {lam2:.1f}), 40 el.:"
    return [Row(f"{label} 1st out-of-plane", base, IRVINE_MODES + ": pi / l sqrt(H / m)",
                float(modes.omega[out_of_plane][0]), 1e-2, unit="rad/s"),
            Row(f"{label} 1st antisymmetric in-plane", 2 * base,
                IRVINE_MODES + ": 2 pi / l sqrt(H / m)", float(modes.omega[antisymmetric][0]),
                1e-2, unit="rad/s"),
            Row(f"{label} 1st symmetric in-plane", 2 * half / span * np.sqrt(cable.H / rope.mass),
                IRVINE_MODES + ": tan(w/2) = w/2 - 4/lambda^2 (w/2)^3",
                float(modes.omega[symmetric][0]), 1e-2, unit="rad/s")]


# ------------------------------------------------------------------ MoorPy

def check_moorpy_end_forces():
    """The paper's case (11 elements): FE static reactions of line C1 against MoorPy's
    catenary at the same anchor, fairlead and length; the draft balances MoorPy's pull."""
    from peers import moorpy_system
    from test_peers_moorpy import static_state

    model, x = static_state(11)
    ms, body = moorpy_system(model, q=model.system.q(x))
    fair, anchor = model.system.reactions(x)
    rows = [Row("paper case, 11 el.: line C1 fairlead tension", ms.lineList[0].TB, MOORPY,
                float(np.linalg.norm(fair[0])), 1e-4, unit="N"),
            Row("paper case, 11 el.: line C1 anchor tension", ms.lineList[0].TA, MOORPY,
                float(np.linalg.norm(anchor[0])), 1e-4, unit="N")]
    rho, g = model.case.water["density"], model.case.water["gravity"]
    length, width, _ = model.case.body["size"]
    weight = model.body.mass * g
    imbalance = (rho * g * length * width * model.draft - weight
                 + body.getForces(lines_only=True)[2]) / weight
    rows.append(Row("paper case: weight - buoyancy - MoorPy's line pull, / weight", 0.0,
                    MOORPY + " (Body.getForces)", float(imbalance), 1e-8, "abs"))
    return rows


def check_moorpy_stiffness(n_elements=11):
    """The 6x6 mooring stiffness at equilibrium (condensed FE tangent) against MoorPy's
    getCoupledStiffnessA, the significant entries."""
    from test_peers_moorpy import NAMES, SIGNIFICANT, stiffness_errors

    _, K_sk, K_mp = stiffness_errors(n_elements)
    keep = ("surge", "sway", "heave", "roll", "pitch", "yaw", "surge-pitch")
    return [Row(f"paper case, {n_elements} el.: mooring stiffness {name}",
                float(K_mp[SIGNIFICANT[k]]), MOORPY + " (getCoupledStiffnessA)",
                float(K_sk[SIGNIFICANT[k]]), 1e-2) for k, name in enumerate(NAMES) if name in keep]


def check_moorpy_stiffness_order():
    """The stiffness error falls fourfold from 20 to 40 elements (surge, heave, pitch)."""
    from test_peers_moorpy import NAMES, stiffness_errors

    ratio = stiffness_errors(20)[0] / stiffness_errors(40)[0]
    return [Row(f"paper case: mooring stiffness error 20 el. / 40 el., {name}", 4.0,
                FE_ORDER + ", error against " + MOORPY, float(ratio[NAMES.index(name)]), 0.4,
                "abs") for name in ("surge", "heave", "pitch")]


def check_moorpy_stretchy_line():
    """Fairlead stiffness of a line strained 4 % (engineering strain law, 40 elements)
    against MoorPy's analytic line stiffness KB."""
    from test_peers_moorpy import stretchy_line_stiffness

    K_sk, line, _ = stretchy_line_stiffness("engineering", 40)
    return [Row(f"stretchy line (T/EA = 4 %), 40 el.: fairlead stiffness {name}",
                float(line.KB[i, i]), MOORPY + " (Line.KB)", float(K_sk[i, i]), 1e-3, unit="N/m")
            for i, name in ((0, "xx"), (2, "zz"))]


# ------------------------------------------------------------------ dynamics

def check_moordyn_driven_line(n=11):
    """Line C1 of the paper's case, fairlead driven 0.05 sin(1.6 t) m along x, 30 s,
    n elements / segments, same physics as MoorDyn (tests/run/test_peers_moordyn.py)."""
    from peers import amplitude
    from test_peers_moordyn import DURATION, PERIOD, compare, side_by_side

    with tempfile.TemporaryDirectory() as workdir, inside(workdir), quiet():
        run = side_by_side(n, Path(workdir))
    _, rms = compare(run, 3)
    t0 = DURATION - 3 * PERIOD
    mean_sk = run["T_sk"][run["t_sk"] >= t0].mean()
    mean_md = run["T_md"][run["t_md"] >= t0].mean()
    label = f"driven line C1, {n} el./segments:"
    return [Row(f"{label} static fairlead tension", run["static_md"], MOORDYN,
                float(run["T_sk"][0]), 1e-4, unit="N"),
            Row(f"{label} tension amplitude, last 3 periods",
                amplitude(run["t_md"], run["T_md"], t0), MOORDYN,
                amplitude(run["t_sk"], run["T_sk"], t0), 3e-2, unit="N"),
            Row(f"{label} mean tension, last 3 periods", float(mean_md), MOORDYN, float(mean_sk),
                1e-3, unit="N"),
            Row(f"{label} RMS tension difference / amplitude, last 3 periods", 0.0, MOORDYN,
                float(rms), 0.10, "abs")]


def check_energy_conservation():
    """Undamped free vibration of the paper's line (10 el., first mode, 0.1 m) over 100
    periods with Newmark's average acceleration: largest energy drift / vibration energy."""
    from test_dynamics import paper_line, potential_energy

    from skmoor.coupling.system import System
    from skmoor.solvers.dynamics import Scheme, integrate
    from skmoor.solvers.modes import eigenmodes

    lines = paper_line()
    system = System(lines, fairleads="fixed")
    _, K, _ = system.residual(np.zeros(system.n))
    modes = eigenmodes(K, system.M, k=1)
    x0 = 0.1 * modes.shapes[:, 0] / np.abs(modes.shapes[:, 0]).max()

    def energy(x, v):
        return 0.5 * v @ (system.M @ v) + potential_energy(lines, system.full_displacement(x))

    zero = np.zeros(system.n)
    e0, amplitude = energy(x0, zero), energy(x0, zero) - energy(zero, zero)
    drift = 0.0
    for state in integrate(system, x0, zero, modes.periods[0] / 50, 100 * modes.periods[0],
                           scheme=Scheme.newmark()):
        if state.step % 10 == 0:
            drift = max(drift, abs(energy(state.x, state.v) - e0))
    return Row("free vibration, 100 periods, Newmark: energy drift / vibration energy", 0.0,
               "energy conservation of the average-acceleration rule", float(drift / amplitude),
               1e-3, "abs")


def check_time_order():
    """Fairlead of the paper's line driven smoothly for 4 s: observed order of the
    error against a 0.004 s reference, dt = 0.08, 0.04, 0.02 s."""
    from test_dynamics import paper_line

    from skmoor.coupling.system import System
    from skmoor.solvers.dynamics import Scheme, integrate

    def final_state(dt, scheme):
        system = System(paper_line(law="engineering"), fairleads="prescribed",
                        motion=lambda t: [[0.5 * np.sin(1.6 * t) ** 2, 0.0,
                                           0.3 * np.sin(1.6 * t) ** 2]])
        for state in integrate(system, np.zeros(system.n), np.zeros(system.n), dt, 4.0,
                               scheme=scheme):
            pass
        return state.x

    rows = []
    for name, scheme in (("Newmark", Scheme.newmark()),
                         ("generalized-alpha 0.8", Scheme.generalized_alpha(0.8))):
        reference = final_state(0.004, scheme)
        dts = [0.08, 0.04, 0.02]
        errors = [np.abs(final_state(dt, scheme) - reference).max() for dt in dts]
        order = np.polyfit(np.log(dts), np.log(errors), 1)[0]
        rows.append(Row(f"driven line, {name}: observed order in dt", 2.0, TIME_ORDER,
                        float(order), 0.25, "abs"))
    return rows


# ------------------------------------------------------------------ sea bed

def check_seabed_touchdown():
    """A chain on a stiff frictionless sea bed (150 elements, from the analytic catenary
    with touchdown, tests/sea/test_seabed.py): static FE solve with the fairlead where the
    catenary has it and moved 5 m away / closer, against the analytic catenary with
    touchdown of the moved fairlead: fairlead tension and laid length."""
    from test_seabed import touchdown_solution

    nel = 150
    rows = []
    for shift in (0.0, -5.0, 5.0):
        tension, laid, exact = touchdown_solution(shift, nel)
        label = f"chain on the sea bed, fairlead moved {shift:+g} m, {nel} el.:"
        rows += [Row(f"{label} fairlead tension", exact.T_fairlead, IRVINE + " with touchdown",
                     tension, 5e-3, unit="N"),
                 Row(f"{label} laid length", exact.laid_length, IRVINE + " with touchdown",
                     laid, 5e-3, unit="m")]
    return rows


def check_seabed_friction():
    """A 100 m line lying on the bed, its far end dragged at 0.2 m/s along and across
    itself (tests/sea/test_seabed.py): the drag force against Coulomb's mu w L_laid."""
    from test_seabed import CHAIN, drag

    force_a, laid = drag([1.0, 0.0], mu_axial=0.3, mu_lateral=0.9, stretch=0.01, t_end=4.0)
    force_l, laid_l = drag([0.0, 1.0], mu_axial=0.1, mu_lateral=0.8, stretch=1.0, t_end=6.0)
    return [Row("line dragged along itself on the bed: friction force", 0.3 * CHAIN.weight * laid,
                "Coulomb: mu_axial w L (mu_axial = 0.3)", float(force_a), 1e-2, unit="N"),
            Row("line dragged across itself on the bed: friction force",
                0.8 * CHAIN.weight * laid_l, "Coulomb: mu_lateral w L (mu_lateral = 0.8)",
                float(force_l), 1e-2, unit="N")]


def check_orcaflex_chain():
    """The chain set MoorDyn validates against OrcaFlex (tests/lines/test_chain_statics.py):
    static FE solve (100 elements, sea-bed term) from a stress-free L-shaped line, end
    tensions against OrcaFlex's and against the analytic catenary with touchdown."""
    from test_chain_statics import CASES, CHAIN, l_shaped

    from skmoor.coupling.system import System
    from skmoor.lines.catenary import solve_catenary
    from skmoor.lines.line import Line, LineSet
    from skmoor.sea.seabed import Seabed, seabed_term
    from skmoor.solvers.statics import solve_static

    rows = []
    for depth, span, length, fair_kN, anchor_kN in CASES.values():
        lines = LineSet([Line.from_polyline(l_shaped(depth, span, length, 100), CHAIN)],
                        law="engineering")
        system = System(lines, fairleads="fixed", terms=[seabed_term(lines, Seabed(depth))])
        x = solve_static(system, pretension=CHAIN.weight * length).x
        fairlead, anchor = (float(np.linalg.norm(f[0])) for f in system.reactions(x))
        exact = solve_catenary([span, 0.0, -depth], np.zeros(3), CHAIN.weight, CHAIN.EA,
                               length=length, seabed_z=-depth)
        label = f"chain in {depth:g} m, {length:g} m long, 100 el.:"
        rows += [Row(f"{label} fairlead tension", fair_kN * 1e3, ORCAFLEX, fairlead, 2e-2,
                     unit="N"),
                 Row(f"{label} anchor tension", anchor_kN * 1e3, ORCAFLEX, anchor, 2e-2, unit="N"),
                 Row(f"{label} fairlead tension", exact.T_fairlead, IRVINE + " with touchdown",
                     fairlead, 1e-3, unit="N"),
                 Row(f"{label} anchor tension", exact.T_anchor, IRVINE + " with touchdown",
                     anchor, 1e-3, unit="N")]
    return rows


def check_chain_dynamics():
    """The 50 m chain deck (examples/decks/chain_50m.dat) heaved 2 m / 10 s at the
    fairlead, skmoor (deck model, dt = 0.05 s) and MoorDyn on the same file
    (tests/lines/test_chain_dynamics.py), 30 s: static tension, and the largest tension
    difference after the transient over MoorDyn's tension range."""
    from test_chain_dynamics import side_by_side

    with tempfile.TemporaryDirectory() as workdir, inside(workdir), quiet():
        results, _, T_md, error, span = side_by_side("50", 2.0, 30.0, 0.05, Path(workdir))
    label = "chain deck 50 m, heave 2 m / 10 s:"
    return [Row(f"{label} static fairlead tension", float(T_md[0]), MOORDYN,
                float(results.fairlead_tension[0, 0]), 5e-3, unit="N"),
            Row(f"{label} largest tension difference / MoorDyn's range "
                f"({span / 1e3:.0f} kN), t >= 20 s", 0.0, MOORDYN, float(error), 5e-2, "abs")]


def check_airy_dispersion():
    """skmoor.sea.waves.wavenumber against the root of omega^2 = g k tanh(k h) found by brentq,
    a 10 s wave in shallow, intermediate and deep water."""
    from skmoor.sea.waves import G, wavenumber

    omega = 2 * np.pi / 10.0
    rows = []
    for depth in (5.0, 50.0, 1000.0):
        exact = brentq(lambda k: G * k * np.tanh(k * depth) - omega**2, 1e-8, 10.0, xtol=1e-15,
                       rtol=1e-15)
        rows.append(Row(f"Airy wave, T = 10 s, h = {depth:g} m: wave number", exact,
                        "Airy: omega^2 = g k tanh(k h) (root by brentq)",
                        float(wavenumber(omega, depth)), 1e-12, unit="rad/m"))
    return rows


def _string(lt, tension=1e5, length=100.0, n=50):
    """A straight horizontal string along x at 50 m depth with fixed ends, tension T (N)."""
    from skmoor.lines.line import Line

    return Line.from_polyline(np.linspace([0.0, 0.0, -50.0], [length, 0.0, -50.0], n + 1), lt,
                              tension=tension)


def check_string_in_current():
    """A weightless taut string (T0 = 1e5 N, EA = 1e8 N, L = 100 m, d = 0.1 m, Cd = 1.2,
    50 elements) across a uniform 1 m/s current: its mid-span deflection against the
    flat-sag string under the drag load q = 1/2 rho Cd d U^2: d = q L^2 / (8 H), its
    stretch (8/3)(d/L)^2 raising the tension to H = T0 + EA (8/3)(d/L)^2 (+12 % here)."""
    from skmoor.coupling.system import System
    from skmoor.lines.line import LineSet, LineType
    from skmoor.sea.hydro import line_hydrodynamics
    from skmoor.sea.waves import Current, Sea
    from skmoor.solvers.statics import solve_static

    T0, EA, L, U = 1e5, 1e8, 100.0, 1.0
    lt = LineType(EA=EA, mass=10.0, diameter=0.1, weight=0.0, Cd_n=1.2)
    lines = LineSet([_string(lt, T0, L)])
    sea = Sea(1000.0, rho=lt.rho_water, current=Current(U, heading_deg=90.0))
    system = System(lines, fairleads="fixed", terms=[line_hydrodynamics(lines, sea)])
    u = system.full_displacement(solve_static(system).x)[lines.nodal_dofs]
    q = 0.5 * lt.rho_water * lt.Cd_n * lt.diameter * U**2
    H = brentq(lambda H: H - T0 - EA * 8 / 3 * (q * L / (8 * H)) ** 2, T0, 10 * T0)
    return Row("taut string across a current, 50 el.: mid-span deflection", q * L**2 / (8 * H),
               "flat-sag string under a uniform load: q L^2 / (8 H), H = T0 + EA (8/3)(d/L)^2, "
               "q = 1/2 rho Cd d U^2", float(u[len(u) // 2, 1]), 1e-2, unit="m")


def check_added_mass_frequency():
    """The taut string (T = 1e5 N, L = 100 m, m = 10 kg/m, d = 0.1 m) with Ca = 1:
    first transverse frequency pi / L sqrt(T / (m + Ca rho pi d^2 / 4))."""
    from skmoor.coupling.system import System
    from skmoor.lines.line import LineSet, LineType
    from skmoor.sea.hydro import line_hydrodynamics
    from skmoor.solvers.modes import eigenmodes

    T, L = 1e5, 100.0
    lt = LineType(EA=1e12, mass=10.0, diameter=0.1, weight=0.0, Ca_n=1.0)
    lines = LineSet([_string(lt, T, L)])
    system = System(lines, fairleads="fixed", terms=[line_hydrodynamics(lines)])
    _, K, _ = system.residual(np.zeros(system.n))
    omega = eigenmodes(K, system.M, k=2).omega[0]
    added = lt.Ca_n * lt.rho_water * lt.area
    return Row("taut string with added mass (Ca = 1), 50 el.: omega_1",
               np.pi / L * np.sqrt(T / (lt.mass + added)),
               "taut string: pi / L sqrt(T / (m + Ca rho A))", float(omega), 5e-3, unit="rad/s")


# ------------------------------------------------------------------ the run

# (section, check, part of --quick)
CHECKS = [
    ("Statics", check_catenary_vs_moorpy, True),
    ("Statics", check_fe_statics_vs_irvine, True),
    ("Statics", check_fe_convergence_order, True),
    ("Statics", check_fe_is_its_discrete_chain, True),
    ("Statics", check_paper_draft, True),
    ("Line laws", check_curve_catenary, False),
    ("Line laws", check_viscoelastic_polyester, False),
    ("Line laws", check_slack_and_snap, False),
    ("Sea bed", check_seabed_touchdown, True),
    ("Sea bed", check_orcaflex_chain, True),
    ("Sea bed", check_seabed_friction, True),
    ("Sea bed", check_bed_damping, False),
    ("Natural frequencies", check_taut_string, True),
    ("Natural frequencies", check_sagging_cable, True),
    ("MoorPy", check_moorpy_end_forces, True),
    ("MoorPy", check_moorpy_stiffness, True),
    ("MoorPy", lambda: check_moorpy_stiffness(40), False),
    ("MoorPy", check_moorpy_stiffness_order, False),
    ("MoorPy", check_moorpy_stretchy_line, True),
    ("Dynamics", check_moordyn_driven_line, True),
    ("Dynamics", lambda: check_moordyn_driven_line(40), False),
    ("Dynamics", check_chain_dynamics, True),
    ("Dynamics", check_energy_conservation, False),
    ("Dynamics", check_time_order, True),
    ("Dynamics", check_paper_case_against_moordyn, False),
    ("Hydrodynamics", check_airy_dispersion, True),
    ("Hydrodynamics", check_string_in_current, True),
    ("Hydrodynamics", check_added_mass_frequency, True),
    ("Bending", check_beams_euler_bernoulli, True),
    ("Bending", check_moordyn_beam_decks, True),
    ("Bending", check_lowe_langley_jumper, True),
    ("Bending", check_lazy_wave, False),
    ("Bending", check_lazy_wave_dynamics_orcaflex, False),
    ("Rods", check_rising_rods, True),
    ("Rods", check_pinned_rod_pendulum, False),
    ("Rods", check_floating_spar_rod, False),
    ("Rods", check_pendulum_on_a_free_body, True),
    ("Rods", check_pinned_rods_in_current, True),
    ("Rigid bodies", check_squat_spar_periods, False),
    ("Rigid bodies", check_free_spin, False),
    ("Rigid bodies", check_symmetric_top, False),
    ("Rigid bodies", check_large_roll, False),
    ("Bodies in waves", check_retardation_kernel, True),
    ("Bodies in waves", check_radiation_memory, False),
    ("Bodies in waves", check_box_in_regular_waves, False),
    ("Bodies in waves", check_capytaine_long_waves, False),
    ("MoorDyn's sea input", check_wavekin3_record, True),
    ("MoorDyn's sea input", check_wavekin7_against_moordyn, False),
    ("MoorDyn's sea input", check_sea_decks_in_time, False),
    ("VolturnUS-S", check_volturnus_static, True),
]


def run_checks(quick=False):
    """[(section, Row)] of every check (the quick ones with ``quick``), the checks not run
    here [(check's name, reason)], and the time."""
    rows, not_run = [], []
    started = time.perf_counter()
    for section, check, fast in CHECKS:
        if quick and not fast:
            continue
        try:
            result = check()
        except NotRun as reason:
            not_run.append((check.__name__, str(reason)))
            continue
        rows += [(section, row) for row in (result if isinstance(result, list) else [result])]
    return rows, not_run, time.perf_counter() - started


def environment():
    """Date, versions, machine, commit: the lines at the top of the report."""
    return _cases.environment(["skmoor", "numpy", "scipy", "scikit-fem", "moorpy", "moordyn"])


def _tolerance(row):
    if row.kind == "abs":
        return _number(row.tolerance, row.unit)
    return f"{row.tolerance:.2%}" if row.tolerance >= 1e-4 else f"{row.tolerance:.0e}"


def markdown(rows, seconds, env, quick, not_run=()):
    """The report: a header with the run's facts, then a table per section, then the
    checks not run here [(name, reason)]."""
    counts = {s: sum(row.status == s for _, row in rows) for s in ("pass", "FAIL")}
    out = ["# Validation", "",
           "Generated by `python benchmarks/validate.py" + (" --quick" if quick else "")
           + "`; do not edit by hand. Every number below comes from that run.", "",
           f"- commit: {env['commit']}",
           f"- versions: {env['versions']}", f"- machine: {env['machine']}",
           f"- {len(rows)} checks: {counts['pass']} pass, {counts['FAIL']} fail, "
           f"in {seconds:.0f} s"
           + (" (quick: the slow checks left out)" if quick else ""), "",
           "Error: relative, |skmoor / reference - 1|, where the tolerance is a fraction; "
           "absolute, |skmoor - reference|, where the reference is an order or zero.", ""]
    for section, group in itertools.groupby(rows, key=lambda item: item[0]):
        out += [f"## {section}", "",
                "| check | reference | source | skmoor | error | tolerance | result |",
                "|---|---|---|---|---|---|---|"]
        for _, row in group:
            out.append(f"| {row.check} | {_number(row.reference, row.unit)} | {row.source} | "
                       f"{_number(row.value, row.unit)} | {_error(row)} | {_tolerance(row)} "
                       f"| {row.status} |")
        out.append("")
    if not_run:
        out += ["## Not run here", ""] + [f"- `{name}`: {reason}" for name, reason in not_run]
        out.append("")
    return "\n".join(out)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="leave out the slow checks")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "validation.md")
    args = parser.parse_args(argv)
    rows, not_run, seconds = run_checks(args.quick)
    report = markdown(rows, seconds, environment(), args.quick, not_run)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(report)
    print(report)
    print(f"wrote {args.out}")
    return 1 if any(row.status == "FAIL" for _, row in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
