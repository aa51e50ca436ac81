"""Checks of benchmarks/validate.py on bodies in waves, MoorDyn's sea input, the bed's
damping, the paper's coupled case against MoorDyn and the VolturnUS-S mooring: each
returns rows (benchmarks/_validation.Row); the set-ups are the test suite's (imported
from tests/bodies/test_radiation.py, test_bem.py, test_sea_files.py, test_sea_moordyn.py,
test_bed_damping_moordyn.py, test_paper_case_moordyn.py) and benchmarks/volturnus.py's."""
from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
from _cases import inside, quiet
from _validation import MOORDYN, NotRun, Row

CAPYTAINE = "Capytaine (BEM), the paper's box on 0.5-1 m panels (meshes/box_hull_bem.npz)"


# ------------------------------------------------------------------ bodies in waves

def check_retardation_kernel():
    """The retardation kernel of a damping B(omega) shaped as a triangle of height 2 on
    [0, 2.6] rad/s, at t = 0.1, 1, 7.3 and 40 s."""
    from skmoor.bodies.radiation import retardation_kernel

    W, b = 1.3, 2.0
    B = np.zeros((3, 6, 6))
    B[1, 2, 2] = b
    t = np.array([0.1, 1.0, 7.3, 40.0])
    K = retardation_kernel(np.array([0.0, W, 2 * W]), B, t)[:, 2, 2]
    exact = 2 / np.pi * b * (2 * np.cos(W * t) - 1 - np.cos(2 * W * t)) / (W * t**2)
    return Row("retardation kernel of a triangular B(omega): largest error / K(0)", 0.0,
               "cosine transform (2/pi) int B cos(omega t): (2/pi) b (2 cos Wt - 1 - cos 2Wt) "
               "/ (W t^2)", float(np.abs(K - exact).max() / (2 / np.pi * b * W)), 1e-6, "abs")


def check_radiation_memory():
    """The paper's box heaved 0.1 m sin(omega t) past its 60 s memory: the radiation force
    -A_inf zddot - int K zdot ds over one period against -A(omega) zddot - B(omega) zdot."""
    from test_radiation import DATA

    from skmoor.bodies.bem import Hydrodynamics
    from skmoor.bodies.radiation import PotentialFlow

    box, dt, Z, heave = Hydrodynamics.load(DATA), 0.05, 0.1, 2
    e = np.eye(6)[heave]
    rows = []
    for omega in (0.5, 1.0, 2.0):
        term = PotentialFlow(box, memory=60.0)
        A, B = box.coefficients(omega)
        warm, worst = 80.0, 0.0
        for t in np.arange(0.0, warm + 2 * np.pi / omega, dt):
            v, acc = Z * omega * np.cos(omega * t), -Z * omega**2 * np.sin(omega * t)
            if t > warm:
                mu, _ = term.memory(t, v * e)
                force = -term.added_mass_inf[heave, heave] * acc - mu[heave]
                worst = max(worst, abs(force + A[heave, heave] * acc + B[heave, heave] * v))
            term.commit(t, Z * np.sin(omega * t) * e, v * e)
        scale = Z * np.hypot(omega**2 * A[heave, heave], omega * B[heave, heave])
        rows.append(Row(f"box heaved at {omega:g} rad/s: radiation memory force error / "
                        "amplitude", 0.0, CAPYTAINE + ": A(omega), B(omega)",
                        float(worst / scale), 1e-2, "abs"))
    return rows


def check_box_in_regular_waves():
    """The paper's box on its lines in 5 cm head waves at 1.6 rad/s (Cummins' equation in
    the implicit step, 16 periods): surge, heave and pitch amplitudes against the
    frequency-domain response of the same linearized network."""
    from test_radiation import DATA, box_in_waves

    from skmoor.bodies.bem import Hydrodynamics

    with quiet():
        time_domain, frequency_domain, _ = box_in_waves(Hydrodynamics.load(DATA), 1.6,
                                                        periods=16)
    return [Row(f"box in head waves, 1.6 rad/s: {name} amplitude", float(ref),
                "frequency-domain response (-w^2 (M + A) - i w B + C + K) X = F",
                float(value), 2e-2, unit=unit)
            for name, unit, ref, value in zip(("surge", "heave", "pitch"), ("m", "m", "rad"),
                                              frequency_domain, time_domain)]


def check_capytaine_long_waves():
    """Capytaine on the paper's box (2 m panels, 100 m of water) at omega = 0.05 rad/s:
    heave excitation and the surge force of head waves in the long-wave limit."""
    import capytaine as cpt
    from test_bem import CENTRE, DRAFT

    from skmoor import bem
    from skmoor.sea.waves import wavenumber

    rho, g, omega = 1025.0, 9.81, 0.05
    mesh = cpt.mesh_parallelepiped(size=(26.0, 10.0, 5.0), resolution=(13, 5, 3))
    with tempfile.TemporaryDirectory() as cache, quiet():
        hydro = bem.from_mesh(mesh, [omega, 1.0], offset=CENTRE, reference_point=CENTRE,
                              depth=100.0, cache=cache)
    taylor = (rho * 26.0 * 10.0 * DRAFT + hydro.added_mass[0, 0, 0]) * g * wavenumber(omega, 100.0)
    return [Row("box, long waves: heave excitation per m of amplitude", rho * g * 260.0,
                "hydrostatic pressure on the keel: rho g A_wp",
                float(abs(hydro.excitation[0, 0, 2])), 1e-2, unit="N/m"),
            Row("box, long waves: surge excitation per m of amplitude", taylor,
                "G. I. Taylor: (rho V + A11) g k", float(abs(hydro.excitation[0, 0, 0])), 3e-2,
                unit="N/m")]


# ------------------------------------------------------------------ sea input

def check_wavekin3_record():
    """WaveKin 3: an Airy wave's elevation record (8 s, 0.6 m, 64 s at 0.25 s) in a deck's
    folder, read back as the water velocity and acceleration 30 m away, 2-40 m deep."""
    from test_sea_files import GRID, airy, deck_folder, stretched_points

    from skmoor.io.sea_files import deck_sea

    a, period, dt = 0.6, 8.0, 0.25
    omega = 2 * np.pi / period
    times = np.arange(0.0, 64.0 + dt / 2, dt)
    record = "".join(f"{t:.6f} {a * np.cos(omega * t):.15e}\n" for t in times)
    with tempfile.TemporaryDirectory() as tmp:
        sea = deck_sea(deck_folder(Path(tmp), {"WaveKin": 3, "dtWave": dt},
                                   {"wave_elevation.txt": record, "water_grid.txt": GRID}))
    z_grid = np.array([-40.0, -20.0, -5.0, -2.0])
    velocity = acceleration = 0.0
    for t in (0.0, 1.25, 5.5, 70.5):  # 70.5 s: the record repeats every 64 s
        v, acc = sea.kinematics(stretched_points(sea, 30.0, z_grid, t), t)
        _, u, w, du, dw = airy(a, omega, 30.0, z_grid, t % 64.0)
        velocity = max(velocity, np.abs(v[:, [0, 2]] - np.c_[u, w]).max() / (a * omega))
        acceleration = max(acceleration,
                           np.abs(acc[:, [0, 2]] - np.c_[du, dw]).max() / (a * omega**2))
    airy_source = "Airy wave, Wheeler-stretched (closed form)"
    return [Row("WaveKin 3 elevation record: velocity error / a omega", 0.0, airy_source,
                float(velocity), 1e-9, "abs"),
            Row("WaveKin 3 elevation record: acceleration error / a omega^2", 0.0, airy_source,
                float(acceleration), 1e-9, "abs")]


def check_wavekin7_against_moordyn():
    """MoorDyn's tests/Mooring/wavekin_7 deck: water velocity, acceleration and elevation
    at seven points, 0.5-2.9 s, against moordyn.GetWavesKin."""
    from test_sea_moordyn import MIRROR, NO_MIRROR, kinematics_difference

    if MIRROR is None:
        raise NotRun(NO_MIRROR)
    with tempfile.TemporaryDirectory() as tmp, inside(tmp), quiet():
        worst, _ = kinematics_difference("tests/Mooring/wavekin_7/wavekin_7.txt", Path(tmp))
    return Row("MoorDyn's wavekin_7 deck: largest water kinematics difference", 0.0,
               MOORDYN + " (GetWavesKin)", float(worst), 1e-6, "abs", "m/s, m/s2, m")


def check_sea_decks_in_time(names=("WaveKin1", "WaveKin2-Currents5", "SeafloorFile")):
    """MoorDyn's sea decks (waves from a file, current grids, a bathymetry), both codes
    started from still water, 20 s (tests/sea/test_sea_decks_moordyn.py): over 5-20 s, the
    offset of skmoor's end tension from MoorDyn's and the rms difference of what the water
    does to the tension (each code's change from its own static state)."""
    from test_sea_decks_moordyn import MIRROR, NO_MIRROR, run_deck

    if MIRROR is None:
        raise NotRun(NO_MIRROR)
    rows = []
    for name in names:
        with tempfile.TemporaryDirectory() as tmp, inside(tmp), quiet():
            offset, change = run_deck(name, Path(tmp))
        rows += [Row(f"{name} deck, 20 s: end tension offset / MoorDyn's mean", 0.0,
                     MOORDYN, float(offset), 1e-2, "abs"),
                 Row(f"{name} deck: water's change of the tension, rms difference / "
                     "MoorDyn's", 0.0, MOORDYN, float(change), 0.2, "abs")]
    return rows


# ------------------------------------------------------------------ sea bed, VolturnUS-S

def check_bed_damping():
    """tests/decks/seabed/bed_drop.dat: a line's nodes dropping onto MoorDyn's bed (kBot
    3e6 Pa/m, cBot 7.5e3 Pa s/m), 0.3 s: the middle node's penetration / its static one."""
    from test_bed_damping_moordyn import (
        G_STATIC,
        MIDDLE,
        closed_form,
        deck_with,
        faded_oscillator,
        run_moordyn,
        run_skmoor,
    )

    cBot = 7.5e3
    with tempfile.TemporaryDirectory() as tmp, inside(tmp), quiet():
        path = deck_with(tmp, cBot)
        t_md, g_md = run_moordyn(path)
        t, g, onset = run_skmoor(path)
    oscillator = "m g'' + cBot d g' + kBot d g = w (solve_ivp, skmoor's damping fade-in)"
    explained = np.interp(t_md, t, faded_oscillator(t, cBot, onset) - closed_form(t, cBot))
    beyond = np.interp(t_md, t, g[:, MIDDLE]) - g_md[:, MIDDLE] - explained
    return [Row("node dropped on the bed: penetration error / static penetration", 0.0,
                oscillator, float(np.abs(g[:, MIDDLE] - faded_oscillator(t, cBot, onset)).max()
                                  / G_STATIC), 1e-2, "abs"),
            Row("node dropped on the bed: skmoor - MoorDyn beyond the fade-in / static "
                "penetration", 0.0, MOORDYN, float(np.abs(beyond).max() / G_STATIC), 1e-2,
                "abs")]


def check_volturnus_static():
    """benchmarks/volturnus.py's IEA 15 MW VolturnUS-S chain mooring (50 segments a line):
    each fairlead's static tension against the published ones."""
    import volturnus

    import skmoor

    if not volturnus.mirror_path().exists():
        raise NotRun(f"no IEA-15-240-RWT mirror at {volturnus.mirror_path()} "
                     "($SKMOOR_IEA_MIRROR)")
    with tempfile.TemporaryDirectory() as tmp:
        model = skmoor.build(volturnus.write_deck("skmoor", 50, 1e-3, tmp))
    static = skmoor.static_results(model, skmoor.equilibrium(model))
    tensions = np.array([t[0] for t in static.fairlead_tension])
    rows = []
    # the published three span 0.5 %: OrcaFlex's is the lowest
    for code, published, tolerance in (("CableDyn", 2437e3, 5e-3), ("OrcaFlex", 2427e3, 1e-2),
                                       ("MoorDyn", 2439e3, 5e-3)):
        farthest = tensions[np.argmax(np.abs(tensions - published))]
        rows.append(Row("VolturnUS-S, 50 segments: static fairlead tension (the farthest of 3)",
                        published, f"{code}, as published for the IEA-15-240-RWT mooring",
                        float(farthest), tolerance, unit="N"))
    return rows


def check_paper_case_against_moordyn():
    """The paper's box on its four lines (11 segments, F_x = 1e5 sin(1.6 t) N, 20 s; the
    'moordyn-damping' scenario of benchmarks/paper_case.py): MoorDyn's lines with the body
    integrated beside them (tests/run/test_paper_case_moordyn.py). Differences over MoorDyn's
    range: the two discretizations of the line (they halve at 40 segments)."""
    import paper_case
    from test_paper_case_moordyn import (
        DT_SKMOOR,
        DURATION,
        SAMPLE,
        difference,
        run_moordyn,
    )

    import skmoor
    from skmoor.post.results import BODY_DOFS

    with tempfile.TemporaryDirectory() as tmp, inside(tmp), quiet():
        scenario = paper_case.Scenario("moordyn-damping")
        results = skmoor.simulate(scenario.model, duration=DURATION, dt=DT_SKMOOR,
                                  output_interval=SAMPLE, progress=False, eq=scenario.eq)
        t_md, T_md, q_md = run_moordyn(scenario, tmp)
    label = "paper case, 11 segments, 20 s:"
    rows = [Row(f"{label} fairlead tensions, largest difference / MoorDyn's range", 0.0,
                MOORDYN, difference(results.t, results.fairlead_tension, t_md, T_md), 5e-2,
                "abs")]
    for dof, tolerance in (("surge", 0.04), ("heave", 0.08), ("pitch", 0.05)):
        i = BODY_DOFS.index(dof)
        rows.append(Row(f"{label} {dof}, largest difference / MoorDyn's range", 0.0,
                        MOORDYN + " (lines) + the body by velocity Verlet",
                        difference(results.t, results.bodies[:, 0, i], t_md, q_md[:, i]),
                        tolerance, "abs"))
    return rows
