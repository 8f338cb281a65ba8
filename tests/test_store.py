"""The unit-field store (railcheck.fea.store): a stored entry gives back the solved fields
bit for bit; a truncated, bit-flipped or swapped entry is detected and solved again; two
processes filling one entry both get correct fields; the size cap evicts the least
recently used entry; `railcheck cache` shows and clears it; and a warm `railcheck check`
equals a cold one byte for byte."""

import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from railcheck.environment import unit_store
from railcheck.fea.materials import MATERIALS
from railcheck.fea.store import UnitRequest, UnitStore, is_stored, read_entry, solve_stored, store_info
from railcheck.fea.unitcases import TractionCase
from railcheck.geometry import bar, mesh_part


@pytest.fixture
def store(tmp_path, monkeypatch):
    """A store in this test's folder, the one the environment names too (RAILCHECK_CACHE,
    for `railcheck cache` and the subprocesses)."""
    monkeypatch.setenv("RAILCHECK_CACHE", str(tmp_path / "cache"))
    return UnitStore(tmp_path / "cache" / "unit-fields", int(2048e6))


def _request(length=0.1, force_dir=1):
    mesh = mesh_part(bar(length, 0.02, 0.02), 10e-3, 10e-3, cache=False)
    cases = {"tip_x": TractionCase(("tip",), 0), "tip_y": TractionCase(("tip",), force_dir)}
    return UnitRequest(mesh.points, mesh.tets, mesh.groups, MATERIALS["steel"], ["clamp"], cases, 2, "tip", 0.0, mesh.curved)


def _same(a, b):
    for name in ("stress", "tip", "displacement", "nodes", "verdict_mask", "cells", "support", "loaded"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert a.names == b.names


def test_a_stored_entry_gives_back_the_solved_fields_bit_for_bit(store):
    request = _request()
    assert not is_stored(request, store)
    fields, solve, origin = solve_stored(request, store=store)
    assert origin == "solved" and is_stored(request, store)
    again, solve2, origin2 = solve_stored(request, store=store)
    assert origin2 == "stored" and set(solve2.seconds) == {"store"}
    _same(fields, again)
    np.testing.assert_array_equal(solve.resultants, solve2.resultants)
    assert (solve.dofs, solve.elements, solve.solver) == (solve2.dofs, solve2.elements, solve2.solver)
    other, _, origin3 = solve_stored(_request(force_dir=2), store=store)  # another case: another entry
    assert origin3 == "solved" and store_info(store).entries == 2
    assert not np.array_equal(other.stress, fields.stress)


def test_inside_reads_shared_an_entry_is_read_once_and_outside_each_time(store, monkeypatch):
    """A check's rails of one size read one hole basis (:func:`fea.store.reads_shared`):
    inside the block the second read of a sound entry is the first's fields, not a second
    read of the file; a damaged entry is not kept (solved again and rewritten, then read
    and kept); after the block every read reads the file again."""
    import railcheck.fea.store as fea_store

    request, other = _request(), _request(force_dir=2)
    fields, _, _ = solve_stored(request, store=store)
    solve_stored(other, store=store)
    other.path(store).write_bytes(b"damaged")
    reads = []
    real = fea_store.read_entry
    monkeypatch.setattr(fea_store, "read_entry", lambda path, payload: reads.append(path) or real(path, payload))
    with fea_store.reads_shared():
        first, _, origin = solve_stored(request, store=store)
        second, _, origin2 = solve_stored(request, store=store)
        assert (origin, origin2) == ("stored", "stored") and second is first and len(reads) == 1
        _same(first, fields)
        assert solve_stored(other, store=store)[2].endswith("solved again") and len(reads) == 2
        kept, _, origin3 = solve_stored(other, store=store)
        assert origin3 == "stored" and len(reads) == 3
        assert solve_stored(other, store=store)[0] is kept and len(reads) == 3
    again, _, _ = solve_stored(request, store=store)
    assert again is not first and len(reads) == 4
    _same(again, fields)


def test_a_member_whose_header_claims_a_huge_array_is_refused_before_it_is_allocated(tmp_path):
    """A damaged or hostile entry whose .npy header claims 10^12 values (8 TB) in a
    member of 8 bytes: :func:`fea.store.read_members` compares the claim with the member's
    size first and refuses it (ValueError naming the size), allocating nothing."""
    import io
    import zipfile

    from numpy.lib import format as npy

    from railcheck.fea.store import read_members

    member = io.BytesIO()
    npy.write_array_header_1_0(member, {"descr": "<f8", "fortran_order": False, "shape": (10**12,)})
    member.write(np.zeros(1).tobytes())
    path = tmp_path / "hostile.npz"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_STORED) as z:
        z.writestr("stress.npy", member.getvalue())
    with pytest.raises(ValueError, match="its size is not its header's"):
        read_members(path)


@pytest.mark.parametrize("damage", ["truncate", "flip", "swap"])
def test_a_damaged_entry_is_detected_and_solved_again(store, damage):
    request = _request()
    fields, _, _ = solve_stored(request, store=store)
    path = request.path(store)
    data = bytearray(path.read_bytes())
    if damage == "truncate":
        path.write_bytes(bytes(data[: len(data) // 2]))
    elif damage == "flip":  # one bit deep inside the stress array
        data[len(data) // 3] ^= 0x04
        path.write_bytes(bytes(data))
    else:  # another request's entry under this name
        other = _request(force_dir=2)
        solve_stored(other, store=store)
        os.replace(other.path(store), path)
    again, _, origin = solve_stored(request, store=store)
    assert origin.startswith("stored unit fields") and origin.endswith("solved again"), origin
    _same(fields, again)
    assert solve_stored(request, store=store)[2] == "stored"  # rewritten whole


def test_no_single_bit_flip_anywhere_in_an_entry_gives_other_fields(store):
    """A bit flipped at any of ~250 places (array bytes, npy headers, zip headers and the
    central directory at the end) is either reported as damage or leaves the fields
    exactly as stored; it never raises and never gives other numbers."""
    request = _request()
    fields, _, _ = solve_stored(request, store=store)
    path, payload = request.path(store), request.payload()
    original = path.read_bytes()
    n = len(original)
    places = sorted({*range(0, n, max(1, n // 160)), *range(max(0, n - 2000), n, 23), n - 1})
    detected = 0
    for at in places:
        data = bytearray(original)
        data[at] ^= 1 << (at % 8)
        path.write_bytes(bytes(data))
        found, why = read_entry(path, payload)
        if found is None:
            assert why, at
            detected += 1
        else:
            _same(fields, found[0])
    path.write_bytes(original)
    assert detected > 0.9 * len(places), (detected, len(places))


@pytest.mark.slow
def test_two_processes_filling_one_entry_both_get_correct_fields(store, tmp_path):
    script = textwrap.dedent(
        """
        import sys, numpy as np
        sys.path.insert(0, %r)
        from test_store import _request
        from railcheck.environment import unit_store
        from railcheck.fea.store import solve_stored
        fields, _, origin = solve_stored(_request(), store=unit_store())
        np.save(sys.argv[1], fields.stress)
        """
        % os.path.dirname(__file__)
    )
    env = {**os.environ, "RAILCHECK_CACHE": str(store.directory.parent)}
    procs = [subprocess.Popen([sys.executable, "-P", "-c", script, str(tmp_path / f"s{i}.npy")], env=env) for i in range(2)]
    assert [p.wait(timeout=300) for p in procs] == [0, 0]
    reference, _, origin = solve_stored(_request(), store=store)
    assert origin == "stored"  # whichever rename won, the entry is whole
    for i in range(2):
        np.testing.assert_array_equal(np.load(tmp_path / f"s{i}.npy"), reference.stress)
    # no temporary left (the store's key, made by the first write, is no temporary)
    assert not [p for p in store.directory.iterdir() if p.name.startswith(".") and p.name != ".key"]


def test_the_size_cap_evicts_the_least_recently_used_entry(store):
    first, second = _request(), _request(force_dir=2)
    solve_stored(first, store=store)
    size = first.path(store).stat().st_size
    os.utime(first.path(store), (1, 1))  # long unused
    solve_stored(second, store=UnitStore(store.directory, int(1.5 * size)))
    assert is_stored(second, store) and not is_stored(first, store)


def test_a_store_that_cannot_be_written_only_costs_time_and_says_so(store, monkeypatch):
    """A full disk (every write raises ENOSPC): the fields are solved and returned, nothing
    half-written is left, the origin says the store could not keep them and why (a
    check's warning, a sweep's progress line: every later run solves them again), and
    the next run solves again."""
    import errno

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(np, "savez", full)
    request = _request()
    fields, _, origin = solve_stored(request, store=store)
    assert origin == "unit fields not stored (No space left on device): the next run solves them again"
    assert fields.stress.size
    assert not store.directory.exists() or not list(store.directory.iterdir())
    assert solve_stored(request, store=store)[2] == origin  # solved again, said again


def test_a_store_under_a_file_only_costs_time(tmp_path, monkeypatch):
    """RAILCHECK_CACHE below a regular file (no folder can be made there): the mesh and
    the fields are made and returned, nothing is written anywhere, and the origin says
    the fields are not stored."""
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("RAILCHECK_CACHE", str(blocker / "cache"))
    fields, _, origin = solve_stored(_request(), store=unit_store())
    assert origin.startswith("unit fields not stored (") and fields.stress.size, origin
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a-file"] and blocker.read_text() == "not a folder"


def test_railcheck_cache_shows_and_clears(store, capsys):
    from railcheck.cli import main

    solve_stored(_request(), store=store)
    assert main(["cache"]) == 0
    assert "unit-field store: 1 entries" in capsys.readouterr().out
    assert main(["cache", "--clear"]) == 0
    assert "1 unit-field entries" in capsys.readouterr().out
    assert store_info(store).entries == 0


@pytest.mark.parametrize("cap", ["abc", "-5", "nan", "inf", "1e309", "2e60"])
def test_a_bad_store_cap_is_one_line_naming_the_variable_before_any_work(store, capsys, monkeypatch, cap, tmp_path):
    from railcheck.cli import main

    monkeypatch.setenv("RAILCHECK_STORE_MB", cap)
    assert main(["kinematics", "--plots", str(tmp_path / "plots")]) == 2
    err = capsys.readouterr().err
    assert err == f"railcheck: error: RAILCHECK_STORE_MB: must be a size in megabytes, 0 or more, got {cap!r}\n"
    assert not (tmp_path / "plots").exists() and not store.directory.parent.exists()


@pytest.mark.parametrize("cap, expected", [("", 2048e6), (" 1.5 ", 1.5e6), ("0", 0)])
def test_the_store_cap_reads_megabytes_and_an_empty_variable_is_the_default(monkeypatch, cap, expected):
    from railcheck.environment import store_cap_bytes

    monkeypatch.setenv("RAILCHECK_STORE_MB", cap)
    assert store_cap_bytes() == expected


def test_an_empty_cache_variable_is_the_default_folder(monkeypatch, tmp_path):
    """RAILCHECK_CACHE="" is unset (not the current folder), for the meshes and the store alike."""
    from railcheck.environment import cache_dir

    monkeypatch.setenv("HOME", str(tmp_path))
    monkeypatch.setenv("RAILCHECK_CACHE", "")
    assert cache_dir() == tmp_path / ".cache" / "railcheck"
    assert unit_store().directory == cache_dir() / "unit-fields"
    monkeypatch.setenv("RAILCHECK_STORE", "0")
    assert unit_store() is None  # bypassed


@pytest.mark.slow
def test_a_warm_check_equals_a_cold_one_byte_for_byte(tmp_path):
    """The crank rail at 20 mm: a cold check fills the store, a warm one reads it (no
    assembly, no solve) and writes the same summary.json; with RAILCHECK_STORE=0 the
    store is bypassed and the summary is the same again."""
    from helpers import FINAL_DESIGN

    scene = tmp_path / "s.toml"
    scene.write_text(
        FINAL_DESIGN + 'speed = "1 Hz"\nsteps = 720\n[check]\nparts = ["crank-rail", "PF_4b_006"]\ncompare = ["2013"]\n'
        '[mesh]\nsize = "20 mm"\nhole_size = "6 mm"\n[output]\nvtk = false\npng = false\nplots = false\n'
    )
    env = {**os.environ, "RAILCHECK_CACHE": str(tmp_path / "cache")}
    runs = {}
    for label, extra in (("cold", {}), ("warm", {}), ("bypass", {"RAILCHECK_STORE": "0"})):
        proc = subprocess.run(
            [sys.executable, "-P", "-m", "railcheck.cli", "check", str(scene), "--out", str(tmp_path / label)],
            capture_output=True,
            text=True,
            env={**env, **extra},
        )
        assert proc.returncode == 0, proc.stderr
        runs[label] = ((tmp_path / label / "summary.json").read_bytes(), proc.stderr)
    assert runs["warm"][0] == runs["cold"][0] == runs["bypass"][0]
    assert "from the store" in runs["warm"][1] and "from the store" not in runs["cold"][1]
    assert "from the store" not in runs["bypass"][1]
    # every entry damaged (the parts' and their 2013 clamped models'): each is solved again
    # and said so, and the numbers are the warm run's
    for entry in (tmp_path / "cache" / "unit-fields").glob("*.npz"):
        data = bytearray(entry.read_bytes())
        data[len(data) // 2] ^= 0x10
        entry.write_bytes(bytes(data))
    proc = subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "check", str(scene), "--out", str(tmp_path / "damaged")],
        capture_output=True,
        text=True,
        env=env,
    )
    assert proc.returncode == 0, proc.stderr
    damaged, warm = (json.loads((tmp_path / run / "summary.json").read_text()) for run in ("damaged", "warm"))
    said = [w for w in damaged.pop("warnings") if "solved again" in w]
    assert any(w.startswith("crank-rail: stored unit fields") for w in said), said
    assert any(w.startswith("crank-rail: 2013 clamped model: stored unit fields") for w in said), said
    warm.pop("warnings")
    assert damaged == warm


def test_railcheck_cache_survives_any_entry(store, capsys):
    """Issue 61: a dangling link in the store made `railcheck cache` fail. A dangling link,
    a folder named like an entry and a temporary file are not entries: shown and cleared
    without an error."""
    from railcheck.cli import main

    solve_stored(_request(), store=store)
    (store.directory / "0000dangling.npz").symlink_to(store.directory / "gone.npz")
    (store.directory / "folder.npz").mkdir()
    (store.directory.parent / "1111dangling.npz").symlink_to(store.directory / "gone.npz")
    assert main(["cache", "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown["unit_field_store"]["entries"] == 1 and shown["unit_field_store"]["bytes"] > 0
    assert main(["cache", "--clear"]) == 0
    assert store_info(store).entries == 0


def test_railcheck_cache_clear_removes_only_what_railcheck_wrote(store, capsys, tmp_path):
    """Issue 79: `cache --clear` deleted every *.npz in RAILCHECK_CACHE and its
    unit-fields/, railcheck's or not. Now an entry is railcheck's when its name is the
    SHA-256 of the payload it holds: foreign files, an entry copied under another name,
    links (to a file outside or to an entry), folders and a linked store folder are left
    and named; the mesh and the field entries railcheck wrote go."""
    from railcheck.cli import main
    from railcheck.geometry.cache import write_cached

    solve_stored(_request(), store=store)
    entry = next(store.directory.glob("*.npz"))
    cache = store.directory.parent
    mesh = mesh_part(bar(0.1, 0.02, 0.02), 10e-3, 10e-3, cache=False)
    payload = '{"a mesh": 1}'
    import hashlib

    key = hashlib.sha256(payload.encode()).hexdigest()[:24]
    assert write_cached(cache / f"bar-{key}.npz", mesh, payload) is None
    outside = tmp_path / "outside.npz"
    np.savez(outside, payload=np.array("mine"))
    np.savez(cache / "work.npz", payload=np.array("a user's array"))
    np.savez(store.directory / "results.npz", x=np.zeros(3))
    (store.directory / ("f" * 40 + ".npz")).write_bytes(entry.read_bytes())  # an entry under another name
    (cache / "link.npz").symlink_to(outside)
    (store.directory / ("e" * 40 + ".npz")).symlink_to(entry)
    (cache / "folder.npz").mkdir()
    (cache / "folder.npz" / "inside.npz").write_bytes(b"x")
    foreign = sorted(["work.npz", "link.npz", "folder.npz", "unit-fields/results.npz", f"unit-fields/{'f' * 40}.npz"])
    foreign = sorted(foreign + [f"unit-fields/{'e' * 40}.npz"])
    assert main(["cache", "--clear"]) == 0
    out = capsys.readouterr().out
    assert "removed 1 mesh entries and 1 unit-field entries" in out, out
    assert f"left {len(foreign)} files railcheck did not write: " in out
    for name in foreign:
        assert (cache / name).exists() or (cache / name).is_symlink(), name
        assert name in out
    assert not entry.exists() and not (cache / f"bar-{key}.npz").exists()
    assert outside.exists() and (cache / "folder.npz" / "inside.npz").exists()


def test_a_linked_store_folder_is_not_followed_by_clear_and_eviction_keeps_foreign_files(store, capsys, tmp_path):
    from railcheck.cli import main
    from railcheck.fea.store import evict

    solve_stored(_request(), store=store)
    foreign = store.directory / ("0" * 40 + ".npz")
    np.savez(foreign, payload=np.array("not the payload of its name"))
    evict(store.directory, 0)  # a cap of 0 bytes evicts every entry railcheck wrote
    assert foreign.exists() and len(list(store.directory.glob("*.npz"))) == 1
    elsewhere = tmp_path / "elsewhere"
    store.directory.rename(elsewhere)
    solve_stored(_request(), store=UnitStore(elsewhere, int(1e9)))
    store.directory.symlink_to(elsewhere)
    assert main(["cache", "--clear"]) == 0
    out = capsys.readouterr().out
    assert "0 unit-field entries" in out and "unit-fields (a link: not followed)" in out, out
    assert len(list(elsewhere.glob("*.npz"))) == 2


@pytest.mark.parametrize("attack", ["scaled", "scaled, its seal kept", "truncated", "another store's", "key gone"])
def test_a_rewritten_entry_is_not_trusted_and_is_solved_again_with_a_warning(store, tmp_path, attack):
    """Issue 79: an entry re-saved with its stress x1.01 (np.savez makes fresh CRC-32s)
    was read as sound. Each entry is sealed by an HMAC under the store's own key over its
    members' directory records; a rewritten, scaled, truncated entry, one copied from
    another store or read without the key is solved again, said, and the right fields
    come back."""
    from railcheck.fea.store import read_members

    request = _request()
    fields, _, _ = solve_stored(request, store=store)
    path, payload = request.path(store), request.payload()
    arrays = read_members(path)
    if attack.startswith("scaled"):
        arrays["stress"] = arrays["stress"] * 1.01
        if attack == "scaled":
            arrays.pop("seal")
        np.savez(path, **arrays)
    elif attack == "truncated":
        path.write_bytes(path.read_bytes()[:-500])
    elif attack == "another store's":
        other = UnitStore(tmp_path / "other", int(1e9))
        solve_stored(request, store=other)
        path.write_bytes(request.path(other).read_bytes())
    else:
        (store.directory / ".key").unlink()
    found, why = read_entry(path, payload)
    assert found is None and why, why
    again, _, origin = solve_stored(request, store=store)
    assert origin.startswith("stored unit fields ") and origin.endswith(": solved again"), origin
    _same(fields, again)
    assert read_entry(path, payload)[0] is not None  # the entry written again is sound
