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
  their coefficients (:class:`railcheck.fea.screen.CoefficientBox`: every node's von Mises
  and component ranges over all steps bounded by two float32 matrix products, and the
  midranges by two more, of the box between each history's mean and its box's ends
  (:func:`railcheck.fea.screen.midrange_box`: a link swings about a small mean, where the
  box alone bounds the midrange 6-16x too high and fatigue kept 5x the nodes von Mises
  kept)); each
  history is then split into its principal subspace and a residual (``c_t = P a_t +
  e_t``; :mod:`railcheck.fea.screen`). The nodes of best box bound, read at steps placed
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
  (:func:`railcheck.fea.screen.history_span`; :func:`_group_box`, :func:`_in_span`):
  every bound over the nodes is r columns wide instead of k. Each history's residual
  outside the span is measured and at most 1e-13 of its size, far inside the bounds'
  :data:`SLACK`; the exact values are still taken in all k coefficients (:class:`_Exact`),
  so the results are bit for bit those without the span, however the settings were
  grouped (captured whole-rig calls and the whole rig's tables: equal).
* One setting's load sources on copies of a part (PF_4b_006 at two joints) are one set
  (:func:`peak_and_fatigue` ``sets``): only the set's worst value is reported, so an exact
  value at any of its histories is a threshold for all of them.

The results equal evaluating every verdict node (:func:`railcheck.check.cycle.evaluate_cycle`)
to rounding. All arrays SI (Pa, m); vectorised over settings, steps and nodes, in chunks
bounded by :data:`CHUNK_VALUES`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from railcheck.fea import screen as screen_
from railcheck.fea.fatigue import alternating_and_mean, safety_factor
from railcheck.fea.invariants import von_mises_squared
from railcheck.fea.superpose import VM_QUADRATIC, candidate_steps, hull_applies, hull_polygon, support

CHUNK_VALUES = 8_000_000  # floats per temporary (nodes x settings x steps)
#: floats per temporary of the exact evaluations at every step (6 x nodes x histories x
#: steps: :func:`_exact_at`, :meth:`_Batch.exact`, :func:`_exact_von_mises2`), 2 MB: each
#: product's result is read again for von Mises and the extremes while in cache (captured
#: PF_4b_006 calls, one thread, six alternating rounds: 2.18 s against 2.43 s at
#: :data:`CHUNK_VALUES`; a group's thresholds at 16 nodes x 64 histories: 14.6 against
#: 28.7 ms)
EXACT_VALUES = 1 << 18
TOP_NODES = 64  # nodes evaluated first for the lower bound
SLACK = 1e-9  # relative margin on the bounds (rounding)
#: nodes of best box bound (per criterion) read at the sampled steps, whose best sampled
#: values are then evaluated exactly for the thresholds (many coefficients)
BOX_FIRST = 128
#: of those, the nodes of best sampled value (each criterion) evaluated exactly for a batch's
#: thresholds (40 captured calls, 2,702 histories, one thread, medians of five alternating
#: rounds: 8 nodes 0.943 of the time of 16, 4 nodes 0.998 of 8; results bit for bit the same)
THRESHOLD_NODES = 8
#: a history whose group box keeps more than this share of the nodes is bounded in its own
#: principal subspace at every node instead (and its thresholds taken again from that box)
LOOSE_SHARE = 0.25
#: nodes of best bound (each criterion) of a group's common shape whose exact values give
#: every history of the group its first thresholds (:func:`_group_thresholds`)
GROUP_CANDIDATES = 8
#: a group's histories are screened on the nodes that can matter to one of them when
#: those are fewer than this share of the part's (:func:`_group_nodes`)
GROUP_SHARE = 0.7
#: histories screened as one group at most (:func:`_screened_group`; a larger group is
#: cut into consecutive ones): the group's box, basis and node restriction are shared by
#: more histories, but their common box is looser (captured crank-rail and PF_4b_006
#: histories, one thread: 6.0 ms per history in groups of 64, 6.5 in groups of 128, 7.4-8.3
#: in one group per hole pair of 600)
GROUP_MOST = 64
#: verdict nodes per slab of a part's fields read by :func:`make_screens` (a rail's: 6 x 128
#: nodes x 89 columns, 0.5 MB, in cache while every hole pair's columns are taken from it)
GATHER_NODES = 128
#: histories x nodes whose box bounds a batch of :func:`_screened_group` holds at once
#: (about 60 bytes each, in float32)
BATCH_PAIRS = 1 << 18


@dataclass(frozen=True)
class ScreenBounds:
    """A screen's bounds per unit coefficient at each of its n nodes: ``lam`` (n,) the
    largest eigenvalue of each node's von Mises quadratic form in the scaled coefficients
    (Pa^2; more than two coefficients: its trace, a bound of it); ``G`` and ``Ga`` (n,) the
    midrange and alternating bound factors of the fatigue screen; ``unit_rows`` (6, n)
    each component's stress per unit scaled coefficient (the norm of its k values over
    ``scale``); ``by_lam`` and ``by_G`` the nodes by decreasing ``lam`` and ``Ga``."""

    lam: np.ndarray
    G: np.ndarray
    Ga: np.ndarray
    unit_rows: np.ndarray
    by_lam: np.ndarray
    by_G: np.ndarray


def screen_bounds(S: np.ndarray, scale: np.ndarray, lam: np.ndarray | None = None) -> ScreenBounds:
    """:class:`ScreenBounds` of the stresses ``S`` (6, n, k) Pa per unit coefficient with
    the coefficients' ``scale`` (k,); ``lam`` when known (two coefficients: the forms'
    eigenvalues), else the trace bound."""
    Sw = S / scale
    lam = screen_.von_mises_norm_bound(Sw) ** 2 if lam is None else lam
    G, Ga = _fatigue_factors(screen_.component_norms(S))
    return ScreenBounds(lam, G, Ga, screen_.component_norms(Sw), np.argsort(-lam), np.argsort(-Ga))


class _FromBounds:
    """A :class:`ScreenBounds` field read as a :class:`Screen`'s own attribute (its
    bounds computed on first use)."""

    def __set_name__(self, owner, name: str) -> None:
        self.name = name

    def __get__(self, screen, owner=None) -> np.ndarray:
        return getattr(screen._bounds(), self.name)


@dataclass(frozen=True)
class Screen:
    """One column set of a part's unit fields, at its verdict nodes: ``stress`` (6, n, k)
    Pa per unit coefficient; ``Q`` (n, k*k) the von Mises quadratic forms in the scaled
    coefficients ``c * scale`` (Pa^2; two coefficients only, else None: a many-coefficient
    history's von Mises is read from the stresses); ``tip`` (3, k) m; ``scale`` (k,) the
    coefficients' scale w; ``bounds`` (:class:`ScreenBounds`: ``lam``, ``G``, ``Ga``,
    ``unit_rows``, ``by_lam``, ``by_G``, read as the screen's own attributes), or None:
    computed on first use. A many-coefficient screen's are mostly never read: a group
    whose histories span fewer dimensions than their coefficients is read in a screen of
    its own (:func:`_in_span`), so the rig's parts skip them (1.8 s of its serial
    preparation)."""

    stress: np.ndarray
    Q: np.ndarray | None
    tip: np.ndarray
    scale: np.ndarray
    bounds: ScreenBounds | None = field(repr=False, default=None)
    angle: np.ndarray | None = field(repr=False, default=None)  # (6, n) arctan2 of each component (k = 2)
    trial: np.ndarray | None = field(repr=False, default=None)  # (6, m, k) screen_.basis_trial_nodes of stress

    def _bounds(self) -> ScreenBounds:
        if self.bounds is None:  # once: a frozen dataclass's cache
            object.__setattr__(self, "bounds", screen_bounds(self.stress, self.scale))
        assert self.bounds is not None
        return self.bounds

    lam = _FromBounds()
    G = _FromBounds()
    Ga = _FromBounds()
    unit_rows = _FromBounds()
    by_lam = _FromBounds()
    by_G = _FromBounds()

    @property
    def vm_norm(self) -> np.ndarray:
        """(n,) a bound of each node's von Mises per unit scaled coefficient: sqrt(lam)."""
        return np.sqrt(np.maximum(self.lam, 0.0))


def make_screen(stress: np.ndarray, verdict_mask: np.ndarray, tip: np.ndarray, cols: list[int]) -> Screen:
    """Screen of the unit-case columns ``cols`` of ``stress`` (6, nodes, cases) at the
    verdict nodes; ``tip`` (3, cases) m."""
    return make_screens(stress, verdict_mask, {None: tip}, {None: cols})[None]


def make_screens(stress: np.ndarray, verdict_mask: np.ndarray, tips: dict, columns: dict) -> dict:
    """key -> :func:`make_screen` of each key's unit-case columns ``columns[key]`` with
    its tip operator ``tips[key]`` (3, cases) m. The fields are read once, in slabs of
    :data:`GATHER_NODES` verdict nodes, each slab's columns gathered for every key while
    it is in cache: a part's fields have tens to hundreds of columns and each hole pair
    a few of them, so a gather per key streamed them all once per key (a rail's 89
    columns and 16 hole pairs of 17: 0.15-0.2 against 0.38-0.44 s). ``stress`` in any
    memory layout (:func:`_node_slab`)."""
    nodes = np.flatnonzero(_verdict_nodes(verdict_mask))
    index = {key: np.asarray(cols, dtype=np.intp) for key, cols in columns.items()}
    out = {key: np.empty((6, nodes.size, i.size)) for key, i in index.items()}
    for start in range(0, nodes.size, GATHER_NODES):
        slab = _node_slab(stress, nodes[start : start + GATHER_NODES])  # (6, b, cases)
        for key, i in index.items():
            out[key][:, start : start + GATHER_NODES] = np.take(slab, i, axis=2)
    return {key: _screen(out[key], tips[key][:, index[key]]) for key in columns}


def _node_slab(stress: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """(6, b, cases) C-contiguous: ``stress[:, nodes]``. ``np.take`` is the faster gather
    of a C-contiguous array, but of any other it first copies the whole array: freshly
    solved fields are a transposed view of the solver's node-major columns
    (:func:`railcheck.fea.stress.recover_stress`), where a take per slab copied a rail's
    421 MB of fields each time (20.6 against 0.6 s for a rail's screens); such fields are
    indexed slab by slab instead (stored ones are read C-contiguous)."""
    if stress.flags.c_contiguous:
        return np.take(stress, nodes, axis=1)
    return np.ascontiguousarray(stress[:, nodes])


def _verdict_nodes(verdict_mask: np.ndarray) -> np.ndarray:
    """The mask of the nodes a screen reads: the verdict nodes, or every node if none is."""
    return verdict_mask if np.any(verdict_mask) else np.ones_like(verdict_mask)


def _screen(S: np.ndarray, tip: np.ndarray) -> Screen:
    """Screen of the stresses ``S`` (6, n, k) Pa per unit coefficient (contiguous) at the
    verdict nodes and the tip's (3, k) m per unit coefficient."""
    k = S.shape[2]
    # the quadratic forms in scaled coefficients c w (w: each coefficient's largest stress
    # per unit), so the bound sqrt(lam) |c w| is not set by mixing forces, torques and
    # accelerations of very different stress per unit
    w = screen_.column_scale(S)
    trial = screen_.basis_trial_nodes(S)
    if k > 2:  # no k x k forms (k^2 floats per node): the screens read the stresses; bounds on first use
        return Screen(S, None, tip, w, trial=trial)
    Sw = S / w
    Q = np.einsum("cnk,cd,dnl->nkl", Sw, VM_QUADRATIC, Sw, optimize=True)
    bounds = screen_bounds(S, w, np.linalg.eigvalsh(Q)[:, -1])
    angle = np.arctan2(S[..., 1], S[..., 0]) if k == 2 else None
    return Screen(S, Q.reshape(-1, k * k), tip, w, bounds, angle, trial)


def _fatigue_factors(norms: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(G, Ga) (n,): the midrange and alternating bound factors of the fatigue screen
    from each component's norm ``norms`` (6, n) Pa per unit coefficient."""
    shear = 3.0 * (norms[3] ** 2 + norms[4] ** 2 + norms[5] ** 2)
    G = np.sqrt(0.5 * ((norms[0] + norms[1]) ** 2 + (norms[1] + norms[2]) ** 2 + (norms[2] + norms[0]) ** 2) + shear)
    return G, np.sqrt(norms[0] ** 2 + norms[1] ** 2 + norms[2] ** 2 + shear)


def hull_steps(C: np.ndarray) -> np.ndarray:
    """(S, H, k): each history ``C`` (S, T, k) reduced to the vertices of its convex hull
    (padded by repeating a vertex). Every quantity evaluated here is the maximum (or
    minimum) over the cycle of a convex (or linear) function of the coefficients, reached
    at a vertex (:func:`railcheck.fea.superpose.candidate_steps`), so the results are unchanged."""

    if not hull_applies(C.shape[1], C.shape[2]):  # every step is a candidate: no copy
        return C
    steps = [candidate_steps(c) for c in C]
    H = max(s.size for s in steps)
    index = np.stack([np.pad(s, (0, H - s.size), mode="edge") for s in steps])
    return screen_.steps_of(C, index)


def _groups(settings: int, per_setting: int, limit: int = CHUNK_VALUES) -> list[slice]:
    """Consecutive slices of ``settings`` items, each of at most ``limit`` floats at
    ``per_setting`` floats an item (at least one item)."""
    size = max(1, limit // max(per_setting, 1))
    return [slice(i, min(i + size, settings)) for i in range(0, settings, size)]


def von_mises_peak(screen: Screen, C: np.ndarray) -> np.ndarray:
    """(S,) Pa: the largest von Mises over the verdict nodes and steps of each setting's
    history ``C`` (S, T, k): histories of more than two coefficients screened in their own
    principal subspace (:func:`_screened`) or, a few steps, read whole; two by the nodes'
    eigenvalue bound."""
    S_, T, k = C.shape
    if k > 2:
        if screen_.applies(T, k):
            return _screened_group(screen, C)[:, 0]
        every = np.arange(screen.stress.shape[1])
        return np.sqrt(np.array([_exact_von_mises2(screen, every, c) for c in C]))
    C = C * screen.scale if screen.scale is not None else C  # the coefficients of Q
    CC = (C[..., :, None] * C[..., None, :]).reshape(S_, T, k * k)
    R2 = np.einsum("stk,stk->st", C, C).max(axis=1)
    top = screen.by_lam[:TOP_NODES]
    L2 = np.zeros(S_)
    for g in _groups(S_, top.size * T):
        vm2 = screen.Q[top] @ CC[g].reshape(-1, k * k).T
        L2[g] = vm2.reshape(top.size, -1, T).max(axis=(0, 2))
    best = L2.copy()
    can = screen.lam[:, None] * R2[None, :] * (1.0 + SLACK) >= L2[None, :]  # (n, S)
    for g in _groups(S_, max(1, int(can.sum(axis=0).max())) * T):
        nodes = np.flatnonzero(can[:, g].any(axis=1))
        if nodes.size:
            vm2 = screen.Q[nodes] @ CC[g].reshape(-1, k * k).T
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
    if not screen_.applies(T, k):
        vm = von_mises_peak(screen, C)
        factor = fatigue_min(screen, C, endurance, ultimate, criterion, yield_strength, enough)
        return _over_sets(vm, labels, np.maximum), _over_sets(factor, labels, np.minimum)
    factor = lambda sa, sm: safety_factor(sa, sm, endurance, ultimate, criterion, yield_strength)  # noqa: E731
    order = np.argsort(labels, kind="stable")  # each set's histories consecutive
    out = np.empty((S_, 2))
    out[order] = _screened_group(screen, C[order], factor, enough, labels[order])
    return out[:, 0], out[:, 1]


def _over_sets(values: np.ndarray, labels: np.ndarray, reduce) -> np.ndarray:
    """``values`` (S,) each replaced by ``reduce`` (``np.maximum`` or ``np.minimum``) over
    the entries of its label in ``labels`` (S,) int."""
    if values.size == 0:
        return values
    _, inverse = np.unique(labels, return_inverse=True)
    best = np.full(inverse.max() + 1, -np.inf if reduce is np.maximum else np.inf)
    reduce.at(best, inverse, values)
    return best[inverse]


def _set_cuts(labels: np.ndarray, size: int) -> list[slice]:
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


def _screened_group(
    screen: Screen, C: np.ndarray, factor=None, enough: float | None = None, labels: np.ndarray | None = None
) -> np.ndarray:
    """(S, 2): the exact von Mises peak (Pa) and fatigue minimum of each history of ``C``
    (S, T, k) (unscaled), in consecutive groups of at most :data:`GROUP_MOST` histories:
    the box bounds of a group's histories from one
    :class:`railcheck.fea.screen.CoefficientBox` over only the nodes that can matter to
    some history of the group (:func:`_group_nodes`), then screened together in batches
    of at most :data:`BATCH_PAIRS` nodes x histories (:class:`_Batch`). ``labels`` (S,)
    ascending: the histories' sets (:func:`peak_and_fatigue`; None: each its own), never
    split between groups or batches; each history's results are its set's."""
    labels = np.arange(C.shape[0]) if labels is None else labels
    if C.shape[0] > GROUP_MOST:  # consecutive groups of nearly equal size
        return np.concatenate(
            [_screened_group(screen, C[p], factor, enough, labels[p]) for p in _set_cuts(labels, GROUP_MOST)]
        )
    out = np.empty((C.shape[0], 2))
    if not np.any(C):
        out[:] = 0.0, np.inf
        return out
    Cs = C * screen.scale
    span = screen_.history_span(Cs)
    Cr = None if span is None else Cs[..., span.index]  # (s, T, r) the independent scaled coefficients
    group, coordinates = _group_box(screen, C, span, Cr)
    lo, hi, taken = group.ranges_and_taken(C, coordinates)
    low, top = _group_thresholds(screen, C, group, lo, hi, factor)
    low, top = _over_sets(low, labels, np.maximum), _over_sets(top, labels, np.minimum)  # exact values of the set
    # (S, k) each history's mean in the basis (linear: the basis of the coefficients' mean),
    # which bounds its midranges; the rounding of either order is within midrange_box's widening
    mean = group.coordinates(C.mean(axis=1, keepdims=True))[:, 0] if factor is not None else None
    nodes = _group_nodes(group, lo, hi, low, top, factor, mean)
    loose = LOOSE_SHARE * screen.stress.shape[1]  # of the part's nodes
    restrict = nodes.size < GROUP_SHARE * screen.stress.shape[1]
    if restrict:
        screen, group = _restricted(screen, nodes), group.restricted(nodes)
    exact = None
    if span is not None:  # bounded in the span's independent coefficients from here on, evaluated in all k
        by_node_k = np.ascontiguousarray(screen.stress.transpose(1, 0, 2))
        exact = _Exact(screen, by_node_k, C)
        screen, C = _in_span(screen, span), Cr
    by_node = np.ascontiguousarray(screen.stress.transpose(1, 0, 2))  # (n, 6, k): a node's rows together
    loaded = np.flatnonzero(np.any(C != 0.0, axis=(1, 2)))
    out[:] = 0.0, np.inf  # an unloaded history: no stress anywhere
    size = max(1, BATCH_PAIRS // screen.stress.shape[1])
    for run in _set_cuts(labels[loaded], size):
        g = loaded[run]
        vm, mid, reach, box_factor = _box_and_factor(group, lo[g], hi[g], None if mean is None else mean[g], factor)
        peak_can = _peak_can(vm, low[g][:, None])
        fatigue_can = _fatigue_can(box_factor, top[g][:, None], enough) if box_factor is not None else None
        # a history none of whose nodes can pass its set's thresholds has them as its values
        live = (peak_can | fatigue_can if fatigue_can is not None else peak_can).any(axis=1)
        out[g[~live], 0], out[g[~live], 1] = low[g[~live]], top[g[~live]]
        if not live.any():
            continue
        some = None if exact is None else exact.of(g[live])
        batch = _Batch(screen, by_node, group, C[g[live]], taken[g[live]], factor, enough, labels[g[live]], some)
        can = (peak_can[live], None if fatigue_can is None else fatigue_can[live])
        box_factor = None if box_factor is None else box_factor[live]
        out[g[live]] = batch.screened(
            vm[live], mid[live], reach[live], box_factor, can, low[g[live]] ** 2, top[g[live]], loose
        )
    return np.stack([_over_sets(out[:, 0], labels, np.maximum), _over_sets(out[:, 1], labels, np.minimum)], axis=1)


def _group_box(
    screen: Screen, C: np.ndarray, span: screen_.Span | None, Cr: np.ndarray | None = None
) -> tuple[screen_.CoefficientBox, np.ndarray]:
    """(box, coordinates (s, T, r)): the group's :class:`railcheck.fea.screen.CoefficientBox`
    over every node of ``screen`` for its histories ``C`` (s, T, k), in the basis
    :func:`railcheck.fea.screen.box_basis_and_coordinates` chooses, and their coordinates
    in it. With a ``span`` (:func:`railcheck.fea.screen.history_span`) the basis is chosen
    among the span's r independent coefficients and their principal axes, and the box is
    r columns wide; ``Cr`` (s, T, r) the histories' independent scaled coefficients, when
    already taken."""
    if span is None:
        basis, coordinates = screen_.box_basis_and_coordinates(screen.stress, screen.scale, C, screen.trial)
        return screen_.CoefficientBox(screen.stress, screen.scale, basis), coordinates
    per_unit = span.basis / screen.scale[:, None]  # (k, r): stress per unit independent scaled coefficient
    trial = screen.trial if screen.trial is not None else screen_.basis_trial_nodes(screen.stress)
    trial = np.ascontiguousarray(trial @ per_unit)
    axes, coordinates = screen_.box_basis_and_coordinates(
        trial, np.ones(span.index.size), (C * screen.scale)[..., span.index] if Cr is None else Cr, trial
    )
    basis, dual = (span.basis, span.dual) if axes is None else (span.basis @ axes, span.dual @ axes)
    return screen_.CoefficientBox(screen.stress, screen.scale, basis, dual), coordinates


def _in_span(screen: Screen, span: screen_.Span) -> Screen:
    """The many-coefficient ``screen`` in the span's r independent scaled coefficients
    (:class:`railcheck.fea.screen.Span`): its stresses per unit of each (Pa), their scale
    1 (its bounds computed on first use)."""
    per_unit = span.basis / screen.scale[:, None]
    return Screen(np.ascontiguousarray(screen.stress @ per_unit), None, screen.tip @ per_unit, np.ones(span.index.size))


@dataclass(frozen=True)
class _Exact:
    """Where a group screened in a span (:func:`_in_span`) takes its exact values: the
    ``screen`` in the original coefficients at the same nodes, its stresses by node
    ``by_node`` (n, 6, k), and the histories ``C`` (s, T, k). Every exact value is then
    the one a group without a span computes, bit for bit: a table does not depend on how
    the settings were grouped (serial or on workers). The bounds, read in the span, are
    those of histories within 1e-13 of these (:data:`railcheck.fea.screen.SPAN_RESIDUAL`),
    far inside the :data:`SLACK` every comparison with an exact value allows."""

    screen: Screen
    by_node: np.ndarray
    C: np.ndarray

    def of(self, histories: np.ndarray) -> _Exact:
        """The same for the ``histories`` (indices) only."""
        return _Exact(self.screen, self.by_node, self.C[histories])


def _box_and_factor(group: screen_.CoefficientBox, lo, hi, mean, factor=None):
    """(vm (s, n), mid (s, 6, n), reach (s, 6, n), factor bound (s, n) or None) float32:
    the box bounds of histories whose basis coordinates range over ``lo`` to ``hi`` (s,
    k), and with a ``factor`` its lower bound with the midranges bounded by the histories'
    means ``mean`` (s, k) (:func:`railcheck.fea.screen.midrange_box`): the boxes and the
    midrange boxes in one pass over the group's rows."""
    s = lo.shape[0]
    if factor is None:  # (and ``mean`` None: the means are only taken for fatigue)
        vm, mid, reach = group.box_arrays(lo, hi)
        return vm, mid, reach, None
    m_lo, m_hi = screen_.midrange_box(lo, hi, mean)
    mid, reach = group.products(np.concatenate([lo, m_lo]), np.concatenate([hi, m_hi]))
    vm = screen_.von_mises_interval_bound(mid[:s], reach[:s], axis=1)
    box = screen_.SampledBounds.box(vm, _by_component(mid[:s]), _by_component(reach[:s]))
    bound = factor(*screen_.fatigue_bounds_by_midranges(box, _by_component(mid[s:]), _by_component(reach[s:])))
    return vm, mid[:s], reach[:s], bound


def _by_component(a: np.ndarray) -> np.ndarray:
    """(6, s, n) view of (s, 6, n) bounds."""
    return a.transpose(1, 0, 2)


class _Batch:
    """Histories ``C`` (s, T, k) (unscaled) of one group screened together: every stage
    of :func:`_screened` on (history, node) pairs at once, in the histories' principal
    subspaces (:func:`railcheck.fea.screen.principal_subspaces`); the exact values per
    history. ``by_node`` (n, 6, k) the screen's stresses grouped by node; ``group`` the
    group's box and ``taken`` (s, p, k) each history's coordinates at a few steps in its
    basis (:meth:`railcheck.fea.screen.CoefficientBox.ranges_and_taken`); ``labels`` (s,)
    ascending the histories' sets (:func:`peak_and_fatigue`); ``exact`` where the exact
    values are taken (:class:`_Exact`; None: ``screen``, ``by_node`` and ``C``). Pa
    throughout."""

    def __init__(
        self,
        screen: Screen,
        by_node: np.ndarray,
        group,
        C: np.ndarray,
        taken: np.ndarray,
        factor,
        enough,
        labels: np.ndarray,
        exact: _Exact | None = None,
    ):
        self.screen, self.by_node, self.group, self.C, self.taken = screen, by_node, group, C, taken
        self.factor, self.enough, self.labels = factor, enough, labels
        self.at = _Exact(screen, by_node, C) if exact is None else exact  # where exact values are taken
        self.sub = screen_.principal_subspaces(screen_.scaled(C, screen.scale))
        self.Pw = self.sub.P / screen.scale[None, :, None]  # (s, k, R) per unit coefficient

    def pair_key(self, h: np.ndarray, nodes: np.ndarray) -> np.ndarray:
        """(q,) one integer per (history, node) pair, ordered by history then node."""
        return h * self.by_node.shape[0] + nodes

    def fatigue_bound(self, b: screen_.SampledBounds) -> np.ndarray | None:
        """The lower bound of the fatigue factor from bounds ``b``, or None (no fatigue)."""
        return self.factor(*screen_.fatigue_bounds(b)) if self.factor is not None else None

    def beats(self, b: screen_.SampledBounds, h: np.ndarray, low2: np.ndarray, top: np.ndarray, bound=None) -> np.ndarray:
        """(q,) bool: the pairs (histories ``h``) whose bounds ``b`` can reach their
        history's peak lower bound ``sqrt(low2)`` or fatigue upper bound ``top`` (s,)
        (``bound``: their fatigue factor's lower bound, when already known)."""
        return _can_beat(b, np.sqrt(low2)[h], top[h], self.factor, self.enough, bound)

    def projected(self, h: np.ndarray, nodes: np.ndarray) -> np.ndarray:
        """(q, 6, R) Pa per unit subspace coordinate of each pair's history (``h`` ascending)."""
        k, R = self.Pw.shape[1:]
        SP = np.empty((h.size, 6, R))
        for i, start, stop in screen_.history_blocks(h):
            SP[start:stop] = (self.by_node[nodes[start:stop]].reshape(-1, k) @ self.Pw[i]).reshape(-1, 6, R)
        return SP

    def sampled(self, SP: np.ndarray, h: np.ndarray, nodes: np.ndarray) -> screen_.SampledBounds:
        """:func:`railcheck.fea.screen.sampled_pairs` of each pair (``h`` ascending)."""
        sub, screen = self.sub, self.screen
        at = screen_.steps_of(sub.a, sub.sampled)  # (s, M, R)
        return screen_.sampled_pairs(SP, h, at, sub.delta, sub.eps, screen.unit_rows[:, nodes], screen.vm_norm[nodes])

    def exact(
        self, h: np.ndarray, nodes: np.ndarray, peak: np.ndarray, fatigue: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """((s,) Pa^2, (s,)): each history's largest von Mises squared over every step at
        its pairs' nodes marked ``peak`` (0 if none), and its smallest fatigue factor at
        those marked ``fatigue`` (inf if none; each component's extremes over every
        step). ``h`` (q,) ascending; one product per history (in chunks of
        :data:`EXACT_VALUES`)."""
        s, T, k = self.at.C.shape
        vm2, least = np.zeros(s), np.full(s, np.inf)
        keep = peak | fatigue
        h, nodes, peak, fatigue = h[keep], nodes[keep], peak[keep], fatigue[keep]
        for i, a, b in screen_.history_blocks(h, max(1, EXACT_VALUES // (6 * T))):
            X = (self.at.by_node[nodes[a:b]].reshape(-1, k) @ self.at.C[i].T).reshape(b - a, 6, T)  # node, component, step
            p, f = peak[a:b], fatigue[a:b]
            if p.any():
                vm2[i] = max(vm2[i], float(von_mises_squared(X[p].transpose(1, 0, 2)).max()))
            if f.any():  # the extremes over the steps of every row (contiguous), then the nodes asked
                high, low = X.max(axis=2)[f].T, X.min(axis=2)[f].T
                least[i] = min(least[i], float(self.factor(*alternating_and_mean(high, low)).min()))
        return vm2, least

    def thresholds(
        self, vm: np.ndarray, bound: np.ndarray | None, passable: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, _Read]:
        """((s,) Pa^2, (s,), read): exact values at the :data:`THRESHOLD_NODES` of best
        sampled value among the :data:`BOX_FIRST` of best box bound ``vm`` (von Mises, (s,
        n)) and ``bound`` (fatigue factor) of each history, of those ``passable`` (s, n)
        (whose bounds can pass the thresholds so far: no other node can raise them);
        ``read`` those pairs' sampled bounds and which of them were evaluated exactly
        (:class:`_Read`)."""
        first = _first_per_row(vm, BOX_FIRST, largest=True)
        if bound is not None:
            first = np.concatenate([first, _first_per_row(bound, BOX_FIRST, largest=False)], axis=1)
        first = np.sort(first, axis=1)
        s, F = first.shape
        # each node once, and only those that can pass the thresholds so far (``passable``)
        use = np.ones(first.shape, dtype=bool)
        use[:, 1:] = first[:, 1:] != first[:, :-1]
        use = (use & np.take_along_axis(passable, first, axis=1)).ravel()
        h, nodes = np.repeat(np.arange(s), F)[use], first.ravel()[use]
        b = self.sampled(self.projected(h, nodes), h, nodes)
        best = np.full(s * F, -np.inf)
        best[use] = b.von_mises
        peak = np.zeros((s, F), dtype=bool)
        np.put_along_axis(peak, _first_per_row(best.reshape(s, F), THRESHOLD_NODES, largest=True), True, axis=1)
        fatigue = np.zeros((s, F), dtype=bool)
        factor_bound = None
        if bound is not None:
            f = np.full(s * F, np.inf)
            f[use] = self.factor(*screen_.fatigue_sampled(b))
            np.put_along_axis(fatigue, _first_per_row(f.reshape(s, F), THRESHOLD_NODES, largest=False), True, axis=1)
            factor_bound = self.fatigue_bound(b)
        peak, fatigue = peak.ravel()[use], fatigue.ravel()[use]
        vm2, least = self.exact(h, nodes, peak, fatigue)
        return vm2, least, _Read(self.pair_key(h, nodes), b.von_mises_upper, factor_bound, peak, fatigue)

    def screened(self, vm, mid, reach, box_factor, can, low2, top, loose) -> np.ndarray:
        """(s, 2): each history's exact peak (Pa) and fatigue minimum, from its group box
        bounds ``vm`` (s, n), ``mid`` and ``reach`` (s, 6, n) (float32), their fatigue
        factor's lower bound ``box_factor`` (s, n) (or None), the group's thresholds
        ``low2`` (Pa^2) and ``top`` (s,), and ``can`` the nodes whose bounds can pass them
        ((s, n) bool for the peak and for fatigue, or None without a factor); a history whose group box keeps more than
        ``loose`` nodes is screened alone (:func:`_screened`)."""
        s = self.C.shape[0]
        out = np.empty((s, 2))
        mid6, reach6 = _by_component(mid), _by_component(reach)
        # the thresholds are taken at nodes that can pass the group's (no other can raise them)
        first_vm = np.where(can[0], vm, -np.inf)
        first_factor = None if box_factor is None else np.where(can[1], box_factor, np.inf)
        passable = can[0] if can[1] is None else can[0] | can[1]
        more_low2, less_top, read = self.thresholds(first_vm, first_factor, passable)
        low2, top = np.maximum(low2, more_low2), np.minimum(top, less_top)  # each an exact value at some node
        low2, top = _over_sets(low2, self.labels, np.maximum), _over_sets(top, self.labels, np.minimum)  # of the set
        every = np.arange(s)
        keep = self.beats(screen_.SampledBounds.box(vm, mid6, reach6), every[:, None], low2, top, box_factor)
        h, nodes = np.nonzero(keep)
        if self.factor is not None and h.size:
            # the box's midrange bounds from the values each history takes, at these pairs only
            m, r = mid[h, :, nodes], reach[h, :, nodes]  # (q, 6)
            mid_upper = self.group.midrange_at(m, r, nodes, h, self.taken)
            tighter = screen_.SampledBounds.box(vm[h, nodes], m.T, r.T, mid_upper.T)
            kept = self.beats(tighter, h, low2, top)
            h, nodes = h[kept], nodes[kept]
        alone = np.bincount(h, minlength=s) > loose  # the group's box is loose for these
        for i in np.flatnonzero(alone):
            box = screen_.SampledBounds.box(vm[i], mid[i], reach[i])
            tighter_i = lambda some, b, i=i: self.group.at_nodes(b, some, self.taken[i])  # noqa: E731
            exact_i = (self.at.screen, self.at.C[i])
            out[i] = _screened(
                self.screen, self.C[i], box, self.factor, self.enough, low2[i], top[i], loose, tighter_i, exact_i
            )
        h, nodes = h[~alone[h]], nodes[~alone[h]]
        # the pairs the thresholds read keep their sampled bounds; only the others are read
        at = read.find(self.pair_key(h, nodes))
        new = at < 0
        upper, factor_bound = np.empty(h.size), np.empty(h.size)
        upper[~new] = read.von_mises_upper[at[~new]]
        b = self.sampled(self.projected(h[new], nodes[new]), h[new], nodes[new])
        upper[new] = b.von_mises_upper
        peak = _peak_can(upper, np.sqrt(low2)[h])
        fatigue = np.zeros_like(peak)
        if self.factor is not None:
            factor_bound[~new] = read.factor_bound[at[~new]]
            factor_bound[new] = self.fatigue_bound(b)
            fatigue = _fatigue_can(factor_bound, top[h], self.enough)
        # and a pair evaluated exactly for a criterion there is not evaluated again for it
        peak[~new] &= ~read.peak[at[~new]]
        fatigue[~new] &= ~read.fatigue[at[~new]]
        vm2, least = self.exact(h, nodes, peak, fatigue)
        out[~alone, 0] = np.sqrt(np.maximum(low2, vm2))[~alone]
        out[~alone, 1] = np.minimum(top, least)[~alone]
        return out


@dataclass(frozen=True)
class _Read:
    """The (history, node) pairs a batch's thresholds read at the sampled steps
    (:meth:`_Batch.thresholds`), by ``key`` (:meth:`_Batch.pair_key`, ascending): their
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


def _can_beat(b: screen_.SampledBounds, low, top, factor=None, enough: float | None = None, bound=None) -> np.ndarray:
    """bool, one per node (or pair) of the bounds ``b``: whether its von Mises bound can
    reach ``low`` (Pa, a lower bound of the peak: an exact value at some node) or, with a
    ``factor`` (sa, sm) -> safety factor, its fatigue factor's lower bound (``bound``,
    when already known) can fall to ``top`` (an upper bound of the minimum) and below
    ``enough`` (:func:`_fatigue_can`). ``low`` and ``top`` broadcast against the nodes;
    both comparisons widened by :data:`SLACK` (rounding)."""
    keep = _peak_can(b.von_mises_upper, low)
    if factor is not None:
        keep |= _fatigue_can(factor(*screen_.fatigue_bounds(b)) if bound is None else bound, top, enough)
    return keep


def _peak_can(upper: np.ndarray, low) -> np.ndarray:
    """bool: whether a von Mises bound ``upper`` (Pa) can reach ``low`` (a lower bound of
    the peak: an exact value at some node), widened by :data:`SLACK` (rounding)."""
    return upper * (1.0 + SLACK) >= low


def _fatigue_can(bound: np.ndarray, top, enough: float | None = None) -> np.ndarray:
    """bool: whether a fatigue factor's lower bound ``bound`` can fall to ``top`` (an
    upper bound of the minimum) and, with ``enough`` (a factor beyond which the exact
    value does not matter, :func:`fatigue_min`), below it; widened by :data:`SLACK`."""
    can = bound <= top * (1.0 + SLACK)
    if enough is not None:
        can &= bound < enough * (1.0 + SLACK)
    return can


def _first_per_row(values: np.ndarray, count: int, largest: bool) -> np.ndarray:
    """(s, min(count, n)): the column indices of each row's ``count`` largest (or
    smallest) ``values`` (s, n), in no order."""
    key = -values if largest else values
    if key.shape[1] <= count:
        return np.broadcast_to(np.arange(key.shape[1]), key.shape).copy()
    return np.argpartition(key, count - 1, axis=1)[:, :count]


def _union(lo: np.ndarray, hi: np.ndarray, scale: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((1, k), (1, k)): the box holding every box ``lo`` to ``hi`` (s, k) scaled by its
    ``scale`` (s,) > 0 (a history scaled by a positive factor has its box scaled)."""
    return (lo * scale[:, None]).min(axis=0, keepdims=True), (hi * scale[:, None]).max(axis=0, keepdims=True)


def _group_thresholds(
    screen: Screen, C: np.ndarray, group: screen_.CoefficientBox, lo: np.ndarray, hi: np.ndarray, factor=None
) -> tuple[np.ndarray, np.ndarray]:
    """((S,) Pa, (S,)): for each history of ``C`` (S, T, k) its exact largest von Mises and
    (with a ``factor``) smallest fatigue factor over a few nodes, every step: a lower bound
    of its peak and an upper bound of its fatigue minimum (else inf). The nodes: the
    :data:`GROUP_CANDIDATES` of best bound (each criterion) over the union of the
    histories' boxes (``lo``, ``hi`` (S, k) in ``group``'s basis) each scaled to the same
    largest corner, the group's common shape."""
    corner = np.linalg.norm(np.maximum(np.abs(lo), np.abs(hi)), axis=1)
    loaded = corner > 0
    shape = group.box_of(*_union(lo[loaded], hi[loaded], 1.0 / corner[loaded]))[0]
    nodes = screen_.first_nodes(shape.von_mises_upper, count=GROUP_CANDIDATES)
    if factor is not None:
        bound = factor(*screen_.fatigue_bounds(shape))
        nodes = np.union1d(nodes, screen_.first_nodes(bound, largest=False, count=GROUP_CANDIDATES))
    vm2, top = _exact_at(screen, nodes, C, factor)
    return np.sqrt(vm2), top


def _group_nodes(
    group: screen_.CoefficientBox,
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
    boxes (:func:`railcheck.fea.screen.midrange_box`), scaled and joined alike. Every node
    where a loaded history has no positive finite threshold (no stress at the
    candidates)."""
    loaded = np.any(lo != 0.0, axis=1) | np.any(hi != 0.0, axis=1)
    every = np.arange(group.nodes)
    if not np.all((low[loaded] > 0) & np.isfinite(low[loaded])):
        return every
    boxes = [_union(lo[loaded], hi[loaded], 1.0 / low[loaded])]
    if factor is not None:
        if not np.all((top[loaded] > 0) & np.isfinite(top[loaded])):
            return every
        boxes.append(_union(lo[loaded], hi[loaded], top[loaded]))
    if factor is not None and mean is not None:
        # each history's midrange box scaled as its box: their union holds every midrange
        boxes.append(_union(*screen_.midrange_box(lo[loaded], hi[loaded], mean[loaded]), top[loaded]))
    mid, reach = group.products(*(np.concatenate([b[i] for b in boxes]) for i in (0, 1)))  # one pass over the rows
    keep = screen_.von_mises_interval_bound(mid[0], reach[0], axis=0) * (1.0 + SLACK) >= 1.0
    if factor is not None:
        fatigue = screen_.SampledBounds.box(None, mid[1], reach[1])  # type: ignore[arg-type]
        if mean is None:
            keep |= factor(*screen_.fatigue_bounds(fatigue)) <= 1.0 + SLACK
        else:
            keep |= factor(*screen_.fatigue_bounds_by_midranges(fatigue, mid[2], reach[2])) <= 1.0 + SLACK
    return np.flatnonzero(keep)


def _restricted(screen: Screen, nodes: np.ndarray) -> Screen:
    """The many-coefficient ``screen`` at ``nodes`` only (its bounds computed there on first use)."""
    return dataclasses.replace(screen, stress=np.ascontiguousarray(screen.stress[:, nodes]), bounds=None)


def _screened(
    screen: Screen,
    c: np.ndarray,
    box: screen_.SampledBounds,
    factor=None,
    enough: float | None = None,
    low2: float = 0.0,
    top: float = np.inf,
    loose: float | None = None,
    tighter=None,
    exact: tuple[Screen, np.ndarray] | None = None,
) -> tuple[float, float]:
    """(Pa, factor): the exact largest von Mises over the nodes and steps of one history
    ``c`` (T, k) (unscaled coefficients) and, with a ``factor`` (sa, sm) -> safety factor,
    its exact smallest fatigue factor (else inf; ``enough`` as in :func:`fatigue_min`).

    ``box``: every node's bound over all steps from its group's box
    (:class:`railcheck.fea.screen.CoefficientBox`). The :data:`BOX_FIRST` nodes of best box
    bound read at the sampled steps, and the FIRST_NODES of best sampled value among them
    evaluated exactly: the thresholds. Only the nodes whose group box can beat a
    threshold, and then whose box in the history's own principal subspace
    (:func:`railcheck.fea.screen.box_bounds`) can, are read at the sampled steps, and only
    those whose sampled bound can beat it are evaluated at every step. ``tighter``:
    (nodes, box) -> ``box`` at those nodes with its midrange bounds from the values the
    history takes (:meth:`railcheck.fea.screen.CoefficientBox.at_nodes`), applied to the
    nodes the box keeps before they are projected. ``exact``: (screen, history) where the
    exact values are taken, the same nodes in other coefficients (:class:`_Exact`); None:
    ``screen`` and ``c``."""
    if not np.any(c):  # unloaded: no stress anywhere (and no screen to build on a zero box)
        return 0.0, np.inf
    ex_screen, ex_c = (screen, c) if exact is None else exact
    sub = screen_.principal_subspace(c * screen.scale)
    norms, vm_norm = screen.unit_rows, screen.vm_norm

    def projected(nodes):
        return screen_.project(screen.stress[:, nodes], screen.scale, sub)

    def sampled(nodes, SP):
        return screen_.sampled_bounds(SP, norms[:, nodes], vm_norm[nodes], sub)

    def beats(bounds, low2, top, bound=None):
        """Nodes whose bounds can reach the peak's lower bound or the fatigue minimum's
        upper one (``bound``: their fatigue factor's lower bound, when already known)."""
        return _can_beat(bounds, np.sqrt(low2), top, factor, enough, bound)

    def thresholds(bounds, bound):
        """(Pa^2, factor): exact values at the nodes of best sampled value among the
        :data:`BOX_FIRST` of best ``bounds`` (von Mises) and ``bound`` (fatigue factor)."""
        first = screen_.first_nodes(bounds.von_mises_upper, count=BOX_FIRST)
        if factor is not None:
            first = np.union1d(first, screen_.first_nodes(bound, largest=False, count=BOX_FIRST))
        b = sampled(first, projected(first))
        low2 = _exact_von_mises2(ex_screen, first[screen_.first_nodes(b.von_mises)], ex_c)
        if factor is None:
            return low2, np.inf
        f = factor(*screen_.fatigue_sampled(b))
        return low2, _fatigue_exact(ex_screen, first[screen_.first_nodes(f, largest=False)], ex_c[None], factor)[0]

    def fatigue_bound(bounds):
        return factor(*screen_.fatigue_bounds(bounds)) if factor is not None else None

    box_factor = fatigue_bound(box)
    more_low2, less_top = thresholds(box, box_factor)
    low2, top = max(low2, more_low2), min(top, less_top)  # each an exact value at some node
    nodes = np.flatnonzero(beats(box, low2, top, box_factor))
    if tighter is not None and factor is not None and nodes.size:
        # the box's midrange bounds from the values the history takes, at these nodes only
        nodes = nodes[beats(tighter(nodes, box), low2, top)]
    if nodes.size > (LOOSE_SHARE * box.von_mises.size if loose is None else loose):  # the group's box is loose here
        SP = screen_.project(screen.stress, screen.scale, sub)
        own = screen_.box_bounds(SP, norms, vm_norm, sub)
        own_factor = fatigue_bound(own)
        more_low2, less_top = thresholds(own, own_factor)
        low2, top = max(low2, more_low2), min(top, less_top)  # each an exact value at some node
        nodes = np.flatnonzero(beats(own, low2, top, own_factor))
        SP = SP[:, nodes]
    else:
        SP = projected(nodes)
        keep = beats(screen_.box_bounds(SP, norms[:, nodes], vm_norm[nodes], sub), low2, top)
        nodes, SP = nodes[keep], SP[:, keep]
    b = sampled(nodes, SP)
    peak = float(np.sqrt(max(low2, _exact_von_mises2(ex_screen, nodes[screen_.peak_candidates(b, np.sqrt(low2))], ex_c))))
    if factor is None:
        return peak, np.inf
    rest = nodes[_fatigue_can(factor(*screen_.fatigue_bounds(b)), top, enough)]
    return peak, min(float(top), float(_fatigue_exact(ex_screen, rest, ex_c[None], factor)[0])) if rest.size else float(top)


def _exact_von_mises2(screen: Screen, nodes: np.ndarray, c: np.ndarray) -> float:
    """Pa^2: the largest von Mises squared over ``nodes`` and every step of the history
    ``c`` (T, k) (the stresses at every step, in chunks)."""
    best = 0.0
    for g in _groups(nodes.size, 6 * c.shape[0], EXACT_VALUES):
        X = screen.stress[:, nodes[g]] @ c.T  # (6, u, T)
        best = max(best, float(von_mises_squared(X).max()))
    return best


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
    if screen_.applies(T, k):
        return _screened_group(screen, C, factor, enough)[:, 1]
    polygons = [hull_polygon(c) for c in C] if screen.angle is not None else None  # once per history
    best = _fatigue_exact(screen, screen.by_G[:TOP_NODES], C, factor, polygons)
    c0, E = _enclosing_ellipse(C)
    n = screen.stress.shape[1]
    for g in _groups(S_, 12 * n):
        bound = factor(*_fatigue_bounds(screen.stress, c0[g], E[g]))  # (n, s)
        can = _fatigue_can(bound, best[g][None, :], enough)
        for h in _groups(can.shape[1], 6 * max(1, int(can.sum(axis=0).max())) * T):
            nodes = np.flatnonzero(can[:, h].any(axis=1))
            if nodes.size:
                sub = np.arange(S_)[g][h]
                some = [polygons[i] for i in sub] if polygons is not None else None
                best[sub] = np.minimum(best[sub], _fatigue_exact(screen, nodes, C[sub], factor, some))
    return best


def _enclosing_ellipse(C: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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


def _fatigue_bounds(stress: np.ndarray, c0: np.ndarray, E: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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


def _fatigue_exact(screen: Screen, nodes: np.ndarray, C: np.ndarray, factor, polygons=None) -> np.ndarray:
    """(S,) the smallest fatigue factor over ``nodes``: each component's maximum and
    minimum over the cycle from every step (tensordot), or, with two coefficients, from the
    cycle's convex polygon's support function (no step loop; :func:`railcheck.fea.superpose.support`;
    ``polygons`` the histories' hulls when already known)."""

    if screen.angle is not None:
        return _fatigue_exact_planar(screen, nodes, C, factor, polygons)
    return _exact_at(screen, nodes, C, factor, peak=False)[1]


def _exact_at(screen: Screen, nodes: np.ndarray, C: np.ndarray, factor=None, peak: bool = True):
    """((S,) Pa^2, (S,)): over ``nodes`` and every step of each history of ``C`` (S, T, k),
    the largest von Mises squared (0 without ``peak``) and, with a ``factor``, the
    smallest fatigue factor (each component's extremes over the steps; else inf), both
    from one product (tensordot), in chunks of :data:`EXACT_VALUES`."""
    vm2, least = np.zeros(C.shape[0]), np.full(C.shape[0], np.inf)
    for g in _groups(C.shape[0], 6 * nodes.size * C.shape[1], EXACT_VALUES):
        # and the nodes in groups too: one history over many nodes stays within EXACT_VALUES
        for h in _groups(nodes.size, 6 * C.shape[1] * (g.stop - g.start), EXACT_VALUES):
            X = np.tensordot(screen.stress[:, nodes[h], :], C[g], axes=([2], [2]))  # (6, u, s, T)
            if peak:
                vm2[g] = np.maximum(vm2[g], von_mises_squared(X).max(axis=(0, 2), initial=0.0))
            if factor is not None:
                sa, sm = alternating_and_mean(X.max(axis=3), X.min(axis=3))
                least[g] = np.minimum(least[g], factor(sa, sm).min(axis=0, initial=np.inf))
    return vm2, least


def _fatigue_exact_planar(screen: Screen, nodes: np.ndarray, C: np.ndarray, factor, polygons=None) -> np.ndarray:

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
