"""Write ``line_example.msh`` (gmsh 2.2 ASCII) and ``line_example.vtu``: two small polylines.

Both are stress-free mooring-line shapes to read with :func:`skmoor.line.read_line_mesh`
(anchor = the end with the lower z):

- ``line_example.msh``: 11 segments on a parabola in the vertical plane y = 0, anchor at
  (-80, 0, -100), fairlead at (0, 0, -1). The points are stored fairlead first, so the
  reader has to turn the chain around.
- ``line_example.vtu``: 8 segments on a 3D curve (plan direction along the diagonal of the
  first quadrant), anchor at (50, 50, -60), fairlead at (5, 3, -2). The segments are stored
  shuffled and some of them reversed, so the reader has to rebuild the chain.

``msh_points()`` and ``vtu_points()`` return the points anchor first, as the reader must.

Run: ``python meshes/make_line_meshes.py``
"""
from pathlib import Path

import meshio
import numpy as np

HERE = Path(__file__).resolve().parent


def msh_points() -> np.ndarray:
    """(12, 3) points of the gmsh line, anchor first, m."""
    t = np.linspace(0.0, 1.0, 12)
    anchor, fairlead = np.array([-80.0, 0.0, -100.0]), np.array([0.0, 0.0, -1.0])
    points = anchor + t[:, None] * (fairlead - anchor)
    points[:, 2] -= 10.0 * 4 * t * (1 - t)  # 10 m sag below the chord
    return points


def vtu_points() -> np.ndarray:
    """(9, 3) points of the VTU line, anchor first, m."""
    t = np.linspace(0.0, 1.0, 9)
    anchor, fairlead = np.array([50.0, 50.0, -60.0]), np.array([5.0, 3.0, -2.0])
    points = anchor + t[:, None] * (fairlead - anchor)
    points[:, 2] -= 6.0 * np.sin(np.pi * t)
    points[:, 0] += 2.0 * np.sin(2 * np.pi * t)  # out of the vertical plane
    return points


def write_msh(path=HERE / "line_example.msh") -> Path:
    points = msh_points()[::-1]  # stored fairlead first
    n = len(points)
    cells = [("line", np.stack([np.arange(n - 1), np.arange(1, n)], axis=1))]
    tags = {"gmsh:physical": [np.ones(n - 1, int)], "gmsh:geometrical": [np.ones(n - 1, int)]}
    meshio.write(path, meshio.Mesh(points, cells, cell_data=tags), file_format="gmsh22",
                 binary=False)
    return Path(path)


def write_vtu(path=HERE / "line_example.vtu") -> Path:
    points = vtu_points()
    n = len(points)
    segments = np.stack([np.arange(n - 1), np.arange(1, n)], axis=1)
    rng = np.random.default_rng(7)
    segments = segments[rng.permutation(n - 1)]
    flip = rng.random(n - 1) < 0.5
    segments[flip] = segments[flip, ::-1]
    meshio.write(path, meshio.Mesh(points, [("line", segments)]))
    return Path(path)


if __name__ == "__main__":
    for path in (write_msh(), write_vtu()):
        print(f"wrote {path}")
