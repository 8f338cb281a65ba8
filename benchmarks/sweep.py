"""Benchmark: `railcheck sweep` of the whole default rig (every four-bar and
slider-crank setting of the hole grid, all five parts, 720 steps, 1 Hz), on a Dask local
cluster of one worker per core and serially, in one run. Prints the stage times and the
settings per second (all settings, and those that pass the configuration checks and so
get the FE verdict).

    python benchmarks/sweep.py [--serial-too] [--workers N]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

from railcheck.progress import Progress
from railcheck.scene import load_scene
from railcheck.sweep.run import run_sweep


def one(label: str, **kw) -> None:
    scene = load_scene(None)
    with tempfile.TemporaryDirectory() as tmp:
        t = time.perf_counter()
        run = run_sweep(scene, os.path.join(tmp, "sweep"), progress=Progress(quiet=True), **kw)
        wall = time.perf_counter() - t
    by = run.summary["by_kind"]
    total = sum(k["settings_total"] for k in by.values())
    fe = sum(k["settings_passing_checks"] for k in by.values())
    chunks = run.timings["chunks"]
    print(
        f"{label:<28} wall {wall:7.1f} s = FE unit cases {run.timings['prepare']:6.1f} s + settings "
        f"{chunks:6.1f} s + report {run.timings['report']:4.1f} s; {total} settings ({fe} with FE): "
        f"{total / chunks:8.0f} settings/s, {fe / chunks:6.1f} FE settings/s"
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--serial-too", action="store_true", help="also run without Dask")
    parser.add_argument("--workers", type=int, default=os.cpu_count())
    args = parser.parse_args()
    print(f"default rig, {os.cpu_count()} cores; mesh cache warm after the first part of the run")
    one(f"Dask, {args.workers} workers", workers=args.workers, dask=True)
    if args.serial_too:
        one("serial", serial=True)


if __name__ == "__main__":
    main()
