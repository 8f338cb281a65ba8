"""A planar mechanism's constraint equations written symbolically (seed 002, §2.5), with
sympy: each body k's coordinates x_k, y_k (m) and theta_k (rad), the driver parameter s,
each body's points as the numbers of the scene (m). ``Phi(q, s) = 0`` equation by
equation, named by its joint; :func:`equations_text` prints them, one per line.
"""

from __future__ import annotations

from typing import Any

from railcheck.kinematics.planar.model import Fixed, Mechanism, Prismatic, Revolute, RotationDriver, TranslationDriver


def coordinates(mech: Mechanism):
    """The sympy symbols (x_k, y_k, theta_k) of every moving body, in q's order, and s."""
    import sympy as sp

    names = " ".join(f"x_{b.name} y_{b.name} theta_{b.name}" for b in mech.bodies)
    return list(sp.symbols(names, real=True)), sp.Symbol("s", real=True)


def _frame(mech: Mechanism, q, k: int):
    """(origin, rotation matrix) of body k as sympy expressions (the ground: fixed)."""
    import sympy as sp

    if k == 0:
        return sp.Matrix([0, 0]), sp.eye(2), sp.Integer(0)
    x, y, th = q[3 * k - 3 : 3 * k]
    return sp.Matrix([x, y]), sp.Matrix([[sp.cos(th), -sp.sin(th)], [sp.sin(th), sp.cos(th)]]), th


def _point(mech: Mechanism, q, k: int, name: str):
    import sympy as sp

    r, A, _ = _frame(mech, q, k)
    return r + A * sp.Matrix(mech.body(k).points[name])


def _direction(mech: Mechanism, q, k: int, a: str, b: str):
    import sympy as sp

    _, A, _ = _frame(mech, q, k)
    pts = mech.body(k).points
    return A * (sp.Matrix(pts[b]) - sp.Matrix(pts[a]))


def _cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


def constraint_equations(mech: Mechanism) -> list[tuple[str, object]]:
    """[(constraint name, sympy expression equal to 0)] in the solver's row order; a
    driver's function of s must be linear (ratio s + offset, as scenes write them)."""
    import sympy as sp

    q, s = coordinates(mech)
    out: list[tuple[str, Any]] = []  # sympy expressions
    for c in mech.constraints():
        if isinstance(c, Revolute):
            d = _point(mech, q, c.i, c.pi) - _point(mech, q, c.j, c.pj)
            out += [(c.name, d[0]), (c.name, d[1])]
        elif isinstance(c, Prismatic):
            di = _direction(mech, q, c.i, c.pi, c.qi)
            h = _point(mech, q, c.j, c.pj) - _point(mech, q, c.i, c.pi)
            out += [(c.name, _cross(di, _direction(mech, q, c.j, c.pj, c.qj))), (c.name, _cross(di, h))]
        elif isinstance(c, Fixed):
            out += _fixed(mech, q, c)
        else:
            out.append((c.name, _driver(mech, q, s, c)))
    return [(n, sp.simplify(e) if e.count_ops() < 60 else e) for n, e in out]


def _fixed(mech: Mechanism, q, c: Fixed) -> list:
    """A fixed joint's three equations: body j keeps its placed pose relative to body i."""
    import sympy as sp

    bi, bj = mech.body(c.i), mech.body(c.j)
    xi = bi.initial if c.i else (0.0, 0.0, 0.0)
    xj = bj.initial
    ci, si = sp.cos(-xi[2]), sp.sin(-xi[2])
    rel = sp.Matrix([[ci, -si], [si, ci]]) * sp.Matrix([xj[0] - xi[0], xj[1] - xi[1]])
    ri, Ai, thi = _frame(mech, q, c.i)
    rj, _, thj = _frame(mech, q, c.j)
    d = rj - ri - Ai * rel
    return [(c.name, d[0]), (c.name, d[1]), (c.name, thj - thi - (xj[2] - xi[2]))]


def _driver(mech: Mechanism, q, s, c):
    """A driver's equation, its function of s read as ratio s + offset."""
    offset, ratio, curvature = c.f(0.0)
    if curvature:
        raise ValueError(f"{c.name}: only a linear drive is written symbolically")
    f = ratio * s + offset
    if isinstance(c, RotationDriver):
        _, _, th = _frame(mech, q, c.body)
        _, _, ref = _frame(mech, q, c.reference)
        return th - ref - f
    assert isinstance(c, TranslationDriver)
    import sympy as sp

    d = _direction(mech, q, c.i, c.pi, c.qi)
    h = _point(mech, q, c.j, c.pj) - _point(mech, q, c.i, c.pi)
    (ax, ay), (bx, by) = mech.body(c.i).points[c.pi], mech.body(c.i).points[c.qi]
    return d.dot(h) / sp.sqrt((bx - ax) ** 2 + (by - ay) ** 2) - f


def equations_text(mech: Mechanism) -> str:
    """The constraint equations, one line each: "joint: expression = 0" (m, rad)."""
    import sympy as sp

    lines = [f"constraint equations of {mech.name} (coordinates in m and rad, s the driver parameter):"]
    for name, e in constraint_equations(mech):
        lines.append(f"  {name}: {sp.sstr(sp.N(e, 6))} = 0")
    return "\n".join(lines)
