"""pandas frames of a check's parts and components and of a sweep's settings (the
optional extra ``pip install "railcheck[frames]"``): one row per part, component or
setting and speed, columns in snake case with their units in their names (``stress_MPa``,
``tip_deflection_mm``, ``crank_rail_utilisation``), so attribute access works
(``frame.stress_MPa``). Built from ``summary.json``'s records and the sweep's tables:
the same figures, converted at this edge to the report's units (MPa, mm)."""

from __future__ import annotations

import re

from railcheck.base.errors import InputError

#: what a column name may hold: letters, digits and underscores
_NOT_A_NAME = re.compile(r"[^0-9A-Za-z_]+")


def column_name(name: str) -> str:
    """``name`` as a pandas column that attribute access reaches: every run of characters
    other than letters, digits and "_" ("-", " ", ".") one "_"; a unit's case kept
    ("crank-rail_stress_MPa" -> "crank_rail_stress_MPa")."""
    return _NOT_A_NAME.sub("_", name).strip("_")


def _scaled(value, factor: float) -> float:
    """``value`` x ``factor``, NaN where summary.json has no figure (null: a free body's
    tip, an unlimited factor)."""
    return float("nan") if value is None else float(value) * factor


def _pandas():
    try:
        import pandas
    except ImportError:
        raise InputError("frames", 'pandas is not installed: pip install "railcheck[frames]"') from None
    return pandas


def _verdict_columns(record: dict) -> dict:
    """A summary record's utilisation, what governs, whether it passes, and each
    criterion's utilisation as ``<criterion>_utilisation``."""
    out = {"utilisation": record["utilisation"], "governs": record["governing_criterion"], "passed": bool(record["pass"])}
    return out | {column_name(f"{k}_utilisation"): u for k, u in record["utilisation_by_criterion"].items()}


def parts_frame(summary: dict):
    """One row per checked part (``summary.json``'s ``parts``): its peak von Mises, limit,
    fatigue factor, tip and largest deflection, each criterion's utilisation, what governs,
    and whether it passes."""
    rows = [
        {
            "part": name,
            "stress_MPa": _scaled(p.get("max_von_mises_Pa"), 1e-6),
            "limit_MPa": _scaled(p.get("limit_Pa"), 1e-6),
            "fatigue_factor": _scaled((p.get("fatigue") or {}).get("min_safety_factor"), 1.0),
            "tip_deflection_mm": _scaled(p.get("tip_deflection_m"), 1e3),
            "max_deflection_mm": _scaled(p.get("max_deflection_m"), 1e3),
        }
        | _verdict_columns(p)
        for name, p in summary.get("parts", {}).items()
    ]
    return _pandas().DataFrame(rows)


def components_frame(summary: dict):
    """One row per checked component (``summary.json``'s ``components``): its kind, joint,
    standard, each criterion's utilisation, what governs, and whether it passes."""
    rows = [
        {"component": name, "kind": c["kind"], "joint": c["joint"], "standard": c["standard"]} | _verdict_columns(c)
        for name, c in summary.get("components", {}).items()
    ]
    return _pandas().DataFrame(rows)


def settings_frame(table):
    """A sweep's ``pyarrow.Table`` (one row per setting and speed) as a frame, its columns
    renamed by :func:`column_name`."""
    _pandas()
    frame = table.to_pandas()
    return frame.rename(columns={c: column_name(c) for c in frame.columns})
