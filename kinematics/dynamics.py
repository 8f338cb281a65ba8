"""Inverse dynamics: joint reactions and motor torque at every crank step.

Two formulations (seed 000, Anexo I; docs/model.md "Kinematics and inverse dynamics"):

* ``newton-euler`` (default): each bar is one rigid body (its rail plus the point masses
  it carries, :mod:`railcheck.kinematics.massmodel`); Newton-Euler equations about each body's
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

from . import batch
from .batch import BatchMotion
from .errors import MechanismError
from .linkage import FourBar
from .massmodel import MassModel, RigidBar
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


def _as_batch(motion: Motion) -> BatchMotion:
    """The single setting as a batch of one (views, no copies)."""
    lk = motion.linkage
    lengths = {k: np.array([[v]]) for k, v in lk.lengths.items()}
    return BatchMotion(
        lk.kind,
        lengths,
        motion.theta2,
        motion.theta.T[:, None, :],
        motion.omega.T[:, None, :],
        motion.alpha.T[:, None, :],
        {k: v[None] for k, v in motion.points.items()},
        {k: v[None] for k, v in motion.velocities.items()},
        {k: v[None] for k, v in motion.accelerations.items()},
        motion.transmission_angle[None],
    )


def _bodies(batch_bodies) -> tuple[BodyKinematics, ...]:
    return tuple(
        BodyKinematics(
            RigidBar(float(b.mass[0, 0]), float(b.com[0, 0]), float(b.inertia_com[0, 0])),
            b.position[0],
            b.velocity[0],
            b.acceleration[0],
            b.omega[0],
            b.alpha[0],
        )
        for b in batch_bodies
    )


def newton_euler(motion: Motion, masses: MassModel = MassModel(), gravity: float = 0.0) -> Dynamics:
    """Rigid-body Newton-Euler reactions (closed form, :func:`railcheck.kinematics.batch.newton_euler`);
    ``gravity`` (m/s^2) acts along -y of the mechanism's plane (a vertical rig) when non-zero."""
    out = batch.newton_euler(_as_batch(motion), masses, gravity)
    return Dynamics("newton-euler", {k: v[0] for k, v in out.reactions.items()}, out.torque[0], gravity, _bodies(out.bodies))


def seed_2013(motion: Motion, masses: MassModel = MassModel()) -> Dynamics:
    """Seed 000 Anexo I, equations as written (four-bar only, no gravity); see
    :func:`railcheck.kinematics.batch.seed_2013`."""
    if not isinstance(motion.linkage, FourBar):
        raise MechanismError(
            "dynamics.formulation",
            "seed-2013 exists only for the four-bar (the seed left the slider-crank undone); use newton-euler",
        )
    out = batch.seed_2013(_as_batch(motion), masses)
    return Dynamics("seed-2013", {k: v[0] for k, v in out.reactions.items()}, out.torque[0], 0.0)


def inverse_dynamics(
    motion: Motion, formulation: str = "newton-euler", masses: MassModel = MassModel(), gravity: float = 0.0
) -> Dynamics:
    """Dispatch on the formulation name."""
    if formulation == "newton-euler":
        return newton_euler(motion, masses, gravity)
    if formulation == "seed-2013":
        if gravity:
            raise MechanismError(
                "check.effects",
                'gravity cannot be combined with dynamics.formulation = "seed-2013" '
                "(the seed's equations have no weight terms); use newton-euler",
            )
        return seed_2013(motion, masses)
    raise MechanismError("dynamics.formulation", f"must be one of {', '.join(FORMULATIONS)}, got {formulation!r}")


def power_residual(motion: Motion, dynamics: Dynamics) -> np.ndarray:
    """Per-step residual of the power balance (W):
    ``M2 omega2 - d/dt(T + V)``, with ``dT/dt = sum(m v_G . a_G + I omega alpha)`` and
    ``dV/dt = sum(m g v_Gy)``. Zero up to rounding for a consistent formulation."""
    if not dynamics.bodies:
        raise ValueError("power_residual needs body kinematics (newton-euler)")
    dT = sum(
        bk.body.mass * np.einsum("ij,ij->i", bk.velocity, bk.acceleration) + bk.body.inertia_com * bk.omega * bk.alpha
        for bk in dynamics.bodies
    )
    dV = sum(bk.body.mass * dynamics.gravity * bk.velocity[:, 1] for bk in dynamics.bodies)
    return dynamics.torque * motion.omega[:, 0] - dT - dV


def kinetic_energy(dynamics: Dynamics) -> np.ndarray:
    """Kinetic energy (J) of the moving bodies at every step."""
    return sum(
        0.5 * bk.body.mass * np.einsum("ij,ij->i", bk.velocity, bk.velocity) + 0.5 * bk.body.inertia_com * bk.omega**2
        for bk in dynamics.bodies
    )
