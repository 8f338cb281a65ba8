"""Where quasi-static holds (docs/model.md, "Is quasi-static true?"): a cheap certificate per part and speed.

The quasi-static model (joint forces from the rigid-body dynamics, the part's elastic
response without its own inertia's dynamics) holds while the load cycle's harmonics stay
well below the part's lowest natural frequency. The certificate estimates the
amplification with one mode: each joint-force coefficient filtered harmonic by harmonic by
the one-degree-of-freedom response ``H(n f / f1)`` (:func:`railcheck.fea.dynamic.one_mode_amplification`).
Where the estimate exceeds :data:`QUASI_STATIC_TOLERANCE`, the part's exact dynamic
response (mode-acceleration, docs/model.md) is computed instead; below it the
estimate is stated beside the verdict.

The lowest natural frequency: for a rail, its Euler-Bernoulli beam on the joints' pins
with the joints' carried masses (:func:`railcheck.fea.beam.beam_lowest_frequency`,
the smaller of its two bending stiffnesses); for any other part, its FE modes.

Units SI: Hz, rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from railcheck.fea.beam import beam_lowest_frequency
from railcheck.fea.dynamic import one_mode_amplification

#: the amplification up to which quasi-static is taken to hold: 5 %, the order of the FE's
#: own agreement with beam theory (3.5 %) and half the margin between 1 and the dynamic
#: limit's default 1.10
QUASI_STATIC_TOLERANCE = 1.05

#: unit cases that are joint forces or couples (the others: the part's own inertia and the
#: pins' pressure harmonics, which follow the joint forces)
FORCE_PREFIXES = ("pin_", "bolt_", "seat_", "torque")

#: the beam model's frequency is taken at this share: the rails' FE modes lie from 0.2 % below
#: to 2 % above their beam models' (holes and the pins' finite size; tested)
BEAM_MARGIN = 0.95

#: small displacements hold while a part's largest deflection stays within this share of
#: its length: slopes of about 3-4 degrees (a beam's largest slope is about 3.2 x its sag
#: over its span), where tan and sin differ from the angle by about 0.1-0.2 %; beyond it the
#: linear result is not valid and the part fails ("beyond small displacements")
SMALL_DISPLACEMENT_SHARE = 0.02


def small_displacement_limit(length: float) -> float:
    """m: the largest deflection for which a part ``length`` m long is in small
    displacements (:data:`SMALL_DISPLACEMENT_SHARE` of it)."""
    return SMALL_DISPLACEMENT_SHARE * length


#: a joint-force column counts when its peak is at least this share of the largest one's
SIGNIFICANT = 0.05


@dataclass(frozen=True)
class Certificate:
    """The one-mode estimate ``estimate`` of a part's dynamic amplification at crank
    ``crank_hz``, from its lowest natural frequency ``lowest_hz`` (``source``: "beam model"
    or "FE modes"), against ``tolerance``."""

    lowest_hz: float
    source: str
    crank_hz: float
    estimate: float
    tolerance: float = QUASI_STATIC_TOLERANCE

    @property
    def holds(self) -> bool:
        """True when the quasi-static model holds within the tolerance."""
        return self.estimate <= self.tolerance

    def sentence(self) -> str:
        """One line for the console and the report."""
        verdict = "quasi-static holds" if self.holds else "dynamic response computed"
        relation = "<=" if self.holds else ">"
        return (
            f"{verdict}: one-mode amplification estimate {self.estimate:.3f} {relation} {self.tolerance:.2f} "
            f"(lowest mode {self.lowest_hz:.3g} Hz by {self.source}, crank {self.crank_hz:.3g} Hz)"
        )


def dynamic_share(amplification, max_amplification: float):
    """A dynamic response's amplification ``A`` (cycle peak over its quasi-static peak) as
    a share of the allowed excess, ``(A - 1) / (A_max - 1)``: 0 at the quasi-static peak,
    1 at the limit; with ``A_max = 1`` (no excess allowed) 0 up to 1 and inf beyond.
    Elementwise (a check's float, a sweep's settings); the one definition both use."""
    a = np.asarray(amplification, dtype=float)
    if max_amplification > 1.0:
        out = (a - 1.0) / (max_amplification - 1.0)
    else:
        out = np.where(a <= 1.0, 0.0, np.inf)
    return float(out) if out.ndim == 0 else out


def force_columns(names) -> tuple[list[int], list[int]]:
    """(joint forces, couples): the indices of the unit cases ``names`` that are joint
    forces (N) and joint couples (``torque``, N m)."""
    names = list(names)
    forces = [i for i, n in enumerate(names) if n.startswith(FORCE_PREFIXES) and not n.startswith("torque")]
    return forces, [i for i, n in enumerate(names) if n.startswith("torque")]


def amplification_estimate(C: np.ndarray, names, speed, hz, damping: float) -> np.ndarray:
    """(...,): the one-mode estimate of the dynamic amplification of histories ``C``
    (..., steps, k; columns the unit cases ``names``, pressure columns after them left
    out) at crank ``speed`` rad/s and lowest frequency ``hz`` Hz: the largest over the
    joint-force columns whose peak is at least :data:`SIGNIFICANT` of the largest's, and
    the couples; at least 1."""
    forces, couples = force_columns(names)
    if not forces + couples:
        return np.ones(C.shape[:-2])
    ratio, peak = one_mode_amplification(C[..., forces + couples], speed, hz, damping)
    return largest_significant(ratio, peak, len(forces))


def largest_significant(ratio: np.ndarray, peak: np.ndarray, n_forces: int) -> np.ndarray:
    """(...,): the largest ``ratio`` (..., k) over the first ``n_forces`` columns (joint
    forces) whose ``peak`` is at least :data:`SIGNIFICANT` of the largest's and the other
    columns (couples) that are not zero; at least 1."""
    largest = peak[..., :n_forces].max(axis=-1, keepdims=True, initial=0.0)
    counts = np.concatenate(
        [(peak[..., :n_forces] >= SIGNIFICANT * largest) & (largest > 0), peak[..., n_forces:] > 0], axis=-1
    )
    return np.maximum(np.where(counts, ratio, 1.0).max(axis=-1, initial=1.0), 1.0)


def estimate(histories, names, speed: float, lowest_hz: float, damping: float) -> float:
    """The largest one-mode amplification over the load sources' coefficient histories
    (each (steps, k), columns ``names``) at crank ``speed`` rad/s."""
    return max([1.0] + [float(amplification_estimate(C, names, speed, lowest_hz, damping)) for C in histories])


def certificate(histories, names, speed: float, lowest_hz: float, source: str, damping: float) -> Certificate:
    """The :class:`Certificate` of one part at crank ``speed`` rad/s."""
    return Certificate(
        lowest_hz=float(lowest_hz),
        source=source,
        crank_hz=speed / (2 * math.pi),
        estimate=estimate(histories, names, speed, lowest_hz, damping),
    )


def _x_of(geo, groups) -> float:
    """The mean x (m) of a rail's hole groups ("hole_K", "shaft_hole" = hole 0)."""
    xs = geo.get("hole_x")
    return float(np.mean([xs[0 if g == "shaft_hole" else int(g.split("_")[1])] for g in groups]))


def rail_lowest_hz(geo, material, pins, lumped, clamp: str | None = None) -> float:
    """The certificate's lowest frequency of a rail (Hz): :data:`BEAM_MARGIN` of its beam (length, the grooved section's
    smaller second moment and area, the material's E and density) held at the ``pins``
    (lists of hole groups) or clamped at the group ``clamp``, carrying the ``lumped``
    masses ((hole groups, kg), ...)."""
    section = geo.section
    EI = material.youngs_modulus * min(section.inertia_in_plane, section.inertia_out_of_plane)
    masses = [(_x_of(geo, groups), kg) for groups, kg in lumped]
    pins_x = [_x_of(geo, groups) for groups in pins or ()]
    clamps = [_x_of(geo, [clamp])] if clamp and not pins_x else []
    return BEAM_MARGIN * beam_lowest_frequency(
        geo.get("length"), EI, section.area * material.density, pins_x, masses, clamps
    )
