"""Stress recovery and post-processing: the element stress projected (L2) onto the
continuous scalar space of the same order, von Mises, peaks away from a support, means
over a surface.

One mass matrix serves all six components and every load case, factorised once and
solved to a relative residual below 1e-12 (checked); on straight elements the mass
matrix and the stress moments are closed form, on curved ones a degree-2p rule. The
"stress nodes" are that space's nodes (P2: vertices and mid-edge nodes). Every step is
linear in the load, so the stress of a combination of loads is the same combination of
their stresses (the cycle envelope relies on it). Units SI (Pa)."""

from __future__ import annotations

import numpy as np

from railcheck.base.machine import available_memory

from .assembly import affine_reference, mass_matrix, straight_and_curved, straight_jacobians
from .errors import NumericalError
from .invariants import von_mises
from .loading import surface_node_weights, surface_vectors
from .materials import Material
from .mesh import scalar_basis, vector_dof_map
from .solvers import FACTOR_MEMORY_FRACTION, factorise, solve_jacobi_cg

__all__ = [
    "VOIGT",
    "MASS_RTOL",
    "recover_stress",
    "von_mises",
    "away_from",
    "peak",
    "mean_over",
    "group_mean_operator",
    "section_mean_operator",
    "relative_deflection",
]


VOIGT = ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))  # xx, yy, zz, xy, yz, xz


MASS_RTOL = 1e-12  # the stress projection's relative residual |b - M s| / |b|
#: displacement columns from which the projection factorises its mass matrix rather than
#: iterate: CG wins for a column or two, the factor for many (``benchmarks/fe_stages.py``;
#: measured: docs/changelog.md, "The measurements behind tuned constants")
MASS_FACTOR_COLUMNS = 8


def recover_stress(basis, U: np.ndarray, material: Material, report=None) -> np.ndarray:
    """(6, nodes[, k]) Pa: the L2 projection of the element stress of each displacement
    column onto the continuous scalar space of the basis's order (xx, yy, zz, xy, yz, xz).
    Straight elements in closed form (:func:`affine_stress_moments`, :func:`mass_matrix`),
    curved ones by a rule exact to order 2p on their isoparametric map. From
    :data:`MASS_FACTOR_COLUMNS` columns the scalar mass matrix is factorised once (a third
    of the stiffness's rows, a far smaller factor) and every column solved by that
    factor, its true residual checked against :data:`MASS_RTOL`; with fewer, or no memory
    for the factor, Jacobi-preconditioned CG solves them (the mass matrix is well
    conditioned once scaled by its diagonal: some 60 iterations)."""

    U2 = U.reshape(U.shape[0], -1)
    k = U2.shape[1]
    straight, curved = straight_and_curved(basis)
    rhs = affine_stress_moments(basis, U2, material)  # (scalar N, 6 k)
    if curved is not None:
        rhs += quadrature_stress_moments(basis, curved, U2, material)
    M = mass_matrix(basis)
    n = M.shape[0]
    S = _project_by_factor(M, rhs, report) if k >= MASS_FACTOR_COLUMNS else None
    if S is None:
        S = solve_jacobi_cg(M, rhs, rtol=MASS_RTOL)
    return S.reshape(n, 6, k).transpose(1, 0, 2).reshape((6, n) + U.shape[1:])


def _project_by_factor(M, rhs: np.ndarray, report=None) -> np.ndarray | None:
    """``M^-1 rhs`` by a direct factor of the mass matrix, its residual checked against
    :data:`MASS_RTOL`; None when the factor does not fit in memory or fails."""
    try:
        factor = factorise(M, "direct", FACTOR_MEMORY_FRACTION * available_memory(), report)
    except (NumericalError, MemoryError):
        return None
    try:
        return factor.solve(rhs, rtol=MASS_RTOL, extended=False, refine=False)
    except NumericalError:
        return None
    finally:
        factor.free()


def affine_stress_moments(basis, U2: np.ndarray, material: Material, values: int = 4_000_000) -> np.ndarray:
    """(scalar N, 6 k): :func:`quadrature_stress_moments` of the straight elements, in closed
    form: on an affine element of degree p <= 2 the stress has degree p - 1 <= 1, so it is
    the interpolant of its values at the four vertices, and its moments are
    |det J| sum_v C[a, v] sigma_v with C from :func:`affine_reference`."""
    numbering = scalar_basis(basis)
    grads, _, C = affine_reference(basis.elem.elem)
    vector_of = vector_dof_map(basis, numbering)
    straight, _ = straight_and_curved(basis)
    sdofs = numbering.element_dofs[:, straight]  # (nb, n)
    nb, n = sdofs.shape
    k = U2.shape[1]
    det, inverse = straight_jacobians(basis)
    out = np.empty((n, nb, 6, k))
    chunk = max(1, values // (4 * 9 * k))
    for start in range(0, n, chunk):
        sl = slice(start, min(start + chunk, n))
        ue = U2[vector_of[sdofs[:, sl]]]  # (nb, e, 3, k)
        H = np.einsum("aeik,vam->evimk", ue, grads, optimize=True)  # du_i/dxi_m
        grad = np.einsum("evimk,emj->evijk", H, inverse[sl], optimize=True)  # du_i/dx_j
        sig = _voigt_stress(grad, material)  # (e, v, 6, k)
        out[sl] = np.einsum("av,evck->eack", C, sig, optimize=True) * det[sl, None, None, None]
    return _sum_onto_nodes(sdofs, numbering.N, out)


def quadrature_stress_moments(basis, sb, U2: np.ndarray, material: Material) -> np.ndarray:
    """(scalar N, 6 k): integral of each stress component of each column times each
    scalar shape function, vectorised over elements (in chunks) and columns."""
    vector_of = vector_dof_map(basis, sb)
    sdofs = sb.element_dofs  # (nb, nel)
    nb, nel = sdofs.shape
    k = U2.shape[1]
    phi = np.stack([sb.basis[a][0].value for a in range(nb)])  # (nb, nel, nq)
    G = np.stack([sb.basis[a][0].grad for a in range(nb)])  # (nb, 3, nel, nq)
    out = np.empty((nel, nb, 6, k))
    chunk = max(1, 2_000_000 // (nb * phi.shape[2] * k * 9))
    for start in range(0, nel, chunk):
        sl = slice(start, min(start + chunk, nel))
        ue = U2[vector_of[sdofs[:, sl]]]  # (nb, e, 3, k)
        grad = np.einsum("aeik,ajeq->eqijk", ue, G[:, :, sl, :], optimize=True)  # du_i/dx_j
        sig = _voigt_stress(grad, material)  # (e, q, 6, k)
        out[sl] = np.einsum("aeq,eq,eqck->eack", phi[:, sl, :], sb.dx[sl], sig, optimize=True)
    return _sum_onto_nodes(sdofs, sb.N, out)


def _voigt_stress(grad: np.ndarray, material: Material) -> np.ndarray:
    """(e, p, 6, k) Pa, components in :data:`VOIGT` order: Hooke's law of the displacement
    gradients ``grad`` (e, p, 3, 3, k), du_i/dx_j at p points of e elements, k columns."""
    lam, mu = material.lame
    ii = np.array([i for i, _ in VOIGT])
    jj = np.array([j for _, j in VOIGT])
    eps = 0.5 * (grad + np.swapaxes(grad, 2, 3))
    tr = eps[:, :, 0, 0] + eps[:, :, 1, 1] + eps[:, :, 2, 2]
    return 2 * mu * eps[:, :, ii, jj, :] + lam * tr[:, :, None, :] * (ii == jj)[None, None, :, None]


def _sum_onto_nodes(sdofs: np.ndarray, n: int, values: np.ndarray) -> np.ndarray:
    """(n, rest): per-element values (e, nb, ...) summed onto the scalar nodes ``sdofs``
    (nb, e) of each element."""
    import scipy.sparse as sp

    nb, e = sdofs.shape
    scatter = sp.csr_matrix((np.ones(e * nb), (sdofs.T.ravel(), np.arange(e * nb))), shape=(n, e * nb))
    return np.asarray(scatter @ values.reshape(e * nb, int(np.prod(values.shape[2:], dtype=int))))


def away_from(locations: np.ndarray, support_points: np.ndarray, distance: float) -> np.ndarray:
    """(nodes,) bool: the ``locations`` (nodes, 3) farther than ``distance`` (m) from
    every ``support_points`` (k, 3); all True when ``distance`` is 0."""
    if distance <= 0:
        return np.ones(locations.shape[0], dtype=bool)
    from scipy.spatial import cKDTree

    dist, _ = cKDTree(support_points).query(locations)
    return dist > distance


def peak(values: np.ndarray, locations: np.ndarray, mask: np.ndarray | None = None) -> tuple[float, np.ndarray, int]:
    """(value, location (3,), index) of the largest ``values`` (nodes,) among the nodes
    where ``mask`` holds (all when None, or when the mask selects nothing)."""
    if mask is not None and np.any(mask):
        i = int(np.argmax(np.where(mask, values, -np.inf)))
    else:
        i = int(np.argmax(values))
    return float(values[i]), locations[i].copy(), i


def mean_over(basis, groups: dict, group: str) -> np.ndarray:
    """(3, N): the area-weighted mean displacement over ``group`` is ``W @ U`` (m)."""
    return surface_vectors(basis, groups, group)


def group_mean_operator(basis, groups: dict, names: list[str]) -> tuple[np.ndarray, float]:
    """((3, N), x m): the operator giving the mean displacement over the named surfaces
    (each surface's area-weighted mean, then their plain mean) and where they sit along x."""
    vector_of = vector_dof_map(basis, scalar_basis(basis))
    sb = scalar_basis(basis)
    op, xs = np.zeros((3, basis.N)), []
    for name in names:
        nodes, weights = surface_node_weights(basis, groups, name)
        w = weights / weights.sum()
        for c in range(3):
            op[c, vector_of[nodes, c]] += w / len(names)
        xs.append(float(w @ sb.doflocs[0, nodes]))
    return op, float(np.mean(xs))


def relative_to_face(basis, groups: dict, face: str, measure: list[str]) -> np.ndarray:
    """(3, N): the mean displacement of the surfaces ``measure`` less the rigid motion of
    the plane face ``face`` (normal z) carried to their centroid: its mean translation t
    and its rotation theta (about x and y from the least-squares plane of its u_z, about z
    from its in-plane displacements), t + theta x (m - c)."""
    sb = scalar_basis(basis)
    vector_of = vector_dof_map(basis, sb)
    nodes, weights = surface_node_weights(basis, groups, face)
    w = weights / weights.sum()
    p = sb.doflocs[:, nodes].T
    c = w @ p
    d = p - c
    dofs = vector_of[nodes]
    translation = np.zeros((3, basis.N))
    for k in range(3):
        translation[k, dofs[:, k]] = w
    design = np.column_stack([np.ones(len(w)), d[:, 0], d[:, 1]])
    fit = np.linalg.solve(design.T @ (w[:, None] * design), (design * w[:, None]).T)  # (3, n): a, b, c of u_z
    rotation = np.zeros((3, basis.N))
    rotation[0, dofs[:, 2]] = fit[2]  # u_z = theta_x y - theta_y x
    rotation[1, dofs[:, 2]] = -fit[1]
    r2 = w @ (d[:, 0] ** 2 + d[:, 1] ** 2)
    rotation[2, dofs[:, 1]] += w * d[:, 0] / r2  # theta_z = mean(x u_y - y u_x) / mean(r^2)
    rotation[2, dofs[:, 0]] -= w * d[:, 1] / r2
    M, _ = group_mean_operator(basis, groups, measure)
    measured = [group_centroid(basis, groups, g) for g in measure]
    arm = np.mean(measured, axis=0) - c
    carried = translation + np.cross(rotation.T, arm).T  # theta x arm, row by row
    return M - carried


def group_centroid(basis, groups: dict, name: str) -> np.ndarray:
    """(3,) m: the area centroid of a named surface."""
    nodes, weights = surface_node_weights(basis, groups, name)
    return weights @ scalar_basis(basis).doflocs[:, nodes].T / weights.sum()


def section_mean_operator(basis, x0: float, half: float) -> np.ndarray:
    """(3, N): the mean displacement of the nodes within ``half`` (m) of the section x = x0."""
    sb = scalar_basis(basis)
    near = np.flatnonzero(np.abs(sb.doflocs[0] - x0) <= half)
    if near.size == 0:
        raise ValueError(f"no node within {half} m of x = {x0} m")
    vector_of = vector_dof_map(basis, sb)
    op = np.zeros((3, basis.N))
    for c in range(3):
        op[c, vector_of[near, c]] = 1.0 / near.size
    return op


def relative_deflection(basis, groups: dict, ref_a: list[str], ref_b: list[str], measure) -> np.ndarray:
    """(3, N): the displacement at ``measure`` (a list of surfaces, or the x in m of a
    section) less the rigid line through the mean displacements of the surfaces ``ref_a``
    and ``ref_b`` (interpolated, or extrapolated, along x): a pinned link's sag relative
    to the line through its pins, or a crank's deflection at A relative to its shaft. With
    ``ref_b`` equal to ``ref_a``: :func:`relative_to_face` (a bracket's top relative to its
    base)."""
    A, xa = group_mean_operator(basis, groups, ref_a)
    if list(ref_b) == list(ref_a):  # one reference face: relative to its rigid motion
        return relative_to_face(basis, groups, ref_a[0], list(measure))
    B, xb = group_mean_operator(basis, groups, ref_b)
    if isinstance(measure, (int, float)):
        M, xm = section_mean_operator(basis, float(measure), 0.5 * abs(xb - xa) / 20), float(measure)
    else:
        M, xm = group_mean_operator(basis, groups, list(measure))
    s = (xm - xa) / (xb - xa)
    return M - (1 - s) * A - s * B
