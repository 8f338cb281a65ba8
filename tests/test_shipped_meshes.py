"""The meshes shipped with railcheck (geometry/meshes/, benchmarks/ship_meshes.py): every
registry part at its default sizes has one, it is read before the cache, it is the mesh
railcheck builds for those parameters, node coordinates bit for bit (a forgotten
regeneration after a mesher change fails it; the numbering aside, which gmsh gives
differently on another machine), and a damaged one is never used."""

import shutil

import numpy as np
import pytest

from railcheck.geometry import mesher
from railcheck.model.jobs import mesh_sizes
from railcheck.parts import PARTS, geometry_of
from railcheck.scene import load_scene


def _default(name):
    part = geometry_of(name, {})
    size, hole = mesh_sizes(load_scene(None).mesh, part.kind)
    return part, size, hole


@pytest.mark.parametrize("name", list(PARTS))
def test_every_registry_part_has_its_shipped_mesh(name):
    part, size, hole = _default(name)
    mesh = mesher.shipped_mesh(part, size, hole)
    assert mesh is not None, f"no shipped mesh for {name}: run benchmarks/ship_meshes.py"
    assert mesh.shipped and mesh.tets.shape[0] > 1000


#: what the curved edges' mid-points may differ by between machines (m)
CURVED_ROUND_OFF = 1e-12


def _node_map(a, b) -> np.ndarray:
    """a's node -> b's node with the same coordinates, bit for bit (each node of a must
    have its one twin in b)."""
    twin = {p.tobytes(): i for i, p in enumerate(b.points)}
    assert len(twin) == len(b.points) == len(a.points)
    mapped = np.array([twin.get(p.tobytes(), -1) for p in a.points])
    assert (mapped >= 0).all(), f"{int((mapped < 0).sum())} nodes differ"
    return mapped


def _rows(cells: np.ndarray) -> np.ndarray:
    """Cells as sorted rows of sorted node ids: the same set whatever the order."""
    rows = np.sort(cells, axis=1)
    return rows[np.lexsort(rows.T[::-1])]


def _signed(points, tets) -> np.ndarray:
    p = points[tets[:, :4]]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])


def _same_mesh(a, b, tolerance: float) -> None:
    """``a`` and ``b`` are one mesh: the same node coordinates (within ``tolerance``, 0 for
    bit for bit), the same tetrahedra with the same orientation, the same surface groups
    and curved edges with their points; the numbering aside (gmsh numbers one mesh
    differently from one machine to another)."""
    if tolerance == 0.0:
        m = _node_map(a, b)
    else:
        np.testing.assert_allclose(a.points, b.points, rtol=0, atol=tolerance)
        m = np.arange(len(a.points))
    np.testing.assert_array_equal(_rows(m[a.tets]), _rows(b.tets))
    signs = set(np.sign(_signed(a.points, a.tets))), set(np.sign(_signed(b.points, b.tets)))
    assert signs[0] == signs[1] and len(signs[0]) == 1  # every tetrahedron oriented alike in both
    assert a.groups.keys() == b.groups.keys()
    for g in a.groups:
        np.testing.assert_array_equal(_rows(m[np.asarray(a.groups[g])]), _rows(np.asarray(b.groups[g])))
    edges_a, edges_b = np.sort(m[a.curved_edges], axis=1), np.sort(b.curved_edges, axis=1)
    order_a, order_b = np.lexsort(edges_a.T[::-1]), np.lexsort(edges_b.T[::-1])
    np.testing.assert_array_equal(edges_a[order_a], edges_b[order_b])
    # the mid-edge points are projected onto the true surfaces in floating point whose last
    # bits differ between CPUs (1.3e-13 m between two machines): 1 pm, against nodes bit for bit
    atol = max(tolerance, CURVED_ROUND_OFF)
    np.testing.assert_allclose(a.curved_points[order_a], b.curved_points[order_b], rtol=0, atol=atol)


def test_a_shipped_plate_is_the_mesh_gmsh_builds_byte_for_byte():
    part, size, hole = _default("PF_4b_006")
    _same_mesh(mesher.shipped_mesh(part, size, hole), mesher.build_mesh(part, size, hole), 0.0)


@pytest.mark.slow  # the 1000 mm rail meshed and untangled afresh, about 10 s
def test_a_shipped_rail_is_the_mesh_railcheck_builds_byte_for_byte():
    part, size, hole = _default("coupler-rail")
    _same_mesh(mesher.shipped_mesh(part, size, hole), mesher.build_mesh(part, size, hole), 0.0)


def test_the_shipped_mesh_is_read_before_the_cache_and_a_damaged_one_is_not_used(tmp_path, monkeypatch):
    part, size, hole = _default("PF_4b_006")
    assert mesher.mesh_part(part, size, hole, cache_dir=tmp_path).shipped  # an empty cache: the shipped one
    assert mesher.cached_mesh(part, size, hole, cache_dir=tmp_path).shipped
    damaged = tmp_path / "shipped"
    damaged.mkdir()
    path = mesher.shipped_entry(part, size, hole)[0]
    shutil.copy(path, damaged / path.name)
    raw = bytearray((damaged / path.name).read_bytes())
    raw[len(raw) // 2] ^= 0xFF
    (damaged / path.name).write_bytes(bytes(raw))
    monkeypatch.setattr(mesher, "SHIPPED_DIR", damaged)
    assert mesher.shipped_mesh(part, size, hole) is None
    assert mesher.cached_mesh(part, size, hole, cache_dir=tmp_path / "empty") is None  # so the part is meshed
