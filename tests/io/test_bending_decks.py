"""Bending lines from MoorDyn's decks: the simply supported beam (tests/Mooring/
BeamSimplySupported.txt) against Euler-Bernoulli, and the Lowe & Langley (2006) flexible
jumper (tests/Mooring/lowe_and_langley_2006/) against the paper's static end forces.

The decks are read from the local mirror of FloatingArrayDesign/MoorDyn
($SKMOOR_MOORDYN_MIRROR, default /work/.mirror/FloatingArrayDesign+MoorDyn/repo); without
it the tests are skipped.
"""
import sys
from pathlib import Path

import numpy as np
import pytest

import skmoor
from skmoor.io.deck import read_deck
from skmoor.run.equilibrium import equilibrium

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import moordyn_decks as md  # noqa: E402

try:
    MIRROR = md.Mirror(md.mirror_path())
except md.MirrorMissing as err:
    MIRROR, NO_MIRROR = None, str(err)

pytestmark = pytest.mark.skipif(MIRROR is None, reason="no MoorDyn mirror")
JUMPER = "tests/Mooring/lowe_and_langley_2006/"


def deck_file(tmp_path, path):
    out = tmp_path / Path(path).name
    out.write_bytes(MIRROR.read(path))
    return out


def static_state(deck):
    model = skmoor.build(deck)
    eq = equilibrium(model, n_modes=1)
    return model, eq.x, model.system.full_displacement(eq.x)


@pytest.mark.filterwarnings("ignore:point point")  # the deck's beam is 10 m above water
def test_simply_supported_beam_deck(tmp_path):
    """BeamSimplySupported.txt (EI = 1e7 N m2, EA = 1.5e9 N, L = 10 m, 19 segments, both
    ends pinned): the static deflection is Euler-Bernoulli's w x (L^3 - 2 L x^2 + x^3) /
    24 EI reduced by the membrane tension of ends that cannot slide, within 0.1 % of the
    largest; the largest moment w L^2 / 8 - N a within 0.2 %. The membrane tension of a
    half-sine sag a: N = EA a^2 pi^2 / 4 L^2, and it shortens the sag by the factor
    1 / (1 + N L^2 / pi^2 EI) (6 kN and 0.6 % here). The beam hangs 10 m above the water:
    w is its dry weight Mass/m g = 981 N/m (skmoor.sea.surface), as in MoorDyn's own check of
    the deck (beam.cpp); a beam weighed as submerged (487 N/m) sags half as much."""
    model, _, u = static_state(read_deck(deck_file(tmp_path, "tests/Mooring/BeamSimplySupported.txt")))
    lines = model.lines
    assert lines.element == "hermite"
    w, EI, EA, L = lines.lines[0].line_type.mass * 9.80665, 1e7, 1.5e9, 10.0
    assert w == pytest.approx(100.0 * 9.80665, rel=1e-12)
    X = lines.points + u[lines.nodal_dofs]
    x = X[:, 0]
    bending = -w * x * (L**3 - 2 * L * x**2 + x**3) / (24 * EI)
    sag = a0 = np.abs(bending).max()
    for _ in range(50):  # a = a0 / (1 + N(a) L^2 / pi^2 EI), N(a) = EA a^2 pi^2 / 4 L^2
        sag = a0 / (1.0 + EA * sag**2 / (4 * EI))
    membrane = EA * sag**2 * np.pi**2 / (4 * L**2)
    assert 5e3 < membrane < 7e3
    assert np.abs(X[:, 2] - 10.0 - bending * sag / a0).max() < 1e-3 * sag
    assert lines.bending_moment(u).max() == pytest.approx(w * L**2 / 8 - membrane * sag, rel=2e-3)


@pytest.mark.filterwarnings("ignore:point point")
def test_cantilevered_beam_deck_is_clamped_on_its_fixed_rod(tmp_path):
    """BeamCantilevered.txt: the beam's end A on the end B of a Fixed rod (MoorDyn attaches
    it along the rod's axis), its tip on a free massless point. Clamped there, the tip sags
    Euler-Bernoulli's w L^4 / 8 EI and the moment in the root element w (L - h/2)^2 / 2 (at
    its middle), both within 0.5 %, w the dry weight Mass/m g (10 m above the water); a
    pinned end would leave the beam free to swing (no static equilibrium at all)."""
    model, _, u = static_state(read_deck(deck_file(tmp_path, "tests/Mooring/BeamCantilevered.txt")))
    lines = model.lines
    w, EI, L = lines.lines[0].line_type.mass * 9.80665, 1e7, 10.0
    X = lines.points + u[lines.nodal_dofs]
    assert 10.0 - X[-1, 2] == pytest.approx(w * L**4 / (8 * EI), rel=5e-3)
    h = L / lines.lines[0].n_elements
    assert lines.bending_moment(u).max() == pytest.approx(w * (L - h / 2) ** 2 / 2, rel=5e-3)


def test_lowe_langley_jumper_static_end_forces(tmp_path):
    """The flexible jumper (170 m, EI = 120.8 kN m2, 68 segments, anchor (-100, 0, -55),
    top (0, 0, -5)): Lowe & Langley's static top force (11.40, 0, 45.71) kN and bottom
    force (-11.40, 0, 24.04) kN within 0.02 kN (the cable alone, EI = 0, gives 11.47 kN
    horizontally). The deck's WaveKin = 1 (waves through MoorDyn's API) is dropped: it
    does not enter the statics."""
    deck = read_deck(deck_file(tmp_path, JUMPER + "line.txt"))
    assert deck.option("WaveKin") == 1
    del deck.options["WaveKin"]
    model, x, u = static_state(deck)
    top, bottom = (f[0] / 1e3 for f in model.system.reactions(x))  # on the line's ends
    np.testing.assert_allclose(-top, [11.40, 0.0, 45.71], atol=0.02)
    np.testing.assert_allclose([-bottom[0], 0.0, -bottom[2]], [-11.40, 0.0, 24.04], atol=0.02)
    kappa = model.lines.curvature(u)
    assert 0.02 < kappa.max() < 0.05  # 1/m: a bend radius of 20 to 50 m at the sag bend


@pytest.mark.slow
@pytest.mark.parametrize("case", [1, 2, 3])
def test_lowe_langley_jumper_top_tension_under_motion(tmp_path, case):
    """Cases 1 to 3 of Lowe & Langley: the top moved 10 m sin(2 pi t / 27 s) in x, y or z
    (faded in over one period as MoorDyn's test does), drag Cd = 1 and added mass Ca = 1
    from the deck, compiled forms; the top tension over the 80 s after the fade-in against
    the digitised series shipped with the deck, within 1 kN (MoorDyn's own tolerance).
    About a minute per case. In case 3 the top rises 5 m out of the water: weighed as
    submerged there, the jumper's top tension falls 6.2 kN below the series
    (skmoor.sea.surface takes the dry part's buoyancy back)."""
    from skmoor.model.from_deck import deck_network
    from skmoor.model.model import from_network
    from skmoor.run.simulate import simulate

    amplitude, period = 10.0, 27.0

    def motion(t):  # MoorDyn's fade-in: f^3 (6 f^2 - 15 f + 10), f = t / period
        f = min(t / period, 1.0)
        out = np.zeros(3)
        out[case - 1] = f**3 * (6 * f * f - 15 * f + 10) * amplitude * np.sin(2 * np.pi * t / period)
        return out

    deck = read_deck(deck_file(tmp_path, JUMPER + "line.txt"))
    del deck.options["WaveKin"]  # waves through MoorDyn's API: cases 4-6, not run here
    network, settings = deck_network(deck, motion=motion)
    network.form_path = "compiled"
    model = from_network(network, settings=settings)
    results = simulate(model, duration=80.0 + period, dt=0.05, output_interval=0.1,
                       progress=False)
    reference = np.loadtxt(deck_file(tmp_path, JUMPER + f"Case {case}.csv"), delimiter=",")
    top = np.interp(reference[:, 0] + period, results.t, results.fairlead_tension[:, 0]) / 1e3
    assert np.abs(top - reference[:, 1]).max() < 1.0
    assert np.ptp(reference[:, 1]) > 3.0  # the motion moves the tension by more than that


def moordyn_jumper_in_waves(path, wave, duration, dt=0.005):
    """MoorDyn's top tension (N) of the jumper deck at ``path`` under ``wave`` (an
    AiryWave) given through its API (WaveKin = 1) at the mid-step times, as MoorDyn's
    own test drives it: (times, tensions)."""
    moordyn = pytest.importorskip("moordyn")
    system = moordyn.Create(str(path))
    top, line = moordyn.GetPoint(system, 2), moordyn.GetLine(system, 1)
    position = list(moordyn.GetPointPos(top))
    moordyn.Init(system, position, [0.0] * 3)
    moordyn.ExternalWaveKinInit(system)
    n, t, out = moordyn.GetLineN(line), 0.0, []
    while t < duration:
        points = np.array(moordyn.ExternalWaveKinGetCoordinates(system)).reshape(-1, 3)
        velocity, acceleration = wave.kinematics(points, t + 0.5 * dt)
        moordyn.ExternalWaveKinSet(system, velocity.tolist(), acceleration.tolist(), t + 0.5 * dt)
        moordyn.Step(system, position, [0.0] * 3, t, dt)
        t += dt
        out.append((t, np.linalg.norm(moordyn.GetLineNodeForce(line, n))))
    moordyn.Close(system)
    return np.array(out).T


@pytest.mark.slow
@pytest.mark.parametrize("case, heading, phase", [(4, 0.0, 230.0), (5, 45.0, 165.0),
                                                  (6, 90.0, 0.0)])
def test_lowe_langley_jumper_top_tension_in_waves(tmp_path, case, heading, phase):
    """Cases 4 to 6 of Lowe & Langley: the top held, a regular wave of amplitude 5 m and
    period 10 s travelling at 0, 45 and 90 deg to the jumper's plane (phases as MoorDyn's
    test gives them), from t = 0 on the static state; the top tension over 20 to 50 s
    against the digitised series within 1 kN (MoorDyn's own tolerance; MoorDyn itself is
    0.82, 0.97 and 0.46 kN off, skmoor 0.79, 0.98, 0.52), and against MoorDyn run side by
    side with the same wave within 0.25 kN (0.11 kN measured). About 40 s per case."""
    from skmoor.model.from_deck import deck_network
    from skmoor.model.model import from_network
    from skmoor.run.simulate import simulate
    from skmoor.sea.waves import AiryWave, Sea

    path = deck_file(tmp_path, JUMPER + "line.txt")
    deck = read_deck(path)
    del deck.options["WaveKin"]  # the waves come as a Sea here
    wave = AiryWave(10.0, 10.0, deck.depth, heading_deg=heading, phase=np.radians(phase),
                    g=deck.g)
    network, settings = deck_network(deck, sea=Sea(deck.depth, rho=deck.rho, g=deck.g,
                                                   waves=[wave]))
    network.form_path = "compiled"
    model = from_network(network, settings=settings)
    results = simulate(model, duration=50.0, dt=0.05, output_interval=0.05, progress=False)
    reference = np.loadtxt(deck_file(tmp_path, JUMPER + f"Case {case}.csv"), delimiter=",")
    times = reference[:, 0] + 20.0
    top = np.interp(times, results.t, results.fairlead_tension[:, 0]) / 1e3
    assert np.abs(top - reference[:, 1]).max() < 1.0
    assert np.ptp(reference[:, 1]) > 10.0  # the waves move the tension by more than that
    t_md, tension_md = moordyn_jumper_in_waves(path, wave, 50.0)
    assert np.abs(top - np.interp(times, t_md, tension_md) / 1e3).max() < 0.25


@pytest.mark.filterwarnings("ignore:point point")
def test_cantilevered_beam_deck_on_a_turned_coupled_rod(tmp_path):
    """BeamCantilevered.txt with its rod made Coupled and turned 10 deg about y by its
    coupled DOFs (MoorDyn's Rx Ry Rz of the axis): the beam, clamped along the turned
    axis, sags w cos(a) L^4 / 8 EI normal to it (a tangent that does not turn leaves the
    tip L sin(a) off that line); the rod passes the beam's and its own weight, and
    their moment about end A (the beam's centre 15 m out along the axis, the rod's 5 m:
    small sag), to the caller (its coupled_loads)."""
    from skmoor.coupling.rods import coupled_reaction

    text = MIRROR.read("tests/Mooring/BeamCantilevered.txt").decode()
    path = tmp_path / "BeamOnCoupledRod.txt"
    path.write_text(text.replace("cantilever Fixed ", "cantilever Coupled "))
    a = np.radians(10.0)
    model = skmoor.build(path, motion=lambda t: np.array([0.0, 0.0, 0.0, 0.0, a, 0.0]))
    eq = equilibrium(model, n_modes=1)
    lines = model.lines
    u = model.system.full_displacement(eq.x)
    X = lines.points + u[lines.nodal_dofs]
    axis, normal = np.array([np.cos(a), 0.0, -np.sin(a)]), np.array([np.sin(a), 0.0, np.cos(a)])
    B = np.array([-10.0, 0.0, 10.0]) + 10.0 * axis  # the turned rod's end B
    w, EI, L = lines.lines[0].line_type.mass * 9.80665, 1e7, 10.0
    assert (X[-1] - B) @ normal == pytest.approx(-w * np.cos(a) * L**4 / (8 * EI), rel=5e-3)
    force, moment = coupled_reaction(model, eq.x, np.zeros(model.system.n), 0.0, "rod1")
    rod_weight = 100.0 * 10.0 * 9.80665
    np.testing.assert_allclose(force, [0.0, 0.0, -(w * L + rod_weight)], rtol=1e-6, atol=1e-3)
    assert moment[1] == pytest.approx((15.0 * w * L + 5.0 * rod_weight) * np.cos(a), rel=1e-3)
