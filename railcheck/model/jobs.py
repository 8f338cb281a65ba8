"""Each checked part's work, resolved once from the scene into a picklable
:class:`PartJob`: its geometry, support and tip groups, mesh sizes, bolt holes, load
model and coefficient histories, material, limits and fatigue settings. Downstream stages
(:mod:`railcheck.model.cycle`, the worker processes) take the job, never the scene.

Also here, because they resolve the scene before any meshing: the seed method's load
cases, each part's mesh sizes, the bolt holes a bar length uses, and the refusals of a
mesh too coarse for a part or too large for this machine's memory.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from railcheck.base import machine
from railcheck.base.errors import InputError
from railcheck.fea.materials import Material
from railcheck.fea.mesh import estimate_dofs
from railcheck.fea.unitcases import FreeBodyCases
from railcheck.geometry.mesher import estimate_elements
from railcheck.geometry.models import PartGeometry
from railcheck.kinematics.massmodel import carried_mass
from railcheck.loads.cases import LoadCase, explicit_load_case, pivot_x, rail_bolt_holes, reaction_load_case
from railcheck.model.certificate import Certificate, certificate, rail_lowest_hz
from railcheck.model.inputs import PartsInput
from railcheck.model.kinematics_stage import KinematicsResult
from railcheck.model.loading import (
    LoadModel,
    SourceHistory,
    load_model,
    source_histories,
    unit_cases,
    with_pressure_histories,
)
from railcheck.parts import BAR_INDEX, KINDS, PARTS, geometry_of, kind_of
from railcheck.scene import FatigueSpec, MeshSpec

#: peak memory per DOF of a P2 solve on the iterative path (assembly, AMG hierarchy, stress
#: projection), bytes; measured on a 1000 mm rail at 145k DOFs (docs/refusals.md, "What railcheck
#: refuses"). The direct path falls back to it when its factor would not fit.
BYTES_PER_DOF_AMG = 11_000


@dataclass(frozen=True)
class MeshJob:
    """A part's mesh: ``size`` and ``hole_size`` (m), element ``order``, curved P2
    (``curved``) and gmsh's optimisation (``optimize``)."""

    size: float
    hole_size: float
    order: int
    curved: bool
    optimize: bool


@dataclass(frozen=True)
class DynamicJob:
    """The dynamic response a part's check computes (effect ``dynamic``): the crank
    ``speed`` rad/s, modal ``damping`` ratio, ``max_amplification``, the number of
    ``modes``, and the ``pins`` (lists of hole surfaces) a free body is held at in its
    modal model (None: a clamped part keeps its clamp)."""

    speed: float
    damping: float
    max_amplification: float
    modes: int
    pins: tuple[tuple[str, ...], ...] | None
    lumped: tuple[tuple[tuple[str, ...], float], ...] = ()  # (hole groups, kg): masses the joints carry
    exact: bool = True  # False: the modes only give the certificate its lowest frequency (a part with no beam model)
    reason: str = "listed in [check] effects"  # why the response is computed


@dataclass(frozen=True)
class PartJob:
    """Everything one part's check needs (SI): ``support`` and ``tip`` mesh groups,
    ``exclusion`` (m) the support's singular zone kept out of the verdict, ``section``
    (width, height) m for the fatigue size factor, the bolt ``holes`` its joint loads,
    its ``loads`` model and ``histories`` (one per load source), the seed method's
    ``load_case``, the stress ``limit`` (Pa), the ``fatigue`` settings and the deflection
    limit ``max_deflection`` (m or None)."""

    name: str
    geometry: PartGeometry
    support: str
    tip: str
    exclusion: float
    section: tuple[float, float]
    mesh: MeshJob
    holes: tuple[str, ...]
    loads: LoadModel
    histories: tuple[SourceHistory, ...]
    load_case: LoadCase
    material: Material
    limit: float
    fatigue: FatigueSpec
    max_deflection: float | None
    free_body: FreeBodyCases | None = None
    dynamic: DynamicJob | None = None
    certificate: Certificate | None = None  # where quasi-static holds (a rail's, from its beam model)
    clamped: PartJob | None = None  # a free rail's 2013 clamped model, checked beside it
    node_fields: bool = True  # each node's envelope and fatigue factor are wanted (the VTU, the pictures)

    @property
    def supports(self) -> list[str]:
        """The clamped groups (none for a free body)."""
        return [] if self.free_body is not None else [self.support]


def mesh_sizes(mesh: MeshSpec, kind: str) -> tuple[float, float]:
    """(size, hole size) in m for a part kind: the scene's [mesh], else the registry's default."""
    if mesh.size is None:
        return KINDS[kind].mesh
    return mesh.size, mesh.hole_size or 0.3 * mesh.size


def part_geometries(inputs: PartsInput) -> dict[str, PartGeometry]:
    """PartGeometry for each part the record checks (light: no gmsh import)."""
    return {name: geometry_of(name, inputs.geometry) for name in inputs.check.parts}


def bolt_holes(inputs: PartsInput, name: str, geo: PartGeometry) -> list[str]:
    """The bolt-hole groups a part's joint uses: on a rail the pair chosen by the bar
    length and ``check.bolt_position``; on a plate every hole."""
    if not kind_of(name).bolts_on_rail:
        return kind_of(name).bolts(geo)
    xs = list(geo.get("hole_x"))
    explicit = name in inputs.check.loads
    bar = PARTS[name].bar
    length = 0.0 if explicit or bar is None else inputs.linkage_spec.linkage.lengths[bar]
    position = "worst" if explicit else inputs.check.bolt_position
    if not explicit and inputs.check.support == "free-body" and PARTS[name].free_body is not None:
        position = "actual"  # a free body's joint force acts where the joint is
    try:
        idx = rail_bolt_holes(xs, pivot_x(xs), length, position)
    except ValueError as exc:
        raise InputError(f"mechanism.{bar}", str(exc)) from None
    return [f"hole_{k}" for k in idx]


def build_load_cases(inputs: PartsInput, kin: KinematicsResult | None, geometries: dict) -> dict[str, LoadCase]:
    """The seed method's load case of every checked part: the factored reaction at the
    instant its magnitude peaks, over the joint with the largest peak (loads stage)."""
    cases = {}
    for name in inputs.check.parts:
        kind, holes = kind_of(name), bolt_holes(inputs, name, geometries[name])
        if name in inputs.check.loads:
            load = inputs.check.loads[name]
            cases[name] = explicit_load_case(name, load.longitudinal, load.transverse, holes, kind.support, kind.tip)
            continue
        assert kin is not None  # the linkage's loads need its kinematics
        dyn, motion = kin.dynamics, kin.motion
        sources = [s for s in PARTS[name].sources if s.joint in dyn.reactions]
        if not sources:
            raise InputError(
                "check.parts",
                f"{name} carries {PARTS[name].sources[0].joint}, which this mechanism lacks: give explicit [loads.{name}]",
            )
        src = max(sources, key=lambda s: dyn.peak(s.joint)[0])
        angle = motion.theta[:, BAR_INDEX[src.axes_bar]] if src.axes_bar else np.zeros(motion.steps)
        cases[name] = reaction_load_case(
            name,
            src.joint,
            src.sign * dyn.reactions[src.joint],
            angle,
            motion.theta2,
            inputs.check.factor,
            holes,
            kind.support,
            kind.tip,
        )
    return cases


def part_jobs(
    inputs: PartsInput, kin: KinematicsResult | None, geometries: dict, cases: dict, material: Material, limit: float
) -> dict[str, PartJob]:
    """The :class:`PartJob` of every checked part, in the scene's order."""
    jobs = {}
    for name, geo in geometries.items():
        kind = kind_of(name)
        holes = bolt_holes(inputs, name, geo)
        loads = load_model(inputs, name, material.density)
        free = free_body_cases(loads, geo, holes) if is_free(loads) else None
        histories = with_pressure_histories(unit_cases(loads, geo, holes), source_histories(loads, kin, holes))
        dynamic, cert = speed_validity(inputs, free, name, geo, holes, histories, unit_cases(loads, geo, holes), material)
        jobs[name] = PartJob(
            clamped=clamped_job(inputs, kin, name, geo, cases, material, limit) if compared(inputs, free) else None,
            name=name,
            geometry=geo,
            support=kind.support,
            tip=kind.tip,
            exclusion=0.0 if free is not None else kind.exclusion(geo),
            section=tuple(kind.section(geo)),
            mesh=MeshJob(*mesh_sizes(inputs.mesh, geo.kind), inputs.mesh.order, inputs.mesh.curved, inputs.mesh.optimize),
            holes=tuple(holes),
            loads=loads,
            histories=histories,
            load_case=cases[name],
            material=material,
            limit=limit,
            fatigue=inputs.fatigue,
            max_deflection=inputs.check.max_deflection,
            free_body=free,
            dynamic=dynamic,
            certificate=cert,
            node_fields=inputs.output.vtk or inputs.output.png,
        )
    return jobs


def compared(inputs: PartsInput, free) -> bool:
    """Whether a part's 2013 clamped model runs beside it: a free part of a record whose
    ``[check] compare`` lists "2013"."""
    return free is not None and "2013" in inputs.check.compare


def clamped_job(
    inputs: PartsInput,
    kin: KinematicsResult | None,
    name: str,
    geo: PartGeometry,
    cases: dict,
    material: Material,
    limit: float,
) -> PartJob:
    """The free rail ``name`` as the 2013 study checked it (``support = "clamped"``: clamped
    at its first hole, the far joint's reaction at the bolts ``bolt_position`` picks),
    quasi-static; the report shows its peak beside the free body's verdict."""
    return replace(
        part_jobs(inputs.clamped(name), kin, {name: geo}, cases, material, limit)[name], dynamic=None, certificate=None
    )


def dynamic_job(
    inputs: PartsInput, free: FreeBodyCases | None, name: str = "", holes: list[str] | tuple = ()
) -> DynamicJob | None:
    """The part's dynamic request when ``dynamic`` is listed and the crank turns (a still
    rig has no cycle to respond to); a free body is pinned at its two joints (a bolted-down
    part held at its base). A rail's
    joints carry the mass model's point masses (plates, carriages, coupling), lumped on
    their holes: the near joint's on its first two holes, the far joint's on its bolt holes."""
    if not inputs.dynamic_response:
        return None
    return _modal_template(inputs, free, name, holes)


def speed_validity(
    inputs: PartsInput, free, name: str, geo, holes, histories, names, material: Material
) -> tuple[DynamicJob | None, Certificate | None]:
    """(the part's dynamic request, its certificate): with ``dynamic`` listed, the exact
    response; else, for a part whose loads vary over the cycle of a turning crank, a rail's
    certificate from its beam model (the exact response when it does not hold) or, for
    any other part, its modes for the certificate (decided once they are solved)."""
    job = dynamic_job(inputs, free, name, holes)
    moving = inputs.mechanism is not None and inputs.linkage_spec.speed > 0 and any(h.C.shape[0] >= 3 for h in histories)
    if not moving or name in inputs.check.loads:
        return job, None
    cert = None
    if kind_of(name).beam_frequency:
        template = job or _modal_template(inputs, free, name, holes)
        clamp = None if template.pins else kind_of(name).support
        hz = rail_lowest_hz(geo, material, template.pins, template.lumped, clamp)
        cert = certificate([h.C for h in histories], names, template.speed, hz, "beam model", inputs.dynamic.damping)
        if job is None and not cert.holds:
            job = replace(template, reason=f"the certificate does not hold ({cert.estimate:.3f} > {cert.tolerance:.2f})")
    elif job is None:
        job = replace(_modal_template(inputs, free, name, holes), exact=False)
    return job, cert


def _modal_template(inputs: PartsInput, free, name: str, holes) -> DynamicJob:
    """The dynamic request the part would make with ``dynamic`` listed."""
    d = inputs.dynamic
    pins = (tuple(free.deflection[0]), tuple(free.deflection[1])) if free is not None and not free.held else None
    lumped = carried_masses(inputs, name, holes)
    return DynamicJob(inputs.linkage_spec.speed, d.damping, d.max_amplification, d.modes, pins, lumped)


def carried_masses(inputs: PartsInput, name: str, holes: list[str] | tuple, kind: str | None = None) -> tuple:
    """((hole surfaces, kg), ...): the point masses a rail carries at its joints in the
    mass model (plates, carriages, coupling) of the linkage ``kind`` (default: the
    scene's): the near joint's on its first two holes, the far joint's on the bolt holes
    ``holes``; () for a plate or a part with explicit loads."""
    part = PARTS.get(name)
    fb = part.free_body if part is not None else None
    if part is None or fb is None or part.bar is None or not holes or name in inputs.check.loads:
        return ()
    masses = inputs.masses
    kind = kind or inputs.linkage_spec.linkage.kind
    kg = [carried_mass(masses, kind, part.bar, joint.joint) for joint in (fb.near, fb.far)]
    return tuple((g, m) for g, m in ((("hole_0", "hole_1"), kg[0]), (tuple(holes), kg[1])) if m > 0)


def is_free(loads: LoadModel) -> bool:
    """Whether the part is solved as a free body (a rail, a joint plate, a bolted-down part)."""
    return loads.is_free_body or loads.is_free_plate or loads.is_on_foundation


def free_body_cases(loads: LoadModel, geo: PartGeometry, holes: list[str]) -> FreeBodyCases:
    """How a free rail is solved: its body cases carry the dynamics' rail mass; its
    deflection is, for the crank, the displacement at A's bolts relative to the line
    through the two screws that clamp it to O2's plate, for a link the sag at mid-span
    relative to the line through its two joints. A free plate's body cases carry its mass; its deflection
    is the seat's displacement relative to the line through its two bolts."""
    if loads.is_on_foundation:  # its top's displacement relative to its base; body cases at the material's density
        assert loads.foundation is not None  # is_on_foundation
        return FreeBodyCases(
            mass=None, deflection=([loads.foundation], [loads.foundation], ["end_free"]), held=(loads.foundation,)
        )
    if loads.is_free_plate:
        assert loads.free_plate is not None and loads.plate is not None  # is_free_plate
        mass, offset, polar = loads.plate  # about the seat
        return FreeBodyCases(
            mass=mass,
            deflection=(["hole_0"], ["hole_1"], [loads.free_plate.seat]),
            centre=(float(geo.get("seat_x")) + offset, 0.0),
            inertia=polar - mass * offset**2,
        )
    xs = geo.get("hole_x")
    far_x = float(np.mean([xs[int(h.split("_")[1])] for h in holes]))
    assert loads.free_body is not None  # a free rail
    deflection: tuple  # (the line's two hole groups, the measured group or the x of mid-span)
    if loads.free_body.motor:
        deflection = (["hole_0"], ["hole_1"], list(holes))
    else:
        deflection = (["hole_0", "hole_1"], list(holes), 0.5 * (pivot_x(xs) + far_x))
    return FreeBodyCases(
        mass=loads.rail_mass, deflection=deflection, centre=(loads.rail_body[0], 0.0), inertia=loads.rail_body[1]
    )


def refuse_unresolvable_meshes(inputs: PartsInput, geometries: dict) -> None:
    """Refuse, before meshing, a mesh size too coarse for a part (more than twice its
    section's smaller side: the stress would be meaningless) and a mesh this machine's
    memory cannot hold (DOFs estimated from the volume and the size field)."""
    if inputs.mesh.size is not None:
        for name, geo in geometries.items():
            side = min(kind_of(name).section(geo))
            if inputs.mesh.size > 2 * side:
                raise InputError(
                    "mesh.size",
                    f"{inputs.mesh.size * 1e3:g} mm is more than twice {name}'s "
                    f"{side * 1e3:g} mm section: too coarse to resolve its stress",
                )
    for name, geo in geometries.items():
        refuse_coarse_holes(name, geo, mesh_sizes(inputs.mesh, geo.kind)[1])
        refuse_beyond_memory(geo, *mesh_sizes(inputs.mesh, geo.kind), inputs.mesh.order, "mesh.size")


def refuse_coarse_holes(name: str, geo: PartGeometry, hole_size: float) -> None:
    """Refuse a hole size (m) that puts fewer than three elements round the part's
    smallest hole: its bore would be a polygon the pins cannot bear on (the FE said
    "hole_0: is not a bore" under no field the user wrote)."""
    diameters = [float(v) for k, v in geo.params if k.endswith("diameter") and isinstance(v, (int, float))]
    if diameters and hole_size > math.pi * min(diameters) / 3:
        raise InputError(
            "mesh.hole_size",
            f"{hole_size * 1e3:g} mm puts fewer than three elements round {name}'s {min(diameters) * 1e3:g} mm holes "
            f"(at most {math.pi * min(diameters) / 3 * 1e3:.3g} mm)",
        )


def refuse_beyond_memory(geo: PartGeometry, size: float, hole_size: float, order: int, field: str) -> None:
    """Raise InputError naming ``field`` when meshing ``geo`` at these sizes (m) would
    need more memory than this machine has (estimated before meshing)."""
    tets = estimate_elements(geo, size, hole_size)
    dofs = estimate_dofs(tets // 5, tets, order)
    machine.refuse_beyond_memory(
        dofs * BYTES_PER_DOF_AMG, field, f"about {machine.short(dofs / 1e6)} M DOFs", "use a larger mesh size"
    )
