"""Benchmark: one configuration's crank cycle, closed form vectorised over the steps against
a per-step loop written the way seed 000's MATLAB does it (fsolve for the position from
the previous step's solution, a 2x2 solve for velocity and acceleration, a 9x9 LU solve
for the reactions), both in one run. Prints medians per step and their ratio.

The closed form runs 1,000,000 steps in a fresh Python process (interpreter start-up and
imports included in its wall time); the loop runs ``--loop-steps`` steps (its cost per
step does not depend on the count).

    python benchmarks/kinematics.py [--repeat 5] [--steps 1000000] [--loop-steps 5000]
"""

from __future__ import annotations

import argparse
import math
import statistics
import subprocess
import sys
import time

import numpy as np
from scipy.optimize import fsolve

from railcheck.kinematics.dynamics import inverse_dynamics
from railcheck.kinematics.linkage import FourBar
from railcheck.kinematics.motion import solve_motion

L2, L3, L4, D = 0.48, 0.84, 0.78, 1.02


VECTORISED = """
import sys, time
t0 = time.perf_counter()
import math
from railcheck.kinematics.linkage import FourBar
from railcheck.kinematics.motion import solve_motion
from railcheck.kinematics.dynamics import inverse_dynamics
motion = solve_motion(FourBar({L2}, {L3}, {L4}, {D}), 2 * math.pi, {steps})
dyn = inverse_dynamics(motion, "seed-2013")
print(dyn.peak("O2")[0], time.perf_counter() - t0)
"""


def vectorised_in_process(steps: int) -> float:
    """s: the same call (kinematics + reactions + peak) in this process, imports done."""
    t = time.perf_counter()
    motion = solve_motion(FourBar(L2, L3, L4, D), 2 * math.pi, steps)
    inverse_dynamics(motion, "seed-2013").peak("O2")
    return time.perf_counter() - t


def vectorised(steps: int) -> tuple[float, float, float]:
    """(wall s of a fresh process, of which in-process s, peak R_O2 N) for ``steps`` steps."""
    code = VECTORISED.format(L2=L2, L3=L3, L4=L4, D=D, steps=steps)
    t = time.perf_counter()
    out = subprocess.run([sys.executable, "-P", "-c", code], capture_output=True, text=True, check=True).stdout.split()
    return time.perf_counter() - t, float(out[1]), float(out[0])


def per_step_loop(steps: int) -> float:
    """The seed's Anexo I structure: one fsolve per step, seeded by the previous step."""
    w2 = 2 * math.pi
    th2 = np.linspace(0, 2 * math.pi, steps)
    x0 = np.radians([5.0, 5.0])
    l3 = 1.0
    m2, m3, m4 = 2.7 * 0.7, 2.7, 2.7
    mp2 = mp3B = 1.835
    mp3A = mp4 = 0.577
    xG2 = (0.35 * m2 + L2 * mp2) / (m2 + mp2)
    xG3 = (0.5 * m3 + L3 * mp3B) / (m3 + mp3B)
    xG4 = (0.5 * m4 + L4 * mp4) / (m4 + mp4)
    I3 = m3 * L3**2 / 12 + mp3B * (L3 - xG3) ** 2 + mp3A * xG3**2
    I4 = m4 * L4**2 / 3 + mp4 * L4**2
    peak = 0.0
    for k in range(steps):
        t2 = th2[k]
        f = lambda x, t2=t2: [
            L2 * math.cos(t2) + L3 * math.cos(x[0]) + L4 * math.cos(x[1]) - D,  # noqa: E731
            L2 * math.sin(t2) + L3 * math.sin(x[0]) + L4 * math.sin(x[1]),
        ]
        x0 = fsolve(f, x0, xtol=1e-12)
        t3, t4 = x0
        A = np.array([[-L3 * math.sin(t3), -L4 * math.sin(t4)], [L3 * math.cos(t3), L4 * math.cos(t4)]])
        w3, w4 = np.linalg.solve(A, -np.array([-L2 * math.sin(t2), L2 * math.cos(t2)]) * w2)
        b = (
            np.array(
                [
                    L3 * math.cos(t3) * w3**2 + L4 * math.cos(t4) * w4**2,
                    L3 * math.sin(t3) * w3**2 + L4 * math.sin(t4) * w4**2,
                ]
            )
            + np.array([L2 * math.cos(t2), L2 * math.sin(t2)]) * w2**2
        )
        a3, a4 = np.linalg.solve(A, b)
        s2, c2, s3, c3, s4, c4 = (math.sin(t2), math.cos(t2), math.sin(t3), math.cos(t3), math.sin(t4), math.cos(t4))
        aA = -(w2**2) * L2 * np.array([c2, s2])
        aB = aA + a3 * L3 * np.array([-s3, c3]) - w3**2 * L3 * np.array([c3, s3])
        aG3 = aA + a3 * xG3 * np.array([-s3, c3]) - w3**2 * xG3 * np.array([c3, s3])
        aG4 = -(w4**2) * (-xG4) * np.array([c4, s4]) + a4 * xG4 * np.array([s4, -c4])
        a4B = np.array([a4 * L4 * s4 + w4**2 * L4 * c4, -a4 * L4 * c4 + w4**2 * L4 * s4])
        AA = np.zeros((9, 9))
        AA[0, 0] = AA[0, 2] = AA[1, 1] = AA[1, 3] = 1
        AA[3, 2], AA[3, 4], AA[4, 3], AA[4, 5] = -1, 1, -1, 1
        AA[6, 4], AA[6, 6], AA[7, 5], AA[7, 7] = -1, 1, -1, 1
        AA[2, 2], AA[2, 3], AA[2, 8] = -L2 * s2, L2 * c2, 1
        AA[5, 2], AA[5, 3] = -l3 / 2 * s3, l3 / 2 * c3
        AA[5, 4], AA[5, 5] = -(L3 - l3 / 2) * s3, (L3 - l3 / 2) * c3
        AA[8, 4], AA[8, 5] = -L4 * s4, L4 * c4
        BB = np.zeros(9)
        BB[0:2] = -m2 * w2**2 * xG2 * np.array([c2, s2]) + mp2 * aA
        BB[3:5] = m3 * aG3 + mp3B * aB + mp3A * aA
        BB[5] = I3 * a3
        BB[6:8] = m4 * aG4 + mp4 * a4B
        BB[8] = I4 * a4
        x = np.linalg.solve(AA, BB)
        peak = max(peak, math.hypot(x[0], x[1]))
    return peak


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--steps", type=int, default=1_000_000)
    parser.add_argument("--loop-steps", type=int, default=5000)
    args = parser.parse_args()
    fast = [vectorised(args.steps) for _ in range(args.repeat)]
    warm = statistics.median(vectorised_in_process(args.steps) for _ in range(args.repeat))
    slow = []
    for _ in range(max(3, args.repeat // 2)):
        t = time.perf_counter()
        pl = per_step_loop(args.loop_steps)
        slow.append(time.perf_counter() - t)
    wall = statistics.median(f[0] for f in fast)
    inner = statistics.median(f[1] for f in fast)
    per_fast, per_inner = wall / args.steps, inner / args.steps
    per_slow = statistics.median(slow) / args.loop_steps
    print(f"configuration 480/840/780/1020 mm, 1 Hz, seed-2013 reactions, medians of {len(fast)} / {len(slow)} runs")
    print(
        f"closed form, {args.steps} steps : {wall:8.3f} s wall in a fresh process ({inner:.3f} s after "
        f"imports) = {per_fast * 1e6:.3f} us/step  (peak R_O2 {fast[0][2]:.4f} N)"
    )
    print(f"per-step fsolve loop, {args.loop_steps} steps: {per_slow * 1e6:8.1f} us/step  (peak R_O2 {pl:.4f} N)")
    print(f"closed form, {args.steps} steps, in this process: {warm:8.3f} s = {warm / args.steps * 1e6:.3f} us/step")
    print(
        f"ratio per step: fresh process, start-up included {per_slow / per_fast:.0f}x; fresh process after imports "
        f"{per_slow / per_inner:.0f}x; in this process {per_slow / (warm / args.steps):.0f}x"
    )


if __name__ == "__main__":
    main()
