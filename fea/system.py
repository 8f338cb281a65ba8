"""The constrained system: the DOFs a support fixes, the free submatrix, the P1 -> P2
prolongation the p-multigrid needs, and the solve of ``K U = F`` with fixed DOFs held at
zero for one or several load columns (one factorisation). Units SI."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .errors import ModelError, NumericalError
from .mesh import dof_components, group_facets, scalar_basis
from .solvers import rigid_body_modes, solve_reduced

__all__ = ["supports", "solve", "free_submatrix", "p1_prolongation"]


def supports(basis, groups: dict, names: list[str]) -> np.ndarray:
    """The fixed DOFs: every component on the named groups' surfaces. Raises
    :class:`ModelError` when no support is named (the system would be singular)."""
    if not names:
        raise ModelError(
            "supports", "the part has no support: its rigid-body motion is undetermined (the stiffness matrix is singular)"
        )
    return np.unique(np.concatenate([basis.get_dofs(facets=group_facets(basis, groups, g)).all() for g in names]))


def solve(
    K,
    F: np.ndarray,
    fixed: np.ndarray,
    method: str | Callable = "auto",
    basis=None,
    maxiter: int = 2000,
    memory_limit: float | None = None,
    report=None,
) -> tuple[np.ndarray, dict]:
    """(U, info): displacements (N[, k]) m for loads F (N[, k]) with the ``fixed`` DOFs
    held at zero; one factorisation serves every column. ``basis`` gives the rigid-body
    modes the ``amg`` path needs; see :mod:`railcheck.fea.solvers` for ``method``."""
    N = K.shape[0]
    free = np.setdiff1d(np.arange(N), fixed)
    U = np.zeros(F.shape)
    if not np.any(F[free]):
        return U, {"solver": "none (zero load)", "iterations": 0, "residual": 0.0}
    Kc = free_submatrix(K, free)
    B = rigid_body_modes(basis.doflocs[:, free], dof_components(basis)[free]) if basis is not None else None
    prolong = (
        (lambda: p1_prolongation(basis)[free][:, _coarse_free(basis, free)])
        if basis is not None and basis.elem.elem.maxdeg == 2
        else None
    )
    U[free], info = solve_reduced(
        Kc, F[free], B, method=method, maxiter=maxiter, memory_limit=memory_limit, report=report, prolongation=prolong
    )
    if not np.all(np.isfinite(U)):
        raise NumericalError("the displacement is not finite")
    return U, info


def free_submatrix(K, free: np.ndarray):
    """``K[free][:, free]`` for a CSR matrix and sorted, distinct ``free`` indices, in one
    pass over the entries (scipy's two fancy-index passes take ten times as long on a
    13M-entry stiffness). Keeps sorted column indices sorted."""
    import scipy.sparse as sp

    K = sp.csr_matrix(K)
    n = K.shape[0]
    keep_dof = np.zeros(n, bool)
    keep_dof[free] = True
    renumber = np.cumsum(keep_dof, dtype=np.int64) - 1
    per_row = np.diff(K.indptr)
    keep = np.repeat(keep_dof, per_row) & keep_dof[K.indices]
    kept = np.concatenate([[0], np.cumsum(keep, dtype=np.int64)])
    counts = kept[K.indptr[1:]] - kept[K.indptr[:-1]]
    indptr = np.concatenate([[0], np.cumsum(counts[free], dtype=np.int64)])
    out = sp.csr_matrix((K.data[keep], renumber[K.indices[keep]], indptr), shape=(free.size, free.size))
    out.has_sorted_indices = K.has_sorted_indices
    return out


def p1_prolongation(basis):
    """(P2 vector DOFs, 3 x vertices): linear interpolation from the same mesh's P1 space:
    a vertex DOF copies its vertex, a mid-edge DOF averages its edge's two vertices
    (scikit-fem's P2 numbers vertices first, then edges). On a curved mesh this is the
    linear interpolation in reference coordinates, the P1 space of the same element map."""
    import scipy.sparse as sp

    sb = scalar_basis(basis)
    mesh = basis.mesh
    nv, ne = mesh.nvertices, mesh.edges.shape[1]
    if sb.N != nv + ne:
        raise RuntimeError("p-multigrid needs a P2 basis with vertex and edge DOFs only")
    edge_dof = sb.edge_dofs[0]
    rows = np.concatenate([sb.nodal_dofs[0], edge_dof, edge_dof])
    cols = np.concatenate([np.arange(nv), mesh.edges[0], mesh.edges[1]])
    vals = np.concatenate([np.ones(nv), np.full(ne, 0.5), np.full(ne, 0.5)])
    scalar = sp.csr_matrix((vals, (rows, cols)), shape=(sb.N, nv))
    return sp.kron(scalar, sp.identity(3), format="csr")  # vector DOFs interleave as 3 s + c


def _coarse_free(basis, free: np.ndarray) -> np.ndarray:
    """The P1 DOFs (3 v + c) whose vertex DOF is free in the P2 system."""
    sb = scalar_basis(basis)
    vertex_vector = (3 * sb.nodal_dofs[0][:, None] + np.arange(3)).ravel()  # P2 DOF of each P1 DOF
    return np.flatnonzero(np.isin(vertex_vector, free))
