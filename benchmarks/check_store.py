"""Benchmark: `railcheck check` of the built-in default scene cold (the unit-field store
empty) and warm (every part's unit fields stored), with `--json` and no files but
summary.json and report.html ([output] vtk, png and plots off), and with every file. Each
run is a fresh process, as a user runs it; the mesh cache is warm in all of them (meshing
is its own cache). Prints the median wall time of ``--repeat`` runs of each and the
ratios warm / cold.

    python benchmarks/check_store.py [--repeat 3]
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

from railcheck.geometry.cache import default_cache_dir

DEFAULT = Path(__file__).resolve().parents[1] / "railcheck" / "scenes" / "default.toml"


def run(scene: Path, out: Path, env: dict) -> float:
    t = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "check", str(scene), "--json", "--out", str(out), "--force"],
        capture_output=True,
        text=True,
        env=env,
    )
    wall = time.perf_counter() - t
    if proc.returncode not in (0, 1):
        raise SystemExit(proc.stderr)
    return wall


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        cache = tmp / "cache"
        shutil.copytree(default_cache_dir(), cache, ignore=shutil.ignore_patterns("unit-fields", ".*"))
        env = {**os.environ, "RAILCHECK_CACHE": str(cache)}
        quiet = tmp / "json-only.toml"
        quiet.write_text(
            DEFAULT.read_text().replace("vtk = true", "vtk = false").replace("png = true", "png = false\nplots = false")
        )
        times: dict[str, list[float]] = {}
        for _ in range(args.repeat):
            for label, scene in (("json only", quiet), ("every file", DEFAULT)):
                shutil.rmtree(cache / "unit-fields", ignore_errors=True)
                times.setdefault(f"cold, {label}", []).append(run(scene, tmp / "out", env))
                times.setdefault(f"warm, {label}", []).append(run(scene, tmp / "out", env))
    med = {k: statistics.median(v) for k, v in times.items()}
    print(f"railcheck check, built-in scene, {os.cpu_count()} cores, median of {args.repeat} (fresh processes):")
    for k, v in med.items():
        print(f"  {k:<22} {v:6.2f} s   ({', '.join(f'{x:.2f}' for x in times[k])})")
    for label in ("json only", "every file"):
        print(f"  warm / cold, {label}: {med[f'warm, {label}'] / med[f'cold, {label}']:.3f}")
    print(f"  warm json only / cold every file: {med['warm, json only'] / med['cold, every file']:.3f}")


if __name__ == "__main__":
    main()
