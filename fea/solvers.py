"""Linear solvers for the (reduced, symmetric positive definite) stiffness system.

One factorisation serves every right-hand side: :func:`factorise` returns a
:class:`Factor` whose ``solve`` takes a vector or a matrix of loads (one column per
load case). Backends:

* ``pardiso``: Intel MKL PARDISO in SPD mode (LL^T of the upper triangle) with METIS
  nested dissection, through ``pypardiso`` (pip wheels ``pypardiso`` + ``mkl``, x86-64).
  Its symbolic phase reports the factor's memory before the numeric factorisation, so
  the ``auto`` choice can fall back to the iterative path for what would not fit.
* ``scipy``: SuperLU with the symmetric minimum-degree ordering, where MKL is missing
  (other platforms); slower on large 3D systems, the same answer.
* ``pmg``: conjugate gradients preconditioned by a two-level p-multigrid for P2
  elasticity: Chebyshev smoothing on P2, and on the same mesh's P1 level (the Galerkin
  product P^T K P with P the P1 -> P2 interpolation) an exact solve by the factorising
  backend (or AMG when even that factor would not fit). The iterative path for P2 systems
  whose factor does not fit.
* ``amg``: conjugate gradients preconditioned by pyamg smoothed aggregation given the
  six rigid-body modes; memory linear in the size (P1, or when no P1 level is given).

``method="direct"`` is the best factorising backend installed; ``"auto"`` is ``pmg`` for
a P2 system of at least :data:`PMG_MIN_DOFS` DOFs with one or two load columns (faster
there), otherwise direct unless the factor's estimate exceeds
:data:`FACTOR_MEMORY_FRACTION` of the machine's memory (or the caller's ``memory_limit``),
then ``pmg`` (P2, a prolongation given) or ``amg``.

Every solve performs one step of iterative refinement (direct) and checks the true
relative residual ``|b - K u| / |b|`` of each column; above the tolerance, or a
non-finite result, raises :class:`NumericalError`. An iterative solve that stops at its
iteration cap never returns a displacement.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from railcheck.base.machine import available_memory

from .errors import NumericalError
from .mkl import MKL_REPRODUCIBLE, pardiso_available
from .products import RowBlocks, sparse_product
from .progress import heartbeat

DIRECT_RTOL = 1e-6  # |f - K u| / |f| after one refinement step; rounding alone gives ~eps |K||u| / |f|
AMG_RTOL = 1e-12  # CG's recurrence residual target
AMG_TRUE_RTOL = 1e-6  # the iterative path's true residual must be below this
FACTOR_MEMORY_FRACTION = 0.6  # of the machine's memory, for the auto choice
#: from this many DOFs, one or two load columns of a P2 system: p-multigrid CG is faster
#: than a factorisation and needs a third of its memory; below it, or with more columns,
#: the factor wins (measured: docs/changelog.md, "The measurements behind tuned constants")
PMG_MIN_DOFS = 300_000
PMG_MAX_COLUMNS = 2
SCIPY_BYTES_PER_DOF = 20_000  # SuperLU's measured peak per DOF on P2 parts (docs/performance.md)


def rigid_body_modes(locations: np.ndarray, components: np.ndarray) -> np.ndarray:
    """The six rigid-body modes (ndofs, 6) of a 3D vector field: three translations and
    three rotations about the centroid. ``locations`` (3, ndofs) is each DOF's position
    (m), ``components`` (ndofs,) its direction 0, 1 or 2."""
    x = locations - locations.mean(axis=1, keepdims=True)
    n = locations.shape[1]
    B = np.zeros((n, 6))
    B[np.arange(n), components] = 1.0
    # rotation about axis a moves direction c by +-x_d: (a, c, d, sign)
    for col, c, d, sign in ((3, 1, 2, -1), (3, 2, 1, 1), (4, 0, 2, 1), (4, 2, 0, -1), (5, 0, 1, -1), (5, 1, 0, 1)):
        mask = components == c
        B[mask, col] = sign * x[d, mask]
    return B


def relative_residuals(K: sp.spmatrix, U: np.ndarray, F: np.ndarray) -> np.ndarray:
    """|f - K u| / |f| per column (|K u| where f = 0)."""
    U2, F2 = U.reshape(U.shape[0], -1), F.reshape(F.shape[0], -1)
    r = np.linalg.norm(F2 - K @ U2, axis=0)
    nf = np.linalg.norm(F2, axis=0)
    return np.where(nf > 0, r / np.where(nf > 0, nf, 1.0), r)


@dataclass
class Factor:
    """A factorised SPD matrix ``K`` (n x n). ``solve(F)`` for (n,) or (n, k) loads.
    ``info``: backend, factor memory (bytes, where known), seconds per phase."""

    K: sp.csr_matrix
    backend: str
    _solve: Callable[[np.ndarray], np.ndarray]
    _free: Callable[[], None] | None = None
    info: dict = field(default_factory=dict)
    _K_extended: RowBlocks | None = None

    @property
    def n(self) -> int:
        return self.K.shape[0]

    def solve(self, F: np.ndarray, rtol: float = DIRECT_RTOL, extended: bool = True, refine: bool = True) -> np.ndarray:
        """``K^-1 F`` with one refinement step (``refine``); checks each column's true
        residual. The refinement's residual is accumulated in long double (``extended``),
        which a stiff, ill-conditioned system needs; a well-conditioned one (a mass matrix)
        needs neither: its factor alone reaches a residual near 1e-16."""
        F = np.asarray(F, float)
        if F.shape[0] != self.n:
            raise ValueError(f"load has {F.shape[0]} rows for a {self.n}-row system")
        if not np.all(np.isfinite(F)):
            raise NumericalError("the load vector is not finite")
        U = self._solve(F)
        if refine:
            U = U + self._solve(self._residual(F, U) if extended else F - self.K @ U)
        res = relative_residuals(self.K, U, F)
        if not np.all(np.isfinite(U)) or np.any(res > rtol):
            raise NumericalError(
                f"{self.backend} solve residual {np.max(res):.2e} above {rtol:.0e} "
                "(singular or ill-conditioned system: is the part held against every rigid motion?)"
            )
        self.info["residual"] = float(np.max(res, initial=0.0))
        return U

    def solve_once(self, F: np.ndarray) -> np.ndarray:
        """``K^-1 F`` by the factor alone (no refinement, no check): a fixed linear map, as
        a preconditioner needs."""
        return self._solve(np.asarray(F, float))

    def _residual(self, F: np.ndarray, U: np.ndarray) -> np.ndarray:
        """F - K U accumulated in extended precision (long double), so that the refinement
        step lowers the forward error below the conditioning's cond(K) x eps floor. The
        product runs on row blocks in threads, one per core (scipy releases the GIL)."""
        if self._K_extended is None:
            self._K_extended = RowBlocks(self.K, np.longdouble)
        U2 = U.reshape(self.n, -1).astype(np.longdouble)
        F2 = F.reshape(self.n, -1)
        r = np.empty(F2.shape)

        def rows(first, stop, block):
            r[first:stop] = F2[first:stop].astype(np.longdouble) - block @ U2

        self._K_extended.each(rows)
        return r.reshape(F.shape)

    def free(self) -> None:
        """Release the factor's memory (the pardiso backend holds it outside Python)."""
        if self._free is not None:
            self._free()
            self._free = None

    def __del__(self):
        try:
            self.free()
        except Exception:  # noqa: BLE001 - interpreter shutdown
            pass


def _pardiso_factor(K: sp.csr_matrix, memory_limit: float | None, report) -> Factor:
    import time

    os.environ.setdefault("MKL_CBWR", MKL_REPRODUCIBLE)
    from pypardiso.pardiso_wrapper import PyPardisoError, PyPardisoSolver

    upper = sp.triu(K, format="csr")
    upper.sort_indices()
    solver = PyPardisoSolver(mtype=2)  # real symmetric positive definite
    solver.set_iparm(1, 1)  # use the iparm values given here
    solver.set_iparm(2, 3)  # METIS nested dissection, parallel (OpenMP)
    solver.set_iparm(8, 0)  # refinement is done by Factor.solve
    solver.set_iparm(10, 8)  # pivot perturbation 1e-8
    solver.set_iparm(35, 0)  # one-based indices (pypardiso adds 1)
    empty = np.zeros((K.shape[0], 1), order="F")
    info: dict = {}

    def call(phase: int, b: np.ndarray) -> np.ndarray:
        solver.set_phase(phase)
        try:
            return solver._call_pardiso(upper, b)
        except PyPardisoError as exc:
            raise NumericalError(
                f"PARDISO failed in phase {phase}: {exc} (a zero pivot means the stiffness is "
                "singular: is the part held against every rigid motion?)"
            ) from None

    t = time.perf_counter()
    call(11, empty)  # symbolic: ordering and the factor's size
    info["analysis_s"] = time.perf_counter() - t
    # iparm(15..17): peak memory (KB) of the analysis, permanent memory, numeric phase
    need = 1024.0 * max(solver.get_iparm(15), solver.get_iparm(16) + solver.get_iparm(17))
    info["factor_bytes"] = need
    info["factor_nnz"] = int(solver.get_iparm(18))
    if memory_limit is not None and need > memory_limit:
        solver.free_memory(everything=True)
        raise MemoryError(need)
    t = time.perf_counter()
    with heartbeat(f"factorising {K.shape[0]} DOFs (PARDISO, {need / 2**30:.1f} GiB)", report):
        call(22, empty)
    info["factorise_s"] = time.perf_counter() - t

    def solve(F: np.ndarray) -> np.ndarray:
        b = np.asfortranarray(F.reshape(F.shape[0], -1))
        return call(33, b).reshape(F.shape)

    return Factor(K, "pardiso", solve, lambda: solver.free_memory(everything=True), info)


def _scipy_factor(K: sp.csr_matrix, memory_limit: float | None, report) -> Factor:
    import time

    need = SCIPY_BYTES_PER_DOF * K.shape[0]
    if memory_limit is not None and need > memory_limit:
        raise MemoryError(need)
    t = time.perf_counter()
    try:
        with heartbeat(f"factorising {K.shape[0]} DOFs (SuperLU)", report):
            lu = spla.splu(
                sp.csc_matrix(K), permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True, "DiagPivotThresh": 0.0}
            )
    except RuntimeError as exc:  # exactly singular
        raise NumericalError(f"direct solve failed: {exc} (is the part held against every rigid motion?)") from None
    info = {"factor_bytes": float(need), "factorise_s": time.perf_counter() - t}
    return Factor(K, "scipy", lambda F: lu.solve(F), None, info)


def factorise(K: sp.spmatrix, backend: str = "direct", memory_limit: float | None = None, report=None) -> Factor:
    """Factorise the SPD matrix ``K`` once. ``backend``: ``direct`` (pardiso when
    installed, else scipy), ``pardiso`` or ``scipy``. Raises MemoryError(bytes needed)
    when the factor's estimate exceeds ``memory_limit`` (bytes)."""
    K = sp.csr_matrix(K, dtype=float)
    if K.shape[0] == 0:
        return Factor(K, "empty", lambda F: np.zeros_like(F))
    if backend == "direct":
        backend = "pardiso" if pardiso_available() else "scipy"
    if backend == "pardiso":
        return _pardiso_factor(K, memory_limit, report)
    if backend == "scipy":
        return _scipy_factor(K, memory_limit, report)
    raise ValueError(f"unknown direct backend {backend!r}")


def solve_jacobi_cg(M: sp.spmatrix, B: np.ndarray, rtol: float = 1e-12, maxiter: int = 400) -> np.ndarray:
    """``M^-1 B`` for a symmetric positive definite ``M`` that is well conditioned once
    scaled by its diagonal (a mass matrix): conjugate gradients with the diagonal as
    preconditioner, every column of ``B`` (n[, k]) at once, each column's scalars its own.
    Stops when every column's true relative residual |b - M x| / |b| is below ``rtol``;
    raises :class:`NumericalError` when that is not reached in ``maxiter`` iterations (a
    degenerate mesh), so the caller can factorise instead."""
    M = sp.csr_matrix(M)
    B2 = np.asarray(B, float).reshape(M.shape[0], -1)
    diagonal = M.diagonal()
    M_rows = sparse_product(M)
    if not (np.all(np.isfinite(B2)) and np.all(diagonal > 0)):
        raise NumericalError("the projection system is not positive definite or its load is not finite")
    inverse_diagonal = (1.0 / diagonal)[:, None]
    limit = (rtol * np.linalg.norm(B2, axis=0)) ** 2  # on squared residual norms
    X = B2 * inverse_diagonal
    R = B2 - M_rows @ X
    Z = R * inverse_diagonal
    P = Z.copy()
    rz = np.einsum("ij,ij->j", R, Z)
    for _ in range(maxiter):
        if np.all(np.einsum("ij,ij->j", R, R) <= limit):
            R = B2 - M_rows @ X  # the true residual, not the recurrence's
            if np.all(np.einsum("ij,ij->j", R, R) <= limit):
                return X.reshape(B.shape)
        MP = M_rows @ P
        pMp = np.einsum("ij,ij->j", P, MP)
        alpha = np.divide(rz, pMp, out=np.zeros_like(rz), where=pMp > 0)
        np.multiply(P, alpha, out=Z)  # Z as scratch until it is recomputed
        X += Z
        MP *= alpha
        R -= MP
        np.multiply(R, inverse_diagonal, out=Z)
        rz_next = np.einsum("ij,ij->j", R, Z)
        beta = np.divide(rz_next, rz, out=np.zeros_like(rz), where=rz > 0)
        P *= beta
        P += Z
        rz = rz_next
    raise NumericalError(f"Jacobi-CG did not reach a relative residual of {rtol:.0e} in {maxiter} iterations")


def solve_amg(
    K: sp.spmatrix, F: np.ndarray, B: np.ndarray, rtol: float = AMG_RTOL, maxiter: int = 2000, report=None
) -> tuple[np.ndarray, dict]:
    """CG (scipy) preconditioned by one V-cycle of pyamg smoothed aggregation built on
    3 x 3 node blocks with the rigid-body modes ``B``, column by column of ``F``.
    (pyamg's own ``solve(accel="cg")`` stalled on these P2 systems; scipy's CG with the
    same hierarchy converges.)"""
    import pyamg

    F = np.asarray(F, float)
    K = sp.csr_matrix(K)
    A = sp.bsr_matrix(K, blocksize=(3, 3)) if K.shape[0] % 3 == 0 else K
    # pyamg estimates spectral radii from np.random start vectors: seed them (and restore the
    # caller's random state) so that the same problem gives bit-identical results
    state = np.random.get_state()
    np.random.seed(20131)
    try:
        ml = pyamg.smoothed_aggregation_solver(A, B=B, symmetry="hermitian", strength="symmetric", max_coarse=500)
    finally:
        np.random.set_state(state)
    U, info = _cg_columns(K, F, ml.aspreconditioner(cycle="V"), "AMG", rtol, maxiter, report)
    return U, {"solver": "amg", **info, "levels": len(ml.levels)}


def _cg_columns(K, F: np.ndarray, precond, label: str, rtol: float, maxiter: int, report) -> tuple[np.ndarray, dict]:
    """Preconditioned CG (:func:`_cg_true_residual`) for each column of ``F``, with the
    elapsed-time heartbeat; (U, {iterations, residual})."""
    columns = np.asarray(F, float).reshape(F.shape[0], -1)
    U = np.zeros_like(columns)
    iterations = 0
    for j in range(columns.shape[1]):
        with heartbeat(f"{label}-CG on {K.shape[0]} DOFs, load {j + 1} of {columns.shape[1]}", report):
            U[:, j], its = _cg_true_residual(K, columns[:, j], precond, rtol, maxiter)
        iterations += its
    res = relative_residuals(K, U, columns)
    return U.reshape(F.shape), {"iterations": iterations, "residual": float(res.max(initial=0.0))}


def _cg_true_residual(K, b: np.ndarray, precond, rtol: float, maxiter: int) -> tuple[np.ndarray, int]:
    """CG from zero, restarted on the true residual (its recurrence drifts on slender,
    coarse systems) up to three times; raises when the true residual is not met."""
    if np.linalg.norm(b) == 0.0:
        return np.zeros_like(b), 0
    count = [0]

    def tick(_):
        count[0] += 1

    u = np.zeros_like(b)
    status, previous = 0, np.inf
    for _ in range(4):
        res = float(np.linalg.norm(b - K @ u) / np.linalg.norm(b))
        # stop at the target, at the cap, or at the rounding floor (no halving per pass)
        if res <= AMG_TRUE_RTOL * 1e-2 or count[0] >= maxiter or res > 0.5 * previous:
            break
        previous = res
        du, status = spla.cg(
            K,
            b - K @ u,
            rtol=max(rtol, AMG_TRUE_RTOL * 1e-3 / res),
            atol=0.0,
            maxiter=maxiter - count[0],
            M=precond,
            callback=tick,
        )
        u = u + du
        if status != 0:
            break
    res = float(np.linalg.norm(b - K @ u) / np.linalg.norm(b))
    if status != 0 or not np.all(np.isfinite(u)) or res > AMG_TRUE_RTOL:
        raise NumericalError(
            f"AMG-CG did not converge: relative residual {res:.2e} after {count[0]} "
            f"iterations (tolerance {AMG_TRUE_RTOL:.0e}, cap {maxiter})"
        )
    return u, count[0]


#: a linear solver: ``solver(K, F, B=..., prolongation=..., maxiter=..., memory_limit=...,
#: report=...) -> (U, info)`` for an SPD ``K`` and one or several load columns ``F``
Solver = Callable[..., tuple[np.ndarray, dict]]


def solve_factorised(
    K,
    F,
    B=None,
    prolongation=None,
    maxiter: int = 2000,
    memory_limit: float | None = None,
    report=None,
    backend: str = "direct",
    capped: bool = False,
) -> tuple[np.ndarray, dict]:
    """One factorisation (``backend`` ``direct``, ``pardiso`` or ``scipy``) for every column.
    A backend chosen by name is not capped: ``memory_limit`` (bytes) applies only when
    ``capped`` (the auto choice), raising MemoryError(bytes needed) above it."""
    factor = factorise(K, backend, memory_limit if capped else None, report)
    U = factor.solve(F)
    info = {"solver": factor.backend, "iterations": 1, **factor.info}
    factor.free()
    return U, info


def solve_multigrid(
    K, F, B=None, prolongation=None, maxiter: int = 2000, memory_limit: float | None = None, report=None
) -> tuple[np.ndarray, dict]:
    """p-multigrid CG (:func:`solve_pmg`); ``prolongation`` a callable giving the P1 -> P2
    interpolation of the free DOFs (a P2 basis)."""
    if prolongation is None:
        raise ValueError("the pmg solver needs the P1 -> P2 prolongation (a P2 basis)")
    return solve_pmg(K, F, prolongation(), B, maxiter, memory_limit, report)


def solve_aggregation(
    K, F, B=None, prolongation=None, maxiter: int = 2000, memory_limit: float | None = None, report=None
) -> tuple[np.ndarray, dict]:
    """Smoothed-aggregation AMG-CG (:func:`solve_amg`); ``B`` the rigid-body modes."""
    if B is None:
        raise ValueError("the amg solver needs the rigid-body modes")
    return solve_amg(K, F, B, AMG_RTOL, maxiter, report)


def solve_auto(
    K, F, B=None, prolongation=None, maxiter: int = 2000, memory_limit: float | None = None, report=None
) -> tuple[np.ndarray, dict]:
    """pmg for a large P2 system with few columns; otherwise the direct factor, unless its
    memory estimate exceeds ``memory_limit`` (default a fraction of this machine's memory),
    then pmg (P2) or amg (module doc)."""
    columns = 1 if np.ndim(F) == 1 else np.shape(F)[1]
    iterative = solve_multigrid if prolongation is not None else solve_aggregation
    if prolongation is not None and K.shape[0] >= PMG_MIN_DOFS and columns <= PMG_MAX_COLUMNS:
        return iterative(K, F, B, prolongation, maxiter, memory_limit, report)
    limit = memory_limit if memory_limit is not None else FACTOR_MEMORY_FRACTION * available_memory()
    try:
        return solve_factorised(K, F, memory_limit=limit, report=report, capped=True)
    except MemoryError as exc:
        if report:
            report(f"{_memory_words(exc)}: iterative {'PMG' if prolongation is not None else 'AMG'}-CG instead")
    return iterative(K, F, B, prolongation, maxiter, memory_limit, report)


def _memory_words(exc: MemoryError) -> str:
    """Why a factorisation was given up: its estimate (bytes, from the memory cap) in GiB,
    or numpy's own allocation failure (an array's shape, not a size)."""
    need = exc.args[0] if exc.args else None
    if isinstance(need, (int, float)) and not isinstance(need, bool):
        return f"the factor would need {need / 2**30:.1f} GiB"
    return f"the factorisation ran out of memory ({exc})"


#: the solvers by name (``[solver]``, ``--solver``); a caller may pass any :data:`Solver` instead
SOLVERS: dict[str, Solver] = {
    "auto": solve_auto,
    "direct": functools.partial(solve_factorised, backend="direct"),
    "pardiso": functools.partial(solve_factorised, backend="pardiso"),
    "scipy": functools.partial(solve_factorised, backend="scipy"),
    "pmg": solve_multigrid,
    "amg": solve_aggregation,
}


def solver_of(method: str | Solver) -> Solver:
    """The solver named ``method`` (a key of :data:`SOLVERS`), or ``method`` itself when it
    is a callable."""
    if callable(method):
        return method
    try:
        return SOLVERS[method]
    except (KeyError, TypeError):
        raise ValueError(f"unknown solver {method!r}") from None


def solve_reduced(
    K: sp.spmatrix,
    F: np.ndarray,
    B: np.ndarray | None = None,
    method: str | Solver = "auto",
    maxiter: int = 2000,
    memory_limit: float | None = None,
    report=None,
    prolongation=None,
) -> tuple[np.ndarray, dict]:
    """Solve ``K U = F`` for an SPD ``K`` and one or several load columns with the solver
    ``method`` (a name of :data:`SOLVERS` or a :data:`Solver`); ``B`` the rigid-body modes
    (needed by amg); ``prolongation`` a callable giving the P1 -> P2 interpolation of the
    free DOFs (needed by pmg). ``memory_limit`` bytes for a factor. Returns (U, info)."""
    return solver_of(method)(K, F, B=B, prolongation=prolongation, maxiter=maxiter, memory_limit=memory_limit, report=report)


def solve_pmg(
    K: sp.spmatrix,
    F: np.ndarray,
    P: sp.spmatrix,
    B: np.ndarray | None = None,
    maxiter: int = 2000,
    memory_limit: float | None = None,
    report=None,
) -> tuple[np.ndarray, dict]:
    """CG preconditioned by the two-level p-multigrid V-cycle (module doc), column by
    column of ``F``; ``P`` (n, n1) the P1 -> P2 interpolation of the free DOFs."""
    K = sp.csr_matrix(K)
    P = sp.csr_matrix(P)
    coarse = (P.T @ K @ P).tocsr()
    with heartbeat(f"p-multigrid: P1 level of {coarse.shape[0]} DOFs", report):
        try:
            limit = memory_limit if memory_limit is not None else FACTOR_MEMORY_FRACTION * available_memory()
            factor = factorise(coarse, "direct", limit, report)
            coarse_solve, coarse_name = (lambda r: factor.solve_once(r)), factor.backend
        except MemoryError:
            if B is None:
                raise ValueError("the P1 level needs AMG, which needs the rigid-body modes") from None
            import pyamg

            ml = pyamg.smoothed_aggregation_solver(
                sp.bsr_matrix(coarse, blocksize=(3, 3)), B=P.T @ B, symmetry="hermitian", max_coarse=500
            )
            coarse_solve, coarse_name = ml.aspreconditioner(cycle="V").matvec, "amg"  # a fixed linear map
    product = sparse_product(K)
    operator = spla.LinearOperator(K.shape, matvec=product.__matmul__, matmat=product.__matmul__, dtype=float)
    cycle = _two_level(product, K.diagonal(), sparse_product(P), sparse_product(P.T), coarse_solve)
    U, info = _cg_columns(operator, F, cycle, "PMG", AMG_RTOL, maxiter, report)
    return U, {"solver": "pmg", **info, "coarse": coarse_name, "coarse_dofs": int(coarse.shape[0])}


CHEBYSHEV_DEGREE = 3  # smoothing steps before and after the P1 correction


def _two_level(K, diagonal: np.ndarray, P, P_T, coarse_solve) -> spla.LinearOperator:
    """The symmetric two-level V-cycle as a preconditioner: Chebyshev smoothing (Jacobi-
    scaled, on the upper part [lmax / 30, 1.1 lmax] of the spectrum), the P1 correction,
    the same smoothing again. ``K``, ``P`` (P1 -> P2) and ``P_T`` are products
    (:func:`~.products.sparse_product`), ``diagonal`` K's."""
    d_inv = 1.0 / diagonal
    rng = np.random.default_rng(20131)
    x = rng.standard_normal(K.shape[0])
    for _ in range(15):  # power iteration for lmax(D^-1 K)
        x = d_inv * (K @ x)
        x /= np.linalg.norm(x)
    lmax = 1.1 * float(x @ (d_inv * (K @ x)))
    lo, hi = lmax / 30.0, lmax
    theta, delta = 0.5 * (hi + lo), 0.5 * (hi - lo)

    def smooth(x, r):
        """CHEBYSHEV_DEGREE steps of Chebyshev iteration on K x = r from x (None: from
        zero); CHEBYSHEV_DEGREE products with K (none for the last step's residual, which
        no step uses, nor for a zero start's)."""
        res = r if x is None else r - K @ x
        sigma = theta / delta
        rho = 1.0 / sigma
        dx = d_inv * res / theta
        for step in range(CHEBYSHEV_DEGREE):
            x = dx if x is None else x + dx
            if step == CHEBYSHEV_DEGREE - 1:
                break
            res = r - K @ x
            rho_new = 1.0 / (2.0 * sigma - rho)
            dx = rho_new * rho * dx + 2.0 * rho_new / delta * (d_inv * res)
            rho = rho_new
        return x

    def apply(r):
        x = smooth(None, r)
        x = x + P @ coarse_solve(P_T @ (r - K @ x))
        return smooth(x, r)

    return spla.LinearOperator(K.shape, matvec=apply, dtype=float)
