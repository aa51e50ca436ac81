"""skmoor.numerics.roots.brent, the bracketed root finder under the catenary solves: roots known in
closed form, to the requested tolerance, and the errors it owes."""
import math

import pytest

from skmoor.numerics.roots import brent


@pytest.mark.parametrize("f, a, b, root", [
    (lambda x: x**3 - 2 * x - 5, 2.0, 3.0, None),  # Wallis' cubic, checked by its residual
    (math.cos, 0.0, 3.0, math.pi / 2),
    (lambda x: math.exp(x) - 1e6, 0.0, 30.0, math.log(1e6)),
    (lambda x: math.tanh(50 * (x - 0.3)), -1.0, 1.0, 0.3),  # nearly a step
    (lambda x: (x - 1.0) ** 5, 0.0, 3.1, 1.0),  # a flat, multiple root
])
def test_brent_finds_the_root_to_the_tolerance(f, a, b, root):
    x = brent(f, a, b, xtol=1e-13)
    if root is None:
        assert abs(f(x)) < 1e-12
    else:
        assert abs(x - root) <= 1e-13 + 4 * 2.2e-16 * abs(root)


def test_brent_takes_few_evaluations_on_smooth_functions():
    calls = []

    def f(x):
        calls.append(x)
        return x**3 - 2 * x - 5

    brent(f, 2.0, 3.0, xtol=1e-14)
    assert len(calls) <= 10  # superlinear: bisection alone would need ~47


def test_brent_refuses_a_bracket_without_a_sign_change():
    with pytest.raises(ValueError, match="same sign"):
        brent(lambda x: x * x + 1.0, -1.0, 1.0)
