"""XDMF and VTU/PVD output, read back with meshio and pyvista."""
import dataclasses

import meshio
import numpy as np
import pytest
from _synthetic import synthetic_results

from skmoor.post.export import (
    box_points,
    export,
    write_mode_series,
    write_vtu_series,
    write_xdmf,
)


@pytest.fixture(scope="module")
def results():
    return synthetic_results()


def test_xdmf_round_trip_with_h5_beside_it(results, tmp_path, monkeypatch):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    path = write_xdmf(results, tmp_path / "out" / "lines.xdmf")
    assert path == tmp_path / "out" / "lines.xdmf"
    assert (tmp_path / "out" / "lines.h5").is_file()
    assert list(elsewhere.iterdir()) == []
    monkeypatch.chdir(tmp_path)                        # read from yet another directory
    with meshio.xdmf.TimeSeriesReader(path) as reader:
        points, cells = reader.read_points_cells()
        assert reader.num_steps == len(results.t)
        np.testing.assert_array_equal(points, results.points)
        assert [c.type for c in cells] == ["line"]
        np.testing.assert_array_equal(cells[0].data, results.cells)
        for k in range(reader.num_steps):
            t, point_data, cell_data = reader.read_data(k)
            assert t == results.t[k]
            assert set(point_data) == {"displacement", "velocity"}
            assert {"tension", "strain"} <= set(cell_data)
            np.testing.assert_allclose(point_data["displacement"], results.displacement[k],
                                       rtol=1e-14, atol=1e-14)
            np.testing.assert_allclose(point_data["velocity"], results.velocity[k], rtol=1e-14)
            np.testing.assert_allclose(cell_data["tension"][0], results.tension[k], rtol=1e-14)
            np.testing.assert_allclose(cell_data["strain"][0], results.strain[k], rtol=1e-14)


def test_pvd_series_read_by_pyvista(results, tmp_path):
    import pyvista as pv

    pvd = write_vtu_series(results, tmp_path)
    assert isinstance(pv.read(pvd), pv.MultiBlock)
    reader = pv.PVDReader(pvd)
    np.testing.assert_array_equal(reader.time_values, results.t)
    for i in (0, 7, len(results.t) - 1):
        reader.set_active_time_value(reader.time_values[i])
        lines, body = reader.read()
        np.testing.assert_allclose(lines.points, results.positions(i), rtol=1e-14)
        np.testing.assert_allclose(lines.point_data["displacement"], results.displacement[i],
                                   rtol=1e-14, atol=1e-14)
        np.testing.assert_allclose(lines.point_data["velocity"], results.velocity[i],
                                   rtol=1e-14, atol=1e-14)
        np.testing.assert_allclose(lines.cell_data["tension"], results.tension[i], rtol=1e-14)
        np.testing.assert_allclose(lines.cell_data["strain"], results.strain[i], rtol=1e-14)
        assert body.n_points == 8 and body.n_cells == 6
        np.testing.assert_allclose(body.points, box_points(results, i), rtol=1e-14)


def test_pvd_blocks_are_named_after_what_they_hold(results, tmp_path):
    """ParaView names a PVD part's block after its DataSet's ``name``: the lines, the
    drawn body (the first dynamic one) and the points, not Block-00..02."""
    import dataclasses
    import xml.etree.ElementTree as ET

    named = dataclasses.replace(
        results, body_names=["hull", "tower"], body_reference=np.zeros((2, 3)),
        bodies=np.zeros((len(results.t), 2, 6)),
        meta={**results.meta, "body_kinds": ["fixed", "dynamic"]},
        point_names=["anchor", "fairlead"], point_reference=np.zeros((2, 3)),
        point_displacement=np.zeros((len(results.t), 2, 3)))
    pvd = write_vtu_series(named, tmp_path, samples=[0, 1])
    names = {(d.get("part"), d.get("name")) for d in ET.parse(pvd).iter("DataSet")}
    assert names == {("0", "lines"), ("1", "tower"), ("2", "points")}


def test_box_moves_rigidly(results):
    for i in (0, 5, 20):
        corners = box_points(results, i)
        u = results.body[i]
        np.testing.assert_allclose(corners.mean(axis=0), results.body_center + u[:3], atol=1e-12)
        edges = np.linalg.norm(corners[[1, 2, 4]] - corners[0], axis=1)
        np.testing.assert_allclose(edges, results.body_box, rtol=1e-12)
    with pytest.raises(ValueError, match="i=41"):
        box_points(results, 41)


def test_export_writes_both(results, tmp_path):
    xdmf, pvd = export(results, tmp_path / "run")
    assert xdmf == tmp_path / "run" / "lines.xdmf" and pvd == tmp_path / "run" / "motion.pvd"
    assert xdmf.is_file() and xdmf.with_suffix(".h5").is_file() and pvd.is_file()
    assert len(list((tmp_path / "run" / "motion").glob("*.vtu"))) == 2 * len(results.t)


def test_no_box_no_body_files(results, tmp_path):
    import pyvista as pv

    pvd = write_vtu_series(dataclasses.replace(results, body_box=np.zeros(3)), tmp_path)
    assert not list((tmp_path / "motion").glob("body_*"))
    assert pv.PVDReader(pvd).read().n_blocks == 1


def test_mode_series(results, tmp_path):
    import pyvista as pv

    shape = np.zeros_like(results.points)
    shape[:, 1] = np.linspace(0, 1, len(shape))
    pvd = write_mode_series(results.points, results.cells, shape, 4.0, tmp_path, n_frames=8,
                            scale=3.0)
    reader = pv.PVDReader(pvd)
    np.testing.assert_allclose(reader.time_values, 0.5 * np.arange(8))
    reader.set_active_time_point(2)                    # a quarter period: sin = 1
    mesh = reader.read()[0]
    np.testing.assert_allclose(mesh.point_data["displacement"], 3.0 * shape, atol=1e-12)
    np.testing.assert_allclose(mesh.points, results.points + 3.0 * shape, atol=1e-12)


@pytest.mark.parametrize("kwargs, message", [
    (dict(shape=np.zeros((3, 3))), "shape must be"),
    (dict(period=0.0), "period"),
    (dict(n_frames=0), "n_frames"),
])
def test_mode_series_bad_input(results, tmp_path, kwargs, message):
    args = dict(points=results.points, cells=results.cells,
                shape=np.ones_like(results.points), period=2.0, folder=tmp_path)
    with pytest.raises(ValueError, match=message):
        write_mode_series(**{**args, **kwargs})


def test_xdmf_bad_suffix(results, tmp_path):
    with pytest.raises(ValueError, match=".xdmf"):
        write_xdmf(results, tmp_path / "lines.xmf")


def test_a_network_without_lines_exports_no_empty_line_file(tmp_path):
    """A coupled body with a point and no line: the VTU series is written, lines.xdmf
    (which would hold no mesh) is not, and export says so with None."""
    import skmoor
    from skmoor.coupling.network import Body, Network, Point

    network = Network([Point("p", "body", [1.0, 0.0, 0.0], body="b")], [],
                      [Body("b", "coupled", np.zeros(3))], depth=50.0,
                      motion=lambda t: np.array([0.1 * t, 0, 0, 0, 0, 0]))
    model = skmoor.from_network(network)
    results = skmoor.simulate(model, duration=0.2, dt=0.1, output_interval=0.1,
                              start="given", progress=False)
    xdmf, pvd = export(results, tmp_path / "run")
    assert xdmf is None and not (tmp_path / "run" / "lines.xdmf").exists()
    assert pvd.exists()
