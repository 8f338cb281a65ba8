"""Closed-form positions, velocities and accelerations over one crank revolution.

Everything is vectorised over the crank-angle steps (arrays shaped ``(steps,)`` or
``(steps, 2)``). SI units: m, rad, rad/s, rad/s^2, m/s, m/s^2. Frames and angle
conventions: see :mod:`kinematics.linkage`.

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

from .errors import MechanismError, SingularConfigurationError
from .linkage import FourBar, SliderCrank

#: a transmission angle closer than this to 0 or pi (rad) is a toggle: refused.
SINGULAR_TOLERANCE_RAD = 1e-7
#: a transmission angle closer than this to 0 or pi (rad) earns a warning.
NEAR_TOGGLE_WARNING_RAD = math.radians(5.0)


def triangle_angle(a, b, c):
    """Angle (rad) opposite side ``c`` in the triangle with sides ``a, b, c``.

    Kahan's formula ("Miscalculating area and angles of a needle-like triangle"),
    accurate for needle-like triangles where ``acos`` of the law of cosines loses half
    the digits. Returns NaN where the sides do not close a triangle.
    """
    a, b, c = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float), np.asarray(c, float))
    big = np.maximum(a, b)
    small = np.minimum(a, b)
    mu = np.where(small >= c, c - (big - small), small - (big - c))
    num = ((big - small) + c) * mu
    den = (big + (small + c)) * ((big - c) + small)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = num / den
        out = 2.0 * np.arctan(np.sqrt(ratio))
    # exact degenerate cases: num == 0 -> angle 0; den == 0 -> angle pi
    out = np.where((den == 0) & (num >= 0), math.pi, out)
    out = np.where(ratio < 0, np.nan, out)
    return out


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


def _unit(angle):
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def _normal(angle):
    return np.stack([-np.sin(angle), np.cos(angle)], axis=-1)


def _rigid_velocity(v_ref, r, omega):
    """Velocity of a point at offset ``r`` (n,2) on a body turning at ``omega`` (n,)."""
    return v_ref + omega[:, None] * np.stack([-r[:, 1], r[:, 0]], axis=-1)


def _rigid_acceleration(a_ref, r, omega, alpha):
    """Acceleration of a point at offset ``r`` (n,2): a_ref + alpha k x r - omega^2 r."""
    return (a_ref + alpha[:, None] * np.stack([-r[:, 1], r[:, 0]], axis=-1)
            - (omega**2)[:, None] * r)


def fourbar_toggle_margins(linkage: FourBar) -> tuple[float, float]:
    """(mu_min, mu_max) in rad: the transmission-angle extremes over a revolution.

    They occur where the diagonal A-O4 is shortest (crank angle 0) and longest (pi);
    NaN where the coupler and rocker cannot reach (the crank does not revolve).
    """
    b2, b3, b4, d = linkage.crank, linkage.coupler, linkage.rocker, linkage.ground
    mu_min = float(triangle_angle(b3, b4, abs(d - b2)))
    mu_max = float(triangle_angle(b3, b4, d + b2))
    return mu_min, mu_max


def _fourbar_revolvability(linkage: FourBar) -> None:
    """Raise unless the crank can make a full revolution away from any toggle."""
    b2, b3, b4, d = linkage.crank, linkage.coupler, linkage.rocker, linkage.ground
    lengths = {"crank": b2, "coupler": b3, "rocker": b4, "ground": d}
    longest = max(lengths, key=lengths.get)
    if 2 * lengths[longest] >= sum(lengths.values()):
        raise MechanismError(
            f"mechanism.{longest}",
            f"the four-bar cannot be assembled: {longest} = {lengths[longest]*1e3:.6g} mm is not "
            f"shorter than the sum of the other three bars ({(sum(lengths.values()) - lengths[longest])*1e3:.6g} mm)")
    r_min, r_max = abs(d - b2), d + b2
    if r_max > b3 + b4:
        raise MechanismError(
            "mechanism",
            f"the crank cannot make a full revolution: at crank angle 180 deg the distance A-O4 = "
            f"{r_max*1e3:.6g} mm exceeds coupler + rocker = {(b3 + b4)*1e3:.6g} mm")
    if r_min < abs(b3 - b4):
        raise MechanismError(
            "mechanism",
            f"the crank cannot make a full revolution: at crank angle 0 deg the distance A-O4 = "
            f"{r_min*1e3:.6g} mm is below |coupler - rocker| = {abs(b3 - b4)*1e3:.6g} mm")
    mu_min, mu_max = fourbar_toggle_margins(linkage)
    ordered = sorted(lengths.values())
    kind = ("Grashof change point (s + l = p + q): all four bars become collinear"
            if abs(ordered[0] + ordered[3] - ordered[1] - ordered[2]) <= 1e-12 * ordered[3]
            else "singular configuration (toggle)")
    if mu_min < SINGULAR_TOLERANCE_RAD:
        raise SingularConfigurationError(
            "mechanism",
            f"{kind} at crank angle 0 deg: coupler and rocker "
            f"are aligned (transmission angle {math.degrees(mu_min):.3g} deg); velocities and reactions "
            "are undefined there", 0.0)
    if math.pi - mu_max < SINGULAR_TOLERANCE_RAD:
        raise SingularConfigurationError(
            "mechanism",
            f"{kind} at crank angle 180 deg: coupler and rocker are folded "
            f"(transmission angle {math.degrees(mu_max):.6g} deg); velocities and reactions are "
            "undefined there", math.pi)


def _toggle_warnings(mu: np.ndarray, theta2: np.ndarray) -> tuple[str, ...]:
    distance = np.minimum(mu, math.pi - mu)
    k = int(np.argmin(distance))
    if distance[k] < NEAR_TOGGLE_WARNING_RAD:
        return (f"near a toggle at crank angle {math.degrees(theta2[k]):.4g} deg: transmission angle "
                f"{math.degrees(mu[k]):.6g} deg; reactions grow like 1/sin(mu) there",)
    return ()


def solve_fourbar(linkage: FourBar, speed: float, steps: int = 5000) -> Motion:
    """Four-bar motion over one crank revolution at ``speed`` rad/s (constant)."""
    _fourbar_revolvability(linkage)
    b2, b3, b4, d = linkage.crank, linkage.coupler, linkage.rocker, linkage.ground
    th2 = crank_angles(steps)
    n = th2.size
    w2 = np.full(n, float(speed))
    a2 = np.zeros(n)
    e2 = _unit(th2)
    A = b2 * e2
    diag = np.array([d, 0.0]) - A                       # A -> O4
    r = np.hypot(diag[:, 0], diag[:, 1])
    psi = np.arctan2(diag[:, 1], diag[:, 0])
    phi_a = triangle_angle(b3, r, b4)                    # angle at A, opposite the rocker
    th3 = psi + linkage.sign * phi_a
    B = A + b3 * _unit(th3)
    O4 = np.array([d, 0.0])
    th4 = np.arctan2(B[:, 1] - O4[1], B[:, 0] - O4[0])
    mu = triangle_angle(b3, b4, r)                       # angle at B, opposite A-O4

    # velocities: b3 w3 n3 - b4 w4 n4 = -b2 w2 n2  (2x2, Cramer, det = b3 b4 sin(th3 - th4))
    s3, c3, s4, c4 = np.sin(th3), np.cos(th3), np.sin(th4), np.cos(th4)
    det = b3 * b4 * (s3 * c4 - c3 * s4)

    def solve(r1, r2):
        x3 = (-b4 * c4 * r1 - b4 * s4 * r2) / det
        x4 = (-b3 * c3 * r1 - b3 * s3 * r2) / det
        return x3, x4

    rhs = -b2 * w2[:, None] * _normal(th2)
    w3, w4 = solve(rhs[:, 0], rhs[:, 1])
    # accelerations: b3 a3 n3 - b4 a4 n4 = -b2 a2 n2 + b2 w2^2 e2 + b3 w3^2 e3 - b4 w4^2 e4
    rhs = (-b2 * a2[:, None] * _normal(th2) + b2 * (w2**2)[:, None] * e2
           + b3 * (w3**2)[:, None] * _unit(th3) - b4 * (w4**2)[:, None] * _unit(th4))
    al3, al4 = solve(rhs[:, 0], rhs[:, 1])

    zeros2 = np.zeros((n, 2))
    vA = _rigid_velocity(zeros2, A, w2)
    aA = _rigid_acceleration(zeros2, A, w2, a2)
    rB = B - O4
    vB = _rigid_velocity(zeros2, rB, w4)
    aB = _rigid_acceleration(zeros2, rB, w4, al4)
    return Motion(
        linkage=linkage, speed=float(speed), theta2=th2,
        theta=np.stack([th2, th3, th4], axis=1),
        omega=np.stack([w2, w3, w4], axis=1),
        alpha=np.stack([a2, al3, al4], axis=1),
        points={"O2": np.zeros((n, 2)), "A": A, "B": B, "O4": np.broadcast_to(O4, (n, 2)).copy()},
        velocities={"O2": zeros2, "A": vA, "B": vB, "O4": zeros2},
        accelerations={"O2": zeros2, "A": aA, "B": aB, "O4": zeros2},
        transmission_angle=mu,
        warnings=_toggle_warnings(mu, th2),
    )


def _slidercrank_revolvability(linkage: SliderCrank) -> None:
    b2, b3, e = linkage.crank, linkage.coupler, linkage.offset
    reach = b2 + abs(e)
    if reach > b3:
        raise MechanismError(
            "mechanism.coupler",
            f"the slider-crank cannot make a full revolution: crank + |offset| = {reach*1e3:.6g} mm "
            f"exceeds the coupler {b3*1e3:.6g} mm (seed 3.3.1 asks crank < coupler)")
    if b3 - reach < SINGULAR_TOLERANCE_RAD * b3:
        angle = 90.0 if e <= 0 else 270.0
        raise SingularConfigurationError(
            "mechanism.coupler",
            f"singular configuration at crank angle {angle:g} deg: the coupler is perpendicular to the "
            "slider's line (crank + |offset| = coupler); velocities and reactions are undefined there",
            math.radians(angle))


def solve_slidercrank(linkage: SliderCrank, speed: float, steps: int = 5000) -> Motion:
    """Slider-crank motion over one crank revolution at ``speed`` rad/s (constant)."""
    _slidercrank_revolvability(linkage)
    b2, b3, e = linkage.crank, linkage.coupler, linkage.offset
    th2 = crank_angles(steps)
    n = th2.size
    w2 = np.full(n, float(speed))
    a2 = np.zeros(n)
    s2, c2 = np.sin(th2), np.cos(th2)
    A = b2 * _unit(th2)
    sin3 = (e - b2 * s2) / b3
    cos3 = linkage.sign * np.sqrt((1.0 - sin3) * (1.0 + sin3))
    th3 = np.arctan2(sin3, cos3)
    B = np.stack([A[:, 0] + b3 * cos3, np.full(n, e)], axis=1)
    # y_B constant: b2 w2 c2 + b3 w3 c3 = 0
    w3 = -b2 * w2 * c2 / (b3 * cos3)
    al3 = (-b2 * (a2 * c2 - w2**2 * s2) + b3 * w3**2 * sin3) / (b3 * cos3)
    vA = _rigid_velocity(np.zeros((n, 2)), A, w2)
    aA = _rigid_acceleration(np.zeros((n, 2)), A, w2, a2)
    rAB = B - A
    vB = _rigid_velocity(vA, rAB, w3)
    aB = _rigid_acceleration(aA, rAB, w3, al3)
    vB[:, 1] = 0.0
    aB[:, 1] = 0.0
    # transmission angle: between the coupler and the normal to the slider's line
    mu = math.pi / 2 - np.abs(np.arcsin(np.clip(sin3, -1.0, 1.0)))
    zeros = np.zeros(n)
    return Motion(
        linkage=linkage, speed=float(speed), theta2=th2,
        theta=np.stack([th2, th3, zeros], axis=1),
        omega=np.stack([w2, w3, zeros], axis=1),
        alpha=np.stack([a2, al3, zeros], axis=1),
        points={"O2": np.zeros((n, 2)), "A": A, "B": B},
        velocities={"O2": np.zeros((n, 2)), "A": vA, "B": vB},
        accelerations={"O2": np.zeros((n, 2)), "A": aA, "B": aB},
        transmission_angle=mu,
        warnings=_toggle_warnings(mu, th2),
    )


def solve_motion(linkage: FourBar | SliderCrank, speed: float, steps: int = 5000) -> Motion:
    """Dispatch on the linkage kind."""
    if isinstance(linkage, FourBar):
        return solve_fourbar(linkage, speed, steps)
    return solve_slidercrank(linkage, speed, steps)
