"""Linear elasticity on a tetrahedral mesh with scikit-fem (vector P1 or P2): the façade
over the FE modules, and :func:`solve_elasticity`, which composes them for one static
problem.

Units SI: m, N, Pa. Supports and loads are addressed by the names of the mesh's boundary
groups (:class:`railcheck.geometry.MeshData`)::

    K, basis = assemble(points, tets, material, order)                 # fea.assembly
    F = load_vector(basis, groups, [HoleLoad("hole_3", (100, 0, 0))])  # fea.loading; or
    F = traction_vector(basis, groups, "end", [t1, t2])                # any traction t(x), k columns
    fixed = supports(basis, groups, ["shaft_hole"])                    # fea.system
    U, info = solve(K, F, fixed)                  # one factorisation for every column of F
    S = recover_stress(basis, U, material)        # fea.stress: (6, nodes[, k]) Pa
    value, where, i = peak(von_mises(S), stress_nodes(basis), exclude=(support_points, 5e-3))
    tip = mean_over(basis, groups, "end_free") @ U   # (3[, k]) m

The modules, along scikit-fem's seams: :mod:`.mesh` (the scikit-fem mesh adaptor and
DOF maps), :mod:`.assembly` (stiffness and mass), :mod:`.loading` (supports, hole loads,
tractions and body forces), :mod:`.system` (fixed DOFs and the solve), :mod:`.stress`
(projection, von Mises, peaks).

P2 elements are isoparametric: given the mesh's curved edges (``curved`` = (edges (k, 2),
mid-edge points (k, 3)), the mid nodes gmsh placed on the true surfaces), the element map
is quadratic (scikit-fem ``MeshTet2``) and holes, seats and fillets are no longer faceted;
every other edge stays straight. P1 elements (and P2 without ``curved``) are straight.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .assembly import assemble, mass_matrix, stiffness_matrix
from .errors import ModelError
from .loading import (
    HoleLoad,
    Support,
    SurfaceDofs,
    body_force_vector,
    body_force_vectors,
    group_area,
    load_vector,
    resultant,
    surface_dofs,
    surface_node_weights,
    traction_vector,
    unit_traction_vectors,
)
from .materials import Material
from .mesh import dof_components, estimate_dofs, group_nodes, node_displacement, stress_nodes
from .solvers import Solver, rigid_body_modes
from .stress import away_from, mean_over, peak, recover_stress, von_mises
from .system import free_submatrix, solve, supports

if TYPE_CHECKING:
    from railcheck.geometry.meshdata import MeshData

__all__ = [
    "HoleLoad",
    "Solution",
    "Support",
    "assemble",
    "body_force_vector",
    "body_force_vectors",
    "check_rigid_modes",
    "estimate_dofs",
    "free_submatrix",
    "group_area",
    "group_nodes",
    "load_vector",
    "mass_matrix",
    "mean_over",
    "peak",
    "recover_stress",
    "resultant",
    "solve",
    "solve_elasticity",
    "stiffness_matrix",
    "stress_nodes",
    "supports",
    "SurfaceDofs",
    "surface_dofs",
    "surface_node_weights",
    "traction_vector",
    "unit_traction_vectors",
    "von_mises",
]

LOCKING_NU = 0.45


@dataclass(frozen=True, kw_only=True)
class Solution:
    """Result of one solve. ``displacement``/``von_mises`` at the mesh's vertices (for
    VTK); ``stress`` (6, nodes) and ``nodes`` (nodes, 3) at every stress node."""

    order: int
    dofs: int
    elements: int
    displacement: np.ndarray  # (n_vertices, 3) m
    von_mises: np.ndarray  # (n_vertices,) Pa
    max_von_mises: float  # Pa, over all stress nodes
    max_von_mises_location: np.ndarray  # (3,) m
    tip_displacement: np.ndarray  # (3,) m, mean over the tip group
    applied_forces: dict[str, np.ndarray]  # group -> integral of the applied traction (N)
    max_von_mises_away: float = 0.0  # Pa, farther than exclude_distance from the support
    max_von_mises_away_location: np.ndarray | None = None
    exclude_distance: float = 0.0  # m
    stress: np.ndarray | None = None  # (6, nodes) Pa: xx, yy, zz, xy, yz, xz
    nodes: np.ndarray | None = None  # (nodes, 3) m
    seconds: dict[str, float] = field(default_factory=dict)
    solver: dict = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    node_displacement: np.ndarray | None = None  # (nodes, 3) m at every stress node

    @property
    def tip_deflection(self) -> float:
        return float(np.linalg.norm(self.tip_displacement))


def solve_elasticity(
    mesh: MeshData,
    material: Material,
    supports_: list[Support],
    loads: list[HoleLoad],
    *,
    order: int = 2,
    tip_group: str | None = None,
    solver: str | Solver = "auto",
    maxiter: int = 2000,
    body_force: np.ndarray | None = None,
    exclude_distance: float = 0.0,
    report=None,
    curved=None,
) -> Solution:
    """Solve one static problem (see the module doc). ``body_force`` (3,) N/m^3;
    ``exclude_distance`` (m): the peak von Mises is also reported over the stress nodes
    farther than this from the supports (``max_von_mises_away``), away from the
    singularity an idealised clamped surface creates at its edges. ``mesh``: its points
    (m), tets and named groups (:class:`railcheck.geometry.meshdata.MeshData`)."""
    points, tets, groups = mesh.points, mesh.tets, mesh.groups
    warnings = _model_warnings(groups, supports_, loads, tip_group, material, order)
    t = [time.perf_counter()]
    K, basis = assemble(points, tets, material, order, curved)
    fixed = supports(basis, groups, [s.group for s in supports_])
    per_load = {ld.group: unit_traction_vectors(basis, groups, ld.group) @ np.asarray(ld.force, float) for ld in loads}
    f = sum(per_load.values(), load_vector(basis, groups, [], body_force))
    t.append(time.perf_counter())
    u, info = solve(K, f, fixed, solver, basis, maxiter, report=report)
    t.append(time.perf_counter())
    S = recover_stress(basis, u, material)
    nodes, vm = stress_nodes(basis), von_mises(S)
    support_pts = points[np.unique(np.concatenate([groups[s.group].ravel() for s in supports_]))]
    top = peak(vm, nodes)
    away = peak(vm, nodes, away_from(nodes, support_pts, exclude_distance))
    tip = mean_over(basis, groups, tip_group) @ u if tip_group else np.zeros(3)
    t.append(time.perf_counter())
    nv = points.shape[0]
    applied = {g: resultant(basis, v) for g, v in per_load.items()}
    return Solution(
        order=order,
        dofs=int(basis.N),
        elements=int(tets.shape[0]),
        displacement=u[basis.nodal_dofs].T.copy(),
        von_mises=vm[:nv].copy(),
        max_von_mises=top[0],
        max_von_mises_location=top[1],
        tip_displacement=tip,
        applied_forces=applied,
        max_von_mises_away=away[0],
        max_von_mises_away_location=away[1],
        exclude_distance=float(exclude_distance),
        stress=S,
        nodes=nodes,
        seconds=dict(zip(("assembly", "solve", "stress"), np.diff(t))),
        solver=info,
        warnings=warnings,
        node_displacement=node_displacement(basis, u),
    )


def _model_warnings(groups, supports_, loads, tip_group, material, order) -> list[str]:
    """Refuse what cannot be solved before any work (:class:`ModelError`); return warnings."""
    if not supports_:
        raise ModelError(
            "supports", "the part has no support: its rigid-body motion is undetermined (the stiffness matrix is singular)"
        )
    for name in [s.group for s in supports_] + [ld.group for ld in loads] + ([tip_group] if tip_group else []):
        if name not in groups:
            raise ModelError(name, f"no such group in the mesh (groups: {', '.join(sorted(groups))})")
    if order == 1 and material.poisson_ratio > LOCKING_NU:
        return [
            f"P1 tetrahedra lock for nearly incompressible material (nu = {material.poisson_ratio}): "
            "displacements and stresses are underestimated; use mesh.order = 2"
        ]
    return []


def check_rigid_modes(points: np.ndarray, tets: np.ndarray, material: Material, order: int = 1, curved=None) -> float:
    """max |K r| / max |K| over the six rigid-body modes r of an unsupported part: ~0."""
    K, basis = assemble(points, tets, material, order, curved)
    B = rigid_body_modes(basis.doflocs, dof_components(basis))
    return float(np.abs(K @ B).max() / np.abs(K).max())
