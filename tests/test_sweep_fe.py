"""The sweep's screened FE evaluation equals evaluating every node and step."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from railcheck.fea.elasticity import von_mises
from railcheck.fea.fatigue import alternating_and_mean, safety_factor
from railcheck.fea.screening import (
    box_union,
    fatigue_min,
    group_nodes,
    group_thresholds,
    make_screen,
    peak_and_fatigue,
    restricted_screen,
    tip_peak,
    von_mises_peak,
)


def _brute(stress, mask, C, se=200e6, sut=750e6, criterion="goodman"):
    S = stress[:, mask]
    X = np.tensordot(S, C, axes=([2], [2]))  # (6, n, s, T)
    vm = von_mises(X).max(axis=(0, 2))
    sa, sm = alternating_and_mean(X.max(axis=3), X.min(axis=3))
    return vm, safety_factor(sa, sm, se, sut, criterion, 400e6).min(axis=0)


@pytest.fixture(params=["with the group's nodes", "each history alone"])
def group_prepass(request, monkeypatch):
    """Both ways a group of many-coefficient histories is screened: after the group's
    pre-pass (its thresholds from a few nodes, the nodes that matter to none dropped), and
    with the group's thresholds withheld (0 and inf: every node stays), so that each
    history's own screen must find the exact values by itself; the pre-pass must never be
    what makes a case exact."""
    if request.param == "each history alone":
        from railcheck.fea.screening import groups

        def withheld(screen, C, *args, **kwargs):
            return np.zeros(C.shape[0]), np.full(C.shape[0], np.inf)

        monkeypatch.setattr(groups, "group_thresholds", withheld)
    return request.param


@pytest.mark.usefixtures("group_prepass")
@pytest.mark.slow  # 40 random examples, 6 s: the fast tier keeps the decoy and threshold cases
@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**31 - 1),
    k=st.sampled_from([2, 3, 4, 6, 12]),
    criterion=st.sampled_from(["goodman", "gerber", "asme-elliptic"]),
    spread=st.floats(0.0, 3.0),
)
def test_screened_peaks_equal_brute_force(seed, k, criterion, spread):
    """Random stress fields with a few hot nodes (as near a hole) and random histories,
    some offset from zero (a mean stress): the screened peak and fatigue factor equal
    every node x every step."""
    rng = np.random.default_rng(seed)
    n = 3000
    stress = rng.normal(size=(6, n, k)) * np.exp(spread * rng.normal(size=(1, n, 1)))
    mask = rng.random(n) > 0.1
    tip = rng.normal(size=(3, k))
    t = np.linspace(0, 2 * np.pi, 97)
    C = (
        rng.normal(size=(7, 1, k))
        + rng.normal(size=(7, 1, k)) * np.cos(t)[None, :, None]
        + rng.normal(size=(7, 1, k)) * np.sin(2 * t)[None, :, None]
    )
    screen = make_screen(stress, mask, tip, list(range(k)))
    vm, n_min = _brute(stress, mask, C, criterion=criterion)
    # vm^2 as a quadratic form c^T Q c sums k^2 terms that can cancel: a few eps of each term's size
    np.testing.assert_allclose(von_mises_peak(screen, C), vm, rtol=1e-11)
    np.testing.assert_allclose(fatigue_min(screen, C, 200e6, 750e6, criterion, 400e6), n_min, rtol=1e-12)
    np.testing.assert_allclose(tip_peak(screen, C), np.linalg.norm(C @ tip.T, axis=2).max(axis=1), rtol=1e-14)


@pytest.mark.usefixtures("group_prepass")
@pytest.mark.parametrize("k", [2, 8])
def test_a_pass_or_fail_question_gets_the_exact_factor_below_its_threshold(k):
    """``enough`` (a safe-speed search asks only whether the factor reaches it): below it
    the factor is exact; at or above it the result says so and is never below the exact
    one. Thresholds on both sides of every setting's exact factor."""
    rng = np.random.default_rng(7)
    n = 3000
    stress = rng.normal(size=(6, n, k)) * np.exp(2.0 * rng.normal(size=(1, n, 1)))
    mask = rng.random(n) > 0.1
    t = np.linspace(0, 2 * np.pi, 97)
    C = rng.normal(size=(9, 1, k)) + rng.normal(size=(9, 1, k)) * np.cos(t)[None, :, None]
    screen = make_screen(stress, mask, np.zeros((3, k)), list(range(k)))
    exact = fatigue_min(screen, C, 200e6, 750e6, "goodman", 400e6)
    for enough in np.quantile(exact, [0.0, 0.3, 0.7, 1.0]) * np.array([[0.999], [1.001]]):
        for e in enough:
            got = fatigue_min(screen, C, 200e6, 750e6, "goodman", 400e6, e)
            below = exact < e
            np.testing.assert_allclose(got[below], exact[below], rtol=1e-12)
            assert np.all(got[~below] >= e * (1 - 1e-9)) and np.all(got >= exact * (1 - 1e-12))


def test_unloaded_setting_has_zero_stress_and_infinite_fatigue_factor():
    rng = np.random.default_rng(1)
    stress = rng.normal(size=(6, 500, 2))
    screen = make_screen(stress, np.ones(500, bool), rng.normal(size=(3, 2)), [0, 1])
    C = np.zeros((2, 50, 2))
    C[1] = rng.normal(size=(50, 2))
    vm = von_mises_peak(screen, C)
    assert vm[0] == 0.0 and vm[1] > 0
    n = fatigue_min(screen, C, 200e6, 750e6, "goodman", None)
    assert np.isinf(n[0]) and np.isfinite(n[1])


def test_an_unloaded_many_coefficient_history_reads_no_node():
    """A history of zeros (k > 2, screened in its subspace) has zero stress and an
    infinite fatigue factor at once: its box is a point, which would keep every node for
    every step (6 x nodes x steps floats)."""
    rng = np.random.default_rng(1)
    stress = rng.normal(size=(6, 400, 5))
    screen = make_screen(stress, np.ones(400, bool), rng.normal(size=(3, 5)), list(range(5)))
    C = np.zeros((2, 200, 5))
    C[1] = rng.normal(size=(200, 5))
    vm, n = peak_and_fatigue(screen, C, 200e6, 750e6, "goodman", None)
    brute_vm, brute_n = _brute(stress, np.ones(400, bool), C)
    assert vm[0] == 0.0 and np.isinf(n[0])
    np.testing.assert_allclose(vm[1], brute_vm[1], rtol=1e-12)
    np.testing.assert_allclose(n[1], brute_n[1], rtol=1e-12)


@pytest.mark.parametrize("columns", [[0, 1], [2, 3]])
def test_screen_selects_columns(columns):
    rng = np.random.default_rng(2)
    stress = rng.normal(size=(6, 400, 4))
    C = rng.normal(size=(3, 40, 2))
    screen = make_screen(stress, np.ones(400, bool), np.zeros((3, 4)), columns)
    full = np.zeros((3, 40, 4))
    full[..., columns] = C
    vm, _ = _brute(stress, np.ones(400, bool), full)
    np.testing.assert_allclose(von_mises_peak(screen, C), vm, rtol=1e-12)


def test_the_screens_of_many_hole_pairs_hold_each_pairs_columns_at_the_verdict_nodes():
    """make_screens reads the fields in slabs of nodes for every key at once: each screen
    holds exactly its columns (any order, repeated) at the verdict nodes, across slab
    boundaries, as plain indexing gives, and its tip's columns."""
    from railcheck.fea.screening import make_screens
    from railcheck.fea.screening.tuning import GATHER_NODES

    rng = np.random.default_rng(5)
    n = 3 * GATHER_NODES + 7
    stress, tip = rng.normal(size=(6, n, 9)), rng.normal(size=(3, 9))
    mask = rng.random(n) < 0.8
    columns = {"a": [0, 1, 2], "b": [8, 3, 3, 5], "c": list(range(9))}
    screens = make_screens(stress, mask, {key: tip + i for i, key in enumerate(columns)}, columns)
    for i, (key, cols) in enumerate(columns.items()):
        np.testing.assert_array_equal(screens[key].stress, stress[:, mask][:, :, cols])
        np.testing.assert_array_equal(screens[key].tip, (tip + i)[:, cols])
        assert screens[key].stress.flags.c_contiguous


def test_the_screens_of_freshly_solved_fields_are_gathered_without_copying_them_whole():
    """A solve returns the fields as a transposed view of node-major columns (not
    C-contiguous). The screens gathered from that layout equal those of a C-contiguous
    copy bit for bit, and no slab's gather copies the whole array: the peak of memory
    allocated while gathering them is within half the fields' size of the contiguous
    gather's (np.take of such an array copies it whole, once per slab)."""
    import tracemalloc

    from railcheck.fea.screening import make_screens
    from railcheck.fea.screening.tuning import GATHER_NODES

    rng = np.random.default_rng(11)
    n, cases = 4 * GATHER_NODES + 3, 60
    fields = np.asfortranarray(rng.normal(size=(n, 6 * cases))).reshape(n, 6, cases).transpose(1, 0, 2)
    assert not fields.flags.c_contiguous  # the layout of railcheck.fea.stress.recover_stress
    contiguous = np.ascontiguousarray(fields)
    mask, tips = rng.random(n) < 0.9, {"a": np.zeros((3, cases)), "b": np.ones((3, cases))}
    columns = {"a": [0, 5, 7], "b": list(range(0, cases, 3))}

    def gathered(stress):
        tracemalloc.start()
        try:
            return make_screens(stress, mask, tips, columns), tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()

    (expected, base), (screens, peak) = gathered(contiguous), gathered(fields)
    for key in columns:
        np.testing.assert_array_equal(screens[key].stress, expected[key].stress)
    assert peak < base + fields.nbytes // 2, f"{peak - base} bytes more than a gather of {fields.nbytes} contiguous bytes"


@pytest.mark.usefixtures("group_prepass")
@pytest.mark.parametrize("k", [2, 3])
def test_screens_stay_exact_when_the_largest_nodes_are_decoys(k):
    """The screens evaluate the nodes with the largest bounds first, then prune the rest
    with those bounds. Here the 300 nodes with the largest bounds are decoys: huge stress
    on a coefficient the history barely uses. The true peak and the true lowest fatigue
    factor lie elsewhere, so only correct bounds find them (a bound too tight loses them,
    which brute force shows)."""
    rng = np.random.default_rng(7)
    n = 2000
    stress = rng.normal(size=(6, n, k))
    decoys = rng.choice(n, 300, replace=False)
    stress[:, decoys, :] *= 1e-3
    stress[:, decoys, k - 1] = rng.normal(size=(6, 300)) * 1e3
    t = np.linspace(0, 2 * np.pi, 181)
    C = np.zeros((3, t.size, k))
    C[..., 0] = 200 * np.cos(t)[None] + np.array([[0.0], [50.0], [-80.0]])
    if k == 3:
        C[..., 1] = 120 * np.sin(2 * t)[None]
    C[..., k - 1] = 1e-4 * np.sin(t)[None]  # the decoys' coefficient: barely used
    mask = np.ones(n, bool)
    screen = make_screen(stress, mask, rng.normal(size=(3, k)), list(range(k)))
    # the largest stress per unit coefficient is all decoys (the screen orders its nodes in
    # coefficients scaled by each one's largest stress per unit, where they need not lead)
    from railcheck.fea.superpose import VM_QUADRATIC

    lam = np.linalg.eigvalsh(np.einsum("cnk,cd,dnl->nkl", stress, VM_QUADRATIC, stress))[:, -1]
    assert set(np.argsort(-lam)[:64]) <= set(decoys)
    vm, n_min = _brute(stress, mask, C)
    np.testing.assert_allclose(von_mises_peak(screen, C), vm, rtol=1e-12)
    np.testing.assert_allclose(fatigue_min(screen, C, 200e6, 750e6, "goodman", None), n_min, rtol=1e-12)


def test_hull_steps_keep_every_result():
    """Reducing each history to its hull's vertices (padded by repetition) leaves the peak,
    the fatigue factor and the tip unchanged, for histories of different hull sizes."""
    from railcheck.fea.screening import hull_steps

    rng = np.random.default_rng(8)
    stress = rng.normal(size=(6, 800, 2))
    screen = make_screen(stress, np.ones(800, bool), rng.normal(size=(3, 2)), [0, 1])
    t = np.linspace(0, 2 * np.pi, 241)
    C = np.stack(
        [
            np.column_stack([np.cos(t), np.sin(t)]),  # many vertices
            np.column_stack([np.cos(t) + 0.3 * np.cos(5 * t), 0.5 * np.sin(t)]),
            np.column_stack([np.sign(np.cos(t)), np.sign(np.sin(t))]),  # four corners
        ]
    )
    H = hull_steps(C)
    assert H.shape[0] == 3 and H.shape[1] < t.size
    np.testing.assert_allclose(von_mises_peak(screen, H), von_mises_peak(screen, C), rtol=1e-12)
    np.testing.assert_allclose(
        fatigue_min(screen, H, 200e6, 750e6, "gerber", None),
        fatigue_min(screen, C, 200e6, 750e6, "gerber", None),
        rtol=1e-12,
    )
    np.testing.assert_allclose(tip_peak(screen, H), tip_peak(screen, C), rtol=1e-12)
    many = rng.normal(size=(2, 240, 5))  # beyond qhull's dimensions every step stays, uncopied
    assert hull_steps(many) is many


@pytest.mark.parametrize("shape", [(1, 9, 3), (4, 720, 8), (3, 50, 2, 6)])
def test_steps_of_paths_equal_take_along_axis(shape):
    """The one gather of the screens' steps (whole rows of the flattened paths) picks each
    path's own steps, as take_along_axis does, for one path, many, and rows of any shape."""
    from railcheck.fea.screening import steps_of

    rng = np.random.default_rng(3)
    a = rng.normal(size=shape)
    index = np.sort(rng.integers(0, shape[1], size=(shape[0], 7)), axis=1)
    expected = np.take_along_axis(a, index.reshape(index.shape + (1,) * (a.ndim - 2)), axis=1)
    np.testing.assert_array_equal(steps_of(a, index), expected)


@pytest.mark.usefixtures("group_prepass")
def test_a_spike_between_sampled_steps_is_not_lost():
    """The screens of three or more coefficients read some steps (spaced along the history's
    path) in its principal subspace and bound the steps between (their distance from a
    read step's). Here a one-step spike on the third coefficient (never every 8th step:
    a uniform reading would miss it), and the
    nodes it loads most hold the true minimum only because of it; decoys (huge stress on a
    coefficient the history barely uses) take the screen's first exact evaluations. The
    minimum and the peak still equal brute force over every step."""
    rng = np.random.default_rng(11)
    n, T, k = 1500, 400, 4
    stress = rng.normal(size=(6, n, k))
    stress[:, :, 3] *= 1e-3
    decoys = rng.choice(n, 300, replace=False)
    stress[:, decoys, 3] = rng.normal(size=(6, 300)) * 1e4
    spiked = rng.choice(np.setdiff1d(np.arange(n), decoys), 40, replace=False)
    stress[:, spiked, 2] *= 12.0
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    C = np.zeros((2, T, k))
    C[..., 0] = 150 * np.cos(t)[None] + np.array([[0.0], [40.0]])
    C[..., 1] = 90 * np.sin(3 * t)[None]
    C[:, 100 * np.arange(1, 4) + 3, 2] = 60.0  # steps 103, 203, 303: never sampled (every 8th)
    C[..., 3] = 1e-6 * np.sin(t)[None]  # the decoys' coefficient: barely used
    mask = np.ones(n, bool)
    screen = make_screen(stress, mask, rng.normal(size=(3, k)), list(range(k)))
    vm, n_min = _brute(stress, mask, C)
    assert np.all(_brute(stress, mask, C[:, ::8])[1] > n_min * 1.05)  # the spike sets the minimum
    np.testing.assert_allclose(fatigue_min(screen, C, 200e6, 750e6, "goodman", 400e6), n_min, rtol=1e-12)
    np.testing.assert_allclose(von_mises_peak(screen, C), vm, rtol=1e-12)


@pytest.mark.usefixtures("group_prepass")
def test_stress_outside_the_history_s_principal_subspace_is_not_lost():
    """A history of twelve coefficients that moves in four of them, with a one-step kick
    in the other eight (too little of the history's energy to be a principal direction):
    the screens read the nodes in the four-dimensional principal subspace and bound the
    rest by the residual's size. Here the nodes that hold the true peak and the true lowest
    factor carry stress only on the eight kicked coefficients, so their values in the
    subspace are nearly zero and only the residual's bound keeps them: the results still
    equal every node x every step."""
    rng = np.random.default_rng(12)
    n, T, k = 2000, 240, 12
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    C = np.zeros((2, T, k))
    for j in range(4):
        C[..., j] = 100 * np.cos((j + 1) * t + j)[None] + np.array([[0.0], [30.0 * j]])
    C[:, 101, 4:] = rng.normal(size=(2, k - 4)) * 0.1  # the kick, between sampled steps
    stress = rng.normal(size=(6, n, k))
    stress[:, :, 4:] *= 1e-3
    hidden = rng.choice(n, 30, replace=False)
    stress[:, hidden, :4] *= 1e-3
    stress[:, hidden, 4:] = rng.normal(size=(6, 30, k - 4)) * 3e3
    mask = np.ones(n, bool)
    screen = make_screen(stress, mask, rng.normal(size=(3, k)), list(range(k)))
    vm, n_min = _brute(stress, mask, C)
    for c in C:  # the hidden nodes govern both
        X = np.tensordot(stress, c, axes=([2], [1]))
        assert np.argmax(von_mises(X).max(axis=1)) in hidden
        sa, sm = alternating_and_mean(X.max(axis=2), X.min(axis=2))
        assert np.argmin(safety_factor(sa, sm, 200e6, 750e6, "goodman")) in hidden
    np.testing.assert_allclose(von_mises_peak(screen, C), vm, rtol=1e-12)
    np.testing.assert_allclose(fatigue_min(screen, C, 200e6, 750e6, "goodman", None), n_min, rtol=1e-12)
    both = peak_and_fatigue(screen, C, 200e6, 750e6, "goodman", None)  # the bounds computed once for both
    np.testing.assert_allclose(both[0], vm, rtol=1e-12)
    np.testing.assert_allclose(both[1], n_min, rtol=1e-12)


def _kicked_rank8(harmonic: float, mean: float, kick: float):
    """(stress (6, 2000, 9), C (1, 1440, 9), hidden nodes, screen): a history of nine
    directions (seven harmonics, a constant, a one-step kick) that its screen reads in
    rank 8 with the kick as the residual; ordinary nodes carry ``harmonic`` x the
    harmonics and ``mean`` x the constant, 20 hidden nodes ``kick`` x the kicked
    coefficient only (so their box value is nearly zero)."""
    from railcheck.fea import screening

    rng = np.random.default_rng(5)
    n, T, k = 2000, 1440, 9
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    C = np.zeros((1, T, k))
    for j in range(7):
        C[0, :, j] = np.cos((j + 1) * t + j)
    C[0, :, 7] = 1.0  # a constant: the mean stress
    C[0, 77, 8] = 1.0  # a one-step kick
    stress = np.zeros((6, n, k))
    stress[:, :, :7] = rng.normal(size=(6, n, 7)) * harmonic
    stress[:, :, 7] = rng.normal(size=(6, n)) * mean
    hidden = rng.choice(n, 20, replace=False)
    stress[:, hidden, :] = 0.0
    stress[:, hidden, 8] = rng.normal(size=(6, 20)) * kick
    screen = make_screen(stress, np.ones(n, bool), np.zeros((3, k)), list(range(k)))
    sub = screening.principal_subspace(C[0] * screen.scale)
    assert sub.P.shape[1] == screening.MAX_RANK and sub.eps > 0.5 * np.linalg.norm(C[0] * screen.scale, axis=1).max()
    return stress, C, hidden, screen


@pytest.mark.usefixtures("group_prepass")
def test_the_box_keeps_nodes_loaded_only_outside_the_subspace():
    """The box screen (every node, before any step is read) bounds each component by its
    value over the box of the subspace coordinates plus the residual's share. In a rank-8
    screen whose residual is a one-step kick, the nodes that hold the lowest fatigue factor
    carry stress only on the kicked coefficient, so their box value is nearly zero, and they
    do not hold the von Mises peak (which would keep them for it); only the residual's share
    of the box keeps them. Planting ``reach`` without it gives 65.8 instead of 56.0."""
    stress, C, hidden, screen = _kicked_rank8(harmonic=0.05, mean=1.1, kick=1.0)
    mask = np.ones(stress.shape[1], bool)
    vm, n_min = _brute(stress, mask, C, se=200.0, sut=750.0)
    X = np.tensordot(stress, C[0], axes=([2], [1]))
    sa, sm = alternating_and_mean(X.max(axis=2), X.min(axis=2))
    assert np.argmin(safety_factor(sa, sm, 200.0, 750.0, "goodman")) in hidden
    assert np.argmax(von_mises(X).max(axis=1)) not in hidden
    peak, factor = peak_and_fatigue(screen, C, 200.0, 750.0, "goodman", 400.0)
    np.testing.assert_allclose(peak, vm, rtol=1e-12)
    np.testing.assert_allclose(factor, n_min, rtol=1e-12)


@pytest.mark.usefixtures("group_prepass")
def test_the_box_keeps_a_peak_loaded_only_outside_the_subspace():
    """The von Mises peak alone (as the sweep reads a quasi-static peak beside the dynamic
    one): the nodes that hold it carry stress only on a one-step kick outside a rank-8
    subspace, so only the box's residual term in its von Mises bound keeps them (planting
    the bound without it gives 2.138, the next node's peak, instead of 2.297)."""
    stress, C, hidden, screen = _kicked_rank8(harmonic=0.1, mean=0.1, kick=0.4)
    vm, _ = _brute(stress, np.ones(stress.shape[1], bool), C)
    X = np.tensordot(stress, C[0], axes=([2], [1]))
    assert np.argmax(von_mises(X).max(axis=1)) in hidden
    np.testing.assert_allclose(von_mises_peak(screen, C), vm, rtol=1e-12)


@pytest.mark.usefixtures("group_prepass")
def test_the_box_keeps_a_fatigue_minimum_that_the_peak_does_not_hold():
    """300 nodes under a mean stress only hold the von Mises peak (and fill the nodes read
    first); 20 under an alternating stress only hold the lowest fatigue factor, and their
    von Mises bound is below the peak, so only the box's reach over the coordinates'
    ranges keeps them for the fatigue minimum (planting the reach without the ranges,
    the residual's share alone, gives 106.36 instead of 105.17)."""
    rng = np.random.default_rng(8)
    n, T, k = 2000, 360, 4
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    C = np.zeros((1, T, k))
    C[0, :, 0], C[0, :, 1], C[0, :, 2] = np.cos(t), np.sin(t), 1.0  # a circle and a mean
    C[0, :, 3] = 0.3 * np.cos(2 * t)
    stress = rng.normal(size=(6, n, k)) * 0.02
    mean = rng.choice(n, 300, replace=False)
    stress[:, mean, :] = 0.0
    stress[:, mean, 2] = rng.normal(size=(6, 300))
    alternating = rng.choice(np.setdiff1d(np.arange(n), mean), 20, replace=False)
    stress[:, alternating, :] = 0.0
    stress[:, alternating, :2] = rng.normal(size=(6, 20, 2)) * 0.35
    mask = np.ones(n, bool)
    screen = make_screen(stress, mask, np.zeros((3, k)), list(range(k)))
    X = np.tensordot(stress, C[0], axes=([2], [1]))
    sa, sm = alternating_and_mean(X.max(axis=2), X.min(axis=2))
    assert np.argmax(von_mises(X).max(axis=1)) in mean
    assert np.argmin(safety_factor(sa, sm, 200.0, 750.0, "goodman")) in alternating
    vm, n_min = _brute(stress, mask, C, se=200.0, sut=750.0)
    peak, factor = peak_and_fatigue(screen, C, 200.0, 750.0, "goodman", 400.0)
    np.testing.assert_allclose(peak, vm, rtol=1e-12)
    np.testing.assert_allclose(factor, n_min, rtol=1e-12)


@pytest.mark.parametrize("rotated", [False, True])
def test_the_coefficient_box_holds_every_step_and_is_reached_at_its_corners(rotated):
    """:class:`railcheck.fea.screening.CoefficientBox`, in the coefficients themselves or in a
    rotated basis of the scaled coefficients, bounds every node's components and von
    Mises over every step of each history of a group (random fields, histories with a
    mean, harmonics and a kick), though it reads its matrices in float32; for a history
    that visits every corner of its box its component bounds are the exact extremes to
    within the float32 widening (the box is no looser than its definition), and so is the
    von Mises bound of a node with one stress component (uniaxial: the interval bound is
    exact)."""
    import itertools

    from railcheck.fea.screening import BOX_WIDENING, CoefficientBox

    rng = np.random.default_rng(21)
    n, k, T = 500, 3, 200
    stress = rng.normal(size=(6, n, k)) * np.exp(rng.normal(size=(1, n, 1)))
    stress[:, 7] = 0.0  # an unstressed node
    stress[1:, 9] = 0.0  # a uniaxial node: sigma_xx only
    stress[:, 11] = 0.0
    stress[4, 11] = rng.normal(size=k)  # pure shear yz
    scale = np.array([1.0, 40.0, 0.2])
    basis = np.linalg.qr(rng.normal(size=(k, k)))[0] if rotated else None
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    C = rng.normal(size=(4, 1, k)) * 5 + rng.normal(size=(4, 1, k)) * np.cos(t)[None, :, None]
    C[:, 50] += rng.normal(size=(4, k)) * 3  # a kick
    corners = np.array(list(itertools.product([-1.0, 1.0], repeat=k))) * [2.0, 0.5, 1.0] + [1.0, -3.0, 0.0]
    if rotated:  # the corners of a box in the basis coordinates d: c = B d / scale
        corners = corners @ basis.T / scale
    C = np.concatenate([C, np.pad(corners, ((0, T - corners.shape[0]), (0, 0)), mode="edge")[None]])
    box = CoefficientBox(np.ascontiguousarray(stress), scale, basis)
    lo, hi, taken = box.ranges_and_taken(C)
    with_taken = [box.at_nodes(b, np.arange(n), t) for b, t in zip(box.box_of(lo, hi), taken)]
    for c, b, bt in zip(C, box.bounds(C), with_taken):
        X = np.tensordot(stress, c, axes=([2], [1]))  # (6, n, T)
        assert np.all(X.max(axis=2) <= b.high + b.slack) and np.all(X.min(axis=2) >= b.low - b.slack)
        assert np.all(von_mises(X).max(axis=1) <= b.von_mises_upper)
        np.testing.assert_array_equal(b.slack[:, 7], 0.0)
        # the values taken bound each midrange, more tightly than the box's centre and reach
        midrange = np.abs(0.5 * (X.max(axis=2) + X.min(axis=2)))
        assert np.all(midrange <= bt.mid_upper)
        assert bt.mid_upper.sum() < 0.9 * (np.abs(bt.high) + bt.slack).sum()
    near = 4 * BOX_WIDENING  # the corners: exact but for the float32 widening
    tol = near * np.abs(X).max(axis=2)  # each component's own magnitude
    assert np.all(np.abs(b.high + b.slack - X.max(axis=2)) <= tol)
    assert np.all(np.abs(b.low - b.slack - X.min(axis=2)) <= tol)
    np.testing.assert_allclose(b.von_mises_upper[[9, 11]], von_mises(X[:, [9, 11]]).max(axis=1), rtol=near)
    # a mean in every basis coordinate and a harmonic in one: the box is exact (one
    # coordinate moves) and the steps taken (a quarter period apart) reach each
    # component's extremes, so the midrange bound is its exact midrange (to float32)
    clean = rng.normal(size=(1, 1, k)) * 5 + np.array([3.0, 0.0, 0.0]) * np.cos(t)[None, :, None]
    if rotated:  # those basis coordinates' coefficients: c = B d / scale
        clean = clean @ basis.T / scale
    Xc = np.tensordot(stress, clean[0], axes=([2], [1]))
    lo, hi, taken = box.ranges_and_taken(clean)
    bc = box.at_nodes(box.box_of(lo, hi)[0], np.arange(n), taken[0])
    midrange = np.abs(0.5 * (Xc.max(axis=2) + Xc.min(axis=2)))
    np.testing.assert_allclose(bc.mid_upper, midrange, rtol=1e-4, atol=1e-4 * np.abs(Xc).max())


@pytest.mark.parametrize("rotated", [False, True])
def test_the_float32_box_stays_a_bound_where_its_rounding_matters(rotated):
    """The float32 :class:`railcheck.fea.screening.CoefficientBox` is still a bound where
    float32 rounding is as large as the quantity bounded: coefficients of large mean whose
    fields nearly cancel (a component of 1e-4 of its terms), and one-component nodes whose
    bounds a corner-visiting history reaches exactly. Every step's components, von Mises
    and every node's fatigue factor (from the box, as the sweep reads it) stay on the safe
    side of the box, at every node, bit for bit (no tolerance)."""
    import itertools

    from railcheck.fea.screening import CoefficientBox, fatigue_bounds

    rng = np.random.default_rng(5)
    n, k = 4000, 3
    base = rng.normal(size=(6, n, 1)) * np.exp(rng.normal(size=(1, n, 1)))
    stress = np.concatenate([base, -base * (1.0 + 1e-4 * rng.normal(size=(6, n, 1))), rng.normal(size=(6, n, 1))], axis=2)
    stress[1:, : n // 2] = 0.0  # half the nodes: sigma_xx only, where the box is reached
    scale = np.array([1.0, 1.0, 1.0])
    basis = np.linalg.qr(rng.normal(size=(k, k)))[0] if rotated else None
    corners = np.array(list(itertools.product([-1.0, 1.0], repeat=k))) * [3.0, 2.0, 1e-3]
    C = (corners + [1e4, 1e4, 0.0])[None]  # a large mean, nearly cancelling
    C = np.concatenate([C, rng.normal(size=(3, 8, k)) * [2.0, 2.0, 1e-3] + [1e4, 1e4, 0.0]])
    if rotated:
        C = C @ basis @ basis.T  # the same points; the box is taken in the rotated basis
    box = CoefficientBox(np.ascontiguousarray(stress), scale, basis)
    factor = lambda sa, sm: safety_factor(sa, sm, 2.6e8, 7.5e8, "goodman")  # noqa: E731
    lo, hi, taken = box.ranges_and_taken(C)
    every = np.arange(n)
    with_taken = [box.at_nodes(b, every, t) for b, t in zip(box.box_of(lo, hi), taken)]  # midranges by values taken too
    # the fatigue bounds of the boxes with the midranges bounded by the steps' means, as the sweep reads them
    by_mean = _fatigue_by_mean(box, C, lo, hi)
    midrange_box = _midrange_images(box, C, lo, hi)
    for c, b, bt, bm, (mid_lo, mid_hi) in zip(C, box.bounds(C), with_taken, by_mean, midrange_box):
        X = np.tensordot(stress, c, axes=([2], [1]))  # (6, n, T) float64
        exact = factor(*alternating_and_mean(X.max(axis=2), X.min(axis=2)))
        midrange = np.abs(0.5 * (X.max(axis=2) + X.min(axis=2)))
        assert np.all(midrange <= bt.mid_upper)
        signed = 0.5 * (X.max(axis=2) + X.min(axis=2))
        assert np.all(mid_lo <= signed) and np.all(signed <= mid_hi)  # in the midrange box's image, bit for bit
        assert np.all(factor(*bm) <= exact)
        for bounds in (b, bt):
            assert np.all(X.max(axis=2) <= bounds.high + bounds.slack) and np.all(X.min(axis=2) >= bounds.low - bounds.slack)
            assert np.all(von_mises(X).max(axis=1) <= bounds.von_mises_upper)
            assert np.all(factor(*fatigue_bounds(bounds)) <= exact)


def _fatigue_by_mean(box, C, lo, hi):
    """(sa, sm) bounds of each history of ``C`` from its box with its midranges bounded by
    its steps' mean (:func:`railcheck.fea.screening.fatigue_bounds_by_midranges`), as
    :func:`railcheck.fea.screening.groups.screened_group` reads them: one (sa, sm) per history."""
    from railcheck.fea.screening import SampledBounds, fatigue_bounds_by_midranges, midrange_box

    vm, mid, reach = box.box_arrays(lo, hi)
    b = SampledBounds.box(vm, mid.transpose(1, 0, 2), reach.transpose(1, 0, 2))
    m_mid, m_reach = box.products(*midrange_box(lo, hi, box.coordinates(C).mean(axis=1)))
    sa, sm = fatigue_bounds_by_midranges(b, m_mid.transpose(1, 0, 2), m_reach.transpose(1, 0, 2))
    return list(zip(sa, sm))


def _midrange_images(box, C, lo, hi):
    """(lo, hi) (6, n) per history: the image of its midrange box (the float32 box's
    component intervals, widened as :func:`railcheck.fea.screening.fatigue_bounds` widens them)."""
    from railcheck.fea.screening import FLOAT32_EPS, midrange_box

    mid, reach = box.products(*midrange_box(lo, hi, box.coordinates(C).mean(axis=1)))
    spread = reach + np.float32(4.0 * FLOAT32_EPS) * (2 * np.abs(mid) + reach)
    return list(zip(mid - spread, mid + spread))


def test_the_midrange_box_holds_a_swing_s_midrange_at_its_mean_within_half_its_reach():
    """:func:`railcheck.fea.screening.midrange_box`: a harmonic about its mean (a link's
    fully reversed swing) has its midrange at the mean; the box of the coordinates'
    ranges only says it lies within ``|mid| + reach``, the midrange box within half the
    reach of the mean, and it holds every component's midrange of random histories (a
    mean, harmonics and a kick)."""
    from railcheck.fea.screening import CoefficientBox, midrange_box

    rng = np.random.default_rng(8)
    n, k, T = 300, 4, 360
    stress = rng.normal(size=(6, n, k))
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    swing = (rng.normal(size=(1, k)) * 0.2 + np.array([3.0, 0.0, 0.0, 0.0]) * np.cos(t)[:, None])[None]
    noisy = rng.normal(size=(5, 1, k)) + rng.normal(size=(5, 1, k)) * np.cos(t[None, :, None] + rng.uniform(0, 6, (5, 1, k)))
    noisy[:, 90] += rng.normal(size=(5, k)) * 2.0
    C = np.concatenate([swing, noisy])
    box = CoefficientBox(np.ascontiguousarray(stress), np.ones(k), None)
    lo, hi = box.ranges(C)
    mid, reach = box.products(*midrange_box(lo, hi, C.mean(axis=1)))
    box_mid, box_reach = box.products(lo, hi)
    X = np.tensordot(stress, C, axes=([2], [2]))  # (6, n, S, T)
    midrange, half = 0.5 * (X.max(axis=3) + X.min(axis=3)), 0.5 * (X.max(axis=3) - X.min(axis=3))  # (6, n, S)
    midrange, half = midrange.transpose(2, 0, 1), half.transpose(2, 0, 1)  # (S, 6, n)
    assert np.all(np.abs(midrange - mid) <= reach * (1 + 1e-5))  # every history, every component
    # the swing: at its mean, within half its reach (the box: anywhere within |mid| + reach)
    np.testing.assert_allclose(mid[0], midrange[0], atol=1e-5 * np.abs(X).max())
    np.testing.assert_allclose(reach[0], 0.5 * half[0], rtol=1e-4, atol=1e-5 * np.abs(X).max())
    np.testing.assert_allclose(box_reach[0], half[0], rtol=1e-4, atol=1e-5 * np.abs(X).max())


def test_the_von_mises_interval_bound_holds_inside_its_intervals_and_in_float32():
    """:func:`railcheck.fea.screening.von_mises_interval_bound`: no stress whose components lie
    in the intervals (random points and every corner) exceeds it; a single component's
    bound is its largest magnitude; computed in float32 it is not below the float64 value
    of the same intervals (its widening covers its own rounding)."""
    import itertools

    from railcheck.fea.screening import von_mises_interval_bound

    rng = np.random.default_rng(8)
    mid = rng.normal(size=(6, 2000)) * np.exp(rng.normal(size=(1, 2000)))
    reach = np.abs(rng.normal(size=(6, 2000))) * np.exp(rng.normal(size=(1, 2000)))
    bound = von_mises_interval_bound(mid, reach)
    for signs in itertools.product([-1.0, 1.0], repeat=6):
        assert np.all(von_mises(mid + np.array(signs)[:, None] * reach) <= bound)
    inside = mid[:, None] + reach[:, None] * rng.uniform(-1.0, 1.0, size=(6, 50, 2000))
    assert np.all(von_mises(inside) <= bound)
    single = np.zeros_like(mid)
    single[2] = mid[2]
    lone = np.zeros_like(reach)
    lone[2] = reach[2]
    np.testing.assert_allclose(von_mises_interval_bound(single, lone), np.abs(mid[2]) + reach[2], rtol=2e-5)
    m32, r32 = mid.astype(np.float32), reach.astype(np.float32)
    m, r = m32.astype(float), r32.astype(float)  # the float32 intervals, evaluated in float64 by hand
    normal = sum((np.abs(m[i] - m[j]) + r[i] + r[j]) ** 2 for i, j in ((0, 1), (1, 2), (2, 0)))
    exact = np.sqrt(0.5 * normal + 3.0 * sum((np.abs(m[i]) + r[i]) ** 2 for i in (3, 4, 5)))
    assert np.all(von_mises_interval_bound(m32, r32) >= exact)


def test_the_von_mises_bound_over_component_intervals_holds_inside_them_and_in_float32():
    """:func:`railcheck.fea.screening.interval_von_mises` (the fatigue screens' bound of the
    alternating and midrange von Mises): no stress whose components lie in the intervals
    (random points and every corner) exceeds it; a single component's bound is its
    largest magnitude; same-signed normal intervals give less than their magnitudes
    added; computed in float32 it is not below the float64 value of the same intervals."""
    import itertools

    from railcheck.fea.screening import BOX_WIDENING, interval_von_mises, von_mises_interval_bound

    rng = np.random.default_rng(9)
    a, b = rng.normal(size=(2, 6, 2000)) * np.exp(rng.normal(size=(1, 1, 2000)))
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    bound = interval_von_mises(lo, hi)
    for corner in itertools.product([0, 1], repeat=6):
        assert np.all(von_mises(np.where(np.array(corner, bool)[:, None], hi, lo)) <= bound)
    inside = lo[:, None] + (hi - lo)[:, None] * rng.uniform(size=(6, 50, 2000))
    assert np.all(von_mises(inside) <= bound)
    assert np.all(interval_von_mises(None, np.abs(hi)) >= interval_von_mises(np.zeros_like(hi), np.abs(hi)) * (1 - 1e-15))
    single_lo, single_hi = np.zeros_like(lo), np.zeros_like(hi)
    single_lo[1], single_hi[1] = lo[1], hi[1]
    np.testing.assert_allclose(
        interval_von_mises(single_lo, single_hi), np.maximum(np.abs(lo[1]), np.abs(hi[1])), rtol=1e-15
    )
    same = abs(hi[0, 0]) * np.array([[1.0], [0.9], [1.1], [0], [0], [0]])  # nearly equal normal stresses
    assert interval_von_mises(0.99 * same, same)[0] < 0.2 * np.abs(same).sum()
    lo32, hi32 = lo.astype(np.float32), hi.astype(np.float32)
    assert np.all(interval_von_mises(lo32, hi32) >= interval_von_mises(lo32.astype(float), hi32.astype(float)))
    # symmetric intervals: the boxes' own form of the same bound (widened by BOX_WIDENING in any precision)
    symmetric = von_mises_interval_bound(0.5 * (lo + hi), 0.5 * (hi - lo))
    np.testing.assert_allclose(bound * (1.0 + BOX_WIDENING), symmetric, rtol=1e-12)


@pytest.mark.parametrize("box", [True, False])
def test_float32_fatigue_bounds_are_not_below_the_float64_bounds_of_the_same_values(box):
    """The group's box is read in float32. Near-hydrostatic stresses (normal components of
    1e8 Pa differing by 1e2, reaches of 10 Pa, below float32's spacing there) make the
    intervals' ends round by more than the von Mises they bound: the fatigue bounds in
    float32 stay at or above those of the same values in float64 (the ends widened by
    their own rounding)."""
    from railcheck.fea.screening import SampledBounds, fatigue_bounds

    rng = np.random.default_rng(11)
    n = 5000
    mid = np.zeros((6, n))
    mid[:3] = 1e8 * rng.choice([-1.0, 1.0], size=n) + 1e2 * rng.normal(size=(3, n))
    mid[3:] = 10.0 * rng.normal(size=(3, n))
    reach = 10.0 * np.abs(rng.normal(size=(6, n)))
    m32, r32 = mid.astype(np.float32), reach.astype(np.float32)
    vm = np.ones(n, dtype=np.float32)

    def bounds(m, r):
        return SampledBounds.box(vm, m, r) if box else SampledBounds(vm, vm, m, m - r, r)

    wide = fatigue_bounds(bounds(m32, r32))
    exact = fatigue_bounds(bounds(m32.astype(float), r32.astype(float)))
    for x, y in zip(wide, exact):
        assert np.all(x >= y)


def test_fatigue_bounds_of_a_box_equal_those_of_the_same_bounds_read_as_steps():
    """A box (:meth:`railcheck.fea.screening.SampledBounds.box`: no step read, ``high`` and
    ``low`` the same array) has the fatigue bounds of the same values given as separate
    sampled extremes: the box's shortcut (the half-range from 0) is only a shortcut, in
    float64 and float32."""
    from railcheck.fea.screening import SampledBounds, fatigue_bounds

    rng = np.random.default_rng(10)
    for dtype in (np.float64, np.float32):
        mid = (rng.normal(size=(6, 500)) * 1e8).astype(dtype)
        reach = (np.abs(rng.normal(size=(6, 500))) * 1e8).astype(dtype)
        vm = np.ones(500, dtype=dtype)
        for upper in (None, np.abs(mid) + 0.5 * reach):
            box = fatigue_bounds(SampledBounds.box(vm, mid, reach, upper))
            read = fatigue_bounds(SampledBounds(vm, vm, mid, mid.copy(), reach, upper))
            for x, y in zip(box, read):
                np.testing.assert_allclose(x, y, rtol=1e-6 if dtype == np.float32 else 1e-15)


def test_the_box_basis_follows_the_histories():
    """:func:`railcheck.fea.screening.box_basis`: a group whose 6 coefficients are 2 signals
    mixed (a rotating load seen through every coefficient) gets its principal axes;
    coefficients that move independently keep their own basis (None)."""
    from railcheck.fea.screening import box_basis

    rng = np.random.default_rng(4)
    stress = np.ascontiguousarray(rng.normal(size=(6, 1000, 6)))
    t = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    signals = np.stack([np.cos(t), np.sin(t)], axis=1)  # (T, 2)
    mixed = (signals @ rng.normal(size=(2, 6)))[None]
    assert box_basis(stress, np.ones(6), mixed) is not None
    independent = rng.uniform(-1.0, 1.0, size=(1, 360, 6))  # each coefficient on its own
    assert box_basis(stress, np.ones(6), independent) is None


@pytest.mark.usefixtures("group_prepass")
@pytest.mark.parametrize("loose_share", [0.0, 1.0])
def test_a_history_bounded_at_every_node_in_its_own_subspace_or_after_the_group_box_is_exact(monkeypatch, loose_share):
    """Both ways a history's nodes are screened: its own subspace's box at every node (the
    group's box kept too many: ``LOOSE_SHARE`` 0 forces it) or only at the nodes the
    group's box keeps (1 forces it); random fields with hot nodes and a group of histories
    with a mean, two harmonics and a kick: both equal every node x every step."""
    from railcheck.fea.screening import tuning

    monkeypatch.setattr(tuning, "LOOSE_SHARE", loose_share)
    rng = np.random.default_rng(31)
    n, k, T = 3000, 9, 240
    stress = rng.normal(size=(6, n, k)) * np.exp(1.5 * rng.normal(size=(1, n, 1)))
    mask = rng.random(n) > 0.1
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    C = (
        rng.normal(size=(5, 1, k))
        + rng.normal(size=(5, 1, k)) * np.cos(t)[None, :, None]
        + rng.normal(size=(5, 1, k)) * np.sin(3 * t)[None, :, None]
    )
    C[:, 17] += rng.normal(size=(5, k))
    screen = make_screen(stress, mask, np.zeros((3, k)), list(range(k)))
    vm, n_min = _brute(stress, mask, C)
    peak, factor = peak_and_fatigue(screen, C, 200e6, 750e6, "goodman", 400e6)
    np.testing.assert_allclose(peak, vm, rtol=1e-12)
    np.testing.assert_allclose(factor, n_min, rtol=1e-12)


@pytest.mark.parametrize("criterion", ["goodman", "gerber", "asme-elliptic"])
def test_a_group_keeps_the_fatigue_minimum_a_steady_load_holds(criterion):
    """Histories of very different sizes whose fatigue minima are held by their means (a
    steady load with a small swing; the swings' nodes elsewhere): each history's midrange
    box is scaled by its own fatigue threshold before the group's union
    (:func:`railcheck.fea.screening.passes.group_nodes` with the means), so every node that can hold
    a minimum is kept, and the screened results equal every node x every step."""
    from railcheck.fea.screening import CoefficientBox, box_basis

    rng = np.random.default_rng(17)
    n, k, T, S = 2500, 5, 240, 9
    stress = 0.05 * rng.normal(size=(6, n, k)) * np.exp(rng.normal(size=(1, n, 1)))
    # hot nodes: some loaded by a steady coefficient alone (the peaks), others by a steady
    # and an alternating one (the fatigue minima: more mean than swing, less peak)
    hot = rng.choice(n, size=80, replace=False)
    steady_row, swing_row = np.eye(k)[rng.integers(0, 2, 80)], np.eye(k)[rng.integers(2, k, 80)]
    weights = (
        np.where(np.arange(80) < 40, 1.3, 1.0)[:, None] * steady_row
        + np.where(np.arange(80) < 40, 0.0, 1.5)[:, None] * swing_row
    )
    stress[:, hot] += rng.normal(size=(6, 80, 1)) * weights[None]
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    steady = np.where(np.arange(k) < 2, 3.0, 0.05) * rng.uniform(0.5, 1.0, size=(S, 1, k))
    swing = np.where(np.arange(k) < 2, 0.1, 0.4) * rng.uniform(0.5, 1.0, size=(S, 1, k))
    C = (steady + swing * np.cos(t[None, :, None] + rng.uniform(0, 6, size=(S, 1, k)))) * 1e7
    C *= np.exp(rng.uniform(-4.0, 4.0, size=(S, 1, 1)))  # sizes over 3.5 decades
    screen = make_screen(stress, np.ones(n, bool), np.zeros((3, k)), list(range(k)))
    factor = lambda sa, sm: safety_factor(sa, sm, 2e8, 7.5e8, criterion, 4e8)  # noqa: E731
    X = np.tensordot(screen.stress, C, axes=([2], [2]))  # (6, n, S, T)
    sa, sm = alternating_and_mean(X.max(axis=3), X.min(axis=3))
    exact = factor(sa, sm)  # (n, S)
    minima = np.argmin(exact, axis=0)
    assert np.all(sm[minima, np.arange(S)] > sa[minima, np.arange(S)])  # more mean than swing
    if criterion != "asme-elliptic":  # (which weighs the mean by the yield strength: its minima are the peaks)
        assert np.mean(minima != np.argmax(von_mises(X).max(axis=2), axis=0)) > 0.5  # mostly not the peaks
    # the whole group, and each history alone (where von Mises's box is tight and keeps
    # only the peaks: the minima are kept by the fatigue bound alone)
    for part in [np.arange(S)] + [np.array([i]) for i in range(S)]:
        Cp = C[part]
        group = CoefficientBox(screen.stress, screen.scale, box_basis(screen.stress, screen.scale, Cp))
        lo, hi = group.ranges(Cp)
        low, top = group_thresholds(screen, Cp, group, lo, hi, factor)
        kept = group_nodes(group, lo, hi, low, top, factor, group.coordinates(Cp).mean(axis=1))
        needed = np.flatnonzero(np.any(exact[:, part] <= top, axis=1))
        assert np.isin(needed, kept).all()
    vm, n_min = _brute(stress, np.ones(n, bool), C, 2e8, 7.5e8, criterion)
    peak, least = peak_and_fatigue(screen, C, 2e8, 7.5e8, criterion, 4e8)
    np.testing.assert_allclose(peak, vm, rtol=1e-12)
    np.testing.assert_allclose(least, n_min, rtol=1e-12)


@pytest.mark.parametrize("criterion", ["goodman", "gerber", "asme-elliptic"])
def test_a_group_keeps_every_node_that_can_hold_a_history_s_peak_or_fatigue_minimum(criterion):
    """The group's pre-pass (:func:`railcheck.fea.screening.passes.group_thresholds`,
    :func:`railcheck.fea.screening.passes.group_nodes`): a part whose nodes are mostly cold, a few hot
    ones each loaded by a different coefficient, and histories of very different sizes
    (x0.05 to x20) and directions. Its thresholds are a lower bound of each peak and an
    upper bound of each fatigue minimum (every node x every step); every node that reaches
    a history's threshold (either criterion) is kept, and the cold ones are not."""
    from railcheck.fea.screening import CoefficientBox, box_basis

    rng = np.random.default_rng(12)
    n, k, T = 3000, 6, 240
    stress = 0.02 * rng.normal(size=(6, n, k)) * np.exp(rng.normal(size=(1, n, 1)))
    hot = rng.choice(n, size=60, replace=False)
    stress[:, hot] += (
        rng.normal(size=(6, 60, 1)) * np.eye(k)[rng.integers(0, k, 60)][None] * np.exp(rng.normal(size=(1, 60, 1)))
    )
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    # coefficients 0-2 steady (the peaks), 3-5 alternating (the fatigue minima, elsewhere)
    mean = np.where(np.arange(k) < 3, 4.0, 0.1) * rng.uniform(0.5, 1.0, size=(8, 1, k))
    swing = np.where(np.arange(k) < 3, 0.2, 2.5) * rng.uniform(0.5, 1.0, size=(8, 1, k))
    C = mean + swing * np.cos(t[None, :, None] + rng.uniform(0, 6, size=(8, 1, k)))
    C[:, 40] += 0.2 * rng.normal(size=(8, k))  # a kick
    C *= np.array([0.05, 0.3, 1.0, 1.0, 3.0, 5.0, 20.0, 1.0])[:, None, None]
    C[7] = 0.0  # an unloaded history in the group
    screen = make_screen(stress, np.ones(n, bool), np.zeros((3, k)), list(range(k)))
    factor = lambda sa, sm: safety_factor(sa, sm, 2e8, 7.5e8, criterion, 4e8)  # noqa: E731
    group = CoefficientBox(screen.stress, screen.scale, box_basis(screen.stress, screen.scale, C))
    lo, hi = group.ranges(C)
    low, top = group_thresholds(screen, C, group, lo, hi, factor)
    kept = group_nodes(group, lo, hi, low, top, factor)
    # the midranges bounded by the histories' means too (as the sweep reads them)
    by_mean = group_nodes(group, lo, hi, low, top, factor, group.coordinates(C).mean(axis=1))

    X = np.tensordot(screen.stress, C, axes=([2], [2]))  # (6, n, S, T)
    vm = von_mises(X).max(axis=2)  # (n, S)
    exact = factor(*alternating_and_mean(X.max(axis=3), X.min(axis=3)))  # (n, S)
    assert np.all(low <= vm.max(axis=0)) and np.all(low[:7] > 0)
    assert np.all(top >= exact.min(axis=0)) and np.all(np.isfinite(top[:7]))
    needed = np.flatnonzero(np.any((vm[:, :7] >= low[:7]) | (exact[:, :7] <= top[:7]), axis=1))
    assert np.isin(needed, kept).all() and np.isin(needed, by_mean).all()
    assert kept.size < 0.1 * n  # the cold nodes are dropped
    assert np.isin(by_mean, kept).all()
    if criterion == "goodman":  # linear in the midrange (Gerber's square makes it count less)
        assert by_mean.size < kept.size  # the means drop more
    peaks, minima = np.argmax(vm[:, :7], axis=0), np.argmin(exact[:, :7], axis=0)
    assert np.setdiff1d(minima, peaks).size  # fatigue keeps nodes of its own


def test_a_group_keeps_the_node_whose_bound_is_exactly_its_threshold():
    """Where the group's box is exact (one history visiting every corner of its box, nodes
    with one stress component) the node that holds the peak has a bound equal to its
    value, which is the threshold: it is kept (the pre-pass compares at 1, not beyond);
    so is the fatigue minimum's. :func:`railcheck.fea.screening.passes.box_union` holds every scaled box
    and no more."""
    import itertools

    from railcheck.fea.screening import CoefficientBox

    rng = np.random.default_rng(3)
    n, k = 400, 3
    stress = np.zeros((6, n, k))
    stress[0] = rng.normal(size=(n, k)) * np.exp(rng.normal(size=(n, 1)))  # sigma_xx only
    corners = np.array(list(itertools.product([-1.0, 1.0], repeat=k))) * [1.0, 0.5, 2.0] + [2.0, -1.0, 0.5]
    C = np.pad(corners, ((0, 40 - corners.shape[0]), (0, 0)), mode="edge")[None]
    screen = make_screen(stress, np.ones(n, bool), np.zeros((3, k)), list(range(k)))
    factor = lambda sa, sm: safety_factor(sa, sm, 2e8, 7.5e8, "goodman")  # noqa: E731
    group = CoefficientBox(screen.stress, screen.scale, None)
    lo, hi = group.ranges(C)
    low, top = group_thresholds(screen, C, group, lo, hi, factor)
    X = np.tensordot(screen.stress, C[0], axes=([2], [1]))  # (6, n, T)
    vm = von_mises(X).max(axis=1)
    exact = factor(*alternating_and_mean(X.max(axis=2), X.min(axis=2)))
    assert low[0] == pytest.approx(vm.max(), rel=1e-12) and top[0] == pytest.approx(exact.min(), rel=1e-12)
    assert np.argmax(vm) in group_nodes(group, lo, hi, low, top)  # the peak alone: its bound is exact
    assert np.argmin(exact) in group_nodes(group, lo, hi, low, top, factor)

    lo3, hi3 = rng.normal(size=(5, k)) - 2.0, rng.normal(size=(5, k)) + 2.0
    scale = rng.uniform(0.1, 3.0, size=5)
    ulo, uhi = box_union(lo3, hi3, scale)
    assert np.all(ulo <= lo3 * scale[:, None]) and np.all(uhi >= hi3 * scale[:, None])
    np.testing.assert_array_equal(ulo[0], (lo3 * scale[:, None]).min(axis=0))
    np.testing.assert_array_equal(uhi[0], (hi3 * scale[:, None]).max(axis=0))


def test_a_screen_and_its_box_restricted_to_some_nodes_are_the_same_at_those_nodes():
    """:func:`railcheck.fea.screening.passes.restricted_screen` and :meth:`CoefficientBox.restricted`: every
    array the per-history screen reads, and every box bound, at the kept nodes equals the
    whole part's at those nodes (in their order)."""
    from railcheck.fea.screening import CoefficientBox, box_basis

    rng = np.random.default_rng(9)
    n, k = 700, 5
    stress = rng.normal(size=(6, n, k)) * np.exp(rng.normal(size=(1, n, 1)))
    screen = make_screen(stress, rng.random(n) > 0.2, rng.normal(size=(3, k)), list(range(k)))
    nodes = np.sort(rng.choice(screen.stress.shape[1], 90, replace=False))
    part = restricted_screen(screen, nodes)
    np.testing.assert_array_equal(part.stress, screen.stress[:, nodes])
    np.testing.assert_array_equal(part.bounds.unit_rows, screen.bounds.unit_rows[:, nodes])
    np.testing.assert_array_equal(part.vm_norm, screen.vm_norm[nodes])
    for name in ("form_bound", "midrange_factor", "alternating_factor"):
        np.testing.assert_array_equal(getattr(part.bounds, name), getattr(screen.bounds, name)[nodes])
    np.testing.assert_array_equal(part.scale, screen.scale)
    np.testing.assert_array_equal(part.tip, screen.tip)
    C = rng.normal(size=(3, 50, k)) + rng.normal(size=(3, 1, k))
    box = CoefficientBox(screen.stress, screen.scale, box_basis(screen.stress, screen.scale, C))
    for whole, kept in zip(box.bounds(C), box.restricted(nodes).bounds(C)):
        np.testing.assert_array_equal(kept.von_mises_upper, whole.von_mises_upper[nodes])
        np.testing.assert_array_equal(kept.high, whole.high[:, nodes])
        np.testing.assert_array_equal(kept.slack, whole.slack[:, nodes])


@pytest.mark.usefixtures("group_prepass")
def test_stresses_beyond_float32_range_are_screened_exactly():
    """Absurd magnitudes: stresses of 1e40 Pa, beyond float32's range (3.4e38), where the
    float32 box overflows. Its bounds become infinite (never NaN), the nodes are kept and
    evaluated in float64: peak and fatigue factor equal every node x every step."""
    rng = np.random.default_rng(17)
    n, k, T = 1500, 6, 200
    stress = rng.normal(size=(6, n, k)) * np.exp(2.0 * rng.normal(size=(1, n, 1))) * 1e28
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    C = (rng.normal(size=(4, 1, k)) + rng.normal(size=(4, 1, k)) * np.cos(t)[None, :, None]) * 1e11
    mask = np.ones(n, bool)
    screen = make_screen(stress, mask, np.zeros((3, k)), list(range(k)))
    vm, n_min = _brute(stress, mask, C)
    assert np.all(np.isfinite(vm)) and vm.max() > 1e39
    peak, factor = peak_and_fatigue(screen, C, 200e6, 750e6, "goodman", 400e6)
    np.testing.assert_allclose(peak, vm, rtol=1e-12)
    np.testing.assert_allclose(factor, n_min, rtol=1e-12)
    C[1] *= 1e-3  # as one setting's two sources: the weaker's nodes pass no threshold of its set's
    vm, n_min = _brute(stress, mask, C)
    peak, factor = peak_and_fatigue(screen, C, 200e6, 750e6, "goodman", 400e6, sets=np.array([0, 0, 1, 1]))
    np.testing.assert_allclose(peak, np.repeat([vm[:2].max(), vm[2:].max()], 2), rtol=1e-12)
    np.testing.assert_allclose(factor, np.repeat([n_min[:2].min(), n_min[2:].min()], 2), rtol=1e-12)


def _chord_distance_brute(a, sampled):
    """Each step's distance from the segment between the read steps around it, one step
    at a time (no shared code with :func:`railcheck.fea.screening.chord_gaps`)."""
    out = np.zeros(a.shape[0])
    for t in range(a.shape[0]):
        i = min(int(np.searchsorted(sampled, t, side="right")) - 1, sampled.size - 2)
        p, q = a[sampled[i]], a[sampled[i + 1]]
        length2 = float(np.sum((q - p) ** 2))
        lam = 0.0 if length2 == 0 else min(1.0, max(0.0, float(np.sum((a[t] - p) * (q - p))) / length2))
        out[t] = float(np.linalg.norm(a[t] - (p + lam * (q - p))))
    return out


def test_the_subspace_bounds_hold_at_every_step_and_the_midrange_bounds_are_tight():
    """The bounds of one history in its principal subspace (:mod:`railcheck.fea.screening`):
    a history of eight harmonics (the subspace, rank 8 at most) and a small constant in a
    ninth coefficient, orthogonal to them and left out of the subspace (its residual). Every node's components,
    von Mises and midranges over every step lie within the box's and the samples' bounds.
    The midrange bounds rest on values the history takes (the box) and on the maximum and
    minimum lying within the slack above and below the sampled ones; at nodes loaded only
    on the constant, both are exact: the residual's share is the whole midrange (dropping
    the share from either bound fails here). Every step lies within ``delta`` of the chord
    between its read steps (measured one step at a time), and ``delta`` is within the
    tolerance the steps were refined to."""
    from railcheck.fea import screening

    rng = np.random.default_rng(31)
    n, T, k = 600, 720, 9
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    C = np.zeros((T, k))
    for j in range(8):
        C[:, j] = (3.0 - 0.3 * j) * np.cos((j + 1) * t + j)
    C[:, 8] = 0.3  # a constant beside the harmonics: outside the rank-8 subspace
    S = rng.normal(size=(6, n, k)) * np.exp(rng.normal(size=(1, n, 1)))
    only = np.arange(20)  # loaded only on the constant
    S[:, only, :8] = 0.0
    p = screening.project_history(S, C)
    assert p.sub.P.shape[1] == screening.MAX_RANK and p.sub.eps > 0
    X = np.tensordot(S, C, axes=([2], [1]))  # (6, n, T)
    high, low = X.max(axis=2), X.min(axis=2)
    midrange = 0.5 * (high + low)
    tol = 1e-12 * np.abs(X).max()
    box = screening.box_bounds(p.SP, p.norms, p.vm_norm, p.sub)
    read = screening.sampled_bounds(p.SP, p.norms, p.vm_norm, p.sub)
    for b in (box, read):
        assert np.all(high <= b.high + b.slack + tol) and np.all(low >= b.low - b.slack - tol)
        assert np.all(von_mises(X).max(axis=1) <= b.von_mises_upper * (1 + 1e-12))
        assert np.all(np.abs(midrange) <= b.mid_upper + tol)
        np.testing.assert_allclose(b.mid_upper[:, only], np.abs(midrange[:, only]), rtol=1e-9)
    ordinary = np.setdiff1d(np.arange(n), only)
    loose = np.abs(0.5 * (box.high + box.low)) + box.slack  # the box's bound without the taken values
    assert box.mid_upper[:, ordinary].sum() < 0.8 * loose[:, ordinary].sum()
    gaps = _chord_distance_brute(p.sub.a, p.sub.sampled)
    assert gaps.max() <= p.sub.delta * (1 + 1e-9) + 1e-12
    assert p.sub.delta <= max(p.sub.eps, screening.CHORD_SHARE * np.linalg.norm(C * screening.column_scale(S), axis=1).max())
    assert p.sub.sampled.size < 90  # fewer steps than the evenly spaced reading it replaced


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_subspace_bounds_hold_against_the_worst_residual_on_a_jagged_path(seed):
    """The box's and the samples' bounds (:func:`railcheck.fea.screening.box_bounds`,
    :func:`~railcheck.fea.screening.sampled_bounds`) against the worst a residual of size
    ``eps`` can do: each component carries its full share ``norms * eps`` with a fixed
    sign at every step, on a random-walk path with a mean (steps that run back past
    their chords' ends, components with midranges far from zero, either sign). Every
    component's maximum, minimum and midrange over every step lie within the bounds, and
    every step lies within ``delta`` of the segment between its read steps."""
    from railcheck.fea import screening

    rng = np.random.default_rng(seed)
    n, T, r = 400, 720, 5
    a = np.cumsum(rng.normal(size=(T, r)), axis=0) + rng.normal(size=r) * 30.0
    SP = rng.normal(size=(6, n, r)) * np.exp(rng.normal(size=(1, n, 1)))
    norms = np.abs(rng.normal(size=(6, n))) * 5.0
    eps = 1.0
    first = screening.path_samples(a, screening.FIRST_SAMPLES)
    sampled, delta = screening.refined_samples(a, 0.5, first)
    sub = screening.Subspace(np.eye(r), a, eps, sampled, delta, screening.touched_steps(a, first))
    sign = rng.choice([-1.0, 1.0], size=(6, n))
    X = np.einsum("jnr,tr->jnt", SP, a) + (sign * norms * eps)[..., None]  # the worst residual
    high, low = X.max(axis=2), X.min(axis=2)
    tol = 1e-12 * np.abs(X).max()
    vm_norm = np.full(n, np.inf)  # von Mises is not asked here
    for b in (screening.box_bounds(SP, norms, vm_norm, sub), screening.sampled_bounds(SP, norms, vm_norm, sub)):
        assert np.all(high <= b.high + b.slack + tol) and np.all(low >= b.low - b.slack - tol)
        assert np.all(np.abs(0.5 * (high + low)) <= b.mid_upper + tol)
    brute = _chord_distance_brute(a, sampled)
    np.testing.assert_allclose(screening.chord_gaps(a, sampled), brute, rtol=1e-9, atol=1e-12 * np.abs(a).max())
    assert brute.max() <= delta * (1 + 1e-12)


def test_the_sampled_von_mises_bound_covers_the_steps_between_read_steps():
    """A history inside its principal subspace (no residual) on a closed curve: between
    two read steps the path bulges outside their chord, so von Mises there can exceed
    both read values. The bound's chord term (``||L SP||_F delta``,
    :func:`railcheck.fea.screening.sampled_pairs`) covers it at every node and step; the
    read values alone do not. Planting the bound without that term fails."""
    from railcheck.fea import screening

    rng = np.random.default_rng(3)
    n, T, k = 300, 720, 6
    t = np.linspace(0.0, 2.0 * np.pi, T, endpoint=False)
    C = np.zeros((T, k))
    C[:, 0], C[:, 1], C[:, 2] = np.cos(t), np.sin(t), 0.3 * np.cos(3.0 * t)
    S = rng.normal(size=(6, n, k))
    p = screening.project_history(S, C)
    b = screening.sampled_bounds(p.SP, p.norms, p.vm_norm, p.sub)
    vm = von_mises(np.einsum("jnk,tk->jnt", S, C)).max(axis=1)
    assert p.sub.eps < 1e-9 and p.sub.delta > 0.0
    assert np.all(vm <= b.von_mises_upper * (1.0 + 1e-12))
    assert np.any(vm > b.von_mises * (1.0 + 1e-6))  # the read steps alone miss some nodes' peaks


def test_the_group_box_s_midrange_bounds_of_many_histories_at_once_equal_each_alone():
    """:meth:`railcheck.fea.screening.CoefficientBox.midrange_at` over (history, node) pairs
    of several histories at once (one product per history) equals
    :meth:`~railcheck.fea.screening.CoefficientBox.at_nodes` of each history alone, and every
    component's midrange over every step lies within it. Histories with different means
    and shapes, so that a pair read against another history's taken values would
    differ. Plant: every history's pairs read with the first history's values."""
    from railcheck.fea.screening import CoefficientBox

    rng = np.random.default_rng(7)
    n, T, k, s = 200, 360, 5, 4
    t = np.linspace(0.0, 2.0 * np.pi, T, endpoint=False)
    stress = rng.normal(size=(6, n, k))
    C = np.stack(
        [
            np.cos((i + 1) * t[:, None] + rng.uniform(0, 6, k)) * rng.uniform(0.5, 3.0, k) + rng.normal(size=k) * i
            for i in range(s)
        ]
    )
    box = CoefficientBox(stress, np.ones(k))
    lo, hi, taken = box.ranges_and_taken(C)
    vm, mid, reach = box.box_arrays(lo, hi)
    h, nodes = np.nonzero(rng.random((s, n)) < 0.5)
    together = box.midrange_at(mid[h, :, nodes], reach[h, :, nodes], nodes, h, taken)
    X = np.einsum("jnk,stk->sjnt", stress, C)
    midrange = np.abs(0.5 * (X.max(axis=3) + X.min(axis=3)))  # (s, 6, n)
    assert np.all(midrange[h, :, nodes] <= together * (1 + 1e-6) + 1e-9 * np.abs(X).max())
    for i, b in enumerate(box.box_of(lo, hi)):
        alone = box.at_nodes(b, nodes[h == i], taken[i])
        np.testing.assert_array_equal(together[h == i], alone.mid_upper.T)


def test_histories_in_their_subspaces_together_equal_each_alone():
    """:func:`railcheck.fea.screening.principal_subspaces` of several histories at once (the
    read steps of every path refined together) gives each history the same rank,
    coordinates, residual, read steps, chord distance and touched steps as that history
    alone. Histories of different reach and shape, so a tolerance or a chord taken from
    another history would differ. Plant: every path refined to the first one's
    tolerance."""
    from railcheck.fea import screening

    rng = np.random.default_rng(11)
    T, k = 720, 12
    t = np.linspace(0.0, 2.0 * np.pi, T, endpoint=False)[:, None]
    C = np.stack(
        [
            np.cos(t * rng.integers(1, 4, k) + rng.uniform(0, 6, k)) * rng.uniform(0.1, 1.0, k) * 10.0**i
            + 10.0**i * 0.02 * rng.normal(size=(T, k)) * (i == 2)
            for i in range(4)
        ]
    )
    together = screening.principal_subspaces(C)
    for i in range(C.shape[0]):
        one, alone = together.one(i), screening.principal_subspace(C[i])
        np.testing.assert_allclose(one.a, alone.a, rtol=1e-12, atol=1e-12 * np.abs(alone.a).max())
        assert one.eps == pytest.approx(alone.eps, rel=1e-9, abs=1e-12 * 10.0**i)
        np.testing.assert_array_equal(one.sampled, alone.sampled)
        np.testing.assert_array_equal(one.touched, alone.touched)
        assert one.delta == pytest.approx(alone.delta, rel=1e-9)


def test_the_step_nearest_a_paths_box_centre_is_found_in_half_width_units():
    """nearest_to_box_centre: the step whose coordinates, each over its box half-width,
    lie nearest the box's centre (brute force), on paths whose coordinates differ by ten
    orders of magnitude, a constant coordinate and one of half-width about 1e-150 (no
    overflow, no NaN; which step a caller gets only tightens its bounds: any step the
    history takes is a valid one)."""
    from railcheck.fea.screening import nearest_to_box_centre

    rng = np.random.default_rng(3)
    d = rng.normal(size=(5, 300, 6)) * np.array([1e-5, 1.0, 1e5, 0.0, 1e-150, 3.0]) + np.array(
        [7.0, -2.0, 0.0, 4.0, 0.0, 1e3]
    )
    lo, hi = d.min(axis=1, keepdims=True), d.max(axis=1, keepdims=True)
    half = np.where(hi > lo, 0.5 * (hi - lo), 1.0)
    brute = np.argmin((((d - 0.5 * (lo + hi)) / half) ** 2).sum(axis=2), axis=1)
    np.testing.assert_array_equal(nearest_to_box_centre(d), brute)
    np.testing.assert_array_equal(nearest_to_box_centre(d[0]), brute[0])


@pytest.mark.usefixtures("group_prepass")
def test_a_pair_the_thresholds_read_but_did_not_evaluate_is_still_evaluated_when_it_can_hold_the_peak(monkeypatch):
    """A batch's thresholds read the nodes of best box bound at the sampled steps and
    evaluate the few of best sampled value exactly; the pairs they read keep their bounds
    for the rest of the screen. Here a history of nine directions is read in rank 8
    (seven harmonics and a constant) with a one-step kick as its residual; twenty decoy
    nodes carry the harmonics (their sampled value is about their peak) and ten hidden
    nodes only the kick (sampled value nearly zero, peak higher than every decoy's). The
    thresholds read the hidden nodes but evaluate decoys, so the hidden ones must then be
    evaluated for the peak. The second history is larger than the first, its kick more so:
    a pair given another history's bounds loses its peak. Each history goes through the
    batch (a history screened alone is refused here)."""
    from railcheck.fea.screening import batch

    def refused(*args, **kwargs):
        raise AssertionError("a history was screened alone")

    monkeypatch.setattr(batch, "screened_alone", refused)
    rng = np.random.default_rng(21)
    n, T, k = 3000, 1440, 9
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    C = np.zeros((2, T, k))
    for j in range(7):
        C[:, :, j] = np.cos((j + 1) * t + j)[None] * np.array([[1.0], [1.8]])
    C[:, :, 7] = 1.0  # a constant: the mean stress
    C[:, 77, 8] = [1.0, 1.5]  # a one-step kick
    stress = rng.normal(size=(6, n, k)) * 1e-3  # the nodes that matter to no history
    stress[:, :, 8] = 0.0
    decoys, hidden = rng.choice(n, 30, replace=False).reshape(2, 15)
    stress[:, decoys, :8] = rng.normal(size=(6, 15, 8))
    stress[:, hidden, :] = 0.0
    stress[:, hidden, 8] = rng.normal(size=(6, 15)) * 6.0
    mask = np.ones(n, bool)
    screen = make_screen(stress, mask, np.zeros((3, k)), list(range(k)))
    vm, n_min = _brute(stress, mask, C)
    for c in C:  # a hidden node holds the peak; every decoy has a larger value off the kick
        X = np.tensordot(stress, c, axes=([2], [1]))
        peak = von_mises(X).max(axis=1)
        assert np.argmax(peak) in hidden and peak[hidden].max() > peak[decoys].max()
        assert von_mises(np.delete(X, 77, axis=2)[:, hidden]).max() < 1e-12 < peak[decoys].min()
    both = peak_and_fatigue(screen, C, 200e6, 750e6, "goodman", None)
    np.testing.assert_allclose(both[0], vm, rtol=1e-12)
    np.testing.assert_allclose(both[1], n_min, rtol=1e-12)


@pytest.mark.usefixtures("group_prepass")
def test_the_load_sources_of_one_setting_are_screened_as_one_set(monkeypatch):
    """A part loaded at two or three places per setting (PF_4b_006 at two joints) needs
    only the largest peak and the smallest factor of each setting's histories, so a
    history's exact value is a threshold for the others of its set. Here 14 settings of
    one to three sources, their histories shuffled: each set's first source strong, the
    others 0.3 of it; in six sets a weak source also carries a one-step kick that only a
    few hidden nodes feel (outside the rank-8 subspace it is read in, so its sampled
    values miss it), enough to hold the set's peak. Groups of at most five histories and
    batches of two cut the sets, which must stay whole. Every history's results equal its
    set's over every node x every step; a threshold shared beyond its set, a set cut
    apart, a weak source dropped or a result left per history fails it."""
    from railcheck.fea.screening import tuning

    monkeypatch.setattr(tuning, "GROUP_MOST", 5)
    rng = np.random.default_rng(33)
    n, T, k = 1500, 360, 9
    monkeypatch.setattr(tuning, "BATCH_PAIRS", 2 * n)
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    sizes = rng.integers(1, 4, size=14)
    sizes[:6] = 2 + (np.arange(6) % 2)  # the sets with a hidden peak have a weak source
    labels = np.repeat(np.arange(14), sizes)
    first = np.concatenate([[True], labels[1:] != labels[:-1]])
    strength = np.where(first, 1.0, 0.3) * np.exp(rng.normal(size=labels.size))[labels]  # sets of different size
    C = np.zeros((labels.size, T, k))
    for j in range(7):
        C[..., j] = np.cos((j + 1) * t + rng.random((labels.size, 1)) * 6) * strength[:, None]
    C[..., 7] = strength[:, None]  # a constant: the mean stress
    kicked = np.flatnonzero(~first & (labels < 6))
    C[kicked, 77, 8] = 2.0 * strength[kicked] / 0.3
    stress = rng.normal(size=(6, n, k))
    stress[:, :, 8] = 0.0
    hidden = rng.choice(n, 12, replace=False)
    stress[:, hidden, :] = 0.0
    stress[:, hidden, 8] = rng.normal(size=(6, 12)) * 6.0
    order = rng.permutation(labels.size)
    C, labels = C[order], labels[order]
    mask = np.ones(n, bool)
    screen = make_screen(stress, mask, np.zeros((3, k)), list(range(k)))
    vm, n_min = _brute(stress, mask, C)
    set_vm = np.array([vm[labels == i].max() for i in labels])
    set_min = np.array([n_min[labels == i].min() for i in labels])
    for i in range(6):  # a weak source holds those sets' peak, at a hidden node
        members = np.flatnonzero(labels == i)
        weak = members[np.isin(order[members], kicked)]
        assert vm[weak].max() == set_vm[members[0]]
        X = np.tensordot(stress, C[weak[np.argmax(vm[weak])]], axes=([2], [1]))
        assert np.argmax(von_mises(X).max(axis=1)) in hidden
    assert len(np.unique(set_vm)) == 14  # a threshold from another set would show
    both = peak_and_fatigue(screen, C, 200e6, 750e6, "goodman", 400e6, sets=labels)
    np.testing.assert_allclose(both[0], set_vm, rtol=1e-12)
    np.testing.assert_allclose(both[1], set_min, rtol=1e-12)
    alone = peak_and_fatigue(screen, C, 200e6, 750e6, "goodman", 400e6)  # no sets: each its own
    np.testing.assert_allclose(alone[0], vm, rtol=1e-12)
    np.testing.assert_allclose(alone[1], n_min, rtol=1e-12)


@pytest.mark.parametrize("seed", range(4))
def test_a_weaker_source_that_holds_its_set_s_fatigue_minimum_is_not_dropped(monkeypatch, seed):
    """Sets of two sources: one carries a mean stress (a constant and a small swing), the
    other a fully reversed swing about a third of it, on other coefficients. In some sets
    the swing, under its set's peak, holds the set's fatigue minimum (Goodman: 200 / s
    against 750 / 3 s). A source is skipped only when no node can pass either of its
    set's thresholds; skipping it on von Mises alone fails this. The group's thresholds
    come from one node per criterion, so they rarely settle a set by themselves."""
    from railcheck.fea.screening import tuning

    monkeypatch.setattr(tuning, "GROUP_CANDIDATES", 1)
    rng = np.random.default_rng(100 + seed)
    n, T, k, sets = 1200, 360, 6, 10
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    stress = rng.normal(size=(6, n, k)) * np.exp(0.7 * rng.normal(size=(1, n, 1)))
    C = np.zeros((2 * sets, T, k))
    size = np.exp(0.5 * rng.normal(size=sets))
    C[:sets, :, :3] = 3.0 * size[:, None, None] * (rng.normal(size=(sets, 1, 3)) + 0.05 * np.sin(t)[None, :, None])
    C[sets:, :, 3:] = (
        size[:, None, None] * rng.normal(size=(sets, 1, 3)) * np.cos(t[None, :, None] + rng.random((sets, 1, 1)) * 6)
    )
    labels = np.tile(np.arange(sets), 2)
    mask = np.ones(n, bool)
    screen = make_screen(stress, mask, np.zeros((3, k)), list(range(k)))
    vm, n_min = _brute(stress, mask, C)
    set_vm = np.maximum(vm[:sets], vm[sets:])
    set_min = np.minimum(n_min[:sets], n_min[sets:])
    assert np.any((n_min[sets:] < n_min[:sets]) & (vm[sets:] < vm[:sets]))  # a swing's minimum under its set's peak
    peak, factor = peak_and_fatigue(screen, C, 200e6, 750e6, "goodman", 400e6, sets=labels)
    np.testing.assert_allclose(peak, np.tile(set_vm, 2), rtol=1e-12)
    np.testing.assert_allclose(factor, np.tile(set_min, 2), rtol=1e-12)


def _in_subspace(rng, s: int, T: int, k: int, r: int) -> np.ndarray:
    """(s, T, k) histories of ``k`` coefficients that lie in a random ``r``-dimensional
    subspace of them (as a free body's: its equilibrium ties the coefficients), each with
    a mean, two harmonics and coefficients of very different sizes."""
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    a = rng.normal(size=(s, 1, r)) + sum(
        rng.normal(size=(s, 1, r)) / j * np.cos(j * t + rng.uniform(0, 6))[None, :, None] for j in range(1, 9)
    )
    return (a @ rng.normal(size=(r, k))) * np.exp(2 * rng.normal(size=k))


def test_history_span_finds_the_subspace_the_histories_lie_in():
    """Histories in a 7-dimensional subspace of 12 coefficients: 7 of the coefficients
    give back every step of every history to rounding, the others combinations of them."""
    from railcheck.fea.screening import history_span

    rng = np.random.default_rng(3)
    C = _in_subspace(rng, 9, 240, 12, 7)
    span = history_span(C)
    assert span is not None and span.index.size == 7
    np.testing.assert_array_equal(span.basis[span.index], np.eye(7))
    np.testing.assert_allclose(C[..., span.index] @ span.basis.T, C, rtol=0, atol=1e-13 * np.abs(C).max())
    np.testing.assert_allclose(span.dual.T @ span.basis, np.eye(7), atol=1e-12)


def test_history_span_is_none_unless_the_span_holds_every_step():
    """No span where the histories use every coefficient, where one step leaves the
    subspace (a step the rank is not read at: only the residual at every step catches
    it), where they are zero, or where they are not finite or their sizes overflow."""
    from railcheck.fea.screening import SPAN_STRIDE, history_span

    rng = np.random.default_rng(4)
    assert history_span(rng.normal(size=(3, 100, 6))) is None
    C = _in_subspace(rng, 4, 240, 12, 7)
    assert history_span(C) is not None
    kicked = C.copy()
    kicked[2, SPAN_STRIDE + 3] += 1e-9 * np.abs(C).max() * rng.normal(size=12)
    assert history_span(kicked) is None
    assert history_span(np.zeros((2, 50, 5))) is None
    broken = C.copy()
    broken[0, 5, 3] = np.nan
    assert history_span(broken) is None
    assert history_span(C * (1e300 / np.abs(C).max())) is None  # finite, but its squares overflow


@pytest.mark.usefixtures("group_prepass")
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_histories_in_a_subspace_are_screened_in_it_and_equal_brute_force(seed, monkeypatch):
    """Histories of 14 coefficients in a 9-dimensional subspace (as a free body's) are
    screened in 9 of their coefficients, over nodes of very different stress (the group's
    box drops most), hot nodes and nodes loaded mostly along the coefficients that are
    combinations of others: the peak and fatigue factor equal every node x every step,
    by set as well, and bit for bit what the same group gives without the span."""
    from railcheck.fea import screening
    from railcheck.fea.screening import groups

    rng = np.random.default_rng(seed)
    n, T, k, r = 2500, 360, 14, 9
    C = _in_subspace(rng, 11, T, k, r) * 1e3
    stress = rng.normal(size=(6, n, k)) * np.exp(1.5 * rng.normal(size=(1, n, 1))) / np.abs(C).max(axis=(0, 1))
    hot = rng.choice(n, 25, replace=False)
    stress[:, hot] *= 5.0
    span = screening.history_span(C * make_screen(stress, np.ones(n, bool), np.zeros((3, k)), list(range(k))).scale)
    assert span is not None and span.index.size == r
    dependent = np.setdiff1d(np.arange(k), span.index)
    stress[:, hot[:10][:, None], dependent[None, :]] *= 40.0  # hot only through the dependent coefficients
    mask = rng.random(n) > 0.05
    screen = make_screen(stress, mask, rng.normal(size=(3, k)), list(range(k)))
    used = []
    monkeypatch.setattr(groups, "in_span", lambda *a, _f=groups.in_span: used.append(1) or _f(*a))
    vm, n_min = _brute(stress, mask, C)
    got = peak_and_fatigue(screen, C, 200e6, 750e6, "goodman", 400e6)
    assert used
    np.testing.assert_allclose(got[0], vm, rtol=1e-12)
    np.testing.assert_allclose(got[1], n_min, rtol=1e-12)
    sets = np.arange(C.shape[0]) // 2
    by_set = peak_and_fatigue(screen, C, 200e6, 750e6, "goodman", 400e6, sets=sets)
    np.testing.assert_allclose(by_set[0], [vm[sets == i].max() for i in sets], rtol=1e-12)
    np.testing.assert_allclose(by_set[1], [n_min[sets == i].min() for i in sets], rtol=1e-12)
    # the exact values are taken in the original coefficients: the same bits as without the
    # span, so a table does not depend on how its settings were grouped
    monkeypatch.setattr(groups, "history_span", lambda Cs: None)
    without = peak_and_fatigue(screen, C, 200e6, 750e6, "goodman", 400e6)
    np.testing.assert_array_equal(got[0], without[0])
    np.testing.assert_array_equal(got[1], without[1])


@pytest.mark.parametrize("axes", ["principal", "independent"])
def test_a_group_in_a_subspace_is_boxed_and_read_in_its_coordinates(axes):
    """The group's box in the span: its coordinates of the histories are those the box
    was built for (also the means' coordinates, :meth:`CoefficientBox.coordinates`), its
    rows times them give every node's stress at every step, and the screen in the span's
    coefficients gives the same stresses, with its bounds per unit coefficient (each
    component's norm, von Mises' trace bound) those of its own stresses. Histories along
    mixed directions, boxed along their principal axes, and histories whose first seven
    coefficients move independently (the rest their combinations), boxed in those seven."""
    from railcheck.fea import screening
    from railcheck.fea.screening import component_norms, history_span, von_mises_norm_bound

    n, k, r = 800, 12, 7
    if axes == "principal":
        rng = np.random.default_rng(5)
        C = _in_subspace(rng, 5, 240, k, r)
    else:
        rng = np.random.default_rng(6)
        t = np.linspace(0, 2 * np.pi, 240, endpoint=False)
        own = np.stack([np.cos((j + 1) * t + rng.uniform(0, 6)) + rng.normal() for j in range(r)], -1)
        own = own[None] * rng.uniform(0.5, 2, size=(5, 1, r))
        C = np.concatenate([own, own @ rng.normal(size=(r, k - r)) * 0.3], -1)
    stress = rng.normal(size=(6, n, k))
    screen = make_screen(stress, np.ones(n, bool), rng.normal(size=(3, k)), list(range(k)))
    span = history_span(C * screen.scale)
    assert span is not None
    group, d = screening.group_box(screen, C, span)
    assert group.rows.shape == (6 * n, r)
    assert (group.B is span.basis) == (axes == "independent")
    np.testing.assert_allclose(group.coordinates(C), d, rtol=1e-12, atol=1e-12 * np.abs(d).max())
    exact = np.einsum("cnk,stk->stcn", stress, C)
    scale = np.abs(exact).max()
    np.testing.assert_allclose(np.einsum("jr,str->stj", group.rows, d).reshape(exact.shape), exact, atol=1e-5 * scale)
    nodes = np.sort(rng.choice(n, 50, replace=False))
    inside = screening.in_span(screening.restricted_screen(screen, nodes), span)
    Cr = (C * screen.scale)[..., span.index]
    np.testing.assert_allclose(np.einsum("cnk,stk->stcn", inside.stress, Cr), exact[..., nodes], atol=1e-12 * scale)
    np.testing.assert_allclose(inside.bounds.unit_rows, component_norms(inside.stress), rtol=1e-14)
    np.testing.assert_allclose(inside.bounds.form_bound, von_mises_norm_bound(inside.stress) ** 2, rtol=1e-14)
    np.testing.assert_array_equal(inside.scale, np.ones(r))
