"""The command line over the public API: a short run of the paper's case writes its files."""
import json

import pytest

from skmoor.cli import main, parser

SUMMARY_KEYS = {"draft", "fairlead_tension_static", "natural_periods", "amplitude",
                "max_tension", "wall_time", "simulated_time", "steps"}


@pytest.fixture(scope="module")
def short_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("run")
    code = main(["run", "--out", str(out), "--duration", "20", "--no-animation", "--quiet"])
    return code, out


def test_run_writes_summary_timeseries_and_plot(short_run):
    code, out = short_run
    assert code == 0
    info = json.loads((out / "summary.json").read_text())
    assert SUMMARY_KEYS <= set(info)
    assert info["draft"] == pytest.approx(0.896, rel=5e-3)
    assert set(info["amplitude"]) == {"surge", "heave", "pitch"}
    assert info["simulated_time"] == pytest.approx(20.0)
    # the static fairlead tension of every line is the catenary's, the max tension larger
    assert len(info["fairlead_tension_static"]) == 4
    assert info["max_tension"] > max(info["fairlead_tension_static"])
    header = (out / "timeseries.csv").read_text().splitlines()[0].split(",")
    assert header[:8] == ["t", "body.surge", "body.sway", "body.heave", "body.roll",
                          "body.pitch", "body.yaw", "max_tension"]
    assert (out / "time_histories.png").stat().st_size > 10_000
    assert (out / "results.npz").exists()


def test_bad_case_file_is_a_clear_error(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text((__import__("pathlib").Path(__file__).parents[1] / "examples" /
                    "paper_case.toml").read_text().replace("sag_ratio = 0.0166", "sag_ratio = 0.7"))
    assert main(["run", str(bad), "--out", str(tmp_path), "--quiet"]) == 2
    assert "sag_ratio: must lie in (0, 0.5)" in capsys.readouterr().err


def test_every_command_documents_its_options():
    p = parser()
    for command in ("run", "sweep", "export", "render"):
        text = p._subparsers._group_actions[0].choices[command].format_help()
        assert "--" in text or "outdir" in text
