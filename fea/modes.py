"""Natural frequencies and mode shapes of a part: the consistent mass matrix of the vector
basis and the lowest eigenpairs of ``K phi = omega^2 M phi`` by shift-invert Lanczos (scipy
``eigsh``) with the stiffness factorisation as the inverse operator.

A supported part takes ``fixed`` DOFs; a free body none (its six rigid-body modes come
first, at zero frequency, and the shift then sits below zero so ``K - sigma M`` stays
positive definite). Units SI: kg/m^3, N/m, Hz.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .assembly import mass_matrix
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


def natural_modes(K, M, fixed: np.ndarray, count: int, shift: float | None = None, factor=None) -> Modes:
    """The ``count`` lowest modes of ``K phi = omega^2 M phi`` with the ``fixed`` DOFs held.
    ``shift`` (rad^2/s^2) the spectral shift: default 0 for a supported part and, for a
    free one (no fixed DOF), minus the squared angular frequency of 1 Hz. ``factor``: a
    factorisation of ``K - shift M`` on the free DOFs already made (:func:`shift_factor`;
    with shift 0 it does not depend on M, so several mass distributions share it)."""
    N = K.shape[0]
    free = np.setdiff1d(np.arange(N), np.asarray(fixed, dtype=np.int64))
    Kf, Mf = free_submatrix(K, free), free_submatrix(M, free)
    sigma = shift if shift is not None else (0.0 if free.size < N else -((2 * np.pi) ** 2))
    factor = factor or factorise((Kf - sigma * Mf).tocsr(), "direct")
    inverse = spla.LinearOperator(Kf.shape, matvec=factor.solve_once, dtype=float)
    # a fixed start vector (ARPACK's default is random: the last bits of the frequencies
    # would change from run to run); random-like so that no mode is orthogonal to it
    v0 = np.random.default_rng(0).standard_normal(Kf.shape[0])
    values, vectors = spla.eigsh(Kf, k=count, M=Mf, sigma=sigma, which="LM", OPinv=inverse, v0=v0)
    order = np.argsort(values)
    shapes = np.zeros((N, count))
    shapes[free] = vectors[:, order]
    return Modes(hz=np.sqrt(np.maximum(values[order], 0.0)) / (2 * np.pi), shapes=shapes)


def stiffness_factor(K, fixed: np.ndarray):
    """The factorisation of ``K`` on its free DOFs (``fixed`` held): :func:`natural_modes`'s
    operator at shift 0, shared by every mass distribution of one supported part."""
    free = np.setdiff1d(np.arange(K.shape[0]), np.asarray(fixed, dtype=np.int64))
    return factorise(free_submatrix(K, free).tocsr(), "direct")
