"""PNG of a part's von Mises field at its governing instant on the deformed shape
(pyvista, off-screen; imported here only).

What an engineer reads on it: the part framed to fill the picture, seen from above (the
plane the mechanism moves and the rails bend in), a perceptually uniform
colour map (viridis) ending at the verdict peak, the support's singular zone above it in
magenta, the support's surface in grey, an arrow per loaded bolt hole along its force,
and a marker with its label at the verdict peak, a length scale in mm and the axes' triad.
One magnification rule for every part (:func:`deformation_scale`): the largest
displacement drawn at most 5% of the part's size, in 1-2-5 steps, never above x1000; the
factor is printed on the picture.

Rendering needs no X server: without a DISPLAY, VTK's EGL window is used (no warning on
the console).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from railcheck.files import atomic_path
from railcheck.parts import kind_of
from railcheck.report.forces import governing_forces, newtons, support_words
from railcheck.report.labels import Box
from railcheck.report.picture_labels import PartPicture, force_labels, hole_centres
from railcheck.units import nice_top

DEFORMATION_FRACTION = 0.05  # of the part's largest dimension
MAX_MAGNIFICATION = 1000.0  # beyond it a tiny deformation would be drawn as a crushed shape
COLOUR_MAP = "viridis"
CAPTION_FRACTION = 0.017  # caption font size, of the picture's height (VTK renders a line ~1.6x the size: ~2.7%)
MIN_FONT = 14  # the smallest font size of any text on the picture (labels, colour bar)
CHAR_WIDTH = 0.55  # a caption character's width, of the font size (a first guess; fit_caption measures)


def caption_font_size(height: int) -> int:
    """Caption font size (VTK points: pixels of text height) for a picture ``height`` px high."""
    return max(MIN_FONT, int(np.ceil(CAPTION_FRACTION * height)))


def fit_caption(plotter, text: str, size: tuple[int, int], font: int) -> int:
    """Add ``text`` at the upper left, wrapped so that its rendered box fits inside the
    picture (measured after rendering, rewrapped narrower until it does); returns its
    number of lines."""
    per_line = max(20, int(0.96 * size[0] / (CHAR_WIDTH * font)))
    for _ in range(8):
        lines = [w for line in text.split("\n") for w in __import__("textwrap").wrap(line, per_line)]
        actor = plotter.add_text("\n".join(lines), position=(8, size[1] - 8), font_size=font, name="caption")
        actor.GetTextProperty().SetVerticalJustificationToTop()
        plotter.render()
        right = caption_box(plotter, actor)[1]
        if right <= 0.985 * size[0]:
            return len(lines)
        per_line = max(10, int(per_line * 0.97 * size[0] / right))
    return len(lines)


def caption_box(plotter, actor) -> tuple[float, float, float, float]:
    """(x min, x max, y min, y max) px of a rendered text actor in the picture (VTK gives
    the box relative to the actor's anchor)."""
    box = [0.0] * 4
    actor.GetBoundingBox(plotter.renderer, box)
    x, y = actor.GetPosition()
    return (x + box[0], x + box[1], y + box[2], y + box[3])


def colour_bar_format(top: float) -> str:
    """printf format of the colour bar's labels (MPa) so that six labels from 0 to ``top``
    read distinct values: whole MPa from 25 MPa up, one or more decimals below."""
    step = max(top, 1e-12) / 5
    return f"%.{min(max(0, int(np.ceil(-np.log10(step)))), 4)}f"


def offscreen_pyvista():
    os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")
    if not os.environ.get("DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv
    from vtkmodules.vtkCommonCore import vtkLogger, vtkObject

    vtkObject.GlobalWarningDisplayOff()
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_ERROR)
    pv.OFF_SCREEN = True
    return pv


def stress_scale_top(part, scale: str = "limit") -> float:
    """MPa: the end of a part picture's von Mises colour scale: ``"limit"``, one for every
    part of a check, a round value at or above the stress limit (375 -> 400 MPa: a 12 MPa
    plate reads cool beside a 176 MPa rail); ``"part"``, a round value at or above the
    part's own verdict peak (190.6 -> 200 MPa). Six labels on it read round values."""
    return nice_top((part.limit if scale == "limit" else part.verdict_stress) / 1e6)


def render_part(path: str | Path, name: str, part, scale: str = "limit") -> PartPicture:
    """A PNG of the part's deformed shape coloured by von Mises at the governing instant
    on the ``scale`` of :func:`stress_scale_top`, with its support, peak, joint forces and
    a caption; written atomically to ``path``. Returns where its labels went."""
    pv = offscreen_pyvista()
    mesh, sol, cycle = part.mesh, part.solution, part.cycle
    extent = np.ptp(mesh.points, axis=0)
    magnified = deformation_scale(float(extent.max()), float(np.linalg.norm(sol.displacement, axis=1).max()))
    slender = extent.max() > 6 * np.sort(extent)[1]
    view = governing_view(name, sol.displacement)
    shown = mesh.points + magnified * sol.displacement
    frame = picture_frame(shown, view, slender)
    size, font = frame.size, frame.font
    plotter = pv.Plotter(off_screen=True, window_size=size)
    top = stress_scale_top(part, scale)
    _stress_surface(pv, plotter, mesh, sol, magnified, top, frame, font)
    _singular_zone(pv, plotter, mesh, sol, magnified, part.verdict_stress, extent.max())
    if part.job.free_body is None:
        _support(pv, plotter, mesh, sol, magnified, part)
    _peak_marker(pv, plotter, cycle, sol, magnified, extent.max())
    ruler = length_scale(plotter, mesh.points, view)
    plotter.add_axes(viewport=frame.triad, line_width=3)
    lines = fit_caption(plotter, picture_caption(name, part, magnified), size, font)

    plotter.enable_parallel_projection()  # "xy": from above, the plane the mechanism moves in
    plotter.camera.tight(padding=0.05, view=view, adjust_render_window=False)
    toward = np.array(plotter.camera.position) - np.array(plotter.camera.focal_point)
    arrow_size = min(extent.max(), 8 * np.sort(extent)[1])
    toward = toward / np.linalg.norm(toward)
    requests = _bolt_arrows(pv, plotter, mesh, sol, magnified, part, cycle, arrow_size, font, toward)
    if view != "xy" and part.job.loads.weight is not None:
        requests.append(weight_arrows(pv, plotter, shown, part, arrow_size, toward))
    frame.place(plotter, lines, shown)
    plotter.render()
    reserved = [frame.bar_box, Box(0.0, 0.0, frame.triad[2] * size[0], frame.triad[3] * size[1])]
    layout = force_labels(plotter, requests, shown, hole_centres(mesh, shown), reserved, ruler, MIN_FONT + 2)
    path = Path(path)
    with atomic_path(path) as tmp:
        plotter.screenshot(str(tmp))
    plotter.close()
    labels, holes, outline, caption = layout
    return PartPicture(path, labels, holes, outline, caption, size)


#: a compact part's picture (px): its width, the part's share of it, the band kept for
#: labels above and below the part, the colour bar's band at the bottom, the tallest picture
COMPACT_WIDTH, COMPACT_SHARE, LABEL_BAND, BAR_BAND, TALLEST = 1800, 0.76, 120, 150, 2400


@dataclass(frozen=True)
class PictureFrame:
    """Where a part picture puts things: its ``size`` (px), the title's ``font``, the
    width share kept free beside the part (each ``side``), the bands above (besides the
    title) and below the part (px), the colour bar's placement and box, the axes' viewport."""

    size: tuple[int, int]
    font: int
    side: float
    above: float
    below: float
    bar: dict
    bar_box: Box
    triad: tuple[float, float, float, float]

    def place(self, plotter, lines: int, shown: np.ndarray) -> None:
        """Scale and centre the view (:func:`leave_room`): the part between the title of
        ``lines`` lines with its band above, and its band and the colour bar below."""
        h = self.size[1]
        title = 1.7 * self.font * (lines + 0.6)
        leave_room(plotter, (title + self.above) / h, self.below / h, self.side, shown, self.side)


def picture_frame(shown: np.ndarray, view: str, slender: bool) -> PictureFrame:
    """A slender part (a rail) on 1600 x 500 px, from edge to edge, its colour bar below;
    a compact one (a plate, the bracket) :data:`COMPACT_SHARE` of an 1800 px width, the
    picture as tall as the part's aspect asks (at most :data:`TALLEST`) with a band for
    labels above and below it and the colour bar at the bottom. The title's font follows
    the width (2 lines of about 110 characters), at least :data:`MIN_FONT`."""
    if slender:
        w, h = 1600, 500
        bar = {"position_x": 0.25, "position_y": 0.05, "width": 0.5, "height": 0.1}
        return PictureFrame(
            (w, h), caption_font_size(h), 0.0, 0.0, 0.2 * h, bar, Box(0.23 * w, 0, 0.77 * w, 0.2 * h), (0.0, 0.0, 0.12, 0.2)
        )
    across, up = ("xyz".index(view[0]), "xyz".index(view[1]))
    aspect = float(np.ptp(shown[:, up]) / max(np.ptp(shown[:, across]), 1e-12))
    w, font = COMPACT_WIDTH, max(MIN_FONT, round(0.0095 * COMPACT_WIDTH))
    fixed = 1.7 * font * 2.6 + 2 * LABEL_BAND + BAR_BAND
    h = int(min(TALLEST, fixed + COMPACT_SHARE * w * aspect))
    bar = {"position_x": 0.25, "position_y": 25.0 / h, "width": 0.5, "height": 80.0 / h}
    return PictureFrame(
        (w, h),
        font,
        (1 - COMPACT_SHARE) / 2,
        LABEL_BAND,
        LABEL_BAND + BAR_BAND,
        bar,
        Box(0.23 * w, 0, 0.77 * w, BAR_BAND),
        (0.0, 0.0, 150.0 / w, 150.0 / h),
    )


def governing_view(name: str, displacement: np.ndarray) -> str:
    """The view a part is drawn in: its kind's (a rail from above, "xy"), or a rail's
    elevation ("xz", from the side) when it moves more out of the mechanism's plane than
    in it (the rocker under the table-top rig's weight): the deformation that governs."""
    view = kind_of(name).view
    largest = np.abs(displacement).max(axis=0)
    return "xz" if view == "xy" and largest[2] > max(largest[0], largest[1]) else view


def weight_arrows(pv, plotter, shown: np.ndarray, part, size: float, toward: np.ndarray) -> tuple:
    """The rail's own weight drawn as eight downward arrows along its top (in front of
    it, as the joint forces are), and its label request: (the middle arrow's tail, words,
    colour)."""
    w = part.job.loads.weight
    front = (shown @ toward).max() + 0.02 * size
    xs = np.linspace(shown[:, 0].min(), shown[:, 0].max(), 10)[1:-1]
    top = shown[:, 2].max()
    tails = []
    for x in xs:
        tail = np.array([x, 0.0, top + 0.12 * size])
        tail += (front - tail @ toward) * toward
        tails.append(tail)
        plotter.add_mesh(pv.Arrow(start=tail, direction=(0.0, 0.0, -1.0), scale=0.1 * size), color="darkorange")
    words = f"own weight {w.mass * 9.80665:.0f} N along it (unfactored), plates' at the joints"
    return tails[len(tails) // 2], words, "darkorange"


def one_two_five(x: float) -> float:
    """The largest of 1, 2, 5 x 10^k not above ``x`` (> 0)."""
    k = 10.0 ** np.floor(np.log10(x))
    return float(max(m * k for m in (1.0, 2.0, 5.0) if m * k <= x * (1 + 1e-12)))


def deformation_scale(size: float, largest: float) -> float:
    """The shape's magnification, one rule for every part: the ``largest`` displacement
    (m) drawn as at most :data:`DEFORMATION_FRACTION` of the part's ``size`` (m), rounded
    down to 1-2-5 steps and never above :data:`MAX_MAGNIFICATION` (a deformation smaller
    than that shows small, as it is, not blown up into a crushed shape); 0 without one."""
    if not largest > 0:
        return 0.0
    return min(one_two_five(DEFORMATION_FRACTION * size / largest), MAX_MAGNIFICATION)


def length_scale(plotter, points: np.ndarray, view: str) -> np.ndarray:
    """A ruler in mm under the part (undeformed coordinates), along the picture's
    horizontal axis, about a quarter of the part's width long (1-2-5); returns its two
    ends (2, 3) m."""
    across, up = "xyz".index(view[0]), "xyz".index(view[1])
    lo, hi = points.min(axis=0), points.max(axis=0)
    length = one_two_five(0.25 * (hi[across] - lo[across]))
    a = lo.copy()
    a[up] = lo[up] - 0.12 * max(hi[up] - lo[up], 0.02 * (hi[across] - lo[across]))
    b = a.copy()
    b[across] += length
    plotter.add_ruler(a, b, title="mm", number_labels=2, scale=1e3, label_format="%.0f", tick_length=4)
    return np.array([a, b])


def colour_bar_args(title: str, fmt: str, frame: PictureFrame, font: int) -> dict:
    """pyvista's colour-bar arguments of every part picture: below the part, where its
    ``frame`` puts it; six labels in ``fmt``."""
    return {
        "title": title,
        "vertical": False,
        "fmt": fmt,
        "n_labels": 6,
        "title_font_size": font,
        "label_font_size": font,
        **frame.bar,
    }


def _stress_surface(pv, plotter, mesh, sol, scale: float, top: float, frame: PictureFrame, font: int) -> None:
    """The part's surface displaced ``scale`` x its displacement, coloured by von Mises
    from 0 to ``top`` MPa, with its colour bar (where ``frame`` puts it); above ``top``
    red, with its swatch (none when nothing is)."""
    beyond = bool(sol.von_mises.max() / 1e6 > top * (1 + 1e-9))
    cells = np.hstack([np.full((mesh.tets.shape[0], 1), 4), mesh.tets]).ravel()
    grid = pv.UnstructuredGrid(
        cells, np.full(mesh.tets.shape[0], pv.CellType.TETRA, dtype=np.uint8), mesh.points + scale * sol.displacement
    )
    grid.point_data["von Mises (MPa)"] = sol.von_mises / 1e6
    plotter.add_mesh(
        grid.extract_surface(algorithm="dataset_surface"),
        scalars="von Mises (MPa)",
        cmap=COLOUR_MAP,
        clim=[0.0, top],
        above_color="red" if beyond else None,
        show_edges=False,
        scalar_bar_args=colour_bar_args("von Mises (MPa)", colour_bar_format(top), frame, font),
    )


def _singular_zone(pv, plotter, mesh, sol, scale: float, verdict: float, size: float) -> None:
    """Magenta dots on the vertices above the verdict's peak ``verdict`` (Pa): the clamp's
    singular zone, which the verdict leaves out (none on a free body)."""
    n = mesh.points.shape[0]
    above = np.flatnonzero(sol.von_mises[:n] > verdict * (1 + 1e-9))
    if above.size:
        pts = mesh.points[above] + scale * sol.displacement[above]
        plotter.add_points(pv.PolyData(pts), color="magenta", point_size=6)


def picture_caption(name: str, part, scale: float) -> str:
    """The picture's two-line title: the verdict, its utilisation and what governs, the
    cycle peak and when; the deflection this part's support gives, the shape's scale, the
    support (in the words of the report's equilibrium table) and the forces' factor."""
    cycle = part.cycle
    when = f"at crank {cycle.history.crank_angle_deg:.1f} deg" if cycle.C.shape[0] > 1 else "under constant loads"
    deflection = (
        "tip deflection"
        if part.job.free_body is None
        else "bore deflection vs screws"
        if part.job.loads.is_free_plate
        else "top deflection vs base"
        if part.job.loads.is_on_foundation
        else "deflection vs joints"
    )
    verdict = "PASS" if part.passed else "FAIL"
    governs = part.governing_criterion
    fat = cycle.fatigue
    figure = (
        f"fatigue n {fat.min_safety_factor:.2f} against {fat.required:g}"
        if governs == "fatigue"
        else f"stress against {part.limit / 1e6:.0f} MPa"
        if governs == "stress"
        else governs
    )
    factored = "as given" if part.job.loads.explicit is not None else f"x{part.job.loads.factor:g} (factored)"
    return (
        f"{name}: {verdict}, utilisation {part.utilisation:.0%} ({figure}), "
        f"peak {part.verdict_stress / 1e6:.1f} MPa (sphere) {when}\n"
        f"{deflection} {cycle.envelope.max_tip * 1e3:.3g} mm, shape x{scale:g}; {support_words(part)}; "
        f"red: forces {factored}" + ("; weight out of plane" if part.job.loads.weight is not None else "")
    )


def _group_points(mesh, sol, scale, groups) -> np.ndarray:
    idx = np.unique(np.concatenate([mesh.groups[g].ravel() for g in groups]))
    return mesh.points[idx] + scale * sol.displacement[idx]


def leave_room(
    plotter, top: float, bottom: float, right: float, points: np.ndarray | None = None, left: float = 0.0
) -> None:
    """Shift and scale the view so the part fills the picture between the caption (the
    top ``top`` of the height), the colour bar (``bottom`` of the height, or ``right`` of
    the width), ``left`` of the width kept free (for labels) and the edges: a parallel
    projection's scale is half the visible height.
    With the part's ``points`` (n, 3) m the scale is the least that fits their extent in
    both directions (5% margin), so a rail fills the width of its band; without, the
    camera's own fit shrunk into the free area."""
    cam = plotter.camera
    free_h = max(0.3, 1.0 - top - bottom)
    free_w = max(0.3, 1.0 - right - left)
    aspect = plotter.window_size[0] / plotter.window_size[1]
    up = np.array(cam.up, float)
    up /= np.linalg.norm(up)
    view = np.array(cam.focal_point) - np.array(cam.position)
    view /= np.linalg.norm(view)
    side = np.cross(view, up)
    if points is None:
        scale = cam.parallel_scale / min(free_h, free_w)
    else:
        across, upward = np.ptp(points @ side), np.ptp(points @ up)
        scale = 1.05 * max(upward / (2.0 * free_h), across / (2.0 * free_w * aspect))
        centre = points.min(axis=0) + np.ptp(points, axis=0) / 2.0  # the view centred on the part first
        offset = centre - np.array(cam.focal_point)
        offset -= (offset @ view) * view
        cam.focal_point = tuple(np.array(cam.focal_point) + offset)
        cam.position = tuple(np.array(cam.position) + offset)
    h = 2.0 * scale
    w = h * aspect
    shift = up * (top - bottom) / 2.0 * h + side * (right - left) / 2.0 * w  # below the caption, between the bars
    cam.focal_point = tuple(np.array(cam.focal_point) + shift)
    cam.position = tuple(np.array(cam.position) + shift)
    cam.parallel_scale = scale


def _support(pv, plotter, mesh, sol, scale, part) -> None:
    pts = _group_points(mesh, sol, scale, [part.load_case.support])
    plotter.add_points(pv.PolyData(pts), color="black", point_size=9, render_points_as_spheres=True)


def _bolt_arrows(pv, plotter, mesh, sol, scale, part, cycle, size, font, toward) -> list[tuple]:
    """An arrow per loaded hole, at its centre, along the joint force of the governing
    instant on it: the bolts' (``bolt_x``, ``bolt_y``) and, on a free body, the first
    joint's two screws (``pin_x``, ``pin_y``); each arrow sits in front of the part (moved
    toward the camera, ``toward`` a unit vector, beyond the part's nearest point), so no
    flange hides it. Returns each group of holes' label: (the arrows' mean tail (3,) m, the
    joint force's magnitude in words), placed by :func:`force_labels`."""
    front = (mesh.points @ toward).max() + 0.02 * size  # the part's nearest point to the camera, and a margin
    labels: list[tuple] = []
    for holes, force, words in _drawn_forces(part):
        if not np.any(force):
            continue
        direction = force / np.linalg.norm(force)
        length = 0.18 * size
        tails = []
        for hole in holes:
            centre = _group_points(mesh, sol, scale, [hole]).mean(axis=0)
            centre += (front - centre @ toward) * toward  # in front of the part, on the line of sight
            tails.append(centre - direction * length)
            plotter.add_mesh(pv.Arrow(start=tails[-1], direction=direction, scale=length), color="red")
        if words is not None:
            labels.append((np.mean(tails, axis=0), words))
    return labels


def _drawn_forces(part) -> list:
    """[(holes, force (3,) N in the part's frame, its label or None)] of
    :func:`railcheck.report.forces.governing_forces`, each label with the load factor; the
    motor couple labelled with the first joint's screws, so the labels do not overlap."""
    factored = "" if part.job.loads.explicit is not None else f" x{part.job.loads.factor:g}"
    out: list[tuple[list, np.ndarray, str | None]] = []
    pin = None
    for f in governing_forces(part):
        if f.couple is not None:
            pin = f
            out.append((list(f.holes), f.force, None))
        elif f.holes == ("hole_0", "hole_1"):
            out.append((list(f.holes), f.force, f"{newtons(f.force)} on the plate's 2 screws{factored}"))
        else:
            bolts = f" on {len(f.holes)} screws" if len(f.holes) > 1 else ""
            out.append((list(f.holes), f.force, f"{newtons(f.force)}{bolts}{factored}"))
    if pin is not None:  # its words under the first joint's
        k = next(i for i, (holes, _, _) in enumerate(out) if holes == ["hole_0", "hole_1"])
        holes, force, label = out[k]
        words = f"\n+-{newtons(pin.force)} across: motor {abs(pin.couple or 0.0):.0f} N·m{factored}"
        out[k] = (holes, force, (label or "") + words)
    return out


def _peak_marker(pv, plotter, cycle, sol, scale, size) -> None:
    """A white sphere at the peak's node; its value is in the caption ("the white
    sphere"), not in a label beside it: a peak by a joint used to cover that joint's force
    label."""
    node = cycle.envelope.node
    where = cycle.fields.nodes[node] + scale * sol.node_displacement[node]
    plotter.add_mesh(pv.Sphere(radius=0.012 * size, center=where), color="white")
