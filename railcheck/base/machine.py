"""What this machine offers a run: its physical memory, the one refusal of work that
would need more of it than a run may take (a clear message with the estimate instead of a
MemoryError or the machine swapping), and handing freed heap back (:func:`trim_heap`).
Imports nothing of ours but the error base, so any layer may use it."""

from __future__ import annotations

import ctypes
import math
import os

from railcheck.base.errors import InputError

#: the share of physical memory one run may plan to use
MEMORY_FRACTION = 0.8

#: bytes per crank step of one mechanism's kinematics and inverse dynamics (motion,
#: bodies, reactions, checks): 7.5 GB peak for 10 million steps, measured with
#: ``/usr/bin/time -v railcheck kinematics`` (steps = 10 000 000), rounded up
BYTES_PER_KINEMATICS_STEP = 800.0


def available_memory() -> float:
    """Bytes of memory this process may use: the machine's physical memory (8 GiB when it
    cannot be read), or less under an address-space limit (``ulimit -v``: the limit less
    what the process has already mapped) or a container's memory limit (cgroup v2)."""
    try:
        physical = float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        physical = 8.0 * 2**30
    return min(physical, _address_space_left(), _container_limit())


def _address_space_left() -> float:
    """Bytes the address-space limit leaves this process (inf without one)."""
    try:
        import resource

        limit = resource.getrlimit(resource.RLIMIT_AS)[0]
        if limit == resource.RLIM_INFINITY:
            return math.inf
        with open("/proc/self/status", encoding="ascii") as f:
            mapped = next((int(line.split()[1]) * 1024 for line in f if line.startswith("VmSize:")), 0)
        return float(max(limit - mapped, 0))
    except (ImportError, OSError, ValueError):
        return math.inf


def _container_limit() -> float:
    """Bytes of a cgroup v2 memory limit (inf without one)."""
    try:
        with open("/sys/fs/cgroup/memory.max", encoding="ascii") as f:
            text = f.read().strip()
        return math.inf if text == "max" else float(int(text))
    except (OSError, ValueError):
        return math.inf


def refuse_beyond_memory(need: float, field: str, what: str, advice: str) -> None:
    """Raise :class:`InputError` naming ``field`` when ``need`` bytes (an estimate made
    before the work) exceed the share of this machine's memory a run may take."""
    avail = available_memory()
    if need > MEMORY_FRACTION * avail:
        raise InputError(
            field,
            f"{what} needs about {short(need / 2**30)} GiB, more than this run may use ({usable_words(avail)}): {advice}",
        )


def usable_words(avail: float) -> str:
    """What a run may plan to use of the ``avail`` bytes this process may take, for a
    refusal: "4.3 GiB, 80% of 5.4 GiB" (the need is compared with the first figure)."""
    return f"{short(MEMORY_FRACTION * avail / 2**30)} GiB, {MEMORY_FRACTION:.0%} of {short(avail / 2**30)} GiB"


def refuse_kinematics_beyond_memory(steps: int, field: str) -> None:
    """Refuse a crank step count whose kinematics would not fit in memory."""
    refuse_beyond_memory(steps * BYTES_PER_KINEMATICS_STEP, field, f"{steps} crank steps", "use fewer steps")


def short(x: float) -> str:
    """A size for a message: one decimal (1.0, 23.5), or three significant digits once it
    is beyond 100,000 (an absurd request's estimate is not printed with hundreds of digits)."""
    return f"{x:.1f}" if abs(x) < 1e5 else f"{x:.3g}"


def trim_heap() -> None:
    """Return the process's free heap pages to the system (glibc ``malloc_trim(0)``); a
    no-op where the C library has none."""
    try:
        ctypes.CDLL(None).malloc_trim(0)
    except (OSError, AttributeError):
        pass
