"""A run's numbers as short text tables, printed as soon as the solve ends (before the
ParaView files and the animations): the summary (draft, periods, amplitudes, maximum
tension, each line's strength and fatigue) and ``skmoor fatigue``'s report.
"""
from __future__ import annotations

__all__ = ["summary_table", "fatigue_table"]


def summary_table(info: dict) -> str:
    """``summary.json``'s key numbers (:func:`skmoor.run.outputs.summary`) as text: the
    case, draft, natural periods, steady amplitudes, the largest tension and the line
    failures, then one row
    per line: its largest tension, MBL, safety factor and utilisation, and at its
    fairlead the fatigue damage per year, the life and the DEL for m = 3."""
    out = [f"case: {info.get('case') or '-'}"]
    if info.get("draft") is not None:
        out.append(f"draft: {info['draft']:.4g} m")
    periods = info.get("natural_periods") or []
    if periods:
        out.append("natural periods: " + ", ".join(f"{p:.4g}" for p in periods[:6]) + " s"
                   + (" ..." if len(periods) > 6 else ""))
    amplitude = info.get("amplitude") or {}
    if amplitude:
        units = {"surge": "m", "heave": "m", "pitch": "rad"}
        out.append("steady amplitudes: " + ", ".join(
            f"{k} {v:.4g} {units.get(k, '')}".rstrip() for k, v in amplitude.items()))
    if info.get("max_tension") is not None:
        steady = info.get("max_tension_steady")
        out.append(f"max tension: {info['max_tension'] / 1e3:.6g} kN"
                   + (f" (steady {steady / 1e3:.6g} kN)" if steady is not None else ""))
    for event in info.get("line_failures") or []:
        out.append(f"line failure: {', '.join(event['lines'])} released from "
                   f"{event['point']} at t = {event['time']:.6g} s ({event['trigger']}, "
                   f"{event['tension'] / 1e3:.6g} kN)")
    strength = info.get("strength") or {}
    fatigue = (info.get("fatigue") or {}).get("lines", {})
    if strength:
        head = ["line", "Tmax [kN]", "MBL [kN]", "SF", "util [%]", "D/year", "life [y]",
                "DEL m=3 [kN]"]
        rows = []
        for name, s in strength.items():
            f = fatigue.get(name, {})
            dels = f.get("DEL") or {}
            rows.append([name, _g(s["max_tension"] / 1e3), _g(_scaled(s.get("MBL"), 1e-3)),
                         _g(s.get("safety_factor"), 3), _g(_scaled(s.get("utilisation"), 100), 3),
                         _g(f.get("damage_per_year")), _g(f.get("life_years")),
                         _g(_scaled(dels.get("3"), 1e-3))])
        out.append(table(head, rows))
        if fatigue:
            out.append("(fatigue at each fairlead on its line type's curve; every element's: "
                       "skmoor fatigue OUTDIR)")
    return "\n".join(out)


def fatigue_table(report: dict) -> str:
    """A fatigue report (:func:`skmoor.post.fatigue.fatigue`) as text: per line its curve,
    damage over the run, per year and over the design life, life (years) and DELs (kN)."""
    m = [f"{x:g}" for x in report["m"]]
    head = ["line", "curve", "D run", "D/year", "life [y]"]
    if report.get("design_life"):
        head.append(f"D {report['design_life']:g} y")
    head += [f"DEL m={x} [kN]" for x in m]
    rows = []
    for name, row in report["lines"].items():
        cells = [name, row["curve"] or "-", _g(row["damage"]), _g(row["damage_per_year"]),
                 _g(row["life_years"])]
        if report.get("design_life"):
            cells.append(_g(row["damage_design_life"]))
        rows.append(cells + [_g(row["DEL"][x] / 1e3) for x in m])
    return table(head, rows) + (f"\n({report['where']}, {report['duration']:g} s of run, "
                                f"DEL at {report['f_eq']:g} Hz)")


def table(head, rows) -> str:
    """Columns padded to their widest cell, two spaces apart."""
    widths = [max(len(str(r[i])) for r in [head] + rows) for i in range(len(head))]
    return "\n".join("  ".join(str(c).ljust(w) for c, w in zip(r, widths)).rstrip()
                     for r in [head] + rows)


def _scaled(x, factor):
    return None if x is None else x * factor


def _g(x, digits=4) -> str:
    return "-" if x is None else f"{x:.{digits}g}"
