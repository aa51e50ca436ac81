"""The case schema (skmoor/io/schema.py): every rule gives one line naming the field, every
case the project treats as valid passes, and no input raises anything but ValueError."""
import copy
import math
import re
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from skmoor.io.case import PAPER_CASE, Case
from skmoor.io.schema import MAX_ELEMENTS_PER_LINE, layout, validate_case

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).parents[2]

NETWORK_CASE = {
    "name": "two chains and a clump weight to a box buoy",
    "water": {"density": 1025.0, "gravity": 9.81, "depth": 100.0},
    "line_types": {"chain": {"EA": 1.674e9, "mass": 390.0, "diameter": 0.252, "Cd_n": 1.37}},
    "points": [
        {"name": "A1", "kind": "fixed", "position": [-400.0, 0.0, -100.0]},
        {"name": "A2", "kind": "fixed", "position": [400.0, 0.0, -100.0]},
        {"name": "F1", "kind": "body", "body": "buoy", "position": [-5.0, 0.0, -2.0]},
        {"name": "F2", "kind": "body", "body": "buoy", "position": [5.0, 0.0, -2.0]},
        {"name": "clump", "kind": "free", "position": [-200.0, 0.0, -90.0], "mass": 1000.0,
         "volume": 0.1, "CdA": 0.5, "Ca": 1.0},
    ],
    "bodies": [{"name": "buoy", "position": [0.0, 0.0, 0.0], "mass": 1e5,
                "inertia": [1e6, 1e6, 1.5e6], "size": [10.0, 10.0, 5.0],
                "drag_coefficients": [1.0, 1.0, 1.0],
                "drag_areas": [50.0, 50.0, 100.0]}],
    "lines": [
        {"name": "L1", "type": "chain", "a": "A1", "b": "clump", "length": 210.0},
        {"name": "L1b", "type": "chain", "a": "clump", "b": "F1", "length": 210.0,
         "n_elements": 20},
        {"name": "L2", "type": "chain", "a": "A2", "b": "F2", "length": 420.0},
    ],
    "mooring": {"strain_law": "engineering", "n_elements": 40},
    "load": {"amplitude": 1e5, "omega": 1.0, "direction": [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]},
    "damping": {"alpha": 0.0, "beta": 0.01},
    "solver": {"duration": 10.0, "dt": 0.05, "scheme": "newmark"},
    "sea": {"current_profile": [[-100.0, 0.2], [0.0, 1.0]]},
    "seabed": {"mu_axial": 0.5},
}


def changed(base, **changes):
    """A deep copy of ``base`` with dotted paths (``__`` for '.') set; a value of DROP
    removes the key, an index one past a list's end appends."""
    data = copy.deepcopy(base)
    for key, value in changes.items():
        node, keys = data, key.split("__")
        for k in keys[:-1]:
            node = node[int(k)] if isinstance(node, list) else node.setdefault(k, {})
        last = int(keys[-1]) if isinstance(node, list) else keys[-1]
        if value is DROP:
            del node[last]
        elif isinstance(node, list) and last == len(node):
            node.append(value)
        else:
            node[last] = value
    return data


DROP = object()


def refused(data):
    """The message of validate_case(data), which must raise a one-line ValueError."""
    with pytest.raises(ValueError) as err:
        validate_case(data)
    message = str(err.value)
    assert message and "\n" not in message
    return message


# ------------------------------------------------------------------ valid inputs


def _readme_case():
    """The README's environment snippet merged into the paper's case."""
    text = (ROOT / "README.md").read_text()
    block = next(b for b in re.findall(r"```toml\n(.*?)```", text, re.DOTALL) if "[sea]" in b)
    data = copy.deepcopy(PAPER_CASE)
    for section, values in tomllib.loads(block).items():
        if section == "line_types":
            for name, spec in values.items():
                data["line_types"].setdefault(name, {}).update(spec)
        else:
            data.setdefault(section, {}).update(values)
    return data


def _readme_network():
    """The README's explicit-tables example."""
    text = (ROOT / "README.md").read_text()
    return tomllib.loads(next(b for b in re.findall(r"```toml\n(.*?)```", text, re.DOTALL)
                              if "points = [" in b))


def _sweep_cases():
    """Every point of the paper's two studies (skmoor.run.sweep.paper_studies)."""
    from skmoor.run.sweep import paper_studies
    return [study.case(v).data for study in paper_studies(3) for v in study.values]


VALID = {
    "PAPER_CASE": PAPER_CASE,
    "examples/paper_case.toml": tomllib.loads((ROOT / "examples" / "paper_case.toml").read_text()),
    "README environment snippet": _readme_case(),
    # the variants the existing tests and examples build (paper_case(**changes), replace)
    "sag 1/45": changed(PAPER_CASE, mooring__sag_ratio=1 / 45),
    "engineering law": changed(PAPER_CASE, mooring__strain_law="engineering"),
    "n_elements 40": changed(PAPER_CASE, mooring__n_elements=40),
    "numpy n_elements": changed(PAPER_CASE, mooring__n_elements=np.int64(20)),
    "current and body drag": changed(PAPER_CASE, sea__current_speed=0.8,
                                     body__drag_coefficients=[1.0, 1.0, 1.0],
                                     body__drag_areas=[130.0, 260.0, 338.0]),
    "sea, seabed, Cd_n": changed(PAPER_CASE, sea__current_speed=0.5, seabed__mu_axial=0.3,
                                 line_types__steel__Cd_n=1.2),
    "heavy body (fails in build, passes the case)": changed(PAPER_CASE, body__mass=1e9),
    "per-line override": changed(PAPER_CASE, lines__0__sag_ratio=0.02),
    "grid point": changed(PAPER_CASE, mooring__chord_angle_deg=40, body__mass=1.4e5),
    "scheme newmark": changed(PAPER_CASE, solver__scheme="newmark"),
    "no load, damping, solver": changed(PAPER_CASE, load=DROP, damping=DROP, solver=DROP),
    "numeric draft": changed(PAPER_CASE, body__draft=0.9),
    "hull instead of a box": changed(PAPER_CASE, body__shape="ship", body__size=DROP,
                                     body__hull="hull.stl", body__inertia=[1e6, 6e6, 7e6]),
    "hull beside the box's size (uniform box inertia)": changed(PAPER_CASE,
                                                                body__hull="box.stl"),
    "EA line type": changed(PAPER_CASE, line_types={"chain": {
        "EA": 1.674e9, "mass": 390.0, "diameter": 0.252, "weight": 3300.0, "BA": 1e6}},
        mooring__type="chain"),
    "anchors and lengths per line": changed(
        PAPER_CASE, mooring__chord_angle_deg=DROP, mooring__sag_ratio=DROP,
        lines=[{"name": f"C{i}", "fairlead": [13.0, 5.0, -2.5], "anchor": [100.0, 40.0, -100.0],
                "length": 140.0 + i} for i in range(2)]),
    "anchor over a shared chord angle (None unsets it)": changed(
        PAPER_CASE, lines__0__anchor=[100.0, 40.0, -100.0], lines__0__chord_angle_deg=None),
    "heading": changed(PAPER_CASE, mooring__heading_deg=30.0),
    "alpha / beta damping": changed(PAPER_CASE, damping={"alpha": 0.01, "beta": 0.001}),
    # Case.replace validates after each key it sets: the steps between must pass too
    "drag coefficients before their areas": changed(PAPER_CASE,
                                                    body__drag_coefficients=[1.0, 1.0, 1.0]),
    "alpha added to the paper's ratio": changed(PAPER_CASE, damping__alpha=0.01),
    "waves": changed(PAPER_CASE, sea={"current_speed": 0.5, "current_heading_deg": 90.0, "waves": [
        {"type": "airy", "height": 2.0, "period": 8.0, "heading_deg": 10.0, "phase": 0.5},
        {"type": "jonswap", "Hs": 3.0, "Tp": 10.0, "gamma": 3.3, "seed": 7,
         "n_components": 50, "f_range": [0.05, 0.5]}]}),
    "full seabed": changed(PAPER_CASE, seabed={
        "stiffness": 1e5, "damping": 1e3, "mu_axial": 0.5, "mu_lateral": 1.0, "slope_deg": 2.0,
        "slope_heading_deg": 45.0, "friction_velocity": 1e-2, "damping_onset": 0.0}),
    "network": NETWORK_CASE,
    "network, submerged volume body with 3x3 inertia": changed(
        NETWORK_CASE, bodies=[{"name": "buoy", "position": [0.0, 0.0, -20.0], "mass": 1e4,
                               "volume": 20.0, "center_of_buoyancy": [0.0, 0.0, 0.5],
                               "inertia": [[1e5, 0, 0], [0, 1e5, 0], [0, 0, 2e5]],
                               "center_of_mass": [0.0, 0.0, -0.5], "attitude": [0, 0, 0],
                               "added_mass": [1e4] * 3 + [1e5] * 3,
                               "linear_damping": np.diag([1e3] * 6).tolist()}]),
    "network, hull body, load on it by name": changed(
        NETWORK_CASE, bodies__0__size=DROP, bodies__0__hull="buoy.stl",
        bodies__0__inertia=[1e6, 1e6, 2e6], load__body="buoy"),
    "network, coupled points only": {
        "water": NETWORK_CASE["water"], "line_types": NETWORK_CASE["line_types"],
        "points": [{"name": "anchor", "kind": "fixed", "position": [-400, 0, -100]},
                   {"name": "fair", "kind": "coupled", "position": [0, 0, 0]}],
        "lines": [{"name": "L", "type": "chain", "a": "anchor", "b": "fair", "length": 410.0,
                   "n_elements": 41}]},
    "network, defaults: point kind, body position, n_elements; no hydrostatics": changed(
        NETWORK_CASE, points__0__kind=DROP, bodies__0__position=DROP, bodies__0__size=DROP,
        mooring=DROP, lines__1__n_elements=DROP),
    "network, zero load without a dynamic body": changed(
        NETWORK_CASE, bodies__0__kind="coupled", load__amplitude=0.0),
    "network of the README": _readme_network(),
    "network, fixed and coupled bodies": changed(
        NETWORK_CASE, load=DROP, bodies=[
            {"name": "buoy", "kind": "coupled", "position": [0, 0, 0]},
            {"name": "frame", "kind": "fixed", "position": [0, 0, -50], "size": [1, 1, 1]}]),
}


@pytest.mark.parametrize("name", list(VALID))
def test_valid_cases_pass_unchanged(name):
    data = copy.deepcopy(VALID[name])
    before = copy.deepcopy(data)
    assert validate_case(data) is data
    assert repr(data) == repr(before)          # nothing filled in or converted


@pytest.mark.parametrize("data", _sweep_cases(), ids=lambda d: "sweep")
def test_every_point_of_the_paper_studies_passes(data):
    assert validate_case(data) is data


def test_case_files_under_examples_pass():
    files = sorted((ROOT / "examples").rglob("*.toml"))
    assert files
    for path in files:
        validate_case(tomllib.loads(path.read_text()))


def test_case_checks_with_the_schema():
    """skmoor.Case validates with the schema: the valid cases above make Cases, and an
    unknown key is refused there with the nearest name (the old hand check let it by)."""
    for data in VALID.values():
        Case(data)
    with pytest.raises(ValueError, match=r"^damping\.ration: unknown key; did you mean 'ratio'\?"):
        Case({**PAPER_CASE, "damping": {"ration": 0.03}})


def test_layout_is_told_by_points():
    assert layout(PAPER_CASE) == "parametric"
    assert layout(NETWORK_CASE) == "network"
    assert layout({"points": []}) == "network"


# ------------------------------------------------------------------ rules: parametric


P = PAPER_CASE

PARAMETRIC_RULES = [
    # unknown keys and sections, with the nearest valid name
    (changed(P, damping__ration=0.03), r"^damping\.ration: unknown key; did you mean 'ratio'\?$"),
    (changed(P, dampin={"ratio": 0.03}), r"^dampin: unknown section; did you mean 'damping'\?$"),
    (changed(P, solver__duraton=10.0), r"^solver\.duraton: unknown key; did you mean 'duration'"),
    (changed(P, nme="x"), r"^nme: unknown key; did you mean 'name'"),
    (changed(P, body__sise=[1, 2, 3]), r"^body\.sise: unknown key; did you mean 'size'"),
    (changed(P, mooring__sag_raito=0.02), r"^mooring\.sag_raito: unknown key; did you mean "
                                          r"'sag_ratio'"),
    (changed(P, lines__1__fairled=[0, 0, 0]), r"^lines\[1\]\.fairled: unknown key; did you mean "
                                              r"'fairlead'"),
    (changed(P, lines__0__strain_law="paper"), r"^lines\[0\]\.strain_law: .*mooring\.strain_law"),
    (changed(P, line_types__steel__Cdn=1.0), r"^line_types\.steel\.Cdn: unknown key; did you "
                                             r"mean 'Cd_n'"),
    (changed(P, bodies=[{"name": "b"}]), r"^bodies: .*network layout.*\[\[points\]\]"),
    (changed(P, load__body="box"), r"^load\.body: unknown key"),
    # [water]
    (changed(P, water__density=DROP), r"^water\.density: missing$"),
    (changed(P, water=DROP), r"^water: missing$"),
    (changed(P, water=5), r"^water: expected a table, got 5$"),
    (changed(P, water__gravity=0), r"^water\.gravity: must be positive, got 0$"),
    (changed(P, water__depth="deep"), r"^water\.depth: expected a number, got 'deep'$"),
    (changed(P, water__depth=True), r"^water\.depth: expected a number, got True$"),
    (changed(P, water__density=math.nan), r"^water\.density: must be finite, got nan$"),
    (changed(P, water__density=math.inf), r"^water\.density: must be finite, got inf$"),
    # [body]
    (changed(P, body=DROP), r"^body: missing$"),
    (changed(P, body__mass=-1.0), r"^body\.mass: must be positive, got -1\.0$"),
    (changed(P, body__mass=DROP), r"^body\.mass: missing$"),
    (changed(P, body__shape="cylinder"), r"^body\.shape: 'cylinder' is not 'box'; give body\.hull"),
    (changed(P, body__size=[26.0, 10.0]), r"^body\.size: need three positive numbers"),
    (changed(P, body__size=[26.0, -10.0, 5.0]), r"^body\.size\[1\]: must be positive, got -10"),
    (changed(P, body__size=DROP), r"^body\.size: missing"),
    (changed(P, body__draft="floating"), r"^body\.draft: must be 'equilibrium' or a positive"),
    (changed(P, body__draft=-1.0), r"^body\.draft: must be positive, got -1\.0$"),
    (changed(P, body__draft=6.0), r"^body\.draft: 6\.0 m must be less than the box height"),
    (changed(P, body__drag_coefficients=[1, 1, 1], body__drag_areas=[1, 2]),
     r"^body\.drag_areas: need 3 or 6 numbers >= 0"),
    (changed(P, body__drag_coefficients=[1, 1, 1], body__drag_areas=[-1, 2, 3]),
     r"^body\.drag_areas\[0\]: must be >= 0, got -1$"),
    (changed(P, body__added_mass=[1, 2, 3, 4, 5, 6]), r"^body\.added_mass: not used by the "
                                                      r"parametric layout's body"),
    (changed(P, body__inertia=[1e6, 6e6, 7e6]), r"^body\.inertia: not used for the box"),
    (changed(P, body__hull="ship.stl", body__size=DROP), r"^body\.inertia: missing \(a hull "
                                                         r"body"),
    (changed(P, body__hull="ship.stl", body__inertia=[1e6, -1.0, 1e6]),
     r"^body\.inertia\[1\]: must be positive"),
    (changed(P, body__hull=5, body__shape="ship"), r"^body\.hull: expected a string, got 5$"),
    # [line_types]
    (changed(P, line_types={}), r"^line_types: define at least one line type$"),
    (changed(P, line_types=[1]), r"^line_types: expected a table"),
    (changed(P, line_types__steel=3), r"^line_types\.steel: expected a table, got 3$"),
    (changed(P, line_types__steel__E=DROP), r"^line_types\.steel\.E: missing"),
    (changed(P, line_types__steel__diameter=0.0), r"^line_types\.steel\.diameter: must be "
                                                  r"positive, got 0\.0$"),
    (changed(P, line_types={"chain": {"EA": "long", "mass": 390.0, "diameter": 0.25}},
             mooring__type="chain"), r"^line_types\.chain\.EA: expected a number, got 'long'$"),
    (changed(P, line_types={"chain": {"EA": 1e9, "diameter": 0.25}}, mooring__type="chain"),
     r"^line_types\.chain\.mass: missing"),
    (changed(P, line_types__steel__EA=1e9), r"^line_types\.steel\.E: not used with EA"),
    (changed(P, line_types__steel__weight=100.0), r"^line_types\.steel\.weight: not used with E"),
    (changed(P, line_types__steel__Cd_n=-1.0), r"^line_types\.steel\.Cd_n: must be >= 0, got -1"),
    (changed(P, line_types__steel__BA="big"), r"^line_types\.steel\.BA: expected a number"),
    # [mooring] and [[lines]]
    (changed(P, mooring__type="chain"), r"^mooring\.type: 'chain' is not one of the line_types "
                                        r"\['steel'\]$"),
    (changed(P, lines__1__type="chain"), r"^lines\[1\]\.type: 'chain' is not one of"),
    (changed(P, mooring__type=DROP), r"^lines\[0\]\.type: missing"),
    (changed(P, mooring__strain_law="linear"), r"^mooring\.strain_law: 'linear' is not 'paper' "
                                               r"or 'engineering'$"),
    (changed(P, mooring=4), r"^mooring: expected a table, got 4$"),
    (changed(P, lines__0__n_elements=0), r"^lines\[0\]\.n_elements: must be an integer >= 1, "
                                         r"got 0$"),
    (changed(P, mooring__n_elements=2.5), r"^mooring\.n_elements: must be an integer >= 1, "
                                          r"got 2\.5$"),
    (changed(P, mooring__n_elements="11"), r"^mooring\.n_elements: must be an integer >= 1, "
                                           r"got '11'$"),
    (changed(P, mooring__n_elements=True), r"^mooring\.n_elements: must be an integer >= 1, "
                                           r"got True$"),
    (changed(P, lines__2__n_elements=MAX_ELEMENTS_PER_LINE + 1),
     r"^lines\[2\]\.n_elements: must be at most 100000 per line \(.*memory\)"),
    (changed(P, mooring__n_elements=DROP), r"^lines\[0\]\.n_elements: missing"),
    (changed(P, lines=[]), r"^lines: define at least one line$"),
    (changed(P, lines=DROP), r"^lines: missing$"),
    (changed(P, lines={"name": "C1"}), r"^lines: expected a list"),
    (changed(P, lines__0="C1"), r"^lines\[0\]: expected a table, got 'C1'$"),
    (changed(P, lines__0__name=DROP), r"^lines\[0\]\.name: missing$"),
    (changed(P, lines__1__name="C1"), r"^lines\[1\]\.name: 'C1' is used by lines\[0\] too$"),
    (changed(P, lines__0__name=7), r"^lines\[0\]\.name: expected a string, got 7$"),
    (changed(P, lines__0__fairlead=[1.0, 2.0]), r"^lines\[0\]\.fairlead: need three finite "
                                                r"numbers"),
    (changed(P, lines__0__fairlead=["a", 0, 0]), r"^lines\[0\]\.fairlead\[0\]: expected a number"),
    (changed(P, lines__0__fairlead=[0, math.nan, 0]), r"^lines\[0\]\.fairlead\[1\]: must be "
                                                      r"finite"),
    (changed(P, lines__0__fairlead=DROP), r"^lines\[0\]\.fairlead: missing$"),
    (changed(P, lines__0__anchor=[100.0, 40.0, -100.0]),
     r"^lines\[0\]: give either anchor or chord_angle_deg \(both are given: lines\[0\]\.anchor "
     r"and mooring\.chord_angle_deg\)$"),
    (changed(P, mooring__chord_angle_deg=DROP), r"^lines\[0\]: give either anchor or "
                                                r"chord_angle_deg \(neither is given\)$"),
    (changed(P, lines__3__length=140.0), r"^lines\[3\]: give either length or sag_ratio \(both"),
    (changed(P, mooring__sag_ratio=DROP), r"^lines\[0\]: give either length or sag_ratio "
                                          r"\(neither"),
    (changed(P, mooring__chord_angle_deg=0), r"^mooring\.chord_angle_deg: must lie in \(0, 90\], "
                                             r"got 0$"),
    (changed(P, lines__1__chord_angle_deg=95.0), r"^lines\[1\]\.chord_angle_deg: must lie in "
                                                 r"\(0, 90\]"),
    (changed(P, mooring__sag_ratio=0.7),
     r"^mooring\.sag_ratio: must lie in \(0, 0\.5\), got 0\.7$"),
    (changed(P, mooring__sag_ratio=DROP, lines__0__length=-5.0, lines__1__length=140.0,
             lines__2__length=140.0, lines__3__length=140.0),
     r"^lines\[0\]\.length: must be positive, got -5\.0$"),
    (changed(P, lines__0__anchor=[100.0, 40.0, -100.0], lines__0__chord_angle_deg=None,
             lines__0__heading_deg=30.0),
     r"^lines\[0\]\.heading_deg: not used when the anchor is given"),
    (changed(P, mooring__heading_deg="north"), r"^mooring\.heading_deg: expected a number"),
    # [load]
    (changed(P, load__amplitude=DROP), r"^load\.amplitude: missing$"),
    (changed(P, load__omega="fast"), r"^load\.omega: expected a number, got 'fast'$"),
    (changed(P, load__direction=[1, 0, 0]), r"^load\.direction: need 6 components \[Fx Fy Fz Mx "
                                            r"My Mz\], got \[1, 0, 0\]$"),
    (changed(P, load__direction=[1, 0, 0, 0, 0, None]), r"^load\.direction\[5\]: expected a "
                                                        r"number, got None$"),
    # [damping]
    (changed(P, damping__ratio=1.0), r"^damping\.ratio: must lie in \[0, 1\), got 1\.0$"),
    (changed(P, damping__ratio=-0.1), r"^damping\.ratio: must lie in \[0, 1\)"),
    (changed(P, damping={"beta": -1.0}), r"^damping\.beta: must be >= 0, got -1\.0$"),
    # [solver]
    (changed(P, solver__dt=0.0), r"^solver\.dt: must be positive, got 0\.0$"),
    (changed(P, solver__duration=-1), r"^solver\.duration: must be positive, got -1$"),
    (changed(P, solver__output_interval="often"), r"^solver\.output_interval: expected a number"),
    (changed(P, solver__scheme="rk4"), r"^solver\.scheme: 'rk4' is not 'newmark' or "
                                       r"'generalized-alpha'$"),
    (changed(P, solver__rho_inf=1.5), r"^solver\.rho_inf: must lie in \[0, 1\], got 1\.5$"),
    (changed(P, solver__steady_periods=0), r"^solver\.steady_periods: must be an integer >= 1, "
                                           r"got 0$"),
    (changed(P, solver__steady_periods=5.0), r"^solver\.steady_periods: must be an integer >= 1"),
    # [sea]
    (changed(P, sea=1.0), r"^sea: expected a table, got 1\.0$"),
    (changed(P, sea__swell=1.0), r"^sea\.swell: unknown key"),
    (changed(P, sea__waves={"type": "airy"}), r"^sea\.waves: expected a list"),
    (changed(P, sea__waves=["airy"]), r"^sea\.waves\[0\]: expected a table, got 'airy'$"),
    (changed(P, sea__waves=[{"type": "stokes", "height": 1.0, "period": 8.0}]),
     r"^sea\.waves\[0\]\.type: 'stokes' is not 'airy' or 'jonswap'$"),
    (changed(P, sea__waves=[{"height": 1.0, "period": 8.0}]), r"^sea\.waves\[0\]\.type: missing"),
    (changed(P, sea__waves=[{"type": "airy", "height": -1.0, "period": 8.0}]),
     r"^sea\.waves\[0\]\.height: must be positive, got -1\.0$"),
    (changed(P, sea__waves=[{"type": "airy", "height": 1.0}]),
     r"^sea\.waves\[0\]\.period: missing"),
    (changed(P, sea__waves=[{"type": "airy", "Hs": 1.0, "period": 8.0}]),
     r"^sea\.waves\[0\]\.Hs: not a key of an 'airy' wave"),
    (changed(P, sea__waves=[{"type": "airy", "height": 1.0, "period": 8.0, "hight": 2}]),
     r"^sea\.waves\[0\]\.hight: unknown key; did you mean 'height'"),
    (changed(P, sea__waves=[{"type": "jonswap", "Hs": 3.0, "Tp": 10.0, "n_components": 0}]),
     r"^sea\.waves\[0\]\.n_components: must be an integer >= 1, got 0$"),
    (changed(P, sea__waves=[{"type": "jonswap", "Hs": 3.0, "Tp": 10.0, "seed": -1}]),
     r"^sea\.waves\[0\]\.seed: must be an integer >= 0, got -1$"),
    (changed(P, sea__waves=[{"type": "jonswap", "Hs": 3.0, "Tp": 10.0, "f_range": [0.2, 0.1]}]),
     r"^sea\.waves\[0\]\.f_range: need 0 < f_min < f_max"),
    (changed(P, sea__waves=[{"type": "jonswap", "Hs": 3.0, "Tp": 10.0, "gamma": 0}]),
     r"^sea\.waves\[0\]\.gamma: must be positive"),
    (changed(P, sea__current_speed=1.0, sea__current_profile=[[0.0, 1.0]]),
     r"^sea\.current_profile: give either current_speed .* not both$"),
    (changed(P, sea__current_profile=[[0.0, 1.0], [0.0, 2.0]]),
     r"^sea\.current_profile: two entries at the same z$"),
    (changed(P, sea__current_profile=[[0.0, 1.0, 2.0]]),
     r"^sea\.current_profile\[0\]: need a pair \[z, speed\]"),
    (changed(P, sea__current_profile=[]), r"^sea\.current_profile: need \[\[z, speed\], \.\.\.\]"),
    (changed(P, sea__current_speed=1.0, sea__current_heading_deg=math.nan),
     r"^sea\.current_heading_deg: must be finite, got nan$"),
    # [seabed]
    (changed(P, seabed=[]), r"^seabed: expected a table, got \[\]$"),
    (changed(P, seabed__mu_axial=-0.5), r"^seabed\.mu_axial: must be >= 0, got -0\.5$"),
    (changed(P, seabed__kbot=1e6), r"^seabed\.kbot: unknown key"),
    (changed(P, seabed__slope_deg=90.0), r"^seabed\.slope_deg: must lie in \[0, 90\), got 90\.0$"),
    (changed(P, seabed__friction_velocity=0.0), r"^seabed\.friction_velocity: must be positive"),
    (changed(P, seabed__stiffness=-1.0), r"^seabed\.stiffness: must be positive"),
    # the case itself
    (changed(P, name=5), r"^name: expected a string, got 5$"),
]


@pytest.mark.parametrize("data, pattern", PARAMETRIC_RULES)
def test_parametric_rule_names_the_field(data, pattern):
    with pytest.raises(ValueError, match=pattern):
        validate_case(data)
    refused(data)


# ------------------------------------------------------------------ rules: network


N = NETWORK_CASE

NETWORK_RULES = [
    (changed(N, points=[]), r"^points: define at least one point$"),
    (changed(N, points__0__kind="anchor"), r"^points\[0\]\.kind: 'anchor' is not one of 'fixed', "
                                           r"'free', 'coupled' or 'body'$"),
    (changed(N, points__0__position=[0, 0]), r"^points\[0\]\.position: need three finite"),
    (changed(N, points__1__name="A1"), r"^points\[1\]\.name: 'A1' is used by points\[0\] too$"),
    (changed(N, points__2__body="hull"), r"^points\[2\]\.body: 'hull' is not one of the bodies "
                                         r"\['buoy'\]$"),
    (changed(N, points__2__body=DROP), r"^points\[2\]\.body: missing \(a point of kind 'body'"),
    (changed(N, points__0__body="buoy"), r"^points\[0\]\.body: only for points of kind 'body'"),
    (changed(N, points__4__mass=-1.0), r"^points\[4\]\.mass: must be >= 0, got -1\.0$"),
    (changed(N, points__4__volume="big"), r"^points\[4\]\.volume: expected a number"),
    (changed(N, points__4__CdA=-1.0), r"^points\[4\]\.CdA: must be >= 0"),
    (changed(N, points__4__Ca=math.inf), r"^points\[4\]\.Ca: must be finite"),
    (changed(N, points__4__cda=1.0), r"^points\[4\]\.cda: unknown key; did you mean 'CdA'"),
    (changed(N, bodies__0__kind="floating"), r"^bodies\[0\]\.kind: 'floating' is not one of "
                                             r"'dynamic', 'coupled' or 'fixed'$"),
    (changed(N, bodies__0__mass=DROP), r"^bodies\[0\]\.mass: missing \(a dynamic body"),
    (changed(N, bodies__0__mass=0.0), r"^bodies\[0\]\.mass: must be positive, got 0\.0$"),
    (changed(N, bodies__0__attitude=[0, 0]), r"^bodies\[0\]\.attitude: need three finite numbers "
                                             r"\[roll, pitch, yaw\]"),
    (changed(N, bodies__0__hull="buoy.stl"), r"^bodies\[0\]\.hull: give one of size, hull, "
                                             r"volume, not size and hull$"),
    (changed(N, bodies__0__inertia=DROP), r"^bodies\[0\]\.inertia: missing \(a dynamic body"),
    (changed(N, bodies__0__attitude=[0, 0, 90]), r"^bodies\[0\]\.attitude: a dynamic body "
                                                 r"starts upright"),
    (changed(N, bodies__0__volume=-1.0), r"^bodies\[0\]\.volume: must be >= 0"),
    (changed(N, points__2__mass=10.0), r"^points\[2\]\.mass: not supported on a point of "
                                       r"kind 'body'"),
    (changed(N, bodies__0__inertia=[1e6, 0.0, 1e6]), r"^bodies\[0\]\.inertia\[1\]: must be "
                                                     r"positive"),
    (changed(N, bodies__0__inertia=[[1, 2, 0], [0, 1, 0], [0, 0, 1]]),
     r"^bodies\[0\]\.inertia: must be symmetric"),
    (changed(N, bodies__0__inertia=[[1, 0, 0], [0, -1, 0], [0, 0, 1]]),
     r"^bodies\[0\]\.inertia: must be positive definite"),
    (changed(N, bodies__0__inertia=[[1, 0], [0, 1]]), r"^bodies\[0\]\.inertia: need \[Ixx, Iyy, "
                                                      r"Izz\] or a 3x3 matrix"),
    (changed(N, bodies__0__center_of_buoyancy=[0, 0, 0]),
     r"^bodies\[0\]\.center_of_buoyancy: only with volume"),
    (changed(N, bodies__0__added_mass=[[0.0] * 6] * 5), r"^bodies\[0\]\.added_mass: need 6 "
                                                        r"numbers"),
    (changed(N, bodies__0__linear_damping=[[0.0] * 6] * 5 + [[0, 0, 0, 0, 0, "x"]]),
     r"^bodies\[0\]\.linear_damping\[5\]\[5\]: expected a number, got 'x'$"),
    (changed(N, bodies__1={"name": "buoy", "kind": "fixed", "position": [0, 0, 0]}),
     r"^bodies\[1\]\.name: 'buoy' is used by bodies\[0\] too$"),
    (changed(N, body={"mass": 1.0}), r"^body: unknown section in the network layout"),
    (changed(N, lines=[]), r"^lines: define at least one line$"),
    (changed(N, lines__0__b="A3"), r"^lines\[0\]\.b: 'A3' is not one of the points \['A1', 'A2', "
                                   r"'F1', 'F2', 'clump'\]$"),
    (changed(N, lines__0__a=DROP), r"^lines\[0\]\.a: missing$"),
    (changed(N, lines__0__b="A1"), r"^lines\[0\]\.b: the line starts and ends at point 'A1'$"),
    (changed(N, lines__0__type="wire"), r"^lines\[0\]\.type: 'wire' is not one of the line_types"),
    (changed(N, lines__1__name="L1"), r"^lines\[1\]\.name: 'L1' is used by lines\[0\] too$"),
    (changed(N, lines__0__length=0), r"^lines\[0\]\.length: must be positive, got 0$"),
    (changed(N, lines__0__length=DROP), r"^lines\[0\]\.length: missing$"),
    (changed(N, lines__1__n_elements=0), r"^lines\[1\]\.n_elements: must be an integer >= 1"),
    (changed(N, lines__1__n_elements=10**7), r"^lines\[1\]\.n_elements: must be at most 100000"),
    (changed(N, lines__0__sag_ratio=0.02), r"^lines\[0\]\.sag_ratio: not a key of a line in the "
                                           r"network layout"),
    (changed(N, mooring__chord_angle_deg=45.0), r"^mooring\.chord_angle_deg: not used in the "
                                                r"network layout"),
    (changed(N, mooring__strain_law="hooke"), r"^mooring\.strain_law: 'hooke' is not"),
    (changed(N, load__body="nobody"), r"^load\.body: 'nobody' is not one of the bodies"),
    (changed(N, load__body="frame", bodies__1={"name": "frame", "kind": "fixed",
                                               "position": [0, 0, -50]}),
     r"^load\.body: body 'frame' is not dynamic"),
    (changed(N, bodies=DROP, points__2__kind="coupled", points__2__body=DROP,
             points__3__kind="coupled", points__3__body=DROP),
     r"^load: no dynamic body to apply the load to"),
    (changed(N, line_types__chain__EA=-1.0), r"^line_types\.chain\.EA: must be positive"),
    (changed(N, water__depth=DROP), r"^water\.depth: missing$"),
    (changed(N, solver__rho_inf=-0.1), r"^solver\.rho_inf: must lie in \[0, 1\]"),
    (changed(N, pionts=[]), r"^pionts: unknown section; did you mean 'points'\?$"),
]


@pytest.mark.parametrize("data, pattern", NETWORK_RULES)
def test_network_rule_names_the_field(data, pattern):
    with pytest.raises(ValueError, match=pattern):
        validate_case(data)
    refused(data)


def test_not_a_table():
    assert refused([1, 2]).startswith("case: expected a table")
    assert refused("case.toml").startswith("case: expected a table")


def test_several_errors_are_joined_on_one_line():
    message = refused(changed(P, water__depth=-1.0, solver__dt=0.0))
    assert message == ("water.depth: must be positive, got -1.0; "
                       "solver.dt: must be positive, got 0.0")


def test_long_values_are_cut_in_the_message():
    message = refused(changed(P, load__direction=list(range(1000))))
    assert len(message) < 200 and message.endswith("...")


def test_cases_the_old_validator_refuses_are_refused():
    """The messages of tests/sea/test_environment.py and tests/run/test_cli.py, as validate_case
    words them (the field by its dotted path)."""
    cases = [
        (changed(P, sea__waves=[{"type": "airy", "height": -1.0, "period": 8.0}]),
         "sea.waves[0].height"),
        (changed(P, sea__waves=[{"type": "stokes", "height": 1.0, "period": 8.0}]),
         "sea.waves[0].type"),
        (changed(P, sea__current_heading_deg=math.nan, sea__current_speed=1.0), "sea.current"),
        (changed(P, sea__swell=1.0), "sea.swell: unknown key"),
        (changed(P, seabed__mu_axial=-0.5), "seabed.mu_axial"),
        (changed(P, seabed__kbot=1e6), "seabed.kbot: unknown key"),
        (changed(P, line_types__steel__Cd_n=-1.0), "line_types.steel.Cd_n"),
        (changed(P, line_types__steel__BA="big"), "line_types.steel.BA: expected a number"),
        (changed(P, mooring__sag_ratio=0.7), "sag_ratio: must lie in (0, 0.5)"),
    ]
    for data, text in cases:
        assert text in refused(data)
        with pytest.raises(ValueError):
            Case(data)


# ------------------------------------------------------------------ fuzz

_scalars = (st.none() | st.booleans() | st.integers(-10**7, 10**7) | st.integers()
            | st.floats(allow_nan=True, allow_infinity=True) | st.text(max_size=8)
            | st.sampled_from([10**400, np.int64(3), np.float64("nan"), np.bool_(True), 1j,
                               "equilibrium", "box", "airy", "jonswap", "body", "fixed"]))
_arrays = st.lists(st.floats(allow_nan=True), max_size=7).map(np.array) | st.sampled_from(
    [np.zeros((6, 6)), np.eye(3), np.array(1.0), np.zeros((3, 0))])
_values = st.recursive(_scalars | _arrays, lambda inner: st.lists(inner, max_size=7)
                       | st.lists(inner, max_size=3).map(tuple)
                       | st.dictionaries(st.text(max_size=8) | st.integers(), inner, max_size=4),
                       max_leaves=12)
_known = sorted({"name", "type", "mass", "size", "draft", "hull", "E", "EA", "diameter",
                 "density", "n_elements", "anchor", "length", "sag_ratio", "chord_angle_deg",
                 "fairlead", "points", "bodies", "lines", "body", "kind", "position", "a", "b",
                 "waves", "ratio", "alpha", "scheme", "direction", "inertia", "volume",
                 "current_profile", "mooring", "sea", "seabed", "load", "solver", "damping"})
_keys = st.sampled_from(_known) | st.text(max_size=8) | st.integers(-3, 3) | st.none()


def _paths(node, prefix=()):
    """Every (container path, key) pair in a nested dict / list."""
    items = node.items() if isinstance(node, dict) else enumerate(node)
    for key, value in items:
        yield prefix, key
        if isinstance(value, (dict, list)):
            yield from _paths(value, prefix + (key,))


def _node(data, path):
    for key in path:
        data = data[key]
    return data


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_fuzz_only_one_line_value_errors(data):
    case = copy.deepcopy(data.draw(st.sampled_from([PAPER_CASE, NETWORK_CASE])))
    for _ in range(data.draw(st.integers(1, 4))):
        paths = list(_paths(case))
        if not paths:
            break
        path, key = data.draw(st.sampled_from(paths))
        parent = _node(case, path)
        action = data.draw(st.sampled_from(["drop", "replace", "insert"]))
        if action == "drop":
            del parent[key]
        elif action == "replace":
            parent[key] = data.draw(_values)
        else:
            target = parent[key] if isinstance(parent[key], dict) else parent
            if isinstance(target, dict):
                target[data.draw(_keys)] = data.draw(_values)
            else:
                target.append(data.draw(_values))
    try:
        assert validate_case(case) is case
    except ValueError as err:
        message = str(err)
        assert message and "\n" not in message and "Traceback" not in message
