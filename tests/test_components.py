"""The joints' components against published figures: Shigley's worked shaft example, the
EN 1993-1-8 bolt resistances tabulated in SCI P363 (the "blue book"), hand checks of the
pin, the bolt group and the bearings, and the pipeline's verdict on both sides."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from railcheck.base.errors import InputError
from railcheck.components import standards
from railcheck.files import to_json
from railcheck.scene import parse_scene

COMPONENTS = ["driving-pin", "motor-shaft", "shaft-A", "shaft-B", "shaft-O4", "bolts-A", "bolts-B"]
COMPONENTS += ["bearings-O2", "bearings-A", "bearings-B", "bearings-O4", "carriage-A", "carriage-B"]


def test_de_goodman_and_first_cycle_yield_match_shigley_example_7_1():
    # Shigley 10th ed., Example 7-1: d = 1.100 in, M_a = 1260 lbf in, T_m = 1100 lbf in,
    # K_f = 1.58, K_fs = 1.39, S_e = 29.3 kpsi, S_ut = 105 kpsi, S_y = 82 kpsi:
    # DE-Goodman n = 1.62, yield n_y = 4.48 (the units cancel: inches, lbf, psi)
    u = standards.shaft_utilisations_of_parts(1260.0, 0.0, 0.0, 1100.0, 1.1, 1.58, 1.39, 29.3e3, 105e3, 82e3)
    assert 1.0 / u["fatigue"] == pytest.approx(1.62, abs=0.005)
    assert 1.0 / u["yield"] == pytest.approx(4.48, abs=0.01)


def test_notch_sensitivity_matches_shigley_example_7_1():
    # S_ut = 105 kpsi, r = 0.11 in: q = 0.85 (read from figure 6-20 in the example)
    q = standards.notch_sensitivity(105e3 * 6.894757e3, 0.11 * 0.0254)
    assert q == pytest.approx(0.85, abs=0.01)


@pytest.mark.parametrize(
    "d, area, shear_kn, tension_kn",
    [(12e-3, 84.3e-6, 32.4, 48.6), (20e-3, 245e-6, 94.1, 141.0)],  # SCI P363, class 8.8, shear through the thread
)
def test_bolt_resistances_match_the_tabulated_en_1993_1_8_values(d, area, shear_kn, tension_kn):
    one = np.array([[1.0]])
    u = standards.bolt_utilisations(one, one, d, area, 800e6, 430e6, 10e-3, 0.6, 100e-3, 100e-3, d + 2e-3)
    assert 1e-3 / u["shear"][0] == pytest.approx(shear_kn, rel=1e-3)
    assert 1e-3 / u["tension"][0] == pytest.approx(tension_kn, rel=1e-3)


def test_bolt_bearing_with_generous_distances_is_2_fu_d_t():
    # k1 = 2.5, alpha_b = 1: F_b,Rd = 2.5 fu d t / 1.25; M20 in 10 mm S275 (fu 430 MPa): 172 kN
    one = np.array([[1.0]])
    u = standards.bolt_utilisations(one, one * 0, 20e-3, 245e-6, 800e6, 430e6, 10e-3, 0.6, 100e-3, 100e-3, 22e-3)
    assert 1e-3 / u["bearing"][0] == pytest.approx(172.0, rel=1e-3)


def test_elastic_bolt_group_shares_a_central_force_and_adds_the_eccentric_moment():
    assert standards.bolt_group_forces(300.0, 400.0, 0.0, 0.06) == pytest.approx(250.0)
    # a transverse force 70 mm from the centroid of two bolts 60 mm apart: F (1/2 + 70/60)
    assert standards.bolt_group_forces(0.0, 600.0, 0.07, 0.06) == pytest.approx(600.0 * (0.5 + 0.07 / 0.06))


def test_pin_by_hand_at_the_default_scenes_peak_torque():
    # the figures: 137.1 N m over the 60 mm arm, x1.4: 3.20 kN on a 7 mm pin
    force = np.array([1.4 * 137.1 / 0.06])
    u = standards.pin_utilisations(force, 7e-3, 13e-3, 10e-3, 1e-3, 640e6, 800e6, 490e6)
    area, w_el = math.pi * 7e-3**2 / 4, math.pi * 7e-3**3 / 32
    assert u["shear"] == pytest.approx(force[0] / (0.6 * area * 800e6 / 1.25))
    assert u["bending"] == pytest.approx(force[0] * (6.5e-3 + 1e-3 + 5e-3) / (1.5 * w_el * 640e6))
    assert u["bearing"] == pytest.approx(force[0] / (1.5 * 10e-3 * 7e-3 * 490e6))


def test_pin_in_double_shear_against_philpots_worked_example():
    # Philpot, Mechanics of Materials, MecMovies M1.5: pin C in double shear carries
    # 88.46 kN at an allowable 50 MPa: shear area 2 A = 1769.2 mm^2, so d = 33.6 mm
    force, allowable = 88.46e3, 50e6
    fu = allowable * standards.GAMMA_M2 / 0.6  # so that 0.6 f_u / gamma_M2 is the allowable stress
    at = lambda d: float(
        standards.pin_utilisations(np.array([force]), d, 20e-3, 40e-3, 0.0, 1e12, fu, 1e12, planes=2)["shear"]
    )
    d_needed = math.sqrt(4.0 * (force / allowable) / (2.0 * math.pi))
    assert at(d_needed) == pytest.approx(1.0, rel=1e-12)
    assert 2.0 * math.pi * d_needed**2 / 4.0 * 1e6 == pytest.approx(1769.2, rel=1e-3)
    assert round(d_needed * 1e3, 1) == 33.6  # published to a tenth of a millimetre
    assert at(33.6e-3) <= 1.0 < at(33.5e-3)  # the published size passes, one tenth less fails


def test_pin_shear_resistance_against_a_published_en_1993_1_8_calculation():
    # a published EN 1993-1-8 Table 3.10 pin calculation (d 16 mm, f_up 360 MPa, gamma_M2
    # 1.25, F_v,Ed 5 kN): F_v,Rd = 35 kN, "SF = 6.95"
    u = standards.pin_utilisations(np.array([5e3]), 16e-3, 10e-3, 10e-3, 0.0, 235e6, 360e6, 235e6)["shear"]
    assert 1.0 / float(u) == pytest.approx(6.95, rel=1e-3)


@pytest.mark.parametrize("outer, middle, gap", [(10e-3, 20e-3, 0.0), (6e-3, 25e-3, 2e-3), (15e-3, 8e-3, 5e-3)])
def test_double_shear_pins_bending_is_the_statics_of_its_bearing_pressures(outer, middle, gap):
    # EN 1993-1-8 Figure 3.11's moment against a beam integrated by hand: the outer plates
    # push F/2 each, uniformly over their thickness, the middle member F back over its own
    force, d, fy = 10e3, 12e-3, 500e6
    length = 2 * outer + 2 * gap + middle
    x = np.linspace(0.0, length, 200_001)
    outer_load = np.where((x <= outer) | (x >= length - outer), force / 2 / outer, 0.0)
    middle_load = np.where(np.abs(x - length / 2) <= middle / 2, force / middle, 0.0)
    shear = np.concatenate([[0.0], np.cumsum((outer_load - middle_load)[1:] * np.diff(x))])
    moment = np.concatenate([[0.0], np.cumsum(shear[1:] * np.diff(x))])
    u = standards.pin_utilisations(np.array([force]), d, outer, middle, gap, fy, 800e6, fy, planes=2)
    m_rd = 1.5 * math.pi * d**3 / 32 * fy
    assert float(u["bending"]) * m_rd == pytest.approx(np.abs(moment).max(), rel=1e-3)
    assert float(u["bearing"]) == pytest.approx(max(force / middle, force / 2 / outer) / (1.5 * d * fy))


def _scene(components: dict | None = None, parts=None, **mechanism):
    data = {
        "mechanism": {"kind": "four-bar", "crank": "480 mm", "coupler": "840 mm", "rocker": "780 mm", "ground": "1020 mm"}
        | {"speed": "1 Hz", "steps": 720}
        | mechanism,
        "check": {"parts": parts or COMPONENTS, "effects": ["inertia"]},
    }
    if components:
        data["components"] = components
    return parse_scene(data, "test")


def _run(scene):
    from railcheck.check.pipeline import run_pipeline
    from railcheck.check.summary import summary_of

    result = run_pipeline(scene)
    return result, summary_of(result)


def test_default_rig_components_fail_on_the_driving_pin_with_its_figures():
    result, summary = _run(_scene())
    assert "mesh" not in result.stages_run  # components alone: nothing meshed
    pin = result.components["driving-pin"]
    torque = np.abs(result.kinematics.dynamics.torque).max()
    assert pin.figures["force_N"] == pytest.approx(1.4 * torque / 0.06)
    assert summary["verdict"] == "FAIL"
    assert any(f.startswith("driving-pin bending") for f in result.failures_with_figures)
    written = json.loads(to_json(summary))["components"]  # summary.json: NaN and inf written as null or words
    assert written["driving-pin"]["utilisation"] == pytest.approx(pin.utilisation) and not written["driving-pin"]["pass"]
    bearing = result.components["bearings-A"]
    peak = np.hypot(*result.kinematics.dynamics.reactions["A"].T).max()
    assert bearing.figures["static_safety"] == pytest.approx(7800.0 / (peak / 2))


def test_a_class_10_9_pin_passes_and_every_component_then_passes():
    _, summary = _run(_scene({"pin_yield": "900 MPa", "pin_ultimate": "1000 MPa"}))
    assert summary["verdict"] == "PASS", summary["failures_with_figures"]
    assert all(c["pass"] for c in summary["components"].values())


def test_at_rest_the_bearings_life_is_unlimited_and_written_without_inf():
    result, summary = _run(_scene(speed="0 Hz"))
    assert math.isinf(result.components["bearings-O2"].figures["life_h"])
    assert result.components["bearings-O2"].utilisations["life"] == 0.0
    to_json(summary)  # allow_nan=False: an inf left as a number would raise here


def test_component_inputs_refused_in_one_line_naming_the_field():
    with pytest.raises(InputError, match="components.pin_diameter"):
        _scene({"pin_diameter": "8 mm"})  # wider than the rail's 7 mm hole
    with pytest.raises(InputError, match="did you mean 'driving-pin'"):
        _scene(parts=["driving-pn"])
    with pytest.raises(InputError, match="components.shaft_kt"):
        _scene({"shaft_kt": -1})
    with pytest.raises(InputError, match="components.shaft_diameter: value outside the physical range"):
        _scene({"shaft_diameter": "1e-300 mm"})  # a ZeroDivisionError traceback before
    with pytest.raises(InputError, match="components.bearing_spacing"):
        _scene({"bearing_spacing": "1e-300 mm"})
    with pytest.raises(InputError, match="components.carriag_c0"):
        _scene({"carriag_c0": "50 kN"})
    with pytest.raises(InputError, match="no shaft-O4"):
        parse_scene(
            {
                "mechanism": {"kind": "slider-crank", "crank": "120 mm", "coupler": "480 mm", "speed": "1 Hz"},
                "check": {"parts": ["shaft-O4"]},
            },
            "test",
        )


def test_the_motor_shaft_carries_the_cranks_weight_moment_only_on_a_table_top_rig():
    from railcheck.loads.weight import shaft_moment
    from railcheck.model.loading import linkage_lengths, rail_weight

    flat, _ = _run(_scene(parts=["motor-shaft", "bearings-O2"]))
    upright, _ = _run(_scene(parts=["motor-shaft", "bearings-O2"], plane="vertical"))
    scene = flat.scene
    weight = abs(float(shaft_moment(rail_weight(scene, "crank", "four-bar"), linkage_lengths(scene.linkage_spec.linkage))))
    in_plane = np.hypot(*flat.kinematics.dynamics.reactions["O2"].T).max() * 0.03
    assert flat.components["motor-shaft"].figures["moment_Nm"] == pytest.approx(1.4 * (in_plane + weight))
    assert weight > 20.0  # DESIGN.md section 12: about 25 N m at the crank's shaft
    up = upright.kinematics.dynamics.reactions["O2"]
    assert upright.components["motor-shaft"].figures["moment_Nm"] == pytest.approx(1.4 * 0.03 * np.hypot(*up.T).max())


def _swept(components=None, speed="1 Hz"):
    """A components-only sweep of a narrowed rig (no FE: analytic, about a second)."""
    import railcheck

    data = {
        "mechanism": {"kind": "four-bar", "crank": "480 mm", "coupler": "840 mm", "rocker": "780 mm", "ground": "1020 mm"},
        "check": {"parts": COMPONENTS, "effects": ["inertia"]},
        "sweep": {"kind": "four-bar", "crank": ["120 mm", "180 mm"], "coupler": ["600 mm", "660 mm"], "speeds": [speed]},
    }
    if components:
        data["components"] = components
    run = railcheck.sweep(data, serial=True)
    columns = {k: np.array(v) for k, v in run.tables["four-bar"].to_pydict().items()}
    keep = columns["verdict"] != "refused"
    return {k: v[keep] for k, v in columns.items()}


def test_a_sweeps_components_equal_a_check_of_the_setting_and_its_safe_speed_reaches_the_limit():
    table = _swept({"pin_yield": "900 MPa", "pin_ultimate": "1000 MPa"})
    assert table["verdict"].size > 100 and {f"{c}_utilisation" for c in COMPONENTS} <= set(table)
    k = int(np.argmax(table["utilisation"]))  # the worst setting
    row = {name: column[k] for name, column in table.items()}
    mech = {b: f"{row[f'{b}_mm']:.6f} mm" for b in ("crank", "coupler", "rocker", "ground")}
    comp = {"pin_yield": "900 MPa", "pin_ultimate": "1000 MPa"}
    result, _ = _run(_scene(comp, **mech))
    for name, c in result.components.items():  # the batch kinematics against the single setting's
        assert row[f"{name}_utilisation"] == pytest.approx(c.utilisation, rel=1e-6), name
    assert row["governing_part"] == max(result.components, key=lambda n: result.components[n].utilisation)
    bearings = [c.figures["static_safety"] for n, c in result.components.items() if n.startswith("bearings-")]
    assert row["bearing_static_safety"] == pytest.approx(min(bearings), rel=1e-6)  # one bearing model in both
    at_safe, _ = _run(_scene(comp, speed=f"{row['safe_speed_Hz']:.12f} Hz", **mech))
    worst = max(c.utilisation for c in at_safe.components.values())
    assert worst == pytest.approx(1.0, abs=1e-6)  # the components set it: none beyond their limit there
    assert row["safe_speed_part"] in COMPONENTS


def test_a_failing_component_fails_the_sweeps_rows_with_its_criterion():
    table = _swept(speed="3 Hz")  # the class 8.8 driving pin fails where the motor torque is large
    named = np.array(["driving-pin" in (r or "") for r in table["reason"]])
    assert named.any() and (table["verdict"][named] == "fail").all()
    assert (table["driving-pin_utilisation"][named] > 1.0).all()
    assert not named[table["driving-pin_utilisation"] <= 1.0].any()


@pytest.mark.parametrize(
    "override, component, criterion",
    [
        ({"pin_rail_thickness": "0.2 mm"}, "driving-pin", "bearing"),
        ({"pin_yield": "2000 MPa", "pin_ultimate": "60 MPa"}, "driving-pin", "shear"),
        ({"bolt_stress_area": "0.3 mm2"}, "bolts-A", "shear"),
        ({"bolt_grip": "0.1 mm", "bolt_end_distance": "2 mm"}, "bolts-A", "bearing"),
        ({"bolt_stress_area": "0.1 mm2"}, "bolts-A", "tension"),
        ({"shaft_diameter": "2 mm"}, "shaft-A", "yield"),
        ({"shaft_kt": 3.0, "shaft_diameter": "3.2 mm"}, "shaft-A", "fatigue"),
        ({"bearing_static": "100 N"}, "bearings-A", "static"),
        ({"bearing_required_life": "1e12 h"}, "bearings-A", "life"),
        ({"carriage_c0": "600 N"}, "carriage-A", "static"),
    ],
)
def test_each_criterion_fails_a_component_and_the_verdict(override, component, criterion):
    pins = {"pin_yield": "900 MPa", "pin_ultimate": "1000 MPa"}  # the default pin fails: keep it out
    result, summary = _run(_scene(pins | override))
    c = result.components[component]
    assert c.utilisations[criterion] > 1.0 and not c.passed
    assert summary["verdict"] == "FAIL" and f"{component} {criterion}" in result.failures


def test_a_sweep_of_both_kinds_skips_the_rockers_components_on_the_slider_crank():
    import railcheck

    data = {
        "mechanism": {"kind": "four-bar", "crank": "480 mm", "coupler": "840 mm", "rocker": "780 mm", "ground": "1020 mm"},
        "check": {"parts": COMPONENTS, "effects": ["inertia"]},
        "sweep": {
            "crank": ["60 mm", "120 mm"],
            "coupler": ["120 mm", "360 mm"],
        },
    }
    run = railcheck.sweep(data, serial=True)
    slider = run.tables["slider-crank"].column_names
    assert "shaft-O4_utilisation" not in slider and "driving-pin_utilisation" in slider
    assert "shaft-O4_utilisation" in run.tables["four-bar"].column_names


def test_a_chunk_that_checks_no_setting_writes_every_components_column():
    # every chunk writes one schema: a chunk with no setting to check has NaN columns
    from railcheck.geometry.catalogue import RAIL
    from railcheck.sweep.columns import fe_columns
    from railcheck.sweep.context import SweepContext

    scene = _scene()
    ctx = SweepContext(scene, "four-bar", (2 * math.pi,), 720, {}, 7850.0, RAIL)
    col = fe_columns(ctx, 3, None, 0, np.zeros(3, dtype=bool), {})
    assert {f"{c}_utilisation" for c in COMPONENTS} <= set(col)
    assert np.isnan(col["driving-pin_utilisation"]).all() and (col["verdict"] == "refused").all()


def test_bearing_life_matches_a_published_worked_example():
    # C = 50 kN, P = 10 kN per bearing at 1500 r/min: L10h = (50/10)^3 1e6 / (60 x 1500) = 1388.9 h
    # (theprimecalculator.com's worked example of the ISO 281 basic rating life)
    from railcheck.loads.bearings import BallBearing, bearing_life_of_magnitude

    speed = np.full(720, 1500 * 2 * math.pi / 60)
    life = bearing_life_of_magnitude(np.full(720, 2 * 10e3), speed, BallBearing("x", 50e3, 25e3))
    assert life.l10_hours == pytest.approx(1388.9, rel=1e-4)


def test_carriage_static_safety_matches_a_published_example_and_sums_moments_linearly():
    # a carriage of C0 = 28.6 kN under 8 kN with a load factor 1.5: S0 = 28.6 / 12 = 2.38
    # (Technische Antriebselemente's linear-guide sizing example)
    p0 = standards.carriage_equivalent_load(0.0, 8e3 * 1.5, 0.0, 0.0, 0.0, 28.6e3, 300.0, 250.0, 250.0)
    assert 28.6e3 / p0 == pytest.approx(2.383, abs=1e-3)
    # each moment counts as its share of its rating, in C0's units (PBC Linear's multiple-load rule)
    p0 = standards.carriage_equivalent_load(1e3, 2e3, 30.0, 25.0, 0.0, 28.6e3, 300.0, 250.0, 250.0)
    assert p0 / 28.6e3 == pytest.approx(1e3 / 28.6e3 + 2e3 / 28.6e3 + 30 / 300 + 25 / 250)


def test_each_joints_load_path_is_the_verdicts_checks_at_its_governing_instant(tmp_path):
    from railcheck.components.scene_checks import scene_joint_paths
    from railcheck.report.joint_diagram import instant_loads, write_joint_diagram

    scene = _scene()
    result, _ = _run(scene)
    paths = scene_joint_paths(scene, result.kinematics)
    assert list(paths) == ["O2", "A", "B", "O4"]
    reactions = result.kinematics.dynamics.reactions
    for joint, p in paths.items():
        assert p.force_N == pytest.approx(np.hypot(*reactions[joint][p.step]))
        worst = max(p.components, key=lambda n: result.components[n].utilisation)
        static = {k: v for k, v in result.components[worst].utilisations.items() if k != "fatigue" and k != "life"}
        if static:  # a static criterion's peak over the cycle is its peak instant's
            assert max(p.components[worst].utilisations[k] for k in static) == pytest.approx(max(static.values()))
    pin = paths["O2"].components["driving-pin"]
    assert pin.figures["force_N"] == pytest.approx(result.components["driving-pin"].figures["force_N"])
    assert instant_loads(pin.figures, True, 1.4).endswith("(x1.4)")
    assert instant_loads(paths["A"].components["carriage-A"].figures, False, 1.4).endswith("(unfactored)")
    picture = write_joint_diagram(tmp_path / "joints.png", paths, result.components, 1.4)
    assert picture is not None and picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert write_joint_diagram(tmp_path / "none.png", {}, {}, 1.4) is None


def test_the_components_safe_speed_is_where_they_really_reach_their_limit():
    result, summary = _run(_scene())
    safe = result.components_safe_speed
    assert safe.component == "driving-pin" and 0.5 < safe.hz < 1.0
    assert summary["components_safe_speed"]["Hz"] == safe.hz
    assert any(t.startswith(f"components: pass up to {safe.hz:.3g} Hz") for t in result.to_pass)
    below, _ = _run(_scene(speed=f"{safe.hz * 0.999!r} Hz"))
    above, _ = _run(_scene(speed=f"{safe.hz * 1.001!r} Hz"))
    assert all(c.passed for c in below.components.values()) and below.to_pass == []
    assert not above.components["driving-pin"].passed


def test_the_sweeps_maps_draw_the_components_largest_utilisation(monkeypatch, tmp_path):
    """The maps' components row is each setting's largest component utilisation, the same
    figures as the table's columns; the map is written."""
    import railcheck
    import railcheck.sweep.run as sweep_run

    seen: dict = {}
    real = sweep_run.write_maps
    monkeypatch.setattr(sweep_run, "write_maps", lambda aggregates, d: (seen.update(aggregates), real(aggregates, d)))
    data = {
        "mechanism": {"kind": "four-bar", "crank": "480 mm", "coupler": "840 mm", "rocker": "780 mm", "ground": "1020 mm"},
        "check": {"parts": COMPONENTS, "effects": ["inertia"]},
        "sweep": {"kind": "four-bar", "crank": ["120 mm", "180 mm"], "coupler": ["600 mm", "660 mm"]},
        "output": {"dir": str(tmp_path / "s")},
    }
    run = railcheck.sweep(data, serial=True, out=tmp_path / "s")
    table = {k: np.array(v) for k, v in run.tables["four-bar"].to_pydict().items()}
    ok = table["checks_passed"]
    largest = np.max([table[f"{c}_utilisation"][ok] for c in COMPONENTS], axis=0)
    mapped = seen["four-bar"].component_util
    assert np.nanmax(mapped) == pytest.approx(largest.max()) and np.nanmin(mapped) <= largest.min() + 1e-12
    assert (
        np.isfinite(mapped).sum()
        == np.unique(
            np.column_stack([table[f"{b}_mm"][ok] for b in ("crank", "coupler", "rocker", "ground")]), axis=0
        ).shape[0]
    )
    assert (tmp_path / "s" / "map-four-bar.png").exists()
