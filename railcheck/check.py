"""`railcheck check`: the main job. Runs the pipeline, writes the results directory and
prints a verdict table per part.

The results are written into a staging directory beside the target and renamed into
place at the end, so a failed run leaves no half-written results and never touches
earlier ones. An existing results directory is never overwritten silently: a new run
goes to ``DIR-2``, ``DIR-3``, ... unless ``--force``.

``summary.json`` holds no timings, so the same scene gives a byte-identical summary;
timings go to ``timings.json``.
"""

from __future__ import annotations

import math
import os
import shutil
import sys
import tempfile
from pathlib import Path

from .atomic import atomic_write_text
from .errors import EXIT_FAIL, EXIT_PASS, InputError
from .pipeline import PipelineResult, Progress, mesh_sizes, run_pipeline
from .report import kinematics_table, to_json
from .scene import load_scene


def choose_output_dir(requested: Path, force: bool) -> Path:
    """The directory this run will produce: ``requested`` if free (or ``force``), else
    the first free ``requested-N``."""
    if requested.exists() and not requested.is_dir():
        raise InputError("output.dir", f"{requested} exists and is not a directory")
    if force or not requested.exists():
        return requested
    k = 2
    while Path(f"{requested}-{k}").exists():
        k += 1
    return Path(f"{requested}-{k}")


def _check_writable(parent: Path) -> None:
    probe = parent
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir():
        raise InputError("output.dir", f"{probe} is not a directory")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise InputError("output.dir", f"{probe} is not writable")


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
    from geometry.catalogue import CATALOGUE_RAIL_MASS, rail_mass_per_metre, rail_mass_per_metre_with_holes, \
        with_overrides
    rail = with_overrides(scene.geometry)[0]
    return {"model_section": rail_mass_per_metre(rail), "model_with_holes": rail_mass_per_metre_with_holes(rail),
            **CATALOGUE_RAIL_MASS}


def parts_table(result: PipelineResult) -> str:
    """The console table: the cycle envelope's peak and where in the cycle, the seed
    method's single instant beside it, the fatigue factor, and each verdict."""
    lines = [f"  {'part':<14}{'cycle max vM':>14}{'at crank':>10}{'seed inst.':>12}{'tip defl.':>11}{'limit':>9}"
             f"{'FoS':>8}{'fatigue n':>11}  {'verdict':<8}{'peak at x, y, z (mm)':<24}{'at support*':>12}"]
    for name, p in result.parts.items():
        c = p.cycle
        loc = ", ".join(f"{x*1e3:.1f}" for x in c.envelope.location)
        fos = p.limit / p.verdict_stress if p.verdict_stress > 0 else math.inf
        why = [] if p.stress_passed else ["stress"]
        why += [] if p.fatigue_passed else ["fatigue"]
        lines.append(f"  {name:<14}{p.verdict_stress/1e6:>10.1f} MPa{c.history['crank_angle_deg']:>7.1f} deg"
                     f"{c.seed_method['max_von_mises_Pa']/1e6:>8.1f} MPa{c.envelope.max_tip*1e3:>8.2f} mm"
                     f"{p.limit/1e6:>5.0f} MPa{_fmt(fos):>8}{_fmt(c.fatigue['min_safety_factor']):>11}  "
                     f"{'PASS' if p.passed else 'FAIL ' + '+'.join(why):<8}{loc:<24}"
                     f"{c.envelope.support_peak/1e6:>8.1f} MPa")
    lines.append("  cycle max vM: the largest von Mises over the whole crank cycle (superposed unit cases); seed inst.: "
                 "at the instant of the peak |reaction| (seed 000's method); FoS = limit / cycle max; fatigue n: "
                 "minimum fatigue safety factor (Shigley 6-14 with the [fatigue] criterion)")
    lines.append("  * the peak at the idealised clamped support grows with mesh refinement (a singularity); the "
                 "verdict uses the peak farther than one hole diameter from it")
    return "\n".join(lines)


def _fmt(x: float) -> str:
    return "inf" if not math.isfinite(x) else f"{x:.2f}"


def _make_staging(target: Path) -> Path:
    """Create the staging directory beside ``target`` now, before any work, so that an
    unusable output location fails at once (exit 2) and nothing is half-written."""
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        return Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    except OSError as exc:
        raise InputError("output.dir", f"cannot write results beside {target}: {exc.strerror or exc}") from None


def run_check_command(args) -> int:
    scene = load_scene(args.scene)
    requested = Path(args.out or scene.output.dir)
    _check_writable(requested.parent if str(requested.parent) else Path("."))
    target = choose_output_dir(requested, args.force)
    staging = _make_staging(target)
    try:
        progress = Progress(quiet=False)
        result = run_pipeline(scene, progress)
        summary = summary_of(result)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    try:
        atomic_write_text(staging / "summary.json", to_json(summary) + "\n")
        atomic_write_text(staging / "timings.json", to_json(result.timings) + "\n")
        if result.kinematics is not None and scene.output.plots:
            from .plots import write_kinematics_plots
            write_kinematics_plots(result.kinematics, staging)
        if result.parts:
            from fea.vtk import write_vtu
            for name, p in result.parts.items():
                nv = p.mesh.points.shape[0]
                if scene.output.vtk:
                    write_vtu(staging / f"{name}.vtu", p.mesh.points, p.mesh.tets, p.solution.displacement,
                              p.solution.von_mises,
                              {"von_mises_envelope": p.cycle.envelope.node_envelope[:nv],
                               "fatigue_safety_factor": p.cycle.fatigue["node_factor"][:nv]})
                if scene.output.plots and p.cycle.C.shape[0] > 1:
                    from .plots import write_cycle_plot
                    write_cycle_plot(name, p, staging / f"{name}-cycle.png")
            if scene.output.png:
                from .render import render_part
                for name, p in result.parts.items():
                    render_part(staging / f"{name}.png", name, p)
            progress.say("report", f"wrote {len(result.parts)} parts")
        if target.exists():          # --force: swap the old directory out only now
            old = Path(tempfile.mkdtemp(prefix=f".{target.name}.old.", dir=target.parent))
            os.replace(target, old / target.name)
            os.replace(staging, target)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(staging, target)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise

    if args.json:
        print(to_json(summary))
    else:
        print(f"scene: {scene.source}")
        if result.kinematics_summary is not None:
            print(kinematics_table(result.kinematics_summary))
            print()
        if result.parts:
            c = scene.check
            sizes = sorted({mesh_sizes(scene, p.geometry.kind) for p in result.parts.values()}, reverse=True)
            sizes = ", ".join(f"{a*1e3:g} mm (holes {b*1e3:.3g} mm)" for a, b in sizes)
            print(f"FE check: material {c.material}, factor {c.factor:g}, bolts {c.bolt_position}, "
                  f"P{scene.mesh.order} tetrahedra, size {sizes}")
            print(parts_table(result))
            if "rail_mass_per_m_kg" in summary:
                m = summary["rail_mass_per_m_kg"]
                print(f"  rail mass: modelled section {m['model_section']:.2f} kg/m ({m['model_with_holes']:.2f} with "
                      f"its holes; solid rectangle, grooves omitted), HIWIN HGR25 {m['HIWIN HGR25 catalogue']:.2f} "
                      f"kg/m, seed {m['seed 000 (Anexo I)']:.2f} kg/m (used by the dynamics)")
            for w in result.warnings:
                if w not in (result.kinematics_summary or {}).get("warnings", []):
                    print(f"warning: {w}")
        print(f"stages run: {', '.join(result.stages_run)}")
        reasons = f" ({'; '.join(result.failures)})" if result.failures else ""
        print(f"verdict: {summary['verdict']}{reasons}; results in {target}/")
    if requested != target:
        print(f"railcheck: {requested} exists; results written to {target} (use --force to replace)", file=sys.stderr)
    return EXIT_FAIL if result.failures else EXIT_PASS
