"""Thread budgets of tasks: numba, OpenMP and BLAS threads within the machine."""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Callable

__all__ = ["available_cpus", "task_threads", "thread_env"]


def available_cpus() -> int:
    """CPUs this process may run on: its affinity mask, else ``os.cpu_count()``.

    A scheduler's job (Slurm, a cgroup cpuset, ``taskset``) is allotted fewer CPUs than
    the node has; ``os.cpu_count()`` counts the node, so the local cluster started one
    worker per CPU of the node (under ``taskset -c 0`` on 2 CPUs: 2 workers on 1 CPU;
    round 47 PART b T01).
    """
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # no affinity on this platform (macOS, Windows)
        return os.cpu_count() or 1


def thread_env(threads: int) -> dict[str, str]:
    """Environment variables limiting OpenMP and BLAS threads of a worker.

    Not ``NUMBA_NUM_THREADS``: the nanny applies this environment inside the spawned
    worker, which may already have imported numba and launched its pool (a cached
    parallel kernel run while ``__main__`` is re-imported, or a notebook's imports);
    numba then refuses any later compilation ("Cannot set NUMBA_NUM_THREADS to a
    different value once the threads have been launched", Leftovers 16-dask, T11).
    Each task limits numba with ``numba.set_num_threads`` instead (``_limited_call``).
    """
    value = str(int(threads))
    return {name: value for name in (
        "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
    )}


def task_threads(n_workers: int, threads_per_worker: int, cpus: int | None = None) -> int:
    """Threads one task may use so that workers x threads x task threads <= cpus."""
    if cpus is None:
        cpus = available_cpus()
    return max(1, cpus // max(1, n_workers * threads_per_worker))


#: BLAS/OpenMP thread limit already applied to this worker process (see _blas_limit).
_PROCESS_LIMIT: list = [None]


def _blas_limit(threads: int) -> contextlib.AbstractContextManager:
    """Limit BLAS/OpenMP threads: once per worker process, else around the call.

    ``threadpoolctl`` scans the loaded libraries at each call (~5 ms), so a worker
    process applies the limit once and keeps it (libraries loaded later read the
    ``*_NUM_THREADS`` variables its nanny set); outside a worker (a single-process
    run) the limit is scoped to the call.
    """
    from threadpoolctl import threadpool_limits

    try:
        from distributed import get_worker

        get_worker()
    except (ImportError, ValueError):
        return threadpool_limits(limits=threads)
    if _PROCESS_LIMIT[0] != threads:
        threadpool_limits(limits=threads)  # process-wide, kept
        _PROCESS_LIMIT[0] = threads
    return contextlib.nullcontext()


def _limited_call(func: Callable[[dict], dict], payload: dict, threads: int | None) -> dict:
    """Run ``func(payload)`` on a worker with a thread budget; exceptions become rows."""
    if threads is None:
        # a cluster we did not start: it may run several worker processes per node
        # (dask worker --nworkers), which a task cannot see; 1 thread, as Dask's nanny
        # sets OMP/MKL/OPENBLAS_NUM_THREADS=1 by default (distributed.nanny.pre-spawn-environ)
        threads = 1
    start = time.perf_counter()
    try:
        import numba

        numba.set_num_threads(max(1, min(threads, numba.config.NUMBA_NUM_THREADS)))
        with _blas_limit(threads):
            row = dict(func(payload))
        row["status"] = "ok"
    except Exception as exc:  # noqa: BLE001 - any failure of one input is that input's row
        from modalinfo.common.files import error_line

        row = {"status": "error", "error_type": type(exc).__name__,
               "error_message": error_line(exc)}
    row["task_seconds"] = time.perf_counter() - start
    return row
