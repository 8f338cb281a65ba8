"""Elapsed-time reports while a long, blocking call runs (a factorisation, a CG solve).

The FE package does not print: callers pass ``report``, a function taking one line of
text (``None`` is silent). :func:`heartbeat` calls it when the work starts and then every
:data:`INTERVAL` seconds from a background thread, so the first minute of a long solve is
never silent; the C libraries release the GIL while they work.
"""

from __future__ import annotations

import contextlib
import threading
import time
from typing import Callable, Iterator

INTERVAL = 5.0  # s between reports


@contextlib.contextmanager
def heartbeat(label: str, report: Callable[[str], None] | None, interval: float = INTERVAL) -> Iterator[None]:
    """Report ``label`` now and ``label ... N s`` every ``interval`` seconds until the
    block ends; then ``label: done in N s`` when it took longer than one interval."""
    if report is None:
        yield
        return
    t0 = time.perf_counter()
    done = threading.Event()

    def beat():
        while not done.wait(interval):
            report(f"{label} ... {time.perf_counter() - t0:.0f} s")

    report(label)
    thread = threading.Thread(target=beat, daemon=True)
    thread.start()
    try:
        yield
    finally:
        done.set()
        thread.join()
        elapsed = time.perf_counter() - t0
        if elapsed > interval:
            report(f"{label}: done in {elapsed:.1f} s")
