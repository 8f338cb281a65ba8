"""The FE side of the rig sweep: each part's unit fields for every bolt-hole pair its
joint can use (one mesh, one factorisation, one multi-column solve), and the cycle's
von Mises peak, fatigue factor and tip deflection of many settings at once.

Exact screening. For a setting with coefficient history ``c(t)`` (steps, k):

* Two coefficients (the clamped rails): von Mises at node n is ``sqrt(c^T Q_n c) <=
  sqrt(lam_n) |c|`` (``lam_n`` the largest eigenvalue of ``Q_n``); a few nodes of largest
  ``lam_n`` give a lower bound ``L`` of the peak and only nodes with ``sqrt(lam_n) max|c|
  >= L`` are evaluated. Fatigue: an ellipse holds the history, which bounds each
  component's half-range and midrange; the ranges are the cycle polygon's support function.
* More coefficients (free bodies: pins, pin pressures, inertia fields, modes): first the
  group of settings that share a hole pair drops the nodes that can matter to none of
  them (:func:`_group_nodes`: each history scaled by its thresholds from a few nodes
  evaluated exactly, one box over all of them; 1.4% of the crank rail's nodes remain on
  short-crank settings, 53% of PF_4b_006's). The histories are then boxed together, in one basis of
  their coefficients (:class:`railcheck.fea.screening.box.CoefficientBox`: every node's von Mises
  and component ranges over all steps bounded by two float32 matrix products, and the
  midranges by two more, of the box between each history's mean and its box's ends
  (:func:`railcheck.fea.screening.bounds.midrange_box`: a link swings about a small mean, where the
  box alone bounds the midrange 6-16x too high and fatigue kept 5x the nodes von Mises
  kept)); each
  history is then split into its principal subspace and a residual (``c_t = P a_t +
  e_t``; :mod:`railcheck.fea.screening`). The nodes of best box bound, read at steps placed
  along the history's path, give exact thresholds (a lower bound of the peak, an upper
  bound of the fatigue minimum); only the nodes whose group box (with the values the
  history takes) can beat them are read at those steps (a pair the thresholds read keeps
  its bounds, and one they evaluated is not evaluated again), whose bounds leave the few
  that are evaluated at every step. The group's histories go through these stages together
  (:class:`_Batch`: every stage on (history, node) pairs, one matrix product per history
  where nodes are read); a history whose group box keeps more than
  :data:`LOOSE_SHARE` of the nodes is screened alone, in its own subspace's box first
  (:func:`_screened`). A many-coefficient history of a real setting lies close to a few
  directions, so a few thousand of 10,000-30,000 nodes are read and a few to a few
  hundred evaluated at every step.
* A group's histories often span fewer dimensions than they have coefficients: a free
  body's equilibrium ties three of them, and the settings of a group share a bar (a link
  rail's 17 coefficients span 10-12, PF_4b_006's 18 span 15). The group is then boxed
  and read in r of its coefficients, the rest combinations of them
  (:func:`railcheck.fea.screening.span.history_span`; :func:`_group_box`, :func:`_in_span`):
  every bound over the nodes is r columns wide instead of k. Each history's residual
  outside the span is measured and at most 1e-13 of its size, far inside the bounds'
  :data:`SLACK`; the exact values are still taken in all k coefficients (:class:`_Exact`),
  so the results are bit for bit those without the span, however the settings were
  grouped (captured whole-rig calls and the whole rig's tables: equal).
* One setting's load sources on copies of a part (PF_4b_006 at two joints) are one set
  (:func:`peak_and_fatigue` ``sets``): only the set's worst value is reported, so an exact
  value at any of its histories is a threshold for all of them.

The results equal evaluating every verdict node (:func:`railcheck.model.cycle.evaluate_cycle`)
to rounding. All arrays SI (Pa, m); vectorised over settings, steps and nodes, in chunks
bounded by :data:`CHUNK_VALUES`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fatigue import safety_factor
from ..hull import hull_polygon
from . import tuning
from .batch import Batch, ExactSource, box_and_factor
from .bounds import basis_trial_nodes, box_basis_and_coordinates
from .box import CoefficientBox
from .exact import ellipse_fatigue_bounds, enclosing_ellipse, exact_von_mises2, fatigue_exact
from .passes import fatigue_may_pass, group_nodes, group_thresholds, over_sets, peak_may_pass, restricted_screen, set_cuts
from .screens import Screen, value_slices
from .span import Span, history_span
from .subspace import applies


def von_mises_peak(screen: Screen, C: np.ndarray) -> np.ndarray:
    """(S,) Pa: the largest von Mises over the verdict nodes and steps of each setting's
    history ``C`` (S, T, k): histories of more than two coefficients screened in their own
    principal subspace (:func:`screened_alone`) or, a few steps, read whole; two by the nodes'
    eigenvalue bound."""
    S_, T, k = C.shape
    if k > 2:
        if applies(T, k):
            return screened_group(screen, C)[:, 0]
        every = np.arange(screen.stress.shape[1])
        return np.sqrt(np.array([exact_von_mises2(screen, every, c) for c in C]))
    C = C * screen.scale if screen.scale is not None else C  # the coefficients of Q
    CC = (C[..., :, None] * C[..., None, :]).reshape(S_, T, k * k)
    R2 = np.einsum("stk,stk->st", C, C).max(axis=1)
    assert screen.forms is not None  # two coefficients: the screen has its quadratic forms
    top = screen.bounds.by_form_bound[: tuning.TOP_NODES]
    L2 = np.zeros(S_)
    for g in value_slices(S_, top.size * T):
        vm2 = screen.forms[top] @ CC[g].reshape(-1, k * k).T
        L2[g] = vm2.reshape(top.size, -1, T).max(axis=(0, 2))
    best = L2.copy()
    can = screen.bounds.form_bound[:, None] * R2[None, :] * (1.0 + tuning.SLACK) >= L2[None, :]  # (n, S)
    for g in value_slices(S_, max(1, int(can.sum(axis=0).max())) * T):
        nodes = np.flatnonzero(can[:, g].any(axis=1))
        if nodes.size:
            vm2 = screen.forms[nodes] @ CC[g].reshape(-1, k * k).T
            best[g] = np.maximum(best[g], vm2.reshape(nodes.size, -1, T).max(axis=(0, 2)))
    return np.sqrt(np.maximum(best, 0.0))


def peak_and_fatigue(
    screen: Screen,
    C: np.ndarray,
    endurance: float,
    ultimate: float,
    criterion: str,
    yield_strength: float | None,
    enough: float | None = None,
    sets: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """(:func:`von_mises_peak`, :func:`fatigue_min`) of the histories ``C`` (S, T, k), each
    (S,); a many-coefficient history's screens computed once for both.

    ``sets`` (S,) int: histories of one label are one setting's load sources on copies of
    the part (PF_4b_006 at two joints), of which only the largest peak and the smallest
    factor matter. Each history's results are then its set's (the exact peak and minimum
    over the set's histories), and an exact value found for one history is a threshold
    for every history of its set: a weaker source's nodes that cannot reach its set's
    peak are never read. None: every history its own set."""
    S_, T, k = C.shape
    labels = np.arange(S_) if sets is None else np.asarray(sets)
    if not applies(T, k):
        vm = von_mises_peak(screen, C)
        least = fatigue_min(screen, C, endurance, ultimate, criterion, yield_strength, enough)
        return over_sets(vm, labels, np.maximum), over_sets(least, labels, np.minimum)
    factor = lambda sa, sm: safety_factor(sa, sm, endurance, ultimate, criterion, yield_strength)  # noqa: E731
    order = np.argsort(labels, kind="stable")  # each set's histories consecutive
    out = np.empty((S_, 2))
    out[order] = screened_group(screen, C[order], factor, enough, labels[order])
    return out[:, 0], out[:, 1]


def screened_group(
    screen: Screen, C: np.ndarray, factor=None, enough: float | None = None, labels: np.ndarray | None = None
) -> np.ndarray:
    """(S, 2): the exact von Mises peak (Pa) and fatigue minimum of each history of ``C``
    (S, T, k) (unscaled), in consecutive groups of at most :data:`tuning.GROUP_MOST` histories:
    the box bounds of a group's histories from one
    :class:`railcheck.fea.screening.box.CoefficientBox` over only the nodes that can matter to
    some history of the group (:func:`group_nodes`), then screened together in batches
    of at most :data:`tuning.BATCH_PAIRS` nodes x histories (:class:`Batch`). ``labels`` (S,)
    ascending: the histories' sets (:func:`peak_and_fatigue`; None: each its own), never
    split between groups or batches; each history's results are its set's."""
    labels = np.arange(C.shape[0]) if labels is None else labels
    if C.shape[0] > tuning.GROUP_MOST:  # consecutive groups of nearly equal size
        return np.concatenate(
            [screened_group(screen, C[p], factor, enough, labels[p]) for p in set_cuts(labels, tuning.GROUP_MOST)]
        )
    out = np.empty((C.shape[0], 2))
    if not np.any(C):
        out[:] = 0.0, np.inf
        return out
    Cs = C * screen.scale
    span = history_span(Cs)
    Cr = None if span is None else Cs[..., span.index]  # (s, T, r) the independent scaled coefficients
    group, coordinates = group_box(screen, C, span, Cr)
    lo, hi, taken = group.ranges_and_taken(C, coordinates)
    low, top = group_thresholds(screen, C, group, lo, hi, factor)
    low, top = over_sets(low, labels, np.maximum), over_sets(top, labels, np.minimum)  # exact values of the set
    # (S, k) each history's mean in the basis (linear: the basis of the coefficients' mean),
    # which bounds its midranges; the rounding of either order is within midrange_box's widening
    mean = group.coordinates(C.mean(axis=1, keepdims=True))[:, 0] if factor is not None else None
    nodes = group_nodes(group, lo, hi, low, top, factor, mean)
    loose = tuning.LOOSE_SHARE * screen.stress.shape[1]  # of the part's nodes
    restrict = nodes.size < tuning.GROUP_SHARE * screen.stress.shape[1]
    if restrict:
        screen, group = restricted_screen(screen, nodes), group.restricted(nodes)
    exact: ExactSource | None = None
    if span is not None:  # bounded in the span's independent coefficients from here on, evaluated in all k
        by_node_k = np.ascontiguousarray(screen.stress.transpose(1, 0, 2))
        exact = ExactSource(screen, by_node_k, C)
        assert Cr is not None  # taken with the span
        screen, C = in_span(screen, span), Cr
    bounds = GroupBounds(group, taken, lo, hi, mean, low, top)
    out[:] = batched(screen, C, bounds, factor, enough, labels, exact, loose)
    return np.stack([over_sets(out[:, 0], labels, np.maximum), over_sets(out[:, 1], labels, np.minimum)], axis=1)


@dataclass(frozen=True)
class GroupBounds:
    """What a group's first pass found, per history (s,): the group's box ``group``, the
    coordinates ``taken`` (s, p, k) at a few steps, their ranges ``lo``, ``hi`` (s, k),
    their means ``mean`` (s, k) (fatigue only, else None), and the thresholds ``low`` (a
    lower bound of the peak, Pa) and ``top`` (an upper bound of the fatigue minimum)."""

    group: CoefficientBox
    taken: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    mean: np.ndarray | None
    low: np.ndarray
    top: np.ndarray


def batched(
    screen: Screen, C: np.ndarray, b: GroupBounds, factor, enough, labels: np.ndarray, exact, loose: float
) -> np.ndarray:
    """(s, 2): each history's exact peak (Pa) and fatigue minimum, its group's histories
    screened together in batches of at most :data:`tuning.BATCH_PAIRS` nodes x histories
    (:class:`Batch`), a set never split; a history none of whose nodes can pass its set's
    thresholds takes them as its values, an unloaded one (0, inf)."""
    by_node = np.ascontiguousarray(screen.stress.transpose(1, 0, 2))  # (n, 6, k): a node's rows together
    loaded = np.flatnonzero(np.any(C != 0.0, axis=(1, 2)))
    out = np.empty((C.shape[0], 2))
    out[:] = 0.0, np.inf  # an unloaded history: no stress anywhere
    size = max(1, tuning.BATCH_PAIRS // screen.stress.shape[1])
    low, top = b.low, b.top
    for run in set_cuts(labels[loaded], size):
        g = loaded[run]
        mean = None if b.mean is None else b.mean[g]
        vm, mid, reach, box_factor = box_and_factor(b.group, b.lo[g], b.hi[g], mean, factor)
        peak_can = peak_may_pass(vm, low[g][:, None])
        fatigue_can = fatigue_may_pass(box_factor, top[g][:, None], enough) if box_factor is not None else None
        # a history none of whose nodes can pass its set's thresholds has them as its values
        live = (peak_can | fatigue_can if fatigue_can is not None else peak_can).any(axis=1)
        out[g[~live], 0], out[g[~live], 1] = low[g[~live]], top[g[~live]]
        if not live.any():
            continue
        some = None if exact is None else exact.of(g[live])
        batch = Batch(screen, by_node, b.group, C[g[live]], b.taken[g[live]], factor, enough, labels[g[live]], some)
        can = (peak_can[live], None if fatigue_can is None else fatigue_can[live])
        box_factor = None if box_factor is None else box_factor[live]
        out[g[live]] = batch.screened(
            vm[live], mid[live], reach[live], box_factor, can, low[g[live]] ** 2, top[g[live]], loose
        )
    return out


def group_box(
    screen: Screen, C: np.ndarray, span: Span | None, Cr: np.ndarray | None = None
) -> tuple[CoefficientBox, np.ndarray]:
    """(box, coordinates (s, T, r)): the group's :class:`railcheck.fea.screening.box.CoefficientBox`
    over every node of ``screen`` for its histories ``C`` (s, T, k), in the basis
    :func:`railcheck.fea.screening.bounds.box_basis_and_coordinates` chooses, and their coordinates
    in it. With a ``span`` (:func:`railcheck.fea.screening.span.history_span`) the basis is chosen
    among the span's r independent coefficients and their principal axes, and the box is
    r columns wide; ``Cr`` (s, T, r) the histories' independent scaled coefficients, when
    already taken."""
    if span is None:
        basis, coordinates = box_basis_and_coordinates(screen.stress, screen.scale, C, screen.trial)
        return CoefficientBox(screen.stress, screen.scale, basis), coordinates
    per_unit = span.basis / screen.scale[:, None]  # (k, r): stress per unit independent scaled coefficient
    trial = screen.trial if screen.trial is not None else basis_trial_nodes(screen.stress)
    trial = np.ascontiguousarray(trial @ per_unit)
    axes, coordinates = box_basis_and_coordinates(
        trial, np.ones(span.index.size), (C * screen.scale)[..., span.index] if Cr is None else Cr, trial
    )
    basis, dual = (span.basis, span.dual) if axes is None else (span.basis @ axes, span.dual @ axes)
    return CoefficientBox(screen.stress, screen.scale, basis, dual), coordinates


def in_span(screen: Screen, span: Span) -> Screen:
    """The many-coefficient ``screen`` in the span's r independent scaled coefficients
    (:class:`railcheck.fea.screening.span.Span`): its stresses per unit of each (Pa), their scale
    1 (its bounds computed on first use)."""
    per_unit = span.basis / screen.scale[:, None]
    return Screen(np.ascontiguousarray(screen.stress @ per_unit), None, screen.tip @ per_unit, np.ones(span.index.size))


def fatigue_min(
    screen: Screen,
    C: np.ndarray,
    endurance: float,
    ultimate: float,
    criterion: str,
    yield_strength: float | None,
    enough: float | None = None,
) -> np.ndarray:
    """(S,) the smallest fatigue safety factor over the verdict nodes of each history
    ``C`` (S, T, k) (component ranges over all steps; :mod:`railcheck.fea.fatigue`).

    ``enough``: a factor beyond which the exact value does not matter (a search that only
    asks whether a part passes). Nodes whose bound is above it are not evaluated, so a
    result below ``enough`` is exact and a result at or above it only says so (it is then
    an upper estimate of the exact minimum, itself at least ``enough``)."""

    factor = lambda sa, sm: safety_factor(sa, sm, endurance, ultimate, criterion, yield_strength)  # noqa: E731
    S_, T, k = C.shape
    if applies(T, k):
        return screened_group(screen, C, factor, enough)[:, 1]
    polygons = [hull_polygon(c) for c in C] if screen.angle is not None else None  # once per history
    best = fatigue_exact(screen, screen.bounds.by_alternating_factor[: tuning.TOP_NODES], C, factor, polygons)
    c0, E = enclosing_ellipse(C)
    n = screen.stress.shape[1]
    for g in value_slices(S_, 12 * n):
        bound = factor(*ellipse_fatigue_bounds(screen.stress, c0[g], E[g]))  # (n, s)
        can = fatigue_may_pass(bound, best[g][None, :], enough)
        for h in value_slices(can.shape[1], 6 * max(1, int(can.sum(axis=0).max())) * T):
            nodes = np.flatnonzero(can[:, h].any(axis=1))
            if nodes.size:
                sub = np.arange(S_)[g][h]
                some = [polygons[i] for i in sub] if polygons is not None else None
                best[sub] = np.minimum(best[sub], fatigue_exact(screen, nodes, C[sub], factor, some))
    return best
