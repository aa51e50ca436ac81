"""The paper's coupled case, skmoor against MoorDyn v2 side by side (a short run).

The set-up is benchmarks/paper_case.py's 'moordyn-damping' scenario, imported from there:
the paper's box on its four steel lines (11 elements / segments each), F_x = 1e5 sin(1.6 t)
N from static rest, the same explicit damping in both codes (MoorDyn's line damping
BA = -0.8, i.e. 80 % of a segment's critical axial damping, and one 6x6 body damping
matrix), no Rayleigh damping, no drag or added mass on the lines, EA times the
engineering strain. MoorDyn has no hydrostatic stiffness for bodies, so its lines end at
four 'Coupled' points and the body (skmoor's 6x6 mass + added mass, hydrostatic
stiffness, buoyancy - weight, load) is integrated here by velocity Verlet at a 5 ms
coupling step, as the benchmark does. What is compared is then the lines and their
coupling to the body: the line's dynamics, its pull at the fairleads and the moments of
those pulls about the body's reference point.

Unlike the benchmark, MoorDyn gets the catenary's own unstretched lengths (no tuning to
skmoor's tension): its chord chain hangs 0.34 % slacker (see
test_peers_moordyn.test_static_tension_with_the_same_length), which shows here as the
mean tension difference. It starts from its catenary initial state (TmaxIC = 0), which
is not the chain's equilibrium: it rings by ~6 kN (2 % of the range) at the start.

Measured over the 20 s (5 forcing periods, a free surge vibration at the first natural
period included), max |skmoor - MoorDyn| over MoorDyn's range:

    quantity                 11 segments   40 segments (not run here: MoorDyn 30 s)
    fairlead tensions (4)    3.1 %         1.25 %
    surge                    2.2 %         0.87 %
    pitch                    3.1 %         0.99 %
    heave                    4.8 %         2.4 %
    mean tension             0.34 %

The difference halves from 11 to 40 segments: it is the two discretizations of the line
(skmoor's FE elements on the exact elastic catenary, MoorDyn's lumped chain of chords),
not the time steps: skmoor at dt = 20 ms is within 0.06 % of its 2.5 ms run, MoorDyn at
dtM = 0.5 ms within 0.3 % of 0.1 ms with a 2 ms coupling step. The tolerances are the 11
segment numbers plus about 60 %: 5 % (tensions, pitch), 4 % (surge), 8 % (heave), 0.5 %
(mean tension). Fails on the lines' mass 1.5 or 2 times too large (tension 47 % / 38 %,
surge 40 % / 29 %), a wrong line weight (the case's density x 1.5: 85 %), the moments of
the fairlead pulls halved on one side (tried on the MoorDyn side's body: pitch 108 %,
tensions 35 %). Not on the lines' BA (3 x: no change) nor EA +10 % (the mooring's
stiffness is mostly geometric here: 2.6 %): those are held by the line-only tests
(test_peers_moordyn.py, test_free_points_moordyn.py). Wall time ~10 s (15 s loaded).
"""
import sys
from pathlib import Path

import numpy as np
import pytest

moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) is the "
                              "lumped-mass dynamic peer")

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import paper_case  # noqa: E402

import skmoor  # noqa: E402

DURATION = 20.0  # s, 5 forcing periods
DT_SKMOOR = 0.02  # s
DT_MOORDYN, COUPLING = 5e-4, 5e-3  # s: MoorDyn's dtM, the body's Verlet step
SAMPLE = 0.1  # s


def run_moordyn(scenario, workdir):
    """(t, fairlead tensions (nt, 4) N, body displacement (nt, 6) m / rad) of MoorDyn's
    lines with the body integrated here (benchmarks/paper_case.coupled_moordyn, as the
    benchmark runs it)."""
    model = scenario.model
    body = paper_case.CoupledBody(scenario)
    lengths = [cat.L for cat in model.catenaries]
    deck = paper_case.moordyn_deck(Path(workdir) / "paper.txt", model, body, lengths,
                                   DT_MOORDYN)
    md = moordyn.Create(str(deck))
    times, tensions, motion = [], [], []
    try:
        every = int(round(SAMPLE / COUPLING))
        steps = paper_case.coupled_moordyn(md, body, DURATION, COUPLING)
        for k, (t, forces, q) in enumerate(steps):
            if (k + 1) % every == 0:
                times.append(t)
                tensions.append(np.linalg.norm(forces, axis=1))
                motion.append(q.copy())
    finally:
        moordyn.Close(md)
    return np.array(times), np.array(tensions), np.array(motion)


@pytest.fixture(scope="module")
def side_by_side(tmp_path_factory):
    workdir = tmp_path_factory.mktemp("paper_moordyn")
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(workdir)  # MoorDyn may write files in the cwd
        scenario = paper_case.Scenario("moordyn-damping")
        results = skmoor.simulate(scenario.model, duration=DURATION, dt=DT_SKMOOR,
                                  output_interval=SAMPLE, progress=False, eq=scenario.eq)
        assert results.meta["stopped"] is None
        with paper_case.quiet():
            md = run_moordyn(scenario, workdir)
    return results, md


def difference(t, values, t_md, md):
    """max |values - MoorDyn| / MoorDyn's range (over every column), skmoor interpolated
    at MoorDyn's samples."""
    values = np.asarray(values).reshape(len(t), -1)
    md = np.asarray(md).reshape(len(t_md), -1)
    ours = np.column_stack([np.interp(t_md, t, values[:, k]) for k in range(values.shape[1])])
    return float(np.abs(ours - md).max() / np.ptp(md))


def test_fairlead_tensions_agree(side_by_side):
    """All four fairlead tension histories within 5 % of MoorDyn's tension range (about
    260 kN; measured 3.1 %), the mean tension within 0.5 % (measured 0.34 %: MoorDyn's
    chord chain is slacker), and the tensions do swing (range > 200 kN, the paper's
    ~2 x 126 kN)."""
    results, (t_md, T_md, _) = side_by_side
    assert np.ptp(T_md) > 2e5
    error = difference(results.t, results.fairlead_tension, t_md, T_md)
    assert error < 0.05, f"fairlead tensions: {error:.2%} of MoorDyn's range"
    keep = results.t >= t_md[0] - 1e-9
    mean_sk, mean_md = results.fairlead_tension[keep].mean(), T_md.mean()
    assert mean_sk == pytest.approx(mean_md, rel=5e-3)


@pytest.mark.parametrize("dof, tolerance", [("surge", 0.04), ("pitch", 0.05), ("heave", 0.08)])
def test_body_motion_agrees(side_by_side, dof, tolerance):
    """Surge (range ~1.3 m; measured 2.2 %), pitch (~0.06 rad; 3.1 %) and heave (~0.08 m;
    4.8 %) histories of the body within the module's tolerances of MoorDyn's range."""
    results, (t_md, _, q_md) = side_by_side
    i = skmoor.post.results.BODY_DOFS.index(dof)
    error = difference(results.t, results.bodies[:, 0, i], t_md, q_md[:, i])
    assert error < tolerance, f"{dof}: {error:.2%} of MoorDyn's range {np.ptp(q_md[:, i]):.3g}"
    if dof == "surge":
        assert np.ptp(q_md[:, i]) > 1.0
