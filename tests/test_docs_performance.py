"""docs/performance.md's tables are the benchmarks' own blocks (written by ``--write``), and
every ratio in them is the quotient of the figures beside it: a hand edit of one figure, or a
figure pasted from another run, fails here (issue 78, item 6)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

PAGE = Path(__file__).resolve().parents[1] / "docs" / "performance.md"


def _block(name: str) -> dict[str, list[str]]:
    """The ``<!-- name -->`` block's table: figure -> its cells."""
    text = PAGE.read_text().split(f"<!-- {name} -->", 1)[1].split(f"<!-- /{name} -->", 1)[0]
    rows = [line.strip("|").split("|") for line in text.splitlines() if line.startswith("| ") and "---" not in line]
    return {cells[0].strip(): [c.strip() for c in cells[1:]] for cells in rows[1:]}


def _value(cell: str) -> str:
    """The number a cell starts with, as printed."""
    return re.match(r"[\d.,]+", cell).group().replace(",", "")


def _half_digit(printed: str) -> float:
    """Half the unit of ``printed``'s last digit: how far the unrounded figure can lie."""
    digits = len(printed.split(".")[1]) if "." in printed else 0
    return 0.5 * 10**-digits


def _close(num: str, den: str, printed: str) -> bool:
    """The printed ratio ``printed`` is num / den for some unrounded num and den within
    their printed rounding (the benchmark divides its unrounded medians)."""
    n, d, r = float(num), float(den), float(printed)
    lo = (n - _half_digit(num)) / (d + _half_digit(den))
    hi = (n + _half_digit(num)) / (d - _half_digit(den))
    return lo - _half_digit(printed) <= r <= hi + _half_digit(printed)


def test_the_first_runs_ratios_are_their_figures_quotients():
    rows = _block("first-check")
    before = _value(rows["cold default check, the code before (s)"][0])
    cold = _value(rows["cold default check, this code (s)"][0])
    checks = {
        "cold default check, this code (s)": before,
        "another setting after it, json only (s)": cold,
        "another setting after it, every file (s)": cold,
        "whole rig from an empty cache (s)": cold,
    }
    for figure, reference in checks.items():
        value, ratio = _value(rows[figure][0]), re.match(r"([\d.]+)x", rows[figure][1]).group(1)
        assert _close(value, reference, ratio), (figure, value, ratio)


def test_the_timings_ratios_are_their_figures_quotients():
    rows = {k: _value(v[0]) for k, v in _block("timings").items()}
    pairs = {
        "warm / cold, json only": ("check, warm, json only (s)", "check, cold, json only (s)"),
        "warm / cold, every file": ("check, warm, every file (s)", "check, cold, every file (s)"),
        "whole rig / cold check, json only": ("whole rig, store warm (s)", "check, cold, json only (s)"),
    }
    text = {k: v[0] for k, v in _block("timings").items()}
    for ratio, (num, den) in pairs.items():
        assert _close(rows[num], rows[den], text[ratio]), ratio


@pytest.mark.parametrize("name", ["first-check", "timings"])
def test_each_block_names_the_command_that_wrote_it(name):
    text = PAGE.read_text().split(f"<!-- {name} -->", 1)[1]
    assert text.lstrip().startswith("`python benchmarks/")


MUTATION = PAGE.parent / "mutation.md"


def _fractions(cell: str) -> list[tuple[int, int, str]]:
    """Every ``a/b (p%)`` in a cell: (a, b, p as printed)."""
    return [(int(a), int(b), p) for a, b, p in re.findall(r"(\d+)/(\d+) \(([\d.]+)%", cell)]


def test_the_mutation_scores_agree_with_themselves():
    """docs/mutation.md's one run: each percentage is its fraction, each module's survivors
    are its mutants less those killed, and the totals are the modules' sums."""
    tables = MUTATION.read_text().split("## Scores", 1)[1].split("Notes on the columns", 1)[0]
    raw = [line.strip("|").split("|") for line in tables.splitlines() if line.startswith("| `railcheck.")]
    scores = [r for r in raw if len(r) == 5]
    assert len(scores) == 8
    for module, mutants, _, after, survivors in scores:
        (killed, total, pct), *_ = _fractions(after)
        assert total == int(mutants) and int(survivors) == total - killed, module
    for line in tables.splitlines():
        for a, b, p in _fractions(line):
            assert abs(100 * a / b - float(p)) <= _half_digit(p), line
    total = next(line for line in tables.splitlines() if line.startswith("| all | 678"))
    assert int(total.split("|")[2]) == sum(int(r[1]) for r in scores)
    assert int(total.split("|")[5]) == sum(int(r[4]) for r in scores)
    assert f"{sum(_fractions(r[3])[0][0] for r in scores)}/678" in total


def test_the_planar_ratios_are_their_figures_quotients():
    text = PAGE.read_text().split("<!-- planar -->", 1)[1].split("<!-- /planar -->", 1)[0]
    assert text.lstrip().startswith("`python benchmarks/planar.py`")
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in text.splitlines() if line.startswith("| ")]
    rows = [r for r in rows[1:] if not r[0].startswith("---")]
    base = {r[0]: _value(r[2]) for r in rows if r[1] == "railcheck closed form"}
    assert set(base) == {"four-bar", "Watt six-bar"}
    for mechanism, tool, time, ratio, _ in rows:
        assert _close(_value(time), base[mechanism], ratio), (mechanism, tool)
