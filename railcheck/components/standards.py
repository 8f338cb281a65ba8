"""The joints' components checked by their standards, vectorised over any leading axes
(the cycle's steps, a sweep's settings). Pure numpy; SI in and out (N, m, Pa, N m, s).

Every function returns utilisations (demand over capacity: 1 = at the limit) per
criterion, each an array over the histories' leading axes reduced over the cycle (the
last axis), and the figures behind them.

* Pins: EN 1993-1-8:2005 Table 3.10 (pin connections): shear ``F_v,Rd = 0.6 A f_up /
  gamma_M2``, bearing ``F_b,Rd = 1.5 t d f_y / gamma_M0`` on each member, bending
  ``M_Rd = 1.5 W_el f_yp / gamma_M0``, and shear with bending
  ``(M_Ed / M_Rd)^2 + (F_v,Ed / F_v,Rd)^2 <= 1``. A pin in single shear (as built)
  bends over the lever between its two members' bearing resultants,
  ``t_1 / 2 + gap + t_2 / 2``; in double shear by Figure 3.11, ``F (b + 4 c + 2 a) / 8``.
* Bolts: EN 1993-1-8:2005 Table 3.4 (category A bearing type, D non-preloaded tension):
  shear per plane through the thread ``F_v,Rd = alpha_v f_ub A_s / gamma_M2``; bearing
  ``F_b,Rd = k_1 alpha_b f_u d t / gamma_M2``; tension ``F_t,Rd = 0.9 f_ub A_s /
  gamma_M2``; combined ``F_v,Ed / F_v,Rd + F_t,Ed / (1.4 F_t,Rd) <= 1``. A bolt group's
  forces by the elastic method (the eccentric force's moment shared in proportion to
  each bolt's distance from the group's centroid).
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


def pin_utilisations(force, d, t1, t2, gap, fy_pin, fu_pin, fy_members, planes: int = 1) -> dict[str, np.ndarray]:
    """EN 1993-1-8 Table 3.10 for a pin of diameter ``d`` carrying ``force`` (..., T) N
    (factored); ``fy_members`` the lower yield strength of the members (Pa). In single
    shear (``planes`` 1, as the rig's driving pin is built) between members ``t1`` and
    ``t2`` thick (m) across ``gap`` (m), bending over the lever between their bearing
    resultants. In double shear (``planes`` 2): a middle member ``t2`` thick between two
    outer plates ``t1`` thick, ``gap`` each side; each plane carries half the force and
    the pin bends by EN 1993-1-8 Figure 3.11, ``M = F (t2 + 4 gap + 2 t1) / 8``. Returns
    the utilisations ``shear``, ``bending``, ``shear+bending``, ``bearing`` (the most
    loaded member's) at the cycle's peak force."""
    f = np.max(np.abs(force), axis=-1)
    area = math.pi * d * d / 4.0
    shear_rd = 0.6 * area * fu_pin / GAMMA_M2
    fy = min(fy_pin, fy_members)
    if planes == 1:
        m_ed = f * (t1 / 2.0 + gap + t2 / 2.0)
        bearing = _ratio(f, 1.5 * min(t1, t2) * d * fy / GAMMA_M0)
    elif planes == 2:
        m_ed = f * (t2 + 4.0 * gap + 2.0 * t1) / 8.0
        bearing = np.maximum(_ratio(f, 1.5 * t2 * d * fy / GAMMA_M0), _ratio(f / 2.0, 1.5 * t1 * d * fy / GAMMA_M0))
    else:
        raise ValueError(f"a pin has 1 or 2 shear planes, not {planes}")
    m_rd = 1.5 * (math.pi * d**3 / 32.0) * fy_pin / GAMMA_M0
    shear, bending = _ratio(f / planes, shear_rd), _ratio(m_ed, m_rd)
    return {"shear": shear, "bending": bending, "shear+bending": np.sqrt(shear**2 + bending**2), "bearing": bearing}


def bolt_group_forces(fx, fy, eccentricity, pitch) -> np.ndarray:
    """(..., T) N the largest shear force on either of two bolts ``pitch`` m apart along
    x, from a force (``fx``, ``fy``) applied ``eccentricity`` m along x from their centroid
    (elastic method: each bolt ``(fx / 2, fy / 2 +- fy e / pitch)``)."""
    fx, fy = np.asarray(fx, float), np.asarray(fy, float)
    twist = fy * eccentricity / pitch
    return np.hypot(0.5 * fx, np.abs(0.5 * fy) + np.abs(twist))


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


def shaft_utilisations(moment, torque, d, kf, kfs, endurance, ultimate, yield_strength) -> dict[str, np.ndarray]:
    """Shigley section 7-4 at a shoulder of diameter ``d`` (m; fatigue notch factors
    ``kf`` in bending, ``kfs`` in torsion): bending ``moment`` and ``torque`` (..., T)
    N m factored, over a rotating shaft: the bending fully reversed (``M_a`` its peak,
    ``M_m = 0``, the conservative side for a shaft turning relative to its load), the
    torque's alternating and midrange parts from its range. ``endurance`` S_e (Pa,
    Marin-modified). Returns ``fatigue`` (1 / n of DE-Goodman, eq. 7-8) and ``yield``
    (1 / n_y, the first cycle's largest von Mises stress with the notch factors, eq. 7-15)."""
    m = np.abs(np.asarray(moment, float))
    tq = np.asarray(torque, float)
    ma, mm = m.max(axis=-1), np.zeros(m.shape[:-1])
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


def carriage_equivalent_load(fy, fz, mx, my, mz, c0, m0x, m0y, m0z) -> np.ndarray:
    """(..., T) N: the catalogues' equivalent static load of a carriage under forces
    ``fy`` (lateral), ``fz`` (normal) N and moments ``mx`` (roll), ``my`` (pitch), ``mz``
    (yaw) N m, against its ratings ``c0`` N, ``m0x``, ``m0y``, ``m0z`` N m."""
    return np.abs(fy) + np.abs(fz) + c0 * (np.abs(mx) / m0x + np.abs(my) / m0y + np.abs(mz) / m0z)
