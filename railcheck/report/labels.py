"""Where a picture's labels go: each beside its anchor, off the drawing, never over another
label or a marked point, inside the picture, joined to its anchor by a leader line. Pure
geometry in pixels (x right, y up), for the matplotlib and the pyvista pictures alike."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: the directions tried around an anchor, as multiples of 360/16 degrees from the first
DIRECTIONS = 16


@dataclass(frozen=True)
class Box:
    """A label's box (px): lower-left ``x0, y0``, upper-right ``x1, y1``."""

    x0: float
    y0: float
    x1: float
    y1: float

    @property
    def centre(self) -> tuple[float, float]:
        return ((self.x0 + self.x1) / 2, (self.y0 + self.y1) / 2)

    def overlaps(self, other: Box, margin: float = 0.0) -> bool:
        """Whether the boxes share any area, each grown by ``margin`` px."""
        return not (
            self.x1 + margin <= other.x0
            or other.x1 + margin <= self.x0
            or self.y1 + margin <= other.y0
            or other.y1 + margin <= self.y0
        )

    def covers(self, x: float, y: float, radius: float = 0.0) -> bool:
        """Whether the box comes within ``radius`` px of the point (x, y)."""
        dx = max(self.x0 - x, 0.0, x - self.x1)
        dy = max(self.y0 - y, 0.0, y - self.y1)
        return math.hypot(dx, dy) < radius

    def inside(self, bounds: Box) -> bool:
        return self.x0 >= bounds.x0 and self.y0 >= bounds.y0 and self.x1 <= bounds.x1 and self.y1 <= bounds.y1


def box_at(centre: tuple[float, float], size: tuple[float, float]) -> Box:
    w, h = size
    return Box(centre[0] - w / 2, centre[1] - h / 2, centre[0] + w / 2, centre[1] + h / 2)


def place_labels(
    anchors: np.ndarray,
    sizes: list[tuple[float, float]],
    points: np.ndarray,
    picture: Box,
    gap: float = 12.0,
    away_from: tuple[float, float] | None = None,
    keep_out: list[Box] | None = None,
) -> list[Box]:
    """Each label's box (px): ``anchors`` (n, 2) the points the labels name, ``sizes`` their
    (width, height), ``points`` (m, 3) marked points (x, y, radius) no box may cover (the
    anchors among them), ``picture`` the area they must stay in, ``keep_out`` areas no box may enter
    (the part's outline). A label is tried beside its anchor in 16 directions, starting
    away from ``away_from`` (the drawing's centre) and turning both ways, slid along that
    side, its near edge ``gap`` px away, then farther (:data:`REACHES`); the first box inside
    the picture that overlaps no box placed before, no keep-out area and covers no marked
    point wins.
    Where none does, the least bad is kept (fewest conflicts), so a label is never lost."""
    placed: list[Box] = []
    keep_out = keep_out or []
    centre = np.mean(anchors, axis=0) if away_from is None else np.asarray(away_from, float)
    for (ax, ay), size in zip(np.asarray(anchors, float), sizes):
        start = math.atan2(ay - centre[1], ax - centre[0]) if (ax, ay) != tuple(centre) else math.pi / 2
        best, fewest = None, math.inf
        for box in [*_candidates(ax, ay, size, start, gap), *_beside(ax, ay, size, keep_out, gap)]:
            conflicts = _conflicts(box, placed, keep_out, points, picture)
            if conflicts < fewest:
                best, fewest = box, conflicts
            if conflicts == 0:
                break
        assert best is not None
        placed.append(best)
    return placed


#: how far a label may sit from its anchor, in gaps, nearest first
REACHES = (1.0, 2.0, 4.0, 7.0, 10.0, 14.0, 20.0)

#: slides of a box along its side of the anchor, in its own width or height
SLIDES = (0.0, -0.35, 0.35, -0.7, 0.7)


def _candidates(ax: float, ay: float, size: tuple[float, float], start: float, gap: float):
    """The boxes a label may take, nearest and most outward first: for each reach and each
    of 16 directions from ``start``, the box beside the anchor on that side (its near edge
    ``reach x gap`` px away), slid along that side."""
    w, h = size
    for reach in REACHES:
        g = reach * gap
        for k in _turns():
            angle = start + 2 * math.pi * k / DIRECTIONS
            c, s = math.cos(angle), math.sin(angle)
            cx, cy = ax + c * (w / 2 + g), ay + s * (h / 2 + g)
            for slide in SLIDES:
                yield box_at((cx - s * slide * w, cy + c * slide * h), size)


def _beside(ax: float, ay: float, size: tuple[float, float], keep_out: list[Box], gap: float):
    """Boxes just outside each keep-out area's four edges (``gap`` / 2 px off), slid
    along the edge to the anchor's level or abscissa and beyond: where a label fits in a
    narrow band between the drawing and the picture's edge or caption."""
    w, h = size
    off = gap / 2
    for area in keep_out:
        for along in (0.0, -0.5, 0.5, -1.0, 1.0):
            x = min(max(ax + along * w, area.x0 - w / 2), area.x1 + w / 2)
            y = min(max(ay + along * h, area.y0 - h / 2), area.y1 + h / 2)
            yield box_at((x, area.y1 + off + h / 2), size)  # above
            yield box_at((x, area.y0 - off - h / 2), size)  # below
            yield box_at((area.x0 - off - w / 2, y), size)  # left
            yield box_at((area.x1 + off + w / 2, y), size)  # right


def _turns() -> list[int]:
    """0, 1, -1, 2, -2, ...: the directions nearest the first first."""
    out = [0]
    for k in range(1, DIRECTIONS // 2 + 1):
        out += [k, -k] if k < DIRECTIONS // 2 else [k]
    return out


def _conflicts(box: Box, placed: list[Box], keep_out: list[Box], points: np.ndarray, picture: Box) -> int:
    """How many things ``box`` runs into: placed labels, keep-out areas, marked points,
    the picture's edge."""
    n = sum(box.overlaps(b, 2.0) for b in placed) + sum(box.overlaps(b) for b in keep_out)
    n += sum(box.covers(x, y, r) for x, y, r in np.asarray(points, float).reshape(-1, 3))
    return n + (0 if box.inside(picture) else 1)


def conflicts_among(boxes: list[Box], points: np.ndarray, picture: Box) -> list[str]:
    """What is wrong with a picture's label boxes: two that overlap, one that covers a
    marked point (x, y, radius), one outside the picture; empty when nothing is."""
    problems = []
    for i, a in enumerate(boxes):
        problems += [f"labels {i} and {j} overlap" for j, b in enumerate(boxes[:i]) if a.overlaps(b)]
        marked = enumerate(np.reshape(points, (-1, 3)))
        problems += [f"label {i} covers point {k}" for k, (x, y, r) in marked if a.covers(x, y, r)]
        if not a.inside(picture):
            problems.append(f"label {i} leaves the picture")
    return problems
