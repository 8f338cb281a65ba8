"""``rig.html``: the rig's settings for the lab, self-contained and offline. Pick the four
bar lengths on the hole grid (each list offers only the lengths that assemble with those
already picked), read the setting's verdict at the sweep's speed, the speed up to which it
is safe and what sets it, what governs and its utilisation, and watch the linkage turn at
a chosen speed with its joints O2, A, B, O4 named. The figures are the sweep table's rows
at its first speed (one JSON block in the page; no script or style is fetched)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from railcheck.files import atomic_write_text
from railcheck.report.html import CSS, html_escape
from railcheck.sweep.table import read_table
from railcheck.units import floored

#: the table's columns the page carries, per setting
COLUMNS: tuple[str, ...] = (
    "crank_mm",
    "coupler_mm",
    "rocker_mm",
    "ground_mm",
    "check_assembly",
    "verdict",
    "reason",
    "utilisation",
)
COLUMNS += ("governing_part", "governing_criterion", "safe_speed_Hz", "safe_speed_part", "safe_speed_criterion")


def rig_rows(table_path: Path, speed_hz: float) -> dict:
    """The page's data: the assembling settings of the four-bar table at ``speed_hz``,
    lengths in whole mm, the safe speed floored to 3 digits (None where not evaluated or
    unlimited: ``unlimited`` says which)."""
    table = read_table(table_path, speed_hz=speed_hz)
    rows = {c: np.asarray(table.column(c).to_numpy(zero_copy_only=False)) for c in COLUMNS if c in table.column_names}
    keep = np.flatnonzero(np.asarray(rows["check_assembly"], bool))
    safe = np.asarray(rows["safe_speed_Hz"], dtype=float)[keep] if "safe_speed_Hz" in rows else np.full(keep.size, np.nan)
    text = lambda c: [str(v) if v is not None else "" for v in rows[c][keep]] if c in rows else [""] * keep.size  # noqa: E731
    util = np.asarray(rows.get("utilisation", np.full(len(rows["crank_mm"]), np.nan)), dtype=float)[keep]
    return {
        "speed_Hz": speed_hz,
        "lengths": [[int(round(float(rows[f"{b}_mm"][i]))) for b in ("crank", "coupler", "rocker", "ground")] for i in keep],
        "verdict": text("verdict"),
        "reason": text("reason"),
        "governs": [f"{p} {c}".strip() for p, c in zip(text("governing_part"), text("governing_criterion"))],
        "utilisation": [round(float(u), 4) if math.isfinite(u) else None for u in util],
        "safe_Hz": [floored(float(s)) if math.isfinite(s) and s > 0 else None for s in safe],
        "unlimited": [bool(np.isinf(s)) for s in safe],
        "set_by": [f"{p} {c}".strip() for p, c in zip(text("safe_speed_part"), text("safe_speed_criterion"))],
    }


def write_rig_page(path: Path, table_path: Path, speed_hz: float, source: str = "") -> None:
    """Write ``rig.html`` at ``path`` from the four-bar table at ``table_path``."""
    data = rig_rows(table_path, speed_hz)
    page = (
        '<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>railcheck: the rig\'s settings</title>'
        f"<style>{CSS}{PAGE_CSS}</style></head><body>"
        f'<h1>The rig\'s settings</h1><p class="note">from {html_escape(source)}: {len(data["lengths"]):,} '
        f"settings that assemble, at {speed_hz:g} Hz (the sweep's speed)</p>"
        f"{CONTROLS}<script>const RIG = {json.dumps(data, separators=(',', ':'))};\n{SCRIPT}</script></body></html>\n"
    )
    atomic_write_text(path, page)


PAGE_CSS = """
.pick{display:flex;gap:1em;flex-wrap:wrap;align-items:end}.pick label{display:flex;flex-direction:column}
#card{margin:1em 0;font-size:1.1em}#verdict.pass{color:#1a7f37}#verdict.fail{color:#b42318}
svg{border:1px solid #ccc;background:#fafafa}
"""

CONTROLS = """
<div class="pick">
<label>crank (mm)<select id="crank"></select></label>
<label>coupler (mm)<select id="coupler"></select></label>
<label>rocker (mm)<select id="rocker"></select></label>
<label>ground (mm)<select id="ground"></select></label>
<label>animate at (Hz)<input id="speed" type="number" min="0" max="5" step="0.05" value="0.2"></label>
<button id="play" type="button">pause</button>
</div>
<div id="card"><div>verdict at <span id="at"></span> Hz: <b id="verdict"></b> <span id="reason"></span></div>
<div>safe up to: <b id="safe"></b> <span id="setby"></span></div>
<div>governs: <span id="governs"></span>, utilisation <span id="utilisation"></span></div>
<div>at the chosen <span id="chosen"></span> Hz: <b id="chosen-verdict"></b></div></div>
<svg id="linkage" width="720" height="420" viewBox="0 0 720 420"></svg>
"""

SCRIPT = r"""
const BARS = ["crank", "coupler", "rocker", "ground"];
const tree = {};
RIG.lengths.forEach((l, i) => {
  let node = tree;
  l.forEach((v, k) => { if (k < 3) { node = node[v] = node[v] || {}; } else { node[v] = i; } });
});
function options(k, node) {
  const sel = document.getElementById(BARS[k]);
  const keep = sel.value;
  const keys = Object.keys(node).map(Number).sort((a, b) => a - b);
  sel.innerHTML = keys.map(v => `<option value="${v}">${v}</option>`).join("");
  if (keys.map(String).includes(keep)) sel.value = keep;
  return node[sel.value];
}
function refresh(from) {
  let node = tree;
  for (let k = 0; k < 4; k++) {
    if (k >= from) node = options(k, node); else node = node[document.getElementById(BARS[k]).value];
  }
  show(node);
}
let current = null;
function show(i) {
  current = i;
  const v = RIG.verdict[i], u = RIG.utilisation[i];
  document.getElementById("at").textContent = RIG.speed_Hz;
  const verdict = document.getElementById("verdict");
  verdict.textContent = v.toUpperCase(); verdict.className = v;
  document.getElementById("reason").textContent = RIG.reason[i] ? `(${RIG.reason[i]})` : "";
  document.getElementById("safe").textContent = RIG.unlimited[i] ? "any speed" :
    (RIG.safe_Hz[i] === null ? "no speed" : `${RIG.safe_Hz[i]} Hz`);
  document.getElementById("setby").textContent = RIG.set_by[i] ? `(${RIG.set_by[i]} sets it)` : "";
  document.getElementById("governs").textContent = RIG.governs[i] || "-";
  document.getElementById("utilisation").textContent = u === null ? "-" : `${Math.round(u * 100)}%`;
  chosen();
}
function chosen() {
  if (current === null) return;
  const i = current, hz = Number(document.getElementById("speed").value);
  const safe = RIG.unlimited[i] || (RIG.safe_Hz[i] !== null && hz <= Number(RIG.safe_Hz[i]));
  document.getElementById("chosen").textContent = hz;
  document.getElementById("chosen-verdict").textContent = safe ? "safe (at or below its safe speed)" :
    (RIG.safe_Hz[i] === null && !RIG.unlimited[i] ? "not safe at any speed" : "not safe (above its safe speed)");
}
function joints(l, theta) {
  const [a, b, c, d] = l, A = [a * Math.cos(theta), a * Math.sin(theta)], O4 = [d, 0];
  const dx = O4[0] - A[0], dy = O4[1] - A[1], e = Math.hypot(dx, dy);
  const x = (b * b - c * c + e * e) / (2 * e), h = Math.sqrt(Math.max(b * b - x * x, 0));
  const B = [A[0] + (x * dx - h * dy) / e, A[1] + (x * dy + h * dx) / e];
  return {O2: [0, 0], A, B, O4};
}
let theta = 0, last = null, playing = true;
function draw(t) {
  if (last !== null && playing) theta += 2 * Math.PI * Number(document.getElementById("speed").value) * (t - last) / 1000;
  last = t;
  if (current !== null) {
    const l = RIG.lengths[current], j = joints(l, theta), span = l[0] + l[3] + l[2];
    const s = Math.min(600 / span, 180 / Math.max(l[0], l[1], l[2]));
    const X = p => 60 + (p[0] + l[0]) * s, Y = p => 210 - p[1] * s;
    const line = (p, q) => `<line x1="${X(p)}" y1="${Y(p)}" x2="${X(q)}" y2="${Y(q)}" stroke="#333" stroke-width="5"/>`;
    const label = (n, p, dy) => `<circle cx="${X(p)}" cy="${Y(p)}" r="6" fill="#c00"/>` +
      `<text x="${X(p) + 8}" y="${Y(p) + dy}" font-size="16">${n}</text>`;
    document.getElementById("linkage").innerHTML = line(j.O2, j.A) + line(j.A, j.B) + line(j.B, j.O4) +
      `<line x1="${X(j.O2)}" y1="${Y(j.O2)}" x2="${X(j.O4)}" y2="${Y(j.O4)}" stroke="#999" stroke-dasharray="6 4"/>` +
      label("O2", j.O2, 22) + label("A", j.A, -10) + label("B", j.B, -10) + label("O4", j.O4, 22);
  }
  requestAnimationFrame(draw);
}
BARS.forEach((b, k) => document.getElementById(b).addEventListener("change", () => refresh(k + 1)));
document.getElementById("speed").addEventListener("input", chosen);
document.getElementById("play").addEventListener("click", e => {
  playing = !playing; e.target.textContent = playing ? "pause" : "play";
});
refresh(0);
requestAnimationFrame(draw);
"""
