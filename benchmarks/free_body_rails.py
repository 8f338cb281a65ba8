"""Mesh convergence of the verdict's model: the default scene's three rails as free bodies.

The built-in default scene (480 / 840 / 780 / 1020 mm, 1 Hz, newton-euler) at 720 steps, the
crank, coupler and rocker rails with ``support = "free-body"``, meshed at 20 (the default),
14, 10 and 7 mm with the holes at 0.3 x size, curved P2. Per size and rail: DOFs, the cycle's
peak von Mises (the verdict's), the smallest fatigue factor and the largest deflection, each
against the finest mesh (the rails' peaks sit at pin-loaded holes and do not converge with a
steady order, so Richardson is not used); and the wall time of the three rails together
with an empty mesh cache and unit-field store (meshing included). The finest row is what
``tests/test_convergence.py`` holds as ``FREE_RAILS_CONVERGED``.

Run by hand (6.6 min on 2 cores, 4 GB at 7 mm):

    python benchmarks/free_body_rails.py [--sizes 20,14,10,7]
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


def run(size_mm: float) -> tuple[float, dict[str, tuple[int, float, float, float]]]:
    """Wall seconds and, per rail, (DOFs, peak Pa, minimum fatigue factor, deflection m)."""
    from railcheck.check.pipeline import run_pipeline
    from railcheck.scene import parse_scene

    data = tomllib.loads(DEFAULT.read_text())
    data["mechanism"]["steps"] = 720
    data["check"]["parts"] = list(RAILS)
    data["check"]["support"] = "free-body"
    data["mesh"] = {**data.get("mesh", {}), "size": f"{size_mm:g} mm", "hole_size": f"{0.3 * size_mm:.3g} mm"}
    data.pop("output", None)
    data.pop("loads", None)  # the bracket's explicit loads: the bracket is not checked here
    scene = parse_scene(data, f"free rails {size_mm:g} mm")
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
    parser.add_argument("--sizes", default="20,14,10,7", help="mesh sizes in mm, coarse to fine")
    sizes = [float(s) for s in parser.parse_args().sizes.split(",")]
    with tempfile.TemporaryDirectory(prefix="railcheck-free-body-") as cache:
        os.environ["RAILCHECK_CACHE"] = cache  # meshes and unit fields solved afresh, then removed
        measured = {size: run(size) for size in sizes}
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
                f"| {name} | {size:g} ({0.3 * size:.3g}) | {dofs:,} | {peak / 1e6:.2f} | {shown[0]} | {fatigue:.3f} | "
                f"{shown[1]} | {deflection * 1e3:.4f} | {shown[2]} | {seconds:.0f} |"
            )
    print("references (peak Pa, fatigue factor, deflection m):")
    for name in RAILS:
        _, peak, fatigue, deflection = reference[name]
        print(f"  {name}: ({peak / 1e6:.8g}e6, {fatigue:.8g}, {deflection * 1e3:.8g}e-3)")


if __name__ == "__main__":
    main()
