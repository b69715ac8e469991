"""Regenerate every figure of the paper, and write a report with the paper's numbers beside ours.

Usage::

    python -m paper_figures [--log LOG [input hints]] [--out out] [--overwrite]
                            [--only 1,2,3,4,5,6,7,8] [--quick] [--duration S] [--seed N]

Figures 1 and 5 analyse modal logs: by default both shipped KAOS-like logs, the
spectral one (``data/kaos_like_closed_loop.npz``) and the one the ``closedloop``
simulator wrote (``data/kaos_closedloop.npz``, files with the suffix ``_closedloop``);
``--log`` analyses a user's log instead (any format ``modalinfo.io`` reads, with the
input hints of every ``modalinfo`` command: ``--rate``, ``--in-units``, ``--in-modes``,
``--wavelength``, ``--fmt``, ... and ``--split-gaps`` for a log whose timestamps have
gaps). Figures 2-4
draw closed-loop MCAO runs of the paper's Table 1 (``closedloop`` preset ``table1``, one
atmosphere, every predictor; :mod:`paper_figures.closedloop_runs`), computed once and
shared: 0.5 s of simulated time by default, or with ``--quick`` 0.2 s on a 5x5 field
grid with the neural net trained for 50 iterations. Figure 6 (the compression x
prediction study the paper proposes) runs the ``kaos`` preset; ``--quick`` uses three
mode counts. Figure 7 (an extension: Figures 2-4 with the solar correlating sensor)
runs ``table1-solar`` beside the table1 runs (``--quick``: their reduced settings).
Figure 8 (an extension: transfer entropy between modes) maps the shipped
logs and a short ``table1-wind`` run (``--quick``: shorter). ``report.md`` and
``report.html`` (figures inline) open with a table of every headline number of the
paper beside ours, each difference explained.

``--quick`` is a smoke run (the test suite's), numbers not the paper's: besides the
reduced settings above, the closed-loop ARMA with AIC orders searches p, q <= 3 (not 5),
and Figure 5 evaluates the predictors on the first 5 modes of each log (the paper's NN
over 2 seeds).

All or nothing: options, logs and the output folder are checked before any work, and
the files are written into a temporary sibling folder moved into place at the end, so
a failed or interrupted run leaves the output folder as it was. One run per output
folder: a run holds ``<out>/.lock`` (the lock of ``modalinfo batch``) while it works, and
a second run into the same folder is refused (exit 2) rather than replacing its files.
"""

from __future__ import annotations

import contextlib
import importlib
import inspect
import platform
import re
import signal
import sys
import threading
import time
from pathlib import Path

from paper_figures import FIGURES, run_as, tell


def quoted(path: str | Path) -> str:
    """Return ``modalinfo.common.files.quoted(path)``, imported when first needed.

    The package (NumPy) must not load before the Ctrl-C guard is in place (round 3's x06).
    """
    from modalinfo.common.files import quoted as shown

    return shown(path)


#: the first line of the module docstring, kept for ``python -OO`` (which strips docstrings;
#: adversarial round 9 PART b, row E20)
_DESCRIPTION = ("Regenerate every figure of the paper, and write a report with the paper's "
                "numbers beside ours.")

DATA = Path(__file__).resolve().parent.parent / "data"
DEFAULT_LOG = DATA / "kaos_like_closed_loop.npz"
SIMULATED_LOG = DATA / "kaos_closedloop.npz"
#: (path, file suffix, key, description) of the logs of Figures 1 and 5 by default
SHIPPED_LOGS = (
    (DEFAULT_LOG, "", "spectral", "spectral KAOS-like log"),
    (SIMULATED_LOG, "_closedloop", "simulated", "simulated kaos closed-loop log"),
)


def _parse_only(text: str | None) -> list[int]:
    numbers = [int(label.split()[-1]) for _, label, _ in FIGURES]
    if text is None:
        return numbers
    try:
        given = [int(t) for t in text.split(",") if t.strip()]
    except ValueError:
        given = []
    if not given or any(c not in numbers for c in given):
        raise ValueError(f"--only must be a comma list of figure numbers "
                         f"{','.join(map(str, numbers))}; got '{text}'")
    twice = next((c for c in given if given.count(c) > 1), None)
    if twice is not None:  # merged silently before (one figure made)
        raise ValueError(f"--only names figure {twice} twice; give each once")
    return sorted(given)


def _not_made(modules) -> str:
    """Return the report's sentence naming the figures a partial run (``--only``) did not make.

    A report after ``--only 1`` held Figure 1's section alone and did not say that
    Figures 2-8 were not made (round 22 PART b, g15).
    """
    made = {label for _, label, _ in modules}
    missing = [label for _, label, _ in FIGURES if label not in made]
    if not missing:
        return ""
    return (f" A partial run (`--only`): made {', '.join(sorted(made))}; not made here: "
            f"{', '.join(missing)}.")


def _kind(module) -> str:
    if getattr(module, "NEEDS_RUNS", False):
        return "runs"
    return "log" if getattr(module, "NEEDS_LOG", True) else "own"


def _has_quick(module) -> bool:
    """Whether ``--quick`` changes this figure.

    The closed-loop and simulated figures all have a quick setting; of the log figures
    only those whose ``compute`` takes ``quick`` (Figure 5; Figure 1 has none: round 49
    PART b, P28).
    """
    if _kind(module) != "log":
        return True
    return "quick" in inspect.signature(module.compute).parameters


def _log_figures(modules) -> tuple[str, str]:
    """Return the chosen figures that read a log ("Figure 1", "Figures 1 and 5") and its verb.

    One copy for every sentence that names them: the gap refusal ("Figures 1 and 5
    needs" whatever --only chose: round 33 PART b) and the report's head ("Input logs of
    Figures 1 and 5" after ``--only 1``: leftovers 33-report).
    """
    chosen = [label.split()[-1] for module, label, _ in modules if _kind(module) == "log"]
    if len(chosen) == 1:
        return f"Figure {chosen[0]}", "needs"
    return f"Figures {', '.join(chosen[:-1])} and {chosen[-1]}", "need"


def _outputs(module, logs) -> list[str]:
    if _kind(module) == "log":
        return [name for _, suffix, _, _ in logs for name in module.output_names(suffix)]
    return [getattr(module, a) for a in ("FIGURE_NAME", "PDF_NAME", "JSON_NAME")
            if hasattr(module, a)]


def comparison_table(rows: list[tuple[str, tuple]]) -> str:
    """Markdown table of ``(figure, (quantity, paper, ours, why))`` rows."""
    lines = ["| figure | quantity | paper | ours | why they differ |", "|---|---|---|---|---|"]
    for figure, (quantity, paper, ours, why) in rows:
        lines.append(f"| {figure} | {quantity} | {paper} | {ours} | {why} |")
    return "\n".join(lines)


class _RefusedError(Exception):
    """A one-line refusal (exit status 2) found before any work."""


class _StdoutError(Exception):
    """Standard output refused a progress or final line (``> /dev/full``): exit status 1.

    Not an ``OSError``: ``naming_target`` took such an ENOSPC, which names no file, for
    the staged folder's and said "No space left on device writing 'OUT' ... free space or
    write elsewhere" (round 38 PART b, P48: the disk was not full). ``done``: the figures
    and reports were already in place.
    """

    def __init__(self, exc: OSError, done: bool = False) -> None:
        super().__init__(exc.strerror or str(exc))
        self.done = done


def _print(line: str, done: bool = False) -> None:
    """Print a progress line; a closed pipe is ignored, a refusing stdout is _StdoutError.

    The figures are the outputs: ``| head -1`` (the reader has what it wanted) lets the
    run go on with stdout discarded, as ``modalinfo``'s commands treat a closed pipe.
    """
    from modalinfo.common.cli import closed_pipe_discarded

    try:
        with closed_pipe_discarded():
            print(line, flush=True)
    except OSError as exc:
        raise _StdoutError(exc, done) from None


#: Input-hint options and their defaults: given without --log they would be ignored.
_HINT_DEFAULTS = {"fmt": None, "loop": None, "rate": None, "in_units": None,
                  "wavelength": None, "in_convention": None, "in_modes": None,
                  "nonfinite": "raise", "transpose": None, "dataset": None,
                  "split_gaps": False}


def _flag(dest: str) -> str:
    return "--" + dest.replace("_", "-")


def _no_shipped_data(path: Path, alternative: str) -> str:
    """Refuse a shipped log that is not there, naming why and the way out.

    An installed wheel carries the code, not data/ (adversarial round 24 PART b): no path
    inside site-packages is named as if the user had given it.
    """
    return (f"the shipped log data/{path.name} is not here ({quoted(path.parent)}): data/ is not "
            f"installed with the package; run from a clone of the repository "
            f"(pip install -e .) {alternative}")


def _check_args(args, modules, logs, needs_log) -> None:
    """Every refusal that needs no computation: options, log files, output folder."""
    from paper_figures._common import OutputError, check_out_dir

    if args.duration is not None and not 0 < args.duration < float("inf"):
        raise _RefusedError(f"--duration must be a number of seconds > 0; got {args.duration:g}")
    if args.seed is not None and not 0 <= args.seed <= 2**63 - 1:
        # closedloop stores the seed as an int64
        raise _RefusedError(f"--seed must be an int in [0, 2**63 - 1]; got {args.seed}")
    numbers = ",".join(label.split()[-1] for _, label, _ in modules)
    kinds = {_kind(module) for module, _, _ in modules}
    # an option no chosen figure reads was ignored silently (audit 9-files g01)
    if args.duration is not None and "runs" not in kinds:
        raise _RefusedError(f"--duration sets the closed-loop runs (Figures 2, 3, 4, 7); "
                            f"--only {numbers} makes none of them (add one, or drop --duration)")
    if args.seed is not None and not kinds & {"runs", "own"}:
        raise _RefusedError(f"--seed sets the simulated figures (2, 3, 4, 6, 7, 8); --only "
                            f"{numbers} makes none of them (add one, or drop --seed)")
    if args.quick and not any(_has_quick(module) for module, _, _ in modules):
        # the report said "with --quick (a smoke run on reduced settings: numbers not the
        # paper's)" of a Figure 1 made on the paper's settings (round 49 PART b, P28)
        raise _RefusedError(f"--quick reduces Figures 2-8 (Figure 5: its first 5 modes); "
                            f"--only {numbers} has no quick setting (add one, or drop --quick)")
    if args.seed is None:
        args.seed = 0
    if args.log is None:
        given = [_flag(d) for d, v in _HINT_DEFAULTS.items() if getattr(args, d, v) != v]
        if given:
            raise _RefusedError(f"{given[0]} describes a user's log and needs --log; the shipped "
                           "logs record it")
        if getattr(args, "outliers", "warn") != "warn":
            # ignored silently: the shipped logs are analysed as they are, no policy
            # applied (leftovers 33-report)
            raise _RefusedError(f"--outliers {args.outliers} applies to a user's log and needs "
                                "--log; the shipped logs are analysed as they are")
    elif not needs_log:
        raise _RefusedError(f"--log is read by Figures 1 and 5 only; --only {numbers} makes "
                       "neither (add 1 or 5, or drop --log)")
    if needs_log:
        for path, *_ in logs:
            if path.is_dir():
                raise _RefusedError(f"--log {quoted(path)} is a folder, not a log file")
            if not path.exists() and args.log is None:
                raise _RefusedError(_no_shipped_data(path, "or give your own log with "
                                                           "--log FILE"))
            if not path.exists():
                raise _RefusedError(f"log file {quoted(path)} does not exist")
            if not path.is_file():  # a FIFO or a device: reading it blocks or never ends
                raise _RefusedError(f"--log {quoted(path)} is not a regular file (a FIFO or a "
                                    "device); give a log file")
    for module, label, _ in modules:  # Figure 8 reads the shipped logs whatever --log says
        for _, path, *_ in getattr(module, "SHIPPED", ()):
            if not path.exists():
                raise _RefusedError(_no_shipped_data(path, f"or drop {label.split()[-1]} "
                                                           "from --only"))
    try:
        check_out_dir(args.out)
    except OutputError as exc:
        raise _RefusedError(str(exc)) from None


def _time_axis_uses(modules) -> str:
    """Name what of the chosen log figures needs the time axis ("Figure 5's predictors")."""
    return " and ".join(getattr(module, "TIME_AXIS_USE", f"{label}'s analyses")
                        for module, label, _ in modules if _kind(module) == "log")


def _kl_notes(log, path, modules) -> list[str]:
    """Say what the theoretical K-L of a chosen figure assumes that ``--log`` omits.

    Figure 1 orders ``kl-theory`` (its ``SPECS``) with the log's outer scale, else an
    infinite one: said as ``modalinfo fitting-error`` says it, in the words of
    ``modalinfo.ordering.compare.kl_geometry_assumption`` (left24-status; adversarial
    round 24 PART b, F31-F35).
    """
    from modalinfo.ordering.compare import kl_geometry_assumption

    labels = [label for module, label, _ in modules if _kind(module) == "log"
              and any(basis == "kl-theory" for basis, _ in getattr(module, "SPECS", ()))]
    what = kl_geometry_assumption(log) if labels else None
    if what is None:
        return []
    return [f"{quoted(Path(path).name)} records {what}: {', '.join(labels)}"]


def _load_logs(args, logs, modules) -> dict:
    """Read the logs of Figures 1 and 5 and refuse one a chosen figure cannot use."""
    from modalinfo.cli.shared import input_notes, load_log_with_hints, split_gaps
    from modalinfo.common.cli import CommandError
    from paper_figures._common import check_log_for, log_source, user_log_outliers

    loaded = {}
    notes: list[str] = []  # printed once every check passed: a refusal stays one line
    for path, suffix, key, desc in logs:
        outliers = None  # the shipped logs: no policy applied, nothing to state
        try:
            # a user's log with the CLI's input hints; the shipped ones as they are
            log = load_log_with_hints(path, args if key == "user" else None, announce=False)
            if key == "user":
                args._notes = []
                # the chosen figures that read the log
                log = split_gaps(log, args, path, *_log_figures(modules))
                # --outliers as in every command and in the stand-alone scripts (one
                # copy); no drop, naming what needs the time axis (leftovers 33-report);
                # stated in the figures' reports too, not only on stderr (round 33 PART
                # b, B31): the policy and its counts
                log, outliers = user_log_outliers(log, args, path, _time_axis_uses(modules))
                # what was assumed, cut or flagged, as the CLI says it
                notes += input_notes(log, path) + [
                    re.split(r": (?:note|warning): ", n, maxsplit=1)[-1] for n in args._notes]
                notes += _kl_notes(log, path, modules)
        except (CommandError, ValueError, TypeError, OSError, KeyError) as exc:
            from modalinfo.cli import cli_words
            from modalinfo.common.files import error_line

            # in command-line words, as modalinfo's commands say it ("loop=UID (command
            # line: --loop UID)" was printed as is: round 10 PART b, row Z26)
            message = error_line(exc, repr(exc))
            raise _RefusedError(f"--log: {cli_words(message)}") from None
        for module, label, _ in modules:
            if _kind(module) != "log":
                continue
            try:
                check_log_for(module, log)
            except ValueError as exc:
                message = str(exc).strip().splitlines()[0].replace("`log`", "the log")
                where = "--log" if key == "user" else f"shipped log {quoted(path)}"
                raise _RefusedError(f"{label} on {where}: {message}") from None
        loaded[key] = ((log, log_source(path)), suffix, desc, outliers)
    for note in notes:
        tell("note", note)
    return loaded


def main(argv: list[str] | None = None) -> int:
    """Make every figure, ``report.md`` and ``report.html``; return the exit status.

    Everything that needs no computation is checked first (options, log files, each
    log against the figures that read it, the output folder: a folder, writable, with
    free space, no file replaced without ``--overwrite``). The figures are then
    written into a temporary sibling folder that is moved into place only when every
    figure and the report are done: a failed or interrupted run leaves the output
    folder as it was. Exit status: 0 done, 2 refused (one line on stderr), 1 a
    failure while computing or writing (nothing written), 130 Ctrl-C, 143 SIGTERM,
    129 SIGHUP, 138 SIGUSR1 (128 + the signal, as every command).
    """
    from modalinfo.common.cli import (
        EXIT_FAILURE,
        EXIT_INTERRUPTED,
        EXIT_USAGE,
        Parser,
        add_version_argument,
        folder_arg,
        say,
    )

    prog = _prog()
    parser = Parser(prog=prog, description=(__doc__ or _DESCRIPTION).split("\n")[0])
    add_version_argument(parser)
    parser.add_argument(
        "--log", type=Path, default=None,
        help="modal log for Figures 1 and 5 (default: both shipped KAOS-like logs)",
    )
    parser.add_argument(
        "--out", type=folder_arg, default=Path("out"), help="output directory (default: out)"
    )
    parser.add_argument("--overwrite", action="store_true",
                        help="replace figures and report already in the output directory")
    parser.add_argument("--only", default=None,
                        help="comma-separated figure numbers to make (default: all)")
    parser.add_argument("--quick", action="store_true",
                        help="a smoke run, numbers not the paper's: reduced closed-loop "
                             "settings for Figures 2-4, 6, 7 and 8, Figure 5's evaluation on "
                             "the first 5 modes")
    parser.add_argument("--duration", type=float, default=None,
                        help="simulated time of the closed-loop runs of Figures 2-4 and 7 [s] "
                             "(default 0.5, quick 0.2)")
    parser.add_argument("--seed", type=int, default=None,
                        help="atmosphere of the closed-loop runs (default 0)")
    from modalinfo.cli.shared import add_gap_argument, add_hint_arguments

    # the same input hints as every modalinfo command, for --log
    add_hint_arguments(parser)
    add_gap_argument(parser)
    parser.set_defaults(command="paper_figures")
    args = parser.parse_args(argv)
    # the command line as typed, for the record every figure carries
    args._argv = [prog, *(sys.argv[1:] if argv is None else [str(a) for a in argv])]
    previous: dict = {}
    if threading.current_thread() is threading.main_thread():
        # `kill` / a batch system's time limit / a closed terminal / SIGUSR1: clean up as
        # for Ctrl-C (the temporary folder is removed, the output folder stays as it was);
        # a signal the caller ignores or handles stays so (SIGTERM excepted, as before)
        from modalinfo.common.files import terminating_signals

        for signum in terminating_signals():
            if signum == signal.SIGTERM or signal.getsignal(signum) is signal.SIG_DFL:
                previous[signum] = signal.signal(signum, _terminated)
    try:
        with run_as(prog):
            return _run(args)
    except _RefusedError as exc:
        say(f"{prog}: error: {exc}\n")
        return EXIT_USAGE
    except _StdoutError as exc:
        kept = (f"the figures and reports in {quoted(args.out)} are complete" if exc.done
                else f"{quoted(args.out)} is as it was")
        say(f"{prog}: error: could not write standard output ({exc}); {kept}\n")
        return EXIT_FAILURE
    except KeyboardInterrupt as exc:  # Ctrl-C, or SIGTERM etc. (_terminated): 130 or 128 + n
        what = "terminated" if isinstance(exc, _Terminated) else "interrupted"
        tell(None, f"{what}; {quoted(args.out)} is as it was")
        return exc.code if isinstance(exc, _Terminated) else EXIT_INTERRUPTED
    except (OSError, MemoryError) as exc:
        what = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        say(f"{prog}: error: {type(exc).__name__}: {what or 'no detail'}{_limit_note(exc)}"
            f"; {quoted(args.out)} is as it was\n")
        return EXIT_FAILURE
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


def _limit_note(exc: BaseException) -> str:
    """Name the process limit behind a write past ``ulimit -f`` or a lack of memory.

    "OSError: File too large" under ``ulimit -f 100`` and "MemoryError: Unable to
    allocate 11.4 MiB" under ``ulimit -d 300000`` named no limit (adversarial round 50
    PART b, R85, R88); the other commands' lines name them.
    """
    import errno

    from modalinfo.common.files import file_size_limit_text
    from modalinfo.common.memory import memory_limits_text

    if isinstance(exc, OSError) and exc.errno == errno.EFBIG:
        limit = file_size_limit_text()
    elif isinstance(exc, MemoryError) or (isinstance(exc, OSError)
                                          and exc.errno == errno.ENOMEM):
        limit = memory_limits_text()
    else:
        return ""
    return f" ({limit}: raise it)" if limit else ""


def _prog() -> str:
    """Return the program name as typed, which starts every refusal (argparse's, its own).

    The console script `paper-figures` is named as typed, not `python -m paper_figures`
    (round 16 PART b, I24: its usage and errors named the other spelling); the command's
    own refusals said "paper_figures: error:" beside argparse's (fixes 45-c, round 44
    PART b c08: one program, two names).
    """
    from paper_figures import program

    return program()


class _Terminated(KeyboardInterrupt):
    """SIGTERM (or SIGHUP, SIGUSR1 ...), unwound as Ctrl-C is but reported as 128 + n.

    ``signum`` is the signal: one dropped in a C callback (numba's compile) is delivered
    again as that signal by ``modalinfo.common.startup.keep_interrupts``, not as a
    Ctrl-C (read56: without it a SIGTERM came back as SIGINT, 130 "interrupted").
    """

    def __init__(self, signum: int = signal.SIGTERM) -> None:
        super().__init__(signum)
        self.signum = int(signum)
        self.code = 128 + int(signum)  # the shell's convention: 143 for SIGTERM


def _terminated(signum, frame) -> None:
    raise _Terminated(signum)


def _run(args) -> int:
    from paper_figures._common import OutputError, locked_output

    try:
        only = _parse_only(args.only)
    except ValueError as exc:
        raise _RefusedError(str(exc)) from None
    chosen = [(name, label, title) for name, label, title in FIGURES
              if int(label.split()[-1]) in only]
    modules = [(importlib.import_module(f"paper_figures.{name}"), label, title)
               for name, label, title in chosen]
    needs_log = any(_kind(m) == "log" for m, _, _ in modules)
    logs = (SHIPPED_LOGS if args.log is None
            else ((args.log, "", "user", "user log"),))
    _check_args(args, modules, logs, needs_log)
    with contextlib.ExitStack() as stack:
        # one run per output folder (two would replace each other's files unasked)
        try:
            stack.enter_context(locked_output(args.out))
        except OutputError as exc:
            raise _RefusedError(str(exc)) from None
        return _run_locked(args, modules, logs, needs_log)


def _run_locked(args, modules, logs, needs_log) -> int:
    """Refuse existing outputs, then make the figures (``_run`` holds the folder)."""
    from paper_figures._common import staged_output

    report_path = args.out / "report.md"
    html_path = args.out / "report.html"
    outputs = [report_path, html_path] + [args.out / name for module, _, _ in modules
                                          for name in _outputs(module, logs)]
    folders = [path for path in outputs if path.is_dir()]
    if folders:
        raise _RefusedError(f"{quoted(folders[0])} is a folder; the run writes a file of that name")
    existing = [path for path in outputs if path.exists()]
    if existing and not args.overwrite:
        raise _RefusedError(f"{quoted(existing[0])} exists; pass --overwrite to replace it")
    loaded = _load_logs(args, logs, modules) if needs_log else {}
    from paper_figures._common import shipped_edit_note

    for path, _, _, _ in logs if needs_log else ():
        note = shipped_edit_note(path)
        if note:  # said before the work as well as in the report's head
            tell("warning", f"{quoted(path)}: {note}")
    import matplotlib

    from modalinfo.common.plotting import rc_overrides
    from modalinfo.common.quiet import recording

    # the user's matplotlibrc, less what cannot draw here (usetex without LaTeX, a
    # missing font: round 19 PART b), said in one line each as every other warning;
    # this thread's only (fixes 41-c: catch_warnings took other threads' warnings)
    with recording() as caught:
        overrides = rc_overrides()
    for warning in caught:
        tell("warning", str(warning.message))
    from modalinfo.common.provenance import provenance
    from paper_figures._common import figure_record

    # what made the figures (version with its source fingerprint, command, seed, the
    # input logs' SHA-256), in each PNG / PDF and on report.md's first line
    record = provenance(getattr(args, "_argv", None), seed=args.seed,
                        inputs=[p for p, _, _, _ in logs] if needs_log else None)
    with (staged_output(args.out) as stage, matplotlib.rc_context(overrides),
          figure_record(record)):
        _make(args, modules, loaded, logs, needs_log, stage, record)
    from modalinfo.common.files import shown_name

    _print(f"[paper_figures] report written to {shown_name(report_path)} and "
           f"{shown_name(html_path)}", done=True)
    return 0


def _make(args, modules, loaded, logs, needs_log, stage: Path, record: dict) -> None:
    """Compute and draw every chosen figure into ``stage``, then the two reports.

    ``record`` is the run's provenance (``modalinfo.common.provenance.provenance``,
    with ``inputs`` the logs' fingerprints in the order of ``logs``).
    """
    sections: list[str] = []
    rows: list[tuple[str, tuple]] = []
    per_log: dict[str, dict] = {}
    runs = None
    total_start = time.perf_counter()
    for module, label, title in modules:
        start = time.perf_counter()
        kind = _kind(module)
        if kind == "runs" and runs is None:
            from paper_figures import closedloop_runs

            _print(f"[paper_figures] closed-loop runs for Figures 2-4"
                   f"{' (quick)' if args.quick else ''} ...")
            try:
                runs = closedloop_runs.compute(quick=args.quick, duration=args.duration,
                                               seed=args.seed)
            except ValueError as exc:  # a run the simulator refuses (--duration, memory)
                raise _RefusedError(f"closed-loop runs of Figures 2-4: "
                                    f"{str(exc).splitlines()[0]}") from None
            elapsed = time.perf_counter() - start
            _print(f"[paper_figures] closed-loop runs done in {elapsed:.1f} s")
            sections.append(closedloop_runs.report_section(runs, elapsed))
            start = time.perf_counter()
        _print(f"[paper_figures] {label}: {title} ...")
        if kind == "log":
            texts = []
            # --quick reaches the log figures that have a quick setting (Figure 5)
            params = inspect.signature(module.compute).parameters
            quick = {"quick": True} if args.quick and _has_quick(module) else {}
            for key, ((log, source), suffix, desc, outliers) in loaded.items():
                # what --outliers did to a user's log, for the figures that report it
                said = ({"outliers": outliers} if outliers is not None
                        and "outliers" in params else {})
                try:
                    result = module.compute(log, source=source, **quick, **said)
                except ValueError as exc:
                    if key != "user":
                        raise
                    # a user's log the figure cannot use (found while computing): one line
                    raise _RefusedError(f"{label} on --log: {str(exc).splitlines()[0]}") from None
                module.plot(result, stage, suffix=suffix)
                text = module.report(result, suffix=suffix)
                if len(loaded) > 1:
                    # one section per log: say which in the heading
                    text = text.replace(f"## {label}:", f"## {label} ({desc}):", 1)
                texts.append(text)
                per_log.setdefault(label, {})[key] = result
                tag = f"{label} ({desc})" if len(loaded) > 1 else label
                rows += [(tag, row) for row in module.table_rows(result)]
            text = "\n".join(texts)
        else:
            try:
                if kind == "runs":
                    result = module.compute(runs)
                else:
                    result = module.compute(quick=args.quick, seed=args.seed)
            except ValueError as exc:  # e.g. a run the simulator refuses (memory, length)
                raise _RefusedError(f"{label}: {str(exc).splitlines()[0]}") from None
            module.plot(result, stage)
            text = module.report(result)
            rows += [(label, row) for row in module.table_rows(result)]
        elapsed = time.perf_counter() - start
        _print(f"[paper_figures] {label} done in {elapsed:.1f} s")
        sections.append(text.rstrip() + f"\n\n_({label} made in {elapsed:.1f} s.)_\n")
    if needs_log and {"spectral", "simulated"} <= set(loaded):
        from paper_figures import logs_compared

        cmp = logs_compared.compute(loaded["spectral"][0][0], loaded["simulated"][0][0])
        sections.append(logs_compared.report(cmp, per_log.get("Figure 1"),
                                             per_log.get("Figure 5")))
    total = time.perf_counter() - total_start
    from paper_figures._common import markdown_path, shipped_edit_note

    # what made the numbers: the code's version (with its source fingerprint) and the
    # input logs' SHA-256 (adversarial round 27 PART b, P19; left27-geometry), on the
    # line the golden numbers skip (it names the machine)
    head = [
        "# modalinfo: regenerated figures of Stangalini et al., LOST MCAO simulations\n",
        f"Python {platform.python_version()}, {platform.machine()}; modalinfo "
        f"{record['modalinfo']} (git {record.get('git') or 'unknown'}, source SHA-256 "
        f"{record.get('source_sha256') or 'unknown'} of modalinfo, closedloop and "
        f"paper_figures); made in {total:.0f} s"
        + (" with `--quick` (a smoke run on reduced settings: numbers not the paper's)"
           if args.quick else "") + "."
        + _not_made(modules)
        + (f" Input log{'s' if len(logs) > 1 else ''} of {_log_figures(modules)[0]}: "
           + ", ".join(f"{markdown_path(p)} ({d}; SHA-256 {made['sha256']}"
                       + (f"; {note}" if (note := shipped_edit_note(p, made["sha256"]))
                          else "") + ")"
                       for (p, _, _, d), made in zip(logs, record["inputs"], strict=True))
           + "." if needs_log else "")
        + "\n",
        "## The paper's numbers beside ours\n",
        "Every number in the *ours* column is computed by this run (the paper's column "
        "quotes the paper); the last column says why they differ.\n",
        comparison_table(rows) + "\n",
    ]
    from paper_figures._html import report_html

    text = "\n".join(head + sections)
    (stage / "report.md").write_text(text, encoding="utf-8")
    (stage / "report.html").write_text(report_html(text, stage), encoding="utf-8")


if __name__ == "__main__":
    from modalinfo.common.startup import (
        exit_quietly,
        import_refusal,
        keep_interrupts,
        memory_refusal,
        one_line_warnings,
        require_current_folder,
        warning_refusal,
    )

    require_current_folder(_prog())  # before the heavy imports
    one_line_warnings(_prog())  # a warning while the package loads: one line
    # a Ctrl-C (or a SIGTERM) dropped in a C callback (numba's compile) still ends the
    # run (read56: fix55-a had hooked modalinfo's and closedloop's __main__ only)
    keep_interrupts()
    try:
        code = main()
    except KeyboardInterrupt:  # Ctrl-C before main's own handler (its imports)
        sys.stderr.write(f"{_prog()}: interrupted\n")
        code = 130
    except (MemoryError, OSError) as exc:  # out of memory (ulimit -v) while loading numba
        code = memory_refusal(_prog(), exc)
    except Warning as exc:  # raised as an error (-W error) while the package loads
        code = warning_refusal(_prog(), exc)
    except ImportError as exc:  # NUMBA_NUM_THREADS=0, or a library not mapped (ulimit -v)
        code = import_refusal(_prog(), exc)
    exit_quietly(code)
