"""Running the specs not yet done, one row each: :func:`run_tasks`."""

from __future__ import annotations

import itertools
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from modalinfo.common.deps import require
from modalinfo.common.files import error_line
from modalinfo.common.tasks.cluster import dashboard_link
from modalinfo.common.tasks.interrupts import raise_if_interrupted
from modalinfo.common.tasks.keys import TaskSpec
from modalinfo.common.tasks.rows import RowStore
from modalinfo.common.tasks.threads import _limited_call
from modalinfo.common.tasks.watch import PROGRESS_EVERY, WORKER_WAIT, _Heartbeat

__all__ = ["STATUSES", "EngineReport", "lost_note", "run_tasks"]


def lost_note() -> str:
    """Name the memory limits a lost task's workers inherited; ``""`` when none is set.

    Under ``ulimit -d 300000`` every local worker of ``batch`` and ``sweep`` died in
    OpenBLAS's allocation, Dask gave up after four, and the row said only that the
    workers died, the command "run again to retry them", which dies alike (adversarial
    round 50 PART b, R09, R13). The limits are this process's, which local workers
    inherit.
    """
    from modalinfo.common.memory import memory_limits_text

    limits = memory_limits_text()
    if not limits:
        return ""
    return (f" ({limits} in the command, which local workers inherit: a worker out of "
            "memory under it dies again on a retry; raise it first)")

#: Row statuses: a task's result, an exception inside it, or a task lost with workers.
STATUSES = ("ok", "error", "lost")


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
                raise_if_interrupted(client)  # a Ctrl-C recorded by open_client's handler
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
                               "error_message": error_line(exc) + lost_note()}
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
