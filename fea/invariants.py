"""Von Mises of stress components: the one formula, numpy only (the scene and the fatigue
criteria read it without the FE stack). Components (6, ...) in the order xx, yy, zz, xy,
yz, xz; Pa."""

from __future__ import annotations

import numpy as np

#: von Mises squared as a quadratic form of the six stress components (xx, yy, zz, xy, yz, xz)
VM_QUADRATIC = np.array(
    [
        [1.0, -0.5, -0.5, 0, 0, 0],
        [-0.5, 1.0, -0.5, 0, 0, 0],
        [-0.5, -0.5, 1.0, 0, 0, 0],
        [0, 0, 0, 3.0, 0, 0],
        [0, 0, 0, 0, 3.0, 0],
        [0, 0, 0, 0, 0, 3.0],
    ]
)


def von_mises(s: np.ndarray) -> np.ndarray:
    """Von Mises stress (Pa) of stress components (6, ...) Pa (xx, yy, zz, xy, yz, xz)."""
    return np.sqrt(von_mises_squared(s))


def von_mises_squared(s: np.ndarray) -> np.ndarray:
    """Von Mises stress squared (Pa^2) of stress components (6, ...) Pa: a maximum needs
    one square root, not one per entry."""
    sxx, syy, szz, sxy, syz, sxz = s
    return 0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3.0 * (sxy**2 + syz**2 + sxz**2)
