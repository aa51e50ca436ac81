"""MoorDyn-style output files of a run, so that scripts written for MoorDyn's outputs read
skmoor's unchanged.

MoorDyn v2 writes, beside its deck ``NAME.dat``: ``NAME.out`` (time and the channels of the
deck's OUTPUTS section) and, for each line whose output flags ask for it, ``NAME_LineN.out``
(time and, in this order, node positions ``p``, node velocities ``v`` and segment tensions
``t``). Both have a header row of channel names, a row of units and one row per output time,
in MoorDyn's column widths (10 for the time, 20 for each value, scientific with 7 digits)
and its units (in brackets in the line files, bare in the main file).
Written here: the line flags p, v, t and the channels FairTen<N>, AnchTen<N> and
L<N>N<M>PX/PY/PZ/VX/VY/VZ; other flags and channels are left out, each named in the notes.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np

WIDTH, PRECISION = 20, 7  # MoorDyn's value column width and digits
LINE_FLAGS = "pvt"  # the per-line flags written here, in MoorDyn's column order
_NODE_CHANNEL = re.compile(r"^L(?:INE)?(\d+)N(\d+)(P|V)([XYZ])$")


def line_nodes(results, k) -> tuple:
    """(node numbers, element numbers) of line k from end A (node 0, the anchor end) to
    end B: a line's elements follow each other in the one mesh, from end A."""
    cells = np.flatnonzero(np.asarray(results.line_of_cell) == k)
    ends = np.asarray(results.cells)[cells]
    return np.append(ends[:, 0], ends[-1, 1]), cells


def _row(time, values) -> str:
    return f"{time:10.4f}" + "".join(f"{v:{WIDTH}.{PRECISION}e}" for v in values) + "\n"


def _header(names, units) -> str:
    return (f"{'Time':>10}" + "".join(f"{n:>{WIDTH}}" for n in names) + "\n"
            + f"{'(s)':>10}" + "".join(f"{u:>{WIDTH}}" for u in units) + "\n")


def _write(path, names, units, t, columns):
    table = np.column_stack(columns) if columns else np.zeros((len(t), 0))
    with open(path, "w") as f:
        f.write(_header(names, units))
        for time, values in zip(t, table):
            f.write(_row(time, values))


def _line_file(results, k, flags, path):
    nodes, elements = line_nodes(results, k)
    names, units, columns = [], [], []
    if "p" in flags:
        position = results.points[nodes][None] + results.displacement[:, nodes]
        for i in range(len(nodes)):
            for c, axis in enumerate("xyz"):
                names.append(f"Node{i}p{axis}")
                units.append("(m)")
                columns.append(position[:, i, c])
    if "v" in flags:
        for i, node in enumerate(nodes):
            for c, axis in enumerate("xyz"):
                names.append(f"Node{i}v{axis}")
                units.append("(m/s)")
                columns.append(results.velocity[:, node, c])
    if "t" in flags:
        for i, e in enumerate(elements):
            names.append(f"Seg{i + 1}Te")
            units.append("(N)")
            columns.append(results.tension[:, e])
    _write(path, names, units, results.t, columns)


def _channel(results, name, line_of):
    """(unit, series) of one OUTPUTS channel, or None when skmoor does not write it."""
    word = name.upper()
    match = re.fullmatch(r"(FAIRTEN|ANCHTEN)(\d+)", word)
    if match:
        k = line_of.get(int(match.group(2)))
        if k is None:
            return None
        series = results.fairlead_tension if match.group(1) == "FAIRTEN" else results.anchor_tension
        return "N", series[:, k]
    match = _NODE_CHANNEL.match(word)
    if match:
        k = line_of.get(int(match.group(1)))
        if k is None:
            return None
        nodes = line_nodes(results, k)[0]
        i = int(match.group(2))
        if i >= len(nodes):
            return None
        c = "XYZ".index(match.group(4))
        if match.group(3) == "P":
            return "m", results.points[nodes[i], c] + results.displacement[:, nodes[i], c]
        return "m/s", results.velocity[:, nodes[i], c]
    return None


def write_moordyn_outputs(results, folder, stem, line_flags=None, channels=None) -> list:
    """Writes ``stem.out`` and ``stem_LineN.out`` into ``folder`` as MoorDyn would for a
    deck ``stem.dat``. line_flags: line number (1-based, as the deck numbers them) -> its
    output flags (default: 'pt' for every line, numbered in results order); channels: the
    deck's OUTPUTS (default: FairTen and AnchTen of every line). Returns the notes: the
    flags and channels left out."""
    folder = Path(folder)
    numbers = {}
    for k, name in enumerate(results.line_names):
        digits = re.findall(r"\d+", str(name))
        numbers[k] = int(digits[-1]) if digits else k + 1
    line_of = {n: k for k, n in numbers.items()}
    if line_flags is None:
        line_flags = {n: "pt" for n in numbers.values()}
    if channels is None:
        channels = [f"FairTen{n}" for n in numbers.values()] + [
            f"AnchTen{n}" for n in numbers.values()]
    notes = []
    for number, flags in line_flags.items():
        written = "".join(f for f in LINE_FLAGS if f in flags)
        left = "".join(f for f in flags if f not in LINE_FLAGS + "-")
        if left:
            notes.append(f"Line{number}: output flags {left!r} not written (skmoor writes "
                         f"{LINE_FLAGS!r})")
        if written and number in line_of:
            _line_file(results, line_of[number], written, folder / f"{stem}_Line{number}.out")
    names, units, columns = [], [], []
    for name in channels:
        found = _channel(results, name, line_of)
        if found is None:
            notes.append(f"{stem}.out: channel {name!r} not written")
            continue
        names.append(name)
        units.append(found[0])
        columns.append(found[1])
    _write(folder / f"{stem}.out", names, units, results.t, columns)
    return notes
