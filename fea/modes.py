"""Natural frequencies and mode shapes of a part: the consistent mass matrix of the vector
basis and the lowest eigenpairs of ``K phi = omega^2 M phi`` by shift-invert Lanczos (scipy
``eigsh``) with the stiffness factorisation as the inverse operator.

A supported part takes ``fixed`` DOFs; a free body none (its six rigid-body modes come
first, at zero frequency, and the shift then sits below zero so ``K - sigma M`` stays
positive definite). Units SI: kg/m^3, N/m, Hz.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .assembly import mass_matrix
from .errors import NumericalError
from .mesh import scalar_basis, vector_dof_map
from .solvers import factorise
from .system import free_submatrix

__all__ = ["Modes", "natural_modes", "stiffness_factor", "vector_mass_matrix"]


@dataclass(frozen=True)
class Modes:
    """The lowest natural frequencies ``hz`` (count,) Hz, ascending, and the mode shapes
    ``shapes`` (N, count), mass-normalised (phi^T M phi = 1) on every DOF (zero on the
    fixed ones)."""

    hz: np.ndarray
    shapes: np.ndarray


def vector_mass_matrix(basis, density: float) -> sp.csr_matrix:
    """(N, N) kg: the consistent mass matrix of the vector basis, ``density`` times the
    scalar mass matrix on each displacement component."""
    Ms = sp.coo_matrix(mass_matrix(basis))
    dof = vector_dof_map(basis, scalar_basis(basis))
    rows = np.concatenate([dof[Ms.row, c] for c in range(3)])
    cols = np.concatenate([dof[Ms.col, c] for c in range(3)])
    return sp.csr_matrix((density * np.tile(Ms.data, 3), (rows, cols)), shape=(basis.N, basis.N))


#: s between two progress lines of a long eigensolve
HEARTBEAT_S = 5.0
#: ARPACK's restarts before an eigensolve is given up (the default six modes of a rail take
#: a few; a count whose lowest modes do not converge in these is refused, naming the count)
MAX_RESTARTS = 20


def _counted_inverse(solve, count: int, n: int, progress):
    """``solve`` (one right-hand side) as ARPACK's inverse operator, reporting through
    ``progress`` (a callable taking one line, or None): after the first solve an estimate
    of the whole (Lanczos vectors x 3 solves, each as long as the first), then every
    :data:`HEARTBEAT_S` s the solves done and the time taken."""
    start = time.perf_counter()
    state = {"solves": 0, "last": start}
    vectors = min(n, max(2 * count + 1, 20))  # eigsh's default ncv

    def matvec(x):
        y = solve(x)
        state["solves"] += 1
        now = time.perf_counter()
        if progress is not None and state["solves"] == 1 and count > 6:
            each = now - start
            least = 3 * vectors
            progress(f"{count} modes: {each:.2f} s a solve, at least {least} solves (about {least * each:.0f} s)")
        elif progress is not None and now - state["last"] >= HEARTBEAT_S:
            state["last"] = now
            progress(f"{count} modes: {state['solves']} solves, {now - start:.0f} s")
        return y

    return matvec


def natural_modes(K, M, fixed: np.ndarray, count: int, shift: float | None = None, factor=None, progress=None) -> Modes:
    """The ``count`` lowest modes of ``K phi = omega^2 M phi`` with the ``fixed`` DOFs held.
    ``shift`` (rad^2/s^2) the spectral shift: default 0 for a supported part and, for a
    free one (no fixed DOF), minus the squared angular frequency of 1 Hz. ``factor``: a
    factorisation of ``K - shift M`` on the free DOFs already made (:func:`shift_factor`;
    with shift 0 it does not depend on M, so several mass distributions share it).
    ``progress``: a callable taking one line, told the estimate and the progress of a long
    eigensolve (:func:`_counted_inverse`)."""
    N = K.shape[0]
    free = np.setdiff1d(np.arange(N), np.asarray(fixed, dtype=np.int64))
    Kf, Mf = free_submatrix(K, free), free_submatrix(M, free)
    sigma = shift if shift is not None else (0.0 if free.size < N else -((2 * np.pi) ** 2))
    factor = factor or factorise((Kf - sigma * Mf).tocsr(), "direct")
    matvec = _counted_inverse(factor.solve_once, count, Kf.shape[0], progress)
    inverse = spla.LinearOperator(Kf.shape, matvec=matvec, dtype=float)
    # a fixed start vector (ARPACK's default is random: the last bits of the frequencies
    # would change from run to run); random-like so that no mode is orthogonal to it
    v0 = np.random.default_rng(0).standard_normal(Kf.shape[0])
    try:
        values, vectors = spla.eigsh(
            Kf,
            k=count,
            M=Mf,
            sigma=sigma,
            which="LM",
            OPinv=inverse,
            v0=v0,
            maxiter=MAX_RESTARTS,
        )
    except spla.ArpackNoConvergence:
        raise NumericalError(f"the lowest {count} modes did not converge: ask for fewer", "dynamic.modes") from None
    if not np.all(np.isfinite(values)) or values.min() < sigma - 1e-6 * abs(values).max():
        raise NumericalError(f"the eigensolver gave spurious values for {count} modes: ask for fewer", "dynamic.modes")
    order = np.argsort(values)
    shapes = np.zeros((N, count))
    shapes[free] = vectors[:, order]
    return Modes(hz=np.sqrt(np.maximum(values[order], 0.0)) / (2 * np.pi), shapes=shapes)


def stiffness_factor(K, fixed: np.ndarray):
    """The factorisation of ``K`` on its free DOFs (``fixed`` held): :func:`natural_modes`'s
    operator at shift 0, shared by every mass distribution of one supported part."""
    free = np.setdiff1d(np.arange(K.shape[0]), np.asarray(fixed, dtype=np.int64))
    return factorise(free_submatrix(K, free).tocsr(), "direct")
