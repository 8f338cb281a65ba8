"""Quantities with units at the edges: one parser, SI inside.

A scene states every dimensional value as a string, "480 mm", "1 Hz", "375 MPa".
:func:`parse_quantity` turns it into an SI float (m, kg, s, N, Pa, rad, rad/s) after
checking that the unit belongs to the expected dimension. A bare number for a
dimensional field is an error: the unit is part of the value.
"""

from __future__ import annotations

import math
import re
import unicodedata

from railcheck.base.errors import InputError

__all__ = ["parse_quantity", "UNITS", "format_quantity", "for_people"]

_TWO_PI = 2.0 * math.pi

#: dimension -> {unit symbol: factor to SI}
UNITS: dict[str, dict[str, float]] = {
    "length": {
        "m": 1.0,
        "cm": 1e-2,
        "mm": 1e-3,
        "um": 1e-6,
        "\u03bcm": 1e-6,
        "in": 0.0254,
    },  # the micro sign reads as \u03bc
    # a crank speed: SI is rad/s
    "angular_speed": {"rad/s": 1.0, "Hz": _TWO_PI, "rpm": _TWO_PI / 60.0, "deg/s": math.pi / 180.0},
    "stress": {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9, "N/mm2": 1e6, "N/mm^2": 1e6},
    "force": {"N": 1.0, "kN": 1e3},
    "area": {"m2": 1.0, "m^2": 1.0, "mm2": 1e-6, "mm^2": 1e-6},
    "moment": {"N m": 1.0, "N*m": 1.0, "Nm": 1.0, "N.m": 1.0, "kN m": 1e3, "kN*m": 1e3},
    "time": {"s": 1.0, "min": 60.0, "h": 3600.0},
    "mass": {"kg": 1.0, "g": 1e-3},
    "linear_density": {"kg/m": 1.0, "g/mm": 1.0},
    "angle": {"rad": 1.0, "deg": math.pi / 180.0, "°": math.pi / 180.0},
    "acceleration": {"m/s2": 1.0, "m/s^2": 1.0, "g": 9.80665},
    "memory": {"B": 1.0, "kB": 1e3, "MB": 1e6, "GB": 1e9, "KiB": 1024.0, "MiB": 1024.0**2, "GiB": 1024.0**3},
}

#: the unit an error message suggests for a bare number
PREFERRED = {
    "length": "mm",
    "angular_speed": "Hz",
    "stress": "MPa",
    "force": "N",
    "area": "mm2",
    "moment": "N m",
    "time": "h",
    "mass": "kg",
    "linear_density": "kg/m",
    "angle": "deg",
    "acceleration": "m/s2",
    "memory": "GB",
}

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[-+]?(?:nan|infinity|inf)"
_PATTERN = re.compile(rf"^\s*({_NUMBER})\s*([^\s\d].*?)?\s*$", re.IGNORECASE)


def parse_quantity(value: object, dimension: str, field: str, *, positive: bool = False, allow_zero: bool = True) -> float:
    """Parse ``value`` ("480 mm") as a ``dimension`` quantity; return its SI value.

    Raises :class:`InputError` naming ``field`` for a bare number, an unknown or wrong
    unit, NaN or infinity, and (with ``positive``) a negative value, or zero unless
    ``allow_zero``.
    """
    units = UNITS[dimension]
    if isinstance(value, bool) or isinstance(value, (int, float)):
        raise InputError(field, f'needs a unit, e.g. "{value} {PREFERRED[dimension]}" (got the bare number {value!r})')
    if not isinstance(value, str):
        raise InputError(field, f"must be a string with a unit, got {type(value).__name__}")
    value = unicodedata.normalize("NFKC", value)  # the micro sign and the Greek mu are one letter
    match = _PATTERN.match(value)
    if not match:
        raise InputError(
            field,
            f"cannot read {value!r} as a {dimension.replace('_', ' ')} (expected a number and one of: {', '.join(units)})",
        )
    number, unit = match.group(1), (match.group(2) or "").strip()
    if re.match(r"^,\d", unit):  # "480,5 mm": a decimal comma, as Spanish and much of Europe write
        raise InputError(field, f'write a decimal point, not a comma: "{number}.{unit[1:]}" (got {value!r})')
    if not unit:
        raise InputError(field, f'needs a unit, e.g. "{number} {PREFERRED[dimension]}"')
    unit = _by_case(unit, units)
    if unit not in units:
        wrong = [dim for dim, table in UNITS.items() if unit in table]
        hint = f" ({unit!r} is {_a(wrong[0])} unit)" if wrong else ""
        raise InputError(field, f"unit {unit!r} is not {_a(dimension)} unit{hint}; use one of: {', '.join(units)}")
    x = float(number)
    if not math.isfinite(x):
        raise InputError(field, f"must be finite, got {value!r}")
    si = x * units[unit]
    if positive and si < 0:
        raise InputError(field, f"must be positive, got {value!r}")
    if positive and not allow_zero and si == 0:
        raise InputError(field, f"must be greater than zero, got {value!r}")
    return si


def _by_case(unit: str, units: dict[str, float]) -> str:
    """``unit`` as the table writes it when only its letters' case differs ("RPM" is rpm,
    "mpa" MPa); unchanged otherwise (every table's units differ in more than case)."""
    if unit in units:
        return unit
    same = [u for u in units if u.lower() == unit.lower()]
    return same[0] if len(same) == 1 else unit


def _a(dimension: str) -> str:
    """ "a length", "an angular speed": a dimension's name with its article."""
    words = dimension.replace("_", " ")
    return f"{'an' if words[0] in 'aeiou' else 'a'} {words}"


def format_quantity(si: float, unit: str, dimension: str, digits: int = 4) -> str:
    """Format an SI value in ``unit`` with ``digits`` significant figures: '480 mm'."""
    return f"{si / UNITS[dimension][unit]:.{digits}g} {unit}"


def for_people(x: float | None, spec: str = ".2f", unlimited: str = "unlimited", missing: str = "none") -> str:
    """A number as a person reads it: ``format(x, spec)``, a word for infinity
    (``unlimited``: a safety factor with no load, a safe speed with no limit) and for a
    missing or NaN value (``missing``), never "inf" or "nan"."""
    if x is None or math.isnan(x):
        return missing
    if math.isinf(x):
        return unlimited if x > 0 else f"-{unlimited}"
    return format(x, spec)


def floored(x: float, digits: int = 3) -> str:
    """``x`` (> 0, finite) to ``digits`` significant figures rounded down, never up: a
    safe speed of 1.195 Hz reads "1.19". The product is nudged by 1e-12 so that a value
    whose decimal digits end exactly there (0.29, stored as 0.28999...) keeps them."""
    exponent = digits - 1 - math.floor(math.log10(x))
    scale = 10.0**exponent
    text = f"{math.floor(x * scale * (1.0 + 1e-12)) / scale:.{max(exponent, 0)}f}"
    return text.rstrip("0").rstrip(".") if "." in text else text


#: the round colour-scale ends, times a power of ten (:func:`nice_top`)
NICE_STEPS = (1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0)


def nice_top(value: float) -> float:
    """``value`` rounded up to a round colour-scale end: 1, 1.5, 2, 2.5, 3, 4, 5, 6, 8 or 10
    times a power of ten (1.62 -> 2, 3.86 -> 4, 0.7 -> 0.8)."""
    if not math.isfinite(value) or value <= 0:
        return 1.0
    power = 10.0 ** math.floor(math.log10(value))
    return next(s for s in NICE_STEPS if s * power >= value * (1 - 1e-12)) * power
