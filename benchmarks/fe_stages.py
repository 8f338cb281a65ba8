"""What dominates an FE solve at about 50k, 200k and 1M DOFs (P2) on this machine.

The benchmark cantilever bar (700 x 23 x 20 mm, 100 N tip load) at three mesh sizes, each
solve in its own process (so peak memory is its own), the solver chosen as `railcheck`
chooses it (``--solver auto``: PARDISO while its factor fits in 60% of the memory), or the
one named. Prints seconds per stage (mesh, assembly, solve, stress recovery), the share of
the largest, and peak memory.

    python benchmarks/fe_stages.py [--sizes 5.8,3.6,2.1] [--solver auto|direct|pmg|amg]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys


def one(size_mm: float, solver: str = "auto") -> dict:
    code = (
        "import json, resource; from railcheck.fea.cantilever import run_cantilever; "
        f"r = run_cantilever(order=2, size={size_mm}e-3, cache=False, solver={solver!r}); "
        "print('OUT' + json.dumps({'dofs': r.solution.dofs, 'elements': r.solution.elements, "
        "'seconds': r.seconds, 'solver': r.solution.solver, 'error': r.relative_error, "
        "'memory': resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024}))"
    )
    proc = subprocess.run([sys.executable, "-P", "-c", code], capture_output=True, text=True)
    line = next((l for l in proc.stdout.splitlines() if l.startswith("OUT")), None)
    if line is None:
        raise RuntimeError(proc.stderr[-3000:])
    return json.loads(line[3:])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="5.8,3.6,2.1", help="mesh sizes in mm")
    parser.add_argument("--solver", default="auto", choices=("auto", "direct", "pmg", "amg"))
    args = parser.parse_args()
    print("| size mm | DOFs | elements | solver | mesh s | assembly s | solve s | stress s | dominant | peak GB |")
    print("| --- " * 10 + "|")
    for size in (float(s) for s in args.sizes.split(",")):
        r = one(size, args.solver)
        s = r["seconds"]
        stages = {k: s[k] for k in ("mesh", "assembly", "solve", "stress")}
        top = max(stages, key=stages.get)
        solver = r["solver"]["solver"] + (
            f" ({r['solver']['iterations']} it)" if r["solver"]["solver"] in ("amg", "pmg") else ""
        )
        print(
            f"| {size:g} | {r['dofs']} | {r['elements']} | {solver} | {s['mesh']:.1f} | {s['assembly']:.1f} | "
            f"{s['solve']:.1f} | {s['stress']:.1f} | {top} {100 * stages[top] / sum(stages.values()):.0f}% | "
            f"{r['memory'] / 1e9:.1f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
