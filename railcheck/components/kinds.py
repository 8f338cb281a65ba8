"""The component kinds, one registered entry each (as meshio registers a format): its
standard as the output names it, the :class:`~railcheck.components.ratings.ComponentSpec`
fields it reads, whether the scene's load factor applies, its check, what it needs to pass
in one check and over a sweep's settings. A new kind is one :func:`register_kind` call
beside its functions; nothing else keys on the kind. SI.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

from railcheck.components import checks, sizing
from railcheck.components.checks import ComponentResult, JointHistories, Strengths
from railcheck.components.ratings import ASSUMED, COMPONENTS, Component, ComponentSpec


@dataclass(frozen=True)
class ComponentKind:
    """One kind of component. ``check(component, spec, histories, factor, strengths)``
    gives (criterion -> utilisation, figures); ``needs(result, spec, histories, factor,
    strengths)`` one check's sizing (a dict of floats), ``needs_of_settings(component, spec,
    histories, factor, strengths)`` a sweep's, one value per setting; None: nothing sized.
    ``factored``: the strength checks (screws, shafts) take the scene's load factor, except
    a screw's slip (a serviceability check, on the loads as they are); the rolling
    elements' standards (bearings, carriages) set their own safety on unfactored loads."""

    name: str
    standard: str
    fields: tuple[str, ...]
    factored: bool
    check: Callable[..., tuple[dict, dict]]
    needs: Callable[..., dict] | None = None
    needs_of_settings: Callable | None = None


#: kind name -> its entry (:func:`register_kind`)
KINDS: dict[str, ComponentKind] = {}


def register_kind(kind: ComponentKind) -> ComponentKind:
    """Add ``kind`` to :data:`KINDS` (a second entry of one name is refused)."""
    if kind.name in KINDS:
        raise ValueError(f"component kind {kind.name!r} is already registered")
    KINDS[kind.name] = kind
    return kind


def check_component(
    component: Component,
    spec: ComponentSpec,
    h: JointHistories,
    factor: float,
    material: Strengths,
    given: frozenset = frozenset(),
) -> ComponentResult:
    """The check of ``component`` by its kind's standard on the histories ``h``: the
    strength checks on loads times ``factor``, slip and the rolling elements' on the loads
    as they are; ``given`` the ``[components]`` keys the scene set (not "assumed")."""
    kind = KINDS[component.kind]
    u, figures = kind.check(component, spec, h, factor if kind.factored else 1.0, material)
    assumed = tuple(n for n in kind.fields if n in ASSUMED and n not in given)
    return ComponentResult(
        component.name, component.kind, component.joint, kind.standard, kind.factored, u, figures, assumed
    )


def check_components(
    names, spec: ComponentSpec, h: JointHistories, factor: float, material: Strengths, given: frozenset = frozenset()
) -> dict:
    """name -> :class:`ComponentResult` of each component ``names`` lists."""
    return {n: check_component(COMPONENTS[n], spec, h, factor, material, given) for n in names}


def with_needs(r: ComponentResult, spec: ComponentSpec, h: JointHistories, factor: float, m: Strengths) -> ComponentResult:
    """``r`` with its ``needs`` (:mod:`railcheck.components.sizing`); a kind that sizes
    nothing (a carriage's catalogue rating) has none."""
    needs = KINDS[r.kind].needs
    return dataclasses.replace(r, needs=needs(r, spec, h, factor, m) if needs else {})


def needs_of_settings(names, spec: ComponentSpec, h: JointHistories, factor: float, m: Strengths) -> dict:
    """name -> (S,) what each of the components ``names`` needs at each of a sweep's
    settings (its kind's ``needs_of_settings``; the kinds that size nothing left out)."""
    out = {}
    for component in (COMPONENTS[name] for name in names):
        need = KINDS[component.kind].needs_of_settings
        if need is not None:
            out[component.name] = need(component, spec, h, factor, m)
    return out


_SCREW_FIELDS = (
    "screw_size",
    "screw_class",
    "screw_thread_friction",
    "screw_head_friction",
    "screw_tightening_factor",
    "screw_preload_utilisation",
    "screw_embedding",
    "joint_friction",
    "slip_safety",
    "screw_grip",
    "screw_end_distance",
    "screw_edge_distance",
    "screw_eccentricity",
)

register_kind(
    ComponentKind(
        "screws",
        "EN 1993-1-8 T3.4, VDI 2230 slip",
        _SCREW_FIELDS,
        True,
        checks.check_screws,
        sizing.screw_needs,
        sizing.screws_needed_of_settings,
    )
)
register_kind(
    ComponentKind(
        "shaft",
        "Shigley DE-Goodman",
        ("shaft_diameter", "shaft_fillet_radius", "shaft_kt", "shaft_kts", "shaft_lever"),
        True,
        checks.check_shaft,
        sizing.shaft_needs,
        sizing.shaft_diameter_needed,
    )
)
register_kind(
    ComponentKind(
        "bearings",
        "ISO 76, ISO 281",
        ("bearing_dynamic", "bearing_static", "bearing_spacing", "bearing_required_s0", "bearing_required_life"),
        False,
        checks.check_bearings,
        sizing.bearing_needs,
        sizing.spacing_needed_of_settings,
    )
)
register_kind(
    ComponentKind(
        "carriage",
        "catalogue P0",
        ("carriage_c0", "carriage_m0x", "carriage_m0y", "carriage_m0z", "carriage_height", "carriage_required_s0"),
        False,
        checks.check_carriage,
    )
)
