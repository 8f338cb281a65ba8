"""Closed-form kinematics and inverse dynamics vectorised over settings x steps.

One function per concept, shaped for many rig settings at once: bar lengths and speeds are
arrays ``(S, 1)`` (one row per setting), the crank angles ``(T,)``, and every result
``(S, T)`` (scalars per step) or ``(S, T, 2)`` (ground-frame vectors). A single setting
is ``S = 1`` (:mod:`railcheck.kinematics.motion` and :mod:`railcheck.kinematics.dynamics` wrap these).

SI units: m, rad, rad/s, rad/s^2, N, N m. Frames and angle conventions: see
:mod:`railcheck.kinematics.linkage`. The crank turns at constant speed (its angular acceleration
is zero).

Inverse dynamics is solved in closed form, never as a per-step linear system: the
rocker's moment about O4 and the coupler's moment about A involve only the force at B
(a 2 x 2 system solved by Cramer's rule at every step); the force equations then give A,
O4 and O2 in turn, and the crank's moment gives the motor torque.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any

import numpy as np

from .massmodel import MassModel, fourbar_bodies, slidercrank_bodies


def half_angle_tangent(a, b, c):
    """tan(gamma / 2) of the angle gamma opposite side ``c`` in the triangle with sides
    ``a, b, c``, by Kahan's formula ("Miscalculating area and angles of a needle-like
    triangle"): accurate for needle-like triangles, where ``acos`` of the law of cosines
    loses half the digits. NaN where the sides do not close a triangle; inf at gamma = pi."""
    a, b, c = np.asarray(a, float), np.asarray(b, float), np.asarray(c, float)
    big, small = np.maximum(a, b), np.minimum(a, b)  # the bars: small arrays, not broadcast
    mu = np.where(small >= c, c - (big - small), small - (big - c))
    num = ((big - small) + c) * mu
    den = (big + (small + c)) * ((big - c) + small)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.sqrt(num / den)  # NaN where num / den < 0 (no triangle)
    degenerate = den == 0  # den == 0 -> angle pi (0/0 included)
    if np.any(degenerate):
        out = np.where(degenerate & (num >= 0), np.inf, out)
    return out


def triangle_angle(a, b, c):
    """Angle (rad) opposite side ``c`` in the triangle with sides ``a, b, c``; see
    :func:`half_angle_tangent` (NaN where the sides do not close a triangle)."""
    return 2.0 * np.arctan(half_angle_tangent(a, b, c))


@dataclass(frozen=True)
class BatchMotion:
    """Kinematics of many settings: ``theta``, ``omega``, ``alpha`` ``(3, S, T)`` for the
    crank, coupler and output (the slider's rows are zero); ``points``, ``velocities``,
    ``accelerations`` joint name -> ``(S, T, 2)``; ``transmission_angle`` ``(S, T)``."""

    kind: str
    lengths: dict
    theta2: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    points: dict
    velocities: dict
    accelerations: dict
    transmission_angle: np.ndarray


@dataclass(frozen=True)
class BatchBody:
    """A bar as a rigid body per setting (``mass``, ``com``, ``inertia_com`` ``(S, 1)``)
    and its centre-of-mass kinematics (``position`` etc. ``(S, T, 2)``, ``omega``,
    ``alpha`` ``(S, T)``)."""

    mass: np.ndarray
    com: np.ndarray
    inertia_com: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray


@dataclass(frozen=True)
class BatchDynamics:
    """Joint reactions ``(S, T, 2)`` N (sign convention of :mod:`railcheck.kinematics.dynamics`)
    and motor torque ``(S, T)`` N m."""

    reactions: dict
    torque: np.ndarray
    bodies: tuple


def _column(x) -> np.ndarray:
    return np.asarray(x, float).reshape(-1, 1)


def _vec(x, y) -> np.ndarray:
    """Ground-frame vectors ``(..., 2)`` from their broadcast components, written into one new array."""
    out = np.empty(np.broadcast_shapes(np.shape(x), np.shape(y)) + (2,))
    out[..., 0], out[..., 1] = x, y
    return out


def _perp(v: np.ndarray) -> np.ndarray:
    """k x v for ground-frame vectors ``(..., 2)``: (-v_y, v_x), written into one new
    array (half the time of a stack of two temporaries; a multiply of the reversed view
    is 5x slower)."""
    out = np.empty_like(v)
    np.negative(v[..., 1], out=out[..., 0])
    out[..., 1] = v[..., 0]
    return out


def _cross(r: np.ndarray, f: np.ndarray) -> np.ndarray:
    return r[..., 0] * f[..., 1] - r[..., 1] * f[..., 0]


def _angle_between(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """(rad, in [0, pi]) the angle between vectors ``u`` and ``v`` ``(..., 2)``: atan2 of
    |cross| and dot, accurate at every angle (no acos)."""
    return np.arctan2(np.abs(_cross(u, v)), u[..., 0] * v[..., 0] + u[..., 1] * v[..., 1])


def _crank(b2, w2, th2):
    """Crank pin A: position, velocity, acceleration (constant speed)."""
    A = _vec(b2 * np.cos(th2), b2 * np.sin(th2))
    w = w2[..., None]
    return A, w * _perp(A), -(w**2) * A


def _fourbar_block(crank, coupler, rocker, ground, sign, speed, theta2) -> BatchMotion:
    b2, b3, b4, d, sign, w2 = (_column(x) for x in (crank, coupler, rocker, ground, sign, speed))
    th2 = np.asarray(theta2, float)[None, :]
    c2, s2 = np.cos(th2), np.sin(th2)
    Ax, Ay = b2 * c2, b2 * s2
    dx, dy = d - Ax, -Ay  # A -> O4
    r = np.sqrt(dx * dx + dy * dy)  # not np.hypot: 3x slower, and lengths of metres cannot overflow
    t = half_angle_tangent(b3, r, b4)  # tan(phi / 2), phi the angle at A
    cphi, sphi = (1.0 - t * t) / (1.0 + t * t), sign * 2.0 * t / (1.0 + t * t)
    ex, ey = dx / r, dy / r
    c3, s3 = ex * cphi - ey * sphi, ey * cphi + ex * sphi  # coupler direction: A->O4 turned by phi
    Bx, By = Ax + b3 * c3, Ay + b3 * s3
    rBx, rBy = Bx - d, By  # O4 -> B
    c4, s4 = rBx / b4, rBy / b4
    det = b3 * b4 * (s3 * c4 - c3 * s4)

    def cramer(r1, r2):  # b3 x3 n3 - b4 x4 n4 = (r1, r2)
        return (-b4 * c4 * r1 - b4 * s4 * r2) / det, (-b3 * c3 * r1 - b3 * s3 * r2) / det

    w3, w4 = cramer(b2 * w2 * s2, -b2 * w2 * c2)
    w22 = w2 * w2
    al3, al4 = cramer(w22 * Ax + b3 * w3**2 * c3 - b4 * w4**2 * c4, w22 * Ay + b3 * w3**2 * s3 - b4 * w4**2 * s4)
    A, rB = _vec(Ax, Ay), _vec(rBx, rBy)
    zero = np.zeros_like(A)
    shape = Ax.shape
    return BatchMotion(
        "four-bar",
        {"crank": b2, "coupler": b3, "rocker": b4, "ground": d},
        np.asarray(theta2, float),
        np.stack([np.broadcast_to(th2, shape), np.arctan2(s3, c3), np.arctan2(rBy, rBx)]),
        np.stack(np.broadcast_arrays(w2, w3, w4)),
        np.stack([np.zeros(shape), al3, al4]),
        {"O2": zero, "A": A, "B": _vec(Bx, By), "O4": zero + _vec(d, np.zeros_like(d))},
        {"O2": zero, "A": w2[..., None] * _perp(A), "B": w4[..., None] * _perp(rB), "O4": zero},
        {"O2": zero, "A": -w22[..., None] * A, "B": al4[..., None] * _perp(rB) - (w4**2)[..., None] * rB, "O4": zero},
        _angle_between(_vec(Ax - Bx, Ay - By), -rB),
    )


def _slidercrank_block(crank, coupler, offset, sign, speed, theta2) -> BatchMotion:
    b2, b3, e, sign, w2 = (_column(x) for x in (crank, coupler, offset, sign, speed))
    th2 = np.asarray(theta2, float)[None, :]
    w2 = np.broadcast_to(w2, np.broadcast_shapes(w2.shape, th2.shape))
    A, vA, aA = _crank(b2, w2, th2)
    s2, c2 = np.sin(th2), np.cos(th2)
    sin3 = (e - b2 * s2) / b3
    cos3 = sign * np.sqrt((1.0 - sin3) * (1.0 + sin3))
    th3 = np.arctan2(sin3, cos3)
    B = _vec(A[..., 0] + b3 * cos3, np.broadcast_to(e, th3.shape))
    w3 = -b2 * w2 * c2 / (b3 * cos3)
    al3 = (b2 * w2**2 * s2 + b3 * w3**2 * sin3) / (b3 * cos3)
    rAB = B - A
    vB = vA + w3[..., None] * _perp(rAB)
    aB = aA + al3[..., None] * _perp(rAB) - (w3**2)[..., None] * rAB
    vB[..., 1] = 0.0
    aB[..., 1] = 0.0
    zero = np.zeros_like(A)
    zs = np.zeros_like(th3)
    mu = np.pi / 2 - np.abs(np.arcsin(np.clip(sin3, -1.0, 1.0)))
    return BatchMotion(
        "slider-crank",
        {"crank": b2, "coupler": b3, "offset": e},
        np.asarray(theta2, float),
        np.stack([np.broadcast_to(th2, th3.shape), th3, zs]),
        np.stack(np.broadcast_arrays(w2, w3, zs)),
        np.stack([zs, al3, zs]),
        {"O2": zero, "A": A, "B": B},
        {"O2": zero, "A": vA, "B": vB},
        {"O2": zero, "A": aA, "B": aB},
        mu,
    )


def bodies(motion: BatchMotion, masses: MassModel) -> tuple[BatchBody, BatchBody, BatchBody]:
    """The three moving bodies of every setting (the mass model of
    :mod:`railcheck.kinematics.massmodel`, fed the settings' length arrays) with their
    centre-of-mass kinematics."""
    lengths: Any = SimpleNamespace(**motion.lengths)  # the linkage's lengths, as arrays
    if motion.kind == "four-bar":
        crank, coupler, output = fourbar_bodies(lengths, masses)
        third = _body(motion, 2, output, "O4", "B", lengths.rocker)
    else:
        crank, coupler, slider = slidercrank_bodies(lengths, masses)
        zs = np.zeros_like(motion.theta[0])
        third = BatchBody(
            _column(slider.mass),
            _column(0.0),
            _column(0.0),
            motion.points["B"],
            motion.velocities["B"],
            motion.accelerations["B"],
            zs,
            zs,
        )
    return (
        _body(motion, 0, crank, "O2", "A", lengths.crank),
        _body(motion, 1, coupler, "A", "B", lengths.coupler),
        third,
    )


def _body(motion: BatchMotion, index: int, bar, origin: str, tip: str, length) -> BatchBody:
    """Centre of mass of body ``index``, whose local axis runs from joint ``origin`` to
    joint ``tip``, ``length`` (S, 1) m apart (its direction from the joints' positions:
    no cosine and sine of the body's angle)."""
    th, w, al = motion.theta[index], motion.omega[index], motion.alpha[index]
    com = np.broadcast_to(_column(bar.com), (th.shape[0], 1))
    r = (com / length)[..., None] * (motion.points[tip] - motion.points[origin])
    pr = _perp(r)
    return BatchBody(
        np.broadcast_to(_column(bar.mass), com.shape),
        com,
        np.broadcast_to(_column(bar.inertia_com), com.shape),
        motion.points[origin] + r,
        motion.velocities[origin] + w[..., None] * pr,
        motion.accelerations[origin] + al[..., None] * pr - (w**2)[..., None] * r,
        w,
        al,
    )


def _newton_euler_block(motion: BatchMotion, masses: MassModel, gravity: float) -> BatchDynamics:
    crank, coupler, out = bodies(motion, masses)
    g = np.array([0.0, -gravity])
    P = motion.points

    def inertial(b):  # m (a_G - g): the resultant force the body needs
        return b.mass[..., None] * (b.acceleration - g if gravity else b.acceleration)

    f_crank, f_coupler, f_out = inertial(crank), inertial(coupler), inertial(out)
    r2 = P["A"] - P["B"]
    k2 = coupler.inertia_com * coupler.alpha + _cross(coupler.position - P["A"], f_coupler)
    if motion.kind == "four-bar":
        r1 = P["B"] - P["O4"]
        k1 = out.inertia_com * out.alpha + _cross(out.position - P["O4"], f_out)
        det = _cross(r1, r2)
        B = _vec((k1 * r2[..., 0] - r1[..., 0] * k2) / det, (r2[..., 1] * k1 - r1[..., 1] * k2) / det)
        extra = {"O4": f_out - B}
    else:
        Bx = f_out[..., 0]
        By = (k2 + r2[..., 1] * Bx) / r2[..., 0]
        B = _vec(Bx, By)
        extra = {"slider": _vec(np.zeros_like(By), f_out[..., 1] - By)}
    A = f_coupler + B
    O2 = f_crank + A
    torque = crank.inertia_com * crank.alpha - _cross(P["O2"] - crank.position, O2) + _cross(P["A"] - crank.position, A)
    reactions = {"O2": O2, "A": A, "B": B, **extra}
    return BatchDynamics(reactions, torque, (crank, coupler, out))


def _seed_2013_block(motion: BatchMotion, masses: MassModel) -> BatchDynamics:
    L = motion.lengths
    b2, b3, b4 = L["crank"], L["coupler"], L["rocker"]
    l2, l3, l4 = masses.crank_rail_length, masses.coupler_rail_length, masses.rocker_rail_length
    m2, m3, m4 = (masses.rail_mass_per_m * x for x in (l2, l3, l4))
    mp2 = mp3B = masses.plate + masses.carriage
    mp3A = mp4 = masses.coupling
    xG2 = (l2 / 2 * m2 + b2 * mp2) / (m2 + mp2)
    xG3 = (l3 / 2 * m3 + b3 * mp3B) / (m3 + mp3B)
    xG4 = (l4 / 2 * m4 + b4 * mp4) / (m4 + mp4)
    I3 = m3 * b3**2 / 12 + mp3B * (b3 - xG3) ** 2 + mp3A * xG3**2
    I4 = m4 * b4**2 / 3 + mp4 * b4**2
    th2, th3, th4 = motion.theta[0], motion.theta[1], motion.theta[2] + np.pi  # seed's theta_4: B -> O4
    w2, w3, w4 = motion.omega
    al3, al4 = motion.alpha[1], motion.alpha[2]
    s2, c2, s3, c3, s4, c4 = np.sin(th2), np.cos(th2), np.sin(th3), np.cos(th3), np.sin(th4), np.cos(th4)
    aAx, aAy = -(w2**2) * b2 * c2, -(w2**2) * b2 * s2
    BB0, BB1 = m2 * -(w2**2) * xG2 * c2 + mp2 * aAx, m2 * -(w2**2) * xG2 * s2 + mp2 * aAy
    BB3 = m3 * (aAx - w3**2 * xG3 * c3 - al3 * xG3 * s3) + mp3B * (aAx - al3 * b3 * s3 - w3**2 * b3 * c3) + mp3A * aAx
    BB4 = m3 * (aAy - w3**2 * xG3 * s3 + al3 * xG3 * c3) + mp3B * (aAy + al3 * b3 * c3 - w3**2 * b3 * s3) + mp3A * aAy
    BB5 = I3 * al3
    BB6 = m4 * (w4**2 * xG4 * c4 + al4 * xG4 * s4) + mp4 * (al4 * b4 * s4 + w4**2 * b4 * c4)
    BB7 = m4 * (w4**2 * xG4 * s4 - al4 * xG4 * c4) + mp4 * (-al4 * b4 * c4 + w4**2 * b4 * s4)
    BB8 = I4 * al4
    # rows 5 and 8 in x4, x5 (x2 = x4 - BB3, x3 = x5 - BB4): -s3 x4 + c3 x5 = k5, -s4 x4 + c4 x5 = k8
    k5 = (BB5 - l3 / 2 * (s3 * BB3 - c3 * BB4)) / b3
    k8 = BB8 / b4
    det = -s3 * c4 + c3 * s4
    x4 = (k5 * c4 - c3 * k8) / det
    x5 = (-s3 * k8 + s4 * k5) / det
    x2, x3 = x4 - BB3, x5 - BB4
    R12 = _vec(BB0 - x2, BB1 - x3)
    torque = b2 * s2 * x2 - b2 * c2 * x3
    reactions = {"O2": R12, "A": -_vec(x2, x3), "B": -_vec(x4, x5), "O4": _vec(BB6 + x4, BB7 + x5)}
    return BatchDynamics(reactions, torque, ())


#: elements (settings x steps) evaluated at once: temporaries (128 kB, vectors 256 kB) stay
#: in the core's own 1 MB cache and are reused instead of being mapped, faulted in and
#: zeroed afresh for every operation. The whole rig's kinematics-only sweep, serially:
#: 2.55 s at 1 << 14, 2.85 s at 1 << 13, 3.98 s at 1 << 12 (numpy's per-call overhead);
#: earlier, two processes sharing the memory bus: 6.1 s at 1 << 17
BLOCK_ELEMENTS = 1 << 14


def _step_blocks(settings: int, steps: int) -> list[slice]:
    size = max(1, BLOCK_ELEMENTS // max(settings, 1))
    return [slice(i, min(i + size, steps)) for i in range(0, steps, size)]


def _join(parts: list, axis: int) -> np.ndarray:
    return parts[0] if len(parts) == 1 else np.concatenate(parts, axis=axis)


def _join_dict(parts: list[dict]) -> dict:
    return {k: _join([p[k] for p in parts], 1) for k in parts[0]}


def _join_motion(parts: list[BatchMotion], theta2: np.ndarray) -> BatchMotion:
    p0 = parts[0]
    theta, omega, alpha = (_join([getattr(p, f) for p in parts], 2) for f in ("theta", "omega", "alpha"))
    return BatchMotion(
        p0.kind,
        p0.lengths,
        theta2,
        theta,
        omega,
        alpha,
        _join_dict([p.points for p in parts]),
        _join_dict([p.velocities for p in parts]),
        _join_dict([p.accelerations for p in parts]),
        _join([p.transmission_angle for p in parts], 1),
    )


def _slice_motion(m: BatchMotion, sl: slice) -> BatchMotion:
    return BatchMotion(
        m.kind,
        m.lengths,
        m.theta2[sl],
        m.theta[:, :, sl],
        m.omega[:, :, sl],
        m.alpha[:, :, sl],
        {k: v[:, sl] for k, v in m.points.items()},
        {k: v[:, sl] for k, v in m.velocities.items()},
        {k: v[:, sl] for k, v in m.accelerations.items()},
        m.transmission_angle[:, sl],
    )


def _join_dynamics(parts: list[BatchDynamics]) -> BatchDynamics:
    bodies = (
        tuple(
            BatchBody(
                b[0].mass,
                b[0].com,
                b[0].inertia_com,
                *(_join([getattr(x, f) for x in b], 1) for f in ("position", "velocity", "acceleration", "omega", "alpha")),
            )
            for b in zip(*(p.bodies for p in parts))
        )
        if parts[0].bodies
        else ()
    )
    return BatchDynamics(_join_dict([p.reactions for p in parts]), _join([p.torque for p in parts], 1), bodies)


def fourbar_motion(crank, coupler, rocker, ground, sign, speed, theta2) -> BatchMotion:
    """Four-bar kinematics for settings ``(S,)`` (lengths m, ``sign`` +1 open / -1
    crossed, ``speed`` rad/s) at the crank angles ``theta2`` ``(T,)``. The settings must
    revolve (see :func:`railcheck.kinematics.motion.fourbar_toggle_margins`); elsewhere the results
    are NaN. Evaluated in blocks of steps (:data:`BLOCK_ELEMENTS`)."""
    theta2 = np.asarray(theta2, float)
    return _join_motion(
        [
            _fourbar_block(crank, coupler, rocker, ground, sign, speed, theta2[sl])
            for sl in _step_blocks(np.size(crank), theta2.size)
        ],
        theta2,
    )


def slidercrank_motion(crank, coupler, offset, sign, speed, theta2) -> BatchMotion:
    """Slider-crank kinematics for settings ``(S,)``; B slides on y = ``offset`` (m)."""
    theta2 = np.asarray(theta2, float)
    return _join_motion(
        [
            _slidercrank_block(crank, coupler, offset, sign, speed, theta2[sl])
            for sl in _step_blocks(np.size(crank), theta2.size)
        ],
        theta2,
    )


def newton_euler(motion: BatchMotion, masses: MassModel = MassModel(), gravity: float = 0.0) -> BatchDynamics:
    """Rigid-body Newton-Euler reactions and motor torque in closed form (module doc);
    ``gravity`` (m/s^2) acts along -y when non-zero."""
    return _join_dynamics(
        [
            _newton_euler_block(_slice_motion(motion, sl), masses, gravity)
            for sl in _step_blocks(motion.theta.shape[1], motion.theta2.size)
        ]
    )


def seed_2013(motion: BatchMotion, masses: MassModel = MassModel()) -> BatchDynamics:
    """Seed 000 Anexo I, equations as written (four-bar only, no gravity), solved in
    closed form: its 9 x 9 system per step reduces to a 2 x 2 one in R34 (rows 5 and 8),
    then back-substitution. Its unknowns map as O2 = R12, A = -R23, B = -R34, O4 = R41."""
    return _join_dynamics(
        [
            _seed_2013_block(_slice_motion(motion, sl), masses)
            for sl in _step_blocks(motion.theta.shape[1], motion.theta2.size)
        ]
    )
