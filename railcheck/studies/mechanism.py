"""`railcheck mechanism NAME`'s mechanism: a planar scene file, a catalogue entry of seed
002 (in body coordinates, driven through the seed's sweep in 1 s), or a rig scene's own
four-bar or slider-crank, each as a :class:`~railcheck.studies.planar_scene.PlanarScene`;
and the drawing shared by its page (a self-contained page with a slider over the driver
that moves the drawn mechanism and shows the traced curve, the seed's CDF document in a
browser) and its GIF animation. Drawing units: mm.
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import numpy as np

from railcheck.base.errors import InputError
from railcheck.files import atomic_path, atomic_write_text
from railcheck.kinematics.linkage import FourBar
from railcheck.kinematics.planar.catalogue import CATALOGUE, SWEEPS, rig_fourbar, rig_slidercrank
from railcheck.kinematics.planar.model import Prismatic, Revolute
from railcheck.parts import mass_model
from railcheck.scene import parse_scene, read_scene_data
from railcheck.studies.planar_scene import MAX_STEPS, PlanarScene, is_planar, planar_scene, with_steps
from railcheck.studies.planar_writer import scene_text


def mechanism_scene(name: str, steps: int | None = None) -> PlanarScene:
    """The planar scene ``railcheck mechanism NAME`` studies: a planar scene file as it is
    (``steps`` overrides its driver's), a catalogue entry over seed 002's sweep, or a
    scene file's own four-bar or slider-crank (its bar lengths, mass model and crank
    speed, over one revolution), each written as a planar scene and read back."""
    if steps is not None and (isinstance(steps, bool) or not isinstance(steps, int) or not 2 <= steps <= MAX_STEPS):
        raise InputError("--steps", f"must be a whole number from 2 to {MAX_STEPS}, got {steps!r}")
    if name.endswith(".toml"):
        data, source = read_scene_data(name)
        if is_planar(data):
            scene = planar_scene(data, source)
            return scene if steps is None else with_steps(scene, steps)
        mech, kind, rate = _linkage_of(parse_scene(data, source), source)
        return _as_planar(mech, SWEEPS[kind], steps or 361, rate, source, steps)
    if name in CATALOGUE:
        sweep = SWEEPS[name]
        return _as_planar(CATALOGUE[name](), sweep, steps or 361, abs(sweep), f"catalogue {name}", steps)
    raise InputError("NAME", f"unknown mechanism {name!r} (catalogue: {', '.join(CATALOGUE)}; or a scene .toml)")


def _as_planar(mech, sweep: float, steps: int, rate: float, source: str, asked: int | None) -> PlanarScene:
    """A body-coordinate mechanism as the planar scene that says the same (written, read);
    the steps a user asked for checked as the option's."""
    scene = planar_scene(tomllib.loads(scene_text(mech, sweep, 361, rate)), source)
    return scene if asked is None else with_steps(scene, steps)


def _linkage_of(scene, path: str):
    """A rig scene's linkage in body coordinates: (mechanism, its catalogue kind, the
    crank's speed in rad/s), with the scene's bar lengths and mass model."""
    if scene.mechanism is None:
        raise InputError("mechanism", f"{path} has no [mechanism] table to animate")
    masses = mass_model(scene.formulation, scene.geometry)
    linkage = scene.mechanism.linkage
    if isinstance(linkage, FourBar):
        return rig_fourbar(linkage, masses), "four-bar", scene.mechanism.speed
    return rig_slidercrank(linkage, masses), "slider-crank", scene.mechanism.speed


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


def page_data(mech, motion, tracer_xy: np.ndarray, driver: np.ndarray, unit: str = "deg") -> dict:
    """The page's drawing data (mm): every body's points at every step, the ground's pivots
    and guides, the traced curve (``tracer_xy`` (steps, 2) m) and the driver's values in
    ``unit`` (deg or mm); the axes' bounds hold everything drawn."""
    segs = _segments(mech, motion)
    pivots, guides = ground_features(mech)
    all_pts = np.concatenate(
        [p.reshape(-1, 2) for _, _, p in segs] + [np.array([q[:2] for q in pivots]).reshape(-1, 2), tracer_xy]
    )
    lo, hi = all_pts.min(axis=0), all_pts.max(axis=0)
    mm = lambda a: np.round(np.asarray(a) * 1e3, 6).tolist()  # noqa: E731
    return {
        "name": mech.name,
        "description": mech.description,
        "driver": [round(float(v), 6) for v in driver],
        "driver_unit": unit,
        "bodies": [{"name": n, "points": names, "xy": mm(p)} for n, names, p in segs],
        "pivots": [[x * 1e3, y * 1e3, n] for x, y, n in pivots],
        "guides": [[mm(a), mm(b), n] for a, b, n in guides],
        "tracer": mm(tracer_xy),
        "bounds": [float(v) * 1e3 for v in (lo[0], lo[1], hi[0], hi[1])],
        "tracer_name": f"{mech.bodies[mech.tracer[0] - 1].name}.{mech.tracer[1]}",
    }


def write_page(path: Path, data: dict) -> None:
    """The self-contained page (inline data and script, no network) of :func:`page_data`."""
    template = (Path(__file__).with_name("mechanism_page.html")).read_text(encoding="utf-8")
    html = template.replace("__DATA__", json.dumps(data, separators=(",", ":"))).replace("__TITLE__", data["name"])
    atomic_write_text(path, html)


def write_gif(path: Path, mech, motion, tracer_xy: np.ndarray, frames: int = 60) -> None:
    """An animation of the cycle (``frames`` frames) with the traced path (m, (steps, 2))."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation, PillowWriter

    segs = _segments(mech, motion)
    idx = np.linspace(0, motion.s.size - 1, min(frames, motion.s.size)).astype(int)
    fig, ax = plt.subplots(figsize=(6, 5))
    allp = np.concatenate([p.reshape(-1, 2) for _, _, p in segs] + [tracer_xy]) * 1e3
    pad = 0.05 * np.ptp(allp, axis=0).max()
    ax.set_xlim(allp[:, 0].min() - pad, allp[:, 0].max() + pad)
    ax.set_ylim(allp[:, 1].min() - pad, allp[:, 1].max() + pad)
    ax.set_aspect("equal")
    ax.set(xlabel="x (mm)", ylabel="y (mm)", title=mech.name)
    ax.plot(tracer_xy[:, 0] * 1e3, tracer_xy[:, 1] * 1e3, "r-", lw=1, alpha=0.6)
    lines = [ax.plot([], [], "-o", lw=2, ms=3)[0] for _ in segs]
    dot = ax.plot([], [], "ro")[0]
    g = np.array(list(mech.ground.points.values())) * 1e3
    ax.plot(g[:, 0], g[:, 1], "k^", ms=6)

    def frame(i):
        k = idx[i]
        for line, (_, _, p) in zip(lines, segs):
            line.set_data(p[k, :, 0] * 1e3, p[k, :, 1] * 1e3)
        dot.set_data([tracer_xy[k, 0] * 1e3], [tracer_xy[k, 1] * 1e3])
        return lines + [dot]

    anim = FuncAnimation(fig, frame, frames=len(idx), blit=True)
    with atomic_path(path) as tmp:
        anim.save(tmp, writer=PillowWriter(fps=15))
    plt.close(fig)
