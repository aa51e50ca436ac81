"""Large steps through touchdown: the step's full-Newton retry with a
line search and the automatic subdivision of a step whose Newton fails
(skmoor.solvers.dynamics.integrate), and the count of subdivided steps in the results.

The system is tests/decks/seabed/chain_semi.dat, a three-leg chain mooring with the IEA
15 MW VolturnUS-S's published line properties (850 m chains in 200 m of water, MoorDyn's
default bottom), on 20 segments per line, its fairleads driven 5 m / 90 s in surge and
2 m / 12 s in heave. Before the line search and the subdivision, Newton stalled on it in a
two-cycle of a touchdown node's height (the bed spring's kink is stiffer than the
iteration matrix's mass term) at t = 32.4 s with dt = 0.2 s and at t = 30.8 s with
dt = 0.4 s ("Newton did not converge in 20 iterations"); on 50 segments at every step
from 25 ms to 0.4 s.
"""
import copy
import dataclasses
from pathlib import Path

import numpy as np
import pytest

import skmoor
from skmoor.run.equilibrium import equilibrium
from skmoor.run.outputs import summary
from skmoor.solvers.dynamics import integrate
from skmoor.solvers.newton import DivergenceError

DECK = Path(__file__).parents[1] / "decks" / "seabed" / "chain_semi.dat"
SEGMENTS = 20
DURATION = 60.0


def motion(t):
    """Every fairlead: 5 m / 90 s surge and 2 m / 12 s heave, faded in over 12 s."""
    y = np.zeros(9)
    fade = 0.5 * (1 - np.cos(np.pi * min(t / 12.0, 1.0)))
    y[0::3] = 5.0 * fade * np.sin(2 * np.pi * t / 90.0)
    y[2::3] = 2.0 * fade * np.sin(2 * np.pi * t / 12.0)
    return y


def chain_model(folder, **solver):
    """(model, its static equilibrium) on SEGMENTS segments per line, with ``solver``."""
    text = DECK.read_text().replace("850.0     50", f"850.0     {SEGMENTS}")
    path = folder / "chain_semi.dat"
    path.write_text(text)
    model = skmoor.build(path, motion=motion)
    model.solver.update(solver)
    return model, equilibrium(model)


@pytest.fixture(scope="module")
def chain(tmp_path_factory):
    """The deck's model (Newmark: no numerical damping) and its static equilibrium."""
    return chain_model(tmp_path_factory.mktemp("deck"))


@pytest.fixture(scope="module")
def runs(chain):
    """Results at 0.05 s (the reference), 0.2 s and 0.4 s, sampled every 0.4 s."""
    model, eq = chain
    return {dt: skmoor.simulate(model, duration=DURATION, dt=dt, output_interval=0.4,
                                progress=False, eq=eq) for dt in (0.05, 0.2, 0.4)}


@pytest.fixture(scope="module")
def damped_runs(tmp_path_factory):
    """Results at 0.05 s and 0.2 s with generalized-alpha at rho_inf 0.5, as ``simulate``
    advises when the step is longer than the bed's contact period."""
    model, eq = chain_model(tmp_path_factory.mktemp("damped"), scheme="generalized-alpha",
                            rho_inf=0.5)
    return {dt: skmoor.simulate(model, duration=DURATION, dt=dt, output_interval=0.4,
                                progress=False, eq=eq) for dt in (0.05, 0.2)}


@pytest.mark.parametrize("dt", [0.2, 0.4])
def test_large_steps_run_through_touchdown(runs, dt):
    """The runs that stalled at 30-32 s go to the end."""
    r = runs[dt]
    assert r.meta["stopped"] is None
    assert r.meta["steps"] == r.meta["steps_planned"] == round(DURATION / dt)
    assert r.t[-1] == pytest.approx(DURATION)


def test_large_step_is_accurate(damped_runs):
    """At 0.2 s (60 steps per heave period) with the numerical damping ``simulate`` advises
    here, the fairlead tensions' std and peak after the fade-in stay within 1 % of the
    0.05 s run's (measured: 0.3 % and 0.1 %, the same at Newton tolerances 1e-5 and 1e-6).
    Without it (Newmark) the 0.2 s run chatters at touchdown and its peaks move by 0 to
    6 % with the Newton iterates' path alone: not a measure of the step's accuracy."""
    ref, r = damped_runs[0.05], damped_runs[0.2]
    window = ref.t > 24.0
    f_ref, f = ref.fairlead_tension[window], r.fairlead_tension[window]
    np.testing.assert_allclose(np.std(f, axis=0), np.std(f_ref, axis=0), rtol=0.01)
    np.testing.assert_allclose(f.max(axis=0), f_ref.max(axis=0), rtol=0.01)


def test_subdivided_steps_are_reported(chain, runs):
    """The steps ``simulate`` split are counted in meta and summary: with every 0.4 s step
    made to fail (:class:`_LongStepsFail`) and its halves not, each of the run's steps,
    and none in the 0.05 s run. (Whether a step through touchdown fails on its own depends
    on Newton's path, which round-off steers: not a count to assert.)"""
    model, eq = chain
    forced = dataclasses.replace(model, system=_LongStepsFail(model.system, 0.2),
                                 settings=copy.deepcopy(model.settings))
    forced.solver.update(compiled=False)  # (the compiled step would not call the residual)
    r = skmoor.simulate(forced, duration=2.0, dt=0.4, output_interval=0.4, progress=False,
                        eq=eq)
    assert r.meta["subdivided_steps"] == r.meta["steps"] == 5
    assert summary(r)["subdivided_steps"] == 5
    assert runs[0.05].meta["subdivided_steps"] == 0
    assert summary(runs[0.05])["subdivided_steps"] == 0


class _LongStepsFail:
    """A system whose residual is NaN at a time more than ``longest`` s after the last
    time it was evaluated finite: every step longer than that fails."""

    def __init__(self, system, longest):
        self.system, self.longest, self.last = system, longest, 0.0

    def __getattr__(self, name):
        return getattr(self.system, name)

    def residual(self, x, v=None, t=0.0, **kw):
        out = self.system.residual(x, v, t, **kw)
        if t - self.last > self.longest * (1 + 1e-6):
            return (np.full_like(out[0], np.nan),) + tuple(out[1:])
        self.last = t
        return out


@pytest.mark.parametrize("levels", [1, 2])
def test_forced_subdivision_is_the_small_step(chain, levels):
    """Every step of dt forced to fail (and, at two levels, every half too): the run
    subdivides every step into 2**levels steps and continues at dt; its states are those
    of the run at dt / 2**levels (to round-off in the substeps' times)."""
    model, eq = chain
    dt, t_end = 0.4, 8.0
    small = dt / 2**levels
    system = _LongStepsFail(model.system, small)
    x0, v0 = eq.x, np.zeros(model.system.n)
    forced = list(integrate(system, x0, v0, dt, t_end))
    reference = list(integrate(model.system, x0, v0, small, t_end))[::2**levels]
    assert len(forced) == len(reference) == round(t_end / dt) + 1
    assert [s.subdivided for s in forced] == list(range(len(forced)))
    for a, b in zip(forced, reference):
        assert a.t == pytest.approx(b.t, abs=1e-12)
        np.testing.assert_allclose(a.x, b.x, rtol=0, atol=1e-9 * np.max(np.abs(b.x)) + 1e-12)
        np.testing.assert_allclose(a.v, b.v, rtol=0, atol=1e-7 * np.max(np.abs(b.v)) + 1e-9)


def test_subdivision_gives_up_with_the_smallest_step(chain):
    """A step that fails down to dt / 2**subdivide stops the run with the time, the step
    and the smallest step tried; subdivide=0 stops at the first failure."""
    model, eq = chain
    x0, v0 = eq.x, np.zeros(model.system.n)
    with pytest.raises(DivergenceError, match=r"step 1\).*not finite.*dt / 8") as err:
        for _ in integrate(_LongStepsFail(model.system, 1e-3), x0, v0, 0.4, 1.0,
                           subdivide=3):
            pass
    assert err.value.step == 1
    with pytest.raises(DivergenceError, match=r"step 1\): the Newton step is not finite\. "):
        for _ in integrate(_LongStepsFail(model.system, 1e-3), x0, v0, 0.4, 1.0,
                           subdivide=0):
            pass


def test_a_run_whose_lines_blow_up_stops_with_the_line_and_the_time():
    """Newton can converge on every step of a run that has blown up (seen on a lazy-wave
    cable heaved without damping: 1e3 m/s and 1e8 N within 3 s): the recorder stops it
    where a line is stretched by more than half its length, naming the line and the time,
    and keeps what came before; a state merely far from rest passes."""
    from skmoor.run.recorder import BLOWN_UP_STRAIN, Recorder
    from skmoor.solvers.dynamics import State

    model = skmoor.build(skmoor.paper_case())
    eq = skmoor.equilibrium(model)
    recorder = Recorder(model)
    zero = np.zeros(model.system.n)
    # the body moved, the lines' inner nodes not: their end elements (~12 m) stretch
    x = eq.x.copy()
    x[model.system.nf] += 2.0  # m: by up to ~17 %, far from rest but no blow-up
    recorder.record(State(1.0, 20, x, zero, zero))
    x[model.system.nf] += 8.0  # m: by ~85 % on the windward lines
    with pytest.raises(DivergenceError, match=r"t = 2 s \(step 40\).*stretched by") as err:
        recorder.record(State(2.0, 40, x, zero, zero))
    assert err.value.t == 2.0 and err.value.step == 40
    assert any(repr(line.name) in str(err.value) for line in model.lines.lines)
    assert len(recorder.rows["t"]) == 1 and BLOWN_UP_STRAIN == 0.5
