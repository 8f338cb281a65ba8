"""docs/cli.md: every subcommand's ``--help``, verbatim, from the parser itself.

    python benchmarks/cli_docs.py        # rewrites docs/cli.md

``tests/test_cli_docs.py`` holds the committed page to the parser (so a changed option or
help text fails until this is rerun) and every option the other documents name to the
parser's options. The help is laid out 100 columns wide (``COLUMNS``), whatever the terminal.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

PAGE = Path(__file__).resolve().parents[1] / "docs" / "cli.md"


def page_text() -> str:
    """The page: a heading, then per subcommand its ``--help`` in a code block."""
    os.environ["COLUMNS"] = "100"
    from railcheck.cli import build_parser

    parser = build_parser()
    subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices
    parts = [
        "# The command line\n",
        "Every subcommand's `--help`, as the parser prints it (written by `python benchmarks/cli_docs.py`,",
        "held to the parser by `tests/test_cli_docs.py`).\n",
        "```",
        parser.format_help().rstrip(),
        "```\n",
    ]
    for name, sub in subs.items():
        parts += [f"## `railcheck {name}`\n", "```", sub.format_help().rstrip(), "```\n"]
    return "\n".join(parts)


if __name__ == "__main__":
    PAGE.write_text(page_text(), encoding="utf-8")
    print(f"wrote {PAGE}")
