"""What every chunk of one linkage kind shares (:class:`SweepContext`, sent to the workers
once) and the revolving settings' loads at the first speed (:class:`Loads`). SI.
"""

from __future__ import annotations

from dataclasses import dataclass

from railcheck.geometry.catalogue import RailSpec
from railcheck.kinematics.batch import BatchDynamics, BatchMotion
from railcheck.scene import Scene


@dataclass(frozen=True)
class SweepContext:
    """What every chunk of one kind needs (picklable: sent to Dask workers once)."""

    scene: Scene
    kind: str
    speeds: tuple  # rad/s
    steps: int
    models: dict  # part name -> railcheck.sweep.parts.PartModel
    density: float
    rail: RailSpec

    @property
    def effects(self) -> tuple[str, ...]:
        return self.scene.check.effects if self.scene.check else ("inertia",)


@dataclass(frozen=True)
class Loads:
    """The revolving settings' loads at the first speed: ``inertial`` and ``constant``
    (gravity) parts of the reactions and torque, and the two motions they come from."""

    motion: BatchMotion  # at the first speed
    static: BatchMotion | None  # at rest (gravity), or None
    inertial: BatchDynamics | None  # of the inertia at the first speed (no gravity)
    constant: BatchDynamics | None  # of gravity at rest
