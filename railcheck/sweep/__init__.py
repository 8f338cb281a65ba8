"""railcheck.sweep: ``railcheck sweep``, every setting of the rig.

:mod:`.run` (chunks, workers, the results directory), :mod:`.inputs` (what the sweep
reads of a scene), :mod:`.grid` (the settings the
rails' holes allow), :mod:`.context` (what a kind's chunks share), :mod:`.chunk` (a chunk
of settings -> rows), :mod:`.columns`, :mod:`.verdicts`, :mod:`.validity`,
:mod:`.components` and :mod:`.motor` (a chunk's columns), :mod:`.parts` (each part's unit
fields for every hole pair), :mod:`.aggregate` (counts, worst settings, summary.json),
:mod:`.exact` (the settings whose dynamic estimate exceeds its tolerance, evaluated on
the exact response), :mod:`.table` (Parquet/CSV), :mod:`.lookup` (one setting's card).
"""

import sys
import types

from railcheck.sweep.run import SweepRun, run_sweep
from railcheck.sweep.table import read_table

__all__ = ["SweepRun", "read_table", "run_sweep"]


import railcheck.api as _api  # noqa: E402  last: the API imports this package


class _Callable(types.ModuleType):
    """``railcheck.sweep(scene, ...)`` is :func:`railcheck.api.sweep` (the package stays importable)."""

    def __call__(self, *args, **kwargs):
        return _api.sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _Callable
