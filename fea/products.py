"""Products of a fixed sparse matrix with vectors or blocks of columns, the inner loop of
every iterative solve (p-multigrid CG, the stress projection's CG) and of the direct
solve's refinement residual.

:func:`sparse_product` gives the fastest one installed:

* :class:`MklProduct`: MKL's inspector-executor sparse BLAS (``mkl_sparse_d_mv`` /
  ``mkl_sparse_d_mm``, threaded and vectorised) on the CSR arrays themselves, no copy,
  through the ``mkl`` wheel that PARDISO already loads (x86-64 Linux). On 2 cores it is
  3-4x scipy's product on the matrices railcheck builds (``benchmarks/fe_stages.py``).
* :class:`RowBlocks`: scipy's product on row blocks, one thread per core (scipy releases
  the GIL); everywhere, and for long-double values, which MKL does not take.

Each output row is summed by one thread in a fixed order, so the result does not depend
on the number of threads.
"""

from __future__ import annotations

import ctypes
import os

import numpy as np
import scipy.sparse as sp

from .mkl import MatrixDescr
from .mkl import sparse_blas as mkl_sparse_library

_GENERAL, _NON_TRANSPOSE, _ROW_MAJOR, _ZERO_BASED = 20, 10, 101, 0  # MKL's sparse enums


def sparse_product(A: sp.spmatrix, dtype=float):
    """The fastest installed product with the sparse matrix ``A`` (``product @ X``)."""
    A = sp.csr_matrix(A)
    if np.dtype(dtype) == np.float64 and 0 < A.nnz < 2**31 and max(A.shape) < 2**31 and mkl_sparse_library() is not None:
        try:
            return MklProduct(A)
        except RuntimeError:  # MKL refused the matrix: scipy takes it
            pass
    return RowBlocks(A, dtype)


class MklProduct:
    """``A @ X`` (X (m,) or (m, k), float64) by MKL's sparse BLAS on A's CSR arrays (kept
    alive here; MKL reads them in place)."""

    def __init__(self, A: sp.csr_matrix):
        self.shape = A.shape
        self._lib = mkl_sparse_library()
        self._indptr = np.ascontiguousarray(A.indptr, dtype=np.int32)
        self._indices = np.ascontiguousarray(A.indices, dtype=np.int32)
        self._data = np.ascontiguousarray(A.data, dtype=np.float64)
        self._handle: ctypes.c_void_p | None = ctypes.c_void_p()
        status = self._lib.mkl_sparse_d_create_csr(
            ctypes.byref(self._handle),
            _ZERO_BASED,
            A.shape[0],
            A.shape[1],
            self._indptr.ctypes.data,
            self._indptr.ctypes.data + self._indptr.itemsize,
            self._indices.ctypes.data,
            self._data.ctypes.data,
        )
        if status != 0:
            self._handle = None
            raise RuntimeError(f"mkl_sparse_d_create_csr failed with status {status}")

    def __matmul__(self, X: np.ndarray) -> np.ndarray:
        X = np.ascontiguousarray(X, dtype=np.float64)
        if X.shape[0] != self.shape[1]:
            raise ValueError(f"product of a {self.shape} matrix with {X.shape[0]} rows")
        out = np.empty((self.shape[0],) + X.shape[1:])
        descr = MatrixDescr(_GENERAL, 0, 0)
        if X.ndim == 1:
            status = self._lib.mkl_sparse_d_mv(_NON_TRANSPOSE, 1.0, self._handle, descr, X.ctypes.data, 0.0, out.ctypes.data)
        else:
            k = X.shape[1]
            status = self._lib.mkl_sparse_d_mm(
                _NON_TRANSPOSE, 1.0, self._handle, descr, _ROW_MAJOR, X.ctypes.data, k, k, 0.0, out.ctypes.data, k
            )
        if status != 0:
            raise RuntimeError(f"MKL sparse product failed with status {status}")
        return out

    def __del__(self):
        handle = getattr(self, "_handle", None)
        if handle:
            try:
                self._lib.mkl_sparse_destroy(handle)
            except Exception:  # noqa: BLE001 - interpreter shutdown
                pass
            self._handle = None


class RowBlocks:
    """A CSR matrix cut into row blocks, one per core (up to 4) when it is large, whose
    products run in threads (scipy's sparse products release the GIL). ``dtype``: the
    blocks' value type (long double for an extended-precision residual)."""

    def __init__(self, K: sp.csr_matrix, dtype=float):
        K = sp.csr_matrix(K)
        self.shape = K.shape
        count = max(1, min(os.cpu_count() or 1, 4)) if K.nnz > 1_000_000 else 1
        edges = np.linspace(0, K.shape[0], count + 1).astype(int)
        self.blocks = [(a, b, _row_block(K, a, b, dtype)) for a, b in zip(edges[:-1], edges[1:])]

    def each(self, work) -> None:
        """``work(first, stop, block)`` for every block, in threads when there are several."""
        if len(self.blocks) == 1:
            work(*self.blocks[0])
            return
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(len(self.blocks)) as pool:
            list(pool.map(lambda block: work(*block), self.blocks))

    def __matmul__(self, X: np.ndarray) -> np.ndarray:
        out = np.empty((self.shape[0],) + X.shape[1:], dtype=np.result_type(self.blocks[0][2].dtype, X.dtype))

        def rows(first, stop, block):
            out[first:stop] = block @ X

        self.each(rows)
        return out


def _row_block(K: sp.csr_matrix, first: int, stop: int, dtype) -> sp.csr_matrix:
    """Rows ``first:stop`` of the CSR matrix ``K`` with values of ``dtype``, sharing its
    column indices (scipy's row slice copies them through a general submatrix routine)."""
    a, b = K.indptr[first], K.indptr[stop]
    block = sp.csr_matrix(
        (K.data[a:b].astype(dtype), K.indices[a:b], K.indptr[first : stop + 1] - a),
        shape=(stop - first, K.shape[1]),
        copy=False,
    )
    block.has_sorted_indices = K.has_sorted_indices
    return block
