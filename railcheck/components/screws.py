"""Screws that clamp a joint's plate to a rail: their thread and head data, property
classes, the preload a tightening method gives (VDI 2230 Part 1:2015), the embedding loss,
the slip safety of the clamped interface, and the choice of the smallest standard screw.
Pure numpy; SI (m, N, Pa, N m).

* Preload (VDI 2230 eq. R8 / Table A1's basis): the largest assembly preload at ``nu`` of
  the yield strength, ``F_M,zul = A_0 nu R_p0.2 / sqrt(1 + 3 [3/2 d_2/d_0 (P / (pi d_2)
  + 1.155 mu_G)]^2)``, ``d_0`` the stress diameter ``(d_2 + d_3) / 2``; the least after a
  tightening method of factor ``alpha_A``: ``F_M,min = F_M,zul / alpha_A``.
* Tightening torque (VDI 2230 eq. 5.4/...): ``M_A = F_M (0.16 P + 0.58 d_2 mu_G + mu_K
  D_Km / 2)``, ``D_Km = (d_w + d_h) / 2`` the head's mean bearing diameter.
* Embedding (VDI 2230 section 5.4.2.1): ``F_Z = f_Z / (delta_S + delta_P)``, with the
  clamped parts' resilience ``delta_P`` left out (the larger loss: an upper bound) and the
  screw's ``delta_S`` of a tapped-thread joint (head ``0.5 d``, the clamped length and the
  engaged thread ``0.5 d`` in the core section, the tapped part ``0.33 d``).
* Slip (VDI 2230 eq. R9 with the slip safety ``S_G``): a clamp ``F_KR`` per screw holds
  a transverse force ``F_Q`` over one interface of friction ``mu_T`` when
  ``S_G F_Q <= mu_T F_KR``; ``F_KR = F_M,min - F_Z - F_A`` (the axial working load taken
  wholly off the clamp: load factor Phi = 0, the conservative side).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

E_SCREW = 205e9  # Pa, VDI 2230's modulus for steel screws


@dataclass(frozen=True)
class Thread:
    """An ISO metric coarse thread (ISO 261, ISO 724) with an ISO 4762 socket head:
    nominal ``d``, pitch ``p``, pitch diameter ``d2``, minor diameter ``d3``, tensile
    stress area ``stress_area`` (ISO 898-1), head diameter ``head`` (m, m^2)."""

    name: str
    d: float
    p: float
    d2: float
    d3: float
    stress_area: float
    head: float


#: the sizes near the rail's 7 mm hole; which of them the hole admits is :func:`admitted`
THREADS = {
    t.name: t
    for t in (
        Thread("M4", 4e-3, 0.7e-3, 3.545e-3, 3.141e-3, 8.78e-6, 7.0e-3),
        Thread("M5", 5e-3, 0.8e-3, 4.480e-3, 4.019e-3, 14.2e-6, 8.5e-3),
        Thread("M6", 6e-3, 1.0e-3, 5.350e-3, 4.773e-3, 20.1e-6, 10.0e-3),
        Thread("M8", 8e-3, 1.25e-3, 7.188e-3, 6.466e-3, 36.6e-6, 13.0e-3),
    )
}


@dataclass(frozen=True)
class PropertyClass:
    """ISO 898-1 property class: nominal ultimate ``ultimate`` (EN 1993-1-8's f_ub), the
    minimum 0.2% proof strength ``proof`` (VDI 2230's R_p0.2min, d <= 16 mm), and
    EN 1993-1-8 Table 3.4's shear factor ``alpha_v`` through the thread (Pa)."""

    name: str
    ultimate: float
    proof: float
    alpha_v: float


#: 12.9 is outside EN 1993-1-8's classes: its alpha_v taken as 10.9's (0.5), stated
CLASSES = {
    c.name: c
    for c in (
        PropertyClass("8.8", 800e6, 640e6, 0.6),
        PropertyClass("10.9", 1000e6, 940e6, 0.5),
        PropertyClass("12.9", 1200e6, 1100e6, 0.5),
    )
}


def admitted(hole: float, counterbore: float) -> tuple[str, ...]:
    """The sizes a rail's through ``hole`` and ``counterbore`` (m) admit, smallest first:
    the shank passes the hole, the head seats on the hole's rim and fits the counterbore."""
    return tuple(n for n, t in THREADS.items() if t.d < hole and hole < t.head <= counterbore)


def assembly_preload(t: Thread, proof: float, thread_friction: float, utilisation: float = 0.9) -> float:
    """N: VDI 2230's largest assembly preload ``F_M,zul`` (module doc) of thread ``t`` at
    ``utilisation`` of the ``proof`` strength (Pa) with thread friction ``thread_friction``."""
    d0 = 0.5 * (t.d2 + t.d3)
    area = math.pi * d0 * d0 / 4.0
    twist = 1.5 * t.d2 / d0 * (t.p / (math.pi * t.d2) + 1.155 * thread_friction)
    return area * utilisation * proof / math.sqrt(1.0 + 3.0 * twist * twist)


def tightening_torque(t: Thread, preload: float, thread_friction: float, head_friction: float, hole: float) -> float:
    """N m: the torque that tightens thread ``t`` to ``preload`` N, its head bearing on
    the annulus between ``hole`` and the head's diameter (m)."""
    mean_bearing = 0.5 * (t.head + hole)
    return preload * (0.16 * t.p + 0.58 * t.d2 * thread_friction + 0.5 * mean_bearing * head_friction)


def embedding_loss(t: Thread, grip: float, embedding: float) -> float:
    """N: the preload lost to ``embedding`` m of settlement (VDI 2230's f_Z) in a screw
    tapped into the plate through ``grip`` m of rail, the plate's resilience left out."""
    nominal, core = math.pi * t.d**2 / 4.0, math.pi * t.d3**2 / 4.0
    resilience = (0.5 * t.d + 0.33 * t.d) / (E_SCREW * nominal) + (grip + 0.5 * t.d) / (E_SCREW * core)
    return embedding / resilience


def least_clamp(t: Thread, c: PropertyClass, spec) -> float:
    """N: the least clamp load per screw before working loads: ``F_M,min - F_Z`` of
    thread ``t`` in class ``c`` tightened as ``spec`` says (its ``screw_*`` fields)."""
    preload = assembly_preload(t, c.proof, spec.screw_thread_friction, spec.screw_preload_utilisation)
    return preload / spec.screw_tightening_factor - embedding_loss(t, spec.screw_grip, spec.screw_embedding)


def slip_utilisation(transverse, axial, clamp: float, friction: float, safety: float) -> np.ndarray:
    """``S_G F_Q / (mu_T F_KR)`` (1 = at the required slip safety ``safety``) of a screw
    with ``clamp`` N less its ``axial`` working load (N, >= 0 pulls), carrying
    ``transverse`` N by friction ``friction``; inf where nothing is left to clamp."""
    remaining = clamp - np.maximum(np.asarray(axial, float), 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(
            remaining > 0, safety * np.abs(transverse) / (friction * np.where(remaining > 0, remaining, 1.0)), np.inf
        )


def clamp_needed(transverse, axial, friction: float, safety: float) -> np.ndarray:
    """N: the least clamp per screw before working loads that holds ``transverse`` N
    with the slip safety ``safety`` (:func:`slip_utilisation` solved for the clamp)."""
    return safety * np.abs(transverse) / friction + np.maximum(np.asarray(axial, float), 0.0)
