"""What would make a check pass: the crank speed up to which the joints' components pass
at the check's setting. The components' model is analytic (kinematics and standards'
formulas, milliseconds a speed), so the speed is searched exactly on the check's own
model: its kinematics rerun at each trial speed, the same components checked, the largest
utilisation's crossing of 1 found by :func:`railcheck.model.crossing.increasing_crossing`
(every utilisation grows with the speed: the joint forces and torque are the inertia's,
growing with its square, over constant weight)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from railcheck.components.scene_checks import check_scene_components
from railcheck.model.crossing import increasing_crossing
from railcheck.model.kinematics_stage import run_kinematics


@dataclasses.dataclass(frozen=True)
class SafeSpeed:
    """The crank speed (Hz) up to which every listed component passes at the check's
    setting (0: one fails at rest; inf: none reaches its limit at any speed), and the
    component and criterion that reach their limit there."""

    hz: float
    component: str
    criterion: str


def components_at_speed(scene, speed: float) -> dict:
    """name -> ComponentResult of the scene's components with the crank at ``speed`` rad/s."""
    at = dataclasses.replace(scene, mechanism=dataclasses.replace(scene.mechanism, speed=speed))
    return check_scene_components(at, run_kinematics(at))


def _largest(results: dict) -> tuple[float, str, str]:
    name = max(results, key=lambda n: float(results[n].utilisation))
    return float(results[name].utilisation), name, str(results[name].governing_criterion)


def components_safe_speed(scene) -> SafeSpeed | None:
    """The crank speed up to which the scene's components pass (None without components
    or without a speed to scale: a static scene)."""
    if not scene.checked.components or scene.mechanism is None or scene.mechanism.speed <= 0:
        return None
    base = scene.mechanism.speed

    def u_of(s, idx):
        return np.array([_largest(components_at_speed(scene, base * math.sqrt(si)))[0] for si in s])

    s = float(increasing_crossing(u_of, 1)[0])
    hz = base * math.sqrt(s) / (2 * math.pi)
    _, name, criterion = _largest(components_at_speed(scene, base * math.sqrt(s) if math.isfinite(s) else base))
    return SafeSpeed(hz, name, criterion)
