"""A case file's model as a network: the paper's parametric layout (the box at its draft on
catenaries) or the explicit tables of points, lines and bodies, with the line types, the
body's hydrostatics and its applied load.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..bodies.body import (
    RigidBody,
    hull_hydrostatics,
    hull_triangles,
    uniform_box_inertia,
)
from ..bodies.large_rotations import box_triangles
from ..coupling.network import Body, LineFailure, MooringLine, Network, Point
from ..io.paths import resolve_inside
from ..lines.catenary import solve_catenary
from ..lines.line import LineType
from ..numerics.roots import brent as brentq
from . import environment


def line_type(case, name) -> LineType:
    """The LineType ``name`` of a case (from EA, mass, diameter or from E, diameter, density;
    optional Morison coefficients Cd_n, Cd_t, Ca_n, Ca_t, internal damping BA, N s, and
    bending stiffness EI, N m2; strength and fatigue: MBL, N, MBR, m, fatigue_curve, d_nom, m)."""
    t = case.data["line_types"][name]
    extra = {key: float(t[key]) for key in ("Cd_n", "Cd_t", "Ca_n", "Ca_t", "BA", "EI", "MBL",
                                            "MBR", "d_nom")
             if key in t}
    if "fatigue_curve" in t:
        extra["fatigue_curve"] = t["fatigue_curve"]
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


def _hull_keel(case) -> float:
    """Lowest z of the case's hull mesh in the body frame (m), or -height/2 for the box."""
    hull = case.body.get("hull")
    if hull is None:
        return -case.body["size"][2] / 2
    import pyvista as pv
    return float(pv.read(_hull_path(case)).bounds[4]) if hull else 0.0


def _hull_path(case) -> Path:
    path = resolve_inside(case.body["hull"], case.directory, "body.hull")
    if not path.is_file():
        raise ValueError(f"body.hull: no such mesh file {path}")
    return path


def _com(case, draft) -> np.ndarray:
    """Centre of mass (the body's reference point) with the keel at z = -draft, m."""
    return np.array([0.0, 0.0, -draft - _hull_keel(case)])


def reference_catenaries(case, draft):
    """(specs, catenaries, types) of all lines with the body floating at ``draft`` (m)."""
    com = _com(case, draft)
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


def _hydrostatics(case, draft, reference_point):
    if case.body.get("hull") is None:
        return None
    return hull_hydrostatics(_hull_path(case), reference_point=reference_point,
                             offset=reference_point)


def _displaced_volume(case, draft) -> float:
    if case.body.get("hull") is None:
        length, width, _ = case.body["size"]
        return draft * length * width
    return _hydrostatics(case, draft, _com(case, draft)).volume


def equilibrium_draft(case) -> float:
    """Draft of the body from vertical equilibrium (paper Eq. 1):
    rho g V(h_s) = M g + sum of the lines' vertical pulls, m (V: the box's h_s A, or the
    hull mesh's displaced volume)."""
    rho, g = case.water["density"], case.water["gravity"]
    mass = case.body["mass"]
    height = -2 * _hull_keel(case) if case.body.get("hull") else case.body["size"][2]

    def imbalance(h):
        _, cats, _ = reference_catenaries(case, h)
        return rho * g * _displaced_volume(case, h) - mass * g - sum(c.V_fairlead for c in cats)

    top = 0.999 * height
    if imbalance(top) < 0:
        raise ValueError("body.mass: the body sinks (buoyancy at full immersion is below the "
                         "weight plus the lines' pull)")
    return brentq(imbalance, 1e-6 * height, top, xtol=1e-12)


def paper_body(case, draft) -> RigidBody:
    """The case's rigid body floating at ``draft``: the box, or the hull mesh it names."""
    spec, rho, g = case.body, case.water["density"], case.water["gravity"]
    rotations = spec.get("rotations", "small")
    if spec.get("hull") is None:
        length, width, height = spec["size"]
        return RigidBody.box(length, width, height, spec["mass"], draft, rho=rho, g=g,
                             rotations=rotations)
    com = _com(case, draft)
    inertia = (np.diag(spec["inertia"]) if "inertia" in spec
               else uniform_box_inertia(spec["mass"], *spec["size"]))
    return RigidBody.from_hull(_hull_path(case), spec["mass"], com, inertia, offset=com,
                               rho=rho, g=g, rotations=rotations,
                               box_size=np.asarray(spec["size"], float)
                               if "size" in spec else None)


def _flat_seabed(case):
    """The parametric layout's sea bed: a plane (its anchors and reference catenaries
    sit on the flat bed at the water depth)."""
    if any(key in (case.data.get("seabed") or {}) for key in environment.BATHYMETRY_KEYS):
        raise ValueError("seabed: a bathymetry (file, or x, y, heights) needs the network "
                         "layout ([[points]] with the anchors where the bed is); the "
                         "parametric layout's lines end on a plane bed at the water depth")
    return environment.seabed(case.data)


def paper_network(case, motion=None):
    """(network, catenaries, draft) of a case in the paper's parametric layout: the box at
    its draft (m; 'equilibrium': from the vertical balance) on its lines' catenaries."""
    body_data = case.body
    draft = body_data.get("draft", "equilibrium")
    draft = equilibrium_draft(case) if draft == "equilibrium" else float(draft)
    specs, cats, types = reference_catenaries(case, draft)
    rigid = paper_body(case, draft)
    com = rigid.reference_point
    water_sea = environment.sea(case.data)
    body_terms = environment.body_terms(case.data, rigid, water_sea, case.directory)
    body = Body("body", "dynamic", com, rigid=rigid, terms=body_terms, load=body_load(case),
                rotation="skmoor")
    points, lines = [], []
    for spec, cat, lt in zip(specs, cats, types):
        points.append(Point(f"{spec.name}.anchor", "fixed", cat.anchor))
        points.append(Point(f"{spec.name}.fairlead", "body", cat.fairlead - com, body="body"))
        lines.append(MooringLine(spec.name, lt, points[-2].name, points[-1].name, cat.L,
                                 int(spec.n_elements)))
    network = Network(points, lines, [body], depth=case.water["depth"],
                      rho=case.water["density"], g=case.water["gravity"],
                      seabed=_flat_seabed(case), sea=water_sea,
                      hydro=environment.has_line_hydrodynamics(case.data),
                      strain_law=case.strain_law, motion=motion)
    return network, cats, draft


def body_load(case, load=None):
    """The case's applied body load as f(t, q, qdot) -> 6-vector (N, N m), or None."""
    load = case.load if load is None else load
    if not load or load.get("amplitude", 0) == 0:
        return None
    amplitude, omega = float(load["amplitude"]), float(load["omega"])
    direction = np.asarray(load.get("direction", [1, 0, 0, 0, 0, 0]), float)

    def applied(t, q, qdot):
        return amplitude * np.sin(omega * t) * direction

    applied.time_only = True  # q, qdot unused (the compiled step evaluates it once a step)
    applied.at_times = lambda times: (amplitude * np.sin(omega * np.asarray(times))[:, None]
                                      * direction)  # (m, 6) at m times
    return applied


def explicit_network(case) -> Network:
    """The Network of a case with ``[[points]]``, ``[[lines]]`` and ``[[bodies]]`` tables."""
    data, water = case.data, case.water
    rho, g, depth = water["density"], water["gravity"], water["depth"]
    water_sea = environment.sea(data)
    shared = data.get("mooring", {})
    bodies = []
    load = data.get("load", {})
    loaded = load.get("body") if load else None
    for i, spec in enumerate(data.get("bodies", [])):
        bodies.append(_explicit_body(case, spec, rho, g, water_sea))
    dynamic = [b for b in bodies if b.kind == "dynamic"]
    if load and load.get("amplitude", 0):
        target = next((b for b in dynamic if b.name == loaded), None) if loaded else (
            dynamic[0] if dynamic else None)
        if target is None:
            raise ValueError(f"load.body: {loaded!r} is not a dynamic body")
        target.load = body_load(case, load)
    points = [Point(p["name"], p.get("kind", "fixed"), p["position"], body=p.get("body"),
                    mass=float(p.get("mass", 0.0)), volume=float(p.get("volume", 0.0)),
                    CdA=float(p.get("CdA", 0.0)), Ca=float(p.get("Ca", 0.0)),
                    smooth=bool(p.get("smooth", False)))
              for p in data["points"]]
    for p in points:
        if p.kind == "body" and (p.mass or p.volume):
            raise ValueError(f"points {p.name}: mass and volume of a point on a body are not "
                             "supported (add them to the body)")
    lines = [MooringLine(ln["name"], line_type(case, ln["type"]), ln["a"], ln["b"],
                         float(ln["length"]), int(ln.get("n_elements", shared.get("n_elements", 20))))
             for ln in data["lines"]]
    failures = [LineFailure(f["point"], f["lines"], f.get("time"), f.get("tension"))
                for f in data.get("failures", [])]
    return Network(points, lines, bodies, depth=depth, rho=rho, g=g,
                   seabed=environment.seabed(data, case.directory), sea=water_sea,
                   hydro=environment.has_line_hydrodynamics(data),
                   strain_law=_network_law(shared), failures=failures)


def _network_law(shared):
    """The network layout's [mooring] strain law (default 'engineering'), carrying
    compression where ``tension_only = false``."""
    name = shared.get("strain_law", "engineering")
    if shared.get("tension_only", True):
        return name
    from ..lines.laws import LAWS
    return LAWS[name](tension_only=False)


def _explicit_body(case, spec, rho, g, sea) -> Body:
    name, kind = spec["name"], spec.get("kind", "dynamic")
    position = np.asarray(spec.get("position", [0.0, 0.0, 0.0]), float)
    attitude = np.radians(spec.get("attitude", [0.0, 0.0, 0.0]))
    if kind != "dynamic":
        return Body(name, kind, position, attitude, rotation="skmoor")
    if np.any(attitude):
        raise ValueError(f"bodies {name}.attitude: a dynamic body starts upright (give its "
                         "points in the rotated frame instead)")
    mass = float(spec["mass"])
    com = position + np.asarray(spec.get("center_of_mass", [0.0, 0.0, 0.0]), float)
    inertia = np.asarray(spec["inertia"], float)
    inertia = np.diag(inertia) if inertia.shape == (3,) else inertia
    box = hull = None
    if "size" in spec:
        from ..bodies.body import box_hydrostatics
        length, width, height = spec["size"]
        draft = height / 2 - position[2]
        hydro = box_hydrostatics(length, width, height, draft, reference_point=position,
                                 center_xy=position[:2])
        box = np.asarray(spec["size"], float)
        hull = box_triangles(box, np.zeros(3))  # centred on the reference point
    elif "hull" in spec:
        path = resolve_inside(spec["hull"], case.directory, f"bodies {name}.hull")
        if not path.is_file():
            raise ValueError(f"bodies {name}.hull: no such mesh file {path}")
        hydro = hull_hydrostatics(path, reference_point=position, offset=position)
        hull = hull_triangles(path, position, offset=position)
    elif spec.get("volume", 0):
        from ..bodies.body import Hydrostatics
        cob = position + np.asarray(spec.get("center_of_buoyancy", [0.0, 0.0, 0.0]), float)
        hydro = Hydrostatics.submerged(float(spec["volume"]), cob, position)
    else:
        hydro = None
    added = spec.get("added_mass")
    added = None if added is None else (np.diag(added) if np.shape(added) == (6,) else added)
    damping = spec.get("linear_damping")
    damping = None if damping is None else (np.diag(damping) if np.shape(damping) == (6,)
                                            else damping)
    rigid = RigidBody(mass, com, inertia, reference_point=position, hydrostatics=hydro,
                      added_mass=added, linear_damping=damping, rho=rho, g=g, box_size=box,
                      rotations=spec.get("rotations", "small"), hull=hull)
    terms = environment.body_terms({"water": case.water, "body": spec}, rigid, sea,
                                   case.directory)
    return Body(name, "dynamic", position, rigid=rigid, terms=terms, rotation="skmoor")
