"""The part registry is the one place that knows the parts: a new part kind added there
alone (plus a geometry builder that already exists) is checked end to end."""

import tomllib

import numpy as np
import pytest

from helpers import FINAL_DESIGN
from railcheck import parts
from railcheck.check.pipeline import run_pipeline
from railcheck.geometry.models import bar
from railcheck.scene import parse_scene


@pytest.fixture
def bracket(monkeypatch):
    """A throw-away 'bracket': a 200 x 20 x 20 mm steel bar clamped at one end, carrying
    the coupler's joint B in the coupler's axes on its free end face."""

    kind = parts.PartKind(
        "bracket",
        lambda overrides, length: bar(0.2, 0.02, 0.02),
        "clamp",
        "tip",
        lambda g: 0.02,
        (12e-3, 12e-3),
        lambda g: (0.02, 0.02),
        bolt_groups=lambda g: ["tip"],
    )
    monkeypatch.setitem(parts.KINDS, "bracket", kind)
    monkeypatch.setitem(
        parts.PARTS, "bracket-B", parts.Part("bracket-B", "bracket", (parts.LoadSource("B", -1.0, "coupler"),))
    )


def test_a_part_added_through_the_registry_alone_is_checked_end_to_end(bracket):
    scene = parse_scene(
        tomllib.loads(FINAL_DESIGN + 'speed = "1 Hz"\nsteps = 720\n[check]\nparts = ["bracket-B"]\n[mesh]\nsize = "12 mm"\n')
    )
    result = run_pipeline(scene)
    part = result.parts["bracket-B"]
    cycle = part.cycle
    # the load history is R_B in the coupler's axes x 1.4, on the tip face
    reaction = result.kinematics.dynamics.reactions["B"]
    peak = 1.4 * np.hypot(reaction[:, 0], reaction[:, 1]).max()
    np.testing.assert_allclose(np.hypot(cycle.C[:, 0], cycle.C[:, 1]).max(), peak, rtol=1e-12)
    # a cantilever with an end load: the verdict's peak sits at the edge of the clamp's
    # 20 mm exclusion zone, where beam theory gives F_t (L - x) c / I + |F_l| / A on the
    # face where bending and axial stress add (3%: the clamp's Saint-Venant zone, the mesh)
    c, inertia, area = 0.01, 0.02 * 0.02**3 / 12, 0.02 * 0.02
    x = part.cycle.envelope.location[0]
    assert 0.02 <= x < 0.025
    beam = np.max(np.abs(cycle.C[:, 1]) * (0.2 - x) * c / inertia + np.abs(cycle.C[:, 0]) / area)
    assert part.verdict_stress == pytest.approx(beam, rel=0.03)
    assert result.stages_run[-1] == "report" and part.passed
