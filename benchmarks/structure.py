"""The code's structure as issue 76 counts it, with ``ast``: lines of railcheck/, functions
taking the whole scene (a parameter named ``scene`` or annotated ``Scene``), calls passing a
``scene`` on, ``replace(scene, ...)`` calls, stages testing a part kind by its name, and the
railcheck modules the tests import. Over this checkout or another one (a git worktree of an
earlier commit):

    python benchmarks/structure.py [CHECKOUT ...]
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOMAIN = ("fea", "geometry", "loads", "kinematics")
PART_KINDS = {"rail", "joint_plate", "i_profile", "bar"}


def _takes_scene(node: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    args = node.args.args + node.args.kwonlyargs
    return any(a.arg == "scene" or (a.annotation is not None and ast.unparse(a.annotation) == "Scene") for a in args)


def _passes_scene(node: ast.Call) -> bool:
    values = list(node.args) + [k.value for k in node.keywords]
    return any(isinstance(v, ast.Name) and v.id == "scene" for v in values)


def _replaces_scene(node: ast.Call) -> bool:
    return ast.unparse(node.func).endswith("replace") and bool(node.args) and ast.unparse(node.args[0]) == "scene"


def _tests_kind(node: ast.Compare, path: Path) -> bool:
    if not (isinstance(node.left, ast.Attribute) and node.left.attr == "kind"):
        return False
    names = {c.value for c in node.comparators if isinstance(c, ast.Constant)}
    return bool(names & PART_KINDS) and "geometry" not in path.parts and path.name != "parts.py"


def counts(root: Path) -> dict[str, int]:
    """The figures over the checkout at ``root``."""
    app = sorted((root / "railcheck").rglob("*.py"))
    code = app + [p for d in DOMAIN for p in sorted((root / d).rglob("*.py"))]
    out = dict.fromkeys(("functions", "passes", "replaces", "kind tests"), 0)
    for path in code:
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                out["functions"] += _takes_scene(node)
            elif isinstance(node, ast.Call):
                out["passes"] += _passes_scene(node)
                out["replaces"] += _replaces_scene(node)
            elif isinstance(node, ast.Compare):
                out["kind tests"] += _tests_kind(node, path)
    imported = set()
    for path in (root / "tests").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("railcheck"):
                imported.add(node.module)
            elif isinstance(node, ast.Import):
                imported |= {a.name for a in node.names if a.name.startswith("railcheck")}
    return {
        "lines of railcheck/": sum(len(p.read_text().splitlines()) for p in app),
        "functions taking the whole scene": out["functions"],
        "calls passing the scene on": out["passes"],
        "replace(scene, ...) calls": out["replaces"],
        "stages testing a part kind by its name": out["kind tests"],
        "railcheck modules the tests import": len(imported),
    }


def main() -> None:
    roots = [Path(a) for a in sys.argv[1:]] or [ROOT]
    table = {root: counts(root) for root in roots}
    print("| figure | " + " | ".join(str(r) for r in roots) + " |")
    print("| --- |" + " --- |" * len(roots))
    for figure in table[roots[0]]:
        print(f"| {figure} | " + " | ".join(str(table[r][figure]) for r in roots) + " |")


if __name__ == "__main__":
    main()
