"""A LineForm with a memory of the past (``state`` and ``update``) in the time loop.

The form: each point of the chain is pulled towards an anchor point s that creeps after
it, k (u - s) per metre, s advanced after each accepted step by the explicit rule
s_new = s + dt (u - s) / TAU. Independent numbers: the same rule run here in NumPy on the
displacements of the recorded steps, interpolated to the form's points by scikit-fem's
basis (not by the generated commit). A commit skipped, a step dt off by a step, the state
advanced within a step instead of after it, the compiled step's copy of the state not
handed back, or a restart that kept the last run's state would each break the equality.
"""
import numpy as np
import pytest
from test_compiled_step import run

import skmoor
from skmoor.fem import form_compiler
from skmoor.fem.terms import LineForm
from skmoor.lines.catenary import solve_catenary
from skmoor.solvers import compiled_step
from skmoor.solvers.dynamics import Scheme, Stepping

pytest.importorskip("jax")

STIFFNESS = 2e4  # N/m per metre of line
TAU = 0.7  # s, how fast the anchor points follow
DT, STEPS = 0.1, 40
NAMES = ("sx", "sy", "sz")


def creeping_spring(v, w):
    # k (u - s) . v: a spring per metre to an anchor point s that creeps after the line
    return STIFFNESS * sum((w.u[c] - w[name]) * v[c]
                           for c, name in enumerate(NAMES))


def creep_after(w):
    return {name: w[name] + w.dt * (w.u[c] - w[name]) / TAU
            for c, name in enumerate(NAMES)}


def _chain(path="compiled", quadrature="gauss"):
    """A 12-element chain moved at its fairlead, with the creeping spring: (system, x0,
    the form)."""
    chain = skmoor.LineType(EA=7.5e8, mass=140.0, diameter=0.09)
    cat = solve_catenary([-300.0, 0.0, -150.0], [0.0, 0.0, -5.0], chain.weight, chain.EA,
                         length=336.0)
    lines = skmoor.LineSet([skmoor.Line.from_catenary(cat, chain, 12)])
    system = skmoor.System(lines, fairleads="prescribed",
                           motion=lambda t: np.array([[np.sin(0.8 * t), 0.0, np.sin(0.8 * t)]]))
    x0 = skmoor.solve_static(system).x
    form = LineForm(creeping_spring, state=dict.fromkeys(NAMES, 0.0), update=creep_after,
                    quadrature=quadrature, path=path)
    system.add_term(form)
    return system, x0, form


def _steps(system, x0, compiled):
    states, _ = run(system, x0, np.zeros(system.n), DT, STEPS, compiled=compiled,
                    scheme=Scheme.newmark())
    return states


def _expected_state(system, form, states):
    """The rule run on the recorded steps at the form's points: (3, nel, nqp)."""
    basis, _ = form.basis_and_fields()
    s = np.zeros((3, *basis.dx.shape))
    for k, x in enumerate(states[1:], start=1):  # (the first commit, at t = 0: dt = 0)
        u, _ = system.full_state(x, np.zeros(system.n), DT * k)
        s = s + DT * (basis.interpolate(u).value - s) / TAU
    return s


@pytest.mark.parametrize("quadrature", ["gauss", "nodal"])
def test_the_compiled_step_advances_the_memory_as_its_update_says(quadrature):
    system, x0, form = _chain(quadrature=quadrature)
    why, kinds = compiled_step.lowered_terms(system)
    assert why is None and form in kinds["form"]  # the whole run is compiled
    states = _steps(system, x0, compiled=True)
    expected = _expected_state(system, form, states)
    got = np.stack([form.state_values()[name] for name in NAMES])
    assert np.abs(expected).max() > 0.3  # the anchors did creep
    assert np.abs(got - expected).max() < 1e-12 * np.abs(expected).max()


@pytest.mark.parametrize("path", ["compiled", "jax.jit", "fd"])
def test_the_python_step_and_the_numpy_update_give_the_compiled_run(path, monkeypatch):
    """The Python step with the generated commit (path 'compiled'), and with the update
    evaluated by NumPy, where JAX's compiler runs the form or NumPy with differences."""
    system, x0, form = _chain()
    fast = _steps(system, x0, compiled=True)
    if path == "jax.jit":  # the generator refuses: JAX's compiler runs the form
        def refuse(*args, **kw):
            raise form_compiler.Unsupported("a test's primitive")

        monkeypatch.setattr(form_compiler, "build_kernel", refuse)
    other, x_other, slow_form = _chain(path="fd" if path == "fd" else "compiled")
    slow = _steps(other, x_other, compiled=False)
    assert path != "jax.jit" or slow_form.backend.startswith("jax.jit")
    motion = np.abs(fast - fast[0]).max()
    rel = 1e-6 if path == "fd" else 1e-9  # (fd: its tangents by differences)
    assert np.abs(slow - fast).max() < rel * motion
    for name in NAMES:
        assert np.allclose(slow_form.state_values()[name], form.state_values()[name],
                           rtol=0, atol=rel)


def test_the_memory_matters_and_a_new_run_starts_from_the_initial_state():
    system, x0, form = _chain()
    first = _steps(system, x0, compiled=True)
    again = _steps(system, x0, compiled=True)  # the same model run again from t = 0
    assert np.abs(again - first).max() < 1e-12 * np.abs(first - first[0]).max()
    fixed, x_fixed = _chain()[:2]
    fixed.terms[-1].update = lambda w: {name: w[name] for name in NAMES}  # never creeps
    held = _steps(fixed, x_fixed, compiled=False)
    assert np.abs(held - first).max() > 1e-3 * np.abs(first - first[0]).max()


def test_an_update_reads_fields_of_time_at_the_committed_step():
    """A memory s that takes the value of a field given as a function of time, f(t) =
    sin t, at each commit: after commits at t = 0.3 and 1.1 the generated commit (path
    'compiled') and NumPy's hold sin(1.1) at every point (the generated commit once read
    the fields packed when the form was first evaluated, sin 0)."""
    chain = skmoor.LineType(EA=7.5e8, mass=140.0, diameter=0.09)
    points = np.c_[np.zeros(4), np.zeros(4), np.linspace(-10.0, 0.0, 4)]
    lines = skmoor.LineSet([skmoor.Line.from_polyline(points, chain)])
    shape = lines.basis.dx.shape
    for path in ("compiled", "fd"):
        form = LineForm(lambda v, w: w.s * v[0], fields=lambda t: {"f": np.full(shape, np.sin(t))},
                        state={"s": 0.0}, update=lambda w: {"s": w.f + 0.0 * w.s},
                        path=path, lines=lines)
        u = np.zeros(lines.ndofs)
        form.add_to(u, u, 0.0, np.zeros(lines.ndofs))
        for t in (0.3, 1.1):
            form.commit(t, u, u)
        held = form.state_values()["s"]
        assert held == pytest.approx(np.full(shape, np.sin(1.1)), abs=1e-15), path


@pytest.mark.parametrize("kwargs, message", [
    (dict(state={"s": 0.0}), "give both"),
    (dict(update=creep_after), "give both"),
    (dict(state={"u": 0.0}, update=creep_after), "name 'u' is taken"),
    (dict(state=[0.0], update=creep_after), "need a dict"),
    (dict(state={"s": 0.0}, update="s + dt"), "need a function"),
])
def test_a_bad_memory_is_refused_with_its_reason(kwargs, message):
    with pytest.raises(ValueError, match=message):
        LineForm(creeping_spring, **kwargs)


def test_an_update_with_other_names_is_refused():
    system, x0, form = _chain(path="fd")
    form.update = lambda w: {"sx": w.sx}
    with pytest.raises(ValueError, match="must return a dict with the state's names"):
        _steps(system, x0, compiled=False)


def test_a_checkpoint_keeps_the_memory_so_the_steps_after_it_repeat():
    """A host's checkpoint and restore (``Stepping``) with the memory advanced in the
    compiled step: the steps after the restore repeat the first ones to round-off."""
    system, x0, form = _chain()
    stepping = Stepping(system, x0, np.zeros(system.n), scheme=Scheme.newmark(), tol=1e-10)
    for _ in range(5):
        stepping.step(DT)
    saved = stepping.checkpoint()
    first = [stepping.step(DT).x.copy() for _ in range(10)]
    kept = form.state_values()["sx"].copy()
    stepping.restore(saved)
    again = [stepping.step(DT).x.copy() for _ in range(10)]
    assert np.abs(np.array(again) - first).max() < 1e-12 * np.abs(first).max()
    assert np.abs(form.state_values()["sx"] - kept).max() < 1e-14
    assert np.abs(kept).max() > 0.1
