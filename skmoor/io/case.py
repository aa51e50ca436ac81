"""Case description: what to simulate, read from TOML, checked by the schema
(:mod:`skmoor.io.schema`: unknown keys refused with the nearest valid name, types and
ranges with the field and the reason).

A case is a nested dict (the TOML file) turned into small dataclasses. ``Case.replace``
changes one value by its dotted path (``"mooring.sag_ratio"``), which is what parameter
studies vary. The paper's case (Wang, Er & Iu; resolved in docs/paper.md) is
:func:`paper_case` and ships as ``examples/paper_case.toml``.
"""
from __future__ import annotations

import copy
import sys
from dataclasses import dataclass
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

import numpy as np

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
        built_in = self.data is PAPER_CASE  # valid as written (tests/io/test_schema.py)
        self.data = copy.deepcopy(self.data)
        if not built_in:  # pydantic loads (~0.2 s) for case files and changed cases only
            from .schema import validate_case

            validate_case(self.data)

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
    def strain_law(self):
        """The lines' strain law: 'paper' (default) or 'engineering', or with
        ``mooring.tension_only = false`` the :class:`skmoor.lines.laws.Law` that carries
        compression."""
        mooring = self.data.get("mooring", {})
        name = mooring.get("strain_law", "paper")
        if mooring.get("tension_only", True):
            return name
        from ..lines.laws import LAWS
        return LAWS[name](tension_only=False)

    def line_specs(self) -> list[LineSpec]:
        shared = {k: v for k, v in self.data.get("mooring", {}).items()
                  if k not in ("strain_law", "tension_only")}
        specs = []
        for entry in self.data["lines"]:
            d = {**shared, **entry}
            for key in ("fairlead", "anchor"):
                if d.get(key) is not None:
                    d[key] = np.asarray(d[key], float)
            specs.append(LineSpec(**d))
        return specs

    def replace(self, path: str, value) -> Case:
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
    def from_toml(cls, path) -> Case:
        path = Path(path)
        if not path.exists():
            raise FileNotFoundError(f"case file {path} does not exist")
        if path.is_dir():
            raise ValueError(f"case file {path}: is a folder, not a case file (.toml)")
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
