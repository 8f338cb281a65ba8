"""A damaged, swapped or stale mesh cache entry is never trusted: it is rebuilt, the
result is the right mesh, and a warning says why."""

import os
import shutil

import numpy as np
import pytest

from railcheck.geometry.mesher import mesh_part
from railcheck.geometry.models import bar


@pytest.fixture
def cache(tmp_path):
    return tmp_path / "cache"


def entries(cache):
    return sorted(p for p in cache.glob("*.npz") if not p.name.startswith("."))


def fresh(size):
    return mesh_part(bar(0.1, 0.02, 0.02), size, size, cache=False)


def test_sound_entry_is_read_back(cache):
    first = mesh_part(bar(0.1, 0.02, 0.02), 8e-3, 8e-3, cache_dir=cache)
    second = mesh_part(bar(0.1, 0.02, 0.02), 8e-3, 8e-3, cache_dir=cache)
    assert not first.cached and second.cached and second.warning is None
    assert np.array_equal(first.points, second.points)


@pytest.mark.parametrize("damage", ["swapped", "truncated", "bit-flipped", "quality-flipped"])
def test_damaged_entry_is_rebuilt_with_a_warning(cache, damage):
    mesh_part(bar(0.1, 0.02, 0.02), 8e-3, 8e-3, cache_dir=cache)
    (entry,) = entries(cache)
    if damage == "swapped":  # another mesh's sound entry under this name
        other = mesh_part(bar(0.1, 0.02, 0.02), 12e-3, 12e-3, cache_dir=cache)
        assert other.cached is False
        (other_entry,) = [p for p in entries(cache) if p != entry]
        shutil.copy(other_entry, entry)
    elif damage == "truncated":
        entry.write_bytes(entry.read_bytes()[: entry.stat().st_size // 2])
    else:  # one bit of the stored coordinates, or of the stored mesh quality, flipped
        import zipfile

        with zipfile.ZipFile(entry) as z:
            members = {n: z.read(n) for n in z.namelist()}
        member = "points.npy" if damage == "bit-flipped" else "min_quality.npy"
        raw = bytearray(members[member])
        raw[-5] ^= 0x01
        members[member] = bytes(raw)
        os.remove(entry)
        with zipfile.ZipFile(entry, "w") as z:
            for n, data in members.items():
                z.writestr(n, data)
    got = mesh_part(bar(0.1, 0.02, 0.02), 8e-3, 8e-3, cache_dir=cache)
    want = fresh(8e-3)
    assert np.array_equal(got.points, want.points) and np.array_equal(got.tets, want.tets)
    assert not got.cached and got.warning and "rebuilt" in got.warning
    again = mesh_part(bar(0.1, 0.02, 0.02), 8e-3, 8e-3, cache_dir=cache)
    assert again.cached and again.warning is None  # the rebuilt entry is sound


@pytest.mark.parametrize("kind", ["fifo", "folder"])
def test_an_entry_that_is_not_a_regular_file_is_rebuilt_without_blocking(cache, kind):
    """A FIFO under an entry's name would block np.load forever: any non-regular file is a
    damaged entry, rebuilt with a warning."""
    mesh_part(bar(0.1, 0.02, 0.02), 8e-3, 8e-3, cache_dir=cache)
    (entry,) = entries(cache)
    entry.unlink()
    if kind == "fifo":
        os.mkfifo(entry)
    else:
        entry.mkdir()
    again = mesh_part(bar(0.1, 0.02, 0.02), 8e-3, 8e-3, cache_dir=cache)
    assert not again.cached and "not a regular file" in again.warning
    assert np.array_equal(again.points, fresh(8e-3).points)


def test_an_entry_gives_back_the_meshers_warning_and_quality(cache):
    """A cached mesh says what the fresh one said (e.g. curved edges straightened): the
    warning and quality record are stored with the arrays and read back under the hash."""
    from dataclasses import replace

    from railcheck.geometry.cache import read_cached, write_cached

    data = replace(fresh(8e-3), warning="3 curved edges straightened to keep elements from folding")
    write_cached(cache / "entry.npz", data, "parameters")
    back, why = read_cached(cache / "entry.npz", "parameters")
    assert why is None and back.cached
    assert (back.warning, back.min_quality, back.slivers) == (data.warning, data.min_quality, data.slivers)
    quiet, _ = read_cached(cache / "entry.npz", "other parameters")
    assert quiet is None


def test_a_caller_that_handles_sigterm_meshes_in_a_child_and_keeps_its_handler():
    """gmsh's initialize resets SIGTERM to the default action, which would kill a run that
    relies on its handler to remove its staging directory (a race CI hit). Such a caller gets
    its mesh from a child process: gmsh never loads here, the mesh equals one built here, and
    a SIGTERM afterwards reaches the caller's handler."""
    import subprocess
    import sys

    script = """
import os, signal, sys, time
import numpy as np
from railcheck.geometry.mesher import build_mesh
from railcheck.geometry.models import bar

class Caught(Exception):
    pass

def handler(signum, frame):
    raise Caught()

here = build_mesh(bar(0.1, 0.02, 0.02), 8e-3, 8e-3)
assert "gmsh" in sys.modules
del sys.modules["gmsh"]
signal.signal(signal.SIGTERM, handler)
child = build_mesh(bar(0.1, 0.02, 0.02), 8e-3, 8e-3)
assert "gmsh" not in sys.modules, "gmsh was loaded by a caller that handles SIGTERM"
assert np.array_equal(child.points, here.points) and np.array_equal(child.tets, here.tets)
try:
    os.kill(os.getpid(), signal.SIGTERM)
    time.sleep(5)
except Caught:
    print("handled")
"""
    proc = subprocess.run([sys.executable, "-P", "-c", script], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "handled"


def test_meshing_here_leaves_sigpipe_ignored_so_a_closed_pipe_is_an_error_not_death():
    """gmsh's initialize sets SIGPIPE back to the default action (death). After meshing in
    this process, Python's disposition (ignored) is back: a write to a pipe whose reader
    has gone (a stopped forked pool's children, ``railcheck ... | head``) raises
    BrokenPipeError instead of killing the process silently with status 141 (a CI run's
    pytest process died so)."""
    import subprocess
    import sys

    script = """
import os
from railcheck.geometry.mesher import build_mesh
from railcheck.geometry.models import bar

def sigpipe_ignored():
    for line in open("/proc/self/status"):
        if line.startswith("SigIgn:"):
            return bool(int(line.split()[1], 16) >> 12 & 1)

assert sigpipe_ignored()
build_mesh(bar(0.1, 0.02, 0.02), 8e-3, 8e-3)
import sys
assert "gmsh" in sys.modules, "meshed in a child, not here"
print("ignored" if sigpipe_ignored() else "default")
read, write = os.pipe()
os.close(read)
try:
    os.write(write, b"x")
except BrokenPipeError:
    print("error")
"""
    proc = subprocess.run([sys.executable, "-P", "-c", script], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, f"status {proc.returncode}: {proc.stderr}"
    assert proc.stdout.split() == ["ignored", "error"]


def test_a_full_disk_leaves_no_temporary_and_a_killed_writers_is_removed(cache, monkeypatch):
    """A mesh-cache write that fills the disk half way (np.savez writes, then ENOSPC) leaves
    no temporary (it kept every run's ``.rail-*.tmp.npz``); the mesh is still returned,
    its warning saying it is not cached and why (a check's warning: the next run meshes
    it again). A
    temporary of a process that no longer runs (a run killed while writing) is removed by
    the next write into the folder; a live process's is kept."""
    import errno
    import subprocess
    import sys

    real_savez = np.savez

    def half_then_full(file, *args, **kwargs):
        with open(file, "wb") as f:
            f.write(b"PK half an entry")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(np, "savez", half_then_full)
    got = mesh_part(bar(0.1, 0.02, 0.02), 8e-3, 8e-3, cache_dir=cache)
    assert got.points.size and not list(cache.glob("*"))  # nothing stored, nothing half-written
    assert got.warning == "mesh not cached (No space left on device): the next run meshes it again"
    monkeypatch.setattr(np, "savez", real_savez)
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    killed = cache / f".bar-abc.{int(dead.stdout)}.tmp.npz"
    alive = cache / f".bar-def.{os.getppid()}.tmp.npz"
    killed.write_bytes(b"PK half")
    alive.write_bytes(b"PK half")
    mesh_part(bar(0.1, 0.02, 0.02), 8e-3, 8e-3, cache_dir=cache)
    assert not killed.exists() and alive.exists() and len(entries(cache)) == 1


def test_a_meshers_warning_is_kept_beside_the_cache_s_own(cache, monkeypatch):
    """A fresh mesh's own warning (curved edges straightened) stays when the cache adds
    its note (it cannot keep the entry): both, the mesher's first (the run's assumptions
    read it there)."""
    import errno
    from dataclasses import replace

    import railcheck.geometry.mesher as mesher

    real = mesher.build_mesh
    monkeypatch.setattr(mesher, "build_mesh", lambda *a, **k: replace(real(*a, **k), warning="3 curved edges straightened"))

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(np, "savez", full)
    got = mesh_part(bar(0.1, 0.02, 0.02), 8e-3, 8e-3, cache_dir=cache)
    assert got.warning == (
        "3 curved edges straightened; mesh not cached (No space left on device): the next run meshes it again"
    )
