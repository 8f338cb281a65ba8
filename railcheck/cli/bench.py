"""``railcheck bench cantilever``: the FE core against Timoshenko beam theory."""

from __future__ import annotations

from railcheck.base.errors import EXIT_PASS
from railcheck.files import to_json
from railcheck.report.text import bench_report
from railcheck.studies.bench import run_bench

HELP = "FE benchmarks against analytic solutions"


def add_args(p) -> None:
    bench = p.add_subparsers(dest="bench", required=True, parser_class=type(p), help="the benchmark to run")
    c = bench.add_parser("cantilever", help="steel cantilever 700 x 23 x 20 mm, 100 N tip load, vs Timoshenko")
    c.add_argument("--order", type=int, choices=(1, 2), default=2, help="tetrahedra's order (default 2)")
    c.add_argument("--size", type=float, default=4.0, metavar="MM", help="mesh size in mm (default 4)")
    c.add_argument("--json", action="store_true", help="print the result as one JSON object")
    c.add_argument(
        "--solver",
        choices=("auto", "direct", "amg"),
        default="auto",
        help="linear solver (default auto: direct, or multigrid for a large P2 system or a factor beyond memory)",
    )


def run(args) -> int:
    out = run_bench(args.order, args.size, args.solver)
    print(to_json(out) if args.json else bench_report(out))
    return EXIT_PASS
