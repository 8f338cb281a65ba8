"""The joints' components (DESIGN.md section 13): what each is, every dimension and
rating with its source or the word "assumed", and the scene's ``[components]`` overrides.
SI (m, Pa, N, N m, h).

Seed 000 (3.3.6, the final design): each revolute joint's shaft runs from its two
bearings (INA-FAG 6205, C = 14 900 N, C0 = 7 800 N) through the second hole of the next
rail, "the largest diameter possible without conflict with the screws"; the joint plate
(PF_4b_006) is joined to the next rail "by two screws"; the carriages are INA KWVE25 on
TKVD25 rails; the motor torque enters the crank over its shaft and the driving pin in the
next hole (DESIGN.md section 13). The rails' holes (7 mm through, 11 mm counterbore 9 mm
deep, 60 mm pitch) are the size-25 rail catalogue's (:mod:`railcheck.geometry.catalogue`).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

from railcheck.base.errors import InputError
from railcheck.loads.bearings import BEARING_6205


@dataclass(frozen=True)
class ComponentSpec:
    """Every dimension and rating of the joints' components (SI). The comment on each
    field is its source; "assumed" where neither seed 000 nor a cited catalogue gives it."""

    # the driving pin (crank rail to the motor's hub, single shear)
    pin_diameter: float = 7e-3  # assumed: the largest that passes the rail's 7 mm hole (catalogue)
    pin_arm: float = 60e-3  # the rail's hole pitch (catalogue): shaft hole to the driving pin's hole
    pin_rail_thickness: float = 13e-3  # the rail's through hole, 22 mm less the 9 mm counterbore (catalogue)
    pin_hub_thickness: float = 10e-3  # assumed: the motor hub's plate
    pin_gap: float = 1e-3  # assumed: between the rail's base and the hub
    pin_yield: float = 640e6  # assumed: property class 8.8 steel (ISO 898-1: f_y 640 MPa)
    pin_ultimate: float = 800e6  # assumed: property class 8.8 steel (ISO 898-1: f_u 800 MPa)
    # the joint plate's screws to the next rail (two per plate, seed 000)
    bolt_diameter: float = 6e-3  # M6: the rail's holes are for M6 (catalogue)
    bolt_stress_area: float = 20.1e-6  # M6 tensile stress area (ISO 898-1)
    bolt_ultimate: float = 800e6  # assumed: property class 8.8 (ISO 898-1)
    bolt_alpha_v: float = 0.6  # EN 1993-1-8 Table 3.4, classes 4.6, 5.6 and 8.8
    bolt_hole: float = 6.6e-3  # M6 medium clearance (ISO 273), as the plate's holes
    bolt_pitch: float = 60e-3  # the rail's hole pitch (catalogue): the plate's two screws
    bolt_eccentricity: float = 70e-3  # assumed: the plate's seat to its screws' centroid (PF_4b_006 as modelled)
    bolt_end_distance: float = 20e-3  # assumed: the last screw to the plate's end (PF_4b_006 as modelled)
    bolt_edge_distance: float = 11.5e-3  # the rail's half width (catalogue): the thinner member's edge
    bolt_grip: float = 13e-3  # the rail's through hole (catalogue): the thinner member in bearing
    # the joints' shafts: stepped from the bearings' bore to the stub through the rail's hole
    shaft_diameter: float = 7e-3  # assumed: the stub the rail's 7 mm hole admits (seed 000: "the largest possible")
    shaft_fillet_radius: float = 0.7e-3  # assumed: a well-rounded shoulder, r/d = 0.1 (Shigley table 7-1)
    shaft_kt: float = 1.7  # Shigley table 7-1: well-rounded shoulder fillet, bending
    shaft_kts: float = 1.5  # Shigley table 7-1: well-rounded shoulder fillet, torsion
    shaft_lever: float = 7.5e-3  # assumed: the shoulder to the rail's bearing resultant (half its 13 mm hole, 1 mm gap)
    motor_shaft_diameter: float = 25e-3  # the 6205's bore (catalogue): the motor shaft in its bearings
    motor_shaft_lever: float = 30e-3  # assumed: the bearing's shoulder to the crank rail's mid-height
    # the bearings: two per joint (seed 000)
    bearing_dynamic: float = BEARING_6205.dynamic_capacity  # seed 000 (INA-FAG catalogue): C
    bearing_static: float = BEARING_6205.static_capacity  # seed 000 (INA-FAG catalogue): C0
    bearing_spacing: float = 15e-3  # assumed: the two bearings side by side (the 6205 is 15 mm wide, catalogue)
    bearing_required_s0: float = 1.0  # ISO 76 practice for ball bearings in normal service (SKF, Schaeffler)
    bearing_required_life: float = 8000.0 * 3600.0  # Shigley table 11-4: machines for intermittent service, 4-8 kh
    # the carriages (INA KWVE25): their ratings are not in the stored catalogues
    carriage_c0: float = 50_000.0  # assumed: a size-25 ball carriage's C0 (HIWIN HGH25CA class); check INA's KWVE25
    carriage_m0x: float = 500.0  # assumed: roll moment rating, same class
    carriage_m0y: float = 450.0  # assumed: pitch moment rating, same class
    carriage_m0z: float = 450.0  # assumed: yaw moment rating, same class
    carriage_height: float = 30e-3  # assumed: the carriage's rating point to the joint force's line
    carriage_required_s0: float = 3.0  # assumed: the top of the catalogues' 1-3 range for normal loading


COMPONENT_SPEC = ComponentSpec()

#: fields whose source is "assumed" (printed beside a component's verdict)
ASSUMED = frozenset(
    {
        "pin_diameter",
        "pin_hub_thickness",
        "pin_gap",
        "pin_yield",
        "pin_ultimate",
        "bolt_ultimate",
        "bolt_eccentricity",
        "bolt_end_distance",
        "shaft_diameter",
        "shaft_fillet_radius",
        "shaft_lever",
        "motor_shaft_lever",
        "bearing_spacing",
        "carriage_c0",
        "carriage_m0x",
        "carriage_m0y",
        "carriage_m0z",
        "carriage_height",
        "carriage_required_s0",
    }
)

_DIMENSION = {"stress": ("yield", "ultimate"), "force": ("dynamic", "static", "c0"), "moment": ("m0x", "m0y", "m0z")}


def _dimension(name: str) -> str:
    """The quantity a ``[components]`` key is written in (:func:`railcheck.units.parse_quantity`;
    "number" for a plain TOML number)."""
    if name == "bolt_stress_area":
        return "area"
    if name == "bearing_required_life":
        return "time"
    if name in ("bolt_alpha_v", "shaft_kt", "shaft_kts") or name.endswith("required_s0"):
        return "number"
    for dimension, endings in _DIMENSION.items():
        if name.endswith(endings):
            return dimension
    return "length"


#: the scene's ``[components]`` keys -> the quantity's dimension
OVERRIDABLE = {f.name: _dimension(f.name) for f in fields(ComponentSpec)}


def refuse_wider_than_the_rails_hole(spec: ComponentSpec, hole: float) -> None:
    """Refuse a driving pin or a joint shaft's stub wider than the rail's ``hole`` (m)
    it passes, naming the field."""
    for key in ("pin_diameter", "shaft_diameter"):
        d = getattr(spec, key)
        if d > hole + 1e-12:
            raise InputError(
                f"components.{key}",
                f"{d * 1e3:g} mm does not pass the rail's {hole * 1e3:g} mm hole (geometry.rail_hole_diameter)",
            )


@dataclass(frozen=True)
class Component:
    """One checked component: its ``kind`` (pin, bolts, shaft, bearings, carriage), the
    ``joint`` it sits at, the ``rail`` whose axes its loads take (bolts, carriages) and,
    for a shaft, whether it carries the motor's torque."""

    name: str
    kind: str
    joint: str
    rail: str | None = None
    motor: bool = False

    @property
    def factored(self) -> bool:
        """Whether the scene's load factor applies: the strength checks (pins, bolts, shafts)
        yes; the rolling elements' (bearings, carriages) standards set their own safety on
        unfactored loads."""
        return self.kind in ("pin", "bolts", "shaft")


COMPONENTS: dict[str, Component] = {
    c.name: c
    for c in (
        Component("driving-pin", "pin", "O2", "crank"),
        Component("motor-shaft", "shaft", "O2", "crank", motor=True),
        Component("shaft-A", "shaft", "A"),
        Component("shaft-B", "shaft", "B"),
        Component("shaft-O4", "shaft", "O4"),
        Component("bolts-A", "bolts", "A", "crank"),
        Component("bolts-B", "bolts", "B", "coupler"),
        Component("bearings-O2", "bearings", "O2"),
        Component("bearings-A", "bearings", "A"),
        Component("bearings-B", "bearings", "B"),
        Component("bearings-O4", "bearings", "O4"),
        Component("carriage-A", "carriage", "A", "crank"),
        Component("carriage-B", "carriage", "B", "coupler"),
    )
}

#: the components a slider-crank does not have (no rocker: no O4; its B is the slider's pin)
NOT_ON_SLIDER_CRANK = ("shaft-O4", "bearings-O4")
