"""The interactive page of a planar mechanism study (seed 002's CDF document, offline):
the drawing over the driver with a slider and play/pause, the traced point's path and, on
demand, its velocity; each joint's reaction and each drive's effort over the cycle as
plots with a cursor at the drawn step. One file, no network."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railcheck.studies.mechanism import page_data, write_page
from railcheck.studies.planar_study import PlanarStudy, driver_shown


def planar_page_data(study: PlanarStudy) -> dict:
    """The page's data: the drawing (mm), the first tracer's velocity (mm/s) and the plots
    (each joint's reaction magnitude in N, each drive's effort in N m or N)."""
    driver, unit = driver_shown(study)
    first = next(iter(study.tracers.values()))
    data = page_data(study.mechanism, study.motion, first[:, :2], driver, unit)
    data["velocity"] = np.round(first[:, 2:4] * 1e3, 6).tolist()
    r = study.reactions
    plots = [
        {"name": f"joint {name} reaction", "unit": "N", "values": np.round(np.hypot(f[:, 0], f[:, 1]), 9).tolist()}
        for name, f in r.forces.items()
    ]
    for d in study.mechanism.drivers:
        effort_unit = "N m" if type(d).__name__ == "RotationDriver" else "N"
        plots.append({"name": f"{d.name} effort", "unit": effort_unit, "values": np.round(r.efforts[d.name], 9).tolist()})
    masses = any(b.mass for b in study.mechanism.bodies)
    data["plots"] = plots if masses or study.scene.gravity else []
    data["plots_note"] = (
        f"at {abs(study.scene.rate):.4g} {'rad/s' if unit == 'deg' else 'm/s'} of the driver, gravity "
        f"{study.scene.gravity:g} m/s2 along -y; rigid bodies, ideal joints"
    )
    return data


def write_planar_page(path: Path, study: PlanarStudy) -> None:
    """mechanism.html of a planar study."""
    write_page(path, planar_page_data(study))
