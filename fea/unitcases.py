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

import numpy as np

from .assembly import integration_basis
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
from .materials import Material
from .mesh import node_cells
from .superpose import UnitFields


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


@dataclass(frozen=True)
class TractionCase:
    groups: tuple[str, ...]
    direction: int  # 0 x, 1 y, 2 z (part frame)


@dataclass(frozen=True)
class BodyCase:
    field: str  # "uniform", "rotational" or "radial"
    direction: int = 0  # for "uniform"
    pivot: tuple[float, float] = (0.0, 0.0)  # m, part frame


def case_vector(basis, groups: dict, case) -> np.ndarray:
    """(N,) the load vector of one unit case."""
    from skfem import LinearForm, asm

    if isinstance(case, TractionCase):
        share = sum(unit_traction_vectors(basis, groups, g)[:, case.direction] for g in case.groups)
        return share / len(case.groups)
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


def solve_unit_cases(
    points: np.ndarray,
    tets: np.ndarray,
    groups: dict,
    material: Material,
    support_groups: list[str],
    cases: dict[str, object],
    order: int = 2,
    tip_group: str | None = None,
    exclude_distance: float = 0.0,
    solver: str = "auto",
    report=None,
    curved=None,
) -> tuple[UnitFields, UnitSolve]:
    """Unit fields of every case (one factorisation) and its :class:`UnitSolve` (timings, solver info, balances)
    (``curved``: the mesh's curved edges for isoparametric P2, :func:`railcheck.fea.elasticity.assemble`)."""
    t = [time.perf_counter()]
    K, basis = assemble(points, tets, material, order, curved)
    fixed = supports(basis, groups, support_groups)
    F = np.column_stack([case_vector(basis, groups, c) for c in cases.values()])
    t.append(time.perf_counter())
    U, info = solve(K, F, fixed, solver, basis, report=report)
    t.append(time.perf_counter())
    S = recover_stress(basis, U, material)
    nodes = stress_nodes(basis)
    support_pts = points[np.unique(np.concatenate([groups[g].ravel() for g in support_groups]))]
    mask = away_from(nodes, support_pts, exclude_distance)
    tip = mean_over(basis, groups, tip_group) @ U if tip_group else np.zeros((3, F.shape[1]))
    loaded = sorted({g for c in cases.values() if isinstance(c, TractionCase) for g in c.groups})
    extras = {
        "cells": node_cells(basis),
        "support": group_nodes(basis, groups, support_groups),
        "loaded": group_nodes(basis, groups, loaded) if loaded else np.zeros(0, dtype=np.int64),
    }
    t.append(time.perf_counter())
    meta = UnitSolve(
        dofs=int(basis.N),
        elements=int(tets.shape[0]),
        vertices=int(points.shape[0]),
        solver=info,
        seconds=dict(zip(("assembly", "solve", "stress"), np.diff(t))),
        resultants=resultant(basis, F),
        support_reactions=_support_reactions(basis, K, U, F, fixed),
    )
    return UnitFields(S, tip, node_displacement(basis, U), nodes, mask, tuple(cases), **extras), meta


def _support_reactions(basis, K, U: np.ndarray, F: np.ndarray, fixed: np.ndarray) -> np.ndarray:
    """(3, k) N: the total force the support exerts on the part in each unit case, the
    resultant of K U - F over the fixed DOFs (it balances the applied loads)."""
    R = np.zeros_like(F)
    R[fixed] = (K @ U - F)[fixed]
    return resultant(basis, R)
