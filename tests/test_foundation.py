"""A part bolted down by a face, as a free body (railcheck.fea.relief.foundation_reaction):
its loads balanced there by a rigid foundation's linear traction, no clamp. Checked
against statics, beam theory away from the base, and the 2013 clamp on PF_4b_003_v2."""

import numpy as np
import pytest

from railcheck.fea.assembly import assemble
from railcheck.fea.loading import unit_traction_vectors
from railcheck.fea.materials import MATERIALS
from railcheck.fea.mesh import scalar_basis, stress_nodes, vector_dof_map
from railcheck.fea.relief import foundation_reaction, imbalance, rigid_modes, solve_free_body
from railcheck.fea.stress import recover_stress, relative_to_face
from railcheck.geometry import mesh_part, rail
from railcheck.parts import geometry_of

STEEL = MATERIALS["steel"]


@pytest.fixture(scope="module")
def bar():
    """A 260 mm rail without holes, P2, assembled once."""
    geo = rail(0.26, holes=False)
    mesh = mesh_part(geo, 6e-3, 6e-3)
    K, basis = assemble(mesh.points, mesh.tets, STEEL, 2, mesh.curved)
    return geo, mesh, K, basis


def test_the_foundation_balances_any_load_to_rounding(bar):
    geo, mesh, K, basis = bar
    rng = np.random.default_rng(3)
    F = rng.normal(size=(basis.N, 4)) * 100.0
    R = foundation_reaction(basis, mesh.groups, "end_pivot", F)
    left = imbalance(rigid_modes(basis, 1.0), F + R)
    assert np.abs(left).max() < 1e-10 * np.abs(imbalance(rigid_modes(basis, 1.0), F)).max()
    # the reaction lives on the face alone
    on_face = np.zeros(basis.N, dtype=bool)
    vmap = vector_dof_map(basis, scalar_basis(basis))
    from railcheck.fea.loading import surface_node_weights

    nodes, _ = surface_node_weights(basis, mesh.groups, "end_pivot")
    on_face[vmap[nodes].ravel()] = True
    assert np.abs(R[~on_face]).max() < 1e-12 * np.abs(R).max()


def test_a_bar_on_a_foundation_bends_as_a_cantilever_away_from_its_base(bar):
    """A transverse force on the far end, balanced by the foundation on the near end face:
    at mid-span sigma = M y / I (beam theory) within 2% (Saint-Venant: the foundation's
    linear traction and a clamp differ only near the base)."""
    geo, mesh, K, basis = bar
    force, L = 500.0, geo.get("length")
    F = unit_traction_vectors(basis, mesh.groups, "end_free")[:, 1] * force
    F = F + foundation_reaction(basis, mesh.groups, "end_pivot", F)
    free = solve_free_body(K, F, basis, STEEL.density, "direct")
    assert np.abs(free.imbalance).max() < 1e-9 * force
    S = recover_stress(basis, free.U, STEEL)
    nodes = stress_nodes(basis)
    x0 = L / 2
    near = np.abs(nodes[:, 0] - x0) < 4e-3
    design = np.column_stack(
        [np.ones(near.sum()), nodes[near, 1], nodes[near, 0] - x0, (nodes[near, 0] - x0) * nodes[near, 1]]
    )
    a, b, *_ = np.linalg.lstsq(design, S[0, near], rcond=None)[0]
    I = geo.section.inertia_in_plane  # the grooved profile's, closed form
    assert abs(b) == pytest.approx(force * (L - x0) / I, rel=0.02)


def test_a_deflection_relative_to_a_face_ignores_rigid_motion():
    geo = geometry_of("PF_4b_003_v2", {})
    mesh = mesh_part(geo, 12e-3, 6e-3)
    K, basis = assemble(mesh.points, mesh.tets, STEEL, 2, mesh.curved)
    op = relative_to_face(basis, mesh.groups, "base", ["end_free"])
    sb = scalar_basis(basis)
    vmap, x = vector_dof_map(basis, sb), sb.doflocs.T
    for t, theta in (
        ((1.0, 2.0, 3.0), (0.0, 0.0, 0.0)),
        ((0.0, 0.0, 0.0), (0.1, -0.2, 0.3)),
        ((1.0, -1.0, 2.0), (0.2, 0.1, -0.3)),
    ):
        u = np.array(t) + np.cross(np.array(theta), x)
        U = np.zeros(basis.N)
        for c in range(3):
            U[vmap[:, c]] = u[:, c]
        assert np.abs(op @ U).max() < 1e-14
    bend = np.zeros(basis.N)  # a shear u_y = z^2 (a cantilever-like bow): the top moves relative to the base
    bend[vmap[:, 1]] = x[:, 2] ** 2
    assert (op @ bend)[1] == pytest.approx(geo.get("depth") ** 2, rel=1e-9)


@pytest.mark.slow  # the bracket's 176k DOFs, free and clamped: 30 s
def test_the_ground_bracket_is_a_free_body_on_its_foundation_with_every_node_in_the_verdict():
    """PF_4b_003_v2 under the seed's explicit loads: no clamp, no excluded zone (the
    verdict's peak is the envelope's largest value), its loads balanced to rounding by the
    foundation, and away from the 2013 clamp's singular edge the two models agree: peak and
    top deflection within 10% (a rigid foundation's linear reaction is a clamp's statics)."""
    import tomllib

    from helpers import PLATE_LOADS
    from railcheck.check.pipeline import run_pipeline
    from railcheck.check.summary import imbalance_summary
    from railcheck.scene import parse_scene

    compared = PLATE_LOADS.replace("[loads.", 'compare = ["2013"]\n[loads.')
    result = run_pipeline(parse_scene(tomllib.loads(compared), "bracket"), jobs=1)
    part = result.parts["PF_4b_003_v2"]
    assert part.job.loads.is_on_foundation and part.job.exclusion == 0.0
    assert np.all(part.cycle.fields.verdict_mask)
    env = part.cycle.envelope
    assert env.support_peak == env.max_von_mises
    imbalance = imbalance_summary(part)
    assert imbalance["force_fraction"] < 1e-9 and imbalance["moment_in_plane_fraction"] < 1e-9
    assert imbalance["moment_out_of_plane_fraction"] < 1e-9
    clamped = part.clamped
    assert env.max_von_mises == pytest.approx(clamped.max_von_mises, rel=0.10)
    assert env.max_tip == pytest.approx(clamped.max_tip, rel=0.10)
