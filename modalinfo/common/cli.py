"""The command-line base every command of every package stands on.

Part of the ground floor (:mod:`modalinfo.common`): ``modalinfo``, ``closedloop`` and
``python -m paper_figures`` report errors the same way.

- :class:`Parser`: ``argparse`` reporting a usage error as one line (exit 2);
- :class:`CommandError` and :func:`dispatch`: an input error is one line on stderr and
  exit status 2, never a traceback; Ctrl-C is 130, SIGTERM during a save 143;
- :func:`check_output`: an output file checked before any work;
- :func:`check_cluster_args`: the Dask options of ``modalinfo batch`` and ``closedloop
  sweep`` checked before any cluster starts.

Exit statuses (the shell's conventions): :data:`EXIT_OK` 0, :data:`EXIT_FAILURE` 1 (the
work ran and failed), :data:`EXIT_USAGE` 2 (refused before any work),
:data:`EXIT_INTERRUPTED` 130 (128 + SIGINT), :data:`EXIT_TERMINATED` 143 (128 + SIGTERM,
raised by :func:`modalinfo.common.files.atomic_write`).
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import io
import os
import re
import sys
from collections.abc import Iterator
from pathlib import Path

from modalinfo.common.deps import MissingDependencyError, require_dist
from modalinfo.common.files import (
    SHOWN_ERRORS,
    OutputGoneError,
    check_not_special,
    error_line,
    files_written,
    quoted,
    shown_errors,
    writable_free_bytes,
)
from modalinfo.common.startup import command_line_text, one_line_format
from modalinfo.common.tasks.cluster import check_memory_limit, check_worker_count

__all__ = [
    "EXIT_FAILURE",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "EXIT_TERMINATED",
    "EXIT_USAGE",
    "CommandError",
    "Parser",
    "StdoutEncodingError",
    "StdoutRefusedError",
    "add_version_argument",
    "check_cluster_args",
    "check_not_folder",
    "check_output",
    "closed_pipe_discarded",
    "discard_stdout",
    "dispatch",
    "folder_arg",
    "interrupted",
    "say",
    "write_stdout",
    "written_summary",
]

#: Exit statuses of every command.
EXIT_OK = 0
EXIT_FAILURE = 1
EXIT_USAGE = 2
EXIT_INTERRUPTED = 130
EXIT_TERMINATED = 143


class CommandError(Exception):
    """An input error a subcommand reports as one line and exit status 2."""


class StdoutRefusedError(OSError):
    """Standard output refused the summary of outputs already written (exit status 1)."""


class StdoutEncodingError(StdoutRefusedError):
    r"""Standard output's encoding cannot hold a character the command prints (exit status 1).

    Raised by stdout's error handler (:func:`modalinfo.common.files.shown_errors`), so
    only a write to standard output raises it: a ``UnicodeEncodeError`` of the input's
    reading stays an input error. Under ``PYTHONIOENCODING=ascii`` a mode label ``Tip_é``
    or an output named ``e27_é.npz`` ended the command with "'ascii' codec can't encode
    character '\xe9' ..." and status 2, "an input error", after its files were written
    (round 45 PART b, E02-E30).
    """

    def __init__(self, exc: UnicodeEncodeError) -> None:
        char = exc.object[exc.start]
        source = ("PYTHONIOENCODING" if os.environ.get("PYTHONIOENCODING", "").split(":")[0]
                  else "the locale, LC_ALL / LC_CTYPE / LANG")
        super().__init__(errno.EILSEQ, f"its encoding {exc.encoding} (from {source}) cannot "
                         f"encode {char!r} (U+{ord(char):04X}); set PYTHONIOENCODING=utf-8 "
                         "or a UTF-8 locale to print it")


def _refuse_stdout(exc: UnicodeEncodeError) -> None:
    """Stdout's encoding refused a character: :class:`StdoutEncodingError` (see there)."""
    raise StdoutEncodingError(exc) from None


@contextlib.contextmanager
def written_summary() -> Iterator[None]:
    """Mark the block as printing, on stdout only, the summary of outputs already written.

    A stdout that refuses it (``> /dev/full``) said "error: [Errno 28] No space left on
    device" with status 2, the status of an input error, after ``convert``, ``synth``,
    ``batch``, ``closedloop run --out`` and ``export`` had written complete files: the
    line named neither standard output nor the files (round 38 PART b, W3). The error
    is re-raised as :class:`StdoutRefusedError`, which :func:`dispatch` reports as a
    failure to write standard output (status 1, as ``--help > /dev/full``). A closed
    pipe (``| head -1``) stays the reader's choice.
    """
    try:
        yield
    except BrokenPipeError:
        raise
    except StdoutRefusedError:
        raise
    except OSError as exc:
        raise StdoutRefusedError(exc.errno, exc.strerror or str(exc)) from None


def write_stdout(text: str) -> None:
    """Write ``text`` on stdout; a stdout that refuses it is :class:`StdoutRefusedError`.

    For a command whose whole output is stdout (``info``): ``> /dev/full`` said
    "error: [Errno 28] No space left on device" with status 2, the status of an input
    error, naming no stream (round 47, fixes 47-e item 3); :func:`dispatch` now says
    "could not write standard output" with status 1. Only the write is judged: an
    ``OSError`` reading the log between two writes stays the input's error.
    """
    with written_summary():
        sys.stdout.write(text)


_URL = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]+:(//|/)|^file:", re.ASCII)
#: arguments read as strings that name a file or a folder (others are typed ``Path``)
_PATH_DESTS = frozenset({"log", "input", "output", "out", "inputs", "extra"})
_WINDOWS = re.compile(r"^([A-Za-z]:[\\/]|\\\\)", re.ASCII)


def path_problem(text: str) -> str | None:
    """Why ``text`` cannot be a local path on this system, or None if it can be one.

    Parameters
    ----------
    text : str
        A path as the user typed it.

    Returns
    -------
    str or None
        The reason (an empty path, a URL, a Windows drive or UNC path, a name longer than
        the file system allows), to follow the quoted path in a one-line message.
    """
    if text == "":
        return "is an empty path; give a file or folder name"
    if text == "-":
        # the Unix "standard input / output" name: it was read as a missing file, and
        # forecast --out - made a folder named '-' (round 23 PART b, o08 / o29)
        return ("means standard input / output, which is not supported; give a file or "
                "folder name (./- for a file named '-')")
    if _URL.match(text):
        return "is a URL; only local paths are read or written (download the file first)"
    if _WINDOWS.match(text):
        return ("is a Windows path; on this system write it with '/' from a mounted "
                "folder (e.g. /mnt/c/...)")
    try:
        limit = os.pathconf(".", "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):
        limit = 255
    for part in text.split("/"):
        size = len(os.fsencode(part))
        if size > limit:
            return f"has a name of {size} bytes; the file system allows {limit}"
    return None


class Parser(argparse.ArgumentParser):
    """argparse that reports usage errors in one line (argparse prints usage first)."""

    def error(self, message: str):  # noqa: D102
        say(f"{self.prog}: error: {self._no_such_option(message)}"
            f"{self._dash_value_hint(message)}\n")
        raise SystemExit(EXIT_USAGE)

    @staticmethod
    def _no_such_option(message: str) -> str:
        """Say that an option is not the command's when argparse calls it "ambiguous".

        A prefix shared by several options (allow_abbrev) was "ambiguous option: --out
        could match --outer-scale, --outliers" for ``fitting-error --out``, a command
        without ``--out``: the words pointed at two options that mean something else
        (round 52 PART b, Left). A unique prefix still stands for its option.
        """
        found = re.fullmatch(r"ambiguous option: (-[^=\s]+)(?:=.*)? could match (.+)", message,
                             re.DOTALL)
        if found is None:
            return message
        name, matches = found.groups()
        return (f"no option {name} (it is the start of {matches}: write the option meant in "
                "full; --help lists them)")

    def parse_args(self, args=None, namespace=None):  # noqa: D102
        parsed, extras = self.parse_known_args(args, namespace)
        if extras:
            # arguments a subcommand's parser left were reported by the top-level parser,
            # "closedloop: error: unrecognized arguments: --quiet" for `closedloop export
            # ... --quiet` (round 52 PART b, Left): report them as the subcommand's
            chosen = self
            for action in self._actions:
                if isinstance(action, argparse._SubParsersAction):
                    chosen = action.choices.get(getattr(parsed, action.dest, None), self)
            chosen.error(f"unrecognized arguments: {' '.join(extras)}")
        return parsed

    def _dash_value_hint(self, message: str) -> str:
        """Explain argparse's "expected one argument" when the value was there.

        ``--memory-limit -0GB`` (or ``--target -Z2``) reads the value as an option, so
        argparse said "expected one argument" of an option given one (round 19 PART b,
        N29). Name the value and the ``--option=value`` spelling that passes it.
        """
        found = re.match(r"argument (\S+?)(?:/\S+)?: expected one argument$", message)
        argv = getattr(self, "_argv", [])
        if not found:
            return ""
        for k, token in enumerate(argv[:-1]):
            value = argv[k + 1]
            if (token == found.group(1) and value.startswith("-")
                    and value.partition("=")[0] not in self._option_string_actions):
                return (f" (its value {value!r} starts with '-' and was read as an option: "
                        f"write {token}={value})")
        return ""

    def _print_message(self, message, file=None):
        """Write help or usage; a stream that refuses it is an error, not a silent exit 0.

        argparse swallows ``OSError`` here, so ``--help > /dev/full`` lost the help and
        exited 0 (audit 10-env). A closed pipe (``| head -1``) stays quiet, as in
        :func:`dispatch`; any other failure is one line on stderr and exit status 1.
        """
        if not message:
            return
        file = file or sys.stderr
        try:
            file.write(message)
            file.flush()
        except BrokenPipeError:
            pass  # the reader has what it wanted; dispatch silences the flush at exit
        except OSError as exc:
            with contextlib.suppress(OSError):
                sys.stderr.write(f"{self.prog}: error: could not write the output: {exc}\n")
            raise SystemExit(EXIT_FAILURE) from None

    def _get_value(self, action, arg_string):
        r"""Refuse a path no local file can have, naming the argument (round 22 PART b).

        A URL (``s3://b/a.npz``) was reported as "no such file: 's3:/b/a.npz'" (its '//'
        folded by ``Path``), a Windows path for an output (``C:\out\b.npz``) was
        written as one odd file in the current folder, an empty path read the current
        folder, and a name over the file system's limit was a bare "[Errno 36]".
        """
        folder = getattr(action.type, "__name__", "") == "folder_arg"
        if (action.type is Path or folder or (action.type is None and action.dest in _PATH_DESTS)) \
                and not (folder and arg_string == ""):  # folder_arg words the empty name
            problem = path_problem(arg_string)
            if problem:
                raise argparse.ArgumentError(action, f"'{arg_string}' {problem}")
        return super()._get_value(action, arg_string)

    def parse_known_args(self, args=None, namespace=None):  # noqa: D102
        args = sys.argv[1:] if args is None else list(args)
        if args[-1:] == ["--"] and args.count("--") == 1:
            # POSIX: '--' ends the options, and nothing may follow it; argparse refused
            # a trailing one as "unrecognized arguments: --" (round 15 PART b, S02)
            args = args[:-1]
        self._argv = args
        self._refuse_conflicting_repeats(args)
        return super().parse_known_args(args, namespace)

    def _full_option_name(self, name: str) -> str:
        """Return the option a unique abbreviation stands for (``--hor``: ``--horizon``).

        argparse accepts unique prefixes (allow_abbrev), so ``--hor 1 --hor 2`` or
        ``--horizon 1 --hor 2`` was one option given twice that the repeat check, which
        looked names up exactly, let through: the last value won without a word
        (round 23 PART b, o27 / o38 / o39 / o44). An unknown or ambiguous prefix is
        returned as typed (argparse words its own error).
        """
        if not name.startswith("--") or name in self._option_string_actions \
                or not self.allow_abbrev:
            return name
        matches = [s for s in self._option_string_actions if s.startswith(name)]
        if len({id(self._option_string_actions[s]) for s in matches}) == 1:
            return matches[0]
        return name

    def _refuse_conflicting_repeats(self, args: list[str]) -> None:
        """Refuse a single-value option given twice with different values.

        argparse keeps the last silently, so ``--target Z2 --target Z3`` analysed Z3
        without a word. The same value twice, flags and append options (``--set``)
        stay allowed; a subcommand's options are checked by its own parser. An action
        class with ``stores_value = True`` (an old spelling storing the same ``dest``,
        ``--modes`` for ``--in-modes``) counts as the option it stands for.
        """
        seen: dict[str, tuple[str, str]] = {}
        for k, token in enumerate(args):
            if token == "--":
                break
            name, eq, value = token.partition("=")
            name = self._full_option_name(name)
            action = self._option_string_actions.get(name) if name.startswith("-") else None
            flag = _flag_value(action, name)
            if flag is not None:
                # two flags of one setting (--transpose --no-transpose): the last won
                first = seen.setdefault(action.dest, (name, flag))
                if first[1] != flag:
                    self.error(f"argument {name}: contradicts {first[0]}; give one of them")
                continue
            stores = type(action) is argparse._StoreAction or getattr(action, "stores_value",
                                                                      False)
            if not stores or action.nargs is not None:
                continue
            if not eq:
                if k + 1 >= len(args):
                    continue
                value = args[k + 1]
            first = seen.setdefault(action.dest, (name, value))
            if first[1] != value:
                # '300 ' and '300' printed alike: quote values that differ in white space
                # only (round 44 PART b, a07)
                spaces = first[1].strip() == value.strip()
                shown = repr if spaces else str
                self.error(f"argument {name}: given twice ({first[0]} {shown(first[1])} and "
                           f"{name} {shown(value)}"
                           f"{', which differ in white space' if spaces else ''}); "
                           "give it once")


class _VersionAction(argparse.Action):
    """``--version``: the build's version on stdout, exit 0 (computed only when asked)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS,
                 help="print the version of the installed code and exit"):  # noqa: A002
        super().__init__(option_strings=option_strings, dest=dest, default=default,
                         nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):  # noqa: D102
        from modalinfo.common.tasks.keys import package_version

        parser._print_message(f"{parser.prog} {package_version()}\n", sys.stdout)
        parser.exit()


def add_version_argument(parser: argparse.ArgumentParser) -> None:
    """Give a top-level parser ``--version`` (stdout, exit 0).

    The version is ``modalinfo.common.tasks.keys.package_version()``, the one batch
    and sweep rows record, so a user can match a folder to the code that wrote it.
    Without it ``modalinfo --version`` was a usage error, exit 2 (round 17 PART b, V01).
    """
    parser.add_argument("--version", action=_VersionAction)


def _flag_value(action, name: str) -> str | None:
    """Return the value a flag sets (``--transpose``: True, ``--no-transpose``: False).

    None for an option that takes a value (checked by its own rule) and for a flag
    that only counts or appends.
    """
    if isinstance(action, argparse.BooleanOptionalAction):
        return repr(not name.startswith("--no-"))
    if isinstance(action, argparse._StoreConstAction):  # store_true / store_false too
        return repr(action.const)
    return None


def dispatch(parser: argparse.ArgumentParser, argv: list[str] | None, prog: str,
             words=None) -> int:
    """Parse ``argv`` and run the chosen subcommand's ``_run``; return the exit status.

    Shared by ``modalinfo`` and ``closedloop``: queued notes after success, one line on
    stderr and status 2 for an input error (through ``words``, which rewrites library
    names in command-line terms), a quiet exit for a closed pipe, 130 for Ctrl-C.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The command's parser (a :class:`Parser`); each subcommand sets ``_run(args) -> int``.
    argv : list of str or None
        The arguments (None: ``sys.argv[1:]``).
    prog : str
        The command's name, starting every error line (``"closedloop"``).
    words : callable, optional
        ``words(message) -> message``: library names said in command-line terms.

    Returns
    -------
    int
        The exit status: the subcommand's, or :data:`EXIT_USAGE`, :data:`EXIT_INTERRUPTED`.
    """
    _open_closed_streams()
    # a file name with bytes that are not UTF-8 is printed as the batch table writes it
    # (\xff), whichever line prints it: the streams' own handlers wrote \udcff on
    # stderr and the raw byte on stdout (left13-cli)
    previous = _show_bad_bytes()
    try:
        return _dispatch(parser, argv, prog, words)
    finally:
        for stream, errors in previous:
            with contextlib.suppress(Exception):
                stream.reconfigure(errors=errors)


def _show_bad_bytes() -> list:
    """Give stdout and stderr the :func:`shown_errors` handler; return what to restore.

    Each keeps its own handler for the characters its encoding cannot hold (a user's
    ``PYTHONIOENCODING=ascii:replace``); where that handler refuses one, stdout raises
    :class:`StdoutEncodingError` and stderr writes it backslash-escaped.
    """
    previous = []
    for stream, refuse in ((sys.stdout, _refuse_stdout), (sys.stderr, None)):
        errors = getattr(stream, "errors", None)
        if not isinstance(errors, str) or errors.startswith(SHOWN_ERRORS) \
                or not hasattr(stream, "reconfigure"):
            continue
        try:
            stream.reconfigure(errors=shown_errors(errors, refuse))
        except (ValueError, OSError, LookupError, io.UnsupportedOperation):  # a stream
            continue  # that cannot
        previous.append((stream, errors))
    return previous


def _memory_advice(args: argparse.Namespace) -> str:
    """Say what may help after a ``MemoryError``: the process memory limits, the workers.

    Under ``ulimit -v`` (or ``ulimit -d``) the limit binds the command and each worker
    of the local Dask cluster it starts (``batch``, ``sweep``: the options ``--workers``
    and ``--threads-per-worker``); "use a smaller log" alone named neither (Leftovers
    16-dask, limit L4).
    """
    from modalinfo.common.memory import memory_limits_text

    local_workers = hasattr(args, "workers") and getattr(args, "scheduler", None) is None
    limits = memory_limits_text()
    helps = ["a smaller log or smaller options"]
    if local_workers:
        helps.insert(0, "fewer local workers or threads (--workers 1 --threads-per-worker 1)")
    if not limits:
        return "use " + " or ".join(helps)
    # ulimit -d binds as ulimit -v does: "use a smaller log" alone, after a 430 kB log
    # ran out of memory under it, named no cause (adversarial round 50 PART b, R03)
    whom = "this process and each local Dask worker" if local_workers else "this process"
    raise_it = "raise it" if " and " not in limits else "raise them"
    return f"{limits} for {whom}: {raise_it}, or use " + " or ".join(helps)


def _dispatch(parser: argparse.ArgumentParser, argv: list[str] | None, prog: str,
              words) -> int:
    try:
        args = parser.parse_args(argv)
    except KeyboardInterrupt:  # Ctrl-C while the parser imports a subcommand's modules
        return interrupted(prog)
    if getattr(args, "_run", None) is None:
        parser.print_help(sys.stderr)
        return EXIT_USAGE
    # the command line as typed, for the provenance record of the outputs
    args._argv = [prog, *(sys.argv[1:] if argv is None else [str(a) for a in argv])]
    import warnings

    # a warning that reaches stderr is one line in the command's voice, as its errors
    # are (Python's default adds the source path and a second line of code)
    previous_format = warnings.formatwarning
    warnings.formatwarning = one_line_format(f"{prog} {args.command}")
    written = files_written()  # a refused stdout names the files only if any were written
    stdout = sys.stdout
    sys.stdout = _ClosedPipeTolerant(stdout)
    try:
        code = int(args._run(args) or 0)
        for note in getattr(args, "_notes", None) or ():
            say(note + "\n")  # notes queued by the command (e.g. assumed units)
        return code
    except BrokenPipeError:
        # the reader (e.g. `| head`) closed the pipe: not an input error
        discard_stdout()
        return EXIT_OK
    except StdoutRefusedError as exc:
        why = (f": {exc.strerror}" if isinstance(exc, StdoutEncodingError)
               else f" ({exc.strerror})")
        kept = "; the files written before it are complete" if files_written() > written else ""
        say(f"{prog} {args.command}: error: could not write standard output{why}{kept}\n")
        return EXIT_FAILURE
    except OutputGoneError as exc:  # a failure during the run, not an input error
        say(f"{prog} {args.command}: error: {exc.strerror}\n")
        return EXIT_FAILURE
    except (CommandError, ValueError, TypeError, OSError, KeyError) as exc:
        message = error_line(exc, type(exc).__name__)
        if isinstance(exc, OSError) and exc.errno == errno.EFBIG:
            message = _file_too_large(exc, message)
        if words is not None:
            message = words(message)
        say(f"{prog} {args.command}: error: {message}\n")
        return EXIT_USAGE
    except Warning as exc:
        # a warning turned into an error (PYTHONWARNINGS=error, python -W error): one line,
        # not a 58-line traceback (adversarial round 9 PART b, row N49)
        message = command_line_text(exc) or type(exc).__name__
        if words is not None:
            message = words(message)
        say(f"{prog} {args.command}: error: {type(exc).__name__} raised as an "
                         f"error (PYTHONWARNINGS / -W error): {message}\n")
        return EXIT_USAGE
    except MemoryError as exc:
        # the estimates before the work should have refused this: still one line, no
        # traceback (numpy's message names the array that did not fit)
        detail = str(exc).strip().splitlines()[0] if str(exc).strip() else "MemoryError"
        say(f"{prog} {args.command}: error: out of memory: {detail}; "
            f"{_memory_advice(args)}\n")
        return EXIT_USAGE
    except ImportError as exc:
        if not isinstance(exc, MissingDependencyError):
            raise  # a broken installation, not a missing option: keep the traceback
        say(f"{prog} {args.command}: error: {exc}\n")
        return EXIT_USAGE
    except KeyboardInterrupt:
        return interrupted(prog)
    finally:
        warnings.formatwarning = previous_format
        if isinstance(sys.stdout, _ClosedPipeTolerant):
            sys.stdout = stdout


def _file_too_large(exc: OSError, message: str) -> str:
    """Say which file and which limit an ``EFBIG`` ("File too large") is about.

    ``[Errno 27] File too large`` named neither the output nor ``ulimit -f`` (adversarial
    round 27 PART b, rows L01-L08).
    """
    from modalinfo.common.files import file_size_limit_text

    named = exc.filename and quoted(exc.filename) in message
    name = f" writing {quoted(exc.filename)}" if exc.filename and not named else ""
    limit = file_size_limit_text() or "a file-size limit"
    return f"{message}{name}: {limit}; raise it (ulimit -f) or write a smaller output"


class _ClosedPipeTolerant:
    """Stdout for a command's run: a closed pipe sends the rest to /dev/null, the run goes on.

    A reader that closed the pipe (``| head -1``) has what it wanted; the command still
    writes its files and exits with its own status.

    A ``BrokenPipeError`` ended the run where it was raised, with status 0: ``reorder
    --max-frames 1000 --frame 4 --out F.json | head -1`` printed its table's first line,
    exited 0 and wrote no F.json (adversarial round 48 PART b). Every other attribute is
    the stream's.
    """

    def __init__(self, stream) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        with closed_pipe_discarded():
            return self._stream.write(text)
        return len(text)  # the reader is gone: taken as written

    def flush(self) -> None:
        with closed_pipe_discarded():
            self._stream.flush()

    def __getattr__(self, name: str):
        return getattr(self._stream, name)


@contextlib.contextmanager
def closed_pipe_discarded() -> Iterator[None]:
    """Run the block; a ``BrokenPipeError`` in it sends stdout to /dev/null and goes on.

    The one rule for a closed pipe (``| head -1``): the command's stdout
    (:class:`_ClosedPipeTolerant`) and ``paper_figures``' progress lines use it.
    """
    try:
        yield
    except BrokenPipeError:
        discard_stdout()


def discard_stdout() -> None:
    """Point stdout at /dev/null after its reader closed the pipe (``| head -1``).

    What is still buffered, later lines and the flush at exit then go nowhere, as the
    Python docs recommend (signal module, "Note on SIGPIPE"); a stream without a file
    descriptor is replaced by one on /dev/null.
    """
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, ValueError, OSError, io.UnsupportedOperation):
        sys.stdout = open(os.devnull, "w", encoding="utf-8")  # noqa: SIM115
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, fd)
    os.close(devnull)


def say(line: str) -> None:
    """Write ``line`` on stderr; a stderr that refuses it (``2>/dev/full``) keeps the status.

    The exit status is the message that always arrives: writing the error line to a full
    disk raised ``OSError`` inside the error handler and turned a refusal (2) into a
    traceback-less exit 1 (audit 10-env).
    """
    with contextlib.suppress(OSError):
        sys.stderr.write(line)
        sys.stderr.flush()


def _open_closed_streams() -> None:
    """Give a closed stdout or stderr (``cmd >&-``: Python sets it to None) to /dev/null.

    Python's own ``print`` discards what it would write to a closed stream; the commands
    write with ``sys.stdout.write`` and would stop on ``None.write`` with a traceback.
    Discarding keeps both in step: the output goes nowhere, as the user asked, and the
    exit status is the command's.
    """
    import os

    for name in ("stdout", "stderr"):
        if getattr(sys, name) is None:
            if not _DEVNULL:  # one stream for the process, kept open (never collected)
                _DEVNULL.append(open(os.devnull, "w", encoding="utf-8"))  # noqa: SIM115
            setattr(sys, name, _DEVNULL[0])


#: The /dev/null stream given to closed standard streams (see :func:`_open_closed_streams`).
_DEVNULL: list = []


def interrupted(prog: str) -> int:
    """Say ``PROG: interrupted`` on stderr (one line, no traceback); return 130.

    For Ctrl-C at any moment of a command, including while it starts (imports, parser):
    ``dispatch`` uses it, and so do the ``__main__`` modules around their imports.
    """
    say(f"{prog}: interrupted\n")
    return EXIT_INTERRUPTED


def folder_arg(text: str | os.PathLike) -> Path:
    """``--out DIR`` of a command that writes a folder: an empty name is refused.

    ``Path("")`` is ``Path(".")``: an unset ``$OUT`` in ``--out "$OUT"`` wrote into the
    current folder (round 11 PART b, E09 and R38); the current folder is ``--out .``.
    """
    if not os.fspath(text).strip():  # main([..., Path]) from Python passes a path
        raise argparse.ArgumentTypeError(
            "must name a folder; got an empty name (give --out . for the current folder)"
        )
    return Path(text)


def check_not_folder(path: Path, flag: str, suffixes: tuple[str, ...] | None = None, *,
                     example: str | None = None) -> None:
    """Refuse an output file named by an existing folder, saying so and what ``flag`` wants.

    The extension check came first and a folder was "unsupported extension '(none)'"
    (``reorder --out fc1``, fc1 a folder a forecast wrote: adversarial round 54 PART b,
    P70): the user sees a folder where the command wants a file, so the line says that.

    Parameters
    ----------
    path : pathlib.Path
        The output named on the command line.
    flag : str
        The option (or positional) named in the message.
    suffixes : tuple of str, optional
        The extensions the file may have (with the dot).
    example : str, optional
        The extension of the example name (default: the first of ``suffixes``).

    Raises
    ------
    CommandError
        When ``path`` is an existing folder (or a symbolic link to one).
    """
    path = Path(path)
    if not path.is_dir():
        return
    ending = f" ending in {', '.join(suffixes)}" if suffixes else ""
    name = path / f"NAME{example or (suffixes[0] if suffixes else '')}"
    raise CommandError(f"{flag} {quoted(path)} is a folder; {flag} wants the name of a file to "
                       f"write{ending}, such as {quoted(name)}")


def check_output(
    path: Path | None, overwrite: bool, *, suffixes: tuple[str, ...] | None = None,
    flag: str = "output", example: str | None = None,
) -> None:
    """Check an output before any work: its extension, its directory, no overwrite.

    Every command writing a file calls this (or modalinfo's
    :func:`modalinfo.cli.shared.check_log_output` / ``check_figure_output``) before it
    loads or computes anything, so a bad output path costs nothing.

    Parameters
    ----------
    path : pathlib.Path or None
        The output file (None: nothing to check).
    overwrite : bool
        Whether an existing file may be replaced.
    suffixes : tuple of str, optional
        The accepted extensions (lower case, with the dot).
    flag : str
        The option named in the message.
    example : str, optional
        The extension of the example file name offered when ``path`` is a folder.

    Raises
    ------
    CommandError
        Naming ``flag``, the path and the rule.
    """
    if path is None:
        return
    path = Path(path)
    check_not_folder(path, flag, suffixes, example=example)
    if suffixes is not None and path.suffix.lower() not in suffixes:
        raise CommandError(f"{flag} {quoted(path)}: unsupported extension "
                           f"{quoted(path.suffix or '(none)')}; use {', '.join(suffixes)}")
    try:
        check_not_special(path)
    except OSError as exc:
        raise CommandError(f"{flag} {exc}") from None
    if not path.parent.exists():
        raise CommandError(f"{flag} {quoted(path)}: directory {quoted(path.parent)} does not exist")
    if path.exists() and not overwrite:
        raise CommandError(f"{flag} {quoted(path)} exists; pass --overwrite to replace it")
    try:  # a real test write: '/proc/x.png' failed only at the end, naming a temporary file
        writable_free_bytes(path.parent)
    except OSError as exc:
        raise CommandError(f"{flag} {quoted(path)}: cannot write in {quoted(path.parent)} "
                           f"({exc.strerror or exc})") from None


#: Open files a local Dask cluster needs (scheduler, nanny, worker, their sockets): under
#: ``ulimit -n 30`` a one-log batch printed Dask's and psutil's tracebacks ("Too many open
#: files"); 64 ran clean (audit 10-env, measured on this machine with 1 worker).
MIN_OPEN_FILES = 64


def _check_open_file_limit() -> None:
    """Refuse a soft ``RLIMIT_NOFILE`` below :data:`MIN_OPEN_FILES` before a cluster starts."""
    try:
        import resource
    except ImportError:  # not on Windows
        return
    soft, _ = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft != resource.RLIM_INFINITY and soft < MIN_OPEN_FILES:
        raise CommandError(f"the open-file limit (ulimit -n) is {soft}; a local Dask cluster "
                           f"needs at least {MIN_OPEN_FILES} (raise it, e.g. ulimit -n 1024)")


def _check_shared_memory() -> None:
    """Refuse before a local cluster starts when its processes cannot share semaphores.

    A local Dask cluster's nanny and worker processes need POSIX semaphores
    (``multiprocessing``'s locks, in ``/dev/shm`` on Linux); with ``/dev/shm`` missing,
    read-only or full, ``batch`` and ``sweep`` printed two Dask tracebacks ending in
    "RuntimeError: Nanny failed to start." and exit 1 (adversarial round 15 PART b,
    R12). The test is the real thing: one lock of the ``spawn`` context Dask uses.

    Under a file-size limit (``ulimit -f 0``) ``/dev/shm`` is fine but glibc's
    ``sem_open`` cannot write the semaphore's file (``EFBIG``): the line names the
    limit and that file, not /dev/shm's mount (round 50 PART b, R91; stop 57, fix51-c).
    """
    import errno
    import multiprocessing

    try:
        multiprocessing.get_context("spawn").Lock()
    except (OSError, ImportError) as exc:
        why = getattr(exc, "strerror", None) or str(exc) or type(exc).__name__
        if getattr(exc, "errno", None) == errno.EFBIG:
            from modalinfo.common.files import file_size_limit_text

            limit = file_size_limit_text() or "a file-size limit"
            # glibc writes a semaphore into a temporary /dev/shm/sem.XXXXXX, then links it
            raise CommandError(f"a local Dask cluster needs POSIX semaphores for its worker "
                               f"processes' locks, and the semaphore's file "
                               f"(/dev/shm/sem.*) could not be written ({why}): {limit}; "
                               "raise it (ulimit -f) or give --scheduler ADDR of a running "
                               "cluster") from None
        raise CommandError(f"a local Dask cluster needs POSIX shared memory for its worker "
                           f"processes' locks (/dev/shm on Linux), and it is not usable "
                           f"here ({why}); mount a writable /dev/shm or give --scheduler "
                           "ADDR of a running cluster") from None


def check_cluster_args(args: argparse.Namespace) -> None:
    """Refuse bad cluster options of ``batch`` and ``closedloop sweep`` before any work.

    The ``dist`` extra must be installed (else one line with ``pip install
    'modalinfo[dist]'``). ``--workers`` and ``--threads-per-worker`` >= 1,
    ``--worker-wait`` a finite number of seconds > 0, ``--memory-limit`` and (on a
    local cluster) the worker count within the machine
    (:func:`modalinfo.common.tasks.cluster.check_memory_limit`, ``check_worker_count``).
    """
    require_dist(str(getattr(args, "command", None) or "this command"))
    for flag, value in (("--workers", args.workers),
                        ("--threads-per-worker", args.threads_per_worker)):
        if value is not None and value < 1:
            raise CommandError(f"{flag} must be >= 1; got {value}")
    if args.worker_wait is not None and not 0 < args.worker_wait < float("inf"):
        raise CommandError(f"--worker-wait must be a number of seconds > 0; got "
                           f"{args.worker_wait:g}")
    if args.scheduler is None:
        _check_open_file_limit()
        _check_shared_memory()
    try:
        check_memory_limit(args.memory_limit, args.threads_per_worker or 1)
        if args.workers is not None and args.scheduler is None:
            check_worker_count(args.workers)
    except ValueError as exc:
        raise CommandError(str(exc).replace("`memory_limit`", "--memory-limit")
                           .replace("`n_workers`", "--workers")) from None
