"""A part's criteria as shares of their limits: the one definition the check (one setting,
floats) and the sweep (arrays over the settings) both use, so a sweep row's utilisation is
the check's by construction.

Every function is elementwise in the figures: ``vm`` the cycle's von Mises peak (Pa),
``fat`` the least fatigue safety factor, ``tip`` the largest deflection (m), ``amp`` the
dynamic amplification (with a dynamic response) or the certificate's one-mode estimate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from railcheck.model.certificate import QUASI_STATIC_TOLERANCE, dynamic_share, small_displacement_limit


@dataclass(frozen=True)
class Limits:
    """What a part is judged against (SI).

    Parameters
    ----------
    stress : Pa, the verdict's stress limit (sigma_u / 2 by default).
    fatigue_required : the fatigue safety factor the part needs.
    deflection : m, the deflection limit, or None (not limited).
    yield_strength : Pa, the material's yield strength (0: none known; no yield criterion).
    length : m, the part's length (the small displacements' limit; 0: none).
    max_amplification : the largest dynamic amplification allowed, or None (no dynamic
        response computed).
    certified : True where the quasi-static verdict rests on the certificate's estimate
        (a sweep's part with loads varying over the cycle and no dynamic response): beyond
        its tolerance the part has no quasi-static verdict (``quasi-static`` criterion).
    """

    stress: float
    fatigue_required: float
    deflection: float | None
    yield_strength: float
    length: float
    max_amplification: float | None = None
    certified: bool = False


def quasi_static_share(amp, beyond_only: bool = False):
    """The certificate's estimate ``amp`` as a share of its tolerance's excess over 1,
    ``(A - 1) / (A_tol - 1)``; ``beyond_only``: 0 where the estimate is within the
    tolerance (there the quasi-static verdict stands and the share is no utilisation)."""
    share = (amp - 1.0) / (QUASI_STATIC_TOLERANCE - 1.0)
    return np.where(amp > QUASI_STATIC_TOLERANCE, share, 0.0) if beyond_only else share


def criterion_utilisations(limits: Limits, vm, fat, tip, amp=None) -> dict:
    """criterion -> its share of the limit (1 = at the limit): ``stress`` (peak / limit),
    ``fatigue`` (required / factor; inf for a factor of 0), ``deflection`` (with a limit),
    ``yield`` (peak / yield strength: beyond 1 the linear result is not physical),
    ``small-displacement`` (deflection / its share of the length: beyond 1 the linear
    result is not valid), ``dynamic`` (with a dynamic response: the amplification's excess
    over 1 as a share of the allowed excess) or, certified, ``quasi-static`` (the estimate's
    share where it is beyond the tolerance). The words of ``railcheck check``."""
    vm, fat, tip = (np.asarray(x, dtype=float) for x in (vm, fat, tip))
    with np.errstate(divide="ignore"):
        out = {"stress": vm / limits.stress, "fatigue": limits.fatigue_required / fat}
    if limits.deflection is not None:
        out["deflection"] = tip / limits.deflection
    if limits.yield_strength > 0:
        out["yield"] = vm / limits.yield_strength
    if limits.length > 0:
        out["small-displacement"] = tip / small_displacement_limit(limits.length)
    if limits.max_amplification is not None and amp is not None:
        out["dynamic"] = dynamic_share(amp, limits.max_amplification)
    elif limits.certified and amp is not None:
        out["quasi-static"] = quasi_static_share(np.asarray(amp, dtype=float), beyond_only=True)
    return out


def utilisation(limits: Limits, vm, fat, tip, amp=None):
    """The largest of :func:`criterion_utilisations`."""
    return np.max(list(criterion_utilisations(limits, vm, fat, tip, amp).values()), axis=0)


def margin_utilisations(limits: Limits, vm, fat, tip, estimate) -> dict:
    """The safe speed's conservative side for a certified part: its quasi-static figures
    amplified by the certificate's ``estimate`` (stress and deflection times it, the fatigue
    factor over it) and the estimate's whole share of its tolerance (``quasi-static``)."""
    estimate = np.asarray(estimate, dtype=float)
    u = criterion_utilisations(limits, vm * estimate, fat / estimate, tip * estimate, estimate)
    u["quasi-static"] = quasi_static_share(estimate)
    return u


def failed_criteria(limits: Limits, vm, fat, tip, amp=None) -> dict:
    """criterion -> True where it fails: ``stress`` above the limit, ``fatigue`` below the
    required factor, ``deflection`` above its limit, ``beyond yield``, ``beyond small
    displacements``, ``dynamic`` an amplification above the largest allowed, ``quasi-static``
    an estimate above the certificate's tolerance; the words of ``railcheck check``'s failures."""
    out = {"stress": vm > limits.stress, "fatigue": fat < limits.fatigue_required}
    if limits.deflection is not None:
        out["deflection"] = tip > limits.deflection
    if limits.yield_strength > 0:
        out["beyond yield"] = vm > limits.yield_strength
    if limits.length > 0:
        out["beyond small displacements"] = tip > small_displacement_limit(limits.length)
    if limits.max_amplification is not None and amp is not None:
        out["dynamic"] = amp > limits.max_amplification
    elif limits.certified and amp is not None:
        out["quasi-static"] = amp > QUASI_STATIC_TOLERANCE
    return out
