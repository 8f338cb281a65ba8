"""railcheck.kinematics.planar: general planar mechanisms in body coordinates (seed 002).

:mod:`.model` (bodies, joints, drivers), :mod:`.solver` (mobility, positions by
Newton-Raphson along the driver, velocities, accelerations, Lagrange reactions),
:mod:`.dyads` (closed-form positions of a crank plus dyads), :mod:`.catalogue` (Artobolevsky
tracer mechanisms and the rig's linkages). Units SI.
"""

from .catalogue import CATALOGUE, SWEEPS, driver_values
from .model import Body, Fixed, Mechanism, Prismatic, Revolute, RotationDriver, TranslationDriver
from .solver import Mobility, PlanarMotion, PlanarReactions, mobility, solve

__all__ = [
    "CATALOGUE",
    "SWEEPS",
    "Body",
    "Fixed",
    "Mechanism",
    "Mobility",
    "PlanarMotion",
    "PlanarReactions",
    "Prismatic",
    "Revolute",
    "RotationDriver",
    "TranslationDriver",
    "driver_values",
    "mobility",
    "solve",
]
