"""Scene files: one TOML file states the mechanism, its speed, the effects to simulate,
the parts to check and the outputs wanted. Values with units are strings ("480 mm");
everything is converted to SI here, once. Unknown keys, bare numbers for dimensional
fields, missing fields and impossible values raise :class:`InputError` naming the field.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from dataclasses import dataclass
from functools import cached_property
from importlib import resources
from pathlib import Path
from typing import Any

from railcheck import parts as registry
from railcheck.base.errors import InputError, InputErrors
from railcheck.base.fields import boolean, number, refuse_unknown, require, string_choice, unknown_keys
from railcheck.components.overrides import component_spec
from railcheck.components.ratings import COMPONENT_SPEC, NOT_ON_SLIDER_CRANK, ComponentSpec
from railcheck.effects import EFFECTS, dynamic_response, rig_plane, simulated_effects  # noqa: F401  re-exported
from railcheck.fea.fatigue import CRITERIA, LOAD, RELIABILITY, SURFACE  # light module: numpy only
from railcheck.fea.materials import MATERIALS  # light module: no skfem import
from railcheck.geometry.catalogue import OVERRIDABLE, validate, with_overrides  # light module: no gmsh import
from railcheck.kinematics.linkage import FourBar, SliderCrank
from railcheck.kinematics.massmodel import MassModel
from railcheck.ranges import RANGES  # noqa: F401  RANGES re-exported
from railcheck.ranges import did_you_mean as _did_you_mean
from railcheck.ranges import in_range as _in_range
from railcheck.specs import (  # noqa: F401  the scene's records, re-exported
    DEFAULT_RELIABILITY,
    PLANES,
    SWEEP_KINDS,
    CheckSpec,
    DynamicSpec,
    ExplicitLoad,
    FatigueSpec,
    MechanismSpec,
    MeshSpec,
    OutputSpec,
    SweepSpec,
)
from railcheck.units import parse_quantity

BOLT_POSITIONS = ("worst", "actual")
SUPPORTS = ("clamped", "free-body")
COMPARISONS = ("2013",)  # [check] compare: the 2013 clamped model beside each free rail
SWEEP_BARS = {"four-bar": ("crank", "coupler", "rocker", "ground"), "slider-crank": ("crank", "coupler", "offset")}
SWEEP_FORMATS = ("parquet", "csv")
FORMULATIONS = ("newton-euler", "seed-2013")
DEFAULT_SCENE = "default.toml"


@dataclass(frozen=True)
class Scene:
    """A parsed scene, SI inside. ``raw`` is the TOML as read (for the summary)."""

    mechanism: MechanismSpec | None
    formulation: str
    check: CheckSpec | None
    mesh: MeshSpec
    output: OutputSpec
    geometry: dict[str, float]
    raw: dict[str, Any]
    source: str
    fatigue: FatigueSpec = FatigueSpec()
    sweep: SweepSpec = SweepSpec()
    dynamic: DynamicSpec = DynamicSpec()
    components: ComponentSpec = COMPONENT_SPEC  # the joints' components' dimensions and ratings

    @cached_property
    def masses(self) -> MassModel:
        """The run's one mass model (:func:`railcheck.parts.mass_model`), resolved once."""
        return registry.mass_model(self.formulation, self.geometry)

    @property
    def requested_effects(self) -> tuple[str, ...]:
        """[check] effects as listed (without a [check]: inertia)."""
        return self.check.effects if self.check else ("inertia",)

    @property
    def check_speeds(self) -> tuple[float, ...]:
        """The crank speeds (rad/s) a check runs at: [mechanism]'s, none without one."""
        return (self.mechanism.speed,) if self.mechanism else ()

    @cached_property
    def effects(self) -> tuple[str, ...]:
        """The loads a check simulates (:func:`simulated_effects` at :attr:`check_speeds`)."""
        return simulated_effects(self.requested_effects, self.check_speeds)

    @cached_property
    def sweep_effects(self) -> tuple[str, ...]:
        """The loads a sweep simulates (:func:`simulated_effects` at [sweep]'s own speeds)."""
        return simulated_effects(self.requested_effects, self.sweep.speeds)

    @property
    def dynamic_response(self) -> bool:
        """Whether a check computes the dynamic response (:func:`dynamic_response`)."""
        return dynamic_response(self.requested_effects, self.check_speeds)

    @property
    def sweep_dynamic_response(self) -> bool:
        """Whether a sweep computes the dynamic response, at [sweep]'s speeds."""
        return dynamic_response(self.requested_effects, self.sweep.speeds)

    @property
    def plane(self) -> str:
        """The rig's plane (:data:`railcheck.specs.PLANES`): [mechanism]'s, or without one
        "vertical" when [check] effects lists "gravity", else "horizontal"."""
        return rig_plane(self.mechanism.plane if self.mechanism else None, self.check.effects if self.check else ())

    @property
    def checked(self) -> CheckSpec:
        """[check], for the stages that run only when the scene has one (an InputError
        naming it otherwise)."""
        if self.check is None:
            raise InputError("check", "the scene has no [check] table")
        return self.check

    @property
    def linkage_spec(self) -> MechanismSpec:
        """[mechanism], for the stages that run only when the scene has one (an InputError
        naming it otherwise)."""
        if self.mechanism is None:
            raise InputError("mechanism", "the scene has no [mechanism] table")
        return self.mechanism


ALLOWED_KEYS: dict[str, set[str] | None] = {
    "mechanism": {"kind", "crank", "coupler", "rocker", "ground", "speed", "steps", "assembly", "plane"},
    "dynamics": {"formulation"},
    "check": {"parts", "factor", "bolt_position", "material", "limit", "effects", "max_deflection", "support", "compare"},
    "mesh": {"order", "size", "hole_size", "optimize", "curved"},
    "output": {"dir", "vtk", "png", "plots", "stress_scale"},
    "loads": None,  # part names, checked below
    "geometry": None,  # catalogue keys, checked below
    "components": None,  # the components' dimensions and ratings, checked below
    "fatigue": {"surface", "reliability", "load", "criterion", "min_safety"},
    "dynamic": {"damping", "max_amplification", "modes"},
    "sweep": {
        "kind",
        "crank",
        "coupler",
        "rocker",
        "ground",
        "offset",
        "speeds",
        "steps",
        "assembly",
        "settings",
        "memory",
        "format",
    },
}


def _mechanism(table: dict) -> MechanismSpec:
    p = "mechanism."
    refuse_unknown(table, ALLOWED_KEYS["mechanism"], p)
    _not_planar(table)
    kind = string_choice(require(table, "kind", p), ("four-bar", "slider-crank"), p + "kind")
    length = lambda key: _in_range(
        parse_quantity(
            require(table, key, p),
            "length",
            p + key,  # noqa: E731
            positive=True,
            allow_zero=False,
        ),
        "length",
        p + key,
    )
    speed = _in_range(
        parse_quantity(table.get("speed", "1 Hz"), "angular_speed", p + "speed", positive=True), "speed", p + "speed"
    )
    steps = table.get("steps", 5000)
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 3:
        raise InputError(p + "steps", f"must be a whole number >= 3, got {steps!r}")
    if steps > 10_000_000:
        raise InputError(p + "steps", f"{steps} steps is more than this tool runs (10 000 000 at most)")
    assembly = string_choice(table.get("assembly", "open"), ("open", "crossed"), p + "assembly")
    if kind == "four-bar":
        linkage: FourBar | SliderCrank = FourBar(
            length("crank"), length("coupler"), length("rocker"), length("ground"), assembly
        )
    else:
        if "rocker" in table:
            raise InputError(p + "rocker", "a slider-crank has no rocker (remove the key)")
        offset = parse_quantity(table.get("ground", "0 mm"), "length", p + "ground")
        if offset != 0:
            _in_range(offset, "length", p + "ground", magnitude=True)
        linkage = SliderCrank(length("crank"), length("coupler"), offset, assembly)
    return MechanismSpec(linkage, speed, steps)


def _not_planar(table: Any) -> None:
    """A planar mechanism scene is not a rig scene: one line pointing to its command."""
    if isinstance(table, dict) and table.get("kind") == "planar":
        raise InputError(
            "mechanism.kind",
            '"planar" is a mechanism study: run `railcheck mechanism FILE` (a check takes "four-bar" or "slider-crank")',
        )


def _oriented(mechanism: MechanismSpec, check: CheckSpec | None, plane: Any) -> tuple[MechanismSpec, CheckSpec | None]:
    """The rig's plane (:data:`PLANES`): "vertical" when [check] effects lists "gravity"
    (the weight in the mechanism's plane), else "horizontal" (the table-top rig, its weight
    out of plane, always applied), unless the scene says; a vertical rig's weight is the
    ``gravity`` effect, always on."""
    gravity = check is not None and "gravity" in check.effects
    if plane is None:
        plane = "vertical" if gravity else "horizontal"
    plane = string_choice(plane, PLANES, "mechanism.plane")
    if plane == "horizontal" and gravity:
        raise InputError(
            "check.effects",
            '"gravity" is the weight in the mechanism\'s plane (a vertical rig); with [mechanism] plane = '
            '"horizontal" the weight acts out of plane and is always applied: remove "gravity" or set plane = "vertical"',
        )
    if plane == "vertical" and check is not None and not gravity:
        check = dataclasses.replace(check, effects=check.effects + ("gravity",))
    return dataclasses.replace(mechanism, plane=plane), check


def _check(table: dict, loads_table: dict, formulation: str = "newton-euler") -> CheckSpec:
    p = "check."
    refuse_unknown(table, ALLOWED_KEYS["check"], p)
    known = tuple(registry.PARTS)
    listed = table.get("parts", list(known))
    if not isinstance(listed, list) or not listed or not all(isinstance(x, str) for x in listed):
        raise InputError(p + "parts", f"must be a non-empty list of part names ({', '.join(known)})")
    for name in listed:
        if name not in known and name not in registry.COMPONENTS:
            raise InputError(p + "parts", f"unknown part {name!r}{_did_you_mean(name, (*known, *registry.COMPONENTS))}")
    if len(set(listed)) != len(listed):
        raise InputError(p + "parts", "lists a part twice")
    parts = [n for n in listed if n in known]
    components = tuple(n for n in listed if n in registry.COMPONENTS)
    factor = table.get("factor", 1.4)
    if isinstance(factor, bool) or not isinstance(factor, (int, float)) or not math.isfinite(factor) or factor <= 0:
        raise InputError(p + "factor", f"must be a positive number (a dimensionless load factor), got {factor!r}")
    _in_range(float(factor), "factor", p + "factor")
    bolt = string_choice(table.get("bolt_position", "worst"), BOLT_POSITIONS, p + "bolt_position")
    material = table.get("material", "steel")
    if not isinstance(material, str):
        raise InputError(p + "material", f"must be a material name, got {material!r}")
    if material not in MATERIALS:
        raise InputError(p + "material", f"unknown material {material!r} (known: {', '.join(MATERIALS)})")
    limit = None
    if "limit" in table:
        limit = _in_range(
            parse_quantity(table["limit"], "stress", p + "limit", positive=True, allow_zero=False), "limit", p + "limit"
        )
    effects = _names(table.get("effects", ["inertia"]), EFFECTS, p + "effects", "effect", "; nothing else is simulated")
    compare = _names(table.get("compare", []), COMPARISONS, p + "compare", "comparison", "")
    loads: dict[str, ExplicitLoad] = {}
    for part, spec in loads_table.items():
        lp = f"loads.{part}."
        if part not in known:
            raise InputError(f"loads.{part}", f"unknown part (known: {', '.join(known)})")
        if part not in parts:
            raise InputError(f"loads.{part}", "explicit loads for a part that check.parts does not list")
        if not isinstance(spec, dict):
            raise InputError(f"loads.{part}", "must be a table with longitudinal and transverse forces per hole")
        refuse_unknown(spec, {"longitudinal", "transverse"}, lp)
        loads[part] = ExplicitLoad(
            *(
                _in_range(parse_quantity(spec.get(key, "0 N"), "force", lp + key), "force", lp + key, magnitude=True)
                for key in ("longitudinal", "transverse")
            )
        )
    max_deflection = None
    if "max_deflection" in table:
        max_deflection = _in_range(
            parse_quantity(table["max_deflection"], "length", p + "max_deflection", positive=True, allow_zero=False),
            "deflection",
            p + "max_deflection",
        )
    default_support = "clamped" if formulation == "seed-2013" else "free-body"  # seed-2013: the 2013 study's model
    support = string_choice(table.get("support", default_support), SUPPORTS, p + "support")
    return CheckSpec(
        tuple(parts), float(factor), bolt, material, limit, effects, loads, max_deflection, support, compare, components
    )


def _names(value: Any, choices: tuple[str, ...], name: str, what: str, note: str) -> tuple[str, ...]:
    """A list of names each one of ``choices`` (an InputError naming ``name`` otherwise)."""
    if not isinstance(value, list) or not all(isinstance(x, str) for x in value):
        raise InputError(name, f"must be a list drawn from {', '.join(choices)}")
    for x in value:
        if x not in choices:
            raise InputError(name, f"unknown {what} {x!r} (known: {', '.join(choices)}{note})")
    return tuple(value)


#: the smallest element size at the holes railcheck meshes (m): a tenth of a millimetre
#: puts about 30 elements round the rail's 7 mm bolt hole (its defaults: 1.5-4 mm)
MIN_HOLE_SIZE = 0.1e-3


def _mesh(table: dict) -> MeshSpec:
    p = "mesh."
    refuse_unknown(table, ALLOWED_KEYS["mesh"], p)
    order = table.get("order", 2)
    if isinstance(order, bool) or order not in (1, 2):
        raise InputError(p + "order", f"must be 1 or 2, got {order!r}")
    size = None
    if "size" in table:
        size = parse_quantity(table["size"], "length", p + "size", positive=True, allow_zero=False)
        if size < 0.2e-3:
            raise InputError(p + "size", f"{size * 1e3:g} mm is below the 0.2 mm this tool meshes")
    hole = None
    if "hole_size" in table:
        hole = parse_quantity(table["hole_size"], "length", p + "hole_size", positive=True, allow_zero=False)
        if hole < MIN_HOLE_SIZE:
            raise InputError(
                p + "hole_size", f"{hole * 1e3:.3g} mm is below the {MIN_HOLE_SIZE * 1e3:g} mm this tool meshes"
            )
        if size is None:
            raise InputError(p + "hole_size", "needs mesh.size too (the defaults come in pairs per part kind)")
    if hole is not None and size is not None and hole > size:
        raise InputError(p + "hole_size", f"{hole * 1e3:g} mm is larger than mesh.size {size * 1e3:g} mm")
    return MeshSpec(order, size, hole, boolean(table, "optimize", p, True), boolean(table, "curved", p, True))


def _output(table: dict) -> OutputSpec:
    p = "output."
    refuse_unknown(table, ALLOWED_KEYS["output"], p)
    d = table.get("dir", "results")
    if not isinstance(d, str) or not d.strip() or "\0" in d:  # no file system takes a NUL
        raise InputError(p + "dir", f"must be a directory name, got {d!r}")
    scale = string_choice(table.get("stress_scale", "limit"), ("limit", "part"), p + "stress_scale")
    return OutputSpec(
        d, boolean(table, "vtk", p, True), boolean(table, "png", p, True), boolean(table, "plots", p, True), scale
    )


#: catalogue dimensions whose zero means a feature left out: a rail without its grooves
#: (a solid rectangle, :class:`railcheck.geometry.catalogue.RailSpec`)
ZERO_MEANS_NONE = ("rail_groove_radius",)


def _geometry(table: dict) -> dict[str, float]:
    out = {}
    for key, value in table.items():
        if key not in OVERRIDABLE:
            raise InputError(f"geometry.{key}", f"unknown key (allowed: {', '.join(sorted(OVERRIDABLE))})")
        zero_ok = key in ZERO_MEANS_NONE
        length = parse_quantity(value, "length", f"geometry.{key}", positive=True, allow_zero=zero_ok)
        out[key] = length if zero_ok and length == 0 else _in_range(length, "geometry", f"geometry.{key}")
    problem = validate(out)
    if problem:
        raise InputError(*problem)
    return out


def _fatigue(table: dict) -> FatigueSpec:

    p = "fatigue."
    refuse_unknown(table, ALLOWED_KEYS["fatigue"], p)
    surface = string_choice(table.get("surface", "machined"), tuple(SURFACE), p + "surface")
    load = string_choice(table.get("load", "bending"), tuple(LOAD), p + "load")
    criterion = string_choice(table.get("criterion", "goodman"), CRITERIA, p + "criterion")
    reliability = table.get("reliability", DEFAULT_RELIABILITY)
    if isinstance(reliability, bool) or reliability not in RELIABILITY:
        raise InputError(p + "reliability", f"must be one of {', '.join(map(str, RELIABILITY))}, got {reliability!r}")
    n = table.get("min_safety", 1.0)
    if isinstance(n, bool) or not isinstance(n, (int, float)) or not math.isfinite(n) or not 0.5 <= n <= 100:
        raise InputError(p + "min_safety", f"must be a number from 0.5 to 100, got {n!r}")
    return FatigueSpec(surface, float(reliability), load, criterion, float(n))


def _dynamic(table: dict) -> DynamicSpec:
    p = "dynamic."
    refuse_unknown(table, ALLOWED_KEYS["dynamic"], p)
    damping = number(table.get("damping", 0.02), p + "damping", 1e-4, 0.5, "a ratio of critical damping")
    amplification = number(table.get("max_amplification", 1.10), p + "max_amplification", 1.0, 10.0, "a ratio")
    if amplification <= 1.0:  # any motion excites the modes a little: 1 would pass no speed, fail nothing at rest
        raise InputError(p + "max_amplification", "must be above 1 (1 allows no dynamic response: no speed would pass)")
    modes = table.get("modes", 6)
    if isinstance(modes, bool) or not isinstance(modes, int) or not 1 <= modes <= 50:
        raise InputError(p + "modes", f"must be a whole number from 1 to 50, got {modes!r}")
    return DynamicSpec(damping, amplification, modes)


def _sweep(table: dict) -> SweepSpec:
    p = "sweep."
    refuse_unknown(table, ALLOWED_KEYS["sweep"], p)
    kind = table.get("kind", "both")
    kinds = SWEEP_KINDS if kind == "both" else (string_choice(kind, SWEEP_KINDS + ("both",), p + "kind"),)
    ranges = {}
    for bar in ("crank", "coupler", "rocker", "ground", "offset"):
        if bar not in table:
            continue
        value = table[bar]
        if not isinstance(value, list) or len(value) != 2:
            raise InputError(p + bar, f'must be a [min, max] pair of lengths, e.g. ["180 mm", "660 mm"], got {value!r}')
        lo, hi = (_sweep_length(v, bar, p + bar) for v in value)
        if lo > hi:
            raise InputError(p + bar, f"min {lo * 1e3:g} mm is above max {hi * 1e3:g} mm")
        ranges[bar] = (lo, hi)
    speeds = table.get("speeds", ["1 Hz"])
    if not isinstance(speeds, list) or not speeds:
        raise InputError(p + "speeds", f'must be a non-empty list of speeds, e.g. ["0.5 Hz", "1 Hz"], got {speeds!r}')
    speeds = tuple(
        _in_range(parse_quantity(v, "angular_speed", p + "speeds", positive=True, allow_zero=False), "speed", p + "speeds")
        for v in speeds
    )
    for i, w in enumerate(speeds):  # one row per setting and speed: a speed listed twice doubles rows
        if any(math.isclose(w, u, rel_tol=1e-9) for u in speeds[:i]):
            raise InputError(p + "speeds", f"{table['speeds'][i]!r} is {w / (2 * math.pi):g} Hz, already listed")
    steps = table.get("steps", 720)
    if isinstance(steps, bool) or not isinstance(steps, int) or not 8 <= steps <= 100_000:
        raise InputError(p + "steps", f"must be a whole number from 8 to 100000, got {steps!r}")
    assembly = string_choice(table.get("assembly", "open"), ("open", "crossed"), p + "assembly")
    memory = parse_quantity(table.get("memory", "512 MB"), "memory", p + "memory", positive=True, allow_zero=False)
    if not 1e5 <= memory <= 1e12:
        raise InputError(p + "memory", "must be from 100 kB to 1000 GB")
    fmt = string_choice(table.get("format", "parquet"), SWEEP_FORMATS, p + "format")
    return SweepSpec(
        kinds, ranges, speeds, steps, assembly, _sweep_settings(table.get("settings", []), kinds), float(memory), fmt
    )


def _sweep_length(value: Any, bar: str, name: str) -> float:
    """A bar length of a sweep (m): positive and within the physical range; a slider's
    offset may be zero or negative (either side of the crank's pivot), its size within the
    same range."""
    if bar == "offset":
        v = parse_quantity(value, "length", name)
        return v if v == 0 else _in_range(v, "length", name, magnitude=True)
    return _in_range(parse_quantity(value, "length", name, positive=True, allow_zero=False), "length", name)


def _sweep_settings(items: Any, kinds: tuple[str, ...]) -> dict:
    """``[[sweep.settings]]`` entries: tables with every bar of one kind (lengths)."""
    p = "sweep.settings"
    if not isinstance(items, list) or not all(isinstance(x, dict) for x in items):
        raise InputError(p, "must be a list of tables, each with the bar lengths of one setting")
    out: dict[str, list] = {}
    for i, item in enumerate(items):
        kind = next((k for k in kinds if set(item) == set(SWEEP_BARS[k])), None)
        if kind is None:
            wanted = " or ".join("{" + ", ".join(SWEEP_BARS[k]) + "}" for k in kinds)
            raise InputError(f"{p}[{i}]", f"must give exactly the bars {wanted}, got {sorted(item)}")
        setting = {}
        for bar, value in item.items():
            setting[bar] = _sweep_length(value, bar, f"{p}[{i}].{bar}")
        out.setdefault(kind, []).append(setting)
    return out


def scene_errors(data: dict[str, Any]) -> list[InputError]:
    """Every error the scene's tables show each on its own, in the file's order: each
    table's unknown keys and the first bad value among its known ones (what depends on
    another table, the parse itself finds once these are fixed)."""
    found: list[InputError] = []

    def attempt(parse, *args) -> Any:
        try:
            return parse(*args)
        except InputError as exc:
            found.append(exc)
            return None

    geometry = attempt(_geometry, data["geometry"]) if isinstance(data.get("geometry"), dict) else {}
    loads: dict = data["loads"] if isinstance(data.get("loads"), dict) else {}
    parsers = {
        "mechanism": _mechanism,
        "check": lambda t: _check(t, loads),
        "mesh": _mesh,
        "output": _output,
        "fatigue": _fatigue,
        "sweep": _sweep,
        "dynamic": _dynamic,
    }
    if geometry is not None:
        parsers["components"] = lambda t: component_spec(t, with_overrides(geometry)[0])
    for name, table in data.items():
        if name not in ALLOWED_KEYS or not isinstance(table, dict):
            continue  # the parse names these
        allowed = ALLOWED_KEYS[name]
        found += unknown_keys(table, allowed, f"{name}.")
        if name in parsers:
            attempt(parsers[name], {k: v for k, v in table.items() if allowed is None or k in allowed})
    unique = {str(e): e for e in found}
    return list(unique.values())


def parse_scene(data: dict[str, Any], source: str = "<scene>") -> Scene:
    """Build a :class:`Scene` from a parsed TOML mapping; several bad values at once are
    refused together (:class:`~railcheck.base.errors.InputErrors`, one line each)."""
    _not_planar(data.get("mechanism"))
    refuse_unknown(data, set(ALLOWED_KEYS), "")
    errors = scene_errors(data)
    if len(errors) > 1:
        raise InputErrors(errors)
    for key, value in data.items():
        if not isinstance(value, dict):
            raise InputError(key, "must be a table ([" + key + "])")
    mechanism = _mechanism(data["mechanism"]) if "mechanism" in data else None
    dyn = data.get("dynamics", {})
    refuse_unknown(dyn, ALLOWED_KEYS["dynamics"], "dynamics.")
    formulation = string_choice(dyn.get("formulation", "newton-euler"), FORMULATIONS, "dynamics.formulation")
    check = None
    if "check" in data:
        check = _check(data["check"], data.get("loads", {}), formulation)
    elif "loads" in data:
        raise InputError("loads", "explicit loads need a [check] table that lists their parts")
    if check is None and mechanism is None and "sweep" not in data:
        raise InputError("mechanism", "missing: a scene needs a [mechanism] table, a [check] table, or both")
    if check is not None:
        needs_linkage = [p for p in check.parts if p not in check.loads]
        if needs_linkage and mechanism is None and "sweep" not in data:
            raise InputError(
                "mechanism",
                f"missing: parts {', '.join(needs_linkage)} take their loads from the "
                "linkage (or give them explicit [loads.PART])",
            )
    if mechanism is not None:
        mechanism, check = _oriented(mechanism, check, data["mechanism"].get("plane"))
    if check is not None:
        if "gravity" in check.effects and formulation == "seed-2013":
            raise InputError(
                "check.effects",
                "gravity cannot be combined with dynamics.formulation = "
                '"seed-2013" (the seed\'s equations have no weight terms)',
            )
        if mechanism is not None and isinstance(mechanism.linkage, SliderCrank):
            rails = [p for p in needs_linkage if p == "rocker-rail"]
            if rails:
                raise InputError("check.parts", "a slider-crank has no rocker rail")
            absent = [c for c in check.components if c in NOT_ON_SLIDER_CRANK]
            if absent:
                raise InputError("check.parts", f"a slider-crank has no rocker: no {', '.join(absent)}")
    mesh = _mesh(data.get("mesh", {}))
    output = _output(data.get("output", {}))
    geometry = _geometry(data.get("geometry", {}))
    fatigue = _fatigue(data.get("fatigue", {}))
    sweep = _sweep(data.get("sweep", {}))
    dynamic = _dynamic(data.get("dynamic", {}))
    components = component_spec(data.get("components", {}), with_overrides(geometry)[0])
    return Scene(mechanism, formulation, check, mesh, output, geometry, data, source, fatigue, sweep, dynamic, components)


def load_scene(path: str | Path | None) -> Scene:
    """Read a scene file; ``None`` reads the built-in default (the seed's final design)."""
    return parse_scene(*read_scene_data(path))


def read_scene_data(path: str | Path | None) -> tuple[dict[str, Any], str]:
    """A scene file's TOML mapping and where it came from (``None``: the built-in
    default); an unreadable file or malformed TOML refused in one line."""
    if path is None:
        text = resources.files("railcheck").joinpath("scenes", DEFAULT_SCENE).read_text(encoding="utf-8")
        source = f"built-in {DEFAULT_SCENE}"
    else:
        p = Path(path)
        try:
            if not p.exists():
                raise InputError("scene", f"file not found: {p}")
            if not p.is_file():
                raise InputError("scene", f"not a file: {p}")
            text = p.read_text(encoding="utf-8-sig")  # a byte-order mark is not part of the scene
        except (OSError, UnicodeDecodeError) as exc:
            why = exc.strerror if isinstance(exc, OSError) and exc.strerror else exc
            name = str(p) if len(str(p)) <= 80 else f"{str(p)[:38]}...{str(p)[-39:]}"  # a name too long: its ends
            raise InputError("scene", f"cannot read {name}: {why}") from None
        source = str(p)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("scene", f"malformed TOML in {source}: {exc}") from None
    except RecursionError:
        raise InputError("scene", f"{source} nests tables or arrays too deeply to be a scene") from None
    return data, source
