"""Configuration checks of the rig (seed 000, 3.3.1-3.3.6), each a named result.

All lengths in m, angles in rad; messages state values in mm and degrees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .linkage import FourBar, SliderCrank
from .motion import fourbar_toggle_margins, triangle_angle


@dataclass(frozen=True)
class CheckLimits:
    """Limits of the configuration checks (seed 000 final values)."""

    mu_min: float = math.radians(35.0)        # 3.3.6
    mu_max: float = math.radians(145.0)       # 3.3.6
    collision_ground: float = 0.660           # Anexo I: d > 660 mm for the 700 mm crank rail
    hole_pitch: float = 0.060                 # 3.3.4: rail holes every 60 mm
    grid_tolerance: float = 1e-6              # m


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
    shortest = min(lengths, key=lengths.get)
    return {"crank": "Grashof crank-rocker", "ground": "Grashof double-crank",
            "coupler": "Grashof double-rocker", "rocker": "Grashof rocker-crank"}[shortest]


def transmission_extremes(linkage: FourBar | SliderCrank) -> tuple[float, float]:
    """(mu_min, mu_max) in rad over a revolution (eq. 2.5 at crank angles 0 and 180 deg)."""
    if isinstance(linkage, FourBar):
        return fourbar_toggle_margins(linkage)
    b2, b3, e = linkage.crank, linkage.coupler, abs(linkage.offset)
    mu_min = math.acos(min(1.0, (b2 + e) / b3))
    mu_max = math.pi / 2 - math.asin(max(0.0, (e - b2)) / b3) if e > b2 else math.pi / 2
    return mu_min, mu_max


def _on_grid(length: float, limits: CheckLimits) -> bool:
    k = round(length / limits.hole_pitch)
    return abs(length - k * limits.hole_pitch) <= limits.grid_tolerance


def configuration_checks(linkage: FourBar | SliderCrank,
                         limits: CheckLimits = CheckLimits()) -> dict[str, CheckResult]:
    """The named checks: assembly, grashof, transmission_angle, crank_rail_collision,
    hole_grid (four-bar); assembly, crank_shorter_than_coupler, transmission_angle,
    hole_grid (slider-crank)."""
    out: dict[str, CheckResult] = {}
    mm = {k: v * 1e3 for k, v in linkage.lengths.items()}
    if isinstance(linkage, FourBar):
        lengths = linkage.lengths
        longest = max(lengths, key=lengths.get)
        rest = sum(lengths.values()) - lengths[longest]
        out["assembly"] = CheckResult(
            lengths[longest] < rest,
            f"longest bar ({longest}) {mm[longest]:.6g} mm vs sum of the others {rest*1e3:.6g} mm")
        cls = grashof_class(linkage)
        b2, b3, b4, d = linkage.crank, linkage.coupler, linkage.rocker, linkage.ground
        out["grashof"] = CheckResult(
            cls == "Grashof crank-rocker",
            f"{cls}; the crank revolves fully when it is the shortest bar and s + l < p + q "
            f"(seed form b2 + d < b3 + b4: {(b2 + d)*1e3:.6g} < {(b3 + b4)*1e3:.6g} mm)")
        mu_min, mu_max = transmission_extremes(linkage)
        if math.isnan(mu_min) or math.isnan(mu_max):
            out["transmission_angle"] = CheckResult(False, "the linkage does not close at crank angle 0 or 180 deg")
        else:
            ok = mu_min > limits.mu_min and mu_max < limits.mu_max
            out["transmission_angle"] = CheckResult(
                ok, f"min {math.degrees(mu_min):.4f} deg, max {math.degrees(mu_max):.4f} deg "
                    f"(limits {math.degrees(limits.mu_min):g} < mu < {math.degrees(limits.mu_max):g} deg)")
        out["crank_rail_collision"] = CheckResult(
            d > limits.collision_ground,
            f"ground {mm['ground']:.6g} mm must exceed {limits.collision_ground*1e3:.6g} mm so the crank rail "
            "clears the rocker's pivot")
    else:
        b2, b3 = linkage.crank, linkage.coupler
        ok = b2 + abs(linkage.offset) < b3
        out["assembly"] = CheckResult(ok, f"crank + |offset| {(b2 + abs(linkage.offset))*1e3:.6g} mm vs coupler "
                                          f"{b3*1e3:.6g} mm")
        out["crank_shorter_than_coupler"] = CheckResult(
            b2 < b3, f"crank {mm['crank']:.6g} mm < coupler {mm['coupler']:.6g} mm (seed 3.3.1)")
        mu_min, mu_max = transmission_extremes(linkage)
        out["transmission_angle"] = CheckResult(
            mu_min > limits.mu_min,
            f"min {math.degrees(mu_min):.4f} deg = acos((crank + |offset|)/coupler), max "
            f"{math.degrees(mu_max):.4f} deg (limit mu > {math.degrees(limits.mu_min):g} deg)")
    off_grid = [f"{k} {mm[k]:.6g} mm" for k, v in linkage.lengths.items()
                if k != "offset" and not _on_grid(v, limits)]
    out["hole_grid"] = CheckResult(
        not off_grid,
        (f"not on the {limits.hole_pitch*1e3:g} mm hole grid: " + ", ".join(off_grid)) if off_grid
        else f"every bar length is a multiple of {limits.hole_pitch*1e3:g} mm")
    return out


__all__ = ["CheckLimits", "CheckResult", "configuration_checks", "grashof_class",
           "transmission_extremes", "triangle_angle"]
