"""Configuration checks of the rig (seed 000, 3.3.1-3.3.6), each a named result.

All lengths in m, angles in rad; messages state values in mm and degrees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .linkage import FourBar, SliderCrank
from .motion import fourbar_toggle_margins, triangle_angle


@dataclass(frozen=True)
class CheckLimits:
    """Limits of the configuration checks (seed 000 final values)."""

    mu_min: float = math.radians(35.0)  # 3.3.6
    mu_max: float = math.radians(145.0)  # 3.3.6
    collision_ground: float = 0.660  # Anexo I: d > 660 mm for the 700 mm crank rail
    hole_pitch: float = 0.060  # 3.3.4: rail holes every 60 mm
    grid_tolerance: float = 1e-6  # m


@dataclass(frozen=True)
class CheckResult:
    ok: bool
    message: str


def grashof_class(linkage: FourBar) -> str:
    """Grashof class of a four-bar: s + l vs p + q, and which bar is the shortest."""
    lengths = linkage.lengths
    ordered = sorted(lengths.values())
    s, p, q, l = ordered[0], ordered[1], ordered[2], ordered[3]
    lhs, rhs = s + l, p + q
    tol = 1e-12 * rhs
    if abs(lhs - rhs) <= tol:
        return "change-point (s + l = p + q)"
    if lhs > rhs:
        return "non-Grashof (triple rocker)"
    shortest = min(lengths, key=lengths.__getitem__)
    return {
        "crank": "Grashof crank-rocker",
        "ground": "Grashof double-crank",
        "coupler": "Grashof double-rocker",
        "rocker": "Grashof rocker-crank",
    }[shortest]


def transmission_extremes(linkage: FourBar | SliderCrank) -> tuple[float, float]:
    """(mu_min, mu_max) in rad over a revolution (eq. 2.5 at crank angles 0 and 180 deg)."""
    if isinstance(linkage, FourBar):
        return fourbar_toggle_margins(linkage)
    b2, b3, e = linkage.crank, linkage.coupler, abs(linkage.offset)
    mu_min = math.acos(min(1.0, (b2 + e) / b3))
    mu_max = math.pi / 2 - math.asin(max(0.0, (e - b2)) / b3) if e > b2 else math.pi / 2
    return mu_min, mu_max


def fourbar_checks_batch(crank, coupler, rocker, ground, limits: CheckLimits = CheckLimits()) -> dict:
    """Pass flags of the four-bar checks for arrays of settings (lengths m, any shape):
    ``assembly``, ``grashof`` (crank-rocker), ``transmission_angle``, ``crank_rail_collision``,
    ``hole_grid``; plus ``mu_min``, ``mu_max`` (rad, NaN where the linkage does not close).
    The one place of the checks' logic: :func:`configuration_checks` reads its flags here."""
    b2, b3, b4, d = np.broadcast_arrays(*(np.asarray(x, float) for x in (crank, coupler, rocker, ground)))
    L = np.stack([b2, b3, b4, d])
    ordered = np.sort(L, axis=0)
    longest, rest = ordered[3], L.sum(axis=0) - ordered[3]
    s_l, p_q = ordered[0] + ordered[3], ordered[1] + ordered[2]
    tie = np.abs(s_l - p_q) <= 1e-12 * p_q
    crank_shortest = b2 <= ordered[0]  # ties: as grashof_class, the crank is named first
    mu_min, mu_max = triangle_angle(b3, b4, np.abs(d - b2)), triangle_angle(b3, b4, d + b2)
    with np.errstate(invalid="ignore"):
        transmission = (mu_min > limits.mu_min) & (mu_max < limits.mu_max)
    return {
        "assembly": longest < rest,
        "grashof": (s_l < p_q) & ~tie & crank_shortest,
        "transmission_angle": transmission,
        "crank_rail_collision": d > limits.collision_ground,
        "hole_grid": _on_grid_batch([b2, b3, b4, d], limits),
        "mu_min": mu_min,
        "mu_max": mu_max,
    }


def slidercrank_checks_batch(crank, coupler, offset, limits: CheckLimits = CheckLimits()) -> dict:
    """Pass flags of the slider-crank checks for arrays of settings (m): ``assembly``,
    ``crank_shorter_than_coupler``, ``transmission_angle``, ``hole_grid``; ``mu_min``,
    ``mu_max`` (rad)."""
    b2, b3, e = np.broadcast_arrays(*(np.asarray(x, float) for x in (crank, coupler, offset)))
    e = np.abs(e)
    with np.errstate(invalid="ignore"):
        mu_min = np.arccos(np.minimum(1.0, (b2 + e) / b3))
        mu_max = np.where(e > b2, np.pi / 2 - np.arcsin(np.clip((e - b2) / b3, 0.0, 1.0)), np.pi / 2)
    return {
        "assembly": b2 + e < b3,
        "crank_shorter_than_coupler": b2 < b3,
        "transmission_angle": mu_min > limits.mu_min,
        "hole_grid": _on_grid_batch([b2, b3], limits),
        "mu_min": mu_min,
        "mu_max": mu_max,
    }


def _on_grid_batch(lengths: list, limits: CheckLimits) -> np.ndarray:
    ok = np.array(True)
    for x in lengths:
        ok = ok & (np.abs(x - np.round(x / limits.hole_pitch) * limits.hole_pitch) <= limits.grid_tolerance)
    return ok


def _on_grid(length: float, limits: CheckLimits) -> bool:
    k = round(length / limits.hole_pitch)
    return abs(length - k * limits.hole_pitch) <= limits.grid_tolerance


def configuration_checks(linkage: FourBar | SliderCrank, limits: CheckLimits = CheckLimits()) -> dict[str, CheckResult]:
    """The named checks: assembly, grashof, transmission_angle, crank_rail_collision,
    hole_grid (four-bar); assembly, crank_shorter_than_coupler, transmission_angle,
    hole_grid (slider-crank). Pass flags from :func:`fourbar_checks_batch` /
    :func:`slidercrank_checks_batch`; this adds the messages."""
    mm = {k: v * 1e3 for k, v in linkage.lengths.items()}
    if isinstance(linkage, FourBar):
        flags = {
            k: bool(v)
            for k, v in fourbar_checks_batch(linkage.crank, linkage.coupler, linkage.rocker, linkage.ground, limits).items()
            if k not in ("mu_min", "mu_max")
        }
        messages = _fourbar_messages(linkage, limits, mm)
    else:
        flags = {
            k: bool(v)
            for k, v in slidercrank_checks_batch(linkage.crank, linkage.coupler, linkage.offset, limits).items()
            if k not in ("mu_min", "mu_max")
        }
        messages = _slidercrank_messages(linkage, limits, mm)
    off_grid = [f"{k} {mm[k]:.6g} mm" for k, v in linkage.lengths.items() if k != "offset" and not _on_grid(v, limits)]
    messages["hole_grid"] = (
        (f"not on the {limits.hole_pitch * 1e3:g} mm hole grid: " + ", ".join(off_grid))
        if off_grid
        else f"every bar length is a multiple of {limits.hole_pitch * 1e3:g} mm"
    )
    return {name: CheckResult(flags[name], messages[name]) for name in flags}


def _fourbar_messages(linkage: FourBar, limits: CheckLimits, mm: dict) -> dict[str, str]:
    lengths = linkage.lengths
    longest = max(lengths, key=lengths.__getitem__)
    rest = sum(lengths.values()) - lengths[longest]
    b2, b3, b4, d = linkage.crank, linkage.coupler, linkage.rocker, linkage.ground
    mu_min, mu_max = transmission_extremes(linkage)
    transmission = (
        "the linkage does not close at crank angle 0 or 180 deg"
        if math.isnan(mu_min) or math.isnan(mu_max)
        else f"min {math.degrees(mu_min):.2f} deg, max {math.degrees(mu_max):.2f} deg "
        f"(limits {math.degrees(limits.mu_min):g} < mu < {math.degrees(limits.mu_max):g} deg)"
    )
    return {
        "assembly": f"longest bar ({longest}) {mm[longest]:.6g} mm vs sum of the others {rest * 1e3:.6g} mm",
        "grashof": f"{grashof_class(linkage)}; the crank revolves fully when it is the shortest bar and "
        f"s + l < p + q (seed form b2 + d < b3 + b4: {(b2 + d) * 1e3:.6g} < {(b3 + b4) * 1e3:.6g} mm)",
        "transmission_angle": transmission,
        "crank_rail_collision": f"ground {mm['ground']:.6g} mm must exceed {limits.collision_ground * 1e3:.6g} mm "
        "so the crank rail clears the rocker's pivot",
    }


def _slidercrank_messages(linkage: SliderCrank, limits: CheckLimits, mm: dict) -> dict[str, str]:
    b2, b3 = linkage.crank, linkage.coupler
    mu_min, mu_max = transmission_extremes(linkage)
    return {
        "assembly": f"crank + |offset| {(b2 + abs(linkage.offset)) * 1e3:.6g} mm vs coupler {b3 * 1e3:.6g} mm",
        "crank_shorter_than_coupler": f"crank {mm['crank']:.6g} mm < coupler {mm['coupler']:.6g} mm (seed 3.3.1)",
        "transmission_angle": f"min {math.degrees(mu_min):.2f} deg = acos((crank + |offset|)/coupler), max "
        f"{math.degrees(mu_max):.2f} deg (limit mu > {math.degrees(limits.mu_min):g} deg)",
    }


__all__ = [
    "CheckLimits",
    "CheckResult",
    "configuration_checks",
    "fourbar_checks_batch",
    "grashof_class",
    "slidercrank_checks_batch",
    "transmission_extremes",
    "triangle_angle",
]
