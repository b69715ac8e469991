"""Dask worker preload: a local worker process leaves Ctrl-C to the command.

A Ctrl-C in a terminal reaches every process of the foreground group: the command, and
the worker processes of its ``LocalCluster``. The command stops the cluster and says
"interrupted" in one line; each worker process also raised ``KeyboardInterrupt`` and
``multiprocessing`` printed its 40-line traceback ("Process Dask Worker process (from
Nanny)", round 14 PART b, S08b). Loaded in each local worker (``preload``), this module
makes the worker ignore SIGINT; the command's cluster shutdown ends it.

It also keeps from the command's stderr the worker's 30-line traceback "Failed to
communicate with scheduler during heartbeat" (``distributed.worker`` at ERROR), which a
worker starved of CPU logs when the scheduler has closed under it at the end of a
finished batch (round 16 PART b, B06: after ``batch`` of 100 logs, exit 0). A worker
that really loses its scheduler is seen by the command (no worker running; retries).

And it gives the worker the command's one-line warning form (``modalinfo batch:
warning: ...``) where the command set one (Leftovers 27-scale): the cluster passes the
prefix in its workers' environment (``modalinfo.common.startup.worker_warning_env``).
"""

from __future__ import annotations

import logging
import signal
import threading
from typing import Any

#: the start of the heartbeat record ``quiet_heartbeat_logs`` drops
HEARTBEAT_FAILURE = "Failed to communicate with scheduler during heartbeat"


def _not_heartbeat_failure(record: logging.LogRecord) -> bool:
    return not str(record.msg).startswith(HEARTBEAT_FAILURE)


def quiet_heartbeat_logs() -> None:
    """Drop the heartbeat-failure record of ``distributed.worker`` in this process."""
    logger = logging.getLogger("distributed.worker")
    if _not_heartbeat_failure not in logger.filters:
        logger.addFilter(_not_heartbeat_failure)


def dask_setup(worker: Any) -> None:
    """Ignore SIGINT in this worker process (Dask calls this when the worker starts).

    Also shows warnings in the one-line form of the command that started the cluster
    (``modalinfo.common.startup.apply_worker_warning_format``; Leftovers 27-scale).
    """
    from modalinfo.common.startup import apply_worker_warning_format

    apply_worker_warning_format()
    quiet_heartbeat_logs()
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        # spawned with SIGINT blocked (``interrupts.sigint_held``): ignored now, so a
        # Ctrl-C held meanwhile is discarded, and the mask is the usual one again
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
