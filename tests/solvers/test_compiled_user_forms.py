"""A user's LineForm inside the compiled time step (its generated kernel called there).

Independent numbers: the Python step of ``dynamics.integrate`` on the same model (the
form evaluated by its own engine through ``System.residual``), and the built-in Morison
drag (a hand-written kernel of the same physics). A form the compiled step did not call,
called at the wrong time (the step's start instead of its end), with another form's
arrays, or with its tangent dropped would make the histories differ by far more than
round-off.
"""
import numpy as np
import pytest
from skfem import LinearForm
from test_compiled_step import run

import skmoor
from skmoor.fem import ops
from skmoor.fem.ops import d_ds, dot
from skmoor.solvers import compiled_step
from skmoor.solvers.dynamics import Scheme

pytest.importorskip("jax")

CD = 1.2  # MoorDyn's normal drag coefficient


@LinearForm
def normal_drag(v, w):
    # + 1/2 rho Cd d |v_n| v_n . du per unit reference length (w.m / mass: 1 / stretch)
    rp = w.Xp + d_ds(w.u)
    tau = rp / ops.norm(rp)
    vn = w.du - dot(w.du, tau) * tau
    return w.k * (w.m / w.mass) * ops.norm(vn) * dot(vn, v)


@LinearForm
def swaying_load(v, w):
    # - q0 sin(omega t) e_y . du: a distributed load in time (N/m)
    return -w.q0 * ops.sin(w.omega * w.t) * v.value[1]


def drag_term(model):
    steel = model.lines.lines[0].line_type
    k = 0.5 * skmoor.paper_case().water["density"] * CD * steel.diameter
    return skmoor.LineForm(normal_drag, fields={"k": k, "mass": steel.mass}, path="compiled")


def load_term():
    return skmoor.LineForm(swaying_load, fields={"q0": 300.0, "omega": 2.0},
                           path="compiled")


def _paper(*terms):
    model = skmoor.build(skmoor.paper_case())
    for make in terms:
        model.add(make(model) if make is drag_term else make())
    return model


@pytest.fixture(scope="module")
def models():
    """Paper case + user drag; + the swaying load; + both; the built-in drag."""
    builtin = skmoor.build(skmoor.paper_case().replace("line_types.steel.Cd_n", CD))
    return (_paper(drag_term), _paper(load_term), _paper(drag_term, load_term), builtin)


def _runs(model, steps=60, dt=0.05):
    eq = skmoor.equilibrium(model)
    v0 = np.zeros(model.system.n)
    v0[model.system.nf:model.system.nf + 2] = [0.3, -0.2]  # a push: the drag works
    fast, it_fast = run(model.system, eq.x, v0, dt, steps, C=eq.C, compiled=True,
                        scheme=Scheme.newmark())
    slow, it_slow = run(model.system, eq.x, v0, dt, steps, C=eq.C, compiled=False,
                        scheme=Scheme.newmark())
    # the same Newton iterations: the terms' tangents are in the compiled Newton matrix
    assert np.array_equal(it_fast, it_slow)
    return fast, slow


@pytest.mark.parametrize("which", ["drag", "load", "both"])
def test_user_forms_run_in_the_compiled_step_as_in_python(models, which):
    model = models[("drag", "load", "both").index(which)]
    why, kinds = compiled_step.lowered_terms(model.system)
    assert why is None and len(kinds["form"]) == (2 if which == "both" else 1)
    fast, slow = _runs(model)
    motion = np.abs(slow - slow[0]).max()
    assert motion > 1e-2
    assert np.abs(fast - slow).max() < 1e-9 * motion


def test_user_drag_in_the_compiled_step_is_the_built_in_drag(models):
    """The generated kernel of the user's drag against the hand-written Morison kernel:
    both runs compiled, the same history to round-off (and unlike the run without drag)."""
    user, builtin = models[0], models[3]
    assert compiled_step.lowered_terms(builtin.system)[0] is None
    user_run, _ = _runs(user, steps=40)
    eq = skmoor.equilibrium(builtin)
    v0 = np.zeros(builtin.system.n)
    v0[builtin.system.nf:builtin.system.nf + 2] = [0.3, -0.2]
    reference, _ = run(builtin.system, eq.x, v0, 0.05, 40, C=eq.C, scheme=Scheme.newmark())
    undamped, _ = run(skmoor.build(skmoor.paper_case()).system, eq.x, v0, 0.05, 40, C=eq.C,
                      scheme=Scheme.newmark())
    motion = np.abs(reference - reference[0]).max()
    assert np.abs(user_run - reference).max() < 1e-9 * motion
    assert np.abs(undamped - reference).max() > 1e-4 * motion  # the drag matters


def test_a_form_with_fields_in_time_is_named_as_python():
    """Fields given as a function of time are evaluated in Python: the step says so."""
    model = skmoor.build(skmoor.paper_case())
    model.add(skmoor.LineForm(swaying_load, path="compiled", name="sway",
                              fields=lambda t: {"q0": 300.0, "omega": 2.0}))
    why, _ = compiled_step.lowered_terms(model.system)
    assert why.startswith("sway on the lines") and "function of time" in why


# --- user point and body loads (their generated C functions called in the step)

DAMPING = np.diag([4e4, 4e4, 1e5, 2e6, 2e6, 1e6])  # N s/m, N m s


def damper(q, qdot, t):
    # a linear damper on the body, F = -B qdot (N, N m), written with jax.numpy-friendly ops
    return -(ops.xp(qdot).asarray(DAMPING) @ qdot)


def test_a_user_body_load_is_the_built_in_linear_damping():
    """The paper case with a user's body damper runs compiled, as its Python step, and as
    the same damping given as the body's linear_damping (the built-in restoring kernel)."""
    user = skmoor.build(skmoor.paper_case())
    term = user.add(skmoor.BodyLoad(damper, body=0))
    assert term.lowered() == "body load", term.why_python
    assert compiled_step.lowered_terms(user.system)[0] is None
    builtin = skmoor.build(skmoor.paper_case())
    builtin.system.bodies[0].linear_damping[:] = DAMPING  # read by its restoring term
    fast, slow = _runs(user, steps=40)
    reference, _ = _runs(builtin, steps=40)
    motion = np.abs(slow - slow[0]).max()
    assert np.abs(fast - slow).max() < 1e-9 * motion
    assert np.abs(fast - reference).max() < 1e-9 * motion
    plain, _ = _runs(skmoor.build(skmoor.paper_case()), steps=40)
    assert np.abs(plain - reference).max() > 1e-3 * motion  # the damper matters


def test_a_body_load_of_its_state_runs_compiled_explicit_as_in_python():
    """The body's own applied load f(t, q, qdot) (``Body.load``: explicit, no tangent), a
    damper of its velocity written with jax.numpy: the compiled step calls its kernel at
    each iterate as the Python step does (the same iterations: no tangent in either
    matrix; the same motion to round-off: a load taken once per step, at the step's start
    state, or twice, would part them), and it is the built-in linear damping's root to the
    Newton tolerance. In NumPy it does not trace: the refusal names it."""
    def applied(t, q, qdot):
        return damper(q, qdot, t)

    def free_decay(load=None):  # the paper case from a push, its wave load taken off
        model = skmoor.build(skmoor.paper_case())
        model.system.body_loads[0] = load
        return model

    model = free_decay(applied)
    assert compiled_step.lowered_terms(model.system)[0] is None
    builtin = free_decay()
    builtin.system.bodies[0].linear_damping[:] = DAMPING
    fast, slow = _runs(model, steps=40)
    reference, _ = _runs(builtin, steps=40)
    plain, _ = _runs(free_decay(), steps=40)
    motion = np.abs(slow - slow[0]).max()
    assert np.abs(fast - slow).max() < 1e-9 * motion
    assert np.abs(fast - reference).max() < 1e-5 * motion  # measured 8e-8
    assert np.abs(plain - reference).max() > 1e-3 * motion  # the damper matters
    model.system.body_loads[0] = lambda t, q, qdot: -(DAMPING @ np.asarray(qdot))
    why, _ = compiled_step.lowered_terms(model.system)
    assert why.startswith("AppliedLoad on the bodies") and "does not trace with JAX" in why


def test_a_user_point_load_runs_in_the_compiled_step_as_in_python():
    """A free clump pushed sideways in time and held by a spring on its own position: the
    load's value, its derivative in the Newton matrix and the time it is called at."""
    from test_network import network_two_bodies

    model = skmoor.from_network(network_two_bodies())

    def push(x, v, t):
        return ops.xp(x).stack([3e3 * ops.sin(1.5 * t) - 2e3 * x[0], -2e3 * x[1],
                                0.0 * x[2]])

    term = model.add(skmoor.PointLoad(push, point="J"))
    assert term.lowered() == "point load", term.why_python
    system = model.system
    eq = skmoor.equilibrium(model)
    v0 = np.zeros(system.n)
    fast, it_fast = run(system, eq.x, v0, 0.05, 60, compiled=True)
    slow, it_slow = run(system, eq.x, v0, 0.05, 60, compiled=False)
    assert np.array_equal(it_fast, it_slow)
    motion = np.abs(slow - slow[0]).max()
    assert motion > 1e-2
    assert np.abs(fast - slow).max() < 1e-9 * motion


def test_a_generated_load_is_made_once_for_its_code_not_per_function_object():
    """Two function objects of the same code (a factory's) give one generated module: its
    label names the function, not its address, so a new process finds the same source
    and numba's cache (an address in the label made every run compile again)."""
    def make():
        def spring(q, qdot, t):
            return -(ops.xp(q).asarray(DAMPING) @ q)
        return spring

    first, second = make(), make()
    assert first is not second and repr(first) != repr(second)
    loads = [skmoor.BodyLoad(f, body=0) for f in (first, second)]
    model = skmoor.build(skmoor.paper_case())
    for load in loads:
        model.add(load)
        assert load.lowered() == "body load", load.why_python
    assert loads[0].step_load is loads[1].step_load


def _chain_on_the_bed(generated):
    """A 20-element chain lying on a bed 150 m down for half of its length, its
    fairlead moved 2 m out and up from rest, with drag and added mass in still water: the bed and Morison
    terms as the hand kernels or as the kernels generated from their forms (the
    definitions, on path 'compiled'). (system, static state)"""
    from skmoor.lines.catenary import solve_catenary
    from skmoor.sea import hydro
    from skmoor.sea.seabed import Seabed, SeabedKernel, form_term

    chain = skmoor.LineType(EA=7.5e8, mass=140.0, diameter=0.09, Cd_n=1.2, Cd_t=0.1,
                            Ca_n=1.0)
    cat = solve_catenary([-300.0, 0.0, -150.0], [0.0, 0.0, -5.0], chain.weight, chain.EA,
                         length=420.0, seabed_z=-150.0)
    lines = skmoor.LineSet([skmoor.Line.from_catenary(cat, chain, 20)])
    bed = Seabed(depth=150.0)
    terms = ([form_term(lines, bed, path="compiled"), *hydro.form_terms(lines, path="compiled")]
             if generated else [SeabedKernel(lines, bed), hydro.line_hydrodynamics(lines)])
    system = skmoor.System(lines, fairleads="prescribed", terms=terms, motion=lambda t: np.array(
        [[1.0 - np.cos(0.6 * t), 0.0, 1.0 - np.cos(0.6 * t)]]))  # from rest
    return system, skmoor.solve_static(system).x


def test_the_bed_and_morison_forms_run_compiled_as_their_hand_kernels():
    """The sea bed's and Morison's forms on path 'compiled' (what ``Network.form_path``
    gives bending lines) run in the compiled step although no node touches and the water
    is still when it is made (their add_to skips those), land on the bed in its Newton
    iteration as the kernel does, and move the chain as the hand kernels (measured 1e-14
    of the motion apart, 13 of its 21 nodes on the bed)."""
    forms, x_forms = _chain_on_the_bed(True)
    hand, x_hand = _chain_on_the_bed(False)
    assert np.abs(x_forms - x_hand).max() < 1e-9 * np.abs(x_hand).max()
    why, kinds = compiled_step.lowered_terms(forms)
    assert why is None and {t.name for t in kinds["form"]} == {"seabed", "morison_drag"}
    assert forms.bed_landing is not None
    got, _ = run(forms, x_forms, np.zeros(forms.n), 0.1, 60, scheme=Scheme.newmark())
    expected, _ = run(hand, x_hand, np.zeros(hand.n), 0.1, 60, scheme=Scheme.newmark())
    motion = np.abs(expected - expected[0]).max()
    assert motion > 1.0
    assert np.abs(got - expected).max() < 1e-10 * motion


def _moves_as(system, x0, reference, x_reference, dt, steps=60):
    """60 compiled steps of dt from rest of ``system`` and of ``reference`` (both
    Newmark): the same motion to 1e-10 of it, and ``system``'s Python step the same
    too. Returns the reference's states and the size of its motion (m)."""
    got, _ = run(system, x0, np.zeros(system.n), dt, steps, scheme=Scheme.newmark())
    expected, _ = run(reference, x_reference, np.zeros(reference.n), dt, steps,
                      scheme=Scheme.newmark())
    motion = np.abs(expected - expected[0]).max()
    assert np.abs(got - expected).max() < 1e-10 * motion
    slow, _ = run(system, x0, np.zeros(system.n), dt, steps, scheme=Scheme.newmark(),
                  compiled=False)
    assert np.abs(slow - got).max() < 1e-10 * motion
    return expected, motion


def _chain_in_waves(generated, EI=0.0, sea="waves"):
    """A 20-element chain (bending stiffness EI, N m2: > 0 on Hermite elements) in a
    sheared current and an Airy wave across it, its fairlead moved 2 m out and up from
    rest: the Morison terms as the hand kernel or as the kernels generated from their
    forms (path 'compiled'). (system, static state)"""
    from skmoor.lines.catenary import solve_catenary
    from skmoor.sea import AiryWave, Current, Sea, hydro

    sea = Sea(150.0, current=Current(profile=[(-150.0, 0.1), (0.0, 0.8)], heading_deg=30.0),
              waves=[AiryWave(3.0, 9.0, 150.0, heading_deg=-20.0)] if sea == "waves" else [])
    chain = skmoor.LineType(EA=7.5e8, mass=140.0, diameter=0.09, Cd_n=1.2, Cd_t=0.1,
                            Ca_n=1.0, EI=EI)
    cat = solve_catenary([-300.0, 0.0, -150.0], [0.0, 0.0, -5.0], chain.weight, chain.EA,
                         length=336.0)
    lines = skmoor.LineSet([skmoor.Line.from_catenary(cat, chain, 20)])
    lumped = not lines.hermite
    terms = (hydro.form_terms(lines, sea, path="compiled", lumped_mass=lumped) if generated
             else [hydro.line_hydrodynamics(lines, sea, lumped_mass=lumped)])
    system = skmoor.System(lines, fairleads="prescribed", terms=terms, motion=lambda t: np.array(
        [[1.0 - np.cos(0.6 * t), 0.0, 1.0 - np.cos(0.6 * t)]]))  # from rest
    return system, skmoor.solve_static(system).x


@pytest.mark.parametrize("EI", [0.0, 2e5])
def test_forms_in_a_current_and_waves_run_compiled_as_the_hand_kernel(EI):
    """Morison's forms (drag on the water's velocity ``w.uw``, fluid inertia on its
    acceleration ``w.aw``, in one ``SeaTerm`` with water='both') in a sheared current
    and Airy waves run in the compiled step, the water evaluated at the displaced nodes
    in compiled code before their generated kernel: the motion of the hand kernel to
    round-off (measured 3e-15), on P1 and bending lines, and the Python step's. Still
    water would move the chain 3 % otherwise, the current alone 1 %: a water field left
    at its first values, or the velocity read as the acceleration, would fail."""
    forms, x_forms = _chain_in_waves(True, EI)
    hand, x_hand = _chain_in_waves(False, EI)
    assert np.abs(x_forms - x_hand).max() < 1e-9 * np.abs(x_hand).max()
    why, kinds = compiled_step.lowered_terms(forms)
    assert why is None
    assert "morison_in_waves" in {getattr(t, "name", "") for t in kinds["form"]}
    expected, motion = _moves_as(forms, x_forms, hand, x_hand, 0.1)
    current, x_current = _chain_in_waves(False, EI, sea="current")
    other, _ = run(current, x_current, np.zeros(current.n), 0.1, 60, scheme=Scheme.newmark())
    assert np.abs(other - expected).max() > 1e-3 * motion


@LinearForm
def more_bending(v, w):
    # the bending stiffness's own form, int k (X'' + u'') . v'' ds: u'' and v'' the
    # fields' second derivatives on bending lines
    return w.k * dot(w.Xpp + w.u.hess[:, 0, 0], v.hess[:, 0, 0])


def _bending_riser(EI, extra=None):
    """A 20-element flexible riser (bending stiffness EI, N m2) hung from a fairlead moved
    1 m at 0.8 rad/s, with ``extra`` more stiffness (N m2) as a user's form on path
    'compiled': (system, static state)."""
    from skmoor.lines.catenary import solve_catenary

    riser = skmoor.LineType(EA=2e8, mass=150.0, diameter=0.3, EI=EI)
    cat = solve_catenary([-150.0, 0.0, -150.0], [0.0, 0.0, -5.0], riser.weight, riser.EA,
                         length=240.0)
    lines = skmoor.LineSet([skmoor.Line.from_catenary(cat, riser, 20)])
    terms = [] if extra is None else [skmoor.LineForm(more_bending, fields={"k": extra},
                                                      path="compiled", lines=lines)]
    system = skmoor.System(lines, fairleads="prescribed", terms=terms, motion=lambda t: np.array(
        [[np.sin(0.8 * t), 0.0, np.sin(0.8 * t)]]))
    return system, skmoor.solve_static(system).x


def test_a_form_of_second_derivatives_runs_compiled_as_the_line_types_bending():
    """On bending lines a form may read u'' (``w.u.hess[:, 0, 0]``) and act on v''
    (``v.hess[:, 0, 0]``): its kernel is generated with the cubics' second derivatives.
    Part of a riser's bending stiffness written so (3/4 of it) runs in the compiled step
    and moves the riser as the line type with all of it in its EI (the hand kernel): the
    same static state and motion to 1e-10 (measured 5e-13), and the element residual and
    blocks to round-off; the riser with the form left out moves otherwise."""
    EI = 4e8
    split, x_split = _bending_riser(0.25 * EI, 0.75 * EI)
    whole, x_whole = _bending_riser(EI)
    assert np.abs(x_split - x_whole).max() < 1e-10 * np.abs(x_whole).max()
    lines, form = split.lines, split.terms[-1]
    u, v = np.random.default_rng(2).standard_normal((2, lines.ndofs)) * [[1e-2], [1e-1]]
    blocks = []
    for kernel in (split.kernel, whole.kernel, form):  # the form: the kernels' difference
        R, K = np.zeros(lines.ndofs), np.zeros((len(lines.element_dofs), 12, 12))
        kernel.add_to(*((u, v, 0.0) if kernel is form else (u, v)), R, K, np.zeros_like(K))
        blocks.append((R, K))
    for k in range(2):
        difference = blocks[1][k] - blocks[0][k]
        assert np.abs(blocks[2][k] - difference).max() < 1e-12 * np.abs(difference).max()
    why, kinds = compiled_step.lowered_terms(split)
    assert why is None and "more_bending" in {getattr(t, "name", "") for t in kinds["form"]}
    expected, motion = _moves_as(split, x_split, whole, x_whole, 0.05)
    softer, x_softer = _bending_riser(0.25 * EI)
    other, _ = run(softer, x_softer, np.zeros(softer.n), 0.05, 60, scheme=Scheme.newmark())
    assert np.abs(other - expected).max() > 1e-2 * motion


DRIFT_DT = 0.1  # s
PULL = 50.0  # N/m per m of water passed


@LinearForm
def pull_of_passed_water(v, w):
    # - k s_x v_x: a pull against the water passed at each point, s = int u_w dt (memory)
    return PULL * w.s * v.value[0]


def passed_water(w):
    # s_new = s + dt u_w,x: explicit, the residual within a step sees the last accepted s
    return {"s": w.s + w.dt * w.uw.value[0]}


@LinearForm
def pull_in_time(v, w):
    # the same in a uniform current U_x: s = U_x (t - dt) within the step to t
    return PULL * w.U * ops.maximum(w.t - DRIFT_DT, 0.0) * v.value[0]


def test_a_form_in_the_water_with_a_memory_runs_compiled():
    """A SeaTerm with a memory (per point, the water passed, s = int u_w dt, advanced
    after each step from the water at the displaced nodes) runs in the compiled step,
    its commit after the water too: in a uniform current it moves the chain as the same
    pull written in time (s = U t), to 1e-10 of the motion, and as its Python step."""
    from skmoor.lines.catenary import solve_catenary
    from skmoor.sea import Current, Sea, SeaTerm

    current = Current(0.8, 30.0)  # m/s, deg
    sea = Sea(150.0, current=current)
    chain = skmoor.LineType(EA=7.5e8, mass=140.0, diameter=0.09)
    cat = solve_catenary([-300.0, 0.0, -150.0], [0.0, 0.0, -5.0], chain.weight, chain.EA,
                         length=336.0)

    def chain_with(make):
        lines = skmoor.LineSet([skmoor.Line.from_catenary(cat, chain, 20)])
        system = skmoor.System(lines, fairleads="prescribed", terms=[make(lines)],
                               motion=lambda t: np.zeros((1, 3)))
        return system, skmoor.solve_static(system).x

    remembering, x0 = chain_with(lambda lines: SeaTerm(
        pull_of_passed_water, sea=sea, state={"s": 0.0}, update=passed_water,
        path="compiled", lines=lines))
    U = float(current.velocity(np.zeros((1, 3)), 0.0)[0, 0])
    in_time, x_time = chain_with(lambda lines: skmoor.LineForm(
        pull_in_time, fields={"U": U}, path="compiled", lines=lines))
    why, kinds = compiled_step.lowered_terms(remembering)
    assert why is None and kinds["form"][0].step_commit is not None
    expected, motion = _moves_as(remembering, x0, in_time, x_time, DRIFT_DT, steps=40)
    assert motion > 0.1
