"""The case file's schema: every section and key, checked with pydantic, errors in one line.

:func:`validate_case` takes the nested dict of a case (the TOML file) and returns it
unchanged (no defaults filled in) or raises ``ValueError`` with one line that names the
field by its dotted path and the reason::

    damping.ration: unknown key; did you mean 'ratio'?
    dampin: unknown section; did you mean 'damping'?
    lines[0].n_elements: must be an integer >= 1, got 0
    line_types.chain.EA: expected a number, got 'long'

A case has one of two layouts, told apart by the presence of ``[[points]]``:

- **parametric** (the paper's, no ``points``): ``[water]``, one box ``[body]``,
  ``[line_types.NAME]``, shared line keys in ``[mooring]`` and ``[[lines]]`` from a
  fairlead with an anchor or chord angle and a length or sag ratio;
- **network** (``[[points]]`` present): ``[water]``, ``[line_types.NAME]``,
  ``[[points]]`` (fixed / free / coupled / on a body), ``[[bodies]]`` and ``[[lines]]``
  joining two points (``a``, ``b``) with an unstretched ``length``.

Both share ``[load]``, ``[damping]``, ``[solver]``, ``[sea]`` and ``[seabed]``. Numbers
must be finite (no nan / inf) and booleans are not numbers.
"""
from __future__ import annotations

import difflib
import math
import numbers
from typing import Annotated, Any, ClassVar

import numpy as np
from pydantic import (
    BaseModel,
    ConfigDict,
    PlainValidator,
    ValidationError,
    model_validator,
)
from pydantic_core import PydanticCustomError

from ..lines.fatigue_curves import CURVES

__all__ = ["validate_case", "layout", "MAX_ELEMENTS_PER_LINE", "ParametricCase", "NetworkCase"]

#: The most elements one line may have: beyond it the model's matrices and the recorded
#: time series of the line would not fit in memory.
MAX_ELEMENTS_PER_LINE = 100_000

# ----------------------------------------------------------------------- error helpers


def _short(value, limit: int = 60) -> str:
    """repr of ``value`` on one line, cut to about ``limit`` characters."""
    try:
        text = repr(value)
    except Exception:  # pragma: no cover - a repr that fails
        text = f"<{type(value).__name__}>"
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _fail(reason: str, *path) -> None:
    """Raise the error pydantic collects: ``reason``, at ``path`` below the current field."""
    raise PydanticCustomError("skmoor", "{reason}", {"reason": reason, "path": tuple(path)})


def _closest(key: str, names) -> str | None:
    """The valid name nearest to ``key`` (difflib, ignoring case), or None."""
    lower = {}
    for name in names:
        lower.setdefault(name.lower(), name)
    close = difflib.get_close_matches(key.lower(), list(lower), n=1)
    return lower[close[0]] if close else None


def _join(loc) -> str:
    """('lines', 2, 'n_elements') -> 'lines[2].n_elements'."""
    out = ""
    for item in loc:
        if isinstance(item, int) and not isinstance(item, bool):
            out += f"[{item}]"
        else:
            out += ("." if out else "") + str(item)
    return out


_GENERIC = {
    "missing": "missing",
    "dict_type": "expected a table",
    "model_type": "expected a table",
    "model_attributes_type": "expected a table",
    "list_type": "expected a list",
    "string_type": "expected a string",
    "extra_forbidden": "unknown key",
}


def _message(error: dict) -> str:
    ctx = error.get("ctx") or {}
    loc = tuple(error["loc"]) + tuple(ctx.get("path", ()))
    if error["type"] == "skmoor":
        reason = ctx["reason"]
    elif loc[-1:] == ("[key]",) and error["type"] == "string_type":
        reason = f"a table's keys are strings, got {_short(loc[-2])}"
        loc = loc[:-2]
    elif error["type"] in _GENERIC:
        reason = _GENERIC[error["type"]]
        if error["type"] != "missing":
            reason += f", got {_short(error.get('input'))}"
    else:
        reason = str(error.get("msg", "invalid"))
    path = _join(loc)
    text = f"{path}: {reason}" if path else reason
    return " ".join(text.split())


# ----------------------------------------------------------------------- leaf checks


def _is_number(v) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))


def _is_int(v) -> bool:
    return isinstance(v, numbers.Integral) and not isinstance(v, (bool, np.bool_))


def _range_text(lo, hi, lo_open, hi_open) -> str:
    if hi is None:
        if lo == 0 and lo_open:
            return "must be positive"
        return f"must be {'>' if lo_open else '>='} {lo:g}"
    if lo is None:
        return f"must be {'<' if hi_open else '<='} {hi:g}"
    return f"must lie in {'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"


def _check_number(v, lo=None, hi=None, lo_open=False, hi_open=False, path=()):
    if not _is_number(v):
        _fail(f"expected a number, got {_short(v)}", *path)
    try:
        finite = math.isfinite(v)
    except OverflowError:           # an integer beyond the range of a float
        finite = False
    if not finite:
        _fail(f"must be finite, got {_short(v)}", *path)
    if ((lo is not None and (v <= lo if lo_open else v < lo))
            or (hi is not None and (v >= hi if hi_open else v > hi))):
        _fail(f"{_range_text(lo, hi, lo_open, hi_open)}, got {_short(v)}", *path)
    return v


def _number(lo=None, hi=None, lo_open=False, hi_open=False, none=False):
    def check(v):
        if v is None and none:
            return v
        return _check_number(v, lo, hi, lo_open, hi_open)
    return PlainValidator(check)


def _integer(lo, hi=None, why="", none=False):
    def check(v):
        if v is None and none:
            return v
        if not _is_int(v) or v < lo:
            _fail(f"must be an integer >= {lo}, got {_short(v)}")
        if hi is not None and v > hi:
            _fail(f"must be at most {hi}{why}, got {_short(v)}")
        return v
    return PlainValidator(check)


def _string(none=False):
    def check(v):
        if v is None and none:
            return v
        if not isinstance(v, str):
            _fail(f"expected a string, got {_short(v)}")
        if not v.strip():
            _fail("must not be empty")
        return v
    return PlainValidator(check)


def _choice(*options, none=False):
    names = [repr(o) for o in options]
    listed = (" or ".join(names) if len(names) <= 2
              else "one of " + ", ".join(names[:-1]) + " or " + names[-1])

    def check(v):
        if v is None and none:
            return v
        if not isinstance(v, str) or v not in options:
            _fail(f"{_short(v)} is not {listed}")
        return v
    return PlainValidator(check)


def _optional_flag(v):
    if v is None or isinstance(v, (bool, np.bool_)):
        return None if v is None else bool(v)
    _fail(f"expected true or false, got {_short(v)}")


def _as_list(v):
    """``v`` as a list when it is a list, tuple or (at least 1-d) numpy array, else None."""
    if isinstance(v, np.ndarray):
        return v.tolist() if v.ndim >= 1 else None
    return list(v) if isinstance(v, (list, tuple)) else None


def _check_vector(v, sizes, what, lo=None, lo_open=False, path=()):
    items = _as_list(v)
    if items is None or len(items) not in sizes:
        _fail(f"need {what}, got {_short(v)}", *path)
    for j, x in enumerate(items):
        _check_number(x, lo=lo, lo_open=lo_open, path=(*path, j))
    return items


def _vector(sizes=(3,), what="three finite numbers [x, y, z]", lo=None, lo_open=False,
            none=False):
    def check(v):
        if v is None and none:
            return v
        _check_vector(v, sizes, what, lo, lo_open)
        return v
    return PlainValidator(check)


def _check_matrix(v, n, what):
    """A list of n rows of n finite numbers, as a numpy array."""
    rows = _as_list(v)
    if rows is None or len(rows) != n or any(_as_list(r) is None or len(_as_list(r)) != n
                                             for r in rows):
        _fail(f"need {what}, got {_short(v)}")
    for i, row in enumerate(rows):
        for j, x in enumerate(_as_list(row)):
            _check_number(x, path=(i, j))
    return np.array([_as_list(r) for r in rows], dtype=float)


def _diagonal_or_matrix(n, unit):
    what = f"{n} numbers (the diagonal) or a {n}x{n} matrix ({unit})"

    def check(v):
        items = _as_list(v)
        if items is not None and len(items) == n and all(_is_number(x) for x in items):
            _check_vector(v, (n,), what)
        else:
            _check_matrix(v, n, what)
        return v
    return PlainValidator(check)


def _inertia(v):
    """[Ixx, Iyy, Izz] > 0 or a symmetric positive definite 3x3 (kg m2)."""
    what = "[Ixx, Iyy, Izz] or a 3x3 matrix about the centre of mass (kg m2)"
    items = _as_list(v)
    if items is not None and len(items) == 3 and all(_is_number(x) for x in items):
        _check_vector(v, (3,), what, lo=0, lo_open=True)
        return v
    matrix = _check_matrix(v, 3, what)
    if not np.allclose(matrix, matrix.T, rtol=1e-10, atol=0.0):
        _fail(f"must be symmetric, got {_short(v)}")
    if np.linalg.eigvalsh(matrix).min() <= 0.0:
        _fail(f"must be positive definite, got {_short(v)}")
    return v


def _draft(v):
    if v == "equilibrium" and isinstance(v, str):
        return v
    if isinstance(v, str) or not _is_number(v):
        _fail(f"must be 'equilibrium' or a positive number (m), got {_short(v)}")
    return _check_number(v, lo=0, lo_open=True)


def _current_profile(v):
    rows = _as_list(v)
    if not rows:
        _fail(f"need [[z, speed], ...] pairs, got {_short(v)}")
    for i, row in enumerate(rows):
        _check_vector(row, (2,), "a pair [z, speed]", path=(i,))
    z = [_as_list(r)[0] for r in rows]
    if len(set(z)) != len(z):
        _fail("two entries at the same z")
    return v


def _f_range(v):
    items = _check_vector(v, (2,), "[f_min, f_max] in Hz")
    if not 0.0 < items[0] < items[1]:
        _fail(f"need 0 < f_min < f_max (Hz), got {_short(v)}")
    return v


Number = Annotated[float, _number()]
OptNumber = Annotated[float | None, _number(none=True)]
Positive = Annotated[float, _number(lo=0, lo_open=True)]
OptPositive = Annotated[float | None, _number(lo=0, lo_open=True, none=True)]
NonNegative = Annotated[float, _number(lo=0)]
OptNonNegative = Annotated[float | None, _number(lo=0, none=True)]
Fraction = Annotated[float, _number(lo=0, hi=1)]
Name = Annotated[str, _string()]
Vector3 = Annotated[list, _vector()]
OptVector3 = Annotated[list | None, _vector(none=True)]
PositiveVector3 = Annotated[list, _vector(what="three positive numbers", lo=0, lo_open=True)]
DragVector = Annotated[list, _vector((3, 6), "3 or 6 numbers >= 0", lo=0)]
Matrix6 = Annotated[list, _diagonal_or_matrix(6, "about the reference point")]
Inertia = Annotated[list, PlainValidator(_inertia)]
Elements = Annotated[int, _integer(
    1, MAX_ELEMENTS_PER_LINE, " per line (the model's matrices and recorded time series "
    "would not fit in memory)")]
OptElements = Annotated[int | None, _integer(
    1, MAX_ELEMENTS_PER_LINE, " per line (the model's matrices and recorded time series "
    "would not fit in memory)", none=True)]
StrainLaw = Annotated[str, _choice("paper", "engineering")]
Rotations = Annotated[str, _choice("small", "exact")]  # skmoor.bodies.body.RigidBody.rotations
OptFlag = Annotated[bool | None, PlainValidator(_optional_flag)]


# ----------------------------------------------------------------------- tables
#
# Case.replace (and so paper_case(**changes) and every sweep point) validates after each
# single key it sets, so a rule between two keys must hold for every one-key edit the
# project makes: body drag_coefficients / drag_areas (set one after the other) and
# damping ratio / alpha, beta (a study of damping.alpha on the paper's case keeps its
# ratio) are therefore left to the build (skmoor.sea.hydro.body_hydrodynamics; run.py uses
# alpha / beta when either is given).


class _Table(BaseModel):
    """A TOML table: a dict whose keys are the model's fields, no others."""

    model_config = ConfigDict(extra="forbid", validate_default=False)
    #: what a key of this table is called in messages ("key" or "section")
    _kind: ClassVar[str] = "key"

    @classmethod
    def _allowed(cls, data: dict) -> list[str]:
        """The keys this table may hold (may depend on the data, e.g. a wave's type)."""
        return list(cls.model_fields)

    @classmethod
    def _hint(cls, key, data: dict) -> str | None:
        """A specific reason for refusing ``key``, or None for the generic one."""
        return None

    @model_validator(mode="before")
    @classmethod
    def _known_keys(cls, data):
        if not isinstance(data, dict):
            _fail(f"expected a table, got {_short(data)}")
        allowed = cls._allowed(data)
        for key in data:
            if key in allowed:
                continue
            hint = cls._hint(key, data)
            kind = cls._kind if isinstance(data[key], (dict, list)) else "key"
            if hint is None:
                close = _closest(str(key), allowed)
                hint = (f"unknown {kind}; did you mean {close!r}?" if close
                        else f"unknown {kind} (known: {', '.join(allowed)})")
            _fail(hint, key if isinstance(key, str) else _short(key))
        return data

    def _given(self, name) -> bool:
        return name in self.model_fields_set and getattr(self, name) is not None


class Water(_Table):
    density: Positive
    gravity: Positive
    depth: Positive


LINE_COEFFICIENTS = ("Cd_n", "Cd_t", "Ca_n", "Ca_t", "BA", "EI", "MBL", "MBR", "fatigue_curve",
                     "d_nom")
_BY_EA = ("EA", "mass", "diameter", "weight")
_BY_E = ("E", "diameter", "density")


class LineTypeSpec(_Table):
    """Either EA (N), mass (kg/m), diameter (m) [, weight (N/m, submerged)] or E (Pa),
    diameter (m), density (kg/m3); Morison coefficients, BA (N s) and the bending
    stiffness EI (N m2) >= 0; for the strength and fatigue checks the minimum breaking
    load MBL (N), the allowable bend radius MBR (m), the fatigue curve's name
    (skmoor.lines.fatigue_curves.CURVES) and the nominal diameter d_nom (m)."""

    EA: Positive = None
    mass: Positive = None
    diameter: Positive = None
    weight: Number = None
    E: Positive = None
    density: Positive = None
    Cd_n: NonNegative = None
    Cd_t: NonNegative = None
    Ca_n: NonNegative = None
    Ca_t: NonNegative = None
    BA: NonNegative = None
    EI: NonNegative = None
    MBL: Positive = None
    MBR: Positive = None
    fatigue_curve: Annotated[str, _choice(*CURVES)] = None
    d_nom: Positive = None

    @staticmethod
    def _by_EA(keys) -> bool:
        """True for the EA form: EA given, or (without E) mass or weight."""
        return "EA" in keys or ("E" not in keys and ("mass" in keys or "weight" in keys))

    @classmethod
    def _allowed(cls, data):
        return list((_BY_EA if cls._by_EA(data) else _BY_E) + LINE_COEFFICIENTS)

    @classmethod
    def _hint(cls, key, data):
        if key in _BY_EA + _BY_E:
            given = "EA" if "EA" in data else "E" if "E" in data else "mass"
            return (f"not used with {given} (a line type is EA, mass, diameter [, weight] "
                    "or E, diameter, density)")
        return None

    @model_validator(mode="after")
    def _complete(self):
        need = ("EA", "mass", "diameter") if self._by_EA(self.model_fields_set) else _BY_E
        for key in need:
            if key not in self.model_fields_set:
                _fail("missing (a line type is EA, mass, diameter [, weight] or "
                      "E, diameter, density)", key)
        return self


class PotentialFlowSpec(_Table):
    """A body's ``potential_flow`` table: Cummins' equation (skmoor.bodies.radiation) from the
    hull ``mesh`` (Capytaine, in the body frame about the reference point, like
    body.hull) or from WAMIT files ``wamit`` (the path without .1 / .3), with
    ``frequencies`` [first, last, step] (rad/s, for the mesh), wave ``headings`` (deg),
    the kernel's ``memory`` and the excitation's ``ramp`` (s)."""

    mesh: Name = None
    wamit: Name = None
    wamit_length: Positive = 1.0
    frequencies: Annotated[list, _vector(what="[first, last, step] in rad/s, all > 0", lo=0,
                                         lo_open=True)] = None
    headings: Annotated[list, _vector((1, 2, 3, 4, 5, 6, 7, 8), "1 to 8 headings (deg)")] = None
    memory: Positive = 60.0
    ramp: NonNegative = 0.0

    @model_validator(mode="after")
    def _source(self):
        given = [k for k in ("mesh", "wamit") if k in self.model_fields_set]
        if len(given) != 1:
            _fail("give one of mesh (a hull mesh for Capytaine) or wamit (WAMIT files)",
                  given[1] if given else "mesh")
        if "mesh" in given and "frequencies" not in self.model_fields_set:
            _fail("missing (need [first, last, step] in rad/s for the BEM solve)", "frequencies")
        if "frequencies" in self.model_fields_set:
            first, last, _step = self.frequencies
            if last < first:
                _fail(f"last {last} is below first {first} rad/s", "frequencies")
        return self


class ParametricBody(_Table):
    """The parametric layout's body: the box of ``size``, or the closed ``hull`` mesh
    (then ``inertia`` [Ixx, Iyy, Izz] about the centre of mass, or ``size`` for a uniform
    box's); the drag pair of MoorDyn's CdA (skmoor.model.environment.body_terms)."""

    shape: Name = "box"
    size: PositiveVector3 = None
    mass: Positive
    draft: Annotated[Any, PlainValidator(_draft)] = "equilibrium"
    hull: Name = None
    inertia: Annotated[list, _vector(what="[Ixx, Iyy, Izz] about the centre of mass (kg m2)",
                                     lo=0, lo_open=True)] = None
    drag_coefficients: DragVector = None
    drag_areas: DragVector = None
    potential_flow: PotentialFlowSpec = None
    rotations: Rotations = "small"

    @classmethod
    def _hint(cls, key, data):
        if key in ("added_mass", "linear_damping", "center_of_mass"):
            return ("not used by the parametric layout's body (a [[bodies]] entry of the "
                    "network layout takes it)")
        return None

    @model_validator(mode="after")
    def _shape(self):
        given = self.model_fields_set
        if "hull" not in given:
            if self.shape != "box":
                _fail(f"{self.shape!r} is not 'box'; give body.hull (a closed surface mesh) "
                      "for other shapes", "shape")
            if "size" not in given:
                _fail("missing (need [length, width, height] of the box, m)", "size")
            if "inertia" in given:
                _fail("not used for the box (its inertia is the uniform box's); only with "
                      "body.hull", "inertia")
            if isinstance(self.draft, numbers.Real) and self.draft >= self.size[2]:
                _fail(f"{self.draft} m must be less than the box height {self.size[2]} m",
                      "draft")
        elif "inertia" not in given and "size" not in given:
            _fail("missing (a hull body needs [Ixx, Iyy, Izz] about its centre of mass, or "
                  "size for a uniform box's)", "inertia")
        return self


_LINE_KEYS = ("type", "n_elements", "chord_angle_deg", "sag_ratio", "length", "heading_deg",
              "anchor")


class ParametricMooring(_Table):
    """Keys shared by all [[lines]] of the parametric layout, and the strain law."""

    type: Annotated[str | None, _string(none=True)] = None
    n_elements: OptElements = None
    chord_angle_deg: Annotated[float | None, _number(0, 90, lo_open=True, none=True)] = None
    sag_ratio: Annotated[float | None, _number(0, 0.5, True, True, none=True)] = None
    strain_law: StrainLaw = None
    tension_only: OptFlag = None
    length: OptPositive = None
    heading_deg: OptNumber = None
    anchor: OptVector3 = None


class ParametricLine(_Table):
    """A [[lines]] entry of the parametric layout (keys not given come from [mooring])."""

    name: Name
    fairlead: Vector3
    type: Annotated[str | None, _string(none=True)] = None
    n_elements: OptElements = None
    chord_angle_deg: Annotated[float | None, _number(0, 90, lo_open=True, none=True)] = None
    sag_ratio: Annotated[float | None, _number(0, 0.5, True, True, none=True)] = None
    length: OptPositive = None
    heading_deg: OptNumber = None
    anchor: OptVector3 = None

    @classmethod
    def _hint(cls, key, data):
        if key in ("strain_law", "tension_only"):
            return f"unknown key; the strain law is one for all lines: give mooring.{key}"
        return None


class Load(_Table):
    """F(t) = amplitude sin(omega t) direction (N, N m), at the body's reference point."""

    amplitude: Number
    omega: Positive  # rad/s
    direction: Annotated[list, _vector((6,), "6 components [Fx Fy Fz Mx My Mz]")]


class NetworkLoad(Load):
    body: Name = None


class Damping(_Table):
    """Rayleigh damping: ratio at the first two natural frequencies, or alpha (M) / beta (K)."""

    ratio: Annotated[float, _number(0, 1, hi_open=True)] = None
    alpha: NonNegative = None
    beta: NonNegative = None


class Solver(_Table):
    duration: Positive = None
    dt: Positive = None
    output_interval: Positive = None
    scheme: Annotated[str, _choice("newmark", "generalized-alpha")] = None
    rho_inf: Fraction = None
    steady_periods: Annotated[int, _integer(1)] = None


class Wave(_Table):
    """A [sea] wave: airy (height, period [, heading_deg, phase]) or jonswap (Hs, Tp
    [, gamma, heading_deg, seed, n_components, f_range])."""

    type: Annotated[str, _choice("airy", "jonswap")]
    heading_deg: Number = None
    height: Positive = None
    period: Positive = None
    phase: Number = None
    Hs: Positive = None
    Tp: Positive = None
    gamma: Positive = None
    seed: Annotated[int, _integer(0)] = None
    n_components: Annotated[int, _integer(1)] = None
    f_range: Annotated[list, PlainValidator(_f_range)] = None

    _KEYS: ClassVar[dict] = {
        "airy": ("type", "height", "period", "heading_deg", "phase"),
        "jonswap": ("type", "Hs", "Tp", "gamma", "heading_deg", "seed", "n_components",
                    "f_range"),
    }
    _REQUIRED: ClassVar[dict] = {"airy": ("height", "period"), "jonswap": ("Hs", "Tp")}

    @classmethod
    def _allowed(cls, data):
        kind = data.get("type")
        if "type" not in data:
            _fail("missing ('airy' or 'jonswap')", "type")
        if not isinstance(kind, str) or kind not in cls._KEYS:
            _fail(f"{_short(kind)} is not 'airy' or 'jonswap'", "type")
        return list(cls._KEYS[kind])

    @classmethod
    def _hint(cls, key, data):
        other = "jonswap" if data["type"] == "airy" else "airy"
        if key in cls._KEYS[other]:
            return f"not a key of an {data['type']!r} wave (it is one of a {other!r} wave)"
        return None

    @model_validator(mode="after")
    def _complete(self):
        for key in self._REQUIRED[self.type]:
            if key not in self.model_fields_set:
                _fail(f"missing (an {self.type!r} wave needs "
                      f"{' and '.join(self._REQUIRED[self.type])})", key)
        return self


class SeaSpec(_Table):
    """Currents (uniform current_speed or current_profile [[z, speed], ...]) and waves."""

    current_speed: Number = None
    current_heading_deg: Number = None
    current_profile: Annotated[list, PlainValidator(_current_profile)] = None
    waves: list[Wave] = None

    @model_validator(mode="after")
    def _one_current(self):
        if "current_speed" in self.model_fields_set and "current_profile" in self.model_fields_set:
            _fail("give either current_speed (uniform) or current_profile, not both",
                  "current_profile")
        return self


def _coordinates(v):
    """A list of at least one finite number (grid coordinates, m)."""
    items = _as_list(v)
    if not items:
        _fail(f"need a list of coordinates (m), got {_short(v)}")
    return _check_vector(v, (len(items),), "a list of coordinates (m)")


def _height_rows(v):
    """Rows of finite heights (m): heights[i][j] at (x[i], y[j])."""
    rows = _as_list(v)
    if not rows or any(_as_list(r) is None for r in rows):
        _fail(f"need rows of bed heights (m, z up): heights[i][j] at (x[i], y[j]), "
              f"got {_short(v)}")
    for i, row in enumerate(rows):
        _check_vector(row, (len(_as_list(row)),), "a row of heights (m)", path=(i,))
    return v


_GRID = ("x", "y", "heights")


class SeabedSpec(_Table):
    """Contact with the bed at the water depth (see :class:`skmoor.sea.seabed.Seabed`): a
    plane (slope_deg towards slope_heading_deg), or a bathymetry (the network layout):
    ``file`` (a MoorDyn seafloor file) or the grid ``x``, ``y``, ``heights``."""

    stiffness: OptPositive = None
    damping: OptNonNegative = None
    mu_axial: NonNegative = None
    mu_lateral: NonNegative = None
    slope_deg: Annotated[float, _number(0, 90, hi_open=True)] = None
    slope_heading_deg: Number = None
    friction_velocity: Positive = None
    damping_onset: OptNonNegative = None
    static_friction: Annotated[str, _choice("as-laid", "reference")] = None
    static_slip: Positive = None
    file: Name = None
    x: Annotated[list, PlainValidator(_coordinates)] = None
    y: Annotated[list, PlainValidator(_coordinates)] = None
    heights: Annotated[list, PlainValidator(_height_rows)] = None

    @model_validator(mode="after")
    def _bathymetry(self):
        grid = [k for k in _GRID if k in self.model_fields_set]
        if grid and "file" in self.model_fields_set:
            _fail("give a bathymetry file or the grid x, y, heights, not both", grid[0])
        if grid and len(grid) < 3:
            missing = next(k for k in _GRID if k not in grid)
            _fail("missing (a bathymetry grid needs x, y and heights)", missing)
        if (grid or "file" in self.model_fields_set) and self.slope_deg:
            _fail("give a slope or a bathymetry (file, or x, y, heights), not both",
                  "slope_deg")
        return self


def _unique(entries, section) -> dict:
    """{name: index} of ``entries``; a repeated name is an error."""
    seen = {}
    for i, entry in enumerate(entries):
        if entry.name in seen:
            _fail(f"{entry.name!r} is used by {section}[{seen[entry.name]}] too", section, i,
                  "name")
        seen[entry.name] = i
    return seen


def _one_of(value, names, what) -> str:
    listed = sorted(names)
    return f"{value!r} is not one of the {what} {listed}"


# ----------------------------------------------------------------------- parametric layout


def _both(first, second) -> str:
    """' (both given: ...)' for two merged (value, path) pairs that are both set."""
    if first[0] is None:
        return " (neither is given)"
    return f" (both are given: {_join(first[1])} and {_join(second[1])})"


class _CaseBase(_Table):
    _kind: ClassVar[str] = "section"
    _OTHER_LAYOUT: ClassVar[dict] = {}

    @classmethod
    def _hint(cls, key, data):
        return cls._OTHER_LAYOUT.get(key)

    def _check_line_types(self):
        if not self.line_types:
            _fail("define at least one line type", "line_types")


class ParametricCase(_CaseBase):
    """The paper's layout: one box body, lines from fairleads (no [[points]])."""

    name: Name = None
    water: Water
    body: ParametricBody
    line_types: dict[str, LineTypeSpec]
    mooring: ParametricMooring = None
    lines: list[ParametricLine]
    load: Load = None
    damping: Damping = None
    solver: Solver = None
    sea: SeaSpec = None
    seabed: SeabedSpec = None

    _OTHER_LAYOUT: ClassVar[dict] = {
        "bodies": "unknown section here; [[bodies]] belongs to the network layout, which "
                  "[[points]] selects (this case has no [[points]]: give one [body])",
    }

    @model_validator(mode="after")
    def _lines(self):
        self._check_line_types()
        if not self.lines:
            _fail("define at least one line", "lines")
        types = self.line_types
        shared = self.mooring
        names = {}
        for i, line in enumerate(self.lines):
            def merged(key):
                """(value, path of the key that gave it) after merging with [mooring]."""
                if key in line.model_fields_set:
                    return getattr(line, key), ("lines", i, key)
                if shared is not None and key in shared.model_fields_set:
                    return getattr(shared, key), ("mooring", key)
                return None, ("lines", i, key)

            if line.name in names:
                _fail(f"{line.name!r} is used by lines[{names[line.name]}] too", "lines", i,
                      "name")
            names[line.name] = i
            kind, where = merged("type")
            if kind is None:
                _fail("missing (give it in the line or in [mooring])", "lines", i, "type")
            if kind not in types:
                _fail(_one_of(kind, types, "line_types"), *where)
            if merged("n_elements")[0] is None:
                _fail("missing (give it in the line or in [mooring])", "lines", i, "n_elements")
            anchor, chord = merged("anchor"), merged("chord_angle_deg")
            if (anchor[0] is None) == (chord[0] is None):
                _fail("give either anchor or chord_angle_deg" + _both(anchor, chord), "lines", i)
            if anchor[0] is not None and merged("heading_deg")[0] is not None:
                _fail("not used when the anchor is given (heading_deg places the anchor "
                      "with chord_angle_deg)", *merged("heading_deg")[1])
            length, sag = merged("length"), merged("sag_ratio")
            if (length[0] is None) == (sag[0] is None):
                _fail("give either length or sag_ratio" + _both(length, sag), "lines", i)
        return self


# ----------------------------------------------------------------------- network layout


class Point(_Table):
    """A [[points]] entry. ``position`` is global, or in the body frame relative to the
    body's reference point for kind 'body'. ``smooth``: a free point joining two bending
    lines C1 (skmoor.coupling.network.Point)."""

    name: Name
    kind: Annotated[str, _choice("fixed", "free", "coupled", "body")] = "fixed"
    position: Vector3
    body: Name = None
    mass: NonNegative = None
    volume: NonNegative = None
    CdA: NonNegative = None
    Ca: NonNegative = None
    smooth: OptFlag = None

    @model_validator(mode="after")
    def _body(self):
        if self.smooth and self.kind != "free":
            _fail(f"only a free point is a smooth joint, this one is {self.kind!r}", "smooth")
        if self.kind == "body" and not self._given("body"):
            _fail("missing (a point of kind 'body' names its body)", "body")
        if self.kind != "body" and "body" in self.model_fields_set:
            _fail(f"only for points of kind 'body', this one is {self.kind!r}", "body")
        if self.kind == "body":
            for key in ("mass", "volume"):
                if getattr(self, key):
                    _fail("not supported on a point of kind 'body' (add it to the body)", key)
        return self


_HYDROSTATICS = ("size", "hull", "volume")


class BodySpec(_Table):
    """A [[bodies]] entry: a rigid body about its reference point ``position`` (default
    the origin). A dynamic body has mass, inertia and at most one of size (a floating box
    centred on the reference point), hull (a mesh) or volume (fully submerged, buoyancy at
    center_of_buoyancy); coupled and fixed bodies use only position and attitude."""

    name: Name
    kind: Annotated[str, _choice("dynamic", "coupled", "fixed")] = "dynamic"
    position: Vector3 = None
    attitude: Annotated[list, _vector(what="three finite numbers [roll, pitch, yaw] (deg)")] \
        = None
    mass: Positive = None
    center_of_mass: Vector3 = None
    inertia: Inertia = None
    size: PositiveVector3 = None
    hull: Name = None
    volume: NonNegative = None
    center_of_buoyancy: Vector3 = None
    added_mass: Matrix6 = None
    linear_damping: Matrix6 = None
    drag_coefficients: DragVector = None
    drag_areas: DragVector = None
    potential_flow: PotentialFlowSpec = None
    rotations: Rotations = "small"

    @model_validator(mode="after")
    def _complete(self):
        given = [k for k in _HYDROSTATICS if k in self.model_fields_set]
        if len(given) > 1:
            _fail(f"give one of size, hull, volume, not {' and '.join(given)}", given[1])
        if self.kind == "dynamic":
            for key, what in (("mass", "its mass, kg"), ("inertia", "[Ixx, Iyy, Izz] or a "
                              "3x3 matrix about its centre of mass, kg m2")):
                if key not in self.model_fields_set:
                    _fail(f"missing (a dynamic body needs {what})", key)
            if self.rotations == "exact" and self.size is None and self.hull is None \
                    and not self.volume:
                _fail("'exact' needs the body's buoyancy geometry: give size, hull or volume "
                      "(none: a body without buoyancy, for 'small' only)", "rotations")
            if self.attitude is not None and any(self.attitude):
                _fail("a dynamic body starts upright: give [0, 0, 0] (and its points in the "
                      "rotated frame)", "attitude")
        elif "rotations" in self.model_fields_set:
            _fail(f"only for a dynamic body (this one is {self.kind})", "rotations")
        if "center_of_buoyancy" in self.model_fields_set and "volume" not in self.model_fields_set:
            _fail("only with volume (a fully submerged body)", "center_of_buoyancy")
        return self


class NetworkLine(_Table):
    """A [[lines]] entry of the network layout: from point ``a`` to point ``b``."""

    name: Name
    type: Name
    a: Name
    b: Name
    length: Positive
    n_elements: Elements = None

    @classmethod
    def _hint(cls, key, data):
        if key in ("fairlead",) + _LINE_KEYS:
            return ("not a key of a line in the network layout (selected by [[points]]): a "
                    "line joins points a and b with an unstretched length")
        return None

    @model_validator(mode="after")
    def _ends(self):
        if self.a == self.b:
            _fail(f"the line starts and ends at point {self.a!r}", "b")
        return self


class FailureSpec(_Table):
    """A [[failures]] entry: the ends of ``lines`` released from ``point`` at ``time`` (s)
    or when the tension at one of them reaches ``tension`` (N), whichever first."""

    point: Name
    lines: list[Name]
    time: OptPositive = None
    tension: OptPositive = None

    @model_validator(mode="after")
    def _trigger(self):
        if not self.lines:
            _fail("name at least one line", "lines")
        if self.time is None and self.tension is None:
            _fail("give time (s) or tension (N), or both: what triggers the failure", "time")
        return self


class NetworkMooring(_Table):
    """The network layout's [mooring]: the strain law (default 'engineering'), whether
    the cables are tension-only (default true) and the lines' default n_elements (20
    without it)."""

    strain_law: StrainLaw = None
    tension_only: OptFlag = None
    n_elements: Elements = None

    @classmethod
    def _hint(cls, key, data):
        if key in _LINE_KEYS:
            return ("not used in the network layout (selected by [[points]]); its [mooring] "
                    "takes only strain_law, tension_only and n_elements")
        return None


class NetworkCase(_CaseBase):
    """The explicit network layout, selected by [[points]]."""

    name: Name = None
    water: Water
    line_types: dict[str, LineTypeSpec]
    points: list[Point]
    bodies: list[BodySpec] = None
    lines: list[NetworkLine]
    mooring: NetworkMooring = None
    load: NetworkLoad = None
    damping: Damping = None
    solver: Solver = None
    sea: SeaSpec = None
    seabed: SeabedSpec = None
    failures: list[FailureSpec] = None

    _OTHER_LAYOUT: ClassVar[dict] = {
        "body": "unknown section in the network layout (selected by [[points]]): describe "
                "bodies as [[bodies]] entries",
    }

    @model_validator(mode="after")
    def _references(self):
        self._check_line_types()
        if not self.points:
            _fail("define at least one point", "points")
        points = _unique(self.points, "points")
        bodies = _unique(self.bodies or [], "bodies")
        for i, point in enumerate(self.points):
            if point.kind == "body" and point.body not in bodies:
                _fail(_one_of(point.body, bodies, "bodies"), "points", i, "body")
        if not self.lines:
            _fail("define at least one line", "lines")
        _unique(self.lines, "lines")
        for i, line in enumerate(self.lines):
            if line.type not in self.line_types:
                _fail(_one_of(line.type, self.line_types, "line_types"), "lines", i, "type")
            for end in ("a", "b"):
                if getattr(line, end) not in points:
                    _fail(_one_of(getattr(line, end), points, "points"), "lines", i, end)
        lines = {line.name: line for line in self.lines}
        for i, failure in enumerate(self.failures or []):
            if failure.point not in points:
                _fail(_one_of(failure.point, points, "points"), "failures", i, "point")
            for name in failure.lines:
                if name not in lines or failure.point not in (lines[name].a, lines[name].b):
                    _fail(f"line {name!r} does not end at point {failure.point!r}",
                          "failures", i, "lines")
        if self.load is not None:
            dynamic = [b.name for b in self.bodies or [] if b.kind == "dynamic"]
            if self.load.body is not None:
                if self.load.body not in bodies:
                    _fail(_one_of(self.load.body, bodies, "bodies"), "load", "body")
                if self.load.body not in dynamic:
                    _fail(f"body {self.load.body!r} is not dynamic; a load needs a dynamic "
                          "body", "load", "body")
            elif not dynamic and self.load.amplitude != 0:
                _fail("no dynamic body to apply the load to (give [[bodies]] with kind "
                      "'dynamic', or drop [load])", "load")
        return self


# ----------------------------------------------------------------------- entry point


def layout(data: dict) -> str:
    """'network' when the case has [[points]], else 'parametric'."""
    return "network" if isinstance(data, dict) and "points" in data else "parametric"


def validate_case(data: dict) -> dict:
    """``data`` itself when it is a valid case (no defaults are filled in), else a
    ``ValueError`` with one line naming the field and the reason (up to three errors,
    joined with '; ')."""
    if not isinstance(data, dict):
        raise ValueError(f"case: expected a table (a dict), got {_short(data)}")
    model = NetworkCase if layout(data) == "network" else ParametricCase
    try:
        model.model_validate(data)
    except ValidationError as err:
        messages = []
        for error in err.errors(include_url=False):
            text = _message(error)
            if text not in messages:
                messages.append(text)
        raise ValueError("; ".join(messages[:3])) from None
    return data
