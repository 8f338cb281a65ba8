"""A scene table's fields read and refused in one place: unknown keys (with the closest
allowed name), missing keys, booleans, choices and plain numbers, each refusal an
:class:`~railcheck.base.errors.InputError` naming the field ("mechanism.kind").
"""

from __future__ import annotations

import difflib
import math
from typing import Any

from railcheck.base.errors import InputError


def unknown_keys(table: dict, allowed: set[str] | None, prefix: str) -> list[InputError]:
    """An InputError for each key of ``table`` not in ``allowed`` (None: any key)."""
    out: list[InputError] = []
    if allowed is None:
        return out
    for key in table:
        if key not in allowed:
            close = difflib.get_close_matches(str(key), sorted(allowed), n=1)
            guess = f'did you mean "{close[0]}"? ' if close else ""
            out.append(InputError(f"{prefix}{key}", f"unknown key ({guess}allowed: {', '.join(sorted(allowed))})"))
    return out


def refuse_unknown(table: dict, allowed: set[str] | None, prefix: str) -> None:
    """Raise the InputError naming the first key of ``table`` not in ``allowed``."""
    errors = unknown_keys(table, allowed, prefix)
    if errors:
        raise errors[0]


def require(table: dict, key: str, prefix: str) -> Any:
    """``table[key]``; an InputError "missing" naming ``prefix + key`` without it."""
    if key not in table:
        raise InputError(f"{prefix}{key}", "missing")
    return table[key]


def boolean(table: dict, key: str, prefix: str, default: bool) -> bool:
    """``table[key]`` as true or false (``default`` when absent); anything else refused."""
    value = table.get(key, default)
    if not isinstance(value, bool):
        raise InputError(f"{prefix}{key}", f"must be true or false, got {value!r}")
    return value


def string_choice(value: Any, choices: tuple[str, ...], name: str) -> str:
    """``value`` if it is one of ``choices``; refused naming ``name`` otherwise."""
    if not isinstance(value, str) or value not in choices:
        raise InputError(name, f"must be one of {', '.join(choices)}, got {value!r}")
    return value


def number(value: Any, name: str, lo: float, hi: float, what: str) -> float:
    """A plain finite number within [lo, hi] (dimensionless)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or not lo <= value <= hi:
        raise InputError(name, f"must be {what} from {lo:g} to {hi:g}, got {value!r}")
    return float(value)
