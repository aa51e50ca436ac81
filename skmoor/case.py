"""Case description: what to simulate, read from TOML, checked with clear errors.

A case is a nested dict (the TOML file) turned into small dataclasses. ``Case.replace``
changes one value by its dotted path (``"mooring.sag_ratio"``), which is what parameter
studies vary. The paper's case (Wang, Er & Iu; resolved in design.md section 4) is
:func:`paper_case` and ships as ``examples/paper_case.toml``.
"""
from __future__ import annotations

import copy
import math
import sys
from dataclasses import dataclass
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

import numpy as np

from . import environment

PAPER_CASE = {
    "name": "Wang, Er & Iu: moored box, d/l = 1/60, theta = 50 deg",
    "water": {"density": 1025.0, "gravity": 9.81, "depth": 100.0},
    "body": {"shape": "box", "size": [26.0, 10.0, 5.0], "mass": 1.2e5, "draft": "equilibrium"},
    "line_types": {"steel": {"E": 2e11, "diameter": 0.1, "density": 8000.0}},
    "mooring": {"type": "steel", "n_elements": 11, "chord_angle_deg": 50.0,
                "sag_ratio": 1 / 60, "strain_law": "paper"},
    "lines": [
        {"name": "C1", "fairlead": [13.0, 5.0, -2.5]},
        {"name": "C2", "fairlead": [-13.0, -5.0, -2.5]},
        {"name": "C3", "fairlead": [-13.0, 5.0, -2.5]},
        {"name": "C4", "fairlead": [13.0, -5.0, -2.5]},
    ],
    "load": {"amplitude": 1e5, "omega": 1.6, "direction": [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]},
    "damping": {"ratio": 0.03},
    "solver": {"duration": 200.0, "dt": 0.05, "output_interval": 0.1,
               "scheme": "generalized-alpha", "rho_inf": 0.9, "steady_periods": 5},
}


@dataclass
class LineSpec:
    """One line: fairlead in body coordinates (relative to the CoM, m); its anchor either
    given (global, m) or placed on the sea bed along ``heading_deg`` (default: outward
    through the fairlead in plan) so that the chord makes ``chord_angle_deg`` with the
    horizontal; its length given (unstretched, m) or found from ``sag_ratio``."""

    name: str
    type: str
    fairlead: np.ndarray
    n_elements: int
    anchor: np.ndarray | None = None
    chord_angle_deg: float | None = None
    heading_deg: float | None = None
    length: float | None = None
    sag_ratio: float | None = None


@dataclass
class Case:
    """A validated case. ``data`` keeps the nested dict it was made from."""

    data: dict
    directory: Path | None = None  # the case file's folder: relative paths start there

    def __post_init__(self):
        self.data = copy.deepcopy(self.data)
        _validate(self.data)

    # -- convenient views
    @property
    def name(self) -> str:
        return self.data.get("name", "case")

    @property
    def water(self) -> dict:
        return self.data["water"]

    @property
    def body(self) -> dict:
        return self.data["body"]

    @property
    def load(self) -> dict:
        return self.data.get("load", {})

    @property
    def solver(self) -> dict:
        return {**PAPER_CASE["solver"], **self.data.get("solver", {})}

    @property
    def damping(self) -> dict:
        return self.data.get("damping", {"ratio": 0.0})

    @property
    def strain_law(self) -> str:
        return self.data.get("mooring", {}).get("strain_law", "paper")

    def line_specs(self) -> list[LineSpec]:
        shared = {k: v for k, v in self.data.get("mooring", {}).items() if k != "strain_law"}
        specs = []
        for entry in self.data["lines"]:
            d = {**shared, **entry}
            for key in ("fairlead", "anchor"):
                if d.get(key) is not None:
                    d[key] = np.asarray(d[key], float)
            specs.append(LineSpec(**d))
        return specs

    def replace(self, path: str, value) -> "Case":
        """A copy with the value at dotted ``path`` changed (e.g. ``"mooring.sag_ratio"``)."""
        data = copy.deepcopy(self.data)
        keys = path.split(".")
        node = data
        for key in keys[:-1]:
            node = node[int(key)] if isinstance(node, list) else node.setdefault(key, {})
        if isinstance(node, list):
            node[int(keys[-1])] = value
        else:
            node[keys[-1]] = value
        return Case(data, self.directory)

    def get(self, path: str):
        """The value at dotted ``path``."""
        node = self.data
        for key in path.split("."):
            node = node[int(key)] if isinstance(node, list) else node[key]
        return node

    @classmethod
    def from_toml(cls, path) -> "Case":
        path = Path(path)
        if not path.exists():
            raise FileNotFoundError(f"case file {path} does not exist")
        with open(path, "rb") as f:
            try:
                data = tomllib.load(f)
            except tomllib.TOMLDecodeError as err:
                raise ValueError(f"{path.name}: not valid TOML ({err})") from None
        try:
            return cls(data, path.resolve().parent)
        except ValueError as err:
            raise ValueError(f"{path.name}: {err}") from None


def paper_case(**changes) -> Case:
    """The paper's case; keyword arguments replace dotted paths written with ``__``
    (``paper_case(mooring__sag_ratio=1/45)``)."""
    case = Case(PAPER_CASE)
    for key, value in changes.items():
        case = case.replace(key.replace("__", "."), value)
    return case


# ---------------------------------------------------------------- validation

def _require(data, path, kind=float, positive=False, optional=False):
    node = data
    for key in path.split("."):
        if not isinstance(node, dict) or key not in node:
            if optional:
                return None
            raise ValueError(f"{path}: missing")
        node = node[key]
    values = node if isinstance(node, list) else [node]
    for v in values:
        if kind is float:
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise ValueError(f"{path}: expected a number, got {v!r}")
            if not math.isfinite(v):
                raise ValueError(f"{path}: must be finite, got {v!r}")
            if positive and v <= 0:
                raise ValueError(f"{path}: must be positive, got {v!r}")
    return node


def _validate(d: dict) -> None:
    if "points" in d:  # the explicit network tables: checked by the schema
        return
    for key in ("water.density", "water.gravity", "water.depth", "body.mass"):
        _require(d, key, positive=True)
    body = d.get("body", {})
    if body.get("shape", "box") != "box" and "hull" not in body:
        raise ValueError(f"body.shape: {body.get('shape')!r} is not 'box'; give body.hull "
                         "(a closed surface mesh) for other shapes")
    if body.get("shape", "box") == "box":
        size = _require(d, "body.size", positive=True)
        if len(size) != 3:
            raise ValueError(f"body.size: need [length, width, height], got {size}")
    draft = body.get("draft", "equilibrium")
    if draft != "equilibrium":
        _require(d, "body.draft", positive=True)
    types = d.get("line_types")
    if not types:
        raise ValueError("line_types: define at least one line type")
    for name, t in types.items():
        if "EA" in t:
            for key in ("EA", "mass", "diameter"):
                _require(d, f"line_types.{name}.{key}", positive=True)
        else:
            for key in ("E", "diameter", "density"):
                _require(d, f"line_types.{name}.{key}", positive=True)
        for key in ("Cd_n", "Cd_t", "Ca_n", "Ca_t", "BA"):
            if key in t and _require(d, f"line_types.{name}.{key}") < 0:
                raise ValueError(f"line_types.{name}.{key}: must be >= 0, got {t[key]}")
    environment.sea(d)
    environment.seabed(d)
    lines = d.get("lines")
    if not lines:
        raise ValueError("lines: define at least one line")
    shared = d.get("mooring", {})
    for i, entry in enumerate(lines):
        spec = {**shared, **entry}
        where = f"lines[{i}]" + (f" ({spec['name']})" if "name" in spec else "")
        if "name" not in spec:
            raise ValueError(f"{where}.name: missing")
        if spec.get("type") not in types:
            raise ValueError(f"{where}.type: {spec.get('type')!r} is not one of the line_types "
                             f"{sorted(types)}")
        for key in ("fairlead", "anchor"):
            if spec.get(key) is not None:
                arr = np.asarray(spec[key], float)
                if arr.shape != (3,) or not np.all(np.isfinite(arr)):
                    raise ValueError(f"{where}.{key}: need three finite numbers, got {spec[key]!r}")
        if "fairlead" not in spec:
            raise ValueError(f"{where}.fairlead: missing")
        if (spec.get("anchor") is None) == (spec.get("chord_angle_deg") is None):
            raise ValueError(f"{where}: give either anchor or chord_angle_deg")
        if spec.get("chord_angle_deg") is not None:
            a = spec["chord_angle_deg"]
            if not (isinstance(a, (int, float)) and 0 < a <= 90):
                raise ValueError(f"{where}.chord_angle_deg: must lie in (0, 90], got {a!r}")
        if (spec.get("length") is None) == (spec.get("sag_ratio") is None):
            raise ValueError(f"{where}: give either length or sag_ratio")
        if spec.get("sag_ratio") is not None:
            r = spec["sag_ratio"]
            if not (isinstance(r, (int, float)) and 0 < r < 0.5):
                raise ValueError(f"{where}.sag_ratio: must lie in (0, 0.5), got {r!r}")
        if spec.get("length") is not None and not spec["length"] > 0:
            raise ValueError(f"{where}.length: must be positive, got {spec['length']!r}")
        n = spec.get("n_elements", 0)
        if not (isinstance(n, int) and n >= 1):
            raise ValueError(f"{where}.n_elements: must be an integer >= 1, got {n!r}")
    if "load" in d:
        _require(d, "load.amplitude")
        _require(d, "load.omega")
        direction = _require(d, "load.direction")
        if len(direction) != 6:
            raise ValueError(f"load.direction: need 6 components [Fx Fy Fz Mx My Mz], got {direction}")
    if "damping" in d:
        ratio = _require(d, "damping.ratio", optional=True)
        if ratio is not None and not 0 <= ratio < 1:
            raise ValueError(f"damping.ratio: must lie in [0, 1), got {ratio}")
    solver = d.get("solver", {})
    for key in ("duration", "dt", "output_interval"):
        if key in solver:
            _require(d, f"solver.{key}", positive=True)
    if solver.get("scheme", "generalized-alpha") not in ("newmark", "generalized-alpha"):
        raise ValueError(f"solver.scheme: {solver['scheme']!r} is not 'newmark' or "
                         "'generalized-alpha'")
