"""Seed 002's study of any planar mechanism a scene draws (``[mechanism] kind = "planar"``):
mobility at the start and along the motion, the motion over the driver's range with the
assembly branch kept and a lock-up or a singular position reported where it happens, every
body's and tracer point's position, velocity and acceleration, and the inverse dynamics
(each joint's reaction, each drive's torque or force) with the bodies' masses and gravity.

Idealisations, stated wherever the results are shown: rigid bodies, ideal (frictionless,
clearance-free) joints, a driver parameter moving at constant speed, gravity along -y,
each body's mass at its stated centre of mass.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from railcheck.base.errors import InputError
from railcheck.kinematics.errors import MechanismError
from railcheck.kinematics.planar.dyads import dyad_positions
from railcheck.kinematics.planar.model import Mechanism, evaluate
from railcheck.kinematics.planar.solver import (
    RANK_TOL,
    Mobility,
    PlanarMotion,
    PlanarReactions,
    assemble,
    inverse_dynamics,
    mobility,
    solve,
)
from railcheck.studies.planar_scene import PlanarScene

#: along the motion the joints' Jacobian rank is evaluated at this many steps at most
RANK_SAMPLES = 721


@dataclass(frozen=True)
class Redundancy:
    """A joint equation that repeats the others at a placement: the joint, which of its
    equations (0-based), and what seed 002's self-alignment relaxes."""

    joint: str
    equation: int
    relax: str


@dataclass(frozen=True)
class ClosedForm:
    """Seed 002 §2.5: the positions in closed form, dyad by dyad (``order``), and the
    largest distance (m) between any body point there and where Newton put it."""

    order: tuple[str, ...]
    largest_difference: float


@dataclass(frozen=True)
class PlanarStudy:
    """A planar mechanism studied over its driver's range (SI; ground frame).

    ``mobility`` at the assembled start; ``dof_along`` the least and most degrees of
    freedom the joints leave along the motion (rank of their Jacobian); ``redundant`` the
    repeated joint equations; ``motion`` the solved steps (``motion.ended`` says why it
    stops early); ``reactions`` at the scene's driver speed with its gravity; ``tracers``
    per traced point its (steps, 6) x, y (m), vx, vy (m/s), ax, ay (m/s^2); ``closed_form``
    the dyad-by-dyad closed-form positions against Newton's, when the mechanism is built so."""

    scene: PlanarScene
    mobility: Mobility
    dof_along: tuple[int, int]
    redundant: tuple[Redundancy, ...]
    motion: PlanarMotion
    reactions: PlanarReactions
    tracers: dict[str, np.ndarray]
    closed_form: ClosedForm | None = None

    @property
    def mechanism(self) -> Mechanism:
        return self.scene.mechanism


def equation_owners(mech: Mechanism, with_driver: bool = False) -> list[tuple[str, int]]:
    """(constraint name, equation index) of each row of the constraint Jacobian."""
    return [(c.name, e) for c in mech.constraints(with_driver) for e in range(c.equations)]


def redundant_equations(mech: Mechanism, q: np.ndarray) -> tuple[Redundancy, ...]:
    """The joint equations that repeat earlier ones at ``q``: rows of the joints' Jacobian
    that add no rank, taken in the scene's order (the later joint of a dependent set is the
    one named)."""
    _, J, _, _ = evaluate(mech, q, with_driver=False)
    tol = RANK_TOL * max(1.0, float(np.abs(J).max()))
    kept: list[np.ndarray] = []
    out = []
    kinds = {j.name: type(j).__name__.lower() for j in mech.joints}
    for (name, e), row in zip(equation_owners(mech), J, strict=True):
        trial = np.array(kept + [row])
        if np.linalg.matrix_rank(trial, tol=tol) > len(kept):
            kept.append(row)
        else:
            out.append(Redundancy(name, e, _relaxation(kinds[name], e)))
    return tuple(out)


def _relaxation(kind: str, equation: int) -> str:
    """Seed 002's self-alignment: the pair that frees the repeated equation."""
    if kind == "revolute":
        axis = "x" if equation == 0 else "y"
        return f"its {axis} equation repeats the others: a pin in a slot (revolute + prismatic) there frees it"
    if kind == "prismatic":
        which = "parallel-lines" if equation == 0 else "point-on-line"
        return f"its {which} equation repeats the others: a pin in a slot (no parallelism) or a looser guide frees it"
    return f"its equation {equation} repeats the others: a revolute or prismatic pair there frees one of its three"


def _assembled(scene: PlanarScene) -> np.ndarray:
    """The bodies' coordinates closed at the driver's first value from their placements."""
    try:
        return assemble(scene.mechanism, scene.start)
    except MechanismError as exc:
        raise InputError(
            "mechanism.bodies",
            f"cannot be assembled from the bodies' placements (their \"at\") at the driver's first value: "
            f"{exc.message.split(': ', 1)[-1]}; place the bodies nearer where the joints put them",
        ) from None


def _driven_right(scene: PlanarScene, mob: Mobility) -> None:
    """As many drives as the joints leave degrees of freedom, else a one-line refusal."""
    drives = len(scene.mechanism.drivers)
    if mob.dof != drives:
        what = "add a drive or a joint" if mob.dof > drives else "remove a drive, or a joint that locks it"
        raise InputError(
            "mechanism.drives",
            f"{drives} drive(s) for {mob.dof} degree(s) of freedom (Gruebler count {mob.gruebler}, "
            f"{mob.redundant} redundant equation(s)): {what}",
        )


def dof_along(mech: Mechanism, motion: PlanarMotion) -> tuple[int, int]:
    """(least, most) degrees of freedom of the joints at up to :data:`RANK_SAMPLES` steps."""
    picks = np.unique(np.linspace(0, motion.s.size - 1, min(RANK_SAMPLES, motion.s.size)).astype(int))
    dofs = [mobility(mech, motion.q[k]).dof for k in picks]
    return min(dofs), max(dofs)


def tracer_table(motion: PlanarMotion, body: int, point: str, rate: float) -> np.ndarray:
    """(steps, 6): x, y (m), vx, vy (m/s), ax, ay (m/s^2) of a body point, the driver
    parameter moving at ``rate`` (rad/s or m/s)."""
    P, V, A = motion.point(body, point)
    return np.column_stack([P, V * rate, A * rate**2])


def driver_shown(study: PlanarStudy) -> tuple[np.ndarray, str]:
    """The driver's solved values in the unit a user reads: (values, "deg" | "mm")."""
    s = study.motion.s
    return (np.degrees(s), "deg") if study.scene.unit == "angle" else (s * 1e3, "mm")


def study_planar(scene: PlanarScene) -> PlanarStudy:
    """Mobility, motion, tracers and reactions of a planar mechanism scene."""
    mech = scene.mechanism
    _driven_right(scene, mobility(mech))  # counted at the placements: a wrong count before any Newton
    q0 = _assembled(scene)
    mob = mobility(mech, q0)
    _driven_right(scene, mob)
    motion = solve(mech, scene.values, q0, partial=True)
    reactions = inverse_dynamics(motion, scene.rate, scene.gravity)
    tracers = {f"{mech.body(b).name}.{p}": tracer_table(motion, b, p, scene.rate) for b, p in scene.tracers}
    closed = closed_form(mech, motion)
    return PlanarStudy(
        scene, mob, dof_along(mech, motion), redundant_equations(mech, q0), motion, reactions, tracers, closed
    )


def closed_form(mech: Mechanism, motion: PlanarMotion) -> ClosedForm | None:
    """The closed-form positions checked against the motion (None: not built of dyads, or
    a dyad that does not close where Newton did)."""
    solution = dyad_positions(mech, motion.s, motion.q[0])
    if solution is None or not solution.valid.all():
        return None
    other = PlanarMotion(mech, motion.s, solution.q, motion.qd, motion.qdd)
    largest = max(
        float(np.abs(other.point(k, p)[0] - motion.point(k, p)[0]).max())
        for k, body in enumerate(mech.bodies, start=1)
        for p in body.points
    )
    return ClosedForm(solution.order, largest)
