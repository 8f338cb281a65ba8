"""The typed stage inputs (railcheck/model/inputs.py, railcheck/model/kinematics_stage.py)
read what the scene says: the same effects, plane and dynamic response as the scene they are
resolved from, and a record varied by speed says what a scene at that speed would."""

import tomllib
from dataclasses import replace

import pytest

from helpers import FINAL_DESIGN
from railcheck.model.inputs import parts_input
from railcheck.model.kinematics_stage import kinematics_input, run_kinematics
from railcheck.scene import load_scene, parse_scene

VARIANTS = {
    "inertia at 1 Hz": 'speed = "1 Hz"\n[check]\nparts = ["crank-rail"]\neffects = ["inertia"]\n',
    "still crank": 'speed = "0 Hz"\n[check]\nparts = ["crank-rail"]\neffects = ["inertia", "dynamic"]\n',
    "gravity and dynamic": 'speed = "2 Hz"\nplane = "vertical"\n[check]\nparts = ["crank-rail"]\n'
    'effects = ["inertia", "gravity", "dynamic"]\n',
}


def _scene(text: str):
    return parse_scene(tomllib.loads(FINAL_DESIGN + text), "t")


@pytest.mark.parametrize("name", VARIANTS)
def test_the_parts_input_reads_the_scenes_effects_plane_and_dynamic_response(name):
    scene = _scene(VARIANTS[name])
    inputs = parts_input(scene)
    assert (inputs.effects, inputs.plane, inputs.dynamic_response) == (scene.effects, scene.plane, scene.dynamic_response)
    assert inputs.masses is scene.masses and inputs.check is scene.checked


def test_explicit_loads_alone_have_a_plane_from_the_effects():
    plain = parse_scene(tomllib.loads('[check]\nparts = ["PF_4b_006"]\n[loads.PF_4b_006]\nlongitudinal = "1 N"\n'), "t")
    heavy = replace(plain, check=replace(plain.checked, effects=("gravity",)))
    assert [parts_input(s).plane for s in (plain, heavy)] == [plain.plane, heavy.plane] == ["horizontal", "vertical"]


@pytest.mark.parametrize("speed", [0.0, 3.0])
def test_a_record_at_a_speed_is_the_scenes_at_that_speed(speed):
    """at_speed varies only the crank speed: effects, dynamic response and the kinematics
    equal those of the scene written at that speed."""
    scene = _scene(VARIANTS["gravity and dynamic"])
    written = _scene(VARIANTS["gravity and dynamic"].replace('"2 Hz"', f'"{speed} rad/s"'))
    moved = parts_input(scene).at_speed(speed)
    assert (moved.effects, moved.dynamic_response) == (written.effects, written.dynamic_response)
    a, b = run_kinematics(kinematics_input(scene).at_speed(speed)), run_kinematics(kinematics_input(written))
    assert a.effects == b.effects
    for joint, force in a.dynamics.reactions.items():
        assert (force == b.dynamics.reactions[joint]).all(), joint


def test_only_and_clamped_vary_the_check_alone():
    inputs = parts_input(load_scene(None))
    only = inputs.only(("crank-rail",))
    assert only.check.parts == ("crank-rail",) and only.check.compare == () and only.mechanism == inputs.mechanism
    clamped = inputs.clamped("coupler-rail")
    assert (clamped.check.parts, clamped.check.support) == (("coupler-rail",), "clamped")
    assert clamped.check.factor == inputs.check.factor and inputs.check.support == "free-body"
