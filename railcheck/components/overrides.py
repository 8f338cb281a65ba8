"""The scene's ``[components]`` table read into a
:class:`~railcheck.components.ratings.ComponentSpec` (SI), each key checked against its
quantity and physical range, the spec refused when it cannot be built."""

from __future__ import annotations

import dataclasses
import math

from railcheck.base.errors import InputError
from railcheck.components.ratings import (
    CHOICES,
    COMPONENT_SPEC,
    FROM_GEOMETRY,
    OVERRIDABLE,
    ComponentSpec,
    refuse_impossible,
)
from railcheck.ranges import did_you_mean, in_range
from railcheck.units import parse_quantity

#: the range a [components] quantity is checked against, where its ranges key differs
COMPONENT_RANGES = {"length": "geometry", "stress": "limit", "number": "factor", "screw_embedding": "embedding"}
#: [components] lengths that may be zero (the joint's line on the screws' centroid)
COMPONENT_ZERO_ALLOWED = frozenset({"screw_eccentricity"})


def component_overrides(table: dict) -> dict[str, float | str]:
    """The ``[components]`` overrides (SI): each key a field of
    :class:`railcheck.components.ratings.ComponentSpec`, a quantity with its unit (a plain
    positive number for factors, frictions and required safeties; a name for a screw's
    size and class)."""
    out: dict[str, float | str] = {}
    for key, value in table.items():
        field = f"components.{key}"
        if key not in OVERRIDABLE:
            raise InputError(field, f"unknown key{did_you_mean(key, tuple(OVERRIDABLE))}")
        dimension = OVERRIDABLE[key]
        if dimension == "choice":
            if value not in CHOICES[key]:
                raise InputError(field, f"must be one of {', '.join(map(repr, CHOICES[key]))}, got {value!r}")
            out[key] = value
            continue
        if dimension == "number":
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
                raise InputError(field, f"must be a positive number, got {value!r}")
            out[key] = float(value)
        else:
            zero = key in COMPONENT_ZERO_ALLOWED
            out[key] = parse_quantity(value, dimension, field, positive=True, allow_zero=zero)
            if zero and out[key] == 0.0:
                continue
        in_range(float(out[key]), COMPONENT_RANGES.get(key, COMPONENT_RANGES.get(dimension, dimension)), field)
    return out


def component_spec(table: dict, rail) -> ComponentSpec:
    """The components' spec: the defaults, the holes of ``rail`` (the scene's
    :class:`~railcheck.geometry.catalogue.RailSpec`, its ``[geometry]`` applied), the
    ``[components]`` overrides ``table``; refused in one line when it cannot be built."""
    holes = {name: getattr(rail, attr) for name, attr in FROM_GEOMETRY.items()}
    values: dict = {**holes, **component_overrides(table)}
    spec = dataclasses.replace(COMPONENT_SPEC, **values)
    refuse_impossible(spec)
    return spec
