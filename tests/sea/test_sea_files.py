"""MoorDyn's wave, current and seafloor input (skmoor.io.sea_files, skmoor.sea.water_grids).

Independent numbers: the kinematics of an Airy wave (closed form, Wheeler-stretched as
MoorDyn stretches them) from the files that describe it (an elevation record, one
frequency component); a current profile's linear interpolation at given depths and
times (a steady profile along one heading read as a Current, the same velocities); a bad
file refused naming the file, its line and the reason. MoorDyn's own
kinematics (``moordyn.GetWavesKin``) on the decks of its set side by side:
tests/sea/test_sea_moordyn.py.
"""
import numpy as np
import pytest

from skmoor.io.deck import read_deck
from skmoor.io.sea_files import deck_bathymetry, deck_sea
from skmoor.model.from_deck import deck_network
from skmoor.sea.waves import wavenumber

DEPTH, G = 50.0, 9.81
GRID = """--- water grid ---
x, y, z
kinds 0 single, 1 list, 2 lattice
2
-100 100 21
0
0
1
-50 -40 -30 -20 -10 -5 -2 0
"""


def deck_folder(tmp_path, options, files=()):
    """A one-line deck (a chain between two fixed points) with ``options`` in tmp_path,
    beside ``files`` {name: text}; returns the read Deck."""
    for name, text in dict(files).items():
        (tmp_path / name).write_text(text)
    text = f"""--- MoorDyn input ---
---------------------- LINE TYPES ------------------------------
TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx
(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
chain 0.1 20 1e8 -1 0 1.2 1.0 0.4 0.0
---------------------- POINTS ----------------------------------
ID Attachment X Y Z Mass Volume CdA Ca
(#) (-) (m) (m) (m) (kg) (m^3) (m^2) (-)
1 Fixed -90 0 -{DEPTH} 0 0 0 0
2 Fixed 0 0 -5 0 0 0 0
---------------------- LINES -----------------------------------
ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs
(#) (name) (#) (#) (m) (-) (-)
1 chain 1 2 100 10 -
---------------------- OPTIONS ---------------------------------
{G} g
{DEPTH} WtrDpth
""" + "".join(f"{value} {name}\n" for name, value in options.items()) + "--- END ---\n"
    (tmp_path / "deck.txt").write_text(text)
    return read_deck(tmp_path / "deck.txt")


def airy(a, omega, x, z, t, phase_shift=0.0):
    """Closed-form linear wave along +x of elevation a cos(omega t - k x + phase_shift):
    (zeta, u, w, du/dt, dw/dt) at x, z (z on the still water column)."""
    k = wavenumber(omega, DEPTH, G)
    theta = omega * t - k * x + phase_shift
    ch = np.cosh(k * (z + DEPTH)) / np.sinh(k * DEPTH)
    sh = np.sinh(k * (z + DEPTH)) / np.sinh(k * DEPTH)
    return (a * np.cos(theta), a * omega * ch * np.cos(theta), -a * omega * sh * np.sin(theta),
            -a * omega**2 * ch * np.sin(theta), -a * omega**2 * sh * np.cos(theta))


def stretched_points(sea, x, z_s, t):
    """Points at x whose Wheeler-stretched height is the grid height z_s under the
    elevation there: z = (z_s + h) (h + zeta) / h - h."""
    zeta = sea.elevation(np.array([[x, 0.0]]), t)[0]
    return np.array([[x, 0.0, (zs + DEPTH) * (DEPTH + zeta) / DEPTH - DEPTH] for zs in z_s])


def test_wavekin3_elevation_record_gives_the_airy_profile(tmp_path):
    """WaveKin 3: an Airy wave's elevation record at x = 0 (8.0 s period, 0.6 m, 64 s at
    dtWave 0.25 s) read back as its velocity and acceleration profile at x = 30 m, at
    grid nodes and wave samples, to 1e-9 of their amplitudes; the elevation record itself
    returned at the samples. A sign of k x, a cos for a sin, a factor 2 in the FFT's
    scale or a missing stretch would each be off by order one."""
    a, period, dt = 0.6, 8.0, 0.25
    omega = 2 * np.pi / period
    times = np.arange(0.0, 64.0 + dt / 2, dt)
    record = "".join(f"{t:.6f} {a * np.cos(omega * t):.15e}\n" for t in times)
    deck = deck_folder(tmp_path, {"WaveKin": 3, "dtWave": dt},
                       {"wave_elevation.txt": record, "water_grid.txt": GRID})
    sea = deck_sea(deck)
    assert sea.has_waves and sea.depth == DEPTH
    for t in (0.0, 1.25, 5.5, 70.5):  # 70.5 s: past the record, which repeats every 64 s
        z_grid = np.array([-40.0, -20.0, -5.0, -2.0])
        points = stretched_points(sea, 30.0, z_grid, t)
        v, acc = sea.kinematics(points, t)
        zeta, u, w, du, dw = airy(a, omega, 30.0, z_grid, t % 64.0)
        assert sea.elevation(np.array([[30.0, 0.0]]), t)[0] == pytest.approx(zeta, abs=1e-9)
        np.testing.assert_allclose(v[:, 0], u, atol=1e-9 * a * omega)
        np.testing.assert_allclose(v[:, 2], w, atol=1e-9 * a * omega)
        np.testing.assert_allclose(v[:, 1], 0.0, atol=1e-12)
        np.testing.assert_allclose(acc[:, 0], du, atol=1e-9 * a * omega**2)
        np.testing.assert_allclose(acc[:, 2], dw, atol=1e-9 * a * omega**2)
    # between samples: linear in time (MoorDyn's), so the sample mean at mid-step
    t0 = 3.0
    mid = sea.elevation(np.array([[0.0, 0.0]]), t0 + dt / 2)[0]
    assert mid == pytest.approx(0.5 * a * (np.cos(omega * t0) + np.cos(omega * (t0 + dt))),
                                abs=1e-9)


def test_wavekin2_frequency_component_on_a_grid(tmp_path):
    """WaveKin 2: one component c = a e^{i phi} at 0.5 rad/s (frequencies 0, 0.25, 0.5,
    0.75 rad/s, the others zero) is the wave a cos(omega t - k x + phi) (MoorDyn's inverse
    FFT convention), at grid nodes and samples."""
    a, phi, omega = 0.8, 0.7, 0.5
    c = a * np.exp(1j * phi)
    rows = ["0 0 0", "0.25 0 0", f"0.5 {c.real:.17g} {c.imag:.17g}", "0.75 0 0"]
    deck = deck_folder(tmp_path, {"WaveKin": 2}, {"wave_frequencies.txt": "\n".join(rows),
                                                 "water_grid.txt": GRID})
    sea = deck_sea(deck)
    dt = 2 * np.pi / 0.25 / 6  # the grid's samples: 2 (n - 1) over one 2 pi / dw period
    for t in (0.0, dt, 4 * dt):
        z_grid = np.array([-30.0, -10.0, -2.0])
        points = stretched_points(sea, -60.0, z_grid, t)
        v, acc = sea.kinematics(points, t)
        zeta, u, w, du, dw = airy(a, omega, -60.0, z_grid, t, phi)
        assert sea.elevation(points[:1, :2], t)[0] == pytest.approx(zeta, abs=1e-9)
        np.testing.assert_allclose(v[:, 0], u, atol=1e-9)
        np.testing.assert_allclose(v[:, 2], w, atol=1e-9)
        np.testing.assert_allclose(acc[:, 0], du, atol=1e-9)
        np.testing.assert_allclose(acc[:, 2], dw, atol=1e-9)
    # the last interval, [5 dt, 6 dt), holds sample 0 (MoorDyn's wrap)
    x = np.array([[-60.0, 0.0]])
    assert sea.elevation(x, 5.5 * dt)[0] == pytest.approx(sea.elevation(x, 0.0)[0], abs=1e-12)


def test_wavekin7_sums_components_at_the_points(tmp_path):
    """WaveKin 7: components summed at the points, elevation a sin(omega t - k l + phi)
    (MoorDyn's SpectrumKin convention, a quarter period from WaveKin 2's cos), heading
    beta from the 4th column: at arbitrary points and times, to round-off."""
    a, phi, omega, beta = 0.5, -0.4, 0.9, 0.6
    c = a * np.exp(1j * phi)
    deck = deck_folder(tmp_path, {"WaveKin": 7}, {"wave_frequencies.txt":
                                                 f"0 0 0\n{omega} {c.real:.17g} {c.imag:.17g} {beta}\n"})
    sea = deck_sea(deck)
    k = wavenumber(omega, DEPTH, G)
    t = 3.3
    points = np.array([[12.0, -7.0, -3.0], [-40.0, 25.0, -33.0]])
    l = points[:, 0] * np.cos(beta) + points[:, 1] * np.sin(beta)
    theta = omega * t - k * l + phi
    zeta = a * np.sin(theta)
    np.testing.assert_allclose(sea.elevation(points, t), zeta, atol=1e-12)
    z_s = DEPTH * (points[:, 2] + DEPTH) / (zeta + DEPTH) - DEPTH
    ch = np.cosh(k * (z_s + DEPTH)) / np.sinh(k * DEPTH)
    sh = np.sinh(k * (z_s + DEPTH)) / np.sinh(k * DEPTH)
    v, acc = sea.kinematics(points, t)
    np.testing.assert_allclose(v[:, 0], a * omega * ch * np.sin(theta) * np.cos(beta), atol=1e-12)
    np.testing.assert_allclose(v[:, 1], a * omega * ch * np.sin(theta) * np.sin(beta), atol=1e-12)
    np.testing.assert_allclose(v[:, 2], a * omega * sh * np.cos(theta), atol=1e-12)
    np.testing.assert_allclose(acc[:, 2], -a * omega**2 * sh * np.sin(theta), atol=1e-12)


def test_current_profiles_interpolate_in_depth_and_time(tmp_path):
    """Currents 1: linear in z between the profile's entries, held beyond them, uy from
    the 3rd column; Currents 2: linear in time between samples (MoorDyn resamples at
    the smallest step), repeating every nt dt with the last interval held at the first
    sample (MoorDyn's wrap of the sample index); no acceleration."""
    steady = "header\nz ux uy\n(m) (m/s) (m/s)\n-50 0.1 0.0\n-20 0.4 0.2\n0 1.0 0.2\n"
    deck = deck_folder(tmp_path, {"Currents": 1}, {"current_profile.txt": steady})
    sea = deck_sea(deck)
    z = np.array([-60.0, -35.0, -20.0, -10.0, 3.0])
    v, acc = sea.kinematics(np.stack([np.zeros(5), np.zeros(5), z], axis=-1), 12.0)
    np.testing.assert_allclose(v[:, 0], [0.1, 0.25, 0.4, 0.7, 1.0], atol=1e-14)
    np.testing.assert_allclose(v[:, 1], [0.0, 0.1, 0.2, 0.2, 0.2], atol=1e-14)
    assert not sea.has_waves and not np.any(acc)
    dynamic = ("h\nh\nh\nh\n-40 0\nt ux\n0 0.0 1.0\n10 1.0 1.0\n20 1.0 3.0\n")
    deck = deck_folder(tmp_path, {"Currents": 2}, {"current_profile_dynamic.txt": dynamic})
    sea = deck_sea(deck)
    point = np.array([[0.0, 0.0, -20.0]])  # halfway between the z's
    # samples every 10 s: [0.5, 1.0, 2.0] at t = 0, 10, 20; period 30 s, [20, 30) at 0.5
    for t, expected in ((0.0, 0.5), (5.0, 0.75), (15.0, 1.5), (20.0, 0.5), (25.0, 0.5),
                        (32.5, 0.625)):
        assert sea.velocity(point, t)[0, 0] == pytest.approx(expected, abs=1e-14), t


def test_a_profile_along_one_heading_is_a_steady_current(tmp_path):
    """Currents 1 with every velocity along one horizontal heading (0.6, 0.8), one of
    them against it: a steady Current (what the compiled step takes), the same
    velocities as the grid of the same file at every depth, beyond the ends too; a
    profile that turns, or rises, stays a grid."""
    from skmoor.io.sea_files import steady_profile
    from skmoor.sea.water_grids import CurrentGrid
    from skmoor.sea.waves import Current

    rows = [(-50.0, -0.1), (-20.0, 0.4), (0.0, 1.0)]
    text = "h\nh\nh\n" + "".join(f"{z} {0.6 * s} {0.8 * s}\n" for z, s in rows)
    sea = deck_sea(deck_folder(tmp_path, {"Currents": 1}, {"current_profile.txt": text}))
    assert isinstance(sea.current, Current) and not sea.fields
    z = np.linspace(-70.0, 10.0, 33)
    points = np.stack([np.zeros(z.size), np.zeros(z.size), z], axis=-1)
    velocity = np.array([[0.6 * s, 0.8 * s, 0.0] for _, s in rows])
    grid = CurrentGrid([0.0], [0.0], [r[0] for r in rows], 1.0,
                       velocity[None, None, :, None, :])
    np.testing.assert_allclose(sea.velocity(points, 3.0), grid.kinematics(points)[0],
                               atol=1e-14)
    turned = velocity.copy()
    turned[0, :2] = [0.1, 0.0]
    rising = velocity.copy()
    rising[1, 2] = 0.01
    assert steady_profile(np.array([r[0] for r in rows]), turned) is None
    assert steady_profile(np.array([r[0] for r in rows]), rising) is None


def test_unified_current_is_sampled_on_the_wave_grid(tmp_path):
    """WaveKin 3 with Currents 1: UnifyCurrentGrid 1 (the default) samples the current at
    the wave grid's z's (then linear between them), 0 keeps its own profile: at z = -45 m
    (between grid z's -50 and -40, and between profile z's -50 and -42), the two differ
    by exactly the two interpolations."""
    dt = 0.5
    record = "".join(f"{t} 0.0\n" for t in np.arange(0.0, 10.5, dt))  # still water
    steady = "h\nh\nh\n-50 0.0\n-42 0.8\n0 1.0\n"
    files = {"wave_elevation.txt": record, "water_grid.txt": GRID, "current_profile.txt": steady}
    point = np.array([[0.0, 0.0, -45.0]])
    unified = deck_sea(deck_folder(tmp_path, {"WaveKin": 3, "Currents": 1, "dtWave": dt}, files))
    apart = deck_sea(deck_folder(tmp_path, {"WaveKin": 3, "Currents": 1, "dtWave": dt,
                                            "UnifyCurrentGrid": 0}, files))
    at_minus_40 = 0.8 + 0.2 * 2.0 / 42.0
    assert unified.velocity(point, 1.0)[0, 0] == pytest.approx(0.5 * at_minus_40, abs=1e-12)
    assert apart.velocity(point, 1.0)[0, 0] == pytest.approx(0.8 * 5.0 / 8.0, abs=1e-12)


def test_wavekin1_waves_come_from_the_caller(tmp_path):
    """WaveKin 1: the deck's water has no waves of its own (MoorDyn's nodes before the
    caller sets them); the caller's Sea drives the lines."""
    from skmoor.sea.waves import AiryWave, Sea

    deck = deck_folder(tmp_path, {"WaveKin": 1})
    assert deck_sea(deck).still
    wave = AiryWave(1.0, 8.0, deck.depth, g=G)
    network, _ = deck_network(deck, sea=Sea(deck.depth, rho=deck.rho, g=G, waves=[wave]))
    assert network.sea.waves == [wave]


BAD = [
    ("WaveKin", 3, "wave_elevation.txt", "0 0\n0.5 0.1\n0.4 0.2\n", "line 3: the times"),
    ("WaveKin", 3, "wave_elevation.txt", "0 0\n0.5 nan\n", "line 2: 'nan' is not finite"),
    ("WaveKin", 3, "wave_elevation.txt", "0 0\n0.5\n", "line 2: 1 values"),
    ("WaveKin", 7, "wave_frequencies.txt", "0.1 0 0\n0.2 1 0\n", "the first frequency"),
    ("WaveKin", 7, "wave_frequencies.txt", "0 0 0\n0.2 1 0 7.0\n", "heading 7"),
    ("WaveKin", 7, "wave_frequencies.txt", "0 0 0\n0.2 x 0\n", "'x' is not a number"),
    ("Currents", 1, "current_profile.txt", "h\nh\nh\n0 1\n-10 1\n", "the z's must increase"),
    ("Currents", 1, "current_profile.txt", "h\nh\n", "at least 4 needed"),
    ("Currents", 2, "current_profile_dynamic.txt", "h\nh\nh\nh\n-10 0\nh\n0 1\n",
     "line 7: 2 values, need t and ux at the 2 z's"),
    ("Currents", 5, "current_profile_4d.txt", "1 1 1 1\n0\n0\n0\n0\nh\n0 0 0 5 1 0 0\n",
     "t = 5 is not on the t axis"),
]


@pytest.mark.parametrize("option, mode, name, text, reason", BAD)
def test_bad_files_are_refused_with_file_line_and_reason(tmp_path, option, mode, name, text,
                                                         reason):
    deck = deck_folder(tmp_path, {option: mode}, {name: text, "water_grid.txt": GRID})
    with pytest.raises(ValueError) as err:
        deck_sea(deck)
    message = str(err.value)
    assert message.startswith(f"deck.txt line {deck.option_lines[option]}: option {option}")
    assert name in message and reason in message, message


def test_missing_files_and_unsupported_modes(tmp_path):
    deck = deck_folder(tmp_path, {"WaveKin": 2})
    with pytest.raises(ValueError, match="wave_frequencies.txt: no such file"):
        deck_sea(deck)
    deck = deck_folder(tmp_path, {"Currents": 3})
    with pytest.raises(ValueError, match=r"deck.txt line \d+: option Currents = 3: skmoor reads"):
        deck_sea(deck)
    deck = deck_folder(tmp_path, {"SeafloorFile": "nowhere.txt"})
    with pytest.raises(ValueError, match="SeafloorFile 'nowhere.txt': no such file"):
        deck_bathymetry(deck)
    bad_grid = GRID.replace("-50 -40 -30", "-50 -30 -40")
    deck = deck_folder(tmp_path, {"WaveKin": 2}, {"water_grid.txt": bad_grid,
                                                 "wave_frequencies.txt": "0 0 0\n1 1 0\n"})
    with pytest.raises(ValueError, match="water_grid.txt line 9: the z coordinates must "
                                         "increase strictly"):
        deck_sea(deck)
    deck = deck_folder(tmp_path, {"SeafloorFile": "bed.txt"},
                       {"bed.txt": "2 2\n0 1\n0 1\n0 0 -5\n"})
    with pytest.raises(ValueError, match="bed.txt: 3 of the 4 grid points have no height"):
        deck_bathymetry(deck)
    deck = deck_folder(tmp_path, {"SeafloorFile": "bed.txt"},
                       {"bed.txt": "2 2\n0 1\n0\n0 0 -5\n"})
    with pytest.raises(ValueError, match="bed.txt line 3: 1 values, expected 2"):
        deck_bathymetry(deck)


def test_seafloor_file_is_a_bathymetry_and_sets_the_wave_depth(tmp_path):
    """A SeafloorFile: bilinear heights, its mean depth the waves' depth (MoorDyn's
    getAverageDepth), the deck's bed on it."""
    bed = "2 3\n-100 100\n-10 0 10\n" + "".join(
        f"{x} {y} {-40.0 - 0.05 * x}\n" for x in (-100, 100) for y in (-10, 0, 10))
    deck = deck_folder(tmp_path, {"SeafloorFile": "bed.txt", "WaveKin": 7},
                       {"bed.txt": bed, "wave_frequencies.txt": "0 0 0\n0.5 0.3 0\n"})
    bathymetry = deck_bathymetry(deck)
    assert bathymetry.height(np.array([30.0, 4.0])) == pytest.approx(-41.5, abs=1e-12)
    assert bathymetry.mean_height == pytest.approx(-40.0, abs=1e-12)
    sea = deck_sea(deck, bathymetry)
    assert sea.depth == pytest.approx(40.0)
    network, _ = deck_network(deck)
    assert network.seabed.bathymetry is not None
    assert network.seabed.height(np.array([[-100.0, 0.0]]))[0] == pytest.approx(-35.0)


def test_4d_current_is_quadrilinear_in_x_y_z_t(tmp_path):
    """Currents 5: values on a 2 x 1 x 2 x 2 grid (line 6 a header, as MoorDyn reads it)
    linear in x, z and t in between: u = 1 + x / 10 + z / 20 + t / 5 is reproduced
    exactly inside the grid and held at its edge outside; a grid point without a line
    has zero current and is noted."""
    lines = ["2 1 2 2", "0 10", "0", "-20 0", "0 5", "x y z t ux uy uz"]
    for x in (0, 10):
        for z in (-20, 0):
            for t in (0, 5):
                lines.append(f"{x} 0 {z} {t} {1 + x / 10 + z / 20 + t / 5} 0 0")
    deck = deck_folder(tmp_path, {"Currents": 5}, {"current_profile_4d.txt": "\n".join(lines)})
    sea = deck_sea(deck)
    points = np.array([[2.5, 3.0, -15.0], [7.0, 0.0, -1.0], [30.0, 0.0, -40.0]])
    expected = lambda x, z, t: 1 + x / 10 + z / 20 + t / 5  # noqa: E731
    for t in (0.0, 1.5, 4.0):
        u = sea.velocity(points, t)[:, 0]
        assert u == pytest.approx([expected(2.5, -15.0, t), expected(7.0, -1.0, t),
                                   expected(10.0, -20.0, t)], abs=1e-12)
    del lines[6]  # the point (0, 0, -20, 0) has no line now
    deck = deck_folder(tmp_path, {"Currents": 5}, {"current_profile_4d.txt": "\n".join(lines)})
    sea = deck_sea(deck)
    assert sea.velocity(np.array([[0.0, 0.0, -20.0]]), 0.0)[0, 0] == 0.0
    assert any("1 grid points have no line" in note for note in deck.notes)
