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
from dataclasses import dataclass, replace

from railcheck import environment
from railcheck.fea.holebasis import HoleBasis, hole_basis, project, surface_nodes
from railcheck.fea.store import UnitRequest, is_stored, solve_stored
from railcheck.fea.unitcases import CoupleCase, FreeBodyCases, TractionCase
from railcheck.model.jobs import PartJob, free_body_cases
from railcheck.parallel.threads import on_one_blas_thread
from railcheck.parts import kind_of

__all__ = [
    "BasisSolve",
    "in_basis",
    "pair_deflections",
    "part_fields",
    "part_request",
    "solve_projected",
    "stored",
    "stored_request",
    "uses_hole_basis",
]


def uses_hole_basis(job: PartJob) -> bool:
    """Whether the part is solved in its hole basis: a free rail whose check needs no
    modes (see the module doc)."""
    return job.free_body is not None and kind_of(job.name).hole_basis and job.dynamic is None


def far_pairs(geo) -> list[tuple[str, str]]:
    """Every pair of neighbouring holes of the rail ``geo`` the far joint's bolts can use
    (beyond the first, which the near joint's screws share with the second)."""
    n = len(geo.get("hole_x"))
    return [(f"hole_{k}", f"hole_{k + 1}") for k in range(1, n - 1)]


def pair_deflections(loads, geo) -> dict:
    """Far pair -> the free rail's deflection with its far joint there (:func:`free_body_cases`)."""
    return {pair: free_body_cases(loads, geo, list(pair)).deflection for pair in far_pairs(geo)}


@dataclass(frozen=True)
class BasisSolve:
    """How a request is solved in its hole basis: the basis, the ``request`` that solves
    it (the store's key) and the deflections' keys: the basis's far pair of the request's
    one deflection (``tip``), or request key -> far pair (``tips``)."""

    basis: HoleBasis
    request: UnitRequest
    tip: tuple | None
    tips: dict | None


def in_basis(request: UnitRequest, geo, deflections: dict) -> BasisSolve | None:
    """The hole-basis solve of ``request`` (a free rail's, on the rail ``geo``, with
    ``deflections`` its :func:`pair_deflections`), or None when the request cannot be
    solved in it: modes asked for, a part without holes along it (``hole_x``), a case or a
    deflection the basis does not hold."""
    free = request.free_body
    if not isinstance(free, FreeBodyCases) or request.modes is not None or "hole_x" not in dict(geo.params):
        return None
    holes = [f"hole_{k}" for k in range(len(geo.get("hole_x")))]
    try:
        basis = hole_basis(request.cases, holes)
    except ValueError:
        return None
    pair_of = {repr(d): pair for pair, d in deflections.items()}
    wanted = free.deflection if isinstance(free.deflection, dict) else {None: free.deflection}
    keys = {key: pair_of.get(repr(d)) for key, d in wanted.items()}
    if None in keys.values():
        return None
    solved = replace(request, cases=basis.cases, free_body=replace(free, deflection=deflections))
    if isinstance(free.deflection, dict):
        return BasisSolve(basis, solved, None, keys)
    return BasisSolve(basis, solved, keys[None], None)


@on_one_blas_thread  # the same digits wherever it runs: alone, on a worker, beside another part on threads
def solve_projected(request: UnitRequest, geo, deflections: dict, solver: str, report, store):
    """(UnitFields, UnitSolve, origin) of ``request`` through ``store``
    (:func:`railcheck.fea.store.solve_stored`), projected from its hole basis when
    :func:`in_basis` can solve it (the solve's ``seconds`` gain ``project``), else as it is."""
    found = in_basis(request, geo, deflections)
    if found is None:
        return solve_stored(request, solver, report, store=store)
    fields, solve, origin = solve_stored(found.request, solver, report, store=store)
    if origin != "stored":
        report(
            f"{len(found.basis.cases)} unit cases solved for every hole of the rail: any setting's are projected from them"
        )
    t = time.perf_counter()
    loaded = _loaded_groups(request.cases)
    groups = request.groups
    nodes = surface_nodes(fields.cells, [groups[g] for g in loaded]) if loaded and fields.cells is not None else None
    fields, solve = project(fields, solve, found.basis, tuple(request.cases), found.tip, nodes, found.tips)
    return fields, replace(solve, seconds={**solve.seconds, "project": time.perf_counter() - t}), origin


def stored_request(request: UnitRequest, geo, deflections: dict) -> UnitRequest:
    """The request the store keys ``request``'s fields by: its hole basis's, or itself."""
    found = in_basis(request, geo, deflections)
    return request if found is None else found.request


def _request(job: PartJob, mesh, cases: dict) -> UnitRequest:
    """The request of the part's ``cases``; a part whose modes only give its certificate
    its lowest frequency asks for that one mode."""
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
        job.free_body,
        (modes.modes if modes.exact else 1, list(modes.pins) if modes.pins else None, modes.lumped) if modes else None,
    )


def _deflections(job: PartJob) -> dict:
    return pair_deflections(job.loads, job.geometry) if uses_hole_basis(job) else {}


def part_request(job: PartJob, mesh, cases: dict) -> UnitRequest:
    """What the part's unit fields are stored by (:class:`railcheck.fea.store.UnitRequest`):
    its hole basis's when it uses one, else its own cases'."""
    return stored_request(_request(job, mesh, cases), job.geometry, _deflections(job))


def part_fields(job: PartJob, mesh, cases: dict, solver: str, report):
    """(UnitFields, UnitSolve, origin) of the part's ``cases`` (:func:`solve_projected`)."""
    request = _request(job, mesh, cases)
    return solve_projected(request, job.geometry, _deflections(job), solver, report, environment.unit_store())


def _loaded_groups(cases: dict) -> list[str]:
    """The groups the cases' hole forces load, sorted (as the solve's node sets name them)."""
    return sorted({g for c in cases.values() if isinstance(c, (TractionCase, CoupleCase)) for g in c.groups})


def stored(job: PartJob, mesh, cases: dict) -> bool:
    """Whether the store holds the part's entry (on disk; reading verifies it)."""
    return is_stored(part_request(job, mesh, cases), environment.unit_store())
