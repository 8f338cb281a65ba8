"""Benchmark: what the effect ``dynamic`` changes in `railcheck sweep` and what it costs.

A neighbourhood of the 2013 final design (crank 420-540, coupler 780-900, rocker 720-840,
ground 960-1080 mm: 81 four-bar settings), the built-in scene's [check] (all five parts,
clamped, default mesh), 720 steps, 1 Hz, on a Dask local cluster of one worker per core:
once with ``effects = ["inertia"]``, once with ``["inertia", "dynamic"]``. Prints both
runs' times, and per setting that gets the FE verdict how the safe speed changes (count of
settings whose safe speed moves by more than 0.1%, the smallest, median and largest ratio
dynamic / quasi-static) and which criterion sets it.

    python benchmarks/sweep_dynamic.py [--workers N] [--support clamped|free-body]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from collections import Counter

import numpy as np

from railcheck.progress import Progress
from railcheck.scene import load_scene
from railcheck.sweep.run import run_sweep
from railcheck.sweep.table import read_table

SCENE = """
[sweep]
kind = "four-bar"
speeds = ["1 Hz"]
steps = 720
crank = ["420 mm", "540 mm"]
coupler = ["780 mm", "900 mm"]
rocker = ["720 mm", "840 mm"]
ground = ["960 mm", "1080 mm"]

[check]
parts = ["crank-rail", "coupler-rail", "rocker-rail", "PF_4b_006", "PF_4b_003_v2"]
effects = EFFECTS
support = "SUPPORT"

[loads.PF_4b_003_v2]
longitudinal = "250 N"
transverse = "250 N"
"""


def one(effects: str, workers: int, tmp: str, support: str) -> tuple[dict, float, dict]:
    path = os.path.join(tmp, f"scene{len(effects)}.toml")
    with open(path, "w") as f:
        f.write(SCENE.replace("EFFECTS", effects).replace("SUPPORT", support))
    scene = load_scene(path)
    t = time.perf_counter()
    run = run_sweep(
        scene, os.path.join(tmp, f"out{len(effects)}"), progress=Progress(quiet=True), workers=workers, dask=True
    )
    wall = time.perf_counter() - t
    table = read_table(run.tables["four-bar"])
    rows = {k: np.asarray(v.to_numpy(zero_copy_only=False)) for k, v in zip(table.column_names, table.columns)}
    return rows, wall, run.timings


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=os.cpu_count())
    parser.add_argument("--support", default="clamped", choices=["clamped", "free-body"])
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        qs, t_qs, tim_qs = one('["inertia"]', args.workers, tmp, args.support)
        dyn, t_dyn, tim_dyn = one('["inertia", "dynamic"]', args.workers, tmp, args.support)
    fe = qs["checks_passed"].astype(bool)
    cores = os.cpu_count()
    print(f"81 settings, {fe.sum()} with the FE verdict, support {args.support}, {args.workers} workers, {cores} cores")
    for label, wall, tim in (("quasi-static", t_qs, tim_qs), ("dynamic", t_dyn, tim_dyn)):
        print(
            f"{label:<13} wall {wall:6.1f} s = unit cases (and modes) {tim['prepare']:6.1f} s + settings "
            f"{tim['chunks']:6.1f} s + report {tim['report']:4.1f} s"
        )
    print(f"dynamic / quasi-static wall time: {t_dyn / t_qs:.2f}; settings stage {tim_dyn['chunks'] / tim_qs['chunks']:.1f}")
    ratio = dyn["safe_speed_Hz"][fe] / qs["safe_speed_Hz"][fe]
    print(
        f"safe speed dynamic / quasi-static: {np.sum(np.abs(ratio - 1) > 1e-3)} of {fe.sum()} change by more than 0.1%; "
        f"ratio min {ratio.min():.4f}, median {np.median(ratio):.4f}, max {ratio.max():.4f}"
    )
    print(
        "quasi-static safe speed: lowest",
        f"{np.min(qs['safe_speed_Hz'][fe]):.3f} Hz,",
        dict(Counter(qs["safe_speed_criterion"][fe])),
    )
    print(
        "dynamic safe speed:      lowest",
        f"{np.min(dyn['safe_speed_Hz'][fe]):.3f} Hz,",
        dict(Counter(dyn["safe_speed_criterion"][fe])),
    )
    print("verdicts at 1 Hz: quasi-static", dict(Counter(qs["verdict"][fe])), "dynamic", dict(Counter(dyn["verdict"][fe])))
    amp = {p: dyn[f"{p}_amplification"][fe] for p in ("crank-rail", "coupler-rail", "rocker-rail", "PF_4b_006")}
    print("amplification at 1 Hz, min-max:", ", ".join(f"{p} {a.min():.4f}-{a.max():.4f}" for p, a in amp.items()))


if __name__ == "__main__":
    main()
