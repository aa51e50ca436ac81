"""The lazy-wave cable of examples/09_lazy_wave.py (three bending lines, two smooth joints)
heaved 3 m / 12 s at its hang-off in still water without drag (CableDyn's VALIDATION.md
case L3-6 less its drag), started from rest by a C2 ramp as CableDyn's own example
``lozon_gomex80_power_cable_motion.dat`` is, against CableDyn stepped side by side with
the same motion; and the start that made the run diverge: a sinusoid from t = 0 moves the
hang-off at 2 pi A / T from rest, an axial shock v sqrt(EA m) of seven times the tension
(CableDyn, run so, reaches hundreds of kN within 2 s too)."""
import math
import warnings

import numpy as np
import pytest
from test_lazy_wave import cabledyn_deck, load_example

import skmoor
from skmoor.bodies.motion import quintic_ramp
from skmoor.run.simulate import ResolutionWarning

AMPLITUDE, PERIOD, DT, RHO_INF = 3.0, 12.0, 0.05, 0.9  # m, s, s, -
ELEMENTS = 64  # CableDyn's example mesh: 28 / 20 / 16 elements


def heave(t, ramp):
    """(z, dz/dt, d2z/dt2) of the hang-off: A sin(2 pi t / T) faded in over ``ramp`` s by
    the quintic r(t / ramp) (m, m/s, m/s2)."""
    omega = 2 * math.pi / PERIOD
    r, dr, ddr = (value / ramp**k for k, value in enumerate(quintic_ramp(t / ramp)))
    s, c = math.sin(omega * t), math.cos(omega * t)
    return (AMPLITUDE * r * s, AMPLITUDE * (dr * s + r * omega * c),
            AMPLITUDE * (ddr * s + 2 * dr * omega * c - r * omega**2 * s))


DRAG = {"Cd_n": 1.2, "Cd_t": 0.1, "Ca_n": 1.0}  # CableDyn's L3-6 (its example's line types)


def skmoor_heave(ex, ramp, duration, drag=False, site="80m"):
    """Hang-off tension (N) every step of the example's cable at ``site`` heaved from rest
    (with ``drag``: DRAG's Morison coefficients on its line types)."""
    network = ex.lazy_wave(ex.SITES[site], ELEMENTS)
    if drag:
        for line in network.lines:
            for name, value in DRAG.items():
                setattr(line.line_type, name, value)
        network.hydro = True
    network.points[0] = skmoor.Point("hang_off", "coupled", ex.SITES[site].hang_off)
    network.motion = skmoor.fade_in(
        lambda t: np.array([0.0, 0.0, AMPLITUDE * np.sin(2 * np.pi * t / PERIOD)]), ramp)
    model = skmoor.from_network(network)
    model.solver.update(scheme="generalized-alpha", rho_inf=RHO_INF)
    results = skmoor.simulate(model, duration=duration, dt=DT, output_interval=DT,
                              progress=False)
    assert results.meta["stopped"] is None
    return results.anchor_tension[:, 0]  # end A of the top section: the hang-off


def cabledyn_heave(ex, ramp, duration, workdir, drag=False, site="80m"):
    """CableDyn's hang-off tension (N) every step, the hang-off's position, velocity and
    acceleration given at each step's end (generalized-alpha at the same rho_inf)."""
    cabledyn = pytest.importorskip("cabledyn")
    options = (f"9.80665 g\n1025.0 rhoW\n{{depth}} WtrDpth\n1.0e5 kBot\n1.0e4 cBot\n"
               f"{RHO_INF} rhoInf\n{DT} dtM\n{duration} TMax\n")
    coefficients = "{Cd_n} {Cd_t} {Ca_n} 0.0".format(**DRAG) if drag else "0 0 0 0"
    model = cabledyn.CableDyn(str(cabledyn_deck(ex, ELEMENTS, workdir, options, coefficients,
                                                site)))
    try:
        q, v, a = model.get_coupled_motion()
        dofs = model.host_dofs()
        z0 = q[dofs[2]]
        tension = [np.linalg.norm(model.calc_output()[dofs])]
        for k in range(1, int(round(duration / DT)) + 1):
            z, vz, az = heave(k * DT, ramp)
            q[dofs[2]], v[dofs[2]], a[dofs[2]] = z0 + z, vz, az
            model.step(DT, q, v, a)
            tension.append(np.linalg.norm(model.calc_output()[dofs]))
    finally:
        model.close()
    return np.array(tension)


def compare(ours, theirs):
    """(largest |difference| as a share of CableDyn's range, relative differences of the
    largest and of the smallest tension)."""
    history = np.max(np.abs(ours - theirs)) / np.ptp(theirs)
    return (history, abs(ours.max() / theirs.max() - 1), abs(ours.min() / theirs.min() - 1))


def test_lazy_wave_heave_against_cabledyn(monkeypatch, tmp_path):
    """Faded in over 6 s, 12 s of heave (64 elements, dt = 0.05 s; the tension swings
    from 6.8 to 10.7 kN about the static 9.32 kN): every step within 0.2 % of CableDyn's
    range (measured 0.04 %: 1.7 N at most, 0.9 N rms), the largest and the smallest
    tension within 0.05 % (0.01 %). A heave of the wrong amplitude or phase, a missing
    buoyancy (the static tension), a mass off by a tenth, or the driven end's inertia left
    out of the balance (M_fp a_p) or of the hang-off reaction (1.8 %, 73 N at most, 36 N
    rms, before they were in) moves these by more."""
    ex = load_example(monkeypatch, tmp_path, ELEMENTS)
    ours = skmoor_heave(ex, ramp=6.0, duration=12.0)
    theirs = cabledyn_heave(ex, 6.0, 12.0, tmp_path)
    assert np.ptp(theirs) > 3.5e3  # a real dynamic swing, not the static tension
    history, largest, smallest = compare(ours, theirs)
    assert history < 2e-3
    assert largest < 5e-4
    assert smallest < 5e-4


def test_lazy_wave_200m_heave_against_cabledyn(monkeypatch, tmp_path):
    """The Gulf of Maine 200 m cable (64 elements: 31 / 11 / 22) faded in over 6 s, 12 s of
    heave without drag (the tension from 17.8 to 29.5 kN about the static 25.16 kN),
    against CableDyn stepped side by side: every step within 0.3 % of CableDyn's range
    (measured 0.08 %: 9 N at most, 5.5 N rms), the largest and the smallest tension within
    0.05 % (0.02 %). The heave with drag against OrcaFlex is tests/lines/test_lazy_wave_orcaflex.py's;
    a heave off in amplitude or phase, a mass off by a tenth
    (4.8 % of the range at 80 m) or a dropped buoyancy moves these by more."""
    ex = load_example(monkeypatch, tmp_path, ELEMENTS, sites="200m")
    ours = skmoor_heave(ex, ramp=6.0, duration=12.0, site="200m")
    theirs = cabledyn_heave(ex, 6.0, 12.0, tmp_path, site="200m")
    assert np.ptp(theirs) > 1e4  # a real dynamic swing, not the static tension
    history, largest, smallest = compare(ours, theirs)
    assert history < 3e-3
    assert largest < 5e-4
    assert smallest < 5e-4


def test_a_motion_that_starts_with_a_jump_is_noted_with_its_shock(monkeypatch, tmp_path):
    """The sinusoid from t = 0 that diverged: the note gives the hang-off's speed
    2 pi A / T and the shock v sqrt(EA m) of the bare cable (EA = 4.69e8 N, 36.70 kg/m)
    against the static 9.32 kN; the faded-in motion is not noted."""
    ex = load_example(monkeypatch, tmp_path, ELEMENTS)
    network = ex.lazy_wave(ex.SITES["80m"], ELEMENTS)
    network.points[0] = skmoor.Point("hang_off", "coupled", ex.SITES["80m"].hang_off)
    network.motion = lambda t: np.array([0.0, 0.0, AMPLITUDE * np.sin(2 * np.pi * t / PERIOD)])
    model = skmoor.from_network(network)
    speed = 2 * math.pi * AMPLITUDE / PERIOD
    shock = speed * math.sqrt(4.69e8 * 36.70)  # 206 kN
    with pytest.warns(ResolutionWarning, match=rf"{speed:.3g} m/s .* {shock / 1e3:.4g} kN on "
                                               r"its 9\.3\d* kN tension"):
        skmoor.simulate(model, duration=DT, dt=DT, progress=False)
    network.motion = skmoor.fade_in(network.motion, PERIOD)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ResolutionWarning)
        skmoor.simulate(skmoor.from_network(network), duration=DT, dt=DT, progress=False)


def test_fade_in_starts_from_rest_and_keeps_the_motion_after_the_ramp():
    """r = 10 tau^3 - 15 tau^4 + 6 tau^5: zero position, velocity and acceleration at
    t = 0 (central differences of the faded motion), the motion itself after the ramp,
    and a Motion's exact velocity equal to the faded position's derivative."""
    ramp = 4.0
    base = skmoor.Motion(lambda t: np.multiply.outer(np.sin(t), [1.0, 0.0, 2.0]),
                         lambda t: np.multiply.outer(np.cos(t), [1.0, 0.0, 2.0]),
                         vectorized=True)
    faded = skmoor.fade_in(base, ramp)
    h = 1e-3
    position = faded.position
    assert np.abs(position(0.0)).max() == 0.0
    assert np.abs((position(h) - position(-h)) / (2 * h)).max() < 1e-8
    assert np.abs((position(h) - 2 * position(0.0) + position(-h)) / h**2).max() < 1e-5
    times = np.array([0.3, 1.7, 3.9, 4.0, 6.5])
    _, rate = faded.at_times(times)
    numeric = (position(times + 1e-6) - position(times - 1e-6)) / 2e-6
    assert np.abs(rate[:, 0] - numeric).max() < 1e-6
    late = times[times >= ramp]
    assert np.allclose(position(late), base.position(late))
    assert skmoor.fade_in(lambda t: np.array([np.sin(t)]), ramp)(2.0)[0] == pytest.approx(
        0.5 * np.sin(2.0))  # r(1/2) = 1/2
    with pytest.raises(ValueError, match="fade_in ramp"):
        skmoor.fade_in(base, 0.0)


def test_lazy_wave_heave_against_cabledyn_over_two_periods(monkeypatch, tmp_path):
    """CableDyn's own example's motion: the 12 s ramp, then two periods (36 s in all; the
    tension from 7.9 to 11.0 kN): every step within 7 % of CableDyn's 3.1 kN range
    (measured 5.9 %, 21 N rms; 5.6 % and 36 N rms without the driven end's inertia), the
    extremes within 0.1 % (0.01 %, 0.03 %; 0.45 %, 0.60 % without)."""
    ex = load_example(monkeypatch, tmp_path, ELEMENTS)
    ours = skmoor_heave(ex, ramp=12.0, duration=36.0)
    theirs = cabledyn_heave(ex, 12.0, 36.0, tmp_path)
    history, largest, smallest = compare(ours, theirs)
    assert history < 0.07
    assert largest < 1e-3
    assert smallest < 1e-3


def test_lazy_wave_heave_with_drag_against_cabledyn(monkeypatch, tmp_path):
    """CableDyn's case L3-6: its example's motion (12 s ramp, 36 s) with the drag and added
    mass of its example's line types (Cd_n 1.2, Cd_t 0.1, Ca_n 1; the tension from 5.7 to
    13.1 kN): every step within 2 % of CableDyn's range (measured 1.2 %, 26 N rms; 1.8 %
    and 39 N rms without the driven end's inertia), the extremes within 0.2 % (0.01 %,
    0.07 %; 0.09 %, 0.12 % without)."""
    ex = load_example(monkeypatch, tmp_path, ELEMENTS)
    ours = skmoor_heave(ex, ramp=12.0, duration=36.0, drag=True)
    theirs = cabledyn_heave(ex, 12.0, 36.0, tmp_path, drag=True)
    history, largest, smallest = compare(ours, theirs)
    assert history < 0.02
    assert largest < 2e-3
    assert smallest < 2e-3
