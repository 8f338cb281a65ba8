"""Inverse dynamics: joint reactions and motor torque at every crank step.

Two formulations (seed 000, Anexo I; README "Kinematics and inverse dynamics"):

* ``newton-euler`` (default): each bar is one rigid body (its rail plus the point masses
  it carries, :mod:`kinematics.massmodel`); Newton-Euler equations about each body's
  own centre of mass. Physically consistent: the motor power equals the rate of change
  of kinetic (plus potential) energy at every step, see :func:`power_residual`.
* ``seed-2013``: the equations of seed 000 Anexo I as written (four-bar only), with its
  inertia terms and moment arms; reproduces the seed's table 3.3.6.

Sign convention of the reactions, SI (N), ground frame, arrays ``(steps, 2)``:

* ``O2``: force of the ground on the crank at O2;
* ``A``: force of the crank on the coupler at A;
* ``B``: force of the coupler on the output (rocker or slider) at B;
* ``O4``: force of the ground on the rocker at O4 (four-bar);
* ``slider``: force of the ground's guide on the slider (slider-crank; normal to the
  guide, frictionless).

``torque``: the motor torque on the crank (N m), positive counter-clockwise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import MechanismError
from .linkage import FourBar
from .massmodel import MassModel, RigidBar, fourbar_bodies, slidercrank_bodies
from .motion import Motion

FORMULATIONS = ("newton-euler", "seed-2013")
STANDARD_GRAVITY = 9.80665


@dataclass(frozen=True)
class BodyKinematics:
    """Centre-of-mass kinematics of one body, ground frame, arrays ``(steps, 2)``."""

    body: RigidBar
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray


@dataclass(frozen=True)
class Dynamics:
    """Joint reactions (N) and motor torque (N m) at every step; see the module doc."""

    formulation: str
    reactions: dict[str, np.ndarray]
    torque: np.ndarray
    gravity: float
    bodies: tuple[BodyKinematics, ...] = ()

    def magnitude(self, joint: str) -> np.ndarray:
        r = self.reactions[joint]
        return np.hypot(r[:, 0], r[:, 1])

    def peak(self, joint: str) -> tuple[float, int]:
        """(peak magnitude N, step index) of a joint's reaction."""
        mag = self.magnitude(joint)
        k = int(np.argmax(mag))
        return float(mag[k]), k

    def peak_torque(self) -> tuple[float, int]:
        """(peak |torque| N m, step index)."""
        k = int(np.argmax(np.abs(self.torque)))
        return float(abs(self.torque[k])), k


def _cross(r, f):
    return r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0]


def _body_kinematics(motion: Motion, index: int, body: RigidBar, origin: str) -> BodyKinematics:
    """Centre of mass of body ``index`` whose local axis starts at joint ``origin``."""
    th = motion.theta[:, index]
    w = motion.omega[:, index]
    al = motion.alpha[:, index]
    e = np.stack([np.cos(th), np.sin(th)], axis=1)
    r = body.com * e
    p0 = motion.points[origin]
    v0 = motion.velocities[origin]
    a0 = motion.accelerations[origin]
    perp = np.stack([-r[:, 1], r[:, 0]], axis=1)
    pos = p0 + r
    vel = v0 + w[:, None] * perp
    acc = a0 + al[:, None] * perp - (w**2)[:, None] * r
    return BodyKinematics(body, pos, vel, acc, w, al)


def _newton_euler_solve(bodies, joints, driver_body: int, gravity: float):
    """Assemble and solve the Newton-Euler system at every step.

    ``joints``: list of (name, point (n,2), plus_body, minus_body, direction or None);
    the joint force F acts as +F on ``plus_body`` and -F on ``minus_body`` (None =
    ground). ``direction`` (n,2) fixes the force's line (one unknown: its size).
    Returns ({name: (n,2) force}, torque (n,)).
    """
    n = bodies[0].position.shape[0]
    rows = []   # (body index, kind) kind in "x", "y", "m"
    for b, bk in enumerate(bodies):
        rows += [(b, "x"), (b, "y")]
        if bk.body.inertia_com > 0 or b == driver_body:
            rows.append((b, "m"))
    row_of = {key: i for i, key in enumerate(rows)}
    cols = []
    for name, _, _, _, direction in joints:
        cols += [(name, 0), (name, 1)] if direction is None else [(name, None)]
    ncols = len(cols) + 1
    if ncols != len(rows):
        raise MechanismError("mechanism", f"inverse dynamics is not square ({len(rows)} x {ncols})")
    M = np.zeros((n, len(rows), ncols))
    rhs = np.zeros((n, len(rows)))
    col = 0
    for _name, point, plus, minus, direction in joints:
        ncomp = 2 if direction is None else 1
        for sign, b in ((1.0, plus), (-1.0, minus)):
            if b is None:
                continue
            r = point - bodies[b].position
            for j in range(ncomp):
                unit = np.zeros((n, 2))
                if direction is None:
                    unit[:, j] = 1.0
                else:
                    unit = direction
                M[:, row_of[(b, "x")], col + j] += sign * unit[:, 0]
                M[:, row_of[(b, "y")], col + j] += sign * unit[:, 1]
                if (b, "m") in row_of:
                    M[:, row_of[(b, "m")], col + j] += sign * _cross(r, unit)
        col += ncomp
    M[:, row_of[(driver_body, "m")], col] = 1.0
    g = np.array([0.0, -gravity])
    for b, bk in enumerate(bodies):
        m = bk.body.mass
        rhs[:, row_of[(b, "x")]] = m * (bk.acceleration[:, 0] - g[0])
        rhs[:, row_of[(b, "y")]] = m * (bk.acceleration[:, 1] - g[1])
        if (b, "m") in row_of:
            rhs[:, row_of[(b, "m")]] = bk.body.inertia_com * bk.alpha
    x = np.linalg.solve(M, rhs[..., None])[..., 0]
    forces = {}
    col = 0
    for name, _point, _plus, _minus, direction in joints:
        if direction is None:
            forces[name] = x[:, col:col + 2].copy()
            col += 2
        else:
            forces[name] = x[:, col:col + 1] * direction
            col += 1
    return forces, x[:, col].copy()


def newton_euler(motion: Motion, masses: MassModel = MassModel(), gravity: float = 0.0) -> Dynamics:
    """Rigid-body Newton-Euler reactions; ``gravity`` (m/s^2) acts along -y of the
    mechanism's plane (a vertical rig) when non-zero."""
    lk = motion.linkage
    n = motion.steps
    if isinstance(lk, FourBar):
        crank, coupler, rocker = fourbar_bodies(lk, masses)
        bodies = (_body_kinematics(motion, 0, crank, "O2"),
                  _body_kinematics(motion, 1, coupler, "A"),
                  _body_kinematics(motion, 2, rocker, "O4"))
        joints = [("O2", motion.points["O2"], 0, None, None),
                  ("A", motion.points["A"], 1, 0, None),
                  ("B", motion.points["B"], 2, 1, None),
                  ("O4", motion.points["O4"], 2, None, None)]
    else:
        crank, coupler, slider = slidercrank_bodies(lk, masses)
        sk = BodyKinematics(slider, motion.points["B"], motion.velocities["B"],
                            motion.accelerations["B"], np.zeros(n), np.zeros(n))
        bodies = (_body_kinematics(motion, 0, crank, "O2"),
                  _body_kinematics(motion, 1, coupler, "A"), sk)
        normal = np.broadcast_to(np.array([0.0, 1.0]), (n, 2))
        joints = [("O2", motion.points["O2"], 0, None, None),
                  ("A", motion.points["A"], 1, 0, None),
                  ("B", motion.points["B"], 2, 1, None),
                  ("slider", motion.points["B"], 2, None, normal)]
    forces, torque = _newton_euler_solve(bodies, joints, driver_body=0, gravity=gravity)
    return Dynamics("newton-euler", forces, torque, gravity, bodies)


def seed_2013(motion: Motion, masses: MassModel = MassModel()) -> Dynamics:
    """Seed 000 Anexo I, equations as written (four-bar only, no gravity).

    Its unknowns R12, R23, R34, R41 are mapped to this module's convention:
    O2 = R12, A = -R23, B = -R34, O4 = R41.
    """
    lk = motion.linkage
    if not isinstance(lk, FourBar):
        raise MechanismError("dynamics.formulation",
                             "seed-2013 exists only for the four-bar (the seed left the slider-crank undone); "
                             "use newton-euler")
    b2, b3, b4 = lk.crank, lk.coupler, lk.rocker
    l2, l3, l4 = masses.crank_rail_length, masses.coupler_rail_length, masses.rocker_rail_length
    m2, m3, m4 = (masses.rail_mass_per_m * x for x in (l2, l3, l4))
    mp2 = masses.plate + masses.carriage
    mp3A = masses.coupling
    mp3B = masses.plate + masses.carriage
    mp4 = masses.coupling
    xG2 = (l2 / 2 * m2 + b2 * mp2) / (m2 + mp2)
    xG3 = (l3 / 2 * m3 + b3 * mp3B) / (m3 + mp3B)
    xG4 = (l4 / 2 * m4 + b4 * mp4) / (m4 + mp4)
    IG3 = m3 * b3**2 / 12
    IO4 = m4 * b4**2 / 3
    ImA = mp3A * xG3**2
    ImB = mp3B * (b3 - xG3) ** 2
    Im4 = mp4 * b4**2

    th2, th3 = motion.theta[:, 0], motion.theta[:, 1]
    th4 = motion.theta[:, 2] + np.pi            # the seed's theta_4 runs along B -> O4
    w21, w31, w41 = motion.omega[:, 0], motion.omega[:, 1], motion.omega[:, 2]
    al31, al41 = motion.alpha[:, 1], motion.alpha[:, 2]
    s2, c2, s3, c3, s4, c4 = np.sin(th2), np.cos(th2), np.sin(th3), np.cos(th3), np.sin(th4), np.cos(th4)

    a21G2x, a21G2y = -w21**2 * xG2 * c2, -w21**2 * xG2 * s2
    a31G3x = -w21**2 * b2 * c2 - w31**2 * xG3 * c3 + al31 * xG3 * (-s3)
    a31G3y = -w21**2 * b2 * s2 - w31**2 * xG3 * s3 + al31 * xG3 * c3
    a41G4x = -w41**2 * (-xG4 * c4) + al41 * xG4 * s4
    a41G4y = -w41**2 * (-xG4 * s4) + al41 * xG4 * (-c4)
    a21Ax, a21Ay = -w21**2 * b2 * c2, -w21**2 * b2 * s2
    a31Bx = a21Ax - al31 * b3 * s3 - w31**2 * b3 * c3
    a31By = a21Ay + al31 * b3 * c3 - w31**2 * b3 * s3
    a41Bx = al41 * b4 * s4 + w41**2 * b4 * c4
    a41By = -al41 * b4 * c4 + w41**2 * b4 * s4

    n = motion.steps
    AA = np.zeros((n, 9, 9))
    AA[:, 0, 0] = AA[:, 0, 2] = 1
    AA[:, 1, 1] = AA[:, 1, 3] = 1
    AA[:, 3, 2], AA[:, 3, 4] = -1, 1
    AA[:, 4, 3], AA[:, 4, 5] = -1, 1
    AA[:, 6, 4], AA[:, 6, 6] = -1, 1
    AA[:, 7, 5], AA[:, 7, 7] = -1, 1
    AA[:, 2, 2], AA[:, 2, 3], AA[:, 2, 8] = -b2 * s2, b2 * c2, 1
    AA[:, 5, 2], AA[:, 5, 3] = -l3 / 2 * s3, l3 / 2 * c3
    AA[:, 5, 4], AA[:, 5, 5] = -(b3 - l3 / 2) * s3, (b3 - l3 / 2) * c3
    AA[:, 8, 4], AA[:, 8, 5] = -b4 * s4, b4 * c4
    BB = np.zeros((n, 9))
    BB[:, 0] = m2 * a21G2x + mp2 * a21Ax
    BB[:, 1] = m2 * a21G2y + mp2 * a21Ay
    BB[:, 3] = m3 * a31G3x + mp3B * a31Bx + mp3A * a21Ax
    BB[:, 4] = m3 * a31G3y + mp3B * a31By + mp3A * a21Ay
    BB[:, 5] = (IG3 + ImB + ImA) * al31
    BB[:, 6] = m4 * a41G4x + mp4 * a41Bx
    BB[:, 7] = m4 * a41G4y + mp4 * a41By
    BB[:, 8] = (IO4 + Im4) * al41
    x = np.linalg.solve(AA, BB[..., None])[..., 0]
    reactions = {"O2": x[:, 0:2].copy(), "A": -x[:, 2:4], "B": -x[:, 4:6], "O4": x[:, 6:8].copy()}
    return Dynamics("seed-2013", reactions, x[:, 8].copy(), 0.0)


def inverse_dynamics(motion: Motion, formulation: str = "newton-euler",
                     masses: MassModel = MassModel(), gravity: float = 0.0) -> Dynamics:
    """Dispatch on the formulation name."""
    if formulation == "newton-euler":
        return newton_euler(motion, masses, gravity)
    if formulation == "seed-2013":
        if gravity:
            raise MechanismError("check.effects",
                                 "gravity cannot be combined with dynamics.formulation = \"seed-2013\" "
                                 "(the seed's equations have no weight terms); use newton-euler")
        return seed_2013(motion, masses)
    raise MechanismError("dynamics.formulation",
                         f"must be one of {', '.join(FORMULATIONS)}, got {formulation!r}")


def power_residual(motion: Motion, dynamics: Dynamics) -> np.ndarray:
    """Per-step residual of the power balance (W):
    ``M2 omega2 - d/dt(T + V)``, with ``dT/dt = sum(m v_G . a_G + I omega alpha)`` and
    ``dV/dt = sum(m g v_Gy)``. Zero up to rounding for a consistent formulation."""
    if not dynamics.bodies:
        raise ValueError("power_residual needs body kinematics (newton-euler)")
    dT = sum(bk.body.mass * np.einsum("ij,ij->i", bk.velocity, bk.acceleration)
             + bk.body.inertia_com * bk.omega * bk.alpha for bk in dynamics.bodies)
    dV = sum(bk.body.mass * dynamics.gravity * bk.velocity[:, 1] for bk in dynamics.bodies)
    return dynamics.torque * motion.omega[:, 0] - dT - dV


def kinetic_energy(dynamics: Dynamics) -> np.ndarray:
    """Kinetic energy (J) of the moving bodies at every step."""
    return sum(0.5 * bk.body.mass * np.einsum("ij,ij->i", bk.velocity, bk.velocity)
               + 0.5 * bk.body.inertia_com * bk.omega**2 for bk in dynamics.bodies)
