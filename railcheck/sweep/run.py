"""`railcheck sweep`: every setting of the reconfigurable rig, its checks, verdict, safe
speed, motor and bearings (:mod:`railcheck.sweep.chunk` computes a chunk of settings).

The settings are chunked so that a chunk's working arrays fit ``[sweep] memory``; the
chunks run on processes forked from this one (:mod:`railcheck.parallel.forked`), serially, on
Dask (``--scheduler`` an existing cluster, or a local one where this process cannot fork),
or on this process's threads (a small sweep that cannot fork), and
their rows are written in order as they arrive (Parquet row groups or CSV), so a sweep
whose table is larger than memory completes. Per kind the run writes
``sweep-KIND.parquet`` (or ``.csv``), the maps, ``motor.png`` and ``summary.json``, all
into a staging directory that is renamed into place at the end (nothing half-written).
"""

from __future__ import annotations

import math
import os
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from contextlib import ExitStack
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from railcheck.base.errors import EXIT_FAIL, EXIT_PASS, InputError
from railcheck.check.run import say_target
from railcheck.fea.materials import MATERIALS
from railcheck.files import Staging, atomic_write_text, reserve_results_dir, to_json
from railcheck.geometry.catalogue import with_overrides
from railcheck.geometry.mesher import estimate_elements
from railcheck.model.jobs import mesh_sizes, part_geometries, refuse_huge
from railcheck.parallel import forked
from railcheck.parallel.forked import in_order_on_processes
from railcheck.parallel.shared import remove_shared, shared, write_shared
from railcheck.parallel.spawned import relayed_pool, worker_say
from railcheck.parallel.threads import blas_on_one_thread, in_order_on_threads
from railcheck.parts import PARTS, geometry_of, rail_length
from railcheck.progress import Progress
from railcheck.report.maps import Aggregate, summary_of, write_maps, write_motor_plot
from railcheck.report.sweep_html import write_sweep_report
from railcheck.sweep.chunk import (
    MOTOR_CURVE_KEY,
    SweepContext,
    checked_settings,
    evaluate_chunk,
    group_size,
    motor_curve_speeds,
)
from railcheck.sweep.grid import narrowed, rig_grid, settings
from railcheck.sweep.parts import applicable, build_part_model, dynamic_in_sweep, is_free_rail, part_is_stored
from railcheck.sweep.table import TableWriter

#: bytes of working memory per setting and crank step of a group of revolving settings
#: (kinematics, reactions at two speeds, FE coefficient histories; measured with
#: tracemalloc, rounded up)
BYTES_PER_SETTING_STEP = 3_000
#: bytes per setting and speed of a chunk's table rows and motor curve (1.4 kB measured
#: with tracemalloc at the peak of a 4,096-setting kinematic chunk, rounded up)
BYTES_PER_ROW = 4_000
#: bytes per crank step of a setting with FE held in its chunk until the chunk's FE
#: settings are screened together (every part's coefficient histories, the motor torque,
#: the screens' temporaries; 1.5 kB measured with tracemalloc at the peak of a whole-rig
#: chunk of 192 of them, rounded up)
BYTES_PER_CHECKED_STEP = 2_000
#: settings per chunk at most (a chunk is one row group of the table)
MAX_CHUNK = 4096
#: settings with FE per chunk at most. A chunk's settings that share a part's hole pair
#: are screened together (:func:`railcheck.fea.screening.groups.peak_and_fatigue`), so more of them
#: make larger groups (the rocker rail's hole pair changes every 41 settings of the grid);
#: fewer share the FE out more evenly between workers (a setting with FE costs about
#: 25 ms, the whole rig's 4,349 about two worker-minutes)
CHECKED_CHUNK = 192


@dataclass(frozen=True)
class SweepRun:
    """A finished sweep: its summary, where it went, and the directory asked for."""

    summary: dict
    target: Path
    requested: Path
    seconds: float = 0.0
    tables: dict[str, Path] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)  # s per stage: prepare (FE unit cases), chunks, report

    @property
    def exit_status(self) -> int:
        """0 when at least one setting of every kind passes, 1 otherwise."""
        kinds = self.summary["by_kind"].values()
        return EXIT_PASS if kinds and all(k["settings_passing"] > 0 for k in kinds) else EXIT_FAIL


def sweep_settings(scene) -> dict[str, dict[str, np.ndarray]]:
    """kind -> bar -> (N,) lengths (m): the rig's grid narrowed by [sweep], then its extra
    settings."""

    grid = rig_grid(scene.geometry)
    return {
        kind: settings(kind, narrowed(grid[kind], scene.sweep.ranges), scene.sweep.settings.get(kind))
        for kind in scene.sweep.kinds
    }


#: a sweep without FE is large beyond this many chunks (where this process cannot fork:
#: runs on Dask; below it this process's threads finish before a local cluster has
#: started: the whole rig's 115,456 settings at 720 steps, about 2 s on two threads, 3.7 s
#: on two Dask workers with their start-up)
KINEMATIC_DASK_CHUNKS = 64

#: settings per chunk at most with a dynamic response (each setting's safe-speed search
#: costs seconds: small chunks keep every worker busy)
DYNAMIC_CHUNK = 16


def chunk_size(scene) -> int:
    """Settings per chunk, the most whose rows (:data:`BYTES_PER_ROW`) and one group of
    revolving settings' loads (:func:`railcheck.sweep.chunk.group_size` settings,
    :data:`BYTES_PER_SETTING_STEP`) fit the working-memory budget; at most
    :data:`MAX_CHUNK`, and :data:`DYNAMIC_CHUNK` with a dynamic response."""
    steps, row = scene.sweep.steps, BYTES_PER_ROW * len(scene.sweep.speeds)
    per_group_setting = steps * BYTES_PER_SETTING_STEP
    group = group_size(steps)
    if group * (per_group_setting + row) >= scene.sweep.memory:  # the chunk is smaller than a group
        size = scene.sweep.memory // (per_group_setting + row)
    else:
        size = (scene.sweep.memory - group * per_group_setting) // row
    size = int(max(1, min(MAX_CHUNK, size)))
    return min(size, DYNAMIC_CHUNK) if dynamic_in_sweep(scene) else size


def checked_chunk_size(scene) -> int:
    """Settings with FE per chunk at most: the most whose held histories
    (:data:`BYTES_PER_CHECKED_STEP`) fit the working-memory budget beside the chunk's rows
    and one group's loads (:func:`chunk_size`); at most :data:`CHECKED_CHUNK`, and
    :data:`DYNAMIC_CHUNK` with a dynamic response."""
    steps, row = scene.sweep.steps, BYTES_PER_ROW * len(scene.sweep.speeds)
    group = min(group_size(steps), chunk_size(scene))
    left = scene.sweep.memory - group * steps * BYTES_PER_SETTING_STEP - chunk_size(scene) * row
    size = int(max(1, min(CHECKED_CHUNK, left // (steps * BYTES_PER_CHECKED_STEP))))
    return min(size, DYNAMIC_CHUNK) if dynamic_in_sweep(scene) else size


#: finished chunks held at most while an earlier one still runs (and fewer when their
#: rows would not fit the working-memory budget: :func:`held_chunks`)
HELD_CHUNKS = 256


def held_chunks(scene) -> int:
    """Finished chunks held at most while an earlier one still runs: as many as their
    rows (:data:`BYTES_PER_ROW`) fit the working-memory budget, at least 4 and at most
    :data:`HELD_CHUNKS`."""
    rows = chunk_size(scene) * BYTES_PER_ROW * len(scene.sweep.speeds)
    return int(max(4, min(HELD_CHUNKS, scene.sweep.memory // rows)))


#: the address schemes a Dask scheduler listens on
SCHEDULER_SCHEMES = ("tcp", "tls", "inproc", "ucx", "ws", "wss")


def check_scheduler(address: str) -> None:
    """Refuse, naming ``--scheduler``, an address that is not ``scheme://host:port``."""
    scheme, sep, rest = address.partition("://")
    host, colon, port = rest.rpartition(":")
    if not sep or scheme not in SCHEDULER_SCHEMES or not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise InputError(
            "--scheduler",
            f"{address!r} is not a Dask scheduler address: scheme://host:port, the scheme one of "
            f"{', '.join(SCHEDULER_SCHEMES)} (e.g. tcp://127.0.0.1:8786)",
        )


def sweep_effects(scene) -> tuple[str, ...]:
    """The effects a sweep simulates: inertia when listed and some [sweep] speed is not
    zero (a sweep's speeds are its own, not [mechanism]'s), gravity when listed."""
    effects = scene.check.effects
    inertia = "inertia" in effects and any(s > 0 for s in scene.sweep.speeds)
    return (("inertia",) if inertia else ()) + (("gravity",) if "gravity" in effects else ())


def validate(scene) -> None:
    if scene.check is not None and not sweep_effects(scene):
        raise InputError(
            "check.effects",
            'a sweep needs a load to compare settings by: list "inertia" (with a speed) or "gravity"',
        )
    if scene.formulation == "seed-2013" and "slider-crank" in scene.sweep.kinds:
        raise InputError(
            "sweep.kind",
            'dynamics.formulation = "seed-2013" exists only for the four-bar: sweep kind = "four-bar", or use newton-euler',
        )
    grid = rig_grid(scene.geometry)
    for kind in scene.sweep.kinds:
        narrowed(grid[kind], scene.sweep.ranges)  # a range with no settable length: refused, naming it


def prepare_models(scene, by_kind: dict, progress, jobs: int = 1) -> dict[str, dict]:
    """kind -> part -> PartModel: each checked part meshed, factorised and solved once,
    in ``jobs`` processes (:func:`_build_in_workers`) when some part must be meshed or
    solved, else on ``jobs`` threads of this one (:func:`_build_on_threads`: read from the
    cache and the store, where the processes' start-up and the models pickled back cost
    more than they share out; the whole rig's parts: 4.6-5.2 s on two threads, 8.2-10.3 s
    on one, 12.1 s in two processes)."""
    if scene.check is None:
        return {kind: {} for kind in by_kind}

    material = MATERIALS[scene.check.material]
    limit = scene.check.limit or material.fatigue_limit
    refuse_huge(scene, part_geometries(scene))
    tasks = part_tasks(scene, by_kind)
    args = (scene, material, limit)
    say = lambda msg: progress.say("solve", msg)  # noqa: E731
    if jobs > 1 and len(tasks) > 1:
        if all(part_is_stored(scene, t.name, t.lengths, material, t.kinds[0]) for t in tasks):
            built = _build_on_threads(tasks, args, say, jobs)
        else:
            built = _build_in_workers(tasks, args, progress, jobs)
    else:
        built = [_build_task(task, *args, say=say) for task in tasks]
    models: dict[str, dict] = {kind: {} for kind in by_kind}
    for task, model in zip(tasks, built):
        for k in task.kinds:
            models[k][task.name] = model
    return models


@dataclass(frozen=True)
class PartTask:
    """One part model to build: the part, the linkage kinds it serves, its bar's lengths
    (m) over their settings, its progress label, and ``after``: the index of an earlier
    task whose unit fields it reuses from the store (the same part in another kind, or a
    rail of the same kind with the same lengths: the coupler's and the rocker's), built
    only once that one is done, or None."""

    name: str
    kinds: tuple[str, ...]
    lengths: np.ndarray
    label: str
    after: int | None


def part_tasks(scene, by_kind: dict) -> list[PartTask]:
    """The part models a sweep needs, in the order they are reported."""
    names = [n for n in scene.check.parts if any(applicable(scene, n, k) for k in by_kind)]
    tasks: list[PartTask] = []
    reuses: dict = {}
    for i, name in enumerate(names, 1):
        bar = PARTS[name].bar
        for kinds in kind_groups(scene, name, [k for k in by_kind if applicable(scene, name, k)]):
            lengths = np.concatenate([by_kind[k][bar] for k in kinds if bar in by_kind[k]]) if bar else np.zeros(0)
            label = f"({i}/{len(names)}) {name}" + (f" ({kinds[0]})" if len(kinds) < len(by_kind) > 1 else "")
            keys = (name, (PARTS[name].kind, bar and rail_length(bar), np.unique(np.round(lengths * 1e6)).tobytes()))
            after = next((reuses[key] for key in keys if key in reuses), None)
            for key in keys:
                reuses.setdefault(key, len(tasks))
            tasks.append(PartTask(name, tuple(kinds), lengths, label, after))
    return tasks


def _build_task(task: PartTask, scene, material, limit: float, say=None):
    """Build one task's PartModel (progress lines to ``say``, or in a worker to the main
    process), with a summary line."""
    say = say or worker_say
    t = time.perf_counter()
    model = build_part_model(
        scene, task.name, task.lengths, material, limit, lambda msg: say(f"{task.label}: {msg}"), linkage=task.kinds[0]
    )
    say(
        f"{task.label}: {model.dofs} DOFs, "
        f"{sum(s.stress.shape[2] for s in model.screens.values())} unit columns"
        f"{_mode_note(model)} "
        f"({time.perf_counter() - t:.1f} s)"
    )
    return model


def _build_on_threads(tasks: list[PartTask], args: tuple, say, jobs: int) -> list:
    """The tasks' models built on ``jobs`` threads of this process, every part's mesh
    cached and unit fields stored: reading the store and gathering the screens are numpy
    copies that release the GIL, and nothing is pickled back (BLAS on one thread each
    meanwhile). In the tasks' order."""
    with blas_on_one_thread(), ThreadPoolExecutor(jobs, thread_name_prefix="railcheck-parts") as pool:
        return list(pool.map(lambda task: _build_task(task, *args, say=say), tasks))


def _build_in_workers(tasks: list[PartTask], args: tuple, progress, jobs: int) -> list:
    """The tasks' models built in ``jobs`` spawned processes (meshing and assembly are
    single-threaded: two parts at once nearly halve a cold start). A free worker takes a
    task whose reused fields are done (cheap: read from the store) before any other, then
    the largest part by its estimated elements; the solver keeps a serial run's thread
    count."""
    scene = args[0]
    size = [
        estimate_elements(g, *mesh_sizes(scene.mesh, g.kind)) for g in (geometry_of(t.name, scene.geometry) for t in tasks)
    ]
    built: list = [None] * len(tasks)
    pending = sorted(range(len(tasks)), key=lambda i: -size[i])
    with relayed_pool(jobs, progress) as pool:
        running: dict = {}
        while pending or running:
            ready = [i for i in pending if tasks[i].after is None or built[tasks[i].after] is not None]
            for i in sorted(ready, key=lambda i: tasks[i].after is None)[: jobs - len(running)]:
                running[pool.submit(_build_task, tasks[i], *args)] = i
                pending.remove(i)
            done, _ = wait(running, return_when=FIRST_COMPLETED)
            for future in done:
                built[running.pop(future)] = future.result()
    return built


def kind_groups(scene, name: str, kinds: list[str]) -> list[list[str]]:
    """The linkage kinds that can share one model of a part: all of them, unless the part
    carries the joints' point masses, which differ between the four-bar and the
    slider-crank (a free rail's joint loads, any rail's modes): then one per kind (the
    unit fields they share come from the store, so the second costs the screening)."""
    carries = name not in scene.check.loads and PARTS[name].bar is not None
    if carries and (is_free_rail(scene, name) or dynamic_in_sweep(scene)):
        return [[k] for k in kinds]
    return [kinds] if kinds else []


def _mode_note(model) -> str:
    """', the lowest mode H Hz (P hole pairs)' with a dynamic response, else ''."""
    if model.dynamic is None:
        return ""
    lowest = min(float(m.hz[0]) for m in model.dynamic.values())
    return f", lowest mode {lowest:.3g} Hz ({len(model.dynamic)} mode set(s))"


def run_sweep(
    scene,
    out: str | None = None,
    force: bool = False,
    scheduler: str | None = None,
    workers: int | None = None,
    serial: bool = False,
    progress=None,
    dask: bool | None = None,
) -> SweepRun:
    """Run the sweep the scene asks for and write its results directory. Dask runs the
    chunks when ``scheduler`` is given, or on a local cluster when the sweep is large and
    this process cannot fork (``dask`` True/False forces it either way); else ``workers``
    processes forked from this one, or threads of this process where it cannot fork
    (default one per core; ``serial``: this process alone, no Dask)."""

    validate(scene)
    if scheduler is not None:
        check_scheduler(scheduler)
    progress = progress or Progress(quiet=True)
    t0 = time.perf_counter()
    requested = Path(out or _default_dir(scene))
    try:
        target, replaces = reserve_results_dir(requested, force)
        staging = Staging(target, replaces)
    except OSError as exc:
        raise InputError("output.dir", f"cannot write results at {requested}: {exc.strerror or exc}") from None
    say_target(progress, requested, target)
    try:
        summary, tables, timings = _run_into(scene, staging.path, scheduler, workers, serial, progress, dask)
        staging.commit()
    except BaseException:
        staging.abandon()
        raise
    tables = {kind: target / Path(p).name for kind, p in tables.items()}
    return SweepRun(summary, target, requested, time.perf_counter() - t0, tables, timings)


def _default_dir(scene) -> str:
    return "sweep" if scene.output.dir == "results" else f"{scene.output.dir}-sweep"


def _run_into(scene, directory: Path, scheduler, workers, serial, progress, dask) -> tuple[dict, dict, dict]:

    clock = [time.perf_counter()]
    workers = local_workers(workers, scheduler, progress)
    by_kind = sweep_settings(scene)
    progress.say(
        "sweep",
        ", ".join(f"{k}: {v['crank'].size} settings" for k, v in by_kind.items())
        + f" x {len(scene.sweep.speeds)} speed(s), {scene.sweep.steps} steps",
    )
    checked = {kind: _checked(scene, kind, lengths) for kind, lengths in by_kind.items()}
    total, total_checked = sum(c.size for c in checked.values()), sum(int(c.sum()) for c in checked.values())
    large = total > KINEMATIC_DASK_CHUNKS * chunk_size(scene) or total_checked > 4 * checked_chunk_size(scene)
    forks = forked.available() and forked.alone()
    if forked.available() and not forks and not serial:
        others = ", ".join(t.name for t in threading.enumerate() if t is not threading.current_thread())
        progress.say(
            "sweep", f"this process runs other threads ({others}): its workers are not forked (a fork could hang them)"
        )
    # a local cluster only where this process cannot fork its workers (they share its memory)
    use_dask = (scheduler is not None or (large and not forks)) if dask is None else dask
    # the parts in two processes when the settings run on Dask, or are many, and in parallel too
    models = prepare_models(
        scene, by_kind, progress, min(2, os.cpu_count() or 1) if (use_dask or large) and not serial else 1
    )
    clock.append(time.perf_counter())
    kinds = list(by_kind)
    tables = {kind: directory / f"sweep-{kind}.{scene.sweep.format}" for kind in kinds}
    aggregates = {
        kind: Aggregate(scene, kind, by_kind[kind], motor_curve_speeds(scene.sweep.speeds), models[kind]) for kind in kinds
    }
    jobs = [(lambda kind=kind: _context(scene, kind, models[kind]), by_kind[kind], kind, checked[kind]) for kind in kinds]
    threads = 1 if serial else workers or os.cpu_count() or 1
    with (
        _Executor(scheduler, workers, use_dask and not serial, progress, directory, threads, forks) as executor,
        ExitStack() as stack,
    ):
        writers = {kind: stack.enter_context(TableWriter(tables[kind], scene.sweep.format)) for kind in kinds}
        for j, columns in executor.map_jobs(jobs, chunk_size(scene), checked_chunk_size(scene), held_chunks(scene)):
            curve = columns.pop(MOTOR_CURVE_KEY)
            writers[kinds[j]].write(columns)
            aggregates[kinds[j]].add(columns, curve)
    clock.append(time.perf_counter())
    summary = summary_of(scene, aggregates, tables, models)

    atomic_write_text(directory / "summary.json", to_json(summary) + "\n")
    write_maps(aggregates, directory)
    write_motor_plot(aggregates, directory / "motor.png")
    write_sweep_report(directory / "report.html", summary, tables, directory)
    clock.append(time.perf_counter())
    timings = dict(zip(("prepare", "chunks", "report"), np.diff(clock)))
    atomic_write_text(directory / "timings.json", to_json(timings) + "\n")
    return summary, tables, timings


def local_workers(workers: int | None, scheduler, progress) -> int | None:
    """``--workers`` for this machine: at most one local Dask worker or thread per core
    (more only share the cores: 1,000 threads took the whole rig's kinematics from 2.5 s to
    102 s), said when it is cut; unchanged for an external scheduler."""
    cores = os.cpu_count() or 1
    if scheduler is None and workers is not None and workers > cores:
        progress.say("sweep", f"--workers {workers}: this machine has {cores} cores; using {cores}")
        return cores
    return workers


def _checked(scene, kind: str, lengths: dict) -> np.ndarray:
    """(N,) True where the sweep checks a setting's parts by FE
    (:func:`railcheck.sweep.chunk.checked_settings`; none without parts to check)."""
    if scene.check is None:
        return np.zeros(lengths["crank"].size, dtype=bool)
    return checked_settings(_context(scene, kind, {}), lengths)


def _context(scene, kind: str, models: dict):

    density = MATERIALS[scene.check.material].density if scene.check else 0.0
    return SweepContext(
        scene, kind, tuple(scene.sweep.speeds), scene.sweep.steps, models, density, with_overrides(scene.geometry)[0]
    )


#: glibc's heap settings of the local cluster's workers. Dask starts its workers with
#: MALLOC_TRIM_THRESHOLD_ = 64 kB (memory back to the system as soon as it is freed), which
#: makes every settings x steps temporary fault its pages in afresh: the kinematics-only sweep
#: of the whole rig ran at half speed on the workers (a pass of the four-bar grid: 3.2-3.9 s
#: wall on two workers, 1.5-1.6 s with a trim threshold of 128 MiB). Any explicit value turns
#: glibc's adaptive thresholds off, so both are set: a worker keeps up to 256 MiB of freed
#: heap and maps only blocks above 32 MiB (glibc's largest threshold), so a part's stresses
#: per basis coordinate (up to 26 MB, one per group of settings) reuse the heap: with 4 MiB
#: the whole rig's workers spent 101 s of 575 core-seconds in the kernel, and the captured
#: near-default histories ran 2.36 s against 2.62 s (sys 0.35 against 1.37 s).
WORKER_MALLOC = {"MALLOC_TRIM_THRESHOLD_": 256 << 20, "MALLOC_MMAP_THRESHOLD_": 32 << 20}
#: Dask settings of the local cluster's workers. Their statistical profiler (for a dashboard
#: this cluster does not start) samples the computing thread's stack every 10 ms, holding the
#: GIL that the screens' many small numpy calls need: the whole rig's settings took 73.1 and
#: 86.5 s without it against 80.0 and 90.6 s with it (two pairs, alternated).
WORKER_CONFIG = {"distributed.worker.profile.enabled": False}


def _quiet_cluster_exit() -> None:
    """Replace distributed's exit hook that closes the local clusters still open by one
    that closes them quietly: a run interrupted while its cluster starts or stops (Ctrl-C)
    ends with ``railcheck: interrupted``, not with the hook's traceback (an assertion on a
    worker still starting); the workers end with this process either way."""
    import atexit
    import contextlib

    from distributed.deploy import spec

    def close_quietly():
        with contextlib.suppress(Exception):
            spec.close_clusters()

    if getattr(spec.close_clusters, "_railcheck_quiet", None) is None:
        atexit.unregister(spec.close_clusters)
        atexit.register(close_quietly)
        spec.close_clusters._railcheck_quiet = close_quietly  # type: ignore[attr-defined]


class _Executor:
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
    ):
        self.progress = progress
        self.use_dask = use_dask
        self.threads = threads
        self.forks = forks
        self.scheduler, self.workers = scheduler, workers
        self.scratch = scratch
        self.client = self.cluster = None

    def __enter__(self):
        if self.use_dask:
            self._start()
        return self

    def _start(self):
        import logging
        import os

        from dask.distributed import Client, LocalCluster

        _quiet_cluster_exit()
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

    def map_jobs(self, jobs: list, size: int, checked_size: int, held: int = HELD_CHUNKS):
        """Yield ``(job index, columns)`` of every chunk of every job ``(make_context,
        lengths, kind, checked)`` in order, job by job, with a progress line every few
        seconds (``make_context()`` builds the job's context when its first chunk is due;
        chunks as :func:`_chunks`; on Dask at most ``held`` finished chunks wait for an
        earlier one)."""
        if self.use_dask:
            yield from self._dask_jobs(jobs, size, checked_size, held)
        elif self.threads > 1:
            yield from self._local_jobs(jobs, size, checked_size, held)
        else:
            for j, (make_context, lengths, kind, checked) in enumerate(jobs):
                ctx, total = make_context(), lengths["crank"].size
                meter = _Meter(self.progress, kind, total)
                for ids in _chunks(checked, size, checked_size):
                    cols = evaluate_chunk(ctx, {b: v[ids] for b, v in lengths.items()}, ids)
                    meter.done(ids.size)
                    yield j, cols

    def _local_jobs(self, jobs: list, size: int, checked_size: int, held: int):
        """:meth:`map_jobs` on processes forked from this one when the executor
        ``forks`` (:mod:`railcheck.parallel.forked`), else on this process's threads
        (:mod:`railcheck.parallel.threads`): the same chunks as on as many Dask workers, the
        same columns."""
        how = "processes forked from this one" if self.forks else "threads in this process"
        self.progress.say("sweep", f"{self.threads} {how}")
        tasks = _shared_out(jobs, size, checked_size, self.threads)
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
                return evaluate_chunk(context, {b: v[ids] for b, v in lengths.items()}, ids)

            meter = _Meter(self.progress, kind, lengths["crank"].size)
            for ids, cols in zip(mine, in_order_on_processes(run, mine, self.threads, max(held, self.threads))):
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
            return evaluate_chunk(contexts[j], {b: v[ids] for b, v in jobs[j][1].items()}, ids)

        meters: dict[int, _Meter] = {}
        for (j, ids), cols in zip(tasks, in_order_on_threads(run, tasks, self.threads, max(held, self.threads))):
            if j not in meters:
                meters[j] = _Meter(self.progress, jobs[j][2], jobs[j][1]["crank"].size, started[j])
            meters[j].done(ids.size)
            yield j, cols

    def _dask_jobs(self, jobs: list, size: int, checked_size: int, held: int):
        from dask.distributed import wait as wait_for

        workers = max(1, len(self.client.scheduler_info()["workers"]))
        tasks = _shared_out(jobs, size, checked_size, workers)
        meters: dict[int, _Meter] = {}
        contexts: dict[int, object] = {}
        running: dict = {}  # future -> task index
        finished: dict[int, dict] = {}
        submitted = done = 0
        try:
            while done < len(tasks):
                while submitted < len(tasks) and len(running) < 2 * workers and len(finished) < held:
                    j, ids = tasks[submitted]
                    if j not in contexts:
                        contexts[j] = self._context_ref(j, jobs[j][0]())
                        meters[j] = _Meter(self.progress, jobs[j][2], jobs[j][1]["crank"].size)
                    lengths = {b: v[ids] for b, v in jobs[j][1].items()}
                    running[self.client.submit(_evaluate, contexts[j], lengths, ids, pure=False)] = submitted
                    submitted += 1
                if done not in finished:
                    if not running:  # cannot happen: the next chunk is either finished or running
                        raise RuntimeError(f"sweep chunk {done} was neither finished nor running")
                    for future in wait_for(list(running), return_when="FIRST_COMPLETED").done:
                        finished[running.pop(future)] = future.result()
                    continue
                j, ids = tasks[done]
                meters[j].done(ids.size)
                yield j, finished.pop(done)
                done += 1
                if done == len(tasks) or tasks[done][0] != j:
                    self._release(contexts.pop(j))
        finally:
            for future in running:
                future.cancel()
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


def _shared_out(jobs: list, size: int, checked_size: int, workers: int) -> list[tuple[int, np.ndarray]]:
    """(job index, settings' indices) of every chunk of every job, in order, for
    ``workers`` running at once: each kind in at least two chunks per worker, so that none
    runs alone (chunks as :func:`_chunks`)."""
    share = lambda n, most: max(1, min(most, -(-n // (2 * workers))))  # noqa: E731
    return [
        (j, ids)
        for j, (_, lengths, _, checked) in enumerate(jobs)
        for ids in _chunks(checked, share(checked.size, size), share(int(checked.sum()), checked_size))
    ]


def _chunks(checked: np.ndarray, size: int, checked_size: int):
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


def _evaluate(context, lengths: dict, ids: np.ndarray) -> dict:
    """:func:`railcheck.sweep.chunk.evaluate_chunk` in a worker, its context a shared
    file's path or the context itself."""
    return evaluate_chunk(shared(context) if isinstance(context, str) else context, lengths, ids)


class _Meter:
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
            bar = "#" * int(30 * self.count / max(self.total, 1))
            self.progress.say(
                "sweep", f"{self.kind:<12} [{bar:<30}] {self.count}/{self.total} settings, {rate:,.0f} settings/s"
            )
