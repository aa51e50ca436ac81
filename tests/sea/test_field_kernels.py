"""The compiled evaluation of MoorDyn's water fields (skmoor.sea.water_grids.field_kinematics
and field_elevation, on packed_fields) against the fields' own NumPy kinematics and
elevation (themselves held against MoorDyn in test_sea_moordyn): current grids, spectra
and wave grids with currents, over a flat bed and a bathymetry, at points inside and
outside the grids, above and below the surface, over more than one period."""
from __future__ import annotations

import numpy as np
import pytest

from skmoor.sea.seabed import Bathymetry
from skmoor.sea.water_grids import (
    CurrentGrid,
    SpectrumWaves,
    Stretching,
    WaveGrid,
    field_elevation,
    field_kinematics,
    fields_lower,
    packed_fields,
)

DEPTH = 40.0


def bathymetry():
    x, y = np.array([-60.0, 0.0, 80.0]), np.array([-50.0, 40.0])
    return Bathymetry(x, y, -DEPTH + np.array([[3.0, -2.0], [0.0, 1.0], [-4.0, 2.0]]))


def current_grid(rng, nt=3):
    px, py, pz = np.array([-50.0, 10.0, 70.0]), np.array([-30.0, 30.0]), \
        np.array([-40.0, -20.0, -5.0, 0.0])
    return CurrentGrid(px, py, pz, 2.5, rng.normal(0.0, 0.4, (3, 2, 4, nt, 3)))


def spectrum(rng, bed):
    omega = np.linspace(0.3, 1.6, 9)
    amplitude = rng.normal(0.0, 0.3, 9) + 1j * rng.normal(0.0, 0.3, 9)
    return SpectrumWaves(omega, amplitude, rng.uniform(-0.6, 0.6, 9), Stretching(DEPTH, bed))


def wave_grid(rng, bed, currents=()):
    n = 8
    omega = np.arange(n) * 0.2
    c = rng.normal(0.0, 0.3, n) + 1j * rng.normal(0.0, 0.3, n)
    return WaveGrid((omega, c, rng.uniform(-0.5, 0.5, n)), np.linspace(-60.0, 60.0, 5),
                    np.array([-20.0, 0.0, 25.0]), np.array([-40.0, -25.0, -10.0, -3.0, 0.0]),
                    DEPTH, Stretching(DEPTH, bed), currents=currents)


def points(rng, m=40):
    """Inside and beyond the grids, from the bed to above the surface."""
    return np.column_stack([rng.uniform(-90.0, 90.0, m), rng.uniform(-45.0, 45.0, m),
                            rng.uniform(-DEPTH - 2.0, 1.5, m)])


def compiled(F, where, t):
    out = np.zeros((len(where), 6))
    for p, (x, y, z) in enumerate(where):
        field_kinematics(x, y, z, t, F, out[p])
    return out, np.array([field_elevation(x, y, t, F) for x, y, _ in where])


@pytest.mark.parametrize("kind", ["current", "spectrum", "grid", "grid with currents", "all"])
@pytest.mark.parametrize("on_bathymetry", [False, True])
def test_compiled_fields_equal_their_numpy_kinematics(kind, on_bathymetry):
    rng = np.random.default_rng(3)
    bed = bathymetry() if on_bathymetry else None
    fields = {"current": lambda: [current_grid(rng)],
              "spectrum": lambda: [spectrum(rng, bed)],
              "grid": lambda: [wave_grid(rng, bed)],
              "grid with currents": lambda: [wave_grid(rng, bed, [current_grid(rng),
                                                                  current_grid(rng, 1)])],
              "all": lambda: [spectrum(rng, bed), current_grid(rng),
                              wave_grid(rng, bed, [current_grid(rng)])]}[kind]()
    F = packed_fields(fields)
    where = points(rng)
    for t in (0.0, 3.7, 41.3):  # (past the grids' periods: 7.5 s and 31.4 s)
        velocity, acceleration, elevation = np.zeros((3, len(where), 3))
        elevation = np.zeros(len(where))
        for field in fields:
            v, a = field.kinematics(where, t)
            velocity, acceleration = velocity + v, acceleration + a
            elevation = elevation + field.elevation(where, t)
        out, zeta = compiled(F, where, t)
        scale = max(np.max(np.abs(velocity)), 1e-3)
        assert np.max(np.abs(velocity)) > 0.01  # the fields move the water there
        assert np.allclose(out[:, :3], velocity, rtol=0, atol=1e-12 * scale)
        assert np.allclose(out[:, 3:], acceleration, rtol=0, atol=1e-12 * max(scale, 1.0))
        assert np.allclose(zeta, elevation, rtol=0, atol=1e-12)


def test_fields_the_kernels_lack_are_not_packed():
    """A field of another kind (or a wave grid's current that is not a current grid) packs
    to None: the terms then stay in Python."""
    rng = np.random.default_rng(0)

    class Uniform:
        has_acceleration = False

        def kinematics(self, points, t=0.0):
            return np.ones(np.shape(points)), np.zeros(np.shape(points))

    assert packed_fields([]).tolist() == [0.0] and fields_lower([])
    for fields in ([current_grid(rng), Uniform()], [wave_grid(rng, None, [spectrum(rng, None)])]):
        assert packed_fields(fields) is None and not fields_lower(fields)
    fields = [spectrum(rng, None), wave_grid(rng, None, [current_grid(rng)])]
    assert packed_fields(fields) is not None and fields_lower(fields)
