"""One part over the whole crank cycle: unit load cases solved once, the stress at every
step by superposition, the von Mises envelope, the seed method's single instant beside
it, and high-cycle fatigue.

Unit cases per part (part frame, :mod:`fea.unitcases`): ``bolt_x`` and ``bolt_y``, a total
force of 1 N along the part's longitudinal / transverse axis shared by the joint's bolt
holes; with ``gravity`` or ``rail-inertia``, ``body_x`` and ``body_y`` (1 N/m^3); with
``rail-inertia`` on a rail, ``body_rot`` and ``body_rad`` (the rigid rotation's
tangential and centripetal fields about the rail's pivot). Each load source of the part
(a joint it can sit at) gives a coefficient history (steps, cases); the part's result is
the worse of its sources.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from railcheck.parts import BAR_INDEX, PARTS, kind_of

GRAVITY = 9.80665   # m/s^2
PIVOT_JOINT = {"crank": "O2", "coupler": "A", "rocker": "O4"}


@dataclass(frozen=True)
class SourceHistory:
    """A load source's coefficient history ``C`` (steps, cases) over ``crank_angle``
    (steps,) rad; ``seed_step`` the instant of its reaction's peak magnitude."""

    joint: str
    C: np.ndarray
    crank_angle: np.ndarray
    seed_step: int


@dataclass
class CycleResult:
    """Envelope, seed method and fatigue of one part (SI)."""

    source: str
    envelope: object
    seed_method: dict
    fatigue: dict
    history: dict
    fields: object
    C: np.ndarray
    meta: dict
    seconds: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)
    deflection_limit: float | None = None      # m


def unit_cases(scene, name: str, geo, holes: list[str]) -> dict:
    """The part's unit load cases, named (see the module doc)."""
    from railcheck.fea.unitcases import BodyCase, TractionCase

    cases = {"bolt_x": TractionCase(tuple(holes), 0), "bolt_y": TractionCase(tuple(holes), 1)}
    effects = scene.check.effects
    rail_inertia = _rail_inertia_applies(scene, name)
    if "gravity" in effects or rail_inertia:
        cases.update(body_x=BodyCase("uniform", 0), body_y=BodyCase("uniform", 1))
    if rail_inertia:
        pivot = (float(geo.get("hole_x")[0]), 0.0)
        cases.update(body_rot=BodyCase("rotational", pivot=pivot), body_rad=BodyCase("radial", pivot=pivot))
    return cases


def _rail_inertia_applies(scene, name: str) -> bool:
    return "rail-inertia" in scene.check.effects and PARTS[name].bar is not None and name not in scene.check.loads


def source_coefficients(scene, name: str, src, reactions: dict, angles: dict, accelerations: dict, omega: dict,
                        alpha: dict, density: float) -> np.ndarray:
    """(..., k): one load source's coefficients in the order of :func:`unit_cases`, for
    arrays with any leading dimensions (one setting's steps, or settings x steps):
    ``reactions`` and ``accelerations`` joint -> (..., 2) ground frame (N, m/s^2);
    ``angles``, ``omega``, ``alpha`` bar -> (...) (rad, rad/s, rad/s^2)."""
    from railcheck.loads.histories import bolt_history, gravity_history, rail_inertia_history

    force = src.sign * reactions[src.joint]
    angle = angles[src.axes_bar] if src.axes_bar else np.zeros(force.shape[:-1])
    cols = [bolt_history(force, angle, scene.check.factor)]
    gravity, inertia = "gravity" in scene.check.effects, _rail_inertia_applies(scene, name)
    if gravity or inertia:
        cols.append(gravity_history(angle, density, GRAVITY) if gravity else np.zeros(force.shape))
    if inertia:
        bar = PARTS[name].bar
        rigid = rail_inertia_history(accelerations[PIVOT_JOINT[bar]], angle, omega[bar], alpha[bar], density)
        cols[-1] = cols[-1] + rigid[..., :2]
        cols.append(rigid[..., 2:])
    return np.concatenate(cols, axis=-1)


def source_histories(scene, kin, name: str, holes: list[str], density: float) -> list[SourceHistory]:
    """The coefficient history of every load source of the part, columns in the order
    of :func:`unit_cases`."""
    from railcheck.loads.histories import gravity_history

    if name in scene.check.loads:
        load = scene.check.loads[name]
        c = [len(holes) * load.longitudinal, len(holes) * load.transverse]
        if "gravity" in scene.check.effects:
            c += list(gravity_history(np.zeros(1), density, GRAVITY)[0])
        return [SourceHistory("explicit", np.array([c]), np.zeros(1), 0)]
    dyn, motion = kin.dynamics, kin.motion
    by_bar = lambda a: {bar: a[:, i] for bar, i in BAR_INDEX.items()}  # noqa: E731
    out = []
    for src in PARTS[name].sources:
        if src.joint not in dyn.reactions:
            continue
        C = source_coefficients(scene, name, src, dyn.reactions, by_bar(motion.theta), motion.accelerations,
                                by_bar(motion.omega), by_bar(motion.alpha), density)
        force = dyn.reactions[src.joint]
        out.append(SourceHistory(src.joint, C, motion.theta2, int(np.argmax(np.hypot(force[:, 0], force[:, 1])))))
    return out


def check_part(scene, kin, name: str, geo, case, material, limit: float, solver: str, report):
    """Mesh, unit cases, envelope, seed method and fatigue of one part -> PartResult."""
    from railcheck.check.pipeline import PartResult, bolt_holes, mesh_sizes
    from railcheck.fea.unitcases import solve_unit_cases
    from railcheck.geometry.mesher import mesh_part

    kind = kind_of(name)
    seconds, warnings = {}, []
    t = time.perf_counter()
    size, hole = mesh_sizes(scene, geo.kind)
    mesh = mesh_part(geo, size, hole, optimize=scene.mesh.optimize)
    seconds["mesh"] = time.perf_counter() - t
    if mesh.warning:
        warnings.append(mesh.warning)
    if mesh.slivers:
        warnings.append(f"{mesh.slivers} sliver elements (gmsh minSICN < 0.05, worst {mesh.min_quality:.3f}); "
                        "stresses near them are unreliable")
    report(f"{mesh.tets.shape[0]} tetrahedra{' (cached)' if mesh.cached else ''}, "
           f"min quality {mesh.min_quality:.2f}")
    holes = bolt_holes(scene, name, geo)
    cases = unit_cases(scene, name, geo, holes)
    fields, meta = solve_unit_cases(mesh.points, mesh.tets, mesh.groups, material, [kind.support], cases,
                                    scene.mesh.order, kind.tip, kind.exclusion(geo), solver, report,
                                    curved=mesh.curved if scene.mesh.curved else None)
    seconds.update(meta["seconds"])
    t = time.perf_counter()
    histories = source_histories(scene, kin, name, holes, material.density)
    cycle = evaluate_cycle(scene, name, geo, fields, histories, material, meta)
    seconds["cycle"] = time.perf_counter() - t
    cycle.seconds, cycle.warnings = seconds, warnings
    cycle.deflection_limit = scene.check.max_deflection
    _refuse_non_finite(name, cycle)
    if not np.any(cycle.C):
        warnings.append("carries no load: its verdict is vacuous")
    when = f"at {cycle.history['crank_angle_deg']:.1f} deg" if cycle.C.shape[0] > 1 else "(constant loads)"
    report(f"{meta['dofs']} DOFs, {meta['solver'].get('solver')}, {len(cases)} unit cases; cycle peak "
           f"{cycle.envelope.max_von_mises / 1e6:.1f} MPa {when} "
           f"(seed method {cycle.seed_method['max_von_mises_Pa'] / 1e6:.1f} MPa), fatigue factor "
           f"{cycle.fatigue['min_safety_factor']:.2f}")
    solution = solution_at(fields, cycle.C[cycle.envelope.step], meta, scene.mesh.order, kind.exclusion(geo),
                           cycle.envelope)
    return PartResult(name, case, mesh, solution, limit, geo, cycle)


def _refuse_non_finite(name: str, cycle) -> None:
    """A NaN or an infinity in the results is a numerical failure, never a number."""
    from railcheck.fea.errors import NumericalError

    env = cycle.envelope
    values = [env.max_von_mises, env.max_tip, env.support_peak, cycle.seed_method["max_von_mises_Pa"],
              cycle.fatigue["sigma_a_Pa"], cycle.fatigue["sigma_m_Pa"]]
    if not (np.all(np.isfinite(values)) and np.all(np.isfinite(cycle.C))):
        raise NumericalError(f"{name}: the stress or deflection over the cycle is not finite")


def evaluate_cycle(scene, name: str, geo, fields, histories: list[SourceHistory], material, meta) -> CycleResult:
    """Envelope, seed method and fatigue over every source; the worse source governs the
    stress verdict, the lower fatigue factor the fatigue verdict."""
    from railcheck.fea.elasticity import von_mises
    from railcheck.fea.superpose import envelope, history_at_node, stress_at

    results = []
    for h in histories:
        env = envelope(fields, h.C)
        vm_seed = von_mises(stress_at(fields.stress, h.C[h.seed_step]))
        mask = fields.verdict_mask if np.any(fields.verdict_mask) else np.ones_like(fields.verdict_mask)
        k = int(np.argmax(np.where(mask, vm_seed, -np.inf)))
        seed = {"max_von_mises_Pa": float(vm_seed[k]), "crank_angle_deg": _deg(h.crank_angle[h.seed_step]),
                "location_m": [float(x) for x in fields.nodes[k]], "joint": h.joint}
        results.append((h, env, seed, fatigue_of(scene, name, geo, fields, h.C, material)))
    h, env, _, _ = max(results, key=lambda r: r[1].max_von_mises)
    seed = max((r[2] for r in results), key=lambda s: s["max_von_mises_Pa"])
    fat = min((r[3] for r in results), key=lambda f: f["min_safety_factor"])
    history = {"crank_angle_deg": _deg(h.crank_angle[env.step]), "angles_deg": np.degrees(h.crank_angle),
               "von_mises_Pa": history_at_node(fields, h.C, env.node), "seed_step": h.seed_step,
               "joint": h.joint, "seed_angle_deg": _deg(h.crank_angle[h.seed_step])}
    return CycleResult(h.joint, env, seed, fat, history, fields, h.C, meta)


def _deg(angle: float) -> float:
    return float(math.degrees(angle) % 360.0)


def fatigue_of(scene, name: str, geo, fields, C: np.ndarray, material) -> dict:
    """The minimum fatigue safety factor over the verdict nodes of one history, where,
    its sigma_a / sigma_m (Pa), the endurance limit and Marin factors; ``node_factor``
    (nodes,) for the VTU."""
    from railcheck.fea.fatigue import alternating_and_mean, endurance_limit, safety_factor
    from railcheck.fea.superpose import candidate_steps, component_range

    spec = scene.fatigue
    marin = endurance_limit(material.ultimate_strength, spec.surface, kind_of(name).section(geo), spec.load,
                            spec.reliability)
    hi, lo = component_range(fields.stress, C[candidate_steps(C)])
    sa, sm = alternating_and_mean(hi, lo)
    n = safety_factor(sa, sm, marin.endurance_limit, material.ultimate_strength, spec.criterion,
                      material.yield_strength)
    mask = fields.verdict_mask if np.any(fields.verdict_mask) else np.ones_like(fields.verdict_mask)
    k = int(np.argmin(np.where(mask, n, np.inf)))
    return {"criterion": spec.criterion, "endurance_limit_Pa": marin.endurance_limit,
            "marin": {"ka": marin.ka, "kb": marin.kb, "kc": marin.kc, "kd": marin.kd, "ke": marin.ke,
                      "unmodified_Pa": marin.unmodified, "surface": spec.surface, "reliability": spec.reliability},
            "min_safety_factor": float(n[k]), "location_m": [float(x) for x in fields.nodes[k]],
            "sigma_a_Pa": float(sa[k]), "sigma_m_Pa": float(sm[k]), "required": spec.min_safety,
            "node_factor": n}


def solution_at(fields, c: np.ndarray, meta: dict, order: int, exclude: float, env):
    """A :class:`fea.elasticity.Solution` of the instant with coefficients ``c`` (for the
    VTU and the picture), built by superposition."""
    from railcheck.fea.elasticity import Solution, peak, von_mises
    from railcheck.fea.superpose import stress_at

    S = stress_at(fields.stress, c)
    vm = von_mises(S)
    nv = meta["vertices"]
    top = peak(vm, fields.nodes)
    away = peak(vm, fields.nodes, fields.verdict_mask)
    u = fields.displacement @ c
    return Solution(order=order, dofs=meta["dofs"], elements=meta["elements"], displacement=u[:nv],
                    von_mises=vm[:nv].copy(), max_von_mises=top[0], max_von_mises_location=top[1],
                    tip_displacement=fields.tip @ c, applied_forces={"total": meta["resultants"] @ c},
                    max_von_mises_away=away[0], max_von_mises_away_location=away[1], exclude_distance=exclude,
                    stress=S, nodes=fields.nodes, seconds=meta["seconds"], solver=meta["solver"], warnings=[],
                    node_displacement=u)
