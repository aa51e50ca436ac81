"""`skmoor run DECK --moordyn-outputs` against MoorDyn's own output files of the same deck.

One hanging chain (no sea bed contact, no drag) from a fixed anchor to a held fairlead,
20 segments, line flags 'pvt' and OUTPUTS FairTen1, AnchTen1 and L1N5PZ. MoorDyn settles
the line and writes its files; skmoor runs the deck with the fairlead held. One reader, as
a user's post-processing script written for MoorDyn would be (header row, units row,
numbers), reads both: the same columns in the same order, and the same static line (node
positions within 5 cm, tensions within 0.5 %: MoorDyn's segments are chords of the
catenary, skmoor's elements carry its tension at their mid-points).
"""
import numpy as np
import pytest

from skmoor.cli import main

moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) writes "
                              "the reference files")

ANCHOR, FAIRLEAD = (-90.0, 0.0, -70.0), (0.0, 0.0, -10.0)
DECK = """one hanging chain, for --moordyn-outputs
---------------------- LINE TYPES ----------------------------------
TypeName  Diam  Mass/m  EA  BA/-zeta  EI  Cd  Ca  CdAx  CaAx
(name)  (m)  (kg/m)  (N)  (N-s/-)  (N-m^2)  (-)  (-)  (-)  (-)
chain  0.1  100.0  5.0e8  -0.8  0  0  0  0  0
---------------------- POINTS --------------------------------------
ID  Attachment  X  Y  Z  Mass  Volume  CdA  Ca
(#)  (word)  (m)  (m)  (m)  (kg)  (m^3)  (m^2)  (-)
1  Fixed  -90.0  0.0  -70.0  0  0  0  0
2  Coupled  0.0  0.0  -10.0  0  0  0  0
---------------------- LINES ---------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)  (#)  (#)  (m)  (-)  (-)
1  chain  1  2  120.0  20  pvt
---------------------- OPTIONS -------------------------------------
2e-4  dtM
9.81  g
1025  rho
200  WtrDpth
60  TmaxIC
1e-6  threshIC
0.5  dtOut
---------------------- OUTPUTS -------------------------------------
FairTen1
AnchTen1
L1N5PZ
---------------------- END -----------------------------------------
"""


def read_out(path):
    """What a script written for MoorDyn's outputs does: (column names, numbers)."""
    with open(path) as f:
        names = f.readline().split()
    return names, np.loadtxt(path, skiprows=2, ndmin=2)


def units(path):
    with open(path) as f:
        return f.readlines()[1].split()


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("moordyn_outputs")
    deck = folder / "chain.dat"
    deck.write_text(DECK)
    md = moordyn.Create(str(deck))
    try:
        assert moordyn.Init(md, list(FAIRLEAD), [0.0, 0.0, 0.0]) == 0
        for k in range(4):
            moordyn.Step(md, list(FAIRLEAD), [0.0, 0.0, 0.0], 0.5 * k, 0.5)
    finally:
        moordyn.Close(md)
    out = folder / "skmoor-out"
    code = main(["run", str(deck), "--out", str(out), "--duration", "2", "--dt", "0.05",
                 "--output-interval", "0.5", "--no-export", "--no-animation", "--quiet",
                 "--moordyn-outputs"])
    assert code == 0
    return folder, out


@pytest.mark.parametrize("name", ["chain.out", "chain_Line1.out"])
def test_same_columns(files, name):
    folder, out = files
    assert (folder / name).exists(), f"MoorDyn wrote no {name}"
    theirs, _ = read_out(folder / name)
    ours, _ = read_out(out / name)
    assert ours == theirs
    assert units(out / name) == units(folder / name)


def test_same_static_line(files):
    folder, out = files
    names, theirs = read_out(folder / "chain_Line1.out")
    _, ours = read_out(out / "chain_Line1.out")
    md, sk = theirs[-1], ours[-1]  # the settled line (both held still)
    position = [i for i, n in enumerate(names) if "p" in n[4:] and n.startswith("Node")]
    tension = [i for i, n in enumerate(names) if n.startswith("Seg")]
    assert len(position) == 3 * 21 and len(tension) == 20
    assert np.abs(sk[position] - md[position]).max() < 0.05  # m
    assert sk[position][:3] == pytest.approx(ANCHOR)  # Node0 is end A, the anchor
    np.testing.assert_allclose(sk[tension], md[tension], rtol=5e-3)
    names, theirs = read_out(folder / "chain.out")
    _, ours = read_out(out / "chain.out")
    np.testing.assert_allclose(ours[-1, 1:3], theirs[-1, 1:3], rtol=5e-3)  # FairTen, AnchTen
    assert ours[-1, 3] == pytest.approx(theirs[-1, 3], abs=0.05)  # L1N5PZ, m
    assert ours[-1, 1] > ours[-1, 2]  # the fairlead carries the line's weight


def test_left_out_flags_are_named(files, tmp_path):
    """A flag or channel skmoor does not write is named, not silently dropped."""
    from skmoor.post.moordyn_outputs import write_moordyn_outputs
    from skmoor.post.results import Results

    results = Results.load(files[1] / "results.npz")
    notes = write_moordyn_outputs(results, tmp_path, "x", {1: "pK"}, ["FairTen1", "Con1Fx"])
    assert any("'K'" in n for n in notes) and any("Con1Fx" in n for n in notes)
    names, _ = read_out(tmp_path / "x.out")
    assert names == ["Time", "FairTen1"]


def test_a_deck_without_outputs_gives_what_moordyn_gives(tmp_path):
    """No OUTPUTS section: MoorDyn's NAME.out has its time column alone; so has skmoor's."""
    deck = tmp_path / "bare.dat"
    head, tail = DECK.split("---------------------- OUTPUTS")
    deck.write_text(head + "---------------------- END" + tail.split("---------------------- END")[1])
    md = moordyn.Create(str(deck))
    try:
        assert moordyn.Init(md, list(FAIRLEAD), [0.0, 0.0, 0.0]) == 0
        moordyn.Step(md, list(FAIRLEAD), [0.0, 0.0, 0.0], 0.0, 0.5)
    finally:
        moordyn.Close(md)
    out = tmp_path / "skmoor-out"
    assert main(["run", str(deck), "--out", str(out), "--duration", "1", "--dt", "0.05",
                 "--output-interval", "0.5", "--no-export", "--no-animation", "--quiet",
                 "--moordyn-outputs"]) == 0
    assert read_out(out / "bare.out")[0] == read_out(tmp_path / "bare.out")[0]
