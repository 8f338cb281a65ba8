"""Parametric part descriptions, light (no gmsh import): what to mesh and its named groups.

A :class:`PartGeometry` is a frozen, hashable description: its kind, its dimensions (SI,
from :mod:`railcheck.geometry.catalogue`), and the names of its physical groups. The gmsh model
is built from it in :mod:`railcheck.geometry.mesher`.

Named groups (surfaces):

* every part: "solid" (the volume);
* ``bar``: "clamp" (x = 0 face), "tip" (x = L face);
* ``rail`` (the grooved size-25 profile): "hole_K" for the bearing (through-hole) surface of the K-th mounting hole
  from the pivot end, "shaft_hole" (the hole the rail is held at, hole 0), "end_pivot"
  (x = 0), "end_free" (x = L);
* ``joint_plate`` (PF_4b_006): "bearing_seat", "hole_0", "hole_1", "end_free";
* ``i_profile`` (PF_4b_003_v2): "hole_0" .. "hole_3", "base" (bottom face), "end_free".
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from .catalogue import I_PROFILE, JOINT_PLATE, RAIL, IProfileSpec, JointPlateSpec, RailSection, RailSpec, rail_section


@dataclass(frozen=True)
class PartGeometry:
    kind: str  # bar, rail, joint_plate, i_profile
    params: tuple[tuple[str, object], ...]  # sorted (name, value) pairs, SI
    groups: tuple[str, ...] = field(default=())

    def get(self, name: str):
        return dict(self.params)[name]

    @property
    def section(self) -> RailSection:
        """A rail's cross-section properties (closed form, holes excluded)."""
        if self.kind != "rail":
            raise ValueError(f"{self.kind} has no rail section")
        p = dict(self.params)
        names = ("width", "height", "groove_radius", "lower_groove_z", "upper_groove_z")
        return rail_section(RailSpec(**{k: p[k] for k in names}))  # type: ignore[arg-type]

    @property
    def volume(self) -> float:
        """Approximate solid volume (m^3), for mesh-size estimates."""
        p: dict[str, Any] = dict(self.params)
        if self.kind == "bar":
            return p["length"] * p["width"] * p["height"]
        if self.kind == "rail":
            return p["length"] * (p["width"] * p["height"] - 2 * math.pi * p.get("groove_radius", 0.0) ** 2)
        if self.kind == "joint_plate":
            return p["length"] * p["width"] * p["thickness"] - math.pi / 4 * p["seat_diameter"] ** 2 * p["thickness"]
        if self.kind == "i_profile":
            return p["length"] * (
                2 * p["flange_width"] * p["flange_thickness"] + (p["depth"] - 2 * p["flange_thickness"]) * p["web_thickness"]
            )
        raise ValueError(self.kind)


def _params(**kw) -> tuple[tuple[str, object], ...]:
    return tuple(sorted(kw.items()))


def bar(length: float, width: float, height: float) -> PartGeometry:
    """A straight rectangular bar along x: width along y, height along z (m)."""
    return PartGeometry("bar", _params(length=length, width=width, height=height), ("clamp", "tip"))


def rail(length: float, spec: RailSpec = RAIL, holes: bool = True) -> PartGeometry:
    """A size-25 rail of ``length`` m, with its counterbored mounting holes unless
    ``holes`` is False (the plain profile, for beam-theory checks)."""
    xs = tuple(spec.hole_positions(length)) if holes else ()
    groups = ("end_pivot", "end_free") + (("shaft_hole",) if xs else ()) + tuple(f"hole_{k}" for k in range(len(xs)))
    return PartGeometry(
        "rail",
        _params(
            length=length,
            width=spec.width,
            height=spec.height,
            hole_x=xs,
            hole_diameter=spec.hole_diameter,
            counterbore_diameter=spec.counterbore_diameter,
            counterbore_depth=spec.counterbore_depth,
            groove_radius=spec.groove_radius,
            lower_groove_z=spec.lower_groove_z,
            upper_groove_z=spec.upper_groove_z,
        ),
        groups,
    )


def joint_plate(spec: JointPlateSpec = JOINT_PLATE) -> PartGeometry:
    """PF_4b_006 (assumed dimensions, see the catalogue)."""
    return PartGeometry(
        "joint_plate",
        _params(
            length=spec.length,
            width=spec.width,
            thickness=spec.thickness,
            seat_diameter=spec.seat_diameter,
            seat_x=spec.seat_x,
            bolt_diameter=spec.bolt_diameter,
            bolt_x=tuple(spec.bolt_x),
        ),
        ("bearing_seat", "hole_0", "hole_1", "end_free"),
    )


def i_profile(spec: IProfileSpec = I_PROFILE) -> PartGeometry:
    """PF_4b_003_v2 (assumed dimensions, see the catalogue)."""
    return PartGeometry(
        "i_profile",
        _params(
            length=spec.length,
            flange_width=spec.flange_width,
            depth=spec.depth,
            flange_thickness=spec.flange_thickness,
            web_thickness=spec.web_thickness,
            root_radius=spec.root_radius,
            bolt_diameter=spec.bolt_diameter,
            bolt_pitch_x=spec.bolt_pitch_x,
            bolt_pitch_y=spec.bolt_pitch_y,
        ),
        ("base", "hole_0", "hole_1", "hole_2", "hole_3", "end_free"),
    )
