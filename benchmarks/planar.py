"""Planar mechanism positions against pylinkage and kinepy: the rig's four-bar
(examples/rig-four-bar.toml) and the Watt six-bar (examples/watt-six-bar.toml) over 10,000
driver steps of one crank turn. railcheck twice: the closed form dyad by dyad
(kinematics/planar/dyads.py, vectorised over the steps) and Newton-Raphson continuation
(kinematics/planar/solver.py, a step at a time, with velocities, accelerations and the rank
watch). Each tool's accuracy: the largest error in a bar length its joints keep (m).

pylinkage and kinepy are installed only in the benchmark's environment:

    python3 -m venv /tmp/bench && . /tmp/bench/bin/activate
    pip install . pylinkage kinepy && python benchmarks/planar.py [--write docs/performance.md]

Prints medians of REPEATS runs (Newton: NEWTON_REPEATS) and the ratios, measured in one run;
``--write FILE`` puts the table between FILE's ``<!-- planar -->`` and ``<!-- /planar -->``.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import math
import os
import statistics
import sys
import time
import tomllib
from pathlib import Path

import numpy as np

from railcheck.kinematics.planar.dyads import dyad_positions
from railcheck.kinematics.planar.solver import PlanarMotion, assemble, solve
from railcheck.studies.planar_scene import planar_scene

STEPS = 10_000
REPEATS = 5
NEWTON_REPEATS = 3
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def median_time(run, repeats: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


def bar_error(pairs) -> float:
    """Largest |distance - length| over (P (n, 2), Q (n, 2), length) triples (m)."""
    return max(float(np.abs(np.hypot(*(p - q).T) - length).max()) for p, q, length in pairs)


def railcheck_runs(name: str, bars):
    scene = planar_scene(tomllib.loads((EXAMPLES / f"{name}.toml").read_text()))
    mech = scene.mechanism
    s = np.linspace(0.0, 2 * math.pi, STEPS)
    q0 = assemble(mech, 0.0)

    def points(q):
        z = np.zeros_like(q)
        motion = PlanarMotion(mech, s, q, z, z)
        return {f"{mech.body(k).name}.{p}": motion.point(k, p)[0] for k, b in enumerate(mech.bodies, 1) for p in b.points}

    closed_t, closed = median_time(lambda: dyad_positions(mech, s, q0), REPEATS)
    newton_t, newton = median_time(lambda: solve(mech, s, q0), NEWTON_REPEATS)
    out = {}
    for label, t, q in (("railcheck closed form", closed_t, closed.q), ("railcheck Newton", newton_t, newton.q)):
        pts = points(q)
        out[label] = (t, bar_error([(pts[a], pts[b], length) for a, b, length in bars]))
    return out


def pylinkage_fourbar():
    import pylinkage as pl

    O2, O4 = pl.Ground(0.0, 0.0), pl.Ground(1.02, 0.0)
    crank = pl.Crank(O2, radius=0.48, angular_velocity=2 * math.pi / STEPS)
    B = pl.RRRDyad(crank, O4, distance1=0.84, distance2=0.78, x=0.69, y=0.71)
    linkage = pl.Linkage([O2, O4, crank, B])
    t, pos = median_time(lambda: np.asarray(list(linkage.step(iterations=STEPS))), REPEATS)
    A, Bp = pos[:, 2], pos[:, 3]
    return t, bar_error([(A, Bp, 0.84), (Bp, np.array([1.02, 0.0]), 0.78)])


def pylinkage_watt():
    import pylinkage as pl

    O2, O4, O6 = pl.Ground(0.0, 0.0), pl.Ground(1.02, 0.0), pl.Ground(1.44, 0.90)
    crank = pl.Crank(O2, radius=0.48 / 2, angular_velocity=2 * math.pi / STEPS)
    B = pl.RRRDyad(crank, O4, distance1=0.84, distance2=0.78, x=0.69, y=0.71)
    # C on the rocker: 540, 240 mm in its frame along O4-B, i.e. |O4C| and the angle B-O4-C
    C = pl.FixedDyad(O4, B, distance=math.hypot(0.54, 0.24), angle=-math.atan2(0.24, 0.54))
    D = pl.RRRDyad(C, O6, distance1=0.72, distance2=0.60, x=0.859, y=1.051)
    linkage = pl.Linkage([O2, O4, O6, crank, B, C, D])
    t, pos = median_time(lambda: np.asarray(list(linkage.step(iterations=STEPS))), REPEATS)
    Cp, Dp = pos[:, 5], pos[:, 6]
    return t, bar_error([(pos[:, 3], pos[:, 4], 0.84), (Cp, Dp, 0.72), (Dp, np.array([1.44, 0.90]), 0.60)])


def kinepy_fourbar(six: bool = False):
    from kinepy import System

    system = System()
    crank, coupler, rocker = (system.add_solid(n) for n in ("crank", "coupler", "rocker"))
    r1 = system.add_revolute(0, crank)
    radius = 240 if six else 480
    system.add_revolute(crank, coupler, (radius, 0), (0, 0))
    rB = system.add_revolute(coupler, rocker, (840, 0), (780, 0))
    system.add_revolute(rocker, 0, (0, 0), (1020, 0))
    joints = [rB]
    if six:
        link, output = system.add_solid("link"), system.add_solid("output")
        rC = system.add_revolute(rocker, link, (540, 240), (0, 0))
        rD = system.add_revolute(link, output, (720, 0), (600, 0))
        system.add_revolute(output, 0, (0, 0), (1440, 900))
        joints += [rC, rD]
    system.pilot(r1)
    with contextlib.redirect_stdout(io.StringIO()):  # kinepy prints its compilation steps
        system.compile()
    angles = np.linspace(0.0, 360.0, STEPS)
    t, _ = median_time(lambda: system.solve_kinematics(angles), REPEATS)
    pts = [np.asarray(j.point).T * 1e-3 for j in joints]
    if six:
        return t, bar_error([(pts[1], pts[2], 0.72), (pts[2], np.array([1.44, 0.90]), 0.60)])
    return t, bar_error([(pts[0], np.array([1.02, 0.0]), 0.78)])


def write_block(path: Path, lines: list[str]) -> None:
    """Replace the lines between ``<!-- planar -->`` and ``<!-- /planar -->`` of ``path``."""
    text = path.read_text()
    start, end = "<!-- planar -->\n", "<!-- /planar -->"
    if start not in text or end not in text:
        raise SystemExit(f"{path}: no {start.strip()} ... {end} block to fill")
    before, rest = text.split(start, 1)
    path.write_text(before + start + "\n".join(lines) + "\n" + end + rest.split(end, 1)[1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", type=Path, help="a Markdown file whose planar block gets this run's table")
    args = parser.parse_args()
    fourbar_bars = [("coupler.A", "coupler.B", 0.84), ("rocker.O4", "rocker.B", 0.78)]
    watt_bars = [("coupler.A", "coupler.B", 0.84), ("link.C", "link.D", 0.72), ("output.O6", "output.D", 0.60)]
    rows = []
    for name, bars, others in (
        ("four-bar", fourbar_bars, (("pylinkage", pylinkage_fourbar), ("kinepy", lambda: kinepy_fourbar(False)))),
        ("Watt six-bar", watt_bars, (("pylinkage", pylinkage_watt), ("kinepy", lambda: kinepy_fourbar(True)))),
    ):
        results = railcheck_runs("rig-four-bar" if name == "four-bar" else "watt-six-bar", bars)
        for label, run in others:
            try:
                results[label] = run()
            except ImportError:
                print(f"{label} is not installed here (pip install {label} in the benchmark's environment)", file=sys.stderr)
        base = results["railcheck closed form"][0]
        for label, (t, err) in results.items():
            rows.append(f"| {name} | {label} | {t * 1e3:.1f} ms | {t / base:.1f} | {err:.1e} m |")
    lines = [
        f"`python benchmarks/planar.py`, {time.strftime('%Y-%m-%d')}, {os.cpu_count()} cores: positions over "
        f"{STEPS:,} driver steps, medians of {REPEATS} runs (Newton {NEWTON_REPEATS}), one process.",
        "",
        "| mechanism | tool | time | / railcheck closed form | largest bar-length error |",
        "| --- | --- | --- | --- | --- |",
        *rows,
    ]
    print("\n".join(lines))
    if args.write:
        write_block(args.write, lines)


if __name__ == "__main__":
    main()
