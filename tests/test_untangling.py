"""railcheck's untangling of folded curved tetrahedra (railcheck.geometry.untangling): its
gradient against finite differences, its minimiser against a closed-form minimum, and on a
grooved rail gmsh curved, what it moves (nothing on a curved surface, flat-face nodes within
their plane) and what it leaves (every element valid but the few it straightens)."""

import numpy as np
import pytest

from railcheck.geometry import curving, mesher, untangling
from railcheck.geometry.models import rail


@pytest.fixture(scope="module")
def gmsh_curved():
    """(points, tets, curved edges, their mid nodes) of a 120 mm grooved rail as gmsh's
    second order left it: before any untangling or straightening."""
    seen = {}

    def capture(points, tets, edges, edge_points, *rest):
        seen["mesh"] = (points, tets, edges, edge_points)
        return curving.straighten_folded(points, tets, edges, edge_points, *rest)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(mesher, "UNTANGLE", False)
        mp.setattr(mesher, "straighten_folded", capture)
        mesher.build_mesh(rail(0.12), 0.02, 0.006)
    return seen["mesh"]


def test_the_objectives_gradient_is_its_finite_difference(gmsh_curved):
    objective, _ = untangling.untangling_problem(*gmsh_curved)
    assert objective.free.size > 10  # the grooves fold elements: there is something to untangle
    rng = np.random.default_rng(7)
    q = rng.normal(0.0, 2e-5, objective.free.size * 3)
    _, grad = objective(q)
    for k in rng.choice(q.size, 12, replace=False):
        h = 1e-9
        up, down = q.copy(), q.copy()
        up[k] += h
        down[k] -= h
        numeric = (objective(up)[0] - objective(down)[0]) / (2 * h)
        assert grad[k] == pytest.approx(numeric, rel=1e-4, abs=1e-6 * np.abs(grad).max())


def test_the_minimiser_reaches_a_quadratics_minimum():
    """L-BFGS on 1/2 x'Ax - b'x (A symmetric positive definite, condition 100): the
    closed-form minimiser A^-1 b to 1e-6 in 100 steps (1e-5 in 60, 4e-3 in 30)."""
    rng = np.random.default_rng(3)
    Q, _ = np.linalg.qr(rng.normal(size=(40, 40)))
    A = Q @ np.diag(np.geomspace(1.0, 100.0, 40)) @ Q.T
    b = rng.normal(size=40)
    x = untangling._lbfgs(lambda x: (0.5 * x @ A @ x - b @ x, A @ x - b), np.zeros(40), 100)
    np.testing.assert_allclose(x, np.linalg.solve(A, b), atol=1e-6)


def test_untangling_lifts_the_folds_moving_only_what_it_may(gmsh_curved):
    points, tets, edges, edge_points = gmsh_curved
    new_edges, new_points = untangling.untangle(points, tets, edges, edge_points)
    n = points.shape[0]
    before = dict(zip(curving.edge_keys(edges, n).tolist(), edge_points))
    after = dict(zip(curving.edge_keys(new_edges, n).tolist(), new_points))
    assert all(np.array_equal(after[k], p) for k, p in before.items())  # no curved-surface node moved
    moved = [k for k in after if k not in before]
    assert len(moved) > 10
    # each folded element's Jacobian lifted: the few still folded are straightened afterwards
    d = curving.edge_offsets(points, tets, new_edges, new_points)
    still = np.count_nonzero(curving.jacobian_ratios(points, tets, d).min(axis=1) < curving.MIN_JACOBIAN_RATIO)
    d0 = curving.edge_offsets(points, tets, edges, edge_points)
    folded = np.count_nonzero(curving.jacobian_ratios(points, tets, d0).min(axis=1) < curving.MIN_JACOBIAN_RATIO)
    assert still < 0.1 * folded, (still, folded)
    # a node on a flat outer face (the ends, sides, base, top) stays in its plane
    pairs = np.array(moved)
    ends = np.column_stack([pairs // n, pairs % n])
    offset = np.array([after[k] for k in moved]) - 0.5 * (points[ends[:, 0]] + points[ends[:, 1]])
    for axis in range(3):
        for plane in (points[:, axis].min(), points[:, axis].max()):
            on = (np.abs(points[ends[:, 0], axis] - plane) < 1e-9) & (np.abs(points[ends[:, 1], axis] - plane) < 1e-9)
            assert np.all(np.abs(offset[on, axis]) < 1e-12)
