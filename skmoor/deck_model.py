"""A MoorDyn v2 deck as an skmoor model, and a run of it (:func:`run_deck`).

Each deck line must hang from a fixed point (an anchor; a point of a fixed body) to a
moving one (a 'Coupled' / 'Vessel' point, or a point of a coupled body): its reference
state is the analytic elastic catenary between them, seabed touchdown included, on
NumSegs elements with MoorDyn's strain law (tension = EA x engineering strain).
MoorDyn's coefficient conventions carry over: Cd -> Cd_n, CdAx -> Cd_t, Ca -> Ca_n,
CaAx -> Ca_t; the submerged weight is (Mass/m - rho pi d^2/4) g; the internal damping
BA (N s, or -zeta: BA = zeta (L / NumSegs) sqrt(EA Mass/m) as MoorDyn sets it) damps the
axial strain rate (``LineType.BA``). Drag and added mass come from
:func:`skmoor.hydro.line_hydrodynamics` (MoorDyn's conventions, still water unless a
``Sea`` is given). The bottom is MoorDyn's (as :meth:`skmoor.seabed.Seabed.from_moordyn`:
stiffness kBot d, damping cBot d per unit length), its damping faded in over the first
tenth of the static penetration w / (kBot d), 13 mm for the chain decks (the bed's
default ``damping_onset``; MoorDyn's jump there leaves the implicit step without a
solution); MoorDyn-C's friction (a viscous ramp mu FricDamp v capped at mu N) maps to
the bed's regularised Coulomb law with the same slope and cap (slip velocity
v0 = N / FricDamp, N a segment's weight).

The coupled objects move as the caller says: ``motion(t)`` returns their displacements
from the deck's positions in MoorDyn's order of coupled DOFs (6 per coupled body:
x, y, z in m and roll, pitch, yaw in rad; then 3 per coupled point). Without a motion
they stay where the deck puts them.

Refused, with the deck line and the reason: free points (line junctions, clump weights,
buoys), free or pinned bodies, lines between two fixed or two moving points, bending
stiffness (EI > 0), VIV (Cl > 0), MoorDyn's wave / current / seafloor files.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .catenary import solve_catenary
from .coupling import System
from .deck import Deck, read_deck
from .dynamics import Scheme
from .hydro import line_hydrodynamics
from .line import Line, LineSet, LineType
from .results import Results
from .run import INTERRUPTED, record_run, write_outputs
from .seabed import Seabed, seabed_term
from .statics import solve_static
from .waves import Sea

__all__ = ["DeckModel", "build_deck", "simulate_deck", "run_deck", "heave_motion"]


@dataclass
class DeckModel:
    """A deck built into a :class:`~skmoor.coupling.System` (fairleads 'prescribed' by
    ``motion``, or 'fixed' without one).

    catenaries: the analytic reference of each line (anchor first). coupled: the moving
    objects in MoorDyn's coupled-DOF order; fairlead_of: what each line's fairlead
    follows (a coupled point, or a body point with its position in the body frame).
    """

    deck: Deck
    system: System
    lines: LineSet
    catenaries: list
    seabed: Seabed | None
    coupled: list  # ('body', id) / ('point', id) in MoorDyn's coupled-DOF order
    fairlead_of: list  # per line: ('body', id, r_local) or ('point', id)
    motion: object = None

    @property
    def n_coupled_dofs(self) -> int:
        return sum(6 if kind == "body" else 3 for kind, _ in self.coupled)

    def fairlead_displacement(self, y) -> np.ndarray:
        """(nlines, 3) fairlead displacements (m) for coupled-DOF displacements y."""
        y = np.asarray(y, float).ravel()
        if y.shape != (self.n_coupled_dofs,):
            raise ValueError(f"deck motion: expected {self.n_coupled_dofs} coupled DOFs "
                             f"({self._dof_names()}), got {y.shape}")
        start, offsets = 0, {}
        for kind, ident in self.coupled:
            size = 6 if kind == "body" else 3
            offsets[(kind, ident)] = y[start:start + size]
            start += size
        out = np.zeros((len(self.fairlead_of), 3))
        for k, end in enumerate(self.fairlead_of):
            q = offsets[end[:2]]
            if end[0] == "point":
                out[k] = q
            else:
                body = self.deck.bodies[end[1] - 1]
                angles0 = np.radians(body.r6[3:])
                r = end[2]
                out[k] = (q[:3] + rotation_matrix(angles0 + q[3:]) @ r
                          - rotation_matrix(angles0) @ r)
        return out

    def _dof_names(self):
        return ", ".join(f"{kind} {ident}" for kind, ident in self.coupled)

    def coupled_positions(self) -> np.ndarray:
        """MoorDyn's coupled-DOF vector of the deck's positions (body angles in rad)."""
        parts = []
        for kind, ident in self.coupled:
            if kind == "body":
                r6 = np.array(self.deck.bodies[ident - 1].r6, float)
                parts.append(np.r_[r6[:3], np.radians(r6[3:])])
            else:
                parts.append(np.array(self.deck.point(ident).position, float))
        return np.concatenate(parts) if parts else np.zeros(0)


def rotation_matrix(angles) -> np.ndarray:
    """MoorDyn's body rotation for angles (roll, pitch, yaw) in rad: R = Rx Ry Rz (not
    skmoor's Rz Ry Rx; measured against MoorDyn 2.7's body point positions)."""
    (cx, cy, cz), (sx, sy, sz) = np.cos(angles), np.sin(angles)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]])
    ry = np.array([[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]])
    rz = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
    return rx @ ry @ rz


def _fail(deck, where, what):
    return ValueError(f"{deck.source} line {where}: {what}")


def line_type_of(deck: Deck, line) -> LineType:
    """skmoor's LineType of a deck line (its type, MoorDyn's coefficient conventions, and
    its internal damping BA, which MoorDyn sets per line from -zeta)."""
    name = line.type
    t = deck.line_types[name]
    if t.EI != 0:
        raise _fail(deck, t.where, f"LINE TYPES {name}: EI = {t.EI:g} N m2: bending "
                    "stiffness is not supported (skmoor lines are cables)")
    if t.viv and t.viv[0] > 0:
        raise _fail(deck, t.where, f"LINE TYPES {name}: Cl = {t.viv[0]:g}: vortex-induced "
                    "vibration is not supported")
    return LineType(EA=t.EA, mass=t.mass, diameter=t.diameter, Cd_n=t.Cd, Cd_t=t.CdAx,
                    Ca_n=t.Ca, Ca_t=t.CaAx, BA=_internal_damping(deck, line),
                    rho_water=deck.rho, g=deck.g)


def _check_options(deck: Deck):
    for name in ("WaveKin", "Currents"):
        if deck.option(name, 0.0) != 0:
            raise _fail(deck, deck.option_lines[name], f"option {name} = "
                        f"{deck.options[name]}: MoorDyn's wave / current input files are "
                        "not supported (give a skmoor.waves.Sea)")
    for name in ("SeafloorFile", "WaterKin"):
        if name in deck.options:
            raise _fail(deck, deck.option_lines[name], f"option {name}: bathymetry / "
                        "water-kinematics files are not supported (flat bed, still water)")


def _end(deck: Deck, line, point_id):
    """(kind 'fixed' or 'coupled', global position in m, what the end follows: ('point',
    id) or ('body', id, position in the body frame))."""
    p = deck.point(point_id)
    if p.kind == "free":
        raise _fail(deck, line.where, f"LINES {line.id}: point {p.id} is 'Free' (deck line "
                    f"{p.where}): free points (line junctions, clump weights, buoys) are "
                    "not supported; end each line at a fixed and a coupled point")
    if p.kind in ("fixed", "coupled"):
        return p.kind, np.array(p.position, float), ("point", p.id)
    body = deck.bodies[p.body - 1]
    if body.kind not in ("fixed", "coupled"):
        raise _fail(deck, body.where, f"BODIES {body.id}: a {body.kind} body (point {p.id} "
                    "is on it): only fixed and coupled bodies are supported")
    r_local = np.array(p.position, float)
    r = rotation_matrix(np.radians(body.r6[3:])) @ r_local
    position = np.array(body.r6[:3], float) + r
    return body.kind, position, ("body", body.id, r_local)


def _coupled_order(deck: Deck):
    """Coupled bodies, then coupled points, as MoorDyn numbers its coupled DOFs."""
    return ([("body", b.id) for b in deck.bodies if b.kind == "coupled"]
            + [("point", p.id) for p in deck.points if p.kind == "coupled"])


def _internal_damping(deck: Deck, line) -> float:
    """BA of a deck line, N s (MoorDyn: -zeta -> zeta (L/N) sqrt(EA Mass/m))."""
    t = deck.line_types[line.type]
    if t.BA >= 0:
        return t.BA
    return -t.BA * line.length / line.n_segments * np.sqrt(t.EA * t.mass)


def build_deck(deck: Deck | str | Path, *, motion=None, sea=None, hydro=True,
               seabed=True) -> DeckModel:
    """Build the skmoor model of a deck (a :class:`~skmoor.deck.Deck` or a path).

    motion: fn(t) -> coupled-DOF displacements (see the module docstring), or None.
    sea: a :class:`skmoor.waves.Sea` (currents, waves); default: still water of the
    deck's depth, rho and g. hydro: add drag, fluid inertia and added mass
    (:func:`skmoor.hydro.line_hydrodynamics`). seabed: add the deck's bottom contact.
    """
    deck = read_deck(deck) if not isinstance(deck, Deck) else deck
    _check_options(deck)
    depth = deck.depth
    lines, catenaries, fairlead_of = [], [], []
    for line in deck.lines:
        lt = line_type_of(deck, line)
        ends = [_end(deck, line, line.a), _end(deck, line, line.b)]
        kinds = sorted(e[0] for e in ends)
        if kinds != ["coupled", "fixed"]:
            raise _fail(deck, line.where, f"LINES {line.id}: ends {line.a} and {line.b} are "
                        f"both {kinds[0]}: each line must run from a fixed point to a "
                        "coupled one")
        anchor, fairlead = (ends if ends[0][0] == "fixed" else ends[::-1])
        try:
            cat = solve_catenary(anchor[1], fairlead[1], lt.weight, lt.EA,
                                 length=line.length, seabed_z=-depth)
        except ValueError as err:
            raise _fail(deck, line.where, f"LINES {line.id}: no catenary: {err}") from None
        lines.append(Line.from_catenary(cat, lt, line.n_segments, name=f"line{line.id}"))
        catenaries.append(cat)
        fairlead_of.append(fairlead[2])
    lineset = LineSet(lines, law="engineering")
    terms = []
    bed = _seabed(deck, lineset, depth) if seabed else None
    if bed is not None:
        terms.append(seabed_term(lineset, bed, fast=True))
    if hydro:
        sea = Sea(depth, rho=deck.rho, g=deck.g) if sea is None else sea
        terms += line_hydrodynamics(lineset, sea, fast=True)
    model = DeckModel(deck, None, lineset, catenaries, bed, _coupled_order(deck),
                      fairlead_of, motion)
    if motion is None:
        model.system = System(lineset, fairleads="fixed", terms=terms)
    else:
        model.system = System(lineset, fairleads="prescribed", terms=terms,
                              motion=lambda t: model.fairlead_displacement(motion(t)))
    return model


def _seabed(deck: Deck, lines: LineSet, depth: float):
    """MoorDyn's bottom for the deck's lines (one diameter), or None when kBot = 0."""
    if deck.option("kBot") == 0:
        return None
    diameters = sorted({line.line_type.diameter for line in lines.lines})
    if len(diameters) > 1:
        raise ValueError(f"{deck.source}: lines of different diameters ({diameters} m) "
                         "on MoorDyn's bottom (pressures kBot, cBot on d l) are not "
                         "supported yet")
    mu = deck.option("FrictionCoefficient")
    mu_axial, mu_lateral = deck.option("mu_kA", mu), deck.option("mu_kT", mu)
    friction = {}
    if mu_axial or mu_lateral:  # MoorDyn's viscous ramp mu FricDamp v, capped at mu N
        segment = max(line.line_type.weight * line.length / line.n_elements
                      for line in lines.lines)
        friction = dict(mu_axial=mu_axial, mu_lateral=mu_lateral,
                        friction_velocity=segment / deck.option("FricDamp"))
    return Seabed(depth, stiffness=deck.option("kBot") * diameters[0],
                  damping=deck.option("cBot") * diameters[0], **friction)


# ------------------------------------------------------------------------ running

def heave_motion(deck: Deck, amplitude: float, period: float, ramp=None):
    """(motion, velocity): fn(t) -> coupled-DOF vectors in which every coupled object
    heaves A sin(2 pi t / T) (m), faded in over ``ramp`` s (default: one period) by
    (1 - cos(pi t / ramp)) / 2."""
    if not period > 0:
        raise ValueError(f"heave period: must be positive, got {period}")
    ramp = float(period if ramp is None else ramp)
    omega = 2 * np.pi / period
    heave, start = [], 0
    for kind, _ in _coupled_order(deck):
        heave.append(start + 2)
        start += 6 if kind == "body" else 3
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


def default_time_step(model: DeckModel, period=None) -> float:
    """dt (s): 0.05 s, cut to resolve a node bouncing on the bed (an eighth of the period
    of its contact spring, with the added mass) and a motion period (1/100 of it)."""
    dt = 0.05
    if model.seabed is not None:
        k, _ = model.seabed.coefficients(model.lines)
        m = max(lt.mass + lt.Ca_n * lt.rho_water * lt.area
                for lt in (line.line_type for line in model.lines.lines))
        dt = min(dt, 2 * np.pi * np.sqrt(m / k) / 8)
    if period:
        dt = min(dt, period / 100)
    return float(dt)


def simulate_deck(model: DeckModel, *, duration=60.0, dt=None, output_interval=None,
                  scheme=None, progress=False) -> Results:
    """Static equilibrium, then the time history (Newmark by default) of a built deck;
    sampled every ``output_interval`` s (default: the deck's dtOut, else every step)."""
    started = time.perf_counter()
    dt = float(dt or default_time_step(model))
    if not duration > 0:
        raise ValueError(f"deck duration: must be positive, got {duration}")
    out_dt = output_interval or model.deck.option("dtOut") or dt
    every = max(1, int(round(out_dt / dt)))
    system = model.system
    static = solve_static(system)
    recorder = _Recorder(model)
    n_steps = int(np.ceil(duration / dt - 1e-9))
    stopped = record_run(system, static.x, dt=dt, duration=duration, every=every,
                         record=recorder.record, scheme=scheme or Scheme.newmark(),
                         progress=progress, label=model.deck.source)
    first = recorder.rows["fair"][0] if recorder.rows["fair"] else []
    meta = {"case": model.deck.source, "deck": True, "dt": dt, "scheme": "newmark"
            if scheme is None else str(scheme), "wall_time": time.perf_counter() - started,
            "steps": n_steps, "stopped": stopped, "interrupted": stopped == INTERRUPTED,
            "fairlead_tension_static": [float(v) for v in first],
            "fairlead_tension_catenary": [c.T_fairlead for c in model.catenaries],
            "anchor_tension_catenary": [c.T_anchor for c in model.catenaries],
            "coupled": [f"{kind} {ident}" for kind, ident in model.coupled],
            "has_body": bool(model.coupled) and model.coupled[0][0] == "body",
            "notes": list(model.deck.notes)}
    return recorder.results(meta)


class _Recorder:
    """Sampled states of a deck run into a :class:`Results` (no body: zeros, or the
    first coupled body's prescribed motion)."""

    def __init__(self, model: DeckModel):
        self.model = model
        self.rows = {k: [] for k in ("t", "body", "u", "v", "tension", "strain", "fair",
                                     "anchor")}

    def record(self, state):
        model, system, lines = self.model, self.model.system, self.model.lines
        u = system.full_displacement(state.x, state.t)
        ud = system.full_velocity(state.x, state.v, state.t)
        fair, anchor = system.reactions(state.x, state.v, state.t)
        body = np.zeros(6)
        if model.motion is not None and model.coupled and model.coupled[0][0] == "body":
            body = np.asarray(model.motion(state.t), float)[:6]
        nodes = lines.nodal_dofs
        tension, strain = lines.element_tension_and_strain(u)
        for key, value in (("t", state.t), ("body", body), ("u", u[nodes]), ("v", ud[nodes]),
                           ("tension", tension), ("strain", strain),
                           ("fair", np.linalg.norm(fair, axis=1)),
                           ("anchor", np.linalg.norm(anchor, axis=1))):
            self.rows[key].append(value)

    def results(self, meta) -> Results:
        r, lines = {k: np.array(v) for k, v in self.rows.items()}, self.model.lines
        return Results(t=r["t"], body=r["body"].reshape(-1, 6), points=lines.points,
                       cells=lines.mesh.t.T.copy(), line_of_cell=lines.line_of_cell,
                       line_names=[line.name for line in lines.lines],
                       displacement=r["u"], velocity=r["v"], tension=r["tension"],
                       strain=r["strain"], fairlead_tension=r["fair"],
                       anchor_tension=r["anchor"], depth=self.model.deck.depth, meta=meta)


def run_deck(path, *, duration=None, dt=None, motion=None, out=None, output_interval=None,
             progress=False) -> tuple[Results, dict | None]:
    """Read and run a MoorDyn v2 deck: statics, then dynamics with the coupled objects
    moved by ``motion`` (fn(t) -> coupled-DOF displacements; None: they stay still).
    duration: s (default 60); dt: s (default :func:`default_time_step`). With ``out``
    writes results.npz, timeseries.csv and summary.json there. Returns (results, summary
    or None)."""
    model = build_deck(path, motion=motion)
    results = simulate_deck(model, duration=duration or 60.0, dt=dt,
                            output_interval=output_interval, progress=progress)
    info = write_outputs(results, out) if out is not None else None
    return results, info
