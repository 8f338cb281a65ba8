"""PNG of a part's von Mises field on its deformed shape (pyvista, off-screen).

The displacement is magnified so that the largest one is 5% of the part's size; the
scale factor is printed on the image. pyvista is imported here only.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .files import atomic_path


def render_part(path: str | Path, name: str, part) -> Path:
    os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")
    import pyvista as pv

    pv.OFF_SCREEN = True
    mesh, sol = part.mesh, part.solution
    pts = mesh.points
    cells = np.hstack([np.full((mesh.tets.shape[0], 1), 4), mesh.tets]).ravel()
    grid = pv.UnstructuredGrid(cells, np.full(mesh.tets.shape[0], pv.CellType.TETRA, dtype=np.uint8), pts)
    umax = float(np.abs(sol.displacement).max())
    extent = float(np.ptp(pts, axis=0).max())
    scale = 0.05 * extent / umax if umax > 0 else 0.0
    grid.points = pts + scale * sol.displacement
    grid.point_data["von Mises (MPa)"] = sol.von_mises / 1e6
    plotter = pv.Plotter(off_screen=True, window_size=(1200, 700))
    # the colour scale ends at the verdict peak: the clamped support's singular values above
    # it would otherwise turn the whole part blue; they show in magenta
    top = max(part.verdict_stress / 1e6, 1e-9)
    plotter.add_mesh(grid.extract_surface(algorithm="dataset_surface"), scalars="von Mises (MPa)", cmap="jet",
                     clim=[0.0, top], above_color="magenta", show_edges=False,
                     scalar_bar_args={"title": "von Mises (MPa)", "vertical": True})
    plotter.add_text(f"{name}: max von Mises {part.verdict_stress/1e6:.1f} MPa away from the support "
                     f"({sol.max_von_mises/1e6:.1f} MPa at it), limit {part.limit/1e6:.0f} MPa, "
                     f"tip {sol.tip_deflection*1e3:.3f} mm\ndeformation x {scale:.3g}; magenta: above the verdict peak "
                     f"(the support's singular zone)", font_size=10)
    plotter.view_isometric()
    plotter.camera.zoom(1.2 if extent < 0.3 else 1.0)
    path = Path(path)
    with atomic_path(path) as tmp:
        plotter.screenshot(str(tmp))
    plotter.close()
    return path
