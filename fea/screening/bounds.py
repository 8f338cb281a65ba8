"""Sampled bounds of one history at the nodes a box keeps: the box's basis, the path
samples read at a node, fatigue bounds from midranges and half-ranges, and the first nodes
to evaluate exactly. Pa throughout."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..invariants import von_mises, von_mises_squared
from .box import (
    BOX_WIDENING,
    FLOAT32_EPS,
    CoefficientBox,
    SampledBounds,
    box_bounds,
    component_norms,
    project,
    von_mises_norm_bound,
)
from .subspace import (
    CHUNK_VALUES,
    FIRST_NODES,
    SLACK,
    VM_FACTOR,
    Subspace,
    column_scale,
    history_blocks,
    principal_subspace,
    scaled,
)

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
        np.array(box.von_mises, copy=True),
        np.array(box.von_mises_upper, copy=True),
        np.array(box.high, copy=True),
        np.array(box.low, copy=True),
        np.array(box.slack, copy=True),
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


def fatigue_bounds_by_midranges(
    box: SampledBounds, mid: np.ndarray, reach: np.ndarray
) -> tuple[np.ndarray | None, np.ndarray]:
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
