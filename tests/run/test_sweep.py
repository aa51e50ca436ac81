"""Parameter studies: CSV, resume, failing points, the Dask path and the paper's trend.

The runs are short (60 s of the paper's case at dt = 0.1 s, 2 real points): the surge
amplitude over the last 5 forcing periods is then within about 1 % of a 200 s run at
dt = 0.05 s (0.729 vs 0.726 m at d/l = 1/45, 0.326 vs 0.322 m at 1/80).
"""
import csv
import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from skmoor import paper_case
from skmoor.run import sweep
from skmoor.run.sweep import (
    COLUMNS,
    Study,
    grid_study,
    paper_studies,
    parse_spec,
    read_studies,
    run_sweep,
    studies_from_args,
)

SETTINGS = dict(duration=60.0, dt=0.1, progress=False)
BAD_SAG = 0.7            # rejected by the case (sag ratio must lie in (0, 0.5))


def studies():
    return [Study("sag", "mooring.sag_ratio", [1 / 45, 1 / 80, BAD_SAG], paper_case(),
                  fixed={"mooring.chord_angle_deg": 50.0}),
            Study("heavy", "body.mass", [1e9])]      # passes the case, fails in build


@pytest.fixture(scope="module")
def local(tmp_path_factory):
    out = tmp_path_factory.mktemp("local")
    rows = run_sweep(studies(), out, workers=2, **SETTINGS)
    return out, rows


def _read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


# ---------------------------------------------------------------- study descriptions

def test_paper_studies():
    sag, angle = paper_studies(8)
    assert sag.parameter == "mooring.sag_ratio" and angle.parameter == "mooring.chord_angle_deg"
    np.testing.assert_allclose(1 / np.array(sag.values), np.linspace(45, 80, 8))
    assert sag.fixed == {"mooring.chord_angle_deg": 50.0}
    np.testing.assert_allclose(angle.values, [40, 42, 44, 46, 48, 50, 52, 54])
    assert angle.fixed == {"mooring.sag_ratio": 1 / 60}
    case = sag.case(sag.values[-1])
    assert case.get("mooring.sag_ratio") == pytest.approx(1 / 80)
    assert case.get("mooring.chord_angle_deg") == 50.0


def test_specs():
    assert parse_spec("mooring.sag_ratio=1/45, 1/60,0.0125") == (
        "mooring.sag_ratio", [1 / 45, 1 / 60, 0.0125])
    assert parse_spec("mooring.chord_angle_deg=40:54:8")[1] == [40, 42, 44, 46, 48, 50, 52, 54]
    assert parse_spec("mooring.n_elements=5,11")[1] == [5, 11]
    np.testing.assert_allclose(parse_spec("a.b=0.5:1:3")[1], [0.5, 0.75, 1.0])
    assert parse_spec("solver.scheme=newmark,generalized-alpha")[1] == [
        "newmark", "generalized-alpha"]
    for bad in ("mooring.sag_ratio", "=1,2", "a.b=1:2", "a.b=1:2:x", "a.b=1,,2"):
        with pytest.raises(ValueError):
            parse_spec(bad)
    study = Study.from_spec("mooring.sag_ratio=1/45,1/80")
    assert study.name == "sag_ratio" and len(study.values) == 2


def test_typo_in_path_is_caught():
    with pytest.raises(ValueError, match="did you mean 'mooring.sag_ratio'"):
        Study("s", "mooring.sag_raito", [0.02])
    with pytest.raises(ValueError, match="did you mean 'mooring'"):
        Study("s", "moorng.sag_ratio", [0.02])
    Study("s", "lines.0.sag_ratio", [0.02])                  # a per-line override: allowed


def test_grid_covers_all_combinations():
    grid = grid_study("g", {"mooring.sag_ratio": [1 / 45, 1 / 80],
                            "mooring.chord_angle_deg": [40, 50], "body.mass": [1e5, 1.2e5, 1.4e5]})
    assert len(grid) == 6 and len({s.name for s in grid}) == 6
    combos = {(v, s.fixed["mooring.chord_angle_deg"], s.fixed["body.mass"])
              for s in grid for v in s.values}
    assert len(combos) == 12


def test_study_file(tmp_path):
    shutil.copy(Path(__file__).parents[2] / "examples" / "paper_case.toml", tmp_path / "base.toml")
    (tmp_path / "studies.toml").write_text(
        'base_case = "base.toml"\n'
        '[[study]]\nname = "sag"\nparameter = "mooring.sag_ratio"\nvalues = "1/45:1/80:3"\n'
        'label = "d/l"\n'
        '[[study]]\nname = "angle"\nparameter = "mooring.chord_angle_deg"\nvalues = [40, 54]\n'
        '[[study]]\nname = "g"\n'
        'grid = { mooring.sag_ratio = "1/45,1/80", "mooring.chord_angle_deg" = [40, 50] }\n')
    sag, angle, *grid = read_studies(tmp_path / "studies.toml")
    assert sag.label == "d/l" and sag.values == pytest.approx(np.linspace(1 / 45, 1 / 80, 3))
    assert angle.values == [40, 54]
    assert sag.base_case.data == angle.base_case.data
    assert [s.fixed for s in grid] == [{"mooring.chord_angle_deg": 40},
                                       {"mooring.chord_angle_deg": 50}]
    (tmp_path / "bad.toml").write_text('[[study]]\nname = "x"\nparameter = "a.b"\n')
    with pytest.raises(ValueError, match=r"study\[0\] \(x\): values: missing"):
        read_studies(tmp_path / "bad.toml")


# ---------------------------------------------------------------- running

def test_csv_and_failures(local, capsys):
    out, rows = local
    table = _read_csv(out / "sweep.csv")
    assert tuple(table[0]) == COLUMNS
    assert len(table) == len(rows) == 4
    assert [(r["study"], r["value"]) for r in rows] == [
        ("sag", 1 / 45), ("sag", 1 / 80), ("sag", BAD_SAG), ("heavy", 1e9)]
    good, bad, heavy = rows[:2], rows[2], rows[3]
    for row in good:
        assert row["error"] == ""
        assert all(math.isfinite(row[k]) and row[k] > 0
                   for k in ("surge", "heave", "pitch", "max_tension_steady"))
    assert "sag_ratio" in bad["error"] and math.isnan(bad["surge"])
    assert "sinks" in heavy["error"] and math.isnan(heavy["max_tension_steady"])
    assert table[2]["error"] == bad["error"] and float(table[0]["surge"]) == good[0]["surge"]
    assert len(list((out / "sweep-points").glob("*.json"))) == 2      # failures not kept
    assert (out / "sweep-sag.png").stat().st_size > 1000
    assert not (out / "sweep-heavy.png").exists()                    # no good point


def test_surge_falls_with_sag_ratio(local):
    """The paper (text under Fig. 7): the surge amplitude decreases as d/l decreases from
    1/45 to 1/80 (tauter lines, stiffer mooring)."""
    _, rows = local
    surge_45, surge_80 = rows[0]["surge"], rows[1]["surge"]
    assert surge_80 < 0.8 * surge_45


def test_resume_computes_only_missing_points(local, tmp_path, monkeypatch, capsys):
    out = tmp_path / "out"
    shutil.copytree(local[0], out)
    files = {json.loads(f.read_text())["task"]["value"]: f
             for f in (out / "sweep-points").glob("*.json")}
    kept, removed = files[1 / 80], files[1 / 45]             # 1/45 is the quicker run
    stamp = kept.stat().st_mtime_ns
    removed.unlink()
    calls = []

    def counting(task):
        calls.append(task["value"])
        return sweep_run_point(task)

    sweep_run_point = sweep.run_point
    monkeypatch.setattr(sweep, "run_point", counting)
    rows = run_sweep(studies(), out, workers=1, **SETTINGS)     # in this process: countable
    assert len(calls) == 2                                      # the removed point + 'heavy'
    assert calls == [1 / 45, 1e9]
    assert removed.exists() and kept.stat().st_mtime_ns == stamp
    assert "1 computed, 1 reused, 2 failed" in capsys.readouterr().out
    for new, old in zip(rows, local[1]):
        assert new["error"] == old["error"]
        np.testing.assert_allclose([new[k] for k in COLUMNS[3:7]],
                                   [old[k] for k in COLUMNS[3:7]], rtol=1e-9)


def test_dask_matches_local(local, tmp_path, capsys):
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        rows = run_sweep(studies(), tmp_path, scheduler=cluster.scheduler_address, **SETTINGS)
    line = capsys.readouterr().out.strip().splitlines()[-1]
    assert "2 computed, 0 reused, 2 failed; wall time" in line
    assert [(r["study"], r["value"], r["error"]) for r in rows] == [
        (r["study"], r["value"], r["error"]) for r in local[1]]
    np.testing.assert_allclose([[r[k] for k in COLUMNS[3:7]] for r in rows],
                               [[r[k] for k in COLUMNS[3:7]] for r in local[1]], rtol=1e-9)


def test_studies_from_command_line_args(tmp_path):
    case_file = Path(__file__).parents[2] / "examples" / "paper_case.toml"
    (one,) = studies_from_args(["mooring.sag_ratio=1/45,1/80"], None, str(case_file))
    assert one.name == "sag_ratio" and one.values == [1 / 45, 1 / 80]
    assert one.base_case.data["name"].startswith("Wang")
    grid = studies_from_args(["mooring.sag_ratio=1/45,1/80", "mooring.chord_angle_deg=40:50:2"])
    assert [s.fixed for s in grid] == [{"mooring.chord_angle_deg": 40},
                                       {"mooring.chord_angle_deg": 50}]
    with pytest.raises(ValueError, match="twice"):
        studies_from_args(["a.b=1", "a.b=2"])
