"""The coefficients a group of histories spans: r of the k original coefficients, the rest
combinations of them, granted only when every history's residual outside the span is
negligible (:func:`history_span`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: singular values of a group's sampled steps above this share of the largest span the
#: group's histories (:func:`history_span`); the rest are rounding (a free body's
#: equilibrium and the joints its group shares: about 1e-16 of the largest, against 1e-4
#: to 1e-3 for the smallest kept)
SPAN_RANK = 1e-10


#: a group's histories are re-expressed in fewer coefficients only when each history's
#: residual outside their span is at most this share of its largest scaled coefficient
#: vector (:func:`history_span`): its results then equal the full ones to rounding
SPAN_RESIDUAL = 1e-13


#: every this-many-th step of each history is read to find the span (the residual is then
#: measured at every step, so a direction only the skipped steps take is never lost)
SPAN_STRIDE = 8


@dataclass(frozen=True)
class Span:
    """A group's scaled coefficients ``c * scale`` (k,) in r of themselves: ``index`` (r,)
    ascending the independent ones, ``basis`` (k, r) with ``c * scale = basis (c *
    scale)[index]`` for every step of every history of the group (to the residual
    :func:`history_span` measured), ``basis[index]`` the identity."""

    index: np.ndarray
    basis: np.ndarray

    @property
    def dual(self) -> np.ndarray:
        """(k, r): the selection of the independent coefficients (``dual^T basis = I``)."""
        out = np.zeros(self.basis.shape)
        out[self.index, np.arange(self.index.size)] = 1.0
        return out


def history_span(Cs: np.ndarray) -> Span | None:
    """The span of the scaled histories ``Cs`` (s, T, k) as r < k of their coefficients
    (:class:`Span`), or None when they span all k (or are not finite, or zero).

    The rank is read from the singular values of every :data:`SPAN_STRIDE`-th step (above
    :data:`SPAN_RANK` of the largest); the independent coefficients are the pivots of a
    column-pivoted QR of the span's basis (the best conditioned choice). The residual of
    each step, ``e = Cs - basis Cs[index]``, is bounded from its part outside the span,
    ``|e| <= |z| (1 + |basis|_2)`` (``z`` the component along the null directions: the
    span's part is reproduced exactly), and the span is used only when every history's
    bound is at most :data:`SPAN_RESIDUAL` of its largest ``|Cs_t|``."""
    s, T, k = Cs.shape
    X = Cs[:, ::SPAN_STRIDE].reshape(-1, k)
    if X.shape[0] < k:
        X = Cs.reshape(-1, k)
    if not np.all(np.isfinite(X)):
        return None
    _, sv, Vt = np.linalg.svd(np.linalg.qr(X, mode="r"))
    if not sv[0] > 0.0:
        return None
    r = int(np.count_nonzero(sv > SPAN_RANK * sv[0]))
    if r >= k:
        return None
    import scipy.linalg

    B, N = Vt[:r].T, Vt[r:].T
    index = np.sort(scipy.linalg.qr(B.T, pivoting=True, mode="r")[1][:r])
    basis = B @ np.linalg.inv(B[index])
    basis[index] = np.eye(r)
    with np.errstate(over="ignore"):  # sizes beyond 1e154 overflow to inf: then no span
        outside = np.linalg.norm(Cs @ N, axis=2).max(axis=1) * (1.0 + np.linalg.norm(basis, 2))
        size = np.linalg.norm(Cs, axis=2).max(axis=1)
    if not np.all(np.isfinite(size) & (outside <= SPAN_RESIDUAL * size)):
        return None
    return Span(index, basis)
