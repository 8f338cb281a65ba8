"""Rolling bearings at the joints: equivalent dynamic load and L10 life from a reaction
history (ISO 281 basic rating life; variable load and speed as in the SKF and
Schaeffler catalogues).

Seed 000, 3.3.6: each revolute joint's shaft runs in two 6205 deep-groove ball bearings
(C = 14 900 N, C0 = 7 800 N); assumed here: the two share the joint's radial reaction
equally, and there is no axial load (a planar mechanism).

Over one crank revolution at constant speed (uniform steps in time), with a bearing's
radial load ``P_i`` and the relative speed of its rings ``n_i`` at step ``i``:

* equivalent mean load ``P_m = (sum P_i^3 |n_i| / sum |n_i|)^(1/3)`` (ball bearings,
  exponent 3), the load that gives the same life at the mean speed;
* ``L10 = (C / P_m)^3`` million revolutions, in hours ``L10 * 1e6 / (3600 * n_mean)``
  with ``n_mean`` the mean |relative speed| in rev/s;
* static: the peak load per bearing against ``C0`` (``s0 = C0 / P0``).

SI units: N, rad/s, hours for the life.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class BallBearing:
    name: str
    dynamic_capacity: float  # C, N
    static_capacity: float  # C0, N


BEARING_6205 = BallBearing("6205", 14_900.0, 7_800.0)  # seed 000, 3.3.6 (INA-FAG catalogue)
BEARINGS_PER_JOINT = 2  # seed 000, 3.3.6: the shaft between two bearings


@dataclass(frozen=True)
class BearingLife:
    """Per joint (arrays over the leading dimensions of the history): ``equivalent_load``
    P_m (N), ``peak_load`` (N, per bearing), ``l10_hours`` (inf where the rings never turn
    or carry nothing), ``static_safety`` C0 / peak."""

    equivalent_load: np.ndarray
    peak_load: np.ndarray
    l10_hours: np.ndarray
    static_safety: np.ndarray


def bearing_life(
    reaction: np.ndarray,
    relative_speed: np.ndarray,
    bearing: BallBearing = BEARING_6205,
    per_joint: int = BEARINGS_PER_JOINT,
) -> BearingLife:
    """``reaction`` (..., T, 2) N the joint's force over one revolution (uniform in time),
    ``relative_speed`` (..., T) rad/s of the bearing's rings."""
    return bearing_life_of_magnitude(np.hypot(reaction[..., 0], reaction[..., 1]), relative_speed, bearing, per_joint)


def bearing_life_of_magnitude(
    magnitude: np.ndarray,
    relative_speed: np.ndarray,
    bearing: BallBearing = BEARING_6205,
    per_joint: int = BEARINGS_PER_JOINT,
) -> BearingLife:
    """:func:`bearing_life` from the joint force's magnitude ``magnitude`` (..., T) N (a
    caller that has it already, e.g. for the peak reaction, does not compute it twice)."""
    P = magnitude / per_joint
    n = np.abs(relative_speed)
    turns = n.sum(axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        pm = np.cbrt(np.where(turns > 0, (P * P * P * n).sum(axis=-1) / turns, 0.0))
        n_mean = n.mean(axis=-1) / (2 * math.pi)  # rev/s
        life = np.where((pm > 0) & (n_mean > 0), (bearing.dynamic_capacity / pm) ** 3 * 1e6 / (3600.0 * n_mean), np.inf)
        peak = P.max(axis=-1)
        static = np.where(peak > 0, bearing.static_capacity / peak, np.inf)
    return BearingLife(pm, peak, life, static)


def relative_speeds(crank, coupler, output, kind: str) -> dict:
    """joint -> the relative angular speed (rad/s) of its bearing's rings, from the bars'
    angular speeds (arrays of one shape): O2 the crank's, A the coupler's less the
    crank's, B the rocker's less the coupler's (a slider-crank's slider does not turn:
    the coupler's), O4 the rocker's (a four-bar only)."""
    out = {"O2": crank, "A": coupler - crank, "B": output - coupler if kind == "four-bar" else coupler}
    if kind == "four-bar":
        out["O4"] = output
    return out


def with_weight_couple(magnitude: np.ndarray, moment, spacing: float) -> np.ndarray:
    """The joint load (N, as :func:`bearing_life_of_magnitude` takes it: shared by the
    joint's two bearings) when the shaft also carries ``moment`` N m about an in-plane axis
    (a table-top rig's cantilevered bar, its weight): each bearing then carries half the
    joint force plus the couple ``|moment| / spacing`` (``spacing`` m between the
    bearings), on the side where they add (an upper bound). ``moment`` (...,) broadcasts
    over ``magnitude``'s steps (..., T)."""
    return magnitude + 2.0 * np.abs(np.asarray(moment, float))[..., None] / spacing
