"""Untangling curved quadratic tetrahedra, the same bytes every run.

Where a mid-edge node placed on a concave surface (a rail's ball-track groove) bulges into a
thin element beside it, that element's Jacobian folds. Straightening the curved edge there
facets the surface (a sixth of the groove's edges: the section gains 3.5% of area at its
extreme fibres, ``benchmarks/groove_mesh.py``); gmsh's high-order untangling instead moves
the mid nodes round the element, but orders its variables by memory address, so its result
moves by up to a micrometre from run to run. This module does what gmsh's does in a fixed
order, with numpy's pairwise sums only (no BLAS, whose threads could change the sums):

* the patch: every element whose Jacobian ratio ``det J / det J_affine`` falls below
  :data:`~railcheck.geometry.curving.MIN_JACOBIAN_RATIO` at a sample point, and the
  elements sharing an edge with one;
* the variables: the offsets of the patch's mid nodes, an interior one free in 3D, one on a
  flat boundary face within its plane, one on a curved surface or a feature line fixed (the
  curved boundary stays on its true surface);
* the objective: over every element a variable touches and every sample point, the squared
  shortfall of the Jacobian ratio below :data:`TARGET`, plus a small pull toward the
  straight position (:data:`PULL` x (offset / edge length)^2);
* the minimiser: L-BFGS (:data:`MEMORY` pairs, backtracking Armijo steps) for
  :data:`ITERATIONS` iterations from the gmsh placement.

Whatever still folds is straightened afterwards (:func:`curving.straighten_folded`). On the
grooved 1000 mm rail it leaves fewer edges straightened than gmsh's untangling and a section
closer to the closed form (docs/model.md, "Meshing the grooves"). Units: m.
"""

from __future__ import annotations

import numpy as np

from .curving import _GRAD_LAMBDA, LOCAL_EDGES, MIN_JACOBIAN_RATIO, _sample_barycentrics, edge_keys

#: the Jacobian ratio the objective lifts every sample point to (above the validity ratio)
TARGET = 0.35

#: weight of the pull toward the straight mid node, per (offset / edge length)^2
PULL = 1e-3

#: L-BFGS iterations (the 1000 mm rail's folds are lifted in about 30)
ITERATIONS = 30

#: L-BFGS correction pairs kept
MEMORY = 8

_FACES = np.array([[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]])


def untangle(points: np.ndarray, tets: np.ndarray, edges: np.ndarray, edge_points: np.ndarray):
    """(edges, edge_points): the curved edges (vertex pairs (k, 2), mid nodes (k, 3), m) of
    the mesh ``points`` / ``tets`` with the folded elements' mid nodes moved (module doc);
    the mesh unchanged where nothing folds."""
    problem = untangling_problem(points, tets, edges, edge_points)
    if problem is None:
        return edges, edge_points
    objective, pairs = problem
    offsets = objective.offsets(_lbfgs(objective, np.zeros(objective.free.size * 3), ITERATIONS))
    curved = np.any(offsets != 0.0, axis=1)
    mid = 0.5 * (points[pairs[:, 0]] + points[pairs[:, 1]])
    return pairs[curved], (mid + offsets)[curved]


def untangling_problem(points: np.ndarray, tets: np.ndarray, edges: np.ndarray, edge_points: np.ndarray):
    """(objective, every edge's vertex pair (e, 2)) of the folded elements' patch (module
    doc), the objective a function of the free mid nodes' reduced coordinates; None where
    nothing folds."""
    import scipy.sparse as sp  # the mesh stage's: reading a scene imports no scipy

    n, m = points.shape[0], tets.shape[0]
    keys, eid = np.unique(edge_keys(tets[:, LOCAL_EDGES].reshape(-1, 2), n), return_inverse=True)
    eid = eid.reshape(m, 6)
    pairs = np.column_stack([keys // n, keys % n])
    offsets = np.zeros((keys.size, 3))
    offsets[np.searchsorted(keys, edge_keys(edges, n))] = edge_points - 0.5 * (points[edges[:, 0]] + points[edges[:, 1]])
    jac = _Jacobians(points, tets, eid)
    bad = np.flatnonzero(jac.ratios(offsets, np.arange(m)).min(axis=1) < MIN_JACOBIAN_RATIO)
    if bad.size == 0:
        return None
    motion = _mid_node_motion(points, tets, keys, np.any(offsets != 0.0, axis=1))
    incidence = sp.csr_matrix((np.ones(m * 6), (eid.ravel(), np.repeat(np.arange(m), 6))), shape=(keys.size, m))
    free = np.unique(eid[_grown(bad, eid, incidence)].ravel())
    free = free[np.any(motion[free] != 0.0, axis=(1, 2))]
    touched = np.flatnonzero(np.asarray(incidence[free].sum(axis=0)).ravel() > 0)
    length = np.linalg.norm(points[pairs[free, 0]] - points[pairs[free, 1]], axis=1)
    return _Objective(jac, offsets, free, motion[free], length, touched, eid), pairs


class _Jacobians:
    """The Jacobian at :func:`curving._sample_barycentrics` of the elements of a mesh with
    given mid-node offsets (J = J_affine + 4 sum_e d_e g_e^T, :mod:`curving`'s doc)."""

    def __init__(self, points: np.ndarray, tets: np.ndarray, eid: np.ndarray):
        lam = _sample_barycentrics()
        i, j = LOCAL_EDGES[:, 0], LOCAL_EDGES[:, 1]
        self.g = lam[:, j, None] * _GRAD_LAMBDA[i][None] + lam[:, i, None] * _GRAD_LAMBDA[j][None]  # (s, 6, 3)
        self.affine = np.einsum("mai,aj->mij", points[tets], _GRAD_LAMBDA)
        self.det_affine = _det(self.affine)
        self.eid = eid

    def matrices(self, offsets: np.ndarray, elements: np.ndarray) -> np.ndarray:
        """(e, s, 3, 3) the Jacobians of ``elements`` at the sample points."""
        return self.affine[elements, None] + 4.0 * np.einsum("mei,sej->msij", offsets[self.eid[elements]], self.g)

    def ratios(self, offsets: np.ndarray, elements: np.ndarray) -> np.ndarray:
        """(e, s) det J / det J_affine of ``elements`` at the sample points."""
        return _det(self.matrices(offsets, elements)) / self.det_affine[elements, None]


class _Objective:
    """The untangling objective and its gradient in the free mid nodes' reduced
    coordinates ``q`` (each node's offset ``d0 + P q``; module doc)."""

    def __init__(self, jac: _Jacobians, offsets, free, motion, length, touched, eid):
        self.jac, self.start, self.free, self.motion, self.length, self.touched = jac, offsets, free, motion, length, touched
        self.eid = eid
        self.sample_grads = np.ascontiguousarray(jac.g.transpose(0, 2, 1)).reshape(-1, 6)  # (s * 3, 6): g[s, k, j]

    def offsets(self, q: np.ndarray) -> np.ndarray:
        out = self.start.copy()
        out[self.free] += np.einsum("vij,vj->vi", self.motion, q.reshape(-1, 3))
        return out

    def __call__(self, q: np.ndarray) -> tuple[float, np.ndarray]:
        d, jac = self.offsets(q), self.jac
        J = jac.matrices(d, self.touched)
        short = np.maximum(TARGET - _det(J) / jac.det_affine[self.touched, None], 0.0)  # (e, s)
        scaled = q.reshape(-1, 3) / self.length[:, None]
        value = float(np.sum(short * short) + PULL * np.sum(scaled * scaled))
        live = np.flatnonzero(np.any(short > 0.0, axis=1))  # the rest add nothing to the gradient
        els = self.touched[live]
        weight = -8.0 * short[live] / jac.det_affine[els, None]  # d(short^2)/d det J, times the 4 of J's mid terms
        weighted = (weight[:, :, None, None] * _cofactor(J[live])).transpose(0, 2, 1, 3)  # (e, i, s, j)
        # d objective / d offset i of each element's edge k: sum over s, j of weighted[., i, s, j] g[s, k, j]
        grad_edges = np.einsum("eil,lk->eki", weighted.reshape(live.size, 3, self.sample_grads.shape[0]), self.sample_grads)
        cols, n_edges = self.eid[els].ravel(), self.start.shape[0]
        flat = grad_edges.reshape(-1, 3)
        grad = np.stack([np.bincount(cols, weights=flat[:, c], minlength=n_edges) for c in range(3)], axis=1)[self.free]
        grad_q = np.einsum("vji,vj->vi", self.motion, grad) + 2.0 * PULL * scaled / self.length[:, None]
        return value, grad_q.ravel()


def _mid_node_motion(points: np.ndarray, tets: np.ndarray, keys: np.ndarray, curved: np.ndarray) -> np.ndarray:
    """(edges, 3, 3) the projection each mid node may move along: the identity inside the
    part, the face's plane on a flat boundary (both boundary faces at the edge coplanar),
    zero on a curved surface or a feature line."""
    n = points.shape[0]
    faces = np.sort(tets[:, _FACES].reshape(-1, 3), axis=1)
    _, inverse, count = np.unique((faces[:, 0] * n + faces[:, 1]) * n + faces[:, 2], return_inverse=True, return_counts=True)
    boundary = faces[count[inverse] == 1]
    normal = np.cross(points[boundary[:, 1]] - points[boundary[:, 0]], points[boundary[:, 2]] - points[boundary[:, 0]])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    side = np.searchsorted(
        keys, edge_keys(np.concatenate([boundary[:, [0, 1]], boundary[:, [1, 2]], boundary[:, [0, 2]]]), n)
    )
    normals = np.concatenate([normal, normal, normal])
    order = np.argsort(side, kind="stable")
    side, normals = side[order], normals[order]
    on_boundary = np.unique(side)
    first, last = np.searchsorted(side, on_boundary), np.searchsorted(side, on_boundary, side="right") - 1
    n1, n2 = normals[first], normals[last]
    flat = (np.abs(np.sum(n1 * n2, axis=1)) > 1.0 - 1e-9) & (last - first == 1) & ~curved[on_boundary]
    motion = np.broadcast_to(np.eye(3), (keys.size, 3, 3)).copy()
    motion[on_boundary] = 0.0
    motion[on_boundary[flat]] = np.eye(3) - n1[flat][:, :, None] * n1[flat][:, None, :]
    return motion


def _grown(bad: np.ndarray, eid: np.ndarray, incidence) -> np.ndarray:
    """Boolean mask of the elements ``bad`` and those sharing an edge with one of them."""
    edges = np.zeros(incidence.shape[0])
    edges[eid[bad].ravel()] = 1.0
    return np.asarray(incidence.T @ edges > 0).ravel()


def _lbfgs(objective, x: np.ndarray, iterations: int) -> np.ndarray:
    """``iterations`` L-BFGS steps on ``objective`` (value, gradient) from ``x``, with
    backtracking Armijo line searches; sums pairwise (np.sum), never through BLAS."""
    value, grad = objective(x)
    history: list[tuple[np.ndarray, np.ndarray, float]] = []
    for _ in range(iterations):
        direction = -_two_loop(grad, history)
        slope = float(np.sum(direction * grad))
        if not slope < 0.0:
            direction, slope, history = -grad, -float(np.sum(grad * grad)), []
        if slope == 0.0:
            break
        step, trial = 1.0, None
        for _ in range(30):
            trial = objective(x + step * direction)
            if trial[0] <= value + 1e-4 * step * slope:
                break
            step *= 0.5
        assert trial is not None
        if not trial[0] < value:
            break
        s, y = step * direction, trial[1] - grad
        sy = float(np.sum(s * y))
        if sy > 0.0:
            history = (history + [(s, y, 1.0 / sy)])[-MEMORY:]
        x, (value, grad) = x + s, trial
    return x


def _two_loop(grad: np.ndarray, history: list) -> np.ndarray:
    """The L-BFGS two-loop recursion: the inverse Hessian estimate times ``grad``."""
    q, alphas = grad.copy(), []
    for s, y, rho in reversed(history):
        a = rho * float(np.sum(s * q))
        q -= a * y
        alphas.append(a)
    if history:
        s, y, _ = history[-1]
        q *= float(np.sum(s * y)) / float(np.sum(y * y))
    for (s, y, rho), a in zip(history, reversed(alphas)):
        q += (a - rho * float(np.sum(y * q))) * s
    return q


def _det(J: np.ndarray) -> np.ndarray:
    """det of (..., 3, 3) matrices, written out (the rows' triple product)."""
    return np.sum(J[..., 0, :] * np.cross(J[..., 1, :], J[..., 2, :]), axis=-1)


def _cofactor(J: np.ndarray) -> np.ndarray:
    """The cofactor matrices of (..., 3, 3) ``J`` (d det J / d J)."""
    a0, a1, a2 = J[..., 0, :], J[..., 1, :], J[..., 2, :]
    return np.stack([np.cross(a1, a2), np.cross(a2, a0), np.cross(a0, a1)], axis=-2)
