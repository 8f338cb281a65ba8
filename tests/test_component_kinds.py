"""The component kinds, one registered entry each (railcheck.components.kinds): every
component's kind is registered and reads only spec fields; a kind registered once is
checked, sized and swept like the built-in ones with no other file touched; the load
factor reaches the strength checks and not the rolling elements'."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from railcheck.components import kinds
from railcheck.components.ratings import COMPONENT_SPEC, COMPONENTS, Component
from railcheck.components.scene_checks import components_input, joint_histories
from railcheck.scene import parse_scene


def _scene():
    data = {
        "mechanism": {"kind": "four-bar", "crank": "480 mm", "coupler": "840 mm", "rocker": "780 mm", "ground": "1020 mm"}
        | {"speed": "1 Hz", "steps": 360},
        "check": {"parts": ["shaft-A", "bearings-A"], "effects": ["inertia"]},
    }
    return parse_scene(data, "test")


@pytest.fixture(scope="module")
def histories():
    from railcheck.model.kinematics_stage import kinematics_input, run_kinematics

    scene = _scene()
    return scene, joint_histories(components_input(scene), run_kinematics(kinematics_input(scene)))


def test_every_component_has_one_registered_kind_reading_only_spec_fields():
    spec_fields = {f.name for f in dataclasses.fields(COMPONENT_SPEC)}
    assert {c.kind for c in COMPONENTS.values()} == set(kinds.KINDS)
    for kind in kinds.KINDS.values():
        assert set(kind.fields) <= spec_fields, kind.name
    with pytest.raises(ValueError, match="already registered"):
        kinds.register_kind(kinds.KINDS["shaft"])


def _pin_check(c, spec, h, f, m):
    """A toy kind: the joint force's peak magnitude times ``f`` over 10 kN."""
    peak = np.sqrt((h.reactions[c.joint] ** 2).sum(axis=-1)).max(axis=-1)
    return {"shear": f * peak / 10e3}, {"peak_N": peak}


@pytest.mark.parametrize("factored", [True, False])
def test_a_kind_registered_once_is_checked_sized_and_swept(histories, monkeypatch, factored):
    scene, h = histories
    monkeypatch.setattr(kinds, "KINDS", dict(kinds.KINDS))
    monkeypatch.setitem(COMPONENTS, "pin-A", Component("pin-A", "pin", "A"))
    kinds.register_kind(kinds.ComponentKind("pin", "toy 10 kN", ("joint_friction",), factored, _pin_check))
    m = components_input(scene).strengths
    r = kinds.check_components(["pin-A", "shaft-A"], scene.components, h, 1.4, m)["pin-A"]
    by_hand = np.hypot(*h.reactions["A"].T).max()
    assert r.utilisation == pytest.approx((1.4 if factored else 1.0) * by_hand / 10e3, rel=1e-12)
    assert r.factored is factored
    assert (r.standard, r.assumed) == ("toy 10 kN", ("joint_friction",))
    given = kinds.check_component(COMPONENTS["pin-A"], scene.components, h, 1.4, m, frozenset({"joint_friction"}))
    assert given.assumed == ()
    assert kinds.with_needs(r, scene.components, h, 1.4, m).needs == {}  # a kind that sizes nothing
    assert set(kinds.needs_of_settings(["pin-A", "shaft-A"], scene.components, h, 1.4, m)) == {"shaft-A"}


def test_the_load_factor_reaches_the_strength_checks_only(histories):
    scene, h = histories
    m = components_input(scene).strengths
    at = {f: kinds.check_components(["shaft-A", "bearings-A"], scene.components, h, f, m) for f in (1.0, 1.4)}
    shaft = {f: at[f]["shaft-A"].utilisations["fatigue"] for f in at}
    assert shaft[1.4] > 1.3 * shaft[1.0]
    assert at[1.4]["bearings-A"].utilisations == at[1.0]["bearings-A"].utilisations
    assert not at[1.4]["bearings-A"].factored and at[1.4]["shaft-A"].factored
