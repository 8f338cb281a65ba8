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


def test_the_readme_is_a_front_door_whose_links_resolve():
    """A README of about 250 lines at most, every relative link in it and in docs/ to a
    file that exists (#24)."""
    import re

    readme = ROOT / "README.md"
    assert len(readme.read_text().splitlines()) <= 250
    quick_start = set(quick_start_commands())  # CI's two commands, each one line
    long = [line for line in readme.read_text().splitlines() if len(line) > 120 and line not in quick_start]
    assert not long, f"README lines over 120 characters: {long}"
    for page in [readme, *sorted((ROOT / "docs").glob("*.md"))]:
        for target in re.findall(r"\]\(([^)#:]+)(?:#[^)]*)?\)", page.read_text()):
            assert (page.parent / target).exists(), f"{page.name} links to a missing {target}"


def _anchors(page: Path) -> set[str]:
    """GitHub's anchors of a markdown page: each heading's slug (lower case, punctuation
    dropped but hyphens and underscores, spaces as hyphens) and every explicit id."""
    text = page.read_text()
    slugs = set(re.findall(r'<a id="([^"]+)"', text))
    for heading in re.findall(r"(?m)^#+ (.+)$", text):
        slugs.add(re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-"))
    return slugs


def test_every_anchor_a_page_links_to_exists():
    for page in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        for target, anchor in re.findall(r"\]\(([^)#:]*\.md)#([^)]+)\)", page.read_text()):
            assert anchor in _anchors(page.parent / target), f"{page.name} links to a missing {target}#{anchor}"


def test_the_timings_are_one_table_the_benchmark_writes(tmp_path):
    """docs/performance.md is the current figures (about 300 lines at most) with one
    timings block, which benchmarks/check_store.py --write fills with its own table."""
    import importlib.util

    text = (ROOT / "docs" / "performance.md").read_text()
    assert len(text.splitlines()) <= 300
    assert text.count("<!-- timings -->\n") == 1 and text.count("<!-- /timings -->") == 1
    spec = importlib.util.spec_from_file_location("check_store", ROOT / "benchmarks" / "check_store.py")
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    page = tmp_path / "p.md"
    page.write_text(text)
    bench.write_table(page, {"check, cold, json only (s)": "47.20", "warm / cold, json only": "0.048"}, "one run.")
    inside = lambda s: s.split("<!-- timings -->\n")[1].split("<!-- /timings -->")[0]  # noqa: E731
    table = "| figure | value |\n| --- | --- |\n"
    table += "| check, cold, json only (s) | 47.20 |\n| warm / cold, json only | 0.048 |\n"
    assert inside(page.read_text()) == "one run.\n\n" + table
    assert page.read_text().replace(inside(page.read_text()), "") == text.replace(inside(text), "")  # nothing else
