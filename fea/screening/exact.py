"""Exact values at the nodes the screens keep: von Mises over every step, and each
component's extremes for fatigue (by the cycle polygon's support function for two
coefficients). Pa throughout."""

from __future__ import annotations

import numpy as np

from ..fatigue import alternating_and_mean
from ..hull import hull_polygon, support
from ..invariants import von_mises_squared
from . import tuning
from .screens import Screen, value_slices


def exact_von_mises2(screen: Screen, nodes: np.ndarray, c: np.ndarray) -> float:
    """Pa^2: the largest von Mises squared over ``nodes`` and every step of the history
    ``c`` (T, k) (the stresses at every step, in chunks)."""
    best = 0.0
    for g in value_slices(nodes.size, 6 * c.shape[0], tuning.EXACT_VALUES):
        X = screen.stress[:, nodes[g]] @ c.T  # (6, u, T)
        best = max(best, float(von_mises_squared(X).max()))
    return best


def enclosing_ellipse(C: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(c0 (S, k), E (S, k, k)): an ellipse ``{c: (c - c0)^T E^-1 (c - c0) <= 1}`` holding
    every point of each history: the points' covariance, scaled to reach the farthest."""
    c0 = C.mean(axis=1)
    D = C - c0[:, None, :]
    k = C.shape[2]
    cov = np.einsum("shk,shl->skl", D, D) / C.shape[1]
    scale = np.trace(cov, axis1=1, axis2=2)[:, None, None]
    cov = cov + (1e-12 * scale + 1e-300) * np.eye(k)
    reach = np.einsum("shk,skl,shl->sh", D, np.linalg.inv(cov), D).max(axis=1)
    return c0, cov * (reach * (1.0 + 1e-9) + 1e-300)[:, None, None]


def ellipse_fatigue_bounds(stress: np.ndarray, c0: np.ndarray, E: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Upper bounds (n, S) of the alternating and midrange von Mises at every node: each
    component's half-range is at most ``h = sqrt(s^T E s)`` and its midrange lies within
    ``s . c0 +- h``; the alternating components are non-negative (no cross terms)."""
    h = np.sqrt(np.maximum(np.einsum("jnk,skl,jnl->jns", stress, E, stress, optimize=True), 0.0))
    B = np.abs(np.einsum("jnk,sk->jns", stress, c0)) + h
    sa = np.sqrt(h[0] ** 2 + h[1] ** 2 + h[2] ** 2 + 3.0 * (h[3] ** 2 + h[4] ** 2 + h[5] ** 2))
    sm = np.sqrt(
        0.5 * ((B[0] + B[1]) ** 2 + (B[1] + B[2]) ** 2 + (B[2] + B[0]) ** 2) + 3.0 * (B[3] ** 2 + B[4] ** 2 + B[5] ** 2)
    )
    return sa, sm


def fatigue_exact(screen: Screen, nodes: np.ndarray, C: np.ndarray, factor, polygons=None) -> np.ndarray:
    """(S,) the smallest fatigue factor over ``nodes``: each component's maximum and
    minimum over the cycle from every step (tensordot), or, with two coefficients, from the
    cycle's convex polygon's support function (no step loop; :func:`railcheck.fea.superpose.support`;
    ``polygons`` the histories' hulls when already known)."""

    if screen.angle is not None:
        return fatigue_exact_planar(screen, nodes, C, factor, polygons)
    return exact_at(screen, nodes, C, factor, peak=False)[1]


def exact_at(screen: Screen, nodes: np.ndarray, C: np.ndarray, factor=None, peak: bool = True):
    """((S,) Pa^2, (S,)): over ``nodes`` and every step of each history of ``C`` (S, T, k),
    the largest von Mises squared (0 without ``peak``) and, with a ``factor``, the
    smallest fatigue factor (each component's extremes over the steps; else inf), both
    from one product (tensordot), in chunks of :data:`tuning.EXACT_VALUES`."""
    vm2, least = np.zeros(C.shape[0]), np.full(C.shape[0], np.inf)
    for g in value_slices(C.shape[0], 6 * nodes.size * C.shape[1], tuning.EXACT_VALUES):
        # and the nodes in groups too: one history over many nodes stays within tuning.EXACT_VALUES
        for h in value_slices(nodes.size, 6 * C.shape[1] * (g.stop - g.start), tuning.EXACT_VALUES):
            X = np.tensordot(screen.stress[:, nodes[h], :], C[g], axes=([2], [2]))  # (6, u, s, T)
            if peak:
                vm2[g] = np.maximum(vm2[g], von_mises_squared(X).max(axis=(0, 2), initial=0.0))
            if factor is not None:
                sa, sm = alternating_and_mean(X.max(axis=3), X.min(axis=3))
                least[g] = np.minimum(least[g], factor(sa, sm).min(axis=0, initial=np.inf))
    return vm2, least


def fatigue_exact_planar(screen: Screen, nodes: np.ndarray, C: np.ndarray, factor, polygons=None) -> np.ndarray:

    assert screen.angle is not None  # two coefficients: the screen has each component's angle
    D = screen.stress[:, nodes, :].reshape(-1, 2)
    angle = screen.angle[:, nodes].reshape(-1)
    out = np.empty(C.shape[0])
    for s, c in enumerate(C):
        V = hull_polygon(c) if polygons is None else polygons[s]
        if V is None:  # a segment or a point: every step, exactly
            X = D @ c.T
            hi, lo = X.max(axis=1), X.min(axis=1)
        else:
            hi, lo = support(D, V, angle), -support(-D, V, angle + np.pi)
        sa, sm = alternating_and_mean(hi.reshape(6, -1), lo.reshape(6, -1))
        out[s] = factor(sa, sm).min()
    return out


def tip_peak(screen: Screen, C: np.ndarray) -> np.ndarray:
    """(S,) m: the largest tip displacement magnitude over each history."""
    return np.linalg.norm(C @ screen.tip.T, axis=2).max(axis=1)
