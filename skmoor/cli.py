"""Command line: ``skmoor run | sweep | loadcases | export | render | fatigue``, over the
public API only."""
from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

DEFAULT_OUT = "skmoor-out"


def _source(path):
    """The paper's case (no path), a case file or a MoorDyn deck."""
    from . import Case, paper_case
    from .io.deck import is_deck, read_deck

    if path is None:
        return paper_case()
    if is_deck(path):
        return read_deck(path)
    return Case.from_toml(path)


def _motion(args, source):
    """The coupled objects' motion of a deck run: --motion FILE or --heave AMP --period T."""
    from .io.deck import Deck
    from .model.from_deck import heave_motion, read_motion
    from .model.openfast_motion import is_openfast_output, openfast_motion

    if args.motion is None and args.heave is None:
        return None
    if not isinstance(source, Deck):
        raise ValueError("--motion / --heave: only for a MoorDyn deck (a case's coupled "
                         "objects move by its own settings)")
    if args.motion is not None and args.heave is not None:
        raise ValueError("--motion, --heave: give one of them")
    if args.motion is not None:
        if is_openfast_output(args.motion):
            return openfast_motion(args.motion, source)
        return read_motion(args.motion, sum(source.coupled_sizes))
    if args.period is None:
        raise ValueError("--heave: give the heave period with --period T (s)")
    return heave_motion(source, args.heave, args.period)[0]


def cmd_run(args) -> int:
    from . import build, precompile, simulate, summary
    from .run.outputs import output_lock, prepare_output

    if precompile() and not args.quiet:  # a helper compiles while the model settles
        print("first run after an install: numba compiles the time step once (20 to 30 s "
              "more; later runs read it from its cache)", file=sys.stderr, flush=True)
    with output_lock(args.out):  # a second run into the same folder is refused
        out = prepare_output(args.out)  # before any solve
        source = _source(args.case)
        settings = {k: getattr(args, k) for k in ("duration", "dt", "output_interval")
                    if getattr(args, k) is not None}
        model = build(source, motion=_motion(args, source), rotations=args.rotations)
        _line_data(model, args)
        results = simulate(model, progress=not args.quiet, out=out, **settings,
                           checkpoint_every=getattr(args, "checkpoint_every", None),
                           restart=getattr(args, "restart", None))
        info = summary(results)
        from .run.report import summary_table
        print(summary_table(info), flush=True)  # the numbers first, then files and renders
        _plots(results, out)
        if args.moordyn_outputs:
            _moordyn_outputs(results, source, args.case, out)
        code, render_later = _finish(results, info, out, args)
    if render_later:  # once the lock is free: the renderer takes it
        _render_in_background(out)
    return code


def _moordyn_outputs(results, source, path, out):
    """MoorDyn's output files of the run in ``out``: a deck's line flags and OUTPUTS, named
    after the deck; for a case, every line's positions and tensions and its end tensions."""
    from .io.deck import Deck
    from .post.moordyn_outputs import write_moordyn_outputs

    if isinstance(source, Deck):
        stem = Path(path).stem
        flags = {line.id: line.outputs for line in source.lines}
        notes = write_moordyn_outputs(results, out, stem, flags, list(source.outputs))
    else:
        stem = Path(path).stem if path else "paper"
        notes = write_moordyn_outputs(results, out, stem)
    for note in notes:
        print(f"--moordyn-outputs: {note}")
    print(f"wrote MoorDyn-style outputs {out}/{stem}.out and {stem}_LineN.out")


def _finish(results, info, out, args) -> tuple:
    """ParaView files and (with --wait) renders unless switched off; the summary. Returns
    (exit status, 1 when the run stopped early; whether to render in the background)."""
    later = False
    if results.meta.get("interrupted") and not (args.no_export and args.no_animation):
        print(f"interrupted: ParaView files and animations skipped (make them with "
              f"`skmoor export {out}` and `skmoor render {out}`)")
    else:
        if not args.no_export:
            _export(results, out, args.frames)
        if not args.no_animation:
            if args.wait:
                _animate(results, out, args.quiet)
            else:
                later = True
    print(json.dumps(info, indent=2))
    print(f"wrote {out}/")
    return (0 if results.meta.get("stopped") is None else 1), later


def _render_in_background(out):
    """``skmoor render OUT`` started apart from this process (it outlives it), its output
    in OUT/render.log: the run returns with its numbers while the animations render."""
    import os
    import subprocess

    root = str(Path(__file__).resolve().parents[1])  # where this skmoor is imported from
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [root] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
    log = open(Path(out) / "render.log", "w")  # noqa: SIM115 - the child writes it
    with log:
        process = subprocess.Popen([sys.executable, "-m", "skmoor.cli", "render", str(out),
                                    "--quiet"], stdout=log, stderr=subprocess.STDOUT,
                                   stdin=subprocess.DEVNULL, env=env, start_new_session=True)
    print(f"rendering snapshot.png, animation.mp4 and animation.gif in the background "
          f"(process {process.pid}, about a minute; log: {Path(out) / 'render.log'}); "
          f"--wait renders them before returning")


def cmd_sweep(args) -> int:
    from .run.sweep import paper_studies, run_sweep, studies_from_args

    studies = studies_from_args(args.param, args.study_file, args.case) if (
        args.param or args.study_file) else paper_studies(args.points)
    rows = run_sweep(studies, args.out, workers=args.workers, scheduler=args.scheduler,
                     duration=args.duration, dt=args.dt, progress=not args.quiet)
    failed = [r for r in rows if r.get("error")]
    return 1 if failed else 0


def cmd_loadcases(args) -> int:
    from .run.load_cases import LoadCaseMatrix, run_load_cases

    matrix, settings = LoadCaseMatrix.from_toml(args.file)
    settings.update({k: getattr(args, k) for k in ("duration", "dt") if getattr(args, k)})
    data = run_load_cases(matrix, args.out, workers=args.workers, scheduler=args.scheduler,
                          progress=not args.quiet, **settings)
    return 1 if (data["error"].values != "").any() else 0


def cmd_export(args) -> int:
    out = Path(args.outdir)
    _export(_load_results(out), out, args.frames)
    return 0


def cmd_render(args) -> int:
    from .run.outputs import output_lock

    out = Path(args.outdir)
    with output_lock(out):  # a run into the folder waits for it
        _animate(_load_results(out), out, args.quiet, scale=args.scale, camera=args.camera)
    return 0


def cmd_fatigue(args) -> int:
    from .post.fatigue import fatigue

    out = Path(args.outdir)
    results = _load_results(out)
    report = fatigue(results, curve=_per_line(args.curve, str, results.line_names, "--curve"),
                     m=args.m, start=args.start, design_life=args.design_life,
                     mbl=_per_line(args.mbl, float, results.line_names, "--mbl"),
                     d_nom=_per_line(args.d_nom, float, results.line_names, "--d-nom"),
                     where="fairlead" if args.fairlead else "elements")
    (out / "fatigue.json").write_text(json.dumps(report, indent=2))
    from .run.report import fatigue_table
    print(fatigue_table(report))
    print(f"wrote {out / 'fatigue.json'}")
    return 0


def _per_line(values, convert, line_names, option):
    """--option VALUE [LINE=VALUE ...] as a value for all lines, or {line: value}."""
    if not values:
        return None
    bare = [v for v in values if "=" not in v]
    if len(bare) > 1:
        raise ValueError(f"{option}: one value for all lines, then LINE=VALUE for some "
                         f"(got {', '.join(bare)})")
    given = {}
    for item in values:
        if "=" in item:
            line, value = item.split("=", 1)
            given[line] = value
    try:
        if not given:
            return convert(bare[0])
        out = {name: convert(bare[0]) for name in line_names} if bare else {}
        out.update({line: convert(v) for line, v in given.items()})
    except ValueError as err:
        raise ValueError(f"{option}: {err}") from None
    return out


def _line_data(model, args):
    """--mbl, --fatigue-curve, --d-nom of ``skmoor run``: the lines' strength and fatigue
    data over their line types' (a MoorDyn deck has none of them)."""
    import dataclasses

    lines = model.lines.lines if model is not None else []
    names = [line.name for line in lines]
    for key, option, convert in (("MBL", "--mbl", float), ("fatigue_curve", "--fatigue-curve", str),
                                 ("d_nom", "--d-nom", float)):
        given = _per_line(getattr(args, key.lower(), None), convert, names, option)
        if given is None:
            continue
        if isinstance(given, dict):
            unknown = sorted(set(given) - set(names))
            if unknown:
                raise ValueError(f"{option}: no line named {', '.join(map(repr, unknown))} "
                                 f"(the lines are {', '.join(names)})")
        for line in lines:
            value = given.get(line.name) if isinstance(given, dict) else given
            if value is not None:
                line.line_type = dataclasses.replace(line.line_type, **{key: value})


def _load_results(out):
    """The Results of a previous run's folder (results.npz, else results.nc), ValueError
    (one line) when it is not one: a file, no results, a truncated file or one without an
    array, non-finite motion."""
    from .run.outputs import load_results

    return load_results(out)


def _plots(results, out):
    """Fig. 6 of the paper for a model with a body; the lines' end tensions without."""
    from .post.plots import plot_line_tensions, plot_time_histories

    if results.body_names:
        plot_time_histories(results, out / "time_histories.png")
    else:
        plot_line_tensions(results, out / "time_histories.png")
    if results.line_names:
        from .post.plots import plot_strength
        plot_strength(results, out / "strength.png")


def _export(results, out, max_frames):
    from .post.export import export

    for path in export(results, out, max_frames=max_frames or None):
        print(f"exported {path}" if path is not None else
              "no lines: lines.xdmf not written (the network has none)")


def _animate(results, out, quiet, scale=None, camera="iso"):
    from .post.render import animate, default_scale, snapshot

    scale = default_scale(results) if scale is None else scale
    snapshot(results, len(results.t) - 1, out / "snapshot.png", scale=scale, camera=camera)
    for name, frames, size in (("animation.mp4", 300, (1024, 768)), ("animation.gif", 80, (800, 600))):
        every = max(1, len(results.t) // frames)
        n = animate(results, out / name, every=every, scale=scale, camera=camera, window_size=size,
                    progress=not quiet)
        print(f"rendered {out / name} ({n} frames)")


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="skmoor", description=__doc__.replace("``", ""))
    sub = p.add_subparsers(dest="command", required=True)

    _add_run(sub)
    sw = sub.add_parser("sweep", help="parameter studies (default: the paper's two studies)",
                        description="Runs parameter studies in parallel processes or on a Dask "
                        "cluster; writes sweep.csv and plots into --out; finished points are "
                        "kept and a rerun does only the missing ones.")
    sw.add_argument("--param", action="append", default=[],
                    help="PATH=v1,v2,... or PATH=start:stop:n (repeat for a grid), e.g. "
                    "mooring.sag_ratio=0.02,0.0167")
    sw.add_argument("--study-file", help="TOML file with [[study]] tables")
    sw.add_argument("--case", help="base case file for --param (default: the paper's case)")
    sw.add_argument("--points", type=int, default=8, help="points per paper study (default: 8)")
    _batch_options(sw, "point")
    sw.set_defaults(func=cmd_sweep)

    lc = sub.add_parser("loadcases", help="a design-load-case matrix into one dataset",
                        description="Runs the [load_cases] matrix of a TOML file (sea states "
                        "x headings x seeds x conditions) in parallel processes or on a Dask "
                        "cluster; writes load_cases.nc and load_cases.csv into --out; "
                        "finished cases are kept and a rerun does only the missing ones.")
    lc.add_argument("file", help="TOML file with a [load_cases] table")
    _batch_options(lc, "case")
    lc.set_defaults(func=cmd_loadcases)

    ex = sub.add_parser("export", help="(re)write ParaView files from saved results",
                        description="Reads OUTDIR/results.nc (or results.npz) and writes lines.xdmf (+ .h5) and "
                        "a VTU series with a .pvd index into OUTDIR.")
    ex.add_argument("outdir", help="folder of a previous run")
    ex.add_argument("--frames", type=int, default=1000, help="at most this many samples, "
                    "evenly strided (0: all; default: %(default)s)")
    ex.set_defaults(func=cmd_export)

    rd = sub.add_parser("render", help="(re)render snapshot and animations from saved results",
                        description="Reads OUTDIR/results.nc (or results.npz) and renders snapshot.png, "
                        "animation.mp4 and animation.gif off-screen.")
    rd.add_argument("outdir", help="folder of a previous run")
    rd.add_argument("--scale", type=float, help="displacement scale factor (default: automatic)")
    rd.add_argument("--camera", default="iso", help="camera preset: iso, side, top, front")
    rd.add_argument("--quiet", action="store_true", help="no progress bar")
    rd.set_defaults(func=cmd_render)
    _add_fatigue(sub)
    return p


def _add_run(sub):
    """The ``run`` command's options."""
    run = sub.add_parser("run", help="run a case (default: the paper's case)",
                         description="Static equilibrium, modes and time history of a case; "
                         "writes summary.json, timeseries.csv, results.npz, plots, ParaView "
                         "files and an animation into --out.")
    run.add_argument("case", nargs="?", help="case file (.toml) or MoorDyn v2 deck (.dat, "
                     ".txt); default: the paper's case")
    run.add_argument("--out", default=DEFAULT_OUT, help="output folder (default: %(default)s)")
    run.add_argument("--duration", type=float, help="simulated time, s (default: the case's)")
    run.add_argument("--dt", type=float, help="time step, s (default: the case's)")
    run.add_argument("--output-interval", dest="output_interval", type=float,
                     help="sampling interval of the results, s (default: the case's)")
    run.add_argument("--no-export", action="store_true", help="skip the XDMF / PVD export")
    run.add_argument("--no-animation", action="store_true", help="skip snapshot and animations")
    run.add_argument("--wait", action="store_true", help="render the snapshot and animations "
                     "before returning (default: in the background once the numbers are out)")
    run.add_argument("--frames", type=int, default=1000, help="ParaView series: at most this "
                     "many samples, evenly strided (0: all; default: %(default)s)")
    run.add_argument("--quiet", action="store_true", help="no progress bars")
    run.add_argument("--moordyn-outputs", dest="moordyn_outputs", action="store_true",
                     help="also write MoorDyn's output files (NAME.out, NAME_LineN.out: "
                          "the deck's OUTPUTS and line flags p, v, t)")
    run.add_argument("--heave", type=float, metavar="AMP",
                     help="deck only: heave the coupled points / bodies AMP m (faded in over "
                     "one period; without it they stay still)")
    run.add_argument("--period", type=float, metavar="T", help="deck only: heave period, s")
    run.add_argument("--motion", metavar="FILE",
                     help="deck only: motion of the coupled bodies and points, a table: time "
                     "(s), then their displacements in MoorDyn's coupled-DOF order (6 per "
                     "coupled body: m, m, m, rad, rad, rad; then 3 per coupled point, m), or an "
                     "OpenFAST output file (.out, .outb) whose platform motion moves them")
    run.add_argument("--rotations", choices=("small", "exact"),
                     help="deck only: the free bodies' rotations, 'exact' for bodies that "
                     "turn far (default: small; a case file sets it per body)")
    run.add_argument("--mbl", nargs="+", metavar="N", help="minimum breaking load, N, of all "
                     "lines and/or LINE=N, over the line types' (a MoorDyn deck gives none): "
                     "the safety factors in summary.json")
    run.add_argument("--fatigue-curve", dest="fatigue_curve", nargs="+", metavar="CURVE",
                     help="fatigue curve of all lines and/or LINE=CURVE (e.g. studless-chain; "
                     "see skmoor fatigue --help)")
    run.add_argument("--d-nom", dest="d_nom", nargs="+", metavar="M", help="nominal "
                     "diameter, m, of all lines and/or LINE=M (the fatigue curves' section)")
    run.add_argument("--checkpoint-every", dest="checkpoint_every", type=float, metavar="S",
                     help="write the whole state to OUT/checkpoint.bin every S s of "
                     "simulated time (replacing the one before)")
    run.add_argument("--restart", metavar="FILE",
                     help="go on from a checkpoint of the same model and dt (its results "
                     "start at the checkpoint's time)")
    run.set_defaults(func=cmd_run)


def _add_fatigue(sub):
    """The ``fatigue`` command's options."""
    fa = sub.add_parser("fatigue", help="rainflow fatigue damage and DELs of a saved run",
                        description="Reads OUTDIR's results, counts each element's tension "
                        "ranges (rainflow, ASTM E1049), sums Miner's damage on the lines' "
                        "T-N / S-N curves (DNV-OS-E301, DNV-RP-C203) over the run, per year "
                        "and per design life, and the damage-equivalent loads at 1 Hz; "
                        "writes OUTDIR/fatigue.json and prints a table.")
    fa.add_argument("outdir", help="folder of a previous run")
    fa.add_argument("--curve", nargs="+", metavar="CURVE", help="fatigue curve for all "
                    "lines and/or LINE=CURVE for some, over the line types' own (names: "
                    "studless-chain, studlink-chain, six-strand-rope, spiral-strand-rope, "
                    "polyester-rope, dnv-c203-D-air ...)")
    fa.add_argument("--m", nargs="+", type=float, default=[3.0, 5.0],
                    help="Wöhler exponents of the damage-equivalent loads (default: 3 5)")
    fa.add_argument("--start", type=float, default=0.0,
                    help="skip the samples before this time, s (the start-up transient)")
    fa.add_argument("--design-life", dest="design_life", type=float, metavar="YEARS",
                    help="also give the damage over this many years")
    fa.add_argument("--mbl", nargs="+", metavar="N", help="minimum breaking load, N, for all "
                    "lines and/or LINE=N (polyester's curve needs it)")
    fa.add_argument("--d-nom", dest="d_nom", nargs="+", metavar="M", help="nominal diameter, "
                    "m, for all lines and/or LINE=M (default: the line types')")
    fa.add_argument("--fairlead", action="store_true",
                    help="the tension at each line's fairlead (end B) only")
    fa.set_defaults(func=cmd_fatigue)


def _one_line_warning(message, category, filename, lineno, line=None):
    """A warning as one line naming its kind, not the source line that raised it."""
    return f"skmoor: {category.__name__}: {message}\n"


def _batch_options(parser, what):
    """The options of a batch of runs (sweep, loadcases): output, where and how long."""
    parser.add_argument("--out", default=DEFAULT_OUT, help="output folder (default: %(default)s)")
    parser.add_argument("--workers", type=int, help="local processes (default: one per core)")
    parser.add_argument("--scheduler", help="Dask scheduler address, e.g. tcp://host:8786")
    parser.add_argument("--duration", type=float, help=f"simulated time per {what}, s")
    parser.add_argument("--dt", type=float, help="time step, s")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def main(argv=None) -> int:
    from .run.simulate import terminate_as_interrupt
    from .solvers.newton import ConvergenceError

    args = parser().parse_args(argv)
    shown = warnings.formatwarning
    warnings.formatwarning = _one_line_warning
    try:
        with terminate_as_interrupt():  # a run keeps its results, a sweep its points
            return args.func(args)
    except (ValueError, FileNotFoundError, ConvergenceError) as err:
        print(f"skmoor {args.command}: error: {_line(err)}", file=sys.stderr)
        return 2
    except OSError as err:  # a full disk, a folder that cannot be written
        where = f"{err.filename}: " if err.filename else ""
        print(f"skmoor {args.command}: error: {where}{err.strerror or err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"skmoor {args.command}: interrupted", file=sys.stderr)
        return 130
    finally:
        warnings.formatwarning = shown


def _line(err) -> str:
    """An error's message on one line."""
    return " ".join(str(err).split())


if __name__ == "__main__":
    sys.exit(main())
