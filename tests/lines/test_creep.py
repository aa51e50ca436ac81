"""The creep state of viscoelastic ropes (skmoor.lines.creep, laws.Viscoelastic) against the
standard linear solid's closed forms.

MoorDyn's viscoelastic element is a creep element (spring EA_1, damper BA) in series with
the dynamic one (EA_d, BA_D), EA_1 = EA_d EA_s / (EA_d - EA_s). Written out here:

1. Held at a strain e from MoorDyn's start (the whole stretch in the creep spring, z = e:
   a deck with TmaxIC = 0), the creep strain relaxes as z_inf + (e - z_inf) exp(-t / tau),
   tau = (BA + BA_D) / (EA_1 + EA_d), z_inf = EA_d e / (EA_1 + EA_d), and the tension is
   EA_s e + (e - z_inf) (EA_1 - BA / tau) exp(-t / tau): skmoor's history within 1e-4 of
   the step (the trapezoidal rule at dt = tau / 100). The same deck with dtIC = tau (MoorDyn's
   IC stage relaxing the held line for tau) starts at the closed form's t = tau.
2. Stretched harmonically, A (1 - cos(omega t)) at omega tau = 1 on a two-segment line (a free
   node: the term's assembly and tangent in the Newton step), the tension's first harmonic
   is A / L |E*| with the phase arg E*, 1 / E* = 1 / (EA_1 + i omega BA) + 1 / (EA_d + i omega
   BA_D): within 0.1 % and 1e-3 rad (measured 2e-5 at dt = tau / 50; the static stiffness
   alone would be 2.2 times smaller, the dynamic one 37 % larger, neither with a lag).
3. The load-dependent stiffness (``EA_s|alphaMBL|beta``): MoorDyn's closed form of EA_d
   satisfies its defining relation EA_d = alphaMBL + beta EA_1 z; the term's tangent passes
   the Taylor test within a step.
4. The compiled step runs the term and advances its state as the Python step does: the
   same motion, end forces, Newton iterations and creep states, step by step.
5. A creep law on a bending line stops the build, naming the line.
"""
import numpy as np
import pytest

import skmoor
from skmoor import laws
from skmoor.fem.terms import check_tangent
from skmoor.lines import creep
from skmoor.solvers import compiled_step
from skmoor.solvers.dynamics import integrate

EA_S, EA_D = 1.0e8, 3.0e8  # N
EA_1 = EA_D * EA_S / (EA_D - EA_S)
BA, BA_D = 4.4e8, 1.0e7  # N s
TAU = (BA + BA_D) / (EA_1 + EA_D)  # 1 s
LENGTH, SPAN = 10.0, 10.1  # m: a 1 % strain


def deck(path, segments=1, options="0 TmaxIC\n", EA=f"{EA_S!r}|{EA_D!r}"):
    """A taut weightless line from a fixed point to a coupled one, MoorDyn v2 deck."""
    path.write_text(f"""a viscoelastic rope, held or stretched
---- LINE TYPES ----
Name Diam Mass/m EA BA EI Cd Ca CdAx CaAx
(-) (m) (kg/m) (N) (N-s) (N-m^2) (-) (-) (-) (-)
rope 0.1 1.0 {EA} {BA!r}|{BA_D!r} 0 0 0 0 0
---- POINTS ----
ID Attachment X Y Z M V CdA CA
(-) (-) (m) (m) (m) (kg) (m^3) (m^2) (-)
1 Fixed 0 0 -10 0 0 0 0
2 Coupled {SPAN!r} 0 -10 0 0 0 0
---- LINES ----
ID LineType AttachA AttachB UnstrLen NumSegs Outputs
(-) (-) (-) (-) (m) (-) (-)
1 rope 1 2 {LENGTH!r} {segments} -
---- OPTIONS ----
0 g
1025 rho
100 WtrDpth
{options}----------------
""")
    return path


def relaxation(t, e):
    """Tension (N) of the held element from z = e (the closed form above)."""
    z_inf = EA_D * e / (EA_1 + EA_D)
    return EA_S * e + (e - z_inf) * (EA_1 - BA / TAU) * np.exp(-t / TAU)


def test_held_rope_relaxes_as_the_standard_linear_solid(tmp_path):
    e = SPAN / LENGTH - 1.0
    model = skmoor.build(deck(tmp_path / "held.dat"))
    assert isinstance(model.lines.laws[0], laws.Viscoelastic)
    assert model.lines.laws[0].relax == 0.0  # TmaxIC = 0: MoorDyn's z = e as it starts
    results = skmoor.simulate(model, duration=3 * TAU, dt=TAU / 100, output_interval=TAU / 100,
                              progress=False)
    T = results.fairlead_tension[:, 0]
    step = relaxation(0.0, e) - EA_S * e
    assert abs(step) > 0.5 * EA_S * e  # the creep moves the tension
    assert np.abs(T - relaxation(results.t, e)).max() < 1e-4 * abs(step)
    # the recorded element tension is the creep element's, not the static mean's
    assert np.abs(results.tension[:, 0] - relaxation(results.t, e)).max() < 1e-4 * abs(step)
    # MoorDyn's IC stage holding the line for dtIC = tau before t = 0
    model = skmoor.build(deck(tmp_path / "relaxed.dat", options=f"{TAU!r} dtIC\n10 TmaxIC\n"))
    assert model.lines.laws[0].relax == pytest.approx(TAU)
    T0 = skmoor.simulate(model, duration=0.01, dt=0.01, output_interval=0.01,
                         progress=False).fairlead_tension[0, 0]
    assert T0 == pytest.approx(relaxation(TAU, e), rel=1e-5)


def test_harmonic_stretch_sees_the_complex_modulus(tmp_path):
    amplitude, omega = 0.01, 1.0 / TAU  # m, rad/s
    model = skmoor.build(deck(tmp_path / "sine.dat", segments=2, options=""),
                         motion=lambda t: np.array([amplitude * (1 - np.cos(omega * t)), 0.0, 0.0]))
    assert model.lines.laws[0].relax is None  # a free node: MoorDyn's IC settles the creep
    dt = 0.02 * TAU
    duration = 10 * TAU + 2 * np.pi / omega
    results = skmoor.simulate(model, duration=duration, dt=dt, output_interval=dt,
                              progress=False)
    assert results.meta["stopped"] is None
    t, T = results.t, results.fairlead_tension[:, 0]
    window = t >= duration - 2 * np.pi / omega - 1e-9
    assert T[0] == pytest.approx(EA_S * (SPAN / LENGTH - 1.0), rel=1e-6)  # relaxed start
    fit = np.c_[np.ones(window.sum()), np.cos(omega * t[window]), np.sin(omega * t[window])]
    _, cosine, sine = np.linalg.lstsq(fit, T[window], rcond=None)[0]
    modulus = 1.0 / (1.0 / (EA_1 + 1j * omega * BA) + 1.0 / (EA_D + 1j * omega * BA_D))
    expected = amplitude / LENGTH * modulus
    measured = -(cosine - 1j * sine)  # T ~ Re(-measured exp(i omega t)): drive -A cos(omega t)
    assert abs(measured) == pytest.approx(abs(expected), rel=1e-3)  # measured 2e-5
    assert np.angle(measured) == pytest.approx(np.angle(expected), abs=1e-3)
    assert np.angle(expected) > 0.3  # the creep's lag is there to see


def test_load_dependent_stiffness_and_the_tangent(tmp_path):
    alpha, beta = 2.0e8, 0.4
    law = laws.Viscoelastic(alpha_MBL=alpha, beta=beta, creep_damping=BA,
                            dynamic_damping=BA_D)
    z = np.array([0.0, 0.003, 0.02, 0.1])
    EA_1z, EA_dz = law.stiffnesses(z, EA_S)
    assert EA_dz == pytest.approx(alpha + beta * EA_1z * z, rel=1e-12)
    assert EA_1z == pytest.approx(EA_dz * EA_S / (EA_dz - EA_S), rel=1e-12)
    model = skmoor.build(deck(tmp_path / "mean.dat", segments=3,
                              EA=f"{EA_S!r}|{alpha!r}|{beta!r}"))
    skmoor.equilibrium(model)
    term = next(t for t in model.system._terms["lines"] if isinstance(t, creep.CreepTerm))
    u0 = np.zeros(model.lines.ndofs)
    term.commit(0.0, u0, u0)
    check = check_tangent(model, term, t=0.05, steps=np.logspace(-1, -4, 7))
    assert check.ok, str(check)


@pytest.mark.parametrize("EA", [f"{EA_S!r}|{EA_D!r}", f"{EA_S!r}|2e8|0.4"])
def test_the_compiled_step_runs_the_creep_as_the_python_step(tmp_path, EA):
    """The harmonic stretch of test 2 on four segments for three tau, both stiffness
    forms: a wrong creep tension shows in the fairlead force (it pulls all segments alike,
    so not in the motion), a wrong tangent in the iterations, a wrong commit in the states."""
    def run(compiled):
        model = skmoor.build(deck(tmp_path / "sine.dat", segments=4, options="", EA=EA),
                             motion=lambda t: np.array([0.01 * (1 - np.cos(t / TAU)), 0, 0]))
        eq = skmoor.equilibrium(model)
        system = model.system
        assert compiled_step.lowered_terms(system)[0] is None
        term = next(t for t in system._terms["lines"] if isinstance(t, creep.CreepTerm))
        states = list(integrate(system, eq.x, np.zeros(system.n), 0.02 * TAU, 3 * TAU,
                                C=eq.C, compiled=compiled, tol=1e-10, report_every=1))
        return (np.array([s.x for s in states]), np.array([s.iterations for s in states]),
                np.array([s.reactions[0][0] for s in states]), term._state.copy())

    x, iterations, force, state = run(True)
    x_py, iterations_py, force_py, state_py = run(False)
    assert np.abs(x - x_py).max() < 1e-9 * np.abs(x_py - x_py[0]).max()
    assert np.array_equal(iterations, iterations_py)
    assert np.abs(force - force_py).max() < 1e-9 * np.abs(force_py).max()
    # the stiffnesses in the state come from differences of strains: 1e-8 of round-off
    assert state == pytest.approx(state_py, rel=1e-8, abs=1e-15, nan_ok=True)
    assert np.ptp(state[1:5]) > 0  # the creep strains moved



def test_a_creep_law_on_a_bending_line_is_refused_by_name(tmp_path):
    """Static-dynamic laws (the creep laws among them) have no bending (Hermite) element:
    the build stops naming the line and what to change, rather than running without
    the creep."""
    path = deck(tmp_path / "bent.dat", segments=2, options="")
    path.write_text(path.read_text().replace(f"{BA!r}|{BA_D!r} 0 ", f"{BA!r}|{BA_D!r} 1000.0 "))
    with pytest.raises(ValueError, match=r"line 'line1'.*static-dynamic.*EI > 0.*EI 0"):
        skmoor.build(path)
