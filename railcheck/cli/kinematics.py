"""``railcheck kinematics [SCENE]``: motion, joint reactions and motor torque over one crank
revolution, the configuration checks and the peaks; exit 1 when a check fails."""

from __future__ import annotations

from pathlib import Path

from railcheck.base.errors import EXIT_FAIL, EXIT_PASS, InputError
from railcheck.files import to_json
from railcheck.model.kinematics_stage import kinematics_input, kinematics_summary, run_kinematics
from railcheck.report.plots import write_kinematics_plots
from railcheck.report.text import kinematics_table
from railcheck.scene import load_scene

HELP = "kinematics, joint reactions and motor torque over a crank revolution"
PARSER = {
    "description": "Positions, velocities, accelerations, joint reactions and motor torque over one crank "
    "revolution, the configuration checks, and the peaks with their crank angles (no FE).",
    "epilog": "exit status: 0 every configuration check passes, 1 one fails, 2 bad input or an impossible "
    "mechanism (one line naming the field).",
}


def add_args(p) -> None:
    p.add_argument(
        "scene", nargs="?", help="scene TOML file (default: the built-in scene, the 2013 design study's final rig)"
    )
    p.add_argument("--json", action="store_true", help="print one JSON object to stdout")
    p.add_argument("--plots", metavar="DIR", help="write PNG plots of reactions, torque, angles into DIR")


def run(args) -> int:
    scene = load_scene(args.scene)
    if scene.mechanism is None:
        raise InputError("mechanism", "missing: `railcheck kinematics` needs a [mechanism] table")
    result = run_kinematics(kinematics_input(scene))
    summary = kinematics_summary(scene.linkage_spec, result)
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
