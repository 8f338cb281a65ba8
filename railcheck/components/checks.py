"""Each component's loads from the joint force histories, and its check by its standard
(:mod:`railcheck.components.standards`), vectorised over any leading axes (a sweep's
settings) and over the cycle's steps (the last axis). SI.

The loads, per component (the idealisations, stated in :func:`component_note`):

* driving pin: the motor torque ``T`` as a couple over the crank's shaft and the pin one
  hole pitch ``a`` apart: ``|T| / a``, in single shear;
* motor shaft: the crank's joint force at O2 ``R_O2`` (the couple's two forces cancel in
  the shaft's bearings) bending it over the lever from its bearing's shoulder, and ``T``;
* joint shafts (A, B, O4): the joint force bending the stub through the rail's hole at its
  shoulder; no torque (the bearings turn freely);
* plate screws (A, B): the joint force in the axes of the rail the plate is screwed to, at
  the plate's bearing seat, shared by the two screws by the elastic method; tension from
  the table-top rig's weight through the joint (:func:`railcheck.loads.weight.joint_vertical_loads`),
  levered about the screws;
* bearings: two per joint sharing the joint force (:mod:`railcheck.loads.bearings`), at
  the rings' relative speed;
* carriages (A, B): the joint force in the rail's axes, lateral and longitudinal, at a
  height above the carriage (roll and pitch moments), the weight through the joint normal.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from railcheck.components import standards
from railcheck.components.ratings import ASSUMED, COMPONENTS, Component, ComponentSpec
from railcheck.fea.fatigue import endurance_limit, size_factor_of_diameter
from railcheck.loads.bearings import BallBearing, bearing_life_of_magnitude, with_weight_couple

#: each kind's standard, as the output names it
STANDARDS = {
    "pin": "EN 1993-1-8 T3.10",
    "bolts": "EN 1993-1-8 T3.4",
    "shaft": "Shigley DE-Goodman",
    "bearings": "ISO 76, ISO 281",
    "carriage": "catalogue P0",
}

#: the spec fields each kind reads (the "assumed" ones among them are named in the output)
FIELDS = {
    "pin": ("pin_diameter", "pin_arm", "pin_rail_thickness", "pin_hub_thickness", "pin_gap", "pin_yield", "pin_ultimate"),
    "bolts": (
        "bolt_diameter",
        "bolt_stress_area",
        "bolt_ultimate",
        "bolt_alpha_v",
        "bolt_hole",
        "bolt_pitch",
        "bolt_eccentricity",
        "bolt_end_distance",
        "bolt_edge_distance",
        "bolt_grip",
    ),
    "shaft": ("shaft_diameter", "shaft_fillet_radius", "shaft_kt", "shaft_kts", "shaft_lever"),
    "motor-shaft": ("motor_shaft_diameter", "shaft_fillet_radius", "shaft_kt", "shaft_kts", "motor_shaft_lever"),
    "bearings": ("bearing_dynamic", "bearing_static", "bearing_spacing", "bearing_required_s0", "bearing_required_life"),
    "carriage": ("carriage_c0", "carriage_m0x", "carriage_m0y", "carriage_m0z", "carriage_height", "carriage_required_s0"),
}


@dataclass(frozen=True)
class JointHistories:
    """What the components need from one cycle (arrays over leading axes ``...`` and the
    steps ``T``): ``reactions`` joint -> (..., T, 2) N in the ground frame (the force on
    the bar the joint's name follows in the parts' load sources: unfactored),
    ``torque`` (..., T) N m on the crank, ``angles`` bar -> (..., T) rad of each bar's axis,
    ``relative_speed`` joint -> (..., T) rad/s of the joint's bearing rings, ``vertical``
    joint -> (...,) N the weight through the joint out of plane, ``moments`` joint ->
    (...,) N m the weight's moment about an in-plane axis that a cantilevered bar's shaft
    carries into its bearings (O2, O4; a joint left out, or a vertical rig: 0)."""

    reactions: dict
    torque: np.ndarray
    angles: dict
    relative_speed: dict
    vertical: dict
    moments: dict


@dataclass(frozen=True)
class Strengths:
    """The strengths a component check reads (Pa): the rig's steel for shafts and the
    members screws and pins bear on."""

    ultimate: float
    yield_strength: float
    surface: str
    reliability: float


@dataclass(frozen=True)
class ComponentResult:
    """One component's check: each criterion's utilisation (1 = at its limit) and the
    figures behind them (SI; arrays over a sweep's settings, floats for one check)."""

    name: str
    kind: str
    joint: str
    standard: str
    factored: bool
    utilisations: dict
    figures: dict
    assumed: tuple[str, ...]

    @property
    def utilisation(self):
        return np.max([np.asarray(u, float) for u in self.utilisations.values()], axis=0)

    @property
    def governing_criterion(self):
        names = list(self.utilisations)
        k = np.argmax([np.asarray(u, float) for u in self.utilisations.values()], axis=0)
        return np.asarray(names, dtype=object)[k]

    @property
    def passed(self):
        return self.utilisation <= 1.0


def in_rail_axes(force: np.ndarray, angle: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(longitudinal, transverse) components (N) of ground-frame forces (..., T, 2) in
    the axes of a bar at ``angle`` (..., T) rad."""
    c, s = np.cos(angle), np.sin(angle)
    return force[..., 0] * c + force[..., 1] * s, -force[..., 0] * s + force[..., 1] * c


def _magnitude(force: np.ndarray) -> np.ndarray:
    return np.sqrt(force[..., 0] ** 2 + force[..., 1] ** 2)


def check_component(
    component: Component, spec: ComponentSpec, h: JointHistories, factor: float, material: Strengths
) -> ComponentResult:
    """The check of ``component`` by its standard on the histories ``h``: the strength
    checks on loads times ``factor``, the rolling elements' on the loads as they are."""
    f = factor if component.factored else 1.0
    u, figures = KIND_CHECKS[component.kind](component, spec, h, f, material)
    key = "motor-shaft" if component.motor else component.kind
    return ComponentResult(
        component.name,
        component.kind,
        component.joint,
        STANDARDS[component.kind],
        component.factored,
        u,
        figures,
        tuple(n for n in FIELDS[key] if n in ASSUMED),
    )


def _pin(c: Component, spec: ComponentSpec, h: JointHistories, f: float, m: Strengths):
    force = f * np.abs(h.torque) / spec.pin_arm
    u = standards.pin_utilisations(
        force,
        spec.pin_diameter,
        spec.pin_rail_thickness,
        spec.pin_hub_thickness,
        spec.pin_gap,
        spec.pin_yield,
        spec.pin_ultimate,
        m.yield_strength,
    )
    return u, {"force_N": force.max(axis=-1)}


def _shaft(c: Component, spec: ComponentSpec, h: JointHistories, f: float, m: Strengths):
    d = spec.motor_shaft_diameter if c.motor else spec.shaft_diameter
    lever = spec.motor_shaft_lever if c.motor else spec.shaft_lever
    moment = f * _magnitude(h.reactions[c.joint]) * lever
    if c.motor:  # the crank's weight, cantilevered from the motor shaft: added to the bending (an upper bound)
        moment = moment + f * np.abs(np.asarray(h.moments.get(c.joint, 0.0), float))[..., None]
    torque = f * h.torque if c.motor else np.zeros_like(moment)
    marin = endurance_limit(m.ultimate, m.surface, None, "bending", m.reliability)
    se = marin.endurance_limit * size_factor_of_diameter(d)
    radius = spec.shaft_fillet_radius * d / spec.shaft_diameter  # the same r/d at either diameter
    kf = standards.fatigue_notch_factor(spec.shaft_kt, m.ultimate, radius)
    kfs = standards.fatigue_notch_factor(spec.shaft_kts, m.ultimate, radius, torsion=True)
    u = standards.shaft_utilisations(moment, torque, d, kf, kfs, se, m.ultimate, m.yield_strength)
    return u, {"moment_Nm": moment.max(axis=-1), "torque_Nm": np.abs(torque).max(axis=-1), "endurance_Pa": se}


def _bolts(c: Component, spec: ComponentSpec, h: JointHistories, f: float, m: Strengths):
    along, across = in_rail_axes(h.reactions[c.joint], h.angles[c.rail])
    shear = f * standards.bolt_group_forces(along, across, spec.bolt_eccentricity, spec.bolt_pitch)
    vertical = np.abs(np.asarray(h.vertical.get(c.joint, 0.0), float))
    tension = f * vertical * (0.5 + spec.bolt_eccentricity / spec.bolt_pitch)
    tension = np.broadcast_to(np.asarray(tension)[..., None], shear.shape)
    u = standards.bolt_utilisations(
        shear,
        tension,
        spec.bolt_diameter,
        spec.bolt_stress_area,
        spec.bolt_ultimate,
        m.ultimate,
        spec.bolt_grip,
        spec.bolt_alpha_v,
        spec.bolt_end_distance,
        spec.bolt_edge_distance,
        spec.bolt_hole,
    )
    return u, {"shear_N": shear.max(axis=-1), "tension_N": tension.max(axis=-1)}


def _bearings(c: Component, spec: ComponentSpec, h: JointHistories, f: float, m: Strengths):
    bearing = BallBearing("6205", spec.bearing_dynamic, spec.bearing_static)
    load = with_weight_couple(_magnitude(h.reactions[c.joint]), h.moments.get(c.joint, 0.0), spec.bearing_spacing)
    life = bearing_life_of_magnitude(load, h.relative_speed[c.joint], bearing)
    hours = spec.bearing_required_life / 3600.0
    with np.errstate(divide="ignore"):
        u = {
            "static": spec.bearing_required_s0 / life.static_safety,
            "life": np.where(np.isfinite(life.l10_hours), hours / life.l10_hours, 0.0),
        }
    return u, {"peak_load_N": life.peak_load, "static_safety": life.static_safety, "life_h": life.l10_hours}


def _carriage(c: Component, spec: ComponentSpec, h: JointHistories, f: float, m: Strengths):
    along, across = in_rail_axes(h.reactions[c.joint], h.angles[c.rail])
    normal = np.broadcast_to(np.asarray(h.vertical.get(c.joint, 0.0), float)[..., None], along.shape)
    height = spec.carriage_height
    p0 = standards.carriage_equivalent_load(
        across,
        normal,
        across * height,
        along * height,
        0.0,
        spec.carriage_c0,
        spec.carriage_m0x,
        spec.carriage_m0y,
        spec.carriage_m0z,
    ).max(axis=-1)
    safety = spec.carriage_c0 / p0
    return {"static": spec.carriage_required_s0 / safety}, {"equivalent_load_N": p0, "static_safety": safety}


KIND_CHECKS = {"pin": _pin, "shaft": _shaft, "bolts": _bolts, "bearings": _bearings, "carriage": _carriage}


def check_components(names, spec: ComponentSpec, h: JointHistories, factor: float, material: Strengths) -> dict:
    """name -> :class:`ComponentResult` of each component ``names`` lists."""
    return {n: check_component(COMPONENTS[n], spec, h, factor, material) for n in names}
