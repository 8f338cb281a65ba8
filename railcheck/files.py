"""Everything railcheck writes goes through here: atomic files, results directories, staging.

* :func:`atomic_path` / :func:`atomic_write_text`: a file is written under a temporary
  name beside its target and renamed into place, so a reader never sees half a file; the
  file gets the user's umask (not mkstemp's 0600).
* :func:`reserve_results_dir`: a run claims its results directory atomically (``mkdir``
  succeeds for one process only), so two runs never share one: the second gets ``DIR-2``.
  The reservation holds a mark naming its process (its id and start time, so a process
  id the system has given to another process since does not count as the run's); a
  reservation whose process is gone (a run killed with SIGKILL) is reclaimed by the next run.
  ``force`` replaces an existing directory, but only when the run has succeeded.
* :class:`Staging`: the run writes into a hidden staging directory beside the target,
  named with its process id; :meth:`Staging.commit` renames it onto the reserved target,
  :meth:`Staging.abandon` removes it. A later run removes staging directories whose
  process is gone (a killed run leaves nothing behind for long).
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import shutil
import tempfile
from pathlib import Path
from typing import Any, Iterator

from railcheck.base.errors import InputError
from railcheck.base.temporaries import process_running

STAGING_MARK = ".staging."
RESERVED_MARK = ".railcheck-reserved-by."


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_path(target: str | Path) -> Iterator[Path]:
    """Yield a temporary path in the target's directory; rename it onto ``target`` when
    the block succeeds, remove it when it fails. The suffix is kept (writers that choose
    a format by extension still work)."""
    target = Path(target)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=target.suffix, dir=target.parent)
    except OSError as exc:
        raise _naming(exc, target) from exc
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        os.chmod(tmp_path, 0o666 & ~_umask())
        os.replace(tmp_path, target)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            tmp_path.unlink()
        if isinstance(exc, OSError) and exc.filename in (tmp, str(tmp_path)):
            raise _naming(exc, target) from exc  # the user's file, not its temporary name
        raise


def _naming(exc: OSError, target: Path) -> OSError:
    """The same error (its errno's class) about ``target``."""
    return OSError(exc.errno, exc.strerror, str(target)) if exc.errno else OSError(str(exc))


def atomic_write_text(target: str | Path, text: str) -> None:
    with atomic_path(target) as tmp:
        tmp.write_text(text, encoding="utf-8")


def reserve_results_dir(requested: Path, force: bool = False) -> tuple[Path, bool]:
    """(target, replaces): claim ``requested`` or the first free ``requested-N`` by
    creating it empty; with ``force`` an existing ``requested`` is kept until the run
    commits (``replaces`` True). Raises OSError when the location cannot be written."""
    requested = Path(requested)
    if requested.exists() and not requested.is_dir():
        raise NotADirectoryError(20, f"{requested} exists and is not a directory")
    created = _make_parents(requested)
    if force and requested.is_dir():
        return requested, True
    k = 1
    while True:
        candidate = requested if k == 1 else Path(f"{requested}-{k}")
        try:
            candidate.mkdir()
            os.chmod(candidate, 0o777 & ~_umask())
            _reservation_mark(candidate).touch()
            _CREATED_PARENTS[candidate] = created
            return candidate, False
        except FileExistsError:
            if not _reclaim_dead_reservation(candidate):
                k += 1


#: results directory -> the folders above it its reservation created (deepest first), which
#: an abandoned run removes again when they are still empty
_CREATED_PARENTS: dict[Path, list[Path]] = {}


def _make_parents(requested: Path) -> list[Path]:
    """Create the folders above ``requested`` that do not exist; those folders, deepest first."""
    missing = [p for p in requested.parents if not p.exists()]
    requested.parent.mkdir(parents=True, exist_ok=True)
    return missing


def _remove_created_parents(target: Path) -> None:
    """Remove the still-empty folders the reservation of ``target`` created."""
    for p in _CREATED_PARENTS.pop(target, []):
        try:
            p.rmdir()
        except OSError:
            break


def _reservation_mark(target: Path, tag: str | None = None) -> Path:
    """The file that says which process reserved ``target`` (removed when it commits)."""
    return Path(target) / f"{RESERVED_MARK}{process_tag() if tag is None else tag}"


def _start_time(pid: int) -> str | None:
    """A process's start time (clock ticks since boot, /proc/PID/stat field 22), None
    where the system does not say (no /proc, or no such process)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except (OSError, ValueError):
        return None
    return stat.rsplit(")", 1)[-1].split()[19]


def process_tag(pid: int | None = None) -> str:
    """ "PID-START" naming a running process (this one by default): its id and start time,
    so that a later process given the same id is told apart; "PID" where the start time
    is unknown."""
    pid = os.getpid() if pid is None else pid
    start = _start_time(pid)
    return f"{pid}-{start}" if start else str(pid)


def tag_alive(tag: str) -> bool:
    """Whether the process a :func:`process_tag` names still runs (the same process: a
    reused id with another start time does not count)."""
    pid_text, _, start = tag.partition("-")
    pid = int(pid_text)
    if not process_running(pid):
        return False
    return not start or _start_time(pid) in (None, start)


def _reclaim_dead_reservation(candidate: Path) -> bool:
    """Remove ``candidate`` when it is only the reservation of a process that no longer
    runs (a run killed with SIGKILL before it committed); True when removed."""
    try:
        entries = list(candidate.iterdir())
    except OSError:
        return False
    if len(entries) != 1 or not entries[0].name.startswith(RESERVED_MARK):
        return False
    tag = entries[0].name[len(RESERVED_MARK) :]
    try:
        if tag == process_tag() or tag_alive(tag):
            return False
    except ValueError:
        return False
    try:
        entries[0].unlink()
        candidate.rmdir()
    except OSError:
        return False  # another run reclaimed or filled it first
    return True


class Staging:
    """A hidden directory beside ``target`` that a run writes into; see the module doc."""

    def __init__(self, target: Path, replaces: bool = False):
        self.target = Path(target)
        self.replaces = replaces
        remove_dead_staging(self.target.parent)
        prefix = f".{self.target.name}{STAGING_MARK}{process_tag()}."
        self.path = Path(tempfile.mkdtemp(prefix=prefix, dir=self.target.parent))
        os.chmod(self.path, 0o777 & ~_umask())

    def commit(self) -> Path:
        """Rename the staging directory onto the target (replacing it with ``force``)."""
        if self.replaces and self.target.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{self.target.name}.old.", dir=self.target.parent))
            os.replace(self.target, old / self.target.name)
            os.replace(self.path, self.target)
            shutil.rmtree(old, ignore_errors=True)
        else:
            with contextlib.suppress(FileNotFoundError):
                _reservation_mark(self.target).unlink()
            os.replace(self.path, self.target)  # onto the empty reserved directory
        return self.target

    def abandon(self) -> None:
        """Remove the staging directory and give up the reservation."""
        shutil.rmtree(self.path, ignore_errors=True)
        if not self.replaces:
            with contextlib.suppress(OSError):
                _reservation_mark(self.target).unlink()
                self.target.rmdir()  # only if still empty
            _remove_created_parents(self.target)


def remove_dead_staging(directory: Path) -> list[Path]:
    """Remove staging directories in ``directory`` whose process no longer runs."""
    removed = []
    for p in Path(directory).glob(f".*{STAGING_MARK}*"):
        try:
            tag = p.name.split(STAGING_MARK, 1)[1].split(".", 1)[0]
            gone = tag != process_tag() and not tag_alive(tag)
        except (IndexError, ValueError):
            continue
        if gone:
            shutil.rmtree(p, ignore_errors=True)
            removed.append(p)
    return removed


def results_dir(requested: str | Path, field: str) -> Path:
    """The results folder a run may claim, or an InputError naming ``field``: a name, and
    not the current folder or one above it (a results folder is replaced whole with
    --force, and without it a "-2" folder would appear beside it)."""
    text = str(requested)
    if not text.strip():
        raise InputError(field, "an empty name: give a folder for the results (e.g. results)")
    path = Path(requested)
    try:
        resolved, here = path.resolve(), Path.cwd().resolve()
    except (OSError, RuntimeError, ValueError) as exc:
        raise _unusable(field, path, exc) from None
    if resolved == here or resolved in here.parents:
        where = "the current folder" if resolved == here else "above the current folder"
        raise InputError(field, f"{text} is {where}: name a new folder for the results (e.g. results)")
    return path


def writable_dir(path: str | Path, option: str) -> Path:
    """Create (if needed) and return a directory the run may write into, or raise
    InputError naming ``option``; called before any work starts."""

    p = _nameable(Path(path), option)
    try:  # a name the file system cannot hold (too long) raises here already
        exists_as_file = p.exists() and not p.is_dir()
    except (OSError, ValueError) as exc:
        raise _unusable(option, p, exc) from None
    if exists_as_file:
        raise InputError(option, f"{p} exists and is not a directory")
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(option, f"cannot create {p}: {exc.strerror or exc}") from None
    if not os.access(p, os.W_OK | os.X_OK):
        raise InputError(option, f"{p} is not writable")
    try:  # a file made and removed: what os.access cannot tell (root, /proc, a read-only mount)
        fd, probe = tempfile.mkstemp(prefix=".railcheck-probe.", dir=p)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise InputError(option, f"cannot write in {p}: {exc.strerror or exc}") from None
    return p


def _nameable(p: Path, option: str) -> Path:
    """``p``, or the InputError naming ``option`` when it holds a NUL character (no file
    system takes one; pathlib's lookups would say "no such file" instead)."""
    if "\0" in str(p):
        raise _unusable(option, p, ValueError("a file name cannot hold a NUL character"))
    return p


def _unusable(option: str, p: Path, exc: Exception) -> InputError:
    """A path the file system cannot even look up (too long a name, a NUL byte), shown
    shortened: the InputError naming ``option``."""
    text = str(p)
    shown = text if len(text) <= 80 else text[:77] + "..."
    return InputError(option, f"cannot use {shown!r}: {getattr(exc, 'strerror', None) or exc}")


def writable_file(path: str | Path, option: str, suffix: str | None = None) -> Path:
    """Check that ``path`` can be written as a file (its directory is created) and, for a
    format chosen by the name, ends in ``suffix`` (e.g. ".gif"), or raise InputError
    naming ``option``; called before any work starts."""

    p = _nameable(Path(path), option)
    try:
        is_dir = p.is_dir()
    except (OSError, ValueError) as exc:
        raise _unusable(option, p, exc) from None
    if is_dir:
        raise InputError(option, f"{p} is a directory, not a file name")
    if suffix and p.suffix.lower() != suffix:
        raise InputError(option, f"the file is written as {suffix[1:].upper()}: name it *{suffix}, got {p.name!r}")
    writable_dir(p.parent if str(p.parent) else Path("."), option)
    if p.exists() and not os.access(p, os.W_OK):
        raise InputError(option, f"{p} is not writable")
    return p


def to_json(data: Any) -> str:
    """Deterministic JSON (sorted keys are not used: the order is the report's order)."""
    return json.dumps(_clean(data), indent=2, ensure_ascii=False, allow_nan=False)


def _clean(x: Any) -> Any:
    if isinstance(x, dict):
        return {str(k): _clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_clean(v) for v in x]
    if hasattr(x, "item") and not isinstance(x, (str, bytes)):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x
