"""Solving planar mechanisms in body coordinates (seed 002).

* Positions: Newton-Raphson on Phi(q, s) = 0 from an initial guess (which selects the
  assembly mode), continued step to step along the driver parameter s; each step starts
  from a second-order extrapolation of the previous steps.
* Velocities: Phi_q qdot = nu; accelerations: Phi_q qddot = gamma (exact gamma).
* Mobility: the planar Gruebler count, and from the rank of the joints' Jacobian the
  actual degrees of freedom and the number of redundant constraint equations.
* A singular Jacobian on the path (the driven system loses rank) raises
  :class:`SingularConfigurationError` naming the driver value.
* Inverse dynamics by Lagrange multipliers: M qddot + Phi_q^T lambda = Q, each joint's
  reaction and the driver's effort from lambda.

The driver parameter s moves at unit rate: velocities are per unit of s (per rad of a
crank angle), accelerations per unit of s squared. For a crank turning at omega rad/s,
multiply by omega and omega^2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import MechanismError, SingularConfigurationError
from .model import Fixed, Mechanism, Prismatic, Revolute, RotationDriver, TranslationDriver, evaluate

RANK_TOL = 1e-9


@dataclass(frozen=True)
class Mobility:
    bodies: int  # moving bodies
    gruebler: int  # 3 n - 2 (revolute + prismatic) - 3 fixed
    dof: int  # n_q - rank(Phi_q) of the joints (no driver)
    redundant: int  # joint equations - rank
    equations: int

    def report(self) -> str:
        return (
            f"{self.bodies} moving bodies, {self.equations} joint equations: Gruebler count "
            f"{self.gruebler}, actual DOF {self.dof}, redundant constraints {self.redundant}"
        )


@dataclass(frozen=True)
class PlanarMotion:
    """q, qdot, qddot (steps, n) against the driver parameter s (steps,)."""

    mechanism: Mechanism
    s: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray

    def point(self, body: int, name: str):
        """(position, velocity, acceleration) of a body point, each (steps, 2), per unit
        of s and s^2."""
        p = np.asarray(self.mechanism.body(body).points[name], float)
        if body == 0:
            z = np.zeros((self.s.size, 2))
            return np.broadcast_to(p, z.shape).copy(), z, z.copy()
        k = body
        r = self.q[:, 3 * k - 3 : 3 * k - 1]
        th, w, al = self.q[:, 3 * k - 1], self.qd[:, 3 * k - 1], self.qdd[:, 3 * k - 1]
        c, si = np.cos(th), np.sin(th)
        As = np.stack([c * p[0] - si * p[1], si * p[0] + c * p[1]], axis=1)
        perp = np.stack([-As[:, 1], As[:, 0]], axis=1)
        v = self.qd[:, 3 * k - 3 : 3 * k - 1] + w[:, None] * perp
        a = self.qdd[:, 3 * k - 3 : 3 * k - 1] + al[:, None] * perp - (w**2)[:, None] * As
        return r + As, v, a


def mobility(mech: Mechanism, q: np.ndarray | None = None) -> Mobility:
    """Gruebler count and the rank-based DOF and redundancy of the joints at ``q``."""
    q = mech.initial_q() if q is None else q
    _, J, _, _ = evaluate(mech, q, with_driver=False)
    m = J.shape[0]
    rank = int(np.linalg.matrix_rank(J, tol=RANK_TOL * max(1.0, np.abs(J).max()))) if m else 0
    n_rev = sum(isinstance(j, (Revolute, Prismatic)) for j in mech.joints)
    n_fix = sum(isinstance(j, Fixed) for j in mech.joints)
    return Mobility(len(mech.bodies), 3 * len(mech.bodies) - 2 * n_rev - 3 * n_fix, mech.n - rank, m - rank, m)


def _newton(mech, q, s, tol=1e-13, maxiter=50):
    for _ in range(maxiter):
        phi, J, _, _ = evaluate(mech, q, s=s)
        scale = max(1.0, float(np.abs(q).max()))
        if np.abs(phi).max() <= tol * scale:
            return q, J
        dq = np.linalg.lstsq(J, -phi, rcond=None)[0]
        q = q + dq
        if np.abs(dq).max() <= 1e-15 * scale:
            phi, J, _, _ = evaluate(mech, q, s=s)
            if np.abs(phi).max() <= 1e-10 * scale:
                return q, J
    raise MechanismError(
        "mechanism",
        f"Newton-Raphson did not close the constraints at driver value {s:.6g} "
        f"(residual {np.abs(phi).max():.2e}): the mechanism cannot be assembled there",
    )


def assemble(mech: Mechanism, s0: float) -> np.ndarray:
    """Close the constraints at driver value s0 from the bodies' initial placement."""
    q, _ = _newton(mech, mech.initial_q(), s0)
    return q


def _singular(value: float, sv: np.ndarray, between: tuple[float, float] | None = None):
    where = f"between driver values {between[0]:.6g} and {between[1]:.6g}" if between else f"at driver value {value:.6g}"
    raise SingularConfigurationError(
        "mechanism",
        f"singular configuration {where} ({np.degrees(value):.4f} deg for an angle): the "
        f"constraint Jacobian loses rank (smallest singular value {sv[-1]:.2e} of {sv[0]:.2e})",
        float(value),
    )


def solve(mech: Mechanism, s: np.ndarray, q0: np.ndarray | None = None) -> PlanarMotion:
    """Positions, velocities and accelerations along the driver values ``s``."""
    s = np.asarray(s, float)
    q = assemble(mech, s[0]) if q0 is None else q0
    n = mech.n
    Q, QD, QDD = np.zeros((s.size, n)), np.zeros((s.size, n)), np.zeros((s.size, n))
    rank0 = None
    det_sign = 0.0
    for k, sk in enumerate(s):  # continuation is sequential: each step starts from the last
        if k >= 2:
            guess = Q[k - 1] + (sk - s[k - 1]) * QD[k - 1] + 0.5 * (sk - s[k - 1]) ** 2 * QDD[k - 1]
        elif k == 1:
            guess = Q[0] + (sk - s[0]) * QD[0]
        else:
            guess = q
        q, J = _newton(mech, guess, sk)
        sv = np.linalg.svd(J, compute_uv=False)
        rank = int(np.count_nonzero(sv > RANK_TOL * sv[0]))
        if rank0 is None:
            rank0 = rank
            if rank0 < n:
                _singular(sk, sv)
        elif rank < rank0:
            _singular(sk, sv)
        if J.shape[0] == n:
            # a sign change of det(J) between two steps: a singular point was stepped over
            sign = float(np.sign(np.linalg.det(J)))
            if det_sign and sign and sign != det_sign:
                _singular(0.5 * (sk + s[k - 1]), sv, between=(s[k - 1], sk))
            det_sign = sign or det_sign
        _, J, nu, gamma = evaluate(mech, q, s=sk)
        qd = np.linalg.lstsq(J, nu, rcond=None)[0]
        _, J, nu, gamma = evaluate(mech, q, qd, s=sk)
        qdd = np.linalg.lstsq(J, gamma, rcond=None)[0]
        Q[k], QD[k], QDD[k] = q, qd, qdd
    return PlanarMotion(mech, s, Q, QD, QDD)


@dataclass(frozen=True)
class PlanarReactions:
    """Joint reactions from Lagrange multipliers, per step: for each joint the force (N)
    that body ``i`` exerts on body ``j`` through it (ground frame, (steps, 2)), and the
    driver's effort (N m or N, (steps,))."""

    forces: dict[str, np.ndarray]
    effort: np.ndarray


def inverse_dynamics(motion: PlanarMotion, rate: float, gravity: float = 0.0) -> PlanarReactions:
    """Lagrange multipliers for a driver moving at constant ``rate`` (rad/s or m/s).

    Bodies' local origins are their centres of mass; M = diag(m, m, I) per body.
    Solves Phi_q^T lambda = Q - M qddot (least squares when constraints are redundant).
    """
    mech = motion.mechanism
    mass = np.concatenate([[b.mass, b.mass, b.inertia] for b in mech.bodies])
    Qg = np.concatenate([[0.0, -b.mass * gravity, 0.0] for b in mech.bodies])
    forces = {j.name: np.zeros((motion.s.size, 2)) for j in mech.joints}
    effort = np.zeros(motion.s.size)
    for k in range(motion.s.size):
        # body origins are centres of mass: M qddot has no velocity terms in the plane
        q, qdd = motion.q[k], motion.qdd[k] * rate**2
        _, J, _, _ = evaluate(mech, q, s=motion.s[k])
        lam = np.linalg.lstsq(J.T, Qg - mass * qdd, rcond=None)[0]
        row = 0
        for c in mech.constraints():
            rows = slice(row, row + c.equations)
            if isinstance(c, (RotationDriver, TranslationDriver)):
                effort[k] = -lam[row]
            else:
                # the constraint force on body j: -(dPhi/dr_j)^T lambda (on i when j is the ground)
                if c.j != 0:
                    cols = slice(3 * c.j - 3, 3 * c.j - 1)
                    forces[c.name][k] = -(J[rows, cols].T @ lam[rows])
                else:
                    cols = slice(3 * c.i - 3, 3 * c.i - 1)
                    forces[c.name][k] = J[rows, cols].T @ lam[rows]
            row += c.equations
    return PlanarReactions(forces, effort)
