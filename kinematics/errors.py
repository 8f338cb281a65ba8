"""Errors raised by the kinematics package (derived from :mod:`railcheck.base.errors`).

Each carries ``field``, the scene field it is about (e.g. ``mechanism.ground``), so the
application can print one line naming it.
"""

from __future__ import annotations

from railcheck.base.errors import InputError

__all__ = ["MechanismError", "SingularConfigurationError"]


class MechanismError(InputError):
    """The mechanism cannot be built or cannot run the requested motion (exit status 2)."""


class SingularConfigurationError(MechanismError):
    """The motion passes through a singular configuration (a toggle or a change point):
    the velocity Jacobian is singular there and the reactions are undefined."""

    def __init__(self, field: str, message: str, crank_angle_rad: float):
        self.crank_angle_rad = crank_angle_rad
        super().__init__(field, message)
