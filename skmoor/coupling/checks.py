"""Physically impossible or suspicious input, found before anything is solved.

:func:`check_network` raises ValueError for what cannot be (a point below the sea bed, a
line far too short for its span, unless its law is made for such strains: a polyester
rope's, or a curve that reaches them) and returns warnings, with the numbers, for what is
probably a mistake (a fixed point, an anchor, above the water or above the fairlead of
its line; a line that must stretch a few percent to reach; a current or waves with
nothing to act on).
"""
from __future__ import annotations

import os

import numpy as np

from ..lines import laws

BYTES_PER_DOF = 4096  # what a model needs per unknown through its statics and a run (4x measured)
STRAIN_WARNING = 0.03  # a span needing more strain than this is warned about
STRAIN_LIMIT = 0.25  # ... and more than this refused (warned for a rope law made for it)
DRAG_LIMIT = 10.0  # a current whose drag on a line exceeds this many times its EA is refused
BED_TOLERANCE = 1e-3  # m below the bed still taken as on it


def available_memory() -> float:
    """Bytes of memory this machine can still give (MemAvailable, else all of it)."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024
    except OSError:
        pass
    return float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))


def check_size(network):
    """ValueError when the lines' elements cannot fit in memory, before allocating."""
    elements = sum(int(line.n_elements) for line in network.lines)
    need, have = 3 * (elements + len(network.lines)) * BYTES_PER_DOF, available_memory()
    if need > have:
        raise ValueError(f"n_elements: {elements} elements on {len(network.lines)} lines "
                         f"need about {need / 2**30:.3g} GiB, this machine has "
                         f"{have / 2**30:.3g} GiB available (fewer elements, or a bigger machine)")


def check_network(network) -> list:
    """ValueError for impossible input (or a model too big for this machine's memory); a
    list of warnings (text) for suspicious input."""
    check_size(network)
    warnings = []
    where = {p.name: network.global_position(p) for p in network.points}
    depth = float(network.depth)
    for p in network.points:
        z = where[p.name][2]
        bed = (-depth if network.seabed is None  # the bed under it: a slope, a bathymetry
               else float(network.seabed.height(where[p.name][:2])))
        if z < bed - BED_TOLERANCE:
            raise ValueError(f"point {p.name}: z = {z:.6g} m is below the sea bed "
                             f"(z = {bed:.6g} m there, depth {depth:g} m)")
        if p.kind == "fixed" and z > 0.0:
            warnings.append(f"point {p.name}: a fixed point (an anchor?) {z:.6g} m above "
                            "the water surface (z = 0)")
    for line in network.lines:
        a, b = network.point(line.a), network.point(line.b)
        span = float(np.linalg.norm(where[b.name] - where[a.name]))
        # a free end is a first guess that the build settles: only held ends have a span
        strain = -1.0 if "free" in (a.kind, b.kind) else span / line.length - 1.0
        if strain > STRAIN_LIMIT and not carries_strain(line.line_type, strain):
            raise ValueError(f"line {line.name}: its ends are {span:.6g} m apart, "
                             f"{100 * strain:.0f} % more than its length {line.length:g} m "
                             "(a cable that short cannot reach)")
        if strain > STRAIN_WARNING:
            warnings.append(f"line {line.name}: its ends are {span:.6g} m apart, "
                            f"{100 * strain:.1f} % more than its length {line.length:g} m: "
                            "it starts that stretched")
        for anchor, other in ((a, b), (b, a)):
            if anchor.kind != "fixed" or other.kind not in ("body", "coupled"):
                continue
            z, top = where[anchor.name][2], where[other.name][2]
            if z > top:
                warnings.append(f"line {line.name}: anchor {anchor.name} (z = {z:.6g} m) is "
                                f"above its fairlead {other.name} (z = {top:.6g} m)")
    _check_current(network)
    warnings += _sea_without_coefficients(network)
    return warnings


def _check_current(network):
    """ValueError for a sea whose water speed drags a line with more than DRAG_LIMIT times
    its axial stiffness (the normal drag 1/2 rho Cd_n d U^2 over its length, U the fastest
    water at its ends and middle at t = 0): no static state, no time step resolves it (a
    current in the wrong unit; no cable stretches that far)."""
    sea = network.sea
    if sea is None or sea.still and not sea.has_waves:
        return
    for line in network.lines:
        lt = line.line_type
        if not lt.Cd_n:
            continue
        a, b = (network.global_position(network.point(p)) for p in (line.a, line.b))
        ends = np.array([a, 0.5 * (a + b), b], float)
        ends[:, 2] = np.minimum(ends[:, 2], 0.0)  # the water below the surface
        speed = float(np.max(np.linalg.norm(sea.velocity(ends, 0.0), axis=-1)))
        drag = 0.5 * float(network.rho) * lt.Cd_n * lt.diameter * speed ** 2 * line.length
        EA = float(lt.law.nominal_EA(lt.EA) if lt.law is not None else lt.EA or 0.0)
        if EA > 0 and drag > DRAG_LIMIT * EA:
            raise ValueError(f"sea: the water's speed {speed:.3g} m/s drags line {line.name} "
                             f"with about {drag:.3g} N, {drag / EA:.3g} times its axial "
                             f"stiffness EA = {EA:.3g} N: no cable holds that (a speed in the "
                             "wrong unit?)")


def carries_strain(line_type, strain) -> bool:
    """True when the line type's law is made for strains this large: a polyester rope's
    (StaticDynamic: static / dynamic stiffness, viscoelastic, Syrope) or a tension-strain
    curve that reaches the strain (-)."""
    law = line_type.law
    if isinstance(law, laws.StaticDynamic):
        return True
    return isinstance(law, laws.Curve) and law.strain[-1] >= strain


def _sea_without_coefficients(network) -> list:
    sea = network.sea
    if sea is None:
        return []
    types = [ln.line_type for ln in network.lines]
    lines_drag = network.hydro and any(t.Cd_n or t.Cd_t for t in types)
    lines_hydro = network.hydro and any(t.Cd_n or t.Cd_t or t.Ca_n or t.Ca_t for t in types)
    bodies_drag = any(getattr(b, "terms", None) for b in network.bodies)
    points_drag = any(p.CdA for p in network.points if p.kind == "free")
    out = []
    if not sea.still and not (lines_drag or bodies_drag or points_drag):
        out.append("the current acts on nothing: no line type has a drag coefficient "
                   "(Cd_n, Cd_t), no body or free point has a drag area")
    if sea.has_waves and not (lines_hydro or bodies_drag or points_drag):
        out.append("the waves act on nothing: no line type has a drag or added-mass "
                   "coefficient (Cd_n, Cd_t, Ca_n, Ca_t), no body or free point a drag area")
    return out
