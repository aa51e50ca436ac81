"""Motion records (skmoor.Record, read_motion): a cubic spline through the rows whose
velocity and acceleration are its own derivatives, one interval search per call for all
columns.

Checked against finite differences of the record's own position and velocity (central,
h = 1e-5 s: consistent to 1e-6 of the values' scale), against the sampled closed form
(sin at 0.01 s: the spline within 1e-7 m of it, its velocity within 1e-5 m/s, its
acceleration within 2e-3 m/s2), held outside the table, and the same values for scalar
and array times, in any order of calls (the kept interval does not change a result)."""
import numpy as np
import pytest

from skmoor import Record, read_motion


def sampled(rows=12_000, dt=0.01):
    t = np.arange(rows) * dt
    values = np.column_stack([np.sin(0.5 * t), 0.3 * np.cos(1.1 * t), 0.1 * t])
    return t, values


def test_derivatives_are_the_interpolations_own():
    t, values = sampled(400)
    record = Record(t, values)
    rng = np.random.default_rng(1)
    h = 1e-5
    for time in rng.uniform(t[0] + h, t[-1] - h, 50):
        p_fd = (record.position(time + h) - record.position(time - h)) / (2 * h)
        v_fd = (record.velocity(time + h) - record.velocity(time - h)) / (2 * h)
        np.testing.assert_allclose(record.velocity(time), p_fd, atol=1e-6)
        np.testing.assert_allclose(record.acceleration(time), v_fd, atol=1e-6)
    # continuity at the knots: the same value, velocity and acceleration from both sides
    for order in (record.position, record.velocity, record.acceleration):
        np.testing.assert_allclose(order(t[100] - 1e-9), order(t[100] + 1e-9), atol=1e-7)


def test_record_follows_the_sampled_motion():
    t, values = sampled()
    record = Record(t, values)
    times = np.linspace(1.0, t[-1] - 1.0, 997)
    exact = np.column_stack([np.sin(0.5 * times), 0.3 * np.cos(1.1 * times), 0.1 * times])
    rate = np.column_stack([0.5 * np.cos(0.5 * times), -0.33 * np.sin(1.1 * times),
                            0.1 + 0 * times])
    accel = np.column_stack([-0.25 * np.sin(0.5 * times), -0.363 * np.cos(1.1 * times),
                             0 * times])
    np.testing.assert_allclose(record.position(times), exact, atol=1e-7)
    np.testing.assert_allclose(record.velocity(times), rate, atol=1e-5)
    np.testing.assert_allclose(record.acceleration(times), accel, atol=2e-3)
    # scalar calls in a scrambled order give the array call's values
    order = np.random.default_rng(2).permutation(len(times))
    scalar = np.array([record.position(times[i]) for i in order])
    np.testing.assert_array_equal(scalar, record.position(times)[order])


def test_held_outside_the_table():
    t, values = sampled(50)
    record = Record(t, values)
    np.testing.assert_allclose(record.position(-3.0), values[0], atol=1e-12)
    np.testing.assert_allclose(record.position(t[-1] + 5.0), values[-1], atol=1e-12)
    assert not np.any(record.velocity(t[-1] + 5.0)) and not np.any(record.acceleration(-1.0))
    with pytest.raises(ValueError, match="increase"):
        Record([0.0, 1.0, 1.0], np.zeros((3, 3)))


def test_read_motion_gives_a_record(tmp_path):
    t, values = sampled(100)
    path = tmp_path / "motion.csv"
    np.savetxt(path, np.column_stack([t, values]), delimiter=",", header="t, x, y, z")
    motion = read_motion(path, 3)
    assert isinstance(motion, Record) and motion.vectorized
    np.testing.assert_allclose(motion(0.505), Record(t, values).position(0.505), rtol=1e-12)
