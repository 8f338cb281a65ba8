"""The scikit-fem mesh adaptor: a tetrahedral mesh (straight, or quadratic with gmsh's
curved mid-edge nodes) as a scikit-fem mesh with its faces and edges, the element of an
order, and the maps between a vector basis, its scalar basis and the mesh's named
boundary groups (facets, nodes, DOF components). Units SI."""

from __future__ import annotations

import numpy as np

from .errors import ModelError

__all__ = [
    "skfem_mesh",
    "mesh_entities",
    "element_bases",
    "curved_elements",
    "cached_on",
    "facets_of",
    "element_of",
    "estimate_dofs",
    "scalar_basis",
    "stress_nodes",
    "node_cells",
    "node_displacement",
    "vector_dof_map",
    "dof_components",
    "group_nodes",
    "group_facets",
    "edge_index",
]


def skfem_mesh(points: np.ndarray, tets: np.ndarray, curved=None):
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
    keys = np.minimum(quadratic.edges[0], quadratic.edges[1]).astype(np.int64) * n + np.maximum(
        quadratic.edges[0], quadratic.edges[1]
    )
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
        entities, of_element = (
            (getattr(source, "_" + name), getattr(source, "_t2" + name[0])) if known else mesh_entities(mesh.t, indices)
        )
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
    if tuples.shape[0] * np.log2(float(base)) >= 62:  # the key would overflow int64
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
    affine = _with_entities(MeshTet(np.ascontiguousarray(mesh.doflocs[:, : mesh.nvertices]), mesh.t), mesh)
    straight = np.setdiff1d(np.arange(mesh.nelements), curved)
    if not (np.array_equal(affine.t, mesh.t) and np.array_equal(affine.t2e, mesh.t2e)):
        raise RuntimeError("the affine twin numbers its DOFs differently from the curved mesh")
    parts = [
        Basis(affine, scalar, quadrature=quadrature, elements=straight),
        Basis(mesh, scalar, intorder=curved_intorder, elements=curved),
    ]
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


def cached_on(owner, key: str, make):
    """``make()``, computed once per ``owner`` object (a mesh or a basis) and kept on it."""
    store = owner.__dict__.setdefault("_railcheck_cache", {})
    if key not in store:
        store[key] = make()
    return store[key]


def forget(owner, key: str) -> None:
    """Drop what :func:`cached_on` keeps on ``owner`` under ``key`` (if anything): its
    next use computes it again."""
    owner.__dict__.get("_railcheck_cache", {}).pop(key, None)


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
    keys, order = cached_on(mesh, "facet_keys", lambda: _sorted_facet_keys(mesh))
    t = np.sort(triangles, axis=1).astype(np.int64).T
    want = (t[0] * n + t[1]) * n + t[2]
    pos = np.clip(np.searchsorted(keys[order], want), 0, keys.size - 1)
    found = keys[order][pos] == want
    if not np.all(found):
        raise ModelError(name, f"{np.count_nonzero(~found)} of its triangles are not faces of the mesh")
    return np.unique(order[pos])


def element_of(order: int):
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


def scalar_basis(basis):
    """The scalar basis of the vector basis's order: its nodes are the stress nodes (built
    once per vector basis)."""
    from skfem import Basis

    return cached_on(basis, "scalar_basis", lambda: Basis(basis.mesh, basis.elem.elem, intorder=1))


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
    return U[vector_dof_map(basis, scalar_basis(basis))]


def vector_dof_map(basis, sbasis) -> np.ndarray:
    """(scalar DOFs, 3): the vector basis's DOF for each scalar DOF and direction."""
    out = np.full((sbasis.N, 3), -1, dtype=np.int64)
    for name in ("nodal_dofs", "edge_dofs", "facet_dofs", "interior_dofs"):
        sd = getattr(sbasis, name, None)
        vd = getattr(basis, name, None)
        if sd is None or vd is None or sd.size == 0:
            continue
        for k in range(sd.shape[0]):
            for c in range(3):
                out[sd[k], c] = vd[3 * k + c]
    if np.any(out < 0):
        raise RuntimeError("could not map the vector DOFs to the scalar ones")
    return out


def dof_components(basis) -> np.ndarray:
    """Direction (0, 1, 2) of every DOF of a vector basis."""
    comp = np.empty(basis.N, dtype=np.int64)
    for name in ("nodal_dofs", "edge_dofs", "facet_dofs", "interior_dofs"):
        dofs = getattr(basis, name, None)
        if dofs is None or dofs.size == 0:
            continue
        for c in range(3):  # rows c, c+3, ... are direction c
            comp[dofs[c::3].ravel()] = c
    return comp


def group_nodes(basis, groups: dict, names: list[str]) -> np.ndarray:
    """Indices of the stress nodes on the named groups' surfaces (mid-edge nodes included)."""
    sb = scalar_basis(basis)
    return np.unique(np.concatenate([sb.get_dofs(facets=group_facets(basis, groups, g)).all() for g in names]))


def group_facets(basis, groups: dict, name: str) -> np.ndarray:
    if name not in groups:
        raise ModelError(name, f"no such group in the mesh (groups: {', '.join(sorted(groups))})")
    return facets_of(basis.mesh, groups[name], name)


def edge_index(mesh, pairs: np.ndarray) -> np.ndarray:
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
