"""MoorDyn's own deck set through skmoor and MoorDyn side by side: docs/moordyn_decks.md.

Every MoorDyn input deck under ``tests/Mooring/``, ``bench/Mooring/`` and ``example/`` of
MoorDyn's repository (FloatingArrayDesign/MoorDyn) is read at run time from a local git
mirror; nothing of MoorDyn's is copied into this project. A deck is a text file with a
'---' line naming a MoorDyn section (LINE TYPES / LINE DICTIONARY, ROD TYPES, BODIES,
POINTS, LINES); deck text inside scripts and notebooks is listed, not run; a deck whose
line dictionary has MoorDyn v1's 9 columns is marked 'v1 format' (none at the mirrored
commit). Each deck, the files of its folder (MoorDyn finds wave, current and state files
there) and the files its words name (curves, Syrope settings, a seafloor file named from
the folder MoorDyn's tests run in) are extracted into a temporary folder and run:

- MoorDyn (the ``moordyn`` package), in a subprocess per deck with a time limit, from
  the folder MoorDyn's own tests run it in: ``Create``; ``Init`` with the coupled DOFs at
  the deck's positions and zero velocity (``coupled_state``; MoorDyn's IC solve, with
  TmaxIC raised to FORCED_TMAX_IC when the deck sets it below SHORT_TMAX_IC); per line
  the end-B force ``|GetLineNodeForce(line, N)|`` (the line's pull on its end point:
  last segment's tension plus the end node's half-segment weight and contact, which is
  what skmoor's ``fairlead_tension`` measures), ``GetLineFairTen`` (the last segment's
  tension alone) and the same at end A; the IC residual MoorDyn logs, which says whether
  the state is static (SETTLED). Templates are filled (TEMPLATES) and decks that start
  from another deck's saved state get it made first (PREREQUISITES), as MoorDyn's tests do.
- skmoor, in this process one deck after the other (``--isolate``: subprocesses), from
  the same folder as MoorDyn (a SeafloorFile path is relative to it), with a time limit: ``model = skmoor.build(deck)``, ``eq = skmoor.equilibrium(model)``,
  ``st = skmoor.static_results(model, eq)``; per line (``st.line_names``, 'line<k>' for
  MoorDyn line k) the end-B tension ``st.fairlead_tension[0]`` and end-A
  ``st.anchor_tension[0]``. A ValueError is a refusal, which must name the deck file,
  the deck line ('<file> line N') and the missing feature (``refusal_problem``); any
  other exception is an error row (a bug).

Each deck also gets a census of the features it uses, from its text alone (``census``:
free points, point masses, free / coupled / pinned bodies, rods, line ends on rods,
EI > 0, EA / BA / EI curve files, viscoelastic '|' EA, Syrope, WaveKin / Currents /
SeafloorFile / fileIC options, bottom friction, VIV Cl, FAILURE / CONTROL / EXTERNAL
LOADS / SYROPE IC sections).

Run: ``python benchmarks/moordyn_decks.py [--mirror PATH] [--out docs/moordyn_decks.md]
[--only NAME] [--jobs N] [--moordyn-timeout S] [--skmoor-timeout S] [--side both|moordyn|
skmoor] [--isolate] [--json FILE]`` (2-4 min on 2 cores, nearly all of it MoorDyn's IC
solves). The mirror defaults to $SKMOOR_MOORDYN_MIRROR or
/work/.mirror/FloatingArrayDesign+MoorDyn/repo; --only keeps the decks whose path
contains NAME and prints the report instead of writing it (unless --out is given).
"""
from __future__ import annotations

import argparse
import concurrent.futures
import importlib.metadata
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_MIRROR = Path("/work/.mirror/FloatingArrayDesign+MoorDyn/repo")
MIRROR_ENV = "SKMOOR_MOORDYN_MIRROR"
UPSTREAM = "FloatingArrayDesign/MoorDyn"
FOLDERS = ("tests/Mooring", "bench/Mooring", "example")
DEFAULT_OUT = ROOT / "docs" / "moordyn_decks.md"
MOORDYN_TIMEOUT = 300.0  # s per deck (MoorDyn's IC solve; the longest measured: ~30 s)
SKMOOR_TIMEOUT = 180.0  # s per deck (build + equilibrium + static results)
TOLERANCE = 0.02  # relative, static end-B tension skmoor vs MoorDyn
FLOOR = 0.01  # of the deck's largest line-end tension: the difference's smallest divisor
SETTLED = 0.1  # m/s2: MoorDyn's IC residual (mean acceleration per state) of a static state
FORCED_TMAX_IC = 60.0  # s: MoorDyn's IC time for decks that set TmaxIC < 1 s (see below)
SHORT_TMAX_IC = 1.0  # s
SOURCE_SUFFIXES = {".py", ".ipynb", ".md", ".cpp", ".c", ".h", ".hpp", ".f90", ".m",
                   ".rs", ".png", ".jpg", ".csv", ".fst", ".dvr"}
MAX_DECK_BYTES = 1_000_000
MOORDYN_DEFAULT_TMAX_IC = 120.0  # s (MoorDyn2.cpp)

# ------------------------------------------------------------------ the mirror


class MirrorMissing(RuntimeError):
    pass


class Mirror:
    """A bare git mirror of MoorDyn's repository, read at HEAD."""

    def __init__(self, path):
        self.path = Path(path)
        if not self.path.exists():
            raise MirrorMissing(
                f"MoorDyn's repository is not at {self.path}: mirror {UPSTREAM} there "
                f"(e.g. git clone --mirror https://github.com/{UPSTREAM} {self.path}), or "
                f"give --mirror PATH (or set ${MIRROR_ENV})")
        try:
            self.commit = self._git("rev-parse", "HEAD").decode().strip()
        except (subprocess.CalledProcessError, OSError) as err:
            raise MirrorMissing(f"{self.path} is not a git repository with a HEAD "
                                f"({err})") from None
        self._sizes = None

    def _git(self, *args) -> bytes:
        return subprocess.run(["git", "-C", str(self.path), *args], check=True,
                              capture_output=True).stdout

    def sizes(self) -> dict:
        """path -> size (bytes) of every file under FOLDERS at HEAD."""
        if self._sizes is None:
            out = self._git("ls-tree", "-r", "-l", "-z", "HEAD", "--", *FOLDERS)
            self._sizes = {}
            for item in out.split(b"\0"):
                if not item:
                    continue
                meta, name = item.split(b"\t", 1)
                kind, size = meta.split()[1], meta.split()[3]
                if kind == b"blob":  # size 'BAD': the blob is absent from the mirror
                    self._sizes[name.decode()] = int(size) if size.isdigit() else None
        return self._sizes

    def absent(self) -> list:
        """Files listed at HEAD whose content the mirror does not hold."""
        return sorted(p for p, size in self.sizes().items() if size is None)

    def read(self, path: str) -> bytes:
        return self._git("cat-file", "blob", f"HEAD:{path}")


def mirror_path(given=None) -> Path:
    return Path(given or os.environ.get(MIRROR_ENV) or DEFAULT_MIRROR)


# ------------------------------------------------------------------ deck text

# '---' header keyword (upper case) -> section (MoorDyn2.cpp's names)
SECTIONS = [
    ("LINE DICTIONARY", "LINE TYPES"), ("LINE TYPES", "LINE TYPES"),
    ("ROD DICTIONARY", "ROD TYPES"), ("ROD TYPES", "ROD TYPES"),
    ("BODIES", "BODIES"), ("BODY LIST", "BODIES"), ("BODY PROPERTIES", "BODIES"),
    ("ROD LIST", "RODS"), ("ROD PROPERTIES", "RODS"), ("RODS", "RODS"),
    ("POINT LIST", "POINTS"), ("POINT PROPERTIES", "POINTS"),
    ("CONNECTION PROPERTIES", "POINTS"), ("NODE PROPERTIES", "POINTS"),
    ("POINTS", "POINTS"),
    ("LINE LIST", "LINES"), ("LINE PROPERTIES", "LINES"), ("LINES", "LINES"),
    ("SOLVER OPTIONS", "OPTIONS"), ("OPTIONS", "OPTIONS"),
    ("OUTPUTS", "OUTPUTS"), ("OUTPUT", "OUTPUTS"),
    ("FAILURE", "FAILURE"), ("CONTROL", "CONTROL"), ("EXTERNAL LOADS", "EXTERNAL LOADS"),
    ("SYROPE IC", "SYROPE IC"),
]
TABLES = {"LINE TYPES", "ROD TYPES", "BODIES", "RODS", "POINTS", "LINES", "FAILURE",
          "CONTROL", "EXTERNAL LOADS", "SYROPE IC"}
STRUCTURE = {"LINE TYPES", "ROD TYPES", "BODIES", "RODS", "POINTS", "LINES"}


def section_of(text: str):
    """Section of a header line ('---' and a known name), '' for another '---' line,
    None for an ordinary line."""
    if "---" not in text:
        return None
    name = " ".join(text.replace("-", " ").upper().split())
    for word, section in SECTIONS:
        if re.search(rf"(^|\s){word}($|\s)", name):
            return section
    return ""


@dataclass
class Row:
    words: list
    number: int  # deck line, 1-based


@dataclass
class DeckText:
    """A deck's sections as rows of words (MoorDyn's reading: two header lines skipped
    in table sections)."""

    sections: dict = field(default_factory=dict)
    headers: dict = field(default_factory=dict)  # section -> deck line of its header

    def rows(self, section):
        return self.sections.get(section, [])


def parse_deck_text(text: str) -> DeckText:
    deck, section, skip = DeckText(), None, 0
    for number, raw in enumerate(text.splitlines(), start=1):
        header = section_of(raw)
        if header is not None:
            section = header or None
            skip = 2 if header in TABLES else 0
            if header:
                deck.headers.setdefault(header, number)
                deck.sections.setdefault(header, [])
            continue
        if section is None:
            continue
        if skip:
            skip -= 1
            continue
        words = raw.split()
        if words:
            deck.sections[section].append(Row(words, number))
    return deck


def deck_format(text: str):
    """'v2', 'v1' (MoorDyn v1: 9-column line dictionary), or None (no deck)."""
    deck = parse_deck_text(text)
    if not STRUCTURE & set(deck.headers):
        return None
    if any(len(r.words) == 9 for r in deck.rows("LINE TYPES")):
        return "v1"
    return "v2"


def _number(word):
    try:
        return float(word)
    except ValueError:
        return None


def _kind(word):
    """MoorDyn's decomposition of an attachment word: (LETTERS, number, LETTERS)."""
    m = re.fullmatch(r"([A-Za-z_]*)(\d*)([A-Za-z]*)", word)
    if not m:
        return word.upper(), None, ""
    return m.group(1).upper(), int(m.group(2)) if m.group(2) else None, m.group(3).upper()


FIXED = {"ANCHOR", "FIXED", "FIX"}
COUPLED = {"VESSEL", "VES", "COUPLED", "CPLD"}
PINNED = {"VESSELPINNED", "VESPIN", "CPLDPIN", "COUPLEDPINNED"}
FREE = {"POINT", "CONNECT", "CON", "FREE"}


def body_kind(word):
    letters = _kind(word)[0]
    if letters in FIXED:
        return "fixed"
    if letters in COUPLED:
        return "coupled"
    if letters in PINNED:
        return "pinned"
    return "free"


def point_kind(word):
    letters = _kind(word)[0]
    if letters == "BODY":
        return "body"
    if letters in FIXED:
        return "fixed"
    if letters in COUPLED:
        return "coupled"
    if letters in FREE:
        return "free"
    return letters.lower() or "?"


def rod_kind(word):
    letters, _, rest = _kind(word)
    if letters == "BODY":
        return "body-pinned" if rest in ("PINNED", "PIN") else "body"
    if letters in FIXED:
        return "fixed"
    if letters in ("PINNED", "PIN"):
        return "pinned"
    if letters in COUPLED:
        return "coupled"
    if letters in PINNED:
        return "coupled-pinned"
    if letters in FREE:
        return "free"
    return letters.lower() or "?"


def census(text: str) -> dict:
    """Counts and the features a deck uses, from its text alone.

    Returns dict(lines, points, bodies, rods, features=[short tags]) where the tags name
    what a plain 'anchor to coupled fairlead' cable model lacks."""
    deck = parse_deck_text(text)
    feats = []

    def add(tag, count=1):
        if count:
            feats.append(tag if count == 1 else f"{tag} x{count}")

    points = deck.rows("POINTS")
    bodies = deck.rows("BODIES")
    rods = deck.rows("RODS")
    lines = deck.rows("LINES")
    kinds = [point_kind(r.words[1]) for r in points if len(r.words) > 1]
    free = [r for r in points if len(r.words) > 1 and point_kind(r.words[1]) == "free"]
    add("free point", len(free))
    lumped = sum(1 for r in points if len(r.words) >= 7
                 and ((_number(r.words[5]) or 0) != 0 or (_number(r.words[6]) or 0) != 0))
    add("point mass/volume", lumped)
    add("point force", sum(1 for r in points if len(r.words) >= 12))
    add("body point", kinds.count("body"))
    bkinds = [body_kind(r.words[1]) for r in bodies if len(r.words) > 1]
    for kind in ("free", "coupled", "pinned", "fixed"):
        add(f"{kind} body", bkinds.count(kind))
    rkinds = [rod_kind(r.words[2]) for r in rods if len(r.words) > 2]
    for kind in sorted(set(rkinds)):
        add(f"{kind} rod", rkinds.count(kind))
    rod_ends = sum(1 for r in lines for w in r.words[2:4] if _kind(w)[0] in ("R", "ROD"))
    add("line end on rod", rod_ends)
    for r in deck.rows("LINE TYPES"):
        w = r.words
        if len(w) < 10:
            continue
        name = w[0]
        ea, ba, ei = w[3], w[4], w[5]
        if ea.upper().startswith("SYROPE:"):
            add(f"Syrope EA ({name})")
        elif "|" in ea:
            add(f"visco EA '|' ({name})")
        elif _number(ea) is None:
            add(f"EA curve file ({name})")
        if "|" in ba:
            add(f"BA '|' ({name})")
        elif _number(ba) is None:
            add(f"BA curve file ({name})")
        if _number(ei) is None:
            add(f"EI curve file ({name})")
        elif _number(ei) > 0:
            add(f"EI>0 ({name})")
        if len(w) in (11, 13) and (_number(w[10]) or 0) > 0:
            add(f"VIV Cl={w[10]} ({name})")
    if deck.rows("ROD TYPES") and not rods:
        add("rod types")
    options = {}
    for r in deck.rows("OPTIONS"):
        if len(r.words) >= 2:
            options[r.words[1].lower()] = r.words[0]
    for name, tag in (("wavekin", "WaveKin"), ("currents", "Currents")):
        value = options.get(name)
        if value is not None and _number(value) not in (0.0, None):
            add(f"{tag}={value}")
    for name, tag in (("seafloorfile", "SeafloorFile"), ("waterkin", "WaterKin"),
                      ("fileic", "fileIC"), ("icfile", "fileIC")):
        if name in options:
            add(tag)
    mu = options.get("frictioncoefficient") or options.get("mu_kt") or options.get("mu_ka")
    if mu is not None and (_number(mu) or 0) > 0:
        add("bottom friction")
    for section in ("FAILURE", "CONTROL", "EXTERNAL LOADS", "SYROPE IC"):
        if deck.rows(section):
            add(f"{section} section")
    if not lines:
        add("no lines")
    return dict(lines=len(lines), points=len(points), bodies=len(bodies), rods=len(rods),
                features=feats, tmax_ic=_number(options.get("tmaxic", "") or "") or
                _number(options.get("ictmax", "") or ""))


def coupled_state(text: str) -> list:
    """MoorDyn's coupled-DOF vector at the deck's positions: coupled bodies (x, y, z and
    roll, pitch, yaw in rad; the same 6 for a pinned body, of which MoorDyn reads x, y,
    z), coupled-pinned rods (end A),
    then coupled points (x, y, z), MoorDyn's order (MoorDyn::Init)."""
    deck = parse_deck_text(text)
    x = []
    for r in deck.rows("BODIES"):
        kind = body_kind(r.words[1])
        if kind == "coupled":
            x += [float(v) for v in r.words[2:5]]
            x += [math.radians(float(v)) for v in r.words[5:8]]
        elif kind == "pinned":
            # MoorDyn's NCoupledDOF counts 6 for a pinned body (its Init reads the first
            # 3); MoorDyn's own test (tests/bodies.cpp, "Pinned body") passes 6
            x += [float(v) for v in r.words[2:5]]
            x += [math.radians(float(v)) for v in r.words[5:8]]
    for r in deck.rows("RODS"):
        kind = rod_kind(r.words[2])
        if kind == "coupled":
            # MoorDyn's coupled rod state is end A and Euler angles of the rod's frame;
            # no deck of the set has one, so the harness does not guess them
            raise NotImplementedError(f"deck line {r.number}: a coupled (cantilevered) "
                                      "rod: the harness builds no coupled state for it")
        elif kind == "coupled-pinned":
            x += [float(v) for v in r.words[3:6]]
    for r in deck.rows("POINTS"):
        if point_kind(r.words[1]) == "coupled":
            x += [float(v) for v in r.words[2:5]]
    return x


# ------------------------------------------------------------------ finding decks


@dataclass
class DeckFile:
    path: str  # in MoorDyn's repository
    format: str  # 'v2' or 'v1'
    text: str
    census: dict


def find_decks(mirror: Mirror):
    """(decks, skipped): the MoorDyn input decks under FOLDERS, and the files holding
    deck text that are not decks (scripts, notebooks: path -> why)."""
    decks, skipped = [], {}
    for path, size in sorted(mirror.sizes().items()):
        if size is None or size > MAX_DECK_BYTES:
            continue
        data = mirror.read(path)
        if b"\0" in data:
            continue  # binary (MoorDyn's saved initial states *.ic)
        text = data.decode("utf-8", errors="replace")
        fmt = deck_format(text)
        if fmt is None:
            continue
        suffix = PurePosixPath(path).suffix.lower()
        if suffix in SOURCE_SUFFIXES:
            skipped[path] = ("deck text inside a script / notebook "
                             f"({suffix}), not an input file")
            continue
        if path in TEMPLATES:
            text = deck_text(mirror, path)
        decks.append(DeckFile(path, fmt, text, census(text)))
        if path in TEMPLATES:
            filled = ", ".join(f"{k} = {v}" for k, v in TEMPLATES[path].items())
            decks[-1].census["features"].insert(0, f"template ({filled})")
    return decks, skipped


def run_folder(path: str) -> str:
    """The folder MoorDyn's own tests run a deck from: the parent of its 'Mooring'
    folder (tests/, bench/; some decks name files from there, e.g.
    'Mooring/3D_seafloor/seafloor_profile_3d.txt'), else the deck's folder."""
    parts = PurePosixPath(path).parts
    if "Mooring" in parts:
        return str(PurePosixPath(*parts[:parts.index("Mooring")]))
    return str(PurePosixPath(path).parent)


# Decks whose initial state file (fileIC) MoorDyn's own tests make first by running
# other decks and saving their state there (tests/test_complex_ic.py).
PREREQUISITES = {
    "tests/Mooring/riser/riser_ic2.txt": ["tests/Mooring/riser/riser_ic1.txt"],
    "tests/Mooring/riser/riser.txt": ["tests/Mooring/riser/riser_ic1.txt",
                                      "tests/Mooring/riser/riser_ic2.txt"],
}


# Decks with no static state in MoorDyn either, with what was measured in MoorDyn 2.7.2
# (a run of the deck as its own test runs it): listed in the notes.
NOT_STATIC = {
    "tests/Mooring/tripod.txt": "sets TmaxIC = 0, so MoorDyn runs it from the deck's "
    "positions without an IC solve (tests/tripod.cpp only steps it); those positions are "
    "no equilibrium: in MoorDyn its free points move 3-5 m in the first 0.5 s, the "
    "buoyant float (line 1) then heaves between 0.6 and 5 m deep for more than 14 s, and "
    "the forced 60 s IC stops at its first check with 246 m/s2 left. skmoor's statics, "
    "started from the same positions, finds no equilibrium either; skmoor.simulate runs "
    "it as MoorDyn does (start='reference', the deck's TmaxIC = 0), and over its first "
    "0.1 s the chain junctions track MoorDyn's within 1.3-4.3 % rms of their range on "
    "twice the deck's segments (tests/coupling/test_tripod_moordyn.py, docs/bending.md)",
}


# Decks that are templates MoorDyn's own tests fill in before running them: the values
# of their first case (tests/time_schemes.cpp: schemes[0], dts[0]).
TEMPLATES = {
    "tests/Mooring/time_schemes.txt": {"@TSCHEME@": "Euler", "@DT@": "1.5E-4"},
}


def deck_text(mirror: Mirror, path: str) -> str:
    """The deck as run: its text, a template's placeholders filled (TEMPLATES)."""
    text = mirror.read(path).decode("utf-8", errors="replace")
    for key, value in TEMPLATES.get(path, {}).items():
        text = text.replace(key, value)
    return text


def extract(mirror: Mirror, deck: DeckFile, dest: Path) -> Path:
    """Write the deck, the files of its folder and the files its words name (curve,
    Syrope, seafloor files, from the deck's folder or the folder MoorDyn's tests run it
    from; recursively through text files) under ``dest``, at their repository paths;
    returns the deck's local path."""
    sizes = {p: s for p, s in mirror.sizes().items() if s is not None}
    folder = PurePosixPath(deck.path).parent
    wanted = {p for p in sizes if PurePosixPath(p).parent == folder}
    wanted |= set(PREREQUISITES.get(deck.path, []))
    todo, seen = [deck.path], set()
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen.add(path)
        wanted.add(path)
        data = mirror.read(path)
        if b"\0" in data or len(data) > MAX_DECK_BYTES:
            continue
        bases = (PurePosixPath(path).parent, PurePosixPath(run_folder(deck.path)))
        for word in re.split(r"[\s|]+", data.decode("utf-8", errors="replace")):
            if word.upper().startswith("SYROPE:"):
                word = word[7:]
            if not word or not re.search(r"[A-Za-z]", word) or "/" not in word and \
                    "." not in word:
                continue
            for base in bases:
                candidate = os.path.normpath(str(base / word)).replace(os.sep, "/")
                if candidate in sizes and candidate not in seen:
                    todo.append(candidate)
    for path in wanted:
        target = dest / path
        target.parent.mkdir(parents=True, exist_ok=True)
        if path in TEMPLATES:
            target.write_text(deck_text(mirror, path), encoding="utf-8")
        else:
            target.write_bytes(mirror.read(path))
    return dest / deck.path


# ------------------------------------------------------------------ workers


def option_value(text: str, *names):
    """The value written for the first of the options ``names`` (lower case), or None."""
    for r in parse_deck_text(text).rows("OPTIONS"):
        if len(r.words) >= 2 and r.words[1].lower() in names:
            return r.words[0]
    return None


def moordyn_init(deck: Path):
    """(system, coupled state, wall s) of MoorDyn after Create and Init (its IC solve)
    with the coupled DOFs at the deck's positions; raises RuntimeError on a failure."""
    import moordyn

    text = deck.read_text(encoding="utf-8", errors="replace")
    started = time.perf_counter()
    system = moordyn.Create(str(deck))
    if system is None:
        raise RuntimeError("moordyn.Create returned None")
    n_dof = moordyn.NCoupledDOF(system)
    x = coupled_state(text)
    if len(x) != n_dof:
        raise RuntimeError(f"harness: built {len(x)} coupled DOFs from the deck, MoorDyn "
                           f"expects {n_dof}")
    rc = moordyn.Init(system, x, [0.0] * n_dof)
    if rc != 0:
        moordyn.Close(system)
        raise RuntimeError(f"moordyn.Init returned error code {rc}")
    return system, x, time.perf_counter() - started


def with_ic_solve(deck: Path):
    """(deck to run, TmaxIC it was given or None). A deck with TmaxIC = 0 skips MoorDyn's
    initial-condition solve, and MoorDyn's Init then computes no line forces at all (all
    tensions read 0); one with a token TmaxIC (lifting.txt: 1 ms) starts its dynamics
    from MoorDyn's catenary guess. Neither is a static state: a deck with TmaxIC <
    SHORT_TMAX_IC is run from a copy beside it with TmaxIC = FORCED_TMAX_IC (MoorDyn
    stops its IC solve earlier when its own criterion, threshIC, is met), everything
    else as written."""
    text = deck.read_text(encoding="utf-8", errors="replace")
    lines = text.splitlines(keepends=True)
    for r in parse_deck_text(text).rows("OPTIONS"):
        if len(r.words) >= 2 and r.words[1].lower() in ("tmaxic", "ictmax") \
                and (_number(r.words[0]) or 0) < SHORT_TMAX_IC:
            raw = lines[r.number - 1]
            lines[r.number - 1] = raw.replace(r.words[0], f"{FORCED_TMAX_IC:g}", 1)
            copy = deck.with_name(f"{deck.stem}_ic{deck.suffix}")
            copy.write_text("".join(lines), encoding="utf-8")
            return copy, FORCED_TMAX_IC
    return deck, None


def moordyn_worker(deck: Path, prerequisites=()) -> dict:
    """MoorDyn's statics of a deck (in this process: run it in a subprocess). The
    ``prerequisites`` (decks) are run first, each saving its state into the deck's
    fileIC, as MoorDyn's own tests do."""
    import moordyn

    text = deck.read_text(encoding="utf-8", errors="replace")
    deck, forced = with_ic_solve(deck)
    wall = 0.0
    for pre in prerequisites:
        state = option_value(text, "fileic", "icfile")
        system, _, seconds = moordyn_init(Path(pre))
        moordyn.SaveState(system, str(deck.parent / state))
        moordyn.Close(system)
        wall += seconds
    try:
        system, x, seconds = moordyn_init(deck)
    except RuntimeError as err:
        return dict(status="error", type="RuntimeError", message=str(err))
    wall += seconds
    n_dof = len(x)
    out = dict(status="runs", wall=wall, n_coupled_dof=n_dof, coupled_state=x,
               forced_tmax_ic=forced,
               tmax_ic=forced or _number(option_value(text, "tmaxic", "ictmax") or "")
               or MOORDYN_DEFAULT_TMAX_IC,
               end_b_force=[], end_b_segment=[], end_a_force=[], end_a_segment=[],
               n_segments=[])
    for k in range(1, moordyn.GetNumberLines(system) + 1):
        line = moordyn.GetLine(system, k)
        n = moordyn.GetLineN(line)
        out["n_segments"].append(n)
        out["end_b_force"].append(_norm(moordyn.GetLineNodeForce(line, n)))
        out["end_b_segment"].append(float(moordyn.GetLineFairTen(line)))
        out["end_a_force"].append(_norm(moordyn.GetLineNodeForce(line, 0)))
        out["end_a_segment"].append(_norm(moordyn.GetLineNodeTen(line, 0)))
    out["counts"] = dict(lines=moordyn.GetNumberLines(system),
                         points=moordyn.GetNumberPoints(system),
                         bodies=moordyn.GetNumberBodies(system),
                         rods=moordyn.GetNumberRods(system))
    moordyn.Close(system)
    return out


def _norm(v):
    return float(math.sqrt(sum(float(c) ** 2 for c in v)))


def skmoor_worker(deck: Path) -> dict:
    """skmoor's statics of a deck: end-B / end-A tension per deck line (N)."""
    started = time.perf_counter()
    try:
        import skmoor
        from skmoor.io.sea_files import deck_bathymetry, still_water

        parsed, sea = skmoor.read_deck(deck), None  # None: the deck's own water
        if parsed.option("Currents", 0):  # still water, as MoorDyn's IC solve has it
            sea = still_water(parsed, deck_bathymetry(parsed))
        model = skmoor.build(deck, sea=sea)
        eq = skmoor.equilibrium(model)
        st = skmoor.static_results(model, eq)
        names = list(st.line_names)
        end_b = [float(v) for v in st.fairlead_tension[0]]
        end_a = [float(v) for v in st.anchor_tension[0]]
    except ValueError as err:
        return dict(status="refused", type=type(err).__name__, message=str(err),
                    wall=time.perf_counter() - started)
    except skmoor.ConvergenceError as err:  # the deck's statics: no equilibrium, and why
        return dict(status="no equilibrium", type=type(err).__name__, message=str(err),
                    wall=time.perf_counter() - started)
    except Exception as err:  # noqa: BLE001 -- reported as an error row
        return dict(status="error", type=type(err).__name__, message=str(err),
                    traceback=traceback.format_exc(limit=-4),
                    wall=time.perf_counter() - started)
    return dict(status="runs", line_names=names, end_b=end_b, end_a=end_a,
                wall=time.perf_counter() - started)


def _worker_main(args):
    """The subprocess side: run one side on one deck, write the JSON result."""
    deck = Path(args.deck)
    os.chdir(args.cwd or deck.parent)
    try:
        if args.worker == "moordyn":
            result = moordyn_worker(deck, args.pre or ())
        else:
            result = skmoor_worker(deck)
    except Exception as err:  # noqa: BLE001
        result = dict(status="error", type=type(err).__name__, message=str(err),
                      traceback=traceback.format_exc(limit=-4))
    Path(args.result).write_text(json.dumps(result))
    return 0


def run_side(side: str, deck: Path, timeout: float, cwd=None, prerequisites=()) -> dict:
    """Run one side on one deck in a subprocess (MoorDyn can abort the interpreter, and
    either can run long), from ``cwd`` (default: the deck's folder): the worker's result
    (MoorDyn's error lines added to a failure), or an error / timeout record."""
    cwd = Path(cwd or deck.parent)
    result = deck.parent / f".{deck.name}.{side}.json"
    command = [sys.executable, str(Path(__file__).resolve()), "--worker", side,
               "--deck", str(deck), "--result", str(result), "--cwd", str(cwd)]
    for pre in prerequisites:
        command += ["--pre", str(pre)]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(ROOT)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]),
        SKMOOR_BLAS_THREADS="1", OMP_NUM_THREADS="1")
    started = time.perf_counter()
    try:
        proc = subprocess.run(command, cwd=cwd, capture_output=True, timeout=timeout, env=env,
                              check=False)
    except subprocess.TimeoutExpired:
        return dict(status="timeout", type="Timeout",
                    message=f"no result within {timeout:g} s", wall=timeout,
                    process_wall=timeout)
    wall = time.perf_counter() - started
    output = b"\n".join((proc.stdout or b"", proc.stderr or b"")).decode(
        "utf-8", errors="replace").splitlines()
    if result.exists():
        data = json.loads(result.read_text())
        data.setdefault("wall", wall)
        data["process_wall"] = wall
        if side == "moordyn" and data.get("status") == "runs":
            data.update(_moordyn_ic(output))
        if side == "moordyn" and data.get("status") != "runs":
            said = _moordyn_errors(output)
            if said:
                data["message"] = f"{data.get('message', '')}; MoorDyn says: {said}"
        if isinstance(data.get("message"), str):  # the TmaxIC copy is the deck
            data["message"] = data["message"].replace(f"{deck.stem}_ic{deck.suffix}",
                                                      deck.name)
        return data
    tail = " | ".join(line.strip() for line in output[-4:] if line.strip())
    return dict(status="error", type="Crash",
                message=f"the {side} process ended with status {proc.returncode} and no "
                        f"result: {tail}", wall=wall, process_wall=wall)


def _moordyn_ic(output) -> dict:
    """What MoorDyn's log says of its (last) IC solve: ic_time (s), ic_error (m/s2 for
    the stationary solver, % for the legacy dynamic relaxation), ic_solver,
    ic_converged (False when the legacy solver says so, None when unknown)."""
    out = dict(ic_time=None, ic_error=None, ic_solver=None, ic_converged=None)
    for line in output:
        m = re.search(r"Remaining error after (\S+) s = (\S+) (m/s2|% on line)", line)
        if m:
            out.update(ic_time=float(m.group(1)), ic_error=float(m.group(2)),
                       ic_solver="stationary" if m.group(3) == "m/s2" else "dynamic")
        if "Fairlead tensions converged" in line:
            out["ic_converged"] = True
        if "Fairlead tensions did not converge" in line:
            out["ic_converged"] = False
    return out


def _moordyn_errors(output) -> str:
    """MoorDyn's error lines (ERR ... and the lines after 'Error ...')."""
    said, keep = [], 0
    for line in output:
        text = line.strip()
        if not text:
            continue
        if text.startswith(("ERR ", "Error")):
            said.append(re.sub(r"^ERR \S+ \w+\(\): ", "", text))
            keep = 2
        elif keep:
            if text.startswith("Traceback"):
                keep = 0
                continue
            said.append(text)
            keep -= 1
    return " / ".join(dict.fromkeys(said))[:600]


# ------------------------------------------------------------------ the survey


@dataclass
class Outcome:
    """One deck: its census and both sides' results (dicts, as the workers wrote them)."""

    deck: DeckFile
    moordyn: dict
    skmoor: dict

    @property
    def name(self):
        return self.deck.path

    @property
    def skmoor_status(self) -> str:
        """'runs', 'refused' (a ValueError naming the deck, a deck line and the
        feature), 'refused badly' (a ValueError without them), 'error' (another
        exception or a timeout), 'no equilibrium' (the statics cannot exist: the message
        names the unrestrained DOFs) or 'not run'."""
        status = self.skmoor.get("status")
        if status == "refused":
            return "refused badly" if self.refusal_problem() else "refused"
        if status in ("runs", "not run", "no equilibrium"):
            return status
        return "error"

    def refusal_problem(self):
        if self.skmoor.get("status") != "refused":
            return None
        return refusal_problem(self.name, self.skmoor.get("message", ""))

    @property
    def moordyn_runs(self) -> bool:
        return self.moordyn.get("status") == "runs"

    @property
    def moordyn_settled(self) -> bool:
        """MoorDyn's IC solve ended in a static state: its stationary solver's residual
        (mean acceleration per state) at most SETTLED, or the legacy solver says its
        fairlead tensions converged."""
        md = self.moordyn
        if md.get("status") != "runs":
            return False
        if md.get("ic_solver") == "dynamic" or md.get("ic_converged") is not None:
            return bool(md.get("ic_converged"))
        return md.get("ic_error") is not None and md["ic_error"] <= SETTLED

    def comparison(self):
        """[(line number, skmoor end-B N, MoorDyn end-B force N, MoorDyn last-segment
        tension N, relative difference)] when both ran, else []. The difference's
        divisor is at least FLOOR times the deck's largest MoorDyn line-end force (a
        line's free end, e.g. at a massless point, carries no tension)."""
        md, sk = self.moordyn, self.skmoor
        if md.get("status") != "runs" or sk.get("status") != "runs":
            return []
        by_name = dict(zip(sk["line_names"], sk["end_b"]))
        scale = max([abs(v) for v in md["end_b_force"] + md["end_a_force"]] + [1.0])
        rows = []
        for k, (force, segment) in enumerate(zip(md["end_b_force"], md["end_b_segment"]),
                                             start=1):
            value = by_name.get(f"line{k}")
            if value is None:
                rows.append((k, None, force, segment, math.inf))
                continue
            rows.append((k, value, force, segment,
                         abs(value - force) / max(abs(force), FLOOR * scale)))
        return rows

    def largest_difference(self):
        """Largest relative end-B difference over the lines, None without a comparison."""
        return max((r[4] for r in self.comparison()), default=None)

    @property
    def compared(self) -> bool:
        """Both ran, MoorDyn settled, and there is at least one line."""
        return self.moordyn_settled and bool(self.comparison())


class SkmoorTimeout(Exception):
    """A deck's skmoor run went past its time limit (raised by the alarm)."""


def run_skmoor_inline(deck: Path, timeout: float, cwd=None) -> dict:
    """skmoor on one deck in this process (one import, one compilation of its kernels
    for the whole set), from ``cwd`` (default: this process's folder; a SeafloorFile
    path is relative to it, as in MoorDyn), time-limited by SIGALRM when called from the
    main thread and no other alarm is set (under pytest-timeout, that one guards the run)."""
    import signal
    import threading

    alarm = (hasattr(signal, "setitimer") and threading.current_thread() is
             threading.main_thread() and timeout and timeout > 0
             and signal.getitimer(signal.ITIMER_REAL)[0] == 0)

    def expire(signum, frame):
        raise SkmoorTimeout(f"no result within {timeout:g} s")

    started = time.perf_counter()
    here = os.getcwd()
    if alarm:
        previous = signal.signal(signal.SIGALRM, expire)
        signal.setitimer(signal.ITIMER_REAL, timeout)
    try:
        os.chdir(cwd or here)
        result = skmoor_worker(deck)
    except SkmoorTimeout as err:
        result = dict(status="timeout", type="Timeout", message=str(err))
    finally:
        os.chdir(here)
        if alarm:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)
    result["process_wall"] = time.perf_counter() - started
    return result


def survey(mirror=None, only=None, jobs=None, moordyn_timeout=MOORDYN_TIMEOUT,
           skmoor_timeout=SKMOOR_TIMEOUT, sides=("moordyn", "skmoor"), isolate=False,
           log=None, keep=None):
    """Run every deck (or those whose path contains ``only``): (outcomes, info).

    MoorDyn runs in subprocesses (``jobs`` at a time); skmoor in this process, one deck
    after the other while MoorDyn runs, unless ``isolate`` (then in subprocesses too)."""
    started = time.perf_counter()
    mirror = mirror if isinstance(mirror, Mirror) else Mirror(mirror_path(mirror))
    decks, skipped = find_decks(mirror)
    if only:
        decks = [d for d in decks if only in d.path]
    if keep:
        decks = [d for d in decks if keep(d.path)]
    have_moordyn = "moordyn" in sides and _installed("moordyn")
    jobs = jobs or os.cpu_count() or 1
    inline = "skmoor" in sides and not isolate
    tmp = Path(tempfile.mkdtemp(prefix="skmoor-moordyn-decks-"))
    results = {}

    def record(path, side, result):
        results[(path, side)] = _relative(result, tmp)
        if log:
            log(f"{side:8s} {result['status']:8s} {result.get('process_wall', 0):7.2f} s  "
                f"{path}")

    try:
        local = {}
        for k, d in enumerate(decks):
            where = tmp / f"d{k:03d}"
            local[d.path] = (extract(mirror, d, where), where / run_folder(d.path),
                             [where / p for p in PREREQUISITES.get(d.path, [])])
        work = []
        for d in decks:
            if have_moordyn:
                work.append((d.path, "moordyn", moordyn_timeout))
            if "skmoor" in sides and not inline:
                work.append((d.path, "skmoor", skmoor_timeout))
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            futures = {pool.submit(run_side, side, local[path][0], timeout, local[path][1],
                                   local[path][2] if side == "moordyn" else ()): (path, side)
                       for path, side, timeout in work}
            if inline:
                for d in decks:
                    record(d.path, "skmoor",
                           run_skmoor_inline(local[d.path][0], skmoor_timeout,
                                             local[d.path][1]))
            for future in concurrent.futures.as_completed(futures):
                record(*futures[future], future.result())
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    missing = dict(status="not run", message="moordyn is not installed"
                   if "moordyn" in sides else "not asked for")
    outcomes = [Outcome(d, results.get((d.path, "moordyn"), missing),
                        results.get((d.path, "skmoor"), dict(status="not run",
                                                              message="not asked for")))
                for d in decks]
    md_walls = [o.moordyn.get("process_wall", 0.0) for o in outcomes]
    sk_walls = [o.skmoor.get("process_wall", 0.0) for o in outcomes]
    info = dict(commit=mirror.commit, skipped=skipped, absent=mirror.absent(), jobs=jobs,
                wall=time.perf_counter() - started, moordyn_cpu=sum(md_walls),
                skmoor_cpu=sum(sk_walls), only=only, skmoor_inline=inline,
                moordyn_version=_version("moordyn"), skmoor_version=_version("skmoor"))
    return outcomes, info


def _relative(result: dict, tmp: Path) -> dict:
    """The result with the temporary folders taken out of its messages (paths then read
    as in MoorDyn's repository)."""
    pattern = re.escape(str(tmp)) + r"/d\d{3}/"
    for key in ("message", "traceback"):
        if isinstance(result.get(key), str):
            result[key] = re.sub(pattern, "", result[key])
    return result


def _installed(name):
    import importlib.util

    return importlib.util.find_spec(name) is not None


def _version(package):
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return "not installed"


# ------------------------------------------------------------------ the report


def _cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def _short(message, limit=220):
    message = " ".join(str(message).split())
    return message if len(message) <= limit else message[:limit - 3] + "..."


def refusal_problem(deck_path: str, message: str):
    """None when a refusal names the deck file, a deck line ('<file> line N') and what
    is missing (words after it); else what it lacks."""
    name = PurePosixPath(deck_path).name
    m = re.search(rf"{re.escape(name)} line (\d+)\b[:,]?\s*(.*)", message, re.DOTALL)
    if m is None:
        if name not in message:
            return f"does not name the deck ({name})"
        return "names no deck line ('<deck> line N')"
    if len(re.findall(r"[A-Za-z]{2,}", m.group(2))) < 2:
        return "names no feature after the deck line"
    return None


def skmoor_cell(o: Outcome):
    sk, status = o.skmoor, o.skmoor_status
    if status == "runs":
        return f"runs ({sk.get('process_wall', 0):.1f} s)"
    if status == "refused":
        return f"refused: {_short(sk['message'])}"
    if status == "refused badly":
        return (f"**refused, but the message {o.refusal_problem()}**: "
                f"{_short(sk['message'])}")
    if status == "not run":
        return f"not run ({sk.get('message', '')})"
    if status == "no equilibrium":
        return f"no static equilibrium: {_short(sk['message'].split('; ')[-1])}"
    return f"**error** {sk.get('type', '')}: {_short(sk.get('message', ''))}"


def moordyn_cell(o: Outcome):
    md = o.moordyn
    status = md.get("status")
    if status == "not run":
        return f"not run ({md.get('message', '')})"
    if status != "runs":
        return f"**fails** {md.get('type', '')}: {_short(md.get('message', ''), 160)}"
    parts = [f"runs ({md['wall']:.1f} s)"]
    if md.get("forced_tmax_ic"):
        parts.append(f"TmaxIC -> {md['forced_tmax_ic']:g} s")
    if md.get("ic_solver") == "dynamic" or md.get("ic_converged") is not None:
        parts.append("IC converged" if md.get("ic_converged") else "**IC not converged**")
    elif md.get("ic_error") is not None:
        text = f"IC residual {md['ic_error']:.2g} m/s2 at {md['ic_time']:g} s"
        parts.append(text if o.moordyn_settled else f"**{text}: not settled**")
    return "; ".join(parts)


def _kN(value):
    return "-" if value is None else f"{value / 1e3:.5g}"


def tension_cell(o: Outcome):
    md = o.moordyn
    rows = o.comparison()
    if rows:
        return "<br>".join(f"{k}: {_kN(sk)} / {_kN(force)}" for k, sk, force, _, _ in rows)
    if md.get("status") == "runs" and md["end_b_force"]:
        return "<br>".join(f"{k}: - / {_kN(force)}"
                           for k, force in enumerate(md["end_b_force"], start=1))
    sk = o.skmoor
    if sk.get("status") == "runs" and sk["end_b"]:
        return "<br>".join(f"{name}: {_kN(v)} / -"
                           for name, v in zip(sk["line_names"], sk["end_b"]))
    return "-"


def difference_cell(o: Outcome):
    diff = o.largest_difference()
    if diff is None:
        return "-"
    text = f"{diff:.2%}" if math.isfinite(diff) else "a line is missing"
    if not o.moordyn_settled:
        return "not compared (MoorDyn not settled)"
    return f"**{text}**" if diff > TOLERANCE else text


def summary(outcomes) -> dict:
    count = lambda status: sum(1 for o in outcomes if o.skmoor_status == status)  # noqa
    compared = [o for o in outcomes if o.compared]
    return dict(decks=len(outcomes), runs=count("runs"), refused=count("refused"),
                refused_badly=count("refused badly"), errors=count("error"),
                moordyn_runs=sum(1 for o in outcomes if o.moordyn_runs),
                moordyn_fails=[o.name for o in outcomes if o.moordyn.get("status")
                               not in ("runs", "not run")],
                compared=len(compared),
                within=sum(1 for o in compared if o.largest_difference() <= TOLERANCE),
                unsettled=[o.name for o in outcomes if o.comparison()
                           and not o.moordyn_settled])


def markdown(outcomes, info) -> str:
    n = summary(outcomes)
    out = [
        "# MoorDyn's own decks in skmoor",
        "",
        "Generated by `python benchmarks/moordyn_decks.py` (do not edit by hand). Every "
        f"MoorDyn input deck under `{'`, `'.join(FOLDERS)}` of "
        f"[{UPSTREAM}](https://github.com/{UPSTREAM}) at commit `{info['commit'][:12]}`, "
        "read from a local mirror at run time (nothing of MoorDyn's is copied here), run "
        f"in MoorDyn {info['moordyn_version']} (Python package `moordyn`) and in skmoor "
        f"{info['skmoor_version']} (`skmoor.build(deck)`, `skmoor.equilibrium`, "
        "`skmoor.static_results`).",
        "",
        f"**{n['runs']} of {n['decks']} decks run** in skmoor; {n['refused']} are refused "
        "with the deck line and the missing feature"
        + (f"; **{n['refused_badly']} are refused without naming the deck line**"
           if n["refused_badly"] else "")
        + (f"; **{n['errors']} end in an error**" if n["errors"] else "; none ends in an "
           "error") + ". "
        f"MoorDyn runs {n['moordyn_runs']} of them. "
        f"{n['compared']} decks run in both with MoorDyn's initial state settled; "
        f"{n['within']} of them agree within {TOLERANCE:.0%} in static end-B tension"
        + (f" ({len(n['unsettled'])} more run in both, but MoorDyn's IC solve leaves them "
           "moving, so they are not compared)" if n["unsettled"] else "") + ".",
        "",
        "How each side is run. MoorDyn: `Create`, then `Init` with the coupled DOFs at "
        "the deck's positions and zero velocity, i.e. its initial-condition (IC) solve as "
        f"the deck sets it; a deck whose TmaxIC is below {SHORT_TMAX_IC:g} s (0: no IC "
        "solve, and MoorDyn then reports no line forces at all) gets TmaxIC = "
        f"{FORCED_TMAX_IC:g} s. MoorDyn's IC solve stops at its own criterion (threshIC) "
        "or at TmaxIC; its state counts as static when the remaining residual it logs "
        f"(mean acceleration per state) is at most {SETTLED:g} m/s2. "
        "skmoor: its static equilibrium with the coupled objects at the same positions, "
        "in still water for a deck with Currents (MoorDyn 2.7.2's IC solve runs without "
        "them: `skmoor.io.sea_files.still_water`). "
        "Tension at end B (the deck's AttachB) per line, kN, `line: skmoor / MoorDyn`; "
        "MoorDyn's value is the end node's net force `|GetLineNodeForce(line, N)|`, the "
        "line's pull on its end point (last segment's tension plus the end node's "
        "half-segment weight and contact), the quantity skmoor reports; MoorDyn's "
        "`GetLineFairTen` (the last segment's tension alone) is in the second table. "
        "Difference: largest |skmoor - MoorDyn| / MoorDyn over the deck's lines (divisor "
        f"at least {FLOOR:.0%} of the deck's largest line-end force).",
        "",
        "| deck | skmoor | MoorDyn | lines / points / bodies / rods | features | "
        "end-B tension, kN (skmoor / MoorDyn) | largest difference |",
        "|---|---|---|---|---|---|---|",
    ]
    for o in outcomes:
        c = o.deck.census
        result = skmoor_cell(o)
        if o.deck.format == "v1":
            result = "v1 format; " + result
        out.append("| " + " | ".join(_cell(v) for v in (
            f"`{o.name}`", result, moordyn_cell(o),
            f"{c['lines']} / {c['points']} / {c['bodies']} / {c['rods']}",
            ", ".join(c["features"]) or "plain", tension_cell(o), difference_cell(o)))
            + " |")
    out += ["", "## MoorDyn's static tensions", "",
            "Per line, kN: end-B net force / end-B last-segment tension "
            "(`GetLineFairTen`); end-A net force / end-A first-segment tension "
            "(`GetLineNodeTen(line, 0)`). Wall time of Create + Init (the IC solve), the "
            "IC solver and the residual it logs.", "",
            "| deck | coupled DOFs | TmaxIC, s | IC | Init, s | per line: B force / B "
            "segment; A force / A segment |", "|---|---|---|---|---|---|"]
    for o in outcomes:
        md = o.moordyn
        if md.get("status") != "runs":
            continue
        lines = "<br>".join(
            f"{k}: {_kN(bf)} / {_kN(bs)}; {_kN(af)} / {_kN(as_)}"
            for k, (bf, bs, af, as_) in enumerate(zip(md["end_b_force"], md["end_b_segment"],
                                                     md["end_a_force"], md["end_a_segment"]),
                                                 start=1)) or "(no lines)"
        if md.get("ic_solver") == "dynamic" or md.get("ic_converged") is not None:
            ic = "dynamic relaxation, " + ("converged" if md.get("ic_converged")
                                           else "not converged")
        elif md.get("ic_error") is not None:
            ic = (f"stationary, stopped at {md['ic_time']:g} s, residual "
                  f"{md['ic_error']:.3g} m/s2")
        else:
            ic = "?"
        tmax = f"{md.get('tmax_ic', 0):g}" + (" (forced)" if md.get("forced_tmax_ic") else "")
        out.append(f"| `{o.name}` | {md['n_coupled_dof']} | {tmax} | {ic} | "
                   f"{md['wall']:.2f} | {lines} |")
    if n["moordyn_fails"]:
        out += ["", "## Decks MoorDyn itself does not run", ""]
        for o in outcomes:
            if o.name in n["moordyn_fails"]:
                out.append(f"- `{o.name}`: {_short(o.moordyn.get('message', ''), 400)}")
    notes = []
    for path, values in TEMPLATES.items():
        filled = ", ".join(f"{k} = {v}" for k, v in values.items())
        notes.append(f"- `{path}` is a template; both codes get it filled as MoorDyn's own "
                     f"test does for its first case ({filled}).")
    for path, before in PREREQUISITES.items():
        notes.append(f"- `{path}` starts from a state file (fileIC) made by running "
                     f"{' then '.join(f'`{p}`' for p in before)} first in MoorDyn, as "
                     "MoorDyn's tests/test_complex_ic.py does (skmoor reads no state "
                     "files).")
    for path, why in NOT_STATIC.items():
        notes.append(f"- `{path}` {why}.")
    for path, why in info["skipped"].items():
        notes.append(f"- `{path}`: {why}; not counted.")
    for path in info.get("absent", []):
        notes.append(f"- `{path}` is not in the mirror (its blob is missing); no deck "
                     "names it.")
    if notes:
        out += ["", "## Notes", ""] + notes
    out += ["", "## Run", "",
            f"{n['decks']} decks in {info['wall']:.0f} s: MoorDyn in subprocesses "
            f"({info['jobs']} at a time, {info['moordyn_cpu']:.0f} s summed over decks, "
            "process start included), skmoor "
            f"{'in one process' if info.get('skmoor_inline') else 'in subprocesses'} "
            f"({info['skmoor_cpu']:.0f} s summed).", ""]
    return "\n".join(out)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mirror", help=f"MoorDyn's git repository (bare or not; default "
                        f"${MIRROR_ENV} or {DEFAULT_MIRROR})")
    parser.add_argument("--out", default=str(DEFAULT_OUT), help="markdown report "
                        "(default docs/moordyn_decks.md; with --only: printed unless given)")
    parser.add_argument("--only", help="only the decks whose path contains this")
    parser.add_argument("--jobs", type=int, default=None, help="parallel processes "
                        "(default: CPU count)")
    parser.add_argument("--moordyn-timeout", type=float, default=MOORDYN_TIMEOUT)
    parser.add_argument("--skmoor-timeout", type=float, default=SKMOOR_TIMEOUT)
    parser.add_argument("--side", choices=("both", "moordyn", "skmoor"), default="both")
    parser.add_argument("--isolate", action="store_true", help="run skmoor in a "
                        "subprocess per deck too (default: in this process)")
    parser.add_argument("--json", help="also write the raw results here")
    parser.add_argument("--quiet", action="store_true")
    parser.add_argument("--worker", choices=("moordyn", "skmoor"), help=argparse.SUPPRESS)
    parser.add_argument("--deck", help=argparse.SUPPRESS)
    parser.add_argument("--result", help=argparse.SUPPRESS)
    parser.add_argument("--cwd", help=argparse.SUPPRESS)
    parser.add_argument("--pre", action="append", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        return _worker_main(args)
    sides = ("moordyn", "skmoor") if args.side == "both" else (args.side,)
    log = None if args.quiet else (lambda msg: print(msg, file=sys.stderr, flush=True))
    try:
        outcomes, info = survey(args.mirror, only=args.only, jobs=args.jobs,
                                moordyn_timeout=args.moordyn_timeout,
                                skmoor_timeout=args.skmoor_timeout, sides=sides,
                                isolate=args.isolate, log=log)
    except MirrorMissing as err:
        print(f"moordyn_decks: {err}", file=sys.stderr)
        return 2
    text = markdown(outcomes, info)
    if args.json:
        Path(args.json).write_text(json.dumps(dict(info=info, decks=[
            dict(deck=o.name, format=o.deck.format, census=o.deck.census,
                 moordyn=o.moordyn, skmoor=o.skmoor) for o in outcomes]), indent=1))
    explicit_out = any(a == "--out" or a.startswith("--out=") for a in (argv or sys.argv))
    if args.only and not explicit_out:
        print(text)
    else:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(text + "\n", encoding="utf-8")
        print(f"wrote {args.out}: {info['wall']:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
