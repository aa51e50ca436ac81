"""The numbers first: ``skmoor run`` prints the summary as a table as soon as the solve
ends, before the ParaView files and the renders; the table shows hand-set numbers."""
import pytest
from _synthetic import synthetic_results

import skmoor
from skmoor.cli import main
from skmoor.run.report import summary_table


def test_summary_table_shows_the_numbers():
    info = {"case": "hand", "draft": 0.896, "natural_periods": [12.5, 4.0],
            "amplitude": {"surge": 1.5, "heave": 0.25, "pitch": 0.0125},
            "max_tension": 2.5e6, "max_tension_steady": 2.0e6,
            "strength": {"C1": {"max_tension": 2.5e6, "MBL": 5e6, "safety_factor": 2.0,
                                "utilisation": 0.5},
                         "C2": {"max_tension": 1.0e6, "MBL": None, "safety_factor": None,
                                "utilisation": None}},
            "fatigue": {"lines": {"C1": {"damage_per_year": 0.02, "life_years": 50.0,
                                         "DEL": {"3": 4.0e5}}}}}
    text = summary_table(info)
    assert "draft: 0.896 m" in text
    assert "natural periods: 12.5, 4 s" in text
    assert "surge 1.5 m, heave 0.25 m, pitch 0.0125 rad" in text
    assert "max tension: 2500 kN (steady 2000 kN)" in text
    c1 = next(line for line in text.splitlines() if line.startswith("C1 "))
    assert c1.split() == ["C1", "2500", "5000", "2", "50", "0.02", "50", "400"]
    c2 = next(line for line in text.splitlines() if line.startswith("C2 "))
    assert c2.split() == ["C2", "1000", "-", "-", "-", "-", "-", "-"]


def test_run_prints_the_table_before_files_and_renders(tmp_path, monkeypatch, capsys):
    import skmoor.cli as cli

    results = synthetic_results(nt=81, t_end=16.0)
    results.meta["line_MBL"] = [4e6] * 4
    monkeypatch.setattr(skmoor, "build", lambda *a, **k: None)
    monkeypatch.setattr(skmoor, "simulate", lambda *a, **k: results)
    monkeypatch.setattr(cli, "_export", lambda *a: print("EXPORTING"))
    monkeypatch.setattr(cli, "_animate", lambda *a, **k: print("RENDERING"))
    monkeypatch.setattr(cli, "_render_in_background", lambda out: print("BACKGROUND"))
    assert main(["run", "--out", str(tmp_path), "--quiet"]) == 0  # renders in the background
    out = capsys.readouterr().out
    assert "RENDERING" not in out
    assert out.index("max tension:") < out.index("EXPORTING") < out.index("BACKGROUND")
    assert main(["run", "--out", str(tmp_path), "--quiet", "--wait"]) == 0  # renders here
    out = capsys.readouterr().out
    assert "BACKGROUND" not in out
    tmax = max(results.tension[:, :11].max(), results.fairlead_tension[:, 0].max(),
               results.anchor_tension[:, 0].max())
    assert f"line1  {tmax / 1e3:.4g}" in out
    assert f"{4e6 / tmax:.3g}" in out
    assert out.index("max tension:") < out.index("EXPORTING") < out.index("RENDERING")
    assert (tmp_path / "strength.png").exists()


@pytest.mark.parametrize("bad", [["--curve", "a", "b"], ["--mbl", "x"]])
def test_fatigue_command_refuses_bad_values(tmp_path, bad, capsys):
    from skmoor.run.outputs import write_outputs

    write_outputs(synthetic_results(), tmp_path)
    assert main(["fatigue", str(tmp_path), *bad]) == 2
    assert "error" in capsys.readouterr().err


def test_run_options_give_a_deck_its_mbl_and_curve():
    """A MoorDyn deck has no MBL: --mbl and --fatigue-curve set them on its lines; the
    static safety factor is the MBL over the static fairlead tension (the reactions')."""
    import argparse
    from pathlib import Path

    from skmoor.cli import _line_data
    from skmoor.post.strength import strength
    from skmoor.run.recorder import static_results

    deck = Path(__file__).parents[2] / "examples" / "decks" / "chain_50m.dat"
    model = skmoor.build(deck)
    names = [line.name for line in model.lines.lines]
    args = argparse.Namespace(mbl=["3e6", f"{names[0]}=2e6"],
                              fatigue_curve=["studless-chain"], d_nom=None)
    _line_data(model, args)
    r = static_results(model)
    assert r.meta["line_MBL"] == [2e6] + [3e6] * (len(names) - 1)
    assert r.meta["line_fatigue_curve"] == ["studless-chain"] * len(names)
    s = strength(r)[names[0]]
    assert s["where"] == "fairlead"
    assert s["safety_factor"] == pytest.approx(2e6 / r.meta["fairlead_tension_static"][0],
                                               rel=1e-9)
    with pytest.raises(ValueError, match="--fatigue-curve"):
        _line_data(model, argparse.Namespace(mbl=None, fatigue_curve=["x=studless-chain"],
                                             d_nom=None))
