"""Box bounds of many coefficient histories at every node: the coefficients' ranges in
one basis bound each node's von Mises and component ranges over all steps by a few float32
matrix products (:class:`CoefficientBox`). Pa throughout."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..invariants import von_mises_squared
from .subspace import VM_FACTOR, Subspace, history_blocks, midrange_bound, nearest_to_box_centre, steps_of

#: steps of each history (evenly spaced, besides the one nearest its box's centre) whose
#: values tighten a group box's midrange bounds (:meth:`CoefficientBox.ranges_and_taken`)
BOX_TAKEN_STEPS = 4


@dataclass(frozen=True)
class SampledBounds:
    """Per node, from the sampled steps in the subspace: ``von_mises`` (n,) Pa the largest
    sampled von Mises and ``von_mises_upper`` (n,) a bound over every step; ``high``,
    ``low`` (6, n) Pa each component's sampled maximum and minimum and ``slack`` (6, n)
    Pa how far outside them its value at any step can lie; ``mid_upper`` (6, n) Pa, or
    None, a bound of each component's midrange magnitude tighter than ``|high + low| / 2
    + slack`` (:func:`box_bounds`; inf where there is none); ``share`` (6, n) Pa, or None
    (then ``slack``), how far inside them its largest and smallest value can lie: a read
    step's value is its subspace value within the residual's share (:func:`sampled_pairs`),
    so the component's maximum is at least ``high - share``, its minimum at most ``low +
    share``."""

    von_mises: np.ndarray
    von_mises_upper: np.ndarray
    high: np.ndarray
    low: np.ndarray
    slack: np.ndarray
    mid_upper: np.ndarray | None = None
    share: np.ndarray | None = None

    @classmethod
    def box(cls, vm: np.ndarray, mid: np.ndarray, reach: np.ndarray, mid_upper: np.ndarray | None = None):
        """Bounds that read no step: every step's components within ``mid +- reach``,
        von Mises at most ``vm``; ``high`` and ``low`` are both ``mid`` (the same array:
        :func:`fatigue_bounds` knows a box by it)."""
        return cls(vm, vm, mid, mid, reach, mid_upper)


def component_norms(Sw: np.ndarray) -> np.ndarray:
    """(6, n): each stress component's norm over its k coefficients (Pa per unit scaled coefficient)."""
    return np.sqrt(np.einsum("cnk,cnk->cn", Sw, Sw))


def von_mises_norm_bound(Sw: np.ndarray) -> np.ndarray:
    """(n,): an upper bound of each node's largest von Mises per unit scaled coefficient,
    the Frobenius norm of its von Mises factor (sqrt of the trace of its quadratic form:
    the sum of each coefficient's von Mises squared)."""
    return np.sqrt(von_mises_squared(Sw).sum(axis=-1))


def project(S: np.ndarray, scale: np.ndarray, sub: Subspace) -> np.ndarray:
    """(6, n, r) Pa per unit of the subspace's coordinates: the stresses ``S`` (6, n, k) Pa
    per unit coefficient along the principal directions of a history scaled by ``scale`` (k,)."""
    return S @ (sub.P / scale[:, None])


def box_bounds(SP: np.ndarray, norms: np.ndarray, vm_norm: np.ndarray, sub: Subspace) -> SampledBounds:
    """Bounds over every step from the box of the subspace coordinates' ranges (module
    doc), as :class:`SampledBounds`: ``high`` = ``low`` the components at the box's centre,
    ``slack`` how far from it they reach, and ``von_mises`` = ``von_mises_upper`` a bound of
    von Mises (the box reads no step). ``SP`` (6, n, r) :func:`project`; ``norms`` (6, n)
    and ``vm_norm`` (n,) as for :func:`sampled_bounds`.

    ``mid_upper``: each component ``x`` has its maximum at most ``U`` = centre + reach and
    its minimum at least ``D`` = centre - reach, and takes the values ``v_p`` (within the
    residual's share ``g``) at the steps ``sub.touched``, so its maximum is at least
    ``max v_p - g`` and its minimum at most ``min v_p + g``: its midrange lies within
    ``[(D + max v_p - g) / 2, (U + min v_p + g) / 2]``. About half the box's
    ``|centre| + reach`` on the rig's histories, whose midranges are small beside their
    ranges."""
    lo, hi = sub.a.min(axis=0), sub.a.max(axis=0)
    centre, half = 0.5 * (hi + lo), 0.5 * (hi - lo)
    mid = SP @ centre  # (6, n)
    share = norms * sub.eps
    reach = np.abs(SP) @ half + share
    L = np.tensordot(VM_FACTOR, SP, axes=([1], [0]))  # (6, n, r): von Mises = |L a|
    rows = np.abs(L @ centre) + np.abs(L) @ half  # each row's largest |L_j . a| over the box
    vm = np.sqrt(np.einsum("jn,jn->n", rows, rows)) + vm_norm * sub.eps
    # (6, p, n): the components at the touched steps (steps before nodes: the extremes
    # over the steps are elementwise over contiguous rows)
    taken = np.matmul(sub.a[sub.touched], SP.transpose(0, 2, 1))
    mid_upper = midrange_bound(mid, reach, taken.min(axis=1), taken.max(axis=1), share)
    return SampledBounds.box(vm, mid, reach, mid_upper)


#: single-precision unit roundoff: :class:`CoefficientBox` reads its matrices in float32
#: (half the memory traffic of every node x every history) and widens its bounds to cover it
FLOAT32_EPS = float(np.finfo(np.float32).eps)


#: relative widening of a float32 von Mises interval bound: covers its own arithmetic
#: (:func:`von_mises_interval_bound`, a few roundoffs of 6e-8)
BOX_WIDENING = 1e-5


class CoefficientBox:
    """Box bounds (as :func:`box_bounds`) of many histories of one part at once, in one
    orthonormal basis of the scaled coefficients shared by the group: each history's
    coordinates ``d_t`` lie in the box of their ranges (centre ``m``, half-widths ``h``),
    so each stress component of a node lies within ``R_j . m +- |R_j| . h`` (``R_j`` the
    component's row per unit basis coordinate), and von Mises within the interval bound
    of those component intervals (:func:`von_mises_interval_bound`). Every history's
    bounds over every node are two matrix products; the basis is of full rank, so there
    is no residual. ``basis`` (k, k) orthonormal in the scaled coefficients ``c * scale``,
    or None for the coefficients themselves (:func:`box_basis` chooses): it only changes
    how many nodes a box keeps, never a result, since a node it keeps is then bounded in
    the history's own principal subspace (:func:`box_bounds`) and read. ``S`` (6, n, k)
    Pa per unit coefficient, ``scale`` (k,) the coefficients' scale.

    Histories that lie in an r-dimensional subspace of the scaled coefficients
    (:func:`history_span`) are boxed in r coordinates: ``basis`` (k, r) spans it and
    ``dual`` (k, r) gives the coordinates, ``d = (c * scale) dual`` with ``c * scale =
    basis d`` for every history in it (``dual^T basis = I``); the rows and the products
    are then r columns wide, and the box bounds the histories as the span re-expresses
    them (each within :data:`SPAN_RESIDUAL` of its size, the rounding its span left;
    :func:`railcheck.fea.screening.groups.in_span` reads them in the same coefficients). None:
    ``dual`` is ``basis``.

    The rows are held in float32 (the products stream every node once per history; half
    the bytes). The bounds stay bounds: a float32 dot product of length k + 2 roundings
    errs by at most ``(k + 4) u |m| . |R_j|`` (u the float32 roundoff; Higham, *Accuracy
    and Stability of Numerical Algorithms*, 3.1), so ``2 (k + 4) u |m|`` is added to the
    half-widths of the reach product (itself of non-negative terms, widened by the same
    share): twice the products' worst error, the other half (at least 10 roundoffs of the
    value) covers the few float32 roundings of the fatigue bounds computed from them
    (:func:`fatigue_bounds`). Results are float32 (Pa)."""

    def __init__(self, S: np.ndarray, scale: np.ndarray, basis: np.ndarray | None = None, dual: np.ndarray | None = None):
        k = S.shape[2]
        S2 = S.reshape(-1, k)  # (6 n, k): rows by component, then node
        rows = S2 if basis is None else S2 @ (basis / scale[:, None])  # per unit of each basis coordinate
        self._hold(rows.astype(np.float32), S.shape[1], scale, basis, dual)

    def _hold(
        self, rows: np.ndarray, nodes: int, scale: np.ndarray, basis: np.ndarray | None, dual: np.ndarray | None = None
    ) -> None:
        """Keep the float32 ``rows`` (6 nodes, r) per unit basis coordinate and what reads them."""
        self.nodes, self.scale, self.B = nodes, scale, basis
        self.W = basis if dual is None else dual  # (k, r): the coordinates of the scaled coefficients
        self.rows = rows
        self.abs_rows = np.abs(rows)
        self.dot_error = 2.0 * (rows.shape[1] + 4) * FLOAT32_EPS  # relative, of |m| . |R_j| (class doc)
        self._by_node: tuple[np.ndarray, np.ndarray] | None = None  # (n, 6, k) rows and (n, 6) norms, when read

    def _node_major(self) -> tuple[np.ndarray, np.ndarray]:
        """((n, 6, k) float32, (n, 6)): the rows grouped by node (a node's six rows
        contiguous: gathering a few thousand nodes is one block each) and each row's
        Euclidean norm, made on first use."""
        if self._by_node is None:
            k = self.rows.shape[1]
            by_node = np.ascontiguousarray(self.rows.reshape(6, self.nodes, k).transpose(1, 0, 2))
            self._by_node = by_node, np.sqrt(np.einsum("njk,njk->nj", by_node, by_node, dtype=np.float64))
        return self._by_node

    def restricted(self, nodes: np.ndarray) -> CoefficientBox:
        """The same box at ``nodes`` (indices into this box's nodes) only."""
        box = object.__new__(CoefficientBox)
        k = self.rows.shape[1]
        box._hold(
            np.ascontiguousarray(self.rows.reshape(6, self.nodes, k)[:, nodes].reshape(-1, k)),
            nodes.size,
            self.scale,
            self.B,
            self.W,
        )
        return box

    def coordinates(self, C: np.ndarray) -> np.ndarray:
        """(s, T, k): the basis coordinates of every step of each history of ``C`` (s, T,
        k) (unscaled coefficients)."""
        return C if self.W is None else (C * self.scale) @ self.W

    def ranges(self, C: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(lo, hi) (s, k): the ranges of the basis coordinates of each history of ``C``
        (s, T, k) (unscaled coefficients), the box :meth:`box_of` bounds over."""
        d = self.coordinates(C)
        return d.min(axis=1), d.max(axis=1)

    def ranges_and_taken(
        self, C: np.ndarray, coordinates: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(lo, hi, taken): :meth:`ranges`, and ``taken`` (s, p, k) the coordinates of a
        few steps of each history (:data:`BOX_TAKEN_STEPS` evenly spaced and the one
        nearest its box's centre), values the history takes (:meth:`at_nodes`).
        ``coordinates``: :meth:`coordinates` of ``C`` when already computed."""
        d = self.coordinates(C) if coordinates is None else coordinates
        lo, hi = d.min(axis=1), d.max(axis=1)
        nearest = nearest_to_box_centre(d)  # (s,)
        spaced = np.linspace(0, d.shape[1], BOX_TAKEN_STEPS, endpoint=False).astype(int)
        steps = np.concatenate([np.broadcast_to(spaced, (d.shape[0], spaced.size)), nearest[:, None]], axis=1)
        return lo, hi, steps_of(d, steps)

    def box_arrays(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(von Mises (s, n), mid (s, 6, n), reach (s, 6, n)) float32 Pa: the bounds over
        each box of basis coordinates ``lo`` to ``hi`` (s, k) (:meth:`ranges`, or any box
        holding a history's steps): the components at the box's centre, their reach
        (:meth:`products`), and the bound of von Mises."""
        mid, reach = self.products(lo, hi)
        return von_mises_interval_bound(mid, reach, axis=1), mid, reach

    def products(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(mid (s, 6, n), reach (s, 6, n)) float32 Pa: each component's value at the
        centre of each box of basis coordinates ``lo`` to ``hi`` (s, k) and how far it
        can move within the box (two products, one pass over the rows for all boxes)."""
        centre, half = 0.5 * (hi + lo), 0.5 * (hi - lo)  # (s, k)
        shape = (lo.shape[0], 6, self.nodes)
        mid = (centre.astype(np.float32) @ self.rows.T).reshape(shape)
        widened = (half + self.dot_error * np.abs(centre)) * (1.0 + self.dot_error)
        reach = (widened.astype(np.float32) @ self.abs_rows.T).reshape(shape)
        # beyond float32's range (3.4e38 Pa: absurd loads) a bound is infinite, never NaN,
        # so such a node is kept and evaluated exactly in float64
        lost = ~(np.isfinite(mid) & np.isfinite(reach))
        if lost.any():
            mid[lost], reach[lost] = 0.0, np.inf
        return mid, reach

    def box_of(self, lo: np.ndarray, hi: np.ndarray) -> list[SampledBounds]:
        """One :class:`SampledBounds` per box of :meth:`box_arrays`: ``high`` = ``low``
        the components at the box's centre, ``slack`` their reach, ``von_mises`` =
        ``von_mises_upper`` the bound of von Mises (float32)."""
        vm, mid, reach = self.box_arrays(lo, hi)
        return [SampledBounds.box(vm[i], mid[i], reach[i]) for i in range(lo.shape[0])]

    def at_nodes(self, b: SampledBounds, nodes: np.ndarray, taken: np.ndarray) -> SampledBounds:
        """The bounds ``b`` of one history (:meth:`box_of`) at ``nodes`` only, with
        midrange bounds from the coordinates of steps the history takes, ``taken`` (p, k)
        (:meth:`ranges_and_taken`, :meth:`midrange_at`)."""
        mid, reach = b.high[:, nodes], b.slack[:, nodes]
        mid_upper = self.midrange_at(mid.T, reach.T, nodes, np.zeros(nodes.size, dtype=int), taken[None]).T
        return SampledBounds.box(b.von_mises[nodes], mid, reach, mid_upper)

    def midrange_at(
        self, mid: np.ndarray, reach: np.ndarray, nodes: np.ndarray, h: np.ndarray, taken: np.ndarray
    ) -> np.ndarray:
        """(q, 6) float32 Pa: bounds of the midrange of each component at ``nodes`` (q,)
        over the history ``h`` (q,) (ascending) of each entry, whose box gives ``mid`` and
        ``reach`` (q, 6) there and which takes the basis coordinates ``taken[h]`` (s, p,
        k) (:meth:`ranges_and_taken`): its maximum is at least the largest taken value,
        its minimum at most the smallest (:func:`midrange_bound`). Their float32 error
        (the dot products' bound of the class doc, ``|t| . |R_j|``, bounded by ``|m|_2
        |R_j|_2`` with ``m`` the largest ``|taken|`` of each coordinate) and four
        roundoffs of the terms summed widen it; inf where a term is not finite. Read only
        where the box alone leaves candidates, since they cost p products per node."""
        by_node, norms = self._node_major()
        k = by_node.shape[2]
        low, high = np.empty(mid.shape, dtype=np.float32), np.empty(mid.shape, dtype=np.float32)
        t32 = taken.astype(np.float32)
        for i, start, stop in history_blocks(h):
            values = t32[i] @ by_node[nodes[start:stop]].reshape(-1, k).T  # (p, 6 m): one product per history
            low[start:stop], high[start:stop] = values.min(axis=0).reshape(-1, 6), values.max(axis=0).reshape(-1, 6)
        scale = self.dot_error * np.linalg.norm(np.abs(taken).max(axis=1), axis=1)  # (s,)
        error = (scale[h][:, None] * norms[nodes]).astype(np.float32)
        error += np.float32(4.0 * FLOAT32_EPS) * (np.abs(mid) + reach + np.maximum(np.abs(low), np.abs(high)))
        out = midrange_bound(mid, reach, low, high, error)
        out[~np.isfinite(out)] = np.inf
        return out

    def bounds(self, C: np.ndarray) -> list[SampledBounds]:
        """:meth:`box_of` the :meth:`ranges` of each history of ``C`` (s, T, k)."""
        return self.box_of(*self.ranges(C))


def von_mises_interval_bound(mid: np.ndarray, reach: np.ndarray, axis: int = 0) -> np.ndarray:
    """Pa: the largest von Mises of any stress whose components (along ``axis``, 6:
    xx, yy, zz, xy, yz, xz) lie within ``mid +- reach`` (Pa): each normal difference
    ``s_i - s_j`` is at most ``|m_i - m_j| + r_i + r_j`` and each shear ``|m| + r``; exact
    for a single component, and a bound of its float32 rounding (:data:`BOX_WIDENING`)."""
    m = np.moveaxis(mid, axis, 0)
    r = np.moveaxis(reach, axis, 0)
    normal = sum((np.abs(m[i] - m[j]) + r[i] + r[j]) ** 2 for i, j in ((0, 1), (1, 2), (2, 0)))
    shear = sum((np.abs(m[i]) + r[i]) ** 2 for i in (3, 4, 5))
    return np.sqrt(0.5 * normal + 3.0 * shear) * (1.0 + mid.dtype.type(BOX_WIDENING))
