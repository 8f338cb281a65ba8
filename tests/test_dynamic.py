"""The effect ``dynamic`` in a check: each part's lowest modes and its steady-state
response to the cycle (mode-acceleration), the amplification over the quasi-static peak,
its verdict, and nothing of it when the effect is not listed. The method itself is checked
against a direct harmonic solve in test_modes.py."""

import json
import math
import tomllib

import numpy as np
import pytest

from helpers import FINAL_DESIGN
from railcheck.base.errors import InputError
from railcheck.check.pipeline import run_pipeline
from railcheck.check.summary import summary_of
from railcheck.model.inputs import parts_input
from railcheck.scene import parse_scene

SCENE = (
    FINAL_DESIGN
    + """speed = "SPEED"
steps = 360
[check]
parts = ["crank-rail"]
effects = EFFECTS
[mesh]
size = "20 mm"
hole_size = "6 mm"
"""
)


def _crank(speed="1 Hz", effects='["inertia", "dynamic"]', extra=""):
    text = SCENE.replace("SPEED", speed).replace("EFFECTS", effects) + extra
    return run_pipeline(parse_scene(tomllib.loads(text), "test"), jobs=1)


@pytest.fixture(scope="module")
def one_hz():
    """Solved, not read from the unit-field store (a warm store would serve the modes and
    leave no "modes" time to report)."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("RAILCHECK_STORE", "0")
        return _crank()


@pytest.mark.slow  # the fixture's cost
def test_the_certificates_beam_frequency_is_below_the_fe_mode_it_stands_for(one_hz):
    """The crank rail's lowest FE mode (pinned at its shaft and driving pin, A's masses
    lumped) is above the certificate's beam frequency, within 10 %; the certificate's
    estimate exceeds the exact amplification (conservative) and both are within 1.05."""
    part = one_hz.parts["crank-rail"]
    fe, cert = float(part.cycle.dynamic.hz[0]), part.job.certificate
    assert 0.9 * fe < cert.lowest_hz < fe
    assert part.cycle.dynamic.amplification < cert.estimate <= cert.tolerance


@pytest.mark.slow  # pin pressures doubled its cost (cold: 6.8 s): out of the fast tier
def test_the_dynamic_response_is_reported_and_quasi_static_holds_at_1_hz(one_hz):
    part = one_hz.parts["crank-rail"]
    d = part.cycle.dynamic
    assert d.hz.size == 6 and np.all(np.diff(d.hz) >= 0) and 10 < d.hz[0] < 200
    assert d.crank_hz == pytest.approx(1.0) and list(d.harmonics[:1]) == [round(d.hz[0])]
    assert 1.0 < d.amplification < d.max_amplification and d.passed and part.passed
    assert d.dynamic_peak == pytest.approx(part.verdict_stress, rel=1e-12)  # the verdict reads the dynamic response
    # its utilisation: the excess over quasi-static as a share of the allowed 10%
    assert part.utilisations["dynamic"] == pytest.approx((d.amplification - 1) / 0.1, rel=1e-12)
    assert part.cycle.fields.names[-6:] == tuple(f"mode {i}" for i in range(1, 7))
    assert "modes" in part.seconds
    import dataclasses

    with pytest.raises(dataclasses.FrozenInstanceError):
        d.amplification = 1.0
    entry = summary_of(one_hz)["parts"]["crank-rail"]["dynamic"]
    assert entry["amplification"] == d.amplification and entry["pass"] is True
    json.dumps(entry, allow_nan=False)


@pytest.mark.slow
def test_the_amplification_grows_with_the_speed_squared_below_resonance(one_hz):
    """Far below the first mode the modal correction of harmonic n is (n Omega / omega)^2
    of its static response to leading order: amplification - 1 grows as the speed squared
    (the quasi-static peak itself scales with it too). 0.25 and 0.5 Hz: the clamped crank
    with its carried masses has its first mode near 20 Hz, so at 1 Hz the next order
    ((n Omega / omega)^2 for harmonics n up to 10) is already 10% of it."""
    clamped = '["inertia", "dynamic"]\nsupport = "clamped"'  # the 2013 clamp: no constant table-top weight in the peak
    a_half = _crank("0.5 Hz", clamped).parts["crank-rail"].cycle.dynamic.amplification - 1
    a_quarter = _crank("0.25 Hz", clamped).parts["crank-rail"].cycle.dynamic.amplification - 1
    assert a_half / a_quarter == pytest.approx(4.0, rel=0.05)


@pytest.mark.slow  # its fixture (the default crank with dynamic, 4.8 s) is the slow tier's since the pin pressures
def test_a_part_above_its_amplification_limit_fails_naming_dynamic(one_hz):
    from dataclasses import replace

    part = one_hz.parts["crank-rail"]
    d = part.cycle.dynamic
    at = replace(part, cycle=replace(part.cycle, dynamic=replace(d, max_amplification=d.amplification)))
    assert at.dynamic_passed  # the limit itself passes
    over = replace(part, cycle=replace(part.cycle, dynamic=replace(d, max_amplification=1.0)))
    result = replace(one_hz, parts={"crank-rail": over})
    assert result.failures == ["crank-rail dynamic"]
    assert over.stress_passed and over.fatigue_passed and not over.dynamic_passed and not over.passed
    assert summary_of(result)["parts"]["crank-rail"]["dynamic"]["pass"] is False
    # and the scene's limit reaches the part
    scene = parse_scene(
        tomllib.loads(
            SCENE.replace("SPEED", "1 Hz").replace("EFFECTS", '["inertia", "dynamic"]')
            + "[dynamic]\nmax_amplification = 1.01\ndamping = 0.05\nmodes = 3\n"
        ),
        "t",
    )
    from railcheck.model.jobs import dynamic_job

    job = dynamic_job(parts_input(scene), None)
    assert (job.max_amplification, job.damping, job.modes, job.speed) == (1.01, 0.05, 3, pytest.approx(2 * math.pi))


@pytest.mark.slow  # pin pressures doubled its cost (cold: 3.4 s): out of the fast tier
def test_without_the_effect_no_mode_is_computed():
    part = _crank(effects='["inertia"]').parts["crank-rail"]
    assert part.cycle.dynamic is None and part.cycle.solve.modes is None
    assert "modes" not in part.seconds and not any(n.startswith("mode") for n in part.cycle.fields.names)


@pytest.mark.parametrize(
    ("table", "field"),
    [
        ("damping = 0", "dynamic.damping"),
        ("damping = 2.0", "dynamic.damping"),
        ('damping = "2 %"', "dynamic.damping"),
        ("max_amplification = 0.9", "dynamic.max_amplification"),
        ("max_amplification = 1.0", "dynamic.max_amplification"),
        ("max_amplification = nan", "dynamic.max_amplification"),
        ("modes = 0", "dynamic.modes"),
        ("modes = 2.5", "dynamic.modes"),
        ("colour = 1", "dynamic.colour"),
    ],
)
def test_bad_dynamic_settings_are_refused_naming_the_field(table, field):
    text = SCENE.replace("SPEED", "1 Hz").replace("EFFECTS", '["inertia", "dynamic"]') + f"[dynamic]\n{table}\n"
    with pytest.raises(InputError) as err:
        parse_scene(tomllib.loads(text), "t")
    assert err.value.field == field


def test_a_still_rig_has_no_cycle_to_respond_to():
    from railcheck.model.jobs import dynamic_job

    scene = parse_scene(tomllib.loads(SCENE.replace("SPEED", "0 Hz").replace("EFFECTS", '["gravity", "dynamic"]')), "t")
    assert dynamic_job(parts_input(scene), None) is None


@pytest.mark.slow
def test_the_report_and_the_files_carry_the_dynamic_response(tmp_path):
    """summary.json, report.html (the table and the Campbell diagram), campbell.png and
    the mode shapes in the VTU, from `railcheck check`."""
    import meshio

    from helpers import assert_picture
    from railcheck.cli import main

    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE.replace("SPEED", "1 Hz").replace("EFFECTS", '["inertia", "dynamic"]') + "[output]\npng = false\n")
    assert main(["check", str(scene), "--out", str(tmp_path / "r")]) == 0
    out = tmp_path / "r"
    d = json.loads((out / "summary.json").read_text())["parts"]["crank-rail"]["dynamic"]
    assert len(d["frequencies_Hz"]) == 6 and d["pass"] is True
    assert_picture(out / "campbell.png")
    page = (out / "report.html").read_text()
    assert "Dynamic response" in page and 'alt="Campbell diagram"' in page
    assert "dynamic amplification" in page and f"{d['amplification']:.4f}" in page  # in the parts table too
    m = meshio.read(out / "crank-rail.vtu")
    modes = [k for k in m.point_data if k.startswith("mode_")]
    assert len(modes) == 6 and modes[0] == f"mode_1_{d['frequencies_Hz'][0]:.1f}Hz"
    assert m.point_data[modes[0]].shape == (m.points.shape[0], 3)
