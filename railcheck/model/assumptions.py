"""Every default and assumption that shaped a check's verdict, in words: the one list the
console, the report and summary.json state (issue "defaults an engineer signs")."""

from __future__ import annotations

import re

from railcheck.components.ratings import ComponentSpec
from railcheck.fea.fatigue import RELIABILITY
from railcheck.fea.materials import MATERIALS
from railcheck.loads.weight import CANTILEVERED, shaft_moment
from railcheck.model.certificate import QUASI_STATIC_TOLERANCE, SMALL_DISPLACEMENT_SHARE
from railcheck.model.inputs import PartsInput
from railcheck.model.loading import linkage_lengths


def assumptions(inputs: PartsInput | None, spec: ComponentSpec, parts: dict) -> list[str]:
    """The assumptions behind a check of the parts' record ``inputs`` (None without a
    [check]: none) whose part results are ``parts`` (name -> PartResult), its components
    dimensioned and rated by ``spec``."""
    if inputs is None:
        return []
    c, f = inputs.check, inputs.fatigue
    m = MATERIALS[c.material]
    out = [
        f"material {m.name}: sigma_u {m.ultimate_strength / 1e6:.0f} MPa, sigma_y {m.yield_strength / 1e6:.0f} MPa, "
        f"E {m.youngs_modulus / 1e9:.0f} GPa, density {m.density:.0f} kg/m^3 ({m.source})",
        (
            f"stress limit {c.limit / 1e6:.0f} MPa (set in [check] limit)"
            if c.limit
            else f"stress limit {m.fatigue_limit / 1e6:.0f} MPa = sigma_u / 2 (seed 000's rule)"
        ),
        "a linear-elastic peak above sigma_y fails the part: beyond yield the linear result is not physical",
        f"small displacements: a deflection beyond {SMALL_DISPLACEMENT_SHARE:.0%} of the part's length (slopes of "
        "3-4 deg) fails the part: beyond it the linear result is not valid",
        f"load factor {c.factor:g} on every joint force and inertia load (seed 000, chapter 4)",
        f"fatigue: {f.criterion} criterion, {f.surface} surface, {f.load} loading, reliability {f.reliability:g} "
        f"(k_e = {RELIABILITY[f.reliability]:g}, Shigley table 6-5), required factor {f.min_safety:g}",
        (
            f"deflection limit {c.max_deflection * 1e3:g} mm ([check] max_deflection)"
            if c.max_deflection is not None
            else "deflection limit: none (no catalogue or code gives one for this rig; [check] max_deflection sets one)"
        ),
        f"effects: {', '.join(c.effects) or 'none'}; support: {c.support}",
    ]
    out.append(weight_assumption(inputs, parts))
    if parts:
        out.append(mesh_assumption(parts))
    if c.components:
        out.append(
            f"components ({', '.join(c.components)}): as the 2013 study's final joints build them, each rail "
            "screwed to its plates by two screws through two neighbouring holes, the plates turning on a 25 mm "
            "shaft between two 6205 bearings, the motor driving O2's shaft; screws and shafts on loads "
            f"x{c.factor:g} with the standards' resistance factors (EN 1993-1-8 gamma_M0 1.0, gamma_M2 1.25; "
            "Shigley DE-Goodman n >= 1, bending fully reversed); the screws' slip (VDI 2230, slip safety "
            f"{spec.slip_safety:g} under a reversing load: a joint that slips loosens) on unfactored "
            "loads, a failure; bearings and carriages on unfactored loads against their required static "
            f"safety ({spec.bearing_required_s0:g}, {spec.carriage_required_s0:g}) and "
            f"life ({spec.bearing_required_life / 3600:.0f} h); every dimension and rating from seed 000, "
            "a cited catalogue or assumed (docs/components.md)"
        )
    if any(p.job.certificate is not None or p.cycle.dynamic is not None for p in parts.values()):
        out.append(
            f"dynamics: quasi-static where the one-mode amplification estimate is at most {QUASI_STATIC_TOLERANCE:.2f}, "
            f"else the modal response (mode-acceleration, modal damping {inputs.dynamic.damping:g}, assumed)"
        )
    return out


def weight_assumption(inputs: PartsInput, parts: dict) -> str:
    """How the rig's weight is applied: in plane (a vertical rig), out of plane on the free
    rails (a table-top rig, with the bound it takes and the shafts' moments), or not at all."""
    if inputs.plane == "vertical":
        return "weight: a vertical rig ([mechanism] plane): every part's weight acts in the mechanism's plane"
    weighed = [p.job.loads for p in parts.values() if p.job.loads.weight is not None]
    if not weighed:
        return (
            "weight: a table-top rig ([mechanism] plane = horizontal), its weight out of plane; "
            "no part checked here carries it (it loads free-body rails)"
        )
    shafts = "; ".join(
        f"{w.weight.bar} shaft {shaft_moment(w.weight, linkage_lengths(inputs.linkage_spec.linkage)):.1f} N m"
        for w in weighed
        if w.weight.bar in CANTILEVERED
    )
    return (
        "weight: a table-top rig ([mechanism] plane = horizontal): each rail's weight and carried masses act out of "
        "plane (-z, rail base down), constant over the cycle, load factor on it; bound: links simply supported at their "
        "joints, crank and rocker cantilevered from their shafts, clamped at their first two holes"
        + (f" (unfactored {shafts})" if shafts else "")
        + "; the other bound, joints rigid out of plane, is not modelled; joint plates and the bracket carry no weight"
    )


def mesh_assumption(parts: dict) -> str:
    """Each part's mesh in words: the elements, sizes, where the mesh came from (shipped
    with railcheck or built on this machine: the same bytes either way, docs/refusals.md
    "Same bytes") and how many curved edges were straightened (the surface faceted there)."""
    each = []
    for name, p in parts.items():
        j = p.job.mesh
        kind = "quadratic tetrahedra" + (", curved edges" if j.curved else "") if j.order == 2 else "linear tetrahedra"
        where = "shipped with railcheck" if p.mesh.shipped else "built by gmsh on this machine"
        sizes = f"{j.size * 1e3:g} mm ({j.hole_size * 1e3:g} mm at the holes)"
        straightened = re.match(r"(\d+) curved edges straightened", p.mesh.warning or "")
        faceted = f", {straightened.group(1)} curved edges straightened" if straightened else ""
        each.append(f"{name} {p.mesh.tets.shape[0]} {kind}, {sizes}, {where}{faceted}")
    return "meshes: " + "; ".join(each)
