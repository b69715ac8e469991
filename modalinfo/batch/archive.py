"""``analyse_archive``: the analyses of ``modalinfo batch`` over an archive of logs, on Dask.

Work is partitioned as one task per (log, analysis), keyed by the SHA-256 of the
log's bytes, the analysis, its parameters, the input hints and the package version
(:func:`modalinfo.batch.engine.task_key`). The SHA-256 of each log is itself computed
by a task on the workers and cached in ``<out>/hashes.json`` by (path, size, mtime),
so a re-run neither re-reads nor re-analyses anything it has done.

Output directory layout::

    <out>/rows/<key>.json      one row per finished task (written atomically)
    <out>/hashes.json          SHA-256 cache
    <out>/batch.csv            the tidy table (one row per log and analysis)
    <out>/batch.parquet        the same table (pyarrow)
    <out>/plots/*.png          summary plots across the archive
"""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from modalinfo.batch.analyses import resolve_params, run_log_task, sha256_file
from modalinfo.batch.engine import (
    EngineReport,
    RowStore,
    TaskSpec,
    canonical_json,
    open_client,
    package_version,
    run_tasks,
    task_key,
    write_table,
)
from modalinfo.batch.manifest import LogEntry, collect_logs

__all__ = ["BatchResult", "analyse_archive", "build_specs"]

#: Leading columns of the table.
FIRST_COLUMNS = ("path", "analysis", "status", "error_type", "error_message", "sha256",
                 "version", "params", "hints", "key")


@dataclass(frozen=True)
class BatchResult:
    """What :func:`analyse_archive` produced.

    Attributes
    ----------
    rows : list of dict
        One row per log and analysis, sorted by path then analysis.
    csv_path, parquet_path : pathlib.Path
        The table.
    plots : tuple of pathlib.Path
        Summary plots written.
    report : EngineReport
        Tasks skipped (resumed), submitted, ok, error and lost in this run.
    n_hashed : int
        Files whose SHA-256 was computed in this run (not taken from the cache).
    """

    rows: list
    csv_path: Path
    parquet_path: Path
    plots: tuple
    report: EngineReport
    n_hashed: int

    @property
    def n_ok(self) -> int:
        """Rows with a result."""
        return sum(r.get("status") == "ok" for r in self.rows)

    @property
    def n_error(self) -> int:
        """Error rows (unreadable log or failed analysis, and lost tasks)."""
        return sum(r.get("status") != "ok" for r in self.rows)


def _hash_or_none(path: str) -> str | None:
    try:
        return sha256_file(path)
    except OSError:
        return None


def _stat(path: str) -> list | None:
    try:
        st = os.stat(path)
    except OSError:
        return None
    return [st.st_size, st.st_mtime_ns]


def _hashes(entries: list[LogEntry], out_dir: Path,
            get_client: Callable[[], Any]) -> tuple[dict, int]:
    """SHA-256 of every entry (None for unreadable files); computed on the workers.

    ``get_client()`` is called only when a file is missing from the cache.
    """
    from modalinfo.io._common import atomic_write

    cache_path = out_dir / "hashes.json"
    cache: dict = {}
    if cache_path.is_file():
        with contextlib.suppress(ValueError, OSError):
            cache = json.loads(cache_path.read_text(encoding="utf-8"))
    result: dict[str, str | None] = {}
    todo = []
    for e in entries:
        stat = _stat(e.path)
        hit = cache.get(e.path)
        if stat is not None and isinstance(hit, list) and hit[:2] == stat:
            result[e.path] = hit[2]
        elif stat is None:
            result[e.path] = None
        else:
            todo.append((e.path, stat))
    if todo:
        client = get_client()
        paths = [p for p, _ in todo]
        keys = ["modalinfo-sha256-" + task_key("sha256", p, s) for p, s in todo]
        digests = client.gather(client.map(_hash_or_none, paths, key=keys, pure=True))
        for (path, stat), digest in zip(todo, digests, strict=True):
            result[path] = digest
            if digest is not None:
                cache[path] = [*stat, digest]
        text = canonical_json(cache).encode()
        atomic_write(cache_path, lambda fh: fh.write(text), overwrite=True)
    return result, len(todo)


def build_specs(entries: list[LogEntry], analyses: list[str], params: dict,
                hashes: dict) -> list[TaskSpec]:
    """One spec per (log, analysis), keyed by content, analysis, parameters and hints."""
    version = package_version()
    specs = []
    for e in entries:
        digest = hashes.get(e.path)
        ident = digest if digest is not None else ["unreadable", e.path]
        for name in analyses:
            p = params[name]
            key = task_key(ident, name, p, e.fmt, e.hints)
            payload = {"path": e.path, "fmt": e.fmt, "hints": e.hints, "analysis": name,
                       "params": p}
            labels = {"path": e.path, "analysis": name, "sha256": digest, "version": version,
                      "params": canonical_json(p), "hints": canonical_json(
                          {"fmt": e.fmt, **e.hints})}
            specs.append(TaskSpec(key, payload, labels))
    return specs


def _check_out_dir(out_dir: Path) -> None:
    if out_dir.exists():
        if not out_dir.is_dir():
            raise ValueError(f"output '{out_dir}' exists and is not a directory")
        if any(out_dir.iterdir()) and not (out_dir / "rows").is_dir():
            raise ValueError(f"output directory '{out_dir}' is not empty and holds no "
                             "earlier batch (no rows/); choose a new or empty directory")
    elif not out_dir.parent.is_dir():
        raise ValueError(f"output directory's parent '{out_dir.parent}' does not exist")


def _parse_analyses(analyses: str | list[str]) -> list[str]:
    names = [a.strip() for a in (analyses.split(",") if isinstance(analyses, str)
                                 else analyses) if a.strip()]
    if not names:
        raise ValueError("`analyses` must name at least one analysis")
    for name in names:
        resolve_params(name)
    return list(dict.fromkeys(names))


def analyse_archive(
    inputs: Any,
    analyses: str | list[str] = ("summary",),
    out_dir: str | os.PathLike = "batch_out",
    *,
    params: dict | None = None,
    fmt: str | None = None,
    hints: dict | None = None,
    scheduler: str | None = None,
    n_workers: int | None = None,
    threads_per_worker: int | None = None,
    memory_limit: str | float | None = None,
    client: Any = None,
    retries: int = 2,
    retry_errors: bool = False,
    progress: bool = True,
    plots: bool = True,
) -> BatchResult:
    """Run per-log analyses over an archive on Dask; resumable, errors become rows.

    Parameters
    ----------
    inputs : path, pattern or sequence of them
        Directories, glob patterns, manifest CSV files or log files (see
        :func:`modalinfo.batch.manifest.collect_logs`).
    analyses : str or list of str
        Among ``summary``, ``ordering``, ``fitting_error``, ``forecast``
        (comma-separated or a list).
    out_dir : path
        Output directory (new, empty, or an earlier batch's to resume it).
    params : dict, optional
        ``{analysis: {name: value}}`` overriding :data:`~modalinfo.batch.analyses.DEFAULTS`.
    fmt, hints : optional
        Format and ``modalinfo.io.load`` hints for every log (a manifest's columns
        take precedence).
    scheduler : str, optional
        Address of a running Dask scheduler; None starts a ``LocalCluster``.
    n_workers, threads_per_worker, memory_limit : optional
        Local cluster shape (see :func:`modalinfo.batch.engine.open_client`).
    client : distributed.Client, optional
        Use this client (then ``scheduler`` and the cluster shape must be None).
    retries : int
        Extra attempts of a task whose worker died.
    retry_errors : bool
        Re-run analyses whose earlier row is an error.
    progress : bool
        Progress bar and dashboard link on stderr.
    plots : bool
        Draw the summary plots into ``<out>/plots``.

    Returns
    -------
    BatchResult

    Raises
    ------
    ValueError
        Unknown analysis or parameter, no input found, or an unusable output directory.
    ImportError
        ``distributed`` or ``pyarrow`` missing (install ``modalinfo[dist]``).
    """
    names = _parse_analyses(analyses)
    params = dict(params or {})
    unknown = sorted(set(params) - set(names))
    if unknown:
        raise ValueError(f"parameters given for {unknown[0]!r}, which is not among the "
                         f"analyses run ({', '.join(names)})")
    resolved = {n: resolve_params(n, params.get(n)) for n in names}
    out_dir = Path(out_dir)
    _check_out_dir(out_dir)
    entries = collect_logs(inputs, exclude=[out_dir], fmt=fmt, hints=hints)
    if client is not None and any(v is not None for v in (scheduler, n_workers,
                                                           threads_per_worker, memory_limit)):
        raise ValueError("give either `client` or a scheduler / cluster shape, not both")
    store = RowStore(out_dir)
    with contextlib.ExitStack() as stack:
        started: list = [client]

        def get_client() -> Any:  # a cluster is started only when there is work
            if started[0] is None:
                started[0] = stack.enter_context(open_client(
                    scheduler, n_workers=n_workers, threads_per_worker=threads_per_worker,
                    memory_limit=memory_limit))
            return started[0]

        hashes, n_hashed = _hashes(entries, out_dir, get_client)
        specs = build_specs(entries, names, resolved, hashes)
        report = run_tasks(specs, run_log_task, store, get_client, retries=retries,
                           progress=progress, retry_errors=retry_errors)
    wanted = {s.key for s in specs}
    order = {n: i for i, n in enumerate(names)}
    rows = [r for r in store.rows() if r["key"] in wanted]
    rows.sort(key=lambda r: (r["path"], order[r["analysis"]]))
    csv_path, pq_path = write_table(rows, out_dir, "batch", FIRST_COLUMNS)
    drawn: tuple = ()
    if plots:
        from modalinfo.batch.report import plot_archive

        drawn = tuple(plot_archive(rows, out_dir / "plots"))
    return BatchResult(rows=rows, csv_path=csv_path, parquet_path=pq_path, plots=drawn,
                       report=report, n_hashed=n_hashed)
