"""Where quasi-static holds: the beam model's lowest frequency against closed forms, the
one-mode estimate against the one-degree-of-freedom response, the certificate deciding
what a check computes, and (slow) the certificate against the FE's exact dynamic response
over sampled settings and speeds, and the sweep's safe speed checked with the dynamic
response."""

from __future__ import annotations

import json
import math
import tomllib
import warnings

import numpy as np
import pytest

from helpers import ROOT, check_scene_of_row, run_sweep_text, table_rows
from railcheck.fea.beam import beam_lowest_frequency
from railcheck.fea.dynamic import one_mode_amplification
from railcheck.model.certificate import QUASI_STATIC_TOLERANCE, amplification_estimate, dynamic_share, rail_lowest_hz
from railcheck.model.inputs import parts_input
from railcheck.model.utilisation import Limits, criterion_utilisations

EI, MASS = 2100.0, 3.0  # N m^2, kg/m


def test_a_simply_supported_beam_bends_at_pi_squared():
    """f1 = (pi / 2 L^2) sqrt(EI / m) for a beam pinned at both ends."""
    assert beam_lowest_frequency(1.0, EI, MASS, pins=[0.0, 1.0]) == pytest.approx(
        math.pi / 2 * math.sqrt(EI / MASS), rel=1e-4
    )


def test_a_cantilever_with_a_tip_mass_matches_its_closed_forms():
    """Clamped, free: f1 = (1.8751^2 / 2 pi) sqrt(EI / m L^4); with a tip mass M four times
    the beam's, Rayleigh's f1 = sqrt(3 EI / (L^3 (M + 0.2357 m L))) / 2 pi (within 0.5 %)."""
    bare = 1.8751**2 / (2 * math.pi) * math.sqrt(EI / (MASS * 1.0**4))
    assert beam_lowest_frequency(1.0, EI, MASS, clamps=[0.0]) == pytest.approx(bare, rel=1e-4)
    tip = 4 * MASS
    rayleigh = math.sqrt(3 * EI / (tip + 0.2357 * MASS)) / (2 * math.pi)
    assert beam_lowest_frequency(1.0, EI, MASS, clamps=[0.0], masses=[(1.0, tip)]) == pytest.approx(rayleigh, rel=5e-3)


def test_a_beam_on_one_pin_is_refused():
    with pytest.raises(ValueError, match="two pins or a clamp"):
        beam_lowest_frequency(1.0, EI, MASS, pins=[0.5])


@pytest.mark.parametrize("n", [1, 3])
def test_one_harmonic_is_amplified_by_the_single_mode_response(n):
    """c(t) = cos(n theta): the filtered history is |H(n f / f1)| cos(n theta - phase), so
    the ratio is |H| exactly; a zero column reads 1."""
    steps = 721
    theta = np.linspace(0, 2 * np.pi, steps)
    C = np.stack([np.cos(n * theta), np.zeros(steps)], axis=1)
    speed, hz, zeta = 2 * np.pi * 2.0, 20.0, 0.02
    r = n * 2.0 / hz
    ratio, peak = one_mode_amplification(C, speed, hz, zeta)
    # the phase-shifted peak falls between steps: at most 1 - cos(n pi / 720) below the true one
    exact = 1 / abs(1 - r**2 + 2j * zeta * r)
    assert exact * math.cos(n * math.pi / 720) - 1e-12 <= ratio[0] <= exact + 1e-12
    assert ratio[1] == 1.0 and peak[1] == 0.0


def test_the_estimate_reads_only_significant_joint_forces():
    """A joint force of 1000 N at the first harmonic and a 10 N one at the fifth (below 5 %
    of the largest) and a body-inertia column at the fifth: only the first counts."""
    theta = np.linspace(0, 2 * np.pi, 361)
    C = np.stack([1000 * np.cos(theta), 10 * np.cos(5 * theta), np.cos(5 * theta)], axis=1)
    speed, hz = 2 * np.pi * 2.0, 20.0
    got = amplification_estimate(C, ["pin_x", "pin_y", "body_x"], speed, hz, 0.02)
    r = 2.0 / hz
    assert got == pytest.approx(1 / abs(1 - r**2 + 0.04j * r), rel=1e-4)  # the peak between steps
    louder = C * np.array([1.0, 10.0, 1.0])  # 100 N: now significant, its fifth harmonic governs
    assert amplification_estimate(louder, ["pin_x", "pin_y", "body_x"], speed, hz, 0.02) > got + 0.1


def _scene(speed_hz: float, effects=("inertia",)):
    """The built-in default scene at ``speed_hz`` with ``effects``."""
    from railcheck.scene import parse_scene

    text = (ROOT / "railcheck/scenes/default.toml").read_text()
    text = text.replace('speed = "1 Hz"', f'speed = "{speed_hz} Hz"').replace(
        'effects = ["inertia"]', f"effects = {json.dumps(list(effects))}"
    )
    return parse_scene(tomllib.loads(text), "test")


def _jobs(speed_hz: float, effects=("inertia",)):
    """The default scene's part jobs at ``speed_hz`` (kinematics only: nothing meshed)."""
    from railcheck.fea.materials import MATERIALS
    from railcheck.model.jobs import build_load_cases, part_geometries, part_jobs
    from railcheck.model.kinematics_stage import kinematics_input, run_kinematics

    scene = _scene(speed_hz, effects)
    kin = run_kinematics(kinematics_input(scene))
    geos = part_geometries(parts_input(scene))
    material = MATERIALS["steel"]
    return part_jobs(
        parts_input(scene), kin, geos, build_load_cases(parts_input(scene), kin, geos), material, material.fatigue_limit
    )


def test_at_the_design_speed_the_rails_are_certified_and_nothing_dynamic_runs():
    """1 Hz: every rail's estimate is within the tolerance (the crank's about 1.04:
    1.036 at its FE frequency, docs/model.md), so no rail asks for modes; the plate with
    cycling loads asks for its modes only to read its lowest frequency."""
    jobs = _jobs(1.0)
    for name in ("crank-rail", "coupler-rail", "rocker-rail"):
        assert jobs[name].certificate.holds and jobs[name].dynamic is None, name
    assert 1.03 < jobs["crank-rail"].certificate.estimate <= QUASI_STATIC_TOLERANCE
    assert jobs["PF_4b_006"].dynamic is not None and not jobs["PF_4b_006"].dynamic.exact
    assert jobs["PF_4b_003_v2"].dynamic is None and jobs["PF_4b_003_v2"].certificate is None  # constant loads


def test_at_8_hz_the_certificate_fails_and_the_check_computes_the_dynamic_response():
    jobs = _jobs(8.0)
    crank = jobs["crank-rail"]
    assert not crank.certificate.holds and crank.certificate.estimate > 1.5
    assert crank.dynamic is not None and crank.dynamic.exact and "certificate" in crank.dynamic.reason


def test_the_beam_frequency_is_below_the_rails_fe_modes_of_the_default_scene():
    """The certificate's frequency (95 % of the beam's) against the FE's pinned modes of
    the default scene (railcheck check with ``dynamic``: 26.32, 66.46, 75.65 Hz; the
    crank's is computed afresh in test_dynamic.py): conservative, and within 10 %."""
    jobs = _jobs(1.0, ("inertia", "dynamic"))
    fe = {"crank-rail": 26.32, "coupler-rail": 66.46, "rocker-rail": 75.65}
    for name, hz in fe.items():
        j = jobs[name]
        beam = rail_lowest_hz(j.geometry, j.material, j.dynamic.pins, j.dynamic.lumped)
        assert 0.9 * hz < beam < hz, name


NEIGHBOURHOOD = """
[sweep]
kind = "four-bar"
speeds = [{speeds}]
steps = 720
crank = ["420 mm", "540 mm"]
coupler = ["840 mm", "840 mm"]
rocker = ["780 mm", "780 mm"]
ground = ["960 mm", "1080 mm"]

[check]
parts = ["crank-rail", "coupler-rail", "rocker-rail", "PF_4b_006"]
effects = {effects}
support = "free-body"
"""


@pytest.mark.slow
def test_wherever_the_certificate_holds_the_exact_dynamic_response_is_within_it(tmp_path):
    """9 settings x 24 speeds (0.25 to 6 Hz) x 4 parts: the sweep's estimates against the
    sweep with ``dynamic`` (the FE modes' mode-acceleration response). Wherever the
    estimate is within the tolerance, so is the exact amplification."""
    speeds = ", ".join(f'"{0.25 * k:g} Hz"' for k in range(1, 25))
    rows = {}
    for label, effects in (("estimate", '["inertia"]'), ("exact", '["inertia", "dynamic"]')):
        run = run_sweep_text(tmp_path, NEIGHBOURHOOD.format(speeds=speeds, effects=effects), label)
        rows[label] = table_rows(run)
    est, ex = rows["estimate"], rows["exact"]
    assert np.array_equal(est["setting"], ex["setting"]) and np.array_equal(est["speed_Hz"], ex["speed_Hz"])
    pairs = 0
    for part in ("crank-rail", "coupler-rail", "rocker-rail", "PF_4b_006"):
        e = np.array(est[f"{part}_amplification_estimate"], float)
        x = np.array(ex[f"{part}_amplification"], float)
        ok = np.isfinite(e) & np.isfinite(x)
        pairs += int(ok.sum())
        holds = ok & (e <= QUASI_STATIC_TOLERANCE)
        assert np.all(x[holds] <= QUASI_STATIC_TOLERANCE), part
        assert np.any(ok & ~holds) or part != "crank-rail"  # the crank's estimate does trip in this range
    assert pairs >= 200


@pytest.mark.slow
def test_the_sweeps_safe_speed_passes_a_check_with_the_dynamic_response(tmp_path):
    """120/900/600/720 mm (next to 120/960/600/720, the setting issue 57 found unsafe at its old
    8.14 Hz safe speed; 960 mm is off the grid since the joints sit between two holes):
    the sweep's safe speed, checked with ``dynamic`` at that speed, passes."""
    text = NEIGHBOURHOOD.format(speeds='"1 Hz"', effects='["inertia"]')
    for bar, mm in (("crank", 120), ("coupler", 900), ("rocker", 600), ("ground", 720)):
        start = text.index(f"{bar} = [")
        text = text[:start] + f'{bar} = ["{mm} mm", "{mm} mm"]' + text[text.index("]", start) + 1 :]
    rows = table_rows(run_sweep_text(tmp_path, text, "s"))
    row = {k: v[0] for k, v in rows.items()}
    safe = float(row["safe_speed_Hz"])
    assert 1.0 < safe < 8.0  # no longer the quasi-static 8.14 Hz
    from railcheck.check.pipeline import run_pipeline

    dynamic = text.replace('effects = ["inertia"]', 'effects = ["inertia", "dynamic"]')
    result = run_pipeline(check_scene_of_row(row, safe, dynamic, steps=720))
    assert result.passed, result.failures
    assert max(p.utilisation for p in result.parts.values()) <= 1.0
    assert all(p.cycle.dynamic is not None for p in result.parts.values())


def test_the_sweeps_quasi_static_criterion_fails_only_beyond_the_tolerance():
    """Within the tolerance the estimate is stated, not a utilisation (0); beyond it the
    row fails on ``quasi-static`` with the share (A - 1) / (A_tol - 1) above 1."""
    from railcheck.model.utilisation import Limits, criterion_utilisations, failed_criteria

    model = Limits(stress=375e6, fatigue_required=1.0, deflection=None, yield_strength=490e6, length=0.5, certified=True)
    vm, fat, tip = np.array([100e6, 100e6]), np.array([2.0, 2.0]), np.zeros(2)
    amp = np.array([1.04, 1.06])
    u = criterion_utilisations(model, vm, fat, tip, amp)
    assert u["quasi-static"][0] == 0.0 and u["quasi-static"][1] == pytest.approx(1.2)
    assert list(failed_criteria(model, vm, fat, tip, amp)["quasi-static"]) == [False, True]
    assert list(failed_criteria(model, np.array([500e6, 1e6]), fat, tip, amp)["beyond yield"]) == [True, False]
    # small displacements: a deflection beyond 2 % of the part's length (10 mm of 0.5 m) fails the row
    sag = np.array([0.0099, 0.0101])
    assert list(failed_criteria(model, vm, fat, sag, amp)["beyond small displacements"]) == [False, True]
    assert criterion_utilisations(model, vm, fat, sag, amp)["small-displacement"] == pytest.approx([0.99, 1.01])


def test_the_safe_speed_with_margin_solves_a_known_crossing():
    """u(s) = 0.5 s A(s), A(s) = 1 + 0.01 s (quasi-static safe s = 2): the margin's
    crossing solves 0.5 s (1 + 0.01 s) = 1 (s = 1.9615...) unless the estimate's share,
    (A - 1) / 0.05, reaches 1 first (at s = 5: not here); a rig failing at rest gives 0."""
    from railcheck.model.utilisation import quasi_static_share
    from railcheck.sweep.validity import safe_ratio_sq_with_margin

    def margin(s, base=0.5):
        a = 1 + 0.01 * s
        return {"p": (None, None, None, a, np.maximum(base * s * a, quasi_static_share(a)))}

    got = safe_ratio_sq_with_margin(margin, np.array([2.0, 2.0]), 2)
    want = (-1 + math.sqrt(1 + 4 * 0.01 * 2)) / (2 * 0.01)
    assert got == pytest.approx([want, want], rel=1e-6)
    steep = safe_ratio_sq_with_margin(lambda s: margin(s, base=0.01), np.array([100.0]), 1)
    assert steep[0] == pytest.approx(5.0, rel=1e-6)  # the estimate's tolerance sets it


def test_every_default_that_shapes_the_verdict_is_stated():
    from railcheck.model.assumptions import assumptions

    scene = _scene(1.0)
    words = " | ".join(assumptions(parts_input(scene), scene.components, {}))
    for needle in (
        "sigma_y 490 MPa",
        "sigma_u / 2",
        "load factor 1.4",
        "reliability 0.99",
        "k_e = 0.814",
        "deflection limit: none",
        "weight: a table-top rig",
        "beyond yield",
        "small displacements",
    ):
        assert needle in words, needle


@pytest.mark.parametrize("holds", [True, False])
def test_a_plate_solves_one_mode_for_its_certificate_and_every_mode_when_it_fails(tmp_path, monkeypatch, holds):
    """PF_4b_006 (no beam model) reads its certificate from its lowest FE mode, so it asks
    for that one mode; where the certificate does not hold (its tolerance lowered here, so
    the estimate exceeds it) the exact response needs the modes the scene asks for, and
    they are solved."""
    from dataclasses import replace

    import railcheck.fea.store as store
    import railcheck.model.cycle as cycle

    monkeypatch.setenv("RAILCHECK_CACHE", str(tmp_path))
    asked = []
    real_solve, real_certificate = store.solve_unit_cases, cycle.certificate

    def counted(*args, **kw):
        asked.append(kw["modes"][0])
        return real_solve(*args, **kw)

    monkeypatch.setattr(store, "solve_unit_cases", counted)
    if not holds:
        monkeypatch.setattr(cycle, "certificate", lambda *a, **k: replace(real_certificate(*a, **k), tolerance=0.5))
    job = _jobs(1.0)["PF_4b_006"]
    job = replace(job, mesh=replace(job.mesh, size=16e-3, hole_size=5e-3, order=1), node_fields=False)
    part = cycle.check_part(job, "auto", lambda message: None)
    count = job.dynamic.modes
    if holds:
        assert asked == [1] and part.job.dynamic is None and part.cycle.dynamic is None
    else:
        assert asked == [1, count] and part.job.dynamic.exact
        assert part.cycle.dynamic.hz.size == count


def test_the_dynamic_share_is_one_definition_for_the_check_and_the_sweep_even_with_no_excess_allowed():
    """A limit of 1 (no excess: the scene refuses it, the API's Limits may carry it) gives
    the check's and the sweep's dynamic utilisation 0 up to the quasi-static peak and inf
    beyond, never a division by zero; above 1 the share of the allowed excess."""
    assert dynamic_share(1.05, 1.10) == pytest.approx(0.5) and dynamic_share(1.0, 1.0) == 0.0
    assert dynamic_share(1.2, 1.0) == float("inf") and isinstance(dynamic_share(0.9, 1.0), float)
    model = Limits(
        stress=375e6, fatigue_required=1.0, deflection=None, yield_strength=0.0, length=0.0, max_amplification=1.0
    )
    amp = np.array([0.98, 1.0, 1.03])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a division by zero warns: it would fail here
        u = criterion_utilisations(model, np.full(3, 100e6), np.full(3, 2.0), np.zeros(3), amp)
    assert list(u["dynamic"]) == [0.0, 0.0, float("inf")]
