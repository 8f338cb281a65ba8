"""Cache keys from the code that produced the entry (railcheck.base.code): the unit-field
store's and the mesh cache's keys carry the hash of the FE and the mesher source, so an
entry written by other code is never read; the shipped meshes (data held to the mesher by
tests/test_shipped_meshes.py) keep theirs."""

from __future__ import annotations

import shutil
import sys

import pytest

from railcheck.base import code
from railcheck.fea import store as unit_store
from railcheck.fea.materials import MATERIALS
from railcheck.fea.store import UnitRequest, UnitStore, is_stored, solve_stored
from railcheck.fea.unitcases import TractionCase
from railcheck.geometry import bar, mesher


@pytest.fixture
def package(tmp_path, monkeypatch):
    """A copy of railcheck.fea's source as the importable package ``copied_fea``."""
    caches = shutil.ignore_patterns("__pycache__")
    shutil.copytree(code.package_root("railcheck.fea"), tmp_path / "copied_fea", ignore=caches)
    monkeypatch.syspath_prepend(str(tmp_path))
    yield tmp_path / "copied_fea"
    sys.modules.pop("copied_fea", None)
    code.code_hash.cache_clear()


def test_the_hash_changes_with_one_byte_of_a_module_or_a_new_module_and_only_then(package):
    first = code.code_hash("copied_fea")
    assert first == code.code_hash("railcheck.fea")  # the same bytes: the same hash, wherever installed
    code.code_hash.cache_clear()
    assert code.code_hash("copied_fea") == first
    target = package / "stress.py"
    target.write_bytes(target.read_bytes().replace(b"von Mises", b"von  Mises", 1))
    code.code_hash.cache_clear()
    edited = code.code_hash("copied_fea")
    assert edited != first
    (package / "extra.py").write_text("X = 1\n")
    code.code_hash.cache_clear()
    assert code.code_hash("copied_fea") not in (first, edited)
    (package / "notes.txt").write_text("not code")  # only modules count
    (package / "extra.py").unlink()
    code.code_hash.cache_clear()
    assert code.code_hash("copied_fea") == edited
    with pytest.raises(ValueError, match="not a package"):
        code.package_sources("railcheck.fea.stress")


def _request():
    mesh = mesher.mesh_part(bar(0.1, 0.02, 0.02), 10e-3, 10e-3, cache=False)
    cases = {"tip_y": TractionCase(("tip",), 1)}
    return UnitRequest(mesh.points, mesh.tets, mesh.groups, MATERIALS["steel"], ["clamp"], cases, 2, "tip", 0.0, mesh.curved)


def test_a_unit_entry_written_by_other_fe_code_is_not_read(tmp_path, monkeypatch):
    monkeypatch.setenv("RAILCHECK_CACHE", str(tmp_path / "cache"))
    store = UnitStore(tmp_path / "cache" / "unit-fields", int(512e6))
    request = _request()
    assert solve_stored(request, store=store)[2] == "solved" and is_stored(request, store)
    monkeypatch.setattr(unit_store, "code_of_entries", lambda: "other code")
    assert not is_stored(request, store)
    assert solve_stored(request, store=store)[2] == "solved"


def test_a_cached_meshs_key_carries_the_mesher_code_and_a_shipped_ones_does_not(monkeypatch):
    part = bar(0.1, 0.02, 0.02)
    cached, shipped = mesher._cache_key(part, 0.01, 0.01), mesher._cache_key(part, 0.01, 0.01, shipped=True)
    monkeypatch.setattr(mesher, "code_hash", lambda *packages: "other code")
    assert mesher._cache_key(part, 0.01, 0.01) != cached
    assert mesher._cache_key(part, 0.01, 0.01, shipped=True) == shipped
