"""The environment sections of a case file: water kinematics, sea bed, hydrodynamics.

All optional; without them a case is the paper's model (no water forces on the lines, no
sea bed). In TOML:

    [line_types.chain]          # Morison coefficients and internal damping per line type
    Cd_n = 1.37                 # MoorDyn's Cd, CdAx, Ca, CaAx; BA in N s
    Cd_t = 0.64
    Ca_n = 1.0

    [sea]                       # currents and waves (needs line coefficients to act)
    current_speed = 0.5         # m/s, or current_profile = [[z, speed], ...]
    current_heading_deg = 0.0
    waves = [{type = "airy", height = 2.0, period = 8.0},
             {type = "jonswap", Hs = 3.0, Tp = 10.0, gamma = 3.3, seed = 1}]

    [seabed]                    # contact with the bed at the water depth
    mu_axial = 0.5              # and stiffness, damping, mu_lateral, slope_deg, ...

    [body]                      # quadratic drag on the body (MoorDyn's CdA)
    drag_coefficients = [1.0, 1.0, 1.0]
    drag_areas = [50.0, 130.0, 260.0]

    [body.potential_flow]       # Cummins' equation: radiation and the [sea]'s wave excitation
    mesh = "box_hull.stl"       # the hull about the reference point (or wamit = "root")
    frequencies = [0.05, 3.0, 0.05]   # rad/s: first, last, step of the BEM solve (cached)
    memory = 60.0               # s, the retardation kernel's length
    ramp = 20.0                 # s, the excitation's fade-in
"""
from __future__ import annotations

from ..io.paths import resolve_inside
from ..sea.hydro import body_hydrodynamics
from ..sea.seabed import Bathymetry, Seabed
from ..sea.waves import AiryWave, Current, JonswapWave, Sea

LINE_COEFFICIENTS = ("Cd_n", "Cd_t", "Ca_n", "Ca_t")
SEABED_KEYS = ("stiffness", "damping", "mu_axial", "mu_lateral", "slope_deg",
               "slope_heading_deg", "friction_velocity", "damping_onset", "static_friction",
               "static_slip")
BATHYMETRY_KEYS = ("file", "x", "y", "heights")


def _named(section, build):
    """Call ``build``; a ValueError is re-raised with the case section in front."""
    try:
        return build()
    except (TypeError, ValueError) as err:
        raise ValueError(f"{section}: {err}") from None


def sea(data: dict) -> Sea | None:
    """The case's :class:`~skmoor.sea.waves.Sea` (None without a [sea] section)."""
    spec = data.get("sea")
    if spec is None:
        return None
    if not isinstance(spec, dict):
        raise ValueError(f"sea: expected a table, got {spec!r}")
    water = data["water"]
    depth, g = float(water["depth"]), float(water.get("gravity", 9.81))
    unknown = set(spec) - {"current_speed", "current_heading_deg", "current_profile", "waves"}
    if unknown:
        raise ValueError(f"sea: unknown keys {sorted(unknown)}")
    current = None
    if "current_speed" in spec or "current_profile" in spec:
        current = _named("sea.current", lambda: Current(
            spec.get("current_speed"), spec.get("current_heading_deg", 0.0),
            spec.get("current_profile")))
    waves = []
    for i, wave in enumerate(spec.get("waves", [])):
        where = f"sea.waves[{i}]"
        if not isinstance(wave, dict):
            raise ValueError(f"{where}: expected a table, got {wave!r}")
        kind = wave.get("type")
        args = {k: v for k, v in wave.items() if k != "type"}
        if kind == "airy":
            waves.append(_named(where, lambda: AiryWave(depth=depth, g=g, **args)))
        elif kind == "jonswap":
            waves.append(_named(where, lambda: JonswapWave(depth=depth, g=g, **args)))
        else:
            raise ValueError(f"{where}.type: {kind!r} is not 'airy' or 'jonswap'")
    return _named("sea", lambda: Sea(depth, rho=float(water["density"]), g=g,
                                      current=current, waves=waves))


def seabed(data: dict, directory=None) -> Seabed | None:
    """The case's :class:`~skmoor.sea.seabed.Seabed` at the water depth (None without [seabed]),
    on its bathymetry when it gives one (``file``: a MoorDyn seafloor file, relative to
    ``directory``; or the grid ``x``, ``y``, ``heights``)."""
    spec = data.get("seabed")
    if spec is None:
        return None
    if not isinstance(spec, dict):
        raise ValueError(f"seabed: expected a table, got {spec!r}")
    unknown = set(spec) - set(SEABED_KEYS) - set(BATHYMETRY_KEYS)
    if unknown:
        raise ValueError(f"seabed: unknown keys {sorted(unknown)}, use "
                         f"{list(SEABED_KEYS + BATHYMETRY_KEYS)}")
    plane = {k: v for k, v in spec.items() if k in SEABED_KEYS}
    return _named("seabed", lambda: Seabed(float(data["water"]["depth"]),
                                           bathymetry=_bathymetry(spec, directory), **plane))


def _bathymetry(spec: dict, directory) -> Bathymetry | None:
    """The [seabed] table's bathymetry, or None (a plane bed)."""
    if "file" in spec:
        from ..io.sea_files import read_seafloor

        path = resolve_inside(spec["file"], directory, "file")
        if not path.is_file():
            raise ValueError(f"file: no such seafloor file {path}")
        return read_seafloor(path)
    if "heights" in spec:
        return Bathymetry(spec["x"], spec["y"], spec["heights"], source="bathymetry grid")
    return None


def has_line_hydrodynamics(data: dict) -> bool:
    """True when any line type has a drag or added-mass coefficient."""
    return any(float(t.get(name, 0.0)) != 0.0 for t in data["line_types"].values()
               for name in LINE_COEFFICIENTS)


def body_terms(data: dict, body, water_sea=None, directory=None) -> list:
    """The terms of a body section (``data["body"]``): its quadratic drag and its
    potential flow (Cummins' equation), if any; relative file names start at
    ``directory``."""
    spec = data["body"]
    terms = []
    if "drag_coefficients" in spec or "drag_areas" in spec:
        terms.append(_named("body", lambda: body_hydrodynamics(
            drag_coefficients=spec.get("drag_coefficients"), drag_areas=spec.get("drag_areas"),
            sea=water_sea, reference_point=body.reference_point,
            rho=float(data["water"]["density"]))))
    if spec.get("potential_flow") is not None:
        terms.append(_named("body.potential_flow", lambda: potential_flow(
            spec["potential_flow"], data["water"], body, water_sea, directory)))
    return terms


def potential_flow(spec: dict, water: dict, body, water_sea=None, directory=None):
    """The :class:`~skmoor.bodies.radiation.PotentialFlow` of a body's ``potential_flow`` table."""
    import numpy as np

    from ..bodies import bem
    from ..bodies.radiation import PotentialFlow

    def path(name):
        return resolve_inside(name, directory, "body.potential_flow")

    rho, g = float(water["density"]), float(water.get("gravity", 9.81))
    depth, point = float(water["depth"]), np.asarray(body.reference_point, float)
    headings = spec.get("headings", [0.0])
    if spec.get("mesh") is not None:
        first, last, step = spec["frequencies"]
        omega = np.arange(first, last + 0.5 * step, step)
        hydro = bem.from_mesh(path(spec["mesh"]), omega, offset=point, reference_point=point,
                              headings=headings, depth=depth, rho=rho, g=g)
    else:
        hydro = bem.read_wamit(path(spec["wamit"]), rho=rho, g=g, depth=depth,
                               length=spec.get("wamit_length", 1.0), reference_point=point)
    return PotentialFlow(hydro, water_sea, memory=spec.get("memory", 60.0),
                         ramp=spec.get("ramp", 0.0))
