"""PNG plots of a kinematics run (the seed's figures 4-9): reactions and torque against
crank angle, and the coupler and rocker angles, angular velocities and accelerations.
Axes in degrees, N and N m. matplotlib is imported here only, with the Agg backend."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from railcheck.files import atomic_path

if TYPE_CHECKING:  # a type only: importing railcheck.check here would be circular
    from railcheck.model.kinematics_stage import KinematicsResult


def _figure():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def write_kinematics_plots(result: KinematicsResult, directory: str | Path) -> list[Path]:
    """Write reactions.png, torque.png, angles.png, angular_velocities.png and
    angular_accelerations.png into ``directory``; return their paths."""
    plt = _figure()
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    motion, dyn = result.motion, result.dynamics
    deg = np.degrees(motion.theta2)
    written = []

    def save(fig, name):
        path = directory / name
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=110, format="png")
        plt.close(fig)
        written.append(path)

    fig, ax = plt.subplots(figsize=(8, 4.5))
    for joint in dyn.reactions:
        value, k = dyn.peak(joint)
        ax.plot(deg, dyn.magnitude(joint), label=f"{joint} (peak {value:.1f} N at {deg[k]:.1f}°)")
    ax.set(
        xlabel="crank angle θ2 (deg)",
        ylabel="reaction magnitude (N)",
        title=f"Joint reactions, {dyn.formulation}, effects: {', '.join(result.effects) or 'none'}",
    )
    ax.set_xlim(0, 360)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    save(fig, "reactions.png")

    fig, ax = plt.subplots(figsize=(8, 4.5))
    value, k = dyn.peak_torque()
    ax.plot(deg, dyn.torque, color="k", label=f"peak |M2| {value:.1f} N·m at {deg[k]:.1f}°")
    ax.set(xlabel="crank angle θ2 (deg)", ylabel="motor torque M2 (N·m)", title="Motor torque")
    ax.set_xlim(0, 360)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    save(fig, "torque.png")

    names = ("crank θ2", "coupler θ3", "output θ4")
    for key, data, unit, title, fname in (
        ("theta", np.degrees(np.unwrap(motion.theta, axis=0)), "deg", "Bar angles", "angles.png"),
        ("omega", motion.omega, "rad/s", "Angular velocities", "angular_velocities.png"),
        ("alpha", motion.alpha, "rad/s²", "Angular accelerations", "angular_accelerations.png"),
    ):
        fig, ax = plt.subplots(figsize=(8, 4.5))
        for j in (1, 2):
            ax.plot(deg, data[:, j], label=names[j].replace("θ", {"theta": "θ", "omega": "ω", "alpha": "α"}[key]))
        ax.set(xlabel="crank angle θ2 (deg)", ylabel=f"{title.lower()} ({unit})", title=title)
        ax.set_xlim(0, 360)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        save(fig, fname)
    return written


def cycle_axis_top(peak: float, seed_peak: float, limit: float) -> float:
    """The cycle plot's upper stress limit (Pa): scaled to the data (15% above the larger
    of the curve's and the seed method's peak), reaching up to the limit only when the
    limit is within twice that, so a 3 MPa cycle is not drawn on a 375 MPa axis."""
    data = 1.15 * max(peak, seed_peak, 1e-9)
    return 1.05 * limit if limit <= 2.0 * data else data


def write_cycle_plot(name: str, part, path: str | Path) -> Path:
    """The governing node's von Mises over the crank angle, the seed method's instant and
    the limit marked (Pa -> MPa on the axis)."""
    plt = _figure()
    h, limit = part.cycle.history, part.limit
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(
        h.angles_deg,
        h.von_mises / 1e6,
        color="C0",
        label=f"governing node, peak {part.verdict_stress / 1e6:.1f} MPa at {h.crank_angle_deg:.1f}°",
    )
    seed = part.cycle.seed_method
    ax.axvline(
        h.seed_angle_deg,
        color="C3",
        ls="--",
        label=f"seed method instant {seed.crank_angle_deg:.1f}° (peak |R_{h.joint}|): "
        f"{seed.max_von_mises / 1e6:.1f} MPa at its own peak node",
    )
    top = cycle_axis_top(float(np.max(h.von_mises)), seed.max_von_mises, limit)
    if limit <= top:
        ax.axhline(limit / 1e6, color="k", lw=0.8, ls=":", label=f"limit {limit / 1e6:.0f} MPa")
    ax.set(
        xlabel="crank angle θ2 (deg)",
        ylabel="von Mises (MPa)",
        xlim=(0, 360),
        ylim=(0, top / 1e6),
        title=f"{name}: von Mises over one crank revolution (joint {h.joint})"
        + (
            ""
            if limit <= top
            else f"\nlimit {limit / 1e6:.0f} MPa: {limit / max(part.verdict_stress, 1e-9):.3g}x the peak, off the axis"
        ),
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    return path


def write_campbell_plot(parts: dict, path: str | Path) -> Path | None:
    """Campbell diagram: the crank harmonics n x crank speed against crank speed from 0 to
    3x the scene's, and each part's lowest natural frequencies as horizontal lines; where
    a harmonic line crosses a frequency the cycle excites that mode in resonance. ``parts``
    maps a name to its :class:`~railcheck.model.records.PartResult` (those without a
    dynamic response are left out). None when no part has one."""
    dynamic = {n: p.cycle.dynamic for n, p in parts.items() if p.cycle.dynamic is not None}
    if not dynamic:
        return None
    plt = _figure()
    crank = next(iter(dynamic.values())).crank_hz
    firsts = [float(d.hz[0]) for d in dynamic.values()]
    lowest = min(firsts)
    top = min(1.3 * max(firsts), 4.0 * lowest)  # the lowest modes, where resonance comes first
    fig, ax = plt.subplots(figsize=(8, 5))
    reach = int(np.ceil(top / (3.0 * crank)))  # the harmonics that reach the top by 3x the speed
    harmonics = [n for n in range(1, reach + 1) if n <= 10 or (n <= 50 and n % 5 == 0) or n % 10 == 0]
    for n in harmonics:
        ax.plot([0.0, 3.0 * crank], [0.0, 3.0 * n * crank], color="0.7", lw=0.7, zorder=1)
        if n > 1 and n % 5:
            continue  # label 1x, 5x, 10x, ...
        x = min(3.0 * crank, 0.98 * top / n)
        ax.annotate(f"{n}×", (x, n * x), fontsize=7, color="0.35", ha="right", va="bottom")
    above = []
    for k, (name, d) in enumerate(dynamic.items()):
        shown = [f for f in d.hz[:3] if f <= top]
        for j, f in enumerate(shown):
            ax.axhline(f, color=f"C{k}", lw=1.6, ls="-" if j == 0 else "--", label=f"{name}: {f:.3g} Hz")
        if not shown:
            above.append(f"{name} {d.hz[0]:.3g} Hz")
    ax.axvline(crank, color="k", lw=1.0, ls=":", label=f"scene speed {crank:.3g} Hz")
    ax.set(
        xlabel="crank speed (Hz)",
        ylabel="frequency (Hz)",
        xlim=(0, 3.0 * crank),
        ylim=(0, top),
        title="Campbell diagram: crank harmonics n × speed against the parts' natural frequencies\n"
        f"(lowest {lowest:.3g} Hz, harmonic {lowest / crank:.1f} of the scene's speed)"
        + (f"; above the plot: {', '.join(above)}" if above else ""),
    )
    ax.grid(alpha=0.25)
    ax.legend(fontsize=7, loc="upper left")
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    return path
