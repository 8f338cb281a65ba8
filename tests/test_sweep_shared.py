"""The sweep context shared by the local workers through one mapped file
(:mod:`railcheck.parallel.shared`): what is read back equals what was written, its arrays
read-only views of the file at aligned offsets, and a refused write leaves nothing."""

from __future__ import annotations

import dataclasses
import pickle

import numpy as np
import pytest

from railcheck.parallel.shared import ALIGN, head_path, read_shared, remove_shared, shared, write_shared


@dataclasses.dataclass(frozen=True)
class Holder:
    name: str
    arrays: dict
    nested: tuple


def _example():
    rng = np.random.default_rng(3)
    return Holder(
        "crank-rail",
        {
            "c": rng.normal(size=(6, 50, 7)),
            "fortran": np.asfortranarray(rng.normal(size=(9, 4))),
            "strided": rng.normal(size=(10, 10))[::2, ::3],
            "empty": np.zeros((0, 3)),
            "ints": np.arange(13, dtype=np.int32),
            "bools": rng.random(17) > 0.5,
        },
        (1.5, None, "x", rng.normal(size=5).astype(np.float32)),
    )


def test_what_is_read_back_equals_what_was_written_and_is_read_only(tmp_path):
    obj = _example()
    path = write_shared(obj, tmp_path / "ctx.bin")
    back = read_shared(path)
    assert back.name == obj.name and back.nested[:3] == obj.nested[:3]
    np.testing.assert_array_equal(back.nested[3], obj.nested[3])
    assert back.nested[3].dtype == np.float32
    for key, a in obj.arrays.items():
        b = back.arrays[key]
        assert b.dtype == a.dtype and b.shape == a.shape, key
        np.testing.assert_array_equal(b, a)
    mapped = [back.arrays[k] for k in ("c", "fortran", "ints", "bools")]
    assert back.arrays["fortran"].flags.f_contiguous
    for b in mapped:
        assert not b.flags.writeable
        with pytest.raises(ValueError):
            b[(0,) * b.ndim] = 1
    _, spans = pickle.loads(head_path(path).read_bytes())
    assert spans and all(offset % ALIGN == 0 for offset, _ in spans)
    assert path.stat().st_size == max(offset + size for offset, size in spans)


def test_a_worker_reads_a_shared_file_once_and_keeps_it_after_removal(tmp_path):
    path = str(write_shared(_example(), tmp_path / "once.bin"))
    first = shared(path)
    remove_shared(tmp_path / "once.bin")
    assert not list(tmp_path.iterdir())
    again = shared(path)  # the mapping outlives the files
    assert again is first
    np.testing.assert_array_equal(again.arrays["c"], _example().arrays["c"])


def test_an_object_without_arrays_round_trips(tmp_path):
    obj = {"kind": "four-bar", "speeds": (6.283185307179586,), "empty": np.zeros(0)}
    back = read_shared(write_shared(obj, tmp_path / "plain.bin"))
    assert back["kind"] == "four-bar" and back["speeds"] == obj["speeds"] and back["empty"].size == 0


def test_a_refused_write_leaves_no_file(tmp_path, monkeypatch):
    from pathlib import Path

    def full_disk(self, data):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Path, "write_bytes", full_disk)
    with pytest.raises(OSError):
        write_shared(_example(), tmp_path / "ctx.bin")
    assert not list(tmp_path.iterdir())
