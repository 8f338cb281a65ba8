"""What meshing the rail's ball-track grooves costs and gives.

A 1000 mm grooved size-25 rail with a pin hole at each end only (960 mm apart), the
check's default mesh sizes (20 mm, 6 mm at the holes), curved P2. Two equal and opposite
1000 N axial pin forces, solved as a free body. At mid-span, 480 mm from either hole,
the section is prismatic and Saint-Venant's solution is exact: sigma_xx = F / A plus the
out-of-plane bending F e z / I_y of the pins' line of action, which runs through the
bores' middle, e below the centroid. Truths: the closed-form section
(geometry.catalogue.rail_section). Reported per variant: tetrahedra, curved edges
straightened to keep elements from folding, meshing time, the mesh's volume against the
closed form, and the fitted axial stress and out-of-plane bending gradient against theory.

Variants: the grooves' element edge (in groove radii) and whether railcheck untangles the
elements beside them (``geometry.mesher.UNTANGLE``, :mod:`railcheck.geometry.untangling`). Run by hand:

    python benchmarks/groove_mesh.py
"""

from __future__ import annotations

import math
import time
from dataclasses import replace

import numpy as np

from railcheck.fea.assembly import assemble
from railcheck.fea.elasticity import mass_matrix
from railcheck.fea.loading import unit_traction_vectors
from railcheck.fea.materials import MATERIALS
from railcheck.fea.mesh import stress_nodes
from railcheck.fea.relief import solve_free_body
from railcheck.fea.stress import recover_stress
from railcheck.geometry import mesher, shapes
from railcheck.geometry.catalogue import RAIL
from railcheck.geometry.models import rail

STEEL = MATERIALS["steel"]
FORCE = 1000.0  # N


def measure(factor: float, untangle: bool) -> dict:
    """One variant's figures (see the module doc)."""
    shapes.GROOVE_ELEMENT_PER_RADIUS, mesher.UNTANGLE = factor, untangle
    geo = rail(1.0, replace(RAIL, hole_pitch=0.96))
    t0 = time.perf_counter()
    mesh = mesher.mesh_part(geo, 20e-3, 6e-3, cache=False)
    seconds = time.perf_counter() - t0
    K, basis = assemble(mesh.points, mesh.tets, STEEL, 2, mesh.curved)
    F = unit_traction_vectors(basis, mesh.groups, "hole_1")[:, 0] - unit_traction_vectors(basis, mesh.groups, "hole_0")[:, 0]
    S = recover_stress(basis, solve_free_body(K, F * FORCE, basis, STEEL.density, "direct").U, STEEL)
    section, nodes = geo.section, stress_nodes(basis)
    near = np.abs(nodes[:, 0] - 0.5) < 6e-3
    x, y, z = nodes[near].T
    design = np.column_stack([np.ones_like(x), y, z - section.centroid_z, (x - 0.5) * y, x - 0.5])
    a, _, c, *_ = np.linalg.lstsq(design, S[0, near], rcond=None)[0]
    holes = 2 * math.pi / 4 * (RAIL.hole_diameter**2 * (RAIL.height - RAIL.counterbore_depth))
    holes += 2 * math.pi / 4 * RAIL.counterbore_diameter**2 * RAIL.counterbore_depth
    eccentricity = (RAIL.height - RAIL.counterbore_depth) / 2 - section.centroid_z
    return {
        "tets": mesh.tets.shape[0],
        "straightened": int(mesh.warning.split()[0]) if mesh.warning else 0,
        "mesh_s": seconds,
        "volume": mass_matrix(basis).sum() / (section.area * 1.0 - holes) - 1.0,
        "axial": a / (FORCE / section.area),
        "bending": c / (FORCE * eccentricity / section.inertia_out_of_plane),
    }


def main() -> None:
    print("| groove element | untangled | tetrahedra | edges straightened | meshing s | volume | F/A | F e / I_y |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for factor in (1.4, 1.1):
        for untangle in (False, True):
            m = measure(factor, untangle)
            print(
                f"| {factor} r | {'yes' if untangle else 'no'} | {m['tets']} | {m['straightened']} | {m['mesh_s']:.1f} "
                f"| {m['volume']:+.2%} | {m['axial']:.4f} | {m['bending']:.4f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
