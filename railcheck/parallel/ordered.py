"""The one ordered map: ``function(item)`` for each item, yielded in the items' order,
serially, on this process's threads (:mod:`.threads`), on processes forked from this one
(:mod:`.forked`) or on a Dask cluster's workers (:mod:`.dask`). The sweep's chunks go
through it (:class:`.executor.ChunkExecutor`); a caller that wants another executor names
it, nothing else changes.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from typing import Any, TypeVar

from railcheck.parallel.dask import in_order_on_dask
from railcheck.parallel.forked import in_order_on_processes
from railcheck.parallel.threads import in_order_on_threads

T = TypeVar("T")

#: where :func:`in_order` runs the items
EXECUTORS = ("serial", "threads", "forked", "dask")


def in_order(
    function: Callable[[Any], T],
    items: Iterable,
    *,
    on: str = "serial",
    workers: int = 1,
    ahead: int | None = None,
    client=None,
) -> Iterator[T]:
    """``function(item)`` for each of ``items``, in order, ``on`` one of :data:`EXECUTORS`
    with ``workers`` at once and at most ``ahead`` results (default ``workers``) finished
    before the one due; serially when ``workers`` is 1 (but on Dask). On Dask ``client``
    is the cluster's client, ``workers`` the items running at once, and the items are
    drawn lazily, each as a place frees. An item's error is raised when its result is due."""
    if on not in EXECUTORS:
        raise ValueError(f"on must be one of {EXECUTORS}, not {on!r}")
    if on == "dask":
        return in_order_on_dask(client, function, items, workers, workers if ahead is None else ahead)
    ahead = max(ahead or workers, workers)
    items = list(items)
    if on == "serial" or workers <= 1:
        return map(function, items)
    if on == "threads":
        return in_order_on_threads(function, items, workers, ahead)
    return in_order_on_processes(function, items, workers, ahead)
