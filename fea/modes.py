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

__all__ = ["Modes", "natural_modes", "vector_mass_matrix"]


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


def natural_modes(K, M, fixed: np.ndarray, count: int, shift: float | None = None) -> Modes:
    """The ``count`` lowest modes of ``K phi = omega^2 M phi`` with the ``fixed`` DOFs held.
    ``shift`` (rad^2/s^2) the spectral shift: default 0 for a supported part and, for a
    free one (no fixed DOF), minus the squared angular frequency of 1 Hz."""
    N = K.shape[0]
    free = np.setdiff1d(np.arange(N), np.asarray(fixed, dtype=np.int64))
    Kf, Mf = free_submatrix(K, free), free_submatrix(M, free)
    sigma = shift if shift is not None else (0.0 if free.size < N else -((2 * np.pi) ** 2))
    factor = factorise((Kf - sigma * Mf).tocsr(), "direct")
    inverse = spla.LinearOperator(Kf.shape, matvec=factor.solve_once, dtype=float)
    values, vectors = spla.eigsh(Kf, k=count, M=Mf, sigma=sigma, which="LM", OPinv=inverse)
    order = np.argsort(values)
    shapes = np.zeros((N, count))
    shapes[free] = vectors[:, order]
    return Modes(hz=np.sqrt(np.maximum(values[order], 0.0)) / (2 * np.pi), shapes=shapes)
