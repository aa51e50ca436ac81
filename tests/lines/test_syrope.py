"""The Syrope polyester model (skmoor.lines.syrope) against its formulas and MoorDyn v2.

1. The working curve of each shape (LINEAR, QUADRATIC, EXP) against its defining formula,
   written out here by hand: exact at the sampled strains, within the linear-interpolation
   bound h^2/8 max|T''| between them, slack below eps_min, on the OWC above T_max; the
   slope is the samples' secant; the motion about a mean T sees alpha_MBL + beta T.
2. MoorDyn's three Syrope decks (``tests/Mooring/syrope/{linear,quadratic,exp}_wc``, one
   1 m segment between a fixed and a coupled point, g = 0), read from the mirror of
   MoorDyn's repository, held where the deck puts the fairlead: both codes start from the
   deck's creep state (SYROPE IC Tmean0, Tmax0; MoorDyn's IC stage holds it 0.01 s) and
   creep onto the working curve at the deck's strain (time constant 70 s on the linear
   deck, longer on the softer curves). skmoor's tension history (skmoor.lines.creep's creep
   state, BA z' = EA_d (e - e_wc(T(z))) + BA_D (e' - z')) is MoorDyn's to 1e-6 over the
   first 60 s (measured 3e-8, 3e-5 at t = 0; the quadratic and exp decks creep by 5 % and
   30 % there);
   after 4000 s MoorDyn's tension is skmoor's static tension (on the curve) to 1e-6 (both
   sample the working curve at 30 strains; the analytic curve differs by up to 5e-4, the
   OWC's first point taken as (0, 0) instead of MoorDyn's first row would move eps_min by
   1.6e-3 of strain). The linear deck's Tmean0 lies on its working curve: no creep.
3. Dynamics of the linear deck as MoorDyn's tests/syrope.cpp drives it: the fairlead
   x = x0 (1 + strain), the strain of the deck plus 4e-4 m^-1 times a JONSWAP wave
   elevation (Hs 5 m, Tp 12 s), 300 s. The rope is stiff with EA_d about the IC's Tmean0;
   its creep state (tau = 72 s) lags the wave by (1 - EA_wc / EA_d) / (omega tau) of its
   tension in quadrature (0.6 % at the spectrum's peak) and lets the mean creep by 0.1 %
   over the run. Fitted means within 1e-5 between the codes (measured 3e-8), stiffness
   within 0.1 % of alpha_MBL + beta Tmean0 and of MoorDyn's (measured 3e-5; the working
   curve's own slope would be 23 % off, EA_Dc alone 6 %), RMS difference 1e-3 of the wave
   tension (measured 4e-5; 0.9 % with the creep state held, skmoor's fast-limit Syrope
   law). A 2 s sine (omega tau = 226) agrees within 0.5 % of its amplitude point by point
   (measured 0.095 %). MoorDyn's Step returns the forces of the last RK2 stage of its last
   sub-step: skmoor's history is read there (at dt = 0.1 s, 0.025 s before the step's end;
   read at the end, the sine would differ by 8 %). syrope.cpp's slow 18 h strain history
   (the mean creeping, rising past Tmax0 onto new working curves) is not run.
"""
import math
import sys
from pathlib import Path

import numpy as np
import pytest

import skmoor
from skmoor.lines import creep, syrope
from skmoor.solvers import compiled_step
from skmoor.solvers.dynamics import integrate

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import moordyn_decks as md_decks  # noqa: E402

try:
    MIRROR = md_decks.Mirror(md_decks.mirror_path())
    NO_MIRROR = ""
except md_decks.MirrorMissing as err:
    MIRROR, NO_MIRROR = None, str(err)

SYROPE = "tests/Mooring/syrope"
DECKS = {"linear_wc": 1.0148657, "quadratic_wc": 1.0150575, "exp_wc": 1.0124577}  # x0, m
T_MAX0, T_MEAN0 = 1.3886e6, 4.339e5  # N, the decks' SYROPE IC
ALPHA, BETA = 1.53e8, 23.12  # N, -: the decks' EA_Dc, EA_D_Lm

# an OWC like the decks' (strain, tension N), first row not at zero as MoorDyn reads it
OWC = (np.array([0.002, 0.01, 0.02, 0.04, 0.06]),
       np.array([1.7e5, 7.4e5, 1.3e6, 2.45e6, 4.39e6]))


def by_hand(e, form, k1, k2, T_max):
    """The working curve's tension (N) at strain e (-), from the formulas: eps_max on the
    OWC's straight piece through T_max, eps_min at the fraction k1 from the OWC's first
    strain (LINEAR with k1 >= 1: k1 is the slope)."""
    e0, T0 = OWC[0][0], OWC[1][0]
    piece = np.searchsorted(OWC[1], T_max) - 1
    slope = (OWC[1][piece + 1] - OWC[1][piece]) / (OWC[0][piece + 1] - OWC[0][piece])
    eps_max = OWC[0][piece] + (T_max - OWC[1][piece]) / slope
    eps_min = eps_max - T_max / k1 if (form == "linear" and k1 >= 1) else e0 + k1 * (eps_max - e0)
    xi = (e - eps_min) / (eps_max - eps_min)
    assert T0 < T_max and 0 <= xi <= 1
    if form == "linear":
        return T_max * xi
    if form == "quadratic":
        return T_max * (k2 * xi**2 + (1 - k2) * xi)
    return T_max * (math.exp(k2 * xi) - 1) / (math.exp(k2) - 1)


CURVES = [("linear", 1.25e8, 0.0), ("linear", 0.3, 0.0), ("quadratic", 0.25, 1.0),
          ("quadratic", 0.4, 0.5), ("exp", 0.2, 1.5)]


@pytest.mark.parametrize("form, k1, k2", CURVES)
def test_working_curve_against_its_formula(form, k1, k2):
    law = syrope.syrope_law(OWC, form, k1, k2, T_MAX0, ALPHA, BETA)
    wc = law.static
    e, _ = wc.table
    assert len(e) == 30 + 2  # 30 samples, then the OWC points above T_max (2.45, 4.39 MN)
    eps_min, eps_max = e[0], e[29]
    samples = e[:30]
    assert wc.tension(samples) == pytest.approx([by_hand(x, form, k1, k2, T_MAX0)
                                                 for x in samples], rel=1e-12, abs=1e-6)
    # between samples: within h^2 / 8 max|T''| of the smooth curve
    h = (eps_max - eps_min) / 29
    shape_curvature = {"linear": 0.0, "quadratic": 2 * k2,  # max |d2(T / T_max) / dxi2|
                       "exp": k2**2 * math.exp(k2) / math.expm1(k2) if k2 else 0.0}[form]
    curvature = shape_curvature * T_MAX0 / (eps_max - eps_min)**2
    middles = 0.5 * (samples[1:] + samples[:-1])
    exact = np.array([by_hand(x, form, k1, k2, T_MAX0) for x in middles])
    assert np.all(np.abs(wc.tension(middles) - exact) <= h**2 / 8 * curvature + 1e-6)
    assert np.allclose(syrope.working_curve_tension(middles, *OWC, form, k1, k2, T_MAX0), exact)
    # tangent: the secant of the samples
    secants = np.diff([by_hand(x, form, k1, k2, T_MAX0) for x in samples]) / np.diff(samples)
    assert wc.slope(middles) == pytest.approx(secants, rel=1e-9)
    # slack below eps_min, on the OWC above T_max
    assert wc.tension(np.array([eps_min - 1e-3, 0.0])) == pytest.approx([0.0, 0.0])
    above = np.array([0.03, 0.05])
    assert wc.tension(above) == pytest.approx(np.interp(above, *OWC), rel=1e-12)
    # statics by tension (the catenary's pieces) invert the curve
    assert wc.static_strain(exact) == pytest.approx(
        np.interp(exact, wc.tension(samples), samples), rel=1e-12)
    # the motion about a mean tension: EA_d = alpha_MBL + beta T_mean
    T_mean = np.array([4e5, 9e5])
    p, _ = law.parameters(1.0, T_mean, wc.static_strain(T_mean))
    assert p["k"] == pytest.approx(ALPHA + BETA * T_mean)
    assert p["T0"] == pytest.approx(T_mean)


def test_linear_slope_form_by_hand():
    """LINEAR with k1 >= 1: a straight line of slope k1 ending at (eps_max, T_max)."""
    wc = syrope.syrope_law(OWC, "linear", 1.25e8, 0.0, T_MAX0, ALPHA, BETA).static
    eps_max = 0.02 + (T_MAX0 - 1.3e6) / ((2.45e6 - 1.3e6) / 0.02)
    e = np.array([eps_max - 0.005, eps_max - 0.001])
    assert wc.tension(e) == pytest.approx(T_MAX0 - 1.25e8 * (eps_max - e), rel=1e-12)


def test_bad_syrope_inputs():
    with pytest.raises(ValueError, match="Tmax0 = 5e\\+06 N is outside"):
        syrope.syrope_law(OWC, "linear", 0.2, 0.0, 5e6, ALPHA, BETA)
    with pytest.raises(ValueError, match="WCType 'cubic'"):
        syrope.syrope_law(OWC, "cubic", 0.2, 0.0, T_MAX0, ALPHA, BETA)
    with pytest.raises(ValueError, match="does not rise"):
        syrope.syrope_law(OWC, "quadratic", 0.2, 2.0, T_MAX0, ALPHA, BETA)


# ------------------------------------------------------------ MoorDyn's decks

def mirror_deck(tmp_path, name):
    if MIRROR is None:
        pytest.skip(NO_MIRROR)
    (tmp_path / name).mkdir()
    for file in ("line.txt", "syrope.dat"):
        (tmp_path / name / file).write_bytes(MIRROR.read(f"{SYROPE}/{name}/{file}"))
    (tmp_path / "owc.dat").write_bytes(MIRROR.read(f"{SYROPE}/owc.dat"))
    return tmp_path / name / "line.txt"


def run_moordyn(deck, x, dt):
    """MoorDyn's tension (N) at the coupled point 2 driven along x (m, at t = k dt) as
    tests/syrope.cpp drives it: each step starts at x[k] with velocity (x[k+1] - x[k]) / dt."""
    moordyn = pytest.importorskip("moordyn")
    md = moordyn.Create(str(deck))
    try:
        y, z = 0.0, -5.0
        assert moordyn.Init(md, [x[0], y, z], [(x[1] - x[0]) / dt, 0.0, 0.0]) == 0
        T = [float(np.linalg.norm(moordyn.GetPointForce(moordyn.GetPoint(md, 2))))]
        for k in range(len(x) - 1):
            force = moordyn.Step(md, [x[k], y, z], [(x[k + 1] - x[k]) / dt, 0.0, 0.0],
                                 k * dt, dt)
            T.append(float(np.linalg.norm(force)))
    finally:
        moordyn.Close(md)
    return np.array(T)


@pytest.mark.parametrize("name", list(DECKS))
def test_syrope_deck_creep_against_moordyn(tmp_path, monkeypatch, capfd, name):
    monkeypatch.chdir(tmp_path)
    deck = mirror_deck(tmp_path, name)
    model = skmoor.build(deck)
    law = model.lines.laws[0]
    assert isinstance(law, syrope.SyropeCreep) and isinstance(law.static, syrope.WorkingCurve)
    assert law.static.T_max == T_MAX0 and law.static.form == name.split("_")[0]
    assert law.T_mean == T_MEAN0 and law.relax == 0.01  # the deck's dtIC
    assert (law.creep_damping, law.dynamic_damping) == (5.0e10, 1.0e5)
    dt, duration = 0.2, 60.0
    T_sk = skmoor.simulate(model, duration=duration, dt=dt, output_interval=dt,
                           progress=False).fairlead_tension[:, 0]
    T_md = run_moordyn(deck, np.full(20001, DECKS[name]), dt)  # 4000 s held
    capfd.readouterr()  # MoorDyn's progress lines
    early = T_md[: len(T_sk)]
    assert T_sk[0] == pytest.approx(early[0], rel=1e-4)  # measured 3e-5: the IC stage
    assert np.abs(T_sk - early)[1:].max() < 1e-6 * early.max()  # measured 3e-8
    T_static = law.static.static_tension(DECKS[name] - 1.0)  # skmoor's statics, on the curve
    assert T_static == pytest.approx(T_md[-1], rel=1e-6)
    assert T_md[-1] == pytest.approx(T_md[-500], rel=1e-6)  # relaxed
    if name == "linear_wc":  # Tmean0 on the working curve: no relaxation
        assert T_static == pytest.approx(T_md[0], rel=1e-4)
        assert T_static == pytest.approx(T_MEAN0, rel=1e-3)
    else:  # MoorDyn starts at Tmean0 off the curve and creeps onto it, skmoor with it
        assert abs(T_md[0] - T_static) > 0.1 * T_static
        assert abs(early[-1] - early[0]) > 0.04 * early[0]  # 5 % and 30 % in 60 s


def jonswap_elevation(t, Hs, Tp, gamma=3.3, n=300, seed=12345):
    """A random-phase JONSWAP surface elevation (m) at times t: n bands over
    [1, 20] / Tz, Tz = Tp / 1.402 (as tests/syrope.cpp builds it)."""
    wp, Tz = 2 * np.pi / Tp, Tp / 1.402
    edges = np.linspace(1.0 / Tz, 20.0 / Tz, n)
    w = 0.5 * (edges[1:] + edges[:-1])
    sigma = np.where(w > wp, 0.09, 0.07)
    S = ((1 - 0.287 * np.log(gamma)) * 5 / 16 * Hs**2 * wp**4 / w**5 * np.exp(-1.25 * (wp / w)**4)
         * gamma ** np.exp(-0.5 * ((w - wp) / (sigma * wp))**2))
    a = np.sqrt(2 * S * (edges[1] - edges[0]))
    phase = np.random.default_rng(seed).uniform(0, 2 * np.pi, len(w))
    return np.cos(np.outer(t, w) + phase) @ a


def run_both(deck, x, dt):
    """(times s, skmoor's and MoorDyn's fairlead tension N there) with the fairlead at x
    (m, at t = k dt). MoorDyn's Step returns the forces of the last RK2 stage of its last
    sub-step, half that sub-step before the step's end: skmoor's history is read there."""
    t = dt * np.arange(len(x))
    model = skmoor.build(deck, motion=lambda time: np.array(
        [np.interp(time, t, x) - DECKS["linear_wc"], 0.0, 0.0]))
    results = skmoor.simulate(model, duration=t[-1], dt=dt, output_interval=dt,
                              progress=False)
    assert results.meta["stopped"] is None
    T_sk = results.fairlead_tension[: len(x), 0]
    t_md = np.r_[0.0, t[1:] - last_substep(dt, float(skmoor.read_deck(deck).option("dtM"))) / 2]
    return t_md, np.interp(t_md, t, T_sk), run_moordyn(deck, x, dt)


def last_substep(dt, dtM):
    """MoorDyn's last sub-step (s) of a coupling step dt: MoorDyn::Step takes dtM from dt
    until nothing is left (0.2 - 4 x 0.05 leaves 1.4e-17 s, 0.1 - 2 x 0.05 nothing)."""
    left, step = dt, 0.0
    while left > 0.0:
        step = min(left, dtM)
        left -= step
    return step


def test_linear_deck_in_waves_against_moordyn(tmp_path, monkeypatch, capfd):
    monkeypatch.chdir(tmp_path)
    deck = mirror_deck(tmp_path, "linear_wc")
    dt = 0.2
    t = np.arange(0.0, 300.0 + dt / 2, dt)
    strain = 4.0e-4 * jonswap_elevation(t, 5.0, 12.0)  # the waves' strain, as syrope.cpp
    t_md, T_sk, T_md = run_both(deck, DECKS["linear_wc"] + strain, dt)
    capfd.readouterr()
    strain = np.interp(t_md, t, strain)
    # both start from the IC's mean Tmean0 on the working curve, stretched by the waves
    # (the start's dampers see the strain rate: the interpolated motion's is one-sided at
    # t = 0, MoorDyn's Init takes the first interval's; measured 1.5e-4)
    assert T_sk[0] == pytest.approx(T_md[0], rel=3e-4)
    fit = np.c_[np.ones_like(t), strain, np.gradient(strain, t_md)]
    (mean_sk, EA_sk, _), (mean_md, EA_md, _) = (np.linalg.lstsq(fit, T, rcond=None)[0]
                                               for T in (T_sk, T_md))
    assert mean_sk == pytest.approx(mean_md, rel=1e-5)  # both creep 0.1 % (measured 3e-8)
    assert mean_sk == pytest.approx(T_MEAN0, rel=2e-3)
    assert EA_sk == pytest.approx(ALPHA + BETA * T_MEAN0, rel=1e-3)
    assert EA_sk == pytest.approx(EA_md, rel=1e-3)  # measured 3e-5
    wave = T_md - T_md.mean()
    assert np.sqrt(np.mean(wave**2)) > 5e4  # the waves load the rope (~ 9e4 N)
    difference = np.sqrt(np.mean((T_sk - T_md)**2)) / np.sqrt(np.mean(wave**2))
    assert difference < 1e-3  # measured 4e-5 (0.9 % with the creep state held)


def test_linear_deck_fast_sine_against_moordyn(tmp_path, monkeypatch, capfd):
    """A 2 s strain sine of 5e-4: omega tau = 226, the creep lag 0.23 / (omega tau) =
    0.1 % of the wave tension: skmoor within 0.5 % of its amplitude, point by point."""
    monkeypatch.chdir(tmp_path)
    deck = mirror_deck(tmp_path, "linear_wc")
    dt = 0.1  # twice the decks' dtM
    t = np.arange(0.0, 20.0 + dt / 2, dt)
    strain = 5e-4 * np.sin(np.pi * t)
    _, T_sk, T_md = run_both(deck, DECKS["linear_wc"] + strain, dt)
    capfd.readouterr()
    wave = 5e-4 * (ALPHA + BETA * T_MEAN0) / np.sqrt(2)  # RMS of the wave tension, N
    assert np.sqrt(np.mean((T_md - T_md.mean())**2)) == pytest.approx(wave, rel=0.02)
    assert np.abs(T_sk - T_md).max() < 0.005 * wave * np.sqrt(2)  # measured 0.095 %


def syrope_deck(folder, ea="SYROPE:syrope.dat|1.53e8|23.12", ic="1  1.3886e6  4.339e5",
                settings="owc.dat OWC\nLINEAR WCType\n1.25e8 k1\n0.0 k2\n"):
    """A one-line Syrope deck in folder with its settings file and the OWC above."""
    (folder / "owc.dat").write_text("OWC\nStrain Tension\n(-) (N)\n"
                                    + "".join(f"{e} {T}\n" for e, T in zip(*OWC)))
    (folder / "syrope.dat").write_text(settings)
    ic_section = ("---- SYROPE IC ----\nLine(s) Tmax0 Tmean0\n(-) (N) (N)\n" + ic + "\n"
                  if ic is not None else "")
    path = folder / "line.txt"
    path.write_text(f"""a Syrope line
---- LINE TYPES ----
Name Diam Mass/m EA BA EI Cd Ca CdAx CaAx
(-) (m) (kg/m) (N) (N-s) (N-m^2) (-) (-) (-) (-)
poly 0.2 40 {ea} 5e10|1e5 0 0 0 0 0
---- POINTS ----
ID Attachment X Y Z M V CdA CA
(-) (-) (m) (m) (m) (kg) (m^3) (m^2) (-)
1 Fixed 0 0 -5 0 0 0 0
2 Coupled 1.015 0 -5 0 0 0 0
---- LINES ----
ID LineType AttachA AttachB UnstrLen NumSegs Outputs
(-) (-) (-) (-) (m) (-) (-)
1 poly 2 1 1.0 1 -
{ic_section}---- OPTIONS ----
0 g
1025 rho
0.05 dtM
70 WtrDpth
----------------
""")
    return path


def test_syrope_deck_reader(tmp_path):
    deck = skmoor.read_deck(syrope_deck(tmp_path))
    t = deck.line_types["poly"]
    assert t.syrope[0] == "syrope.dat" and t.syrope[2:] == ("linear", 1.25e8, 0.0)
    assert t.syrope[1][0] == pytest.approx(OWC[0]) and t.EA_visco == (ALPHA, BETA)
    assert deck.syrope_ic == {1: (T_MAX0, T_MEAN0)}
    law = skmoor.build(deck).lines.laws[0]
    assert isinstance(law, syrope.SyropeCreep) and law.T_mean == T_MEAN0
    with pytest.raises(ValueError, match="line.txt line 5: LINE TYPES poly EA .*Tmax0 = 5e"):
        skmoor.build(syrope_deck(tmp_path, ic="1 5e6 1e5"))
    with pytest.raises(ValueError, match="line.txt line 14: LINES 1: a Syrope line needs its "
                       "Tmax0 in a SYROPE IC section"):
        skmoor.build(syrope_deck(tmp_path, ic=None))
    with pytest.raises(ValueError, match="line.txt line 18: SYROPE IC Line\\(s\\): there is no "
                       "line 2"):
        skmoor.read_deck(syrope_deck(tmp_path, ic="1,2 1.3886e6 4.339e5"))
    with pytest.raises(ValueError, match="Tmean0: must be within \\[0, Tmax0"):
        skmoor.read_deck(syrope_deck(tmp_path, ic="1 1e6 2e6"))
    with pytest.raises(ValueError, match="line 5: LINE TYPES EA: .*: a Syrope EA is "
                       "SYROPE:file\\|EA_Dc\\|EA_D_Lm"):
        skmoor.read_deck(syrope_deck(tmp_path, ea="SYROPE:syrope.dat|1.53e8"))
    with pytest.raises(ValueError, match="Syrope file syrope.dat line 2: WCType 'CUBIC'"):
        skmoor.read_deck(syrope_deck(tmp_path, settings="owc.dat OWC\nCUBIC WCType\n1 k1\n0 k2\n"))
    with pytest.raises(ValueError, match="Syrope file syrope.dat does not give k2"):
        skmoor.read_deck(syrope_deck(tmp_path, settings="owc.dat OWC\nEXP WCType\n0.2 k1\n"))
    with pytest.raises(ValueError, match="writing Syrope line types is not supported"):
        skmoor.write_deck(deck, tmp_path / "out.txt")


def test_the_compiled_step_runs_syrope_as_the_python_step(tmp_path, monkeypatch, capfd):
    """The linear deck stretched 1 % past its strain in 10 s, held for two creep times,
    and let back: its creep tension passes Tmax0 (the commit builds the working curve of
    the new highest tension), then the rope unloads on that curve. The compiled step's
    fairlead force and creep state (the highest tension included) equal the Python
    step's, which evaluates the curves with NumPy (a wrong curve, a highest tension not
    raised or raised from the wrong curve would show in the force after the peak)."""
    monkeypatch.chdir(tmp_path)
    deck = mirror_deck(tmp_path, "linear_wc")

    def stretch(t):
        return 0.01 * np.interp(t, [0.0, 10.0, 150.0, 160.0], [0.0, 1.0, 1.0, 0.3])

    def run(compiled):
        model = skmoor.build(deck, motion=lambda t: np.array([stretch(t), 0.0, 0.0]))
        system = model.system
        assert compiled_step.lowered_terms(system)[0] is None
        eq = skmoor.equilibrium(model)
        term = next(t for t in system._terms["lines"] if isinstance(t, creep.CreepTerm))
        states = list(integrate(system, eq.x, np.zeros(system.n), 0.25, 200.0, C=eq.C,
                                compiled=compiled, tol=1e-10, report_every=1))
        return np.array([np.linalg.norm(s.reactions[0][0]) for s in states]), term._state.copy()

    force, state = run(True)
    force_py, state_py = run(False)
    capfd.readouterr()
    highest = state[-1]  # the one element's highest tension (the state's last part)
    assert highest > 1.005 * T_MAX0, highest  # the creep tension passed Tmax0: new curves
    assert force.max() > 1.2 * T_MAX0, force.max()
    assert np.abs(force - force_py).max() < 1e-9 * force_py.max()
    assert state == pytest.approx(state_py, rel=1e-9, abs=1e-15)
