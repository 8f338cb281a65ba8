"""What every chunk of one linkage kind shares (:class:`SweepContext`, sent to the workers
once) and the revolving settings' loads at the first speed (:class:`Loads`). SI.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SweepContext:
    """What every chunk of one kind needs (picklable: sent to Dask workers once)."""

    scene: object
    kind: str
    speeds: tuple  # rad/s
    steps: int
    models: dict  # part name -> railcheck.sweep.parts.PartModel
    density: float
    rail: object  # geometry.catalogue.RailSpec

    @property
    def effects(self) -> tuple[str, ...]:
        return self.scene.check.effects if self.scene.check else ("inertia",)


@dataclass(frozen=True)
class Loads:
    """The revolving settings' loads at the first speed: ``inertial`` and ``constant``
    (gravity) parts of the reactions and torque, and the two motions they come from."""

    motion: object  # at the first speed
    static: object | None  # at rest (gravity), or None
    inertial: object | None  # BatchDynamics of the inertia at the first speed (no gravity)
    constant: object | None  # BatchDynamics of gravity at rest
