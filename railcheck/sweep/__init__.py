"""railcheck.sweep: ``railcheck sweep``, every setting of the rig.

:mod:`.run` (chunks, Dask, the results directory), :mod:`.shared` (the context the
local workers map from one file), :mod:`.grid` (the settings the
rails' holes allow), :mod:`.chunk` (a chunk of settings -> rows), :mod:`.parts` (each
part's unit fields for every hole pair), :mod:`.fe` (exact screened superposition),
:mod:`.table` (Parquet/CSV), :mod:`.maps` (aggregates, the seed's hypotheses, maps).
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
