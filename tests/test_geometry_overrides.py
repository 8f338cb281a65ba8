"""Every ``[geometry]`` key reaches every model that uses the dimension, and no other
(issue 79: ``rail_hole_pitch = "50 mm"`` left the motor couple split over 60 mm). For each
key the scene is parsed with the dimension changed a little, and each derived model is
compared with the default's: the part geometries the FE meshes, the one mass model the
dynamics and the FE carry, the components' hole and pitch, the sweep's hole grid. Closed
form only (no mesh, no solve)."""

from __future__ import annotations

import numpy as np
import pytest

from railcheck.geometry.catalogue import OVERRIDABLE, with_overrides
from railcheck.parts import geometry_of, mass_model
from railcheck.scene import parse_scene
from railcheck.sweep.grid import rig_grid

MECHANISM = {"kind": "four-bar", "crank": "480 mm", "coupler": "840 mm", "rocker": "780 mm", "ground": "1020 mm"}

#: what each key must move (the others must not): the rail's, plate's or bracket's geometry,
#: the rail's mass per metre, its overhang behind the pivot, the components' holes, the grid
RAIL_SECTION = {"rail_width", "rail_height", "rail_groove_radius", "rail_hole_diameter", "rail_counterbore_diameter"}
MOVES = {
    "rail": {k for k in OVERRIDABLE if k.startswith("rail_")},
    "plate": {k for k in OVERRIDABLE if k.startswith("plate_")} | {"rail_hole_pitch"},
    "bracket": {k for k in OVERRIDABLE if k.startswith("iprofile_")},
    "mass_per_m": RAIL_SECTION | {"rail_counterbore_depth", "rail_hole_pitch"},  # holes per metre, not where
    "overhang": {"rail_end_distance", "rail_hole_pitch"},
    "components": {"rail_hole_diameter", "rail_counterbore_diameter", "rail_hole_pitch"},
    "grid": {"rail_end_distance", "rail_hole_pitch"},
}


def _derived(geometry: dict) -> dict:
    scene = parse_scene({"mechanism": MECHANISM, "geometry": geometry}, "t")
    masses = mass_model("newton-euler", scene.geometry)
    c = scene.components
    return {
        "rail": geometry_of("crank-rail", scene.geometry).params,
        "plate": geometry_of("PF_4b_006", scene.geometry).params,
        "bracket": geometry_of("PF_4b_003_v2", scene.geometry).params,
        "mass_per_m": masses.rail_mass_per_m,
        "overhang": masses.rail_overhang,
        "components": (c.rail_hole, c.rail_counterbore, c.rail_pitch),
        "grid": tuple(tuple(v) for v in rig_grid(scene.geometry)["four-bar"].values()),
    }


def _changed(key: str) -> str:
    """The key's default, a little larger (smaller where larger would not fit), in mm."""
    which, name = OVERRIDABLE[key]
    spec = dict(zip(("rail", "plate", "iprofile"), with_overrides({})))[which]
    value = getattr(spec, name) * 1e3
    return f"{value * (0.95 if key in SMALLER else 1.05):.6g} mm"


#: keys a 5% increase would make impossible (the section's limits)
SMALLER = {"rail_upper_groove_z", "rail_counterbore_diameter", "rail_counterbore_depth", "plate_seat_diameter"}
DEFAULT = _derived({})


@pytest.mark.parametrize("key", sorted(OVERRIDABLE))
def test_each_geometry_key_moves_what_uses_it_and_nothing_else(key):
    moved = _derived({key: _changed(key)})
    for what, users in MOVES.items():
        same = moved[what] == DEFAULT[what]
        assert same == (key not in users), f"{key} {'left' if same else 'moved'} {what}"


def test_the_pitch_reaches_the_components_couple_and_the_upper_plates_screws():
    """The reported case: at a 50 mm pitch the O2 screws' couple is split over 50 mm and
    PF_4b_006's screws sit 25 mm either side of its shaft."""
    scene = parse_scene({"mechanism": MECHANISM, "geometry": {"rail_hole_pitch": "50 mm"}}, "t")
    assert scene.components.rail_pitch == pytest.approx(0.05)
    plate = dict(geometry_of("PF_4b_006", scene.geometry).params)
    assert np.subtract(plate["bolt_x"], plate["seat_x"]) == pytest.approx([-0.025, 0.025])
