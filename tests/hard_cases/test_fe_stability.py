"""FE hard cases: slender coarse meshes, units scaling, locking, slivers, degenerate loads."""

from dataclasses import replace

import numpy as np
import pytest

from railcheck.fea.elasticity import HoleLoad, Support, solve_elasticity
from railcheck.fea.errors import ModelError
from railcheck.fea.materials import MATERIALS, Material
from railcheck.geometry.catalogue import RAIL
from railcheck.geometry.meshdata import MeshData
from railcheck.geometry.mesher import mesh_part
from railcheck.geometry.models import bar, joint_plate, rail

STEEL = MATERIALS["steel"]


@pytest.mark.slow
def test_coarse_2500_mm_rail_amg_converges_to_direct():
    """The plain (ungrooved) profile: the subject is slenderness. On the grooved profile at
    this coarse 25 mm mesh CG with smoothed aggregation does not reach 1e-12 in 2000
    iterations (the grooves' 2.5 mm lands); the direct solver is the default and AMG only
    the fallback when a factor would not fit in memory (a known limitation, docs/model.md)."""
    mesh = mesh_part(rail(2.5, replace(RAIL, groove_radius=0.0)), 25e-3, hole_size=6e-3)
    assert 2.5 / 0.022 > 100  # the part's aspect ratio
    args = (
        mesh,
        STEEL,
        [Support("shaft_hole")],
        [HoleLoad("hole_40", (300.0, 150.0, 0.0)), HoleLoad("hole_41", (300.0, 150.0, 0.0))],
    )
    d = solve_elasticity(*args, order=2, tip_group="end_free", solver="direct")
    a = solve_elasticity(*args, order=2, tip_group="end_free", solver="amg")
    assert a.solver["solver"] == "amg"
    assert np.abs(a.displacement - d.displacement).max() < 1e-6 * np.abs(d.displacement).max()
    assert a.max_von_mises == pytest.approx(d.max_von_mises, rel=1e-6)


@pytest.mark.parametrize("order", [1, 2])
def test_same_problem_in_mm_and_m_gives_the_same_stresses(order):
    mesh = mesh_part(bar(0.2, 0.02, 0.02), 8e-3, hole_size=8e-3)
    si = solve_elasticity(
        mesh,
        STEEL,
        [Support("clamp")],
        [HoleLoad("tip", (10.0, 50.0, -30.0))],
        order=order,
        tip_group="tip",
        solver="direct",
    )
    # mm, N, MPa (N/mm^2): coordinates x 1000, E in N/mm^2
    mm = Material(
        "steel-mm",
        STEEL.youngs_modulus / 1e6,
        STEEL.poisson_ratio,
        STEEL.ultimate_strength / 1e6,
        STEEL.density,
        "same steel in N/mm^2",
    )
    smm = solve_elasticity(
        MeshData.of(mesh.points * 1e3, mesh.tets, mesh.groups),
        mm,
        [Support("clamp")],
        [HoleLoad("tip", (10.0, 50.0, -30.0))],
        order=order,
        tip_group="tip",
        solver="direct",
    )
    np.testing.assert_allclose(smm.von_mises, si.von_mises / 1e6, rtol=1e-9, atol=1e-9 * si.von_mises.max() / 1e6)
    np.testing.assert_allclose(
        smm.displacement, si.displacement * 1e3, rtol=1e-9, atol=1e-9 * np.abs(si.displacement).max() * 1e3
    )


def test_nearly_incompressible_p1_locks_and_warns():
    mesh = mesh_part(bar(0.3, 0.03, 0.03), 10e-3, hole_size=10e-3)
    rubbery = replace(STEEL, name="nu049", poisson_ratio=0.49)
    args = (mesh, rubbery, [Support("clamp")], [HoleLoad("tip", (0.0, 0.0, -100.0))])
    p1 = solve_elasticity(*args, order=1, tip_group="tip")
    p2 = solve_elasticity(*args, order=2, tip_group="tip")
    assert any("lock" in w for w in p1.warnings)
    assert not p2.warnings
    assert abs(p1.tip_displacement[2]) < 0.7 * abs(p2.tip_displacement[2])


def test_slivers_from_a_bad_size_field_are_detected():
    bad = mesh_part(joint_plate(), 30e-3, hole_size=3e-3, optimize=False, cache=False)
    good = mesh_part(joint_plate(), 30e-3, hole_size=3e-3, optimize=True, cache=False)
    assert bad.slivers > 0 and bad.min_quality < 0.05
    assert good.slivers == 0 and good.min_quality > 0.1


@pytest.fixture(scope="module")
def plate():
    return mesh_part(joint_plate(), 12e-3, hole_size=4e-3)


def test_zero_load_gives_exactly_zero(plate):
    s = solve_elasticity(
        plate,
        STEEL,
        [Support("bearing_seat")],
        [HoleLoad("hole_0", (0.0, 0.0, 0.0)), HoleLoad("hole_1", (0.0, 0.0, 0.0))],
        order=2,
        tip_group="end_free",
    )
    assert np.all(s.displacement == 0.0) and np.all(s.von_mises == 0.0) and s.tip_deflection == 0.0


def test_load_on_a_hole_not_in_the_mesh_is_an_error(plate):
    with pytest.raises(ModelError, match="hole_7: no such group"):
        solve_elasticity(plate, STEEL, [Support("bearing_seat")], [HoleLoad("hole_7", (10.0, 0.0, 0.0))])


def test_unsupported_part_is_detected_before_the_solve(plate):
    with pytest.raises(ModelError, match="no support"):
        solve_elasticity(plate, STEEL, [], [HoleLoad("hole_0", (10.0, 0.0, 0.0))])
