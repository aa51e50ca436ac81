"""A bathymetry in a case file ([seabed] file = a MoorDyn seafloor file, or the grid x, y,
heights) against the analytic sloped plane bed (slope_deg): a grid of the same plane is
the same bed (bilinear patches reproduce a plane exactly), so the bed heights and the
static state of a chain lying partly on it must agree; and the keys are validated."""
import copy

import numpy as np
import pytest

import skmoor
from skmoor.io.case import Case, paper_case
from skmoor.io.schema import validate_case

SLOPE_DEG, DEPTH = 4.0, 100.0
RISE = float(np.tan(np.radians(SLOPE_DEG)))  # the bed rises towards +x
X, Y = [-1500.0, 0.0, 1000.0], [-500.0, 500.0]
HEIGHTS = [[-DEPTH + RISE * x] * len(Y) for x in X]

CHAIN_ON_A_SLOPE = {
    "name": "a chain from an anchor on a slope up to a fixed fairlead",
    "water": {"density": 1025.0, "gravity": 9.81, "depth": DEPTH},
    "line_types": {"chain": {"EA": 1.674e9, "mass": 390.0, "diameter": 0.252}},
    "points": [
        {"name": "anchor", "kind": "fixed", "position": [-500.0, 0.0, -DEPTH - 500.0 * RISE]},
        {"name": "fairlead", "kind": "fixed", "position": [0.0, 0.0, -10.0]},
    ],
    "lines": [{"name": "chain", "type": "chain", "a": "anchor", "b": "fairlead",
               "length": 540.0, "n_elements": 20}],
    "seabed": {"mu_axial": 0.0, "mu_lateral": 0.0},
}


def case_with(**seabed):
    data = copy.deepcopy(CHAIN_ON_A_SLOPE)
    data["seabed"].update(seabed)
    return data


def seafloor_file(path):
    """The grid as a MoorDyn seafloor file: nx ny, the x's, the y's, then x y z a line."""
    rows = [f"{len(X)} {len(Y)}", " ".join(map(str, X)), " ".join(map(str, Y))]
    rows += [f"{x} {y} {HEIGHTS[i][j]!r}" for i, x in enumerate(X) for j, y in enumerate(Y)]
    path.write_text("\n".join(rows) + "\n")
    return path


def static_state(data, directory=None):
    model = skmoor.build(Case(data, directory))
    results = skmoor.static_results(model)
    nodes = results.points + results.displacement[0]
    return model, results.fairlead_tension[0, 0], results.anchor_tension[0, 0], nodes


def test_bathymetry_of_a_plane_is_the_sloped_plane_bed(tmp_path):
    plane = static_state(case_with(slope_deg=SLOPE_DEG))
    grid = static_state(case_with(x=X, y=Y, heights=HEIGHTS))
    from_file = skmoor.build(Case(case_with(file="bed.dat"),
                                  seafloor_file(tmp_path / "bed.dat").parent))
    bed = grid[0].network.seabed
    assert bed.bathymetry is not None and plane[0].network.seabed.bathymetry is None
    xy = np.random.default_rng(0).uniform([X[0], Y[0]], [X[-1], Y[-1]], (20, 2))
    assert np.allclose(bed.height(xy), -DEPTH + RISE * xy[:, 0], atol=1e-9)
    assert np.allclose(from_file.network.seabed.height(xy), bed.height(xy), atol=1e-12)
    nodes = plane[3]
    lying = plane[0].network.seabed.penetration(nodes) > -0.05
    assert 0.2 < lying.mean() < 0.9  # part of the chain lies on the slope, part hangs
    assert grid[1] == pytest.approx(plane[1], rel=1e-6)  # fairlead tension, N
    assert grid[2] == pytest.approx(plane[2], rel=1e-6)  # anchor tension
    assert np.allclose(grid[3], nodes, atol=1e-5)
    # the bed carries part of the chain: hanging free (no bed) it pulls otherwise
    free = {k: v for k, v in case_with().items() if k != "seabed"}
    free["water"] = {**free["water"], "depth": 2 * DEPTH}  # no bed above the anchor
    assert abs(static_state(free)[1] / plane[1] - 1) > 0.01


def test_bathymetry_keys_are_validated():
    for seabed, message in (
            (dict(file="bed.dat", x=X, y=Y, heights=HEIGHTS),
             "seabed.x: give a bathymetry file or the grid x, y, heights, not both"),
            (dict(x=X, y=Y), "seabed.heights: missing"),
            (dict(x=X, y=Y, heights=HEIGHTS, slope_deg=2.0),
             "seabed.slope_deg: give a slope or a bathymetry"),
            (dict(x=X, y=Y, heights="deep"), "seabed.heights: need rows of bed heights")):
        with pytest.raises(ValueError, match=message.replace(".", r"\.").replace("(", r"\(")
                           .replace(")", r"\)")):
            validate_case(case_with(**seabed))
    with pytest.raises(ValueError, match="seabed: bathymetry grid: heights of shape"):
        skmoor.build(Case(case_with(x=X, y=Y, heights=HEIGHTS[:2])))
    with pytest.raises(ValueError, match="seabed: file: no such seafloor file"):
        skmoor.build(Case(case_with(file="missing.dat")))
    data = paper_case().data | {"seabed": {"x": X, "y": Y, "heights": HEIGHTS}}
    with pytest.raises(ValueError, match="seabed: a bathymetry .* needs the network layout"):
        skmoor.build(Case(data))
