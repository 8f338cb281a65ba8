"""The Python API: ``railcheck.check(scene)`` and ``railcheck.sweep(scene)``.

A scene is a path to a TOML file, TOML text, a dict as TOML reads it, a parsed
:class:`~railcheck.scene.Scene`, or None (the built-in default). Both return frozen
records: the check's :class:`Check` holds the pipeline's :class:`~railcheck.model.records.PipelineResult`
(every part's envelope, fatigue, deflection, utilisation), the ``summary`` dict that
``summary.json`` holds, and where the files went; the sweep's :class:`Sweep` holds its
summary and each linkage kind's table as a ``pyarrow.Table`` (``.to_pandas()`` for a
DataFrame). The CLI commands are this layer plus printing. Bad input raises
:class:`~railcheck.base.errors.InputError` naming the field, as the CLI's one line does.

    >>> import railcheck
    >>> run = railcheck.check({"mechanism": {...}, "check": {...}})   # no files unless out=
    >>> run.passed, run.summary["parts"]["crank-rail"]["utilisation"]
"""

from __future__ import annotations

import inspect
import os
import shutil
import sys
import tempfile
import threading
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import railcheck.check.pipeline as check_pipeline  # modules, not names: the packages import this one
import railcheck.check.run as check_run
import railcheck.check.summary as check_summary
import railcheck.frames as frames
import railcheck.sweep.run as sweep_run
import railcheck.sweep.table as sweep_table
from railcheck.base.errors import EXIT_FAIL, EXIT_PASS, InputError
from railcheck.base.temporaries import process_running
from railcheck.files import writable_dir
from railcheck.progress import Progress
from railcheck.scene import Scene, load_scene, parse_scene
from railcheck.studies.mechanism import mechanism_scene
from railcheck.studies.planar_outputs import planar_summary, write_planar_outputs
from railcheck.studies.planar_scene import planar_scene, with_steps
from railcheck.studies.planar_study import study_planar


def scene_of(scene: Any = None) -> Scene:
    """A :class:`Scene` from a path, TOML text, a dict, a Scene or None (the built-in)."""
    if scene is None or isinstance(scene, Scene):
        return scene if scene is not None else load_scene(None)
    if isinstance(scene, dict):
        return parse_scene(scene, "<dict>")
    if isinstance(scene, Path) or (isinstance(scene, str) and "\n" not in scene and "=" not in scene):
        return load_scene(scene)
    if isinstance(scene, str) and "\n" not in scene and _is_file(scene):  # a path with "=" in its name
        return load_scene(scene)
    if isinstance(scene, str):
        try:
            return parse_scene(tomllib.loads(scene), "<text>")
        except tomllib.TOMLDecodeError as exc:
            raise InputError("scene", f"malformed TOML: {exc}") from None
    raise InputError("scene", f"must be a path, TOML text, a dict or None, got {type(scene).__name__}")


def _is_file(text: str) -> bool:
    """Whether ``text`` names an existing file (False for text no path can be)."""
    try:
        return Path(text).is_file()
    except (OSError, ValueError):
        return False


@dataclass(frozen=True)
class Check:
    """A finished check: ``result`` (:class:`~railcheck.model.records.PipelineResult`),
    ``summary`` (what summary.json holds), ``target`` the results folder or None."""

    result: Any
    summary: dict
    target: Path | None = None

    @property
    def passed(self) -> bool:
        """True when every configuration check and every part passes."""
        return not self.result.failures

    @property
    def exit_status(self) -> int:
        return EXIT_PASS if self.passed else EXIT_FAIL

    def parts_frame(self):
        """pandas frame, a row per part (:func:`railcheck.frames.parts_frame`)."""
        return frames.parts_frame(self.summary)

    def components_frame(self):
        """pandas frame, a row per component (:func:`railcheck.frames.components_frame`)."""
        return frames.components_frame(self.summary)

    def __repr__(self) -> str:
        """One line: the verdict, what fails, each part's and component's utilisation, the
        safe speed and the folder (the records themselves are ``result`` and ``summary``)."""
        s = self.summary
        uses = {n: round(p["utilisation"], 3) for n, p in s.get("parts", {}).items()}
        uses |= {n: round(c["utilisation"], 3) for n, c in s.get("components", {}).items()}
        safe = s.get("safe_speed")
        speed = "none" if safe is None else ("any" if safe["Hz"] is None else f"{safe['Hz']:.4g} Hz")
        return (
            f"Check(verdict={s.get('verdict')!r}, failures={self.result.failures!r}, utilisation={uses!r}, "
            f"safe_speed={speed!r}, target={str(self.target) if self.target else None!r})"
        )


#: one check or sweep at a time in a process: calls from several threads wait their turn
#: (a run already uses both cores; two at once gave other last digits, the solvers'
#: thread pools shared, and raced pyvista's first import)
_ONE_RUN = threading.RLock()


def check(
    scene: Any = None, out: str | Path | None = None, force: bool = False, jobs: int = 1, progress: Any = False
) -> Check:
    """Check one setting of the rig, as ``railcheck check`` does, and return its records.

    Parameters
    ----------
    scene : str, Path, dict, Scene or None
        A TOML file's path, TOML text, a dict as TOML reads it, a parsed
        :class:`~railcheck.scene.Scene`, or None for the built-in default scene.
    out : str or Path, optional
        Write the results folder there, as ``railcheck check --out``; None writes nothing.
    force : bool
        Replace an existing ``out`` folder (else the run goes to ``out-2``).
    jobs : int
        Parts checked at once; above 1 in worker processes started by spawning, which a
        script must allow (its calls under ``if __name__ == "__main__":``).
    progress : bool or callable
        True prints the command line's progress lines on stderr; a callable receives each
        line (str); False (the default) is silent.

    Returns
    -------
    Check
        ``passed``, ``exit_status``, ``summary`` (what summary.json holds), ``result``
        (the pipeline's records), ``target``; ``parts_frame()``, ``components_frame()``.

    Raises
    ------
    InputError
        Bad input, naming the field (:class:`~railcheck.base.errors.InputErrors` for
        several at once).

    Notes
    -----
    Safe from threads: calls run one after another in a process.
    """
    parsed = scene_of(scene)
    with _ONE_RUN:
        return _check(parsed, out, force, jobs, progress_of(progress))


def progress_of(progress: Any) -> Progress:
    """The :class:`~railcheck.progress.Progress` the API's ``progress`` argument asks for."""
    if callable(progress):
        return Progress(sink=progress)
    return Progress(quiet=not progress)


def _check(parsed: Scene, out: str | Path | None, force: bool, jobs: int, progress: Progress) -> Check:
    if out is not None:
        run = check_run.run_check(parsed, str(out), force, progress, jobs=jobs)
        return Check(run.result, run.summary, run.target)
    result = check_pipeline.run_pipeline(parsed, progress, jobs=jobs)
    return Check(result, check_summary.summary_of(result))


SCRATCH_PREFIX = "railcheck-sweep-"


def _scratch_folder() -> Path:
    """A new scratch folder for a sweep kept in memory (``$TMPDIR/railcheck-sweep-<pid>-*``),
    after removing those a killed process left (its pid no longer runs)."""
    root = Path(tempfile.gettempdir())
    for old in root.glob(f"{SCRATCH_PREFIX}*-*"):
        pid = old.name[len(SCRATCH_PREFIX) :].split("-", 1)[0]
        if pid.isdigit() and int(pid) != os.getpid() and not process_running(int(pid)) and not old.is_symlink():
            shutil.rmtree(old, ignore_errors=True)
    return Path(tempfile.mkdtemp(prefix=f"{SCRATCH_PREFIX}{os.getpid()}-"))


@dataclass(frozen=True)
class Sweep:
    """A finished sweep: its ``summary`` (what summary.json holds), ``tables`` linkage kind
    -> ``pyarrow.Table`` (one row per setting and speed), ``target`` the results folder or
    None."""

    summary: dict
    tables: dict = field(default_factory=dict)
    target: Path | None = None

    def frame(self, kind: str = "four-bar"):
        """pandas frame of linkage ``kind``'s table, a row per setting and speed
        (:func:`railcheck.frames.settings_frame`)."""
        if kind not in self.tables:
            raise InputError("kind", f"no {kind!r} table in this sweep (it has: {', '.join(self.tables) or 'none'})")
        return frames.settings_frame(self.tables[kind])

    def __repr__(self) -> str:
        """One line: each linkage kind's settings and those that pass, its rows, the folder."""
        kinds = {
            kind: f"{k['settings_passing']}/{k['settings_total']} settings pass"
            for kind, k in self.summary.get("by_kind", {}).items()
        }
        rows = {kind: t.num_rows for kind, t in self.tables.items()}
        return f"Sweep(kinds={kinds!r}, rows={rows!r}, target={str(self.target) if self.target else None!r})"


def sweep(
    scene: Any = None,
    out: str | Path | None = None,
    force: bool = False,
    workers: int | None = None,
    serial: bool = False,
    progress: Any = False,
) -> Sweep:
    """Sweep every setting the scene asks for, as ``railcheck sweep`` does.

    Parameters
    ----------
    scene : str, Path, dict, Scene or None
        As :func:`check`'s; its ``[sweep]`` narrows the rig's hole grid (none: every setting).
    out : str or Path, optional
        Keep the results folder there (tables, maps, report.html, rig.html); None reads the
        tables into memory and keeps no files.
    force : bool
        Replace an existing ``out`` folder.
    workers : int, optional
        Local workers (at most one per core, the default).
    serial : bool
        Run in this process on one thread.
    progress : bool or callable
        As :func:`check`'s.

    Returns
    -------
    Sweep
        ``summary``, ``tables`` (linkage kind -> ``pyarrow.Table``, a row per setting and
        speed), ``target``; ``frame(kind)`` a pandas frame.

    Notes
    -----
    Safe from threads: calls run one after another in a process.
    """
    parsed = scene_of(scene)
    with _ONE_RUN:
        return _sweep(parsed, out, force, workers, serial, progress_of(progress))


def _sweep(parsed: Scene, out, force: bool, workers: int | None, serial: bool, progress: Progress) -> Sweep:
    scratch = None if out is not None else _scratch_folder()
    destination = Path(out) if out is not None else Path(str(scratch)) / "sweep"
    try:
        run = sweep_run.run_sweep(parsed, str(destination), force, workers=workers, serial=serial, progress=progress)
        tables = {kind: sweep_table.read_table(path) for kind, path in run.tables.items()}
        return Sweep(run.summary, tables, None if scratch is not None else run.target)
    finally:
        if scratch is not None:
            shutil.rmtree(scratch, ignore_errors=True)


@dataclass(frozen=True)
class MechanismStudy:
    """A planar mechanism study (:func:`mechanism`): ``study`` the frozen record (mobility,
    motion, reactions, tracers in SI; :class:`~railcheck.studies.planar_study.PlanarStudy`),
    ``summary`` the dict summary.json holds, ``files`` what was written (none without out=)."""

    study: Any
    summary: dict
    files: tuple[Path, ...] = ()


def mechanism(scene: Any, steps: int | None = None, out: str | Path | None = None) -> MechanismStudy:
    """Seed 002's study of a planar mechanism: a planar scene (a path, TOML text or a dict
    with ``[mechanism] kind = "planar"``), a catalogue name ("a-z-1139"), or a rig scene's
    own linkage (a path). ``out``: a folder for summary.json, the CSVs and the page."""
    if isinstance(scene, dict):
        parsed = planar_scene(scene, "<dict>")
    elif isinstance(scene, str) and "\n" in scene:
        try:
            parsed = planar_scene(tomllib.loads(scene), "<text>")
        except tomllib.TOMLDecodeError as exc:
            raise InputError("scene", f"malformed TOML: {exc}") from None
    elif isinstance(scene, (str, Path)):
        parsed = mechanism_scene(str(scene))
    else:
        raise InputError("scene", f"must be a path, a catalogue name, TOML text or a dict, got {type(scene).__name__}")
    if steps is not None:
        parsed = with_steps(parsed, steps, "steps")
    study = study_planar(parsed)
    summary = planar_summary(study)
    files = tuple(write_planar_outputs(study, summary, writable_dir(out, "out"))) if out is not None else ()
    return MechanismStudy(study, summary, files)


def _describe_callable_packages() -> None:
    """``railcheck.check`` and ``railcheck.sweep`` are packages made callable: give them the
    functions' signature and docstring, which ``inspect.signature`` and ``help`` read
    (else ``(*args, **kwargs)`` and the package's text)."""
    for name, function in (("railcheck.check", check), ("railcheck.sweep", sweep)):
        package = sys.modules[name]
        if getattr(package, "__wrapped__", None) is function:
            continue
        package.__signature__ = inspect.signature(function)  # type: ignore[attr-defined]
        package.__wrapped__ = function  # type: ignore[attr-defined]
        package.__doc__ = f"{name}{package.__signature__}\n\n{function.__doc__}\n\nThe package: {package.__doc__}"


_describe_callable_packages()
