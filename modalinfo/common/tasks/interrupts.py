"""Ctrl-C while a Dask client starts and lives: held, recorded, raised at a poll.

The command side of the project's Ctrl-C handling for the task runner (``modalinfo
batch``, ``closedloop sweep``): ``open_client`` holds a Ctrl-C while its local
cluster starts (``sigint_held``) and records one while the client lives
(``sigint_deferred``); the runner's poll loops call ``raise_if_interrupted``. The
worker side (each local worker ignores SIGINT) is the preload
``modalinfo.common.tasks.worker_signals``, a separate module because Dask imports it by
name in every worker process.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from typing import Any

__all__ = ["raise_if_interrupted", "sigint_deferred", "sigint_held"]


@contextlib.contextmanager
def sigint_held() -> Iterator[list[bool]]:
    """Hold a Ctrl-C while a local cluster starts; yield a list that gets True if one came.

    A SIGINT to the terminal's process group while ``LocalCluster`` spawned its workers
    killed the worker in its interpreter start-up ("Fatal Python error:
    init_import_site") and left a half-started cluster whose ``atexit`` close asserted
    (``AssertionError: Status.init``): two tracebacks after "interrupted" (Leftovers
    16-dask). Here SIGINT is blocked in this thread, so in the cluster's loop thread
    created meanwhile and in the worker processes it spawns (a signal mask survives
    ``fork`` and ``exec``; each worker's preload then ignores SIGINT, which discards it);
    the command's own Ctrl-C is recorded by a handler (in the main thread) or left
    pending by the mask and collected here at the end. The caller then stops the whole
    cluster and re-raises ``KeyboardInterrupt``: the Ctrl-C is acted on once the workers
    have started (seconds), never lost.
    """
    came: list[bool] = []
    if not hasattr(signal, "pthread_sigmask"):  # not POSIX (Windows): no masks to inherit
        yield came
        return
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.getsignal(signal.SIGINT)
        if callable(previous):  # an ignored or default SIGINT stays as it is
            signal.signal(signal.SIGINT, lambda *_: came.append(True))
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield came
    finally:
        if signal.SIGINT in signal.sigpending() and signal.SIGINT not in mask:
            signal.sigwait({signal.SIGINT})  # pending for this thread or the process: take it
            came.append(True)
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        if callable(previous):
            signal.signal(signal.SIGINT, previous)


@contextlib.contextmanager
def sigint_deferred() -> Iterator[threading.Event]:
    """Record a Ctrl-C while the client lives; yield the event it sets.

    Python raises ``KeyboardInterrupt`` wherever the main thread happens to be when
    its SIGINT handler runs: inside a ``gc`` callback (distributed registers one) or a
    finalizer it is printed as "Exception ignored in ..." and dropped, and the batch
    ran on to exit 0 (Leftovers 16-dask, G1). Here the handler only sets the event;
    the runner's poll loops (``run_tasks``, ``gather_watched``, which wake at least
    every 0.25 s) raise ``KeyboardInterrupt`` when it is set, and so does the end of
    this block when no other exception is on its way (a Ctrl-C after the last poll).
    Main thread only (``signal.signal`` works nowhere else) and only over Python's
    default handler: an ignored SIGINT (``nohup``) or a caller's own handler stays.
    The previous handler is restored on leaving.
    """
    event = threading.Event()
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.getsignal(signal.SIGINT)
        if previous is signal.default_int_handler:
            signal.signal(signal.SIGINT, lambda *_: event.set())
        else:
            previous = None
    failed = True
    try:
        yield event
        failed = False
    finally:
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
        if event.is_set() and not failed:  # came after the last poll: honoured here
            raise KeyboardInterrupt


def raise_if_interrupted(client: Any) -> None:
    """Raise ``KeyboardInterrupt`` if a Ctrl-C was recorded while ``client`` lives.

    See ``sigint_deferred``: the poll loops call this instead of letting the signal
    handler raise wherever the interpreter is.

    Parameters
    ----------
    client : distributed.Client
        A client from ``open_client`` (any other object: never raises).

    Raises
    ------
    KeyboardInterrupt
        A SIGINT came since the client was opened.
    """
    event = getattr(client, "modalinfo_interrupt", None)
    if event is not None and event.is_set():
        raise KeyboardInterrupt
