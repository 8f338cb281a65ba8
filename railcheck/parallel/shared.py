"""A sweep context shared by the local Dask workers through one file they map.

The context of a kind (:class:`railcheck.sweep.context.SweepContext`: the parts' screens,
about 1.3 GB of unit stresses for the default four-bar) is pickled once with protocol 5,
its arrays' buffers out of band: the pickle stream (tens of kB) goes to ``PATH.head``,
the buffers to ``PATH``, each at a 64-byte aligned offset. Every worker maps ``PATH``
read-only and unpickles the stream onto the mapped buffers: no copy per worker, the
pages shared through the page cache (scattering the same context from the scheduler took
8 s and one copy per worker). The arrays a worker gets are read-only.

The files live in the run's staging directory (:class:`railcheck.files.Staging`) and are
removed once the kind's chunks are done; a killed run's staging directory, files and all,
is removed by the next run.
"""

from __future__ import annotations

import mmap
import pickle
from pathlib import Path

#: alignment (bytes) of each buffer in the file
ALIGN = 64

_loaded: dict[str, object] = {}  # in a worker: path -> its context, loaded once


def write_shared(obj, path: Path) -> Path:
    """Write ``obj`` to ``path`` (its buffers) and ``path.head`` (the pickle stream, the
    buffers' offsets and sizes); returns ``path``. Raises OSError when the disk refuses
    (the files are removed first)."""
    path = Path(path)
    buffers: list[pickle.PickleBuffer] = []
    stream = pickle.dumps(obj, protocol=5, buffer_callback=buffers.append)
    spans = []
    try:
        with open(path, "wb") as out:
            offset = 0
            for buffer in buffers:
                raw = buffer.raw()
                pad = -offset % ALIGN
                out.write(b"\0" * pad)
                out.write(raw)
                spans.append((offset + pad, raw.nbytes))
                offset += pad + raw.nbytes
        head_path(path).write_bytes(pickle.dumps((stream, spans), protocol=5))
    except OSError:
        remove_shared(path)
        raise
    return path


def read_shared(path: str | Path):
    """The object :func:`write_shared` wrote to ``path``, its arrays read-only views of
    the mapped file."""
    stream, spans = pickle.loads(head_path(Path(path)).read_bytes())
    if not any(size for _, size in spans):
        return pickle.loads(stream, buffers=[b""] * len(spans))
    with open(path, "rb") as f:
        mapped = memoryview(mmap.mmap(f.fileno(), 0, access=mmap.ACCESS_READ))
    return pickle.loads(stream, buffers=[mapped[offset : offset + size] for offset, size in spans])


def shared(path: str):
    """In a worker: the context at ``path``, read once per process."""
    if path not in _loaded:
        _loaded[path] = read_shared(path)
    return _loaded[path]


def head_path(path: Path) -> Path:
    """Where the pickle stream of the shared file ``path`` is written."""
    return path.with_name(path.name + ".head")


def remove_shared(path: Path) -> None:
    """Remove both files of ``path`` (those that exist); a worker's mapping stays valid."""
    for p in (Path(path), head_path(Path(path))):
        p.unlink(missing_ok=True)
