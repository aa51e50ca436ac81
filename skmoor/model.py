"""From a :class:`~skmoor.case.Case` to a coupled model: the draft, the lines' reference
catenaries, the rigid body and the :class:`~skmoor.coupling.System` that joins them."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from . import environment
from .body import RigidBody
from .catenary import solve_catenary
from .coupling import System
from .line import Line, LineSet, LineType


@dataclass
class Model:
    """A built case: ``system`` (reduced lines + body), ``lines`` (LineSet), ``body``,
    ``catenaries`` (the analytic reference of each line), ``draft`` (m)."""

    case: object
    system: System
    lines: LineSet
    body: RigidBody
    catenaries: list
    draft: float

    @property
    def forcing_period(self) -> float | None:
        omega = self.case.load.get("omega")
        return 2 * np.pi / omega if omega else None


def line_type(case, name) -> LineType:
    """The LineType ``name`` of a case (from EA, mass, diameter or from E, diameter, density;
    optional Morison coefficients Cd_n, Cd_t, Ca_n, Ca_t and internal damping BA, N s)."""
    t = case.data["line_types"][name]
    extra = {key: float(t[key]) for key in ("Cd_n", "Cd_t", "Ca_n", "Ca_t", "BA") if key in t}
    rho, g = case.water["density"], case.water["gravity"]
    if "EA" in t:
        return LineType(EA=t["EA"], mass=t["mass"], diameter=t["diameter"], weight=t.get("weight"),
                        rho_water=rho, g=g, **extra)
    return LineType.steel_rod(t["diameter"], E=t["E"], density=t["density"], rho_water=rho,
                              g=g, **extra)


def _anchor(spec, fairlead, depth):
    """Anchor of a line given by chord angle and heading (on the sea bed at -depth)."""
    if spec.anchor is not None:
        return spec.anchor
    heading = (np.deg2rad(spec.heading_deg) if spec.heading_deg is not None
               else np.arctan2(spec.fairlead[1], spec.fairlead[0]))
    rise = fairlead[2] + depth
    if rise <= 0:
        raise ValueError(f"line {spec.name}: fairlead at z = {fairlead[2]:.3f} m is below the sea bed")
    run = rise / np.tan(np.deg2rad(spec.chord_angle_deg))
    return fairlead + np.array([run * np.cos(heading), run * np.sin(heading), -rise])


def reference_catenaries(case, draft):
    """(specs, catenaries, types) of all lines with the box floating at ``draft`` (m)."""
    height = case.body["size"][2]
    com = np.array([0.0, 0.0, height / 2 - draft])
    depth = case.water["depth"]
    specs, cats, types = case.line_specs(), [], []
    lengths = {}  # lines alike in their plane share the length a sag ratio gives
    for spec in specs:
        lt = line_type(case, spec.type)
        fairlead = com + spec.fairlead
        anchor = _anchor(spec, fairlead, depth)
        chord = fairlead - anchor
        key = (round(float(np.hypot(*chord[:2])), 9), round(float(chord[2]), 9),
               round(float(anchor[2] + depth), 9), lt.weight, lt.EA, spec.sag_ratio)
        length = spec.length if spec.length is not None else lengths.get(key)
        try:
            cat = solve_catenary(anchor, fairlead, lt.weight, lt.EA, length=length,
                                 sag_ratio=None if length is not None else spec.sag_ratio,
                                 seabed_z=-depth)
            lengths[key] = cat.L
        except ValueError as err:
            raise ValueError(f"line {spec.name}: {err}") from None
        cats.append(cat)
        types.append(lt)
    return specs, cats, types


def equilibrium_draft(case) -> float:
    """Draft of the box from vertical equilibrium (paper Eq. 1):
    rho g h_s A = M g + sum of the lines' vertical pulls, m."""
    rho, g = case.water["density"], case.water["gravity"]
    length, width, height = case.body["size"]
    mass = case.body["mass"]

    def imbalance(h):
        _, cats, _ = reference_catenaries(case, h)
        return rho * g * h * length * width - mass * g - sum(c.V_fairlead for c in cats)

    top = 0.999 * height
    if imbalance(top) < 0:
        raise ValueError("body.mass: the box sinks (buoyancy at full immersion is below the "
                         "weight plus the lines' pull)")
    return brentq(imbalance, 1e-6 * height, top, xtol=1e-12)


def build(case) -> Model:
    """The coupled model of ``case`` in its reference state (lines on their catenaries)."""
    body_data = case.body
    draft = body_data.get("draft", "equilibrium")
    draft = equilibrium_draft(case) if draft == "equilibrium" else float(draft)
    specs, cats, types = reference_catenaries(case, draft)
    lines = LineSet([Line.from_catenary(c, t, s.n_elements, name=s.name)
                     for s, c, t in zip(specs, cats, types)], law=case.strain_law)
    length, width, height = body_data["size"]
    body = RigidBody.box(length, width, height, body_data["mass"], draft,
                         rho=case.water["density"], g=case.water["gravity"])
    cable_terms, body_terms = environment.terms(case.data, lines, body)
    system = System(lines, body, body_load=body_load(case), terms=cable_terms,
                    body_terms=body_terms)
    return Model(case, system, lines, body, cats, draft)


def body_load(case):
    """The case's applied body load as f(t, q, qdot) -> 6-vector (N, N m), or None."""
    load = case.load
    if not load or load.get("amplitude", 0) == 0:
        return None
    amplitude, omega = float(load["amplitude"]), float(load["omega"])
    direction = np.asarray(load.get("direction", [1, 0, 0, 0, 0, 0]), float)

    def applied(t, q, qdot):
        return amplitude * np.sin(omega * t) * direction

    return applied
