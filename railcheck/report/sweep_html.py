"""The sweep's ``report.html``: one self-contained page (pictures inline, no script, no
network) with what a rig engineer asks of a sweep: how many settings pass, the maps, the
motor a rig needs (the curve and the figures at each speed), the worst settings, the best
setting per criterion, the safe speeds' criteria and the 2013 study's hypotheses re-stated
on the table. Units at this edge: mm, Hz, N·m, W, h.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from railcheck.files import atomic_write_text
from railcheck.report.html import CSS, html_escape, html_image, html_table
from railcheck.sweep.table import read_table
from railcheck.units import floored

#: how many of the most utilised settings the report lists per kind
WORST_LISTED = 10

#: (title, column, "min" or "max", format, unit) of the best passing setting per criterion
BEST = (
    ("lowest utilisation at the first speed", "utilisation", "min", ".3f", ""),
    ("highest safe speed", "safe_speed_Hz", "max", ".3g", "Hz"),
    ("lowest peak motor torque", "torque_peak_Nm", "min", ".3g", "N·m"),
    ("lowest peak motor power", "power_peak_W", "min", ",.0f", "W"),
    ("longest bearing life (L10) of the least-lived 6205", "bearing_life_h", "max", ".3g", "h"),
)


def write_sweep_report(path: Path, summary: dict, tables: dict, directory: Path, plots: bool = True) -> None:
    """Write the sweep's report.html at ``path`` (the maps and motor.png read from
    ``directory``; ``tables`` kind -> table path; ``plots`` False: none drawn, said so)."""
    speed = summary["speeds_Hz"][0]
    sections = [
        "<h1>railcheck sweep</h1>",
        f'<p class="note">speeds {html_escape(", ".join(f"{v:g}" for v in summary["speeds_Hz"]))} Hz, '
        f"{summary['steps']} steps per revolution, {html_escape(summary['assembly'])} assembly, effects: "
        f"{html_escape(', '.join(summary['effects']))}; scene: {html_escape(summary.get('scene_source', ''))}</p>",
        _counts(summary),
        "" if plots else '<p class="note">no maps or motor curve: the scene asks for none ([output] plots = false)</p>',
    ]
    for kind, path_k in tables.items():
        rows = _first_speed_rows(path_k, speed)
        sections += [
            f"<h2>{html_escape(kind)}</h2>",
            html_image(directory / f"map-{kind}.png", f"{kind} maps"),
            _worst(rows),
            _best(rows),
            safe_settings(rows, speed),
            _safe_criteria(summary["by_kind"][kind]),
        ]
    sections += [_motor(summary, directory), _hypotheses(summary)]
    page = (
        '<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>railcheck sweep</title>'
        f"<style>{CSS}</style></head><body>{''.join(s for s in sections if s)}</body></html>\n"
    )
    atomic_write_text(path, page)


def _first_speed_rows(path: Path, speed_hz: float) -> dict:
    table = read_table(path, None, speed_hz)
    return {k: np.asarray(v.to_numpy(zero_copy_only=False)) for k, v in zip(table.column_names, table.columns)}


def _lengths(rows: dict, i: int) -> str:
    bars = [b for b in ("crank", "coupler", "rocker", "ground", "offset") if f"{b}_mm" in rows]
    return "/".join(f"{rows[f'{b}_mm'][i]:.0f}" for b in bars) + " mm"


def _counts(summary: dict) -> str:
    head = ["kind", "settings", "assemble", "revolve", "pass the configuration checks", "pass every check"]
    rows = [
        [
            html_escape(kind),
            f"{k['settings_total']:,}",
            f"{k['settings_assemblable']:,}",
            f"{k['settings_revolving']:,}",
            f"{k['settings_passing_checks']:,}",
            f"{k['settings_passing']:,} at {summary['speeds_Hz'][0]:g} Hz",
        ]
        for kind, k in summary["by_kind"].items()
    ]
    return "<h2>Settings</h2>" + html_table(head, rows)


def _number(value, fmt: str) -> str:
    try:
        v = float(value)
    except (TypeError, ValueError):
        return "-"
    return format(v, fmt) if math.isfinite(v) else "-"


def _worst(rows: dict) -> str:
    if "utilisation" not in rows:
        return ""
    u = np.asarray(rows["utilisation"], dtype=float)
    order = [i for i in np.argsort(-np.where(np.isfinite(u), u, -np.inf)) if np.isfinite(u[i])][:WORST_LISTED]
    if not order:
        return ""
    body = [
        [
            html_escape(_lengths(rows, i)),
            f"{u[i]:.3f}",
            html_escape(f"{rows['governing_part'][i]} {rows['governing_criterion'][i]}"),
            _number(rows["safe_speed_Hz"][i], ".3g"),
            html_escape(f"{rows['safe_speed_part'][i] or '-'} {rows['safe_speed_criterion'][i] or ''}"),
            _number(rows["torque_peak_Nm"][i], ".3g"),
            html_escape(rows["verdict"][i]),
        ]
        for i in order
    ]
    head = ["setting", "utilisation", "governs", "safe speed (Hz)", "set by", "peak torque (N·m)", "verdict"]
    return f"<h3>The {len(order)} most utilised settings</h3>" + html_table(head, body, left=1)


#: how many safe settings the report lists per kind, fastest first
SAFE_LISTED = 20


def safe_settings(rows: dict, speed_hz: float) -> str:
    """The settings that pass every check at ``speed_hz``, fastest safe speed first (at
    most :data:`SAFE_LISTED`, with their count): the list a teacher picks a setting from;
    each safe speed floored, never rounded up."""
    if "safe_speed_Hz" not in rows:
        return ""
    passing = np.flatnonzero(np.asarray(rows["verdict"] == "pass"))
    safe = np.asarray(rows["safe_speed_Hz"], dtype=float)
    if "safe_speed_unlimited" in rows:
        safe = np.where(np.asarray(rows["safe_speed_unlimited"], bool), np.inf, safe)
    passing = passing[np.isfinite(safe[passing]) | np.isinf(safe[passing])]
    if passing.size == 0:
        return f"<p>No setting passes every check at {speed_hz:g} Hz.</p>"
    order = passing[np.argsort(-safe[passing], kind="stable")][:SAFE_LISTED]
    body = [
        [
            html_escape(_lengths(rows, i)),
            "unlimited" if np.isinf(safe[i]) else floored(safe[i]),
            html_escape(f"{rows['safe_speed_part'][i] or '-'} {rows['safe_speed_criterion'][i] or ''}"),
            _number(rows["torque_peak_Nm"][i], ".3g"),
        ]
        for i in order
    ]
    head = ["setting", "safe up to (Hz)", "set by", f"peak torque at {speed_hz:g} Hz (N·m)"]
    title = f"The {len(order)} of {passing.size:,} settings safe at {speed_hz:g} Hz with the highest safe speed"
    return f"<h3>{title}</h3>" + html_table(head, body, left=1)


def _best(rows: dict) -> str:
    passing = np.asarray(rows["verdict"] == "pass")
    body = []
    for title, column, sense, fmt, unit in BEST:
        if column not in rows or not passing.any():
            continue
        values = np.asarray(rows[column], dtype=float)
        if column == "safe_speed_Hz" and "safe_speed_unlimited" in rows:
            values = np.where(np.asarray(rows["safe_speed_unlimited"], bool), np.inf, values)
        ok = passing & ~np.isnan(values)
        if not ok.any():
            continue
        pick = np.where(ok, values if sense == "max" else -values, -np.inf)
        i = int(np.argmax(pick))
        value = "unlimited" if np.isinf(values[i]) else f"{format(values[i], fmt)} {unit}".strip()
        body.append([html_escape(title), html_escape(_lengths(rows, i)), html_escape(value)])
    if not body:
        return ""
    return "<h3>The best passing setting per criterion</h3>" + html_table(["criterion", "setting", "value"], body)


def _safe_criteria(kind: dict) -> str:
    counts = kind.get("safe_speed_criteria") or {}
    if not counts:
        return ""
    text = ", ".join(f"{c}: {n:,}" for c, n in counts.items())
    return f"<p>what sets each setting's safe speed (settings per criterion): {html_escape(text)}</p>"


def _motor(summary: dict, directory: Path) -> str:
    rows = []
    for kind, k in summary["by_kind"].items():
        sizing = k.get("motor_sizing") or {}
        for speed, entry in sizing.get("at_listed_speeds", {}).items():
            if "torque_peak_Nm" not in entry:
                continue
            t, r, p = (entry[q] for q in ("torque_peak_Nm", "torque_rms_Nm", "power_peak_W"))
            rows.append(
                [
                    html_escape(kind),
                    f"{float(speed):g} Hz",
                    f"{t['value']:.3g}",
                    f"{r['value']:.3g}",
                    f"{p['value']:.3g}",
                    html_escape(_mm(t)),
                ]
            )
        safe = sizing.get("at_safe_speed", {})
        if "torque_peak_Nm" in safe:
            t, r, p = (safe[q] for q in ("torque_peak_Nm", "torque_rms_Nm", "power_peak_W"))
            rows.append(
                [
                    html_escape(kind),
                    f"each setting's safe speed (largest at {t['safe_speed_Hz']:.3g} Hz)",
                    f"{t['value']:.3g}",
                    f"{r['value']:.3g}",
                    f"{p['value']:.3g}",
                    html_escape(_mm(t)),
                ]
            )
    if not rows:
        return ""
    head = ["kind", "to run every passing setting at", "peak torque (N·m)", "RMS torque (N·m)", "peak power (W)", "set by"]
    return (
        "<h2>The motor a rig needs</h2><p>The 2013 design study estimated at least 200 N·m. Each row is the largest "
        "over the settings that pass at that speed; the curve is the largest over the settings still safe at each "
        "speed.</p>"
        + html_table(head, rows, left=2)
        + html_image(directory / "motor.png", "motor torque against crank speed")
    )


def _mm(entry: dict) -> str:
    return "/".join(f"{v * 1e3:.0f}" for v in entry["lengths_m"].values()) + " mm"


def _hypotheses(summary: dict) -> str:
    hyps = summary.get("seed_hypotheses") or []
    if not hyps:
        return ""
    mark = {True: "holds", False: "does not hold", None: "not tested here"}
    rows = [
        [
            html_escape(h["id"]),
            f'<span class="l">{html_escape(h["statement"])}</span>',
            html_escape(mark[h["holds"]]),
            html_escape(h["evidence"]),
        ]
        for h in hyps
    ]
    return "<h2>The 2013 study's hypotheses (chapter 3.3), on this sweep</h2>" + html_table(
        ["section", "hypothesis", "on this sweep", "evidence"], rows, left=4
    )
