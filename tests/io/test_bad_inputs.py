"""The catalogue of bad inputs: each gets a one-line message naming the field and the
reason (case files, decks, the Python API and the command line). Run settings, output
folders and physically impossible geometry have their own tests (test_run_settings.py,
test_checks.py); fuzzed edits of cases and decks are in test_fuzz_inputs.py."""
import pytest

import skmoor
from skmoor import cli

PAPER = skmoor.paper_case()


def build_paper(path, value):
    return lambda: skmoor.build(PAPER.replace(path, value))


CATALOGUE = [
    ("a heading in words", build_paper("lines.0.heading_deg", "north"),
     r"lines\[0\]\.heading_deg: expected a number, got 'north'"),
    ("a length in words", build_paper("lines.0.length", "long"),
     r"lines\[0\]\.length: expected a number, got 'long'"),
    ("a number for a name", build_paper("lines.0.name", 42),
     r"lines\[0\]\.name: expected a string, got 42"),
    ("a negative forcing frequency", build_paper("load.omega", -1.0),
     r"load\.omega: must be positive, got -1\.0"),
    ("no elements", build_paper("mooring.n_elements", 0),
     r"mooring\.n_elements: must be an integer >= 1, got 0"),
    ("a billion elements", build_paper("mooring.n_elements", 10**9),
     r"mooring\.n_elements: must be at most"),
    ("a negative depth", build_paper("water.depth", -100.0),
     r"water\.depth: must be positive, got -100\.0"),
    ("a folder for a case file", lambda: skmoor.build("examples"),
     r"build: examples is a folder"),
    ("a folder for a case file (Case)", lambda: skmoor.Case.from_toml("examples"),
     r"case file examples: is a folder"),
    ("a folder for a deck", lambda: skmoor.read_deck("examples"),
     r"deck examples: is a folder"),
    ("a missing deck", lambda: skmoor.read_deck("no/such/deck.dat"),
     r"deck no/such/deck\.dat does not exist"),
    ("a time step in words", lambda: skmoor.simulate(skmoor.build(PAPER), dt="0.1"),
     r"dt: must be a number of seconds, got '0\.1'"),
]


@pytest.mark.parametrize("what, make, message", CATALOGUE, ids=[c[0] for c in CATALOGUE])
def test_bad_input_gets_one_line_naming_the_field(what, make, message):
    with pytest.raises((ValueError, FileNotFoundError), match=message) as info:
        make()
    assert "\n" not in str(info.value).strip()


def test_the_command_line_says_it_in_one_line(capsys, tmp_path):
    assert cli.main(["run", "examples", "--out", str(tmp_path / "o"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("skmoor run: error:") and "is a folder" in err and "\n" not in err
