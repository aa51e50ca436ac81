"""The compiled step in MoorDyn's tabulated water (skmoor.sea.water_grids: a wave grid with
a current grid added, a spectrum of components, over a flat bed and a bathymetry)
against the Python step, which evaluates the fields' NumPy kinematics (held to MoorDyn in
test_sea_moordyn): lines' Morison drag and fluid inertia on P1 and bending elements, a
free point's and bodies' drag, VIV lift and the free surface's hand-back. The two runs
repeat the same Newton, so they agree to round-off; the water read at the reference
nodes, at the step's start or without the fields' acceleration would part them by far
more (each test checks that the fields move the run)."""
import numpy as np
import pytest
from test_compiled_step import (
    SHEAR,
    TOL,
    _chain_on_the_bed,
    assert_same_runs,
    chain_to_the_surface,
    chains_in_seas,
    run,
    runs_of_variants,
    steps_before_handing_back,
)
from test_network import network_two_bodies

import skmoor
from skmoor.sea.seabed import Bathymetry
from skmoor.sea.water_grids import CurrentGrid, SpectrumWaves, Stretching, WaveGrid
from skmoor.sea.waves import Current, Sea
from skmoor.solvers import compiled_step
from skmoor.solvers.dynamics import Scheme


def field_sea(depth, bathymetry=None, seed=2):
    """A current profile and two fields: a wave grid (8 components, 2.4 s to 31 s, a
    current grid added) and a spectrum (6 components), headings across +x."""
    rng = np.random.default_rng(seed)
    stretching = Stretching(depth, bathymetry)
    n = 14
    omega = np.arange(n) * 0.2
    amplitude = np.where((omega > 0.4) & (omega < 1.8), 0.35, 0.0) * np.exp(
        1j * rng.uniform(0, 2 * np.pi, n))
    px, py = np.linspace(-400.0, 400.0, 9), np.array([-200.0, 0.0, 200.0])
    pz = np.linspace(-depth, 0.0, 7)
    current = CurrentGrid(px[::4], py, pz[::3], 4.0,
                          rng.normal(0.0, 0.2, (3, 3, 3, 4, 3)) + [0.3, 0.1, 0.0])
    grid = WaveGrid((omega, amplitude, np.full(n, 0.4)), px, py, pz, depth, stretching,
                    currents=[current])
    spectrum = SpectrumWaves(np.linspace(0.5, 1.2, 6), 0.2 * np.exp(1j * rng.uniform(0, 6, 6)),
                             np.full(6, -0.3), stretching)
    return Sea(depth, current=Current(profile=[(z, s / 3) for z, s in SHEAR], heading_deg=30.0),
               fields=[grid, spectrum])


@pytest.mark.parametrize("EI", [0.0, 1e5])
@pytest.mark.parametrize("on_bathymetry", [False, True])
def test_a_chain_in_water_fields_steps_as_the_python_newton(EI, on_bathymetry):
    bathymetry = (Bathymetry([-200.0, 100.0], [-50.0, 50.0], [[-31.0, -30.5], [-29.0, -30.0]])
                  if on_bathymetry else None)
    runs = runs_of_variants(chains_in_seas({
        "fields": field_sea(30.0, bathymetry),
        "current": Sea(30.0, current=field_sea(30.0).current)}, EI))
    assert np.abs(runs["fields"] - runs["current"]).max() > 0.05


def test_points_and_bodies_with_drag_in_water_fields_step_as_the_python_newton():
    """The two buoys' network (a free clump with drag, lines with Morison terms) with
    MoorDyn's body drag, in the fields: the water at the displaced clump and reference
    points at each residual's time."""
    from skmoor.sea.hydro import body_hydrodynamics

    sea = field_sea(150.0)
    runs = {}
    for name, water in (("fields", sea), ("still", None)):
        network = network_two_bodies(water)
        for body in network.bodies:
            body.terms.append(body_hydrodynamics(
                drag_coefficients=[1.2, 0.8, 1.0, 0.6, 0.5, 0.7],
                drag_areas=[12.0, 15.0, 10.0, 40.0, 30.0, 50.0], sea=water,
                reference_point=body.position))
        model = skmoor.from_network(network)
        system = model.system
        x0 = skmoor.equilibrium(model).x
        if name == "fields":
            assert_same_runs(system, x0, np.zeros(system.n), 0.02, 60)
        runs[name], _ = run(system, x0, np.zeros(system.n), 0.02, 60)
    assert np.abs(runs["fields"] - runs["still"]).max() > 0.01


def test_a_line_under_a_field_surface_is_handed_back_where_the_waves_reach_it():
    """A chain from the bed to a fixed fairlead 0.5 m under the still surface with the dry
    part of the line (SurfaceTerm) under the fields' waves: the compiled step takes it and
    hands the step back at the first step time t where -0.5 - eta(0, 0, t) > -d / 2 by
    Sea.elevation (the fields' elevation); the run through the handed-back steps is the
    Python step's."""
    sea = field_sea(30.0)
    dt, steps = 0.05, 120
    times = dt * np.arange(1, steps + 1)
    system, x0, diameter = chain_to_the_surface(sea, -0.5)
    eta = np.array([sea.elevation(np.zeros(2), t) for t in times])
    expected = int(np.argmax(-0.5 - eta > -0.5 * diameter))
    assert 5 < expected and np.any(-0.5 - eta > -0.5 * diameter)
    assert steps_before_handing_back(system, x0, times, dt) == expected
    assert_same_runs(system, x0, np.zeros(system.n), dt, expected + 10,
                     scheme=Scheme.generalized_alpha(0.5), same_iterations=False, rel=1e-8)


def test_fields_of_other_kinds_stay_in_python_and_say_so():
    """A field the compiled kernels lack keeps the lines' Morison term in Python, the
    refusal naming it."""
    from skmoor.sea.hydro import line_hydrodynamics

    class Uniform:
        has_acceleration = False

        def kinematics(self, points, t=0.0):
            return np.full(np.shape(points), 0.2), np.zeros(np.shape(points))

        def elevation(self, xy, t=0.0):
            return np.zeros(np.shape(xy)[:-1])

        def steady_parts(self):
            return [self]

    motion = lambda t: np.array([[0.0, 0.0, np.sin(0.6 * t)]])  # noqa: E731
    base, _ = _chain_on_the_bed(motion, hydro=False)
    system = skmoor.System(base.lines, fairleads="prescribed", motion=motion,
                           terms=[*base.terms, line_hydrodynamics(
                               base.lines, Sea(30.0, fields=[Uniform()]))])
    assert compiled_step.build(system, None, Scheme.newmark(), TOL, 20) is None
    assert "water field" in compiled_step.last_refusal


def test_the_compiled_step_advances_the_lift_in_a_wave_spectrum_as_the_python_step():
    """The VIV lock-in string raised to 1 m under the still surface in a current, under a
    one-component spectrum field (1.5 m amplitude, 8 s, across the current: the middle
    node falls dry in its trough at 2 s): the compiled step (the field's velocity and
    elevation at the displaced node) steps as the Python step and ends with the same lift state;
    the field moves the string by far more than the tolerance."""
    from test_viv import raised_lock_in_run

    spectrum = [SpectrumWaves([2 * np.pi / 8.0], [-1.5], [np.pi / 3], Stretching(50.0))]
    times = np.linspace(0.0, 3.0, 100)  # (the run: 300 steps of 1 / (50 f_n), 3.3 s)
    assert min(Sea(50.0, fields=spectrum).elevation(np.zeros(2), t) for t in times) < -1.2
    fast, state_fast, _ = raised_lock_in_run(True, fields=spectrum)
    slow, state_slow, _ = raised_lock_in_run(False, fields=spectrum)
    motion = np.abs(slow - slow[0]).max()
    assert np.abs(fast - slow).max() < 1e-9 * motion
    assert state_fast == pytest.approx(state_slow, rel=1e-9, abs=1e-9 * np.abs(state_slow).max())
    calm, _, _ = raised_lock_in_run(True)
    assert np.abs(calm - slow).max() > 0.1 * motion
