"""Fatigue (skmoor.post.fatigue) against independent numbers: ASTM E1049-85's worked
rainflow example (its table of ranges and counts), a cosine whose cycles are known
exactly, the damage-equivalent load worked by hand, DNV-RP-C203's two slopes meeting at
the switch, and a rainflow count written here from the standard's procedure."""
import json

import numpy as np
import pytest
from _synthetic import NEL, synthetic_results

from skmoor.cli import main
from skmoor.lines.fatigue_curves import CURVES
from skmoor.post.fatigue import (
    YEAR,
    count_cycles,
    damage_equivalent_load,
    fatigue,
    miner_damage,
)
from skmoor.run.outputs import write_outputs

# ASTM E1049-85 (2017), section 5.4.4 and its Table 4: the load history
# -2, 1, -3, 5, -1, 3, -4, 4, -2 counts these ranges (units) and cycles
ASTM_SERIES = [-2, 1, -3, 5, -1, 3, -4, 4, -2]
ASTM_TABLE = {3: 0.5, 4: 1.5, 6: 0.5, 8: 1.0, 9: 0.5}


def _histogram(ranges, counts):
    table = {}
    for r, c in zip(ranges, counts):
        table[float(r)] = table.get(float(r), 0.0) + float(c)
    return table


def test_astm_e1049_worked_example():
    assert _histogram(*count_cycles(ASTM_SERIES)) == ASTM_TABLE


def test_damage_and_del_of_the_astm_history_by_hand():
    ranges, counts = count_cycles(1e6 + 1e5 * np.array(ASTM_SERIES, float))
    # studless chain, DNV-OS-E301: N = 6.0e10 s^-3, s in MPa on a 0.1 m nominal bar
    area = np.pi * 0.1**2 / 4
    by_hand = sum(n * (r * 1e5 / area / 1e6)**3 / 6.0e10 for r, n in ASTM_TABLE.items())
    assert miner_damage(ranges, counts, "studless-chain", d_nom=0.1) == pytest.approx(
        by_hand, rel=1e-12)
    # DEL_3 over 8 s at 1 Hz: (0.5 3^3 + 1.5 4^3 + 0.5 6^3 + 1 8^3 + 0.5 9^3) / 8 = 1094 / 8
    assert damage_equivalent_load(ranges, counts, 3, 8.0) == pytest.approx(
        (1094 / 8)**(1 / 3) * 1e5, rel=1e-12)
    # polyester: N = 0.259 R^-13.46 with R the range over the MBL
    r, n = count_cycles([0.0, 2e6, 0.0])
    assert miner_damage(r, n, "polyester-rope", mbl=1e7) == pytest.approx(
        1 / (0.259 * 0.2**-13.46), rel=1e-12)


def test_rp_c203_two_slopes_meet_at_the_switch():
    for c in CURVES.values():
        if c.switch is None:
            continue
        (m1, a1), (m2, a2) = c.slopes
        s_switch = 10**((a1 - np.log10(c.switch)) / m1)
        assert a2 - m2 * np.log10(s_switch) == pytest.approx(np.log10(c.switch), abs=0.01), c.name
    # D in air, 100 MPa: log N = 12.164 - 3 log 100; 20 MPa: under the switch, 15.606 - 5 log 20
    d = CURVES["dnv-c203-D-air"]
    assert d.cycles(100.0) == pytest.approx(10**6.164, rel=1e-12)
    assert d.cycles(20.0) == pytest.approx(10**(15.606 - 5 * np.log10(20.0)), rel=1e-12)


def _cosine_results(k=5, period=2.0, amplitude=2e5):
    """Every element's tension 1 MN + amplitude cos(2 pi t / period) over k periods."""
    r = synthetic_results(nt=40 * k + 1, t_end=k * period)
    wave = 1e6 + amplitude * np.cos(2 * np.pi * r.t / period)
    r.tension[:] = wave[:, None] * np.tile(np.linspace(1.0, 1.1, NEL), 4)
    r.fairlead_tension[:] = wave[:, None]
    r.meta.update({"line_fatigue_curve": ["studless-chain", "spiral-strand-rope", None, None],
                   "line_d_nom": [0.1] * 4})
    return r


def test_cosine_cycles_damage_per_year_and_design_life():
    k, period, amplitude = 5, 2.0, 2e5
    r = _cosine_results(k, period, amplitude)
    report = fatigue(r, m=(3, 5), design_life=20)
    area = np.pi * 0.1**2 / 4
    last = 1.1                               # the last element of each line: the largest range
    row = report["lines"][r.line_names[0]]
    # k cycles of range 2 amplitude on the studless chain curve
    expected = k * (2 * amplitude * last / area / 1e6)**3 / 6.0e10
    assert row["damage"] == pytest.approx(expected, rel=1e-9)
    assert row["element"] == NEL - 1
    assert report["duration"] == pytest.approx(k * period)
    assert row["damage_per_year"] == pytest.approx(expected * YEAR / (k * period), rel=1e-9)
    assert row["damage_design_life"] == pytest.approx(20 * row["damage_per_year"], rel=1e-12)
    assert row["life_years"] == pytest.approx(1 / row["damage_per_year"], rel=1e-12)
    # DEL at 1 Hz: k cycles of 2 amplitude over k period seconds
    for m in (3, 5):
        assert row["DEL"][str(m)] == pytest.approx(
            2 * amplitude * last * (k / (k * period))**(1 / m), rel=1e-9)
    spiral = report["lines"][r.line_names[1]]
    assert spiral["damage"] == pytest.approx(
        k * (2 * amplitude * last / area / 1e6)**4.8 / 1.7e17, rel=1e-9)
    assert report["lines"][r.line_names[2]]["damage"] is None     # no curve, DEL only
    # a curve given for every line replaces the types'; the fairlead series alone
    fair = fatigue(r, curve="studless-chain", where="fairlead")
    for row in fair["lines"].values():
        assert row["damage"] == pytest.approx(expected / last**3, rel=1e-9)


def _astm_rainflow(x):
    """ASTM E1049-85 5.4.4, written from the standard: (ranges, counts)."""
    x = np.asarray(x, float)
    x = x[np.r_[True, np.diff(x) != 0]]
    keep = [0] + [i for i in range(1, len(x) - 1)
                  if (x[i] - x[i - 1]) * (x[i + 1] - x[i]) < 0] + [len(x) - 1]
    stack, out = [], []
    for point in x[keep]:
        stack.append(point)
        while len(stack) >= 3:
            X, Y = abs(stack[-1] - stack[-2]), abs(stack[-2] - stack[-3])
            if X < Y:
                break
            if len(stack) == 3:
                out.append((Y, 0.5))
                stack.pop(0)
            else:
                out.append((Y, 1.0))
                del stack[-3:-1]
    out += [(abs(b - a), 0.5) for a, b in zip(stack[:-1], stack[1:])]
    return np.array(out).T


def test_skmoor_fatigue_command_equals_an_independent_count(tmp_path, capsys):
    rng = np.random.default_rng(7)
    r = synthetic_results(nt=801, t_end=400.0)
    r.tension[:] = 1e6 + np.cumsum(rng.normal(0, 2e4, r.tension.shape), axis=0)
    r.meta.update({"line_fatigue_curve": [None] * 4, "line_d_nom": [0.1] * 4})
    write_outputs(r, tmp_path)
    assert main(["fatigue", str(tmp_path), "--curve", "six-strand-rope",
                 f"{r.line_names[1]}=studlink-chain", "--m", "3", "5",
                 "--design-life", "25"]) == 0
    printed = capsys.readouterr().out
    report = json.loads((tmp_path / "fatigue.json").read_text())
    area = np.pi * 0.1**2 / 4
    for k, name in enumerate(r.line_names):
        a_D, m = (1.2e11, 3.0) if k == 1 else (3.4e14, 4.0)
        cells = np.flatnonzero(r.line_of_cell == k)
        damage = []
        for j in cells:
            ranges, counts = _astm_rainflow(r.tension[:, j])
            damage.append(np.sum(counts * (ranges / area / 1e6)**m) / a_D)
        row = report["lines"][name]
        assert row["element_damage"] == pytest.approx(damage, rel=1e-6)
        assert row["damage_design_life"] == pytest.approx(
            max(damage) * YEAR / 400.0 * 25, rel=1e-6)
        j = cells[row["element"]]
        ranges, counts = _astm_rainflow(r.tension[:, j])
        assert row["DEL"]["5"] == pytest.approx(
            (np.sum(counts * ranges**5) / 400.0)**0.2, rel=1e-6)
        assert name in printed


def test_summary_carries_the_fairlead_fatigue():
    from skmoor.run.outputs import summary

    k, period, amplitude = 5, 2.0, 2e5
    info = summary(_cosine_results(k, period, amplitude))
    row = info["fatigue"]["lines"]["line1"]
    area = np.pi * 0.1**2 / 4
    assert row["damage"] == pytest.approx(k * (2 * amplitude / area / 1e6)**3 / 6.0e10,
                                          rel=1e-9)
    json.dumps(info, allow_nan=False)      # strict JSON


def test_fatigue_command_help(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["fatigue", "--help"])
    assert stop.value.code == 0
    text = capsys.readouterr().out
    for option in ("--curve", "--m", "--start", "--design-life", "--mbl", "--d-nom",
                   "--fairlead"):
        assert option in text


def test_summary_of_a_history_that_is_not_finite_still_writes():
    from skmoor.run.outputs import summary

    r = _cosine_results()
    r.fairlead_tension[-1, 0] = np.nan
    assert "not finite" in summary(r)["fatigue"]["note"]
