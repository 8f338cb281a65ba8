"""Every dimension of the modelled parts, with its source or the word "assumed".

SI units (m). Part frames: x along the part's long axis (longitudinal), y across it in
the mechanism's plane (transverse), z normal to the plane (the bolts' axis).

The size-25 profile rail: THK HSR25 and HIWIN HGR25 catalogues agree on the section
(23 x 22 mm) and the mounting holes (60 mm pitch, 20 mm end distance, M6 counterbored
7 x 11 x 9 mm); INA TKVD25 (seed 000) is of this size. The four ball tracks are modelled
as four semicircular grooves along the rail, two in each side face (:class:`RailSpec`);
the catalogues do not dimension them, so their radius and heights are assumed, chosen so
the rail with its holes weighs what the catalogues say (3.16 kg/m against 3.1-3.21 kg/m:
:func:`rail_mass_per_metre_with_holes`) and so the section's centroid stays at mid-height.

PF_4b_006 and PF_4b_003_v2: seed 000 shows them only as pictures, so their dimensions
here are assumptions, chosen to be plausible and, for PF_4b_006, to match the seed's
plate mass (1.155 kg in steel).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any

STEEL_DENSITY = 7850.0  # kg/m^3


@dataclass(frozen=True)
class RailSpec:
    """Size-25 rail (THK HSR25 / HIWIN HGR25 catalogue)."""

    width: float = 23e-3  # catalogue
    height: float = 22e-3  # catalogue
    hole_pitch: float = 60e-3  # catalogue
    end_distance: float = 20e-3  # catalogue (E = 20 mm)
    hole_diameter: float = 7e-3  # catalogue, through hole for M6
    counterbore_diameter: float = 11e-3  # catalogue
    counterbore_depth: float = 9e-3  # catalogue
    groove_radius: float = 3.6e-3  # assumed: sized to the catalogue mass (0 = a solid rectangle)
    lower_groove_z: float = 6.1e-3  # assumed: centre height of the lower groove above the base
    upper_groove_z: float = 15.9e-3  # assumed: of the upper groove (symmetric about mid-height)

    def hole_positions(self, length: float) -> list[float]:
        """x of every mounting hole (m) along a rail of ``length`` m."""
        n = int(math.floor((length - 2 * self.end_distance) / self.hole_pitch + 1e-9)) + 1
        return [self.end_distance + k * self.hole_pitch for k in range(max(n, 0))]


@dataclass(frozen=True)
class JointPlateSpec:
    """PF_4b_006, the upper plate of seed 000's final joints (3.3.6, SE_4b_001_v2 /
    SE_4b_002_v2; assumed dimensions): a steel plate screwed to the next rail by two
    screws through two of its neighbouring holes, fixed on the joint's shaft, whose line
    lies midway between the two screws (the 6205 bearings it turns in are in the lower
    plate, the previous rail's). So the plate has the shaft's 25 mm bore (the 6205's bore)
    at its centre and a screw hole half a rail pitch either side (``bolt_x``: from the
    rail's pitch, :func:`with_overrides`). The seed's 1.155 kg is the mass the dynamics
    and the FE carry."""

    length: float = 120e-3  # assumed: the two screws 30 mm from its ends
    width: float = 75e-3  # assumed
    thickness: float = 15e-3  # assumed: the 6205's width
    seat_diameter: float = 25e-3  # the shaft's bore: the 6205's bore (catalogue), the shaft fixed in the plate
    seat_x: float = 60e-3  # assumed: the shaft at the plate's centre, midway between the screws
    bolt_diameter: float = 6.6e-3  # M6 medium clearance (ISO 273)
    bolt_x: tuple[float, float] = (30e-3, 90e-3)  # half the rail's 60 mm pitch either side of the shaft


@dataclass(frozen=True)
class IProfileSpec:
    """PF_4b_003_v2 I-profile (assumed dimensions): an I-section extruded along x,
    flanges normal to z; four M6 clearance holes through the top flange on a 60 x 30 mm
    pattern; the bottom flange's lower face is bolted to the ground rail (held)."""

    length: float = 100e-3  # assumed
    flange_width: float = 60e-3  # assumed (y)
    depth: float = 60e-3  # assumed (z, overall height)
    flange_thickness: float = 8e-3  # assumed
    web_thickness: float = 6e-3  # assumed
    root_radius: float = 3e-3  # assumed: the web-flange fillet (a sharp corner is a stress singularity)
    bolt_diameter: float = 6.6e-3  # M6 medium clearance (ISO 273)
    bolt_pitch_x: float = 60e-3  # assumed
    bolt_pitch_y: float = 36e-3  # assumed


RAIL = RailSpec()
JOINT_PLATE = JointPlateSpec()
I_PROFILE = IProfileSpec()

#: scene [geometry] keys -> (spec name, field)
OVERRIDABLE = {f"rail_{f.name}": ("rail", f.name) for f in fields(RailSpec)}
OVERRIDABLE |= {f"plate_{f.name}": ("plate", f.name) for f in fields(JointPlateSpec) if f.name != "bolt_x"}
OVERRIDABLE |= {f"iprofile_{f.name}": ("iprofile", f.name) for f in fields(IProfileSpec)}


def with_overrides(overrides: dict[str, float]) -> tuple[RailSpec, JointPlateSpec, IProfileSpec]:
    """The three specs with the scene's [geometry] overrides (SI) applied."""
    specs: dict[str, Any] = {"rail": RAIL, "plate": JOINT_PLATE, "iprofile": I_PROFILE}
    for key, value in overrides.items():
        which, name = OVERRIDABLE[key]
        specs[which] = replace(specs[which], **{name: value})
    plate, half = specs["plate"], specs["rail"].hole_pitch / 2  # the plate's screws on the rail's pitch
    specs["plate"] = replace(plate, bolt_x=(plate.seat_x - half, plate.seat_x + half))
    return specs["rail"], specs["plate"], specs["iprofile"]


@dataclass(frozen=True)
class RailSection:
    """The rail's cross-section (holes excluded), in the part frame: ``area`` m^2,
    ``centroid_z`` m above the base (y = 0 by symmetry), ``inertia_in_plane`` m^4 about
    the z axis through the centroid (bending by in-plane, y, loads), ``inertia_out_of_plane``
    m^4 about the y axis through the centroid (bending by z loads)."""

    area: float
    centroid_z: float
    inertia_in_plane: float
    inertia_out_of_plane: float
    width: float
    height: float

    @property
    def modulus_in_plane(self) -> float:
        """m^3: I / c for in-plane bending, c the half width (the side faces' lands)."""
        return self.inertia_in_plane / (self.width / 2)

    @property
    def modulus_out_of_plane(self) -> float:
        """m^3: I / c for out-of-plane bending, c the farther face from the centroid."""
        return self.inertia_out_of_plane / max(self.centroid_z, self.height - self.centroid_z)


def rail_section(spec: RailSpec = RAIL) -> RailSection:
    """The grooved profile's section properties in closed form: the w x h rectangle less
    four half-discs of radius r, their flat sides on the side faces at the grooves'
    heights. A half-disc's second moment about its flat side and about the axis normal to
    it through its centre is pi r^4 / 8 each; its centroid lies 4 r / (3 pi) inside."""
    w, h, r = spec.width, spec.height, spec.groove_radius
    zs = (spec.lower_groove_z, spec.upper_groove_z)
    half = math.pi * r**2 / 2
    area = w * h - 4 * half
    centroid_z = (w * h * h / 2 - 2 * half * sum(zs)) / area
    lever = 4 * r / (3 * math.pi)
    # about y = 0: each half-disc's integral of y^2, with y = w/2 - s and s >= 0 inward
    groove_y2 = half * (w / 2) ** 2 - 2 * (w / 2) * half * lever + math.pi * r**4 / 8
    inertia_in_plane = h * w**3 / 12 - 4 * groove_y2
    rect_z2 = w * h**3 / 12 + w * h * (h / 2 - centroid_z) ** 2
    grooves_z2 = sum(2 * (math.pi * r**4 / 8 + half * (z - centroid_z) ** 2) for z in zs)
    return RailSection(area, centroid_z, inertia_in_plane, rect_z2 - grooves_z2, w, h)


def rail_mass_per_metre(spec: RailSpec = RAIL, density: float = STEEL_DENSITY) -> float:
    """Mass per metre (kg/m) of the modelled section (grooved profile), holes excluded."""
    return rail_section(spec).area * density


def rail_mass_per_metre_with_holes(spec: RailSpec = RAIL, density: float = STEEL_DENSITY) -> float:
    """Mass per metre (kg/m) of the modelled rail with its counterbored holes removed."""
    through = math.pi / 4 * spec.hole_diameter**2 * (spec.height - spec.counterbore_depth)
    cbore = math.pi / 4 * spec.counterbore_diameter**2 * spec.counterbore_depth
    return rail_mass_per_metre(spec, density) - (through + cbore) * density / spec.hole_pitch


#: what the catalogues and the seed say the rail weighs (kg/m)
CATALOGUE_RAIL_MASS = {"HIWIN HGR25 catalogue": 3.21, "seed 000 (Anexo I)": 2.7}


def plate_planar_inertia(spec: JointPlateSpec = JOINT_PLATE) -> tuple[float, float]:
    """(x of the centroid m, polar second moment of area about the seat's centre per unit
    area m^2) of the plate's outline with its seat and bolt holes cut through: a plate of
    mass m has its centre of mass at that x and I_seat = m x that second moment."""
    import math

    regions = [(spec.length * spec.width, spec.length / 2, (spec.length**2 + spec.width**2) / 12)]
    for x, d in [(spec.seat_x, spec.seat_diameter)] + [(x, spec.bolt_diameter) for x in spec.bolt_x]:
        regions.append((-math.pi * d**2 / 4, x, d**2 / 8))  # a hole: negative area, r^2 / 2 about its centre
    area = sum(a for a, _, _ in regions)
    centroid = sum(a * x for a, x, _ in regions) / area
    polar = sum(a * (j + (x - spec.seat_x) ** 2) for a, x, j in regions) / area
    return centroid, polar


def _rail_checks(rail) -> list[tuple[str, bool, str]]:
    """(field, holds, message) of the rail's dimensions: holes, counterbores, grooves, pitch."""
    return [
        (
            "rail_hole_diameter",
            rail.hole_diameter < 0.8 * rail.width,
            "the through hole must be narrower than 0.8 x the rail width",
        ),
        (
            "rail_counterbore_diameter",
            rail.hole_diameter < rail.counterbore_diameter < 0.9 * rail.width,
            "the counterbore must be wider than the hole and narrower than 0.9 x the rail width",
        ),
        (
            "rail_counterbore_depth",
            rail.counterbore_depth < 0.9 * rail.height,
            "the counterbore must be shallower than 0.9 x the rail height",
        ),
        (
            "rail_groove_radius",
            0.0 <= rail.groove_radius
            and (rail.groove_radius == 0.0 or rail.width / 2 - rail.groove_radius > rail.counterbore_diameter / 2 + 1e-3),
            "the grooves must leave at least 1 mm of wall beside the counterbore",
        ),
        (
            "rail_lower_groove_z",
            rail.groove_radius < rail.lower_groove_z
            and rail.lower_groove_z + 2 * rail.groove_radius < rail.upper_groove_z
            and rail.upper_groove_z + rail.groove_radius < rail.height,
            "the grooves must lie within the rail's height and apart from each other",
        ),
        ("rail_hole_pitch", rail.hole_pitch > 1.2 * rail.counterbore_diameter, "neighbouring counterbores overlap"),
        (
            "rail_end_distance",
            rail.hole_diameter / 2 < rail.end_distance < rail.hole_pitch,
            "the first hole must lie on the rail, within one pitch of its end",
        ),
    ]


def _plate_checks(plate) -> list[tuple[str, bool, str]]:
    """(field, holds, message) of the joint plate's shaft bore and screw holes."""
    half = 0.5 * (plate.bolt_x[1] - plate.bolt_x[0])  # half the rail's pitch
    r_seat, r_bolt = plate.seat_diameter / 2, plate.bolt_diameter / 2
    return [
        (
            "plate_seat_diameter",
            plate.seat_diameter < 0.9 * plate.width and r_seat + r_bolt < half,
            "the shaft's bore must fit the plate's width and clear the screw holes half a rail pitch either side",
        ),
        (
            "plate_seat_x",
            min(plate.bolt_x) - r_bolt > 0 and max(plate.bolt_x) + r_bolt < plate.length,
            "the shaft's line, with a screw hole half a rail pitch either side, must lie on the plate",
        ),
        (
            "plate_bolt_diameter",
            plate.bolt_diameter < 0.8 * plate.width,
            "the screw holes must fit on the plate",
        ),
    ]


def _iprofile_checks(ipr) -> list[tuple[str, bool, str]]:
    """(field, holds, message) of the I-profile's web, flanges and bolt holes."""
    return [
        (
            "iprofile_web_thickness",
            ipr.web_thickness + 2 * ipr.root_radius < ipr.flange_width,
            "web and fillets must be narrower than the flange",
        ),
        (
            "iprofile_flange_thickness",
            2 * ipr.flange_thickness + 2 * ipr.root_radius < ipr.depth,
            "two flanges and the fillets must fit in the depth",
        ),
        (
            "iprofile_bolt_diameter",
            ipr.bolt_diameter < min(ipr.bolt_pitch_y, ipr.flange_width - ipr.bolt_pitch_y)
            and ipr.bolt_pitch_x + ipr.bolt_diameter < ipr.length,
            "the bolt holes must fit on the top flange",
        ),
    ]


def validate(overrides: dict[str, float]) -> tuple[str, str] | None:
    """(field, message) for overrides that cannot make a valid part, else None: holes
    wider than the section, counterbores not around their hole or deeper than the rail,
    holes that overlap or leave the plate, a web or fillet that does not fit."""
    rail, plate, ipr = with_overrides(overrides)
    checks = _rail_checks(rail) + _plate_checks(plate) + _iprofile_checks(ipr)
    for name, ok, message in checks:
        if not ok:
            return f"geometry.{name}", message
    return None
