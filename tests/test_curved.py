"""Curved (isoparametric) P2: the mid-edge nodes gmsh places on the true surfaces.

Truths: a hole's exact circumference; a linear displacement field (patch test) and the
six rigid-body motions, which the isoparametric P2 space holds exactly on any element map;
the resultant of a traction; Jacobians computed here by finite differences of the map."""

from dataclasses import replace

import numpy as np
import pytest

from railcheck.fea.assembly import straight_and_curved
from railcheck.fea.elasticity import (
    assemble,
    check_rigid_modes,
    dof_components,
    group_area,
    mass_matrix,
    recover_stress,
    resultant,
    unit_traction_vectors,
)
from railcheck.fea.materials import MATERIALS
from railcheck.fea.mesh import curved_elements, group_facets, skfem_mesh
from railcheck.fea.stress import affine_stress_moments, quadrature_stress_moments
from railcheck.geometry import curving
from railcheck.geometry.catalogue import RAIL
from railcheck.geometry.mesher import mesh_part
from railcheck.geometry.models import rail

STEEL = MATERIALS["steel"]


#: the rail without its grooves: only the holes are curved, and gmsh's mid-edge nodes
#: are the only ones off the straight midpoints (the grooved profile's mesh also moves
#: interior mid nodes: test_grooves_are_curved_and_no_element_folds)
PLAIN = replace(RAIL, groove_radius=0.0)


@pytest.fixture(scope="module")
def short_rail():
    """A 120 mm rail with two holes, 2 mm elements at the holes (11 per circumference)."""
    geo = rail(0.12, PLAIN)
    return geo, mesh_part(geo, 0.006, 0.002, cache=False)


@pytest.fixture(scope="module")
def tiny_rail():
    """A 60 mm rail with one hole, coarse enough for an eigenvalue count."""
    return mesh_part(rail(0.06, PLAIN), 0.01, 0.004, cache=False)


def test_grooves_are_curved_and_no_element_folds():
    """The grooved profile (default mesh sizes): the mid nodes of the edges whose ends both
    lie on a groove lie on its cylinder (to 1 nm: the untangling moves no node on a curved
    surface; a chord's midpoint misses it by tens of um), the untangling leaves every
    element's Jacobian positive, and nearly every curved edge
    stays curved (straightening one loses the groove's arc there)."""
    geo = rail(0.12)
    mesh = mesh_part(geo, 0.02, 0.006, cache=False)
    edges, mids = mesh.curved
    p = dict(geo.params)
    r, w = p["groove_radius"], p["width"]

    def groove_distance(points):
        y, z = points[:, 1], points[:, 2]
        return np.min(
            [
                np.abs(np.hypot(y - s * w / 2, z - zg) - r)
                for s in (-1, 1)
                for zg in (p["lower_groove_z"], p["upper_groove_z"])
            ],
            axis=0,
        )

    # the boundary faces with three vertices on a groove: their edges lie on the cylinder
    faces = np.sort(mesh.tets[:, [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]].reshape(-1, 3), axis=1)
    unique, count = np.unique(faces, axis=0, return_counts=True)
    boundary = unique[count == 1]
    grid = 1e-9  # m: gmsh's placement on the cylinder, kept by the untangling
    on_groove = groove_distance(mesh.points) < grid
    groove_faces = boundary[on_groove[boundary].all(axis=1)]
    surface_edges = np.unique(np.sort(groove_faces[:, [[0, 1], [1, 2], [0, 2]]].reshape(-1, 2), axis=1), axis=0)
    # an edge along the groove's axis (x) is a straight line of the cylinder: its mid node sits on its chord
    across = np.hypot(*(mesh.points[surface_edges[:, 0], 1:] - mesh.points[surface_edges[:, 1], 1:]).T) > 1e-9
    surface_edges = surface_edges[across]
    keys = curving.edge_keys(edges, mesh.points.shape[0])
    on_surface = np.isin(keys, curving.edge_keys(surface_edges, mesh.points.shape[0]))
    assert on_surface.sum() > 0.8 * surface_edges.shape[0] > 100  # curved, bar the few straightened
    assert np.all(groove_distance(mids[on_surface]) < grid)
    d = curving.edge_offsets(mesh.points, mesh.tets, edges, mids)
    assert curving.jacobian_ratios(mesh.points, mesh.tets, d).min() > 0
    straightened = int(mesh.warning.split()[0]) if mesh.warning else 0
    assert straightened < 0.15 * edges.shape[0], (straightened, edges.shape[0])


def _vector_basis(mesh, curved, intorder=2):
    from skfem import Basis, ElementTetP2
    from skfem.element import ElementVector

    return Basis(skfem_mesh(mesh.points, mesh.tets, curved), ElementVector(ElementTetP2()), intorder=intorder)


def test_curved_p2_gives_a_hole_circumference_to_1e4_where_straight_p2_does_not(short_rail):
    geo, mesh = short_rail
    p = dict(geo.params)
    height = p["height"] - p["counterbore_depth"]  # the through-hole below the counterbore
    exact = np.pi * p["hole_diameter"]
    for k in range(2):
        curved = group_area(_vector_basis(mesh, mesh.curved), mesh.groups, f"hole_{k}") / height
        straight = group_area(_vector_basis(mesh, None), mesh.groups, f"hole_{k}") / height
        assert abs(curved / exact - 1) < 1e-4, curved / exact - 1
        assert abs(straight / exact - 1) > 3e-3, straight / exact - 1  # faceted: ~1e-2 short


def test_only_edges_on_curved_surfaces_are_curved_and_they_lie_on_the_cylinders(short_rail):
    geo, mesh = short_rail
    p = dict(geo.params)
    edges, mids = mesh.curved
    assert edges.shape[0] > 100
    radius = np.hypot(mids[:, 0][:, None] - np.array(p["hole_x"])[None, :], mids[:, 1][:, None]).min(axis=1)
    on_hole = np.abs(radius - p["hole_diameter"] / 2) < 1e-9
    on_counterbore = np.abs(radius - p["counterbore_diameter"] / 2) < 1e-9
    assert np.all(on_hole | on_counterbore)
    straight_mid = 0.5 * (mesh.points[edges[:, 0]] + mesh.points[edges[:, 1]])
    assert np.all(np.linalg.norm(mids - straight_mid, axis=1) > 0)


def test_patch_test_is_exact_on_the_curved_mesh(tiny_rail):
    from skfem import condense, solve

    mesh = tiny_rail
    K, basis = assemble(mesh.points, mesh.tets, STEEL, 2, mesh.curved)
    assert curved_elements(basis.mesh).size > 50
    G = np.array([[1e-3, 2e-4, -3e-4], [5e-4, -1e-3, 1e-4], [-2e-4, 3e-4, 7e-4]])
    c = np.array([1e-5, -2e-5, 3e-5])
    comp = dof_components(basis)
    exact = (G @ basis.doflocs)[comp, np.arange(basis.N)] + c[comp]
    boundary = basis.get_dofs().all()
    u = solve(*condense(K, np.zeros(basis.N), x=exact, D=boundary))
    assert np.max(np.abs(u - exact)) < 1e-10 * np.max(np.abs(exact))
    # its stress is constant, and the projection onto the curved space keeps it exactly
    strain = 0.5 * (G + G.T)
    lam, mu = STEEL.lame
    sigma = 2 * mu * strain + lam * np.trace(strain) * np.eye(3)
    expected = np.array([sigma[0, 0], sigma[1, 1], sigma[2, 2], sigma[0, 1], sigma[1, 2], sigma[0, 2]])
    S = recover_stress(basis, u, STEEL)
    assert np.max(np.abs(S - expected[:, None])) < 1e-9 * np.max(np.abs(expected))
    # the degree-3 rule on curved elements is what makes it exact: the 4-point rule is not
    K4 = _four_point_stiffness(mesh)
    u4 = solve(*condense(K4, np.zeros(basis.N), x=exact, D=boundary))
    assert np.max(np.abs(u4 - exact)) > 1e-8 * np.max(np.abs(exact))


def test_closed_form_projection_on_straight_elements_equals_quadrature_everywhere(tiny_rail):
    """The stress projection's mass matrix and stress moments, closed form on the straight
    elements and quadrature on the curved ones, against scikit-fem's degree-4 rule on the
    isoparametric map of every element (random displacements, two columns)."""
    from skfem import Basis, BilinearForm, asm

    mesh = tiny_rail
    _, basis = assemble(mesh.points, mesh.tets, STEEL, 2, mesh.curved)
    straight, curved = straight_and_curved(basis)
    assert straight.size > 50 and curved is not None
    everywhere = Basis(basis.mesh, basis.elem.elem, intorder=4)
    M = mass_matrix(basis)
    ref = asm(BilinearForm(lambda u, v, w: u * v), everywhere)
    assert abs(M - ref).max() <= 1e-12 * abs(ref).max()
    U = np.random.default_rng(3).normal(size=(basis.N, 2)) * 1e-5
    mine = affine_stress_moments(basis, U, STEEL) + quadrature_stress_moments(basis, curved, U, STEEL)
    quadrature = quadrature_stress_moments(basis, everywhere, U, STEEL)
    assert np.max(np.abs(mine - quadrature)) <= 1e-11 * np.max(np.abs(quadrature))


def _four_point_stiffness(mesh):
    """The stiffness of the curved mesh with the 4-point rule on every element (what the
    straight-element rule would give), assembled by scikit-fem itself."""
    from skfem import asm
    from skfem.models.elasticity import linear_elasticity

    return asm(linear_elasticity(*STEEL.lame), _vector_basis(mesh, mesh.curved))


def test_six_rigid_body_modes_on_the_curved_mesh(tiny_rail):
    from scipy.sparse import identity
    from scipy.sparse.linalg import eigsh

    mesh = tiny_rail
    assert mesh.curved_edges.shape[0] > 20
    assert check_rigid_modes(mesh.points, mesh.tets, STEEL, 2, mesh.curved) < 1e-12
    K, _ = assemble(mesh.points, mesh.tets, STEEL, 2, mesh.curved)
    scale = K.diagonal().max()
    shift = 1e-8 * scale
    ev = np.sort(eigsh(K + shift * identity(K.shape[0]), k=8, sigma=0.0, which="LM", return_eigenvectors=False)) - shift
    assert np.all(np.abs(ev[:6]) < 1e-9 * scale)  # six zero-energy modes
    assert ev[6] > 1e-7 * scale  # and no seventh


def test_traction_on_a_curved_hole_integrates_to_the_force(short_rail):
    _, mesh = short_rail
    K, basis = assemble(mesh.points, mesh.tets, STEEL, 2, mesh.curved)
    F = np.array([120.0, -45.0, 30.0])
    total = resultant(basis, unit_traction_vectors(basis, mesh.groups, "hole_1") @ F)
    assert np.allclose(total, F, rtol=0, atol=1e-12 * np.abs(F).max())


def test_straight_mesh_surface_weights_equal_scikit_fem_facet_integrals(short_rail):
    from skfem import FacetBasis, LinearForm, asm

    _, mesh = short_rail
    basis = _vector_basis(mesh, None)
    fb = FacetBasis(basis.mesh, basis.elem, facets=group_facets(basis, mesh.groups, "hole_0"), intorder=4)
    area = asm(LinearForm(lambda v, w: v[0]), fb).sum()
    ref = np.stack([asm(LinearForm(lambda v, w, c=c: v[c] / area), fb) for c in range(3)], axis=1)
    mine = unit_traction_vectors(basis, mesh.groups, "hole_0")
    assert np.abs(mine - ref).max() < 1e-12 * np.abs(ref).max()


def test_jacobian_ratio_equals_finite_differences_of_the_quadratic_map():
    rng = np.random.default_rng(3)
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]]) + 0.05 * rng.standard_normal((4, 3))
    tets = np.array([[0, 1, 2, 3]])
    d = 0.08 * rng.standard_normal((1, 6, 3))
    lam = curving._sample_barycentrics()
    got = curving.jacobian_ratios(points, tets, d)[0]

    def x_of(xi):
        L = np.array([1 - xi.sum(), *xi])
        x = sum(points[i] * L[i] * (2 * L[i] - 1) for i in range(4))
        for k, (a, b) in enumerate(curving.LOCAL_EDGES):
            x = x + 4 * L[a] * L[b] * (0.5 * (points[a] + points[b]) + d[0, k])
        return x

    h = 1e-6
    for s, L in enumerate(lam):
        xi = L[1:]
        J = np.column_stack([(x_of(xi + h * e) - x_of(xi - h * e)) / (2 * h) for e in np.eye(3)])
        J_aff = np.column_stack([points[k] - points[0] for k in (1, 2, 3)])
        assert got[s] == pytest.approx(np.linalg.det(J) / np.linalg.det(J_aff), rel=1e-7, abs=1e-9)


def test_a_folding_curved_edge_is_straightened():
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0], [1, 1, 1.0]])
    tets = np.array([[0, 1, 2, 3], [1, 2, 3, 4]])
    edges = np.array([[0, 1], [1, 4]])
    # edge 0-1 bulges far past the opposite face: the first element folds; edge 1-4 is mild
    mids = np.array([[0.5, 0.0, 0.0], [1.0, 0.5, 0.5]]) + np.array([[0.0, 0.0, 0.9], [0.02, 0.0, 0.0]])
    kept, where, dropped = curving.straighten_folded(points, tets, edges, mids)
    assert dropped == 1 and kept.tolist() == [[1, 4]] and np.array_equal(where, mids[1:])
    d = curving.edge_offsets(points, tets, kept, where)
    assert curving.jacobian_ratios(points, tets, d).min() > curving.MIN_JACOBIAN_RATIO


def test_cached_mesh_keeps_its_curved_edges(tmp_path):
    geo = rail(0.06)
    built = mesh_part(geo, 0.01, 0.004, cache_dir=tmp_path)
    read = mesh_part(geo, 0.01, 0.004, cache_dir=tmp_path)
    assert read.cached and not built.cached
    assert np.array_equal(read.curved_edges, built.curved_edges)
    assert np.array_equal(read.curved_points, built.curved_points)


def test_a_few_straightened_edges_are_a_note_and_many_a_warning():
    """Under 1% of the curved edges straightened (the default rails: 0.3-0.5%) is a note on
    the mesh's progress line, not a run warning nobody can act on; 40% (a 0.5 mm groove
    radius), or a straightening after a failed untangling, stays a warning."""
    from railcheck.model.cycle import minor_straightening

    few = "100 curved edges straightened to keep elements from folding (0.5% of the curved edges; "
    few += "the surface is faceted there)"
    assert minor_straightening(few) == few
    assert minor_straightening(few.replace("(0.5%", "(40.4%")) is None
    assert minor_straightening("gmsh's untangling of the curved elements failed (x): meshed without it; " + few) is None
    assert minor_straightening(None) is None and minor_straightening("cached mesh x.npz damaged: rebuilt") is None
