"""What ``railcheck sweep`` reads of a scene, resolved once into a typed, frozen record.

:func:`sweep_input` takes from a :class:`~railcheck.scene.Scene` the [sweep] table, the
part stages' record (:class:`~railcheck.model.inputs.PartsInput`, None without [check]),
the components' (:class:`~railcheck.components.scene_checks.ComponentsInput`), the mass
model, the formulation, the catalogue overrides, the rig's plane and the scene's source;
below :func:`railcheck.sweep.run.run_sweep` the sweep reads that record, never the scene.
The settings settled on their exact response vary the record
(:meth:`SweepInput.responding`), not the scene.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from railcheck.components.ratings import ComponentSpec
from railcheck.components.scene_checks import ComponentsInput, components_input
from railcheck.effects import dynamic_response, simulated_effects
from railcheck.kinematics.massmodel import MassModel
from railcheck.model.inputs import PartsInput, parts_input
from railcheck.scene import Scene
from railcheck.specs import CheckSpec, SweepSpec


@dataclass(frozen=True)
class SweepInput:
    """A sweep's view of a scene (SI).

    Parameters
    ----------
    sweep : [sweep]: the kinds, ranges, extra settings, crank speeds (rad/s), steps,
        assembly, working memory (bytes) and table format.
    parts : the part stages' record ([check], [mesh], [fatigue], [dynamic], ...), or None
        without [check] (a kinematics-only sweep).
    components : the components' record, or None without [check].
    component_spec : [components]: the bearings' spacing reaches the motor columns of a
        kinematics-only sweep too.
    masses : the run's one mass model (kg, m, kg m^2).
    formulation : the inverse-dynamics formulation's name.
    geometry : the catalogue overrides (name -> m).
    plane : the rig's plane.
    source : the scene's source (a path or "built-in"), for the pages and the summary.
    plots : [output] plots: whether the sweep draws its maps and motor.png (the tables,
        summary, pages and card are written whatever it says).
    """

    sweep: SweepSpec
    parts: PartsInput | None
    components: ComponentsInput | None
    component_spec: ComponentSpec
    masses: MassModel
    formulation: str
    geometry: dict[str, float]
    plane: str
    source: str
    plots: bool = True

    @property
    def check(self) -> CheckSpec | None:
        """[check], or None without one."""
        return None if self.parts is None else self.parts.check

    @property
    def requested_effects(self) -> tuple[str, ...]:
        """[check] effects as listed (without a [check]: inertia)."""
        return ("inertia",) if self.parts is None else tuple(self.parts.check.effects)

    @property
    def effects(self) -> tuple[str, ...]:
        """The loads the sweep simulates (:func:`railcheck.effects.simulated_effects` at
        [sweep]'s speeds)."""
        return simulated_effects(self.requested_effects, self.sweep.speeds)

    @property
    def dynamic_response(self) -> bool:
        """Whether the sweep computes the dynamic response, at [sweep]'s speeds."""
        return dynamic_response(self.requested_effects, self.sweep.speeds)

    @property
    def certifies(self) -> bool:
        """Whether the sweep certifies its quasi-static results: parts to check, some speed
        above zero, and no ``dynamic`` listed (that computes the exact response)."""
        return self.parts is not None and any(w > 0 for w in self.sweep.speeds) and not self.dynamic_response

    def responding(self, parts: tuple[str, ...]) -> SweepInput:
        """This record with the ``dynamic`` effect asked for and ``parts`` alone checked
        (the settings beyond a part's quasi-static tolerance: their exact response)."""
        if self.parts is None:
            raise ValueError("a sweep without [check] has no parts to respond")
        check = self.parts.check
        effects = tuple(check.effects) + ("dynamic",) * ("dynamic" not in check.effects)
        kept = tuple(p for p in check.parts if p in parts)
        return replace(self, parts=replace(self.parts, check=replace(check, effects=effects, parts=kept)))


def sweep_input(scene: Scene) -> SweepInput:
    """The scene's :class:`SweepInput`."""
    checked = scene.check is not None
    return SweepInput(
        scene.sweep,
        parts_input(scene) if checked else None,
        components_input(scene) if checked else None,
        scene.components,
        scene.masses,
        scene.formulation,
        scene.geometry,
        scene.plane,
        scene.source,
        scene.output.plots,
    )
