"""What the subcommands that write a results directory say alike."""

from __future__ import annotations

import sys


def say_where(result) -> None:
    """On stderr, when the results went elsewhere than asked (the directory existed)."""
    if result.requested != result.target:
        print(
            f"railcheck: {result.requested} exists; results written to {result.target} (use --force to replace)",
            file=sys.stderr,
        )


def add_results_args(p, scene_default: str, out_default: str) -> None:
    """The arguments of a subcommand that writes a results directory: the scene, --out,
    --json and --force (defaults named in the help)."""
    p.add_argument("scene", nargs="?", help=f"scene TOML file (default: {scene_default})")
    p.add_argument("--out", metavar="DIR", help=f"results directory (default: {out_default})")
    p.add_argument("--json", action="store_true", help="print summary.json to stdout")
    p.add_argument("--force", action="store_true", help="overwrite an existing results directory")
