"""A Dask client on a new ``LocalCluster`` or a running scheduler, and its checks."""

from __future__ import annotations

import contextlib
import logging
import os
from collections.abc import Iterator
from typing import Any

from modalinfo.common.deps import require
from modalinfo.common.files import quoted
from modalinfo.common.memory import machine_memory_bytes
from modalinfo.common.sizes import format_size, parse_size
from modalinfo.common.startup import worker_warning_env
from modalinfo.common.tasks.interrupts import raise_if_interrupted, sigint_deferred, sigint_held
from modalinfo.common.tasks.threads import available_cpus, task_threads, thread_env

__all__ = ["MIN_MEMORY_LIMIT", "WORKER_BASELINE", "check_memory_limit", "check_worker_count",
           "dashboard_link", "open_client", "raise_if_interrupted"]

#: Smallest per-worker memory limit of a local cluster [bytes]: a worker process with
#: numpy, numba and the library imported holds ~150 MB, and running the smallest task
#: (``summary`` of a 3000 x 27 log) it peaks between 243 and 285 MiB: at 256 and 257 MiB
#: Dask killed 4 workers in turn (its terminate threshold is 95 % of the limit) and the
#: row was lost; at 300 MiB it ran (adversarial round 24 PART b). Dask pauses a worker at
#: 80 % of its limit, so the floor keeps that pause above the peak: 0.8 x 384 = 307 MiB.
MIN_MEMORY_LIMIT = 384 * 2**20

#: the preload that makes each local worker process leave Ctrl-C to the command
_WORKER_SIGNALS = "modalinfo.common.tasks.worker_signals"


def _lack_of_memory(exc: BaseException) -> str | None:
    """Name the lack of memory behind a failed cluster start-up, or return None.

    Under an address-space limit (``ulimit -v 1 GB``) the nanny's thread could not
    start (``RuntimeError: can't start new thread``: each thread maps its stack) and
    ``LocalCluster`` raised "Nanny failed to start" with three tracebacks (Leftovers
    16-dask, L4b).
    """
    seen = 0
    while exc is not None and seen < 20:
        if isinstance(exc, MemoryError) or (isinstance(exc, RuntimeError)
                                            and "can't start new thread" in str(exc)):
            return str(exc).strip() or type(exc).__name__
        exc = exc.__cause__ or exc.__context__
        seen += 1
    return None


def _worker_start_failure(exc: BaseException) -> str | None:
    """Return the nanny's "failed to start" message behind ``exc``, or None."""
    seen = 0
    while exc is not None and seen < 20:
        if isinstance(exc, RuntimeError) and "failed to start" in str(exc):
            return str(exc).strip().rstrip(".")
        exc = exc.__cause__ or exc.__context__
        seen += 1
    return None


def _memory_failure_record(record: logging.LogRecord) -> bool:
    """Keep a log record unless it is a traceback of a lack of memory (said in one line)."""
    return not (record.exc_info and record.exc_info[1] is not None
                and _lack_of_memory(record.exc_info[1]) is not None)


@contextlib.contextmanager
def _without(logger: logging.Logger, keep: Any) -> Iterator[None]:
    """Filter ``logger``'s records with ``keep`` inside the block."""
    logger.addFilter(keep)
    try:
        yield
    finally:
        logger.removeFilter(keep)


#: Memory of one idle worker process (interpreter, numpy, numba, distributed) [bytes].
WORKER_BASELINE = 150 * 2**20


def check_worker_count(n_workers: int) -> None:
    """Refuse more local worker processes than the machine's free memory can start.

    Raises
    ------
    ValueError
        ``n_workers x`` :data:`WORKER_BASELINE` exceeds the available memory.
    """
    available = require("psutil").virtual_memory().available
    if n_workers * WORKER_BASELINE > available:
        most = max(1, available // WORKER_BASELINE)
        raise ValueError(f"`n_workers` must be at most {most} here: each worker process "
                         f"holds ~{WORKER_BASELINE // 2**20} MB before any task and "
                         f"{available / 2**30:.1f} GiB is available; got {n_workers}")


def check_memory_limit(memory_limit: str | float | None, threads_per_worker: int = 1) -> None:
    """Refuse a per-worker memory limit a worker cannot run under, before any cluster.

    Accepts what ``distributed.LocalCluster`` accepts: None or ``"auto"``, ``0`` (no
    limit), a size (``"2GB"``, ``"512 MiB"``, bytes as a number > 1) or a fraction
    ``0 < f <= 1`` of the machine's memory.

    Raises
    ------
    ValueError
        A limit that does not parse, is negative, or is below :data:`MIN_MEMORY_LIMIT`
        (a worker would be paused by its own memory before running a task).
    """
    if memory_limit is None or memory_limit == "auto":
        return
    # parsed here without dask (modalinfo.common.sizes.parse_size reads sizes as
    # dask.utils.parse_bytes does), so the check runs, and refuses, before any import of
    # the optional `dist` extra; the rules are distributed.worker_memory.parse_memory_limit's
    del threads_per_worker  # only "auto" depends on it, and "auto" is always accepted
    rule = (f"`memory_limit` must be a size such as '2GB', 'auto', 0 (no limit) or a "
            f"fraction of the machine's memory in (0, 1]; got {memory_limit!r}")
    if isinstance(memory_limit, bool):
        raise ValueError(rule)
    try:
        number = float(memory_limit)
    except (ValueError, TypeError):
        number = None
    try:
        if number is not None and number <= 1:
            if number < 0 or number != number:
                raise ValueError(rule)
            value = int(number * machine_memory_bytes()) if number > 0 else None
        else:
            value = parse_size(memory_limit, "memory_limit") or None
    except ValueError:
        raise ValueError(rule) from None
    if value is not None and value < MIN_MEMORY_LIMIT:
        raise ValueError(f"`memory_limit` must be at least {format_size(MIN_MEMORY_LIMIT)} "
                         f"per worker (a worker process running a task peaks near 285 MiB and "
                         f"Dask pauses it at 80 % of its limit); got {memory_limit!r} = "
                         f"{format_size(value)}")


@contextlib.contextmanager
def open_client(
    scheduler: str | None = None,
    *,
    n_workers: int | None = None,
    threads_per_worker: int | None = None,
    memory_limit: str | float | None = None,
    retries: int | None = None,
    dashboard_address: str | None = ":0",
) -> Iterator[Any]:
    """Open a ``distributed.Client`` on a new ``LocalCluster`` or on a running scheduler.

    Parameters
    ----------
    scheduler : str, optional
        Address of a running scheduler (``tcp://host:8786``). None starts a
        ``LocalCluster`` of worker processes, closed on exit.
    n_workers : int, optional
        Worker processes of the local cluster (default: CPUs // threads_per_worker).
    threads_per_worker : int, optional
        Tasks run at once per worker (default 1).
    memory_limit : str or float, optional
        Per-worker memory limit of the local cluster (``"2GB"``; default ``"auto"``).
    retries : int, optional
        Times the local cluster's scheduler re-runs a task whose worker died before
        giving up on it (``distributed.scheduler.allowed-failures``; default Dask's, 3).
        Exceptions raised by a task are never retried: they are its error row.
    dashboard_address : str or None
        Dashboard of the local cluster (``":0"``: a free port; None: no dashboard, the
        scheduler's HTTP server still takes a free port, never a fixed one).

    Yields
    ------
    distributed.Client
        With ``client.modalinfo_task_threads`` set: the thread budget of one task
        (None on a remote cluster: each task then uses 1 thread).
    """
    distributed = require("distributed")
    if scheduler is not None:
        given = {"workers": n_workers, "threads-per-worker": threads_per_worker,
                 "memory-limit": memory_limit, "retries": retries}
        clash = [k for k, v in given.items() if v is not None]
        if clash:
            raise ValueError(
                f"`{clash[0]}` applies to the local cluster only; the cluster at "
                f"{scheduler!r} sets its own workers"
            )
        with sigint_deferred() as event, distributed.Client(scheduler) as client:
            client.modalinfo_task_threads = None
            client.modalinfo_interrupt = event
            yield client
        return
    cpus = available_cpus()
    threads_per_worker = 1 if threads_per_worker is None else int(threads_per_worker)
    if threads_per_worker < 1:
        raise ValueError(f"`threads_per_worker` must be >= 1; got {threads_per_worker}")
    if n_workers is None:
        n_workers = max(1, cpus // threads_per_worker)
    if int(n_workers) < 1:
        raise ValueError(f"`n_workers` must be >= 1; got {n_workers}")
    n_workers = int(n_workers)
    check_memory_limit(memory_limit, threads_per_worker)
    check_worker_count(n_workers)
    threads = task_threads(n_workers, threads_per_worker, cpus)
    failures = {}
    if retries is not None:
        if isinstance(retries, bool) or not isinstance(retries, int) or retries < 0:
            raise ValueError(f"`retries` must be an int >= 0; got {retries!r}")
        failures = {"distributed.scheduler.allowed-failures": retries}
    import dask

    _check_scratch_folder(dask.config.get("temporary-directory", default=None))
    nanny_log = logging.getLogger("distributed.nanny")
    # the config is read once, by the scheduler created here
    with dask.config.set(failures), sigint_held() as interrupted, \
            _without(nanny_log, _memory_failure_record):
        try:
            cluster = distributed.LocalCluster(
                n_workers=n_workers,
                threads_per_worker=threads_per_worker,
                memory_limit="auto" if memory_limit is None else memory_limit,
                processes=True,
                # the command's one-line warnings in its workers (Leftovers 27-scale)
                env={**thread_env(threads), **worker_warning_env()},
                dashboard_address=":0" if dashboard_address is None else dashboard_address,
                scheduler_kwargs={"dashboard": dashboard_address is not None},
                silence_logs=logging.ERROR,
                # a Ctrl-C is the command's to handle: no traceback from each worker
                preload=[*(dask.config.get("distributed.worker.preload") or []),
                         _WORKER_SIGNALS],
            )
        except Exception as exc:
            if interrupted:  # a worker's start-up failed after the Ctrl-C: that is the cause
                raise KeyboardInterrupt from None
            lack = _lack_of_memory(exc)
            if lack is not None:  # under `ulimit -v`: "Nanny failed to start", 3 tracebacks
                raise MemoryError(f"the local Dask cluster could not start its workers "
                                  f"({lack})") from None
            if isinstance(exc, KeyError) and "Invalid time unit" in str(exc.args[0]):
                # a distributed.yaml (or DASK_* variable) timeout "abc": the bare quoted
                # "Invalid time unit: abc. Valid units are: s, ms, ... (54 names)" said
                # nothing of where (adversarial round 20 PART b, D01)
                raise ValueError(
                    f"the local Dask cluster could not start: a time in the Dask "
                    f"configuration does not parse ({str(exc.args[0]).split('. Valid')[0]}); "
                    f"check the YAML files of {_dask_config_places()} and the DASK_* "
                    "environment variables (e.g. distributed.comm.timeouts.connect: 30s)"
                ) from None
            dead = _worker_start_failure(exc)
            if dead is not None:
                # a worker process killed or ended during start-up (SIGKILL, the OOM
                # killer): "Nanny failed to start" and 71 lines of traceback, exit 1
                # (adversarial round 29 PART b, L01); an OSError is the command's one line
                raise ChildProcessError(
                    f"the local Dask cluster could not start its workers ({dead}: a "
                    "worker process ended during start-up, e.g. killed); run the command "
                    "again (a batch or sweep resumes), with fewer --workers if memory is "
                    "short") from None
            raise
    try:
        if interrupted:
            raise KeyboardInterrupt  # now that the cluster is whole, stopped below
        with sigint_deferred() as event, distributed.Client(cluster) as client:
            client.modalinfo_task_threads = threads
            client.modalinfo_interrupt = event
            yield client
    finally:
        cluster.close()


def _check_scratch_folder(folder: Any) -> None:
    """Refuse a Dask ``temporary-directory`` that cannot take files, before the cluster starts.

    Each worker keeps ``dask-scratch-space`` there. ``DASK_TEMPORARY_DIRECTORY`` on a
    read-only mount ended in "could not start its workers (Cluster failed to start:
    [Errno 30] Read-only file system: '.../dask-scratch-space': a worker process ended
    during start-up, e.g. killed); run the command again ..., with fewer --workers if
    memory is short": advice that cannot help (adversarial round 40 PART b, E53). The
    unset default is Python's temporary folder, which :mod:`tempfile` picks writable.
    """
    if not folder:
        return
    from pathlib import Path

    from modalinfo.common.files import writable_free_bytes

    place = Path(os.path.expanduser(str(folder)))
    while not place.exists() and place != place.parent:
        place = place.parent  # Dask creates the missing folders
    try:
        writable_free_bytes(place)
    except OSError as exc:
        raise ValueError(
            f"the Dask temporary-directory {quoted(folder)} cannot take the workers' scratch "
            f"files ({quoted(place)}: {exc.strerror or exc}); set DASK_TEMPORARY_DIRECTORY (or "
            f"temporary-directory in the YAML files of {_dask_config_places()}) to a "
            "writable folder, or unset it") from None


def _dask_config_places() -> str:
    """Name the folders Dask reads its YAML configuration from (``dask.config.paths``)."""
    import dask

    return ", ".join(f"'{p}'" for p in dask.config.paths)


def dashboard_link(client: Any) -> str | None:
    """Return the dashboard URL when the scheduler serves one, else None."""
    try:
        services = client.scheduler_info().get("services", {})
    except Exception:  # noqa: BLE001 - a missing dashboard is not an error
        return None
    if "dashboard" not in services:
        return None
    import importlib.util

    needs = "" if importlib.util.find_spec("bokeh") else " (install bokeh to view it)"
    return f"{client.dashboard_link}{needs}"
