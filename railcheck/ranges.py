"""The physical ranges every number of a scene is checked against when it is read (SI),
and the words of a refusal: a value outside is refused, naming the field."""

from __future__ import annotations

import difflib
import math

from railcheck.base.errors import InputError

#: physical ranges checked when the scene is read (SI): a value outside is refused, naming
#: the field. A teaching rig's bars are centimetres to metres; its crank turns at most a
#: few revolutions per second (inertia loads grow with the square); limits are stresses
#: of real materials; forces are what bolts and plates of this size could carry.
RANGES = {
    "length": (1e-3, 10.0, "1 mm", "10 m"),
    "speed": (0.0, 2 * math.pi * 50.0, "0 Hz", "50 Hz"),
    "limit": (1e6, 5e9, "1 MPa", "5 GPa"),
    "force": (0.0, 1e6, "0 N", "1 MN"),
    "factor": (0.1, 100.0, "0.1", "100"),
    "embedding": (1e-7, 1e-4, "0.1 um", "0.1 mm"),  # [components] screw_embedding: VDI 2230's f_Z
    "geometry": (0.1e-3, 2.0, "0.1 mm", "2 m"),
    "deflection": (1e-6, 1.0, "1 um", "1 m"),  # a plate's limit is a few tenths of a millimetre
    "moment": (0.1, 1e6, "0.1 N m", "1 MN m"),  # [components]: a screw's, a pin's, a bearing's ratings
    "area": (1e-9, 1e-2, "0.001 mm2", "10,000 mm2"),
    "time": (3600.0, 3.6e15, "1 h", "1e12 h"),
}


def in_range(value: float, kind: str, name: str, magnitude: bool = False) -> float:
    """``value`` when it lies in the range ``kind`` of :data:`RANGES` (its magnitude with
    ``magnitude``); else an :class:`InputError` naming the field ``name``."""
    lo, hi, lo_text, hi_text = RANGES[kind]
    v = abs(value) if magnitude else value
    if not lo <= v <= hi:
        shown = "|value|" if magnitude else "value"
        raise InputError(name, f"{shown} outside the physical range {lo_text} to {hi_text} this tool accepts")
    return value


def did_you_mean(name: str, known: tuple[str, ...]) -> str:
    """ " (did you mean 'x'?)" for the nearest known name, else the list of them."""
    near = difflib.get_close_matches(name, known, n=1)
    return f" (did you mean {near[0]!r}?)" if near else f" (known: {', '.join(known)})"
