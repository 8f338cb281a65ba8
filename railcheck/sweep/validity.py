"""Where the sweep's quasi-static answers hold: each certified part's one-mode amplification
estimate (:mod:`railcheck.model.certificate`) per setting and speed, the ``quasi-static``
criterion it adds to the verdict, and the safe speed with the estimate as a margin.

At a speed of the table, a part's stresses, fatigue factor and deflection are the
quasi-static ones (as ``railcheck check`` gives them) and its ``quasi-static`` utilisation
is the estimate's excess over 1 as a share of the tolerance's: above 1 the quasi-static
verdict is not given (the row fails on ``quasi-static``: check the setting with the
``dynamic`` effect). The safe speed is the largest at which every criterion, the
quasi-static results amplified by the estimate (stress and deflection times it, fatigue
factor over it), stays within its limit and the estimate within the tolerance: the exact
dynamic response there is within it (the certificate is conservative, tested). SI.
"""

from __future__ import annotations

import numpy as np

from railcheck.model.certificate import amplification_estimate
from railcheck.sweep.context import SweepContext
from railcheck.sweep.verdicts import utilisation


def certifying(ctx: SweepContext) -> bool:
    """Whether some part of the sweep carries the certificate."""
    return any(m.certified and m.constant is None for m in ctx.models.values())


def estimates(ctx: SweepContext, histories: dict, lengths: dict, s) -> dict:
    """part -> (S,) the one-mode amplification estimate of every certified part at speed
    ratio squared ``s`` (scalar or (S,)), the largest over its load sources."""
    out = {}
    for name, m in ctx.models.items():
        if not m.certified or m.constant is not None:
            continue
        sources = histories[name]
        n_set = sources[0][1].shape[0]
        ss = np.broadcast_to(np.asarray(s, float), (n_set,))
        amp = np.ones(n_set)
        for idx, key in _key_groups(m, lengths[m.bar] if m.bar else None, n_set):
            speed = ctx.speeds[0] * np.sqrt(ss[idx])
            for Cg, Ci in sources:
                C = ss[idx, None, None] * Ci[idx] + (Cg[idx] if Cg is not None else 0.0)
                est = amplification_estimate(C, m.case_names[key], speed, m.lowest_hz[key], m.damping)
                amp[idx] = np.maximum(amp[idx], est)
        out[name] = amp
    return out


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
        vm, fat, tip = vm * amp, fat / amp, tip * amp
        out[name] = (vm, fat, tip, amp, utilisation(ctx.models[name], vm, fat, tip, amp))
    return out
