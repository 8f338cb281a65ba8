"""Benchmark: what the quasi-static certificate costs (issue 57's targets: a default check
at most 1.1x, the whole rig at most 1.5x the code before it). Runs this tree and an
earlier checkout (``--before``, e.g. a ``git worktree`` of the commit before the
certificate) alternately, each run a fresh process with a fresh ``RAILCHECK_CACHE``
holding only the meshes (copied from a warm mesh cache: meshing is its own cache and
gmsh's run-to-run jitter would otherwise change the meshes), the unit-field store empty:
the state a user meets after a first meshing. Measures `railcheck check --json` of the
built-in scene ([output] files on, as the default) and `railcheck sweep` of the whole
rig. Prints each run, the medians and the ratios this / before.

    python benchmarks/validity_cost.py --before /tmp/wt-old [--repeat 2] [--meshes ~/.cache/railcheck]
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]


def fresh_cache(meshes: Path) -> Path:
    """A temporary cache folder holding a copy of ``meshes``' mesh entries only."""
    root = Path(tempfile.mkdtemp(prefix="rc-bench-"))
    for entry in meshes.glob("*.npz"):
        shutil.copy2(entry, root / entry.name)
    return root


def timed(tree: Path, args: list[str], meshes: Path) -> float:
    """Wall seconds of ``python -m railcheck args`` run from ``tree`` on a fresh cache."""
    cache = fresh_cache(meshes)
    out = Path(tempfile.mkdtemp(prefix="rc-out-"))
    env = dict(os.environ, RAILCHECK_CACHE=str(cache), PYTHONPATH=str(tree))
    env.pop("RAILCHECK_STORE", None)
    t = time.perf_counter()
    subprocess.run(
        [sys.executable, "-m", "railcheck", *args, "--out", str(out / "r")],
        cwd=tree,
        env=env,
        check=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    seconds = time.perf_counter() - t
    shutil.rmtree(cache, ignore_errors=True)
    shutil.rmtree(out, ignore_errors=True)
    return seconds


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", required=True, type=Path, help="a checkout of the code before")
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--meshes", type=Path, default=Path.home() / ".cache" / "railcheck")
    a = parser.parse_args()
    jobs = {"check": ["check", "--json"], "whole rig": ["sweep"]}
    times: dict[tuple[str, str], list[float]] = {}
    for r in range(a.repeat):
        for job, args in jobs.items():
            for label, tree in (("before", a.before.resolve()), ("this", HERE)):
                s = timed(tree, args, a.meshes)
                times.setdefault((job, label), []).append(s)
                print(f"round {r + 1}: {job:<9} {label:<6} {s:7.1f} s", flush=True)
    print("\n| job | before (median s) | this (median s) | this / before |\n| --- | --- | --- | --- |")
    for job in jobs:
        b, t = statistics.median(times[(job, "before")]), statistics.median(times[(job, "this")])
        print(f"| {job} | {b:.1f} | {t:.1f} | {t / b:.2f}x |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
