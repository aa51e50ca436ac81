"""Time integration: energy conservation, second-order accuracy, failure handling."""
import numpy as np
import pytest

import skmoor
from skmoor.coupling.system import System
from skmoor.lines.line import Line, LineSet
from skmoor.solvers.dynamics import Scheme, integrate
from skmoor.solvers.newton import DivergenceError


def paper_line(n_elements=10, law="paper"):
    """Line C1 of the paper's case, on its analytic catenary."""
    model = skmoor.build(skmoor.paper_case())
    cat = model.catenaries[0]
    lt = model.lines.lines[0].line_type
    return LineSet([Line.from_catenary(cat, lt, n_elements)], law=law)


def potential_energy(lines, u):
    """Energy of Eq. 11, int (T |u'|^2 / 2 + EA eps^2 / 2) ds on the cable quadrature,
    plus the potentials of the (constant) reference force and weight, J, from the strain
    definition (Eq. 3), independently of the force assembly."""
    f = lines.cable_fields
    up = lines.element_slopes(u)[:, :, None]  # (3, nel, 1), constant per element
    eps = (f["Xp"] * up).sum(0) + 0.5 * (up * up).sum(0)
    energy = (0.5 * f["T"] * (up * up).sum(0) + 0.5 * f["EA"] * eps**2) * lines.cable_basis.dx
    return energy.sum() + (lines.reference_force() - lines.weight_load()) @ u


def test_newmark_conserves_energy_over_100_periods():
    """Undamped, unloaded free vibration of a sagging line: total energy within 0.1 %."""
    lines = paper_line()
    system = System(lines, fairleads="fixed")
    _, K, _ = system.residual(np.zeros(system.n))
    modes = skmoor.eigenmodes(K, system.M, k=1)
    period = modes.periods[0]
    x0 = 0.1 * modes.shapes[:, 0] / np.abs(modes.shapes[:, 0]).max()  # 0.1 m amplitude

    def energy(state):
        u = system.full_displacement(state.x)
        return 0.5 * state.v @ (system.M @ state.v) + potential_energy(lines, u)

    e0 = energy(next(integrate(system, x0, np.zeros(system.n), 1.0, 0.0)))
    e_ref = energy(next(integrate(system, np.zeros(system.n), np.zeros(system.n), 1.0, 0.0)))
    amplitude_energy = e0 - e_ref
    drift = 0.0
    for state in integrate(system, x0, np.zeros(system.n), period / 50, 100 * period,
                           scheme=Scheme.newmark()):
        if state.step % 10 == 0:
            drift = max(drift, abs(energy(state) - e0))
    assert drift < 1e-3 * amplitude_energy


def _fairlead_run(dt, scheme, t_end=4.0):
    lines = paper_line(law="engineering")
    system = System(lines, fairleads="prescribed",
                    motion=lambda t: [[0.5 * np.sin(1.6 * t) ** 2, 0.0, 0.3 * np.sin(1.6 * t) ** 2]])
    for state in integrate(system, np.zeros(system.n), np.zeros(system.n), dt, t_end,
                           scheme=scheme):
        pass
    assert state.t == pytest.approx(t_end)
    return state.x


@pytest.mark.parametrize("scheme", [Scheme.newmark(), Scheme.generalized_alpha(0.8)],
                         ids=["newmark", "generalized-alpha"])
def test_error_falls_at_second_order_in_dt(scheme):
    """Error against a fine-step reference: observed order 2 (fairlead driven smoothly)."""
    reference = _fairlead_run(0.004, scheme)
    dts = [0.08, 0.04, 0.02]
    errors = [np.abs(_fairlead_run(dt, scheme) - reference).max() for dt in dts]
    order = np.polyfit(np.log(dts), np.log(errors), 1)[0]
    assert 1.8 < order < 2.3, (errors, order)


def test_generalized_alpha_parameters_match_chung_hulbert():
    """rho_inf = 1 is the midpoint rule, rho_inf = 0 annihilates at infinity (Chung & Hulbert 1993)."""
    s = Scheme.generalized_alpha(1.0)
    assert (s.alpha_m, s.alpha_f, s.beta, s.gamma) == pytest.approx((0.5, 0.5, 0.25, 0.5))
    s = Scheme.generalized_alpha(0.0)
    assert (s.alpha_m, s.alpha_f, s.beta, s.gamma) == pytest.approx((-1.0, 0.0, 1.0, 1.5))
    with pytest.raises(ValueError, match="rho_inf"):
        Scheme.generalized_alpha(1.5)


def test_divergence_stops_with_time_step_and_hint():
    """A load that turns NaN stops the run with the time, the step and a hint."""
    model = skmoor.build(skmoor.paper_case())
    model.system.body_load = lambda t, q, v: np.full(6, np.nan) if t > 0.25 else np.zeros(6)
    with pytest.raises(DivergenceError, match=r"t = 0\.3 s \(step 6\).*smaller time step") as err:
        for _ in integrate(model.system, np.zeros(model.system.n), np.zeros(model.system.n),
                           0.05, 1.0):
            pass
    assert err.value.step == 6


def test_simulate_keeps_results_when_interrupted():
    """Ctrl-C during a run returns the samples computed so far, marked as stopped."""
    model = skmoor.build(skmoor.paper_case())

    def load(t, q, v):
        if t > 1.0:
            raise KeyboardInterrupt
        return np.array([1e5 * np.sin(1.6 * t), 0, 0, 0, 0, 0])

    model.system.body_load = load
    results = skmoor.simulate(model, duration=5.0, dt=0.05, output_interval=0.1, progress=False)
    assert "interrupted" in results.meta["stopped"]
    assert 0.9 <= results.t[-1] <= 1.0 + 1e-9
    assert np.all(np.isfinite(results.body))


def test_commit_after_every_accepted_step_and_half_step():
    """integrate passes System.commit the initial state and every accepted step, on the
    term's own DOFs; a step whose Newton fails (here: a residual that is not finite at
    that step's end for the full step's two Newton tries) is split, and both halves are
    committed."""
    from skmoor.fem.terms import Term
    from skmoor.lines.catenary import solve_catenary
    from skmoor.lines.line import LineType

    rope = LineType(EA=5e8, mass=80.0, diameter=0.12)
    cat = solve_catenary([0.0, 0.0, -60.0], [90.0, 20.0, -5.0], rope.weight, rope.EA,
                         length=115.0)
    lines = LineSet([Line.from_catenary(cat, rope, 8)], law="engineering")
    dt, bad = 0.1, 0.3

    class History(Term):
        def __init__(self):
            self.commits, self.failures = [], 2

        def add_to(self, u, v, t, R, K=None, C=None):
            if abs(t - bad) < 1e-12 and self.failures:  # the full step to 0.3 s fails
                self.failures -= 1
                R += np.nan

        def commit(self, t, u, v):
            self.commits.append((t, u.copy()))

    term = History()
    system = System(lines, fairleads="prescribed", terms=[term],
                    motion=lambda t: [[0.0, 0.0, 0.5 * np.sin(t)]])
    states = list(integrate(system, np.zeros(system.n), np.zeros(system.n), dt, 0.5))
    times = [t for t, _ in term.commits]
    np.testing.assert_allclose(times, [0.0, 0.1, 0.2, 0.25, 0.3, 0.4, 0.5], atol=1e-12)
    assert states[3].subdivided == 1
    for state in states:  # the committed u is the state's full line displacement
        u = dict((round(t, 9), u) for t, u in term.commits)[round(state.t, 9)]
        np.testing.assert_allclose(u, system.full_displacement(state.x, state.t))


def cusp(negative_side):
    """balance(x) = sqrt(x) for x >= 0, -c sqrt(-x) below, with c = negative_side: Newton's
    step from x is to -x, a two-cycle no fresh matrix breaks."""
    def balance(x, tangent):
        c = 1.0 if x[0] >= 0 else negative_side
        a = max(abs(x[0]), 1e-300)
        f = np.sign(x) * c * np.sqrt(a)
        return f, (np.array([[0.5 * c / np.sqrt(a)]]) if tangent else None)
    return balance


def test_modified_newton_stops_on_the_error_it_leaves():
    """Corrections shrinking at a rate theta (s_k = theta^k) leave the tail
    s_k theta / (1 - theta) after s_k: error_below says a correction's tail is below a
    bound exactly when it is (a factor theta, or a tail summed from 1, would be off), and
    never before a third correction (two rates), while the corrections grow, or on one
    small correction after a slow rate (the larger of the last two rates counts: one
    chance-small correction would end the iteration early). On a smooth equation,
    modified Newton then ends within its tolerance of the root itself."""
    from skmoor.solvers.newton import _IterationMatrix, _newton, error_below

    for theta in (0.05, 0.3, 0.8):
        for k in range(2, 30):
            size, previous, before = theta**k, theta ** (k - 1), theta ** (k - 2)
            tail = size * theta / (1 - theta)
            assert error_below(size, previous, before, tail * (1 + 1e-9))
            assert not error_below(size, previous, before, tail * (1 - 1e-9))
    assert not error_below(1e-3, np.inf, np.inf, 1.0)  # the first correction: no rate yet
    assert not error_below(1e-6, 1e-3, np.inf, 1.0)  # the second: one rate only
    assert not error_below(2.0, 1.0, 0.5, 1e9)  # growing corrections
    # rates 0.9 then 0.01: the tail at the slower rate, 9 times the correction
    assert not error_below(0.009, 0.9, 1.0, 0.05) and error_below(0.009, 0.9, 1.0, 0.09)

    def balance(x, tangent):  # x + x^3 / 3 = 2, its matrix made once at the start
        return x + x**3 / 3 - 2.0, (np.array([[1.0 + x[0] ** 2]]) if tangent else None)

    root = np.roots([1 / 3, 0.0, 1.0, -2.0])
    root = root[np.isreal(root)].real[0]
    for tol in (1e-4, 1e-8):
        x, iterations = _newton(balance, np.array([0.0]), np.array([0.0]),
                                _IterationMatrix("dense"), tol, 50, full=False)
        assert abs(x[0] - root) <= tol * 2.0  # the change as the first correction left it


def test_modified_newton_leaves_a_cycle_for_the_line_search():
    """On the symmetric cusp the secant (Broyden) update through x = 1 and x = -1 lands on
    the root at once. On a lopsided one (c = 2) the update would shrink the correction to a
    third (a kink between the iterates): a new matrix is made instead, the fresh matrices
    do not shrink the correction, and modified Newton gives up (long before maxiter) for
    full Newton, whose line search halves the step onto the root."""
    from skmoor.solvers.newton import _IterationMatrix, _newton

    x0 = np.array([0.0])
    x, iterations = _newton(cusp(1.0), np.array([1.0]), x0, _IterationMatrix("dense"),
                            1e-9, 20, full=False)
    assert x is not None and x[0] == pytest.approx(0.0, abs=1e-12) and iterations == 3
    x, iterations = _newton(cusp(2.0), np.array([1.0]), x0, _IterationMatrix("dense"),
                            1e-9, 20, full=False)
    assert x is None and iterations < 10
    x, _ = _newton(cusp(2.0), np.array([1.0]), x0, _IterationMatrix("dense"), 1e-9, 20,
                   full=True)
    assert x is not None and abs(x[0]) < 1e-12


def test_broyden_corrections_solve_a_linear_system_in_2n_steps(monkeypatch):
    """Broyden's corrections on a kept matrix solve a linear system A x = b from the
    identity in at most 2 n steps (Gay 1979); the first correction is the kept matrix's
    own. (The guard against large scalings, which makes a new matrix, is lifted here.)"""
    from skmoor.solvers import newton
    from skmoor.solvers.newton import broyden

    monkeypatch.setattr(newton, "BROYDEN_SCALING", np.inf)
    rng = np.random.default_rng(3)
    n = 5
    A = np.eye(n) + 0.3 * rng.standard_normal((n, n))
    b = rng.standard_normal(n)
    x, steps = np.zeros(n), []
    first = b - A @ x
    assert np.array_equal(broyden(first, []), first)
    for _ in range(2 * n):
        dx = broyden(b - A @ x, steps)  # the kept matrix: the identity
        steps.append(dx)
        x = x + dx
    np.testing.assert_allclose(x, np.linalg.solve(A, b), rtol=1e-8, atol=1e-10)


def test_first_guess_is_exact_on_a_cubic_motion():
    """x(t) = c0 + c1 t + c2 t^2 + c3 t^3 has a linear acceleration: from (x, v, a) at t0
    and a(t0 - h_prev), the first guess x0 + h v0 + h^2 a0 / 2 + h^3 (a0 - a_-1) /
    (6 h_prev) is x(t0 + h) exactly, for unequal steps too; without a trend it misses by
    c3 h^3 (the jerk term)."""
    from skmoor.solvers.dynamics import _Stepper

    c = np.array([[0.3, -1.2], [2.0, 0.5], [-0.7, 0.25], [0.9, -0.4]])  # (power, DOF)

    def x(t):
        return c[0] + c[1] * t + c[2] * t**2 + c[3] * t**3

    def v(t):
        return c[1] + 2 * c[2] * t + 3 * c[3] * t**2

    def a(t):
        return 2 * c[2] + 6 * c[3] * t

    stepper = _Stepper.__new__(_Stepper)
    stepper.trend = None
    t0, h = 1.7, 0.3
    np.testing.assert_allclose(stepper.first_guess(x(t0), v(t0), a(t0), h) - x(t0 + h),
                               -c[3] * h**3, rtol=1e-12)
    for h_prev in (0.3, 0.15, 0.6):
        stepper.accepted(a(t0 - h_prev), h_prev)
        np.testing.assert_allclose(stepper.first_guess(x(t0), v(t0), a(t0), h), x(t0 + h),
                                   rtol=1e-13, atol=1e-13)
