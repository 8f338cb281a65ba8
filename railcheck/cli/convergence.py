"""``railcheck convergence [TARGET]``: what accuracy costs in time (mesh or step study)."""

from __future__ import annotations

import sys

from railcheck.base.errors import EXIT_PASS
from railcheck.files import to_json
from railcheck.report.text import convergence_report
from railcheck.studies.convergence import plot_study, run_convergence

HELP = "accuracy against time: mesh and step convergence study"


def add_args(p) -> None:
    p.add_argument("target", nargs="?", default="cantilever", help="cantilever, kinematics, or a part of the default scene")
    p.add_argument("--orders", default="1,2", help="elements: 1 (P1), 2 (curved P2), 2s (straight-sided P2), e.g. 1,2,2s")
    p.add_argument("--sizes", default=None, help="mesh sizes in mm, e.g. 8,6,4,3")
    p.add_argument("--json", action="store_true", help="print the study (every row and its errors) as one JSON object")
    p.add_argument("--plot", metavar="FILE", help="write a log-log plot of error against time")


def run(args) -> int:
    result = run_convergence(args.target, args.orders, args.sizes, progress=lambda m: print(m, file=sys.stderr, flush=True))
    if args.plot and args.target != "kinematics":
        plot_study(result["rows"], args.target, args.plot)
    print(to_json(result) if args.json else convergence_report(result))
    if args.plot and not args.json and args.target != "kinematics":
        print(f"wrote {args.plot}")
    return EXIT_PASS
