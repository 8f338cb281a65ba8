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
from .model import Fixed, Mechanism, Prismatic, Revolute, RotationDriver, evaluate

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
    """q, qdot, qddot (steps, n) against the driver parameter s (steps,); per step the
    rank of the driven constraint Jacobian and its smallest singular value over its
    largest (``conditioning``: near 0 at a dead centre). ``ended``: why the motion stops
    before the last driver value asked for (a lock-up or a singular position, with the
    driver value), or None when it covers them all."""

    mechanism: Mechanism
    s: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    rank: np.ndarray | None = None
    conditioning: np.ndarray | None = None
    ended: str | None = None

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


def _guess(Q, QD, QDD, s, k, q0):
    """The Newton start of step k: a second-order extrapolation of the steps before."""
    if k >= 2:
        h = s[k] - s[k - 1]
        return Q[k - 1] + h * QD[k - 1] + 0.5 * h**2 * QDD[k - 1]
    if k == 1:
        return Q[0] + (s[1] - s[0]) * QD[0]
    return q0


class _RankWatch:
    """Raises :class:`SingularConfigurationError` when the driven Jacobian loses rank at a
    step, or when det(J) changes sign between two steps (a singular point stepped over)."""

    def __init__(self, n: int):
        self.n, self.sign = n, 0.0
        self.rank0: int | None = None

    def __call__(self, J, sk: float, previous: float | None) -> tuple[int, float]:
        sv = np.linalg.svd(J, compute_uv=False)
        rank = int(np.count_nonzero(sv > RANK_TOL * sv[0]))
        if self.rank0 is None:
            self.rank0 = rank
            if rank < self.n:
                _singular(sk, sv)
        elif rank < self.rank0:
            _singular(sk, sv)
        if J.shape[0] == self.n:
            sign = float(np.sign(np.linalg.det(J)))
            if self.sign and sign and sign != self.sign and previous is not None:
                _singular(0.5 * (sk + previous), sv, between=(previous, sk))
            self.sign = sign or self.sign
        return rank, float(sv[-1] / sv[0])


def solve(mech: Mechanism, s: np.ndarray, q0: np.ndarray | None = None, partial: bool = False) -> PlanarMotion:
    """Positions, velocities and accelerations along the driver values ``s``.

    A lock-up (the constraints cannot be closed) or a singular position raises; with
    ``partial`` the motion up to the last good step is returned instead, its ``ended``
    saying why and where (no step past a singular position is ever returned)."""
    s = np.asarray(s, float)
    q = assemble(mech, s[0]) if q0 is None else q0
    Q, QD, QDD = (np.zeros((s.size, mech.n)) for _ in range(3))
    rank, cond = np.zeros(s.size, int), np.zeros(s.size)
    watch, ended, done = _RankWatch(mech.n), None, s.size
    for k, sk in enumerate(s):  # continuation is sequential: each step starts from the last
        try:
            q, J = _newton(mech, _guess(Q, QD, QDD, s, k, q), sk)
            rank[k], cond[k] = watch(J, sk, s[k - 1] if k else None)
        except MechanismError as exc:
            if not partial or k == 0:
                raise
            ended, done = exc.message, k
            break
        _, J, nu, _ = evaluate(mech, q, s=sk)
        qd = np.linalg.lstsq(J, nu, rcond=None)[0]
        _, J, _, gamma = evaluate(mech, q, qd, s=sk)
        Q[k], QD[k], QDD[k] = q, qd, np.linalg.lstsq(J, gamma, rcond=None)[0]
    keep = slice(0, done)
    return PlanarMotion(mech, s[keep], Q[keep], QD[keep], QDD[keep], rank[keep], cond[keep], ended)


@dataclass(frozen=True)
class PlanarReactions:
    """Joint reactions from Lagrange multipliers, per step (ground frame).

    ``forces``: for each joint the force (N, (steps, 2)) that body ``i`` exerts on body
    ``j`` through it. ``loads``: for each joint the generalized force it puts on each of its
    two moving bodies, ``{joint: {body: (steps, 3)}}`` (Fx N, Fy N, moment N m about the
    body's centre of mass); a prismatic or fixed joint carries a moment besides its force.
    ``efforts``: each driver's torque (N m) or force (N) on its body, (steps,); ``effort``
    the first driver's. ``residual``: per step, the largest of |M qddot - Q - sum of the
    joints' and drivers' loads| over every body's three equations, an equilibrium check of
    the solve (near 0; not 0 when redundant constraints share a load by least squares)."""

    forces: dict[str, np.ndarray]
    effort: np.ndarray
    loads: dict[str, dict[int, np.ndarray]]
    efforts: dict[str, np.ndarray]
    residual: np.ndarray
    scale: float  # N: the largest joint force or weight, the residual's reference


def _mass_and_weight(mech: Mechanism, gravity: float) -> tuple[np.ndarray, np.ndarray]:
    """diag(M) (n,) and the weights' generalized force (n,): gravity (m/s^2) along -y."""
    mass = np.concatenate([[b.mass, b.mass, b.inertia] for b in mech.bodies])
    weight = np.concatenate([[0.0, -b.mass * gravity, 0.0] for b in mech.bodies])
    return mass, weight


def _body_cols(k: int) -> slice:
    return slice(3 * k - 3, 3 * k)


def inverse_dynamics(motion: PlanarMotion, rate: float, gravity: float = 0.0) -> PlanarReactions:
    """Lagrange multipliers for the driver parameter moving at constant ``rate`` (rad/s
    or m/s); bodies' local origins are their centres of mass, M = diag(m, m, I) per body,
    gravity (m/s^2) acts along -y. Solves Phi_q^T lambda = Q - M qddot per step (least
    squares when constraints are redundant); each constraint's load on a body is
    -Phi_q[rows, body]^T lambda[rows]."""
    mech, steps = motion.mechanism, motion.s.size
    mass, weight = _mass_and_weight(mech, gravity)
    loads = {c.name: {k: np.zeros((steps, 3)) for k in _moving(c)} for c in mech.constraints()}
    efforts = {d.name: np.zeros(steps) for d in mech.drivers}
    residual = np.zeros(steps)
    for k in range(steps):  # one small dense solve a step
        # body origins are centres of mass: M qddot has no velocity terms in the plane
        inertial = mass * motion.qdd[k] * rate**2
        _, J, _, _ = evaluate(mech, motion.q[k], s=motion.s[k])
        lam = np.linalg.lstsq(J.T, weight - inertial, rcond=None)[0]
        total = weight.copy()
        row = 0
        for c in mech.constraints():
            rows = slice(row, row + c.equations)
            for body, load in loads[c.name].items():
                load[k] = -(J[rows, _body_cols(body)].T @ lam[rows])
                total[_body_cols(body)] += load[k]
            if c.name in efforts:  # a driver's torque or force along its line on its body
                efforts[c.name][k] = -lam[row]
            row += c.equations
        residual[k] = np.abs(inertial - total).max()
    return _reactions(mech, loads, efforts, residual, weight)


def _moving(c) -> tuple[int, ...]:
    """The moving bodies a constraint acts on."""
    if isinstance(c, RotationDriver):
        bodies: tuple[int, ...] = (c.body, c.reference)
    else:
        bodies = (c.i, c.j)
    return tuple(dict.fromkeys(b for b in bodies if b))


def _reactions(mech: Mechanism, loads: dict, efforts: dict, residual: np.ndarray, weight: np.ndarray) -> PlanarReactions:
    """The record: each joint's force on its body j (or, j the ground, minus that on i)."""
    forces = {}
    for j in mech.joints:
        forces[j.name] = loads[j.name][j.j][:, :2] if j.j else -loads[j.name][j.i][:, :2]
    largest = max([float(np.abs(f).max()) for f in forces.values()] + [float(np.abs(weight).max()), 1e-300])
    first = efforts[mech.drivers[0].name] if mech.drivers else np.zeros(residual.size)
    return PlanarReactions(forces, first, loads, efforts, residual, largest)
