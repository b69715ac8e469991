"""A resumable, fault-tolerant task runner on Dask's ``distributed`` scheduler.

Part of the ground floor (:mod:`modalinfo.common`). The runner is generic: it runs a
list of :class:`~modalinfo.common.tasks.keys.TaskSpec` (each with a stable key) through
a function returning one table row (a dict of scalars), and keeps the rows in a
:class:`~modalinfo.common.tasks.rows.RowStore`. ``modalinfo batch`` (one task per log
and analysis) and ``closedloop sweep`` (one task per simulation) both sit on it.

Modules
-------
keys
    Stable task keys (:func:`task_key`, :func:`canonical_json`), :class:`TaskSpec`.
rows
    The row store (one JSON file per key) and the final tables (CSV and Parquet).
threads
    Thread budgets: workers x threads per worker x task threads within the machine.
interrupts
    Ctrl-C while a client starts (held) and lives (recorded, raised at the runner's
    next poll: ``raise_if_interrupted``).
cluster
    Opening a client (a ``LocalCluster`` or a scheduler address) and the checks of
    its worker count and memory limit before any cluster starts.
watch
    Progress lines and the watch for running workers (:class:`NoWorkersError`).
runner
    :func:`run_tasks`, which puts them together, and its :class:`EngineReport`.

The lock that keeps two runs out of one output folder is
:class:`modalinfo.common.folders.OutputLock`. ``modalinfo.batch.engine`` re-exports
every public name for the code written against it.

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
  machine; a local cluster also passes the BLAS/OpenMP limits to its workers as environment
  variables (see :func:`thread_env`).
"""
