"""Reading and writing line meshes (skmoor.lines.line.read_line_mesh / write_line_mesh) against the
points of meshes/make_line_meshes.py, and the errors of bad meshes and bad line input."""
import importlib.util
from pathlib import Path

import meshio
import numpy as np
import pytest

from skmoor.lines.catenary import solve_catenary
from skmoor.lines.line import Line, LineType, read_line_mesh, write_line_mesh

MESHES = Path(__file__).resolve().parents[2] / "meshes"
ROPE = LineType(EA=1e8, mass=50.0, diameter=0.1)


def generator():
    path = MESHES / "make_line_meshes.py"
    spec = importlib.util.spec_from_file_location("make_line_meshes", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("suffix, points", [("msh", "msh_points"), ("vtu", "vtu_points")])
def test_read_line_mesh_gives_the_generator_points(suffix, points):
    """The stored polylines (gmsh fairlead first; VTU shuffled, partly reversed segments)
    come back anchor first, with arclengths = cumulative chord lengths."""
    expected = getattr(generator(), points)()
    line = read_line_mesh(MESHES / f"line_example.{suffix}", ROPE, tension=5.0)
    np.testing.assert_allclose(line.X, expected, rtol=0, atol=1e-12)
    chords = np.linalg.norm(np.diff(expected, axis=0), axis=1)
    np.testing.assert_allclose(line.s, np.concatenate([[0.0], np.cumsum(chords)]), atol=1e-12)
    assert line.name == "line_example"
    assert np.all(line.tension(line.s) == 5.0)


@pytest.mark.parametrize("suffix", ["vtu", "msh"])
def test_write_and_read_back(tmp_path, suffix):
    """write_line_mesh then read_line_mesh returns the catenary's node positions."""
    cable = solve_catenary([-300.0, 10.0, -100.0], [0.0, 0.0, -2.0], ROPE.weight, ROPE.EA,
                           length=330.0)
    line = Line.from_catenary(cable, ROPE, 9)
    path = write_line_mesh(line, tmp_path / f"cable.{suffix}")
    back = read_line_mesh(path, ROPE)
    np.testing.assert_allclose(back.X, line.X, rtol=0, atol=1e-9)
    assert back.name == "cable"


def test_mesh_without_line_cells(tmp_path):
    """A triangle mesh is refused, naming the missing line cells and what was found."""
    path = tmp_path / "plate.vtu"
    triangle = meshio.Mesh([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]], [("triangle", [[0, 1, 2]])])
    meshio.write(path, triangle)
    with pytest.raises(ValueError, match="no line cells.*triangle"):
        read_line_mesh(path, ROPE)


def test_broken_chain(tmp_path):
    """Two disconnected segments are not one line."""
    path = tmp_path / "broken.vtu"
    points = [[0.0, 0, -10], [1, 0, -9], [5, 0, -5], [6, 0, -4]]
    meshio.write(path, meshio.Mesh(points, [("line", [[0, 1], [2, 3]])]))
    with pytest.raises(ValueError, match="unbroken chain"):
        read_line_mesh(path, ROPE)


@pytest.mark.parametrize("name, value, reason", [
    ("EA", 0.0, "positive"), ("EA", -1e8, "positive"), ("EA", np.nan, "finite"),
    ("mass", 0.0, "positive"), ("mass", -5.0, "positive"), ("mass", np.nan, "finite"),
    ("diameter", 0.0, "positive"), ("diameter", -0.1, "positive"),
    ("diameter", np.nan, "finite"), ("weight", np.nan, "finite"), ("Cd_n", np.inf, "finite"),
])
def test_line_type_rejects_bad_values(name, value, reason):
    """Each bad property raises ValueError naming LineType.<field> and the reason."""
    kwargs = {**dict(EA=1e8, mass=50.0, diameter=0.1), name: value}
    with pytest.raises(ValueError, match=rf"LineType\.{name}: must be {reason}"):
        LineType(**kwargs)


def test_polyline_with_a_repeated_point():
    """A node on top of the previous one is a zero-length element; the message names it."""
    points = [[0.0, 0, -10], [1, 0, -9], [1, 0, -9], [2, 0, -8]]
    with pytest.raises(ValueError, match="node 2 repeats the previous one"):
        Line.from_polyline(points, ROPE)


def test_catenary_line_needs_elements():
    """n_elements = 0 is refused by name."""
    cable = solve_catenary([0.0, 0, -50], [80.0, 0, 0], ROPE.weight, ROPE.EA, length=100.0)
    with pytest.raises(ValueError, match="n_elements: must be >= 1"):
        Line.from_catenary(cable, ROPE, 0)
