"""The effect ``dynamic`` in the sweep: each rail's modes per hole pair (the far joint's
carried mass sits at the pair's holes), the mode-acceleration response of every setting
at every speed, the amplification as a criterion, and a safe speed that keeps it within
the limit. Every figure is compared with ``railcheck check`` of the same setting, an
independent path (one hole pair, its own mesh solve, modes and cycle evaluation). The
rails are clamped (the 2013 model), whose coupler, a cantilever carrying its far joint's
mass, passes at 0.5 Hz and fails on its amplification at 1.5 Hz: the criterion's both
sides (the free bodies' dynamic sweep: test_sweep_freebody.py). On the solid section,
before the grooved profile, it still passed at 1 Hz; the grooves lowered its safe speed
to 0.85 Hz."""

import math

import numpy as np
import pytest

from helpers import FE_SWEEP, check_scene_of_row, run_sweep_text, table_rows
from railcheck.check.pipeline import run_pipeline

ONE_SETTING = (
    FE_SWEEP.replace('crank = ["480 mm", "540 mm"]', 'crank = ["480 mm", "480 mm"]')
    .replace('rocker = ["780 mm", "840 mm"]', 'rocker = ["780 mm", "780 mm"]')
    .replace('ground = ["1020 mm", "1080 mm"]', 'ground = ["1020 mm", "1020 mm"]')
    .replace('speeds = ["1 Hz"]', 'speeds = ["0.5 Hz", "1.5 Hz"]')
    .replace(
        'parts = ["crank-rail", "coupler-rail", "rocker-rail", "PF_4b_006", "PF_4b_003_v2"]',
        'support = "clamped"\neffects = ["inertia", "dynamic"]\n'
        'parts = ["crank-rail", "coupler-rail", "PF_4b_006", "PF_4b_003_v2"]',
    )
)


def _check(row: dict, speed_hz: float):
    """`railcheck check` of the row's setting at ``speed_hz``: clamped, bolts at the
    setting's holes, the sweep's mesh, steps, parts and effects."""
    return run_pipeline(check_scene_of_row(row, speed_hz, ONE_SETTING), jobs=1)


@pytest.fixture(scope="module")
def rows(tmp_path_factory):
    return table_rows(run_sweep_text(tmp_path_factory.mktemp("dyn"), ONE_SETTING, serial=True))


def _row(rows: dict, speed_hz: float) -> dict:
    i = int(np.flatnonzero(np.isclose(rows["speed_Hz"], speed_hz))[0])
    return {k: v[i] for k, v in rows.items()}


@pytest.mark.slow
@pytest.mark.parametrize("speed_hz", [0.5, 1.5])
def test_a_dynamic_sweep_row_equals_the_check_of_that_setting(rows, speed_hz):
    """Stress, fatigue factor, tip and amplification of every part, at both speeds (the
    response is not a rescaling of the first speed's), and the verdict's both sides: the
    coupler passes at 0.5 Hz and fails on its amplification at 1.5 Hz, in the sweep and in
    the check alike."""
    row = _row(rows, speed_hz)
    result = _check(row, speed_hz)
    for name, part in result.parts.items():
        env, fat = part.cycle.envelope, part.cycle.fatigue
        assert row[f"{name}_stress_MPa"] * 1e6 == pytest.approx(env.max_von_mises, rel=1e-9), name
        assert row[f"{name}_fatigue"] == pytest.approx(fat.min_safety_factor, rel=1e-9), name
        assert row[f"{name}_utilisation"] == pytest.approx(part.utilisation, rel=1e-9), name
        if part.cycle.dynamic is not None and f"{name}_amplification" in row:
            assert row[f"{name}_amplification"] == pytest.approx(part.cycle.dynamic.amplification, rel=1e-9), name
    assert "PF_4b_003_v2_amplification" not in row  # constant loads: nothing to respond to
    coupler = result.parts["coupler-rail"]
    assert coupler.cycle.dynamic.amplification > 1.0
    if speed_hz == 0.5:
        assert row["verdict"] == "pass" and coupler.passed
    else:
        assert row["verdict"] == "fail" and "coupler-rail dynamic" in row["reason"]
        assert not coupler.dynamic_passed and coupler.governing_criterion == "dynamic"


@pytest.mark.slow
def test_checking_at_the_dynamic_safe_speed_gives_utilisation_one(rows):
    """The safe speed is searched (scan, then regula falsi): a check at that speed puts the
    governing part and criterion the sweep names exactly at the limit, and the speed lies
    between the passing 0.5 Hz and the failing 1.5 Hz."""
    row = _row(rows, 0.5)
    safe = float(row["safe_speed_Hz"])
    assert 0.5 < safe < 1.5
    result = _check(row, safe)
    u = {name: p.utilisation for name, p in result.parts.items()}
    assert max(u.values()) == pytest.approx(1.0, abs=1e-6)
    governing = max(u, key=u.__getitem__)
    assert (governing, result.parts[governing].governing_criterion) == (
        row["safe_speed_part"],
        row["safe_speed_criterion"],
    )
    assert math.isfinite(safe)
