"""Polyester lines side by side with MoorDyn v2.

1. MoorDyn's own polyester deck ``tests/Mooring/polyester/simple.txt`` (a taut 1400 m
   polyester line, 70 segments, in 372 m of water), read from the local mirror of
   MoorDyn's repository at run time, its fairlead moved as MoorDyn's test moves it
   (``motion.csv``, piecewise linear in 1 s steps: 4.6 m of surge in the first 100 s,
   most of it in the first 20 s, which loads the line from 1.52 to 2.49 MN). Both codes
   run the deck as written (MoorDyn's test also resets EA and the length while it runs,
   to emulate a load-dependent stiffness: that is the law below). Static tension within
   0.1 %; the history within 3 % of its range while the kinks of the motion ring the
   line's axial modes (first 40 s: lumped and FE lines ring differently, measured 2.5 %),
   RMS 0.5 %, and within 0.2 % of the range after (a stiffness 1 % off would leave 1 %).
2. MoorDyn's viscoelastic polyester (``EA_s|EA_d``, ``BA|BA_D``: a static spring with a
   creep damper BA in series with the dynamic spring EA_d and its damper BA_D) against
   skmoor's :class:`~skmoor.lines.laws.Viscoelastic` read from the same deck (the same creep
   state, integrated: skmoor.lines.creep): a taut 199 m line (10 segments) driven 0.5 m
   sin(2 t) along its chord. With a creep time tau = (BA + BA_D) / (EA_1 + EA_d) = 10 s,
   omega tau = 20: the creep holds the mean stretch (the dynamic stiffness is then within
   0.1 % of EA_d). Static tension (EA_s) within 0.1 %; peak, mean and first harmonic of
   the fairlead tension within 1 % (measured 0.15 %); with the static EA alone the first
   harmonic would be 2.5 times smaller. The same with MoorDyn's load-dependent
   ``EA_s|alphaMBL|beta`` (EA_d = alphaMBL + beta T_1, T_1 the creep spring's tension).
3. MoorDyn's viscoelastic test deck ``visco.txt`` (``EA_s|alphaMBL|beta``, ``BA|BA_D``: a
   1 m rope of one segment held stretched to 2 m, then pulled to 11 m in 200 s): read into
   a :class:`~skmoor.lines.laws.Viscoelastic` law (its water density given twice: the later
   value, with a warning), it runs, warned for its 100 % stretch. Its creep state starts
   as MoorDyn's (the whole stretch in the creep spring, relaxed for the IC stage's 5 s with
   the ends held). The fairlead moved as MoorDyn's test moves it (the strain column of
   MoorDyn's expected ``stress_strain_curve.csv``: its motion file is not in the mirror),
   skmoor's tension against that file's stresses (MoorDyn's test allows 3 %) and against
   MoorDyn run side by side, the fairlead's velocity at each row that of the interval
   ending there (MoorDyn's): over the first 10 s (the ramp) within 0.05 % of both in the
   median (measured 0.023 %), at worst 0.5 % from MoorDyn and 1.5 % from the file (at the
   velocity's jump at 0.01 s: 0.2 % and 0.9 %, the file made with 0.001 s steps); over
   200 s (slow suite) within 0.05 % of MoorDyn in the median, 2 % at worst (1.4 % measured
   at the record's jumps at 20 s, 40 s, ..., where the two time schemes differ most), and
   3 % of the file (MoorDyn's own test's bound).
"""
import sys
from pathlib import Path

import numpy as np
import pytest

moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) is the "
                              "lumped-mass dynamic peer")

from peers import faded_sine  # noqa: E402

import skmoor  # noqa: E402
from skmoor import laws  # noqa: E402
from skmoor.bodies.motion import Motion

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import moordyn_decks as md_decks  # noqa: E402

try:
    MIRROR = md_decks.Mirror(md_decks.mirror_path())
    NO_MIRROR = ""
except md_decks.MirrorMissing as err:
    MIRROR, NO_MIRROR = None, str(err)

POLYESTER = "tests/Mooring/polyester"


def mirror_file(name, folder):
    if MIRROR is None:
        pytest.skip(NO_MIRROR)
    path = folder / Path(name).name
    path.write_bytes(MIRROR.read(f"{POLYESTER}/{name}"))
    return path


def run_moordyn(deck, fairlead, displacement, velocity, duration, dt):
    """MoorDyn's fairlead tension history (N) on the coupled point 2."""
    md = moordyn.Create(str(deck))
    try:
        assert moordyn.Init(md, list(fairlead), [0.0, 0.0, 0.0]) == 0
        t = [0.0]
        T = [float(np.linalg.norm(moordyn.GetPointForce(moordyn.GetPoint(md, 2))))]
        for k in range(int(round(duration / dt))):
            tk = k * dt
            force = moordyn.Step(md, list(fairlead + displacement(tk + dt)),
                                 list(velocity(tk + dt)), tk, dt)
            t.append(tk + dt)
            T.append(float(np.linalg.norm(force)))
    finally:
        moordyn.Close(md)
    return np.array(t), np.array(T)


def run_skmoor(deck, displacement, duration, dt):
    model = skmoor.build(deck, motion=displacement)
    results = skmoor.simulate(model, duration=duration, dt=dt, output_interval=dt,
                              progress=False)
    assert results.meta["stopped"] is None
    return model, results.t, results.fairlead_tension[:, 0]


# ------------------------------------------------------------ 1. simple.txt

def test_moordyn_polyester_deck_in_slow_surge(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    deck = mirror_file("simple.txt", tmp_path)
    table = np.loadtxt(mirror_file("motion.csv", tmp_path), delimiter=",", skiprows=1)
    duration = 100.0
    t_tab, x_tab = table[:, 0], table[:, 1] - table[0, 1]
    fairlead = np.array([1360.0, 0.0, -18.0])

    def displacement(t):
        return np.array([np.interp(t, t_tab, x_tab), 0.0, 0.0])

    def velocity(t):
        k = min(max(np.searchsorted(t_tab, t) - 1, 0), len(t_tab) - 2)
        return np.array([(x_tab[k + 1] - x_tab[k]) / (t_tab[k + 1] - t_tab[k]), 0.0, 0.0])

    model, t_sk, T_sk = run_skmoor(deck, displacement, duration, 0.1)
    assert isinstance(model.lines.laws[0], laws.Engineering)
    t_md, T_md = run_moordyn(deck, fairlead, displacement, velocity, duration, 0.1)
    span = T_md.max() - T_md.min()
    assert span > 9e5  # the surge loads the line (1.52 -> 2.49 MN)
    assert T_sk[0] == pytest.approx(T_md[0], rel=1e-3)
    difference = np.abs(T_sk - np.interp(t_sk, t_md, T_md))
    assert difference.max() < 0.03 * span
    assert np.sqrt(np.mean(difference**2)) < 0.005 * span
    assert difference[t_sk > 40.0].max() < 2e-3 * span


# ------------------------------------------------------------ 2. EA_s|EA_d

EA_S, EA_D = 1e8, 3e8  # N
EA_1 = EA_D * EA_S / (EA_D - EA_S)  # MoorDyn's static spring, in series with EA_d
TAU = 10.0  # s, the creep time
AMPLITUDE, OMEGA = 0.5, 2.0  # m, rad/s
PERIOD = 2 * np.pi / OMEGA
FAIRLEAD = np.array([180.0, 0.0, -10.0])
CHORD = (FAIRLEAD - [0.0, 0.0, -100.0]) / np.linalg.norm(FAIRLEAD - [0.0, 0.0, -100.0])


# MoorDyn's load-dependent dynamic stiffness EA_d = alphaMBL + beta T_mean, here about
# EA_D at the line's static tension (1.137 MN)
ALPHA_MBL, BETA = 2.0e8, 88.0


def visco_deck(path, EA_column):
    num = lambda v: repr(float(v))  # noqa: E731
    BA_D = 1e-4 * EA_D
    BA = TAU * (EA_1 + EA_D) - BA_D
    path.write_text(f"""taut polyester line, MoorDyn's viscoelastic EA_s|EA_d
---------------------- LINE TYPES ----------------------------------
TypeName  Diam  Mass/m  EA  BA/-zeta  EI  Cd  Ca  CdAx  CaAx
(name)  (m)  (kg/m)  (N)  (N-s/-)  (N-m^2)  (-)  (-)  (-)  (-)
poly  0.217  52.0  {EA_column}  {num(BA)}|{num(BA_D)}  0  1.6  1.0  0.008  0
---------------------- POINTS --------------------------------------
ID  Attachment  X  Y  Z  Mass  Volume  CdA  Ca
(#)  (word)  (m)  (m)  (m)  (kg)  (m^3)  (m^2)  (-)
1  Fixed  0.0  0.0  -100.0  0  0  0  0
2  Coupled  {num(FAIRLEAD[0])}  0.0  {num(FAIRLEAD[2])}  0  0  0  0
---------------------- LINES ---------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)  (#)  (#)  (m)  (-)  (-)
1  poly  1  2  199.0  10  -
---------------------- OPTIONS -------------------------------------
0  writeLog
1e-3  dtM
9.81  g
1025.0  rho
100.0  WtrDpth
0  kBot
{num(15 * TAU)}  TmaxIC
1e-12  threshIC
1  disableOutput
1  disableOutTime
---------------------- END -----------------------------------------
""")
    return path


def chord_motion():
    return faded_sine(AMPLITUDE, OMEGA, PERIOD, CHORD)


def measures(t, T, duration):
    window = t >= duration - 3 * PERIOD - 1e-9
    t, T = t[window], T[window]
    span = t[-1] - t[0]
    return T.max(), np.trapezoid(T, t) / span, abs(2 * np.trapezoid(
        T * np.exp(-1j * OMEGA * t), t) / span)


@pytest.mark.parametrize("EA_column", [f"{EA_S!r}|{EA_D!r}", f"{EA_S!r}|{ALPHA_MBL!r}|{BETA!r}"],
                         ids=["EA_s|EA_d", "EA_s|alphaMBL|beta"])
def test_viscoelastic_polyester_against_moordyn(tmp_path, monkeypatch, EA_column):
    monkeypatch.chdir(tmp_path)
    deck = visco_deck(tmp_path / "visco.dat", EA_column)
    lt = skmoor.read_deck(deck).line_types["poly"]
    assert lt.EA_visco == tuple(float(v) for v in EA_column.split("|")[1:])
    assert lt.BA_dynamic == pytest.approx(1e-4 * EA_D)
    displacement, velocity = chord_motion()
    duration = 6 * PERIOD
    model, t_sk, T_sk = run_skmoor(deck, displacement, duration, 0.01)
    law = model.lines.laws[0]
    assert isinstance(law, laws.StaticDynamic)
    assert law.dynamic_EA(T_sk[0]) == pytest.approx(EA_D, rel=0.02)
    t_md, T_md = run_moordyn(deck, FAIRLEAD, displacement, velocity, duration, 0.01)
    assert T_sk[0] == pytest.approx(T_md[0], rel=1e-3)
    sk, md = measures(t_sk, T_sk, duration), measures(t_md, T_md, duration)
    for name, a, b in zip(("peak", "mean", "first harmonic"), sk, md):
        assert a == pytest.approx(b, rel=0.01), f"{name}: skmoor {a:.6g} N, MoorDyn {b:.6g} N"


# ------------------------------------------------------------ 3. visco.txt

AREA = np.pi * 0.1438**2 / 4  # m2, visco.txt's rope, as MoorDyn's test takes the stress


def mirror_visco_deck(tmp_path):
    """visco.txt from the mirror, its repeated water density (WtrDnsty) left out."""
    deck = mirror_file("visco.txt", tmp_path)
    text = deck.read_text(encoding="utf-8", errors="replace").splitlines()
    deck.write_text("\n".join(line for line in text if "WtrDnsty" not in line) + "\n")
    return deck


def test_moordyn_visco_deck_is_read(tmp_path):
    """visco.txt gives the water density twice (rho 1025 on line 26, then WtrDnsty 0):
    read as MoorDyn reads it, the later value used, with a warning naming both lines;
    its line type reads into the Viscoelastic law, the line (stretched to twice its
    length) warned about, its creep state relaxed for the IC stage's first check."""
    deck = mirror_file("visco.txt", tmp_path)
    with pytest.warns(UserWarning, match=r"^visco.txt line 27: OPTIONS WtrDnsty: given "
                      r"twice \(line 26: 1025, and here: 0.0\); the later value is used"):
        assert skmoor.read_deck(deck).rho == 0.0
    deck = mirror_visco_deck(tmp_path)
    lt = skmoor.read_deck(deck).line_types["rope"]
    assert lt.EA == 1.424e8 and lt.EA_visco == (1.586e8, 0.4)
    assert lt.BA == 4e9 and lt.BA_dynamic == 11e6
    model = skmoor.build(deck)
    law = model.lines.laws[0]
    assert isinstance(law, laws.Viscoelastic) and law.relax == 5.0  # min(dtIC, TmaxIC)
    assert law.creep_damping == 4e9 and law.dynamic_damping == 11e6
    assert law.dynamic_EA(1e6) == pytest.approx(1.586e8 + 0.4e6)
    assert any("line line1: its ends are 2 m apart, 100.0 % more than its length 1 m" in n
               for n in model.notes)


def visco_both(tmp_path, duration):
    """(t, skmoor's, MoorDyn's and MoorDyn's expected tension N) of visco.txt driven by
    the strain record of MoorDyn's expected stress_strain_curve.csv (0.01 s rows)."""
    deck = mirror_visco_deck(tmp_path)
    expected = np.loadtxt(mirror_file("viscoelastic/stress_strain_curve.csv", tmp_path),
                          delimiter=",", skiprows=1)
    n = int(round(duration / 0.01))
    t_tab, x_tab = expected[: n + 1, 0], 1.0 + expected[: n + 1, 1]  # l0 = 1 m from x = 0

    def displacement(t):
        return np.array([np.interp(t, t_tab, x_tab) - x_tab[0], 0.0, 0.0])

    def velocity(t):  # at a row, the rate of the interval ending there (MoorDyn's then)
        k = min(max(np.searchsorted(t_tab, t - 1e-9), 1), n)
        return np.array([(x_tab[k] - x_tab[k - 1]) / (t_tab[k] - t_tab[k - 1]), 0.0, 0.0])

    model = skmoor.build(deck, motion=Motion(displacement, velocity))
    results = skmoor.simulate(model, duration=duration, dt=0.01, output_interval=0.01,
                              progress=False)
    assert results.meta["stopped"] is None
    md = moordyn.Create(str(deck))
    try:
        assert moordyn.Init(md, [x_tab[0], 0.0, 0.0], [0.0, 0.0, 0.0]) == 0
        line = moordyn.GetLine(md, 1)
        T_md = [np.linalg.norm(moordyn.GetLineNodeTen(line, 1))]
        for k in range(n):  # as MoorDyn's test: the start of each interval and its velocity
            rate = (x_tab[k + 1] - x_tab[k]) / (t_tab[k + 1] - t_tab[k])
            moordyn.Step(md, [x_tab[k], 0.0, 0.0], [rate, 0.0, 0.0], t_tab[k],
                         t_tab[k + 1] - t_tab[k])
            T_md.append(np.linalg.norm(moordyn.GetLineNodeTen(line, 1)))
    finally:
        moordyn.Close(md)
    return (results.t, results.fairlead_tension[:, 0], np.array(T_md),
            expected[: n + 1, 2] * AREA)


def test_moordyn_visco_deck_against_moordyn(tmp_path, monkeypatch, capfd):
    monkeypatch.chdir(tmp_path)
    t, T_sk, T_md, T_expected = visco_both(tmp_path, 10.0)
    capfd.readouterr()
    assert T_expected[0] == pytest.approx(70.69e6, rel=1e-3)  # 5 s of creep from z = e
    assert T_expected[-1] > 3 * T_expected[0]  # the pull loads the rope (to 221 MN)
    # the velocity's jump at 0.01 s: 0.2 % from MoorDyn there, 0.9 % from the file (made
    # with the motion in 0.001 s steps)
    for other, worst in ((T_md, 5e-3), (T_expected, 0.015)):
        difference = np.abs(T_sk / other - 1)
        assert difference.max() < worst and np.median(difference) < 5e-4


@pytest.mark.slow
def test_moordyn_visco_deck_whole_record(tmp_path, monkeypatch, capfd):
    monkeypatch.chdir(tmp_path)
    t, T_sk, T_md, T_expected = visco_both(tmp_path, 199.9)  # the file's last rows
    capfd.readouterr()
    difference = np.abs(T_sk / T_md - 1)
    assert difference.max() < 0.02 and np.median(difference) < 5e-4  # 1.4 % at a jump
    assert np.abs(T_sk / T_expected - 1).max() < 0.03  # MoorDyn's own test's bound
