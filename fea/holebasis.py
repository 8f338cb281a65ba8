"""A rail's unit cases in a setting-independent basis: one force per hole and direction,
each hole's pin-pressure harmonics and the body cases, solved once; any setting's cases
are then exact linear combinations of them (:class:`HoleBasis`), so a check of another
setting of the rig reads the store and solves nothing.

Every step from a load vector to a field is linear (assembly of the load, inertia relief,
the solve, the rigid-motion removal, stress recovery, a deflection operator), so the field
of a combination of load vectors is the same combination of their fields: with ``F_case =
F_basis T`` (T (basis, cases) the coefficients), ``S_case = S_basis T``. Where the two
paths differ is rounding only (about 1e-13 of the unit fields). Units: the fields' own
(Pa, m, N per unit coefficient).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .superpose import UnitFields
from .unitcases import CoupleCase, PressureCase, TractionCase, UnitSolve

__all__ = ["HoleBasis", "hole_basis", "project", "surface_nodes"]


@dataclass(frozen=True)
class HoleBasis:
    """``cases`` the basis's unit cases (named), ``transform`` (basis, cases) the
    coefficients that make each of the setting's cases from them (``F_case = F_basis T``)."""

    cases: dict
    transform: np.ndarray


def _force_name(hole: str, direction: int, pressure: bool) -> str:
    return f"{'xyz'[direction]}{'' if pressure else '_traction'}:{hole}"


def _force_kinds(cases: dict) -> list[tuple[int, bool]]:
    """(direction, pressure) of every hole force the cases use, in a fixed order."""
    kinds = set()
    for c in cases.values():
        if isinstance(c, TractionCase):
            kinds.add((c.direction, c.pressure))
        elif isinstance(c, CoupleCase):
            kinds.add((1, c.pressure))
    return sorted(kinds)


def _harmonics(cases: dict) -> tuple[tuple[int, ...], tuple[str, ...]]:
    """(harmonics, field names) of the cases' pin pressures, ((), ()) without any."""
    found = [c for c in cases.values() if isinstance(c, PressureCase)]
    if not found:
        return (), ()
    harmonics = found[0].harmonics
    return harmonics, tuple(dict.fromkeys(c.field for c in found))


def hole_basis(cases: dict, holes: list[str]) -> HoleBasis:
    """The basis for ``cases`` (a rail's unit cases for one setting) on every hole of
    ``holes``: the cases that are not hole forces (body cases) as they are, then per hole
    each (direction, pressure) force the cases use and each pin-pressure field; and the
    transform that rebuilds ``cases`` from it. Raises ValueError for a case it cannot
    express (a hole not in ``holes``, pressures of mixed harmonics)."""
    kinds = _force_kinds(cases)
    harmonics, fields = _harmonics(cases)
    basis: dict = {n: c for n, c in cases.items() if not isinstance(c, (TractionCase, CoupleCase, PressureCase))}
    for hole in holes:
        basis.update({_force_name(hole, d, p): TractionCase((hole,), d, pressure=p) for d, p in kinds})
        basis.update({f"pressure_{f}:{hole}": PressureCase(hole, f, harmonics) for f in fields})
    index = {n: i for i, n in enumerate(basis)}
    T = np.zeros((len(basis), len(cases)))
    for j, (name, case) in enumerate(cases.items()):
        for row, coefficient in _combination(name, case, harmonics).items():
            if row not in index:
                raise ValueError(f"unit case {name!r} uses {row!r}, which the hole basis lacks")
            T[index[row], j] += coefficient
    return HoleBasis(basis, T)


def _combination(name: str, case, harmonics: tuple[int, ...]) -> dict[str, float]:
    """basis case name -> coefficient that makes ``case`` (:func:`railcheck.fea.unitcases.case_vector`'s sums)."""
    if isinstance(case, TractionCase):
        weights = case.weights or (1.0 / len(case.groups),) * len(case.groups)
        out: dict[str, float] = {}
        for g, w in zip(case.groups, weights):
            key = _force_name(g, case.direction, case.pressure)
            out[key] = out.get(key, 0.0) + w
        return out
    if isinstance(case, CoupleCase):
        first, second = (_force_name(g, 1, case.pressure) for g in case.groups)
        return {first: -1.0 / case.arm, second: 1.0 / case.arm}
    if isinstance(case, PressureCase):
        if case.harmonics != harmonics:
            raise ValueError(f"unit case {name!r}: pin pressures of mixed harmonics")
        return {f"pressure_{case.field}:{case.group}": 1.0}
    return {name: 1.0}


def project(
    fields: UnitFields, solve: UnitSolve, basis: HoleBasis, names: tuple, tip_key, loaded, tip_keys: dict | None = None
):
    """(UnitFields, UnitSolve) of the setting's cases ``names`` from the basis's solved
    ``fields`` and ``solve``: stresses, displacements, resultants and balances times the
    transform; the deflection the one of ``fields.tips[tip_key]`` (a free body's per-setting
    deflection, None: ``fields.tip``), or with ``tip_keys`` (key -> basis tip key) one per
    key (``UnitFields.tips``); ``loaded`` the setting's loaded nodes."""
    T = basis.transform
    tips = fields.tips or {}  # a free body's deflection per far pair
    tip = fields.tip if tip_key is None else tips[tip_key]
    out = replace(
        fields,
        stress=np.tensordot(fields.stress, T, axes=([2], [0])),
        tip=np.zeros((3, T.shape[1])) if tip_keys else tip @ T,
        displacement=np.tensordot(fields.displacement, T, axes=([2], [0])),
        names=tuple(names),
        loaded=loaded,
        tips={key: tips[k] @ T for key, k in tip_keys.items()} if tip_keys else None,
    )
    meta = replace(
        solve,
        resultants=solve.resultants @ T,
        support_reactions=solve.support_reactions @ T,
        imbalance=None if solve.imbalance is None else solve.imbalance @ T,
    )
    return out, meta


def surface_nodes(cells: np.ndarray, facets: list[np.ndarray]) -> np.ndarray:
    """Indices of the stress nodes on the surface triangles ``facets`` (each (k, 3) vertex
    indices): their vertices and, for quadratic ``cells`` (elements, 10; VTK order:
    vertices, then the mid-nodes of edges 01, 12, 20, 03, 13, 23), their edges' mid-nodes
    (:func:`railcheck.fea.mesh.group_nodes` without a basis)."""
    tris = np.concatenate([np.asarray(f, dtype=np.int64).reshape(-1, 3) for f in facets])
    vertices = np.unique(tris)
    if cells.shape[1] < 10:
        return vertices
    n = np.int64(cells[:, :4].max() + 1)
    ends = np.array([[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]])
    a, b = cells[:, ends[:, 0]].ravel(), cells[:, ends[:, 1]].ravel()
    keys = np.minimum(a, b).astype(np.int64) * n + np.maximum(a, b)
    mids = cells[:, 4:10].ravel()
    keys, first = np.unique(keys, return_index=True)
    mids = mids[first]
    ea = tris[:, [0, 1, 2]].ravel()
    eb = tris[:, [1, 2, 0]].ravel()
    want = np.minimum(ea, eb) * n + np.maximum(ea, eb)
    pos = np.searchsorted(keys, want)
    return np.union1d(vertices, mids[pos])
