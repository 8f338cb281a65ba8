"""A package's docstring lists its modules: every module it names exists, and every module
of the check's and the sweep's packages is named (issue 76: docstrings listed modules that
had moved)."""

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "railcheck"


@pytest.mark.parametrize("package", ["check", "sweep"])
def test_the_package_docstring_names_exactly_its_modules(package):
    folder = ROOT / package
    doc = ast.get_docstring(ast.parse((folder / "__init__.py").read_text()))
    named = set(re.findall(r":mod:`\.(\w+)`", doc))
    modules = {p.stem for p in folder.glob("*.py") if p.stem != "__init__"}
    assert named <= modules, f"named but missing: {named - modules}"
    assert modules <= named, f"not named: {modules - named}"
