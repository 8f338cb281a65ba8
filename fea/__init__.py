"""railcheck.fea: scikit-fem linear elasticity for the rig's parts, as small functions.

One flat public namespace, as scikit-fem's own: the mesh adaptor (:mod:`.mesh`), assembly
(:mod:`.assembly`), loads (:mod:`.loading`: supports, hole loads, tractions as functions of
position, body force fields), the constrained solve (:mod:`.system`, solvers as callables
in :mod:`.solvers`), stress recovery (:mod:`.stress`), :func:`solve_elasticity` composing
them (:mod:`.elasticity`), unit load cases and their superposition over a cycle, fatigue,
materials and VTK output. Each name is imported from its module on first use (PEP 562),
and scikit-fem inside the functions that need it, so importing this package, or one
of its modules, costs only what is used. Units SI: m, N, Pa.
"""

from importlib import import_module

#: public name -> the module that defines it
_WHERE = {
    "assemble": "assembly",
    "mass_matrix": "assembly",
    "stiffness_matrix": "assembly",
    "CantileverResult": "cantilever",
    "run_cantilever": "cantilever",
    "timoshenko_tip": "cantilever",
    "Solution": "elasticity",
    "check_rigid_modes": "elasticity",
    "solve_elasticity": "elasticity",
    "ModelError": "errors",
    "NumericalError": "errors",
    "CRITERIA": "fatigue",
    "SURFACE": "fatigue",
    "Marin": "fatigue",
    "alternating_and_mean": "fatigue",
    "endurance_limit": "fatigue",
    "safety_factor": "fatigue",
    "HoleLoad": "loading",
    "Support": "loading",
    "SurfaceDofs": "loading",
    "body_force_vector": "loading",
    "body_force_vectors": "loading",
    "group_area": "loading",
    "load_vector": "loading",
    "resultant": "loading",
    "surface_dofs": "loading",
    "surface_node_weights": "loading",
    "traction_vector": "loading",
    "unit_traction_vectors": "loading",
    "MATERIALS": "materials",
    "Material": "materials",
    "limit_warning": "materials",
    "dof_components": "mesh",
    "estimate_dofs": "mesh",
    "group_nodes": "mesh",
    "stress_nodes": "mesh",
    "vector_dof_map": "mesh",
    "Modes": "modes",
    "natural_modes": "modes",
    "vector_mass_matrix": "modes",
    "FreeBodySolve": "relief",
    "RigidModes": "relief",
    "relieve": "relief",
    "rigid_modes": "relief",
    "solve_free_body": "relief",
    "three_two_one": "relief",
    "SOLVERS": "solvers",
    "Solver": "solvers",
    "factorise": "solvers",
    "solve_reduced": "solvers",
    "solver_of": "solvers",
    "away_from": "stress",
    "mean_over": "stress",
    "peak": "stress",
    "recover_stress": "stress",
    "von_mises": "stress",
    "Envelope": "superpose",
    "UnitFields": "superpose",
    "envelope": "superpose",
    "stress_at": "superpose",
    "free_submatrix": "system",
    "solve": "system",
    "supports": "system",
    "BodyCase": "unitcases",
    "TractionCase": "unitcases",
    "PressureCase": "unitcases",
    "bearing_vectors": "pin_pressure",
    "UnitSolve": "unitcases",
    "solve_unit_cases": "unitcases",
    "pvd_text": "vtk",
    "write_vtu": "vtk",
}

__all__ = sorted(_WHERE)


def __getattr__(name: str):
    """The public name from its module, imported on first use."""
    if name not in _WHERE:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(import_module(f".{_WHERE[name]}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_WHERE))
