"""The check pipeline: scene -> kinematics -> loads -> geometry -> mesh -> solve -> stress
-> report, running only the stages the requested outputs need.

* A scene without a [check] table stops after kinematics: gmsh, skfem and pyvista are
  never imported.
* A scene whose parts all have explicit [loads] never runs the linkage.
* Gravity is applied only when check.effects lists it; inertia only with a non-zero speed.

The scene is resolved here, once, into one :class:`~railcheck.model.jobs.PartJob` per
part; the parts' checks (:mod:`railcheck.check.workers`) take the jobs.
``stages_run`` records, in order, each stage that ran.
"""

from __future__ import annotations

import time

import numpy as np

from railcheck.check.margins import SafeSpeed, components_safe_speed, failing_parts_safe_speeds, safe_speed
from railcheck.check.workers import check_parts
from railcheck.components.scene_checks import check_listed_components, components_input
from railcheck.fea.materials import MATERIALS, limit_warning
from railcheck.model.inputs import parts_input
from railcheck.model.jobs import build_load_cases, part_geometries, part_jobs, refuse_unresolvable_meshes
from railcheck.model.kinematics_stage import all_checks, kinematics_input, kinematics_summary, run_kinematics
from railcheck.model.memory import refuse_recovery_before_meshing
from railcheck.model.records import PipelineResult
from railcheck.progress import Progress
from railcheck.scene import Scene

STAGES = ("scene", "kinematics", "components", "loads", "geometry", "mesh", "solve", "stress", "report")


def needs_linkage(scene: Scene) -> bool:
    """True when some requested output depends on the linkage's reactions."""
    if scene.check is None:
        return scene.mechanism is not None
    return bool(scene.checked.components) or any(p not in scene.checked.loads for p in scene.checked.parts)


def unused_component_keys(scene: Scene) -> list[str]:
    """A warning when the scene's ``[components]`` table sets values that no listed
    component reads (``[check] parts`` lists none): said, not silently dropped."""
    table = scene.raw.get("components") if isinstance(scene.raw, dict) else None
    listed = scene.check.components if scene.check is not None else ()
    if not table or listed:
        return []
    keys = ", ".join(sorted(table))
    return [f"[components] sets {keys}, but [check] parts lists no component: nothing reads them"]


def run_pipeline(
    scene: Scene, progress: Progress | None = None, solver: str = "auto", jobs: int | None = None, part_done=None
) -> PipelineResult:
    """Run the stages the scene needs; see the module doc. ``part_done(name, part)``, a
    picklable callable, runs as each part finishes, where it was checked (its files)."""
    progress = progress or Progress(quiet=True)
    stages, warnings, timings = ["scene"], unused_component_keys(scene), {}
    progress.say("scene", scene.source)
    kin = kin_summary = None
    if needs_linkage(scene):
        t = time.perf_counter()
        kin = run_kinematics(kinematics_input(scene))
        kin_summary = kinematics_summary(scene.linkage_spec, kin)
        warnings += list(kin.motion.warnings)
        timings["kinematics"] = time.perf_counter() - t
        stages.append("kinematics")
        progress.say(
            "kinematics",
            f"{scene.linkage_spec.steps} steps, {kin.dynamics.formulation}, effects: {', '.join(kin.effects) or 'none'}",
        )
    if kin is not None:
        checks = dict(kin.checks)
    elif scene.mechanism is not None:  # closed-form geometry only: the linkage is not run
        inputs = kinematics_input(scene)
        checks = all_checks(inputs.mechanism.linkage, inputs.rail)
    else:
        checks = {}
    parts: dict = {}
    unloaded: tuple[str, ...] = ()
    components, components_safe = _components_stage(scene, kin, progress, stages, timings)
    if scene.check is not None and scene.checked.parts:
        parts, unloaded = _check_stage(scene, kin, progress, solver, jobs, part_done, stages, warnings)
        for name, part in parts.items():
            timings.update({f"{k}:{name}": v for k, v in part.seconds.items()})
    t = time.perf_counter()
    parts_safe, every_safe = _margins_stage(scene, parts, components_safe, progress)
    timings["margins"] = time.perf_counter() - t
    stages.append("report")
    return PipelineResult(
        scene=scene,
        stages_run=tuple(stages),
        kinematics=kin,
        kinematics_summary=kin_summary,
        parts=parts,
        components=components,
        components_safe_speed=components_safe,
        parts_safe_speed=parts_safe,
        safe_speed=every_safe,
        warnings=tuple(warnings),
        timings=timings,
        checks=checks,
        unloaded=unloaded,
    )


def _components_stage(scene: Scene, kin, progress: Progress, stages: list, timings: dict) -> tuple[dict, SafeSpeed | None]:
    """(components, their safe speed): the joints' components checked by their standards
    (empty, None without ``[check] components``); the stage and its time appended."""
    if scene.check is None or not scene.checked.components:
        return {}, None
    t = time.perf_counter()
    inputs = components_input(scene)
    components = check_listed_components(inputs, kin)
    safe_speed = components_safe_speed(kinematics_input(scene), inputs)
    timings["components"] = time.perf_counter() - t
    stages.append("components")
    progress.say("components", f"{len(components)} checked by their standards (load factor on pins, screws, shafts)")
    return components, safe_speed


def _margins_stage(
    scene: Scene, parts: dict, components: SafeSpeed | None, progress: Progress
) -> tuple[dict, SafeSpeed | None]:
    """(failing parts' safe speeds, the check's one safe speed): none without a [check] or a
    [mechanism] (nothing the speed moves is checked); ``parts`` name -> PartResult,
    ``components`` the components' safe speed."""
    if scene.check is None or scene.mechanism is None:
        return {}, None
    inputs, kinematics = parts_input(scene), kinematics_input(scene)
    failing = failing_parts_safe_speeds(inputs, kinematics, parts, progress)
    return failing, safe_speed(inputs, kinematics, parts, components, failing, progress)


def _check_stage(
    scene: Scene, kin, progress: Progress, solver: str, jobs: int | None, part_done, stages: list, warnings: list
) -> tuple[dict, tuple[str, ...]]:
    """(parts, unloaded): the loads, geometry and FE stages of the scene's [check], each
    part resolved into its job and checked (those that carry no load are named in
    ``warnings`` and left out); the stages run and the warnings appended to ``stages``
    and ``warnings``."""
    material = MATERIALS[scene.checked.material]
    limit = scene.checked.limit or material.fatigue_limit
    w = limit_warning(material, scene.checked.limit)
    if w:
        warnings.append(w)
    inputs = parts_input(scene)
    geometries = part_geometries(inputs)
    cases = build_load_cases(inputs, kin, geometries)
    stages.append("loads")
    progress.say("loads", f"{len(cases)} load cases, factor {scene.checked.factor:g}, support {scene.checked.support}")
    refuse_unresolvable_meshes(inputs, geometries)
    stages.append("geometry")
    all_jobs = part_jobs(inputs, kin, geometries, cases, material, limit)
    unloaded = tuple(name for name, job in all_jobs.items() if not carries_load(job))
    for name in unloaded:
        warnings.append(f"{name}: {NO_LOAD}")
        progress.say("loads", f"{name}: {NO_LOAD}")
    loaded = {name: job for name, job in all_jobs.items() if name not in unloaded}
    refuse_recovery_before_meshing(loaded)
    parts: dict = {}
    if loaded:
        parts = check_parts(loaded, solver, progress, jobs, part_done)
        stages += ["mesh", "solve", "stress"]
    warnings += [f"{name}: {w}" for name, part in parts.items() for w in part.warnings]
    return parts, unloaded


#: why a part is not meshed or solved
NO_LOAD = "carries no load (no speed, no gravity and no explicit load): nothing to check; not meshed or solved"


def carries_load(job) -> bool:
    """True when some load history of the part is not zero at every step."""
    return any(np.any(h.C) for h in job.histories)
