import math
import os

import pytest


def _share_blas_threads_among_workers() -> None:
    """Give each pytest-xdist worker its share of the cores for OpenBLAS (numpy's and
    scipy's BLAS): with every worker's BLAS spawning a thread per core, two workers on two
    cores run four busy threads that trade the cores (the fast tier, warm cache: 96 s
    without the share, 87 s with it). MKL, which PARDISO runs on, is left alone: its thread count changes the
    order of its sums and so the last digits some tests compare."""
    workers = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "0") or 0)
    if workers < 2:
        return
    share = str(max(1, (os.cpu_count() or 1) // workers))
    os.environ.setdefault("OPENBLAS_NUM_THREADS", share)
    from threadpoolctl import ThreadpoolController

    ThreadpoolController().select(internal_api="openblas").limit(limits=int(share))


_share_blas_threads_among_workers()


def agree_sig(a: float, b: float, figures: int = 4) -> bool:
    """True when ``a`` agrees with the published ``b`` to ``figures`` significant figures
    (within half a unit of the last published figure)."""
    if b == 0:
        return abs(a) < 10 ** (-figures)
    unit = 10 ** (math.floor(math.log10(abs(b))) - (figures - 1))
    return abs(a - b) <= 0.5 * unit


@pytest.fixture
def sig():
    return agree_sig
