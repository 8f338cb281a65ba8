"""Where the sweep's quasi-static answers hold: each certified part's one-mode amplification
estimate (:mod:`railcheck.model.certificate`) per setting and speed, the ``quasi-static``
criterion it adds to the verdict, and the safe speed with the estimate as a margin.

At a speed of the table, a part's stresses, fatigue factor and deflection are the quasi-
static ones (as ``railcheck check`` gives them) and its ``quasi-static`` utilisation is
the estimate's excess over 1 as a share of the tolerance's: above 1 the quasi-static
verdict is not given (the row fails on ``quasi-static``, and :mod:`railcheck.sweep.exact`
evaluates it again on the exact response before it reaches the table). The safe speed is
the largest at which every criterion, the quasi-static results amplified by the estimate
(stress and deflection times it, fatigue factor over it), stays within its limit and the
estimate within the tolerance: the exact dynamic response there is within it (the
certificate is conservative, tested).

The load histories' harmonics are taken once per part and setting (:class:`Spectra`); each
speed then costs one inverse transform. SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from railcheck.fea.dynamic import harmonic_spectrum, one_mode_peak
from railcheck.model.certificate import force_columns, largest_significant
from railcheck.model.crossing import increasing_crossing, refine_crossing
from railcheck.model.utilisation import margin_utilisations, quasi_static_share
from railcheck.sweep.context import SweepContext
from railcheck.sweep.verdicts import (
    CROSSING_TOLERANCE,
    criterion_utilisations,
    governing_of,
    illinois,
    safe_ratio_sq_convex,
    utilisation,
    worst_utilisation,
)


def certifying(ctx: SweepContext) -> bool:
    """Whether some part of the sweep carries the certificate."""
    return any(m.certified and m.constant is None for m in ctx.models.values())


@dataclass(frozen=True)
class _Source:
    """One load source of the settings ``idx`` sharing a hole pair: the joint-force and
    couple columns' spectra of the inertia (per unit ``s``) and gravity histories, their
    histories (for the peaks with gravity), the number of force columns, the pair's
    lowest frequency (Hz) and the steps per revolution."""

    idx: np.ndarray
    P_inertia: np.ndarray
    P_gravity: np.ndarray | None
    C_inertia: np.ndarray
    C_gravity: np.ndarray | None
    n_forces: int
    hz: float
    steps: int


class Spectra:
    """The certified parts' load harmonics for a group of settings, taken once; :meth:`at`
    gives each part's estimate at any speed ratio squared."""

    def __init__(self, ctx: SweepContext, histories: dict, lengths: dict):
        self.ctx = ctx
        self.parts: dict[str, list[_Source]] = {}
        self.n = next(iter(lengths.values())).size
        self._at_reference: dict | None = None  # every setting's estimates at the reference speed
        for name, m in ctx.models.items():
            if not m.certified or m.constant is not None:
                continue
            bar = lengths[m.bar] if m.bar else None
            self.parts[name] = [
                self._source(m, idx, key, C_gravity, C_inertia)
                for idx, key in _key_groups(m, bar, self.n)
                for C_gravity, C_inertia in histories[name]
            ]

    @staticmethod
    def _source(m, idx: np.ndarray, key, C_gravity, C_inertia) -> _Source:
        forces, couples = force_columns(m.case_names[key])
        cols = forces + couples
        c_inertia = C_inertia[idx][..., cols]
        c_gravity = None if C_gravity is None else C_gravity[idx][..., cols]
        return _Source(
            idx,
            harmonic_spectrum(c_inertia),
            None if c_gravity is None else harmonic_spectrum(c_gravity),
            c_inertia,
            c_gravity,
            len(forces),
            m.lowest_hz[key],
            c_inertia.shape[-2],
        )

    def at(self, s, idx: np.ndarray | None = None) -> dict:
        """part -> its estimate at speed ratio squared ``s``: (n,) of every setting (``s``
        scalar or (n,)), or (len(idx),) of the settings ``idx`` only (``s`` scalar or one
        per setting of ``idx``); only those settings' harmonics are transformed, none at
        rest (``s = 0``), and every setting's at the reference speed only once."""
        idx = np.arange(self.n) if idx is None else np.asarray(idx)
        ss = np.broadcast_to(np.asarray(s, float), idx.shape)
        reference = idx.size == self.n and np.all(ss == 1.0)
        if reference and self._at_reference is not None:
            return {k: v.copy() for k, v in self._at_reference.items()}
        where = np.full(self.n, -1)
        moving = ss > 0.0  # at rest the one-mode response is the load itself: the estimate is 1
        where[idx[moving]] = np.flatnonzero(moving)
        out = {}
        for name, sources in self.parts.items():
            amp = np.ones(idx.size)
            for src in sources:
                rows = np.flatnonzero(where[src.idx] >= 0)
                if rows.size:
                    at = where[src.idx[rows]]
                    est = _estimate(src, ss[at], self.ctx.speeds[0], self.ctx.models[name].damping, rows)
                    amp[at] = np.maximum(amp[at], est)
            out[name] = amp
        if reference:
            self._at_reference = {k: v.copy() for k, v in out.items()}
        return out


def _estimate(src: _Source, s: np.ndarray, speed0: float, damping: float, rows=None) -> np.ndarray:
    """(len(s),): one source's estimate at speed ratios squared ``s`` of its settings
    ``rows`` (positions in ``src.idx``; None: all): without gravity the ratio does not
    depend on the histories' scale, so the unit spectra serve."""
    whole = rows is None or rows.size == src.idx.size
    take = (lambda a: a) if whole else (lambda a: a[rows])  # noqa: E731
    P_inertia, C_inertia = take(src.P_inertia), take(src.C_inertia)
    speed = speed0 * np.sqrt(s)
    if src.P_gravity is None:
        peak = np.abs(C_inertia).max(axis=-2)
        filtered = one_mode_peak(P_inertia, src.steps, speed, src.hz, damping)
    else:
        assert src.C_gravity is not None  # a gravity spectrum comes with its history
        P_gravity, C_gravity = take(src.P_gravity), take(src.C_gravity)
        peak = np.abs(s[:, None, None] * C_inertia + C_gravity).max(axis=-2)
        filtered = one_mode_peak(s[:, None, None] * P_inertia + P_gravity, src.steps, speed, src.hz, damping)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(peak > 0, filtered / np.where(peak > 0, peak, 1.0), 1.0)
    return largest_significant(ratio, peak, src.n_forces)


def _key_groups(model, bar_lengths: np.ndarray | None, n_set: int) -> list[tuple[np.ndarray, object]]:
    """[(setting indices, hole-pair key)]: the settings grouped by the hole pair their bar
    length uses (one group, key None, for a part on no bar)."""
    if bar_lengths is None:
        return [(np.arange(n_set), None)]
    um, inverse = np.unique(np.round(bar_lengths * 1e6).astype(np.int64), return_inverse=True)
    return [(np.flatnonzero(inverse == i), model.key_for(u / 1e6)) for i, u in enumerate(um)]


def with_estimates(ctx: SweepContext, results: dict, amps: dict) -> dict:
    """``results`` (part -> (vm, fatigue, tip, amplification, utilisation)) with each
    certified part's estimate as its amplification and its ``quasi-static`` criterion in
    the utilisation; the quasi-static figures as they are."""
    out = dict(results)
    for name, amp in amps.items():
        vm, fat, tip, _, _ = results[name]
        out[name] = (vm, fat, tip, amp, utilisation(ctx.models[name], vm, fat, tip, amp))
    return out


def with_margin(ctx: SweepContext, results: dict, amps: dict) -> dict:
    """``results`` with each certified part's quasi-static figures amplified by its
    estimate (stress and deflection times it, fatigue factor over it): the safe speed's
    conservative side."""
    out = dict(results)
    for name, amp in amps.items():
        vm, fat, tip, _, _ = results[name]
        u = np.max(list(margin_utilisations(ctx.models[name].limits, vm, fat, tip, amp).values()), axis=0)
        out[name] = (vm * amp, fat / amp, tip * amp, amp, u)
    return out


def margin_governs(ctx: SweepContext, results: dict) -> tuple[np.ndarray, np.ndarray]:
    """(part, criterion) that sets the safe speed in :func:`with_margin` ``results``: the
    part whose estimate is nearest its tolerance when that share exceeds every other
    criterion's utilisation (``quasi-static``), else :func:`governing_of`'s."""
    part, criterion = governing_of(ctx, results)
    shares = {n: quasi_static_share(r[3]) for n, r in results.items() if ctx.models[n].certified}
    if not shares:
        return part, criterion
    names = list(shares)
    stacked = np.array([shares[n] for n in names])
    k = np.argmax(stacked, axis=0)
    best = stacked[k, np.arange(stacked.shape[1])]
    others = np.max([governing_value(ctx, r, n) for n, r in results.items()], axis=0)
    validity = best >= others
    return np.where(validity, np.array(names, dtype=object)[k], part), np.where(validity, "quasi-static", criterion)


def governing_value(ctx: SweepContext, result: tuple, name: str) -> np.ndarray:
    """(S,) a part's largest utilisation without the certificate's share."""
    vm, fat, tip, amp, _ = result
    crits = criterion_utilisations(ctx.models[name], vm, fat, tip, amp)
    crits.pop("quasi-static", None)
    return np.max([np.where(np.isnan(u), -np.inf, u) for u in crits.values()], axis=0)


#: Illinois iterations refining the safe speed with the estimate's margin
MARGIN_REFINE = 14


def safe_ratio_sq_with_margin(margin, upper: np.ndarray, n: int) -> np.ndarray:
    """The speed ratio squared ``s`` at which the largest utilisation of ``margin(s)``
    (:func:`with_margin` results) reaches 1, vectorised over the settings: 0 where the rig
    fails at rest, inf where no ``s`` up to 2^40 reaches it. ``upper``: the quasi-static
    safe ``s`` (inf where unlimited), where the margin's utilisation is already at least 1
    (the estimate is at least 1), so the crossing lies in [0, upper]; below the first
    resonance the estimate grows with the speed, and the tolerance is reached well before
    it, so the crossing is single and regula falsi (Illinois) refines it."""

    def worst(s):
        return worst_utilisation(margin(s))

    u0 = worst(np.zeros(n))
    hi = np.where(np.isfinite(upper) & (upper > 0), upper, 1.0)
    u_hi = worst(hi)
    for _ in range(40):  # unlimited quasi-statically: the estimate's tolerance bounds the speed
        short = ~(u_hi > 1.0)
        if not np.any(short):
            break
        hi = np.where(short, 2.0 * hi, hi)
        u_hi = np.where(short, worst(hi), u_hi)
    r = illinois(lambda r: worst(r**2), np.zeros(n), u0, np.sqrt(hi), u_hi, MARGIN_REFINE)
    return np.where(u0 > 1.0, 0.0, np.where(u_hi > 1.0, r**2, np.inf))


def share_crossing(share_of, n: int, iterations: int = 60) -> np.ndarray:
    """(n,) the speed ratio squared at which the largest certified estimate's share
    ``share_of(s, idx)`` (of the settings ``idx`` at their ``s``; no FE: the load spectra
    alone) reaches 1 (:func:`railcheck.model.crossing.increasing_crossing`): below the first
    resonance the estimate grows with the speed, so the crossing is single."""
    return increasing_crossing(share_of, n, iterations)


def scattered(full: dict, idx: np.ndarray, part: dict) -> dict:
    """``full`` (part -> tuple of (n,) arrays) with the settings ``idx`` taken from
    ``part`` (part -> tuple of (len(idx),) arrays); a new dict of new arrays."""
    out = {}
    for name, arrays in full.items():
        merged = tuple(np.array(a, copy=True) for a in arrays)
        for m, p in zip(merged, part[name]):
            m[idx] = p
        out[name] = merged
    return out


def certified_safe_ratio_sq(ctx: SweepContext, margin_of, share_of, n: int, u1: np.ndarray) -> tuple[np.ndarray, dict]:
    """(safe s (n,), :func:`with_margin` results at it) for loads ``C_g + s C_i`` (convex
    in s) with the estimate as a margin: ``margin_of(s, idx)`` the margin results of the
    settings ``idx`` at their ``s``, ``share_of(s, idx)`` the largest estimate's share of
    the settings ``idx`` (no FE),
    ``u1`` the margin utilisation at s = 1. The estimate's crossing ``s_q``
    (:func:`share_crossing`) bounds the safe speed; one FE evaluation there settles every
    setting whose other criteria stay within their limits at rest and at ``s_q`` (convex:
    within them in between), the safe speed ``s_q``. The others' crossing lies below
    ``s_q`` (or beyond, with no estimate's crossing) and is refined from the points 0, 1
    and ``s_q`` (:func:`refine_crossing`); one more evaluation gives their results."""
    every = np.arange(n)
    s_q = share_crossing(share_of, n)
    at_q = margin_of(np.where(np.isfinite(s_q), s_q, 1.0), every)
    u0 = worst_utilisation(margin_of(np.zeros(n), every))
    other = np.max([governing_value(ctx, r, name) for name, r in at_q.items()], axis=0)
    settled = np.isfinite(s_q) & (other <= 1.0) & (u0 <= 1.0)
    safe = np.where(u0 > 1.0, 0.0, s_q)
    rest = np.flatnonzero(~settled & (u0 <= 1.0))
    if rest.size == 0:
        return safe, at_q
    bounded = rest[np.isfinite(s_q[rest])]
    if bounded.size:  # the crossing lies in [0, s_q], or in [1, s_q] where the rig passes at 1
        one_below = u1[bounded] <= 1.0
        lower = (np.where(one_below, 1.0, 0.0), np.where(one_below, u1[bounded], u0[bounded]))
        third = (np.where(one_below, 0.0, 1.0), np.where(one_below, u0[bounded], u1[bounded]))
        upper = (s_q[bounded], np.maximum(other[bounded], 1.0 + CROSSING_TOLERANCE))
        sub = lambda s, j: worst_utilisation(margin_of(s, bounded[j]))  # noqa: E731
        every_b = np.ones(bounded.size, dtype=bool)
        safe[bounded] = refine_crossing(sub, lower, upper, third, every_b, 40)
    unbounded = rest[~np.isfinite(s_q[rest])]
    if unbounded.size:  # no estimate's crossing: the criteria's own, from the secant through 0 and 1
        sub_at = lambda s, j: margin_of(s, unbounded[j])  # noqa: E731
        safe[unbounded] = safe_ratio_sq_convex(sub_at, unbounded.size, u1[unbounded])
    finite = rest[np.isfinite(safe[rest])]
    at_safe = at_q if finite.size == 0 else scattered(at_q, finite, margin_of(safe[finite], finite))
    return safe, at_safe
