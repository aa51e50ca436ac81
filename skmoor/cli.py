"""Command line: ``skmoor run | sweep | export | render``, over the public API only."""
from __future__ import annotations

import argparse
import json
import sys
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

    if args.motion is None and args.heave is None:
        return None
    if not isinstance(source, Deck):
        raise ValueError("--motion / --heave: only for a MoorDyn deck (a case's coupled "
                         "objects move by its own settings)")
    if args.motion is not None and args.heave is not None:
        raise ValueError("--motion, --heave: give one of them")
    if args.motion is not None:
        n = sum(source.coupled_sizes)
        return read_motion(args.motion, n)
    if args.period is None:
        raise ValueError("--heave: give the heave period with --period T (s)")
    return heave_motion(source, args.heave, args.period)[0]


def cmd_run(args) -> int:
    from . import build, simulate, summary
    from .run.outputs import prepare_output

    out = prepare_output(args.out)  # before any solve
    source = _source(args.case)
    settings = {k: getattr(args, k) for k in ("duration", "dt", "output_interval")
                if getattr(args, k) is not None}
    model = build(source, motion=_motion(args, source), rotations=args.rotations)
    results = simulate(model, progress=not args.quiet, out=out, **settings,
                       checkpoint_every=getattr(args, "checkpoint_every", None),
                       restart=getattr(args, "restart", None))
    info = summary(results)
    _plots(results, out)
    return _finish(results, info, out, args)


def _finish(results, info, out, args) -> int:
    """ParaView files and renders unless switched off; the summary; exit status 1 when the
    run stopped early."""
    if results.meta.get("interrupted") and not (args.no_export and args.no_animation):
        print(f"interrupted: ParaView files and animations skipped (make them with "
              f"`skmoor export {out}` and `skmoor render {out}`)")
    else:
        if not args.no_export:
            _export(results, out, args.frames)
        if not args.no_animation:
            _animate(results, out, args.quiet)
    print(json.dumps(info, indent=2))
    print(f"wrote {out}/")
    return 0 if results.meta.get("stopped") is None else 1


def cmd_sweep(args) -> int:
    from .run.sweep import paper_studies, run_sweep, studies_from_args

    studies = studies_from_args(args.param, args.study_file, args.case) if (
        args.param or args.study_file) else paper_studies(args.points)
    rows = run_sweep(studies, args.out, workers=args.workers, scheduler=args.scheduler,
                     duration=args.duration, dt=args.dt, progress=not args.quiet)
    failed = [r for r in rows if r.get("error")]
    return 1 if failed else 0


def cmd_export(args) -> int:
    from . import Results

    out = Path(args.outdir)
    _export(Results.load(out / "results.npz"), out, args.frames)
    return 0


def cmd_render(args) -> int:
    from . import Results

    out = Path(args.outdir)
    _animate(Results.load(out / "results.npz"), out, args.quiet, scale=args.scale,
             camera=args.camera)
    return 0


def _plots(results, out):
    """Fig. 6 of the paper for a model with a body; the lines' end tensions without."""
    from .post.plots import plot_line_tensions, plot_time_histories

    if results.body_names:
        plot_time_histories(results, out / "time_histories.png")
    else:
        plot_line_tensions(results, out / "time_histories.png")


def _export(results, out, max_frames):
    from .post.export import export

    for path in export(results, out, max_frames=max_frames or None):
        print(f"exported {path}" if path is not None else
              "no lines: lines.xdmf not written (the network has none)")


def _animate(results, out, quiet, scale=None, camera="iso"):
    from .post.render import animate, default_scale, snapshot

    scale = default_scale(results) if scale is None else scale
    snapshot(results, len(results.t) - 1, out / "snapshot.png", scale=scale, camera=camera)
    for name, frames, size in (("animation.mp4", 300, (1024, 768)), ("animation.gif", 80, (480, 360))):
        every = max(1, len(results.t) // frames)
        n = animate(results, out / name, every=every, scale=scale, camera=camera, window_size=size,
                    progress=not quiet)
        print(f"rendered {out / name} ({n} frames)")


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="skmoor", description=__doc__)
    sub = p.add_subparsers(dest="command", required=True)

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
    run.add_argument("--frames", type=int, default=1000, help="ParaView series: at most this "
                     "many samples, evenly strided (0: all; default: %(default)s)")
    run.add_argument("--quiet", action="store_true", help="no progress bars")
    run.add_argument("--heave", type=float, metavar="AMP",
                     help="deck only: heave the coupled points / bodies AMP m (faded in over "
                     "one period; without it they stay still)")
    run.add_argument("--period", type=float, metavar="T", help="deck only: heave period, s")
    run.add_argument("--motion", metavar="FILE",
                     help="deck only: motion of the coupled bodies and points, a table: time "
                     "(s), then their displacements in MoorDyn's coupled-DOF order (6 per "
                     "coupled body: m, m, m, rad, rad, rad; then 3 per coupled point, m)")
    run.add_argument("--rotations", choices=("small", "exact"),
                     help="deck only: the free bodies' rotations, 'exact' for bodies that "
                     "turn far (default: small; a case file sets it per body)")
    run.add_argument("--checkpoint-every", dest="checkpoint_every", type=float, metavar="S",
                     help="write the whole state to OUT/checkpoint.bin every S s of "
                     "simulated time (replacing the one before)")
    run.add_argument("--restart", metavar="FILE",
                     help="go on from a checkpoint of the same model and dt (its results "
                     "start at the checkpoint's time)")
    run.set_defaults(func=cmd_run)

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
    sw.add_argument("--out", default=DEFAULT_OUT, help="output folder (default: %(default)s)")
    sw.add_argument("--workers", type=int, help="local processes (default: one per core)")
    sw.add_argument("--scheduler", help="Dask scheduler address, e.g. tcp://host:8786")
    sw.add_argument("--duration", type=float, help="simulated time per point, s")
    sw.add_argument("--dt", type=float, help="time step, s")
    sw.add_argument("--quiet", action="store_true", help="no progress bar")
    sw.set_defaults(func=cmd_sweep)

    ex = sub.add_parser("export", help="(re)write ParaView files from saved results",
                        description="Reads OUTDIR/results.npz and writes lines.xdmf (+ .h5) and "
                        "a VTU series with a .pvd index into OUTDIR.")
    ex.add_argument("outdir", help="folder of a previous run")
    ex.add_argument("--frames", type=int, default=1000, help="at most this many samples, "
                    "evenly strided (0: all; default: %(default)s)")
    ex.set_defaults(func=cmd_export)

    rd = sub.add_parser("render", help="(re)render snapshot and animations from saved results",
                        description="Reads OUTDIR/results.npz and renders snapshot.png, "
                        "animation.mp4 and animation.gif off-screen.")
    rd.add_argument("outdir", help="folder of a previous run")
    rd.add_argument("--scale", type=float, help="displacement scale factor (default: automatic)")
    rd.add_argument("--camera", default="iso", help="camera preset: iso, side, top, front")
    rd.add_argument("--quiet", action="store_true", help="no progress bar")
    rd.set_defaults(func=cmd_render)
    return p


def main(argv=None) -> int:
    args = parser().parse_args(argv)
    try:
        return args.func(args)
    except (ValueError, FileNotFoundError) as err:
        print(f"skmoor {args.command}: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"skmoor {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
