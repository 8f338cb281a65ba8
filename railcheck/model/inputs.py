"""What the part stages read of a scene, resolved once into a typed, frozen record.

:func:`parts_input` takes from a :class:`~railcheck.scene.Scene` only what the loads and
the part jobs need ([check], [mechanism], the mass model, the catalogue overrides, [mesh],
[output], [fatigue], [dynamic]); the stages below the command layer read that record, never
the scene. A search that varies a parameter varies the record: :meth:`PartsInput.at_speed`
(a crank speed, rad/s), :meth:`PartsInput.only` (the parts checked, none compared) and
:meth:`PartsInput.clamped` (the 2013 clamped model of one part).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from railcheck.base.errors import InputError
from railcheck.effects import dynamic_response, rig_plane, simulated_effects
from railcheck.kinematics.massmodel import MassModel
from railcheck.scene import Scene
from railcheck.specs import CheckSpec, DynamicSpec, FatigueSpec, MechanismSpec, MeshSpec, OutputSpec


@dataclass(frozen=True)
class PartsInput:
    """The part stages' view of a scene (SI).

    Parameters
    ----------
    check : [check]: the parts, factor, support, bolt position, effects asked for, loads.
    mechanism : [mechanism] (linkage, crank speed rad/s, steps, plane), or None (explicit
        loads only).
    masses : the run's one mass model (kg, m, kg m^2).
    geometry : the catalogue overrides (name -> m).
    mesh, output, fatigue, dynamic : [mesh], [output], [fatigue], [dynamic].
    """

    check: CheckSpec
    mechanism: MechanismSpec | None
    masses: MassModel
    geometry: dict[str, float]
    mesh: MeshSpec
    output: OutputSpec
    fatigue: FatigueSpec
    dynamic: DynamicSpec

    @property
    def linkage_spec(self) -> MechanismSpec:
        """[mechanism], for the loads that come from the linkage (an InputError naming it
        otherwise)."""
        if self.mechanism is None:
            raise InputError("mechanism", "the scene has no [mechanism] table")
        return self.mechanism

    @property
    def speeds(self) -> tuple[float, ...]:
        """The crank speeds (rad/s) the parts are loaded at: [mechanism]'s, none without one."""
        return (self.mechanism.speed,) if self.mechanism else ()

    @property
    def effects(self) -> tuple[str, ...]:
        """The loads simulated (:func:`railcheck.effects.simulated_effects`)."""
        return simulated_effects(self.check.effects, self.speeds)

    @property
    def dynamic_response(self) -> bool:
        """Whether the dynamic response is computed (:func:`railcheck.effects.dynamic_response`)."""
        return dynamic_response(self.check.effects, self.speeds)

    @property
    def plane(self) -> str:
        """The rig's plane: [mechanism]'s, or without one "vertical" when gravity is
        asked for, else "horizontal" (as :attr:`railcheck.scene.Scene.plane`)."""
        return rig_plane(self.mechanism.plane if self.mechanism else None, self.check.effects)

    def at_speed(self, speed: float) -> PartsInput:
        """This record with the crank at ``speed`` rad/s."""
        return replace(self, mechanism=replace(self.linkage_spec, speed=speed))

    def only(self, parts: tuple[str, ...]) -> PartsInput:
        """This record checking ``parts`` alone, with no model compared beside them."""
        return replace(self, check=replace(self.check, parts=parts, compare=()))

    def clamped(self, name: str) -> PartsInput:
        """This record checking the part ``name`` alone as the 2013 study did: clamped."""
        return replace(self, check=replace(self.check, support="clamped", parts=(name,)))


def parts_input(scene: Scene) -> PartsInput:
    """The scene's :class:`PartsInput` (an InputError naming [check] without one)."""
    return PartsInput(
        scene.checked,
        scene.mechanism,
        scene.masses,
        scene.geometry,
        scene.mesh,
        scene.output,
        scene.fatigue,
        scene.dynamic,
    )
