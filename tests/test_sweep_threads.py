"""Chunks on this process's threads (:mod:`railcheck.parallel.threads`): results in order,
at most ``ahead`` started beyond the awaited one, an error at its turn, nothing started
once the caller stops; and a sweep on threads writes the serial run's tables."""

import os
import threading
import time

import numpy as np
import pytest

from railcheck.parallel.threads import blas_on_one_thread, in_order_on_threads


def _slow_square(i: int) -> int:
    time.sleep(0.002 * ((7 * i) % 5))  # finish out of order
    return i * i


@pytest.mark.parametrize("workers", [1, 2, 3])
@pytest.mark.parametrize("forks", [False, pytest.param(True, marks=pytest.mark.slow)], ids=["threads", "forked"])
def test_results_come_in_the_items_order_whatever_order_they_finish_in(workers, forks):
    """On threads and on forked processes (:mod:`railcheck.parallel.forked`)."""
    from railcheck.parallel import forked

    if forks and not forked.available():
        pytest.skip("this platform does not fork")
    if forks and os.environ.get("PYTEST_XDIST_WORKER"):
        pytest.skip("forks: the slow tier runs it")
    in_order = forked.in_order_on_processes if forks else in_order_on_threads
    items = list(range(40))
    assert list(in_order(_slow_square, items, workers, ahead=4)) == [i * i for i in items]


def test_no_more_than_ahead_items_are_started_beyond_the_awaited_one():
    lock, started, worst = threading.Lock(), [], [0]
    taken = [0]  # results the caller has taken

    def record(i):
        with lock:
            started.append(i)
            worst[0] = max(worst[0], i - taken[0])
        time.sleep(0.001)
        return i

    for value in in_order_on_threads(record, list(range(30)), threads=3, ahead=2):
        time.sleep(0.003)  # a slow consumer: the workers would run ahead if allowed
        with lock:
            taken[0] = value + 1
    assert sorted(started) == list(range(30))
    assert worst[0] <= 2 + 1  # the awaited item itself, plus two ahead


def test_an_error_is_raised_at_its_turn_after_the_results_before_it():
    def fail_at_5(i):
        if i == 5:
            raise ValueError("item 5")
        return i

    got = []
    with pytest.raises(ValueError, match="item 5"):
        for value in in_order_on_threads(fail_at_5, list(range(20)), threads=2, ahead=3):
            got.append(value)
    assert got == [0, 1, 2, 3, 4]


def test_nothing_more_is_started_once_the_caller_stops():
    started = []

    def record(i):
        started.append(i)
        time.sleep(0.002)
        return i

    results = in_order_on_threads(record, list(range(100)), threads=2, ahead=2)
    assert next(results) == 0
    results.close()  # the caller stops (an abandoned iterator, an exception, a signal)
    time.sleep(0.05)  # a running item may still finish
    count = len(started)
    time.sleep(0.05)
    assert len(started) == count <= 1 + 2 + 2  # the first, two ahead, and one per thread at most


def test_openblas_runs_on_one_thread_inside_the_block_only_and_pardisos_mkl_keeps_its_threads():
    """numpy's and scipy's BLAS on one thread inside the block; MKL, loaded for PARDISO,
    keeps its thread count (PARDISO's digits depend on it: a store entry solved again
    inside the block must give a serial run's, tests/test_store.py)."""
    from threadpoolctl import threadpool_info

    import railcheck.fea.mkl as mkl

    def threads(api):
        return [p["num_threads"] for p in threadpool_info() if p["internal_api"] == api]

    mkl.pardiso_available()  # MKL loaded where it is installed
    np.ones((4, 4)) @ np.ones((4, 4))  # BLAS loaded
    before = {api: threads(api) for api in ("openblas", "mkl")}
    with blas_on_one_thread():
        assert threads("openblas") and all(n == 1 for n in threads("openblas"))
        assert threads("mkl") == before["mkl"]
    assert {api: threads(api) for api in ("openblas", "mkl")} == before
