"""Each component's loads from the joint force histories, and its check by its standard
(:mod:`railcheck.components.standards`, :mod:`railcheck.components.screws`), vectorised
over any leading axes (a sweep's settings) and over the cycle's steps (the last axis). SI.

The loads, per component (the idealisations, stated in docs/components.md):

* screws (two per plate through two adjacent holes of the rail, ``rail_pitch`` apart):
  the joint force in the rail's axes, ``screw_eccentricity`` from their centroid along the
  rail, and at O2 the motor torque, shared by the elastic method; tension from a table-top
  rig's weight (the cantilevered bar's weight couple over the two screws at its first
  joint; at a far joint the weight through the joint, levered about the screws);
* shafts: the joint force bending the 25 mm shaft at the upper bearing's shoulder over
  ``shaft_lever`` (fully reversed: its direction turns relative to the shaft), and a
  cantilevered bar's weight moment (O2, O4: constant in the shaft's frame, the shaft fixed
  in the bar's upper plate: a mean stress); the motor torque at O2;
* bearings: two per joint sharing the joint force (:mod:`railcheck.loads.bearings`), at
  the rings' relative speed, a cantilevered bar's weight moment as a couple over them;
* carriages (A, B): the joint force in the rail's axes, lateral and longitudinal, at a
  height above the carriage (roll and pitch moments), the weight through the joint normal.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from railcheck.components import screws, standards
from railcheck.components.ratings import Component, ComponentSpec
from railcheck.fea.fatigue import endurance_limit, size_factor_of_diameter
from railcheck.loads.bearings import BallBearing, bearing_life_of_magnitude, with_weight_couple


@dataclass(frozen=True)
class JointHistories:
    """What the components need from one cycle (arrays over leading axes ``...`` and the
    steps ``T``): ``reactions`` joint -> (..., T, 2) N in the ground frame (the force on
    the bar that starts at the joint, or for A and B the force on the crank and the coupler
    at their far joints: unfactored; the checks read magnitudes and, at O2, the force on
    the crank), ``torque`` (..., T) N m on the crank, ``angles`` bar -> (..., T) rad of each
    bar's axis, ``relative_speed`` joint -> (..., T) rad/s of the joint's bearing rings,
    ``vertical`` joint -> (...,) N the weight through the joint out of plane, ``moments``
    joint -> (...,) N m the weight's moment about an in-plane axis that a cantilevered
    bar's shaft carries into its bearings (O2, O4; a joint left out, or a vertical rig: 0),
    ``screw_tension`` joint -> ((...,), (...,)) N the weight's pull on the first and second
    screw of the upper plate at that joint (>= 0; absent: none)."""

    reactions: dict
    torque: np.ndarray
    angles: dict
    relative_speed: dict
    vertical: dict
    moments: dict
    screw_tension: dict = field(default_factory=dict)
    #: the joint forces in rail axes already computed from these histories (:func:`rail_axes_of`)
    projected: dict = field(default_factory=dict, compare=False, repr=False)


@dataclass(frozen=True)
class Strengths:
    """The strengths a component check reads (Pa): the rig's steel for shafts and the
    members screws bear on."""

    ultimate: float
    yield_strength: float
    surface: str
    reliability: float


@dataclass(frozen=True)
class ComponentResult:
    """One component's check: each criterion's utilisation (1 = at its limit) and the
    figures behind them (SI; arrays over a sweep's settings, floats for one check);
    ``assumed`` the assumed fields it reads; ``needs`` what it needs to pass (one check's
    sizing, :mod:`railcheck.components.sizing`; empty in a sweep)."""

    name: str
    kind: str
    joint: str
    standard: str
    factored: bool
    utilisations: dict
    figures: dict
    assumed: tuple[str, ...]
    needs: dict = field(default_factory=dict)

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


def rail_axes_of(h: JointHistories, joint: str, rail: str) -> tuple[np.ndarray, np.ndarray]:
    """:func:`in_rail_axes` of ``joint``'s force in ``rail``'s axes, computed once per
    histories (several components at a joint read the same projection; each rail's cosine
    and sine once)."""
    key = (joint, rail)
    if key not in h.projected:
        if rail not in h.projected:
            h.projected[rail] = (np.cos(h.angles[rail]), np.sin(h.angles[rail]))
        c, s = h.projected[rail]
        force = h.reactions[joint]
        h.projected[key] = (force[..., 0] * c + force[..., 1] * s, -force[..., 0] * s + force[..., 1] * c)
    return h.projected[key]


def _magnitude(force: np.ndarray) -> np.ndarray:
    return np.sqrt(force[..., 0] ** 2 + force[..., 1] ** 2)


def screw_loads(c: Component, spec: ComponentSpec, h: JointHistories, peaks: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(transverse (2, ..., T), tension (2, ...)) N, unfactored, on each of the plate's two
    screws (the first nearer the joint's line): the joint force (and at O2 the motor torque)
    by the elastic method (:func:`railcheck.components.standards.two_screw_forces`), the
    weight's pull on each screw; with ``peaks`` the transverse forces' largest over the
    cycle (2, ..., 1)."""
    assert c.rail is not None  # a screw group fixes a rail
    along, across = rail_axes_of(h, c.joint, c.rail)
    torque = h.torque if c.motor else 0.0
    if peaks:
        transverse = standards.two_screw_peaks(along, across, torque, spec.screw_eccentricity, spec.rail_pitch)[..., None]
    else:
        transverse = standards.two_screw_forces(along, across, torque, spec.screw_eccentricity, spec.rail_pitch)
    if c.end == "near":
        pulls = h.screw_tension.get(c.joint, (0.0, 0.0))
        tension = np.array([np.broadcast_to(np.asarray(t, float), along.shape[:-1]) for t in pulls])
    else:  # the weight through the far joint, levered about the screws (the joint at the first)
        vertical = np.abs(np.asarray(h.vertical.get(c.joint, 0.0), float))
        share = vertical * (0.5 + spec.screw_eccentricity / spec.rail_pitch)
        tension = np.array([np.broadcast_to(share, along.shape[:-1])] * 2)
    return transverse, tension


def check_screws(c: Component, spec: ComponentSpec, h: JointHistories, f: float, m: Strengths):
    """(criterion -> utilisation, figures) of a screw group: EN 1993-1-8 Table 3.4 on its
    loads times ``f``, and slip (VDI 2230) on them as they are."""
    # every criterion grows with the transverse force and the tension is constant over the
    # cycle, so each screw's peak over the cycle gives every criterion's peak
    transverse, tension = screw_loads(c, spec, h, peaks=True)
    thread, grade = spec.thread, spec.property_class
    shear, pull = f * transverse.max(axis=0), f * np.broadcast_to(tension[..., None], transverse.shape).max(axis=0)
    u = standards.bolt_utilisations(
        shear,
        pull,
        thread.d,
        thread.stress_area,
        grade.ultimate,
        m.ultimate,
        spec.screw_grip,
        grade.alpha_v,
        spec.screw_end_distance,
        spec.screw_edge_distance,
        spec.rail_hole,
    )
    clamp = screws.least_clamp(thread, grade, spec)
    slip = screws.slip_utilisation(transverse, tension[..., None], clamp, spec.joint_friction, spec.slip_safety)
    u["slip"] = slip.max(axis=(0, -1))
    peak = shear.max(axis=-1)
    figures = {"shear_N": peak, "tension_N": pull.max(axis=-1), "clamp_N": np.full_like(peak, clamp)}
    figures["transverse_N"] = transverse.max(axis=(0, -1))
    return u, figures


def check_shaft(c: Component, spec: ComponentSpec, h: JointHistories, f: float, m: Strengths):
    """(criterion -> utilisation, figures) of a joint's shaft: DE-Goodman fatigue and
    first-cycle yield (Shigley eq. 7-8, 7-15) on its loads times ``f``."""
    d = spec.shaft_diameter
    moment = f * (_magnitude(h.reactions[c.joint]) * spec.shaft_lever)
    # a cantilevered bar's weight moment (O2, O4): constant in the shaft's frame, a mean stress
    weight = f * np.abs(np.asarray(h.moments.get(c.joint, 0.0), float))
    torque = f * h.torque if c.motor else np.zeros_like(moment)
    kf, kfs, se = shaft_factors(spec, m, d)
    u = standards.shaft_utilisations(moment, torque, d, kf, kfs, se, m.ultimate, m.yield_strength, weight)
    figures = {"moment_Nm": moment.max(axis=-1), "mean_moment_Nm": weight + 0.0 * moment.max(axis=-1)}
    return u, figures | {"torque_Nm": np.abs(torque).max(axis=-1), "endurance_Pa": se}


def shaft_factors(spec: ComponentSpec, m: Strengths, d: float) -> tuple[float, float, float]:
    """(K_f, K_fs, S_e Pa) of a shaft of diameter ``d`` m at its bearing's shoulder: the
    notch factors of the fillet ``shaft_fillet_radius`` (fixed by the bearing's corner),
    the Marin-modified endurance limit with the size factor of ``d``."""
    marin = endurance_limit(m.ultimate, m.surface, None, "bending", m.reliability)
    kf = standards.fatigue_notch_factor(spec.shaft_kt, m.ultimate, spec.shaft_fillet_radius)
    kfs = standards.fatigue_notch_factor(spec.shaft_kts, m.ultimate, spec.shaft_fillet_radius, torsion=True)
    return kf, kfs, marin.endurance_limit * size_factor_of_diameter(d)


def bearing_load(c: Component, spec: ComponentSpec, h: JointHistories) -> np.ndarray:
    """(..., T) N: the joint load its two bearings share, a cantilevered bar's weight
    moment added as a couple over their spacing (:func:`railcheck.loads.bearings.with_weight_couple`)."""
    return with_weight_couple(_magnitude(h.reactions[c.joint]), h.moments.get(c.joint, 0.0), spec.bearing_spacing)


def check_bearings(c: Component, spec: ComponentSpec, h: JointHistories, f: float, m: Strengths):
    """(criterion -> utilisation, figures) of a joint's pair of bearings: static safety
    (ISO 76) and L10 life (ISO 281) on the loads as they are (``f`` unused)."""
    bearing = BallBearing("6205", spec.bearing_dynamic, spec.bearing_static)
    life = bearing_life_of_magnitude(bearing_load(c, spec, h), h.relative_speed[c.joint], bearing)
    hours = spec.bearing_required_life / 3600.0
    with np.errstate(divide="ignore"):
        u = {
            "static": spec.bearing_required_s0 / life.static_safety,
            "life": np.where(np.isfinite(life.l10_hours), hours / life.l10_hours, 0.0),
        }
    return u, {"peak_load_N": life.peak_load, "static_safety": life.static_safety, "life_h": life.l10_hours}


def check_carriage(c: Component, spec: ComponentSpec, h: JointHistories, f: float, m: Strengths):
    """(criterion -> utilisation, figures) of a carriage: the catalogue's static safety on
    its equivalent load as it is (``f`` unused)."""
    assert c.rail is not None  # a carriage runs on a rail
    along, across = rail_axes_of(h, c.joint, c.rail)
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
