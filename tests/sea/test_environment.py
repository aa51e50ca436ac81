"""The case file's environment sections ([sea], [seabed], line and body coefficients):
validation, and the loads they switch on against hand numbers."""
from pathlib import Path

import numpy as np
import pytest
from peers import condensed_line_stiffness

import skmoor
from skmoor.sea.hydro import LineHydroKernel
from skmoor.sea.seabed import SeabedKernel


@pytest.mark.parametrize("change, message", [
    (dict(sea__waves=[{"type": "airy", "height": -1.0, "period": 8.0}]),
     "sea.waves[0].height: must be positive"),
    (dict(sea__waves=[{"type": "stokes", "height": 1.0, "period": 8.0}]), "sea.waves[0].type"),
    (dict(sea__current_heading_deg=float("nan"), sea__current_speed=1.0), "sea.current"),
    (dict(sea__swell=1.0), "sea.swell: unknown key"),
    (dict(seabed__mu_axial=-0.5), "seabed.mu_axial: must be >= 0"),
    (dict(seabed__kbot=1e6), "seabed.kbot: unknown key"),
    (dict(line_types__steel__Cd_n=-1.0), "line_types.steel.Cd_n"),
    (dict(line_types__steel__BA="big"), "line_types.steel.BA: expected a number"),
])
def test_bad_environment_input_names_the_field(change, message):
    with pytest.raises(ValueError, match=message.replace("[", r"\[").replace("]", r"\]")):
        skmoor.paper_case(**change)


def test_sections_switch_the_terms_on(tmp_path):
    """A TOML case with the sections builds the hydrodynamic and sea-bed kernels and a
    body drag term; the paper's case has none."""
    assert skmoor.build(skmoor.paper_case()).system.terms == ()
    text = (tmp_path / "base.toml")
    text.write_text(Path("examples/paper_case.toml").read_text() + """
[sea]
current_speed = 0.5
[seabed]
mu_axial = 0.3
""")
    case = skmoor.Case.from_toml(text).replace("line_types.steel.Cd_n", 1.2)
    system = skmoor.build(case.replace("body.drag_coefficients", [1.0, 1.0, 1.0])
                          .replace("body.drag_areas", [50.0, 130.0, 260.0])).system
    kinds = {type(term) for term in system.line_terms}
    assert kinds == {LineHydroKernel, SeabedKernel}
    assert len(system.body_terms) == 1


def test_current_on_the_body_offsets_it_by_drag_over_stiffness():
    """Body drag only ([sea] current along x, body CdA): the static surge offset is
    1/2 rho CdA U^2 over the mooring's surge stiffness (condensed, with the body's own
    hydrostatics, zero in surge), within 2 % (the offset is 1e-3 of the line length)."""
    U, cd, area = 0.8, 1.0, 130.0
    case = skmoor.paper_case(sea__current_speed=U, body__drag_coefficients=[cd, cd, cd],
                             body__drag_areas=[area, 260.0, 338.0])
    model = skmoor.build(case)
    x = skmoor.solve_static(model.system).x
    still = skmoor.build(skmoor.paper_case())
    x0 = skmoor.solve_static(still.system).x
    K = condensed_line_stiffness(still.system, x0) + still.system.K_body
    force = 0.5 * case.water["density"] * cd * area * U**2
    surge = model.system.q(x)[0] - still.system.q(x0)[0]
    expected = np.linalg.solve(K, np.r_[force, 0, 0, 0, 0, 0])[0]
    assert surge == pytest.approx(expected, rel=0.02)
