"""The force labels of a part's von Mises picture (:mod:`railcheck.report.render`): each
off the part, beside the arrows it names, joined to them by a leader line, never over a
hole, another label, the caption or the colour bar (:func:`railcheck.report.labels.place_labels`
in the picture's pixels, from VTK's world-to-display transform of the rendered view)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from railcheck.report.labels import Box, place_labels

#: the mesh groups whose centres are holes no label may cover
HOLE_PREFIXES = ("hole_", "bolt_", "pin_", "screw_")


@dataclass(frozen=True)
class PartPicture:
    """A written part picture: its ``path``, its force labels' boxes, the holes' centres
    and radii (x, y, r), the part's outline box and the caption's, all px (x right, y up),
    and the picture's ``size``."""

    path: Path
    labels: tuple[Box, ...]
    holes: np.ndarray
    part: Box
    caption: Box
    size: tuple[int, int]


def display_points(plotter, points: np.ndarray) -> np.ndarray:
    """(n, 3) the display coordinates (px x, px y, depth) of world ``points`` (n, 3) m in
    the plotter's current view (a parallel projection: one affine map, from three points)."""
    ren = plotter.renderer
    basis = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    images = []
    for p in basis:
        ren.SetWorldPoint(*p, 1.0)
        ren.WorldToDisplay()
        images.append(ren.GetDisplayPoint())
    origin, images = np.array(images[0]), np.array(images[1:]) - np.array(images[0])
    return np.asarray(points, float) @ images + origin


def world_point(plotter, x: float, y: float, depth: float) -> np.ndarray:
    """The world point (3,) m shown at pixel (x, y) at ``depth`` (display z)."""
    ren = plotter.renderer
    ren.SetDisplayPoint(x, y, depth)
    ren.DisplayToWorld()
    w = np.array(ren.GetWorldPoint(), float)
    return w[:3] / w[3]


def hole_centres(mesh, shown: np.ndarray) -> list[tuple[np.ndarray, float]]:
    """Each hole's centre (3,) m and radius m, from its mesh group's nodes as drawn."""
    out = []
    for name, nodes in mesh.groups.items():
        if name.startswith(HOLE_PREFIXES):
            pts = shown[np.unique(np.ravel(nodes))]
            centre = pts.mean(axis=0)
            out.append((centre, float(np.linalg.norm(pts - centre, axis=1).max())))
    return out


def outline(pixels: np.ndarray) -> Box:
    """The box (px) of displayed points (n, 3)."""
    return Box(*pixels[:, 0:2].min(axis=0), *pixels[:, 0:2].max(axis=0))


def caption_area(plotter) -> Box:
    """The caption's box (px), from its rendered text."""
    actor = plotter.actors["caption"]
    box = [0.0] * 4
    actor.GetBoundingBox(plotter.renderer, box)
    x, y = actor.GetPosition()
    return Box(x + box[0], y + box[2], x + box[1], y + box[3])


def force_labels(plotter, requests: list, shown: np.ndarray, holes: list, reserved: list, ruler, font: int) -> tuple:
    """Draw each request's words (anchor (3,) m, text, optional colour: red) off the part (``shown``, its
    drawn points) with a leader line to its anchor, clear of the ``holes`` (centre, radius
    m), the ``reserved`` boxes (px: colour bar, axes), the ``ruler`` (its ends, m) and the
    caption; returns (label boxes, holes (x, y, r) px, part box, caption box)."""
    width, height = plotter.window_size
    part = outline(display_points(plotter, shown[:: max(1, shown.shape[0] // 20000)]))
    steps = display_points(plotter, np.vstack([np.zeros(3), 1e-3 * np.eye(3)]))[:, :2]
    scale = float(np.linalg.norm(steps[1:] - steps[0], axis=1).max()) / 1e-3  # px per m in the view's plane
    marked = np.array([[*display_points(plotter, c[None])[0, :2], r * scale + 3.0] for c, r in holes]).reshape(-1, 3)
    caption = caption_area(plotter)
    if not requests:
        return (), marked, part, caption
    actors = [_text(plotter, r[1], font, f"force-{i}", *r[2:]) for i, r in enumerate(requests)]
    plotter.render()
    sizes = [(b.x1 - b.x0 + 10.0, b.y1 - b.y0 + 8.0) for b in (_box_of(plotter, a) for a in actors)]
    anchors = display_points(plotter, np.array([r[0] for r in requests]))
    ends = display_points(plotter, np.asarray(ruler, float))
    rule = Box(ends[:, 0].min() - 20, ends[:, 1].min() - 45, ends[:, 0].max() + 30, ends[:, 1].max() + 10)  # its numbers
    keep_out = [Box(part.x0 - 4, part.y0 - 4, part.x1 + 4, part.y1 + 4), caption, rule, *reserved]
    picture = Box(0, 0, width, height)
    boxes = place_labels(anchors[:, :2], sizes, marked, picture, gap=14.0, away_from=part.centre, keep_out=keep_out)
    for actor, box, anchor, request in zip(actors, boxes, anchors, requests):
        actor.SetPosition(box.x0 + 5.0, box.y0 + 4.0)
        end = _nearest_on(box, anchor[:2])
        line = np.array([world_point(plotter, *anchor), world_point(plotter, *end, anchor[2])])
        plotter.add_lines(line, color=request[2] if len(request) > 2 else "red", width=2)
    plotter.render()
    return tuple(_box_of(plotter, a) for a in actors), marked, part, caption


def _text(plotter, words: str, font: int, name: str, colour: str = "red"):
    actor = plotter.add_text(words, position=(0, 0), font_size=font, color=colour, name=name)
    prop = actor.GetTextProperty()
    prop.SetBackgroundColor(1.0, 1.0, 1.0)
    prop.SetBackgroundOpacity(0.85)
    return actor


def _box_of(plotter, actor) -> Box:
    box = [0.0] * 4
    actor.GetBoundingBox(plotter.renderer, box)
    x, y = actor.GetPosition()
    return Box(x + box[0], y + box[2], x + box[1], y + box[3])


def _nearest_on(box: Box, point: np.ndarray) -> tuple[float, float]:
    """The point of ``box``'s edge nearest ``point`` (px), where the leader line ends."""
    return (float(np.clip(point[0], box.x0, box.x1)), float(np.clip(point[1], box.y0, box.y1)))
