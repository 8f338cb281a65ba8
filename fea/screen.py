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

from .stress import VM_QUADRATIC, von_mises, von_mises_squared

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


def applies(steps: int, k: int) -> bool:
    """Whether a history of ``steps`` x ``k`` coefficients is screened in its subspace
    (two coefficients have exact planar paths; a few steps are cheaper read whole)."""
    return k > 2 and steps > MIN_STEPS


def column_scale(S: np.ndarray) -> np.ndarray:
    """(k,) each coefficient's largest stress per unit (Pa per unit) over the nodes of
    ``S`` (6, n, k): the coefficients' scale."""
    return np.sqrt(np.einsum("cnk,cnk->nk", S, S)).max(axis=0) + 1e-300


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


def subspace_rank(c: np.ndarray, Vt: np.ndarray) -> int:
    """The smallest rank from REDUCED_RANK to MAX_RANK (at most k) whose residual is at
    most RESIDUAL_SHARE of the history's largest step norm (``Vt``: the history's right
    singular vectors, rows by decreasing singular value)."""
    coords = c @ Vt.T  # (T, m): every step in the singular basis
    # tail[:, r]: each step's residual beyond rank r (sums of squares from the back: no cancellation)
    tail = np.sqrt(np.cumsum(coords[:, ::-1] ** 2, axis=1)[:, ::-1]).max(axis=0)
    reach = float(np.linalg.norm(c, axis=1).max())
    top = min(MAX_RANK, c.shape[1])
    r = min(REDUCED_RANK, top)
    while r < top and r < tail.size and tail[r] > RESIDUAL_SHARE * reach:
        r += 1
    return r


def path_samples(a: np.ndarray, samples: int) -> np.ndarray:
    """Indices (ascending, first and last included) of about ``samples`` steps of the path
    ``a`` (T, r), evenly spaced along its length."""
    T = a.shape[0]
    length = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(a, axis=0), axis=1))])
    marks = np.linspace(0.0, length[-1], min(samples, T))
    return np.unique(np.concatenate([np.searchsorted(length, marks).clip(0, T - 1), [0, T - 1]]))


def chord_gaps(a: np.ndarray, sampled: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((T,), (T,)): each step's distance from the chord between the read steps
    ``sampled`` (ascending, first and last step included) before and after it, and the
    index of that chord (its first read step's position in ``sampled``). A read step is
    at distance 0."""
    T = a.shape[0]
    j = np.minimum(np.searchsorted(sampled, np.arange(T), side="right") - 1, max(sampled.size - 2, 0))
    start = a[sampled[j]]
    d = a[sampled[np.minimum(j + 1, sampled.size - 1)]] - start
    along = np.einsum("tr,tr->t", a - start, d) / np.maximum(np.einsum("tr,tr->t", d, d), np.finfo(float).tiny)
    offset = a - start - np.clip(along, 0.0, 1.0)[:, None] * d
    return np.sqrt(np.einsum("tr,tr->t", offset, offset)), j


def refined_samples(a: np.ndarray, tolerance: float, first: np.ndarray) -> tuple[np.ndarray, float]:
    """(indices, delta): steps of the path ``a`` (T, r) (ascending, first and last
    included) such that every step lies within ``tolerance`` of the chord between the
    read steps around it, and the largest such distance (:func:`chord_gaps`). From the
    steps ``first`` (:func:`path_samples`), round by round the farthest step of every
    chord that has one beyond ``tolerance`` is added (Douglas-Peucker, all chords at
    once), up to :data:`MAX_SAMPLES`."""
    sampled, cap = first, min(MAX_SAMPLES, a.shape[0])
    while True:
        gap, chord = chord_gaps(a, sampled)
        if sampled.size >= cap or sampled.size < 2:
            break
        farthest = np.maximum.reduceat(gap, sampled[:-1])  # each chord's steps are contiguous
        over = farthest > tolerance
        if not over.any():
            break
        at = np.flatnonzero((gap == farthest[chord]) & over[chord])
        new = at[np.unique(chord[at], return_index=True)[1]]  # one per chord
        sampled = np.union1d(sampled, new[: cap - sampled.size])
    return sampled, float(gap.max())


def nearest_to_box_centre(d: np.ndarray) -> np.ndarray:
    """(...,) the index of the step of each path ``d`` (..., T, k) nearest the centre of
    the box of its coordinates' ranges, each coordinate in units of its half-width."""
    lo, hi = d.min(axis=-2, keepdims=True), d.max(axis=-2, keepdims=True)
    scaled = (d - 0.5 * (lo + hi)) / np.maximum(0.5 * (hi - lo), np.finfo(float).tiny)
    return np.argmin(np.square(scaled).sum(axis=-1), axis=-1)


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


def touched_steps(a: np.ndarray, first: np.ndarray) -> np.ndarray:
    """Indices (ascending) of about :data:`TOUCHED_STEPS` of the evenly spaced steps
    ``first`` (:func:`path_samples`) of the path ``a`` (T, r) and of the step nearest the
    centre of its box (:func:`nearest_to_box_centre`): values the history takes, which
    bound each component's midrange from both sides (:func:`box_bounds`)."""
    return np.union1d(first[:: max(1, first.size // TOUCHED_STEPS)], [nearest_to_box_centre(a)])


def principal_subspace(c: np.ndarray) -> Subspace:
    """The scaled history ``c`` (T, k) in its principal subspace (:func:`subspace_rank`),
    read at :func:`refined_samples` (every step within :data:`CHORD_SHARE` of the
    history's largest ``|c_t|``, or within its residual, of its chord). The directions
    are the eigenvectors of ``c^T c`` (the right singular vectors; any orthonormal ``P``
    gives valid bounds, since ``eps`` is the measured residual)."""
    Vt = np.linalg.eigh(c.T @ c)[1][:, ::-1].T
    P = Vt[: subspace_rank(c, Vt)].T
    a = c @ P
    eps = float(np.linalg.norm(c - a @ P.T, axis=1).max())
    reach = float(np.linalg.norm(c, axis=1).max())
    first = path_samples(a, FIRST_SAMPLES)
    sampled, delta = refined_samples(a, max(eps, CHORD_SHARE * reach), first)
    return Subspace(P, a, eps, sampled, delta, touched_steps(a, first))


@dataclass(frozen=True)
class SampledBounds:
    """Per node, from the sampled steps in the subspace: ``von_mises`` (n,) Pa the largest
    sampled von Mises and ``von_mises_upper`` (n,) a bound over every step; ``high``,
    ``low`` (6, n) Pa each component's sampled maximum and minimum and ``slack`` (6, n)
    Pa how far outside them its value at any step can lie; ``mid_upper`` (6, n) Pa, or
    None, a bound of each component's midrange magnitude tighter than ``|high + low| / 2
    + slack`` (:func:`box_bounds`; inf where there is none)."""

    von_mises: np.ndarray
    von_mises_upper: np.ndarray
    high: np.ndarray
    low: np.ndarray
    slack: np.ndarray
    mid_upper: np.ndarray | None = None


def component_norms(Sw: np.ndarray) -> np.ndarray:
    """(6, n): each stress component's norm over its k coefficients (Pa per unit scaled coefficient)."""
    return np.sqrt(np.einsum("cnk,cnk->cn", Sw, Sw))


def von_mises_norm_bound(Sw: np.ndarray) -> np.ndarray:
    """(n,): an upper bound of each node's largest von Mises per unit scaled coefficient,
    the Frobenius norm of its von Mises factor (sqrt of the trace of its quadratic form)."""
    return np.sqrt(np.maximum(np.einsum("cnk,cd,dnk->n", Sw, VM_QUADRATIC, Sw, optimize=True), 0.0))


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
    return SampledBounds(vm, vm, mid, mid, reach, mid_upper)


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

    The rows are held in float32 (the products stream every node once per history; half
    the bytes). The bounds stay bounds: a float32 dot product of length k + 2 roundings
    errs by at most ``(k + 4) u |m| . |R_j|`` (u the float32 roundoff; Higham, *Accuracy
    and Stability of Numerical Algorithms*, 3.1), so ``2 (k + 4) u |m|`` is added to the
    half-widths of the reach product (itself of non-negative terms, widened by the same
    share): twice the products' worst error, the other half (at least 10 roundoffs of the
    value) covers the few float32 roundings of the fatigue bounds computed from them
    (:func:`fatigue_bounds`). Results are float32 (Pa)."""

    def __init__(self, S: np.ndarray, scale: np.ndarray, basis: np.ndarray | None = None):
        k = S.shape[2]
        S2 = S.reshape(-1, k)  # (6 n, k): rows by component, then node
        rows = S2 if basis is None else S2 @ (basis / scale[:, None])  # per unit of each basis coordinate
        self._hold(rows.astype(np.float32), S.shape[1], scale, basis)

    def _hold(self, rows: np.ndarray, nodes: int, scale: np.ndarray, basis: np.ndarray | None) -> None:
        """Keep the float32 ``rows`` (6 nodes, k) per unit basis coordinate and what reads them."""
        self.nodes, self.scale, self.B = nodes, scale, basis
        self.rows = rows
        self.abs_rows = np.abs(rows)
        self.dot_error = 2.0 * (rows.shape[1] + 4) * FLOAT32_EPS  # relative, of |m| . |R_j| (class doc)

    def restricted(self, nodes: np.ndarray) -> CoefficientBox:
        """The same box at ``nodes`` (indices into this box's nodes) only."""
        box = object.__new__(CoefficientBox)
        k = self.rows.shape[1]
        box._hold(
            np.ascontiguousarray(self.rows.reshape(6, self.nodes, k)[:, nodes].reshape(-1, k)),
            nodes.size,
            self.scale,
            self.B,
        )
        return box

    def coordinates(self, C: np.ndarray) -> np.ndarray:
        """(s, T, k): the basis coordinates of every step of each history of ``C`` (s, T,
        k) (unscaled coefficients)."""
        return C if self.B is None else (C * self.scale) @ self.B

    def ranges(self, C: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(lo, hi) (s, k): the ranges of the basis coordinates of each history of ``C``
        (s, T, k) (unscaled coefficients), the box :meth:`box_of` bounds over."""
        d = self.coordinates(C)
        return d.min(axis=1), d.max(axis=1)

    def ranges_and_taken(self, C: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(lo, hi, taken): :meth:`ranges`, and ``taken`` (s, p, k) the coordinates of a
        few steps of each history (:data:`BOX_TAKEN_STEPS` evenly spaced and the one
        nearest its box's centre), values the history takes (:meth:`at_nodes`)."""
        d = self.coordinates(C)
        lo, hi = d.min(axis=1), d.max(axis=1)
        nearest = nearest_to_box_centre(d)  # (s,)
        spaced = np.linspace(0, d.shape[1], BOX_TAKEN_STEPS, endpoint=False).astype(int)
        steps = np.concatenate([np.broadcast_to(spaced, (d.shape[0], spaced.size)), nearest[:, None]], axis=1)
        return lo, hi, np.take_along_axis(d, steps[:, :, None], axis=1)

    def box_of(self, lo: np.ndarray, hi: np.ndarray) -> list[SampledBounds]:
        """One :class:`SampledBounds` per box of basis coordinates ``lo`` to ``hi`` (s, k)
        (:meth:`ranges`, or any box holding a history's steps): ``high`` = ``low`` the
        components at the box's centre, ``slack`` their reach, ``von_mises`` =
        ``von_mises_upper`` the bound of von Mises (float32)."""
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
        vm = von_mises_interval_bound(mid, reach, axis=1)
        return [SampledBounds(vm[i], vm[i], mid[i], mid[i], reach[i]) for i in range(lo.shape[0])]

    def at_nodes(self, b: SampledBounds, nodes: np.ndarray, taken: np.ndarray) -> SampledBounds:
        """The bounds ``b`` of one history (:meth:`box_of`) at ``nodes`` only, with
        midrange bounds (``mid_upper``, :func:`midrange_bound`) from the coordinates of
        steps the history takes, ``taken`` (p, k) (:meth:`ranges_and_taken`): its maximum
        is at least the largest taken value, its minimum at most the smallest. Their
        float32 error (the dot products' bound above, on the largest ``|taken|`` of each
        coordinate) and four roundoffs of the terms summed widen it. Read only where the
        box alone leaves candidates, since they cost p products per node."""
        k = self.rows.shape[1]
        rows = self.rows.reshape(6, self.nodes, k)[:, nodes].reshape(-1, k)
        abs_rows = self.abs_rows.reshape(6, self.nodes, k)[:, nodes].reshape(-1, k)
        mid, reach = b.high[:, nodes], b.slack[:, nodes]
        mid_upper = self._mid_upper(mid[None], reach[None], taken[None], rows, abs_rows)[0]
        return SampledBounds(b.von_mises[nodes], b.von_mises_upper[nodes], mid, mid, reach, mid_upper)

    def _mid_upper(
        self, mid: np.ndarray, reach: np.ndarray, taken: np.ndarray, rows: np.ndarray, abs_rows: np.ndarray
    ) -> np.ndarray:
        """(s, 6, n) float32: each component's midrange bound of :meth:`at_nodes` from the
        values at the ``taken`` (s, p, k) coordinates, with the box's ``mid`` and
        ``reach`` (s, 6, n) and its float32 ``rows`` and ``abs_rows`` (6 n, k) at those
        nodes; inf where any term is not finite."""
        t = taken.astype(np.float32)
        values = np.matmul(t, rows.T)  # (s, p, 6 n)
        low, high = (v.reshape(mid.shape) for v in (values.min(axis=1), values.max(axis=1)))
        error = ((self.dot_error * np.abs(taken).max(axis=1)).astype(np.float32) @ abs_rows.T).reshape(mid.shape)
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


#: steps of each history (evenly spaced, besides the one nearest its box's centre) whose
#: values tighten a group box's midrange bounds (:meth:`CoefficientBox.ranges_and_taken`)
BOX_TAKEN_STEPS = 4
#: nodes (evenly strided) on which :func:`box_basis` compares the two bases' boxes
BASIS_TRIAL_NODES = 512


def box_basis(S: np.ndarray, scale: np.ndarray, C: np.ndarray) -> np.ndarray | None:
    """The basis of :class:`CoefficientBox` for the group of histories ``C`` (s, T, k):
    the principal axes of their scaled steps' deviations from each history's mean, or
    None (the coefficients themselves), whichever gives the smaller bounds (the sum of
    von Mises bounds and component reaches) on :data:`BASIS_TRIAL_NODES` nodes of ``S``
    (6, n, k). The principal axes suit histories that move in a few mixed directions (a
    short crank's rail: 18 coefficients that are 4 signals, whose coefficient box kept
    more than half the nodes), the coefficients loads that vary independently (the
    coupler's and rocker's pins)."""
    k = S.shape[2]
    Cs = C * scale
    D = (Cs - Cs.mean(axis=1, keepdims=True)).reshape(-1, k)
    principal = np.linalg.eigh(D.T @ D)[1]
    trial = np.ascontiguousarray(S[:, :: max(1, S.shape[1] // BASIS_TRIAL_NODES)])

    def size(basis):
        return sum(float(b.von_mises_upper.sum() + b.slack.sum()) for b in CoefficientBox(trial, scale, basis).bounds(C))

    return principal if size(principal) < size(None) else None


def sampled_bounds(SP: np.ndarray, norms: np.ndarray, vm_norm: np.ndarray, sub: Subspace) -> SampledBounds:
    """The nodes' sampled values and bounds (module doc). ``SP`` (6, n, r) the stresses
    per unit of the subspace's coordinates (:func:`project`); ``norms`` (6, n)
    :func:`component_norms` of the stress per unit scaled coefficient; ``vm_norm`` (n,) a
    bound of each node's von Mises per unit scaled coefficient
    (:func:`von_mises_norm_bound`, or the square root of its quadratic form's largest
    eigenvalue)."""
    a = sub.a[sub.sampled]  # (s, r)
    n = SP.shape[1]
    vm, high, low = np.empty(n), np.empty((6, n)), np.empty((6, n))
    size = max(1, CHUNK_VALUES // (6 * a.shape[0]))
    for start in range(0, n, size):
        sl = slice(start, min(start + size, n))
        # (6, s, m): the components at the read steps, nodes last, so that the extremes
        # over the steps are elementwise maxima of contiguous rows
        X = np.matmul(a, SP[:, sl].transpose(0, 2, 1))
        high[:, sl], low[:, sl] = X.max(axis=1), X.min(axis=1)
        vm[sl] = np.sqrt(von_mises_squared(X).max(axis=0))
    # ||L SP||_F: the Frobenius norm of each node's von Mises factor in the r coordinates
    vm_P = np.sqrt(von_mises_squared(SP).sum(axis=1))
    upper = vm + vm_P * sub.delta + vm_norm * sub.eps
    share = norms * sub.eps  # the residual's share of a component
    slack = np.linalg.norm(SP, axis=2) * sub.delta + share
    # a read step's value is its subspace value within the residual's share, so the
    # maximum lies in [high - share, high + slack] and the minimum in [low - slack, low +
    # share]: the midrange within half of slack + share of the sampled one
    return SampledBounds(vm, upper, high, low, slack, np.abs(0.5 * (high + low)) + 0.5 * (slack + share))


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
    )
    out.von_mises[nodes], out.von_mises_upper[nodes] = s.von_mises, s.von_mises_upper
    out.high[:, nodes], out.low[:, nodes], out.slack[:, nodes] = s.high, s.low, s.slack
    if out.mid_upper is not None:
        out.mid_upper[:, nodes] = s.mid_upper
    return out


def fatigue_bounds(b: SampledBounds) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(sa_upper, sm_upper, sa_sampled, sm_sampled) (n,) Pa: upper bounds of each node's
    alternating and midrange von Mises over every step (no cross terms between the
    components' unknown signs), and their sampled values (an estimate)."""
    half = 0.5 * (b.high - b.low) + b.slack
    mid = np.abs(0.5 * (b.high + b.low)) + b.slack
    if b.mid_upper is not None:
        mid = np.minimum(mid, b.mid_upper)
    sa = np.sqrt(half[0] ** 2 + half[1] ** 2 + half[2] ** 2 + 3.0 * (half[3] ** 2 + half[4] ** 2 + half[5] ** 2))
    sm = np.sqrt(
        0.5 * ((mid[0] + mid[1]) ** 2 + (mid[1] + mid[2]) ** 2 + (mid[2] + mid[0]) ** 2)
        + 3.0 * (mid[3] ** 2 + mid[4] ** 2 + mid[5] ** 2)
    )
    return sa, sm, von_mises(0.5 * (b.high - b.low)), von_mises(0.5 * (b.high + b.low))


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
