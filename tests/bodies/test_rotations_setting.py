"""rotations = 'exact' | 'small' from a case file ([body], [[bodies]]) and for a MoorDyn
deck (skmoor.build(deck, rotations=...)): validated, and the bodies built with the hull
that the exact hydrostatics clip (placed right: at rest its buoyancy and moment are the
linear hydrostatics' ones)."""
import copy
from pathlib import Path

import numpy as np
import pytest
from test_schema import NETWORK_CASE

import skmoor
from skmoor.cli import main, parser
from skmoor.io.case import Case, paper_case
from skmoor.io.schema import validate_case

DECKS = Path(__file__).parents[1] / "decks"


def network_data(**body):
    data = copy.deepcopy(NETWORK_CASE)
    data["bodies"][0].update(body)
    return data


def test_rotations_key_is_validated_with_its_field_named():
    for case in (network_data(rotations="large"),
                 paper_case().data | {"body": paper_case().data["body"] | {"rotations": 1}}):
        with pytest.raises(ValueError, match=r"rotations.*'small'.*'exact'|rotations.*exact"):
            validate_case(case)
    data = copy.deepcopy(NETWORK_CASE)
    data["bodies"][0].update(kind="fixed", rotations="exact")
    with pytest.raises(ValueError, match="rotations.*only for a dynamic body"):
        validate_case(data)
    data = copy.deepcopy(NETWORK_CASE)
    del data["bodies"][0]["size"]
    data["bodies"][0]["rotations"] = "exact"
    with pytest.raises(ValueError, match="rotations.*buoyancy geometry"):
        validate_case(data)


def assert_exact_at_rest_is_the_linear_hydrostatics(rigid):
    """Its clipped hull at q = 0 gives the linear model's buoyancy and moment (a hull
    placed about the wrong point, or left out, gives another force or an error)."""
    assert rigid.rotations == "exact" and rigid.hull is not None
    assert np.allclose(rigid.restoring_load(np.zeros(6)), rigid.static_force(),
                       rtol=1e-9, atol=1e-6 * rigid.mass * rigid.g)


def test_network_case_body_with_exact_rotations():
    model = skmoor.build(Case(network_data(rotations="exact")))
    assert_exact_at_rest_is_the_linear_hydrostatics(model.system.bodies[0])


def test_paper_case_body_with_exact_rotations():
    model = skmoor.build(paper_case(body__rotations="exact"))
    rigid = model.system.bodies[0]
    assert_exact_at_rest_is_the_linear_hydrostatics(rigid)
    # the paper's box floats at its equilibrium draft: weight + lines = buoyancy
    eq = skmoor.equilibrium(model)
    assert np.abs(eq.x[-6:]).max() < 1e-3


def test_deck_bodies_take_rotations_from_build():
    deck = DECKS / "bodies" / "turning_body.dat"
    with pytest.warns(Warning):  # its taut lines start stretched
        exact = skmoor.build(deck, rotations="exact")
    assert [b.rotations for b in exact.system.bodies] == ["exact"]
    with pytest.raises(ValueError, match="rotations: 'large' is not 'small' or 'exact'"):
        skmoor.build(deck, rotations="large")
    with pytest.raises(ValueError, match="build rotations: a case sets"):
        skmoor.build(paper_case(), rotations="exact")


def test_command_line_rotations_for_a_deck(tmp_path, capsys):
    assert parser().parse_args(["run", "deck.dat", "--rotations", "exact"]).rotations == "exact"
    with pytest.raises(SystemExit):  # argparse: not one of the choices
        parser().parse_args(["run", "deck.dat", "--rotations", "large"])
    case = Path(__file__).parents[2] / "examples" / "paper_case.toml"
    code = main(["run", str(case), "--out", str(tmp_path / "out"), "--rotations", "exact",
                 "--quiet"])
    assert code == 2 and "a case sets its bodies' rotations" in capsys.readouterr().err
