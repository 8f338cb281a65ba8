"""Mutation testing of the modules that decide verdicts: plant one small bug at a time and
count how many the fast tests catch. Run by hand (it takes a while; results in
docs/mutation.md):

    python benchmarks/mutation.py [--module NAME ...] [--jobs 2] [--tests-root DIR] [--json FILE]

A mutant is the module's source with one change (an arithmetic or comparison operator
swapped, ``and``/``or`` swapped, a ``not`` or unary minus dropped, a number changed: an
integer +1, a float x 1.1 or 0 -> 1, ``True``/``False`` flipped, ``max``/``min``-like
calls swapped). Each mutant replaces the module for one pytest session of the module's
own fast tests (``benchmarks/mutation_plugin.py``, nothing on disk is changed); the mutant
is *killed* when a test fails or the session times out, and *survives* when every test
passes. Error messages (f-strings, the arguments of ``raise``) and docstrings are not
mutated. Tests that start child processes see the original module, so what those catch
does not count here.

``--tests-root`` runs another checkout's tests (e.g. an older commit's, for a "before"
score) against this checkout's modules.
"""

from __future__ import annotations

import argparse
import ast
import concurrent.futures as cf
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: module -> (source file, functions to mutate (None: all), the fast tests that guard it:
#: test files, then optionally "-k" and an expression)
TARGETS: dict[str, tuple[str, tuple[str, ...] | None, tuple[str, ...]]] = {
    "railcheck.fea.fatigue": ("fea/fatigue.py", None, ("tests/test_fatigue.py",)),
    "railcheck.model.records": (
        "railcheck/model/records.py",
        None,
        ("tests/test_verdicts.py", "tests/test_fatigue.py"),
    ),
    "railcheck.fea.superpose": ("fea/superpose.py", None, ("tests/test_superpose.py",)),
    # the screens' entry points (their helpers run inside them)
    "railcheck.fea.screening.screens": (
        "fea/screening/screens.py",
        ("make_screen", "hull_steps"),
        ("tests/test_sweep_fe.py",),
    ),
    "railcheck.fea.screening.groups": (
        "fea/screening/groups.py",
        ("von_mises_peak", "fatigue_min"),
        ("tests/test_sweep_fe.py",),
    ),
    "railcheck.fea.screening.exact": ("fea/screening/exact.py", ("tip_peak",), ("tests/test_sweep_fe.py",)),
    "railcheck.sweep.chunk": (
        "railcheck/sweep/chunk.py",
        ("evaluate_part", "fe_results", "_fe_columns"),
        ("tests/test_sweep_speeds.py", "tests/test_verdicts.py", "tests/test_sweep.py", "-k", "sweep or speed"),
    ),
    "railcheck.sweep.verdicts": (
        "railcheck/sweep/verdicts.py",
        ("utilisation", "scaled_results", "safe_s_closed", "failed_criteria"),
        ("tests/test_sweep_speeds.py", "tests/test_verdicts.py", "tests/test_sweep.py", "-k", "sweep or speed"),
    ),
    "railcheck.loads.bearings": ("loads/bearings.py", None, ("tests/test_sweep.py", "-k", "bearing")),
    "railcheck.kinematics.checks": (
        "kinematics/checks.py",
        None,
        (
            "tests/test_checks.py",
            "tests/test_seed_tables.py",
            "tests/test_cli_kinematics.py",
            "tests/test_sweep.py",
            "-k",
            "not dask and not memory",
        ),
    ),
    "railcheck.loads.rotation": ("loads/rotation.py", None, ("tests/test_check.py",)),
}

#: the fast tests that guarded each module before issue 27 (commit c3ef04e), for its
#: "before" score: ``--targets before --tests-root`` a checkout of that commit
BEFORE: dict[str, tuple[str, ...]] = {
    "railcheck.fea.fatigue": ("tests/test_cycle.py", "-k", "marin or goodman or polygon"),
    "railcheck.model.records": ("tests/test_check.py", "tests/test_registry.py", "tests/test_cli_kinematics.py"),
    "railcheck.sweep.chunk": ("tests/test_sweep.py", "-k", "not dask and not memory"),
    "railcheck.loads.bearings": ("tests/test_sweep.py", "-k", "bearing"),
    "railcheck.kinematics.checks": tuple(
        t for t in TARGETS["railcheck.kinematics.checks"][2] if t != "tests/test_checks.py"
    ),
    "railcheck.loads.rotation": ("tests/test_check.py",),
}

_BINOPS = {ast.Add: ast.Sub, ast.Sub: ast.Add, ast.Mult: ast.Div, ast.Div: ast.Mult, ast.Pow: ast.Mult}
_CMPOPS = {
    ast.Lt: ast.LtE,
    ast.LtE: ast.Lt,
    ast.Gt: ast.GtE,
    ast.GtE: ast.Gt,
    ast.Eq: ast.NotEq,
    ast.NotEq: ast.Eq,
    ast.Is: ast.IsNot,
    ast.IsNot: ast.Is,
    ast.In: ast.NotIn,
    ast.NotIn: ast.In,
}
_CALLS = {
    "max": "min",
    "min": "max",
    "maximum": "minimum",
    "minimum": "maximum",
    "argmax": "argmin",
    "argmin": "argmax",
    "all": "any",
    "any": "all",
}


@dataclass(frozen=True)
class Site:
    index: int
    line: int
    what: str


class _Mutator(ast.NodeTransformer):
    """Visits the mutable sites in a fixed order; mutates the one numbered ``target``
    (-1: none, only counts and describes them)."""

    def __init__(self, functions: tuple[str, ...] | None, target: int = -1):
        self.functions, self.target = functions, target
        self.sites: list[Site] = []
        self._stack: list[str] = []

    # --- where mutation is allowed
    def _active(self) -> bool:
        return self.functions is None or (bool(self._stack) and self._stack[0] in self.functions)

    def _site(self, node: ast.AST, what: str) -> bool:
        if not self._active():
            return False
        i = len(self.sites)
        self.sites.append(Site(i, getattr(node, "lineno", 0), what))
        return i == self.target

    def _scoped(self, node):
        self._stack.append(node.name)
        node.decorator_list = [self.visit(d) for d in node.decorator_list]
        node.body = [self.visit(s) for s in node.body]
        self._stack.pop()
        return node

    def visit_FunctionDef(self, node):
        return self._scoped(node)

    visit_AsyncFunctionDef = visit_FunctionDef

    def visit_ClassDef(self, node):
        return self._scoped(node)

    def visit_Expr(self, node):
        if isinstance(node.value, ast.Constant) and isinstance(node.value.value, str):
            return node  # a docstring
        return self.generic_visit(node)

    def visit_JoinedStr(self, node):
        return node  # messages

    def visit_Raise(self, node):
        return node

    def visit_AnnAssign(self, node):
        if node.value is not None:
            node.value = self.visit(node.value)
        return node

    def visit_Assign(self, node):
        if any(isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets):
            return node
        return self.generic_visit(node)

    # --- the mutations
    def visit_BinOp(self, node):
        self.generic_visit(node)
        new = _BINOPS.get(type(node.op))
        if new and self._site(node, f"{type(node.op).__name__} -> {new.__name__}"):
            node.op = new()
        return node

    def visit_AugAssign(self, node):
        self.generic_visit(node)
        new = _BINOPS.get(type(node.op))
        if new and self._site(node, f"{type(node.op).__name__}= -> {new.__name__}="):
            node.op = new()
        return node

    def visit_Compare(self, node):
        self.generic_visit(node)
        for k, op in enumerate(node.ops):
            new = _CMPOPS.get(type(op))
            if new and self._site(node, f"{type(op).__name__} -> {new.__name__}"):
                node.ops[k] = new()
        return node

    def visit_BoolOp(self, node):
        self.generic_visit(node)
        new = ast.Or if isinstance(node.op, ast.And) else ast.And
        if self._site(node, f"{type(node.op).__name__} -> {new.__name__}"):
            node.op = new()
        return node

    def visit_UnaryOp(self, node):
        self.generic_visit(node)
        if isinstance(node.op, (ast.Not, ast.USub)) and self._site(node, f"drop {type(node.op).__name__}"):
            return node.operand
        return node

    def visit_Constant(self, node):
        v = node.value
        if isinstance(v, bool):
            if self._site(node, f"{v} -> {not v}"):
                return ast.copy_location(ast.Constant(not v), node)
        elif isinstance(v, int):
            if self._site(node, f"{v} -> {v + 1}"):
                return ast.copy_location(ast.Constant(v + 1), node)
        elif isinstance(v, float):
            new = v * 1.1 if v != 0.0 else 1.0
            if self._site(node, f"{v!r} -> {new!r}"):
                return ast.copy_location(ast.Constant(new), node)
        return node

    def visit_Call(self, node):
        self.generic_visit(node)
        f = node.func
        name = f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) else None
        if name in _CALLS and self._site(node, f"{name}() -> {_CALLS[name]}()"):
            if isinstance(f, ast.Name):
                f.id = _CALLS[name]
            else:
                f.attr = _CALLS[name]
        return node


def sites(source: str, functions) -> list[Site]:
    m = _Mutator(functions)
    m.visit(ast.parse(source))
    return m.sites


def mutant(source: str, functions, index: int) -> str:
    return ast.unparse(_Mutator(functions, index).visit(ast.parse(source)))


def run_tests(module: str, source_text: str, origin: Path, tests: tuple[str, ...], tests_root: Path, timeout: float):
    """(status, seconds) of one pytest session with ``module`` replaced by ``source_text``;
    status "passed", "failed" or "timeout"."""
    with tempfile.NamedTemporaryFile("w", suffix=".py", delete=False) as f:
        f.write(source_text)
    env = dict(os.environ)
    env.update(
        RAILCHECK_MUTANT_MODULE=module,
        RAILCHECK_MUTANT_SOURCE=f.name,
        RAILCHECK_MUTANT_ORIGIN=str(origin),
        PYTHONPATH=os.pathsep.join([str(ROOT / "benchmarks"), env.get("PYTHONPATH", "")]),
    )
    cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "mutation_plugin", "-p", "no:cacheprovider"]
    cmd += [
        "-p",
        "no:warnings",
        "-m",
        "not slow",
        *(t if t == "-k" or not t.startswith("tests/") else str(tests_root / t) for t in tests),
    ]
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(cmd, cwd=tests_root, env=env, capture_output=True, text=True, timeout=timeout)
        status = "passed" if proc.returncode == 0 else "failed"
        if proc.returncode not in (0, 1):  # collection or usage error: show it, count as killed
            status = f"error {proc.returncode}"
    except subprocess.TimeoutExpired:
        status = "timeout"
    finally:
        os.unlink(f.name)
    return status, time.perf_counter() - t0


def score_module(module: str, jobs: int, tests_root: Path, log, before: bool = False) -> dict:
    path, functions, wanted = TARGETS[module]
    wanted = BEFORE[module] if before else wanted
    k = wanted.index("-k") if "-k" in wanted else len(wanted)
    tests = tuple(t for t in wanted[:k] if (tests_root / t).exists()) + wanted[k:]  # an older checkout may lack some
    origin = ROOT / path
    source = origin.read_text(encoding="utf-8")
    found = sites(source, functions)
    status, base = run_tests(module, ast.unparse(ast.parse(source)), origin, tests, tests_root, 1800)
    if status != "passed":
        raise SystemExit(f"{module}: the tests fail on the unmutated module ({status}); fix that first")
    timeout = 3 * base + 10  # a mutant that disables a screen may only be slow: killed as a timeout
    log(f"{module}: {len(found)} mutants, tests {base:.1f} s each")
    results = {}
    with cf.ThreadPoolExecutor(jobs) as pool:
        futures = {
            pool.submit(run_tests, module, mutant(source, functions, s.index), origin, tests, tests_root, timeout): s
            for s in found
        }
        for k, fut in enumerate(cf.as_completed(futures), 1):
            s = futures[fut]
            results[s.index] = fut.result()
            if k % 10 == 0 or k == len(found):
                log(f"  {k}/{len(found)}")
    survivors = [s for s in found if results[s.index][0] == "passed"]
    killed = len(found) - len(survivors)
    return {
        "module": module,
        "tests": list(tests),
        "mutants": len(found),
        "killed": killed,
        "score": killed / len(found) if found else 1.0,
        "seconds_per_session": statistics.median(t for _, t in results.values()) if results else base,
        "errors": sorted({st for st, _ in results.values() if st.startswith("error")}),
        "survivors": [{"line": s.line, "mutation": s.what} for s in survivors],
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--module", action="append", choices=sorted(TARGETS), help="default: every target")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--tests-root", type=Path, default=ROOT)
    parser.add_argument("--targets", choices=("after", "before"), default="after", help="which tests guard each module")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args(argv)
    out = []
    t0 = time.perf_counter()
    default = list(BEFORE) if args.targets == "before" else list(TARGETS)
    for module in args.module or default:
        r = score_module(
            module, args.jobs, args.tests_root, lambda s: print(s, file=sys.stderr, flush=True), args.targets == "before"
        )
        out.append(r)
        print(f"{module:28s} {r['killed']:4d}/{r['mutants']:<4d} killed  {100 * r['score']:5.1f}%", flush=True)
        for s in r["survivors"]:
            print(f"    survived: line {s['line']}: {s['mutation']}", flush=True)
    total_m, total_k = sum(r["mutants"] for r in out), sum(r["killed"] for r in out)
    print(f"{'all':28s} {total_k:4d}/{total_m:<4d} killed  {100 * total_k / max(total_m, 1):5.1f}%")
    print(f"({time.perf_counter() - t0:.0f} s, {args.jobs} jobs)")
    if args.json:
        args.json.write_text(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
