"""Which code produced a cached entry: the SHA-256 of the source of every module of the
packages that compute it, so a change to that code gives new keys and an entry written by
other code is never read (no hand-bumped format number to forget). Read once per process.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
from pathlib import Path


def package_root(package: str) -> Path:
    """The folder of ``package`` (a dotted name); a module that is not a package refused."""
    spec = importlib.util.find_spec(package)
    if spec is None or not spec.submodule_search_locations:
        raise ValueError(f"{package} is not a package")
    return Path(next(iter(spec.submodule_search_locations)))


def package_sources(package: str) -> list[Path]:
    """The ``.py`` files of ``package`` and its subpackages, sorted."""
    return sorted(f for f in package_root(package).rglob("*.py") if "__pycache__" not in f.parts)


@functools.lru_cache(maxsize=None)
def code_hash(*packages: str) -> str:
    """24 hex digits of the SHA-256 over each package's source files (their paths inside
    the package and their bytes, not where it is installed): equal exactly when the code is."""
    h = hashlib.sha256()
    for package in packages:
        root = package_root(package)
        for path in package_sources(package):
            h.update(f"{path.relative_to(root).as_posix()}\0".encode())
            h.update(path.read_bytes())
            h.update(b"\0")
        h.update(b"\1")  # the next package
    return h.hexdigest()[:24]
