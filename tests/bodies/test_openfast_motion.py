"""Platform motion from OpenFAST output files (skmoor.openfast_motion, ``--motion X.outb``).

The file is read with NREL's reader (openfast_io); the test writes the two formats as
OpenFAST lays them out (text: 8 header lines, names and units; binary: file format 3,
uncompressed doubles with a start time and step), with the platform channels among others
and out of order, the angles in degrees. Checked:

- a coupled body's six columns are the platform's DOFs (angles in rad);
- a coupled point on the platform moves as MoorDyn moves the same point on a coupled body
  given the same six DOFs (MoorDyn v2.7 stepped through the record, GetPointPos of the body
  points, at 17-29 deg of roll, pitch and yaw: 1e-9 m). A sign, the order of the rotations
  (Rz Ry Rx instead of MoorDyn's Rx Ry Rz: 2.2 m off here) or degrees read as radians fail it;
- a run of the coupled-points deck (CLI, binary file) equals the run of the coupled-body
  deck (API, text file) in every element's tension, to the time step's accuracy;
- a real OpenFAST binary file (OpenFAST's python-toolbox sample, fetched, not copied) reads;
  files without the platform channels, decks the record cannot move and a table reader
  given an OpenFAST file say so.
"""
import os
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("openfast_io", reason="OpenFAST files are read with openfast_io "
                    "(pip install 'skmoor[openfast]')")

import skmoor  # noqa: E402
from skmoor.io.deck import read_deck  # noqa: E402
from skmoor.model.openfast_motion import read_openfast_platform  # noqa: E402

ROOT = Path(__file__).parents[2]
TOOLBOX = Path("/work/.mirror/OpenFAST+python-toolbox/repo")
FAIRLEADS = np.array([[-10.0, 0.0, -5.0], [5.0, 8.66, -5.0], [5.0, -8.66, -5.0]])
ANCHORS = 6.0 * FAIRLEADS * [1, 1, 0] + [0, 0, -50.0]
PEAK = np.array([3.0, -2.0, 1.5, 0.3, -0.4, 0.5])  # m, m, m, rad, rad, rad


def deck_text(fairleads: str) -> str:
    """A three-line mooring, the fairleads on a coupled body ('Body1') or coupled points."""
    body = "1   Coupled  0 0 0  0 0 0  0 0 0 0 0 0\n" if fairleads == "Body1" else ""
    points = "".join(f"{2 * i + 1}  {fairleads}  {f[0]} {f[1]} {f[2]}  0 0 0 0\n"
                     f"{2 * i + 2}  Fixed  {a[0]:.3f} {a[1]:.3f} {a[2]}  0 0 0 0\n"
                     for i, (f, a) in enumerate(zip(FAIRLEADS, ANCHORS)))
    lines = "".join(f"{i + 1}  chain  {2 * i + 2}  {2 * i + 1}  80.0  12  -\n" for i in range(3))
    return f"""skmoor test deck: three chains on a platform driven by an OpenFAST record
----------------------- LINE TYPES ------------------------------------------
TypeName  Diam   Mass/m   EA       BA/-zeta  EI   Cd   Ca    CdAx  CaAx
(name)    (m)    (kg/m)   (N)      (N-s/-)   (-)  (-)  (-)   (-)   (-)
chain     0.1    60.0     5.0e8    -1.0      0    1.2  1.0   0.4   0.0
---------------------- BODIES ------------------------------------------------
ID  Attachment  X0 Y0 Z0  r0 p0 y0  Mass CG* I* Volume CdA* Ca*
(#) (-)         (m) (m) (m) (deg) (deg) (deg) (kg) (m) (kg-m^2) (m^3) (m^2) (-)
{body}---------------------- POINTS ------------------------------------------------
ID  Attachment  X  Y  Z  Mass  Volume  CdA  Ca
(#) (-)         (m) (m) (m) (kg) (m^3) (m2) (-)
{points}---------------------- LINES -------------------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  Outputs
(#) (name)    (#)      (#)      (m)       (-)      (-)
{lines}---------------------- OPTIONS -----------------------------------------------
0.0005    dtM       time step (s)
50.0      WtrDpth   water depth (m)
3.0e6     kBot      bed stiffness (Pa/m)
3.0e5     cBot      bed damping (Pa s/m)
5.0       TmaxIC    initial-condition time (s)
------------------------- END -----------------------------------------------
"""


def platform_history(dt=0.05, duration=4.0):
    """(times, six DOFs): the platform eased from rest to PEAK over the first 2 s, held."""
    t = np.arange(0.0, duration + dt / 2, dt)
    s = np.clip(t / 2.0, 0.0, 1.0)
    return t, (s**3 * (10 - 15 * s + 6 * s**2))[:, None] * PEAK


# OpenFAST's channels for the six DOFs, with others, not in the DOFs' order
CHANNELS = ["Wave1Elev", "PtfmYaw", "PtfmSurge", "PtfmRoll", "PtfmSway", "PtfmPitch",
            "PtfmHeave"]
UNITS = ["m", "deg", "m", "deg", "m", "deg", "m"]


def channel_table(q):
    by_dof = dict(zip(["PtfmSurge", "PtfmSway", "PtfmHeave", "PtfmRoll", "PtfmPitch",
                       "PtfmYaw"], q.T))
    columns = [np.degrees(by_dof[c]) if u == "deg" else by_dof.get(c, 0.1 * np.ones(len(q)))
               for c, u in zip(CHANNELS, UNITS)]
    return np.column_stack(columns)


def write_text_output(path, t, q):
    """OpenFAST's text output: 8 header lines (names on the 7th, units on the 8th), rows."""
    header = ["", "Predictions were generated using OpenFAST (written by skmoor's tests)",
              " linked with NWTC Subroutine Library; ElastoDyn; HydroDyn; MoorDyn", "",
              "Description from the FAST input file: skmoor test platform", "",
              "\t".join(["Time"] + CHANNELS), "\t".join(f"({u})" for u in ["s"] + UNITS)]
    rows = ["\t".join(f"{v:.15e}" for v in row) for row in np.column_stack([t, channel_table(q)])]
    Path(path).write_text("\n".join(header + rows) + "\n")


def write_binary_output(path, t, q):
    """OpenFAST's binary output, file format 3: uncompressed doubles, time as start + step."""
    data = channel_table(q)
    names = ["Time"] + CHANNELS
    units = ["(s)"] + [f"({u})" for u in UNITS]
    desc = b"skmoor test platform"
    blob = struct.pack("<hiidd", 3, len(CHANNELS), len(t), t[0], t[1] - t[0])
    blob += struct.pack("<i", len(desc)) + desc
    blob += b"".join(n.ljust(10).encode() for n in names)
    blob += b"".join(u.ljust(10).encode() for u in units)
    blob += data.astype("<f8").tobytes()
    Path(path).write_bytes(blob)


@pytest.fixture
def files(tmp_path):
    t, q = platform_history()
    write_text_output(tmp_path / "platform.out", t, q)
    write_binary_output(tmp_path / "platform.outb", t, q)
    (tmp_path / "body.dat").write_text(deck_text("Body1"))
    (tmp_path / "points.dat").write_text(deck_text("Coupled"))
    return tmp_path, t, q


def test_both_formats_give_the_platform_dofs(files):
    folder, t, q = files
    for name in ("platform.out", "platform.outb"):
        times, dofs = read_openfast_platform(folder / name)
        np.testing.assert_allclose(times, t, atol=1e-12)
        np.testing.assert_allclose(dofs, q, atol=1e-12)
    record = skmoor.openfast_motion(folder / "platform.out", read_deck(folder / "body.dat"))
    np.testing.assert_allclose(record.position(t), q, atol=1e-12)


def test_fairleads_move_as_moordyn_moves_them_on_a_coupled_body(files):
    moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 turns the coupled body")
    folder, t, q = files
    record = skmoor.openfast_motion(folder / "platform.outb", read_deck(folder / "points.dat"))
    moved = record.position(t).reshape(len(t), 3, 3) + FAIRLEADS
    md = moordyn.Create(str(folder / "body.dat"))
    try:
        moordyn.Init(md, q[0], np.zeros(6))
        worst = 0.0
        for k in range(1, len(t)):
            # MoorDyn takes the pose at the step's start and carries it on at the velocity
            dt = t[k] - t[k - 1]
            moordyn.Step(md, q[k - 1], (q[k] - q[k - 1]) / dt, t[k - 1], dt)
            ours = moved[k]
            theirs = np.array([moordyn.GetPointPos(moordyn.GetPoint(md, 2 * i + 1))
                               for i in range(3)])
            worst = max(worst, np.abs(ours - theirs).max())
    finally:
        moordyn.Close(md)
    assert worst < 1e-9, worst
    # the pose is far from small angles: the order of the rotations matters by metres here
    assert np.abs(moved[-1] - (FAIRLEADS + PEAK[:3])).max() > 3.0


def test_cli_run_on_points_equals_the_coupled_body_run(files, monkeypatch):
    folder, _, _ = files
    monkeypatch.chdir(folder)
    out = subprocess.run([sys.executable, "-m", "skmoor.cli", "run", "points.dat", "--motion",
                          "platform.outb", "--duration", "3", "--dt", "0.01",
                          "--output-interval", "0.1", "--out", "points-out", "--no-export",
                          "--no-animation", "--quiet"], capture_output=True, text=True,
                         env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert out.returncode == 0, out.stderr[-2000:]
    deck = read_deck(folder / "body.dat")
    model = skmoor.build(deck, motion=skmoor.openfast_motion(folder / "platform.out", deck))
    body = skmoor.simulate(model, duration=3.0, dt=0.01, output_interval=0.1, progress=False)
    points = skmoor.Results.load(folder / "points-out" / "results.npz")
    # equal to the step's accuracy: the body's points move by the exact kinematics at the
    # scheme's stages, the coupled points by their splines (measured 1.2e-4 of the largest
    # tension at dt 0.01 s, 0.9e-4 at 0.005 s; halving dt itself changes them by 1.7e-3)
    scale = np.abs(points.tension).max()
    np.testing.assert_allclose(body.tension, points.tension, atol=3e-4 * scale)
    # the motion matters: every element's tension changes by a tenth of the largest or more
    assert np.ptp(points.tension, axis=0).min() > 0.1 * scale


def test_a_real_openfast_binary_file_reads(tmp_path):
    if not (TOOLBOX / "HEAD").exists() and not (TOOLBOX / "objects").exists():
        pytest.skip("fetch github:OpenFAST/python-toolbox for OpenFAST's sample outputs")

    def sample(name):
        target = tmp_path / Path(name).name
        target.write_bytes(subprocess.run(["git", "--git-dir", str(TOOLBOX), "show",
                                           f"HEAD:{name}"], capture_output=True,
                                          check=True).stdout)
        return target

    times, dofs = read_openfast_platform(sample("data/example_files/fastout_allnodes.outb"))
    assert times.shape == (101,) and times[0] == 0.0 and times[-1] == pytest.approx(10.0)
    assert dofs.shape == (101, 6) and np.all(np.isfinite(dofs))
    with pytest.raises(ValueError, match="no channel PtfmSurge"):
        read_openfast_platform(sample("pyFAST/input_output/tests/example_files/FASTOut.out"))


def test_what_a_record_cannot_move_is_refused(files):
    folder, t, q = files
    text = (folder / "platform.out").read_text().replace("PtfmPitch", "PtfmPitxh")
    (folder / "bad.out").write_text(text)
    with pytest.raises(ValueError, match="no channel PtfmPitch"):
        read_openfast_platform(folder / "bad.out")
    text = (folder / "platform.out").read_text().replace("(deg)", "(rpm)", 1)
    (folder / "rpm.out").write_text(text)
    with pytest.raises(ValueError, match="PtfmYaw in 'rpm'"):
        read_openfast_platform(folder / "rpm.out")
    two = deck_text("Body1").replace("1   Coupled  0 0 0  0 0 0  0 0 0 0 0 0\n",
                                     "1   Coupled  0 0 0  0 0 0  0 0 0 0 0 0\n"
                                     "2   Coupled  50 0 0  0 0 0  0 0 0 0 0 0\n")
    (folder / "two.dat").write_text(two)
    with pytest.raises(ValueError, match="2 coupled bodies"):
        skmoor.openfast_motion(folder / "platform.out", read_deck(folder / "two.dat"))
    with pytest.raises(ValueError, match="openfast_motion"):
        skmoor.read_motion(folder / "platform.out", 9)
