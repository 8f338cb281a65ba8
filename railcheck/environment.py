"""The environment variables railcheck reads, in one place. The domain packages never read
the environment: the application resolves these here and passes them as parameters (the
mesh cache's folder, the unit-field store, gmsh's log).

* ``RAILCHECK_CACHE``: the folder of the mesh cache and the unit-field store (unset or
  empty: ~/.cache/railcheck);
* ``RAILCHECK_STORE_MB``: the store's size cap in megabytes (unset or empty: 2048);
* ``RAILCHECK_STORE=0``: bypass the store (every part solved afresh, nothing stored);
* ``RAILCHECK_GMSH_VERBOSE=1``: gmsh prints its log.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from railcheck.base.errors import InputError
from railcheck.fea.store import UnitStore
from railcheck.geometry.cache import default_cache_dir

#: the unit-field store's cap when ``RAILCHECK_STORE_MB`` is unset or empty (MB)
DEFAULT_CAP_MB = 2048


def cache_dir() -> Path:
    """The folder of the mesh cache and the unit-field store: ``RAILCHECK_CACHE``, or
    ~/.cache/railcheck when it is unset or empty."""
    return Path(os.environ.get("RAILCHECK_CACHE") or default_cache_dir())


def store_cap_bytes() -> int:
    """The store's size cap in bytes: ``RAILCHECK_STORE_MB`` megabytes (unset or empty:
    :data:`DEFAULT_CAP_MB`); anything but a finite number of at least 0 is refused."""
    text = os.environ.get("RAILCHECK_STORE_MB", "").strip()
    if not text:
        return int(DEFAULT_CAP_MB * 1e6)
    try:
        mb = float(text)
    except ValueError:
        mb = math.nan
    if not (math.isfinite(mb) and 0.0 <= mb * 1e6 < 2.0**62):
        raise InputError("RAILCHECK_STORE_MB", f"must be a size in megabytes, 0 or more, got {text!r}")
    return int(mb * 1e6)


def unit_store() -> UnitStore | None:
    """The unit-field store (:mod:`railcheck.fea.store`) in the cache's folder with its
    cap, or None with ``RAILCHECK_STORE=0`` (every part solved afresh)."""
    if os.environ.get("RAILCHECK_STORE", "1") == "0":
        return None
    return UnitStore(cache_dir() / "unit-fields", store_cap_bytes())


def gmsh_verbose() -> bool:
    """Whether gmsh prints its log: ``RAILCHECK_GMSH_VERBOSE`` set to anything but 0."""
    return os.environ.get("RAILCHECK_GMSH_VERBOSE", "") not in ("", "0")
