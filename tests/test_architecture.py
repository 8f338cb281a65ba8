"""The layout's rules, read from the source: no import cycles between our modules, each
domain package imports only what is upstream of it (kinematics -> loads -> geometry ->
fea, and the one error base), heavy packages only inside the functions that need them,
our own modules imported at module top, and each package's public API importable."""

import ast
import importlib
import re
from pathlib import Path

import pytest

from helpers import ROOT, package_dirs

HEAVY = {
    "gmsh",
    "skfem",
    "pyvista",
    "vtk",
    "vtkmodules",
    "meshio",
    "pyamg",
    "matplotlib",
    "dask",
    "distributed",
    "pyarrow",
    "pypardiso",
}
#: what each domain package may import of ours (besides itself): the packages upstream of it
BASE = {"railcheck.base"}  # the error base and the machine's memory: any layer
UPSTREAM = {
    "railcheck.kinematics": BASE,
    "railcheck.loads": BASE | {"railcheck.kinematics"},
    "railcheck.geometry": BASE | {"railcheck.kinematics", "railcheck.loads"},
    "railcheck.fea": BASE | {"railcheck.kinematics", "railcheck.loads", "railcheck.geometry"},
}


def our_modules() -> dict[str, Path]:
    """Every module of the installed package, dotted name -> file."""
    out = {}
    for pkg, folder in package_dirs().items():
        for path in folder.glob("*.py"):
            out[pkg if path.stem == "__init__" else f"{pkg}.{path.stem}"] = path
    return out


def imports_of(name: str, path: Path, modules: dict) -> list[tuple[str, bool, str | None]]:
    """(our module imported, at module level?, third-party top name) for each import."""
    tree = ast.parse(path.read_text())
    package = name if path.stem == "__init__" else name.rsplit(".", 1)[0]
    out = []

    def visit(node, in_function: bool):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and "TYPE_CHECKING" in ast.unparse(child.test):
                continue
            if isinstance(child, ast.Import):
                for a in child.names:
                    target = a.name
                    out.append((target if target in modules else None, not in_function, target.split(".")[0]))
            elif isinstance(child, ast.ImportFrom) and child.module != "__future__":
                base = package
                for _ in range(max(child.level - 1, 0)):
                    base = base.rsplit(".", 1)[0]
                target = (f"{base}.{child.module}" if child.module else base) if child.level else child.module
                subs = [f"{target}.{a.name}" for a in child.names if f"{target}.{a.name}" in modules]
                for t in subs if len(subs) == len(child.names) else [target, *subs]:
                    out.append((t if t in modules else None, not in_function, t.split(".")[0]))
            visit(child, in_function or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)))

    visit(tree, False)
    return out


def import_graph() -> dict[str, set[str]]:
    modules = our_modules()
    return {name: {t for t, _, _ in imports_of(name, path, modules) if t and t != name} for name, path in modules.items()}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), and self-loops."""
    index, low, stack, on_stack, out = {}, {}, [], set(), []

    def connect(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                connect(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1 or v in graph.get(v, ()):
                out.append(sorted(component))

    for v in graph:
        if v not in index:
            connect(v)
    return out


def test_the_cycle_finder_finds_planted_cycles():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"a"}}) == [["a"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_every_module_is_found():
    modules = our_modules()
    assert {
        "railcheck.cli",
        "railcheck.check.pipeline",
        "railcheck.fea.elasticity",
        "railcheck.geometry.mesher",
        "railcheck.loads.cases",
        "railcheck.kinematics.planar.solver",
        "railcheck.sweep.table",
    } <= set(modules)
    assert len(modules) > 60


def test_no_import_cycles_between_our_modules():
    """Imports inside functions count too: they hid three cycles before."""
    assert cycles(import_graph()) == []


@pytest.mark.parametrize("package", sorted(UPSTREAM))
def test_a_domain_package_imports_only_what_is_upstream_of_it(package):
    allowed = UPSTREAM[package] | {package}
    bad = {
        (name, t)
        for name, targets in import_graph().items()
        if name.startswith(package)
        for t in targets
        if not any(t == a or t.startswith(a + ".") for a in allowed)
    }
    assert not bad


def railcheck_variables(path: Path) -> list[str]:
    """The application's environment variables (string constants RAILCHECK_*) a module names."""
    return [
        node.value
        for node in ast.walk(ast.parse(path.read_text()))
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value.startswith("RAILCHECK_")
    ]


@pytest.mark.parametrize("package", sorted(UPSTREAM))
def test_a_domain_package_reads_no_application_variable(package):
    """The application resolves RAILCHECK_* (railcheck.environment) and passes the values."""
    bad = {name: railcheck_variables(path) for name, path in our_modules().items() if name.startswith(package + ".")}
    assert not {name: v for name, v in bad.items() if v}


def test_the_variable_finder_finds_a_planted_read(tmp_path):
    planted = tmp_path / "m.py"
    planted.write_text('import os\nx = os.environ.get("RAILCHECK_CACHE")\n')
    assert railcheck_variables(planted) == ["RAILCHECK_CACHE"]


def test_the_base_imports_nothing_of_ours():
    """railcheck.base is below every layer: errors and machine limits, nothing else of ours."""
    bad = {
        (name, t)
        for name, targets in import_graph().items()
        if name.startswith("railcheck.base")
        for t in targets
        if not t.startswith("railcheck.base")
    }
    assert not bad


def test_heavy_packages_are_imported_only_inside_functions():
    modules = our_modules()
    bad = [
        (name, top)
        for name, path in modules.items()
        for _, module_level, top in imports_of(name, path, modules)
        if module_level and top in HEAVY
    ]
    assert not bad


def test_our_own_modules_are_imported_at_module_top():
    modules = our_modules()
    bad = [
        (name, t)
        for name, path in modules.items()
        for t, module_level, _ in imports_of(name, path, modules)
        if t and not module_level
    ]
    assert not bad


@pytest.mark.parametrize(
    "package",
    [
        "railcheck.fea",
        "railcheck.geometry",
        "railcheck.loads",
        "railcheck.kinematics",
        "railcheck.kinematics.planar",
        "railcheck.check",
        "railcheck.sweep",
        "railcheck.parallel",
        "railcheck.fea.screening",
    ],
)
def test_each_public_name_imports(package):
    module = importlib.import_module(package)
    assert module.__all__ and sorted(set(module.__all__)) == sorted(module.__all__)
    for name in module.__all__:
        assert getattr(module, name) is not None


#: the house's sizes: a module a reader can hold, a function that does one job
MAX_MODULE_LINES = 600
MAX_FUNCTION_LINES = 60


def oversized(path: Path) -> list[str]:
    """What in one module is over the house's sizes: the module itself (lines) and each
    function or method (from its ``def`` to its last line, docstring included)."""
    text = path.read_text()
    out = [f"{path.name}: {len(text.splitlines())} lines"] if len(text.splitlines()) > MAX_MODULE_LINES else []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            lines = node.end_lineno - node.lineno + 1
            if lines > MAX_FUNCTION_LINES:
                out.append(f"{path.name}:{node.lineno} {node.name}: {lines} lines")
    return out


def test_the_size_rule_finds_a_planted_long_function_and_module(tmp_path):
    body = "\n".join(f"    x{i} = {i}" for i in range(MAX_FUNCTION_LINES))
    long = tmp_path / "long.py"
    long.write_text(f"def f():\n{body}\n" + "\n" * MAX_MODULE_LINES)
    assert [s.split(":")[0] for s in oversized(long)] == ["long.py", "long.py"]
    short = tmp_path / "short.py"
    short.write_text("def f():\n    return 1\n")
    assert oversized(short) == []


def test_no_module_over_600_lines_and_no_function_over_60():
    """Every module of the installed package (the domain packages and the application)."""
    bad = [s for path in our_modules().values() for s in oversized(path)]
    assert not bad, bad


def private_reaches(path: Path) -> list[str]:
    """What a test module reaches that is private to railcheck: ``from railcheck... import
    _name``, and ``monkeypatch.setattr(module, "_name", ...)``."""
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("railcheck"):
            out += [f"import {node.module}.{a.name}" for a in node.names if a.name.startswith("_")]
        elif isinstance(node, ast.Call) and ast.unparse(node.func).endswith("setattr") and len(node.args) >= 2:
            name = node.args[1]
            if isinstance(name, ast.Constant) and isinstance(name.value, str) and name.value.startswith("_"):
                out.append(f"setattr {ast.unparse(node.args[0])}.{name.value}")
    return out


def test_the_private_finder_finds_a_planted_import_and_patch(tmp_path):
    planted = tmp_path / "test_x.py"
    planted.write_text('from railcheck.sweep.run import _hidden\nmonkeypatch.setattr(run, "_hidden", 1)\n')
    assert private_reaches(planted) == ["import railcheck.sweep.run._hidden", "setattr run._hidden"]


def test_no_test_reaches_a_private_name_of_railcheck():
    """The tests use public seams; a private name a test needs is an API hiding there."""
    bad = {p.name: private_reaches(p) for p in sorted((ROOT / "tests").rglob("test_*.py"))}
    assert not {name: found for name, found in bad.items() if found}


def test_no_second_copy_of_the_package_and_no_tests_inside_it():
    for name in ("railcheck.railcheck", "railcheck.tests", "railcheck.benchmarks"):
        with pytest.raises(ModuleNotFoundError):
            importlib.import_module(name)


DEVELOPMENT = ROOT / "docs" / "development.md"  # the README's development page


def readme_layout() -> set[str]:
    """The paths the development page's Layout section lists (folders end with /)."""
    text = DEVELOPMENT.read_text()
    block = text.split("## Layout", 1)[1].split("```", 2)[1]
    paths, parents = set(), []
    for line in block.splitlines():
        if not line.strip():
            continue
        depth = (len(line) - len(line.lstrip())) // 2
        parents = parents[:depth]
        names = [w for w in line.split() if w.endswith((".py", "/"))]
        listed = names if all(n.endswith(".py") for n in names) else names[:1]
        for name in listed:
            paths.add("".join(parents) + name)
        if names and names[0].endswith("/"):
            parents.append(names[0])
    return paths


def test_the_readme_layout_matches_the_tree():
    listed = readme_layout()
    missing = sorted(p for p in listed if not (ROOT / p).exists())
    assert not missing, f"listed in the README but not in the tree: {missing}"
    modules = {str(path.relative_to(ROOT)) for path in our_modules().values()}
    unlisted = sorted(m for m in modules if not m.endswith(("__init__.py", "__main__.py")) and m not in listed)
    assert not unlisted, f"in the tree but not in the README's Layout: {unlisted}"


@pytest.mark.slow  # 3.7 s (a P2 solve): the README's example, not a regression check; the fast tier stays under 90 s
def test_the_readme_fe_api_example_runs_with_public_names():
    """The development page's FE API example (a torque as a traction) runs as printed."""
    text = DEVELOPMENT.read_text()
    code = text.split("### The FE API", 1)[1].split("```python\n", 1)[1].split("```", 1)[0]
    assert "import _" not in code and "._" not in code
    scope: dict = {}
    exec(compile(code, "docs/development.md", "exec"), scope)
    assert 20e6 < scope["value"] < 80e6  # von Mises of a 50 N·m torque on a 23 x 20 mm bar


def test_a_package_docstring_names_only_modules_it_holds():
    """Every :mod:`.name` in a package's docstring is a module or package inside it (the
    docstrings of check/ and sweep/ listed modules that had moved)."""
    missing = []
    for package, folder in package_dirs().items():
        text = ast.get_docstring(ast.parse((folder / "__init__.py").read_text())) or ""
        for name in re.findall(r":mod:`\.(\w+)`", text):
            if not (folder / f"{name}.py").exists() and not (folder / name).is_dir():
                missing.append(f"{package}: .{name}")
    assert not missing, missing


OUTSIDE = re.compile("DESIGN" + r"(\.md| §)|\.\./" + "shared")  # split so this file does not match itself
TEXT_SUFFIXES = {".py", ".md", ".toml", ".txt", ".html", ".js", ".cfg", ".yml", ".yaml"}


def _outside_references(root: Path) -> list[str]:
    """Every ``file:line`` under ``root`` that names a document a clone does not hold."""
    skip = {".git", ".venv", "venv", "results", "__pycache__", ".pytest_cache", ".mypy_cache", ".hypothesis"}
    hits = []
    for path in root.rglob("*"):
        if path.suffix in TEXT_SUFFIXES and not skip & set(path.relative_to(root).parts) and path.is_file():
            lines = path.read_text(errors="replace").splitlines()
            hits += [f"{path.relative_to(root)}:{i}" for i, line in enumerate(lines, 1) if OUTSIDE.search(line)]
    return hits


def test_the_reference_finder_finds_a_planted_one(tmp_path):
    (tmp_path / "a.md").write_text("see the notes\nas DESIGN" + ".md says\n")
    assert _outside_references(tmp_path) == ["a.md:2"]


def test_no_file_refers_to_documents_outside_the_repository():
    """A clone holds no design notes nor the seeds' folder: what a reader needs is in docs/."""
    assert _outside_references(ROOT) == []


PART_KIND_NAMES = {"rail", "joint_plate", "i_profile", "bar"}


def _kind_name_tests(source: str) -> list[int]:
    """Lines of ``source`` comparing a ``.kind`` attribute with a part kind's name: what a
    stage does for a kind belongs in its registry entry (railcheck.parts.PartKind)."""
    lines = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Compare) and isinstance(node.left, ast.Attribute) and node.left.attr == "kind":
            names = {c.value for c in node.comparators if isinstance(c, ast.Constant)}
            lines += [node.lineno] if names & PART_KIND_NAMES else []
    return lines


def test_the_kind_test_finder_finds_a_planted_one():
    assert _kind_name_tests('if geo.kind == "rail":\n    pass\nif motion.kind == "four-bar":\n    pass\n') == [1]


STAGES = ("railcheck.model", "railcheck.check", "railcheck.sweep", "railcheck.report", "railcheck.studies")


def test_no_stage_tests_a_part_kind_by_its_name():
    """The stages above the geometry (whose shapes are the kinds) read a kind's fields."""
    found = {
        name: lines
        for name, path in our_modules().items()
        if name.startswith(STAGES) and (lines := _kind_name_tests(path.read_text()))
    }
    assert found == {}
