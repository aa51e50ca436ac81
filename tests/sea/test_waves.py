"""Water kinematics (skmoor.sea.waves) against the dispersion relation and its limits, the
continuity equation, the bed and free-surface boundary conditions, and the JONSWAP
spectrum's definition."""
import numpy as np
import pytest
from scipy.integrate import trapezoid

from skmoor.sea.waves import (
    AiryWave,
    Current,
    JonswapWave,
    Sea,
    jonswap_spectrum,
    wavenumber,
)

G = 9.81


def test_dispersion_relation_to_round_off():
    omega = np.linspace(0.05, 6.0, 200)
    for depth in (1.0, 20.0, 150.0, 3000.0):
        k = wavenumber(omega, depth)
        np.testing.assert_allclose(G * k * np.tanh(k * depth), omega**2, rtol=4e-15)


def test_dispersion_limits():
    omega = 2 * np.pi / 8.0
    # deep water (k h ~ 630): k = omega^2 / g
    assert wavenumber(omega, 1000.0) == pytest.approx(omega**2 / G, rel=1e-14)
    # shallow water (k h ~ 1e-3): k = omega / sqrt(g h) (1 + (k h)^2 / 6 + ...)
    omega = 2 * np.pi / 2000.0
    k = wavenumber(omega, 1.0)
    assert k * 1.0 < 2e-3
    assert k == pytest.approx(omega / np.sqrt(G * 1.0), rel=(k * 1.0) ** 2)


@pytest.fixture
def wave():
    return AiryWave(height=3.0, period=9.0, depth=40.0, heading_deg=30.0, phase=0.4)


def below_surface(n=20, depth=40.0, seed=0):
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(-100, 100, n), rng.uniform(-100, 100, n),
                            rng.uniform(-depth * 0.98, -0.5, n)])


def test_airy_velocity_is_divergence_free(wave):
    x, t, h = below_surface(), 2.3, 1e-3
    div = np.zeros(len(x))
    scale = np.zeros(len(x))
    for i in range(3):
        e = np.zeros(3)
        e[i] = h
        d = (wave.velocity(x + e, t)[:, i] - wave.velocity(x - e, t)[:, i]) / (2 * h)
        div += d
        scale += np.abs(d)
    assert np.max(np.abs(div) / scale) < 1e-7


def test_airy_bed_and_surface_conditions(wave):
    # no flow through the bed: w = 0 at z = -h
    bed = np.column_stack([np.linspace(-50, 50, 11), np.zeros(11), np.full(11, -40.0)])
    for t in (0.0, 1.7, 5.0):
        assert np.max(np.abs(wave.velocity(bed, t)[:, 2])) < 1e-15
    # linear kinematic surface condition: d(eta)/dt = w at z = 0
    surface = bed.copy()
    surface[:, 2] = 0.0
    t, dt = 1.3, 1e-4
    deta = (wave.elevation(surface, t + dt) - wave.elevation(surface, t - dt)) / (2 * dt)
    np.testing.assert_allclose(deta, wave.velocity(surface, t)[:, 2], atol=1e-7)
    # and above the surface the kinematics are those at z = 0
    lifted = surface + [0.0, 0.0, 1.2]
    np.testing.assert_array_equal(wave.velocity(lifted, t), wave.velocity(surface, t))


def test_airy_acceleration_is_the_time_derivative_and_amplitudes(wave):
    x, t, dt = below_surface(), 0.8, 1e-4
    dudt = (wave.velocity(x, t + dt) - wave.velocity(x, t - dt)) / (2 * dt)
    np.testing.assert_allclose(wave.acceleration(x, t), dudt, atol=1e-8)
    # horizontal surface velocity under the crest: (H / 2) omega / tanh(k h), along the heading
    k, omega, a = wave.wavenumber, 2 * np.pi / 9.0, 1.5
    crest = np.array([0.0, 0.0, 0.0])
    t_crest = 0.4 / omega  # phase 0.4 - omega t = 0
    u = wave.velocity(crest, t_crest)
    assert wave.elevation(crest, t_crest) == pytest.approx(a, rel=1e-14)
    assert np.hypot(u[0], u[1]) == pytest.approx(a * omega / np.tanh(k * 40.0), rel=1e-13)
    assert np.degrees(np.arctan2(u[1], u[0])) == pytest.approx(30.0, rel=1e-12)
    assert abs(u[2]) < 1e-14


@pytest.mark.parametrize("gamma", [1.0, 2.0, 3.3, 7.0])
def test_jonswap_spectrum_integrates_to_hs(gamma):
    Hs, Tp = 2.5, 11.0
    f = np.linspace(1e-4, 4.0, 400001)
    m0 = trapezoid(jonswap_spectrum(f, Hs, Tp, gamma), f)
    assert 4 * np.sqrt(m0) == pytest.approx(Hs, rel=2e-6)  # the tail beyond 4 Hz: < 1e-6
    fine = np.linspace(0.5 / Tp, 2 / Tp, 150001)
    peak = fine[np.argmax(jonswap_spectrum(fine, Hs, Tp, gamma))]
    assert peak == pytest.approx(1 / Tp, abs=2 * (fine[1] - fine[0]))


def test_jonswap_with_gamma_one_is_pierson_moskowitz():
    Hs, Tp = 4.0, 9.0
    fp = 1 / Tp
    f = np.linspace(0.02, 1.0, 300)
    pm = 5 / 16 * Hs**2 * fp**4 * f**-5 * np.exp(-1.25 * (fp / f) ** 4)
    np.testing.assert_allclose(jonswap_spectrum(f, Hs, Tp, 1.0), pm, rtol=1e-12)


def test_jonswap_realisation():
    sea = JonswapWave(Hs=3.0, Tp=10.0, depth=200.0, seed=7)
    t = np.arange(0.0, 1 / sea.df, 0.2)  # the longest record without repetition
    eta = sea.elevation(np.zeros(2), t)
    assert 4 * eta.std() == pytest.approx(3.0, rel=0.01)
    assert abs(eta.mean()) < 0.01
    same = JonswapWave(Hs=3.0, Tp=10.0, depth=200.0, seed=7).elevation(np.zeros(2), t)
    np.testing.assert_array_equal(same, eta)
    other = JonswapWave(Hs=3.0, Tp=10.0, depth=200.0, seed=8).elevation(np.zeros(2), t)
    assert np.abs(other - eta).max() > 0.5
    # kinematics: each component satisfies the bed condition
    bed = np.array([[5.0, 3.0, -200.0]])
    assert abs(sea.velocity(bed, 12.0)[0, 2]) < 1e-14


def test_current_uniform_and_profile():
    points = np.array([[0.0, 0.0, -120.0], [0.0, 0.0, -50.0], [0.0, 0.0, -10.0], [1.0, 2.0, 3.0]])
    uniform = Current(0.8, heading_deg=90.0).velocity(points)
    np.testing.assert_allclose(uniform, np.tile([0.0, 0.8, 0.0], (4, 1)), atol=1e-15)
    profile = Current(profile=[(0.0, 1.0), (-100.0, 0.2)], heading_deg=180.0)
    speeds = -profile.velocity(points)[:, 0]
    np.testing.assert_allclose(speeds, [0.2, 0.6, 0.92, 1.0], rtol=1e-14)
    assert np.all(profile.velocity(points)[:, 1:] == pytest.approx(0.0, abs=1e-15))


def test_sea_sums_current_and_waves():
    wave = AiryWave(2.0, 8.0, 60.0)
    jon = JonswapWave(2.0, 9.0, 60.0, n_components=30, heading_deg=45.0)
    current = Current(0.5, heading_deg=20.0)
    sea = Sea(60.0, current=current, waves=[wave, jon])
    x, t = below_surface(8, 60.0), 4.2
    np.testing.assert_allclose(sea.velocity(x, t), current.velocity(x) + wave.velocity(x, t)
                               + jon.velocity(x, t), rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(sea.acceleration(x, t), wave.acceleration(x, t)
                               + jon.acceleration(x, t), rtol=1e-14, atol=1e-14)
    v, a = sea.kinematics(x, t)
    np.testing.assert_array_equal(v, sea.velocity(x, t))
    np.testing.assert_array_equal(a, sea.acceleration(x, t))
    np.testing.assert_allclose(sea.elevation(x, t), wave.elevation(x, t) + jon.elevation(x, t))
    assert Sea(60.0).still and not Sea(60.0, current=current).still
    waves_only = Sea(60.0, waves=[wave])  # no current: the wave's kinematics alone
    np.testing.assert_allclose(waves_only.velocity(x, t), wave.velocity(x, t), rtol=1e-14,
                               atol=1e-14)
    assert np.abs(waves_only.velocity(x, t)).max() > 0.1
    np.testing.assert_array_equal(Sea(60.0).velocity(x, t), np.zeros_like(x))


@pytest.mark.parametrize("build, field", [
    (lambda: Sea(-5.0), "Sea depth"),
    (lambda: Sea(50.0, rho=-1.0), "Sea rho"),
    (lambda: Sea(50.0, current=0.5), "Sea current"),
    (lambda: Sea(50.0, waves=[AiryWave(1.0, 8.0, 40.0)]), "Sea waves[0]: depth"),
    (lambda: Sea(50.0, waves=["big"]), "Sea waves[0]"),
    (lambda: Current(), "Current"),
    (lambda: Current(1.0, profile=[(0.0, 1.0)]), "Current"),
    (lambda: Current(profile=[(0.0, 1.0), (0.0, 2.0)]), "Current profile"),
    (lambda: Current(np.nan), "Current speed"),
    (lambda: AiryWave(-1.0, 8.0, 40.0), "AiryWave height"),
    (lambda: AiryWave(1.0, 0.0, 40.0), "AiryWave period"),
    (lambda: JonswapWave(1.0, 8.0, 40.0, n_components=0), "JonswapWave n_components"),
    (lambda: JonswapWave(1.0, 8.0, 40.0, f_range=(0.3, 0.1)), "JonswapWave f_range"),
    (lambda: jonswap_spectrum(0.1, 1.0, 8.0, gamma=-1.0), "jonswap_spectrum gamma"),
])
def test_bad_input_names_the_field(build, field):
    with pytest.raises(ValueError, match=field.replace("[", r"\[").replace("]", r"\]")):
        build()
