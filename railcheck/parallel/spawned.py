"""Spawned worker processes whose progress lines reach the console as they happen.

A :func:`relayed_pool` is a :class:`~concurrent.futures.ProcessPoolExecutor` of spawned
processes (no library state forked: gmsh, MKL and the FE packages start afresh in each);
a worker's :func:`worker_say` puts a line on a queue that a thread of the parent process
prints through its :class:`~railcheck.progress.Progress`. Used by the check's parts
(:mod:`railcheck.check.workers`) and by the sweep's part preparation.
"""

from __future__ import annotations

import multiprocessing
import threading
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager

from railcheck.progress import Progress

_QUEUE = None  # the worker's progress queue (set by _init_worker)


@contextmanager
def relayed_pool(workers: int, progress: Progress):
    """A pool of ``workers`` spawned processes (no library state forked) whose progress
    lines (:func:`worker_say`) reach ``progress`` as they happen. An error, Ctrl-C or
    SIGTERM in the block stops every worker at once."""
    ctx = multiprocessing.get_context("spawn")
    queue = ctx.SimpleQueue()
    relay = threading.Thread(target=_relay, args=(queue, progress), daemon=True)
    relay.start()
    pool = ProcessPoolExecutor(workers, mp_context=ctx, initializer=_init_worker, initargs=(queue,))
    try:
        yield pool
    except BaseException:
        for process in list(getattr(pool, "_processes", {}).values()):
            process.terminate()
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    finally:
        queue.put(None)
        relay.join(timeout=5)
    pool.shutdown()


def worker_say(message: str) -> None:
    """A progress line from a :func:`relayed_pool` worker (printed by the main process)."""
    if _QUEUE is None:
        raise RuntimeError("worker_say is for relayed_pool's workers")
    _QUEUE.put(message)


def _relay(queue, progress: Progress) -> None:
    """Print the workers' progress lines until the sentinel arrives."""
    while True:
        item = queue.get()
        if item is None:
            return
        progress.say("solve", item)


def _init_worker(queue) -> None:
    """The worker's progress queue. Thread counts stay those of a serial run (a single
    MKL thread here would be faster, but PARDISO's rounding depends on the thread count
    and ``--jobs 1`` must give the same digits)."""
    global _QUEUE
    _QUEUE = queue
