"""The convex hull of a coefficient history: the steps at which any convex function of the
coefficients (von Mises, a component's extremes) takes its maximum over the cycle
(:func:`candidate_steps`), and for two coefficients the cycle's polygon and its support
function (:func:`hull_polygon`, :func:`support`). Shared by the superposition
(:mod:`.superpose`) and the screens (:mod:`.screening`)."""

from __future__ import annotations

import numpy as np

HULL_MAX_DIM = 3  # above it, every step is evaluated (qhull on a closed curve in 5 dimensions took minutes)


def hull_applies(steps: int, k: int) -> bool:
    """Whether qhull can drop steps of a history of ``steps`` x ``k`` coefficients (not
    for few steps, one coefficient or more than :data:`HULL_MAX_DIM`)."""
    return steps > 8 * (k + 1) and 2 <= k <= HULL_MAX_DIM


def candidate_steps(C: np.ndarray) -> np.ndarray:
    """Indices of the steps that can hold the maximum of any convex function of the
    coefficients (the convex hull's vertices), or every step where qhull cannot help
    (:func:`hull_applies`; degenerate point sets)."""
    steps, k = C.shape
    everything = np.arange(steps)
    if not hull_applies(steps, k):
        return everything
    from scipy.spatial import ConvexHull, QhullError

    scale = np.abs(C).max(axis=0)
    live = (scale > 0) & (np.ptp(C, axis=0) > 0)  # a constant column cannot move the maximum
    X = C[:, live] / scale[live]
    if X.shape[1] < 2:
        return np.unique(np.r_[np.argmax(X[:, 0]) if X.size else 0, np.argmin(X[:, 0]) if X.size else 0])
    rank = np.linalg.matrix_rank(X - X.mean(axis=0), tol=1e-9 * np.sqrt(steps))
    if rank < X.shape[1]:
        return everything
    try:
        return np.unique(ConvexHull(X).vertices)
    except (QhullError, ValueError):
        return everything


def hull_polygon(C: np.ndarray) -> np.ndarray | None:
    """The 2D points' convex hull vertices in counter-clockwise order, or None when
    they do not span a polygon."""
    from scipy.spatial import ConvexHull, QhullError

    scale = np.abs(C).max(axis=0)
    if C.shape[0] < 4 or np.any(scale == 0):
        return None
    try:
        hull = ConvexHull(C / scale)
    except (QhullError, ValueError):
        return None
    return C[hull.vertices]  # qhull orders 2D vertices counter-clockwise


def support_range(D: np.ndarray, V: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(max, min) over the polygon's vertices V (h, 2, counter-clockwise) of d . v for
    every row d of D (m, 2): :func:`support` of D and of -D, whose angle is d's plus pi
    (one arctan2 for both; the bracket's neighbours absorb the rounding)."""
    angle = np.arctan2(D[:, 1], D[:, 0])
    return support(D, V, angle), -support(-D, V, angle + np.pi)


def support(D: np.ndarray, V: np.ndarray, angle: np.ndarray | None = None) -> np.ndarray:
    """max over the polygon's vertices V (h, 2, counter-clockwise) of d . v for every row
    d of D (m, 2): the vertex after the edge whose outward normal angle precedes d's
    (``angle``: the rows' arctan2, when already known)."""
    edges = np.roll(V, -1, axis=0) - V
    normal_angle = np.arctan2(-edges[:, 0], edges[:, 1])  # outward normal (e_y, -e_x)
    start = normal_angle[0]
    rel = np.mod(normal_angle - start, 2 * np.pi)
    rel[0] = 0.0
    theta = np.mod((np.arctan2(D[:, 1], D[:, 0]) if angle is None else angle) - start, 2 * np.pi)
    edge = np.searchsorted(rel, theta, side="right") - 1
    h = V.shape[0]
    # the candidate and its neighbours, to absorb rounding at the bracket's ends
    best = np.full(D.shape[0], -np.inf)
    for shift in (0, 1, 2):
        v = V[(edge + shift) % h]
        best = np.maximum(best, np.einsum("ij,ij->i", D, v))
    return best
