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

from railcheck.base.errors import EXIT_FAIL, EXIT_PASS, InputError
from railcheck.check.pipeline import run_pipeline
from railcheck.check.summary import summary_of
from railcheck.components.scene_checks import components_input, listed_joint_paths
from railcheck.fea.vtk import pvd_text
from railcheck.files import Staging, atomic_path, atomic_write_text, reserve_results_dir, results_dir, to_json
from railcheck.model.records import PartResult, PipelineResult
from railcheck.progress import Progress
from railcheck.report.html import write_report
from railcheck.report.joint_diagram import write_joint_diagram
from railcheck.report.linkage_picture import write_linkage_picture
from railcheck.report.plots import write_campbell_plot, write_cycle_plot, write_kinematics_plots
from railcheck.report.render import render_part
from railcheck.report.utilisation_picture import render_utilisation
from railcheck.report.vtu import write_part_vtu
from railcheck.scene import OutputSpec, Scene


@dataclass(frozen=True)
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


def say_target(progress: Progress, requested: Path, target: Path) -> None:
    """First, when the results go elsewhere than asked (the directory exists): say where,
    so a report open in a browser is not taken for this run's."""
    if Path(target) != Path(requested):
        progress.say("output", f"{requested}/ exists: this run's results go to {target}/ (--force replaces it)")


def run_check(
    scene: Scene, out: str | None = None, force: bool = False, progress: Progress | None = None, jobs: int | None = None
) -> CheckRun:
    """Reserve the results directory, run the pipeline, write every output into a staging
    directory and rename it into place (see :mod:`railcheck.files`). ``jobs``: parts
    checked at once (:mod:`railcheck.check.workers`)."""
    requested = results_dir(scene.output.dir if out is None else out, "output.dir" if out is None else "--out")
    try:
        target, replaces = reserve_results_dir(requested, force)
        staging = Staging(target, replaces)
    except OSError as exc:
        raise InputError("output.dir", f"cannot write results at {requested}: {exc.strerror or exc}") from None
    progress = progress or Progress(quiet=True)
    say_target(progress, requested, target)
    try:
        result = run_pipeline(
            scene, progress, jobs=jobs, part_done=functools.partial(write_part_files, scene.output, directory=staging.path)
        )
        summary = summary_of(result)
        write_outputs(scene, result, summary, staging.path)
        progress.say("report", f"wrote {len(result.parts)} parts")
        staging.commit()
    except BaseException:
        staging.abandon()
        raise
    return CheckRun(result, summary, target, requested)


def write_outputs(scene: Scene, result: PipelineResult, summary: dict, directory: Path) -> None:
    """summary.json, timings.json, the kinematics plots and the linkage, per part its VTU, its picture
    and its cycle plot, as the scene's [output] asks, and report.html with all of them."""
    atomic_write_text(directory / "summary.json", to_json(summary) + "\n")
    atomic_write_text(directory / "timings.json", to_json(result.timings) + "\n")
    if result.kinematics is not None and scene.output.plots:
        write_kinematics_plots(result.kinematics, directory)
        write_linkage_picture(directory / "linkage.png", result.kinematics.motion, result.kinematics.dynamics)
    if scene.output.plots:
        write_campbell_plot(result.parts, directory / "campbell.png")
    if scene.output.plots and result.components and result.kinematics is not None:
        paths = listed_joint_paths(components_input(scene), result.kinematics)
        write_joint_diagram(directory / "joints.png", paths, result.components, scene.checked.factor)
    if scene.output.vtk and result.parts:
        atomic_write_text(directory / "parts.pvd", pvd_text({n: f"{n}.vtu" for n in result.parts}))
    for name, p in result.parts.items():
        if not (directory / f"{name}.written").exists():  # not already written as the part finished
            write_part_files(scene.output, name, p, directory)
        (directory / f"{name}.written").unlink(missing_ok=True)
    with atomic_path(directory / "report.html") as tmp:
        write_report(tmp, scene, result, summary, directory)


def write_part_files(output: OutputSpec, name: str, p: PartResult, directory: Path) -> None:
    """One part's files, as the scene's [output] asks: its VTU, its cycle plot and its
    picture; then a ``NAME.written`` marker (removed by :func:`write_outputs`). Called as
    each part finishes, in the worker that checked it (:mod:`railcheck.check.workers`)."""
    if output.vtk:
        write_part_vtu(directory / f"{name}.vtu", p)
    if output.plots and p.cycle.C.shape[0] > 1:
        write_cycle_plot(name, p, directory / f"{name}-cycle.png")
    if output.png:
        render_part(directory / f"{name}.png", name, p, output.stress_scale)
        render_utilisation(directory / f"{name}-utilisation.png", name, p)
    (directory / f"{name}.written").touch()
