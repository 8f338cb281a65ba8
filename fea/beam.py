"""The lowest bending frequency of a straight beam on pins, with point masses: Euler-Bernoulli
beam elements (cubic Hermite, two DOFs per node: deflection and slope), consistent mass,
dense generalised eigenproblem. A rail's quasi-static certificate takes its lowest natural
frequency from here (docs/model.md, "Is quasi-static true?") instead of a 3D modal solve per hole pair.

Idealisations: bending only (shear deformation and rotary inertia left out: the rails are
slender, length over depth above 20); a pin holds the deflection, not the slope; a point
mass is translational. Units SI: m, Pa, kg, Hz.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["beam_lowest_frequency"]

#: elements between consecutive stations (pins, masses, ends)
ELEMENTS_PER_SPAN = 8


def _stations(length: float, pins, masses) -> np.ndarray:
    """The beam's nodes (m): its ends, every pin and mass position, and
    :data:`ELEMENTS_PER_SPAN` elements between consecutive ones."""
    marks = np.unique(np.round(np.concatenate([[0.0, length], list(pins), [x for x, _ in masses]]), 12))
    spans = [np.linspace(a, b, ELEMENTS_PER_SPAN + 1)[:-1] for a, b in zip(marks[:-1], marks[1:])]
    return np.concatenate([*spans, [length]])


def _element_matrices(h: np.ndarray, EI: float, mass_per_m: float) -> tuple[np.ndarray, np.ndarray]:
    """(E, 4, 4) stiffness (N/m) and consistent mass (kg) of Hermite elements of lengths ``h``."""
    k = np.array([[12, 6, -12, 6], [6, 4, -6, 2], [-12, -6, 12, -6], [6, 2, -6, 4]], float)
    m = np.array([[156, 22, 54, -13], [22, 4, 13, -3], [54, 13, 156, -22], [-13, -3, -22, 4]], float)
    p = np.array([0, 1, 0, 1])  # slope DOFs carry one more power of h
    scale = h[:, None, None] ** (p[:, None] + p[None, :])
    K = EI / h[:, None, None] ** 3 * k * scale
    M = mass_per_m * h[:, None, None] / 420 * m * scale
    return K, M


def beam_lowest_frequency(length: float, EI: float, mass_per_m: float, pins=(), masses=(), clamps=()) -> float:
    """The lowest natural frequency (Hz) of a uniform beam of ``length`` m, bending
    stiffness ``EI`` (N m^2) and ``mass_per_m`` (kg/m), its deflection held at the ``pins``
    and its deflection and slope at the ``clamps`` (x in m: two pins or a clamp at least,
    else the beam has a rigid-body mode), carrying point ``masses`` [(x m, kg)]."""
    pins, clamps = sorted(float(x) for x in pins), sorted(float(x) for x in clamps)
    if len(pins) + 2 * len(clamps) < 2 or not all(0.0 <= x <= length for x in pins + clamps):
        raise ValueError("a beam needs two pins or a clamp on it")
    x = _stations(length, pins + clamps, masses)
    Ke, Me = _element_matrices(np.diff(x), EI, mass_per_m)
    n = 2 * x.size
    dofs = 2 * np.arange(x.size - 1)[:, None] + np.arange(4)[None, :]
    K, M = np.zeros((n, n)), np.zeros((n, n))
    np.add.at(K, (dofs[:, :, None], dofs[:, None, :]), Ke)
    np.add.at(M, (dofs[:, :, None], dofs[:, None, :]), Me)
    node = lambda at: 2 * int(np.argmin(np.abs(x - at)))  # noqa: E731  the deflection DOF at x = at
    for xm, kg in masses:
        M[node(xm), node(xm)] += kg
    held = {node(p) for p in pins} | {node(c) + d for c in clamps for d in (0, 1)}
    free = np.array([i for i in range(n) if i not in held])
    from scipy.linalg import eigh

    values = eigh(K[np.ix_(free, free)], M[np.ix_(free, free)], eigvals_only=True, subset_by_index=[0, 0])
    return math.sqrt(max(float(values[0]), 0.0)) / (2 * math.pi)
