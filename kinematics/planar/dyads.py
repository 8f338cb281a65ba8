"""Closed-form positions of a mechanism built of dyads (seed 002, §2.5: each coordinate as a
function of the driver), vectorised over every driver value at once.

A driven crank (a body turned by a rotation driver about a revolute joint to a known body)
is known first; then, while some pair of unknown bodies forms a dyad on known bodies, it is
solved in closed form and becomes known:

* **RRR**: bodies u, v joined by a revolute; u pinned to a known point A, v to a known point
  B. Their common pin C is where the circles about A (radius |AC| on u) and B (|BC| on v)
  meet; the branch is the one of the assembled start.
* **RRP**: u pinned to a known point A and to v at C; v slides on a known body's line
  (a prismatic joint, the line on the known body). v's angle is the line's (parallel), and C
  lies where the line, carried by v's offset to C, meets the circle about A.
* **RPR**: u and v each pinned to a known point and sliding on each other, each pin on the
  slide's line (a slotted lever through a pivoted block): the line joins the two pins.

Not every mechanism is built so (a-z-1139's guides, fixed joints, a drive on a slide): then
:func:`dyad_positions` returns None, and the Newton solution stands alone. Units SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .model import Mechanism, Prismatic, Revolute, RotationDriver

Pose = tuple[np.ndarray, np.ndarray, np.ndarray]  # x (m), y (m), theta (rad), each (steps,)


@dataclass(frozen=True)
class DyadSolution:
    """q (steps, n) in closed form; ``order`` how it was built ("crank 2", "RRR 3+4", ...);
    ``valid`` (steps,) False where a dyad cannot close (its circles do not meet)."""

    q: np.ndarray
    order: tuple[str, ...]
    valid: np.ndarray


def _rotate(th: np.ndarray, p) -> np.ndarray:
    """R(theta) p for each theta: (steps, 2)."""
    c, s = np.cos(th), np.sin(th)
    return np.stack([c * p[0] - s * p[1], s * p[0] + c * p[1]], axis=1)


def _world(mech: Mechanism, poses: dict[int, Pose], body: int, point: str) -> np.ndarray:
    """A body point's ground-frame position at every step (steps, 2)."""
    x, y, th = poses[body]
    return np.stack([x, y], axis=1) + _rotate(th, mech.body(body).points[point])


def _pose_through(mech: Mechanism, body: int, a: str, c: str, A: np.ndarray, C: np.ndarray) -> Pose:
    """The pose that puts local points a and c of ``body`` at A and C."""
    pts = mech.body(body).points
    local = np.subtract(pts[c], pts[a])
    th = np.arctan2(C[:, 1] - A[:, 1], C[:, 0] - A[:, 0]) - np.arctan2(local[1], local[0])
    r = A - _rotate(th, pts[a])
    return r[:, 0], r[:, 1], th


def _side(q0: np.ndarray, mech: Mechanism, body: int, point: str, A0, B0) -> float:
    """Which side of the line A-B the assembled start puts a body point: +1 or -1."""
    x, y, th = q0[3 * body - 3 : 3 * body]
    P = np.array([x, y]) + _rotate(np.array([th]), mech.body(body).points[point])[0]
    d, e = B0 - A0, P - A0
    return 1.0 if d[0] * e[1] - d[1] * e[0] >= 0 else -1.0


def _circles(A: np.ndarray, B: np.ndarray, ra: float, rb: float, side: float) -> tuple[np.ndarray, np.ndarray]:
    """The meeting point of the circles about A (radius ra) and B (rb) on ``side`` of A-B,
    and where they meet at all (steps,)."""
    d = B - A
    dist = np.hypot(d[:, 0], d[:, 1])
    a = (ra**2 - rb**2 + dist**2) / (2 * dist)
    h2 = ra**2 - a**2
    h = np.sqrt(np.clip(h2, 0.0, None))
    u = d / dist[:, None]
    n = np.stack([-u[:, 1], u[:, 0]], axis=1)
    return A + a[:, None] * u + side * h[:, None] * n, h2 >= -1e-12 * ra**2


def _revolutes(mech: Mechanism) -> list[Revolute]:
    return [j for j in mech.joints if isinstance(j, Revolute)]


def _pin(j: Revolute, body: int) -> tuple[int, str, str]:
    """(the other body, this body's point, the other's point) of a revolute on ``body``."""
    return (j.j, j.pi, j.pj) if j.i == body else (j.i, j.pj, j.pi)


def _crank(mech: Mechanism, s: np.ndarray, poses: dict) -> str | None:
    """The driven body's pose from its driver, when it turns about a known pin."""
    d = mech.driver
    if len(mech.drivers) != 1 or not isinstance(d, RotationDriver) or d.reference not in poses:
        return None
    for j in _revolutes(mech):
        if d.body in (j.i, j.j):
            other, mine, theirs = _pin(j, d.body)
            if other in poses:
                th = np.fromiter((d.f(float(v))[0] for v in s), float, s.size) + poses[d.reference][2]
                P = _world(mech, poses, other, theirs)
                r = P - _rotate(th, mech.body(d.body).points[mine])
                poses[d.body] = (r[:, 0], r[:, 1], th)
                return f"crank {mech.body(d.body).name}"
    return None


def _rrr(mech: Mechanism, q0: np.ndarray, poses: dict, valid: np.ndarray) -> str | None:
    """Solve one RRR dyad on known bodies, if there is one; its name, else None."""
    pins = _revolutes(mech)
    for middle in pins:
        u, v = middle.i, middle.j
        if u in poses or v in poses or 0 in (u, v):
            continue
        to_u = [(j, *_pin(j, u)) for j in pins if j is not middle and u in (j.i, j.j) and _pin(j, u)[0] in poses]
        to_v = [(j, *_pin(j, v)) for j in pins if j is not middle and v in (j.i, j.j) and _pin(j, v)[0] in poses]
        if not (to_u and to_v):
            continue
        (_, ku, a, ka), (_, kv, b, kb) = to_u[0], to_v[0]
        A, B = _world(mech, poses, ku, ka), _world(mech, poses, kv, kb)
        pu, pv = mech.body(u).points, mech.body(v).points
        ra, rb = float(np.hypot(*np.subtract(pu[middle.pi], pu[a]))), float(np.hypot(*np.subtract(pv[middle.pj], pv[b])))
        side = _side(q0, mech, u, middle.pi, A[0], B[0])
        C, meets = _circles(A, B, ra, rb, side)
        valid &= meets
        poses[u] = _pose_through(mech, u, a, middle.pi, A, C)
        poses[v] = _pose_through(mech, v, b, middle.pj, B, C)
        return f"RRR {mech.body(u).name}+{mech.body(v).name}"
    return None


def _rrp(mech: Mechanism, q0: np.ndarray, poses: dict, valid: np.ndarray) -> str | None:
    """Solve one RRP dyad (the slide's line on a known body), if there is one."""
    for middle in _revolutes(mech):
        for u, v, cu, cv in ((middle.i, middle.j, middle.pi, middle.pj), (middle.j, middle.i, middle.pj, middle.pi)):
            if u in poses or v in poses or 0 in (u, v):
                continue
            pin = next(
                (_pin(j, u) for j in _revolutes(mech) if j is not middle and u in (j.i, j.j) and _pin(j, u)[0] in poses),
                None,
            )
            slide = _known_line(mech, v, poses)
            if pin is None or slide is None:
                continue
            ku, a, ka = pin
            known, kp, kq, vp, vq = slide
            A = _world(mech, poses, ku, ka)
            P, Q = _world(mech, poses, known, kp), _world(mech, poses, known, kq)
            pv = mech.body(v).points
            local = np.subtract(pv[vq], pv[vp])
            th_line = np.arctan2(Q[:, 1] - P[:, 1], Q[:, 0] - P[:, 0])
            flip = _flip(q0, v, th_line[0] - np.arctan2(local[1], local[0]))
            th = th_line - np.arctan2(local[1], local[0]) + flip
            e = (Q - P) / np.hypot(*(Q - P).T)[:, None]
            w = _rotate(th, np.subtract(pv[cv], pv[vp]))  # from v's point on the line to C
            ra = float(np.hypot(*np.subtract(mech.body(u).points[cu], mech.body(u).points[a])))
            t, meets = _line_circle(P + w - A, e, ra, q0, mech, v, vp, P[0], e[0])
            valid &= meets
            C = P + t[:, None] * e + w
            poses[u] = _pose_through(mech, u, a, cu, A, C)
            r = C - _rotate(th, pv[cv])
            poses[v] = (r[:, 0], r[:, 1], th)
            return f"RRP {mech.body(u).name}+{mech.body(v).name}"
    return None


def _known_line(mech: Mechanism, v: int, poses: dict) -> tuple[int, str, str, str, str] | None:
    """A prismatic joint between body v and a known body: (the known body, its two line
    points, v's two line points). Either body may carry the line the other's point is on:
    the lines are parallel and share that point, so they are one line."""
    for j in mech.joints:
        if isinstance(j, Prismatic) and j.j == v and j.i in poses:
            return j.i, j.pi, j.qi, j.pj, j.qj
        if isinstance(j, Prismatic) and j.i == v and j.j in poses:
            return j.j, j.pj, j.qj, j.pi, j.qi
    return None


def _rpr(mech: Mechanism, q0: np.ndarray, poses: dict, valid: np.ndarray) -> str | None:
    """Solve one RPR dyad: u and v each pinned to a known point, sliding on each other,
    each one's pin on the slide's line (a slotted lever through a pivoted block): the line
    runs through both pins."""
    for slide in (j for j in mech.joints if isinstance(j, Prismatic)):
        u, v = slide.i, slide.j
        if u in poses or v in poses or 0 in (u, v):
            continue
        pin_u = next((_pin(j, u) for j in _revolutes(mech) if u in (j.i, j.j) and _pin(j, u)[0] in poses), None)
        pin_v = next((_pin(j, v) for j in _revolutes(mech) if v in (j.i, j.j) and _pin(j, v)[0] in poses), None)
        if pin_u is None or pin_v is None or pin_u[1] != slide.pi or pin_v[1] != slide.pj:
            continue
        U, V = _world(mech, poses, pin_u[0], pin_u[2]), _world(mech, poses, pin_v[0], pin_v[2])
        valid &= np.hypot(*(V - U).T) > 0
        along = np.arctan2(V[:, 1] - U[:, 1], V[:, 0] - U[:, 0])
        for body, a, b, at in ((u, slide.pi, slide.qi, U), (v, slide.pj, slide.qj, V)):
            local = np.subtract(mech.body(body).points[b], mech.body(body).points[a])
            th = along - np.arctan2(local[1], local[0])
            th = th + _flip(q0, body, th[0])
            r = at - _rotate(th, mech.body(body).points[a])
            poses[body] = (r[:, 0], r[:, 1], th)
        return f"RPR {mech.body(u).name}+{mech.body(v).name}"
    return None


def _flip(q0: np.ndarray, v: int, parallel: float) -> float:
    """0 or pi: whether the start has the slide's line along or against the guide's."""
    return 0.0 if np.cos(q0[3 * v - 1] - parallel) >= 0 else np.pi


def _line_circle(m: np.ndarray, e: np.ndarray, r: float, q0, mech, v, vp: str, P0, e0) -> tuple[np.ndarray, np.ndarray]:
    """t with |m + t e| = r (e unit), the root nearer the start's; and where there is one."""
    b = np.einsum("ij,ij->i", m, e)
    disc = b**2 - (np.einsum("ij,ij->i", m, m) - r**2)
    root = np.sqrt(np.clip(disc, 0.0, None))
    x, y, th = q0[3 * v - 3 : 3 * v]
    start = np.array([x, y]) + _rotate(np.array([th]), mech.body(v).points[vp])[0]
    t0 = float((start - P0) @ e0)
    sign = 1.0 if abs(-b[0] + root[0] - t0) <= abs(-b[0] - root[0] - t0) else -1.0
    return -b + sign * root, disc >= -1e-12 * r**2


def dyad_positions(mech: Mechanism, s: np.ndarray, q0: np.ndarray) -> DyadSolution | None:
    """Every body's pose at every driver value ``s`` in closed form, on the assembly branch
    of the start ``q0``; None when the mechanism is not a driven crank plus dyads."""
    s = np.asarray(s, float)
    zero = np.zeros_like(s)
    poses: dict[int, Pose] = {0: (zero, zero, zero)}
    valid = np.ones(s.size, bool)
    crank = _crank(mech, s, poses)
    if crank is None:
        return None
    order = [crank]
    while len(poses) <= len(mech.bodies):
        step = _rrr(mech, q0, poses, valid) or _rrp(mech, q0, poses, valid) or _rpr(mech, q0, poses, valid)
        if step is None:
            return None
        order.append(step)
    q = np.column_stack([c for k in range(1, len(mech.bodies) + 1) for c in poses[k]])
    return DyadSolution(q, tuple(order), valid)
