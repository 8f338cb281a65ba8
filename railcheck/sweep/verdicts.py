"""A setting's verdict in the sweep: each criterion's utilisation (the words of
``railcheck check``), what governs, which criteria fail, and the safe speed: the speed ratio
squared ``s = (omega / omega_0)^2`` at which the largest utilisation reaches 1, in closed
form when every result scales with ``s`` (no gravity, no dynamic response), else searched
(a scan, then the Illinois method). SI.
"""

from __future__ import annotations

import numpy as np

from railcheck.model import utilisation as core
from railcheck.model.crossing import CROSSING_TOLERANCE, refine_crossing
from railcheck.sweep.context import SweepContext


def criterion_utilisations(model, vm, fat, tip, amp=None) -> dict[str, np.ndarray]:
    """criterion -> (S,) its share of the limit for the sweep's ``model`` (a PartModel):
    :func:`railcheck.model.utilisation.criterion_utilisations` of its limits."""
    return core.criterion_utilisations(model.limits, vm, fat, tip, amp)


def utilisation(model, vm, fat, tip, amp=None) -> np.ndarray:
    """The largest of :func:`criterion_utilisations`."""
    return core.utilisation(model.limits, vm, fat, tip, amp)


def worst_utilisation(results: dict) -> np.ndarray:
    """(S,) the largest utilisation over the parts of results (part -> (..., utilisation))."""
    return np.max([u for *_, u in results.values()], axis=0)


def governing_of(ctx: SweepContext, results: dict) -> tuple[np.ndarray, np.ndarray]:
    """(part, criterion) (S,) object arrays: what has the largest utilisation in
    ``results`` (part -> (vm, fatigue, tip, utilisation))."""
    names, crits, values = [], [], []
    for name, (vm, fat, tip, amp, _) in results.items():
        for crit, u in criterion_utilisations(ctx.models[name], vm, fat, tip, amp).items():
            names.append(name)
            crits.append(crit)
            values.append(np.where(np.isnan(u), -np.inf, u))
    k = np.argmax(np.array(values), axis=0)
    return np.array(names, dtype=object)[k], np.array(crits, dtype=object)[k]


def scaled_results(ctx: SweepContext, base: dict, s) -> dict:
    """Results at speed ratio squared ``s`` from those at 1, without gravity and without
    a dynamic response (module doc)."""
    out = {}
    for name, (vm, fat, tip, amp, _) in base.items():
        m = ctx.models[name]
        if m.constant is None:
            with np.errstate(divide="ignore"):  # at rest (s = 0) the fatigue factor is infinite
                vm, fat, tip = s * vm, fat / s, s * tip
        out[name] = (vm, fat, tip, amp, utilisation(m, vm, fat, tip, amp))
    return out


def safe_ratio_sq_closed(ctx: SweepContext, base: dict, n: int) -> np.ndarray:
    """Without gravity: every speed-dependent utilisation is ``s u(1)``; constant parts
    (explicit loads) do not change. 0 where a constant part already fails; inf where no
    part depends on speed."""
    u_var = np.zeros(n)
    u_const = np.zeros(n)
    for name, (*_, u) in base.items():
        if ctx.models[name].constant is None:
            u_var = np.maximum(u_var, u)
        else:
            u_const = np.maximum(u_const, u)
    with np.errstate(divide="ignore"):
        safe = np.where(u_var > 0, 1.0 / u_var, np.inf)
    return np.where(u_const > 1.0, 0.0, safe)


#: speeds scanned below the bracketing speed before the root is refined, with a dynamic response
SAFE_SPEED_SCAN = 8


#: regula falsi (Illinois) iterations refining a bracketed crossing with a dynamic response
SAFE_SPEED_REFINE = 10


def safe_ratio_sq_bisect(ctx: SweepContext, at, n: int, iterations: int = 60, scan: int = 0) -> np.ndarray:
    """The ``s`` where the largest utilisation first reaches 1 (vectorised over the
    settings): doubling from 1 until it is exceeded, then bisection; 0 where the rig fails
    at rest, inf where no ``s`` up to 2^60 reaches 1.

    With gravity alone the utilisation grows with ``s`` once inertia dominates (it is
    convex in the loads), so the bracket holds the first crossing. A dynamic response is
    not monotonic in the speed (a harmonic of the crank meets a mode): with ``scan`` > 0
    the first of ``scan`` speeds evenly spaced up to the bracketing one that exceeds 1
    brackets the crossing, and regula falsi (Illinois) refines it. A resonance narrower
    than the scan's spacing (1/``scan`` of the bracketing speed) below that crossing can be
    missed; docs/sweep.md states this."""

    def worst(s):
        return worst_utilisation(at(s))

    fails_at_rest = worst(np.zeros(n)) > 1.0
    lo, hi = np.zeros(n), np.ones(n)
    u_hi = worst(hi)
    for _ in range(60):
        over = u_hi > 1.0
        if np.all(over | fails_at_rest):
            break
        lo, hi = np.where(over, lo, hi), np.where(over, hi, 2.0 * hi)
        u_hi = np.where(over, u_hi, worst(hi))
    unbounded = ~(u_hi > 1.0)
    if not scan:
        for _ in range(iterations):
            mid = 0.5 * (lo + hi)
            over = worst(mid) > 1.0
            lo, hi = np.where(over, lo, mid), np.where(over, mid, hi)
        return np.where(fails_at_rest, 0.0, np.where(unbounded, np.inf, 0.5 * (lo + hi)))
    top = np.sqrt(hi)  # speed ratios from here on: the bracket [a, b] of the first crossing
    a, u_a, b, u_b = np.zeros(n), np.zeros(n), top.copy(), u_hi.copy()
    found = np.zeros(n, dtype=bool)
    for j in range(1, scan + 1):
        r = top * j / scan
        u = worst(r**2)
        over = ~found & (u > 1.0)
        b, u_b = np.where(over, r, b), np.where(over, u, u_b)
        found |= over
        a, u_a = np.where(found, a, r), np.where(found, u_a, u)
    r = illinois(lambda r: worst(r**2), a, u_a, b, u_b, SAFE_SPEED_REFINE)
    return np.where(fails_at_rest, 0.0, np.where(unbounded, np.inf, r**2))


def safe_ratio_sq_convex(at, n: int, u1: np.ndarray, iterations: int = 40) -> np.ndarray:
    """The ``s`` where the largest utilisation of ``at(s, idx)`` (the results of the
    settings ``idx`` at their ``s``) reaches 1, for loads ``C_g + s C_i`` with no dynamic
    response (vectorised over the ``n`` settings; ``u1`` the utilisation at s = 1): each
    criterion is convex in s (a von Mises peak, Goodman's alternating part linear and
    midrange convex), so the secant through s = 0 and 1 brackets the crossing from one side
    (below it inside [0, 1], above it beyond), and :func:`refine_crossing` refines it from
    the three points, each step on the settings not yet within :data:`CROSSING_TOLERANCE`.
    0 where the rig fails at rest, inf where no s up to 2^60 reaches 1."""

    def worst(s, idx):
        return worst_utilisation(at(s, idx))

    every = np.arange(n)
    u0 = worst(np.zeros(n), every)
    with np.errstate(divide="ignore", invalid="ignore"):
        secant = np.where(u1 > u0, (1.0 - u0) / (u1 - u0), np.inf)
    over = u1 > 1.0
    guess = np.where(np.isfinite(secant) & (secant > 0), secant, np.where(over, 0.5, 2.0))
    live = np.flatnonzero(u0 <= 1.0)  # the rig that fails at rest has no crossing to find
    u_guess = np.full(n, np.inf)
    u_guess[live] = worst(guess[live], live)
    below = u_guess <= 1.0  # the guess from inside [0, 1] lies below the crossing (else start from 0)
    a, u_a = np.where(over, np.where(below, guess, 0.0), 1.0), np.where(over, np.where(below, u_guess, u0), u1)
    b, u_b = np.where(over, 1.0, guess), np.where(over, u1, u_guess)
    # the third point: s = 0 or 1, whichever the bracket's ends are not
    x3, u3 = np.where(over & ~below, 1.0, 0.0), np.where(over & ~below, u1, u0)
    for _ in range(60):  # a crossing beyond the secant's guess (not convex after all): doubled
        short = np.flatnonzero(~(u_b > 1.0) & (u0 <= 1.0) & (b < 2.0**60))
        if short.size == 0:
            break
        x3[short], u3[short] = a[short], u_a[short]
        a[short], u_a[short], b[short] = b[short], u_b[short], 2.0 * b[short]
        u_b[short] = worst(b[short], short)
    searched = (u0 <= 1.0) & (u_b > 1.0)
    s = refine_crossing(worst, (a, u_a), (b, u_b), (x3, u3), searched, iterations)
    return np.where(u0 > 1.0, 0.0, np.where(u_b > 1.0, s, np.inf))


def illinois(u_of, a, u_a, b, u_b, iterations: int):
    """Refine brackets ``[a, b]`` (u(a) <= 1 < u(b), vectorised) of ``u(x) = 1`` by regula
    falsi with the Illinois modification (superlinear on smooth crossings, never leaving
    the bracket); returns the end whose utilisation is nearer 1. Stops early once every
    setting's is within :data:`CROSSING_TOLERANCE` of 1."""
    fa, fb, side = u_a - 1.0, u_b - 1.0, np.zeros(a.shape, dtype=int)
    ga, gb = fa.copy(), fb.copy()  # the ends' true values (fa, fb may be halved)
    for _ in range(iterations):
        if np.all(np.minimum(np.abs(ga), np.abs(gb)) < CROSSING_TOLERANCE):
            break
        with np.errstate(invalid="ignore", divide="ignore"):
            x = np.where(fb != fa, b - fb * (b - a) / (fb - fa), 0.5 * (a + b))
        x = np.where((x > a) & (x < b), x, 0.5 * (a + b))
        fx = u_of(x) - 1.0
        over = fx > 0.0
        # the end that stays twice in a row has its value halved (Illinois)
        fa = np.where(over & (side == -1), 0.5 * fa, fa)
        fb = np.where(~over & (side == 1), 0.5 * fb, fb)
        a, fa, ga = np.where(over, a, x), np.where(over, fa, fx), np.where(over, ga, fx)
        b, fb, gb = np.where(over, x, b), np.where(over, fx, fb), np.where(over, fx, gb)
        side = np.where(over, -1, 1)
    return np.where(np.abs(gb) < np.abs(ga), b, a)


def failed_criteria(model, vm: np.ndarray, fat: np.ndarray, tip: np.ndarray, amp=None) -> dict[str, np.ndarray]:
    """criterion -> (S,) True where that criterion fails for the sweep's ``model``:
    :func:`railcheck.model.utilisation.failed_criteria` of its limits."""
    return core.failed_criteria(model.limits, vm, fat, tip, amp)
