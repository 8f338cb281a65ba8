"""PNG of a part's von Mises field at its governing instant on the deformed shape
(pyvista, off-screen; imported here only).

What an engineer reads on it: the part framed to fill the picture, seen from above (the
plane the mechanism moves and the rails bend in), a perceptually uniform
colour map (viridis) ending at the verdict peak, the support's singular zone above it in
magenta, the support's surface in grey, an arrow per loaded bolt hole along its force,
and a marker with its label at the verdict peak. The displacement is magnified so the
largest one is 5% of the part's size; the factor is printed on the picture.

Rendering needs no X server: without a DISPLAY, VTK's EGL window is used (no warning on
the console).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from railcheck.files import atomic_path
from railcheck.parts import kind_of

DEFORMATION_FRACTION = 0.05  # of the part's largest dimension
COLOUR_MAP = "viridis"


def _pyvista():
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
    pv = _pyvista()
    mesh, sol, cycle = part.mesh, part.solution, part.cycle
    pts = mesh.points
    extent = np.ptp(pts, axis=0)
    umax = float(np.abs(sol.displacement).max())
    scale = DEFORMATION_FRACTION * extent.max() / umax if umax > 0 else 0.0
    cells = np.hstack([np.full((mesh.tets.shape[0], 1), 4), mesh.tets]).ravel()
    grid = pv.UnstructuredGrid(
        cells, np.full(mesh.tets.shape[0], pv.CellType.TETRA, dtype=np.uint8), pts + scale * sol.displacement
    )
    grid.point_data["von Mises (MPa)"] = sol.von_mises / 1e6
    slender = extent.max() > 6 * np.sort(extent)[1]
    plotter = pv.Plotter(off_screen=True, window_size=(1600, 560) if slender else (1200, 900))
    top = max(part.verdict_stress / 1e6, 1e-9)
    plotter.add_mesh(
        grid.extract_surface(algorithm="dataset_surface"),
        scalars="von Mises (MPa)",
        cmap=COLOUR_MAP,
        clim=[0.0, top],
        above_color="magenta",
        show_edges=False,
        scalar_bar_args={
            "title": "von Mises (MPa)",
            "vertical": not slender,
            "fmt": "%.0f",
            **({"position_x": 0.3, "position_y": 0.04, "width": 0.4, "height": 0.08} if slender else {}),
        },
    )
    if part.job.free_body is None:
        _support(pv, plotter, mesh, sol, scale, part)
    _bolt_arrows(pv, plotter, mesh, sol, scale, part, cycle, min(extent.max(), 8 * np.sort(extent)[1]))
    _peak_marker(pv, plotter, cycle, sol, scale, extent.max(), part)
    when = (
        f"at crank {cycle.history.crank_angle_deg:.1f} deg" if cycle.C.shape[0] > 1 else "under its constant explicit loads"
    )
    plotter.add_text(
        f"{name}: cycle peak {part.verdict_stress / 1e6:.1f} MPa {when} (limit {part.limit / 1e6:.0f} MPa, FoS "
        f"{part.limit / max(part.verdict_stress, 1e-9):.3g}); largest "
        f"{'deflection relative to the joints' if part.job.free_body is not None else 'tip deflection'} "
        f"{cycle.envelope.max_tip * 1e3:.3g} mm\n"
        f"deformation x {scale:.3g} (largest displacement = {DEFORMATION_FRACTION:.0%} of the part); "
        + (
            "free body (no support: inertia relief); arrows: the joints' forces on the first hole and the bolts"
            if part.job.free_body is not None
            else "magenta: above the verdict peak (the support's singular zone); grey: support; arrows: bolt forces"
        ),
        font_size=9,
    )

    plotter.enable_parallel_projection()  # "xy": from above, the plane the mechanism moves in
    plotter.camera.tight(padding=0.05 if slender else 0.12, view=kind_of(name).view, adjust_render_window=False)
    if slender:
        plotter.camera.zoom(0.9)  # room for the title above and the colour bar below
    path = Path(path)
    with atomic_path(path) as tmp:
        plotter.screenshot(str(tmp))
    plotter.close()
    return path


def _group_points(mesh, sol, scale, groups) -> np.ndarray:
    idx = np.unique(np.concatenate([mesh.groups[g].ravel() for g in groups]))
    return mesh.points[idx] + scale * sol.displacement[idx]


def _support(pv, plotter, mesh, sol, scale, part) -> None:
    pts = _group_points(mesh, sol, scale, [part.load_case.support])
    plotter.add_points(pv.PolyData(pts), color="grey", point_size=6, render_points_as_spheres=True)


def _bolt_arrows(pv, plotter, mesh, sol, scale, part, cycle, size) -> None:
    """An arrow per loaded hole, at its centre, along the joint force of the governing
    instant on it: the bolts' (``bolt_x``, ``bolt_y``) and, on a free body, the first
    hole's pin (``pin_x``, ``pin_y``)."""
    c, names = cycle.C[cycle.envelope.step], list(cycle.fields.names)
    loads = [([b.group for b in part.load_case.bolts], "bolt")]
    if "pin_x" in names:
        loads.append((["hole_0"], "pin"))
    above = mesh.points[:, 2].max() + 0.02 * size  # drawn over the part, seen from above
    for holes, case in loads:
        force = np.array([c[names.index(f"{case}_x")], c[names.index(f"{case}_y")], 0.0])
        if not np.any(force):
            continue
        direction = force / np.linalg.norm(force)
        for hole in holes:
            centre = _group_points(mesh, sol, scale, [hole]).mean(axis=0)
            centre[2] = above
            length = 0.18 * size
            plotter.add_mesh(pv.Arrow(start=centre - direction * length, direction=direction, scale=length), color="red")


def _peak_marker(pv, plotter, cycle, sol, scale, size, part) -> None:
    node = cycle.envelope.node
    where = cycle.fields.nodes[node] + scale * sol.node_displacement[node]
    plotter.add_mesh(pv.Sphere(radius=0.012 * size, center=where), color="white")
    plotter.add_point_labels(
        pv.PolyData(where[None, :]),
        [f"peak {part.verdict_stress / 1e6:.1f} MPa"],
        font_size=14,
        point_color="white",
        point_size=1,
        shape_opacity=0.7,
        always_visible=True,
    )
