"""A check's cycle -> the components' load histories and their results (one setting:
floats). SI.

:func:`components_input` resolves what the components read of a scene once
(:class:`ComponentsInput`); the check and the sweep read that record, never the scene.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from railcheck.components.checks import ComponentResult, JointHistories, Strengths
from railcheck.components.kinds import check_components, with_needs
from railcheck.components.load_path import joint_paths
from railcheck.components.ratings import ComponentSpec
from railcheck.fea.materials import MATERIALS
from railcheck.kinematics.massmodel import MassModel
from railcheck.loads.bearings import relative_speeds
from railcheck.loads.weight import joint_vertical_loads, screw_pulls, shaft_moment
from railcheck.model.loading import linkage_lengths, rail_weight

#: each bar's first joint, where its rail is screwed to the upper plate
FIRST_JOINTS = {"O2": "crank", "A": "coupler", "O4": "rocker"}


@dataclass(frozen=True)
class ComponentsInput:
    """The components' view of a scene (SI).

    Parameters
    ----------
    listed : the components [check] parts lists, in its order.
    spec : [components]: every dimension and rating (seed 000's, a catalogue's or assumed).
    given : the [components] keys the scene sets (an assumed field it gives is no longer assumed).
    factor : [check] factor on the joint forces (1.4 by default).
    strengths : the material's strengths (Pa) and the fatigue surface and reliability.
    plane : the rig's plane; "horizontal" carries a table-top rig's weight through the joints.
    masses : the run's one mass model (kg, m).
    geometry : the catalogue overrides (name -> m).
    """

    listed: tuple[str, ...]
    spec: ComponentSpec
    given: frozenset[str]
    factor: float
    strengths: Strengths
    plane: str
    masses: MassModel
    geometry: dict[str, float]


def components_input(scene) -> ComponentsInput:
    """The scene's :class:`ComponentsInput` (an InputError naming [check] without one)."""
    check = scene.checked
    material = MATERIALS[check.material]
    strengths = Strengths(
        material.ultimate_strength, material.yield_strength, scene.fatigue.surface, scene.fatigue.reliability
    )
    return ComponentsInput(
        tuple(check.components),
        scene.components,
        frozenset(scene.raw.get("components", {})),
        check.factor,
        strengths,
        scene.plane,
        scene.masses,
        scene.geometry,
    )


def joint_histories(inputs: ComponentsInput, kin) -> JointHistories:
    """The components' loads over the check's cycle: the kinematics' joint reactions and
    motor torque (unfactored), the bars' angles, the bearings' relative speeds at the
    scene's speed, a table-top rig's weight through the joints A and B and its moment at
    the cantilevered bars' shafts (O2, O4)."""
    motion, dyn = kin.motion, kin.dynamics
    kind = motion.linkage.kind
    theta, omega = motion.theta, motion.omega
    vertical, moments, pulls = {}, {}, {}
    if inputs.plane == "horizontal":
        lengths = linkage_lengths(motion.linkage)
        vertical = {
            j: float(v)
            for j, v in joint_vertical_loads(rail_weight(inputs.masses, inputs.geometry, "crank", kind), lengths).items()
        }
        for joint, bar in FIRST_JOINTS.items():
            if kind == "four-bar" or bar != "rocker":
                w = rail_weight(inputs.masses, inputs.geometry, bar, kind)
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


def check_listed_components(inputs: ComponentsInput, kin) -> dict[str, ComponentResult]:
    """name -> :class:`ComponentResult` of every component ``inputs`` lists, on the
    check's cycle ``kin`` (one check: floats)."""
    h = joint_histories(inputs, kin)
    results = check_components(inputs.listed, inputs.spec, h, inputs.factor, inputs.strengths, inputs.given)
    return {n: _as_floats(with_needs(r, inputs.spec, h, inputs.factor, inputs.strengths)) for n, r in results.items()}


def _as_floats(r: ComponentResult) -> ComponentResult:
    """``r`` with its 0-d arrays as floats (one check's figures)."""
    return dataclasses.replace(
        r,
        utilisations={k: float(v) for k, v in r.utilisations.items()},
        figures={k: float(v) for k, v in r.figures.items()},
        needs={k: v if isinstance(v, str) or v is None else float(v) for k, v in r.needs.items()},
    )


def listed_joint_paths(inputs: ComponentsInput, kin) -> dict:
    """joint -> :class:`railcheck.components.load_path.JointPath` of every joint with a
    component ``inputs`` lists, at the instant its most utilised component peaks."""
    h = joint_histories(inputs, kin)
    return joint_paths(inputs.listed, inputs.spec, h, inputs.factor, inputs.strengths, kin.motion.theta[:, 0])
