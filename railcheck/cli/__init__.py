"""The ``railcheck`` command line.

Exit statuses: 0 pass, 1 a check failed, 2 bad input or impossible mechanism (one line on
stderr naming the field, no traceback), 3 numerical failure.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from railcheck.check.kinematics_stage import kinematics_summary, run_kinematics
from railcheck.check.run import run_check
from railcheck.errors import EXIT_FAIL, EXIT_INPUT, EXIT_PASS, InputError, RailcheckError
from railcheck.fea.fatigue import CRITERIA, SURFACE
from railcheck.fea.materials import MATERIALS
from railcheck.files import atomic_write_text, to_json, writable_dir, writable_file
from railcheck.kinematics.planar.catalogue import CATALOGUE
from railcheck.parts import PARTS
from railcheck.progress import Progress
from railcheck.report.plots import write_kinematics_plots
from railcheck.report.text import (
    bench_report,
    check_report,
    convergence_report,
    kinematics_table,
    mechanism_report,
    sweep_report,
)
from railcheck.scene import EFFECTS, load_scene, parse_scene
from railcheck.studies.bench import run_bench
from railcheck.studies.convergence import plot_study, run_convergence
from railcheck.studies.mechanism import run_mechanism, write_mechanism_outputs
from railcheck.sweep.run import run_sweep


class _Parser(argparse.ArgumentParser):
    """argparse that exits 2 with one line (its default already uses 2)."""

    def error(self, message: str):  # noqa: D401
        self.exit(EXIT_INPUT, f"railcheck: error: {message}\n")


def _cmd_kinematics(args) -> int:

    scene = load_scene(args.scene)
    if scene.mechanism is None:
        raise InputError("mechanism", "missing: `railcheck kinematics` needs a [mechanism] table")
    result = run_kinematics(scene)
    summary = kinematics_summary(scene, result)
    if args.plots:
        paths = write_kinematics_plots(result, Path(args.plots))
        summary["plots"] = [str(p) for p in paths]
    if args.json:
        print(to_json(summary))
    else:
        print(f"scene: {scene.source}")
        print(kinematics_table(summary))
        for p in summary.get("plots", []):
            print(f"wrote {p}")
    failed = [name for name, c in summary["checks"].items() if not c["ok"]]
    if failed and not args.json:
        print(f"verdict: FAIL (check {', check '.join(failed)})")
    return EXIT_FAIL if failed else EXIT_PASS


#: output options: attribute -> (option, directory?)
OUTPUT_OPTIONS = {"plots": ("--plots", True), "csv": ("--csv", False), "html": ("--html", False),
                  "gif": ("--gif", False), "plot": ("--plot", False)}


def _check_output_options(args) -> None:
    """Every output path the command line names is checked before any work starts."""

    for attr, (option, is_dir) in OUTPUT_OPTIONS.items():
        value = getattr(args, attr, None)
        if value:
            (writable_dir if is_dir else writable_file)(value, option)


def _cmd_init(args) -> int:
    from importlib import resources


    path = writable_file(args.file, "FILE")
    if path.exists() and not args.force:
        raise InputError("FILE", f"{path} exists (use --force to replace it)")
    text = resources.files("railcheck").joinpath("scenes", "starter.toml").read_text(encoding="utf-8")
    import tomllib
    parse_scene(tomllib.loads(text), "starter.toml")          # the starter is always a valid scene
    atomic_write_text(path, text)
    print(f"wrote {path}: edit it, then run `railcheck check {path}`")
    return EXIT_PASS


def _cmd_check(args) -> int:

    if args.jobs is not None and args.jobs < 1:
        raise InputError("--jobs", f"must be at least 1, got {args.jobs}")
    run = run_check(load_scene(args.scene), args.out, args.force, Progress(quiet=False), args.jobs)
    print(to_json(run.summary) if args.json else check_report(run))
    if run.requested != run.target:
        print(f"railcheck: {run.requested} exists; results written to {run.target} (use --force to replace)",
              file=sys.stderr)
    return run.exit_status


def _cmd_sweep(args) -> int:

    if args.workers is not None and args.workers < 1:
        raise InputError("--workers", f"must be at least 1, got {args.workers}")
    run = run_sweep(load_scene(args.scene), args.out, args.force, args.scheduler, args.workers, args.serial,
                    Progress(quiet=False))
    print(to_json(run.summary) if args.json else sweep_report(run))
    if run.requested != run.target:
        print(f"railcheck: {run.requested} exists; results written to {run.target} (use --force to replace)",
              file=sys.stderr)
    return run.exit_status


def _cmd_bench(args) -> int:

    out = run_bench(args.order, args.size, args.solver)
    print(to_json(out) if args.json else bench_report(out))
    return EXIT_PASS


def _cmd_convergence(args) -> int:

    result = run_convergence(args.target, args.orders, args.sizes,
                             progress=lambda m: print(m, file=sys.stderr, flush=True))
    if args.plot and args.target != "kinematics":
        plot_study(result["rows"], args.target, args.plot)
    print(to_json(result) if args.json else convergence_report(result))
    if args.plot and not args.json and args.target != "kinematics":
        print(f"wrote {args.plot}")
    return EXIT_PASS


def _cmd_mechanism(args) -> int:

    run = run_mechanism(args.name, args.steps)
    print(mechanism_report(run))
    for path in write_mechanism_outputs(run, args.csv, args.html, args.gif):
        print(f"wrote {path}")
    return EXIT_PASS


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version
    try:
        return version("railcheck")
    except PackageNotFoundError:
        return "unknown"


def _catalogue_epilog() -> str:
    return (f"parts: {', '.join(PARTS)}\nmaterials: {', '.join(MATERIALS)}\neffects: {', '.join(EFFECTS)}\n"
            f"fatigue criteria: {', '.join(CRITERIA)}; surfaces: {', '.join(SURFACE)}\n"
            "`railcheck init` writes a commented starter scene.")


def _mechanism_names() -> list[str]:
    return list(CATALOGUE)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="railcheck", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"railcheck {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("init", help="write a commented starter scene")
    p.add_argument("file", nargs="?", default="scene.toml", help="where to write it (default scene.toml)")
    p.add_argument("--force", action="store_true", help="replace an existing file")
    p.set_defaults(func=_cmd_init)

    p = sub.add_parser("kinematics", help="kinematics, joint reactions and motor torque over a crank revolution")
    p.add_argument("scene", nargs="?", help="scene TOML file (default: the built-in seed final design)")
    p.add_argument("--json", action="store_true", help="print one JSON object to stdout")
    p.add_argument("--plots", metavar="DIR", help="write PNG plots of reactions, torque, angles into DIR")
    p.set_defaults(func=_cmd_kinematics)

    p = sub.add_parser("check", help="reactions -> bolt loads -> FE stress verdict for every part",
                       description="Reactions over the whole crank cycle -> bolt loads -> FE stress envelope, "
                                   "deflection and fatigue per part.", epilog=_catalogue_epilog(),
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene", nargs="?", help="scene TOML file (default: the built-in seed final design)")
    p.add_argument("--out", metavar="DIR", help="results directory (default: the scene's output.dir)")
    p.add_argument("--json", action="store_true", help="print summary.json to stdout")
    p.add_argument("--force", action="store_true", help="overwrite an existing results directory")
    p.add_argument("--jobs", type=int, metavar="N",
                   help="parts checked at once in worker processes (default: one per core, at most 2)")
    p.set_defaults(func=_cmd_check)

    p = sub.add_parser("sweep", help="every setting of the rig: checks, verdict, safe speed, motor, bearings",
                       description="Every bar length the rails' holes allow (narrowed by the scene's [sweep]): "
                                   "configuration checks, reactions, motor torque, bearing life and, by "
                                   "superposition of unit loads, each part's stress and fatigue verdict and the "
                                   "safe crank speed. Writes a table per linkage kind, maps and summary.json.")
    p.add_argument("scene", nargs="?", help="scene TOML file (default: the built-in scene, the whole rig at 1 Hz)")
    p.add_argument("--out", metavar="DIR", help="results directory (default: sweep)")
    p.add_argument("--json", action="store_true", help="print summary.json to stdout")
    p.add_argument("--force", action="store_true", help="overwrite an existing results directory")
    p.add_argument("--scheduler", metavar="ADDR", help="a running Dask scheduler, e.g. tcp://host:8786 "
                                                     "(default: a local cluster for large sweeps)")
    p.add_argument("--workers", type=int, metavar="N", help="local Dask workers (default: one per core)")
    p.add_argument("--serial", action="store_true", help="run in this process, without Dask")
    p.set_defaults(func=_cmd_sweep)

    p = sub.add_parser("bench", help="FE benchmarks against analytic solutions")
    bsub = p.add_subparsers(dest="bench", required=True, parser_class=_Parser)
    c = bsub.add_parser("cantilever", help="steel cantilever 700 x 23 x 20 mm, 100 N tip load, vs Timoshenko")
    c.add_argument("--order", type=int, choices=(1, 2), default=2)
    c.add_argument("--size", type=float, default=4.0, metavar="MM", help="mesh size in mm (default 4)")
    c.add_argument("--json", action="store_true")
    c.add_argument("--solver", choices=("auto", "direct", "amg"), default="auto")
    p.set_defaults(func=_cmd_bench)

    p = sub.add_parser("convergence", help="accuracy against time: mesh and step convergence study")
    p.add_argument("target", nargs="?", default="cantilever",
                   help="cantilever, kinematics, or a part of the default scene")
    p.add_argument("--orders", default="1,2", help="elements: 1 (P1), 2 (curved P2), 2s (straight-sided P2), e.g. 1,2,2s")
    p.add_argument("--sizes", default=None, help="mesh sizes in mm, e.g. 8,6,4,3")
    p.add_argument("--json", action="store_true")
    p.add_argument("--plot", metavar="FILE", help="write a log-log plot of error against time")
    p.set_defaults(func=_cmd_convergence)

    p = sub.add_parser("mechanism", help="general planar mechanisms of the catalogue (seed 002)")
    p.add_argument("name", help=f"catalogue name: {', '.join(_mechanism_names())}")
    p.add_argument("--steps", type=int, default=361, help="driver steps over the sweep (default 361)")
    p.add_argument("--csv", metavar="FILE", help="tracer path, velocity and acceleration (SI) as CSV")
    p.add_argument("--html", metavar="FILE", help="a self-contained interactive page with a slider")
    p.add_argument("--gif", metavar="FILE", help="an animation of the mechanism")
    p.set_defaults(func=_cmd_mechanism)
    return parser


def _terminate(signum, frame):
    """SIGTERM unwinds like Ctrl-C, so staging directories are removed on the way out."""
    raise _Terminated()


class _Terminated(KeyboardInterrupt):
    pass


def main(argv: list[str] | None = None) -> int:
    """Run one command; every error becomes one line on stderr and an exit status."""
    import signal

    parser = build_parser()
    if not (sys.argv[1:] if argv is None else argv):
        parser.print_help()
        return EXIT_INPUT
    args = parser.parse_args(argv)
    previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        _check_output_options(args)
        return int(args.func(args))
    except (RailcheckError, OSError, KeyboardInterrupt) as exc:
        return _report_error(exc)
    finally:
        signal.signal(signal.SIGTERM, previous)


def _report_error(exc: BaseException) -> int:
    """One line on stderr for an error that ends a run, and its exit status."""
    if isinstance(exc, BrokenPipeError):     # `railcheck ... | head`: end quietly
        import os
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_PASS
    if isinstance(exc, RailcheckError):
        print(f"railcheck: {exc.label}: {exc}", file=sys.stderr)
        return exc.exit_status
    if isinstance(exc, OSError):             # a full disk, a vanished directory: nothing half-written
        print(f"railcheck: error: cannot write {exc.filename or 'the results'}: {exc.strerror or exc}",
              file=sys.stderr)
        return EXIT_INPUT
    terminated = isinstance(exc, _Terminated)
    print(f"railcheck: {'terminated' if terminated else 'interrupted'}", file=sys.stderr)
    return 143 if terminated else 130


if __name__ == "__main__":
    sys.exit(main())
