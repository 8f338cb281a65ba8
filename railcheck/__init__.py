"""railcheck: design check for reconfigurable planar linkages built from linear-guide rails.

The application layer: the part registry (:mod:`railcheck.parts`), scenes
(:mod:`railcheck.scene`), units, files and errors at the top; ``check/``, ``sweep/``,
``report/``, ``studies/`` and ``cli/`` below. The domain packages ``railcheck.kinematics``,
``railcheck.loads``, ``railcheck.geometry`` and ``railcheck.fea`` are installed into this
namespace from the repository's top-level folders (see pyproject.toml).
"""

__version__ = "0.1.0"
