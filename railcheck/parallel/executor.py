"""Jobs of chunks -> their results, in order, on any executor: serially, on processes forked
from this one (:mod:`.forked`), on this process's threads (:mod:`.threads`), or on Dask (a
local cluster or an existing scheduler: :mod:`.dask`), through one call,
:meth:`ChunkExecutor.map_jobs`. A job is ``(make_context, lengths, kind, checked)``: its
context is built when its first chunk is due, its settings are cut into chunks
(:func:`chunk_ranges`) and each chunk is ``evaluate(context, lengths, ids)``, the function the
executor was made with (a module-level function, so that Dask can send it by reference).
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Generator
from pathlib import Path
from typing import Any

import numpy as np

from railcheck.base.errors import InputError
from railcheck.parallel.dask import WORKER_CONFIG, WORKER_MALLOC, quiet_cluster_exit
from railcheck.parallel.ordered import in_order
from railcheck.parallel.shared import remove_shared, shared, write_shared
from railcheck.parallel.threads import blas_on_one_thread


class ChunkExecutor:
    """Chunks of settings -> their columns, in order: serially, on ``threads`` local
    workers (forked processes when ``forks``, else threads), or on Dask (a local cluster
    unless ``scheduler`` names one). On Dask every kind's chunks form one queue
    (a kind's last chunks share the workers with the next kind's first), two chunks per
    worker in flight, finished chunks held until the ones before them are done (a slow
    chunk does not idle the other workers). A local cluster's workers map each kind's
    context from a file in ``scratch`` (:mod:`railcheck.parallel.shared`); an external
    scheduler's receive it scattered."""

    def __init__(
        self,
        scheduler,
        workers,
        use_dask: bool,
        progress,
        scratch: Path | None = None,
        threads: int = 1,
        forks: bool = False,
        evaluate=None,
    ):
        self.evaluate = evaluate  # (context, lengths, ids) -> a chunk's result
        self.progress = progress
        self.use_dask = use_dask
        self.threads = threads
        self.forks = forks
        self.scheduler, self.workers = scheduler, workers
        self.scratch = scratch
        self.client: Any = None  # dask.distributed.Client once started
        self.cluster: Any = None  # dask.distributed.LocalCluster when started here

    def __enter__(self):
        if self.use_dask:
            self._start()
        return self

    def _start(self):
        import logging

        from dask.distributed import Client, LocalCluster

        quiet_cluster_exit()
        if self.scheduler:
            try:
                self.client = Client(self.scheduler, timeout="5s")
            except (OSError, TimeoutError) as exc:
                raise InputError("--scheduler", f"cannot reach {self.scheduler}: {exc}") from None
        else:
            import dask

            n = self.workers or os.cpu_count() or 1
            environ = {f"distributed.nanny.pre-spawn-environ.{k}": v for k, v in WORKER_MALLOC.items()}
            with dask.config.set(environ | WORKER_CONFIG):
                self.cluster = LocalCluster(
                    n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=logging.ERROR
                )
            self.client = Client(self.cluster)
        self.progress.say(
            "sweep", f"Dask: {len(self.client.scheduler_info()['workers'])} workers ({self.scheduler or 'local cluster'})"
        )

    def __exit__(self, *exc):
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()
        return False

    def map_jobs(self, jobs: list, size: int, checked_size: int, held: int):
        """Yield ``(job index, columns)`` of every chunk of every job ``(make_context,
        lengths, kind, checked)`` in order, job by job, with a progress line every few
        seconds (``make_context()`` builds the job's context when its first chunk is due;
        chunks as :func:`chunk_ranges`; on Dask at most ``held`` finished chunks wait for an
        earlier one)."""
        if self.use_dask:
            yield from self._dask_jobs(jobs, size, checked_size, held)
        elif self.threads > 1:
            yield from self._local_jobs(jobs, size, checked_size, held)
        else:
            for j, (make_context, lengths, kind, checked) in enumerate(jobs):
                ctx, total = make_context(), lengths["crank"].size
                meter = Meter(self.progress, kind, total)
                for ids in chunk_ranges(checked, size, checked_size):
                    cols = self.evaluate(ctx, {b: v[ids] for b, v in lengths.items()}, ids)
                    meter.done(ids.size)
                    yield j, cols

    def _local_jobs(self, jobs: list, size: int, checked_size: int, held: int):
        """:meth:`map_jobs` on processes forked from this one when the executor
        ``forks`` (:mod:`railcheck.parallel.forked`), else on this process's threads
        (:mod:`railcheck.parallel.threads`): the same chunks as on as many Dask workers, the
        same columns."""
        how = "processes forked from this one" if self.forks else "threads in this process"
        self.progress.say("sweep", f"{self.threads} {how}")
        tasks = shared_out(jobs, size, checked_size, self.threads)
        with blas_on_one_thread():
            if self.forks:
                yield from self._forked_jobs(jobs, tasks, held)
            else:
                yield from self._threaded_jobs(jobs, tasks, held)

    def _forked_jobs(self, jobs: list, tasks: list[tuple[int, np.ndarray]], held: int):
        """Each job's chunks on processes forked once its context is built: they share it
        (and the settings) copy on write; it is released when the job is done."""
        for j, (make_context, lengths, kind, _) in enumerate(jobs):
            context = make_context()
            mine = [ids for i, ids in tasks if i == j]

            def run(ids, context=context, lengths=lengths):
                return self.evaluate(context, {b: v[ids] for b, v in lengths.items()}, ids)

            meter = Meter(self.progress, kind, lengths["crank"].size)
            for ids, cols in zip(mine, in_order(run, mine, on="forked", workers=self.threads, ahead=held)):
                meter.done(ids.size)
                yield j, cols
            del context, run

    def _threaded_jobs(self, jobs: list, tasks: list[tuple[int, np.ndarray]], held: int):
        """Every job's chunks in one queue on this process's threads (each job's context
        built first)."""
        contexts = [make_context() for make_context, *_ in jobs]
        started: dict[int, float] = {}  # job index -> when its first chunk started

        def run(task):
            j, ids = task
            started.setdefault(j, time.perf_counter())
            return self.evaluate(contexts[j], {b: v[ids] for b, v in jobs[j][1].items()}, ids)

        meters: dict[int, Meter] = {}
        for (j, ids), cols in zip(tasks, in_order(run, tasks, on="threads", workers=self.threads, ahead=held)):
            if j not in meters:
                meters[j] = Meter(self.progress, jobs[j][2], jobs[j][1]["crank"].size, started[j])
            meters[j].done(ids.size)
            yield j, cols

    def _dask_jobs(self, jobs: list, size: int, checked_size: int, held: int):
        """:meth:`map_jobs` on Dask: every job's chunks in one ordered map (:func:`in_order`
        on the client), two chunks per worker running, a job's context built when its
        first chunk is submitted and released when its last is yielded."""
        workers = max(1, len(self.client.scheduler_info()["workers"]))
        tasks = shared_out(jobs, size, checked_size, workers)
        meters: dict[int, Meter] = {}
        contexts: dict[int, object] = {}

        def submitted():
            for j, ids in tasks:
                if j not in contexts:
                    contexts[j] = self._context_ref(j, jobs[j][0]())
                    meters[j] = Meter(self.progress, jobs[j][2], jobs[j][1]["crank"].size)
                yield self.evaluate, contexts[j], {b: v[ids] for b, v in jobs[j][1].items()}, ids

        results = in_order(evaluate_shared, submitted(), on="dask", client=self.client, workers=2 * workers, ahead=held)
        try:
            for done, ((j, ids), cols) in enumerate(zip(tasks, results), 1):
                meters[j].done(ids.size)
                yield j, cols
                if done == len(tasks) or tasks[done][0] != j:
                    self._release(contexts.pop(j))
        finally:
            if isinstance(results, Generator):
                results.close()  # cancels the chunks still running
            for ref in contexts.values():
                self._release(ref)

    def _context_ref(self, j: int, ctx):
        """What a task is given for its context: a shared file's path (local cluster,
        :mod:`railcheck.parallel.shared`), else the context scattered to every worker."""
        if self.cluster is not None and self.scratch is not None:
            try:
                return str(write_shared(ctx, self.scratch / f".context-{j}.bin"))
            except OSError as exc:
                self.progress.say("sweep", f"cannot share the context through {self.scratch} ({exc}): scattering it")
        return self.client.scatter(ctx, broadcast=True)

    @staticmethod
    def _release(ref) -> None:
        if isinstance(ref, str):
            remove_shared(Path(ref))


def shared_out(jobs: list, size: int, checked_size: int, workers: int) -> list[tuple[int, np.ndarray]]:
    """(job index, settings' indices) of every chunk of every job, in order, for
    ``workers`` running at once: each kind in at least two chunks per worker, so that none
    runs alone (chunks as :func:`chunk_ranges`)."""
    share = lambda n, most: max(1, min(most, -(-n // (2 * workers))))  # noqa: E731
    return [
        (j, ids)
        for j, (_, lengths, _, checked) in enumerate(jobs)
        for ids in chunk_ranges(checked, share(checked.size, size), share(int(checked.sum()), checked_size))
    ]


def chunk_ranges(checked: np.ndarray, size: int, checked_size: int):
    """The settings' indices of each chunk: consecutive settings, at most ``size`` of them
    and at most ``checked_size`` checked by FE (``checked`` (N,) bool, one per setting)."""
    count = np.concatenate([[0], np.cumsum(checked)])  # checked settings before each
    a = 0
    while a < checked.size:
        # the last end b whose chunk [a, b) holds at most checked_size checked settings
        b = int(np.searchsorted(count, count[a] + checked_size, side="right")) - 1
        b = max(a + 1, min(b, a + size))
        yield np.arange(a, b)
        a = b


def evaluate_shared(task: tuple) -> dict:
    """One chunk in a worker: ``task`` = (evaluate, context, lengths, ids), the context a
    shared file's path or the context itself; ``evaluate(context, lengths, ids)``."""
    evaluate, context, lengths, ids = task
    return evaluate(shared(context) if isinstance(context, str) else context, lengths, ids)


class Meter:
    """Progress of one kind: settings done, rate and elapsed time, every 5 s at most."""

    def __init__(self, progress, kind: str, total: int, t0: float | None = None):
        self.progress, self.kind, self.total = progress, kind, total
        self.count, self.t0, self.last = 0, time.perf_counter() if t0 is None else t0, -math.inf

    def done(self, n: int) -> None:
        self.count += n
        now = time.perf_counter()
        if now - self.last >= 5.0 or self.count == self.total:
            self.last = now
            rate = self.count / max(now - self.t0, 1e-9)
            bar = "#" * int(20 * self.count / max(self.total, 1))
            left = f", about {eta_words((self.total - self.count) / rate)} left" if self.count < self.total else ""
            self.progress.say(
                "sweep", f"{self.kind:<12} [{bar:<20}] {self.count}/{self.total} settings, {rate:,.0f} settings/s{left}"
            )


def eta_words(seconds: float) -> str:
    """A remaining time as a person reads it: "40 s", "3 min", "1.2 h" (at the rate so far)."""
    if seconds < 90:
        return f"{max(seconds, 1):.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"
