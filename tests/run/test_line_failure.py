"""Line failures (skmoor.run.failures; MoorDyn v2's FAILURE section, [[failures]] in a case).

The transient is checked side by side with MoorDyn on tests/decks/free_points/hanging.dat
(two chains from two vessels joined at a clump): line 1 is released from vessel 1 at
t = 1 s, in skmoor by the deck's FAILURE entry, in MoorDyn by its ``BreakLine`` between
two Step() calls (MoorDyn 2.7 reads FAILURE but fires an entry at its first step, whatever
its FailTime, and has no tension trigger). The clump and both chains then swing down
under vessel 2. MoorDyn's end-segment tension is compared with skmoor's end-element
tension (see test_free_points_moordyn.py for why), as magnitudes.

    compared (1 - 20 s)                                  measured at dt 2 ms
    line 2 at vessel 2, history                          1.4 % of MoorDyn's range
    line 2 at vessel 2, peak in the release's stress wave 0.1 %
    line 2 at vessel 2 and at the clump, peak             0.04 %, 0.09 %
    line 1 at its released end                           < 1.5 kN (25 kN before)
"""
import json
import re
from pathlib import Path

import numpy as np
import pytest

import skmoor
from skmoor import cli
from skmoor.coupling.network import LineFailure
from skmoor.io.deck import read_deck, write_deck

DECKS = Path(__file__).parents[1] / "decks"
HANGING = DECKS / "free_points" / "hanging.dat"
RELEASE = 1.0  # s
FAILURE = ("---------------------- FAILURE ----\n"
           "FailureID  Point  Line(s)  FailTime  FailTen\n"
           "()         ()     (,)      (s)       (N)\n{rows}\n"
           "---------------------- OPTIONS")


def deck_with(tmp_path, rows, name="hanging_fail.dat"):
    text = HANGING.read_text().replace("---------------------- OPTIONS",
                                       FAILURE.format(rows=rows), 1)
    path = tmp_path / name
    path.write_text(text)
    return path


def end_element_tensions(results):
    """(A, B): |tension| of each line's first and last element (nt, nlines), N."""
    cells = [np.flatnonzero(results.line_of_cell == j) for j in range(len(results.line_names))]
    T = np.abs(results.tension)
    return T[:, [c[0] for c in cells]], T[:, [c[-1] for c in cells]]


def moordyn_release(path, duration, coupling=0.01):
    """MoorDyn on ``path`` (no FAILURE section), line 1 broken off point 1 at RELEASE:
    (t, TA, TB) end-segment tensions (nt, nlines), N."""
    moordyn = pytest.importorskip("moordyn")
    md = moordyn.Create(str(path))
    vessels = [-40.0, 0.0, -5.0, 40.0, 0.0, -5.0]
    try:
        assert moordyn.Init(md, vessels, [0.0] * 6) == 0
        lines = [moordyn.GetLine(md, i + 1) for i in range(2)]
        ends = [moordyn.GetLineN(line) for line in lines]
        t, TA, TB = [], [], []
        for k in range(int(round(duration / coupling))):
            tk = k * coupling
            if abs(tk - RELEASE) < 1e-9:
                moordyn.BreakLine(md, moordyn.GetPoint(md, 1), lines[0])
            moordyn.Step(md, vessels, [0.0] * 6, tk, coupling)
            t.append(tk + coupling)
            TA.append([np.linalg.norm(moordyn.GetLineNodeTen(line, 0)) for line in lines])
            TB.append([np.linalg.norm(moordyn.GetLineNodeTen(line, n))
                       for line, n in zip(lines, ends)])
    finally:
        moordyn.Close(md)
    return np.array(t), np.array(TA), np.array(TB)


def test_release_transient_against_moordyn(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    duration = 20.0
    md_deck = tmp_path / "hanging.dat"
    md_deck.write_text(HANGING.read_text())
    t_md, TA_md, TB_md = moordyn_release(md_deck, duration)
    model = skmoor.build(deck_with(tmp_path, f"1  1  1  {RELEASE}  0"))
    results = skmoor.simulate(model, duration=duration, dt=0.002, output_interval=0.01,
                              progress=False)
    assert results.meta["stopped"] is None
    (event,) = results.meta["line_failures"]
    assert event["point"] == "point1" and event["lines"] == ["line1"]
    assert event["trigger"] == "time" and event["time"] == pytest.approx(RELEASE)
    TA, TB = end_element_tensions(results)
    after = results.t >= RELEASE
    md_after = t_md >= RELEASE
    top = np.interp(results.t[after], t_md, TA_md[:, 1])
    span = np.ptp(TA_md[md_after, 1])
    assert np.max(np.abs(TA[after, 1] - top)) < 0.02 * span
    wave, md_wave = after & (results.t <= 3.0), md_after & (t_md <= 3.0)
    assert TA[wave, 1].max() == pytest.approx(TA_md[md_wave, 1].max(), rel=0.02)
    assert TA[after, 1].max() == pytest.approx(TA_md[md_after, 1].max(), rel=0.02)
    assert TB[after, 1].max() == pytest.approx(TB_md[md_after, 1].max(), rel=0.02)
    # before: the intact state; after: line 1's released end carries (almost) nothing
    assert TA[results.t < RELEASE, 0].min() > 24e3
    assert results.anchor_tension[results.t >= RELEASE + 0.5, 0].max() < 1.5e3
    # the released end moves off vessel 1 (its first node is the line's end node)
    first = np.flatnonzero(results.line_of_cell == 0)[0]
    node = results.cells[first, 0]
    drop = results.displacement[-1, node]
    assert drop[2] < -5.0 and np.allclose(results.displacement[0, node], 0.0, atol=1e-9)


def test_tension_trigger_fires_where_the_tension_crosses(tmp_path):
    """A second failure at vessel 2 triggered by line 2's tension there (its end A):
    it fires at the first step where the run without it crosses the threshold."""
    threshold = 30e3  # N: line 2's top tension crosses it as the chains swing down
    single = skmoor.simulate(skmoor.build(deck_with(tmp_path, f"1  1  1  {RELEASE}  0")),
                             duration=15.0, dt=0.005, output_interval=0.005, progress=False)
    crossed = single.t[np.argmax(single.anchor_tension[:, 1] >= threshold)]
    assert 5.0 < crossed < 15.0
    both = skmoor.simulate(skmoor.build(deck_with(
        tmp_path, f"1  1  1  {RELEASE}  0\n2  2  2  0  {threshold}", "two.dat")),
        duration=15.0, dt=0.005, output_interval=0.005, progress=False)
    first, second = both.meta["line_failures"]
    assert first["trigger"] == "time" and second["trigger"] == "tension"
    assert second["point"] == "point2" and second["lines"] == ["line2"]
    assert second["time"] == pytest.approx(crossed, abs=1e-9)
    assert second["tension"] >= threshold
    k = np.searchsorted(both.t, crossed)
    np.testing.assert_allclose(both.anchor_tension[:k, 1], single.anchor_tension[:k, 1])
    assert both.anchor_tension[k + 20:, 1].max() < 2e3  # let go: the chains fall free
    # the clump's velocity (line 2's end node) goes on through the release: no jump
    clump = both.cells[np.flatnonzero(both.line_of_cell == 1)[-1], 1]
    assert np.linalg.norm(both.velocity[k, clump]) > 1.0
    assert np.linalg.norm(both.velocity[k + 1, clump] - both.velocity[k, clump]) < 0.02


def test_deck_failure_section_read_written_and_refused(tmp_path):
    deck = read_deck(deck_with(tmp_path, "1  1  1  12  0"))
    (failure,) = deck.failures
    assert (failure.point, failure.lines, failure.time, failure.tension) == (1, (1,), 12.0, 0.0)
    again = read_deck(write_deck(deck, tmp_path / "again.dat"))
    assert again.failures == deck.failures
    network = skmoor.build(tmp_path / "again.dat").network
    assert network.failures == [LineFailure("point1", ("line1",), 12.0, None)]
    for row, what in (("1  1  3  12  0", "Line(s): '3' is not a line number"),
                      ("1  7  1  12  0", "Point: point 7 is not in POINTS"),
                      ("1  1  1  0  0", "FailTime, FailTen: both 0"),
                      ("1  1  1  -1  0", "FailTime: must be >= 0")):
        with pytest.raises(ValueError, match=r"hanging_fail\.dat line \d+: FAILURE " + re.escape(what)):
            read_deck(deck_with(tmp_path, row))
    with pytest.raises(ValueError, match="line 'line2' does not end at point1"):
        skmoor.build(deck_with(tmp_path, "1  1  2  12  0"))
    with pytest.raises(ValueError, match="every line of the free point"):
        skmoor.build(deck_with(tmp_path, "1  3  1,2  12  0"))


def test_case_file_failures_and_the_summary(tmp_path, capsys):
    """[[failures]] in a case file; the event in summary.json and in the printed table."""
    text = (Path(__file__).resolve().parents[2] / "examples" / "network_buoy.toml").read_text()
    lines = re.findall(r'(?m)^\[\[lines\]\]\s*\nname = "([^"]+)"\s*\ntype = "[^"]+"\s*\n'
                       r'a = "([^"]+)"\s*\nb = "([^"]+)"', text)
    name, a, _b = lines[0]
    case = tmp_path / "failing.toml"
    case.write_text(text + f'\n[[failures]]\npoint = "{a}"\nlines = ["{name}"]\ntime = 0.5\n')
    out = tmp_path / "out"
    assert cli.main(["run", str(case), "--out", str(out), "--quiet", "--no-export",
                     "--no-animation", "--duration", "1"]) == 0
    said = capsys.readouterr().out
    assert f"line failure: {name} released from {a} at t = 0.5 s (time" in said
    info = json.loads((out / "summary.json").read_text())
    assert info["line_failures"][0]["time"] == pytest.approx(0.5)
    bad = tmp_path / "bad.toml"
    bad.write_text(text + '\n[[failures]]\npoint = "nowhere"\nlines = ["x"]\ntime = 0.5\n')
    assert cli.main(["run", str(bad), "--out", str(tmp_path / "o2"), "--quiet"]) == 2
    assert "failures[0].point" in capsys.readouterr().err


def test_what_a_failure_does_not_run_with_is_refused_up_front(tmp_path):
    """Checkpoints and terms of one's own cannot follow a release yet: refused before the
    run, naming why (not a crash at the failure)."""
    path = deck_with(tmp_path, f"1  1  1  {RELEASE}  0")
    with pytest.raises(ValueError, match="line failures and checkpoints"):
        skmoor.simulate(skmoor.build(path), duration=2.0, dt=0.01, progress=False,
                        out=tmp_path / "o", checkpoint_every=1.0)
    model = skmoor.build(path)
    model.add(skmoor.PointLoad(lambda x, v, t: 0.0 * x, point="point3"))
    with pytest.raises(ValueError, match="terms of your own"):
        skmoor.simulate(model, duration=2.0, dt=0.01, progress=False)


# the chains as MoorDyn's viscoelastic rope: EA_s|EA_d (N), BA|BA_D (N s), a creep time
# (BA + BA_D) / (EA_1 + EA_d) of 1 s
VISCOELASTIC = "chain     0.1    40.65    5.0e8|1.5e9   2.25e9|6e5 "
EA_S, EA_D, CREEP, DYNAMIC = 5.0e8, 1.5e9, 2.25e9, 6e5
EA_1 = EA_D * EA_S / (EA_D - EA_S)


def creep_rate(strain, rate, state, reference):
    z, = state
    return ((EA_D * strain - (EA_1 + EA_D) * z + DYNAMIC * rate) / (CREEP + DYNAMIC),)


def creep_tension(strain, rate, state, reference):
    z, = state
    return EA_1 * z + CREEP * creep_rate(strain, rate, state, reference)[0]


def _user_creep_law():
    """The same rope as a user law with a state rate (its state in a LineForm)."""
    pytest.importorskip("jax")
    return skmoor.UserLaw(creep_tension, state=lambda e, T: (e * EA_D / (EA_1 + EA_D),),
                          state_rate=creep_rate, reference="static",
                          static=skmoor.Engineering(), tension_only=False)


@pytest.mark.parametrize("law", ["deck", "user"])
def test_a_release_keeps_the_creep_state_of_the_lines(tmp_path, law, monkeypatch):
    """A line failure in a model whose lines keep a history: the hanging chains as
    MoorDyn's viscoelastic rope (``EA_s|EA_d`` with ``BA|BA_D``, the deck's law; or the
    same rope as a user law with a state rate), vessel 1 surged 2 m before the release,
    so that the creep state lags the strain. The rebuilt model takes on each line's
    creep state (``carry_memory``). The intact run is the reference: up to the release
    the two runs are the same, and one step after it line 2's top element (60 m and a
    clump away from the release) carries the intact run's tension within 1 N (measured
    0.01 N; the step before changed it by 70 N). A creep state started afresh at the
    release would jump it by 200 N."""
    text = HANGING.read_text().replace("chain     0.1    40.65    5.0e8   -1.0 ", VISCOELASTIC)
    intact_deck = tmp_path / "visco.dat"
    intact_deck.write_text(text)
    failing_deck = tmp_path / "visco_fail.dat"
    failing_deck.write_text(text.replace("---------------------- OPTIONS",
                                         FAILURE.format(rows=f"1  1  1  {RELEASE}  0"), 1))
    omega = 2 * np.pi / 4.0
    options = dict(motion=lambda t: np.array([[2.0 * (1.0 - np.cos(omega * t)), 0.0, 0.0],
                                              [0.0, 0.0, 0.0]]))
    if law == "user":
        options["law"] = _user_creep_law()

    def run(deck):
        return skmoor.simulate(skmoor.build(deck, **options), duration=RELEASE + 0.02,
                               dt=0.002, output_interval=0.002, progress=False)

    intact, broken = run(intact_deck), run(failing_deck)
    assert broken.meta["stopped"] is None and len(broken.meta["line_failures"]) == 1
    k = int(np.searchsorted(intact.t, RELEASE - 1e-9))  # the release's step
    top = np.flatnonzero(intact.line_of_cell == 1)[0]
    T_intact, T_broken = np.abs(intact.tension[:, top]), np.abs(broken.tension[:, top])
    assert np.array_equal(T_broken[:k + 1], T_intact[:k + 1])
    assert np.abs(np.diff(T_intact[k - 5:k + 1])).max() > 20.0  # the creep state moves
    assert abs(T_broken[k + 1] - T_intact[k + 1]) < 1.0


def carried_lift(kind):
    """Two lifts of ``kind`` (VortexLift or VortexLiftForm) on a rope in a current: the
    first committed at 0, 0.1 and 0.2 s at random states, its memory carried to the
    second, which then commits at 0.2 s (a run going on from there). (old, new, u, v)."""
    from skmoor.lines.catenary import solve_catenary
    from skmoor.sea import Current, Sea

    rope = skmoor.LineType(EA=5e8, mass=40.0, diameter=0.1, Cl=0.8)
    cat = solve_catenary([-40.0, 0.0, -5.0], [40.0, 0.0, -5.0], rope.weight, rope.EA,
                         length=100.0)
    lines = skmoor.LineSet([skmoor.Line.from_catenary(cat, rope, 10)])
    sea = Sea(100.0, current=Current(1.0, 90.0))
    old, new = kind(lines, sea), kind(lines, sea)
    rng = np.random.default_rng(3)
    u, v = 0.01 * rng.standard_normal(lines.ndofs), rng.standard_normal(lines.ndofs)
    for t in (0.0, 0.1, 0.2):
        old.commit(t, u * (1 + t), v * (1 - t))
    new.carry_memory(old)
    new.commit(0.2, u, 0.0 * v)
    return old, new, u, v


def test_a_release_carries_the_lift_phases_of_viv():
    """VIV's state (phases, their rates, running mean squares, velocities) carries over
    to a rebuilt lift on the same lines, and a run going on from the last committed time
    keeps it (a time before it starts anew)."""
    from skmoor.sea import VortexLift

    old, new, u, v = carried_lift(VortexLift)
    assert np.array_equal(new._state, old._state)
    new.commit(0.1, u, v)  # a time before: a new run
    assert np.array_equal(new._phase, new.first_phase)


def test_a_release_carries_the_memory_of_the_lift_written_as_forms():
    """The same for the lift's forms (VortexLiftForm, compiled): the memory by name and
    the last commit's time carry over, a run going on keeps it, an earlier time starts
    the phases anew."""
    pytest.importorskip("jax", reason="the lift's forms run compiled")
    from skmoor.sea import VortexLiftForm

    old, new, u, v = carried_lift(VortexLiftForm)
    for name, value in old.state_values().items():
        assert np.array_equal(new.state_values()[name], value), name
    assert new.state_values()["lifting"].all() and new.state_values()["rate"].any()
    new.commit(0.1, u, v)  # a time before: a new run
    assert np.array_equal(new.state_values()["phase"], new.state["phase"])


def test_a_release_carries_the_radiation_memory_of_a_body():
    """A body's radiation memory (Cummins' convolution over its velocity history) carries
    over to the rebuilt term: the same memory force at the next time, where a history
    started afresh would have none; a run going on from the last committed time keeps
    it, a time before it starts anew."""
    from skmoor.bodies.bem import Hydrodynamics
    from skmoor.bodies.radiation import PotentialFlow

    hydro = Hydrodynamics.load(Path(__file__).parents[2] / "meshes" / "box_hull_bem.npz")
    old, new = PotentialFlow(hydro), PotentialFlow(hydro)
    q, times = np.zeros(6), np.arange(0.0, 4.0, 0.1)
    for t in times:  # a surge and heave history
        old.commit(t, q, np.array([np.sin(t), 0.0, 0.5 * np.cos(t), 0.0, 0.0, 0.0]))
    new.carry_memory(old)
    t, qdot = 4.05, np.array([0.3, 0.0, 0.1, 0.0, 0.0, 0.0])
    memory = old.memory(t, qdot)[0]
    assert np.abs(memory).max() > 1e3  # N: the history matters
    np.testing.assert_allclose(new.memory(t, qdot)[0], memory, rtol=1e-12)
    new.commit(times[-1], q, 0.0 * qdot)  # (a run going on from the last time)
    np.testing.assert_allclose(new.memory(t, qdot)[0], memory, rtol=1e-12)
    new.commit(1.0, q, qdot)  # a time before: a new run
    assert new._count == 1


def host_run(module, path, duration, coupling=0.01, break_at=None, **create):
    """A host's loop on ``path`` (MoorDyn's Python interface, or skmoor's): line 2's
    force at vessel 2 (N) after each Step, line 1 broken off point 1 at ``break_at``."""
    md = module.Create(str(path), **create)
    vessels = [-40.0, 0.0, -5.0, 40.0, 0.0, -5.0]
    module.Init(md, vessels, [0.0] * 6)
    out = []
    for k in range(int(round(duration / coupling))):
        tk = k * coupling
        if break_at is not None and abs(tk - break_at) < 1e-9:
            module.BreakLine(md, module.GetPoint(md, 1), module.GetLine(md, 1))
        module.Step(md, vessels, [0.0] * 6, tk, coupling)
        out.append(np.linalg.norm(module.GetLineNodeTen(module.GetLine(md, 2), 0)))
    return md, np.array(out)


def test_a_host_breaks_a_line_or_the_deck_does(tmp_path, monkeypatch):
    """skmoor's MoorDyn interface: BreakLine between two Steps (MoorDyn's call) and a
    deck's FAILURE entry firing inside Step give the run skmoor.simulate makes of the
    deck (5 substeps of 2 ms per 10 ms call: the same steps); BreakLine adds a point."""
    from skmoor import moordyn as host

    monkeypatch.chdir(tmp_path)
    failing = deck_with(tmp_path, f"1  1  1  {RELEASE}  0")
    results = skmoor.simulate(skmoor.build(failing), duration=3.0, dt=0.002,
                              output_interval=0.01, progress=False)
    expected = results.anchor_tension[1:, 1]
    broken, by_call = host_run(host, HANGING, 3.0, break_at=RELEASE, substeps=5)
    assert host.GetNumberPoints(broken) == 4
    assert broken.model.network.points[-1].name == "point1.released"
    by_deck, fired = host_run(host, failing, 3.0, substeps=5)
    assert [e["time"] for e in by_deck.line_failures] == [pytest.approx(RELEASE)]
    for series in (by_call, fired):
        np.testing.assert_allclose(series, expected, rtol=1e-4)
    assert expected[int(RELEASE / 0.01) + 3] < 0.6 * expected[0]  # the release's stress wave
    with pytest.raises(ValueError, match="does not end at point 1"):
        host.BreakLine(broken, host.GetPoint(broken, 1), host.GetLine(broken, 2))
    before = host.SaveState(by_deck)  # taken after the release: restores
    host.LoadState(by_deck, before)
    md = host.Create(str(HANGING), substeps=5)
    host.Init(md, [-40.0, 0.0, -5.0, 40.0, 0.0, -5.0], [0.0] * 6)
    intact = host.SaveState(md)
    host.BreakLine(md, host.GetPoint(md, 1), host.GetLine(md, 1))
    with pytest.raises(ValueError, match="before a line failure"):
        host.LoadState(md, intact)


def test_a_rebased_body_keeps_its_frame_in_the_released_model():
    """A failure after a body was re-based (exact rotations past 60 deg of pitch): the
    released model counts the body's angles from the same frame (``use_frames``) with its
    own line ends placed on it, so that every line node and the body sit where they were.
    Here: buoy_on_a_rod.dat's body pitched 70 deg and re-based, line 2 released from the
    rod's end B."""
    from skmoor.run import failures

    model = skmoor.build(DECKS / "rods" / "buoy_on_a_rod.dat", rotations="exact")
    system = model.system
    x, v = np.zeros(system.n), np.zeros(system.n)
    x[system.nf:system.nf + 6] = [0.3, 0.0, 0.2, 0.1, np.radians(70.0), 0.2]
    v[system.nf:system.nf + 6] = [0.1, 0.0, 0.0, 0.0, 0.5, 0.0]
    turned = system.rebase(x, v)
    assert turned is not None and system.frames[0] is not None
    x, v = turned
    u_before, ud_before = system.full_state(x, v)
    pose = system.body_pose(x)
    frames = failures.frames_of(system)
    system.reset_frames()  # as the time loop leaves it when a failure stops it
    after = failures.released(model, "rod1.B", ["line2"])
    x_new, v_new = failures.carried_state(model, after, x, v, 0.0, frames)
    u_after, ud_after = after.system.full_state(x_new, v_new)
    np.testing.assert_allclose(u_after, u_before, atol=1e-12)
    np.testing.assert_allclose(ud_after, ud_before, atol=1e-12)
    np.testing.assert_allclose(after.system.body_pose(x_new), pose, atol=1e-12)
    assert np.abs(u_before).max() > 1.0  # the body did turn the lines' ends
