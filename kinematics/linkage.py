"""The two linkages of the rig, in SI units.

Frames: the ground frame has O2 (the crank pivot) at the origin and the x axis through
O4 (four-bar) or parallel to the slider's line (slider-crank). Angles are measured
counter-clockwise from +x, in radians.

* ``theta2``: angle of O2->A (crank).
* ``theta3``: angle of A->B (coupler).
* ``theta4``: angle of O4->B (rocker, four-bar). Seed 000 measures its theta_4 along
  B->O4, i.e. ``theta4 + pi``; angular velocities and accelerations are the same.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import MechanismError

ASSEMBLIES = ("open", "crossed")


def _check_length(field: str, value: float) -> None:
    if not (isinstance(value, (int, float)) and math.isfinite(value)):
        raise MechanismError(field, f"must be a finite length, got {value!r}")
    if value <= 0:
        raise MechanismError(field, f"must be greater than zero, got {value!r} m")


@dataclass(frozen=True)
class FourBar:
    """Four-bar linkage O2-A-B-O4: bar lengths in m (barra 2, 3, 4 and d of seed 000).

    ``assembly`` "open": B lies to the left of the diagonal A->O4 (the quadrilateral
    O2-A-B-O4 is convex while the crank is above the ground line); "crossed": its mirror.
    """

    crank: float
    coupler: float
    rocker: float
    ground: float
    assembly: str = "open"

    def __post_init__(self) -> None:
        for name in ("crank", "coupler", "rocker", "ground"):
            _check_length(f"mechanism.{name}", getattr(self, name))
        if self.assembly not in ASSEMBLIES:
            raise MechanismError("mechanism.assembly", f"must be one of {', '.join(ASSEMBLIES)}, got {self.assembly!r}")

    @property
    def kind(self) -> str:
        return "four-bar"

    @property
    def sign(self) -> float:
        """+1 for the open assembly, -1 for the crossed one."""
        return 1.0 if self.assembly == "open" else -1.0

    @property
    def lengths(self) -> dict[str, float]:
        return {"crank": self.crank, "coupler": self.coupler, "rocker": self.rocker, "ground": self.ground}


@dataclass(frozen=True)
class SliderCrank:
    """Slider-crank O2-A-B with B sliding on the line y = ``offset`` (m).

    ``assembly`` "open": the slider lies on the +x side of A; "crossed": on the -x side.
    """

    crank: float
    coupler: float
    offset: float = 0.0
    assembly: str = "open"

    def __post_init__(self) -> None:
        _check_length("mechanism.crank", self.crank)
        _check_length("mechanism.coupler", self.coupler)
        if not math.isfinite(self.offset):
            raise MechanismError("mechanism.ground", f"slider offset must be finite, got {self.offset!r}")
        if self.assembly not in ASSEMBLIES:
            raise MechanismError("mechanism.assembly", f"must be one of {', '.join(ASSEMBLIES)}, got {self.assembly!r}")

    @property
    def kind(self) -> str:
        return "slider-crank"

    @property
    def sign(self) -> float:
        return 1.0 if self.assembly == "open" else -1.0

    @property
    def lengths(self) -> dict[str, float]:
        return {"crank": self.crank, "coupler": self.coupler, "offset": self.offset}
