"""The joints' load paths as one picture (joints.png): a column per joint with a checked
component, from the rail the joint force comes from, through each component in the order
the force passes it (docs/components.md), to the rail or frame it ends in. Each box
names the component, its verdict's utilisation and criterion over the whole cycle, and
the loads it carries at the joint's governing instant, each marked factored (x the load
factor) or unfactored. A schematic, not to scale. matplotlib (Agg) imported here only."""

from __future__ import annotations

from pathlib import Path

from railcheck.files import atomic_path

#: a component's figures that are loads at the instant (kN or N m), in the picture's words
LOAD_WORDS = {
    "force_N": ("F", 1e-3, "kN"),
    "moment_Nm": ("M", 1.0, "N m"),
    "mean_moment_Nm": ("M mean", 1.0, "N m"),
    "torque_Nm": ("T", 1.0, "N m"),
    "shear_N": ("V per screw", 1e-3, "kN"),
    "tension_N": ("N per screw", 1e-3, "kN"),
    "peak_load_N": ("P per bearing", 1e-3, "kN"),
    "equivalent_load_N": ("P0", 1e-3, "kN"),
}


def instant_loads(figures: dict, factored: bool, factor: float) -> str:
    """A component's loads at the instant, e.g. "F 3.20 kN (x1.4)" or "P0 2.27 kN
    (unfactored)"; zero torques and mean moments left out."""
    words = []
    for key, (name, scale, unit) in LOAD_WORDS.items():
        v = figures.get(key)
        if v is None or (key in ("torque_Nm", "mean_moment_Nm") and v == 0.0):
            continue
        words.append(f"{name} {v * scale:.3g} {unit}")
    tag = f"x{factor:g}" if factored else "unfactored"
    return f"{', '.join(words)} ({tag})" if words else ""


def write_joint_diagram(path: str | Path, paths: dict, verdicts: dict, factor: float) -> Path | None:
    """Draw ``paths`` (joint -> :class:`railcheck.components.load_path.JointPath`) into
    ``path`` (PNG); ``verdicts`` name -> the check's :class:`ComponentResult` over the
    whole cycle (its utilisation and criterion label each box). None if no joint."""
    if not paths:
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = max(len(p.components) for p in paths.values()) + 2
    fig, axes = plt.subplots(1, len(paths), figsize=(3.4 * len(paths), 1.15 * rows + 1.2), squeeze=False)
    for ax, p in zip(axes[0], paths.values()):
        _draw_joint(ax, p, verdicts, factor, rows)
    fig.suptitle(
        "Joints' load paths at each joint's governing instant (schematic, not to scale)\n"
        "box: component, utilisation over the cycle (criterion); loads at the instant, factored or not",
        fontsize=9,
    )
    fig.tight_layout(rect=(0, 0, 1, 0.93))
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    return path


def _draw_joint(ax, p, verdicts: dict, factor: float, rows: int) -> None:
    """One joint's column: the source rail, the components, the sink, arrows between."""
    ax.set_xlim(0, 1)
    ax.set_ylim(0, rows)
    ax.axis("off")
    ax.set_title(
        f"joint {p.joint}: {p.force_N:.0f} N (x{factor:g}: {factor * p.force_N:.0f} N)\ncrank at {p.crank_deg:.1f} deg",
        fontsize=8.5,
    )
    y = rows - 0.5
    _box(ax, y, p.source, "the joint force comes from here", "#dddddd")
    for name, c in p.components.items():
        y -= 1.0
        _arrow(ax, y)
        whole = verdicts[name]
        colour = "#f4c7c3" if whole.utilisation > 1.0 else "#cfe8cf"
        head = f"{name}: {whole.utilisation:.0%} ({whole.governing_criterion})"
        _box(ax, y, head, instant_loads(c.figures, c.factored, factor), colour)
    y -= 1.0
    _arrow(ax, y)
    _box(ax, y, p.sink, "", "#dddddd")


def _box(ax, y: float, title: str, detail: str, colour: str) -> None:
    from matplotlib.patches import FancyBboxPatch

    ax.add_patch(FancyBboxPatch((0.03, y - 0.32), 0.94, 0.64, boxstyle="round,pad=0.02", fc=colour, ec="#555555", lw=0.8))
    ax.text(0.5, y + (0.1 if detail else 0.0), title, ha="center", va="center", fontsize=7.5, weight="bold")
    if detail:
        ax.text(0.5, y - 0.15, detail, ha="center", va="center", fontsize=6.5, wrap=True)


def _arrow(ax, y: float) -> None:
    """The force passing from the box above (at ``y + 1``) to the box at ``y``."""
    ax.annotate("", xy=(0.5, y + 0.34), xytext=(0.5, y + 0.66), arrowprops={"arrowstyle": "-|>", "color": "#333333"})
