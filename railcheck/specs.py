"""The parsed scene's tables as frozen records, SI inside (:mod:`railcheck.scene` reads and
validates them; every stage takes them from a :class:`railcheck.scene.Scene`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from railcheck.kinematics.linkage import FourBar, SliderCrank

SWEEP_KINDS = ("four-bar", "slider-crank")
#: the rig's orientation: "horizontal" (a table-top rig, its weight out of the mechanism
#: plane) or "vertical" (its weight in the plane: the ``gravity`` effect)
PLANES = ("horizontal", "vertical")


@dataclass(frozen=True)
class MechanismSpec:
    """[mechanism]: the linkage, its crank speed (rad/s), steps per revolution and the
    rig's ``plane`` (:data:`PLANES`)."""

    linkage: FourBar | SliderCrank
    speed: float  # rad/s
    steps: int
    plane: str = "horizontal"


@dataclass(frozen=True)
class ExplicitLoad:
    """A force applied on every bolt hole of a part, in the part's frame (N):
    ``longitudinal`` along the part's long axis, ``transverse`` across it in-plane."""

    longitudinal: float
    transverse: float


@dataclass(frozen=True)
class CheckSpec:
    parts: tuple[str, ...]
    factor: float = 1.4
    bolt_position: str = "worst"
    material: str = "steel"
    limit: float | None = None  # Pa; None = sigma_u / 2
    effects: tuple[str, ...] = ("inertia",)
    loads: dict[str, ExplicitLoad] = field(default_factory=dict)
    max_deflection: float | None = None  # m; a part whose tip deflects more fails
    support: str = "free-body"  # "free-body" (inertia relief, rails) or "clamped" (the 2013 cantilever)
    compare: tuple[str, ...] = ()  # "2013": each free rail's clamped 2013 model beside it, for comparison
    components: tuple[str, ...] = ()  # the joints' components checked by their standards (railcheck.components)


#: the fatigue verdict's reliability: 99 % of such parts reach the computed life (Shigley,
#: Mechanical Engineering Design, table 6-5: ke = 0.814), the reliability Shigley's design
#: examples take for machine parts; 0.5 (ke = 1) would be the mean endurance limit, at
#: which half of such parts fail before the computed life
DEFAULT_RELIABILITY = 0.99


@dataclass(frozen=True)
class FatigueSpec:
    """High-cycle fatigue settings (fea.fatigue): each default from Shigley, chapter 6."""

    surface: str = "machined"  # table 6-2; precision rails are ground, plates machined
    reliability: float = DEFAULT_RELIABILITY  # table 6-5; see DEFAULT_RELIABILITY
    load: str = "bending"  # kc: the parts bend under the transverse bolt loads
    criterion: str = "goodman"  # modified Goodman (eq. 6-41); gerber, asme-elliptic
    min_safety: float = 1.0  # a part fails below it


@dataclass(frozen=True)
class DynamicSpec:
    """The dynamic response (effect ``dynamic``; fea.dynamic): the modal damping ratio
    (0.02, assumed for a bolted steel frame with carriages and bearings; EN 1991-1-4 table
    F.2 gives a structural logarithmic decrement of 0.05 for ordinary-bolted steel, zeta =
    0.05 / 2 pi = 0.008, so near a resonance the real peak may be up to 2.5x what 0.02
    gives: the report states the damping used), the largest dynamic amplification a part may
    show (1.10: dynamics that raise a part's stress by more than 10% mean the quasi-static
    check does not hold, and the part fails), and how many modes."""

    damping: float = 0.02
    max_amplification: float = 1.10
    modes: int = 6


@dataclass(frozen=True)
class MeshSpec:
    order: int = 2
    size: float | None = None  # m; None = each part kind's default (parts.KINDS)
    hole_size: float | None = None  # m; None = the kind's default, or 0.3 x size
    optimize: bool = True  # gmsh's tetrahedron optimisation
    curved: bool = True  # P2: mid-edge nodes on the true surfaces (isoparametric)


@dataclass(frozen=True)
class OutputSpec:
    """``[output]``: the results folder, which files to write, and the parts' von Mises
    pictures' colour scale: ``"limit"`` one scale for every part, from 0 to a round value at
    or above the stress limit, or ``"part"`` each to a round value at or above its own peak."""

    dir: str = "results"
    vtk: bool = True
    png: bool = True
    plots: bool = True
    stress_scale: str = "limit"


@dataclass(frozen=True)
class SweepSpec:
    """``railcheck sweep`` settings (SI): the kinds swept, each bar's [min, max] range (m)
    narrowing the rig's grid, the crank speeds (rad/s), steps per revolution, the
    assembly, ``settings`` extra settings per kind (dicts of bar -> m, on the grid or not),
    the working-memory budget (bytes) and the table format."""

    kinds: tuple[str, ...] = SWEEP_KINDS
    ranges: dict = field(default_factory=dict)
    speeds: tuple[float, ...] = (2 * math.pi,)
    steps: int = 720
    assembly: str = "open"
    settings: dict = field(default_factory=dict)
    memory: float = 512e6
    format: str = "parquet"
