"""Checks of benchmarks/validate.py on the lines' tension laws: a tension-strain curve, the
static-dynamic polyester, a tension-only line going slack; each returns rows
(benchmarks/_validation.Row); the set-ups are the test suite's (imported from
tests/lines/test_curve_catenary.py, test_polyester_moordyn.py, test_slack_snap_moordyn.py)."""
from __future__ import annotations

import tempfile
from pathlib import Path

from _cases import inside, quiet
from _validation import MOORDYN, Row

SHOT = "elastic catenary with the curve's strain, integrated by solve_ivp and shot (fsolve)"


def check_curve_catenary():
    """A 1000 m line (600 N/m) with a stiffening four-point tension-strain curve, anchor
    400 m deep, fairlead 850 m away: the closed-form catenary with the curve law and the
    FE statics from a stress-free polyline (40 elements)."""
    from test_curve_catenary import (
        ANCHOR,
        FAIRLEAD,
        STRAIN,
        TENSION,
        L,
        W,
        fe_statics,
        shot_line,
    )

    import skmoor
    from skmoor import laws

    _, _, TA, TB = shot_line()
    cat = skmoor.solve_catenary(ANCHOR, FAIRLEAD, W, 2e7, length=L,
                                law=laws.Curve(STRAIN, TENSION))
    fe_anchor, fe_fairlead = fe_statics(40)
    return [Row("curve law, closed-form catenary: fairlead tension", TB, SHOT,
                float(cat.T_fairlead), 1e-9, unit="N"),
            Row("curve law, FE statics, 40 el.: fairlead tension", TB, SHOT, float(fe_fairlead),
                5e-4, unit="N"),
            Row("curve law, FE statics, 40 el.: anchor tension", TA, SHOT, float(fe_anchor),
                5e-4, unit="N")]


def check_viscoelastic_polyester():
    """A taut 199 m polyester line (10 segments) with MoorDyn's EA_s|EA_d (creep time
    10 s) driven 0.5 m sin(2 t) along its chord for six periods: skmoor's viscoelastic law
    (its creep state integrated in time) against MoorDyn's, fairlead tension over the last
    3 periods."""
    from test_polyester_moordyn import (
        EA_D,
        EA_S,
        FAIRLEAD,
        PERIOD,
        chord_motion,
        measures,
        run_moordyn,
        run_skmoor,
        visco_deck,
    )

    duration = 6 * PERIOD
    displacement, velocity = chord_motion()
    with tempfile.TemporaryDirectory() as tmp, inside(tmp), quiet():
        deck = visco_deck(Path(tmp) / "visco.dat", f"{EA_S!r}|{EA_D!r}")
        _, t_sk, T_sk = run_skmoor(deck, displacement, duration, 0.01)
        t_md, T_md = run_moordyn(deck, FAIRLEAD, displacement, velocity, duration, 0.01)
    label = "polyester EA_s|EA_d driven along its chord:"
    rows = [Row(f"{label} static fairlead tension", float(T_md[0]), MOORDYN, float(T_sk[0]),
                1e-3, unit="N")]
    for name, ours, theirs in zip(("peak", "mean", "first harmonic"),
                                  measures(t_sk, T_sk, duration), measures(t_md, T_md, duration)):
        rows.append(Row(f"{label} {name} tension, last 3 periods", float(theirs), MOORDYN,
                        float(ours), 1e-2, unit="N"))
    return rows


def check_slack_and_snap():
    """The paper's line C1 alone (20 segments), its fairlead driven 1 m sin(1.6 t) along
    the line for eight periods, so that it goes slack and snaps taut every cycle
    (tests/solvers/test_slack_snap_moordyn.py): fairlead tension over the last four periods."""
    from test_slack_snap_moordyn import measures, slack_snap_runs

    with tempfile.TemporaryDirectory() as tmp, inside(tmp), quiet():
        runs = slack_snap_runs(Path(tmp))
    label = "line going slack and snapping, tension-only:"
    return [Row(f"{label} {name} fairlead tension, last 4 periods", float(theirs), MOORDYN,
                float(ours), 3e-2, unit="N")
            for name, ours, theirs in zip(("peak", "mean", "first harmonic"),
                                          measures(runs["t_sk"], runs["T_sk"]),
                                          measures(runs["t_md"], runs["T_md"]))]
