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
