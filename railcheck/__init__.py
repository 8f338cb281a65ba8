"""railcheck: design check for reconfigurable planar linkages built from linear-guide rails.

The application layer: the part registry (:mod:`railcheck.parts`), scenes
(:mod:`railcheck.scene`), units, files and errors at the top; ``check/``, ``sweep/``,
``report/``, ``studies/`` and ``cli/`` below. The domain packages ``railcheck.kinematics``,
``railcheck.loads``, ``railcheck.geometry`` and ``railcheck.fea`` are installed into this
namespace from the repository's top-level folders (see pyproject.toml).

Python API (:mod:`railcheck.api`): ``railcheck.check(scene)``, ``railcheck.sweep(scene)`` and
``railcheck.mechanism(scene)`` (a planar mechanism study).
"""

__version__ = "0.1.0"


def __getattr__(name: str):
    """``railcheck.check`` and ``railcheck.sweep``, imported when first used: callable
    packages (:mod:`railcheck.api`), so ``import railcheck`` stays light."""
    if name in ("check", "sweep", "api"):
        import importlib

        return importlib.import_module(f"railcheck.{name}")
    if name == "mechanism":
        import importlib

        return importlib.import_module("railcheck.api").mechanism

        return importlib.import_module(f"railcheck.{name}")
    raise AttributeError(f"module 'railcheck' has no attribute {name!r}")
