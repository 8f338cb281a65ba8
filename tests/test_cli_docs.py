"""The command line and its documents cannot disagree (issue 78 item 6): docs/cli.md is
every subcommand's ``--help`` as the parser prints it (``benchmarks/cli_docs.py`` writes
it), so every option is documented with its help text; and every option the README and
the other docs/ pages give a command exists in that command's parser."""

import argparse
import re
from pathlib import Path

from helpers import benchmark_module
from railcheck.cli import build_parser

ROOT = Path(__file__).resolve().parents[1]


def _script():
    return benchmark_module("cli_docs")


def _options() -> dict[str, set[str]]:
    parser = build_parser()
    subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices
    return {
        n: {o for a in sp._actions for o in a.option_strings if o.startswith("--") and o != "--help"}
        for n, sp in subs.items()
    }


def test_the_cli_page_is_the_parsers_help(monkeypatch):
    monkeypatch.setenv("COLUMNS", "100")
    page = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    assert page == _script().page_text(), "rerun python benchmarks/cli_docs.py"
    for sub, options in _options().items():  # each command's options, each under its own heading
        section = page.split(f"## `railcheck {sub}`")[1].split("## `railcheck ")[0]
        assert all(re.search(rf"(?<![\w-]){re.escape(o)}\b", section) for o in options), sub


def test_the_documents_give_no_option_a_command_does_not_have():
    options = _options()
    pages = [ROOT / "README.md", *sorted(p for p in (ROOT / "docs").glob("*.md") if p.name != "cli.md")]
    for page in pages:
        for sub, rest in re.findall(r"railcheck ([a-z]+)([^`\n]*)", page.read_text(encoding="utf-8")):
            if sub in options:
                named = set(re.findall(r"(?<![\w-])--[a-z][a-z-]*", rest)) - {"--help"}
                assert named <= options[sub], (page.name, sub, sorted(named - options[sub]), rest)
