"""Time histories and parameter studies as figures (PNG, PDF or SVG by the suffix;
matplotlib without pyplot, so no GUI backend is ever touched): the paper's Fig. 6
(:func:`plot_time_histories`), one body of a network with its lines' fairlead tensions
(:func:`plot_body_and_tensions`), the lines' strength (:func:`plot_strength`) and the
parameter studies (:func:`plot_study`)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

STUDY_KEYS = ("value", "surge", "heave", "pitch", "max_tension_steady")


def plot_time_histories(results, path, title=None, figsize=(8.0, 9.0), dpi=120) -> Path:
    """Surge x (m), heave (m), pitch (rad) and the maximum element tension over all lines
    (kN) against time (s), stacked in 4 panels (the paper's Fig. 6). The title defaults
    to ``results.meta["case"]``; pass ``""`` for none."""
    panels = [(results.body_series("surge"), "surge x [m]"),
              (results.body_series("heave"), "heave z [m]"),
              (results.body_series("pitch"), "pitch [rad]"),
              (results.max_tension / 1e3, "max tension [kN]")]
    fig = Figure(figsize=figsize, dpi=dpi, layout="constrained")
    axes = fig.subplots(4, 1, sharex=True)
    for ax, (y, label), letter in zip(axes, panels, "abcd"):
        ax.plot(results.t, y, color="C0", lw=1.2)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.set_title(f"({letter})", loc="left", fontsize="medium")
    return _finish_history(fig, axes, results, title, path)


def _finish_history(fig, axes, results, title, path) -> Path:
    """Time axis, the title (default ``results.meta["case"]``) and the file."""
    axes[-1].set_xlabel("time t [s]")
    axes[-1].set_xlim(results.t[0], results.t[-1])
    title = results.meta.get("case", "") if title is None else title
    if title:
        fig.suptitle(str(title))
    return _save(fig, path)


def plot_body_and_tensions(results, path, body=None, lines=None, title=None,
                           figsize=(8.0, 9.0), dpi=120) -> Path:
    """Surge x (m), heave z (m) and pitch (rad) of one body of a network and the
    fairlead (end B) tension of the chosen lines (kN, one curve each, dashed in turn so
    that equal ones stay visible) against time (s), stacked in 4 panels. body: its name
    in ``results.body_names`` (default the first); lines: names in
    ``results.line_names`` (default all). The title defaults to ``results.meta["case"]``;
    pass ``""`` for none."""
    names = list(results.body_names)
    if not names:
        raise ValueError("results have no body to plot")
    body = names[0] if body is None else body
    if body not in names:
        raise ValueError(f"body {body!r} is not one of the results' bodies {names}")
    lines = list(results.line_names) if lines is None else list(lines)
    unknown = [name for name in lines if name not in results.line_names]
    if unknown or not lines:
        raise ValueError(f"lines {unknown or lines} are not among the results' lines "
                         f"{list(results.line_names)}")
    q = np.asarray(results.bodies)[:, names.index(body)]
    panels = [(q[:, 0], f"{body} surge x [m]"), (q[:, 2], f"{body} heave z [m]"),
              (q[:, 4], f"{body} pitch [rad]")]
    fig = Figure(figsize=figsize, dpi=dpi, layout="constrained")
    axes = fig.subplots(4, 1, sharex=True)
    for ax, (y, label) in zip(axes, panels):
        ax.plot(results.t, y, color="C0", lw=1.2)
        ax.set_ylabel(label)
    ax = axes[-1]
    for k, name in enumerate(lines):
        column = list(results.line_names).index(name)
        ax.plot(results.t, np.asarray(results.fairlead_tension)[:, column] / 1e3,
                color=f"C{k}", ls=("-", "--", "-.", ":")[k % 4], lw=1.2, label=name)
    ax.set_ylabel("fairlead tension [kN]")
    ax.legend(loc="upper right", fontsize="small", ncol=min(len(lines), 4))
    for ax, letter in zip(axes, "abcd"):
        ax.grid(alpha=0.3)
        ax.set_title(f"({letter})", loc="left", fontsize="medium")
    return _finish_history(fig, axes, results, title, path)


def plot_line_tensions(results, path, title=None, figsize=(8.0, 5.0), dpi=120) -> Path:
    """The tension at the fairlead, end B (solid) and at the anchor, end A (dashed) of
    every line (kN) against time (s): the time-history plot of a network without bodies."""
    fig = Figure(figsize=figsize, dpi=dpi, layout="constrained")
    ax = fig.subplots(1, 1)
    for k, name in enumerate(results.line_names):
        ax.plot(results.t, np.asarray(results.fairlead_tension)[:, k] / 1e3, color=f"C{k}",
                lw=1.2, label=f"{name} fairlead (end B)")
        ax.plot(results.t, np.asarray(results.anchor_tension)[:, k] / 1e3, color=f"C{k}",
                lw=1.0, ls="--", label=f"{name} anchor (end A)")
    ax.set_ylabel("tension [kN]")
    ax.ticklabel_format(axis="y", useOffset=False)
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize="small", ncol=2)
    return _finish_history(fig, [ax], results, title, path)


def plot_strength(results, path, mbl=None, title=None, figsize=(8.0, 6.0), dpi=120) -> Path:
    """The lines' strength (:func:`skmoor.post.strength.strength`): (a) each element's
    largest tension over the run (kN) along its line (element index from end A), the
    line's MBL dashed where known; (b) each line's utilisation Tmax / MBL (%), its safety
    factor written on the bar. mbl: as for ``strength`` (a value or {line: N})."""
    from .strength import strength

    rows = strength(results, mbl=mbl)
    fig = Figure(figsize=figsize, dpi=dpi, layout="constrained")
    top, bottom = fig.subplots(2, 1)
    for k, (name, row) in enumerate(rows.items()):
        y = np.asarray(row["element_max_tension"]) / 1e3
        top.plot(np.arange(len(y)), y, "o-", ms=3, lw=1.2, color=f"C{k}", label=name)
        if row["MBL"] is not None:
            top.axhline(row["MBL"] / 1e3, color=f"C{k}", ls="--", lw=1.0)
    top.set_xlabel("element (from the anchor end)")
    top.set_ylabel("largest tension [kN]")
    top.ticklabel_format(axis="y", useOffset=False)
    top.legend(loc="best", fontsize="small", ncol=min(len(rows), 4) or 1)
    names = [n for n, row in rows.items() if row["utilisation"] is not None]
    use = [100 * rows[n]["utilisation"] for n in names]
    bars = bottom.bar(names, use, color=[f"C{list(rows).index(n)}" for n in names])
    for bar, name in zip(bars, names):
        bottom.annotate(f"SF {rows[name]['safety_factor']:.2f}",
                        (bar.get_x() + bar.get_width() / 2, bar.get_height()),
                        ha="center", va="bottom", fontsize="small")
    if not names:
        bottom.text(0.5, 0.5, "no MBL given: no utilisation", ha="center", va="center",
                    transform=bottom.transAxes)
    bottom.set_ylabel("utilisation Tmax / MBL [%]")
    for ax, letter in zip((top, bottom), "ab"):
        ax.grid(alpha=0.3)
        ax.set_title(f"({letter})", loc="left", fontsize="medium")
    title = results.meta.get("case", "") if title is None else title
    if title:
        fig.suptitle(str(title))
    return _save(fig, path)


def plot_study(rows, path, parameter_label, title=None, figsize=(9.0, 7.0), dpi=120) -> Path:
    """Steady-state amplitudes of surge (m), heave (m), pitch (rad) and the maximum
    tension (kN) against the studied parameter, in 2 x 2 panels.

    rows: dicts with keys value, surge, heave, pitch (amplitudes, SI) and max_tension_steady (N)."""
    if len(rows) == 0:
        raise ValueError("rows is empty")
    for k, row in enumerate(rows):
        missing = [key for key in STUDY_KEYS if key not in row]
        if missing:
            raise ValueError(f"rows[{k}] misses key(s) {missing}")
    rows = sorted(rows, key=lambda row: row["value"])
    x = np.array([row["value"] for row in rows], dtype=float)
    panels = [("surge", 1.0, "surge amplitude [m]"), ("heave", 1.0, "heave amplitude [m]"),
              ("pitch", 1.0, "pitch amplitude [rad]"), ("max_tension_steady", 1e-3, "steady max tension [kN]")]
    fig = Figure(figsize=figsize, dpi=dpi, layout="constrained")
    axes = fig.subplots(2, 2, sharex=True)
    for ax, (key, factor, label), letter in zip(axes.flat, panels, "abcd"):
        ax.plot(x, factor * np.array([row[key] for row in rows], dtype=float), "o-",
                color="C0", lw=1.2, ms=5)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.set_title(f"({letter})", loc="left", fontsize="medium")
    for ax in axes[1]:
        ax.set_xlabel(parameter_label)
    if title:
        fig.suptitle(title)
    return _save(fig, path)


def _save(fig, path):
    path = Path(path)
    if path.suffix not in (".png", ".pdf", ".svg"):
        raise ValueError(f"path must end in .png, .pdf or .svg, got {path.name!r}")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    return path
