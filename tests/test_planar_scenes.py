"""Planar mechanism scenes ([mechanism] kind = "planar"): the examples against independent
truths (the catalogue's solves, the rig's closed-form kinematics and Newton-Euler, a six-bar's
second loop solved apart as a circle intersection, the quick-return's travel), equilibrium at
every step, mobility of a redundant model and a dead centre, the symbolic equations against
the numerical ones, refusals in one line naming the key, and the page in a real browser."""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from helpers import chromium_driver
from railcheck.base.errors import InputError
from railcheck.cli import main
from railcheck.kinematics.dynamics import inverse_dynamics
from railcheck.kinematics.linkage import FourBar
from railcheck.kinematics.motion import solve_fourbar, solve_motion
from railcheck.kinematics.planar.catalogue import CATALOGUE, driver_values
from railcheck.kinematics.planar.model import evaluate
from railcheck.kinematics.planar.solver import solve
from railcheck.studies.planar_outputs import planar_summary
from railcheck.studies.planar_scene import planar_scene
from railcheck.studies.planar_study import study_planar

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def example(name: str, steps: int | None = None):
    data = tomllib.loads((EXAMPLES / f"{name}.toml").read_text())
    if steps:
        data["mechanism"]["driver"]["steps"] = steps
    return study_planar(planar_scene(data, name))


@pytest.mark.parametrize("name", ["a-4-1553", "a-z-1139", "a-z-1066"])
def test_the_seeds_examples_trace_what_the_catalogue_traces(name):
    """Each seed example file solves to the catalogue entry's motion (whose own tests hold
    the strophoid and the hyperbola to their closed forms to 1e-9)."""
    mech = CATALOGUE[name]()
    ref = solve(mech, driver_values(name, 121)).point(*mech.tracer)[0]
    got = next(iter(example(name, 121).tracers.values()))[:, :2]
    assert np.abs(got - ref).max() <= 1e-9 * np.abs(ref).max()


def _frames_at_first_points(data: dict) -> dict:
    """The scene rewritten as a user writes it: each body's frame at its first point, its
    centre of mass given by ``centre_of_mass`` (the example has its frames at the centres)."""
    from railcheck.units import parse_quantity

    for body in data["mechanism"]["bodies"]:
        pts = {k: [parse_quantity(v, "length", k) for v in xy] for k, xy in body["points"].items()}
        first = next(iter(pts.values()))
        body["points"] = {k: [f"{(x - first[0]) * 1e3!r} mm", f"{(y - first[1]) * 1e3!r} mm"] for k, (x, y) in pts.items()}
        body["centre_of_mass"] = [f"{-first[0] * 1e3!r} mm", f"{-first[1] * 1e3!r} mm"]
        x, y, th = (parse_quantity(v, d, "at") for v, d in zip(body["at"], ("length", "length", "angle")))
        c, s = math.cos(th), math.sin(th)
        body["at"] = [
            f"{(x + c * first[0] - s * first[1]) * 1e3!r} mm",
            f"{(y + s * first[0] + c * first[1]) * 1e3!r} mm",
            body["at"][2],
        ]
    return data


@pytest.mark.parametrize("frames", ["at the centres of mass", "at the first points"])
def test_the_rig_four_bar_scene_equals_the_closed_form_and_newton_euler(frames):
    """examples/rig-four-bar.toml against the closed-form four-bar (positions to 1e-9 m) and
    its Newton-Euler reactions and torque (a separate formulation, 1e-8 of the peak); the
    same with every body's frame at its first point and ``centre_of_mass`` saying where its
    mass is, as a user writes it."""
    data = tomllib.loads((EXAMPLES / "rig-four-bar.toml").read_text())
    if frames == "at the first points":
        data = _frames_at_first_points(data)
        assert data["mechanism"]["bodies"][0]["points"]["O2"] == ["0.0 mm", "0.0 mm"]
    study = study_planar(planar_scene(data))
    closed = solve_motion(FourBar(0.48, 0.84, 0.78, 1.02), 2 * math.pi, 361)
    for body, point in ((1, "A"), (3, "B")):
        np.testing.assert_allclose(study.motion.point(body, point)[0], closed.points[point], atol=1e-9)
    ne = inverse_dynamics(closed, "newton-euler")
    for joint in ("O2", "A", "B", "O4"):
        ref = ne.reactions[joint]
        assert np.abs(study.reactions.forces[joint] - ref).max() <= 1e-8 * np.abs(ref).max(), joint
    assert np.abs(study.reactions.effort - ne.torque).max() <= 1e-8 * np.abs(ne.torque).max()


def _circle_meet(c, o, rc, ro, previous):
    """The point at rc from each c (n, 2) and ro from o, the one nearer ``previous``."""
    d = o - c
    dist = np.linalg.norm(d, axis=1)
    a = (rc**2 - ro**2 + dist**2) / (2 * dist)
    h = np.sqrt(rc**2 - a**2)
    u = d / dist[:, None]
    n = np.stack([-u[:, 1], u[:, 0]], axis=1)
    both = [c + a[:, None] * u + s * h[:, None] * n for s in (1, -1)]
    pick = np.argmin([np.linalg.norm(b[0] - previous) for b in both])
    return both[pick]


@pytest.mark.parametrize(
    "name, carrier, local, o6, link, output",
    [
        ("watt-six-bar", "rocker", (0.54, 0.24), (1.44, 0.90), 0.72, 0.60),
        ("stephenson-six-bar", "coupler", (0.42, 0.30), (0.60, 1.10), 0.66, 0.54),
    ],
)
def test_a_six_bars_second_loop_solved_apart(name, carrier, local, o6, link, output):
    """The six-bar's output pin D: the closed-form four-bar gives the ternary link's pose,
    C on it, then D where the circles about C and O6 meet (on the assembled branch)."""
    study = example(name)
    lk = FourBar(0.24, 0.84, 0.78, 1.02)
    closed = solve_fourbar(lk, 0.0, 361)
    k = 2 if carrier == "rocker" else 1
    origin = np.array([1.02, 0.0]) if carrier == "rocker" else closed.points["A"]
    th = closed.theta[:, k]
    c = origin + np.stack([np.cos(th) * local[0] - np.sin(th) * local[1], np.sin(th) * local[0] + np.cos(th) * local[1]], 1)
    got = study.tracers["output.D"][:, :2]
    expected = _circle_meet(c, np.array(o6), link, output, got[0])
    assert np.abs(got - expected).max() <= 1e-9


def test_the_rig_as_a_quick_return_carries_its_carriage_between_the_crank_pin_and_the_pivot():
    """The inverted slider-crank from the rig's parts: the carriage bears on the long rail
    from |O2C| - crank to |O2C| + crank from A (360 to 840 mm), the lever's swing is the
    closed form's +-asin(240/600), the slide carries no force along the rail (ideal guide)."""
    study = example("rig-inverted-slider-crank")
    summary = planar_summary(study)
    assert summary["slides_mm"]["slide"]["from"] == pytest.approx(360.0, abs=0.05)
    assert summary["slides_mm"]["slide"]["to"] == pytest.approx(840.0, abs=1e-6)
    lever = study.motion.q[:, 5]
    swing = np.degrees(np.ptp(np.unwrap(lever)))
    assert swing == pytest.approx(2 * math.degrees(math.asin(240 / 600)), abs=0.05)
    # the quick return: one stroke takes 180 + 2 asin(240/600) deg of the crank's turn, the other the rest
    rising = np.count_nonzero(np.diff(np.unwrap(lever)) > 0) / (lever.size - 1) * 360
    slow = 180 + 2 * math.degrees(math.asin(240 / 600))
    assert min(abs(rising - slow), abs(rising - (360 - slow))) <= 1.0
    load = study.reactions.loads["slide"][2]  # on the lever, in the lever's own axes
    along = np.cos(lever) * load[:, 0] + np.sin(lever) * load[:, 1]
    assert np.abs(along).max() <= 1e-9 * np.abs(load).max()


@pytest.mark.parametrize("name", ["rig-four-bar", "rig-slider-crank", "rig-inverted-slider-crank"])
def test_every_body_is_in_equilibrium_at_every_step(name):
    """Each body's joint loads and weight add up to its mass times its acceleration, to 1e-9
    of the largest force (summed here from the loads by joint, apart from the solve)."""
    study = example(name)
    mech, r = study.mechanism, study.reactions
    g = study.scene.gravity
    rate = study.scene.rate
    for k, body in enumerate(mech.bodies, start=1):
        total = np.zeros((study.motion.s.size, 3))
        for loads in r.loads.values():
            total += loads.get(k, 0.0)
        total[:, 1] -= body.mass * g
        inertial = study.motion.qdd[:, 3 * k - 3 : 3 * k] * rate**2 * [body.mass, body.mass, body.inertia]
        assert np.abs(total - inertial).max() <= 1e-9 * r.scale, body.name


PARALLELOGRAM = {
    "mechanism": {
        "kind": "planar",
        "ground": {"O2": ["0 mm", "0 mm"], "O4": ["500 mm", "0 mm"], "O6": ["250 mm", "0 mm"]},
        "driver": {"range": ["10 deg", "80 deg"], "steps": 31},
        "bodies": [
            {"name": "crank", "points": {"O": ["0 mm", "0 mm"], "A": ["200 mm", "0 mm"]}, "at": ["0 mm", "0 mm", "10 deg"]},
            {
                "name": "coupler",
                "points": {"A": ["0 mm", "0 mm"], "B": ["500 mm", "0 mm"], "C": ["250 mm", "0 mm"]},
                "at": ["197 mm", "35 mm", "0 deg"],
            },
            {
                "name": "rocker",
                "points": {"O": ["0 mm", "0 mm"], "B": ["200 mm", "0 mm"]},
                "at": ["500 mm", "0 mm", "10 deg"],
            },
            {
                "name": "middle",
                "points": {"O": ["0 mm", "0 mm"], "C": ["200 mm", "0 mm"]},
                "at": ["250 mm", "0 mm", "10 deg"],
            },
        ],
        "joints": [
            {"name": "O2", "kind": "revolute", "bodies": ["ground", "crank"], "points": ["O2", "O"]},
            {"name": "A", "kind": "revolute", "bodies": ["crank", "coupler"], "points": ["A", "A"]},
            {"name": "B", "kind": "revolute", "bodies": ["coupler", "rocker"], "points": ["B", "B"]},
            {"name": "O4", "kind": "revolute", "bodies": ["ground", "rocker"], "points": ["O4", "O"]},
            {"name": "O6", "kind": "revolute", "bodies": ["ground", "middle"], "points": ["O6", "O"]},
            {"name": "C", "kind": "revolute", "bodies": ["coupler", "middle"], "points": ["C", "C"]},
        ],
        "drives": [{"joint": "O2"}],
    }
}


def test_a_redundant_model_moves_and_names_the_joint_to_relax():
    """A parallelogram with a third parallel bar: Gruebler 0, yet one DOF; the repeated
    equation is named by joint with seed 002's self-alignment, and the motion runs."""
    study = study_planar(planar_scene(copy.deepcopy(PARALLELOGRAM)))
    m = planar_summary(study)["mobility"]
    assert (m["gruebler"], m["dof"], m["redundant"]) == (0, 1, 1)
    assert [r["joint"] for r in m["redundant_equations"]] == ["C"] and "slot" in m["redundant_equations"][0]["relax"]
    assert study.motion.ended is None and study.motion.s.size == 31


def test_a_dead_centre_ends_the_motion_with_its_driver_value_not_a_jump():
    """The parallelogram driven through 0 deg, where its bars fold onto the ground line (a
    change point): the motion stops there, the summary says where, nothing past it."""
    data = copy.deepcopy(PARALLELOGRAM)
    data["mechanism"]["driver"]["range"] = ["30 deg", "-30 deg"]
    del data["mechanism"]["bodies"][3], data["mechanism"]["joints"][4:]
    for b in data["mechanism"]["bodies"]:
        b["at"][2] = "30 deg"
    data["mechanism"]["bodies"][1]["at"] = ["173 mm", "100 mm", "0 deg"]
    study = study_planar(planar_scene(data))
    assert study.motion.ended and "driver value" in study.motion.ended
    assert 0 <= np.degrees(study.motion.s[-1]) <= 3  # stopped at the fold, not beyond
    assert study.motion.s.size < 61


def test_the_symbolic_equations_are_the_solvers():
    """sympy's Phi(q, s) of the quick-return (revolutes, a prismatic, a relative drive)
    equals the numerical constraint vector at random coordinates, to 1e-12."""
    import sympy as sp

    from railcheck.studies.planar_symbolic import constraint_equations, coordinates

    mech = example("rig-inverted-slider-crank", 25).mechanism
    q, s = coordinates(mech)
    f = sp.lambdify([q, s], [e for _, e in constraint_equations(mech)])
    rng = np.random.default_rng(3)
    for _ in range(5):
        qv, sv = rng.normal(size=mech.n), float(rng.normal())
        phi = evaluate(mech, qv, s=sv)[0]
        assert np.abs(np.array(f(qv, sv), float) - phi).max() <= 1e-12


def _bad(mutate) -> str:
    data = tomllib.loads((EXAMPLES / "rig-inverted-slider-crank.toml").read_text())
    mutate(data["mechanism"])
    with pytest.raises(InputError) as info:
        study_planar(planar_scene(data))
    return str(info.value)


@pytest.mark.parametrize(
    "mutate, words",
    [
        (lambda m: m["joints"][1].update(points=["A", "Z"]), ("mechanism.joints[1].points", "no point 'Z'")),
        (lambda m: m["joints"][0].update(bodies=["crank", "crank"]), ("mechanism.joints[0].bodies", "and itself")),
        (lambda m: m["drives"].append({"joint": "O2"}), ("mechanism.drives[1].joint", "driven twice")),
        (lambda m: m["drives"].append({"joint": "C"}), ("mechanism.drives", "2 drive(s) for 1 degree")),
        (lambda m: m["joints"][3].update(lines=[["C", "C"], ["A", "E"]]), ("mechanism.joints[3].lines", "coincident")),
        (lambda m: m["bodies"][0].update(name="ground"), ("mechanism.bodies[0].name", "other than")),
        (lambda m: m["bodies"][0].update(colour="red"), ("mechanism.bodies[0].colour", "unknown key")),
        (lambda m: m.update(tracers=["lever.Q"]), ("mechanism.tracers[0]", "no point 'Q'")),
        (lambda m: m["driver"].update(steps=1), ("mechanism.driver.steps", "from 2")),
        (lambda m: m["driver"].update(steps=10), ("mechanism.driver.steps", "jump the assembly branch: 25 or more")),
        (lambda m: m["driver"].update(range=["0 deg", "1e12 deg"]), ("mechanism.driver.range", "100 turns")),
        (lambda m: m["driver"].update(speed="1e12 Hz"), ("mechanism.driver.speed", "not a mechanism's speed")),
        (lambda m: m["bodies"][0].update(mass="1e30 kg"), ("mechanism.bodies[0].mass", "1e+06")),
        (lambda m: m["bodies"][0].update(inertia="nan kg m2"), ("mechanism.bodies[0].inertia", "nan")),
        (lambda m: m["joints"].pop(3), ("mechanism.drives", "for 3 degree(s)", "add a drive or a joint")),
    ],
)
def test_a_bad_planar_scene_is_refused_naming_its_key(mutate, words):
    message = _bad(mutate)
    assert all(w in message for w in words), message
    assert "\n" not in message


def test_a_mechanism_that_cannot_close_is_refused_at_its_placements():
    """The rig's four-bar with its ground pivots 3 m apart: crank, coupler and rocker
    (2.1 m) cannot reach; one line naming the bodies' placements, no motion."""
    data = tomllib.loads((EXAMPLES / "rig-four-bar.toml").read_text())
    data["mechanism"]["ground"]["O4"] = ["3000 mm", "0 mm"]
    with pytest.raises(InputError) as info:
        study_planar(planar_scene(data))
    assert info.value.field == "mechanism.bodies" and "cannot be assembled" in str(info.value)


def test_the_command_writes_the_study_and_a_check_refuses_a_planar_scene(tmp_path, capsys):
    scene = EXAMPLES / "rig-inverted-slider-crank.toml"
    assert main(["mechanism", str(scene), "--out", str(tmp_path / "r"), "--steps", "73"]) == 0
    out = capsys.readouterr().out
    assert "slide slide: along lever from 360.0 to 840.0 mm" in out and "model: rigid bodies" in out
    assert sorted(p.name for p in (tmp_path / "r").iterdir()) == [
        "mechanism.html",
        "reactions.csv",
        "summary.json",
        "tracers.csv",
    ]
    head = (tmp_path / "r" / "tracers.csv").read_text().splitlines()[0]
    assert head.startswith("driver_deg,lever.E_x_mm,lever.E_y_mm,lever.E_vx_mm_s")
    assert main(["check", str(scene)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "mechanism.kind" in err and "railcheck mechanism" in err


def test_the_api_returns_the_frozen_study():
    import railcheck

    run = railcheck.mechanism(str(EXAMPLES / "watt-six-bar.toml"), steps=37)
    assert run.summary["mobility"]["dof"] == 1 and run.study.motion.s.size == 37 and run.files == ()
    with pytest.raises(InputError, match="steps"):
        railcheck.mechanism("a-z-1139", steps=1)
    with pytest.raises(InputError, match="holds only"):
        railcheck.mechanism({"mechanism": {"kind": "planar"}, "check": {}})


PAGE = """
const s = document.getElementById('slider'); s.value = String(arguments[0]); s.dispatchEvent(new Event('input'));
const v = document.getElementById('velocity'); v.checked = true; v.dispatchEvent(new Event('change'));
return drawn;
"""


def test_the_page_moves_with_the_slider_and_shows_the_tracer_of_the_csv(tmp_path):
    """mechanism.html in headless Chromium: each slider position draws the tracer where
    tracers.csv has it (through the page's own scale), its velocity arrow on demand, and a
    cursor on every reaction plot at the drawn driver value."""
    assert (
        main(["mechanism", str(EXAMPLES / "rig-inverted-slider-crank.toml"), "--out", str(tmp_path), "--steps", "91"]) == 0
    )
    rows = np.loadtxt(tmp_path / "tracers.csv", delimiter=",", skiprows=1)
    driver = chromium_driver()
    try:
        driver.get(f"file://{tmp_path / 'mechanism.html'}")
        seen = []
        for k in (0, 30, 77):
            drawn = driver.execute_script(PAGE, k)
            assert drawn["step"] == k
            assert drawn["velocity"] == pytest.approx(rows[k, 3:5], abs=1e-3)
            assert len(drawn["plots"]) == 5  # four joints and the drive
            seen.append((drawn["tracer_px"], [p["cursor_px"] for p in drawn["plots"]]))
        data = driver.execute_script("return D;")
        assert data["tracer"][77] == pytest.approx(rows[77, 1:3].tolist(), abs=1e-6)
        # positions on screen: a linear map of the CSV's mm (the page's own scale, checked on three steps)
        px = np.array([t for t, _ in seen])
        mm = rows[[0, 30, 77], 1:3]
        scale = (px[1] - px[0]) / (mm[1] - mm[0])
        assert scale[0] == pytest.approx(-scale[1], rel=1e-3)  # y up on screen
        np.testing.assert_allclose(px[2], px[0] + scale * (mm[2] - mm[0]), atol=0.05)
        assert seen[0][1][0] < seen[1][1][0] < seen[2][1][0]  # the cursors move with the driver
    finally:
        driver.quit()


def test_a_drives_ratio_and_offset_move_the_joint_by_ratio_s_plus_offset():
    """The rig's four-bar driven at ratio 2 over 0-180 deg from an offset of 360 deg: the
    crank turns once, twice as fast as the parameter: the closed form's positions and its
    velocities at twice the parameter's speed."""
    data = tomllib.loads((EXAMPLES / "rig-four-bar.toml").read_text())
    data["mechanism"]["driver"].update(range=["0 deg", "180 deg"], steps=181)
    data["mechanism"]["drives"][0].update(ratio=2, offset="360 deg")
    study = study_planar(planar_scene(data))
    rate = study.scene.rate
    closed = solve_motion(FourBar(0.48, 0.84, 0.78, 1.02), 2 * rate, 181)
    P, V, _ = study.motion.point(3, "B")
    np.testing.assert_allclose(P, closed.points["B"], atol=1e-9)
    np.testing.assert_allclose(V * rate, closed.velocities["B"], atol=1e-9 * np.abs(closed.velocities["B"]).max())


@pytest.mark.parametrize(
    "name, file",
    [("a-4-1553", "a-4-1553"), ("a-z-1139", "a-z-1139"), ("a-z-1066", "a-z-1066"), ("four-bar", "rig-four-bar")],
)
def test_an_example_written_from_the_catalogue_is_what_the_writer_writes(name, file):
    """The catalogue's example files are the writer's text (comments aside): they cannot
    drift from the entries the catalogue's tests hold to the seed's curves."""
    from railcheck.kinematics.planar.catalogue import SWEEPS
    from railcheck.studies.planar_writer import scene_text

    def body(text):
        return [line for line in text.splitlines() if not line.startswith("#")]

    written = scene_text(CATALOGUE[name](), SWEEPS[name], 361, abs(SWEEPS[name]))
    assert body((EXAMPLES / f"{file}.toml").read_text()) == body(written)


@pytest.mark.parametrize(
    "name, order",
    [
        ("rig-four-bar", ["crank crank", "RRR coupler+rocker"]),
        ("rig-slider-crank", ["crank crank", "RRP coupler+slider"]),
        ("watt-six-bar", ["crank crank", "RRR coupler+rocker", "RRR link+output"]),
        ("stephenson-six-bar", ["crank crank", "RRR coupler+rocker", "RRR link+output"]),
        ("rig-inverted-slider-crank", ["crank crank", "RPR carriage+lever"]),
        ("a-4-1553", ["crank 2", "RRP 3+4"]),  # the guide's line on the slider, the ground's point on it
        ("a-z-1139", None),
    ],
)
def test_a_mechanism_of_dyads_is_solved_in_closed_form_too(name, order):
    """Seed 002 §2.5: dyad by dyad, every coordinate in the driver in closed form; every body
    point within 1e-9 m of Newton's; a-z-1139 (its guides are no dyads) has none. The
    seed's a-4-1553 is its own check of the reading: its crank and L-shaped coupler on a slider."""
    summary = planar_summary(example(name, 181))["closed_form"]
    assert summary["dyads"] == order
    if order:
        assert summary["largest_difference_mm"] <= 1e-6  # 1e-9 m


@pytest.mark.parametrize("assembly", ["open", "crossed"])
def test_the_closed_form_keeps_the_assembly_branch_of_the_start(assembly):
    """dyad_positions against the closed-form four-bar of either assembly: the branch is
    the one the start is on (the example's crank placement, its other bodies on that side)."""
    from railcheck.kinematics.planar.catalogue import rig_fourbar
    from railcheck.kinematics.planar.dyads import dyad_positions

    lk = FourBar(0.48, 0.84, 0.78, 1.02, assembly)
    mech = rig_fourbar(lk)
    s = np.linspace(0, 2 * math.pi, 181)
    closed = solve_fourbar(lk, 1.0, 181)
    solution = dyad_positions(mech, s, mech.initial_q())
    from railcheck.kinematics.planar.solver import PlanarMotion

    z = np.zeros_like(solution.q)
    motion = PlanarMotion(mech, s, solution.q, z, z)
    np.testing.assert_allclose(motion.point(3, "B")[0], closed.points["B"], atol=1e-12)
