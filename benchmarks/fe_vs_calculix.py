"""railcheck's FE against CalculiX on the same second-order mesh, in one run.

Two problems: the cantilever benchmark (700 x 23 x 20 mm, 100 N tip load) and the crank
rail of the default scene (its load case from the default check). Both solvers get the
same P2 mesh (railcheck's vertices and mid-edge nodes written as C3D10 elements), the same
fixed nodes and the same consistent nodal forces (railcheck's assembled traction loads).
Reported: wall time and peak memory of each solve (each in its own process), their ratio,
the tip deflection (mean displacement of the tip face's nodes) and von Mises at a common
node (nodal stresses: railcheck's L2 projection, CalculiX's extrapolated and averaged).

Needs CalculiX (Debian): ``apt-get install calculix-ccx``. Run:

    python benchmarks/fe_vs_calculix.py [--size-cantilever 6] [--size-rail 10] [--solver direct]

Node order: Abaqus/CalculiX C3D10 numbers the mid-edge nodes 5-10 on edges 1-2, 2-3,
3-1, 1-4, 2-4, 3-4, with nodes 1-2-3 counter-clockwise seen from node 4; gmsh's tet10 swaps
the last two (edges 3-4 and 2-4). This script finds every mid-edge node by its location,
so it depends on neither numbering, and orients every element by its volume's sign.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from railcheck.fea.cantilever import HEIGHT, LENGTH, LOAD, WIDTH
from railcheck.fea.elasticity import (
    HoleLoad,
    Support,
    assemble,
    group_nodes,
    load_vector,
    solve_elasticity,
    von_mises,
)
from railcheck.fea.materials import MATERIALS
from railcheck.fea.mesh import scalar_basis, vector_dof_map
from railcheck.geometry.mesher import mesh_part
from railcheck.geometry.models import bar
from railcheck.model.inputs import parts_input
from railcheck.model.jobs import build_load_cases, part_geometries
from railcheck.model.kinematics_stage import kinematics_input, run_kinematics
from railcheck.scene import load_scene

ABAQUS_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]


def railcheck_solve(problem: str, size: float, solver: str = "direct") -> dict:
    """Solve with railcheck (run in a child process) by ``solver``; return arrays as lists."""
    import resource

    if problem == "cantilever":
        mesh = mesh_part(bar(LENGTH, WIDTH, HEIGHT), size, hole_size=size)
        supports, loads, tip = [Support("clamp")], [HoleLoad("tip", (0.0, 0.0, LOAD))], "tip"
        probe = np.array([LENGTH / 4, 0.0, HEIGHT / 2])
    else:
        from dataclasses import replace

        scene = load_scene(None)
        scene = replace(scene, check=replace(scene.check, parts=("crank-rail",)))
        geos = part_geometries(parts_input(scene))
        case = build_load_cases(parts_input(scene), run_kinematics(kinematics_input(scene)), geos)["crank-rail"]
        mesh = mesh_part(geos["crank-rail"], size, hole_size=0.3 * size)
        supports, tip = [Support(case.support)], case.tip_group
        loads = [HoleLoad(b.group, b.force) for b in case.bolts]
        probe = np.array([0.3, 0.0115, 0.011])  # mid-length, on the side face, mid-height
    t = time.perf_counter()
    sol = solve_elasticity(mesh, MATERIALS["steel"], supports, loads, order=2, tip_group=tip, solver=solver)
    seconds = time.perf_counter() - t
    # what only this comparison needs, from the FE API: consistent nodal forces and the fixed nodes
    K, basis = assemble(mesh.points, mesh.tets, MATERIALS["steel"], 2)
    f = load_vector(basis, mesh.groups, loads)
    nodal_forces = f[vector_dof_map(basis, scalar_basis(basis))]
    fixed = group_nodes(basis, mesh.groups, [s.group for s in supports])
    tip_tris = mesh.groups[tip]
    return {
        "seconds": seconds,
        "peak_memory": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,
        "points": mesh.points.tolist(),
        "tets": mesh.tets.tolist(),
        "nodes": sol.nodes.tolist(),
        "u": sol.node_displacement.tolist(),
        "vm": von_mises(sol.stress).tolist(),
        "forces": nodal_forces.tolist(),
        "fixed": fixed.tolist(),
        "tip_vertices": np.unique(tip_tris).tolist(),
        "probe": probe.tolist(),
        "dofs": sol.dofs,
    }


def c3d10_connectivity(points, tets, nodes):
    """C3D10 node indices (m, 10) into ``nodes`` (railcheck's P2 nodes), positively oriented."""
    from scipy.spatial import cKDTree

    tree = cKDTree(nodes)
    tets = tets.copy()
    p = points[tets]
    vol = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
    neg = vol < 0
    tets[neg, 1], tets[neg, 2] = tets[neg, 2].copy(), tets[neg, 1].copy()
    corners = tree.query(points[tets].reshape(-1, 3))[1].reshape(-1, 4)
    mids = []
    for a, b in ABAQUS_EDGES:
        d, k = tree.query(0.5 * (points[tets[:, a]] + points[tets[:, b]]))
        if d.max() > 1e-9:
            raise RuntimeError("a mid-edge node was not found")
        mids.append(k)
    return np.column_stack([corners] + mids)


def write_inp(path, nodes, conn, fixed, forces, E=210e9, nu=0.3):
    with open(path, "w") as f:
        f.write("*HEADING\nrailcheck vs CalculiX\n*NODE, NSET=NALL\n")
        f.writelines(f"{i + 1}, {x:.12e}, {y:.12e}, {z:.12e}\n" for i, (x, y, z) in enumerate(nodes))
        f.write("*ELEMENT, TYPE=C3D10, ELSET=EALL\n")
        f.writelines(f"{e + 1}, " + ", ".join(str(int(n) + 1) for n in row) + "\n" for e, row in enumerate(conn))
        f.write("*NSET, NSET=FIXED\n")
        fx = [int(n) + 1 for n in fixed]
        for k in range(0, len(fx), 16):
            f.write(", ".join(map(str, fx[k : k + 16])) + "\n")
        f.write(f"*MATERIAL, NAME=STEEL\n*ELASTIC\n{E:.12e}, {nu}\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n")
        f.write("*STEP\n*STATIC\n*BOUNDARY\nFIXED, 1, 3, 0.\n*CLOAD\n")
        for i in np.nonzero(np.any(forces != 0, axis=1))[0]:
            for c in range(3):
                if forces[i, c] != 0:
                    f.write(f"{i + 1}, {c + 1}, {forces[i, c]:.12e}\n")
        # U printed to the .dat as well: 7 significant digits there against 6 in the .frd
        f.write("*NODE FILE\nU\n*EL FILE\nS\n*NODE PRINT, NSET=NALL\nU\n*END STEP\n")


def read_frd(path, n):
    """Nodal DISP (n, 3) and STRESS (n, 6: xx yy zz xy yz zx) from a CalculiX .frd."""
    disp, stress = np.zeros((n, 3)), np.zeros((n, 6))
    block = None
    with open(path) as f:
        for line in f:
            if line.startswith(" -4"):
                name = line.split()[1]
                block = {"DISP": disp, "STRESS": stress}.get(name)
            elif line.startswith(" -3"):
                block = None
            elif block is not None and line.startswith(" -1"):
                node = int(line[3:13])
                vals = [float(line[13 + 12 * k : 25 + 12 * k]) for k in range(block.shape[1])]
                block[node - 1] = vals
    return disp, stress


def read_dat_displacements(path, n):
    """Nodal U (n, 3) from the *NODE PRINT table of a CalculiX .dat (format e13.6)."""
    u = np.full((n, 3), np.nan)
    with open(path) as f:
        for line in f:
            parts = line.split()
            if len(parts) == 4 and parts[0].isdigit():
                u[int(parts[0]) - 1] = [float(v) for v in parts[1:]]
    if np.isnan(u).any():
        raise RuntimeError("the .dat file lacks some nodal displacements")
    return u


def von_mises6(s):
    xx, yy, zz, xy, yz, zx = s.T
    return np.sqrt(0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2) + 3 * (xy**2 + yz**2 + zx**2))


def run_ccx(workdir: Path) -> tuple[float, int]:
    env = dict(os.environ, OMP_NUM_THREADS="1", CCX_NPROC_EQUATION_SOLVER="1")
    t = time.perf_counter()
    log = open(workdir / "ccx.log", "w")
    proc = subprocess.Popen(["ccx", "-i", "job"], cwd=workdir, stdout=log, stderr=subprocess.STDOUT, env=env)
    _, status, usage = os.wait4(proc.pid, 0)
    seconds = time.perf_counter() - t
    if status != 0:
        raise RuntimeError(f"ccx failed: {(workdir / 'ccx.log').read_text()[-2000:]}")
    return seconds, usage.ru_maxrss * 1024


def compare(problem: str, size: float, solver: str = "direct") -> dict:
    code = (
        "import json, importlib.util as u; "
        f"s = u.spec_from_file_location('fe_vs_calculix', {str(Path(__file__).resolve())!r}); "
        "m = u.module_from_spec(s); s.loader.exec_module(m); "
        f"print('OUT' + json.dumps(m.railcheck_solve({problem!r}, {size!r}, {solver!r})))"
    )
    proc = subprocess.run(
        [sys.executable, "-P", "-c", code], capture_output=True, text=True, cwd=Path(__file__).resolve().parents[1]
    )
    line = next((l for l in proc.stdout.splitlines() if l.startswith("OUT")), None)
    if line is None:
        raise RuntimeError(proc.stderr[-3000:])
    r = json.loads(line[3:])
    nodes = np.array(r["nodes"])
    points, tets = np.array(r["points"]), np.array(r["tets"])
    conn = c3d10_connectivity(points, tets, nodes)
    work = Path(tempfile.mkdtemp(prefix="railcheck-ccx-"))
    try:
        write_inp(work / "job.inp", nodes, conn, np.array(r["fixed"]), np.array(r["forces"]))
        ccx_seconds, ccx_mem = run_ccx(work)
        _, s_ccx = read_frd(work / "job.frd", nodes.shape[0])
        u_ccx = read_dat_displacements(work / "job.dat", nodes.shape[0])
    finally:
        shutil.rmtree(work, ignore_errors=True)
    u_rc = np.array(r["u"])
    from scipy.spatial import cKDTree

    tip_nodes = cKDTree(nodes).query(points[r["tip_vertices"]])[1]
    tip_rc = np.linalg.norm(u_rc[tip_nodes].mean(axis=0))
    tip_ccx = np.linalg.norm(u_ccx[tip_nodes].mean(axis=0))
    k = int(cKDTree(nodes).query(r["probe"])[1])
    vm_rc, vm_ccx = r["vm"][k], float(von_mises6(s_ccx[k : k + 1])[0])
    return {
        "problem": problem,
        "size_mm": size * 1e3,
        "dofs": r["dofs"],
        "railcheck_seconds": r["seconds"],
        "ccx_seconds": ccx_seconds,
        "railcheck_peak_memory": r["peak_memory"],
        "ccx_peak_memory": ccx_mem,
        "tip_railcheck_mm": tip_rc * 1e3,
        "tip_ccx_mm": tip_ccx * 1e3,
        "tip_rel_diff": tip_rc / tip_ccx - 1,
        "probe_mm": [x * 1e3 for x in nodes[k]],
        "vm_railcheck_MPa": vm_rc / 1e6,
        "vm_ccx_MPa": vm_ccx / 1e6,
        "vm_rel_diff": vm_rc / vm_ccx - 1,
        "max_u_diff_rel": float(np.abs(u_rc - u_ccx).max() / np.abs(u_ccx).max()),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size-cantilever", type=float, default=6.0, help="mm")
    parser.add_argument("--size-rail", type=float, default=10.0, help="mm")
    parser.add_argument("--solver", default="direct", help="railcheck's solver (direct, pmg, auto, ...)")
    args = parser.parse_args()
    if shutil.which("ccx") is None:
        sys.exit("CalculiX not found: apt-get install calculix-ccx")
    rows = [
        compare("cantilever", args.size_cantilever * 1e-3, args.solver),
        compare("crank-rail", args.size_rail * 1e-3, args.solver),
    ]
    print(
        "| problem | DOFs | railcheck s | ccx s | time ratio ccx/railcheck | railcheck GB | ccx GB | "
        "tip railcheck mm | tip ccx mm | diff | von Mises railcheck / ccx MPa at (mm) | diff | max nodal u diff |"
    )
    print("| --- " * 13 + "|")
    for r in rows:
        print(
            f"| {r['problem']} ({r['size_mm']:g} mm) | {r['dofs']} | {r['railcheck_seconds']:.2f} | "
            f"{r['ccx_seconds']:.2f} | {r['ccx_seconds'] / r['railcheck_seconds']:.2f} | "
            f"{r['railcheck_peak_memory'] / 1e9:.2f} | {r['ccx_peak_memory'] / 1e9:.2f} | {r['tip_railcheck_mm']:.5f} | "
            f"{r['tip_ccx_mm']:.5f} | {r['tip_rel_diff']:+.1e} | {r['vm_railcheck_MPa']:.3f} / {r['vm_ccx_MPa']:.3f} at "
            f"({', '.join(f'{x:.1f}' for x in r['probe_mm'])}) | {r['vm_rel_diff']:+.1e} | {r['max_u_diff_rel']:.1e} |"
        )


if __name__ == "__main__":
    main()
