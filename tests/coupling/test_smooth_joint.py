"""Smooth (C1) joints of bending lines at a free point (``Point(smooth=True)``,
``Ends.smooth``) against Euler-Bernoulli: a beam made of two lines joined at mid-span
carries the bending moment across the joint as one beam does; the same two lines
joined at a hinge (a plain free point) do not."""
from pathlib import Path

import numpy as np
import pytest

from skmoor.coupling.network import MooringLine, Network, Point
from skmoor.coupling.system import Ends
from skmoor.lines.laws import Engineering
from skmoor.lines.line import LineType
from skmoor.model.model import from_network
from skmoor.run.equilibrium import equilibrium

L, EI, EA, W = 10.0, 1e8, 1e10, 100.0  # m, N m2, N, N/m: deflections ~1e-5 L (linear theory)
N = 4  # elements per half


def beam_type(EI=EI):
    return LineType(EA=EA, mass=W / 9.81, diameter=0.1, weight=W, EI=EI,
                    law=Engineering(tension_only=False))


def two_half_beam(smooth, clamped):
    """A beam of length L under its weight W, pinned (or clamped horizontally) at both
    ends, made of two lines of L / 2 joined at a free point at mid-span. Returns the
    mid-span deflection (m, down positive), the LineSet and the displacement."""
    held = (1.0, 0.0, 0.0) if clamped else False
    points = [Point("a", "fixed", [0.0, 0.0, -5.0]),
              Point("mid", "free", [L / 2, 0.0, -5.0], smooth=smooth),
              Point("b", "fixed", [L, 0.0, -5.0])]
    lines = [MooringLine("left", beam_type(), "a", "mid", L / 2, N, clamp_a=held),
             MooringLine("right", beam_type(), "mid", "b", L / 2, N, clamp_b=held)]
    model = from_network(Network(points, lines, depth=50.0, hydro=False))
    eq = equilibrium(model, n_modes=1)
    lineset, u = model.lines, model.system.full_displacement(eq.x)
    z = (lineset.points + u[lineset.nodal_dofs])[:, 2]
    return -5.0 - z[lineset.fairlead_nodes[0]], lineset, u


def test_simply_supported_beam_of_two_smooth_lines():
    """Pinned ends, smooth joint: mid-span deflection 5 w L^4 / 384 EI and moment
    w s (L - s) / 2 (its largest, w L^2 / 8, at the joint: 1224 N m at the element
    mid-points 0.625 m from it, within 1 % of the exact 1230.5). A dropped joint (each
    line's own tangent: a hinge) would make the beam a mechanism that sags as a cable."""
    deflection, lineset, u = two_half_beam(smooth=True, clamped=False)
    assert deflection == pytest.approx(5 * W * L**4 / (384 * EI), rel=1e-4)
    s = np.r_[(np.arange(N) + 0.5) * L / (2 * N), L / 2 + (np.arange(N) + 0.5) * L / (2 * N)]
    exact = W * s * (L - s) / 2
    M = lineset.bending_moment(u)
    np.testing.assert_allclose(M, exact, rtol=0.01, atol=0.01 * W * L**2 / 8)
    assert M[N - 1] == pytest.approx(M[N], rel=1e-6)  # symmetric about the joint
    # the joint's tangent is one: the slope DOFs of the two ends are the same numbers
    left_end, right_start = lineset.fairlead_nodes[0], lineset.anchor_nodes[1]
    np.testing.assert_array_equal(u[lineset.slope_dofs[left_end]], u[lineset.slope_dofs[right_start]])


def test_clamped_beam_smooth_against_hinged_joint():
    """Clamped ends: smooth, one clamped-clamped beam, mid-span deflection w L^4 / 384 EI
    and end moment w L^2 / 12; hinged, two cantilevers of L / 2 meeting tip to tip
    (no shear by symmetry), mid-span deflection w (L / 2)^4 / 8 EI = w L^4 / 128 EI, three
    times more, and no moment at the joint."""
    smooth, lines_s, u_s = two_half_beam(smooth=True, clamped=True)
    hinged, lines_h, u_h = two_half_beam(smooth=False, clamped=True)
    assert smooth == pytest.approx(W * L**4 / (384 * EI), rel=2e-3)
    assert hinged == pytest.approx(W * L**4 / (128 * EI), rel=2e-3)
    # the moments at the element mid-points next to an end (s = h / 2) and the joint
    h = L / (2 * N)
    M_s, M_h = lines_s.bending_moment(u_s), lines_h.bending_moment(u_h)

    def clamped_beam(s):  # |w (6 L s - 6 s^2 - L^2) / 12|: w L^2 / 12 at the ends
        return abs(W * (6 * L * s - 6 * s**2 - L**2) / 12)

    def cantilever(s):  # w (L / 2 - s)^2 / 2 from the clamp at s = 0 to the hinge
        return W * (L / 2 - s) ** 2 / 2

    assert M_s[0] == pytest.approx(clamped_beam(h / 2), rel=0.03)
    assert M_s[N - 1] == pytest.approx(clamped_beam(L / 2 - h / 2), rel=0.03)
    assert M_h[0] == pytest.approx(cantilever(h / 2), rel=0.03)
    assert M_h[N - 1] == pytest.approx(cantilever(L / 2 - h / 2), abs=0.01 * cantilever(0))


def test_modes_across_a_smooth_joint():
    """The pinned beam of two smoothly joined lines vibrates as one beam: omega_n =
    (n pi / L)^2 sqrt(EI / m), n = 1, 2, 3, in both planes, within 1e-4 at 16 elements
    as one line of 16 (the joint's shared tangent DOFs carry the consistent mass of both
    sides; dropping one side's would raise the frequencies)."""
    points = [Point("a", "fixed", [0.0, 0.0, -5.0]),
              Point("mid", "free", [L / 2, 0.0, -5.0], smooth=True),
              Point("b", "fixed", [L, 0.0, -5.0])]
    lines = [MooringLine("left", beam_type(), "a", "mid", L / 2, 8),
             MooringLine("right", beam_type(), "mid", "b", L / 2, 8)]
    model = from_network(Network(points, lines, depth=50.0, hydro=False))
    omega = equilibrium(model, n_modes=6).modes.omega
    exact = (np.repeat([1, 2, 3], 2) * np.pi / L) ** 2 * np.sqrt(EI / (W / 9.81))
    np.testing.assert_allclose(np.sort(omega), exact, rtol=1e-4)


def beam_case(smooth, anchor=None):
    """The pinned two-line beam as a case file's tables (``smooth`` on the joint, and on
    the fixed end a when ``anchor`` is given)."""
    from skmoor.io.case import Case

    point = {"name": "mid", "kind": "free", "position": [L / 2, 0.0, -5.0], "smooth": smooth}
    end = {"name": "a", "kind": "fixed", "position": [0.0, 0.0, -5.0]}
    if anchor is not None:
        end["smooth"] = anchor
    return Case({
        "name": "two-line beam", "water": {"density": 1025.0, "gravity": 9.81, "depth": 50.0},
        "line_types": {"beam": {"EA": EA, "mass": 50.0, "diameter": 0.1, "EI": EI}},
        "mooring": {"tension_only": False},
        "points": [end, point,
                   {"name": "b", "kind": "fixed", "position": [L, 0.0, -5.0]}],
        "lines": [{"name": "left", "type": "beam", "a": "a", "b": "mid", "length": L / 2,
                   "n_elements": N},
                  {"name": "right", "type": "beam", "a": "mid", "b": "b", "length": L / 2,
                   "n_elements": N}]}, Path("."))


def test_case_file_smooth_point():
    """``smooth = true`` on a case file's free point: the pinned beam of two lines sags
    5 w L^4 / 384 EI (w its submerged weight); on a fixed point, or not a flag, refused."""
    import skmoor

    model = skmoor.build(beam_case(True))
    w = model.network.lines[0].line_type.weight
    lineset = model.lines
    u = model.system.full_displacement(equilibrium(model, n_modes=1).x)
    z = (lineset.points + u[lineset.nodal_dofs])[lineset.fairlead_nodes[0], 2]
    assert -5.0 - z == pytest.approx(5 * w * L**4 / (384 * EI), rel=1e-3)
    with pytest.raises(ValueError, match=r"points\[1\]\.smooth: expected true or false"):
        skmoor.build(beam_case("yes"))
    with pytest.raises(ValueError, match=r"points\[0\]\.smooth: only a free point"):
        skmoor.build(beam_case(True, anchor=True))


def test_bad_smooth_joints():
    """A smooth joint is a free point between end b of one bending line and end a of the
    next; anything else is refused naming the point (or the Ends entry)."""
    with pytest.raises(ValueError, match="point p smooth: only a free point"):
        Point("p", "fixed", [0.0, 0.0, 0.0], smooth=True)
    points = [Point("a", "fixed", [0.0, 0.0, -5.0]), Point("mid", "free", [5.0, 0.0, -5.0], smooth=True),
              Point("b", "fixed", [10.0, 0.0, -5.0])]
    backwards = [MooringLine("left", beam_type(), "a", "mid", 5.0, 2),
                 MooringLine("right", beam_type(), "b", "mid", 5.0, 2)]
    with pytest.raises(ValueError, match="point mid smooth: a smooth joint takes end b of one "
                                         "line and end a of the next"):
        from_network(Network(points, backwards, depth=50.0, hydro=False))
    cable = [MooringLine("left", beam_type(), "a", "mid", 5.0, 2),
             MooringLine("right", beam_type(EI=0.0), "mid", "b", 5.0, 2)]
    with pytest.raises(ValueError, match="line right has no bending stiffness"):
        from_network(Network(points, cable, depth=50.0, hydro=False))
    with pytest.raises(ValueError, match="not on the same free point"):
        Ends([("fixed",), ("point", 0)], [("point", 1), ("fixed",)], smooth=[(0, 1)])
    with pytest.raises(ValueError, match="end B of line 0 is in two joints"):
        Ends([("fixed",), ("point", 0), ("point", 0)], [("point", 0), ("fixed",), ("fixed",)],
             smooth=[(0, 1), (0, 2)])
