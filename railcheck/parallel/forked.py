"""A sweep's chunks on processes forked from this one (Linux), unless ``--scheduler``
names a Dask cluster or this process runs other threads (:func:`alone`: a library caller's
own; its sweep then runs where a process that cannot fork runs it).

Forked children share this process's memory (the settings, each kind's context with its
parts' screens, 1.3 GB for the whole rig) copy on write: a task is a chunk's index and its
result one chunk's columns, with nothing written to a shared file or scattered, and no
cluster to start, so they beat a Dask local cluster on one machine. They also beat this
process's threads on the kinematics' thousands of small numpy calls, which hold the GIL
between their loops (measured: docs/changelog.md, "The measurements behind tuned
constants").

The chunks call numpy and scipy only (their own OpenBLAS, pthreads, fork-safe); never
MKL, whose OpenMP runtime this process may have started for the unit fields and which a
forked child must not use. The children ignore Ctrl-C and die on SIGTERM: the caller
stops them when it stops (an error, a signal, an abandoned iterator), and the kernel sends
it to them when their parent dies (a killed run).
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import itertools
import multiprocessing
import os
import pickle
import signal
import sys
import threading
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures import TimeoutError as FutureTimeout
from concurrent.futures.process import BrokenProcessPool
from typing import Any, TypeVar

from railcheck.base.errors import RailcheckError

T = TypeVar("T")

#: seconds between looks at a result that has not arrived (signals are handled in between)
WAIT_S = 0.2

#: token -> (function, items) of each running call, read by the children it forks
_CALLS: dict[int, tuple[Callable, Sequence]] = {}
_TOKENS = itertools.count()

#: prctl option: the signal a process receives when its parent dies (linux/prctl.h)
PR_SET_PDEATHSIG = 1

#: glibc ``mallopt`` parameters (malloc.h) and the values a forked child sets
#: (:func:`reuse_freed_memory`): blocks up to 32 MiB (the largest glibc takes) from the
#: heap, and freed memory kept for the next ones
M_TRIM_THRESHOLD, M_TOP_PAD, M_MMAP_THRESHOLD = -1, -2, -3
CHILD_MALLOPT = ((M_MMAP_THRESHOLD, 32 << 20), (M_TRIM_THRESHOLD, 1 << 30), (M_TOP_PAD, 64 << 20))


@functools.cache
def available() -> bool:
    """Whether this platform forks processes (Linux; macOS's fork is unsafe with its system
    libraries, Windows has none) and has the semaphores a pool's queues need (a container
    without ``/dev/shm`` has not)."""
    if sys.platform != "linux" or "fork" not in multiprocessing.get_all_start_methods():
        return False
    try:
        multiprocessing.get_context("fork").Lock()
    except (OSError, ImportError):
        return False
    return True


def alone() -> bool:
    """Whether this process runs no Python thread but the one calling: the only state in
    which it forks its workers. A child has only the forking thread, and a lock another
    thread holds at the fork stays held in it; OpenBLAS's own fork handler deadlocks when
    another thread is inside a multi-threaded product (OpenBLAS issues #2270, #5520; seen
    here: a caller whose thread ran 200 x 200 products hung in ``blas_thread_shutdown_``
    in 3 of 3 runs). A library caller with threads of its own gets its sweep where a
    process that cannot fork runs it: a Dask local cluster for a large sweep, else this
    process's threads (:mod:`railcheck.parallel.threads`)."""
    return threading.active_count() == 1


def in_order_on_processes(function: Callable[[Any], T], items: Sequence, processes: int, ahead: int) -> Iterator[T]:
    """``function(item)`` of every item, yielded in the items' order, computed in
    ``processes`` forked children with at most ``ahead`` items started beyond the one the
    caller waits for. ``function`` and ``items`` reach the children by the fork (neither is
    pickled); each result comes back pickled. An exception from ``function`` is raised here
    at its item's turn; a child that dies (killed, out of memory) is a
    :class:`~railcheck.base.errors.RailcheckError` naming the sweep. Once the caller stops, the
    children are terminated. Call it only when this process is :func:`alone`."""
    token = next(_TOKENS)
    _CALLS[token] = (function, items)
    with _sigpipe_held():
        pool = ProcessPoolExecutor(
            processes, mp_context=multiprocessing.get_context("fork"), initializer=_child_signals, initargs=(os.getpid(),)
        )
    pending: deque = deque()
    finished = False
    try:
        for i in range(len(items)):
            while len(pending) < len(items) - i and len(pending) <= ahead:
                try:
                    with _sigpipe_held():  # the pool's threads start here and keep the mask
                        pending.append(pool.submit(_run_item, token, i + len(pending)))
                except BrokenProcessPool:  # a child died since the last result
                    raise _died() from None
            ok, value = _result(pending.popleft())
            if not ok:
                raise value
            yield value
        finished = True
    finally:
        _CALLS.pop(token, None)
        if not finished:
            _terminate_children(pool)
        pool.shutdown(wait=True, cancel_futures=True)


@contextlib.contextmanager
def _sigpipe_held():
    """SIGPIPE blocked in this thread for the block, and so in the threads it starts (the
    pool's manager and its queue's feeder, which write the tasks to the children's pipe).
    Once the children are stopped those writes meet a closed pipe: blocked, that is an
    error the pool handles, whatever the process's disposition. Python ignores SIGPIPE, but
    a library may have set it back to the default action, death (gmsh's initialize does;
    a CI run's pytest process died so, status 141). The mask is this thread's own: nothing
    process-wide changes, and it works in any thread."""
    held = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGPIPE})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, held)


def _result(future) -> tuple[bool, Any]:
    """The future's (ok, value), waiting in short steps so that signals are handled."""
    while True:
        try:
            return future.result(timeout=WAIT_S)
        except FutureTimeout:
            continue
        except BrokenProcessPool:
            raise _died() from None


def _died() -> RailcheckError:
    return RailcheckError("sweep", "a worker process died (killed, or out of memory): run again, or with --serial")


def _child_signals(parent: int) -> None:
    """In a child: Ctrl-C is the parent's to handle, SIGTERM (from the parent) ends it, and
    so does the parent's death (Linux ``PR_SET_PDEATHSIG``: a killed run leaves no child
    waiting for tasks); then its allocator is tuned (:func:`reuse_freed_memory`)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGPIPE})  # forked while held
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(PR_SET_PDEATHSIG, signal.SIGTERM)
    except (OSError, AttributeError):  # no prctl in this libc: a killed run's children outlive it
        pass
    if os.getppid() != parent:  # the parent died before the request took effect
        os._exit(1)
    reuse_freed_memory()


def reuse_freed_memory() -> None:
    """In a child: glibc's allocator keeps freed blocks of up to 32 MiB for the next ones
    (:data:`CHILD_MALLOPT`). A chunk's screens allocate and free thousands of temporary
    arrays of 0.1-30 MB; by default each comes from fresh ``mmap`` pages, zeroed by the
    kernel at first touch, and goes back at its free. The whole rig (three alternating
    runs each): system CPU 9-14 -> 4-5 s, chunks 48.4 -> 47.3 s (medians), the largest
    resident set the same (2.6 GB, the parent's), the tables the same. A child lives for
    one kind's chunks, so what it keeps is returned at its exit. Nothing without glibc's
    ``mallopt`` (musl)."""
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):
        return
    mallopt.argtypes, mallopt.restype = (ctypes.c_int, ctypes.c_int), ctypes.c_int
    for option, value in CHILD_MALLOPT:
        mallopt(option, value)


def _run_item(token: int, i: int) -> tuple[bool, Any]:
    """In a child: (True, the result) of item ``i`` of call ``token``, or (False, the
    exception, or a RuntimeError naming it if it cannot be pickled)."""
    function, items = _CALLS[token]
    try:
        return True, function(items[i])
    except BaseException as exc:  # handed to the caller in order
        return False, _sendable(exc)


def _sendable(exc: BaseException) -> BaseException:
    try:
        pickle.loads(pickle.dumps(exc))
        return exc
    except Exception:
        return RuntimeError(f"{type(exc).__name__}: {exc}")


def _terminate_children(pool: ProcessPoolExecutor) -> None:
    """Terminate the pool's children at once (their running items are abandoned)."""
    for process in list((getattr(pool, "_processes", None) or {}).values()):
        process.terminate()
