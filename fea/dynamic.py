"""Is quasi-static true? The steady-state response of a part to its periodic load cycle by
modal superposition with the mode-acceleration correction (docs/model.md, "Is quasi-static true?").

The unit-case coefficients ``c(t)`` (steps, k) repeat every crank revolution (period
``T = 2 pi / Omega``). With the part's lowest modes ``phi_m`` (mass-normalised, angular
frequencies ``omega_m``, modal damping ratio ``zeta``), the unit load vectors ``F`` (N, k)
and the modal loads ``p_m(t) = phi_m^T F c(t)``:

    u(t) = u_qs(t) + sum_m phi_m (q_m(t) - p_m(t) / omega_m^2)

where ``u_qs`` is the quasi-static (superposed) solution and ``q_m`` the steady-state modal
response: harmonic ``n`` of ``p_m`` (frequency ``n Omega``) divided by
``omega_m^2 - (n Omega)^2 + 2 i zeta omega_m n Omega``. The correction ``delta q_m(t)`` is
computed by FFT over one revolution (the steps are uniform in time at constant speed; the
last step repeats the first and is left out of the transform). The mode shapes' stress
fields join the unit fields as extra columns and ``delta q`` joins the coefficients, so the
same envelope, fatigue and deflection code runs on the dynamic response.

Supports of the modal model: a clamped part keeps its clamp; a free body is held at its
joints as pins, each pin holding the mean translation of its hole surfaces and their mean
rotation about the bar's axis (the rig's joint keeps the rail in its plane), by a penalty
``alpha W^T W`` on those means (``alpha`` 1e4 times the largest diagonal entry of K).

Units SI: N, m, kg, s, rad/s; frequencies reported in Hz.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .errors import NumericalError
from .loading import surface_dofs
from .modes import natural_modes, stiffness_factor, vector_mass_matrix

__all__ = [
    "DynamicModel",
    "harmonic_spectrum",
    "lumped_masses",
    "modal_correction",
    "one_mode_amplification",
    "one_mode_peak",
    "part_modes",
    "pin_constraints",
]

#: penalty stiffness of a pin, relative to the largest diagonal entry of K
PIN_PENALTY = 1e4


@dataclass(frozen=True)
class DynamicModel:
    """A part's lowest modes for the dynamic response: ``hz`` (m,) natural frequencies,
    ``shapes`` (N, m) mass-normalised mode shapes (1/sqrt(kg) per m), ``modal_loads``
    (m, k) ``phi^T F`` of each unit case (N/sqrt(kg))."""

    hz: np.ndarray
    shapes: np.ndarray
    modal_loads: np.ndarray


def pin_constraints(basis, groups: dict, pins: list[list[str]]) -> sp.csr_matrix:
    """(4 x pins, N): each pin's constraint rows, the area-weighted mean x, y and z
    displacement of its surfaces and their mean rotation about x (the bar's axis)."""
    rows = []
    for names in pins:
        parts = [surface_dofs(basis, groups, g) for g in names]
        dofs = np.concatenate([p.dofs for p in parts])  # (n, 3)
        w = np.concatenate([p.weights for p in parts])
        pts = np.concatenate([p.points for p in parts])
        w = w / w.sum()
        for c in range(3):
            rows.append(sp.csr_matrix((w, (np.zeros(w.size, dtype=np.int64), dofs[:, c])), shape=(1, basis.N)))
        y, z = pts[:, 1] - w @ pts[:, 1], pts[:, 2] - w @ pts[:, 2]
        r2 = w @ (y**2 + z**2)
        data = np.concatenate([-w * z, w * y]) / r2  # theta_x = mean of (y u_z - z u_y) / r^2
        cols = np.concatenate([dofs[:, 1], dofs[:, 2]])
        rows.append(sp.csr_matrix((data, (np.zeros(data.size, dtype=np.int64), cols)), shape=(1, basis.N)))
    return sp.vstack(rows).tocsr()


def lumped_masses(basis, groups: dict, lumped) -> sp.csr_matrix:
    """(N, N) kg: point masses carried by hole surfaces, ``lumped`` = [(surfaces, kg)],
    each spread over its surfaces' nodes in proportion to their area, on every component
    (a translational mass: the carried body's rotary inertia is left out)."""
    diag = np.zeros(basis.N)
    for names, kg in lumped:
        parts = [surface_dofs(basis, groups, g) for g in names]
        dofs = np.concatenate([p.dofs for p in parts])
        w = np.concatenate([p.weights for p in parts])
        np.add.at(diag, dofs, kg * (w / w.sum())[:, None])
    return sp.diags(diag).tocsr()


def part_modes(
    K,
    basis,
    density: float,
    F: np.ndarray,
    count: int,
    fixed=None,
    pins=None,
    groups=None,
    lumped=(),
    shared=None,
    progress=None,
) -> DynamicModel:
    """The ``count`` lowest modes of a part with its ``fixed`` DOFs held (a clamped part)
    or its ``pins`` (lists of hole surfaces, :func:`pin_constraints`) held by penalty (a
    free body), the masses ``lumped`` on hole surfaces ([(surfaces, kg)]) added to the
    consistent mass, and each unit load vector's modal load (``F`` (N, k)). ``shared``: a
    dict reused across calls on one part (its consistent mass matrix and, for a part held
    at ``fixed`` DOFs, its stiffness factorisation: both independent of the lumped masses).
    ``progress``: told a long eigensolve's estimate and progress (one line at a time)."""
    shared = {} if shared is None else shared
    if "M" not in shared:
        shared["M"] = vector_mass_matrix(basis, density)
    M = shared["M"]
    if lumped:
        M = (M + lumped_masses(basis, groups, lumped)).tocsr()
    Kd = K
    if pins:
        G = pin_constraints(basis, groups, pins)
        alpha = PIN_PENALTY * K.diagonal().max()
        Kd = (K + alpha * (G.T @ G)).tocsr()
    held = np.zeros(0, dtype=np.int64) if fixed is None else fixed
    if not pins and "factor" not in shared:
        shared["factor"] = stiffness_factor(K, held)
    factor = None if pins else shared["factor"]
    modes = natural_modes(Kd, M, held, count, shift=0.0, factor=factor, progress=progress)
    if not np.all(modes.hz > 0.0):  # held at supports or pins, every mode is elastic: a zero one is spurious
        raise NumericalError(f"the eigensolver gave a mode at 0 Hz among {count}: ask for fewer", "dynamic.modes")
    return DynamicModel(hz=modes.hz, shapes=modes.shapes, modal_loads=modes.shapes.T @ F)


def modal_correction(modal_loads: np.ndarray, hz: np.ndarray, C: np.ndarray, speed, damping: float) -> np.ndarray:
    """(..., steps, m): ``delta q_m(t) = q_m(t) - p_m(t) / omega_m^2`` at each step of one
    revolution, for coefficients ``C`` (..., steps, k) (one history or a stack of them) at
    crank ``speed`` rad/s (a scalar, or one per history: shape ``C.shape[:-2]``) with modal
    ``damping`` (ratio of critical). The first and last steps are the same instant; a
    history at speed 0 has no correction."""
    steps = C.shape[-2]
    lead = C.shape[:-2]
    if steps < 3:
        return np.zeros((*lead, steps, hz.size))
    if not np.all(np.isfinite(hz) & (hz > 0.0)):  # a held part's modes are elastic
        raise NumericalError(f"a mode at {np.min(hz):g} Hz: the eigensolve failed; ask for fewer modes", "dynamic.modes")
    speed = np.broadcast_to(np.asarray(speed, float), lead)
    p = C[..., :-1, :] @ modal_loads.T  # (..., T, m): one period without the repeated end point
    P = np.fft.rfft(p, axis=-2)
    n = np.arange(P.shape[-2])[:, None]  # harmonic number
    w = 2 * np.pi * hz  # (m,)
    W = n * speed[..., None, None]  # (..., H, 1)
    H = 1.0 / (w**2 - W**2 + 2j * damping * w * W) - 1.0 / w**2
    dq = np.fft.irfft(P * H, n=steps - 1, axis=-2)
    dq = np.where((speed > 0)[..., None, None], dq, 0.0)
    return np.concatenate([dq, dq[..., :1, :]], axis=-2)


def harmonic_spectrum(C: np.ndarray) -> np.ndarray:
    """(..., k, H): the harmonics of periodic histories ``C`` (..., steps, k) over one
    revolution (the repeated end point left out), harmonic n in column n of each history's
    row (harmonics last: the transforms run over contiguous memory, twice as fast as
    across it on 720 steps, with the same bits)."""
    return np.fft.rfft(np.swapaxes(C[..., :-1, :], -1, -2), axis=-1)


def one_mode_peak(P: np.ndarray, steps: int, speed, hz, damping: float) -> np.ndarray:
    """(..., k): the largest absolute value over the cycle of each history of spectrum
    ``P`` (..., k, H) (:func:`harmonic_spectrum` of ``steps`` steps) filtered harmonic by
    harmonic by the one-mode response ``H(r) = 1 / (1 - r^2 + 2 i zeta r)``,
    ``r = n Omega / omega_1`` (crank ``speed`` rad/s, lowest natural frequency ``hz`` Hz,
    scalars or one per history)."""
    lead = P.shape[:-2]
    speed = np.broadcast_to(np.asarray(speed, float), lead)
    hz = np.broadcast_to(np.asarray(hz, float), lead)
    n = np.arange(P.shape[-1])
    r = n * (speed / (2 * np.pi * hz))[..., None, None]  # (..., 1, H)
    return np.abs(np.fft.irfft(P / (1.0 - r**2 + 2j * damping * r), n=steps - 1, axis=-1)).max(axis=-1)


def one_mode_amplification(C: np.ndarray, speed, hz, damping: float) -> tuple[np.ndarray, np.ndarray]:
    """(ratio, peak), each (..., k): the one-mode estimate of each coefficient column's
    dynamic amplification (docs/model.md) and the column's peak: each column of
    ``C`` (..., steps, k) filtered as :func:`one_mode_peak` says, its peak over the
    column's own (1 for a column that is zero). The first and last steps are the same
    instant."""
    steps = C.shape[-2]
    lead = C.shape[:-2]
    peak = np.abs(C).max(axis=-2) if steps else np.zeros((*lead, C.shape[-1]))
    if steps < 3:
        return np.ones_like(peak), peak
    filtered = one_mode_peak(harmonic_spectrum(C), steps, speed, hz, damping)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(peak > 0, filtered / np.where(peak > 0, peak, 1.0), 1.0), peak
