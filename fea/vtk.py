"""VTK output: one .vtu per solved part, linear tetrahedra at the mesh's vertices with
point data ``displacement`` (m, 3 components), ``von_mises`` (Pa) and any further point
fields given (e.g. ``von_mises_envelope`` Pa, ``fatigue_safety_factor``). Writes the
path it is given: callers that need an atomic file pass a temporary path and rename it
(railcheck.files.atomic_path)."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def write_vtu(path: str | Path, points: np.ndarray, tets: np.ndarray, displacement: np.ndarray,
              von_mises: np.ndarray, extra: dict[str, np.ndarray] | None = None) -> Path:
    import meshio

    data = {"displacement": np.asarray(displacement, float), "von_mises": np.asarray(von_mises, float)}
    for key, value in (extra or {}).items():
        value = np.asarray(value, float)
        data[key] = np.where(np.isfinite(value), value, np.finfo(float).max)   # VTK has no inf
    meshio.write(str(path), meshio.Mesh(points, [("tetra", tets.astype(np.int64))], point_data=data),
                 file_format="vtu")
    return Path(path)
