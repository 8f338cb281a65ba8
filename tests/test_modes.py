"""Natural frequencies (railcheck.fea.modes) against Euler-Bernoulli beam theory on a
700 x 23 x 20 mm steel bar: free-free and cantilevered, bending about the thin side."""

import numpy as np
import pytest

from railcheck.fea import MATERIALS, assemble, dof_components, supports
from railcheck.fea.modes import natural_modes, vector_mass_matrix
from railcheck.geometry import bar, mesh_part

STEEL = MATERIALS["steel"]
L, W, H = 0.7, 0.023, 0.020


@pytest.fixture(scope="module")
def beam():
    mesh = mesh_part(bar(L, W, H), 6e-3, 6e-3)
    K, basis = assemble(mesh.points, mesh.tets, STEEL, 2, mesh.curved)
    return mesh, K, basis, vector_mass_matrix(basis, STEEL.density)


def beam_hz(beta_l: float, thickness: float, width: float) -> float:
    """Euler-Bernoulli: f = (beta L)^2 / (2 pi L^2) sqrt(E I / (rho A)), I = b t^3 / 12."""
    I, A = width * thickness**3 / 12, width * thickness
    return beta_l**2 / (2 * np.pi * L**2) * np.sqrt(STEEL.youngs_modulus * I / (STEEL.density * A))


def test_the_mass_matrix_weighs_the_bar(beam):
    mesh, K, basis, M = beam
    for c in range(3):
        translation = (dof_components(basis) == c).astype(float)  # a unit translation along c
        assert translation @ M @ translation == pytest.approx(STEEL.density * L * W * H, rel=1e-9)


def test_a_free_bar_has_six_rigid_modes_then_beam_bending(beam):
    mesh, K, basis, M = beam
    modes = natural_modes(K, M, [], 8)
    assert np.all(modes.hz[:6] < 1e-3 * modes.hz[6])
    assert modes.hz[6] == pytest.approx(beam_hz(4.7300407, H, W), rel=0.01)  # first free-free bending, about the thin side
    assert modes.hz[7] == pytest.approx(beam_hz(4.7300407, W, H), rel=0.01)  # and about the wide side


def test_a_cantilever_bends_at_beam_theory_frequency(beam):
    mesh, K, basis, M = beam
    modes = natural_modes(K, M, supports(basis, mesh.groups, ["clamp"]), 2)
    assert modes.hz[0] == pytest.approx(beam_hz(1.8751041, H, W), rel=0.01)
    assert modes.hz[1] == pytest.approx(beam_hz(1.8751041, W, H), rel=0.01)
    phi = modes.shapes[:, 0]
    assert phi @ M @ phi == pytest.approx(1.0, rel=1e-8)
