"""A check's cycle -> the components' load histories and their results (one setting:
floats). SI."""

from __future__ import annotations

import dataclasses

from railcheck.components.checks import ComponentResult, JointHistories, Strengths
from railcheck.components.kinds import check_components, with_needs
from railcheck.components.load_path import joint_paths
from railcheck.fea.materials import MATERIALS
from railcheck.loads.bearings import relative_speeds
from railcheck.loads.weight import joint_vertical_loads, screw_pulls, shaft_moment
from railcheck.model.loading import linkage_lengths, rail_weight

#: each bar's first joint, where its rail is screwed to the upper plate
FIRST_JOINTS = {"O2": "crank", "A": "coupler", "O4": "rocker"}


def joint_histories(scene, kin) -> JointHistories:
    """The components' loads over the check's cycle: the kinematics' joint reactions and
    motor torque (unfactored), the bars' angles, the bearings' relative speeds at the
    scene's speed, a table-top rig's weight through the joints A and B and its moment at
    the cantilevered bars' shafts (O2, O4)."""
    motion, dyn = kin.motion, kin.dynamics
    kind = motion.linkage.kind
    theta, omega = motion.theta, motion.omega
    vertical, moments, pulls = {}, {}, {}
    if scene.plane == "horizontal":
        lengths = linkage_lengths(motion.linkage)
        vertical = {
            j: float(v)
            for j, v in joint_vertical_loads(rail_weight(scene.masses, scene.geometry, "crank", kind), lengths).items()
        }
        for joint, bar in FIRST_JOINTS.items():
            if kind == "four-bar" or bar != "rocker":
                w = rail_weight(scene.masses, scene.geometry, bar, kind)
                pulls[joint] = tuple(float(p) for p in screw_pulls(w, lengths))
                if bar != "coupler":
                    moments[joint] = float(shaft_moment(w, lengths))
    return JointHistories(
        reactions=dict(dyn.reactions),
        torque=dyn.torque,
        angles={"crank": theta[:, 0], "coupler": theta[:, 1], "rocker": theta[:, 2]},
        relative_speed=relative_speeds(omega[:, 0], omega[:, 1], omega[:, 2], kind),
        vertical=vertical,
        moments=moments,
        screw_tension=pulls,
    )


def check_scene_components(scene, kin) -> dict[str, ComponentResult]:
    """name -> :class:`ComponentResult` of every component the scene's ``[check] parts``
    lists, on its cycle (one check: floats)."""
    strengths, factor = strengths_of(scene), scene.checked.factor
    histories = joint_histories(scene, kin)
    given = frozenset(scene.raw.get("components", {}))
    results = check_components(scene.checked.components, scene.components, histories, factor, strengths, given)
    return {n: _as_floats(with_needs(r, scene.components, histories, factor, strengths)) for n, r in results.items()}


def strengths_of(scene) -> Strengths:
    """The strengths the components read: the scene's material, its fatigue surface and
    reliability."""
    material = MATERIALS[scene.checked.material]
    return Strengths(material.ultimate_strength, material.yield_strength, scene.fatigue.surface, scene.fatigue.reliability)


def _as_floats(r: ComponentResult) -> ComponentResult:
    """``r`` with its 0-d arrays as floats (one check's figures)."""
    return dataclasses.replace(
        r,
        utilisations={k: float(v) for k, v in r.utilisations.items()},
        figures={k: float(v) for k, v in r.figures.items()},
        needs={k: v if isinstance(v, str) or v is None else float(v) for k, v in r.needs.items()},
    )


def scene_joint_paths(scene, kin) -> dict:
    """joint -> :class:`railcheck.components.load_path.JointPath` of every joint with a
    component the scene lists, at the instant its most utilised component peaks."""
    h = joint_histories(scene, kin)
    checked = scene.checked.components
    return joint_paths(checked, scene.components, h, scene.checked.factor, strengths_of(scene), kin.motion.theta[:, 0])
