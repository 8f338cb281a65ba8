"""One part over the whole crank cycle, from its :class:`~railcheck.model.jobs.PartJob`:
mesh, unit load cases solved once (:mod:`railcheck.model.loading`), the stress at every
step by superposition, the von Mises envelope, the seed method's single instant beside
it, and high-cycle fatigue. A part with several load sources (a plate used at two joints)
takes the worse source: the larger stress governs the stress verdict, the lower fatigue
factor the fatigue verdict. With the effect ``dynamic`` each history gains the modes'
mode-acceleration columns, so the envelope, fatigue and deflection read the dynamic
response, and the result states the amplification over the quasi-static one.
"""

from __future__ import annotations

import math
import re
import time
from dataclasses import replace

import numpy as np

from railcheck import environment
from railcheck.base.errors import NumericalError
from railcheck.fea import screening
from railcheck.fea.dynamic import modal_correction
from railcheck.fea.elasticity import Solution
from railcheck.fea.fatigue import alternating_and_mean, endurance_limit, safety_factor
from railcheck.fea.hull import candidate_steps
from railcheck.fea.stress import peak, von_mises
from railcheck.fea.superpose import (
    UnitFields,
    component_range,
    envelope,
    first_columns,
    history_at_node,
    node_envelope_of,
    reduced,
    stress_at,
    subspace_candidates,
)
from railcheck.fea.unitcases import UnitSolve
from railcheck.geometry.mesher import cached_mesh, mesh_part
from railcheck.model.certificate import certificate
from railcheck.model.jobs import PartJob
from railcheck.model.loading import SourceHistory, unit_cases
from railcheck.model.records import (
    ClampedComparison,
    CycleHistory,
    CycleResult,
    DynamicResult,
    FatigueResult,
    PartResult,
    SeedMethod,
)
from railcheck.model.setting_free import part_fields, stored
from railcheck.parallel.threads import on_one_blas_thread
from railcheck.units import for_people

#: curved edges straightened below this share of them are a note on the mesh's progress line,
#: not a warning: the surface is faceted on a few edges, nothing to act on
MINOR_STRAIGHTENING = 1.0  # per cent


def minor_straightening(warning: str | None) -> str | None:
    """The mesh's warning when it only says that fewer than :data:`MINOR_STRAIGHTENING` per
    cent of the curved edges were straightened (a note then), else None."""
    found = re.fullmatch(r"\d+ curved edges straightened .*\(([\d.]+)% of the curved edges; .*\)", warning or "")
    return warning if found and float(found.group(1)) < MINOR_STRAIGHTENING else None


def check_part(job: PartJob, solver: str, report) -> PartResult:
    """Mesh, unit cases, envelope, seed method and fatigue of one part -> PartResult;
    ``report(message)`` prints a progress line."""
    seconds, warnings = {}, []
    t = time.perf_counter()
    if cached_mesh(job.geometry, job.mesh.size, job.mesh.hole_size, job.mesh.optimize, environment.cache_dir()) is None:
        report(f"meshing (gmsh, {job.mesh.size * 1e3:g} mm, {job.mesh.hole_size * 1e3:g} mm at the holes)")
    mesh = job_mesh(job)
    seconds["mesh"] = time.perf_counter() - t
    note = minor_straightening(mesh.warning)
    if mesh.warning and not note:
        warnings.append(mesh.warning)
    if mesh.slivers:
        warnings.append(
            f"{mesh.slivers} sliver elements (gmsh minSICN < 0.05, worst {mesh.min_quality:.3f}); "
            "stresses near them are unreliable"
        )
    report(
        f"{mesh.tets.shape[0]} tetrahedra{_mesh_source(mesh)}, min quality {mesh.min_quality:.2f}"
        + (f"; {note}" if note else "")
    )
    cases = unit_cases(job.loads, job.geometry, list(job.holes))
    fields, solve, origin = part_fields(job, mesh, cases, solver, report)
    seconds.update(solve.seconds)
    if origin == "stored":
        report(f"unit fields from the store ({solve.dofs} DOFs; not assembled or solved)")
    elif origin != "solved":
        warnings.append(origin)
    job, solve, fields = certify_from_fe_modes(job, solve, fields, cases)
    if job.dynamic is not None and solve.modes is not None and solve.modes.hz.size < job.dynamic.modes:
        report(f"solving its {job.dynamic.modes} lowest modes for the dynamic response")
        fields, solve, _ = part_fields(job, mesh, cases, solver, report)  # its certificate's one mode was not enough
        seconds.update({k: seconds.get(k, 0.0) + v for k, v in solve.seconds.items()})
    if job.certificate is not None:
        report(job.certificate.sentence())
    t = time.perf_counter()
    cycle = evaluate_cycle(job, fields, job.histories, solve)
    seconds["cycle"] = time.perf_counter() - t
    _refuse_non_finite(job.name, cycle)
    if not np.any(cycle.C):
        warnings.append("carries no load: its verdict is vacuous")
    when = f"at {cycle.history.crank_angle_deg:.1f} deg" if cycle.C.shape[0] > 1 else "(constant loads)"
    report(
        f"{solve.dofs} DOFs, {solve.solver.get('solver')}, {len(cases)} unit cases; cycle peak "
        f"{cycle.envelope.max_von_mises / 1e6:.1f} MPa {when} "
        f"(seed method {cycle.seed_method.max_von_mises / 1e6:.1f} MPa), fatigue factor "
        f"{for_people(cycle.fatigue.min_safety_factor)}"
    )
    solution = solution_at(fields, cycle.C[cycle.envelope.step], solve, job.mesh.order, job.exclusion)
    clamped = None
    if job.clamped is not None:
        t = time.perf_counter()
        clamped, origin = clamped_comparison(job.clamped, mesh, solver, report)
        if origin not in ("stored", "solved"):  # a damaged entry, solved again: said, as for the part's own
            warnings.append(f"2013 clamped model: {origin}")
        seconds["clamped (2013)"] = time.perf_counter() - t
    return PartResult(
        job=job, mesh=mesh, solution=solution, cycle=cycle, seconds=seconds, warnings=tuple(warnings), clamped=clamped
    )


@on_one_blas_thread
def certify_from_fe_modes(
    job: PartJob, solve: UnitSolve, fields: UnitFields, cases: dict
) -> tuple[PartJob, UnitSolve, UnitFields]:
    """A part whose modes were solved for its certificate only (no beam model): its
    certificate from its lowest FE mode, and the exact response kept when it does not hold
    (else the modes are dropped: the quasi-static verdict stands, the estimate beside it)."""
    d = job.dynamic
    if d is None or d.exact or solve.modes is None:
        return job, solve, fields
    cert = certificate([h.C for h in job.histories], list(cases), d.speed, float(solve.modes.hz[0]), "FE modes", d.damping)
    if cert.holds:
        return replace(job, dynamic=None, certificate=cert), replace(solve, modes=None), first_columns(fields, len(cases))
    reason = f"the certificate does not hold ({cert.estimate:.3f} > {cert.tolerance:.2f})"
    return replace(job, dynamic=replace(d, exact=True, reason=reason), certificate=cert), solve, fields


def clamped_comparison(job: PartJob, mesh, solver: str, report) -> tuple[ClampedComparison, str]:
    """The cycle peaks of a free rail's clamped (2013) model ``job`` on the same mesh, its
    unit fields through the store like any part's, and where those came from
    (:func:`railcheck.fea.store.solve_stored`'s ``origin``)."""
    cases = unit_cases(job.loads, job.geometry, list(job.holes))
    fields, solve, origin = part_fields(job, mesh, cases, solver, lambda msg: None)
    cycle = evaluate_cycle(job, fields, job.histories, solve)
    _refuse_non_finite(job.name, cycle)
    env = cycle.envelope
    report(
        f"clamped as in 2013 (for comparison): cycle peak {env.max_von_mises / 1e6:.1f} MPa, "
        f"{env.support_peak / 1e6:.1f} MPa at the clamp"
    )
    comparison = ClampedComparison(
        max_von_mises=env.max_von_mises,
        support_peak=env.support_peak,
        crank_angle_deg=cycle.history.crank_angle_deg,
        fatigue_factor=cycle.fatigue.min_safety_factor,
        max_tip=env.max_tip,
    )
    return comparison, origin


def _refuse_non_finite(name: str, cycle: CycleResult) -> None:
    """A NaN or an infinity in the results is a numerical failure, never a number."""
    env = cycle.envelope
    values = [
        env.max_von_mises,
        env.max_tip,
        env.support_peak,
        cycle.seed_method.max_von_mises,
        cycle.fatigue.sigma_a,
        cycle.fatigue.sigma_m,
    ]
    if not (np.all(np.isfinite(values)) and np.all(np.isfinite(cycle.C))):
        raise NumericalError(f"{name}: the stress or deflection over the cycle is not finite")


def job_mesh(job: PartJob):
    """The part's mesh (:func:`railcheck.geometry.mesher.mesh_part`: from the mesh cache in
    the environment's folder, or built and cached), at the job's sizes."""
    return mesh_part(
        job.geometry,
        job.mesh.size,
        job.mesh.hole_size,
        optimize=job.mesh.optimize,
        cache_dir=environment.cache_dir(),
        verbose=environment.gmsh_verbose(),
    )


def in_store(job: PartJob) -> bool:
    """True when the store holds an entry for the part's unit fields (its mesh read from
    the mesh cache; the entry itself is verified when it is read)."""
    store = environment.unit_store()
    if store is None:
        return False
    mesh = cached_mesh(job.geometry, job.mesh.size, job.mesh.hole_size, job.mesh.optimize, environment.cache_dir())
    if mesh is None:  # a probe: never meshes (a cold part is meshed where its progress is shown)
        return False
    jobs = [job] + ([job.clamped] if job.clamped is not None else [])
    return all(stored(j, mesh, unit_cases(j.loads, j.geometry, list(j.holes))) for j in jobs)


@on_one_blas_thread
def evaluate_cycle(job: PartJob, fields: UnitFields, histories: tuple[SourceHistory, ...], solve: UnitSolve) -> CycleResult:
    """Envelope, seed method and fatigue over every source; the worse source governs the
    stress verdict, the lower fatigue factor the fatigue verdict."""
    results = []
    histories = tuple(with_dynamics(job, solve, h) for h in histories)
    for h in histories:
        basis, C = reduced(fields, h.C)  # the same stresses in the fewest coefficients (exact)
        steps = candidate_steps(C)
        # the nodes' subspace bounds, once for the peaks and the fatigue minimum
        bounds = verdict_bounds(job, basis, C[steps]) if screening.applies(steps.size, C.shape[1]) else None
        env = envelope(basis, C, every_node=False, steps=steps, bounds=bounds)  # each node's maximum only for the VTU
        vm_seed = von_mises(stress_at(fields.stress, h.C[h.seed_step]))
        k = int(np.argmax(np.where(_verdict_mask(fields), vm_seed, -np.inf)))
        seed = SeedMethod(
            max_von_mises=float(vm_seed[k]),
            crank_angle_deg=_deg(h.crank_angle[h.seed_step]),
            location=_point(fields.nodes[k]),
            joint=h.joint,
        )
        results.append((h, env, seed, fatigue_of(job, basis, C, steps, bounds)))
    h, env, _, _ = max(results, key=lambda r: r[1].max_von_mises)
    if job.node_fields:  # the VTU's envelope at every node, here with the cycle (on its thread or worker)
        env = replace(env, node_envelope=node_envelope_of(fields, h.C))
    seed = max((r[2] for r in results), key=lambda s: s.max_von_mises)
    fat = min((r[3] for r in results), key=lambda f: f.min_safety_factor)
    history = CycleHistory(
        crank_angle_deg=_deg(h.crank_angle[env.step]),
        angles_deg=np.degrees(h.crank_angle),
        von_mises=history_at_node(fields, h.C, env.node),
        seed_step=h.seed_step,
        joint=h.joint,
        seed_angle_deg=_deg(h.crank_angle[h.seed_step]),
    )
    return CycleResult(
        source=h.joint,
        envelope=env,
        seed_method=seed,
        fatigue=fat,
        history=history,
        fields=fields,
        C=h.C,
        solve=solve,
        dynamic=dynamic_result(job, fields, solve, histories),
    )


def with_dynamics(job: PartJob, solve: UnitSolve, h: SourceHistory) -> SourceHistory:
    """The history with one coefficient column per mode appended: the mode-acceleration
    correction (:func:`railcheck.fea.dynamic.modal_correction`) with ``dynamic``, else as
    it is."""
    if solve.modes is None:
        return h
    d = job.dynamic
    assert d is not None  # modes were solved because the job asks for its dynamic response
    dq = modal_correction(solve.modes.modal_loads, solve.modes.hz, h.C, d.speed, d.damping)
    return replace(h, C=np.hstack([h.C, dq]))


def dynamic_result(job: PartJob, fields: UnitFields, solve: UnitSolve, histories) -> DynamicResult | None:
    """Frequencies, the crank harmonic nearest each, and the dynamic amplification: the
    cycle's von Mises peak with the modal correction over the quasi-static peak (the
    correction's columns zeroed), the largest over the load sources."""
    if solve.modes is None:
        return None
    d, hz = job.dynamic, solve.modes.hz
    assert d is not None  # modes were solved because the job asks for its dynamic response
    m = hz.size
    ratios = []
    for h in histories:
        quasi = h.C.copy()
        quasi[:, -m:] = 0.0
        qs = envelope(*reduced(fields, quasi), every_node=False).max_von_mises  # fewest coefficients, exact
        dyn = envelope(*reduced(fields, h.C), every_node=False).max_von_mises
        ratios.append((dyn / qs if qs > 0 else 1.0, qs, dyn))
    amplification, qs, dyn = max(ratios)
    crank_hz = d.speed / (2 * math.pi)
    harmonics = np.maximum(np.rint(hz / crank_hz), 1).astype(int)
    return DynamicResult(
        hz=hz,
        harmonics=harmonics,
        crank_hz=crank_hz,
        amplification=float(amplification),
        quasi_static_peak=float(qs),
        dynamic_peak=float(dyn),
        damping=d.damping,
        max_amplification=d.max_amplification,
    )


def _point(x: np.ndarray) -> tuple[float, float, float]:
    """A node's (3,) coordinates (m) as a tuple of floats."""
    return float(x[0]), float(x[1]), float(x[2])


def _deg(angle: float) -> float:
    return float(math.degrees(angle) % 360.0)


def _verdict_mask(fields: UnitFields) -> np.ndarray:
    """The nodes the verdict reads (every node when the support zone covers them all)."""
    return fields.verdict_mask if np.any(fields.verdict_mask) else np.ones_like(fields.verdict_mask)


def fatigue_of(
    job: PartJob,
    fields: UnitFields,
    C: np.ndarray,
    steps: np.ndarray | None = None,
    bounds: screening.SampledBounds | None = None,
) -> FatigueResult:
    """The minimum fatigue safety factor over the verdict nodes of one history, where,
    its sigma_a / sigma_m (Pa), the endurance limit and Marin factors, and, when the job
    writes node fields (the VTU), the factor at every node. Without, the nodes of a
    history of more than :data:`railcheck.fea.screening.MIN_STEPS` candidate steps are screened
    (:mod:`railcheck.fea.screening`: many coefficients by their principal subspace's sampled steps, two
    or three by its box) and only those that can hold the minimum are evaluated: the same
    minimum, node and stresses (``bounds``: the nodes' :func:`verdict_bounds` or
    :func:`railcheck.fea.screening.history_bounds` for ``C[steps]``, when already known)."""
    spec = job.fatigue
    marin, factor = fatigue_factor(job)
    C = C[candidate_steps(C) if steps is None else steps]
    mask = _verdict_mask(fields)
    if job.node_fields or C.shape[0] <= screening.MIN_STEPS:
        sa, sm = alternating_and_mean(*component_range(fields.stress, C))
        n = factor(sa, sm)
        k = int(np.argmin(np.where(mask, n, np.inf)))
        node_factor, n_k, sa_k, sm_k = n, n[k], sa[k], sm[k]
    else:
        if bounds is not None:
            b = bounds
        elif screening.applies(*C.shape):
            b = screening.history_bounds(fields.stress, C)
        else:  # two coefficients (or an affine plane): the box screens, the polygon's support evaluates
            b = screening.history_box_bounds(fields.stress, C)
        nodes = _fatigue_candidates(fields.stress, C, factor, b, mask)
        sa, sm = alternating_and_mean(*component_range(fields.stress[:, nodes], C))
        n = factor(sa, sm)
        j = int(np.argmin(n))
        k = int(nodes[j])
        node_factor, n_k, sa_k, sm_k = None, n[j], sa[j], sm[j]
    return FatigueResult(
        criterion=spec.criterion,
        marin=marin,
        surface=spec.surface,
        reliability=spec.reliability,
        min_safety_factor=float(n_k),
        location=_point(fields.nodes[k]),
        sigma_a=float(sa_k),
        sigma_m=float(sm_k),
        required=spec.min_safety,
        node_factor=node_factor,
    )


def fatigue_factor(job: PartJob):
    """(Marin factors and endurance limit, ``factor(sa, sm)``: the job's fatigue safety
    factor of alternating and midrange von Mises stresses, Pa)."""
    spec, material = job.fatigue, job.material
    marin = endurance_limit(material.ultimate_strength, spec.surface, job.section, spec.load, spec.reliability)

    def factor(sa: np.ndarray, sm: np.ndarray) -> np.ndarray:
        return safety_factor(
            sa, sm, marin.endurance_limit, material.ultimate_strength, spec.criterion, material.yield_strength
        )

    return marin, factor


def verdict_bounds(job: PartJob, fields: UnitFields, C: np.ndarray) -> screening.SampledBounds:
    """The nodes' bounds over the many-coefficient history ``C`` (its candidate steps) for
    the peaks and the fatigue minimum: the box of its principal subspace at every node
    (:func:`railcheck.fea.screening.box_bounds`), and its sampled steps read only at the nodes that the
    box leaves as candidates for the verdict nodes' peak, every node's peak or the fatigue
    minimum (below 1% of the nodes on the default rig's free bodies, against 100% read
    before). Valid at every node, so the screens that use them stay exact."""
    S = fields.stress
    p = screening.project_history(S, C)
    box = screening.box_bounds(p.SP, p.norms, p.vm_norm, p.sub)
    mask = _verdict_mask(fields)
    keep = np.union1d(subspace_candidates(S, C, box, mask), subspace_candidates(S, C, box, np.ones_like(mask)))
    keep = np.union1d(keep, _fatigue_candidates(S, C, fatigue_factor(job)[1], box, mask))
    return screening.sampled_at(p, box, keep)


def _fatigue_candidates(S: np.ndarray, C: np.ndarray, factor, b: screening.SampledBounds, mask: np.ndarray) -> np.ndarray:
    """Indices (ascending) of the nodes in ``mask`` of ``S`` (6, n, k) that can hold their
    smallest fatigue factor over the history ``C`` (steps, k): a lower bound of each node's
    factor from its sampled subspace bounds ``b`` (:func:`railcheck.fea.screening.fatigue_bounds`), a
    threshold from the nodes of smallest sampled factor evaluated exactly."""
    sa, sm = screening.fatigue_bounds(b)
    first = screening.first_nodes(np.where(mask, factor(*screening.fatigue_sampled(b)), np.inf), largest=False)
    first = first[mask[first]]
    top = float(factor(*alternating_and_mean(*component_range(S[:, first], C))).min())
    return np.flatnonzero(mask & (factor(sa, sm) <= top * (1.0 + screening.SLACK)))


@on_one_blas_thread
def solution_at(fields: UnitFields, c: np.ndarray, solve: UnitSolve, order: int, exclude: float) -> Solution:
    """The :class:`~railcheck.fea.elasticity.Solution` of the instant with coefficients
    ``c`` (for the VTU and the picture), built by superposition."""
    S = stress_at(fields.stress, c)
    vm = von_mises(S)
    nv = solve.vertices
    top = peak(vm, fields.nodes)
    away = peak(vm, fields.nodes, fields.verdict_mask)
    u = fields.displacement @ c
    return Solution(
        order=order,
        dofs=solve.dofs,
        elements=solve.elements,
        displacement=u[:nv],
        von_mises=vm[:nv].copy(),
        max_von_mises=top[0],
        max_von_mises_location=top[1],
        tip_displacement=fields.tip @ c,
        applied_forces={"total": solve.resultants @ c[: solve.resultants.shape[1]]},
        max_von_mises_away=away[0],
        max_von_mises_away_location=away[1],
        exclude_distance=exclude,
        stress=S,
        nodes=fields.nodes,
        seconds=solve.seconds,
        solver=solve.solver,
        warnings=[],
        node_displacement=u,
    )


def _mesh_source(mesh) -> str:
    """Where a part's mesh came from, for its progress line."""
    return " (shipped with railcheck)" if mesh.shipped else " (cached)" if mesh.cached else ""
