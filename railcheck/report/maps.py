"""What a sweep reports: per kind the counts, the worst setting, the motor envelope and
the maps (:class:`Aggregate`, built chunk by chunk while the rows stream to disk), and
seed 000's hypotheses of chapter 3.3 stated true or false from the table.

Everything at the sweep's first speed unless stated; lengths in m in the summary.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path

import numpy as np

from railcheck.files import atomic_path
from railcheck.sweep.grid import BARS, narrowed, rig_grid
from railcheck.sweep.table import read_table
from railcheck.units import for_people

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

    def __init__(self, scene, kind: str, lengths: dict, motor_speeds: np.ndarray | None = None, models=None):

        self.scene, self.kind, self.bars = scene, kind, BARS[kind]
        self.first_speed = scene.sweep.speeds[0] / (2 * math.pi)
        self.grid = narrowed(rig_grid(scene.geometry)[kind], scene.sweep.ranges)
        self.counts = {
            "settings_total": int(lengths["crank"].size),
            "settings_assemblable": 0,
            "settings_revolving": 0,
            "settings_passing_checks": 0,
            "settings_passing": 0,
        }
        self.passing_by_speed = {}
        self.worst = None
        self.motor = None
        self.min_safe = None
        self.min_life = None
        shape = tuple(v.size for v in self.grid.values())
        self.util = np.full(shape, np.nan)  # per grid setting: utilisation at the first speed
        self.safe = np.full(shape, np.nan)  # Hz
        self.safe_dynamic = np.zeros(shape, dtype=bool)  # the safe speed is set by the dynamic amplification
        self.safe_criteria: dict[str, int] = {}  # criterion -> settings whose safe speed it sets
        self.torque = np.full(shape, np.nan)  # N m, peak motor torque
        self.reaction = np.full(shape, np.nan)  # N, the largest peak joint reaction
        self.reason = np.full(shape, -1, dtype=np.int8)
        self.motor_sizing = MotorSizing(scene.sweep.speeds, motor_speeds)
        models = models or {}
        #: parts whose loads depend on the setting get a map each; constant-load parts are listed
        self.constant_parts = [n for n, m in models.items() if m.constant is not None]
        self.part_util = {n: np.full(shape, np.nan) for n, m in models.items() if m.constant is None}

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
        }


#: the 2013 design study's motor estimate (its conclusion: at least 200 N·m)
MOTOR_ESTIMATE_2013_NM = 200.0


class MotorSizing:
    """What a motor must deliver, streamed chunk by chunk: at each listed speed the
    largest peak torque, RMS torque and peak power over the settings that pass every check
    there; at each setting's own safe speed the largest of the same; and the curve of
    required torque against speed (at each curve speed, the largest over the settings that
    pass the configuration checks and are still safe at that speed). N m, W, Hz."""

    QUANTITIES = ("torque_peak_Nm", "torque_rms_Nm", "power_peak_W")

    def __init__(self, speeds, curve_speeds: np.ndarray | None):
        self.speeds_hz = [w / (2 * math.pi) for w in speeds]
        self.curve_hz = np.zeros(0) if curve_speeds is None else curve_speeds / (2 * math.pi)
        self.by_speed = {f"{v:.6g}": {} for v in self.speeds_hz}
        self.at_safe: dict = {}
        self.curve = {q: np.full(self.curve_hz.size, -np.inf) for q in self.QUANTITIES}  # -inf: no setting
        self.curve_settings = np.zeros(self.curve_hz.size, dtype=np.int64)

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
            values = np.where(running & np.isfinite(curve[q]), curve[q], -np.inf)
            self.curve[q] = np.maximum(self.curve[q], values.max(axis=0, initial=-np.inf))

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
            },
        }


def summary_of(scene, aggregates: dict, tables: dict, models: dict) -> dict:
    """summary.json (deterministic: no timings)."""

    grid = rig_grid(scene.geometry)
    out = {
        "grid": {kind: {f"{b}_m": [float(x) for x in v] for b, v in grid[kind].items()} for kind in grid},
        "ranges_m": {b: list(r) for b, r in scene.sweep.ranges.items()},
        "speeds_Hz": [w / (2 * math.pi) for w in scene.sweep.speeds],
        "steps": scene.sweep.steps,
        "assembly": scene.sweep.assembly,
        "effects": list(scene.check.effects) if scene.check else ["inertia"],
        "parts": {kind: list(m) for kind, m in models.items()},
        "by_kind": {kind: a.summary() for kind, a in aggregates.items()},
        "tables": {kind: Path(p).name for kind, p in tables.items()},
    }
    if "four-bar" in tables:
        out["seed_hypotheses"] = hypotheses(tables["four-bar"], scene.sweep.speeds[0] / (2 * math.pi))
    out["scene_source"] = scene.source
    return out


def _family(t: dict, **fixed) -> np.ndarray:
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
    return [_h1(t), _h2(t), _h32(t), _smallest(t), _final(t)]


def _verdict(hid: str, statement: str, holds, evidence: str) -> dict:
    return {"id": hid, "statement": statement, "holds": None if holds is None else bool(holds), "evidence": evidence}


NOT_SWEPT = "not in this sweep: no revolving setting of its family"


def _h1(t: dict) -> dict:
    sel = _family(t, crank=180, coupler=240) & np.isclose(t["rocker_mm"], t["ground_mm"])
    x, r = t["rocker_mm"][sel], t["reaction"][sel]
    order = np.argsort(x)
    holds = bool(np.all(np.diff(r[order]) < 0)) if x.size > 1 else None
    statement = "crank 180 mm, coupler 240 mm, rocker = ground: the longer rocker and ground, the smaller the reactions"
    if not x.size:
        return _verdict("3.3.2 H1", statement, None, NOT_SWEPT)
    return _verdict(
        "3.3.2 H1", statement, holds, f"{x.size} revolving settings, rocker = ground {_span(x)} mm; reaction {_trend(x, r)}"
    )


def _h2(t: dict) -> dict:
    sel = _family(t, crank=180, rocker=720, ground=720)
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


def _h32(t: dict) -> dict:
    ok = t["checks_passed"] & np.isfinite(t["reaction"])
    cranks = np.unique(t["crank_mm"][ok])
    worst = np.array([t["reaction"][ok & np.isclose(t["crank_mm"], c)].max() for c in cranks])
    holds = bool(np.all(np.diff(worst) > 0)) if cranks.size > 1 else None
    statement = "among settings that pass every check, the longer the crank, the larger the largest reaction"
    if cranks.size < 2:
        return _verdict("3.3.5 H3.2", statement, None, "not in this sweep: fewer than two crank lengths pass every check")
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
        "among settings that pass every check, the smallest mechanism (least total bar length) has the largest reactions",
        bool(np.isclose(size[i], size.min())),
        f"largest reaction {r[i]:.1f} N at total length {size[i]:.0f} mm; smallest total {size.min():.0f} mm",
    )


def _final(t: dict) -> dict:
    ok = t["checks_passed"]
    if not np.any(ok):
        return _verdict(
            "3.3.6", "480/840/780/1020 mm has the largest reactions of the settings that pass", None, "no setting passes"
        )
    i = int(np.argmax(np.where(ok, t["reaction"], -np.inf)))
    name = "/".join(f"{t[f'{b}_mm'][i]:.0f}" for b in ("crank", "coupler", "rocker", "ground"))
    torque = np.nanmax(np.where(ok, t["torque_peak_Nm"], np.nan))
    return _verdict(
        "3.3.6",
        "480/840/780/1020 mm has the largest reactions of the settings that pass every check",
        name == "480/840/780/1020",
        f"largest: {name} mm with {t['reaction'][i]:.1f} N; largest peak motor torque of the settings "
        f"that pass {for_people(torque, '.1f', missing='not computed')} N·m (the seed asks for a motor of at least 200 N·m)",
    )


def _span(x: np.ndarray) -> str:
    return f"{x.min():.0f}-{x.max():.0f}" if x.size else "none"


def _trend(x: np.ndarray, r: np.ndarray) -> str:
    if x.size < 2:
        return "not enough settings"
    order = np.argsort(x)
    return f"{r[order][0]:.1f} N -> {r[order][-1]:.1f} N"


def write_maps(aggregates: dict, directory: Path) -> None:
    """``map-KIND.png``: utilisation and safe speed over pairs of bars (the worst over the
    other bars; without FE parts the largest reaction and motor torque), refused cells
    coloured by a failing check."""
    import matplotlib

    matplotlib.use("Agg")
    for kind, agg in aggregates.items():
        if agg.util.size:
            _map_figure(agg, directory / f"map-{kind}.png")


def _map_figure(agg: Aggregate, path: Path) -> None:
    """One row per map (each part whose loads depend on the setting: its utilisation at the
    first speed; then the lowest safe speed), one column per pair of bars (the worst over
    the other bars); utilisation on a scale from 0 with the utilisation-1 contour; refused
    cells coloured by their first failing check, with only the checks that occur in the
    legend; constant-load parts listed in the title."""
    import warnings

    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    pairs = [(0, 1), (2, 3)] if len(agg.bars) == 4 else [(0, 1)]
    has_fe = not np.all(np.isnan(agg.util))
    if has_fe:
        panels = [(g, np.nanmax, f"{n}: utilisation (1 = limit)", "viridis", True) for n, g in agg.part_util.items()]
        panels.append((agg.safe, np.nanmin, "lowest safe crank speed (Hz)", "viridis_r", False))
    else:  # no FE parts: the loads instead
        panels = [
            (agg.reaction, np.nanmax, "largest peak joint reaction (N)", "viridis", False),
            (agg.torque, np.nanmax, "largest peak motor torque (N·m)", "viridis", False),
        ]
    fig, axes = plt.subplots(
        len(panels), len(pairs), figsize=(max(9.0, 6.5 * len(pairs)), 3.6 * len(panels) + 1.6), squeeze=False
    )
    colours = ["#bdbdbd", "#fdae6b", "#9ecae1", "#f781bf", "#cab2d6", "#a1d99b", "#ffffb3"]  # one per REASON_ORDER
    reason_colors = ListedColormap(colours)
    for col, (a, b) in enumerate(pairs):
        others = tuple(i for i in range(len(agg.bars)) if i not in (a, b))
        reasons = np.max(agg.reason, axis=others) if others else agg.reason
        xs, ys = agg.grid[agg.bars[a]] * 1e3, agg.grid[agg.bars[b]] * 1e3
        extent = _extent(xs, ys)
        for row, (data, reduce, label, cmap, is_util) in enumerate(panels):
            ax = axes[row, col]
            with np.errstate(all="ignore"), warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                grid = reduce(data, axis=others) if others else data
            refused = np.ma.masked_where(~np.isnan(grid) | (reasons < 0), reasons)
            ax.imshow(
                refused.T,
                origin="lower",
                extent=extent,
                aspect="auto",
                cmap=reason_colors,
                vmin=0,
                vmax=len(REASON_ORDER) - 1,
                interpolation="nearest",
            )
            finite = grid[np.isfinite(grid)]
            top = max(1.0, float(finite.max())) if is_util and finite.size else (finite.max() if finite.size else 1)
            im = ax.imshow(
                np.ma.masked_invalid(grid).T,
                origin="lower",
                extent=extent,
                aspect="auto",
                cmap=cmap,
                interpolation="nearest",
                vmin=0,
                vmax=top,
            )
            fig.colorbar(im, ax=ax, label=label.split(": ")[-1])
            if is_util and finite.size and finite.min() < 1 < finite.max() and min(grid.shape) > 1:
                ax.contour(xs, ys, np.where(np.isfinite(grid), grid, 0).T, levels=[1.0], colors="red", linewidths=1.5)
            if data is agg.safe and agg.safe_dynamic.any():
                _mark_dynamic(ax, agg, others, xs, ys)
            ax.set_xlabel(f"{agg.bars[a]} (mm)")
            ax.set_ylabel(f"{agg.bars[b]} (mm)")
            over = f", worst over {' and '.join(agg.bars[i] for i in others)}" if others else ""
            ax.set_title(f"{label.split(' (')[0]}{over}", fontsize=9)
    handles = [
        Patch(color=colours[REASON_ORDER.index(r)], label=f"refused: {r.replace('_', ' ')}") for r in occurring_reasons(agg)
    ]
    if handles:
        fig.legend(handles=handles, loc="lower center", ncol=min(4, len(handles)), fontsize=8)
    note = " (red line: utilisation 1)" if has_fe else ""
    constant = (
        f"\nconstant loads, the same for every setting (not mapped): {', '.join(agg.constant_parts)}"
        if agg.constant_parts
        else ""
    )
    fig.suptitle(
        f"railcheck sweep, {agg.kind} at {agg.first_speed:g} Hz: settings that pass every configuration "
        f"check in colour{note}{constant}",
        fontsize=10,
    )
    _fixed_layout(fig, len(panels), len(pairs), bottom=1.0 if handles else 0.6)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=100)
    plt.close(fig)


#: inches around and between a map figure's panels (:func:`_fixed_layout`): left of the
#: first column (y label and ticks), right of the last colorbar, above the first row (the
#: title, two lines), between rows (a panel's x label and the next one's title), between
#: columns (a colorbar with its label and the next panel's y label)
MAP_MARGINS = {"left": 0.9, "right": 0.3, "top": 1.3, "between_rows": 0.9, "between_columns": 1.1}


def _fixed_layout(fig, rows: int, columns: int, bottom: float) -> None:
    """The map figure's panels placed by fixed margins in inches (:data:`MAP_MARGINS`;
    ``bottom`` below the last row: its x labels and the legend). The figure's layout is
    the same for every sweep (only the numbers change), so it is not measured from the
    drawn text as ``tight_layout`` does, which cost nearly half of the whole rig's maps
    (1.79 against 0.96 s for the four-bar's)."""
    width, height = fig.get_size_inches()
    m = MAP_MARGINS
    panel_w = (width - m["left"] - m["right"] - (columns - 1) * m["between_columns"]) / columns
    panel_h = (height - m["top"] - bottom - (rows - 1) * m["between_rows"]) / rows
    fig.subplots_adjust(
        left=m["left"] / width,
        right=1 - m["right"] / width,
        top=1 - m["top"] / height,
        bottom=bottom / height,
        wspace=m["between_columns"] / panel_w,
        hspace=m["between_rows"] / panel_h,
    )


def occurring_reasons(agg: Aggregate) -> list[str]:
    """The refusal reasons the map legend lists: each the first failing check (in
    :data:`REASON_ORDER`) of some refused setting on the grid."""
    return [REASON_ORDER[int(r)] for r in np.unique(agg.reason) if r >= 0]


def _mark_dynamic(ax, agg: Aggregate, others: tuple, xs: np.ndarray, ys: np.ndarray) -> None:
    """White crosses on the safe-speed panel where the lowest safe speed shown (over the
    other bars) is set by the dynamic amplification rather than by stress or fatigue."""
    safe = np.moveaxis(agg.safe, others, tuple(range(-len(others), 0))) if others else agg.safe[..., None]
    dyn = np.moveaxis(agg.safe_dynamic, others, tuple(range(-len(others), 0))) if others else agg.safe_dynamic[..., None]
    safe, dyn = safe.reshape(*safe.shape[:2], -1), dyn.reshape(*dyn.shape[:2], -1)
    filled = np.where(np.isnan(safe), np.inf, safe)
    pick = np.argmin(filled, axis=2)
    marked = np.take_along_axis(dyn, pick[..., None], axis=2)[..., 0] & np.isfinite(filled.min(axis=2))
    i, j = np.nonzero(marked)
    ax.plot(xs[i], ys[j], "x", color="white", markersize=4, label="safe speed set by dynamics")
    ax.legend(loc="upper right", fontsize=7)


def write_motor_plot(aggregates: dict, path: Path) -> None:
    """``motor.png``: per kind the peak torque a motor must deliver against crank speed
    (the largest over the settings still safe at that speed), the 2013 estimate of 200 N·m
    as a line, the listed speeds marked, and how many settings the curve covers."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.0, 5.0))
    drawn = False
    for kind, agg in aggregates.items():
        m = agg.motor_sizing
        finite = lambda v: np.where(np.isfinite(v), v, np.nan)  # noqa: E731
        torque = finite(m.curve["torque_peak_Nm"])
        if not np.any(np.isfinite(torque)):
            continue
        drawn = True
        (line,) = ax.plot(m.curve_hz, torque, lw=2, label=f"{kind}: peak torque, settings safe at that speed")
        rms = finite(m.curve["torque_rms_Nm"])
        ax.plot(m.curve_hz, rms, lw=1, ls="--", color=line.get_color(), label=f"{kind}: RMS torque")
        for v, entry in m.by_speed.items():
            if "torque_peak_Nm" in entry:
                t = entry["torque_peak_Nm"]["value"]
                ax.plot([float(v)], [t], "o", color=line.get_color())
                ax.annotate(f"{t:.0f} N·m at {float(v):g} Hz", (float(v), t), textcoords="offset points", xytext=(6, -12))
        safe = m.at_safe.get("torque_peak_Nm")
        if safe:
            ax.plot([safe["safe_speed_Hz"]], [safe["value"]], "s", color=line.get_color())
            ax.annotate(
                f"{safe['value']:.0f} N·m: the largest at a setting's own safe speed ({safe['safe_speed_Hz']:.2f} Hz)",
                (safe["safe_speed_Hz"], safe["value"]),
                textcoords="offset points",
                xytext=(0, 10),
                ha="center",
            )
    ax.axhline(MOTOR_ESTIMATE_2013_NM, color="grey", lw=1, ls=":", label="2013 study's estimate, 200 N·m")
    ax.set_xlabel("crank speed (Hz)")
    ax.set_ylabel("motor torque (N·m)")
    ax.set_ylim(0, 1.2 * max(ax.get_ylim()[1], MOTOR_ESTIMATE_2013_NM))
    ax.set_xlim(left=0)
    ax.grid(alpha=0.3)
    ax.set_title(
        "The motor a rig needs: at each crank speed, the largest torque over the settings still safe there\n"
        "(a setting leaves the curve above its safe speed, so the curve drops where the most demanding ones leave)",
        fontsize=9,
    )
    if drawn:
        ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)


def _extent(xs: np.ndarray, ys: np.ndarray) -> tuple:
    dx = (xs[1] - xs[0]) if xs.size > 1 else 60.0
    dy = (ys[1] - ys[0]) if ys.size > 1 else 60.0
    return (xs.min() - dx / 2, xs.max() + dx / 2, ys.min() - dy / 2, ys.max() + dy / 2)
