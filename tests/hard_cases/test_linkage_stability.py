"""Linkages near and at singular configurations, extreme speeds, random configurations."""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

from railcheck.kinematics.dynamics import inverse_dynamics, power_residual
from railcheck.kinematics.errors import MechanismError, SingularConfigurationError
from railcheck.kinematics.linkage import FourBar, SliderCrank
from railcheck.kinematics.motion import solve_motion

B2, B3, B4 = 0.3, 0.8, 0.7


def ground_for_mu_min(delta):
    """d such that the minimum transmission angle (at crank angle 0) is ``delta``."""
    r = math.sqrt(B3**2 + B4**2 - 2 * B3 * B4 * math.cos(delta))
    return B2 + r


def ground_for_mu_max(delta):
    """d such that the maximum transmission angle (at crank angle 180 deg) is pi - delta."""
    r = math.sqrt(B3**2 + B4**2 - 2 * B3 * B4 * math.cos(math.pi - delta))
    return r - B2


@pytest.mark.parametrize("delta", [1e-2, 1e-4, 1e-6])
@pytest.mark.parametrize("which", ["min", "max"])
def test_approaching_a_toggle_stays_finite_continuous_and_named(delta, which):
    d = ground_for_mu_min(delta) if which == "min" else ground_for_mu_max(delta)
    lk = FourBar(B2, B3, B4, d)
    m = solve_motion(lk, 2 * math.pi, 4001)
    dyn = inverse_dynamics(m, "newton-euler")
    for arr in (m.theta, m.omega, m.alpha, dyn.torque, *dyn.reactions.values()):
        assert np.all(np.isfinite(arr))
    # closure holds to rounding even beside the toggle
    B, A, O4 = m.points["B"], m.points["A"], m.points["O4"]
    assert np.max(np.abs(np.hypot(*(B - A).T) - B3)) < 1e-12
    assert np.max(np.abs(np.hypot(*(B - O4).T) - B4)) < 1e-12
    # continuous: no branch jump between steps (the crank moves 0.09 deg a step)
    assert np.max(np.abs(np.diff(np.unwrap(m.theta[:, 1])))) < 0.05
    assert np.max(np.abs(np.diff(np.unwrap(m.theta[:, 2])))) < 0.05
    # the report names the singular crank angle and the transmission angle there
    angle = "0" if which == "min" else "180"
    assert any(f"crank angle {angle} deg" in w for w in m.warnings), m.warnings
    # the extreme transmission angle is resolved to ~1e-9 rad even at delta = 1e-6
    mu = m.transmission_angle
    extreme = mu.min() if which == "min" else math.pi - mu.max()
    assert extreme == pytest.approx(delta, rel=1e-3)


@pytest.mark.parametrize("which", ["min", "max"])
def test_reactions_grow_as_the_toggle_nears_but_stay_finite(which):
    peaks = []
    for delta in (1e-2, 1e-3, 1e-4):
        d = ground_for_mu_min(delta) if which == "min" else ground_for_mu_max(delta)
        dyn = inverse_dynamics(solve_motion(FourBar(B2, B3, B4, d), 2 * math.pi, 2001), "newton-euler")
        peaks.append(dyn.peak("O4")[0])
    assert peaks[0] < peaks[1] < peaks[2] < 1e15


@pytest.mark.parametrize("which", ["min", "max"])
def test_inside_the_singular_set_is_refused(which):
    d = B2 + (B3 - B4) if which == "min" else (B3 + B4) - B2  # exactly aligned / folded
    with pytest.raises(MechanismError) as info:
        solve_motion(FourBar(B2, B3, B4, d), 2 * math.pi, 1000)
    assert "crank angle" in str(info.value)


@pytest.mark.parametrize(
    "lengths,angle",
    [
        ((0.3, 0.5, 0.4, 0.6), math.pi),  # 300 + 600 = 500 + 400: folds straight at 180 deg
        ((0.2, 0.7, 0.4, 0.5), 0.0),  # 200 + 700 = 400 + 500: d - b2 = b3 - b4 at 0 deg
    ],
)
def test_grashof_change_point_is_refused_naming_the_angle(lengths, angle):
    with pytest.raises(SingularConfigurationError) as info:
        solve_motion(FourBar(*lengths), 2 * math.pi, 1000)
    assert info.value.crank_angle_rad == angle
    assert "change point" in str(info.value)
    assert f"crank angle {round(math.degrees(angle))} deg" in str(info.value)


@pytest.mark.parametrize("eps", [1e-2, 1e-4, 1e-6])
def test_slidercrank_crank_approaching_coupler(eps):
    lk = SliderCrank(0.8 * (1 - eps), 0.8)
    m = solve_motion(lk, 2 * math.pi, 4001)
    dyn = inverse_dynamics(m, "newton-euler")
    assert all(np.all(np.isfinite(r)) for r in dyn.reactions.values())
    assert np.max(np.abs(np.hypot(*(m.points["B"] - m.points["A"]).T) - 0.8)) < 1e-12
    with pytest.raises(SingularConfigurationError):
        solve_motion(SliderCrank(0.8, 0.8), 2 * math.pi, 100)


def test_zero_speed_is_statics_exactly():
    dyn = inverse_dynamics(solve_motion(FourBar(0.48, 0.84, 0.78, 1.02), 0.0, 361), "newton-euler")
    assert all(np.all(r == 0.0) for r in dyn.reactions.values()) and np.all(dyn.torque == 0.0)


@pytest.mark.parametrize("hz", [0.01, 100.0, 10_000.0])
def test_reactions_scale_with_omega_squared_at_extreme_speeds(hz):
    lk = FourBar(0.48, 0.84, 0.78, 1.02)
    base = inverse_dynamics(solve_motion(lk, 2 * math.pi, 500), "newton-euler")
    fast = inverse_dynamics(solve_motion(lk, 2 * math.pi * hz, 500), "newton-euler")
    for j in base.reactions:
        np.testing.assert_allclose(
            fast.reactions[j], hz**2 * base.reactions[j], rtol=1e-11, atol=1e-11 * hz**2 * np.abs(base.reactions[j]).max()
        )
    np.testing.assert_allclose(fast.torque, hz**2 * base.torque, rtol=1e-11, atol=1e-11 * hz**2 * np.abs(base.torque).max())


lengths = st.floats(0.05, 2.0)


@given(b2=st.floats(0.05, 0.6), b3=lengths, b4=lengths, d=lengths, crossed=st.booleans())
# the assume()s below define the domain (a crank that revolves, away from toggles); on some
# seeds they reject more draws than hypothesis's health check allows (it failed a CI-like
# run once: FailedHealthCheck filter_too_much, not a wrong result), so that check is off
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
def test_random_assemblable_fourbars(b2, b3, b4, d, crossed):
    lk = FourBar(b2, b3, b4, d, "crossed" if crossed else "open")
    # keep configurations whose crank revolves at least 1e-4 rad away from a toggle
    r_min, r_max = abs(d - b2), d + b2
    assume(abs(b3 - b4) < r_min and r_max < b3 + b4)
    mu_min = math.acos(max(-1, min(1, (b3**2 + b4**2 - r_min**2) / (2 * b3 * b4))))
    mu_max = math.acos(max(-1, min(1, (b3**2 + b4**2 - r_max**2) / (2 * b3 * b4))))
    assume(mu_min > 1e-4 and math.pi - mu_max > 1e-4)
    m = solve_motion(lk, 2 * math.pi, 721)
    A, B = m.points["A"], m.points["B"]
    assert np.max(np.abs(np.hypot(*(B - A).T) - b3)) < 1e-12
    assert np.max(np.abs(np.hypot(*(B - m.points["O4"]).T) - b4)) < 1e-12
    dyn = inverse_dynamics(m, "newton-euler")
    assert not any(np.isnan(r).any() for r in dyn.reactions.values())
    power = np.abs(dyn.torque * m.omega[:, 0]).max()
    assert np.abs(power_residual(m, dyn)).max() <= 1e-8 * power + 1e-12


@given(b2=lengths, b3=lengths, b4=lengths, d=lengths)
@example(b2=2.0, b3=1.9999999999999998, b4=0.18268109930324344, d=0.18268109930324344)  # one ulp short
@settings(max_examples=150, deadline=None)
def test_random_non_assemblable_fourbars_are_refused(b2, b3, b4, d):
    r_min, r_max = abs(d - b2), d + b2
    assume(not (abs(b3 - b4) <= r_min and r_max <= b3 + b4))
    with pytest.raises(MechanismError) as info:
        solve_motion(FourBar(b2, b3, b4, d), 2 * math.pi, 100)
    assert info.value.field.startswith("mechanism")
    reasons = ["assembled", "revolution"]
    # within rounding of the assembly limit (b2 = 2.0, b3 = 2.0 - 2e-16, b4 = d: short by
    # one ulp) the linkage is at its Grashof change point, and is refused as that
    gap = min(abs(d - b2) - abs(b3 - b4), b3 + b4 - (d + b2))
    if abs(gap) <= 1e-12 * max(b2, b3, b4, d):
        reasons.append("change point")
    assert any(reason in info.value.message for reason in reasons), info.value.message
