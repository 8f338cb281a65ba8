"""A planar mechanism scene: ``[mechanism] kind = "planar"`` read into a body-coordinate
:class:`~railcheck.kinematics.planar.model.Mechanism` (seed 002's pieces and pairs) and
the study's inputs (the driver parameter's range, steps and speed, gravity, tracers).

Units at this edge only: lengths, angles, masses and inertias are strings with units
("480 mm", "90 deg", "2.1 kg", "0.04 kg m2"); inside everything is SI. Each body's
points are in its own frame; a body's centre of mass (default its frame's origin) becomes
its frame's origin here, as the solver's inverse dynamics assume. Every refusal is one
:class:`~railcheck.base.errors.InputError` naming the key (``mechanism.joints[2].points``).
The keys are documented in docs/scenes.md ("Planar mechanisms").
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

from railcheck.base.errors import InputError
from railcheck.base.fields import number, refuse_unknown, require, string_choice
from railcheck.kinematics.planar.model import (
    Body,
    Fixed,
    Mechanism,
    Prismatic,
    Revolute,
    RotationDriver,
    TranslationDriver,
)
from railcheck.units import parse_quantity

GROUND = "ground"
KEYS = {"kind", "name", "description", "gravity", "ground", "bodies", "joints", "driver", "drives", "tracers"}
BODY_KEYS = {"name", "points", "at", "mass", "centre_of_mass", "inertia"}
JOINT_KEYS = {"name", "kind", "bodies", "points", "lines"}
DRIVER_KEYS = {"range", "steps", "speed"}
DRIVE_KEYS = {"joint", "ratio", "offset"}
JOINT_KINDS = ("revolute", "prismatic", "fixed")
COORDINATE_LIMIT = 100.0  # m: a point or placement farther than this from the origin is a typo
MAX_STEPS = 100_000
MAX_BODIES = 200
MAX_STEP_ANGLE = 15.0  # deg: the largest driver step the continuation is trusted to keep its branch over
MAX_TURNS = 100  # an angle range of at most this many turns
MAX_RATE = 1e4  # rad/s (about 1600 Hz) or m/s: beyond it the driver speed is a typo
MAX_MASS = 1e6  # kg


@dataclass(frozen=True)
class PlanarScene:
    """A planar mechanism and how to move it: ``values`` the driver parameter's values
    (rad for an angle, m for a slide), ``unit`` "angle" or "length", ``rate`` the
    parameter's rate of change (rad/s or m/s; negative when the range runs down), ``gravity`` (m/s^2, along -y), ``tracers``
    [(body index, point name)], ``source`` where it was read from."""

    mechanism: Mechanism
    start: float
    stop: float
    steps: int
    unit: str
    rate: float
    gravity: float
    tracers: tuple[tuple[int, str], ...]
    source: str

    @property
    def values(self):
        import numpy as np

        return np.linspace(self.start, self.stop, self.steps)


def is_planar(data: dict) -> bool:
    """True when a parsed scene's [mechanism] is a planar mechanism (kind "planar")."""
    table = data.get("mechanism")
    return isinstance(table, dict) and table.get("kind") == "planar"


def _table_list(value: Any, name: str, what: str) -> list[dict]:
    """``value`` as a non-empty list of tables ([[name]] in TOML)."""
    if not isinstance(value, list) or not value or not all(isinstance(v, dict) for v in value):
        raise InputError(name, f"must be one or more [[{name}]] tables ({what})")
    return value


def _length(value: Any, name: str) -> float:
    x = parse_quantity(value, "length", name)
    if abs(x) > COORDINATE_LIMIT:
        raise InputError(name, f"|value| is more than {COORDINATE_LIMIT:g} m from the origin")
    return x


def _point(value: Any, name: str) -> tuple[float, float]:
    """A point ["x mm", "y mm"] (m)."""
    if not isinstance(value, list) or len(value) != 2:
        raise InputError(name, f'must be a point ["x mm", "y mm"], got {value!r}')
    return _length(value[0], f"{name}[0]"), _length(value[1], f"{name}[1]")


def _points(value: Any, name: str) -> dict[str, tuple[float, float]]:
    """A body's points {name = ["x", "y"]} in its frame (m)."""
    if not isinstance(value, dict) or not value:
        raise InputError(name, 'must name at least one point: { A = ["0 mm", "0 mm"], ... }')
    return {str(k): _point(v, f"{name}.{k}") for k, v in value.items()}


def _placement(value: Any, name: str) -> tuple[float, float, float]:
    """["x mm", "y mm", "angle deg"]: where the body's frame is placed to start (m, m, rad)."""
    if not isinstance(value, list) or len(value) != 3:
        raise InputError(name, f'must be ["x mm", "y mm", "angle deg"], got {value!r}')
    x, y = _point(value[:2], name)
    return x, y, parse_quantity(value[2], "angle", f"{name}[2]")


def _body(table: dict, name: str) -> Body:
    """A moving body, its frame moved to its centre of mass (points and placement alike)."""
    refuse_unknown(table, BODY_KEYS, name + ".")
    body_name = require(table, "name", name + ".")
    if not isinstance(body_name, str) or not body_name or body_name == GROUND:
        raise InputError(name + ".name", f'must be a name other than "{GROUND}", got {body_name!r}')
    points = _points(require(table, "points", name + "."), name + ".points")
    x, y, th = _placement(table.get("at", ["0 mm", "0 mm", "0 deg"]), name + ".at")
    mass = parse_quantity(table.get("mass", "0 kg"), "mass", name + ".mass", positive=True)
    number(mass, name + ".mass", 0.0, MAX_MASS, "a mass in kg")
    inertia = _inertia(table.get("inertia", "0 kg m2"), name + ".inertia")
    cx, cy = _point(table.get("centre_of_mass", ["0 mm", "0 mm"]), name + ".centre_of_mass")
    shifted = {k: (px - cx, py - cy) for k, (px, py) in points.items()}
    c, s = math.cos(th), math.sin(th)
    return Body(body_name, shifted, mass, inertia, (x + c * cx - s * cy, y + s * cx + c * cy, th))


def _inertia(value: Any, name: str) -> float:
    """A moment of inertia about the centre of mass, "0.04 kg m2" (kg m^2)."""
    text = str(value).strip() if isinstance(value, str) else value
    for unit, factor in (("kg m2", 1.0), ("kg m^2", 1.0), ("kg*m^2", 1.0), ("kg mm2", 1e-6), ("kg mm^2", 1e-6)):
        if isinstance(text, str) and text.endswith(unit):
            inertia = number(_float(text[: -len(unit)], name), name, 0.0, 1e6, "an inertia in kg m2") * factor
            return inertia
    raise InputError(name, f'must be an inertia with its unit, "0.04 kg m2" or "4e4 kg mm2", got {value!r}')


def _float(text: str, name: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise InputError(name, f"{text.strip()!r} is not a number") from None


def _bodies_of(table: dict, name: str, index: dict[str, int], bodies: list[Body]) -> tuple[int, int]:
    """A joint's two bodies (indices; 0 the ground), named, existing and distinct."""
    pair = require(table, "bodies", name + ".")
    if not isinstance(pair, list) or len(pair) != 2 or not all(isinstance(b, str) for b in pair):
        raise InputError(name + ".bodies", f'must name two bodies, ["{GROUND}", "crank"], got {pair!r}')
    for b in pair:
        if b not in index:
            raise InputError(name + ".bodies", f"no body named {b!r} (bodies: {', '.join(index)})")
    if pair[0] == pair[1]:
        raise InputError(name + ".bodies", f"a joint between {pair[0]!r} and itself")
    return index[pair[0]], index[pair[1]]


def _named_points(value: Any, name: str, bodies: tuple[Body, ...], per_body: int) -> list[list[str]]:
    """Point names on each of a joint's two bodies (one each, or two for a line), each
    one the body has."""
    shape = '["A", "A"]' if per_body == 1 else '[["G1", "G2"], ["P", "Q"]]'
    rows = [[v] for v in value] if per_body == 1 and isinstance(value, list) else value
    if not isinstance(rows, list) or len(rows) != 2 or not all(isinstance(r, list) and len(r) == per_body for r in rows):
        raise InputError(name, f"must be {shape}, got {value!r}")
    for body, names in zip(bodies, rows, strict=True):
        for p in names:
            if p not in body.points:
                raise InputError(name, f"{body.name!r} has no point {p!r} (its points: {', '.join(body.points)})")
    if per_body == 2:
        for body, (a, b) in zip(bodies, rows, strict=True):
            if math.dist(body.points[a], body.points[b]) < 1e-9:
                raise InputError(name, f"the line {a}-{b} of {body.name!r} has two coincident points")
    return rows


def _joint(table: dict, name: str, index: dict[str, int], bodies: list[Body], ground: Body):
    """A revolute, prismatic or fixed joint between two named bodies."""
    refuse_unknown(table, JOINT_KEYS, name + ".")
    kind = string_choice(require(table, "kind", name + "."), JOINT_KINDS, name + ".kind")
    i, j = _bodies_of(table, name, index, bodies)
    pair = tuple(ground if k == 0 else bodies[k - 1] for k in (i, j))
    joint_name = str(table.get("name", f"{pair[0].name}-{pair[1].name}"))
    if kind == "revolute":
        (pi,), (pj,) = _named_points(require(table, "points", name + "."), name + ".points", pair, 1)
        return Revolute(joint_name, i, pi, j, pj)
    if kind == "prismatic":
        (pi, qi), (pj, qj) = _named_points(require(table, "lines", name + "."), name + ".lines", pair, 2)
        return Prismatic(joint_name, i, pi, qi, j, pj, qj)
    return Fixed(joint_name, i, j)


def _driver_range(table: Any) -> tuple[float, float, int, str, float]:
    """[mechanism.driver]: (start, stop, steps, "angle" | "length", rate) in SI."""
    p = "mechanism.driver."
    if not isinstance(table, dict):
        raise InputError("mechanism.driver", 'must be a table: range = ["0 deg", "360 deg"], steps, speed')
    refuse_unknown(table, DRIVER_KEYS, p)
    span = require(table, "range", p)
    if not isinstance(span, list) or len(span) != 2:
        raise InputError(p + "range", f'must be ["from", "to"] (angles or lengths), got {span!r}')
    unit = "length" if any(str(v).strip().endswith("m") for v in span) else "angle"
    start, stop = (parse_quantity(v, unit, f"{p}range[{k}]") for k, v in enumerate(span))
    if start == stop:
        raise InputError(p + "range", "from and to are the same value: the mechanism would not move")
    if unit == "angle" and abs(stop - start) > MAX_TURNS * 2 * math.pi:
        raise InputError(p + "range", f"more than {MAX_TURNS} turns: give the range of one cycle")
    if unit == "length" and abs(stop - start) > COORDINATE_LIMIT:
        raise InputError(p + "range", f"a slide of more than {COORDINATE_LIMIT:g} m")
    steps = table.get("steps", 361)
    if isinstance(steps, bool) or not isinstance(steps, int) or not 2 <= steps <= MAX_STEPS:
        raise InputError(p + "steps", f"must be a whole number from 2 to {MAX_STEPS}, got {steps!r}")
    if unit == "angle" and math.degrees(abs(stop - start)) / (steps - 1) > MAX_STEP_ANGLE:
        need = math.ceil(math.degrees(abs(stop - start)) / MAX_STEP_ANGLE) + 1
        raise InputError(
            p + "steps", f"steps of more than {MAX_STEP_ANGLE:g} deg may jump the assembly branch: {need} or more"
        )
    default_speed = "1 rad/s" if unit == "angle" else "0.1 m/s"
    rate = _rate(table.get("speed", default_speed), unit, p + "speed")
    return start, stop, steps, unit, math.copysign(rate, stop - start)


def _fine_enough(start: float, stop: float, steps: int, unit: str, name: str) -> None:
    """Refuse driver steps so coarse the continuation could jump the assembly branch."""
    if unit == "angle" and math.degrees(abs(stop - start)) / (steps - 1) > MAX_STEP_ANGLE:
        need = math.ceil(math.degrees(abs(stop - start)) / MAX_STEP_ANGLE) + 1
        raise InputError(name, f"steps of more than {MAX_STEP_ANGLE:g} deg may jump the assembly branch: {need} or more")


def with_steps(scene: PlanarScene, steps: int, name: str = "--steps") -> PlanarScene:
    """The scene over ``steps`` driver steps (2 to 100 000, fine enough), else refused."""
    if isinstance(steps, bool) or not isinstance(steps, int) or not 2 <= steps <= MAX_STEPS:
        raise InputError(name, f"must be a whole number from 2 to {MAX_STEPS}, got {steps!r}")
    _fine_enough(scene.start, scene.stop, steps, scene.unit, name)
    return dataclasses.replace(scene, steps=steps)


def _rate(value: Any, unit: str, name: str) -> float:
    """The driver parameter's speed: rad/s (or Hz, rpm) for an angle, m/s or mm/s for a slide."""
    if unit == "angle":
        rate = parse_quantity(value, "angular_speed", name, positive=True, allow_zero=False)
        if rate > MAX_RATE:
            raise InputError(
                name, f"more than {MAX_RATE:g} rad/s ({MAX_RATE / (2 * math.pi):.0f} Hz) is not a mechanism's speed"
            )
        return rate
    text = value.strip() if isinstance(value, str) else ""
    for suffix, factor in (("mm/s", 1e-3), ("m/s", 1.0)):
        if text.endswith(suffix):
            return number(_float(text[: -len(suffix)], name) * factor, name, 1e-9, 1e3, "a speed in m/s")
    raise InputError(name, f'a slide\'s speed must be in m/s or mm/s, e.g. "0.1 m/s", got {value!r}')


def _drive(table: dict, name: str, joints: dict):
    """A drive: the joint's relative angle (revolute: body j's angle from body i's) or
    slide (prismatic: body j's point along body i's line) = ratio * s + offset."""
    refuse_unknown(table, DRIVE_KEYS, name + ".")
    joint_name = require(table, "joint", name + ".")
    joint = joints.get(joint_name)
    if joint is None:
        raise InputError(name + ".joint", f"no joint named {joint_name!r} (joints: {', '.join(joints)})")
    ratio = number(table.get("ratio", 1.0), name + ".ratio", -1e6, 1e6, "a ratio")
    if ratio == 0:
        raise InputError(name + ".ratio", "a ratio of 0 does not move the joint")
    if isinstance(joint, Revolute):
        offset = parse_quantity(table.get("offset", "0 deg"), "angle", name + ".offset")
        if joint.j == 0:  # the ground's angle from body i: body i's own angle, negated
            return RotationDriver(f"drive {joint.name}", joint.i, _linear(-ratio, -offset)), joint
        return RotationDriver(f"drive {joint.name}", joint.j, _linear(ratio, offset), joint.i), joint
    if isinstance(joint, Prismatic):
        offset = parse_quantity(table.get("offset", "0 mm"), "length", name + ".offset")
        f = _linear(ratio, offset)
        return TranslationDriver(f"drive {joint.name}", joint.i, joint.pi, joint.qi, joint.j, joint.pj, f), joint
    raise InputError(name + ".joint", f"{joint.name!r} is a fixed joint: only a revolute or a prismatic joint moves")


def _linear(ratio: float, offset: float):
    """f(s) = ratio s + offset, with its first and second derivatives in s."""
    return lambda s: (ratio * s + offset, ratio, 0.0)


def _tracer(value: Any, name: str, index: dict[str, int], bodies: list[Body]) -> tuple[int, str]:
    """ "body.point" -> (body index, point name); a moving body's point."""
    if not isinstance(value, str) or "." not in value:
        raise InputError(name, f'must be "body.point", e.g. "coupler.P", got {value!r}')
    body, point = value.rsplit(".", 1)
    if body not in index or index[body] == 0:
        raise InputError(name, f"no moving body named {body!r} (bodies: {', '.join(b.name for b in bodies)})")
    if point not in bodies[index[body] - 1].points:
        raise InputError(name, f"{body!r} has no point {point!r} (its points: {', '.join(bodies[index[body] - 1].points)})")
    return index[body], point


def planar_scene(data: dict, source: str = "<scene>") -> PlanarScene:
    """A planar mechanism scene from its parsed TOML (only [mechanism] is read; a scene of
    this kind has no other table)."""
    for key in data:
        if key != "mechanism":
            raise InputError(
                key, 'a planar mechanism scene holds only [mechanism] (its keys: docs/scenes.md, "Planar mechanisms")'
            )
    table = data["mechanism"]
    refuse_unknown(table, KEYS, "mechanism.")
    p = "mechanism."
    ground = Body(GROUND, _points(require(table, "ground", p), p + "ground"))
    raw = _table_list(require(table, "bodies", p), p + "bodies", "a moving body each")
    if len(raw) > MAX_BODIES:
        raise InputError(p + "bodies", f"{len(raw)} bodies is more than this tool solves ({MAX_BODIES} at most)")
    bodies = [_body(t, f"{p}bodies[{k}]") for k, t in enumerate(raw)]
    index = {GROUND: 0}
    for k, b in enumerate(bodies, start=1):
        if b.name in index:
            raise InputError(f"{p}bodies[{k - 1}].name", f"two bodies are named {b.name!r}")
        index[b.name] = k
    joints = [_joint(t, f"{p}joints[{k}]", index, bodies, ground) for k, t in enumerate(_joint_tables(table))]
    by_name = _unique_joints(joints)
    start, stop, steps, unit, rate = _driver_range(require(table, "driver", p))
    drives = _drives(_table_list(require(table, "drives", p), p + "drives", "a driven joint each"), by_name)
    tracer_names = table.get("tracers", [f"{bodies[-1].name}.{list(bodies[-1].points)[-1]}"])
    if not isinstance(tracer_names, list) or not tracer_names:
        raise InputError(p + "tracers", f'must list body points, ["coupler.P"], got {tracer_names!r}')
    tracers = tuple(_tracer(t, f"{p}tracers[{k}]", index, bodies) for k, t in enumerate(tracer_names))
    gravity = parse_quantity(table.get("gravity", "0 m/s2"), "acceleration", p + "gravity", positive=True)
    number(gravity, p + "gravity", 0.0, 1000.0, "an acceleration in m/s2")
    name = str(table.get("name", source))
    mech = Mechanism(name, ground, bodies, joints, drives, tracers[0], str(table.get("description", "")))
    return PlanarScene(mech, start, stop, steps, unit, rate, gravity, tracers, source)


def _joint_tables(table: dict) -> list[dict]:
    return _table_list(require(table, "joints", "mechanism."), "mechanism.joints", "a joint each")


def _unique_joints(joints: list) -> dict:
    """The joints by name; two joints of one name refused."""
    by_name: dict = {}
    for k, j in enumerate(joints):
        if j.name in by_name:
            raise InputError(f"mechanism.joints[{k}].name", f"two joints are named {j.name!r}: name them apart")
        by_name[j.name] = j
    return by_name


def _drives(tables: list[dict], joints: dict) -> tuple:
    """The drivers; a joint driven twice refused."""
    drivers, driven = [], set()
    for k, t in enumerate(tables):
        driver, joint = _drive(t, f"mechanism.drives[{k}]", joints)
        if joint.name in driven:
            raise InputError(f"mechanism.drives[{k}].joint", f"{joint.name!r} is driven twice")
        driven.add(joint.name)
        drivers.append(driver)
    return tuple(drivers)
