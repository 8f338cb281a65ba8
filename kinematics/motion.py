"""Closed-form positions, velocities and accelerations over one crank revolution.

Everything is vectorised over the crank-angle steps (arrays shaped ``(steps,)`` or
``(steps, 2)``). SI units: m, rad, rad/s, rad/s^2, m/s, m/s^2. Frames and angle
conventions: see :mod:`railcheck.kinematics.linkage`.

The crank turns at constant speed ``omega2`` (rad/s) through one revolution,
``theta2 = linspace(0, 2 pi, steps)`` (both ends included, as the seed's MATLAB does).
A speed of zero is allowed: the same positions, with zero velocities and accelerations
(statics).

Positions near a toggle are computed with Kahan's stable triangle angle, so the motion
stays accurate (and the closure residual at rounding level) to within about 1e-7 rad
of the toggle; closer than :data:`SINGULAR_TOLERANCE_RAD` the configuration is treated
as singular and refused.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .batch import BatchMotion, fourbar_motion, slidercrank_motion, triangle_angle
from .errors import MechanismError, SingularConfigurationError
from .linkage import FourBar, SliderCrank

#: a transmission angle closer than this to 0 or pi (rad) is a toggle: refused.
SINGULAR_TOLERANCE_RAD = 1e-7
#: a transmission angle closer than this to 0 or pi (rad) earns a warning.
NEAR_TOGGLE_WARNING_RAD = math.radians(5.0)


@dataclass(frozen=True)
class Motion:
    """Kinematics of the three moving bodies over the cycle.

    Bodies, in order: crank (0), coupler (1), output (2: rocker of a four-bar, slider
    of a slider-crank, which does not rotate). ``theta``, ``omega``, ``alpha`` are
    shaped ``(steps, 3)``. ``points``, ``velocities`` and ``accelerations`` map the
    joint names ("O2", "A", "B", and "O4" for a four-bar) to ``(steps, 2)`` arrays
    in the ground frame. ``transmission_angle`` (rad, ``(steps,)``) is the angle at B
    between the coupler and the output (rocker, or the normal of the slider's line).
    """

    linkage: FourBar | SliderCrank
    speed: float
    theta2: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    points: dict[str, np.ndarray]
    velocities: dict[str, np.ndarray]
    accelerations: dict[str, np.ndarray]
    transmission_angle: np.ndarray
    warnings: tuple[str, ...] = field(default=())

    @property
    def steps(self) -> int:
        return self.theta2.shape[0]

    @property
    def time(self) -> np.ndarray:
        """Time (s) of each step; NaN-free only for a non-zero speed."""
        return self.theta2 / self.speed if self.speed else np.zeros_like(self.theta2)


def crank_angles(steps: int) -> np.ndarray:
    """The crank-angle grid of one revolution: ``steps`` angles in [0, 2 pi] (rad)."""
    if int(steps) != steps or steps < 3:
        raise MechanismError("mechanism.steps", f"must be a whole number >= 3, got {steps!r}")
    return np.linspace(0.0, 2.0 * math.pi, int(steps))


def fourbar_toggle_margins(linkage: FourBar) -> tuple[float, float]:
    """(mu_min, mu_max) in rad: the transmission-angle extremes over a revolution.

    They occur where the diagonal A-O4 is shortest (crank angle 0) and longest (pi);
    NaN where the coupler and rocker cannot reach (the crank does not revolve).
    """
    b2, b3, b4, d = linkage.crank, linkage.coupler, linkage.rocker, linkage.ground
    mu_min = float(triangle_angle(b3, b4, abs(d - b2)))
    mu_max = float(triangle_angle(b3, b4, d + b2))
    return mu_min, mu_max


def distinct_mm(a: float, b: float) -> tuple[str, str]:
    """Two lengths (m) in mm with the fewest significant digits (at least 6) that tell them
    apart, so a message never says that 200 mm is below 200 mm."""
    for digits in range(6, 18):
        x, y = f"{a * 1e3:.{digits}g}", f"{b * 1e3:.{digits}g}"
        if x != y:
            return x, y
    return x, y


def _fourbar_revolvability(linkage: FourBar) -> None:
    """Raise unless the crank can make a full revolution away from any toggle."""
    b2, b3, b4, d = linkage.crank, linkage.coupler, linkage.rocker, linkage.ground
    lengths = {"crank": b2, "coupler": b3, "rocker": b4, "ground": d}
    longest = max(lengths, key=lengths.__getitem__)
    if 2 * lengths[longest] >= sum(lengths.values()):
        raise MechanismError(
            f"mechanism.{longest}",
            f"the four-bar cannot be assembled: {longest} = {lengths[longest] * 1e3:.6g} mm is not "
            f"shorter than the sum of the other three bars ({(sum(lengths.values()) - lengths[longest]) * 1e3:.6g} mm)",
        )
    r_min, r_max = abs(d - b2), d + b2
    tol = 1e-12 * (d + b2 + b3 + b4)  # equal to rounding: a change point or a toggle, reported below
    if r_max > b3 + b4 + tol:
        raise MechanismError(
            "mechanism",
            "the crank cannot make a full revolution: at crank angle 180 deg the distance A-O4 = "
            "{} mm exceeds coupler + rocker = {} mm".format(*distinct_mm(r_max, b3 + b4)),
        )
    if r_min < abs(b3 - b4) - tol:
        raise MechanismError(
            "mechanism",
            "the crank cannot make a full revolution: at crank angle 0 deg the distance A-O4 = "
            "{} mm is below |coupler - rocker| = {} mm".format(*distinct_mm(r_min, abs(b3 - b4))),
        )
    mu_min, mu_max = fourbar_toggle_margins(linkage)
    # collinear to rounding (a change point): the margin's arccos falls outside [-1, 1]
    mu_min = 0.0 if math.isnan(mu_min) else mu_min
    mu_max = math.pi if math.isnan(mu_max) else mu_max
    ordered = sorted(lengths.values())
    kind = (
        "Grashof change point (s + l = p + q): all four bars become collinear"
        if abs(ordered[0] + ordered[3] - ordered[1] - ordered[2]) <= 1e-12 * ordered[3]
        else "singular configuration (toggle)"
    )
    if mu_min < SINGULAR_TOLERANCE_RAD:
        raise SingularConfigurationError(
            "mechanism",
            f"{kind} at crank angle 0 deg: coupler and rocker "
            f"are aligned (transmission angle {math.degrees(mu_min):.3g} deg); velocities and reactions "
            "are undefined there",
            0.0,
        )
    if math.pi - mu_max < SINGULAR_TOLERANCE_RAD:
        raise SingularConfigurationError(
            "mechanism",
            f"{kind} at crank angle 180 deg: coupler and rocker are folded "
            f"(transmission angle {math.degrees(mu_max):.6g} deg); velocities and reactions are "
            "undefined there",
            math.pi,
        )


def _toggle_warnings(mu: np.ndarray, theta2: np.ndarray) -> tuple[str, ...]:
    distance = np.minimum(mu, math.pi - mu)
    k = int(np.argmin(distance))
    if distance[k] < NEAR_TOGGLE_WARNING_RAD:
        return (
            f"near a toggle at crank angle {math.degrees(theta2[k]) % 360.0:.4g} deg: transmission angle "
            f"{math.degrees(mu[k]):.6g} deg; reactions grow like 1/sin(mu) there",
        )
    return ()


def solve_fourbar(linkage: FourBar, speed: float, steps: int = 5000) -> Motion:
    """Four-bar motion over one crank revolution at ``speed`` rad/s (constant)."""
    _fourbar_revolvability(linkage)
    b = fourbar_motion(
        linkage.crank, linkage.coupler, linkage.rocker, linkage.ground, linkage.sign, float(speed), crank_angles(steps)
    )
    return _single(linkage, speed, b)


def _single(linkage, speed: float, b: BatchMotion) -> Motion:
    """The :class:`Motion` of the batch's only setting."""
    mu = b.transmission_angle[0]
    return Motion(
        linkage=linkage,
        speed=float(speed),
        theta2=b.theta2,
        theta=b.theta[:, 0].T,
        omega=b.omega[:, 0].T,
        alpha=b.alpha[:, 0].T,
        points={k: v[0] for k, v in b.points.items()},
        velocities={k: v[0] for k, v in b.velocities.items()},
        accelerations={k: v[0] for k, v in b.accelerations.items()},
        transmission_angle=mu,
        warnings=_toggle_warnings(mu, b.theta2),
    )


def _slidercrank_revolvability(linkage: SliderCrank) -> None:
    b2, b3, e = linkage.crank, linkage.coupler, linkage.offset
    reach = b2 + abs(e)
    if reach > b3:
        raise MechanismError(
            "mechanism.coupler",
            f"the slider-crank cannot make a full revolution: crank + |offset| = {reach * 1e3:.6g} mm "
            f"exceeds the coupler {b3 * 1e3:.6g} mm (seed 3.3.1 asks crank < coupler)",
        )
    if b3 - reach < SINGULAR_TOLERANCE_RAD * b3:
        angle = 90.0 if e <= 0 else 270.0
        raise SingularConfigurationError(
            "mechanism.coupler",
            f"singular configuration at crank angle {angle:g} deg: the coupler is perpendicular to the "
            "slider's line (crank + |offset| = coupler); velocities and reactions are undefined there",
            math.radians(angle),
        )


def solve_slidercrank(linkage: SliderCrank, speed: float, steps: int = 5000) -> Motion:
    """Slider-crank motion over one crank revolution at ``speed`` rad/s (constant)."""
    _slidercrank_revolvability(linkage)
    b = slidercrank_motion(linkage.crank, linkage.coupler, linkage.offset, linkage.sign, float(speed), crank_angles(steps))
    return _single(linkage, speed, b)


def solve_motion(linkage: FourBar | SliderCrank, speed: float, steps: int = 5000) -> Motion:
    """Dispatch on the linkage kind."""
    if isinstance(linkage, FourBar):
        return solve_fourbar(linkage, speed, steps)
    return solve_slidercrank(linkage, speed, steps)
