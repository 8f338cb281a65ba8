"""Linear elasticity on a tetrahedral mesh with scikit-fem (vector P1 or P2).

Units SI: m, N, Pa. Supports and loads are addressed by the names of the mesh's boundary
groups (:class:`geometry.mesher.MeshData`):

* :class:`Support`: every displacement component fixed on the group's surface;
* :class:`HoleLoad`: a total force vector (N) on a group, applied as the uniform traction
  ``F / area`` so that its integral over the (discrete) surface equals ``F`` exactly.

P2 elements take their mid-edge nodes from the straight-sided P1 mesh (curved hole
surfaces are faceted at the mesh size for both orders).

Stress: the element stress is projected (L2) onto the continuous scalar space of the same
order and von Mises is evaluated from the projected components at the nodes; the peak
and its location are reported. Deflection: the mean displacement over a named group
(the loaded free end, "tip") and its magnitude.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .errors import ModelError, NumericalError
from .materials import Material
from .solvers import rigid_body_modes, solve

LOCKING_NU = 0.45


@dataclass(frozen=True)
class Support:
    group: str


@dataclass(frozen=True)
class HoleLoad:
    group: str
    force: tuple[float, float, float]     # N, part frame


@dataclass
class Solution:
    """Result of one solve. Nodal arrays are at the mesh's vertices (for VTK)."""

    order: int
    dofs: int
    elements: int
    displacement: np.ndarray           # (n_vertices, 3) m
    von_mises: np.ndarray              # (n_vertices,) Pa
    max_von_mises: float               # Pa, over all nodes of the order's space
    max_von_mises_location: np.ndarray  # (3,) m
    tip_displacement: np.ndarray       # (3,) m, mean over the tip group
    applied_forces: dict[str, np.ndarray]  # group -> integral of the applied traction (N)
    seconds: dict[str, float] = field(default_factory=dict)
    solver: dict = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    strain_energy: float = 0.0         # J
    max_von_mises_away: float = 0.0    # Pa, farther than exclude_distance from the support
    max_von_mises_away_location: np.ndarray | None = None
    exclude_distance: float = 0.0      # m
    # on every node of the order's space (P2: vertices and mid-edge nodes), for comparison
    # with other solvers: locations (n, 3) m, displacement (n, 3) m, von Mises (n,) Pa,
    # consistent nodal forces (n, 3) N, and the fixed nodes' indices
    node_locations: np.ndarray | None = None
    node_displacement: np.ndarray | None = None
    node_von_mises: np.ndarray | None = None
    node_forces: np.ndarray | None = None
    fixed_nodes: np.ndarray | None = None

    @property
    def tip_deflection(self) -> float:
        return float(np.linalg.norm(self.tip_displacement))


def _skfem_mesh(points: np.ndarray, tets: np.ndarray):
    from skfem import MeshTet
    return MeshTet(np.ascontiguousarray(points.T), np.ascontiguousarray(tets.T))


def facets_of(mesh, triangles: np.ndarray, name: str) -> np.ndarray:
    """Indices of ``mesh.facets`` matching the (k, 3) vertex triangles of a group
    (vectorised search on sorted vertex triples)."""
    n = np.int64(mesh.p.shape[1])
    f = np.sort(mesh.facets, axis=0).astype(np.int64)
    keys = (f[0] * n + f[1]) * n + f[2]
    order = np.argsort(keys)
    t = np.sort(triangles, axis=1).astype(np.int64).T
    want = (t[0] * n + t[1]) * n + t[2]
    pos = np.searchsorted(keys[order], want)
    pos = np.clip(pos, 0, keys.size - 1)
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


def stiffness_matrix(basis, material: Material):
    """The elasticity stiffness matrix (sparse CSR, N/m) of a vector basis.

    All element matrices at once: with the scalar shape-function gradients G[a, i] at the
    quadrature points, K_e[(a,i),(b,j)] = sum_q dx (lambda G_ai G_bj + mu (delta_ij G_a.G_b
    + G_aj G_bi)), in element chunks, then one sparse sum. Equal to scikit-fem's
    ``asm(linear_elasticity(lambda, mu), basis)`` (tests/test_fea.py), several times faster:
    scikit-fem evaluates the form once per local DOF pair (900 times for vector P2).
    """
    import scipy.sparse as sp
    from skfem import Basis

    lam, mu = material.lame
    scalar = basis.elem.elem
    sb = Basis(basis.mesh, scalar, quadrature=basis.quadrature)
    vector_of = _vector_dof_map(basis, sb)               # (scalar dofs, 3)
    sdofs = sb.element_dofs                              # (nb, nel)
    nb, nel = sdofs.shape
    G = np.stack([sb.basis[a][0].grad for a in range(nb)])   # (nb, 3, nel, nq)
    dx = sb.dx                                           # (nel, nq)
    n = 3 * nb
    rows, cols, vals = [], [], []
    chunk = max(1, 4_000_000 // (n * n))
    eye = np.eye(3)
    for start in range(0, nel, chunk):
        sl = slice(start, min(start + chunk, nel))
        g = G[:, :, sl, :]
        P = np.einsum("aieq,bjeq,eq->eabij", g, g, dx[sl], optimize=True)   # (e, a, b, i, j)
        trace = np.einsum("eabkk->eab", P)
        Ke = (lam * P + mu * np.swapaxes(P, 3, 4)
              + mu * trace[:, :, :, None, None] * eye)                  # (e, a, b, i, j)
        Ke = Ke.transpose(0, 1, 3, 2, 4).reshape(-1, n, n)              # (e, (a,i), (b,j))
        gd = vector_of[sdofs[:, sl]]                                     # (nb, e, 3)
        gd = gd.transpose(1, 0, 2).reshape(-1, n)                        # (e, (a,i))
        rows.append(np.repeat(gd, n, axis=1).ravel())
        cols.append(np.tile(gd, (1, n)).ravel())
        vals.append(Ke.ravel())
    N = basis.N
    K = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(N, N))
    return K.tocsr()


def _vector_dof_map(basis, sbasis) -> np.ndarray:
    """(scalar DOFs, 3): the vector basis's DOF for each scalar DOF and direction."""
    out = np.full((sbasis.N, 3), -1, dtype=np.int64)
    for name in ("nodal_dofs", "edge_dofs", "facet_dofs", "interior_dofs"):
        sd = getattr(sbasis, name, None)
        vd = getattr(basis, name, None)
        if sd is None or sd.size == 0:
            continue
        per = sd.shape[0]
        for k in range(per):
            for c in range(3):
                out[sd[k], c] = vd[3 * k + c]
    if np.any(out < 0):
        raise RuntimeError("could not map the vector DOFs to the scalar ones")
    return out


def solve_elasticity(points: np.ndarray, tets: np.ndarray, groups: dict[str, np.ndarray],
                     material: Material, supports: list[Support], loads: list[HoleLoad],
                     order: int = 2, tip_group: str | None = None, solver: str = "auto",
                     maxiter: int = 2000, body_force: np.ndarray | None = None,
                     exclude_distance: float = 0.0) -> Solution:
    """Solve one static linear-elastic problem; see the module doc.

    ``body_force`` (3,) N/m^3, e.g. density x gravity, is applied when given.
    ``exclude_distance`` (m): the peak von Mises is also reported over the nodes farther
    than this from the supports' surfaces (``max_von_mises_away``), away from the stress
    singularity that an idealised clamped surface creates at its edges.
    Raises :class:`ModelError` for a load or support on a group the mesh lacks, or no
    support at all (before any solve), :class:`NumericalError` when the solve fails.
    """
    from skfem import Basis, FacetBasis, Functional, LinearForm, asm, condense
    from skfem.element import ElementVector

    seconds: dict[str, float] = {}
    messages: list[str] = []
    if not supports:
        raise ModelError("supports", "the part has no support: its rigid-body motion is undetermined "
                                     "(the stiffness matrix is singular)")
    for item in list(supports) + list(loads):
        if item.group not in groups:
            raise ModelError(item.group, f"no such group in the mesh (groups: {', '.join(sorted(groups))})")
    if tip_group is not None and tip_group not in groups:
        raise ModelError(tip_group, "no such group in the mesh for the tip deflection")
    if order == 1 and material.poisson_ratio > LOCKING_NU:
        messages.append(f"P1 tetrahedra lock for nearly incompressible material (nu = {material.poisson_ratio}): "
                        "displacements and stresses are underestimated; use mesh.order = 2")

    t = time.perf_counter()
    mesh = _skfem_mesh(points, tets)
    scalar = _element(order)
    element = ElementVector(scalar)
    intorder = 2 * (order - 1) if order > 1 else 1
    basis = Basis(mesh, element, intorder=max(intorder, 1))
    K = stiffness_matrix(basis, material)
    f = np.zeros(basis.N)
    applied: dict[str, np.ndarray] = {}
    for load in loads:
        fb = FacetBasis(mesh, element, facets=facets_of(mesh, groups[load.group], load.group),
                        intorder=max(2 * order, 2))
        area = asm(Functional(lambda w: 1.0 + 0.0 * w.x[0]), fb)
        if area <= 0:
            raise ModelError(load.group, "has zero area")
        traction = np.asarray(load.force, float) / area

        @LinearForm
        def surface_load(v, w, tr=traction):
            return tr[0] * v[0] + tr[1] * v[1] + tr[2] * v[2]

        contribution = asm(surface_load, fb)
        f += contribution
        applied[load.group] = _resultant(basis, contribution)
    if body_force is not None and np.any(body_force):
        bf = np.asarray(body_force, float)

        @LinearForm
        def volume_load(v, w):
            return bf[0] * v[0] + bf[1] * v[1] + bf[2] * v[2]

        f += asm(volume_load, basis)
    fixed = np.unique(np.concatenate([
        basis.get_dofs(facets=facets_of(mesh, groups[s.group], s.group)).all() for s in supports]))
    seconds["assembly"] = time.perf_counter() - t

    t = time.perf_counter()
    free = np.setdiff1d(np.arange(basis.N), fixed)
    u = np.zeros(basis.N)
    if np.any(f[free]):
        Kc, fc, _, I = condense(K, f, D=fixed)
        components = _components(basis)
        B = rigid_body_modes(basis.doflocs[:, I], components[I]) if Kc.shape[0] > 0 else None
        u[I], info = solve(Kc, fc, B, method=solver, maxiter=maxiter)
    else:
        info = {"solver": "none (zero load)", "iterations": 0, "residual": 0.0}
    if not np.all(np.isfinite(u)):
        raise NumericalError("the displacement is not finite")
    seconds["solve"] = time.perf_counter() - t

    t = time.perf_counter()
    vm_all, locs = von_mises_nodal(basis, scalar, u, material)
    k = int(np.argmax(vm_all))
    away, away_loc = float(vm_all[k]), locs[:, k].copy()
    if exclude_distance > 0:
        from scipy.spatial import cKDTree
        support_nodes = np.unique(np.concatenate([groups[s.group].ravel() for s in supports]))
        dist, _ = cKDTree(points[support_nodes]).query(locs.T)
        mask = dist > exclude_distance
        if np.any(mask):
            ka = int(np.argmax(np.where(mask, vm_all, -np.inf)))
            away, away_loc = float(vm_all[ka]), locs[:, ka].copy()
    nv = mesh.p.shape[1]
    disp = u[basis.nodal_dofs].T.copy()
    sbasis = Basis(mesh, scalar, intorder=1)
    vmap = _vector_dof_map(basis, sbasis)
    fixed_nodes = np.unique(np.concatenate([
        sbasis.get_dofs(facets=facets_of(mesh, groups[s.group], s.group)).all() for s in supports]))
    tip = np.zeros(3)
    if tip_group is not None:
        tip = mean_over_group(mesh, element, u, facets_of(mesh, groups[tip_group], tip_group))
    seconds["stress"] = time.perf_counter() - t
    energy = 0.5 * float(u @ (K @ u))
    return Solution(order=order, dofs=int(basis.N), elements=int(tets.shape[0]), displacement=disp,
                    von_mises=vm_all[:nv].copy(), max_von_mises=float(vm_all[k]),
                    max_von_mises_location=locs[:, k].copy(), tip_displacement=tip, applied_forces=applied,
                    seconds=seconds, solver=info, warnings=messages, strain_energy=energy,
                    max_von_mises_away=away, max_von_mises_away_location=away_loc,
                    exclude_distance=float(exclude_distance), node_locations=sbasis.doflocs.T.copy(),
                    node_displacement=u[vmap], node_von_mises=vm_all, node_forces=f[vmap],
                    fixed_nodes=fixed_nodes)


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


def _resultant(basis, load_vector: np.ndarray) -> np.ndarray:
    """The total force (N) of an assembled load vector: the sum of its entries per
    direction (the shape functions sum to one)."""
    comp = _components(basis)
    return np.array([load_vector[comp == c].sum() for c in range(3)])


def mean_over_group(mesh, element, u: np.ndarray, facets: np.ndarray) -> np.ndarray:
    """Area-weighted mean of the displacement over the given facets (m)."""
    from skfem import FacetBasis, Functional, asm

    fb = FacetBasis(mesh, element, facets=facets, intorder=4)
    uh = fb.interpolate(u)
    area = asm(Functional(lambda w: 1.0 + 0.0 * w.x[0]), fb)
    out = np.zeros(3)
    for c in range(3):
        out[c] = asm(Functional(lambda w, c=c: w["uh"][c]), fb, uh=uh) / area
    return out


def element_stress(basis, u: np.ndarray, material: Material):
    """Stress tensor at the quadrature points, shape (3, 3, elements, points), Pa."""
    lam, mu = material.lame
    grad = basis.interpolate(u).grad
    eps = 0.5 * (grad + np.swapaxes(grad, 0, 1))
    tr = eps[0, 0] + eps[1, 1] + eps[2, 2]
    sigma = 2 * mu * eps
    for i in range(3):
        sigma[i, i] += lam * tr
    return sigma


def von_mises(s):
    """Von Mises stress of a stress tensor given by its components (Pa)."""
    sxx, syy, szz, sxy, syz, sxz = s
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2)
                   + 3.0 * (sxy**2 + syz**2 + sxz**2))


def von_mises_nodal(basis, scalar_element, u: np.ndarray, material: Material):
    """L2 projection of the six stress components onto the continuous scalar space of
    the element's order; von Mises at its nodes. Returns (values (ndofs,), locations
    (3, ndofs))."""
    from skfem import Basis, BilinearForm, LinearForm, asm
    import scipy.sparse.linalg as spla

    # the mass matrix of order p needs a rule exact to order 2p: with the stiffness's rule
    # (order 2(p-1)) a P2 mass matrix is rank-deficient element by element
    order = 2 if scalar_element.maxdeg == 2 else 1
    qbasis = Basis(basis.mesh, basis.elem, intorder=2 * order)
    sigma = element_stress(qbasis, u, material)
    sb = Basis(basis.mesh, scalar_element, quadrature=qbasis.quadrature)

    @BilinearForm
    def mass(a, v, w):
        return a * v

    M = asm(mass, sb)
    diag = M.diagonal()
    pre = spla.LinearOperator(M.shape, matvec=lambda x: x / diag)
    comps = []
    for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2)):
        @LinearForm
        def rhs(v, w, s=sigma[i, j]):
            return s * v

        b = asm(rhs, sb)
        if not np.any(b):
            comps.append(np.zeros_like(b))
            continue
        x, status = spla.cg(M, b, rtol=1e-11, atol=0.0, maxiter=2000, M=pre)
        if status != 0:
            raise NumericalError("stress projection did not converge")
        comps.append(x)
    return von_mises(comps), sb.doflocs


def check_rigid_modes(points: np.ndarray, tets: np.ndarray, material: Material, order: int = 1) -> float:
    """max |K r| / max |K| over the six rigid-body modes r of an unsupported part: ~0."""
    from skfem import Basis
    from skfem.element import ElementVector

    mesh = _skfem_mesh(points, tets)
    basis = Basis(mesh, ElementVector(_element(order)), intorder=max(2 * (order - 1), 1))
    K = stiffness_matrix(basis, material)
    B = rigid_body_modes(basis.doflocs, _components(basis))
    return float(np.abs(K @ B).max() / np.abs(K).max())

