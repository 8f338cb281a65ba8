"""PNG of a part's utilisation at every point over the whole cycle (PART-utilisation.png),
beside the von Mises picture of its governing instant: each vertex's larger of its von
Mises envelope over the stress limit and the required fatigue factor over its own. One
colour scale for every part (logarithmic, 1% to 100%, above it red: fails there), on the
undeformed shape (the envelope is over the cycle, not one instant). pyvista, off-screen."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railcheck.files import atomic_path
from railcheck.parts import kind_of
from railcheck.report.render import (
    COLOUR_MAP,
    colour_bar_args,
    fit_caption,
    length_scale,
    offscreen_pyvista,
    picture_frame,
)
from railcheck.report.vtu import node_envelope


def node_utilisation(part) -> np.ndarray | None:
    """(vertices,) each vertex's utilisation over the cycle (1 = at its limit): the larger
    of its von Mises envelope over the part's stress limit and the required fatigue factor
    over its own; None when the node fields were not kept."""
    fat = part.cycle.fatigue
    if fat.node_factor is None:
        return None
    n = part.mesh.points.shape[0]  # the P2 nodes list the mesh's vertices first
    stress = node_envelope(part)[:n] / part.limit
    with np.errstate(divide="ignore"):
        fatigue = np.where(fat.node_factor[:n] > 0, fat.required / fat.node_factor[:n], np.inf)
    return np.maximum(stress, fatigue)


def utilisation_caption(name: str, part, largest: float) -> str:
    """What the picture shows, the part's verdict utilisation and what governs it."""
    fat = part.cycle.fatigue
    return (
        f"{name}: utilisation over the cycle, the larger of von Mises envelope / {part.limit / 1e6:.0f} MPa "
        f"and {fat.required:g} / fatigue factor\n"
        f"the part {part.utilisation:.0%} ({part.governing_criterion}), largest drawn {largest:.0%}; "
        "one log scale for every part, red above 100%; undeformed"
    )


def render_utilisation(path: str | Path, name: str, part) -> Path | None:
    """Write the part's utilisation picture to ``path``; None without node fields."""
    u = node_utilisation(part)
    if u is None:
        return None
    pv = offscreen_pyvista()
    mesh = part.mesh
    extent = np.ptp(mesh.points, axis=0)
    slender = extent.max() > 6 * np.sort(extent)[1]
    view = kind_of(name).view
    frame = picture_frame(mesh.points, view, slender)
    plotter = pv.Plotter(off_screen=True, window_size=frame.size)
    _surface(pv, plotter, mesh, u, frame, frame.font)
    length_scale(plotter, mesh.points, view)
    plotter.add_axes(viewport=frame.triad, line_width=3)
    lines = fit_caption(plotter, utilisation_caption(name, part, float(np.max(u))), frame.size, frame.font)
    plotter.enable_parallel_projection()
    plotter.camera.tight(padding=0.05, view=view, adjust_render_window=False)
    frame.place(plotter, lines, mesh.points)
    path = Path(path)
    with atomic_path(path) as tmp:
        plotter.screenshot(str(tmp))
    plotter.close()
    return path


#: the utilisation picture's scale (%): logarithmic from 1% (below it the lowest colour) to
#: 100% (above it red), so a part used at 5% shows where, not a uniform dark
UTILISATION_SCALE = (1.0, 100.0)


def _surface(pv, plotter, mesh, u: np.ndarray, frame, font: int) -> None:
    """The part's surface coloured by utilisation (%) on :data:`UTILISATION_SCALE`
    (logarithmic: 1, 10, 100 labelled), red above 100%."""
    cells = np.hstack([np.full((mesh.tets.shape[0], 1), 4), mesh.tets]).ravel()
    grid = pv.UnstructuredGrid(cells, np.full(mesh.tets.shape[0], pv.CellType.TETRA, dtype=np.uint8), mesh.points)
    low, high = UTILISATION_SCALE
    grid.point_data["utilisation (%)"] = np.clip(100.0 * u, low, None)
    plotter.add_mesh(
        grid.extract_surface(algorithm="dataset_surface"),
        scalars="utilisation (%)",
        cmap=COLOUR_MAP,
        clim=[low, high],
        log_scale=True,
        above_color="red" if np.max(u) > 1.0 else None,
        scalar_bar_args={**colour_bar_args("utilisation (%), log scale", "%.0f", frame, font), "n_labels": 3},
    )
