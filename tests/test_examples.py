"""The examples run (as scikit-fem's do) and their numbers hold physics."""
import importlib.util
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).parents[1] / "examples"


def load(name, monkeypatch=None, **env):
    for key, value in env.items():
        monkeypatch.setenv(key, value)
    spec = importlib.util.spec_from_file_location(name.replace(".py", ""), EXAMPLES / name)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_static_line_converges_to_catenary_at_second_order():
    """Example 01: FE fairlead tension -> analytic elastic catenary, order 2, < 0.1 % at 20."""
    ex = load("01_static_line.py")
    assert -ex.order == pytest.approx(2.0, abs=0.15)
    assert ex.errors[ex.elements.index(20)] < 1e-3


def test_drag_form_damps_the_coupled_response(monkeypatch):
    """Example 03: a user-written Morison drag form lowers surge and tension amplitudes."""
    ex = load("03_weak_form_drag.py", monkeypatch, SKMOOR_EXAMPLE_DURATION="20")
    assert ex.drag[0] < 0.95 * ex.plain[0]
    assert ex.drag[1] < 0.95 * ex.plain[1]
