"""Hydrodynamic coefficients: Capytaine on a coarse box (cached), the WAMIT reader."""

import numpy as np
import pytest

from skmoor import bem
from skmoor.sea.waves import wavenumber

cpt = pytest.importorskip("capytaine")

DRAFT, MASS = 0.9, 1.2e5
CENTRE = (0.0, 0.0, 2.5 - DRAFT)  # the box's centre of mass, floated at DRAFT


@pytest.fixture(scope="module")
def coarse(tmp_path_factory):
    """The paper's box on 2 m panels at two frequencies, 100 m of water, head waves."""
    mesh = cpt.mesh_parallelepiped(size=(26.0, 10.0, 5.0), resolution=(13, 5, 3))
    cache = tmp_path_factory.mktemp("bem")
    hydro = bem.from_mesh(mesh, [0.05, 1.0], offset=CENTRE, reference_point=CENTRE,
                          depth=100.0, cache=cache)
    return mesh, cache, hydro


def test_capytaine_box_limits(coarse):
    """Long waves: heave excitation -> rho g A_wp (the hydrostatic pressure on the
    keel), the surge force of head waves 90 deg ahead of the elevation (-i) and equal to
    G. I. Taylor's (rho V + A11) g k a; Capytaine's hydrostatic stiffness against the
    box's waterplane integrals."""
    _, _, hydro = coarse
    rho, g = 1025.0, 9.81
    heave = hydro.excitation[0, 0, 2]
    assert abs(heave - rho * g * 26.0 * 10.0) < 0.01 * rho * g * 260.0
    surge = hydro.excitation[0, 0, 0]
    assert surge.imag < 0 and abs(surge.real) < 0.05 * abs(surge.imag)
    k = wavenumber(0.05, 100.0)
    # G. I. Taylor's long-wave force: (rho V + A11) times the water acceleration g k a
    expected = (rho * 26.0 * 10.0 * DRAFT + hydro.added_mass[0, 0, 0]) * g * k
    assert abs(abs(surge) - expected) < 0.03 * expected
    # the box's waterplane terms, its weight taken equal to its buoyancy (Capytaine's
    # assumption without a mass): rho g (I_wp + V (z_B - z_G)), I_wp = int y^2 dA as
    # Capytaine integrates it, at the centres of the 2 m panels: L W (W^2 - 2^2) / 12
    V, z_B, z_G = 26.0 * 10.0 * DRAFT, -DRAFT / 2, CENTRE[2]
    exact = {2: rho * g * 260.0, 3: rho * g * (260.0 * (10.0**2 - 4) / 12 + V * (z_B - z_G)),
             4: rho * g * (260.0 * (26.0**2 - 4) / 12 + V * (z_B - z_G))}
    for i, value in exact.items():
        assert abs(hydro.hydrostatic_stiffness[i, i] - value) < 1e-6 * abs(value)


def test_cache_reused(coarse, monkeypatch):
    """The second call with the same mesh and settings reads the cache file (no solve);
    other settings solve again under another key."""
    mesh, cache, hydro = coarse

    def no_solve(*args, **kwargs):
        raise AssertionError("solved again instead of reading the cache")

    monkeypatch.setattr(bem, "_solve_capytaine", no_solve)
    again = bem.from_mesh(mesh, [0.05, 1.0], offset=CENTRE, reference_point=CENTRE,
                          depth=100.0, cache=cache)
    monkeypatch.undo()
    assert len(list(cache.glob("*.npz"))) == 1
    np.testing.assert_array_equal(again.added_mass, hydro.added_mass)
    np.testing.assert_array_equal(again.excitation, hydro.excitation)


def test_wamit_reader_against_capytaine_export(tmp_path):
    """Capytaine's own WAMIT writer (.1, .3, .hst: nondimensional, exp(+i omega t)) on
    random, asymmetric coefficients, read back by skmoor's reader: the dimensional
    coefficients in exp(-i omega t). Capytaine 3.0.0's .1 writer puts the radiating DOF
    in column I (WAMIT's manual: I the force, J the motion, which the reader follows), so
    the file holds the transposes of A and B."""
    import xarray as xr

    rng = np.random.default_rng(1)
    omega = [0.8, 1.6, np.inf]
    A, B = rng.normal(size=(2, 3, 6, 6)) * 1e5
    B[-1] = 0.0
    X = (rng.normal(size=(3, 2, 6)) + 1j * rng.normal(size=(3, 2, 6))) * 1e6
    C = rng.normal(size=(6, 6)) * 1e6
    matrix, force = ("omega", "influenced_dof", "radiating_dof"), ("omega", "wave_direction",
                                                                    "influenced_dof")
    data = xr.Dataset(
        dict(added_mass=(matrix, A), radiation_damping=(matrix, B), excitation_force=(force, X),
             hydrostatic_stiffness=(matrix[1:], C)),
        coords=dict(omega=omega, period=("omega", [2 * np.pi / 0.8, 2 * np.pi / 1.6, 0.0]),
                    wave_direction=[0.0, np.pi / 2], influenced_dof=list(bem.DOFS),
                    radiating_dof=list(bem.DOFS), rho=1025.0, g=9.81, water_depth=100.0,
                    forward_speed=0.0))
    cpt.export_dataset(str(tmp_path / "box"), data, format="wamit", exports=("1", "3", "hst"))
    read = bem.read_wamit(tmp_path / "box", rho=1025.0, g=9.81)
    np.testing.assert_allclose(read.omega, [0.8, 1.6], rtol=1e-6)
    np.testing.assert_allclose(read.headings, [0.0, 90.0])
    np.testing.assert_allclose(read.added_mass, A[:2].transpose(0, 2, 1), rtol=1e-5)
    np.testing.assert_allclose(read.damping, B[:2].transpose(0, 2, 1), rtol=1e-5)
    np.testing.assert_allclose(read.added_mass_inf, A[2].T, rtol=1e-5)
    np.testing.assert_allclose(read.excitation, X[:2], rtol=1e-5)
    np.testing.assert_allclose(read.hydrostatic_stiffness, C, rtol=1e-5)


def test_wamit_errors_name_file_and_line(tmp_path):
    (tmp_path / "bad.1").write_text("0.0 3 3 1.0\n6.28 3 3 x 2.0\n")
    (tmp_path / "bad.3").write_text("6.28 0.0 3 1 0 1 0\n")
    with pytest.raises(ValueError, match=r"bad\.1:2"):
        bem.read_wamit(tmp_path / "bad")
    (tmp_path / "nofreq.1").write_text("6.28 3 3 1.0 2.0\n")
    (tmp_path / "nofreq.3").write_text("6.28 0.0 3 1 0 1 0\n")
    with pytest.raises(ValueError, match="PER = 0"):
        bem.read_wamit(tmp_path / "nofreq")
    with pytest.raises(ValueError, match="no file"):
        bem.read_wamit(tmp_path / "missing")


def _write_wamit(root, periods, heave_phase_deg):
    """WAMIT files of a made-up body: A = 1e5 kg (x 1.2 at infinite frequency), B = 2e4 N s/m
    on the diagonal (rho = 1025, L = 1), heave excitation rho g 260 per m with the given
    phase (WAMIT's: the force leads the elevation at the origin, exp(+i omega t))."""
    rows = [f"0.0 {i} {i} {1.2e5 / 1025:.9e}" for i in range(1, 7)]
    for T in periods:
        rows += [f"{T} {i} {i} {1e5 / 1025:.9e} {2e4 / 1025 / (2 * np.pi / T):.9e}"
                 for i in range(1, 7)]
    root.with_suffix(".1").write_text("\n".join(rows) + "\n")
    phase = np.radians(heave_phase_deg)
    root.with_suffix(".3").write_text("".join(
        f"{T} 0.0 3 260.0 {heave_phase_deg} {260 * np.cos(phase)} {260 * np.sin(phase)}\n"
        for T in periods))


def test_case_file_body_potential_flow(tmp_path):
    """A case file's body.potential_flow (WAMIT files of known coefficients, a wave from
    the case's [sea]): the body's mass gains A_inf, and its heave excitation is
    rho g 260 a cos(omega t - phi + 30 deg) for the wave a cos(phi - omega t) at the
    reference point and a WAMIT heave force 30 deg ahead of the elevation."""
    import skmoor

    _write_wamit(tmp_path / "body", periods=[2 * np.pi / 0.8, 2 * np.pi / 1.2], heave_phase_deg=30.0)
    wave = {"type": "airy", "height": 0.2, "period": 2 * np.pi, "phase": 0.7}
    case = skmoor.paper_case(sea={"waves": [wave]},
                             body__potential_flow={"wamit": str(tmp_path / "body")})
    model = skmoor.build(case)
    term = model.system.body_terms[-1]
    assert isinstance(term, skmoor.PotentialFlow)
    body = slice(model.system.nf, model.system.nf + 6)
    system, rigid = model.system, model.system.bodies[0]
    without = (system.reduce_constant(system.M_lines).toarray()[body, body]
               + rigid.mass_matrix() + rigid.added_mass)  # the lines' fairlead masses too
    np.testing.assert_allclose(system.M.toarray()[body, body] - without, term.added_mass_inf,
                               atol=1e-9 * np.abs(without).max())
    for t in (0.0, 1.0, 2.5, 4.0):
        expected = 1025 * 9.81 * 260 * 0.1 * np.cos(t - 0.7 + np.radians(30.0))
        assert abs(term.excitation(t)[2] - expected) < 1e-9 * 1025 * 9.81 * 260
