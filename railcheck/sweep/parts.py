"""Each checked part of a sweep, prepared once: its mesh, one factorisation, the unit
cases of every bolt-hole pair its joint can use, and the screens
(:mod:`railcheck.fea.screening`) that give any setting's cycle peak, fatigue factor and tip
deflection by superposition.

The unit cases and their column order are those of ``railcheck check``
(:func:`railcheck.model.cycle.unit_cases`), so a setting's result equals a check of that setting
with ``bolt_position = "actual"`` and the same mesh.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from railcheck import environment
from railcheck.fea.fatigue import endurance_limit
from railcheck.fea.screening import fatigue_min, make_screens, tip_peak, von_mises_peak
from railcheck.fea.store import UnitRequest, is_stored
from railcheck.geometry.mesher import cached_mesh, mesh_part
from railcheck.geometry.models import PartGeometry
from railcheck.loads.cases import pivot_x, rail_bolt_holes
from railcheck.model.certificate import rail_lowest_hz
from railcheck.model.inputs import PartsInput
from railcheck.model.jobs import carried_masses, free_body_cases, mesh_sizes
from railcheck.model.loading import LoadModel, load_model, pin_pressure_map, source_histories, unit_cases
from railcheck.model.setting_free import pair_deflections, solve_projected, stored_request
from railcheck.model.utilisation import Limits
from railcheck.parts import PARTS, geometry_of, kind_of
from railcheck.specs import CheckSpec
from railcheck.sweep.inputs import SweepInput


@dataclass(frozen=True)
class PartModel:
    """A part ready for superposition. ``screens``: hole-pair key -> Screen (rails: the
    pair ``(i, j)`` of hole indices; other parts: None). ``pair_of``: bar length in um ->
    pair key (rails). ``constant``: for a part with explicit [loads], its (stress Pa,
    fatigue factor, tip m), the same for every setting. Limits SI; ``required`` the
    fatigue factor a part needs; ``deflection_limit`` m or None."""

    name: str
    bar: str | None
    screens: dict
    pair_of: dict
    limit: float
    endurance: float
    ultimate: float
    criterion: str
    yield_strength: float
    required: float
    deflection_limit: float | None
    dofs: int
    loads: LoadModel
    constant: tuple | None = None
    dynamic: dict | None = None  # hole-pair key -> PairModes (effect ``dynamic``)
    damping: float = 0.0
    max_amplification: float = math.inf
    pressure: dict | None = None  # hole-pair key -> PinPressureMap (free bodies: pins bear on their holes)
    lowest_hz: dict | None = None  # hole-pair key -> the certificate's lowest frequency (Hz), without ``dynamic``
    case_names: dict | None = None  # hole-pair key -> its unit cases' names, in its columns' order
    length: float = 0.0  # m: the part's length (small displacements' limit; 0: none)

    @property
    def certified(self) -> bool:
        """Whether the part's quasi-static results carry the certificate's estimate
        (:mod:`railcheck.model.certificate`) instead of a dynamic response."""
        return self.lowest_hz is not None and self.dynamic is None

    @property
    def limits(self) -> Limits:
        """What this part is judged against (:class:`~railcheck.model.utilisation.Limits`):
        the dynamic limit with a dynamic response; the certificate's criterion for a
        certified part whose loads vary with the setting."""
        return Limits(
            stress=self.limit,
            fatigue_required=self.required,
            deflection=self.deflection_limit or None,
            yield_strength=self.yield_strength,
            length=self.length,
            max_amplification=None if self.dynamic is None else self.max_amplification,
            certified=self.certified and self.constant is None,
        )

    def key_for(self, length: float | None):
        """The hole-pair key a bar of ``length`` m uses (rails), else None."""
        return None if self.bar is None else self.pair_of[micrometres(length)]

    def with_pin_pressure(self, length: float | None, C: np.ndarray) -> np.ndarray:
        """Force coefficients ``C`` (..., k) completed with the pin pressures' harmonics of
        the hole pair a bar of ``length`` m uses (:class:`~railcheck.model.loading.PinPressureMap`)."""
        if self.pressure is None:
            return C
        return self.pressure[None if self.bar is None else self.pair_of[micrometres(length)]].extend(C)

    def modes_for(self, length: float):
        """The :class:`PairModes` of the hole pair a bar of ``length`` m uses (like
        :meth:`screen_for`), or None without a dynamic response."""
        if self.dynamic is None:
            return None
        return self.dynamic[None] if self.bar is None else self.dynamic[self.pair_of[micrometres(length)]]

    def screen_for(self, length: float):
        """The screen of the hole pair a bar of ``length`` m uses (rails), else the only one."""
        if self.bar is None:
            return self.screens[None]
        return self.screens[self.pair_of[micrometres(length)]]


@dataclass(frozen=True)
class PairModes:
    """One hole pair's lowest modes (clamped part, its joints' carried masses lumped on
    the pair's holes): ``hz`` (m,), ``modal_loads`` (m, k) per unit coefficient of the
    pair's columns, and ``screen``: the pair's unit columns followed by the mode columns,
    so a history with the mode-acceleration correction appended reads the dynamic
    response (:mod:`railcheck.fea.dynamic`)."""

    hz: np.ndarray
    modal_loads: np.ndarray
    screen: object


def micrometres(length: float | None) -> int:
    """A bar length (m) as whole micrometres: the key of its hole pair (a part on no bar has none)."""
    if length is None:
        raise ValueError("a part on a bar needs the bar's length")
    return int(round(length * 1e6))


def applicable(check: CheckSpec, name: str, kind: str) -> bool:
    """Whether a part is checked in a linkage kind: explicit loads in [check] ``check``
    always; otherwise its joint and its bar must exist there (a slider-crank has no rocker
    and no O4)."""
    if name in check.loads:
        return True
    joints = {"four-bar": {"O2", "A", "B", "O4"}, "slider-crank": {"O2", "A", "B", "slider"}}[kind]
    bars = {"four-bar": {"crank", "coupler", "rocker"}, "slider-crank": {"crank", "coupler"}}[kind]
    srcs = [s for s in PARTS[name].sources if s.joint in joints and (s.axes_bar is None or s.axes_bar in bars)]
    return bool(srcs) and (PARTS[name].bar is None or PARTS[name].bar in bars)


def is_free_plate(check: CheckSpec, name: str) -> bool:
    """Whether the part is a joint plate checked as a free body (``support = "free-body"``,
    no explicit loads)."""
    return check.support == "free-body" and PARTS[name].free_plate is not None and name not in check.loads


def is_on_foundation(check: CheckSpec, name: str) -> bool:
    """Whether the part is a bolted-down part checked as a free body (``support =
    "free-body"``): its loads balanced by a rigid foundation's reaction on its base."""
    return check.support == "free-body" and PARTS[name].foundation is not None


def is_free_rail(check: CheckSpec, name: str) -> bool:
    """Whether the part is checked as a free body (``support = "free-body"``, a rail of
    the registry's free-body model, no explicit loads)."""
    return check.support == "free-body" and PARTS[name].free_body is not None and name not in check.loads


def hole_groups(check: CheckSpec, name: str, geo, lengths: np.ndarray) -> tuple[dict, dict]:
    """(key -> bolt-hole groups, length um -> key): a rail's pair ``(i, j)`` for every bar
    length in ``lengths`` (m; lengths off the rail are left out: their settings fail
    ``joints_on_rails``), and for a free rail ``(i, j, length um)`` (its plate's bolts share
    the joint force by the lever rule about the joint, which sits at the bar length); one
    key None with every hole for other parts."""

    kind = kind_of(name)
    if name in check.loads:
        holes = (
            kind.bolts(geo)
            if not kind.bolts_on_rail
            else [f"hole_{k}" for k in rail_bolt_holes(list(geo.get("hole_x")), 0, 0, "worst")]
        )
        return {None: holes}, {}
    if not kind.bolts_on_rail:
        return {None: kind.bolts(geo)}, {}
    xs = list(geo.get("hole_x"))
    groups, pair_of = {}, {}
    for length in np.unique(lengths):
        try:
            pair = tuple(rail_bolt_holes(xs, pivot_x(xs), float(length), "actual"))
        except ValueError:
            continue
        key = (*pair, micrometres(length)) if is_free_rail(check, name) else pair
        groups[key] = [f"hole_{k}" for k in pair]
        pair_of[micrometres(length)] = key
    return groups, pair_of


def build_part_model(
    inputs: SweepInput, name: str, lengths: np.ndarray, material, limit: float, report, linkage: str = "four-bar"
) -> PartModel:
    """Mesh, factorise and solve the unit cases of every hole pair of one part; screen
    them (``lengths``: the bar lengths, m, the sweep's settings give this part's bar;
    ``linkage``: its kind, which sets the point masses a rail's joints carry)."""

    parts = _parts_of(inputs)
    geo = geometry_of(name, parts.geometry)
    mesh = mesh_part(
        geo,
        *mesh_sizes(parts.mesh, geo.kind),
        optimize=parts.mesh.optimize,
        cache_dir=environment.cache_dir(),
        verbose=environment.gmsh_verbose(),
    )
    setup = _part_setup(inputs, name, geo, mesh, lengths, material, linkage)
    deflections = pair_deflections(setup.loads, geo) if setup.free else {}
    fields, meta, origin = solve_projected(setup.request, geo, deflections, "auto", report, environment.unit_store())
    if origin == "stored":
        report("unit fields: stored")
    elif origin != "solved":  # a damaged entry solved again, or one the store could not keep
        report(origin)
    return _part_model(inputs, name, setup, fields, meta, material, limit)


def part_is_stored(inputs: SweepInput, name: str, lengths: np.ndarray, material, linkage: str = "four-bar") -> bool:
    """Whether :func:`build_part_model` of these arguments would find the part's mesh in
    the cache and its unit fields in the store (on disk: reading verifies them), so that
    it neither meshes nor solves; a probe that never meshes."""
    store = environment.unit_store()
    if store is None:
        return False
    parts = _parts_of(inputs)
    geo = geometry_of(name, parts.geometry)
    mesh = cached_mesh(
        geo, *mesh_sizes(parts.mesh, geo.kind), optimize=parts.mesh.optimize, cache_dir=environment.cache_dir()
    )
    if mesh is None:
        return False
    setup = _part_setup(inputs, name, geo, mesh, lengths, material, linkage)
    deflections = pair_deflections(setup.loads, geo) if setup.free else {}
    return is_stored(stored_request(setup.request, geo, deflections), store)


@dataclass(frozen=True)
class _PartSetup:
    """What a part model derives from the scene and the mesh before its unit fields."""

    geo: PartGeometry
    free: bool
    plate: bool
    loads: LoadModel
    groups: dict
    pair_of: dict
    cases: dict
    columns: dict
    pressure: dict
    modes: object
    request: UnitRequest
    names: dict
    linkage: str
    deflections: dict  # hole-pair key -> a free body's deflection groups (its modal pins: the first two)


def _part_setup(inputs: SweepInput, name: str, geo, mesh, lengths: np.ndarray, material, linkage: str) -> _PartSetup:
    """The part's loads, hole groups, unit cases and store request (:func:`build_part_model`)."""
    kind, parts = kind_of(name), _parts_of(inputs)
    free, plate = is_free_rail(parts.check, name), is_free_plate(parts.check, name) or is_on_foundation(parts.check, name)
    inertia = "inertia" in inputs.requested_effects
    loads = load_model(parts, name, material.density, *((0.0, inertia, linkage) if free else ()))
    if plate:
        loads = load_model(parts, name, material.density, inertia=inertia)
    groups, pair_of = hole_groups(parts.check, name, geo, lengths)
    cases: dict[str, dict] = {}
    columns: dict[str, list] = {}
    deflections: dict[str, tuple | dict] = {}
    pressure: dict = {}
    names_of: dict = {}
    for key, holes in groups.items():
        names = []
        loads_key = dataclasses.replace(loads, bar_length=key[2] / 1e6) if free else loads
        key_cases = unit_cases(loads_key, geo, holes)
        pressure[key] = pin_pressure_map(key_cases)
        names_of[key] = list(key_cases)
        for case_name, case in key_cases.items():
            full = (
                f"{case_name}@{'-'.join(map(str, key))}" if key is not None and case_name.startswith("bolt") else case_name
            )
            cases.setdefault(full, case)
            names.append(full)
        columns[key] = [list(cases).index(n) for n in names]
        if free or plate:
            deflections[key] = free_body_cases(loads_key, geo, holes).deflection
    modes = mode_requests(inputs, name, groups, deflections, linkage)
    request = UnitRequest(
        mesh.points,
        mesh.tets,
        mesh.groups,
        material,
        [] if free or plate else [kind.support],
        cases,
        parts.mesh.order,
        kind.tip,
        0.0 if free or plate else kind.exclusion(geo),
        mesh.curved if parts.mesh.curved else None,
        dataclasses.replace(free_body_cases(loads, geo, next(iter(groups.values()))), deflection=_one_or_many(deflections))
        if free or plate
        else None,
        modes,
    )
    return _PartSetup(
        geo, free, plate, loads, groups, pair_of, cases, columns, pressure, modes, request, names_of, linkage, deflections
    )


def _one_or_many(deflections: dict):
    """A free part's deflection request: the one deflection of a part whose holes no
    setting moves (key None: a plate, the bracket), as a check asks for it, so the two
    share the stored fields; else one per hole-pair key."""
    return deflections[None] if set(deflections) == {None} else deflections


def _part_model(inputs: SweepInput, name: str, setup: _PartSetup, fields, meta, material, limit: float) -> PartModel:
    """The part model of its setup and unit fields: screens, modes, limits, and a
    constant-load part's own figures (:func:`build_part_model`)."""
    kind, geo = kind_of(name), setup.geo
    free, plate, loads, groups, pair_of = setup.free, setup.plate, setup.loads, setup.groups, setup.pair_of
    cases, columns, pressure, modes = setup.cases, setup.columns, setup.pressure, setup.modes
    screens = screens_of(fields, columns)
    parts = _parts_of(inputs)
    dynamic = pair_modes(fields, meta, columns, len(cases)) if modes and inputs.dynamic_response else None
    spec = parts.fatigue
    marin = endurance_limit(material.ultimate_strength, spec.surface, kind.section(geo), spec.load, spec.reliability)
    model = PartModel(
        name,
        PARTS[name].bar if name not in parts.check.loads else None,
        screens,
        pair_of,
        limit,
        marin.endurance_limit,
        material.ultimate_strength,
        spec.criterion,
        material.yield_strength,
        spec.min_safety,
        parts.check.max_deflection,
        meta.dofs,
        loads,
        dynamic=dynamic,
        damping=parts.dynamic.damping,
        max_amplification=parts.dynamic.max_amplification,
        pressure=pressure if free or plate else None,
        lowest_hz=None if dynamic is not None else certificate_frequencies(inputs, name, setup, meta, material),
        case_names=setup.names,
        length=geo.get("length"),
    )
    if name not in parts.check.loads:
        return model
    C = model.with_pin_pressure(None, source_histories(loads, None, groups[None])[0].C[None])
    scr = screens[None]
    constant = (
        float(von_mises_peak(scr, C)[0]),
        float(fatigue_min(scr, C, model.endurance, model.ultimate, model.criterion, model.yield_strength)[0]),
        float(tip_peak(scr, C)[0]),
    )
    return PartModel(**{**model.__dict__, "constant": constant})


def certificate_frequencies(inputs: SweepInput, name: str, setup: _PartSetup, meta, material) -> dict | None:
    """Hole-pair key -> the lowest frequency (Hz) the part's certificate reads: a rail's
    beam model per hole pair, any other part's lowest FE mode; None without a turning
    crank or for explicit loads."""
    parts = _parts_of(inputs)
    if not inputs.certifies or name in parts.check.loads:
        return None
    if not kind_of(name).beam_frequency:
        return {key: float(m.hz[0]) for key, m in meta.mode_sets.items()} if meta.mode_sets else None
    pins = setup.deflections
    clamp = None if setup.free else kind_of(name).support
    return {
        key: rail_lowest_hz(
            setup.geo,
            material,
            (tuple(pins[key][0]), tuple(pins[key][1])) if setup.free else None,
            carried_masses(parts, name, holes, setup.linkage),
            clamp,
        )
        for key, holes in setup.groups.items()
    }


def _parts_of(inputs: SweepInput) -> PartsInput:
    """The part stages' record of a sweep with parts to check."""
    if inputs.parts is None:
        raise ValueError("a sweep without [check] has no part models")
    return inputs.parts


def screens_of(fields, columns: dict) -> dict:
    """Hole-pair key -> the screen of its unit-case columns ``columns[key]`` in the part's
    ``fields`` (:func:`railcheck.fea.screening.screens.make_screens`, each key's own tip operator)."""
    return make_screens(fields.stress, fields.verdict_mask, {key: tip_of(fields, key) for key in columns}, columns)


def sharing_screens(model: PartModel, others) -> PartModel:
    """``model`` with each screen equal to one of ``others``' (PartModels of the same part
    for another linkage kind: the same unit fields, other joint masses) replaced by that
    one, so that its arrays are held once (the whole rig's crank and coupler rails, 0.86 GB
    of screens twice without it). Equal: the same key, stresses, forms, tip, scale and
    trial nodes; any other screen is kept as it is."""
    twins: dict = {}
    for other in others:
        if other.name == model.name and other is not model:
            twins |= {k: s for k, s in other.screens.items() if k in model.screens and equal_screens(s, model.screens[k])}
    if not twins:
        return model
    return dataclasses.replace(model, screens={k: twins.get(k, s) for k, s in model.screens.items()})


def equal_screens(a, b) -> bool:
    """Whether two screens hold the same arrays (values and shapes; None alike); the same
    screen at once (a model shared on arrival is shared again by :func:`prepare_models`'s
    pass without comparing its arrays a second time)."""
    if a is b:
        return True
    fields = ("stress", "forms", "tip", "scale", "angle", "trial")
    pairs = [(getattr(a, f), getattr(b, f)) for f in fields]
    return all((x is None) == (y is None) and (x is None or np.array_equal(x, y)) for x, y in pairs)


def tip_of(fields, key):
    """(3, k) m: the deflection operator's columns of a key (a free rail has one per key)."""
    return fields.tips[key] if fields.tips else fields.tip


def mode_requests(
    inputs: SweepInput, name: str, groups: dict, deflections: dict | None = None, kind: str = "four-bar"
) -> dict | None:
    """Hole-pair key -> (modes, pins, carried masses) for
    :func:`railcheck.fea.unitcases.solve_unit_cases`, or None: without ``dynamic``, and
    for a part with explicit loads (constant over the cycle: nothing to respond to)."""
    parts = _parts_of(inputs)
    certificate_modes = inputs.certifies and kind_of(name).bolts_on_rail is False
    if not (inputs.dynamic_response or certificate_modes) or name in parts.check.loads:
        return None
    held = PARTS[name].foundation is not None  # a bolted-down part: its modes held at its base
    pins = (
        {} if held else {key: (tuple(d[0]), tuple(d[1])) for key, d in (deflections or {}).items()}
    )  # a free rail's joints
    return {
        key: (parts.dynamic.modes, pins.get(key), carried_masses(parts, name, holes, kind)) for key, holes in groups.items()
    }


def pair_modes(fields, meta, columns: dict, n_cases: int) -> dict:
    """Hole-pair key -> :class:`PairModes` from a solve with one mode set per key (the
    mode columns follow the ``n_cases`` unit cases, key by key)."""
    with_modes, start = {}, n_cases
    for key, cols in columns.items():
        hz = meta.mode_sets[key].hz
        with_modes[key] = list(cols) + list(range(start, start + hz.size))
        start += hz.size
    screens = screens_of(fields, with_modes)
    return {
        key: PairModes(meta.mode_sets[key].hz, meta.mode_sets[key].modal_loads[:, cols], screens[key])
        for key, cols in columns.items()
    }
