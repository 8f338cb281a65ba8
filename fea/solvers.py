"""Linear solvers for the stiffness system, each checking its own residual.

* ``direct``: sparse LU (SuperLU through scipy) for small systems;
* ``amg``: conjugate gradients preconditioned by pyamg smoothed aggregation, given the
  six rigid-body modes as near-null-space candidates, for large ones;
* ``auto``: direct below :data:`DIRECT_LIMIT` unknowns, amg above.

Every solve computes ``|b - K u| / |b|`` and raises :class:`NumericalError` when it is
above the tolerance; an iterative solve that stops at its iteration cap never returns
a displacement.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .errors import NumericalError

DIRECT_LIMIT = 100_000   # above it AMG-CG: the study found LU slow on chunky parts (README)
DIRECT_RTOL = 1e-6   # |b - K u| / |b|; LU backward error scales with |K||u| >> |b| here
AMG_RTOL = 1e-12        # CG's recurrence residual target
AMG_TRUE_RTOL = 1e-6    # the true residual |b - K u| / |b| must be below this (as direct)


def rigid_body_modes(locations: np.ndarray, components: np.ndarray) -> np.ndarray:
    """The six rigid-body modes (ndofs, 6) of a 3D vector field: three translations and
    three rotations about the centroid. ``locations`` (3, ndofs) is each DOF's position
    (m), ``components`` (ndofs,) its direction 0, 1 or 2."""
    x = locations - locations.mean(axis=1, keepdims=True)
    n = locations.shape[1]
    B = np.zeros((n, 6))
    for c in range(3):
        B[components == c, c] = 1.0
    X, Y, Z = x
    # rotation about x: (0, -z, y); about y: (z, 0, -x); about z: (-y, x, 0)
    rot = {3: ((1, -Z), (2, Y)), 4: ((0, Z), (2, -X)), 5: ((0, -Y), (1, X))}
    for col, pairs in rot.items():
        for comp, values in pairs:
            mask = components == comp
            B[mask, col] = values[mask]
    return B


def relative_residual(K: sp.spmatrix, u: np.ndarray, b: np.ndarray) -> float:
    nb = np.linalg.norm(b)
    if nb == 0.0:
        return float(np.linalg.norm(K @ u))
    return float(np.linalg.norm(b - K @ u) / nb)


def solve_direct(K: sp.spmatrix, b: np.ndarray, rtol: float = DIRECT_RTOL) -> tuple[np.ndarray, dict]:
    try:
        Kc = sp.csc_matrix(K)
        lu = spla.splu(Kc, permc_spec="COLAMD")
        u = lu.solve(b)
        u += lu.solve(b - Kc @ u)      # one step of iterative refinement
    except RuntimeError as exc:   # exactly singular
        raise NumericalError(f"direct solve failed: {exc} (is the part held against every rigid motion?)") from None
    res = relative_residual(K, u, b)
    if not np.all(np.isfinite(u)) or res > rtol:
        raise NumericalError(f"direct solve residual {res:.2e} above {rtol:.0e} (singular or ill-conditioned system)")
    return u, {"solver": "direct", "iterations": 1, "residual": res}


def solve_amg(K: sp.spmatrix, b: np.ndarray, B: np.ndarray, rtol: float = AMG_RTOL,
              maxiter: int = 2000) -> tuple[np.ndarray, dict]:
    """CG (scipy) preconditioned by one V-cycle of pyamg smoothed aggregation built on
    3 x 3 node blocks with the rigid-body modes ``B``. (pyamg's own ``solve(accel="cg")``
    stalled on these P2 systems; scipy's CG with the same hierarchy converges.)"""
    import pyamg

    if np.linalg.norm(b) == 0.0:
        return np.zeros_like(b), {"solver": "amg", "iterations": 0, "residual": 0.0}
    K = sp.csr_matrix(K)
    A = sp.bsr_matrix(K, blocksize=(3, 3)) if K.shape[0] % 3 == 0 else K
    # pyamg estimates spectral radii from np.random start vectors: seed them (and restore the
    # caller's random state) so that the same problem gives bit-identical results
    state = np.random.get_state()
    np.random.seed(20131)
    try:
        ml = pyamg.smoothed_aggregation_solver(A, B=B, symmetry="hermitian", strength="symmetric",
                                               max_coarse=500)
    finally:
        np.random.set_state(state)
    count = [0]

    def tick(_):
        count[0] += 1

    precond = ml.aspreconditioner(cycle="V")
    u = np.zeros_like(b)
    status, res = 0, 1.0
    # CG's recurrence residual drifts from the true one on ill-conditioned (slender,
    # coarse) systems: restart on the true residual, up to three times
    previous = np.inf
    for _ in range(4):
        r = b - K @ u
        res = float(np.linalg.norm(r) / np.linalg.norm(b))
        # stop at the target, at the cap, or at the rounding floor (no halving per pass)
        if res <= AMG_TRUE_RTOL * 1e-2 or count[0] >= maxiter or res > 0.5 * previous:
            break
        previous = res
        du, status = spla.cg(K, r, rtol=max(rtol, AMG_TRUE_RTOL * 1e-3 / res), atol=0.0,
                             maxiter=maxiter - count[0], M=precond, callback=tick)
        u = u + du
        if status != 0:
            break
    res = relative_residual(K, u, b)
    if status != 0 or not np.all(np.isfinite(u)) or res > AMG_TRUE_RTOL:
        raise NumericalError(f"AMG-CG did not converge: relative residual {res:.2e} after {count[0]} "
                             f"iterations (tolerance {AMG_TRUE_RTOL:.0e}, cap {maxiter})")
    return u, {"solver": "amg", "iterations": count[0], "residual": res, "levels": len(ml.levels)}


def solve(K: sp.spmatrix, b: np.ndarray, B: np.ndarray | None = None, method: str = "auto",
          rtol: float | None = None, maxiter: int = 2000) -> tuple[np.ndarray, dict]:
    """Solve ``K u = b``; ``B`` the rigid-body modes of the free DOFs (needed by amg)."""
    if method == "auto":
        method = "direct" if K.shape[0] <= DIRECT_LIMIT else "amg"
    if method == "direct":
        return solve_direct(K, b, rtol or DIRECT_RTOL)
    if method == "amg":
        if B is None:
            raise ValueError("the amg solver needs the rigid-body modes")
        return solve_amg(K, b, B, rtol or AMG_RTOL, maxiter)
    raise ValueError(f"unknown solver {method!r}")
