"""The task runner ``modalinfo batch`` sits on, by its former name.

The runner is shared plumbing and lives on the ground floor, split by concept:
:mod:`modalinfo.common.tasks` (``keys``, ``rows``, ``threads``, ``cluster``, ``watch``,
``runner``) and, for the output lock, :mod:`modalinfo.common.folders`. This module
only re-exports their public names, so code written against
``modalinfo.batch.engine`` keeps working; new code imports from there.
"""

from __future__ import annotations

from modalinfo.common.folders import OutputInUseError, OutputLock
from modalinfo.common.tasks.cluster import (
    MIN_MEMORY_LIMIT,
    WORKER_BASELINE,
    check_memory_limit,
    check_worker_count,
    dashboard_link,
    open_client,
)
from modalinfo.common.tasks.keys import TaskSpec, canonical_json, package_version, task_key
from modalinfo.common.tasks.rows import RowStore, write_table
from modalinfo.common.tasks.runner import STATUSES, EngineReport, run_tasks
from modalinfo.common.tasks.threads import task_threads, thread_env
from modalinfo.common.tasks.watch import (
    PROGRESS_EVERY,
    WORKER_WAIT,
    NoWorkersError,
    gather_watched,
)

__all__ = [
    "MIN_MEMORY_LIMIT",
    "PROGRESS_EVERY",
    "STATUSES",
    "WORKER_BASELINE",
    "WORKER_WAIT",
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
