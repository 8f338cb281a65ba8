"""Where a utilisation that grows with the speed reaches 1: vectorised over settings
(each searched until its own tolerance, so a setting's answer does not depend on the others
it is computed with). Generic numerics in the speed ratio squared ``s``; used by the
sweep's safe speeds and by a check's components' safe speed."""

from __future__ import annotations

import numpy as np

#: a crossing's search stops where the utilisation is within this of 1
CROSSING_TOLERANCE = 1e-9


def refine_crossing(u_of, lower: tuple, upper: tuple, third: tuple, searched: np.ndarray, iterations: int):
    """The crossings ``u = 1`` in the brackets ``[a, b]`` (``lower`` = (a, u(a)), u(a) <= 1;
    ``upper`` = (b, u(b)), u(b) > 1) of the ``searched`` settings, given a third point
    ``third`` = (x, u(x)) off the bracket's ends: each step fits ``u^2`` by the parabola
    through the last three iterates (Muller's method; exact in one step where one node's
    von Mises governs, since ``|s_i + s s_i|^2`` is quadratic in s), falling back to the
    secant through the last two, then to regula falsi on the bracket, then to its middle,
    whichever first stays inside the bracket; each step evaluates ``u_of(x, idx)`` only on
    the settings not yet within :data:`CROSSING_TOLERANCE` of 1. Returns the bracket's
    end whose utilisation is nearer 1."""
    (a, ua), (b, ub), (x3, u3) = lower, upper, third
    a, b, fa, fb = a.copy(), b.copy(), ua - 1.0, ub - 1.0
    # the last three iterates, oldest first: the third point, then the bracket's ends
    xs = [x3.copy(), a.copy(), b.copy()]
    fs = [u3 - 1.0, fa.copy(), fb.copy()]
    for _ in range(iterations):
        i = np.flatnonzero(searched & (np.minimum(np.abs(fa), np.abs(fb)) >= CROSSING_TOLERANCE))
        if i.size == 0:
            break
        x = _next_iterate([v[i] for v in xs], [v[i] for v in fs], a[i], b[i], fa[i], fb[i])
        fx = u_of(x, i) - 1.0
        over = fx > 0.0
        a[i], fa[i] = np.where(over, a[i], x), np.where(over, fa[i], fx)
        b[i], fb[i] = np.where(over, x, b[i]), np.where(over, fx, fb[i])
        for k in range(2):
            xs[k][i], fs[k][i] = xs[k + 1][i], fs[k + 1][i]
        xs[2][i], fs[2][i] = x, fx
    return np.where(np.abs(fb) < np.abs(fa), b, a)


def _next_iterate(xs: list, fs: list, a, b, fa, fb) -> np.ndarray:
    """The next iterate of :func:`refine_crossing` inside ``(a, b)``: Muller's step on
    ``u^2 - 1`` through the three iterates ``xs``, ``fs`` (``f = u - 1``, oldest first),
    else the secant through the last two, else regula falsi, else the bracket's middle."""
    (x0, x1, x2), (f0, f1, f2) = xs, fs
    g0, g1, g2 = (f * (f + 2.0) for f in (f0, f1, f2))  # u^2 - 1
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        d01, d12 = (g1 - g0) / (x1 - x0), (g2 - g1) / (x2 - x1)
        d2 = (d12 - d01) / (x2 - x0)
        B = d12 + d2 * (x2 - x1)
        root = np.sqrt(B * B - 4.0 * d2 * g2)
        den = np.where(B >= 0.0, B + root, B - root)  # the root nearer x2 (the larger denominator)
        muller = x2 - 2.0 * g2 / den
        secant = x2 - f2 * (x2 - x1) / (f2 - f1)
        falsi = b - fb * (b - a) / (fb - fa)
    x = 0.5 * (a + b)
    for step in (falsi, secant, muller):  # the last inside the bracket wins
        x = np.where((step > a) & (step < b), step, x)
    return x


def increasing_crossing(u_of, n: int, iterations: int = 60) -> np.ndarray:
    """(n,) the speed ratio squared at which ``u_of(s, idx)`` (a utilisation of the
    settings ``idx`` at their ``s``, growing with s) reaches 1: extrapolated from s = 1
    until it is exceeded (:func:`_extrapolation_factor`), then refined
    (:func:`refine_crossing`, each setting until its own tolerance, so a setting's answer
    does not depend on the others it is computed with); each step evaluates only the
    settings still searched. 0 where it exceeds 1 at rest, inf where no s up to 2^60
    reaches it."""
    every = np.arange(n)
    prev, u_prev = np.zeros(n), u_of(np.zeros(n), every)
    lo, u_lo, hi = prev.copy(), u_prev.copy(), np.ones(n)
    u_hi = u_of(hi, every)
    for _ in range(60):
        short = np.flatnonzero(~(u_hi > 1.0) & (hi < 2.0**60))
        if short.size == 0:
            break
        prev[short], u_prev[short] = lo[short], u_lo[short]
        lo[short], u_lo[short] = hi[short], u_hi[short]
        hi[short] *= _extrapolation_factor(u_hi[short])
        u_hi[short] = u_of(hi[short], short)
    crossing = u_hi > 1.0
    s = refine_crossing(u_of, (lo, u_lo), (hi, u_hi), (prev, u_prev), crossing & (u_lo <= 1.0), iterations)
    return np.where(crossing, np.where(u_lo > 1.0, 0.0, s), np.inf)


def _extrapolation_factor(share: np.ndarray) -> np.ndarray:
    """How far to multiply ``s`` to reach a crossing from a point where the utilisation
    is ``share`` (< 1): the line through rest (0 there) says ``1 / share``; where it grows
    faster than ``s`` (the certificate's estimate: the response's excess grows as ``r^2`` of
    a load that grows with ``s``) that line reaches past the crossing. At least doubled, at
    most 2^20 in one step."""
    with np.errstate(divide="ignore"):
        return np.clip(1.0 / np.maximum(share, 0.0), 2.0, 2.0**20)
