"""Superposition and its screens (railcheck.fea.superpose) against brute force on random
fields: every node at every step, with von Mises written out from its definition. No FE:
these run in a second and guard each shortcut (the hull's candidate steps, the quadratic
form, the polygon's support function) on its own."""

import numpy as np
import pytest

from railcheck.fea.hull import candidate_steps, hull_polygon, support
from railcheck.fea.superpose import UnitFields, component_range, envelope, history_at_node, stress_at, von_mises_max


def von_mises_by_definition(s: np.ndarray) -> np.ndarray:
    """Voigt (xx, yy, zz, xy, yz, xz) on the first axis -> von Mises, written out."""
    xx, yy, zz, xy, yz, xz = s
    return np.sqrt(0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2) + 3 * (xy**2 + yz**2 + xz**2))


def brute(S: np.ndarray, C: np.ndarray) -> np.ndarray:
    """(nodes, steps) von Mises of every node at every step."""
    return von_mises_by_definition(np.einsum("cnk,tk->cnt", S, C))


def random_case(seed: int, nodes: int = 300, k: int = 3, steps: int = 200):
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 2 * np.pi, steps)
    C = np.column_stack([np.cos((j + 1) * t + rng.uniform(0, 6)) * rng.uniform(50, 500) for j in range(k)])
    C += rng.normal(scale=5.0, size=C.shape)
    S = rng.normal(size=(6, nodes, k)) * 1e5
    return S, C


@pytest.mark.parametrize(("k", "seed"), [(1, 0), (2, 1), (3, 2), (5, 3), (15, 6)])
def test_von_mises_max_equals_every_step(k, seed):
    S, C = random_case(seed, k=k)
    vm = brute(S, C)
    best, where = von_mises_max(S, C)
    np.testing.assert_allclose(best, vm.max(axis=1), rtol=1e-12)
    np.testing.assert_allclose(vm[np.arange(vm.shape[0]), where], vm.max(axis=1), rtol=1e-12)


@pytest.mark.parametrize(("k", "seed"), [(2, 4), (3, 5)])
def test_candidate_steps_hold_every_maximum_of_a_convex_function(k, seed):
    """The hull's vertices: fewer than the steps, and the maximum of von Mises (convex in
    the coefficients) over them is the maximum over all steps, at every node."""
    S, C = random_case(seed, k=k, steps=400)
    steps = candidate_steps(C)
    assert 0 < steps.size < C.shape[0] and np.all(np.diff(steps) > 0)
    np.testing.assert_allclose(brute(S, C[steps]).max(axis=1), brute(S, C).max(axis=1), rtol=1e-12)
    # every step for few steps or one coefficient
    assert candidate_steps(C[:10]).size == 10
    assert candidate_steps(C[:, :1]).size == C.shape[0]
    # a degenerate (collinear) history: every step, nothing lost
    line = np.outer(np.linspace(-1, 1, 100), [1.0, 2.0])
    assert candidate_steps(line).size == 100


def test_stress_at_is_the_weighted_sum_of_unit_fields():
    S, C = random_case(6)
    c = C[17]
    np.testing.assert_allclose(stress_at(S, c), S[:, :, 0] * c[0] + S[:, :, 1] * c[1] + S[:, :, 2] * c[2], rtol=1e-12)
    assert stress_at(S, C).shape == (6, S.shape[1], C.shape[0])


@pytest.mark.parametrize("k", [1, 2, 3])
def test_component_range_equals_every_step(k):
    S, C = random_case(7, k=k)
    s = np.einsum("cnk,tk->cnt", S, C)
    hi, lo = component_range(S, C)
    np.testing.assert_allclose(hi, s.max(axis=2), rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(lo, s.min(axis=2), rtol=1e-12, atol=1e-9)


def _long_history(kind: str, steps: int, k: int, rng) -> np.ndarray:
    """(steps, k) coefficients like a crank cycle's: a constant 1, then columns of very
    different scales (forces, torques, accelerations); ``kind`` shapes them."""
    t = np.linspace(0.0, 2 * np.pi, steps, endpoint=False)
    C = np.zeros((steps, k))
    for j in range(1, k):
        for h in range(1, 6):
            C[:, j] += rng.normal() / h * np.cos(h * t + rng.uniform(0, 2 * np.pi))
        for h in range(6, 40 if kind == "rich" else 6):  # harmonics to the 39th, undamped (a rail's small columns)
            C[:, j] += rng.normal() * np.cos(h * t + rng.uniform(0, 2 * np.pi))
    C[:, 1:] *= np.logspace(7, 0, k - 1)  # 1e7 down to 1
    C[:, 0] = 1.0
    if kind == "noisy":  # no smoothness: every step a jump
        C[:, 1:] += rng.normal(size=(steps, k - 1)) * np.logspace(7, 0, k - 1)
    elif kind == "plateau":  # long stretches of equal values: many blocks hold the extreme
        C[:, 1:] = np.clip(C[:, 1:], -0.3 * np.abs(C[:, 1:]).max(axis=0), 0.3 * np.abs(C[:, 1:]).max(axis=0))
    elif kind == "still column":  # a coefficient that never moves, and one that is zero
        C[:, 2] = 3.0e5
        C[:, 3] = 0.0
    elif kind == "polyline":  # straight within each block of 32: the along-bound alone is tight
        corners = C[::32]
        at = np.arange(steps) / 32.0
        b = np.minimum(at.astype(int), corners.shape[0] - 2)
        C = corners[b] + (at - b)[:, None] * (corners[b + 1] - corners[b])
    return C


def _long_stresses(kind: str, C: np.ndarray, rng) -> np.ndarray:
    """(6, 300, k) unit stresses for a :func:`_long_history`: every coefficient's stress of
    one order, an unstressed node (5) and a node only the smallest coefficient stresses (9);
    for ``kind`` "large constant", the constant load's (``C[:, 0] == 1``) 30 times the rest."""
    k = C.shape[1]
    S = rng.normal(size=(6, 300, k)) / np.maximum(np.abs(C).max(axis=0), 1.0)
    if kind == "large constant":
        S[:, :, 0] *= 30.0
    S[:, 5] = 0.0
    S[:, 9] = 0.0
    S[:, 9, k - 1] = 1.0
    return S


#: (kind, steps, coefficients) of the long histories read by blocks (:func:`_long_history`)
LONG_HISTORIES = [
    ("smooth", 5000, 13),
    ("smooth", 1001, 10),
    ("smooth", 1001, 6),
    ("noisy", 2000, 12),
    ("plateau", 3000, 11),
    ("still column", 777, 8),
    ("polyline", 4000, 9),
    ("large constant", 3000, 10),
    ("rich", 2000, 9),
]


@pytest.mark.parametrize(("kind", "steps", "k"), LONG_HISTORIES)
def test_a_long_history_s_component_range_equals_every_step(kind, steps, k):
    """A history long enough to be read by blocks (:func:`fea.superpose.pruned_range`):
    each component's maximum and minimum at every node equal every step's, to rounding
    (relative to the row's |s| |c|), on smooth, noisy, clipped and still coefficients,
    with an unstressed node and a node stressed by one coefficient only."""
    from railcheck.fea.superpose import RANGE_PRUNE_STEPS, dense_range

    assert steps >= RANGE_PRUNE_STEPS
    rng = np.random.default_rng(steps + k)
    C = _long_history(kind, steps, k, rng)
    S = _long_stresses(kind, C, rng)
    s = np.einsum("cnk,tk->cnt", S, C)
    scale = np.einsum("cnk,k->cn", np.abs(S), np.abs(C).max(axis=0)) + 1e-300
    hi, lo = component_range(S, C)
    assert np.abs(hi - s.max(axis=2)).max() / scale.max() < 1e-13
    assert np.all(np.abs(hi - s.max(axis=2)) <= 1e-12 * scale)
    assert np.all(np.abs(lo - s.min(axis=2)) <= 1e-12 * scale)
    assert np.all(hi[:, 5] == 0.0) and np.all(lo[:, 5] == 0.0)
    dense = dense_range(S, C)
    assert np.all(np.abs(hi - dense[0]) <= 1e-12 * scale) and np.all(np.abs(lo - dense[1]) <= 1e-12 * scale)


@pytest.mark.parametrize(("kind", "steps", "k"), LONG_HISTORIES)
def test_a_long_history_s_von_mises_max_equals_every_step(kind, steps, k):
    """A history long enough to be read by blocks (:func:`fea.superpose.pruned_von_mises_max`):
    each node's largest von Mises equals the one of every step by definition, to rounding,
    at a step that holds it (the first of equal ones where the values are equal: an
    unstressed node's is step 0, as a read of every step gives)."""
    from railcheck.fea.superpose import RANGE_PRUNE_STEPS, dense_von_mises_max

    assert steps >= RANGE_PRUNE_STEPS
    rng = np.random.default_rng(steps + 3 * k)
    C = _long_history(kind, steps, k, rng)
    S = _long_stresses(kind, C, rng)
    vm = brute(S, C)  # (nodes, steps)
    scale = np.sqrt((np.einsum("cnk,k->cn", np.abs(S), np.abs(C).max(axis=0)) ** 2).sum(axis=0)) + 1e-300
    best, where = von_mises_max(S, C)
    assert np.all(np.abs(best - vm.max(axis=1)) <= 1e-7 * scale)
    assert np.all(np.abs(vm[np.arange(300), where] - vm.max(axis=1)) <= 1e-7 * scale)
    assert best[5] == 0.0 and where[5] == 0
    dense_best, dense_where = dense_von_mises_max(S, C)
    assert np.all(np.abs(best - dense_best) <= 1e-7 * scale)
    stressed = vm.max(axis=1) > 1e-3 * scale  # a clear maximum: the same step
    assert np.mean(where[stressed] == dense_where[stressed]) > 0.99


def test_a_long_history_with_a_nan_gives_nan_not_an_error():
    """A non-finite coefficient (a numerical failure upstream) reaches the caller as NaN,
    which it refuses as a numerical failure (``railcheck.model.cycle``), not as the block
    bounds' SVD error."""
    rng = np.random.default_rng(1)
    C = _long_history("smooth", 600, 6, rng)
    C[100, 3] = np.nan
    S = rng.normal(size=(6, 20, 6))
    assert np.isnan(von_mises_max(S, C)[0]).all()
    hi, lo = component_range(S, C)
    assert np.isnan(hi).all() and np.isnan(lo).all()


def test_hull_polygon_and_its_support_function():
    """A square's hull is its four corners counter-clockwise; the support function of any
    direction is the largest projection of the corners; no polygon for three points or
    a zero column."""
    square = np.array([[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0], [0.2, 0.1], [0.0, 0.5]])
    V = hull_polygon(square)
    assert V.shape == (4, 2)
    area = 0.5 * np.sum(V[:, 0] * np.roll(V[:, 1], -1) - np.roll(V[:, 0], -1) * V[:, 1])
    assert area == pytest.approx(4.0)  # positive: counter-clockwise
    rng = np.random.default_rng(8)
    D = rng.normal(size=(1000, 2))
    np.testing.assert_allclose(support(D, V), (D @ square.T).max(axis=1), rtol=1e-12)
    angle = np.arctan2(D[:, 1], D[:, 0])
    np.testing.assert_allclose(support(D, V, angle), (D @ square.T).max(axis=1), rtol=1e-12)
    assert hull_polygon(square[:3]) is None
    assert hull_polygon(np.column_stack([square[:, 0], np.zeros(6)])) is None


def _fields(S, verdict=None, tip=None):
    nodes = S.shape[1]
    rng = np.random.default_rng(9)
    return UnitFields(
        stress=S,
        tip=rng.normal(size=(3, S.shape[2])) * 1e-6 if tip is None else tip,
        displacement=np.zeros((nodes, 3, S.shape[2])),
        nodes=rng.normal(size=(nodes, 3)),
        verdict_mask=np.ones(nodes, bool) if verdict is None else verdict,
        names=tuple(f"c{i}" for i in range(S.shape[2])),
    )


@pytest.mark.parametrize("k", [2, 3])
def test_envelope_equals_every_node_at_every_step(k):
    """The peak over the verdict nodes and its step, node and place; every node's maximum;
    the support peak over all nodes; the tip's largest magnitude and its step."""
    S, C = random_case(10 + k, k=k)
    verdict = np.arange(S.shape[1]) % 3 != 0
    f = _fields(S, verdict)
    vm = brute(S, C)
    env = envelope(f, C)
    masked = np.where(verdict[:, None], vm, -np.inf)
    node, step = np.unravel_index(np.argmax(masked), vm.shape)
    assert env.max_von_mises == pytest.approx(vm[node, step], rel=1e-12)
    assert (env.node, env.step) == (node, step)
    np.testing.assert_array_equal(env.location, f.nodes[node])
    np.testing.assert_allclose(env.node_envelope, vm.max(axis=1), rtol=1e-12)
    assert env.support_peak == pytest.approx(vm.max(), rel=1e-12) and env.support_peak >= env.max_von_mises
    tip = np.linalg.norm(C @ f.tip.T, axis=1)
    assert env.max_tip == pytest.approx(tip.max(), rel=1e-12) and env.tip_step == int(np.argmax(tip))
    # an all-excluded mask reads every node
    none = envelope(_fields(S, np.zeros(S.shape[1], bool)), C)
    assert none.max_von_mises == pytest.approx(vm.max(), rel=1e-12)


def test_history_at_one_node_is_its_von_mises_at_every_step():
    S, C = random_case(14)
    f = _fields(S)
    np.testing.assert_allclose(history_at_node(f, C, 42), brute(S, C)[42], rtol=1e-12)


def test_screens_on_histories_with_zeros_a_dead_column_and_a_line():
    """Histories that take the screens' other branches: a column with exact zeros (sin 0),
    one live column beside a dead one, and two columns on a line (no polygon); every
    result equals brute force, and a node with no stress has none."""
    t = np.linspace(0, 2 * np.pi, 300)
    rng = np.random.default_rng(15)
    S = rng.normal(size=(6, 50, 2)) * 1e5
    S[:, 7] = 0.0  # an unstressed node
    for C in (
        np.column_stack([300 * np.cos(t), 200 * np.sin(t)]),  # sin(0) = 0 exactly
        np.column_stack([-50 - 300 * np.cos(t), np.zeros_like(t)]),  # one live column, its minimum the larger
        np.column_stack([50 + 300 * np.cos(t), np.zeros_like(t)]),  # and its maximum the larger
        np.outer(np.cos(t), [1.0, -2.0]),  # collinear: no polygon
    ):
        vm = brute(S, C)
        steps = candidate_steps(C)
        np.testing.assert_allclose(brute(S, C[steps]).max(axis=1), vm.max(axis=1), rtol=1e-12)
        best, _ = von_mises_max(S, C)
        np.testing.assert_allclose(best, vm.max(axis=1), rtol=1e-12)
        assert best[7] == 0.0
        s = np.einsum("cnk,tk->cnt", S, C)
        hi, lo = component_range(S, C)
        np.testing.assert_allclose(hi, s.max(axis=2), rtol=1e-12, atol=1e-6)
        np.testing.assert_allclose(lo, s.min(axis=2), rtol=1e-12, atol=1e-6)
        env = envelope(_fields(S), C)
        assert env.node_envelope[7] == 0.0 and env.max_von_mises == pytest.approx(vm.max(), rel=1e-12)


def test_the_support_function_of_a_many_sided_polygon():
    """A 60-gon (the binary search over edge normals has work to do) in every direction."""
    a = np.sort(np.random.default_rng(16).uniform(0, 2 * np.pi, 60))
    P = np.column_stack([3 * np.cos(a), np.sin(a)])
    V = hull_polygon(P)
    D = np.random.default_rng(17).normal(size=(5000, 2))
    np.testing.assert_allclose(support(D, V), (D @ P.T).max(axis=1), rtol=1e-12)


def test_the_records_are_frozen():
    import dataclasses

    S, C = random_case(18)
    f = _fields(S)
    for record in (f, envelope(f, C)):
        with pytest.raises(dataclasses.FrozenInstanceError):
            record.stress = None


@pytest.mark.parametrize("k", [2, 8])
def test_the_screened_peak_is_every_nodes_peak_with_its_node_and_step(k):
    """envelope(every_node=False) evaluates only the nodes that can hold the peak: its
    peak, node and step equal those of every node x every step, over the verdict nodes and
    over all (the support peak), on random fields with a few hot nodes and decoys (the
    nodes of largest eigenvalue that do not hold the peak)."""
    from railcheck.fea.superpose import UnitFields, envelope, von_mises_max

    rng = np.random.default_rng(k)
    n, T = 4000, 300
    S = rng.normal(size=(6, n, k)) * np.exp(1.5 * rng.normal(size=(1, n, 1)))
    # decoys, more than the screen evaluates first: huge along the first coefficient, which stays small
    S[:, :200] *= 0.0
    S[0, :200, 0] = 5 * np.abs(S).max()
    t = np.linspace(0, 2 * np.pi, T)
    C = np.column_stack([0.01 * np.cos(t)] + [np.cos((j + 1) * t + j) for j in range(1, k)])
    mask = rng.random(n) > 0.2
    mask[np.argsort(-von_mises_max(S, C)[0])[:5]] = False  # the hottest nodes outside: two different peaks
    fields = UnitFields(S, np.zeros((3, k)), np.zeros((n, 3, k)), rng.normal(size=(n, 3)), mask, tuple(map(str, range(k))))
    full, fast = envelope(fields, C), envelope(fields, C, every_node=False)
    assert full.support_peak > full.max_von_mises
    assert fast.node_envelope is None
    assert (fast.node, fast.step) == (full.node, full.step)
    assert fast.max_von_mises == pytest.approx(full.max_von_mises, rel=1e-13)
    assert fast.support_peak == pytest.approx(full.support_peak, rel=1e-13)


def test_reduced_histories_give_the_same_stresses_in_fewer_coefficients():
    """A free body's history spans a low-dimensional affine space (the crank's a plane):
    :func:`reduced` rewrites it exactly in its mean and principal coordinates. Every
    node's stress at every step, the envelope and the component ranges equal the full
    fields' to 1e-12, also when one coefficient barely moves but carries a huge stress per
    unit (a mode's): the truncation is judged in stress, not in coefficients."""
    from dataclasses import replace as _replace

    from railcheck.fea.superpose import UnitFields, component_range, reduced, stress_at

    rng = np.random.default_rng(5)
    n, T = 400, 720
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    basis = np.column_stack([np.ones(T), np.cos(t), np.sin(t)])  # an affine plane
    mix = rng.normal(size=(3, 8))
    C = basis @ mix
    C[:, 7] = 1e-13 * np.sin(5 * t)  # barely moves...
    S = rng.normal(size=(6, n, 8))
    S[:, :, 7] *= 1e12  # ...but each unit of it is a huge stress
    fields = UnitFields(
        S, rng.normal(size=(3, 8)), np.zeros((n, 3, 8)), rng.normal(size=(n, 3)), np.ones(n, bool), tuple("abcdefgh")
    )
    few, A = reduced(fields, C)
    assert A.shape[1] == 4 and np.all(A[:, 0] == 1.0)  # the mean, the plane's two, the small one
    full = stress_at(S, C)
    np.testing.assert_allclose(stress_at(few.stress, A), full, rtol=0, atol=1e-12 * np.abs(full).max())
    hi, lo = component_range(S, C)
    hi_r, lo_r = component_range(few.stress, A)
    np.testing.assert_allclose(hi_r, hi, rtol=0, atol=1e-12 * np.abs(full).max())
    np.testing.assert_allclose(lo_r, lo, rtol=0, atol=1e-12 * np.abs(full).max())
    # the plane alone: the affine planar fast path (support functions) gives the ranges
    plane = _replace(fields, stress=S[:, :, :7], tip=fields.tip[:, :7], displacement=fields.displacement[..., :7])
    few, A = reduced(plane, C[:, :7])
    assert A.shape[1] == 3
    hi, lo = component_range(S[:, :, :7], C[:, :7])
    hi_r, lo_r = component_range(few.stress, A)
    np.testing.assert_allclose(hi_r, hi, rtol=0, atol=1e-12 * np.abs(hi).max())
    np.testing.assert_allclose(lo_r, lo, rtol=0, atol=1e-12 * np.abs(hi).max())


@pytest.mark.parametrize(
    ("reader", "kind", "constant", "most"),
    [
        ("component range", "smooth", 1.0, 2.8),
        ("von Mises", "smooth", 1.0, 6.0),
        ("component range", "rich", 100.0, 6.5),
        ("von Mises", "rich", 100.0, 30.0),
    ],
)
def test_a_smooth_long_history_is_read_in_a_few_blocks_per_row(monkeypatch, reader, kind, constant, most):
    """The blocks' bounds prune (:func:`fea.superpose.pruned_range`,
    :func:`fea.superpose.pruned_von_mises_max`): on a history of 5,000 steps with
    coefficients of scales 1 to 1e7, a row's extreme (a node's largest von Mises) is sought
    in a few blocks of its 157, not all (the bounds in scaled coefficients; unscaled, the
    largest coefficient's reach would keep every block). Also on a rich history (harmonics
    to the 39th) where a constant load's stress is 100 times the moving ones' (a rail
    under the rig's weight: the constant never moves, so it widens no bound). Before issue
    59's third stop (one direction per block, the constant in the rest's norm) these read
    3.1, 5.9, 135 and 156 blocks per search; with two directions and the constant in the
    rest's norm, 2.5, 5.5, 10.2 and 55."""
    import railcheck.fea.superpose as superpose

    rng = np.random.default_rng(5)
    C = _long_history(kind, 5000, 13, rng)
    S = rng.normal(size=(6, 400, 13)) / np.abs(C).max(axis=0)
    S[:, :, 0] *= constant  # C[:, 0] == 1: the constant load's stress
    name, pruned, searches = {
        "component range": ("_read_blocks", superpose.pruned_range, 2 * 6 * 400),  # each row's maximum and minimum
        "von Mises": ("_read_von_mises_blocks", superpose.pruned_von_mises_max, 400),
    }[reader]
    pairs = []
    read = getattr(superpose, name)
    monkeypatch.setattr(superpose, name, lambda *args: pairs.append(args[-2].size) or read(*args))  # args[-2]: the rows
    pruned(S, C)
    assert 1.0 <= sum(pairs) / searches < most


@pytest.mark.parametrize("k", [1, 2])
def test_screened_max_of_one_or_two_coefficients_equals_every_node_at_every_step(k):
    """One load source alone (a check without inertia: one coefficient) is screened as two,
    the second zero: the same maximum, node and step as evaluating everything, over the
    verdict nodes and over all of them (issue 61: an IndexError before)."""
    from railcheck.fea.superpose import screened_max

    rng = np.random.default_rng(61 + k)
    S = rng.normal(size=(6, 300, k)) * 1e6
    C = rng.normal(size=(90, k))
    mask = rng.random(300) > 0.3
    vm = von_mises_by_definition(np.einsum("cnk,tk->cnt", S, C))  # (nodes, steps)
    inside = np.where(mask[:, None], vm, -np.inf)
    node = int(np.argmax(inside.max(axis=1)))
    peak, at, step, everywhere = screened_max(S, C, mask)
    assert peak == pytest.approx(inside.max(), rel=1e-12) and at == node
    assert step == int(np.argmax(vm[node])) and everywhere == pytest.approx(vm.max(), rel=1e-12)
