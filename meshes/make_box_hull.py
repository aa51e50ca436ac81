"""Write ``box_hull.stl``: the closed, triangulated surface of the paper's box hull.

26 m (x) by 10 m (y) by 5 m (z), centred on the origin (its centre of mass), outward
normals, faces cut into 1 m squares of two triangles each (1760 triangles). Float it
with ``skmoor.body.hull_hydrostatics(path, offset=(0, 0, 2.5 - draft))``.

Run: ``python meshes/make_box_hull.py``
"""
from pathlib import Path

import numpy as np
import pyvista as pv

LENGTH, WIDTH, HEIGHT = 26.0, 10.0, 5.0
SPACING = 1.0


def box_hull() -> pv.PolyData:
    shape = np.array([LENGTH, WIDTH, HEIGHT])
    grid = pv.ImageData(dimensions=tuple(np.rint(shape / SPACING).astype(int) + 1),
                        spacing=(SPACING,) * 3, origin=tuple(-shape / 2))
    surface = grid.extract_surface(algorithm="dataset_surface").triangulate().clean()
    surface = surface.compute_normals(cell_normals=True, point_normals=False,
                                      auto_orient_normals=True)
    surface.clear_data()
    return surface


if __name__ == "__main__":
    hull = box_hull()
    assert hull.is_manifold and np.isclose(hull.volume, LENGTH * WIDTH * HEIGHT)
    path = Path(__file__).with_name("box_hull.stl")
    hull.save(path)
    print(f"wrote {path}: {hull.n_cells} triangles, volume {hull.volume:.1f} m3")
