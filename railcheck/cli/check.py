"""``railcheck check [SCENE]``: the main job (:func:`railcheck.check.run.run_check`)."""

from __future__ import annotations

import argparse

from railcheck.base.errors import InputError
from railcheck.check.run import run_check
from railcheck.cli.common import add_results_args, say_where
from railcheck.fea.fatigue import CRITERIA, SURFACE
from railcheck.fea.materials import MATERIALS
from railcheck.files import to_json
from railcheck.parts import COMPONENTS, PARTS
from railcheck.progress import Progress
from railcheck.report.text import check_report
from railcheck.scene import EFFECTS, load_scene

HELP = "reactions -> bolt loads -> FE stress verdict for every part"
PARSER = {
    "description": "Reactions over the whole crank cycle -> bolt loads -> FE stress envelope, deflection "
    "and fatigue per part.",
    "epilog": f"parts: {', '.join(PARTS)}\ncomponents ([check] parts too; docs/components.md): {', '.join(COMPONENTS)}\n"
    f"materials: {', '.join(MATERIALS)}\neffects: {', '.join(EFFECTS)}\n"
    f"fatigue criteria: {', '.join(CRITERIA)}; surfaces: {', '.join(SURFACE)}\n"
    "railcheck init writes a commented starter scene.\n"
    "results: --out DIR, else the scene's [output] dir (default results/; an existing folder is kept and the run "
    "goes to DIR-2, unless --force)\n"
    "exit status: 0 every check passes, 1 a configuration check or a part fails, 2 bad input (one line naming "
    "the field), 3 numerical failure",
    "formatter_class": argparse.RawDescriptionHelpFormatter,
}


def add_args(p) -> None:
    add_results_args(p, "the built-in scene: the 2013 design study's final rig", "the scene's output.dir")
    p.add_argument(
        "--jobs", type=int, metavar="N", help="parts checked at once in worker processes (default: one per core, at most 2)"
    )


def run(args) -> int:
    if args.jobs is not None and args.jobs < 1:
        raise InputError("--jobs", f"must be at least 1, got {args.jobs}")
    result = run_check(load_scene(args.scene), args.out, args.force, Progress(quiet=False), args.jobs)
    print(to_json(result.summary) if args.json else check_report(result))
    say_where(result)
    return result.exit_status
