"""`railcheck check`: the main job. Runs the pipeline and writes the results directory
(:func:`run_check`); the CLI prints the tables.

The results are written into a staging directory beside the target and renamed into
place at the end, so a failed run leaves no half-written results and never touches
earlier ones. An existing results directory is never overwritten silently: a new run
goes to ``DIR-2``, ``DIR-3``, ... unless ``--force``.

``summary.json`` holds no timings, so the same scene gives a byte-identical summary;
timings go to ``timings.json``.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from railcheck.check.pipeline import PipelineResult, Progress, mesh_sizes, run_pipeline
from railcheck.errors import EXIT_FAIL, EXIT_PASS, InputError
from railcheck.fea.elasticity import von_mises
from railcheck.files import Staging, atomic_path, atomic_write_text, reserve_results_dir
from railcheck.report.text import to_json


def summary_of(result: PipelineResult) -> dict:
    """The summary.json content (deterministic: no timings)."""
    scene = result.scene
    parts = {}
    for name, p in result.parts.items():
        parts[name] = part_summary(scene, p)
    out = {
        "verdict": "FAIL" if result.failures else ("PASS" if result.parts else "NO CHECK"),
        "failures": result.failures,
        "parts": parts,
        "stages_run": list(result.stages_run),
        "warnings": list(result.warnings),
    }
    if scene.check is not None:
        out["material"] = scene.check.material
        out["effects"] = list(scene.check.effects)
    if any(p.geometry.kind == "rail" for p in result.parts.values()):
        out["rail_mass_per_m_kg"] = rail_masses(scene)
    if result.kinematics_summary is not None:
        out["kinematics"] = result.kinematics_summary
    out["scene"] = scene.raw
    out["scene_source"] = scene.source
    return out


def part_summary(scene, p) -> dict:
    """One part's entry of summary.json (SI; the envelope governs ``max_von_mises_Pa``)."""
    s, cyc = p.solution, p.cycle
    env = cyc.envelope
    fatigue = {k: v for k, v in cyc.fatigue.items() if k != "node_factor"}
    return {
        "max_von_mises_Pa": env.max_von_mises,
        "max_von_mises_location_m": [float(x) for x in env.location],
        "crank_angle_deg": cyc.history["crank_angle_deg"],
        "support_peak_von_mises_Pa": env.support_peak,
        "support_exclusion_m": s.exclude_distance,
        "tip_deflection_m": env.max_tip,
        "max_deflection_m": p.deflection_limit,
        "deflection_pass": bool(p.deflection_passed),
        "limit_Pa": p.limit,
        "utilisation": p.verdict_stress / p.limit,
        "factor_of_safety": p.limit / p.verdict_stress if p.verdict_stress > 0 else None,
        "pass": bool(p.passed),
        "envelope": {"max_von_mises_Pa": env.max_von_mises, "crank_angle_deg": cyc.history["crank_angle_deg"],
                     "location_m": [float(x) for x in env.location], "max_tip_deflection_m": env.max_tip,
                     "joint": cyc.source},
        "seed_method": {**cyc.seed_method,
                        "ratio_envelope_to_seed": (env.max_von_mises / cyc.seed_method["max_von_mises_Pa"]
                                                   if cyc.seed_method["max_von_mises_Pa"] > 0 else None)},
        "fatigue": fatigue,
        "load_case": {"support": p.load_case.support, "tip": p.load_case.tip_group,
                      "factor": p.load_case.factor, **p.load_case.origin,
                      "bolts": {b.group: list(b.force) for b in p.load_case.bolts}},
        "unit_cases": list(cyc.fields.names),
        "mesh": {"order": s.order, "size_m": mesh_sizes(scene, p.geometry.kind)[0],
                 "hole_size_m": mesh_sizes(scene, p.geometry.kind)[1],
                 "dofs": s.dofs, "elements": s.elements, "min_quality": p.mesh.min_quality,
                 "slivers": p.mesh.slivers, "solver": cyc.meta["solver"].get("solver")},
    }


def rail_masses(scene) -> dict:
    """kg/m of the modelled rail section beside the seed's and the catalogue's figures."""
    from railcheck.geometry.catalogue import (
        CATALOGUE_RAIL_MASS,
        rail_mass_per_metre,
        rail_mass_per_metre_with_holes,
        with_overrides,
    )
    rail = with_overrides(scene.geometry)[0]
    return {"model_section": rail_mass_per_metre(rail), "model_with_holes": rail_mass_per_metre_with_holes(rail),
            **CATALOGUE_RAIL_MASS}


@dataclass
class CheckRun:
    """A finished ``railcheck check``: the pipeline's result, the summary written, where
    the results went, and the directory asked for."""

    result: PipelineResult
    summary: dict
    target: Path
    requested: Path

    @property
    def exit_status(self) -> int:
        return EXIT_FAIL if self.result.failures else EXIT_PASS


def run_check(scene, out: str | None = None, force: bool = False, progress: Progress | None = None,
              jobs: int | None = None) -> CheckRun:
    """Reserve the results directory, run the pipeline, write every output into a staging
    directory and rename it into place (see :mod:`railcheck.files`). ``jobs``: parts
    checked at once (:mod:`railcheck.check.workers`)."""
    requested = Path(out or scene.output.dir)
    try:
        target, replaces = reserve_results_dir(requested, force)
        staging = Staging(target, replaces)
    except OSError as exc:
        raise InputError("output.dir", f"cannot write results at {requested}: {exc.strerror or exc}") from None
    progress = progress or Progress(quiet=True)
    try:
        result = run_pipeline(scene, progress, jobs=jobs,
                              part_done=functools.partial(write_part_files, scene, directory=staging.path))
        summary = summary_of(result)
        write_outputs(scene, result, summary, staging.path)
        progress.say("report", f"wrote {len(result.parts)} parts")
        staging.commit()
    except BaseException:
        staging.abandon()
        raise
    return CheckRun(result, summary, target, requested)


def write_outputs(scene, result: PipelineResult, summary: dict, directory: Path) -> None:
    """summary.json, timings.json, the kinematics plots, per part its VTU, its picture
    and its cycle plot, as the scene's [output] asks, and report.html with all of them."""
    atomic_write_text(directory / "summary.json", to_json(summary) + "\n")
    atomic_write_text(directory / "timings.json", to_json(result.timings) + "\n")
    if result.kinematics is not None and scene.output.plots:
        from railcheck.report.plots import write_kinematics_plots
        write_kinematics_plots(result.kinematics, directory)
    if scene.output.vtk and result.parts:
        from railcheck.fea.vtk import pvd_text
        atomic_write_text(directory / "parts.pvd", pvd_text({n: f"{n}.vtu" for n in result.parts}))
    for name, p in result.parts.items():
        if not (directory / f"{name}.written").exists():      # not already written as the part finished
            write_part_files(scene, name, p, directory)
        (directory / f"{name}.written").unlink(missing_ok=True)
    from railcheck.report.html import write_report
    with atomic_path(directory / "report.html") as tmp:
        write_report(tmp, scene, result, summary, directory)


def write_part_files(scene, name: str, p, directory: Path) -> None:
    """One part's files, as the scene's [output] asks: its VTU, its cycle plot and its
    picture; then a ``NAME.written`` marker (removed by :func:`write_outputs`). Called as
    each part finishes, in the worker that checked it (:mod:`railcheck.check.workers`)."""
    if scene.output.vtk:
        write_part_vtu(directory / f"{name}.vtu", p)
    if scene.output.plots and p.cycle.C.shape[0] > 1:
        from railcheck.report.plots import write_cycle_plot
        write_cycle_plot(name, p, directory / f"{name}-cycle.png")
    if scene.output.png:
        from railcheck.report.render import render_part
        render_part(directory / f"{name}.png", name, p)
    (directory / f"{name}.written").touch()


def write_part_vtu(path: Path, p) -> None:
    """The part's VTU on every node of its order: the governing instant's displacement,
    stress and von Mises, the cycle envelope, the fatigue factor, and 0/1 masks of the
    support, the loaded holes and the verdict zone (away from the support)."""
    from railcheck.fea.vtk import write_vtu

    f, s = p.cycle.fields, p.solution
    n = f.nodes.shape[0]
    masks = {name: np.isin(np.arange(n), idx).astype(float)
             for name, idx in (("support_surface", f.support), ("loaded_holes", f.loaded))}
    with atomic_path(path) as tmp:
        write_vtu(tmp, f.nodes, f.cells, s.node_displacement, von_mises(s.stress),
                  {"stress": s.stress.T, "von_mises_envelope": p.cycle.envelope.node_envelope,
                   "fatigue_safety_factor": p.cycle.fatigue["node_factor"],
                   "verdict_zone": f.verdict_mask.astype(float), **masks})
