"""Dask worker preload: a local worker process leaves Ctrl-C to the command.

A Ctrl-C in a terminal reaches every process of the foreground group: the command, and
the worker processes of its ``LocalCluster``. The command stops the cluster and says
"interrupted" in one line; each worker process also raised ``KeyboardInterrupt`` and
``multiprocessing`` printed its 40-line traceback ("Process Dask Worker process (from
Nanny)", round 14 PART b, S08b). Loaded in each local worker (``preload``), this module
makes the worker ignore SIGINT; the command's cluster shutdown ends it.
"""

from __future__ import annotations

import signal
import threading
from typing import Any


def dask_setup(worker: Any) -> None:
    """Ignore SIGINT in this worker process (Dask calls this when the worker starts)."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)
