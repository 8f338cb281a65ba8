"""``railcheck sweep [SCENE]``: every setting of the rig (:func:`railcheck.sweep.run.run_sweep`)."""

from __future__ import annotations

import argparse

from railcheck.base.errors import InputError
from railcheck.cli.common import add_results_args, say_where
from railcheck.files import to_json
from railcheck.progress import Progress
from railcheck.report.text import sweep_report
from railcheck.scene import load_scene
from railcheck.sweep.run import run_sweep

HELP = "every setting of the rig: checks, verdict, safe speed, motor, bearings"
PARSER = {
    "description": "Every bar length the rails' holes allow (narrowed by the scene's [sweep]): configuration "
    "checks, reactions, motor torque, bearing life and, by superposition of unit loads, each "
    "part's stress and fatigue verdict and the safe crank speed. Writes a table per linkage "
    "kind, maps, report.html, rig.html (pick a setting: its verdict and safe speed) and summary.json.",
    "epilog": "where it runs: on processes forked from this one, one per core (Linux; --workers N, --serial\n"
    "one), on --scheduler ADDR, or, where this process cannot fork, on a Dask local cluster when the\n"
    "sweep is large and else on this process's threads: the same tables bit for bit.\n"
    "exit status: 0 at least one setting of every linkage kind passes, 1 none of a kind does,\n"
    "2 bad input (one line naming the field), 3 numerical failure",
    "formatter_class": argparse.RawDescriptionHelpFormatter,
}


def add_args(p) -> None:
    add_results_args(p, "the built-in scene, the whole rig at 1 Hz", "sweep")
    p.add_argument(
        "--scheduler",
        metavar="ADDR",
        help="a running Dask scheduler, e.g. tcp://host:8786 (default: processes forked from this one)",
    )
    p.add_argument(
        "--workers",
        type=int,
        metavar="N",
        help="local workers: forked processes (or Dask workers, threads where neither applies); at most one "
        "per core (the default)",
    )
    p.add_argument("--serial", action="store_true", help="run in this process on one thread, without Dask")


def run(args) -> int:
    if args.workers is not None and args.workers < 1:
        raise InputError("--workers", f"must be at least 1, got {args.workers}")
    result = run_sweep(
        load_scene(args.scene), args.out, args.force, args.scheduler, args.workers, args.serial, Progress(quiet=False)
    )
    print(to_json(result.summary) if args.json else sweep_report(result))
    say_where(result)
    return result.exit_status
