"""Linear elasticity on a tetrahedral mesh with scikit-fem (vector P1 or P2): a small API
of plain functions with one job each, composed by :func:`solve_elasticity`.

Units SI: m, N, Pa. Supports and loads are addressed by the names of the mesh's boundary
groups (:class:`geometry.mesher.MeshData`)::

    K, basis = assemble(points, tets, material, order)
    F = load_vector(basis, groups, [HoleLoad("hole_3", (100, 0, 0))])    # (N,) or stack columns
    fixed = supports(basis, groups, ["shaft_hole"])
    U, info = solve(K, F, fixed)                  # one factorisation for every column of F
    S = recover_stress(basis, U, material)        # (6, nodes[, k]) Pa at the stress nodes
    value, where, i = peak(von_mises(S), stress_nodes(basis), exclude=(support_points, 5e-3))
    tip = mean_over(basis, groups, "end_free") @ U   # (3[, k]) m

* :class:`Support`: every displacement component fixed on the group's surface;
* :class:`HoleLoad`: a total force vector (N) on a group, applied as the uniform traction
  ``F / area`` so that its integral over the (discrete) surface equals ``F`` exactly.

P2 elements are isoparametric: given the mesh's curved edges (``curved`` = (edges (k, 2),
mid-edge points (k, 3)), the mid nodes gmsh placed on the true surfaces), the element map
is quadratic (scikit-fem ``MeshTet2``) and holes, seats and fillets are no longer faceted;
every other edge stays straight. P1 elements (and P2 without ``curved``) are straight.
Curved elements take a degree-3 quadrature rule in the stiffness (straight ones keep the
4-point rule, as C3D10), so the patch test stays exact on curved meshes.

Stress: the element stress is projected (L2) onto the continuous scalar space of the same
order (one mass matrix for all six components and every load case, solved by
Jacobi-preconditioned CG to a relative residual of 1e-12; on straight elements the mass
matrix and the stress moments are closed form, on curved ones a degree-2p rule); the
"stress nodes" are that space's nodes (P2: vertices and mid-edge nodes). Every step is
linear in the load (CG to 1e-12 is, to 1e-12), so the stress of a combination of loads is
the same combination of their stresses (the cycle envelope relies on it).

Assembly: the element matrices' 3 x 3 blocks are written in place, (element, a, b) by
component, and summed onto the scalar DOF pairs by one sparse product
(:func:`pair_pattern`); the pattern comes from a counting sort in scipy's compiled
sparse tools, not a global sort of the pair keys.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .errors import ModelError, NumericalError
from .materials import Material
from .solvers import rigid_body_modes, solve_reduced

LOCKING_NU = 0.45
VOIGT = ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))   # xx, yy, zz, xy, yz, xz


@dataclass(frozen=True)
class Support:
    group: str


@dataclass(frozen=True)
class HoleLoad:
    group: str
    force: tuple[float, float, float]     # N, part frame


@dataclass
class Solution:
    """Result of one solve. ``displacement``/``von_mises`` at the mesh's vertices (for
    VTK); ``stress`` (6, nodes) and ``nodes`` (nodes, 3) at every stress node."""

    order: int
    dofs: int
    elements: int
    displacement: np.ndarray           # (n_vertices, 3) m
    von_mises: np.ndarray              # (n_vertices,) Pa
    max_von_mises: float               # Pa, over all stress nodes
    max_von_mises_location: np.ndarray  # (3,) m
    tip_displacement: np.ndarray       # (3,) m, mean over the tip group
    applied_forces: dict[str, np.ndarray]  # group -> integral of the applied traction (N)
    max_von_mises_away: float = 0.0    # Pa, farther than exclude_distance from the support
    max_von_mises_away_location: np.ndarray | None = None
    exclude_distance: float = 0.0      # m
    stress: np.ndarray | None = None   # (6, nodes) Pa: xx, yy, zz, xy, yz, xz
    nodes: np.ndarray | None = None    # (nodes, 3) m
    seconds: dict[str, float] = field(default_factory=dict)
    solver: dict = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    node_displacement: np.ndarray | None = None   # (nodes, 3) m at every stress node

    @property
    def tip_deflection(self) -> float:
        return float(np.linalg.norm(self.tip_displacement))


def _skfem_mesh(points: np.ndarray, tets: np.ndarray, curved=None):
    """scikit-fem's mesh: straight ``MeshTet``, or ``MeshTet2`` with the ``curved`` edges'
    mid nodes moved onto the true surfaces (see the module doc)."""
    from skfem import MeshTet
    mesh = _with_entities(MeshTet(np.ascontiguousarray(points.T), np.ascontiguousarray(tets.T)))
    if curved is None or len(curved[0]) == 0:
        return mesh
    from dataclasses import replace

    from skfem import MeshTet2

    edges, where = curved
    quadratic = MeshTet2.from_mesh(mesh)
    n = np.int64(points.shape[0])
    keys = np.minimum(quadratic.edges[0], quadratic.edges[1]).astype(np.int64) * n \
        + np.maximum(quadratic.edges[0], quadratic.edges[1])
    order = np.argsort(keys)
    want = np.minimum(edges[:, 0], edges[:, 1]).astype(np.int64) * n + np.maximum(edges[:, 0], edges[:, 1])
    pos = np.clip(np.searchsorted(keys[order], want), 0, keys.size - 1)
    if not np.all(keys[order][pos] == want):
        raise ModelError("mesh.curved", "a curved edge is not an edge of the mesh")
    doflocs = quadratic.doflocs.copy()
    doflocs[:, quadratic.dofs.edge_dofs[0, order[pos]]] = np.asarray(where, float).T
    return _with_entities(replace(quadratic, doflocs=doflocs), mesh)


def _with_entities(mesh, source=None):
    """``mesh`` with its faces and edges (and each element's) set: copied from ``source``
    (a mesh of the same elements), or built by :func:`mesh_entities`, in place of
    scikit-fem's lazy ``np.unique(axis=1)``, six times slower."""
    for name, indices in (("facets", mesh.elem.refdom.facets), ("edges", mesh.elem.refdom.edges)):
        known = source is not None and hasattr(source, "_" + name)
        entities, of_element = (getattr(source, "_" + name), getattr(source, "_t2" + name[0])) if known \
            else mesh_entities(mesh.t, indices)
        setattr(mesh, "_" + name, entities)
        setattr(mesh, "_t2" + name[0], of_element)
    return mesh


def mesh_entities(t: np.ndarray, indices) -> tuple[np.ndarray, np.ndarray]:
    """(entities, of_element): the distinct sorted vertex tuples (k, n) of the elements'
    local ``indices`` (faces or edges), in lexicographic order, and each element's entity
    numbers (len(indices), elements): scikit-fem's ``Mesh.build_entities`` by one integer
    key per tuple."""
    tuples = np.sort(np.hstack([t[list(ix)] for ix in indices]), axis=0)
    base = np.int64(t.max(initial=0)) + 1
    if tuples.shape[0] * np.log2(float(base)) >= 62:      # the key would overflow int64
        from skfem.mesh import Mesh
        return Mesh.build_entities(t, indices)
    key = tuples[0].astype(np.int64)
    for row in tuples[1:]:
        key = key * base + row
    _, first, inverse = np.unique(key, return_index=True, return_inverse=True)
    return np.ascontiguousarray(tuples[:, first]), inverse.reshape(len(indices), t.shape[1])


def element_bases(mesh, scalar, quadrature: tuple, curved_intorder: int) -> list:
    """Scalar bases that together cover every element once: on a straight mesh one basis
    with ``quadrature``; on a curved one the straight elements through the affine map
    (same DOF numbering, several times cheaper than the isoparametric one) with
    ``quadrature``, and the curved elements with a rule of degree ``curved_intorder``."""
    from skfem import Basis, MeshTet

    curved = curved_elements(mesh)
    if curved.size == 0:
        return [Basis(mesh, scalar, quadrature=quadrature)]
    affine = _with_entities(MeshTet(np.ascontiguousarray(mesh.doflocs[:, :mesh.nvertices]), mesh.t), mesh)
    straight = np.setdiff1d(np.arange(mesh.nelements), curved)
    if not (np.array_equal(affine.t, mesh.t) and np.array_equal(affine.t2e, mesh.t2e)):
        raise RuntimeError("the affine twin numbers its DOFs differently from the curved mesh")
    parts = [Basis(affine, scalar, quadrature=quadrature, elements=straight),
             Basis(mesh, scalar, intorder=curved_intorder, elements=curved)]
    return parts


def curved_elements(mesh) -> np.ndarray:
    """Indices of the elements with a curved edge (none on a straight mesh)."""
    if mesh.doflocs.shape[1] == mesh.nvertices:
        return np.zeros(0, dtype=np.int64)
    p = mesh.doflocs
    a, b = p[:, mesh.edges[0]], p[:, mesh.edges[1]]
    off = np.linalg.norm(p[:, mesh.dofs.edge_dofs[0]] - 0.5 * (a + b), axis=0)
    moved = off > 1e-9 * np.linalg.norm(b - a, axis=0)
    return np.flatnonzero(np.any(moved[mesh.t2e], axis=0))


def _cached(owner, key: str, make):
    """``make()``, computed once per ``owner`` object (a mesh or a basis) and kept on it."""
    store = owner.__dict__.setdefault("_railcheck_cache", {})
    if key not in store:
        store[key] = make()
    return store[key]


def _sorted_facet_keys(mesh) -> tuple[np.ndarray, np.ndarray]:
    """(keys, order): a key per facet of the mesh from its sorted vertex triple, and the
    order that sorts the keys (built once per mesh)."""
    n = np.int64(mesh.nvertices)
    f = np.sort(mesh.facets, axis=0).astype(np.int64)
    keys = (f[0] * n + f[1]) * n + f[2]
    return keys, np.argsort(keys)


def facets_of(mesh, triangles: np.ndarray, name: str) -> np.ndarray:
    """Indices of ``mesh.facets`` matching the (k, 3) vertex triangles of a group
    (vectorised search on sorted vertex triples)."""
    n = np.int64(mesh.nvertices)
    keys, order = _cached(mesh, "facet_keys", lambda: _sorted_facet_keys(mesh))
    t = np.sort(triangles, axis=1).astype(np.int64).T
    want = (t[0] * n + t[1]) * n + t[2]
    pos = np.clip(np.searchsorted(keys[order], want), 0, keys.size - 1)
    found = keys[order][pos] == want
    if not np.all(found):
        raise ModelError(name, f"{np.count_nonzero(~found)} of its triangles are not faces of the mesh")
    return np.unique(order[pos])


def _element(order: int):
    from skfem import ElementTetP1, ElementTetP2
    if order == 1:
        return ElementTetP1()
    if order == 2:
        return ElementTetP2()
    raise ModelError("mesh.order", f"must be 1 or 2, got {order!r}")


def estimate_dofs(n_vertices: int, n_tets: int, order: int) -> int:
    """DOFs of the vector field: 3 per vertex (P1), plus 3 per edge (P2; ~1.2 edges per
    tetrahedron in a typical mesh, plus the vertices)."""
    return 3 * n_vertices if order == 1 else 3 * (n_vertices + int(1.25 * n_tets) + n_vertices)


def assemble(points: np.ndarray, tets: np.ndarray, material: Material, order: int = 2, curved=None):
    """(K, basis): the stiffness matrix (CSR, N/m) and scikit-fem's vector basis of
    ``order`` on the mesh (``points`` (n, 3) m, ``tets`` (m, 4); ``curved`` edges for P2,
    see the module doc)."""
    from skfem import Basis
    from skfem.element import ElementVector

    mesh = _skfem_mesh(points, tets, curved if order == 2 else None)
    element = _element(order)
    # the vector basis serves DOF numbering and node positions: a one-point rule keeps its
    # construction cheap; integrals take their own rule (stiffness, integration_basis)
    basis = Basis(mesh, ElementVector(element), intorder=1)
    return stiffness_matrix(basis, material), basis


def _load_intorder(order: int) -> int:
    """The quadrature degree of the stiffness and the load integrals: 2 (the 4-point
    rule, as C3D10) for P2, 1 for P1."""
    return max(2 * (order - 1), 1)


def integration_basis(basis):
    """The vector basis with the load integrals' rule (built once per basis)."""
    from skfem import Basis
    order = basis.elem.elem.maxdeg
    return _cached(basis, "integration_basis", lambda: Basis(basis.mesh, basis.elem, intorder=_load_intorder(order)))


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
    quadrature = quadrature or get_quadrature(scalar.refdom, _load_intorder(scalar.maxdeg))
    sb = scalar_basis(basis)                             # numbering only
    parts = element_bases(basis.mesh, scalar, quadrature, 3)
    vector_of = _vector_dof_map(basis, sb)               # (scalar dofs, 3)
    if not np.array_equal(vector_of, 3 * np.arange(sb.N)[:, None] + np.arange(3)[None, :]):
        raise RuntimeError("the vector basis does not interleave its components (3 s + c)")
    sdofs = sb.element_dofs.T                            # (nel, nb)
    nel, nb = sdofs.shape
    Ns = sb.N
    indptr, indices, summing = scalar_pair_pattern(basis)
    entries = np.empty((nel * nb * nb, 9))                # element blocks, (e, a, b) x (i, j)
    for part in parts:
        _element_blocks(part, material, entries)
    blocks = summing @ entries                            # (pairs, 9): every pair's summed block
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
    slower on P2 meshes (README, "What dominates a solve")."""
    nel, nb = dofs.shape
    pairs = nel * nb * nb
    if pairs == 0 or pairs >= 2**31 or n >= 2**31:
        return _pair_pattern_by_unique(dofs, n)
    try:
        from scipy.sparse._sparsetools import coo_tocsr, csr_sort_indices
    except ImportError:     # a scipy without its private sparse tools
        return _pair_pattern_by_unique(dofs, n)
    import scipy.sparse as sp

    d32 = dofs.astype(np.int32)
    rows = np.repeat(d32, nb, axis=1).ravel()            # (e, a, b) -> dof a
    cols = np.tile(d32, (1, nb)).ravel()                 # (e, a, b) -> dof b
    indptr = np.empty(n + 1, np.int32)
    indices = np.empty(pairs, np.int32)
    source = np.empty(pairs, np.int32)                   # which element pair each CSR entry is
    coo_tocsr(n, n, pairs, rows, cols, np.arange(pairs, dtype=np.int32), indptr, indices, source)
    del rows, cols
    csr_sort_indices(n, indptr, indices, source)
    first = np.empty(pairs, bool)                        # the first of equal entries in a row
    first[0] = True
    np.not_equal(indices[1:], indices[:-1], out=first[1:])
    first[indptr[1:-1][indptr[1:-1] < pairs]] = True
    starts = np.flatnonzero(first)
    counted = np.concatenate([[0], np.cumsum(first, dtype=np.int64)])
    summing = sp.csr_matrix((np.ones(pairs), source, np.append(starts, pairs).astype(np.int32)),
                            shape=(starts.size, pairs), copy=False)
    return counted[indptr].astype(np.int32), indices[starts], summing


def scalar_pair_pattern(basis):
    """:func:`pair_pattern` of the vector basis's scalar numbering, built once per basis
    (the stiffness and the stress projection's mass matrix share it)."""
    numbering = scalar_basis(basis)
    return _cached(basis, "pair_pattern", lambda: pair_pattern(numbering.element_dofs.T, numbering.N))


def _pair_pattern_by_unique(dofs: np.ndarray, n: int):
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
    G = np.stack([sb.basis[a][0].grad for a in range(nb)])   # (nb, 3, nel, nq)
    nel = G.shape[2]
    elements = np.arange(nel) if sb.tind is None else np.asarray(sb.tind)
    chunk = max(1, values // (9 * nb * nb))
    for start in range(0, nel, chunk):
        sl = slice(start, min(start + chunk, nel))
        g = G[:, :, sl, :]
        P = np.einsum("aieq,bjeq,eq->eabij", g, g, sb.dx[sl], optimize=True).reshape(-1, 9)
        these = elements[sl]
        run = these[-1] - these[0] == these.size - 1
        Kb = entries[these[0] * nb * nb:(these[-1] + 1) * nb * nb] if run else np.empty_like(P)
        np.copyto(Kb.reshape(-1, 3, 3), P.reshape(-1, 3, 3).transpose(0, 2, 1))   # mu P_ji
        Kb *= mu
        trace = P[:, 0] + P[:, 4] + P[:, 8]
        trace *= mu
        P *= lam
        Kb += P                                           # + lambda P_ij
        for diagonal in (0, 4, 8):                        # + mu delta_ij tr P
            Kb[:, diagonal] += trace
        if not run:
            entries[(these[:, None] * (nb * nb) + np.arange(nb * nb)).ravel()] = Kb


def _vector_dof_map(basis, sbasis) -> np.ndarray:
    """(scalar DOFs, 3): the vector basis's DOF for each scalar DOF and direction."""
    out = np.full((sbasis.N, 3), -1, dtype=np.int64)
    for name in ("nodal_dofs", "edge_dofs", "facet_dofs", "interior_dofs"):
        sd = getattr(sbasis, name, None)
        vd = getattr(basis, name, None)
        if sd is None or sd.size == 0:
            continue
        for k in range(sd.shape[0]):
            for c in range(3):
                out[sd[k], c] = vd[3 * k + c]
    if np.any(out < 0):
        raise RuntimeError("could not map the vector DOFs to the scalar ones")
    return out


def _components(basis) -> np.ndarray:
    """Direction (0, 1, 2) of every DOF of a vector basis."""
    comp = np.empty(basis.N, dtype=np.int64)
    for name in ("nodal_dofs", "edge_dofs", "facet_dofs", "interior_dofs"):
        dofs = getattr(basis, name, None)
        if dofs is None or dofs.size == 0:
            continue
        for c in range(3):          # rows c, c+3, ... are direction c
            comp[dofs[c::3].ravel()] = c
    return comp


def _group_facets(basis, groups: dict, name: str) -> np.ndarray:
    if name not in groups:
        raise ModelError(name, f"no such group in the mesh (groups: {', '.join(sorted(groups))})")
    return facets_of(basis.mesh, groups[name], name)


def surface_node_weights(basis, groups: dict, name: str) -> tuple[np.ndarray, np.ndarray]:
    """(nodes, weights m^2): the integral of each scalar shape function over ``name``'s
    surface, on the element's own (straight or curved) faces; the weights sum to the
    surface's area. A face's trace of the tetrahedral basis is the triangle's: 3 nodes (P1),
    or 6 (P2: vertices, then the mid nodes of edges 01, 12, 02), and a curved face's area
    element comes from its quadratic map, integrated by a degree-6 triangle rule."""
    _group_facets(basis, groups, name)                     # refuses unknown groups / foreign faces
    sb = scalar_basis(basis)
    mesh = basis.mesh
    tri = np.asarray(groups[name], dtype=np.int64)
    vertex_dof = sb.nodal_dofs[0][tri]                     # (f, 3)
    if sb.N == mesh.nvertices:                             # P1: linear faces
        nodes, lam_shape = vertex_dof, _tri_p1
        x = mesh.doflocs.T[tri]
    else:
        pairs = tri[:, [[0, 1], [1, 2], [0, 2]]]           # (f, 3, 2)
        edge = _edge_index(mesh, pairs.reshape(-1, 2)).reshape(-1, 3)
        nodes = np.concatenate([vertex_dof, sb.edge_dofs[0][edge]], axis=1)       # (f, 6)
        lam_shape = _tri_p2
        x = sb.doflocs.T[nodes]                            # (f, 6, 3): the face's own nodes
    w = _face_integrals(x, lam_shape)                      # (f, nodes per face)
    weights = np.bincount(nodes.ravel(), weights=w.ravel(), minlength=sb.N)
    used = np.flatnonzero(np.bincount(nodes.ravel(), minlength=sb.N))
    return used, weights[used]


def _tri_p1(lam: np.ndarray):
    """Linear triangle: shape values (q, 3) and barycentric derivatives (q, 3, 3)."""
    return lam, np.broadcast_to(np.eye(3), (lam.shape[0], 3, 3))


def _tri_p2(lam: np.ndarray):
    """Quadratic triangle (vertices, then edges 01, 12, 02): values (q, 6) and the
    derivatives with respect to each barycentric coordinate (q, 6, 3)."""
    L0, L1, L2 = lam.T
    N = np.stack([L0 * (2 * L0 - 1), L1 * (2 * L1 - 1), L2 * (2 * L2 - 1), 4 * L0 * L1, 4 * L1 * L2, 4 * L0 * L2], 1)
    z = np.zeros_like(L0)
    dN = np.stack([np.stack([4 * L0 - 1, z, z], 1), np.stack([z, 4 * L1 - 1, z], 1), np.stack([z, z, 4 * L2 - 1], 1),
                   np.stack([4 * L1, 4 * L0, z], 1), np.stack([z, 4 * L2, 4 * L1], 1), np.stack([4 * L2, z, 4 * L0], 1)], 1)
    return N, dN


def _face_integrals(x: np.ndarray, shape) -> np.ndarray:
    """(f, n): integral of each face shape function over faces with nodes ``x`` (f, n, 3)."""
    from skfem.quadrature import get_quadrature
    from skfem.refdom import RefTri

    X, W = get_quadrature(RefTri, 6)                       # reference triangle (0,0), (1,0), (0,1)
    lam = np.column_stack([1 - X[0] - X[1], X[0], X[1]])
    N, dN = shape(lam)                                     # (q, n), (q, n, 3)
    ds = dN[:, :, 1] - dN[:, :, 0]                         # d/ds with L1 = s, L2 = t
    dt = dN[:, :, 2] - dN[:, :, 0]
    a = np.einsum("qn,fnk->fqk", ds, x)
    b = np.einsum("qn,fnk->fqk", dt, x)
    jac = np.linalg.norm(np.cross(a, b), axis=-1)          # (f, q) area element
    return np.einsum("qn,fq,q->fn", N, jac, W)


def _edge_index(mesh, pairs: np.ndarray) -> np.ndarray:
    """Index into ``mesh.edges`` of each vertex pair (k, 2)."""
    n = np.int64(mesh.nvertices)
    e = np.sort(mesh.edges, axis=0).astype(np.int64)
    keys = e[0] * n + e[1]
    order = np.argsort(keys)
    p = np.sort(pairs, axis=1).astype(np.int64)
    want = p[:, 0] * n + p[:, 1]
    pos = np.clip(np.searchsorted(keys[order], want), 0, keys.size - 1)
    if not np.all(keys[order][pos] == want):
        raise RuntimeError("a face edge is not an edge of the mesh")
    return order[pos]


def _surface_vectors(basis, groups: dict, group: str) -> np.ndarray:
    """(3, N): row c holds the surface weights of group's nodes on their c DOFs, divided by
    the area (a unit total force along c as a uniform traction; also the mean over it)."""
    nodes, w = surface_node_weights(basis, groups, group)
    area = w.sum()
    if not area > 0:
        raise ModelError(group, "has zero area")
    out = np.zeros((3, basis.N))
    vector_of = _vector_dof_map(basis, scalar_basis(basis))
    for c in range(3):
        out[c, vector_of[nodes, c]] = w / area
    return out


def group_area(basis, groups: dict, group: str) -> float:
    """The area (m^2) of a group's surface on the element geometry (curved when P2 is)."""
    return float(surface_node_weights(basis, groups, group)[1].sum())


def unit_traction_vectors(basis, groups: dict, group: str) -> np.ndarray:
    """(N, 3): the load vectors of a unit total force (1 N) along x, y and z spread as a
    uniform traction over ``group``'s surface. Any force F on the group is ``T @ F``."""
    return _surface_vectors(basis, groups, group).T.copy()


def body_force_vectors(basis) -> np.ndarray:
    """(N, 3): the load vectors of a unit body force (1 N/m^3) along x, y and z."""
    from skfem import LinearForm, asm
    ib = integration_basis(basis)
    return np.stack([asm(LinearForm(lambda v, w, c=c: v[c] + 0.0 * w.x[0]), ib) for c in range(3)], axis=1)


def load_vector(basis, groups: dict, loads: list[HoleLoad], body_force=None) -> np.ndarray:
    """(N,) the consistent load vector of the hole loads (N) plus an optional uniform
    body force (3,) N/m^3."""
    f = np.zeros(basis.N)
    for load in loads:
        f += unit_traction_vectors(basis, groups, load.group) @ np.asarray(load.force, float)
    if body_force is not None and np.any(body_force):
        f += body_force_vectors(basis) @ np.asarray(body_force, float)
    return f


def resultant(basis, F: np.ndarray) -> np.ndarray:
    """The total force (3[, k]) N of assembled load vectors (the shape functions sum to one)."""
    comp = _components(basis)
    F2 = F.reshape(F.shape[0], -1)
    out = np.stack([F2[comp == c].sum(axis=0) for c in range(3)])
    return out.reshape((3,) + F.shape[1:])


def supports(basis, groups: dict, names: list[str]) -> np.ndarray:
    """The fixed DOFs: every component on the named groups' surfaces. Raises
    :class:`ModelError` when no support is named (the system would be singular)."""
    if not names:
        raise ModelError("supports", "the part has no support: its rigid-body motion is undetermined "
                                     "(the stiffness matrix is singular)")
    return np.unique(np.concatenate([basis.get_dofs(facets=_group_facets(basis, groups, g)).all() for g in names]))


def solve(K, F: np.ndarray, fixed: np.ndarray, method: str = "auto", basis=None, maxiter: int = 2000,
          memory_limit: float | None = None, report=None) -> tuple[np.ndarray, dict]:
    """(U, info): displacements (N[, k]) m for loads F (N[, k]) with the ``fixed`` DOFs
    held at zero; one factorisation serves every column. ``basis`` gives the rigid-body
    modes the ``amg`` path needs; see :mod:`fea.solvers` for ``method``."""
    N = K.shape[0]
    free = np.setdiff1d(np.arange(N), fixed)
    U = np.zeros(F.shape)
    if not np.any(F[free]):
        return U, {"solver": "none (zero load)", "iterations": 0, "residual": 0.0}
    Kc = free_submatrix(K, free)
    B = rigid_body_modes(basis.doflocs[:, free], _components(basis)[free]) if basis is not None else None
    prolong = (lambda: p1_prolongation(basis)[free][:, _coarse_free(basis, free)]) \
        if basis is not None and basis.elem.elem.maxdeg == 2 else None
    U[free], info = solve_reduced(Kc, F[free], B, method=method, maxiter=maxiter, memory_limit=memory_limit,
                                  report=report, prolongation=prolong)
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
    return sp.kron(scalar, sp.identity(3), format="csr")     # vector DOFs interleave as 3 s + c


def _coarse_free(basis, free: np.ndarray) -> np.ndarray:
    """The P1 DOFs (3 v + c) whose vertex DOF is free in the P2 system."""
    sb = scalar_basis(basis)
    vertex_vector = (3 * sb.nodal_dofs[0][:, None] + np.arange(3)).ravel()    # P2 DOF of each P1 DOF
    return np.flatnonzero(np.isin(vertex_vector, free))


def scalar_basis(basis):
    """The scalar basis of the vector basis's order: its nodes are the stress nodes (built
    once per vector basis)."""
    from skfem import Basis
    return _cached(basis, "scalar_basis", lambda: Basis(basis.mesh, basis.elem.elem, intorder=1))


def stress_nodes(basis) -> np.ndarray:
    """(nodes, 3) m: where :func:`recover_stress` gives the stress (the scalar space's
    nodes: the vertices first, then (P2) the mid-edge nodes)."""
    return scalar_basis(basis).doflocs.T.copy()


def node_cells(basis) -> np.ndarray:
    """(elements, 4 or 10) node indices per element in VTK's order (tetra / tetra10:
    vertices, then edges 01, 12, 20, 03, 13, 23, which is scikit-fem's order)."""
    return scalar_basis(basis).element_dofs.T.copy()


def node_displacement(basis, U: np.ndarray) -> np.ndarray:
    """(nodes, 3[, k]) m: the displacement at every stress node."""
    return U[_vector_dof_map(basis, scalar_basis(basis))]


def group_nodes(basis, groups: dict, names: list[str]) -> np.ndarray:
    """Indices of the stress nodes on the named groups' surfaces (mid-edge nodes included)."""
    sb = scalar_basis(basis)
    return np.unique(np.concatenate([sb.get_dofs(facets=_group_facets(basis, groups, g)).all() for g in names]))


MASS_RTOL = 1e-12       # the stress projection's relative residual |b - M s| / |b|


def recover_stress(basis, U: np.ndarray, material: Material, report=None) -> np.ndarray:
    """(6, nodes[, k]) Pa: the L2 projection of the element stress of each displacement
    column onto the continuous scalar space of the basis's order (xx, yy, zz, xy, yz, xz).
    Straight elements in closed form (:func:`_affine_stress_moments`, :func:`mass_matrix`),
    curved ones by a rule exact to order 2p on their isoparametric map. The mass matrix is
    well conditioned once scaled by its diagonal, so Jacobi-preconditioned CG solves all
    columns together to a relative residual of 1e-12 in some 60 iterations, far cheaper
    than factorising it (a factor as large as the stiffness's); a direct solve takes over
    should CG stall."""
    from .errors import NumericalError
    from .solvers import factorise, solve_jacobi_cg

    U2 = U.reshape(U.shape[0], -1)
    k = U2.shape[1]
    straight, curved = _straight_and_curved(basis)
    rhs = _affine_stress_moments(basis, U2, material)                          # (scalar N, 6 k)
    if curved is not None:
        rhs += _stress_moments(basis, curved, U2, material)
    M = mass_matrix(basis)
    n = M.shape[0]
    try:
        S = solve_jacobi_cg(M, rhs, rtol=MASS_RTOL)
    except NumericalError:
        S = factorise(M, "direct", report=report).solve(rhs, rtol=1e-9, extended=False)
    return S.reshape(n, 6, k).transpose(1, 0, 2).reshape((6, n) + U.shape[1:])


def _straight_and_curved(basis):
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
    return _cached(basis, "straight_and_curved", make)


def _straight_jacobians(basis) -> tuple[np.ndarray, np.ndarray]:
    """:func:`affine_jacobians` of the straight elements (built once per vector basis:
    the stress moments and the mass matrix share them)."""
    straight, _ = _straight_and_curved(basis)
    return _cached(basis, "straight_jacobians", lambda: affine_jacobians(basis.mesh, straight))


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
    phi = np.stack([scalar.lbasis(X, a)[0] for a in range(nb)])                       # (nb, q)
    grads = np.stack([scalar.lbasis(vertices, a)[1].T for a in range(nb)], axis=1)    # (4, nb, 3)
    lam = np.vstack([1.0 - X.sum(axis=0), X])                                          # (4, q)
    return grads, np.einsum("aq,bq,q->ab", phi, phi, W), np.einsum("aq,vq,q->av", phi, lam, W)


def affine_jacobians(mesh, elements: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(|det J| (n,), J^-1 (n, 3, 3)) of the affine map x = x0 + J xi of the given
    elements, J[:, m] = x_{m+1} - x0 (m), from their vertices."""
    x = mesh.doflocs[:, :mesh.nvertices].T[mesh.t[:, elements].T]                   # (n, 4, 3)
    J = np.transpose(x[:, 1:] - x[:, :1], (0, 2, 1))
    return np.abs(np.linalg.det(J)), np.linalg.inv(J)


def _affine_stress_moments(basis, U2: np.ndarray, material: Material, values: int = 4_000_000) -> np.ndarray:
    """(scalar N, 6 k): :func:`_stress_moments` of the straight elements, in closed
    form: on an affine element of degree p <= 2 the stress has degree p - 1 <= 1, so it is
    the interpolant of its values at the four vertices, and its moments are
    |det J| sum_v C[a, v] sigma_v with C from :func:`affine_reference`."""
    numbering = scalar_basis(basis)
    grads, _, C = affine_reference(basis.elem.elem)
    vector_of = _vector_dof_map(basis, numbering)
    straight, _ = _straight_and_curved(basis)
    sdofs = numbering.element_dofs[:, straight]                    # (nb, n)
    nb, n = sdofs.shape
    k = U2.shape[1]
    det, inverse = _straight_jacobians(basis)
    out = np.empty((n, nb, 6, k))
    chunk = max(1, values // (4 * 9 * k))
    for start in range(0, n, chunk):
        sl = slice(start, min(start + chunk, n))
        ue = U2[vector_of[sdofs[:, sl]]]                          # (nb, e, 3, k)
        H = np.einsum("aeik,vam->evimk", ue, grads, optimize=True)            # du_i/dxi_m
        grad = np.einsum("evimk,emj->evijk", H, inverse[sl], optimize=True)   # du_i/dx_j
        sig = _voigt_stress(grad, material)                                   # (e, v, 6, k)
        out[sl] = np.einsum("av,evck->eack", C, sig, optimize=True) * det[sl, None, None, None]
    return _sum_onto_nodes(sdofs, numbering.N, out)


def mass_matrix(basis):
    """The scalar mass matrix (m^3) of the vector basis's scalar space,
    M_ab = int phi_a phi_b, summed on :func:`pair_pattern`: |det J| times the reference
    matrix on straight elements, a rule exact to order 2p on curved ones."""
    import scipy.sparse as sp

    numbering = scalar_basis(basis)
    nb = numbering.element_dofs.shape[0]
    indptr, indices, summing = scalar_pair_pattern(basis)
    straight, curved = _straight_and_curved(basis)
    _, reference, _ = affine_reference(basis.elem.elem)
    entries = np.empty((numbering.element_dofs.shape[1], nb, nb))
    det, _ = _straight_jacobians(basis)
    if curved is None:
        np.multiply(det[:, None, None], reference[None], out=entries)
    else:
        entries[straight] = det[:, None, None] * reference[None]
        phi = np.stack([curved.basis[a][0].value for a in range(nb)])          # (nb, nel, nq)
        entries[np.asarray(curved.tind)] = np.einsum("aeq,beq,eq->eab", phi, phi, curved.dx, optimize=True)
    M = sp.csr_matrix((summing @ entries.reshape(-1), indices, indptr), shape=(numbering.N, numbering.N))
    M.has_sorted_indices = True
    return M


def _stress_moments(basis, sb, U2: np.ndarray, material: Material) -> np.ndarray:
    """(scalar N, 6 k): integral of each stress component of each column times each
    scalar shape function, vectorised over elements (in chunks) and columns."""
    vector_of = _vector_dof_map(basis, sb)
    sdofs = sb.element_dofs                                        # (nb, nel)
    nb, nel = sdofs.shape
    k = U2.shape[1]
    phi = np.stack([sb.basis[a][0].value for a in range(nb)])      # (nb, nel, nq)
    G = np.stack([sb.basis[a][0].grad for a in range(nb)])         # (nb, 3, nel, nq)
    out = np.empty((nel, nb, 6, k))
    chunk = max(1, 2_000_000 // (nb * phi.shape[2] * k * 9))
    for start in range(0, nel, chunk):
        sl = slice(start, min(start + chunk, nel))
        ue = U2[vector_of[sdofs[:, sl]]]                          # (nb, e, 3, k)
        grad = np.einsum("aeik,ajeq->eqijk", ue, G[:, :, sl, :], optimize=True)   # du_i/dx_j
        sig = _voigt_stress(grad, material)                                   # (e, q, 6, k)
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
    return np.asarray(scatter @ values.reshape(e * nb, -1))


def von_mises(s: np.ndarray) -> np.ndarray:
    """Von Mises stress (Pa) of stress components (6, ...) Pa (xx, yy, zz, xy, yz, xz)."""
    sxx, syy, szz, sxy, syz, sxz = s
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2)
                   + 3.0 * (sxy**2 + syz**2 + sxz**2))


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
    return _surface_vectors(basis, groups, group)


def solve_elasticity(points: np.ndarray, tets: np.ndarray, groups: dict[str, np.ndarray],
                     material: Material, supports_: list[Support], loads: list[HoleLoad],
                     order: int = 2, tip_group: str | None = None, solver: str = "auto",
                     maxiter: int = 2000, body_force: np.ndarray | None = None,
                     exclude_distance: float = 0.0, report=None, curved=None) -> Solution:
    """Solve one static problem (see the module doc). ``body_force`` (3,) N/m^3;
    ``exclude_distance`` (m): the peak von Mises is also reported over the stress nodes
    farther than this from the supports (``max_von_mises_away``), away from the
    singularity an idealised clamped surface creates at its edges."""
    warnings = _model_warnings(groups, supports_, loads, tip_group, material, order)
    t = [time.perf_counter()]
    K, basis = assemble(points, tets, material, order, curved)
    fixed = supports(basis, groups, [s.group for s in supports_])
    per_load = {ld.group: unit_traction_vectors(basis, groups, ld.group) @ np.asarray(ld.force, float) for ld in loads}
    f = sum(per_load.values(), load_vector(basis, groups, [], body_force))
    t.append(time.perf_counter())
    u, info = solve(K, f, fixed, solver, basis, maxiter, report=report)
    t.append(time.perf_counter())
    S = recover_stress(basis, u, material)
    nodes, vm = stress_nodes(basis), von_mises(S)
    support_pts = points[np.unique(np.concatenate([groups[s.group].ravel() for s in supports_]))]
    top = peak(vm, nodes)
    away = peak(vm, nodes, away_from(nodes, support_pts, exclude_distance))
    tip = mean_over(basis, groups, tip_group) @ u if tip_group else np.zeros(3)
    t.append(time.perf_counter())
    nv = points.shape[0]
    applied = {g: resultant(basis, v) for g, v in per_load.items()}
    return Solution(order, int(basis.N), int(tets.shape[0]), u[basis.nodal_dofs].T.copy(), vm[:nv].copy(),
                    top[0], top[1], tip, applied, away[0], away[1], float(exclude_distance), S, nodes,
                    dict(zip(("assembly", "solve", "stress"), np.diff(t))), info, warnings,
                    node_displacement(basis, u))


def _model_warnings(groups, supports_, loads, tip_group, material, order) -> list[str]:
    """Refuse what cannot be solved before any work (:class:`ModelError`); return warnings."""
    if not supports_:
        raise ModelError("supports", "the part has no support: its rigid-body motion is undetermined "
                                     "(the stiffness matrix is singular)")
    for name in [s.group for s in supports_] + [ld.group for ld in loads] + ([tip_group] if tip_group else []):
        if name not in groups:
            raise ModelError(name, f"no such group in the mesh (groups: {', '.join(sorted(groups))})")
    if order == 1 and material.poisson_ratio > LOCKING_NU:
        return [f"P1 tetrahedra lock for nearly incompressible material (nu = {material.poisson_ratio}): "
                "displacements and stresses are underestimated; use mesh.order = 2"]
    return []


def check_rigid_modes(points: np.ndarray, tets: np.ndarray, material: Material, order: int = 1,
                      curved=None) -> float:
    """max |K r| / max |K| over the six rigid-body modes r of an unsupported part: ~0."""
    K, basis = assemble(points, tets, material, order, curved)
    B = rigid_body_modes(basis.doflocs, _components(basis))
    return float(np.abs(K @ B).max() / np.abs(K).max())
