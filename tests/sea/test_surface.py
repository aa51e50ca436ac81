"""Lines through the free surface (skmoor.sea.surface): the dry part has no buoyancy, no drag.

Independent numbers: the weight of a vertical hanging line, dry above z = 0 and submerged
below, in closed form (statics); central differences of the term (its Taylor test).
The Lowe & Langley heave case, where the jumper's top leaves the water, is in
tests/io/test_bending_decks.py (slow).
"""
import numpy as np
import pytest

import skmoor
from skmoor import MooringLine, Network, Point
from skmoor.fem.terms import check_tangent
from skmoor.run.equilibrium import equilibrium
from skmoor.sea.surface import SurfaceTerm

RHO, G = 1025.0, 9.81
ROPE = skmoor.LineType(EA=5e8, mass=60.0, diameter=0.2, Cd_n=1.2, Cd_t=0.1,
                       rho_water=RHO, g=G)
ABOVE, BELOW = 12.3, 37.7  # m of line above and below the still water line


def hanging(surface, element="p1", n=100):
    """A line hanging from a fixed point ABOVE m over the water to a free clump BELOW m
    under it (almost vertical: the clump 0.5 m aside), n elements."""
    line_type = ROPE if element == "p1" else skmoor.LineType(
        EA=ROPE.EA, mass=ROPE.mass, diameter=ROPE.diameter, EI=2e3, Cd_n=ROPE.Cd_n,
        Cd_t=ROPE.Cd_t, rho_water=RHO, g=G)
    points = [Point("top", "fixed", [0.0, 0.0, ABOVE]),
              Point("clump", "free", [0.5, 0.0, -BELOW], mass=3000.0, volume=0.5)]
    lines = [MooringLine("line", line_type, "top", "clump", ABOVE + BELOW + 1e-3, n)]
    return Network(points, lines, depth=200.0, rho=RHO, g=G, surface=surface)


pytestmark = pytest.mark.filterwarnings("ignore:point top")  # the top is 12.3 m above water


@pytest.mark.parametrize("element", ["p1", "hermite"])
def test_hanging_line_weighs_dry_above_the_surface(element):
    """Vertical pull at the top = clump's net weight + the line's dry weight m g over the
    part above z = 0 + its submerged weight (m - rho A) g below, within 2e-4 at 100 P1
    or 50 Hermite elements (the part above: its unstretched length from the static
    stretch; the Gauss points see the surface crossing to about a tenth of an element:
    P1 1.4e-3 at 25 elements, 4e-5 at 100; Hermite 3.7e-4 at 25, 9.5e-5 at 50). Without the term (all submerged) the pull is 4.5 % lower: a
    lost buoyancy with the wrong sign or a factor 2, or a dry fraction turned upside
    down, fails."""
    results = {}
    for surface in (True, False):
        model = skmoor.from_network(hanging(surface, element, n=100 if element == "p1" else 50))
        eq = equilibrium(model, n_modes=1)
        u = model.system.full_displacement(eq.x)
        lines = model.lines
        X = lines.points + u[lines.nodal_dofs]
        top = model.system.reactions(eq.x)[1][0]  # the line's end A force on the top
        results[surface] = -top[2]
        if surface:
            z = X[:, 2]
            assert z.max() == pytest.approx(ABOVE) and z.min() < -BELOW + 0.1
    line = ROPE
    clump = (3000.0 - RHO * 0.5) * G
    # the length above water, unstretched: the line is nearly vertical and its strain tiny
    strain = results[True] / line.EA
    above = ABOVE / (1.0 + strain)
    total = ABOVE + BELOW + 1e-3
    dry = line.mass * G * above + (line.mass - RHO * line.area) * G * (total - above) + clump
    wet = (line.mass - RHO * line.area) * G * total + clump
    assert results[True] == pytest.approx(dry, rel=2e-4)
    assert results[False] == pytest.approx(wet, rel=2e-4)
    assert (dry - wet) / wet > 0.04


@pytest.mark.parametrize("element", ["p1", "hermite"])
def test_surface_term_tangents(element):
    """Taylor test of the dry part's hand-written tangents (buoyancy ramp and drag, both
    in u and in the velocity) on a line crossing the surface, shifted up so that a Gauss
    point lies inside the ramp: slope 2 (a dropped d(dry)/dz or a drag tangent not
    scaled by the dry fraction gives 1)."""
    model = skmoor.from_network(hanging(True, element, n=8))
    lines = model.lines
    term = next(t for t in model.system.terms if isinstance(t, SurfaceTerm))
    z = np.asarray(lines.basis.interpolate(lines.reference_dofs))[2]  # heights of the Gauss points
    nearest = z.ravel()[np.argmin(np.abs(z.ravel()))]
    u = np.zeros(lines.ndofs)
    u[lines.nodal_dofs[:, 2]] = 0.25 * ROPE.diameter - nearest  # that point in the ramp
    u += 1e-3 * np.random.default_rng(1).standard_normal(lines.ndofs)
    v = 0.5 * np.random.default_rng(2).standard_normal(lines.ndofs)
    check = check_tangent(model, term, u=u, v=v, seed=3)
    assert check.ok, str(check)
    assert check.slope_u is not None and check.slope_v is not None


@pytest.mark.parametrize("element", ["p1", "hermite"])
def test_buoyancy_sums_are_the_forms(element):
    """The term sums its buoyancy part in NumPy on the elements near the surface: the
    same residual and stiffness as scikit-fem's assembly of the forms dry_buoyancy and
    dry_buoyancy_stiffness on every element, to round-off."""
    from skfem import asm

    from skmoor.sea.surface import dry_buoyancy, dry_buoyancy_stiffness

    model = skmoor.from_network(hanging(True, element, n=8))
    lines = model.lines
    term = next(t for t in model.system.terms if isinstance(t, SurfaceTerm))
    u = 0.05 * np.random.default_rng(4).standard_normal(lines.ndofs)
    R, K, _ = term.evaluate(u, np.zeros_like(u))
    _, w = term._w(u, np.zeros_like(u), 0.0)
    R_form = asm(dry_buoyancy, lines.basis, **w)
    K_form = asm(dry_buoyancy_stiffness, lines.basis, **w)
    assert np.abs(R_form).max() > 100.0  # the part above water is there
    np.testing.assert_allclose(R, R_form, rtol=0, atol=1e-9 * np.abs(R_form).max())
    assert abs(K - K_form).max() <= 1e-9 * abs(K_form).max()
