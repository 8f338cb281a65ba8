"""``linkage.png``: the mechanism the check's tables name, drawn to scale at one instant:
its bars (crank, coupler, rocker or slider) with their lengths, the ground between its
pivots, the joints O2, A, B (and O4) labelled off the drawing with leader lines (no label
over a joint or another label: :mod:`railcheck.report.labels`), and the paths of A and B
over the crank's revolution. The instant is the largest joint reaction's, said in the
title. matplotlib (Agg) imported here only. Lengths in mm on the picture, SI inside."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railcheck.files import atomic_path
from railcheck.report.labels import Box, place_labels

#: the bars drawn, joint to joint, and their names
BARS = (("O2", "A", "crank"), ("A", "B", "coupler"), ("B", "O4", "rocker"))

#: a joint marker's radius (px) that no label may cover
JOINT_RADIUS = 9.0


def peak_instant(dynamics) -> tuple[int, str, float]:
    """(step, joint, N): the instant of the largest joint reaction over the cycle."""
    joint = max(dynamics.reactions, key=lambda j: dynamics.peak(j)[0])
    value, step = dynamics.peak(joint)
    return step, joint, value


def write_linkage_picture(path: str | Path, motion, dynamics) -> tuple[list[Box], np.ndarray, Box]:
    """Draw the linkage of ``motion`` (:class:`kinematics.motion.Motion`) at the instant of
    ``dynamics``' largest reaction into ``path``; return the label boxes as drawn, the
    joints (x, y, radius) and the plot's frame, in px (for the tests: no label overlaps
    another, covers a joint or leaves the frame)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    step, joint, force = peak_instant(dynamics)
    at = {name: xy[step] * 1e3 for name, xy in motion.points.items()}  # mm
    fig, ax = plt.subplots(figsize=(9.0, 5.2))
    _draw(ax, motion, at)
    ax.set_title(
        f"The linkage at crank {np.degrees(motion.theta2[step]) % 360:.1f} deg, the instant of the largest joint "
        f"reaction ({joint}, {force:.0f} N unfactored)\ndashed: the paths of A and B over the revolution; mm",
        fontsize=9,
    )
    boxes, joints, area = _labels(fig, ax, at)
    with atomic_path(Path(path)) as tmp:
        fig.savefig(tmp, dpi=100, format="png")
    plt.close(fig)
    return boxes, joints, area


def _draw(ax, motion, at: dict) -> None:
    """Paths, ground, bars and joints, the axes fitted around them with room for labels."""
    for name in ("A", "B"):
        path = motion.points[name] * 1e3
        ax.plot(path[:, 0], path[:, 1], ls="--", lw=1, color="#999999")
    ground = [at["O2"], at["O4"]] if "O4" in at else [at["O2"], at["O2"]]
    if "O4" in at:
        ax.plot(*np.transpose(ground), color="#555555", lw=2, ls=(0, (6, 3)))
    else:  # a slider: its line through B's path
        b = motion.points["B"] * 1e3
        ax.plot([b[:, 0].min() - 40, b[:, 0].max() + 40], [b[0, 1]] * 2, color="#555555", lw=2, ls=(0, (6, 3)))
    for a, b, _ in BARS:
        if a in at and b in at:
            ax.plot(*np.transpose([at[a], at[b]]), lw=5, solid_capstyle="round")
    for name, xy in at.items():
        fixed = name in ("O2", "O4")
        ax.plot(*xy, marker="^" if fixed else "o", ms=11, mfc="white", mec="black", mew=1.5, zorder=5)
    ax.set_aspect("equal", adjustable="datalim")  # the frame fills the figure: room for labels beside
    every = np.concatenate([p * 1e3 for p in motion.points.values()])
    span = np.ptp(every, axis=0).max()
    lo, hi = every.min(axis=0) - 0.25 * span, every.max(axis=0) + 0.25 * span
    ax.update_datalim([lo, hi])
    ax.autoscale_view(tight=True)
    ax.grid(alpha=0.25)


def _segments(at: dict) -> list[tuple[np.ndarray, np.ndarray]]:
    """(start, end) mm of every bar drawn, the ground's too: no label lies on them."""
    pairs = [(at[a], at[b]) for a, b, _ in BARS if a in at and b in at]
    return pairs + ([(at["O2"], at["O4"])] if "O4" in at else [])


def _bar_label(a: str, b: str, name: str, at: dict) -> tuple[str, np.ndarray]:
    length = float(np.linalg.norm(at[b] - at[a]))
    return f"{name} {length:.0f}", (at[a] + at[b]) / 2


def _labels(fig, ax, at: dict) -> tuple[list[Box], np.ndarray, Box]:
    """Every joint's and bar's label placed by :func:`place_labels` (anchors, joints and
    bar midpoints in px), with a leader line to what it names; the boxes as drawn."""
    words = [(name, xy) for name, xy in at.items()]
    words += [_bar_label(a, b, n, at) for a, b, n in BARS if a in at and b in at]
    if "O4" in at:
        words.append(_bar_label("O2", "O4", "ground", at))
    to_px = ax.transData.transform
    texts = [ax.text(0, 0, w, fontsize=10, ha="center", va="center", zorder=6) for w, _ in words]
    fig.canvas.draw()
    sizes = [(t.get_window_extent().width + 6, t.get_window_extent().height + 4) for t in texts]
    anchors = np.array([to_px(xy) for _, xy in words])
    joints = np.array([[*to_px(xy), JOINT_RADIUS] for xy in at.values()])
    along = np.array([[*to_px(a + t * (b - a)), 4.0] for a, b in _segments(at) for t in np.linspace(0.0, 1.0, 25)])
    area = Box(*np.ravel(ax.get_window_extent().get_points()))  # the plot's frame: no label over the ticks
    centre = tuple(anchors[: len(at)].mean(axis=0))  # the joints' middle: labels go outward from it
    boxes = place_labels(anchors, sizes, np.vstack([joints, along]), area, gap=10.0, away_from=centre)
    to_data = ax.transData.inverted().transform
    for text, box, anchor in zip(texts, boxes, anchors):
        text.set_position(to_data(box.centre))
        text.set_bbox({"boxstyle": "round,pad=0.2", "fc": "white", "ec": "#bbbbbb", "lw": 0.6})
        leader = {"arrowstyle": "-", "lw": 0.7, "color": "#444444", "shrinkA": 8, "shrinkB": 9}
        ax.annotate("", xy=to_data(anchor), xytext=to_data(box.centre), arrowprops=leader)
    fig.canvas.draw()
    joints = np.array([[*ax.transData.transform(xy), JOINT_RADIUS] for xy in at.values()])
    return [Box(*np.ravel(t.get_bbox_patch().get_window_extent().get_points())) for t in texts], joints, area
