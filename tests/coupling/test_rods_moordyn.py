"""Rods: skmoor and MoorDyn v2 side by side on MoorDyn's own rod decks.

The decks are read from the local mirror of MoorDyn's repository (as
tests/io/test_moordyn_deck_set.py does; skipped without it) and copied into a temporary
folder, where MoorDyn writes its log. Changes made to them, the same for both codes:

    rod_tests/AddedMass.txt   as given (no lines: a network of rods alone); a
    RodPinnedFloating.txt     second run of RodPinnedFloating with Cd 1.2, Ca 1 on 20
                              segments (MoorDyn's dtM 1e-4 s)
    RodHanging.txt            its two fixed points made Coupled and heaved 2 m at 10 s
                              (the deck as given starts from lines far off their
                              equilibrium: MoorDyn's first step pulls 18 MN)
    body_tests/pinnedBody.txt (in air: water density 0) the pinned body moved 0.5 m in
                              x over 2 s, then held: the rod swings as a pendulum
    BodiesAndRods.dat         its lines replaced by one between two fixed points, the
                              body lowered to 20 m, no drag or added mass on the cans
                              (see the test)

Starting state: MoorDyn with TmaxIC = 0 starts from the deck's positions at rest, as
skmoor's ``start='given'`` does. RodHanging starts from equilibrium: MoorDyn's dynamic
relaxation does not settle this deck (4.6 m/s2 left after 100 s), so MoorDyn first runs
150 s with the points held and its line damping settles the rod (to 1 mm/s), skmoor
starts from its static solve.

What is compared: rod end positions (MoorDyn's GetRodNodePos at nodes 0 and N, skmoor's
points rodN.A / rodN.B), the end-segment tension at the rod of each line (MoorDyn's
GetLineNodeTen at node N, skmoor's last element tension), MoorDyn interpolated at
skmoor's samples; criterion max |skmoor - MoorDyn| over the run within a fraction of
MoorDyn's range (max - min) there.

Measured (wall time of the test incl. MoorDyn, on the shared 2-core machine):

    test                    compared                          measured          wall
    added_mass_rise         end A z vs MoorDyn, vs analytic   1e-13 m, 1e-13 m  3 s
    pinned_floating         ends B of both rods (x, y, z)     0.09 - 0.16 %     6 s (slow)
                            (dt 5 ms; 0.5 % at 10 ms)
                            rod 2's period vs the analytic    4e-4
                            pendulum of 90 deg amplitude
    pinned_floating_with_   the same with Cd 1.2, Ca 1 on 20  0.08 - 0.15 %     3 s
    drag                    segments (dt 10 ms)
    rod_hanging_heaved      end A z; end tensions (2 lines)   0.3 %; 0.15 %    19 s (slow)
    pinned_body_swing       end B x, z                        0.06 %, 0.18 %    5 s
    bodies_and_rods_pinned_ the pinned can's angle; its ends' 1.7 %; 0.25 %,    1 s
    rod                     heights (end A: the pin, body     0.2 %
                            heave)
    bodies_and_rods_pinned_ (no MoorDyn: its IC does not      upright to 1e-6   9 s (slow)
    can_stands_upright      settle) the static pinned can
                            upright

pinnedBody is coupled every 1 ms: MoorDyn moves a coupled object at constant velocity
within each Step() call, which at 5 ms raises the differences to 0.25 % and 0.55 %.
The 0.3 % of RodHanging's z is its static offset: MoorDyn's settled lumped-mass lines
hang the rod 9 mm lower than skmoor's (exact catenary) equilibrium.
"""
import re
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.special import ellipk

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import moordyn_decks as md  # noqa: E402

moordyn = pytest.importorskip("moordyn", reason="MoorDyn v2 (pip install moordyn) is the "
                              "lumped-mass dynamic peer")

from peers import faded_sine  # noqa: E402

import skmoor  # noqa: E402

try:
    MIRROR, NO_MIRROR = md.Mirror(md.mirror_path()), ""
except md.MirrorMissing as err:
    MIRROR, NO_MIRROR = None, str(err)
pytestmark = pytest.mark.skipif(MIRROR is None, reason=NO_MIRROR)

DUMMY_LINE = """---------------------- POINTS --------------------------------------
ID  Attachment  X  Y  Z  Mass  Volume  CdA  Ca
(#)  (word)  (m)  (m)  (m)  (kg)  (m^3)  (m^2)  (-)
1  Fixed  50  0  -1  0  0  0  0
2  Fixed  50  0  -2  0  0  0  0
---------------------- LINES ---------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)  (#)  (#)  (m)  (-)  (-)
1  {type}  1  2  1.0  1  -
"""
def deck(workdir, path, *, replace=()):
    """A copy of MoorDyn's deck ``path`` in workdir with the (old, new) text replacements
    done."""
    text = MIRROR.read(path).decode()
    for old, new in replace:
        assert old in text, old
        text = text.replace(old, new)
    out = Path(workdir) / Path(path).name
    out.write_text(text)
    return out


def run_moordyn(path, duration, *, coupling, sample, x=None, v=None, rods=(1,), lines=(),
                start=0.0):
    """MoorDyn's histories: t (s), ends A and B of ``rods`` (nt, nrods, 2, 3) (m), the
    tension at node N of ``lines`` (nt, nlines) (N), every ``sample`` s. Coupled DOFs
    x(t), v(t) (absolute, MoorDyn's order); a ``start`` s first with them held at x(0)."""
    system = moordyn.Create(str(path))
    try:
        x, v = x or (lambda t: []), v or (lambda t: [])
        assert moordyn.Init(system, list(x(0.0)), list(v(0.0))) == 0
        handles = [moordyn.GetRod(system, k) for k in rods]
        line_handles = [moordyn.GetLine(system, k) for k in lines]
        for k in range(int(round(start / 0.01))):
            moordyn.Step(system, list(x(0.0)), [0.0] * len(v(0.0)), k * 0.01, 0.01)
        every = int(round(sample / coupling))
        t, ends, tension = [], [], []
        for k in range(int(round(duration / coupling))):
            tk = k * coupling
            moordyn.Step(system, list(x(tk)), list(v(tk)), start + tk, coupling)
            if (k + 1) % every == 0:
                t.append(tk + coupling)
                ends.append([[moordyn.GetRodNodePos(h, 0),
                              moordyn.GetRodNodePos(h, moordyn.GetRodN(h))] for h in handles])
                tension.append([np.linalg.norm(moordyn.GetLineNodeTen(h, moordyn.GetLineN(h)))
                                for h in line_handles])
    finally:
        moordyn.Close(system)
    return np.array(t), np.array(ends), np.array(tension)


def simulate(path, duration, dt, *, start="given", motion=None, rotations="small"):
    """skmoor's Results on the deck at ``path`` (build notes silenced)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = skmoor.build(path, motion=motion, rotations=rotations)
        return skmoor.simulate(model, duration=duration, dt=dt, output_interval=dt,
                               start=start, progress=False)


def track(results, name):
    i = results.point_names.index(name)
    return results.point_reference[i] + results.point_displacement[:, i]


def worst(t, series, t_md, series_md):
    """max |skmoor - MoorDyn| / MoorDyn's range, MoorDyn interpolated at skmoor's t."""
    keep = t >= t_md[0]
    peer = np.interp(t[keep], t_md, series_md)
    return float(np.max(np.abs(series[keep] - peer)) / np.ptp(series_md))


def test_added_mass_rise(tmp_path):
    """rod_tests/AddedMass.txt: a buoyant horizontal rod (Ca = 1, no drag) rises from
    10 m at a = (rho V - m) g / (m + Ca rho V) in both codes."""
    path = deck(tmp_path, "tests/Mooring/rod_tests/AddedMass.txt")
    t_md, ends_md, _ = run_moordyn(path, 2.3, coupling=0.01, sample=0.01)
    r = simulate(path, 2.3, 0.05)
    z = track(r, "rod1.A")[:, 2]
    volume, mass, g = np.pi * 0.25 ** 2 * 2.0, 200.0, 9.80665
    a = (1025 * volume - mass) * g / (mass + 1025 * volume)
    assert np.max(np.abs(z - (-10 + 0.5 * a * r.t ** 2))) < 1e-9
    assert np.max(np.abs(ends_md[:, 0, 0, 2] - (-10 + 0.5 * a * t_md ** 2))) < 1e-9
    assert np.max(np.abs(z[1:] - np.interp(r.t[1:], t_md, ends_md[:, 0, 0, 2]))) < 1e-9


@pytest.mark.slow
def test_pinned_floating(tmp_path):
    """RodPinnedFloating.txt: two buoyant rods pinned at one end, released horizontal,
    swing up through the vertical to the other side and back (no drag: conservative);
    one along x (its pitch passes 90 deg), one along y. Rod 2's period is the compound
    pendulum's at 90 deg amplitude, 2 K(1/2) / pi longer than the small-swing one."""
    path = deck(tmp_path, "tests/Mooring/RodPinnedFloating.txt")
    t_md, ends_md, _ = run_moordyn(path, 1.3, coupling=0.01, sample=0.01, rods=(1, 2))
    r = simulate(path, 1.3, 0.005)
    for k in (1, 2):
        B = track(r, f"rod{k}.B")
        for axis in range(3):
            if np.ptp(ends_md[:, k - 1, 1, axis]) > 1e-6:
                assert worst(r.t, B[:, axis], t_md, ends_md[:, k - 1, 1, axis]) < 5e-3, (k, axis)
    L, d, mu, rho, g = 1.0, 0.25, 10.0, 1000.0, 9.80665
    mass, buoyant = mu * L, rho * np.pi * d ** 2 / 4 * L
    w0 = np.sqrt((buoyant - mass) * g * L / 2 / (mass * (L ** 2 / 3 + (d / 2) ** 2 / 4)))
    y = track(r, "rod2.B")[:, 1]  # 0 when upright: twice a period
    k = np.flatnonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)
    upright = r.t[k] - y[k] * (r.t[k + 1] - r.t[k]) / (y[k + 1] - y[k])
    assert len(upright) >= 3
    assert 2 * np.mean(np.diff(upright)) == pytest.approx(4 * ellipk(0.5) / w0, rel=1e-3)


@pytest.mark.parametrize("rotations", ["small", "exact"])
def test_pinned_floating_with_drag(tmp_path, rotations):
    """RodPinnedFloating.txt with drag and added mass on its rods (Cd 1.2, Ca 1) on 20
    segments (MoorDyn lumps a rod's added mass at its nodes: on NumSegs 1 its rotational
    added inertia is 3/2 of the exact one, on 20 within 0.2 %): the rods turn up, damped,
    through the vertical; transverse drag and added mass of a turning rod. With exact
    rotations rod 1 (along x) passes pitch 90 deg, the gimbal lock, re-based with its rod
    load (0.14 % of MoorDyn's range, as the small model, which is exact for a swing in
    one plane)."""
    path = deck(tmp_path, "tests/Mooring/RodPinnedFloating.txt", replace=[
        ("0.25     10.0      0.0    0.0     0.0      0.0",
         "0.25     10.0      1.2    1.0     0.0      0.0"),
        ("-5   1         -", "-5   20        -"), ("1e-5          dtM", "1e-4          dtM")])
    t_md, ends_md, _ = run_moordyn(path, 2.0, coupling=0.01, sample=0.01, rods=(1, 2))
    r = simulate(path, 2.0, 0.01, rotations=rotations)
    if rotations == "exact":
        assert np.abs(r.bodies[:, 0, 4]).max() > np.radians(89)
    for k in (1, 2):
        B = track(r, f"rod{k}.B")
        for axis in range(3):
            if np.ptp(ends_md[:, k - 1, 1, axis]) > 1e-6:
                assert worst(r.t, B[:, axis], t_md, ends_md[:, k - 1, 1, axis]) < 5e-3, (k, axis)


@pytest.mark.slow
def test_rod_hanging_heaved(tmp_path):
    """RodHanging.txt: a free rod (Cd 1.6, Ca 1, CdEnd 1.6, CaEnd 1) on two 450 m ropes,
    their tops heaved 2 m at 10 s: transverse drag and added mass of the rod."""
    path = deck(tmp_path, "tests/Mooring/RodHanging.txt", replace=[
        ("1     Fixed     -450", "1     Coupled   -450"),
        ("2     Fixed      450", "2     Coupled    450")])
    heave, speed = faded_sine(2.0, 2 * np.pi / 10.0, 10.0, np.array([0.0, 0.0, 1.0]))
    tops = np.array([-450.0, 0.0, 0.0, 450.0, 0.0, 0.0])
    t_md, ends_md, tension_md = run_moordyn(
        path, 20.0, coupling=0.005, sample=0.02, lines=(1, 2), start=150.0,
        x=lambda t: tops + np.r_[heave(t), heave(t)], v=lambda t: np.r_[speed(t), speed(t)])
    r = simulate(path, 20.0, 0.1, start="equilibrium",
                 motion=lambda t: np.r_[heave(t), heave(t)])
    assert worst(r.t, track(r, "rod1.A")[:, 2], t_md, ends_md[:, 0, 0, 2]) < 0.01
    for k in range(2):
        last = np.flatnonzero(r.line_of_cell == k)[-1]
        assert worst(r.t, r.tension[:, last], t_md, tension_md[:, k]) < 0.005, k
    assert np.max(np.abs(r.bodies[:, 0, 3:])) < 1e-9  # symmetric: it does not turn


def test_pinned_body_swing(tmp_path):
    """body_tests/pinnedBody.txt: a rod (Body1) hanging 10 m below a CoupledPinned
    body of no mass, which is moved 0.5 m in x and held: the rod swings as a
    compound pendulum about the body's pin."""
    path = deck(tmp_path, "tests/Mooring/body_tests/pinnedBody.txt")
    pin = np.array([0.0, 0.0, -5.0])

    def shift(t):
        return 0.5 * 0.5 * (1 - np.cos(np.pi * min(t, 2.0) / 2.0))

    def speed(t):
        return 0.5 * 0.5 * np.pi / 2.0 * np.sin(np.pi * t / 2.0) if t < 2.0 else 0.0

    t_md, ends_md, _ = run_moordyn(
        path, 6.0, coupling=0.001, sample=0.01,
        x=lambda t: np.r_[pin + [shift(t), 0.0, 0.0], 0.0, 0.0, 0.0],
        v=lambda t: np.r_[speed(t), 0.0, 0.0, 0.0, 0.0, 0.0])
    r = simulate(path, 6.0, 0.02, start="equilibrium",
                 motion=lambda t: np.r_[shift(t), 0.0, 0.0, 0.0, 0.0, 0.0])
    B = track(r, "rod1.B")
    assert worst(r.t, B[:, 0], t_md, ends_md[:, 0, 1, 0]) < 5e-3
    assert worst(r.t, B[:, 2], t_md, ends_md[:, 0, 1, 2]) < 1e-2


def test_bodies_and_rods_pinned_rod(tmp_path):
    """BodiesAndRods.dat's free body with its two cans, one fixed on it (Body1), one
    pinned to it (Body1Pinned: a pin between two bodies), lowered to 20 m (both cans
    under water), its lines replaced by one between two fixed points, no drag or added
    mass on the cans: released at rest, the pair rises and the pinned can swings up
    from 13 deg. Compared: the pinned can's angle, its ends' heights (end A: the pin on
    the body)."""
    text = MIRROR.read("tests/Mooring/BodiesAndRods.dat").decode()
    start = re.search(r"(?m)^-+ POINTS", text).start()
    options = re.search(r"(?m)^-+ SOLVER OPTIONS", text).start()
    text = text[:start] + DUMMY_LINE.format(type="cable") + text[options:]
    for old, new in (("Can           10       1.0e3     0.6    1.0     1.2      1.0",
                      "Can           10       1.0e3     0.0    0.0     0.0      0.0"),
                     ("1       free      0     0      0 ", "1       free      0     0    -20 "),
                     ("100.0    TmaxIC", "0.0      TmaxIC"),
                     ("FairTen1 FairTen2 FairTen3", ""), ("Point2px Point2py Point2pz", "")):
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "BodiesAndRods.dat"
    path.write_text(text)
    t_md, ends_md, _ = run_moordyn(path, 0.9, coupling=0.005, sample=0.01, rods=(2,))
    r = simulate(path, 0.9, 0.01)
    A, B = track(r, "rod2.A"), track(r, "rod2.B")
    angle = np.arctan2(B[:, 0] - A[:, 0], B[:, 2] - A[:, 2])
    angle_md = np.arctan2(*(ends_md[:, 0, 1] - ends_md[:, 0, 0])[:, [0, 2]].T)
    assert worst(r.t, angle, t_md, angle_md) < 0.03  # 1.7 %: see the docs (rods.md)
    assert worst(r.t, B[:, 2], t_md, ends_md[:, 0, 1, 2]) < 5e-3
    assert worst(r.t, A[:, 2], t_md, ends_md[:, 0, 0, 2]) < 5e-3  # the pin: body heave


@pytest.mark.slow
def test_bodies_and_rods_pinned_can_stands_upright(tmp_path):
    """BodiesAndRods.dat without its lazy cable (LINES 4-6, which skmoor cannot lay out:
    see docs/rods.md): the static state of the free body on its three nylon lines, with
    the pinned can (13 deg off the vertical as given) turned upright, as the moment of
    its buoyancy and weight about the pin, both vertical, demands. Needs the body's spin
    spring (all its lines meet on its can's axis: nothing else holds its yaw)."""
    text = MIRROR.read("tests/Mooring/BodiesAndRods.dat").decode()
    keep = [line for line in text.splitlines()
            if not re.match(r"\s*(4|5|6)\s+(cable|buoyancy)\s", line)
            and not re.match(r"\s*(7|8|9|10)\s+(Fixed|Free|Body1)\s", line)]
    path = tmp_path / "BodiesAndRods.dat"
    path.write_text("\n".join(keep) + "\n")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = skmoor.build(path)
        eq = skmoor.equilibrium(model)
    system = model.system
    q_body, q_can = (eq.x[system.nf + 6 * k: system.nf + 6 * k + 6] for k in (0, 1))
    R = skmoor.bodies.body.rotation_matrix(q_can[3:])
    axis = R @ np.array([3.0, 0.0, 13.0]) / np.hypot(3.0, 13.0)
    assert abs(axis[0]) < 1e-6 and axis[2] > 0  # upright (it started 13 deg off)
    assert abs(q_body[5]) < 1e-9  # the yaw stays
    assert q_body[2] < -5.0  # the cans float the body: it sinks from z = 0 to its draft
