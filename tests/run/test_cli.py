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
    bad.write_text((__import__("pathlib").Path(__file__).parents[2] / "examples" /
                    "paper_case.toml").read_text().replace("sag_ratio = 0.0166", "sag_ratio = 0.7"))
    assert main(["run", str(bad), "--out", str(tmp_path), "--quiet"]) == 2
    assert "sag_ratio: must lie in (0, 0.5)" in capsys.readouterr().err


COMMANDS = ("run", "sweep", "export", "render")


def squeeze(text):
    """text without any whitespace (argparse re-wraps help lines where it likes)."""
    return "".join(text.split())


def test_every_command_documents_its_options(capsys):
    """``skmoor COMMAND --help`` exits 0 and shows, for every argument of the command,
    its option strings (or name) with its own help text (defaults filled in), and every
    argument has one (an option added without ``help=`` fails here); the command has a
    description; ``skmoor --help`` lists the four commands with their one-line help.
    (The test this replaces asked for "--" in the help, which "-h, --help" always gives.)"""
    p = parser()
    choices = p._subparsers._group_actions[0].choices
    assert set(COMMANDS) <= set(choices)
    with pytest.raises(SystemExit) as stop:
        main(["--help"])
    assert stop.value.code == 0
    top = squeeze(capsys.readouterr().out)
    assert "``" not in top  # reST markup of a docstring is not shown as such
    for command in COMMANDS:
        sub = choices[command]
        assert sub.description and len(sub.description) > 20, command
        with pytest.raises(SystemExit) as stop:
            main([command, "--help"])
        assert stop.value.code == 0
        text = squeeze(capsys.readouterr().out)
        assert squeeze(sub.description) in text, command
        assert "``" not in text, command
        documented = 0
        for action in sub._actions:
            if action.dest == "help":
                continue
            assert action.help and len(action.help) >= 10, f"{command} {action.dest}: no help"
            names = action.option_strings or [action.metavar or action.dest]
            for name in names:
                assert name in text, f"{command}: {name} not in its --help"
            shown = action.help % dict(vars(action), prog=sub.prog)
            assert squeeze(shown) in text, f"{command} {names[0]}: help text not shown"
            documented += 1
        assert documented >= 1, command
        help_line = p._subparsers._group_actions[0]._choices_actions
        summary = next(a.help for a in help_line if a.dest == command)
        assert command in top and squeeze(summary) in top, command


def test_readme_synopsis_matches_the_parser():
    """Every option the README's "Command line" block shows for a command is an option
    of that command (a renamed or dropped option fails here)."""
    import re
    from pathlib import Path

    readme = (Path(__file__).parents[2] / "README.md").read_text()
    block = readme.split("## Command line", 1)[1].split("```", 2)[1]
    choices = parser()._subparsers._group_actions[0].choices
    seen = 0
    for line in block.splitlines():
        match = re.match(r"skmoor (\w+) (.*)", line.strip())
        if not match:
            continue
        command, rest = match.groups()
        known = {s for a in choices[command]._actions for s in a.option_strings}
        for option in re.findall(r"--[a-z][a-z-]*", rest.split("#")[0]):
            assert option in known, f"README: skmoor {command} {option} is not an option"
            seen += 1
    assert seen >= 10, seen
