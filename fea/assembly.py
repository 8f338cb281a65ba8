"""Assembly: the stiffness matrix of vector P1/P2 linear elasticity and the scalar mass
matrix of the stress projection, on straight and curved elements.

The element matrices' 3 x 3 blocks are written in place, (element, a, b) by component,
and summed onto the scalar DOF pairs by one sparse product (:func:`pair_pattern`); the
pattern comes from a counting sort in scipy's compiled sparse tools, not a global sort of
the pair keys. Curved elements take a degree-3 rule in the stiffness (straight ones the
4-point rule, as C3D10), so the patch test stays exact on curved meshes."""

from __future__ import annotations

import numpy as np

from .materials import Material
from .mesh import cached_on, curved_elements, element_bases, element_of, scalar_basis, skfem_mesh, vector_dof_map

__all__ = [
    "assemble",
    "load_intorder",
    "integration_basis",
    "stiffness_matrix",
    "pair_pattern",
    "scalar_pair_pattern",
    "mass_matrix",
    "affine_reference",
    "affine_jacobians",
    "straight_jacobians",
    "straight_and_curved",
]


def assemble(points: np.ndarray, tets: np.ndarray, material: Material, order: int = 2, curved=None):
    """(K, basis): the stiffness matrix (CSR, N/m) and scikit-fem's vector basis of
    ``order`` on the mesh (``points`` (n, 3) m, ``tets`` (m, 4); ``curved`` edges for P2,
    see the module doc)."""
    from skfem import Basis
    from skfem.element import ElementVector

    mesh = skfem_mesh(points, tets, curved if order == 2 else None)
    element = element_of(order)
    # the vector basis serves DOF numbering and node positions: a one-point rule keeps its
    # construction cheap; integrals take their own rule (stiffness, integration_basis)
    basis = Basis(mesh, ElementVector(element), intorder=1)
    return stiffness_matrix(basis, material), basis


def load_intorder(order: int) -> int:
    """The quadrature degree of the stiffness and the load integrals: 2 (the 4-point
    rule, as C3D10) for P2, 1 for P1."""
    return max(2 * (order - 1), 1)


def integration_basis(basis):
    """The vector basis with the load integrals' rule (built once per basis)."""
    from skfem import Basis

    order = basis.elem.elem.maxdeg
    return cached_on(basis, "integration_basis", lambda: Basis(basis.mesh, basis.elem, intorder=load_intorder(order)))


def stiffness_matrix(basis, material: Material, quadrature: tuple | None = None):
    """The elasticity stiffness matrix (sparse CSR, N/m) of a vector basis.

    All element matrices at once: with the scalar shape-function gradients G[a, i] at the
    quadrature points, the 3 x 3 block of scalar DOFs (a, b) is K_ab[i, j] = sum_q dx
    (lambda G_ai G_bj + mu (delta_ij G_a.G_b + G_aj G_bi)). The blocks are summed on the
    scalar DOF pairs (a tenth of the entries of a per-DOF COO sum) into a 3 x 3 block
    sparse matrix, then converted to CSR. Equal to scikit-fem's
    ``asm(linear_elasticity(lambda, mu), basis)`` with a basis of the same rule
    (tests/test_fea.py). ``quadrature``: the rule of straight elements (default: the
    4-point rule for P2, one point for P1), whatever the basis's own; curved elements take
    a degree-3 rule (:func:`curved_elements`).
    """
    import scipy.sparse as sp
    from skfem.quadrature import get_quadrature

    scalar = basis.elem.elem
    quadrature = quadrature or get_quadrature(scalar.refdom, load_intorder(scalar.maxdeg))
    sb = scalar_basis(basis)  # numbering only
    parts = element_bases(basis.mesh, scalar, quadrature, 3)
    vector_of = vector_dof_map(basis, sb)  # (scalar dofs, 3)
    if not np.array_equal(vector_of, 3 * np.arange(sb.N)[:, None] + np.arange(3)[None, :]):
        raise RuntimeError("the vector basis does not interleave its components (3 s + c)")
    sdofs = sb.element_dofs.T  # (nel, nb)
    nel, nb = sdofs.shape
    Ns = sb.N
    indptr, indices, summing = scalar_pair_pattern(basis)
    entries = np.empty((nel * nb * nb, 9))  # element blocks, (e, a, b) x (i, j)
    for part in parts:
        _element_blocks(part, material, entries)
    blocks = summing @ entries  # (pairs, 9): every pair's summed block
    del entries
    K = sp.bsr_matrix((blocks.reshape(-1, 3, 3), indices, indptr), shape=(3 * Ns, 3 * Ns)).tocsr()
    K.has_sorted_indices = True
    return K


def pair_pattern(dofs: np.ndarray, n: int):
    """The sparsity pattern of the pairs of DOFs that share an element, and how element
    entries sum into it. ``dofs`` (elements, nb) numbers each element's DOFs (< ``n``).
    Returns CSR ``indptr`` (n + 1,) and sorted ``indices`` (int32) of the pattern, and
    ``summing``: the 0/1 CSR matrix (pattern entries, elements * nb * nb) whose row p picks
    the element pairs (e, a, b), in that order, that land on entry p; ``summing @ values``
    sums element values into the pattern, each output row reading its inputs in one pass.

    A counting sort by row and a sort of each (short) row, in scipy's compiled sparse
    tools, instead of a global sort of the pair keys: ``np.unique`` of the keys is 2.5x
    slower on P2 meshes (docs/performance.md, "What dominates a solve")."""
    nel, nb = dofs.shape
    pairs = nel * nb * nb
    if pairs == 0 or pairs >= 2**31 or n >= 2**31:
        return pair_pattern_by_unique(dofs, n)
    try:
        from scipy.sparse._sparsetools import coo_tocsr, csr_sort_indices
    except ImportError:  # a scipy without its private sparse tools
        return pair_pattern_by_unique(dofs, n)
    import scipy.sparse as sp

    d32 = dofs.astype(np.int32)
    rows = np.repeat(d32, nb, axis=1).ravel()  # (e, a, b) -> dof a
    cols = np.tile(d32, (1, nb)).ravel()  # (e, a, b) -> dof b
    indptr = np.empty(n + 1, np.int32)
    indices = np.empty(pairs, np.int32)
    source = np.empty(pairs, np.int32)  # which element pair each CSR entry is
    coo_tocsr(n, n, pairs, rows, cols, np.arange(pairs, dtype=np.int32), indptr, indices, source)
    del rows, cols
    csr_sort_indices(n, indptr, indices, source)
    first = np.empty(pairs, bool)  # the first of equal entries in a row
    first[0] = True
    np.not_equal(indices[1:], indices[:-1], out=first[1:])
    first[indptr[1:-1][indptr[1:-1] < pairs]] = True
    starts = np.flatnonzero(first)
    counted = np.concatenate([[0], np.cumsum(first, dtype=np.int64)])
    summing = sp.csr_matrix(
        (np.ones(pairs), source, np.append(starts, pairs).astype(np.int32)), shape=(starts.size, pairs), copy=False
    )
    return counted[indptr].astype(np.int32), indices[starts], summing


def scalar_pair_pattern(basis):
    """:func:`pair_pattern` of the vector basis's scalar numbering, built once per basis
    (the stiffness and the stress projection's mass matrix share it)."""
    numbering = scalar_basis(basis)
    return cached_on(basis, "pair_pattern", lambda: pair_pattern(numbering.element_dofs.T, numbering.N))


def pair_pattern_by_unique(dofs: np.ndarray, n: int):
    """:func:`pair_pattern` by a global sort of the pair keys (reference and fallback)."""
    import scipy.sparse as sp

    key = (dofs[:, :, None].astype(np.int64) * n + dofs[:, None, :]).ravel()
    pairs, inverse = np.unique(key, return_inverse=True)
    indptr = np.concatenate([[0], np.cumsum(np.bincount(pairs // n, minlength=n))])
    summing = sp.csr_matrix((np.ones(key.size), (inverse.ravel(), np.arange(key.size))), shape=(pairs.size, key.size))
    return indptr.astype(np.int32), (pairs % n).astype(np.int32), summing


def _element_blocks(sb, material: Material, entries: np.ndarray, values: int = 2_000_000) -> None:
    """Write the element stiffness matrices' 3 x 3 blocks of the basis's elements into
    ``entries`` (elements * nb * nb, 9): rows in (element, a, b) order, component (i, j)
    in column 3 i + j. K_ab[i, j] = lambda P_ij + mu P_ji + mu delta_ij tr P with
    P_ij = sum_q dx G_ai G_bj, in chunks of about ``values`` numbers, each written in
    place where its elements are consecutive."""
    lam, mu = material.lame
    nb = len(sb.basis)
    G = np.stack([sb.basis[a][0].grad for a in range(nb)])  # (nb, 3, nel, nq)
    nel = G.shape[2]
    elements = np.arange(nel) if sb.tind is None else np.asarray(sb.tind)
    chunk = max(1, values // (9 * nb * nb))
    for start in range(0, nel, chunk):
        sl = slice(start, min(start + chunk, nel))
        g = G[:, :, sl, :]
        P = np.einsum("aieq,bjeq,eq->eabij", g, g, sb.dx[sl], optimize=True).reshape(-1, 9)
        these = elements[sl]
        run = these[-1] - these[0] == these.size - 1
        Kb = entries[these[0] * nb * nb : (these[-1] + 1) * nb * nb] if run else np.empty_like(P)
        np.copyto(Kb.reshape(-1, 3, 3), P.reshape(-1, 3, 3).transpose(0, 2, 1))  # mu P_ji
        Kb *= mu
        trace = P[:, 0] + P[:, 4] + P[:, 8]
        trace *= mu
        P *= lam
        Kb += P  # + lambda P_ij
        for diagonal in (0, 4, 8):  # + mu delta_ij tr P
            Kb[:, diagonal] += trace
        if not run:
            entries[(these[:, None] * (nb * nb) + np.arange(nb * nb)).ravel()] = Kb


def mass_matrix(basis):
    """The scalar mass matrix (m^3) of the vector basis's scalar space,
    M_ab = int phi_a phi_b, summed on :func:`pair_pattern`: |det J| times the reference
    matrix on straight elements, a rule exact to order 2p on curved ones."""
    import scipy.sparse as sp

    numbering = scalar_basis(basis)
    nb = numbering.element_dofs.shape[0]
    indptr, indices, summing = scalar_pair_pattern(basis)
    straight, curved = straight_and_curved(basis)
    _, reference, _ = affine_reference(basis.elem.elem)
    entries = np.empty((numbering.element_dofs.shape[1], nb, nb))
    det, _ = straight_jacobians(basis)
    if curved is None:
        np.multiply(det[:, None, None], reference[None], out=entries)
    else:
        entries[straight] = det[:, None, None] * reference[None]
        phi = np.stack([curved.basis[a][0].value for a in range(nb)])  # (nb, nel, nq)
        entries[np.asarray(curved.tind)] = np.einsum("aeq,beq,eq->eab", phi, phi, curved.dx, optimize=True)
    M = sp.csr_matrix((summing @ entries.reshape(-1), indices, indptr), shape=(numbering.N, numbering.N))
    M.has_sorted_indices = True
    return M


def affine_reference(scalar) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Reference-tetrahedron integrals of a scalar element of degree p <= 2 (reference
    volume 1/6): the shape functions' gradients at the four vertices (4, nb, 3), the mass
    matrix int phi_a phi_b (nb, nb), and int phi_a lambda_v (nb, 4) against the vertices'
    barycentric coordinates (a stress of degree p - 1 <= 1 is exactly its vertex
    interpolant). Integrated by a rule exact to degree 2p."""
    from skfem.quadrature import get_quadrature

    if scalar.maxdeg > 2:
        raise ValueError("the closed-form stress recovery needs an element of degree at most 2")
    nb = scalar.doflocs.shape[0]
    vertices = np.array([[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
    X, W = get_quadrature(scalar.refdom, 2 * scalar.maxdeg)
    phi = np.stack([scalar.lbasis(X, a)[0] for a in range(nb)])  # (nb, q)
    grads = np.stack([scalar.lbasis(vertices, a)[1].T for a in range(nb)], axis=1)  # (4, nb, 3)
    lam = np.vstack([1.0 - X.sum(axis=0), X])  # (4, q)
    return grads, np.einsum("aq,bq,q->ab", phi, phi, W), np.einsum("aq,vq,q->av", phi, lam, W)


def affine_jacobians(mesh, elements: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(|det J| (n,), J^-1 (n, 3, 3)) of the affine map x = x0 + J xi of the given
    elements, J[:, m] = x_{m+1} - x0 (m), from their vertices."""
    x = mesh.doflocs[:, : mesh.nvertices].T[mesh.t[:, elements].T]  # (n, 4, 3)
    J = np.transpose(x[:, 1:] - x[:, :1], (0, 2, 1))
    return np.abs(np.linalg.det(J)), np.linalg.inv(J)


def straight_jacobians(basis) -> tuple[np.ndarray, np.ndarray]:
    """:func:`affine_jacobians` of the straight elements (built once per vector basis:
    the stress moments and the mass matrix share them)."""
    straight, _ = straight_and_curved(basis)
    return cached_on(basis, "straight_jacobians", lambda: affine_jacobians(basis.mesh, straight))


def straight_and_curved(basis):
    """(straight, curved): the indices of the elements whose map is affine, and a scalar
    basis with a rule exact to order 2p on the curved ones (None on a straight mesh),
    built once per vector basis."""

    def make():
        from skfem import Basis

        mesh = basis.mesh
        curved = curved_elements(mesh)
        straight = np.setdiff1d(np.arange(mesh.nelements), curved)
        if curved.size == 0:
            return straight, None
        return straight, Basis(mesh, basis.elem.elem, intorder=2 * basis.elem.elem.maxdeg, elements=curved)

    return cached_on(basis, "straight_and_curved", make)
