"""The 2013 design study's hypotheses (seed 000, chapter 3.3), each stated true, false or
not tested on a sweep's four-bar table at its first speed ("reaction": the largest peak
joint reaction of a setting). "Settings that pass" are those that pass the configuration
checks (assembly, Grashof, transmission angle, the hole grid...): the valid configurations
among which the study hunted for the largest reactions, whatever the parts' and components'
verdicts. Lengths in mm as the table's columns.
"""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np

from railcheck.sweep.table import read_table
from railcheck.units import for_people

#: the 2013 design study's motor estimate (its conclusion: at least 200 N·m)
MOTOR_ESTIMATE_2013_NM = 200.0


def _revolving_family(t: dict, **fixed) -> np.ndarray:
    sel = np.isfinite(t["reaction"])
    for bar, mm in fixed.items():
        sel &= np.isclose(t[f"{bar}_mm"], mm)
    return sel


def hypotheses(path: Path, speed_hz: float) -> list[dict]:
    """Seed 000 chapter 3.3's hypotheses, each true or false on this table's four-bar
    rows at ``speed_hz`` ("reaction": the largest peak joint reaction of a setting)."""

    cols = [
        "crank_mm",
        "coupler_mm",
        "rocker_mm",
        "ground_mm",
        "speed_Hz",
        "checks_passed",
        "peak_O2_N",
        "peak_A_N",
        "peak_B_N",
        "peak_O4_N",
        "torque_peak_Nm",
    ]
    table = read_table(path, cols, speed_hz)
    t = {
        k: np.asarray(v.to_numpy(zero_copy_only=False), dtype=float if k != "checks_passed" else bool)
        for k, v in zip(cols, table.columns)
    }
    t["reaction"] = functools.reduce(np.fmax, [t[f"peak_{j}_N"] for j in ("O2", "A", "B", "O4")])
    return [
        _h1_longer_rocker_and_ground(t),
        _h2_longer_coupler(t),
        _h32_longer_crank_when_passing(t),
        _smallest(t),
        _final(t),
    ]


def _verdict(hid: str, statement: str, holds, evidence: str) -> dict:
    return {"id": hid, "statement": statement, "holds": None if holds is None else bool(holds), "evidence": evidence}


#: seed 000's final design (3.3.6, "CUMPLE Y MONTABLE"), bar lengths in mm
FINAL_DESIGN_MM = {"crank": 480.0, "coupler": 840.0, "rocker": 780.0, "ground": 1020.0}
NOT_SWEPT = "not in this sweep: no revolving setting of its family"


def _h1_longer_rocker_and_ground(t: dict) -> dict:
    sel = _revolving_family(t, crank=180, coupler=240) & np.isclose(t["rocker_mm"], t["ground_mm"])
    x, r = t["rocker_mm"][sel], t["reaction"][sel]
    order = np.argsort(x)
    holds = bool(np.all(np.diff(r[order]) < 0)) if x.size > 1 else None
    statement = "crank 180 mm, coupler 240 mm, rocker = ground: the longer rocker and ground, the smaller the reactions"
    if not x.size:
        return _verdict("3.3.2 H1", statement, None, NOT_SWEPT)
    return _verdict(
        "3.3.2 H1", statement, holds, f"{x.size} revolving settings, rocker = ground {_span(x)} mm; reaction {_trend(x, r)}"
    )


def _h2_longer_coupler(t: dict) -> dict:
    sel = _revolving_family(t, crank=180, rocker=720, ground=720)
    x, r = t["coupler_mm"][sel], t["reaction"][sel]
    base = r[np.isclose(x, 240)]
    longer = r[x > 240]
    holds = bool(np.all(longer < base[0])) if base.size and longer.size else None
    statement = (
        "crank 180 mm, rocker = ground = 720 mm: every coupler longer than 240 mm gives smaller reactions than 240 mm"
    )
    if not base.size or not longer.size:
        return _verdict("3.3.2 H2", statement, None, NOT_SWEPT + " (coupler 240 mm and a longer one)")
    return _verdict(
        "3.3.2 H2",
        statement,
        holds,
        f"{x.size} revolving settings, coupler {_span(x)} mm; reaction at 240 mm {base[0]:.1f} N, "
        f"largest beyond {longer.max():.1f} N",
    )


def _h32_longer_crank_when_passing(t: dict) -> dict:
    ok = t["checks_passed"] & np.isfinite(t["reaction"])
    cranks = np.unique(t["crank_mm"][ok])
    worst = np.array([t["reaction"][ok & np.isclose(t["crank_mm"], c)].max() for c in cranks])
    holds = bool(np.all(np.diff(worst) > 0)) if cranks.size > 1 else None
    statement = "among settings that pass the configuration checks, the longer the crank, the larger the largest reaction"
    if cranks.size < 2:
        return _verdict(
            "3.3.5 H3.2", statement, None, "not in this sweep: fewer than two crank lengths pass the configuration checks"
        )
    return _verdict(
        "3.3.5 H3.2",
        statement,
        holds,
        "largest reaction per crank: " + ", ".join(f"{c:.0f} mm {w:.0f} N" for c, w in zip(cranks, worst)),
    )


def _smallest(t: dict) -> dict:
    ok = t["checks_passed"]
    if not np.any(ok):
        return _verdict("3.3.3", "the smallest mechanism has the largest reactions", None, "no setting passes")
    size = (t["crank_mm"] + t["coupler_mm"] + t["rocker_mm"] + t["ground_mm"])[ok]
    r = t["reaction"][ok]
    i = int(np.argmax(r))
    return _verdict(
        "3.3.3",
        "among settings that pass the configuration checks, the smallest mechanism (least total bar length) has the "
        "largest reactions",
        bool(np.isclose(size[i], size.min())),
        f"largest reaction {r[i]:.1f} N at total length {size[i]:.0f} mm; smallest total {size.min():.0f} mm",
    )


def _final(t: dict) -> dict:
    ok = t["checks_passed"]
    if not np.any(ok):
        return _verdict(
            "3.3.6",
            "480/840/780/1020 mm has the largest reactions of the settings that pass the configuration checks",
            None,
            "no setting passes",
        )
    i = int(np.argmax(np.where(ok, t["reaction"], -np.inf)))
    name = "/".join(f"{t[f'{b}_mm'][i]:.0f}" for b in ("crank", "coupler", "rocker", "ground"))
    torque = np.nanmax(np.where(ok, t["torque_peak_Nm"], np.nan))
    return _verdict(
        "3.3.6",
        "480/840/780/1020 mm has the largest reactions of the settings that pass the configuration checks",
        name == "480/840/780/1020",
        f"largest: {name} mm with {t['reaction'][i]:.1f} N; largest peak motor torque of those "
        f"settings {for_people(torque, '.1f', missing='not computed')} N·m (the seed asks for a motor of at least 200 N·m)",
    )


def _span(x: np.ndarray) -> str:
    return f"{x.min():.0f}-{x.max():.0f}" if x.size else "none"


def _trend(x: np.ndarray, r: np.ndarray) -> str:
    if x.size < 2:
        return "not enough settings"
    order = np.argsort(x)
    return f"{r[order][0]:.1f} N -> {r[order][-1]:.1f} N"
