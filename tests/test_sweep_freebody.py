"""`support = "free-body"` in the sweep: each rail a free body (no clamp), its far joint's
bolts sharing the joint force by the lever rule about the joint (so one unit-case set per
bar length, not per hole pair), its deflection relative to its joints, its modes pinned at
its joints, and the dynamics with the free-body mass model. Every figure of a sweep row is
compared with `railcheck check` of that setting, an independent path (one setting's load
model, unit cases, solve, modes and cycle)."""

import dataclasses

import numpy as np
import pytest

from helpers import FE_SWEEP, check_scene_of_row, run_sweep_text, table_rows
from railcheck.check.pipeline import run_pipeline
from railcheck.fea.screening import make_screens
from railcheck.sweep.parts import PartModel, sharing_screens


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


@pytest.mark.slow
def test_a_parts_models_for_both_kinds_hold_their_equal_screens_once():
    """Issue 59's memory: the crank and coupler rails' four-bar and slider-crank models
    carry different joint masses but the same unit fields, so the second kind's model
    takes the first's screens (the same arrays, held once) and nothing else changes: its
    keys and its own loads stay its own."""
    import tomllib

    from railcheck.scene import parse_scene
    from railcheck.sweep.inputs import sweep_input
    from railcheck.sweep.run import prepare_models, sweep_settings

    inputs = sweep_input(parse_scene(tomllib.loads(SLIDER_CRANK.replace("EFFECTS", '["inertia"]')), "test"))

    class Quiet:
        def say(self, *args):
            pass

    models = prepare_models(inputs, sweep_settings(inputs), Quiet(), jobs=1)
    for name in ("crank-rail", "coupler-rail"):
        four, slider = models["four-bar"][name], models["slider-crank"][name]
        assert four is not slider and four.loads is not slider.loads
        assert slider.screens.keys() == four.screens.keys()
        assert all(slider.screens[k] is four.screens[k] for k in four.screens), name


def _model(name: str, stress: np.ndarray) -> PartModel:
    """A part model with two hole pairs' screens of ``stress`` (6, n, 4), columns 0-1 and
    2-3; every other field a placeholder that sharing never reads."""
    columns = {(0, 1): [0, 1], (1, 2): [2, 3]}
    tips = {key: np.ones((3, 4)) for key in columns}
    screens = make_screens(stress, np.ones(stress.shape[1], bool), tips, columns)
    needed = {f.name: None for f in dataclasses.fields(PartModel) if f.default is dataclasses.MISSING}
    return PartModel(**(needed | {"name": name, "screens": screens, "pair_of": {}}))


def test_equal_screens_of_a_part_are_shared_and_any_other_kept():
    stress = np.random.default_rng(3).normal(size=(6, 40, 4))
    first = _model("crank-rail", stress)
    twin = sharing_screens(_model("crank-rail", stress.copy()), [first])
    assert all(twin.screens[k] is first.screens[k] for k in first.screens)
    other = stress.copy()
    other[0, 5, 3] += 1.0  # the second pair's columns differ
    partly = sharing_screens(_model("crank-rail", other), [first])
    assert partly.screens[(0, 1)] is first.screens[(0, 1)]
    assert partly.screens[(1, 2)] is not first.screens[(1, 2)]
    assert np.array_equal(partly.screens[(1, 2)].stress, other[:, :, 2:])
    stranger = _model("coupler-rail", stress.copy())
    assert sharing_screens(stranger, [first]) is stranger  # another part: nothing shared
