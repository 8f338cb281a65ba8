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
(:mod:`railcheck.fea.screening`, :func:`fea.superpose.screened_max`,
:func:`railcheck.model.cycle.fatigue_of`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..invariants import VM_QUADRATIC

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


#: floats per temporary (nodes x sampled steps x 6): 4 MB, small enough to be read twice
#: (max and min) from cache (measured: docs/changelog.md, "The measurements behind tuned constants")
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
