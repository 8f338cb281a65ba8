"""A sweep's chunks on this process's threads, when the sweep is too small for a Dask
cluster to pay for its start-up (two processes importing the project: 2-3 s) and this
process cannot fork its workers (elsewhere :mod:`railcheck.parallel.forked`).

numpy releases the GIL inside its loops, so two chunks on two threads run about 1.5x as
fast as one after the other (a narrow FE sweep of 981 settings with FE: 25.1 s -> 15.5 s;
the screens' many small numpy calls hold the GIL between their loops, so not 2x). BLAS
is held to one thread meanwhile: two chunks, each with a BLAS pool of one thread per
core, oversubscribe the cores and are slower than one chunk alone (28.4 s)."""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable, Iterator, Sequence
from contextlib import AbstractContextManager
from typing import Any, TypeVar

T = TypeVar("T")

#: seconds between looks at a result that has not arrived (signals are handled in between)
WAIT_S = 0.2


def blas_on_one_thread() -> AbstractContextManager:
    """While it is entered, numpy's and scipy's BLAS (OpenBLAS) runs on the calling
    threads only. MKL, loaded for PARDISO alone, keeps its threads: PARDISO's digits
    depend on its thread count, and a factorisation here must give a serial run's."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController().select(internal_api="openblas").limit(limits=1)


def on_one_blas_thread(function: Callable[..., T]) -> Callable[..., T]:
    """``function`` run with BLAS on one thread (:func:`blas_on_one_thread`), so that its
    digits are the same whatever runs it: this process alone, two of its threads (a check
    whose parts are stored), a worker (BLAS sums a product in another order on another
    thread count; a warm check's summary equals a cold one's byte for byte). Entered
    inside an outer limit of one thread it restores one thread: no other thread's limit is
    lifted."""

    @functools.wraps(function)
    def run(*args, **kw):
        with blas_on_one_thread():
            return function(*args, **kw)

    return run


def in_order_on_threads(function: Callable[[Any], T], items: Sequence, threads: int, ahead: int) -> Iterator[T]:
    """``function(item)`` of every item, yielded in the items' order, computed on
    ``threads`` daemon threads with at most ``ahead`` items started beyond the one the
    caller waits for (their results' memory). An exception from ``function`` is raised
    here when its item's turn comes; once the caller stops (an exception, a signal, an
    abandoned iterator) no further item is started, and a running one cannot keep the
    process alive (daemon threads)."""
    cond = threading.Condition()
    results: dict[int, tuple[bool, Any]] = {}
    state = {"next": 0, "wanted": 0, "stop": False}

    def work() -> None:
        while True:
            with cond:
                while not state["stop"] and state["next"] < len(items) and state["next"] - state["wanted"] > ahead:
                    cond.wait()
                if state["stop"] or state["next"] >= len(items):
                    return
                i = state["next"]
                state["next"] += 1
            try:
                result: tuple[bool, Any] = (True, function(items[i]))
            except BaseException as exc:  # handed to the caller in order
                result = (False, exc)
            with cond:
                results[i] = result
                cond.notify_all()

    for k in range(max(1, threads)):
        threading.Thread(target=work, name=f"railcheck-chunks-{k}", daemon=True).start()
    try:
        for i in range(len(items)):
            with cond:
                state["wanted"] = i
                cond.notify_all()
                while i not in results:
                    cond.wait(WAIT_S)
                ok, value = results.pop(i)
            if not ok:
                raise value
            yield value
    finally:
        with cond:
            state["stop"] = True
            cond.notify_all()
