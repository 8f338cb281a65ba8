"""railcheck.loads: joint reactions in a part's axes, factored and split over its bolts.

:mod:`.rotation` (ground frame -> rail axes), :mod:`.cases` (a part's load case at one
instant, the bolt holes a bar length uses), :mod:`.histories` (coefficient histories of
the unit load cases over the cycle), :mod:`.bearings` (the joints' bearing lives).
Imports nothing of railcheck but numpy. Units SI.
"""

from .bearings import BEARING_6205, BallBearing, BearingLife, bearing_life
from .cases import BoltForce, LoadCase, explicit_load_case, peak_in_rail_axes, pivot_x, rail_bolt_holes, reaction_load_case
from .histories import bolt_history, gravity_history, rail_inertia_history
from .rotation import to_rail_axes

__all__ = [
    "BEARING_6205",
    "BallBearing",
    "BearingLife",
    "BoltForce",
    "LoadCase",
    "bearing_life",
    "bolt_history",
    "explicit_load_case",
    "gravity_history",
    "peak_in_rail_axes",
    "pivot_x",
    "rail_bolt_holes",
    "rail_inertia_history",
    "reaction_load_case",
    "to_rail_axes",
]
