"""The cable's weak forms (skmoor.lines.cable_forms) assembled on a straight line against
closed forms: under a displacement with a uniform slope u' = g every element has the same
strain eps = d.g + |g|^2 / 2 (Eq. 3) and carries the force (T + S) r', r' = d + g, so the
nodal forces sit at the two ends only; the Kelvin-Voigt damping BA (r'.udot') r' likewise;
the weight, mass and unit-tension matrices are the textbook P1 element matrices; the
tangents are the forces' derivatives by central differences."""
import numpy as np
import pytest
from skfem import asm

from skmoor.lines import cable_forms as forms
from skmoor.lines.line import Line, LineSet, LineType

DIRECTION = np.array([2.0, -1.0, 2.0]) / 3.0  # unit
LENGTH, N_ELEMENTS = 30.0, 3
EA, T0, BA, MASS, WEIGHT = 1e7, 1e5, 2e5, 50.0, 300.0
SLOPE = np.array([0.02, -0.01, 0.03])  # u' (-), stretching: d.g > 0
SLOPE_RATE = np.array([-0.02, 0.01, 0.04])  # udot' (1/s)


def straight_lines(law="paper", tension=T0):
    """A LineSet of one straight line from the origin along DIRECTION (3 elements of
    10 m) with a uniform reference tension (N)."""
    s = np.linspace(0.0, LENGTH, N_ELEMENTS + 1)
    line_type = LineType(EA=EA, mass=MASS, diameter=0.1, weight=WEIGHT, BA=BA)
    return LineSet([Line.from_polyline(s[:, None] * DIRECTION, line_type, tension=tension)],
                   law=law)


def uniform_slope(lines, slope):
    """The DOF vector of u(s) = s * slope (m)."""
    u = np.zeros(lines.ndofs)
    s = np.linspace(0.0, LENGTH, N_ELEMENTS + 1)
    u[lines.nodal_dofs] = s[:, None] * slope
    return u


def end_loads(lines, vector):
    """The expected nodal vector (ndofs,): -vector at the anchor, +vector at the far end."""
    out = np.zeros(lines.ndofs)
    out[lines.nodal_dofs[0]] = -vector
    out[lines.nodal_dofs[-1]] = vector
    return out


def green_strain(slope):
    return DIRECTION @ slope + 0.5 * slope @ slope


def test_internal_force_of_a_uniform_slope_is_the_end_tension_along_the_deformed_tangent():
    """Paper law S = EA eps (Eq. 6): the ends carry (T + EA eps) r' (a dropped |u'|^2 / 2,
    a sign of the T u' term or of the reference force show at O(eps))."""
    lines = straight_lines()
    assert np.allclose(lines.reference_force(), end_loads(lines, T0 * DIRECTION), atol=1e-8)
    assert np.allclose(lines.internal_force(np.zeros(lines.ndofs)),
                       end_loads(lines, T0 * DIRECTION), atol=1e-8)
    u = uniform_slope(lines, SLOPE)
    force = (T0 + EA * green_strain(SLOPE)) * (DIRECTION + SLOPE)
    assert np.allclose(lines.internal_force(u), end_loads(lines, force), rtol=0, atol=1e-6)


def test_engineering_law_end_force_is_ea_times_the_engineering_strain():
    """Tension = EA e of the engineering strain e = (1 + T0/EA) |r'| - 1 (Irvine, MoorPy),
    along r' / |r'|; the tension the line reports is that same value."""
    lines = straight_lines("engineering")
    u = uniform_slope(lines, SLOPE)
    stretch = np.linalg.norm(DIRECTION + SLOPE)
    tension = EA * ((1.0 + T0 / EA) * stretch - 1.0)
    force = tension * (DIRECTION + SLOPE) / stretch
    assert np.allclose(lines.internal_force(u), end_loads(lines, force), rtol=0, atol=1e-6)
    element_tension, strain = lines.element_tension_and_strain(u)
    assert np.allclose(element_tension, tension, rtol=1e-12)
    assert np.allclose(strain, green_strain(SLOPE), rtol=1e-12)


def test_reported_tension_adds_the_kelvin_voigt_term_and_stretches_with_the_line():
    """Paper law: (T + EA eps + BA deps/dt) |r'| with deps/dt = r'.udot' (MoorDyn's
    reported tension); without the velocity, the elastic part alone."""
    lines = straight_lines()
    u, ud = uniform_slope(lines, SLOPE), uniform_slope(lines, SLOPE_RATE)
    rp = DIRECTION + SLOPE
    elastic = T0 + EA * green_strain(SLOPE)
    assert np.allclose(lines.element_tension(u), elastic * np.linalg.norm(rp), rtol=1e-12)
    assert np.allclose(lines.element_tension(u, ud),
                       (elastic + BA * rp @ SLOPE_RATE) * np.linalg.norm(rp), rtol=1e-12)
    assert np.allclose(lines.element_strain(u), green_strain(SLOPE), rtol=1e-12)


def test_axial_damping_force_is_ba_times_the_strain_rate_along_the_deformed_tangent():
    lines = straight_lines()
    u, ud = uniform_slope(lines, SLOPE), uniform_slope(lines, SLOPE_RATE)
    rp = DIRECTION + SLOPE
    assert np.allclose(lines.damping_force(u, ud), end_loads(lines, BA * (rp @ SLOPE_RATE) * rp),
                       rtol=0, atol=1e-8)


@pytest.mark.parametrize("law", ["paper", "engineering"])
def test_cable_tangent_is_the_derivative_of_the_internal_force(law):
    """Eq. 17 against central differences of Eq. 11 at a non-uniform displacement."""
    lines = straight_lines(law)
    rng = np.random.default_rng(4)
    u = 0.05 * rng.normal(size=lines.ndofs)
    K = lines.tangent_stiffness(u).toarray()
    h = 1e-7
    fd = np.column_stack([(lines.internal_force(u + h * e) - lines.internal_force(u - h * e))
                          / (2 * h) for e in np.eye(lines.ndofs)])
    assert np.abs(K - fd).max() < 1e-6 * np.abs(K).max()


def test_weight_mass_and_unit_tension_matrices_are_the_p1_element_matrices():
    """Weight w h / 2 per element end along -z; consistent mass m h / 6 [[2, 1], [1, 2]]
    per component, lumped its row sums; unit-tension stiffness [[1, -1], [-1, 1]] / h."""
    lines = straight_lines()
    h = LENGTH / N_ELEMENTS
    share = np.array([0.5, 1.0, 1.0, 0.5]) * h  # length carried by each node
    weight = np.zeros(lines.ndofs)
    weight[lines.nodal_dofs[:, 2]] = -WEIGHT * share
    assert np.allclose(lines.weight_load(), weight, rtol=1e-12)
    tri = (np.diag([2.0, 4.0, 4.0, 2.0]) + np.diag([1.0] * 3, 1) + np.diag([1.0] * 3, -1)) / 6
    stiff = (np.diag([1.0, 2.0, 2.0, 1.0]) - np.diag([1.0] * 3, 1) - np.diag([1.0] * 3, -1)) / h
    consistent, unit = np.zeros((lines.ndofs,) * 2), np.zeros((lines.ndofs,) * 2)
    for c in range(3):
        dofs = lines.nodal_dofs[:, c]
        consistent[np.ix_(dofs, dofs)] = MASS * h * tri
        unit[np.ix_(dofs, dofs)] = stiff
    assert np.allclose(lines.mass_matrix(lumped=False).toarray(), consistent, rtol=1e-12)
    assert np.allclose(lines.mass_matrix().diagonal(), MASS * np.repeat(share, 3)
                       [np.argsort(lines.nodal_dofs.ravel())], rtol=1e-12)
    assert np.allclose(lines.unit_tension_stiffness().toarray(), unit, rtol=1e-12)


def test_axial_damping_tangents_are_its_derivatives():
    """axial_damping_rate = d(damping)/d(udot), axial_damping_tangent = d(damping)/du,
    against central differences of the damping force at a non-uniform state."""
    lines = straight_lines()
    rng = np.random.default_rng(5)
    u, ud = 0.05 * rng.normal(size=lines.ndofs), 0.1 * rng.normal(size=lines.ndofs)
    fields = dict(lines.cable_fields)
    rate = asm(forms.axial_damping_rate, lines.cable_basis, u=u, **fields).toarray()
    tangent = asm(forms.axial_damping_tangent, lines.cable_basis, u=u, du=ud,
                  **fields).toarray()
    h, unit = 1e-7, np.eye(lines.ndofs)
    fd_rate = np.column_stack([(lines.damping_force(u, ud + h * e)
                                - lines.damping_force(u, ud - h * e)) / (2 * h) for e in unit])
    fd_tangent = np.column_stack([(lines.damping_force(u + h * e, ud)
                                   - lines.damping_force(u - h * e, ud)) / (2 * h) for e in unit])
    assert np.abs(rate - fd_rate).max() < 1e-6 * np.abs(rate).max()
    assert np.abs(tangent - fd_tangent).max() < 1e-6 * np.abs(tangent).max()


def test_distributed_load_and_line_damping_are_the_p1_element_integrals():
    """A uniform load f (N/m) gives f h / 2 per element end; a damping c (N s/m2) the
    matrix c h / 6 [[2, 1], [1, 2]] per component."""
    lines = straight_lines()
    h = LENGTH / N_ELEMENTS
    shape = lines.fields["T"].shape
    f = np.array([3.0, -2.0, 5.0])
    load = asm(forms.distributed_load, lines.basis,
               f=np.broadcast_to(f[:, None, None], (3,) + shape))
    assert np.allclose(load[lines.nodal_dofs], np.outer([0.5, 1, 1, 0.5], f) * h, rtol=1e-12)
    c = 7.0
    C = asm(forms.line_damping, lines.basis, c=np.full(shape, c)).toarray()
    M = asm(forms.mass, lines.basis, m=np.full(shape, c)).toarray()
    dofs = lines.nodal_dofs[:, 1]
    tri = (np.diag([2.0, 4.0, 4.0, 2.0]) + np.diag([1.0] * 3, 1) + np.diag([1.0] * 3, -1)) / 6
    assert np.allclose(C[np.ix_(dofs, dofs)], c * h * tri, rtol=1e-12)
    assert np.allclose(C, M, rtol=1e-12)
