"""The sweep's pictures: per kind the maps of utilisation, safe speed and why settings fail
(:func:`write_maps`), and the motor's torque and power envelope (:func:`write_motor_plot`),
from each kind's :class:`~railcheck.sweep.aggregate.Aggregate`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railcheck.files import atomic_path
from railcheck.studies.hypotheses import FINAL_DESIGN_MM, MOTOR_ESTIMATE_2013_NM
from railcheck.sweep.aggregate import REASON_ORDER, Aggregate
from railcheck.units import nice_top


def write_maps(aggregates: dict, directory: Path) -> None:
    """``map-KIND.png``: utilisation and safe speed over pairs of bars (the worst over the
    other bars; without FE parts the largest reaction and motor torque), refused cells
    coloured by a failing check."""
    import matplotlib

    matplotlib.use("Agg")
    for kind, agg in aggregates.items():
        if agg.util.size:
            _map_figure(agg, directory / f"map-{kind}.png")


#: one colour per refusal reason of REASON_ORDER
REASON_COLOURS = ["#bdbdbd", "#fdae6b", "#9ecae1", "#f781bf", "#cab2d6", "#a1d99b", "#ffffb3"]


def _map_figure(agg: Aggregate, path: Path) -> None:
    """One row per map (each part whose loads depend on the setting: its utilisation at the
    first speed; then the lowest safe speed), one column per pair of bars (the worst over
    the other bars); utilisation on a scale from 0 with the utilisation-1 contour; refused
    cells coloured by their first failing check, with only the checks that occur in the
    legend; constant-load parts listed in the title."""
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    pairs = [(0, 1), (2, 3)] if len(agg.bars) == 4 else [(0, 1)]
    has_fe = not np.all(np.isnan(agg.util))
    panels = _panels(agg, has_fe)
    tops = shared_tops(agg, panels)
    fig, axes = plt.subplots(
        len(panels), len(pairs), figsize=(max(9.0, 6.5 * len(pairs)), 3.6 * len(panels) + 1.6), squeeze=False
    )
    for col, (a, b) in enumerate(pairs):
        for row, panel in enumerate(panels):
            _map_panel(fig, axes[row, col], agg, a, b, panel, tops[row])
    handles: list = [
        Patch(color=REASON_COLOURS[REASON_ORDER.index(r)], label=f"refused: {r.replace('_', ' ')}")
        for r in occurring_reasons(agg)
    ]
    if agg.kind == "four-bar":
        handles.append(Line2D([], [], marker="*", ms=11, mfc="white", mec="black", ls="none", label="the 2013 final design"))
    if handles:
        fig.legend(handles=handles, loc="lower center", ncol=min(4, len(handles)), fontsize=8)
    note = " (red line: utilisation 1)" if has_fe or agg.component_util is not None else ""
    constant = (
        f"\nconstant loads, the same for every setting (not mapped): {', '.join(agg.constant_parts)}"
        if agg.constant_parts
        else ""
    )
    fig.suptitle(
        f"railcheck sweep, {agg.kind} at {agg.first_speed:g} Hz: settings that pass every configuration "
        f"check in colour{note}{constant}",
        fontsize=10,
    )
    _fixed_layout(fig, len(panels), len(pairs), bottom=1.0 if handles else 0.6)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=100)
    plt.close(fig)


def _panels(agg: Aggregate, has_fe: bool) -> list[tuple]:
    """(data, reduction, label, colour map, is a utilisation) of each row of maps: each
    part's utilisation, the components' largest, and the lowest safe speed; without FE
    parts the loads instead of the parts."""
    components = (
        [(agg.component_util, np.nanmax, "the joints' components: largest utilisation (1 = limit)", "viridis", True)]
        if agg.component_util is not None
        else []
    )
    if not has_fe:  # no FE parts: the loads instead
        return [
            (agg.reaction, np.nanmax, "largest peak joint reaction (N)", "viridis", False),
            (agg.torque, np.nanmax, "largest peak motor torque (N·m)", "viridis", False),
            *components,
        ]
    panels = [(g, np.nanmax, f"{n}: utilisation (1 = limit)", "viridis", True) for n, g in agg.part_util.items()]
    return [*panels, *components, (agg.safe, np.nanmin, "lowest safe crank speed (Hz)", "viridis_r", False)]


def shared_tops(agg: Aggregate, panels: list[tuple]) -> list[float]:
    """Each panel row's colour-scale end, one per quantity across the figure: every
    utilisation map (the parts' and the components') on one scale from 0 to at least 1,
    each other quantity on its own; each a :func:`nice_top` of the largest finite value,
    so a 0.1-utilised plate reads cooler than a 0.9-utilised rail."""

    def largest(data) -> float:
        finite = np.asarray(data, float)[np.isfinite(data)]
        return float(finite.max()) if finite.size else 1.0

    util_top = max([1.0] + [largest(p[0]) for p in panels if p[4]])
    return [nice_top(util_top if p[4] else largest(p[0])) for p in panels]


def _map_panel(fig, ax, agg: Aggregate, a: int, b: int, panel: tuple, top: float) -> None:
    """One map over bars ``a`` and ``b`` (mm), the worst over the others: refused cells by
    their reason, the panel's quantity in colour from 0 to ``top`` (shared by the figure's
    panels of that quantity), the utilisation-1 contour, the safe speed's contours at 1 Hz
    and at the sweep's first speed, the settings whose safe speed the dynamic response
    sets."""
    import warnings

    from matplotlib.colors import ListedColormap

    data, reduce, label, cmap, is_util = panel
    others = tuple(i for i in range(len(agg.bars)) if i not in (a, b))
    reasons = np.max(agg.reason, axis=others) if others else agg.reason
    xs, ys = agg.grid[agg.bars[a]] * 1e3, agg.grid[agg.bars[b]] * 1e3
    extent = _extent(xs, ys)
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        grid = reduce(data, axis=others) if others else data
    refused = np.ma.masked_where(~np.isnan(grid) | (reasons < 0), reasons)
    style = {"origin": "lower", "extent": extent, "aspect": "auto", "interpolation": "nearest"}
    reason_colours = ListedColormap(REASON_COLOURS)
    ax.imshow(refused.T, cmap=reason_colours, vmin=0, vmax=len(REASON_ORDER) - 1, **style)
    finite = grid[np.isfinite(grid)]
    im = ax.imshow(np.ma.masked_invalid(grid).T, cmap=cmap, vmin=0, vmax=top, **style)
    fig.colorbar(im, ax=ax, label=label.split(": ")[-1])
    if is_util and finite.size and finite.min() < 1 < finite.max() and min(grid.shape) > 1:
        # refused cells masked: a contour against them would draw a limit that is not there
        ax.contour(xs, ys, np.ma.masked_invalid(grid).T, levels=[1.0], colors="red", linewidths=1.5)
    if data is agg.safe:
        _speed_contours(ax, grid, xs, ys, sorted({1.0, float(agg.first_speed)}))
    if data is agg.safe and agg.safe_dynamic.any():
        _mark_dynamic(ax, agg, others, xs, ys)
    if agg.kind == "four-bar":  # the 2013 study's final design
        at = (FINAL_DESIGN_MM[agg.bars[a]], FINAL_DESIGN_MM[agg.bars[b]])
        ax.plot(*at, marker="*", ms=13, mfc="white", mec="black", ls="none", label="the 2013 final design")
    ax.set_xlabel(f"{agg.bars[a]} (mm)")
    ax.set_ylabel(f"{agg.bars[b]} (mm)")
    over = f", worst over {' and '.join(agg.bars[i] for i in others)}" if others else ""
    ax.set_title(f"{label.split(' (')[0]}{over}", fontsize=9)


def _speed_contours(ax, safe: np.ndarray, xs: np.ndarray, ys: np.ndarray, speeds: list[float]) -> None:
    """The safe-speed map's contours at ``speeds`` (Hz; 1 Hz solid, another dashed), drawn
    only where the map crosses them (an unlimited speed counts as above every level; a
    refused cell is left out)."""
    finite = np.ma.masked_invalid(np.where(np.isposinf(safe), 1e9, safe))
    if min(safe.shape) < 2 or finite.count() == 0:
        return
    for hz in speeds:
        if finite.min() < hz < finite.max():
            dashed = "solid" if hz == 1.0 else "dashed"
            ax.contour(xs, ys, finite.T, levels=[hz], colors="red", linewidths=1.3, linestyles=dashed)
            ax.plot([], [], color="red", ls=dashed, label=f"safe speed {hz:g} Hz")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper right", fontsize=7)


#: inches around and between a map figure's panels (:func:`_fixed_layout`): left of the
#: first column (y label and ticks), right of the last colorbar, above the first row (the
#: title, two lines), between rows (a panel's x label and the next one's title), between
#: columns (a colorbar with its label and the next panel's y label)
MAP_MARGINS = {"left": 0.9, "right": 0.3, "top": 1.3, "between_rows": 0.9, "between_columns": 1.1}


def _fixed_layout(fig, rows: int, columns: int, bottom: float) -> None:
    """The map figure's panels placed by fixed margins in inches (:data:`MAP_MARGINS`;
    ``bottom`` below the last row: its x labels and the legend). The figure's layout is
    the same for every sweep (only the numbers change), so it is not measured from the
    drawn text as ``tight_layout`` does, which cost nearly half of the maps' time
    (measured: docs/changelog.md, "The measurements behind tuned constants")."""
    width, height = fig.get_size_inches()
    m = MAP_MARGINS
    panel_w = (width - m["left"] - m["right"] - (columns - 1) * m["between_columns"]) / columns
    panel_h = (height - m["top"] - bottom - (rows - 1) * m["between_rows"]) / rows
    fig.subplots_adjust(
        left=m["left"] / width,
        right=1 - m["right"] / width,
        top=1 - m["top"] / height,
        bottom=bottom / height,
        wspace=m["between_columns"] / panel_w,
        hspace=m["between_rows"] / panel_h,
    )


def occurring_reasons(agg: Aggregate) -> list[str]:
    """The refusal reasons the map legend lists: each the first failing check (in
    :data:`REASON_ORDER`) of some refused setting on the grid."""
    return [REASON_ORDER[int(r)] for r in np.unique(agg.reason) if r >= 0]


def _mark_dynamic(ax, agg: Aggregate, others: tuple, xs: np.ndarray, ys: np.ndarray) -> None:
    """White crosses on the safe-speed panel where the lowest safe speed shown (over the
    other bars) is set by the dynamic amplification rather than by stress or fatigue."""
    safe = np.moveaxis(agg.safe, others, tuple(range(-len(others), 0))) if others else agg.safe[..., None]
    dyn = np.moveaxis(agg.safe_dynamic, others, tuple(range(-len(others), 0))) if others else agg.safe_dynamic[..., None]
    safe, dyn = safe.reshape(*safe.shape[:2], -1), dyn.reshape(*dyn.shape[:2], -1)
    filled = np.where(np.isnan(safe), np.inf, safe)
    pick = np.argmin(filled, axis=2)
    marked = np.take_along_axis(dyn, pick[..., None], axis=2)[..., 0] & np.isfinite(filled.min(axis=2))
    i, j = np.nonzero(marked)
    ax.plot(xs[i], ys[j], "x", color="white", markersize=4, label="safe speed set by dynamics")
    ax.legend(loc="upper right", fontsize=7)


def write_motor_plot(aggregates: dict, path: Path) -> None:
    """``motor.png``: per kind the peak torque a motor must deliver against crank speed to
    drive every setting that passes the configuration checks (whatever the parts' and
    components' verdicts: the motor's demand), beside it the largest over the settings
    still safe at that speed (what their safe speeds cap), the 2013 estimate of 200 N·m as
    a line, the listed speeds marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.0, 5.0 + 0.9 * len(aggregates)))
    drawn = False
    for kind, agg in aggregates.items():
        m = agg.motor_sizing
        finite = lambda v: np.where(np.isfinite(v), v, np.nan)  # noqa: E731
        torque = finite(m.curve["torque_peak_Nm"])
        if not np.any(np.isfinite(torque)):
            continue
        drawn = True
        demand = finite(m.demand["torque_peak_Nm"])
        (line,) = ax.plot(m.curve_hz, demand, lw=2, label=f"{kind}: peak torque to drive every assemblable setting")
        ax.plot(
            m.curve_hz,
            torque,
            lw=1.5,
            ls="--",
            color=line.get_color(),
            label=f"{kind}: only the settings safe at that speed ({_capped_by(agg)})",
        )
        rms = finite(m.curve["torque_rms_Nm"])
        ax.plot(m.curve_hz, rms, lw=1, ls=":", color=line.get_color(), label=f"{kind}: RMS, settings safe there")
        _label_speeds(ax, kind, m, line.get_color())
    ax.axhline(MOTOR_ESTIMATE_2013_NM, color="grey", lw=1, ls=":", label="2013 study's estimate, 200 N·m")
    _estimate_label(ax)
    ax.set_xlabel("crank speed (Hz)")
    ax.set_ylabel("motor torque (N·m)")
    ax.set_yscale("log")  # the demand grows with the speed squared; the safe settings' stays near their limit
    ax.set_ylim(1.0, 2.0 * max(ax.get_ylim()[1], MOTOR_ESTIMATE_2013_NM))
    ax.set_xlim(left=0)
    ax.grid(alpha=0.3)
    ax.set_title(
        "The motor a rig needs: at each crank speed, the largest peak torque over every setting (solid),\n"
        "and over those still safe at that speed (dashed: a setting leaves it above its safe speed)",
        fontsize=9,
    )
    if drawn:  # below the axes: no curve or marker under it
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(0.0, -0.13), ncol=1, frameon=False)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)


def _estimate_label(ax) -> None:
    """The 2013 estimate's words on its line, at its right end, above it."""
    ax.annotate(
        "2013 estimate 200 N·m",
        (1.0, MOTOR_ESTIMATE_2013_NM),
        xycoords=("axes fraction", "data"),
        xytext=(-4, 3),
        textcoords="offset points",
        ha="right",
        va="bottom",
        fontsize=8,
        color="dimgrey",
    )


def _capped_by(agg) -> str:
    """What caps the safe settings' curve: the criteria that set the settings' safe speeds,
    most settings first (``agg.safe_criteria``)."""
    ranked = sorted(agg.safe_criteria.items(), key=lambda kv: -kv[1])
    words = ", ".join(f"{crit} {n:,}" for crit, n in ranked[:3])
    return f"their safe speeds set by {words}" if words else "no safe speed limits them"


def _label_speeds(ax, kind: str, m, colour) -> None:
    """Mark a kind's peak torque at each listed speed (circles) and its largest at a
    setting's own safe speed (a square), their values in the legend (labels on the axes
    ran into the curves and the axis label)."""
    for v, entry in m.by_speed.items():
        if "torque_peak_Nm" in entry:
            t = entry["torque_peak_Nm"]["value"]
            ax.plot(
                [float(v)],
                [t],
                "o",
                color=colour,
                label=f"{kind}: {t:.0f} N·m, the largest over the settings that pass at {float(v):g} Hz",
            )
    safe = m.at_safe.get("torque_peak_Nm")
    if safe:
        ax.plot(
            [safe["safe_speed_Hz"]],
            [safe["value"]],
            "s",
            color=colour,
            label=f"{kind}: {safe['value']:.0f} N·m, the largest at a setting's own safe speed "
            f"({safe['safe_speed_Hz']:.2f} Hz)",
        )


def _extent(xs: np.ndarray, ys: np.ndarray) -> tuple:
    dx = (xs[1] - xs[0]) if xs.size > 1 else 60.0
    dy = (ys[1] - ys[0]) if ys.size > 1 else 60.0
    return (xs.min() - dx / 2, xs.max() + dx / 2, ys.min() - dy / 2, ys.max() + dy / 2)
