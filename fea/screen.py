"""Exact screens of a many-coefficient load history over a part's nodes: which nodes can
hold the cycle's von Mises peak or its lowest fatigue factor, so that only those are
evaluated at every step.

A history ``c`` (T steps, k coefficients, each scaled by its largest stress per unit so
forces, torques and accelerations are comparable) is split into its principal subspace
and a residual: ``c_t = P a_t + e_t``, of the smallest rank from :data:`REDUCED_RANK` to
:data:`MAX_RANK` whose residual is at most :data:`RESIDUAL_SHARE` of the history's
largest ``|c_t|``. With ``Sw`` a node's stress per unit scaled coefficient (6 x k) and
``L`` the von Mises factor (von Mises = ``|L Sw c|``), two bounds over every step:

* **the box** (:func:`box_bounds`, a few operations per node): every ``a_t`` lies in the
  box of the coordinates' ranges, over which a linear function's extremes are its value at
  the box's centre plus or minus ``|row| . half-widths``; each stress component lies
  within that of ``Sw_j P`` plus ``|Sw_j| |e_t|``, and von Mises within the norm of the
  six rows of ``L Sw P`` so bounded plus ``||L Sw|| |e_t|``. A component's midrange is
  bounded more tightly by the values it takes at a few steps (:func:`box_bounds`).
* **the samples** (:func:`sampled_bounds`): a few tens of steps of the history's path in
  the subspace, chosen so that every step lies within ``delta`` of the chord between
  the read steps before and after it (:func:`refined_samples`: the path is split at its
  farthest step from a chord until every step is within :data:`CHORD_SHARE` of the
  history's reach, or its residual, of its chord), are read at the node in the r
  coordinates. A step between two read ones is a point ``p`` of their chord plus at
  most ``delta``; a linear function at ``p`` lies between its values at the chord's
  ends, and von Mises (a norm) at ``p`` is at most the larger of them. So von Mises at
  step t <= sampled von Mises + ``||L Sw P||_F delta`` + ``||L Sw|| |e_t|``, and each
  component's maximum and minimum lie within ``g = |Sw_j P| delta + |Sw_j| |e_t|``
  outside the sampled ones (bounds of its half-range and of its midrange's magnitude,
  hence of the alternating and midrange von Mises). On the rig's histories 20-40 read
  steps so placed bound as tightly as 90 evenly spaced ones bounded by the distance to
  the nearer read step.

The box discards most nodes for the price of reading their stresses once; the samples,
read only at the nodes the box keeps, leave a few to a few hundred of 10,000-30,000
nodes. Everything in SI (Pa); the callers evaluate the remaining nodes exactly
(:mod:`railcheck.sweep.fe`, :func:`fea.superpose.screened_max`,
:func:`railcheck.check.cycle.fatigue_of`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .invariants import VM_QUADRATIC, von_mises, von_mises_squared

#: the smallest rank of the principal subspace a history is screened in
REDUCED_RANK = 4
#: the largest rank (the sampled bounds cost r^2 per node and read step)
MAX_RANK = 8
#: the rank grows until the residual ``max |e_t|`` is at most this share of ``max |c_t|``
RESIDUAL_SHARE = 0.01
#: steps read first, evenly spaced along the history's path in the subspace; each round of
#: :func:`refined_samples` then adds the farthest step of every chord farther than its tolerance
FIRST_SAMPLES = 16
#: every step lies within this share of the history's largest ``|a_t|`` (or within its
#: residual, if larger) of the chord between the read steps around it
CHORD_SHARE = 0.01
#: steps of a history read at every node the box bounds (:func:`touched_steps`)
TOUCHED_STEPS = 8
#: at most this many steps are read (a history that is noise everywhere stops there; its
#: ``delta`` is then measured, still a bound)
MAX_SAMPLES = 256
#: a history of at most this many steps is read whole (no screen)
MIN_STEPS = 32
#: nodes of best sampled value evaluated exactly first, for a threshold near the optimum
FIRST_NODES = 16
#: relative margin on the bounds (rounding)
SLACK = 1e-9
#: floats per temporary (nodes x sampled steps x 6): 4 MB, read twice (max and min) from
#: cache; 70 ms against 85 ms at 8M for 29,000 nodes, 20 coefficients, 90 read steps
CHUNK_VALUES = 1 << 19

_w, _V = np.linalg.eigh(VM_QUADRATIC)
#: the symmetric square root of VM_QUADRATIC: von Mises = |VM_FACTOR s|
VM_FACTOR = (_V * np.sqrt(np.maximum(_w, 0.0))) @ _V.T


def scaled(C: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """``C * scale``, or ``C`` itself where every scale is 1 (a screen in a span's
    coefficients: no copy of the histories)."""
    return C if np.all(scale == 1.0) else C * scale


def applies(steps: int, k: int) -> bool:
    """Whether a history of ``steps`` x ``k`` coefficients is screened in its subspace
    (two coefficients have exact planar paths; a few steps are cheaper read whole)."""
    return k > 2 and steps > MIN_STEPS


def column_scale(S: np.ndarray) -> np.ndarray:
    """(k,) each coefficient's largest stress per unit (Pa per unit) over the nodes of
    ``S`` (6, n, k): the coefficients' scale."""
    return np.sqrt(np.einsum("cnk,cnk->nk", S, S)).max(axis=0) + 1e-300


def nearest_to_box_centre(d: np.ndarray) -> np.ndarray:
    """(...,) the index of the step of each path ``d`` (..., T, k) nearest the centre of
    the box of its coordinates' ranges, each coordinate in units of its half-width."""
    lo, hi = d.min(axis=-2, keepdims=True), d.max(axis=-2, keepdims=True)
    e = d - 0.5 * (lo + hi)
    np.multiply(e, e, out=e)
    # each squared offset over its squared half-width (at most 1: no overflow, and 0 on a
    # constant coordinate), summed by one product: 2.2x faster than scaling every offset
    weight = 1.0 / np.maximum(np.square(0.5 * (hi - lo)), np.finfo(float).tiny)  # (..., 1, k)
    return np.argmin(np.matmul(e, np.swapaxes(weight, -1, -2))[..., 0], axis=-1)


def midrange_bound(mid: np.ndarray, reach: np.ndarray, low: np.ndarray, high: np.ndarray, margin) -> np.ndarray:
    """A bound of each component's midrange magnitude over a history: its maximum is at
    most ``mid + reach`` and its minimum at least ``mid - reach`` (a box), and it takes
    values from ``low`` to ``high`` (within ``margin``) at a few steps, so its maximum is
    at least ``high - margin`` and its minimum at most ``low + margin``: the midrange lies
    within ``[(mid - reach + high - margin) / 2, (mid + reach + low + margin) / 2]``, and
    within the box's ``|mid| + reach``. Arrays of one shape (Pa)."""
    above = mid + reach + low + margin  # twice the midrange's upper bound
    below = mid - reach + high - margin  # twice its lower bound
    return np.minimum(0.5 * np.maximum(np.abs(above), np.abs(below)), np.abs(mid) + reach)


@dataclass(frozen=True)
class Subspace:
    """One scaled history ``c`` (T, k) as ``c_t = P a_t + e_t``: ``P`` (k, r) its principal
    directions, ``a`` (T, r) the steps' coordinates, ``eps`` the largest ``|e_t|``;
    ``sampled`` the indices of the steps read (:func:`refined_samples`) and ``delta`` the
    largest distance of any step from the chord between the read steps around it
    (:func:`chord_gaps`); ``touched`` the few steps (:func:`touched_steps`) whose values
    tighten the box's midrange bounds (:func:`box_bounds`)."""

    P: np.ndarray
    a: np.ndarray
    eps: float
    sampled: np.ndarray
    delta: float
    touched: np.ndarray


@dataclass(frozen=True)
class Subspaces:
    """Many scaled histories ``C`` (S, T, k) in their principal subspaces at once
    (:func:`principal_subspaces`), padded to one rank ``R`` = min(:data:`MAX_RANK`, k):
    ``P`` (S, k, R) the directions (the columns beyond each history's ``rank`` (S,) zero),
    ``a`` (S, T, R) the coordinates, ``eps`` (S,) the largest residual, ``sampled`` (S, M)
    and ``touched`` (S, p) step indices (ascending, each row padded by repeating its last
    index), ``delta`` (S,) as :class:`Subspace`."""

    P: np.ndarray
    a: np.ndarray
    eps: np.ndarray
    sampled: np.ndarray
    delta: np.ndarray
    touched: np.ndarray
    rank: np.ndarray

    def one(self, i: int) -> Subspace:
        """History ``i`` as a :class:`Subspace` (its own rank, no padding)."""
        r = int(self.rank[i])
        return Subspace(
            self.P[i, :, :r], self.a[i, :, :r], float(self.eps[i]), np.unique(self.sampled[i]),
            float(self.delta[i]), np.unique(self.touched[i]),
        )  # fmt: skip


def subspace_ranks(coords: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """(S,) for each history the smallest rank from REDUCED_RANK to MAX_RANK (at most k)
    whose residual is at most RESIDUAL_SHARE of its largest step norm ``reach`` (S,);
    ``coords`` (S, T, k) its steps in its singular basis (columns by decreasing singular
    value)."""
    k = coords.shape[2]
    top = min(MAX_RANK, k)
    low = min(REDUCED_RANK, top)
    # tail[:, r - low]: the largest residual beyond rank r, low <= r < top (sums of squares
    # from the back: no cancellation; the square root after the maximum, as it is monotone)
    tail = np.sqrt(np.cumsum(coords[..., ::-1] ** 2, axis=2)[..., k - top : k - low][..., ::-1].max(axis=1))
    small = tail <= RESIDUAL_SHARE * reach[:, None]
    if not small.shape[1]:
        return np.full(coords.shape[0], top)
    return np.where(small.any(axis=1), low + np.argmax(small, axis=1), top)


def path_sample_mask(a: np.ndarray, samples: int) -> np.ndarray:
    """(S, T) bool: about ``samples`` steps of each path ``a`` (S, T, r), evenly spaced
    along its length, the first and last included."""
    S, T = a.shape[:2]
    steps = np.linalg.norm(np.diff(a, axis=1), axis=2)
    length = np.concatenate([np.zeros((S, 1)), np.cumsum(steps, axis=1)], axis=1)
    marks = np.linspace(0.0, 1.0, min(samples, T))[None, :] * length[:, -1:]  # (S, m)
    at = (length[:, None, :] < marks[:, :, None]).sum(axis=2).clip(0, T - 1)  # searchsorted, row by row
    mask = np.zeros((S, T), dtype=bool)
    np.put_along_axis(mask, at, True, axis=1)
    mask[:, [0, -1]] = True
    return mask


def steps_of(a: np.ndarray, index: np.ndarray) -> np.ndarray:
    """(S, M, r): the steps ``index`` (S, M) of each path ``a`` (S, T, r), as
    ``np.take_along_axis(a, index[:, :, None], axis=1)``: one gather of whole rows from
    the flattened paths, 10x faster than take_along_axis's broadcast fancy index."""
    S, T = a.shape[:2]
    flat = np.asarray(index) + T * np.arange(S)[:, None]
    return np.take(a.reshape(S * T, *a.shape[2:]), flat, axis=0)


def chord_gaps_of(a: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """(S, T): each step's distance from the chord between the read steps (``mask`` (S,
    T), first and last step read) before and after it, on each path ``a`` (S, T, r); 0
    at a read step."""
    S, T = mask.shape
    t = np.arange(T)
    before = np.maximum.accumulate(np.where(mask, t, 0), axis=1)  # the last read step <= t
    at_or_after = np.minimum.accumulate(np.where(mask, t, T - 1)[:, ::-1], axis=1)[:, ::-1]
    after = np.concatenate([at_or_after[:, 1:], np.full((S, 1), T - 1)], axis=1)  # the first read step > t
    start = steps_of(a, before)
    d = steps_of(a, after) - start
    rel = a - start
    along = np.einsum("str,str->st", rel, d) / np.maximum(np.einsum("str,str->st", d, d), np.finfo(float).tiny)
    offset = rel - np.clip(along, 0.0, 1.0)[:, :, None] * d
    return np.sqrt(np.einsum("str,str->st", offset, offset))


def refined_masks(a: np.ndarray, tolerance: np.ndarray, mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((S, T) bool, (S,)): read steps of each path ``a`` (S, T, r) such that every step
    lies within its ``tolerance`` (S,) of the chord between the read steps around it,
    and the largest such distance (:func:`chord_gaps_of`). From the read steps ``mask``
    (:func:`path_sample_mask`), round by round the farthest step of every chord that has
    one beyond the tolerance is added (Douglas-Peucker, all chords of all paths at once),
    up to :data:`MAX_SAMPLES` per path."""
    S, T = mask.shape
    cap = min(MAX_SAMPLES, T)
    mask = mask.copy()
    while True:
        gap = chord_gaps_of(a, mask)
        counts = mask.sum(axis=1)
        starts = np.flatnonzero(mask)  # each chord's steps are contiguous from its first read step
        farthest = np.maximum.reduceat(gap.ravel(), starts)
        chord = np.cumsum(mask.ravel()) - 1  # (S T,) each step's chord
        over = (farthest > tolerance[starts // T]) & (counts[starts // T] < cap)
        at = np.flatnonzero((gap.ravel() == farthest[chord]) & over[chord])
        at = at[np.unique(chord[at], return_index=True)[1]]  # one per chord, ascending
        at = at[~mask.ravel()[at]]  # only steps not yet read: every round adds one, so the loop ends
        if not at.size:
            return mask, gap.max(axis=1)
        path = at // T
        first = np.searchsorted(path, path)  # each path's first new step's position in ``at``
        keep = np.arange(at.size) - first < (cap - counts)[path]
        mask.ravel()[at[keep]] = True


def history_blocks(h: np.ndarray, limit: int | None = None) -> list[tuple[int, int, int]]:
    """(history, start, stop) of each run of one value in ``h`` (ascending history
    indices of (history, node) pairs), runs longer than ``limit`` split: each history's
    pairs, for one product each."""
    if not h.size:
        return []
    cuts = np.flatnonzero(np.diff(h)) + 1
    starts, stops = np.concatenate([[0], cuts]), np.concatenate([cuts, [h.size]])
    step = limit or h.size
    return [(int(h[a]), int(c), int(min(c + step, b))) for a, b in zip(starts, stops) for c in range(a, b, step)]


def padded_indices(mask: np.ndarray) -> np.ndarray:
    """(S, M): the indices of each row's True entries (ascending; at least one per row),
    each row padded by repeating its last one to the longest row's count M."""
    counts = mask.sum(axis=1)
    order = np.argsort(~mask, axis=1, kind="stable")[:, : counts.max()]
    return np.take_along_axis(order, np.minimum(np.arange(order.shape[1])[None, :], counts[:, None] - 1), axis=1)


def touched_of(a: np.ndarray, first: np.ndarray) -> np.ndarray:
    """(S, p) indices (ascending, padded): about :data:`TOUCHED_STEPS` of each path's
    evenly spaced steps ``first`` (S, T) bool (:func:`path_sample_mask`) and the step
    nearest the centre of its box (:func:`nearest_to_box_centre`): values each history
    takes, which bound each component's midrange from both sides (:func:`box_bounds`)."""
    order = np.cumsum(first, axis=1) - 1  # each step's position among the read ones
    stride = np.maximum(1, first.sum(axis=1) // TOUCHED_STEPS)[:, None]
    touched = first & (order % stride == 0)
    touched[np.arange(a.shape[0]), nearest_to_box_centre(a)] = True
    return padded_indices(touched)


def principal_subspaces(C: np.ndarray) -> Subspaces:
    """The scaled histories ``C`` (S, T, k) in their principal subspaces
    (:func:`subspace_ranks`), read at :func:`refined_masks` (every step within
    :data:`CHORD_SHARE` of the history's largest ``|c_t|``, or within its residual, of
    its chord). The directions are the eigenvectors of ``c^T c`` (the right singular
    vectors; any orthonormal ``P`` gives valid bounds, since ``eps`` is the measured
    residual)."""
    k = C.shape[2]
    V = np.linalg.eigh(np.matmul(C.transpose(0, 2, 1), C))[1][:, :, ::-1]  # (S, k, k) by decreasing eigenvalue
    reach = np.linalg.norm(C, axis=2).max(axis=1)
    rank = subspace_ranks(np.matmul(C, V), reach)
    R = min(MAX_RANK, k)
    P = V[:, :, :R] * (np.arange(R)[None, :] < rank[:, None])[:, None, :]
    a = np.matmul(C, P)
    eps = np.linalg.norm(C - np.matmul(a, P.transpose(0, 2, 1)), axis=2).max(axis=1)
    first = path_sample_mask(a, FIRST_SAMPLES)
    sampled, delta = refined_masks(a, np.maximum(eps, CHORD_SHARE * reach), first)
    return Subspaces(P, a, eps, padded_indices(sampled), delta, touched_of(a, first), rank)


def principal_subspace(c: np.ndarray) -> Subspace:
    """:func:`principal_subspaces` of one scaled history ``c`` (T, k)."""
    return principal_subspaces(c[None]).one(0)


def path_samples(a: np.ndarray, samples: int) -> np.ndarray:
    """:func:`path_sample_mask` of one path ``a`` (T, r), as indices."""
    return np.flatnonzero(path_sample_mask(a[None], samples)[0])


def chord_gaps(a: np.ndarray, sampled: np.ndarray) -> np.ndarray:
    """:func:`chord_gaps_of` one path ``a`` (T, r) read at the steps ``sampled``."""
    mask = np.zeros((1, a.shape[0]), dtype=bool)
    mask[0, sampled] = True
    return chord_gaps_of(a[None], mask)[0]


def refined_samples(a: np.ndarray, tolerance: float, first: np.ndarray) -> tuple[np.ndarray, float]:
    """:func:`refined_masks` of one path ``a`` (T, r) from the steps ``first``, as indices."""
    mask = np.zeros((1, a.shape[0]), dtype=bool)
    mask[0, first] = True
    mask, delta = refined_masks(a[None], np.array([tolerance]), mask)
    return np.flatnonzero(mask[0]), float(delta[0])


def touched_steps(a: np.ndarray, first: np.ndarray) -> np.ndarray:
    """:func:`touched_of` one path ``a`` (T, r) from its evenly spaced steps ``first``."""
    mask = np.zeros((1, a.shape[0]), dtype=bool)
    mask[0, first] = True
    return np.unique(touched_of(a[None], mask)[0])


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
    :func:`railcheck.sweep.fe._in_span` reads them in the same coefficients). None:
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


#: singular values of a group's sampled steps above this share of the largest span the
#: group's histories (:func:`history_span`); the rest are rounding (a free body's
#: equilibrium and the joints its group shares: about 1e-16 of the largest, against 1e-4
#: to 1e-3 for the smallest kept)
SPAN_RANK = 1e-10
#: a group's histories are re-expressed in fewer coefficients only when each history's
#: residual outside their span is at most this share of its largest scaled coefficient
#: vector (:func:`history_span`): its results then equal the full ones to rounding
SPAN_RESIDUAL = 1e-13
#: every this-many-th step of each history is read to find the span (the residual is then
#: measured at every step, so a direction only the skipped steps take is never lost)
SPAN_STRIDE = 8


@dataclass(frozen=True)
class Span:
    """A group's scaled coefficients ``c * scale`` (k,) in r of themselves: ``index`` (r,)
    ascending the independent ones, ``basis`` (k, r) with ``c * scale = basis (c *
    scale)[index]`` for every step of every history of the group (to the residual
    :func:`history_span` measured), ``basis[index]`` the identity."""

    index: np.ndarray
    basis: np.ndarray

    @property
    def dual(self) -> np.ndarray:
        """(k, r): the selection of the independent coefficients (``dual^T basis = I``)."""
        out = np.zeros(self.basis.shape)
        out[self.index, np.arange(self.index.size)] = 1.0
        return out


def history_span(Cs: np.ndarray) -> Span | None:
    """The span of the scaled histories ``Cs`` (s, T, k) as r < k of their coefficients
    (:class:`Span`), or None when they span all k (or are not finite, or zero).

    The rank is read from the singular values of every :data:`SPAN_STRIDE`-th step (above
    :data:`SPAN_RANK` of the largest); the independent coefficients are the pivots of a
    column-pivoted QR of the span's basis (the best conditioned choice). The residual of
    each step, ``e = Cs - basis Cs[index]``, is bounded from its part outside the span,
    ``|e| <= |z| (1 + |basis|_2)`` (``z`` the component along the null directions: the
    span's part is reproduced exactly), and the span is used only when every history's
    bound is at most :data:`SPAN_RESIDUAL` of its largest ``|Cs_t|``."""
    s, T, k = Cs.shape
    X = Cs[:, ::SPAN_STRIDE].reshape(-1, k)
    if X.shape[0] < k:
        X = Cs.reshape(-1, k)
    if not np.all(np.isfinite(X)):
        return None
    _, sv, Vt = np.linalg.svd(np.linalg.qr(X, mode="r"))
    if not sv[0] > 0.0:
        return None
    r = int(np.count_nonzero(sv > SPAN_RANK * sv[0]))
    if r >= k:
        return None
    import scipy.linalg

    B, N = Vt[:r].T, Vt[r:].T
    index = np.sort(scipy.linalg.qr(B.T, pivoting=True, mode="r")[1][:r])
    basis = B @ np.linalg.inv(B[index])
    basis[index] = np.eye(r)
    with np.errstate(over="ignore"):  # sizes beyond 1e154 overflow to inf: then no span
        outside = np.linalg.norm(Cs @ N, axis=2).max(axis=1) * (1.0 + np.linalg.norm(basis, 2))
        size = np.linalg.norm(Cs, axis=2).max(axis=1)
    if not np.all(np.isfinite(size) & (outside <= SPAN_RESIDUAL * size)):
        return None
    return Span(index, basis)


#: steps of each history (evenly spaced, besides the one nearest its box's centre) whose
#: values tighten a group box's midrange bounds (:meth:`CoefficientBox.ranges_and_taken`)
BOX_TAKEN_STEPS = 4
#: nodes (evenly strided) on which :func:`box_basis` compares the two bases' boxes
BASIS_TRIAL_NODES = 512


def box_basis(S: np.ndarray, scale: np.ndarray, C: np.ndarray) -> np.ndarray | None:
    """The basis of :class:`CoefficientBox` for the group of histories ``C`` (s, T, k)
    (:func:`box_basis_and_coordinates`)."""
    return box_basis_and_coordinates(S, scale, C)[0]


def basis_trial_nodes(S: np.ndarray) -> np.ndarray:
    """(6, m, k) contiguous: the stresses ``S`` (6, n, k) at the :data:`BASIS_TRIAL_NODES`
    evenly strided nodes on which :func:`box_basis_and_coordinates` compares the bases."""
    return np.ascontiguousarray(S[:, :: max(1, S.shape[1] // BASIS_TRIAL_NODES)])


def box_basis_and_coordinates(
    S: np.ndarray, scale: np.ndarray, C: np.ndarray, trial: np.ndarray | None = None
) -> tuple[np.ndarray | None, np.ndarray]:
    """(basis, coordinates): the basis of :class:`CoefficientBox` for the group of
    histories ``C`` (s, T, k), the principal axes of their scaled steps' deviations from
    each history's mean, or None (the coefficients themselves), whichever gives the
    smaller bounds (the sum of von Mises bounds and component reaches) on the trial nodes
    of ``S`` (6, n, k) (``trial``: :func:`basis_trial_nodes` of ``S``, made once per
    screen; None: made here); and every step's coordinates in it (s, T, k), as
    :meth:`CoefficientBox.coordinates` gives them (the trial computed them). The
    principal axes suit histories that move in a few mixed directions (a short crank's
    rail: 18 coefficients that are 4 signals, whose coefficient box kept more than half
    the nodes), the coefficients loads that vary independently (the coupler's and
    rocker's pins)."""
    k = S.shape[2]
    Cs = scaled(C, scale)
    D = (Cs - Cs.mean(axis=1, keepdims=True)).reshape(-1, k)
    principal = np.linalg.eigh(D.T @ D)[1]
    trial = basis_trial_nodes(S) if trial is None else trial

    def size(basis, d):
        box = CoefficientBox(trial, scale, basis)
        vm, _, reach = box.box_arrays(d.min(axis=1), d.max(axis=1))
        return float(vm.sum(dtype=np.float64) + reach.sum(dtype=np.float64))

    d = Cs @ principal  # (CoefficientBox.coordinates in this basis)
    return (principal, d) if size(principal, d) < size(None, C) else (None, C)


def sampled_bounds(SP: np.ndarray, norms: np.ndarray, vm_norm: np.ndarray, sub: Subspace) -> SampledBounds:
    """The nodes' sampled values and bounds (module doc) for one history: ``SP`` (6, n, r)
    the stresses per unit of the subspace's coordinates (:func:`project`); ``norms`` (6,
    n) :func:`component_norms` of the stress per unit scaled coefficient; ``vm_norm``
    (n,) a bound of each node's von Mises per unit scaled coefficient
    (:func:`von_mises_norm_bound`, or the square root of its quadratic form's largest
    eigenvalue). :func:`sampled_pairs` with every node paired with the one history."""
    n = SP.shape[1]
    at = sub.a[sub.sampled][None]
    one = np.zeros(n, dtype=int)
    return sampled_pairs(
        np.ascontiguousarray(SP.transpose(1, 0, 2)), one, at, np.array([sub.delta]), np.array([sub.eps]), norms, vm_norm
    )


def sampled_pairs(
    SP: np.ndarray, h: np.ndarray, at: np.ndarray, delta: np.ndarray, eps: np.ndarray, norms: np.ndarray, vm_norm: np.ndarray
) -> SampledBounds:
    """:class:`SampledBounds` (components first, (6, q)) of (history, node) pairs (module
    doc): ``SP`` (q, 6, r) each pair's stresses per unit of its history's subspace
    coordinates, ``h`` (q,) its history (ascending), ``at`` (s, M, r) each history's
    read steps' coordinates, ``delta`` and ``eps`` (s,) its chord distance and residual,
    ``norms`` (6, q) and ``vm_norm`` (q,) as for :func:`sampled_bounds`. One product per
    history (and per :data:`CHUNK_VALUES` of its values)."""
    q, _, r = SP.shape
    vm, high, low = np.empty(q), np.empty((q, 6)), np.empty((q, 6))
    for i, start, stop in history_blocks(h, max(1, CHUNK_VALUES // (6 * at.shape[1]))):
        # (M, m, 6): the components at the read steps, steps first, so that the extremes
        # over the steps are elementwise maxima of contiguous rows
        X = (at[i] @ SP[start:stop].reshape(-1, r).T).reshape(at.shape[1], -1, 6)
        high[start:stop], low[start:stop] = X.max(axis=0), X.min(axis=0)
        vm[start:stop] = np.sqrt(von_mises_squared(X.transpose(2, 0, 1)).max(axis=0))
    high, low = np.ascontiguousarray(high.T), np.ascontiguousarray(low.T)
    delta, eps = delta[h], eps[h]
    # ||L SP||_F: the Frobenius norm of each node's von Mises factor in the r coordinates
    # (one batched product and one contraction: half the time of summing von Mises squared
    # over the coordinates' strided columns)
    LSP = np.matmul(VM_FACTOR, SP).reshape(q, 6 * r)
    vm_P = np.sqrt(np.einsum("qi,qi->q", LSP, LSP))
    upper = vm + vm_P * delta + vm_norm * eps
    share = norms * eps  # the residual's share of a component
    slack = np.sqrt(np.einsum("qcr,qcr->cq", SP, SP)) * delta + share
    # a read step's value is its subspace value within the residual's share, so the
    # maximum lies in [high - share, high + slack] and the minimum in [low - slack, low +
    # share]: the midrange within half of slack + share of the sampled one
    return SampledBounds(vm, upper, high, low, slack, np.abs(0.5 * (high + low)) + 0.5 * (slack + share), share)


@dataclass(frozen=True)
class Projected:
    """One history's principal subspace ``sub`` (:func:`principal_subspace` of the scaled
    history) and the nodes in it: ``SP`` (6, n, r) Pa per unit coordinate
    (:func:`project`), ``norms`` (6, n) :func:`component_norms` and ``vm_norm`` (n,)
    :func:`von_mises_norm_bound` of the stress per unit scaled coefficient."""

    SP: np.ndarray
    norms: np.ndarray
    vm_norm: np.ndarray
    sub: Subspace


def project_history(S: np.ndarray, C: np.ndarray) -> Projected:
    """:class:`Projected` of the nodes of ``S`` (6, n, k) Pa per unit coefficient for one
    history ``C`` (steps, k), the coefficients scaled by :func:`column_scale`."""
    w = column_scale(S)
    Sw = S / w
    sub = principal_subspace(C * w)
    return Projected(project(S, w, sub), component_norms(Sw), von_mises_norm_bound(Sw), sub)


def history_bounds(S: np.ndarray, C: np.ndarray) -> SampledBounds:
    """:func:`sampled_bounds` of every node of ``S`` (6, n, k) Pa per unit coefficient for
    one history ``C`` (steps, k)."""
    p = project_history(S, C)
    return sampled_bounds(p.SP, p.norms, p.vm_norm, p.sub)


def history_box_bounds(S: np.ndarray, C: np.ndarray) -> SampledBounds:
    """:func:`box_bounds` of the nodes of ``S`` (6, n, k) Pa per unit coefficient for one
    history ``C`` (steps, k): the box of its coordinates in its principal subspace bounds
    every step without reading one (a few array passes over the nodes)."""
    p = project_history(S, C)
    return box_bounds(p.SP, p.norms, p.vm_norm, p.sub)


def sampled_at(p: Projected, box: SampledBounds, nodes: np.ndarray) -> SampledBounds:
    """The box bounds ``box`` (:func:`box_bounds` of ``p``) at every node but ``nodes``,
    where the history is read at its sampled steps (:func:`sampled_bounds`): valid bounds
    everywhere, tight where the box left candidates."""
    s = sampled_bounds(p.SP[:, nodes], p.norms[:, nodes], p.vm_norm[nodes], p.sub)
    out = SampledBounds(
        *(np.array(a, copy=True) for a in (box.von_mises, box.von_mises_upper, box.high, box.low, box.slack)),
        mid_upper=None if box.mid_upper is None else np.array(box.mid_upper, copy=True),
        share=np.array(box.slack if box.share is None else box.share, copy=True),  # the box's centre: +- its reach
    )
    out.von_mises[nodes], out.von_mises_upper[nodes] = s.von_mises, s.von_mises_upper
    out.high[:, nodes], out.low[:, nodes], out.slack[:, nodes] = s.high, s.low, s.slack
    if out.mid_upper is not None:
        out.mid_upper[:, nodes] = s.mid_upper
    assert out.share is not None and s.share is not None  # both set above and by sampled_pairs
    out.share[:, nodes] = s.share
    return out


#: relative widening of :func:`midrange_box` (the float64 rounding of a mean of many steps)
MEAN_ROUNDING = 1e-9


def midrange_box(lo: np.ndarray, hi: np.ndarray, mean: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi) (s, k): for each history whose coordinates range over ``lo`` to ``hi``
    (s, k) and whose steps' mean is ``mean`` (s, k), a box whose image under any linear
    function holds that function's midrange over the steps: its maximum is at most the
    box's and at least its mean, its minimum at least the box's and at most its mean, so
    the midrange lies within ``[(mean . R + min_box) / 2, (mean . R + max_box) / 2]``,
    the image of ``[(mean + lo) / 2, (mean + hi) / 2]``. Widened by :data:`MEAN_ROUNDING`
    of the coordinates' magnitude: a mean summed over many steps in float64 lies within
    that of the true one (T eps: 1e-11 at 100,000 steps)."""
    pad = MEAN_ROUNDING * (np.abs(lo) + np.abs(hi))
    return 0.5 * (mean + lo) - pad, 0.5 * (mean + hi) + pad


def fatigue_bounds_by_midranges(box: SampledBounds, mid: np.ndarray, reach: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(sa_upper, sm_upper) (..., n) Pa: :func:`fatigue_bounds` of the boxes ``box``, the
    midrange bound tightened by the products (:meth:`CoefficientBox.products`, components
    first: ``mid``, ``reach`` (6, ..., n)) of boxes whose image holds each component's
    midrange (:func:`midrange_box`). A history that swings about a small mean (a link's)
    has a midrange far below its box's ``|mid| + reach``."""
    sa, sm = fatigue_bounds(box)
    midranges = SampledBounds.box(None, mid, reach)  # type: ignore[arg-type]
    return sa, np.minimum(sm, fatigue_bounds(midranges, alternating=False)[1])


def fatigue_bounds(b: SampledBounds, alternating: bool = True) -> tuple[np.ndarray | None, np.ndarray]:
    """(sa_upper, sm_upper) (n,) Pa: upper bounds of each node's alternating and midrange
    von Mises over every step. Each component's maximum lies within ``[high - share, high
    + slack]`` and its minimum within ``[low - slack, low + share]`` (``share`` the
    bounds' own, else ``slack``), so its half-range lies within ``[(high - low) / 2 -
    share, (high - low) / 2 + slack]`` (and is not negative) and its midrange within
    ``(high + low) / 2 +- (slack + share) / 2`` (and within ``+- mid_upper``); each von
    Mises is bounded over those intervals (:func:`interval_von_mises`). In float32 (a
    group's box) the intervals are widened by their ends' own rounding."""
    spread = b.slack
    inner = b.slack if b.share is None else b.share
    if b.high.dtype == np.float32:
        rounding = np.float32(4.0 * FLOAT32_EPS) * (np.abs(b.high) + np.abs(b.low) + b.slack)
        spread, inner = spread + rounding, inner + rounding
    if b.high is b.low:  # a box: its centre, no step read; the half-range from 0 to the reach
        centre, half_lo, half_hi = b.high, None, spread
        mid_lo, mid_hi = centre - spread, centre + spread
    else:
        half, centre = 0.5 * (b.high - b.low), 0.5 * (b.high + b.low)
        half_lo, half_hi = np.maximum(half - inner, 0.0), half + spread
        mid_lo, mid_hi = centre - 0.5 * (spread + inner), centre + 0.5 * (spread + inner)
    if b.mid_upper is not None:
        mid_lo, mid_hi = np.maximum(mid_lo, -b.mid_upper), np.minimum(mid_hi, b.mid_upper)
    return interval_von_mises(half_lo, half_hi) if alternating else None, interval_von_mises(mid_lo, mid_hi)


def fatigue_sampled(b: SampledBounds) -> tuple[np.ndarray, np.ndarray]:
    """(sa, sm) (n,) Pa: each node's alternating and midrange von Mises over the steps
    read (an estimate: the nodes worth evaluating first)."""
    return von_mises(0.5 * (b.high - b.low)), von_mises(0.5 * (b.high + b.low))


def interval_von_mises(lo: np.ndarray | None, hi: np.ndarray) -> np.ndarray:
    """(n,) Pa: a bound of the von Mises of any stress whose components (6, n) lie within
    ``[lo, hi]`` (Pa; ``lo`` None: 0): each normal difference ``s_i - s_j`` at most
    ``max(hi_i - lo_j, hi_j - lo_i)`` in magnitude, each shear at most ``max(|lo|,
    |hi|)``; widened by :data:`BOX_WIDENING` in float32 (its own arithmetic). For
    intervals ``mid +- reach`` this is :func:`von_mises_interval_bound`, which the boxes
    compute from ``mid`` and ``reach`` without forming the ends."""
    pairs = ((0, 1), (1, 2), (2, 0))
    if lo is None:
        normal = sum(np.maximum(hi[i], hi[j]) ** 2 for i, j in pairs)
        shear = sum(hi[i] ** 2 for i in (3, 4, 5))
    else:
        normal = sum(np.maximum(hi[i] - lo[j], hi[j] - lo[i]) ** 2 for i, j in pairs)
        shear = sum(np.maximum(np.abs(lo[i]), np.abs(hi[i])) ** 2 for i in (3, 4, 5))
    widening = BOX_WIDENING if hi.dtype == np.float32 else 0.0
    return np.sqrt(0.5 * normal + 3.0 * shear) * (1.0 + hi.dtype.type(widening))


def peak_candidates(b: SampledBounds, lower: float) -> np.ndarray:
    """Nodes whose von Mises bound reaches ``lower`` (Pa, an exact value at some node):
    the only ones that can hold the peak (ascending)."""
    return np.flatnonzero(b.von_mises_upper * (1.0 + SLACK) >= lower)


def first_nodes(values: np.ndarray, largest: bool = True, count: int = FIRST_NODES) -> np.ndarray:
    """The ``count`` nodes of largest (or smallest) ``values``, ascending (a partial
    sort: which of several equal values at the cut is taken is unspecified)."""
    key = -values if largest else values
    if key.size <= count:
        return np.arange(key.size)
    return np.sort(np.argpartition(key, count - 1)[:count])
