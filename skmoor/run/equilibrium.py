"""The static state a run starts from and what is read off it: the static solve with its
fall-backs, the unrestrained DOFs named, modes and Rayleigh damping, the released and
reference states, the mooring stiffness.
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass

import numpy as np

from ..bodies import body as rigid
from ..coupling.network import coupled_size, coupled_vector
from ..model.model import Model
from ..solvers.dynamics import Scheme, integrate, rayleigh_coefficients
from ..solvers.modes import Modes, eigenmodes
from ..solvers.newton import ConvergenceError, DivergenceError
from ..solvers.statics import solve_static


@dataclass
class Equilibrium:
    """Static equilibrium of a model: state x, tangent K, modes (None when the state has
    a free rigid mode, e.g. an unrestrained yaw), damping matrix C, Rayleigh (a0, a1)."""

    x: np.ndarray
    K: object
    modes: Modes | None
    C: object
    rayleigh: tuple


def static_state(system, x0=None, held=None, march=True):
    """The static solution of a System: Newton from the reference state, then with load
    continuation, then also with a vanishing tension stiffness (for slack lines), then
    (``march``) as a pseudo-transient march on the mass matrix (networks whose Newton
    wanders; the slowest attempt). held: reduced DOFs kept where x0 has them."""
    attempts = [dict(), dict(steps=8), dict(steps=8, pretension=_pretension(system))]
    attempts += [dict(relax=True, maxiter=300)] if march else []
    error = None
    for options in attempts:
        try:
            return solve_static(system, x0, held=held, **options)
        except (ConvergenceError, ValueError) as err:
            error = err
    raise ConvergenceError(f"{error}. The network has no static equilibrium near the "
                           "positions given: check the line lengths and the points' "
                           "positions, masses and volumes") from None


def unrestrained(model: Model, x=None) -> list:
    """Names of the DOFs that the static tangent at x (default: the reference state)
    does not hold (its near-null vectors), e.g. ``body1 rx``, ``point3 z``, ``line2 node 4``."""
    system = model.system
    if system.n > 3000:
        return []
    x = np.zeros(system.n) if x is None else x
    _, K, _ = system.residual(x, layout="dense")
    K = 0.5 * (K + K.T)
    w, V = np.linalg.eigh(K)
    scale = max(np.abs(w).max(initial=0.0), 1.0)
    names = dof_names(model)
    found = []
    for k in np.flatnonzero(np.abs(w) < 1e-10 * scale):
        v = np.abs(V[:, k])
        found += [names[i] for i in np.flatnonzero(v > 0.3 * v.max()) if names[i] not in found]
    return found


def dof_names(model: Model) -> list:
    """The name of each reduced DOF: ``point3 x``, ``body1 rz``, ``line2 node 4``."""
    system, network = model.system, model.network
    names = [""] * system.n
    free = iter(p.name for p in network.points if p.kind == "free")
    for columns in system.point_columns:
        name = next(free)
        for c, axis in zip(columns, "xyz"):
            names[c] = f"{name} {axis}"
    dynamic = [b.name for b in network.bodies if b.kind == "dynamic"]
    for k, name in enumerate(dynamic):
        for j, dof in enumerate(("x", "y", "z", "rx", "ry", "rz")):
            names[system.nf + 6 * k + j] = f"{name} {dof}"
    lines = model.lines
    for column in range(system.nf):
        if not names[column]:
            dof = system.free[np.flatnonzero(system.dofs.columns == column)[0]]
            slope = lines.slope_dofs is not None and dof in lines.slope_dofs
            dofs = lines.slope_dofs if slope else lines.nodal_dofs
            node = int(np.flatnonzero((dofs == dof).any(axis=1))[0])
            line = int(np.searchsorted(lines.fairlead_nodes, node))
            names[column] = (f"{lines.lines[line].name} node {node - lines.anchor_nodes[line]}"
                             + (" tangent" if slope else ""))
    return names


def _pretension(system) -> float:
    """A tension of the order of the heaviest line's weight (N), for starting Newton."""
    return max((abs(line.line_type.weight) * line.length for line in system.lines.lines),
               default=0.0) or 1.0


def steady_water(model: Model):
    """A context in which the model's sea is its steady part (:meth:`skmoor.sea.waves.Sea.steady`):
    what its static state, the static results and the stiffness about it see."""
    sea = getattr(model.network, "sea", None)
    return sea.steady() if sea is not None else contextlib.nullcontext()


def equilibrium(model: Model, n_modes: int = 12, march: bool = True) -> Equilibrium:
    """Static solve of the whole network in the sea's steady part (its currents, no waves:
    :meth:`skmoor.sea.waves.Sea.steady`), modes about it and Rayleigh damping (the settings'
    ``damping.ratio`` at the first two natural frequencies, or ``damping.alpha`` /
    ``damping.beta``). march: whether the static solve may end in its pseudo-transient
    march (see :func:`static_state`)."""
    system = model.system
    with steady_water(model):
        try:
            static = static_state(system, march=march)
        except ConvergenceError as err:
            free = unrestrained(model)
            hint = (". The deck asks for no initial-condition solve (TmaxIC = 0): "
                    "skmoor.simulate runs it from its given state (start='reference')"
                    if model.solver.get("start") == "reference" else "")
            if free:
                raise ConvergenceError(f"{err}; unrestrained at the given state: "
                                       f"{', '.join(free)} (nothing holds them statically)"
                                       f"{hint}") from None
            if hint:
                raise ConvergenceError(f"{err}{hint}") from None
            raise
    return about(model, static.x, n_modes)


def about(model: Model, x, n_modes: int = 12) -> Equilibrium:
    """The :class:`Equilibrium` record of the state x (reduced): the tangent there, modes
    and the model's Rayleigh damping about it."""
    system = model.system
    with steady_water(model):
        _, K, _ = system.residual(x)
    damping = model.damping
    ratio = float(damping.get("ratio", 0.0))
    try:
        modes = eigenmodes(K, system.M, k=n_modes)
    except ValueError:
        if ratio and "alpha" not in damping and "beta" not in damping:
            raise
        modes = None
    if "alpha" in damping or "beta" in damping:
        a0, a1 = float(damping.get("alpha", 0.0)), float(damping.get("beta", 0.0))
    elif ratio:
        a0, a1 = rayleigh_coefficients(ratio, *modes.omega[:2])
    else:
        a0 = a1 = 0.0
    C = a0 * system.M + a1 * K if (a0 or a1) else None
    return Equilibrium(x, K, modes, C, (a0, a1))


# MoorDyn's initial-condition options (MoorDyn2.cpp's defaults): its dynamic relaxation
IC_DEFAULTS = {"tmax": 120.0, "dt_check": 1.0, "threshold": 0.01}
RELAX_DAMPING = 1.0  # 1/s: mass-proportional damping of the relaxation (C = a0 M)
RELAX_CHECKS = 3  # consecutive checks within the threshold: settled


@dataclass
class Relaxation:
    """The end of a dynamic relaxation: state x, time t (s) it ran, whether the line-end
    tensions settled (``settled``), their last relative change, and why it stopped early
    (a diverging step) or None."""

    x: np.ndarray
    t: float
    settled: bool
    change: float
    stopped: str | None = None


def relaxed_state(model: Model, x0=None, *, tmax=None, dt_check=None, threshold=None,
                  dt=None, damping=RELAX_DAMPING) -> Relaxation:
    """MoorDyn's initial condition: damped dynamics from x0 (default: the reference
    state as built) with the coupled objects held where they are at t = 0, in the sea's
    steady part, until the tensions at both ends of every line change by less than
    ``threshold`` (relative) from one check to the next over RELAX_CHECKS checks
    ``dt_check`` s apart, or for ``tmax`` s (MoorDyn's TmaxIC, dtIC, threshIC; defaults:
    the model's ``solver["ic"]``, else MoorDyn's). The damping is a mass-proportional
    C = damping M (1/s) and the generalized-alpha scheme's largest numerical damping
    (rho_inf = 0), in place of MoorDyn's scaled drag (CdScaleIC); dt: the step (default:
    the model's)."""
    system, network = model.system, model.network
    ic = {**IC_DEFAULTS, **model.solver.get("ic", {})}
    tmax = float(ic["tmax"] if tmax is None else tmax)
    dt_check = float(ic["dt_check"] if dt_check is None else dt_check)
    threshold = float(ic["threshold"] if threshold is None else threshold)
    dt = float(model.solver.get("dt", 0.01) if dt is None else dt)
    dt = min(dt, tmax) if tmax > 0 else dt
    every = max(1, int(round(dt_check / dt)))
    x = np.zeros(system.n) if x0 is None else np.asarray(x0, float)
    if tmax <= 0:
        return Relaxation(x, 0.0, False, np.inf)
    given = network.motion
    if given is not None:
        held = coupled_vector(network, 0.0)
        network.motion = lambda t: held
        system.forget_prescribed()
    previous, quiet, change, t, stopped = None, 0, np.inf, 0.0, None
    system.reset_frames()
    try:
        with steady_water(model):
            for state in integrate(system, x, np.zeros(system.n), dt, tmax,
                                   C=damping * system.M, scheme=Scheme.generalized_alpha(0.0),
                                   report_every=every):
                x, t = state.x, state.t
                if state.reactions is None:
                    continue
                tension = np.concatenate([np.linalg.norm(f, axis=1) for f in state.reactions])
                if not np.all(np.isfinite(tension)):
                    stopped = "the tensions are not finite"
                    break
                if previous is not None:
                    floor = 1e-3 * max(tension.max(), previous.max(), 1e-9)
                    change = float(np.max(np.abs(tension - previous)
                                          / np.maximum(tension, floor)))
                    quiet = quiet + 1 if change < threshold else 0
                    if quiet >= RELAX_CHECKS:
                        break
                previous = tension
    except DivergenceError as err:
        stopped = str(err)
    finally:
        system.reset_frames()
        if given is not None:
            network.motion = given
            system.forget_prescribed()
    return Relaxation(np.array(x), t, quiet >= RELAX_CHECKS, change, stopped)


def relaxed_equilibrium(model: Model, why: str) -> tuple[Equilibrium, str]:
    """(start, note) when the static solve found no state (``why``): MoorDyn's dynamic
    relaxation (:func:`relaxed_state`), then a static solve from where it ends; the
    relaxed state itself when that solve fails too, or the given state (the reference
    as built) when the relaxation diverged; the note says which, in one line."""
    system = model.system
    relaxed = relaxed_state(model)
    if relaxed.stopped is None and relaxed.t > 0:
        try:
            with steady_water(model):
                x = static_state(system, relaxed.x).x
            return about(model, x), (f"static state found after a dynamic relaxation of "
                                     f"{relaxed.t:.3g} s (MoorDyn's initial condition; "
                                     f"the static solve from the given state: {why})")
        except (ConvergenceError, ValueError):
            pass
    if relaxed.stopped is None and np.all(np.isfinite(relaxed.x)) and relaxed.t > 0:
        how = ("its line tensions settled to within "
               f"{relaxed.change:.2g}" if relaxed.settled else
               f"not settled (last change in the line tensions {relaxed.change:.2g})")
        x, note = relaxed.x, (f"no static state ({why}): started from a dynamic relaxation "
                              f"of {relaxed.t:.3g} s, {how}, as MoorDyn does")
    else:
        x = np.zeros(system.n)
        note = (f"no static state ({why}) and the dynamic relaxation "
                f"{'stopped: ' + relaxed.stopped if relaxed.stopped else 'was not run'}: "
                "started from the given state")
    try:
        start = about(model, x)
    except (ValueError, ConvergenceError):
        start = Equilibrium(x, None, None, None, (0.0, 0.0))
    return start, " ".join(note.split())


def released_state(model: Model) -> np.ndarray:
    """The reduced state with the free points and dynamic bodies held where the model
    gives them and the lines in static equilibrium between them (a release from rest),
    in the sea's steady part."""
    system, network = model.system, model.network
    x0 = np.zeros(system.n)
    free = [p for p in network.points if p.kind == "free"]
    for p, columns in zip(free, system.point_columns):  # given - settled reference
        x0[columns] = network.global_position(p) - model.positions[p.name]
    # first guess: each line's end displacements spread linearly along it
    lines, u = model.lines, system.full_displacement(x0)
    dofs = lines.nodal_dofs
    for a, b in zip(lines.anchor_nodes, lines.fairlead_nodes):
        share = np.linspace(0.0, 1.0, b - a + 1)[1:-1, None]
        u[dofs[a + 1:b]] = (1 - share) * u[dofs[a]] + share * u[dofs[b]]
    x0[system.dofs.columns] = u[system.free]  # (a point's column gets its own value back)
    held = np.concatenate([system.point_columns.ravel(), np.arange(system.nf, system.n)])
    if len(np.unique(held)) == system.n:  # nothing left to settle
        return x0
    with steady_water(model):
        return static_state(system, x0, held=held.astype(int)).x


def reference_state(model: Model) -> np.ndarray:
    """The reduced state of the reference as built (x = 0: the points and bodies where
    the model puts them, each line on its catenary between them), its bending lines'
    node tangents turned to rotational balance with every position held (in the sea's
    steady part): the catenary's curvature at a pinned end would otherwise be a moment
    on a tangent of almost no rotary inertia, a start shock of ~1e4 m/s2 that the
    consistent Hermite mass passes on to the points (MoorDyn's nodes have no tangents)."""
    system, lines = model.system, model.lines
    x0 = np.zeros(system.n)
    if lines.slope_dofs is None:
        return x0
    turning = np.unique(system.dofs.columns[np.isin(system.free, lines.slope_dofs)])
    if turning.size == 0:  # every tangent clamped
        return x0
    held = np.setdiff1d(np.arange(system.n), turning)
    with steady_water(model):
        return static_state(system, x0, held=held).x


def mooring_stiffness(model: Model, eq: Equilibrium | None = None, body=None) -> np.ndarray:
    """(6, 6) stiffness of the mooring at a dynamic body's reference point about the
    static state (N/m, N/rad, N m/rad; generalized loads J^T f, q = [x, y, z, rx, ry, rz]):
    the reduced tangent condensed to that body's DOFs (every other DOF in equilibrium),
    less the body's own hydrostatics and weight, in the sea's steady part. body: its name (default: the first)."""
    eq = eq or equilibrium(model)
    system, network = model.system, model.network
    dynamic = [b.name for b in network.bodies if b.kind == "dynamic"]
    coupled = [b.name for b in network.bodies if b.kind == "coupled"]
    name = (dynamic + coupled)[0] if body is None and dynamic + coupled else body
    if name in coupled:
        with steady_water(model):
            return _coupled_stiffness(model, eq, network.body(name))
    if name not in dynamic:
        raise ValueError(f"mooring_stiffness body: {name!r} is not a dynamic or coupled "
                         f"body {dynamic + coupled}")
    k = dynamic.index(name)
    with steady_water(model):
        _, K, _ = system.residual(eq.x, layout="dense")
    keep = np.arange(system.nf + 6 * k, system.nf + 6 * k + 6)
    rest = np.setdiff1d(np.arange(system.n), keep)
    condensed = (K[np.ix_(keep, keep)]
                 - K[np.ix_(keep, rest)] @ np.linalg.solve(K[np.ix_(rest, rest)],
                                                           K[np.ix_(rest, keep)]))
    return condensed - system.K_bodies[k]


def _coupled_stiffness(model: Model, eq: Equilibrium, body, step=1e-4) -> np.ndarray:
    """-dF/dq of a coupled body by central differences: each of its DOFs moved by +-step
    (m, rad), the rest of the network solved again statically, F = sum J(q)^T f the
    generalized load of the lines' forces f on its points (J = d(point)/dq with
    R = Rz Ry Rx, as for a dynamic body)."""
    system, network = model.system, model.network
    n = network.n_coupled_dofs
    start = 0
    for obj in network.coupled:
        if obj is body:
            break
        start += coupled_size(obj)
    ends = [(k, end) for k, line in enumerate(network.lines) for end, point in
            (("a", line.a), ("b", line.b)) if network.point(point).kind == "body"
            and network.point(point).body == body.name]
    given, x = network.motion, eq.x
    K = np.zeros((6, 6))
    try:
        for j in range(6):
            loads = []
            for sign in (1.0, -1.0):
                y = np.zeros(n)
                y[start + j] = sign * step
                network.motion = lambda t, y=y: y
                system.forget_prescribed()
                x = static_state(system, x).x
                fb, fa = system.reactions(x)
                F = np.zeros(6)
                q = y[start:start + 6]
                for k, end in ends:
                    f = fb[k] if end == "b" else fa[k]
                    node = model.lines.fairlead_nodes[k] if end == "b" else model.lines.anchor_nodes[k]
                    r = model.lines.points[node] - body.position
                    F += rigid.attachment_jacobian(q, r[None, :])[0].T @ f
                loads.append(F)
            K[:, j] = -(loads[0] - loads[1]) / (2 * step)
    finally:
        network.motion = given
        system.forget_prescribed()
    return K
