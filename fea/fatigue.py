"""High-cycle fatigue of a node's stress history (Shigley's Mechanical Engineering
Design, Budynas & Nisbett, 10th ed., chapter 6).

* Multiaxial reduction, Shigley section 6-14 ("combinations of loading modes"): each
  stress component's alternating and midrange parts over the cycle,
  ``sigma_a,ij = (max - min) / 2`` and ``sigma_m,ij = (max + min) / 2``, reduced to the
  von Mises stresses of the alternating and of the midrange tensors (eqs. 6-66, 6-67).
  The midrange von Mises is never negative, so a compressive mean gets no credit
  (conservative).
* Endurance limit: ``Se = ka kb kc kd ke Se'`` with ``Se' = 0.5 Sut`` (Sut <= 1400 MPa,
  eq. 6-8); surface factor ``ka = a Sut^b`` (table 6-2); size factor from the equivalent
  diameter of a rectangular section ``d_e = 0.808 sqrt(h b)`` (table 6-3) with
  ``kb = 1.24 d^-0.107`` (2.79 <= d <= 51 mm) or ``1.51 d^-0.157`` (51 < d <= 254 mm)
  (eq. 6-20); load factor ``kc`` 1 (bending, combined loading per section 6-14), 0.85
  (axial); reliability ``ke`` (table 6-5); temperature ``kd`` 1 (room temperature).
* Criteria for the safety factor ``n`` (eqs. 6-41, 6-47, 6-50 with the load line through
  the origin): modified Goodman ``1/n = sa/Se + sm/Sut``; Gerber; ASME-elliptic
  ``1/n^2 = (sa/Se)^2 + (sm/Sy)^2``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .invariants import von_mises

#: surface factor ka = a Sut^b, Sut in MPa (Shigley table 6-2)
SURFACE = {
    "ground": (1.58, -0.085),
    "machined": (4.51, -0.265),
    "cold-drawn": (4.51, -0.265),
    "hot-rolled": (57.7, -0.718),
    "as-forged": (272.0, -0.995),
}
#: reliability factor ke (Shigley table 6-5)
RELIABILITY = {0.5: 1.000, 0.9: 0.897, 0.95: 0.868, 0.99: 0.814, 0.999: 0.753, 0.9999: 0.702}
LOAD = {"bending": 1.0, "axial": 0.85}
CRITERIA = ("goodman", "gerber", "asme-elliptic")


@dataclass(frozen=True)
class Marin:
    """The endurance limit's factors and result (Pa)."""

    ka: float
    kb: float
    kc: float
    kd: float
    ke: float
    unmodified: float
    endurance_limit: float


def endurance_limit(
    ultimate: float,
    surface: str = "machined",
    section: tuple[float, float] | None = None,
    load: str = "bending",
    reliability: float = 0.5,
) -> Marin:
    """Se (Pa) from the ultimate strength (Pa) and the Marin factors; ``section`` (width,
    height) m of a rectangular section for the size factor (None: kb = 1)."""
    sut_mpa = ultimate / 1e6
    unmodified = 0.5 * ultimate if sut_mpa <= 1400 else 700e6
    a, b = SURFACE[surface]
    ka = min(1.0, a * sut_mpa**b)
    kb = size_factor(section) if load != "axial" else 1.0
    kc = LOAD[load]
    ke = RELIABILITY[reliability]
    kd = 1.0  # temperature factor: room temperature
    return Marin(ka, kb, kc, kd, ke, unmodified, ka * kb * kc * kd * ke * unmodified)


def size_factor(section: tuple[float, float] | None) -> float:
    """kb of a rectangular section (width, height) m through its equivalent diameter."""
    if section is None:
        return 1.0
    return size_factor_of_diameter(0.808 * np.sqrt(section[0] * section[1]))


def size_factor_of_diameter(diameter):
    """kb of a round section of ``diameter`` m in rotating bending (Shigley eq. 6-20):
    ``1.24 d^-0.107`` (2.79 <= d <= 51 mm), ``1.51 d^-0.157`` (51 < d <= 254 mm), 1 below;
    a float for a float, an array (elementwise) for an array."""
    d = np.asarray(diameter, float) * 1e3  # mm
    small = 1.24 * np.clip(d, 2.79, 51.0) ** -0.107
    large = 1.51 * np.clip(d, 51.0, 254.0) ** -0.157
    kb = np.where(d <= 2.79, 1.0, np.where(d <= 51, small, large))
    return float(kb) if kb.ndim == 0 else kb


def alternating_and_mean(high: np.ndarray, low: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Von Mises (Pa) of the alternating and of the midrange stress tensors, from each
    component's maximum and minimum over the cycle (6, nodes)."""
    return von_mises(0.5 * (high - low)), von_mises(0.5 * (high + low))


def safety_factor(
    sa: np.ndarray, sm: np.ndarray, se: float, sut: float, criterion: str = "goodman", sy: float | None = None
) -> np.ndarray:
    """Fatigue safety factor per node (inf where the node carries no stress)."""
    sa, sm = np.asarray(sa, float), np.asarray(sm, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        if criterion == "goodman":
            n = 1.0 / (sa / se + sm / sut)
        elif criterion == "gerber":
            # the root of n sa / se + (n sm / sut)^2 = 1, written without the cancellation of
            # -1 + sqrt(1 + x^2) (x = 2 sm se / (sut sa)), which gives 0 once sm << sa
            x = 2.0 * np.maximum(sm, 0.0) * se / (sut * sa)
            n = 2.0 * se / (sa * (1.0 + np.sqrt(1.0 + x**2)))
            n = np.where(sa > 0, n, sut / sm)
        elif criterion == "asme-elliptic":
            if not sy:
                raise ValueError("the ASME-elliptic criterion needs the yield strength")
            n = 1.0 / np.sqrt((sa / se) ** 2 + (sm / sy) ** 2)
        else:
            raise ValueError(f"unknown fatigue criterion {criterion!r}")
    return np.where((sa <= 0) & (sm <= 0), np.inf, n)
