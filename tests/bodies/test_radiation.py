"""Cummins' equation: the retardation kernel, the radiation memory, waves on the paper's box."""
import copy
import functools
from pathlib import Path

import numpy as np
import pytest

from skmoor.bodies.bem import Hydrodynamics
from skmoor.bodies.radiation import PotentialFlow, retardation_kernel

DATA = Path(__file__).parents[2] / "meshes" / "box_hull_bem.npz"  # by meshes/make_box_bem.py


@pytest.fixture(scope="module")
def box():
    return Hydrodynamics.load(DATA)


def test_kernel_of_a_triangle():
    """B a triangle of height b on [0, 2 W] (peak at W): its cosine transform is
    (2/pi) b (2 cos(W t) - 1 - cos(2 W t)) / (W t^2), and (2/pi) b W at t = 0."""
    W, b = 1.3, 2.0
    omega = np.array([0.0, W, 2 * W])
    B = np.zeros((3, 6, 6))
    B[1, 2, 2] = b
    t = np.array([0.0, 1e-5, 0.1, 1.0, 7.3, 40.0])
    K = retardation_kernel(omega, B, t)[:, 2, 2]
    exact = np.empty_like(t)
    exact[0] = 2 / np.pi * b * W
    exact[1:] = 2 / np.pi * b * (2 * np.cos(W * t[1:]) - 1 - np.cos(2 * W * t[1:])) / (W * t[1:] ** 2)
    np.testing.assert_allclose(K, exact, rtol=1e-6, atol=1e-9 * b * W)


def test_memory_of_heave_forced_at_one_frequency(box):
    """The box heaved z = Z sin(omega t) for longer than the kernel: the radiation force
    -A_inf zddot - int K(t - s) zdot(s) ds from the convolution over the committed
    steps against -A(omega) zddot - B(omega) zdot from Capytaine at that frequency
    (A(omega) is not used by the kernel: Kramers-Kronig and the tail are tested), over
    one period, within 1 % of the force amplitude (heave: the kernel's tail matters
    more in surge and pitch, see docs/waves_bodies.md)."""
    dt, Z = 0.05, 0.1
    term = PotentialFlow(box, memory=60.0)  # a commit at t = 0 starts a new history
    for dof in (2,):
        for omega in (0.5, 1.0, 2.0):
            A, B = box.coefficients(omega)
            period, warm = 2 * np.pi / omega, 80.0
            e = np.eye(6)[dof]
            errors, scale = [], Z * np.hypot(omega**2 * A[dof, dof], omega * B[dof, dof])
            for t in np.arange(0.0, warm + period, dt):
                v, acc = Z * omega * np.cos(omega * t), -Z * omega**2 * np.sin(omega * t)
                if t > warm:  # the step's own part implicit, as in a time step
                    mu, _ = term.memory(t, v * e)
                    force = -term.added_mass_inf[dof, dof] * acc - mu[dof]
                    errors.append(abs(force + A[dof, dof] * acc + B[dof, dof] * v))
                term.commit(t, Z * np.sin(omega * t) * e, v * e)
            assert max(errors) < 0.01 * scale, (dof, omega, max(errors) / scale)


@functools.lru_cache(maxsize=1)
def _paper_model():
    import skmoor

    return skmoor.build(skmoor.paper_case())


def test_waves_the_coefficients_do_not_cover_are_refused(box):
    import skmoor

    fast = skmoor.Sea(depth=100.0, waves=[skmoor.AiryWave(0.1, 1.5, 100.0)])  # 4.2 rad/s
    with pytest.raises(ValueError, match=r"sea\.waves\[0\].*outside the computed range"):
        PotentialFlow(box, fast)
    beam = skmoor.Sea(depth=100.0, waves=[skmoor.AiryWave(0.1, 8.0, 100.0, heading_deg=90.0)])
    with pytest.raises(ValueError, match=r"sea\.waves\[0\].*heading: 90"):
        PotentialFlow(box, beam)
    with pytest.raises(ValueError, match="added_mass_inf"):
        PotentialFlow(box, added_mass_inf="wamit")


def box_in_waves(box, omega, amplitude=0.05, periods=None, steps_per_period=80):
    """The paper's box on its four lines in a regular head wave of ``amplitude`` (m) at
    omega (rad/s), the paper's sine load off: the surge, heave and pitch amplitudes of the
    time-domain run (fitted at omega over its last 5 periods) and of the frequency-domain
    response of the same linearized equations, lines included (their inertia and Rayleigh
    damping; no water forces on the lines in the paper's case), and of the 6x6 one with
    the lines as a quasi-static stiffness: (time, full, 6x6), each (3,)."""
    import skmoor
    from skmoor.run.equilibrium import equilibrium, mooring_stiffness

    period = 2 * np.pi / omega
    model = copy.deepcopy(_paper_model())
    model.system.body_load = None
    sea = skmoor.Sea(depth=100.0, waves=[skmoor.AiryWave(2 * amplitude, period, 100.0)])
    term = model.add(PotentialFlow(box, sea, ramp=4 * period))
    eq = equilibrium(model)
    system = model.system
    _, K, Kv = system.residual(eq.x, layout="dense")
    C = eq.C.toarray() + (0.0 if Kv is None else Kv)
    body = slice(system.nf, system.nf + 6)
    A, B = box.coefficients(omega)
    F = amplitude * box.excitation_force(omega)[0]
    # (-w^2 (M + A) - i w B + C) X = F in exp(-i w t), M, C, K of the whole linearized network
    Z = -omega**2 * system.M.toarray() - 1j * omega * C + K
    Z[body, body] += -omega**2 * (A - term.added_mass_inf) - 1j * omega * B  # M has A_inf
    load = np.zeros(system.n, complex)
    load[body] = F
    full = np.abs(np.linalg.solve(Z, load)[body])
    rigid = system.bodies[0].mass_matrix()
    Z6 = (-omega**2 * (rigid + A) - 1j * omega * B + system.K_bodies[0]
          + mooring_stiffness(model, eq))
    quasi_static = np.abs(np.linalg.solve(Z6, F))
    dt = min(0.05, period / steps_per_period)
    periods = periods or max(24, int(np.ceil(120.0 / period)))
    results = skmoor.simulate(model, duration=periods * period, dt=dt, output_interval=dt,
                              progress=False, eq=eq)
    assert results.meta["stopped"] is None
    t, q = np.asarray(results.t), np.asarray(results.body)
    last = t >= t[-1] - 5 * period
    G = np.stack([np.ones(last.sum()), np.cos(omega * t[last]), np.sin(omega * t[last])], 1)
    c = np.linalg.lstsq(G, q[last], rcond=None)[0]
    dofs = [0, 2, 4]
    return np.hypot(c[1], c[2])[dofs], full[dofs], quasi_static[dofs]


def _check_box(box, omega, **run):
    # (the quasi-static 6x6 response, the third value, is for docs/waves_bodies.md: it
    # misses the heave at 1.6 rad/s by more than half, the lines' inertia matters here)
    time_domain, full, _ = box_in_waves(box, omega, **run)
    np.testing.assert_allclose(time_domain, full, rtol=0.02, err_msg=f"omega {omega} rad/s")


def test_box_in_regular_waves_paper_frequency(box):
    """The paper's box in small head waves at the paper's 1.6 rad/s: surge, heave and
    pitch amplitudes of the time-domain run (Cummins, in the implicit step with the
    lines) within 2 % of the frequency-domain response from the same coefficients."""
    _check_box(box, 1.6, periods=16)


@pytest.mark.slow
@pytest.mark.parametrize("omega", [0.3, 0.5, 0.8, 1.0, 1.2, 2.0])
def test_box_in_regular_waves_sweep(box, omega):
    """As above, from 0.3 to 2.0 rad/s."""
    _check_box(box, omega)
