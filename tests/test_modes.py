"""Natural frequencies (railcheck.fea.modes) against Euler-Bernoulli beam theory on a
700 x 23 x 20 mm steel bar: free-free and cantilevered, bending about the thin side."""

import numpy as np
import pytest

from railcheck.fea.assembly import assemble
from railcheck.fea.materials import MATERIALS
from railcheck.fea.mesh import dof_components
from railcheck.fea.modes import natural_modes, vector_mass_matrix
from railcheck.fea.system import supports
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


@pytest.mark.slow  # 3 s; the fast tier keeps the cantilever's first frequency against beam theory
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


@pytest.mark.slow
def test_pins_at_both_ends_give_the_simply_supported_beam(beam):
    """Both end faces held as pins (mean translation and roll; rotation in bending free):
    the first bending frequency is the simply supported beam's, beta L = pi."""
    from railcheck.fea.dynamic import part_modes

    mesh, K, basis, M = beam
    model = part_modes(K, basis, STEEL.density, np.zeros((basis.N, 1)), 2, pins=[["clamp"], ["tip"]], groups=mesh.groups)
    assert model.hz[0] == pytest.approx(beam_hz(np.pi, H, W), rel=0.02)
    assert model.hz[1] == pytest.approx(beam_hz(np.pi, W, H), rel=0.02)


@pytest.mark.slow
@pytest.mark.parametrize("ratio", [0.6, 0.047])
def test_mode_acceleration_equals_a_direct_harmonic_solve(beam, ratio):
    """A cantilever under a tip force F cos(Omega t): quasi-static superposition plus the
    mode-acceleration correction of its six lowest modes (no damping) against the direct
    solve of (K - Omega^2 M) u = F, at Omega = 0.6 and 0.047 of the first frequency (no
    harmonic of it on a natural frequency)."""
    import scipy.sparse.linalg as spla

    from railcheck.fea.dynamic import modal_correction, part_modes
    from railcheck.fea.loading import unit_traction_vectors
    from railcheck.fea.system import free_submatrix

    mesh, K, basis, M = beam
    fixed = supports(basis, mesh.groups, ["clamp"])
    F = unit_traction_vectors(basis, mesh.groups, "tip")[:, 2:3]  # 1 N across the 20 mm side
    model = part_modes(K, basis, STEEL.density, F, 6, fixed=fixed)
    omega = ratio * 2 * np.pi * model.hz[0]
    steps = 361
    C = np.cos(np.linspace(0, 2 * np.pi, steps))[:, None]  # one period of cos(Omega t)
    free = np.setdiff1d(np.arange(basis.N), fixed)
    Kf, Mf = free_submatrix(K, free), free_submatrix(M, free)
    static = np.zeros(basis.N)
    static[free] = spla.spsolve(Kf.tocsc(), F[free, 0])
    direct = np.zeros(basis.N)
    direct[free] = spla.spsolve((Kf - omega**2 * Mf).tocsc(), F[free, 0])
    dq = modal_correction(model.modal_loads, model.hz, C, omega, 0.0)
    u0 = static * C[0, 0] + model.shapes @ dq[0]  # at t = 0 the response peaks with the load
    tip = np.argmax(np.abs(direct))
    assert u0[tip] == pytest.approx(direct[tip], rel=2e-3)
    if ratio == 0.6:  # well above quasi-static: 1 / (1 - 0.36) on the first mode
        assert direct[tip] / static[tip] > 1.5
    np.testing.assert_allclose(dq[-1], dq[0], rtol=1e-12)  # the period's end is its start


@pytest.mark.slow
def test_a_mass_on_the_tip_lowers_the_cantilever_as_rayleigh_says(beam):
    """2 kg lumped on the free end face: f = sqrt(k / (m + 0.2357 m_beam)) / 2 pi with the
    tip stiffness k = 3 E I / L^3 (Rayleigh, within 2%); the mass matrix weighs 2 kg more."""
    from railcheck.fea.dynamic import lumped_masses, part_modes

    mesh, K, basis, M = beam
    extra = lumped_masses(basis, mesh.groups, [(("tip",), 2.0)])
    translation = (dof_components(basis) == 1).astype(float)
    assert translation @ extra @ translation == pytest.approx(2.0, rel=1e-12)
    fixed = supports(basis, mesh.groups, ["clamp"])
    model = part_modes(
        K, basis, STEEL.density, np.zeros((basis.N, 1)), 1, fixed=fixed, groups=mesh.groups, lumped=[(("tip",), 2.0)]
    )
    I = W * H**3 / 12
    k = 3 * STEEL.youngs_modulus * I / L**3
    m_beam = STEEL.density * L * W * H
    assert model.hz[0] == pytest.approx(np.sqrt(k / (2.0 + 0.2357 * m_beam)) / (2 * np.pi), rel=0.02)


@pytest.fixture(scope="module")
def coarse_cantilever():
    """The bar at 12 mm (7,764 DOFs), clamped, a 1 N tip force across its 20 mm side, its
    free system, the static solution and its six lowest modes."""
    import scipy.sparse.linalg as spla

    from railcheck.fea.dynamic import part_modes
    from railcheck.fea.loading import unit_traction_vectors
    from railcheck.fea.system import free_submatrix

    mesh = mesh_part(bar(L, W, H), 12e-3, 12e-3)
    K, basis = assemble(mesh.points, mesh.tets, STEEL, 2, mesh.curved)
    M = vector_mass_matrix(basis, STEEL.density)
    fixed = supports(basis, mesh.groups, ["clamp"])
    F = unit_traction_vectors(basis, mesh.groups, "tip")[:, 2:3]
    free = np.setdiff1d(np.arange(basis.N), fixed)
    Kf, Mf = free_submatrix(K, free).tocsc(), free_submatrix(M, free).tocsc()
    static = np.zeros(basis.N)
    static[free] = spla.spsolve(Kf, F[free, 0])
    model = part_modes(K, basis, STEEL.density, F, 6, fixed=fixed)

    def direct(omega):
        u = np.zeros(basis.N)
        u[free] = spla.spsolve((Kf - omega**2 * Mf).tocsc(), F[free, 0])
        return u

    return static, model, direct


@pytest.mark.slow
def test_mode_acceleration_equals_the_direct_solve_at_two_harmonics_to_1e6(coarse_cantilever):
    """A load with harmonics 1 and 3 of Omega = 0.2317 of the first frequency (3 Omega at
    0.70 of it; no harmonic on a natural frequency), undamped: the quasi-static solution
    plus the FFT mode-acceleration correction of six modes equals the superposed direct
    solves of (K - (n Omega)^2 M) U_n = F at every step, to 1e-6 of the largest
    displacement (the modes above the sixth enter only through their static part)."""
    from railcheck.fea.dynamic import modal_correction

    static, model, direct = coarse_cantilever
    omega = 0.2317 * 2 * np.pi * model.hz[0]
    t = np.linspace(0, 2 * np.pi, 721)
    C = (np.cos(t) + 0.5 * np.cos(3 * t))[:, None]
    dq = modal_correction(model.modal_loads, model.hz, C, omega, 0.0)
    ours = np.outer(C[:, 0], static) + dq @ model.shapes.T
    exact = np.outer(np.cos(t), direct(omega)) + 0.5 * np.outer(np.cos(3 * t), direct(3 * omega))
    assert np.abs(ours - exact).max() <= 1e-6 * np.abs(exact).max()


@pytest.mark.slow
@pytest.mark.parametrize(("ratio", "expected", "tolerance"), [(0.5, 1.0 / (1.0 - 0.25), 0.01), (0.05, 1.0, 0.005)])
def test_a_lightly_damped_mode_amplifies_as_one_over_one_minus_r_squared(coarse_cantilever, ratio, expected, tolerance):
    """A harmonic tip force at r = Omega / omega_1 with 0.1% damping: the tip's dynamic
    peak over its quasi-static peak is 1 / (1 - r^2) = 1.333 at r = 0.5 (the first mode
    carries the tip) within 1%, and at r = 0.05 the two agree to 0.5%."""
    from railcheck.fea.dynamic import modal_correction

    static, model, _ = coarse_cantilever
    tip = int(np.argmax(np.abs(static)))
    t = np.linspace(0, 2 * np.pi, 361)
    C = np.cos(t)[:, None]
    dq = modal_correction(model.modal_loads, model.hz, C, ratio * 2 * np.pi * model.hz[0], 0.001)
    dynamic = C[:, 0] * static[tip] + dq @ model.shapes[tip]
    assert np.abs(dynamic).max() / np.abs(static[tip]) == pytest.approx(expected, rel=tolerance)


def test_a_long_eigensolve_says_what_it_costs_and_a_failed_one_is_refused_naming_the_count():
    """A spring-mass chain (n = 400, stiffness tridiagonal, unit masses, one end held):
    asking for 12 modes prints an estimate after the first solve; the frequencies equal the
    chain's closed form 2 sqrt(k/m) sin((2j - 1) pi / (2 (2n + 1))) / (2 pi). A spectrum
    clustered within 1e-6 of itself does not converge in two restarts: refused under
    ``dynamic.modes``; a modal correction handed a 0 Hz mode refuses instead of dividing
    by it."""
    import scipy.sparse as sp

    from railcheck.fea import modes as modes_module
    from railcheck.fea.dynamic import modal_correction
    from railcheck.fea.errors import NumericalError

    n = 400
    K = sp.diags([-np.ones(n - 1), np.r_[2.0 * np.ones(n - 1), 1.0], -np.ones(n - 1)], [-1, 0, 1]).tocsr()
    lines: list[str] = []
    got = natural_modes(K, sp.identity(n, format="csr"), np.zeros(0, dtype=np.int64), 12, shift=0.0, progress=lines.append)
    j = np.arange(1, 13)
    want = 2 * np.sin((2 * j - 1) * np.pi / (2 * (2 * n + 1))) / (2 * np.pi)
    assert np.allclose(got.hz, want, rtol=1e-9)
    assert lines and "12 modes" in lines[0] and "at least" in lines[0]
    restarts = modes_module.MAX_RESTARTS
    try:
        modes_module.MAX_RESTARTS = 2
        clustered = sp.diags(1.0 + 1e-6 * np.arange(n)).tocsr()
        with pytest.raises(NumericalError, match=r"dynamic\.modes: the lowest 12 modes did not converge"):
            natural_modes(clustered, sp.identity(n, format="csr"), np.zeros(0, dtype=np.int64), 12, shift=0.0)
    finally:
        modes_module.MAX_RESTARTS = restarts
    with pytest.raises(NumericalError, match=r"dynamic\.modes"):
        modal_correction(np.ones((2, 1)), np.array([0.0, 30.0]), np.ones((9, 1)), 2 * np.pi, 0.02)
