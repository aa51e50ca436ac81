"""The lines' strength over a run: each line's largest tension against its minimum
breaking load (MBL), the safety factor ``MBL / Tmax`` and the utilisation ``Tmax / MBL``;
for bending lines the smallest bend radius against the allowable one (MBR).

The MBL, MBR, fatigue curve and nominal diameter of each line come from its line type
(``LineType.MBL`` ..., a case file's ``[line_types.NAME]``) and travel with the results
in ``results.meta`` (``line_MBL`` ...). MoorDyn's LINE TYPES table has no MBL column (its
``alphaMBL`` is a product, alpha times MBL): for a deck's run give them here (``mbl=``).
"""
from __future__ import annotations

import numpy as np

__all__ = ["line_strength_meta", "line_property", "strength"]


def line_strength_meta(lines) -> dict:
    """The per-line strength and fatigue data kept in ``Results.meta``: lists over the
    lines of their MBL (N), MBR (m), fatigue curve's name and nominal diameter (m; the
    diameter when the type gives none), None where unknown."""
    types = [line.line_type for line in lines]
    return {"line_MBL": [t.MBL for t in types], "line_MBR": [t.MBR for t in types],
            "line_fatigue_curve": [t.fatigue_curve for t in types],
            "line_d_nom": [t.d_nom if t.d_nom is not None else t.diameter for t in types]}


def line_property(results, key, given=None) -> list:
    """One value per line of ``results.meta["line_" + key]``, overridden by ``given``: a
    value for every line, or {line name: value} for some."""
    values = list(results.meta.get(f"line_{key}") or [None] * len(results.line_names))
    if given is None:
        return values
    if not isinstance(given, dict):
        return [given] * len(results.line_names)
    unknown = sorted(set(given) - set(results.line_names))
    if unknown:
        raise ValueError(f"{key}: no line named {', '.join(map(repr, unknown))} (the lines are "
                         f"{', '.join(results.line_names)})")
    return [given.get(name, v) for name, v in zip(results.line_names, values)]


def strength(results, mbl=None, mbr=None, start=0.0) -> dict:
    """{line name: its strength over the samples from time ``start`` (s)}:

    ``max_tension`` (N: the largest of the element tensions and the two end tensions),
    its ``time`` (s) and ``where`` ('element J', 'fairlead' or 'anchor'), ``element``
    (the most loaded element's index within the line, from end A),
    ``element_max_tension`` (N, each element's largest), ``MBL`` (N or None),
    ``safety_factor`` = MBL / max_tension and ``utilisation`` = max_tension / MBL (None
    without an MBL); on bending lines also ``min_bend_radius`` (m, 1 / the largest
    curvature; None if straight throughout), ``MBR`` and ``bend_radius_ratio`` = min_bend_radius / MBR (>= 1: within
    the allowable). mbl, mbr: a value for all lines or {line name: value}, over the line
    types' own."""
    keep = results.t >= start - 1e-12
    if not keep.any():
        raise ValueError(f"strength: no sample from t = {start:g} s (the run ends at "
                         f"{results.t[-1]:g} s)")
    mbls = line_property(results, "MBL", mbl)
    mbrs = line_property(results, "MBR", mbr)
    tension = results.tension[keep]
    t = results.t[keep]
    out = {}
    for k, name in enumerate(results.line_names):
        cells = np.flatnonzero(results.line_of_cell == k)
        if not len(cells):
            continue
        series = tension[:, cells]
        i, j = np.unravel_index(int(np.argmax(series)), series.shape)
        tmax, at = float(series[i, j]), f"element {int(j)}"
        for end, values in (("fairlead", results.fairlead_tension[keep][:, k]),
                            ("anchor", results.anchor_tension[keep][:, k])):
            if len(values) and values.max() > tmax:
                i, tmax, at = int(np.argmax(values)), float(values.max()), end
        MBL = None if mbls[k] is None else float(mbls[k])
        row = {"max_tension": tmax, "time": float(t[i]), "where": at,
               "element": int(np.argmax(series.max(axis=0))),
               "MBL": MBL,
               "safety_factor": None if MBL is None or tmax <= 0 else MBL / tmax,
               "utilisation": None if MBL is None else tmax / MBL,
               "element_max_tension": series.max(axis=0).tolist()}
        if results.bending:
            kappa = float(np.abs(results.curvature[keep][:, cells]).max())
            radius = None if kappa == 0 else 1.0 / kappa
            MBR = None if mbrs[k] is None else float(mbrs[k])
            row.update({"min_bend_radius": radius, "MBR": MBR,
                        "bend_radius_ratio": (None if MBR is None or radius is None
                                              else radius / MBR)})
        out[name] = row
    return out
