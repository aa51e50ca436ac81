"""From a network to the System that solves it: each line's reference state (a catenary
between its ends, free points settled first), the DOF slots of points and bodies, pins
and smooth joints.
"""
from __future__ import annotations

import copy

import numpy as np

from ..bodies.motion import Motion
from ..lines.catenary import solve_catenary
from ..lines.line import Line, LineSet, LineType
from ..sea.hydro import line_terms
from ..sea.seabed import seabed_term
from ..sea.surface import SurfaceTerm
from ..sea.viv import vortex_lift_term
from .checks import carries_strain
from .network import (
    _LINEAR,
    PINS,
    Body,
    MooringLine,
    Network,
    Point,
    coupled_offsets,
    coupled_vector,
)
from .no_lines import NoLines
from .system import Ends, PointMass, System


def _on_bed(z, seabed_z, scale):
    return seabed_z is not None and abs(z - seabed_z) <= 1e-6 * max(scale, 1.0)


def line_catenary(line_type: LineType, length, a, b, seabed_z=None):
    """(catenary, flipped) of a weighted line between a and b (m): the elastic catenary
    solved from its lower end (with touchdown when that end is on the bed at seabed_z),
    flipped = True when that is end b; None when there is none (weightless or buoyant,
    or slack on the bed)."""
    w = line_type.weight
    if w <= 0:
        return None, False
    flipped = b[2] < a[2]
    low, high = (b, a) if flipped else (a, b)
    bed = seabed_z if _on_bed(low[2], seabed_z, length) else None
    try:
        cat = solve_catenary(low, high, w, line_type.EA, length=length, seabed_z=bed,
                             law=line_type.law)
    except ValueError:
        return None, flipped
    return cat, flipped


def reference_line(name, line_type: LineType, length, n_elements, a, b, seabed_z=None):
    """(Line from a to b, its analytic catenary or None): the line's reference state."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    cat, flipped = line_catenary(line_type, length, a, b, seabed_z)
    if cat is not None:
        line = Line.from_catenary(cat, line_type, n_elements, name=name)
        return (line.reversed() if flipped else line), cat
    chord = float(np.linalg.norm(b - a))
    if chord == 0:
        raise ValueError(f"line {name}: both ends at the same place {a}")
    if chord >= length:  # straight and taut, tension of the strain (stretch - 1)
        stretch = chord / length
        if stretch > 1.5 and not carries_strain(line_type, stretch - 1.0):
            raise ValueError(f"line {name}: its ends are {chord:.6g} m apart, {100 * (stretch - 1):.3g} % "
                             f"beyond its length {length:.6g} m")
        s = np.linspace(0.0, chord, n_elements + 1)
        X = a + s[:, None] / chord * (b - a)
        tangent = (b - a) / chord
        T = _taut_tension(line_type, stretch)
        return Line(name, line_type, s, X, lambda sq: np.broadcast_to(tangent, np.shape(sq) + (3,)),
                    lambda sq: np.full(np.shape(sq), T),
                    lambda sq: np.full(np.shape(sq), stretch)), None
    if line_type.weight < 0:  # buoyant and slack: the catenary upside down
        upside, _ = reference_line(name, _upside_down(line_type), length, n_elements,
                                   a * MIRROR, b * MIRROR)
        return _mirrored(upside, line_type), None
    return Line.from_polyline(_sagging(a, b, length, n_elements, line_type.weight, seabed_z),
                              line_type, name=name), None


MIRROR = np.array([1.0, 1.0, -1.0])  # z -> -z: a buoyant line's catenary hangs upside down


def _upside_down(line_type: LineType) -> LineType:
    """The line type of the mirrored problem: the same line weighing what it buoys (N/m)."""
    return LineType(line_type.EA, line_type.mass, line_type.diameter, weight=-line_type.weight,
                    rho_water=line_type.rho_water, g=line_type.g, law=line_type.law)


def _mirrored(line: Line, line_type: LineType) -> Line:
    """A reference Line mirrored in z (positions and tangents), of ``line_type``."""
    tangent, ends = line.tangent, line.end_tangents
    return Line(line.name, line_type, line.s, line.X * MIRROR,
                lambda sq: tangent(sq) * MIRROR, line.tension, line.stretch,
                tuple(None if t is None else t * MIRROR for t in ends))


def _taut_tension(line_type: LineType, stretch):
    """Tension (N) of a straight line stretched by ``stretch`` (its static law)."""
    law = line_type.law or _LINEAR
    return float(law.static_tension(stretch - 1.0, line_type.EA))


def _sagging(a, b, length, n, weight, seabed_z):
    """A stress-free polyline of ``length`` (m) from a to b, sagging down (up for a buoyant
    line) as a parabola, kept above the bed: the slack line's first guess. A (nearly)
    vertical chord bows sideways instead (a sag along the chord would fold the line onto
    itself, a state tension-only elements cannot leave). A line too long to sag onto the
    bed (its ends nearer than its length along the bed and up) bows sideways in plan as
    well, across its chord, to take up the rest."""
    t = np.linspace(0.0, 1.0, n + 1)[:, None]
    bow = 4 * t * (1 - t)
    direction = np.array([0.0, 0.0, 1.0 if weight < 0 else -1.0])
    chord = (b - a) / np.linalg.norm(b - a)
    if abs(chord[2]) > 0.9:
        side = np.cross(chord, [0.0, 1.0, 0.0])
        direction = side / np.linalg.norm(side)
    across = np.cross(chord, [0.0, 0.0, 1.0])  # horizontal, across the chord in plan
    across = across / np.linalg.norm(across) if np.linalg.norm(across) > 1e-9 else np.eye(3)[1]

    def shape(d, w=0.0):
        X = a + t * (b - a) + d * bow * direction + w * bow * across
        if seabed_z is not None:
            X[:, 2] = np.maximum(X[:, 2], seabed_z)
        return X

    def excess(d, w=0.0):
        return np.linalg.norm(np.diff(shape(d, w), axis=0), axis=1).sum() - length

    def bisect(f):  # the root of the increasing f on [0, length]
        low, high = 0.0, length
        for _ in range(200):
            mid = 0.5 * (low + high)
            low, high = (mid, high) if f(mid) < 0 else (low, mid)
            if high - low < 1e-12 * length:
                break
        return high

    if excess(length) < 0:  # the bed stops the sag: the rest bows across in plan
        return shape(length, bisect(lambda w: excess(length, w)))
    return shape(bisect(excess))


def line_end_forces(line_type: LineType, length, a, b, seabed_z=None):
    """(f_a, f_b): static forces (N) the line exerts on its ends at a and b, from the
    analytic catenary, a taut weightless line, or (slack) half its weight at each end."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    cat, flipped = line_catenary(line_type, length, a, b, seabed_z)
    if cat is not None:
        f_low, f_high = cat.anchor_force(), cat.fairlead_force()
        return (f_high, f_low) if flipped else (f_low, f_high)
    chord = np.linalg.norm(b - a)
    if line_type.weight < 0 and chord < length:  # buoyant and slack: mirror the catenary
        fa, fb = line_end_forces(_upside_down(line_type), length, a * MIRROR, b * MIRROR)
        return fa * MIRROR, fb * MIRROR
    if chord >= length:
        pull = _taut_tension(line_type, chord / length) * (b - a) / chord
        half = np.array([0.0, 0.0, -0.5 * line_type.weight * length])
        return pull + half, -pull + half
    half = np.array([0.0, 0.0, -0.5 * line_type.weight * length])
    return half, half.copy()


def settle_points(network: Network) -> dict:
    """Free-point positions (m) where the analytic line end forces balance each point's
    net buoyancy (the catenary-network first guess; bodies held where they are given).
    Returns {name: position}; the given positions where the solve does not converge (and
    a line in ``network.notes`` says so)."""
    free = [p for p in network.points if p.kind == "free"]
    given = {p.name: network.global_position(p) for p in network.points}
    if not free:
        return given
    index = {p.name: k for k, p in enumerate(free)}
    bed = -network.depth
    scale = max(max(ln.line_type.weight * ln.length, ln.line_type.EA * 1e-6)
                for ln in network.lines)

    def imbalance(z):
        where = dict(given)
        for p in free:
            where[p.name] = z[3 * index[p.name]: 3 * index[p.name] + 3]
        F = np.zeros(3 * len(free))
        for p in free:
            F[3 * index[p.name] + 2] += (network.rho * p.volume - p.mass) * network.g
        for ln in network.lines:
            fa, fb = line_end_forces(ln.line_type, ln.length, where[ln.a], where[ln.b], bed)
            for end, f in ((ln.a, fa), (ln.b, fb)):
                if end in index:
                    F[3 * index[end]: 3 * index[end] + 3] += f
        return F / scale

    z0 = np.concatenate([given[p.name] for p in free])
    unsettled = ("free points not settled on catenaries (the catenary-network solve did not "
                 "converge): the statics start from the given positions")
    from scipy.optimize import root  # here: scipy.optimize takes 0.5 s to import

    try:
        with np.errstate(all="ignore"):
            sol = root(imbalance, z0, method="hybr", options={"xtol": 1e-12})
    except (ValueError, ArithmeticError):
        network.notes.append(unsettled)
        return given
    if not sol.success or np.max(np.abs(imbalance(sol.x))) > 1e-6:
        network.notes.append(unsettled)
        return given
    settled = dict(given)
    for p in free:
        z = sol.x[3 * index[p.name]: 3 * index[p.name] + 3].copy()
        z[2] = max(z[2], bed)
        settled[p.name] = z
    return settled


def build_system(network: Network, positions: dict | None = None):
    """(System, LineSet, catenaries, positions) of a network whose points sit at
    ``positions`` ({name: (3,) m}; default: settled by :func:`settle_points`)."""
    positions = settle_points(network) if positions is None else positions
    bed = -network.depth
    lines, catenaries = [], []
    for ln in network.lines:
        try:
            line, cat = reference_line(ln.name, ln.line_type, ln.length, int(ln.n_elements),
                                       positions[ln.a], positions[ln.b], bed)
        except ValueError as err:
            message = str(err)
            raise ValueError(message if message.startswith(f"line {ln.name}")
                             else f"line {ln.name}: {message}") from None
        lines.append(line)
        catenaries.append(cat)
    dynamic = [b for b in network.bodies if b.kind == "dynamic"]
    body_index = {b.name: k for k, b in enumerate(dynamic)}
    free = [p for p in network.points if p.kind == "free"]
    point_index = {p.name: k for k, p in enumerate(free)}
    slots = []  # prescribed ends: (coupled object, point)
    points = {p.name: p for p in network.points}

    def end(name):
        p = points[name]
        if p.kind == "fixed":
            return ("fixed",)
        if p.kind == "free":
            return ("point", point_index[name])
        body = network.body(p.body) if p.kind == "body" else None
        if body is not None and body.kind == "dynamic":
            return ("body", body_index[body.name])
        if body is not None and body.kind == "fixed":
            return ("fixed",)
        slots.append(p)
        return ("prescribed", len(slots) - 1)

    ends_a, ends_b = [end(ln.a) for ln in network.lines], [end(ln.b) for ln in network.lines]
    clamped = []
    for k, ln in enumerate(network.lines):
        for side, clamp, held in (("a", ln.clamp_a, ends_a[k]), ("b", ln.clamp_b, ends_b[k])):
            if clamp is False or clamp is None:
                continue
            if ln.line_type.EI <= 0:
                raise ValueError(f"line {ln.name} clamp_{side}: only a bending line (EI > 0) "
                                 "can be clamped; a cable end is pinned")
            if held[0] == "point":
                raise ValueError(f"line {ln.name} clamp_{side}: point {getattr(ln, side)} is "
                                 "free; only ends on fixed or coupled points or on bodies "
                                 "can be clamped")
            lines[k].end_tangents = _clamp_tangents(ln, side, clamp, positions,
                                                    lines[k].end_tangents)
            point = points[getattr(ln, side)]
            if held[0] == "prescribed" and point.kind == "body":  # turns with its body
                slots.append((point, lines[k].end_tangents[0 if side == "a" else 1]))
                clamped.append((k, side, len(slots) - 1))
            else:
                clamped.append((k, side))
    smooth = [_smooth_joint(network, p, lines) for p in network.points if p.smooth]
    ends = Ends(ends_a, ends_b, clamped=clamped, smooth=smooth)
    lineset = LineSet(lines, law=network.strain_law) if lines else NoLines()
    motion = _slot_motion(network, slots) if slots else None
    masses = [PointMass(p.mass, p.volume, p.CdA, p.Ca, rho=network.rho, g=network.g)
              for p in free]
    terms = []  # on the lines: sea bed, hydrodynamics, free surface
    if network.seabed is not None:
        terms.append(seabed_term(lineset, network.seabed, path=network.form_path))
    if network.hydro and any(getattr(ln.line_type, c) for ln in network.lines
                             for c in ("Cd_n", "Cd_t", "Ca_n", "Ca_t")):
        terms += line_terms(lineset, network.sea, path=network.form_path)
    if network.hydro and any(ln.line_type.Cl > 0 for ln in network.lines):
        make_lift = network.viv_lift or vortex_lift_term
        terms.append(make_lift(lineset, network.sea, path=network.form_path, **(
            {} if network.viv_rms_time is None else {"rms_time": network.viv_rms_time})))
    if network.surface and lines:
        terms.append(SurfaceTerm(lineset, network.sea, drag=network.hydro,
                                 path=network.form_path))
    for k, body in enumerate(dynamic):
        for term in body.terms:
            term = copy.copy(term)
            term.body = k
            terms.append(term)
        if body.pin is not None:
            terms.append(_pin(network, body, k, body_index))
    system = System(lineset, ends=ends, bodies=[b.rigid for b in dynamic], points=masses,
                    motion=motion, body_load=[b.load for b in dynamic], terms=terms,
                    sea=network.sea)
    return system, lineset, catenaries, positions


def _pin(network: Network, body: Body, k: int, body_index: dict):
    """The PinLoad of a pinned dynamic body (number k among the dynamic bodies; body_index:
    {name: number}), or its BodyPin when the pin is on another dynamic body: stiff on the
    length scale of its centre of mass from the pin (at least 1 m)."""
    from ..bodies.rod_loads import PinLoad
    from .joints import BodyPin

    rigid = body.rigid
    scale = max(float(np.linalg.norm(rigid.center_of_mass - rigid.reference_point)), 1.0)
    point = network.point(body.pin) if body.pin not in PINS else None
    if point is not None and point.kind == "body" and network.body(point.body).kind == "dynamic":
        carrier = network.body(point.body)
        return BodyPin(carrier.rotation_matrix() @ point.position, mass=rigid.mass,
                       carrier_mass=carrier.rigid.mass, length=scale, g=network.g,
                       bodies=(body_index[carrier.name], k))
    if body.pin == "fixed":
        return PinLoad(rigid.mass, scale, g=network.g, body=k)
    if body.pin == "coupled":
        where = coupled_offsets(network)[("Body", body.name)]

        def at(time):
            return coupled_vector(network, time)[where]
    else:  # a point moved by the motion
        followed = _slot_motion(network, [network.point(body.pin)])

        def at(time):
            return followed(time)[0]

    def motion(t, dt=1e-6):
        return at(t), (at(t + dt) - at(t - dt)) / (2 * dt)

    return PinLoad(rigid.mass, scale, g=network.g, motion=motion, body=k)


def _smooth_joint(network: Network, point: Point, lines) -> tuple:
    """(k, j) of the smooth joint at ``point``: line k ends there (b), line j starts
    there (a); both reference Lines get one end tangent there, so that the C1 reference
    geometry is smooth across the joint: the mean of their unit tangents weighted by each
    end element's bending stiffness EI / h, the direction that balances their end moments
    (MoorDyn's zero-length rod: Rod.cpp's setDependentStates)."""
    ending = [k for k, ln in enumerate(network.lines) if ln.b == point.name]
    starting = [k for k, ln in enumerate(network.lines) if ln.a == point.name]
    if len(ending) != 1 or len(starting) != 1:
        raise ValueError(f"point {point.name} smooth: a smooth joint takes end b of one line "
                         f"and end a of the next (found {len(ending)} b and "
                         f"{len(starting)} a ends there)")
    k, j = ending[0], starting[0]
    for m in (k, j):
        if network.lines[m].line_type.EI <= 0:
            raise ValueError(f"point {point.name} smooth: line {network.lines[m].name} has "
                             "no bending stiffness (EI = 0); a cable is hinged at its points")
    before, after = lines[k], lines[j]
    t_b = before.end_tangents[1]
    t_b = before.tangent(np.array([before.s[-1]]))[0] if t_b is None else t_b
    t_a = after.end_tangents[0]
    t_a = after.tangent(np.array([after.s[0]]))[0] if t_a is None else t_a
    stiffness = [network.lines[m].line_type.EI / np.diff(line.s)[end]
                 for m, line, end in ((k, before, -1), (j, after, 0))]
    mean = stiffness[0] * t_b / np.linalg.norm(t_b) + stiffness[1] * t_a / np.linalg.norm(t_a)
    if not np.linalg.norm(mean) > 1e-6:
        raise ValueError(f"point {point.name} smooth: lines {network.lines[k].name} and "
                         f"{network.lines[j].name} leave it in opposite directions")
    mean = mean / np.linalg.norm(mean)
    before.end_tangents = (before.end_tangents[0], mean)
    after.end_tangents = (mean, after.end_tangents[1])
    return k, j


def _clamp_tangents(ln: MooringLine, side, clamp, positions, tangents):
    """The line's end tangents with the clamped end's direction (see MooringLine)."""
    if clamp is True:
        direction = np.asarray(positions[ln.b], float) - np.asarray(positions[ln.a], float)
    else:
        direction = np.asarray(clamp, float)
        if direction.shape != (3,) or not np.all(np.isfinite(direction)):
            raise ValueError(f"line {ln.name} clamp_{side}: need True, False or a direction "
                             f"(3-vector), got {clamp!r}")
    if not np.linalg.norm(direction) > 0:
        raise ValueError(f"line {ln.name} clamp_{side}: the direction is zero")
    direction = direction / np.linalg.norm(direction)
    a, b = tangents
    return (direction, b) if side == "a" else (a, direction)


def _point_slots(given, where, n):
    """The vectorized :class:`~skmoor.bodies.motion.Motion` of coupled points' slots from
    a vectorized network motion: its columns ``where`` (a slice per slot), no per-time
    Python (what a host's or a record's motion costs per step)."""
    columns = np.concatenate([np.arange(n)[w] for w in where])

    def pick(f, name):
        def picked(t):
            y = np.asarray(f(t), float)
            if y.shape[-1] != n:
                raise ValueError(f"motion {name}: expected {n} coupled DOFs, got {y.shape}")
            return y[..., columns].reshape(y.shape[:-1] + (len(where), 3))
        return picked
    acceleration = given.acceleration
    return Motion(pick(given.position, "position"), pick(given.velocity, "velocity"),
                  None if acceleration is None else pick(acceleration, "acceleration"),
                  vectorized=True)


def _slot_motion(network: Network, slots):
    """A :class:`~skmoor.bodies.motion.Motion` of the prescribed ends from the network's
    coupled-DOF motion (zeros without one): (nslots, 3) displacements, m; velocities and
    accelerations from the network's motion when it is a Motion with a velocity (its
    acceleration, or differences of its velocity), else differences of the positions. A
    slot is a Point, or (a Point on a coupled body, t0): the change R(t) R0^T t0 - t0 of a
    line's clamped tangent t0 there (turned, not carried)."""
    offsets = coupled_offsets(network)
    given = network.motion
    if (isinstance(given, Motion) and given.vectorized and given.velocity is not None
            and all(not isinstance(p, tuple) and p.kind == "coupled" for p in slots)):
        return _point_slots(given, [offsets[("Point", p.name)] for p in slots],
                            network.n_coupled_dofs)

    def turned(body, q, r):
        """R(attitude + q) r - R(attitude) r (m) of a point r (body frame) on a body."""
        return body.rotation_matrix(body.attitude + q) @ r - body.rotation_matrix() @ r

    def along(body, q, r, w, order):
        """The first (order 1) or second derivative of turned(q + h w) in h at h = 0
        (central differences over h |w| = 1e-6 or 1e-4 rad)."""
        size = np.linalg.norm(w)
        if size == 0.0:
            return np.zeros(3)
        h = (1e-6 if order == 1 else 1e-4) / size
        ahead, behind = turned(body, q + h * w, r), turned(body, q - h * w, r)
        if order == 1:
            return (ahead - behind) / (2 * h)
        return (ahead - 2 * turned(body, q, r) + behind) / h**2

    def on_body(p):
        """(body, r in the body's frame, 1 if the body's translation carries it else 0)."""
        if isinstance(p, tuple):  # a clamped tangent turning with its coupled body
            point, t0 = p
            body = network.body(point.body)
            return body, body.rotation_matrix().T @ t0, 0.0
        return network.body(p.body), p.position, 1.0

    n_coupled = network.n_coupled_dofs
    # the coupled points' slots and their coupled DOFs (taken in one go), the others'
    on_points = np.array([k for k, p in enumerate(slots)
                          if not isinstance(p, tuple) and p.kind == "coupled"], np.int64)
    point_dofs = np.array([np.arange(n_coupled)[offsets[("Point", slots[k].name)]]
                           for k in on_points], np.int64).reshape(-1, 3)
    on_bodies = sorted(set(range(len(slots))) - set(on_points.tolist()))

    def motion(t):
        y = coupled_vector(network, t, n_coupled)
        out = np.zeros((len(slots), 3))
        out[on_points] = y[point_dofs]
        for k in on_bodies:
            body, r, carried = on_body(slots[k])
            q = y[offsets[("Body", body.name)]]
            out[k] = carried * q[:3] + turned(body, q[3:], r)
        return out

    def rates(t, order):
        """(nslots, 3) velocities (order 1, m/s) or accelerations (order 2, m/s2): from
        the network's motion as it is now (a Motion's velocity and acceleration, else
        central differences of the ends' positions or velocities)."""
        given = network.motion
        if order == 1 and getattr(given, "velocity", None) is None:
            return (motion(t + 1e-6) - motion(t - 1e-6)) / 2e-6
        if order == 2 and getattr(given, "acceleration", None) is None:
            return (rates(t + 1e-6, 1) - rates(t - 1e-6, 1)) / 2e-6
        y = coupled_vector(network, t, n_coupled)
        yd = np.asarray(given.velocity(t), float).ravel()
        ydd = np.asarray(given.acceleration(t), float).ravel() if order == 2 else None
        for name, value in (("velocity", yd), ("acceleration", ydd)):
            if value is not None and value.shape != y.shape:
                raise ValueError(f"motion {name}: expected {y.size} coupled DOFs, got "
                                 f"{value.shape}")
        out = np.zeros((len(slots), 3))
        for k, p in enumerate(slots):
            if not isinstance(p, tuple) and p.kind == "coupled":
                where = offsets[("Point", p.name)]
                out[k] = (yd if order == 1 else ydd)[where]
                continue
            body, r, carried = on_body(p)
            where = offsets[("Body", body.name)]
            q, qd = y[where], yd[where]
            if order == 1:  # d/dt [q + R(a + q) r]
                out[k] = carried * qd[:3] + along(body, q[3:], r, qd[3:], 1)
            else:
                qdd = ydd[where]
                out[k] = (carried * qdd[:3] + along(body, q[3:], r, qdd[3:], 1)
                          + along(body, q[3:], r, qd[3:], 2))
        return out

    own = getattr(network.motion, "acceleration", None) is not None  # else: the step's
    return Motion(motion, lambda t: rates(t, 1), (lambda t: rates(t, 2)) if own else None)
