"""The meshes shipped with railcheck (geometry/meshes/, benchmarks/ship_meshes.py): every
registry part at its default sizes has one, it is read before the cache, it is the mesh
railcheck builds for those parameters byte for byte (a forgotten regeneration after a
mesher change fails it), and a damaged one is never used."""

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


def _same_mesh(a, b, tolerance: float) -> None:
    np.testing.assert_array_equal(a.tets, b.tets)
    assert a.groups.keys() == b.groups.keys()
    for g in a.groups:
        np.testing.assert_array_equal(a.groups[g], b.groups[g])
    np.testing.assert_allclose(a.points, b.points, rtol=0, atol=tolerance)
    np.testing.assert_array_equal(a.curved_edges, b.curved_edges)
    np.testing.assert_allclose(a.curved_points, b.curved_points, rtol=0, atol=tolerance)


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
