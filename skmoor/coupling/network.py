"""A mooring as a network (MoorPy's and MoorDyn's object model): :class:`Point` objects,
:class:`MooringLine` objects between any two of them, and :class:`Body` objects.

Points are ``fixed``; ``free`` (a line junction, or a clump weight or buoy with mass,
volume, CdA and Ca); ``coupled`` (moved by a given motion); or on a ``body`` (at a
position in the body frame, relative to its reference point). Bodies are ``dynamic``
(6 DOF: a :class:`~skmoor.bodies.body.RigidBody` with its loads; ``pin``: its reference point held
in place or on a coupled motion, the body free to turn), ``coupled`` (prescribed motion)
or ``fixed``. A multi-segment line is lines joined at free points; a shared line runs
between two bodies. Rods (:mod:`skmoor.coupling.rods`) are bodies with a rod load.

:func:`build_network` turns a :class:`Network` into a :class:`~skmoor.model.model.Model`: the
free points are first settled on analytic catenaries (the catenary-network first guess),
each line's reference state is the elastic catenary between its ends there (seabed
touchdown included; a buoyant line's catenary upside down; a weightless line: straight
and taut, or a stress-free sagging polyline when slack), and one
:class:`~skmoor.coupling.system.System` joins them.

Coupled motion (``Network.motion``): fn(t) -> displacements of the coupled objects from
their given positions in MoorDyn's order of coupled DOFs: 6 per coupled body (x, y, z in
m; roll, pitch, yaw in rad, applied as MoorDyn does: R = Rx Ry Rz of the attitude plus
the angles) and 3 per body pinned on a coupled motion (``pin='coupled'``: x, y, z of its
reference point), in the order of ``Network.bodies``; then 3 per coupled point.
"""
from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field

import numpy as np

from ..bodies.body import RigidBody
from ..lines.catenary import solve_catenary
from .checks import carries_strain
from .system import Ends, PointMass, System
from ..lines.creep import CreepTerm, has_creep
from ..sea.hydro import line_terms
from ..sea.viv import VortexLift
from ..sea.surface import SurfaceTerm
from ..lines.laws import Engineering
from ..lines.line import Line, LineSet, LineType
from ..bodies.motion import Motion
from .no_lines import NoLines
from ..sea.seabed import seabed_term

_LINEAR = Engineering(tension_only=False)

POINT_KINDS = ("fixed", "free", "coupled", "body")
BODY_KINDS = ("dynamic", "coupled", "fixed")
PINS = (None, "fixed", "coupled")


@dataclass
class Point:
    """A point of the network. position: global (m), or for kind 'body' in the body's
    frame relative to its reference point. mass kg, volume m3, CdA m2, Ca (-): loads of a
    free point (a body point's are not modelled: refused when non-zero). smooth: a free
    point where one bending line ends (its b) and the next starts (its a), joined C1:
    their tangents there are one (the joint carries the bending moment, as between the
    sections of one cable); False: a hinge."""

    name: str
    kind: str
    position: np.ndarray
    body: str | None = None
    mass: float = 0.0
    volume: float = 0.0
    CdA: float = 0.0
    Ca: float = 0.0
    smooth: bool = False

    def __post_init__(self):
        if self.smooth and self.kind != "free":
            raise ValueError(f"point {self.name} smooth: only a free point is a smooth "
                             f"joint (this one is {self.kind!r})")
        if self.kind not in POINT_KINDS:
            raise ValueError(f"point {self.name}: kind {self.kind!r} is not one of {POINT_KINDS}")
        self.position = _vector(f"point {self.name} position", self.position)
        if (self.kind == "body") != (self.body is not None):
            raise ValueError(f"point {self.name}: a point of kind 'body' names its body, "
                             "other kinds do not")


@dataclass
class MooringLine:
    """A line from point ``a`` to point ``b`` (names): its LineType, unstretched length
    (m) and number of elements. clamp_a, clamp_b: clamp a bending line (EI > 0) at that
    end (on a fixed or coupled point, or on a body, where the tangent turns with the
    body): True holds its tangent along the chord from a to b (a straight beam's axis),
    a 3-vector along that direction (the line's tangent there at the given state,
    pointing from a towards b); False (default): pinned, the end tangent free."""

    name: str
    line_type: LineType
    a: str
    b: str
    length: float
    n_elements: int
    clamp_a: object = False
    clamp_b: object = False

    def __post_init__(self):
        if not (isinstance(self.length, (int, float)) and math.isfinite(self.length)
                and self.length > 0):
            raise ValueError(f"line {self.name} length: must be a positive number of m, "
                             f"got {self.length!r}")
        if isinstance(self.n_elements, bool) or not isinstance(self.n_elements, (int, np.integer)) \
                or self.n_elements < 1:
            raise ValueError(f"line {self.name} n_elements: must be an integer >= 1, "
                             f"got {self.n_elements!r}")
        if self.a == self.b:
            raise ValueError(f"line {self.name}: both ends on point {self.a}")


@dataclass
class Body:
    """A body: kind 'dynamic' (``rigid``: its RigidBody, whose reference point is the
    body's position), 'coupled' or 'fixed' (``position``, m, and ``attitude``, rad, of
    its reference point). terms: BodyLoads (drag, ...); load(t, q, qdot) -> 6-vector.
    pin (dynamic bodies): None (free), 'fixed' (its reference point held where it is),
    'coupled' (held on 3 coupled DOFs of the network's motion) or the name of a point
    moved by the motion (a coupled point, or a point on a coupled body: held where that
    point goes, from where it starts) or of a point on another dynamic body (where the
    body's reference point starts; a joint of the two, :class:`~skmoor.coupling.joints.BodyPin`);
    the body turns freely about it (a stiff :class:`~skmoor.coupling.rods.PinLoad`)."""

    name: str
    kind: str
    position: np.ndarray
    attitude: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rigid: RigidBody | None = None
    terms: list = field(default_factory=list)
    load: object = None
    rotation: str = "moordyn"  # order of the attitude angles: 'moordyn' (Rx Ry Rz) or 'skmoor'
    pin: str | None = None

    def __post_init__(self):
        if self.kind not in BODY_KINDS:
            raise ValueError(f"body {self.name}: kind {self.kind!r} is not one of {BODY_KINDS}")
        if not (self.pin in PINS or isinstance(self.pin, str)):
            raise ValueError(f"body {self.name} pin: {self.pin!r} is not one of {PINS} "
                             "or a point's name")
        if self.pin is not None and self.kind != "dynamic":
            raise ValueError(f"body {self.name} pin: only a dynamic body is pinned")
        self.position = _vector(f"body {self.name} position", self.position)
        self.attitude = _vector(f"body {self.name} attitude", self.attitude)
        if self.kind == "dynamic" and self.rigid is None:
            raise ValueError(f"body {self.name}: a dynamic body needs its mass properties")

    def rotation_matrix(self, angles=None) -> np.ndarray:
        """Rotation of the body frame for ``angles`` (default: the attitude), rad."""
        angles = self.attitude if angles is None else angles
        if self.rotation == "moordyn":
            return moordyn_rotation(angles)
        from ..bodies.body import rotation_matrix
        return rotation_matrix(angles)


@dataclass
class Network:
    """Points, lines and bodies in water of ``depth`` (m), density rho, gravity g.

    seabed: a :class:`~skmoor.sea.seabed.Seabed` or None; sea: a :class:`~skmoor.sea.waves.Sea`
    (currents and waves on the lines, when their coefficients are non-zero); hydro: add
    the lines' Morison terms when any coefficient is non-zero; strain_law: the strain law
    of the line types without their own (``LineType.law``): a :class:`skmoor.lines.laws.Law`
    or 'paper' / 'engineering'; motion: see the module docstring. form_path: how the
    hydrodynamic and sea-bed forms run on bending (Hermite) lines, a
    :class:`~skmoor.fem.terms.LineForm` path: 'auto' (scikit-fem's assembly with the exact
    tangents: no compile, slow per call) or 'compiled' (numba kernels generated once,
    ~30 s each, cached on disk: for time integration). P1 lines have compiled kernels.
    surface: the lines' parts above the free surface lose their buoyancy and drag
    (:mod:`skmoor.sea.surface`, on ``form_path``; MoorDyn's decks have it); off by default:
    the lines are taken as submerged. viv_rms_time: the time constant (s) of the VIV
    lift's running mean squares (:class:`~skmoor.sea.viv.VortexLift`; None: its default; a
    MoorDyn deck sets 500 of its steps dtM).
    """

    points: list
    lines: list
    bodies: list = field(default_factory=list)
    depth: float = 100.0
    rho: float = 1025.0
    g: float = 9.81
    seabed: object = None
    sea: object = None
    hydro: bool = True
    strain_law: object = "engineering"
    motion: object = None
    form_path: str = "auto"
    surface: bool = False
    viv_rms_time: float | None = None
    notes: list = field(default_factory=list)  # what the build noticed (see Model.notes)

    def __post_init__(self):
        for kind, items in (("point", self.points), ("line", self.lines), ("body", self.bodies)):
            names = [item.name for item in items]
            repeated = sorted({n for n in names if names.count(n) > 1})
            if repeated:
                raise ValueError(f"{kind} names: {repeated[0]!r} is used more than once")
        points = {p.name: p for p in self.points}
        bodies = {b.name: b for b in self.bodies}
        for p in self.points:
            if p.kind == "body" and p.body not in bodies:
                raise ValueError(f"point {p.name} body: {p.body!r} is not a body "
                                 f"({sorted(bodies) or 'none defined'})")
        for line in self.lines:
            for end in (line.a, line.b):
                if end not in points:
                    raise ValueError(f"line {line.name}: point {end!r} is not defined")
        for p in self.points:
            if p.kind == "free" and not any(p.name in (ln.a, ln.b) for ln in self.lines):
                raise ValueError(f"point {p.name}: a free point with no line")
        for b in self.bodies:
            if b.pin in PINS:
                continue
            p = points.get(b.pin)
            held = p is not None and (p.kind == "coupled" or (
                p.kind == "body" and bodies[p.body].kind in ("coupled", "dynamic")))
            if not held:
                raise ValueError(f"body {b.name} pin: {b.pin!r} is not a coupled point or a "
                                 "point on a coupled or dynamic body")
            if p.kind == "body" and p.body == b.name:
                raise ValueError(f"body {b.name} pin: {b.pin!r} is on the body itself")
            if p.kind == "body" and bodies[p.body].kind == "dynamic":
                gap = np.linalg.norm(self.global_position(p) - b.position)
                if gap > 1e-6 * max(1.0, np.linalg.norm(b.position)):
                    raise ValueError(f"body {b.name} pin: point {b.pin!r} is {gap:.3g} m "
                                     "from the body's reference point (they must meet)")

    def point(self, name) -> Point:
        return next(p for p in self.points if p.name == name)

    def body(self, name) -> Body:
        return next(b for b in self.bodies if b.name == name)

    def global_position(self, point: Point) -> np.ndarray:
        """Position of a point at the given state (m)."""
        if point.kind != "body":
            return point.position.copy()
        body = self.body(point.body)
        return body.position + body.rotation_matrix() @ point.position

    @property
    def coupled(self) -> list:
        """The coupled objects in MoorDyn's coupled-DOF order: bodies (coupled ones, and
        dynamic ones pinned on a coupled motion), then points."""
        return ([b for b in self.bodies if b.kind == "coupled" or b.pin == "coupled"]
                + [p for p in self.points if p.kind == "coupled"])

    @property
    def n_coupled_dofs(self) -> int:
        return sum(coupled_size(c) for c in self.coupled)

    def coupled_positions(self) -> np.ndarray:
        """MoorDyn's coupled-DOF vector of the given positions (body angles in rad)."""
        parts = [np.r_[c.position, c.attitude] if coupled_size(c) == 6 else c.position
                 for c in self.coupled]
        return np.concatenate(parts) if parts else np.zeros(0)


def coupled_size(obj) -> int:
    """Coupled DOFs of a coupled object: 6 for a coupled body, 3 for a pinned body or a
    coupled point."""
    return 6 if isinstance(obj, Body) and obj.kind == "coupled" else 3


def moordyn_rotation(angles) -> np.ndarray:
    """MoorDyn's body rotation for (roll, pitch, yaw) in rad: R = Rx Ry Rz."""
    (cx, cy, cz), (sx, sy, sz) = np.cos(angles), np.sin(angles)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]])
    ry = np.array([[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]])
    rz = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
    return rx @ ry @ rz


def _vector(name, value) -> np.ndarray:
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected three numbers, got {value!r}") from None
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise ValueError(f"{name}: expected three finite numbers, got {value!r}")
    return arr


# ------------------------------------------------------------ reference states

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


# ------------------------------------------------------------ network -> System

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
        terms.append(VortexLift(lineset, network.sea, **(
            {} if network.viv_rms_time is None else {"rms_time": network.viv_rms_time})))
    if network.surface and lines:
        terms.append(SurfaceTerm(lineset, network.sea, drag=network.hydro,
                                 path=network.form_path))
    if lines and any(has_creep(law) for law in lineset.laws):  # viscoelastic, Syrope ropes
        terms.append(CreepTerm(lineset))
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
    from .joints import BodyPin
    from .rods import PinLoad

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
        where = _coupled_offsets(network)[("Body", body.name)]

        def at(time):
            return _coupled_vector(network, time)[where]
    else:  # a point moved by the motion
        followed = _slot_motion(network, [network.point(body.pin)])

        def at(time):
            return followed(time)[0]

    def motion(t, dt=1e-6):
        return at(t), (at(t + dt) - at(t - dt)) / (2 * dt)

    return PinLoad(rigid.mass, scale, g=network.g, motion=motion, body=k)


def _coupled_offsets(network: Network) -> dict:
    """{(type name, name): slice} of each coupled object in the coupled-DOF vector."""
    offsets, start = {}, 0
    for obj in network.coupled:
        size = coupled_size(obj)
        offsets[(type(obj).__name__, obj.name)] = slice(start, start + size)
        start += size
    return offsets


def _coupled_vector(network: Network, t) -> np.ndarray:
    """The network's coupled-DOF displacements at time t (zeros without a motion)."""
    n = network.n_coupled_dofs
    y = np.zeros(n) if network.motion is None else np.asarray(network.motion(t), float).ravel()
    if y.shape != (n,):
        raise ValueError(f"motion: expected {n} coupled DOFs "
                         f"({', '.join(o.name for o in network.coupled)}), got {y.shape}")
    return y


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


def _slot_motion(network: Network, slots):
    """A :class:`~skmoor.bodies.motion.Motion` of the prescribed ends from the network's
    coupled-DOF motion (zeros without one): (nslots, 3) displacements, m; velocities and
    accelerations from the network's motion when it is a Motion with a velocity (its
    acceleration, or differences of its velocity), else differences of the positions. A
    slot is a Point, or (a Point on a coupled body, t0): the change R(t) R0^T t0 - t0 of a
    line's clamped tangent t0 there (turned, not carried)."""
    offsets = _coupled_offsets(network)

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

    def motion(t):
        y = _coupled_vector(network, t)
        out = np.zeros((len(slots), 3))
        for k, p in enumerate(slots):
            if not isinstance(p, tuple) and p.kind == "coupled":
                out[k] = y[offsets[("Point", p.name)]]
                continue
            body, r, carried = on_body(p)
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
        y = _coupled_vector(network, t)
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
