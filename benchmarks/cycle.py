"""What the whole crank cycle costs: unit-case solves against one single-load solve, and
the evaluation of one configuration's full cycle (envelope, seed method, fatigue) for
all five parts of the default scene at its default meshes, after the unit solves.

    python benchmarks/cycle.py [--repeat 5]

Prints medians over the repeats (seconds) and the ratios the README quotes.
"""

from __future__ import annotations

import argparse
import statistics
import time

from railcheck.fea.elasticity import HoleLoad, Support, solve_elasticity
from railcheck.fea.materials import MATERIALS
from railcheck.fea.unitcases import solve_unit_cases
from railcheck.geometry.mesher import mesh_part
from railcheck.model.cycle import evaluate_cycle
from railcheck.model.inputs import parts_input
from railcheck.model.jobs import build_load_cases, part_geometries, part_jobs
from railcheck.model.kinematics_stage import kinematics_input, run_kinematics
from railcheck.model.loading import unit_cases
from railcheck.parts import kind_of
from railcheck.scene import load_scene


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()

    scene = load_scene(None)
    steel = MATERIALS["steel"]
    kin = run_kinematics(kinematics_input(scene))
    geos = part_geometries(parts_input(scene))
    jobs = part_jobs(
        parts_input(scene), kin, geos, build_load_cases(parts_input(scene), kin, geos), steel, steel.fatigue_limit
    )
    prepared, unit_s, single_s = {}, {}, {}
    for name, job in jobs.items():
        geo, kind, holes = job.geometry, kind_of(name), list(job.holes)
        mesh = mesh_part(geo, job.mesh.size, job.mesh.hole_size)
        cases = unit_cases(job.loads, geo, holes)
        t = time.perf_counter()
        fields, meta = solve_unit_cases(
            mesh, steel, [kind.support], cases, order=2, tip_group=kind.tip, exclude_distance=kind.exclusion(geo)
        )
        unit_s[name] = time.perf_counter() - t
        t = time.perf_counter()
        solve_elasticity(
            mesh,
            steel,
            [Support(kind.support)],
            [HoleLoad(h, (100.0, 100.0, 0.0)) for h in holes],
            order=2,
            tip_group=kind.tip,
            exclude_distance=kind.exclusion(geo),
        )
        single_s[name] = time.perf_counter() - t
        prepared[name] = (job, fields, meta)
        print(
            f"{name:<14} {meta.dofs:>7} DOFs  unit cases {unit_s[name]:6.2f} s  one load {single_s[name]:6.2f} s  "
            f"ratio {unit_s[name] / single_s[name]:.2f}"
        )
    runs = []
    for _ in range(args.repeat):
        t = time.perf_counter()
        for job, fields, meta in prepared.values():
            evaluate_cycle(job, fields, job.histories, meta)
        runs.append(time.perf_counter() - t)
    print(
        f"unit cases, all parts: {sum(unit_s.values()):.2f} s; one load each: {sum(single_s.values()):.2f} s; "
        f"ratio {sum(unit_s.values()) / sum(single_s.values()):.2f}"
    )
    print(
        f"full cycle ({scene.mechanism.steps} steps), all five parts, after the unit solves: median "
        f"{statistics.median(runs):.3f} s over {args.repeat} runs"
    )


if __name__ == "__main__":
    main()
