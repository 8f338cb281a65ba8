"""A history screened alone in its own principal subspace: box, samples, then the few
nodes left evaluated at every step."""

from __future__ import annotations

import numpy as np

from . import tuning
from .bounds import fatigue_bounds, fatigue_sampled, first_nodes, peak_candidates, sampled_bounds
from .box import SampledBounds, box_bounds, project
from .exact import exact_von_mises2, fatigue_exact
from .passes import can_beat, fatigue_may_pass
from .screens import Screen
from .subspace import principal_subspace


def screened_alone(
    screen: Screen,
    c: np.ndarray,
    box: SampledBounds,
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
    (:class:`railcheck.fea.screening.box.CoefficientBox`). The :data:`tuning.BOX_FIRST` nodes of best box
    bound read at the sampled steps, and the FIRST_NODES of best sampled value among them
    evaluated exactly: the thresholds. Only the nodes whose group box can beat a
    threshold, and then whose box in the history's own principal subspace
    (:func:`railcheck.fea.screening.box.box_bounds`) can, are read at the sampled steps, and only
    those whose sampled bound can beat it are evaluated at every step. ``tighter``:
    (nodes, box) -> ``box`` at those nodes with its midrange bounds from the values the
    history takes (:meth:`railcheck.fea.screening.box.CoefficientBox.at_nodes`), applied to the
    nodes the box keeps before they are projected. ``exact``: (screen, history) where the
    exact values are taken, the same nodes in other coefficients (:class:`ExactSource`); None:
    ``screen`` and ``c``."""
    if not np.any(c):  # unloaded: no stress anywhere (and no screen to build on a zero box)
        return 0.0, np.inf
    one = OneHistory(screen, c, factor, enough, (screen, c) if exact is None else exact)
    box_factor = one.fatigue_bound(box)
    more_low2, less_top = one.thresholds(box, box_factor)
    low2, top = max(low2, more_low2), min(top, less_top)  # each an exact value at some node
    nodes = np.flatnonzero(one.beats(box, low2, top, box_factor))
    if tighter is not None and factor is not None and nodes.size:
        # the box's midrange bounds from the values the history takes, at these nodes only
        nodes = nodes[one.beats(tighter(nodes, box), low2, top)]
    if nodes.size > (tuning.LOOSE_SHARE * box.von_mises.size if loose is None else loose):  # the group's box is loose here
        SP = project(screen.stress, screen.scale, one.sub)
        own = box_bounds(SP, one.norms, one.vm_norm, one.sub)
        own_factor = one.fatigue_bound(own)
        more_low2, less_top = one.thresholds(own, own_factor)
        low2, top = max(low2, more_low2), min(top, less_top)  # each an exact value at some node
        nodes = np.flatnonzero(one.beats(own, low2, top, own_factor))
        SP = SP[:, nodes]
    else:
        SP = one.projected(nodes)
        keep = one.beats(box_bounds(SP, one.norms[:, nodes], one.vm_norm[nodes], one.sub), low2, top)
        nodes, SP = nodes[keep], SP[:, keep]
    return one.exact_values(nodes, SP, low2, top)


class OneHistory:
    """One history ``c`` (T, k) (unscaled) on a ``screen``, in its own principal subspace:
    the stages of :func:`screened_alone`. ``factor`` (sa, sm) -> safety factor or None;
    ``enough`` as in :func:`railcheck.fea.screening.groups.fatigue_min`; ``exact`` (screen,
    history) where the exact values are taken. Pa throughout."""

    def __init__(self, screen: Screen, c: np.ndarray, factor, enough, exact: tuple[Screen, np.ndarray]):
        self.screen, self.factor, self.enough = screen, factor, enough
        self.ex_screen, self.ex_c = exact
        self.sub = principal_subspace(c * screen.scale)
        self.norms, self.vm_norm = screen.bounds.unit_rows, screen.vm_norm

    def projected(self, nodes: np.ndarray) -> np.ndarray:
        """(6, q, R) Pa per unit subspace coordinate at ``nodes``."""
        return project(self.screen.stress[:, nodes], self.screen.scale, self.sub)

    def sampled(self, nodes: np.ndarray, SP: np.ndarray) -> SampledBounds:
        """The sampled bounds at ``nodes`` from their projected stresses ``SP``."""
        return sampled_bounds(SP, self.norms[:, nodes], self.vm_norm[nodes], self.sub)

    def beats(self, bounds: SampledBounds, low2: float, top: float, bound=None) -> np.ndarray:
        """Nodes whose bounds can reach the peak's lower bound or the fatigue minimum's
        upper one (``bound``: their fatigue factor's lower bound, when already known)."""
        return can_beat(bounds, np.sqrt(low2), top, self.factor, self.enough, bound)

    def fatigue_bound(self, bounds: SampledBounds) -> np.ndarray | None:
        """The fatigue factor's lower bound from ``bounds``, or None without a factor."""
        return self.factor(*fatigue_bounds(bounds)) if self.factor is not None else None

    def thresholds(self, bounds: SampledBounds, bound) -> tuple[float, float]:
        """(Pa^2, factor): exact values at the nodes of best sampled value among the
        :data:`tuning.BOX_FIRST` of best ``bounds`` (von Mises) and ``bound`` (fatigue factor)."""
        first = first_nodes(bounds.von_mises_upper, count=tuning.BOX_FIRST)
        if self.factor is not None:
            first = np.union1d(first, first_nodes(bound, largest=False, count=tuning.BOX_FIRST))
        b = self.sampled(first, self.projected(first))
        low2 = exact_von_mises2(self.ex_screen, first[first_nodes(b.von_mises)], self.ex_c)
        if self.factor is None:
            return low2, np.inf
        f = self.factor(*fatigue_sampled(b))
        return low2, fatigue_exact(self.ex_screen, first[first_nodes(f, largest=False)], self.ex_c[None], self.factor)[0]

    def exact_values(self, nodes: np.ndarray, SP: np.ndarray, low2: float, top: float) -> tuple[float, float]:
        """(Pa, factor): the exact peak and fatigue minimum, from the sampled bounds at the
        ``nodes`` left (their projected stresses ``SP``) and the thresholds so far."""
        b = self.sampled(nodes, SP)
        ex_screen, ex_c = self.ex_screen, self.ex_c
        peak = float(np.sqrt(max(low2, exact_von_mises2(ex_screen, nodes[peak_candidates(b, np.sqrt(low2))], ex_c))))
        if self.factor is None:
            return peak, np.inf
        rest = nodes[fatigue_may_pass(self.factor(*fatigue_bounds(b)), top, self.enough)]
        if not rest.size:
            return peak, float(top)
        return peak, min(float(top), float(fatigue_exact(ex_screen, rest, ex_c[None], self.factor)[0]))
