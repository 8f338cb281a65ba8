"""Benchmark: `railcheck check` of the built-in default scene cold (the unit-field store
empty) and warm (every part's unit fields stored), with `--json` and no files but
summary.json and report.html ([output] vtk, png and plots off), and with every file. Each
run is a fresh process, as a user runs it; the mesh cache is warm in all of them (meshing
is its own cache). Prints the median wall time of ``--repeat`` runs of each and the
ratios warm / cold.

With ``--sweeps``, in the same run and against the same cold check: the whole default rig
(`railcheck sweep` with no scene: every four-bar and slider-crank setting, all five parts,
720 steps; its unit fields from the user's store, filled by a first whole rig that is not
counted; meshes cached) and the
kinematics-only sweep of the same grid (a scene with only ``[sweep] kind = "both"``: no
FE), each in a fresh process on one process per core forked from the sweep's (a Dask
local cluster where it cannot fork) and, for the kinematics, serially too. The
kinematics' rate is its settings over its settings stage (``timings.json`` ``chunks``,
the workers' start-up included).

    python benchmarks/check_store.py [--repeat 3] [--sweeps] [--write docs/performance.md]

``--write FILE`` puts the run's figures as one table between FILE's ``<!-- timings -->``
and ``<!-- /timings -->`` lines: the one place the docs quote them.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from railcheck.environment import cache_dir

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


def sweep(scene: Path | None, out: Path, env: dict, *extra: str) -> tuple[float, dict, dict, str]:
    """(wall s, summary.json, timings.json, where its chunks ran) of one `railcheck sweep`
    in a fresh process."""
    cmd = [sys.executable, "-P", "-m", "railcheck.cli", "sweep", *([str(scene)] if scene else []), "--out", str(out)]
    t = time.perf_counter()
    proc = subprocess.run([*cmd, "--force", *extra], capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t
    if proc.returncode not in (0, 1):
        raise SystemExit(proc.stderr)
    ran = next(
        (
            line.split("sweep", 1)[1].strip()
            for line in proc.stderr.splitlines()
            if "threads in" in line or "forked from" in line or "Dask:" in line
        ),
        "serially",
    )
    return wall, json.loads((out / "summary.json").read_text()), json.loads((out / "timings.json").read_text()), ran


def settings_of(summary: dict) -> int:
    return sum(k["settings_total"] for k in summary["by_kind"].values())


def sweeps(tmp: Path, env: dict, cold: dict[str, float]) -> dict[str, str]:
    """The whole rig and its kinematics alone, against the cold checks ``cold``. The
    whole rig runs twice: the first (not measured) puts in the store whatever unit fields
    the rig needs and the store has not kept (other runs' entries evict the least recently
    used beyond its cap), so the measured one is the store-warm rig."""
    fill, _, fill_timings, _ = sweep(None, tmp / "rig-fill", env)
    print(f"  whole rig, filling the store first: {fill:.1f} s (unit fields {fill_timings['prepare']:.1f} s), not counted")
    wall, summary, timings, ran = sweep(None, tmp / "rig", env)
    rows = {
        "whole rig, store warm (s)": f"{wall:.1f} (unit fields {timings['prepare']:.1f}, settings "
        f"{timings['chunks']:.1f}, report {timings['report']:.1f}; {settings_of(summary)} settings, {ran})",
        "whole rig / cold check, json only": f"{wall / cold['json only']:.2f}",
    }
    print(
        f"  whole rig ({ran}): {wall:.1f} s (unit fields {timings['prepare']:.1f} s, settings {timings['chunks']:.1f} s, "
        f"report {timings['report']:.1f} s), {settings_of(summary)} settings; "
        + ", ".join(f"{wall / v:.2f}x the cold check {k}" for k, v in cold.items())
    )
    kinematic = tmp / "kinematics.toml"
    kinematic.write_text('[sweep]\nkind = "both"\n')
    for extra in ((), ("--serial",)):
        wall, summary, timings, ran = sweep(kinematic, tmp / "kin", env, *extra)
        n = settings_of(summary)
        rows[f"kinematics only, {ran} (settings/s)"] = f"{n / timings['chunks']:,.0f}"
        print(
            f"  kinematics only ({ran}): {n} settings in {timings['chunks']:.2f} s = "
            f"{n / timings['chunks']:,.0f} settings/s (wall {wall:.1f} s with start-up and report)"
        )
    return rows


def write_table(path: Path, rows: dict[str, str], header: str) -> None:
    """Replace the lines between ``<!-- timings -->`` and ``<!-- /timings -->`` of ``path``
    by ``header`` and a two-column table of ``rows``."""
    text = path.read_text()
    start, end = "<!-- timings -->\n", "<!-- /timings -->"
    if start not in text or end not in text:
        raise SystemExit(f"{path}: no {start.strip()} ... {end} block to fill")
    table = "| figure | value |\n| --- | --- |\n" + "".join(f"| {k} | {v} |\n" for k, v in rows.items())
    before, rest = text.split(start, 1)
    path.write_text(before + start + header + "\n\n" + table + end + rest.split(end, 1)[1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--sweeps", action="store_true", help="also the whole rig and the kinematics-only sweep")
    parser.add_argument("--write", type=Path, help="a Markdown file whose timings block gets this run's table")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        cache = tmp / "cache"
        shutil.copytree(cache_dir(), cache, ignore=shutil.ignore_patterns("unit-fields", ".*"))
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
    rows = {f"check, {k} (s)": f"{v:.2f}" for k, v in med.items()}
    rows |= {
        f"warm / cold, {label}": f"{med[f'warm, {label}'] / med[f'cold, {label}']:.3f}"
        for label in ("json only", "every file")
    }
    if args.sweeps:
        with tempfile.TemporaryDirectory() as tmp:
            env = {**os.environ}  # the user's own store and meshes, which the checks above do not touch
            run(DEFAULT, Path(tmp) / "fill", env)  # the default scene's unit fields in the user's store
            rows |= sweeps(Path(tmp), env, {label: med[f"cold, {label}"] for label in ("json only", "every file")})
    if args.write:
        header = (
            f"`python benchmarks/check_store.py --repeat {args.repeat}{' --sweeps' if args.sweeps else ''}`, "
            f"{time.strftime('%Y-%m-%d')}, {os.cpu_count()} cores: medians of {args.repeat} fresh processes, "
            'meshes cached ("cold": the unit-field store empty).'
        )
        write_table(args.write, rows, header)


if __name__ == "__main__":
    main()
