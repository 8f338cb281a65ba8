"""A free rail's unit fields solved once for every setting of the rig.

A rail's unit cases follow the setting: its far joint's bolts are the pair of holes the
bar length picks, shared by the lever rule. Solved as they are, each new setting would
assemble and solve the rail again. Instead a free rail is solved in its hole basis
(:mod:`railcheck.fea.holebasis`: a force per hole and direction, each hole's pin-pressure
harmonics, the body cases) with the deflection of every pair of holes its far joint can
use, and the setting's own cases are projected from it, exactly up to rounding. The store
keys the basis, which no bar length enters, so a check of any other setting reads it and
solves nothing.

A part whose check asks for its modes (effect ``dynamic``, or a certificate that does not
hold) pins its modal model at the setting's holes and carries its joints' masses there:
it is solved for its own cases, as before, and so is a clamped rail.
"""

from __future__ import annotations

import time
from dataclasses import replace

from railcheck import environment
from railcheck.fea.holebasis import HoleBasis, hole_basis, project, surface_nodes
from railcheck.fea.store import UnitRequest, is_stored, solve_stored
from railcheck.fea.unitcases import CoupleCase, TractionCase
from railcheck.model.jobs import PartJob, free_body_cases

__all__ = ["basis_free_body", "part_fields", "part_request", "stored", "uses_hole_basis"]


def uses_hole_basis(job: PartJob) -> bool:
    """Whether the part is solved in its hole basis: a free rail whose check needs no
    modes (see the module doc)."""
    return job.free_body is not None and job.geometry.kind == "rail" and job.dynamic is None


def far_pairs(job: PartJob) -> list[tuple[str, str]]:
    """Every pair of neighbouring holes the far joint's bolts can use (beyond the first
    hole, where the near joint sits)."""
    n = len(job.geometry.get("hole_x"))
    return [(f"hole_{k}", f"hole_{k + 1}") for k in range(1, n - 1)]


def _basis(job: PartJob, cases: dict) -> tuple[HoleBasis, object] | None:
    """(the hole basis, the key of the setting's deflection) for a part that uses one
    and whose setting the basis holds; None otherwise."""
    if not uses_hole_basis(job) or tuple(job.holes) not in far_pairs(job):
        return None
    holes = [f"hole_{k}" for k in range(len(job.geometry.get("hole_x")))]
    try:
        return hole_basis(cases, holes), tuple(job.holes)
    except ValueError:
        return None


def basis_free_body(job: PartJob):
    """The job's free-body request with the deflection of every far pair (keyed by it)."""
    assert job.free_body is not None  # uses_hole_basis
    deflections = {pair: free_body_cases(job.loads, job.geometry, list(pair)).deflection for pair in far_pairs(job)}
    return replace(job.free_body, deflection=deflections)


def _request(job: PartJob, mesh, cases: dict, free_body) -> UnitRequest:
    """The request of ``cases``; a part whose modes only give its certificate its lowest
    frequency asks for that one mode."""
    modes = job.dynamic
    return UnitRequest(
        mesh.points,
        mesh.tets,
        mesh.groups,
        job.material,
        list(job.supports),
        cases,
        job.mesh.order,
        job.tip,
        job.exclusion,
        mesh.curved if job.mesh.curved else None,
        free_body,
        (modes.modes if modes.exact else 1, list(modes.pins) if modes.pins else None, modes.lumped) if modes else None,
    )


def part_request(job: PartJob, mesh, cases: dict) -> UnitRequest:
    """What the part's unit solve depends on (:class:`railcheck.fea.store.UnitRequest`):
    its hole basis's when it uses one, else its own cases'."""
    found = _basis(job, cases)
    if found is None:
        return _request(job, mesh, cases, job.free_body)
    return _request(job, mesh, found[0].cases, basis_free_body(job))


def part_fields(job: PartJob, mesh, cases: dict, solver: str, report):
    """(UnitFields, UnitSolve, origin) of the part's ``cases`` through the store
    (:func:`railcheck.fea.store.solve_stored`), projected from its hole basis when it
    uses one (the solve's ``seconds`` gain ``project``)."""
    store = environment.unit_store()
    found = _basis(job, cases)
    if found is None:
        return solve_stored(part_request(job, mesh, cases), solver, report, store=store)
    basis, key = found
    fields, solve, origin = solve_stored(_request(job, mesh, basis.cases, basis_free_body(job)), solver, report, store=store)
    if origin != "stored":
        report(f"{len(basis.cases)} unit cases solved for every hole of the rail: any setting's are projected from them")
    t = time.perf_counter()
    loaded = _loaded_groups(cases)
    nodes = surface_nodes(fields.cells, [mesh.groups[g] for g in loaded]) if loaded and fields.cells is not None else None
    fields, solve = project(fields, solve, basis, tuple(cases), key, nodes)
    return fields, replace(solve, seconds={**solve.seconds, "project": time.perf_counter() - t}), origin


def _loaded_groups(cases: dict) -> list[str]:
    """The groups the cases' hole forces load, sorted (as the solve's node sets name them)."""
    return sorted({g for c in cases.values() if isinstance(c, (TractionCase, CoupleCase)) for g in c.groups})


def stored(job: PartJob, mesh, cases: dict) -> bool:
    """Whether the store holds the part's entry (on disk; reading verifies it)."""
    return is_stored(part_request(job, mesh, cases), environment.unit_store())
