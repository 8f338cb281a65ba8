"""The sweep's speed scaling without a constant load (the clamped crank rail: no gravity, no
table-top weight; inertia loads grow with the speed squared):
a second speed's row is the first's scaled (stress x s, fatigue factor / s, tip x s with
s the squared speed ratio) and equals ``railcheck check`` of that setting at that speed;
the closed-form safe speed puts every setting's governing part exactly at its limit."""

import tomllib

import numpy as np
import pytest

from helpers import COARSE_RAILS, check_scene_of_row, run_sweep_text, sweep_table, table_rows, utilisation_at_safe_speed
from railcheck.check.pipeline import run_pipeline
from railcheck.scene import parse_scene
from railcheck.sweep.run import run_sweep
from railcheck.sweep.table import read_table

MESH = """
[mesh]
size = "20 mm"
hole_size = "6 mm"
"""

SWEEP = (
    """
[sweep]
kind = "four-bar"
speeds = ["1 Hz", "2 Hz"]
steps = 90
crank = ["420 mm", "480 mm"]
coupler = ["840 mm", "840 mm"]
rocker = ["780 mm", "780 mm"]
ground = ["1020 mm", "1020 mm"]
[check]
parts = ["crank-rail"]
"""
    + MESH
)
#: the scaling fixture's sweep: the 2013 clamp, which carries no table-top weight, so every load
#: grows with the speed squared (a free rail's constant weight makes the search exact instead)
#: (cranks 360 and 420 mm: a clamped 480 mm crank's certificate no longer holds at 1 Hz)
SCALING = (
    SWEEP.replace('parts = ["crank-rail"]', 'parts = ["crank-rail"]\nsupport = "clamped"')
    .replace('crank = ["420 mm", "480 mm"]', 'crank = ["360 mm", "420 mm"]')
    .replace('speeds = ["1 Hz", "2 Hz"]', 'speeds = ["1 Hz", "1.15 Hz", "2 Hz"]')
)

#: the scaling fixture's speeds (Hz): the certificate holds at the first two (the second
#: below both settings' safe speeds, 1.22 and 1.53 Hz), not at the third
SPEEDS = (1.0, 1.15, 2.0)


def _check(row: dict, speed_hz: float, text: str = SCALING):
    """``railcheck check`` of a sweep row's setting at ``speed_hz``: bolts at the
    setting's holes, as the sweep loads them, and the sweep's mesh, support and steps."""
    return run_pipeline(check_scene_of_row(row, speed_hz, text, steps=90)).parts["crank-rail"]


@pytest.fixture(scope="module")
def rows(tmp_path_factory):
    run = run_sweep(parse_scene(tomllib.loads(SCALING), "test"), str(tmp_path_factory.mktemp("speeds") / "s"), serial=True)
    table = read_table(run.tables["four-bar"])
    out = {k: np.asarray(v.to_numpy(zero_copy_only=False)) for k, v in zip(table.column_names, table.columns)}
    assert out["setting"].size == 6 and list(out["speed_Hz"]) == [*SPEEDS, *SPEEDS]  # setting-major
    assert out["checks_passed"].all()
    return out


@pytest.mark.slow  # its fixture's free-body sweep, 5.5 s cold since the pin pressures: out of the fast tier
def test_the_second_speed_is_the_first_scaled_by_the_speed_squared(rows):
    one, two = (np.flatnonzero(rows["speed_Hz"] == hz) for hz in SPEEDS[:2])
    s = (SPEEDS[1] / SPEEDS[0]) ** 2
    np.testing.assert_allclose(rows["crank-rail_stress_MPa"][two], s * rows["crank-rail_stress_MPa"][one], rtol=1e-12)
    np.testing.assert_allclose(rows["crank-rail_fatigue"][two], rows["crank-rail_fatigue"][one] / s, rtol=1e-12)
    np.testing.assert_allclose(rows["crank-rail_tip_mm"][two], s * rows["crank-rail_tip_mm"][one], rtol=1e-12)
    # the utilisation scales too: within its tolerance the estimate is no criterion of the row
    est = rows["crank-rail_amplification_estimate"]
    assert np.all(est[one] <= 1.05) and np.all(est[two] <= 1.05)
    np.testing.assert_allclose(rows["utilisation"][two], s * rows["utilisation"][one], rtol=1e-12)
    assert not rows["exact_dynamic"][one].any() and not rows["exact_dynamic"][two].any()
    # the safe speed is a property of the setting, the same on every row
    for hz in SPEEDS[1:]:
        np.testing.assert_array_equal(rows["safe_speed_Hz"][rows["speed_Hz"] == hz], rows["safe_speed_Hz"][one])


@pytest.mark.slow  # the same fixture: out of the fast tier
def test_a_row_beyond_the_certificates_tolerance_gets_the_exact_response_not_a_quasi_static_fail(rows):
    """At 2 Hz the clamped crank's estimate exceeds its tolerance at both settings: the row
    is the exact dynamic response (flagged), failing only on a real criterion: the shorter
    crank passes there, the longer fails on its stress, fatigue and amplification, never
    on ``quasi-static``."""
    three = np.flatnonzero(rows["speed_Hz"] == SPEEDS[2])
    assert rows["exact_dynamic"][three].all()
    assert all("quasi-static" not in (r or "") for r in rows["reason"][three])
    assert list(rows["verdict"][three]) == ["pass", "fail"]
    assert "crank-rail dynamic" in rows["reason"][three[1]]
    assert np.all(rows["crank-rail_amplification_estimate"][three] > 1.05)  # the estimate, kept
    assert np.all(rows["crank-rail_amplification"][three] > 1.0)  # the exact amplification beside it
    assert np.all(np.isnan(rows["crank-rail_amplification"][rows["speed_Hz"] < 2.0]))  # null where not settled


@pytest.mark.slow  # the same fixture, and a check: out of the fast tier
def test_a_second_speed_row_equals_check_at_that_speed(rows):
    """At 1 Hz (the certificate holds) the row is the check's quasi-static verdict; at 2 Hz
    the check computes the dynamic response (its certificate fails, as the row's does) and
    the row's stress is that response's quasi-static peak."""
    i = int(np.flatnonzero(rows["speed_Hz"] == 1.0)[-1])
    row = {k: v[i] for k, v in rows.items()}
    part = _check(row, 1.0)
    assert part.job.certificate.holds and part.cycle.dynamic is None
    assert row["crank-rail_stress_MPa"] * 1e6 == pytest.approx(part.cycle.envelope.max_von_mises, rel=1e-9)
    assert row["crank-rail_fatigue"] == pytest.approx(part.cycle.fatigue.min_safety_factor, rel=1e-9)
    assert row["crank-rail_tip_mm"] / 1e3 == pytest.approx(part.cycle.envelope.max_tip, rel=1e-9)
    assert row["crank-rail_amplification_estimate"] == pytest.approx(part.job.certificate.estimate, rel=1e-9)
    j = int(np.flatnonzero(rows["speed_Hz"] == 2.0)[-1])
    row = {k: v[j] for k, v in rows.items()}
    part = _check(row, 2.0)
    assert not part.job.certificate.holds and part.cycle.dynamic is not None  # the check's exact response
    assert row["exact_dynamic"]  # and the row's
    assert row["crank-rail_stress_MPa"] * 1e6 == pytest.approx(part.cycle.envelope.max_von_mises, rel=1e-9)
    assert row["crank-rail_fatigue"] == pytest.approx(part.cycle.fatigue.min_safety_factor, rel=1e-9)
    assert row["crank-rail_tip_mm"] / 1e3 == pytest.approx(part.cycle.envelope.max_tip, rel=1e-9)
    assert row["crank-rail_utilisation"] == pytest.approx(max(part.utilisations.values()), rel=1e-9)
    assert row["crank-rail_amplification"] == pytest.approx(part.cycle.dynamic.amplification, rel=1e-9)
    assert row["crank-rail_amplification_estimate"] == pytest.approx(part.job.certificate.estimate, rel=1e-9)
    assert (row["verdict"] == "pass") == part.passed


@pytest.mark.slow
def test_checking_each_setting_at_its_safe_speed_puts_it_at_its_limit(rows):
    """Two settings: at the safe speed the governing utilisation as the sweep reads it
    (stress / limit or required / fatigue factor times the certificate's estimate, or the
    estimate's share of its tolerance) is 1, by a check that knows nothing of the sweep's
    search; the check passes there."""
    first = np.flatnonzero(rows["speed_Hz"] == 1.0)
    assert len(set(rows["safe_speed_Hz"][first])) == 2
    for i in first:
        row = {k: v[i] for k, v in rows.items()}
        part = _check(row, float(row["safe_speed_Hz"]))
        assert utilisation_at_safe_speed(part) == pytest.approx(1.0, abs=1e-7) and part.passed


def _sweep_rows(tmp_path, text: str) -> dict:
    run = run_sweep(parse_scene(tomllib.loads(text), "test"), str(tmp_path / "s"), serial=True)
    table = read_table(run.tables["four-bar"])
    return {k: np.asarray(v.to_numpy(zero_copy_only=False)) for k, v in zip(table.column_names, table.columns)}


@pytest.mark.slow
def test_a_constant_load_part_that_fails_at_rest_gives_a_safe_speed_of_zero(tmp_path):
    """A plate under explicit (speed-independent) loads above its limit fails at every
    speed: safe speed 0, verdict fail naming it; the speed-dependent crank rail does not
    hide it (the worst constant part counts, not the first)."""
    text = (
        SWEEP.replace('crank = ["420 mm", "480 mm"]', 'crank = ["480 mm", "480 mm"]')
        .replace('speeds = ["1 Hz", "2 Hz"]', 'speeds = ["1 Hz"]')
        .replace('parts = ["crank-rail"]', 'parts = ["crank-rail", "PF_4b_006", "PF_4b_003_v2"]\nlimit = "75 MPa"')
        + '[loads.PF_4b_006]\nlongitudinal = "1 N"\ntransverse = "1 N"\n'
        + '[loads.PF_4b_003_v2]\nlongitudinal = "250 N"\ntransverse = "250 N"\n'
    )
    rows = _sweep_rows(tmp_path, text)
    # just over: the bracket on its foundation reads 77.8 MPa on this mesh (the 2013 clamp between 65 and 71.5)
    assert 75 < rows["PF_4b_003_v2_stress_MPa"][0] < 1.1 * 75 and rows["PF_4b_006_stress_MPa"][0] < 75
    assert rows["safe_speed_Hz"][0] == 0.0 and rows["verdict"][0] == "fail"
    assert "PF_4b_003_v2 stress" in rows["reason"][0]


@pytest.mark.slow
def test_a_sweep_with_gravity_equals_check_with_gravity(tmp_path):
    """With gravity the loads are C_g + s C_i (no closed-form scaling): the row equals
    `railcheck check` of the setting with gravity, to 1e-9."""
    text = SWEEP.replace('crank = ["420 mm", "480 mm"]', 'crank = ["480 mm", "480 mm"]').replace(
        'parts = ["crank-rail"]', 'parts = ["crank-rail"]\neffects = ["inertia", "gravity"]'
    )
    rows = _sweep_rows(tmp_path, text)
    i = int(np.flatnonzero(rows["speed_Hz"] == 1.0)[0])  # where the certificate holds: quasi-static
    row = {k: v[i] for k, v in rows.items()}
    check_text = f"""
[mechanism]
kind = "four-bar"
crank = "{row["crank_mm"]:.6f} mm"
coupler = "{row["coupler_mm"]:.6f} mm"
rocker = "{row["rocker_mm"]:.6f} mm"
ground = "{row["ground_mm"]:.6f} mm"
speed = "1 Hz"
steps = 90
[check]
parts = ["crank-rail"]
bolt_position = "actual"
effects = ["inertia", "gravity"]
"""
    part = run_pipeline(parse_scene(tomllib.loads(check_text + MESH), "check")).parts["crank-rail"]
    assert part.job.certificate.holds
    assert row["crank-rail_amplification_estimate"] == pytest.approx(part.job.certificate.estimate, rel=1e-9)
    assert row["crank-rail_stress_MPa"] * 1e6 == pytest.approx(part.cycle.envelope.max_von_mises, rel=1e-9)
    assert row["crank-rail_fatigue"] == pytest.approx(part.cycle.fatigue.min_safety_factor, rel=1e-9)


@pytest.mark.slow  # pin pressures doubled its cost (cold: 6.0 s): out of the fast tier
def test_the_safe_speed_names_the_part_and_criterion_that_reach_their_limit(tmp_path):
    """At 0.25 Hz the constant-load plate governs the utilisation; the safe speed is set by
    the crank rail (whose loads grow with the speed, over its constant table-top weight), and
    the row says so (#24): a check at that speed puts the crank rail's named criterion at
    exactly 1."""
    text = (
        SWEEP.replace('crank = ["420 mm", "480 mm"]', 'crank = ["480 mm", "480 mm"]')
        .replace('speeds = ["1 Hz", "2 Hz"]', 'speeds = ["0.25 Hz"]')
        .replace('parts = ["crank-rail"]', 'parts = ["crank-rail", "PF_4b_003_v2"]')
        + '[loads.PF_4b_003_v2]\nlongitudinal = "250 N"\ntransverse = "250 N"\n'
    )
    rows = _sweep_rows(tmp_path, text)
    row = {k: v[0] for k, v in rows.items()}
    assert row["governing_part"] == "PF_4b_003_v2" and row["governing_criterion"] == "stress"
    assert row["safe_speed_part"] == "crank-rail"
    part = _check(row, float(row["safe_speed_Hz"]), text)
    assert utilisation_at_safe_speed(part, row["safe_speed_criterion"]) == pytest.approx(1.0, abs=1e-7)
    assert utilisation_at_safe_speed(part) == pytest.approx(1.0, abs=1e-7)


@pytest.mark.slow
def test_a_part_without_constant_loads_is_scaled_from_the_first_speed_as_its_evaluation_gives(tmp_path, monkeypatch):
    """Issue 59's whole rig: a part with no constant load part and no dynamic response
    (the joint plate; the rails carry the table-top weight) is evaluated once, at the
    first speed, and every other speed of the safe-speed search scales it (s, 1/s); the
    table equals that of a sweep evaluating it at every speed (a direct solve of the same
    question) to rounding."""
    import railcheck.sweep.chunk as chunk

    ranges = {"crank": (480, 540), "coupler": (840, 840), "rocker": (780, 840), "ground": (1020, 1080)}
    sweep = sweep_table(speeds=("1 Hz", "1.7 Hz"), steps=180, **ranges)  # the second speed's rows scaled
    check = '[check]\nsupport = "free-body"\nparts = ["crank-rail", "PF_4b_006"]\n'
    text = sweep + check + COARSE_RAILS.replace('"7 mm"', '"6 mm"')  # 6 mm: three elements round the plate's holes
    found, real = [], chunk.homogeneous_parts
    monkeypatch.setattr(chunk, "homogeneous_parts", lambda *a: found.append(real(*a)) or found[-1])
    scaled = table_rows(run_sweep_text(tmp_path, text, "scaled", serial=True))
    assert found and all(parts == {"PF_4b_006"} for parts in found)
    monkeypatch.setattr(chunk, "homogeneous_parts", lambda *a: set())
    direct = table_rows(run_sweep_text(tmp_path, text, "direct", serial=True))
    assert np.isfinite(scaled["safe_speed_Hz"]).any() and np.isfinite(scaled["PF_4b_006_fatigue"]).any()
    assert set(scaled["speed_Hz"]) == {1.0, 1.7}
    for key, want in direct.items():
        if want.dtype.kind == "f":
            np.testing.assert_allclose(scaled[key], want, rtol=1e-12, atol=0, err_msg=key)
        else:
            np.testing.assert_array_equal(scaled[key], want, err_msg=key)
