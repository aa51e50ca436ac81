"""skmoor's network statics against MoorPy on five MoorDyn v2 decks (tests/decks/network).

The decks: a chain-polyester leg with a free junction (two_segment), a clump weight
(clump_weight), a subsurface buoy making an S (s_line), a free 6-DOF buoy on three taut
legs (buoy_three_legs), two coupled floaters with a shared line (shared_line). MoorPy's
numbers come from tests/moorpy_network.py (its module docstring lists MoorPy's
conventions); the tests whose names contain 'sanity' check those numbers by hand and
need no skmoor, the others compare skmoor through its public API:

    model = skmoor.build(deck); eq = skmoor.equilibrium(model)
    st = skmoor.static_results(model, eq); skmoor.mooring_stiffness(model, eq, body=...)

Criteria (the issue's): end tensions within 0.1 %; every point's position within 0.1 %
of the shortest line attached to it (m); the free body's reference point likewise and
its rotations within ROT_TOL; the 6x6 mooring stiffness within 1 % per 3x3 block of the
block's scale (the largest diagonal entry of a diagonal block; the geometric mean of the
two for a coupling block), against MoorPy's stiffness turned into skmoor's generalized
convention d(J^T f)/dq (they differ by the lines' moment about the reference point, 7 %
of the rotational block for the shared line's floaters; see moorpy_network). The
'bugs_detectable' sanity test shows, with MoorPy itself, that plausible bugs (a dropped
point buoyancy or mass, a weight sign, a junction not released, a body's rotations not
free, a fairlead offset lost, the arm term of the rotational stiffness lost, MoorPy's
stiffness convention taken as is) move the numbers beyond these tolerances.
"""
import functools

import numpy as np
import pytest

pytest.importorskip("moorpy", reason="MoorPy (pip install moorpy) is the quasi-static peer")

from moorpy_network import (  # noqa: E402
    DECK_NAMES,
    arm_stiffness,
    block_error,
    deck_path,
    moorpy_reference,
    perturbed_reference,
    sanity,
)

TENSION_RTOL = 1e-3   # end tensions, relative
POSITION_RTOL = 1e-3  # positions, relative to the shortest line at the point
STIFFNESS_RTOL = 1e-2  # stiffness entries, relative to their block's scale
# Body rotations, rad. The buoy tilts 2.8e-3 rad; 1.5e-4 rad (0.4 mm at its fairleads) is
# 5 % of that. Its tilt comes from the legs' tension differences (1 %), which an FE
# error common to the three similar legs hardly changes; locking the rotations (a 3-DOF
# body) misses by 2.8e-3 rad, a sign error by 5.5e-3 rad.
ROT_TOL = 1.5e-4
BODY_DECKS = ["buoy_three_legs", "shared_line"]


def ref_of(name):
    return moorpy_reference(deck_path(name))


@functools.cache
def skmoor_static(name):
    """(model, eq, st) of skmoor's static equilibrium of the deck, built once per deck."""
    import skmoor
    model = skmoor.build(str(deck_path(name)))
    eq = skmoor.equilibrium(model)
    st = skmoor.static_results(model, eq)
    return model, eq, st


def length_scale(ref, pid):
    """Shortest unstretched length of the lines at point pid, m."""
    return min(ref["length"][k] for k, ends in ref["line_ends"].items() if pid in ends)


def body_length_scale(ref, bid):
    """Shortest unstretched length of the lines at the points of body bid, m."""
    pids = [p for p, kind in ref["point_kind"].items() if kind == f"body{bid}"]
    return min(length_scale(ref, p) for p in pids)


# ------------------------------------------------------------------ skmoor against MoorPy

@pytest.mark.parametrize("name", DECK_NAMES)
def test_end_tensions(name):
    """Tension at end A (anchor_tension) and end B (fairlead_tension) of every line
    within 0.1 % of MoorPy's, N."""
    ref = ref_of(name)
    _, _, st = skmoor_static(name)
    names = list(st.line_names)
    assert sorted(names) == sorted(f"line{k}" for k in ref["tension_A"])
    ids = sorted(ref["tension_A"])
    rows = [names.index(f"line{k}") for k in ids]
    TA = np.asarray(st.anchor_tension[0])[rows]
    TB = np.asarray(st.fairlead_tension[0])[rows]
    TA_ref = np.array([ref["tension_A"][k] for k in ids])
    TB_ref = np.array([ref["tension_B"][k] for k in ids])
    np.testing.assert_allclose(TA, TA_ref, rtol=TENSION_RTOL, err_msg=f"{name}: end A, lines {ids}")
    np.testing.assert_allclose(TB, TB_ref, rtol=TENSION_RTOL, err_msg=f"{name}: end B, lines {ids}")


@pytest.mark.parametrize("name", DECK_NAMES)
def test_point_positions(name):
    """Every point (fixed, free, coupled, on a body) at equilibrium within 0.1 % of the
    shortest line attached to it of MoorPy's position, m (the free points are the test;
    the others catch a point mapped to the wrong ID or a body offset lost)."""
    ref = ref_of(name)
    _, _, st = skmoor_static(name)
    names = list(st.point_names)
    assert sorted(names) == sorted(f"point{k}" for k in ref["points"])
    pos = np.asarray(st.point_reference) + np.asarray(st.point_displacement[0])
    for pid, r_ref in ref["points"].items():
        r = pos[names.index(f"point{pid}")]
        tol = POSITION_RTOL * length_scale(ref, pid)
        err = np.linalg.norm(r - r_ref)
        assert err <= tol, (f"{name}: point{pid} ({ref['point_kind'][pid]}) at {r}, MoorPy "
                            f"{r_ref}: off by {err:.3g} m > {tol:.3g} m")


@pytest.mark.parametrize("name", BODY_DECKS)
def test_body_poses(name):
    """Every body's reference point within 0.1 % of its shortest line of MoorPy's (m),
    its rotations within ROT_TOL (rad); the free buoy is the test, the coupled floaters
    must stay where the deck puts them."""
    ref = ref_of(name)
    _, _, st = skmoor_static(name)
    names = list(st.body_names)
    assert sorted(names) == sorted(f"body{k}" for k in ref["bodies"])
    for bid, r6 in ref["bodies"].items():
        i = names.index(f"body{bid}")
        x = np.asarray(st.body_reference)[i] + np.asarray(st.bodies[0])[i, :3]
        rot = np.asarray(st.bodies[0])[i, 3:]
        tol = POSITION_RTOL * body_length_scale(ref, bid)
        assert np.linalg.norm(x - r6[:3]) <= tol, (f"{name}: body{bid} at {x}, MoorPy {r6[:3]}")
        np.testing.assert_allclose(rot, r6[3:], rtol=0, atol=ROT_TOL,
                                   err_msg=f"{name}: body{bid} rotations (rad)")


@pytest.mark.parametrize("name", BODY_DECKS)
def test_mooring_stiffness(name):
    """skmoor.mooring_stiffness at each body's reference point (generalized, mooring
    alone) within 1 % of MoorPy's in the generalized convention, per 3x3 block scale
    (N/m, N/rad, N m/m, N m/rad)."""
    ref = ref_of(name)
    import skmoor
    model, eq, _ = skmoor_static(name)
    for bid, K_ref in ref["stiffness"].items():
        K = np.asarray(skmoor.mooring_stiffness(model, eq, body=f"body{bid}"))
        assert K.shape == (6, 6)
        err = block_error(K, K_ref)
        assert err <= STIFFNESS_RTOL, (
            f"{name}: body{bid} stiffness off by {err:.3g} of its block scale\n"
            f"skmoor diag {np.diag(K)}\nMoorPy diag {np.diag(K_ref)}")


# ------------------------------------------------------------------- MoorPy sanity checks

@pytest.mark.parametrize("name", DECK_NAMES)
def test_moorpy_sanity_hand_checks(name):
    """MoorPy's solution passes the hand checks of moorpy_network.sanity: independent
    elastic catenaries for every line, each line's and each free point's and free body's
    force (and moment) balance from the deck's Mass and Volume, the generalized
    stiffness against finite differences of J^T f, and its symmetry (relative errors)."""
    s = sanity(deck_path(name))
    limits = dict(catenary=1e-9, line_balance=1e-9, point_balance=1e-6, body_balance=1e-6,
                  stiffness_fd=1e-5, stiffness_symmetry=1e-9)
    bad = {k: v for k, v in s.items() if not v <= limits[k]}
    assert not bad, f"{name}: {bad}"


def test_moorpy_sanity_buoy_net_buoyancy():
    """The free buoy: the legs' vertical pulls on it add up to its net buoyancy
    (50 m^3 x 1025 - 20 t) x 9.81 = 306.56 kN; each leg pulls 100-104 kN down; it sits
    a little off centre (the legs differ) and 0.26 m below its deck position."""
    ref = ref_of("buoy_three_legs")
    net = (50.0 * 1025.0 - 20000.0) * 9.81
    pulls = np.array([ref["force_B"][k][2] for k in (1, 2, 3)])  # lines end at the buoy (B)
    assert pulls.sum() == pytest.approx(-net, rel=1e-8)
    assert np.all((-pulls > 0.9 * net / 3) & (-pulls < 1.1 * net / 3))
    r6 = ref["bodies"][1]
    assert ref["body_kind"][1] == "free"
    assert -20.4 < r6[2] < -20.1 and 0.1 < np.hypot(*r6[:2]) < 1.0
    assert 1e-3 < np.abs(r6[3:5]).max() < 1e-2


def test_moorpy_sanity_network_shapes():
    """The decks do what they say: the two-segment leg's chain lies partly on the bed and
    its junction hangs > 2 m above it; the clump hangs mid-water and the tension jumps
    there by about its 42.6 kN submerged weight; the S-line's buoy is below the surface,
    the chain sags below it and every line is in tension; the shared line sags clear of
    the bed and the floaters' legs are taut, nothing on the bed."""
    depth = 150.0
    r = ref_of("two_segment")
    assert 0 < r["on_bed"][1] < r["length"][1] and r["on_bed"][2] == 0
    assert r["points"][2][2] > -depth + 2.0
    r = ref_of("clump_weight")
    assert -90.0 < r["points"][2][2] < -20.0 and r["on_bed"][2] == 0
    hold = r["force_A"][2] + r["force_B"][1]  # both lines' forces on the clump hold it up
    assert hold[2] == pytest.approx((5000.0 - 0.64 * 1025.0) * 9.81, rel=1e-6)
    assert np.hypot(*hold[:2]) < 1e-6 * r["tension_A"][2]
    r = ref_of("s_line")
    zb = r["points"][2][2]
    assert -150.0 < zb < -10.0
    assert r["lowest_z"][2] < zb - 10.0 and r["lowest_z"][2] > -200.0 + 10.0
    assert min(r["tension_A"].values()) > 1e5 and r["on_bed"] == {1: 0.0, 2: 0.0}
    r = ref_of("shared_line")
    assert r["lowest_z"][5] > -200.0 + 50.0 and r["lowest_z"][5] < -10.0 - 20.0
    assert all(v == 0 for v in r["on_bed"].values())
    assert all(5e5 < r["tension_B"][k] < 1e6 for k in (1, 2, 3, 4))


def test_moorpy_sanity_stiffness_convention():
    """MoorPy's own stiffness differs from the generalized one by the lines' moment
    about the reference point: by far more than 1 % for the shared line's floaters
    (their lines' moment is ~2e6 N m), by less than 1 % for the free buoy (zero moment at
    equilibrium; what is left comes from its 3e-3 rad tilt). So skmoor is compared with
    the generalized matrix, and taking MoorPy's as is would be a bug the test sees."""
    for bid in (1, 2):
        r = ref_of("shared_line")
        assert block_error(r["stiffness_moorpy"][bid], r["stiffness"][bid]) > 0.05
        assert np.linalg.norm(r["moment"][bid]) > 1e6
    r = ref_of("buoy_three_legs")
    assert block_error(r["stiffness_moorpy"][1], r["stiffness"][1]) < 0.005
    assert np.linalg.norm(r["moment"][1]) < 1.0


def _fix_point(pid):
    def change(ms):
        ms.pointList[pid - 1].type = 1
    return change


def _point(pid, **values):
    def change(ms):
        for k, v in values.items():
            setattr(ms.pointList[pid - 1], k, v)
    return change


def _body(bid, **values):
    def change(ms):
        body = ms.bodyList[bid - 1]
        for k, v in values.items():
            setattr(body, k, v)
        body.nDOF = len(body.DOFs)
    return change


def _flip_weight(lid):
    def change(ms):  # the line's submerged weight with the wrong sign
        line = ms.lineList[lid - 1]
        t = dict(line.type)
        t["m"] = 2 * np.pi / 4 * t["d_vol"] ** 2 * ms.rho - t["m"]
        line.type = t
    return change


def _offset_lost(bid, pid):
    def change(ms):  # the point sits at the body's reference point
        body = ms.bodyList[bid - 1]
        body.rPointRel[body.attachedP.index(pid)] = np.zeros(3)
    return change


BUGS = {
    "two_segment: junction not released": ("two_segment", _fix_point(2)),
    "two_segment: polyester weight sign": ("two_segment", _flip_weight(2)),
    "clump_weight: clump buoyancy dropped": ("clump_weight", _point(2, v=0.0)),
    "clump_weight: clump mass dropped": ("clump_weight", _point(2, m=0.0)),
    "s_line: buoy mass dropped": ("s_line", _point(2, m=0.0)),
    "s_line: buoy buoyancy halved": ("s_line", _point(2, v=40.0)),
    "buoy_three_legs: rotations not free": ("buoy_three_legs", _body(1, DOFs=[0, 1, 2])),
    "buoy_three_legs: body mass dropped": ("buoy_three_legs", _body(1, m=0.0)),
    "shared_line: fairlead offset lost": ("shared_line", _offset_lost(1, 7)),
}


@pytest.mark.parametrize("bug", list(BUGS))
def test_moorpy_sanity_bugs_detectable(bug):
    """Each plausible bug, applied to MoorPy's model, moves a tension by more than
    TENSION_RTOL, a point or body by more than its position tolerance, or a rotation by
    more than ROT_TOL: the skmoor tests above would fail on it."""
    name, change = BUGS[bug]
    ref = ref_of(name)
    bad = perturbed_reference(deck_path(name), change)
    dT = max(abs(bad[e][k] / ref[e][k] - 1) for e in ("tension_A", "tension_B")
             for k in ref[e])
    dP = max(np.linalg.norm(bad["points"][p] - ref["points"][p])
             / (POSITION_RTOL * length_scale(ref, p)) for p in ref["points"])
    dR = max([np.abs(bad["bodies"][b][3:] - ref["bodies"][b][3:]).max() / ROT_TOL
              for b in ref["bodies"]] + [0.0])
    # by at least twice the tolerance, so an FE error of up to one tolerance cannot hide it
    assert max(dT / TENSION_RTOL, dP, dR) > 2.0, (bug, dT, dP, dR)


@pytest.mark.parametrize("name", BODY_DECKS)
def test_moorpy_sanity_arm_term_detectable(name):
    """Dropping the arm term of the rotational stiffness (the moment of the line forces
    as the arms turn, -sum H(f) H(r)) moves the stiffness far beyond 1 %."""
    ref = ref_of(name)
    for bid, K in ref["stiffness"].items():
        K_bad = K.copy()
        K_bad[3:, 3:] -= arm_stiffness(deck_path(name), bid)
        assert block_error(K_bad, K) > 10 * STIFFNESS_RTOL
