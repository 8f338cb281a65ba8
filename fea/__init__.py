"""railcheck.fea: scikit-fem linear elasticity for the rig's parts, as small modules.

Each name is imported from the module that defines it (``from railcheck.fea.elasticity
import solve_elasticity``), by the application and the tests alike, so every import says
where its name lives and the layering test sees every dependency. The modules: the mesh
adaptor (:mod:`.mesh`), assembly (:mod:`.assembly`), loads (:mod:`.loading`: supports,
hole loads, tractions as functions of position, body force fields), the constrained solve
(:mod:`.system`, solvers as callables in :mod:`.solvers`), stress recovery
(:mod:`.stress`), :func:`~.elasticity.solve_elasticity` composing them
(:mod:`.elasticity`), unit load cases (:mod:`.unitcases`) and their superposition over a
cycle (:mod:`.superpose`, :mod:`.hull`, :mod:`.screening`), inertia relief
(:mod:`.relief`), modes and the dynamic response (:mod:`.modes`, :mod:`.dynamic`),
fatigue, materials, the unit-field store and VTK output. scikit-fem is imported inside
the functions that need it, so importing a module costs only what it uses. Units SI:
m, N, Pa.
"""

from importlib import import_module

#: the package's modules
__all__ = [
    "assembly",
    "cantilever",
    "dynamic",
    "elasticity",
    "errors",
    "fatigue",
    "hull",
    "invariants",
    "loading",
    "materials",
    "mesh",
    "mkl",
    "modes",
    "pin_pressure",
    "products",
    "progress",
    "relief",
    "screening",
    "solvers",
    "store",
    "stress",
    "superpose",
    "system",
    "unitcases",
    "vtk",
]


def __getattr__(name: str):
    """A module of the package, imported on first use (``railcheck.fea.elasticity``)."""
    if name not in __all__:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    module = import_module(f".{name}", __name__)
    globals()[name] = module
    return module


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
