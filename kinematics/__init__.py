"""railcheck.kinematics: the rig's linkages over a crank revolution.

:mod:`.linkage` (four-bar and slider-crank dimensions), :mod:`.motion` (closed-form
positions, velocities, accelerations), :mod:`.dynamics` (inverse dynamics: joint reactions
and motor torque, ``newton-euler`` and ``seed-2013``), :mod:`.massmodel` (the one mass
model), :mod:`.checks` (configuration checks), :mod:`.batch` (the same vectorised over
settings x steps), :mod:`.planar` (general planar mechanisms in body coordinates, seed 002).
Imports nothing of railcheck but its errors. Units SI.
"""

from .checks import CheckLimits, CheckResult, configuration_checks, grashof_class, transmission_extremes
from .dynamics import FORMULATIONS, STANDARD_GRAVITY, Dynamics, inverse_dynamics, kinetic_energy, power_residual
from .errors import MechanismError, SingularConfigurationError
from .linkage import FourBar, SliderCrank
from .massmodel import MassModel, RigidBar
from .motion import Motion, crank_angles, solve_motion

__all__ = [
    "FORMULATIONS",
    "STANDARD_GRAVITY",
    "CheckLimits",
    "CheckResult",
    "Dynamics",
    "FourBar",
    "MassModel",
    "MechanismError",
    "Motion",
    "RigidBar",
    "SingularConfigurationError",
    "SliderCrank",
    "configuration_checks",
    "crank_angles",
    "grashof_class",
    "inverse_dynamics",
    "kinetic_energy",
    "power_residual",
    "solve_motion",
    "transmission_extremes",
]
