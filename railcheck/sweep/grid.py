"""The rig's settings: every bar length the rails' mounting holes allow (seed 000).

Each bar's rail is screwed to its first joint's upper plate through its first two mounting
holes, the joint's shaft midway between them, and its far joint's plate is screwed through
two other neighbouring holes, its shaft midway between those, so a bar's settable lengths
are ``k x pitch`` for ``k = 1 .. holes - 2``. The
holes follow the size-25 rail catalogue (:class:`railcheck.geometry.catalogue.RailSpec`: 60 mm
pitch, 20 mm end distance). The rails:

* crank 700 mm, coupler 1000 mm, rocker 1000 mm (seed 000, Anexo I; the mass model);
* ground 2500 mm (seed 000, 3.2.1 "L_d = 2500 mm", kept in Anexo I as the limit of d):
  both pivots O2 and O4 sit on its holes, so d is a multiple of the pitch too;
* slider-crank: the crank and coupler on their rails; the slider's carriage runs on the
  ground rail through the crank's pivot, so the offset is 0 (assumed: the seed left the
  slider-crank undone). Extra settings (any offset, or off the grid) come from
  ``[[sweep.settings]]``.

All lengths in m.
"""

from __future__ import annotations

import itertools

import numpy as np

from railcheck.base.errors import InputError
from railcheck.geometry.catalogue import with_overrides
from railcheck.kinematics.massmodel import MassModel

GROUND_RAIL_LENGTH = 2.5  # m, seed 000 3.2.1 and Anexo I
BARS = {"four-bar": ("crank", "coupler", "rocker", "ground"), "slider-crank": ("crank", "coupler", "offset")}


def rail_lengths() -> dict[str, float]:
    """m: the rail each bar's length is set on."""

    m = MassModel()
    return {
        "crank": m.crank_rail_length,
        "coupler": m.coupler_rail_length,
        "rocker": m.rocker_rail_length,
        "ground": GROUND_RAIL_LENGTH,
    }


def settable_lengths(rail_length: float, rail) -> np.ndarray:
    """m: every distance from a rail's first joint (midway between its first two holes)
    to a far joint midway between two other neighbouring holes."""
    holes = np.asarray(rail.hole_positions(rail_length))
    return np.round(np.round((holes[1:-1] - holes[0]) / rail.hole_pitch) * rail.hole_pitch, 12)


def rig_grid(overrides: dict | None = None) -> dict[str, dict[str, np.ndarray]]:
    """kind -> bar -> the settable lengths (m), sorted."""

    rail = with_overrides(overrides or {})[0]
    lengths = {bar: settable_lengths(L, rail) for bar, L in rail_lengths().items()}
    return {
        "four-bar": {bar: lengths[bar] for bar in BARS["four-bar"]},
        "slider-crank": {"crank": lengths["crank"], "coupler": lengths["coupler"], "offset": np.zeros(1)},
    }


def narrowed(grid: dict[str, np.ndarray], ranges: dict) -> dict[str, np.ndarray]:
    """The grid with each bar limited to its [min, max] range (m, inclusive to 1 um).
    Raises :class:`~railcheck.base.errors.InputError` naming ``sweep.BAR`` and the nearest
    settable lengths when a range holds none of them."""
    out = {}
    for bar, values in grid.items():
        lo, hi = ranges.get(bar, (-np.inf, np.inf))
        out[bar] = values[(values >= lo - 1e-6) & (values <= hi + 1e-6)]
        if values.size and not out[bar].size:
            raise InputError(f"sweep.{bar}", _no_setting_message(values, lo, hi))
    return out


def _no_setting_message(values: np.ndarray, lo: float, hi: float) -> str:
    """Which settable lengths (m) lie nearest a range that holds none, in mm."""
    below, above = values[values < lo], values[values > hi]
    near = [f"{x * 1e3:g} mm" for x in np.concatenate([below[-1:], above[:1]])]
    near_text = " and ".join(near) if values.size > 1 else f"{values[0] * 1e3:g} mm only"
    hint = " (other offsets: [[sweep.settings]])" if values.size == 1 else ""
    return f"no settable length of the rig from {lo * 1e3:g} to {hi * 1e3:g} mm; the nearest: {near_text}{hint}"


def settings(kind: str, grid: dict[str, np.ndarray], extra: list[dict] | None = None) -> dict[str, np.ndarray]:
    """bar -> (N,) lengths (m) of every setting: the grid's Cartesian product (the first
    bar varies slowest), then the ``extra`` settings."""
    bars = BARS[kind]
    combos = list(itertools.product(*(grid[b] for b in bars)))
    combos += [tuple(e[b] for b in bars) for e in (extra or [])]
    table = np.array(combos, dtype=float).reshape(-1, len(bars))
    return {bar: table[:, i].copy() for i, bar in enumerate(bars)}
