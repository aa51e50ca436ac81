"""Set the peers (MoorPy, MoorDyn) up on skmoor's numbers, for the side-by-side tests.

Nothing here imports moorpy or moordyn at module level: the test files skip cleanly
(``pytest.importorskip``) on a machine without them.
"""
from __future__ import annotations

import numpy as np
from scipy.optimize import brentq, root

# ----------------------------------------------------------------------- skmoor side

def condensed_line_stiffness(system, x):
    """6x6 mooring stiffness of the lines at the body, N/m, N, N m: the reduced tangent
    at x condensed to the body DOFs (K_bb - K_bf K_ff^-1 K_fb), minus the body's own
    hydrostatic stiffness. Generalized loads J^T f about the reference point."""
    _, K, _ = system.residual(x)
    K = K.toarray()
    nf = system.nf
    Kff, Kfb, Kbf, Kbb = K[:nf, :nf], K[:nf, nf:], K[nf:, :nf], K[nf:, nf:]
    return Kbb - Kbf @ np.linalg.solve(Kff, Kfb) - system.K_body


def condensed_fairlead_stiffness(system, x):
    """3x3 stiffness of a one-line System at its fairlead (fairleads='fixed' or
    'prescribed'), N/m: d(internal - external force at the fairlead)/d(fairlead motion)
    with the free nodes in equilibrium."""
    u = system.full_displacement(x)
    _, K, _ = system.line_residual(u, None)
    K = K.toarray()
    free, fair = system.free, system.fairlead_dofs.ravel()
    return (K[np.ix_(fair, fair)]
            - K[np.ix_(fair, free)] @ np.linalg.solve(K[np.ix_(free, free)], K[np.ix_(free, fair)]))


def amplitude(t, y, t_from):
    """Half the peak-to-peak of y over t >= t_from."""
    window = y[np.asarray(t) >= t_from - 1e-9]
    return 0.5 * (window.max() - window.min())


# ----------------------------------------------------------------------- MoorPy

def moorpy_system(model, q=None, tol=1e-12):
    """MoorPy System of a built skmoor model: depth, water and line types from the case,
    a coupled Body at the reference point displaced by q, anchors and fairleads at the
    catenaries' positions, unstretched lengths catenaries[k].L. Returns (system, body).

    Each line is solved again with a tight catenary tolerance: MoorPy's default
    (1e-4 m) moves the fairlead tension of these stiff steel lines by ~1e-5."""
    import moorpy as mp

    from skmoor.model.from_case import line_type

    case = model.case
    q = np.zeros(6) if q is None else np.asarray(q, float)
    ms = mp.System(depth=case.water["depth"], rho=case.water["density"], g=case.water["gravity"])
    for name in {spec.type for spec in case.line_specs()}:
        lt = line_type(case, name)
        # MoorPy computes the submerged weight w = (m - rho pi d_vol^2 / 4) g itself
        ms.setLineType(name=name, lineType=dict(m=lt.mass, d_vol=lt.diameter, EA=lt.EA))
    ref = model.body.reference_point
    body = ms.addBody(-1, np.r_[ref + q[:3], q[3:]])
    for spec, cat in zip(case.line_specs(), model.catenaries):
        anchor = ms.addPoint(1, cat.anchor)
        fairlead = ms.addPoint(1, cat.fairlead - ref, body=1)
        ms.addLine(cat.L, spec.type, pointA=anchor.number, pointB=fairlead.number)
    ms.initialize()
    for line in ms.lineList:
        line.staticSolve(tol=tol, profiles=1)
    for point in ms.pointList:
        point.getForces()
    return ms, body


# ----------------------------------------------------------------------- MoorDyn

def lumped_chain(L, n, w, EA, span, rise, H0, V0):
    """Statics of MoorDyn's discrete line: n straight segments of unstretched length
    L/n, tension EA * engineering strain, weight w L/n lumped at each inner node (the
    end nodes' halves go to the end points). Returns (H, V of the first segment, V of
    the last segment), N, for the ends (span, rise) apart in the line's vertical plane."""
    l0, W = L / n, w * L / n
    scale = np.hypot(H0, V0)

    def mismatch(z):
        H, V = z * scale
        Vs = V + W * np.arange(n)
        T = np.hypot(H, Vs)
        lengths = l0 * (1 + T / EA)
        return np.array([np.sum(lengths * H / T) - span, np.sum(lengths * Vs / T) - rise]) / span

    sol = root(mismatch, [H0 / scale, V0 / scale], tol=1e-15)
    H, V = sol.x * scale
    return H, V, V + W * (n - 1)


def chain_fairlead_force(cat, n, L=None):
    """|force| (N) of MoorDyn's n-segment chain on its fairlead (last segment's pull plus
    the fairlead node's half-segment weight), between the ends of catenary ``cat``."""
    L = cat.L if L is None else L
    d = cat.fairlead - cat.anchor
    H, _, V = lumped_chain(L, n, cat.w, cat.EA, np.hypot(d[0], d[1]), d[2], cat.H, cat.V_anchor)
    return float(np.hypot(H, V + 0.5 * cat.w * L / n))


def chain_length_for(cat, n, force):
    """Unstretched length (m) whose n-segment chain pulls on the fairlead with ``force``
    (N). MoorDyn's segments are chords of the catenary: with the catenary's own L its
    chain hangs slacker (by 0.34 % in tension at 11 segments for the paper's line)."""
    return brentq(lambda L: chain_fairlead_force(cat, n, L) - force,
                  cat.L * (1 - 1e-3), cat.L * (1 + 1e-3), xtol=1e-13 * cat.L)


def moordyn_deck(path, *, anchor, fairlead, line_type, length, n_segments, BA, dt,
                 depth, rho, g, tmax_ic=100.0, thresh_ic=1e-9):
    """Write a MoorDyn v2 input file: one line from a fixed anchor to a coupled
    fairlead, no drag (Cd = CdAx = 0), no added mass (Ca = CaAx = 0), no bending,
    internal damping BA (N s), time step dt (s). Returns the path."""
    num = lambda v: repr(float(v))  # noqa: E731  (numpy 2 scalars repr as np.float64(...))
    a, f = [num(v) for v in anchor], [num(v) for v in fairlead]
    text = f"""skmoor side-by-side test: one line, written by tests/peers.py
---------------------- LINE TYPES ----------------------------------
TypeName  Diam  Mass/m  EA  BA/-zeta  EI  Cd  Ca  CdAx  CaAx
(name)  (m)  (kg/m)  (N)  (N-s/-)  (N-m^2)  (-)  (-)  (-)  (-)
line  {num(line_type.diameter)}  {num(line_type.mass)}  {num(line_type.EA)}  {num(BA)}  0  0  0  0  0
---------------------- POINTS --------------------------------------
ID  Attachment  X  Y  Z  Mass  Volume  CdA  Ca
(#)  (word)  (m)  (m)  (m)  (kg)  (m^3)  (m^2)  (-)
1  Fixed  {a[0]}  {a[1]}  {a[2]}  0  0  0  0
2  Coupled  {f[0]}  {f[1]}  {f[2]}  0  0  0  0
---------------------- LINES ---------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)  (#)  (#)  (m)  (-)  (-)
1  line  1  2  {num(length)}  {int(n_segments)}  -
---------------------- OPTIONS -------------------------------------
0  writeLog
{num(dt)}  dtM
{num(g)}  g
{num(rho)}  rho
{num(depth)}  WtrDpth
{num(tmax_ic)}  TmaxIC
{thresh_ic:g}  threshIC
1  disableOutput
1  disableOutTime
---------------------- OUTPUTS -------------------------------------
---------------------- END -----------------------------------------
"""
    with open(path, "w") as out:
        out.write(text)
    return path


def faded_sine(amplitude, omega, fade, direction):
    """(displacement, velocity) of a point driven amplitude sin(omega t) along direction,
    faded in over ``fade`` s by (1 - cos(pi t / fade)) / 2: fn(t) -> (3,), m and m/s."""
    def ramp(t):
        if t >= fade:
            return 1.0, 0.0
        return (0.5 * (1 - np.cos(np.pi * t / fade)),
                0.5 * np.pi / fade * np.sin(np.pi * t / fade))

    def displacement(t):
        return amplitude * ramp(t)[0] * np.sin(omega * t) * direction

    def velocity(t):
        f, df = ramp(t)
        return amplitude * (df * np.sin(omega * t) + f * omega * np.cos(omega * t)) * direction

    return displacement, velocity

