"""railcheck.parallel: every way railcheck runs work at once, behind one ordered map.

:func:`in_order` runs ``function(item)`` for each item serially, on threads, on forked
processes or on a Dask cluster, and yields the results in the items' order;
:class:`ChunkExecutor` cuts the sweep's jobs into chunks and runs them through it;
:func:`relayed_pool` is a pool of spawned workers whose progress lines reach the console
(the check's parts, the sweep's part preparation).
"""

from railcheck.parallel.executor import ChunkExecutor
from railcheck.parallel.ordered import EXECUTORS, in_order
from railcheck.parallel.spawned import relayed_pool, worker_say
from railcheck.parallel.threads import blas_on_one_thread

__all__ = ["EXECUTORS", "ChunkExecutor", "blas_on_one_thread", "in_order", "relayed_pool", "worker_say"]
