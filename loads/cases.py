"""Load cases per part (seed 000, chapter 4).

For each rail: the peak magnitude of the joint reaction it carries, with the bar angle at
that same instant, projected on the rail's longitudinal and transverse axes; times the
factor (1.4); divided equally over the joint's bolts; applied on each bolt hole. Forces
in N, in the part's own frame (x longitudinal, y transverse in-plane, z normal).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .rotation import to_rail_axes


@dataclass(frozen=True)
class BoltForce:
    """The force (N, part frame) on one bolt hole, named by its mesh group."""

    group: str
    force: tuple[float, float, float]


@dataclass(frozen=True)
class LoadCase:
    """What one part carries: support group, bolt forces, where its tip is, and where the
    numbers came from (``origin``: joint, peak magnitude, crank angle, bar angle, the
    factored components before the split)."""

    part: str
    support: str
    bolts: tuple[BoltForce, ...]
    tip_group: str
    factor: float
    origin: dict = field(default_factory=dict)

    @property
    def total_force(self) -> np.ndarray:
        """Vector sum of the bolt forces (N, part frame)."""
        return np.sum([b.force for b in self.bolts], axis=0)


def peak_in_rail_axes(force_xy: np.ndarray, bar_angle: np.ndarray) -> tuple[int, np.ndarray]:
    """Step of the peak |F| and F at that step in the rail's axes (N)."""
    mag = np.hypot(force_xy[:, 0], force_xy[:, 1])
    k = int(np.argmax(mag))
    return k, to_rail_axes(force_xy[k], bar_angle[k])


def reaction_load_case(
    part: str,
    joint: str,
    force_xy: np.ndarray,
    bar_angle: np.ndarray,
    crank_angle: np.ndarray,
    factor: float,
    holes: list[str],
    support: str,
    tip_group: str,
    body_force_dir: np.ndarray | None = None,
) -> LoadCase:
    """A load case from a joint reaction history: ``force_xy`` (steps, 2) is the force
    on the part at ``joint`` (ground frame), ``bar_angle`` (steps,) the angle of the
    part's longitudinal axis; the factored peak is split equally over ``holes``."""
    k, local = peak_in_rail_axes(force_xy, bar_angle)
    factored = factor * local
    per_hole = factored / len(holes)
    bolts = tuple(BoltForce(h, (float(per_hole[0]), float(per_hole[1]), 0.0)) for h in holes)
    origin = {
        "joint": joint,
        "peak_N": float(np.hypot(*force_xy[k])),
        "crank_angle_deg": float(np.degrees(crank_angle[k])),
        "bar_angle_deg": float(np.degrees(bar_angle[k]) % 360.0),
        "longitudinal_N": float(local[0]),
        "transverse_N": float(local[1]),
        "factored_longitudinal_N": float(factored[0]),
        "factored_transverse_N": float(factored[1]),
        "bolt_count": len(holes),
    }
    return LoadCase(part, support, bolts, tip_group, factor, origin)


def explicit_load_case(
    part: str, longitudinal: float, transverse: float, holes: list[str], support: str, tip_group: str
) -> LoadCase:
    """The same (longitudinal, transverse) force (N) on each hole, as given (already
    factored: the seed's 250 N + 250 N per hole of PF_4b_003_v2)."""
    bolts = tuple(BoltForce(h, (float(longitudinal), float(transverse), 0.0)) for h in holes)
    return LoadCase(
        part,
        support,
        bolts,
        tip_group,
        1.0,
        {
            "joint": "explicit",
            "per_hole_longitudinal_N": float(longitudinal),
            "per_hole_transverse_N": float(transverse),
            "bolt_count": len(holes),
        },
    )


def pivot_x(hole_x) -> float:
    """x (m, along the rail) of a rail's first joint: the shaft's line, midway between the
    rail's first two holes, where the two screws clamp it to the joint's upper plate."""
    return 0.5 * (float(hole_x[0]) + float(hole_x[1]))


def rail_bolt_holes(hole_x: list[float], shaft_x: float, bar_length: float, position: str) -> list[int]:
    """Indices of the two holes the far joint's plate is screwed to.

    ``worst``: the last two holes (the far end of the rail, seed 000's choice).
    ``actual``: the two neighbouring holes either side of the joint (``shaft_x +
    bar_length``, the joint's line midway between them on the 60 mm grid; the pair whose
    span holds it otherwise). Raises ValueError when the joint does not fall between two
    of the rail's holes.
    """
    n = len(hole_x)
    if n < 2:
        raise ValueError("the rail has fewer than two holes")
    if position == "worst":
        return [n - 2, n - 1]
    x = shaft_x + bar_length
    if x > hole_x[-1] + 1e-9 or x < hole_x[0] - 1e-9:
        last = 0.5 * (hole_x[-2] + hole_x[-1]) - shaft_x
        raise ValueError(
            f"the joint at {bar_length * 1e3:.6g} mm from the pivot is beyond the rail's last holes "
            f"(its far plate reaches {last * 1e3:.6g} mm)"
        )
    k = int(np.clip(np.searchsorted(np.asarray(hole_x), x - 1e-9) - 1, 0, n - 2))
    return [k, k + 1]
