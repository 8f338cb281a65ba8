"""Exact screens of a many-coefficient load history over a part's nodes: which nodes can
hold the cycle's von Mises peak or its lowest fatigue factor, so that only those are
evaluated at every step.

A history ``c`` (T steps, k coefficients, each scaled by its largest stress per unit so
forces, torques and accelerations are comparable) is split into its principal subspace
of rank :data:`REDUCED_RANK` and a residual: ``c_t = P a_t + e_t``. Every STRIDE-th step
is read at every node in the r coordinates ``a`` (r terms per stress component instead
of k). A step between lies within ``|a_t - a_s|`` of its nearer sampled step ``s`` and
within ``|e_t|`` of the subspace, so with ``Sw`` a node's stress per unit scaled
coefficient (6 x k) and ``L`` the von Mises factor (von Mises = ``|L Sw c|``):

* von Mises at step t <= sampled von Mises + ``||L Sw P||_F |a_t - a_s|`` + ``||L Sw|| |e_t|``;
* each stress component's maximum and minimum over all steps lie within ``g = |Sw_j P|
  |a_t - a_s| + |Sw_j| |e_t|`` outside the sampled ones (bounds of its half-range and of
  its midrange's magnitude, hence of the alternating and midrange von Mises).

A real setting's history lies close to a few directions (its singular values fall to a
few % of the first by the fourth), so the bounds are tight and a few to a few hundred of
10,000-30,000 nodes remain. Everything in SI (Pa); the callers evaluate the remaining
nodes exactly (:mod:`railcheck.sweep.fe`, :func:`fea.superpose.screened_max`,
:func:`railcheck.check.cycle.fatigue_of`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .stress import VM_QUADRATIC, von_mises

#: the rank of the principal subspace a history is screened in
REDUCED_RANK = 4
#: every STRIDE-th step (at least) is read at every node; the steps between are bounded
STRIDE = 8
#: a longer history is read at about this many steps (a stride of T / SAMPLES): the gap
#: between read steps, which sets the bounds, is then that of 720 steps at STRIDE
SAMPLES = 90
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
    return k > 2 and steps > 4 * STRIDE


def column_scale(S: np.ndarray) -> np.ndarray:
    """(k,) each coefficient's largest stress per unit (Pa per unit) over the nodes of
    ``S`` (6, n, k): the coefficients' scale."""
    return np.linalg.norm(S, axis=0).max(axis=0) + 1e-300


@dataclass(frozen=True)
class Subspace:
    """One scaled history ``c`` (T, k) as ``c_t = P a_t + e_t``: ``P`` (k, r) its principal
    directions, ``a`` (T, r) the steps' coordinates, ``eps`` the largest ``|e_t|``;
    ``sampled`` the indices of the steps read (every STRIDE-th, or about SAMPLES of a long
    history) and ``delta`` the largest distance
    ``|a_t - a_s|`` of any step from its nearer sampled neighbour."""

    P: np.ndarray
    a: np.ndarray
    eps: float
    sampled: np.ndarray
    delta: float


def principal_subspace(c: np.ndarray) -> Subspace:
    """The scaled history ``c`` (T, k) in its principal subspace of rank REDUCED_RANK."""
    T, k = c.shape
    _, _, Vt = np.linalg.svd(c, full_matrices=False)
    P = Vt[: min(REDUCED_RANK, k)].T
    a = c @ P
    eps = float(np.linalg.norm(c - a @ P.T, axis=1).max())
    stride = max(STRIDE, -(-T // SAMPLES))
    sampled = np.arange(0, T, stride)
    before = (np.arange(T) // stride) * stride
    after = np.minimum(before + stride, sampled[-1])
    gap = np.minimum(np.linalg.norm(a - a[before], axis=1), np.linalg.norm(a - a[after], axis=1))
    return Subspace(P, a, eps, sampled, float(gap.max()))


@dataclass(frozen=True)
class SampledBounds:
    """Per node, from the sampled steps in the subspace: ``von_mises`` (n,) Pa the largest
    sampled von Mises and ``von_mises_upper`` (n,) a bound over every step; ``high``,
    ``low`` (6, n) Pa each component's sampled maximum and minimum and ``slack`` (6, n)
    Pa how far outside them its value at any step can lie."""

    von_mises: np.ndarray
    von_mises_upper: np.ndarray
    high: np.ndarray
    low: np.ndarray
    slack: np.ndarray


def component_norms(Sw: np.ndarray) -> np.ndarray:
    """(6, n): each stress component's norm over its k coefficients (Pa per unit scaled coefficient)."""
    return np.linalg.norm(Sw, axis=2)


def von_mises_norm_bound(Sw: np.ndarray) -> np.ndarray:
    """(n,): an upper bound of each node's largest von Mises per unit scaled coefficient,
    the Frobenius norm of its von Mises factor (sqrt of the trace of its quadratic form)."""
    return np.sqrt(np.maximum(np.einsum("cnk,cd,dnk->n", Sw, VM_QUADRATIC, Sw, optimize=True), 0.0))


def sampled_bounds(S: np.ndarray, scale: np.ndarray, norms: np.ndarray, vm_norm: np.ndarray, sub: Subspace) -> SampledBounds:
    """The nodes' sampled values and bounds (module doc). ``S`` (6, n, k) Pa per unit
    coefficient and ``scale`` (k,) the coefficients' scale (so ``S / scale`` is the stress
    per unit scaled coefficient); ``norms`` (6, n) :func:`component_norms` of ``S /
    scale``; ``vm_norm`` (n,) a bound of each node's von Mises per unit scaled coefficient
    (:func:`von_mises_norm_bound`, or the square root of its quadratic form's largest
    eigenvalue)."""
    SP = S @ (sub.P / scale[:, None])  # (6, n, r): stress per unit of the subspace's coordinates
    a = sub.a[sub.sampled]  # (s, r)
    n, r = SP.shape[1], SP.shape[2]
    # von Mises squared as an r x r form per node (r^2 terms per node and step, one matrix product)
    L = np.tensordot(VM_FACTOR, SP, axes=([1], [0]))  # (6, n, r)
    QP = np.einsum("cnr,cns->nrs", L, L).reshape(n, r * r)
    aa = (a[:, :, None] * a[:, None, :]).reshape(-1, r * r)
    vm, high, low = np.empty(n), np.empty((6, n)), np.empty((6, n))
    size = max(1, CHUNK_VALUES // (6 * a.shape[0]))
    for start in range(0, n, size):
        sl = slice(start, min(start + size, n))
        X = SP[:, sl] @ a.T  # (6, m, s)
        high[:, sl], low[:, sl] = X.max(axis=2), X.min(axis=2)
        vm[sl] = np.sqrt(np.maximum((QP[sl] @ aa.T).max(axis=1), 0.0))
    vm_P = np.sqrt(np.maximum(QP[:, :: r + 1].sum(axis=1), 0.0))  # the form's trace: ||L SP||_F
    upper = vm + vm_P * sub.delta + vm_norm * sub.eps
    slack = np.linalg.norm(SP, axis=2) * sub.delta + norms * sub.eps
    return SampledBounds(vm, upper, high, low, slack)


def history_bounds(S: np.ndarray, C: np.ndarray) -> SampledBounds:
    """:func:`sampled_bounds` of the nodes of ``S`` (6, n, k) Pa per unit coefficient for
    one history ``C`` (steps, k), the coefficients scaled by :func:`column_scale`."""
    w = column_scale(S)
    Sw = S / w
    return sampled_bounds(S, w, component_norms(Sw), von_mises_norm_bound(Sw), principal_subspace(C * w))


def fatigue_bounds(b: SampledBounds) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(sa_upper, sm_upper, sa_sampled, sm_sampled) (n,) Pa: upper bounds of each node's
    alternating and midrange von Mises over every step (no cross terms between the
    components' unknown signs), and their sampled values (an estimate)."""
    half = 0.5 * (b.high - b.low) + b.slack
    mid = np.abs(0.5 * (b.high + b.low)) + b.slack
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


def first_nodes(values: np.ndarray, largest: bool = True) -> np.ndarray:
    """The FIRST_NODES nodes of largest (or smallest) ``values``, ascending."""
    order = np.argsort(-values if largest else values, kind="stable")
    return np.sort(order[:FIRST_NODES])
