"""The joints' components checked by their standards, vectorised over any leading axes
(the cycle's steps, a sweep's settings). Pure numpy; SI in and out (N, m, Pa, N m, s).

Every function returns utilisations (demand over capacity: 1 = at the limit) per
criterion, each an array over the histories' leading axes reduced over the cycle (the
last axis), and the figures behind them.

* Bolts: EN 1993-1-8:2005 Table 3.4 (category A bearing type, D non-preloaded tension):
  shear per plane through the thread ``F_v,Rd = alpha_v f_ub A_s / gamma_M2``; bearing
  ``F_b,Rd = k_1 alpha_b f_u d t / gamma_M2``; tension ``F_t,Rd = 0.9 f_ub A_s /
  gamma_M2``; combined ``F_v,Ed / F_v,Rd + F_t,Ed / (1.4 F_t,Rd) <= 1``. A bolt group's
  forces by the elastic method (the moment about the group's centroid shared in
  proportion to each bolt's distance from it; for two bolts, a couple over their pitch).
* Shafts: Shigley, Mechanical Engineering Design, 10th ed., section 7-4: DE-Goodman
  (eq. 7-8) ``1/n = 16 / (pi d^3) { [4 (K_f M_a)^2 + 3 (K_fs T_a)^2]^(1/2) / S_e +
  [4 (K_f M_m)^2 + 3 (K_fs T_m)^2]^(1/2) / S_ut }`` and first-cycle yield (eq. 7-15)
  ``n_y = S_y / sigma'_max``; fatigue stress concentration ``K_f = 1 + q (K_t - 1)``
  with Neuber's notch sensitivity (eqs. 6-34, 6-35).
* Bearings: ISO 76 static safety ``s_0 = C_0 / P_0`` and ISO 281 basic rating life
  (:mod:`railcheck.loads.bearings`).
* Carriages: the profile-rail catalogues' equivalent static load under combined loads,
  ``P_0 = |F_y| + |F_z| + C_0 (|M_x| / M_0x + |M_y| / M_0y + |M_z| / M_0z)``, and the static
  safety ``S_0 = C_0 / P_0`` against the one required.
"""

from __future__ import annotations

import math

import numpy as np

#: EN 1993-1-8:2005 Table 2.1 (recommended values): resistance of cross-sections (pins'
#: bending and bearing) and of bolts and pins in shear, bearing and tension
GAMMA_M0 = 1.0
GAMMA_M2 = 1.25


def _ratio(demand, capacity) -> np.ndarray:
    """Demand over capacity; inf where the capacity is not positive."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(capacity > 0, np.asarray(demand, float) / np.where(capacity > 0, capacity, 1.0), np.inf)


def two_screw_forces(along, across, torque, eccentricity, pitch) -> np.ndarray:
    """(2, ..., T) N the transverse force on each of two screws ``pitch`` m apart along a
    rail (the elastic method), from a force (``along``, ``across``) N in the rail's axes
    whose line crosses the rail ``eccentricity`` m from the screws' centroid, on the first
    screw's side, and a ``torque`` N m about the normal to the plane: each screw carries
    half the force, and the moment about the centroid ``M = torque - eccentricity across``
    as a couple ``+-M / pitch`` across the rail (the second screw ``+``)."""
    along, across = np.asarray(along, float), np.asarray(across, float)
    couple = (np.asarray(torque, float) - eccentricity * across) / pitch
    return np.array([np.hypot(0.5 * along, 0.5 * across - couple), np.hypot(0.5 * along, 0.5 * across + couple)])


def two_screw_peaks(along, across, torque, eccentricity, pitch) -> np.ndarray:
    """(2, ...) N each screw's largest transverse force over the last axis (the cycle's
    steps) of :func:`two_screw_forces`, from the squares (one square root a setting)."""
    along, across = np.asarray(along, float), np.asarray(across, float)
    couple = (np.asarray(torque, float) - eccentricity * across) / pitch
    half, lateral = (0.5 * along) ** 2, 0.5 * across
    return np.sqrt(np.array([(half + (lateral - couple) ** 2).max(axis=-1), (half + (lateral + couple) ** 2).max(axis=-1)]))


def bolt_utilisations(shear, tension, d, stress_area, fub, fu_member, t, alpha_v, e1, e2, d0) -> dict[str, np.ndarray]:
    """EN 1993-1-8 Table 3.4 for one bolt (diameter ``d``, tensile stress area
    ``stress_area`` m^2, ultimate ``fub`` Pa; the shear plane through the thread) in a
    member ``t`` thick of ultimate ``fu_member`` with end and edge distances ``e1``,
    ``e2`` and hole ``d0`` (m): ``shear`` and ``tension`` (..., T) N factored. Returns the
    utilisations ``shear``, ``bearing``, ``tension``, ``shear+tension`` (the combined
    rule at every step, its largest)."""
    v_rd = alpha_v * fub * stress_area / GAMMA_M2
    alpha_b = min(e1 / (3.0 * d0), fub / fu_member, 1.0)
    k1 = min(2.8 * e2 / d0 - 1.7, 2.5)
    b_rd = k1 * alpha_b * fu_member * d * t / GAMMA_M2
    t_rd = 0.9 * fub * stress_area / GAMMA_M2
    v, n = np.abs(shear), np.maximum(np.asarray(tension, float), 0.0)
    return {
        "shear": _ratio(v.max(axis=-1), v_rd),
        "bearing": _ratio(v.max(axis=-1), b_rd),
        "tension": _ratio(n.max(axis=-1), t_rd),
        "shear+tension": np.max(_ratio(v, v_rd) + _ratio(n, 1.4 * t_rd), axis=-1),
    }


def notch_sensitivity(ultimate: float, radius: float, torsion: bool = False) -> float:
    """Neuber's notch sensitivity ``q = 1 / (1 + sqrt(a) / sqrt(r))`` (Shigley eqs. 6-34,
    6-35: ``sqrt(a)`` in sqrt(in) from S_ut in kpsi, S_ut + 20 kpsi in torsion) of a
    fillet of ``radius`` m in steel of ``ultimate`` Pa."""
    sut = ultimate / 6.894757e6 + (20.0 if torsion else 0.0)  # kpsi
    root_a = 0.246 - 3.08e-3 * sut + 1.51e-5 * sut**2 - 2.67e-8 * sut**3  # sqrt(in)
    return 1.0 / (1.0 + root_a / math.sqrt(radius / 0.0254))


def fatigue_notch_factor(kt: float, ultimate: float, radius: float, torsion: bool = False) -> float:
    """``K_f = 1 + q (K_t - 1)`` (Shigley eq. 6-32) with :func:`notch_sensitivity`."""
    return 1.0 + notch_sensitivity(ultimate, radius, torsion) * (kt - 1.0)


def shaft_utilisations(
    moment, torque, d, kf, kfs, endurance, ultimate, yield_strength, mean_moment=0.0
) -> dict[str, np.ndarray]:
    """Shigley section 7-4 at a shoulder of diameter ``d`` (m; fatigue notch factors
    ``kf`` in bending, ``kfs`` in torsion): bending ``moment`` and ``torque`` (..., T)
    N m factored: the ``moment`` fully reversed (``M_a`` its peak: a joint force whose
    direction turns relative to the shaft, the conservative side), ``mean_moment`` (...)
    a bending moment constant in the shaft's frame (``M_m``), the torque's alternating and
    midrange parts from its range. ``endurance`` S_e (Pa, Marin-modified). Returns
    ``fatigue`` (1 / n of DE-Goodman, eq. 7-8) and ``yield`` (1 / n_y, the first cycle's
    largest von Mises stress with the notch factors, eq. 7-15)."""
    m = np.abs(np.asarray(moment, float))
    tq = np.asarray(torque, float)
    ma, mm = m.max(axis=-1), np.broadcast_to(np.abs(np.asarray(mean_moment, float)), m.shape[:-1])
    ta, tm = 0.5 * (tq.max(axis=-1) - tq.min(axis=-1)), 0.5 * (tq.max(axis=-1) + tq.min(axis=-1))
    return shaft_utilisations_of_parts(ma, mm, ta, tm, d, kf, kfs, endurance, ultimate, yield_strength)


def shaft_utilisations_of_parts(ma, mm, ta, tm, d, kf, kfs, endurance, ultimate, yield_strength) -> dict[str, np.ndarray]:
    """:func:`shaft_utilisations` from the alternating and midrange bending moments and
    torques (N m) as Shigley's examples state them."""
    k = 16.0 / (math.pi * d**3)
    alternating = np.sqrt(4 * (kf * ma) ** 2 + 3 * (kfs * ta) ** 2)
    midrange = np.sqrt(4 * (kf * mm) ** 2 + 3 * (kfs * tm) ** 2)
    inv_n = k * (alternating / endurance + midrange / ultimate)
    sigma = 2.0 * k * kf * (ma + mm)  # 32 K_f M / (pi d^3)
    tau = k * kfs * (np.abs(tm) + ta)
    return {"fatigue": inv_n, "yield": np.sqrt(sigma**2 + 3.0 * tau**2) / yield_strength}


def de_goodman_diameter(ma, ta, tm, kf, kfs, endurance, ultimate, n: float = 1.0, start: float = 25e-3, mm=0.0):
    """m: the shaft diameter at which DE-Goodman (Shigley eq. 7-8) gives the factor of
    safety ``n`` under the alternating and midrange moments ``ma``, ``mm`` and the torque's
    alternating and midrange parts ``ta``, ``tm`` (N m), solved for
    ``d``: ``d = (16 n / pi (A / S_e + B / S_ut))^(1/3)``. ``endurance`` is S_e (Pa), or a
    function of the diameter (the size factor's weak dependence: solved by substitution
    from ``start``, contracting by about 0.107 / 3 a step). Elementwise over arrays (a
    float for floats)."""
    alternating = np.sqrt(4 * (kf * np.asarray(ma, float)) ** 2 + 3 * (kfs * np.asarray(ta, float)) ** 2)
    midrange = np.sqrt(4 * (kf * np.asarray(mm, float)) ** 2 + 3 * (kfs * np.asarray(tm, float)) ** 2)
    se = endurance if callable(endurance) else (lambda d: endurance)
    d = np.full(np.broadcast(alternating, midrange).shape, start)
    for _ in range(40):
        d = (16.0 * n / math.pi * (alternating / se(d) + midrange / ultimate)) ** (1.0 / 3.0)
    return float(d) if d.ndim == 0 else d


def yield_diameter(m_max, t_max, kf, kfs, yield_strength, n: float = 1.0):
    """m: the shaft diameter at which the first cycle's largest von Mises stress (Shigley
    eq. 7-15, the notch factors applied) reaches ``yield_strength / n`` under the largest
    moment ``m_max`` and torque ``t_max`` (N m); elementwise over arrays."""
    peak = np.sqrt(4 * (kf * np.asarray(m_max, float)) ** 2 + 3 * (kfs * np.asarray(t_max, float)) ** 2)
    d = (16.0 * n * peak / (math.pi * yield_strength)) ** (1.0 / 3.0)
    return float(d) if np.ndim(d) == 0 else d


def carriage_equivalent_load(fy, fz, mx, my, mz, c0, m0x, m0y, m0z) -> np.ndarray:
    """(..., T) N: the catalogues' equivalent static load of a carriage under forces
    ``fy`` (lateral), ``fz`` (normal) N and moments ``mx`` (roll), ``my`` (pitch), ``mz``
    (yaw) N m, against its ratings ``c0`` N, ``m0x``, ``m0y``, ``m0z`` N m."""
    return np.abs(fy) + np.abs(fz) + c0 * (np.abs(mx) / m0x + np.abs(my) / m0y + np.abs(mz) / m0z)
