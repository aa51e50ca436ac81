"""The compiled Newton step (skmoor.solvers.compiled_step) against the Python step it stands for.

Independent numbers: the Python iteration of ``dynamics.integrate`` on
``coupling.System.residual`` (whose tangents are held to central differences and whose
runs are held to analytic solutions and MoorDyn elsewhere in the suite) and LAPACK's
solves (the bordered band LU). The compiled step repeats the same modified Newton, so on
systems it covers the two runs must agree to round-off, step by step: a dropped term of
the residual (a body's hydrostatics, a free point's drag, the lines' velocity slope at a
rotating body), a wrong factor in the Newton matrix (it changes the iterates) or a wrong
scheme update would show as a difference orders of magnitude above that.
"""
import dataclasses

import numpy as np
import pytest
import scipy.sparse as sp
from test_network import network_two_bodies

import skmoor
from skmoor.numerics import bordered
from skmoor.solvers import compiled_step
from skmoor.solvers.dynamics import Scheme, integrate

TOL = 1e-10  # Newton's tolerance in both runs: its stopping decisions then agree too


def run(system, x0, v0, dt, steps, C=None, compiled=True, scheme=None, **kw):
    """(states (steps, n), iterations) of integrate from (x0, v0)."""
    scheme = scheme or Scheme.generalized_alpha(0.8)
    xs, its = [], []
    for state in integrate(system, x0, v0, dt, steps * dt, C=C, scheme=scheme, tol=TOL,
                           compiled=compiled, **kw):
        xs.append(state.x.copy())
        its.append(state.iterations)
    return np.array(xs), np.array(its)


def assert_same_runs(system, x0, v0, dt, steps, C=None, scheme=None, rel=1e-9,
                     same_iterations=True):
    assert compiled_step.build(system, None if C is None else sp.csr_matrix(C),
                               scheme or Scheme.newmark(), TOL, 20) is not None, \
        compiled_step.last_refusal
    fast, it_fast = run(system, x0, v0, dt, steps, C, True, scheme)
    slow, it_slow = run(system, x0, v0, dt, steps, C, False, scheme)
    motion = np.abs(slow - slow[0]).max()
    assert motion > 1e-3  # the run does move
    assert np.abs(fast - slow).max() < rel * motion
    if same_iterations:  # (a step the compiled Newton gives up on is counted anew)
        assert np.array_equal(it_fast, it_slow)


def runs_of_variants(variants, dt=0.05, steps=40, rel=1e-8):
    """{name: (system, x0)}: each taken by the compiled step, the first stepping as the
    Python Newton (generalized-alpha, rho_inf 0.5, from rest; within ``rel`` of the
    motion: a chain's touchdown grows the two steps' round-off to 5e-10 of it); each
    one's states (steps, n) by name."""
    scheme, runs = Scheme.generalized_alpha(0.5), {}
    for k, (name, (system, x0)) in enumerate(variants.items()):
        assert compiled_step.build(system, None, scheme, TOL, 20) is not None, \
            compiled_step.last_refusal
        if k == 0:
            assert_same_runs(system, x0, np.zeros(system.n), dt, steps, scheme=scheme,
                             rel=rel)
        runs[name], _ = run(system, x0, np.zeros(system.n), dt, steps, scheme=scheme)
    return runs


def test_paper_case_steps_as_the_python_newton():
    """The paper's box on its four lines with its Rayleigh damping and sine load."""
    model = skmoor.build(skmoor.paper_case())
    eq = skmoor.equilibrium(model)
    assert_same_runs(model.system, eq.x, np.zeros(model.system.n), 0.05, 60, C=eq.C)


def test_damped_lines_on_rotating_bodies_step_as_the_python_newton():
    """Two buoys on a shared rope, a free clump with mass, volume and drag, a prescribed
    point, lines with internal damping (BA): the bodies start turning, so the velocity
    slope of their line ends and the Hessian of the attachment enter the Newton matrix."""
    model = skmoor.from_network(network_two_bodies())
    system = model.system
    eq = skmoor.equilibrium(model)
    v0 = np.zeros(system.n)
    v0[system.nf:] = [0.2, -0.1, 0.05, 0.02, -0.03, 0.04, -0.1, 0.2, 0.0, -0.02, 0.01, 0.05]
    assert_same_runs(system, eq.x, v0, 0.02, 80)


def test_a_network_in_waves_and_a_current_steps_as_the_python_newton():
    """The two buoys' network in a current and a JONSWAP sea: the free clump's drag takes
    the water's velocity at the displaced point at the step's time (Sea.velocity in the
    Python step), the lines' Morison terms theirs at the nodes. A clump drag in still
    water, at the reference position or at another time would part the runs."""
    from skmoor.sea.waves import Current, JonswapWave, Sea

    sea = Sea(150.0, current=Current(0.8, heading_deg=30.0),
              waves=[JonswapWave(3.0, 9.0, depth=150.0, heading_deg=20.0, n_components=20,
                                 seed=1)])
    model = skmoor.from_network(network_two_bodies(sea))
    system = model.system
    eq = skmoor.equilibrium(model)
    assert_same_runs(system, eq.x, np.zeros(system.n), 0.02, 80)


@pytest.mark.parametrize("water", ["still", "current and waves"])
def test_bodies_with_drag_step_as_the_python_newton(water):
    """The two buoys' network with MoorDyn's body drag (BodyDrag: force on the reference
    point's velocity relative to the water, moment on the angular velocity, along axes
    turned from the global ones), the bodies set moving and turning: the compiled step
    takes it and steps as the Python Newton (the water at the displaced reference point
    at the step's time, d/dqdot exact). The drag moves the buoys by more than the
    tolerance: a dropped moment, the water at the reference position or the force's sign
    would part the runs (checked against the run without drag)."""
    from scipy.spatial.transform import Rotation

    from skmoor.sea.hydro import body_hydrodynamics
    from skmoor.sea.waves import Current, JonswapWave, Sea

    sea = None if water == "still" else Sea(
        150.0, current=Current(0.8, heading_deg=30.0),
        waves=[JonswapWave(3.0, 9.0, depth=150.0, heading_deg=20.0, n_components=20, seed=1)])
    axes = Rotation.from_euler("xyz", [10.0, -20.0, 35.0], degrees=True).as_matrix()
    runs = {}
    for drag in (True, False):
        network = network_two_bodies(sea)
        for body in network.bodies if drag else []:
            body.terms.append(body_hydrodynamics(
                drag_coefficients=[1.2, 0.8, 1.0, 0.6, 0.5, 0.7],
                drag_areas=[12.0, 15.0, 10.0, 40.0, 30.0, 50.0], sea=sea,
                reference_point=body.position, axes=axes))
        model = skmoor.from_network(network)
        system = model.system
        eq = skmoor.equilibrium(model)
        v0 = np.zeros(system.n)
        v0[system.nf:] = [0.4, -0.2, 0.1, 0.05, -0.06, 0.08, -0.2, 0.4, 0.0, -0.04, 0.02, 0.1]
        if drag:
            assert_same_runs(system, eq.x, v0, 0.02, 80)
        runs[drag], _ = run(system, eq.x, v0, 0.02, 80)
    assert np.abs(runs[True] - runs[False])[:, -12:].max() > 1e-3
    if sea is not None:  # the step holds one sea: a body's drag in another is Python's
        network = network_two_bodies(sea)
        network.bodies[0].terms.append(body_hydrodynamics(
            drag_coefficients=[1.0] * 6, drag_areas=[10.0] * 6, sea=Sea(150.0),
            reference_point=network.bodies[0].position))
        system = skmoor.from_network(network).system
        assert compiled_step.build(system, None, Scheme.newmark(), TOL, 20) is None
        assert "different seas" in compiled_step.last_refusal


@pytest.mark.parametrize("EI", [0.0, 1e5])
def test_a_chain_on_a_bathymetry_steps_as_the_python_newton(EI):
    """The chain heaved and surged on a bumpy bed (a Bathymetry: bilinear heights, the
    contact along each cell's normal under the displaced node), on P1 and on bending
    elements: the compiled step takes it (the bed's plane under each node at each
    residual) and steps as the Python Newton, its reports' anchor support on the
    bathymetry's plane too (test_reported_end_forces_and_line_state_are_the_systems). The
    bed's shape moves the chain by decimetres from its run on the flat bed (the planes
    under displaced nodes: tests/sea/test_bathymetry.py)."""
    motion = lambda t: np.array([[8.0 * np.sin(0.6 * t), 0.0, 2.0 * np.sin(0.6 * t)]])  # noqa: E731
    runs = runs_of_variants({
        "bathymetry": _chain_on_the_bed(motion, EI=EI, bathymetry=bumpy_bed()),
        "flat": _chain_on_the_bed(motion, EI=EI)})
    assert np.abs(runs["bathymetry"] - runs["flat"]).max() > 0.1


@pytest.mark.parametrize("friction, surface", [(0.0, False), (0.6, False), (0.0, True)])
def test_chain_on_the_bed_with_drag_steps_as_the_python_newton(friction, surface):
    """A chain from the bed to a fairlead 1 m under the surface, heaved 2 m (prescribed),
    on a sea bed with drag and added mass: a System without bodies (a pure band); with bed
    friction (different axial and lateral coefficients); and with the dry part of the line
    (SurfaceTerm), whose steps with the fairlead near the surface go to Python."""
    from skmoor.lines.catenary import solve_catenary
    from skmoor.sea.hydro import line_hydrodynamics
    from skmoor.sea.seabed import Seabed, seabed_term
    from skmoor.sea.surface import SurfaceTerm

    chain = skmoor.LineType(EA=7.5e8, mass=140.0, diameter=0.09, BA=7.5e4, Cd_n=2.4,
                            Ca_n=1.0)
    cat = solve_catenary([-80.0, 0.0, -30.0], [0.0, 0.0, -1.0], chain.weight, chain.EA,
                         length=100.0, seabed_z=-30.0)
    lines = skmoor.LineSet([skmoor.Line.from_catenary(cat, chain, 12)], law="engineering")
    bed = Seabed(30.0, stiffness=3e6 * chain.diameter, damping=3e5 * chain.diameter,
                 mu_axial=friction, mu_lateral=1.5 * friction)
    terms = [seabed_term(lines, bed), line_hydrodynamics(lines)]
    if surface:
        terms.append(SurfaceTerm(lines))
    system = skmoor.System(lines, fairleads="prescribed",
                           motion=lambda t: np.array([[0.0, 0.0, 2.0 * np.sin(0.6 * t)]]),
                           terms=terms)
    x0 = skmoor.solve_static(system).x
    handed_back = []
    if surface:  # count the steps the compiled step hands back
        fast = compiled_step.build(system, None, Scheme.generalized_alpha(0.5), TOL, 20)
        times = 0.05 * np.arange(1, 26)
        v = np.zeros(system.n)
        R, _, _ = system.residual(x0, v, 0.0, tangent=False)
        done, why = fast.steps(x0, v, v, R, times, 0.05)
        handed_back.append(why)
    # 25 steps: later on the slack chain's snaps amplify round-off (1e-12 m at step 30
    # grows to 1e-4 m by step 100 between any two runs that sum in another order)
    # (a handed-back step starts from Python's own kept factors: other iteration counts,
    # and other iterates within Newton's tolerance, TOL of a step's change, which the
    # snaps then amplify)
    assert_same_runs(system, x0, np.zeros(system.n), 0.05, 25,
                     scheme=Scheme.generalized_alpha(0.5), same_iterations=not surface,
                     rel=1e-8 if surface else 1e-9)
    if surface:  # the fairlead rises within half a diameter of the surface by t = 0.5 s
        assert handed_back[0] == compiled_step.TO_PYTHON and len(done) < 20


def test_bending_lines_on_rotating_bodies_step_as_the_python_newton():
    """The network of two buoys with every line given bending stiffness (Hermite lines,
    12 x 12 element blocks, slope DOFs at the body ends and at the free clump) and the
    lines' internal damping: the compiled Hermite kernel, its blocks' reduction to the
    bodies and its band assembly against the Python step (a bending block on the wrong
    DOFs, a dropped slope DOF or the damping's rate slopes left out would show)."""
    network = network_two_bodies()
    for line in network.lines:
        line.line_type = dataclasses.replace(line.line_type, EI=2e4)
    model = skmoor.from_network(network)
    system = model.system
    assert system.lines.hermite
    eq = skmoor.equilibrium(model)
    v0 = np.zeros(system.n)
    v0[system.nf:] = [0.2, -0.1, 0.05, 0.02, -0.03, 0.04, -0.1, 0.2, 0.0, -0.02, 0.01, 0.05]
    assert_same_runs(system, eq.x, v0, 0.02, 60)


@pytest.mark.parametrize("friction", [0.0, 0.6])
def test_a_bending_line_on_the_bed_steps_as_the_python_newton(friction):
    """A chain with bending stiffness (EI 1e5 N m2) from the bed to a heaved fairlead, on a
    sea bed with and without friction: the bed's blocks on the position DOFs of the 12 x
    12 element blocks (on the slope DOFs they would change the iterates at once)."""
    system, x0 = _chain_on_the_bed(lambda t: np.array([[0.0, 0.0, 2.0 * np.sin(0.6 * t)]]),
                                   EI=1e5, friction=friction, hydro=False)
    assert system.lines.hermite
    assert_same_runs(system, x0, np.zeros(system.n), 0.05, 25,
                     scheme=Scheme.generalized_alpha(0.5))


def chain_to_the_surface(sea, fairlead_z):
    """A chain from the bed (30 m) to a fixed fairlead at height ``fairlead_z`` (m) with
    drag, added mass and the dry part of the line (SurfaceTerm) in ``sea``: (system, its
    static state, the chain's diameter m)."""
    from skmoor.lines.catenary import solve_catenary
    from skmoor.sea.hydro import line_hydrodynamics
    from skmoor.sea.seabed import Seabed, seabed_term
    from skmoor.sea.surface import SurfaceTerm

    chain = skmoor.LineType(EA=7.5e8, mass=140.0, diameter=0.09, BA=7.5e4, Cd_n=2.4,
                            Ca_n=1.0)
    cat = solve_catenary([-80.0, 0.0, -30.0], [0.0, 0.0, fairlead_z], chain.weight, chain.EA,
                         length=100.0, seabed_z=-30.0)
    lines = skmoor.LineSet([skmoor.Line.from_catenary(cat, chain, 12)], law="engineering")
    bed = Seabed(30.0, stiffness=3e6 * chain.diameter, damping=3e5 * chain.diameter)
    system = skmoor.System(lines, fairleads="prescribed", motion=lambda t: np.zeros((1, 3)),
                           terms=[seabed_term(lines, bed), line_hydrodynamics(lines, sea),
                                  SurfaceTerm(lines, sea)])
    return system, skmoor.solve_static(system).x, chain.diameter


def steps_before_handing_back(system, x0, times, dt):
    """How many of the steps to ``times`` the compiled step takes from rest at x0 before
    it hands one to the Python step (None: it hands none back)."""
    fast = compiled_step.build(system, None, Scheme.generalized_alpha(0.5), TOL, 20)
    assert fast is not None, compiled_step.last_refusal
    v = np.zeros(system.n)
    R, _, _ = system.residual(x0, v, 0.0, tangent=False)
    done, why = fast.steps(x0, v, v, R, times, dt)
    return len(done) if why == compiled_step.TO_PYTHON else None


def test_a_line_under_a_wavy_surface_is_handed_back_where_the_waves_reach_it():
    """A chain from the bed to a fixed fairlead 1 m under the still surface, with the
    dry part of the line (SurfaceTerm) under a regular wave (1.2 m amplitude, 4 s): the
    compiled step takes it and hands the step back to Python where the wave's trough first
    comes within half a diameter of the fairlead (the highest node): at the first step
    time t with -1 - eta(0, 0, t) > -d / 2 by Sea.elevation. Still water (or the
    elevation's sign flipped, or taken at the step's start) would hand back no step there.
    The run through the handed-back steps is the Python step's."""
    from skmoor.sea.waves import AiryWave, Sea

    dt, steps = 0.05, 50
    times = dt * np.arange(1, steps + 1)
    handed_back = {}
    for name, sea in (("waves", Sea(30.0, waves=[AiryWave(2.4, 4.0, depth=30.0)])),
                      ("still", Sea(30.0))):
        system, x0, diameter = chain_to_the_surface(sea, -1.0)
        handed_back[name] = steps_before_handing_back(system, x0, times, dt)
        if name == "waves":
            assert_same_runs(system, x0, np.zeros(system.n), dt, steps,
                             scheme=Scheme.generalized_alpha(0.5), same_iterations=False,
                             rel=1e-8)
            eta = sea.elevation(np.zeros((steps, 2)), times)
            expected = int(np.argmax(-1.0 - eta > -0.5 * diameter))
    assert handed_back["still"] is None
    assert 10 < expected == handed_back["waves"]


@pytest.mark.parametrize("maxiter", [4, 3])
def test_steps_modified_newton_gives_up_on_go_as_in_python(maxiter):
    """With few iterations allowed, modified Newton gives up on some steps: the compiled
    step then runs Newton with the line search as the Python step does (maxiter 4),
    and a step that fails that too is split in halves in Python (maxiter 3): the run
    reaches its end, step by step as the pure Python run."""
    model = skmoor.build(skmoor.paper_case())
    eq = skmoor.equilibrium(model)
    system, n = model.system, model.system.n
    states = []
    for compiled in (True, False):
        xs, subdivided = [], 0
        for state in integrate(system, eq.x, np.zeros(n), 0.1, 4.0, C=eq.C, tol=1e-8,
                               scheme=Scheme.generalized_alpha(0.8), maxiter=maxiter,
                               compiled=compiled):
            xs.append(state.x.copy())
            subdivided = state.subdivided
        states.append((np.array(xs), subdivided))
    (fast, split_fast), (slow, split_slow) = states
    assert len(fast) == len(slow) == 41 and split_fast == split_slow
    assert (split_slow > 0) == (maxiter == 3)
    assert np.abs(fast - slow).max() < 1e-9 * np.abs(slow - slow[0]).max()


def test_what_the_compiled_step_leaves_to_python_is_named():
    """Physics it does not cover makes build() return None with the reason: a body load
    of the state in NumPy (JAX cannot trace it); the same load in plain arithmetic
    traces, and builds."""
    model = skmoor.build(skmoor.paper_case())
    system = model.system
    given = system.body_loads[0]
    system.body_loads[0] = lambda t, q, qdot: -1e3 * np.asarray(qdot)  # NumPy, of the state
    assert compiled_step.build(system, None, Scheme.newmark(), 1e-5, 20) is None
    assert "state" in compiled_step.last_refusal
    assert "does not trace with JAX" in compiled_step.last_refusal
    system.body_loads[0] = lambda t, q, qdot: -1e3 * qdot
    assert compiled_step.build(system, None, Scheme.newmark(), 1e-5, 20) is not None
    system.body_loads[0] = given
    assert compiled_step.build(system, None, Scheme.newmark(), 1e-5, 20) is not None


def bumpy_bed():
    """A Bathymetry under the chain of :func:`_chain_on_the_bed`: z = -30 m at its anchor,
    rising 3 % along x and 1 % along y, a 0.8 m ridge across x = -63 m."""
    from skmoor.sea.seabed import Bathymetry

    x, y = np.array([-120.0, -63.0, -20.0, 20.0]), np.array([-30.0, 0.0, 30.0])
    X, Y = np.meshgrid(x, y, indexing="ij")
    return Bathymetry(x, y, -30.0 + 0.03 * (X + 80.0) + 0.01 * Y + 0.8 * (X == -63.0))


def _chain_on_the_bed(motion, EI=0.0, friction=0.0, hydro=True, bathymetry=None):
    """A 12-element chain on a sea bed (friction: its axial coefficient, 1.5 times that
    laterally; a ``bathymetry``, or flat at 30 m) with drag and added mass (``hydro``),
    its fairlead moved by ``motion``, and its static state; EI > 0 (N m2): on bending
    (Hermite) elements."""
    from skmoor.lines.catenary import solve_catenary
    from skmoor.sea.hydro import line_hydrodynamics
    from skmoor.sea.seabed import Seabed, seabed_term

    chain = skmoor.LineType(EA=7.5e8, mass=140.0, diameter=0.09, BA=7.5e4, Cd_n=2.4,
                            Ca_n=1.0, EI=EI)
    cat = solve_catenary([-80.0, 0.0, -30.0], [0.0, 0.0, -1.0], chain.weight, chain.EA,
                         length=100.0, seabed_z=-30.0)
    lines = skmoor.LineSet([skmoor.Line.from_catenary(cat, chain, 12)], law="engineering")
    bed = Seabed(30.0, stiffness=3e6 * chain.diameter, damping=3e5 * chain.diameter,
                 mu_axial=friction, mu_lateral=1.5 * friction, bathymetry=bathymetry)
    terms = [seabed_term(lines, bed)] + ([line_hydrodynamics(lines)] if hydro else [])
    system = skmoor.System(lines, fairleads="prescribed", motion=motion, terms=terms)
    return system, skmoor.solve_static(system).x


@pytest.mark.parametrize("which", ["bodies", "chain", "bending chain", "chain on a bathymetry"])
@pytest.mark.parametrize("compiled", [True, False])
def test_reported_end_forces_and_line_state_are_the_systems(which, compiled):
    """States integrate reports (report_every) carry the lines' full state and end forces
    as System.full_state and System.reactions (with the held ends' inertia at the state's
    accelerations) compute them at that state, from the
    compiled step and from the Python one: a report taken at the step's alpha level, a
    sign, the anchor and fairlead swapped or a velocity left out (the drag, the lines' BA)
    would differ by far more than round-off. Other steps carry none."""
    if which == "bodies":
        model = skmoor.from_network(network_two_bodies())
        system, x0 = model.system, skmoor.equilibrium(model).x
    else:
        system, x0 = _chain_on_the_bed(lambda t: np.array([[0.0, 0.0, 2.0 * np.sin(0.6 * t)]]),
                                       EI=1e5 if which == "bending chain" else 0.0,
                                       hydro=which != "bending chain",
                                       bathymetry=bumpy_bed() if "bathymetry" in which
                                       else None)
    v0 = np.zeros(system.n)
    v0[system.nf:] = 0.1  # the bodies start moving
    reported = 0
    for state in integrate(system, x0, v0, 0.05, 1.5, scheme=Scheme.generalized_alpha(0.8),
                           tol=TOL, compiled=compiled, report_every=3):
        if state.step % 3:
            assert state.reactions is None and state.full_state is None
            continue
        reported += 1
        u, ud = system.full_state(state.x, state.v, state.t)
        fair, anchor = system.reactions(state.x, state.v, state.t, state.a)
        for got, expected in zip((*state.full_state, *state.reactions), (u, ud, fair, anchor)):
            assert np.abs(got - expected).max() <= 1e-9 * np.abs(expected).max()
        assert np.abs(ud).max() > 1e-3  # the lines do move
    assert reported == 11  # steps 0, 3, ..., 30


@pytest.mark.parametrize("diagonal", ["small", "moderate", "dominant"])
def test_bordered_band_solves_as_lapack(diagonal):
    """The bordered band LU (threshold pivoting in the band, Schur complement on the
    border) solves a random bordered system as numpy's LAPACK solve does: with rows
    swapped where a diagonal entry is below PIVOT_THRESHOLD of its column's largest (U
    then has fill-in above its w superdiagonals, which the back substitution must reach),
    and without where it is not, even when smaller than other entries of its column
    (partial pivoting would swap there)."""
    rng = np.random.default_rng(3)
    nf, nb, w = 40, 6, 4
    A = np.zeros((nf + nb, nf + nb))
    for i in range(nf):
        for j in range(max(0, i - w), min(nf, i + w + 1)):
            A[i, j] = rng.standard_normal()
        A[i, i] = {"small": 1e-4 * A[i, i],  # below the threshold: swapped
                   "moderate": 0.3 * np.sign(A[i, i]) + 0.05 * A[i, i],
                   "dominant": A[i, i] + 4.0 * (2 * w + 1)}[diagonal]
    dominant = diagonal != "small"
    if diagonal == "moderate":  # the columns' largest entries are off the diagonal
        assert np.mean(np.abs(np.diag(A)[:nf]) < np.abs(A[:nf, :nf]).max(axis=0)) > 0.5
    A[:nf, nf:] = rng.standard_normal((nf, nb)) * (rng.random((nf, nb)) < 0.3)
    A[nf:, :nf] = rng.standard_normal((nb, nf)) * (rng.random((nb, nf)) < 0.3)
    A[nf:, nf:] = rng.standard_normal((nb, nb))
    ab, E, F, D = bordered.split(A, nf, w)
    out = np.empty(nf + nb)
    x = rng.standard_normal(nf + nb)
    bordered.matvec(ab, w, E, F, D, x, out)
    assert np.allclose(out, A @ x, rtol=0, atol=1e-12 * np.abs(A @ x).max())
    piv_band, piv_schur = np.zeros(nf + 1, np.int64), np.zeros(nb, np.int64)
    assert bordered.factor(ab, w, E, F, D, piv_band, piv_schur)
    swapped = np.any(piv_band[:nf] != np.arange(nf))
    assert swapped != dominant and (piv_band[nf] > w) == swapped
    b = rng.standard_normal(nf + nb)
    y = b.copy()
    bordered.solve(ab, w, E, F, D, piv_band, piv_schur, y)
    expected = np.linalg.solve(A, b)
    assert np.abs(y - expected).max() < 1e-10 * np.abs(expected).max()
    with pytest.raises(ValueError, match="wider than the band"):
        bordered.split(A + np.eye(nf + nb, k=w + 1), nf, w)


def test_the_compiled_step_names_the_first_term_that_does_not_lower():
    """Every term answers lowered(): the paper case's own physics (cable, restoring, the
    time-only load) all lower; a user's body load in NumPy (JAX cannot trace it) does not,
    and the refusal names it and says why."""
    model = skmoor.build(skmoor.paper_case())
    system = model.system
    kinds = sorted(term.lowered() for term in system.built_in_terms)
    assert kinds == ["body restoring", "cable", "time load"]
    assert compiled_step.build(system, None, Scheme.newmark(), 1e-5, 20) is not None
    body_load = skmoor.BodyLoad(lambda q, qdot, t: -1e3 * np.asarray(qdot), body=0)
    model.add(body_load)
    assert compiled_step.build(system, None, Scheme.newmark(), 1e-5, 20) is None
    assert compiled_step.last_refusal.startswith("BodyLoad on the bodies")
    assert body_load.why_python in compiled_step.last_refusal


SHEAR = [(-30.0, 0.3), (-10.0, 1.0), (0.0, 1.2)]


@pytest.mark.parametrize("profile, EI", [(None, 0.0), (SHEAR, 0.0), (SHEAR, 1e5)])
def test_a_chain_in_a_steady_current_steps_as_the_python_newton(profile, EI):
    """The chain on the bed with drag in a steady current (uniform 0.8 m/s, or sheared from
    0.3 m/s at the bed to 1.2 m/s at the surface) heading 30 deg across the line, on P1
    and on bending (Hermite, EI 1e5 N m2) elements: the compiled step takes it (the water
    at the displaced nodes, as Current.velocity) and steps as the Python Newton; the
    current moves the chain away from its still-water run by centimetres (so a compiled
    step that dropped it, or read the water at the reference nodes, would differ)."""
    from skmoor.sea.hydro import line_hydrodynamics
    from skmoor.sea.waves import Current, Sea

    current = (Current(speed=0.8, heading_deg=30.0) if profile is None
               else Current(profile=profile, heading_deg=30.0))
    motion = lambda t: np.array([[0.0, 0.0, 2.0 * np.sin(0.6 * t)]])  # noqa: E731
    still, x0 = _chain_on_the_bed(motion, EI=EI)
    system, _ = _chain_on_the_bed(motion, EI=EI, hydro=False)
    system = skmoor.System(system.lines, fairleads="prescribed", motion=motion,
                           terms=[*system.terms,
                                  line_hydrodynamics(system.lines, Sea(30.0, current=current))])
    assert system.lines.hermite == (EI > 0)
    assert compiled_step.build(system, None, Scheme.generalized_alpha(0.5), TOL, 20) \
        is not None, compiled_step.last_refusal
    assert_same_runs(system, x0, np.zeros(system.n), 0.05, 25,
                     scheme=Scheme.generalized_alpha(0.5))
    flowing, _ = run(system, x0, np.zeros(system.n), 0.05, 25,
                     scheme=Scheme.generalized_alpha(0.5))
    calm, _ = run(still, x0, np.zeros(still.n), 0.05, 25, scheme=Scheme.generalized_alpha(0.5))
    assert np.abs(flowing[-1] - calm[-1]).max() > 1e-2


@pytest.mark.parametrize("EI", [0.0, 1e5])
def test_a_chain_in_waves_and_a_current_steps_as_the_python_newton(EI):
    """The chain with drag and fluid inertia under a JONSWAP sea (30 components, across
    the line at 60 deg) and a sheared current, on P1 and on bending elements: the
    compiled step takes it (the Airy components' velocity and acceleration at the
    displaced nodes at each residual's time, as Sea.kinematics) and steps as the Python
    Newton. Without the waves' acceleration (the fluid inertia), with the kinematics at
    the reference nodes or at the step's start time, the runs would part: the waves move
    the chain by decimetres from its run in the current alone."""
    from skmoor.sea.waves import Current, JonswapWave, Sea

    current = Current(profile=SHEAR, heading_deg=30.0)
    waves = JonswapWave(3.0, 9.0, depth=30.0, heading_deg=60.0, n_components=30, seed=3)
    runs = runs_of_variants(chains_in_seas({"waves": Sea(30.0, current=current, waves=[waves]),
                                            "current": Sea(30.0, current=current)}, EI))
    assert np.abs(runs["waves"] - runs["current"]).max() > 0.1


def chains_in_seas(seas, EI):
    """{name: (system, x0)}: the chain on the bed heaved 1 m at 0.6 rad/s with drag and
    fluid inertia in each of the ``seas`` ({name: Sea}), on bending elements with EI > 0."""
    from skmoor.sea.hydro import line_hydrodynamics

    motion = lambda t: np.array([[0.0, 0.0, 1.0 * np.sin(0.6 * t)]])  # noqa: E731
    variants = {}
    for name, sea in seas.items():
        base, x0 = _chain_on_the_bed(motion, EI=EI, hydro=False)
        variants[name] = (skmoor.System(base.lines, fairleads="prescribed", motion=motion,
                                        terms=[*base.terms, line_hydrodynamics(base.lines, sea)]),
                          x0)
    return variants
