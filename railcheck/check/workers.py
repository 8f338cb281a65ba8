"""The parts of a check, two (or ``jobs``) at a time.

Each part is independent once its :class:`~railcheck.model.jobs.PartJob` is resolved:
mesh, unit cases, envelope, fatigue (:func:`railcheck.model.cycle.check_part`). With more
than one part and more than one core the parts are taken in :func:`work_order` (costliest
first, a second rail of one size last, and only once the first is done: it reads the
first's unit fields from the store) by this process and ``jobs - 1`` worker processes
(spawned, so no library state is forked), whichever is free taking the next; the
workers' progress lines reach the console through a queue as they happen, and each
part's result comes back whole. Errors raised in a worker are raised here unchanged.
When every part's unit fields are already stored (nothing to factorise, no worker worth
its start-up) the parts' cycles run on two threads of this process instead and their
files are written on this thread as each is done. ``jobs=1`` (``railcheck check --jobs
1``) runs them in this process, one after another; the results are the same, byte for
byte (every stage whose digits they show runs with OpenBLAS on one thread wherever it runs:
:func:`railcheck.parallel.threads.on_one_blas_thread`).
"""

from __future__ import annotations

import dataclasses
import os
import threading
import time
from concurrent.futures import ThreadPoolExecutor, as_completed

from railcheck import environment
from railcheck.fea.store import reads_shared
from railcheck.geometry.mesher import estimate_elements
from railcheck.model.cycle import check_part, in_store
from railcheck.model.jobs import PartJob
from railcheck.model.records import PartResult
from railcheck.model.setting_free import pair_deflections, uses_hole_basis
from railcheck.parallel.spawned import relayed_pool, worker_say
from railcheck.parallel.threads import blas_on_one_thread
from railcheck.progress import Progress


def default_jobs(parts: int) -> int:
    """Worker processes for ``parts`` parts: one per core, at most two (each part's solve
    already uses every core while it factorises), never more than the parts."""
    return max(1, min(parts, os.cpu_count() or 1, 2))


class Starts:
    """Each part's progress label, "(k/n) name", numbered in the order the parts start and
    announced ("(k/n) name: started") the moment its number is given, under one lock, so
    the console's lines count up whichever thread or worker runs a part: a part started
    second never shows before the first's announcement."""

    def __init__(self, parts: int, say):
        self.parts = parts
        self.say = say
        self.given = 0
        self.lock = threading.Lock()

    def label(self, name: str) -> str:
        """The next number for ``name``, announced before this returns."""
        with self.lock:
            self.given += 1
            label = f"({self.given}/{self.parts}) {name}"
            self.say(f"{label}: started")
            return label


def check_parts(
    part_jobs: dict[str, PartJob], solver: str, progress: Progress, jobs: int | None = None, part_done=None
) -> dict[str, PartResult]:
    """{name: PartResult} in the jobs' order; ``part_done(name, part)``, a picklable
    callable, runs as each part finishes, in the process that checked it."""
    n = len(part_jobs)
    starts = Starts(n, lambda msg: progress.say("solve", msg))
    if jobs is None and n > 1 and all(in_store(job) for job in part_jobs.values()):
        return _on_threads(part_jobs, solver, progress, default_jobs(n), starts, part_done)
    jobs = default_jobs(n) if jobs is None else max(1, min(jobs, n))
    if jobs == 1:
        return {
            name: _check_one(job, solver, starts.label(name), part_done, lambda msg: progress.say("solve", msg))
            for name, job in part_jobs.items()
        }
    return _in_workers(part_jobs, solver, progress, jobs, starts, part_done)


def _on_threads(
    part_jobs: dict[str, PartJob], solver: str, progress: Progress, threads: int, starts: Starts, part_done
) -> dict[str, PartResult]:
    """Every part's unit fields stored (nothing to solve, no worker worth starting): the
    parts' cycles on ``threads`` threads of this process, in :func:`work_order` (their
    numpy work releases the GIL; BLAS on one thread each), and each part's files written
    here, on this thread, one part at a time as each is done (VTK's renderer and
    matplotlib stay on one thread). The same results, in the parts' order, as one after
    another."""
    say = lambda msg: progress.say("solve", msg)  # noqa: E731
    order = work_order(part_jobs)
    label: dict[str, str] = {}

    def run(name: str) -> PartResult:
        label[name] = t = starts.label(name)
        return check_part(part_jobs[name], solver, lambda m: say(f"{t}: {m}"))

    with blas_on_one_thread(), reads_shared(), ThreadPoolExecutor(threads, thread_name_prefix="railcheck-parts") as pool:
        futures = {name: pool.submit(run, name) for name in order}
        names = {future: name for name, future in futures.items()}
        try:
            done = {
                names[f]: _with_files(f.result(), part_jobs[names[f]], label[names[f]], part_done, say)
                for f in as_completed(futures.values())
            }
            return {name: done[name] for name in part_jobs}
        except BaseException:
            pool.shutdown(wait=False, cancel_futures=True)
            raise


def _in_workers(
    part_jobs: dict[str, PartJob], solver: str, progress: Progress, jobs: int, starts: Starts, part_done
) -> dict[str, PartResult]:
    """The parts in :func:`work_order`, whoever is free taking the next it may
    (:class:`_Queue`: a part that reads another's fields waits for it): this process and
    ``jobs - 1`` workers, each fed by a thread here (a fixed split left this process idle
    after the largest part while one worker checked all the others)."""
    queue = _Queue(work_order(part_jobs), shared_fields(part_jobs), starts)
    label = queue.labels
    results: dict[str, PartResult] = {}

    def here(name: str) -> PartResult:
        return _check_one(part_jobs[name], solver, label[name], part_done, lambda m: progress.say("solve", m))

    with relayed_pool(jobs - 1, progress) as pool:

        def feed() -> None:
            while (name := queue.take()) is not None:
                try:
                    results[name] = pool.submit(_check_one, part_jobs[name], solver, label[name], part_done).result()
                except BaseException as exc:  # noqa: BLE001 - raised in this process below, unchanged
                    queue.failed(exc)
                queue.done(name)

        feeders = [threading.Thread(target=feed, daemon=True) for _ in range(jobs - 1)]
        for t in feeders:
            t.start()
        try:
            while (name := queue.take()) is not None:
                results[name] = here(name)
                queue.done(name)
        except BaseException as exc:
            queue.failed(exc)
        for t in feeders:
            t.join()
    if queue.errors:
        raise queue.errors[0]
    return {name: results[name] for name in part_jobs}


class _Queue:
    """The parts left to check, in order, shared by the threads that take them: a part
    whose unit fields another part solves (``after``: name -> that part) is taken only
    once that part is done (it then reads them from the store instead of solving them
    again beside it); a taker with only such parts left waits. Nothing more is taken
    after an error. A part taken is given its label (``labels``) in the same step, so
    the numbers count up in the order the parts are taken."""

    def __init__(self, order: list[str], after: dict[str, str], starts: Starts):
        self.left = list(order)
        self.starts = starts
        self.labels: dict[str, str] = {}
        self.after = after
        self.finished: set[str] = set()
        self.errors: list[BaseException] = []
        self.changed = threading.Condition()

    def take(self) -> str | None:
        """The next part that may start, waiting while only blocked ones are left; None
        when none is left or after an error."""
        with self.changed:
            while self.left and not self.errors:
                ready = [n for n in self.left if self.after.get(n) in (None, *self.finished)]
                if ready:
                    self.left.remove(ready[0])
                    self.labels[ready[0]] = self.starts.label(ready[0])
                    return ready[0]
                self.changed.wait()
            return None

    def done(self, name: str) -> None:
        with self.changed:
            self.finished.add(name)
            self.changed.notify_all()

    def failed(self, exc: BaseException) -> None:
        with self.changed:
            self.errors.append(exc)
            self.changed.notify_all()


def shared_fields(part_jobs: dict[str, PartJob]) -> dict[str, str]:
    """Part -> the part before it in :func:`work_order` whose stored unit fields it reads:
    two free rails of one size with one rail mass share their hole basis
    (:mod:`railcheck.model.setting_free`: its request has no bar length in it). None
    with the store bypassed (``RAILCHECK_STORE=0``): waiting would gain nothing."""
    if environment.unit_store() is None:
        return {}
    first: dict = {}
    after: dict[str, str] = {}
    for name in work_order(part_jobs):
        key = _basis_key(part_jobs[name])
        if key is not None and key in first:
            after[name] = first[key]
        first.setdefault(key, name)
    return after


def _basis_key(job: PartJob):
    """What a free rail's hole-basis request is made of, without its mesh (which the
    geometry and mesh sizes make): None for a part solved for its own cases."""
    if not uses_hole_basis(job):
        return None
    free = job.free_body
    assert free is not None  # uses_hole_basis: a free rail
    deflections = pair_deflections(job.loads, job.geometry)
    return (repr(job.geometry), job.mesh, repr(job.material), free.mass, free.centre, free.inertia, repr(deflections))


def _estimated_cost(job: PartJob) -> int:
    """The part's work in elements: its estimated element count, doubled when its modes
    are solved too (their shift-invert Lanczos costs about the unit cases' solve)."""
    elements = estimate_elements(job.geometry, job.mesh.size, job.mesh.hole_size)
    return elements * (2 if job.dynamic is not None else 1)


def work_order(part_jobs: dict[str, PartJob]) -> list[str]:
    """The parts costliest first (:func:`_estimated_cost`), except that a part on the same
    geometry and mesh as one before it goes last: two free rails of one size share their
    hole basis's unit fields (:mod:`railcheck.model.setting_free`), so the second, taken
    after the first is done (:func:`shared_fields`), reads them from the store instead of
    solving them beside it. The first of such a group ranks by the group's cost (what
    waits for it), so that it starts early: the default check's coupler rail beside the
    bracket, not after the joint plate (a cold check 2-3 s shorter)."""
    cost = {name: _estimated_cost(job) for name, job in part_jobs.items()}
    group = {name: (repr(job.geometry), job.mesh) for name, job in part_jobs.items()}
    lead: dict = {}
    total: dict = {}
    for name in sorted(part_jobs, key=lambda n: -cost[n]):  # the group's costliest leads (stable: scene order)
        lead.setdefault(group[name], name)
        total[group[name]] = total.get(group[name], 0) + cost[name]
    first = sorted((n for n in part_jobs if lead[group[n]] == n), key=lambda n: -total[group[n]])
    repeated = sorted((n for n in part_jobs if lead[group[n]] != n), key=lambda n: -cost[n])
    return first + repeated


def _check_one(job: PartJob, solver: str, label: str, part_done=None, say=None) -> PartResult:
    """Check one part (and write its files); progress lines go to ``say`` or, in a
    worker, to the queue."""
    say = say or worker_say
    part = check_part(job, solver, lambda msg: say(f"{label}: {msg}"))
    return _with_files(part, job, label, part_done, say)


def _with_files(part: PartResult, job: PartJob, label: str, part_done, say) -> PartResult:
    """``part`` after ``part_done(name, part)`` (its files), with their time."""
    if part_done is None:
        return part
    t = time.perf_counter()
    part_done(job.name, part)
    files = time.perf_counter() - t
    say(f"{label}: files written in {files:.1f} s")
    return dataclasses.replace(part, seconds={**part.seconds, "files": files})
