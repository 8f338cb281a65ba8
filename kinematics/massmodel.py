"""The rig's mass model (seed 000, Anexo I, final values) and rigid bodies built from it.

SI units: kg, m, kg m^2. Body frames: each bar's local x axis runs from its first joint
(O2 for the crank, A for the coupler, O4 for the rocker) along the bar, so a point at
local coordinate ``s`` lies at ``first_joint + s * e_bar``.
"""

from __future__ import annotations

from dataclasses import dataclass

from .linkage import FourBar, SliderCrank


@dataclass(frozen=True)
class MassModel:
    """Masses of the rig's parts (seed 000 Anexo I; every value overridable).

    ``rail_mass_per_m`` is the seed's 2.7 kg/m (the TKDV25 catalogue figure it used),
    kept for ``formulation = "seed-2013"``; every other run takes the meshed profile's
    3.16 kg/m (railcheck.parts.mass_model, geometry.catalogue).
    """

    rail_mass_per_m: float = 2.7
    crank_rail_length: float = 0.7
    coupler_rail_length: float = 1.0
    rocker_rail_length: float = 1.0
    carriage: float = 0.68  # patin KWVE25
    plate: float = 1.155  # disco, PF_4b_006
    coupling: float = 0.577  # acop
    # m of rail behind the first joint: 0 is the 2013 study's placement (the rail starts at
    # the pivot); the rail's first hole, where the pivot sits, is really 20 mm from its end,
    # and the free-body check uses that (railcheck.parts.mass_model), as its FE meshes it
    rail_overhang: float = 0.0

    @property
    def plate_and_carriage(self) -> float:
        return self.plate + self.carriage


@dataclass(frozen=True)
class RigidBar:
    """A bar as one rigid body: total mass (kg), centre of mass at local coordinate
    ``com`` (m from the first joint along the bar) and inertia ``inertia_com`` (kg m^2)
    about the centre of mass."""

    mass: float
    com: float
    inertia_com: float


def bar_from_parts(
    rail_mass: float, rail_length: float, point_masses: list[tuple[float, float]], overhang: float = 0.0
) -> RigidBar:
    """Combine a uniform rail from local ``-overhang`` (m) with point masses [(mass kg, s m)]."""
    parts = [(rail_mass, rail_length / 2.0 - overhang, rail_mass * rail_length**2 / 12.0)]
    parts += [(m, s, 0.0) for m, s in point_masses]
    mass = sum(m for m, _, _ in parts)
    com = sum(m * s for m, s, _ in parts) / mass
    inertia = sum(i + m * (s - com) ** 2 for m, s, i in parts)
    return RigidBar(mass=mass, com=com, inertia_com=inertia)


def rail_body(masses: MassModel, bar: str, point_masses: list[tuple[float, float]]) -> RigidBar:
    """The ``bar``'s rail (``crank``, ``coupler``, ``rocker``) with the point masses it
    carries [(kg, m from its first joint)], from the mass model."""
    length = getattr(masses, f"{bar}_rail_length")
    return bar_from_parts(masses.rail_mass_per_m * length, length, point_masses, masses.rail_overhang)


#: The point masses each bar's rail carries at its joints, by linkage kind: bar -> joint ->
#: :class:`MassModel` attribute names (seed 000, Anexo I; the slider-crank's assumed, the
#: seed left it undone). The one place the dynamics' rigid bodies and the FE's joint loads
#: and lumped masses read them from. Each bar's first joint (O2, A, O4) is at s = 0, its
#: second at s = its length.
CARRIED: dict[str, dict[str, dict[str, tuple[str, ...]]]] = {
    "four-bar": {
        "crank": {"A": ("plate", "carriage")},
        "coupler": {"A": ("coupling",), "B": ("plate", "carriage")},
        "rocker": {"B": ("coupling",)},
    },
    "slider-crank": {
        "crank": {"A": ("plate", "carriage")},
        "coupler": {"A": ("coupling",), "B": ("coupling",)},
    },
}
FIRST_JOINT = {"crank": "O2", "coupler": "A", "rocker": "O4"}


def carried_mass(masses: MassModel, kind: str, bar: str, joint: str) -> float:
    """kg: the point masses ``bar``'s rail carries at ``joint`` in a ``kind`` linkage."""
    return sum(getattr(masses, name) for name in CARRIED[kind].get(bar, {}).get(joint, ()))


def _carrying_rail(masses: MassModel, kind: str, bar: str, length) -> RigidBar:
    """A bar's rail with the point masses :data:`CARRIED` puts at its two joints."""
    joints = CARRIED[kind][bar]
    points = [(carried_mass(masses, kind, bar, j), 0.0 if j == FIRST_JOINT[bar] else length) for j in joints]
    return rail_body(masses, bar, points)


def fourbar_bodies(linkage: FourBar, masses: MassModel) -> tuple[RigidBar, RigidBar, RigidBar]:
    """Crank, coupler and rocker as rigid bodies (seed 000, Anexo I mass model).

    Crank: rail + plate and carriage at A. Coupler: rail from A + coupling at A + plate
    and carriage at B. Rocker: rail from O4 + coupling at B (:data:`CARRIED`).
    """
    return tuple(_carrying_rail(masses, "four-bar", bar, getattr(linkage, bar)) for bar in ("crank", "coupler", "rocker"))  # type: ignore[return-value]


def slidercrank_bodies(linkage: SliderCrank, masses: MassModel) -> tuple[RigidBar, RigidBar, RigidBar]:
    """Crank, coupler and slider (assumed: the seed left the slider-crank undone).

    Crank: as in the four-bar. Coupler: rail from A + coupling at A + coupling at B
    (:data:`CARRIED`). Slider: a carriage with its plate on the ground rail (a particle,
    no rotation).
    """
    crank, coupler = (_carrying_rail(masses, "slider-crank", bar, getattr(linkage, bar)) for bar in ("crank", "coupler"))
    slider = RigidBar(mass=masses.plate_and_carriage, com=0.0, inertia_com=0.0)
    return crank, coupler, slider
