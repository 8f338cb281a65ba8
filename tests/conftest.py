import math
import os
import shutil
from pathlib import Path

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


def _copy_meshes(source: Path, target: Path) -> None:
    """Copy the mesh entries of cache folder ``source`` that ``target`` lacks (each through
    a temporary name and a rename, as the mesher writes: a reader never sees half a file;
    an entry is a regular file, checked against its own hash when read)."""
    from railcheck.geometry.cache import ENTRY_NAME

    if not source.is_dir():
        return
    target.mkdir(parents=True, exist_ok=True)
    for entry in source.glob("*.npz"):
        if ENTRY_NAME.fullmatch(entry.name) and entry.is_file() and not entry.is_symlink():
            if not (target / entry.name).exists():
                partial = target / f".{entry.name}.{os.getpid()}.copy"
                shutil.copyfile(entry, partial)
                os.replace(partial, target / entry.name)


@pytest.fixture
def cache_with_meshes():
    """A factory of cache folders (RAILCHECK_CACHE) holding the default cache's meshes and
    no unit fields, for the tests that count unit solves from an empty store without
    meshing again (a few seconds a rail); the meshes such a test made go back to the
    default cache when it ends, where the next run finds them."""
    from railcheck.environment import cache_dir

    default, made = cache_dir(), []

    def make(folder: Path) -> Path:
        _copy_meshes(default, folder)
        made.append(folder)
        return folder

    yield make
    for folder in made:
        _copy_meshes(folder, default)
