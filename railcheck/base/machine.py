"""What this machine offers a run: its physical memory, and the one refusal of work that
would need more of it than a run may take (a clear message with the estimate instead of a
MemoryError or the machine swapping). Imports nothing of ours but the error base, so any
layer may use it."""

from __future__ import annotations

import os

from railcheck.base.errors import InputError

#: the share of physical memory one run may plan to use
MEMORY_FRACTION = 0.8

#: bytes per crank step of one mechanism's kinematics and inverse dynamics (motion,
#: bodies, reactions, checks): 7.5 GB peak for 10 million steps, measured with
#: ``/usr/bin/time -v railcheck kinematics`` (steps = 10 000 000), rounded up
BYTES_PER_KINEMATICS_STEP = 800.0


def available_memory() -> float:
    """Bytes of physical memory on this machine (8 GiB when it cannot be read)."""
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return 8.0 * 2**30


def refuse_beyond_memory(need: float, field: str, what: str, advice: str) -> None:
    """Raise :class:`InputError` naming ``field`` when ``need`` bytes (an estimate made
    before the work) exceed the share of this machine's memory a run may take."""
    avail = available_memory()
    if need > MEMORY_FRACTION * avail:
        raise InputError(
            field,
            f"{what} needs about {short(need / 2**30)} GiB, "
            f"more than this machine's {short(avail / 2**30)} GiB allow: {advice}",
        )


def refuse_kinematics_beyond_memory(steps: int, field: str) -> None:
    """Refuse a crank step count whose kinematics would not fit in memory."""
    refuse_beyond_memory(steps * BYTES_PER_KINEMATICS_STEP, field, f"{steps} crank steps", "use fewer steps")


def short(x: float) -> str:
    """A size for a message: one decimal (1.0, 23.5), or three significant digits once it
    is beyond 100,000 (an absurd request's estimate is not printed with hundreds of digits)."""
    return f"{x:.1f}" if abs(x) < 1e5 else f"{x:.3g}"
