"""The joints' screws (railcheck.components.screws, .sizing): VDI 2230's preload and
tightening torque against its published table, the slip criterion against SCI P363's
tabulated slip resistance, the two-screw group against statics and the default scene's O2
screws by hand at the torque peak, and every sizing answer: what it returns passes and
the next size down fails."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from railcheck.components import screws, standards
from railcheck.components.kinds import check_component
from railcheck.components.ratings import COMPONENT_SPEC, COMPONENTS
from railcheck.components.scene_checks import check_listed_components, components_input, joint_histories
from railcheck.components.sizing import bearing_needs, screw_needs, shaft_needs
from railcheck.scene import parse_scene

#: ISO 261 M8 x 1 fine thread with a hex head's bearing diameter (d_w 11.63 mm), as VDI
#: 2230's tables take it (ISO 273 medium hole 9 mm)
M8_FINE = screws.Thread("M8x1", 8e-3, 1e-3, 8e-3 - 0.6495e-3, 8e-3 - 1.22687e-3, 39.2e-6, 11.63e-3)


@pytest.mark.parametrize(
    "friction, preloads_kn",
    [(0.10, (20.7, 30.4, 35.6)), (0.12, (20.2, 29.7, 34.7)), (0.14, (19.7, 28.9, 33.9))],
)
def test_assembly_preload_matches_vdi_2230s_table_for_m8x1(friction, preloads_kn):
    # VDI 2230 (2001), "approximate values for metric fine threads" (as Mastik and Bossard
    # publish them): F_M,max at 90 % of R_p0.2 for classes 8.8, 10.9, 12.9, truncated to 0.1 kN
    for grade, kn in zip(("8.8", "10.9", "12.9"), preloads_kn):
        f = screws.assembly_preload(M8_FINE, screws.CLASSES[grade].proof, friction) / 1e3
        assert kn <= f < kn + 0.1, (grade, f)


@pytest.mark.parametrize("friction, torque_nm", [(0.10, 22.8), (0.12, 26.1), (0.14, 29.2)])
def test_tightening_torque_matches_vdi_2230s_table_for_m8x1_class_8_8(friction, torque_nm):
    preload = screws.assembly_preload(M8_FINE, 640e6, friction)
    assert screws.tightening_torque(M8_FINE, preload, friction, friction, 9e-3) == pytest.approx(torque_nm, abs=0.05)


def test_slip_criterion_is_en_1993_1_8s_slip_resistance_tabulated_in_sci_p363():
    # SCI P363: an M20 8.8 preloaded bolt (F_p,C = 0.7 f_ub A_s = 137.2 kN), class A
    # surfaces (mu 0.5), one interface, normal holes, gamma_M3 1.25: F_s,Rd = 54.9 kN. VDI
    # 2230's slip criterion with the clamp F_p,C and the slip safety gamma_M3 is the same rule.
    clamp = 0.7 * 800e6 * 245e-6
    at = lambda force: float(screws.slip_utilisation(force, 0.0, clamp, 0.5, 1.25))  # noqa: E731
    assert at(54.9e3) == pytest.approx(1.0, abs=1e-3)
    assert screws.clamp_needed(54.88e3, 0.0, 0.5, 1.25) == pytest.approx(clamp, rel=1e-3)
    assert at(1e3) < 1.0 < at(56e3)
    assert math.isinf(float(screws.slip_utilisation(1.0, 2 * clamp, clamp, 0.5, 1.25)))  # pulled open: nothing clamps


def test_embedding_loss_is_settlement_over_the_screws_resilience_by_hand():
    # M6 through 13 mm: head 0.5 d and the tapped part 0.33 d in the nominal section, the
    # grip and the engaged 0.5 d in the core (d3 4.773 mm); E 205 GPa; 10 um of settlement
    t = screws.THREADS["M6"]
    nominal, core = math.pi * 6e-3**2 / 4, math.pi * 4.773e-3**2 / 4
    resilience = (0.83 * 6e-3) / (205e9 * nominal) + (13e-3 + 3e-3) / (205e9 * core)
    assert screws.embedding_loss(t, 13e-3, 10e-6) == pytest.approx(10e-6 / resilience, rel=1e-12)
    assert 1.5e3 < screws.embedding_loss(t, 13e-3, 10e-6) < 2.5e3  # a fifth of an M6 8.8's preload


def test_the_rails_hole_admits_m5_and_m6():
    assert screws.admitted(7e-3, 11e-3) == ("M5", "M6")  # M4's head falls through, M8 does not pass
    assert screws.admitted(9e-3, 14e-3) == ("M6", "M8")  # an M8 rail: its M5 head falls through


def test_two_screws_share_the_force_and_carry_the_moment_as_a_couple():
    along, across, torque, e, a = 300.0, -400.0, 50.0, 0.012, 0.06
    first, second = standards.two_screw_forces(along, across, torque, e, a)
    moment = torque - e * across  # about the centroid: the force's line e before it
    # statics: the two screws' forces (along/2, across/2 -+ M/a) add to the force and carry M
    assert first == pytest.approx(math.hypot(along / 2, across / 2 - moment / a))
    assert second == pytest.approx(math.hypot(along / 2, across / 2 + moment / a))
    assert (across / 2 - moment / a) + (across / 2 + moment / a) == pytest.approx(across)
    assert (-a / 2) * (across / 2 - moment / a) + (a / 2) * (across / 2 + moment / a) == pytest.approx(moment)


def _default(components: dict | None = None, speed: str = "1 Hz"):
    data = {
        "mechanism": {"kind": "four-bar", "crank": "480 mm", "coupler": "840 mm", "rocker": "780 mm", "ground": "1020 mm"}
        | {"speed": speed, "steps": 720},
        "check": {
            "parts": ["crank-screws-O2", "coupler-screws-A", "shaft-O2", "shaft-O4", "bearings-O4"],
            "effects": ["inertia"],
        },
    }
    if components:
        data["components"] = components
    return parse_scene(data, "test")


def _kinematics(scene):
    from railcheck.model.kinematics_stage import kinematics_input, run_kinematics

    return run_kinematics(kinematics_input(scene))


def test_the_o2_screws_by_hand_at_the_torque_peak():
    """The crank rail is screwed to O2's upper plate through its first two holes, 60 mm
    apart, the shaft's line midway: at the step of the largest motor torque, each screw
    carries half the joint force in the rail's axes and the torque as a couple T / 60 mm
    across the rail; slip needs S_G F_Q / mu_T of clamp."""
    scene = _default()
    kin = _kinematics(scene)
    dyn, theta = kin.dynamics, kin.motion.theta[:, 0]
    k = int(np.argmax(np.abs(dyn.torque)))
    fx, fy = dyn.reactions["O2"][k]
    along = fx * math.cos(theta[k]) + fy * math.sin(theta[k])
    across = -fx * math.sin(theta[k]) + fy * math.cos(theta[k])
    couple = dyn.torque[k] / 0.06
    by_hand = max(math.hypot(along / 2, across / 2 - couple), math.hypot(along / 2, across / 2 + couple))
    assert abs(dyn.torque[k]) > 100.0  # the default rig's peak torque, about 137 N m
    h = joint_histories(components_input(scene), kin)
    c = check_component(COMPONENTS["crank-screws-O2"], scene.components, h, 1.0, components_input(scene).strengths)
    transverse = standards.two_screw_forces(*_axes(h), h.torque, 0.0, 0.06)
    assert transverse.max(axis=0)[k] == pytest.approx(by_hand, rel=1e-12)
    assert c.figures["transverse_N"] >= by_hand
    m6 = screws.THREADS["M6"]
    clamp = screws.assembly_preload(m6, 640e6, 0.12) / 1.6 - screws.embedding_loss(m6, 13e-3, 10e-6)
    # every step by hand: each screw's transverse force over its clamp less the weight's pull on it
    c_all, s_all = np.cos(theta), np.sin(theta)
    al = dyn.reactions["O2"][:, 0] * c_all + dyn.reactions["O2"][:, 1] * s_all
    ac = -dyn.reactions["O2"][:, 0] * s_all + dyn.reactions["O2"][:, 1] * c_all
    pulls = h.screw_tension["O2"]
    ratio = max(
        np.max(np.hypot(al / 2, ac / 2 - dyn.torque / 0.06)) / (clamp - pulls[0]),
        np.max(np.hypot(al / 2, ac / 2 + dyn.torque / 0.06)) / (clamp - pulls[1]),
    )
    assert c.utilisations["slip"] == pytest.approx(1.8 * ratio / 0.15, rel=1e-12)


def _axes(h):
    from railcheck.components.checks import in_rail_axes

    return in_rail_axes(h.reactions["O2"], h.angles["crank"])


def _results(components: dict | None = None, speed: str = "1 Hz"):
    scene = _default(components, speed)
    return scene, check_listed_components(components_input(scene), _kinematics(scene))


def test_a_screw_sizing_answer_passes_and_the_next_size_down_fails():
    """At several speeds the O2 screws' answer is the first of the admitted catalogue
    (sizes, then classes) that passes: it passes, the one before it slips."""
    catalogue = [(size, grade) for size in ("M5", "M6") for grade in ("8.8", "10.9", "12.9")]
    answered = set()
    for speed in ("0.3 Hz", "0.34 Hz", "0.37 Hz", "0.42 Hz", "0.47 Hz"):
        _, results = _results(speed=speed)
        answer = results["crank-screws-O2"].needs["screw"]
        if answer is None:
            continue
        size, grade = answer.split()
        answered.add(answer)
        _, chosen = _results({"screw_size": size, "screw_class": grade}, speed=speed)
        assert chosen["crank-screws-O2"].passed, (speed, answer)
        k = catalogue.index((size, grade))
        if k > 0:
            down = catalogue[k - 1]
            _, smaller = _results({"screw_size": down[0], "screw_class": down[1]}, speed=speed)
            assert not smaller["crank-screws-O2"].passed, (speed, down)
        t, c = screws.THREADS[size], screws.CLASSES[grade]
        preload = screws.assembly_preload(t, c.proof, 0.12)
        torque = screws.tightening_torque(t, preload, 0.12, 0.12, 7e-3)
        assert results["crank-screws-O2"].needs["tightening_torque_Nm"] == pytest.approx(torque)
    assert len(answered) >= 2  # the answers move with the load: not one fixed reply


def test_where_no_screw_holds_the_friction_it_names_would():
    _, results = _results()
    needs = results["crank-screws-O2"].needs
    assert needs["screw"] is None and needs["strongest"] == "M6 12.9"
    friction = needs["friction_needed"]
    _, at = _results({"screw_class": "12.9", "joint_friction": math.ceil(friction * 1000) / 1000})
    _, below = _results({"screw_class": "12.9", "joint_friction": math.floor(friction * 1000) / 1000})
    assert at["crank-screws-O2"].utilisations["slip"] <= 1.0 < below["crank-screws-O2"].utilisations["slip"]


@pytest.mark.parametrize("shaft", ["shaft-O2", "shaft-O4"])
def test_a_shafts_needed_diameter_meets_its_criterion_and_a_thinner_one_fails(shaft):
    _, results = _results()
    d = results[shaft].needs["diameter_needed_m"]
    assert 5e-3 < d < 25e-3
    _, exact = _results({"shaft_diameter": f"{d * 1e3!r} mm"})
    assert exact[shaft].utilisation == pytest.approx(1.0, rel=1e-9)
    _, thinner = _results({"shaft_diameter": f"{d * 0.99e3!r} mm"})
    assert not thinner[shaft].passed


def test_a_constant_moment_is_a_mean_stress_in_de_goodman():
    # Shigley eq. 7-8 with M_m alone: 1/n = 16 / (pi d^3) * 2 K_f M_m / S_ut
    u = standards.shaft_utilisations(np.zeros((1, 3)), np.zeros((1, 3)), 0.02, 2.0, 1.5, 200e6, 750e6, 490e6, 30.0)
    k = 16.0 / (math.pi * 0.02**3)
    assert float(u["fatigue"][0]) == pytest.approx(k * 2 * 2.0 * 30.0 / 750e6, rel=1e-12)
    d = standards.de_goodman_diameter(0.0, 0.0, 0.0, 2.0, 1.5, 200e6, 750e6, mm=30.0)
    assert d**3 == pytest.approx(16.0 / math.pi * 2 * 2.0 * 30.0 / 750e6, rel=1e-12)


def test_de_goodman_diameter_solves_shigley_example_7_1_back():
    # Example 7-1's loads give n = 1.62 at d = 1.100 in: solved for d at n = 1.62, 1.100 in
    d = standards.de_goodman_diameter(1260.0, 0.0, 1100.0, 1.58, 1.39, 29.3e3, 105e3, n=1.62, start=1.0)
    assert d == pytest.approx(1.100, abs=0.002)


def test_a_bearing_spacing_answer_meets_the_static_safety_and_a_closer_one_fails():
    _, results = _results({"bearing_static": "1500 N"})
    spacing = results["bearings-O4"].needs["spacing_needed_m"]
    assert 0 < spacing < 1.0
    _, exact = _results({"bearing_static": "1500 N", "bearing_spacing": f"{spacing * 1e3!r} mm"})
    assert exact["bearings-O4"].utilisations["static"] == pytest.approx(1.0, rel=1e-9)
    _, closer = _results({"bearing_static": "1500 N", "bearing_spacing": f"{spacing * 0.99e3!r} mm"})
    assert closer["bearings-O4"].utilisations["static"] > 1.0


def test_sizing_on_its_own_seams():
    """The sizing functions read the check's own histories: a bearing with no weight couple
    needs no spacing; one whose joint force alone exceeds its rating needs a larger bearing."""
    scene = _default()
    h = joint_histories(components_input(scene), _kinematics(scene))
    m = components_input(scene).strengths
    r = check_component(COMPONENTS["bearings-A"], scene.components, h, 1.4, m)
    assert bearing_needs(r, scene.components, h, 1.4, m) == {"spacing_needed_m": 0.0}
    weak = dataclasses.replace(scene.components, bearing_static=10.0)
    r = check_component(COMPONENTS["bearings-O4"], weak, h, 1.4, m)
    assert math.isinf(bearing_needs(r, weak, h, 1.4, m)["spacing_needed_m"])
    r = check_component(COMPONENTS["shaft-O4"], COMPONENT_SPEC, h, 1.4, m)
    assert shaft_needs(r, COMPONENT_SPEC, h, 1.4, m)["diameter_needed_m"] < 0.025
    r = check_component(COMPONENTS["coupler-screws-A"], COMPONENT_SPEC, h, 1.4, m)
    assert screw_needs(r, COMPONENT_SPEC, h, 1.4, m)["screw"] == "M5 8.8"
