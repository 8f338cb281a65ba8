"""A part's mesh as plain numpy arrays (m): vertices, tetrahedra, named boundary groups
(triangles), quality figures and the curved edges of a quadratic mesh."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["MeshData"]


@dataclass(frozen=True)
class MeshData:
    """A tetrahedral mesh: ``points`` (n, 3) m, ``tets`` (m, 4) node indices, and named
    boundary groups ``groups[name]`` = (k, 3) triangle node indices. ``min_quality`` is
    gmsh's smallest minSICN over the elements, ``slivers`` how many fall below
    :data:`SLIVER_SICN`; ``seconds`` the meshing time (0 when read from the cache)."""

    points: np.ndarray
    tets: np.ndarray
    groups: dict[str, np.ndarray]
    min_quality: float
    slivers: int
    seconds: float
    cached: bool = False
    warning: str | None = None
    shipped: bool = False  # read from the meshes shipped with railcheck
    curved_edges: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int64))
    curved_points: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))

    @classmethod
    def of(cls, points: np.ndarray, tets: np.ndarray, groups: dict[str, np.ndarray]) -> MeshData:
        """A mesh of these arrays alone (quality unknown: NaN; no slivers counted; no
        meshing time), for the FE API where a mesh comes from elsewhere."""
        return cls(points, tets, groups, min_quality=float("nan"), slivers=0, seconds=0.0)

    @property
    def curved(self) -> tuple[np.ndarray, np.ndarray]:
        """(edges (k, 2), mid-edge points (k, 3) m): the quadratic mesh's curved edges
        (mid nodes on the true surfaces); every other edge of a P2 mesh is straight."""
        return self.curved_edges, self.curved_points
