"""PNG plots of a kinematics run (the seed's figures 4-9): reactions and torque against
crank angle, and the coupler and rocker angles, angular velocities and accelerations.
Axes in degrees, N and N m. matplotlib is imported here only, with the Agg backend."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railcheck.check.kinematics_stage import KinematicsResult
from railcheck.files import atomic_path


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
    ax.axhline(limit / 1e6, color="k", lw=0.8, ls=":", label=f"limit {limit / 1e6:.0f} MPa")
    ax.set(
        xlabel="crank angle θ2 (deg)",
        ylabel="von Mises (MPa)",
        xlim=(0, 360),
        ylim=(0, None),
        title=f"{name}: von Mises over one crank revolution (joint {h.joint})",
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    return path
