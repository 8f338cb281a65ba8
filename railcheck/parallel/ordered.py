"""The one ordered map: ``function(item)`` for each item, yielded in the items' order,
serially, on this process's threads (:mod:`.threads`) or on processes forked from this one
(:mod:`.forked`). The sweep's chunks go through it (:class:`.executor.ChunkExecutor`, which
adds Dask for a cluster); a caller that wants another executor names it, nothing else
changes.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from typing import Any, TypeVar

from railcheck.parallel.forked import in_order_on_processes
from railcheck.parallel.threads import in_order_on_threads

T = TypeVar("T")

#: where :func:`in_order` runs the items
EXECUTORS = ("serial", "threads", "forked")


def in_order(
    function: Callable[[Any], T], items: Sequence, *, on: str = "serial", workers: int = 1, ahead: int | None = None
) -> Iterator[T]:
    """``function(item)`` for each of ``items``, in order, ``on`` one of :data:`EXECUTORS`
    with ``workers`` at once and at most ``ahead`` results (default ``workers``) finished
    before the one due; serially when ``workers`` is 1. An item's error is raised when
    its result is due."""
    if on not in EXECUTORS:
        raise ValueError(f"on must be one of {EXECUTORS}, not {on!r}")
    ahead = max(ahead or workers, workers)
    if on == "serial" or workers <= 1:
        return map(function, items)
    if on == "threads":
        return in_order_on_threads(function, items, workers, ahead)
    return in_order_on_processes(function, items, workers, ahead)
