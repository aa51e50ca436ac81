"""The VIV lift (skmoor.sea.viv, MoorDyn's cross-flow model with Thorsen's synchronization)
against its closed forms: the lift per length, the phase rate, the phase of a harmonic
motion, and the nodal loads and phase update of the term on a straight line in a current.
"""
import sys
from pathlib import Path

import numpy as np
import pytest
from skfem import LinearForm

import skmoor
from skmoor.fem import ops
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.sea import viv
from skmoor.sea.viv import (
    VortexLift,
    VortexLiftForm,
    lift_per_length,
    motion_phase,
    phase_rate,
    vortex_lift,
    vortex_lift_term,
    vortex_lift_update,
)
from skmoor.sea.waves import Current, Sea
from skmoor.solvers import compiled_step, dynamics

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import moordyn_decks as md  # noqa: E402

try:
    MIRROR, NO_MIRROR = md.Mirror(md.mirror_path()), ""
except md.MirrorMissing as err:
    MIRROR, NO_MIRROR = None, str(err)
needs_mirror = pytest.mark.skipif(MIRROR is None, reason=NO_MIRROR)

RHO, D, CL, U = 1000.0, 0.024, 0.7, 0.2


def test_lift_per_length_is_half_rho_d_cl_u_squared_across_the_flow():
    """A vertical line in a flow along x: the lift is along z x x = +y, of size 1/2 rho d Cl
    U^2 cos(phi) (a swapped cross product flips it, |v| v in place of |v| (q x v) or a lost
    1/2 scales it)."""
    q, flow = np.array([[0.0, 0.0, 1.0]] * 3), np.array([[U, 0.0, 0.0]] * 3)
    phase = np.array([0.0, np.pi / 3, np.pi])
    force = lift_per_length(RHO, D, CL, flow, q, phase)
    size = 0.5 * RHO * D * CL * U**2 * np.cos(phase)
    assert force == pytest.approx(np.c_[np.zeros(3), size, np.zeros(3)], abs=1e-12)
    # the lift turns with the flow: a flow along y lifts along z x y = -x
    turned = lift_per_length(RHO, D, CL, np.array([[0.0, U, 0.0]]), q[:1], np.zeros(1))
    assert turned[0] == pytest.approx([-0.5 * RHO * D * CL * U**2, 0.0, 0.0])


def test_phase_rate_spans_the_synchronization_range():
    """In step with the motion the lift runs at the Strouhal rate 2 pi cF U / d; a quarter
    period behind (phi_y - phi = pi/2) at 2 pi (cF + dF) U / d, ahead at (cF - dF)."""
    cF, dF = 0.18, 0.08
    rate = phase_rate(np.array([1.0, 1.0, 1.0]), np.array([1.0, 1.0 + np.pi / 2, 1.0 - np.pi / 2]),
                      U, D, cF, dF)
    assert rate == pytest.approx(2 * np.pi * np.array([cF, cF + dF, cF - dF]) * U / D)


def test_motion_phase_of_a_harmonic_motion_is_its_argument():
    """y = A sin(w t): yd = A w cos, ydd = -A w^2 sin, rms A w / sqrt 2 and A w^2 / sqrt 2,
    so phi_y = w t (mod 2 pi) for any amplitude and frequency (a sign error on ydd gives
    -w t, the rms normalization missing gives the wrong angle for w != 1)."""
    A, w = 0.03, 6.5
    t = np.linspace(0.05, 2.0, 9)
    yd, ydd = A * w * np.cos(w * t), -A * w**2 * np.sin(w * t)
    phase = motion_phase(yd, ydd, np.full(t.size, A * w / np.sqrt(2)),
                         np.full(t.size, A * w**2 / np.sqrt(2)))
    assert phase == pytest.approx(np.mod(w * t, 2 * np.pi), abs=1e-12)


def vertical_line(n=4, stretch=1.0):
    """A straight vertical line from z = -10 to -2 m on n elements, its reference state
    stretched by ``stretch`` (8 m / stretch unstretched)."""
    line_type = LineType(EA=1e5, mass=0.69, diameter=D, rho_water=RHO, Cl=CL)
    points = np.c_[np.zeros(n + 1), np.zeros(n + 1), np.linspace(-10.0, -2.0, n + 1)]
    line = Line.from_polyline(points, line_type)
    line.stretch = lambda s: np.full(np.shape(s), stretch)
    return LineSet([line])


def test_nodal_lift_on_a_line_in_a_current_and_its_phase_update():
    """At rest in a uniform current U along x: no lift before the first commit (statics);
    then internal node i (of n) carries 1/2 rho d Cl U^2 cos(2 pi i / n) times its
    unstretched length (8 m / n / stretch) along +y, the end nodes none. After a step h
    at rest (yd = ydd = 0, phi_y = 0) the phase is 2 pi i / n + 2 pi (cF - dF sin phi) U / d h."""
    n, stretch = 4, 1.1
    lines = vertical_line(n, stretch)
    sea = Sea(depth=50.0, rho=RHO, current=Current(speed=U))
    term = VortexLift(lines, sea)
    u, v = np.zeros(lines.ndofs), np.zeros(lines.ndofs)
    R = np.zeros(lines.ndofs)
    term.add_to(u, v, 0.0, R)
    assert not R.any()

    term.commit(0.0, u, v)
    phase0 = 2 * np.pi * np.arange(1, n) / n
    length = 8.0 / n / stretch
    expected = np.zeros((n + 1, 3))
    expected[1:n, 1] = 0.5 * RHO * D * CL * U**2 * np.cos(phase0) * length
    R = np.zeros(lines.ndofs)
    term.add_to(u, v, 0.0, R)
    assert -R[lines.nodal_dofs] == pytest.approx(expected, abs=1e-12)

    h = 0.01
    rate = 2 * np.pi * (0.18 - 0.08 * np.sin(phase0)) * U / D
    R = np.zeros(lines.ndofs)
    term.add_to(u, v, h, R)  # within the step: the phase extrapolated to t = h
    phase1 = phase0 + rate * h
    assert -R[lines.nodal_dofs[1:n, 1]] == pytest.approx(
        0.5 * RHO * D * CL * U**2 * np.cos(phase1) * length, rel=1e-10)
    term.commit(h, u, v)
    assert term._phase == pytest.approx(np.mod(phase1, 2 * np.pi), abs=1e-12)


def test_dry_nodes_carry_no_lift():
    """A line lifted 20 m (above the still surface): its nodes are dry, no lift."""
    lines = vertical_line()
    term = VortexLift(lines, Sea(depth=50.0, rho=RHO, current=Current(speed=U)))
    u = np.zeros(lines.ndofs)
    u[lines.nodal_dofs[:, 2]] = 20.0
    v = np.zeros(lines.ndofs)
    term.commit(0.0, u, v)
    R = np.zeros(lines.ndofs)
    term.add_to(u, v, 0.0, R)
    assert not R.any()


def test_bad_lift_coefficient_is_refused():
    with pytest.raises(ValueError, match="LineType.Cl"):
        LineType(EA=1e5, mass=0.69, diameter=D, Cl=-0.1)


def deck_copy(folder, path, *extra):
    """MoorDyn's deck ``path`` (and the files ``extra`` of its folder) copied to folder."""
    for name in (path,) + extra:
        out = folder / Path(name).name
        out.write_bytes(MIRROR.read(str(Path(path).parent / Path(name).name)))
    return folder / Path(path).name


@needs_mirror
@pytest.mark.filterwarnings("ignore")
def test_rotating_body_deck_reads_its_lift_column_and_runs(tmp_path):
    """rotatingBody.txt's eleventh line-type column is Cl = 0.05 alone: dF and cF take
    MoorDyn's documented defaults 0.08 and 0.18 (docs/inputs.rst), the running mean
    squares its 500 steps of dtM = 0.5 ms, and the deck runs."""
    from skmoor.run.simulate import simulate

    model = skmoor.build(deck_copy(tmp_path, "tests/Mooring/body_tests/rotatingBody.txt"),
                         rotations="exact")
    types = {(ln.line_type.Cl, ln.line_type.viv_dF, ln.line_type.viv_cF)
             for ln in model.network.lines}
    assert types == {(0.05, 0.08, 0.18)}
    lift = next(t for t in model.system.line_terms if isinstance(t, VortexLift))
    assert lift.rms_time == pytest.approx(500 * 5e-4)  # MoorDyn's 500 steps of its dtM
    results = simulate(model, duration=0.2, dt=0.01, progress=False, start="given")
    assert results.t[-1] == pytest.approx(0.2) and np.isfinite(results.displacement).all()


def lock_in_case(zeta, dF=0.08, cF=0.18, bottom=-10.0, waves=(), fields=(), form_path="auto",
                 viv_lift=None):
    """A weightless taut string of two elements (8 m, vertical, from z = ``bottom``) in a
    current U along x (and ``waves``, ``fields``): its middle node a cross-flow oscillator tuned to
    f_n = (cF + dF / 2) U / d with damping ratio ``zeta`` from the current's drag,
    ½ rho d Cd U per length across the flow (skmoor integrates the drag at Gauss points:
    the middle node takes 2/3 of the lumped share, int N^2 = 2 h / 3), lift lumped at the
    node, its running mean squares over two periods (a clean rms of a harmonic motion);
    form_path 'auto' the lift's hand kernels, else its forms; viv_lift: what makes the
    lift (Network.viv_lift). (model, f_n, m, h)."""
    from skmoor.coupling.network import MooringLine, Network, Point
    from skmoor.model.model import from_network

    Cd, L = 1.2, 8.0
    f_n = (cF + 0.5 * dF) * U / D
    w_n, h = 2 * np.pi * f_n, L / 2
    damping = 0.5 * RHO * D * Cd * U * (2 / 3)  # N s/m2 on the node's length h
    m = damping / (2 * zeta * w_n)  # kg/m, lumped m h on the node
    T = m * h**2 * w_n**2 / 2  # the node's stiffness 2 T / h = m h w_n^2
    EA = 1e3 * T
    line_type = LineType(EA=EA, mass=m, diameter=D, Cd_n=Cd, rho_water=RHO, g=0.0,
                         Cl=0.05, viv_dF=dF, viv_cF=cF)
    sea = Sea(depth=50.0, rho=RHO, current=Current(speed=U), waves=list(waves),
              fields=list(fields))
    network = Network([Point("A", "fixed", [0.0, 0.0, bottom]),
                       Point("B", "fixed", [0.0, 0.0, bottom + L])],
                      [MooringLine("string", line_type, "A", "B", L / (1 + T / EA), 2)],
                      depth=50.0, rho=RHO, sea=sea, viv_rms_time=2 / f_n,
                      form_path=form_path, viv_lift=viv_lift)
    return from_network(network), f_n, m, h


def locked_response(zeta, duration=6.0, since=4.0):
    """Run the lock-in case from its static state: the cross-flow motion's frequency (Hz)
    and amplitude (m) over t > since, and the mean of the lift's phase lag behind the
    motion, phi_y - phi (rad, the motion's phase from a sine fitted to it)."""
    model, f_n, m, h = lock_in_case(zeta)
    lift = next(t for t in model.system.line_terms if isinstance(t, VortexLift))
    phases, commit, steps = [], lift.commit, compiled_step.CompiledStep.steps

    def recording_commit(t, u, v):  # a Python step's
        commit(t, u, v)
        phases.append((t, lift._phase[0]))

    def recording_steps(self, x, v, a, force, times, h, **kw):  # a compiled step's
        done = steps(self, x, v, a, force, times, h, **kw)
        if done[0]:
            phases.append((times[0], lift._phase[0]))
        return done

    lift.commit = recording_commit
    dt = 1 / (50 * f_n)
    with pytest.MonkeyPatch.context() as patch:  # one step per call: its phase after it
        patch.setattr(dynamics, "COMPILED_BATCH", 1)
        patch.setattr(compiled_step.CompiledStep, "steps", recording_steps)
        results = skmoor.simulate(model, duration=duration, dt=dt, output_interval=dt,
                                  progress=False)
    t, y = results.t, results.displacement[:, 1, 1]
    late = t > since
    t, y = t[late], y[late] - y[late].mean()
    up = np.nonzero((y[:-1] < 0) & (y[1:] >= 0))[0]
    crossings = t[up] - y[up] * (t[up + 1] - t[up]) / (y[up + 1] - y[up])
    if len(crossings) < 3:  # no oscillation to speak of
        return 0.0, 0.5 * np.ptp(y), np.nan, (f_n, m, h)
    f = (len(crossings) - 1) / (crossings[-1] - crossings[0])
    w = 2 * np.pi * f
    (a, b), *_ = np.linalg.lstsq(np.c_[np.sin(w * t), np.cos(w * t)], y, rcond=None)
    tp, phase = np.array(phases).T
    late = tp > since
    lag = np.mod(w * tp[late] + np.arctan2(b, a) - phase[late] + np.pi, 2 * np.pi) - np.pi
    return f, np.hypot(a, b), lag.mean(), (f_n, m, h)


def test_lift_locks_a_cross_flow_oscillator_at_the_closed_form_frequency():
    """Thorsen's synchronization on a linear oscillator (natural frequency f_n, damping
    ratio zeta, forced by F cos(phi)): in lock-in the motion and the lift run at one
    frequency f = r f_n with the lift a phase psi = pi/2 - lag(r) behind the motion
    (lag = atan2(2 zeta r, 1 - r^2), the oscillator's), and the phase rate gives
    r f_n d / U = cF + dF sin(psi) = cF + dF cos(lag(r)); the amplitude is the static
    deflection F / k over sqrt((1 - r^2)^2 + (2 zeta r)^2). Tuned to f_n = (cF + dF/2) U / d
    with zeta = 0.15: f = 0.945 f_n, psi = 0.358 rad, amplitude 0.045 d. Measured within
    0.2 %, 0.01 rad and 0.5 %; dF's sign flipped or the lift's turned, the motion dies
    out (amplitude < 0.02 d, no lock); the rate halved: 1.07 Hz for 1.73; the
    acceleration's sign flipped in the motion's phase: 1.45 Hz."""
    from scipy.optimize import brentq

    zeta, cF, dF, Cl = 0.15, 0.18, 0.08, 0.05
    f, amplitude, psi, (f_n, m, h) = locked_response(zeta)

    def lag(r):
        return np.arctan2(2 * zeta * r, 1 - r * r)

    r = brentq(lambda r: r * f_n * D / U - cF - dF * np.cos(lag(r)), 0.5, 1.5)
    static = 0.5 * RHO * D * Cl * U**2 / (m * (2 * np.pi * f_n) ** 2)  # F / k, m
    assert f == pytest.approx(r * f_n, rel=5e-3)
    assert psi == pytest.approx(np.pi / 2 - lag(r), abs=0.03)
    assert amplitude == pytest.approx(static / np.hypot(1 - r * r, 2 * zeta * r), rel=0.03)


def test_the_compiled_step_advances_the_lift_as_the_python_step():
    """The lock-in case's first 300 steps in the compiled step (the lift by address, its
    phases advanced by its compiled commit) and in the Python step: the same motion to
    round-off and the same phases, rates and mean squares; the lift moves the string
    (without it the motion differs by far more)."""
    def run(compiled, lift_on=True):
        model, f_n, _, _ = lock_in_case(0.15)
        system = model.system
        lift = next(t for t in system.line_terms if isinstance(t, VortexLift))
        eq = skmoor.equilibrium(model)
        if not lift_on:
            lift.Cl = np.zeros_like(lift.Cl)
        assert compiled_step.lowered_terms(system)[0] is None
        dt = 1 / (50 * f_n)
        states = [s.x.copy() for s in dynamics.integrate(
            system, eq.x, np.zeros(system.n), dt, 300 * dt, C=eq.C, compiled=compiled,
            tol=1e-10)]
        return np.array(states), lift._state.copy()

    fast, state_fast = run(True)
    slow, state_slow = run(False)
    motion = np.abs(slow - slow[0]).max()
    assert np.abs(fast - slow).max() < 1e-9 * motion
    assert state_fast == pytest.approx(state_slow, rel=1e-9, abs=1e-12)
    unlifted, _ = run(True, lift_on=False)
    assert np.abs(unlifted - slow).max() > 0.1 * motion


def test_the_compiled_kernels_evaluate_the_waves_as_the_sea():
    """The compiled step's wave kinematics and elevation (skmoor.sea.hydro) at scattered
    points and times equal Sea.kinematics and Sea.elevation of a JONSWAP sea plus a regular
    wave on another heading: a phase sign, a heading's component or a depth factor off
    would part them."""
    from skmoor.sea.hydro import wave_components, wave_elevation, wave_kinematics
    from skmoor.sea.waves import AiryWave, JonswapWave

    waves = [JonswapWave(4.0, 10.0, depth=80.0, heading_deg=25.0, n_components=15, seed=2),
             AiryWave(2.0, 7.0, depth=80.0, heading_deg=-70.0, phase=0.4)]
    sea = Sea(80.0, waves=waves)
    components = wave_components(waves)
    rng = np.random.default_rng(5)
    points = rng.uniform([-200.0, -200.0, -80.0], [200.0, 200.0, 0.0], (40, 3))
    times = rng.uniform(0.0, 300.0, 40)
    for point, t in zip(points, times):
        velocity, acceleration = sea.kinematics(point, t)
        out = np.zeros(6)
        wave_kinematics(*point, t, components, out)
        scale = np.abs(velocity).max() + np.abs(acceleration).max()
        np.testing.assert_allclose(out, np.concatenate([velocity, acceleration]), rtol=0,
                                   atol=1e-12 * scale)
        assert wave_elevation(point[0], point[1], t, components, np.zeros(1)) == pytest.approx(
            float(sea.elevation(point, t)), rel=1e-12, abs=1e-12)


def raised_lock_in_run(compiled, waves=(), fields=(), form_path="auto"):
    """The lock-in string raised to 1 m under the still surface (in ``waves`` and
    ``fields``), 300 steps from its equilibrium, compiled or not (its lift's hand kernels
    or with ``form_path`` its forms): (states, the lift's state at the end, the lift)."""
    model, f_n, _, _ = lock_in_case(0.15, bottom=-5.0, waves=waves, fields=fields,
                                    form_path=form_path)
    system = model.system
    lift = next(t for t in system.line_terms if isinstance(t, (VortexLift, VortexLiftForm)))
    eq = skmoor.equilibrium(model)
    assert compiled_step.lowered_terms(system)[0] is None
    dt = 1 / (50 * f_n)
    states = [s.x.copy() for s in dynamics.integrate(
        system, eq.x, np.zeros(system.n), dt, 300 * dt, C=eq.C, compiled=compiled, tol=1e-10)]
    memory = lift._state if isinstance(lift, VortexLift) else lift.state_values()["phase"]
    return np.array(states), memory.copy(), lift


def test_the_compiled_step_advances_the_lift_in_waves_as_the_python_step():
    """The lock-in string raised so that its middle node stands 1 m under the still
    surface, under a regular wave of 3 m (1.5 m amplitude: the node falls dry in the
    troughs) across the current: the compiled step (the waves' velocity and elevation at
    the displaced node at each residual's time) steps as the Python step, and its lift
    state ends the same. The waves change the motion by far more than the tolerance (a
    wet fraction on z + eta, or the waves' velocity left out, would part the runs)."""
    from skmoor.sea.waves import AiryWave

    waves = [AiryWave(3.0, 8.0, depth=50.0, heading_deg=60.0, phase=-1.0)]
    fast, state_fast, lift = raised_lock_in_run(True, waves=waves)
    slow, state_slow, _ = raised_lock_in_run(False, waves=waves)
    motion = np.abs(slow - slow[0]).max()
    assert np.abs(fast - slow).max() < 1e-9 * motion
    # the state's small entries carry the round-off of its large ones
    assert state_fast == pytest.approx(state_slow, rel=1e-9,
                                       abs=1e-9 * np.abs(state_slow).max())
    times = np.linspace(0.0, 300 / (50 * (0.18 + 0.04) * U / D), 200)
    assert lift.sea.elevation(np.zeros((200, 2)), times).min() < -1.0 - D  # dry there
    calm, _, _ = raised_lock_in_run(True)
    assert np.abs(calm - slow).max() > 0.1 * motion


def chain_with_lift(EI=0.0, dF=0.1):
    """A 10-element catenary chain (bending stiffness EI) with Cl = 0.8 (and dF) hung to
    0.5 m under the still surface in a sheared current and a 3 m Airy wave across it:
    (lines, sea)."""
    from skmoor.lines.catenary import solve_catenary
    from skmoor.sea.waves import AiryWave

    sea = Sea(150.0, current=Current(profile=[(-150.0, 0.1), (0.0, 0.8)], heading_deg=30.0),
              waves=[AiryWave(3.0, 9.0, 150.0, heading_deg=-20.0)])
    chain = LineType(EA=7.5e8, mass=140.0, diameter=0.09, Cl=0.8, viv_cF=0.2, viv_dF=dF,
                     EI=EI)
    catenary = solve_catenary([-300.0, 0.0, -150.0], [0.0, 0.0, -0.5], chain.weight, chain.EA,
                              length=336.0)
    return LineSet([Line.from_catenary(catenary, chain, 10)]), sea


@pytest.mark.parametrize("EI, path", [(0.0, "compiled"), (0.0, "fd"), (2e5, "compiled")])
def test_the_lift_form_is_the_hand_kernel_at_every_node(EI, path):
    """The lift written as forms (VortexLiftForm: vortex_lift and its memory's update on
    nodal quadrature) against the hand kernels (VortexLift), node by node, on a chain in
    waves whose top nodes go in and out of the water, at random states: the loads (with
    the phases extrapolated within a step), the phases, rates and mean squares after
    commits along a run, a second commit at the same time (kept), and a new run (a time
    before the last: started again). A lift on the element's tangent (not the node's
    chord), a wet fraction of the reference z or the acceleration's sign flipped in the
    update each parts them (tried)."""
    lines, sea = chain_with_lift(EI)
    hand = VortexLift(lines, sea, rms_time=1.5)
    form = vortex_lift_term(lines, sea, rms_time=1.5, path=path)
    assert isinstance(form, VortexLiftForm) and isinstance(vortex_lift_term(lines, sea),
                                                            VortexLift)
    # the form's points at each hand node: its element's end there
    point = {node: (e, j) for j in range(2) for e, node in enumerate(lines.mesh.t[j])}
    at_nodes = tuple(np.array([point[n][k] for n in hand.nodes]) for k in range(2))
    rng = np.random.default_rng(7)
    scale = np.zeros(lines.ndofs)
    scale[lines.nodal_dofs] = 1.0
    u = rng.normal(0.0, 0.3, lines.ndofs) * scale
    R = np.zeros(lines.ndofs)
    form.add_to(u, u, 0.0, R)
    assert not R.any()  # no lift before the first commit (statics)
    top, below = lines.nodal_dofs[-2], lines.nodal_dofs[-3]
    fractions = []
    for t in (0.0, 0.1, 0.25, 0.25, 0.4, 0.15, 0.3):  # kept at 0.25; a new run at 0.15
        u = u + rng.normal(0.0, 0.05, lines.ndofs) * scale
        v = rng.normal(0.0, 0.4, lines.ndofs) * scale
        u[top[2]] = 3.0 - lines.points[-2, 2]  # dry above the crests
        x = lines.points[-3] + u[below]  # 1 cm over the surface: half wet
        u[below[2]] += float(sea.elevation(x[None], t + 0.05)[0]) + 0.01 - x[2]
        for term in (hand, form):
            term.commit(t, u, v)
        memory = form.state_values()
        for name, part in (("phase", hand._phase), ("rate", hand._rate),
                           ("yd_ms", hand._yd_ms), ("ydd_ms", hand._ydd_ms)):
            assert memory[name][at_nodes] == pytest.approx(part, rel=1e-12, abs=1e-12), name
        loads = []
        for term in (hand, form):
            R = np.zeros(lines.ndofs)
            term.add_to(u, v, t + 0.05, R)
            loads.append(R)
        assert np.abs(loads[1] - loads[0]).max() < 1e-12 * np.abs(loads[0]).max()
        fractions.append(hand._flow(u, v, t + 0.05)[3][-2:])
    assert np.allclose(fractions, [0.5 - 0.01 / 0.09, 0.0]) and np.abs(hand._rate).max() > 1.0


def test_the_compiled_commit_advances_keeps_and_restarts_as_the_python_one():
    """VortexLift's compiled commit (its C function on the step kernel's buffers, as the
    compiled step calls it) and its Python commit along the same commits of a chain in
    waves at random states: the same state after each, a second commit at the same time
    keeping it and an earlier time starting again."""
    import ctypes

    lines, sea = chain_with_lift()
    python, compiled = VortexLift(lines, sea, rms_time=1.5), VortexLift(lines, sea, rms_time=1.5)
    _, ints, floats = compiled.step_kernel
    state, offset = compiled.step_state()
    at = floats.size - offset
    rng = np.random.default_rng(11)
    scale = np.zeros(lines.ndofs)
    scale[lines.nodal_dofs] = 1.0
    R = np.zeros(lines.ndofs)

    def pointer(array, kind=ctypes.c_double):
        return array.ctypes.data_as(ctypes.POINTER(kind))

    states = []
    for t in (0.0, 0.1, 0.25, 0.25, 0.4, 0.15, 0.3):  # kept at 0.25; a new run at 0.15
        u = rng.normal(0.0, 0.3, lines.ndofs) * scale
        v = rng.normal(0.0, 0.4, lines.ndofs) * scale
        python.commit(t, u, v)
        compiled.step_commit.ctypes(pointer(u), pointer(v), lines.ndofs, t,
                                    pointer(ints, ctypes.c_int64), pointer(floats), pointer(R),
                                    pointer(R), pointer(R), 0)
        assert floats[at: at + state.size] == pytest.approx(python._state, rel=1e-12,
                                                             abs=1e-12), t
        states.append(python._state.copy())
    assert np.array_equal(states[2], states[3])  # kept
    assert not np.allclose(states[4], states[3])


def strouhal_rate(w):
    # the lift's phase at the Strouhal rate alone, 2 pi cF |v_p| / d (no synchronization)
    new = vortex_lift_update(w)
    _, _, speed = viv.node_flow(w)
    held = (w.lifting > 0.5) & (w.dt <= 0.0)
    new["rate"] = ops.where(held, w.rate, 2 * np.pi * w.cF * speed / w.d)
    return new


@LinearForm
def growing_lift(v, w):
    # the built-in lift times (1 + the commits so far)
    return (1.0 + w.commits) * vortex_lift.form(v, w)


def count_commits(w):
    return dict(vortex_lift_update(w), commits=w.commits + 1.0)


def test_a_lift_model_of_ones_own_runs_on_the_same_fields():
    """VortexLiftForm with a user's update and load on its fields, compiled: a phase at
    the Strouhal rate alone (the rate's synchronization term dropped) gives the built-in
    lift of a line type with dF = 0, node by node; a load scaled by a memory of one's own
    (the commits counted) is the built-in one times 1 + that count."""
    lines, sea = chain_with_lift()
    mine = VortexLiftForm(lines, sea, 1.5, update=strouhal_rate)
    unsynchronized = VortexLiftForm(*chain_with_lift(dF=0.0), 1.5)
    growing = VortexLiftForm(lines, sea, 1.5, lift=growing_lift, update=count_commits,
                             state={"commits": 0.0})
    built_in = VortexLiftForm(lines, sea, 1.5)
    rng = np.random.default_rng(3)
    scale = np.zeros(lines.ndofs)
    scale[lines.nodal_dofs] = 1.0
    u = rng.normal(0.0, 0.3, lines.ndofs) * scale
    for k, t in enumerate((0.0, 0.1, 0.2)):
        u = u + rng.normal(0.0, 0.05, lines.ndofs) * scale
        v = rng.normal(0.0, 0.4, lines.ndofs) * scale
        loads = {}
        for name, term in (("mine", mine), ("dF = 0", unsynchronized), ("grow", growing),
                           ("built-in", built_in)):
            term.commit(t, u, v)
            loads[name] = np.zeros(lines.ndofs)
            term.add_to(u, v, t + 0.05, loads[name])
        size = np.abs(loads["built-in"]).max()
        assert np.abs(loads["mine"] - loads["dF = 0"]).max() < 1e-12 * size
        assert np.abs(loads["mine"] - loads["built-in"]).max() > 1e-6 * size  # (other rates)
        assert np.abs(loads["grow"] - (k + 2) * loads["built-in"]).max() < 1e-12 * size
    assert mine.backend == growing.backend == "numba"


def test_a_network_takes_a_lift_model_of_ones_own():
    """Network.viv_lift puts the Strouhal model in place of the built-in lift: the
    compiled step runs it (the whole loop compiled) and the lock-in string moves
    otherwise than with the built-in synchronizing lift."""
    def strouhal_lift(lines, sea, **options):
        return VortexLiftForm(lines, sea, update=strouhal_rate, **options)

    runs = []
    for viv_lift in (strouhal_lift, None):
        model, f_n, _, _ = lock_in_case(0.15, viv_lift=viv_lift)
        lifts = [t for t in model.system.line_terms if isinstance(t, (VortexLift, VortexLiftForm))]
        assert len(lifts) == 1 and (viv_lift is None) == isinstance(lifts[0], VortexLift)
        if viv_lift is not None:
            assert lifts[0].update is strouhal_rate and lifts[0].rms_time == 2 / f_n
        eq = skmoor.equilibrium(model)
        assert compiled_step.lowered_terms(model.system)[0] is None
        dt = 1 / (50 * f_n)
        runs.append(np.array([s.x.copy() for s in dynamics.integrate(
            model.system, eq.x, np.zeros(model.system.n), dt, 300 * dt, C=eq.C, tol=1e-10)]))
    mine, built_in = runs
    assert np.abs(mine - built_in).max() > 0.01 * np.abs(built_in - built_in[0]).max()


def test_the_compiled_step_runs_the_lift_form_as_the_hand_kernel():
    """The raised lock-in string in a 3 m wave with its lift written as forms on path
    'compiled': the compiled step runs it (the form's kernel and commit generated, the
    water, the node chords and the surface set in compiled code first) as the hand
    kernels: the same motion to 1e-9 of it and the same phase at the middle node (to
    1e-6 rad: the two solve to the tolerance along other Newton paths, the form with its
    tangents)."""
    from skmoor.sea.waves import AiryWave

    waves = [AiryWave(3.0, 8.0, depth=50.0, heading_deg=60.0, phase=-1.0)]
    form, phases, lift = raised_lock_in_run(True, waves=waves, form_path="compiled")
    assert isinstance(lift, VortexLiftForm) and lift.backend == "numba"
    hand, state, _ = raised_lock_in_run(True, waves=waves)
    motion = np.abs(hand - hand[0]).max()
    assert np.abs(form - hand).max() < 1e-9 * motion
    assert phases[0, 1] == pytest.approx(state[1], abs=1e-6)  # the middle node's


def tension_period(t, tension):
    """Mean period (s) between the upward crossings of a tension's mean."""
    x = tension - tension.mean()
    up = np.nonzero((x[:-1] < 0) & (x[1:] >= 0))[0]
    crossings = t[up] - x[up] * (t[up + 1] - t[up]) / (x[up + 1] - x[up])
    return (crossings[-1] - crossings[0]) / (len(crossings) - 1)


VIV_DECK, VIV_END, VIV_SINCE, VIV_SAMPLE = "tests/Mooring/viv/viv.txt", 12.0, 8.0, 0.005


def moordyn_viv(path):
    """MoorDyn's viv.txt: (t, fairlead tension N, node positions (nt, 101, 3) m) every
    VIV_SAMPLE s, coupled every 1 ms (its own dtM 0.1 ms, RK4)."""
    moordyn = pytest.importorskip("moordyn")
    system = moordyn.Create(str(path))
    try:
        assert moordyn.Init(system, [], []) == 0
        line = moordyn.GetLine(system, 1)
        n, every, coupling = moordyn.GetLineN(line), round(VIV_SAMPLE / 1e-3), 1e-3
        t, tension, nodes = [], [], []
        for k in range(round(VIV_END / coupling)):
            moordyn.Step(system, [], [], k * coupling, coupling)
            if (k + 1) % every == 0:
                t.append((k + 1) * coupling)
                tension.append(moordyn.GetLineFairTen(line))
                nodes.append([moordyn.GetLineNodePos(line, i) for i in range(n + 1)])
    finally:
        moordyn.Close(system)
    return np.array(t), np.array(tension), np.array(nodes)


@needs_mirror
@pytest.mark.slow
@pytest.mark.filterwarnings("ignore")
def test_viv_deck_against_moordyn(tmp_path, monkeypatch):
    """MoorDyn's viv.txt (Thorsen's catenary riser in a uniform 0.2 m/s current: 23.71 m,
    100 segments, EI 10.5 N m2, Cl 0.7) in skmoor (Hermite line, dt 5 ms, the compiled
    step) and MoorDyn side by side, both from the still-water static state (MoorDyn's
    IC solve sees no current) with the current on from t = 0, over 8 to 12 s: the
    fairlead tension's period within 0.01 s of MoorDyn's and of MoorDyn's own test's
    target 1 / (2 x 1.04 Hz) = 0.4808 s (tests/viv.cpp, which checks 0.01 s after 10 s),
    the largest cross-flow amplitude within 5 % of MoorDyn's and every node's within
    0.03 d, the mean tension within 1 %. Measured: 0.4801 s against 0.4806 s, 0.342 d
    against 0.350 d (nodes within 0.013 d), 69.87 N against 69.68 N. The lift does not lock
    at the Strouhal frequency cF U / d = 1.5 Hz (a tension period of 0.333 s) but at a
    riser mode of 1.04 Hz inside the synchronization band (cF -+ dF) U / d = 0.83 to
    2.17 Hz: the motion's frequency is checked in that band, off the Strouhal one.
    About 2 min, nearly all MoorDyn's (skmoor's 2400 steps: seconds)."""
    from skmoor.io.deck import read_deck
    from skmoor.io.sea_files import still_water
    from skmoor.model.from_deck import deck_network
    from skmoor.model.model import from_network

    monkeypatch.chdir(tmp_path)
    path = deck_copy(tmp_path, VIV_DECK, "current_profile.txt")
    path.write_text(path.read_text().replace("2        writeLog", "0        writeLog"))
    t_md, tension_md, nodes_md = moordyn_viv(path)

    deck = read_deck(path)
    models = []
    for sea in (still_water(deck), None):
        network, settings = deck_network(deck, sea=sea)
        models.append(from_network(network, settings=settings))
    eq = skmoor.equilibrium(models[0])
    results = skmoor.simulate(models[1], duration=VIV_END, dt=VIV_SAMPLE,
                              output_interval=VIV_SAMPLE, progress=False, eq=eq)
    assert results.meta["stopped"] is None, results.meta["stopped"]

    late, late_md = results.t > VIV_SINCE, t_md > VIV_SINCE
    tension = results.fairlead_tension[late, 0]
    period, period_md = (tension_period(results.t[late], tension),
                         tension_period(t_md[late_md], tension_md[late_md]))
    assert period == pytest.approx(period_md, abs=0.01)
    assert period == pytest.approx(1 / (2 * 1.04), abs=0.01)
    speed, cF, dF = 0.2, 0.18, 0.08
    assert (cF - dF) * speed / D < 1 / (2 * period) < (cF + dF) * speed / D
    assert abs(1 / (2 * period) - cF * speed / D) > 0.3  # not at the Strouhal frequency
    assert tension.mean() == pytest.approx(tension_md[late_md].mean(), rel=0.01)
    crossflow = 0.5 * np.ptp(results.displacement[late, :, 1], axis=0)  # per node, m
    crossflow_md = 0.5 * np.ptp(nodes_md[late_md, :, 1], axis=0)
    assert crossflow.max() == pytest.approx(crossflow_md.max(), rel=0.05)
    assert np.abs(crossflow - crossflow_md).max() < 0.03 * D
    assert crossflow_md.max() > 0.2 * D  # the riser does vibrate
