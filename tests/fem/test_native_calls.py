"""Calls by address between compiled functions (skmoor.fem.native_calls.call_compiled):
the callee's result, its in-place writes and its errors reach the caller as a direct
call's would; the caller compiles before its callee, and a caller that expects another
result type than the compiled callee's is refused while compiling."""
import numpy as np
import pytest
from numba import errors, njit, types

from skmoor.fem.native_calls import call_compiled, compiled_address


@njit(no_cpython_wrapper=True)
def _weighted_sum(values, weights, out):
    """out[0] <- sum(values * weights[1]) * weights[0]; raises on an empty ``values``."""
    if values.size == 0:
        raise ValueError("no values")
    total = 0.0
    for v in values:
        total += v * weights[1]
    out[0] = total * weights[0]
    return values.size


@njit
def _by_address(address, values, weights, out):
    return call_compiled(_weighted_sum, address, (values, weights, out), 0)


def test_a_call_by_address_returns_and_writes_what_the_function_computes():
    values, weights, out = np.array([1.0, -2.0, 4.0]), (0.5, 3.0), np.zeros(1)
    address = compiled_address(_weighted_sum, values, weights, out)
    assert _by_address(address, values, weights, out) == 3
    assert out[0] == pytest.approx(0.5 * 3.0 * 3.0)  # a swapped weight gives 0.5 * 1.5 * 3
    other = np.array([2.0])
    assert _by_address(address, other, (2.0, 1.0), out) == 1  # the same types, new values
    assert out[0] == 4.0


def test_an_error_in_the_callee_reaches_the_caller():
    empty, weights, out = np.zeros(0), (1.0, 1.0), np.zeros(1)
    address = compiled_address(_weighted_sum, empty, weights, out)
    with pytest.raises(ValueError, match="no values"):
        _by_address(address, empty, weights, out)


@njit(no_cpython_wrapper=True)
def _scaled(values, factor):
    """values <- factor * values; their new sum."""
    total = 0.0
    for i in range(values.size):
        values[i] *= factor
        total += values[i]
    return total


@njit
def _scaled_by_address(address, values, factor):
    return call_compiled(_scaled, address, (values, factor), 0.0)


def test_the_caller_compiles_before_its_callee():
    values = np.array([1.0, 2.0])
    _scaled_by_address.compile((types.int64, types.float64[::1], types.float64))
    assert not _scaled.overloads  # the caller's code needs only the callee's types
    address = compiled_address(_scaled, values, 2.0)
    assert _scaled_by_address(address, values, 2.0) == 6.0  # a dropped factor gives 3
    assert list(values) == [2.0, 4.0]


def test_a_caller_expecting_another_result_type_is_refused():
    @njit
    def by_address_float(address, values, weights, out):
        return call_compiled(_weighted_sum, address, (values, weights, out), 0.0)

    values, weights, out = np.ones(2), (1.0, 2.0), np.zeros(1)
    compiled_address(_weighted_sum, values, weights, out)  # returns an int64
    with pytest.raises(errors.TypingError, match="returns int64, not float64"):
        by_address_float(0, values, weights, out)
