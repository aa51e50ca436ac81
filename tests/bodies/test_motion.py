"""Prescribed motions (skmoor.bodies.motion.Motion): the exact velocity and batched evaluation.

Independent numbers: the same motion as a plain function, whose velocity System takes by
central differences; the motion's own derivative written by hand.
"""
import numpy as np
import pytest
from test_compiled_step import _chain_on_the_bed

import skmoor
from skmoor.solvers.dynamics import Scheme, integrate

OMEGA, AMPLITUDE = 0.6, 1.0  # rad/s, m


def along_z(z):
    out = np.zeros(np.shape(z) + (1, 3))
    out[..., 0, 2] = z
    return out


def heave(t):
    """A (1 - cos w t): starts at rest (no snap from a jump of the velocity)."""
    return along_z(AMPLITUDE * (1 - np.cos(OMEGA * np.asarray(t, float))))


def heave_rate(t, factor=1.0):
    return along_z(factor * AMPLITUDE * OMEGA * np.sin(OMEGA * np.asarray(t, float)))


def fairlead_tensions(motion, compiled=True):
    system, x0 = _chain_on_the_bed(motion)
    out = []
    for state in integrate(system, x0, np.zeros(system.n), 0.05, 3.0, compiled=compiled,
                           scheme=Scheme.generalized_alpha(0.8), tol=1e-10, report_every=1):
        out.append(np.linalg.norm(state.reactions[0][0]))
    return np.array(out)


@pytest.mark.parametrize("vectorized", [True, False])
def test_a_motion_with_its_velocity_moves_the_line_as_central_differences_do(vectorized):
    """A heaving fairlead as a Motion with its exact velocity (a batch of times per call
    when vectorized) gives the tension history of the same motion as a plain function,
    differentiated numerically by System; a velocity with a wrong factor does not (the
    drag, the bed's damping and the lines' BA see it), so the velocity is the one used.
    The fairlead's inertia in its reaction takes the acceleration from differences over
    the step, of the velocity or of the positions: they differ by O(dt^2), 3e-6 of the
    swing here."""
    plain = fairlead_tensions(lambda t: heave(t))
    exact = fairlead_tensions(skmoor.Motion(heave, heave_rate, vectorized=vectorized))
    swing = np.ptp(plain)
    assert swing > 5e3  # N: the heave does load the line
    assert np.abs(exact - plain).max() < 1e-5 * swing
    wrong = fairlead_tensions(skmoor.Motion(heave, lambda t: heave_rate(t, 2.0)))
    assert np.abs(wrong - plain).max() > 1e-3 * swing
    python = fairlead_tensions(skmoor.Motion(heave, heave_rate, vectorized=vectorized),
                               compiled=False)
    assert np.abs(python - exact).max() < 1e-8 * swing


def test_motion_checks_its_input():
    with pytest.raises(ValueError, match="Motion position"):
        skmoor.Motion(3.0)
    with pytest.raises(ValueError, match="Motion velocity"):
        skmoor.Motion(heave, velocity="fast")
    times = np.array([0.0, 0.5, 1.0])
    disp, rate = skmoor.Motion(heave).at_times(times)  # central differences
    assert disp.shape == rate.shape == (3, 1, 3)
    assert np.allclose(rate[:, 0, 2], AMPLITUDE * OMEGA * np.sin(OMEGA * times), atol=1e-7)
