"""Closed-form kinematics: loop closure, finite differences, assembly modes."""

import math

import numpy as np
import pytest

from railcheck.kinematics.linkage import FourBar, SliderCrank
from railcheck.kinematics.motion import solve_motion, triangle_angle

CONFIGS = [(0.48, 0.84, 0.78, 1.02), (0.54, 0.9, 0.78, 1.058), (0.18, 0.24, 0.72, 0.72), (0.3, 0.9, 0.5, 0.8)]


@pytest.mark.parametrize("lengths", CONFIGS)
@pytest.mark.parametrize("assembly", ["open", "crossed"])
def test_fourbar_loop_closure(lengths, assembly):
    lk = FourBar(*lengths, assembly=assembly)
    m = solve_motion(lk, 2 * math.pi, 5000)
    A, B, O4 = m.points["A"], m.points["B"], m.points["O4"]
    assert np.max(np.abs(np.hypot(*(A - m.points["O2"]).T) - lk.crank)) < 1e-12
    assert np.max(np.abs(np.hypot(*(B - A).T) - lk.coupler)) < 1e-12
    assert np.max(np.abs(np.hypot(*(B - O4).T) - lk.rocker)) < 1e-12
    # the vector loop of seed eq. (3.2.3): b2 e2 + b3 e3 - b4 e4 - d x = 0
    th = m.theta
    loop = (
        lk.crank * np.stack([np.cos(th[:, 0]), np.sin(th[:, 0])], 1)
        + lk.coupler * np.stack([np.cos(th[:, 1]), np.sin(th[:, 1])], 1)
        - lk.rocker * np.stack([np.cos(th[:, 2]), np.sin(th[:, 2])], 1)
        - [lk.ground, 0]
    )
    assert np.max(np.abs(loop)) < 1e-12


def _fd_check(motion, key_pos, key_vel, h):
    """Central differences in time of a quantity sampled on the crank grid."""
    pos = key_pos(motion)
    vel = key_vel(motion)
    d = (pos[2:] - pos[:-2]) / (2 * h)
    scale = np.max(np.abs(vel))
    return np.max(np.abs(d - vel[1:-1])) / scale


@pytest.mark.parametrize("lengths", CONFIGS)
def test_fourbar_velocities_and_accelerations_match_finite_differences(lengths):
    lk = FourBar(*lengths)
    w = 2 * math.pi * 1.7
    m = solve_motion(lk, w, 20001)
    h = (m.theta2[1] - m.theta2[0]) / w
    unwrap = lambda mm: np.unwrap(mm.theta, axis=0)  # noqa: E731
    assert _fd_check(m, unwrap, lambda mm: mm.omega, h) < 1e-6
    assert _fd_check(m, lambda mm: mm.omega, lambda mm: mm.alpha, h) < 1e-6
    for p in ("A", "B"):
        assert _fd_check(m, lambda mm, p=p: mm.points[p], lambda mm, p=p: mm.velocities[p], h) < 1e-6
        assert _fd_check(m, lambda mm, p=p: mm.velocities[p], lambda mm, p=p: mm.accelerations[p], h) < 1e-6


def test_crossed_is_the_mirror_of_open():
    """The crossed assembly driven at +omega is the open one mirrored in the ground line
    and driven backwards: crank angle -theta2, B mirrored in y."""
    lk = (0.48, 0.84, 0.78, 1.02)
    op = solve_motion(FourBar(*lk, "open"), 2 * math.pi, 3601)
    cr = solve_motion(FourBar(*lk, "crossed"), 2 * math.pi, 3601)
    # step k of crossed (theta2_k) mirrors step -k of open (theta2 = 2 pi - theta2_k)
    Bo = op.points["B"][::-1]
    Bc = cr.points["B"]
    assert np.allclose(Bc[:, 0], Bo[:, 0], atol=1e-12)
    assert np.allclose(Bc[:, 1], -Bo[:, 1], atol=1e-12)
    # theta_cr(t) = -theta_open(-t): omega keeps its sign, alpha changes it
    assert np.allclose(cr.omega[:, 1:], op.omega[::-1, 1:], atol=1e-9)
    assert np.allclose(cr.alpha[:, 1:], -op.alpha[::-1, 1:], atol=1e-8)


def test_open_assembly_is_convex_at_quarter_turn():
    m = solve_motion(FourBar(0.48, 0.84, 0.78, 1.02, "open"), 1.0, 5)
    A, B = m.points["A"][1], m.points["B"][1]  # theta2 = 90 deg
    assert A[1] > 0 and B[1] > 0  # B above the ground line


@pytest.mark.parametrize("offset", [0.0, 0.05, -0.1])
def test_slidercrank_closure_and_finite_differences(offset):
    lk = SliderCrank(0.3, 0.8, offset)
    w = 2 * math.pi
    m = solve_motion(lk, w, 20001)
    A, B = m.points["A"], m.points["B"]
    assert np.max(np.abs(np.hypot(*(B - A).T) - lk.coupler)) < 1e-12
    assert np.max(np.abs(B[:, 1] - offset)) == 0.0
    h = (m.theta2[1] - m.theta2[0]) / w
    assert _fd_check(m, lambda mm: mm.points["B"], lambda mm: mm.velocities["B"], h) < 1e-6
    assert _fd_check(m, lambda mm: mm.velocities["B"], lambda mm: mm.accelerations["B"], h) < 1e-6
    assert _fd_check(m, lambda mm: np.unwrap(mm.theta, axis=0), lambda mm: mm.omega, h) < 1e-6
    # zero offset: slider position x = b2 cos + sqrt(b3^2 - b2^2 sin^2) exactly
    if offset == 0.0:
        th = m.theta2
        x = 0.3 * np.cos(th) + np.sqrt(0.8**2 - (0.3 * np.sin(th)) ** 2)
        assert np.max(np.abs(B[:, 0] - x)) < 1e-14


def test_triangle_angle_is_accurate_for_needles():
    # right angle, equilateral, and a needle whose angle is known to high accuracy
    assert triangle_angle(3.0, 4.0, 5.0) == pytest.approx(math.pi / 2, rel=1e-15)
    assert triangle_angle(1.0, 1.0, 1.0) == pytest.approx(math.pi / 3, rel=1e-15)
    eps = 1e-7
    c = 2 * math.sin(eps / 2)  # isosceles, sides 1, 1, apex angle eps
    assert triangle_angle(1.0, 1.0, c) == pytest.approx(eps, rel=1e-9)
    assert math.isnan(float(triangle_angle(1.0, 1.0, 3.0)))
