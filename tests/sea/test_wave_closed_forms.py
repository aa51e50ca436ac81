"""Water kinematics (skmoor.sea.waves) against Airy's formulas written out with cosh and
sinh, the deep-water limits, the JONSWAP sea's construction as documented (bin centres,
amplitudes sqrt(2 S df), seeded phases), and the superposition of the sea's parts (a
uniform water field stands in for a tabulated one)."""
import numpy as np
import pytest

from skmoor.sea.waves import (
    AiryWave,
    Current,
    JonswapWave,
    Sea,
    jonswap_spectrum,
    wavenumber,
)

G = 9.81


class UniformField:
    """A water field with one velocity, acceleration and elevation everywhere, each
    growing as (1 + t); its steady part is ``steady`` (a list of fields)."""

    def __init__(self, velocity, acceleration, elevation, steady=()):
        self.v, self.a, self.eta = (np.asarray(x, float) for x in (velocity, acceleration,
                                                                   elevation))
        self.has_acceleration = bool(np.any(self.a))
        self.steady = list(steady)

    def kinematics(self, points, t=0.0):
        """Its velocity and acceleration scaled by (1 + t) (it changes in time)."""
        shape = np.shape(points)
        return ((1.0 + t) * np.broadcast_to(self.v, shape),
                (1.0 + t) * np.broadcast_to(self.a, shape))

    def elevation(self, xy, t=0.0):
        shape = np.broadcast_shapes(np.shape(xy)[:-1], np.shape(t))
        return (1.0 + np.broadcast_to(t, shape)) * float(self.eta)

    def steady_parts(self):
        return self.steady


def airy(a, T, h, heading_deg, phase, point, t):
    """(eta, u, du/dt) of one Airy component, textbook form (finite depth)."""
    omega = 2 * np.pi / T
    k = wavenumber(omega, h)
    e = np.array([np.cos(np.radians(heading_deg)), np.sin(np.radians(heading_deg))])
    theta = k * (point[:2] @ e) - omega * t + phase
    z = np.clip(point[2], -h, 0.0)
    ch, sh = np.cosh(k * (z + h)) / np.sinh(k * h), np.sinh(k * (z + h)) / np.sinh(k * h)
    u = np.r_[a * omega * ch * np.cos(theta) * e, a * omega * sh * np.sin(theta)]
    dudt = np.r_[a * omega**2 * ch * np.sin(theta) * e, -a * omega**2 * sh * np.cos(theta)]
    return a * np.cos(theta), u, dudt


@pytest.mark.parametrize("point", [[12.0, -7.0, -9.0], [-30.0, 4.0, -39.0], [5.0, 5.0, -0.2]])
def test_airy_kinematics_are_the_textbook_formulas(point):
    """Velocity and acceleration of H = 3 m, T = 9 s in 40 m of water, heading 30 deg,
    against cosh k(z + h) / sinh kh and sinh k(z + h) / sinh kh written out."""
    wave = AiryWave(3.0, 9.0, 40.0, heading_deg=30.0, phase=0.4)
    point, t = np.array(point), 2.7
    eta, u, dudt = airy(1.5, 9.0, 40.0, 30.0, 0.4, point, t)
    v, a = wave.kinematics(point, t)
    assert np.allclose(v, u, rtol=1e-12, atol=1e-14)
    assert np.allclose(a, dudt, rtol=1e-12, atol=1e-14)
    assert wave.elevation(point, t) == pytest.approx(eta, rel=1e-12, abs=1e-14)


def test_airy_kinematics_below_the_seabed_are_those_at_the_seabed():
    """The water column ends at z = -h: a point below it sees the bed's kinematics (no
    vertical velocity), not a continued sinh profile."""
    wave = AiryWave(2.0, 7.0, 30.0, heading_deg=-20.0)
    bed, below = np.array([3.0, 1.0, -30.0]), np.array([3.0, 1.0, -36.0])
    for t in (0.3, 1.9):
        assert np.array_equal(wave.velocity(below, t), wave.velocity(bed, t))
        assert np.array_equal(wave.acceleration(below, t), wave.acceleration(bed, t))
    assert np.allclose(wave.velocity(bed, 0.3), airy(1.0, 7.0, 30.0, -20.0, 0.0, bed, 0.3)[1],
                       rtol=1e-12)


def test_deep_water_wave_decays_as_exp_kz_and_has_the_deep_water_length():
    """k h ~ 2400 (no overflow): u = a omega exp(k z) at the crest, L = g T^2 / (2 pi)."""
    wave = AiryWave(2.0, 5.0, 5000.0)
    omega = 2 * np.pi / 5.0
    k = omega**2 / G
    assert wave.wavenumber == pytest.approx(k, rel=1e-13)
    assert wave.wavelength == pytest.approx(G * 5.0**2 / (2 * np.pi), rel=1e-13)
    for z in (0.0, -3.0, -12.0):
        v, a = wave.kinematics(np.array([0.0, 0.0, z]), 0.0)
        assert np.all(np.isfinite(v)) and np.all(np.isfinite(a))
        assert v[0] == pytest.approx(omega * np.exp(k * z), rel=1e-12)
        assert a[2] == pytest.approx(-omega**2 * np.exp(k * z), rel=1e-12)


def jonswap_by_hand(f, Hs, Tp, gamma):
    """JONSWAP S(f) (m2/Hz) written out, scaled to Hs by a fine trapezoid sum of m0."""
    def shape(f):
        fp = 1.0 / Tp
        sigma = np.where(f <= fp, 0.07, 0.09)
        r = np.exp(-((f - fp) ** 2) / (2 * sigma**2 * fp**2))
        return f**-5 * np.exp(-1.25 * (fp / f) ** 4) * gamma**r

    grid = np.linspace(1e-3, 10.0 / Tp * 20, 2_000_001)
    values = shape(grid)
    m0 = np.sum(0.5 * (values[1:] + values[:-1]) * np.diff(grid))
    return Hs**2 / 16.0 / m0 * shape(f)


def test_jonswap_sea_is_the_documented_sum_of_components():
    """Bins of f_range split in n, frequencies at their centres, amplitudes sqrt(2 S df),
    phases default_rng(seed).uniform(0, 2 pi): the elevation at a point equals that sum
    (S written out by hand, both sides of the peak: sigma 0.07 and 0.09)."""
    Hs, Tp, gamma, n, seed = 3.0, 10.0, 2.5, 40, 11
    sea = JonswapWave(Hs, Tp, 80.0, gamma=gamma, seed=seed, n_components=n,
                      f_range=(0.05, 0.3), heading_deg=60.0)
    df = 0.25 / n
    f = 0.05 + df * (np.arange(n) + 0.5)
    assert sea.df == pytest.approx(df, rel=1e-14) and np.allclose(sea.f, f, rtol=1e-14)
    amplitudes = np.sqrt(2 * jonswap_by_hand(f, Hs, Tp, gamma) * df)
    phases = np.random.default_rng(seed).uniform(0.0, 2 * np.pi, n)
    point, t = np.array([40.0, -25.0, -10.0]), 17.0
    parts = [airy(a, 1 / fi, 80.0, 60.0, p, point, t) for a, fi, p in zip(amplitudes, f, phases)]
    assert sea.elevation(point, t) == pytest.approx(sum(p[0] for p in parts), rel=1e-6)
    v, a = sea.kinematics(point, t)
    assert np.allclose(v, sum(p[1] for p in parts), rtol=1e-6, atol=1e-9)
    assert np.allclose(a, sum(p[2] for p in parts), rtol=1e-6, atol=1e-9)


def test_jonswap_default_band_is_half_to_five_times_the_peak_frequency():
    Tp, n = 8.0, 9
    sea = JonswapWave(2.0, Tp, 100.0, n_components=n)
    df = (5.0 - 0.5) / Tp / n
    assert sea.df == pytest.approx(df, rel=1e-14)
    assert np.allclose(sea.f, 0.5 / Tp + df * (np.arange(n) + 0.5), rtol=1e-14)


def test_sea_superposes_current_waves_and_fields():
    """Velocity, acceleration and elevation of the sea are the sums of its parts (the
    current steady: no acceleration); one wave may be given without a list."""
    wave = AiryWave(2.0, 8.0, 60.0, heading_deg=10.0)
    current = Current(0.5, heading_deg=20.0)
    field = UniformField([0.1, -0.2, 0.05], [0.01, 0.02, -0.03], 0.25)
    sea = Sea(60.0, current=current, waves=wave, fields=[field])
    points, t = np.array([[3.0, 4.0, -5.0], [-20.0, 8.0, -41.0]]), 3.3
    velocity = current.velocity(points) + wave.velocity(points, t) + (1 + t) * field.v
    acceleration = wave.acceleration(points, t) + (1 + t) * field.a
    assert np.allclose(sea.velocity(points, t), velocity, rtol=1e-14, atol=1e-15)
    assert np.allclose(sea.acceleration(points, t), acceleration, rtol=1e-14, atol=1e-15)
    v, a = sea.kinematics(points, t)
    assert np.allclose(v, velocity, rtol=1e-14, atol=1e-15)
    assert np.allclose(a, acceleration, rtol=1e-14, atol=1e-15)
    assert np.allclose(sea.elevation(points, t), wave.elevation(points, t) + (1 + t) * 0.25,
                       rtol=1e-14)
    assert sea.elevation(points, np.array([[0.0], [1.0]])).shape == (2, 2)


def test_steady_sea_keeps_the_current_and_the_fields_steady_parts_only():
    """Within Sea.steady(): no waves, each field replaced by its steady parts (what a
    static solve sees); afterwards the sea is whole again."""
    wave = AiryWave(2.0, 8.0, 60.0)
    steady_part = UniformField([0.3, 0.0, 0.0], [0.0, 0.0, 0.0], 0.0)
    field = UniformField([0.1, -0.2, 0.05], [0.01, 0.02, -0.03], 0.25, steady=[steady_part])
    current = Current(0.5)
    sea = Sea(60.0, current=current, waves=[wave], fields=[field])
    point = np.array([[1.0, 2.0, -3.0]])
    assert sea.has_waves and not sea.still
    with sea.steady() as steady:
        assert steady is sea and not sea.has_waves and not sea.still
        assert np.allclose(sea.velocity(point, 2.0), [[0.5 + 3 * 0.3, 0.0, 0.0]], rtol=1e-14)
        assert not sea.acceleration(point, 2.0).any()
        assert not sea.elevation(point, 2.0).any()
    assert sea.waves == [wave] and sea.fields == [field]
    whole = current.velocity(point) + wave.velocity(point, 2.0) + 3.0 * field.v
    assert np.allclose(sea.velocity(point, 2.0), whole, rtol=1e-14)


def test_which_seas_accelerate_and_which_are_still():
    """has_waves: waves, or a field that accelerates; still: nothing at all. Air (rho = 0)
    and no gravity are allowed seas."""
    calm = UniformField([0.1, 0.0, 0.0], [0.0, 0.0, 0.0], 0.0)
    moving = UniformField([0.0, 0.0, 0.0], [0.0, 0.1, 0.0], 0.0)
    assert not Sea(50.0, fields=[calm]).has_waves and not Sea(50.0, fields=[calm]).still
    assert Sea(50.0, fields=[moving]).has_waves
    assert Sea(50.0, waves=[AiryWave(1.0, 6.0, 50.0)]).has_waves
    assert not Sea(50.0, current=Current(0.2)).has_waves
    assert Sea(50.0, rho=0.0, g=0.0).still
    assert Sea(50.0, rho=0.0).rho == 0.0
    assert Sea(50.0, rho=0.5, g=0.5).g == 0.5  # a light fluid, weak gravity: allowed
    for depth, g in ((50.0 + 5e-9, G), (50.0, G + 5e-9)):  # a wave of another depth or g
        with pytest.raises(ValueError):
            Sea(depth, g=g, waves=[AiryWave(1.0, 6.0, 50.0)])
    with pytest.raises(ValueError):
        Sea(50.0, g=-1.0)
    with pytest.raises(ValueError):
        Sea(50.0, waves=[AiryWave(1.0, 6.0, 50.0, g=9.8)])
    with pytest.raises(ValueError):
        Sea(50.0, fields=[object()])


def test_jonswap_edges_of_its_inputs():
    """No variance at f <= 0; one component is a sea (a single Airy wave of amplitude
    sqrt(2 S df)); a band must start above 0 Hz and end at a finite frequency, the number
    of components be a whole number."""
    assert not jonswap_spectrum(np.array([0.0, -0.2]), 2.0, 8.0).any()
    one = JonswapWave(2.0, 8.0, 100.0, n_components=1, f_range=(0.1, 0.15), seed=3)
    f, df = 0.125, 0.05
    amplitude = np.sqrt(2 * jonswap_spectrum(f, 2.0, 8.0) * df)
    phase = np.random.default_rng(3).uniform(0.0, 2 * np.pi, 1)[0]
    assert one.elevation(np.zeros(2), 4.0) == pytest.approx(
        amplitude * np.cos(-2 * np.pi * f * 4.0 + phase), rel=1e-12)
    for bad in (dict(f_range=(0.0, 0.2)), dict(f_range=(0.1, np.inf)),
                dict(f_range=(0.1, 0.1)), dict(n_components=2.5)):
        with pytest.raises(ValueError):
            JonswapWave(2.0, 8.0, 100.0, **bad)


def test_documented_defaults():
    """t = 0 when no time is given; heading 0 (along +x) and phase 0 (a crest at the
    origin at t = 0); JONSWAP's gamma 3.3 with 200 components and seed 0; sea water
    1025 kg/m3 and g = 9.81 m/s2."""
    wave = AiryWave(2.0, 8.0, 50.0)
    point = np.array([[3.0, 0.0, -4.0]])
    assert wave.elevation(np.zeros(2)) == pytest.approx(1.0, rel=1e-14)
    assert np.allclose(wave.velocity(point), airy(1.0, 8.0, 50.0, 0.0, 0.0, point[0], 0.0)[1])
    assert np.allclose(wave.acceleration(point), airy(1.0, 8.0, 50.0, 0.0, 0.0, point[0],
                                                      0.0)[2])
    assert np.array_equal(wave.kinematics(point)[0], wave.velocity(point, 0.0))
    sea = Sea(50.0, waves=[wave])
    assert sea.rho == 1025.0 and sea.g == 9.81
    for name in ("velocity", "acceleration", "elevation"):
        assert np.array_equal(getattr(sea, name)(point), getattr(sea, name)(point, 0.0))
    assert np.array_equal(sea.kinematics(point)[1], sea.kinematics(point, 0.0)[1])
    assert np.allclose(Current(0.7).velocity(point), [[0.7, 0.0, 0.0]])
    f = np.array([0.08, 0.1, 0.2])
    assert np.array_equal(jonswap_spectrum(f, 2.0, 10.0), jonswap_spectrum(f, 2.0, 10.0, 3.3))
    default = JonswapWave(2.0, 10.0, 50.0)
    explicit = JonswapWave(2.0, 10.0, 50.0, gamma=3.3, heading_deg=0.0, seed=0,
                           n_components=200)
    assert np.array_equal(default.velocity(point, 7.0), explicit.velocity(point, 7.0))


def test_current_profile_is_sorted_by_height_and_may_be_short():
    """Entries in any order are sorted by z (not by speed); one entry is a uniform
    current; entries closer than 1 m are fine; pairs must be (z, speed)."""
    profile = Current(profile=[(-100.0, 0.2), (0.0, 0.5), (-50.0, 0.9)])
    z = np.array([-120.0, -75.0, -50.0, -25.0, 0.0, 4.0])
    points = np.column_stack([np.zeros_like(z), np.zeros_like(z), z])
    assert np.allclose(profile.velocity(points)[:, 0], [0.2, 0.55, 0.9, 0.7, 0.5, 0.5],
                       rtol=1e-14)
    assert np.allclose(Current(profile=[(-10.0, 0.4)]).velocity(points)[:, 0], 0.4)
    fine = Current(profile=[(0.0, 1.0), (-0.5, 0.8)])
    assert fine.velocity(np.array([0.0, 0.0, -0.25]))[0] == pytest.approx(0.9, rel=1e-14)
    for bad in ([(0.0, 1.0, 2.0), (-1.0, 1.0, 2.0)], [0.0, 1.0], np.zeros((0, 2))):
        with pytest.raises(ValueError):
            Current(profile=bad)


def test_waves_under_another_gravity_follow_its_dispersion_relation():
    """omega^2 = g k tanh(k h) with the wave's own g (Mars: 3.71 m/s2), here and in the
    sea it belongs to."""
    wave = AiryWave(1.0, 10.0, 30.0, g=3.71)
    omega, k = 2 * np.pi / 10.0, wave.wavenumber
    assert 3.71 * k * np.tanh(k * 30.0) == pytest.approx(omega**2, rel=1e-13)
    jonswap = JonswapWave(1.0, 10.0, 30.0, n_components=5, g=3.71)
    assert np.allclose(3.71 * jonswap.k * np.tanh(jonswap.k * 30.0), jonswap.omega**2,
                       rtol=1e-13)
    assert Sea(30.0, g=3.71, waves=[wave, jonswap]).g == 3.71


def test_still_sea_has_a_flat_surface_of_the_points_and_times_shape():
    """No waves: elevation 0 at every point and time asked, shaped like them."""
    xy = np.zeros((4, 3))
    assert Sea(30.0).elevation(xy).shape == (4,)
    assert Sea(30.0).elevation(xy, np.zeros((2, 1))).shape == (2, 4)
    assert Sea(30.0).elevation(np.zeros((2, 5, 2)), 1.0).shape == (2, 5)
    assert not Sea(30.0).elevation(xy, 3.0).any()


def test_very_long_waves_travel_at_the_shallow_water_speed():
    """k h << 1 (a semidiurnal tide over the ocean and a shelf, a 10-day and a monthly wave
    in a metre of water, k h down to 1e-6): k = k0 (1 + (k0 h)^2 / 6) with
    k0 = omega / sqrt(g h), celerity sqrt(g h)."""
    for period, depth in ((44714.0, 4000.0), (44714.0, 50.0), (864000.0, 1.0),
                          (2.6e6, 1.0)):
        omega = 2 * np.pi / period
        k0 = omega / np.sqrt(G * depth)
        k = wavenumber(np.array([omega]), depth)[0]
        assert k0 * depth < 3e-3
        assert k == pytest.approx(k0 * (1 + (k0 * depth) ** 2 / 6), rel=1e-9)
        assert omega / k == pytest.approx(np.sqrt(G * depth), rel=2e-6)


def test_pierson_moskowitz_peak_value_and_no_division_at_zero_frequency():
    """gamma = 1: int shape = 1/5, so S(fp) = Hs^2 / 16 * 5 Tp exp(-5/4); S = 0 at f <= 0,
    evaluated without dividing by zero."""
    import warnings

    Hs, Tp = 2.0, 10.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        S = jonswap_spectrum(np.array([0.0, -0.05, 0.1]), Hs, Tp, gamma=1.0)
    assert S[0] == 0.0 and S[1] == 0.0
    assert S[2] == pytest.approx(Hs**2 / 16 * 5 * Tp * np.exp(-1.25), rel=1e-9)


def test_exact_number_types_give_the_float_kinematics():
    """Positions, times, phases and profiles given as Fraction or Decimal (as read from
    an exact-number parser) are numbers like any other: the textbook Airy values."""
    from decimal import Decimal
    from fractions import Fraction

    wave = AiryWave(3.0, 9.0, 40.0, heading_deg=30.0, phase=Fraction(2, 5))
    point, t = np.array([12.0, -7.0, -9.0]), 2.7
    eta, u, dudt = airy(1.5, 9.0, 40.0, 30.0, 0.4, point, t)
    for kind in (Fraction, Decimal):
        exact = [kind(12), kind(-7), kind(-9)]
        time = Fraction(27, 10) if kind is Fraction else Decimal("2.7")
        v, a = wave.kinematics(exact, time)
        assert np.allclose(v, u, rtol=1e-12, atol=1e-14)
        assert np.allclose(a, dudt, rtol=1e-12, atol=1e-14)
        assert wave.elevation(exact, time) == pytest.approx(eta, rel=1e-12, abs=1e-14)
        sea = Sea(40.0, waves=[wave], current=Current(0.5))
        assert sea.elevation(exact, time) == pytest.approx(eta, rel=1e-12, abs=1e-14)
        assert np.allclose(sea.velocity(exact, time), u + [0.5, 0.0, 0.0], rtol=1e-12)
        assert np.allclose(sea.acceleration(exact, time), dudt, rtol=1e-12, atol=1e-14)
    k = wavenumber([Fraction(1, 2), Fraction(1, 1)], 40.0)
    assert np.allclose(G * k * np.tanh(k * 40.0), [0.25, 1.0], rtol=1e-13)
    S = jonswap_spectrum([Fraction(1, 10)], 2.0, 10.0, gamma=1.0)
    assert S[0] == pytest.approx(4.0 / 16 * 5 * 10.0 * np.exp(-1.25), rel=1e-9)
    profile = Current(profile=[(Fraction(-10), Fraction(1, 2)), (Decimal(0), Decimal(1))])
    assert np.allclose(profile.velocity([0.0, 0.0, Fraction(-5)]), [0.75, 0.0, 0.0],
                       rtol=1e-14)


@pytest.mark.parametrize("build, field", [
    (lambda: Current(0.5, heading_deg=np.nan), "Current heading_deg"),
    (lambda: Current(profile=[(0.0, 1.0), (-5.0, np.inf)]), "Current profile"),
    (lambda: Current(profile=[0.0, 1.0]), "Current profile"),
    (lambda: Current(0.5).velocity(np.zeros((2, 2))), "Current.velocity"),
    (lambda: AiryWave(1.0, 8.0, -40.0), "AiryWave depth"),
    (lambda: AiryWave(1.0, 8.0, 40.0, g=0.0), "AiryWave g"),
    (lambda: AiryWave(1.0, 8.0, 40.0, heading_deg=np.inf), "AiryWave heading_deg"),
    (lambda: AiryWave(1.0, 8.0, 40.0, phase=np.nan), "AiryWave phase"),
    (lambda: AiryWave(1.0, 8.0, 40.0).velocity(np.zeros(2)), "AiryWave"),
    (lambda: JonswapWave(1.0, 8.0, 40.0, n_components=3).kinematics(np.zeros((4, 4))),
     "JonswapWave"),
    (lambda: jonswap_spectrum(0.1, 0.0, 8.0), "jonswap_spectrum Hs"),
    (lambda: jonswap_spectrum(0.1, 1.0, np.nan), "jonswap_spectrum Tp"),
    (lambda: JonswapWave(-1.0, 8.0, 40.0), "JonswapWave Hs"),
    (lambda: JonswapWave(1.0, 0.0, 40.0), "JonswapWave Tp"),
    (lambda: JonswapWave(1.0, 8.0, 40.0, gamma=0.0), "JonswapWave gamma"),
    (lambda: JonswapWave(1.0, 8.0, 0.0), "JonswapWave depth"),
    (lambda: Sea(50.0, rho=np.nan), "Sea rho"),
    (lambda: Sea(50.0, g=np.inf), "Sea g"),
    (lambda: Sea(50.0, g=-1.0), "Sea g"),
    (lambda: Sea(50.0, current="strong"), "Sea current.*str"),
    (lambda: Sea(50.0, waves=[AiryWave(1.0, 6.0, 50.0), "big"]), r"Sea waves\[1\].*str"),
    (lambda: Sea(50.0, waves=[AiryWave(1.0, 6.0, 50.0, g=9.8)]), r"Sea waves\[0\]"),
    (lambda: Sea(50.0, fields=[object()]), r"Sea fields\[0\].*object"),
    (lambda: Sea(50.0).kinematics(np.zeros((2, 2))), "Sea.kinematics"),
    (lambda: Sea(50.0).velocity(np.zeros((2, 2))), "Sea.velocity"),
    (lambda: Sea(50.0).acceleration(np.zeros((2, 2))), "Sea.acceleration"),
])
def test_bad_input_names_the_field_it_came_in(build, field):
    """Each rejected input's error names the argument (and for a wrong object, its type)."""
    with pytest.raises(ValueError, match=field):
        build()
