"""A platform's motion from an OpenFAST output file (``.out`` text, ``.outb`` binary) as a
MoorDyn deck's coupled-DOF record: the six platform channels (PtfmSurge, PtfmSway,
PtfmHeave in m; PtfmRoll, PtfmPitch, PtfmYaw in deg or rad as the file's units say) read
with NREL's reader (``openfast_io``, ``pip install 'skmoor[openfast]'``) and carried to
the deck's coupled objects as a rigid platform turning about its reference point (the
origin, as OpenFAST's MoorDyn decks place it), the angles taken as MoorDyn takes a
coupled body's (R = Rx(roll) Ry(pitch) Rz(yaw)):

- a coupled body (at r0, zero attitude) moves to ``xi + R r0`` and turns by the angles;
- a coupled point (a fairlead at p0) moves by ``xi + R p0 - p0``.

The result is a :class:`~skmoor.bodies.motion.Record` through the file's rows.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..bodies.motion import Record
from ..coupling.network import moordyn_rotation

PLATFORM_CHANNELS = ("PtfmSurge", "PtfmSway", "PtfmHeave", "PtfmRoll", "PtfmPitch", "PtfmYaw")
OPENFAST_SUFFIXES = (".out", ".outb")
_LENGTH_UNITS = {"m": 1.0}
_ANGLE_UNITS = {"deg": np.pi / 180, "rad": 1.0}

__all__ = ["read_openfast_platform", "openfast_motion", "is_openfast_output"]


def is_openfast_output(path) -> bool:
    return Path(path).suffix.lower() in OPENFAST_SUFFIXES


def read_openfast_platform(path) -> tuple[np.ndarray, np.ndarray]:
    """(times (m,) in s, platform DOFs (m, 6): surge, sway, heave in m, roll, pitch, yaw in
    rad) from an OpenFAST output file."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"--motion: no such file {path}")
    if not is_openfast_output(path):
        raise ValueError(f"{path.name}: not an OpenFAST output file (.out or .outb)")
    try:
        from openfast_io.FAST_output_reader import load_ascii_output, load_binary_output
    except ImportError:
        raise ImportError(f"{path.name}: reading OpenFAST output files needs openfast_io "
                          "(pip install 'skmoor[openfast]')") from None
    try:
        if path.suffix.lower() == ".outb":
            data, info, _ = load_binary_output(str(path))
        else:
            data, info = load_ascii_output(str(path))
    except Exception as err:  # the reader's own errors: struct, ValueError, IndexError
        raise ValueError(f"{path.name}: not readable as an OpenFAST output file "
                         f"({type(err).__name__}: {err})") from None
    names = [str(n).strip() for n in info["attribute_names"]]
    units = [str(u).strip().strip("()") for u in info["attribute_units"]]
    lower = [n.lower() for n in names]
    missing = [c for c in ("Time",) + PLATFORM_CHANNELS if c.lower() not in lower]
    if missing:
        raise ValueError(f"{path.name}: no channel {', '.join(missing)} (the platform's "
                         "six DOFs are ElastoDyn's outputs PtfmSurge ... PtfmYaw; add them "
                         "to its OutList)")
    data = np.asarray(data, float)
    times = data[:, lower.index("time")]
    dofs = np.empty((len(times), 6))
    for k, channel in enumerate(PLATFORM_CHANNELS):
        i = lower.index(channel.lower())
        table = _LENGTH_UNITS if k < 3 else _ANGLE_UNITS
        unit = units[i].lower() if i < len(units) else ""
        if unit not in table:
            raise ValueError(f"{path.name}: channel {names[i]} in '{unit}', expected "
                             f"{' or '.join(table)}")
        dofs[:, k] = data[:, i] * table[unit]
    if not (np.all(np.isfinite(times)) and np.all(np.isfinite(dofs))):
        raise ValueError(f"{path.name}: the time or a platform channel holds NaN or inf")
    if len(times) < 2 or np.any(np.diff(times) <= 0):
        raise ValueError(f"{path.name}: the times must increase row by row (two rows or more)")
    return times, dofs


def openfast_motion(path, deck) -> Record:
    """The coupled-DOF displacements of ``deck`` (a :class:`~skmoor.io.deck.Deck`) from the
    platform motion in the OpenFAST output file ``path``, in MoorDyn's order of coupled
    DOFs (6 per coupled body, 3 per coupled point), as a :class:`Record`."""
    pinned = [b.id for b in deck.bodies if b.kind == "pinned"]
    rods = [r.id for r in deck.rods if r.kind in ("coupled", "coupled pinned")]
    bodies = [b for b in deck.bodies if b.kind == "coupled"]
    if rods or pinned:
        what = f"rod {rods[0]}" if rods else f"body {pinned[0]} (CoupledPinned)"
        raise ValueError(f"--motion {Path(path).name}: the deck's coupled {what} is not "
                         "moved by a platform record (coupled bodies and points are); give "
                         "its DOFs as a table of numbers instead")
    if len(bodies) > 1:
        raise ValueError(f"--motion {Path(path).name}: the deck has {len(bodies)} coupled "
                         "bodies and an OpenFAST file holds one platform's motion")
    turned = [b.id for b in bodies if np.any(np.asarray(b.r6[3:], float) != 0)]
    if turned:
        raise ValueError(f"--motion {Path(path).name}: coupled body {turned[0]} starts "
                         "turned (roll, pitch, yaw not 0); a platform record turns a body "
                         "from zero attitude")
    points = np.array([p.position for p in deck.points if p.kind == "coupled"],
                      float).reshape(-1, 3)
    if not bodies and not len(points):
        raise ValueError(f"--motion {Path(path).name}: the deck has no coupled body or point "
                         "to move")
    times, q = read_openfast_platform(path)
    R = np.array([moordyn_rotation(angles) for angles in q[:, 3:]])  # (m, 3, 3)

    def moved(r):  # displacement (m, 3) of the platform-fixed point r (3,)
        return q[:, :3] + R @ r - r

    columns = []
    for body in bodies:
        columns += [moved(np.asarray(body.r6[:3], float)), q[:, 3:]]
    columns += [moved(p) for p in points]
    return Record(times, np.hstack(columns))
