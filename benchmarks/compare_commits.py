"""Benchmark: `railcheck check` of the built-in scene (json only: no VTU, PNG or plots) at
two commits, each installed with pip in its own venv from a git worktree, run in fresh
processes and interleaved (so a drift of the machine's speed falls on both alike): cold
(the unit-field store empty, meshes cached) and warm, medians of ``--repeat`` pairs and
the ratios after / before. What "nothing slower than N %" is measured with.

    python benchmarks/compare_commits.py BEFORE AFTER [--repeat 5] [--work /tmp/compare]
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def install(rev: str, work: Path) -> Path:
    """The venv's python with ``rev`` installed (a worktree of this repository at it)."""
    tree, venv = work / f"tree-{rev}", work / f"venv-{rev}"
    if not tree.exists():
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-f", str(tree), rev], check=True)
    python = venv / "bin" / "python"
    if not python.exists():
        subprocess.run(["python3", "-m", "venv", str(venv)], check=True)
        subprocess.run([str(python), "-m", "pip", "install", "-q", str(tree)], check=True)
    return python


def check(python: Path, scene: Path, cache: Path, out: Path) -> float:
    """Wall seconds of one check in a fresh process (a traceback stops the benchmark)."""
    env = {**os.environ, "RAILCHECK_CACHE": str(cache)}
    t = time.perf_counter()
    cmd = [str(python), "-P", "-m", "railcheck.cli", "check", str(scene), "--json", "--out", str(out), "--force"]
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if proc.returncode not in (0, 1) or "Traceback" in proc.stderr:
        raise SystemExit(proc.stderr[-3000:])
    return time.perf_counter() - t


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--work", type=Path, default=Path("/tmp/compare"))
    args = parser.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    revs = {"before": args.before, "after": args.after}
    pythons = {k: install(rev, args.work) for k, rev in revs.items()}
    scene = args.work / "json-only.toml"
    text = (ROOT / "railcheck" / "scenes" / "default.toml").read_text()
    scene.write_text(text.replace("vtk = true", "vtk = false").replace("png = true", "png = false\nplots = false"))
    caches = {k: args.work / f"cache-{k}" for k in revs}
    for k in revs:  # meshes into each cache, not counted
        check(pythons[k], scene, caches[k], args.work / f"out-{k}")
    times: dict[tuple[str, str], list[float]] = {}
    for r in range(args.repeat):
        for k in revs if r % 2 == 0 else tuple(revs)[::-1]:
            shutil.rmtree(caches[k] / "unit-fields", ignore_errors=True)
            times.setdefault((k, "cold"), []).append(check(pythons[k], scene, caches[k], args.work / f"out-{k}"))
            times.setdefault((k, "warm"), []).append(check(pythons[k], scene, caches[k], args.work / f"out-{k}"))
    med = {key: statistics.median(v) for key, v in times.items()}
    print(f"railcheck check, built-in scene, json only; {os.cpu_count()} cores; median of {args.repeat}:")
    for state in ("cold", "warm"):
        b, a = med[("before", state)], med[("after", state)]
        print(f"  {state}: {args.before} {b:.2f} s, {args.after} {a:.2f} s, after / before {a / b:.3f}")


if __name__ == "__main__":
    main()
