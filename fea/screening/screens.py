"""A part's screens: its unit fields at the verdict nodes, per column set, with the bounds
the exact screening reads (:class:`Screen`), built once per part and hole group."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..hull import candidate_steps, hull_applies
from ..invariants import VM_QUADRATIC
from . import tuning
from .bounds import basis_trial_nodes
from .box import component_norms, von_mises_norm_bound
from .subspace import column_scale, steps_of


@dataclass(frozen=True)
class ScreenBounds:
    """A screen's bounds per unit coefficient at each of its n nodes (Pa per unit scaled
    coefficient unless stated):

    * ``form_bound`` (n,) Pa^2: the largest eigenvalue of each node's von Mises quadratic
      form in the scaled coefficients (more than two coefficients: its trace, a bound of it);
    * ``midrange_factor`` and ``alternating_factor`` (n,): the fatigue screen's bounds of
      the midrange and alternating von Mises per unit coefficient;
    * ``unit_rows`` (6, n): each component's stress per unit scaled coefficient (the norm
      of its k values over ``scale``);
    * ``by_form_bound`` and ``by_alternating_factor``: the nodes by decreasing
      ``form_bound`` and ``alternating_factor``."""

    form_bound: np.ndarray
    midrange_factor: np.ndarray
    alternating_factor: np.ndarray
    unit_rows: np.ndarray
    by_form_bound: np.ndarray
    by_alternating_factor: np.ndarray


def screen_bounds(S: np.ndarray, scale: np.ndarray, form_bound: np.ndarray | None = None) -> ScreenBounds:
    """:class:`ScreenBounds` of the stresses ``S`` (6, n, k) Pa per unit coefficient with
    the coefficients' ``scale`` (k,); ``form_bound`` when known (two coefficients: the
    forms' largest eigenvalues), else the trace bound."""
    Sw = S / scale
    form_bound = von_mises_norm_bound(Sw) ** 2 if form_bound is None else form_bound
    midrange, alternating = fatigue_factors(component_norms(S))
    return ScreenBounds(
        form_bound, midrange, alternating, component_norms(Sw), np.argsort(-form_bound), np.argsort(-alternating)
    )


@dataclass(frozen=True)
class Screen:
    """One column set of a part's unit fields, at its verdict nodes: ``stress`` (6, n, k)
    Pa per unit coefficient; ``forms`` (n, k*k) the von Mises quadratic forms in the scaled
    coefficients ``c * scale`` (Pa^2; two coefficients only, else None: a many-coefficient
    history's von Mises is read from the stresses); ``tip`` (3, k) m; ``scale`` (k,) the
    coefficients' scale w; ``known_bounds`` the :class:`ScreenBounds` when the maker has
    them (two coefficients: exact eigenvalues), else None. :attr:`bounds` is computed on
    first use: a many-coefficient screen's are mostly never read, since a group whose
    histories span fewer dimensions than their coefficients is read in a screen of its
    own (:func:`in_span`), so the rig's parts skip them (1.8 s of its serial preparation)."""

    stress: np.ndarray
    forms: np.ndarray | None
    tip: np.ndarray
    scale: np.ndarray
    known_bounds: ScreenBounds | None = field(repr=False, default=None)
    angle: np.ndarray | None = field(repr=False, default=None)  # (6, n) arctan2 of each component (k = 2)
    trial: np.ndarray | None = field(repr=False, default=None)  # (6, m, k) basis_trial_nodes of stress

    @cached_property
    def bounds(self) -> ScreenBounds:
        """The screen's :class:`ScreenBounds`: ``known_bounds``, or computed once."""
        return self.known_bounds if self.known_bounds is not None else screen_bounds(self.stress, self.scale)

    @property
    def vm_norm(self) -> np.ndarray:
        """(n,) a bound of each node's von Mises per unit scaled coefficient: the square
        root of :attr:`ScreenBounds.form_bound`."""
        return np.sqrt(np.maximum(self.bounds.form_bound, 0.0))


def make_screen(stress: np.ndarray, verdict_mask: np.ndarray, tip: np.ndarray, cols: list[int]) -> Screen:
    """Screen of the unit-case columns ``cols`` of ``stress`` (6, nodes, cases) at the
    verdict nodes; ``tip`` (3, cases) m."""
    return make_screens(stress, verdict_mask, {None: tip}, {None: cols})[None]


def make_screens(stress: np.ndarray, verdict_mask: np.ndarray, tips: dict, columns: dict) -> dict:
    """key -> :func:`make_screen` of each key's unit-case columns ``columns[key]`` with
    its tip operator ``tips[key]`` (3, cases) m. The fields are read once, in slabs of
    :data:`tuning.GATHER_NODES` verdict nodes, each slab's columns gathered for every key while
    it is in cache: a part's fields have tens to hundreds of columns and each hole pair
    a few of them, so a gather per key streamed them all once per key (a rail's 89
    columns and 16 hole pairs of 17: 0.15-0.2 against 0.38-0.44 s). ``stress`` in any
    memory layout (:func:`node_slab`)."""
    nodes = np.flatnonzero(verdict_nodes(verdict_mask))
    index = {key: np.asarray(cols, dtype=np.intp) for key, cols in columns.items()}
    out = {key: np.empty((6, nodes.size, i.size)) for key, i in index.items()}
    for start in range(0, nodes.size, tuning.GATHER_NODES):
        slab = node_slab(stress, nodes[start : start + tuning.GATHER_NODES])  # (6, b, cases)
        for key, i in index.items():
            out[key][:, start : start + tuning.GATHER_NODES] = np.take(slab, i, axis=2)
    return {key: screen_of(out[key], tips[key][:, index[key]]) for key in columns}


def node_slab(stress: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """(6, b, cases) C-contiguous: ``stress[:, nodes]``. ``np.take`` is the faster gather
    of a C-contiguous array, but of any other it first copies the whole array: freshly
    solved fields are a transposed view of the solver's node-major columns
    (:func:`railcheck.fea.stress.recover_stress`), where a take per slab would copy all of
    a rail's fields each time; such fields are indexed slab by slab instead (stored ones are
    read C-contiguous). Measured: docs/changelog.md, "The measurements behind tuned constants"."""
    if stress.flags.c_contiguous:
        return np.take(stress, nodes, axis=1)
    return np.ascontiguousarray(stress[:, nodes])


def verdict_nodes(verdict_mask: np.ndarray) -> np.ndarray:
    """The mask of the nodes a screen reads: the verdict nodes, or every node if none is."""
    return verdict_mask if np.any(verdict_mask) else np.ones_like(verdict_mask)


def screen_of(S: np.ndarray, tip: np.ndarray) -> Screen:
    """Screen of the stresses ``S`` (6, n, k) Pa per unit coefficient (contiguous) at the
    verdict nodes and the tip's (3, k) m per unit coefficient."""
    k = S.shape[2]
    # the quadratic forms in scaled coefficients c w (w: each coefficient's largest stress
    # per unit), so the bound sqrt(form bound) |c w| is not set by mixing forces, torques and
    # accelerations of very different stress per unit
    w = column_scale(S)
    trial = basis_trial_nodes(S)
    if k > 2:  # no k x k forms (k^2 floats per node): the screens read the stresses; bounds on first use
        return Screen(S, None, tip, w, trial=trial)
    Sw = S / w
    Q = np.einsum("cnk,cd,dnl->nkl", Sw, VM_QUADRATIC, Sw, optimize=True)
    bounds = screen_bounds(S, w, np.linalg.eigvalsh(Q)[:, -1])
    angle = np.arctan2(S[..., 1], S[..., 0]) if k == 2 else None
    return Screen(S, Q.reshape(-1, k * k), tip, w, bounds, angle, trial)


def fatigue_factors(norms: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(midrange, alternating) (n,): the bound factors of the fatigue screen
    from each component's norm ``norms`` (6, n) Pa per unit coefficient."""
    shear = 3.0 * (norms[3] ** 2 + norms[4] ** 2 + norms[5] ** 2)
    midrange = np.sqrt(0.5 * ((norms[0] + norms[1]) ** 2 + (norms[1] + norms[2]) ** 2 + (norms[2] + norms[0]) ** 2) + shear)
    return midrange, np.sqrt(norms[0] ** 2 + norms[1] ** 2 + norms[2] ** 2 + shear)


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
    return steps_of(C, index)


def value_slices(settings: int, per_setting: int, limit: int = tuning.CHUNK_VALUES) -> list[slice]:
    """Consecutive slices of ``settings`` items, each of at most ``limit`` floats at
    ``per_setting`` floats an item (at least one item)."""
    size = max(1, limit // max(per_setting, 1))
    return [slice(i, min(i + size, settings)) for i in range(0, settings, size)]
