"""Fatigue against hand values from Shigley's equations (Budynas & Nisbett, 10th ed.,
chapter 6): each criterion, every Marin branch, and each ``[fatigue]`` scene option
carried into the calculation of a part's safety factor."""

import math
import tomllib
from dataclasses import replace

import numpy as np
import pytest

from railcheck.fea import screening
from railcheck.fea.fatigue import alternating_and_mean, endurance_limit, safety_factor, size_factor
from railcheck.fea.hull import candidate_steps
from railcheck.fea.materials import MATERIALS
from railcheck.fea.superpose import UnitFields, component_range
from railcheck.model.cycle import fatigue_of
from railcheck.model.inputs import parts_input
from railcheck.scene import parse_scene

MPa = 1e6
SA, SM, SE, SUT, SY = 100 * MPa, 200 * MPa, 250 * MPa, 750 * MPa, 490 * MPa


def _n(criterion, sa=SA, sm=SM, sy=SY):
    return float(safety_factor(np.array([sa]), np.array([sm]), SE, SUT, criterion, sy)[0])


def test_criteria_equal_shigley_by_hand():
    """sa = 100, sm = 200, Se = 250, Sut = 750, Sy = 490 MPa, load line through the origin:
    Goodman 1/n = 0.4 + 0.2667 (eq. 6-41); Gerber eq. 6-47 by hand: 1.875; ASME-elliptic
    1/n^2 = 0.16 + (200/490)^2 (eq. 6-50): 1.7498."""
    assert _n("goodman") == pytest.approx(1.5, rel=1e-12)
    gerber = 0.5 * (750 / 200) ** 2 * (100 / 250) * (-1 + math.sqrt(1 + (2 * 200 * 250 / (750 * 100)) ** 2))
    assert gerber == pytest.approx(1.875, rel=1e-12)
    assert _n("gerber") == pytest.approx(1.875, rel=1e-12)
    assert _n("asme-elliptic") == pytest.approx(1.7498, abs=5e-5)
    assert _n("asme-elliptic") == pytest.approx(1 / math.sqrt(0.4**2 + (200 / 490) ** 2), rel=1e-12)


@pytest.mark.parametrize("criterion", ["goodman", "gerber", "asme-elliptic"])
def test_fully_reversed_static_and_unloaded_limits(criterion):
    """No mean stress: every criterion gives Se / sa. No alternation: Sut / sm (Goodman,
    Gerber) or Sy / sm (ASME-elliptic). Nothing: infinity."""
    assert _n(criterion, sm=0.0) == pytest.approx(2.5, rel=1e-12)
    static = 490 / 200 if criterion == "asme-elliptic" else 750 / 200
    assert _n(criterion, sa=0.0) == pytest.approx(static, rel=1e-12)
    assert _n(criterion, sa=0.0, sm=0.0) == math.inf


@pytest.mark.parametrize("criterion", ["goodman", "gerber", "asme-elliptic"])
def test_each_factor_solves_its_criterion_over_twenty_decades(criterion):
    """n is the root of its criterion's equation, to rounding, for sa and sm from 1 Pa to
    1e19 Pa (one far below the other included: Gerber's textbook form loses every digit to
    the cancellation of -1 + sqrt(1 + x^2) there, and gave 0)."""
    sa, sm = (a.ravel() for a in np.meshgrid(np.logspace(0, 19, 39), np.logspace(0, 19, 39)))
    n = safety_factor(sa, sm, SE, SUT, criterion, SY)
    equation = {
        "goodman": n * sa / SE + n * sm / SUT,
        "gerber": n * sa / SE + (n * sm / SUT) ** 2,
        "asme-elliptic": (n * sa / SE) ** 2 + (n * sm / SY) ** 2,
    }[criterion]
    assert np.all(n > 0) and np.all(np.isfinite(n))
    np.testing.assert_allclose(equation, 1.0, rtol=1e-12)


def test_criteria_refuse_what_they_cannot_compute():
    with pytest.raises(ValueError, match="yield"):
        _n("asme-elliptic", sy=0.0)
    with pytest.raises(ValueError, match="unknown"):
        _n("soderberg")


def test_alternating_and_mean_von_mises_by_hand():
    """A uniaxial history 100..300 MPa with a constant 50 MPa shear: sa = 100 (the shear
    does not alternate), sm = sqrt(200^2 + 3 * 50^2) (eqs. 6-66, 6-67)."""
    high = np.array([[300.0], [0], [0], [50.0], [0], [0]]) * MPa
    low = np.array([[100.0], [0], [0], [50.0], [0], [0]]) * MPa
    sa, sm = alternating_and_mean(high, low)
    assert sa[0] == pytest.approx(100 * MPa, rel=1e-12)
    assert sm[0] == pytest.approx(math.sqrt(200**2 + 3 * 50**2) * MPa, rel=1e-12)


def test_marin_surface_factor_and_its_cap():
    """ka = a Sut^b (table 6-2), never above 1: ground at Sut = 200 MPa would give 1.007."""
    for surface, (a, b) in {"ground": (1.58, -0.085), "machined": (4.51, -0.265), "hot-rolled": (57.7, -0.718)}.items():
        assert endurance_limit(750e6, surface).ka == pytest.approx(a * 750**b, rel=1e-12)
    assert 1.58 * 200**-0.085 > 1.0
    assert endurance_limit(200e6, "ground").ka == 1.0


def test_marin_tables_are_shigleys():
    """Every row of table 6-2 (surface, a in MPa, b) and table 6-5 (reliability, ke) as
    printed in Shigley, 10th ed."""
    from railcheck.fea.fatigue import RELIABILITY, SURFACE

    table_6_2 = {
        "ground": (1.58, -0.085),
        "machined": (4.51, -0.265),
        "cold-drawn": (4.51, -0.265),
        "hot-rolled": (57.7, -0.718),
        "as-forged": (272.0, -0.995),
    }
    table_6_5 = {0.5: 1.000, 0.9: 0.897, 0.95: 0.868, 0.99: 0.814, 0.999: 0.753, 0.9999: 0.702}
    assert SURFACE == table_6_2 and RELIABILITY == table_6_5
    for surface, (a, b) in table_6_2.items():
        assert endurance_limit(600e6, surface).ka == pytest.approx(min(1.0, a * 600**b), rel=1e-12)
    for r, ke in table_6_5.items():
        assert endurance_limit(600e6, "machined", None, "bending", r).ke == ke


def test_the_marin_record_is_frozen_and_its_product_is_se():
    import dataclasses

    m = endurance_limit(750e6, "machined", (0.023, 0.022), "bending", 0.99)
    assert m.kd == 1.0  # room temperature
    assert m.endurance_limit == pytest.approx(m.ka * m.kb * m.kc * m.kd * m.ke * m.unmodified, rel=1e-15)
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.ka = 1.0


def test_marin_size_factor_branches():
    """kb from d_e = 0.808 sqrt(h b) (table 6-3): 1 below 2.79 mm and without a section;
    1.24 d^-0.107 up to 51 mm; 1.51 d^-0.157 above (eq. 6-20); held at 254 mm."""
    assert size_factor(None) == 1.0
    assert size_factor((0.002, 0.002)) == 1.0  # d = 1.6 mm
    d_small = 0.808 * math.sqrt(23 * 22)
    assert size_factor((0.023, 0.022)) == pytest.approx(1.24 * d_small**-0.107, rel=1e-12)
    d_large = 0.808 * math.sqrt(80 * 70)  # 60.5 mm
    assert size_factor((0.080, 0.070)) == pytest.approx(1.51 * d_large**-0.157, rel=1e-12)
    assert size_factor((0.5, 0.5)) == pytest.approx(1.51 * 254.0**-0.157, rel=1e-12)
    # just inside each branch's end: d = 3.0 mm (first fit) and d = 51.5 mm (second fit)
    side = lambda d: (d / 0.808 / 1e3, d / 0.808 / 1e3)  # noqa: E731 - a square section of that d_e
    assert size_factor(side(3.0)) == pytest.approx(1.24 * 3.0**-0.107, rel=1e-12)
    assert size_factor(side(51.5)) == pytest.approx(1.51 * 51.5**-0.157, rel=1e-12)
    # continuity at 51 mm within Shigley's rounding of the two fits
    assert 1.24 * 51**-0.107 == pytest.approx(1.51 * 51**-0.157, rel=0.01)


def test_marin_load_reliability_and_the_ceiling_of_the_unmodified_limit():
    """Axial: kc = 0.85 and no size effect (kb = 1); ke from table 6-5; Se' = 0.5 Sut up to
    1400 MPa, 700 MPa above (eq. 6-8); Se the product of every factor."""
    section = (0.023, 0.022)
    bending = endurance_limit(750e6, "machined", section, "bending", 0.5)
    axial = endurance_limit(750e6, "machined", section, "axial", 0.5)
    assert (bending.kc, axial.kc, axial.kb) == (1.0, 0.85, 1.0) and bending.kb < 1.0
    assert axial.endurance_limit == pytest.approx(bending.ka * 0.85 * 375e6, rel=1e-12)
    for reliability, ke in {0.9: 0.897, 0.99: 0.814, 0.9999: 0.702}.items():
        assert endurance_limit(750e6, "machined", None, "bending", reliability).ke == ke
    assert endurance_limit(1000e6).unmodified == 500e6
    assert endurance_limit(1500e6).unmodified == 700e6
    assert endurance_limit(1400e6).unmodified == 700e6
    assert endurance_limit(1400.5e6).unmodified == 700e6  # not 0.5 x 1400.5
    m = endurance_limit(1500e6, "ground", section, "bending", 0.95)
    assert m.endurance_limit == pytest.approx(1.58 * 1500**-0.085 * m.kb * 0.868 * 700e6, rel=1e-12)


def _crank_job(fatigue_table: str):
    """The default scene's crank-rail job with a ``[fatigue]`` table, no FE."""
    from railcheck.model.jobs import build_load_cases, part_geometries, part_jobs
    from railcheck.model.kinematics_stage import kinematics_input, run_kinematics

    text = (
        '[mechanism]\nkind = "four-bar"\ncrank = "480 mm"\ncoupler = "840 mm"\nrocker = "780 mm"\nground = "1020 mm"\n'
        'speed = "1 Hz"\nsteps = 8\n[check]\nparts = ["crank-rail"]\n' + fatigue_table
    )
    scene = parse_scene(tomllib.loads(text), "test")
    kin = run_kinematics(kinematics_input(scene))
    geos = part_geometries(parts_input(scene))
    steel = MATERIALS["steel"]
    return part_jobs(parts_input(scene), kin, geos, build_load_cases(parts_input(scene), kin, geos), steel, 375e6)[
        "crank-rail"
    ]


def _one_node_fields() -> UnitFields:
    """One node whose unit case is 1 Pa of uniaxial stress: a history C (Pa) is its stress."""
    stress = np.zeros((6, 1, 1))
    stress[0, 0, 0] = 1.0
    return UnitFields(
        stress=stress,
        tip=np.zeros((3, 1)),
        displacement=np.zeros((1, 3, 1)),
        nodes=np.zeros((1, 3)),
        verdict_mask=np.ones(1, bool),
        names=("unit",),
    )


@pytest.mark.parametrize(
    ("table", "expect"),
    [
        ("", dict(surface="machined", reliability=0.99, load="bending", criterion="goodman", required=1.0)),
        ('[fatigue]\nsurface = "ground"\n', dict(surface="ground")),
        ("[fatigue]\nreliability = 0.5\n", dict(reliability=0.5)),
        ('[fatigue]\nload = "axial"\n', dict(load="axial")),
        ('[fatigue]\ncriterion = "gerber"\n', dict(criterion="gerber")),
        ('[fatigue]\ncriterion = "asme-elliptic"\n', dict(criterion="asme-elliptic")),
        ("[fatigue]\nmin_safety = 2.5\n", dict(required=2.5)),
    ],
)
def test_each_fatigue_option_reaches_the_safety_factor(table, expect):
    """A node cycling 100..300 MPa (sa = 100, sm = 200 MPa): the part's fatigue result uses
    exactly the scene's surface, reliability, load type, criterion and required factor,
    against Shigley's formulas written out here."""
    job = _crank_job(table)
    spec = dict(surface="machined", reliability=0.99, load="bending", criterion="goodman", required=1.0) | expect
    C = np.array([[100e6], [300e6], [200e6]])
    result = fatigue_of(job, _one_node_fields(), C)
    a, b = {"machined": (4.51, -0.265), "ground": (1.58, -0.085)}[spec["surface"]]
    ka = a * 750**b
    d = 0.808 * math.sqrt(23 * 22)
    kb = 1.0 if spec["load"] == "axial" else 1.24 * d**-0.107
    kc = 0.85 if spec["load"] == "axial" else 1.0
    ke = {0.5: 1.0, 0.99: 0.814}[spec["reliability"]]
    se = ka * kb * kc * ke * 375e6
    sa, sm = 100e6, 200e6
    hand = {
        "goodman": 1 / (sa / se + sm / 750e6),
        "gerber": 0.5 * (750e6 / sm) ** 2 * (sa / se) * (-1 + math.sqrt(1 + (2 * sm * se / (750e6 * sa)) ** 2)),
        "asme-elliptic": 1 / math.sqrt((sa / se) ** 2 + (sm / 490e6) ** 2),
    }[spec["criterion"]]
    assert job.section == pytest.approx((0.023, 0.022))
    assert (result.sigma_a, result.sigma_m) == pytest.approx((sa, sm), rel=1e-12)
    assert result.marin.endurance_limit == pytest.approx(se, rel=1e-12)
    assert result.min_safety_factor == pytest.approx(hand, rel=1e-12)
    assert (result.criterion, result.surface, result.reliability, result.required) == (
        spec["criterion"],
        spec["surface"],
        spec["reliability"],
        spec["required"],
    )
    assert result.passed == (hand >= spec["required"])


def test_the_fatigue_verdict_compares_with_the_required_factor():
    job = _crank_job("[fatigue]\nmin_safety = 3\n")
    C = np.array([[100e6], [300e6]])
    result = fatigue_of(job, _one_node_fields(), C)
    assert 1.0 < result.min_safety_factor < 3.0 and not result.passed
    lower = fatigue_of(
        replace(job, fatigue=replace(job.fatigue, min_safety=result.min_safety_factor)), _one_node_fields(), C
    )
    assert lower.passed  # at exactly the required factor: passes


@pytest.mark.parametrize("criterion", ["goodman", "gerber", "asme-elliptic"])
@pytest.mark.parametrize("k", [9, 2, 3])
def test_without_node_fields_the_screened_minimum_is_every_nodes(criterion, k):
    """A check that writes no VTU needs only the minimum: a history's nodes are screened
    (many coefficients at its principal subspace's sampled steps, two coefficients or an
    affine plane by its box) and only the few that can hold the minimum are evaluated.
    Minimum, node, sigma_a and sigma_m equal every node x every step's, on random fields
    with hot nodes, decoys (huge stress on a barely used coefficient) and a history with a
    mean and a kick between sampled steps; and the verdict mask is honoured."""
    job = _crank_job(f'[fatigue]\ncriterion = "{criterion}"\n')
    rng = np.random.default_rng(21)
    n, T = 3000, 400
    S = rng.normal(size=(6, n, k)) * np.exp(1.2 * rng.normal(size=(1, n, 1))) * 1e3
    S[:, :150, :] *= 1e-3
    S[:, :150, k - 1] = rng.normal(size=(6, 150)) * 1e8  # decoys
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    C = np.column_stack([1e4 * np.cos((j + 1) * t + j) + 3e3 * j for j in range(k - 1)] + [1e-6 * np.sin(t)])
    if k == 3:  # an affine plane, as a reduced free body's history
        C = np.column_stack([np.ones(T), 1e4 * np.cos(t) + 3e3, 1e4 * np.sin(2 * t + 1)])
    C[203, 1 if k == 3 else 0 : max(k - 1, 1)] *= 1.8  # a kick between sampled steps

    def fields_with(mask):
        return UnitFields(S, np.zeros((3, k)), np.zeros((n, 3, k)), rng.normal(size=(n, 3)), mask, tuple(map(str, range(k))))

    mask = rng.random(n) > 0.2
    mask[np.argmin(fatigue_of(job, fields_with(np.ones(n, bool)), C).node_factor)] = False  # the mask matters
    fields = fields_with(mask)
    full = fatigue_of(job, fields, C)
    fast = fatigue_of(replace(job, node_fields=False), fields, C)
    assert full.node_factor is not None and fast.node_factor is None
    assert fast.location == full.location
    assert fast.min_safety_factor == pytest.approx(full.min_safety_factor, rel=1e-12)
    assert (fast.sigma_a, fast.sigma_m) == pytest.approx((full.sigma_a, full.sigma_m), rel=1e-12)
    assert full.node_factor.min() < full.min_safety_factor  # the minimum over all nodes is left out
    # what the screen rests on: at every node its bounds reach the exact alternating and mean stress
    Cs = C[candidate_steps(C)]
    bounds = screening.history_bounds(S, Cs) if screening.applies(*Cs.shape) else screening.history_box_bounds(S, Cs)
    sa_upper, sm_upper = screening.fatigue_bounds(bounds)
    sa, sm = alternating_and_mean(*component_range(S, Cs))
    assert np.all(sa_upper >= sa * (1 - 1e-12)) and np.all(sm_upper >= sm * (1 - 1e-12))


def test_the_checks_bounds_sample_only_the_boxs_candidates_and_stay_exact():
    """:func:`railcheck.model.cycle.verdict_bounds`: the box at every node, the sampled
    steps read only where the box leaves candidates. Its bounds reach every node's exact
    von Mises peak and alternating and mean stresses, fewer than a quarter of the nodes
    are read at the samples, and the peaks and fatigue minimum screened with them equal
    every node x every step's."""
    from railcheck.fea.superpose import envelope, von_mises_max
    from railcheck.model.cycle import verdict_bounds

    job = replace(_crank_job(""), node_fields=False)
    rng = np.random.default_rng(8)
    n, T, k = 4000, 500, 9
    S = rng.normal(size=(6, n, k)) * np.exp(1.2 * rng.normal(size=(1, n, 1))) * 1e3
    S[:, :150, :] *= 1e-3
    S[:, :150, k - 1] = rng.normal(size=(6, 150)) * 1e8  # decoys on a barely used coefficient
    t = np.linspace(0, 2 * np.pi, T, endpoint=False)
    C = np.column_stack([1e4 * np.cos((j + 1) * t + j) + 3e3 * j for j in range(k - 1)] + [1e-6 * np.sin(t)])
    C[203, : k - 1] *= 1.8  # a kick between sampled steps
    mask = rng.random(n) > 0.2
    fields = UnitFields(S, np.zeros((3, k)), np.zeros((n, 3, k)), rng.normal(size=(n, 3)), mask, tuple(map(str, range(k))))
    steps = candidate_steps(C)
    b = verdict_bounds(job, fields, C[steps])
    peak = von_mises_max(S, C)[0]
    high, low = component_range(S, C)
    sa, sm = alternating_and_mean(high, low)
    sa_upper, sm_upper = screening.fatigue_bounds(b)
    assert np.all(b.von_mises_upper >= peak * (1 - 1e-12))
    reach = 1e-12 * np.abs(high).max()
    assert np.all(high <= b.high + b.slack + reach) and np.all(low >= b.low - b.slack - reach)
    # and within the residual's share inside the read values (fatigue_bounds rests on both)
    assert np.all(high >= b.high - b.share - reach) and np.all(low <= b.low + b.share + reach)
    assert np.all(sa_upper >= sa * (1 - 1e-12)) and np.all(sm_upper >= sm * (1 - 1e-12))
    sampled = np.flatnonzero(b.high != b.low)  # the box's nodes have high = low (its centre)
    assert 0 < sampled.size < n / 4
    full, fast = envelope(fields, C), envelope(fields, C, every_node=False, steps=steps, bounds=b)
    assert (fast.node, fast.step) == (full.node, full.step)
    assert (fast.max_von_mises, fast.support_peak) == pytest.approx((full.max_von_mises, full.support_peak), rel=1e-13)
    every = fatigue_of(replace(job, node_fields=True), fields, C)
    screened = fatigue_of(job, fields, C, steps, b)
    assert screened.location == every.location
    assert screened.min_safety_factor == pytest.approx(every.min_safety_factor, rel=1e-12)


def test_fatigue_bounds_cover_every_stress_range_their_sampled_bounds_allow():
    """:func:`railcheck.fea.screening.fatigue_bounds` of sampled bounds: each component's maximum may lie
    anywhere in ``[high - share, high + slack]`` and its minimum in ``[low - slack, low +
    share]`` (read values within the residual's share inside, the chords' slack outside).
    At every corner of those intervals, drawn at random per component over many nodes, the
    alternating and mean von Mises stay within the bounds, and some come within 2% of
    them (the bounds are tight at the corners). Planted: the share taken as 0 (read values
    exact), or the midrange's width as the slack alone, each fails."""
    rng = np.random.default_rng(12)
    n = 20000
    high = rng.normal(size=(6, n)) * 100.0
    low = high - np.abs(rng.normal(size=(6, n))) * rng.choice([1.0, 100.0], size=(1, n))
    slack = np.abs(rng.normal(size=(6, n))) * 20.0
    share = slack * rng.uniform(0.0, 1.0, size=(6, n))
    b = screening.SampledBounds(np.zeros(n), np.zeros(n), high, low, slack, None, share)
    sa_upper, sm_upper = screening.fatigue_bounds(b)
    closest = 0.0
    for _ in range(40):
        top = np.where(rng.random((6, n)) < 0.5, high - share, high + slack)
        bottom = np.where(rng.random((6, n)) < 0.5, low - slack, low + share)
        bottom = np.minimum(bottom, top)  # a minimum is never above the maximum
        sa, sm = alternating_and_mean(top, bottom)
        assert np.all(sa <= sa_upper * (1 + 1e-12)) and np.all(sm <= sm_upper * (1 + 1e-12))
        closest = max(closest, float(np.max(sa / sa_upper)), float(np.max(sm / sm_upper)))
    assert closest > 0.98


def test_sampled_bounds_hold_each_component_s_extremes_inside_and_outside():
    """:func:`railcheck.fea.screening.sampled_bounds` on a history with a residual outside its largest
    subspace (12 independent harmonics, rank 8): every node's component maximum over every
    step lies in ``[high - share, high + slack]`` and its minimum in ``[low - slack, low +
    share]``, what :func:`railcheck.fea.screening.fatigue_bounds` rests on. Planted: the share a tenth
    of the residual's, the test fails."""
    rng = np.random.default_rng(4)
    n, T, k = 3000, 720, 12
    t = np.linspace(0.0, 2.0 * np.pi, T, endpoint=False)
    C = np.column_stack([np.cos((j + 1) * t + rng.uniform(0, 6)) * rng.uniform(0.5, 2.0) for j in range(k)])
    S = rng.normal(size=(6, n, k))
    p = screening.project_history(S, C)
    assert p.sub.eps > 0.05 * np.abs(C).max()  # a real residual
    b = screening.sampled_bounds(p.SP, p.norms, p.vm_norm, p.sub)
    high, low = component_range(S, C)
    tol = 1e-12 * np.abs(high).max()
    assert np.all(high <= b.high + b.slack + tol) and np.all(low >= b.low - b.slack - tol)
    assert np.all(high >= b.high - b.share - tol) and np.all(low <= b.low + b.share + tol)
