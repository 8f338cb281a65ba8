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
from pathlib import Path

import numpy as np

from railcheck.files import atomic_path
from railcheck.parts import kind_of
from railcheck.report.forces import governing_forces, newtons

DEFORMATION_FRACTION = 0.05  # of the part's largest dimension
MAX_MAGNIFICATION = 1000.0  # beyond it a tiny deformation would be drawn as a crushed shape
COLOUR_MAP = "viridis"
CAPTION_FRACTION = 0.02  # caption font size, of the picture's height (VTK renders a line ~1.6x the size: ~3%)
MIN_FONT = 14  # the smallest font size of any text on the picture (labels, colour bar)
CHAR_WIDTH = 0.75  # a caption character's width, of the font size (a first guess; fit_caption measures)


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


def render_part(path: str | Path, name: str, part) -> Path:
    """A PNG of the part's deformed shape coloured by von Mises at the governing instant,
    with its support, peak, joint forces and a caption; written atomically to ``path``."""
    pv = offscreen_pyvista()
    mesh, sol, cycle = part.mesh, part.solution, part.cycle
    extent = np.ptp(mesh.points, axis=0)
    scale = deformation_scale(float(extent.max()), float(np.linalg.norm(sol.displacement, axis=1).max()))
    slender = extent.max() > 6 * np.sort(extent)[1]
    size = (1600, 500) if slender else (1200, 1000)
    plotter = pv.Plotter(off_screen=True, window_size=size)
    font = caption_font_size(size[1])
    top = max(part.verdict_stress / 1e6, 1e-9)
    beyond = bool(sol.von_mises.max() / 1e6 > top * (1 + 1e-9))  # a clamp's singular zone above the verdict's peak
    _stress_surface(pv, plotter, mesh, sol, scale, top, slender, font, beyond)
    if part.job.free_body is None:
        _support(pv, plotter, mesh, sol, scale, part)
    _peak_marker(pv, plotter, cycle, sol, scale, extent.max())
    length_scale(plotter, mesh.points, kind_of(name).view)
    plotter.add_axes(viewport=(0.0, 0.0, 0.12, 0.2) if slender else (0.0, 0.0, 0.15, 0.15), line_width=3)
    lines = fit_caption(plotter, picture_caption(name, part, scale), size, font)

    plotter.enable_parallel_projection()  # "xy": from above, the plane the mechanism moves in
    plotter.camera.tight(padding=0.05 if slender else 0.12, view=kind_of(name).view, adjust_render_window=False)
    toward = np.array(plotter.camera.position) - np.array(plotter.camera.focal_point)
    arrow_size = min(extent.max(), 8 * np.sort(extent)[1])
    _bolt_arrows(pv, plotter, mesh, sol, scale, part, cycle, arrow_size, font, toward / np.linalg.norm(toward))
    caption_share = 1.7 * font * (lines + 0.6) / size[1]  # of the height, above the part
    leave_room(plotter, caption_share, 0.2 if slender else 0.1, 0.0 if slender else 0.16)
    path = Path(path)
    with atomic_path(path) as tmp:
        plotter.screenshot(str(tmp))
    plotter.close()
    return path


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


def length_scale(plotter, points: np.ndarray, view: str) -> None:
    """A ruler in mm under the part (undeformed coordinates), along the picture's
    horizontal axis, about a quarter of the part's width long (1-2-5)."""
    across, up = "xyz".index(view[0]), "xyz".index(view[1])
    lo, hi = points.min(axis=0), points.max(axis=0)
    length = one_two_five(0.25 * (hi[across] - lo[across]))
    a = lo.copy()
    a[up] = lo[up] - 0.12 * max(hi[up] - lo[up], 0.02 * (hi[across] - lo[across]))
    b = a.copy()
    b[across] += length
    plotter.add_ruler(a, b, title="mm", number_labels=2, scale=1e3, label_format="%.0f", tick_length=4)


def colour_bar_args(title: str, fmt: str, slender: bool, font: int) -> dict:
    """pyvista's colour-bar arguments of every part picture: below a slender part, else
    beside it; six labels in ``fmt``."""
    place = (
        {"position_x": 0.25, "position_y": 0.05, "width": 0.5, "height": 0.1}
        if slender
        else {"position_x": 0.86, "position_y": 0.08, "width": 0.08, "height": 0.55}
    )
    return {
        "title": title,
        "vertical": not slender,
        "fmt": fmt,
        "n_labels": 6,
        "title_font_size": font,
        "label_font_size": font,
        **place,
    }


def _stress_surface(pv, plotter, mesh, sol, scale: float, top: float, slender: bool, font: int, beyond: bool) -> None:
    """The part's surface displaced ``scale`` x its displacement, coloured by von Mises
    from 0 to ``top`` MPa, with its colour bar (below a slender part, else beside it);
    ``beyond``: some of it lies above ``top`` (magenta, with its swatch; else no swatch)."""
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
        above_color="magenta" if beyond else None,
        show_edges=False,
        scalar_bar_args=colour_bar_args("von Mises (MPa)", colour_bar_format(top), slender, font),
    )


def picture_caption(name: str, part, scale: float) -> str:
    """The picture's caption: the cycle peak and when, the limit, the deflection and what
    it means for this part's support, the shape's scale and what the colours mark."""
    cycle = part.cycle
    when = (
        f"at crank {cycle.history.crank_angle_deg:.1f} deg" if cycle.C.shape[0] > 1 else "under its constant explicit loads"
    )
    deflection = (
        "tip deflection"
        if part.job.free_body is None
        else "the shaft bore's deflection relative to the screws"
        if part.job.loads.is_free_plate
        else "top deflection relative to the base"
        if part.job.loads.is_on_foundation
        else "deflection relative to the joints"
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
    return (
        f"{name}: {verdict}, utilisation {part.utilisation:.0%} ({figure}); "
        f"cycle peak {part.verdict_stress / 1e6:.1f} MPa (the white sphere) {when} (limit {part.limit / 1e6:.0f} MPa)\n"
        f"largest {deflection} {cycle.envelope.max_tip * 1e3:.3g} mm; "
        f"shape x{scale:g} (one rule for every part: largest displacement <= 5% of its size, 1-2-5, <= x1000)\n"
        + (
            "on a rigid foundation: its base carries the loads' linear reaction (not drawn); red: loads as given"
            if part.job.loads.is_on_foundation
            else f"free body: no support (inertia relief); red: joint forces x{part.job.loads.factor:g} (factored)"
            if part.job.free_body is not None
            else f"black: the clamp; magenta: its singular zone; red: joint force x{part.job.loads.factor:g} (factored)"
        )
        + ("; its weight out of plane (table-top rig, not drawn)" if part.job.loads.weight is not None else "")
    )


def _group_points(mesh, sol, scale, groups) -> np.ndarray:
    idx = np.unique(np.concatenate([mesh.groups[g].ravel() for g in groups]))
    return mesh.points[idx] + scale * sol.displacement[idx]


def leave_room(plotter, top: float, bottom: float, right: float) -> None:
    """Shift and shrink the view so the part fills the picture between the caption (the
    top ``top`` of the height), the colour bar (``bottom`` of the height, or ``right`` of
    the width) and the edges: a parallel projection's scale is half the visible height."""
    cam = plotter.camera
    free_h = max(0.3, 1.0 - top - bottom)
    free_w = max(0.3, 1.0 - right)
    scale = cam.parallel_scale / min(free_h, free_w)
    h = 2.0 * scale
    w = h * plotter.window_size[0] / plotter.window_size[1]
    dy = (top - bottom) / 2.0 * h  # move the view up so the part sits below the caption
    dx = right / 2.0 * w
    up = np.array(cam.up, float)
    up /= np.linalg.norm(up)
    view = np.array(cam.focal_point) - np.array(cam.position)
    view /= np.linalg.norm(view)
    side = np.cross(view, up)
    shift = up * dy + side * dx
    cam.focal_point = tuple(np.array(cam.focal_point) + shift)
    cam.position = tuple(np.array(cam.position) + shift)
    cam.parallel_scale = scale


def _support(pv, plotter, mesh, sol, scale, part) -> None:
    pts = _group_points(mesh, sol, scale, [part.load_case.support])
    plotter.add_points(pv.PolyData(pts), color="black", point_size=9, render_points_as_spheres=True)


def _bolt_arrows(pv, plotter, mesh, sol, scale, part, cycle, size, font, toward) -> None:
    """An arrow per loaded hole, at its centre, along the joint force of the governing
    instant on it: the bolts' (``bolt_x``, ``bolt_y``) and, on a free body, the first
    joint's two screws (``pin_x``, ``pin_y``); drawn over the part and labelled with the joint
    force's magnitude (N) once per group of holes; each arrow sits in front of the part
    (moved toward the camera, ``toward`` a unit vector, beyond the part's nearest point), so
    no flange hides it."""
    front = (mesh.points @ toward).max() + 0.02 * size  # the part's nearest point to the camera, and a margin
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
        if words is None:
            continue
        plotter.add_point_labels(
            pv.PolyData(np.mean(tails, axis=0)[None, :]),
            [words],
            font_size=font,
            text_color="red",
            point_size=1,
            shape_opacity=0.6,
            always_visible=True,
        )


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
