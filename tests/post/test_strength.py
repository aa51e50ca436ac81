"""The strength check (skmoor.post.strength) against numbers set by hand: a tension
history whose largest value, place and time are known, an MBL giving a safety factor of
exactly 2; the line type and case-file fields it reads."""
import pytest
from _synthetic import NEL, synthetic_results

from skmoor import paper_case
from skmoor.io.schema import validate_case
from skmoor.lines.line import LineType
from skmoor.model.from_case import line_type
from skmoor.post.strength import strength
from skmoor.run.outputs import summary


def _results_with_peak():
    r = synthetic_results()
    r.tension[:] = 1e6
    r.tension[7, 1 * NEL + 3] = 2.5e6     # line 1, its element 3, sample 7
    r.meta["line_MBL"] = [None, 5e6, 5e6, None]
    return r


def test_peak_safety_factor_and_utilisation():
    r = _results_with_peak()
    s = strength(r)
    name = r.line_names[1]
    assert s[name]["max_tension"] == 2.5e6
    assert s[name]["element"] == 3
    assert s[name]["time"] == pytest.approx(r.t[7])
    assert s[name]["safety_factor"] == pytest.approx(2.0)
    assert s[name]["utilisation"] == pytest.approx(0.4 / 0.8)
    assert s[name]["element_max_tension"] == [1e6] * 3 + [2.5e6] + [1e6] * (NEL - 4)
    # a line without an MBL: its tension, no factor
    assert s[r.line_names[0]]["safety_factor"] is None
    assert s[r.line_names[0]]["max_tension"] == 1e6
    # an MBL given for one line replaces the type's; from t after the peak it is gone
    s = strength(r, mbl={r.line_names[0]: 4e6}, start=r.t[8])
    assert s[r.line_names[0]]["safety_factor"] == pytest.approx(4.0)
    assert s[name]["max_tension"] == 1e6
    with pytest.raises(ValueError, match="no line named 'nope'"):
        strength(r, mbl={"nope": 1.0})


def test_summary_carries_the_strength():
    r = _results_with_peak()
    info = summary(r)
    assert info["strength"][r.line_names[1]]["safety_factor"] == pytest.approx(2.0)


def test_line_type_fields_validated():
    assert LineType(EA=1e8, mass=100.0, diameter=0.1, MBL=5e6).MBL == 5e6
    with pytest.raises(ValueError, match="MBL"):
        LineType(EA=1e8, mass=100.0, diameter=0.1, MBL=-1.0)
    with pytest.raises(ValueError, match="unknown curve 'steel'"):
        LineType(EA=1e8, mass=100.0, diameter=0.1, fatigue_curve="steel")


def test_case_file_line_type_strength_fields():
    case = paper_case(**{"line_types__steel__MBL": 7.0e6,
                         "line_types__steel__fatigue_curve": "spiral-strand-rope"})
    lt = line_type(case, "steel")
    assert (lt.MBL, lt.fatigue_curve, lt.d_nom) == (7.0e6, "spiral-strand-rope", None)
    data = paper_case().data
    data["line_types"]["steel"]["fatigue_curve"] = "rope"
    with pytest.raises(ValueError, match="fatigue_curve"):
        validate_case(data)
    data["line_types"]["steel"]["fatigue_curve"] = "studless-chain"
    data["line_types"]["steel"]["MBL"] = 0.0
    with pytest.raises(ValueError, match="MBL"):
        validate_case(data)


def test_strength_plot(tmp_path):
    from skmoor.post.plots import plot_strength

    path = plot_strength(_results_with_peak(), tmp_path / "strength.png")
    assert path.stat().st_size > 1000


def test_bend_radius_against_mbr():
    r = _results_with_peak()
    r.meta["bending"] = True
    r.meta["line_MBR"] = [None, 4.0, None, None]
    r.curvature[:] = 0.05
    r.curvature[3, NEL + 2] = -0.125              # radius 8 m on line 1
    s = strength(r)
    row = s[r.line_names[1]]
    assert row["min_bend_radius"] == pytest.approx(8.0)
    assert row["bend_radius_ratio"] == pytest.approx(2.0)
    assert s[r.line_names[0]]["min_bend_radius"] == pytest.approx(20.0)
    assert s[r.line_names[0]]["bend_radius_ratio"] is None


def test_end_tension_counts_where_it_is_larger():
    r = _results_with_peak()
    r.fairlead_tension[:] = 0.5e6
    r.anchor_tension[:] = 0.5e6
    r.fairlead_tension[12, 1] = 4e6
    row = strength(r)[r.line_names[1]]
    assert (row["max_tension"], row["where"], row["element"]) == (4e6, "fairlead", 3)
    assert row["time"] == pytest.approx(r.t[12])
    assert row["safety_factor"] == pytest.approx(1.25)
