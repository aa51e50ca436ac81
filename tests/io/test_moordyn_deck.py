"""MoorDyn v2 decks: read, write, refuse, build, run; MoorDyn reads what skmoor writes.

Independent numbers: MoorDyn 2.7 itself (it reads the written decks; its body-point
positions, coupled-DOF count and static fairlead force), and the static tensions
OrcaFlex gives for the quasi-static chain set MoorDyn validates against (MoorDyn's
tests/quasi_static_chain.cpp): fairlead / anchor 991.6 / 826.2 kN (50 m of water),
2065.4 / 1402.2 (200 m), 5232.6 / 3244.2 (600 m).
"""
import json
import re
from pathlib import Path

import numpy as np
import pytest

import skmoor
from skmoor import build
from skmoor.cli import main
from skmoor.io.deck import is_deck, read_deck, write_deck
from skmoor.model.from_deck import heave_motion
from skmoor.solvers.statics import solve_static

DECKS = Path(__file__).parents[2] / "examples" / "decks"
ORCAFLEX = {"50": (991.6e3, 826.2e3), "200": (2065.4e3, 1402.2e3), "600": (5232.6e3, 3244.2e3)}

# a deck using most of the format: comments, aliases, a coupled body with a rotated
# frame, a 12-column point, a line listed fairlead-first, outputs and an unknown option
RICH = """--------------------- MoorDyn Input File ---------------------
A test deck   # with a comment
---------------------- LINE TYPES --------------------------------
TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx
(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
rope 0.1 20.0 1.0e8 -0.5 0.0 1.2 1.0 0.2 0.0
wire 0.1 30.0 2.0e8 1000 0 1.0 0.8 0.1 0.1 0.0   # with VIV Cl = 0
---------------------- BODIES -----------------------------------
ID Attachment X0 Y0 Z0 r0 p0 y0 Mass CG* I* Volume CdA* Ca*
(#) (word) (m) (m) (m) (deg) (deg) (deg) (kg) (m) (kg-m^2) (m^3) (m^2) (-)
1 coupled 5 2 -1 10 5 30 1000 0|0|-1 5e3|6e3|7e3 2 3 1
---------------------- POINT PROPERTIES --------------------------
ID Attachment X Y Z Mass Volume FX FY FZ CdA Ca
(#) (word) (m) (m) (m) (kg) (m^3) (N) (N) (N) (m^2) (-)
1 Anchor 100.0 0.0 -50.0 0 0 0 0 0 0 0
2 Body1 10.0 0.0 -2.0 0 0 0 0 0 0 0
3 Fix -80.0 30.0 -50.0 0 0 0 0 0 0 0
4 Vessel -5.0 3.0 -3.0 0 0 0 0 0 0 0
---------------------- LINES -------------------------------------
ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs
(#) (name) (#) (#) (m) (-) (-)
1 rope 1 2 110.0 10 pt
2 wire P4 3 100.0 10 -
---------------------- OPTIONS -----------------------------------
0 writeLog
1.0e-4 dt
50 WtrDpth
1000.0 WtrDnsty
9.80665 gravity
1 TmaxIC
1 disableOutput
7 myOption   # unknown: kept
---------------------- OUTPUTS -----------------------------------
FAIRTEN1 ANCHTEN2
BODY1PZ
END
------------------------- need this line -------------------------
"""


@pytest.fixture
def rich(tmp_path):
    path = tmp_path / "rich.dat"
    path.write_text(RICH)
    return path


def test_read_rich_deck(rich):
    deck = read_deck(rich)
    assert deck.title == ["A test deck   # with a comment"]  # free-form, kept as written
    assert list(deck.line_types) == ["rope", "wire"]
    assert deck.line_types["wire"].viv == (0.0,)
    assert deck.line_types["rope"].BA == -0.5
    body = deck.bodies[0]
    assert (body.kind, body.r6, body.cg, body.inertia) == (
        "coupled", (5.0, 2.0, -1.0, 10.0, 5.0, 30.0), (0.0, 0.0, -1.0), (5e3, 6e3, 7e3))
    assert [p.kind for p in deck.points] == ["fixed", "body", "fixed", "coupled"]
    assert deck.points[1].body == 1 and deck.points[0].force == (0.0, 0.0, 0.0)
    assert (deck.lines[1].a, deck.lines[1].b, deck.lines[0].outputs) == (4, 3, "pt")
    # aliases to MoorDyn-C's names; the unknown option kept with a note
    assert deck.options["dtM"] == "1.0e-4" and deck.rho == 1000.0 and deck.g == 9.80665
    assert deck.options["myOption"] == "7" and any("myOption" in n for n in deck.notes)
    assert deck.outputs == ["FAIRTEN1", "ANCHTEN2", "BODY1PZ"]
    assert deck.depth == 50.0


@pytest.mark.parametrize("name", ["rich", "chain_50m", "chain_200m", "chain_600m"])
def test_round_trip(name, rich, tmp_path):
    """read -> write -> read gives the same deck (every number and option)."""
    path = rich if name == "rich" else DECKS / f"{name}.dat"
    deck = read_deck(path)
    again = read_deck(write_deck(deck, tmp_path / "again.dat"))
    assert again == deck
    assert again.notes == deck.notes


@pytest.fixture
def in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # MoorDyn writes its .out / .log files next to the deck
    return tmp_path


def test_moordyn_reads_the_written_deck_and_places_body_points_as_skmoor(rich, in_tmp):
    """MoorDyn 2.7 reads the written deck with 9 coupled DOFs (a body, a point), puts the
    body's point where skmoor does (frame rotated by roll, pitch, yaw), and moves the
    fairleads as skmoor's coupled-DOF motion does."""
    moordyn = pytest.importorskip("moordyn")
    deck = read_deck(rich)
    del deck.options["myOption"]  # MoorDyn would only warn; keep its log clean
    written = write_deck(deck, in_tmp / "written.dat")
    y = np.array([0.5, -0.3, 1.0, 0.05, -0.04, 0.1, 0.2, 0.1, -0.3])
    model = build(written, motion=lambda t: y)
    x0 = model.network.coupled_positions()
    md = moordyn.Create(str(written))
    try:
        assert moordyn.NCoupledDOF(md) == model.network.n_coupled_dofs == 9
        assert moordyn.Init(md, list(x0), [0.0] * 9) == 0
        before = [moordyn.GetPointPos(moordyn.GetPoint(md, i)) for i in (2, 4)]
        moordyn.Step(md, list(x0 + y), [0.0] * 9, 0.0, 1e-4)  # zero velocity: lands on x0 + y
        after = [moordyn.GetPointPos(moordyn.GetPoint(md, i)) for i in (2, 4)]
    finally:
        moordyn.Close(md)
    lines = model.lines  # point 2 is line 1's end B, point 4 line 2's end A
    ends = [lines.fairlead_nodes[0], lines.anchor_nodes[1]]
    np.testing.assert_allclose(lines.points[ends], before, atol=1e-9)
    u = model.system.full_displacement(np.zeros(model.system.n), 1.0)[lines.nodal_dofs[ends]]
    np.testing.assert_allclose(lines.points[ends] + u, after, atol=1e-9)


def test_moordyn_runs_a_written_chain_deck_to_skmoor_statics(in_tmp):
    """MoorDyn's settled chain (its own statics, discrete, same bed) pulls on the
    fairlead as skmoor's static line within 0.5 % (measured 0.15 %)."""
    moordyn = pytest.importorskip("moordyn")
    deck = read_deck(DECKS / "chain_50m.dat")
    written = write_deck(deck, in_tmp / "chain.dat")
    model = build(written)
    fair, _ = model.system.reactions(solve_static(model.system).x)
    md = moordyn.Create(str(written))
    try:
        assert moordyn.Init(md, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]) == 0
        force = np.linalg.norm(moordyn.GetPointForce(moordyn.GetPoint(md, 2)))
    finally:
        moordyn.Close(md)
    assert np.linalg.norm(fair[0]) == pytest.approx(force, rel=5e-3)


@pytest.mark.parametrize("depth", ["50", "200", "600"])
def test_chain_statics_from_decks(depth):
    """Static fairlead and anchor tensions of each chain deck (catenary reference, FE
    line, MoorDyn's bottom springs) within 2 % of OrcaFlex (measured: +1.6 / +1.8 %,
    +0.4 / +0.5 %, +0.1 / +0.2 %; the analytic catenary alone gives +1.0 / +1.2 % at
    50 m, the bed springs letting the laid chain sink 0.13 m add the rest)."""
    model = build(DECKS / f"chain_{depth}m.dat")
    fair, anchor = model.system.reactions(solve_static(model.system).x)
    fairlead_ref, anchor_ref = ORCAFLEX[depth]
    assert np.linalg.norm(fair[0]) == pytest.approx(fairlead_ref, rel=0.02)
    assert np.linalg.norm(anchor[0]) == pytest.approx(anchor_ref, rel=0.02)


def _deck_with(tmp_path, old, new):
    path = tmp_path / "edited.dat"
    text = (DECKS / "chain_50m.dat").read_text()
    assert old in text
    path.write_text(text.replace(old, new))
    return path


@pytest.mark.parametrize("old, new, message", [
    ("1.674e9 ", "ea_curve.txt ", "line 8: LINE TYPES EA: 'ea_curve.txt' is neither a number "
     "nor a curve file"),
    ("1.674e9 ", "1.6e9|2e9|0.3|1 ", "line 8: LINE TYPES EA: '1.6e9|2e9|0.3|1' has 4"),
    ("-1.0      0.0", "-1.0 0.0 1.0 0.1", "line 8: LINE TYPES entry: needs the 10 columns"),
    ("-1.0      0.0", "-1.0      -3.0e5", "line 8: LINE TYPES EI: bending stiffness must be >= 0"),
    ("1   chain     1        2", "1   chain     R1A      2",
     "line 17: LINES AttachA: rod 1 is not in RODS (0 rods)"),
    ("1   chain     1        2", "1   chain     1        3",
     "line 17: LINES AttachB: point 3 is not in"),
    ("1   chain     1", "1   cable     1", "line 17: LINES LineType: 'cable' is not in LINE TYPES"),
    ("2   Coupled", "2   Floating", "line 13: POINTS Attachment: 'Floating' is not"),
    ("2   Coupled", "3   Coupled", "line 13: POINTS ID: must count up from 1"),
    ("-------- OPTIONS", "-------- RODS ---\nID\n(#)\n1 x\n-------- OPTIONS",
     "line 21: RODS entry: needs the 11 columns"),
    ("-------- OUTPUTS", "-------- WATER STUFF ---\n3 x\n-------- OUTPUTS",
     "line 31: '3 x' under '---------------------- WATER STUFF ---', which is no section"),
])
def test_reader_refuses_with_the_deck_line(tmp_path, old, new, message):
    with pytest.raises(ValueError, match="edited.dat " + re.escape(message)):
        read_deck(_deck_with(tmp_path, old, new))


@pytest.mark.parametrize("old, new, message", [
    ("1          disableOutput", "1 disableOutput\n4 WaveKin",
     "line 30: option WaveKin = 4: skmoor reads WaveKin 1, 2, 3, 7"),
    ("1          disableOutput", "1 disableOutput\n2 WaveKin",
     "line 30: option WaveKin = 2: wave_frequencies.txt: no such file"),
    ("410.0", "150.0", "line 17: LINES 1: its ends are 403.113 m apart, 169 % more than its length 150 m"),
])
def test_model_refuses_with_the_deck_line(tmp_path, old, new, message):
    with pytest.raises(ValueError, match="edited.dat " + re.escape(message)):
        build(_deck_with(tmp_path, old, new))


def test_heave_motion_velocity_is_its_derivative():
    """The heave motion's velocity (given to MoorDyn) is the time derivative of its
    displacement (given to both codes), through the fade-in and after it."""
    motion, velocity = heave_motion(read_deck(DECKS / "chain_50m.dat"), 2.0, 10.0)
    h = 1e-6
    for t in (0.0, 1.3, 7.7, 10.0 + 2 * h, 23.4):
        fd = (motion(t + h) - motion(max(t - h, 0.0))) / (h + min(t, h))
        np.testing.assert_allclose(velocity(t), fd, atol=1e-6)
    assert motion(0.0)[2] == 0.0 and motion(12.5)[2] == pytest.approx(2.0)


def test_run_deck_cli(tmp_path):
    """`skmoor run deck.dat --heave A --period T` writes the TOML path's files; the
    static fairlead tension in summary.json is OrcaFlex's within 2 %, sampled at the
    deck's dtOut; --heave needs --period."""
    out = tmp_path / "out"
    deck = DECKS / "chain_50m.dat"
    assert is_deck(deck) and not is_deck(DECKS.parent / "paper_case.toml")
    code = main(["run", str(deck), "--out", str(out), "--duration", "4", "--heave", "2",
                 "--period", "10", "--no-export", "--no-animation", "--quiet"])
    assert code == 0
    info = json.loads((out / "summary.json").read_text())
    assert info["fairlead_tension_static"][0] == pytest.approx(ORCAFLEX["50"][0], rel=0.02)
    assert info["simulated_time"] == pytest.approx(4.0)
    table = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)
    assert np.allclose(np.diff(table["t"]), 0.1)
    assert np.ptp(table["fairlead_tension_line1"]) > 1e4  # the heave moves it
    assert not any("surge" in name for name in table.dtype.names)  # no body: no body columns
    assert (out / "results.npz").exists()
    assert main(["run", str(deck), "--out", str(out), "--heave", "2", "--quiet"]) == 2


def test_deck_bed_damping_fades_in_over_a_tenth_of_the_static_penetration():
    """The deck's bed fades its damping in over a tenth of the chain's static penetration
    w / (kBot d) (13.2 mm; w = (Mass/m - rho pi d^2 / 4) g, MoorDyn's ww_l), so the bed
    force on a node moving into the bed at 0.3 m/s is continuous through touchdown
    (MoorDyn's law jumps by cBot d W v, W the node's 10 m share of line length)."""
    model = build(DECKS / "chain_50m.dat")
    lines, bed = model.lines, model.network.seabed
    w = (390.0 - 1025.0 * np.pi * 0.252**2 / 4) * 9.81
    assert bed.onset(lines) == pytest.approx(0.1 * w / (1e5 * 0.252), rel=1e-12)
    term = model.system.terms[0]
    node = lines.nodal_dofs[10]  # a node of the laid chain
    ud = np.zeros(lines.ndofs)
    ud[node[2]] = -0.3  # moving into the bed

    def bed_force(g):
        u = np.zeros(lines.ndofs)
        u[node[2]] = bed.penetration(lines.points[10]) - g  # penetration g at the node
        return term.evaluate(u, ud, 0.0, tangent=False)[0][node[2]]

    assert abs(bed_force(1e-9) - bed_force(-1e-9)) < 1e-6 * 1e4 * 0.252 * 10.0 * 0.3


def test_run_deck_with_a_motion_file(tmp_path):
    """`skmoor run deck --motion FILE`: the coupled point moved by a table of times and
    displacements gives the same fairlead tension history as the same motion given in
    Python (the file sampled every 0.01 s, linear in between: within 0.2 % of the swing);
    a table with the wrong number of columns is refused naming the file and the count."""
    deck = DECKS / "chain_50m.dat"
    motion, _ = heave_motion(read_deck(deck), 2.0, 10.0)
    times = np.arange(0.0, 6.01, 0.01)
    table = np.column_stack([times, [motion(t) for t in times]])
    path = tmp_path / "motion.csv"
    np.savetxt(path, table, delimiter=",", header="t, x, y, z", comments="# ")
    out = tmp_path / "out"
    assert main(["run", str(deck), "--out", str(out), "--duration", "6", "--motion", str(path),
                 "--no-export", "--no-animation", "--quiet"]) == 0
    from_file = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)
    model = build(deck, motion=motion)
    direct = skmoor.simulate(model, duration=6.0, progress=False)
    swing = np.ptp(direct.fairlead_tension[:, 0])
    assert swing > 1e4
    assert np.max(np.abs(from_file["fairlead_tension_line1"] - direct.fairlead_tension[:, 0])) \
        < 2e-3 * swing
    bad = tmp_path / "bad.csv"
    np.savetxt(bad, table[:, :3], delimiter=",")
    assert main(["run", str(deck), "--out", str(out), "--motion", str(bad), "--quiet"]) == 2
