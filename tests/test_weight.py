"""The table-top rig's weight out of plane (railcheck.loads.weight, docs/model.md):
statics by hand, a grooved rail cantilevered under its own weight against beam theory, the
plane's scene key, and the weight in a check (a standing rig carries it)."""

from dataclasses import replace

import numpy as np
import pytest

from helpers import FINAL_DESIGN
from railcheck.base.errors import InputError
from railcheck.fea.assembly import assemble
from railcheck.fea.loading import body_force_vectors, resultant, surface_dofs
from railcheck.fea.materials import MATERIALS
from railcheck.fea.mesh import stress_nodes
from railcheck.fea.stress import recover_stress
from railcheck.fea.system import solve, supports
from railcheck.geometry import mesh_part
from railcheck.geometry.catalogue import RAIL
from railcheck.geometry.models import rail as rail_part
from railcheck.loads.weight import GRAVITY, joint_forces, shaft_moment
from railcheck.model.inputs import parts_input
from railcheck.model.loading import linkage_lengths, load_model, weight_columns
from railcheck.scene import parse_scene

STEEL = MATERIALS["steel"]


def _scene(extra_mechanism: str = "", check: str = "") -> object:
    import tomllib

    text = FINAL_DESIGN + extra_mechanism + '\n[check]\nparts = ["crank-rail", "coupler-rail", "rocker-rail"]\n' + check
    return parse_scene(tomllib.loads(text))


# --- statics: the default scene's crank and rocker by hand (seed 000 masses) ---


def test_the_default_crank_carries_its_weight_moment_at_its_shaft_and_at_its_second_screw():
    """By hand, with the seed's masses (plate 1.155, carriage 0.68, coupling 0.577 kg) and the
    meshed profile's 3.16 kg/m: every rail starts 50 mm behind its first joint (the rail's
    20 mm end distance and half the 60 mm pitch: the joint's shaft midway between the first
    two holes, where the upper plate's two screws are). The coupler (840 mm; its 1000 mm
    rail's centre 450 mm from A) rests on A and B, so A takes its rail's weight times
    (840 - 450) / 840 and the coupling bolted at A; the crank (480 mm; its 700 mm rail's
    centre 300 mm from O2) carries that, its plate and carriage at A and its own weight,
    cantilevered from the shaft through the plate's two screws, 30 mm either side of it."""
    scene = _scene()
    model = load_model(parts_input(scene), "crank-rail", STEEL.density)
    per_m = scene.masses.rail_mass_per_m
    assert per_m == pytest.approx(3.16, abs=0.01)
    coupler_at_a = per_m * 1.0 * GRAVITY * (0.84 - 0.45) / 0.84
    at_a = (1.155 + 0.68 + 0.577) * GRAVITY + coupler_at_a
    rail = per_m * 0.7 * GRAVITY
    shaft = at_a * 0.48 + rail * (0.35 - 0.05)
    beyond = per_m * (0.65 - 0.03) * GRAVITY  # the crank rail beyond its second screw
    at_screw = at_a * (0.48 - 0.03) + beyond * (0.65 - 0.03) / 2
    lengths = linkage_lengths(scene.linkage_spec.linkage)
    assert float(shaft_moment(model.weight, lengths)) == pytest.approx(shaft, rel=1e-9)
    assert shaft == pytest.approx(24.75, abs=0.01) and at_screw == pytest.approx(23.06, abs=0.01)
    near, drive, far = (float(v) for v in joint_forces(model.weight, lengths))
    assert far == pytest.approx(-at_a, rel=1e-9)
    # the loads past the second screw, about it: the model's forces give the hand's moment
    moment_at_screw = -far * (0.48 - 0.03) + beyond * (0.65 - 0.03) / 2
    assert moment_at_screw == pytest.approx(at_screw, rel=1e-12)
    # and about the shaft's line the two screws' forces carry the shaft's moment
    assert (drive - near) * 0.03 == pytest.approx(shaft, rel=1e-12)
    assert near + drive + far == pytest.approx(rail, rel=1e-12)  # the shaft's clamp holds the weight


def test_each_bar_balances_its_weight_and_the_links_rest_on_their_joints():
    """Vertical equilibrium of every rail; the coupler's joint forces are its rail's weight
    shared by the lever rule (its carried masses go straight to the joints); what the
    coupler's joints take is what the crank and rocker carry at A and B, with their masses."""
    scene = _scene()
    lengths = linkage_lengths(scene.linkage_spec.linkage)
    per_m, g = scene.masses.rail_mass_per_m, GRAVITY
    forces = {
        bar: joint_forces(load_model(parts_input(scene), f"{bar}-rail", STEEL.density).weight, lengths)
        for bar in ("crank", "coupler", "rocker")
    }
    for bar, length in (("crank", 0.7), ("coupler", 1.0), ("rocker", 1.0)):
        assert sum(float(v) for v in forces[bar]) == pytest.approx(per_m * length * g, rel=1e-12)
    a, drive, b = forces["coupler"]
    assert float(drive) == 0.0
    assert float(a) == pytest.approx(per_m * 1.0 * g * (0.84 - 0.45) / 0.84, rel=1e-9)  # its centre 450 mm from A
    assert float(forces["rocker"][2]) == pytest.approx(-(float(b) + (0.577 + 1.155 + 0.68) * g), rel=1e-12)


def test_the_weight_columns_are_the_factored_joint_forces_at_every_step_and_setting():
    """Constant over steps; a sweep's settings each with their own lengths."""
    scene = _scene()
    model = load_model(parts_input(scene), "rocker-rail", STEEL.density)
    lengths = {
        "crank": np.array([[0.48], [0.6]]),
        "coupler": np.array([[0.84], [0.96]]),
        "rocker": np.array([[0.78], [0.9]]),
    }
    cols = weight_columns(model, lengths, (2, 5))
    assert cols.shape == (2, 5, 4)
    np.testing.assert_array_equal(cols[:, 0], cols[:, 4])
    one = weight_columns(model, {b: float(v[1, 0]) for b, v in lengths.items()}, (5,))
    np.testing.assert_allclose(cols[1], one, rtol=1e-15)
    assert cols[0, 0, 0] == pytest.approx(-1.4 * GRAVITY)


# --- the scene's plane ---


def test_the_rig_is_horizontal_by_default_and_vertical_when_gravity_is_listed():
    assert _scene().plane == "horizontal"
    vertical = _scene(check='effects = ["inertia", "gravity"]\n')
    assert vertical.plane == "vertical" and "gravity" in vertical.effects
    stated = _scene('plane = "vertical"\n')
    assert stated.plane == "vertical" and "gravity" in stated.checked.effects  # its weight is always there
    assert load_model(parts_input(vertical), "crank-rail", STEEL.density).weight is None
    assert load_model(parts_input(_scene()), "crank-rail", STEEL.density).weight is not None


def test_gravity_on_a_horizontal_rig_is_refused_naming_the_effect():
    with pytest.raises(InputError) as err:
        _scene('plane = "horizontal"\n', 'effects = ["inertia", "gravity"]\n')
    assert err.value.field == "check.effects" and "out of plane" in str(err.value)
    with pytest.raises(InputError) as err:
        _scene('plane = "sideways"\n')
    assert err.value.field == "mechanism.plane"


# --- a grooved rail cantilevered under its own weight, out of plane ---


@pytest.fixture(scope="module")
def cantilever():
    """A 600 mm grooved size-25 rail without holes (an end distance of 350 mm leaves none:
    a hole 20 mm from the clamp, where the moment is largest, softens the root by 6%, which
    beam theory cannot see), its x = 0 face clamped, under its own weight along -z: P2, the
    check's rail mesh sizes."""
    geo = rail_part(0.6, replace(RAIL, end_distance=0.35))
    mesh = mesh_part(geo, 20e-3, 6e-3)
    K, basis = assemble(mesh.points, mesh.tets, STEEL, 2, mesh.curved)
    F = -STEEL.density * GRAVITY * body_force_vectors(basis)[:, 2]
    U, _ = solve(K, F, supports(basis, mesh.groups, ["end_pivot"]), "direct", basis)
    return geo, mesh, basis, F, U


def test_a_rail_cantilevered_under_its_own_weight_bends_as_beam_theory(cantilever):
    """sigma = M z / I_y at a section mid-way (x = 300 mm, M = w (L - x)^2 / 2) and the tip's
    deflection w L^4 / (8 E I_y), the grooved profile's closed-form I_y, within 2%."""
    geo, mesh, basis, F, U = cantilever
    length, section = geo.get("length"), geo.section
    w = -resultant(basis, F)[2] / length  # N/m
    x0 = 0.3
    moment = w * (length - x0) ** 2 / 2  # hogging: the top in tension
    S = recover_stress(basis, U, STEEL)
    from test_freebody import section_fit

    _, _, c = section_fit(S, stress_nodes(basis), x0)
    assert c * section.inertia_out_of_plane == pytest.approx(moment, rel=0.02)
    tip = surface_dofs(basis, mesh.groups, "end_free")
    sag = -(tip.weights @ U[tip.dofs[:, 2]]) / tip.weights.sum()
    assert sag == pytest.approx(w * length**4 / (8 * STEEL.youngs_modulus * section.inertia_out_of_plane), rel=0.02)


# --- the weight in a check ---


@pytest.mark.slow  # a crank-rail check (mesh and solve, about 10 s cold)
def test_a_standing_table_top_rig_bends_its_crank_as_the_statics_of_its_weight_say():
    """At 0 Hz the horizontal rig's crank rail carries its weight alone (a vertical rig's
    would carry nothing in plane): the FE's out-of-plane bending at a section between holes
    4 and 5 times I_y equals the factored moment of the loads beyond it (the far joint's
    weight and the rail beyond the section) within 3%, the holes every 60 mm disturbing
    the section's stress by a few per cent (as the in-plane check of test_freebody)."""
    import tomllib

    from railcheck.check.pipeline import run_pipeline

    text = FINAL_DESIGN + 'speed = "0 Hz"\nsteps = 3\n[check]\nparts = ["crank-rail"]\n'
    scene = parse_scene(tomllib.loads(text))
    assert scene.linkage_spec.speed == 0.0
    result = run_pipeline(scene, jobs=1)
    part = result.parts["crank-rail"]
    cyc, geo = part.cycle, part.geometry
    S = cyc.fields.stress @ cyc.C[0]
    xs = geo.get("hole_x")
    x0 = 0.5 * (xs[4] + xs[5])  # part frame: the shaft (O2) midway between xs[0] and xs[1]
    per_m = scene.masses.rail_mass_per_m * GRAVITY  # N/m, the dynamics' rail (the FE's graded density carries it)
    at_a = (1.155 + 0.68 + 0.577) * GRAVITY + per_m * 1.0 * (0.84 - 0.45) / 0.84  # by hand, as above
    beyond = geo.get("length") - x0
    moment = 1.4 * (at_a * (0.5 * (xs[0] + xs[1]) + 0.48 - x0) + per_m * beyond**2 / 2)  # hogging: top in tension
    from test_freebody import section_fit

    _, _, c = section_fit(S, cyc.fields.nodes, x0)
    assert c * geo.section.inertia_out_of_plane == pytest.approx(moment, rel=0.03)
