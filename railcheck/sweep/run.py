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

import gc
import os
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from contextlib import ExitStack
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from railcheck.base.errors import EXIT_FAIL, EXIT_PASS, InputError
from railcheck.base.machine import trim_heap
from railcheck.check.run import say_target
from railcheck.fea.materials import MATERIALS
from railcheck.fea.store import reads_shared
from railcheck.files import Staging, atomic_write_text, reserve_results_dir, results_dir, to_json
from railcheck.geometry.catalogue import with_overrides
from railcheck.geometry.mesher import estimate_elements
from railcheck.model.inputs import PartsInput
from railcheck.model.jobs import mesh_sizes, part_geometries, refuse_unresolvable_meshes
from railcheck.parallel import forked
from railcheck.parallel.executor import ChunkExecutor
from railcheck.parallel.threads import blas_on_one_thread
from railcheck.parts import PARTS, geometry_of, rail_length
from railcheck.progress import Progress
from railcheck.report.card import write_card
from railcheck.report.maps import write_maps, write_motor_plot
from railcheck.report.rig_page import write_rig_page
from railcheck.report.sweep_html import write_sweep_report
from railcheck.scene import Scene
from railcheck.specs import CheckSpec
from railcheck.sweep.aggregate import Aggregate, summary_of
from railcheck.sweep.chunk import (
    MOTOR_CURVE_KEY,
    SweepContext,
    checked_settings,
    evaluate_chunk,
    group_size,
    motor_curve_speeds,
)
from railcheck.sweep.exact import ExactPass
from railcheck.sweep.grid import narrowed, rig_grid, settings
from railcheck.sweep.inputs import SweepInput, sweep_input
from railcheck.sweep.parts import (
    applicable,
    build_part_model,
    is_free_rail,
    part_is_stored,
    sharing_screens,
)
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


def sweep_settings(inputs: SweepInput) -> dict[str, dict[str, np.ndarray]]:
    """kind -> bar -> (N,) lengths (m): the rig's grid narrowed by [sweep], then its extra
    settings."""

    grid, spec = rig_grid(inputs.geometry), inputs.sweep
    return {kind: settings(kind, narrowed(grid[kind], spec.ranges), spec.settings.get(kind)) for kind in spec.kinds}


#: a sweep without FE is large beyond this many chunks (where this process cannot fork:
#: runs on Dask; below it this process's threads finish before a local cluster has
#: started: the whole rig's 115,456 settings at 720 steps, about 2 s on two threads, 3.7 s
#: on two Dask workers with their start-up)
KINEMATIC_DASK_CHUNKS = 64


#: settings per chunk at most with a dynamic response (each setting's safe-speed search
#: costs seconds: small chunks keep every worker busy)
DYNAMIC_CHUNK = 16


def chunk_size(inputs: SweepInput) -> int:
    """Settings per chunk, the most whose rows (:data:`BYTES_PER_ROW`) and one group of
    revolving settings' loads (:func:`railcheck.sweep.chunk.group_size` settings,
    :data:`BYTES_PER_SETTING_STEP`) fit the working-memory budget; at most
    :data:`MAX_CHUNK`, and :data:`DYNAMIC_CHUNK` with a dynamic response."""
    steps, row = inputs.sweep.steps, BYTES_PER_ROW * len(inputs.sweep.speeds)
    per_group_setting = steps * BYTES_PER_SETTING_STEP
    group = group_size(steps)
    if group * (per_group_setting + row) >= inputs.sweep.memory:  # the chunk is smaller than a group
        size = inputs.sweep.memory // (per_group_setting + row)
    else:
        size = (inputs.sweep.memory - group * per_group_setting) // row
    size = int(max(1, min(MAX_CHUNK, size)))
    return min(size, DYNAMIC_CHUNK) if inputs.dynamic_response else size


def checked_chunk_size(inputs: SweepInput) -> int:
    """Settings with FE per chunk at most: the most whose held histories
    (:data:`BYTES_PER_CHECKED_STEP`) fit the working-memory budget beside the chunk's rows
    and one group's loads (:func:`chunk_size`); at most :data:`CHECKED_CHUNK`, and
    :data:`DYNAMIC_CHUNK` with a dynamic response."""
    steps, row = inputs.sweep.steps, BYTES_PER_ROW * len(inputs.sweep.speeds)
    group = min(group_size(steps), chunk_size(inputs))
    left = inputs.sweep.memory - group * steps * BYTES_PER_SETTING_STEP - chunk_size(inputs) * row
    size = int(max(1, min(CHECKED_CHUNK, left // (steps * BYTES_PER_CHECKED_STEP))))
    return min(size, DYNAMIC_CHUNK) if inputs.dynamic_response else size


#: finished chunks held at most while an earlier one still runs (and fewer when their
#: rows would not fit the working-memory budget: :func:`held_chunks`)
HELD_CHUNKS = 256


def held_chunks(inputs: SweepInput) -> int:
    """Finished chunks held at most while an earlier one still runs: as many as their
    rows (:data:`BYTES_PER_ROW`) fit the working-memory budget, at least 4 and at most
    :data:`HELD_CHUNKS`."""
    rows = chunk_size(inputs) * BYTES_PER_ROW * len(inputs.sweep.speeds)
    return int(max(4, min(HELD_CHUNKS, inputs.sweep.memory // rows)))


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


def validate(inputs: SweepInput) -> None:
    """Refuse, naming the field, a sweep with no load to compare settings by, the seed's
    2013 formulation on a slider-crank, or a range with no settable length."""
    if inputs.check is not None and not inputs.effects:
        raise InputError(
            "check.effects",
            'a sweep needs a load to compare settings by: list "inertia" (with a speed) or "gravity"',
        )
    if inputs.formulation == "seed-2013" and "slider-crank" in inputs.sweep.kinds:
        raise InputError(
            "sweep.kind",
            'dynamics.formulation = "seed-2013" exists only for the four-bar: sweep kind = "four-bar", or use newton-euler',
        )
    grid = rig_grid(inputs.geometry)
    for kind in inputs.sweep.kinds:
        narrowed(grid[kind], inputs.sweep.ranges)  # a range with no settable length: refused, naming it


def prepare_models(inputs: SweepInput, by_kind: dict, progress, jobs: int = 1) -> dict[str, dict]:
    """kind -> part -> PartModel: each checked part meshed, factorised and solved once.
    When some part must be meshed or solved they are built in this process one at a time
    (:func:`build_one_at_a_time`: a little slower than two at once in worker processes,
    with two thirds of their peak memory); when every part's mesh is cached and unit fields
    stored they are read on ``jobs`` threads of this one (:func:`build_on_threads`, about
    twice as fast on two threads as on one; measured: docs/changelog.md, "The measurements
    behind tuned constants"). A part's models for two linkage kinds hold their equal screens once
    (:func:`railcheck.sweep.parts.sharing_screens`)."""
    if inputs.parts is None:
        return {kind: {} for kind in by_kind}

    check = inputs.parts.check
    material = MATERIALS[check.material]
    limit = check.limit or material.fatigue_limit
    refuse_unresolvable_meshes(inputs.parts, part_geometries(inputs.parts))
    tasks = part_tasks(inputs, by_kind)
    args = (inputs, material, limit)
    say = lambda msg: progress.say("solve", msg)  # noqa: E731
    if jobs > 1 and len(tasks) > 1 and all(part_is_stored(inputs, t.name, t.lengths, material, t.kinds[0]) for t in tasks):
        built = build_on_threads(numbered(tasks, range(len(tasks))), args, say, jobs)
        built = [sharing_screens(model, built[:i]) for i, model in enumerate(built)]
    else:
        built = build_one_at_a_time(tasks, args, say)
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


def part_tasks(inputs: SweepInput, by_kind: dict) -> list[PartTask]:
    """The part models a sweep needs (none without [check]), in the order they are reported."""
    if inputs.check is None:
        return []
    check, responding = inputs.check, inputs.dynamic_response
    names = [n for n in check.parts if any(applicable(check, n, k) for k in by_kind)]
    tasks: list[PartTask] = []
    reuses: dict = {}
    for name in names:
        bar = PARTS[name].bar
        for kinds in kind_groups(check, responding, name, [k for k in by_kind if applicable(check, name, k)]):
            lengths = np.concatenate([by_kind[k][bar] for k in kinds if bar in by_kind[k]]) if bar else np.zeros(0)
            label = name + (f" ({kinds[0]})" if len(kinds) < len(by_kind) > 1 else "")
            keys = (name, (PARTS[name].kind, bar and rail_length(bar), np.unique(np.round(lengths * 1e6)).tobytes()))
            after = next((reuses[key] for key in keys if key in reuses), None)
            for key in keys:
                reuses.setdefault(key, len(tasks))
            tasks.append(PartTask(name, tuple(kinds), lengths, label, after))
    return tasks


def numbered(tasks: list[PartTask], order) -> list[PartTask]:
    """``tasks`` with their progress labels numbered "(k/n)" in the ``order`` (indices)
    they start, so the lines count up."""
    rank = {i: k for k, i in enumerate(order, 1)}
    return [replace(t, label=f"({rank[i]}/{len(tasks)}) {t.label}") for i, t in enumerate(tasks)]


def build_task(task: PartTask, inputs: SweepInput, material, limit: float, say):
    """Build one task's PartModel (progress lines to ``say``), with a summary line."""
    t = time.perf_counter()
    model = build_part_model(
        inputs, task.name, task.lengths, material, limit, lambda msg: say(f"{task.label}: {msg}"), linkage=task.kinds[0]
    )
    say(
        f"{task.label}: {model.dofs} DOFs, "
        f"{sum(s.stress.shape[2] for s in model.screens.values())} unit columns"
        f"{_mode_note(model)} "
        f"({time.perf_counter() - t:.1f} s)"
    )
    return model


def build_on_threads(tasks: list[PartTask], args: tuple, say, jobs: int) -> list:
    """The tasks' models built on ``jobs`` threads of this process, every part's mesh
    cached and unit fields stored: reading the store and gathering the screens are numpy
    copies that release the GIL, and nothing is pickled back (BLAS on one thread each
    meanwhile). In the tasks' order."""
    with blas_on_one_thread(), reads_shared(), ThreadPoolExecutor(jobs, thread_name_prefix="railcheck-parts") as pool:
        inputs, material, limit = args
        return list(pool.map(lambda task: build_task(task, inputs, material, limit, say=say), tasks))


def build_one_at_a_time(tasks: list[PartTask], args: tuple, say) -> list:
    """The tasks' models built in this process one after another in :func:`build_order`,
    the heap each build freed handed back to the system before the next
    (:func:`railcheck.base.machine.trim_heap`), each model's screens shared with the
    equal ones built before it. In the tasks' order.

    One at a time, because a build's memory peaks while PARDISO factorises (the bracket:
    2.45 GB alone, 1.0 GiB of it the factor) and two at once, with the models already
    built, passed 4 GB on the whole rig; PARDISO uses both cores meanwhile, so two
    builds at once saved only their single-threaded assembly and stress recovery
    (:func:`prepare_models`)."""
    inputs, material, limit = args
    built: list = [None] * len(tasks)
    order = build_order(tasks, inputs.parts)
    tasks = numbered(tasks, order)
    for i in order:
        model = build_task(tasks[i], inputs, material, limit, say=say)
        built[i] = sharing_screens(model, [b for b in built if b is not None])
        del model
        gc.collect()
        trim_heap()
    return built


def build_order(tasks: list[PartTask], parts: PartsInput) -> list[int]:
    """The indices of ``tasks`` in the order :func:`build_one_at_a_time` builds them: by
    the model each leaves in memory while the later ones are built, the smallest first,
    so the largest builds run beside the fewest models: the parts without a bar (one
    screen each) before the rails (a screen per hole pair), each by decreasing estimated
    elements (the largest solve's peak beside the least); a task that reuses another's
    stored fields (``after``) right after it."""
    size = [
        estimate_elements(g, *mesh_sizes(parts.mesh, g.kind)) for g in (geometry_of(t.name, parts.geometry) for t in tasks)
    ]
    ranked = sorted(range(len(tasks)), key=lambda i: (PARTS[tasks[i].name].bar is not None, -size[i], i))
    order: list[int] = []

    def place(i: int) -> None:
        order.append(i)
        for j in ranked:
            if tasks[j].after == i:
                place(j)

    for i in ranked:
        if tasks[i].after is None:
            place(i)
    return order


def kind_groups(check: CheckSpec, responding: bool, name: str, kinds: list[str]) -> list[list[str]]:
    """The linkage kinds that can share one model of a part: all of them, unless the part
    carries the joints' point masses, which differ between the four-bar and the
    slider-crank (a free rail's joint loads, any rail's modes): then one per kind (the
    unit fields they share come from the store, so the second costs the screening)."""
    carries = name not in check.loads and PARTS[name].bar is not None
    if carries and (is_free_rail(check, name) or responding):
        return [[k] for k in kinds]
    return [kinds] if kinds else []


def _mode_note(model) -> str:
    """', the lowest mode H Hz (P hole pairs)' with a dynamic response, else ''."""
    if model.dynamic is None:
        return ""
    lowest = min(float(m.hz[0]) for m in model.dynamic.values())
    return f", lowest mode {lowest:.3g} Hz ({len(model.dynamic)} mode set(s))"


def run_sweep(
    scene: Scene,
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

    inputs = sweep_input(scene)
    validate(inputs)
    if scheduler is not None:
        check_scheduler(scheduler)
    progress = progress or Progress(quiet=True)
    t0 = time.perf_counter()
    requested = results_dir(_default_dir(scene) if out is None else out, "output.dir" if out is None else "--out")
    try:
        target, replaces = reserve_results_dir(requested, force)
        staging = Staging(target, replaces)
    except OSError as exc:
        raise InputError("output.dir", f"cannot write results at {requested}: {exc.strerror or exc}") from None
    say_target(progress, requested, target)
    try:
        summary, tables, timings = _run_into(inputs, staging.path, scheduler, workers, serial, progress, dask)
        staging.commit()
    except BaseException:
        staging.abandon()
        raise
    tables = {kind: target / Path(p).name for kind, p in tables.items()}
    return SweepRun(summary, target, requested, time.perf_counter() - t0, tables, timings)


def _default_dir(scene: Scene) -> str:
    return "sweep" if scene.output.dir == "results" else f"{scene.output.dir}-sweep"


def _run_into(inputs: SweepInput, directory: Path, scheduler, workers, serial, progress, dask) -> tuple[dict, dict, dict]:

    clock = [time.perf_counter()]
    workers = local_workers(workers, scheduler, progress)
    by_kind = sweep_settings(inputs)
    progress.say(
        "sweep",
        ", ".join(f"{k}: {v['crank'].size} settings" for k, v in by_kind.items())
        + f" x {len(inputs.sweep.speeds)} speed(s), {inputs.sweep.steps} steps",
    )
    checked = {kind: _checked(inputs, kind, lengths) for kind, lengths in by_kind.items()}
    total, total_checked = sum(c.size for c in checked.values()), sum(int(c.sum()) for c in checked.values())
    large = total > KINEMATIC_DASK_CHUNKS * chunk_size(inputs) or total_checked > 4 * checked_chunk_size(inputs)
    forks = forked.available() and forked.alone()
    if forked.available() and not forks and not serial:
        others = ", ".join(t.name for t in threading.enumerate() if t is not threading.current_thread())
        progress.say(
            "sweep", f"this process runs other threads ({others}): its workers are not forked (a fork could hang them)"
        )
    # a local cluster only where this process cannot fork its workers (they share its memory)
    use_dask = (scheduler is not None or (large and not forks)) if dask is None else dask
    # stored parts read on two threads when the settings run on Dask or are many; any to build: here, one at a time
    models = prepare_models(
        inputs, by_kind, progress, min(2, os.cpu_count() or 1) if (use_dask or large) and not serial else 1
    )
    clock.append(time.perf_counter())
    kinds = list(by_kind)
    tables = {kind: directory / f"sweep-{kind}.{inputs.sweep.format}" for kind in kinds}
    aggregates = {
        kind: Aggregate(inputs, kind, by_kind[kind], motor_curve_speeds(inputs.sweep.speeds), models[kind]) for kind in kinds
    }
    jobs = [
        (lambda kind=kind: sweep_context(inputs, kind, models[kind]), by_kind[kind], kind, checked[kind]) for kind in kinds
    ]
    threads = 1 if serial else workers or os.cpu_count() or 1
    with (
        ChunkExecutor(
            scheduler, workers, use_dask and not serial, progress, directory, threads, forks, evaluate_chunk
        ) as executor,
        ExitStack() as stack,
    ):
        writers = {kind: stack.enter_context(TableWriter(tables[kind], inputs.sweep.format)) for kind in kinds}
        for kind, columns, curve in evaluated_chunks(inputs, jobs, by_kind, models, executor, progress):
            writers[kind].write(columns)
            aggregates[kind].add(columns, curve)
    clock.append(time.perf_counter())
    summary = summary_of(inputs, aggregates, tables, models)

    atomic_write_text(directory / "summary.json", to_json(summary) + "\n")
    if inputs.plots:  # [output] plots = false: no maps, no motor curve
        write_maps(aggregates, directory)
        write_motor_plot(aggregates, directory / "motor.png")
    write_sweep_report(directory / "report.html", summary, tables, directory, inputs.plots)
    if "four-bar" in tables:
        write_rig_page(directory / "rig.html", tables["four-bar"], summary["speeds_Hz"][0], inputs.source)
        write_card(directory, tables["four-bar"], summary["speeds_Hz"][0], inputs.source)
    clock.append(time.perf_counter())
    timings = dict(zip(("prepare", "chunks", "report"), np.diff(clock)))
    atomic_write_text(directory / "timings.json", to_json(timings) + "\n")
    return summary, tables, timings


def evaluated_chunks(inputs: SweepInput, jobs: list, by_kind: dict, models: dict, executor, progress):
    """Yield (kind, columns, motor curve) of every chunk of ``jobs`` on ``executor``, the
    settings with a row beyond a part's quasi-static tolerance held back and yielded last,
    settled on their exact response (:func:`settle_exact`)."""
    exact = ExactPass(len(inputs.sweep.speeds))
    kinds = [job[2] for job in jobs]
    for j, columns in executor.map_jobs(jobs, chunk_size(inputs), checked_chunk_size(inputs), held_chunks(inputs)):
        columns, curve = exact.hold(kinds[j], columns, columns.pop(MOTOR_CURVE_KEY))
        if columns["setting"].size:
            yield kinds[j], columns, curve
    yield from settle_exact(inputs, exact, by_kind, models, executor, progress)


def settle_exact(inputs: SweepInput, exact: ExactPass, by_kind: dict, models: dict, executor, progress):
    """Yield (kind, columns, motor curve) of the settings :class:`ExactPass` held back
    (a row beyond a part's quasi-static tolerance): their parts' dynamic models built for
    those settings alone, the settings evaluated again on ``executor``, each chunk merged
    (:meth:`ExactPass.merged`)."""
    for kind in list(exact.held):
        ids = exact.settings(kind)
        lengths = {b: v[ids] for b, v in by_kind[kind].items()}
        parts = sorted(exact.parts[kind])
        progress.say(
            "sweep",
            f"{kind}: {ids.size:,} settings beyond the quasi-static estimate's tolerance ({', '.join(parts)}): "
            "their exact dynamic response, as a check gives it",
        )
        built = prepare_models(inputs.responding(tuple(exact.parts[kind])), {kind: lengths}, progress)[kind]
        mixed = {name: built.get(name, m) if name in exact.parts[kind] else m for name, m in models[kind].items()}
        job = (
            lambda kind=kind, mixed=mixed: sweep_context(inputs, kind, mixed),
            lengths,
            kind,
            np.ones(ids.size, dtype=bool),
        )
        for _, columns in executor.map_jobs([job], chunk_size(inputs), checked_chunk_size(inputs), held_chunks(inputs)):
            curve = columns.pop(MOTOR_CURVE_KEY)
            columns["setting"] = ids[columns["setting"]]
            yield (kind, *exact.merged(kind, columns, curve))


def local_workers(workers: int | None, scheduler, progress) -> int | None:
    """``--workers`` for this machine: at most one local Dask worker or thread per core
    (more only share the cores: 1,000 threads took the whole rig's kinematics from 2.5 s to
    102 s), said when it is cut; unchanged for an external scheduler."""
    cores = os.cpu_count() or 1
    if scheduler is None and workers is not None and workers > cores:
        progress.say("sweep", f"--workers {workers}: this machine has {cores} cores; using {cores}")
        return cores
    return workers


def _checked(inputs: SweepInput, kind: str, lengths: dict) -> np.ndarray:
    """(N,) True where the sweep checks a setting's parts by FE
    (:func:`railcheck.sweep.chunk.checked_settings`; none without parts to check)."""
    if inputs.check is None:
        return np.zeros(lengths["crank"].size, dtype=bool)
    return checked_settings(sweep_context(inputs, kind, {}), lengths)


def sweep_context(inputs: SweepInput, kind: str, models: dict) -> SweepContext:
    """What every chunk of ``kind`` shares (:class:`~railcheck.sweep.context.SweepContext`):
    the sweep's record, its speeds and steps, the parts' ``models``, the material's density."""
    density = MATERIALS[inputs.check.material].density if inputs.check else 0.0
    return SweepContext(
        inputs, kind, tuple(inputs.sweep.speeds), inputs.sweep.steps, models, density, with_overrides(inputs.geometry)[0]
    )
