"""Curved (isoparametric quadratic) tetrahedra: the mid-edge nodes gmsh places on the true
CAD surfaces, kept as a short list of the edges that are not straight, and a validity check.

A quadratic tetrahedron maps the reference element through its 10 nodes; with each
mid-edge node written as the edge's midpoint plus an offset d_ij, the map is the straight
(affine) one plus sum_ij 4 d_ij lambda_i lambda_j, so its Jacobian is

    J(xi) = J_affine + sum_ij 4 d_ij (lambda_j grad lambda_i + lambda_i grad lambda_j)^T.

Only the edges on curved surfaces (holes, bearing seats, fillets) have d_ij != 0; an
element is valid when det J keeps the sign of det J_affine everywhere. Units: m.
"""

from __future__ import annotations

import numpy as np

# barycentric gradients of the reference tetrahedron (lambda_0 = 1 - xi - eta - zeta)
_GRAD_LAMBDA = np.array([[-1.0, -1.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
LOCAL_EDGES = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])
MIN_JACOBIAN_RATIO = 0.2  # det J / det J_affine below this at a sample point: straighten the element


def _sample_barycentrics() -> np.ndarray:
    """(s, 4) barycentric points where det J is checked: vertices, edge midpoints, face and
    element centroids and the points of a degree-4 rule's layout (interior)."""
    pts = list(np.eye(4))
    pts += [0.5 * (np.eye(4)[a] + np.eye(4)[b]) for a, b in LOCAL_EDGES]
    pts += [np.where(np.arange(4) == k, 0.0, 1.0 / 3.0) for k in range(4)]
    pts += [np.full(4, 0.25)]
    for a in (0.1, 0.7):
        for k in range(4):
            w = np.full(4, (1.0 - a) / 3.0)
            w[k] = a
            pts.append(w)
    return np.array(pts)


def edge_keys(pairs: np.ndarray, n_points: int) -> np.ndarray:
    """int64 key of each vertex pair (k, 2), independent of the pair's order."""
    a, b = np.minimum(pairs[:, 0], pairs[:, 1]).astype(np.int64), np.maximum(pairs[:, 0], pairs[:, 1]).astype(np.int64)
    return a * np.int64(n_points) + b


def curved_from_tet10(points: np.ndarray, tets: np.ndarray, mids: np.ndarray, tol: float = 1e-9):
    """(edges (k, 2), edge_points (k, 3)): from quadratic tetrahedra (vertex indices
    ``tets`` (m, 4) into ``points``, mid-edge node coordinates ``mids`` (m, 6, 3) in the
    order of :data:`LOCAL_EDGES`), the edges whose mid node lies off the straight midpoint
    by more than ``tol`` x the edge length; one row per edge, vertex indices ascending."""
    ends = tets[:, LOCAL_EDGES]  # (m, 6, 2)
    straight = 0.5 * (points[ends[..., 0]] + points[ends[..., 1]])
    length = np.linalg.norm(points[ends[..., 0]] - points[ends[..., 1]], axis=-1)
    off = np.linalg.norm(mids - straight, axis=-1) > tol * length
    pairs = np.sort(ends[off], axis=1)
    _, first = np.unique(edge_keys(pairs, points.shape[0]), return_index=True)
    return pairs[first].astype(np.int64), mids[off][first]


def edge_offsets(points: np.ndarray, tets: np.ndarray, edges: np.ndarray, edge_points: np.ndarray) -> np.ndarray:
    """(m, 6, 3) m: each element's mid-edge offsets d_ij from the straight midpoints."""
    d = np.zeros((tets.shape[0], 6, 3))
    if edges.shape[0] == 0:
        return d
    n = points.shape[0]
    keys = edge_keys(edges, n)
    order = np.argsort(keys)
    mine = edge_keys(tets[:, LOCAL_EDGES].reshape(-1, 2), n)
    pos = np.clip(np.searchsorted(keys[order], mine), 0, keys.size - 1)
    hit = keys[order][pos] == mine
    offsets = edge_points - 0.5 * (points[edges[:, 0]] + points[edges[:, 1]])
    d.reshape(-1, 3)[hit] = offsets[order][pos[hit]]
    return d


def jacobian_ratios(points: np.ndarray, tets: np.ndarray, d: np.ndarray) -> np.ndarray:
    """(m, s): det J / det J_affine of each element at the sample points (1 for straight
    elements; <= 0 where a curved element folds over)."""
    lam = _sample_barycentrics()  # (s, 4)
    x = points[tets]  # (m, 4, 3)
    J_aff = np.einsum("mai,aj->mij", x, _GRAD_LAMBDA)  # (m, 3, 3): dx_i / dxi_j
    i, j = LOCAL_EDGES[:, 0], LOCAL_EDGES[:, 1]
    # gradient (reference) of lambda_i lambda_j at each sample: (s, 6, 3)
    g = lam[:, j, None] * _GRAD_LAMBDA[i][None] + lam[:, i, None] * _GRAD_LAMBDA[j][None]
    J = J_aff[:, None] + 4.0 * np.einsum("mei,sej->msij", d, g)
    return np.linalg.det(J) / np.linalg.det(J_aff)[:, None]


def straighten_folded(
    points: np.ndarray, tets: np.ndarray, edges: np.ndarray, edge_points: np.ndarray, min_ratio: float = MIN_JACOBIAN_RATIO
):
    """(edges, edge_points, straightened): drop the curving of every element whose
    Jacobian ratio falls below ``min_ratio`` at a sample point (its edges go back to
    straight, also in its neighbours), repeated until every element is valid."""
    dropped = 0
    n = points.shape[0]
    for _ in range(50):
        d = edge_offsets(points, tets, edges, edge_points)
        curved = np.flatnonzero(np.any(d != 0.0, axis=(1, 2)))
        if curved.size == 0:
            break
        bad = curved[np.min(jacobian_ratios(points, tets[curved], d[curved]), axis=1) < min_ratio]
        if bad.size == 0:
            break
        remove = np.isin(edge_keys(edges, n), edge_keys(tets[bad][:, LOCAL_EDGES].reshape(-1, 2), n))
        dropped += int(np.count_nonzero(remove))
        edges, edge_points = edges[~remove], edge_points[~remove]
    return edges, edge_points, dropped
