"""The coefficients of a pin's bearing pressure (:mod:`railcheck.fea.pin_pressure` builds the
fields): a force F = (Fx, Fy) N on a hole, as a cosine pressure over the loaded half of
its bore, is ``Fx`` and ``Fy`` on the bore's unit-force fields plus ``|F| a_k cos k theta``
and ``|F| a_k sin k theta`` on its self-equilibrated harmonics (``a_k`` the Fourier
coefficients of max(0, cos psi), theta the force's angle in the part frame).

The harmonic coefficients are positively homogeneous of degree 1 in the force (twice the
force, twice the pressure) but not linear in it: the loaded half turns with the force.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["HARMONICS", "half_cosine_coefficient", "harmonic_coefficients"]

#: the harmonics of the loaded-half cosine beyond k = 1 that the model keeps (k = 0 and the
#: even ones: the odd ones above 1 vanish). Truncated after 2 the peak pressure is 3% above
#: the cosine's, and the stress at a pin-loaded hole within 2.5% of the exact cosine's
#: (k <= 4 and k <= 6 change it by 2% or less; ``docs/model.md``, ``tests/test_pin_pressure.py``)
HARMONICS = (0, 2)


def half_cosine_coefficient(k: int) -> float:
    """a_k of max(0, cos psi) = sum_k a_k cos k psi: 1/pi, 1/2, then for even k
    (2/pi) (-1)^(k/2 + 1) / (k^2 - 1), and 0 for odd k > 1."""
    if k == 0:
        return 1.0 / math.pi
    if k == 1:
        return 0.5
    if k % 2:
        return 0.0
    return (2.0 / math.pi) * (-1) ** (k // 2 + 1) / (k * k - 1)


def harmonic_coefficients(force: np.ndarray, harmonics: tuple[int, ...] = HARMONICS) -> np.ndarray:
    """(..., m): the coefficients of a hole's self-equilibrated bearing fields (in the
    order of :func:`railcheck.fea.pin_pressure.harmonic_names`) for in-plane forces ``force``
    (..., 2) N on it: ``|F| a_k cos k theta`` (and ``sin``); 0 where the force is 0."""
    z = force[..., 0] + 1j * force[..., 1]
    size = np.abs(z)
    with np.errstate(invalid="ignore", divide="ignore"):
        turn = np.where(size > 0, z / size, 0.0)  # e^{i theta}
    cols = []
    for k in harmonics:
        a = half_cosine_coefficient(k)
        if k == 0:
            cols.append(a * size)
        else:
            w = a * size * turn**k
            cols += [w.real, w.imag]
    return np.stack(cols, axis=-1)
