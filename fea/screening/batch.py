"""A group's histories screened together on (history, node) pairs (:class:`Batch`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..fatigue import alternating_and_mean
from ..invariants import von_mises_squared
from . import tuning
from .alone import screened_alone
from .bounds import fatigue_bounds, fatigue_bounds_by_midranges, fatigue_sampled, midrange_box, sampled_pairs
from .box import CoefficientBox, SampledBounds, von_mises_interval_bound
from .passes import PairsRead, can_beat, fatigue_may_pass, first_per_row, over_sets, peak_may_pass
from .screens import Screen
from .subspace import history_blocks, principal_subspaces, scaled, steps_of


@dataclass(frozen=True)
class ExactSource:
    """Where a group screened in a span (:func:`in_span`) takes its exact values: the
    ``screen`` in the original coefficients at the same nodes, its stresses by node
    ``by_node`` (n, 6, k), and the histories ``C`` (s, T, k). Every exact value is then
    the one a group without a span computes, bit for bit: a table does not depend on how
    the settings were grouped (serial or on workers). The bounds, read in the span, are
    those of histories within 1e-13 of these (:data:`railcheck.fea.screening.span.SPAN_RESIDUAL`),
    far inside the :data:`tuning.SLACK` every comparison with an exact value allows."""

    screen: Screen
    by_node: np.ndarray
    C: np.ndarray

    def of(self, histories: np.ndarray) -> ExactSource:
        """The same for the ``histories`` (indices) only."""
        return ExactSource(self.screen, self.by_node, self.C[histories])


def box_and_factor(group: CoefficientBox, lo, hi, mean, factor=None):
    """(vm (s, n), mid (s, 6, n), reach (s, 6, n), factor bound (s, n) or None) float32:
    the box bounds of histories whose basis coordinates range over ``lo`` to ``hi`` (s,
    k), and with a ``factor`` its lower bound with the midranges bounded by the histories'
    means ``mean`` (s, k) (:func:`railcheck.fea.screening.bounds.midrange_box`): the boxes and the
    midrange boxes in one pass over the group's rows."""
    s = lo.shape[0]
    if factor is None:  # (and ``mean`` None: the means are only taken for fatigue)
        vm, mid, reach = group.box_arrays(lo, hi)
        return vm, mid, reach, None
    m_lo, m_hi = midrange_box(lo, hi, mean)
    mid, reach = group.products(np.concatenate([lo, m_lo]), np.concatenate([hi, m_hi]))
    vm = von_mises_interval_bound(mid[:s], reach[:s], axis=1)
    box = SampledBounds.box(vm, by_component(mid[:s]), by_component(reach[:s]))
    bound = factor(*fatigue_bounds_by_midranges(box, by_component(mid[s:]), by_component(reach[s:])))
    return vm, mid[:s], reach[:s], bound


def by_component(a: np.ndarray) -> np.ndarray:
    """(6, s, n) view of (s, 6, n) bounds."""
    return a.transpose(1, 0, 2)


class Batch:
    """Histories ``C`` (s, T, k) (unscaled) of one group screened together: every stage
    of :func:`screened_alone` on (history, node) pairs at once, in the histories' principal
    subspaces (:func:`railcheck.fea.screening.subspace.principal_subspaces`); the exact values per
    history. ``by_node`` (n, 6, k) the screen's stresses grouped by node; ``group`` the
    group's box and ``taken`` (s, p, k) each history's coordinates at a few steps in its
    basis (:meth:`railcheck.fea.screening.box.CoefficientBox.ranges_and_taken`); ``labels`` (s,)
    ascending the histories' sets (:func:`peak_and_fatigue`); ``exact`` where the exact
    values are taken (:class:`ExactSource`; None: ``screen``, ``by_node`` and ``C``). Pa
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
        exact: ExactSource | None = None,
    ):
        self.screen, self.by_node, self.group, self.C, self.taken = screen, by_node, group, C, taken
        self.factor, self.enough, self.labels = factor, enough, labels
        self.at = ExactSource(screen, by_node, C) if exact is None else exact  # where exact values are taken
        self.sub = principal_subspaces(scaled(C, screen.scale))
        self.Pw = self.sub.P / screen.scale[None, :, None]  # (s, k, R) per unit coefficient

    def pair_key(self, h: np.ndarray, nodes: np.ndarray) -> np.ndarray:
        """(q,) one integer per (history, node) pair, ordered by history then node."""
        return h * self.by_node.shape[0] + nodes

    def fatigue_bound(self, b: SampledBounds) -> np.ndarray | None:
        """The lower bound of the fatigue factor from bounds ``b``, or None (no fatigue)."""
        return self.factor(*fatigue_bounds(b)) if self.factor is not None else None

    def beats(self, b: SampledBounds, h: np.ndarray, low2: np.ndarray, top: np.ndarray, bound=None) -> np.ndarray:
        """(q,) bool: the pairs (histories ``h``) whose bounds ``b`` can reach their
        history's peak lower bound ``sqrt(low2)`` or fatigue upper bound ``top`` (s,)
        (``bound``: their fatigue factor's lower bound, when already known)."""
        return can_beat(b, np.sqrt(low2)[h], top[h], self.factor, self.enough, bound)

    def projected(self, h: np.ndarray, nodes: np.ndarray) -> np.ndarray:
        """(q, 6, R) Pa per unit subspace coordinate of each pair's history (``h`` ascending)."""
        k, R = self.Pw.shape[1:]
        SP = np.empty((h.size, 6, R))
        for i, start, stop in history_blocks(h):
            SP[start:stop] = (self.by_node[nodes[start:stop]].reshape(-1, k) @ self.Pw[i]).reshape(-1, 6, R)
        return SP

    def sampled(self, SP: np.ndarray, h: np.ndarray, nodes: np.ndarray) -> SampledBounds:
        """:func:`railcheck.fea.screening.bounds.sampled_pairs` of each pair (``h`` ascending)."""
        sub, screen = self.sub, self.screen
        at = steps_of(sub.a, sub.sampled)  # (s, M, R)
        return sampled_pairs(SP, h, at, sub.delta, sub.eps, screen.bounds.unit_rows[:, nodes], screen.vm_norm[nodes])

    def exact(
        self, h: np.ndarray, nodes: np.ndarray, peak: np.ndarray, fatigue: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """((s,) Pa^2, (s,)): each history's largest von Mises squared over every step at
        its pairs' nodes marked ``peak`` (0 if none), and its smallest fatigue factor at
        those marked ``fatigue`` (inf if none; each component's extremes over every
        step). ``h`` (q,) ascending; one product per history (in chunks of
        :data:`tuning.EXACT_VALUES`)."""
        s, T, k = self.at.C.shape
        vm2, least = np.zeros(s), np.full(s, np.inf)
        keep = peak | fatigue
        h, nodes, peak, fatigue = h[keep], nodes[keep], peak[keep], fatigue[keep]
        for i, a, b in history_blocks(h, max(1, tuning.EXACT_VALUES // (6 * T))):
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
    ) -> tuple[np.ndarray, np.ndarray, PairsRead]:
        """((s,) Pa^2, (s,), read): exact values at the :data:`tuning.THRESHOLD_NODES` of best
        sampled value among the :data:`tuning.BOX_FIRST` of best box bound ``vm`` (von Mises, (s,
        n)) and ``bound`` (fatigue factor) of each history, of those ``passable`` (s, n)
        (whose bounds can pass the thresholds so far: no other node can raise them);
        ``read`` those pairs' sampled bounds and which of them were evaluated exactly
        (:class:`PairsRead`)."""
        first = first_per_row(vm, tuning.BOX_FIRST, largest=True)
        if bound is not None:
            first = np.concatenate([first, first_per_row(bound, tuning.BOX_FIRST, largest=False)], axis=1)
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
        np.put_along_axis(peak, first_per_row(best.reshape(s, F), tuning.THRESHOLD_NODES, largest=True), True, axis=1)
        fatigue = np.zeros((s, F), dtype=bool)
        factor_bound = None
        if bound is not None:
            f = np.full(s * F, np.inf)
            f[use] = self.factor(*fatigue_sampled(b))
            np.put_along_axis(fatigue, first_per_row(f.reshape(s, F), tuning.THRESHOLD_NODES, largest=False), True, axis=1)
            factor_bound = self.fatigue_bound(b)
        peak, fatigue = peak.ravel()[use], fatigue.ravel()[use]
        vm2, least = self.exact(h, nodes, peak, fatigue)
        return vm2, least, PairsRead(self.pair_key(h, nodes), b.von_mises_upper, factor_bound, peak, fatigue)

    def screened(self, vm, mid, reach, box_factor, can, low2, top, loose) -> np.ndarray:
        """(s, 2): each history's exact peak (Pa) and fatigue minimum, from its group box
        bounds ``vm`` (s, n), ``mid`` and ``reach`` (s, 6, n) (float32), their fatigue
        factor's lower bound ``box_factor`` (s, n) (or None), the group's thresholds
        ``low2`` (Pa^2) and ``top`` (s,), and ``can`` the nodes whose bounds can pass them
        ((s, n) bool for the peak and for fatigue, or None without a factor); a history whose group box keeps more than
        ``loose`` nodes is screened alone (:func:`screened_alone`)."""
        s = self.C.shape[0]
        out = np.empty((s, 2))
        mid6, reach6 = by_component(mid), by_component(reach)
        # the thresholds are taken at nodes that can pass the group's (no other can raise them)
        first_vm = np.where(can[0], vm, -np.inf)
        first_factor = None if box_factor is None else np.where(can[1], box_factor, np.inf)
        passable = can[0] if can[1] is None else can[0] | can[1]
        more_low2, less_top, read = self.thresholds(first_vm, first_factor, passable)
        low2, top = np.maximum(low2, more_low2), np.minimum(top, less_top)  # each an exact value at some node
        low2, top = over_sets(low2, self.labels, np.maximum), over_sets(top, self.labels, np.minimum)  # of the set
        every = np.arange(s)
        keep = self.beats(SampledBounds.box(vm, mid6, reach6), every[:, None], low2, top, box_factor)
        h, nodes = np.nonzero(keep)
        if self.factor is not None and h.size:
            # the box's midrange bounds from the values each history takes, at these pairs only
            m, r = mid[h, :, nodes], reach[h, :, nodes]  # (q, 6)
            mid_upper = self.group.midrange_at(m, r, nodes, h, self.taken)
            tighter = SampledBounds.box(vm[h, nodes], m.T, r.T, mid_upper.T)
            kept = self.beats(tighter, h, low2, top)
            h, nodes = h[kept], nodes[kept]
        alone = np.bincount(h, minlength=s) > loose  # the group's box is loose for these
        for i in np.flatnonzero(alone):
            box = SampledBounds.box(vm[i], mid[i], reach[i])
            tighter_i = lambda some, b, i=i: self.group.at_nodes(b, some, self.taken[i])  # noqa: E731
            exact_i = (self.at.screen, self.at.C[i])
            out[i] = screened_alone(
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
        peak = peak_may_pass(upper, np.sqrt(low2)[h])
        fatigue = np.zeros_like(peak)
        if self.factor is not None:
            assert read.factor_bound is not None  # the thresholds read fatigue when there is a factor
            factor_bound[~new] = read.factor_bound[at[~new]]
            factor_bound[new] = self.fatigue_bound(b)
            fatigue = fatigue_may_pass(factor_bound, top[h], self.enough)
        # and a pair evaluated exactly for a criterion there is not evaluated again for it
        peak[~new] &= ~read.peak[at[~new]]
        fatigue[~new] &= ~read.fatigue[at[~new]]
        vm2, least = self.exact(h, nodes, peak, fatigue)
        out[~alone, 0] = np.sqrt(np.maximum(low2, vm2))[~alone]
        out[~alone, 1] = np.minimum(top, least)[~alone]
        return out
