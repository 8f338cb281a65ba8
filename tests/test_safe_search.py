"""The safe speed's searches against closed-form crossings: a von Mises peak of
``C_g + s C_i`` at one node is ``sqrt(a + b s + c s^2)``, whose crossing of 1 is a root of
a quadratic; a setting's answer does not depend on the settings it is searched with."""

from __future__ import annotations

import numpy as np

from railcheck.sweep.validity import share_crossing
from railcheck.sweep.verdicts import CROSSING_TOLERANCE, safe_ratio_sq_convex


def _quadratics(n: int, seed: int = 3):
    """(a, b, c) of ``u(s)^2 = a + b s + c s^2`` = |g + s i|^2 for random g, i (6 components)."""
    rng = np.random.default_rng(seed)
    g, i = rng.normal(size=(n, 6)), rng.normal(size=(n, 6))
    g *= rng.uniform(0.05, 0.9, (n, 1)) / np.linalg.norm(g, axis=1, keepdims=True)  # at rest within the limit
    i *= rng.uniform(0.05, 3.0, (n, 1)) / np.linalg.norm(i, axis=1, keepdims=True)
    return (g * g).sum(1), 2 * (g * i).sum(1), (i * i).sum(1)


def _root(a, b, c):
    """The positive s where a + b s + c s^2 = 1 (a < 1)."""
    return (-b + np.sqrt(b * b - 4 * c * (a - 1.0))) / (2 * c)


def test_convex_search_finds_the_quadratic_crossing_and_counts_few_evaluations():
    a, b, c = _quadratics(300)
    calls = []

    def at(s, idx):
        calls.append(idx.size)
        return {"part": (None, None, None, None, np.sqrt(a[idx] + b[idx] * s + c[idx] * s * s))}

    u1 = np.sqrt(a + b + c)
    s = safe_ratio_sq_convex(at, a.size, u1)
    u = np.sqrt(a + b * s + c * s * s)
    assert np.all(np.abs(u - 1.0) < 10 * CROSSING_TOLERANCE)
    assert np.allclose(s, _root(a, b, c), rtol=1e-7)
    assert sum(calls) < 6 * a.size  # rest, the secant's guess, a step or two (one on a single node)


def test_share_crossing_is_the_same_whatever_settings_it_is_searched_with():
    a, b, c = _quadratics(200, seed=5)
    share = lambda sub: lambda s, i: np.sqrt(a[sub][i] + b[sub][i] * s + c[sub][i] * s * s)  # noqa: E731
    whole = share_crossing(share(np.arange(200)), 200)
    part = share_crossing(share(np.arange(0, 200, 3)), np.arange(0, 200, 3).size)
    assert np.array_equal(whole[::3], part)
    assert np.allclose(whole, _root(a, b, c), rtol=1e-7)


def test_share_crossing_is_infinite_where_the_estimate_never_reaches_its_tolerance():
    s = share_crossing(lambda s, i: np.full(np.shape(i), 0.5), 4)
    assert np.all(np.isinf(s))


def test_share_crossing_brackets_a_one_mode_estimate_in_one_step_and_counts_few_evaluations():
    # the one-mode estimate's excess 1 / (1 - s / s_r) - 1 over a tolerance t: convex in s,
    # crossing at s_r t / (1 + t); resonances from 4x to 3000x the reference speed squared
    rng = np.random.default_rng(11)
    n, t = 300, 0.05
    s_r = 10.0 ** rng.uniform(0.6, 3.5, n)
    rows = []

    def share(s, idx):
        rows.append(idx.size)
        return (1.0 / (1.0 - s / s_r[idx]) - 1.0) / t

    s = share_crossing(share, n)
    assert np.allclose(s, s_r * t / (1.0 + t), rtol=1e-7)
    assert sum(rows) <= 7 * n  # rest, s = 1, one extrapolation, a few refining steps
