"""skmoor stepped by a host through MoorDyn's interface (skmoor.moordyn), against MoorDyn.

The host is what hosts do: a floating body integrated in Python (symplectic Euler at the
coupling step dt = 0.05 s) whose fairlead is a deck's coupled point. Body mass 5e6 kg,
a heave spring of 1e6 N/m, a 10 s force of 2 MN in surge and in heave faded in over the
first period; the lines' force from Step enters less its static value. The same loop
runs on ``import moordyn`` (MoorDyn v2.7, RK2 at the deck's dtM = 1 ms) and on
``from skmoor import moordyn`` (implicit steps, 5 per coupling step: substeps=5).

Compared: the fairlead tension (GetLineFairTen). The static tensions differ by the two
discretizations of the line on its bed (MoorDyn's straight lumped-mass segments, skmoor's
finite elements): 1.0 % at 38 segments (tests/decks/host/buoy_chain.dat), 0.25 % at 170
(examples/decks/chain_600m.dat); at about 1 % of 2.4 MN that offset is 5 % of the
0.48 MN swing. So the swing is compared, T(t) - T(0) of each code: measured

    deck                         segments  run    max |diff| / MoorDyn's range
    buoy_chain (200 m of water)  38        20 s   0.47 %   (default suite)
    chain_600m, fairlead -10 m   170       60 s   0.15 %   (slow)

With one implicit step per coupling step (substeps=1) the swing differs by 4.4 % and
1.8 %: the coupling step is then skmoor's time step, too coarse for the chain's fast
tension response.

A coupled body's forces and moments (6 coupled DOFs) are MoorDyn's at a held pose.

Checkpoints: SaveState / LoadState in memory, to a file and as bytes bring a run back
so that it repeats to 1e-12 (exactly, here).
"""
from pathlib import Path

import numpy as np
import pytest

moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) is the "
                              "host's peer")

from skmoor import moordyn as skmoordyn  # noqa: E402

ROOT = Path(__file__).parents[2]
BUOY = ROOT / "tests" / "decks" / "host" / "buoy_chain.dat"
DT = 0.05  # s, the coupling step
START = np.array([0.0, 0.0, -10.0])  # the fairlead where the host holds it at rest, m


def host_loop(lib, md, duration, dt=DT, start=START, mass=5e6, k_heave=1e6,
              force=(2e6, 0.0, 2e6), period=10.0):
    """A floating body on the coupled point: (t, fairlead tension, position) each step."""
    x, v = np.array(start, float), np.zeros(3)
    lib.Init(md, x, v)
    line = lib.GetLine(md, 1)
    f0 = np.asarray(lib.GetPointForce(lib.GetPoint(md, 2)), float)
    t, times, tension, path = 0.0, [0.0], [lib.GetLineFairTen(line)], [x]
    for _ in range(int(round(duration / dt))):
        f = np.asarray(lib.Step(md, x, v, t, dt), float)
        ramp = min(t / period, 1.0)
        load = (f - f0 + ramp * np.asarray(force) * np.sin(2 * np.pi * t / period)
                - np.array([0.0, 0.0, k_heave]) * (x - start))
        v = v + dt * load / mass
        x = x + dt * v
        t += dt
        times.append(t)
        tension.append(lib.GetLineFairTen(line))
        path.append(x)
    return np.array(times), np.array(tension), np.array(path)


def here(deck):
    """The deck copied into the working folder: MoorDyn writes its outputs next to it."""
    copy = Path.cwd() / deck.name
    copy.write_text(deck.read_text())
    return copy


def side_by_side(deck, duration, substeps=5):
    md = moordyn.Create(str(here(deck)))
    try:
        _, T_md, x_md = host_loop(moordyn, md, duration)
    finally:
        moordyn.Close(md)
    sk = skmoordyn.Create(deck, substeps=substeps)
    t, T_sk, x_sk = host_loop(skmoordyn, sk, duration)
    skmoordyn.Close(sk)
    span = np.ptp(T_md)
    swing = np.max(np.abs((T_sk - T_sk[0]) - (T_md - T_md[0]))) / span
    return t, T_sk, T_md, swing, span, x_sk, x_md


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # MoorDyn may write next to the deck / in the cwd
    return tmp_path


def test_host_loop_against_moordyn(workdir):
    t, T_sk, T_md, swing, span, x_sk, x_md = side_by_side(BUOY, 20.0)
    assert T_sk[0] == pytest.approx(T_md[0], rel=0.015)  # statics: the discretizations
    assert span > 3e5  # a real swing (about 480 kN), not noise
    assert swing < 0.01, f"swing differs by {swing:.2%} of the {span / 1e3:.0f} kN range"
    assert np.max(np.abs(x_sk - x_md)) < 0.01  # the host's body: within 1 cm


@pytest.mark.slow
def test_host_loop_against_moordyn_long(workdir):
    deck = ROOT / "examples" / "decks" / "chain_600m.dat"
    t, T_sk, T_md, swing, span, _, _ = side_by_side(deck, 60.0)
    assert T_sk[0] == pytest.approx(T_md[0], rel=0.005)
    assert span > 1e6
    assert swing < 0.005, f"swing differs by {swing:.2%} of the {span / 1e3:.0f} kN range"


def test_interface_reads(workdir):
    sk = skmoordyn.Create(BUOY)
    assert skmoordyn.NCoupledDOF(sk) == 3 and skmoordyn.GetNumberLines(sk) == 1
    skmoordyn.Init(sk, START, np.zeros(3))
    line = skmoordyn.GetLine(sk, 1)
    n = skmoordyn.GetLineN(line)
    assert n == 38 and skmoordyn.GetLineNumberNodes(line) == 39
    np.testing.assert_allclose(skmoordyn.GetLineNodePos(line, 0), [700.0, 0.0, -200.0],
                               atol=1e-9)
    np.testing.assert_allclose(skmoordyn.GetLineNodePos(line, n), START, atol=1e-9)
    np.testing.assert_allclose(skmoordyn.GetPointPos(skmoordyn.GetPoint(sk, 2)), START,
                               atol=1e-9)
    force = skmoordyn.GetPointForce(skmoordyn.GetPoint(sk, 2))
    assert np.linalg.norm(force) == pytest.approx(skmoordyn.GetLineFairTen(line), rel=1e-12)
    assert skmoordyn.GetLineNodeTen(line, n) == skmoordyn.GetLineFairTen(line)
    f = skmoordyn.Step(sk, START + [0.1, 0.0, 0.0], [2.0, 0.0, 0.0], 0.0, DT)
    np.testing.assert_allclose(skmoordyn.GetLineNodePos(line, n), START + [0.2, 0.0, 0.0],
                               atol=1e-9)  # moved to x + xd dt over the step
    np.testing.assert_allclose(skmoordyn.GetPointVel(skmoordyn.GetPoint(sk, 2)),
                               [2.0, 0.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(f, skmoordyn.GetPointForce(skmoordyn.GetPoint(sk, 2)))
    with pytest.raises(ValueError, match="no line 2"):
        skmoordyn.GetLine(sk, 2)
    with pytest.raises(ValueError, match="expected 3 coupled DOFs"):
        skmoordyn.Step(sk, [0.0, 0.0], [0.0, 0.0], DT, DT)


def _steps(sk, t0, count, record):
    """count host steps of a prescribed wobble from t0: the forces of each."""
    out = []
    for k in range(count):
        t = t0 + k * DT
        x = START + np.array([2.0 * np.sin(0.7 * t), 0.0, 1.5 * np.sin(0.5 * t)])
        xd = np.array([1.4 * np.cos(0.7 * t), 0.0, 0.75 * np.cos(0.5 * t)])
        out.append(skmoordyn.Step(sk, x, xd, t, DT))
        if record is not None:
            record.append(skmoordyn.GetLineFairTen(skmoordyn.GetLine(sk, 1)))
    return np.array(out)


@pytest.mark.parametrize("how", ["memory", "file", "bytes"])
def test_checkpoint_repeats_the_run(workdir, how):
    sk = skmoordyn.Create(BUOY)
    skmoordyn.Init(sk, START, np.zeros(3))
    _steps(sk, 0.0, 40, None)
    if how == "memory":
        saved = skmoordyn.SaveState(sk)
    elif how == "file":
        skmoordyn.SaveState(sk, workdir / "state.bin")
    else:
        saved = skmoordyn.Serialize(sk)
    first = _steps(sk, 40 * DT, 60, None)
    if how == "memory":
        skmoordyn.LoadState(sk, saved)
    elif how == "file":
        fresh = skmoordyn.Create(BUOY)  # another instance of the deck, restored from the file
        skmoordyn.Init(fresh, START, np.zeros(3))
        skmoordyn.LoadState(fresh, workdir / "state.bin")
        sk = fresh
    else:
        skmoordyn.Deserialize(sk, saved)
    again = _steps(sk, 40 * DT, 60, None)
    scale = np.max(np.abs(first))
    assert np.max(np.abs(again - first)) <= 1e-12 * scale


def test_coupled_body_forces_against_moordyn(workdir):
    """A coupled body (6 DOFs: the semisubmersible's three chains on it) held at a pose
    surged 5 m, pitched 0.05 rad and yawed 0.02 rad: the forces and moments Step returns
    after 1 s at rest are MoorDyn's within 1 % of the largest force and moment (measured:
    0.1 % of the 6.1 MN vertical force, 0.3 % of the 19.5 MN m pitch moment)."""
    deck = ROOT / "tests" / "decks" / "host" / "semi_body.dat"
    pose = np.array([5.0, 0.0, 0.0, 0.0, 0.05, 0.02])
    out = []
    for lib, md in ((moordyn, moordyn.Create(str(here(deck)))),
                    (skmoordyn, skmoordyn.Create(deck))):
        assert lib.NCoupledDOF(md) == 6
        lib.Init(md, pose, np.zeros(6))
        for k in range(20):
            f = np.asarray(lib.Step(md, pose, np.zeros(6), k * DT, DT), float)
        lib.Close(md)
        out.append(f)
    md_f, sk_f = out
    force, moment = np.max(np.abs(md_f[:3])), np.max(np.abs(md_f[3:]))
    assert force > 5e6 and moment > 1e7  # the chains' weight and the pitched pose's moment
    assert np.max(np.abs(sk_f[:3] - md_f[:3])) < 0.01 * force
    assert np.max(np.abs(sk_f[3:] - md_f[3:])) < 0.01 * moment


def test_points_are_numbered_as_moordyn_numbers_them(tmp_path, monkeypatch):
    """A deck with a rod: MoorDyn's points are the deck's POINTS (the rod's ends are not
    among them), so GetPoint(md, 2) is POINTS ID 2 in both libraries."""
    monkeypatch.chdir(tmp_path)
    deck = ROOT / "tests" / "decks" / "rods" / "buoy_on_a_rod.dat"
    (tmp_path / deck.name).write_text(deck.read_text())
    found = {}
    for lib in (moordyn, skmoordyn):
        md = lib.Create(str(tmp_path / deck.name))
        try:
            lib.Init(md, [], [])
            found[lib] = (lib.GetNumberPoints(md),
                          [np.asarray(lib.GetPointPos(lib.GetPoint(md, k)), float)
                           for k in (1, 2)])
        finally:
            lib.Close(md)
    assert found[skmoordyn][0] == found[moordyn][0] == 2
    for ours, theirs, given in zip(found[skmoordyn][1], found[moordyn][1],
                                   ([-2.0, 0.0, -50.0], [2.0, 0.0, -50.0])):
        np.testing.assert_allclose(theirs, given, atol=1e-9)
        np.testing.assert_allclose(ours, given, atol=1e-9)


def test_a_point_without_lines_moves_with_its_body(tmp_path, monkeypatch):
    """A point on the coupled body that no line holds (a sensor, a light): GetPointPos
    gives where the body carries it, as MoorDyn does, at a pose surged, heaved and turned
    (0.2, 0.3, 0.5 rad: the body-frame position, or the deck's, is metres off)."""
    monkeypatch.chdir(tmp_path)
    text = (ROOT / "tests" / "decks" / "host" / "semi_body.dat").read_text()
    row = "6   Fixed       418.8    -725.383 -200.0  0     0       0    0\n"
    assert row in text
    deck = tmp_path / "semi_sensor.dat"
    deck.write_text(text.replace(row, row + "7   Body1       10.0     -20.0    5.0     0     0"
                                 "       0    0\n"))
    pose = np.array([3.0, -2.0, 1.0, 0.2, 0.3, 0.5])
    found = {}
    for lib in (moordyn, skmoordyn):
        md = lib.Create(str(deck))
        try:
            lib.Init(md, np.zeros(6), np.zeros(6))
            for k in range(10):  # to the pose over 0.5 s, at its velocity
                lib.Step(md, pose * k / 10, pose / (10 * DT), k * DT, DT)
            found[lib] = np.asarray(lib.GetPointPos(lib.GetPoint(md, 7)), float)
        finally:
            lib.Close(md)
    np.testing.assert_allclose(found[skmoordyn], found[moordyn], atol=1e-9)
    assert np.linalg.norm(found[moordyn] - [10.0, -20.0, 5.0]) > 5.0
