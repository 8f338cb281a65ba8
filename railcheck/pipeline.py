"""The check pipeline: scene -> kinematics -> loads -> geometry -> mesh -> solve -> stress
-> report, running only the stages the requested outputs need.

* A scene without a [check] table stops after kinematics: gmsh, skfem and pyvista are
  never imported.
* A scene whose parts all have explicit [loads] never runs the linkage.
* Gravity is applied only when check.effects lists it; inertia only with a non-zero speed.

``stages_run`` records, in order, each stage that ran.
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from .errors import InputError
from .kinematics_stage import KinematicsResult, kinematics_summary, run_kinematics
from .scene import Scene

#: default (size, hole size) in m per part kind, from the accuracy-versus-time study
#: (README, "What accuracy costs"): the coarsest P2 mesh within 1% of the converged tip
#: deflection and 5% of the converged peak von Mises away from the support
DEFAULT_MESH = {"rail": (20e-3, 6e-3), "joint_plate": (6e-3, 1.8e-3), "i_profile": (4.2e-3, 1.26e-3)}


def mesh_sizes(scene, kind: str) -> tuple[float, float]:
    """(size, hole size) in m for a part kind: the scene's [mesh], else the default."""
    if scene.mesh.size is None:
        return DEFAULT_MESH[kind]
    return scene.mesh.size, scene.mesh.hole_size or 0.3 * scene.mesh.size


STAGES = ("scene", "kinematics", "loads", "geometry", "mesh", "solve", "stress", "report")

SUPPORT = {"rail": "shaft_hole", "joint_plate": "bearing_seat", "i_profile": "base"}


def support_exclusion(geo) -> float:
    """Distance (m) from the support within which the idealised clamp's singular stress is
    reported apart from the verdict: one bolt-hole diameter (rails, PF_4b_006), one
    flange thickness (PF_4b_003_v2)."""
    p = dict(geo.params)
    return {"rail": p.get("hole_diameter"), "joint_plate": p.get("bolt_diameter"),
            "i_profile": p.get("flange_thickness")}[geo.kind]
PART_KIND = {"crank-rail": "rail", "coupler-rail": "rail", "rocker-rail": "rail",
             "PF_4b_006": "joint_plate", "PF_4b_003_v2": "i_profile"}


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
    name: str
    load_case: object
    mesh: object
    solution: object
    limit: float
    geometry: object

    @property
    def verdict_stress(self) -> float:
        """Pa: the peak von Mises away from the support's singular edge (see README)."""
        return self.solution.max_von_mises_away

    @property
    def passed(self) -> bool:
        return self.verdict_stress <= self.limit


@dataclass
class PipelineResult:
    scene: Scene
    stages_run: list[str] = field(default_factory=list)
    kinematics: KinematicsResult | None = None
    kinematics_summary: dict | None = None
    parts: dict[str, PartResult] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        return all(p.passed for p in self.parts.values())


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
    from geometry.catalogue import with_overrides
    from geometry.models import i_profile, joint_plate, rail
    from kinematics.massmodel import MassModel

    rail_spec, plate_spec, iprof_spec = with_overrides(scene.geometry)
    masses = MassModel()
    lengths = {"crank-rail": masses.crank_rail_length, "coupler-rail": masses.coupler_rail_length,
               "rocker-rail": masses.rocker_rail_length}
    out = {}
    for name in scene.check.parts:
        if name in lengths:
            out[name] = rail(lengths[name], rail_spec)
        elif name == "PF_4b_006":
            out[name] = joint_plate(plate_spec)
        else:
            out[name] = i_profile(iprof_spec)
    return out


def build_load_cases(scene: Scene, kin: KinematicsResult | None, geometries: dict) -> dict:
    """The load case of every checked part (loads stage)."""
    from loads.cases import explicit_load_case, rail_bolt_holes, reaction_load_case

    check = scene.check
    cases = {}
    for name in check.parts:
        geo = geometries[name]
        kind = PART_KIND[name]
        holes = [g for g in geo.groups if g.startswith("hole_")]
        tip = "end_free"
        if name in check.loads:
            load = check.loads[name]
            targets = holes if kind != "rail" else [f"hole_{k}" for k in rail_bolt_holes(
                list(geo.get("hole_x")), geo.get("hole_x")[0], 0.0, "worst")]
            cases[name] = explicit_load_case(name, load.longitudinal, load.transverse, targets, SUPPORT[kind], tip)
            continue
        motion, dyn = kin.motion, kin.dynamics
        th = motion.theta
        if kind == "rail":
            bar = {"crank-rail": ("crank", "A", -dyn.reactions["A"], th[:, 0]),
                   "coupler-rail": ("coupler", "B", -dyn.reactions["B"], th[:, 1]),
                   "rocker-rail": ("rocker", "B", dyn.reactions["B"], th[:, 2])}[name]
            length = scene.mechanism.linkage.lengths[bar[0]]
            xs = list(geo.get("hole_x"))
            try:
                idx = rail_bolt_holes(xs, xs[0], length, check.bolt_position)
            except ValueError as exc:
                raise InputError(f"mechanism.{bar[0]}", str(exc)) from None
            cases[name] = reaction_load_case(name, bar[1], bar[2], bar[3], motion.theta2, check.factor,
                                             [f"hole_{k}" for k in idx], SUPPORT[kind], tip)
        elif kind == "joint_plate":
            # the plate at the moving joint with the larger peak: A (on the crank) or B (on the coupler)
            pa, pb = dyn.peak("A")[0], dyn.peak("B")[0]
            joint, force, angle = ("A", -dyn.reactions["A"], th[:, 0]) if pa >= pb else \
                ("B", -dyn.reactions["B"], th[:, 1])
            cases[name] = reaction_load_case(name, joint, force, angle, motion.theta2, check.factor,
                                             holes, SUPPORT[kind], tip)
        else:
            # the I-profiles carry the rocker's pivot O4 to the ground: ground frame
            if "O4" not in dyn.reactions:
                raise InputError("check.parts", "PF_4b_003_v2 carries O4: give explicit [loads.PF_4b_003_v2] "
                                                "for a slider-crank")
            cases[name] = reaction_load_case(name, "O4", dyn.reactions["O4"], np.zeros(motion.steps),
                                             motion.theta2, check.factor, holes, SUPPORT[kind], tip)
    return cases


def run_pipeline(scene: Scene, progress: Progress | None = None, solver: str = "auto") -> PipelineResult:
    """Run the stages the scene needs; see the module doc."""
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
    if scene.check is None:
        _mark(result, "report")
        return result

    from fea.materials import MATERIALS, limit_warning

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

    gravity_on = "gravity" in scene.check.effects
    from fea.elasticity import HoleLoad, Support, solve_elasticity
    from geometry.mesher import mesh_part

    _mark(result, "geometry")
    n = len(cases)
    for i, (name, case) in enumerate(cases.items(), 1):
        geo = geometries[name]
        t = time.perf_counter()
        size, hole = mesh_sizes(scene, geo.kind)
        mesh = mesh_part(geo, size, hole, optimize=scene.mesh.optimize)
        result.timings[f"mesh:{name}"] = time.perf_counter() - t
        _mark(result, "mesh")
        if mesh.slivers:
            result.warnings.append(f"{name}: {mesh.slivers} sliver elements (gmsh minSICN < 0.05, worst "
                                   f"{mesh.min_quality:.3f}); stresses near them are unreliable")
        progress.say("mesh", f"({i}/{n}) {name}: {mesh.tets.shape[0]} tetrahedra"
                              f"{' (cached)' if mesh.cached else ''}, min quality {mesh.min_quality:.2f}")
        body = None
        if gravity_on:
            angle = math.radians(case.origin.get("bar_angle_deg", 0.0))
            g = 9.80665 * material.density
            body = np.array([-math.sin(angle) * g, -math.cos(angle) * g, 0.0])
        t = time.perf_counter()
        sol = solve_elasticity(mesh.points, mesh.tets, mesh.groups, material, [Support(case.support)],
                               [HoleLoad(b.group, b.force) for b in case.bolts], order=scene.mesh.order,
                               tip_group=case.tip_group, solver=solver, body_force=body,
                               exclude_distance=support_exclusion(geo))
        result.timings[f"solve:{name}"] = time.perf_counter() - t
        _mark(result, "solve")
        _mark(result, "stress")
        result.warnings += [f"{name}: {m}" for m in sol.warnings]
        progress.say("solve", f"({i}/{n}) {name}: {sol.dofs} DOFs, {sol.solver.get('solver')}, "
                              f"max von Mises {sol.max_von_mises_away/1e6:.1f} MPa away from the support "
                              f"({sol.max_von_mises/1e6:.1f} MPa at it)")
        result.parts[name] = PartResult(name, case, mesh, sol, limit, geo)
    _mark(result, "report")
    return result


def _refuse_huge(scene: Scene, geometries: dict) -> None:
    """Estimate DOFs and memory before meshing; refuse what this machine cannot hold."""
    from fea.elasticity import estimate_dofs
    from geometry.mesher import estimate_elements

    worst = 0
    for geo in geometries.values():
        size, hole = mesh_sizes(scene, geo.kind)
        tets = estimate_elements(geo, size, hole)
        worst = max(worst, estimate_dofs(tets // 5, tets, scene.mesh.order))
    from fea.solvers import DIRECT_LIMIT
    need = worst * (BYTES_PER_DOF_DIRECT if worst <= DIRECT_LIMIT else BYTES_PER_DOF_AMG)
    avail = available_memory()
    if need > 0.8 * avail:
        raise InputError("mesh.size", f"about {worst/1e6:.1f} M DOFs needing about {need/2**30:.1f} GiB, more than "
                                      f"this machine's {avail/2**30:.1f} GiB allow: use a larger mesh size")


#: peak memory per DOF of a P2 solve (assembly, LU factors or AMG hierarchy, stress
#: projection), bytes; measured on a 1000 mm rail at 145k DOFs (README, "What railcheck refuses")
BYTES_PER_DOF_DIRECT = 20_000
BYTES_PER_DOF_AMG = 11_000


def available_memory() -> float:
    try:
        import os
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return 8 * 2**30
