"""What every chunk of one linkage kind shares (:class:`SweepContext`, sent to the workers
once) and the revolving settings' loads at the first speed (:class:`Loads`). SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from railcheck.geometry.catalogue import RailSpec
from railcheck.kinematics.batch import BatchDynamics, BatchMotion
from railcheck.sweep.inputs import SweepInput


@dataclass(frozen=True)
class SweepContext:
    """What every chunk of one kind needs (picklable: sent to Dask workers once)."""

    inputs: SweepInput
    kind: str
    speeds: tuple  # rad/s
    steps: int
    models: dict  # part name -> railcheck.sweep.parts.PartModel
    density: float
    rail: RailSpec

    @property
    def effects(self) -> tuple[str, ...]:
        """The loads the sweep simulates (:attr:`railcheck.sweep.inputs.SweepInput.effects`)."""
        return self.inputs.effects


@dataclass(frozen=True)
class Loads:
    """The revolving settings' loads at the first speed: ``inertial`` and ``constant``
    (gravity) parts of the reactions and torque, and the two motions they come from."""

    motion: BatchMotion  # at the first speed
    static: BatchMotion | None  # at rest (gravity), or None
    inertial: BatchDynamics | None  # of the inertia at the first speed (no gravity)
    constant: BatchDynamics | None  # of gravity at rest


def reactions_at(loads: Loads, s) -> tuple[dict, np.ndarray]:
    """(joint -> (S, T, 2) N, torque (S, T) N m) at speed ratio squared ``s``: a scalar,
    or one per setting (S,)."""
    s = np.asarray(s, float)
    weights = [(d, w) for d, w in ((loads.constant, 1.0), (loads.inertial, s)) if d is not None]
    ref = loads.inertial or loads.constant
    if not weights or ref is None:
        raise ValueError("no effect to simulate")
    per = lambda w, nd: w if np.ndim(w) == 0 else np.reshape(w, np.shape(w) + (1,) * (nd - 1))  # noqa: E731
    R = {j: sum(per(w, 3) * d.reactions[j] for d, w in weights) for j in ref.reactions}
    torque: np.ndarray = sum(per(w, 2) * d.torque for d, w in weights)  # a sum of arrays
    return R, torque


def setting_lengths(motion, sel: np.ndarray) -> dict:
    """bar -> (S_sel, 1) m: the settings' crank, coupler and rocker lengths (a slider-crank's
    rocker 0), shaped to broadcast over steps."""
    n = np.size(motion.lengths["crank"])
    get = lambda bar: np.broadcast_to(np.reshape(motion.lengths.get(bar, 0.0), -1), (n,))  # noqa: E731
    return {bar: get(bar)[sel][:, None] for bar in ("crank", "coupler", "rocker")}
