"""``analyse_archive``: the analyses of ``modalinfo batch`` over an archive of logs, on Dask.

Work is partitioned as one task per (log, analysis) -- or per (log, analysis, time
window) with ``window_frames`` -- keyed by the SHA-256 of the log's bytes, the
analysis, its parameters, the input hints, the window and the package version
(:func:`modalinfo.common.tasks.keys.task_key`). The SHA-256 of each log (and its frame
count when windows are asked for) is itself computed by a task on the workers and
cached in ``<out>/hashes.json`` by (path, size, mtime, inode, ctime, format, hints), so a
re-run neither re-reads nor re-analyses anything it has done.

Output directory layout::

    <out>/rows/<key>.json      one row per finished task (written atomically)
    <out>/hashes.json          SHA-256 cache
    <out>/batch.csv            the tidy table (one row per log and analysis)
    <out>/batch.parquet        the same table (pyarrow)
    <out>/plots/*.png          summary plots across the archive
    <out>/.lock                pid and host of the batch running in it (removed at its end)
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
from modalinfo.batch.manifest import LogEntry, collect_logs
from modalinfo.common.folders import check_out_dir, locked_out_dir
from modalinfo.common.tasks.cluster import check_memory_limit, open_client
from modalinfo.common.tasks.keys import TaskSpec, canonical_json, package_version, task_key
from modalinfo.common.tasks.rows import RowStore, clean_run_staging, write_table
from modalinfo.common.tasks.runner import EngineReport, run_tasks
from modalinfo.common.tasks.watch import WORKER_WAIT, gather_watched

__all__ = ["BatchResult", "analyse_archive", "build_specs", "time_windows"]

#: Leading columns of the table.
FIRST_COLUMNS = ("path", "analysis", "window", "window_start", "window_stop", "status",
                 "error_type", "error_message", "sha256", "version", "params", "hints", "key")


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
    identical : tuple of tuple of str
        Groups of byte-identical input paths: each was analysed once, and each path
        has its own rows.
    skipped : tuple of str
        Files of the input directories left out because their extension is not a
        log's (``modalinfo.io.formats.EXTENSIONS``); hidden files are not listed.
    unreadable : tuple of str
        Subfolders of the input directories this process may not list, left out (the
        rest is analysed).
    manifests : tuple of str
        Manifests met in the input directories, not read as logs (give one as an
        input of its own to read it).
    removed_plots : tuple of pathlib.Path
        With ``plots=False``: summary plots an earlier run left in ``OUT/plots``, drawn
        from another table than this one, removed.
    """

    rows: list
    csv_path: Path
    parquet_path: Path
    plots: tuple
    report: EngineReport
    n_hashed: int
    identical: tuple = ()
    skipped: tuple = ()
    unreadable: tuple = ()
    manifests: tuple = ()
    removed_plots: tuple = ()

    @property
    def n_ok(self) -> int:
        """Rows with a result."""
        return sum(r.get("status") == "ok" for r in self.rows)

    @property
    def n_error(self) -> int:
        """Error rows (unreadable log or failed analysis, and lost tasks)."""
        return sum(r.get("status") != "ok" for r in self.rows)


def _probe(path: str, fmt: str | None, hints: dict, frames: bool) -> list:
    """[SHA-256 or None, frame count] of one file (run on a worker).

    The frame count is None when not asked for, -1 when the file cannot be loaded.
    """
    try:
        digest = sha256_file(path)
    except OSError:
        return [None, None]
    n_frames = None
    if frames:
        from modalinfo.io import load

        try:
            n_frames = int(load(path, fmt=fmt, mmap=True, **hints).n_frames)
        except Exception:  # noqa: BLE001 - the analysis task reports why as an error row
            n_frames = -1
    return [digest, n_frames]


def _stat(path: str) -> list | None:
    """Return what tells a file's bytes unchanged: size, mtime, inode and ctime.

    Size and mtime alone were fooled by a log replaced with another of the same size
    whose mtime was set back (``cp`` then ``touch -r``, ``rsync -t``): the cached
    SHA-256 of the old bytes was reused and the old rows with it, "1 already done"
    (adversarial round 15 PART b, F13). The inode and ctime change with any
    replacement or write and cannot be set back by the user.
    """
    try:
        st = os.stat(path)
    except OSError:
        return None
    return [st.st_size, st.st_mtime_ns, st.st_ino, st.st_ctime_ns]


def _probes(entries: list[LogEntry], out_dir: Path, get_client: Callable[[], Any],
            frames: bool, worker_wait: float) -> tuple[dict, int]:
    """SHA-256 (and frame count if ``frames``) of every entry, computed on the workers.

    Cached in ``hashes.json`` by path, size, modification time, inode, ctime, format
    and hints; ``get_client()`` is called only when some file is missing from the
    cache. Returns
    ``({path: [sha256 or None, n_frames]}, files probed)`` (``n_frames``: None when
    not asked for, -1 for a file that does not load).
    """
    from modalinfo.common.files import atomic_write

    cache_path = out_dir / "hashes.json"
    cache: dict = {}
    if cache_path.is_file():
        with contextlib.suppress(ValueError, OSError):
            cache = json.loads(cache_path.read_text(encoding="utf-8"))
    result: dict[str, list] = {}
    todo = []
    for e in entries:
        stat = _stat(e.path)
        name = e.path + "\n" + canonical_json([e.fmt, e.hints])
        hit = cache.get(name)
        if stat is None:
            result[e.path] = [None, None]
        elif (isinstance(hit, list) and len(hit) == len(stat) + 2
              and hit[:len(stat)] == stat
              and (not frames or hit[-1] is not None or hit[-2] is None)):
            result[e.path] = hit[-2:]
        else:
            todo.append((e, name, stat))
    if todo:
        client = get_client()
        keys = ["modalinfo-probe-" + task_key("probe", n, s, frames) for _, n, s in todo]
        found = gather_watched(client, client.map(
            _probe, [e.path for e, _, _ in todo], [e.fmt for e, _, _ in todo],
            [e.hints for e, _, _ in todo], [frames] * len(todo), key=keys, pure=True),
            worker_wait=worker_wait)
        for (e, name, stat), (digest, n_frames) in zip(todo, found, strict=True):
            result[e.path] = [digest, n_frames]
            if digest is not None:
                cache[name] = [*stat, digest, n_frames]
        text = canonical_json(cache).encode()
        atomic_write(cache_path, lambda fh: fh.write(text), overwrite=True)
    return result, len(todo)


def time_windows(n_frames: int, window: int) -> list[tuple[int, int]]:
    """Consecutive windows of ``window`` frames; the last one takes the remainder.

    ``n_frames // window`` windows (at least one); the last runs to the end, so it has
    between ``window`` and ``2 window - 1`` frames and no window is a short tail.
    """
    count = max(1, n_frames // window)
    starts = [i * window for i in range(count)]
    return [(a, b) for a, b in zip(starts, [*starts[1:], n_frames], strict=True)]


def build_specs(entries: list[LogEntry], analyses: list[str], params: dict,
                probes: dict, window_frames: int | None = None) -> list[TaskSpec]:
    """One spec per (log, analysis[, time window]), keyed by content and parameters.

    The key covers the log's SHA-256 (its path when unreadable), the analysis, its
    parameters, the format and hints, the window and the package version.
    """
    version = package_version()
    specs = []
    for e in entries:
        digest, n_frames = probes.get(e.path, [None, None])
        ident = digest if digest is not None else ["unreadable", e.path]
        windows: list = [None]
        if window_frames is not None and n_frames is not None and n_frames > 0:
            windows = time_windows(n_frames, window_frames)
        for name in analyses:
            p = params[name]
            for w, bounds in enumerate(windows):
                key = task_key(ident, name, p, e.fmt, e.hints, bounds)
                payload = {"path": e.path, "fmt": e.fmt, "hints": e.hints, "analysis": name,
                           "params": p}
                labels = {"path": e.path, "analysis": name, "sha256": digest,
                          "version": version, "params": canonical_json(p),
                          "hints": canonical_json({"fmt": e.fmt, **e.hints})}
                if bounds is not None:
                    payload["window"] = list(bounds)
                    labels.update(window=w, window_start=bounds[0], window_stop=bounds[1])
                specs.append(TaskSpec(key, payload, labels))
    return specs


def _parse_analyses(analyses: str | list[str]) -> list[str]:
    names = [a.strip() for a in (analyses.split(",") if isinstance(analyses, str)
                                 else analyses) if a.strip()]
    if not names:
        raise ValueError("`analyses` must name at least one analysis")
    twice = next((n for n in names if names.count(n) > 1), None)
    if twice is not None:  # merged silently before: one row where two were asked
        raise ValueError(f"`analyses` names {twice!r} twice; give each analysis once")
    for name in names:
        resolve_params(name)
    return names


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
    window_frames: int | None = None,
    retries: int | None = None,
    retry_errors: bool = False,
    progress: bool = True,
    plots: bool = True,
    worker_wait: float | None = None,
    provenance: dict | None = None,
) -> BatchResult:
    """Run per-log analyses over an archive on Dask; resumable, errors become rows.

    Parameters
    ----------
    inputs : path, pattern or sequence of them
        Directories, glob patterns, manifest CSV files or log files (see
        ``modalinfo.batch.manifest.collect_logs``).
    analyses : str or list of str
        Among ``summary``, ``ordering``, ``fitting_error``, ``forecast``
        (comma-separated or a list).
    out_dir : path
        Output directory (new, empty, or an earlier batch's to resume it).
    params : dict, optional
        ``{analysis: {name: value}}`` overriding ``modalinfo.batch.analyses.DEFAULTS``.
    fmt, hints : optional
        Format and ``modalinfo.io.load`` hints for every log (a manifest's columns
        take precedence).
    scheduler : str, optional
        Address of a running Dask scheduler; None starts a ``LocalCluster``.
    n_workers, threads_per_worker, memory_limit : optional
        Local cluster shape (see ``modalinfo.common.tasks.cluster.open_client``).
    client : distributed.Client, optional
        Use this client (then ``scheduler`` and the cluster shape must be None).
    window_frames : int, optional
        Split each log into consecutive windows of this many frames (the last takes
        the remainder, see ``time_windows``) and analyse each window as a log of
        its own: one task and one row per window (columns ``window``,
        ``window_start``, ``window_stop``; ``start_time`` is the window's, and
        ``date`` too unless the metadata carries a date of its own).
        A task then maps only its window, so a worker's memory follows the window,
        not the log. None: whole logs.
    retries : int, optional
        Re-runs of a task whose worker died, on the local cluster started here
        (default Dask's ``allowed-failures``, 3); a task that keeps killing its
        worker becomes a ``lost`` row, retried by the next run.
    retry_errors : bool
        Re-run analyses whose earlier row is an error.
    progress : bool
        Progress bar and dashboard link on stderr.
    plots : bool
        Draw the summary plots into ``<out>/plots``. False draws none and removes the
        plots an earlier run left there from another table (``BatchResult.removed_plots``).
    worker_wait : float, optional
        Seconds to wait while no worker is running before giving up
        (``NoWorkersError``; default
        ``modalinfo.common.tasks.watch.WORKER_WAIT``).
    provenance : dict, optional
        The record of the run (``modalinfo batch`` passes its command's,
        ``modalinfo.common.provenance.provenance``; default: that of a Python call,
        the version and no command). The plots carry it with the SHA-256 of the table
        they draw (``table_sha256``, of ``batch.csv``) in their PNG metadata
        (``Description``; adversarial round 27 PART b, P20).

    Returns
    -------
    BatchResult

    Raises
    ------
    ValueError
        Unknown analysis or parameter, a bad parameter value, a memory limit too
        small for a worker, no input found, or an unusable output directory
        (not a directory, not writable, too little free space, foreign content).
    OutputInUseError
        Another batch holds the output directory (``<out>/.lock``; a ValueError).
    NoWorkersError
        No worker ran a task for ``worker_wait`` seconds; finished rows are kept.
    ImportError
        ``distributed`` or ``pyarrow`` missing (install ``modalinfo[dist]``).
    """
    names = _parse_analyses(analyses)
    if window_frames is not None and (isinstance(window_frames, bool)
                                      or not isinstance(window_frames, int)
                                      or window_frames < 2):
        raise ValueError(f"`window_frames` must be an int >= 2 or None; got {window_frames!r}")
    params = dict(params or {})
    unknown = sorted(set(params) - set(names))
    if unknown:
        raise ValueError(f"parameters given for {unknown[0]!r}, which is not among the "
                         f"analyses run ({', '.join(names)})")
    resolved = {n: resolve_params(n, params.get(n)) for n in names}
    out_dir = Path(out_dir)
    check_out_dir(out_dir)
    skipped: list[str] = []
    unreadable: list[str] = []
    manifests: list[str] = []
    entries = collect_logs(inputs, exclude=[out_dir], fmt=fmt, hints=hints, skipped=skipped,
                           unreadable=unreadable, manifests=manifests)
    if client is not None and any(v is not None for v in (
            scheduler, n_workers, threads_per_worker, memory_limit, retries)):
        raise ValueError("give either `client` or a scheduler / cluster shape, not both")
    check_memory_limit(memory_limit, threads_per_worker or 1)
    with contextlib.ExitStack() as stack:
        stack.enter_context(locked_out_dir(out_dir, "modalinfo batch"))
        clean_run_staging(out_dir, "batch", "modalinfo batch")
        store = RowStore(out_dir)
        started: list = [client]
        # the client's life, closed before the table and plots are written: its Ctrl-C
        # handler only records the signal (raised at the runner's polls), so a Ctrl-C
        # during the writes was acted on when they ended; closed, a Ctrl-C ends a write
        # at once (atomic_write removes its temporary file: the old file or none)
        client_life = stack.enter_context(contextlib.ExitStack())

        def get_client() -> Any:  # a cluster is started only when there is work
            if started[0] is None:
                started[0] = client_life.enter_context(open_client(
                    scheduler, n_workers=n_workers, threads_per_worker=threads_per_worker,
                    memory_limit=memory_limit, retries=retries))
            return started[0]

        wait = WORKER_WAIT if worker_wait is None else worker_wait
        probes, n_hashed = _probes(entries, out_dir, get_client, window_frames is not None,
                                   wait)
        specs = build_specs(entries, names, resolved, probes, window_frames)
        report = run_tasks(specs, run_log_task, store, get_client, progress=progress,
                           retry_errors=retry_errors, worker_wait=wait,
                           name="modalinfo batch")
        client_life.close()  # the cluster stops; a Ctrl-C recorded meanwhile is raised
        wanted = {s.key for s in specs}
        order = {n: i for i, n in enumerate(names)}
        stored = {r["key"]: r for r in store.rows() if r["key"] in wanted}
        # byte-identical logs share a task key (analysed once), yet every input path
        # gets its own row, labelled with its own path: nothing is merged silently
        rows = [_labelled(stored[s.key], s.labels) for s in specs if s.key in stored]
        rows.sort(key=lambda r: (r["path"], order[r["analysis"]], r.get("window", 0)))
        csv_path, pq_path = write_table(rows, out_dir, "batch", FIRST_COLUMNS)
        drawn: tuple = ()
        removed: tuple = ()
        if plots:
            from modalinfo.batch.report import plot_archive
            from modalinfo.common.provenance import provenance as run_record
            from modalinfo.common.provenance import sha256_file

            record = dict(provenance if provenance is not None else run_record(None))
            record["table_sha256"] = sha256_file(csv_path)
            drawn = tuple(plot_archive(rows, out_dir / "plots", provenance=record))
        else:
            from modalinfo.batch.report import remove_stale_plots
            from modalinfo.common.provenance import sha256_file

            # an earlier run's plots show other rows than this table's (round 54 PART b)
            removed = tuple(remove_stale_plots(out_dir / "plots", sha256_file(csv_path)))
    return BatchResult(rows=rows, csv_path=csv_path, parquet_path=pq_path, plots=drawn,
                       report=report, n_hashed=n_hashed,
                       identical=identical_inputs(entries, probes), skipped=tuple(skipped),
                       unreadable=tuple(unreadable), manifests=tuple(manifests),
                       removed_plots=removed)


def _labelled(row: dict, labels: dict) -> dict:
    """Return a stored ``row`` under a task's ``labels``, its error naming the labelled path.

    A byte-identical copy shares the row of the file analysed first: its error message
    named that other file ("'zero.csv' is empty" on zero.h5's row; round 18 PART b, M04).
    A message quotes its path in the shown form (``files.quoted``): a name whose shown
    form differs (a backslash, an undecodable byte) was not replaced (fixes 47-e).
    """
    from modalinfo.common.files import shown_name

    out = {**row, **labels}
    msg, first, own = row.get("error_message"), row.get("path"), labels.get("path")
    if isinstance(msg, str) and first and own and first != own:
        msg = msg.replace(shown_name(first), shown_name(own))
        if shown_name(first) != first:  # a raw path from a message not of ours
            msg = msg.replace(first, own)
        out["error_message"] = msg
    return out


def identical_inputs(entries: list[LogEntry], probes: dict) -> tuple[tuple[str, ...], ...]:
    """Return the groups of input paths whose bytes are identical (same SHA-256), in input order."""
    groups: dict[str, list[str]] = {}
    for e in entries:
        digest = probes.get(e.path, [None, None])[0]
        if digest is not None and e.path not in groups.setdefault(digest, []):
            groups[digest].append(e.path)
    return tuple(tuple(g) for g in groups.values() if len(g) > 1)
