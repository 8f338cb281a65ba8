"""Which files in a cache folder railcheck wrote: an entry of the mesh cache or of the
unit-field store is a regular file (not a link) named by the SHA-256 of the inputs it was
made for, and it holds those inputs as its ``payload`` member, so a file is recognised
as railcheck's by hashing what it says it was made for and comparing that with its own
name. A foreign file, a link, a folder or a copy renamed by hand is not an entry, and
nothing that clears or evicts a cache touches it."""

from __future__ import annotations

import hashlib
import os
import re
import stat
import zipfile
from pathlib import Path

from railcheck.base.temporaries import process_running, temporary_parts

#: a payload is a few kB of text; a larger ``payload`` member is not railcheck's
MAX_PAYLOAD_BYTES = 1 << 20


def is_regular_file(path: Path) -> bool:
    """Whether ``path`` is a regular file itself (a link to one is not)."""
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except OSError:
        return False


def stored_payload(path: Path) -> str | None:
    """The text of the ``payload`` member of the ``.npz`` at ``path`` (None when it is no
    regular file, no zip, has no such member or one too large or not a text array)."""
    if not is_regular_file(path):
        return None
    try:
        import numpy as np
        from numpy.lib import format as npy

        with zipfile.ZipFile(path) as z:
            info = z.getinfo("payload.npy")
            if info.file_size > MAX_PAYLOAD_BYTES:
                return None
            with z.open(info) as f:
                array = npy.read_array(f, allow_pickle=False)
        return str(array) if array.dtype.kind == "U" and np.ndim(array) == 0 else None
    except Exception:  # noqa: BLE001 - anything unreadable is not an entry railcheck wrote
        return None


def is_own_entry(path: Path, pattern: re.Pattern[str]) -> bool:
    """Whether ``path`` is an entry railcheck wrote: its name matches ``pattern``, whose
    group ``key`` is the leading hex digits of the SHA-256 of its ``payload`` member."""
    match = pattern.fullmatch(path.name)
    if match is None:
        return False
    payload = stored_payload(path)
    if payload is None:
        return False
    key = match.group("key")
    return hashlib.sha256(payload.encode()).hexdigest()[: len(key)] == key


def is_dead_own_temporary(path: Path, pattern: re.Pattern[str]) -> bool:
    """Whether ``path`` is the temporary of an entry named by ``pattern`` that a process
    no longer running left (:func:`railcheck.base.temporaries.temporary_name`)."""
    parts = temporary_parts(path.name)
    if parts is None or pattern.fullmatch(parts[0]) is None or not is_regular_file(path):
        return False
    return not process_running(parts[1])


def _live_own_temporary(path: Path, pattern: re.Pattern[str]) -> bool:
    parts = temporary_parts(path.name)
    return parts is not None and pattern.fullmatch(parts[0]) is not None


def clear_entries(directory: Path, pattern: re.Pattern[str], known: frozenset[str] = frozenset()) -> tuple[int, list[str]]:
    """Remove from ``directory`` (not below it, no link in it followed) the entries
    railcheck wrote and the temporaries of dead runs; (entries removed, names of what was
    left: everything else but the ``known`` names). A live run's temporary is left unnamed."""
    removed, left = 0, []
    if not directory.is_dir():
        return 0, []
    for path in sorted(directory.iterdir()):
        if is_own_entry(path, pattern) or is_dead_own_temporary(path, pattern):
            try:
                path.unlink()
            except OSError:
                left.append(path.name)
                continue
            removed += 0 if path.name.startswith(".") else 1
        elif path.name not in known and not _live_own_temporary(path, pattern):
            left.append(path.name)
    return removed, left
