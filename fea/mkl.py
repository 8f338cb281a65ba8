"""Intel MKL, where the ``mkl`` wheel that pypardiso installs loads (x86-64 Linux): whether
PARDISO is available, and MKL's runtime library with the sparse BLAS prototypes that
:mod:`railcheck.fea.products` calls. Elsewhere both answer "not here" and the solvers
fall back to scipy."""

from __future__ import annotations

import ctypes
import functools
import os

__all__ = ["MKL_REPRODUCIBLE", "MatrixDescr", "pardiso_available", "sparse_blas"]


#: MKL's conditional numerical reproducibility: without it a threaded PARDISO factor of a
#: large system differs run to run in the last digits (summary.json must be repeatable)
MKL_REPRODUCIBLE = "AUTO,STRICT"


@functools.cache
def pardiso_available() -> bool:
    """Whether MKL PARDISO loads. The first solver found MKL's library by searching the
    installation tree (about 0.3 s); its path goes to ``PYPARDISO_MKL_RT`` so that every
    later solver loads it directly."""
    os.environ.setdefault("MKL_CBWR", MKL_REPRODUCIBLE)  # read once, when MKL loads
    try:
        from pypardiso.pardiso_wrapper import PyPardisoSolver

        solver = PyPardisoSolver()
    except (ImportError, OSError):
        return False
    path = getattr(solver.libmkl, "_name", None)
    if path:
        os.environ.setdefault("PYPARDISO_MKL_RT", path)
    return True


class MatrixDescr(ctypes.Structure):
    """MKL's ``struct matrix_descr`` (type, fill mode, diagonal), passed by value."""

    _fields_ = [("type", ctypes.c_int), ("mode", ctypes.c_int), ("diag", ctypes.c_int)]


@functools.cache
def sparse_blas():
    """MKL's runtime library with the sparse BLAS prototypes set (LP64: 32-bit
    indices), or None where it does not load."""
    if not pardiso_available():
        return None
    try:
        lib = ctypes.CDLL(os.environ["PYPARDISO_MKL_RT"]) if "PYPARDISO_MKL_RT" in os.environ else None
        if lib is None:
            from pypardiso.pardiso_wrapper import PyPardisoSolver

            lib = PyPardisoSolver().libmkl
        ptr, i32, i64, dbl = ctypes.c_void_p, ctypes.c_int32, ctypes.c_int64, ctypes.c_double
        lib.mkl_sparse_d_create_csr.argtypes = [ctypes.POINTER(ptr), ctypes.c_int, i32, i32, ptr, ptr, ptr, ptr]
        lib.mkl_sparse_d_mv.argtypes = [ctypes.c_int, dbl, ptr, MatrixDescr, ptr, dbl, ptr]
        lib.mkl_sparse_d_mm.argtypes = [ctypes.c_int, dbl, ptr, MatrixDescr, ctypes.c_int, ptr, i64, i64, dbl, ptr, i64]
        lib.mkl_sparse_destroy.argtypes = [ptr]
        for name in ("mkl_sparse_d_create_csr", "mkl_sparse_d_mv", "mkl_sparse_d_mm", "mkl_sparse_destroy"):
            getattr(lib, name).restype = ctypes.c_int
    except (OSError, AttributeError, ImportError):
        return None
    return lib
