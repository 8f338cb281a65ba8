"""Load histories over the crank cycle: the coefficient of each unit load case at every
step (the cycle envelope superposes unit-load stress fields with them).

Part frame: x along the part's longitudinal axis, y the in-plane transverse axis, z the
normal of the mechanism's plane. Shapes ``(steps, k)``; units in each function's doc.
"""

from __future__ import annotations

import numpy as np

from .rotation import to_rail_axes


def bolt_history(force_xy: np.ndarray, bar_angle: np.ndarray | float, factor: float) -> np.ndarray:
    """(steps, 2) N: the factored force on the part at a joint in its axes
    (longitudinal, transverse). ``force_xy`` (steps, 2) N in the ground frame, ``bar_angle``
    (steps,) rad of the part's longitudinal axis (0: the ground frame)."""
    return factor * to_rail_axes(force_xy, bar_angle)


def gravity_history(bar_angle: np.ndarray, density: float, g: float) -> np.ndarray:
    """(..., 2) N/m^3 (the shape of ``bar_angle`` plus 2): the self-weight body force in the part's axes, for a vertical
    rig whose ground frame has +y up: rho g (0, -1) rotated by -angle."""
    angle = np.asarray(bar_angle, float)
    down = np.broadcast_to(np.array([0.0, -density * g]), angle.shape + (2,))
    return to_rail_axes(down, angle)


def rail_inertia_history(
    pivot_acceleration: np.ndarray, bar_angle: np.ndarray, omega: np.ndarray, alpha: np.ndarray, density: float
) -> np.ndarray:
    """(..., 4) (leading dimensions of the inputs): coefficients of the rail's d'Alembert body force ``-rho a(r)`` for the
    rigid-body field a(r) = a_pivot + alpha k x r - omega^2 r (r from the pivot, part
    frame). Columns: uniform x and y (N/m^3), the rotational field (-r_y, r_x) and the
    radial field (r_x, r_y) (N/m^4 per m of r): (-rho a_l, -rho a_t, -rho alpha, rho omega^2).
    ``pivot_acceleration`` (steps, 2) m/s^2 ground frame; ``omega``, ``alpha`` (steps,) of the bar."""
    a = to_rail_axes(pivot_acceleration, bar_angle)
    return np.stack(
        np.broadcast_arrays(-density * a[..., 0], -density * a[..., 1], -density * alpha, density * omega**2), axis=-1
    )
