"""The joints' components as seed 000's final (v2) joints build them: what each is, every
dimension and rating with its source or the word "assumed", and the scene's
``[components]`` overrides. SI (m, Pa, N, N m, h). The reading of the seed behind each
choice is docs/components.md's.

Seed 000, 3.3.6 (SE_4b_001_v2, SE_4b_002_v2): the upper plate (PF_4b_006 or a thicker
sibling) "se une a la siguiente guía mediante dos tornillos" and turns on a shaft "que está
entre 2 rodamientos" (INA-FAG 6205: C = 14 900 N, C0 = 7 800 N) housed in the lower plate;
"estos rodamientos no están en contacto con la guía"; the shaft is "el diámetro mayor
posible sin que entre en conflicto con los tornillos y sus agujeros" (the 6205's 25 mm
bore). Seed 000, 3.1: the plate's holes are threaded and the screws go "desde la guía a la
pieza". So every joint is a rail screwed to its plate by two screws through two adjacent
holes, the plates turning on a 25 mm shaft between two bearings; at O2 the motor drives
the shaft (seed 000, 5) and its torque reaches the crank rail through the upper plate's two
screws. The lower plate of a moving joint sits on the previous rail's carriage (INA KWVE25)
and is screwed to that rail at the hole its bar length picks. The rails' holes (7 mm
through, 11 mm counterbore, 60 mm pitch) are the size-25 rail catalogue's
(:mod:`railcheck.geometry.catalogue`); the scene's ``[geometry]`` reaches the screws too.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

from railcheck.base.errors import InputError
from railcheck.components.screws import CLASSES, THREADS, admitted
from railcheck.loads.bearings import BEARING_6205


@dataclass(frozen=True)
class ComponentSpec:
    """Every dimension and rating of the joints' components (SI). The comment on each
    field is its source; "assumed" where neither seed 000 nor a cited catalogue gives it."""

    # the screws clamping a plate to a rail: two per plate through two adjacent holes (seed 000)
    screw_size: str = "M6"  # the rail's holes are for M6 (catalogue: 7 mm through, 11 mm counterbore)
    screw_class: str = "8.8"  # assumed: property class 8.8 (ISO 898-1)
    screw_thread_friction: float = 0.12  # assumed: mu_G, steel lightly oiled (VDI 2230 Table A5: 0.10-0.16)
    screw_head_friction: float = 0.12  # assumed: mu_K under the head, as the thread
    screw_tightening_factor: float = 1.6  # assumed: alpha_A of a torque wrench (VDI 2230 Table A8: 1.4-1.6)
    screw_preload_utilisation: float = 0.9  # VDI 2230: assembly preload at 90% of the proof strength
    screw_embedding: float = (
        10e-6  # assumed: f_Z, VDI 2230 Table 5.4/1 (Rz 10-40 um, shear: thread 3, head 4.5, joint 2.5 um)
    )
    joint_friction: float = 0.15  # assumed: mu_T of the rail's base on the plate, steel dry (VDI 2230 Table A6: 0.1-0.23)
    slip_safety: float = 1.8  # VDI 2230 section 5.5.6: S_G >= 1.8 under alternating transverse load (1.2 static)
    screw_grip: float = 13e-3  # the rail's through hole, 22 mm less the 9 mm counterbore (catalogue)
    screw_end_distance: float = 20e-3  # the rail's end distance (catalogue): the first hole to the rail's end
    screw_edge_distance: float = 11.5e-3  # the rail's half width (catalogue): the thinner member's edge
    screw_eccentricity: float = (
        0.0  # the joint's line to the two screws' centroid: midway (seed 000's 6205 clears both screws)
    )
    rail_hole: float = 7e-3  # [geometry] rail_hole_diameter (catalogue)
    rail_counterbore: float = 11e-3  # [geometry] rail_counterbore_diameter (catalogue)
    rail_pitch: float = 60e-3  # [geometry] rail_hole_pitch (catalogue): the two screws' spacing
    # the joints' shafts: the 6205's bore between its two bearings, the upper plate fixed on it
    shaft_diameter: float = 25e-3  # the 6205's bore (seed 000: the largest without conflict with the screws)
    shaft_fillet_radius: float = 1e-3  # the 6205's corner r_s min 1 mm (catalogue): the largest fillet it seats on
    shaft_kt: float = 2.7  # Shigley table 7-1: sharp shoulder fillet (r/d 0.02), bending (r/d 0.04 here: conservative)
    shaft_kts: float = 2.2  # Shigley table 7-1: sharp shoulder fillet, torsion
    shaft_lever: float = 16e-3  # assumed: the upper bearing's centre to the upper plate's mid-plane (7.5 + 1 + 7.5 mm)
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

    @property
    def thread(self):
        """The screws' :class:`~railcheck.components.screws.Thread`."""
        return THREADS[self.screw_size]

    @property
    def property_class(self):
        """The screws' :class:`~railcheck.components.screws.PropertyClass`."""
        return CLASSES[self.screw_class]


COMPONENT_SPEC = ComponentSpec()

#: fields whose source is "assumed" (printed beside a component's verdict unless the scene sets them)
ASSUMED = frozenset(
    {
        "screw_class",
        "screw_thread_friction",
        "screw_head_friction",
        "screw_tightening_factor",
        "screw_embedding",
        "joint_friction",
        "shaft_lever",
        "bearing_spacing",
        "carriage_c0",
        "carriage_m0x",
        "carriage_m0y",
        "carriage_m0z",
        "carriage_height",
        "carriage_required_s0",
    }
)

#: the fields the scene's [geometry] sets (the rail's holes), not [components]
FROM_GEOMETRY = {"rail_hole": "hole_diameter", "rail_counterbore": "counterbore_diameter", "rail_pitch": "hole_pitch"}

#: a [components] key whose value is one of a list of names
CHOICES = {"screw_size": tuple(THREADS), "screw_class": tuple(CLASSES)}

_DIMENSION = {"stress": ("yield", "ultimate"), "force": ("dynamic", "static", "c0"), "moment": ("m0x", "m0y", "m0z")}
_NUMBERS = ("shaft_kt", "shaft_kts", "slip_safety", "joint_friction", "screw_tightening_factor")


def _dimension(name: str) -> str:
    """The quantity a ``[components]`` key is written in (:func:`railcheck.units.parse_quantity`;
    "number" for a plain TOML number, "choice" for one of :data:`CHOICES`)."""
    if name in CHOICES:
        return "choice"
    if name == "bearing_required_life":
        return "time"
    if name in _NUMBERS or name.endswith(("required_s0", "_friction", "_utilisation")):
        return "number"
    for dimension, endings in _DIMENSION.items():
        if name.endswith(endings):
            return dimension
    return "length"


#: the scene's ``[components]`` keys -> the quantity's dimension
OVERRIDABLE = {f.name: _dimension(f.name) for f in fields(ComponentSpec) if f.name not in FROM_GEOMETRY}


def refuse_impossible(spec: ComponentSpec) -> None:
    """Refuse components that cannot be built or flatter the verdict, naming the key: a
    screw the rail's hole does not admit, a fraction outside (0, 1), a friction or
    tightening factor outside what VDI 2230's tables span, end and edge distances below
    EN 1993-1-8 Table 3.3's minimum."""
    sizes = admitted(spec.rail_hole, spec.rail_counterbore)
    if spec.screw_size not in sizes:
        allowed = " or ".join(sizes) if sizes else "no metric screw"
        raise InputError(
            "components.screw_size",
            f"{spec.screw_size} does not fit the rail's {spec.rail_hole * 1e3:g} mm hole and "
            f"{spec.rail_counterbore * 1e3:g} mm counterbore (it admits {allowed}; geometry.rail_hole_diameter)",
        )
    bounds = {
        "screw_preload_utilisation": (0.1, 1.0),
        "screw_thread_friction": (0.04, 0.5),
        "screw_head_friction": (0.04, 0.5),
        "joint_friction": (0.05, 0.8),
        "screw_tightening_factor": (1.0, 4.0),
        "slip_safety": (1.0, 10.0),
        "shaft_kt": (1.0, 10.0),
        "shaft_kts": (1.0, 10.0),
    }
    for key, (lo, hi) in bounds.items():
        v = getattr(spec, key)
        if not lo <= v <= hi:
            raise InputError(f"components.{key}", f"{v:g} is outside {lo:g}-{hi:g}")
    for key in ("screw_end_distance", "screw_edge_distance"):  # EN 1993-1-8 Table 3.3: e1, e2 >= 1.2 d0
        v = getattr(spec, key)
        if v < 1.2 * spec.rail_hole - 1e-12:
            raise InputError(
                f"components.{key}",
                f"{v * 1e3:g} mm is below EN 1993-1-8's minimum 1.2 d0 = {1.2 * spec.rail_hole * 1e3:g} mm "
                "for the rail's hole",
            )
    if spec.screw_eccentricity > 2 * spec.rail_pitch:
        raise InputError("components.screw_eccentricity", "more than two hole pitches from the screws' centroid")


@dataclass(frozen=True)
class Component:
    """One checked component: its ``kind`` (screws, shaft, bearings, carriage), the
    ``joint`` it sits at, the ``rail`` whose axes its loads take (screws, carriages);
    for screws the plate's ``end`` of the rail ("near": the upper plate at the rail's first
    joint; "far": the lower plate at the hole its bar length picks), and whether the motor's
    torque passes (the shaft and the upper screws at O2)."""

    name: str
    kind: str
    joint: str
    rail: str | None = None
    motor: bool = False
    end: str = "near"


COMPONENTS: dict[str, Component] = {
    c.name: c
    for c in (
        Component("crank-screws-O2", "screws", "O2", "crank", motor=True),
        Component("coupler-screws-A", "screws", "A", "coupler"),
        Component("rocker-screws-O4", "screws", "O4", "rocker"),
        Component("crank-screws-A", "screws", "A", "crank", end="far"),
        Component("coupler-screws-B", "screws", "B", "coupler", end="far"),
        Component("rocker-screws-B", "screws", "B", "rocker", end="far"),
        Component("shaft-O2", "shaft", "O2", motor=True),
        Component("shaft-A", "shaft", "A"),
        Component("shaft-B", "shaft", "B"),
        Component("shaft-O4", "shaft", "O4"),
        Component("bearings-O2", "bearings", "O2"),
        Component("bearings-A", "bearings", "A"),
        Component("bearings-B", "bearings", "B"),
        Component("bearings-O4", "bearings", "O4"),
        Component("carriage-A", "carriage", "A", "crank"),
        Component("carriage-B", "carriage", "B", "coupler"),
    )
}

#: the components a slider-crank does not have (no rocker: no O4; its B is the slider's pin)
NOT_ON_SLIDER_CRANK = ("rocker-screws-O4", "rocker-screws-B", "shaft-O4", "bearings-O4")
