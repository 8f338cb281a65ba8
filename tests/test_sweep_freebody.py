"""`support = "free-body"` in the sweep: each rail a free body (no clamp), its far joint's
bolts sharing the joint force by the lever rule about the joint (so one unit-case set per
bar length, not per hole pair), its deflection relative to its joints, its modes pinned at
its joints, and the dynamics with the free-body mass model. Every figure of a sweep row is
compared with `railcheck check` of that setting, an independent path (one setting's load
model, unit cases, solve, modes and cycle)."""

import numpy as np
import pytest
from test_sweep import FE_SWEEP, _check_scene, _rows, _sweep

from railcheck.check.pipeline import run_pipeline
from railcheck.errors import InputError
from railcheck.scene import parse_scene


def _text(effects: str) -> str:
    return FE_SWEEP.replace("parts = [", f'support = "free-body"\neffects = {effects}\nparts = [')


@pytest.mark.slow
@pytest.mark.parametrize("effects", ['["inertia"]', '["inertia", "dynamic"]'])
def test_a_free_body_sweep_row_equals_the_free_body_check_of_that_setting(tmp_path, effects):
    text = _text(effects)
    rows = _rows(_sweep(tmp_path, text, serial=True))
    passing = np.flatnonzero(rows["checks_passed"])
    assert passing.size >= 2
    for i in passing[[0, -1]]:
        row = {k: v[i] for k, v in rows.items()}
        result = run_pipeline(_check_scene(row, 1.0, text), jobs=1)
        free = [n for n, p in result.parts.items() if p.job.free_body is not None]
        assert free == ["crank-rail", "coupler-rail", "rocker-rail"]
        for name, part in result.parts.items():
            env, fat = part.cycle.envelope, part.cycle.fatigue
            assert row[f"{name}_stress_MPa"] * 1e6 == pytest.approx(env.max_von_mises, rel=1e-9), name
            assert row[f"{name}_fatigue"] == pytest.approx(fat.min_safety_factor, rel=1e-9), name
            assert row[f"{name}_tip_mm"] / 1e3 == pytest.approx(env.max_tip, rel=1e-9, abs=1e-15), name
            assert row[f"{name}_utilisation"] == pytest.approx(part.utilisation, rel=1e-9), name
            if part.cycle.dynamic is not None and f"{name}_amplification" in row:
                amp = part.cycle.dynamic.amplification
                assert row[f"{name}_amplification"] == pytest.approx(amp, rel=1e-9), name


def test_the_free_body_sweep_is_for_the_four_bar():
    text = _text('["inertia"]').replace('kind = "four-bar"', 'kind = "both"')
    with pytest.raises(InputError) as info:
        from railcheck.sweep.run import validate

        validate(parse_scene(__import__("tomllib").loads(text), "test"))
    assert info.value.field == "check.support" and "four-bar" in str(info.value)
