"""The direct path against the iterative one on railcheck's own systems: factorisation,
one right-hand side, 32 right-hand sides with the same factor, and AMG-CG for one.

    python benchmarks/solvers.py [--part PF_4b_003_v2] [--amg]

Default: the part's default P2 mesh. Times in seconds from one run on this machine.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from railcheck.fea.elasticity import assemble, dof_components, supports, unit_traction_vectors
from railcheck.fea.materials import MATERIALS
from railcheck.fea.solvers import factorise, rigid_body_modes, solve_amg
from railcheck.geometry.mesher import mesh_part
from railcheck.model.jobs import mesh_sizes
from railcheck.parts import geometry_of, kind_of
from railcheck.scene import load_scene


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--part", default="PF_4b_003_v2")
    parser.add_argument("--amg", action="store_true", help="also time AMG-CG on one right-hand side")
    args = parser.parse_args()

    geo = geometry_of(args.part, {})
    kind = kind_of(args.part)
    mesh = mesh_part(geo, *mesh_sizes(load_scene(None).mesh, geo.kind))
    t = time.perf_counter()
    K, basis = assemble(mesh.points, mesh.tets, MATERIALS["steel"], 2)
    t_asm = time.perf_counter() - t
    fixed = supports(basis, mesh.groups, [kind.support])
    free = np.setdiff1d(np.arange(basis.N), fixed)
    Kc = K[free][:, free]
    holes = kind.bolts(geo) if not kind.bolts_on_rail else [g for g in geo.groups if g.startswith("hole_")][-2:]
    T = np.column_stack([unit_traction_vectors(basis, mesh.groups, h) for h in holes])[free]
    rng = np.random.default_rng(1)
    F32 = T @ rng.normal(size=(T.shape[1], 32))
    t = time.perf_counter()
    factor = factorise(Kc)
    t_fac = time.perf_counter() - t
    t = time.perf_counter()
    factor.solve(F32[:, 0])
    t_first = time.perf_counter() - t  # also builds the long-double copy of K

    def median_seconds(work, repeat: int = 3) -> float:
        times = []
        for _ in range(repeat):
            t = time.perf_counter()
            work()
            times.append(time.perf_counter() - t)
        return float(np.median(times))

    t_one = median_seconds(lambda: factor.solve(F32[:, 0]))
    t_32 = median_seconds(lambda: factor.solve(F32))
    bare_one = median_seconds(lambda: factor.solve_once(F32[:, :1]))
    bare_32 = median_seconds(lambda: factor.solve_once(F32))
    print(f"{args.part}: {Kc.shape[0]} free DOFs, {Kc.nnz} non-zeros; assembly {t_asm:.2f} s")
    print(
        f"  {factor.backend}: factorise {t_fac:.2f} s ({factor.info.get('factor_bytes', 0) / 2**30:.2f} GiB), "
        f"first solve {t_first:.2f} s"
    )
    print(
        f"  with refinement and residual check (medians of 3): one RHS {t_one:.3f} s, 32 RHS {t_32:.3f} s "
        f"= {t_32 / t_one:.1f} x one"
    )
    print(
        f"  the factor's two triangular passes alone: one RHS {bare_one:.3f} s, 32 RHS {bare_32:.3f} s "
        f"= {bare_32 / bare_one:.1f} x one"
    )
    if args.amg:
        B = rigid_body_modes(basis.doflocs[:, free], dof_components(basis)[free])
        t = time.perf_counter()
        _, info = solve_amg(Kc, F32[:, 0], B)
        print(f"  AMG-CG one RHS: {time.perf_counter() - t:.2f} s, {info['iterations']} iterations")


if __name__ == "__main__":
    main()
