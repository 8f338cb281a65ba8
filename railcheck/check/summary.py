"""``summary.json`` of a check: the one place that maps the check's records
(:mod:`railcheck.model.records`) to JSON keys, each key naming its unit (``_Pa``, ``_m``,
``_deg``, ``_N``, ``_kg``). Deterministic: no timings (those go to ``timings.json``), so the
same scene gives a byte-identical summary.
"""

from __future__ import annotations

import numpy as np

from railcheck.geometry.catalogue import (
    CATALOGUE_RAIL_MASS,
    rail_mass_per_metre,
    rail_mass_per_metre_with_holes,
    with_overrides,
)
from railcheck.model.assumptions import assumptions
from railcheck.model.inputs import parts_input
from railcheck.model.records import DynamicResult, FatigueResult, PartResult, PipelineResult, SeedMethod
from railcheck.parts import kind_of, mass_model
from railcheck.report.forces import applied_factor, governing_forces


def _components_safe_speed(result: PipelineResult) -> dict:
    """``components_safe_speed``: the crank speed (Hz) up to which the components pass at
    this setting and what reaches its limit there (absent without components or speed)."""
    safe = result.components_safe_speed
    if safe is None:
        return {}
    return {"components_safe_speed": {"Hz": safe.hz, "component": safe.component, "criterion": safe.criterion}}


def _parts_safe_speed(result: PipelineResult) -> dict:
    """``parts_safe_speed``: each failing part's crank speed (Hz) up to which it passes at
    this setting and the criterion that reaches 1 there (absent when no part fails)."""
    safe = result.parts_safe_speed
    if not safe:
        return {}
    return {"parts_safe_speed": {name: {"Hz": s.hz, "criterion": s.criterion} for name, s in safe.items()}}


def _safe_speed(result: PipelineResult) -> dict:
    """``safe_speed``: the crank speed (Hz) up to which every checked part and component
    passes at this setting, and the part or component and criterion that reach 1 there
    (absent for a still crank; ``Hz``, ``set_by`` and ``criterion`` null where nothing the
    speed loads reaches a limit: no part or criterion sets it)."""
    safe = result.safe_speed
    if safe is None:
        return {}
    if not np.isfinite(safe.hz):
        return {"safe_speed": {"Hz": None, "set_by": None, "criterion": None}}
    return {"safe_speed": {"Hz": safe.hz, "set_by": safe.component, "criterion": safe.criterion}}


def summary_of(result: PipelineResult) -> dict:
    """The summary.json content."""
    scene = result.scene
    out = {
        "verdict": verdict_of(result),
        "failures": result.failures,
        "failures_with_figures": result.failures_with_figures,
        "to_pass": result.to_pass,
        "parts": {name: part_summary(p) for name, p in result.parts.items()},
        "components": {name: component_summary(c) for name, c in result.components.items()},
        **_components_safe_speed(result),
        **_parts_safe_speed(result),
        **_safe_speed(result),
        "unloaded_parts": list(result.unloaded),
        "stages_run": list(result.stages_run),
        "warnings": list(result.warnings),
    }
    if scene.check is not None:
        out["material"] = scene.check.material
        out["effects"] = list(scene.check.effects)
        out["assumptions"] = assumptions(parts_input(scene), scene.components, result.parts)
    if any(kind_of(name).weighed_per_metre for name in result.parts):
        out["rail_mass_per_m_kg"] = rail_masses(scene.geometry, scene.formulation)
    if result.kinematics_summary is not None:
        out["kinematics"] = result.kinematics_summary
    out["scene"] = scene.raw
    out["scene_source"] = scene.source
    return out


def verdict_of(result: PipelineResult) -> str:
    """FAIL on any failure; PASS when parts were checked; NO LOAD when every part was
    left unloaded; NO CHECK when there was nothing to check."""
    if result.failures:
        return "FAIL"
    if result.parts or result.components:
        return "PASS"
    return "NO LOAD" if result.unloaded else "NO CHECK"


def component_summary(c) -> dict:
    """One component's entry of summary.json (SI; the figures' keys carry their units)."""
    return {
        "kind": c.kind,
        "joint": c.joint,
        "standard": c.standard,
        "loads_factored": c.factored,
        "utilisation": float(c.utilisation),
        "governing_criterion": str(c.governing_criterion),
        "utilisation_by_criterion": dict(c.utilisations),
        "figures": dict(c.figures),
        "assumed": list(c.assumed),
        "needs": dict(c.needs),
        "pass": bool(c.passed),
    }


def part_summary(p: PartResult) -> dict:
    """One part's entry of summary.json (SI; the envelope governs ``max_von_mises_Pa``).
    A free body adds ``support``, the deflection's meaning and its ``imbalance``."""
    s, cyc, job = p.solution, p.cycle, p.job
    env = cyc.envelope
    out = {
        "max_von_mises_Pa": env.max_von_mises,
        "max_von_mises_location_m": [float(x) for x in env.location],
        "crank_angle_deg": cyc.history.crank_angle_deg,
        "support_peak_von_mises_Pa": env.support_peak,
        "support_exclusion_m": s.exclude_distance,
        "tip_deflection_m": env.max_tip,
        "max_deflection_m": p.deflection_limit,
        "deflection_pass": bool(p.deflection_passed),
        "limit_Pa": p.limit,
        "utilisation": p.utilisation,
        "governing_criterion": p.governing_criterion,
        "utilisation_by_criterion": p.utilisations,
        "factor_of_safety": p.limit / p.verdict_stress if p.verdict_stress > 0 else None,
        "pass": bool(p.passed),
        "envelope": {
            "max_von_mises_Pa": env.max_von_mises,
            "crank_angle_deg": cyc.history.crank_angle_deg,
            "location_m": [float(x) for x in env.location],
            "max_tip_deflection_m": env.max_tip,
            "joint": cyc.source,
        },
        "seed_method": seed_summary(cyc.seed_method, env.max_von_mises),
        "fatigue": fatigue_summary(cyc.fatigue),
        # a free body's loads are its joints' forces over the cycle; the 2013 study's single
        # load case (a clamp, the far joint's peak) is kept under its own name
        ("load_case" if job.free_body is None else "seed_load_case"): load_case_summary(p),
        "loads_at_governing_instant": governing_loads_summary(p),
        "unit_cases": list(cyc.fields.names),
        "mesh": mesh_summary(p),
    }
    if job.certificate is not None:
        out["quasi_static"] = certificate_summary(job)
    if cyc.dynamic is not None:
        out["dynamic"] = dynamic_summary(cyc.dynamic) | {"reason": job.dynamic.reason if job.dynamic else ""}
    if p.clamped is not None:
        out["clamped_2013"] = clamped_summary(p.clamped)
    if job.free_body is not None:
        out["support"] = {
            "model": "free-body",
            "deflection": free_deflection_words(job),
            "imbalance": imbalance_summary(p),
        }
    return out


def load_case_summary(p: PartResult) -> dict:
    """The part's load case in summary.json: support, tip group, factor, origin, bolt forces (N)."""
    return {
        "support": p.load_case.support,
        "tip": p.load_case.tip_group,
        "factor": p.load_case.factor,
        **p.load_case.origin,
        "bolts": {b.group: list(b.force) for b in p.load_case.bolts},
    }


def governing_loads_summary(p: PartResult) -> list[dict]:
    """Each load the FE applied at the part's governing instant, in the part's axes (x
    along it, y across it): as applied (``applied_N``, with ``factor``: the load factor, or
    1 for explicit loads) and unfactored; the motor couple's torque (N m) where there is one."""
    factor = applied_factor(p)
    return [
        {
            "name": f.name,
            "holes": list(f.holes),
            "factor": factor,
            "applied_N": [float(v) for v in f.force],
            "unfactored_N": [float(v) / factor for v in f.force],
            **({"couple_Nm": f.couple, "unfactored_couple_Nm": f.couple / factor} if f.couple is not None else {}),
        }
        for f in governing_forces(p)
    ]


def mesh_summary(p: PartResult) -> dict:
    """The part's mesh in summary.json: order, sizes (m), DOFs, elements, quality, solver."""
    s, job = p.solution, p.job
    return {
        "order": s.order,
        "size_m": job.mesh.size,
        "hole_size_m": job.mesh.hole_size,
        "dofs": s.dofs,
        "elements": s.elements,
        "min_quality": p.mesh.min_quality,
        "slivers": p.mesh.slivers,
        "solver": p.cycle.solve.solver.get("solver"),
    }


def clamped_summary(k) -> dict:
    """The 2013 study's clamped model of the part in summary.json (for comparison)."""
    return {
        "note": "the 2013 study's model (a rail clamped at its first hole, a plate at its seat, the joint's "
        "reaction at the bolts), for comparison: not part of the verdict",
        "max_von_mises_Pa": k.max_von_mises,
        "support_peak_von_mises_Pa": k.support_peak,
        "crank_angle_deg": k.crank_angle_deg,
        "fatigue_factor": k.fatigue_factor,
        "max_tip_deflection_m": k.max_tip,
    }


def free_deflection_words(job) -> str:
    """What a free body's deflection measures, in words."""
    if job.loads.is_on_foundation:
        return "the top face's displacement relative to the base's"
    if job.loads.is_free_plate:
        return "the seat's displacement relative to the line through the two bolts"
    if job.loads.free_body.motor:
        return "at A's bolts relative to the line through the two screws at O2"
    return "sag at mid-span relative to the line through the two joints"


def certificate_summary(job) -> dict:
    """Where quasi-static holds (:mod:`railcheck.model.certificate`): the one-mode estimate
    of the part's dynamic amplification, its lowest frequency and where it came from."""
    c = job.certificate
    return {
        "holds": bool(c.holds),
        "amplification_estimate": c.estimate,
        "tolerance": c.tolerance,
        "lowest_frequency_Hz": c.lowest_hz,
        "lowest_frequency_from": c.source,
        "crank_Hz": c.crank_hz,
        "then": "quasi-static verdict" if c.holds else "the dynamic response is computed (see dynamic)",
    }


def dynamic_summary(d: DynamicResult) -> dict:
    """The dynamic response of a part (effect ``dynamic``): frequencies, nearest crank
    harmonics, amplification (dynamic over quasi-static cycle peak) and its verdict."""
    return {
        "frequencies_Hz": [float(x) for x in d.hz],
        "nearest_harmonic": [int(n) for n in d.harmonics],
        "crank_Hz": d.crank_hz,
        "quasi_static_peak_von_mises_Pa": d.quasi_static_peak,
        "dynamic_peak_von_mises_Pa": d.dynamic_peak,
        "amplification": d.amplification,
        "damping_ratio": d.damping,
        "max_amplification": d.max_amplification,
        "pass": bool(d.passed),
        "method": "steady-state modal superposition with the mode-acceleration correction over one revolution",
    }


def imbalance_summary(p: PartResult) -> dict:
    """How far a free body's loads are from equilibrium before inertia relief, over the
    cycle: the largest resultant force (N), in-plane moment (about z) and out-of-plane
    moment (about x and y, N m, about the centroid), and each as a fraction of the largest
    joint force (times the part's length for moments). The out-of-plane part is what the
    joints' bearings carry in the rig (the pins bear below the section's centroid, the
    inertia acts at it; the planar dynamics has no out-of-plane equations); inertia relief
    applies it as a rigid rotational acceleration."""
    cyc = p.cycle
    imbalance = (cyc.solve.imbalance @ cyc.load_C.T).T  # (steps, 6)
    joints = [i for i, n in enumerate(cyc.fields.names) if n.startswith(("pin_", "bolt_"))]
    scale = float(np.abs(cyc.C[:, joints]).max()) or 1.0
    length = float(p.geometry.get("length"))
    force = float(np.linalg.norm(imbalance[:, :3], axis=1).max())
    in_plane = float(np.abs(imbalance[:, 5]).max())
    out_of_plane = float(np.linalg.norm(imbalance[:, 3:5], axis=1).max())
    return {
        "max_force_N": force,
        "max_moment_in_plane_Nm": in_plane,
        "max_moment_out_of_plane_Nm": out_of_plane,
        "force_fraction": force / scale,
        "moment_in_plane_fraction": in_plane / (scale * length),
        "moment_out_of_plane_fraction": out_of_plane / (scale * length),
        "largest_joint_force_N": scale,
    }


def seed_summary(seed: SeedMethod, envelope_peak: float) -> dict:
    """The seed method's entry, with the envelope's ratio to it."""
    return {
        "max_von_mises_Pa": seed.max_von_mises,
        "crank_angle_deg": seed.crank_angle_deg,
        "location_m": list(seed.location),
        "joint": seed.joint,
        "ratio_envelope_to_seed": envelope_peak / seed.max_von_mises if seed.max_von_mises > 0 else None,
    }


def fatigue_summary(f: FatigueResult) -> dict:
    """The fatigue entry (Pa): criterion, endurance limit and Marin factors, the minimum
    safety factor, where, its alternating and midrange stresses, and the factor required."""
    m = f.marin
    return {
        "criterion": f.criterion,
        "endurance_limit_Pa": m.endurance_limit,
        "marin": {
            "ka": m.ka,
            "kb": m.kb,
            "kc": m.kc,
            "kd": m.kd,
            "ke": m.ke,
            "unmodified_Pa": m.unmodified,
            "surface": f.surface,
            "reliability": f.reliability,
        },
        "min_safety_factor": f.min_safety_factor,
        "location_m": list(f.location),
        "sigma_a_Pa": f.sigma_a,
        "sigma_m_Pa": f.sigma_m,
        "required": f.required,
    }


def rail_masses(geometry_overrides: dict, formulation: str = "newton-euler") -> dict:
    """kg/m of the modelled (grooved) rail section, with and without its holes, beside the
    seed's and the catalogue's figures, and what the run's dynamics and FE carry."""
    rail = with_overrides(geometry_overrides)[0]
    return {
        "model_section": rail_mass_per_metre(rail),
        "model_with_holes": rail_mass_per_metre_with_holes(rail),
        **CATALOGUE_RAIL_MASS,
        "dynamics": mass_model(formulation, geometry_overrides).rail_mass_per_m,
    }
