"""Reactions from the ground frame into a rail's own axes.

A bar at angle ``theta`` (rad, counter-clockwise from the ground's +x) has its
longitudinal axis ``e_l = (cos theta, sin theta)`` and its in-plane transverse axis
``e_t = (-sin theta, cos theta)``. A force ``F`` (N, ground frame) has components
``(F . e_l, F . e_t)`` there: ``R(-theta) F``. Vectorised over leading dimensions.
"""

from __future__ import annotations

import numpy as np


def to_rail_axes(force_xy, theta) -> np.ndarray:
    """(..., 2) forces in the ground frame -> (..., 2) (longitudinal, transverse), N."""
    f = np.asarray(force_xy, float)
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([c * f[..., 0] + s * f[..., 1], -s * f[..., 0] + c * f[..., 1]], axis=-1)
