"""``railcheck mechanism NAME``: a seed 002 catalogue mechanism in body coordinates."""

from __future__ import annotations

from railcheck.base.errors import EXIT_PASS
from railcheck.kinematics.planar.catalogue import CATALOGUE
from railcheck.report.text import mechanism_report
from railcheck.studies.mechanism import run_mechanism, write_mechanism_outputs

HELP = "general planar mechanisms in body coordinates (the catalogue of the mechanisms study)"


def add_args(p) -> None:
    p.add_argument("name", help=f"catalogue name ({', '.join(CATALOGUE)}) or a scene .toml: its own linkage")
    p.add_argument("--steps", type=int, default=361, help="driver steps over the sweep (default 361)")
    p.add_argument("--csv", metavar="FILE", help="tracer path, velocity and acceleration (SI) as CSV")
    p.add_argument("--html", metavar="FILE", help="a self-contained interactive page with a slider")
    p.add_argument("--gif", metavar="FILE", help="an animation of the mechanism")


def run(args) -> int:
    result = run_mechanism(args.name, args.steps)
    print(mechanism_report(result))
    for path in write_mechanism_outputs(result, args.csv, args.html, args.gif):
        print(f"wrote {path}")
    return EXIT_PASS
