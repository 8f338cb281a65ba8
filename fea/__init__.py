"""railcheck.fea: scikit-fem linear elasticity for the rig's parts, as small functions.

One flat public namespace, as scikit-fem's own: the mesh adaptor (:mod:`.mesh`), assembly
(:mod:`.assembly`), loads (:mod:`.loading`: supports, hole loads, tractions as functions of
position, body force fields), the constrained solve (:mod:`.system`, solvers as callables
in :mod:`.solvers`), stress recovery (:mod:`.stress`), :func:`solve_elasticity` composing
them (:mod:`.elasticity`), unit load cases and their superposition over a cycle, fatigue,
materials and VTK output. scikit-fem is imported inside the functions that need it, so
importing this package is light. Units SI: m, N, Pa.
"""

from .assembly import assemble, mass_matrix, stiffness_matrix
from .cantilever import CantileverResult, run_cantilever, timoshenko_tip
from .elasticity import Solution, check_rigid_modes, solve_elasticity
from .errors import ModelError, NumericalError
from .fatigue import CRITERIA, SURFACE, Marin, alternating_and_mean, endurance_limit, safety_factor
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
from .materials import MATERIALS, Material, limit_warning
from .mesh import dof_components, estimate_dofs, group_nodes, stress_nodes, vector_dof_map
from .modes import Modes, natural_modes, vector_mass_matrix
from .relief import FreeBodySolve, RigidModes, relieve, rigid_modes, solve_free_body, three_two_one
from .solvers import SOLVERS, Solver, available_memory, factorise, solve_reduced, solver_of
from .stress import away_from, mean_over, peak, recover_stress, von_mises
from .superpose import Envelope, UnitFields, envelope, stress_at
from .system import free_submatrix, solve, supports
from .unitcases import BodyCase, TractionCase, UnitSolve, solve_unit_cases
from .vtk import pvd_text, write_vtu

__all__ = [
    "CRITERIA",
    "MATERIALS",
    "SOLVERS",
    "SURFACE",
    "BodyCase",
    "CantileverResult",
    "Envelope",
    "FreeBodySolve",
    "RigidModes",
    "relieve",
    "rigid_modes",
    "solve_free_body",
    "three_two_one",
    "HoleLoad",
    "Marin",
    "Modes",
    "natural_modes",
    "vector_mass_matrix",
    "Material",
    "ModelError",
    "NumericalError",
    "Solution",
    "Solver",
    "Support",
    "TractionCase",
    "UnitFields",
    "UnitSolve",
    "alternating_and_mean",
    "assemble",
    "available_memory",
    "away_from",
    "body_force_vector",
    "body_force_vectors",
    "check_rigid_modes",
    "dof_components",
    "endurance_limit",
    "envelope",
    "estimate_dofs",
    "factorise",
    "free_submatrix",
    "group_area",
    "group_nodes",
    "limit_warning",
    "load_vector",
    "mass_matrix",
    "mean_over",
    "peak",
    "pvd_text",
    "recover_stress",
    "resultant",
    "run_cantilever",
    "safety_factor",
    "solve",
    "solve_elasticity",
    "solve_reduced",
    "solve_unit_cases",
    "solver_of",
    "stiffness_matrix",
    "stress_at",
    "stress_nodes",
    "supports",
    "SurfaceDofs",
    "surface_dofs",
    "surface_node_weights",
    "timoshenko_tip",
    "traction_vector",
    "unit_traction_vectors",
    "vector_dof_map",
    "von_mises",
    "write_vtu",
]
