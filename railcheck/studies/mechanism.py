"""`railcheck mechanism NAME`: a catalogue mechanism in body coordinates (seed 002), or a
scene's own four-bar or slider-crank (NAME a scene .toml).

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

from railcheck.base.errors import InputError
from railcheck.files import atomic_path, atomic_write_text
from railcheck.kinematics.linkage import FourBar
from railcheck.kinematics.planar.catalogue import CATALOGUE, SWEEPS, driver_values, rig_fourbar, rig_slidercrank
from railcheck.kinematics.planar.model import Prismatic, Revolute
from railcheck.kinematics.planar.solver import mobility, solve
from railcheck.parts import mass_model
from railcheck.scene import load_scene


def _solve(name: str, steps: int):
    """The mechanism ``name`` (a catalogue name, or a scene file: its own four-bar or
    slider-crank with its bar lengths and masses) solved over its driver's sweep; returns
    (mechanism, motion, mobility, driver rate rad/s)."""
    if steps < 2 or steps > 100_000:
        raise InputError("--steps", f"must be between 2 and 100000, got {steps}")
    if name.endswith(".toml"):
        mech, kind, rate = scene_mechanism(name)
    elif name in CATALOGUE:
        mech, kind, rate = CATALOGUE[name](), name, SWEEPS[name]
    else:
        raise InputError("NAME", f"unknown mechanism {name!r} (catalogue: {', '.join(CATALOGUE)}; or a scene .toml)")
    motion = solve(mech, driver_values(kind, steps))
    return mech, motion, mobility(mech, motion.q[0]), rate


def scene_mechanism(path: str):
    """A scene's linkage in body coordinates: (mechanism, its catalogue kind, the crank's
    speed in rad/s), with the scene's bar lengths and mass model."""
    scene = load_scene(path)
    if scene.mechanism is None:
        raise InputError("mechanism", f"{path} has no [mechanism] table to animate")
    masses = mass_model(scene.formulation, scene.geometry)
    linkage = scene.mechanism.linkage
    if isinstance(linkage, FourBar):
        return rig_fourbar(linkage, masses), "four-bar", scene.mechanism.speed
    return rig_slidercrank(linkage, masses), "slider-crank", scene.mechanism.speed


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


def ground_features(mech) -> tuple[list, list]:
    """(pivots, guides) of the ground, in m: each revolute joint's ground point [x, y, name]
    (where a pin holds a body to the frame), and each prismatic joint's guide line on the
    ground [[x1, y1], [x2, y2], name] (two points of the line; the page extends it)."""
    pivots, guides = [], []
    for joint in mech.joints:
        if isinstance(joint, Revolute) and 0 in (joint.i, joint.j):
            point = joint.pi if joint.i == 0 else joint.pj
            x, y = mech.ground.points[point]
            pivots.append([float(x), float(y), joint.name])
        elif isinstance(joint, Prismatic) and 0 in (joint.i, joint.j):
            ends = (joint.pi, joint.qi) if joint.i == 0 else (joint.pj, joint.qj)
            a, b = (mech.ground.points[e] for e in ends)
            guides.append([[float(a[0]), float(a[1])], [float(b[0]), float(b[1])], joint.name])
    return pivots, guides


def write_html(path: Path, mech, motion, table: np.ndarray) -> None:
    """A self-contained page (inline data and script, no network): the mechanism drawn to
    scale on axes in mm with a grid and a scale bar, bodies and joints labelled, the ground
    drawn where it holds the mechanism (pivots, slider guides), the traced curve, a slider
    and a play/pause control over the driver, and a readout in mm and degrees."""
    segs = _segments(mech, motion)
    pivots, guides = ground_features(mech)
    all_pts = np.concatenate(
        [p.reshape(-1, 2) for _, _, p in segs] + [np.array([q[:2] for q in pivots]).reshape(-1, 2), table[:, 1:3]]
    )
    lo, hi = all_pts.min(axis=0), all_pts.max(axis=0)
    mm = lambda a: np.round(np.asarray(a) * 1e3, 6).tolist()  # noqa: E731
    data = {
        "name": mech.name,
        "description": mech.description,
        "driver_deg": [round(math.degrees(v), 6) for v in table[:, 0]],
        "bodies": [{"name": n, "points": names, "xy": mm(p)} for n, names, p in segs],
        "pivots": [[x * 1e3, y * 1e3, n] for x, y, n in pivots],
        "guides": [[mm(a), mm(b), n] for a, b, n in guides],
        "tracer": mm(table[:, 1:3]),
        "bounds": [float(v) * 1e3 for v in (lo[0], lo[1], hi[0], hi[1])],
        "tracer_name": f"{mech.bodies[mech.tracer[0] - 1].name}.{mech.tracer[1]}",
    }
    template = (Path(__file__).with_name("mechanism_page.html")).read_text(encoding="utf-8")
    html = template.replace("__DATA__", json.dumps(data, separators=(",", ":"))).replace("__TITLE__", mech.name)
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
