"""The ``modalinfo`` command line.

Each subcommand lives in its own module ``modalinfo/cli/cmd_<name>.py`` exposing

- ``NAME``: the subcommand as typed (e.g. ``"fitting-error"``),
- ``HELP``: one line for ``modalinfo --help``,
- ``add_arguments(parser)``: fill an ``argparse.ArgumentParser``,
- ``run(args) -> int``: do the work and return the exit code.

Subcommands are discovered, so adding one never edits this file. Usage and input
errors print one line on stderr and exit with status 2, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import re
import sys

__all__ = ["main", "dispatch", "CommandError"]


class CommandError(Exception):
    """An input error a subcommand reports as one line and exit status 2."""


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors in one line (argparse prints usage first)."""

    def error(self, message: str):  # noqa: D102
        sys.stderr.write(f"{self.prog}: error: {message}\n")
        raise SystemExit(2)


#: library argument names (as written in messages, between backticks) -> what the user
#: typed or sees on the command line
_WORDS = {
    "sample_budget": "--budget", "n_resamples": "--resamples", "n_pixels": "--pupil-pixels",
    "outer_scale": "--outer-scale", "chunk_frames": "--chunk-frames",
    "refit_every": "--refit-every", "horizons": "--horizon", "horizon": "--horizon",
    "train": "--train", "window": "--window", "frame": "--frame", "seed": "--seed",
    "rate": "--rate", "wavelength": "--wavelength", "stability": "--stability",
    "history": "the training frames (--train)", "log": "the log", "coeffs": "the data",
    "log_or_coeffs": "the log", "timestamps": "the timestamps", "fmt": "--fmt",
    "max_lag": "--max-lag", "max_inputs": "--max-inputs", "n_surrogates": "--surrogates",
    "extra": "--extra", "alpha": "--alpha", "data": "the log",
}
_REWRITES = (
    (re.compile(r"`history` needs at least (\d+) samples along axis 0 for (\w+)"),
     r"too few training frames (--train): \2 needs at least \1"),
    # "pass nonfinite='drop' or 'interpolate'" -> "use --nonfinite drop or interpolate"
    (re.compile(r"pass nonfinite='(\w+)' or '(\w+)'"), r"use --nonfinite \1 or --nonfinite \2"),
    (re.compile(r"pass overwrite=True(?: \(command line: --overwrite\))?"), "pass --overwrite"),
    # "pass transpose=True (command line: --transpose)" -> "pass --transpose"
    (re.compile(r"\w+=\S* \(command line: (--[\w-]+(?: [A-Z]+)?)\)"), r"\1"),
    (re.compile(r"pass fmt="), "pass --to-fmt"),
    (re.compile(r"max\(horizons\) \+ 1"), "--horizon + 1"),
    # hint `rate`=2000.0 -> --rate 2000
    (re.compile(r"hint `(\w+)`="), lambda m: f"hint {_WORDS.get(m.group(1), m.group(1))} "),
    (re.compile(r"`(\w+)(\.coeffs)?`"), lambda m: _WORDS.get(m.group(1), m.group(0))),
    # numpy scalar reprs: np.float64(0.0505) -> 0.0505
    (re.compile(r"np\.(?:float|int|uint)\d*\(([-+0-9.eE]+|nan|inf)\)"),
     lambda m: f"{float(m.group(1)):g}"),
)


def cli_words(message: str) -> str:
    """Say a library error message in command-line terms.

    Library messages name Python arguments (`` `sample_budget` ``,
    ``nonfinite='drop'``, ``overwrite=True``) and may show numpy scalar reprs; on
    the command line the user typed flags and numbers, so those are rewritten
    (``--budget``, ``--nonfinite drop``, ``--overwrite``, ``0.0505``).
    """
    for pattern, repl in _REWRITES:
        message = pattern.sub(repl, message)
    return message


def _commands():
    import modalinfo.cli as pkg

    found = []
    for info in pkgutil.iter_modules(pkg.__path__):
        if info.name.startswith("cmd_"):
            found.append(importlib.import_module(f"modalinfo.cli.{info.name}"))
    return sorted(found, key=lambda m: m.NAME)


def build_parser() -> argparse.ArgumentParser:
    """Return the top-level parser with every discovered subcommand."""
    parser = _Parser(
        prog="modalinfo",
        description="Mutual-information analysis and forecasting of wavefront modal logs.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for module in _commands():
        epilog = getattr(module, "EPILOG", None)  # e.g. the columns of a printed table
        cmd = sub.add_parser(module.NAME, help=module.HELP, description=module.HELP,
                             epilog=epilog, formatter_class=argparse.RawDescriptionHelpFormatter
                             if epilog else argparse.HelpFormatter)
        module.add_arguments(cmd)
        cmd.set_defaults(_run=module.run)
    return parser


def dispatch(parser: argparse.ArgumentParser, argv: list[str] | None, prog: str,
             words=None) -> int:
    """Parse ``argv`` and run the chosen subcommand's ``_run``; return the exit status.

    Shared by ``modalinfo`` and ``closedloop``: queued notes after success, one line on
    stderr and status 2 for an input error (through ``words``, which rewrites library
    names in command-line terms), a quiet exit for a closed pipe, 130 for Ctrl-C.
    """
    args = parser.parse_args(argv)
    if getattr(args, "_run", None) is None:
        parser.print_help(sys.stderr)
        return 2
    try:
        code = int(args._run(args) or 0)
        for note in getattr(args, "_notes", None) or ():
            sys.stderr.write(note + "\n")  # notes queued by the command (e.g. assumed units)
        return code
    except BrokenPipeError:
        # the reader (e.g. `| head`) closed the pipe: not an input error; silence the
        # flush at exit as the Python docs recommend (signal module, "Note on SIGPIPE")
        import os

        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    except (CommandError, ValueError, TypeError, OSError, KeyError) as exc:
        message = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        if words is not None:
            message = words(message)
        sys.stderr.write(f"{prog} {args.command}: error: {message}\n")
        return 2
    except MemoryError as exc:
        # the estimates before the work should have refused this: still one line, no
        # traceback (numpy's message names the array that did not fit)
        detail = str(exc).strip().splitlines()[0] if str(exc).strip() else "MemoryError"
        sys.stderr.write(f"{prog} {args.command}: error: out of memory: {detail}; use a "
                         "smaller log or smaller options\n")
        return 2
    except ImportError as exc:
        from modalinfo.batch._deps import MissingDependencyError

        if not isinstance(exc, MissingDependencyError):
            raise  # a broken installation, not a missing option: keep the traceback
        sys.stderr.write(f"{prog} {args.command}: error: {exc}\n")
        return 2
    except KeyboardInterrupt:
        sys.stderr.write(f"{prog}: interrupted\n")
        return 130


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the exit status."""
    return dispatch(build_parser(), argv, "modalinfo", words=cli_words)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
