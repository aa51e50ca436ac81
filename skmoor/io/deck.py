"""MoorDyn v2 input decks: :func:`read_deck` into a :class:`Deck`, :func:`write_deck` back.

A v2 deck is plain text in sections. A section starts at a line holding ``---`` and the
section's name (``LINE TYPES``, ``POINTS``, ...); table sections have a line of column
names and a line of units after it, then one entry a line (columns split by blanks, ``#``
starts a comment); OPTIONS lines are ``value name``; OUTPUTS lists channel names; a last
``---`` line ends the deck. The text before the first section is free-form.

Read: LINE TYPES (EA: a number, a tension-strain curve file (path relative to the deck;
three header lines, then strain and tension a line) or MoorDyn's viscoelastic
``EA_s|EA_d`` / ``EA_s|alphaMBL|beta``, each EA_s a number or a curve file; BA or -zeta,
with ``BA|BA_D``; EI, Cd, Ca, CdAx, CaAx, optional VIV Cl dF cF), ROD TYPES (Name Diam
Mass/m Cd Ca CdEnd CaEnd), BODIES, RODS (ID RodType Attachment Xa Ya Za Xb Yb Zb NumSegs
RodOutputs), POINTS (9 columns, or 12 with a constant force), LINES between points and
rod ends (``R<N>A``, ``R<N>B``), OPTIONS (names as MoorDyn-C spells them, aliases
mapped; unknown options kept with a note), OUTPUTS and FAILURE (FailureID Point
Line(s) FailTime FailTen: line ends released in the run). Refused with the deck line and
the reason: damping and bending curve files and the MoorDyn-F-only sections CONTROL and
EXTERNAL LOADS. Syrope polyester (EA
``SYROPE:file|EA_Dc|EA_D_Lm``, the settings file naming the OWC table, WCType, k1, k2,
relative to the deck) with its SYROPE IC section (Line(s) Tmax0 Tmean0) is read too. The reader checks the format only; what
skmoor can simulate is checked when the model is built (:mod:`skmoor.model.from_deck`).

Units as MoorDyn: m, kg, N, s; body angles in degrees.
"""
from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

from ..numerics.validation import user_stacklevel
from .paths import resolve_inside

__all__ = ["Deck", "DeckLineType", "DeckPoint", "DeckLine", "DeckBody", "DeckRodType",
           "DeckRod", "read_deck", "write_deck", "is_deck"]

# section name as written -> canonical name (MoorDyn2.cpp's synonyms)
MAX_ELEMENTS_PER_LINE = 100_000  # as a case file's (schema.MAX_ELEMENTS_PER_LINE)
MAX_ROWS = 2_000  # lines (or rods) of one deck: MoorDyn's largest farms have hundreds
MAX_ELEMENTS = 10 * MAX_ELEMENTS_PER_LINE  # segments of all the lines of one deck

SECTIONS = {
    "LINE TYPES": "LINE TYPES", "LINE DICTIONARY": "LINE TYPES",
    "ROD TYPES": "ROD TYPES", "ROD DICTIONARY": "ROD TYPES",
    "BODIES": "BODIES", "BODY LIST": "BODIES", "BODY PROPERTIES": "BODIES",
    "RODS": "RODS", "ROD LIST": "RODS", "ROD PROPERTIES": "RODS",
    "POINTS": "POINTS", "POINT LIST": "POINTS", "POINT PROPERTIES": "POINTS",
    "CONNECTION PROPERTIES": "POINTS", "NODE PROPERTIES": "POINTS",
    "LINES": "LINES", "LINE LIST": "LINES", "LINE PROPERTIES": "LINES",
    "OPTIONS": "OPTIONS", "SOLVER OPTIONS": "OPTIONS",
    "OUTPUTS": "OUTPUTS", "OUTPUT": "OUTPUTS",
    "FAILURE": "FAILURE", "CONTROL": "CONTROL", "EXTERNAL LOADS": "EXTERNAL LOADS",
    "SYROPE IC": "SYROPE IC",
}
REFUSED_SECTIONS = {
    "CONTROL": "line control channels are not supported",
    "EXTERNAL LOADS": "external loads on points / bodies are not supported",
}
TABLES = ("LINE TYPES", "ROD TYPES", "BODIES", "RODS", "POINTS", "LINES", "FAILURE",
          "CONTROL", "EXTERNAL LOADS", "SYROPE IC")

# option name (lower case) -> the name MoorDyn-C reads
OPTION_NAMES = {
    "dtm": "dtM", "dt": "dtM", "cfl": "CFL", "writelog": "writeLog", "tscheme": "tScheme",
    "g": "g", "gravity": "g", "rho": "rho", "rhow": "rho", "wtrdnsty": "rho",
    "wtrdpth": "WtrDpth", "kbot": "kBot", "kb": "kBot", "cbot": "cBot", "cb": "cBot",
    "dtic": "dtIC", "icdt": "dtIC", "tmaxic": "TmaxIC", "ictmax": "TmaxIC",
    "cdscaleic": "CdScaleIC", "icdfac": "CdScaleIC", "threshic": "threshIC",
    "icthresh": "threshIC", "icgendynamic": "ICgenDynamic", "gendynamicic": "ICgenDynamic",
    "fileic": "fileIC", "icfile": "fileIC", "wavekin": "WaveKin", "dtwave": "dtWave",
    "currents": "Currents", "unifycurrentgrid": "UnifyCurrentGrid",
    "writeunits": "WriteUnits", "frictioncoefficient": "FrictionCoefficient",
    "fricdamp": "FricDamp", "cv": "FricDamp", "statdynfricscale": "StatDynFricScale",
    "mc": "StatDynFricScale", "dtout": "dtOut", "seafloorfile": "SeafloorFile",
    "disableoutput": "disableOutput", "disableouttime": "disableOutTime",
    # MoorDyn-F only (MoorDyn-C ignores them with a warning)
    "mu_kt": "mu_kT", "mu_ka": "mu_kA", "waterkin": "WaterKin", "inertialf": "inertialF",
    "inertialf_rampt": "inertialF_rampT", "outswitch": "OutSwitch",
}
F_ONLY = {"mu_kT", "mu_kA", "WaterKin", "inertialF", "inertialF_rampT", "OutSwitch"}
DEFAULTS = {"g": 9.80665, "rho": 1025.0, "WtrDpth": 0.0, "kBot": 3.0e6, "cBot": 3.0e5,
            "FrictionCoefficient": 0.0, "FricDamp": 200.0, "StatDynFricScale": 1.0,
            "dtOut": 0.0}  # MoorDyn-C's

POINT_KINDS = {"ANCHOR": "fixed", "FIXED": "fixed", "FIX": "fixed",
               "FAIRLEAD": "coupled", "VESSEL": "coupled", "VES": "coupled",
               "COUPLED": "coupled", "CPLD": "coupled",
               "POINT": "free", "CONNECT": "free", "CON": "free", "FREE": "free"}
BODY_KINDS = {"ANCHOR": "fixed", "FIXED": "fixed", "FIX": "fixed",
              "VESSEL": "coupled", "VES": "coupled", "COUPLED": "coupled", "CPLD": "coupled",
              "VESSELPINNED": "pinned", "VESPIN": "pinned", "CPLDPIN": "pinned",
              "COUPLEDPINNED": "pinned"}
WORD = {"fixed": "Fixed", "coupled": "Coupled", "free": "Free", "pinned": "CoupledPinned"}
ROD_KINDS = {"ANCHOR": "fixed", "FIXED": "fixed", "FIX": "fixed", "PINNED": "pinned",
             "PIN": "pinned", "VESSEL": "coupled", "VES": "coupled", "COUPLED": "coupled",
             "CPLD": "coupled", "VESSELPINNED": "coupled pinned", "VESPIN": "coupled pinned",
             "CPLDPIN": "coupled pinned", "COUPLEDPINNED": "coupled pinned",
             "POINT": "free", "CON": "free", "FREE": "free"}  # MoorDyn2.cpp's words
ROD_WORD = {"fixed": "Fixed", "pinned": "Pinned", "coupled": "Coupled",
            "coupled pinned": "CoupledPinned", "free": "Free"}


@dataclass
class DeckLineType:
    """A LINE TYPES entry. diameter (m, volume-equivalent), mass (kg/m), EA (N; of a
    curve, its last point's secant as MoorDyn takes it), BA (N s; a negative value is
    -zeta, a damping ratio per segment), EI (N m2), Cd, Ca (transverse), CdAx, CaAx
    (axial), viv: the optional (Cl,) or (Cl, dF, cF).

    EA_curve: the tension-strain curve ((strain, ...), (tension N, ...)) read from the
    file ``EA_file`` (as written in the deck), or () for a constant EA; EA_visco: the
    viscoelastic values after EA_s, (EA_d,) in N or (alphaMBL N, beta), () if none;
    BA_dynamic: BA_D (N s) of ``BA|BA_D``, or None."""

    name: str
    diameter: float
    mass: float
    EA: float
    BA: float
    EI: float
    Cd: float
    Ca: float
    CdAx: float
    CaAx: float
    viv: tuple = ()
    EA_curve: tuple = ()
    EA_file: str = ""
    EA_visco: tuple = ()
    BA_dynamic: float | None = None
    syrope: tuple = ()  # (settings file, (OWC strains, tensions), WCType, k1, k2) of SYROPE:
    where: int = field(default=0, compare=False)  # deck line number (1-based)


@dataclass
class DeckPoint:
    """A POINTS entry. kind: 'fixed' (anchor), 'coupled' (vessel / fairlead, moved by
    the caller), 'free', or 'body' (attached to body ``body``, position in its frame).
    position (m), mass (kg), volume (m3), CdA (m2), Ca, force (N, the optional columns)."""

    id: int
    kind: str
    position: tuple
    mass: float = 0.0
    volume: float = 0.0
    CdA: float = 0.0
    Ca: float = 0.0
    body: int | None = None
    force: tuple | None = None
    where: int = field(default=0, compare=False)

    @property
    def attachment(self) -> str:
        return f"Body{self.body}" if self.kind == "body" else WORD[self.kind]


@dataclass
class DeckRodType:
    """A ROD TYPES entry: diameter (m), mass (kg/m), Cd, Ca (transverse), CdEnd, CaEnd
    (the end caps, axial)."""

    name: str
    diameter: float
    mass: float
    Cd: float
    Ca: float
    CdEnd: float
    CaEnd: float
    where: int = field(default=0, compare=False)


@dataclass
class DeckRod:
    """A RODS entry. kind: 'fixed', 'pinned' (end A fixed in place, free to turn),
    'body' (on body ``body``; ``pinned``: by end A only), 'coupled', 'coupled pinned' or
    'free'. a, b: end positions (m; on a body, in its frame relative to its reference
    point); n_segments: NumSegs (0: a zero-length rod, MoorDyn's 6-DOF connection node;
    Free rods only, a == b)."""

    id: int
    type: str
    kind: str
    a: tuple
    b: tuple
    n_segments: int
    body: int | None = None
    pinned: bool = False
    outputs: str = "-"
    where: int = field(default=0, compare=False)

    @property
    def attachment(self) -> str:
        if self.kind == "body":
            return f"Body{self.body}" + ("Pinned" if self.pinned else "")
        return ROD_WORD[self.kind]


@dataclass
class DeckLine:
    """A LINES entry: from end ``a`` (end A, anchor end) to end ``b`` (end B): a point
    number, or a rod end ``'R<N>A'`` / ``'R<N>B'``; unstretched length (m), number of
    segments, MoorDyn's line-output flags."""

    id: int
    type: str
    a: int | str
    b: int | str
    length: float
    n_segments: int
    outputs: str = "-"
    where: int = field(default=0, compare=False)


@dataclass
class DeckFailure:
    """A FAILURE entry: the ends of ``lines`` (numbers) released from ``point`` (a point
    number, or a rod end ``'R<N>A'`` / ``'R<N>B'``) at ``time`` (s) or when their tension
    reaches ``tension`` (N), whichever first (0: no such trigger)."""

    id: int
    point: int | str
    lines: tuple
    time: float
    tension: float
    where: int = field(default=0, compare=False)


@dataclass
class DeckBody:
    """A BODIES entry. kind: 'fixed', 'coupled', 'pinned' or 'free'. r6: x, y, z (m) and
    roll, pitch, yaw (deg). cg, inertia, CdA, Ca: tuples as written (MoorDyn expands 1 or
    3 values; CdA also 2 or 6)."""

    id: int
    kind: str
    r6: tuple
    mass: float
    cg: tuple
    inertia: tuple
    volume: float
    CdA: tuple
    Ca: tuple
    where: int = field(default=0, compare=False)

    @property
    def attachment(self) -> str:
        return WORD.get(self.kind, "Free")


@dataclass
class Deck:
    """A MoorDyn v2 deck. options: MoorDyn-C option name -> value as written (str);
    notes: what the reader kept without using (never compared)."""

    title: list = field(default_factory=list)
    line_types: dict = field(default_factory=dict)
    rod_types: dict = field(default_factory=dict)
    bodies: list = field(default_factory=list)
    rods: list = field(default_factory=list)
    points: list = field(default_factory=list)
    lines: list = field(default_factory=list)
    options: dict = field(default_factory=dict)
    outputs: list = field(default_factory=list)
    source: str = field(default="deck", compare=False)
    folder: Path = field(default=Path("."), compare=False)  # MoorDyn's wave / current files
    notes: list = field(default_factory=list, compare=False)
    option_lines: dict = field(default_factory=dict, compare=False)
    syrope_ic: dict = field(default_factory=dict)  # line id -> (Tmax0, Tmean0) N, SYROPE IC
    failures: list = field(default_factory=list)  # DeckFailure entries

    def option(self, name: str, default=None):
        """The option ``name`` (MoorDyn-C spelling) as a float, or ``default``
        (MoorDyn-C's default when ``default`` is None and it has one)."""
        if name not in self.options:
            return DEFAULTS.get(name) if default is None else default
        value = self.options[name]
        try:
            return float(value)
        except ValueError:
            raise ValueError(f"{self.where(name)}: option {name}: {value!r} is not a "
                             "number") from None

    def where(self, option: str) -> str:
        """'deck line N' of an option, for messages."""
        return f"{self.source} line {self.option_lines.get(option, '?')}"

    @property
    def depth(self) -> float:
        """Water depth, m: WtrDpth, raised to the lowest fixed / free / coupled point as
        MoorDyn-C does."""
        lowest = [-p.position[2] for p in self.points if p.kind != "body"]
        return max([self.option("WtrDpth")] + lowest)

    @property
    def rho(self) -> float:
        return self.option("rho")

    @property
    def g(self) -> float:
        return self.option("g")

    @property
    def coupled_sizes(self) -> list:
        """DOFs of each coupled object in MoorDyn's order (its NCoupledDOF): bodies (6,
        coupled or pinned), rods (6 coupled, 3 coupled pinned), points (3)."""
        return ([6 for b in self.bodies if b.kind in ("coupled", "pinned")]
                + [6 if r.kind == "coupled" else 3 for r in self.rods
                   if r.kind in ("coupled", "coupled pinned")]
                + [3 for p in self.points if p.kind == "coupled"])

    def point(self, point_id: int) -> DeckPoint:
        return self.points[point_id - 1]


# ------------------------------------------------------------------------ reading

class _Entry:
    """One table line: its words, the deck line number, and the source name."""

    def __init__(self, words, number, source, section):
        self.words, self.number, self.source, self.section = words, number, source, section

    def error(self, what: str) -> ValueError:
        return ValueError(f"{self.source} line {self.number}: {self.section} {what}")

    def number_at(self, index: int, name: str, *, curve_ok=False) -> float:
        text = self.words[index]
        try:
            value = float(text)
        except ValueError:
            if "|" in text:
                raise self.error(f"{name}: {text!r} has several '|'-separated values "
                                 "(viscoelastic or load-dependent models are not "
                                 "supported; give one number)") from None
            if curve_ok:
                raise self.error(f"{name}: {text!r} is not a number (a curve file? "
                                 "only constant values are supported)") from None
            raise self.error(f"{name}: {text!r} is not a number") from None
        if not math.isfinite(value):
            raise self.error(f"{name}: must be finite, got {text!r}")
        return value

    def integer_at(self, index: int, name: str) -> int:
        text = self.words[index]
        if not re.fullmatch(r"[+-]?\d+", text):
            raise self.error(f"{name}: {text!r} is not an integer")
        return int(text)

    def bar_numbers(self, index: int, name: str, counts) -> tuple:
        parts = self.words[index].split("|")
        if len(parts) not in counts:
            raise self.error(f"{name}: {self.words[index]!r} must have "
                             f"{' or '.join(map(str, counts))} '|'-separated numbers")
        values = []
        for part in parts:
            try:
                values.append(float(part))
            except ValueError:
                raise self.error(f"{name}: {part!r} is not a number") from None
        return tuple(values)


def _section_of(text: str):
    """Canonical section name of a header line, '' for a '---' line of no known section,
    None for an ordinary line."""
    if "---" not in text:
        return None
    name = " ".join(text.replace("-", " ").split()).upper()
    for written in sorted(SECTIONS, key=len, reverse=True):
        if re.search(rf"(^|\s){written}($|\s)", name):
            return SECTIONS[written]
    return ""


def read_deck(path) -> Deck:
    """Read a MoorDyn v2 input file into a :class:`Deck` (see the module docstring for
    what is supported); a ValueError names the deck line and the reason. Curve files are
    read relative to the deck's folder, as MoorDyn does."""
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"deck {path} does not exist")
    if path.is_dir():
        raise ValueError(f"deck {path}: is a folder, not a MoorDyn input file")
    text = path.read_text(encoding="utf-8", errors="replace").splitlines()
    deck = Deck(source=path.name, folder=path.parent)
    entries = _split_sections(text, deck)
    for entry in entries.get("LINE TYPES", []):
        _line_type(entry, deck, path.parent)
    for entry in entries.get("ROD TYPES", []):
        _rod_type(entry, deck)
    for entry in entries.get("BODIES", []):
        _body(entry, deck)
    for entry in entries.get("RODS", []):
        _rod(entry, deck)
    for entry in entries.get("POINTS", []):
        _point(entry, deck)
    _check_count(entries.get("LINES", []), "LINES", "lines", deck)
    _check_count(entries.get("RODS", []), "RODS", "rods", deck)
    for entry in entries.get("LINES", []):
        _line(entry, deck)
    elements = sum(line.n_segments for line in deck.lines)
    if elements > MAX_ELEMENTS:
        raise ValueError(f"{deck.source}: LINES NumSegs: {elements} segments in all, at most "
                         f"{MAX_ELEMENTS} (the model's matrices and recorded time series "
                         "would not fit in memory)")
    for entry in entries.get("SYROPE IC", []):
        _syrope_ic(entry, deck)
    for entry in entries.get("FAILURE", []):
        _failure(entry, deck)
    for entry in entries.get("OPTIONS", []):
        _option(entry, deck)
    for entry in entries.get("OUTPUTS", []):
        deck.outputs.extend(entry.words)
    return deck


def _check_count(entries, section, what, deck):
    """Refuse a table with more rows than a model runs, before reading them."""
    if len(entries) > MAX_ROWS:
        raise ValueError(f"{deck.source}: {section}: {len(entries)} {what}, at most "
                         f"{MAX_ROWS} (a model that size would run for days)")


def _split_sections(text, deck):
    """Table / option entries of each section, the header and units lines skipped."""
    entries, section, skip, seen, unknown = {}, None, 0, set(), ""
    for number, raw in enumerate(text, start=1):
        header = _section_of(raw)
        if header is not None:
            if header in seen:
                raise ValueError(f"{deck.source} line {number}: a second {header} section")
            if header:
                seen.add(header)
            section, skip, unknown = header, (2 if header in TABLES else 0), raw.strip()
            continue
        if not seen:  # free-form text above the first section
            deck.title.append(raw.rstrip())
            continue
        if skip:
            skip -= 1
            continue
        words = raw.split("#", 1)[0].split()
        if not words:
            continue
        if not section:
            raise ValueError(f"{deck.source} line {number}: {raw.strip()!r} under "
                             f"{unknown!r}, which is no section of a MoorDyn v2 deck")
        if section in REFUSED_SECTIONS:
            raise ValueError(f"{deck.source} line {number}: {section}: "
                             f"{REFUSED_SECTIONS[section]}")
        if section == "OUTPUTS" and [w.upper() for w in words] == ["END"]:
            continue  # the v1 end marker
        entries.setdefault(section, []).append(_Entry(words, number, deck.source, section))
    while deck.title and not deck.title[-1].strip():
        deck.title.pop()
    return entries


def _line_type(e, deck, folder=Path(".")):
    if len(e.words) < 10 or len(e.words) in (12,) or len(e.words) > 13:
        raise e.error(f"entry: needs the 10 columns Name Diam Mass/m EA BA/-zeta EI Cd Ca "
                      f"CdAx CaAx (optionally Cl, or Cl dF cF), got {len(e.words)}")
    name = e.words[0]
    if name in deck.line_types:
        raise e.error(f"name: {name!r} is defined twice")
    syrope = ()
    if e.words[3].upper().startswith("SYROPE:"):
        EA, syrope, visco = _syrope_stiffness(e, folder)
        curve, curve_file = (), ""
    else:
        EA, curve, curve_file, visco = _axial_stiffness(e, folder)
    BA, BA_dynamic = _damping(e, len(visco) + 1)
    lt = DeckLineType(
        name=name, diameter=e.number_at(1, "Diam"), mass=e.number_at(2, "Mass/m"),
        EA=EA, BA=BA, EI=e.number_at(5, "EI", curve_ok=True), Cd=e.number_at(6, "Cd"),
        Ca=e.number_at(7, "Ca"), CdAx=e.number_at(8, "CdAx"), CaAx=e.number_at(9, "CaAx"),
        viv=tuple(e.number_at(i, n) for i, n in zip(range(10, len(e.words)),
                                                    ("Cl", "dF", "cF"))),
        EA_curve=curve, EA_file=curve_file, EA_visco=visco, BA_dynamic=BA_dynamic,
        syrope=syrope, where=e.number)
    for column, value in (("Diam", lt.diameter), ("Mass/m", lt.mass), ("EA", lt.EA)):
        if value <= 0:
            raise e.error(f"{column}: must be positive, got {value:g}")
    if lt.EI < 0:
        raise e.error(f"EI: bending stiffness must be >= 0 N m2, got {lt.EI:g}")
    deck.line_types[name] = lt


def _axial_stiffness(e, folder):
    """(EA N, curve, curve file, viscoelastic values) of a LINE TYPES EA column: a number
    or a curve file, then optionally '|' EA_d or '|' alphaMBL '|' beta."""
    parts = e.words[3].split("|")
    if len(parts) > 3:
        raise e.error(f"EA: {e.words[3]!r} has {len(parts)} '|'-separated values; MoorDyn "
                      "takes EA_s, EA_s|EA_d or EA_s|alphaMBL|beta")
    visco = []
    for part, label in zip(parts[1:], ("EA_d" if len(parts) == 2 else "alphaMBL", "beta")):
        try:
            value = float(part)
        except ValueError:
            raise e.error(f"EA: {label} {part!r} is not a number") from None
        if not (math.isfinite(value) and value >= 0):
            raise e.error(f"EA: {label} must be a finite number >= 0, got {part!r}")
        visco.append(value)
    if len(parts) == 2 and visco[0] <= 0:
        raise e.error(f"EA: EA_d must be positive, got {parts[1]!r}")
    try:
        EA = float(parts[0])
    except ValueError:
        curve = _curve_file(e, folder, parts[0])
        return curve[1][-1] / curve[0][-1], curve, parts[0], tuple(visco)
    if not math.isfinite(EA):
        raise e.error(f"EA: must be finite, got {parts[0]!r}")
    if len(parts) == 2 and visco[0] == EA:
        raise e.error(f"EA: EA_d = EA_s = {EA:g} N: the dynamic stiffness must differ from the "
                      "static one (MoorDyn refuses it too)")
    return EA, (), "", tuple(visco)


def _syrope_stiffness(e, folder):
    """(EA N, syrope, (alphaMBL, beta)) of a LINE TYPES EA column SYROPE:file|EA_Dc|EA_D_Lm."""
    from ..lines.syrope import read_owc, read_syrope_file

    parts = e.words[3].split("|")
    if len(parts) != 3:
        raise e.error(f"EA: {e.words[3]!r}: a Syrope EA is SYROPE:file|EA_Dc|EA_D_Lm "
                      f"(3 '|'-separated values), got {len(parts)}")
    visco = []
    for part, label in zip(parts[1:], ("EA_Dc", "EA_D_Lm")):
        try:
            visco.append(float(part))
        except ValueError:
            raise e.error(f"EA: Syrope {label} {part!r} is not a number") from None
        if not (math.isfinite(visco[-1]) and visco[-1] >= 0):
            raise e.error(f"EA: Syrope {label} must be a finite number >= 0, got {part!r}")
    name = parts[0][len("SYROPE:"):]
    where = f"{e.source} line {e.number}: LINE TYPES EA"
    owc_name, form, k1, k2 = read_syrope_file(resolve_inside(name, folder, where), source=where)
    # the OWC table is named relative to the deck; MoorDyn's own Syrope decks keep it one
    # folder up (../owc.dat), shared by the decks of several working curves
    owc = read_owc(resolve_inside(owc_name, folder, f"{where} ({name}) OWC",
                                  root=Path(folder).resolve().parent),
                   source=f"{where} ({name})")
    return owc[1][-1] / owc[0][-1], (name, owc, form, k1, k2), tuple(visco)


def _syrope_ic(e, deck):
    """A SYROPE IC entry: Line(s) (a number or a comma-separated list) Tmax0 Tmean0 (N)."""
    if len(e.words) != 3:
        raise e.error(f"entry: needs the 3 columns Line(s) Tmax0 Tmean0, got {len(e.words)}")
    Tmax0, Tmean0 = e.number_at(1, "Tmax0"), e.number_at(2, "Tmean0")
    if not 0 <= Tmean0 <= Tmax0:
        raise e.error(f"Tmean0: must be within [0, Tmax0 = {Tmax0:g}] N, got {Tmean0:g}")
    for word in e.words[0].split(","):
        try:
            line = int(word)
        except ValueError:
            raise e.error(f"Line(s): {word!r} is not a line number") from None
        if not any(ln.id == line for ln in deck.lines):
            raise e.error(f"Line(s): there is no line {line}")
        deck.syrope_ic[line] = (Tmax0, Tmean0)


def _curve_file(e, folder, name):
    """((strain, ...), (tension, ...)) of a MoorDyn curve file named in the EA column."""
    from ..lines.laws import read_curve

    where = f"{e.source} line {e.number}: LINE TYPES EA"
    path = resolve_inside(name, folder, where)
    if not path.is_file():
        raise ValueError(f"{where}: {name!r} is neither a number nor a curve file (no file "
                         f"{path})")
    curve = read_curve(path, source=where)
    return tuple(curve.strain), tuple(curve.tension_values)


def _damping(e, allowed):
    """(BA, BA_D or None) of the BA/-zeta column: a number, or BA|BA_D after a
    viscoelastic EA."""
    parts = e.words[4].split("|")
    if len(parts) > max(allowed, 1) or len(parts) > 2:
        raise e.error(f"BA/-zeta: {e.words[4]!r} has more '|'-separated values than the EA "
                      "column allows (BA|BA_D goes with a viscoelastic EA_s|...)")
    values = []
    for part in parts:
        try:
            values.append(float(part))
        except ValueError:
            raise e.error(f"BA/-zeta: {part!r} is not a number (damping curve files are "
                          "not supported)") from None
        if not math.isfinite(values[-1]):
            raise e.error(f"BA/-zeta: must be finite, got {part!r}")
    if len(values) == 2 and values[1] < 0:
        raise e.error(f"BA/-zeta: BA_D = {values[1]:g} cannot be a damping ratio (MoorDyn)")
    return values[0], (values[1] if len(values) == 2 else None)


def _decompose(word):
    """MoorDyn's split of an attachment word: (LETTERS, number or None, rest)."""
    m = re.fullmatch(r"([A-Za-z_]*)(\d*)([A-Za-z]*)", word)
    if not m:
        return word.upper(), None, ""
    return m.group(1).upper(), (int(m.group(2)) if m.group(2) else None), m.group(3).upper()


def _next_id(e, entries):
    """The entry's ID, which must count up from 1 within its section."""
    number = e.integer_at(0, "ID")
    if number != len(entries) + 1:
        raise e.error(f"ID: must count up from 1 (expected {len(entries) + 1}, got {number})")
    return number


def _body(e, deck):
    if len(e.words) < 14:
        raise e.error("entry: needs the 14 columns ID Attachment X0 Y0 Z0 r0 p0 y0 Mass "
                      f"CG* I* Volume CdA* Ca*, got {len(e.words)}")
    number = _next_id(e, deck.bodies)
    letters, _, _ = _decompose(e.words[1])
    deck.bodies.append(DeckBody(
        id=number, kind=BODY_KINDS.get(letters, "free"),
        r6=tuple(e.number_at(i, c) for i, c in zip(range(2, 8),
                                                   ("X0", "Y0", "Z0", "r0", "p0", "y0"))),
        mass=e.number_at(8, "Mass"), cg=e.bar_numbers(9, "CG", (1, 3)),
        inertia=e.bar_numbers(10, "I", (1, 3)), volume=e.number_at(11, "Volume"),
        CdA=e.bar_numbers(12, "CdA", (1, 2, 3, 6)), Ca=e.bar_numbers(13, "Ca", (1, 3)),
        where=e.number))


def _rod_type(e, deck):
    if len(e.words) < 7:
        raise e.error("entry: needs the 7 columns TypeName Diam Mass/m Cd Ca CdEnd CaEnd, "
                      f"got {len(e.words)}")
    name = e.words[0]
    if name in deck.rod_types:
        raise e.error(f"name: {name!r} is defined twice")
    values = [e.number_at(i, c) for i, c in enumerate(
        ("Diam", "Mass/m", "Cd", "Ca", "CdEnd", "CaEnd"), start=1)]
    for column, value in zip(("Diam", "Mass/m"), values):
        if value <= 0:
            raise e.error(f"{column}: must be positive, got {value:g}")
    for column, value in zip(("Cd", "Ca", "CdEnd", "CaEnd"), values[2:]):
        if value < 0:
            raise e.error(f"{column}: must be >= 0, got {value:g}")
    deck.rod_types[name] = DeckRodType(name, *values, where=e.number)


def _rod(e, deck):
    if len(e.words) < 11:
        raise e.error("entry: needs the 11 columns ID RodType Attachment Xa Ya Za Xb Yb Zb "
                      f"NumSegs RodOutputs, got {len(e.words)}")
    number = _next_id(e, deck.rods)
    if e.words[1] not in deck.rod_types:
        raise e.error(f"RodType: {e.words[1]!r} is not in ROD TYPES "
                      f"({', '.join(deck.rod_types) or 'none'})")
    letters, body, rest = _decompose(e.words[2])
    pinned = False
    if letters == "BODY":
        if body is None or not 1 <= body <= len(deck.bodies):
            raise e.error(f"Attachment: {e.words[2]!r} names no body of the BODIES "
                          f"section ({len(deck.bodies)} bodies)")
        if rest not in ("", "PIN", "PINNED"):
            raise e.error(f"Attachment: {e.words[2]!r} is not Body<N> or Body<N>Pinned")
        kind, pinned = "body", rest != ""
    elif letters in ROD_KINDS and body is None:
        kind = ROD_KINDS[letters]
    else:
        raise e.error(f"Attachment: {e.words[2]!r} is not Fixed, Pinned, Body<N>, "
                      "Body<N>Pinned, Coupled, CoupledPinned or Free")
    columns = ("Xa", "Ya", "Za", "Xb", "Yb", "Zb")
    ends = [e.number_at(i, c) for i, c in zip(range(3, 9), columns)]
    segments = e.integer_at(9, "NumSegs")
    if segments < 0:
        raise e.error(f"NumSegs: must be >= 0, got {segments}")
    if segments > MAX_ELEMENTS_PER_LINE:
        raise e.error(f"NumSegs: must be at most {MAX_ELEMENTS_PER_LINE} per rod, got "
                      f"{segments}")
    if segments == 0 and kind != "free":
        raise e.error(f"NumSegs: 0 makes a zero-length rod (MoorDyn's 6-DOF connection "
                      f"node), supported as a Free rod only (this one is {e.words[2]})")
    if segments == 0 and ends[:3] != ends[3:]:
        raise e.error("NumSegs: 0 (a zero-length rod) needs ends A and B at the same place")
    if segments > 0 and ends[:3] == ends[3:]:
        raise e.error("Xa..Zb: ends A and B at the same place need NumSegs = 0 (a "
                      "zero-length rod)")
    deck.rods.append(DeckRod(id=number, type=e.words[1], kind=kind, a=tuple(ends[:3]),
                             b=tuple(ends[3:]), n_segments=segments,
                             body=body if kind == "body" else None, pinned=pinned,
                             outputs=e.words[10], where=e.number))


def _point(e, deck):
    if len(e.words) not in (9, 12):
        raise e.error("entry: needs the 9 columns ID Attachment X Y Z Mass Volume CdA Ca "
                      f"(or 12 with FX FY FZ before CdA), got {len(e.words)}")
    number = _next_id(e, deck.points)
    letters, body, _ = _decompose(e.words[1])
    if letters == "BODY":
        if body is None or not 1 <= body <= len(deck.bodies):
            raise e.error(f"Attachment: {e.words[1]!r} names no body of the BODIES "
                          f"section ({len(deck.bodies)} bodies)")
        kind = "body"
    elif letters in POINT_KINDS:
        kind, body = POINT_KINDS[letters], None
    else:
        raise e.error(f"Attachment: {e.words[1]!r} is not Fixed/Anchor, Coupled/Vessel, "
                      "Free/Point or Body<N>")
    force = None
    if len(e.words) == 12:
        force = tuple(e.number_at(i, c) for i, c in zip((7, 8, 9), ("FX", "FY", "FZ")))
    k = 10 if force is not None else 7
    deck.points.append(DeckPoint(
        id=number, kind=kind, body=body,
        position=tuple(e.number_at(i, c) for i, c in zip((2, 3, 4), ("X", "Y", "Z"))),
        mass=e.number_at(5, "Mass"), volume=e.number_at(6, "Volume"),
        CdA=e.number_at(k, "CdA"), Ca=e.number_at(k + 1, "Ca"), force=force,
        where=e.number))


def _line(e, deck):
    if len(e.words) < 7:
        raise e.error("entry: needs the 7 columns ID LineType AttachA AttachB UnstrLen "
                      f"NumSegs LineOutputs, got {len(e.words)}")
    number = _next_id(e, deck.lines)
    if e.words[1] not in deck.line_types:
        raise e.error(f"LineType: {e.words[1]!r} is not in LINE TYPES "
                      f"({', '.join(deck.line_types) or 'none'})")
    ends = []
    for column, word in (("AttachA", e.words[2]), ("AttachB", e.words[3])):
        ends.append(_attachment(e, deck, column, word))
    length = e.number_at(4, "UnstrLen")
    segments = e.integer_at(5, "NumSegs")
    if length <= 0:
        raise e.error(f"UnstrLen: must be positive, got {length:g}")
    if segments < 1:
        raise e.error(f"NumSegs: must be >= 1, got {segments}")
    if segments > MAX_ELEMENTS_PER_LINE:
        raise e.error(f"NumSegs: must be at most {MAX_ELEMENTS_PER_LINE} per line (the "
                      f"model's matrices and recorded time series would not fit in memory), "
                      f"got {segments}")
    deck.lines.append(DeckLine(id=number, type=e.words[1], a=ends[0], b=ends[1],
                               length=length, n_segments=segments, outputs=e.words[6],
                               where=e.number))


def _attachment(e, deck, column, word):
    """A point number, or a rod end 'R<N>A' / 'R<N>B', as a LINES or FAILURE entry
    names it."""
    letters, point, rest = _decompose(word)
    if letters in ("R", "ROD"):
        if point is None or rest.upper() not in ("A", "B"):
            raise e.error(f"{column}: {word!r} is not a rod end R<N>A or R<N>B")
        if not 1 <= point <= len(deck.rods):
            raise e.error(f"{column}: rod {point} is not in RODS ({len(deck.rods)} rods)")
        return f"R{point}{rest.upper()}"
    if letters not in ("", "C", "CON", "P", "POINT") or point is None:
        raise e.error(f"{column}: {word!r} is not a point number")
    if not 1 <= point <= len(deck.points):
        raise e.error(f"{column}: point {point} is not in POINTS ({len(deck.points)} points)")
    return point


def _failure(e, deck):
    if len(e.words) < 5:
        raise e.error("entry: needs the 5 columns FailureID Point Line(s) FailTime FailTen, "
                      f"got {len(e.words)}")
    point = _attachment(e, deck, "Point", e.words[1])
    lines = []
    for word in e.words[2].split(","):
        if not re.fullmatch(r"\d+", word) or not 1 <= int(word) <= len(deck.lines):
            raise e.error(f"Line(s): {word!r} is not a line number of LINES "
                          f"({len(deck.lines)} lines)")
        lines.append(int(word))
    time, tension = e.number_at(3, "FailTime"), e.number_at(4, "FailTen")
    for name, value in (("FailTime", time), ("FailTen", tension)):
        if value < 0:
            raise e.error(f"{name}: must be >= 0 (0: no such trigger), got {value:g}")
    if time == 0 and tension == 0:
        raise e.error("FailTime, FailTen: both 0, the failure never happens")
    deck.failures.append(DeckFailure(id=len(deck.failures) + 1, point=point,
                                     lines=tuple(lines), time=time, tension=tension,
                                     where=e.number))


def _option(e, deck):
    if len(e.words) < 2:
        deck.notes.append(f"line {e.number}: option line without a name ignored")
        return
    value, written = e.words[0], e.words[1]
    name = OPTION_NAMES.get(written.lower())
    if name is None:
        name = written
        deck.notes.append(f"line {e.number}: unknown option {written!r} kept, not used")
    elif name in F_ONLY:
        deck.notes.append(f"line {e.number}: option {written!r} is MoorDyn-F only "
                          "(MoorDyn-C ignores it)")
    if name in deck.options:  # MoorDyn reads on: the later value wins
        warnings.warn(f"{e.source} line {e.number}: {e.section} {written}: given twice "
                      f"(line {deck.option_lines[name]}: {deck.options[name]}, and here: "
                      f"{value}); the later value is used, as MoorDyn uses it",
                      stacklevel=user_stacklevel())
    deck.options[name] = value
    deck.option_lines[name] = e.number


# ------------------------------------------------------------------------ writing

def _num(value) -> str:
    """Shortest text that reads back as the same float."""
    return repr(float(value))


def _bar(values) -> str:
    return "|".join(_num(v) for v in values)


def write_deck(deck: Deck, path) -> Path:
    """Write ``deck`` as a MoorDyn v2 input file (MoorDyn-C 2.x reads it); returns the path.
    A line type's EA curve is written beside it, in its file (``EA_file``, or
    ``NAME_EA.txt``)."""
    path = Path(path)
    for lt in deck.line_types.values():
        if lt.syrope:
            raise ValueError(f"write_deck: line type {lt.name}: writing Syrope line types is "
                             "not supported")
        if lt.EA_curve:
            lt.EA_file = lt.EA_file or f"{lt.name}_EA.txt"
            curve = path.parent / lt.EA_file
            curve.parent.mkdir(parents=True, exist_ok=True)
            rows = [f"{_num(e)} {_num(T)}" for e, T in zip(*lt.EA_curve)]
            curve.write_text("\n".join([f"tension-strain curve of line type {lt.name}",
                                        "Strain Tension", "(-) (N)"] + rows) + "\n",
                             encoding="utf-8")
    rule = lambda name: f"{'-' * 22} {name} {'-' * max(4, 50 - len(name))}"  # noqa: E731
    out = [rule("MoorDyn Input File")] + list(deck.title)
    out += [rule("LINE TYPES"),
            "TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx",
            "(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)"]
    for lt in deck.line_types.values():
        EA = "|".join([lt.EA_file or _num(lt.EA)] + [_num(v) for v in lt.EA_visco])
        BA = _num(lt.BA) + ("" if lt.BA_dynamic is None else "|" + _num(lt.BA_dynamic))
        out.append(" ".join([lt.name, _num(lt.diameter), _num(lt.mass), EA, BA] + [
            _num(v) for v in (lt.EI, lt.Cd, lt.Ca, lt.CdAx, lt.CaAx) + tuple(lt.viv)]))
    if deck.rod_types:
        out += [rule("ROD TYPES"), "TypeName Diam Mass/m Cd Ca CdEnd CaEnd",
                "(name) (m) (kg/m) (-) (-) (-) (-)"]
        for rt in deck.rod_types.values():
            out.append(" ".join([rt.name] + [_num(v) for v in (
                rt.diameter, rt.mass, rt.Cd, rt.Ca, rt.CdEnd, rt.CaEnd)]))
    if deck.bodies:
        out += [rule("BODIES"),
                "ID Attachment X0 Y0 Z0 r0 p0 y0 Mass CG* I* Volume CdA* Ca*",
                "(#) (word) (m) (m) (m) (deg) (deg) (deg) (kg) (m) (kg-m^2) (m^3) (m^2) (-)"]
        for b in deck.bodies:
            out.append(" ".join([str(b.id), b.attachment] + [_num(v) for v in b.r6]
                                + [_num(b.mass), _bar(b.cg), _bar(b.inertia),
                                   _num(b.volume), _bar(b.CdA), _bar(b.Ca)]))
    if deck.rods:
        out += [rule("RODS"), "ID RodType Attachment Xa Ya Za Xb Yb Zb NumSegs RodOutputs",
                "(#) (name) (word) (m) (m) (m) (m) (m) (m) (-) (-)"]
        for r in deck.rods:
            out.append(" ".join([str(r.id), r.type, r.attachment]
                                + [_num(v) for v in r.a + r.b]
                                + [str(r.n_segments), r.outputs]))
    out += [rule("POINTS")]
    with_force = any(p.force is not None for p in deck.points)
    out += ["ID Attachment X Y Z Mass Volume " + ("FX FY FZ " if with_force else "")
            + "CdA Ca",
            "(#) (word) (m) (m) (m) (kg) (m^3) " + ("(N) (N) (N) " if with_force else "")
            + "(m^2) (-)"]
    for p in deck.points:
        force = [] if not with_force else [_num(f) for f in (p.force or (0.0, 0.0, 0.0))]
        out.append(" ".join([str(p.id), p.attachment] + [_num(v) for v in p.position]
                            + [_num(p.mass), _num(p.volume)] + force
                            + [_num(p.CdA), _num(p.Ca)]))
    out += [rule("LINES"),
            "ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs",
            "(#) (name) (#) (#) (m) (-) (-)"]
    for line in deck.lines:
        out.append(f"{line.id} {line.type} {line.a} {line.b} {_num(line.length)} "
                   f"{line.n_segments} {line.outputs}")
    if deck.failures:
        out += [rule("FAILURE"), "FailureID Point Line(s) FailTime FailTen",
                "() () (,) (s) (N)"]
        out += [f"{f.id} {f.point} {','.join(map(str, f.lines))} {_num(f.time)} "
                f"{_num(f.tension)}" for f in deck.failures]
    out += [rule("OPTIONS")]
    out += [f"{value} {name}" for name, value in deck.options.items()]
    if deck.outputs:
        out += [rule("OUTPUTS")] + list(deck.outputs)
    out += [rule("END")]
    path.write_text("\n".join(out) + "\n", encoding="utf-8")
    return path


def is_deck(path) -> bool:
    """True for a MoorDyn deck: a .dat / .txt file, or text with a '---' LINE TYPES line."""
    path = Path(path)
    if path.suffix.lower() in (".dat", ".txt"):
        return True
    try:
        head = path.read_text(encoding="utf-8", errors="replace")[:20000]
    except OSError:
        return False
    return any(_section_of(line) == "LINE TYPES" for line in head.splitlines())
