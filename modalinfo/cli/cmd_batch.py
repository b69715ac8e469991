r"""``modalinfo batch INPUTS... --out DIR``: analyse an archive of logs on Dask.

Example::

    modalinfo batch /data/2026/ --analyses summary,forecast --out season/
    modalinfo batch 'logs/**/*.h5' manifest.csv --scheduler tcp://head:8786 --out season/

Inputs are directories (searched recursively), glob patterns, manifest CSV files (a
``path`` column plus per-file hint columns) or log files. One task per log and
analysis runs on a Dask ``LocalCluster`` (``--workers``, ``--threads-per-worker``,
``--memory-limit``) or on the scheduler at ``--scheduler``. The table
``DIR/batch.csv`` / ``DIR/batch.parquet`` has one row per log and analysis; a log
that cannot be read becomes an error row. Its ``path`` column is written as ``ls -b``
shows a name: a byte that is not UTF-8 as ``\xNN``, a backslash as ``\\``
(``codecs.escape_decode`` gives the name's bytes back). Running the same command again
resumes: finished rows are skipped (matched by content and parameters, not by path).
Exit status 1 when some row failed (the count on stderr), or when no worker ran a task
for ``--worker-wait`` seconds; 2 for an input error, found before any work (a ``--set``
value, ``--memory-limit`` below 384 MiB, an output directory in use by another batch:
``DIR/.lock``). When stderr is not a terminal, a progress line every few seconds
replaces the bar.
``--set analysis.name=value`` changes a parameter (value read as JSON when it parses,
else as text), e.g. ``--set forecast.horizon=10``.
"""

from __future__ import annotations

import argparse
import json
import sys

from modalinfo.cli import CommandError
from modalinfo.cli.shared import (
    add_hint_arguments,
    command_provenance,
    hints_from_args,
    refuse_outlier_drop,
)
from modalinfo.common.cli import check_cluster_args, folder_arg
from modalinfo.common.files import quoted, shown_message, shown_name

NAME = "batch"
HELP = "Analyse an archive of logs on Dask (local cluster or --scheduler); resumable."

ANALYSES = ("summary", "ordering", "fitting_error", "forecast")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Fill the ``batch`` parser."""
    parser.add_argument("inputs", nargs="+", metavar="INPUT",
                        help="directory, glob pattern, manifest CSV or log file")
    parser.add_argument("--analyses", default="summary", metavar="LIST",
                        help=f"comma-separated, from {', '.join(ANALYSES)} "
                        "(default: %(default)s)")
    parser.add_argument("--out", type=folder_arg, required=True, metavar="DIR",
                        help="output directory (new, empty, or an earlier batch's to resume)")
    parser.add_argument("--set", dest="settings", action="append", default=[],
                        metavar="ANALYSIS.NAME=VALUE", help="change an analysis parameter")
    parser.add_argument("--window-frames", type=int, default=None, metavar="N",
                        help="analyse each log in consecutive windows of N frames "
                        "(one row per window; bounded worker memory for long logs)")
    parser.add_argument("--scheduler", default=None, metavar="ADDR",
                        help="address of a running Dask scheduler (tcp://host:8786); "
                        "default: start a local cluster")
    parser.add_argument("--workers", type=int, default=None, metavar="N",
                        help="local worker processes (default: CPUs / threads per worker)")
    parser.add_argument("--threads-per-worker", type=int, default=None, metavar="K",
                        help="tasks at once per local worker (default 1)")
    parser.add_argument("--memory-limit", default=None, metavar="SIZE",
                        help="memory limit per local worker, e.g. 2GB (default: auto)")
    parser.add_argument("--retries", type=int, default=None, metavar="R",
                        help="re-runs of a task whose local worker died (default: Dask's "
                        "allowed-failures, 3); exceptions are error rows, never retried")
    parser.add_argument("--worker-wait", type=float, default=None, metavar="S",
                        help="give up (exit 1, finished rows kept) after S seconds with no "
                        "running worker (default 60)")
    parser.add_argument("--retry-errors", action="store_true",
                        help="re-run analyses whose earlier row is an error")
    parser.add_argument("--no-plots", action="store_true",
                        help="skip the summary plots (and remove those an earlier run "
                             "drew from another table)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar, no summary")
    add_hint_arguments(parser, is_info=False, modes_flag="--in-modes")


def parse_settings(items: list[str]) -> dict:
    """``["forecast.horizon=10"]`` -> ``{"forecast": {"horizon": 10}}``."""
    out: dict = {}
    for item in items:
        name, sep, text = item.partition("=")
        analysis, dot, param = name.strip().partition(".")
        if not sep or not dot or not analysis or not param:
            raise CommandError(f"--set must look like analysis.name=value; got {item!r}")
        try:
            value = json.loads(text)
        except ValueError:
            value = text
        given = out.setdefault(analysis, {})
        if param in given and given[param] != value:  # the Parser's rule for an option
            raise CommandError(f"--set {analysis}.{param}: given twice ({given[param]!r} "
                               f"and {value!r}); give it once")
        given[param] = value
    return out


def kl_assumption_note(rows: list[dict]) -> None:
    """Say once on stderr what the theoretical K-L of the rows assumed (column ``kl_assumed``).

    One line per assumption (``modalinfo.ordering.compare.kl_geometry_assumption``'s
    words, as ``reorder`` and ``fitting-error`` print them), with the number of logs and
    the first five (adversarial round 24 PART b, F31-F35: batch assumed it silently).
    """
    paths: dict[str, list[str]] = {}
    for row in rows:
        what = row.get("kl_assumed")
        if row.get("status") == "ok" and isinstance(what, str) and what:
            group = paths.setdefault(what, [])
            if (shown := shown_name(row["path"])) not in group:
                group.append(shown)
    for what, group in paths.items():
        shown = ", ".join(group[:5]) + (", ..." if len(group) > 5 else "")
        sys.stderr.write(f"modalinfo batch: note: {len(group)} log(s) record {what}; "
                         f"column kl_assumed: {shown}\n")


def layout_doubt_note(rows: list[dict]) -> None:
    """Say once on stderr which logs look stored modes x frames (column ``layout_doubt``).

    Each task reads its log and the reader's ``LayoutWarning`` reached stderr once per
    analysis (left31-orient): one line for the batch instead, naming the first five logs.
    """
    paths: list[str] = []
    for row in rows:
        doubt = row.get("layout_doubt")
        if row.get("status") == "ok" and isinstance(doubt, str) and doubt:
            if (shown := shown_name(row["path"])) not in paths:
                paths.append(shown)
    if paths:
        shown = ", ".join(paths[:5]) + (", ..." if len(paths) > 5 else "")
        sys.stderr.write(f"modalinfo batch: warning: {len(paths)} log(s) were read frames x "
                         "modes but their content says modes x frames (lag-1 "
                         "autocorrelation larger from column to column than from row to "
                         f"row; column layout_doubt): {shown}; pass --transpose to read "
                         "them the other way round, or --no-transpose to keep the layout\n")


def _policies_applied(rows: list[dict]) -> str:
    """Name the outlier policy each analysis applied to its flagged logs, from the rows.

    From the rows' ``outliers`` column, not from ``--outliers``: ``--set
    summary.outliers=drop`` was reported as "--outliers warn applied" while the rows
    said drop (round 33 PART b, B37 / B38). The hint that clip, drop or raise act on the
    flagged values goes with warn only.
    """
    logs: dict[tuple[str, str], set] = {}
    for row in rows:
        key = (str(row.get("analysis")), str(row.get("outliers") or "warn"))
        logs.setdefault(key, set()).add(row.get("path"))
    parts = [f"{analysis}: {policy} on {len(paths)} log(s)"
             for (analysis, policy), paths in sorted(logs.items())]
    hint = (" (--outliers clip, drop or raise, or --set ANALYSIS.outliers=..., act on "
            "them)" if any(policy == "warn" for _, policy in logs) else "")
    return "outlier policy applied: " + ", ".join(parts) + hint


def run(args: argparse.Namespace) -> int:
    """Run the batch and print what was done; 1 when some row failed (count on stderr)."""
    from modalinfo.batch import analyse_archive
    from modalinfo.common.tasks.watch import NoWorkersError

    check_cluster_args(args)
    if args.retries is not None and args.retries < 0:
        raise CommandError(f"--retries must be >= 0; got {args.retries}")
    if args.window_frames is not None and args.window_frames < 2:
        raise CommandError(f"--window-frames must be >= 2; got {args.window_frames}")
    settings = parse_settings(args.settings)
    if args.outliers != "warn":  # --set analysis.outliers=... wins for its analysis
        chosen = [a.strip() for a in args.analyses.split(",") if a.strip()]
        own = [a for a in chosen if "outliers" in settings.get(a, {})]
        if chosen and len(own) == len(chosen):
            raise CommandError(f"--outliers {args.outliers} applies to no analysis: each sets "
                               f"its own ({', '.join(f'{a}.outliers' for a in own)}); drop "
                               "--outliers or those --set")
        if "forecast" in chosen and "forecast" not in own:
            # --set forecast.outliers=... wins for forecast: --outliers drop then acts on
            # the other analyses only (round 39 PART b, S35)
            refuse_outlier_drop(args, "the forecast analysis")
        for analysis in chosen:
            settings.setdefault(analysis, {}).setdefault("outliers", args.outliers)
    hints = hints_from_args(args)
    if hints.get("nonfinite") == "raise":
        hints.pop("nonfinite")  # the reader's default: keeps the task keys of plain runs
    if args.dataset is not None:
        hints["dataset"] = args.dataset
    try:
        result = analyse_archive(
            args.inputs, args.analyses, args.out, params=settings,
            fmt=args.fmt, hints=hints, scheduler=args.scheduler, n_workers=args.workers,
            threads_per_worker=args.threads_per_worker, memory_limit=args.memory_limit,
            window_frames=args.window_frames, retries=args.retries,
            retry_errors=args.retry_errors, progress=not args.quiet,
            plots=not args.no_plots, worker_wait=args.worker_wait,
            provenance=command_provenance(args, None),
        )
    except ImportError as exc:
        raise CommandError(str(exc)) from None
    except NoWorkersError as exc:
        sys.stderr.write(f"modalinfo batch: error: {exc}\n")
        return 1
    for group in result.identical:  # a warning: even with --quiet
        sys.stderr.write(f"modalinfo batch: note: {len(group)} inputs are byte-identical "
                         f"(same SHA-256), analysed once, one row each: "
                         f"{', '.join(map(shown_name, group))}\n")
    if result.skipped:  # a warning: even with --quiet
        from modalinfo.io.formats import EXTENSIONS

        shown = (", ".join(map(shown_name, result.skipped[:5]))
                 + (", ..." if len(result.skipped) > 5 else ""))
        sys.stderr.write(f"modalinfo batch: note: {len(result.skipped)} file(s) of the input "
                         f"folders skipped, their extension is not a log's "
                         f"({' '.join(EXTENSIONS)}): {shown}; name them in a manifest "
                         f"with an 'fmt' column to analyse them\n")
    if result.unreadable:  # a warning: even with --quiet (round 18 PART b, U06)
        shown = (", ".join(map(shown_name, result.unreadable[:5]))
                 + (", ..." if len(result.unreadable) > 5 else ""))
        sys.stderr.write(f"modalinfo batch: note: {len(result.unreadable)} subfolder(s) of "
                         f"the input folders cannot be read (permission denied) and were "
                         f"skipped: {shown}; give read and search permission (chmod u+rx) "
                         f"or run as their owner to analyse them\n")
    manifests = getattr(result, "manifests", ())  # a result of before round 53 has none
    if manifests:  # a warning: even with --quiet (round 53 PART b, M16)
        shown = (", ".join(map(shown_name, manifests[:5]))
                 + (", ..." if len(manifests) > 5 else ""))
        sys.stderr.write(f"modalinfo batch: note: {len(manifests)} manifest(s) in the "
                         f"input folders not read as logs: {shown}; give a manifest as an "
                         f"input of its own to analyse the logs it names\n")
    removed = getattr(result, "removed_plots", ())
    if removed:  # a note: even with --quiet (files of the output folder went away)
        sys.stderr.write(f"modalinfo batch: note: removed {len(removed)} summary plot(s) of an "
                         f"earlier table from {shown_name(removed[0].parent)} "
                         f"({', '.join(p.name for p in removed)}): --no-plots drew none of "
                         "this table\n")
    kl_assumption_note(result.rows)  # a warning: even with --quiet
    layout_doubt_note(result.rows)
    refused = None  # a stdout that refuses the summary: said after the warnings below
    if not args.quiet:
        from modalinfo.common.cli import StdoutRefusedError, written_summary
        from modalinfo.common.tasks.rows import superseded_rows

        rep = result.report
        out = sys.stdout
        try:
            with written_summary():
                out.write(f"{rep.n_specs} tasks: {rep.n_skipped} already done, "
                          f"{rep.n_submitted} run ({rep.n_ok} ok, {rep.n_error} error, "
                          f"{rep.n_lost} lost) in {rep.elapsed:.1f} s\n")
                out.write(f"table: {result.n_ok} result rows, {result.n_error} error rows -> "
                          f"{shown_name(result.csv_path)}, {shown_name(result.parquet_path)}\n")
                rows_dir = result.csv_path.parent / "rows"
                stale = superseded_rows(rows_dir, result.rows, ("sha256", "analysis", "window"))
                if stale:
                    out.write(f"{stale} earlier row(s) in {shown_name(rows_dir)} of these "
                              "logs and analyses were not reused: another version of the "
                              "code or other settings wrote them (kept there, not in the "
                              "table)\n")
                for row in result.rows:
                    if row.get("status") != "ok":
                        # the path and message as the table's cells show them
                        out.write(f"error  {shown_name(row['path'])} [{row['analysis']}]: "
                                  f"{row.get('error_type')}: "
                                  f"{shown_message(str(row.get('error_message')), row['path'])}\n")
                for path in result.plots:
                    out.write(f"plot: {shown_name(path)}\n")
        except StdoutRefusedError as exc:
            refused = exc
    # a log whose frame pairs look swapped has no flagged frame, yet its order is a finding
    # the rows call "warned" (round 37 PART b, BQ1 / BQ2: such a log went without a word)
    flagged = [r for r in result.rows if r.get("status") == "ok"
               and ((r.get("quality_flagged_frames") or 0) > 0 or r.get("quality_pair_order"))]
    if flagged:  # warn is never silent: one line for the batch, the counts in the table
        logs = len({r["path"] for r in flagged})
        swapped = len({r["path"] for r in flagged if r.get("quality_pair_order")})
        sys.stderr.write(
            f"modalinfo batch: warning: {logs} log(s) have frames flagged by the quality "
            f"pass (outliers, glitched frames or stuck values"
            + (f"; frame pairs in reversed order in {swapped}" if swapped else "")
            + f"; columns quality_* of {quoted(result.csv_path)}); {_policies_applied(flagged)}\n")
    if result.n_error:
        from modalinfo.common.tasks.runner import lost_note

        lost = sum(r.get("status") == "lost" for r in result.rows)
        sys.stderr.write(
            f"modalinfo batch: {result.n_error} of {len(result.rows)} rows failed"
            + (f" ({lost} lost with their workers: run again to retry them){lost_note()}"
               if lost else "")
            + f"; see {quoted(result.csv_path)}\n")
    if refused is not None:
        raise refused
    return 1 if result.n_error else 0
