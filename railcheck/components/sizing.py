"""What each component needs to pass, solved from its own criteria (one check: floats).
SI.

* Screws: the clamp per screw the slip criterion needs (solved for the clamp), the
  strength T3.4 needs (solved for the tensile stress area times the ultimate), then the
  smallest standard screw the rail's hole admits (size, then class) that gives both, with
  the tightening torque of its assembly preload; where none does, the joint friction that
  the strongest admitted screw would need.
* Shafts: the smallest diameter at which DE-Goodman (Shigley eq. 7-8) and first-cycle
  yield (eq. 7-15) reach n = 1, the size factor's weak dependence on the diameter solved
  by substitution (it contracts by a factor 0.107 / 3 a step).
* Bearings: the spacing at which the more loaded bearing's static safety meets the
  required one (ISO 76), the cantilevered bar's weight couple shared over it.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from railcheck.components import screws
from railcheck.components.checks import (
    ComponentResult,
    JointHistories,
    Strengths,
    screw_loads,
    shaft_factors,
)
from railcheck.components.ratings import COMPONENTS, ComponentSpec
from railcheck.components.standards import GAMMA_M2, de_goodman_diameter, yield_diameter
from railcheck.fea.fatigue import size_factor_of_diameter


def screw_needs(r: ComponentResult, spec: ComponentSpec, h: JointHistories, factor: float, m: Strengths) -> dict:
    """The smallest admitted screw and class that passes slip and T3.4, its tightening
    torque, the clamp it needs; or, where none passes, the friction that would."""
    transverse, tension = screw_loads(COMPONENTS[r.name], spec, h)
    clamp, shear, pull = screw_demands(transverse, tension, spec, factor)
    out: dict = {"clamp_needed_N": float(np.max(clamp)), "screw": None}
    choice, choices = int(smallest_screw(spec, clamp, shear, pull)), screw_choices(spec)
    if choice >= 0:
        size, grade = choices[choice]
        trial = dataclasses.replace(spec, screw_size=size, screw_class=grade)
        preload = screws.assembly_preload(
            trial.thread, trial.property_class.proof, spec.screw_thread_friction, spec.screw_preload_utilisation
        )
        torque = screws.tightening_torque(
            trial.thread, preload, spec.screw_thread_friction, spec.screw_head_friction, spec.rail_hole
        )
        return out | {"screw": f"{size} {grade}", "tightening_torque_Nm": torque, "assembly_preload_N": preload}
    strongest = " ".join(choices[-1]) if choices else None
    return out | {"friction_needed": _friction_needed(spec, transverse, tension), "strongest": strongest}


def screw_choices(spec: ComponentSpec) -> tuple[tuple[str, str], ...]:
    """(size, class) of every screw the rail's hole admits, smallest size first, then the
    weakest class."""
    return tuple(
        (size, grade) for size in screws.admitted(spec.rail_hole, spec.rail_counterbore) for grade in screws.CLASSES
    )


def screw_demands(transverse, tension, spec: ComponentSpec, factor: float) -> tuple[np.ndarray, ...]:
    """(clamp per screw N the slip criterion needs, factored shear N, factored pull N),
    each (...): the largest over the group's two screws and the cycle of the unfactored
    ``transverse`` (2, ..., T) and ``tension`` (2, ...) N (:func:`screw_loads`)."""
    transverse, tension = np.asarray(transverse, float), np.asarray(tension, float)
    clamp = screws.clamp_needed(transverse, tension[..., None], spec.joint_friction, spec.slip_safety)
    return np.max(clamp, axis=(0, -1)), factor * np.max(transverse, axis=(0, -1)), factor * np.max(tension, axis=0)


def smallest_screw(spec: ComponentSpec, clamp, shear, pull) -> np.ndarray:
    """(...) int: the index in :func:`screw_choices` of the first screw whose least clamp
    reaches ``clamp`` N and which carries ``shear`` and ``pull`` N factored by EN 1993-1-8
    Table 3.4; -1 where none does. Vectorised over settings."""
    ok = [
        (screws.least_clamp(t.thread, t.property_class, t) >= np.asarray(clamp)) & _strong_enough(t, shear, pull)
        for t in (dataclasses.replace(spec, screw_size=size, screw_class=grade) for size, grade in screw_choices(spec))
    ]
    if not ok:
        return np.full(np.shape(clamp), -1)
    stack = np.array(ok)
    return np.where(stack.any(axis=0), stack.argmax(axis=0), -1)


def _strong_enough(spec: ComponentSpec, shear, pull) -> np.ndarray:
    """Whether a screw of ``spec`` carries ``shear`` and ``pull`` N factored by EN 1993-1-8
    Table 3.4 (shear, tension and their combination; bearing on the rail is the screw's
    diameter times the rail's, checked by the verdict)."""
    t, c = spec.thread, spec.property_class
    v_rd = c.alpha_v * c.ultimate * t.stress_area / GAMMA_M2
    t_rd = 0.9 * c.ultimate * t.stress_area / GAMMA_M2
    shear, pull = np.asarray(shear, float), np.asarray(pull, float)
    return (shear <= v_rd) & (pull <= t_rd) & (shear / v_rd + pull / (1.4 * t_rd) <= 1.0)


def _friction_needed(spec: ComponentSpec, transverse: np.ndarray, tension: np.ndarray) -> float:
    """The joint friction at which the strongest admitted screw holds each screw's
    ``transverse`` force (2, ..., T) N with the slip safety, its clamp less its own
    ``tension`` (2, ...) N (inf where a pull exceeds the clamp)."""
    sizes = screws.admitted(spec.rail_hole, spec.rail_counterbore)
    strongest = dataclasses.replace(spec, screw_size=sizes[-1], screw_class=list(screws.CLASSES)[-1])
    left = screws.least_clamp(strongest.thread, strongest.property_class, strongest) - np.asarray(tension, float)[..., None]
    if np.any(left <= 0):
        return math.inf
    return float(np.max(spec.slip_safety * np.abs(transverse) / left))


def shaft_needs(r: ComponentResult, spec: ComponentSpec, h: JointHistories, factor: float, m: Strengths) -> dict:
    """The smallest shaft diameter (m) that passes DE-Goodman and first-cycle yield at
    n = 1 under this check's moments and torque (the fillet fixed by the bearing)."""
    return {"diameter_needed_m": float(np.max(shaft_diameter_needed(COMPONENTS[r.name], spec, h, factor, m)))}


def shaft_diameter_needed(c, spec: ComponentSpec, h: JointHistories, factor: float, m: Strengths) -> np.ndarray:
    """(...) m: per setting of ``h`` the smallest diameter of shaft ``c`` at which
    DE-Goodman (Shigley eq. 7-8, the size factor solved with it) and first-cycle yield
    (eq. 7-15) reach n = 1: the joint force over the shaft's lever fully reversed, a
    cantilevered bar's weight couple as the midrange moment, at O2 the motor torque's range
    and mean; all factored by ``factor``."""
    moment = factor * np.max(np.hypot(*np.moveaxis(h.reactions[c.joint], -1, 0)) * spec.shaft_lever, axis=-1)
    mm = factor * np.abs(np.asarray(h.moments.get(c.joint, 0.0), float))
    torque = factor * np.asarray(h.torque, float) if c.motor else np.zeros((*moment.shape, 1))
    ta, tm = 0.5 * np.ptp(torque, axis=-1), 0.5 * (torque.max(axis=-1) + torque.min(axis=-1))
    kf, kfs, se = shaft_factors(spec, m, spec.shaft_diameter)
    unsized = se / size_factor_of_diameter(spec.shaft_diameter)
    fatigue = de_goodman_diameter(moment, ta, tm, kf, kfs, lambda d: unsized * size_factor_of_diameter(d), m.ultimate, mm=mm)
    first_cycle = yield_diameter(moment + mm, np.abs(tm) + ta, kf, kfs, m.yield_strength)
    return np.maximum(fatigue, first_cycle)


def bearing_needs(r: ComponentResult, spec: ComponentSpec, h: JointHistories, factor: float, m: Strengths) -> dict:
    """The bearings' spacing (m) at which the more loaded bearing meets the required
    static safety (0 where no weight couple acts; inf where the joint force alone
    exceeds it: a larger bearing is needed)."""
    return {"spacing_needed_m": float(np.max(bearing_spacing_needed(COMPONENTS[r.name], spec, h)))}


def bearing_spacing_needed(c, spec: ComponentSpec, h: JointHistories) -> np.ndarray:
    """(...) m per setting of ``h``: the spacing of joint ``c``'s two bearings at which the
    more loaded one meets the required static safety, the cantilevered bar's weight couple
    shared over it (0 without a couple, inf where the joint force alone is too much)."""
    moment = np.abs(np.asarray(h.moments.get(c.joint, 0.0), float))
    force = np.max(np.hypot(*np.moveaxis(h.reactions[c.joint], -1, 0)), axis=-1)
    room = spec.bearing_static / spec.bearing_required_s0 - 0.5 * force
    with np.errstate(divide="ignore", invalid="ignore"):
        spacing = np.where(room > 0, moment / np.where(room > 0, room, 1.0), np.inf)
    return np.where(moment == 0.0, 0.0, spacing)


def screws_needed_of_settings(c, spec: ComponentSpec, h: JointHistories, factor: float, m: Strengths) -> np.ndarray:
    """(S,) object: a sweep's screw group's smallest screw (``"M5 8.8"``) that passes slip
    and EN 1993-1-8 T3.4 at each setting, ``"none"`` where no admitted screw does."""
    names = np.array([" ".join(choice) for choice in screw_choices(spec)] + ["none"], dtype=object)
    transverse, tension = screw_loads(c, spec, h, peaks=True)
    return names[smallest_screw(spec, *screw_demands(transverse, tension, spec, factor))]


def spacing_needed_of_settings(c, spec: ComponentSpec, h: JointHistories, factor: float, m: Strengths) -> np.ndarray:
    """(S,) m: a sweep's pair of bearings' least spacing (:func:`bearing_spacing_needed`)."""
    return np.broadcast_to(bearing_spacing_needed(c, spec, h), (h.torque.shape[0],))
