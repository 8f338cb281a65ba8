"""FE core: patch test, rigid modes, cantilever regressions, loads, solvers, VTK."""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg  # noqa: F401

from railcheck.fea import products
from railcheck.fea.assembly import pair_pattern, pair_pattern_by_unique
from railcheck.fea.cantilever import run_cantilever
from railcheck.fea.elasticity import (
    HoleLoad,
    Support,
    assemble,
    check_rigid_modes,
    dof_components,
    free_submatrix,
    mass_matrix,
    solve,
    solve_elasticity,
    stiffness_matrix,
    supports,
    unit_traction_vectors,
)
from railcheck.fea.errors import ModelError, NumericalError
from railcheck.fea.materials import MATERIALS
from railcheck.fea.mesh import element_of, mesh_entities, skfem_mesh
from railcheck.fea.solvers import factorise, rigid_body_modes, solve_jacobi_cg
from railcheck.fea.vtk import write_vtu
from railcheck.geometry.catalogue import RAIL, rail_section
from railcheck.geometry.mesher import local_numbering, mesh_part
from railcheck.geometry.models import bar, rail

STEEL = MATERIALS["steel"]


@pytest.fixture(scope="module")
def block():
    return mesh_part(bar(0.06, 0.03, 0.02), 0.01, hole_size=0.01)


@pytest.mark.parametrize("order", [1, 2])
def test_patch_test_linear_field_is_exact(block, order):
    from skfem import Basis, condense, solve
    from skfem.element import ElementVector

    mesh = skfem_mesh(block.points, block.tets)
    basis = Basis(mesh, ElementVector(element_of(order)), intorder=2)
    K = stiffness_matrix(basis, STEEL)
    G = np.array([[1e-3, 2e-4, -3e-4], [5e-4, -1e-3, 1e-4], [-2e-4, 3e-4, 7e-4]])
    c = np.array([1e-5, -2e-5, 3e-5])
    comp = dof_components(basis)
    exact = (G @ basis.doflocs)[comp, np.arange(basis.N)] + c[comp]
    boundary = basis.get_dofs().all()
    u = solve(*condense(K, np.zeros(basis.N), x=exact, D=boundary))
    interior = np.setdiff1d(np.arange(basis.N), boundary)
    assert interior.size > 0
    assert np.max(np.abs(u - exact)) < 1e-10 * np.max(np.abs(exact))


@pytest.mark.parametrize("order", [1, 2])
def test_six_rigid_body_modes(block, order):
    from skfem import Basis
    from skfem.element import ElementVector

    assert check_rigid_modes(block.points, block.tets, STEEL, order) < 1e-12
    mesh = skfem_mesh(block.points, block.tets)
    basis = Basis(mesh, ElementVector(element_of(order)), intorder=2)
    K = stiffness_matrix(basis, STEEL).toarray()
    ev = np.linalg.eigvalsh(K)
    assert np.all(np.abs(ev[:6]) < 1e-9 * ev[-1])  # six zero-energy modes
    assert ev[6] > 1e-6 * ev[-1]  # and no seventh


@pytest.mark.parametrize("axis", ["z", "y", "x"])
def test_p2_cantilever_within_one_percent_of_timoshenko(axis):
    r = run_cantilever(order=2, size=8e-3, axis=axis)
    assert abs(r.relative_error) < 0.01, r.relative_error


@pytest.mark.slow  # 1.6-2.5 s, three meshes: a convergence study (the fast tier keeps the Timoshenko cantilever)
def test_p2_error_shrinks_under_refinement_and_p1_locking_is_measured():
    errors = [abs(run_cantilever(order=2, size=s).relative_error) for s in (20e-3, 10e-3, 7e-3)]
    assert errors[0] > errors[1] > errors[2]
    p1 = run_cantilever(order=1, size=10e-3).relative_error
    # P1 tetrahedra lock in bending: far stiffer than beam theory at this mesh
    assert p1 < -0.2
    assert abs(p1) > 20 * errors[1]


@pytest.mark.slow  # 6.3 s in CI (its own 700 mm mesh at 8 mm): over the marker's few seconds
def test_plain_rail_profile_matches_beam_theory_with_its_own_section():
    L = 0.7
    mesh = mesh_part(rail(L, holes=False), 8e-3, hole_size=8e-3)
    P = 100.0
    sol = solve_elasticity(
        mesh,
        STEEL,
        [Support("end_pivot")],
        [HoleLoad("end_free", (0.0, P, 0.0))],
        order=2,
        tip_group="end_free",
        curved=mesh.curved,  # the grooves' arcs: straight-sided P2 would be 4-16% stiff
    )
    # transverse (in-plane) load bends about z: the grooved profile's closed-form I and area
    # (the shear term, with a rectangle's coefficient, is 0.3% of the deflection)
    section = rail_section(RAIL)
    E, G = STEEL.youngs_modulus, STEEL.youngs_modulus / (2 * (1 + STEEL.poisson_ratio))
    kappa = 10 * (1 + STEEL.poisson_ratio) / (12 + 11 * STEEL.poisson_ratio)
    analytic = P * L**3 / (3 * E * section.inertia_in_plane) + P * L / (kappa * G * section.area)
    assert sol.tip_displacement[1] == pytest.approx(analytic, rel=0.02)


@pytest.mark.slow
def test_holed_rail_is_more_flexible_and_the_difference_is_measured():
    L, P = 0.7, 100.0
    out = {}
    for holes in (False, True):
        mesh = mesh_part(rail(L, holes=holes), 8e-3, hole_size=3e-3)
        sol = solve_elasticity(
            mesh,
            STEEL,
            [Support("end_pivot")],
            [HoleLoad("end_free", (0.0, 0.0, -P))],
            order=2,
            tip_group="end_free",
        )
        out[holes] = -sol.tip_displacement[2]
    extra = out[True] / out[False] - 1.0
    # counterbored holes every 60 mm soften vertical bending by a few percent, not more
    assert 0.0 < extra < 0.25, extra


@pytest.fixture(scope="module")
def rail_mesh():
    """A 700 mm grooved rail on the check's default mesh (the crank rail's: in CI the main
    job has meshed it, so it is read from the mesh cache)."""
    return mesh_part(rail(0.7), 20e-3, hole_size=6e-3)


@pytest.mark.slow
def test_tractions_sum_to_the_requested_force_and_linearity(rail_mesh):
    F = (123.0, -45.6, 7.8)
    args = (rail_mesh, STEEL, [Support("shaft_hole")])
    s1 = solve_elasticity(*args, [HoleLoad("hole_11", F)], order=2, tip_group="end_free")
    np.testing.assert_allclose(s1.applied_forces["hole_11"], F, rtol=1e-10, atol=1e-10 * np.linalg.norm(F))
    s2 = solve_elasticity(*args, [HoleLoad("hole_11", tuple(2 * np.array(F)))], order=2, tip_group="end_free")
    np.testing.assert_allclose(s2.displacement, 2 * s1.displacement, rtol=1e-7, atol=1e-7 * np.abs(s1.displacement).max())
    assert s2.max_von_mises == pytest.approx(2 * s1.max_von_mises, rel=1e-7)


@pytest.mark.slow
def test_amg_and_direct_agree(rail_mesh):
    args = (
        rail_mesh,
        STEEL,
        [Support("shaft_hole")],
        [HoleLoad("hole_10", (200.0, 50.0, 0.0)), HoleLoad("hole_11", (200.0, 50.0, 0.0))],
    )
    d = solve_elasticity(*args, order=2, tip_group="end_free", solver="direct")
    a = solve_elasticity(*args, order=2, tip_group="end_free", solver="amg")
    assert a.solver["solver"] == "amg" and a.solver["iterations"] > 1
    scale = np.abs(d.displacement).max()
    assert np.abs(a.displacement - d.displacement).max() < 1e-6 * scale
    assert a.max_von_mises == pytest.approx(d.max_von_mises, rel=1e-6)


@pytest.mark.slow
def test_unconverged_iterative_solve_raises(rail_mesh):
    with pytest.raises(NumericalError, match="did not converge"):
        solve_elasticity(
            rail_mesh,
            STEEL,
            [Support("shaft_hole")],
            [HoleLoad("hole_11", (100.0, 100.0, 0.0))],
            order=2,
            solver="amg",
            maxiter=3,
        )


def test_zero_load_is_exactly_zero(rail_mesh):
    s = solve_elasticity(
        rail_mesh,
        STEEL,
        [Support("shaft_hole")],
        [HoleLoad("hole_11", (0.0, 0.0, 0.0))],
        order=2,
        tip_group="end_free",
    )
    assert np.all(s.displacement == 0.0) and s.max_von_mises == 0.0


def test_missing_group_and_missing_support_are_errors(rail_mesh):
    args = (rail_mesh, STEEL)
    with pytest.raises(ModelError, match="hole_99"):
        solve_elasticity(*args, [Support("shaft_hole")], [HoleLoad("hole_99", (1.0, 0, 0))])
    with pytest.raises(ModelError, match="no support"):
        solve_elasticity(*args, [], [HoleLoad("hole_11", (1.0, 0, 0))])


@pytest.mark.slow  # 3.0-3.4 s: the output format's round trip; the fast tier stays under 90 s
def test_vtu_round_trip(tmp_path, rail_mesh):
    import meshio

    s = solve_elasticity(
        rail_mesh,
        STEEL,
        [Support("shaft_hole")],
        [HoleLoad("hole_11", (10.0, 20.0, 0.0))],
        order=2,
    )
    path = write_vtu(tmp_path / "rail.vtu", rail_mesh.points, rail_mesh.tets, s.displacement, s.von_mises)
    m = meshio.read(path)
    assert m.point_data["displacement"].shape == (rail_mesh.points.shape[0], 3)
    np.testing.assert_allclose(m.point_data["von_mises"], s.von_mises)
    assert [p.name for p in tmp_path.iterdir()] == ["rail.vtu"]  # no temporary left


def test_rigid_body_modes_are_the_kernel_of_a_free_stiffness(block):
    from skfem import Basis
    from skfem.element import ElementVector

    basis = Basis(skfem_mesh(block.points, block.tets), ElementVector(element_of(2)), intorder=2)
    x, comp = basis.doflocs, dof_components(basis)
    B = rigid_body_modes(x, comp)
    # each column is a rigid motion written out here: u(p) = t + w x (p - centroid)
    c = x.mean(axis=1, keepdims=True)
    for k in range(6):
        t, w = np.eye(3)[k] if k < 3 else np.zeros(3), np.eye(3)[k - 3] if k >= 3 else np.zeros(3)
        u = t[:, None] + np.cross(w[:, None], x - c, axis=0)
        np.testing.assert_allclose(B[:, k], u[comp, np.arange(comp.size)], atol=1e-15)
    # and they are the free stiffness's kernel: no strain energy, no force
    K = stiffness_matrix(basis, STEEL)
    assert np.abs(K @ B).max() < 1e-9 * abs(K).max() * np.abs(B).max()
    assert np.linalg.matrix_rank(B) == 6


@pytest.mark.parametrize("order", [1, 2])
def test_fast_assembly_equals_scikit_fem(block, order):
    from skfem import Basis, asm
    from skfem.element import ElementVector
    from skfem.models.elasticity import linear_elasticity

    basis = Basis(skfem_mesh(block.points, block.tets), ElementVector(element_of(order)), intorder=2)
    mine = stiffness_matrix(basis, STEEL)
    ref = asm(linear_elasticity(*STEEL.lame), basis)
    assert abs(mine - ref).max() <= 1e-12 * abs(ref).max()


def test_pair_pattern_equals_a_global_sort_of_the_pair_keys():
    """The compiled counting-sort pattern against np.unique of the keys, with a DOF in no
    element (an empty row) first, in the middle and last, and repeated DOFs in an element."""
    rng = np.random.default_rng(3)
    n = 500
    dofs = rng.choice(np.setdiff1d(np.arange(n), [0, 250, n - 1]), size=(300, 10))
    dofs[:5, 1] = dofs[:5, 0]
    mine = pair_pattern(dofs, n)
    ref = pair_pattern_by_unique(dofs, n)
    for a, b in zip(mine[:2], ref[:2]):
        np.testing.assert_array_equal(a, b)
    assert mine[2].shape == ref[2].shape and (mine[2] != ref[2]).nnz == 0
    values = rng.normal(size=(dofs.size * 10, 2))
    expected = np.zeros((mine[1].size, 2))  # scatter-add by pair key, the plain way
    key = (dofs[:, :, None] * n + dofs[:, None, :]).ravel()
    entry = np.searchsorted(np.repeat(np.arange(n), np.diff(mine[0])) * n + mine[1], key)
    np.add.at(expected, entry, values)
    np.testing.assert_allclose(mine[2] @ values, expected, rtol=1e-14, atol=1e-14)
    assert mine[0][1] == mine[0][0] and mine[0][-1] == mine[0][-2]  # the empty rows


@pytest.mark.slow
def test_amg_is_deterministic(rail_mesh):
    args = (
        rail_mesh,
        STEEL,
        [Support("shaft_hole")],
        [HoleLoad("hole_11", (150.0, 80.0, 0.0))],
    )
    a = solve_elasticity(*args, order=2, solver="amg")
    b = solve_elasticity(*args, order=2, solver="amg")
    assert np.array_equal(a.displacement, b.displacement) and a.max_von_mises == b.max_von_mises


def _rail_system(rail_mesh):

    K, basis = assemble(rail_mesh.points, rail_mesh.tets, STEEL, 2)
    fixed = supports(basis, rail_mesh.groups, ["shaft_hole"])
    F = unit_traction_vectors(basis, rail_mesh.groups, "hole_11")[:, :2] * 300.0
    return K, basis, fixed, F


@pytest.mark.slow
def test_every_solver_path_agrees(rail_mesh):
    """PARDISO, SuperLU, p-multigrid CG and AMG-CG on the same P2 rail, two load columns:
    the same displacements to 1e-8 of the largest."""

    K, basis, fixed, F = _rail_system(rail_mesh)
    ref, info = solve(K, F, fixed, "pardiso", basis)
    assert info["solver"] == "pardiso"
    scale = np.abs(ref).max()
    for method in ("scipy", "pmg", "amg"):
        U, info = solve(K, F, fixed, method, basis)
        assert info["solver"] == method
        assert np.abs(U - ref).max() < 1e-8 * scale, (method, np.abs(U - ref).max() / scale)


@pytest.mark.slow
def test_a_memory_cap_sends_p2_to_p_multigrid(rail_mesh):
    """The factor's estimate exceeds a 1 MB cap: the auto choice solves iteratively with the
    P2 -> P1 p-multigrid (its P1 level, over the cap too, by AMG), to the direct answer."""

    K, basis, fixed, F = _rail_system(rail_mesh)
    U, info = solve(K, F[:, 0], fixed, "auto", basis, memory_limit=1e6)
    assert info["solver"] == "pmg" and info["coarse"] == "amg"
    ref, _ = solve(K, F[:, 0], fixed, "direct", basis)
    assert np.abs(U - ref).max() < 1e-8 * np.abs(ref).max()


def test_free_submatrix_equals_fancy_indexing():
    import scipy.sparse as sp

    rng = np.random.default_rng(4)
    K = sp.random(300, 300, density=0.05, format="csr", random_state=5)
    K.sort_indices()
    for free in (np.arange(300), np.sort(rng.choice(300, 170, replace=False)), np.array([], int), np.array([299])):
        mine = free_submatrix(K, free)
        ref = K[free][:, free]
        assert mine.shape == ref.shape and np.array_equal(mine.toarray(), ref.toarray())
        resorted = mine.copy()
        resorted.has_sorted_indices = False
        resorted.sort_indices()
        assert mine.has_sorted_indices and np.array_equal(resorted.indices, mine.indices)


def test_mesh_entities_equal_scikit_fem(block):
    from skfem import MeshTet

    t = np.ascontiguousarray(block.tets.T)
    for indices in (MeshTet.elem.refdom.facets, MeshTet.elem.refdom.edges):
        mine = mesh_entities(t, indices)
        ref = MeshTet.build_entities(t, indices)
        for a, b in zip(mine, ref):
            np.testing.assert_array_equal(a, b)


def test_mass_matrix_equals_scikit_fem_and_jacobi_cg_equals_a_factorisation(block):
    """The stress projection's mass matrix against scikit-fem's assembly, and its
    Jacobi-CG solve (several columns, one of them zero) against a sparse factorisation."""
    from skfem import Basis, BilinearForm, asm
    from skfem.element import ElementVector
    from skfem.quadrature import get_quadrature

    basis = Basis(skfem_mesh(block.points, block.tets), ElementVector(element_of(2)), intorder=1)
    scalar = basis.elem.elem
    M = mass_matrix(basis)
    ref = asm(BilinearForm(lambda u, v, w: u * v), Basis(basis.mesh, scalar, quadrature=get_quadrature(scalar.refdom, 4)))
    assert abs(M - ref).max() <= 1e-13 * abs(ref).max()
    B = np.random.default_rng(6).normal(size=(M.shape[0], 3))
    B[:, 1] = 0.0
    X = solve_jacobi_cg(M, B)
    np.testing.assert_allclose(
        X, factorise(M, "scipy").solve(B, rtol=1e-9, extended=False), rtol=0, atol=1e-9 * np.abs(X).max()
    )
    assert not np.any(X[:, 1])
    with pytest.raises(NumericalError):
        solve_jacobi_cg(M, B, maxiter=2)
    with pytest.raises(NumericalError):
        solve_jacobi_cg(-M, B)


def test_the_stress_projection_by_its_factor_equals_jacobi_cg_and_falls_back_to_it(block, monkeypatch):
    """The projection solves the mass matrix by a direct factor when it has many columns;
    with no memory for the factor, or few columns, by Jacobi-CG. Both are the same projection: each satisfies
    M s = b to 1e-12, and they agree to 1e-10 of the largest stress. Without the CG
    fallback the memory-starved case raises."""
    from skfem import Basis
    from skfem.element import ElementVector

    import railcheck.fea.stress as stress
    from railcheck.fea.stress import recover_stress

    basis = Basis(skfem_mesh(block.points, block.tets), ElementVector(element_of(2)), intorder=1)
    U = np.random.default_rng(8).normal(scale=1e-6, size=(basis.N, stress.MASS_FACTOR_COLUMNS))
    cg_calls = []
    real_cg = stress.solve_jacobi_cg
    monkeypatch.setattr(stress, "solve_jacobi_cg", lambda *a, **k: cg_calls.append(1) or real_cg(*a, **k))
    by_factor = recover_stress(basis, U, STEEL)
    assert not cg_calls
    monkeypatch.setattr(stress, "available_memory", lambda: 0.0)
    by_cg = recover_stress(basis, U, STEEL)
    assert cg_calls
    monkeypatch.undo()
    cg_calls.clear()
    monkeypatch.setattr(stress, "solve_jacobi_cg", lambda *a, **k: cg_calls.append(1) or real_cg(*a, **k))
    few = recover_stress(basis, U[:, :-1], STEEL)  # under MASS_FACTOR_COLUMNS: by CG
    np.testing.assert_allclose(few, by_cg[..., :-1], rtol=0, atol=1e-10 * np.abs(by_cg).max())
    assert cg_calls
    np.testing.assert_allclose(by_factor, by_cg, rtol=0, atol=1e-10 * np.abs(by_cg).max())
    M = mass_matrix(basis)
    rhs = stress.affine_stress_moments(basis, U, STEEL)
    for S in (by_factor, by_cg):
        nodal = S.reshape(6, M.shape[0], -1).transpose(1, 0, 2).reshape(M.shape[0], -1)
        residual = np.linalg.norm(rhs - M @ nodal, axis=0) / np.linalg.norm(rhs, axis=0)
        assert residual.max() <= stress.MASS_RTOL


def test_local_numbering_keeps_the_mesh_and_shrinks_the_bandwidth():
    """Reverse Cuthill-McKee on a shuffled structured mesh: the same tetrahedra (as sets of
    points), sorted by their lowest vertex, with a vertex bandwidth near a layer's size
    (one (k+1)^2 layer of a k^3 cube) where the shuffled numbering's is near n."""

    k = 12
    grid = np.stack(np.meshgrid(*[np.arange(k + 1)] * 3, indexing="ij"), -1).reshape(-1, 3).astype(float)
    corner = np.arange((k + 1) ** 3).reshape(k + 1, k + 1, k + 1)[:-1, :-1, :-1].ravel()
    step = np.array([(k + 1) ** 2, k + 1, 1])
    cube = [0, step[0], step[1], step[2], step[0] + step[1], step[0] + step[2], step[1] + step[2], step.sum()]
    kuhn = [[0, 1, 4, 7], [0, 1, 5, 7], [0, 2, 4, 7], [0, 2, 6, 7], [0, 3, 5, 7], [0, 3, 6, 7]]
    tets = np.concatenate([corner[:, None] + np.array(cube)[t] for t in kuhn])
    shuffle = np.random.default_rng(0).permutation(grid.shape[0])
    points, tets = grid[shuffle], np.argsort(shuffle)[tets]

    def bandwidth(t):
        return np.max(t.max(axis=1) - t.min(axis=1))

    new, renumbered = local_numbering(tets, points.shape[0])
    assert np.array_equal(np.sort(new), np.arange(points.shape[0]))
    moved = np.empty_like(points)
    moved[new] = points
    as_points = {tuple(sorted(map(tuple, points[t]))) for t in tets}
    assert {tuple(sorted(map(tuple, moved[t]))) for t in renumbered} == as_points
    assert np.all(np.diff(renumbered.min(axis=1)) >= 0)
    assert bandwidth(tets) > 0.8 * points.shape[0]
    assert bandwidth(renumbered) < 3 * (k + 1) ** 2


def test_sparse_products_equal_scipy_and_fall_back_without_mkl(monkeypatch):
    """MKL's sparse BLAS (where it loads) and the threaded row blocks against scipy's own
    product, for a vector and a block of columns of a non-square matrix."""
    import scipy.sparse as sp

    A = sp.random(3000, 2000, density=0.002, random_state=4, format="csr") + sp.eye(3000, 2000, format="csr")
    rng = np.random.default_rng(5)
    x, X = rng.normal(size=2000), rng.normal(size=(2000, 7))
    fast = products.sparse_product(A)
    if products.mkl_sparse_library() is not None:
        assert isinstance(fast, products.MklProduct)
    for v in (x, X):
        exact = A @ v
        assert (fast @ v).shape == exact.shape
        np.testing.assert_allclose(fast @ v, exact, rtol=0, atol=1e-13 * np.abs(exact).max())
    if products.mkl_sparse_library() is not None:
        with pytest.raises(ValueError):
            products.MklProduct(A) @ np.ones(3000)  # rows of A, not columns
    empty = products.sparse_product(sp.csr_matrix((0, 5)))
    assert (empty @ np.ones(5)).shape == (0,)
    monkeypatch.setattr(products, "mkl_sparse_library", lambda: None)
    slow = products.sparse_product(A)
    assert isinstance(slow, products.RowBlocks)
    np.testing.assert_allclose(slow @ X, A @ X, rtol=0, atol=1e-13 * np.abs(A @ X).max())
    extended = products.sparse_product(A, np.longdouble) @ X.astype(np.longdouble)
    assert extended.dtype == np.longdouble


def test_solvers_are_callables_a_caller_may_pass_its_own():
    """The solvers are a registry of callables: a user-supplied one is called with the
    reduced system and its answer is used; an unknown name is refused."""
    from railcheck.fea.solvers import SOLVERS, solve_reduced, solver_of

    K = sp.diags([4.0, 5.0, 6.0]).tocsr()
    F = np.array([4.0, 10.0, 18.0])
    calls = []

    def mine(K, F, **options):
        calls.append(sorted(options))
        return sp.linalg.spsolve(K.tocsc(), F), {"solver": "mine"}

    U, info = solve_reduced(K, F, method=mine)
    assert info == {"solver": "mine"} and calls == [["B", "maxiter", "memory_limit", "prolongation", "report"]]
    np.testing.assert_allclose(U, [1.0, 2.0, 3.0])
    for name in ("direct", "scipy", "amg"):
        np.testing.assert_allclose(solve_reduced(K, F, B=np.eye(3), method=name)[0], [1.0, 2.0, 3.0], rtol=1e-9)
    assert set(SOLVERS) >= {"auto", "direct", "pardiso", "scipy", "pmg", "amg"}
    with pytest.raises(ValueError, match="unknown solver 'cholesky'"):
        solver_of("cholesky")


def saint_venant_torsion_constant(a: float, b: float, terms: int = 50) -> float:
    """J (m^4) of an a x b rectangle (a >= b), Saint-Venant's exact series (Timoshenko &
    Goodier, Theory of Elasticity, 3rd ed., sec. 109)."""
    n = np.arange(1, 2 * terms, 2)
    return a * b**3 * (1 / 3 - 64 / np.pi**5 * (b / a) * np.sum(np.tanh(n * np.pi * a / (2 * b)) / n**5))


@pytest.mark.slow  # 2.2-2.6 s, a fine bar: the fast tier keeps tractions giving F / A (test_freebody)
def test_a_torque_as_a_traction_twists_a_bar_as_saint_venant_says():
    """A textbook case written with public names only: a torque T on the tip face as the
    traction t = (T / I_p) (0, -(z - zc), y - yc), linear in the section coordinates, and
    a body force field; the twist angle between two sections far from the ends equals
    T L / (G J) with J from Saint-Venant's series (the ends' warping restraint stays
    local)."""
    from railcheck.fea.assembly import assemble
    from railcheck.fea.loading import body_force_vector, body_force_vectors, resultant, surface_dofs, traction_vector
    from railcheck.fea.materials import MATERIALS
    from railcheck.fea.mesh import dof_components, scalar_basis, vector_dof_map
    from railcheck.fea.system import solve, supports
    from railcheck.geometry import bar, mesh_part

    steel = MATERIALS["steel"]
    length, width, height, torque = 0.3, 0.023, 0.020, 50.0
    mesh = mesh_part(bar(length, width, height), 4e-3, 4e-3)
    K, basis = assemble(mesh.points, mesh.tets, steel, 2)
    tip = surface_dofs(basis, mesh.groups, "tip")
    yc, zc = tip.weights @ tip.points[:, 1:] / tip.weights.sum()
    polar = tip.weights @ ((tip.points[:, 1] - yc) ** 2 + (tip.points[:, 2] - zc) ** 2)
    k = torque / polar

    def twisting(x):
        return np.stack([0.0 * x[0], -k * (x[2] - zc), k * (x[1] - yc)])

    F = traction_vector(basis, mesh.groups, "tip", twisting)
    np.testing.assert_allclose(resultant(basis, F), 0.0, atol=1e-9 * torque / width)
    locs, comp = basis.doflocs.T, dof_components(basis)
    moment = np.sum((locs[:, 1] - yc) * F * (comp == 2) - (locs[:, 2] - zc) * F * (comp == 1))
    assert moment == pytest.approx(torque, rel=1e-9)
    uniform = body_force_vector(basis, [lambda x, c=c: np.stack([x[0] * 0 + (c == i) for i in range(3)]) for c in range(3)])
    np.testing.assert_allclose(uniform, body_force_vectors(basis), atol=1e-15)
    U, _ = solve(K, F, supports(basis, mesh.groups, ["clamp"]), "direct", basis)
    sb = scalar_basis(basis)
    nodes, dof = sb.doflocs.T, vector_dof_map(basis, sb)

    def twist_at(x0: float) -> float:
        """The section's mean rotation about x: least squares over the nodes near x0."""
        near = np.abs(nodes[:, 0] - x0) < 2.5e-3
        y, z = nodes[near, 1] - yc, nodes[near, 2] - zc
        uy, uz = U[dof[near, 1]], U[dof[near, 2]]
        return float(np.sum(y * uz - z * uy) / np.sum(y**2 + z**2))

    a, b = max(width, height), min(width, height)
    G = steel.youngs_modulus / (2 * (1 + steel.poisson_ratio))
    rate = torque / (G * saint_venant_torsion_constant(a, b))
    measured = (twist_at(0.2) - twist_at(0.1)) / 0.1
    assert measured == pytest.approx(rate, rel=0.005)


@pytest.mark.parametrize("failure", [MemoryError(3 * 2**30), MemoryError((40000, 40000), np.dtype(float))])
def test_a_factor_out_of_memory_falls_back_to_cg_and_says_why(monkeypatch, failure):
    """The cap's estimate (bytes) or numpy's own failure (an array's shape: issue 61, a
    TypeError before): either way one line saying why, then the iterative solve."""
    import scipy.sparse as sp

    from railcheck.fea import solvers

    def refused(*args, **kwargs):
        raise failure

    monkeypatch.setattr(solvers, "solve_factorised", refused)
    n = 60
    K = sp.diags([-np.ones(n - 1), 2.1 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csr")
    said: list[str] = []
    U, info = solvers.solve_auto(K, np.ones(n), B=np.ones((n, 1)), report=said.append)
    np.testing.assert_allclose(K @ U, np.ones(n), rtol=1e-6, atol=1e-8)
    assert len(said) >= 1 and ("GiB" in said[0] or "ran out of memory" in said[0]) and "AMG-CG instead" in said[0]
