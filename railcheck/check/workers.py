"""The parts of a check, two (or ``jobs``) at a time.

Each part is independent once the loads are known: mesh, unit cases, envelope, fatigue
(:func:`railcheck.check.cycle.check_part`). With more than one part and more than one core the
largest part (by its estimated element count) is checked in this process while the others
run in ``jobs - 1`` worker processes (spawned, so no library state is forked); the
workers' progress lines reach the console through a queue as they happen, and each part's
result comes back whole. Errors raised in a worker are raised here unchanged.
``jobs=1`` (``railcheck check --jobs 1``) runs them in this process, one after another;
the results are the same.
"""

from __future__ import annotations

import os
import threading

_QUEUE = None     # the worker's progress queue (set by _init_worker)


def default_jobs(parts: int) -> int:
    """Worker processes for ``parts`` parts: one per core, at most two (each part's solve
    already uses every core while it factorises), never more than the parts."""
    return max(1, min(parts, os.cpu_count() or 1, 2))


def check_parts(scene, kin, geometries: dict, cases: dict, material, limit: float, solver: str, progress,
                jobs: int | None = None, part_done=None) -> dict:
    """{name: PartResult} in the scene's order; ``part_done(name, part)`` runs as each
    part finishes, in the process that checked it."""
    n = len(cases)
    jobs = default_jobs(n) if jobs is None else max(1, min(jobs, n))
    label = {name: f"({i}/{n}) {name}" for i, name in enumerate(cases, 1)}
    if jobs == 1:
        return {name: _check_one(scene, kin, name, geometries[name], case, material, limit, solver, label[name],
                                 part_done, lambda msg: progress.say("solve", msg))
                for name, case in cases.items()}
    return _in_workers(scene, kin, geometries, cases, material, limit, solver, progress, jobs, label, part_done)


def _in_workers(scene, kin, geometries, cases, material, limit, solver, progress, jobs, label, part_done) -> dict:
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    ctx = multiprocessing.get_context("spawn")
    queue = ctx.SimpleQueue()
    relay = threading.Thread(target=_relay, args=(queue, progress), daemon=True)
    relay.start()
    order = sorted(cases, key=lambda name: -_estimated_elements(scene, geometries[name]))
    largest, rest = order[0], order[1:]
    pool = ProcessPoolExecutor(jobs - 1, mp_context=ctx, initializer=_init_worker, initargs=(queue,))
    try:
        futures = {name: pool.submit(_check_one, scene, kin, name, geometries[name], cases[name], material,
                                     limit, solver, label[name], part_done) for name in rest}
        here = _check_one(scene, kin, largest, geometries[largest], cases[largest], material, limit, solver,
                          label[largest], part_done, lambda msg: progress.say("solve", msg))
        results = {name: here if name == largest else futures[name].result() for name in cases}
    except BaseException:            # an error, Ctrl-C or SIGTERM: stop the other parts now
        for process in list(getattr(pool, "_processes", {}).values()):
            process.terminate()
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    finally:
        queue.put(None)
        relay.join(timeout=5)
    pool.shutdown()
    return results


def _estimated_elements(scene, geo) -> int:
    from railcheck.check.pipeline import mesh_sizes
    from railcheck.geometry.mesher import estimate_elements
    return estimate_elements(geo, *mesh_sizes(scene, geo.kind))


def _relay(queue, progress) -> None:
    """Print the workers' progress lines until the sentinel arrives."""
    while True:
        item = queue.get()
        if item is None:
            return
        progress.say("solve", item)


def _init_worker(queue) -> None:
    """The worker's progress queue. Thread counts stay those of a serial run (a single
    MKL thread here would be faster, but PARDISO's rounding depends on the thread count
    and ``--jobs 1`` must give the same digits)."""
    global _QUEUE
    _QUEUE = queue


def _check_one(scene, kin, name, geo, case, material, limit, solver, label, part_done=None, say=None):
    """Check one part (and write its files); progress lines go to ``say`` or, in a
    worker, to the queue."""
    import time

    from railcheck.check.cycle import check_part

    say = say or _QUEUE.put
    part = check_part(scene, kin, name, geo, case, material, limit, solver, lambda msg: say(f"{label}: {msg}"))
    if part_done is not None:
        t = time.perf_counter()
        part_done(name, part)
        part.cycle.seconds["files"] = time.perf_counter() - t
        say(f"{label}: files written in {part.cycle.seconds['files']:.1f} s")
    return part
