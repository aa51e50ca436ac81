"""Bending stiffness on the Hermite line element (skmoor.lines.bending) against Euler-Bernoulli:
cantilever and simply supported beams under their weight and a point load (deflection,
bending moment, observed orders of convergence), the modes of a pinned-pinned beam and
of a tensioned beam-string against the analytic frequencies, and the kernel against the
forms' assembly."""
import numpy as np
import pytest

from skmoor.bodies.loads import PointLoad
from skmoor.coupling.system import Ends, PointMass, System
from skmoor.fem.terms import Term
from skmoor.lines.laws import Engineering
from skmoor.lines.line import Line, LineSet, LineType
from skmoor.solvers.modes import eigenmodes
from skmoor.solvers.statics import solve_static

L, EI, EA = 10.0, 1e8, 1e10  # m, N m2, N: a stiff beam, deflections ~1e-4 L (linear theory)
W, P = 100.0, 500.0  # weight per length N/m, point load N


def beam_type(weight=W, mass=None):
    return LineType(EA=EA, mass=weight / 9.81 if mass is None else mass, diameter=0.1,
                    weight=weight, EI=EI, law=Engineering(tension_only=False))


def straight(n, line_type, tension=0.0):
    points = np.c_[np.linspace(0.0, L, n + 1), np.zeros(n + 1), np.zeros(n + 1)]
    return Line.from_polyline(points, line_type, name="beam", tension=tension)


def order(errors, sizes):
    """Observed orders of convergence between successive meshes."""
    return np.diff(np.log(errors)) / np.diff(np.log(sizes))


def cantilever(n, weight=W, tip=0.0):
    """Clamped at s = 0, free (a massless free point with a load -tip e_z) at s = L."""
    lines = LineSet([straight(n, beam_type(weight))])
    system = System(lines, ends=Ends([("fixed",)], [("point", 0)], clamped=[(0, "a")]),
                    points=[PointMass()],
                    terms=[PointLoad(lambda x, v, t: np.array([0, 0, -tip]),
                                     tangent=lambda x, v, t: (None, None))])
    u = system.full_displacement(solve_static(system).x)
    return lines, u


def test_cantilever_tip_deflection_and_root_moment():
    """Tip deflection w L^4 / 8 EI + P L^3 / 3 EI (the cubic is nodally exact for these
    loads); moment M(s) = w (L - s)^2 / 2 + P (L - s) at the element mid-points with
    second-order convergence, the deflection between nodes with fourth order."""
    exact_tip = W * L**4 / (8 * EI) + P * L**3 / (3 * EI)
    moment_errors, deflection_errors, sizes = [], [], []
    for n in (2, 4, 8):
        lines, u = cantilever(n, tip=P)
        tip = u[lines.nodal_dofs[-1]]
        assert tip[2] == pytest.approx(-exact_tip, rel=1e-5)
        s_mid = 0.5 * (lines.mesh.p[0, :-1] + lines.mesh.p[0, 1:])
        M = lines.bending_moment(u)
        exact = W * (L - s_mid) ** 2 / 2 + P * (L - s_mid)
        assert M[0] == pytest.approx(exact[0], rel=0.05)
        moment_errors.append(np.abs(M - exact).max())
        x = s_mid / L  # deflection at the mid-points from the slopes and nodal values
        exact_w = (W * L**4 / (24 * EI) * (x**4 - 4 * x**3 + 6 * x**2)
                   + P * L**3 / (6 * EI) * (3 * x**2 - x**3))
        midpoint = np.einsum("eb,ebc->ec", _hermite_mid(lines), u[lines.element_dofs].reshape(-1, 4, 3))
        deflection_errors.append(np.abs(midpoint[:, 2] + exact_w).max())
        sizes.append(L / n)
    assert order(moment_errors, sizes) == pytest.approx([2.0, 2.0], abs=0.15)
    assert np.all(order(deflection_errors, sizes) > 3.8)
    # curvature = M / EI, 1/m
    np.testing.assert_allclose(lines.curvature(u), lines.bending_moment(u) / EI, rtol=1e-12)


def _hermite_mid(lines):
    from skmoor.fem.hermite import hermite_shapes
    N, _, _ = hermite_shapes(np.array([0.5]), lines.element_lengths)
    return N[:, 0]


class NodeLoad(Term):
    """A force (N) on one line node (the test's load at mid-span)."""

    def __init__(self, node, force):
        self.node, self.force = node, np.asarray(force, float)

    def add_to(self, u, v, t, R, K=None, C=None):
        R[self.lines.nodal_dofs[self.node]] -= self.force


def test_simply_supported_midspan_deflection_and_moment():
    """Pinned at both ends: mid-span deflection 5 w L^4 / 384 EI + P L^3 / 48 EI, moment
    w s (L - s) / 2 + P min(s, L - s) / 2, second order in the element size."""
    exact_mid = 5 * W * L**4 / (384 * EI) + P * L**3 / (48 * EI)
    errors, sizes = [], []
    for n in (4, 8, 16):
        lines = LineSet([straight(n, beam_type())])
        system = System(lines, fairleads="fixed", terms=[NodeLoad(n // 2, [0, 0, -P])])
        u = system.full_displacement(solve_static(system).x)
        assert u[lines.nodal_dofs[n // 2]][2] == pytest.approx(-exact_mid, rel=1e-4)
        s = 0.5 * (lines.mesh.p[0, :-1] + lines.mesh.p[0, 1:])
        exact = W * s * (L - s) / 2 + P * np.minimum(s, L - s) / 2
        errors.append(np.abs(lines.bending_moment(u) - exact).max())
        sizes.append(L / n)
        # pinned: the end tangents turn by w L^3 / 24 EI + P L^2 / 16 EI
        slope = u[lines.slope_dofs[0]][2]
        assert slope == pytest.approx(-(W * L**3 / (24 * EI) + P * L**2 / (16 * EI)), rel=1e-4)
    assert order(errors, sizes) == pytest.approx([2.0, 2.0], abs=0.15)


def beam_modes(n, tension=0.0, k=6):
    m = 50.0
    lines = LineSet([straight(n, beam_type(weight=0.0, mass=m), tension=tension)])
    system = System(lines, fairleads="fixed")
    _, K, _ = system.residual(np.zeros(system.n))
    return m, eigenmodes(K, system.M, k=k)


def test_pinned_pinned_beam_modes():
    """omega_n = (n pi / L)^2 sqrt(EI / m), n = 1, 2, 3, twice each (two planes), within
    1e-4 at 16 elements, converging at fourth order (consistent mass: from above)."""
    errors = []
    for n in (8, 16):
        m, modes = beam_modes(n)
        exact = np.repeat((np.arange(1, 4) * np.pi / L) ** 2 * np.sqrt(EI / m), 2)
        assert np.all(modes.omega[:6] >= exact * (1 - 1e-9))
        errors.append(np.abs(modes.omega[:6] / exact - 1).max())
    assert errors[1] < 1e-4
    assert order(errors, [2.0, 1.0])[0] > 3.5


def test_tensioned_beam_string_modes():
    """Beam-string of tension T: omega_n = (n pi / L)^2 sqrt(EI / m) sqrt(1 + T L^2 /
    (n^2 pi^2 EI)); T chosen so that tension and bending matter alike."""
    T = np.pi**2 * EI / L**2
    m, modes = beam_modes(16, tension=T)
    n = np.repeat(np.arange(1, 4), 2)
    exact = (n * np.pi / L) ** 2 * np.sqrt(EI / m) * np.sqrt(1 + T * L**2 / (n**2 * np.pi**2 * EI))
    np.testing.assert_allclose(modes.omega[:6], exact, rtol=1e-4)


def test_kernel_equals_the_forms():
    """HermiteKernel (cable + axial damping + bending) against the forms' assembly on a
    curved, tensioned, damped line at a random state."""
    line_type = LineType(EA=1e7, mass=20.0, diameter=0.1, EI=3e4, BA=2e4)
    theta = np.linspace(0.0, 1.2, 9)
    points = 20.0 * np.c_[np.sin(theta), np.zeros(9), 1.0 - np.cos(theta)]
    lines = LineSet([Line.from_polyline(points, line_type, tension=1e4)])
    from skfem import asm

    from skmoor.lines import cable_forms as forms
    from skmoor.lines.bending import HermiteKernel
    kernel = HermiteKernel(lines)
    rng = np.random.default_rng(3)
    u, ud = 0.05 * rng.standard_normal(lines.ndofs), rng.standard_normal(lines.ndofs)
    R, K, C = kernel.evaluate(u, ud)
    R_forms = lines.internal_force(u) + lines.damping_force(u, ud)
    K_forms = (lines.tangent_stiffness(u)
               + asm(forms.axial_damping_tangent, lines.basis, u=u, du=ud, **lines.fields))
    C_forms = asm(forms.axial_damping_rate, lines.basis, u=u, **lines.fields)
    scale = np.abs(R_forms).max()
    np.testing.assert_allclose(R, R_forms, atol=1e-10 * scale)
    np.testing.assert_allclose(K.toarray(), K_forms.toarray(), atol=1e-10 * np.abs(K_forms).max())
    np.testing.assert_allclose(C.toarray(), C_forms.toarray(), atol=1e-10 * np.abs(C_forms).max())


def test_zero_EI_keeps_the_p1_cable():
    """EI = 0 everywhere: the P1 set of today (3 DOFs per node, 6x6 blocks)."""
    lines = LineSet([straight(4, LineType(EA=EA, mass=10.0, diameter=0.1))])
    assert lines.element == "p1" and lines.ndofs == 15 and lines.block_size == 6


def test_bad_bending_inputs():
    with pytest.raises(ValueError, match="LineType.EI"):
        LineType(EA=EA, mass=1.0, diameter=0.1, EI=-1.0)
    cable = LineSet([straight(4, LineType(EA=EA, mass=10.0, diameter=0.1))])
    with pytest.raises(ValueError, match="clamped ends need bending lines"):
        System(cable, ends=Ends([("fixed",)], [("fixed",)], clamped=[(0, "a")]))
    with pytest.raises(ValueError, match="only fixed, prescribed or body ends can be clamped"):
        Ends([("fixed",)], [("point", 0)], clamped=[(0, "b")])
    with pytest.raises(ValueError, match="Ends clamped"):
        Ends([("fixed",)], [("fixed",)], clamped=[(1, "a")])


def test_outputs_carry_curvature_and_moment(tmp_path):
    """A propped cantilever built as a network (clamped at a, pinned at b): Results,
    summary.json and the VTU series carry the bending moment, Euler-Bernoulli's
    |w L^2 / 8 - 5 w L s / 8 + w s^2 / 2| at the element mid-points (largest next to the
    clamp); the clamped end turns no tangent, the pinned one does."""
    import json

    import meshio

    from skmoor.coupling.network import MooringLine, Network, Point
    from skmoor.model.model import from_network
    from skmoor.post.export import write_vtu_series
    from skmoor.run.equilibrium import equilibrium
    from skmoor.run.outputs import write_outputs
    from skmoor.run.recorder import static_results

    n = 8
    points = [Point("a", "fixed", [0.0, 0.0, -5.0]), Point("b", "fixed", [L, 0.0, -5.0])]
    beam = MooringLine("beam", beam_type(), "a", "b", L, n, clamp_a=True)
    model = from_network(Network(points, [beam], depth=50.0, hydro=False))
    eq = equilibrium(model, n_modes=1)
    results = static_results(model, eq)
    assert results.bending and results.bending_moment.shape == (1, n)
    info = write_outputs(results, tmp_path)
    saved = json.loads((tmp_path / "summary.json").read_text())
    s = (np.arange(n) + 0.5) * L / n
    exact = np.abs(W * L**2 / 8 - 5 * W * L * s / 8 + W * s**2 / 2)
    np.testing.assert_allclose(results.bending_moment[0], exact, rtol=0.02, atol=0.02 * exact.max())
    assert saved["max_bending_moment"]["beam"] == pytest.approx(exact.max(), rel=0.01)
    assert saved["max_curvature"]["beam"] == pytest.approx(saved["max_bending_moment"]["beam"] / EI)
    assert info["max_bending_moment"] == saved["max_bending_moment"]
    u = model.system.full_displacement(eq.x)
    assert np.abs(u[model.lines.slope_dofs[0]]).max() == 0.0  # clamped: the tangent held
    assert abs(u[model.lines.slope_dofs[-1]][2]) > 1e-5  # pinned: the tangent turns
    write_vtu_series(results, tmp_path)
    vtu = meshio.read(tmp_path / "motion" / "lines_0000.vtu")
    np.testing.assert_allclose(vtu.cell_data["bending_moment"][0], results.bending_moment[0])


def test_seabed_kernel_on_bending_lines_equals_the_form():
    """On a Hermite set the compiled contact (node positions) gives the seabed form's
    normal force and damping (nodal quadrature: the same points), here for a line that
    dips 5 cm into the bed over part of its length."""
    from skmoor.sea.seabed import Seabed, SeabedKernel, form_term
    line_type = LineType(EA=1e7, mass=20.0, diameter=0.1, EI=3e4)
    x = np.linspace(0.0, 10.0, 11)
    points = np.c_[x, np.zeros(11), -30.0 + 0.01 * (x - 5.0) ** 2 - 0.05]
    lines = LineSet([Line.from_polyline(points, line_type)])
    bed = Seabed(depth=30.0)
    rng = np.random.default_rng(1)
    u, v = 1e-3 * rng.standard_normal(lines.ndofs), rng.standard_normal(lines.ndofs)
    R, K, C = SeabedKernel(lines, bed).evaluate(u, v)
    R_form, K_form, C_form = form_term(lines, bed).evaluate(u, v)
    assert np.abs(R_form).max() > 0
    np.testing.assert_allclose(R, R_form, atol=1e-9 * np.abs(R_form).max())
    np.testing.assert_allclose(K.toarray(), K_form.toarray(), atol=1e-9 * np.abs(K_form).max())
    np.testing.assert_allclose(C.toarray(), C_form.toarray(), atol=1e-9 * np.abs(C_form).max())
    # the Newton iteration lands the free nodes on the bed alike on either path
    position = np.arange(lines.ndofs)
    position[lines.nodal_dofs[0]] = -1  # the first node held
    kernel, form = SeabedKernel(lines, bed).landing(position), form_term(lines, bed).landing(
        position)
    assert len(kernel[0]) == 10 and kernel[4] > 0
    for a, b in zip(kernel, form):
        np.testing.assert_array_equal(a, b)


def _user_form_case():
    """A Hermite set, a state and a small user integrand in u, u' and the velocity."""
    from skfem import LinearForm

    from skmoor.fem.ops import d_ds, dot

    @LinearForm
    def springy(v, w):
        return 3.0 * w.u[2] * dot(w.u, v) + 2.0 * dot(d_ds(w.u), d_ds(v)) + 0.5 * dot(w.du, v)

    lines = LineSet([straight(6, LineType(EA=1e7, mass=20.0, diameter=0.1, EI=3e4))])
    rng = np.random.default_rng(2)
    return springy, lines, 0.1 * rng.standard_normal(lines.ndofs), rng.standard_normal(lines.ndofs)


def test_user_form_on_bending_lines():
    """A user LineForm on a Hermite set, NumPy path (the Hermite fields and the 12 test
    functions per element): residual = scikit-fem's assembly, tangents = the exact
    derivative forms assembled."""
    from skfem import BilinearForm, asm

    from skmoor.fem.ops import d_ds, dot
    from skmoor.fem.terms import LineForm

    springy, lines, u, v = _user_form_case()

    @BilinearForm
    def stiffness(du, v, w):  # d/du of springy
        return (3.0 * du[2] * dot(w.u, v) + 3.0 * w.u[2] * dot(du, v)
                + 2.0 * dot(d_ds(du), d_ds(v)))

    R, K, C = LineForm(springy, path="fd", lines=lines).evaluate(u, v)
    fields = dict(u=u, du=v, **lines.fields)
    R_asm = asm(springy, lines.basis, **fields)
    K_asm = asm(stiffness, lines.basis, **fields).toarray()
    C_asm = 0.5 * asm(BilinearForm(lambda du, v, w: dot(du, v)), lines.basis).toarray()
    np.testing.assert_allclose(R, R_asm, atol=1e-12 * np.abs(R_asm).max())
    np.testing.assert_allclose(K.toarray(), K_asm, atol=1e-7 * np.abs(K_asm).max())
    np.testing.assert_allclose(C.toarray(), C_asm, atol=1e-7 * np.abs(C_asm).max())


@pytest.mark.slow
def test_user_form_compiled_on_bending_lines():
    """The same form on the compiled path: the generated numba kernel's Hermite element
    loop against the NumPy path (20 s cold: JAX's trace and numba's compile)."""
    from skmoor.fem.terms import LineForm

    springy, lines, u, v = _user_form_case()
    compiled = LineForm(springy, path="compiled", lines=lines)
    R, K, C = compiled.evaluate(u, v)
    assert compiled.backend == "numba"
    R_fd, K_fd, C_fd = LineForm(springy, path="fd", lines=lines).evaluate(u, v)
    np.testing.assert_allclose(R, R_fd, atol=1e-12 * np.abs(R_fd).max())
    np.testing.assert_allclose(K.toarray(), K_fd.toarray(), atol=1e-6 * np.abs(K_fd).max())
    np.testing.assert_allclose(C.toarray(), C_fd.toarray(), atol=1e-6 * np.abs(C_fd).max())


def test_case_file_line_type_takes_EI():
    """A case file's line type with EI (N m2) is a bending line type: the paper's layout
    then runs on the Hermite element; a negative EI is refused by the schema."""
    from pathlib import Path

    from skmoor.io.case import Case
    from skmoor.model.from_case import line_type

    path = Path(__file__).resolve().parents[2] / "examples" / "paper_case.toml"
    case = Case.from_toml(path).replace("line_types.steel.EI", 2.5e5)
    assert line_type(case, "steel").EI == 2.5e5
    with pytest.raises(ValueError, match="EI"):
        Case.from_toml(path).replace("line_types.steel.EI", -1.0)
