"""Property-based fuzzing of the case reader and the deck reader: whatever a user writes,
skmoor builds a model or stops with a one-line error naming what is wrong, never a
traceback (any other exception type) and never a silent NaN in the built model."""
import math
from pathlib import Path

import numpy as np
import pytest
import tomllib
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import skmoor

CASE = Path("examples/paper_case.toml")
DECK = Path("tests/decks/network/two_segment.dat")
FUZZ = settings(max_examples=40, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

# what a user might type where a value belongs
VALUES = st.one_of(
    st.sampled_from([0, -1, -1e9, 1e12, math.inf, -math.inf, math.nan, "", "north", "1e3",
                     True, [], [1.0], [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0], {}, {"a": 1},
                     10**7]),
    st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**6, 10**6),
    st.text(max_size=8))


def leaves(data, prefix=()):
    """Every (path, value) leaf of a nested dict (lists of tables by index)."""
    for key, value in data.items():
        path = prefix + (key,)
        if isinstance(value, dict):
            yield from leaves(value, path)
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            for i, item in enumerate(value):
                yield from leaves(item, path + (i,))
        else:
            yield path, value


def assign(data, path, value):
    target = data
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value


def remove(data, path):
    target = data
    for key in path[:-1]:
        target = target[key]
    del target[path[-1]]


def one_line_error_or_model(make):
    """Build with ``make()``: a Model without NaN, or a ValueError of one line."""
    try:
        model = make()
    except (ValueError, FileNotFoundError) as err:
        text = str(err)
        assert text and "\n" not in text.strip(), f"a multi-line message: {text!r}"
        assert "Traceback" not in text
        return None
    assert np.all(np.isfinite(model.lines.points))
    return model


@pytest.fixture(scope="module")
def case_data():
    with open(CASE, "rb") as f:
        return tomllib.load(f)


@FUZZ
@given(data=st.data())
def test_any_case_edit_builds_or_fails_in_one_line(case_data, data):
    import copy

    edited = copy.deepcopy(case_data)
    paths = sorted(leaves(edited), key=str)
    for _ in range(data.draw(st.integers(1, 3))):
        path, _ = data.draw(st.sampled_from(paths))
        if data.draw(st.booleans()):
            assign(edited, path, data.draw(VALUES))
        else:
            try:
                remove(edited, path)
            except KeyError:
                pass
        paths = sorted(leaves(edited), key=str)
    one_line_error_or_model(lambda: skmoor.build(skmoor.Case(edited, CASE.parent)))


WORDS = st.sampled_from(["", "x", "-", "nan", "inf", "-1", "0", "1e40", "Fixed", "Free",
                         "Coupled", "Body1", "chain", "99", "3.5.2", "(m)", "|", "1|2"])


@FUZZ
@given(data=st.data())
def test_any_deck_edit_builds_or_fails_in_one_line(data, tmp_path_factory):
    lines = DECK.read_text().splitlines()
    for _ in range(data.draw(st.integers(1, 3))):
        k = data.draw(st.integers(0, len(lines) - 1))
        words = lines[k].split()
        action = data.draw(st.sampled_from(["word", "drop-word", "drop-line", "duplicate"]))
        if action == "word" and words:
            words[data.draw(st.integers(0, len(words) - 1))] = data.draw(WORDS)
            lines[k] = "  ".join(words)
        elif action == "drop-word" and words:
            del words[data.draw(st.integers(0, len(words) - 1))]
            lines[k] = "  ".join(words)
        elif action == "drop-line":
            del lines[k]
        else:
            lines.insert(k, lines[k])
    path = tmp_path_factory.mktemp("deck") / "fuzzed.dat"
    path.write_text("\n".join(lines) + "\n")
    one_line_error_or_model(lambda: skmoor.build(path))
