"""Free bodies by inertia relief (railcheck.fea.relief): no support, the loads' imbalance
removed as a rigid-body acceleration, a statically determinate 3-2-1 hold whose reactions
vanish. Checked against statics and beam theory on a 1000 mm grooved size-25 rail."""

from dataclasses import replace

import numpy as np
import pytest

from helpers import FINAL_DESIGN
from railcheck.fea.assembly import assemble
from railcheck.fea.loading import resultant, surface_dofs, unit_traction_vectors
from railcheck.fea.materials import MATERIALS
from railcheck.fea.mesh import stress_nodes
from railcheck.fea.relief import solve_free_body
from railcheck.fea.stress import recover_stress
from railcheck.fea.unitcases import BodyCase, case_vector
from railcheck.geometry import mesh_part
from railcheck.geometry.catalogue import RAIL
from railcheck.geometry.models import rail as rail_part

STEEL = MATERIALS["steel"]


@pytest.fixture(scope="module")
def rail():
    """A 600 mm grooved size-25 rail with a pin hole at each end only (560 mm apart), on
    the check's default P2 mesh, assembled once: prismatic away from its two holes, as
    beam theory assumes. (On the rig's rails a counterbored hole every 60 mm disturbs the
    section's stress by several percent everywhere between them: no section is far from
    a hole there.)"""
    geo = rail_part(0.6, replace(RAIL, hole_pitch=0.56))
    mesh = mesh_part(geo, 20e-3, 6e-3)
    K, basis = assemble(mesh.points, mesh.tets, STEEL, 2, mesh.curved)
    xs = list(geo.get("hole_x"))
    return geo, mesh, K, basis, xs


def section_fit(S: np.ndarray, nodes: np.ndarray, x0: float, half: float = 6e-3) -> np.ndarray:
    """Least-squares fit of sigma_xx = a + b y + c z + d (x - x0) y + e (x - x0) over the
    stress nodes within ``half`` of x = x0: (a, b, c) Pa, Pa/m, Pa/m at the section."""
    near = np.abs(nodes[:, 0] - x0) < half
    x, y, z = nodes[near].T
    zc = 0.5 * (z.min() + z.max())
    A = np.column_stack([np.ones_like(x), y, z - zc, (x - x0) * y, x - x0])
    coef, *_ = np.linalg.lstsq(A, S[0, near], rcond=None)
    return coef[:3]


def _pin_pair_load(rail, force=1000.0):
    """(N,) N: ``force`` along x pulling the far pin's hole, pushing the near one's."""
    geo, mesh, K, basis, xs = rail
    return (
        unit_traction_vectors(basis, mesh.groups, f"hole_{len(xs) - 1}")[:, 0]
        - unit_traction_vectors(basis, mesh.groups, "hole_0")[:, 0]
    ) * force


def _rigid_acceleration_load(rail):
    """(N,) N: the d'Alembert force of a_O = (3, -7) m/s^2 and alpha = 40 rad/s^2 about the
    near hole, no pin force."""
    geo, mesh, K, basis, xs = rail
    fields = [
        case_vector(basis, mesh.groups, c)
        for c in (BodyCase("uniform", 0), BodyCase("uniform", 1), BodyCase("rotational", pivot=(xs[0], 0.0)))
    ]
    return -STEEL.density * (fields[0] * 3.0 + fields[1] * -7.0 + fields[2] * 40.0)


def _transverse_inertia_load(rail):
    """((N,) N, total N): 200 N/m of transverse (y) inertia on the steel, held by the end
    pins, w L / 2 each."""
    geo, mesh, K, basis, xs = rail
    body = -200.0 / geo.section.area * case_vector(basis, mesh.groups, BodyCase("uniform", 1))  # N/m^3
    total = resultant(basis, body)[1]  # N: less than 200 N/m x L, the holes hold no steel
    ends = sum(unit_traction_vectors(basis, mesh.groups, h)[:, 1] for h in ("hole_0", f"hole_{len(xs) - 1}"))
    return body - 0.5 * total * ends, total


@pytest.fixture(scope="module")
def free_rail(rail):
    """The three loads below solved as one free body, one factorisation: the solve, and
    its column of each (FreeBodySolve with (N, 3) displacements, (6, 3) imbalances)."""
    geo, mesh, K, basis, xs = rail
    F = np.column_stack([_pin_pair_load(rail), _rigid_acceleration_load(rail), _transverse_inertia_load(rail)[0]])
    return F, solve_free_body(K, F, basis, STEEL.density, "direct")


def test_two_equal_and_opposite_pin_forces_give_axial_stress_f_over_a(rail, free_rail):
    """F/A to 1% and no in-plane bending. The pins bear on the hole's plain bore, below the
    counterbore, so their line of action sits under the section's centroid: statics gives
    the out-of-plane bending F e / Z_y, which the FE must match too (2%)."""
    geo, mesh, K, basis, xs = rail
    force = 1000.0
    _, free = free_rail
    span = xs[-1] - xs[0]
    np.testing.assert_allclose(free.imbalance[:3, 0], 0.0, atol=1e-9 * force)
    # the uniform tractions' lines of action miss the hole axes by the facets' asymmetry (microns)
    np.testing.assert_allclose(free.imbalance[3:, 0], 0.0, atol=1e-4 * force * span)
    np.testing.assert_allclose(free.reactions[:, 0], 0.0, atol=1e-9 * force)
    S = recover_stress(basis, free.U[:, 0], STEEL)
    section = geo.section  # the grooved profile's, closed form
    axial = force / section.area
    a, b, c = section_fit(S, stress_nodes(basis), 0.5 * (xs[0] + xs[1]))
    assert a == pytest.approx(axial, rel=0.01)
    assert abs(b) * geo.get("width") / 2 < 0.01 * axial
    bore = surface_dofs(basis, mesh.groups, "hole_0")
    eccentricity = bore.weights @ bore.points[:, 2] / bore.weights.sum() - section.centroid_z
    # the bore's mid-depth: (height - counterbore depth) / 2 above the base
    assert eccentricity == pytest.approx(
        (geo.get("height") - geo.get("counterbore_depth")) / 2 - section.centroid_z, rel=0.02
    )
    assert abs(c) * (geo.get("height") - section.centroid_z) == pytest.approx(
        force * abs(eccentricity) / section.modulus_out_of_plane, rel=0.02
    )


def test_a_rigid_body_acceleration_field_alone_gives_no_stress(rail, free_rail):
    """The d'Alembert force of a rigid acceleration (translation and angular acceleration,
    no pin force) is exactly what inertia relief removes: zero stress."""
    geo, mesh, K, basis, xs = rail
    F, free = free_rail
    scale = np.abs(F[:, 1]).sum()
    assert np.abs(free.imbalance[:2, 1]).max() > 0.1 * scale / len(F)  # a real load, wholly unbalanced
    S = recover_stress(basis, free.U[:, 1], STEEL)
    assert np.abs(S).max() < 1e-9 * STEEL.density * 40.0 * 1.0 * 1.0  # rho alpha L^2: the load's stress scale
    assert np.abs(free.U[:, 1]).max() < 1e-15


def test_a_pinned_bar_under_uniform_transverse_inertia_bends_as_beam_theory(rail, free_rail):
    """Pins at the end holes carry w L / 2 each; the rail's own uniform transverse inertia
    (w N/m) bends it: M(x) from statics (overhangs included), sigma = M / Z at a section
    between holes near mid-span, within 2%."""
    geo, mesh, K, basis, xs = rail
    width, length, section = geo.get("width"), geo.get("length"), geo.section
    _, total = _transverse_inertia_load(rail)
    w = total / length  # N/m, the holes' missing steel spread evenly
    _, free = free_rail
    assert np.abs(free.imbalance[:3, 2]).max() < 1e-9 * abs(total)
    np.testing.assert_allclose(free.reactions[:, 2], 0.0, atol=1e-9 * abs(total))
    S = recover_stress(basis, free.U[:, 2], STEEL)
    x0 = 0.5 * (xs[0] + xs[1])
    reaction = -0.5 * total
    moment = reaction * (x0 - xs[0]) + w * x0**2 / 2  # about z, sagging positive for w < 0
    Z = section.modulus_in_plane  # the grooved profile's, closed form
    a, b, c = section_fit(S, stress_nodes(basis), x0)
    bending = abs(b) * width / 2
    assert bending == pytest.approx(abs(moment) / Z, rel=0.02)
    assert abs(a) < 0.01 * bending


# --- the rig's rails as free bodies (railcheck check, [check] support = "free-body") ---

FREE_BODY_SCENE = (
    FINAL_DESIGN
    + """steps = 360
[check]
parts = ["crank-rail", "coupler-rail", "rocker-rail"]
support = "free-body"
compare = ["2013"]
"""
)


@pytest.fixture(scope="module")
def free_run():
    import tomllib

    from railcheck.check.pipeline import run_pipeline
    from railcheck.scene import parse_scene

    scene = parse_scene(tomllib.loads(FREE_BODY_SCENE), "free-body")
    clamped = parse_scene(tomllib.loads(FREE_BODY_SCENE.replace('"free-body"', '"clamped"')), "clamped")
    return run_pipeline(scene, jobs=1), run_pipeline(clamped, jobs=1)


@pytest.mark.slow  # pin pressures doubled its cost (cold: the fixture's two checks 9 s): out of the fast tier
def test_free_rails_have_no_support_zone_and_their_loads_balance(free_run):
    """Pin and bolt forces (reactions plus the point masses' d'Alembert forces) and the
    rail's own inertia balance before relief: the force and the in-plane moment to 1e-9 of
    the largest joint force (the same mass model in the dynamics and the FE: the rail's
    mass, centre of mass and moment of inertia through the graded density; each pin's
    pressure radial through its hole's axis); out of the plane, where the pins bear 4.5 mm
    below the centroid the inertia acts at, to 2e-3 (the planar dynamics has no
    out-of-plane equations)."""
    from railcheck.check.summary import imbalance_summary

    free, _ = free_run
    for name, part in free.parts.items():
        assert part.job.free_body is not None and part.job.exclusion == 0.0
        assert np.all(part.cycle.fields.verdict_mask)
        assert part.cycle.envelope.support_peak == part.cycle.envelope.max_von_mises
        imbalance = imbalance_summary(part)
        # in the plane, to rounding: one mass model (graded density) and pins bearing through their axes;
        # a grooved rail's nodes lie on the mesher's 0.24 um grid (two cold runs agree to the byte), so its
        # bores' pressures act up to that far off their axes: moments to 1e-6 of force x length
        in_plane = 1e-6 if part.job.geometry.kind == "rail" else 1e-9
        assert imbalance["force_fraction"] < 1e-9 and imbalance["moment_in_plane_fraction"] < in_plane, (name, imbalance)
        assert imbalance["moment_out_of_plane_fraction"] < 2e-3, (name, imbalance)


@pytest.mark.slow  # pin pressures doubled its cost (cold: the shared fixture): out of the fast tier
def test_the_2013_clamped_model_beside_the_verdict_equals_a_clamped_check(free_run):
    """Each free rail also reports the 2013 model (clamped at its first hole, quasi-static
    as the 2013 study read it): its figures equal an independent `support = "clamped"`
    check of the same scene at a tenth of the speed (where the clamped rails' certificate
    holds, so that check is quasi-static too), scaled by the speed squared, and they stay
    out of the verdict (a limit between the two peaks passes the free body). At the
    scene's 1 Hz the clamped check itself computes the dynamic response (its cantilevers'
    certificate fails) and its quasi-static peak is the comparison's."""
    import tomllib

    from railcheck.check.pipeline import run_pipeline
    from railcheck.check.summary import summary_of
    from railcheck.scene import parse_scene

    free, clamped = free_run
    text = FREE_BODY_SCENE.replace('"free-body"', '"clamped"').replace("steps = 360", 'speed = "0.1 Hz"\nsteps = 360')
    slow = run_pipeline(parse_scene(tomllib.loads(text), "clamped, 0.1 Hz"), jobs=1)
    for name, part in free.parts.items():
        k, ref = part.clamped, slow.parts[name]
        assert ref.clamped is None and ref.job.free_body is None and ref.job.certificate.holds
        assert k.max_von_mises == pytest.approx(100 * ref.verdict_stress, rel=1e-9), name
        assert k.support_peak == pytest.approx(100 * ref.cycle.envelope.support_peak, rel=1e-9), name
        assert k.fatigue_factor == pytest.approx(ref.cycle.fatigue.min_safety_factor / 100, rel=1e-9), name
        assert k.max_tip == pytest.approx(100 * ref.cycle.envelope.max_tip, rel=1e-9), name
        at_1_hz = clamped.parts[name].cycle.dynamic
        assert at_1_hz is not None and k.max_von_mises == pytest.approx(at_1_hz.quasi_static_peak, rel=1e-9), name
        entry = summary_of(free)["parts"][name]["clamped_2013"]
        assert entry["max_von_mises_Pa"] == k.max_von_mises and "not part of the verdict" in entry["note"]
    crank = free.parts["crank-rail"]
    between = 0.5 * (crank.verdict_stress + crank.clamped.max_von_mises)
    text = FREE_BODY_SCENE.replace('parts = ["crank-rail", "coupler-rail", "rocker-rail"]', 'parts = ["crank-rail"]')
    text += f'limit = "{between / 1e6:.3f} MPa"\n'
    part = run_pipeline(parse_scene(tomllib.loads(text), "between"), jobs=1).parts["crank-rail"]
    assert part.clamped.max_von_mises > part.limit > part.verdict_stress and part.stress_passed


@pytest.mark.slow  # pin pressures doubled its cost (cold: the shared fixture): out of the fast tier
def test_free_links_bend_a_tenth_of_what_the_clamp_says(free_run):
    """The joints' and the inertia's loads (the table-top rig's out-of-plane weight, which
    the 2013 clamp does not carry, left out: its columns zeroed) bend the free links less
    than 15% of what the clamp says, and the free crank less than the clamped one."""
    from railcheck.fea.invariants import von_mises

    free, clamped = free_run

    def without_weight(part) -> float:
        cyc = part.cycle
        C = cyc.C.copy()
        C[:, [i for i, n in enumerate(cyc.fields.names) if n.endswith("_z")]] = 0.0
        return max(float(von_mises(cyc.fields.stress @ C[a : a + 30].T).max()) for a in range(0, C.shape[0], 30))

    for name in ("coupler-rail", "rocker-rail"):
        assert without_weight(free.parts[name]) < 0.15 * clamped.parts[name].verdict_stress
        assert without_weight(free.parts[name]) < free.parts[name].verdict_stress  # the weight adds to them
    assert without_weight(free.parts["crank-rail"]) < clamped.parts["crank-rail"].verdict_stress


@pytest.mark.slow  # pin pressures doubled its cost (cold: the shared fixture): out of the fast tier
def test_a_free_coupler_bends_as_the_statics_of_its_loads_say(free_run):
    """At the governing instant, the in-plane bending moment at a section between holes,
    from the statics of the loads left of it (the pin force at the first hole, the rail's
    distributed inertia whose coefficients the load model gives, and the inertia relief's
    rigid acceleration that removes the small imbalance), equals the FE's bending stress
    times I/c within 3%."""
    free, _ = free_run
    part = free.parts["coupler-rail"]
    cyc, geo = part.cycle, part.geometry
    names = list(cyc.fields.names)
    c = cyc.C[cyc.envelope.step]
    xs = geo.get("hole_x")
    x_pivot, x0, length = 0.5 * (xs[0] + xs[1]), 0.5 * (xs[6] + xs[7]), geo.get("length")  # the pivot: between its screws
    mu = part.job.free_body.mass / length  # kg/m
    pin, uniform, rot = c[names.index("pin_y")], c[names.index("body_y")], c[names.index("body_rot")]
    # left segment [0, x0]: the pin force halved on the two screws (its resultant at x_pivot),
    # load mu (uniform + rot (x - x_pivot)) per metre
    moment = pin * (x0 - x_pivot) + mu * (uniform * x0**2 / 2 + rot * (x0**3 / 6 - x_pivot * x0**2 / 2))
    # relief: the imbalance (force y, moment z about the centre) as a rigid acceleration of the rail
    imbalance = cyc.solve.imbalance @ c
    mass, x_c = part.job.free_body.mass, length / 2
    inertia = mass * (length**2 + geo.get("width") ** 2) / 12
    a_y, alpha = imbalance[1] / mass, imbalance[5] / inertia
    moment -= mu * (a_y * x0**2 / 2 + alpha * (x0**3 / 6 - x_c * x0**2 / 2))
    S = np.einsum("snk,k->sn", cyc.fields.stress, c)
    a, b, _ = section_fit(S, cyc.fields.nodes, x0)
    I = geo.section.inertia_in_plane
    assert abs(b) * I == pytest.approx(abs(moment), rel=0.03)


@pytest.mark.slow  # 6 s; the fast tier keeps superposition against a direct solve in test_cycle.py
def test_free_body_superposition_equals_a_direct_solve(rail):
    """Inertia relief is linear: the relieved unit cases combined equal the combined load
    relieved and solved directly, to 1e-9."""
    from railcheck.fea.unitcases import CoupleCase, TractionCase

    geo, mesh, K, basis, xs = rail
    cases = [
        TractionCase(("hole_0",), 1),
        CoupleCase(("hole_0", "hole_1"), xs[1] - xs[0]),
        TractionCase(("hole_0", "hole_1"), 1, (0.25, 0.75)),
        BodyCase("uniform", 1),
        BodyCase("rotational", pivot=(xs[0], 0.0)),
        BodyCase("radial", pivot=(xs[0], 0.0)),
    ]
    F = np.column_stack([case_vector(basis, mesh.groups, k) for k in cases])
    c = np.array([120.0, 35.0, -80.0, -2.0e4, 3.0e3, 1.5e3])
    units = solve_free_body(K, F, basis, STEEL.density, "direct")
    direct = solve_free_body(K, F @ c, basis, STEEL.density, "direct")
    S_units = np.einsum("snk,k->sn", recover_stress(basis, units.U, STEEL), c)
    S_direct = recover_stress(basis, direct.U, STEEL)
    assert np.abs(S_units - S_direct).max() <= 1e-9 * np.abs(S_direct).max()


def test_an_unknown_support_is_refused():
    import tomllib

    from railcheck.base.errors import InputError
    from railcheck.scene import parse_scene

    with pytest.raises(InputError, match="check.support"):
        parse_scene(tomllib.loads(FREE_BODY_SCENE.replace('"free-body"', '"hinged"')), "bad")


SLIDER_CRANK_SCENE = """
[mechanism]
kind = "slider-crank"
crank = "300 mm"
coupler = "840 mm"
speed = "1 Hz"
steps = 180
[check]
parts = ["crank-rail", "coupler-rail"]
support = "free-body"
effects = ["inertia", "gravity"]
[mesh]
size = "20 mm"
hole_size = "6 mm"
"""


@pytest.mark.slow  # two rails meshed and solved twice (free, clamped) when the caches are cold: 5 s
def test_slider_crank_rails_as_free_bodies_balance_with_their_own_carried_masses():
    """The slider-crank's coupler carries a coupling at B (the four-bar's a plate and a
    carriage): the FE's joint loads read the same mass model as the dynamics, so the loads
    balance before relief as the four-bar's do (with the four-bar's masses at B the force
    would be off by about a quarter of the largest joint force)."""
    import tomllib

    from railcheck.check.pipeline import run_pipeline
    from railcheck.check.summary import imbalance_summary
    from railcheck.scene import parse_scene

    result = run_pipeline(parse_scene(tomllib.loads(SLIDER_CRANK_SCENE), "slider-crank"), jobs=1)
    assert set(result.parts) == {"crank-rail", "coupler-rail"}
    for name, part in result.parts.items():
        assert part.job.free_body is not None and part.job.exclusion == 0.0
        imbalance = imbalance_summary(part)
        in_plane = 1e-6 if part.job.geometry.kind == "rail" else 1e-9  # the node grid (above)
        assert imbalance["force_fraction"] < 1e-9 and imbalance["moment_in_plane_fraction"] < in_plane, (name, imbalance)
        assert part.passed and np.isfinite(part.verdict_stress), name


PLATE_SCENE = (
    FINAL_DESIGN
    + """speed = "1 Hz"
steps = 360
[check]
parts = ["PF_4b_006"]
effects = ["inertia", "gravity"]
[mesh]
size = "12 mm"
hole_size = "4 mm"
"""
)


def test_a_free_joint_plate_balances_its_pin_force_bolts_and_own_inertia():
    """PF_4b_006 as a free body at A (crank axes) and B (coupler axes): the pin force on
    its bearing seat, the bolts carrying the balance (force through the seat plus a couple
    for the moment of the plate's own inertia about it), the plate's d'Alembert field and
    weight. The assembled loads' resultants (independent of the coefficient algebra)
    balance before relief in the plane to 1e-9 of the largest joint force (its density
    graded to the outline's mass, centroid and polar moment; without the bolts' couple the
    moment is off by 1.4e-3), out of it to 2e-4; the seat is in the verdict and, with
    ``compare = ["2013"]``, the clamped model is reported beside it."""
    import tomllib

    from railcheck.check.pipeline import run_pipeline
    from railcheck.check.summary import imbalance_summary, summary_of
    from railcheck.scene import parse_scene

    compared = PLATE_SCENE.replace("[mesh]", 'compare = ["2013"]\n[mesh]')
    result = run_pipeline(parse_scene(tomllib.loads(compared), "plate"), jobs=1)
    part = result.parts["PF_4b_006"]
    assert part.job.free_body is not None and part.job.exclusion == 0.0 and part.job.supports == []
    assert {h.joint for h in part.job.histories} == {"A", "B"}
    imbalance = imbalance_summary(part)
    assert imbalance["force_fraction"] < 1e-9 and imbalance["moment_in_plane_fraction"] < 1e-9, imbalance
    assert imbalance["moment_out_of_plane_fraction"] < 2e-4, imbalance
    assert part.clamped is not None and part.clamped.max_von_mises > 0
    entry = summary_of(result)["parts"]["PF_4b_006"]["support"]
    assert "seat" in entry["deflection"]


def _free_rail_histories(name: str, effects: list, speed: str, plane: str = "vertical"):
    """case name -> (T,) the coefficient history of free rail ``name`` at the final design,
    the check's [check] ``effects`` at crank ``speed`` on a rig in ``plane``."""
    from helpers import make_scene
    from railcheck.model.inputs import parts_input
    from railcheck.model.jobs import bolt_holes
    from railcheck.model.kinematics_stage import kinematics_input, run_kinematics
    from railcheck.model.loading import free_body_cases, load_model, source_histories
    from railcheck.parts import geometry_of

    mechanism = {"speed": speed, "steps": 90, "plane": plane}
    scene = make_scene(FINAL_DESIGN, {"mechanism": mechanism, "check": {"parts": [name], "effects": effects}})
    geo = geometry_of(name, {})
    holes = bolt_holes(parts_input(scene), name, geo)
    model = load_model(parts_input(scene), name, STEEL.density)
    (h,) = source_histories(model, run_kinematics(kinematics_input(scene)), holes)
    names = list(free_body_cases(model, geo, holes))
    assert len(names) == h.C.shape[1]
    return dict(zip(names, h.C.T))


def _on(columns: dict, names) -> np.ndarray:
    """(T, len(names)) the columns ``names`` of a history, zero where it has none."""
    steps = len(next(iter(columns.values())))
    return np.column_stack([columns.get(n, np.zeros(steps)) for n in names])


@pytest.mark.parametrize("plane", ["vertical", "horizontal"])
@pytest.mark.parametrize("name", ["crank-rail", "coupler-rail", "rocker-rail"])
def test_a_free_rails_loads_hold_only_the_effects_the_scene_lists(name, plane):
    """The weight always acts (upright: "gravity" is added; on a table top out of plane);
    without "inertia" no load of a free rail depends on the crank speed, the point masses
    its joints carry included (their d'Alembert force, -m a, is inertia): the history at
    3 Hz is the one at 1 Hz. With "inertia" every inertia load scales with the speed squared
    (a steady crank), the weight does not: C(2 Hz) - C(1 Hz) = 3 (C(1 Hz) - C(weight alone))."""
    weight = _free_rail_histories(name, [], "1 Hz", plane)
    np.testing.assert_array_equal(_on(_free_rail_histories(name, [], "3 Hz", plane), weight), _on(weight, weight))
    slow, fast = (_free_rail_histories(name, ["inertia"], speed, plane) for speed in ("1 Hz", "2 Hz"))
    assert set(weight) <= set(slow)  # the inertia's cases: the weight's and the rigid rotation's
    slow, fast, weight = (_on(c, slow) for c in (slow, fast, weight))
    assert np.abs(slow - weight).max() > 10.0  # N: real inertia loads
    np.testing.assert_allclose(fast - slow, 3.0 * (slow - weight), rtol=1e-9, atol=1e-9 * np.abs(fast).max())
