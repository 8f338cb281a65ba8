"""The part registry: the one place that knows the parts railcheck checks.

A :class:`PartKind` says how to build, hold, mesh and measure a kind of part; a
:class:`Part` names one checked part, its kind, and where its loads come from
(:class:`LoadSource`: which joint's reaction, with which sign, in which bar's axes).
Every stage reads this module: the scene (part names), the loads (sources), geometry and
mesh (builder, default sizes), the FE (support, tip, support exclusion) and the report.
Adding a part is one :class:`Part` entry (plus a gmsh builder for a new kind). The joints'
components (pins, shafts, screws, bearings, carriages: no mesh, checked analytically) are
registered beside them, :data:`COMPONENTS` (:mod:`railcheck.components.ratings`); ``[check]
parts`` names both.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from railcheck.components.ratings import COMPONENTS  # noqa: F401  the joints' components, checked by their standards
from railcheck.geometry.catalogue import rail_mass_per_metre_with_holes, with_overrides
from railcheck.geometry.models import i_profile, joint_plate, rail
from railcheck.kinematics.massmodel import MassModel


@dataclass(frozen=True)
class LoadSource:
    """The force on the part at ``joint`` is ``sign`` x the solver's reaction there
    (ground frame, N), taken into the axes of ``axes_bar`` (``crank``, ``coupler``,
    ``rocker``; None: the ground frame)."""

    joint: str
    sign: float
    axes_bar: str | None


@dataclass(frozen=True)
class JointLoad:
    """A joint of a bar seen from its rail: the force on the bar there is ``sign`` x the
    solver's reaction at ``joint``. The point masses bolted there (the mass model's
    :data:`railcheck.kinematics.massmodel.CARRIED`, which depend on the linkage kind) add
    their d'Alembert force and weight through the same holes."""

    joint: str
    sign: float


@dataclass(frozen=True)
class FreeBody:
    """A rail as a free body (``[check] support = "free-body"``): its ``near`` joint on
    the two screws through its first two holes (its upper plate's, the joint's shaft
    midway between them), its ``far`` joint at the bolt holes the bar length picks, and,
    for the crank, the ``motor`` torque entering as a couple over the same two screws."""

    near: JointLoad
    far: JointLoad
    motor: bool = False


@dataclass(frozen=True)
class FreePlate:
    """A joint plate as a free body (``[check] support = "free-body"``): the joint's pin
    force enters at its ``seat`` (the bearing's outer ring) and leaves through its two
    bolts to the rail, less the plate's own d'Alembert force and weight (``mass``: the
    :class:`~railcheck.kinematics.massmodel.MassModel` attribute of its mass); the plate
    moves with the bar it is bolted to (its load source's ``axes_bar``)."""

    seat: str = "bearing_seat"
    mass: str = "plate"


@dataclass(frozen=True)
class PartKind:
    """``build(overrides, rail_length_m or None)`` -> geometry.models.PartGeometry; ``support`` and
    ``tip`` are mesh groups; ``exclusion(geometry)`` the distance (m) from the support
    inside which the idealised clamp's singular stress is reported apart from the verdict;
    ``mesh`` the default (size, hole size) in m from the accuracy-versus-time study;
    ``section(geometry)`` the (width, height) in m of the loaded section, for the
    fatigue size factor. What the stages do differently for a kind is a field here, never a
    test of its name: ``bolts_on_rail`` (a linear-guide rail: its far bolts chosen along it
    by the bar length), ``hole_basis`` (a free body solved once in the basis of its holes'
    loads, any setting's far bolts a combination of it), ``beam_frequency`` (its lowest
    frequency, for the quasi-static certificate, from a beam model rather than FE modes),
    ``weighed_per_metre`` (a profile whose mass per metre the summary states)."""

    name: str
    build: Callable
    support: str
    tip: str
    exclusion: Callable
    mesh: tuple[float, float]
    section: Callable
    bolts_on_rail: bool = False  # bolt holes chosen along a rail by the bar length
    bolt_groups: Callable | None = None  # geometry -> the bolt-hole groups (default: every "hole_K")
    view: str = "xy"  # the picture's view axis pair (pyvista camera.tight): "xy" from above
    hole_basis: bool = False
    beam_frequency: bool = False
    weighed_per_metre: bool = False

    def bolts(self, geometry) -> list[str]:
        """The groups a plate's joint loads (rails choose theirs by the bar length)."""
        if self.bolt_groups is not None:
            return list(self.bolt_groups(geometry))
        return [g for g in geometry.groups if g.startswith("hole_")]


@dataclass(frozen=True)
class Part:
    """One checked part. ``bar``: the bar whose length sets the rail length and the bolt
    position (rails); ``sources``: every joint the part can sit at (a plate used at two
    joints is checked for both; the worse governs)."""

    name: str
    kind: str
    sources: tuple[LoadSource, ...]
    bar: str | None = None
    free_body: FreeBody | None = None
    free_plate: FreePlate | None = None
    foundation: str | None = None  # a face the part is bolted down by: as a free body, a rigid foundation's reaction there


def _rail(overrides: dict, length: float):
    return rail(length, with_overrides(overrides)[0])


def _joint_plate(overrides: dict, length: float | None = None):
    return joint_plate(with_overrides(overrides)[1])


def _i_profile(overrides: dict, length: float | None = None):
    return i_profile(with_overrides(overrides)[2])


KINDS: dict[str, PartKind] = {
    k.name: k
    for k in (
        PartKind(
            "rail",
            _rail,
            "shaft_hole",
            "end_free",
            lambda g: g.get("hole_diameter"),
            (10e-3, 4e-3),
            lambda g: (g.get("width"), g.get("height")),
            bolts_on_rail=True,
            hole_basis=True,
            beam_frequency=True,
            weighed_per_metre=True,
        ),
        PartKind(
            "joint_plate",
            _joint_plate,
            "bearing_seat",
            "end_free",
            lambda g: g.get("bolt_diameter"),
            (6e-3, 1.8e-3),
            lambda g: (g.get("width"), g.get("thickness")),
        ),
        PartKind(
            "i_profile",
            _i_profile,
            "base",
            "end_free",
            lambda g: g.get("flange_thickness"),
            (5e-3, 1.5e-3),
            lambda g: (g.get("flange_width"), g.get("depth")),
            view="yz",
        ),
    )
}

PARTS: dict[str, Part] = {
    p.name: p
    for p in (
        Part(
            "crank-rail",
            "rail",
            (LoadSource("A", -1.0, "crank"),),
            "crank",
            FreeBody(JointLoad("O2", +1.0), JointLoad("A", -1.0), motor=True),
        ),
        Part(
            "coupler-rail",
            "rail",
            (LoadSource("B", -1.0, "coupler"),),
            "coupler",
            FreeBody(JointLoad("A", +1.0), JointLoad("B", -1.0)),
        ),
        Part(
            "rocker-rail",
            "rail",
            (LoadSource("B", +1.0, "rocker"),),
            "rocker",
            FreeBody(JointLoad("O4", +1.0), JointLoad("B", +1.0)),
        ),
        Part(
            "PF_4b_006",
            "joint_plate",
            (LoadSource("A", -1.0, "crank"), LoadSource("B", -1.0, "coupler")),
            free_plate=FreePlate(),
        ),
        Part("PF_4b_003_v2", "i_profile", (LoadSource("O4", +1.0, None),), foundation="base"),
    )
}

BAR_INDEX = {"crank": 0, "coupler": 1, "rocker": 2}


def kind_of(name: str) -> PartKind:
    """The registered kind of the part ``name``."""
    return KINDS[PARTS[name].kind]


def geometry_of(name: str, overrides: dict):
    """The part's geometry (light: no gmsh import), with the scene's catalogue overrides."""
    part = PARTS[name]
    return KINDS[part.kind].build(overrides, rail_length(part.bar) if part.bar else None)


def mass_model(formulation: str, geometry_overrides: dict) -> MassModel:
    """The one mass model of a run, shared by the dynamics and the FE, whatever the
    support: each rail weighs what its meshed profile weighs (the grooved size-25 section
    less its holes, spread per metre: 3.16 kg/m by default) and is placed as it is meshed,
    its pivot midway between its first two holes (the upper plate's shaft between its two
    screws: the catalogue's end distance and half a pitch from the rail's end);
    ``formulation = "seed-2013"`` keeps the 2013 study's masses (2.7 kg/m) and placement
    (the rail starts at the pivot), so its published tables stay reproduced."""
    if formulation == "seed-2013":
        return MassModel()
    rail = with_overrides(geometry_overrides)[0]
    return MassModel(
        rail_mass_per_m=rail_mass_per_metre_with_holes(rail), rail_overhang=rail.end_distance + 0.5 * rail.hole_pitch
    )


def rail_length(bar: str) -> float:
    """m: the physical rail of a bar (seed 000, Anexo I; the mass model's lengths)."""
    return getattr(MassModel(), f"{bar}_rail_length")
