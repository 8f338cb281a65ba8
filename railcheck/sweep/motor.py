"""The motor's demand in the sweep: peak torque and power at each speed, at the safe speed,
and over a curve of speeds around the sweep's (N m, W; speeds in rad/s inside).
"""

from __future__ import annotations

import numpy as np

from railcheck.sweep.context import Loads, SweepContext

#: points of the motor curve (required torque against crank speed), evenly spaced from
#: 0 to ``MOTOR_CURVE_SPAN`` x the largest listed speed
MOTOR_CURVE_POINTS = 61
MOTOR_CURVE_SPAN = 3.0


def motor_curve_speeds(speeds) -> np.ndarray:
    """(G,) rad/s: the speeds at which the sweep records every setting's motor demand."""
    return np.linspace(0.0, MOTOR_CURVE_SPAN * max(speeds), MOTOR_CURVE_POINTS)


def torque_parts(loads: Loads, rows: np.ndarray) -> tuple[np.ndarray | None, np.ndarray | None]:
    """(gravity part, inertial part at the first speed) of the motor torque (R, T) N m over
    the cycle of the revolving settings ``rows``, each None without that effect."""
    return tuple(None if d is None else d.torque[rows] for d in (loads.constant, loads.inertial))  # type: ignore[return-value]


def torque_at(parts: tuple[np.ndarray | None, np.ndarray | None], s: np.ndarray) -> np.ndarray:
    """(R, T) N m: the motor torque over the cycle at speed ratios squared ``s`` (R,) from
    its :func:`torque_parts`: the gravity part plus ``s`` times the inertial part."""
    constant, inertial = parts
    out = np.zeros(next(p for p in parts if p is not None).shape)
    if constant is not None:
        out += constant
    if inertial is not None:
        out += s[:, None] * inertial
    return out


def motor_demand(loads: Loads, speed0: float, speeds: np.ndarray) -> dict:
    """Per setting (S, G) at each crank speed of ``speeds`` (rad/s): ``torque_peak_Nm``,
    ``torque_rms_Nm`` and ``power_peak_W`` (peak torque x speed: the speed is constant).
    Without gravity the torque is ``s`` times the first speed's (every acceleration scales
    with omega^2), so its peak and RMS scale too; with gravity each speed is evaluated."""
    s = (speeds / speed0) ** 2
    if loads.constant is None:
        assert loads.inertial is not None  # a sweep simulates gravity, inertia or both
        Ti = loads.inertial.torque  # (S, T)
        peak = np.abs(Ti).max(axis=1)[:, None] * s[None, :]
        rms = np.sqrt(np.mean(Ti**2, axis=1))[:, None] * s[None, :]
    else:
        Tg = loads.constant.torque
        Ti = loads.inertial.torque if loads.inertial is not None else np.zeros_like(Tg)
        T = Tg[:, None, :] + s[None, :, None] * Ti[:, None, :]  # (S, G, T)
        peak, rms = np.abs(T).max(axis=-1), np.sqrt(np.mean(T**2, axis=-1))
    return {"torque_peak_Nm": peak, "torque_rms_Nm": rms, "power_peak_W": peak * speeds}


def demand_at_safe(ctx: SweepContext, torque: tuple, safe_s: np.ndarray) -> dict:
    """The motor's peak and RMS torque (N m) and peak power (W) of settings whose
    :func:`torque_parts` are ``torque`` at their safe speed ratio squared ``safe_s``: NaN
    where the safe speed is not finite."""
    out = {
        k: np.full(safe_s.size, np.nan) for k in ("torque_peak_at_safe_Nm", "torque_rms_at_safe_Nm", "power_peak_at_safe_W")
    }
    finite = np.isfinite(safe_s)
    T = torque_at(tuple(None if p is None else p[finite] for p in torque), safe_s[finite])  # type: ignore[arg-type]
    peak = np.abs(T).max(axis=1)
    out["torque_peak_at_safe_Nm"][finite] = peak
    out["torque_rms_at_safe_Nm"][finite] = np.sqrt(np.mean(T**2, axis=1))
    out["power_peak_at_safe_W"][finite] = peak * ctx.speeds[0] * np.sqrt(safe_s[finite])
    return out


#: the chunk's per-setting motor curve travels with its columns under this key (the
#: aggregate takes it; it is not a table column)
MOTOR_CURVE_KEY = "_motor_curve"


def motor_columns(ctx: SweepContext, n: int, idx: np.ndarray, rev: dict, passed: np.ndarray) -> dict:
    """``columns``: the motor's demand at each setting's safe speed (peak and RMS torque
    N m, peak power W; null without a finite safe speed); ``curve``: ``rows``, the
    settings that pass the configuration checks (the only ones the motor curve counts; a
    chunk's other settings' curves never leave it), and quantity -> (rows, G) their
    demand at :func:`motor_curve_speeds` (NaN where a setting does not revolve)."""
    grid = motor_curve_speeds(ctx.speeds)
    rows = np.flatnonzero(passed)
    curve: dict = {k: np.full((rows.size, grid.size), np.nan) for k in ("torque_peak_Nm", "torque_rms_Nm", "power_peak_W")}
    cols = {k: np.full(n, np.nan) for k in ("torque_peak_at_safe_Nm", "torque_rms_at_safe_Nm", "power_peak_at_safe_W")}
    position = np.full(n, -1)
    position[rows] = np.arange(rows.size)
    at = position[idx]  # each revolving setting's row in the curve, -1 if it fails a check
    for k, v in rev.get("curve", {}).items():
        curve[k][at[at >= 0]] = v[at >= 0]
    curve["rows"] = rows
    for k, v in rev.get("at_safe", {}).items():
        cols[k][rev["fe_at"]] = v
    return {"columns": cols, "curve": curve}
