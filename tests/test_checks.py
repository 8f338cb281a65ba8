"""The configuration checks (railcheck.kinematics.checks) against textbook cases and brute
force: Grashof's classes (Norton, Design of Machinery, 2.13), assembly, the transmission
angle sampled from the motion, the crank-rail collision and the hole grid at their
boundaries, and the single-linkage checks equal to the batch flags."""

import math

import numpy as np
import pytest

from railcheck.kinematics.checks import (
    CheckLimits,
    configuration_checks,
    fourbar_checks_batch,
    grashof_class,
    slidercrank_checks_batch,
    transmission_extremes,
)
from railcheck.kinematics.linkage import FourBar, SliderCrank
from railcheck.kinematics.motion import solve_motion


@pytest.mark.parametrize(
    ("lengths", "expected", "crank_rocker"),
    [
        ((0.2, 0.7, 0.9, 0.6), "Grashof crank-rocker", True),  # s + l = 1.1 < p + q = 1.3, crank shortest
        ((0.6, 0.7, 0.9, 0.2), "Grashof double-crank", False),  # ground shortest
        ((0.6, 0.2, 0.9, 0.7), "Grashof double-rocker", False),  # coupler shortest
        ((0.6, 0.7, 0.2, 0.9), "Grashof rocker-crank", False),  # rocker shortest
        ((0.5, 0.6, 0.7, 0.9), "non-Grashof (triple rocker)", False),  # s + l = 1.4 > 1.3
        ((0.4, 0.6, 0.7, 0.5), "change-point (s + l = p + q)", False),  # 1.1 = 1.1
    ],
)
def test_grashof_classes_of_textbook_linkages(lengths, expected, crank_rocker):
    assert grashof_class(FourBar(*lengths)) == expected
    flags = fourbar_checks_batch(*(np.array([x]) for x in lengths))
    assert bool(flags["grashof"][0]) is crank_rocker


def test_assembly_is_strict_at_the_flat_linkage():
    """The longest bar must be shorter than the sum of the others: equal is a flat,
    locked linkage."""
    flat = fourbar_checks_batch(np.array([0.25]), np.array([0.25]), np.array([0.5]), np.array([1.0]))
    almost = fourbar_checks_batch(np.array([0.25]), np.array([0.25]), np.array([0.5]), np.array([0.999]))
    assert not flat["assembly"][0] and almost["assembly"][0]


@pytest.mark.parametrize("lengths", [(0.48, 0.84, 0.78, 1.02), (0.18, 0.24, 0.72, 0.72), (0.3, 0.9, 0.6, 0.84)])
def test_fourbar_transmission_extremes_equal_the_motion_sampled_densely(lengths):
    """mu between coupler and rocker at B, from the joint positions at 100,001 crank
    angles, against the closed form (crank at 0 and 180 deg) and the batch flags."""
    linkage = FourBar(*lengths)
    motion = solve_motion(linkage, 1.0, 100_001)
    a, b, o4 = motion.points["A"], motion.points["B"], motion.points["O4"]
    u, v = a - b, o4 - b
    mu = np.arccos(np.einsum("ij,ij->i", u, v) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1))
    lo, hi = transmission_extremes(linkage)
    assert lo == pytest.approx(mu.min(), abs=1e-8) and hi == pytest.approx(mu.max(), abs=1e-8)
    flags = fourbar_checks_batch(*(np.array([x]) for x in lengths))
    assert (flags["mu_min"][0], flags["mu_max"][0]) == pytest.approx((lo, hi), abs=1e-12)
    ok = math.radians(35) < lo and hi < math.radians(145)
    assert bool(flags["transmission_angle"][0]) is ok


def test_transmission_limits_are_strict():
    """35 < mu_min and mu_max < 145 deg: a linkage exactly at a limit fails it."""
    limits_at = CheckLimits(mu_min=math.radians(38.71916), mu_max=math.radians(150.0))
    lo, _ = transmission_extremes(FourBar(0.48, 0.84, 0.78, 1.02))
    exact = CheckLimits(mu_min=lo, mu_max=math.radians(150.0))
    args = (np.array([0.48]), np.array([0.84]), np.array([0.78]), np.array([1.02]))
    assert fourbar_checks_batch(*args, limits_at)["transmission_angle"][0]
    assert not fourbar_checks_batch(*args, exact)["transmission_angle"][0]


def test_crank_rail_collision_and_hole_grid_at_their_boundaries():
    """d must exceed 660 mm (equal collides); a length is on the 60 mm grid within 1 um."""
    base = dict(crank=np.array([0.48]), coupler=np.array([0.84]), rocker=np.array([0.78]))
    assert not fourbar_checks_batch(**base, ground=np.array([0.66]))["crank_rail_collision"][0]
    assert fourbar_checks_batch(**base, ground=np.array([0.6601]))["crank_rail_collision"][0]
    on = fourbar_checks_batch(np.array([0.4800009]), base["coupler"], base["rocker"], np.array([1.02]))
    off = fourbar_checks_batch(np.array([0.4800011]), base["coupler"], base["rocker"], np.array([1.02]))
    assert on["hole_grid"][0] and not off["hole_grid"][0]
    below = fourbar_checks_batch(np.array([0.4799991]), base["coupler"], base["rocker"], np.array([1.02]))
    assert below["hole_grid"][0]
    for bar in ("coupler", "rocker"):  # every bar is on the grid, not only the crank
        args = {**base, "ground": np.array([1.02])}
        args[bar] = args[bar] + 0.01
        assert not fourbar_checks_batch(**args)["hole_grid"][0]
    assert not fourbar_checks_batch(**base, ground=np.array([1.03]))["hole_grid"][0]


def test_slider_crank_flags_at_their_boundaries():
    """Assembly: crank + |offset| < coupler; the crank shorter than the coupler; the grid
    on crank and coupler only (any offset)."""
    f = slidercrank_checks_batch(
        np.array([0.3, 0.3, 0.3, 0.6]), np.array([0.6, 0.6, 0.6, 0.6]), np.array([0.3, 0.29, -0.29, 0.0])
    )
    assert list(f["assembly"]) == [False, True, True, False]
    assert list(f["crank_shorter_than_coupler"]) == [True, True, True, False]
    assert list(f["hole_grid"]) == [True, True, True, True]
    g = slidercrank_checks_batch(np.array([0.31]), np.array([0.6]), np.array([0.0123]))
    assert not g["hole_grid"][0]


@pytest.mark.parametrize(
    "linkage",
    [
        FourBar(0.48, 0.84, 0.78, 1.02),
        FourBar(0.54, 0.84, 0.78, 1.02),
        FourBar(0.5, 0.6, 0.7, 0.9),
        FourBar(0.48, 0.84, 0.78, 0.6),
        SliderCrank(0.48, 0.84, 0.05),
        SliderCrank(0.3, 0.6, 0.0),
    ],
)
def test_each_named_check_equals_the_batch_flag(linkage):
    """configuration_checks (one linkage, with messages) reads the same flags as the sweep."""
    checks = configuration_checks(linkage)
    if isinstance(linkage, FourBar):
        flags = fourbar_checks_batch(
            *(np.array([x]) for x in (linkage.crank, linkage.coupler, linkage.rocker, linkage.ground))
        )
    else:
        flags = slidercrank_checks_batch(np.array([linkage.crank]), np.array([linkage.coupler]), np.array([linkage.offset]))
    for name, result in checks.items():
        if name in flags:
            assert result.ok == bool(flags[name][0]), name
            assert result.message


def test_near_ties_frozen_records_and_exact_limits():
    """Grashof's change point within rounding (1e-14 m) is a tie, not a crank-rocker; the
    grid tolerance is 1 um, not more; every transmission limit is strict; the records are
    frozen."""
    import dataclasses

    near = (0.4, 0.6, 0.7, 0.5 + 1e-14)  # s + l a hair below p + q: a change point to rounding
    assert grashof_class(FourBar(*near)) == "change-point (s + l = p + q)"
    assert not fourbar_checks_batch(*(np.array([x]) for x in near))["grashof"][0]
    just_off = fourbar_checks_batch(np.array([0.48000105]), np.array([0.84]), np.array([0.78]), np.array([1.02]))
    assert not just_off["hole_grid"][0]
    lo, hi = transmission_extremes(FourBar(0.48, 0.84, 0.78, 1.02))
    args = (np.array([0.48]), np.array([0.84]), np.array([0.78]), np.array([1.02]))
    assert not fourbar_checks_batch(*args, CheckLimits(mu_min=0.1, mu_max=hi))["transmission_angle"][0]
    slo, _ = transmission_extremes(SliderCrank(0.3, 0.6, 0.0))
    sargs = (np.array([0.3]), np.array([0.6]), np.array([0.0]))
    assert not slidercrank_checks_batch(*sargs, CheckLimits(mu_min=slo))["transmission_angle"][0]
    assert slidercrank_checks_batch(*sargs, CheckLimits(mu_min=slo - 1e-9))["transmission_angle"][0]
    with pytest.raises(dataclasses.FrozenInstanceError):
        CheckLimits().mu_min = 0.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        configuration_checks(FourBar(0.48, 0.84, 0.78, 1.02))["assembly"].ok = False


def test_the_messages_state_the_values_in_mm():
    """What the console and the summary print: the assembly's longest bar and the sum of the
    others, each bar off the grid with its length, and a linkage that does not close."""
    ok = configuration_checks(FourBar(0.48, 0.84, 0.78, 1.02))
    assert "longest bar (ground) 1020 mm vs sum of the others 2100 mm" in ok["assembly"].message
    off = configuration_checks(FourBar(0.48, 0.845, 0.78, 1.02))
    assert not off["hole_grid"].ok and "coupler 845 mm" in off["hole_grid"].message
    assert "crank 480" not in off["hole_grid"].message  # only the bars off the grid
    slider = configuration_checks(SliderCrank(0.3, 0.6, 0.0123))
    assert slider["hole_grid"].ok  # the offset is not on a rail's grid
    locked = configuration_checks(FourBar(0.25, 0.25, 0.5, 1.0))
    assert not locked["assembly"].ok and not locked["transmission_angle"].ok
