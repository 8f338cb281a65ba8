"""Superposition of unit load cases: the stress at every node and step of a load history
without a solve per step.

A linear part's stress is ``sigma(node, t) = sum_k c_k(t) S_k(node)``: ``S`` (6, nodes, k)
the recovered stress of unit case k (Pa per unit coefficient), ``C`` (steps, k) the
coefficient history. Von Mises is a convex function of ``c`` and every stress component
a linear one, so their maxima (and the components' minima) over the cycle are reached at
the vertices of the convex hull of the points ``c(t)``: :func:`candidate_steps` finds
them (qhull), and everything else is evaluated on those steps only, exactly. All of it is
vectorised over nodes and steps, in memory-bounded chunks of nodes.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from . import screening
from .elasticity import von_mises
from .hull import candidate_steps, hull_polygon, support_range
from .invariants import VM_QUADRATIC  # von Mises squared as s^T P s (re-exported)

CHUNK_VALUES = 20_000_000  # floats per chunk of (6, nodes, steps) of a von Mises pass
#: floats per chunk of (6, nodes, steps) when each component's maximum and minimum are read
#: from the chunk (:func:`component_range`): 4 MB stay in cache for the two passes, where
#: a larger chunk streams from memory twice (the same digits; measured: docs/changelog.md,
#: "The measurements behind tuned constants")
RANGE_CHUNK_VALUES = 1 << 19
#: steps per block of :func:`pruned_range`, and the fewest steps it is used for
RANGE_BLOCK = 32
RANGE_PRUNE_STEPS = 8 * RANGE_BLOCK
#: main directions by which a block of steps is bounded (:class:`_Blocks`): with one, the
#: default check's rails read 15-22 of 157 blocks per node component and extreme; with
#: two (the arc's curvature), 5-6
BLOCK_DIRECTIONS = 2
#: relative margin of :func:`pruned_range`'s bounds for the products' rounding (of
#: ``|s w| k``, w the coefficients' scales: far above float64's, far below any stress
#: that matters)
PRUNE_SLACK = 1e-12


@dataclass(frozen=True)
class UnitFields:
    """Unit-case results of one part at its stress nodes (vertices first, then P2's
    mid-edge nodes): ``stress`` (6, nodes, k) Pa, ``displacement`` (nodes, 3, k) m,
    ``tip`` (3, k) m, ``nodes`` (nodes, 3) m, ``cells`` (elements, 4 or 10) in VTK order,
    ``verdict_mask`` (nodes,) True away from the support's singular zone, ``support`` and
    ``loaded`` the indices of the nodes on the support and on the loaded groups."""

    stress: np.ndarray
    tip: np.ndarray
    displacement: np.ndarray
    nodes: np.ndarray
    verdict_mask: np.ndarray
    names: tuple[str, ...]
    cells: np.ndarray | None = None
    support: np.ndarray | None = None
    loaded: np.ndarray | None = None
    tips: dict | None = None  # key -> (3, k) m: one deflection per key (FreeBodyCases.deflection a dict)


@dataclass(frozen=True)
class Envelope:
    """The cycle's worst: ``max_von_mises`` (Pa) over the verdict nodes and steps, at
    ``step`` and node ``node`` (``location`` m); ``node_envelope`` (nodes,) each node's
    maximum over the cycle (Pa); ``max_tip`` (m) and its step; ``support_peak`` (Pa), the
    maximum at any node including the support's singular zone."""

    max_von_mises: float
    step: int
    node: int
    location: np.ndarray
    node_envelope: np.ndarray | None  # None when only the peaks were asked for (node_envelope_of gives it)
    max_tip: float
    tip_step: int
    support_peak: float


def first_columns(fields: UnitFields, k: int) -> UnitFields:
    """The fields of the first ``k`` unit cases only (a part's modes dropped)."""
    return replace(
        fields,
        stress=fields.stress[..., :k],
        tip=fields.tip[:, :k],
        displacement=fields.displacement[..., :k],
        names=fields.names[:k],
        tips=None if fields.tips is None else {key: v[:, :k] for key, v in fields.tips.items()},
    )


def reduced(fields: UnitFields, C: np.ndarray, rtol: float = 1e-12) -> tuple[UnitFields, np.ndarray]:
    """The same history in the fewest coefficients, exactly: ``C = A B^T`` with the first
    column of ``A`` all ones (B's first column the history's mean) and the others its
    principal coordinates (an SVD of the centred history, keeping the singular values above
    ``rtol`` of the largest); the fields' ``stress`` and ``tip`` become ``S B`` and
    ``tip B`` (displacements are left out: use the full fields for them). A free body's
    8-9 coefficients span an affine plane (the crank) or a 3-5 dimensional one; the planar
    case then takes the convex polygon's fast paths. Returns the inputs when nothing is
    gained."""
    T, k = C.shape
    if T < 2 or k < 3:
        return fields, C
    # in stress units (each coefficient times its largest stress per unit), so what the
    # truncation drops is small in stress, not only in coefficients (a mode's unit stress
    # is huge beside a force's)
    w = np.sqrt((fields.stress**2).sum(axis=0).max(axis=0)) + 1e-300  # (k,)
    Cw = C * w
    mean = Cw.mean(axis=0)
    U, s, Vt = np.linalg.svd(Cw - mean, full_matrices=False)
    scale = max(float(s[0]) if s.size else 0.0, float(np.abs(mean).max()) * np.sqrt(T))
    r = int(np.count_nonzero(s > rtol * scale)) if scale > 0 else 0
    if r + 1 >= k:
        return fields, C
    B = np.column_stack([mean, Vt[:r].T]) / w[:, None]  # (k, r + 1)
    A = np.column_stack([np.ones(T), U[:, :r] * s[:r]])  # (T, r + 1)
    names = ("mean",) + tuple(f"principal {i + 1}" for i in range(r))
    out = replace(
        fields,
        stress=np.tensordot(fields.stress, B, axes=([2], [0])),
        tip=fields.tip @ B,
        displacement=fields.displacement[..., :0],
        names=names,
        tips=None,
    )
    return out, A


def stress_at(S: np.ndarray, c: np.ndarray) -> np.ndarray:
    """(6, nodes[, steps]) Pa for coefficients ``c`` (k,) or (steps, k)."""
    return np.tensordot(S, np.asarray(c, float).T, axes=([2], [0]))


def _node_chunks(nodes: int, steps: int, values: int = CHUNK_VALUES):
    size = max(1, values // (6 * max(steps, 1)))
    for start in range(0, nodes, size):
        yield slice(start, min(start + size, nodes))


def von_mises_max(S: np.ndarray, C: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(max over steps (nodes,) Pa, the step of it (nodes,), the first of equal ones) for
    every node: a long history by blocks of steps, only the blocks that can hold a node's
    maximum read whole (:func:`pruned_von_mises_max`), a short one at every step
    (:func:`dense_von_mises_max`)."""
    if C.shape[0] >= RANGE_PRUNE_STEPS and np.isfinite(C).all():  # else NaN out, for the caller to refuse
        return pruned_von_mises_max(S, C)
    return dense_von_mises_max(S, C)


def _quadratic_forms(S: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Von Mises squared as a quadratic form in the coefficients, ``c^T Q_n c`` with ``Q_n
    = S_n^T P S_n`` (k x k per node, symmetric): (nodes, k (k + 1) / 2) its distinct
    entries, and their (i, j) indices (:func:`_products` pairs the steps with them)."""
    nodes, k = S.shape[1], S.shape[2]
    i, j = np.triu_indices(k)
    full = np.einsum("cnk,cd,dnl->nkl", S, VM_QUADRATIC, S, optimize=True).reshape(nodes, k * k)
    return np.take(full, i * k + j, axis=1), i, j


def _products(C: np.ndarray, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """(k (k + 1) / 2, steps) the steps' products ``c_i c_j``, off the diagonal twice."""
    return (C[:, i] * C[:, j] * np.where(i == j, 1.0, 2.0)).T


def dense_von_mises_max(S: np.ndarray, C: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`von_mises_max` at every step: one matrix product of the quadratic forms'
    k (k + 1) / 2 distinct entries with the steps' products, (nodes x k(k+1)/2) @
    (k(k+1)/2 x steps): 120 products per node and step instead of 225 at 15 coefficients."""
    nodes = S.shape[1]
    Q, i, j = _quadratic_forms(S)
    CC = _products(C, i, j)
    best = np.empty(nodes)
    where = np.empty(nodes, dtype=np.int64)
    for sl in _node_chunks(nodes, C.shape[0]):
        vm2 = Q[sl] @ CC  # (chunk, steps)
        where[sl] = np.argmax(vm2, axis=1)
        best[sl] = np.take_along_axis(vm2, where[sl, None], axis=1)[:, 0]
    return np.sqrt(np.maximum(best, 0.0)), where


def pruned_von_mises_max(S: np.ndarray, C: np.ndarray, block: int = RANGE_BLOCK) -> tuple[np.ndarray, np.ndarray]:
    """:func:`von_mises_max` of a long history ``C`` (steps, k) by blocks of ``block``
    consecutive steps (:class:`_Blocks`), exact (to rounding).

    Von Mises is a norm of the stress, ``|A c|`` with ``A = VM_FACTOR S_n`` (6 x k), so
    at a step of a block ``|A c_t| <= |A c_m| + sum_d |A u_d w| max|a_td| + ||A w_moving||_F
    max|e_t|`` (triangle inequality; the spectral norm is at most the Frobenius one): a block where
    that cannot reach the node's best middle value cannot hold its maximum. Only the
    blocks that can are read at every step, with the quadratic forms of
    :func:`dense_von_mises_max` (the same values)."""
    nodes, k = S.shape[1], S.shape[2]
    g = _Blocks.of(C, block)
    nb, width = g.steps.shape
    Q, i, j = _quadratic_forms(S)
    middle2 = Q @ _products(g.middle, i, j)  # (nodes, nb): von Mises squared at real steps
    first = np.argmax(middle2, axis=1)
    best2 = middle2[np.arange(nodes), first]
    best = np.sqrt(np.maximum(best2, 0.0))
    found_rows, found_blocks = [], []
    size = max(1, RANGE_CHUNK_VALUES // (6 * nb))
    for sl in (slice(a, min(a + size, nodes)) for a in range(0, nodes, size)):
        F = np.tensordot(screening.VM_FACTOR, S[:, sl], axes=(1, 0))  # (6, chunk, k): von Mises = |F c|
        reach = np.zeros((F.shape[1], nb))
        for u, a in zip(g.directions_w, g.reach_along):
            along = F @ u.T  # (6, chunk, nb)
            reach += np.sqrt(np.einsum("cnb,cnb->nb", along, along)) * a
        # |F w|_F, and the square root of the quadratic forms' rounding (relative eps k^2)
        frob = np.sqrt(np.einsum("cnk,cnk,k->n", F, F, g.w * g.w))
        frob_moving = np.sqrt(np.einsum("cnk,cnk,k->n", F, F, g.w_moving * g.w_moving))
        reach += frob_moving[:, None] * g.reach_across + (frob * VM_PRUNE_SLACK * k)[:, None]
        reach += np.sqrt(np.maximum(middle2[sl], 0.0))
        can_rows, can_blocks = np.nonzero(reach >= best[sl, None])
        found_rows.append(can_rows + sl.start)
        found_blocks.append(can_blocks)
    rows = np.concatenate(found_rows)
    value, step = _read_von_mises_blocks(
        Q, _products(g.values.reshape(-1, k), i, j), g.steps, rows, np.concatenate(found_blocks)
    )
    # each node's largest value, at the first step of equal ones (as a read of every step)
    middle_step = g.steps[first, width // 2]
    np.maximum.at(best2, rows, value)
    where = np.where(middle2[np.arange(nodes), first] == best2, middle_step, np.iinfo(np.int64).max)
    tied = value == best2[rows]
    np.minimum.at(where, rows[tied], step[tied])
    return np.sqrt(np.maximum(best2, 0.0)), where


#: margin of :func:`pruned_von_mises_max`'s bounds, in units of a node's ``|A w|_F k``:
#: the square root of the quadratic forms' relative rounding (von Mises squared is read,
#: so a small von Mises is known to about sqrt(eps) of the node's scale)
VM_PRUNE_SLACK = 1e-7


def _read_von_mises_blocks(Q, CC, steps, rows, which) -> tuple[np.ndarray, np.ndarray]:
    """(von Mises squared, step) of the largest value over the steps of block ``which[p]``
    at node ``rows[p]``, for every pair p (``CC`` the blocks' steps' products, block after
    block): one product per block (:func:`_pairs_by_block`)."""
    width = steps.shape[1]
    value, step = np.empty(rows.size), np.empty(rows.size, dtype=np.int64)
    for blk, p in _pairs_by_block(which, steps.shape[0]):
        vm2 = Q[rows[p]] @ CC[:, blk * width : (blk + 1) * width]  # (pairs, width)
        at = np.argmax(vm2, axis=1)
        value[p] = vm2[np.arange(p.size), at]
        step[p] = steps[blk, at]
    return value, step


def _pairs_by_block(which: np.ndarray, blocks: int):
    """(block, the indices of the pairs that read it) for every block some pair reads,
    ``which`` (pairs,) each pair's block of ``blocks``: the pairs ordered by block with a
    radix sort of their block numbers (16-bit where they fit)."""
    order = np.argsort(which.astype(np.int16 if blocks <= np.iinfo(np.int16).max else np.int64), kind="stable")
    ordered = which[order]
    starts = np.flatnonzero(np.r_[True, ordered[1:] != ordered[:-1]]) if which.size else np.empty(0, int)
    for a, b in zip(starts, np.r_[starts[1:], which.size]):
        yield int(ordered[a]), order[a:b]


def component_range(S: np.ndarray, C: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(max, min) over steps of each stress component: two (6, nodes) arrays, Pa.

    With two coefficients the maximum of a linear function over the cycle is the convex
    polygon's support function, found per direction by a binary search on the polygon's
    edge normals (O(nodes log vertices)); a long history by blocks of steps, only the blocks
    that can hold a row's extreme read whole (:func:`pruned_range`); otherwise every step
    is evaluated in chunks (:func:`dense_range`)."""
    if C.shape[1] == 2:
        polygon = hull_polygon(C)
        if polygon is not None:
            hi, lo = support_range(S.reshape(-1, 2), polygon)
            return hi.reshape(S.shape[:2]), lo.reshape(S.shape[:2])
    if C.shape[1] == 3 and np.all(C[:, 0] == 1.0):  # an affine plane (:func:`reduced`)
        polygon = hull_polygon(C[:, 1:])
        if polygon is not None:
            hi, lo = support_range(np.ascontiguousarray(S[:, :, 1:]).reshape(-1, 2), polygon)
            return S[:, :, 0] + hi.reshape(S.shape[:2]), S[:, :, 0] + lo.reshape(S.shape[:2])
    if C.shape[0] >= RANGE_PRUNE_STEPS and np.isfinite(C).all():  # else NaN out, for the caller to refuse
        return pruned_range(S, C)
    return dense_range(S, C)


def dense_range(S: np.ndarray, C: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`component_range` with every step evaluated at every node, in chunks."""
    nodes = S.shape[1]
    hi, lo = np.empty((6, nodes)), np.empty((6, nodes))
    for sl in _node_chunks(nodes, C.shape[0], RANGE_CHUNK_VALUES):
        s = stress_at(S[:, sl], C)  # (6, chunk, steps)
        hi[:, sl], lo[:, sl] = s.max(axis=2), s.min(axis=2)
    return hi, lo


@dataclass(frozen=True)
class _Blocks:
    """A long history ``C`` (steps, k) cut into blocks of consecutive steps, each bounded
    about its middle step: in coefficients scaled by their largest values ``w`` (forces,
    torques and accelerations differ by orders of magnitude), a step ``t`` of block ``b``
    is ``c_t = c_m + w (sum_d a_td u_d + e_t)``, ``u_d`` the block's :data:`BLOCK_DIRECTIONS`
    main directions (a short arc of the cycle lies nearly in the plane of its tangent and
    its curvature), ``|a_td| <= reach_along[d, b]`` and ``|e_t| <= reach_across[b]``, ``e_t``
    zero in the coefficients that never move (a constant load's: ``w_moving`` is ``w``
    without them, so a large constant stress widens no bound). ``steps`` (nb, block) the
    steps' indices (the last block padded by its last step), ``values`` (nb, block, k)
    their coefficients, ``middle`` (nb, k) the middle steps' and ``directions_w`` (D, nb,
    k) ``u_d w``. The decomposition holds for any ``u_d`` (``e_t`` is the remainder), so
    the bounds do not rest on the SVD's accuracy."""

    steps: np.ndarray
    values: np.ndarray
    middle: np.ndarray
    directions_w: np.ndarray
    reach_along: np.ndarray
    reach_across: np.ndarray
    w: np.ndarray
    w_moving: np.ndarray

    @classmethod
    def of(cls, C: np.ndarray, block: int) -> _Blocks:
        T, k = C.shape
        nb = -(-T // block)
        steps = np.minimum(np.arange(nb * block), T - 1).reshape(nb, block)
        values = C[steps]
        middle = values[:, block // 2]
        w = np.abs(C).max(axis=0)
        w[w == 0.0] = 1.0
        moving = C.max(axis=0) > C.min(axis=0)
        offsets = (values - middle[:, None, :]) / w  # exactly zero where a coefficient never moves
        directions = np.linalg.svd(offsets, full_matrices=False)[2][:, :BLOCK_DIRECTIONS, :] * moving  # (nb, D, k)
        along = np.einsum("tbk,tdk->tbd", offsets, directions)
        across = offsets - np.einsum("tbd,tdk->tbk", along, directions)  # zero where it never moves
        reach_across = np.sqrt(np.einsum("tbk,tbk->tb", across, across)).max(axis=1)
        reach_along = np.abs(along).max(axis=1).T  # (D, nb)
        directions_w = (directions * w).transpose(1, 0, 2)
        return cls(steps, values, middle, directions_w, reach_along, reach_across, w, w * moving)


def pruned_range(S: np.ndarray, C: np.ndarray, block: int = RANGE_BLOCK) -> tuple[np.ndarray, np.ndarray]:
    """:func:`component_range` of a long history ``C`` (steps, k) by blocks of ``block``
    consecutive steps (:class:`_Blocks`), exact (to rounding).

    Each row ``s`` (a node's component, (k,)) is read at each block's middle step ``m``:
    ``s . c_t <= s . c_m + sum_d |s . u_d w| max|a_td| + |s w_moving| max|e_t|``
    (Cauchy-Schwarz on the rest), so a block where that cannot reach the row's best middle
    value cannot hold its maximum (nor, mirrored, its minimum). Only the blocks that can
    are read at every step: on the default check's parts 5-6 blocks of 157 per row, its
    maximum and minimum together (29-44 with one direction and the constant load in the
    rest's norm). A few products of (rows x k) by (k x blocks) and one small product per
    block, instead of (rows x k) by (k x steps)."""
    k = C.shape[1]
    g = _Blocks.of(C, block)
    nb = g.steps.shape[0]
    R = S.reshape(-1, k)
    hi, lo = np.empty(R.shape[0]), np.empty(R.shape[0])
    pairs: dict[str, list] = {"hi_rows": [], "hi_blocks": [], "lo_rows": [], "lo_blocks": []}
    size = max(1, RANGE_CHUNK_VALUES // nb)
    for sl in (slice(a, min(a + size, R.shape[0])) for a in range(0, R.shape[0], size)):
        r = R[sl]
        values = r @ g.middle.T  # (rows, nb): exact values at real steps
        upper = _row_reach(r, g)
        lower = values - upper
        upper += values
        slack = PRUNE_SLACK * k * np.sqrt(np.einsum("rk,rk,k->r", r, r, g.w * g.w))  # the products' rounding
        hi[sl], lo[sl] = values.max(axis=1), values.min(axis=1)
        for side, can in (("hi", upper >= (hi[sl] - slack)[:, None]), ("lo", lower <= (lo[sl] + slack)[:, None])):
            i, b = np.nonzero(can)
            pairs[f"{side}_rows"].append(i + sl.start)
            pairs[f"{side}_blocks"].append(b)
    for side, best, reduce in (("hi", hi, np.maximum), ("lo", lo, np.minimum)):
        rows, which = np.concatenate(pairs[f"{side}_rows"]), np.concatenate(pairs[f"{side}_blocks"])
        _read_blocks(R, g.values, best, reduce, rows, which)
    return hi.reshape(S.shape[:2]), lo.reshape(S.shape[:2])


def _row_reach(r: np.ndarray, g: _Blocks) -> np.ndarray:
    """(rows, nb): how far each row ``r`` (rows, k) can move from its value at each block's
    middle step within the block, ``sum_d |r . u_d w| max|a_td| + |r w_moving| max|e_t|``
    (:class:`_Blocks`), in place on one product of the rows by every direction."""
    D, nb, k = g.directions_w.shape
    along = r @ g.directions_w.reshape(D * nb, k).T  # (rows, D nb)
    np.abs(along, out=along)
    along *= g.reach_along.reshape(-1)
    reach = along[:, :nb]
    for d in range(1, D):
        reach += along[:, d * nb : (d + 1) * nb]
    reach += np.multiply.outer(np.sqrt(np.einsum("rk,rk,k->r", r, r, g.w_moving * g.w_moving)), g.reach_across)
    return reach


def _read_blocks(R, blocks, best, reduce, rows, which) -> None:
    """``best[row] = reduce(best[row], each step's value)`` over the steps of block
    ``which[p]`` of row ``rows[p]``, for every pair p: one product per block
    (:func:`_pairs_by_block`)."""
    extreme = np.empty(rows.size)
    for blk, p in _pairs_by_block(which, blocks.shape[0]):
        values = R[rows[p]] @ blocks[blk].T  # (pairs, block)
        extreme[p] = values.max(axis=1) if reduce is np.maximum else values.min(axis=1)
    reduce.at(best, rows, extreme)


def envelope(
    fields: UnitFields,
    C: np.ndarray,
    every_node: bool = True,
    steps: np.ndarray | None = None,
    bounds: screening.SampledBounds | None = None,
) -> Envelope:
    """The von Mises and tip-deflection envelope of the history ``C`` (steps, k). With
    ``every_node`` False only the peaks are found (:func:`screened_max`: the same values,
    steps and nodes, without each node's maximum) and ``node_envelope`` is None.
    ``steps``: the history's :func:`candidate_steps`, when already known; ``bounds``: the
    nodes' :func:`railcheck.fea.screening.history_bounds` for ``C[steps]``, when already known."""
    steps = candidate_steps(C) if steps is None else steps
    if bounds is None and not every_node and screening.applies(steps.size, C.shape[1]):
        bounds = screening.history_bounds(fields.stress, C[steps])  # once for the verdict's and the support's peak
    mask = fields.verdict_mask if np.any(fields.verdict_mask) else np.ones_like(fields.verdict_mask)
    if every_node:
        best, where = von_mises_max(fields.stress, C[steps])
        node = int(np.argmax(np.where(mask, best, -np.inf)))
        peak, step, top, node_env = float(best[node]), int(steps[where[node]]), float(best.max()), best
    else:
        peak, node, k, top = screened_max(fields.stress, C[steps], mask, bounds)
        step = int(steps[k])
        node_env = None
    tip = np.linalg.norm(C @ fields.tip.T, axis=1)  # every step: (steps,)
    t = int(np.argmax(tip))
    return Envelope(peak, step, node, fields.nodes[node].copy(), node_env, float(tip[t]), t, top)


def node_envelope_of(fields: UnitFields, C: np.ndarray) -> np.ndarray:
    """(nodes,) Pa: each node's largest von Mises over the history ``C``."""
    fields, C = reduced(fields, C)
    return von_mises_max(fields.stress, C[candidate_steps(C)])[0]


#: nodes evaluated first for the screen's lower bound
SCREEN_TOP = 64


def screened_max(
    S: np.ndarray, C: np.ndarray, mask: np.ndarray, bounds: screening.SampledBounds | None = None
) -> tuple[float, int, int, float]:
    """(largest von Mises Pa over the nodes ``mask``, its node, its step, the largest von
    Mises Pa over every node) over the steps of ``C``, as :func:`von_mises_max` would give
    (the first node and step of the maximum), evaluating only the nodes that can hold
    either maximum: a node's von Mises is at most sqrt(largest eigenvalue of its quadratic
    form) x the history's largest norm; the exact maximum over the nodes of largest
    eigenvalue is a lower bound, and only nodes whose bound reaches it are evaluated. A
    history of more than two coefficients is screened in its principal subspace instead
    (:mod:`railcheck.fea.screening`; ``bounds``: its :func:`railcheck.fea.screening.history_bounds` over every node
    of ``S``, when already known). A node left out of a maximum's candidates is strictly
    below it, so evaluating the union of both candidate sets gives both exactly."""
    k = S.shape[2]
    everywhere = np.ones_like(mask)
    if screening.applies(C.shape[0], k):  # many coefficients: the history's own subspace screens the nodes
        b = screening.history_bounds(S, C) if bounds is None else bounds
        nodes = np.union1d(subspace_candidates(S, C, b, mask), subspace_candidates(S, C, b, everywhere))
        best, where = von_mises_max(S[:, nodes], C)
    elif k > 2:  # a few steps (a constant load: one): every node, directly (no k x k forms)
        nodes = np.arange(S.shape[1])
        vm = von_mises(stress_at(S, C))  # (nodes, steps)
        where = np.argmax(vm, axis=1)
        best = np.take_along_axis(vm, where[:, None], axis=1)[:, 0]
    else:  # one coefficient (a part loaded by one source, e.g. no inertia) as two, the second zero: exact
        if k == 1:
            S, C = np.concatenate([S, np.zeros_like(S)], axis=2), np.concatenate([C, np.zeros_like(C)], axis=1)
        nodes, best, where = _two_coefficient_candidates(S, C, mask)
    inside = mask[nodes]
    j = int(np.argmax(np.where(inside, best, -np.inf)))
    return float(best[j]), int(nodes[j]), int(where[j]), float(best.max())


def _two_coefficient_candidates(S: np.ndarray, C: np.ndarray, mask: np.ndarray):
    """(nodes ascending, their largest von Mises Pa, its step) for the nodes that can hold
    the largest von Mises over ``mask`` or over every node of the two-coefficient fields
    ``S`` (6, n, 2) and history ``C`` (steps, 2): each node's quadratic form's largest
    eigenvalue (closed form) times the history's largest squared norm bounds it."""
    q = np.einsum("cnk,cd,dnl->nkl", S, VM_QUADRATIC, S, optimize=True)
    a, b, d = q[:, 0, 0], q[:, 0, 1], q[:, 1, 1]
    lam = 0.5 * (a + d) + np.hypot(0.5 * (a - d), b)  # the 2 x 2 form's largest eigenvalue
    Q = q.reshape(-1, 4)
    CC = np.einsum("tk,tl->klt", C, C).reshape(4, -1)
    R2 = float(np.einsum("tk,tk->t", C, C).max())
    keep = np.zeros(S.shape[1], dtype=bool)
    for within in (np.flatnonzero(mask), np.arange(S.shape[1])):
        if within.size == 0:
            continue
        top = within[np.argsort(-lam[within])[:SCREEN_TOP]]
        lower = float((Q[top] @ CC).max())
        keep[within[lam[within] * R2 * (1.0 + 1e-9) + 1e-300 >= lower]] = True
    nodes = np.flatnonzero(keep)
    best, where = np.empty(nodes.size), np.empty(nodes.size, dtype=np.int64)
    for sl in _node_chunks(nodes.size, C.shape[0]):
        vm2 = Q[nodes[sl]] @ CC
        where[sl] = np.argmax(vm2, axis=1)
        best[sl] = np.take_along_axis(vm2, where[sl, None], axis=1)[:, 0]
    return nodes, np.sqrt(np.maximum(best, 0.0)), where


def subspace_candidates(S: np.ndarray, C: np.ndarray, b: screening.SampledBounds, mask: np.ndarray) -> np.ndarray:
    """Indices (ascending) of the nodes in ``mask`` of ``S`` (6, n, k) that can hold their
    largest von Mises over the history ``C`` (steps, k): the bounds ``b`` from its principal
    subspace (:mod:`railcheck.fea.screening`), a lower bound from the nodes of largest sampled value."""
    first = screening.first_nodes(np.where(mask, b.von_mises, -np.inf))
    first = first[mask[first]]
    lower = float(von_mises(stress_at(S[:, first], C)).max())
    candidates = screening.peak_candidates(b, lower)  # ascending
    return candidates[mask[candidates]]


def history_at_node(fields: UnitFields, C: np.ndarray, node: int) -> np.ndarray:
    """(steps,) Pa: one node's von Mises over the whole history."""
    return von_mises(stress_at(fields.stress[:, node : node + 1], C))[0]
