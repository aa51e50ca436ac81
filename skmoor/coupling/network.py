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

import math
from dataclasses import dataclass, field

import numpy as np

from ..bodies.body import RigidBody
from ..lines.laws import Engineering
from ..lines.line import LineType

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
    the body turns freely about it (a stiff :class:`~skmoor.bodies.rod_loads.PinLoad`)."""

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
class LineFailure:
    """A release of the ends of ``lines`` (names) from ``point`` (a name): at ``time`` (s)
    or when the tension at one of those ends reaches ``tension`` (N), whichever comes
    first (None: no such trigger); MoorDyn v2's FAILURE entry. The released ends stay
    joined at a new massless free point, which starts where the point is."""

    point: str
    lines: tuple
    time: float | None = None
    tension: float | None = None

    def __post_init__(self):
        self.lines = tuple(self.lines)
        where = f"failure at point {self.point}"
        if not self.lines:
            raise ValueError(f"{where} lines: name at least one line")
        for name, value in (("time", self.time), ("tension", self.tension)):
            if value is not None and not (isinstance(value, (int, float))
                                          and math.isfinite(value) and value > 0):
                raise ValueError(f"{where} {name}: must be a positive number (s, N) or "
                                 f"None, got {value!r}")
        if self.time is None and self.tension is None:
            raise ValueError(f"{where}: give a time or a tension that triggers it")


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
    ~30 s each, cached on disk: for time integration). P1 lines have compiled kernels;
    the VIV lift runs its hand-written kernels on 'auto', its forms on another path
    (:func:`~skmoor.sea.viv.vortex_lift_term`).
    surface: the lines' parts above the free surface lose their buoyancy and drag
    (:mod:`skmoor.sea.surface`, on ``form_path``; MoorDyn's decks have it); off by default:
    the lines are taken as submerged. viv_rms_time: the time constant (s) of the VIV
    lift's running mean squares (:class:`~skmoor.sea.viv.VortexLift`; None: its default; a
    MoorDyn deck sets 500 of its steps dtM). viv_lift: what makes the VIV lift term,
    fn(lines, sea, *, path, [rms_time]) -> Term (None:
    :func:`~skmoor.sea.viv.vortex_lift_term`; a lift model of one's own, e.g. a
    :class:`~skmoor.sea.viv.VortexLiftForm` with another update, docs/forms.md).
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
    viv_lift: object = None
    notes: list = field(default_factory=list)  # what the build noticed (see Model.notes)
    failures: list = field(default_factory=list)  # LineFailure events of the run

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
        for failure in self.failures:
            _check_failure(failure, points, self.lines)
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


def _check_failure(failure: LineFailure, points: dict, lines: list):
    """Refuse a failure whose point or lines do not exist or do not meet, or that leaves
    a free point with no line."""
    where = f"failure at point {failure.point}"
    if failure.point not in points:
        raise ValueError(f"{where}: no such point ({len(points)} points)")
    attached = {ln.name for ln in lines if failure.point in (ln.a, ln.b)}
    for name in failure.lines:
        if name not in attached:
            raise ValueError(f"{where} lines: line {name!r} does not end at {failure.point} "
                             f"(lines there: {sorted(attached) or 'none'})")
    if points[failure.point].kind == "free" and attached <= set(failure.lines):
        raise ValueError(f"{where}: it releases every line of the free point, which would "
                         "be left with none (release all but one, or the line's other end)")


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


# ------------------------------------------------------------ network -> System


def coupled_offsets(network: Network) -> dict:
    """{(type name, name): slice} of each coupled object in the coupled-DOF vector."""
    offsets, start = {}, 0
    for obj in network.coupled:
        size = coupled_size(obj)
        offsets[(type(obj).__name__, obj.name)] = slice(start, start + size)
        start += size
    return offsets


def coupled_vector(network: Network, t, n=None) -> np.ndarray:
    """The network's coupled-DOF displacements at time t (zeros without a motion); n: their
    number when the caller knows it (else counted)."""
    n = network.n_coupled_dofs if n is None else n
    y = np.zeros(n) if network.motion is None else np.asarray(network.motion(t), float).ravel()
    if y.shape != (n,):
        raise ValueError(f"motion: expected {n} coupled DOFs "
                         f"({', '.join(o.name for o in network.coupled)}), got {y.shape}")
    return y
