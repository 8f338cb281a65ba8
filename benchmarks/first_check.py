"""Benchmark (issue 59): what a new user meets, from an empty cache, on this machine.

* the cold default check (`railcheck check --json`, an empty cache and store) of this tree
  beside an earlier checkout's (``--before``, a ``pip install --target`` of it, so its own
  domain packages run: an editable install would lend it this tree's), alternated;
* another setting (420/900/720/1020 mm, the same parts) after one cold default check, with
  ``--json`` and no files, and with every file;
* the whole default rig (`railcheck sweep`, every setting, every part) from an empty cache,
  with its peak memory (the sweep and its workers' proportional set sizes summed, sampled
  every 0.2 s; only this run is sampled, its time with the sampler's cost).

Prints each run, then one table of medians and ratios; ``--write FILE`` puts the table
between FILE's ``<!-- first-check -->`` and ``<!-- /first-check -->`` lines.

    pip install --target /tmp/before --no-deps <checkout of the earlier commit>
    pip install --target /tmp/this --no-deps .    # this tree, fixed while the benchmark runs
    python benchmarks/first_check.py --before /tmp/before --this /tmp/this [--repeat 3] [--write docs/performance.md]
"""

from __future__ import annotations

import argparse
import datetime
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
OTHER = '[mechanism]\nkind = "four-bar"\ncrank = "420 mm"\ncoupler = "900 mm"\nrocker = "720 mm"\nground = "1020 mm"\n'


def tree_memory(pid: int) -> int:
    """Bytes of process ``pid`` and its descendants (/proc, Linux): their proportional set
    sizes summed (PSS: a page shared by forked workers counted once in all)."""
    children: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
                children.setdefault(int(stat[stat.rindex(")") + 2 :].split()[1]), []).append(int(entry.name))
            except (OSError, ValueError, IndexError):
                continue
    total, todo = 0, [pid]
    while todo:
        p = todo.pop()
        todo += children.get(p, [])
        try:
            rollup = Path(f"/proc/{p}/smaps_rollup").read_text()
            total += 1024 * int(next(line.split()[1] for line in rollup.splitlines() if line.startswith("Pss:")))
        except (OSError, StopIteration, ValueError):
            continue
    return total


def timed(cmd: list[str], env: dict, sampled: bool = False) -> tuple[float, int]:
    """(wall s, peak resident bytes of the process tree, or 0 unless ``sampled``) of
    ``cmd``. Sampling reads every process's smaps_rollup every 0.2 s, which costs CPU the
    two cores' run would use (0.2-0.7 s of a 7 s check): only the memory's run samples."""
    t = time.perf_counter()
    proc = subprocess.Popen(
        cmd, env=env, cwd=tempfile.gettempdir(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )
    peak = [0]

    def sample():
        while proc.poll() is None:
            peak[0] = max(peak[0], tree_memory(proc.pid))
            time.sleep(0.2)

    sampler = threading.Thread(target=sample, daemon=True)
    if sampled:
        sampler.start()
    _, err = proc.communicate()
    if sampled:
        sampler.join()
    if proc.returncode not in (0, 1):
        raise SystemExit(f"{' '.join(cmd)} failed:\n{err}")
    return time.perf_counter() - t, peak[0]


def environment(cache: Path, tree: Path | None) -> dict:
    env = dict(os.environ, RAILCHECK_CACHE=str(cache))
    env.pop("RAILCHECK_STORE", None)
    if tree is not None:
        env["PYTHONPATH"] = str(tree)
    return env


def railcheck(*args: str) -> list[str]:
    return [sys.executable, "-m", "railcheck.cli", *args]


THIS: Path | None = None  # --this: a pip --target install of this tree (None: the installed railcheck)


def cold_check(tree: Path | None, work: Path) -> float:
    cache = Path(tempfile.mkdtemp(dir=work))
    seconds, _ = timed(railcheck("check", "--json", "--out", str(cache / "out")), environment(cache, tree))
    shutil.rmtree(cache, ignore_errors=True)
    return seconds


def another_setting(work: Path) -> tuple[float, float]:
    """(json only, every file) s of a check of another setting after one cold default check:
    first with ``--json`` and no files ([output] off), then the same setting again with
    every file (as the issue measured them)."""
    cache = Path(tempfile.mkdtemp(dir=work))
    env = environment(cache, THIS)
    timed(railcheck("check", "--json", "--out", str(cache / "first")), env)
    base = ((THIS or HERE) / "railcheck" / "scenes" / "default.toml").read_text()
    body = base[base.index("[dynamics]") : base.index("[output]")]
    quiet, files = cache / "quiet.toml", cache / "files.toml"
    quiet.write_text(OTHER + body + "[output]\nvtk = false\npng = false\nplots = false\n")
    files.write_text(OTHER + base[base.index("[dynamics]") :])
    json_only, _ = timed(railcheck("check", str(quiet), "--json", "--out", str(cache / "json")), env)
    every, _ = timed(railcheck("check", str(files), "--out", str(cache / "files")), env)
    shutil.rmtree(cache, ignore_errors=True)
    return json_only, every


def whole_rig(work: Path) -> tuple[float, int]:
    cache = Path(tempfile.mkdtemp(dir=work))
    result = timed(railcheck("sweep", "--out", str(cache / "sweep")), environment(cache, THIS), sampled=True)
    shutil.rmtree(cache, ignore_errors=True)
    return result


def table(before: list[float], this: list[float], other: list[tuple[float, float]], rig: tuple[float, int], n: int) -> str:
    b, c = statistics.median(before), statistics.median(this)
    j, f = statistics.median(o[0] for o in other), statistics.median(o[1] for o in other)
    rows = [
        ("cold default check, the code before (s)", f"{b:.1f}", ""),
        ("cold default check, this code (s)", f"{c:.1f}", f"{c / b:.2f}x the code before (target 0.5x)"),
        ("another setting after it, json only (s)", f"{j:.1f}", f"{j / c:.3f}x the cold check (target 0.05x)"),
        ("another setting after it, every file (s)", f"{f:.1f}", f"{f / c:.3f}x the cold check (target 0.2x)"),
        ("whole rig from an empty cache (s)", f"{rig[0]:.1f}", f"{rig[0] / c:.2f}x the cold check (target 1.0x)"),
        ("whole rig's peak memory, PSS of its processes (GB)", f"{rig[1] / 1e9:.2f}", "target 3 GB"),
    ]
    head = (
        f"`python benchmarks/first_check.py --repeat {n}`, {datetime.date.today()}, {os.cpu_count()} cores; "
        f"medians of {n} (the whole rig: one run), every run from an empty cache.\n\n"
    )
    return head + "| figure | value | ratio |\n| --- | --- | --- |\n" + "".join(f"| {a} | {v} | {r} |\n" for a, v, r in rows)


def write_table(path: Path, text: str) -> None:
    page = path.read_text()
    start, end = "<!-- first-check -->\n", "<!-- /first-check -->"
    a, b = page.index(start) + len(start), page.index(end)
    path.write_text(page[:a] + text + page[b:])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", required=True, type=Path, help="a pip --target install of the earlier code")
    parser.add_argument("--this", type=Path, help="a pip --target install of this tree (default: the installed railcheck)")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--write", type=Path)
    a = parser.parse_args()
    global THIS
    THIS = a.this.resolve() if a.this else None
    work = Path(tempfile.mkdtemp(prefix="rc-first-"))
    before, this, other = [], [], []
    for i in range(a.repeat):
        before.append(cold_check(a.before.resolve(), work))
        this.append(cold_check(THIS, work))
        other.append(another_setting(work))
        print(
            f"round {i + 1}: cold before {before[-1]:.1f} s, this {this[-1]:.1f} s; another setting {other[-1]}", flush=True
        )
    rig = whole_rig(work)
    print(f"whole rig {rig[0]:.1f} s, peak {rig[1] / 1e9:.2f} GB", flush=True)
    text = table(before, this, other, rig, a.repeat)
    print(text)
    if a.write:
        write_table(a.write, text)
    shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
