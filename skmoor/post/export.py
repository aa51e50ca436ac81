"""Lines, body and network points over time as files for ParaView: XDMF (meshio) and
VTU + PVD series.

Arrays written on the lines, SI: point data ``displacement`` (m) and ``velocity`` (m/s),
cell data ``tension`` (N), ``strain`` (-) and ``line`` (line index of the element); with
bending lines also ``curvature`` (1/m) and ``bending_moment`` (N m).

The network's points (anchors, junctions, clump weights, fairleads: ``results.point_names``)
go into the VTU series as a third part, one vertex per point, with point data ``index``
(the point's index in ``results.point_names``), ``kind`` (:data:`POINT_KINDS`: 0 fixed,
1 free, 2 coupled, 3 on a body; -1 unknown), ``displacement`` (m, from
``results.point_reference``) and ``mass`` (kg, from ``results.meta["point_masses"]``
when the run has it, else 0). In ``motion.pvd`` the lines are part 0, the body's box
part 1 and the points part 2 (``motion/lines_*.vtu``, ``body_*.vtu``, ``points_*.vtu``),
named ``lines``, the body's name and ``points`` (ParaView's block names);
ParaView shows the points with the Point Gaussian representation or the Glyph filter.
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import meshio
import numpy as np

from ..bodies.body import rotation_matrix

POINT_KINDS = ("fixed", "free", "coupled", "body")  # codes 0..3 of the point data 'kind'
# the 6 faces of a box whose 8 corners are numbered by bits (x, y, z) = (i & 1, i & 2, i & 4)
BOX_FACES = np.array([[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4],
                      [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]])


def box_points(results, i: int, scale: float = 1.0) -> np.ndarray:
    """(8, 3) corners of the body's box at sample ``i``, m (see :data:`BOX_FACES`).

    ``scale`` multiplies the body displacement (translation and angles)."""
    _check_index(results, i)
    bits = (np.arange(8)[:, None] >> np.arange(3)) & 1
    local = results.body_box_center + (bits - 0.5) * results.body_box
    u = scale * np.asarray(results.body[i], dtype=float)
    return results.body_center + u[:3] + local @ rotation_matrix(u[3:]).T


def has_box(results) -> bool:
    """True when the results carry a box to draw."""
    return bool(np.all(np.asarray(results.body_box) > 0))


MAX_FRAMES = 1000  # default: a ParaView series of at most this many samples


def frames(results, max_frames=MAX_FRAMES) -> np.ndarray:
    """Sample indices of a series of at most ``max_frames`` (evenly strided, the last
    sample always in); None for every sample."""
    n = len(results.t)
    if max_frames is None:
        return np.arange(n)
    if isinstance(max_frames, bool) or not isinstance(max_frames, (int, np.integer)) or max_frames < 1:
        raise ValueError(f"max_frames: must be a whole number >= 1 (or None), got {max_frames!r}")
    picked = np.arange(0, n, max(1, int(np.ceil(n / max_frames))))
    return picked if picked[-1] == n - 1 else np.append(picked, n - 1)


def write_xdmf(results, path, samples=None) -> Path:
    """XDMF time series of the lines at ``path`` (``.xdmf``), its ``.h5`` beside it.

    Points are the reference positions; move them by ``displacement`` (ParaView: Warp By
    Vector). One step per sample (``samples``: the indices, default all), time in s.
    Returns the path of the ``.xdmf``."""
    path = Path(path)
    if path.suffix != ".xdmf":
        raise ValueError(f"write_xdmf: path must end in .xdmf, got {path.name!r}")
    path.parent.mkdir(parents=True, exist_ok=True)
    samples = range(len(results.t)) if samples is None else samples
    with _TimeSeriesWriter(path) as writer:
        writer.write_points_cells(results.points, [("line", results.cells)])
        for i in samples:
            t = results.t[i]
            writer.write_data(float(t), point_data=_point_data(results, i),
                              cell_data=_cell_data(results, i))
    return path


def write_vtu_series(results, folder, samples=None) -> Path:
    """One VTU of the moved lines per sample (``samples``: the indices, default all), of
    the body's box when it has one and of the network's points when the results have them
    (see the module docstring), in ``folder/motion/`` (cleared of earlier frames first),
    indexed by ``folder/motion.pvd`` (parts 0, 1, 2: lines, body, points; ParaView's blocks
    named ``lines``, the body's name and ``points``). Returns the
    path of the PVD."""
    folder = Path(folder)
    (folder / "motion").mkdir(parents=True, exist_ok=True)
    for old in (folder / "motion").glob("*.vtu"):
        old.unlink()
    entries = []
    points = _network_points(results)
    dynamic = [n for n, k in zip(results.body_names, results.meta.get("body_kinds", []))
               if k == "dynamic"]
    body_name = (dynamic or list(results.body_names) or ["body"])[0]
    samples = range(len(results.t)) if samples is None else samples
    for i in samples:
        t = results.t[i]
        name = f"motion/lines_{i:04d}.vtu"
        meshio.write(folder / name, meshio.Mesh(
            results.positions(i), [("line", results.cells)],
            point_data=_point_data(results, i), cell_data=_cell_data(results, i)))
        entries.append((t, 0, name, "lines"))
        if has_box(results):
            name = f"motion/body_{i:04d}.vtu"
            meshio.write(folder / name, meshio.Mesh(box_points(results, i), [("quad", BOX_FACES)]))
            entries.append((t, 1, name, body_name))
        if points is not None:
            name = f"motion/points_{i:04d}.vtu"
            displacement = np.asarray(results.point_displacement[i], float)
            meshio.write(folder / name, meshio.Mesh(
                results.point_reference + displacement, [("vertex", points["vertices"])],
                point_data={**points["data"], "displacement": displacement}))
            entries.append((t, 2, name, "points"))
    return _write_pvd(folder / "motion.pvd", entries)


def _network_points(results):
    """The constant part of the points' VTU (vertices and point data), None without points."""
    n = len(results.point_names)
    if n == 0:
        return None
    kinds = list(results.meta.get("point_kinds", []))
    codes = [POINT_KINDS.index(k) if k in POINT_KINDS else -1 for k in kinds]
    masses = results.meta.get("point_masses")
    return {"vertices": np.arange(n).reshape(-1, 1),
            "data": {"index": np.arange(n, dtype=np.int32),
                     "kind": np.array(codes if len(codes) == n else [-1] * n, np.int32),
                     "mass": (np.asarray(masses, float) if masses is not None
                              and len(masses) == n else np.zeros(n))}}


def export(results, outdir, max_frames=MAX_FRAMES) -> tuple[Path | None, Path]:
    """Write ``outdir/lines.xdmf`` (+ ``.h5``) and ``outdir/motion.pvd`` (+ ``motion/``),
    at most ``max_frames`` samples each (evenly strided; None: every sample).

    Returns the paths of the ``.xdmf`` (None for a network without lines: no file, it
    would hold no mesh) and the ``.pvd``."""
    outdir = Path(outdir)
    samples = frames(results, max_frames)
    lines = (write_xdmf(results, outdir / "lines.xdmf", samples) if len(results.cells)
             else None)
    return lines, write_vtu_series(results, outdir, samples)


def write_mode_series(points, cells, shape, period, folder, n_frames=24, scale=None,
                      name="mode") -> Path:
    """One period of a mode shape as ``folder/<name>.pvd`` + ``folder/<name>/*.vtu``.

    points (nnodes, 3) reference positions, m; cells (nel, 2); shape (nnodes, 3);
    period in s. Frame k at t = k period / n_frames shows points + scale shape sin(2 pi t /
    period). ``scale=None`` makes the largest displacement 5 % of the model's size.
    Point data ``displacement`` (m) and ``shape``. Returns the path of the PVD."""
    points, cells, shape = _check_mode(points, cells, shape, period, n_frames)
    scale = mode_scale(points, shape) if scale is None else float(scale)
    folder = Path(folder)
    (folder / name).mkdir(parents=True, exist_ok=True)
    entries = []
    for k in range(n_frames):
        t = k * period / n_frames
        u = scale * np.sin(2 * np.pi * k / n_frames) * shape
        file = f"{name}/{name}_{k:04d}.vtu"
        meshio.write(folder / file, meshio.Mesh(points + u, [("line", cells)],
                                                point_data={"displacement": u, "shape": shape}))
        entries.append((t, 0, file, name))
    return _write_pvd(folder / f"{name}.pvd", entries)


def mode_scale(points, shape) -> float:
    """Scale factor that makes the largest mode displacement 5 % of the model's size."""
    size = np.linalg.norm(np.ptp(points, axis=0))
    return 0.05 * size / np.linalg.norm(shape, axis=1).max()


def _check_mode(points, cells, shape, period, n_frames):
    points = np.asarray(points, dtype=float)
    shape = np.asarray(shape, dtype=float)
    cells = np.asarray(cells)
    if points.ndim != 2 or points.shape[1] != 3:
        raise ValueError(f"points must be (nnodes, 3), got shape {points.shape}")
    if shape.shape != points.shape:
        raise ValueError(f"shape must be (nnodes, 3) = {points.shape}, got {shape.shape}")
    if not np.any(shape):
        raise ValueError("shape is all zeros")
    if cells.ndim != 2 or cells.shape[1] != 2:
        raise ValueError(f"cells must be (nel, 2), got shape {cells.shape}")
    if not period > 0:
        raise ValueError(f"period must be > 0 s, got {period}")
    if n_frames < 1:
        raise ValueError(f"n_frames must be >= 1, got {n_frames}")
    return points, cells, shape


def _check_index(results, i):
    if not -len(results.t) <= i < len(results.t):
        raise ValueError(f"sample index i={i} out of range for {len(results.t)} samples")
    return i


def _point_data(results, i):
    return {"displacement": results.displacement[i], "velocity": results.velocity[i]}


def _cell_data(results, i):
    data = {"tension": [results.tension[i]], "strain": [results.strain[i]],
            "line": [np.asarray(results.line_of_cell, dtype=np.int32)]}
    if results.bending:
        data.update(curvature=[results.curvature[i]], bending_moment=[results.bending_moment[i]])
    return data


def _write_pvd(path, entries):
    """PVD index of (time s, part, relative file, name) entries: ParaView names each
    part's block after its ``name`` attribute."""
    root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
    collection = ET.SubElement(root, "Collection")
    for t, part, file, name in entries:
        ET.SubElement(collection, "DataSet", timestep=repr(float(t)), group="",
                      part=str(part), name=name, file=file)
    ET.indent(root)
    ET.ElementTree(root).write(path, xml_declaration=True, encoding="utf-8")
    return Path(path)


class _TimeSeriesWriter(meshio.xdmf.TimeSeriesWriter):
    """meshio's writer with the .h5 beside the .xdmf: meshio opens it in the current
    directory. No chdir, so it is safe in threads."""

    def __enter__(self):
        self.h5_filename = str(self.filename.with_suffix(".h5"))
        self.h5_file = h5py.File(self.h5_filename, "w")
        return self
