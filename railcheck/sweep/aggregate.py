"""What a sweep aggregates while its rows stream to disk: per kind the counts, the worst
setting, the motor envelope and the maps' arrays (:class:`Aggregate`, built chunk by chunk),
and summary.json (:func:`summary_of`).

Everything at the sweep's first speed unless stated; lengths in m in the summary.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path

import numpy as np

from railcheck.components.ratings import COMPONENTS
from railcheck.components.sizing import screw_choices
from railcheck.studies.hypotheses import MOTOR_ESTIMATE_2013_NM, hypotheses
from railcheck.sweep.grid import BARS, narrowed, rig_grid
from railcheck.sweep.inputs import SweepInput

REASON_ORDER = (
    "assembly",
    "grashof",
    "crank_shorter_than_coupler",
    "transmission_angle",
    "crank_rail_collision",
    "joints_on_rails",
    "hole_grid",
)


class Aggregate:
    """Streaming statistics of one kind's rows at the first speed."""

    def __init__(self, inputs: SweepInput, kind: str, lengths: dict, motor_speeds: np.ndarray | None = None, models=None):

        self.inputs, self.kind, self.bars = inputs, kind, BARS[kind]
        self.first_speed = inputs.sweep.speeds[0] / (2 * math.pi)
        self.grid = narrowed(rig_grid(inputs.geometry)[kind], inputs.sweep.ranges)
        self.counts = {
            "settings_total": int(lengths["crank"].size),
            "settings_assemblable": 0,
            "settings_revolving": 0,
            "settings_passing_checks": 0,
            "settings_passing": 0,
        }
        self.passing_by_speed: dict[str, int] = {}
        self.worst: dict[str, object] | None = None
        self.motor: dict[str, object] | None = None
        self.min_safe: dict[str, object] | None = None
        self.min_life: dict[str, object] | None = None
        shape = tuple(v.size for v in self.grid.values())
        self.util = np.full(shape, np.nan)  # per grid setting: utilisation at the first speed
        self.safe = np.full(shape, np.nan)  # Hz
        self.safe_dynamic = np.zeros(shape, dtype=bool)  # the safe speed is set by the dynamic amplification
        self.safe_criteria: dict[str, int] = {}  # criterion -> settings whose safe speed it sets
        self.torque = np.full(shape, np.nan)  # N m, peak motor torque
        self.reaction = np.full(shape, np.nan)  # N, the largest peak joint reaction
        self.reason = np.full(shape, -1, dtype=np.int8)
        self.motor_sizing = MotorSizing(inputs.sweep.speeds, motor_speeds)
        models = models or {}
        #: parts whose loads depend on the setting get a map each; constant-load parts are listed
        self.constant_parts = [n for n, m in models.items() if m.constant is not None]
        self.part_util = {n: np.full(shape, np.nan) for n, m in models.items() if m.constant is None}
        #: the largest of the listed components' utilisations (None: the scene lists none)
        listed = inputs.components.listed if inputs.components is not None else ()
        self.component_util = np.full(shape, np.nan) if listed else None
        #: screw group -> {smallest screw that passes: settings} over the settings checked
        self.screw_needs: dict[str, dict[str, int]] = {}
        #: "shaft-O2_diameter", "bearings-O4_spacing" -> the largest (m) a setting checked needs
        self.shaft_needs: dict[str, float] = {}

    def add(self, col: dict, curve: dict | None = None) -> None:
        self.motor_sizing.add(col, curve, self._lengths)
        for speed in np.unique(col["speed_Hz"]):
            sel = col["speed_Hz"] == speed
            key = f"{speed:.6g}"
            self.passing_by_speed[key] = self.passing_by_speed.get(key, 0) + int(np.sum(col["verdict"][sel] == "pass"))
        first = np.isclose(col["speed_Hz"], self.first_speed, rtol=1e-12)
        c = {k: v[first] for k, v in col.items()}
        ok = c["checks_passed"]
        self.counts["settings_assemblable"] += int(np.sum(c["check_assembly"]))
        self.counts["settings_revolving"] += int(np.sum(np.isfinite(c["torque_peak_Nm"])))
        self.counts["settings_passing_checks"] += int(np.sum(ok))
        self.counts["settings_passing"] += int(np.sum(c["verdict"] == "pass"))
        self._extremes(c, ok)
        self._maps(c)
        self._screw_needs(c, ok)
        self._shaft_needs(c, ok)

    def _shaft_needs(self, c: dict, ok: np.ndarray) -> None:
        """The largest shaft diameter and bearing spacing (m) a checked setting needs."""
        for key in (k for k in c if k.endswith(("_diameter_needed_mm", "_spacing_needed_mm"))):
            d = c[key][ok & ~np.isnan(c[key])]
            if d.size:
                name = key[: -len("_needed_mm")]  # "shaft-O2_diameter", "bearings-O4_spacing"
                self.shaft_needs[name] = max(self.shaft_needs.get(name, 0.0), float(d.max()) / 1e3)

    def _screw_needs(self, c: dict, ok: np.ndarray) -> None:
        for key in (k for k in c if k.endswith("_needs")):
            counts = self.screw_needs.setdefault(key[: -len("_needs")], {})
            needed, n = np.unique(c[key][ok & (c[key] != "")].astype(str), return_counts=True)
            for screw, k in zip(needed.tolist(), n.tolist()):
                counts[screw] = counts.get(screw, 0) + int(k)

    def _lengths(self, c: dict, i: int) -> dict:
        return {b: float(c[f"{b}_mm"][i]) / 1e3 for b in self.bars}

    def _extremes(self, c: dict, ok: np.ndarray) -> None:
        u = np.where(ok & np.isfinite(c["utilisation"]), c["utilisation"], -np.inf)
        if u.size and np.isfinite(u.max()) and (self.worst is None or u.max() > self.worst["utilisation"]):
            i = int(np.argmax(u))
            self.worst = {
                "lengths_m": self._lengths(c, i),
                "part": str(c["governing_part"][i]),
                "criterion": str(c["governing_criterion"][i]),
                "utilisation": float(u[i]),
            }
        t = np.where(ok & np.isfinite(c["torque_peak_Nm"]), c["torque_peak_Nm"], -np.inf)
        if t.size and np.isfinite(t.max()) and (self.motor is None or t.max() > self.motor["torque_peak_Nm"]):
            i = int(np.argmax(t))
            self.motor = {
                "lengths_m": self._lengths(c, i),
                "torque_peak_Nm": float(t[i]),
                "torque_rms_Nm": float(c["torque_rms_Nm"][i]),
                "power_peak_W": float(c["power_peak_W"][i]),
            }
        for crit in c["safe_speed_criterion"][ok & np.isfinite(c["safe_speed_Hz"])]:
            self.safe_criteria[str(crit)] = self.safe_criteria.get(str(crit), 0) + 1
        s = np.where(ok & ~np.isnan(c["safe_speed_Hz"]), c["safe_speed_Hz"], np.inf)
        if s.size and np.isfinite(s.min()) and (self.min_safe is None or s.min() < self.min_safe["safe_speed_Hz"]):
            i = int(np.argmin(s))
            self.min_safe = {
                "lengths_m": self._lengths(c, i),
                "safe_speed_Hz": float(s[i]),
                "part": str(c["safe_speed_part"][i]),  # what reaches utilisation 1 at that speed
                "criterion": str(c["safe_speed_criterion"][i]),
            }
        life = np.where(ok & ~np.isnan(c["bearing_life_h"]), c["bearing_life_h"], np.inf)
        if life.size and np.isfinite(life.min()) and (self.min_life is None or life.min() < self.min_life["hours"]):
            i = int(np.argmin(life))
            self.min_life = {
                "lengths_m": self._lengths(c, i),
                "hours": float(life[i]),
                "static_safety": float(c["bearing_static_safety"][i]),
            }

    def _maps(self, c: dict) -> None:
        index = []
        on_grid = np.ones(c["setting"].size, dtype=bool)
        for b in self.bars:
            values = self.grid[b]
            x = c[f"{b}_mm"] / 1e3
            k = np.clip(np.searchsorted(values, x - 1e-9), 0, max(values.size - 1, 0))
            on_grid &= (np.abs(values[k] - x) < 1e-9) if values.size else False
            index.append(k)
        idx = tuple(k[on_grid] for k in index)
        self.util[idx] = np.where(c["checks_passed"][on_grid], c["utilisation"][on_grid], np.nan)
        self.safe[idx] = np.where(c["checks_passed"][on_grid], c["safe_speed_Hz"][on_grid], np.nan)
        self.safe_dynamic[idx] = c["checks_passed"][on_grid] & (c["safe_speed_criterion"][on_grid] == "dynamic")
        for name, grid in self.part_util.items():
            grid[idx] = np.where(c["checks_passed"][on_grid], c[f"{name}_utilisation"][on_grid], np.nan)
        columns = [c[f"{n}_utilisation"][on_grid] for n in COMPONENTS if f"{n}_utilisation" in c]
        if self.component_util is not None and columns:
            largest = functools.reduce(np.fmax, columns)
            self.component_util[idx] = np.where(c["checks_passed"][on_grid], largest, np.nan)
        ok = c["checks_passed"][on_grid]
        self.torque[idx] = np.where(ok, c["torque_peak_Nm"][on_grid], np.nan)
        peaks = [c[k][on_grid] for k in c if k.startswith("peak_") and k.endswith("_N")]
        self.reaction[idx] = np.where(ok, functools.reduce(np.fmax, peaks), np.nan)
        reasons = np.full(on_grid.sum(), -1, dtype=np.int8)
        for r, name in reversed(list(enumerate(REASON_ORDER))):
            key = f"check_{name}"
            if key in c:
                reasons = np.where(~c[key][on_grid], r, reasons)
        self.reason[idx] = reasons

    def summary(self) -> dict:
        return {
            **self.counts,
            "settings_passing_by_speed_Hz": self.passing_by_speed,
            "worst": self.worst,
            "max_motor_torque_Nm": self.motor["torque_peak_Nm"] if self.motor else None,
            "motor": self.motor,
            "lowest_safe_speed": self.min_safe,
            "safe_speed_criteria": dict(sorted(self.safe_criteria.items())),
            "motor_sizing": self.motor_sizing.summary(),
            "shortest_bearing_life": self.min_life,
            "screw_needs": {name: self._screw_need_summary(counts) for name, counts in self.screw_needs.items()},
            "sizes_needed_m": dict(self.shaft_needs),  # the largest over the settings checked
        }

    def _screw_need_summary(self, counts: dict[str, int]) -> dict:
        """The settings per smallest passing screw, smallest first, and the one screw that
        passes at every setting checked (``"none"``: some setting has none)."""
        order = [" ".join(c) for c in screw_choices(self.inputs.component_spec)] + ["none"]
        ranked = sorted(counts, key=lambda screw: order.index(screw) if screw in order else len(order))
        return {"settings": {screw: counts[screw] for screw in ranked}, "every_setting": ranked[-1] if ranked else None}


class MotorSizing:
    """What a motor must deliver, streamed chunk by chunk: at each listed speed the
    largest peak torque, RMS torque and peak power over the settings that pass every check
    there; at each setting's own safe speed the largest of the same; and the curve of
    required torque against speed: at each curve speed the largest over the settings that
    pass the configuration checks and are still safe at that speed (``curve``: what the
    rig's safe settings ask, capped by whatever limits their speed), and over every setting
    that passes the configuration checks whatever its verdict (``demand``: what a motor must
    give to drive them all). N m, W, Hz."""

    QUANTITIES = ("torque_peak_Nm", "torque_rms_Nm", "power_peak_W")

    def __init__(self, speeds, curve_speeds: np.ndarray | None):
        self.speeds_hz = [w / (2 * math.pi) for w in speeds]
        self.curve_hz = np.zeros(0) if curve_speeds is None else curve_speeds / (2 * math.pi)
        self.by_speed: dict[str, dict] = {f"{v:.6g}": {} for v in self.speeds_hz}
        self.at_safe: dict = {}
        self.curve = {q: np.full(self.curve_hz.size, -np.inf) for q in self.QUANTITIES}  # -inf: no setting
        self.curve_settings = np.zeros(self.curve_hz.size, dtype=np.int64)
        self.demand = {q: np.full(self.curve_hz.size, -np.inf) for q in self.QUANTITIES}

    def add(self, col: dict, curve: dict | None, lengths_of) -> None:
        for v in self.speeds_hz:
            sel = np.isclose(col["speed_Hz"], v, rtol=1e-12) & (col["verdict"] == "pass")
            self._keep(self.by_speed[f"{v:.6g}"], col, sel, "", lengths_of)
        first = np.isclose(col["speed_Hz"], self.speeds_hz[0], rtol=1e-12)
        c = {k: v[first] for k, v in col.items()}
        safe_known = c["checks_passed"] & np.isfinite(c["torque_peak_at_safe_Nm"])
        self._keep(self.at_safe, c, safe_known, "_at_safe", lengths_of, with_safe=True)
        if curve is None or not self.curve_hz.size:
            return
        rows = curve["rows"]  # the settings that pass the configuration checks: the curve's rows
        safe = c["safe_speed_Hz"][rows]
        safe = np.where(np.isnan(safe), np.inf, safe)  # no FE: no speed limit known
        running = self.curve_hz[None, :] <= safe[:, None]  # (rows, G)
        self.curve_settings += running.sum(axis=0)
        for q in self.QUANTITIES:
            known = np.isfinite(curve[q])
            values = np.where(running & known, curve[q], -np.inf)
            self.curve[q] = np.maximum(self.curve[q], values.max(axis=0, initial=-np.inf))
            every = np.where(known, curve[q], -np.inf)
            self.demand[q] = np.maximum(self.demand[q], every.max(axis=0, initial=-np.inf))

    def _keep(self, best: dict, c: dict, sel: np.ndarray, suffix: str, lengths_of, with_safe=False) -> None:
        """Keep in ``best`` the largest of each quantity over the rows ``sel`` and where it is."""
        for q in self.QUANTITIES:
            key = q.replace("_Nm", f"{suffix}_Nm").replace("_W", f"{suffix}_W")
            values = np.where(sel, c[key], -np.inf)
            if not values.size or not np.isfinite(values.max()):
                continue
            i = int(np.argmax(values))
            if q not in best or values[i] > best[q]["value"]:
                best[q] = {"value": float(values[i]), "lengths_m": lengths_of(c, i)}
                if with_safe:
                    best[q]["safe_speed_Hz"] = float(c["safe_speed_Hz"][i])

    def summary(self) -> dict:
        return {
            "estimate_2013_Nm": MOTOR_ESTIMATE_2013_NM,
            "at_listed_speeds": {k: {q: v[q] for q in self.QUANTITIES if q in v} for k, v in self.by_speed.items()},
            "at_safe_speed": {q: self.at_safe[q] for q in self.QUANTITIES if q in self.at_safe},
            "curve": {
                "speed_Hz": [float(v) for v in self.curve_hz],
                "settings": [int(v) for v in self.curve_settings],
                **{q: [None if not np.isfinite(v) else float(v) for v in self.curve[q]] for q in self.QUANTITIES},
                **{
                    f"demand_{q}": [None if not np.isfinite(v) else float(v) for v in self.demand[q]]
                    for q in self.QUANTITIES
                },
            },
        }


def summary_of(inputs: SweepInput, aggregates: dict, tables: dict, models: dict) -> dict:
    """summary.json (deterministic: no timings)."""

    grid, spec = rig_grid(inputs.geometry), inputs.sweep
    out = {
        "grid": {kind: {f"{b}_m": [float(x) for x in v] for b, v in grid[kind].items()} for kind in grid},
        "ranges_m": {b: list(r) for b, r in spec.ranges.items()},
        "speeds_Hz": [w / (2 * math.pi) for w in spec.speeds],
        "steps": spec.steps,
        "assembly": spec.assembly,
        "effects": list(inputs.requested_effects),
        "parts": {kind: list(m) for kind, m in models.items()},
        "by_kind": {kind: a.summary() for kind, a in aggregates.items()},
        "tables": {kind: Path(p).name for kind, p in tables.items()},
    }
    if "four-bar" in tables:
        out["seed_hypotheses"] = hypotheses(tables["four-bar"], spec.speeds[0] / (2 * math.pi))
    out["scene_source"] = inputs.source
    return out
