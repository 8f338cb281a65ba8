"""The kinematics stage: a mechanism -> motion, reactions, checks and peaks.

The scene is read once, into a :class:`KinematicsInput` (:func:`kinematics_input`): the
linkage, its speed and steps, the formulation, the effects asked for, the mass model and the
rail the joints sit on. :func:`run_kinematics` takes that record, never the scene, and runs
the closed-form kinematics and the requested inverse-dynamics formulation with only the
effects called for: inertia needs a non-zero speed (and "inertia" in check.effects when a
[check] table exists); gravity only when listed. A search over the crank speed varies the
record (:meth:`KinematicsInput.at_speed`), not the scene.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from railcheck.base.machine import refuse_kinematics_beyond_memory
from railcheck.effects import simulated_effects
from railcheck.geometry.catalogue import RailSpec, with_overrides
from railcheck.kinematics.checks import CheckResult, configuration_checks, transmission_extremes
from railcheck.kinematics.dynamics import STANDARD_GRAVITY, Dynamics, inverse_dynamics
from railcheck.kinematics.massmodel import MassModel
from railcheck.kinematics.motion import Motion, solve_motion
from railcheck.parts import rail_length
from railcheck.scene import Scene
from railcheck.specs import MechanismSpec


@dataclass(frozen=True)
class KinematicsResult:
    motion: Motion  # at the scene's speed (positions, velocities, accelerations)
    dynamics: Dynamics  # reactions with the effects the scene asks for
    checks: dict[str, CheckResult]
    effects: tuple[str, ...]
    transmission_deg: tuple[float, float]

    @property
    def joints(self) -> tuple[str, ...]:
        return tuple(self.dynamics.reactions)


@dataclass(frozen=True)
class KinematicsInput:
    """What the kinematics stage reads, resolved once from a scene (SI).

    Parameters
    ----------
    mechanism : the linkage, its crank speed (rad/s), steps, plane.
    formulation : the inverse-dynamics formulation's name.
    requested_effects : [check] effects as listed (without a [check]: inertia).
    masses : the run's one mass model (kg, m, kg m^2).
    rail : the rail profile the bars are set on (its hole grid bounds each bar's length).
    """

    mechanism: MechanismSpec
    formulation: str
    requested_effects: tuple[str, ...]
    masses: MassModel
    rail: RailSpec

    @property
    def effects(self) -> tuple[str, ...]:
        """The loads simulated at this record's speed (:func:`simulated_effects`)."""
        return simulated_effects(self.requested_effects, (self.mechanism.speed,))

    def at_speed(self, speed: float) -> KinematicsInput:
        """This record with the crank at ``speed`` rad/s (a speed search's trial)."""
        return replace(self, mechanism=replace(self.mechanism, speed=speed))


def kinematics_input(scene: Scene) -> KinematicsInput:
    """The scene's :class:`KinematicsInput` (an InputError naming [mechanism] without one)."""
    return KinematicsInput(
        scene.linkage_spec, scene.formulation, scene.requested_effects, scene.masses, with_overrides(scene.geometry)[0]
    )


def run_kinematics(inputs: KinematicsInput) -> KinematicsResult:
    """Kinematics and inverse dynamics of ``inputs``' mechanism (raises InputError for an
    impossible mechanism, naming the field)."""
    spec = inputs.mechanism
    refuse_kinematics_beyond_memory(spec.steps, "mechanism.steps")
    effects = inputs.effects
    motion = solve_motion(spec.linkage, spec.speed, spec.steps)
    dyn_motion = motion if "inertia" in effects else solve_motion(spec.linkage, 0.0, spec.steps)
    gravity = STANDARD_GRAVITY if "gravity" in effects else 0.0
    dynamics = inverse_dynamics(dyn_motion, inputs.formulation, inputs.masses, gravity=gravity)
    mu_min, mu_max = transmission_extremes(spec.linkage)
    checks = all_checks(spec.linkage, inputs.rail)
    return KinematicsResult(motion, dynamics, checks, effects, (math.degrees(mu_min), math.degrees(mu_max)))


def all_checks(linkage, rail: RailSpec) -> dict[str, CheckResult]:
    """The linkage's configuration checks plus :func:`joints_on_rails` on ``rail``."""
    return {**configuration_checks(linkage), **joints_on_rails(linkage.lengths, rail)}


def joint_reach(rail, bar: str) -> tuple[float, float]:
    """(shortest, longest) length in m a bar can be set to on its rail: one hole pitch,
    and the distance from its first joint (midway between holes 0 and 1) to the last
    joint a far plate screwed through the last two holes gives (midway between them)."""

    holes = rail.hole_positions(rail_length(bar))
    return rail.hole_pitch, (holes[-2] - holes[0] if len(holes) > 2 else 0.0)


def joints_on_rails_flags(lengths: dict, rail) -> np.ndarray:
    """Pass flags of :func:`joints_on_rails` for arrays of settings (bar -> lengths m)."""
    ok = np.ones(np.shape(next(iter(lengths.values()))), dtype=bool)
    for bar in ("crank", "coupler", "rocker"):
        if bar in lengths:
            lo, hi = joint_reach(rail, bar)
            ok &= (lengths[bar] <= hi + 1e-9) & (lengths[bar] >= lo - 1e-9)
    return ok


def joints_on_rails(lengths: dict[str, float], rail: RailSpec) -> dict[str, CheckResult]:
    """``joints_on_rails``: every bar's far joint must sit between two mounting holes of
    its rail (the rail's first joint midway between its holes 0 and 1): not beyond the
    last two, and at least one hole pitch from the first joint. Independent of
    check.bolt_position. ``lengths``: bar -> m."""

    problems, notes = [], []
    for bar in ("crank", "coupler", "rocker"):
        if bar not in lengths:
            continue
        lo, reach = joint_reach(rail, bar)
        length = lengths[bar]
        notes.append(
            f"{bar} {length * 1e3:.6g} mm on a {rail_length(bar) * 1e3:.6g} mm rail (reach "
            f"{lo * 1e3:.6g} to {reach * 1e3:.6g} mm)"
        )
        if length > reach + 1e-9:
            problems.append(
                f"{bar} joint {length * 1e3:.6g} mm from its pivot is beyond the rail's last two holes "
                f"({reach * 1e3:.6g} mm)"
            )
        elif length < lo - 1e-9:
            problems.append(f"{bar} {length * 1e3:.6g} mm is shorter than one hole pitch ({lo * 1e3:.6g} mm)")
    ok = bool(joints_on_rails_flags({k: np.asarray(v) for k, v in lengths.items()}, rail))
    return {"joints_on_rails": CheckResult(ok, "; ".join(problems) if problems else "; ".join(notes))}


def kinematics_summary(mechanism: MechanismSpec, result: KinematicsResult) -> dict:
    """The JSON-ready summary of the kinematics stage of ``mechanism`` (units in the key names)."""
    lk = mechanism.linkage
    dyn = result.dynamics
    peaks, angles = {}, {}
    for joint in dyn.reactions:
        value, k = dyn.peak(joint)
        peaks[joint] = value
        angles[joint] = math.degrees(result.motion.theta2[k])
    torque, kt = dyn.peak_torque()
    angles["torque"] = math.degrees(result.motion.theta2[kt])
    mechanism = {
        "kind": lk.kind,
        "assembly": lk.assembly,
        **{f"{k}_mm": v * 1e3 for k, v in lk.lengths.items()},
        "speed_Hz": mechanism.speed / (2 * math.pi),
        "steps": mechanism.steps,
    }
    return {
        "mechanism": mechanism,
        "formulation": dyn.formulation,
        "effects": list(result.effects),
        "transmission_angle_deg": {"min": result.transmission_deg[0], "max": result.transmission_deg[1]},
        "checks": {name: {"ok": bool(c.ok), "message": c.message} for name, c in result.checks.items()},
        "peak_reactions_N": peaks,
        "peak_torque_Nm": torque,
        "peak_crank_angle_deg": angles,
        "warnings": list(result.motion.warnings),
    }
