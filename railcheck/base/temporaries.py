"""Whether a process runs, and the temporary files of the caches (the mesh cache, the unit-field store): each written under
a name that carries its process id beside its entry and renamed onto it, so a reader never
sees half an entry. A write that fails (a full disk) removes its temporary; one whose
process was killed is removed by the next write into that folder."""

from __future__ import annotations

import contextlib
import os
from pathlib import Path

SUFFIX = ".tmp.npz"


def temporary_name(path: Path) -> Path:
    """The temporary name this process writes ``path`` under (hidden, with its id)."""
    return path.with_name(f".{path.stem}.{os.getpid()}{SUFFIX}")


def temporary_parts(name: str) -> tuple[str, int] | None:
    """(the entry's file name, the writer's pid) of a temporary's ``name``
    (:func:`temporary_name`); None for any other name."""
    if not (name.startswith(".") and name.endswith(SUFFIX)):
        return None
    stem, _, pid = name[1 : -len(SUFFIX)].rpartition(".")
    return (f"{stem}.npz", int(pid)) if stem and pid.isdigit() else None


def remove_dead_temporaries(directory: Path) -> list[Path]:
    """Remove the temporaries in ``directory`` whose process no longer runs (a run killed
    while it wrote); the removed paths."""
    removed = []
    for p in Path(directory).glob(f".*{SUFFIX}"):
        parts = temporary_parts(p.name)
        if parts is None:
            continue
        pid = parts[1]
        if pid != os.getpid() and not process_running(pid):
            with contextlib.suppress(OSError):
                p.unlink()
                removed.append(p)
    return removed


def process_running(pid: int) -> bool:
    """Whether a process with this id runs (one of another user's counts as running)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError):
        return True
    return True
