"""Results of a run: time series of the body and the lines, saved as one ``.npz``.

All arrays are SI (m, N, s, rad). Lines share one node numbering (the one mesh of
:class:`skmoor.lines.line.LineSet`): ``cells`` joins nodes into elements, ``line_of_cell``
tells which line an element belongs to.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

BODY_DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")


@dataclass
class Results:
    """Sampled states of a coupled run (or a single static state with ``nt == 1``).

    t                   (nt,)            time, s
    body                (nt, 6)          first body's displacement [x, y, z, rx, ry, rz] from its reference, m / rad (zeros without one; the body drawn)
    points              (nnodes, 3)      reference (static) node positions, m
    cells               (nel, 2)         element connectivity
    line_of_cell        (nel,)           line index of each element
    line_names          [nlines]         names of the lines
    displacement        (nt, nnodes, 3)  node displacement from ``points``, m
    velocity            (nt, nnodes, 3)  node velocity, m/s
    tension             (nt, nel)        element tension, N
    strain              (nt, nel)        element strain (relative to the reference), -
    fairlead_tension    (nt, nlines)     tension at end B (the fairlead end), N
    anchor_tension      (nt, nlines)     tension at end A (the anchor end), N
    body_center         (3,)             reference position of the body's reference point, m
    body_box            (3,)             box dimensions (Lx, Ly, Lz) in m for drawing, or zeros
    body_box_center     (3,)             box centre relative to the body's reference point, m
    depth               float            water depth, m
    meta                dict             free-form (case name, solver settings, wall time ...)
    body_names          [nbodies]        names of all bodies (dynamic, coupled, fixed)
    body_reference      (nbodies, 3)     reference-point positions of the bodies, m
    bodies              (nt, nbodies, 6) each body's displacement from its reference, m / rad
    point_names         [npoints]        names of all points of the network
    point_reference     (npoints, 3)     point positions in the reference state, m
    point_displacement  (nt, npoints, 3) point displacements from it, m
    curvature           (nt, nel)        curvature at the element mid-points, 1/m (zeros on cables)
    bending_moment      (nt, nel)        bending moment EI x curvature there, N m (zeros on cables)
    coupled_loads       (nt, nbodies, 6) force (N) and moment (N m, about the reference point, global axes) each coupled body, and each body pinned on coupled DOFs (its pin's force), passes to the caller (skmoor.coupling.rods.coupled_reaction; zeros on the others)
    """

    t: np.ndarray
    body: np.ndarray
    points: np.ndarray
    cells: np.ndarray
    line_of_cell: np.ndarray
    line_names: list
    displacement: np.ndarray
    velocity: np.ndarray
    tension: np.ndarray
    strain: np.ndarray
    fairlead_tension: np.ndarray
    anchor_tension: np.ndarray
    body_center: np.ndarray = field(default_factory=lambda: np.zeros(3))
    body_box: np.ndarray = field(default_factory=lambda: np.zeros(3))
    body_box_center: np.ndarray = field(default_factory=lambda: np.zeros(3))
    depth: float = 0.0
    meta: dict = field(default_factory=dict)
    body_names: list = field(default_factory=list)
    body_reference: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    bodies: np.ndarray = None
    point_names: list = field(default_factory=list)
    point_reference: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    point_displacement: np.ndarray = None
    curvature: np.ndarray = None
    bending_moment: np.ndarray = None
    coupled_loads: np.ndarray = None

    def __post_init__(self):
        nt = len(self.t)
        for name in ("curvature", "bending_moment"):
            if getattr(self, name) is None:
                setattr(self, name, np.zeros((nt, len(self.line_of_cell))))
        if self.bodies is None:
            self.bodies = np.zeros((nt, len(self.body_names), 6))
        if self.point_displacement is None:
            self.point_displacement = np.zeros((nt, len(self.point_names), 3))
        if self.coupled_loads is None:
            self.coupled_loads = np.zeros((nt, len(self.body_names), 6))

    def point_positions(self, i: int) -> np.ndarray:
        """(npoints, 3) positions of the network's points at sample ``i``, m."""
        return self.point_reference + self.point_displacement[i]

    @property
    def bending(self) -> bool:
        """True when the run has bending lines (EI > 0): curvature and moment are data."""
        return bool(self.meta.get("bending", False))

    def line_maxima(self, name: str) -> dict:
        """{line name: largest value} of a (nt, nel) array (e.g. ``bending_moment``) over
        the run and each line's elements."""
        values = np.abs(getattr(self, name)).max(axis=0)
        return {line: float(values[self.line_of_cell == k].max())
                for k, line in enumerate(self.line_names)}

    @property
    def max_tension(self) -> np.ndarray:
        """(nt,) largest element tension over all lines at each time, N (0 without lines)."""
        return self.tension.max(axis=1) if self.tension.shape[1] else np.zeros(len(self.t))

    def positions(self, i: int) -> np.ndarray:
        """(nnodes, 3) deformed node positions at sample ``i``, m."""
        return self.points + self.displacement[i]

    def body_series(self, name: str) -> np.ndarray:
        """Time series of one body DOF by name (``surge``, ``heave``, ``pitch`` ...)."""
        return self.body[:, BODY_DOFS.index(name)]

    def amplitude(self, series: np.ndarray, period: float, n_periods: int = 5) -> float:
        """Steady-state amplitude of ``series``: half its range over the last
        ``n_periods`` periods (of length ``period``, s)."""
        start = self.t[-1] - n_periods * period
        if start < self.t[0]:
            raise ValueError(f"amplitude: the run ({self.t[-1] - self.t[0]:g} s) is shorter "
                             f"than {n_periods} periods of {period:g} s")
        window = series[self.t >= start - 1e-12]
        return 0.5 * float(window.max() - window.min())

    def truncated(self, n: int) -> Results:
        """The first ``n`` samples (used to save what a stopped run computed)."""
        kw = {f.name: getattr(self, f.name) for f in fields(self)}
        for name in _TIME_ARRAYS:
            kw[name] = kw[name][:n]
        return Results(**kw)

    def save(self, path) -> Path:
        """Write to ``path`` (``.npz``); returns the path."""
        path = Path(path)
        arrays = {f.name: np.asarray(getattr(self, f.name)) for f in fields(self)
                  if f.name not in ("meta", "depth") + _NAMES}
        names = {key: np.array(getattr(self, key), dtype=str) for key in _NAMES}
        np.savez_compressed(path, **arrays, depth=np.float64(self.depth), **names,
                            meta=np.array(json.dumps(self.meta, default=_jsonable)))
        return path

    def to_xarray(self):
        """The results as an :class:`xarray.Dataset`: dimensions ``time``, ``line``,
        ``node``, ``element``, ``body``, ``dof`` (surge ... yaw), ``point``, ``axis`` (x, y,
        z), ``end`` (A, B) and ``load`` (Fx ... Mz); every variable with its ``units``
        and ``long_name``; the water depth and the meta (JSON) as attributes.
        :meth:`from_xarray` reads it back."""
        import xarray as xr

        data = {}
        for name, (dims, units, long_name) in _XARRAY.items():
            value = np.asarray(getattr(self, name))
            data[_XR_NAME.get(name, name)] = xr.Variable(
                dims, value.reshape([_size(self, d) for d in dims]),
                {"units": units, "long_name": long_name})
        coords = {"time": ("time", np.asarray(self.t, float), {"units": "s", "long_name": "time"}),
                  "line": ("line", np.array(self.line_names, dtype=str)),
                  "body": ("body", np.array(self.body_names, dtype=str)),
                  "point": ("point", np.array(self.point_names, dtype=str)),
                  "node": np.arange(len(self.points)),
                  "element": np.arange(len(self.line_of_cell)),
                  "dof": list(BODY_DOFS), "axis": ["x", "y", "z"], "end": ["A", "B"],
                  "load": list(LOAD_COMPONENTS)}
        return xr.Dataset(data, coords=coords, attrs={
            "title": "skmoor results", "depth": float(self.depth), "depth_units": "m",
            "meta": json.dumps(self.meta, default=_jsonable)})

    @classmethod
    def from_xarray(cls, ds) -> Results:
        """Results from a Dataset made by :meth:`to_xarray` (or read from ``results.nc``)."""
        kw = {name: np.asarray(ds[_XR_NAME.get(name, name)].values) for name in _XARRAY}
        kw["t"] = np.asarray(ds["time"].values, float)
        kw["cells"] = kw["cells"].astype(int)
        kw["line_of_cell"] = kw["line_of_cell"].astype(int)
        for key, dim in (("line_names", "line"), ("body_names", "body"),
                         ("point_names", "point")):
            kw[key] = [str(s) for s in ds[dim].values]
        kw["depth"] = float(ds.attrs["depth"])
        kw["meta"] = json.loads(ds.attrs.get("meta", "{}"))
        return cls(**kw)

    def to_netcdf(self, path) -> Path:
        """Write :meth:`to_xarray` as netCDF-4 (h5netcdf, the arrays deflated) to ``path``;
        returns the path."""
        path = Path(path)
        ds = self.to_xarray()
        encoding = {name: {"zlib": True, "complevel": 4} for name, var in ds.data_vars.items()
                    if var.size and var.ndim}
        ds.to_netcdf(path, engine="h5netcdf", encoding=encoding)
        return path

    def to_dataframe(self):
        """The time series as a :class:`pandas.DataFrame` indexed by time (s), the columns
        of ``timeseries.csv``: each body's six DOFs ``BODY.surge`` ... (m, rad),
        ``max_tension``, ``fairlead_tension_LINE`` and ``anchor_tension_LINE`` (N) and each
        point's displacement ``POINT.x`` ... (m)."""
        import pandas as pd

        columns = {}
        for k, body in enumerate(self.body_names):
            for j, dof in enumerate(BODY_DOFS):
                columns[f"{body}.{dof}"] = self.bodies[:, k, j]
        columns["max_tension"] = self.max_tension
        for k, line in enumerate(self.line_names):
            columns[f"fairlead_tension_{line}"] = self.fairlead_tension[:, k]
        for k, line in enumerate(self.line_names):
            columns[f"anchor_tension_{line}"] = self.anchor_tension[:, k]
        for k, point in enumerate(self.point_names):
            for j, c in enumerate("xyz"):
                columns[f"{point}.{c}"] = self.point_displacement[:, k, j]
        return pd.DataFrame(columns, index=pd.Index(np.asarray(self.t, float), name="t"))

    @classmethod
    def load(cls, path) -> Results:
        """Read a file written by :meth:`save` (``.npz``) or :meth:`to_netcdf` (``.nc``)."""
        if Path(path).suffix == ".nc":
            import xarray as xr

            with xr.open_dataset(Path(path), engine="h5netcdf") as ds:
                return cls.from_xarray(ds.load())
        with np.load(Path(path), allow_pickle=False) as data:
            kw = {f.name: data[f.name] for f in fields(cls)
                  if f.name not in ("meta", "depth") + _NAMES and f.name in data}
            kw["depth"] = float(data["depth"])
            for key in _NAMES:
                kw[key] = [str(s) for s in data[key]] if key in data else []
            kw["meta"] = json.loads(str(data["meta"]))
        return cls(**kw)


_TIME_ARRAYS = ("t", "body", "displacement", "velocity", "tension", "strain",
                "fairlead_tension", "anchor_tension", "bodies", "point_displacement",
                "curvature", "bending_moment", "coupled_loads")
_NAMES = ("line_names", "body_names", "point_names")

#: the six components of a body's load: force (N) and moment (N m)
LOAD_COMPONENTS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")

# field: (dimensions, units, long name) of the netCDF / xarray form
_XARRAY = {
    "body": (("time", "dof"), "m, rad", "first body's displacement from its reference "
             "(surge, sway, heave in m; roll, pitch, yaw in rad)"),
    "points": (("node", "axis"), "m", "reference (static) node position"),
    "cells": (("element", "end"), "1", "element connectivity: node of end A and end B"),
    "line_of_cell": (("element",), "1", "line index of the element"),
    "displacement": (("time", "node", "axis"), "m", "node displacement from the reference"),
    "velocity": (("time", "node", "axis"), "m s-1", "node velocity"),
    "tension": (("time", "element"), "N", "element tension"),
    "strain": (("time", "element"), "1", "element strain relative to the reference"),
    "fairlead_tension": (("time", "line"), "N", "tension at end B (fairlead)"),
    "anchor_tension": (("time", "line"), "N", "tension at end A (anchor)"),
    "body_center": (("axis",), "m", "reference point of the drawn body"),
    "body_box": (("axis",), "m", "box size of the drawn body (zeros: none)"),
    "body_box_center": (("axis",), "m", "box centre relative to the body's reference point"),
    "body_reference": (("body", "axis"), "m", "reference point of each body"),
    "bodies": (("time", "body", "dof"), "m, rad", "each body's displacement from its "
               "reference (surge, sway, heave in m; roll, pitch, yaw in rad)"),
    "point_reference": (("point", "axis"), "m", "point position in the reference state"),
    "point_displacement": (("time", "point", "axis"), "m", "point displacement"),
    "curvature": (("time", "element"), "m-1", "curvature at the element mid-point"),
    "bending_moment": (("time", "element"), "N m", "bending moment at the element mid-point"),
    "coupled_loads": (("time", "body", "load"), "N, N m", "force and moment each coupled "
                      "body passes to the caller"),
}
# variables renamed in the Dataset (a variable may not share its name with a dimension)
_XR_NAME = {"body": "body_displacement", "points": "node_reference",
            "line_of_cell": "element_line", "cells": "element_nodes"}


def _size(results, dim) -> int:
    return {"time": len(results.t), "line": len(results.line_names),
            "node": len(results.points), "element": len(results.line_of_cell),
            "body": len(results.body_names), "dof": 6, "point": len(results.point_names),
            "axis": 3, "end": 2, "load": 6}[dim]


def _jsonable(x):
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    return str(x)
