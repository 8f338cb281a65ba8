"""Unit load cases of one part: assemble and factorise once, solve every unit load, keep
what superposition needs (:class:`railcheck.fea.superpose.UnitFields`).

A case is either a :class:`TractionCase` (a total force of 1 N along one axis, shared
equally by the named groups as uniform tractions) or a :class:`BodyCase` (a body force
field per unit coefficient: ``uniform`` 1 N/m^3 along one axis; ``rotational``
(-(y - y0), x - x0, 0) and ``radial`` (x - x0, y - y0, 0) in N/m^3 per m about the pivot
(x0, y0), the shapes of a rigid rotation's tangential and centripetal accelerations).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from railcheck.base import machine

from .assembly import integration_basis
from .dynamic import DynamicModel, part_modes
from .elasticity import (
    assemble,
    away_from,
    body_force_vectors,
    group_nodes,
    mean_over,
    node_displacement,
    recover_stress,
    resultant,
    solve,
    stress_nodes,
    supports,
    unit_traction_vectors,
)
from .errors import ModelError
from .materials import Material
from .mesh import cached_on, forget, node_cells
from .pin_pressure import bearing_vectors, harmonic_names
from .relief import foundation_reaction, rigid_modes, solve_free_body
from .stress import relative_deflection
from .superpose import UnitFields

if TYPE_CHECKING:
    from railcheck.geometry.meshdata import MeshData


@dataclass(frozen=True)
class UnitSolve:
    """What a unit-case solve cost and balanced: DOFs, elements, vertices, the solver's
    info, stage ``seconds``, and per unit case (3, k) N the applied ``resultants`` and the
    ``support_reactions`` (which balance them)."""

    dofs: int
    elements: int
    vertices: int
    solver: dict
    seconds: dict[str, float]
    resultants: np.ndarray
    support_reactions: np.ndarray
    imbalance: np.ndarray | None = None  # (6, k) N, N m about the centroid: a free body's loads before relief
    modes: DynamicModel | None = None  # the lowest modes (their shapes dropped) when a dynamic response was asked
    mode_sets: dict | None = None  # key -> DynamicModel when several mode sets were asked (``modes`` a dict)


@dataclass(frozen=True)
class FreeBodyCases:
    """How a free body's unit cases are solved: its body cases carry ``mass`` kg (the
    dynamics' mass of the part) and its deflection is ``deflection`` = (reference groups
    A, reference groups B, measured groups or the x (m) of a section): the displacement
    there less the rigid line through A and B; or a dict key -> such a tuple, one
    deflection per key (a sweep's hole groups), given back as ``UnitFields.tips``.

    With ``centre`` (x, y) m (part frame) and ``inertia`` kg m^2 about it (the dynamics'
    centre of mass and moment of inertia of the part) the mass is spread by a density
    graded to have exactly those (:func:`graded_density`), so the body forces balance the
    joint forces to rounding; without them, uniformly; with ``mass`` None the body cases
    keep their unit density (their coefficients carry the material's)."""

    mass: float | None
    deflection: tuple | dict
    centre: tuple[float, float] | None = None
    inertia: float | None = None
    held: tuple[str, ...] = ()  # groups held for its modes (a bolted-down part's base), instead of pins


@dataclass(frozen=True)
class TractionCase:
    """A unit force (1 N) along ``direction`` (0 x, 1 y, 2 z, part frame) shared by the
    ``groups``: equally, or in the proportions ``weights`` (summing to 1). Spread over each
    hole as a uniform traction, or with ``pressure`` (x or y only) as the radial pressure
    ``cos phi`` / ``sin phi`` of a pin (:func:`railcheck.fea.pin_pressure.bearing_vectors`)."""

    groups: tuple[str, ...]
    direction: int
    weights: tuple[float, ...] = ()
    pressure: bool = False


@dataclass(frozen=True)
class CoupleCase:
    """A unit couple (1 N m about +z) carried by two holes ``arm`` m apart along x: -1/arm N
    along y on ``groups[0]``, +1/arm N on ``groups[1]`` (the two screws of a plate that carries a torque); each
    hole's force spread as :class:`TractionCase` spreads it (``pressure``)."""

    groups: tuple[str, str]
    arm: float
    pressure: bool = False


@dataclass(frozen=True)
class PressureCase:
    """A self-equilibrated radial pressure on the bore of ``group``: the field ``field``
    (``"0"``, ``"2c"``, ...) of :func:`railcheck.fea.pin_pressure.bearing_vectors` with
    ``harmonics``; its coefficient is a pin force's ``|F| a_k cos k theta`` (N)."""

    group: str
    field: str
    harmonics: tuple[int, ...]


@dataclass(frozen=True)
class FoundationCase:
    """A unit case ``case`` together with the reaction of a rigid foundation on the face
    ``group`` that balances it (:func:`railcheck.fea.relief.foundation_reaction`): a part
    bolted down by that face, as a free body with no clamp."""

    case: object
    group: str


@dataclass(frozen=True)
class BodyCase:
    field: str  # "uniform", "rotational" or "radial"
    direction: int = 0  # for "uniform"
    pivot: tuple[float, float] = (0.0, 0.0)  # m, part frame


def graded_density(basis, mass: float, centre: tuple[float, float], inertia: float):
    """rho(x) kg/m^3, a callable of points (3, ...) m: the density c0 + c1 xi + c2 xi^2 +
    c3 eta (xi, eta the offsets from ``centre`` over the radius of gyration) with which
    the meshed part has exactly ``mass`` kg, its centre of mass at ``centre`` (x, y) m and
    the polar moment ``inertia`` kg m^2 about it (z axis), integrated by the rule of the
    load vectors, so the body cases' resultants are the dynamics' rigid body's to
    rounding. Refuses a density that is not positive everywhere (a mass model the part's
    shape cannot carry)."""
    ib = integration_basis(basis)
    x = ib.global_coordinates().value  # (3, elements, points)
    dx = ib.dx
    scale = np.sqrt(inertia / mass)
    terms = _density_terms(x, centre, scale)
    cx, cy = x[0] - centre[0], x[1] - centre[1]
    tests = [np.ones_like(cx), cx, cy, cx**2 + cy**2]
    A = np.array([[np.sum(t * g * dx) for g in terms] for t in tests])
    c = np.linalg.solve(A, [mass, 0.0, 0.0, inertia])
    rho = lambda p: np.tensordot(c, _density_terms(p, centre, scale), axes=1)  # noqa: E731
    if rho(x).min() <= 0:
        raise ModelError("mass model", "the part's shape cannot carry the dynamics' mass distribution (density <= 0)")
    return rho


def _density_terms(x, centre, scale) -> np.ndarray:
    xi, eta = (x[0] - centre[0]) / scale, (x[1] - centre[1]) / scale
    return np.stack([np.ones_like(xi), xi, xi**2, eta])


def case_vector(basis, groups: dict, case, density=None) -> np.ndarray:
    """(N,) the load vector of one unit case; a body case's field times ``density(x)``
    (a callable of points (3, ...) m) when given."""
    from skfem import LinearForm, asm

    if isinstance(case, FoundationCase):
        load = case_vector(basis, groups, case.case, density)
        return load + foundation_reaction(basis, groups, case.group, load)
    if density is not None and isinstance(case, BodyCase):
        rho = density
        if case.field == "uniform":
            form = LinearForm(lambda v, w: rho(w.x) * v[case.direction])
        else:
            x0, y0 = case.pivot
            if case.field == "rotational":
                form = LinearForm(lambda v, w: rho(w.x) * (-(w.x[1] - y0) * v[0] + (w.x[0] - x0) * v[1]))
            else:
                form = LinearForm(lambda v, w: rho(w.x) * ((w.x[0] - x0) * v[0] + (w.x[1] - y0) * v[1]))
        return asm(form, integration_basis(basis))

    if isinstance(case, TractionCase):
        weights = case.weights or (1.0 / len(case.groups),) * len(case.groups)
        spread = _pressure_vectors if case.pressure else unit_traction_vectors
        total = np.zeros(basis.N)
        for g, w in zip(case.groups, weights):  # in order, from 0: the same sum as Python's
            total = total + w * spread(basis, groups, g)[:, case.direction]
        return total
    if isinstance(case, CoupleCase):
        spread = _pressure_vectors if case.pressure else unit_traction_vectors
        first, second = (spread(basis, groups, g)[:, 1] for g in case.groups)
        return (second - first) / case.arm
    if isinstance(case, PressureCase):
        fields = _pressure_vectors(basis, groups, case.group, case.harmonics)
        return fields[:, 2 + harmonic_names(case.harmonics).index(case.field)]
    if case.field == "uniform":
        return body_force_vectors(basis)[:, case.direction]
    x0, y0 = case.pivot
    if case.field == "rotational":
        form = LinearForm(lambda v, w: -(w.x[1] - y0) * v[0] + (w.x[0] - x0) * v[1])
    elif case.field == "radial":
        form = LinearForm(lambda v, w: (w.x[0] - x0) * v[0] + (w.x[1] - y0) * v[1])
    else:
        raise ValueError(f"unknown body force field {case.field!r}")
    return asm(form, integration_basis(basis))


def _pressure_vectors(basis, groups: dict, group: str, harmonics: tuple[int, ...] = ()) -> np.ndarray:
    """:func:`railcheck.fea.pin_pressure.bearing_vectors` of a group, once per basis."""
    key = f"pin_pressure:{group}:{harmonics}"
    return cached_on(basis, key, lambda: bearing_vectors(basis, groups, group, harmonics))


def stress_recovery_bytes(elements: int, per_element: int, nodes: int, columns: int) -> float:
    """Bytes the stress recovery of ``columns`` unit cases holds at its peak: per case its
    element stresses (``elements`` x ``per_element`` nodes x 6 doubles, the curved
    quadrature's peak) and three node-stress arrays of ``nodes`` nodes."""
    return 8.0 * 6.0 * columns * (elements * per_element + 3.0 * nodes)


def refuse_fields_beyond_memory(basis, columns: int) -> None:
    """Refuse (``mesh.size``, one line) before the solve a part whose stress recovery
    cannot fit in memory: per unit case its element stresses (elements x nodes per element
    x 6 doubles, the curved quadrature's peak) and three node-stress arrays; a machine
    that holds the factor but not these failed after the whole solve."""
    need = stress_recovery_bytes(basis.nelems, basis.Nbfun // 3, basis.N // 3, columns)
    machine.refuse_beyond_memory(
        need,
        "mesh.size",
        f"recovering the stresses of {basis.nelems:,} elements for {columns} unit cases",
        "use a larger mesh size or hole_size",
    )


def solve_unit_cases(
    mesh: MeshData,
    material: Material,
    support_groups: list[str],
    cases: dict[str, object],
    *,
    order: int = 2,
    tip_group: str | None = None,
    exclude_distance: float = 0.0,
    solver: str = "auto",
    report=None,
    curved=None,
    free_body: FreeBodyCases | None = None,
    modes: tuple[int, list | None, tuple] | dict | None = None,
) -> tuple[UnitFields, UnitSolve]:
    """Unit fields of every case of ``cases`` on ``mesh`` (its points, tets and groups; one
    factorisation) and its :class:`UnitSolve` (timings, solver info, balances); ``curved``:
    the mesh's curved edges for isoparametric P2 (:func:`railcheck.fea.elasticity.assemble`).
    With ``free_body`` the part has no support: each case is solved by inertia relief
    (:mod:`railcheck.fea.relief`), the body cases carry ``free_body.mass`` kg spread
    uniformly, every node is in the verdict, and the "tip" is the deflection that
    ``free_body.deflection`` defines (:func:`railcheck.fea.stress.relative_deflection`).
    With ``modes`` the part's lowest modes follow the unit cases' as extra columns
    (:func:`_with_modes`: (count, pins, lumped masses), or a dict of them per key, then
    ``UnitSolve.mode_sets`` key -> its modes)."""
    points, groups = mesh.points, mesh.groups
    t = [time.perf_counter()]
    K, basis = assemble(points, mesh.tets, material, order, curved)
    F = case_matrix(basis, groups, cases, free_body)
    refuse_fields_beyond_memory(basis, F.shape[1])
    if modes is None:
        loads_integrated(basis, free_body is not None)
    t.append(time.perf_counter())
    if free_body is not None:
        held = _free_body_solve(K, F, basis, groups, material, solver, report, free_body)
    else:
        held = _supported_solve(K, F, basis, points, groups, support_groups, solver, report, exclude_distance, tip_group)
    U, info, fixed, imbalance, reactions, mask, tip_op = held
    names = tuple(cases)
    t.append(time.perf_counter())
    sets = None
    if modes is not None:
        U, names, sets = _with_modes(K, F, U, names, basis, groups, material, fixed, free_body, modes, report)
    tip = tip_op @ U if tip_op is not None else np.zeros((3, U.shape[1]))
    per_key = free_body.deflection if free_body is not None and isinstance(free_body.deflection, dict) else None
    tips = {key: relative_deflection(basis, groups, *d) @ U for key, d in per_key.items()} if per_key else None
    t.append(time.perf_counter())
    S = recover_stress(basis, U, material)
    extras = _node_sets(basis, groups, support_groups, cases)
    t.append(time.perf_counter())
    meta = _solve_meta(basis, mesh, info, np.diff(t), F, reactions, imbalance, sets, modes)
    return UnitFields(S, tip, node_displacement(basis, U), stress_nodes(basis), mask, names, **extras, tips=tips), meta


def loads_integrated(basis, free: bool) -> None:
    """Once the load vectors are integrated (and no modes follow, whose mass matrix takes
    the same rule): the rigid modes a free body's relief needs integrated now, then the
    load rule's basis dropped (:func:`fea.assembly.integration_basis`: 0.4 GB
    on the bracket's 175,566 DOFs, a third of what its process held when factorising)."""
    if free:
        rigid_modes(basis, 1.0)
    forget(basis, "integration_basis")


def _solve_meta(basis, mesh: MeshData, info: dict, seconds, F, reactions, imbalance, sets, modes) -> UnitSolve:
    """The solve's :class:`UnitSolve`: sizes, solver info, the ``seconds`` of its four
    stages (assembly, solve, modes, stress; modes only when asked), the cases'
    resultants and balances, and the modes (one set, or ``sets`` by key when ``modes``
    was a dict)."""
    return UnitSolve(
        dofs=int(basis.N),
        elements=int(mesh.tets.shape[0]),
        vertices=int(mesh.points.shape[0]),
        solver=info,
        seconds={
            k: v for k, v in zip(("assembly", "solve", "modes", "stress"), seconds) if k != "modes" or sets is not None
        },
        resultants=resultant(basis, F),
        support_reactions=reactions,
        imbalance=imbalance,
        modes=sets[None] if sets is not None and not isinstance(modes, dict) else None,
        mode_sets=sets if isinstance(modes, dict) else None,
    )


def case_matrix(basis, groups: dict, cases: dict, free_body: FreeBodyCases | None) -> np.ndarray:
    """(dofs, cases) N: each case's load vector; a free body's body cases carry its mass
    (spread uniformly, or graded to its centre and inertia) unless their coefficients
    carry the material's density."""
    F = np.column_stack([case_vector(basis, groups, c) for c in cases.values()])
    if free_body is None:
        return F
    body = np.array([isinstance(c, BodyCase) for c in cases.values()])
    if free_body.mass is None:  # the body cases' coefficients carry the material's density
        pass
    elif free_body.inertia is None:
        F[:, body] *= free_body.mass / body_force_vectors(basis)[:, 0].sum()  # kg / m^3: the FE body weighs mass
    elif body.any():
        assert free_body.centre is not None  # given with the inertia (FreeBodyCases)
        rho = graded_density(basis, free_body.mass, free_body.centre, free_body.inertia)
        F[:, body] = np.column_stack([case_vector(basis, groups, c, rho) for c in cases.values() if isinstance(c, BodyCase)])
    return F


def _free_body_solve(K, F: np.ndarray, basis, groups: dict, material: Material, solver, report, free_body: FreeBodyCases):
    """(U, info, fixed, imbalance, reactions, verdict mask, tip operator) of a free body
    solved by inertia relief: no fixed DOF, every node in the verdict, the reactions the
    negative imbalance."""
    relieved = solve_free_body(K, F, basis, material.density, solver, report)
    mask = np.ones(stress_nodes(basis).shape[0], dtype=bool)
    per_key = free_body.deflection if isinstance(free_body.deflection, dict) else None
    tip_op = None if per_key else relative_deflection(basis, groups, *free_body.deflection)
    fixed = np.zeros(0, dtype=np.int64)
    return relieved.U, relieved.info, fixed, relieved.imbalance, -relieved.imbalance[:3], mask, tip_op


def _supported_solve(K, F, basis, points, groups: dict, support_groups, solver, report, exclude_distance, tip_group):
    """(U, info, fixed, imbalance None, support reactions, verdict mask, tip operator) of a
    part held at ``support_groups``: the verdict away from them by ``exclude_distance`` m."""
    fixed = supports(basis, groups, support_groups)
    U, info = solve(K, F, fixed, solver, basis, report=report)
    reactions = _support_reactions(basis, K, U, F, fixed)
    support_pts = points[np.unique(np.concatenate([groups[g].ravel() for g in support_groups]))]
    mask = away_from(stress_nodes(basis), support_pts, exclude_distance)
    tip_op = mean_over(basis, groups, tip_group) if tip_group else None
    return U, info, fixed, None, reactions, mask, tip_op


def _with_modes(K, F, U, names: tuple, basis, groups: dict, material: Material, fixed, free_body, modes, report=None):
    """(U with the modes' shapes as extra columns, names with theirs, key -> DynamicModel).
    ``modes`` = (count, pins, lumped masses): the part's lowest modes
    (:func:`railcheck.fea.dynamic.part_modes`: held at its supports, at a free body's held
    groups, or at ``pins``), columns "mode 1", ...; or a dict key -> (count, pins, lumped
    masses): one mode set per key (a rail's hole pairs carry their far joint's mass at
    different holes), columns "mode 1@key", ..., key by key."""
    requests = modes if isinstance(modes, dict) else {None: modes}
    held_modes = free_body is not None and bool(free_body.held)
    density = material.density
    if free_body is not None and free_body.mass is not None:  # the FE body carries the dynamics' mass
        density = free_body.mass / body_force_vectors(basis)[:, 0].sum()
    sets: dict = {}
    shared: dict = {}
    for key, (count, pins, lumped) in requests.items():
        held = None if pins else (supports(basis, groups, list(free_body.held)) if held_modes else fixed)
        found = part_modes(
            K, basis, density, F, count, fixed=held, pins=pins, groups=groups, lumped=lumped, shared=shared, progress=report
        )
        U = np.hstack([U, found.shapes])
        names += tuple(f"mode {i + 1}" + ("" if key is None else f"@{key}") for i in range(count))
        sets[key] = DynamicModel(hz=found.hz, shapes=np.zeros((0, count)), modal_loads=found.modal_loads)
    return U, names, sets


def _node_sets(basis, groups: dict, support_groups: list[str], cases: dict) -> dict:
    """The fields' node sets: ``cells`` (the P2 cells' nodes), ``support`` and ``loaded``
    (the nodes of the support groups and of the groups a traction or couple loads)."""
    inner = [c.case if isinstance(c, FoundationCase) else c for c in cases.values()]
    loaded = sorted({g for c in inner if isinstance(c, (TractionCase, CoupleCase)) for g in c.groups})
    return {
        "cells": node_cells(basis),
        "support": group_nodes(basis, groups, support_groups) if support_groups else np.zeros(0, dtype=np.int64),
        "loaded": group_nodes(basis, groups, loaded) if loaded else np.zeros(0, dtype=np.int64),
    }


def _support_reactions(basis, K, U: np.ndarray, F: np.ndarray, fixed: np.ndarray) -> np.ndarray:
    """(3, k) N: the total force the support exerts on the part in each unit case, the
    resultant of K U - F over the fixed DOFs (it balances the applied loads)."""
    R = np.zeros_like(F)
    R[fixed] = (K @ U - F)[fixed]
    return resultant(basis, R)
