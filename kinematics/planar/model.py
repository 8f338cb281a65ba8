"""Planar multibody models in body coordinates (seed 002).

Each moving body k has coordinates ``(x_k, y_k, theta_k)``: the position (m) of its local
origin and the angle (rad) of its local x axis in the ground frame. Points are given in
the body's local frame. The ground is body ``0`` (fixed, not a coordinate).

Joints (constraint equations, each a smooth function of the coordinates):

* :class:`Revolute` (2 equations): point ``pi`` of body ``i`` coincides with point ``pj``
  of body ``j``;
* :class:`Prismatic` (2 equations): the line (``pi``, ``qi``) of body ``i`` and the line
  (``pj``, ``qj``) of body ``j`` are parallel, and ``pj`` lies on the first line
  (Mechanica's ``Translate2``);
* :class:`Fixed` (3 equations): body ``j`` is welded to body ``i`` as placed.

Drivers (1 equation each): :class:`RotationDriver` sets a body's angle to ``f(s)`` and
:class:`TranslationDriver` a point's distance along a body's line, as functions of the
driver parameter ``s`` (an angle in rad, or a length in m).

Every constraint is built from two primitives, a body point ``P = r + A p`` and a body
direction ``d = A u``, whose first and second time derivatives are exact, so the
right-hand side of the acceleration equations (gamma) is exact, not differenced.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, ClassVar

import numpy as np

Vec = tuple[float, float]


@dataclass(frozen=True)
class Body:
    """A rigid body: local points (m) by name; for inverse dynamics its mass (kg) and
    inertia (kg m^2) about its local origin, which is then taken as its centre of mass.
    ``initial``: its placement (x m, y m, theta rad) for the first Newton iteration."""

    name: str
    points: dict[str, Vec]
    mass: float = 0.0
    inertia: float = 0.0
    initial: tuple[float, float, float] = (0.0, 0.0, 0.0)  # x (m), y (m), theta (rad)


@dataclass(frozen=True)
class Revolute:
    name: str
    i: int
    pi: str
    j: int
    pj: str

    equations: ClassVar[int] = 2  # constraint equations


@dataclass(frozen=True)
class Prismatic:
    name: str
    i: int
    pi: str
    qi: str
    j: int
    pj: str
    qj: str

    equations: ClassVar[int] = 2  # constraint equations


@dataclass(frozen=True)
class Fixed:
    name: str
    i: int
    j: int

    equations: ClassVar[int] = 3  # constraint equations


@dataclass(frozen=True)
class RotationDriver:
    """theta_body - theta_reference = f(s) (rad): a body's angle, or with ``reference`` a
    revolute joint's relative angle; ``f`` returns (value, d/ds, d2/ds2)."""

    name: str
    body: int
    f: Callable[[float], tuple[float, float, float]]
    reference: int = 0  # the body the angle is measured from (0: the ground)

    equations: ClassVar[int] = 1  # constraint equations


@dataclass(frozen=True)
class TranslationDriver:
    """The signed distance of point ``pj`` of body ``j`` from point ``pi`` of body ``i``
    along the unit line (``pi``, ``qi``) of body ``i`` equals f(s)."""

    name: str
    i: int
    pi: str
    qi: str
    j: int
    pj: str
    f: Callable[[float], tuple[float, float, float]]

    equations: ClassVar[int] = 1  # constraint equations


@dataclass
class Mechanism:
    """Bodies (index 1..n; index 0 is the ground, given as ``ground``), joints, and the
    drivers (each a function of the one driver parameter s)."""

    name: str
    ground: Body
    bodies: list[Body]
    joints: list = field(default_factory=list)
    drivers: tuple = ()  # RotationDriver | TranslationDriver, each one equation in s
    tracer: tuple[int, str] | None = None  # (body, point) whose path is traced
    description: str = ""
    curve_parameters: dict[str, float] = field(default_factory=dict)  # m: the traced curve's (tests)

    @property
    def n(self) -> int:
        return 3 * len(self.bodies)

    @property
    def driver(self):
        """The first driver (the one whose value the driver parameter is), or None."""
        return self.drivers[0] if self.drivers else None

    def body(self, k: int) -> Body:
        return self.ground if k == 0 else self.bodies[k - 1]

    def initial_q(self) -> np.ndarray:
        return np.array([c for b in self.bodies for c in b.initial], float)

    def constraints(self, with_driver: bool = True) -> list:
        return list(self.joints) + (list(self.drivers) if with_driver else [])

    def m(self, with_driver: bool = True) -> int:
        return sum(c.equations for c in self.constraints(with_driver))


# -- primitives ---------------------------------------------------------------------


def _rot(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]])


def _perp(v):
    return np.array([-v[1], v[0]])


def _cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


class _Frame:
    """Position, velocity and q-Jacobians of body points and directions at (q, qdot)."""

    def __init__(self, mech: Mechanism, q: np.ndarray, qd: np.ndarray | None = None):
        self.mech, self.q, self.qd = mech, q, qd if qd is not None else np.zeros_like(q)

    def _body(self, k):
        if k == 0:
            return np.zeros(2), 0.0, np.zeros(2), 0.0
        x, y, th = self.q[3 * k - 3 : 3 * k]
        vx, vy, w = self.qd[3 * k - 3 : 3 * k]
        return np.array([x, y]), th, np.array([vx, vy]), w

    def point(self, k, name):
        """(P, J (2, n), Pdot, Pddot0): Pddot0 is the acceleration with qddot = 0."""
        r, th, v, w = self._body(k)
        s = np.asarray(self.mech.body(k).points[name], float)
        As = _rot(th) @ s
        J = np.zeros((2, self.mech.n))
        if k:
            J[:, 3 * k - 3 : 3 * k - 1] = np.eye(2)
            J[:, 3 * k - 1] = _perp(As)
        return r + As, J, v + w * _perp(As), -(w**2) * As

    def direction(self, k, a, b):
        """The vector from local point a to b: (d, J, ddot, dddot0)."""
        _, th, _, w = self._body(k)
        pts = self.mech.body(k).points
        u = np.asarray(pts[b], float) - np.asarray(pts[a], float)
        d = _rot(th) @ u
        J = np.zeros((2, self.mech.n))
        if k:
            J[:, 3 * k - 1] = _perp(d)
        return d, J, w * _perp(d), -(w**2) * d


def _cross_terms(a, b):
    """Constraint cross(a, b) from two primitives: (value, row, gamma)."""
    va, Ja, da, aa = a
    vb, Jb, db, ab = b
    value = _cross(va, vb)
    row = va[0] * Jb[1] - va[1] * Jb[0] + Ja[0] * vb[1] - Ja[1] * vb[0]
    gamma = -(_cross(aa, vb) + 2 * _cross(da, db) + _cross(va, ab))
    return value, row, gamma


def evaluate(mech: Mechanism, q: np.ndarray, qd: np.ndarray | None = None, s: float = 0.0, with_driver: bool = True):
    """Constraints at (q, qdot, driver parameter s): (Phi (m,), Phi_q (m, n), nu (m,), gamma (m,)).

    ``nu`` is the velocity right-hand side (Phi_q qdot = nu), ``gamma`` the acceleration
    one (Phi_q qddot = gamma); the driver's parameter moves at unit rate (ds/dt = 1), so
    velocities and accelerations come out per unit of s and per unit of s squared.
    """
    fr = _Frame(mech, q, qd)
    acc: tuple[list, list, list, list] = ([], [], [], [])  # phi, rows, nu, gamma
    for c in mech.constraints(with_driver):
        rows_of = _CONSTRAINT_ROWS.get(type(c))
        if rows_of is None:
            raise TypeError(f"unknown constraint {c!r}")
        rows_of(mech, fr, q, s, c, acc)
    phi, rows, nu, gamma = acc
    return np.array(phi), np.array(rows).reshape(len(phi), mech.n), np.array(nu), np.array(gamma)


def _revolute_rows(mech: Mechanism, fr: _Frame, q, s: float, c: Revolute, acc: tuple) -> None:
    """A revolute joint's two rows: its two bodies' points coincide."""
    phi, rows, nu, gamma = acc
    Pi, Ji, Vi, Ai = fr.point(c.i, c.pi)
    Pj, Jj, Vj, Aj = fr.point(c.j, c.pj)
    phi += list(Pi - Pj)
    rows += list(Ji - Jj)
    nu += [0.0, 0.0]
    gamma += list(-(Ai - Aj))


def _prismatic_rows(mech: Mechanism, fr: _Frame, q, s: float, c: Prismatic, acc: tuple) -> None:
    """A prismatic joint's two rows: the two directions parallel, and the second body's
    point on the first's line."""
    di = fr.direction(c.i, c.pi, c.qi)
    dj = fr.direction(c.j, c.pj, c.qj)
    v, r, g = _cross_terms(di, dj)
    _add(acc, v, r, 0.0, g)
    Pi, Pj = fr.point(c.i, c.pi), fr.point(c.j, c.pj)
    h = (Pj[0] - Pi[0], Pj[1] - Pi[1], Pj[2] - Pi[2], Pj[3] - Pi[3])
    v, r, g = _cross_terms(di, h)
    _add(acc, v, r, 0.0, g)


def _fixed_rows(mech: Mechanism, fr: _Frame, q, s: float, c: Fixed, acc: tuple) -> None:
    """A fixed joint's three rows: the relative pose at the initial placement is kept."""
    phi, rows, nu, gamma = acc
    bi, bj = mech.body(c.i), mech.body(c.j)
    xi = np.array(bi.initial) if c.i else np.zeros(3)
    xj = np.array(bj.initial)
    rel_th = xj[2] - xi[2]
    rel = _rot(-xi[2]) @ (xj[:2] - xi[:2])
    ri, thi, vi, wi = fr._body(c.i)
    rj, thj, vj, wj = fr._body(c.j)
    Ar = _rot(thi) @ rel
    phi += list(rj - ri - Ar) + [thj - thi - rel_th]
    J = np.zeros((3, mech.n))
    J[0:2, 3 * c.j - 3 : 3 * c.j - 1] = np.eye(2)
    J[2, 3 * c.j - 1] = 1.0
    if c.i:
        J[0:2, 3 * c.i - 3 : 3 * c.i - 1] = -np.eye(2)
        J[0:2, 3 * c.i - 1] = -_perp(Ar)
        J[2, 3 * c.i - 1] = -1.0
    rows += list(J)
    nu += [0.0, 0.0, 0.0]
    gamma += list(-(wi**2 * Ar)) + [0.0]


def _rotation_driver_rows(mech: Mechanism, fr: _Frame, q, s: float, c: RotationDriver, acc: tuple) -> None:
    """A rotation driver's row: the body's angle from its reference body's is f(s)."""
    f, f1, f2 = c.f(s)
    th = q[3 * c.body - 1] - (q[3 * c.reference - 1] if c.reference else 0.0)
    row = np.zeros(mech.n)
    row[3 * c.body - 1] = 1.0
    if c.reference:
        row[3 * c.reference - 1] = -1.0
    _add(acc, th - f, row, f1, f2)


def _translation_driver_rows(mech: Mechanism, fr: _Frame, q, s: float, c: TranslationDriver, acc: tuple) -> None:
    """A translation driver's row: the distance along the first body's line is f(s)."""
    f, f1, f2 = c.f(s)
    di = fr.direction(c.i, c.pi, c.qi)
    length = float(np.hypot(*np.subtract(mech.body(c.i).points[c.qi], mech.body(c.i).points[c.pi])))
    Pi, Pj = fr.point(c.i, c.pi), fr.point(c.j, c.pj)
    h = tuple(Pj[k] - Pi[k] for k in range(4))
    # dot(d, h) / |u| = f(s)
    va, Ja, da, aa = di
    vb, Jb, db, ab = h
    value = float(va @ vb) / length
    row = (va @ Jb + vb @ Ja) / length
    g = -(float(aa @ vb) + 2 * float(da @ db) + float(va @ ab)) / length
    _add(acc, value - f, row, f1, g + f2)


#: each constraint's rows (:func:`evaluate`)
_CONSTRAINT_ROWS: dict[type, Callable[..., None]] = {
    Revolute: _revolute_rows,
    Prismatic: _prismatic_rows,
    Fixed: _fixed_rows,
    RotationDriver: _rotation_driver_rows,
    TranslationDriver: _translation_driver_rows,
}


def _add(lists, *values) -> None:
    """Append one constraint's (phi, Jacobian row, nu, gamma) to the four lists."""
    for target, value in zip(lists, values, strict=True):
        target.append(value)
