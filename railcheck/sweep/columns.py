"""A chunk's table columns at one speed: each part's and component's figures, the
utilisation and what governs, the safe speed, the verdict and its reason. SI inside,
units in the column names."""

from __future__ import annotations

import math

import numpy as np

from railcheck.components.ratings import COMPONENTS
from railcheck.sweep.components import swept_components
from railcheck.sweep.context import SweepContext
from railcheck.sweep.verdicts import failed_criteria, governing_of


def fe_columns(ctx: SweepContext, n: int, fe, j: int, passed: np.ndarray, checks: dict) -> dict:
    """Per-part and per-component columns at the ``j``-th speed, the utilisation,
    governing part, safe speed, verdict and reason."""
    col: dict[str, np.ndarray] = {}
    worst, governing = np.full(n, np.nan), np.full(n, "", dtype=object)
    failing: dict[int, list[str]] = {}  # setting -> its failed criteria, in the parts' order
    for name, m in ctx.models.items():
        vm, fat, tip, amp, u = (np.full(n, np.nan) for _ in range(5))
        if fe is not None:
            at, res = fe
            vm[at], fat[at], tip[at], amp[at], u[at] = res["per_speed"][j][name]
            for failed, fails in failed_criteria(m, vm[at], fat[at], tip[at], amp[at]).items():
                for i in at[fails]:
                    failing.setdefault(int(i), []).append(f"{name} {failed}")
        col[f"{name}_stress_MPa"], col[f"{name}_fatigue"] = vm / 1e6, fat
        col[f"{name}_tip_mm"], col[f"{name}_utilisation"] = tip * 1e3, u
        if m.dynamic is not None:
            col[f"{name}_amplification"] = amp
        elif m.certified and m.constant is None:
            col[f"{name}_amplification_estimate"] = amp
        better = np.isfinite(u) & ~(u <= worst)
        worst, governing = np.where(better, u, worst), np.where(better, name, governing)
    safe = np.full(n, np.nan)
    criterion, safe_part, safe_criterion = (np.full(n, "", dtype=object) for _ in range(3))
    if fe is not None:
        at, res = fe
        safe[at] = ctx.speeds[0] * np.sqrt(res["safe_s"]) / (2 * math.pi)
        safe_part[at], safe_criterion[at] = res["safe_governs"]
        if res["per_speed"][j]:
            criterion[at] = governing_of(ctx, res["per_speed"][j])[1]
    worst, governing, criterion = _component_columns(ctx, col, n, fe, j, (worst, governing, criterion), failing)
    col["utilisation"], col["governing_part"], col["governing_criterion"] = worst, governing, criterion
    col["safe_speed_Hz"], col["safe_speed_part"], col["safe_speed_criterion"] = safe, safe_part, safe_criterion
    col["safe_speed_unlimited"] = np.isinf(safe)  # the table holds null for the infinite speed
    fails = np.zeros(n, dtype=bool)
    fails[list(failing)] = True
    reason = refusal_reasons(checks, n)  # object: any length
    reason[passed] = ""
    for i, criteria in failing.items():
        if passed[i]:
            reason[i] = ", ".join(criteria)
    verdict = np.where(~passed, "refused", np.where(fails, "fail", "pass"))
    col["verdict"], col["reason"] = verdict.astype(object), reason
    return col


def refusal_reasons(checks: dict[str, np.ndarray], n: int) -> np.ndarray:
    """(n,) object: each setting's failed configuration checks, comma-separated in the
    checks' order ("" where none fails); each distinct combination is joined once."""
    names = list(checks)
    code = np.zeros(n, dtype=np.int64)
    for bit, name in enumerate(names):
        code |= (~np.asarray(checks[name], dtype=bool)).astype(np.int64) << bit
    combos, which = np.unique(code, return_inverse=True)
    text = [", ".join(name for bit, name in enumerate(names) if combo >> bit & 1) for combo in combos.tolist()]
    return np.array(text, dtype=object)[which.reshape(-1)]


def _component_columns(ctx: SweepContext, col: dict, n: int, fe, j: int, governs: tuple, failing: dict) -> tuple:
    """Each listed component's utilisation column at the ``j``-th speed (NaN where a
    setting is not checked: every chunk writes the same columns); ``governs`` (worst,
    part, criterion) updated where a component's utilisation is the larger, and its failed
    criteria added to ``failing``."""
    worst, governing, criterion = (np.array(a, copy=True) for a in governs)
    at, per = (np.zeros(0, dtype=np.int64), {}) if fe is None else (fe[0], fe[1].get("components", [{}] * (j + 1))[j])
    for name in swept_components(ctx):
        u, crit, needs = np.full(n, np.nan), np.full(n, "", dtype=object), np.full(n, "", dtype=object)
        if name in per:
            u_at, crit_at, failed_at, needs_at = per[name]
            u[at], crit[at], needs[at] = u_at, crit_at, needs_at
            for i, why in zip(at[failed_at != ""], failed_at[failed_at != ""]):
                failing.setdefault(int(i), []).append(f"{name} {why}")
        col[f"{name}_utilisation"] = u
        if COMPONENTS[name].kind == "screws":
            col[f"{name}_needs"] = needs  # the smallest screw that passes ("" where not checked)
        elif COMPONENTS[name].kind == "shaft":  # the least diameter that passes (NaN where not checked)
            col[f"{name}_diameter_needed_mm"] = np.where(needs == "", np.nan, needs).astype(float) * 1e3
        elif COMPONENTS[name].kind == "bearings":  # the least spacing that passes (NaN where not checked)
            col[f"{name}_spacing_needed_mm"] = np.where(needs == "", np.nan, needs).astype(float) * 1e3
        better = np.isfinite(u) & ~(u <= worst)
        worst, governing = np.where(better, u, worst), np.where(better, name, governing)
        criterion = np.where(better, crit, criterion)
    return worst, governing, criterion
