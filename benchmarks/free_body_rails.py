"""Mesh convergence of the verdict's model: the default scene's three rails as free bodies.

The built-in default scene (480 / 840 / 780 / 1020 mm, 1 Hz, newton-euler) at 720 steps, the
crank, coupler and rocker rails with ``support = "free-body"``, meshed at each SIZE:HOLE pair
of ``--meshes`` (mm; default 20:6, 20:4 (the default), 20:3, 10:4, 7:2.1, 5:1.5), curved P2.
Per size and rail: DOFs, the cycle's peak von Mises (the verdict's), the smallest fatigue
factor and the largest deflection, each against the finest mesh (the rails' peaks sit at
hole edges and do not converge with a steady order, so Richardson is not used); and the wall time of the three rails together
with an empty mesh cache and unit-field store (meshing included). The finest row is what
``tests/test_convergence.py`` holds as ``FREE_RAILS_CONVERGED``.

Run by hand (about 35 min on 2 cores, 9 GB at 5 mm):

    python benchmarks/free_body_rails.py [--meshes 20:6,20:4,20:3,10:4,7:2.1,5:1.5]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
import tomllib
from pathlib import Path

DEFAULT = Path(__file__).resolve().parents[1] / "railcheck" / "scenes" / "default.toml"

RAILS = ("crank-rail", "coupler-rail", "rocker-rail")


def run(size_mm: float, hole_mm: float) -> tuple[float, dict[str, tuple[int, float, float, float]]]:
    """Wall seconds and, per rail, (DOFs, peak Pa, minimum fatigue factor, deflection m)."""
    from railcheck.check.pipeline import run_pipeline
    from railcheck.scene import parse_scene

    data = tomllib.loads(DEFAULT.read_text())
    data["mechanism"]["steps"] = 720
    data["check"]["parts"] = list(RAILS)
    data["check"]["support"] = "free-body"
    data["mesh"] = {**data.get("mesh", {}), "size": f"{size_mm:g} mm", "hole_size": f"{hole_mm:g} mm"}
    data.pop("output", None)
    data.pop("loads", None)  # the bracket's explicit loads: the bracket is not checked here
    scene = parse_scene(data, f"free rails {size_mm:g} mm ({hole_mm:g} mm at the holes)")
    t0 = time.perf_counter()
    result = run_pipeline(scene, jobs=1)
    seconds = time.perf_counter() - t0
    rows = {}
    for name in RAILS:
        part = result.parts[name]
        cycle = part.cycle
        rows[name] = (part.solution.dofs, part.verdict_stress, cycle.fatigue.min_safety_factor, cycle.envelope.max_tip)
    return seconds, rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--meshes", default="20:6,20:4,20:3,10:4,7:2.1,5:1.5", help="SIZE:HOLE pairs in mm, the last the reference"
    )
    sizes = [tuple(float(v) for v in pair.split(":")) for pair in parser.parse_args().meshes.split(",")]
    with tempfile.TemporaryDirectory(prefix="railcheck-free-body-") as cache:
        os.environ["RAILCHECK_CACHE"] = cache  # meshes and unit fields solved afresh, then removed
        measured = {size: run(*size) for size in sizes}
    reference = measured[sizes[-1]][1]
    print("| rail | size mm (holes) | DOFs | peak MPa | err | fatigue n | err | deflection mm | err | s (three rails) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for name in RAILS:
        ref = reference[name]
        for size in sizes:
            seconds, rows = measured[size]
            dofs, peak, fatigue, deflection = rows[name]
            errors = [value / truth - 1 for value, truth in zip((peak, fatigue, deflection), ref[1:], strict=True)]
            shown = ["(ref)" if size == sizes[-1] else f"{e:+.2%}" for e in errors]
            print(
                f"| {name} | {size[0]:g} ({size[1]:g}) | {dofs:,} | {peak / 1e6:.2f} | {shown[0]} | {fatigue:.3f} | "
                f"{shown[1]} | {deflection * 1e3:.4f} | {shown[2]} | {seconds:.0f} |"
            )
    print("references (peak Pa, fatigue factor, deflection m):")
    for name in RAILS:
        _, peak, fatigue, deflection = reference[name]
        print(f"  {name}: ({peak / 1e6:.8g}e6, {fatigue:.8g}, {deflection * 1e3:.8g}e-3)")


if __name__ == "__main__":
    main()
