"""railcheck.geometry: the parts' catalogue dimensions, solid models and cached gmsh meshes.

:mod:`.catalogue` (dimensions, overridable per scene), :mod:`.models` (a part's geometry
as plain parameters and named groups), :mod:`.shapes` (the gmsh solid models),
:mod:`.mesher` (the gmsh session: meshing, extraction, numbering), :mod:`.cache` (the
on-disk mesh cache), :mod:`.meshdata` (the mesh as numpy arrays), :mod:`.curving` (the
curved edges of quadratic meshes). gmsh is imported inside the mesher's functions only.
Units m.
"""

from .catalogue import (
    CATALOGUE_RAIL_MASS,
    RailSection,
    RailSpec,
    rail_mass_per_metre,
    rail_mass_per_metre_with_holes,
    rail_section,
    with_overrides,
)
from .meshdata import MeshData
from .mesher import estimate_elements, local_numbering, mesh_part
from .models import PartGeometry, bar, i_profile, joint_plate, rail

__all__ = [
    "CATALOGUE_RAIL_MASS",
    "RailSection",
    "rail_section",
    "MeshData",
    "PartGeometry",
    "RailSpec",
    "bar",
    "estimate_elements",
    "i_profile",
    "joint_plate",
    "local_numbering",
    "mesh_part",
    "rail",
    "rail_mass_per_metre",
    "rail_mass_per_metre_with_holes",
    "with_overrides",
]
