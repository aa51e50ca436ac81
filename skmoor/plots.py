"""Time histories and parameter studies as figures (PNG, PDF or SVG by the suffix;
matplotlib without pyplot, so no GUI backend is ever touched)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

STUDY_KEYS = ("value", "surge", "heave", "pitch", "max_tension")


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
    axes[-1].set_xlabel("time t [s]")
    axes[-1].set_xlim(results.t[0], results.t[-1])
    title = results.meta.get("case", "") if title is None else title
    if title:
        fig.suptitle(str(title))
    return _save(fig, path)


def plot_study(rows, path, parameter_label, title=None, figsize=(9.0, 7.0), dpi=120) -> Path:
    """Steady-state amplitudes of surge (m), heave (m), pitch (rad) and the maximum
    tension (kN) against the studied parameter, in 2 x 2 panels.

    rows: dicts with keys value, surge, heave, pitch (amplitudes, SI) and max_tension (N)."""
    if len(rows) == 0:
        raise ValueError("rows is empty")
    for k, row in enumerate(rows):
        missing = [key for key in STUDY_KEYS if key not in row]
        if missing:
            raise ValueError(f"rows[{k}] misses key(s) {missing}")
    rows = sorted(rows, key=lambda row: row["value"])
    x = np.array([row["value"] for row in rows], dtype=float)
    panels = [("surge", 1.0, "surge amplitude [m]"), ("heave", 1.0, "heave amplitude [m]"),
              ("pitch", 1.0, "pitch amplitude [rad]"), ("max_tension", 1e-3, "max tension [kN]")]
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
