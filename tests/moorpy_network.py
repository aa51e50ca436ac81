"""MoorPy reference numbers for the network decks (tests/decks/network/*.dat).

:func:`moorpy_reference` reads a MoorDyn v2 deck into MoorPy (v1.3), solves its static
equilibrium tightly and returns the numbers skmoor is validated against: end tensions,
positions of points and free bodies, and the bodies' mooring stiffness in skmoor's
generalized convention. :func:`sanity` checks those numbers by hand (force balance at
every free point and free body, an independent elastic catenary for every line, the
generalized stiffness by finite differences). moorpy is imported inside the functions
only. SI units throughout: m, N, N m, rad.

What MoorPy does with a deck (read from moorpy 1.3's ``system.py``, ``point.py``,
``body.py``, ``line.py``), and what the decks do so that it agrees with MoorDyn:

- IDs index lists: point, line and body IDs must be 1, 2, ... in file order.
- Lines: end A is AttachA, end B is AttachB. The catenary lets only the part next to
  end A lie on the bed, and only when end A is on the bed (``cb = 0``, frictionless);
  a line whose end B is the lower end, or whose end A is off the bed, is taken as
  suspended. So every line in these decks that touches the bed runs from an anchor (A).
  Submerged weight (Mass/m - rho pi Diam^2 / 4) g per unstretched metre, constant EA.
  ``TA``/``TB`` are the tension magnitudes at ends A/B, ``fA``/``fB`` the forces the line
  applies to the points at its ends.
- Points: Mass weighs m g; Volume buoys rho g V at the point, fully only when the point
  is more than 1 m below the surface (MoorPy ramps it linearly over z in [-1, 1] m;
  MoorDyn-C's Point applies it whole); a point within 2 m of the bed gets a support
  force. CdA and Ca do not enter statics. The decks keep every free point well inside
  the water column.
- Bodies: angles r0 p0 y0 in degrees; R = Rz(yaw) Ry(pitch) Rx(roll). Weight at the CG,
  buoyancy rho g Volume at the reference point (MoorDyn-C puts both at the CG); the decks
  put the CG at the reference point so the two agree. Mass, Volume, CdA, Ca of a body do
  not enter its mooring stiffness here (``lines_only=True``). A 'Free' body is 6 free
  DOFs, 'Coupled' is held where the deck puts it. Points attached to 'BodyN' carry
  coordinates relative to the body's reference point, in body axes.
- Options: g, rho, WtrDpth are read (OPTIONS comes last in the file, after MoorPy has
  already computed the line types' 'w' with its defaults 1025 / 9.81; the statics use
  the system's rho and g, so the decks keep 1025 and 9.81 to leave no doubt).

Stiffness. MoorPy's analytic body stiffness (``Body.getStiffnessA(lines_only=True)``,
the lines with their far ends held; ``System.getCoupledStiffnessA(lines_only=True)``
condenses free points and free bodies out, Guyan) is K_mp = -d(f, M)/d(x, phi): f the
lines' force on the body, M = sum r_i x f_i their moment about the body's reference
point in global axes, phi a small rotation about the global axes. skmoor's generalized
stiffness is K = -dQ/dq with Q = J^T f = (f, T(q)^T M), q = (x, y, z, rx, ry, rz) the
Euler angles of R = Rz Ry Rx and T = [Rz Ry e_x, Rz e_y, e_z] the map from angle rates to
angular velocity. Therefore

    K_tt = K_mp,tt,  K_tr = K_mp,tr T,  K_rt = T^T K_mp,rt,
    K_rr = T^T K_mp,rr T - E,  E[k, j] = M . dT[:, k]/dq_j,

and at q = 0 (T = I) E = [[0, -Mz, My], [0, 0, -Mx], [0, 0, 0]]. K is symmetric (the
Hessian of the lines' energy); K_mp is not: its rotational block carries + [M]x / 2
(the 'asymmetric moment terms'). Where the lines' moment about the reference point
vanishes (the free buoy at equilibrium) the two coincide; where it does not (the shared
line's coupled bodies) they differ by O(|M|) in the rotational block. The translational
block is convention independent. ``reference['stiffness']`` is K (generalized, mooring
alone, no hydrostatics of the body), ``reference['stiffness_moorpy']`` is K_mp.

Only the 6x6 diagonal block of each body is used: in moorpy 1.3's
``getSystemStiffnessA`` the rotation-rotation block coupling two bodies through a shared
line is transposed (``H2 KB H1^T`` where finite differences give ``H1^T KB H2``; checked
on shared_line.dat), and it also pairs a body's points with free points using
``point1.attachedEndB == 1`` (a list against 1, always False), harmless while the lines'
cross stiffness KBA is symmetric.
"""
from __future__ import annotations

import contextlib
import functools
import io
from pathlib import Path

import numpy as np

DECKS = Path(__file__).parent / "decks" / "network"
DECK_NAMES = ["two_segment", "clump_weight", "s_line", "buoy_three_legs", "shared_line"]

EQ_TOL = 1e-7    # m: MoorPy's equilibrium tolerance on positions (its line solves get 1e-9 m)
CAT_TOL = 1e-10  # m: catenary tolerance for the final solve of every line


def deck_path(name):
    """Path of a network deck by its stem ('two_segment', ...)."""
    return DECKS / f"{name}.dat"


def _quiet(fn, *args, **kwargs):
    """Call fn with MoorPy's prints swallowed."""
    with contextlib.redirect_stdout(io.StringIO()):
        return fn(*args, **kwargs)


def load_system(path, change=None):
    """A MoorPy System of the deck, initialized and in static equilibrium (positions to
    EQ_TOL m), every line solved again to CAT_TOL m. change(ms), if given, is applied
    to the initialized system before the equilibrium solve (see perturbed_reference)."""
    import moorpy as mp

    ms = _quiet(mp.System, file=str(path))
    for kind, objs in (("point", ms.pointList), ("line", ms.lineList), ("body", ms.bodyList)):
        ids = [o.number for o in objs]
        if ids != list(range(1, len(ids) + 1)):
            raise ValueError(f"{path}: {kind} IDs {ids} are not 1..n in order (MoorPy "
                             "indexes its lists by ID)")
    _quiet(ms.initialize)
    if change is not None:
        change(ms)
        _quiet(ms.initialize)
    _quiet(ms.solveEquilibrium, tol=EQ_TOL, maxIter=5000)
    for line in ms.lineList:
        line.staticSolve(tol=CAT_TOL, profiles=1)
    return ms


def point_kinds(ms):
    """{point ID: 'fixed' | 'free' | 'coupled' | 'bodyN'}."""
    kinds = {}
    for p in ms.pointList:
        kinds[p.number] = {1: "fixed", 0: "free", -1: "coupled"}[p.type]
    for b in ms.bodyList:
        for pid in b.attachedP:
            kinds[pid] = f"body{b.number}"
    return kinds


def line_ends(ms):
    """{line ID: (point ID at end A, point ID at end B)}."""
    ends = {line.number: [None, None] for line in ms.lineList}
    for p in ms.pointList:
        for lid, endB in zip(p.attached, p.attachedEndB):
            ends[lid][int(endB)] = p.number
    return {k: tuple(v) for k, v in ends.items()}


def line_weight(ms, line):
    """Submerged weight per unstretched metre, N/m, from the deck's Mass/m and Diam."""
    t = line.type
    return (t["m"] - ms.rho * np.pi / 4 * t["d_vol"] ** 2) * ms.g


# ------------------------------------------------------------------ generalized stiffness

def _rotation(q3):
    from moorpy.helpers import rotationMatrix
    return rotationMatrix(*q3)


def angular_rate_map(q3):
    """T(q): angular velocity (global axes) = T dq/dt for R = Rz Ry Rx, q = (rx, ry, rz)."""
    from moorpy.helpers import rotationMatrix
    Rz = rotationMatrix(0.0, 0.0, q3[2])
    Ry = rotationMatrix(0.0, q3[1], 0.0)
    return np.column_stack([Rz @ Ry @ [1.0, 0, 0], Rz @ [0, 1.0, 0], [0, 0, 1.0]])


def generalized_from_moorpy(K_mp, M, q3, h=1e-6):
    """skmoor's generalized 6x6 stiffness d(J^T f)/dq (sign: restoring positive) from
    MoorPy's K_mp = -d(f, M)/d(x, phi) at Euler angles q3, M the lines' moment about the
    reference point (global axes). See the module docstring."""
    T = angular_rate_map(q3)
    K = np.array(K_mp, float).copy()
    K[:3, 3:] = K_mp[:3, 3:] @ T
    K[3:, :3] = T.T @ K_mp[3:, :3]
    E = np.zeros((3, 3))
    for j in range(3):
        dq = np.zeros(3)
        dq[j] = h
        dT = (angular_rate_map(q3 + dq) - angular_rate_map(q3 - dq)) / (2 * h)
        E[:, j] = dT.T @ M
    K[3:, 3:] = T.T @ K_mp[3:, 3:] @ T - E
    return K


def _body_line_forces(ms, body):
    """Lines' force on each attached point of the body, (n, 3) N, global axes."""
    return np.array([ms.pointList[pid - 1].getForces(lines_only=True, xyz=True)
                     for pid in body.attachedP])


def generalized_force(ms, body):
    """Q = sum_i J_i^T f_i of the lines on the body at its current pose, J_i = dp_i/dq the
    Jacobian of the attachment point p_i = x + R(q) r_i: (f, T^T M), N and N m."""
    f = _body_line_forces(ms, body)
    R = _rotation(body.r6[3:])
    arms = np.array([R @ r for r in body.rPointRel])
    M = np.cross(arms, f).sum(axis=0)
    return np.concatenate([f.sum(axis=0), angular_rate_map(body.r6[3:]).T @ M])


def stiffness_fd(ms, body_id, h=1e-4, hr=1e-5):
    """Generalized mooring stiffness of body body_id by central differences of
    Q = J^T f (lines only) in q = (x, y, z, rx, ry, rz): the body held at q0 +- h e_j,
    every other free object re-equilibrated, every line solved to CAT_TOL. 6x6, SI."""
    body = ms.bodyList[body_id - 1]
    q0 = body.r6.copy()
    type0 = body.type
    free_others = ms.getDOFs()[0] - (body.nDOF if type0 == 0 else 0)
    body.type = 1
    saved = [(b, b.r6.copy()) for b in ms.bodyList] + [(p, p.r.copy()) for p in ms.pointList]

    def Q(q):
        body.setPosition(q)
        if free_others:
            _quiet(ms.solveEquilibrium, tol=EQ_TOL, maxIter=5000)
        for line in ms.lineList:
            line.staticSolve(tol=CAT_TOL)
        return generalized_force(ms, body)

    K = np.zeros((6, 6))
    try:
        for j in range(6):
            dq = np.zeros(6)
            dq[j] = h if j < 3 else hr
            K[:, j] = -(Q(q0 + dq) - Q(q0 - dq)) / (2 * dq[j])
    finally:
        body.type = type0
        for obj, r in saved:
            obj.setPosition(r)
        for line in ms.lineList:
            line.staticSolve(tol=CAT_TOL, profiles=1)
    return K


def moorpy_stiffness(ms, body_id):
    """MoorPy's analytic mooring stiffness K_mp of body body_id (6x6, about its reference
    point, global axes, lines only): System.getCoupledStiffnessA(lines_only=True) with
    this body made coupled for the call (free points / other free bodies condensed out,
    other coupled bodies held), its 6x6 diagonal block."""
    body = ms.bodyList[body_id - 1]
    type0 = body.type
    body.type = -1
    try:
        K_all = _quiet(ms.getCoupledStiffnessA, lines_only=True)
    finally:
        body.type = type0
    i = 0
    for b in ms.bodyList:  # coupled DOFs: coupled bodies in order, then coupled points
        if b is body:
            return K_all[i:i + 6, i:i + 6]
        if b.type == -1:
            i += b.nDOF


def arm_stiffness(path, body_id):
    """The part of MoorPy's rotational stiffness of body body_id that comes from the
    moment arms turning under the line forces, -sum H(f_i) H(r_i) (MoorPy's H(r) v =
    v x r), 3x3 N m/rad: what a model that forgets the arms rotate would drop."""
    from moorpy.helpers import getH
    ms = load_system(path)
    body = ms.bodyList[body_id - 1]
    R = _rotation(body.r6[3:])
    K = np.zeros((3, 3))
    for pid, r in zip(body.attachedP, body.rPointRel):
        f = ms.pointList[pid - 1].getForces(xyz=True)
        K -= getH(f) @ getH(R @ r)
    return K


# ---------------------------------------------------------------------------- reference

@functools.cache
def moorpy_reference(path):
    """MoorPy's static solution of the MoorDyn deck at path, keyed by MoorDyn IDs:

    - 'tension_A', 'tension_B': {line ID: tension at end A / end B, N}
    - 'force_A', 'force_B': {line ID: force of the line on the point at end A / B, (3,) N}
    - 'line_ends': {line ID: (point ID at A, point ID at B)}, 'length': {line ID: L, m},
      'on_bed': {line ID: length lying on the bed, m}, 'lowest_z': {line ID: z of the
      line's lowest point, m}
    - 'points': {point ID: position at equilibrium, (3,) m} (every point),
      'point_kind': {point ID: 'fixed' | 'free' | 'coupled' | 'bodyN'},
      'free_points': [IDs of the free points]
    - 'bodies': {body ID: (x, y, z, rx, ry, rz) of the reference point, m and rad},
      'body_kind': {body ID: 'free' | 'coupled' | 'fixed'}
    - 'stiffness': {body ID: 6x6 generalized mooring stiffness at the reference point}
      (see the module docstring; N/m, N/rad, N m/m, N m/rad), 'stiffness_moorpy': the same
      in MoorPy's convention, 'moment': {body ID: lines' moment about the reference
      point, (3,) N m, global axes}, 'force': {body ID: lines' force, (3,) N}
    - 'depth', 'rho', 'g'

    Cached per path; returns plain numbers (no MoorPy objects)."""
    ms = load_system(path)
    ref = dict(depth=ms.depth, rho=ms.rho, g=ms.g,
               tension_A={}, tension_B={}, force_A={}, force_B={}, length={}, on_bed={},
               lowest_z={},
               line_ends=line_ends(ms), points={}, point_kind=point_kinds(ms),
               bodies={}, body_kind={}, stiffness={}, stiffness_moorpy={}, moment={},
               force={})
    for line in ms.lineList:
        ref["tension_A"][line.number] = float(line.TA)
        ref["tension_B"][line.number] = float(line.TB)
        ref["force_A"][line.number] = np.array(line.fA, float)
        ref["force_B"][line.number] = np.array(line.fB, float)
        ref["length"][line.number] = float(line.L)
        ref["on_bed"][line.number] = float(line.LBot)
        ref["lowest_z"][line.number] = float(min(line.z_extreme, line.rA[2], line.rB[2]))
    for p in ms.pointList:
        ref["points"][p.number] = np.array(p.r, float)
    ref["free_points"] = [k for k, v in ref["point_kind"].items() if v == "free"]
    for b in ms.bodyList:
        ref["bodies"][b.number] = np.array(b.r6, float)
        ref["body_kind"][b.number] = {1: "fixed", 0: "free", -1: "coupled"}[b.type]
        f6 = b.getForces(lines_only=True, all_DOFs=True)
        ref["force"][b.number], ref["moment"][b.number] = f6[:3].copy(), f6[3:].copy()
        K_mp = moorpy_stiffness(ms, b.number)
        ref["stiffness_moorpy"][b.number] = K_mp
        ref["stiffness"][b.number] = generalized_from_moorpy(K_mp, f6[3:], b.r6[3:])
    return ref


# ------------------------------------------------------------------------------- checks

def catenary_span(H, VF, L, EA, w, on_bed):
    """End B relative to end A, (horizontal, vertical) m, of an elastic catenary with
    horizontal tension H and vertical tension VF at end B (N), unstretched length L,
    axial stiffness EA, submerged weight w per unstretched metre. on_bed: end A on a
    frictionless bed and the line lying on it from A (then VF < w L)."""
    if on_bed:
        Lb = L - VF / w
        x = Lb + H / w * np.arcsinh(VF / H) + H * L / EA
        z = H / w * (np.sqrt(1 + (VF / H) ** 2) - 1) + VF ** 2 / (2 * EA * w)
    else:
        VA = VF - w * L
        x = H / w * (np.arcsinh(VF / H) - np.arcsinh(VA / H)) + H * L / EA
        z = (H / w * (np.sqrt(1 + (VF / H) ** 2) - np.sqrt(1 + (VA / H) ** 2))
             + (VF ** 2 - VA ** 2) / (2 * EA * w))
    return x, z


def sanity(path):
    """Hand checks of MoorPy's solution of the deck; returns {check: worst relative
    error}. The checks (each should be ~1e-8 or less):

    - 'catenary': per line, the end-to-end vector from an independent elastic catenary
      (H, V at end B from MoorPy's fB) against the actual ends, over L;
    - 'line_balance': per line, fA + fB + w (L - L_bed) e_z = 0 (and no horizontal force
      from a frictionless bed), over the line's tension;
    - 'point_balance': per free point, sum of line end forces + (rho V - m) g e_z = 0
      with the deck's Mass and Volume (full buoyancy), over the largest tension there;
    - 'body_balance': per free body, the lines' force + (rho V - m) g e_z = 0 and the
      lines' moment about the reference point (CG and buoyancy there) = 0, over the
      legs' tensions (times the largest arm for the moment);
    - 'stiffness_fd': per body, the generalized stiffness from the analytic MoorPy
      matrix against central differences of J^T f, per 3x3 block over its scale
      (:func:`block_scales`);
    - 'stiffness_symmetry': the generalized stiffness's asymmetry, same scaling.
    """
    ms = load_system(path)
    ref = moorpy_reference(path)
    out = {}
    # lines: independent catenary, and each line's own balance
    cat, bal = 0.0, 0.0
    for line in ms.lineList:
        w = line_weight(ms, line)
        d = line.rB - line.rA
        horiz = np.hypot(d[0], d[1])
        e_h = np.array([d[0], d[1], 0.0]) / horiz
        H, VF = -line.fB @ e_h, -line.fB[2]
        on_bed = line.rA[2] <= -ms.depth + 1e-9 and VF < w * line.L
        x, z = catenary_span(H, VF, line.L, line.EA, w, on_bed)
        cat = max(cat, np.hypot(x - horiz, z - d[2]) / line.L)
        suspended = line.L - (line.LBot if on_bed else 0.0)
        resid = line.fA + line.fB + np.array([0, 0, w * suspended])
        bal = max(bal, np.linalg.norm(resid) / max(line.TA, line.TB))
        if not on_bed and line.LBot > 0:
            raise AssertionError(f"line {line.number}: MoorPy lays {line.LBot} m on the bed "
                                 "although end A is off it")
    out["catenary"], out["line_balance"] = cat, bal
    # free points
    worst = 0.0
    for p in ms.pointList:
        if p.type != 0:
            continue
        f = np.array([0.0, 0.0, (ms.rho * p.v - p.m) * ms.g])
        T = 0.0
        for lid, endB in zip(p.attached, p.attachedEndB):
            line = ms.lineList[lid - 1]
            f += line.fB if endB else line.fA
            T = max(T, line.TB if endB else line.TA)
        worst = max(worst, np.linalg.norm(f) / T)
    out["point_balance"] = worst
    # free bodies
    worst = 0.0
    for b in ms.bodyList:
        if b.type != 0:
            continue
        assert np.allclose(b.rCG, 0) and np.allclose(b.rM, 0)
        f = _body_line_forces(ms, b)
        R = _rotation(b.r6[3:])
        arms = np.array([R @ r for r in b.rPointRel])
        T = np.linalg.norm(f, axis=1).max()
        F = f.sum(axis=0) + [0, 0, (ms.rho * b.v - b.m) * ms.g]
        M = np.cross(arms, f).sum(axis=0)
        worst = max(worst, np.linalg.norm(F) / T,
                    np.linalg.norm(M) / (T * np.linalg.norm(arms, axis=1).max()))
    out["body_balance"] = worst
    # stiffness
    fd, sym = 0.0, 0.0
    for b in ms.bodyList:
        K = ref["stiffness"][b.number]
        K_fd = stiffness_fd(ms, b.number)
        fd = max(fd, block_error(K_fd, K))
        sym = max(sym, block_error(K.T, K))
    out["stiffness_fd"], out["stiffness_symmetry"] = fd, sym
    return out


def block_scales(K):
    """6x6 array of scales for K's entries: for the block (a, b) of the 3x3 blocks
    a, b in (translation, rotation), sqrt(max |diag K_aa| max |diag K_bb|), i.e. the
    largest diagonal entry of the diagonal blocks and their geometric mean (same units)
    for the coupling blocks."""
    d = np.abs(np.diag(K))
    s = np.array([d[:3].max(), d[3:].max()])
    S = np.sqrt(np.outer(s, s))
    return np.kron(S, np.ones((3, 3)))


def block_error(K, K_ref):
    """Largest |K - K_ref| entry over K_ref's block scales (:func:`block_scales`)."""
    return float(np.max(np.abs(np.asarray(K) - K_ref) / block_scales(K_ref)))


# ----------------------------------------------------------- perturbed decks (bug models)

def perturbed_reference(path, change):
    """MoorPy's tensions and point / body positions after change(ms) (a plausible bug
    applied to the loaded system at the deck's positions, e.g. a point's Volume dropped
    or a free point held where the deck puts it) and a new equilibrium:
    {'tension_A', 'tension_B', 'points', 'bodies'} as in :func:`moorpy_reference`."""
    ms = load_system(path, change)
    return dict(tension_A={l.number: float(l.TA) for l in ms.lineList},
                tension_B={l.number: float(l.TB) for l in ms.lineList},
                points={p.number: np.array(p.r, float) for p in ms.pointList},
                bodies={b.number: np.array(b.r6, float) for b in ms.bodyList})
