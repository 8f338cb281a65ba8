"""Dask for the sweep's chunks: a local cluster's workers' settings (heap, profiler), its
quiet exit, and a client to a local cluster or an existing scheduler.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from typing import Any, TypeVar

T = TypeVar("T")

#: glibc's heap settings of the local cluster's workers. Dask starts its workers with
#: MALLOC_TRIM_THRESHOLD_ = 64 kB (memory back to the system as soon as it is freed), which
#: makes every settings x steps temporary fault its pages in afresh (the kinematics-only
#: sweep ran at half speed on the workers). Any explicit value turns glibc's adaptive
#: thresholds off, so both are set: a worker keeps up to 256 MiB of freed heap and maps only
#: blocks above 32 MiB (glibc's largest threshold), so a part's stresses per basis
#: coordinate (up to 26 MB, one per group of settings) reuse the heap instead of going
#: through the kernel (measured: docs/changelog.md, "The measurements behind tuned constants").
WORKER_MALLOC = {"MALLOC_TRIM_THRESHOLD_": 256 << 20, "MALLOC_MMAP_THRESHOLD_": 32 << 20}


#: Dask settings of the local cluster's workers. Their statistical profiler (for a dashboard
#: this cluster does not start) samples the computing thread's stack every 10 ms, holding the
#: GIL that the screens' many small numpy calls need, so it is off (measured:
#: docs/changelog.md, "The measurements behind tuned constants").
WORKER_CONFIG = {"distributed.worker.profile.enabled": False}


def quiet_cluster_exit() -> None:
    """Replace distributed's exit hook that closes the local clusters still open by one
    that closes them quietly: a run interrupted while its cluster starts or stops (Ctrl-C)
    ends with ``railcheck: interrupted``, not with the hook's traceback (an assertion on a
    worker still starting); the workers end with this process either way."""
    import atexit
    import contextlib

    from distributed.deploy import spec

    def close_quietly():
        with contextlib.suppress(Exception):
            spec.close_clusters()

    if getattr(spec.close_clusters, "_railcheck_quiet", None) is None:
        atexit.unregister(spec.close_clusters)
        atexit.register(close_quietly)
        spec.close_clusters._railcheck_quiet = close_quietly  # type: ignore[attr-defined]


def in_order_on_dask(client, function: Callable[[Any], T], items: Iterable, running_at_most: int, held: int) -> Iterator[T]:
    """``function(item)`` on ``client``'s workers for each of ``items`` (drawn lazily, when
    a place frees, so an item may be built as it is due), yielded in the items' order: at
    most ``running_at_most`` running and ``held`` finished ahead of the one due (a slow
    item does not idle the other workers). Closing the iterator cancels what still runs."""
    from dask.distributed import wait as wait_for

    items = iter(items)
    running: dict = {}  # future -> item index
    finished: dict[int, Any] = {}  # item index -> its finished future, read when due
    submitted = done = 0
    exhausted = False
    try:
        while True:
            while not exhausted and len(running) < running_at_most and len(finished) < held:
                item = next(items, _END)
                if item is _END:
                    exhausted = True
                    break
                running[client.submit(function, item, pure=False)] = submitted
                submitted += 1
            if exhausted and done == submitted:
                return
            if done not in finished:
                if not running:  # cannot happen: the next item is either finished or running
                    raise RuntimeError(f"item {done} was neither finished nor running")
                for future in wait_for(list(running), return_when="FIRST_COMPLETED").done:
                    finished[running.pop(future)] = future  # an error is raised when its item is due
                continue
            yield finished.pop(done).result()
            done += 1
    finally:
        for future in running:
            future.cancel()


_END = object()  # the end of an items iterator
