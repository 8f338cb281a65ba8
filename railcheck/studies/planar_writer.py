"""A body-coordinate mechanism written as a planar mechanism scene (the TOML that
:func:`railcheck.studies.planar_scene.planar_scene` reads back to the same mechanism):
``railcheck mechanism NAME --scene FILE`` writes a catalogue entry's, the examples/
folder's seed mechanisms are such files. Lengths in mm, angles in deg, as a user writes them.
"""

from __future__ import annotations

import math

from railcheck.kinematics.planar.model import Fixed, Mechanism, Prismatic, Revolute, RotationDriver


def _mm(x: float) -> str:
    return f'"{x * 1e3:.12g} mm"'


def _pt(p) -> str:
    return f"[{_mm(p[0])}, {_mm(p[1])}]"


def _points(points: dict) -> str:
    return "{ " + ", ".join(f"{k} = {_pt(v)}" for k, v in points.items()) + " }"


def _bodies(mech: Mechanism) -> list[str]:
    out = []
    for b in mech.bodies:
        x, y, th = b.initial
        out += ["", "[[mechanism.bodies]]", f'name = "{b.name}"', f"points = {_points(b.points)}"]
        out.append(f'at = [{_mm(x)}, {_mm(y)}, "{math.degrees(th):.12g} deg"]')
        if b.mass:
            out += [f'mass = "{b.mass:.12g} kg"', f'inertia = "{b.inertia:.12g} kg m2"']
    return out


def _joints(mech: Mechanism) -> list[str]:
    name = lambda k: "ground" if k == 0 else mech.body(k).name  # noqa: E731
    out = []
    for j in mech.joints:
        out += ["", "[[mechanism.joints]]", f'name = "{j.name}"']
        if isinstance(j, Revolute):
            out += ['kind = "revolute"', f'bodies = ["{name(j.i)}", "{name(j.j)}"]', f'points = ["{j.pi}", "{j.pj}"]']
        elif isinstance(j, Prismatic):
            out += ['kind = "prismatic"', f'bodies = ["{name(j.i)}", "{name(j.j)}"]']
            out.append(f'lines = [["{j.pi}", "{j.qi}"], ["{j.pj}", "{j.qj}"]]')
        elif isinstance(j, Fixed):
            out += ['kind = "fixed"', f'bodies = ["{name(j.i)}", "{name(j.j)}"]']
    return out


def _drive(mech: Mechanism) -> list[str]:
    """The catalogue's one driver (a body's angle, start + s) as the drive of the revolute
    joint that holds that body to the ground."""
    d = mech.driver
    if not isinstance(d, RotationDriver) or d.reference:
        raise ValueError(f"{mech.name}: only a body's angle from the ground is written as a drive")
    joint = next(
        j for j in mech.joints if isinstance(j, Revolute) and {j.i, j.j} == {0, d.body}
    )  # the driven body's pin to the ground
    offset, ratio, _ = d.f(0.0)
    sign = 1.0 if joint.j == d.body else -1.0  # the joint's angle is body j's from body i's
    return [
        "",
        "[[mechanism.drives]]",
        f'joint = "{joint.name}"',
        f"ratio = {sign * ratio:g}",
        f'offset = "{sign * math.degrees(offset):.12g} deg"',
    ]


def scene_text(mech: Mechanism, sweep_rad: float, steps: int, speed_rad_s: float, header: str = "") -> str:
    """The planar scene of ``mech`` driven over ``sweep_rad`` from its placement."""
    tracer = f"{mech.body(mech.tracer[0]).name}.{mech.tracer[1]}" if mech.tracer else None
    lines = [f"# {line}" if line else "#" for line in header.splitlines()]
    lines += ["[mechanism]", 'kind = "planar"', f'name = "{mech.name}"', f'description = "{mech.description}"']
    if tracer:
        lines.append(f'tracers = ["{tracer}"]')
    if any(b.mass for b in mech.bodies):
        lines.append('gravity = "0 m/s2"')
    lines.append(f"ground = {_points(mech.ground.points)}")
    lines += ["", "[mechanism.driver]", f'range = ["0 deg", "{math.degrees(sweep_rad):.12g} deg"]']
    lines += [f"steps = {steps}", f'speed = "{speed_rad_s:.12g} rad/s"']
    return "\n".join(lines + _bodies(mech) + _joints(mech) + _drive(mech)) + "\n"
