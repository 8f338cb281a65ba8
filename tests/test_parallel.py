"""The one ordered map (railcheck.parallel.in_order): every executor gives the items'
results in their order, raises an item's error when its result is due, and on Dask draws
the items lazily within its limits."""

import time

import pytest

from railcheck.parallel import forked
from railcheck.parallel.executor import Meter, eta_words
from railcheck.parallel.ordered import EXECUTORS, in_order


def slow_square(x: int) -> int:
    """x squared, the early items slower (so that later ones finish first)."""
    time.sleep(0.002 * (8 - x % 8))
    return x * x


def fails_at_five(x: int) -> int:
    if x == 5:
        raise ValueError("item five")
    return x


def fails_at_five_before_a_slow_four(x: int) -> int:
    """Item five fails while item four still runs: its error is not yet due."""
    if x == 4:
        time.sleep(0.5)
    return fails_at_five(x)


LOCAL = [e for e in EXECUTORS if e != "dask" and (e != "forked" or forked.available())]


@pytest.mark.parametrize("on", LOCAL)
def test_every_local_executor_gives_the_results_in_order(on):
    assert list(in_order(slow_square, range(20), on=on, workers=2, ahead=3)) == [x * x for x in range(20)]


@pytest.mark.parametrize("on", LOCAL)
def test_an_items_error_is_raised_when_its_result_is_due(on):
    results = in_order(fails_at_five, range(10), on=on, workers=2)
    assert [next(results) for _ in range(5)] == [0, 1, 2, 3, 4]
    with pytest.raises(ValueError, match="item five"):
        next(results)


def test_an_unknown_executor_is_refused():
    with pytest.raises(ValueError, match="on must be one of"):
        in_order(slow_square, [1], on="gpu")


@pytest.fixture(scope="module")
def client():
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def first_slow(x: int) -> int:
    """x, item 0 slow enough that every other could finish before it."""
    time.sleep(0.5 if x == 0 else 0.001)
    return x * x


def test_dask_gives_the_results_in_order_and_draws_the_items_within_its_limits(client):
    drawn = []

    def items():
        for x in range(30):
            drawn.append(x)
            yield x

    results = in_order(first_slow, items(), on="dask", client=client, workers=3, ahead=4)
    first = next(results)
    assert first == 0 and len(drawn) <= 3 + 4  # at most 3 running and 4 finished ahead
    assert [first, *results] == [x * x for x in range(30)]


@pytest.mark.parametrize("function", [fails_at_five, fails_at_five_before_a_slow_four])
def test_dask_raises_an_items_error_when_due_and_cancels_the_rest(client, function):
    results = in_order(function, range(50), on="dask", client=client, workers=2, ahead=2)
    assert [next(results) for _ in range(5)] == [0, 1, 2, 3, 4]
    with pytest.raises(ValueError, match="item five"):
        next(results)


def test_the_sweeps_bar_says_how_long_is_left_at_the_rate_so_far():
    """Each line before the last gives the time left at the rate so far; the last none."""
    said: list[str] = []
    progress = type("P", (), {"say": lambda self, stage, message: said.append(message)})()
    meter = Meter(progress, "four-bar", 100, t0=time.perf_counter() - 10.0)  # 10 s for the first 25
    meter.done(25)
    meter.done(75)
    assert "25/100 settings" in said[0] and "about 30 s left" in said[0]
    assert said[-1].endswith("settings/s") and "100/100" in said[-1]
    assert (eta_words(30), eta_words(600), eta_words(7200)) == ("30 s", "10 min", "2.0 h")
