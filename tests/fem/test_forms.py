"""The cable's weak forms (skmoor.lines.cable_forms through LineSet) against exact derivatives, the
fast kernel, closed-form mass matrices and the analytic elastic catenary."""
import numpy as np
import pytest
from skfem import BilinearForm, LinearForm
from skfem.helpers import dot

from skmoor.coupling.system import System
from skmoor.fem.terms import LineForm
from skmoor.lines.cable_kernel import CableKernel
from skmoor.lines.catenary import solve_catenary
from skmoor.lines.laws import Engineering, Paper
from skmoor.lines.line import Line, LineSet, LineType

# A soft rope (T/EA up to 0.06), so that the two strain laws differ visibly.
ROPE = LineType(EA=2e6, mass=50.0, diameter=0.1)
ANCHOR, FAIRLEAD = np.array([-300.0, 0.0, -100.0]), np.zeros(3)
# the random states below push some elements into compression: the laws carry it here, so
# that the Taylor test sees a smooth force (tension-only laws: tests/lines/test_laws.py)
LAWS = [Paper(tension_only=False), Engineering(tension_only=False)]


@pytest.fixture(scope="module")
def rope():
    """A curved, fully suspended catenary that dips below its anchor."""
    return solve_catenary(ANCHOR, FAIRLEAD, ROPE.weight, ROPE.EA, length=330.0)


def several_lines(rope):
    """Two catenaries and a pretensioned 3D polyline, on one mesh."""
    other = solve_catenary([10.0, -5.0, -80.0], [0.0, 40.0, 5.0], ROPE.weight, ROPE.EA,
                           length=110.0)
    kinked = np.array([[0.0, 0.0, -50.0], [10.0, 5.0, -20.0], [20.0, 0.0, 0.0], [22.0, 3.0, 4.0]])
    return [Line.from_catenary(rope, ROPE, 7, name="a"),
            Line.from_catenary(other, ROPE, 5, name="b"),
            Line.from_polyline(kinked, ROPE, name="c", tension=1e4)]


def slope(x, y):
    """Slope of log y against log x (least squares)."""
    return np.polyfit(np.log(x), np.log(y), 1)[0]


@pytest.mark.parametrize("law", LAWS, ids=["paper", "engineering"])
def test_tangent_is_derivative_of_internal_force(rope, law):
    """Taylor test: |F(u + e du) - F(u) - e K du| falls as e^2 (and as e^1 without K)."""
    lines = LineSet([Line.from_catenary(rope, ROPE, 12)], law=law)
    rng = np.random.default_rng(1)
    u, du = rng.normal(size=lines.ndofs), rng.normal(size=lines.ndofs)  # m; h = 27.5 m
    F, K = lines.internal_force(u), lines.tangent_stiffness(u)
    e = np.logspace(-1, -4, 7)
    change = [lines.internal_force(u + ei * du) - F for ei in e]
    second = [np.linalg.norm(c - ei * (K @ du)) for c, ei in zip(change, e)]
    first = [np.linalg.norm(c) for c in change]
    assert slope(e, second) == pytest.approx(2.0, abs=0.1)
    assert slope(e, first) == pytest.approx(1.0, abs=0.1)


@pytest.mark.parametrize("law", LAWS, ids=["paper", "engineering"])
def test_kernel_equals_forms(rope, law):
    """CableKernel.force_and_tangent equals the scikit-fem assembly of the forms (1e-12)."""
    lines = LineSet(several_lines(rope), law=law)
    u = np.random.default_rng(2).normal(size=lines.ndofs)
    F_forms, K_forms = lines.internal_force(u), lines.tangent_stiffness(u)
    kernel = CableKernel(lines)
    F, K = kernel.force_and_tangent(u)
    assert np.linalg.norm(F - F_forms) <= 1e-12 * np.linalg.norm(F_forms)
    assert np.linalg.norm(kernel.force(u) - F_forms) <= 1e-12 * np.linalg.norm(F_forms)
    assert abs(K - K_forms).max() <= 1e-12 * abs(K_forms).max()


def mass_sums(lineset, lumped):
    """The mass matrix (dense) and its sums over the x, y and z DOFs, kg."""
    M = lineset.mass_matrix(lumped=lumped).toarray()
    dofs = lineset.nodal_dofs
    return M, np.array([M[np.ix_(dofs[:, k], dofs[:, k])].sum() for k in range(3)])


def test_lumped_mass_is_diagonal_with_the_line_mass():
    """Eq. 20 on polylines: diagonal; per direction it sums to mass * length."""
    straight = Line.from_polyline(np.linspace([0.0, 0.0, -40.0], [30.0, 0.0, 0.0], 6), ROPE)
    kinked = Line.from_polyline([[0.0, 0.0, -50.0], [10.0, 5.0, -20.0], [20.0, 0.0, 0.0]],
                                ROPE, tension=1e4)
    M, sums = mass_sums(LineSet([straight, kinked]), lumped=True)
    assert np.count_nonzero(M - np.diag(np.diag(M))) == 0
    total = ROPE.mass * (50.0 + np.sqrt(10**2 + 5**2 + 30**2) + np.sqrt(10**2 + 5**2 + 20**2))
    np.testing.assert_allclose(sums, total, rtol=1e-12)


def test_lumped_mass_of_a_stretched_catenary_keeps_the_line_mass(rope):
    """Eq. 20 on a catenary reference (stretch 1 + T/EA up to 1.06): the lumped mass sums to
    mass * unstretched length, as the consistent mass does."""
    lines = LineSet([Line.from_catenary(rope, ROPE, 7)])
    M, sums = mass_sums(lines, lumped=True)
    assert np.count_nonzero(M - np.diag(np.diag(M))) == 0
    np.testing.assert_allclose(sums, ROPE.mass * rope.L, rtol=1e-6)


def test_consistent_mass_has_the_line_mass_and_the_2_to_1_pattern(rope):
    """Eq. 19: sums to mass * unstretched length; m h / 6 [[2, 1], [1, 2]] on a straight
    element."""
    _, sums = mass_sums(LineSet(several_lines(rope)), lumped=False)
    unstretched = rope.L + 110.0 + several_lines(rope)[2].length  # m
    np.testing.assert_allclose(sums, ROPE.mass * unstretched, rtol=1e-6)  # Gauss, h ~ 40 m

    h = 7.0
    element = LineSet([Line.from_polyline([[1.0, 2.0, -9.0], [3.0, 5.0, -3.0]], ROPE)])
    assert element.lines[0].length == pytest.approx(h)
    M = element.mass_matrix(lumped=False).toarray()
    dofs = element.nodal_dofs.T.ravel()  # x0 x1 y0 y1 z0 z1
    expected = np.kron(np.eye(3), ROPE.mass * h / 6 * np.array([[2.0, 1.0], [1.0, 2.0]]))
    np.testing.assert_allclose(M[np.ix_(dofs, dofs)], expected, rtol=1e-13, atol=1e-12)


def test_catenary_reference_is_an_equilibrium_of_the_forms(rope):
    """Irvine's catenary as reference state: interior residual ~0 (< 1e-8 w L) and end
    reactions equal to catenary.fairlead_force() / anchor_force(), converging with h."""
    wL = ROPE.weight * rope.L
    errors = []
    for n in (8, 16, 32):
        lines = LineSet([Line.from_catenary(rope, ROPE, n)])
        R = lines.internal_force(np.zeros(lines.ndofs)) - lines.weight_load()
        dofs = lines.nodal_dofs
        assert np.abs(R[dofs[1:-1]]).max() < 1e-8 * wL
        errors.append([np.linalg.norm(-R[dofs[-1]] - rope.fairlead_force()) / rope.T_fairlead,
                       np.linalg.norm(-R[dofs[0]] - rope.anchor_force()) / rope.T_anchor])
    errors = np.array(errors)
    assert errors.max() < 1e-8
    # where not at round-off, the reaction error falls at least as h^2 (it is ~h^6 here)
    coarse = errors[:2]
    assert np.all(np.log2(coarse[0] / coarse[1]) > 2.0)


def test_user_term_adds_its_residual(rope):
    """A user LinearForm (linear drag c udot) added as a LineForm: for a uniform
    velocity V of the free nodes the extra force sums to c V (L - 2 (h_first + h_last) / 3)."""
    c = 30.0  # N s / m2

    @LinearForm
    def drag(v, w):
        return w.c * dot(w.du, v)

    @BilinearForm
    def drag_rate(du, v, w):
        return w.c * dot(du, v)

    lines = LineSet([Line.from_catenary(rope, ROPE, 10)])
    plain = System(lines, fairleads="fixed")
    dragged = System(lines, fairleads="fixed", terms=[LineForm(drag, damping=drag_rate,
                                                               fields={"c": c})])
    x = np.zeros(plain.n)
    V = np.array([0.3, -0.2, 0.5])  # m/s
    v = np.tile(V, plain.n // 3)  # free DOFs are node-major: x, y, z of each free node
    assert np.allclose(lines.nodal_dofs[1:-1].ravel(), plain.free)

    R0 = plain.residual(x, v)[0]
    R, _, Kv = dragged.residual(x, v)
    extra = (R - R0).reshape(-1, 3)
    h = lines.element_lengths
    np.testing.assert_allclose(extra.sum(axis=0), c * V * (lines.lines[0].length
                                                           - 2 * (h[0] + h[-1]) / 3), rtol=1e-12)
    np.testing.assert_allclose(R - R0, Kv @ v, rtol=1e-12, atol=1e-9)
    # without velocity the term is silent
    np.testing.assert_allclose(dragged.residual(x)[0], plain.residual(x)[0], atol=1e-9)


def test_axial_damping_kernel_forms_and_derivatives(rope):
    """BA damping: kernel == forms (1e-12), and its u- and udot-derivatives pass a Taylor
    test (second-order remainder)."""
    damped = LineType(EA=ROPE.EA, mass=ROPE.mass, diameter=ROPE.diameter, BA=3e4)
    lines = LineSet([Line.from_catenary(rope, damped, 9)], law="engineering")
    rng = np.random.default_rng(5)
    u, ud, du = (rng.normal(size=lines.ndofs) for _ in range(3))
    kernel = CableKernel(lines)
    f, K_u, K_v = kernel.evaluate(u, ud)
    f0, K0, _ = kernel.evaluate(u)
    damping = lines.damping_force(u, ud)
    assert np.linalg.norm(f - f0 - damping) <= 1e-12 * np.linalg.norm(damping)
    f, K_u = f - f0, K_u - K0
    K_u_forms = asm_form("axial_damping_tangent", lines, u, ud)
    K_v_forms = asm_form("axial_damping_rate", lines, u, ud)
    assert abs(K_u - K_u_forms).max() <= 1e-12 * abs(K_u_forms).max()
    assert abs(K_v - K_v_forms).max() <= 1e-12 * abs(K_v_forms).max()
    e = np.logspace(-1, -4, 7)
    def damping_force(u, ud):
        return kernel.evaluate(u, ud, tangent=False)[0] - kernel.evaluate(u, tangent=False)[0]

    rem_u = [np.linalg.norm(damping_force(u + ei * du, ud) - f - ei * (K_u @ du)) for ei in e]
    rem_v = [np.linalg.norm(damping_force(u, ud + ei * du) - f - ei * (K_v @ du)) for ei in e]
    assert slope(e, rem_u) == pytest.approx(2.0, abs=0.1)
    assert max(rem_v) <= 1e-9 * np.linalg.norm(f)  # linear in the velocity


def asm_form(name, lines, u, ud):
    from skfem import asm

    from skmoor.lines import cable_forms as forms
    return asm(getattr(forms, name), lines.cable_basis, u=u, du=ud, **lines.cable_fields)


def test_axial_damping_gives_kelvin_voigt_modal_damping():
    """A taut straight bar with BA: the first axial mode's damping ratio (quadratic
    eigenproblem of M, Kv, K) is BA omega / (2 (EA + T)) (Kelvin-Voigt; the axial stiffness
    of a line under tension T is EA + T), and omega is pi / L sqrt((EA + T) / m) within 1 %."""
    EA, m, L, BA, T = 1e8, 80.0, 100.0, 2e4, 1e5
    bar = LineType(EA=EA, mass=m, diameter=0.1, BA=BA)
    points = np.linspace([0.0, 0.0, 0.0], [L, 0.0, 0.0], 41)
    system = System(LineSet([Line.from_polyline(points, bar, tension=T)]), fairleads="fixed")
    _, K, Kv = system.residual(np.zeros(system.n))
    K, C, M = K.toarray(), Kv.toarray(), system.M.toarray()
    axial = np.arange(0, system.n, 3)  # x DOFs of the inner nodes
    Ka, Ca, Ma = (A[np.ix_(axial, axial)] for A in (K, C, M))
    n = len(axial)
    A = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-np.linalg.solve(Ma, Ka), -np.linalg.solve(Ma, Ca)]])
    lam = np.linalg.eigvals(A)
    first = lam[np.argmin(np.abs(lam))]
    omega = abs(first)
    assert omega == pytest.approx(np.pi / L * np.sqrt((EA + T) / m), rel=1e-2)
    assert -first.real / omega == pytest.approx(BA * omega / (2 * (EA + T)), rel=1e-6)
