"""Loads: supports and hole loads by group name, tractions and body forces as load vectors
(one column per load), their resultants, and each surface's area and node weights.

* :class:`Support`: every displacement component fixed on the group's surface;
* :class:`HoleLoad`: a total force vector (N) on a group, applied as the uniform traction
  ``F / area`` so that its integral over the (discrete) surface equals ``F`` exactly;
* :func:`traction_vector`: any traction given as a function of position on a named
  surface (Pa): a pressure, a torque as a traction linear in the section coordinates;
* :func:`body_force_vector`: any body force field (N/m^3) as a function of position.

Surface integrals are exact on the element faces (curved faces by their quadratic map).
Units SI."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .assembly import integration_basis
from .errors import ModelError
from .mesh import dof_components, edge_index, group_facets, scalar_basis, vector_dof_map

__all__ = [
    "Support",
    "HoleLoad",
    "surface_node_weights",
    "surface_node_integrals",
    "group_area",
    "unit_traction_vectors",
    "body_force_vectors",
    "traction_vector",
    "body_force_vector",
    "load_vector",
    "resultant",
    "surface_vectors",
    "SurfaceDofs",
    "surface_dofs",
]


def surface_node_weights(basis, groups: dict, name: str) -> tuple[np.ndarray, np.ndarray]:
    """(nodes, weights m^2): the integral of each scalar shape function over ``name``'s
    surface, on the element's own (straight or curved) faces; the weights sum to the
    surface's area. A face's trace of the tetrahedral basis is the triangle's: 3 nodes (P1),
    or 6 (P2: vertices, then the mid nodes of edges 01, 12, 02), and a curved face's area
    element comes from its quadratic map, integrated by a degree-6 triangle rule."""
    nodes, weights = surface_node_integrals(basis, groups, name)
    return nodes, weights[:, 0]


def surface_node_integrals(basis, groups: dict, name: str, functions=()) -> tuple[np.ndarray, np.ndarray]:
    """(nodes, integrals (n, 1 + m)): over ``name``'s surface, the integral of each scalar
    shape function (column 0, m^2, as :func:`surface_node_weights`) and of it times each of
    the ``functions`` of position (each takes points (..., 3) m and returns values (...)),
    by the same degree-6 rule on the element's own faces."""
    group_facets(basis, groups, name)  # refuses unknown groups / foreign faces
    sb = scalar_basis(basis)
    mesh = basis.mesh
    tri = np.asarray(groups[name], dtype=np.int64)
    vertex_dof = sb.nodal_dofs[0][tri]  # (f, 3)
    if sb.N == mesh.nvertices:  # P1: linear faces
        nodes, lam_shape = vertex_dof, _tri_p1
        x = mesh.doflocs.T[tri]
    else:
        pairs = tri[:, [[0, 1], [1, 2], [0, 2]]]  # (f, 3, 2)
        edge = edge_index(mesh, pairs.reshape(-1, 2)).reshape(-1, 3)
        nodes = np.concatenate([vertex_dof, sb.edge_dofs[0][edge]], axis=1)  # (f, 6)
        lam_shape = _tri_p2
        x = sb.doflocs.T[nodes]  # (f, 6, 3): the face's own nodes
    w = _face_integrals(x, lam_shape, functions)  # (f, nodes per face, 1 + m)
    used = np.flatnonzero(np.bincount(nodes.ravel(), minlength=sb.N))
    columns = [np.bincount(nodes.ravel(), weights=w[..., j].ravel(), minlength=sb.N)[used] for j in range(w.shape[-1])]
    return used, np.stack(columns, axis=1)


def _tri_p1(lam: np.ndarray):
    """Linear triangle: shape values (q, 3) and barycentric derivatives (q, 3, 3)."""
    return lam, np.broadcast_to(np.eye(3), (lam.shape[0], 3, 3))


def _tri_p2(lam: np.ndarray):
    """Quadratic triangle (vertices, then edges 01, 12, 02): values (q, 6) and the
    derivatives with respect to each barycentric coordinate (q, 6, 3)."""
    L0, L1, L2 = lam.T
    N = np.stack([L0 * (2 * L0 - 1), L1 * (2 * L1 - 1), L2 * (2 * L2 - 1), 4 * L0 * L1, 4 * L1 * L2, 4 * L0 * L2], 1)
    z = np.zeros_like(L0)
    dN = np.stack(
        [
            np.stack([4 * L0 - 1, z, z], 1),
            np.stack([z, 4 * L1 - 1, z], 1),
            np.stack([z, z, 4 * L2 - 1], 1),
            np.stack([4 * L1, 4 * L0, z], 1),
            np.stack([z, 4 * L2, 4 * L1], 1),
            np.stack([4 * L2, z, 4 * L0], 1),
        ],
        1,
    )
    return N, dN


def _face_integrals(x: np.ndarray, shape, functions=()) -> np.ndarray:
    """(f, n, 1 + m): integral of each face shape function over faces with nodes ``x``
    (f, n, 3), alone and times each of the ``functions`` of position."""
    from skfem.quadrature import get_quadrature
    from skfem.refdom import RefTri

    X, W = get_quadrature(RefTri, 6)  # reference triangle (0,0), (1,0), (0,1)
    lam = np.column_stack([1 - X[0] - X[1], X[0], X[1]])
    N, dN = shape(lam)  # (q, n), (q, n, 3)
    ds = dN[:, :, 1] - dN[:, :, 0]  # d/ds with L1 = s, L2 = t
    dt = dN[:, :, 2] - dN[:, :, 0]
    a = np.einsum("qn,fnk->fqk", ds, x)
    b = np.einsum("qn,fnk->fqk", dt, x)
    jac = np.linalg.norm(np.cross(a, b), axis=-1)  # (f, q) area element
    points = np.einsum("qn,fnk->fqk", N, x)  # (f, q, 3) the quadrature points
    values = [np.ones(jac.shape)] + [np.asarray(g(points), float) for g in functions]
    return np.stack([np.einsum("qn,fq,q->fn", N, jac * v, W) for v in values], axis=-1)


def surface_vectors(basis, groups: dict, group: str) -> np.ndarray:
    """(3, N): row c holds the surface weights of group's nodes on their c DOFs, divided by
    the area (a unit total force along c as a uniform traction; also the mean over it)."""
    nodes, w = surface_node_weights(basis, groups, group)
    area = w.sum()
    if not area > 0:
        raise ModelError(group, "has zero area")
    out = np.zeros((3, basis.N))
    vector_of = vector_dof_map(basis, scalar_basis(basis))
    for c in range(3):
        out[c, vector_of[nodes, c]] = w / area
    return out


def group_area(basis, groups: dict, group: str) -> float:
    """The area (m^2) of a group's surface on the element geometry (curved when P2 is)."""
    return float(surface_node_weights(basis, groups, group)[1].sum())


def unit_traction_vectors(basis, groups: dict, group: str) -> np.ndarray:
    """(N, 3): the load vectors of a unit total force (1 N) along x, y and z spread as a
    uniform traction over ``group``'s surface. Any force F on the group is ``T @ F``."""
    return surface_vectors(basis, groups, group).T.copy()


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
    comp = dof_components(basis)
    F2 = F.reshape(F.shape[0], -1)
    out = np.stack([F2[comp == c].sum(axis=0) for c in range(3)])
    return out.reshape((3,) + F.shape[1:])


@dataclass(frozen=True)
class Support:
    group: str


@dataclass(frozen=True)
class HoleLoad:
    group: str
    force: tuple[float, float, float]  # N, part frame


def traction_vector(basis, groups: dict, group: str, traction) -> np.ndarray:
    """The load vector of a traction given as a function of position on ``group``'s
    surface: ``traction(x)`` takes the points ``x`` (3, ...) m and returns the traction
    (3, ...) Pa at them (a pressure ``-p n`` needs the normal: use :func:`unit_traction_vectors`
    for a uniform force instead). A sequence of such functions gives one column each:
    (N,) for one function, (N, k) for k. Integrated on the element's own faces (curved
    faces by their quadratic map) with a rule exact for a traction linear in x."""
    from skfem import FacetBasis, LinearForm, asm

    functions = [traction] if callable(traction) else list(traction)
    facets = group_facets(basis, groups, group)
    fb = FacetBasis(basis.mesh, basis.elem, facets=facets, intorder=2 * basis.elem.elem.maxdeg + 1)
    columns = [asm(LinearForm(lambda v, w, t=t: _dot(t(w.x), v)), fb) for t in functions]
    return columns[0] if callable(traction) else np.stack(columns, axis=1)


def body_force_vector(basis, force) -> np.ndarray:
    """The load vector of a body force field: ``force(x)`` takes the points ``x`` (3, ...)
    m and returns the force density (3, ...) N/m^3 at them. A sequence of functions gives
    one column each, as :func:`traction_vector`."""
    from skfem import LinearForm, asm

    functions = [force] if callable(force) else list(force)
    ib = integration_basis(basis)
    columns = [asm(LinearForm(lambda v, w, b=b: _dot(b(w.x), v)), ib) for b in functions]
    return columns[0] if callable(force) else np.stack(columns, axis=1)


def _dot(field, v):
    """Pointwise dot product of a vector field (3, ...) with a vector test function."""
    return sum(np.asarray(field[c]) * v[c] for c in range(3))


@dataclass(frozen=True)
class SurfaceDofs:
    """A named surface's nodes of the (vector) basis: ``dofs`` (n, 3) the x, y, z DOF of
    each node, ``weights`` (n,) m^2 the integral of its shape function over the surface
    (they sum to the area), ``points`` (n, 3) m where the nodes are. Any surface mean of
    a field is ``weights @ field / weights.sum()``."""

    dofs: np.ndarray
    weights: np.ndarray
    points: np.ndarray


def surface_dofs(basis, groups: dict, group: str) -> SurfaceDofs:
    """The :class:`SurfaceDofs` of ``group``'s surface (on the element's own faces)."""
    sb = scalar_basis(basis)
    nodes, weights = surface_node_weights(basis, groups, group)
    return SurfaceDofs(dofs=vector_dof_map(basis, sb)[nodes], weights=weights, points=sb.doflocs.T[nodes])
