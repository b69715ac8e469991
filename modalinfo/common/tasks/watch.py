"""Never a silent wait: progress lines and the watch for running workers."""

from __future__ import annotations

import sys
import time
from typing import Any

__all__ = ["NoWorkersError", "PROGRESS_EVERY", "WORKER_WAIT", "gather_watched"]

#: Seconds between two progress lines on a stderr that is not a terminal.
PROGRESS_EVERY = 5.0

#: Seconds :func:`run_tasks` waits for a running worker before giving up.
WORKER_WAIT = 60.0


class NoWorkersError(RuntimeError):
    """No worker ran a task for ``worker_wait`` seconds (gone, or paused by memory)."""


def _running_workers(client: Any) -> int | None:
    """Workers of the scheduler able to run a task now (not paused, not closing).

    None when the scheduler cannot be asked (connection lost): the caller treats it
    as no worker. ``Client.scheduler_info()`` returns the client's cached identity, which
    its periodic refresh writes with the cluster's totals only (``identity(n_workers=0)``:
    ``"n_workers"`` 2, ``"workers"`` empty; distributed 2026.8) whenever the call's own
    refresh fails or loses the race with it: under a load of ~30 on 2 cores that read 0
    running workers for 60 s while both ran, and ``NoWorkersError`` ended a batch
    (fix52-c). Totals without the workers are asked again, from the scheduler itself.
    """
    try:
        if getattr(client, "status", "running") not in ("running", "connecting"):
            return None
        info = client.scheduler_info() or {}
        if not info.get("workers") and info.get("n_workers"):
            info = client.sync(client.scheduler.identity, n_workers=-1) or {}
    except Exception:  # noqa: BLE001 - an unreachable scheduler runs nothing
        return None
    workers = info.get("workers", {}) or {}
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
    from modalinfo.common.tasks.interrupts import raise_if_interrupted

    while pending:
        raise_if_interrupted(client)  # a Ctrl-C recorded by open_client's handler
        try:
            distributed.wait(pending, timeout=0.25, return_when="FIRST_COMPLETED")
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
