"""VTK output: one .vtu per solved part, linear tetrahedra at the mesh's vertices with
point data ``displacement`` (m, 3 components), ``von_mises`` (Pa) and any further point
fields given (e.g. ``von_mises_envelope`` Pa, ``fatigue_safety_factor``). Written to a
temporary name in the target's directory and renamed."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np


def write_vtu(path: str | Path, points: np.ndarray, tets: np.ndarray, displacement: np.ndarray,
              von_mises: np.ndarray, extra: dict[str, np.ndarray] | None = None) -> Path:
    import meshio

    path = Path(path)
    data = {"displacement": np.asarray(displacement, float), "von_mises": np.asarray(von_mises, float)}
    for key, value in (extra or {}).items():
        value = np.asarray(value, float)
        data[key] = np.where(np.isfinite(value), value, np.finfo(float).max)   # VTK has no inf
    mesh = meshio.Mesh(points, [("tetra", tets.astype(np.int64))], point_data=data)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=".vtu", dir=path.parent)
    os.close(fd)
    try:
        meshio.write(tmp, mesh, file_format="vtu")
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path
