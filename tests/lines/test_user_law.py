"""A user's constitutive law (skmoor.UserLaw) against the built-in laws of the same tension.

Independent numbers: the built-in Engineering law (tension EA e, the hand-written cable
kernel) and a built-in Curve (a piecewise-linear table) of the same tension as the user's
function. A law that saw the strain from the static state instead of the unstretched
line, a dropped reference strain, a factor of the stretch in the force or a user law left
out of the reported tension would make the histories or the tensions differ.
"""
import numpy as np
import pytest
from test_compiled_step import run

import skmoor
from skmoor.fem import ops
from skmoor.lines import creep, syrope
from skmoor.lines.catenary import solve_catenary
from skmoor.solvers import compiled_step
from skmoor.solvers.dynamics import Scheme

pytest.importorskip("jax")

EA = 7.5e8  # N, a studless chain of 90 mm
KINK = 1.8e-3  # strain where the curved law stiffens (above the static state, 1.25e-3 at most)
LENGTH = 336.0  # m: a taut chain (its motion is not chaotic: round-off stays round-off)
AMPLITUDE = 1.0  # m, the fairlead's surge and heave


def _chain(law, BA=0.0, EI=0.0, offset=0.0, amplitude=AMPLITUDE):
    """A 20-element chain from an anchor to a fairlead moved ``amplitude`` m (prescribed)
    about ``offset`` m out in x (the static state then away from the catenary the line
    is built on), with internal damping BA (N s) and bending stiffness EI (N m2; > 0:
    Hermite elements), and its static state: (system, x0)."""
    chain = skmoor.LineType(EA=EA, mass=140.0, diameter=0.09, BA=BA, EI=EI, law=law)
    cat = solve_catenary([-300.0, 0.0, -150.0], [0.0, 0.0, -5.0], chain.weight, chain.EA,
                         length=LENGTH)
    lines = skmoor.LineSet([skmoor.Line.from_catenary(cat, chain, 20)])
    system = skmoor.System(lines, fairleads="prescribed", motion=lambda t: np.array(
        [[offset + amplitude * np.sin(0.8 * t), 0.0, amplitude * np.sin(0.8 * t)]]))
    return system, skmoor.solve_static(system).x


def hooke(strain, rate):
    return EA * strain


def stiffening(strain, rate):
    return EA * strain + 2.0 * EA * ops.maximum(strain - KINK, 0.0)


def _history(system, x0, compiled=True, steps=50):
    states, _ = run(system, x0, np.zeros(system.n), 0.1, steps, compiled=compiled,
                    scheme=Scheme.newmark())
    u, _ = system.full_state(states[-1], np.zeros(system.n), 5.0)
    return states, system.lines.element_tension(u)


@pytest.mark.parametrize("user, builtin, BA", [
    (hooke, skmoor.Engineering(), 0.0),
    (hooke, skmoor.Engineering(), 3e7),  # with the line type's internal damping
    (stiffening, skmoor.Curve([0.0, KINK, 2 * KINK], [0.0, EA * KINK, 4 * EA * KINK]), 0.0),
])
def test_user_law_moves_the_chain_as_the_built_in_law(user, builtin, BA):
    law = skmoor.UserLaw(user)
    system_user, x_user = _chain(law, BA)
    system_builtin, x_builtin = _chain(builtin, BA)
    assert np.abs(x_user - x_builtin).max() < 1e-9  # the static state
    why, kinds = compiled_step.lowered_terms(system_user.system
                                             if hasattr(system_user, "system")
                                             else system_user)
    assert why is None and [t.name for t in kinds["form"]] == [user.__name__]
    got, tension = _history(system_user, x_user)
    expected, tension_builtin = _history(system_builtin, x_builtin)
    motion = np.abs(expected - expected[0]).max()
    assert motion > 1.0
    assert np.abs(got - expected).max() < 1e-9 * motion
    assert np.abs(tension - tension_builtin).max() < 1e-9 * tension_builtin.max()


@pytest.mark.parametrize("user, builtin, BA", [
    (hooke, skmoor.Engineering(), 3e7),
    (stiffening, skmoor.Curve([0.0, KINK, 2 * KINK], [0.0, EA * KINK, 4 * EA * KINK]), 0.0),
])
def test_user_law_moves_a_bending_chain_as_the_built_in_law(user, builtin, BA):
    """On Hermite elements the law's term carries the elements' whole axial force (the
    bending kernel leaves it out, its reference part too: left in, the static state
    moves by a metre) at the Gauss points, its strain from the reference state."""
    system_user, x_user = _chain(skmoor.UserLaw(user), BA, EI=2e5)
    system_builtin, x_builtin = _chain(builtin, BA, EI=2e5)
    assert system_user.lines.hermite
    assert np.abs(x_user - x_builtin).max() < 1e-9
    why, kinds = compiled_step.lowered_terms(system_user)  # (the bending loop first)
    assert why is None and [getattr(t, "name", "") for t in kinds["form"]][1:] == [
        user.__name__]
    got, tension = _history(system_user, x_user, steps=30)
    expected, tension_builtin = _history(system_builtin, x_builtin, steps=30)
    motion = np.abs(expected - expected[0]).max()
    assert motion > 1.0
    assert np.abs(got - expected).max() < 1e-9 * motion
    # (the reported tensions: N against the built-in's N |r'| / lambda, |X'| = 1 to 1e-7)
    assert np.abs(tension - tension_builtin).max() < 1e-8 * tension_builtin.max()
    slow, _ = _history(system_user, x_user, compiled=False, steps=30)
    assert np.abs(slow - got).max() < 1e-9 * motion  # the Python step's too


def test_the_kink_is_crossed_so_the_strain_measure_matters():
    """The stiffening law against the same kink placed on the strain from the static
    state: far apart (so the test above tells the two strains apart)."""
    system, x0 = _chain(skmoor.UserLaw(stiffening))
    e_ref = system.lines.cable_fields["e_ref"][:, 0]
    assert 0.5 * KINK < e_ref.max() < KINK  # the static state is below the kink ...
    states, _ = _history(system, x0)
    largest = max(np.max((1 + e_ref) * np.sqrt(1 + 2 * system.lines.element_strain(
        system.full_state(x, np.zeros(system.n), 0.1 * k)[0])) - 1)
        for k, x in enumerate(states))
    assert largest > KINK  # ... and the motion crosses it

    def from_static(strain, rate):  # the mistake: the kink on the strain beyond e_ref
        return EA * strain + 2.0 * EA * ops.maximum(strain - e_ref.max() - KINK, 0.0)

    other, x_other = _chain(skmoor.UserLaw(from_static))
    wrong, _ = _history(other, x_other)
    assert np.abs(wrong - states).max() > 1e-3


def test_the_python_step_of_a_user_law_is_the_compiled_one():
    system, x0 = _chain(skmoor.UserLaw(stiffening))
    fast, _ = _history(system, x0, compiled=True, steps=30)
    slow, _ = _history(system, x0, compiled=False, steps=30)
    assert np.abs(fast - slow).max() < 1e-9 * np.abs(slow - slow[0]).max()


@pytest.mark.parametrize("tension, message", [
    (lambda e, r: EA * e + 5.0, "at zero strain must be 0 N"),
    (lambda e, r: -EA * e, "must increase with the strain"),
    (lambda e, r: EA * e / np.maximum(0.1 - e, 0.0), "not finite"),
    ("EA e", "need a function"),
])
def test_a_bad_law_is_refused_with_its_reason(tension, message):
    with pytest.raises(ValueError, match=message):
        skmoor.UserLaw(tension)


def test_the_static_strain_inverts_the_law():
    law = skmoor.UserLaw(stiffening)
    T = np.array([0.0, 1e5, EA * KINK, 3e6])
    e = law.static_strain(T)
    assert np.allclose(law.tension(e), T, rtol=1e-12, atol=1e-6)


# --- a law with a memory: a spring EA in series with a Kelvin element (spring 3 EA,
# dashpot C_DASH), N = EA (e - e_v), the Kelvin strain e_v advanced by implicit Euler
C_DASH = 8.0 * EA  # N s: the Kelvin strain follows within about 2 s


def zener(strain, rate, state):
    return EA * (strain - state[0])


def zener_update(strain, rate, state, dt):
    return ((state[0] + dt * EA * strain / C_DASH) / (1.0 + dt * 4.0 * EA / C_DASH),)


def test_a_law_with_a_memory_advances_it_on_the_strain_from_the_unstretched_line():
    """The Kelvin strain after the run against the same implicit Euler run here on the
    strains of the recorded steps (e from the unstretched line, independently of the
    law's form); the reported tension against EA (e - e_v); the Python step against the
    compiled one. A law that saw the strain from the static state (off by e_ref, about
    1e-3), a step dt off, a commit skipped or the state left out of the reported tension
    would fail it."""
    law = skmoor.UserLaw(zener, state=[0.0], update=zener_update)
    system, x0 = _chain(law)
    why, kinds = compiled_step.lowered_terms(system)
    assert why is None and [t.name for t in kinds["form"]] == ["zener"]
    states, tension = _history(system, x0)
    e_ref = system.lines.cable_fields["e_ref"][:, 0]
    e_v = np.zeros_like(e_ref)
    for k, x in enumerate(states[1:], start=1):  # (the first commit, at t = 0: dt = 0)
        u, _ = system.full_state(x, np.zeros(system.n), 0.1 * k)
        e = (1 + e_ref) * np.sqrt(1 + 2 * system.lines.element_strain(u)) - 1
        e_v = (e_v + 0.1 * EA * e / C_DASH) / (1.0 + 0.4 * EA / C_DASH)
    kept = system.lines._law_memories[id(law)].state_values()["law_state_0"][:, 0]
    assert e_v.max() > 0.2 * e_ref.max()  # the Kelvin element did take strain
    assert np.abs(kept - e_v).max() < 1e-12 * e_v.max()
    assert np.abs(tension - EA * (e - e_v)).max() < 1e-8 * tension.max()
    slow, _ = _history(system, x0, compiled=False)  # (a new run: the state starts again)
    assert np.abs(slow - states).max() < 1e-9 * np.abs(states - states[0]).max()
    hooke_run, _ = _history(*_chain(skmoor.UserLaw(hooke)))
    assert np.abs(hooke_run - states).max() > 1e-2  # the memory changes the motion


def test_a_law_with_a_memory_on_a_bending_chain_runs_compiled_as_in_python():
    law = skmoor.UserLaw(zener, state=[0.0], update=zener_update)
    system, x0 = _chain(law, EI=2e5)
    assert compiled_step.lowered_terms(system)[0] is None
    fast, _ = _history(system, x0, steps=30)
    kept = system.lines._law_memories[id(law)].state_values()["law_state_0"].copy()
    slow, _ = _history(system, x0, compiled=False, steps=30)
    assert np.abs(slow - fast).max() < 1e-9 * np.abs(fast - fast[0]).max()
    again = system.lines._law_memories[id(law)].state_values()["law_state_0"]
    assert kept.max() > 1e-4 and np.abs(again - kept).max() < 1e-12


def zener_rate(strain, rate, state):
    # C de_v/dt = EA (e - e_v) - 3 EA e_v: the Kelvin element's strain rate
    return ((EA * strain - 4.0 * EA * state[0]) / C_DASH,)


def test_a_law_with_a_state_rate_integrates_it_by_the_trapezoidal_rule_within_the_step():
    """The same Kelvin element given by its rate: the state after the run against the
    trapezoidal rule run here on the strains of the recorded steps (implicit: the rate is
    linear in e_v), the reported tension against EA (e - e_v) at that state, the Python
    step against the compiled one, on cables and on bending lines (its state at the Gauss
    points). A rate taken at the step's start only or a half step dropped would fail it
    (the tension's change within the step is held against the built-in creep law
    below)."""
    law = skmoor.UserLaw(zener, state=[0.0], state_rate=zener_rate)
    system, x0 = _chain(law)
    assert compiled_step.lowered_terms(system)[0] is None
    states, tension = _history(system, x0)
    e_ref = system.lines.cable_fields["e_ref"][:, 0]
    e_v, e_old, h, k = np.zeros_like(e_ref), None, 0.1, 4.0 * EA / C_DASH
    for step, x in enumerate(states):
        u, _ = system.full_state(x, np.zeros(system.n), h * step)
        e = (1 + e_ref) * np.sqrt(1 + 2 * system.lines.element_strain(u)) - 1
        if e_old is not None:
            e_v = (e_v * (1 - 0.5 * h * k) + 0.5 * h * EA * (e_old + e) / C_DASH) / (
                1 + 0.5 * h * k)
        e_old = e
    kept = system.lines._law_memories[id(law)].state_values()["law_state_0"][:, 0]
    assert e_v.max() > 0.2 * e_ref.max()
    assert np.abs(kept - e_v).max() < 1e-12 * e_v.max()
    assert np.abs(tension - EA * (e - e_v)).max() < 1e-8 * tension.max()
    slow, _ = _history(system, x0, compiled=False)
    assert np.abs(slow - states).max() < 1e-9 * np.abs(states - states[0]).max()
    explicit, _ = _history(*_chain(skmoor.UserLaw(zener, state=[0.0], update=zener_update)))
    assert np.abs(explicit - states).max() > 1e-4  # the integration changes the motion
    bending, x_bending = _chain(law, EI=2e5)
    fast, _ = _history(bending, x_bending, steps=30)
    slow, _ = _history(bending, x_bending, compiled=False, steps=30)
    assert np.abs(slow - fast).max() < 1e-9 * np.abs(fast - fast[0]).max()


@pytest.mark.parametrize("kwargs, message", [
    (dict(state=[0.0]), "needs the initial values and update"),
    (dict(state=[np.nan], update=zener_update), "finite initial values"),
    (dict(state=[0.0], update=lambda e, r, s, dt: (s[0], s[0])), "returned 2 values"),
    (dict(state=[0.0], update=lambda e, r, s, dt: (s[0] / 0.0,)), "not finite"),
])
def test_a_bad_memory_of_a_law_is_refused_with_its_reason(kwargs, message):
    with pytest.raises(ValueError, match=message):
        skmoor.UserLaw(zener, **kwargs)


# --- a law of the reference state: the paper's own law (Eq. 6) written as a user's


def _runs_as(user, builtin, **chain):
    """The chain of :func:`_chain` (``chain``: its options) under a user's law and under
    the built-in law it is written after: the same static state, motion and tensions to
    1e-9 (compiled; the user's in Python too). Returns the built-in run's states and the
    size of its motion (m)."""
    system_user, x_user = _chain(user, **chain)
    system_builtin, x_builtin = _chain(builtin, **chain)
    assert np.abs(x_user - x_builtin).max() < 1e-9 * max(np.abs(x_builtin).max(), 1.0)
    assert compiled_step.lowered_terms(system_user)[0] is None
    got, tension = _history(system_user, x_user)
    expected, tension_builtin = _history(system_builtin, x_builtin)
    motion = np.abs(expected - expected[0]).max()
    assert np.abs(got - expected).max() < 1e-9 * motion
    assert np.abs(tension - tension_builtin).max() < 1e-9 * tension_builtin.max()
    slow, _ = _history(system_user, x_user, compiled=False)
    assert np.abs(slow - got).max() < 1e-9 * motion
    return expected, motion


def green(strain, rate, reference):
    # Eq. 6: the reference tension plus EA eps, eps of Eq. 3 from the reference state,
    # times the stretch lambda from it (the force along r' per unit reference length)
    e_ref, T_ref = reference
    stretch = (1.0 + strain) / (1.0 + e_ref)
    return (T_ref + EA * 0.5 * (stretch * stretch - 1.0)) * stretch


def test_the_papers_law_written_as_a_user_law_moves_the_chain_as_the_built_in_one():
    """``UserLaw(green, reference=True, static=Engineering())`` reads each point's
    reference strain and tension: the same static state, motion and tensions as the
    built-in Paper law (the hand kernel's Green strain), compiled and in Python; the
    engineering law from the same state moves the chain measurably otherwise, so a
    reference taken as zero (or the strain from the unstretched line read as the Green
    strain) would fail it."""
    law = skmoor.UserLaw(green, reference=True, static=skmoor.Engineering())
    expected, motion = _runs_as(law, skmoor.Paper())  # (measured 6e-15 apart)
    engineering, _ = _history(*_chain(skmoor.Engineering()))
    assert np.abs(engineering - expected).max() > 1e-4 * motion  # measured 5e-4


@pytest.mark.parametrize("kwargs, message", [
    (dict(reference=True), "needs the built-in law that makes that state"),
    (dict(reference=True, static=skmoor.UserLaw(hooke)), "needs the built-in law"),
])
def test_a_law_of_the_reference_state_needs_its_static_law(kwargs, message):
    with pytest.raises(ValueError, match=message):
        skmoor.UserLaw(green, **kwargs)


def test_a_law_of_the_reference_state_must_give_its_tension_there():
    """At its own reference the law must give the reference's tension: Eq. 6 without the
    reference tension (EA eps alone) is refused, naming the strain."""
    def green_without_T(strain, rate, reference):
        e_ref, _ = reference
        stretch = (1.0 + strain) / (1.0 + e_ref)
        return EA * 0.5 * (stretch * stretch - 1.0) * stretch

    with pytest.raises(ValueError, match=r"must be that tension; it is 0 N, not .* at strain"):
        skmoor.UserLaw(green_without_T, reference=True, static=skmoor.Engineering())


# --- a law about the static state: polyester's dynamic stiffness written as a user's

EA_DYNAMIC = 2.0 * EA  # N
ALPHA, BETA = 1.2 * EA, 20.0  # N, -: MoorDyn's EA_d = alphaMBL + beta T_mean


def about_the_mean(strain, rate, reference):
    # StaticDynamic: the static state's tension plus EA_d times the strain from it
    e_mean, T_mean = reference
    return T_mean + EA_DYNAMIC * (strain - e_mean)


def about_the_mean_loaded(strain, rate, reference):
    # the same with MoorDyn's load-dependent EA_d = alphaMBL + beta T_mean
    e_mean, T_mean = reference
    return T_mean + (ALPHA + BETA * T_mean) * (strain - e_mean)


# Syrope's fast limit (its working curve the static law; MoorDyn's deck values)
SYROPE_OWC = (np.array([0.002, 0.01, 0.02, 0.04, 0.06]),
              np.array([1.7e5, 7.4e5, 1.3e6, 2.45e6, 4.39e6]))  # strain, N
SYROPE_ALPHA, SYROPE_BETA = 1.53e8, 23.12  # N, -


def about_the_mean_syrope(strain, rate, reference):
    e_mean, T_mean = reference
    return T_mean + (SYROPE_ALPHA + SYROPE_BETA * T_mean) * (strain - e_mean)


SYROPE = syrope.syrope_law(SYROPE_OWC, "quadratic", 0.25, 1.0, 1.3886e6, SYROPE_ALPHA,
                           SYROPE_BETA)


@pytest.mark.parametrize("user, builtin", [
    (about_the_mean, skmoor.laws.StaticDynamic(EA_dynamic=EA_DYNAMIC)),
    (about_the_mean_loaded, skmoor.laws.StaticDynamic(alpha_MBL=ALPHA, beta=BETA)),
    (about_the_mean_syrope, SYROPE),
])
def test_polyesters_law_written_about_the_static_state_moves_as_the_built_in_one(user,
                                                                                 builtin):
    """``UserLaw(f, reference='static', static=...)`` reads each element's static strain
    and tension: the statics run the static law (the same static state as the built-in
    StaticDynamic's; Syrope's on its working curve), and the motion and tensions about
    it are the built-in law's, compiled and in Python. The fairlead's offset puts the
    static state away from the catenary the line is built on, so the same law about
    that catenary (reference='line') moves otherwise: a law that read the wrong state
    would fail."""
    law = skmoor.UserLaw(user, reference="static", static=builtin.static)
    expected, motion = _runs_as(law, builtin, offset=0.5, amplitude=0.3)  # (5e-14 apart)
    about_the_catenary = skmoor.UserLaw(user, reference="line", static=builtin.static)
    other, _ = _history(*_chain(about_the_catenary, offset=0.5, amplitude=0.3))
    assert np.abs(other - expected).max() > 1e-3 * motion  # measured 1e-2 to 3e-2


def test_a_law_about_the_static_state_is_refused_where_it_cannot_act():
    """On a bending line (as StaticDynamic), with an unknown reference: each refused
    naming the field."""
    with pytest.raises(ValueError, match="reference: True or 'line'"):
        skmoor.UserLaw(about_the_mean, reference="mean", static=skmoor.Engineering())
    law = skmoor.UserLaw(about_the_mean, reference="static", static=skmoor.Engineering())
    with pytest.raises(ValueError, match="static-dynamic law.*EI > 0"):
        _chain(law, EI=2e5)


# --- a law with a creep state: MoorDyn's viscoelastic polyester written as a user's

EA_1 = EA_DYNAMIC * EA / (EA_DYNAMIC - EA)  # N, the creep spring (EA_s = EA)
CREEP_DAMPING, DYNAMIC_DAMPING = 5e8, 2e7  # N s: a creep time (BA + BA_D) / (EA_1 + EA_d)
                                           # of 0.17 s, within the 5 s run


def creep_rate(strain, rate, state, reference):
    # dz/dt: the dynamic element's tension less the creep spring's, over the dampers
    z, = state
    return ((EA_DYNAMIC * strain - (EA_1 + EA_DYNAMIC) * z + DYNAMIC_DAMPING * rate)
            / (CREEP_DAMPING + DYNAMIC_DAMPING),)


def creep_tension(strain, rate, state, reference):
    # the creep element's: its spring (held only in tension) and its damper
    z, = state
    return (ops.where(strain >= 0.0, EA_1 * z, 0.0)
            + CREEP_DAMPING * creep_rate(strain, rate, state, reference)[0])


def relaxed(e_static, T_static):
    # at rest in creep equilibrium at the static strain: EA_d (e - z) = EA_1 z
    return (e_static * EA_DYNAMIC / (EA_1 + EA_DYNAMIC),)


def _viscoelastic(**kwargs):
    """The built-in law the creep user laws here are written after."""
    return skmoor.laws.Viscoelastic(EA_dynamic=EA_DYNAMIC, creep_damping=CREEP_DAMPING,
                                    dynamic_damping=DYNAMIC_DAMPING, **kwargs)


def _creep_law(**kwargs):
    kwargs = dict(dict(state=relaxed, state_rate=creep_rate, reference="static"), **kwargs)
    return skmoor.UserLaw(creep_tension, static=skmoor.Engineering(), tension_only=False,
                          **kwargs)


def test_the_viscoelastic_law_written_with_a_state_rate_moves_as_the_built_in_one():
    """``UserLaw(tension, state=relaxed, state_rate=rate, reference='static')``: the creep
    strain z starts relaxed at each element's static strain and is integrated within the
    step (the trapezoidal rule linearized at the accepted state): the same motion and
    tensions as the built-in Viscoelastic law (CreepTerm, its slopes by central
    differences: measured 3e-10 of the motion), compiled and in Python. Creep matters
    here: the fast limit StaticDynamic (no creep) moves 0.26 of the motion otherwise, a
    state started from the catenary 0.03, one advanced after the step only (explicit,
    first order) 0.01."""
    builtin = _viscoelastic()
    expected, motion = _runs_as(_creep_law(), builtin, offset=0.5, amplitude=0.3)
    variants = {
        "fast limit": skmoor.laws.StaticDynamic(EA_dynamic=EA_DYNAMIC),
        "from the catenary": _creep_law(reference="line"),
        "explicit": _creep_law(state_rate=None, update=lambda e, r, s, dt: (
            s[0] + dt * creep_rate(e, r, s, None)[0],)),
    }
    for name, law in variants.items():
        other, _ = _history(*_chain(law, offset=0.5, amplitude=0.3))
        assert np.abs(other - expected).max() > 1e-3 * motion, name


def test_without_jax_the_creep_law_runs_on_numpy_as_the_built_in_one(monkeypatch):
    """Without JAX (skmoor's optional extra) a law's form runs on NumPy (path 'fd': the
    state's slopes by central differences, its update in NumPy): the viscoelastic user
    law still moves the chain and reports tensions as the built-in law (measured 6e-11)."""
    from skmoor.fem import terms

    builtin = _viscoelastic()
    expected, tension_builtin = _history(*_chain(builtin, offset=0.5, amplitude=0.3),
                                         steps=20)
    monkeypatch.setattr(terms, "HAS_JAX", False)
    system, x0 = _chain(_creep_law(), offset=0.5, amplitude=0.3)
    assert [t.path for t in system._terms["lines"] if hasattr(t, "path")] == ["fd"]
    got, tension = _history(system, x0, compiled=False, steps=20)
    motion = np.abs(expected - expected[0]).max()
    assert np.abs(got - expected).max() < 1e-9 * motion
    assert np.abs(tension - tension_builtin).max() < 1e-9 * tension_builtin.max()


RELAX = 0.1  # s: MoorDyn's start relaxes z = e this long with the ends held


def moordyn_start(e_static, T_static):
    # z = e relaxed over RELAX in CreepTerm's 2000 trapezoidal steps: the rate is linear
    # in z, c + J z, so that each step multiplies z - z_inf by (1 + h J / 2) / (1 - h J / 2)
    h = RELAX / creep.RELAX_STEPS
    J = -(EA_1 + EA_DYNAMIC) / (CREEP_DAMPING + DYNAMIC_DAMPING)
    relaxed_z = relaxed(e_static, T_static)[0]
    ratio = (1.0 + 0.5 * h * J) / (1.0 - 0.5 * h * J)
    return (relaxed_z + (e_static - relaxed_z) * ratio**creep.RELAX_STEPS,)


def test_moordyns_start_of_the_creep_state_written_as_a_user_law():
    """MoorDyn's start (z = e relaxed for a while with the ends held: the built-in law's
    ``relax``) as the user law's initial state, ``balanced=False`` (it does not balance
    the static tension, so the line moves from its static state at t = 0): the same
    motion and tensions as the built-in law (measured 2e-10 of the motion); without the
    relaxation (z = e) it moves 0.1 of the motion otherwise, and a line refuses such a
    state without ``balanced=False``."""
    builtin = _viscoelastic(relax=RELAX)
    law = _creep_law(state=moordyn_start, balanced=False)
    expected, motion = _runs_as(law, builtin, offset=0.5, amplitude=0.3)
    unrelaxed, _ = _history(*_chain(_creep_law(state=lambda e, T: (e,), balanced=False),
                                    offset=0.5, amplitude=0.3))
    assert np.abs(unrelaxed - expected).max() > 1e-2 * motion
    with pytest.raises(ValueError, match="must be that tension"):
        _chain(_creep_law(state=moordyn_start))


@pytest.mark.parametrize("kwargs, message", [
    (dict(state=lambda e, T: (e,)), r"the initial state there\) must be that tension"),
    (dict(state=[0.0], balanced=False), "balanced: False is for an initial state given"),
    (dict(state=lambda e, T: (e / 0.0,)), "initial state is not finite"),
    (dict(state=lambda e, T: (), ), "returned no values"),
    (dict(state_rate=lambda e, r, s, ref: (s[0], s[0])), "state_rate: returned 2 values"),
    (dict(update=lambda e, r, s, dt: (s[0], s[0])), "update: returned 2 values"),
    (dict(update=1.0), "update.*or state_rate.*or both"),
    (dict(reference=False), "need a law of a reference state"),
])
def test_a_bad_state_rate_law_is_refused_with_its_reason(kwargs, message):
    """A state that does not start in equilibrium with the static law (z = e, not
    relaxed: found on the line, where its EA is known), not finite, empty; a rate or an
    update beside it of the wrong length; an update that is no function; a state
    function without a reference."""
    with pytest.raises(ValueError, match=message):
        law = _creep_law(**kwargs)
        _chain(law)


# --- a law with a rate and an update: MoorDyn's Syrope rope written as a user's

SYROPE_T_MAX0, SYROPE_T_MEAN0 = 1.3886e6, 4.339e5  # N: MoorDyn's SYROPE IC Tmax0, Tmean0


def _syrope_creep(form="quadratic", k1=0.25, k2=1.0, points=8):
    """The built-in Syrope rope with its creep state (a small working-curve table)."""
    return syrope.syrope_law(SYROPE_OWC, form, k1, k2, SYROPE_T_MAX0, SYROPE_ALPHA,
                             SYROPE_BETA, T_mean=SYROPE_T_MEAN0, points=points,
                             creep_damping=CREEP_DAMPING, dynamic_damping=DYNAMIC_DAMPING)


@pytest.mark.parametrize("form, k1, k2", [("linear", 1.25e8, 0.0), ("linear", 0.3, 0.0),
                                          ("quadratic", 0.4, 0.5), ("exp", 0.2, 1.5)])
def test_syropes_user_law_has_the_working_curves_of_the_built_in_one(form, k1, k2):
    """``SyropeCreep.user_law()``, its working curve traced as a function of T_max
    (``ops.interp`` on a table of the state): the creep spring's tension and the rate
    of z as the built-in law's tables (``working_curve``, ``np.interp``) give them, for
    each WCType, on curves of T_max from Tmax0 to past the OWC's points (those below
    T_max dropped) and at creep strains from slack to beyond the table."""
    builtin = _syrope_creep(form, k1, k2, points=30)
    law = builtin.user_law()
    z = np.linspace(-0.005, 0.06, 400)
    strain = z + 0.004
    for T_max in (SYROPE_T_MAX0, 2.0e6, 2.45e6, 3.0e6):
        memory = np.full(z.shape, T_max)
        state = (z, memory)
        a, b = builtin.creep_drive(z, None, memory)
        F_1 = builtin.creep_spring(z, None, memory)
        rate = law.state_rate(strain, 0.0 * z, state, None)
        assert np.abs(rate[0] - (a * strain - b) / (CREEP_DAMPING + DYNAMIC_DAMPING)).max() \
            < 1e-9 * np.abs(rate[0]).max()
        assert np.all(rate[1] == 0.0)
        tension = law.function(strain, 0.0 * z, state, None) - CREEP_DAMPING * rate[0]
        assert np.abs(tension - F_1).max() < 1e-9 * T_max
        assert np.abs(law.update(strain, 0.0, state, 0.1)[1] - np.maximum(T_max, F_1)).max() \
            < 1e-9 * T_max


def test_syropes_creep_written_with_a_rate_and_an_update_moves_as_the_built_in_one():
    """MoorDyn's Syrope rope (SyropeCreep: CreepTerm's kernel, its working-curve tables
    rebuilt in compiled code) as a user law (``SyropeCreep.user_law``) whose state is
    (z, T_max): the creep strain by its rate, the highest mean tension by an update
    after each step. The fairlead pulls the rope past Tmax0, so the working curve moves:
    the same motion, tensions, creep strains and highest tensions as the built-in law
    (measured 2e-10 of the motion), compiled and in Python. Without the update (Tmax0
    kept) the motion is 2 % otherwise."""
    builtin = _syrope_creep()
    law = builtin.user_law()
    systems = {}
    for name, each in (("builtin", builtin), ("user", law)):
        system, x0 = _chain(each, offset=2.0)
        systems[name] = system, x0, _history(system, x0)
    expected, tension_builtin = systems["builtin"][2]
    got, tension = systems["user"][2]
    motion = np.abs(expected - expected[0]).max()
    assert compiled_step.lowered_terms(systems["user"][0])[0] is None
    assert np.abs(got - expected).max() < 1e-9 * motion
    assert np.abs(tension - tension_builtin).max() < 1e-9 * tension_builtin.max()
    term = next(t for t in systems["builtin"][0]._terms["lines"]
                if isinstance(t, creep.CreepTerm))
    highest = term.memory[0]
    assert highest.max() > SYROPE_T_MAX0 * 1.01  # measured 1.016: the curve moved
    form = next(t for t in systems["user"][0]._terms["lines"]
                if getattr(t, "name", None) == law.label)
    states = form.state_values()
    assert np.abs(states["law_state_1"][:, 0] - highest).max() < 1e-9 * SYROPE_T_MAX0
    assert np.abs(states["law_state_0"][:, 0] - term.z).max() < 1e-9 * np.abs(term.z).max()
    slow, _ = _history(*systems["user"][:2], compiled=False)
    assert np.abs(slow - got).max() < 1e-9 * motion


def test_syropes_user_law_needs_its_start():
    with pytest.raises(ValueError, match="needs Tmean0"):
        syrope.syrope_law(SYROPE_OWC, "linear", 0.3, 0.0, SYROPE_T_MAX0, SYROPE_ALPHA,
                          SYROPE_BETA, creep_damping=CREEP_DAMPING,
                          dynamic_damping=DYNAMIC_DAMPING).user_law()
