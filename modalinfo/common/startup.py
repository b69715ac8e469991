"""Checks a command makes before its heavy imports (standard library only).

``python -m modalinfo``, ``python -m closedloop`` and ``python -m paper_figures`` import
NumPy, SciPy and numba before their own code runs; a process started in a folder that
has since been deleted failed there with a traceback (numba's import of coverage calls
``os.getcwd()``: audit 10-env). This module imports nothing of the project or beyond
the standard library, so the check costs nothing and comes first.
"""

from __future__ import annotations

import errno
import os
import sys

__all__ = ["await_dropped_interrupt", "command_line_text", "exit_quietly", "import_refusal",
           "keep_interrupts", "memory_refusal", "one_line_format", "one_line_warnings",
           "require_current_folder", "warning_refusal"]


def require_current_folder(prog: str) -> None:
    """Exit with status 2 and one line on stderr if the current folder no longer exists.

    Parameters
    ----------
    prog : str
        The command's name, for the message (e.g. ``"modalinfo"``).
    """
    try:
        os.getcwd()
    except FileNotFoundError:
        sys.stderr.write(f"{prog}: error: the current folder no longer exists (deleted); "
                         "cd to an existing folder\n")
        sys.exit(2)


def command_line_text(message) -> str:
    """Return a warning's text for a command line, in one line.

    A warning that carries a ``cli_text`` attribute (the package's plausibility
    warnings, ``modalinfo.common.validation``) has advice for a command's user (the
    option or the file to check) in place of the Python caller's "filter this
    UserWarning", which a command's user cannot do (Leftovers 26-rate).

    Parameters
    ----------
    message : Warning or str
        The warning (or its text).
    """
    text = getattr(message, "cli_text", None)
    return " ".join(str(message if text is None else text).split())


def one_line_format(prefix: str):
    """Return a ``warnings.formatwarning`` that says ``PREFIX: warning: MESSAGE`` in one line.

    Python's default form adds the source path and line number, and a second line with
    the line of code, which means nothing to a user of a command.

    Parameters
    ----------
    prefix : str
        What the line starts with (``"modalinfo"``, ``"modalinfo info"``).
    """
    def formatwarning(message, category, filename, lineno, line=None) -> str:
        return f"{prefix}: warning: {command_line_text(message)}\n"

    formatwarning.prefix = prefix  # read by worker_warning_env
    return formatwarning


#: Environment variable carrying a command's warning prefix to its Dask worker
#: processes (``worker_warning_env``, ``apply_worker_warning_format``).
WARNING_PREFIX_ENV = "MODALINFO_WARNING_PREFIX"


def worker_warning_env() -> dict[str, str]:
    """Return the environment giving worker processes this process's one-line warnings.

    ``{WARNING_PREFIX_ENV: prefix}`` when ``warnings.formatwarning`` is a
    ``one_line_format`` (a command runs), else ``{}`` (a Python caller keeps
    Python's form in its workers too). A ``LocalCluster``'s workers are other processes:
    without it a worker's warning came in Python's two-line form with a Dask source line
    (``dask/_task_spec.py``) while the command's own said ``modalinfo batch: warning:
    ...`` (Leftovers 26-rate, Left; Leftovers 27-scale).
    """
    import warnings

    prefix = getattr(warnings.formatwarning, "prefix", None)
    return {WARNING_PREFIX_ENV: prefix} if isinstance(prefix, str) else {}


def apply_worker_warning_format() -> None:
    """In a worker process, show warnings as the command that started it does.

    Reads ``WARNING_PREFIX_ENV`` (set by ``worker_warning_env`` through the
    cluster's ``env``); unset: Python's form is kept.
    """
    prefix = os.environ.get(WARNING_PREFIX_ENV)
    if prefix:
        import warnings

        warnings.formatwarning = one_line_format(prefix)


def one_line_warnings(prog: str) -> None:
    """Show every warning from here on as one line ``PROG: warning: MESSAGE``.

    For the commands' ``__main__`` before their heavy imports: a warning given while
    the package loads (numba's cache folder not writable: ``modalinfo.common.jit``)
    came in Python's two-line form with an ``@jit`` line of the package's source
    (Leftovers 23-misc); ``dispatch`` names the subcommand while one runs.

    Parameters
    ----------
    prog : str
        The command's name (e.g. ``"modalinfo"``).
    """
    import warnings

    warnings.formatwarning = one_line_format(prog)


def warning_refusal(prog: str, exc: Warning) -> int:
    """Say in one line that a warning was raised as an error; return 2.

    Under ``PYTHONWARNINGS=error`` (or ``python -W error``) a warning given while the
    package loads, before the subcommand's own handler, ended in a traceback.

    Parameters
    ----------
    prog : str
        The command's name, for the message.
    exc : Warning
        The warning raised.

    Returns
    -------
    int
        The exit status, 2.
    """
    message = command_line_text(exc) or type(exc).__name__
    sys.stderr.write(f"{prog}: error: {type(exc).__name__} raised as an error "
                     f"(PYTHONWARNINGS / -W error): {message}\n")
    return 2


def _out_of_memory(exc: BaseException) -> bool:
    """Tell whether an exception (or one it was raised while handling) means memory ran out."""
    seen = 0
    while exc is not None and seen < 8:
        if isinstance(exc, MemoryError):
            return True
        if isinstance(exc, OSError) and exc.errno == errno.ENOMEM:
            return True
        # the dynamic loader's words, in an OSError (ctypes, llvmlite) or in the
        # ImportError of an extension module (SciPy's _lbfgsb under `ulimit -v 400000`:
        # a traceback, adversarial round 50 PART b)
        if isinstance(exc, OSError | ImportError) and (
            "failed to map segment" in str(exc) or "cannot allocate memory" in str(exc).lower()
        ):
            return True
        exc = exc.__cause__ or exc.__context__
        seen += 1
    return False


def memory_refusal(prog: str, exc: BaseException) -> int:
    """Say in one line that the process ran out of memory; return 2, or re-raise.

    Under ``ulimit -v`` below what NumPy, SciPy and numba's LLVM need to load, the
    import failed with a two-part traceback from llvmlite ("failed to map segment from
    shared object": round 12 PART b, E07). Anything that is not a lack of memory is
    re-raised unchanged.

    Parameters
    ----------
    prog : str
        The command's name, for the message.
    exc : BaseException
        The exception caught around the command.

    Returns
    -------
    int
        The exit status, 2.
    """
    if not _out_of_memory(exc):
        raise exc
    sys.stderr.write(f"{prog}: error: out of memory while loading the program or its data "
                     "(a memory limit such as `ulimit -v` or `ulimit -d` too low?); raise the "
                     "limit or use a smaller log or smaller options\n")
    return 2


def import_refusal(prog: str, exc: ImportError) -> int:
    """Say in one line why the package could not load; return 2, or re-raise ``exc``.

    An extension module the loader could not map for lack of memory (``ulimit -v``:
    :func:`memory_refusal`'s line) or numba refusing its environment
    (``NUMBA_NUM_THREADS=0``: adversarial round 8, e105); any other ImportError is a
    broken installation and keeps its traceback.
    """
    if _out_of_memory(exc):
        return memory_refusal(prog, exc)
    if "NUMBA_" not in str(exc):
        raise exc
    sys.stderr.write(f"{prog}: error: {exc}\n")
    return 2


def keep_interrupts() -> None:
    """Make a Ctrl-C that Python had to drop raise again at the next line of Python code.

    Python runs the SIGINT handler (``KeyboardInterrupt``) at the next bytecode of the
    main thread. When a C library calls back into Python, that bytecode can be the
    callback's: numba compiles through LLVM, which calls llvmlite's object-cache
    callbacks (``ctypes``), and a Ctrl-C during the compile landed there. ``ctypes``
    cannot pass an exception through C, so Python printed "Exception ignored on
    calling ctypes callback function ... KeyboardInterrupt" and dropped it: the command
    ran on to exit 0 with its files written (fix54-d), or numba, whose callback never
    stored the compiled code, failed with "RuntimeError: no compiled object yet" (exit
    1). The same holds for a ``__del__`` or a ``gc`` callback.

    Such an exception goes to ``sys.unraisablehook``: this hook takes a dropped
    ``KeyboardInterrupt`` (printing nothing) and has the signal delivered again, by
    ``_thread.interrupt_main`` from a new thread: called here, the handler would raise
    at the hook's own next bytecode and be dropped again ("Exception ignored in
    sys.unraisablehook"); the thread runs once this one releases the GIL (the callback
    has returned into C), so the handler raises at the next line of Python outside
    it (a later callback of the same compile drops it and passes it on again). The
    command then ends as for any Ctrl-C, one line and status 130, no file written. A
    subclass carrying a ``signum`` (a SIGTERM raised as one, ``paper_figures``) is
    delivered as that signal. Every other exception goes to the previous hook. For the
    commands' ``__main__`` (the process is the command's); a Python caller's process
    keeps its own hook.
    """
    import _thread
    import signal

    previous = sys.unraisablehook

    def hook(unraisable) -> None:
        exc_type = unraisable.exc_type
        if not (isinstance(exc_type, type) and issubclass(exc_type, KeyboardInterrupt)):
            previous(unraisable)
            return
        signum = getattr(unraisable.exc_value, "signum", None)
        signum = int(signum) if isinstance(signum, int) else int(signal.SIGINT)
        _ON_ITS_WAY.append(signum)
        try:
            _thread.start_new_thread(_deliver, (signum,))
        except RuntimeError:  # no thread to be had (a limit, the interpreter's exit):
            _ON_ITS_WAY.clear()
            previous(unraisable)  # Python's own report, as before

    sys.unraisablehook = hook


#: Signals dropped in a callback whose delivery by :func:`_deliver` is still to come.
_ON_ITS_WAY: list[int] = []


def _deliver(signum: int) -> None:
    """Deliver ``signum`` to the main thread again (run in a thread of its own)."""
    import _thread

    try:
        # a handler that is no longer Python's (SIG_IGN, SIG_DFL) is left alone
        _thread.interrupt_main(signum)
    finally:
        _ON_ITS_WAY.clear()  # after: the main thread's next bytecode raises


def await_dropped_interrupt() -> None:
    """Let a Ctrl-C dropped in a callback (:func:`keep_interrupts`) raise here, if one is due.

    The thread delivering it needs the GIL, which this thread gives up only every few
    milliseconds while it runs Python: numba, whose object-cache callback took the
    dropped Ctrl-C and so never stored the compiled code, reached its cache write first
    and failed with "RuntimeError: no compiled object yet" (2 runs of 30 with the first
    form of the hook). Called before such a step (``modalinfo.common.jit``), this
    sleeps, which gives up the GIL, until the signal's handler has raised (at most a
    second; nothing waits when none is due).
    """
    if not _ON_ITS_WAY:
        return
    import time

    for _ in range(1000):  # in the main thread the handler raises in here
        if not _ON_ITS_WAY:
            return
        time.sleep(0.001)


def exit_quietly(code: int) -> None:
    """End the command with ``code``; a Ctrl-C from here on ends it at once with ``code``.

    The command's work is over and its exit status decided, but the interpreter's
    shutdown still joins threads and runs ``atexit`` callbacks (Dask, numba, tqdm):
    a SIGINT there printed "Exception ignored in ... KeyboardInterrupt" with a
    traceback, then exit 0, after `closedloop export` and `modalinfo forecast --out`
    had written complete files (adversarial round 15 PART b, interruption fuzz). The
    streams are flushed first, so the exit skips nothing the command wrote.

    Parameters
    ----------
    code : int
        The exit status.
    """
    import signal

    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError, AttributeError):  # closed or broken: nothing to keep
            pass

    def now(signum, frame):  # noqa: ARG001 - the signal module's signature
        os._exit(code)

    try:
        if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            signal.signal(signal.SIGINT, now)  # an ignored SIGINT (nohup) stays ignored
    except ValueError:  # not the main thread (runpy in a thread): Python's default stays
        pass
    sys.exit(code)
