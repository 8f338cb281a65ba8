"""The kinematics stage: a scene's mechanism -> motion, reactions, checks and peaks.

Runs the closed-form kinematics and the requested inverse-dynamics formulation, with
only the effects the scene calls for: inertia needs a non-zero speed (and "inertia" in
check.effects when a [check] table exists); gravity only when listed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from railcheck.base.errors import InputError
from railcheck.base.machine import refuse_kinematics_beyond_memory
from railcheck.geometry.catalogue import with_overrides
from railcheck.kinematics.checks import CheckResult, configuration_checks, transmission_extremes
from railcheck.kinematics.dynamics import STANDARD_GRAVITY, Dynamics, inverse_dynamics
from railcheck.kinematics.linkage import FourBar
from railcheck.kinematics.motion import Motion, solve_motion
from railcheck.parts import rail_length
from railcheck.scene import Scene


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


def run_kinematics(scene: Scene) -> KinematicsResult:
    """Kinematics and inverse dynamics of the scene's mechanism (raises InputError for an
    impossible mechanism, naming the field)."""
    spec = scene.mechanism
    if spec is None:
        raise InputError("mechanism", "missing: this run needs the linkage")
    refuse_kinematics_beyond_memory(spec.steps, "mechanism.steps")
    effects = scene.effects
    motion = solve_motion(spec.linkage, spec.speed, spec.steps)
    dyn_motion = motion if "inertia" in effects else solve_motion(spec.linkage, 0.0, spec.steps)
    gravity = STANDARD_GRAVITY if "gravity" in effects else 0.0
    masses = scene.masses
    dynamics = inverse_dynamics(dyn_motion, scene.formulation, masses, gravity=gravity)
    mu_min, mu_max = transmission_extremes(spec.linkage)
    return KinematicsResult(motion, dynamics, all_checks(scene), effects, (math.degrees(mu_min), math.degrees(mu_max)))


def all_checks(scene: Scene) -> dict[str, CheckResult]:
    """The linkage's configuration checks plus :func:`joints_on_rails`."""
    return {**configuration_checks(scene.linkage_spec.linkage), **joints_on_rails(scene)}


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


def joints_on_rails(scene: Scene) -> dict[str, CheckResult]:
    """``joints_on_rails``: every bar's far joint must sit between two mounting holes of
    its rail (the rail's first joint midway between its holes 0 and 1): not beyond the
    last two, and at least one hole pitch from the first joint. Independent of
    check.bolt_position."""

    rail = with_overrides(scene.geometry)[0]
    lengths = scene.linkage_spec.linkage.lengths
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


def kinematics_summary(scene: Scene, result: KinematicsResult) -> dict:
    """The JSON-ready summary of the kinematics stage (units in the key names)."""
    lk = scene.linkage_spec.linkage
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
        "speed_Hz": scene.linkage_spec.speed / (2 * math.pi),
        "steps": scene.linkage_spec.steps,
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


def is_fourbar(scene: Scene) -> bool:
    return scene.mechanism is not None and isinstance(scene.linkage_spec.linkage, FourBar)
