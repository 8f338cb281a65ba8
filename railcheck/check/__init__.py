"""railcheck.check: ``railcheck check``, one setting of the rig from scene to verdict.

:mod:`.pipeline` (the stages a scene needs), :mod:`.workers` (parts in worker processes),
:mod:`.margins` (the one safe speed), :mod:`.summary` (summary.json), :mod:`.run` (the
results directory). What a part carries at a setting (its job, loading, cycle and
records) is :mod:`railcheck.model`.
"""

import sys
import types

from railcheck.check.pipeline import run_pipeline
from railcheck.check.run import CheckRun, run_check
from railcheck.check.summary import summary_of
from railcheck.model.jobs import PartJob, part_jobs
from railcheck.model.records import CycleResult, PartResult, PipelineResult

__all__ = [
    "CheckRun",
    "CycleResult",
    "PartJob",
    "PartResult",
    "PipelineResult",
    "part_jobs",
    "run_check",
    "run_pipeline",
    "summary_of",
]


import railcheck.api as _api  # noqa: E402  last: the API imports this package


class _Callable(types.ModuleType):
    """``railcheck.check(scene, ...)`` is :func:`railcheck.api.check` (the package stays importable)."""

    def __call__(self, *args, **kwargs):
        return _api.check(*args, **kwargs)


sys.modules[__name__].__class__ = _Callable
