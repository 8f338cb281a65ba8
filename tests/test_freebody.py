"""Free bodies by inertia relief (railcheck.fea.relief): no support, the loads' imbalance
removed as a rigid-body acceleration, a statically determinate 3-2-1 hold whose reactions
vanish. Checked against statics and beam theory on a 1000 mm size-25 rail."""

import numpy as np
import pytest

from railcheck.fea import (
    MATERIALS,
    assemble,
    recover_stress,
    resultant,
    solve_free_body,
    stress_nodes,
    surface_dofs,
    unit_traction_vectors,
)
from railcheck.fea.unitcases import BodyCase, case_vector
from railcheck.geometry import mesh_part
from railcheck.parts import geometry_of

STEEL = MATERIALS["steel"]


@pytest.fixture(scope="module")
def rail():
    """The coupler's 1000 mm rail on the check's default P2 mesh, assembled once."""
    geo = geometry_of("coupler-rail", {})
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


def test_two_equal_and_opposite_pin_forces_give_axial_stress_f_over_a(rail):
    """F/A to 1% and no in-plane bending. The pins bear on the hole's plain bore, below the
    counterbore, so their line of action sits under the section's centroid: statics gives
    the out-of-plane bending F e / Z_y, which the FE must match too (2%)."""
    geo, mesh, K, basis, xs = rail
    force = 1000.0
    F = (
        unit_traction_vectors(basis, mesh.groups, f"hole_{len(xs) - 1}")[:, 0]
        - unit_traction_vectors(basis, mesh.groups, "hole_0")[:, 0]
    ) * force
    free = solve_free_body(K, F, basis, STEEL.density, "direct")
    span = xs[-1] - xs[0]
    np.testing.assert_allclose(free.imbalance[:3], 0.0, atol=1e-9 * force)
    # the uniform tractions' lines of action miss the hole axes by the facets' asymmetry (microns)
    np.testing.assert_allclose(free.imbalance[3:], 0.0, atol=1e-4 * force * span)
    np.testing.assert_allclose(free.reactions, 0.0, atol=1e-9 * force)
    S = recover_stress(basis, free.U, STEEL)
    axial = force / (geo.get("width") * geo.get("height"))
    a, b, c = section_fit(S, stress_nodes(basis), 0.5 * (xs[7] + xs[8]))
    assert a == pytest.approx(axial, rel=0.01)
    assert abs(b) * geo.get("width") / 2 < 0.01 * axial
    bore = surface_dofs(basis, mesh.groups, "hole_0")
    eccentricity = bore.weights @ bore.points[:, 2] / bore.weights.sum() - geo.get("height") / 2
    assert eccentricity == pytest.approx(-(geo.get("counterbore_depth")) / 2, rel=0.02)  # the bore's mid-depth
    Zy = geo.get("width") * geo.get("height") ** 2 / 6
    assert abs(c) * geo.get("height") / 2 == pytest.approx(force * abs(eccentricity) / Zy, rel=0.02)


def test_a_rigid_body_acceleration_field_alone_gives_no_stress(rail):
    """The d'Alembert force of a rigid acceleration (translation and angular acceleration,
    no pin force) is exactly what inertia relief removes: zero stress."""
    geo, mesh, K, basis, xs = rail
    pivot = (xs[0], 0.0)
    fields = [
        case_vector(basis, mesh.groups, c)
        for c in (BodyCase("uniform", 0), BodyCase("uniform", 1), BodyCase("rotational", pivot=pivot))
    ]
    rho = STEEL.density
    F = -rho * (fields[0] * 3.0 + fields[1] * -7.0 + fields[2] * 40.0)  # a_O = (3, -7) m/s^2, alpha = 40 rad/s^2
    free = solve_free_body(K, F, basis, rho, "direct")
    scale = np.abs(F).sum()
    assert np.abs(free.imbalance[:2]).max() > 0.1 * scale / len(F)  # a real load, wholly unbalanced
    S = recover_stress(basis, free.U, STEEL)
    assert np.abs(S).max() < 1e-9 * rho * 40.0 * 1.0 * 1.0  # rho alpha L^2: the load's stress scale
    assert np.abs(free.U).max() < 1e-15


def test_a_pinned_bar_under_uniform_transverse_inertia_bends_as_beam_theory(rail):
    """Pins at the end holes carry w L / 2 each; the rail's own uniform transverse inertia
    (w N/m) bends it: M(x) from statics (overhangs included), sigma = M / Z at a section
    between holes near mid-span, within 2%."""
    geo, mesh, K, basis, xs = rail
    width, height, length = geo.get("width"), geo.get("height"), geo.get("length")
    area = width * height
    body = -200.0 / area * case_vector(basis, mesh.groups, BodyCase("uniform", 1))  # N/m^3, transverse (y)
    total = resultant(basis, body)[1]  # N: less than 200 N/m x L, the holes hold no steel
    w = total / length  # N/m, the holes' missing steel spread evenly
    F = body - 0.5 * total * sum(
        unit_traction_vectors(basis, mesh.groups, h)[:, 1] for h in ("hole_0", f"hole_{len(xs) - 1}")
    )
    free = solve_free_body(K, F, basis, STEEL.density, "direct")
    assert np.abs(free.imbalance[:3]).max() < 1e-9 * abs(total)
    np.testing.assert_allclose(free.reactions, 0.0, atol=1e-9 * abs(total))
    S = recover_stress(basis, free.U, STEEL)
    x0 = 0.5 * (xs[7] + xs[8])
    reaction = -0.5 * total
    moment = reaction * (x0 - xs[0]) + w * x0**2 / 2  # about z, sagging positive for w < 0
    Z = height * width**2 / 6
    a, b, c = section_fit(S, stress_nodes(basis), x0)
    bending = abs(b) * width / 2
    assert bending == pytest.approx(abs(moment) / Z, rel=0.02)
    assert abs(a) < 0.01 * bending
