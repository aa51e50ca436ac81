"""Design-load-case matrices (skmoor.run.load_cases, ``skmoor loadcases``).

The base case is the spar buoy network (examples/network_buoy.toml: MBLs and T-N curves on
its line types); 2 sea states x 2 headings x 1 seed x 2 conditions (intact, leg 1's top
chain released at 1 s), 6 s runs at dt = 0.2 s. Checked: every case is the base case with
its own wave and failures; a case's numbers are those of the same case run alone (largest
tension and damage per year over the window after the transient, by skmoor.post's
strength and fatigue, themselves tested against independent rainflow counts); the
lifetime damage is the probability-weighted sum written out by hand; the broken leg
carries nearly nothing after its release and the buoy drifts from it, slackening the
others; a rerun computes nothing, an interrupted run keeps what finished and a rerun
computes the rest; a Dask cluster on loopback that loses a worker in the middle gives the
same dataset.
"""
import os
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import skmoor
from skmoor import cli
from skmoor.post.fatigue import fatigue
from skmoor.post.strength import strength
from skmoor.run import load_cases
from skmoor.run.load_cases import Condition, LoadCaseMatrix, SeaState, run_load_cases

ROOT = Path(__file__).parents[2]
SETTINGS = dict(duration=6.0, dt=0.2, progress=False)
BROKEN = Condition("leg1 broken", [{"point": "leg1.fairlead", "lines": ["leg1.top"],
                                   "time": 1.0}])


def matrix(**kw):
    base = skmoor.Case.from_toml(ROOT / "examples" / "network_buoy.toml")
    return LoadCaseMatrix([SeaState(2.0, 8.0, 0.6), SeaState(5.0, 11.0, 0.3)],
                          headings_deg=[0.0, 60.0], seeds=[3],
                          conditions=[Condition("intact"), BROKEN], base_case=base,
                          transient=2.0, n_components=20, **kw)


@pytest.fixture(scope="module")
def local(tmp_path_factory):
    out = tmp_path_factory.mktemp("load-cases")
    return out, run_load_cases(matrix(), out, workers=2, **SETTINGS)


def test_each_case_is_the_base_case_with_its_wave_and_failures():
    m = matrix()
    cases = list(m.cases())
    assert len(cases) == m.size == 8
    for (i, j, k, c), case in cases:
        (wave,) = case.data["sea"]["waves"]
        assert (wave["Hs"], wave["Tp"], wave["heading_deg"], wave["seed"]) == (
            m.sea_states[i].Hs, m.sea_states[i].Tp, m.headings_deg[j], m.seeds[k])
        assert case.data.get("failures", []) == m.conditions[c].failures
        assert case.data["lines"] == m.base_case.data["lines"]


def test_a_case_equals_the_same_case_run_alone(local):
    out, data = local
    m = matrix()
    index = (1, 1, 0, 0)  # Hs 5 m, heading 60 deg, intact
    case = dict(m.cases())[index]
    results = skmoor.simulate(skmoor.build(case), duration=6.0, dt=0.2, progress=False)
    peaks = strength(results, start=2.0)
    tired = fatigue(results, start=2.0, where="fairlead")["lines"]
    for name in results.line_names:
        got = data.sel(line=name).isel(sea_state=1, heading=1, seed=0, condition=0)
        assert float(got.max_tension) == pytest.approx(peaks[name]["max_tension"], rel=1e-9)
        assert float(got.damage_per_year) == pytest.approx(tired[name]["damage_per_year"],
                                                           rel=1e-9)
    # the window matters: the full run's largest tension includes the start
    assert data.attrs["transient_s"] == 2.0
    assert (out / "load_cases.nc").is_file() and (out / "load_cases.csv").is_file()


def test_lifetime_damage_is_the_weighted_sum(local):
    _, data = local
    m = matrix()
    rate = data["damage_per_year"].values  # (sea_state, heading, seed, condition, line)
    expected = np.zeros(rate.shape[3:])
    for i, state in enumerate(m.sea_states):
        for j, w in enumerate(m.heading_probabilities):
            expected += state.probability * w * rate[i, j].mean(axis=0)
    np.testing.assert_allclose(data["lifetime_damage"].values, m.design_life * expected,
                               rtol=1e-12)
    assert np.all(np.isfinite(expected)) and expected.max() > 0
    assert data["lifetime_damage"].attrs["units"] == "1"


def test_the_broken_leg_unloads_and_the_others_slacken(local):
    _, data = local
    peaks = data["max_tension"].isel(seed=0)
    assert (data["error"].values == "").all()
    broken = peaks.sel(condition="leg1 broken", line="leg1.top")
    intact = peaks.sel(condition="intact", line="leg1.top")
    assert float(broken.max()) < 0.5 * float(intact.min())
    # leg 1 no longer balances the others' pull: the buoy drifts towards their anchors and
    # they slacken (after 4 s, by a few per cent)
    for other in ("leg2.top", "leg3.top"):
        assert (peaks.sel(condition="leg1 broken", line=other)
                < 0.99 * peaks.sel(condition="intact", line=other)).all()


def test_rerun_reuses_and_interrupt_keeps_what_finished(local, tmp_path, monkeypatch, capsys):
    out, data = local
    again = run_load_cases(matrix(), out, workers=2, **SETTINGS)
    said = capsys.readouterr()
    assert "0 computed, 8 reused, 0 failed" in said.out
    # the cases' warnings once for the matrix (dt 0.2 s is longer than the bed's contact
    # period), not once a case
    warned = [line for line in said.err.splitlines() if "ResolutionWarning" in line]
    assert len(warned) == 1 and "load cases: 8 of 8 warned" in warned[0], said.err
    np.testing.assert_array_equal(again["max_tension"].values, data["max_tension"].values)

    real, calls = load_cases.run_load_case, []

    def stops_at_the_fourth(task):
        calls.append(1)
        if len(calls) == 4:
            raise KeyboardInterrupt
        return real(task)

    monkeypatch.setattr(load_cases, "run_load_case", stops_at_the_fourth)
    with pytest.raises(KeyboardInterrupt):
        run_load_cases(matrix(), tmp_path, workers=1, **SETTINGS)
    assert "3 of 8 cases are kept" in capsys.readouterr().err
    monkeypatch.setattr(load_cases, "run_load_case", real)
    resumed = run_load_cases(matrix(), tmp_path, workers=1, **SETTINGS)
    assert "5 computed, 3 reused, 0 failed" in capsys.readouterr().out
    np.testing.assert_allclose(resumed["max_tension"].values, data["max_tension"].values,
                               rtol=1e-9)


def test_dask_survives_a_killed_worker(local, tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    _, data = local
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        pids = client.run(os.getpid)
        victim = sorted(pids.values())[0]

        def kill_soon():  # once the victim works on a case (build, statics or the run)
            while not any(client.processing().values()):
                time.sleep(0.1)
            time.sleep(1.0)
            os.kill(victim, signal.SIGKILL)

        threading.Thread(target=kill_soon, daemon=True).start()
        got = run_load_cases(matrix(), tmp_path, scheduler=client, **SETTINGS)
        assert victim not in client.run(os.getpid).values()
    assert (got["error"].values == "").all()
    np.testing.assert_allclose(got["max_tension"].values, data["max_tension"].values,
                               rtol=1e-9)


def test_study_file_and_its_errors(tmp_path):
    file = tmp_path / "matrix.toml"
    (tmp_path / "buoy.toml").write_text((ROOT / "examples" / "network_buoy.toml").read_text())
    file.write_text('[load_cases]\ncase = "buoy.toml"\nheadings_deg = [0, 90]\nseeds = [1, 2]\n'
                    'duration = 5.0\ntransient = 1.0\n'
                    'sea_states = [{Hs = 2.0, Tp = 8.0, probability = 0.7},\n'
                    '              {Hs = 4.0, Tp = 10.0, probability = 0.3}]\n'
                    'conditions = [{name = "intact"}]\n')
    m, settings = LoadCaseMatrix.from_toml(file)
    assert m.shape == (2, 2, 2, 1) and settings == {"duration": 5.0}
    assert m.base_case.data["name"].startswith("spar buoy")
    bad = {"probabilities add up to 1.2": "sea_states = [{Hs = 2.0, Tp = 8.0, probability = 0.7},"
                                         " {Hs = 3.0, Tp = 9.0, probability = 0.5}]",
           "Hs must be a number > 0": "sea_states = [{Hs = -2.0, Tp = 8.0, probability = 0.5}]",
           "load_cases.seed: unknown key": "seed = [1]\nsea_states = [{Hs = 2.0, Tp = 8.0, "
                                           "probability = 0.5}]",
           "sea_states: missing": "seeds = [1]"}
    for message, body in bad.items():
        file.write_text(f"[load_cases]\n{body}\n")
        with pytest.raises(ValueError, match=message):
            LoadCaseMatrix.from_toml(file)
    file.write_text("[load_cases]\ncase = \"../../../etc/passwd\"\n")
    with pytest.raises(ValueError, match="load_cases.case: '../../../etc/passwd' leads out"):
        LoadCaseMatrix.from_toml(file)
    file.write_text("[load_cases]\nsea_states = [{Hs = 2.0, Tp = 8.0, probability = 0.5}]\n"
                    'conditions = [{name = "broken", failures = [{point = "nowhere", '
                    'lines = ["C1"], time = 1.0}]}]\n')
    with pytest.raises(ValueError, match="load case .*broken.*failures"):
        list(LoadCaseMatrix.from_toml(file)[0].cases())
    file.write_text("[load_cases\n")
    assert cli.main(["loadcases", str(file), "--quiet"]) == 2
