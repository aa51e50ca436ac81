"""The term protocol: automatic tangents of forms (generated numba kernels, jax.jit,
skfem.autodiff, central differences) against the hand-written tangents of the built-in
terms, the Taylor test, and terms in statics and the mass matrix through Model.add."""
import numpy as np
import pytest
from skfem import BilinearForm, LinearForm

import skmoor
from skmoor.bodies.loads import BodyLoad, PointLoad
from skmoor.fem import form_compiler as compiled
from skmoor.fem import ops, terms
from skmoor.fem.terms import LineForm, check_tangent
from skmoor.lines.catenary import solve_catenary
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.sea import hydro
from skmoor.sea.seabed import form_term

pytest.importorskip("jax")

ROPE = LineType(EA=5e8, mass=80.0, diameter=0.12, Cd_n=1.2, Cd_t=0.3, Ca_n=1.0, Ca_t=0.5)


@pytest.fixture(scope="module")
def lines():
    cat = solve_catenary([0.0, 0.0, -60.0], [90.0, 20.0, -5.0], ROPE.weight, ROPE.EA,
                         length=115.0)
    return LineSet([Line.from_catenary(cat, ROPE, 14)], law="engineering")


def state(lines, seed=0):
    rng = np.random.default_rng(seed)
    return 0.05 * rng.standard_normal(lines.ndofs), 0.4 * rng.standard_normal(lines.ndofs)


def dense(term, u, v, t=0.0):
    return term.evaluate(u, v, t, True, "dense")


def close(a, b, rtol):
    """Largest difference relative to the largest entry of b."""
    return np.max(np.abs(a - b)) <= rtol * max(np.max(np.abs(b)), 1e-300)


class UniformWater(skmoor.Sea):
    """Water moving and accelerating uniformly (the forms' d/du has no water gradient
    to miss, so the hand tangents are exact)."""

    def __init__(self):
        super().__init__(100.0, current=skmoor.Current(0.0))
        self.waves = ["uniform"]

    def velocity(self, points, t=0.0):
        return np.broadcast_to([0.4, -0.3, 0.2], np.shape(points)) * (1 + 0.1 * t)

    def acceleration(self, points, t=0.0):
        return np.broadcast_to([0.5, 0.2, -0.7], np.shape(points)).copy()


@pytest.mark.parametrize("path, rtol", [("compiled", 1e-10), ("autodiff", 1e-10),
                                        ("fd", 1e-6)])
def test_automatic_tangents_of_the_morison_forms_equal_the_hand_tangents(lines, path, rtol):
    """Drag on the relative velocity and the fluid inertia in moving water: residual,
    d/du and d/dv from the residual alone (one form of both, water='both') equal the
    hand-written BilinearForms (two terms)."""
    sea = UniformWater()
    u, v = state(lines)
    hand, auto = hydro.form_terms(lines, sea), hydro.form_terms(lines, sea, path=path)
    assert len(hand) == 2 and len(auto) == 1
    R0, K0, C0 = (sum(parts) for parts in zip(*(dense(term, u, v, 2.0) for term in hand)))
    R1, K1, C1 = dense(auto[0], u, v, 2.0)
    assert close(R1, R0, 1e-13) and close(K1, K0, rtol) and close(C1, C0, rtol)
    if path == "compiled":
        assert auto[0].backend == "numba"


@pytest.mark.parametrize("friction", [True, False])
def test_automatic_tangent_of_the_seabed_equals_the_hand_tangent(friction):
    """Contact with a faded-in damping and regularised Coulomb friction on a sloped bed."""
    from test_seabed import contact_state  # chains partly buried in a sloped bed

    lines, bed, u, v = contact_state(friction=friction)
    R0, K0, C0 = dense(form_term(lines, bed), u, v)
    R1, K1, C1 = dense(form_term(lines, bed, path="compiled"), u, v)
    assert close(R1, R0, 1e-13) and close(K1, K0, 1e-10) and close(C1, C0, 1e-10)


@LinearForm
def nonlinear_spring(v, w):
    # a made-up term using the generator's operations: int f(u, u', udot, t) . v + g . v' ds
    up, speed = ops.d_ds(w.u), ops.norm(w.du)
    u = ops.value(w.u)
    f = (w.k * ops.tanh(u) + w.c * ops.exp(-speed) * w.du
         + ops.where(u > 0, ops.sqrt(1 + u ** 2), ops.abs(u)))
    g = w.EA * 1e-6 * ops.maximum(ops.dot(up, up), 1e-4) * up / (1 + ops.clip(w.t, 0, 1))
    return ops.dot(f, v) + ops.dot(g, ops.d_ds(v)) + w.q * ops.dot(w.Xp, v) * w.Xp[2]


def test_all_paths_agree_on_a_form_with_fields_in_time(lines):
    """compiled (numba), jax.jit, skfem.autodiff and central differences give one
    residual and one tangent for a form with P1, per-point and time-dependent fields."""
    nel, nqp = lines.basis.dx.shape
    k = np.linspace(1.0, 2.0, lines.ndofs)  # a P1 field (interpolated like u)

    def fields(t):
        return {"k": k, "c": np.full((nel, nqp), 3.0 + t), "q": 0.5}

    u, v = state(lines, 4)
    out = {path: dense(LineForm(nonlinear_spring, fields=fields, path=path, lines=lines),
                       u, v, 0.7) for path in ("compiled", "autodiff", "fd")}
    R0, K0, C0 = out["autodiff"]
    for path, rtol in (("compiled", 1e-12), ("fd", 1e-6)):
        R, K, C = out[path]
        assert close(R, R0, 1e-13) and close(K, K0, rtol) and close(C, C0, rtol), path


@LinearForm
def oscillating_spring(v, w):
    # every elementwise function of skmoor.fem.ops in one integrand
    up = ops.d_ds(w.u)
    s = ops.dot(up, up)
    g = (ops.sin(3.0 * s) + ops.cos(s) * ops.exp(-s) + ops.tanh(s) + ops.log(1.0 + s)
         + ops.sqrt(1.0 + s) + ops.abs(w.u[0]) + ops.minimum(s, 0.5)
         + ops.interp(s, [0.0, 1e-3 * (1.0 + s), 0.1], [0.0, 2.0, 1.0])
         + ops.arctan2(s - 0.01, 1.0 - 30.0 * s) + ops.mod(40.0 * s, 0.3)) * up
    return 1e3 * ops.dot(g + ops.cross(up, ops.value(w.du)), ops.d_ds(v))


@LinearForm
def softening_bending(v, w):
    # a bending moment k |kappa| kappa that grows with the curvature's change kappa = u''
    # and a damping of its rate, on v'' (the second derivatives of bending lines)
    kappa = w.u.hess[:, 0, 0]
    return w.k * (ops.norm(kappa) * ops.dot(kappa, v.hess[:, 0, 0])
                  + ops.dot(w.Xpp, v.hess[:, 0, 0]) + 0.1 * ops.dot(w.du.hess[:, 0, 0], v.hess[:, 0, 0]))


def test_a_form_of_second_derivatives_on_bending_lines_on_every_path():
    """On bending (Hermite) lines a form reads u'' and udot'' and acts on v'': the
    generated kernel (its cubics' second derivatives), NumPy with central differences
    and JAX on its own (the Hermite fields' hess) give scikit-fem's autodiff assembly
    (its basis' own second derivatives)."""
    rope = skmoor.LineType(EA=5e8, mass=100.0, diameter=0.1, EI=2e5)
    cat = solve_catenary([0.0, 0.0, -60.0], [90.0, 20.0, -5.0], rope.weight, rope.EA,
                         length=115.0)
    bending = LineSet([Line.from_catenary(cat, rope, 8)])
    u, v = state(bending, 3)
    out = {}
    for path in ("compiled", "autodiff", "fd", "jax"):
        term = LineForm(softening_bending, fields={"k": 1e5},
                        path="compiled" if path == "jax" else path, lines=bending)
        if path == "jax":
            term._engine = terms._jax_engine(term)
        out[path] = dense(term, u, v, 0.0)
        if path == "compiled":
            assert term.backend == "numba"
    R0, K0, C0 = out["autodiff"]
    for path, rtol in (("compiled", 1e-10), ("jax", 1e-10), ("fd", 1e-5)):
        R, K, C = out[path]
        assert close(R, R0, 1e-12) and close(K, K0, rtol) and close(C, C0, rtol), path


def test_interp_is_numpys_on_tables_of_numbers_and_of_arrays():
    """ops.interp, written as comparisons and one division: numpy.interp's values
    inside, at the knots and beyond both ends; a piece of no width is a step (numpy's
    jump, its value at the knot the one after it); a table whose points are arrays (a
    function of the state) interpolates point by point."""
    xs, ys = [0.0, 0.5, 0.5, 2.0, 3.0], [1.0, -1.0, -1.0, 4.0, 4.5]
    x = np.linspace(-1.0, 4.0, 101)
    assert np.abs(ops.interp(x, xs, ys) - np.interp(x, xs, ys)).max() < 1e-14
    jump = ([0.0, 1.0, 1.0, 2.0], [0.0, 1.0, 5.0, 6.0])
    x_jump = np.array([-0.5, 0.5, 1.0, 1.2, 1.5, 2.5])
    assert np.abs(ops.interp(x_jump, *jump) - np.interp(x_jump, *jump)).max() < 1e-14
    shift = np.linspace(0.0, 1.0, x.size)  # each point its own table
    moved = ops.interp(x, [k + shift for k in xs], ys)
    assert np.abs(moved - np.interp(x - shift, xs, ys)).max() < 1e-14


def test_every_elementwise_op_traces_and_compiles(lines):
    """sin, cos, exp, tanh, log, sqrt, abs, minimum, interp on a table of the state,
    arctan2, mod and cross in one form: the compiled kernel, the
    JAX tangent and central differences agree (a function missing from the compiler, or
    one with a wrong derivative rule, would not)."""
    u, v = state(lines, 5)
    terms_by_path = {path: LineForm(oscillating_spring, path=path, lines=lines)
                     for path in ("compiled", "autodiff", "fd")}
    out = {path: dense(term, u, v, 0.0) for path, term in terms_by_path.items()}
    assert terms_by_path["compiled"].backend == "numba"  # not JAX's fallback
    R0, K0, _ = out["autodiff"]
    assert close(out["compiled"][0], R0, 1e-12) and close(out["compiled"][1], K0, 1e-10)
    assert close(out["fd"][0], R0, 1e-12) and close(out["fd"][1], K0, 1e-5)


@LinearForm
def written_naturally(v, w):
    # the operators a user writes on fields: -u, 1 + u, abs(u), u > 0
    relative = -w.du
    return ops.dot((1.0 + ops.norm(relative)) * relative, v) + ops.dot(
        ops.where(w.u > 0.0, abs(w.u), 2.0 * w.u), ops.d_ds(v))


def test_fields_take_the_operators_users_write(lines):
    u, v = state(lines, 6)
    out = [dense(LineForm(written_naturally, path=path, lines=lines), u, v)
           for path in ("compiled", "autodiff", "fd")]
    for R, K, C in out[:2]:
        assert close(R, out[2][0], 1e-13) and close(K, out[2][1], 1e-6)
        assert close(C, out[2][2], 1e-6)
    assert close(out[0][1], out[1][1], 1e-12) and close(out[0][2], out[1][2], 1e-12)


def test_a_form_without_a_velocity_is_at_rest(lines):
    """The term protocol lets a caller give no velocity (a static state, end forces): a
    LineForm then runs at rest on every path. The Morison drag in a current is not zero
    there (a velocity passed on as None failed in the generated kernel and in scikit-fem's
    fields; zeros of the wrong kind would show in R)."""
    fields = hydro.coefficients(lines) | {"uw": np.full(lines.ndofs, 0.7)}
    u, _ = state(lines, 7)
    rest = np.zeros(lines.ndofs)
    out = []
    for path, v in (("compiled", None), ("compiled", rest), ("autodiff", None)):
        R = np.zeros(lines.ndofs)
        LineForm(hydro.morison_drag, fields=fields, path=path, lines=lines).add_to(u, v, 0.0, R)
        out.append(R)
    assert np.abs(out[0]).max() > 0
    assert close(out[0], out[1], 1e-15) and close(out[0], out[2], 1e-12)


def test_jax_jit_fallback_gives_the_same_numbers(lines, monkeypatch):
    """Where the scalar code generator meets an operation it lacks, jax.jit runs the form."""
    def refuse(*args, **kw):
        raise compiled.Unsupported("a test's primitive")

    monkeypatch.setattr(compiled, "build_kernel", refuse)
    u, v = state(lines, 5)
    fallback = LineForm(hydro.morison_drag, fields=hydro.coefficients(lines) | {
        "uw": np.zeros(lines.ndofs)}, path="compiled", lines=lines)
    R, K, C = dense(fallback, u, v)
    assert fallback.backend.startswith("jax.jit")
    hand = hydro.form_terms(lines)[0]
    R0, K0, C0 = dense(hand, u, v)
    assert close(R, R0, 1e-13) and close(K, K0, 1e-10) and close(C, C0, 1e-10)


def test_without_jax_the_forms_fall_back_to_central_differences(lines, monkeypatch):
    monkeypatch.setattr(terms, "HAS_JAX", False)
    assert LineForm(hydro.morison_drag).path == "fd"
    with pytest.raises(ValueError, match="needs JAX"):
        LineForm(hydro.morison_drag, path="compiled")


def test_taylor_test_tells_a_wrong_tangent_from_a_right_one(lines):
    """The drag with its exact d/dv shows slope 2; with the v_n v_n^T / |v_n| part
    dropped (a typical slip), slope 1."""
    @BilinearForm
    def incomplete_rate(dv, v, w):
        tau, _ = hydro._tangent(w)
        _, vn = hydro._split(w.uw - w.du, tau)
        _, dvn = hydro._split(dv, tau)
        return w.drag_n * ops.norm(vn) * ops.dot(dvn, v)

    system = skmoor.System(lines, fairleads="fixed")
    fields = hydro.coefficients(lines) | {"uw": np.zeros(lines.ndofs)}
    fields["drag_t"] = 0.0 * fields["drag_t"]
    good = check_tangent(system, LineForm(hydro.morison_drag, fields=fields))
    bad = check_tangent(system, LineForm(hydro.morison_drag, damping=incomplete_rate,
                                         stiffness=hydro.morison_drag_stiffness, fields=fields))
    assert good.ok and abs(good.slope_u - 2) < 0.2 and abs(good.slope_v - 2) < 0.2
    assert not bad.ok and abs(bad.slope_v - 1) < 0.2
    assert "TANGENT WRONG" in str(bad)


def test_body_load_tangents_by_jax_or_differences_and_the_taylor_test(paper):
    """A BodyLoad without a tangent: written with jax.numpy its derivatives come from JAX
    (equal to the analytic ones to round-off), written with NumPy from central
    differences; the Taylor slopes are 2 either way."""
    import jax.numpy as jnp

    def load(q, qdot, t, xp=np):
        zero = 0.0 * q[0]
        return xp.stack([-3e4 * q[0] ** 3, zero, -2e3 * qdot[2] * abs(qdot[2]), zero,
                         zero, zero])

    q = np.array([0.5, 0.0, 0.1, 0.0, 0.0, 0.0])
    qdot = np.array([0.2, 0.0, -0.3, 0.0, 0.0, 0.0])
    exact_q, exact_v = np.zeros((6, 6)), np.zeros((6, 6))
    exact_q[0, 0] = 9e4 * q[0] ** 2  # the residual's -dF/dq
    exact_v[2, 2] = 4e3 * abs(qdot[2])
    for xp, by, rtol in ((jnp, "jax", 1e-13), (np, "central differences", 1e-6)):
        term = BodyLoad(lambda a, b, t, xp=xp: load(a, b, t, xp))
        R, K, C = np.zeros(6), np.zeros((6, 6)), np.zeros((6, 6))
        term.add_to(q, qdot, 0.0, R, K, C)
        assert term.tangent_by == by
        np.testing.assert_allclose(K, exact_q, rtol=rtol, atol=rtol * 1e4)
        np.testing.assert_allclose(C, exact_v, rtol=rtol, atol=rtol * 1e3)
        check = check_tangent(paper, term, q, qdot)
        assert check.ok and abs(check.slope_u - 2) < 0.3 and abs(check.slope_v - 2) < 0.3


@pytest.fixture(scope="module")
def paper():
    return skmoor.build(skmoor.paper_case())


def test_body_load_acts_in_statics_and_its_mass_enters(paper):
    """A steady surge force F on the box: at equilibrium the lines' horizontal pull
    balances it (hydrostatics has no surge stiffness); its added mass is in M."""
    model = skmoor.build(skmoor.paper_case())
    F = 2.0e4  # N
    added = np.diag([5e4, 0, 0, 0, 0, 0])
    M0 = model.system.M.toarray()
    model.add(BodyLoad(lambda q, qdot, t: np.array([F, 0, 0, 0, 0, 0]), body="body",
                       added_mass=added, tangent=lambda q, qdot, t: (None, None)))
    eq = skmoor.equilibrium(model)
    fair, _ = model.system.reactions(eq.x)
    assert fair[:, 0].sum() == pytest.approx(-F, rel=1e-8)
    assert model.system.q(eq.x)[0] > 0.01  # pushed downstream
    b = model.system.nf
    np.testing.assert_allclose(model.system.M.toarray() - M0,
                               np.pad(added, ((b, 0), (b, 0))), atol=1e-9)
    with pytest.raises(AttributeError):
        model.system.terms.append(None)


def test_line_form_mass_is_in_the_mass_matrix(paper):
    """A LineForm's mass form (a constant added mass per length) adds exactly its total."""
    model = skmoor.build(skmoor.paper_case())
    M0 = model.system.M.copy()

    @BilinearForm
    def extra_mass(du, v, w):
        return 7.0 * ops.dot(du, v)  # kg/m in each direction

    term = model.add(LineForm(lambda v, w: 0.0 * ops.dot(w.u, v), mass=extra_mass))
    extra = term.mass_matrix()
    total = 3 * 7.0 * sum(line.length for line in model.lines.lines)
    assert extra.sum() == pytest.approx(total, rel=1e-12)
    P0 = model.system.P(np.zeros(model.system.n))  # lines' DOFs from the unknowns at rest
    added = (model.system.M - M0).toarray()
    np.testing.assert_allclose(added, (P0.T @ extra @ P0).toarray(), atol=1e-9)


def test_point_load_acts_in_statics():
    """A PointLoad lifting a free junction by F: at equilibrium the two lines' end forces
    on the junction balance F (the sign convention and the statics of point terms)."""
    chain = LineType(EA=5e8, mass=100.0, diameter=0.1)
    points = [skmoor.Point("anchor", "fixed", [-120.0, 0.0, -80.0]),
              skmoor.Point("junction", "free", [-40.0, 0.0, -40.0]),
              skmoor.Point("top", "fixed", [0.0, 0.0, -5.0])]
    lines = [skmoor.MooringLine("low", chain, "anchor", "junction", 100.0, 10),
             skmoor.MooringLine("up", chain, "junction", "top", 60.0, 8)]
    heights = {}
    for lift in (0.0, 3.0e4):
        model = skmoor.from_network(skmoor.Network(points, lines, depth=100.0))
        model.add(PointLoad(lambda x, v, t: np.array([0.0, 0.0, lift]), point="junction"))
        x = skmoor.equilibrium(model).x
        on_b, on_a = model.system.reactions(x)
        balance = on_b[0] + on_a[1] + [0.0, 0.0, lift]
        assert np.abs(balance).max() < 1e-6 * np.abs(on_b[0]).max()
        heights[lift] = (model.system.point_reference[0] + model.system.point_displacement(x)[0])[2]
    assert heights[3.0e4] > heights[0.0] + 1.0


def test_model_add_names_must_exist(paper):
    with pytest.raises(ValueError, match="no dynamic body 'hull'"):
        paper.add(BodyLoad(lambda q, qdot, t: np.zeros(6), body="hull"))
    with pytest.raises(ValueError, match="not a skmoor.fem.terms.Term"):
        paper.system.add_term(object())


def cable_lines(law):
    """A sagging line of the given law with a few strongly pushed (slack) elements."""
    from skmoor import laws

    kind = {"paper": "paper", "engineering": "engineering",
            "curve": laws.Curve([0.0, 0.002, 0.006, 0.02], [0.0, 4e5, 1.6e6, 8e6]),
            "static-dynamic": laws.StaticDynamic(EA_dynamic=9e8)}[law]
    rope = LineType(EA=5e8 if law != "curve" else None, mass=80.0, diameter=0.12, BA=3e6,
                    law=None if isinstance(kind, str) else kind)
    cat = solve_catenary([0.0, 0.0, -60.0], [90.0, 20.0, -5.0], 2000.0, 5e8, length=115.0)
    lines = LineSet([Line.from_catenary(cat, rope, 14)],
                    law=kind if isinstance(kind, str) else "engineering")
    rng = np.random.default_rng(7)
    u = 0.05 * rng.standard_normal(lines.ndofs)
    u[lines.nodal_dofs[5:8, 0]] -= np.array([0.0, 6.0, 12.0])  # squeeze two elements slack
    v = 0.3 * rng.standard_normal(lines.ndofs)
    return lines, u, v


@pytest.mark.parametrize("law", ["paper", "engineering", "curve", "static-dynamic"])
def test_automatic_tangent_of_the_cable_equals_the_hand_tangent(law):
    """The cable forms (Eq. 11 with the law, tension-only with slack elements, and the
    axial damping): d/du and d/dv traced from the residual equal Eq. 17 and the damping's
    hand-written derivatives, and the compiled cable kernel."""
    from skmoor.lines import cable_forms as forms

    lines, u, v = cable_lines(law)
    tension, _ = lines.element_tension_and_strain(u)
    assert np.min(tension) == 0.0 and np.max(tension) > 1e4  # slack and taut elements
    hand = [LineForm(forms.cable_force, stiffness=forms.cable_tangent, quadrature="midpoint",
                     lines=lines),
            LineForm(forms.axial_damping, stiffness=forms.axial_damping_tangent,
                     damping=forms.axial_damping_rate, quadrature="midpoint", lines=lines)]
    auto = [LineForm(form.residual, quadrature="midpoint", path="compiled", lines=lines)
            for form in hand]
    for h, a in zip(hand, auto):
        R0, K0, C0 = dense(h, u, v)
        R1, K1, C1 = dense(a, u, v)
        assert close(R1, R0, 1e-13) and close(K1, K0, 1e-10) and close(C1, C0, 1e-10)
        assert a.backend == "numba"
    _, K2, C2 = skmoor.System(lines, fairleads="fixed").kernel.evaluate(u, v, layout="dense")
    assert close(K2, sum(dense(a, u, v)[1] for a in auto), 1e-10)
    assert close(C2, sum(dense(a, u, v)[2] for a in auto), 1e-10)
