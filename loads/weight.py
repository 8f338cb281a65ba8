"""The table-top rig's weight, out of the mechanism plane (docs/model.md, "The table-top rig's weight").

The rig lies flat: its bars in horizontal layers, joined by vertical shafts between bearings.
Every bar's weight and the masses it carries act along -z (the rails' base down, their
carriages on top) and reach the ground through the joints' shafts, which carry moment about
in-plane axes. Idealisation (one bound, stated where results are shown): the links (the
coupler) are simply supported at their two joints, the crank and the rocker cantilevered
from their shafts, clamped over their first two holes (the upper plate's two screws, one
hole pitch apart, the shaft's line midway between them), carrying the links' reactions at their far joints. It
is statically determinate, so the out-of-plane load is constant over the cycle: a mean
stress. The other bound (joints rigid out of plane, a grillage whose moments follow the
pose) is not modelled; section 12 puts it at 18-32 N m at the crank's shaft against this
bound's 24.9 N m.

Forces are z components on the rail (N, +z up, unfactored), for arrays of bar lengths.
Imports nothing of railcheck but numpy. Units SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

GRAVITY = 9.80665  # m/s^2, standard gravity

#: the bars cantilevered from a shaft (the others simply supported at their two joints)
CANTILEVERED = ("crank", "rocker")


@dataclass(frozen=True)
class RailWeight:
    """What the out-of-plane weight of one bar's rail needs: the rail's ``mass`` kg and
    centre of mass ``com`` m from its first joint; the point masses carried at each joint
    by every bar (``carried``: bar -> joint -> kg, the one mass model's); the coupler's
    rail mass and centre of mass (kg, m from A), whose reactions the crank and rocker
    carry; whether the linkage has a rocker (a slider-crank's coupler rests at B on its
    slider); ``drive_arm`` m between the two screws at its first joint (the clamp's length)."""

    bar: str
    mass: float
    com: float
    carried: dict
    coupler: tuple[float, float]
    drive_arm: float

    def at(self, bar: str, joint: str) -> float:
        """kg carried by ``bar``'s rail at ``joint``."""
        return float(self.carried.get(bar, {}).get(joint, 0.0))


def coupler_reactions(w: RailWeight, coupler_length) -> tuple[np.ndarray, np.ndarray]:
    """(at A, at B) N: the upward forces the joints exert on the simply supported coupler's
    rail (its own weight shared by the lever rule; the masses it carries at A and B pass
    straight into the joints and do not bend it)."""
    mass, com = w.coupler
    length = np.asarray(coupler_length, float)
    weight = mass * GRAVITY
    return weight * (length - com) / length, weight * com / length


def joint_vertical_loads(w: RailWeight, lengths: dict) -> dict:
    """joint -> N, the downward weight passing through the joints A and B between the
    layers: the coupler's share by the lever rule and the masses carried there by the two
    bars the joint joins (the load a joint's plate screws and carriage carry out of plane);
    ``lengths`` bar -> m (arrays)."""
    at_a, at_b = coupler_reactions(w, lengths["coupler"])
    return {
        "A": at_a + GRAVITY * (w.at("crank", "A") + w.at("coupler", "A")),
        "B": at_b + GRAVITY * (w.at("coupler", "B") + w.at("rocker", "B")),
    }


def joint_forces(w: RailWeight, lengths: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(near, drive, far) N, +z up, on ``w.bar``'s rail: at its first screw (the first
    hole, half the clamp's length before the joint's line), at its second (the next hole,
    as far after; a link's first joint carries the whole ``near`` at its line and ``drive``
    is 0) and at its far joint's bolts, which with the rail's own weight balance;
    ``lengths`` bar -> m (arrays)."""
    at_a, at_b = coupler_reactions(w, lengths["coupler"])
    if w.bar == "coupler":
        return at_a, np.zeros_like(at_a), at_b
    far = -joint_vertical_loads(w, lengths)["A" if w.bar == "crank" else "B"]
    length = np.asarray(lengths[w.bar], float)
    weight = w.mass * GRAVITY
    # about the joint's line, midway between the screws (+ where an upward force lies further along the bar)
    couple = (weight * w.com - far * length) / w.drive_arm
    drive = 0.5 * (weight - far) + couple
    near = weight - far - drive
    return near, drive, far


def shaft_moment(w: RailWeight, lengths: dict) -> np.ndarray:
    """N m: the moment a cantilevered bar's shaft carries about the in-plane axis across
    the bar (its rail's weight and the far joint's load about the shaft hole)."""
    near, drive, _ = joint_forces(w, lengths)
    return 0.5 * (drive - near) * w.drive_arm


def screw_pulls(w: RailWeight, lengths: dict) -> tuple[np.ndarray, np.ndarray]:
    """(first, second) N >= 0: the weight's pull on the two screws that clamp ``w.bar``'s
    rail to its first joint's plate (the rail rests on the plate's face, so a downward force
    on the rail at a screw is that screw's tension; an upward one bears on the face)."""
    near, drive, _ = joint_forces(w, lengths)
    return np.maximum(-np.asarray(near, float), 0.0), np.maximum(-np.asarray(drive, float), 0.0)
