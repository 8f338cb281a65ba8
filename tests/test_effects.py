"""What a run simulates, defined once (railcheck.effects.simulated_effects and
dynamic_response) and read by the check and the sweep alike: only the effects a scene calls
for, and inertia or a dynamic response only when the crank turns."""

from __future__ import annotations

import tomllib

import pytest

from helpers import FINAL_DESIGN
from railcheck.scene import dynamic_response, parse_scene, simulated_effects


@pytest.mark.parametrize(
    ("requested", "speeds", "loads", "dynamic"),
    [
        (("inertia",), (6.28,), ("inertia",), False),
        (("inertia",), (0.0,), (), False),  # a still rig has no inertia
        (("inertia", "gravity"), (0.0,), ("gravity",), False),
        (("gravity", "inertia"), (0.0, 3.0), ("inertia", "gravity"), False),  # one turning speed is enough
        (("inertia", "dynamic"), (6.28,), ("inertia",), True),
        (("dynamic",), (0.0,), (), False),  # no cycle to respond to
        (("rail-inertia",), (6.28,), (), False),  # a load-model option, not a load of its own
        ((), (6.28,), (), False),
    ],
)
def test_the_effects_simulated(requested, speeds, loads, dynamic):
    assert simulated_effects(requested, speeds) == loads
    assert dynamic_response(requested, speeds) is dynamic


def _scene(check: str, mechanism: str = ""):
    return parse_scene(tomllib.loads(FINAL_DESIGN.replace("[mechanism]", "[mechanism]\n" + mechanism, 1) + check))


def test_the_check_and_the_sweep_read_the_one_definition():
    """A check at [mechanism]'s speed, a sweep at its own speeds: a scene whose mechanism
    stands still and whose sweep turns simulates inertia in the sweep only."""
    still = _scene('\n[check]\neffects = ["inertia", "dynamic"]\n[sweep]\nspeeds = ["1 Hz"]\n', 'speed = "0 Hz"\n')
    assert still.effects == () and not still.dynamic_response
    assert still.sweep_effects == ("inertia",) and still.sweep_dynamic_response
    turning = _scene('\n[check]\neffects = ["gravity"]\n')
    assert turning.effects == turning.sweep_effects == ("gravity",)
    assert not turning.dynamic_response and not turning.sweep_dynamic_response
