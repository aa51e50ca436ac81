"""Constitutive laws (skmoor.lines.laws) against hand numbers and closed-form dynamics.

- each law's tension on a straight element stretched by hand (independent arithmetic:
  np.interp for a curve, EA x strain, the paper's EA eps lambda) and a slack element's
  zero force and stiffness;
- the compiled kernel equal to the forms on lines with different laws, some slack;
- the tangent of every law (Taylor test at a taut state, off the curve's knots);
- the reported tension includes the internal damping BA x strain rate;
- tension-only dynamics: a mass bouncing on a rope goes ballistic when the rope goes
  slack (flight time 2 v/g, snap peak Mg + kA), where a rope that could push would
  oscillate harmonically into compression; ten times the paper's load no longer
  compresses a line (-291 kN before);
- polyester's static and dynamic stiffness: the static stretch with EA_s, the period of
  the oscillation about it with EA_d;
- clear errors on bad curves and curve files.
"""
import numpy as np
import pytest
from scipy.optimize import brentq

import skmoor
from skmoor import laws
from skmoor.coupling.network import MooringLine, Network, Point
from skmoor.lines.cable_kernel import CableKernel
from skmoor.lines.line import Line, LineSet, LineType

EA = 1e6  # N
CURVE_E = [0.01, 0.02, 0.05]
CURVE_T = [5e3, 1.5e4, 9e4]  # stiffening: slopes 5e5, 1e6, 2.5e6 N


def straight(law, L=10.0, n=1, EA=EA):
    """A stress-free straight line of n elements along x, length L (m)."""
    lt = LineType(EA=EA, mass=1.0, diameter=0.01, law=law)
    X = np.c_[np.linspace(0.0, L, n + 1), np.zeros(n + 1), np.zeros(n + 1)]
    return LineSet([Line.from_polyline(X, lt)])


def stretch_to(lines, factor):
    """Displacement stretching the straight line uniformly by ``factor`` along x."""
    u = np.zeros(lines.ndofs)
    u[lines.nodal_dofs[:, 0]] = (factor - 1.0) * lines.points[:, 0]
    return u


@pytest.mark.parametrize("strain", [-0.01, 0.005, 0.015, 0.03, 0.08])
def test_curve_tension_on_a_stretched_element_is_the_table(strain):
    """An element stretched by 1 + e carries the curve's tension at e: np.interp inside
    the table, the last slope beyond it, the first slope through (0, 0) below its first
    point, nothing in compression (tension-only). A wrong hinge (knot or coefficient)
    shifts one of these."""
    e_tab, T_tab = np.r_[0.0, CURVE_E], np.r_[0.0, CURVE_T]
    if strain <= 0:
        expected = 0.0
    elif strain <= e_tab[-1]:
        expected = np.interp(strain, e_tab, T_tab)
    else:
        expected = T_tab[-1] + (strain - e_tab[-1]) * (T_tab[-1] - T_tab[-2]) / (e_tab[-1] - e_tab[-2])
    lines = straight(laws.Curve(CURVE_E, CURVE_T))
    u = stretch_to(lines, 1.0 + strain)
    assert lines.element_tension(u)[0] == pytest.approx(expected, rel=1e-12, abs=1e-6)
    f = lines.internal_force(u)
    assert f[lines.nodal_dofs[1, 0]] == pytest.approx(expected, rel=1e-12, abs=1e-6)


@pytest.mark.parametrize("name", ["paper", "engineering"])
def test_named_laws_on_a_stretched_element(name):
    """Engineering: EA (l/L - 1); the paper's Eq. 6: EA eps with eps = (lambda^2 - 1)/2,
    tension EA eps lambda. Compressed: 0 (tension-only), or the same formula pushing."""
    for factor in (1.02, 0.97):
        for only in (True, False):
            lines = straight(laws.LAWS[name](tension_only=only))
            u = stretch_to(lines, factor)
            eps = 0.5 * (factor**2 - 1.0)
            expected = EA * (factor - 1.0) if name == "engineering" else EA * eps * factor
            if only and factor < 1:
                expected = 0.0
            assert lines.element_tension(u)[0] == pytest.approx(expected, rel=1e-12, abs=1e-9)


def test_slack_element_has_no_force_and_no_stiffness():
    """Tension-only: a compressed element adds nothing to the residual or the tangent
    (kernel and forms); an element that may push keeps its EA."""
    for law in (laws.Engineering(), laws.Paper(), laws.Curve(CURVE_E, CURVE_T)):
        lines = straight(law, n=3)
        u = stretch_to(lines, 0.98)
        R, K, _ = CableKernel(lines).evaluate(u)
        assert np.abs(R).max() == 0.0 and abs(K).max() == 0.0
        assert np.abs(lines.internal_force(u)).max() == 0.0
        assert abs(lines.tangent_stiffness(u)).max() == 0.0
    pushing = straight(laws.Engineering(tension_only=False), n=3)
    K = pushing.tangent_stiffness(stretch_to(pushing, 0.98))
    assert K.diagonal()[pushing.nodal_dofs[1, 0]] == pytest.approx(2 * EA / (10 / 3), rel=1e-12)


def mixed_lines():
    """Four lines on one mesh with four laws (paper, engineering, a curve, static-dynamic),
    reference states in tension from catenaries."""
    cat = skmoor.solve_catenary([-30.0, 0.0, -20.0], [0.0, 0.0, 0.0], 50.0, EA, length=38.0)
    out = []
    for k, law in enumerate([laws.Paper(), laws.Engineering(), laws.Curve(CURVE_E, CURVE_T),
                             laws.StaticDynamic(EA_dynamic=3 * EA)]):
        lt = LineType(EA=EA, mass=7.0, diameter=0.03, law=law, BA=2e4 * k)
        c = skmoor.solve_catenary(cat.anchor, cat.fairlead, lt.weight, EA, length=38.0,
                                  law=law)
        out.append(Line.from_catenary(c, lt, 6 + k, name=f"l{k}"))
    return LineSet(out)


def test_kernel_equals_forms_for_every_law_with_slack_elements():
    """The compiled kernel's residual and tangents (with damping) and its element
    tensions (with BA x strain rate) equal the forms' on lines of four laws, in a state
    where some elements are slack."""
    lines = mixed_lines()
    rng = np.random.default_rng(3)
    u = 0.3 * rng.normal(size=lines.ndofs)
    ud = rng.normal(size=lines.ndofs)
    assert (lines.element_strain(u) < -0.005).any()  # some elements compressed
    tension_forms, strain_forms = lines.element_tension_and_strain(u, ud)  # no kernel yet
    R, K, C = CableKernel(lines).evaluate(u, ud)
    tension, strain = lines.element_tension_and_strain(u, ud)  # the kernel's copy
    assert np.abs(tension - tension_forms).max() < 1e-12 * np.abs(tension_forms).max()
    assert np.abs(strain - strain_forms).max() < 1e-15
    from skfem import asm

    from skmoor.lines import cable_forms as forms
    f = lines.cable_fields
    R_forms = lines.internal_force(u) + lines.damping_force(u, ud)
    K_forms = lines.tangent_stiffness(u) + asm(forms.axial_damping_tangent, lines.cable_basis,
                                               u=u, du=ud, **f)
    C_forms = asm(forms.axial_damping_rate, lines.cable_basis, u=u, **f)
    scale = np.abs(R_forms).max()
    assert np.abs(R - R_forms).max() < 1e-12 * scale
    assert abs(K - K_forms).max() < 1e-12 * abs(K_forms).max()
    assert abs(C - C_forms).max() < 1e-12 * abs(C_forms).max()


def test_tangent_of_every_law_is_the_derivative():
    """Taylor test at a taut state with strains off the curve's knots: the remainder of
    F(u + h du) - F(u) - h K du falls as h^2 for each law (a wrong dS/deps leaves h^1)."""
    lines = mixed_lines()
    rng = np.random.default_rng(5)
    u = 1e-3 * rng.normal(size=lines.ndofs)
    du = rng.normal(size=lines.ndofs)
    F, K = lines.internal_force(u), lines.tangent_stiffness(u)
    h = np.logspace(-5, -7, 5)
    rest = [np.linalg.norm(lines.internal_force(u + s * du) - F - s * (K @ du)) for s in h]
    assert np.polyfit(np.log(h), np.log(rest), 1)[0] == pytest.approx(2.0, abs=0.1)


def test_reported_tension_includes_internal_damping():
    """With the velocity, the element tension is the elastic one plus BA deps/dt |r'|
    (deps/dt = lambda dlambda/dt on a straight element), as MoorDyn reports T + BA x
    strain rate; without the velocity, the elastic tension (a recorder that drops the
    velocity, or a rate of the wrong sign, fails here)."""
    BA = 3e4
    lt = LineType(EA=EA, mass=1.0, diameter=0.01, BA=BA)
    X = np.c_[np.linspace(0.0, 10.0, 2), np.zeros(2), np.zeros(2)]
    lines = LineSet([Line.from_polyline(X, lt)], law="engineering")
    factor, rate = 1.01, 0.2  # stretch, d(stretch)/dt (1/s)
    u = stretch_to(lines, factor)
    ud = np.zeros(lines.ndofs)
    ud[lines.nodal_dofs[:, 0]] = rate * lines.points[:, 0]
    elastic = EA * (factor - 1.0)
    assert lines.element_tension(u)[0] == pytest.approx(elastic, rel=1e-12)
    assert lines.element_tension(u, ud)[0] == pytest.approx(
        elastic + BA * factor * rate * factor, rel=1e-12)


# ------------------------------------------------------------ tension-only dynamics

M, L_ROPE, EA_ROPE = 1000.0, 10.0, 1e6  # kg, m, N: k = 1e5 N/m, omega = 10 rad/s
G = 9.81
ROPE_MASS = 0.02  # kg/m


def bouncing_mass(amplitude, law, EA_rope=EA_ROPE, n=2):
    """A mass hanging on a light vertical rope (2 elements, 0.2 kg against the mass's
    1000 kg), released from rest ``amplitude`` (m) below its static position
    (start='given'); returns the Results."""
    delta = M * G * L_ROPE / EA_rope
    rope = LineType(EA=EA_rope, mass=ROPE_MASS, diameter=0.001, law=law)
    points = [Point("top", "fixed", [0.0, 0.0, 0.0]),
              Point("mass", "free", [0.0, 0.0, -(L_ROPE + delta + amplitude)], mass=M)]
    network = Network(points, [MooringLine("rope", rope, "top", "mass", L_ROPE, n)],
                      depth=100.0, rho=1025.0, g=G, hydro=False)
    model = skmoor.from_network(network, settings={
        "solver": {"scheme": "generalized-alpha", "rho_inf": 0.9, "duration": 1.2,
                   "dt": 1e-3, "output_interval": 1e-3}, "damping": {"ratio": 0.0}, "load": {}})
    results = skmoor.simulate(model, progress=False, start="given")
    assert results.meta["stopped"] is None
    return results


def test_mass_on_a_slack_rope_flies_and_snaps():
    """Released A = 0.3 m below equilibrium (static stretch d = Mg/k = 0.098 m), the mass
    rises harmonically and the rope goes slack at t = acos(-d/A)/omega, at velocity
    v = omega sqrt(A^2 - d^2); the mass flies for 2 v / g with the rope carrying nothing,
    then snaps it taut (the tension back at Mg/2 a time tau later: d (1 - cos omega tau) +
    v/omega sin omega tau = d/2), peaking at Mg + k A (energy conserved). A rope that can
    push instead oscillates harmonically with tension Mg - k A = -20.2 kN at the top."""
    A, k = 0.3, EA_ROPE / L_ROPE
    omega, d = np.sqrt(k / M), M * G / k
    v = omega * np.sqrt(A**2 - d**2)
    tau = brentq(lambda s: d * (1 - np.cos(omega * s)) + v / omega * np.sin(omega * s) - d / 2,
                 0.0, 0.5 / omega)
    results = bouncing_mass(A, laws.Engineering())
    T, t = results.tension[:, -1], results.t
    assert results.tension.min() >= 0.0
    slack = t[np.argmax(T <= 0)]
    assert slack == pytest.approx(np.arccos(-d / A) / omega, abs=2e-3)
    taut = t[np.argmax((t > slack) & (T > 0.5 * M * G))]
    assert taut - slack == pytest.approx(2 * v / G + tau, rel=0.01)
    snap = (t >= taut) & (t <= taut + np.pi / omega)
    assert T[snap].max() == pytest.approx(M * G + k * A, rel=0.02)
    pushing = bouncing_mass(A, laws.Engineering(tension_only=False))
    assert pushing.tension.min() == pytest.approx(M * G - k * A, rel=0.01)


def test_ten_times_the_papers_load_does_not_compress_the_lines():
    """The paper's case at F = 1e6 sin(1.6 t): with lines that may push, elements reach
    -291 kN within 20 s; tension-only lines carry none (snapping taut to 3.3 MN)."""
    tensions = {}
    for only in (True, False):
        model = skmoor.build(skmoor.paper_case(load__amplitude=1e6, mooring__tension_only=only))
        results = skmoor.simulate(model, duration=20.0, progress=False)
        assert results.meta["stopped"] is None
        tensions[only] = results.tension
    assert tensions[False].min() < -2e5
    assert tensions[True].min() >= 0.0
    assert tensions[True].max() > 3e6


def test_static_and_dynamic_stiffness_of_polyester():
    """StaticDynamic(EA_d = 3 EA_s): the mass hangs at the static stretch Mg L / EA_s, and
    released 1 cm below it oscillates about it with the period 2 pi sqrt(M L / EA_d) (with
    EA_s the period would be sqrt(3) longer; a mean state left at the release point would
    shift the centre by 2/3 cm; the rope stays taut: EA_d a / L < Mg)."""
    EA_s, EA_d = 2e6, 6e6
    law = laws.StaticDynamic(EA_dynamic=EA_d)
    a = 0.01
    delta = M * G * L_ROPE / EA_s
    rope = LineType(EA=EA_s, mass=0.01, diameter=0.001, law=law)
    points = [Point("top", "fixed", [0.0, 0.0, 0.0]),
              Point("mass", "free", [0.0, 0.0, -(L_ROPE + delta + a)], mass=M)]
    network = Network(points, [MooringLine("rope", rope, "top", "mass", L_ROPE, 4)],
                      depth=100.0, hydro=False, g=G)
    model = skmoor.from_network(network, settings={
        "solver": {"scheme": "newmark", "duration": 3.0, "dt": 2e-3, "output_interval": 2e-3},
        "damping": {"ratio": 0.0}, "load": {}})
    static = skmoor.static_results(model)
    z_static = static.point_reference[1, 2] + static.point_displacement[0, 1, 2]
    results = skmoor.simulate(model, progress=False, start="given")
    z = results.point_reference[1, 2] + results.point_displacement[:, 1, 2]
    centre = 0.5 * (z.max() + z.min())
    assert centre == pytest.approx(-(L_ROPE + delta), abs=2e-4)
    assert z_static == pytest.approx(-(L_ROPE + delta), abs=1e-5)  # the rope weighs 2 N
    crossings = results.t[1:][np.diff(np.sign(z - centre)) != 0]
    period = 2 * np.mean(np.diff(crossings))
    assert period == pytest.approx(2 * np.pi * np.sqrt(M * L_ROPE / EA_d), rel=0.01)


# ------------------------------------------------------------ input checks

@pytest.mark.parametrize("strain, tension, message", [
    ([0.01, 0.01, 0.02], [1.0, 2.0, 3.0], r"strain must increase point by point; point 2"),
    ([0.01, 0.02], [2.0, 1.0], r"tension must increase point by point; point 2"),
    ([0.0, 0.01], [5.0, 10.0], r"tension at zero strain must be 0 N"),
    ([-0.01, 0.01], [0.0, 10.0], r"give strains >= 0"),
    ([0.01, np.nan], [1.0, 2.0], r"must be finite"),
    ([0.01, 0.02], [1.0], r"as many strains as tensions"),
])
def test_bad_curves_are_refused_with_the_reason(strain, tension, message):
    with pytest.raises(ValueError, match=r"^my curve: .*" + message):
        laws.Curve(strain, tension, source="my curve")


def test_curve_file_errors_name_the_file(tmp_path):
    with pytest.raises(ValueError, match="curve file .*missing.txt does not exist"):
        laws.read_curve(tmp_path / "missing.txt")
    bad = tmp_path / "bad.txt"
    bad.write_text("title\nStrain Tension\n(-) (N)\n0.01 100\n0.02 oops\n")
    with pytest.raises(ValueError, match=r"bad.txt line 5: '0.02 oops' is not two numbers"):
        laws.read_curve(bad)


def test_unknown_law_names_the_field():
    lt = LineType(EA=1.0, mass=1.0, diameter=0.1)
    with pytest.raises(ValueError, match=r"^LineSet law: unknown strain law 'hooke'"):
        LineSet([Line.from_polyline([[0, 0, 0], [1, 0, 0]], lt)], law="hooke")
    with pytest.raises(ValueError, match=r"^LineType.law: unknown strain law 'linear'"):
        LineType(EA=1.0, mass=1.0, diameter=0.1, law="linear")
    with pytest.raises(ValueError, match=r"^LineType.EA: give the axial stiffness"):
        LineType(EA=None, mass=1.0, diameter=0.1)
    with pytest.raises(ValueError, match=r"StaticDynamic: give EA_dynamic or alpha_MBL"):
        laws.StaticDynamic()


JAX_CHECK = """
import jax, numpy as np
jax.config.update("jax_enable_x64", True)
import test_laws as t
from skmoor import laws
lines = t.mixed_lines()
p = {name: value[:, 0] for name, value in lines.cable_fields.items() if name != "Xp"}
eps = np.linspace(-0.01, 0.03, lines.mesh.t.shape[1])
grad = jax.grad(lambda x: laws.stress_resultant(x, p["T"], p)[0].sum())(jax.numpy.asarray(eps))
slope = laws.stress_resultant(eps, p["T"], p)[1]
print(np.abs(np.asarray(grad) - slope).max() / np.abs(slope).max())
"""


def test_laws_trace_under_jax_and_their_slopes_are_the_derivatives():
    """The pointwise law (skmoor.fem.ops) traces under JAX: jax.grad of S(eps) equals the
    hand slope dS/deps for every law, slack, taut and beyond a curve's knots. (In a
    subprocess: JAX's threads in the test process would make later forks unsafe.)"""
    pytest.importorskip("jax", reason="JAX traces the forms (skmoor[autodiff])")
    import os
    import subprocess
    import sys
    from pathlib import Path

    here = Path(__file__).resolve().parent
    path = os.pathsep.join([str(here.parents[1]), str(here), os.environ.get("PYTHONPATH", "")])
    out = subprocess.run([sys.executable, "-c", JAX_CHECK], capture_output=True, text=True,
                         cwd=here.parents[1], env={**os.environ, "PYTHONPATH": path}, check=False)
    assert out.returncode == 0, out.stderr[-2000:]
    assert float(out.stdout.split()[-1]) <= 1e-9


def test_case_key_tension_only():
    """mooring.tension_only = false gives the paper's law that may push; a non-boolean
    is refused naming the key."""
    assert skmoor.paper_case().strain_law == "paper"
    law = skmoor.paper_case(mooring__tension_only=False).strain_law
    assert isinstance(law, laws.Paper) and not law.tension_only
    with pytest.raises(ValueError, match=r"mooring\.tension_only: expected true or false"):
        skmoor.paper_case(mooring__tension_only="no")


def test_the_network_layout_reads_tension_only():
    """[mooring] tension_only = false in a case with network tables gives a law that can
    push (the default is tension-only)."""
    from skmoor.lines.laws import as_law
    from skmoor.model.from_case import explicit_network

    case = skmoor.Case.from_toml("examples/network_buoy.toml")
    assert as_law(explicit_network(case).strain_law).tension_only
    pushing = explicit_network(case.replace("mooring.tension_only", False)).strain_law
    assert not pushing.tension_only and pushing.name == "engineering"


FD_LAWS = [laws.Paper(), laws.Paper(tension_only=False), laws.Engineering(),
           laws.Curve(CURVE_E, CURVE_T), laws.StaticDynamic(EA_dynamic=3 * EA),
           laws.Viscoelastic(EA_dynamic=3 * EA, creep_damping=1e5)]


@pytest.mark.parametrize("law", FD_LAWS, ids=lambda law: f"{law.name}-{law.tension_only}")
def test_each_laws_slope_is_the_central_difference_of_its_tension(law):
    """Law.slope(e) equals (T(e + h) - T(e - h)) / 2h of Law.tension (h = 1e-7) at strains
    off any knot, taut and (for a law that pushes) compressed, to 1e-6 of the slope: a
    derivative with a sign flipped inside it (the paper's EA (lambda^2 + eps) written
    lambda^2 - eps, a hinge's slope subtracted) is off by far more."""
    e = np.array([0.004, 0.013, 0.037, 0.12] + ([-0.02] if not law.tension_only else []))
    h = 1e-7
    fd = (law.tension(e + h, EA) - law.tension(e - h, EA)) / (2 * h)
    slope = law.slope(e, EA)
    assert np.all(np.abs(slope - fd) <= 1e-6 * np.abs(fd)), (slope, fd)


def test_stress_resultants_slope_is_the_central_difference_of_it():
    """dS/deps of ``stress_resultant`` equals the central difference of S (h = 1e-8) for
    every law's parameters, taut and compressed, without JAX (its own test is skipped
    where JAX is missing)."""
    lines = mixed_lines()
    p = {name: value[:, 0] for name, value in lines.cable_fields.items() if name != "Xp"}
    eps = np.linspace(-0.013, 0.031, lines.mesh.t.shape[1])
    h = 1e-8
    S = lambda x: laws.stress_resultant(x, p["T"], p)[0]  # noqa: E731
    fd = (S(eps + h) - S(eps - h)) / (2 * h)
    slope = laws.stress_resultant(eps, p["T"], p)[1]
    assert np.max(np.abs(slope - fd)) <= 1e-5 * np.max(np.abs(fd))


def test_papers_law_from_a_stress_free_state_is_eq_6():
    """Eq. 6 from a stress-free state: the Green strain eps = (lambda^2 - 1) / 2 of the
    stretch lambda = 1 + e carries S = EA eps per reference length, N = S lambda; its
    slope is EA (lambda^2 + eps). Slack (N < 0) carries nothing under tension_only."""
    EA = 3.0e8
    e = np.array([-0.02, 0.0, 0.001, 0.01, 0.05])
    lam = 1.0 + e
    eps = 0.5 * (lam**2 - 1.0)
    taut = laws.Paper(tension_only=False)
    np.testing.assert_allclose(taut.tension(e, EA), EA * eps * lam, rtol=1e-12, atol=1e-6)
    np.testing.assert_allclose(taut.slope(e, EA), EA * (lam**2 + eps), rtol=1e-12)
    cable = laws.Paper()
    np.testing.assert_allclose(cable.tension(e, EA), np.maximum(EA * eps * lam, 0.0),
                               rtol=1e-12, atol=1e-6)
    assert cable.slope(e, EA)[0] == 0.0 and cable.slope(e, EA)[-1] > 0


def test_curve_statics_invert_the_table_on_every_piece():
    """A curve's static tension at a strain is the table's linear interpolation, continued
    beyond the last point with the last slope; the static strain is its inverse, at the
    knots and between them; a taut-and-slack (tension_only=False) curve keeps going below
    zero with the first slope."""
    strain = np.array([0.0, 0.01, 0.03, 0.06])
    tension = np.array([0.0, 2.0e5, 1.0e6, 3.4e6])
    curve = laws.Curve(strain, tension)
    e = np.array([0.0, 0.004, 0.01, 0.02, 0.03, 0.05, 0.06, 0.08])
    last_slope = (tension[-1] - tension[-2]) / (strain[-1] - strain[-2])
    expected = np.where(e <= strain[-1], np.interp(e, strain, tension),
                        tension[-1] + last_slope * (e - strain[-1]))
    np.testing.assert_allclose(curve.static_tension(e), expected, rtol=1e-12, atol=1e-6)
    np.testing.assert_allclose(curve.static_strain(expected), e, rtol=1e-12, atol=1e-15)
    assert curve.static_tension(-0.01) == 0.0
    both = laws.Curve(strain, tension, tension_only=False)
    assert both.static_tension(-0.01) == pytest.approx(-0.01 * tension[1] / strain[1])


def test_dynamic_stiffness_grows_with_the_mean_tension():
    """MoorDyn's EA_d = alpha_MBL + beta T_mean (N) for a rope given alpha and beta; a
    fixed EA_dynamic does not depend on the mean tension."""
    rope = laws.StaticDynamic(alpha_MBL=1.2e8, beta=20.0)
    T_mean = np.array([0.0, 1.0e6, 4.0e6])
    np.testing.assert_allclose(rope.dynamic_EA(T_mean), 1.2e8 + 20.0 * T_mean, rtol=1e-14)
    fixed = laws.StaticDynamic(EA_dynamic=3.0e8)
    np.testing.assert_allclose(fixed.dynamic_EA(T_mean), 3.0e8, rtol=1e-14)


def test_curve_files_read_with_blanks_or_commas(tmp_path):
    """A MoorDyn curve file: three header lines, then strain and tension per line, blank-
    or comma-separated, blank lines skipped; the same Curve either way."""
    head = "EA curve\nStrain Tension\n(-) (N)\n"
    (tmp_path / "blanks.txt").write_text(head + "0.0 0.0\n0.01  2e5\n\n0.03\t1e6\n")
    (tmp_path / "commas.txt").write_text(head + "0.0,0.0\n0.01, 2e5\n0.03,1e6\n")
    blanks = laws.read_curve(tmp_path / "blanks.txt")
    commas = laws.read_curve(tmp_path / "commas.txt")
    assert blanks.strain == commas.strain == (0.0, 0.01, 0.03)
    assert blanks.tension_values == commas.tension_values == (0.0, 2e5, 1e6)
    assert "commas.txt" in commas.source
    named = laws.read_curve(tmp_path / "commas.txt", source="line type poly")
    assert named.source.startswith("line type poly (curve file commas.txt)")


def test_static_dynamic_carries_compression_when_told():
    """StaticDynamic(tension_only=False) over a tension-only static law: the static law's
    parameters are taken, but the slack rule is the StaticDynamic's own (compression
    carried at EA_s); tension_only=True leaves a slack cable at zero."""
    EA = 1.0e8
    both = laws.StaticDynamic(EA_dynamic=3 * EA, tension_only=False)
    assert both.tension(-0.01, EA) == pytest.approx(-0.01 * EA)
    assert both.tension(0.02, EA) == pytest.approx(0.02 * EA)
    cable = laws.StaticDynamic(EA_dynamic=3 * EA)
    assert cable.tension(-0.01, EA) == 0.0 and cable.tension(0.02, EA) == pytest.approx(0.02 * EA)


def test_viscoelastic_springs_in_series_give_the_static_stiffness():
    """The creep spring EA_1 and the dynamic spring EA_d in series make EA_s: 1/EA_1 +
    1/EA_d = 1/EA_s, at any creep strain for a fixed EA_d; with alpha and beta, EA_d =
    alpha_MBL + beta EA_1 z (MoorDyn's closed form) at the creep strain z."""
    EA_s = 1.0e8
    fixed = laws.Viscoelastic(EA_dynamic=3 * EA_s, creep_damping=1e9)
    z = np.array([0.0, 0.01, 0.05])
    EA_1, EA_d = fixed.stiffnesses(z, EA_s)
    np.testing.assert_allclose(EA_d, 3 * EA_s)
    np.testing.assert_allclose(1 / EA_1 + 1 / EA_d, 1 / EA_s, rtol=1e-12)
    rope = laws.Viscoelastic(alpha_MBL=2.0 * EA_s, beta=30.0, creep_damping=1e9)
    EA_1, EA_d = rope.stiffnesses(z, EA_s)
    np.testing.assert_allclose(EA_d, 2.0 * EA_s + 30.0 * EA_1 * z, rtol=1e-12)
    np.testing.assert_allclose(1 / EA_1 + 1 / EA_d, 1 / EA_s, rtol=1e-12)
    with pytest.raises(ValueError, match="must exceed the static one"):
        laws.Viscoelastic(EA_dynamic=EA_s, creep_damping=1e9).stiffnesses(z, EA_s)
