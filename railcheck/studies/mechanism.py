"""`railcheck mechanism NAME`: a catalogue mechanism in body coordinates (seed 002).

Prints the mobility report and the tracer point's range; ``--csv`` writes the tracer's
path (``driver,x,y,vx,vy,ax,ay``: rad, m, m/s, m/s^2 in the catalogue's frame, the
driver moving through seed 002's sweep in 1 s); ``--html`` a self-contained page with a
slider over the driver that moves the drawn mechanism and shows the traced curve (the
seed's CDF document, in a browser); ``--gif`` an animation of the cycle.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from railcheck.errors import InputError
from railcheck.files import atomic_path, atomic_write_text
from railcheck.kinematics.planar.catalogue import CATALOGUE, SWEEPS, driver_values
from railcheck.kinematics.planar.solver import mobility, solve


def _solve(name: str, steps: int):

    if name not in CATALOGUE:
        raise InputError("NAME", f"unknown mechanism {name!r} (catalogue: {', '.join(CATALOGUE)})")
    if steps < 2 or steps > 100_000:
        raise InputError("--steps", f"must be between 2 and 100000, got {steps}")
    mech = CATALOGUE[name]()
    s = driver_values(name, steps)
    motion = solve(mech, s)
    return mech, motion, mobility(mech, motion.q[0]), SWEEPS[name]


def tracer_table(mech, motion, rate: float) -> np.ndarray:
    """(steps, 7): driver (rad), x, y (m), vx, vy (m/s), ax, ay (m/s^2) of the tracer,
    for the driver moving at ``rate`` rad/s."""
    P, V, A = motion.point(*mech.tracer)
    driver = np.array([mech.driver.f(si)[0] for si in motion.s])
    return np.column_stack([driver, P, V * rate, A * rate**2])


def _segments(mech, motion) -> list:
    """Drawing data per body: its points' global positions at every step, ordered along
    the body's local x (then y): list of (name, [steps][points][2])."""
    out = []
    for k, body in enumerate(mech.bodies, start=1):
        names = sorted(body.points, key=lambda n: (body.points[n][0], body.points[n][1]))
        pos = np.stack([motion.point(k, n)[0] for n in names], axis=1)  # (steps, points, 2)
        out.append((body.name, names, pos))
    return out


def write_html(path: Path, mech, motion, table: np.ndarray) -> None:
    """A self-contained page (inline data and script, no network) with a slider."""
    segs = _segments(mech, motion)
    ground = [list(map(float, p)) for p in mech.ground.points.values()]
    all_pts = np.concatenate([p.reshape(-1, 2) for _, _, p in segs] + [np.array(ground), table[:, 1:3]])
    lo, hi = all_pts.min(axis=0), all_pts.max(axis=0)
    data = {
        "name": mech.name,
        "description": mech.description,
        "driver_deg": [round(math.degrees(v), 6) for v in table[:, 0]],
        "bodies": [{"name": n, "points": names, "xy": np.round(p, 9).tolist()} for n, names, p in segs],
        "ground": ground,
        "tracer": np.round(table[:, 1:3], 9).tolist(),
        "bounds": [float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])],
        "tracer_body": mech.bodies[mech.tracer[0] - 1].name,
    }
    html = _HTML.replace("__DATA__", json.dumps(data, separators=(",", ":"))).replace("__TITLE__", mech.name)
    atomic_write_text(path, html)


def write_gif(path: Path, mech, motion, table: np.ndarray, frames: int = 60) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation, PillowWriter

    segs = _segments(mech, motion)
    idx = np.linspace(0, motion.s.size - 1, min(frames, motion.s.size)).astype(int)
    fig, ax = plt.subplots(figsize=(6, 5))
    allp = np.concatenate([p.reshape(-1, 2) for _, _, p in segs] + [table[:, 1:3]]) * 1e3
    pad = 0.05 * np.ptp(allp, axis=0).max()
    ax.set_xlim(allp[:, 0].min() - pad, allp[:, 0].max() + pad)
    ax.set_ylim(allp[:, 1].min() - pad, allp[:, 1].max() + pad)
    ax.set_aspect("equal")
    ax.set(xlabel="x (mm)", ylabel="y (mm)", title=mech.name)
    ax.plot(table[:, 1] * 1e3, table[:, 2] * 1e3, "r-", lw=1, alpha=0.6)
    lines = [ax.plot([], [], "-o", lw=2, ms=3)[0] for _ in segs]
    dot = ax.plot([], [], "ro")[0]
    g = np.array(list(mech.ground.points.values())) * 1e3
    ax.plot(g[:, 0], g[:, 1], "k^", ms=6)

    def frame(i):
        k = idx[i]
        for line, (_, _, p) in zip(lines, segs):
            line.set_data(p[k, :, 0] * 1e3, p[k, :, 1] * 1e3)
        dot.set_data([table[k, 1] * 1e3], [table[k, 2] * 1e3])
        return lines + [dot]

    anim = FuncAnimation(fig, frame, frames=len(idx), blit=True)
    with atomic_path(path) as tmp:
        anim.save(tmp, writer=PillowWriter(fps=15))
    plt.close(fig)


@dataclass(frozen=True)
class MechanismRun:
    """A catalogue mechanism over its driver sweep: ``table`` (steps, 7) holds the
    driver value and the tracer's position, velocity, acceleration (SI); ``rate`` the
    driver's speed (rad/s: the seed's driver covers its sweep in 1 s)."""

    mech: object
    motion: object
    mobility: object
    table: np.ndarray
    rate: float
    steps: int


def run_mechanism(name: str, steps: int) -> MechanismRun:
    mech, motion, mob, sweep = _solve(name, steps)
    rate = math.copysign(abs(sweep), sweep)
    return MechanismRun(mech, motion, mob, tracer_table(mech, motion, rate), rate, steps)


def write_mechanism_outputs(run: MechanismRun, csv: str | None, html: str | None, gif: str | None) -> list[str]:
    """The CSV, HTML page and GIF asked for; returns the paths written."""
    written = []
    if csv:
        lines = ["driver,x,y,vx,vy,ax,ay"] + [",".join(f"{v:.12g}" for v in row) for row in run.table]
        atomic_write_text(csv, "\n".join(lines) + "\n")
        written.append(csv)
    if html:
        write_html(Path(html), run.mech, run.motion, run.table)
        written.append(html)
    if gif:
        write_gif(Path(gif), run.mech, run.motion, run.table)
        written.append(gif)
    return written


_HTML = r"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>__TITLE__ — railcheck</title>
<style>
body{font-family:sans-serif;margin:1em;color:#222} canvas{border:1px solid #ccc;background:#fff}
#controls{margin:.5em 0} input[type=range]{width:600px} pre{font-size:12px;color:#555}
</style></head><body>
<h2 id="title"></h2><div id="desc"></div>
<div id="controls"><label>driver <input id="slider" type="range" min="0" value="0" step="1"></label>
<span id="angle"></span></div>
<canvas id="view" width="800" height="600"></canvas>
<pre id="state"></pre>
<script>
const D = __DATA__;
const canvas = document.getElementById('view'), ctx = canvas.getContext('2d');
const slider = document.getElementById('slider');
document.getElementById('title').textContent = D.name;
document.getElementById('desc').textContent = D.description + ' (tracer on body ' + D.tracer_body + ')';
slider.max = D.driver_deg.length - 1;
const [x0, y0, x1, y1] = D.bounds, pad = 30;
const sc = Math.min((canvas.width - 2 * pad) / (x1 - x0 || 1), (canvas.height - 2 * pad) / (y1 - y0 || 1));
const px = p => [pad + (p[0] - x0) * sc, canvas.height - pad - (p[1] - y0) * sc];
const colours = ['#1f77b4', '#2ca02c', '#ff7f0e', '#9467bd', '#8c564b', '#e377c2', '#17becf', '#bcbd22', '#7f7f7f'];
let drawn = null;
function draw(k) {
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  ctx.strokeStyle = '#d62728'; ctx.lineWidth = 1; ctx.beginPath();
  D.tracer.forEach((p, i) => { const q = px(p); i ? ctx.lineTo(q[0], q[1]) : ctx.moveTo(q[0], q[1]); });
  ctx.stroke();
  ctx.fillStyle = '#000';
  D.ground.forEach(p => { const q = px(p); ctx.beginPath(); ctx.moveTo(q[0], q[1]); ctx.lineTo(q[0] - 6, q[1] + 10);
    ctx.lineTo(q[0] + 6, q[1] + 10); ctx.closePath(); ctx.fill(); });
  const bodies = [];
  D.bodies.forEach((b, j) => {
    const pts = b.xy[k].map(px);
    ctx.strokeStyle = colours[j % colours.length]; ctx.lineWidth = 4; ctx.beginPath();
    pts.forEach((q, i) => i ? ctx.lineTo(q[0], q[1]) : ctx.moveTo(q[0], q[1])); ctx.stroke();
    ctx.fillStyle = '#333'; pts.forEach(q => { ctx.beginPath(); ctx.arc(q[0], q[1], 3, 0, 2 * Math.PI); ctx.fill(); });
    bodies.push(pts.map(q => [Math.round(q[0] * 100) / 100, Math.round(q[1] * 100) / 100]));
  });
  const t = px(D.tracer[k]);
  ctx.fillStyle = '#d62728'; ctx.beginPath(); ctx.arc(t[0], t[1], 5, 0, 2 * Math.PI); ctx.fill();
  document.getElementById('angle').textContent = D.driver_deg[k].toFixed(2) + ' deg';
  drawn = {step: k, tracer_px: [Math.round(t[0] * 100) / 100, Math.round(t[1] * 100) / 100], bodies: bodies};
  document.getElementById('state').textContent = JSON.stringify({step: k, tracer_m: D.tracer[k]});
}
slider.addEventListener('input', () => draw(parseInt(slider.value)));
draw(0);
</script></body></html>
"""
