"""One setting's card for the lab: its verdict, the speed up to which it is safe and what
sets it, the motor's peak torque and power, and every criterion's utilisation, read from a
sweep's table when it holds the setting (milliseconds: one filtered scan of the Parquet or
CSV file) or computed by a check of the built-in scene at that setting.

A card from the table and one from the check of the same setting agree to the sweep's
own agreement with a check (the same models; the sweep's steps): tested in
``tests/test_lookup.py``. Lengths in m inside; the card's words in mm, Hz, N m, W."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from railcheck.base.errors import InputError
from railcheck.sweep.grid import BARS
from railcheck.sweep.table import read_table

#: two lengths within this (m) are the same hole-grid setting (the table holds mm floats)
SAME_LENGTH = 1e-6


@dataclass(frozen=True)
class Card:
    """One setting at one speed: ``source`` (the table's path or "check"), ``lengths_m``
    bar -> m, ``speed_hz``, ``verdict`` ("PASS"/"FAIL"), ``reason`` (what fails, "" when
    none), ``safe_speed_hz`` (inf: no limit; 0: fails at rest; NaN: not evaluated, a
    configuration check fails or the crank stands still) with ``safe_set_by`` and
    ``safe_criterion``, the motor's ``torque_peak_Nm`` and ``power_peak_W`` at
    ``speed_hz``, and ``utilisations`` part or component -> share of its limit."""

    source: str
    kind: str
    lengths_m: dict
    speed_hz: float
    verdict: str
    reason: str
    safe_speed_hz: float
    safe_set_by: str
    safe_criterion: str
    torque_peak_Nm: float
    power_peak_W: float
    utilisations: dict = field(default_factory=dict)


def parse_setting(text: str) -> tuple[str, dict]:
    """(kind, bar -> m) of "480/840/780/1020" (a four-bar's crank/coupler/rocker/ground,
    mm) or "300/900/0" (a slider-crank's crank/coupler/offset, mm)."""
    parts = text.replace(" ", "").split("/")
    kind = {4: "four-bar", 3: "slider-crank"}.get(len(parts))
    if kind is None:
        raise InputError("setting", f"give crank/coupler/rocker/ground or crank/coupler/offset in mm, got {text!r}")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise InputError("setting", f"lengths are numbers of mm separated by '/', got {text!r}") from None
    if not all(math.isfinite(v) for v in values) or any(v <= 0 for v in values[: 4 if kind == "four-bar" else 2]):
        raise InputError("setting", f"bar lengths must be positive and finite mm, got {text!r}")
    return kind, {bar: v * 1e-3 for bar, v in zip(BARS[kind], values)}


def table_path(directory: Path, kind: str) -> Path | None:
    """The sweep table of ``kind`` in ``directory`` (Parquet or CSV), or None."""
    for suffix in ("parquet", "csv"):
        path = Path(directory) / f"sweep-{kind}.{suffix}"
        if path.is_file():
            return path
    return None


def cards_from_table(path: Path, kind: str, lengths_m: dict, speed_hz: float | None = None) -> list[Card]:
    """The table's cards of the setting ``lengths_m`` (one per speed, or at ``speed_hz``
    only), empty when the table does not hold it."""
    try:
        table = read_table(path, speed_hz=speed_hz)
        rows = {name: np.asarray(table.column(name).to_numpy(zero_copy_only=False)) for name in table.column_names}
        if not rows or rows["setting"].size == 0:
            return []
        match = np.ones(rows["setting"].size, dtype=bool)
        for bar, value in lengths_m.items():
            match &= np.abs(rows[f"{bar}_mm"] * 1e-3 - value) <= SAME_LENGTH
        return [_card_of_row(str(path), kind, lengths_m, {k: v[i] for k, v in rows.items()}) for i in np.flatnonzero(match)]
    except (OSError, ValueError, KeyError, TypeError) as exc:  # pyarrow's ArrowInvalid is a ValueError
        raise InputError(
            "--sweep", f"{path} is not a readable sweep table ({type(exc).__name__}): run railcheck sweep again"
        ) from None


def _card_of_row(source: str, kind: str, lengths_m: dict, row: dict) -> Card:
    uses = {k[: -len("_utilisation")]: float(v) for k, v in row.items() if k.endswith("_utilisation") and k != "utilisation"}
    safe = float(row["safe_speed_Hz"]) if np.isfinite(row["safe_speed_Hz"]) else math.inf
    if not bool(row["checks_passed"]):  # a configuration check fails: nothing else evaluated
        safe = math.nan
    return Card(
        source,
        kind,
        lengths_m,
        float(row["speed_Hz"]),
        "PASS" if str(row["verdict"]).lower() == "pass" else "FAIL",
        str(row["reason"]) if str(row["verdict"]).lower() != "pass" else "",
        safe,
        str(row["safe_speed_part"]),
        str(row["safe_speed_criterion"]),
        float(row["torque_peak_Nm"]),
        float(row["power_peak_W"]),
        {k: v for k, v in uses.items() if math.isfinite(v)},
    )


def card_from_check(result, summary: dict, kind: str, lengths_m: dict) -> Card:
    """The card of a finished check (``railcheck.check``'s result and summary)."""
    scene = result.scene
    hz = scene.mechanism.speed / (2 * math.pi)
    torque = float(summary.get("kinematics", {}).get("peak_torque_Nm", math.nan))
    safe = result.safe_speed
    uses = {n: float(p["utilisation"]) for n, p in summary["parts"].items()}
    uses |= {n: float(c["utilisation"]) for n, c in summary["components"].items()}
    return Card(
        "check",
        kind,
        lengths_m,
        hz,
        summary["verdict"],
        "; ".join(result.failures),
        safe.hz if safe is not None else math.nan,
        safe.component if safe is not None else "",
        safe.criterion if safe is not None else "",
        torque,
        torque * scene.mechanism.speed,  # constant crank speed: P = T omega at every instant
        uses,
    )
