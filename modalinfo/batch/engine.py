"""A resumable, fault-tolerant task runner on Dask's ``distributed`` scheduler.

The engine is generic: it runs a list of :class:`TaskSpec` (each with a stable key)
through a function returning one table row (a dict of scalars), and keeps the rows in
a :class:`RowStore`. ``modalinfo batch`` (one task per log and analysis) and the
closed-loop sweep (one task per simulation) both sit on it.

Guarantees
----------
- **Resume**: a spec whose key already has a row in the store is not submitted.
- **Atomic rows**: the client writes each finished row to ``rows/<key>.json`` through
  a temporary file and ``os.replace``; a row is either complete or absent, and the
  final tables are assembled from the row files only at the end.
- **Exactly once**: the file name is the key, so a task the scheduler re-runs after a
  worker died (``distributed.scheduler.allowed-failures`` times; ``retries`` of
  :func:`open_client` for a local cluster) still gives one row. Only the client
  writes rows, so workers need no shared file system.
- **Errors are rows**: an exception inside a task becomes an error row (key, the
  spec's labels, ``error_type``, ``error_message``); a task lost with its workers
  (``KilledWorker``) becomes an error row with ``status="lost"``, which a later run
  retries. The batch goes on either way.
- **Never a silent wait**: when stderr is not a terminal, a progress line every
  :data:`PROGRESS_EVERY` seconds; when no worker is running (all gone, or all paused
  by their memory limit) a notice, and :class:`NoWorkersError` after ``worker_wait``
  seconds (the rows already written are kept: the next run resumes).
- **One run per output directory**: :class:`OutputLock` (``<out>/.lock`` with the
  pid and host of its holder) keeps a second batch or sweep out of a directory in
  use; a lock left by a dead process on this host is taken over.
- **Threads**: a task runs with ``threads`` BLAS/OpenMP threads (``threadpoolctl``) and
  numba threads, so workers x threads-per-worker x task threads stays within the
  machine; a local cluster also passes the limits to its workers as environment
  variables (see :func:`thread_env`).
"""

from __future__ import annotations

import contextlib
import hashlib
import itertools
import json
import logging
import os
import socket
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from modalinfo.batch._deps import require
from modalinfo.io.files import format_size, parse_size

__all__ = [
    "EngineReport",
    "NoWorkersError",
    "gather_watched",
    "OutputInUseError",
    "OutputLock",
    "RowStore",
    "TaskSpec",
    "canonical_json",
    "check_memory_limit",
    "check_worker_count",
    "dashboard_link",
    "open_client",
    "package_version",
    "run_tasks",
    "task_key",
    "task_threads",
    "thread_env",
    "write_table",
]

#: Row statuses: a task's result, an exception inside it, or a task lost with workers.
STATUSES = ("ok", "error", "lost")

#: Seconds between two progress lines on a stderr that is not a terminal.
PROGRESS_EVERY = 5.0

#: Seconds :func:`run_tasks` waits for a running worker before giving up.
WORKER_WAIT = 60.0

#: Smallest per-worker memory limit of a local cluster [bytes]: a worker process with
#: numpy, numba and the library imported holds ~150 MB, and Dask pauses a worker at 80 %
#: of its limit, so a smaller limit leaves workers paused for ever.
MIN_MEMORY_LIMIT = 256 * 2**20


class NoWorkersError(RuntimeError):
    """No worker ran a task for ``worker_wait`` seconds (gone, or paused by memory)."""


class OutputInUseError(ValueError):
    """The output directory is locked by another running batch or sweep."""


def canonical_json(value: Any) -> str:
    """JSON with sorted keys and no spaces: the same value always gives the same text."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), allow_nan=True)


def package_version() -> str:
    """Version of the installed modalinfo (``modalinfo.__version__``)."""
    import modalinfo

    return str(modalinfo.__version__)


def task_key(*parts: Any) -> str:
    """Stable key of a task: SHA-256 of the canonical JSON of ``parts`` and the version.

    Parameters
    ----------
    *parts
        JSON-able values identifying the work (e.g. input SHA-256, analysis name,
        parameters, hints).

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    text = canonical_json([package_version(), *parts])
    return hashlib.sha256(text.encode()).hexdigest()


@dataclass(frozen=True)
class TaskSpec:
    """One unit of work.

    Attributes
    ----------
    key : str
        Stable identifier (see :func:`task_key`); also the row's file name.
    payload : dict
        JSON-able argument of the task function.
    labels : dict
        Scalar columns copied into the row, ok or error (e.g. ``path``, ``analysis``,
        ``sha256``, ``params``), so an error row names its input.
    """

    key: str
    payload: dict
    labels: dict = field(default_factory=dict)


@dataclass(frozen=True)
class EngineReport:
    """What one :func:`run_tasks` call did.

    Attributes
    ----------
    n_specs : int
        Distinct specs given.
    n_skipped : int
        Specs whose row was already in the store (resume).
    n_submitted : int
        Tasks submitted to the scheduler.
    n_ok, n_error, n_lost : int
        Rows written with each status in this call.
    elapsed : float
        Wall time of the call [s].
    """

    n_specs: int
    n_skipped: int
    n_submitted: int
    n_ok: int
    n_error: int
    n_lost: int
    elapsed: float


class RowStore:
    """Rows of a batch as one small JSON file per key in ``<out_dir>/rows``.

    Parameters
    ----------
    out_dir : str or os.PathLike
        Output directory (created if missing).
    """

    def __init__(self, out_dir: str | os.PathLike) -> None:
        self.out_dir = Path(out_dir)
        self.rows_dir = self.out_dir / "rows"
        self.rows_dir.mkdir(parents=True, exist_ok=True)

    def _path(self, key: str) -> Path:
        if not key or any(c in key for c in "/\\") or key.startswith("."):
            raise ValueError(f"`key` must be a plain file name; got {key!r}.")
        return self.rows_dir / f"{key}.json"

    def finished(self, *, retry_errors: bool = False) -> set[str]:
        """Keys with a final row (``ok``, and ``error`` unless ``retry_errors``)."""
        keep = {"ok"} if retry_errors else {"ok", "error"}
        return {row["key"] for row in self.rows() if row.get("status") in keep}

    def write(self, key: str, row: dict) -> Path:
        """Write one row atomically (replacing an earlier row of the same key)."""
        from modalinfo.io import atomic_write

        data = canonical_json({**row, "key": key}).encode()
        return atomic_write(self._path(key), lambda fh: fh.write(data), overwrite=True)

    def rows(self) -> list[dict]:
        """Every stored row, sorted by key (temporary files are never read)."""
        out = []
        for path in sorted(self.rows_dir.glob("*.json")):
            with open(path, encoding="utf-8") as fh:
                out.append(json.load(fh))
        return out


# ----------------------------------------------------------------------- lock
def _pid_alive(pid: int) -> bool:
    """Tell whether process ``pid`` exists on this host (True when unsure: no permission)."""
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # someone else's process: alive
        return True
    return True


class OutputLock:
    """Exclusive use of an output directory by one batch or sweep (a context manager).

    The lock is the file ``<out>/.lock`` holding JSON ``{"pid", "host", "started",
    "command"}``; it is created complete or not at all (written to a temporary file,
    then hard-linked to its name, which fails if the name exists), so two runs
    starting together cannot both hold it. A lock whose holder is a dead process on
    this host is stale and taken over; a lock held by a live process, or by a
    process on another host (which cannot be checked from here), raises
    :class:`OutputInUseError` naming the holder and the file to remove if that run is
    known to be over.

    Parameters
    ----------
    out_dir : str or os.PathLike
        An existing directory.
    command : str
        What holds the lock (``"modalinfo batch"``), recorded in the file.
    """

    NAME = ".lock"

    def __init__(self, out_dir: str | os.PathLike, command: str = "modalinfo batch") -> None:
        self.path = Path(out_dir) / self.NAME
        self.command = command
        self.held = False

    def _holder(self) -> dict | None:
        """Return the lock file's content; None when absent; {} when unreadable."""
        try:
            text = self.path.read_text(encoding="utf-8")
        except FileNotFoundError:
            return None
        except OSError:
            return {}
        try:
            data = json.loads(text)
        except ValueError:
            return {}
        return data if isinstance(data, dict) else {}

    def _stale(self, holder: dict) -> bool:
        pid = holder.get("pid")
        if holder.get("host") != socket.gethostname() or not isinstance(pid, int):
            return False
        return pid != os.getpid() and not _pid_alive(pid)

    def acquire(self) -> OutputLock:
        """Take the lock (taking over a stale one); raise OutputInUseError if held."""
        info = canonical_json({"pid": os.getpid(), "host": socket.gethostname(),
                               "started": time.time(), "command": self.command})
        tmp = self.path.with_name(f".lock.{os.getpid()}.{time.monotonic_ns()}.tmp")
        tmp.write_text(info, encoding="utf-8")
        try:
            for _ in range(3):  # a stale lock removed by us (or another taker) in between
                try:
                    os.link(tmp, self.path)
                    self.held = True
                    return self
                except FileExistsError:
                    pass
                holder = self._holder()
                if holder is None:
                    continue  # released between our link and our read: try again
                if not self._stale(holder):
                    who = (f"{holder.get('command', 'a run')} (pid {holder.get('pid')} on "
                           f"{holder.get('host')})" if holder else "another run")
                    raise OutputInUseError(
                        f"output directory '{self.path.parent}' is in use by {who}; wait "
                        f"for it to finish, or remove '{self.path}' if it is no longer running")
                # stale: remove it only if it is still the same dead holder's file
                with contextlib.suppress(FileNotFoundError):
                    if self._holder() == holder:
                        self.path.unlink()
            raise OutputInUseError(f"output directory '{self.path.parent}': could not take "
                                   f"the lock '{self.path}' (others keep taking it)")
        finally:
            with contextlib.suppress(OSError):
                tmp.unlink()

    def release(self) -> None:
        """Remove the lock file if this process holds it."""
        if self.held:
            holder = self._holder()
            if holder and holder.get("pid") == os.getpid():
                with contextlib.suppress(FileNotFoundError):
                    self.path.unlink()
            self.held = False

    def __enter__(self) -> OutputLock:
        return self.acquire()

    def __exit__(self, *exc: Any) -> None:
        self.release()


# ----------------------------------------------------------------------- threads
def thread_env(threads: int) -> dict[str, str]:
    """Environment variables limiting numba, OpenMP and BLAS threads of a worker."""
    value = str(int(threads))
    return {name: value for name in (
        "NUMBA_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
    )}


def task_threads(n_workers: int, threads_per_worker: int, cpus: int | None = None) -> int:
    """Threads one task may use so that workers x threads x task threads <= cpus."""
    if cpus is None:
        cpus = os.cpu_count() or 1
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
        message = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
        row = {"status": "error", "error_type": type(exc).__name__, "error_message": message}
    row["task_seconds"] = time.perf_counter() - start
    return row


# ----------------------------------------------------------------------- client
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
    # parsed here without dask (modalinfo.io.files.parse_size reads sizes as
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
            value = int(number * _machine_memory()) if number > 0 else None
        else:
            value = parse_size(memory_limit, "memory_limit") or None
    except ValueError:
        raise ValueError(rule) from None
    if value is not None and value < MIN_MEMORY_LIMIT:
        raise ValueError(f"`memory_limit` must be at least {format_size(MIN_MEMORY_LIMIT)} "
                         f"per worker (a worker process alone holds ~150 MB and Dask pauses "
                         f"it at 80 % of its limit); got {memory_limit!r} = "
                         f"{format_size(value)}")


def _machine_memory() -> float:
    """Physical memory of this machine [bytes] (what a fraction ``memory_limit`` is of)."""
    try:
        return float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - exotic platforms
        return float("inf")


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
        with distributed.Client(scheduler) as client:
            client.modalinfo_task_threads = None
            yield client
        return
    cpus = os.cpu_count() or 1
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

    with dask.config.set(failures):  # read once, by the scheduler created here
        cluster = distributed.LocalCluster(
            n_workers=n_workers,
            threads_per_worker=threads_per_worker,
            memory_limit="auto" if memory_limit is None else memory_limit,
            processes=True,
            env=thread_env(threads),
            dashboard_address=":0" if dashboard_address is None else dashboard_address,
            scheduler_kwargs={"dashboard": dashboard_address is not None},
            silence_logs=logging.ERROR,
        )
    try:
        with distributed.Client(cluster) as client:
            client.modalinfo_task_threads = threads
            yield client
    finally:
        cluster.close()


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


# ----------------------------------------------------------------------- run
def _running_workers(client: Any) -> int | None:
    """Workers of the scheduler able to run a task now (not paused, not closing).

    None when the scheduler cannot be asked (connection lost): the caller treats it
    as no worker.
    """
    try:
        if getattr(client, "status", "running") not in ("running", "connecting"):
            return None
        info = client.scheduler_info()
    except Exception:  # noqa: BLE001 - an unreachable scheduler runs nothing
        return None
    workers = (info or {}).get("workers", {}) or {}
    return sum(1 for w in workers.values() if w.get("status", "running") == "running")


class _Heartbeat:
    """Progress lines (stderr not a terminal) and the watch for running workers."""

    def __init__(self, client: Any, total: int, *, name: str, progress: bool,
                 worker_wait: float, progress_every: float) -> None:
        self.client = client
        self.total = total
        self.name = name
        self.lines = progress and not _isatty(sys.stderr)
        self.worker_wait = float(worker_wait)
        self.progress_every = float(progress_every)
        self.start = self.last_line = self.seen_workers = time.monotonic()
        self.next_check = self.start
        self.warned = False

    def line(self, counts: dict, force: bool = False) -> None:
        now = time.monotonic()
        if self.lines and (force or now - self.last_line >= self.progress_every):
            done = sum(counts.values())
            sys.stderr.write(
                f"{self.name}: {done}/{self.total} tasks done ({counts['ok']} ok, "
                f"{counts['error']} error, {counts['lost']} lost), "
                f"{now - self.start:.0f} s elapsed\n")
            sys.stderr.flush()
            self.last_line = now

    def idle(self, counts: dict) -> None:
        """Check the workers (about once a second) while no task has finished."""
        now = time.monotonic()
        self.line(counts)
        if now < self.next_check:
            return
        self.next_check = now + 1.0
        running = _running_workers(self.client)
        if running:
            if self.warned:
                sys.stderr.write(f"{self.name}: {running} worker(s) running again\n")
                self.warned = False
            self.seen_workers = now
            return
        waited = now - self.seen_workers
        if not self.warned:
            why = ("the scheduler cannot be reached" if running is None else
                   "no Dask worker is running (none connected, or all paused by their "
                   "memory limit)")
            sys.stderr.write(f"{self.name}: {why}; waiting up to {self.worker_wait:g} s "
                             "for one\n")
            sys.stderr.flush()
            self.warned = True
        if waited >= self.worker_wait:
            raise NoWorkersError(
                f"no Dask worker ran a task for {waited:.0f} s ("
                + ("the scheduler cannot be reached" if running is None else
                   "none connected, or all paused by their memory limit")
                + f"); {sum(counts.values())} of {self.total} tasks finished and are kept: "
                "run the same command again to resume")

    def seen(self) -> None:
        """Record that a task finished: some worker ran it."""
        self.seen_workers = time.monotonic()


def gather_watched(client: Any, futures: list, *, worker_wait: float = WORKER_WAIT,
                   name: str = "modalinfo batch") -> list:
    """Return ``client.gather(futures)``, but never wait forever for absent workers.

    While no future finishes, the scheduler is asked (about once a second) for running
    workers, as :func:`run_tasks` does: a notice on stderr when there is none, and
    :class:`NoWorkersError` after ``worker_wait`` seconds without one.
    """
    import distributed

    beat = _Heartbeat(client, len(futures), name=name, progress=False,
                      worker_wait=worker_wait, progress_every=float("inf"))
    counts = {"ok": 0, "error": 0, "lost": 0}
    pending = list(futures)
    while pending:
        try:
            distributed.wait(pending, timeout=0.5, return_when="FIRST_COMPLETED")
        except TimeoutError:
            beat.idle(counts)
            continue
        still = [f for f in pending if not f.done()]
        if len(still) < len(pending):
            beat.seen()
            counts["ok"] += len(pending) - len(still)
        pending = still
    return client.gather(futures)


def _isatty(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


def run_tasks(
    specs: Sequence[TaskSpec],
    func: Callable[[dict], dict],
    store: RowStore,
    client: Any,
    *,
    progress: bool = True,
    retry_errors: bool = False,
    on_row: Callable[[str, dict], None] | None = None,
    max_pending: int = 10_000,
    worker_wait: float = WORKER_WAIT,
    progress_every: float = PROGRESS_EVERY,
    name: str = "batch",
) -> EngineReport:
    """Run the specs not yet in ``store`` on ``client``; write one row per spec.

    Parameters
    ----------
    specs : sequence of TaskSpec
        The work (duplicate keys are run once).
    func : callable
        ``func(payload) -> dict`` of scalars; must be importable by the workers
        (a module-level function). Deterministic in its payload: tasks are submitted
        with ``pure=True`` under their spec key.
    store : RowStore
        Where rows go; its finished keys are skipped.
    client : distributed.Client or callable
        The scheduler, or a function returning it, called only when some spec is
        not yet done (so a finished batch starts no cluster).
    progress : bool
        Show progress on stderr: a bar on a terminal (and the dashboard link),
        else one line every ``progress_every`` seconds and a last one at the end.
    retry_errors : bool
        Also re-run specs whose stored row is an error.
    on_row : callable, optional
        Called as ``on_row(key, row)`` after each row is written.
    max_pending : int
        At most this many tasks are on the scheduler at once (one more is submitted
        as each finishes), so a year of logs does not sit in the scheduler's memory.
    worker_wait : float
        Seconds to wait while no worker is running (none connected, all paused by
        their memory limit, or the scheduler unreachable) before raising
        :class:`NoWorkersError`; a notice is written on stderr when the wait starts,
        whatever ``progress``.
    progress_every : float
        Seconds between progress lines when stderr is not a terminal.
    name : str
        Prefix of the progress lines and notices (``"modalinfo batch"``).

    Returns
    -------
    EngineReport

    Raises
    ------
    NoWorkersError
        No worker for ``worker_wait`` seconds; the rows written so far are kept.
    """
    distributed = require("distributed")
    start = time.perf_counter()
    unique: dict[str, TaskSpec] = {}
    for spec in specs:
        unique.setdefault(spec.key, spec)
    done = store.finished(retry_errors=retry_errors)
    todo = [s for k, s in unique.items() if k not in done]
    counts = dict.fromkeys(STATUSES, 0)
    if todo:
        if callable(client) and not hasattr(client, "map"):
            client = client()
        threads = getattr(client, "modalinfo_task_threads", None)
        by_future: dict = {}

        def submit(batch: list[TaskSpec]) -> list:
            if not batch:
                return []
            futures = client.map(
                _limited_call, [func] * len(batch), [s.payload for s in batch],
                [threads] * len(batch), key=[f"modalinfo-{s.key}" for s in batch],
                pure=True,
            )
            by_future.update({f.key: s for f, s in zip(futures, batch, strict=True)})
            return futures

        queue = iter(todo)
        first = list(itertools.islice(queue, max_pending))
        bar = None
        beat = _Heartbeat(client, len(todo), name=name, progress=progress,
                          worker_wait=worker_wait, progress_every=progress_every)
        if progress:
            link = dashboard_link(client)
            if link:
                sys.stderr.write(f"dask dashboard: {link}\n")
            from tqdm import tqdm

            # disable=None: no bar when stderr is not a terminal (logs, CI, batch jobs),
            # where the heartbeat writes a line every few seconds instead
            bar = tqdm(total=len(todo), unit="task", file=sys.stderr, smoothing=0.1,
                       disable=None)
        try:
            pending = distributed.as_completed(submit(first))
            while not pending.is_empty():
                ready = pending.next_batch(block=False)
                if not ready:
                    beat.idle(counts)
                    # woken by the next finished task (as as_completed's own __next__)
                    with pending.thread_condition:
                        pending.thread_condition.wait(timeout=0.2)
                    continue
                beat.seen()
                for future in ready:
                    spec = by_future.pop(future.key)
                    try:
                        row = future.result()
                    except Exception as exc:  # noqa: BLE001 - the task's workers died
                        row = {"status": "lost", "error_type": type(exc).__name__,
                               "error_message": str(exc).strip().splitlines()[0]
                               if str(exc).strip() else ""}
                    row = {**spec.labels, **row}
                    store.write(spec.key, row)
                    counts[row["status"]] += 1
                    if on_row is not None:
                        on_row(spec.key, row)
                    future.release()
                    for new in submit(list(itertools.islice(queue, 1))):  # keep max_pending
                        pending.add(new)
                    if bar is not None:
                        bar.update(1)
                beat.line(counts)
            beat.line(counts, force=True)
        finally:
            if bar is not None:
                bar.close()
    return EngineReport(
        n_specs=len(unique), n_skipped=len(unique) - len(todo), n_submitted=len(todo),
        n_ok=counts["ok"], n_error=counts["error"], n_lost=counts["lost"],
        elapsed=time.perf_counter() - start,
    )


def _column_order(rows: list[dict], first: Sequence[str]) -> list[str]:
    seen = dict.fromkeys(c for c in first if any(c in r for r in rows))
    for row in rows:
        for name in row:
            seen.setdefault(name, None)
    return list(seen)


def write_table(rows: list[dict], out_dir: Path, stem: str, first: Sequence[str] = (),
                overwrite: bool = True) -> tuple[Path, Path]:
    """Write the rows as ``<stem>.csv`` and ``<stem>.parquet`` (pyarrow), atomically.

    Columns are the union of the rows' keys (``first`` leading); a row lacking a
    column has a null there. Returns the two paths.
    """
    pa = require("pyarrow")
    pacsv = require("pyarrow.csv")
    pq = require("pyarrow.parquet")
    from modalinfo.io import atomic_write

    columns = _column_order(rows, first)
    data = {}
    for name in columns:
        values = [r.get(name) for r in rows]
        kinds = {type(v) for v in values if v is not None}
        if kinds <= {int, float} and float in kinds:
            values = [None if v is None else float(v) for v in values]
        elif len(kinds) > 1:
            values = [None if v is None else str(v) for v in values]
        data[name] = pa.array(values)
    table = pa.table(data) if columns else pa.table({"key": pa.array([], pa.string())})
    csv_path = Path(out_dir) / f"{stem}.csv"
    pq_path = Path(out_dir) / f"{stem}.parquet"
    atomic_write(pq_path, lambda fh: pq.write_table(table, fh), overwrite=overwrite)
    atomic_write(csv_path, lambda fh: pacsv.write_csv(table, fh), overwrite=overwrite)
    return csv_path, pq_path

