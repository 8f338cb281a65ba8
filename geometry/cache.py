"""The on-disk mesh cache: one ``.npz`` entry per part and mesh parameters, stored with
the parameters it was made for and a SHA-256 of its arrays; read back only when both
match, written atomically (a per-process temporary name, then a rename), so concurrent
runs never read half a file and a damaged entry is rebuilt. The directory is
``$RAILCHECK_CACHE`` (default ``~/.cache/railcheck``)."""

from __future__ import annotations

import contextlib
import hashlib
import os
import re
import stat
from pathlib import Path

import numpy as np

from railcheck.base.temporaries import remove_dead_temporaries, temporary_name

from .meshdata import MeshData

__all__ = ["ENTRY_NAME", "default_cache_dir", "read_cached", "write_cached"]

#: a mesh entry's file name: the part kind, then the SHA-256 of its payload's first 24 digits
ENTRY_NAME = re.compile(r"(?P<kind>[a-z_]+)-(?P<key>[0-9a-f]{24})\.npz")


def default_cache_dir() -> Path:
    """The mesh cache's folder when the caller names none: ~/.cache/railcheck (the
    application passes ``RAILCHECK_CACHE``'s, :mod:`railcheck.environment`)."""
    return Path.home() / ".cache" / "railcheck"


def _digest(
    points: np.ndarray,
    tets: np.ndarray,
    groups: dict[str, np.ndarray],
    curved: tuple[np.ndarray, np.ndarray],
    quality: tuple[float, int, str],
) -> str:
    """SHA-256 of everything an entry gives back: the mesh arrays' bytes, the group names,
    and the quality record (smallest minSICN, sliver count, the mesher's warning), so a
    flipped quality figure is damage like a flipped coordinate."""
    h = hashlib.sha256()
    for a in (points, tets, *curved):
        h.update(np.ascontiguousarray(a).tobytes())
    for name in sorted(groups):
        h.update(name.encode())
        h.update(np.ascontiguousarray(groups[name]).tobytes())
    h.update(repr((float(quality[0]), int(quality[1]), str(quality[2]))).encode())
    return h.hexdigest()


def read_cached(path: Path, payload: str) -> tuple[MeshData | None, str | None]:
    """(mesh, None) for a sound cache entry of these parameters; (None, why) for a missing,
    damaged, swapped or stale one."""
    if not path.exists():
        return None, None
    try:
        regular = stat.S_ISREG(os.stat(path).st_mode)
    except OSError as exc:
        return None, f"unreadable ({type(exc).__name__})"
    if not regular:  # a FIFO would block np.load forever; a device or a folder is no entry
        return None, "not a regular file"
    try:
        with np.load(path, allow_pickle=False) as z:
            stored_payload, stored_digest = str(z["payload"]), str(z["digest"])
            points, tets = z["points"], z["tets"]
            groups = {k[2:]: z[k] for k in z.files if k.startswith("g_")}
            quality, slivers, warning = float(z["min_quality"]), int(z["slivers"]), str(z["warning"])
            curved = (z["curved_edges"], z["curved_points"])
    except Exception as exc:  # noqa: BLE001 - any unreadable file is a damaged entry
        return None, f"unreadable ({type(exc).__name__})"
    if stored_payload != payload:
        return None, "made for other parameters"
    if stored_digest != _digest(points, tets, groups, curved, (quality, slivers, warning)):
        return None, "content does not match its hash"
    return MeshData(
        points,
        tets,
        groups,
        quality,
        slivers,
        0.0,
        cached=True,
        warning=warning or None,
        curved_edges=curved[0],
        curved_points=curved[1],
    ), None


def write_cached(path: Path, data: MeshData, payload: str, compressed: bool = False) -> str | None:
    """Write a cache entry atomically (a per-process temporary name, then a rename), so
    concurrent runs never read half a file. None when written, else why not (the
    system's words): an unwritable cache only costs time, and the caller says so.
    ``compressed``: zip-deflated (the shipped meshes: smaller, a little slower to read)."""
    tmp = temporary_name(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        remove_dead_temporaries(path.parent)
        (np.savez_compressed if compressed else np.savez)(
            tmp,
            points=data.points,
            tets=data.tets,
            min_quality=data.min_quality,
            slivers=data.slivers,
            curved_edges=data.curved_edges,
            curved_points=data.curved_points,
            warning=np.array(data.warning or ""),
            payload=np.array(payload),
            digest=np.array(
                _digest(
                    data.points, data.tets, data.groups, data.curved, (data.min_quality, data.slivers, data.warning or "")
                )
            ),
            **{f"g_{k}": v for k, v in data.groups.items()},  # type: ignore[arg-type]  # numpy stubs: **kwds as allow_pickle
        )
        os.replace(tmp, path)
    except OSError as exc:  # a full disk, a read-only cache: nothing half-written is left
        with contextlib.suppress(OSError):
            tmp.unlink(missing_ok=True)
        return exc.strerror or type(exc).__name__
    return None
