"""Leftovers 16-dask (issue 27), T11: numba's pool launched before a worker's env is applied.

A spawned Dask worker may import numba (and run a cached parallel kernel, which launches
its thread pool without compiling) before the nanny applies the ``env`` of the local
cluster (``os.environ.update(env)`` in ``distributed.nanny.WorkerProcess._run``); the next
compilation re-reads the environment and numba raises "Cannot set NUMBA_NUM_THREADS to a
different value once the threads have been launched" - every task of the worker failed.

Reference from outside the code: numba's own rule (``numba.core.config.reload_config``,
called by each compilation, refuses a changed ``NUMBA_NUM_THREADS`` once
``numba.np.ufunc.parallel._is_initialized``) and ``numba.get_num_threads``.
"""

from __future__ import annotations

import numba
import numpy as np

from modalinfo.common.tasks.threads import _limited_call, thread_env


@numba.njit(parallel=True)
def _parallel_sum(x):
    total = 0.0
    for i in numba.prange(x.size):
        total += x[i]
    return total


def test_worker_env_applied_after_numba_launched_its_threads(monkeypatch):
    assert _parallel_sum(np.ones(8)) == 8.0  # numba's pool launched, as in the worker
    launched = numba.config.NUMBA_NUM_THREADS
    for name, value in thread_env(launched + 1).items():  # what the nanny applies
        monkeypatch.setenv(name, value)

    def task(_payload):
        # a new compilation re-reads the environment (numba.core.config.reload_config)
        return {"sum": numba.njit(lambda a: a.sum() + 0.0)(np.arange(4.0)),
                "numba": numba.get_num_threads()}

    row = _limited_call(task, {}, 1)
    assert row["status"] == "ok", row
    assert row["sum"] == 6.0 and row["numba"] == 1
