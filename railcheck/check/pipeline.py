"""The check pipeline: scene -> kinematics -> loads -> geometry -> mesh -> solve -> stress
-> report, running only the stages the requested outputs need.

* A scene without a [check] table stops after kinematics: gmsh, skfem and pyvista are
  never imported.
* A scene whose parts all have explicit [loads] never runs the linkage.
* Gravity is applied only when check.effects lists it; inertia only with a non-zero speed.

``stages_run`` records, in order, each stage that ran.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass, field

import numpy as np

from railcheck.check.kinematics_stage import KinematicsResult, kinematics_summary, run_kinematics
from railcheck.errors import InputError
from railcheck.scene import Scene


def mesh_sizes(scene, kind: str) -> tuple[float, float]:
    """(size, hole size) in m for a part kind: the scene's [mesh], else the registry's default."""
    from railcheck.parts import KINDS
    if scene.mesh.size is None:
        return KINDS[kind].mesh
    return scene.mesh.size, scene.mesh.hole_size or 0.3 * scene.mesh.size


STAGES = ("scene", "kinematics", "loads", "geometry", "mesh", "solve", "stress", "report")


class Progress:
    """Per-stage lines on stderr: '[stage] what ... 1.2 s'."""

    def __init__(self, quiet: bool = False):
        self.quiet = quiet
        self.t0 = time.perf_counter()

    def say(self, stage: str, message: str) -> None:
        if not self.quiet:
            print(f"[{time.perf_counter() - self.t0:7.1f} s] {stage:<10} {message}", file=sys.stderr, flush=True)


@dataclass
class PartResult:
    """One part's check. ``solution``: the field at the governing instant (for the VTU
    and the picture); ``cycle``: :class:`railcheck.check.cycle.CycleResult` (envelope, seed
    method, fatigue); ``limit`` Pa."""

    name: str
    load_case: object
    mesh: object
    solution: object
    limit: float
    geometry: object
    cycle: object = None

    @property
    def verdict_stress(self) -> float:
        """Pa: the cycle's peak von Mises away from the support's singular edge (README)."""
        return self.cycle.envelope.max_von_mises

    @property
    def stress_passed(self) -> bool:
        return self.verdict_stress <= self.limit

    @property
    def fatigue_passed(self) -> bool:
        return self.cycle.fatigue["min_safety_factor"] >= self.cycle.fatigue["required"]

    @property
    def deflection_limit(self) -> float | None:
        """m, from ``[check] max_deflection`` (None: no limit)."""
        return self.cycle.deflection_limit

    @property
    def deflection_passed(self) -> bool:
        return self.deflection_limit is None or self.cycle.envelope.max_tip <= self.deflection_limit

    @property
    def passed(self) -> bool:
        return self.stress_passed and self.fatigue_passed and self.deflection_passed


@dataclass
class PipelineResult:
    scene: Scene
    stages_run: list[str] = field(default_factory=list)
    kinematics: KinematicsResult | None = None
    kinematics_summary: dict | None = None
    parts: dict[str, PartResult] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)
    checks: dict = field(default_factory=dict)      # configuration checks of the scene's linkage

    @property
    def failures(self) -> list[str]:
        """Every reason the run fails: a configuration check or a part's stress or
        fatigue verdict (empty: pass)."""
        out = [f"check {name}" for name, c in self.checks.items() if not c.ok]
        for name, p in self.parts.items():
            out += [f"{name} stress"] if not p.stress_passed else []
            out += [f"{name} fatigue"] if not p.fatigue_passed else []
            out += [f"{name} deflection"] if not p.deflection_passed else []
        return out

    @property
    def passed(self) -> bool:
        return not self.failures


def _mark(result: PipelineResult, stage: str) -> None:
    if stage not in result.stages_run:
        result.stages_run.append(stage)


def needs_linkage(scene: Scene) -> bool:
    """True when some requested output depends on the linkage's reactions."""
    if scene.check is None:
        return scene.mechanism is not None
    return any(p not in scene.check.loads for p in scene.check.parts)


def part_geometries(scene: Scene) -> dict:
    """PartGeometry for each part the scene checks (light: no gmsh import)."""
    from railcheck.parts import geometry_of
    return {name: geometry_of(name, scene.geometry) for name in scene.check.parts}


def bolt_holes(scene: Scene, name: str, geo) -> list[str]:
    """The bolt-hole groups a part's joint uses: on a rail the pair chosen by the bar
    length and ``check.bolt_position``; on a plate every hole."""
    from railcheck.loads.cases import rail_bolt_holes
    from railcheck.parts import PARTS, kind_of
    if not kind_of(name).bolts_on_rail:
        return kind_of(name).bolts(geo)
    xs = list(geo.get("hole_x"))
    explicit = name in scene.check.loads
    bar = PARTS[name].bar
    length = 0.0 if explicit else scene.mechanism.linkage.lengths[bar]
    try:
        idx = rail_bolt_holes(xs, xs[0], length, "worst" if explicit else scene.check.bolt_position)
    except ValueError as exc:
        raise InputError(f"mechanism.{bar}", str(exc)) from None
    return [f"hole_{k}" for k in idx]


def build_load_cases(scene: Scene, kin: KinematicsResult | None, geometries: dict) -> dict:
    """The seed method's load case of every checked part: the factored reaction at the
    instant its magnitude peaks, over the joint with the largest peak (loads stage)."""
    from railcheck.loads.cases import explicit_load_case, reaction_load_case
    from railcheck.parts import BAR_INDEX, PARTS, kind_of
    cases = {}
    for name in scene.check.parts:
        kind, holes = kind_of(name), bolt_holes(scene, name, geometries[name])
        if name in scene.check.loads:
            load = scene.check.loads[name]
            cases[name] = explicit_load_case(name, load.longitudinal, load.transverse, holes, kind.support, kind.tip)
            continue
        dyn, motion = kin.dynamics, kin.motion
        sources = [s for s in PARTS[name].sources if s.joint in dyn.reactions]
        if not sources:
            raise InputError("check.parts", f"{name} carries {PARTS[name].sources[0].joint}, which this mechanism "
                                            f"lacks: give explicit [loads.{name}]")
        src = max(sources, key=lambda s: dyn.peak(s.joint)[0])
        angle = motion.theta[:, BAR_INDEX[src.axes_bar]] if src.axes_bar else np.zeros(motion.steps)
        cases[name] = reaction_load_case(name, src.joint, src.sign * dyn.reactions[src.joint], angle,
                                         motion.theta2, scene.check.factor, holes, kind.support, kind.tip)
    return cases


def run_pipeline(scene: Scene, progress: Progress | None = None, solver: str = "auto",
                 jobs: int | None = None, part_done=None) -> PipelineResult:
    """Run the stages the scene needs; see the module doc. ``part_done(name, part)``, a
    picklable callable, runs as each part finishes, where it was checked (its files)."""
    progress = progress or Progress(quiet=True)
    result = PipelineResult(scene)
    _mark(result, "scene")
    progress.say("scene", scene.source)
    if needs_linkage(scene):
        t = time.perf_counter()
        result.kinematics = run_kinematics(scene)
        result.kinematics_summary = kinematics_summary(scene, result.kinematics)
        result.warnings += list(result.kinematics.motion.warnings)
        result.timings["kinematics"] = time.perf_counter() - t
        _mark(result, "kinematics")
        progress.say("kinematics", f"{scene.mechanism.steps} steps, {result.kinematics.dynamics.formulation}, "
                                   f"effects: {', '.join(result.kinematics.effects) or 'none'}")
    if result.kinematics is not None:
        result.checks = dict(result.kinematics.checks)
    elif scene.mechanism is not None:        # closed-form geometry only: the linkage is not run
        from railcheck.check.kinematics_stage import all_checks
        result.checks = all_checks(scene)
    if scene.check is None:
        _mark(result, "report")
        return result

    from railcheck.fea.materials import MATERIALS, limit_warning

    material = MATERIALS[scene.check.material]
    limit = scene.check.limit or material.fatigue_limit
    w = limit_warning(material, scene.check.limit)
    if w:
        result.warnings.append(w)
    geometries = part_geometries(scene)
    cases = build_load_cases(scene, result.kinematics, geometries)
    _mark(result, "loads")
    progress.say("loads", f"{len(cases)} load cases, factor {scene.check.factor:g}, bolts {scene.check.bolt_position}")
    _refuse_huge(scene, geometries)

    from railcheck.check.workers import check_parts

    _mark(result, "geometry")
    parts = check_parts(scene, result.kinematics, geometries, cases, material, limit, solver, progress, jobs,
                        part_done)
    for stage in ("mesh", "solve", "stress"):
        _mark(result, stage)
    for name, part in parts.items():
        result.timings.update({f"{k}:{name}": v for k, v in part.cycle.seconds.items()})
        result.warnings += [f"{name}: {w}" for w in part.cycle.warnings]
        result.parts[name] = part
    _mark(result, "report")
    return result


def _refuse_huge(scene: Scene, geometries: dict) -> None:
    """Refuse, before meshing, a mesh size too coarse for a part (more than twice its
    section's smaller side: the stress would be meaningless) and a mesh this machine's
    memory cannot hold (DOFs estimated from the volume and the size field)."""
    from railcheck.parts import kind_of

    if scene.mesh.size is not None:
        for name, geo in geometries.items():
            side = min(kind_of(name).section(geo))
            if scene.mesh.size > 2 * side:
                raise InputError("mesh.size", f"{scene.mesh.size*1e3:g} mm is more than twice {name}'s "
                                              f"{side*1e3:g} mm section: too coarse to resolve its stress")
    for geo in geometries.values():
        refuse_beyond_memory(geo, *mesh_sizes(scene, geo.kind), scene.mesh.order, "mesh.size")


def refuse_beyond_memory(geo, size: float, hole_size: float, order: int, field: str) -> None:
    """Raise InputError naming ``field`` when meshing ``geo`` at these sizes (m) would
    need more memory than this machine has (estimated before meshing)."""
    from railcheck.fea.elasticity import estimate_dofs
    from railcheck.fea.solvers import available_memory
    from railcheck.geometry.mesher import estimate_elements

    tets = estimate_elements(geo, size, hole_size)
    dofs = estimate_dofs(tets // 5, tets, order)
    need, avail = dofs * BYTES_PER_DOF_AMG, available_memory()
    if need > 0.8 * avail:
        raise InputError(field, f"about {dofs/1e6:.1f} M DOFs needing about {need/2**30:.1f} GiB, more than "
                                f"this machine's {avail/2**30:.1f} GiB allow: use a larger mesh size")


#: peak memory per DOF of a P2 solve on the iterative path (assembly, AMG hierarchy, stress
#: projection), bytes; measured on a 1000 mm rail at 145k DOFs (README, "What railcheck
#: refuses"). The direct path falls back to it when its factor would not fit.
BYTES_PER_DOF_AMG = 11_000
