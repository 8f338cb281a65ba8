"""The README's Quick start and .ci/run agree: CI runs exactly the two documented lines."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def quick_start_commands():
    text = (ROOT / "README.md").read_text()
    block = re.search(r"(?is)## Quick start.*?```bash\n(.*?)```", text).group(1)
    return [l.strip() for l in block.splitlines() if l.strip() and not l.strip().startswith("#")]


def test_quick_start_has_two_commands_and_ci_runs_them():
    cmds = quick_start_commands()
    assert len(cmds) == 2
    assert "railcheck check" in cmds[0] and "pytest" in cmds[1]
    ci = (ROOT / ".ci" / "run").read_text().splitlines()
    for c in cmds:
        assert c in ci, c
