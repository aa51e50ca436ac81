"""Results as labelled data: the xarray Dataset and netCDF file keep every field (compared
with the Results they came from, value by value), with units; the DataFrame's columns are
the time series."""
from dataclasses import fields

import numpy as np
import pytest
import xarray as xr
from _synthetic import synthetic_results

from skmoor.post.results import Results
from skmoor.run.outputs import write_outputs


def _same(a, b):
    for f in fields(Results):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray):
            assert np.array_equal(x, y), f.name
            assert x.shape == y.shape, f.name
        else:
            assert x == y, f.name


def test_dataset_dimensions_units_and_round_trip(tmp_path):
    r = synthetic_results()
    r.body_names, r.point_names = ["box"], ["a", "b"]
    r.body_reference = np.array([[0.0, 0.0, -1.0]])
    r.bodies = np.stack([r.body], axis=1)
    r.point_reference = np.arange(6.0).reshape(2, 3)
    r.point_displacement = np.random.default_rng(1).normal(size=(len(r.t), 2, 3))
    r.coupled_loads = np.ones((len(r.t), 1, 6))
    ds = r.to_xarray()
    for dim in ("time", "line", "node", "element", "body", "dof"):
        assert dim in ds.dims
    assert list(ds["dof"].values) == ["surge", "sway", "heave", "roll", "pitch", "yaw"]
    assert list(ds["line"].values) == r.line_names
    assert ds["tension"].dims == ("time", "element")
    assert ds["tension"].attrs["units"] == "N"
    assert ds["fairlead_tension"].sel(line="line2").values.tolist() == \
        r.fairlead_tension[:, 1].tolist()
    assert ds["bodies"].sel(body="box", dof="heave").values.tolist() == \
        r.body[:, 2].tolist()
    for name, var in ds.data_vars.items():
        assert var.attrs["units"] and var.attrs["long_name"], name
    _same(Results.from_xarray(ds), r)
    # netCDF through h5netcdf, opened by xarray as a user would
    path = r.to_netcdf(tmp_path / "results.nc")
    with xr.open_dataset(path) as opened:
        assert opened["tension"].attrs["units"] == "N"
        assert np.array_equal(opened["tension"].values, r.tension)
    _same(Results.load(path), r)


def test_dataframe_columns_are_the_timeseries():
    r = synthetic_results()
    r.body_names, r.bodies = ["box"], r.body[:, None, :].copy()
    df = r.to_dataframe()
    assert df.index.name == "t" and np.array_equal(df.index.values, r.t)
    assert np.array_equal(df["box.heave"].values, r.body[:, 2])
    assert np.array_equal(df["fairlead_tension_line3"].values, r.fairlead_tension[:, 2])
    assert np.array_equal(df["max_tension"].values, r.tension.max(axis=1))


def test_outputs_write_results_nc_and_the_commands_read_it(tmp_path, capsys):
    from skmoor.cli import _load_results, main

    r = synthetic_results(nt=81, t_end=16.0)
    write_outputs(r, tmp_path)
    assert (tmp_path / "results.nc").exists()
    _same(_load_results(tmp_path), r)
    # the fatigue command on results.nc alone
    (tmp_path / "results.npz").unlink()
    assert main(["fatigue", str(tmp_path), "--m", "4"]) == 0
    assert "DEL m=4" in capsys.readouterr().out
    with pytest.raises(FileNotFoundError):
        _load_results(tmp_path / "nowhere")
