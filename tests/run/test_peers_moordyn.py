"""skmoor against MoorDyn v2 (explicit lumped mass), run side by side on one line.

The line is C1 of the paper's case (anchor, fairlead, unstretched length, EA, mass and
diameter from ``build(paper_case())``), hanging free of the sea bed. Its fairlead is a
MoorDyn 'Coupled' point, an skmoor 'prescribed' fairlead, driven along x by
0.05 sin(1.6 t) m from static rest; the fairlead tension (the line's pull on the
fairlead: the last segment's tension plus the fairlead node's half-segment weight, no
inertia) is compared over the run.

Same physics on both sides: no drag, no added mass, no bending, tension = EA times the
engineering strain ('engineering' strain law in skmoor), lumped mass, and the same small
axial damping: skmoor's stiffness-proportional Rayleigh damping C = BETA K (K the static
tangent, dominated by EA) against MoorDyn's internal damping BA = BETA EA (N s).
MoorDyn's RK2 at 0.5 ms on 11 segments blows up with BA = 0 or 1e4 N s and runs with
5e4 N s; BA = 1.57e5 N s (BETA = 1e-4 s) gives the line's first modes damping ratios of
1e-4 to 3e-4, so the free vibration started at t = 0 does not die out: the comparison
covers the whole history, and the amplitude over the last three forcing periods.

Same static state: MoorDyn's segments are chords of the catenary, so with the
catenary's own L its chain hangs slacker than skmoor's line (whose reference tension is
the catenary's): by 0.34 % in tension at 11 segments, 0.03 % at 40. MoorDyn is given the
unstretched length whose discrete chain has skmoor's static fairlead tension (a change
of 6e-6 L at 11 segments, 5e-7 L at 40), and its initial-condition solver settles the
line (TmaxIC = 100 s).

Discretization: the comparison is made at 40 segments, and again at the paper's 11
(test_tension_at_paper_segments). The cable terms are integrated at element mid-points,
which removed the membrane locking that once made skmoor's in-plane stiffness 6 % too
high at 11 elements (see test_peers_moorpy.py).
"""
import time

import numpy as np
import pytest

moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) is the "
                              "lumped-mass dynamic peer")

from peers import amplitude, chain_fairlead_force, chain_length_for, moordyn_deck  # noqa: E402

from skmoor.coupling.system import System
from skmoor.io.case import paper_case
from skmoor.lines.line import Line, LineSet
from skmoor.model.from_case import line_type
from skmoor.model.model import build
from skmoor.solvers.dynamics import Scheme, integrate
from skmoor.solvers.statics import solve_static

AMPLITUDE, OMEGA = 0.05, 1.6  # fairlead motion along x, m and rad/s
DURATION = 30.0  # s
PERIOD = 2 * np.pi / OMEGA
BETA = 1e-4  # stiffness-proportional damping, s (BA = BETA * EA)
DT_SKMOOR = 0.02  # s, Newmark (average acceleration)
DT_COUPLING = 0.01  # s, MoorDyn Step() calls; it substeps at dtM
DT_MOORDYN = {11: 5e-4, 40: 1.2e-4}  # s, RK2, stable for the segment length


def fairlead_motion(t):
    return np.array([AMPLITUDE * np.sin(OMEGA * t), 0.0, 0.0])


def fairlead_velocity(t):
    return np.array([AMPLITUDE * OMEGA * np.cos(OMEGA * t), 0.0, 0.0])


def run_skmoor(cat, lt, n):
    """Static state, then the driven run; fairlead tension history (N)."""
    system = System(LineSet([Line.from_catenary(cat, lt, n)], law="engineering"),
                    fairleads="prescribed", motion=lambda t: fairlead_motion(t)[None, :])
    x0 = solve_static(system).x
    _, K, _ = system.residual(x0)
    t, tension = [], []
    for state in integrate(system, x0, np.zeros(system.n), DT_SKMOOR, DURATION,
                           C=BETA * K, scheme=Scheme.newmark()):
        fair, _ = system.reactions(state.x, state.v, state.t)
        t.append(state.t)
        tension.append(np.linalg.norm(fair[0]))
    return np.array(t), np.array(tension)


def line_deck(path, cat, lt, n, length):
    """MoorDyn's deck of the line (catenary cat's ends, line type lt, unstretched length
    m, n segments, BA = BETA EA, MoorDyn's step for n segments, 100 m of water)."""
    return moordyn_deck(path, anchor=cat.anchor, fairlead=cat.fairlead, line_type=lt,
                        length=length, n_segments=n, BA=BETA * lt.EA, dt=DT_MOORDYN[n],
                        depth=100.0, rho=lt.rho_water, g=lt.g)


def run_moordyn(cat, lt, n, length, workdir):
    """MoorDyn's static state (fairlead force, N) and the driven run's history."""
    deck = line_deck(workdir / "line.txt", cat, lt, n, length)
    md = moordyn.Create(str(deck))
    try:
        assert moordyn.Init(md, list(cat.fairlead), [0.0, 0.0, 0.0]) == 0
        static = float(np.linalg.norm(moordyn.GetPointForce(moordyn.GetPoint(md, 2))))
        t, tension = [0.0], [static]
        for k in range(int(round(DURATION / DT_COUPLING))):
            tk = k * DT_COUPLING
            force = moordyn.Step(md, list(cat.fairlead + fairlead_motion(tk)),
                                 list(fairlead_velocity(tk)), tk, DT_COUPLING)
            t.append(tk + DT_COUPLING)
            tension.append(np.linalg.norm(force))
    finally:
        moordyn.Close(md)
    return static, np.array(t), np.array(tension)


def side_by_side(n, workdir):
    case = paper_case()
    cat, lt = build(case).catenaries[0], line_type(case, "steel")
    started = time.perf_counter()
    t_sk, T_sk = run_skmoor(cat, lt, n)
    wall_sk = time.perf_counter() - started
    length = chain_length_for(cat, n, T_sk[0])
    started = time.perf_counter()
    static_md, t_md, T_md = run_moordyn(cat, lt, n, length, workdir)
    wall_md = time.perf_counter() - started
    return dict(cat=cat, n=n, length=length, t_sk=t_sk, T_sk=T_sk, t_md=t_md, T_md=T_md,
                static_md=static_md, chain=chain_fairlead_force(cat, n, length),
                wall_sk=wall_sk, wall_md=wall_md)


def compare(run, periods):
    """(amplitude error, RMS difference / amplitude) over the last ``periods`` periods;
    MoorDyn's history is interpolated on skmoor's time steps."""
    t0 = DURATION - periods * PERIOD
    a_md = amplitude(run["t_md"], run["T_md"], t0)
    a_sk = amplitude(run["t_sk"], run["T_sk"], t0)
    window = run["t_sk"] >= t0 - 1e-9
    diff = run["T_sk"][window] - np.interp(run["t_sk"][window], run["t_md"], run["T_md"])
    return a_sk / a_md - 1, np.sqrt(np.mean(diff**2)) / a_md


@pytest.fixture(scope="module")
def run40(tmp_path_factory, monkeypatch_module):
    workdir = tmp_path_factory.mktemp("moordyn40")
    monkeypatch_module.chdir(workdir)  # MoorDyn writes its .out file in the cwd
    return side_by_side(40, workdir)


@pytest.fixture(scope="module")
def monkeypatch_module():
    with pytest.MonkeyPatch.context() as mp:
        yield mp


def test_same_static_state(run40):
    """With the length tuned (chain_length_for), MoorDyn's settled line pulls on the
    fairlead as skmoor's static FE line (and as the lumped-chain statics of peers.py
    predict) within 1e-4 (measured ~2e-5). This checks the set-up of the dynamic
    comparison (both start from the same state), not skmoor's statics: the tuning would
    absorb an error in them. test_static_tension_with_the_same_length does that."""
    static_sk = run40["T_sk"][0]
    assert run40["static_md"] == pytest.approx(static_sk, rel=1e-4)
    assert run40["chain"] == pytest.approx(static_sk, rel=1e-9)
    assert static_sk == pytest.approx(run40["cat"].T_fairlead, rel=1e-6)
    assert run40["length"] == pytest.approx(run40["cat"].L, rel=1e-5)


def moordyn_static_force(cat, lt, n, length, workdir):
    """|force| (N) of MoorDyn's line, settled by its initial-condition solve, on the
    fairlead, for an unstretched length ``length`` on n segments."""
    deck = line_deck(workdir / "static.txt", cat, lt, n, length)
    md = moordyn.Create(str(deck))
    try:
        assert moordyn.Init(md, list(cat.fairlead), [0.0, 0.0, 0.0]) == 0
        return float(np.linalg.norm(moordyn.GetPointForce(moordyn.GetPoint(md, 2))))
    finally:
        moordyn.Close(md)


def test_static_tension_with_the_same_length(tmp_path, monkeypatch):
    """Both codes given the same line (the paper's C1, unstretched length L = 129.438 m
    from the catenary, no tuning), 11 segments / elements: MoorDyn's settled fairlead
    force is below skmoor's static FE tension by the chords' slack, -0.34 %, which
    MoorDyn's discrete-chain statics (peers.lumped_chain, from the catenary's w and EA
    alone) predict: agreement with that prediction within 1e-4 of the tension (measured
    1e-7), and within 0.5 % outright. MoorDyn computes the line's weight from the deck's
    mass, diameter and rho itself, so a wrong submerged weight, EA or length on
    skmoor's side fails (the steel's buoyancy alone is 13 % of its weight; a 1e-3 error
    in L moves the tension by ~10 %). At 40 segments the chord effect is -0.03 %, but
    MoorDyn's initial-condition solve then takes 30 s."""
    monkeypatch.chdir(tmp_path)
    n = 11
    case = paper_case()
    cat, lt = build(case).catenaries[0], line_type(case, "steel")
    system = System(LineSet([Line.from_catenary(cat, lt, n)], law="engineering"),
                    fairleads="prescribed", motion=lambda t: fairlead_motion(0.0)[None, :])
    x0 = solve_static(system).x
    fair, _ = system.reactions(x0, np.zeros(system.n), 0.0)
    static_sk = float(np.linalg.norm(fair[0]))
    static_md = moordyn_static_force(cat, lt, n, cat.L, tmp_path)
    chord = chain_fairlead_force(cat, n) / static_sk - 1  # the lumped chain's slack
    assert -0.004 < chord < -0.003
    assert static_md / static_sk - 1 == pytest.approx(chord, abs=1e-4)
    assert static_md == pytest.approx(static_sk, rel=5e-3)


def test_tension_amplitude_after_transient(run40):
    """Fairlead tension amplitude over the last 2 and 3 forcing periods within 3 %
    (measured: +0.1 % and -0.4 %; the amplitude is about 113 kN, the free vibration
    started at t = 0 included)."""
    for periods in (3, 2):
        error, _ = compare(run40, periods)
        assert abs(error) < 0.03, f"last {periods} periods: skmoor {error:+.2%} from MoorDyn"


def test_tension_history(run40):
    """The whole history agrees, not only its extremes: RMS difference over the last
    3 periods below 10 % of the amplitude (measured ~3 %), and the mean tension within
    0.1 %."""
    _, rms = compare(run40, 3)
    assert rms < 0.10
    t0 = DURATION - 3 * PERIOD
    mean_sk = run40["T_sk"][run40["t_sk"] >= t0].mean()
    mean_md = run40["T_md"][run40["t_md"] >= t0].mean()
    assert mean_sk == pytest.approx(mean_md, rel=1e-3)


def test_tension_at_paper_segments(tmp_path, monkeypatch):
    """The same comparison at the paper's 11 elements / segments."""
    monkeypatch.chdir(tmp_path)
    run = side_by_side(11, tmp_path)
    assert run["static_md"] == pytest.approx(run["T_sk"][0], rel=1e-4)
    for periods in (3, 2):
        error, rms = compare(run, periods)
        assert abs(error) < 0.03 and rms < 0.15, (periods, error, rms)
