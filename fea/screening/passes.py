"""The screening's tests and a group's first pass: which (history, node) pairs can beat
their thresholds, the thresholds from a few exactly evaluated nodes, and the nodes that can
matter to some history of a group."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from . import tuning
from .bounds import fatigue_bounds, fatigue_bounds_by_midranges, first_nodes, midrange_box
from .box import CoefficientBox, SampledBounds, von_mises_interval_bound
from .exact import exact_at
from .screens import Screen


def over_sets(values: np.ndarray, labels: np.ndarray, reduce) -> np.ndarray:
    """``values`` (S,) each replaced by ``reduce`` (``np.maximum`` or ``np.minimum``) over
    the entries of its label in ``labels`` (S,) int."""
    if values.size == 0:
        return values
    _, inverse = np.unique(labels, return_inverse=True)
    best = np.full(inverse.max() + 1, -np.inf if reduce is np.maximum else np.inf)
    reduce.at(best, inverse, values)
    return best[inverse]


def set_cuts(labels: np.ndarray, size: int) -> list[slice]:
    """Consecutive runs of the histories (``labels`` (S,) ascending: each set's histories
    consecutive) of nearly equal length, at most ``size`` unless one set is longer, each
    cut where a set begins."""
    S_ = labels.size
    if S_ <= size:
        return [slice(0, S_)]
    starts = np.flatnonzero(np.concatenate([[True], labels[1:] != labels[:-1]]))
    ideal = np.cumsum([p.size for p in np.array_split(np.arange(S_), -(-S_ // size))])[:-1]
    at = np.searchsorted(starts, ideal)
    cuts = np.unique(np.concatenate([[0], np.where(at < starts.size, starts[at.clip(max=starts.size - 1)], S_), [S_]]))
    return [slice(int(a), int(b)) for a, b in zip(cuts[:-1], cuts[1:]) if b > a]


@dataclass(frozen=True)
class PairsRead:
    """The (history, node) pairs a batch's thresholds read at the sampled steps
    (:meth:`Batch.thresholds`), by ``key`` (:meth:`Batch.pair_key`, ascending): their
    ``von_mises_upper`` (Pa) and fatigue factor ``factor_bound`` (or None) bounds, and
    whether each was evaluated exactly for the ``peak`` and for ``fatigue`` (its exact
    value is then in the thresholds)."""

    key: np.ndarray
    von_mises_upper: np.ndarray
    factor_bound: np.ndarray | None
    peak: np.ndarray
    fatigue: np.ndarray

    def find(self, keys: np.ndarray) -> np.ndarray:
        """(q,) the index of each of ``keys`` among the pairs read, -1 where not read."""
        if not self.key.size:
            return np.full(keys.size, -1)
        at = np.searchsorted(self.key, keys).clip(max=self.key.size - 1)
        return np.where(self.key[at] == keys, at, -1)


def can_beat(b: SampledBounds, low, top, factor=None, enough: float | None = None, bound=None) -> np.ndarray:
    """bool, one per node (or pair) of the bounds ``b``: whether its von Mises bound can
    reach ``low`` (Pa, a lower bound of the peak: an exact value at some node) or, with a
    ``factor`` (sa, sm) -> safety factor, its fatigue factor's lower bound (``bound``,
    when already known) can fall to ``top`` (an upper bound of the minimum) and below
    ``enough`` (:func:`fatigue_may_pass`). ``low`` and ``top`` broadcast against the nodes;
    both comparisons widened by :data:`tuning.SLACK` (rounding)."""
    keep = peak_may_pass(b.von_mises_upper, low)
    if factor is not None:
        keep |= fatigue_may_pass(factor(*fatigue_bounds(b)) if bound is None else bound, top, enough)
    return keep


def peak_may_pass(upper: np.ndarray, low) -> np.ndarray:
    """bool: whether a von Mises bound ``upper`` (Pa) can reach ``low`` (a lower bound of
    the peak: an exact value at some node), widened by :data:`tuning.SLACK` (rounding)."""
    return upper * (1.0 + tuning.SLACK) >= low


def fatigue_may_pass(bound: np.ndarray, top, enough: float | None = None) -> np.ndarray:
    """bool: whether a fatigue factor's lower bound ``bound`` can fall to ``top`` (an
    upper bound of the minimum) and, with ``enough`` (a factor beyond which the exact
    value does not matter, :func:`fatigue_min`), below it; widened by :data:`tuning.SLACK`."""
    can = bound <= top * (1.0 + tuning.SLACK)
    if enough is not None:
        can &= bound < enough * (1.0 + tuning.SLACK)
    return can


def first_per_row(values: np.ndarray, count: int, largest: bool) -> np.ndarray:
    """(s, min(count, n)): the column indices of each row's ``count`` largest (or
    smallest) ``values`` (s, n), in no order."""
    key = -values if largest else values
    if key.shape[1] <= count:
        return np.broadcast_to(np.arange(key.shape[1]), key.shape).copy()
    return np.argpartition(key, count - 1, axis=1)[:, :count]


def box_union(lo: np.ndarray, hi: np.ndarray, scale: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((1, k), (1, k)): the box holding every box ``lo`` to ``hi`` (s, k) scaled by its
    ``scale`` (s,) > 0 (a history scaled by a positive factor has its box scaled)."""
    return (lo * scale[:, None]).min(axis=0, keepdims=True), (hi * scale[:, None]).max(axis=0, keepdims=True)


def group_thresholds(
    screen: Screen, C: np.ndarray, group: CoefficientBox, lo: np.ndarray, hi: np.ndarray, factor=None
) -> tuple[np.ndarray, np.ndarray]:
    """((S,) Pa, (S,)): for each history of ``C`` (S, T, k) its exact largest von Mises and
    (with a ``factor``) smallest fatigue factor over a few nodes, every step: a lower bound
    of its peak and an upper bound of its fatigue minimum (else inf). The nodes: the
    :data:`tuning.GROUP_CANDIDATES` of best bound (each criterion) over the union of the
    histories' boxes (``lo``, ``hi`` (S, k) in ``group``'s basis) each scaled to the same
    largest corner, the group's common shape."""
    corner = np.linalg.norm(np.maximum(np.abs(lo), np.abs(hi)), axis=1)
    loaded = corner > 0
    shape = group.box_of(*box_union(lo[loaded], hi[loaded], 1.0 / corner[loaded]))[0]
    nodes = first_nodes(shape.von_mises_upper, count=tuning.GROUP_CANDIDATES)
    if factor is not None:
        bound = factor(*fatigue_bounds(shape))
        nodes = np.union1d(nodes, first_nodes(bound, largest=False, count=tuning.GROUP_CANDIDATES))
    vm2, top = exact_at(screen, nodes, C, factor)
    return np.sqrt(vm2), top


def group_nodes(
    group: CoefficientBox,
    lo: np.ndarray,
    hi: np.ndarray,
    low: np.ndarray,
    top: np.ndarray,
    factor=None,
    mean: np.ndarray | None = None,
) -> np.ndarray:
    """The nodes (ascending) that can hold some history's von Mises peak or fatigue
    minimum: each history's box (``lo``, ``hi`` (S, k)) scaled by 1 / its peak's lower
    bound ``low`` (S,) Pa (a node that cannot reach 1 cannot reach that history's peak)
    and, for fatigue, by its minimum's upper bound ``top`` (S,) (the factor is homogeneous
    of degree -1 in the stresses: a node whose factor cannot fall to 1 cannot fall to that
    history's minimum); one box holds all the scaled ones and bounds every node at once.
    With the histories' means ``mean`` (S, k) the midranges are bounded by their own
    boxes (:func:`railcheck.fea.screening.bounds.midrange_box`), scaled and joined alike. Every node
    where a loaded history has no positive finite threshold (no stress at the
    candidates)."""
    loaded = np.any(lo != 0.0, axis=1) | np.any(hi != 0.0, axis=1)
    every = np.arange(group.nodes)
    if not np.all((low[loaded] > 0) & np.isfinite(low[loaded])):
        return every
    boxes = [box_union(lo[loaded], hi[loaded], 1.0 / low[loaded])]
    if factor is not None:
        if not np.all((top[loaded] > 0) & np.isfinite(top[loaded])):
            return every
        boxes.append(box_union(lo[loaded], hi[loaded], top[loaded]))
    if factor is not None and mean is not None:
        # each history's midrange box scaled as its box: their union holds every midrange
        boxes.append(box_union(*midrange_box(lo[loaded], hi[loaded], mean[loaded]), top[loaded]))
    mid, reach = group.products(*(np.concatenate([b[i] for b in boxes]) for i in (0, 1)))  # one pass over the rows
    keep = von_mises_interval_bound(mid[0], reach[0], axis=0) * (1.0 + tuning.SLACK) >= 1.0
    if factor is not None:
        fatigue = SampledBounds.box(None, mid[1], reach[1])  # type: ignore[arg-type]
        if mean is None:
            keep |= factor(*fatigue_bounds(fatigue)) <= 1.0 + tuning.SLACK
        else:
            keep |= factor(*fatigue_bounds_by_midranges(fatigue, mid[2], reach[2])) <= 1.0 + tuning.SLACK
    return np.flatnonzero(keep)


def restricted_screen(screen: Screen, nodes: np.ndarray) -> Screen:
    """The many-coefficient ``screen`` at ``nodes`` only (its bounds computed there on first use)."""
    return dataclasses.replace(screen, stress=np.ascontiguousarray(screen.stress[:, nodes]), known_bounds=None)
