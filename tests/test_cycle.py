"""The whole crank cycle by unit-load superposition: against direct solves, the seed
method, beam-theory fatigue by hand, and the rail's own inertia."""

import math
import tomllib

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from helpers import FINAL_DESIGN
from railcheck.fea.elasticity import HoleLoad, Support, solve_elasticity, von_mises
from railcheck.fea.fatigue import alternating_and_mean, endurance_limit, safety_factor
from railcheck.fea.hull import candidate_steps
from railcheck.fea.materials import MATERIALS
from railcheck.fea.superpose import component_range, envelope, stress_at, von_mises_max
from railcheck.fea.unitcases import TractionCase, solve_unit_cases
from railcheck.geometry.mesher import mesh_part
from railcheck.geometry.models import bar
from railcheck.model.inputs import parts_input
from railcheck.model.jobs import bolt_holes
from railcheck.model.kinematics_stage import kinematics_input, run_kinematics
from railcheck.model.loading import load_model, source_histories, unit_cases
from railcheck.parts import geometry_of, kind_of
from railcheck.scene import parse_scene

STEEL = MATERIALS["steel"]


def crank_scene(extra: str = "", lengths: str = FINAL_DESIGN):
    """The crank rail clamped at its first hole (the 2013 model; free bodies: test_freebody.py)."""
    text = lengths + 'speed = "1 Hz"\nsteps = 720\n[check]\nparts = ["crank-rail"]\nsupport = "clamped"\n' + extra
    return parse_scene(tomllib.loads(text))


def first_cases(fields, k):
    """The unit fields of the first ``k`` cases only."""
    from dataclasses import replace

    return replace(
        fields,
        stress=fields.stress[:, :, :k],
        tip=fields.tip[:, :k],
        displacement=fields.displacement[:, :, :k],
        names=fields.names[:k],
    )


@pytest.fixture(scope="module")
def crank():
    """The crank rail on its default P2 mesh (the default check's, meshed once per run),
    its unit fields and the default kinematics."""
    scene = crank_scene('effects = ["inertia", "gravity", "rail-inertia"]\n[mesh]\nsize = "20 mm"\nhole_size = "6 mm"\n')
    geo = geometry_of("crank-rail", {})
    mesh = mesh_part(geo, 20e-3, 6e-3)
    holes = bolt_holes(parts_input(scene), "crank-rail", geo)
    cases = unit_cases(load_model(parts_input(scene), "crank-rail", STEEL.density), geo, holes)
    kind = kind_of("crank-rail")
    fields, meta = solve_unit_cases(
        mesh,
        STEEL,
        [kind.support],
        cases,
        order=2,
        tip_group=kind.tip,
        exclude_distance=kind.exclusion(geo),
        solver="direct",
    )
    return scene, geo, mesh, holes, fields, meta


def direct_stress(mesh, holes, c, body=(0.0, 0.0)):
    """solve_elasticity with the instant's bolt forces (c[0], c[1] shared by the holes)
    and a uniform body force (N/m^3)."""
    per_hole = (c[0] / len(holes), c[1] / len(holes), 0.0)
    return solve_elasticity(
        mesh,
        STEEL,
        [Support("shaft_hole")],
        [HoleLoad(g, per_hole) for g in holes],
        order=2,
        tip_group="end_free",
        solver="direct",
        body_force=np.array([body[0], body[1], 0.0]),
    )


# one instant in the fast tier; the two others (the same property, 3 s each) in the slow one
@pytest.mark.parametrize("step", [0, pytest.param(200, marks=pytest.mark.slow), pytest.param(555, marks=pytest.mark.slow)])
def test_superposition_equals_a_direct_solve_at_three_instants(crank, step):
    scene, geo, mesh, holes, fields, meta = crank
    fields = first_cases(fields, 2)
    plain = crank_scene()
    (h,) = source_histories(
        load_model(parts_input(plain), "crank-rail", STEEL.density), run_kinematics(kinematics_input(plain)), holes
    )
    direct = direct_stress(mesh, holes, h.C[step])
    scale = np.abs(direct.stress).max()
    assert np.abs(stress_at(fields.stress, h.C[step]) - direct.stress).max() < 1e-9 * scale
    np.testing.assert_allclose(
        fields.tip @ h.C[step], direct.tip_displacement, rtol=1e-9, atol=1e-9 * np.abs(direct.tip_displacement).max()
    )


@pytest.mark.slow  # 3 s; the fast tier keeps superposition against a direct solve at one instant
def test_superposition_with_body_forces_equals_a_direct_solve(crank):
    scene, geo, mesh, holes, fields, meta = crank
    assert list(fields.names) == ["bolt_x", "bolt_y", "body_x", "body_y", "body_rot", "body_rad"]
    (h,) = source_histories(
        load_model(parts_input(scene), "crank-rail", STEEL.density), run_kinematics(kinematics_input(scene)), holes
    )
    c = h.C[300].copy()
    c[4:] = 0.0  # the direct solver takes uniform body forces only
    direct = direct_stress(mesh, holes, c, c[2:4])
    # gravity and the bolt loads partly cancel, so the floor is the solve's rounding times
    # the terms' size over the result's: 1e-8 here, 1e-9 for the bolt loads alone (above)
    assert np.abs(stress_at(fields.stress, c) - direct.stress).max() < 1e-8 * np.abs(direct.stress).max()


def test_hull_candidates_give_the_exact_maximum(crank):
    *_, fields, _ = crank
    t = np.linspace(0, 2 * np.pi, 3000)
    C = np.column_stack([300 * np.cos(t), 250 * np.sin(2 * t + 0.3), 40 * np.cos(3 * t)])
    steps = candidate_steps(C)
    assert steps.size <= t.size
    full, _ = von_mises_max(fields.stress[:, :, [0, 1, 2]], C)
    hull, _ = von_mises_max(fields.stress[:, :, [0, 1, 2]], C[steps])
    np.testing.assert_allclose(hull, full, rtol=1e-12)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    crank_mm=st.integers(3, 8),
    coupler_mm=st.integers(12, 16),
    rocker_mm=st.integers(10, 16),
    ground_mm=st.integers(12, 17),
    hz=st.sampled_from([0.5, 1.0, 2.0]),
)
def test_envelope_is_never_below_the_seed_method(crank, crank_mm, coupler_mm, rocker_mm, ground_mm, hz):
    *_, holes, fields, _ = crank
    lengths = (
        f'[mechanism]\nkind = "four-bar"\ncrank = "{60 * crank_mm} mm"\ncoupler = "{60 * coupler_mm} mm"\n'
        f'rocker = "{60 * rocker_mm} mm"\nground = "{60 * ground_mm} mm"\n'
    )
    bars = sorted([crank_mm, coupler_mm, rocker_mm, ground_mm])
    if bars[0] != crank_mm or bars[0] + bars[3] >= bars[1] + bars[2]:
        return  # only Grashof crank-rockers revolve fully
    scene = crank_scene('effects = ["inertia", "gravity", "rail-inertia"]\n', lengths.replace("1 Hz", f"{hz} Hz"))
    (h,) = source_histories(
        load_model(parts_input(scene), "crank-rail", STEEL.density), run_kinematics(kinematics_input(scene)), holes
    )
    env = envelope(fields, h.C)
    seed = von_mises(stress_at(fields.stress, h.C[h.seed_step]))[fields.verdict_mask].max()
    brute = von_mises_max(fields.stress, h.C)[0][fields.verdict_mask].max()
    assert env.max_von_mises >= seed * (1 - 1e-12)
    assert env.max_von_mises == pytest.approx(brute, rel=1e-12)


def test_default_crank_rail_governs_where_the_transverse_load_peaks(crank):
    *_, holes, fields, _ = crank
    fields = first_cases(fields, 2)
    scene = crank_scene()  # the default effects: mechanism inertia only
    kin = run_kinematics(kinematics_input(scene))
    (h,) = source_histories(load_model(parts_input(scene), "crank-rail", STEEL.density), kin, holes)
    env = envelope(fields, h.C)
    angle = np.degrees(h.crank_angle)
    transverse_peak = angle[np.argmax(np.abs(h.C[:, 1]))]
    magnitude_peak = angle[h.seed_step]
    governing = angle[env.step]
    assert abs(governing - transverse_peak) < 2.0
    assert abs(governing - magnitude_peak) > 4.0
    seed = von_mises(stress_at(fields.stress, h.C[h.seed_step]))[fields.verdict_mask].max()
    assert env.max_von_mises > 1.1 * seed  # the seed's shortcut underestimates the bending


def test_rail_inertia_unit_fields_balance_the_rigid_accelerations(crank):
    _, geo, mesh, _, fields, meta = crank
    p, t = mesh.points, mesh.tets
    a, b, c, d = (p[t[:, i]] for i in range(4))
    vol = np.abs(np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))) / 6.0
    centre = (a + b + c + d) / 4.0
    V = vol.sum()
    x0 = 0.5 * (geo.get("hole_x")[0] + geo.get("hole_x")[1])  # the pivot: midway between the first two holes
    rx, ry = (vol * (centre[:, 0] - x0)).sum(), (vol * centre[:, 1]).sum()
    R = meta.resultants  # (3, cases): N per unit coefficient
    names = list(fields.names)
    np.testing.assert_allclose(R[:, names.index("bolt_x")], [1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(R[:, names.index("bolt_y")], [0, 1, 0], atol=1e-12)
    np.testing.assert_allclose(R[:, names.index("body_x")], [V, 0, 0], rtol=1e-9, atol=1e-9 * V)
    np.testing.assert_allclose(R[:, names.index("body_y")], [0, V, 0], rtol=1e-9, atol=1e-9 * V)
    np.testing.assert_allclose(R[:, names.index("body_rot")], [-ry, rx, 0], rtol=1e-9, atol=1e-9 * abs(rx))
    np.testing.assert_allclose(R[:, names.index("body_rad")], [rx, ry, 0], rtol=1e-9, atol=1e-9 * abs(rx))


def test_rail_inertia_only_when_listed():
    geo = geometry_of("crank-rail", {})
    plain = crank_scene()
    listed = crank_scene('effects = ["inertia", "rail-inertia"]\n')
    holes = bolt_holes(parts_input(plain), "crank-rail", geo)
    assert list(unit_cases(load_model(parts_input(plain), "crank-rail", STEEL.density), geo, holes)) == ["bolt_x", "bolt_y"]
    assert list(unit_cases(load_model(parts_input(listed), "crank-rail", STEEL.density), geo, holes))[-2:] == [
        "body_rot",
        "body_rad",
    ]
    (h,) = source_histories(
        load_model(parts_input(listed), "crank-rail", STEEL.density), run_kinematics(kinematics_input(listed)), holes
    )
    omega = 2 * np.pi
    np.testing.assert_allclose(h.C[:, 5], STEEL.density * omega**2, rtol=1e-9)  # the crank turns steadily


@pytest.fixture(scope="module")
def cantilever():
    L, w, hgt = 0.7, 0.023, 0.020
    mesh = mesh_part(bar(L, w, hgt), 8e-3, hole_size=8e-3)
    fields, _ = solve_unit_cases(
        mesh, STEEL, ["clamp"], {"tip_z": TractionCase(("tip",), 2)}, order=2, tip_group="tip", solver="direct"
    )
    return (L, w, hgt), fields


@pytest.mark.parametrize("cycle", ["fully reversed", "zero to max"])
def test_fatigue_of_a_cantilever_matches_goodman_by_hand(cantilever, cycle):

    (L, w, hgt), fields = cantilever
    F = 150.0
    t = np.linspace(0, 2 * np.pi, 400)
    C = (F * np.sin(t) if cycle == "fully reversed" else 0.5 * F * (1 - np.cos(t)))[:, None]
    hi, lo = component_range(fields.stress, C)
    sa, sm = alternating_and_mean(hi, lo)
    marin = endurance_limit(STEEL.ultimate_strength, "machined", (w, hgt))
    n = safety_factor(sa, sm, marin.endurance_limit, STEEL.ultimate_strength)
    # beam theory at mid-span on the top face: sigma = F (L - x) (h / 2) / I
    x = 0.35
    node = int(np.argmin(np.linalg.norm(fields.nodes - [x, 0.0, hgt / 2], axis=1)))
    sigma = F * (L - fields.nodes[node, 0]) * (hgt / 2) / (w * hgt**3 / 12)
    sa_hand, sm_hand = (sigma, 0.0) if cycle == "fully reversed" else (sigma / 2, sigma / 2)
    n_hand = 1.0 / (sa_hand / marin.endurance_limit + sm_hand / STEEL.ultimate_strength)
    assert sa[node] == pytest.approx(sa_hand, rel=0.02)
    assert sm[node] == pytest.approx(sm_hand, abs=0.02 * sigma)
    assert n[node] == pytest.approx(n_hand, rel=0.02)


def test_marin_factors_match_shigley():
    m = endurance_limit(750e6, "machined", (0.023, 0.022), "bending", 0.99)
    assert m.ka == pytest.approx(4.51 * 750**-0.265, rel=1e-12)
    d = 0.808 * math.sqrt(23 * 22)
    assert m.kb == pytest.approx(1.24 * d**-0.107, rel=1e-12)
    assert m.ke == 0.814
    assert m.endurance_limit == pytest.approx(m.ka * m.kb * 0.814 * 375e6, rel=1e-12)
    # Gerber and ASME-elliptic sit above Goodman for a positive mean (Shigley fig. 6-27)
    sa, sm = np.array([100e6]), np.array([200e6])
    good = safety_factor(sa, sm, 250e6, 750e6, "goodman")
    assert safety_factor(sa, sm, 250e6, 750e6, "gerber") > good
    assert safety_factor(sa, sm, 250e6, 750e6, "asme-elliptic", 490e6) > good


def test_polygon_support_function_equals_every_step():

    rng = np.random.default_rng(3)
    t = np.linspace(0, 2 * np.pi, 2000)
    C = np.column_stack([300 * np.cos(t) + 80 * np.cos(3 * t), 250 * np.sin(t + 0.4) - 60 * np.sin(2 * t)])
    S = rng.normal(size=(6, 5000, 2))
    hi, lo = component_range(S, C)
    s = np.einsum("cnk,tk->cnt", S, C)
    np.testing.assert_allclose(hi, s.max(axis=2), rtol=1e-12)
    np.testing.assert_allclose(lo, s.min(axis=2), rtol=1e-12)
