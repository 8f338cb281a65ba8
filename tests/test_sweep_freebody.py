"""`support = "free-body"` in the sweep: each rail a free body (no clamp), its far joint's
bolts sharing the joint force by the lever rule about the joint (so one unit-case set per
bar length, not per hole pair), its deflection relative to its joints, its modes pinned at
its joints, and the dynamics with the free-body mass model. Every figure of a sweep row is
compared with `railcheck check` of that setting, an independent path (one setting's load
model, unit cases, solve, modes and cycle)."""

import numpy as np
import pytest

from helpers import FE_SWEEP, check_scene_of_row, run_sweep_text, table_rows
from railcheck.check.pipeline import run_pipeline


def _text(effects: str) -> str:
    return FE_SWEEP.replace("parts = [", f'support = "free-body"\neffects = {effects}\nparts = [')


@pytest.mark.slow
@pytest.mark.parametrize("effects", ['["inertia"]', '["inertia", "dynamic"]'])
def test_a_free_body_sweep_row_equals_the_free_body_check_of_that_setting(tmp_path, effects):
    text = _text(effects)
    rows = table_rows(run_sweep_text(tmp_path, text, serial=True))
    passing = np.flatnonzero(rows["checks_passed"])
    assert passing.size >= 2
    for i in passing[[0, -1]]:
        row = {k: v[i] for k, v in rows.items()}
        result = run_pipeline(check_scene_of_row(row, 1.0, text), jobs=1)
        free = [n for n, p in result.parts.items() if p.job.free_body is not None]
        # the plate too, and the ground bracket on its foundation
        assert free == ["crank-rail", "coupler-rail", "rocker-rail", "PF_4b_006", "PF_4b_003_v2"]
        for name, part in result.parts.items():
            env, fat = part.cycle.envelope, part.cycle.fatigue
            assert row[f"{name}_stress_MPa"] * 1e6 == pytest.approx(env.max_von_mises, rel=1e-9), name
            assert row[f"{name}_fatigue"] == pytest.approx(fat.min_safety_factor, rel=1e-9), name
            assert row[f"{name}_tip_mm"] / 1e3 == pytest.approx(env.max_tip, rel=1e-9, abs=1e-15), name
            assert row[f"{name}_utilisation"] == pytest.approx(part.utilisation, rel=1e-9), name
            if part.cycle.dynamic is not None and f"{name}_amplification" in row:
                amp = part.cycle.dynamic.amplification
                assert row[f"{name}_amplification"] == pytest.approx(amp, rel=1e-9), name


SLIDER_CRANK = """
[sweep]
kind = "both"
speeds = ["1 Hz"]
steps = 360
crank = ["480 mm", "540 mm"]
coupler = ["840 mm", "840 mm"]
rocker = ["780 mm", "780 mm"]
ground = ["1020 mm", "1020 mm"]
offset = ["0 mm", "0 mm"]

[check]
support = "free-body"
effects = EFFECTS
parts = ["crank-rail", "coupler-rail"]

[mesh]
size = "20 mm"
hole_size = "6 mm"
"""


@pytest.mark.slow
@pytest.mark.parametrize("effects", ['["inertia"]', '["inertia", "dynamic"]'])
def test_a_both_kinds_free_body_sweep_equals_the_check_of_each_kind(tmp_path, effects):
    """kind = "both": the coupler carries a plate and a carriage at B in the four-bar, a
    coupling in the slider-crank (the mass model's CARRIED), so each kind has its own free
    coupler (its joint loads and, with dynamic, its modes): a row of either kind equals
    the free-body check of its setting."""
    text = SLIDER_CRANK.replace("EFFECTS", effects)
    run = run_sweep_text(tmp_path, text, serial=True)
    for kind in ("four-bar", "slider-crank"):
        rows = table_rows(run, kind)
        passing = np.flatnonzero(rows["checks_passed"])
        assert passing.size >= 1, kind
        row = {k: v[passing[-1]] for k, v in rows.items()}
        result = run_pipeline(check_scene_of_row(row, 1.0, text), jobs=1)
        assert result.scene.mechanism.linkage.kind == kind
        for name, part in result.parts.items():
            assert part.job.free_body is not None
            env = part.cycle.envelope
            assert row[f"{name}_stress_MPa"] * 1e6 == pytest.approx(env.max_von_mises, rel=1e-9), (kind, name)
            assert row[f"{name}_fatigue"] == pytest.approx(part.cycle.fatigue.min_safety_factor, rel=1e-9), (kind, name)
            assert row[f"{name}_tip_mm"] / 1e3 == pytest.approx(env.max_tip, rel=1e-9, abs=1e-15), (kind, name)
            if part.cycle.dynamic is not None:
                amp = part.cycle.dynamic.amplification
                assert row[f"{name}_amplification"] == pytest.approx(amp, rel=1e-9), (kind, name)
