"""Chain decks heaved at the fairlead: skmoor and MoorDyn v2 side by side on the same deck.

The decks (examples/decks/chain_*.dat) are the quasi-static chain set that MoorDyn
validates against OrcaFlex: a 0.252 m, 390 kg/m chain (EA 1.674e9 N, Cd 1.37, Ca 1,
CdAx 0.64, CaAx 0, internal damping 100 % of critical per 10 m segment) from an anchor
on the bed to a fairlead at the surface, MoorDyn's bottom springs kBot 1e5 Pa/m, cBot
1e4 Pa s/m. Both codes read the same file (written back by skmoor's write_deck) and get
the same fairlead motion: heave A sin(2 pi t / 10 s), faded in over the first period.
MoorDyn (RK2 at the deck's dtM = 1 ms) is stepped every 10 ms with the motion at the
start of each step and its velocity; skmoor (Newmark) uses its own time step.

Compared: the fairlead tension (the line's pull on the fairlead, no end-node inertia in
either code) after the transient (t >= 20 s), MoorDyn's history interpolated at skmoor's
samples: max |difference| within 5 % of MoorDyn's tension range (max - min). Measured:

    depth  heave  dt (skmoor)  range (MoorDyn)  max |diff| / range
    50 m   2 m    0.05 s        217 kN           2.7 %   (default suite, 30 s record)
    50 m   5 m    0.025 s      1376 kN           2.8 %   (4.3 % at dt = 0.05 s)
    200 m  2 m    0.05 s        495 kN           1.0 %
    200 m  5 m    0.05 s       2345 kN           0.9 %
    600 m  2 m    0.05 s       1649 kN           0.3 %
    600 m  5 m    0.05 s       5746 kN           0.2 %

The static fairlead tensions agree within 0.15 %. The 5 m heave in 50 m of water nearly
slackens the chain: the trough carries a fast (0.3 s) axial ringing that both codes
show and that skmoor follows better at dt = 0.025 s. skmoor's bed damping is faded in
over the first 13 mm of penetration (the sea bed's default `damping_onset`, a tenth of w / k): MoorDyn's jump there
leaves the implicit step without a solution (Newton cycles; the 50 m / 2 m run stops
at t = 24.6 s without it).
"""
from pathlib import Path

import numpy as np
import pytest

moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) is the "
                              "lumped-mass dynamic peer")

from skmoor import build, simulate  # noqa: E402
from skmoor.io.deck import read_deck, write_deck
from skmoor.model.from_deck import heave_motion

DECKS = Path(__file__).parents[2] / "examples" / "decks"
PERIOD = 10.0  # s
DT_COUPLING = 0.01  # s, MoorDyn Step() calls; it substeps at the deck's dtM
SETTLED = 2 * PERIOD  # s: the fade-in and the start-up transient are over


def run_moordyn(path, motion, velocity, duration):
    """MoorDyn's fairlead tension history (s, N) for coupled-point motion(t)."""
    md = moordyn.Create(str(path))
    try:
        assert moordyn.Init(md, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]) == 0
        t = [0.0]
        tension = [np.linalg.norm(moordyn.GetPointForce(moordyn.GetPoint(md, 2)))]
        for k in range(int(round(duration / DT_COUPLING))):
            tk = k * DT_COUPLING
            force = moordyn.Step(md, list(motion(tk)), list(velocity(tk)), tk, DT_COUPLING)
            t.append(tk + DT_COUPLING)
            tension.append(np.linalg.norm(force))
    finally:
        moordyn.Close(md)
    return np.array(t), np.array(tension)


def side_by_side(depth, amplitude, duration, dt, workdir):
    """(skmoor results, MoorDyn t, MoorDyn tension, error) for one deck and heave."""
    deck = read_deck(DECKS / f"chain_{depth}m.dat")
    path = write_deck(deck, workdir / "chain.dat")
    motion, velocity = heave_motion(deck, amplitude, PERIOD)
    results = simulate(build(path, motion=motion), duration=duration, dt=dt,
                       output_interval=dt, progress=False)
    assert results.meta["stopped"] is None, results.meta["stopped"]
    t_md, T_md = run_moordyn(path, motion, velocity, duration)
    after = results.t >= SETTLED - 1e-9
    T_sk = results.fairlead_tension[after, 0]
    T_md_at = np.interp(results.t[after], t_md, T_md)
    span = np.ptp(T_md[t_md >= SETTLED - 1e-9])
    error = np.max(np.abs(T_sk - T_md_at)) / span
    return results, t_md, T_md, error, span


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # MoorDyn may write next to the deck / in the cwd
    return tmp_path


def test_chain_50m_heave_2m(workdir):
    """Default suite: 50 m of water, 2 m heave, 30 s (one settled period)."""
    results, _t_md, T_md, error, span = side_by_side("50", 2.0, 30.0, 0.05, workdir)
    assert results.fairlead_tension[0, 0] == pytest.approx(T_md[0], rel=5e-3)  # statics
    assert span > 1e5  # a real swing (about 200 kN), not noise
    assert error < 0.05, f"max |skmoor - MoorDyn| = {error:.2%} of the {span / 1e3:.0f} kN range"


@pytest.mark.slow
@pytest.mark.parametrize("depth, amplitude, dt", [
    ("50", 5.0, 0.025), ("200", 2.0, 0.05), ("200", 5.0, 0.05), ("600", 2.0, 0.05),
    ("600", 5.0, 0.05)])
def test_chain_heave(depth, amplitude, dt, workdir):
    """The other cases, 60 s each (four settled periods)."""
    results, _t_md, T_md, error, span = side_by_side(depth, amplitude, 60.0, dt, workdir)
    assert results.fairlead_tension[0, 0] == pytest.approx(T_md[0], rel=5e-3)
    assert error < 0.05, f"max |skmoor - MoorDyn| = {error:.2%} of the {span / 1e3:.0f} kN range"
