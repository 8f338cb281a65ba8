"""How each part is loaded over the cycle: its :class:`LoadModel` (resolved once from the
scene), its unit load cases, and the coefficient history of every load source.

Unit cases per part (part frame, :mod:`railcheck.fea.unitcases`): ``bolt_x`` and
``bolt_y``, a total force of 1 N along the part's longitudinal / transverse axis shared by
the joint's bolt holes; with ``gravity`` or ``rail-inertia``, ``body_x`` and ``body_y``
(1 N/m^3); with ``rail-inertia`` on a rail, ``body_rot`` and ``body_rad`` (the rigid
rotation's tangential and centripetal fields about the rail's pivot). Each load source of
the part (a joint it can sit at) gives a coefficient history (steps, cases). The check and
the sweep share these functions, so a sweep's setting equals a check of it.

Free body (``[check] support = "free-body"``, rails): the bar is loaded as the rig loads
it, with no clamp. Unit cases ``pin_x``, ``pin_y`` (the near joint's force on the two
screws that clamp the rail to its upper plate, through its first two holes, the joint's
line midway between them), for the crank ``torque`` (the motor torque as a couple over
the same two screws), ``bolt_x``, ``bolt_y`` (the far joint's force on its bolt holes) and, with
gravity or inertia, the rail's own body forces ``body_x``, ``body_y``, ``body_rot``,
``body_rad``, which carry the dynamics' rail mass (:class:`~railcheck.fea.unitcases.FreeBodyCases`),
so their coefficients are accelerations (m/s^2, rad/s^2, rad^2/s^2). A joint's force on
the rail is the reaction on the bar plus the d'Alembert force and weight of the point
masses bolted there (plate, carriage, coupling). One load factor multiplies every load,
so the body stays in equilibrium; the solve removes what remains by inertia relief.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from railcheck.fea.pin_pressure import harmonic_names
from railcheck.fea.unitcases import BodyCase, CoupleCase, FoundationCase, PressureCase, TractionCase
from railcheck.geometry.catalogue import plate_planar_inertia, with_overrides
from railcheck.kinematics import massmodel
from railcheck.kinematics.massmodel import carried_mass
from railcheck.loads.cases import pivot_x
from railcheck.loads.histories import bolt_history, gravity_history, rail_inertia_history
from railcheck.loads.pin_pressure import HARMONICS, harmonic_coefficients
from railcheck.loads.rotation import to_rail_axes
from railcheck.loads.weight import CANTILEVERED, RailWeight, joint_forces
from railcheck.model.inputs import PartsInput
from railcheck.model.kinematics_stage import KinematicsResult
from railcheck.parts import BAR_INDEX, PARTS, FreeBody, FreePlate, LoadSource, rail_length
from railcheck.scene import ExplicitLoad

GRAVITY = 9.80665  # m/s^2
PIVOT_JOINT = {"crank": "O2", "coupler": "A", "rocker": "O4"}


@dataclass(frozen=True)
class LoadModel:
    """How one part is loaded: its ``sources`` (the joints it can sit at), the load
    ``factor`` on reactions, whether ``gravity`` and the rail's own d'Alembert inertia
    (``rail_inertia``) are applied, the ``explicit`` per-hole load that replaces the
    linkage (or None), the ``bar`` whose axes and motion a rail follows, and the
    material ``density`` (kg/m^3) of the body forces."""

    part: str
    bar: str | None
    sources: tuple[LoadSource, ...]
    factor: float
    gravity: bool
    rail_inertia: bool
    explicit: ExplicitLoad | None
    density: float
    free_body: FreeBody | None = None
    inertia: bool = False
    joint_masses: tuple[float, float] = (0.0, 0.0)
    rail_mass: float = 0.0
    bar_length: float = 0.0
    free_plate: FreePlate | None = None
    plate: tuple[float, float, float] = (0.0, 0.0, 0.0)  # (kg, centroid - seat m, polar moment about the seat kg m^2)
    rail_body: tuple[float, float] = (0.0, 0.0)  # the dynamics' rail: centre of mass x (m, part frame), inertia (kg m^2)
    foundation: str | None = None  # a bolted-down part as a free body: the face a rigid foundation's reaction acts on
    weight: RailWeight | None = None  # a table-top rig's rail: its weight out of plane (loads.weight)

    @property
    def is_free_body(self) -> bool:
        """A rail as a free body (joint forces at both ends, its own inertia)."""
        return self.free_body is not None

    @property
    def is_on_foundation(self) -> bool:
        """A part bolted down by a face, as a free body: its loads balanced there by a
        rigid foundation's linear reaction (no clamp)."""
        return self.foundation is not None

    @property
    def is_free_plate(self) -> bool:
        """A joint plate as a free body (pin force at its seat, bolts to the rail)."""
        return self.free_plate is not None


@dataclass(frozen=True)
class SourceHistory:
    """A load source's coefficient history ``C`` (steps, cases) over ``crank_angle``
    (steps,) rad; ``seed_step`` the instant of its reaction's peak magnitude."""

    joint: str
    C: np.ndarray
    crank_angle: np.ndarray
    seed_step: int


def load_model(
    inputs: PartsInput,
    name: str,
    density: float,
    bar_length: float | None = None,
    inertia: bool | None = None,
    kind: str | None = None,
) -> LoadModel:
    """The part's :class:`LoadModel` from the scene's [check] (density kg/m^3). A free
    rail's bar length (m), whether inertia acts and the linkage ``kind`` (which sets the
    masses its joints carry) come from the scene's [mechanism] unless given (a sweep
    gives each setting's)."""
    effects, explicit = inputs.check.effects, inputs.check.loads.get(name)
    part = PARTS[name]
    bar = part.bar
    model = LoadModel(
        part=name,
        bar=bar,
        sources=part.sources,
        factor=inputs.check.factor,
        gravity="gravity" in effects,
        rail_inertia="rail-inertia" in effects and bar is not None and explicit is None,
        explicit=explicit,
        density=density,
    )
    if inputs.check.support == "free-body" and part.free_plate is not None and explicit is None:
        return free_plate_model(inputs, model, part.free_plate, inertia)
    if inputs.check.support == "free-body" and part.foundation is not None:
        return dataclasses.replace(model, foundation=part.foundation)
    if not (inputs.check.support == "free-body" and part.free_body is not None and explicit is None):
        return model
    assert bar is not None  # a free body is a rail: it has a bar
    if bar_length is None:
        bar_length = inputs.linkage_spec.linkage.lengths[bar]
    kind = kind or inputs.linkage_spec.linkage.kind
    masses, fb = inputs.masses, part.free_body
    return dataclasses.replace(
        model,
        rail_inertia=False,
        free_body=fb,
        inertia="inertia" in inputs.effects if inertia is None else inertia,
        joint_masses=(carried_mass(masses, kind, bar, fb.near.joint), carried_mass(masses, kind, bar, fb.far.joint)),
        rail_mass=masses.rail_mass_per_m * rail_length(bar),
        bar_length=bar_length,
        rail_body=rail_body(masses, bar, geo_pivot(inputs)),
        weight=rail_weight(inputs.masses, inputs.geometry, bar, kind) if inputs.plane == "horizontal" else None,
    )


def rail_weight(masses: massmodel.MassModel, geometry: dict[str, float], bar: str, kind: str) -> RailWeight:
    """What ``bar``'s rail needs for its out-of-plane weight (:mod:`railcheck.loads.weight`),
    from the one mass model: the rails' masses and centres of mass, the point masses each
    bar carries at its joints (:data:`railcheck.kinematics.massmodel.CARRIED`) and the
    clamp's length, the rail's hole pitch. ``geometry``: the catalogue overrides (m)."""
    rod, coupler = massmodel.rail_body(masses, bar, []), massmodel.rail_body(masses, "coupler", [])
    carried = {b: {j: carried_mass(masses, kind, b, j) for j in joints} for b, joints in massmodel.CARRIED[kind].items()}
    pitch = float(with_overrides(geometry)[0].hole_pitch)
    return RailWeight(bar, rod.mass, rod.com, carried, (coupler.mass, coupler.com), pitch)


def geo_pivot(inputs: PartsInput) -> float:
    """x (m, part frame) of a rail's first joint: midway between its first two holes."""
    rail = with_overrides(inputs.geometry)[0]
    return float(rail.end_distance + 0.5 * rail.hole_pitch)


def rail_body(masses, bar: str, pivot: float) -> tuple[float, float]:
    """The dynamics' rail of ``bar`` (:func:`railcheck.kinematics.massmodel.rail_body`, no
    point masses) in the part frame: (x of its centre of mass m, its moment of inertia
    about it kg m^2); its first joint sits at ``pivot`` m."""
    rod = massmodel.rail_body(masses, bar, [])
    return pivot + rod.com, rod.inertia_com


def free_plate_model(inputs: PartsInput, model: LoadModel, plate: FreePlate, inertia: bool | None) -> LoadModel:
    """A joint plate's free-body load model: its mass from the mass model, its centre of
    mass and polar moment about the seat from its outline (holes cut through)."""
    mass = getattr(inputs.masses, plate.mass)
    spec = with_overrides(inputs.geometry)[1]
    centroid, polar = plate_planar_inertia(spec)
    return dataclasses.replace(
        model,
        rail_inertia=False,
        free_plate=plate,
        inertia="inertia" in inputs.effects if inertia is None else inertia,
        plate=(mass, centroid - spec.seat_x, mass * polar),
    )


def unit_cases(model: LoadModel, geo, holes: list[str]) -> dict:
    """The part's unit load cases, named (see the module doc); a free body's joint forces
    as pins' bearing pressures (:func:`with_pin_pressure`)."""
    if model.is_free_body:
        return with_pin_pressure(free_body_cases(model, geo, holes))
    if model.is_free_plate:
        return with_pin_pressure(free_plate_cases(model, geo, holes))
    if model.is_on_foundation:
        clamped = unit_cases(dataclasses.replace(model, foundation=None), geo, holes)
        assert model.foundation is not None  # is_on_foundation
        return {n: FoundationCase(c, model.foundation) for n, c in with_pin_pressure(clamped).items()}
    cases: dict[str, object] = {"bolt_x": TractionCase(tuple(holes), 0), "bolt_y": TractionCase(tuple(holes), 1)}
    if model.gravity or model.rail_inertia:
        cases.update(body_x=BodyCase("uniform", 0), body_y=BodyCase("uniform", 1))
    if model.rail_inertia:
        pivot = (pivot_x(geo.get("hole_x")), 0.0)
        cases.update(body_rot=BodyCase("rotational", pivot=pivot), body_rad=BodyCase("radial", pivot=pivot))
    return cases


def with_pin_pressure(cases: dict, harmonics: tuple[int, ...] = HARMONICS) -> dict:
    """The cases with every in-plane joint force carried as a pin bears on its hole (a
    cosine pressure over the loaded half of the bore, :mod:`railcheck.fea.pin_pressure`):
    the force cases spread as the k = 1 radial pressure, then per loaded hole its
    self-equilibrated harmonics ``pressure_<field>:<hole>`` (coefficients from
    :func:`pin_pressure_columns`)."""
    out = {n: dataclasses.replace(c, pressure=True) if _in_plane_force(c) else c for n, c in cases.items()}
    for hole in _loaded_holes(out):
        out.update({f"pressure_{f}:{hole}": PressureCase(hole, f, harmonics) for f in harmonic_names(harmonics)})
    return out


def _in_plane_force(case) -> bool:
    return isinstance(case, CoupleCase) or (isinstance(case, TractionCase) and case.direction in (0, 1))


def _loaded_holes(cases: dict) -> list[str]:
    """The holes the cases' pin pressures load, in the order they first appear."""
    seen: dict[str, None] = {}
    for c in cases.values():
        if isinstance(c, (TractionCase, CoupleCase)) and c.pressure:
            seen.update(dict.fromkeys(c.groups))
    return list(seen)


@dataclass(frozen=True)
class PinPressureMap:
    """How a case list's pin-pressure coefficients follow from its force coefficients:
    the first ``linear`` columns are the force cases' (and the body cases'); ``holes``
    (h, linear, 2) N per unit coefficient: each loaded hole's in-plane force; the
    ``harmonics`` of every hole's pressure columns, which follow hole by hole."""

    linear: int
    holes: np.ndarray
    harmonics: tuple[int, ...]

    def extend(self, C: np.ndarray) -> np.ndarray:
        """(..., linear + h m): the coefficients ``C`` (..., linear) with every hole's
        pressure harmonics appended (:func:`railcheck.loads.pin_pressure.harmonic_coefficients`)."""
        if self.holes.shape[0] == 0:
            return C
        h = self.holes.shape[0]
        # one matrix product (einsum's generic loop took 4.4 of a whole rig's 117 s)
        forces = (C @ self.holes.transpose(1, 0, 2).reshape(self.linear, 2 * h)).reshape(C.shape[:-1] + (h, 2))
        extra = harmonic_coefficients(forces, self.harmonics)  # (..., h, m)
        return np.concatenate([C, extra.reshape(extra.shape[:-2] + (-1,))], axis=-1)


def pin_pressure_map(cases: dict) -> PinPressureMap:
    """The :class:`PinPressureMap` of a case list (:func:`with_pin_pressure`'s order)."""
    unwrapped = [c.case if isinstance(c, FoundationCase) else c for c in cases.values()]
    linear = [c for c in unwrapped if not isinstance(c, PressureCase)]
    pressure = [c for c in unwrapped if isinstance(c, PressureCase)]
    holes = list(dict.fromkeys(c.group for c in pressure))
    H = np.zeros((len(holes), len(linear), 2))
    for j, c in enumerate(linear):
        if isinstance(c, TractionCase) and c.pressure:
            weights = c.weights or (1.0 / len(c.groups),) * len(c.groups)
            for g, w in zip(c.groups, weights):
                H[holes.index(g), j, c.direction] += w
        elif isinstance(c, CoupleCase) and c.pressure:
            H[holes.index(c.groups[0]), j, 1] -= 1.0 / c.arm
            H[holes.index(c.groups[1]), j, 1] += 1.0 / c.arm
    return PinPressureMap(len(linear), H, pressure[0].harmonics if pressure else ())


def pin_pressure_columns(cases: dict, C: np.ndarray) -> np.ndarray:
    """(..., len(cases)): force coefficients ``C`` (..., linear) completed with the pin
    pressures' harmonic coefficients (:class:`PinPressureMap`); unchanged without them."""
    return pin_pressure_map(cases).extend(C)


def with_pressure_histories(cases: dict, histories: tuple[SourceHistory, ...]) -> tuple[SourceHistory, ...]:
    """The histories with the pin pressures' harmonic coefficients appended (one column
    per unit case of ``cases``, :func:`pin_pressure_columns`)."""
    return tuple(dataclasses.replace(h, C=pin_pressure_columns(cases, h.C)) for h in histories)


def free_body_cases(model: LoadModel, geo, holes: list[str]) -> dict:
    """A free rail's unit cases (module doc): first-hole pin, motor couple, far bolts, body."""
    xs = geo.get("hole_x")
    near = ("hole_0", "hole_1")  # the upper plate's two screws, the joint midway between them
    cases: dict = {"pin_x": TractionCase(near, 0), "pin_y": TractionCase(near, 1)}
    assert model.free_body is not None  # a free rail's cases
    if model.free_body.motor:
        cases["torque"] = CoupleCase(("hole_0", "hole_1"), float(xs[1] - xs[0]))
    cases.update(bolt_x=TractionCase(tuple(holes), 0), bolt_y=TractionCase(tuple(holes), 1, lever_rule(geo, holes, model)))
    if model.gravity or model.inertia:
        cases.update(body_x=BodyCase("uniform", 0), body_y=BodyCase("uniform", 1))
    if model.inertia:
        pivot = (pivot_x(xs), 0.0)
        cases.update(body_rot=BodyCase("rotational", pivot=pivot), body_rad=BodyCase("radial", pivot=pivot))
    if model.weight is not None:
        cases.update(weight_cases(model, geo, holes))
    return cases


def weight_cases(model: LoadModel, geo, holes: list[str]) -> dict:
    """A table-top rig's rail, out of plane (:mod:`railcheck.loads.weight`): its weight
    (``body_z``, carrying the dynamics' rail mass), the z forces at the first joint
    (``pin_z``: on a cantilevered bar its first screw, on a link both screws), at a
    cantilevered bar's second screw (``drive_z``) and at the far joint's bolts, shared so
    that it acts at the joint (``bolt_z``)."""
    assert model.weight is not None  # a rail's out-of-plane weight
    cantilevered = model.weight.bar in CANTILEVERED
    cases: dict = {
        "body_z": BodyCase("uniform", 2),
        "pin_z": TractionCase(("hole_0",) if cantilevered else ("hole_0", "hole_1"), 2),
    }
    if cantilevered:
        cases["drive_z"] = TractionCase(("hole_1",), 2)
    cases["bolt_z"] = TractionCase(tuple(holes), 2, lever_rule(geo, holes, model))
    return cases


def weight_cases_names(model: LoadModel) -> tuple[str, ...]:
    """The names of :func:`weight_cases`, in order (the last columns of a free rail's cases)."""
    assert model.weight is not None  # a rail's out-of-plane weight
    drive = ("drive_z",) if model.weight.bar in CANTILEVERED else ()
    return ("body_z", "pin_z", *drive, "bolt_z")


def weight_columns(model: LoadModel, lengths: dict, shape: tuple) -> np.ndarray:
    """(*shape, k): the coefficients of :func:`weight_cases`, constant over the cycle:
    the load factor times -g (body, m/s^2) and the joints' z forces (N); ``lengths`` bar ->
    m, scalars or arrays broadcasting to ``shape`` (a sweep's settings)."""
    assert model.weight is not None  # a rail's out-of-plane weight
    near, drive, far = (np.asarray(v, float) for v in joint_forces(model.weight, lengths))
    cols = [np.full(near.shape, -GRAVITY), near] + ([drive] if model.weight.bar in CANTILEVERED else []) + [far]
    return model.factor * np.broadcast_to(np.stack(np.broadcast_arrays(*cols), axis=-1), (*shape, len(cols)))


def free_plate_cases(model: LoadModel, geo, holes: list[str]) -> dict:
    """A free joint plate's unit cases: the pin's force on the seat (``seat_x``,
    ``seat_y``); the bolts' force, transverse shared so it acts at the seat (``bolt_x``,
    ``bolt_y``) plus a couple over the two bolts (``bolt_couple``, 1 N m) carrying the
    moment of the plate's own inertia about the seat; its body cases about the seat."""
    seat = float(geo.get("seat_x"))
    x1, x2 = (float(x) for x in geo.get("bolt_x"))
    assert model.free_plate is not None  # a free plate's cases
    seat_group = model.free_plate.seat
    cases: dict = {"seat_x": TractionCase((seat_group,), 0), "seat_y": TractionCase((seat_group,), 1)}
    shares = ((x2 - seat) / (x2 - x1), (seat - x1) / (x2 - x1))
    cases.update(
        bolt_x=TractionCase(tuple(holes), 0),
        bolt_y=TractionCase(tuple(holes), 1, shares),
        bolt_couple=CoupleCase((holes[0], holes[1]), x2 - x1),
    )
    if model.gravity or model.inertia:
        cases.update(body_x=BodyCase("uniform", 0), body_y=BodyCase("uniform", 1))
    if model.inertia:
        cases.update(body_rot=BodyCase("rotational", pivot=(seat, 0.0)), body_rad=BodyCase("radial", pivot=(seat, 0.0)))
    return cases


def free_plate_coefficients(
    model: LoadModel, src: LoadSource, reactions: dict, angles: dict, accelerations: dict, omega: dict, alpha: dict
) -> np.ndarray:
    """(..., k): a free plate's coefficients at one joint, in the order of
    :func:`free_plate_cases` (arrays as :func:`source_coefficients`). The pin's force
    ``sign`` x the reaction on the seat; the plate moves with ``src.axes_bar`` (its
    acceleration field about the seat: the joint's acceleration, the bar's omega and
    alpha); the bolts carry what balances the pin force and the plate's d'Alembert force
    and weight W (force -(P + W), moment -M_W about the seat): one load factor on all."""
    f, bar = model.factor, src.axes_bar
    angle = angles[bar]
    pin = f * to_rail_axes(src.sign * reactions[src.joint], angle)
    zero = np.zeros(pin.shape[:-1])
    bx = by = rot = rad = zero
    if model.gravity:
        g = gravity_history(angle, 1.0, GRAVITY)
        bx, by = f * g[..., 0], f * g[..., 1]
    if model.inertia:
        rigid = f * rail_inertia_history(accelerations[src.joint], angle, omega[bar], alpha[bar], 1.0)
        bx, by, rot, rad = bx + rigid[..., 0], by + rigid[..., 1], rigid[..., 2], rigid[..., 3]
    mass, d, polar = model.plate
    w_x, w_y = mass * (bx + rad * d), mass * (by + rot * d)
    moment = mass * d * by + rot * polar
    cols = [pin[..., 0], pin[..., 1], -(pin[..., 0] + w_x), -(pin[..., 1] + w_y), -moment]
    if model.gravity or model.inertia:
        cols += [bx, by]
    if model.inertia:
        cols += [rot, rad]
    return np.stack(np.broadcast_arrays(*cols), axis=-1)


def lever_rule(geo, holes: list[str], model: LoadModel) -> tuple[float, ...]:
    """The shares of a transverse joint force over the two bolt holes of the joint's plate
    that keep its line of action at the joint (x = the pivot + bar length): the plate
    is in equilibrium, so the bolts carry the force and no moment about the joint."""
    xs = geo.get("hole_x")
    x1, x2 = (float(xs[int(h.split("_")[1])]) for h in holes)
    joint = pivot_x(xs) + model.bar_length
    return ((x2 - joint) / (x2 - x1), (joint - x1) / (x2 - x1))


def free_body_coefficients(
    model: LoadModel,
    reactions: dict,
    torque,
    angles: dict,
    accelerations: dict,
    omega: dict,
    alpha: dict,
    lengths: dict | None = None,
) -> np.ndarray:
    """(..., k): a free rail's coefficients in the order of :func:`free_body_cases` (module
    doc), arrays as :func:`source_coefficients`; ``torque`` (...) N m the motor's on the crank;
    ``lengths`` bar -> m (broadcasting to ``...``) for a table-top rig's weight."""
    fb, bar, f = model.free_body, model.bar, model.factor
    assert fb is not None and bar is not None  # a free rail's coefficients
    angle = angles[bar]
    down = np.array([0.0, -GRAVITY]) if model.gravity else np.zeros(2)

    def joint_force(joint, mass):
        """The joint's force on the rail (N): the pin's reaction and the point mass carried
        there, its weight and, with inertia, its d'Alembert force -m a."""
        force = joint.sign * reactions[joint.joint]
        if not mass:
            return force
        return force + mass * (down - accelerations[joint.joint] if model.inertia else down)

    cols = [f * to_rail_axes(joint_force(fb.near, model.joint_masses[0]), angle)]
    if fb.motor:
        cols.append(f * np.asarray(torque)[..., None])
    cols.append(f * to_rail_axes(joint_force(fb.far, model.joint_masses[1]), angle))
    if model.gravity or model.inertia:
        body = gravity_history(angle, 1.0, GRAVITY) if model.gravity else np.zeros(angle.shape + (2,))
        if model.inertia:
            rigid = rail_inertia_history(accelerations[PIVOT_JOINT[bar]], angle, omega[bar], alpha[bar], 1.0)
            body = body + rigid[..., :2]
        cols.append(f * body)
        if model.inertia:
            cols.append(f * rigid[..., 2:])
    if model.weight is not None:
        assert lengths is not None  # the out-of-plane weight follows the bar lengths
        cols.append(weight_columns(model, lengths, angle.shape))
    return np.concatenate(cols, axis=-1)


def linkage_lengths(linkage) -> dict:
    """bar -> m: a linkage's crank, coupler and (a four-bar's) rocker."""
    return {bar: float(getattr(linkage, bar, 0.0)) for bar in ("crank", "coupler", "rocker")}


def source_coefficients(
    model: LoadModel, src: LoadSource, reactions: dict, angles: dict, accelerations: dict, omega: dict, alpha: dict
) -> np.ndarray:
    """(..., k): one load source's coefficients in the order of :func:`unit_cases`, for
    arrays with any leading dimensions (one setting's steps, or settings x steps):
    ``reactions`` and ``accelerations`` joint -> (..., 2) ground frame (N, m/s^2);
    ``angles``, ``omega``, ``alpha`` bar -> (...) (rad, rad/s, rad/s^2)."""
    if model.is_free_plate:
        return free_plate_coefficients(model, src, reactions, angles, accelerations, omega, alpha)
    force = src.sign * reactions[src.joint]
    angle = angles[src.axes_bar] if src.axes_bar else np.zeros(force.shape[:-1])
    cols = [bolt_history(force, angle, model.factor)]
    if model.gravity or model.rail_inertia:
        cols.append(gravity_history(angle, model.density, GRAVITY) if model.gravity else np.zeros(force.shape))
    if model.rail_inertia:
        bar = model.bar
        assert bar is not None  # a rail's own inertia follows its bar
        rigid = rail_inertia_history(accelerations[PIVOT_JOINT[bar]], angle, omega[bar], alpha[bar], model.density)
        cols[-1] = cols[-1] + rigid[..., :2]
        cols.append(rigid[..., 2:])
    return np.concatenate(cols, axis=-1)


def source_histories(model: LoadModel, kin: KinematicsResult | None, holes: list[str]) -> tuple[SourceHistory, ...]:
    """The coefficient history of every load source of the part, columns in the order
    of :func:`unit_cases` (``kin`` may be None for explicit loads)."""
    if model.explicit is not None:
        load = model.explicit
        c = [len(holes) * load.longitudinal, len(holes) * load.transverse]
        if model.gravity:
            c += list(gravity_history(np.zeros(1), model.density, GRAVITY)[0])
        return (SourceHistory("explicit", np.array([c]), np.zeros(1), 0),)
    assert kin is not None  # the linkage's loads need its kinematics
    dyn, motion = kin.dynamics, kin.motion
    by_bar = lambda a: {bar: a[:, i] for bar, i in BAR_INDEX.items()}  # noqa: E731
    if model.is_free_body:
        assert model.free_body is not None  # is_free_body
        far = model.free_body.far.joint
        C = free_body_coefficients(
            model,
            dyn.reactions,
            dyn.torque,
            by_bar(motion.theta),
            motion.accelerations,
            by_bar(motion.omega),
            by_bar(motion.alpha),
            linkage_lengths(motion.linkage),
        )
        step = int(np.argmax(np.hypot(dyn.reactions[far][:, 0], dyn.reactions[far][:, 1])))
        return (SourceHistory(far, C, motion.theta2, step),)
    out = []
    for src in model.sources:
        if src.joint not in dyn.reactions:
            continue
        C = source_coefficients(
            model, src, dyn.reactions, by_bar(motion.theta), motion.accelerations, by_bar(motion.omega), by_bar(motion.alpha)
        )
        force = dyn.reactions[src.joint]
        out.append(SourceHistory(src.joint, C, motion.theta2, int(np.argmax(np.hypot(force[:, 0], force[:, 1])))))
    return tuple(out)
