"""The joints' components against published figures: Shigley's worked shaft example, the
EN 1993-1-8 bolt resistances tabulated in SCI P363 (the "blue book"), hand checks of the
screw groups and the bearings, and the pipeline's verdict on both sides (the screws by
VDI 2230 and their sizing: tests/test_screws.py)."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from railcheck.base.errors import InputError
from railcheck.components import standards
from railcheck.files import to_json
from railcheck.model.records import safe_speed_words
from railcheck.scene import parse_scene
from railcheck.units import floored

COMPONENTS = ["crank-screws-O2", "coupler-screws-A", "rocker-screws-O4"]
COMPONENTS += ["crank-screws-A", "coupler-screws-B", "rocker-screws-B"]
COMPONENTS += ["shaft-O2", "shaft-A", "shaft-B", "shaft-O4"]
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


def _scene(components: dict | None = None, parts=None, factor: float = 1.4, **mechanism):
    data = {
        "mechanism": {"kind": "four-bar", "crank": "480 mm", "coupler": "840 mm", "rocker": "780 mm", "ground": "1020 mm"}
        | {"speed": "1 Hz", "steps": 720}
        | mechanism,
        "check": {"parts": parts or COMPONENTS, "effects": ["inertia"], "factor": factor},
    }
    if components:
        data["components"] = components
    return parse_scene(data, "test")


def _run(scene):
    from railcheck.check.pipeline import run_pipeline
    from railcheck.check.summary import summary_of

    result = run_pipeline(scene)
    return result, summary_of(result)


#: what lets the O2 screws hold the motor's torque by friction (their sizing's answer)
HOLDS = {"screw_class": "12.9", "joint_friction": 0.5}


def test_default_rig_components_fail_on_the_o2_screws_slip_with_their_figures():
    result, summary = _run(_scene())
    assert "mesh" not in result.stages_run  # components alone: nothing meshed
    screws = result.components["crank-screws-O2"]
    torque = np.abs(result.kinematics.dynamics.torque).max()
    assert screws.figures["transverse_N"] >= torque / 0.06  # the motor's couple over the two screws, at least
    assert summary["verdict"] == "FAIL"
    assert any(f.startswith("crank-screws-O2 slip") for f in result.failures_with_figures)
    assert [c for c, r in result.components.items() if not r.passed] == ["crank-screws-O2"]
    written = json.loads(to_json(summary))["components"]  # summary.json: NaN and inf written as null or words
    o2 = written["crank-screws-O2"]
    assert o2["utilisation"] == pytest.approx(screws.utilisation) and not o2["pass"]
    assert o2["needs"]["screw"] is None and o2["needs"]["friction_needed"] > 0.15
    bearing = result.components["bearings-A"]
    peak = np.hypot(*result.kinematics.dynamics.reactions["A"].T).max()
    assert bearing.figures["static_safety"] == pytest.approx(7800.0 / (peak / 2))


def test_a_stronger_screw_on_a_rougher_joint_holds_and_every_component_then_passes():
    _, summary = _run(_scene(HOLDS))
    assert summary["verdict"] == "PASS", summary["failures_with_figures"]
    assert all(c["pass"] for c in summary["components"].values())
    assert "joint_friction" not in summary["components"]["crank-screws-O2"]["assumed"]  # given by the scene


def test_at_rest_the_bearings_life_is_unlimited_and_written_without_inf():
    result, summary = _run(_scene(speed="0 Hz"))
    assert math.isinf(result.components["bearings-O2"].figures["life_h"])
    assert result.components["bearings-O2"].utilisations["life"] == 0.0
    to_json(summary)  # allow_nan=False: an inf left as a number would raise here


def test_component_inputs_refused_in_one_line_naming_the_field():
    with pytest.raises(InputError, match="components.screw_size: M8 does not fit the rail's 7 mm hole"):
        _scene({"screw_size": "M8"})  # larger than the rail's 7 mm hole
    with pytest.raises(InputError, match="components.screw_size: M4 does not fit"):
        _scene({"screw_size": "M4"})  # its 7 mm head falls through the 7 mm hole
    with pytest.raises(InputError, match="components.screw_class: must be one of"):
        _scene({"screw_class": "14.9"})
    with pytest.raises(InputError, match="components.joint_friction: value outside the physical range"):
        _scene({"joint_friction": 0.001})  # no friction: no clamp holds anything
    with pytest.raises(InputError, match="components.joint_friction: 0.9 is outside 0.05-0.8"):
        _scene({"joint_friction": 0.9})  # beyond what steel on steel gives
    with pytest.raises(InputError, match="components.screw_preload_utilisation: 1.2 is outside"):
        _scene({"screw_preload_utilisation": 1.2})  # a preload above the screw's proof load
    with pytest.raises(InputError, match="components.screw_edge_distance: 1 mm is below EN 1993-1-8's minimum"):
        _scene({"screw_edge_distance": "1 mm"})  # "inf% bearing" before: a negative k1
    with pytest.raises(InputError, match="did you mean 'crank-screws-O2'"):
        _scene(parts=["crank-screws-02"])
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

    flat, _ = _run(_scene(parts=["shaft-O2", "bearings-O2"]))
    upright, _ = _run(_scene(parts=["shaft-O2", "bearings-O2"], plane="vertical"))
    scene = flat.scene
    weight = abs(
        float(
            shaft_moment(
                rail_weight(scene.masses, scene.geometry, "crank", "four-bar"), linkage_lengths(scene.linkage_spec.linkage)
            )
        )
    )
    in_plane = np.hypot(*flat.kinematics.dynamics.reactions["O2"].T).max() * 0.016
    assert flat.components["shaft-O2"].figures["moment_Nm"] == pytest.approx(1.4 * in_plane)
    assert flat.components["shaft-O2"].figures["mean_moment_Nm"] == pytest.approx(1.4 * weight)  # turns with the shaft
    assert weight > 20.0  # about 25 N m at the crank's shaft (docs/model.md)
    up = upright.kinematics.dynamics.reactions["O2"]
    assert upright.components["shaft-O2"].figures["moment_Nm"] == pytest.approx(1.4 * 0.016 * np.hypot(*up.T).max())
    assert upright.components["shaft-O2"].figures["mean_moment_Nm"] == 0.0
    torque = np.abs(flat.kinematics.dynamics.torque).max()
    assert flat.components["shaft-O2"].figures["torque_Nm"] == pytest.approx(1.4 * torque)


def _swept(components=None, speed="1 Hz", summary=None):
    """A components-only sweep of a narrowed rig (no FE: analytic, about a second)."""
    import railcheck

    data = {
        "mechanism": {"kind": "four-bar", "crank": "480 mm", "coupler": "840 mm", "rocker": "780 mm", "ground": "1020 mm"},
        "check": {"parts": COMPONENTS, "effects": ["inertia"]},
        "sweep": {"kind": "four-bar", "crank": ["120 mm", "180 mm"], "coupler": ["600 mm", "660 mm"], "speeds": [speed]},
        "output": {"plots": False},  # the columns are read, not the maps
    }
    if components:
        data["components"] = components
    run = railcheck.sweep(data, serial=True)
    if summary is not None:
        summary.update(run.summary)
    columns = {k: np.array(v) for k, v in run.tables["four-bar"].to_pydict().items()}
    keep = columns["verdict"] != "refused"
    return {k: v[keep] for k, v in columns.items()}


def test_a_sweeps_components_equal_a_check_of_the_setting_and_its_safe_speed_reaches_the_limit():
    table = _swept(HOLDS)
    assert table["verdict"].size > 100 and {f"{c}_utilisation" for c in COMPONENTS} <= set(table)
    k = int(np.argmax(table["utilisation"]))  # the worst setting
    row = {name: column[k] for name, column in table.items()}
    mech = {b: f"{row[f'{b}_mm']:.6f} mm" for b in ("crank", "coupler", "rocker", "ground")}
    comp = HOLDS
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


def test_a_sweeps_screw_needs_equal_a_checks_and_the_screw_named_passes_where_the_next_smaller_fails():
    from railcheck.components.ratings import COMPONENT_SPEC
    from railcheck.components.sizing import screw_choices

    summary: dict = {}
    table = _swept(speed="2 Hz", summary=summary)  # every O2 screw from M5 8.8 to none over this corner
    choices = [" ".join(c) for c in screw_choices(COMPONENT_SPEC)]
    column = table["crank-screws-O2_needs"]
    # an M6 8.8 clamps less than an M5 12.9 (which comes first), so no setting needs it
    assert set(column) == (set(choices) | {"none"}) - {"M6 8.8"}, set(column)
    needs = summary["by_kind"]["four-bar"]["screw_needs"]["crank-screws-O2"]
    assert needs["every_setting"] == "none" and list(needs["settings"])[-1] == "none"
    assert needs["settings"] == {n: int(np.sum(column == n)) for n in needs["settings"]}
    assert summary["by_kind"]["four-bar"]["screw_needs"]["crank-screws-A"]["every_setting"] in choices
    for need in ("M5 10.9", "M6 12.9", "none"):
        k = int(np.flatnonzero(column == need)[0])
        mech = {b: f"{table[f'{b}_mm'][k]:.6f} mm" for b in ("crank", "coupler", "rocker", "ground")}
        result, _ = _run(_scene(parts=["crank-screws-O2"], speed="2 Hz", **mech))
        screw = result.components["crank-screws-O2"].needs["screw"]
        assert (screw or "none") == need  # the sweep's vectorised sizing is the check's
        if need == "none":
            continue
        size, grade = need.split()
        sized, _ = _run(_scene({"screw_size": size, "screw_class": grade}, parts=["crank-screws-O2"], speed="2 Hz", **mech))
        assert sized.components["crank-screws-O2"].passed
        size, grade = choices[choices.index(need) - 1].split()
        smaller, _ = _run(
            _scene({"screw_size": size, "screw_class": grade}, parts=["crank-screws-O2"], speed="2 Hz", **mech)
        )
        assert not smaller.components["crank-screws-O2"].passed


def test_a_sweeps_shaft_diameters_and_bearing_spacings_needed_equal_a_checks_and_the_summary_holds_the_largest():
    summary: dict = {}
    table = _swept(summary=summary)
    needed = summary["by_kind"]["four-bar"]["sizes_needed_m"]
    spacing = table["bearings-O4_spacing_needed_mm"]
    k = int(np.nanargmax(spacing))
    mech = {b: f"{table[f'{b}_mm'][k]:.6f} mm" for b in ("crank", "coupler", "rocker", "ground")}
    result, _ = _run(_scene(parts=["bearings-O4"], **mech))
    assert result.components["bearings-O4"].needs["spacing_needed_m"] * 1e3 == pytest.approx(spacing[k], rel=1e-9)
    assert needed["bearings-O4_spacing"] * 1e3 == pytest.approx(np.nanmax(spacing), rel=1e-12)
    for shaft in ("shaft-O2", "shaft-O4"):
        column = table[f"{shaft}_diameter_needed_mm"]
        assert needed[f"{shaft}_diameter"] * 1e3 == pytest.approx(np.nanmax(column), rel=1e-12)
        k = int(np.nanargmax(column))
        mech = {b: f"{table[f'{b}_mm'][k]:.6f} mm" for b in ("crank", "coupler", "rocker", "ground")}
        result, _ = _run(_scene(parts=[shaft], **mech))
        assert result.components[shaft].needs["diameter_needed_m"] * 1e3 == pytest.approx(column[k], rel=1e-9)
        sized, _ = _run(_scene({"shaft_diameter": f"{column[k] * 1.001:.6f} mm"}, parts=[shaft], **mech))
        thin, _ = _run(_scene({"shaft_diameter": f"{column[k] * 0.98:.6f} mm"}, parts=[shaft], **mech))
        assert sized.components[shaft].passed and not thin.components[shaft].passed


def test_a_failing_component_fails_the_sweeps_rows_with_its_criterion():
    table = _swept(speed="3 Hz")  # the O2 screws slip where the motor torque is large
    named = np.array(["crank-screws-O2" in (r or "") for r in table["reason"]])
    assert named.any() and (table["verdict"][named] == "fail").all()
    assert (table["crank-screws-O2_utilisation"][named] > 1.0).all()
    assert not named[table["crank-screws-O2_utilisation"] <= 1.0].any()


@pytest.mark.parametrize(
    "override, factor, component, criterion",
    [
        ({}, 1.4, "crank-screws-O2", "slip"),
        ({"screw_size": "M5"} | HOLDS, 3.0, "crank-screws-O2", "shear"),
        ({"screw_grip": "0.2 mm"} | HOLDS, 1.4, "crank-screws-O2", "bearing"),
        ({"screw_size": "M5"} | HOLDS, 20.0, "rocker-screws-O4", "tension"),
        ({"screw_size": "M5"} | HOLDS, 20.0, "rocker-screws-O4", "shear+tension"),
        ({"shaft_diameter": "4 mm"} | HOLDS, 1.4, "shaft-A", "yield"),
        ({"shaft_diameter": "4 mm"} | HOLDS, 1.4, "shaft-A", "fatigue"),
        ({"bearing_static": "100 N"} | HOLDS, 1.4, "bearings-A", "static"),
        ({"bearing_required_life": "1e12 h"} | HOLDS, 1.4, "bearings-A", "life"),
        ({"carriage_c0": "600 N"} | HOLDS, 1.4, "carriage-A", "static"),
    ],
)
def test_each_criterion_fails_a_component_and_the_verdict(override, factor, component, criterion):
    result, summary = _run(_scene(override, factor=factor))
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
        "output": {"plots": False},
    }
    run = railcheck.sweep(data, serial=True)
    slider = run.tables["slider-crank"].column_names
    assert "shaft-O4_utilisation" not in slider and "crank-screws-O2_utilisation" in slider
    assert "shaft-O4_utilisation" in run.tables["four-bar"].column_names


def test_a_chunk_that_checks_no_setting_writes_every_components_column():
    # every chunk writes one schema: a chunk with no setting to check has NaN columns
    from railcheck.geometry.catalogue import RAIL
    from railcheck.sweep.columns import fe_columns
    from railcheck.sweep.context import SweepContext
    from railcheck.sweep.inputs import sweep_input

    ctx = SweepContext(sweep_input(_scene()), "four-bar", (2 * math.pi,), 720, {}, 7850.0, RAIL)
    col = fe_columns(ctx, 3, None, 0, np.zeros(3, dtype=bool), {})
    assert {f"{c}_utilisation" for c in COMPONENTS} <= set(col)
    assert np.isnan(col["crank-screws-O2_utilisation"]).all() and (col["verdict"] == "refused").all()


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
    from railcheck.components.scene_checks import components_input, listed_joint_paths
    from railcheck.report.joint_diagram import instant_loads, write_joint_diagram

    scene = _scene()
    result, _ = _run(scene)
    paths = listed_joint_paths(components_input(scene), result.kinematics)
    assert list(paths) == ["O2", "A", "B", "O4"]
    reactions = result.kinematics.dynamics.reactions
    for joint, p in paths.items():
        assert p.force_N == pytest.approx(np.hypot(*reactions[joint][p.step]))
        worst = max(p.components, key=lambda n: result.components[n].utilisation)
        static = {k: v for k, v in result.components[worst].utilisations.items() if k != "fatigue" and k != "life"}
        if static:  # a static criterion's peak over the cycle is its peak instant's
            assert max(p.components[worst].utilisations[k] for k in static) == pytest.approx(max(static.values()))
    screws = paths["O2"].components["crank-screws-O2"]
    assert screws.figures["shear_N"] == pytest.approx(result.components["crank-screws-O2"].figures["shear_N"])
    assert instant_loads(screws.figures, True, 1.4).endswith("(x1.4)")
    assert instant_loads(paths["A"].components["carriage-A"].figures, False, 1.4).endswith("(unfactored)")
    picture = write_joint_diagram(tmp_path / "joints.png", paths, result.components, 1.4)
    assert picture is not None and picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert write_joint_diagram(tmp_path / "none.png", {}, {}, 1.4) is None


def test_the_components_safe_speed_is_where_they_really_reach_their_limit():
    result, summary = _run(_scene())
    safe = result.components_safe_speed
    assert safe.component == "crank-screws-O2" and safe.criterion == "slip" and 0.3 < safe.hz < 0.6
    assert summary["components_safe_speed"]["Hz"] == safe.hz
    assert safe_speed_words(result.safe_speed).startswith(f"every part and component passes up to {floored(safe.hz)} Hz")
    assert summary["safe_speed"] == {"Hz": safe.hz, "set_by": "crank-screws-O2", "criterion": "slip"}
    below, _ = _run(_scene(speed=f"{safe.hz * 0.999!r} Hz"))
    above, _ = _run(_scene(speed=f"{safe.hz * 1.001!r} Hz"))
    assert all(c.passed for c in below.components.values()) and below.to_pass == []
    assert not above.components["crank-screws-O2"].passed


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


def test_a_components_table_no_listed_component_reads_is_said_not_dropped():
    """Issue 79: ``[components]`` beside a ``[check] parts`` without a component was
    ignored without a word; now the check warns and names the keys."""
    from railcheck.check.pipeline import run_pipeline

    scene = _scene({"shaft_diameter": "20 mm", "joint_friction": 0.3}, parts=["crank-rail"])
    said = run_pipeline(dataclasses.replace(scene, check=dataclasses.replace(scene.check, parts=()))).warnings
    assert (
        said[0]
        == "[components] sets joint_friction, shaft_diameter, but [check] parts lists no component: nothing reads them"
    )
    listed = run_pipeline(_scene({"shaft_diameter": "20 mm"}, parts=["shaft-A"])).warnings
    assert not any("[components]" in w for w in listed)


def test_values_the_scene_sets_are_given_not_assumed():
    """A [components] value the scene sets is listed as given (as written) and dropped from
    the assumed list, in the console and in report.html's note."""
    from railcheck.report.text import components_table

    result, _ = _run(_scene(components={"screw_class": "10.9", "joint_friction": 0.2}, parts=["crank-screws-O2"]))
    text = " ".join(line.strip() for line in components_table(result))
    assumed = text.split("assumed (", 1)[1].split("given (", 1)[0]
    assert 'given (the scene\'s [components], not assumed): joint_friction = 0.2, screw_class = "10.9"' in text
    assert "screw_class" not in assumed and "joint_friction" not in assumed and "screw_thread_friction" in assumed
    plain, _ = _run(_scene(parts=["crank-screws-O2"]))
    assert "given (" not in " ".join(components_table(plain))
