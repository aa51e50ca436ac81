"""A MoorDyn v2 deck as an skmoor :class:`~skmoor.coupling.network.Network` (:func:`deck_network`;
``skmoor.build(deck)`` builds and ``skmoor.simulate`` runs it like any case).

Points keep their kinds: fixed, free (junctions, clump weights and buoys: Mass, Volume,
CdA and Ca act on them as in MoorDyn: net buoyancy (rho V - m) g, drag 0.5 rho CdA |v| v,
added mass rho V Ca), coupled, and on bodies (``BodyN``). Bodies: 'free' ones are dynamic
(Mass, CG, I about the CG, Volume: buoyancy rho g V at the CG as MoorDyn applies it, no
waterplane; CdA: quadratic drag in each of the 6 DOFs; Ca: added mass rho V Ca in x, y, z),
coupled ones follow the motion, fixed ones stay. Each line's reference state is the
elastic catenary between its ends (after the free points are settled on catenaries), on
NumSegs elements with MoorDyn's strain law: tension = EA x engineering strain, or the
deck's tension-strain curve (:class:`skmoor.lines.laws.Curve`), tension-only as in MoorDyn; a
viscoelastic ``EA_s|EA_d`` or ``EA_s|alphaMBL|beta`` line with ``BA|BA_D`` is a
:class:`skmoor.lines.laws.Viscoelastic` (static state with EA_s, MoorDyn's creep state
integrated in time by :mod:`skmoor.lines.creep`, started as MoorDyn starts it:
:func:`initial_creep_time`), without ``BA_D`` a :class:`skmoor.lines.laws.StaticDynamic`
(the motion about the static state with the dynamic stiffness); a Syrope line with
``BA|BA_D`` a :class:`skmoor.lines.syrope.SyropeCreep` from its SYROPE IC.
MoorDyn's coefficient conventions carry over: Cd -> Cd_n, CdAx -> Cd_t, Ca -> Ca_n,
CaAx -> Ca_t; the submerged weight is (Mass/m - rho pi d^2/4) g; the internal damping
BA (N s, or -zeta: BA = zeta (L / NumSegs) sqrt(EA Mass/m) as MoorDyn sets it) damps the
axial strain rate (``LineType.BA``). Drag and added mass come from
:func:`skmoor.sea.hydro.line_hydrodynamics` (MoorDyn's conventions, still water unless a
``Sea`` is given); a line's part above the free surface has no buoyancy and no drag
(:mod:`skmoor.sea.surface`, as MoorDyn's wetted length). The bottom is MoorDyn's (as :meth:`skmoor.sea.seabed.Seabed.from_moordyn`:
stiffness kBot d, damping cBot d per unit length), its damping faded in over the first
tenth of the static penetration w / (kBot d), 13 mm for the chain decks (the bed's
default ``damping_onset``; MoorDyn's jump there leaves the implicit step without a
solution); MoorDyn-C's friction (a viscous ramp mu FricDamp v capped at mu N) maps to
the bed's regularised Coulomb law with the same slope and cap (slip velocity
v0 = N / FricDamp, N a segment's weight).

The coupled objects move as the caller says: ``motion(t)`` returns their displacements
from the deck's positions in MoorDyn's order of coupled DOFs (6 per coupled body:
x, y, z in m and roll, pitch, yaw in rad; then 6 per Coupled rod, the same of its end A,
and 3 per CoupledPinned rod; then 3 per coupled point). Without a motion
they stay where the deck puts them. ``skmoor run DECK --motion FILE`` reads such a motion
from a time-series file (:func:`read_motion`).

MoorDyn's water and bed input (WaveKin 1, 2, 3, 7; Currents 1, 2, 5; SeafloorFile) is
read from the deck's folder (:mod:`skmoor.io.sea_files`).

Rods (:mod:`skmoor.coupling.rods`): a Free rod is a dynamic body of its own (reference point at
end A) with its :class:`~skmoor.bodies.rod_loads.RodLoad` and a spin spring; a Pinned rod the same,
end A pinned in place; a CoupledPinned rod, end A on 3 coupled DOFs; a Fixed rod is its
two end points, fixed; a Body<N> rod adds its mass and its RodLoad to body N (on a
coupled or fixed body it only carries its line ends); a Body<N>Pinned rod on a fixed
body is a Pinned rod there, on a coupled or free body a rod pinned to the body's point
``rodN.pin`` (on a free body, a joint of the two bodies: :class:`~skmoor.coupling.joints.BodyPin`).
Line ends ``R<N>A`` / ``R<N>B`` are the points ``rodN.A`` / ``rodN.B`` on
the rod. A CoupledPinned body is a dynamic body (its mass and its rods')
pinned at its reference point on 3 coupled DOFs (MoorDyn's coupled-DOF vector gives it
6, of which the first 3, its position, are used); a body of no mass of its own carrying
one rod gets that rod's spin spring. A free or pinned body's RigidBody holds its own mass
and its points' and rods' (:func:`_body_rigid`); its points' volumes are buoyant there.

A line type with EI > 0 is a bending line (:mod:`skmoor.lines.bending`: the deck's lines then
all go on the Hermite element, the cables with EI = 0), its ends pinned, but where it ends
on a rod: there it is clamped along the rod's axis (as MoorDyn attaches it), its end
tangent turning with the rod.

A zero-length Free rod (NumSegs 0, MoorDyn's 6-DOF connection node) is a massless free
point ``rodN`` joining the lines on its two ends. MoorDyn clamps bending lines to the
node's direction, which turns to balance their end moments: where one bending line ends
on it and the next starts from its other end, the point is a smooth joint of the two
(``Point.smooth``: one shared end tangent, the bending moment carried across); any other
set of lines is pinned there.

A Coupled rod is a coupled body ``rodN`` at end A (its 6 coupled DOFs: end A's
position and MoorDyn's angles Rx Ry Rz turning the deck's axis), carrying its RodLoad
for :func:`skmoor.coupling.rods.coupled_reaction`.

A line type's Cl > 0 (with dF, cF) adds the VIV lift (:mod:`skmoor.sea.viv`). Refused, with
the deck line and the reason: mass or volume on a point of a fixed or coupled body, a free
body whose summed mass matrix is singular, MoorDyn-F's WaterKin file.
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ..bodies.body import Hydrostatics, RigidBody, combined_mass, point_mass_matrix
from ..bodies.motion import Record
from ..bodies.rod_loads import RodLoad, RodType, SpinLoad, spring_weight
from ..coupling import rods
from ..coupling.network import (
    Body,
    LineFailure,
    MooringLine,
    Network,
    Point,
    moordyn_rotation,
)
from ..io.deck import Deck, read_deck
from ..io.sea_files import deck_bathymetry, deck_sea
from ..lines import laws
from ..lines.line import LineType
from ..numerics.validation import user_stacklevel
from ..sea.hydro import body_hydrodynamics
from ..sea.seabed import Seabed
from ..sea.viv import RMS_STEPS
from .openfast_motion import is_openfast_output

__all__ = ["deck_network", "heave_motion", "read_motion", "default_time_step"]


def _fail(deck, where, what):
    return ValueError(f"{deck.source} line {where}: {what}")


def line_type_of(deck: Deck, line) -> LineType:
    """skmoor's LineType of a deck line (its type, MoorDyn's coefficient conventions, and
    its internal damping BA, which MoorDyn sets per line from -zeta)."""
    name = line.type
    t = deck.line_types[name]
    Cl, dF, cF = (t.viv + (0.08, 0.18))[:3] if t.viv else (0.0, 0.08, 0.18)  # MoorDyn's defaults
    if Cl < 0:
        raise _fail(deck, t.where, f"LINE TYPES {name}: Cl = {Cl:g}: the VIV lift "
                    "coefficient must be >= 0")
    law = _syrope_law(deck, t, line) if t.syrope else _law(deck, t, line)
    BA = _internal_damping(deck, line)
    if isinstance(law, laws.StaticDynamic):
        BA = t.BA_dynamic or 0.0
    if isinstance(law, laws.Viscoelastic):
        BA = 0.0  # both dampers are the law's (skmoor.lines.creep)
    return LineType(EA=t.EA, mass=t.mass, diameter=t.diameter, Cd_n=t.Cd, Cd_t=t.CdAx,
                    Ca_n=t.Ca, Ca_t=t.CaAx, BA=BA, rho_water=deck.rho, g=deck.g, law=law,
                    EI=t.EI, Cl=Cl, viv_dF=dF, viv_cF=cF)


def _law(deck: Deck, t, line):
    """The strain law of a deck line type: None (EA x strain, the network's), a Curve, a
    StaticDynamic law (EA_s|... without BA|BA_D) or a Viscoelastic one (with it)."""
    where = f"{deck.source} line {t.where}: LINE TYPES {t.name} EA"
    static = laws.Curve(*t.EA_curve, source=f"{where} ({t.EA_file})") if t.EA_curve else None
    if not t.EA_visco:
        return static
    static = static or laws.Engineering()
    stiffness = (dict(EA_dynamic=t.EA_visco[0]) if len(t.EA_visco) == 1
                 else dict(alpha_MBL=t.EA_visco[0], beta=t.EA_visco[1]))
    try:
        if t.BA_dynamic is None:  # no creep damper pair: the fast limit
            return laws.StaticDynamic(**stiffness, static=static)
        return laws.Viscoelastic(**stiffness, static=static, creep_damping=t.BA,
                                 dynamic_damping=t.BA_dynamic,
                                 relax=initial_creep_time(deck, line))
    except ValueError as err:
        raise ValueError(f"{where}: {err}") from None


def initial_creep_time(deck: Deck, line):
    """How long (s) MoorDyn's initial-condition stage lets a deck line's creep state relax
    from its start (MoorDyn's z = e, or Syrope's Tmean0) with the ends held: to the
    stage's first convergence check, min(dtIC, TmaxIC), for a line of one segment between
    held points (nothing moves, the stage stops there); None for a line with free nodes
    (the stage runs until they stop, the creep settled: skmoor relaxes it fully)."""
    if "TmaxIC" in deck.options and deck.option("TmaxIC") == 0:
        return 0.0  # MoorDyn: no IC stage
    points = {p.id: p for p in deck.points}
    held = all(isinstance(end, int) and points[end].kind in ("fixed", "coupled")
               for end in (line.a, line.b))
    if line.n_segments == 1 and held:
        return min(deck.option("dtIC", 1.0), deck.option("TmaxIC", 120.0))
    return None


def _syrope_law(deck: Deck, t, line):
    """The Syrope law of a deck line (skmoor.lines.syrope): the working curve of the line's
    SYROPE IC Tmax0, the motion about its Tmean0 with EA_Dc + EA_D_Lm Tmean0."""
    from ..lines.syrope import syrope_law

    name, owc, form, k1, k2 = t.syrope
    where = f"{deck.source} line {t.where}: LINE TYPES {t.name} EA ({name})"
    if line.id not in deck.syrope_ic:
        raise _fail(deck, line.where, f"LINES {line.id}: a Syrope line needs its Tmax0 in a "
                    "SYROPE IC section")
    return syrope_law(owc, form, k1, k2, *deck.syrope_ic[line.id][:1], *t.EA_visco,
                      T_mean=deck.syrope_ic[line.id][1], source=where, creep_damping=t.BA,
                      dynamic_damping=t.BA_dynamic, relax=initial_creep_time(deck, line))


def _check_options(deck: Deck):
    if "WaterKin" in deck.options:
        raise _fail(deck, deck.option_lines["WaterKin"], "option WaterKin: MoorDyn-F's "
                    "water-kinematics file is not supported (MoorDyn-C's WaveKin and "
                    "Currents are)")


def _internal_damping(deck: Deck, line) -> float:
    """BA of a deck line, N s (MoorDyn: -zeta -> zeta (L/N) sqrt(EA Mass/m))."""
    t = deck.line_types[line.type]
    if t.BA >= 0:
        return t.BA
    return -t.BA * line.length / line.n_segments * np.sqrt(t.EA * t.mass)


def _six(values, kind):
    """MoorDyn's expansion of a body's CdA (1, 2, 3 or 6 values) or Ca (1 or 3)."""
    v = [float(x) for x in values]
    if kind == "CdA":
        if len(v) == 2:
            return [v[0]] * 3 + [v[1]] * 3
        return v * 6 if len(v) == 1 else v + v if len(v) == 3 else v
    return (v * 3 if len(v) == 1 else v) + [0.0, 0.0, 0.0]


def _deck_body(deck: Deck, body, sea, bed=None, rotations="small") -> Body:
    """A deck body as a network Body (free -> dynamic; coupled pinned -> dynamic, pinned
    on 3 coupled DOFs), with the rods fixed on it; ``rotations`` of its RigidBody."""
    name = f"body{body.id}"
    position = np.array(body.r6[:3], float)
    attitude = np.radians(np.array(body.r6[3:], float))
    if body.kind in ("fixed", "coupled"):
        return Body(name, body.kind, position, attitude)
    R0 = moordyn_rotation(attitude)
    cg = np.array(body.cg, float) if len(body.cg) == 3 else np.array([0.0, 0.0, body.cg[0]])
    inertia = np.array(body.inertia, float)
    inertia = np.full(3, inertia[0]) if inertia.size == 1 else inertia
    rods = [r for r in deck.rods if r.kind == "body" and r.body == body.id and not r.pinned]
    com = position + R0 @ cg
    rotated = R0 @ np.diag(inertia) @ R0.T
    rigid, held = _body_rigid(deck, body, position, R0, com, rotated, rods, rotations)
    terms = []
    if held is not None:  # no inertia about a line of masses: its rotation about it held
        a, b, extent = held
        terms.append(SpinLoad(a, b, spring_weight(rigid.mass, deck.g) * extent))
    cda = _six(body.CdA, "CdA")
    if any(cda) and deck.rho > 0:  # in air (rho = 0) nothing drags
        terms.append(body_hydrodynamics(drag_coefficients=np.ones(6), drag_areas=cda, sea=sea,
                                        reference_point=position, rho=deck.rho, axes=R0))
    for rod in rods:  # the rod's ends in the body frame -> global offsets at the start
        rod_type, a, b = _rod_type(deck, rod), R0 @ rod.a, R0 @ rod.b
        terms.append(RodLoad(rod_type, a, b, reference_point=position,
                             n_segments=rod.n_segments, rho=deck.rho, g=deck.g, sea=sea,
                             bed=bed, name=f"rod{rod.id}"))
    if len(rods) == 1 and _spins_freely(deck, body, cg, rods[0]):  # the rod's spin
        terms.append(SpinLoad(a, b, spring_weight(rigid.mass, deck.g) * np.linalg.norm(b - a)))
    return Body(name, "dynamic", position, attitude, rigid=rigid, terms=terms,
                pin="coupled" if body.kind == "pinned" else None)


def _massive_points(deck: Deck, body):
    """The deck points fixed on ``body`` that carry a mass or a volume."""
    return [p for p in deck.points
            if p.kind == "body" and p.body == body.id and (p.mass or p.volume)]


def _body_rigid(deck: Deck, body, position, R0, com, inertia, body_rods, rotations):
    """(RigidBody, held) of a free deck body: its own mass and inertia (about com, global
    axes), plus the masses, volumes and added masses of its points and the masses of its
    rods, as MoorDyn sums them into the body's 6x6 mass matrix (Body.cpp, Point.cpp's
    getNetForceAndMass); a point's volume is buoyant at the point, the body's at com.
    held: None, or (a, b, extent m) of a body whose masses and points all lie on one
    line (no inertia about it, and no load with a moment about it): two points on that
    line (from the reference point, global axes) and its masses' extent along it, for
    the spring that holds its rotation about the line (:func:`_held_axis`)."""
    points = _massive_points(deck, body)
    offsets = [R0 @ np.array(p.position, float) for p in points]
    parts = [(body.mass, com, inertia)]
    parts += [(p.mass, position + r, np.zeros((3, 3))) for p, r in zip(points, offsets)]
    parts += [rods.rod_inertia(_rod_type(deck, rod), position + R0 @ rod.a,
                               position + R0 @ rod.b, f"rod{rod.id}") for rod in body_rods]
    mass, centre, total = combined_mass(parts)
    scale = max(mass * 1.0, np.trace(total), 1e-300)
    lowest, axes = np.linalg.eigh(total)
    held = None
    if mass <= 0 or lowest[0] <= 1e-12 * scale:
        axis = np.round(axes[:, 0], 12) + 0.0
        line = mass > 0 and lowest[1] > 1e-12 * scale  # one axis without inertia, not two
        held = _held_axis(deck, body, position, R0, centre, axis) if line else None
        if held is None:
            raise _fail(deck, body.where, f"BODIES {body.id}: a free body's mass matrix (its "
                        f"own {body.mass:g} kg, {inertia.diagonal().tolist()} kg m2, plus "
                        f"{len(points)} point mass(es) and {len(body_rods)} rod(s) on it) is "
                        "singular: " + ("no mass" if mass <= 0 else
                                        "no inertia about two axes (all its mass at one "
                                        "point)" if lowest[1] <= 1e-12 * scale else
                                        f"no inertia about the axis {axis.tolist()} through "
                                        f"its centre of mass {centre.tolist()} (all its "
                                        "masses on that line), and a load that can turn it "
                                        "about that line (a point off it, a volume or a "
                                        "drag area)")
                        + ": give the body a Mass and an inertia I")
    volumes = [(body.volume, com)] + [(p.volume, position + r) for p, r in zip(points, offsets)]
    volume = sum(v for v, _ in volumes)
    hydro = None
    if volume > 0:  # MoorDyn: buoyancy rho g V at each volume's place, submerged or not
        hydro = Hydrostatics.submerged(volume, sum(v * c for v, c in volumes) / volume,
                                       position)
    added = deck.rho * body.volume * np.diag(_six(body.Ca, "Ca"))
    for p, r in zip(points, offsets):  # Point.cpp: Ca rho V E at the point
        added = added + point_mass_matrix(deck.rho * p.volume * p.Ca, r)
    return RigidBody(mass, centre, total, reference_point=position, hydrostatics=hydro,
                     added_mass=added, rho=deck.rho, g=deck.g, rotations=rotations,
                     line_of_masses=held is not None), held


def _held_axis(deck: Deck, body, position, R0, centre, axis):
    """(a, b, extent) for :func:`_body_rigid` of a body with no inertia about ``axis``
    through ``centre`` (global, at the deck's attitude), or None when a load could turn
    it about that line: a body volume or drag area, or a point of the body off the line
    (its weight, buoyancy, drag and lines act at its points). Nothing then drives the
    rotation about the line (every force on it passes through it: no moment), which
    MoorDyn's QR solve of M a = F leaves at zero; skmoor holds it with a torsional spring,
    as a free rod's spin (:class:`~skmoor.bodies.rod_loads.SpinLoad`), and says so."""
    if body.volume or any(_six(body.CdA, "CdA")):
        return None
    places = [position + R0 @ np.array(p.position, float) for p in deck.points
              if p.kind == "body" and p.body == body.id] or [centre]
    along = [float((r - centre) @ axis) for r in places]
    off = [np.linalg.norm(r - centre - s * axis) for r, s in zip(places, along)]
    extent = max(along) - min(along)
    if max(off) > 1e-9 * max(extent, 1.0):
        return None
    warnings.warn(f"{deck.source} line {body.where}: BODIES {body.id}: no inertia about the "
                  f"axis {axis.tolist()} through its centre of mass {centre.tolist()} (all "
                  "its masses and points on that line, so nothing turns it about it either): "
                  "its rotation about that line is held by a torsional spring (MoorDyn "
                  "leaves it at zero); give the body an inertia I to free it",
                  stacklevel=user_stacklevel())
    a = centre - position
    return a, a + axis, max(extent, 1.0)


def _spins_freely(deck: Deck, body, cg, rod) -> bool:
    """True when nothing holds a body on one rod about the rod's axis in statics: no
    mass of its own, or its centre of mass, all its points and its pinned rods' pins on
    the axis (body frame); a pinned rod that carries no line may pin off a vertical axis
    (it pulls there with its weight and buoyancy alone, vertical)."""
    if body.mass <= 0 and not _massive_points(deck, body):
        return True
    a, b = np.array(rod.a, float), np.array(rod.b, float)
    axis = (b - a) / np.linalg.norm(b - a)
    points = [cg] * (body.mass > 0) + [np.array(p.position, float) for p in deck.points
                                       if p.kind == "body" and p.body == body.id]
    vertical = abs(abs(axis[2]) - 1) < 1e-9 and np.allclose(body.r6[3:5], 0.0)
    for r in deck.rods:
        if r.kind == "body" and r.body == body.id and r.pinned:
            carries = any(end in (f"R{r.id}A", f"R{r.id}B")
                          for line in deck.lines for end in (line.a, line.b))
            if carries or not vertical:
                points.append(np.array(r.a, float))
    return all(np.linalg.norm(np.cross(x - a, axis)) < 1e-9 * max(1.0, np.linalg.norm(b - a))
               for x in points)


def _rod_bed(deck: Deck):
    """MoorDyn's bottom for the rods: (depth m, kBot N/m3, cBot N s/m3), None if kBot = 0."""
    return (deck.depth, deck.option("kBot"), deck.option("cBot")) if deck.option("kBot") else None


def _rod_type(deck: Deck, rod) -> RodType:
    t = deck.rod_types[rod.type]
    return RodType(t.name, t.diameter, t.mass, t.Cd, t.Ca, t.CdEnd, t.CaEnd)


def _deck_rod(deck: Deck, rod, bodies, sea, bed=None, rotations="small"):
    """(points, body or None) of a deck rod: its end points ``rodN.A``, ``rodN.B`` and,
    for a free or pinned rod, its own dynamic body (with ``rotations``)."""
    name = f"rod{rod.id}"
    a, b = np.array(rod.a, float), np.array(rod.b, float)
    if rod.n_segments == 0:  # a zero-length Free rod: a massless junction of its lines
        return [Point(name, "free", a, smooth=_joins_smoothly(deck, rod))], None
    if rod.kind == "body":
        carrier = bodies[rod.body - 1]
        if not rod.pinned:
            return [Point(f"{name}.A", "body", a, body=carrier.name),
                    Point(f"{name}.B", "body", b, body=carrier.name)], None
        R0 = carrier.rotation_matrix()
        pin = Point(f"{name}.pin", "body", a, body=carrier.name)  # where end A is held
        a, b = carrier.position + R0 @ a, carrier.position + R0 @ b
        if carrier.kind in ("coupled", "dynamic"):  # on a free body: a joint of the two
            body, ends = rods.rod(name, _rod_type(deck, rod), a, b, pin=pin.name,
                                  n_segments=rod.n_segments, rho=deck.rho, g=deck.g, sea=sea,
                                  bed=bed, rotations=rotations)
            return [pin, *ends], body
        kind = "pinned"
    else:
        kind = rod.kind
    if kind == "fixed":
        return [Point(f"{name}.A", "fixed", a), Point(f"{name}.B", "fixed", b)], None
    if kind == "coupled":  # a coupled body at end A, its attitude the deck's axis
        body, ends = rods.coupled_rod(name, _rod_type(deck, rod), a, b,
                                      n_segments=rod.n_segments, rho=deck.rho, g=deck.g,
                                      sea=sea, bed=bed)
        return ends, body
    pin = {"free": None, "pinned": "fixed", "coupled pinned": "coupled"}[kind]
    body, ends = rods.rod(name, _rod_type(deck, rod), a, b, pin=pin, n_segments=rod.n_segments,
                          rho=deck.rho, g=deck.g, sea=sea, bed=bed, rotations=rotations)
    return ends, body


def deck_network(deck: Deck | str | Path, *, motion=None, sea=None, hydro=True,
                 seabed=True, rotations="small") -> tuple[Network, dict]:
    """(Network, settings) of a deck (a :class:`~skmoor.io.deck.Deck` or a path).

    motion: fn(t) -> coupled-DOF displacements (see the module docstring), or None.
    sea: a :class:`skmoor.sea.waves.Sea` (currents, waves) in place of the deck's water;
    default: the deck's own (:func:`skmoor.io.sea_files.deck_sea`: its WaveKin and Currents
    files, still water without them), which is also what a WaveKin 1 deck's caller
    builds its waves on (``Sea(..., fields=deck_sea(deck).fields)``). hydro: add drag, fluid inertia and added mass
    (:func:`skmoor.sea.hydro.line_hydrodynamics`). seabed: add the deck's bottom contact
    (on the lines and the rods). rotations: 'small' or 'exact' for the free bodies and
    the free and pinned rods (:class:`~skmoor.bodies.body.RigidBody`; 'exact' for those that
    turn far).
    settings: the solver's defaults for the deck (Newmark, dtOut as the output interval;
    ``start='reference'`` when the deck gives TmaxIC = 0: MoorDyn then runs it from its
    given state, every line on its catenary between the points as given, no IC solve).
    """
    deck = read_deck(deck) if not isinstance(deck, Deck) else deck
    _check_options(deck)
    if deck.g < 0 or (deck.g == 0 and deck.option("WaveKin", 0.0)):
        raise _fail(deck, deck.option_lines.get("g", "?"), f"option g = {deck.g:g}: "
                    "gravity must be positive, or 0 in still water (waves need gravity)")
    if not deck.rho >= 0:
        raise _fail(deck, deck.option_lines.get("rho", "?"), f"option rho = {deck.rho:g}: "
                    "the water density must be positive, or 0 (in air)")
    bathymetry = deck_bathymetry(deck)
    sea = deck_sea(deck, bathymetry) if sea is None else sea
    bed = _rod_bed(deck) if seabed else None
    if rotations not in ("small", "exact"):
        raise ValueError(f"rotations: {rotations!r} is not 'small' or 'exact'")
    bodies = [_deck_body(deck, b, sea, bed, rotations) for b in deck.bodies]
    points = []
    for rod in deck.rods:
        ends, body = _deck_rod(deck, rod, bodies[:len(deck.bodies)], sea, bed, rotations)
        points += ends
        if body is not None:
            bodies.append(body)
    for p in deck.points:
        kind = p.kind
        on_body = kind == "body" and deck.bodies[p.body - 1].kind not in ("fixed", "coupled")
        if kind == "body" and (p.mass or p.volume) and not on_body:
            raise _fail(deck, p.where, f"POINTS {p.id}: mass or volume on a point of a "
                        "fixed or coupled body is not supported (it moves as given)")
        if p.force and any(p.force):
            raise _fail(deck, p.where, f"POINTS {p.id}: a constant point force is not supported")
        points.append(Point(f"point{p.id}", kind, p.position,
                            body=f"body{p.body}" if kind == "body" else None,
                            mass=0.0 if on_body else p.mass,  # in its body's RigidBody
                            volume=0.0 if on_body else p.volume, CdA=p.CdA, Ca=p.Ca))
    lines = []
    for line in deck.lines:
        line_type = line_type_of(deck, line)
        clamps = ({} if not line_type.EI > 0 else
                  {"clamp_a": _rod_clamp(deck, line.a, "a"), "clamp_b": _rod_clamp(deck, line.b, "b")})
        lines.append(MooringLine(f"line{line.id}", line_type, _end_name(deck, line.a),
                                 _end_name(deck, line.b), line.length, int(line.n_segments),
                                 **clamps))
    failures = [LineFailure(_end_name(deck, f.point), [f"line{k}" for k in f.lines],
                            f.time or None, f.tension or None) for f in deck.failures]
    try:
        network = Network(points, lines, bodies, depth=deck.depth, rho=deck.rho, g=deck.g,
                          sea=sea, hydro=hydro, strain_law="engineering",
                          motion=_network_motion(deck, motion), surface=True,
                          failures=failures)
    except ValueError as err:
        raise ValueError(f"{deck.source}: {err}") from None
    if "dtM" in deck.options:  # MoorDyn's VIV rms runs over 500 of its steps dtM
        network.viv_rms_time = RMS_STEPS * deck.option("dtM")
    if seabed and lines:  # the lines' bed (the rods' is their own, above)
        network.seabed = _seabed(deck, network, bathymetry)
    dt_out = deck.option("dtOut") or None
    no_ic = "TmaxIC" in deck.options and deck.option("TmaxIC") == 0  # MoorDyn: no IC stage
    ic = {"tmax": deck.option("TmaxIC", 120.0), "dt_check": deck.option("dtIC", 1.0),
          "threshold": deck.option("threshIC", 0.01)}  # MoorDyn's IC stage (its defaults)
    settings = {"solver": {"scheme": "newmark", "duration": 60.0, "ic": ic,
                           **({"output_interval": dt_out} if dt_out else {}),
                           **({"start": "reference"} if no_ic else {})},
                "damping": {"ratio": 0.0}, "load": {}}
    return network, settings


def _network_motion(deck: Deck, motion):
    """The network's coupled-DOF motion from MoorDyn's coupled-DOF vector: a
    CoupledPinned body takes 6 entries there (MoorDyn's NCoupledDOF) of which its
    position, the first 3, is used."""
    if motion is None or not any(b.kind == "pinned" for b in deck.bodies):
        return motion
    keep, start = [], 0
    for size, body in zip(deck.coupled_sizes, _coupled_kinds(deck)):
        keep += list(range(start, start + (3 if body == "pinned" else size)))
        start += size

    def network_motion(t):
        return np.asarray(motion(t), float)[keep]

    return network_motion


def _coupled_kinds(deck: Deck) -> list:
    """The kind of each coupled object in MoorDyn's order (as Deck.coupled_sizes)."""
    return ([b.kind for b in deck.bodies if b.kind in ("coupled", "pinned")]
            + [r.kind for r in deck.rods if r.kind in ("coupled", "coupled pinned")]
            + ["point" for p in deck.points if p.kind == "coupled"])


def _rod_clamp(deck: Deck, end, side):
    """The clamp of a bending line's end ``side`` ('a' or 'b') on a rod's end: the line
    leaves the rod along its axis (global, at the deck's state), as MoorDyn attaches it,
    and turns with the rod (False on a point: pinned; and on a zero-length rod, which
    joins its lines itself: :func:`_joins_smoothly`)."""
    if isinstance(end, int):
        return False
    rod = next(r for r in deck.rods if r.id == int(end[1:-1]))
    if rod.n_segments == 0:
        return False
    axis = np.asarray(rod.b, float) - np.asarray(rod.a, float)  # A -> B
    if rod.kind == "body":  # the rod's ends are in its body's frame
        carrier = next(b for b in deck.bodies if b.id == rod.body)
        axis = moordyn_rotation(np.radians(np.asarray(carrier.r6[3:], float))) @ axis
    outward = axis if end[-1] == "B" else -axis  # out of the rod at that end
    return outward if side == "a" else -outward  # the line's tangent runs a -> b


def _joins_smoothly(deck: Deck, rod) -> bool:
    """Whether a zero-length rod is a smooth joint (``Point.smooth``) of its lines: two
    bending lines, one ending on it and one starting from it, on its two different ends.
    MoorDyn clamps both to the rod's direction q there (Line.cpp's setEndOrientation:
    both then run along q, or both along -q) and turns q to balance their end moments
    (Rod.cpp's setDependentStates): one shared end tangent, the moment carried across.
    Any other set of lines on it is pinned there (a hinge)."""
    tag = f"R{rod.id}"
    ending = [(ln, ln.b[-1]) for ln in deck.lines if isinstance(ln.b, str) and ln.b[:-1] == tag]
    starting = [(ln, ln.a[-1]) for ln in deck.lines if isinstance(ln.a, str) and ln.a[:-1] == tag]
    if len(ending) != 1 or len(starting) != 1 or ending[0][1] == starting[0][1]:
        return False
    return all(line_type_of(deck, ln).EI > 0 for ln, _ in ending + starting)


def _end_name(deck: Deck, end) -> str:
    """The network point of a deck line end: a point number, or a rod end 'R<N>A' (both
    ends of a zero-length rod are its one point ``rodN``)."""
    if isinstance(end, int):
        return f"point{end}"
    rod = next(r for r in deck.rods if r.id == int(end[1:-1]))
    return f"rod{rod.id}" if rod.n_segments == 0 else f"rod{rod.id}.{end[-1]}"


def _seabed(deck: Deck, network: Network, bathymetry=None):
    """MoorDyn's bottom for the deck's lines (pressures kBot, cBot on each line's
    diameter; on the deck's bathymetry if it has one), or None when kBot = 0."""
    if deck.option("kBot") == 0:
        return None
    depth = deck.depth
    mu = deck.option("FrictionCoefficient")
    mu_axial, mu_lateral = deck.option("mu_kA", mu), deck.option("mu_kT", mu)
    friction = {}
    if mu_axial or mu_lateral:  # MoorDyn's viscous ramp mu FricDamp v, capped at mu N
        segment = max(line.line_type.weight * line.length / line.n_elements
                      for line in network.lines)
        friction = dict(mu_axial=mu_axial, mu_lateral=mu_lateral,
                        friction_velocity=segment / deck.option("FricDamp"))
    return Seabed(depth, stiffness=deck.option("kBot"), damping=deck.option("cBot"),
                  per_diameter=True, bathymetry=bathymetry, **friction)


def heave_motion(deck: Deck, amplitude: float, period: float, ramp=None):
    """(motion, velocity): fn(t) -> coupled-DOF vectors in which every coupled object
    heaves A sin(2 pi t / T) (m), faded in over ``ramp`` s (default: one period) by
    (1 - cos(pi t / ramp)) / 2."""
    if not period > 0:
        raise ValueError(f"heave period: must be positive, got {period}")
    ramp = float(period if ramp is None else ramp)
    omega = 2 * np.pi / period
    heave, start = [], 0
    for size in deck.coupled_sizes:
        heave.append(start + 2)
        start += size
    n = start

    def fade(t):
        if ramp <= 0 or t >= ramp:
            return 1.0, 0.0
        return (0.5 * (1 - np.cos(np.pi * t / ramp)),
                0.5 * np.pi / ramp * np.sin(np.pi * t / ramp))

    def motion(t):
        y = np.zeros(n)
        y[heave] = amplitude * fade(t)[0] * np.sin(omega * t)
        return y

    def velocity(t):
        f, df = fade(t)
        y = np.zeros(n)
        y[heave] = amplitude * (df * np.sin(omega * t) + f * omega * np.cos(omega * t))
        return y

    return motion, velocity


def read_motion(path, n_dofs: int):
    """motion(t) from a time-series file: whitespace- or comma-separated columns, the time
    (s) first, then the coupled DOFs' displacements from the deck's positions in MoorDyn's
    order (6 per coupled body: m, m, m, rad, rad, rad; then 3 per coupled point, m); lines
    starting with '#' are comments. A :class:`~skmoor.bodies.motion.Record`: a cubic
    spline through the rows with its own velocity and acceleration, held at the first /
    last row outside the table; a step costs the same for a record of any length."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"--motion: no such file {path}")
    if is_openfast_output(path):
        raise ValueError(f"{path.name}: an OpenFAST output file; its platform motion is "
                         "read with skmoor.openfast_motion(path, deck)")
    try:
        text = path.read_text().replace(",", " ")
        table = np.loadtxt(text.splitlines(), comments="#", ndmin=2)
    except ValueError as err:
        raise ValueError(f"{path.name}: not a table of numbers ({err})") from None
    if table.shape[1] != n_dofs + 1:
        raise ValueError(f"{path.name}: {table.shape[1]} columns, expected the time and "
                         f"{n_dofs} coupled DOFs ({n_dofs + 1})")
    if not np.all(np.isfinite(table)):
        raise ValueError(f"{path.name}: contains NaN or inf")
    if len(table) < 2 or np.any(np.diff(table[:, 0]) <= 0):
        raise ValueError(f"{path.name}: the times must increase row by row (two rows or more)")
    return Record(table[:, 0], table[:, 1:])


def default_time_step(model, period=None) -> float:
    """dt (s): 0.05 s, cut to resolve a node bouncing on the bed (an eighth of the period
    of its contact spring, with the added mass) and a motion period (1/100 of it)."""
    dt = 0.05
    bed = model.network.seabed
    if bed is not None:
        k, _ = bed.cell_coefficients(model.lines)
        m = np.array([lt.mass + lt.Ca_n * lt.rho_water * lt.area for lt in
                      (line.line_type for line in model.lines.lines)])[model.lines.line_of_cell]
        dt = min(dt, float(np.min(2 * np.pi * np.sqrt(m / k) / 8)))
    if period:
        dt = min(dt, period / 100)
    return float(dt)
