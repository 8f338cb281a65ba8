"""The parts of a check, two (or ``jobs``) at a time.

Each part is independent once the loads are known: mesh, unit cases, envelope, fatigue
(:func:`railcheck.cycle.check_part`). With more than one part and more than one core they
run in worker processes (spawned, so no library state is forked), the largest first; the
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
                jobs: int | None = None) -> dict:
    """{name: PartResult} in the scene's order."""
    from .cycle import check_part

    n = len(cases)
    jobs = default_jobs(n) if jobs is None else max(1, min(jobs, n))
    label = {name: f"({i}/{n}) {name}" for i, name in enumerate(cases, 1)}
    if jobs == 1:
        return {name: check_part(scene, kin, name, geometries[name], case, material, limit, solver,
                                 lambda msg, name=name: progress.say("solve", f"{label[name]}: {msg}"))
                for name, case in cases.items()}
    return _in_workers(scene, kin, geometries, cases, material, limit, solver, progress, jobs, label)


def _in_workers(scene, kin, geometries, cases, material, limit, solver, progress, jobs, label) -> dict:
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    ctx = multiprocessing.get_context("spawn")
    queue = ctx.SimpleQueue()
    relay = threading.Thread(target=_relay, args=(queue, progress), daemon=True)
    relay.start()
    order = sorted(cases, key=lambda name: -_estimated_elements(scene, geometries[name]))
    pool = ProcessPoolExecutor(jobs, mp_context=ctx, initializer=_init_worker, initargs=(queue,))
    try:
        futures = {name: pool.submit(_check_one, scene, kin, name, geometries[name], cases[name], material,
                                     limit, solver, label[name]) for name in order}
        results = {name: futures[name].result() for name in cases}
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
    from railcheck.geometry.mesher import estimate_elements

    from .pipeline import mesh_sizes
    return estimate_elements(geo, *mesh_sizes(scene, geo.kind))


def _relay(queue, progress) -> None:
    """Print the workers' progress lines until the sentinel arrives."""
    while True:
        item = queue.get()
        if item is None:
            return
        progress.say("solve", item)


def _init_worker(queue) -> None:
    global _QUEUE
    _QUEUE = queue


def _check_one(scene, kin, name, geo, case, material, limit, solver, label):
    from .cycle import check_part
    return check_part(scene, kin, name, geo, case, material, limit, solver,
                      lambda msg: _QUEUE.put(f"{label}: {msg}"))
