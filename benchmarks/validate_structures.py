"""Checks of benchmarks/validate.py on bending lines, rods and rigid bodies: each returns
rows (benchmarks/_validation.Row); the set-ups are the test suite's (imported from
tests/lines/test_bending.py, test_bending_decks.py, test_rods.py, test_large_rotations.py)."""
from __future__ import annotations

import tempfile
import warnings
from pathlib import Path

import numpy as np
from _validation import NotRun, Row
from scipy.special import ellipk

EULER_BERNOULLI = "Euler-Bernoulli beam"
LOWE_LANGLEY = "Lowe & Langley (2006), static end force (MoorDyn's jumper deck)"
NEWTON_EULER = "free rigid body (Euler's equations): invariants"


def _moordyn_mirror():
    """Stop the check when the MoorDyn mirror (its decks) is not on this machine."""
    import test_bending_decks

    if test_bending_decks.MIRROR is None:
        raise NotRun(test_bending_decks.NO_MIRROR)


# ------------------------------------------------------------------ bending

def check_beams_euler_bernoulli():
    """Hermite beams (L = 10 m, EI = 1e8 N m2, w = 100 N/m, P = 500 N; tests/lines/test_bending.py):
    cantilever tip and simply supported mid-span deflections (8 / 16 elements), pinned-pinned
    and tensioned beam-string first frequencies (16 elements)."""
    from test_bending import (
        EI,
        L,
        NodeLoad,
        P,
        W,
        beam_modes,
        beam_type,
        cantilever,
        straight,
    )

    from skmoor.coupling.system import System
    from skmoor.lines.line import LineSet
    from skmoor.solvers.statics import solve_static

    lines, u = cantilever(8, tip=P)
    tip = -u[lines.nodal_dofs[-1]][2]
    beam = LineSet([straight(16, beam_type())])
    system = System(beam, fairleads="fixed", terms=[NodeLoad(8, [0, 0, -P])])
    middle = -system.full_displacement(solve_static(system).x)[beam.nodal_dofs[8]][2]
    m, modes = beam_modes(16)
    tension = np.pi**2 * EI / L**2  # tension and bending alike
    _, taut = beam_modes(16, tension=tension)
    pinned = (np.pi / L) ** 2 * np.sqrt(EI / m)
    return [Row("cantilever, 8 el.: tip deflection, weight and tip load",
                W * L**4 / (8 * EI) + P * L**3 / (3 * EI),
                EULER_BERNOULLI + ": w L^4 / 8 EI + P L^3 / 3 EI", float(tip), 1e-5, unit="m"),
            Row("simply supported, 16 el.: mid-span deflection, weight and mid load",
                5 * W * L**4 / (384 * EI) + P * L**3 / (48 * EI),
                EULER_BERNOULLI + ": 5 w L^4 / 384 EI + P L^3 / 48 EI", float(middle), 1e-4,
                unit="m"),
            Row("pinned-pinned beam, 16 el.: omega_1", pinned,
                EULER_BERNOULLI + ": (pi / L)^2 sqrt(EI / m)", float(modes.omega[0]), 1e-4,
                unit="rad/s"),
            Row("beam-string, T = pi^2 EI / L^2, 16 el.: omega_1",
                pinned * np.sqrt(1 + tension * L**2 / (np.pi**2 * EI)),
                EULER_BERNOULLI + " with tension: omega_1 sqrt(1 + T L^2 / (pi^2 EI))",
                float(taut.omega[0]), 1e-4, unit="rad/s")]


def check_moordyn_beam_decks():
    """MoorDyn's beam decks (tests/Mooring/BeamSimplySupported.txt, BeamCantilevered.txt:
    EI = 1e7 N m2, EA = 1.5e9 N, L = 10 m, 10 m above the water, so w is the dry weight
    Mass/m g as in MoorDyn's own check): largest moment and tip sag."""
    from test_bending_decks import deck_file, static_state

    from skmoor.io.deck import read_deck

    _moordyn_mirror()
    EI, EA, L = 1e7, 1.5e9, 10.0
    with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the decks' beams are 10 m above the water
        model, _, u = static_state(read_deck(deck_file(Path(tmp), "tests/Mooring/BeamSimplySupported.txt")))
        w = model.lines.lines[0].line_type.mass * 9.80665
        moment = model.lines.bending_moment(u).max()
        model, _, u = static_state(read_deck(deck_file(Path(tmp), "tests/Mooring/BeamCantilevered.txt")))
        lines = model.lines
        w_tip = lines.lines[0].line_type.mass * 9.80665
        sag = 10.0 - (lines.points + u[lines.nodal_dofs])[-1, 2]
    # ends that cannot slide: the half-sine sag a = a0 / (1 + N L^2 / pi^2 EI) carries the
    # membrane tension N = EA a^2 pi^2 / 4 L^2, which takes N a off the moment
    a0 = 5 * w * L**4 / (384 * EI)
    a = a0
    for _ in range(50):
        a = a0 / (1.0 + EA * a**2 / (4 * EI))
    membrane = EA * a**2 * np.pi**2 / (4 * L**2)
    return [Row("MoorDyn's BeamSimplySupported deck: largest bending moment",
                w * L**2 / 8 - membrane * a,
                EULER_BERNOULLI + ": w L^2 / 8 less the membrane tension's N a (ends pinned)",
                float(moment), 5e-3, unit="N m"),
            Row("MoorDyn's BeamCantilevered deck: tip sag", w_tip * L**4 / (8 * EI),
                EULER_BERNOULLI + ": w L^4 / 8 EI", float(sag), 5e-3, unit="m")]


def check_lowe_langley_jumper():
    """The flexible jumper (170 m, EI = 120.8 kN m2, 68 segments) of MoorDyn's
    lowe_and_langley_2006 deck, static: its end forces against the paper's."""
    from test_bending_decks import JUMPER, deck_file, static_state

    from skmoor.io.deck import read_deck

    _moordyn_mirror()
    with tempfile.TemporaryDirectory() as tmp:
        deck = read_deck(deck_file(Path(tmp), JUMPER + "line.txt"))
        del deck.options["WaveKin"]  # waves through MoorDyn's API: no part of the statics
        model, x, _ = static_state(deck)
    top, bottom = (f[0] / 1e3 for f in model.system.reactions(x))  # kN, on the line's ends
    label = "Lowe & Langley jumper, static:"
    return [Row(f"{label} top force, horizontal", 11.40, LOWE_LANGLEY, float(-top[0]), 0.02,
                "abs", "kN"),
            Row(f"{label} top force, vertical", 45.71, LOWE_LANGLEY, float(-top[2]), 0.02, "abs",
                "kN"),
            Row(f"{label} bottom force, vertical", 24.04, LOWE_LANGLEY, float(-bottom[2]), 0.02,
                "abs", "kN")]


# ------------------------------------------------------------------ rods

def check_pinned_rod_pendulum():
    """tests/decks/rods/pinned_pendulum.dat: a 10 m rod (d = 0.2 m, 250 kg/m) pinned at
    its end, swinging 5 deg in water: period over 7.5 s at dt = 0.025 s."""
    from test_rods import RHO, G, build, crossings, point_track, run

    r = run(build("pinned_pendulum.dat"), 7.5, 0.025)
    L, d, mu = 10.0, 0.2, 250.0
    mass, buoyant = mu * L, RHO * np.pi * d**2 / 4 * L
    w0 = np.sqrt((mass - buoyant) * G * L / 2 / (mass * (L**2 / 3 + (d / 2) ** 2 / 4)))
    period = 4 * ellipk(np.sin(np.radians(5) / 2) ** 2) / w0
    half = np.diff(crossings(r.t, point_track(r, "rod1.B")[:, 0]))
    return Row("pinned rod, 5 deg swing: period", period,
               "compound pendulum: 4 K(sin(a/2)) / w0, w0^2 = (m - rho V) g L/2 / I_pin",
               float(np.mean(2 * half)), 3e-4, unit="s")


def check_floating_spar_rod():
    """tests/decks/rods/floating_spar.dat: a free vertical rod (d = 0.5 m, 100 kg/m, 10 m)
    released below its draft: mean draft and heave period over 10 s at dt = 0.02 s."""
    from test_rods import RHO, G, build, crossings, point_track, run

    r = run(build("floating_spar.dat"), 10.0, 0.02)
    z = point_track(r, "rod1.A")[:, 2]
    d, mu, L = 0.5, 100.0, 10.0
    area = np.pi * d**2 / 4
    draft = mu * L / (RHO * area)
    period = 2 * np.pi * np.sqrt((mu * L + RHO * 2 / 3 * np.pi * (d / 2) ** 3) / (RHO * G * area))
    up = crossings(r.t, z + draft)[::2]
    return [Row("floating rod: mean draft", draft, "Archimedes: m L / (rho A)",
                float(-(z.max() + z.min()) / 2), 1e-5, "abs", "m"),
            Row("floating rod: heave period", period,
                "2 pi sqrt((m L + CaEnd rho 2/3 pi r^3) / (rho g A))",
                float(np.mean(np.diff(up))), 3e-4, unit="s")]


def check_rising_rods():
    """tests/decks/rods/rising_rods.dat: two buoyant rods rising from rest, 1.5 s:
    largest departure from z0 + a t^2 / 2, a = (rho V - m) g / (m + m_a)."""
    from test_rods import RHO, G, build, point_track, run

    r = run(build("rising_rods.dat"), 1.5, 0.05)
    d, mu, L = 0.5, 100.0, 2.0
    volume, mass = np.pi * d**2 / 4 * L, mu * L
    rows = []
    for name, label, added in (("rod1.A", "horizontal (m_a = Ca rho V)", RHO * volume),
                               ("rod2.B", "vertical (m_a: two end caps)",
                                2 * RHO * 2 / 3 * np.pi * (d / 2) ** 3)):
        a = (RHO * volume - mass) * G / (mass + added)
        z = point_track(r, name)[:, 2]
        rows.append(Row(f"rising rod, {label}: largest |z - z(t)|", 0.0,
                        "uniform acceleration (rho V - m) g / (m + m_a)",
                        float(np.max(np.abs(z - (-10.0 + 0.5 * a * r.t**2)))), 1e-9, "abs", "m"))
    return rows


# ------------------------------------------------------------------ rigid bodies

def check_squat_spar_periods():
    """CableDyn's V-SPW squat spar (d = 10 m, draft 20 m, GM 0.41 m), exact rotations,
    released 1 deg in pitch or 1 m in heave, 2.2 periods at 60 steps a period."""
    from test_large_rotations import (
        lone_body_system,
        spar_periods,
        squat_spar,
        zero_up_periods,
    )

    from skmoor.solvers.dynamics import integrate

    body, *numbers = squat_spar("exact")
    periods = spar_periods(*numbers)
    rows = []
    for dof, name, release in ((4, "pitch", np.radians(1.0)), (2, "heave", 1.0)):
        period = periods[dof == 4]
        q0 = np.zeros(6)
        q0[dof] = release
        states = list(integrate(lone_body_system(body), q0, np.zeros(6), period / 60,
                                2.2 * period))
        measured = zero_up_periods(np.array([s.t for s in states]),
                                   np.array([s.x[dof] for s in states]))
        rows.append(Row(f"squat spar, exact rotations: {name} period", float(period),
                        "linear hydrostatics and strip added mass (CableDyn V-SPW: 20.535 s "
                        "pitch)", float(measured), 5e-3, unit="s"))
    return rows


def check_free_spin():
    """A free asymmetric body (I = diag(3, 1, 1.2) kg m2) spun near its intermediate axis
    for two periods at 80 and 160 steps a period: angular momentum and the energy's order."""
    from test_large_rotations import ASYMMETRIC, free_spin, invariant_errors

    omega0 = [0.0, 0.05, 1.0]
    period = 2 * np.pi / np.linalg.norm(omega0)
    errors = [invariant_errors(*free_spin(ASYMMETRIC, omega0, period / steps, 2 * period))
              for steps in (80, 160)]
    (e1, h1), (e2, h2) = errors
    return [Row("free spin, intermediate axis, 160 steps a period: angular momentum error",
                0.0, NEWTON_EULER + " (momentum conserved)", float(max(h1, h2)), 1e-7, "abs"),
            Row("free spin, intermediate axis: observed order of the energy error", 2.0,
                NEWTON_EULER + " (energy), dt^2 of the step", float(np.log2(e1 / e2)), 0.35,
                "abs")]


def check_symmetric_top():
    """A free symmetric top (I_perp = 2, I_axis = 1 kg m2, omega0 = (0.1, 0, 2) rad/s),
    10 s at 0.04 s: the rate its axis circles the angular momentum H."""
    from test_large_rotations import free_spin

    from skmoor.bodies.body import rotation_matrix

    inertia, omega0 = np.diag([2.0, 2.0, 1.0]), np.array([0.1, 0.0, 2.0])
    _, states = free_spin(inertia, omega0, 0.04, 10.0)
    h = inertia @ omega0 / np.linalg.norm(inertia @ omega0)
    u = np.cross(h, [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    w = np.cross(h, u)
    axis = np.array([rotation_matrix(s.x[3:]) @ [0.0, 0.0, 1.0] for s in states])
    rate = np.polyfit([s.t for s in states], np.unwrap(np.arctan2(axis @ w, axis @ u)), 1)[0]
    return Row("free symmetric top: precession rate", float(np.linalg.norm(inertia @ omega0) / 2.0),
               "free symmetric top: |H| / I_perp", float(rate), 1e-3, unit="rad/s")


def check_large_roll():
    """A box (20 x 10 x 8 m, draft 3 m, small GM) released at 30 deg roll, exact
    rotations, 12 s at 0.05 s, against scipy's solve_ivp of its clipped 2D section."""
    from test_large_rotations import (
        DRAFT,
        HEIGHT,
        LENGTH,
        RHO,
        WIDTH,
        G,
        lone_body_system,
        roll_reference,
    )

    from skmoor.bodies.body import RigidBody
    from skmoor.solvers.dynamics import integrate

    roll0 = np.radians(30.0)
    mass, reference = roll_reference(roll0, 12.0)
    body = RigidBody.box(LENGTH, WIDTH, HEIGHT, mass, DRAFT, rho=RHO, g=G, rotations="exact")
    q0 = np.zeros(6)
    q0[3] = roll0
    states = list(integrate(lone_body_system(body), q0, np.zeros(6), 0.05, 12.0))
    t = np.array([s.t for s in states])
    roll = np.array([s.x[3] for s in states])
    return Row("box released at 30 deg roll, 12 s: largest roll difference / 30 deg", 0.0,
               "solve_ivp of heave and roll with the waterline-clipped section",
               float(np.abs(roll - reference.sol(t)[1]).max() / roll0), 1e-2, "abs")


LOZON = "OrcaFlex 11.6d (Lozon et al. 2025; CableDyn's VALIDATION.md, case L3-5)"


def check_lazy_wave(elements=(("80m", 256), ("200m", 476))):
    """examples/09_lazy_wave.py: the Lozon 80 m and 200 m lazy-wave power cables (three
    bending lines joined smoothly) in their static state: hang-off tension and peak
    curvature against the published OrcaFlex numbers, and those and the touchdown against
    CableDyn run side by side on the same mesh (``elements``: (site, elements) pairs)."""
    import pytest
    from test_lazy_wave import cabledyn_static, load_example

    try:
        import cabledyn
    except ImportError:
        cabledyn = None
    rows = []
    for site, n in elements:
        with tempfile.TemporaryDirectory() as workdir, pytest.MonkeyPatch.context() as patch:
            ex = load_example(patch, Path(workdir), n, sites=site)
            cable, orcaflex = ex.cables[site], ex.SITES[site].orcaflex
            tension, peak = cable.hang_off_tension, float(cable.curvature.max())
            rows += [Row(f"lazy-wave cable ({site[:-1]} m): hang-off tension",
                         orcaflex["hang_off_tension"], LOZON, tension, 1e-3 if site == "80m"
                         else 3e-4, unit="N"),
                     Row(f"lazy-wave cable ({site[:-1]} m): peak curvature",
                         orcaflex["peak_curvature"], LOZON, peak,
                         5e-3 if site == "80m" else 3e-3, unit="1/m")]
            if cabledyn is None:
                continue
            T_cd, kappa_cd, nodes_cd = cabledyn_static(ex, n, Path(workdir), site=site)
        version = f"CableDyn {cabledyn.__version__}" if hasattr(cabledyn, "__version__") \
            else "CableDyn"
        side_by_side = f"{version}, run side by side ({n} elements)"
        rows += [
            Row(f"lazy-wave cable ({site[:-1]} m): hang-off tension", T_cd, side_by_side, tension,
                1e-4 if site == "80m" else 1e-6, unit="N"),
            Row(f"lazy-wave cable ({site[:-1]} m): peak curvature (mid-points vs CableDyn's "
                "nodes)", float(np.max(kappa_cd)), side_by_side, peak,
                5e-3 if site == "80m" else 1e-3, unit="1/m"),
            Row(f"lazy-wave cable ({site[:-1]} m): touchdown, arclength from the hang-off",
                ex.touchdown(nodes_cd, ex.SITES[site].depth)[0], side_by_side,
                cable.touchdown[0], 0.02 if site == "80m" else 0.01, "abs", unit="m")]
    return rows


def check_pendulum_on_a_free_body():
    """tests/decks/rods/pendulum_on_a_free_body.dat: a buoyant rod pinned to a free body
    (skmoor.coupling.joints.BodyPin), 2 deg off the vertical: the swing's period with the
    carrier's recoil."""
    import skmoor

    deck = Path(__file__).parents[1] / "tests" / "decks" / "rods" / "pendulum_on_a_free_body.dat"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = skmoor.simulate(skmoor.build(deck), duration=5.5, dt=0.0125,
                            output_interval=0.0125, start="given", progress=False)
    G, RHO, L, d, mu = 9.80665, 1025.0, 4.0, 0.5, 100.0
    m, lift = mu * L, RHO * np.pi * d ** 2 / 4 * L
    I_A = m * (L ** 2 / 3 + (d / 2) ** 2 / 4)
    I_eff = I_A - m ** 2 * (L / 2) ** 2 / lift  # M + m = the lift: neutrally buoyant
    w = np.sqrt((lift - m) * G * L / 2 / I_eff)

    def track(name):
        i = r.point_names.index(name)
        return r.point_reference[i] + r.point_displacement[:, i]

    x = track("rod1.B")[:, 0] - track("rod1.A")[:, 0]
    k = np.flatnonzero(np.sign(x[:-1]) * np.sign(x[1:]) < 0)
    upright = r.t[k] - x[k] * (r.t[k + 1] - r.t[k]) / (x[k + 1] - x[k])
    return Row("rod pinned to a free body, 2 deg swing: period",
               4 * ellipk(np.sin(np.radians(1.0)) ** 2) / w,
               "pendulum on a free carrier: w^2 = (rho V - m) g L/2 / I_eff, "
               "I_eff = I_A - m^2 (L/2)^2 / (M + m)",
               float(2 * np.mean(np.diff(upright))), 1e-3, unit="s")


def check_pinned_rods_in_current():
    """MoorDyn's RodPinnedFloating.txt (no lines): two buoyant rods pinned at one end,
    given drag, settled in a uniform current (tests/coupling/test_no_lines_moordyn.py)."""
    from test_no_lines_moordyn import MIRROR, NO_MIRROR, pinned_rods_in_current

    if MIRROR is None:
        raise NotRun(NO_MIRROR)
    with tempfile.TemporaryDirectory() as workdir:
        theta, _, _, ends = pinned_rods_in_current(workdir)
    angle = max((np.arctan2(*(B - A)[[0, 2]]) for A, B in ends), key=lambda a: abs(a - theta))
    return Row("pinned rods in a 1.5 m/s current: static angle from the vertical (the worse "
               "rod)", float(theta), "moment balance about the pin: 1/2 rho Cd d (U cos a)^2 "
               "= (rho A - m) g sin a", float(angle), 1e-6, unit="rad")


L3_6 = ("OrcaFlex 11.6d (CableDyn's L3-6 reference values, its "
        "tests/test_l3_lazywave_dynamic.f90)")


def check_lazy_wave_dynamics_orcaflex(elements=(("80m", 128), ("200m", 256)), dt=0.05):
    """The Lozon 80 m and 200 m lazy waves' suspended spans heaved 3 m / 12 s at their
    hang-off in still water, with drag and added mass, scored over the last three periods
    (tests/lines/test_lazy_wave_orcaflex.py; ``elements``: (site, elements) pairs): peak curvature, its
    amplification, hang-off tension mean / min / max against OrcaFlex as CableDyn
    publishes it."""
    from test_lazy_wave_orcaflex import SPANS, heave_protocol

    checks = [("static peak curvature (interior 3-97 % of the arc)", "static_curvature",
               3e-3, "1/m"),
              ("dynamic peak curvature", "dynamic_curvature", 1e-2, "1/m"),
              ("curvature amplification (dynamic / static)", "amplification", 1e-2, ""),
              ("hang-off tension, mean", "tension_mean", 5e-3, "N"),
              ("hang-off tension, smallest", "tension_min", 5e-3, "N"),
              ("hang-off tension, largest", "tension_max", 5e-3, "N")]
    rows = []
    for site, n in elements:
        span = SPANS[site]
        scored = heave_protocol(n, dt, span)
        rows += [Row(f"lazy-wave span ({site[:-1]} m) heaved 3 m / 12 s: {label}",
                     span.orcaflex[key], L3_6, scored[key], tolerance, unit=unit)
                 for label, key, tolerance, unit in checks]
    return rows
