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

from modalinfo.common.cli import CommandError, Parser, add_version_argument, dispatch

# CommandError and dispatch are the ground floor's (modalinfo.common.cli), named here too
# because code calling the command line in Python has imported them from here
__all__ = ["main", "dispatch", "CommandError"]


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
    "extra": "--extra", "alpha": "--alpha", "data": "the log", "max_seconds": "--max-seconds",
}
_REWRITES = (
    (re.compile(r"`history` needs at least (\d+) samples along axis 0 for (\w+)"),
     r"too few training frames (--train): \2 needs at least \1"),
    # "pass nonfinite='drop' or 'interpolate'" -> "use --nonfinite drop or interpolate"
    (re.compile(r"pass nonfinite='(\w+)' or '(\w+)'"), r"use --nonfinite \1 or --nonfinite \2"),
    (re.compile(r"pass overwrite=True(?: \(command line: --overwrite\))?"), "pass --overwrite"),
    # "pass transpose=True (command line: --transpose)" -> "pass --transpose"
    # "method='gaussian' (command line: --method gaussian)" -> "--method gaussian"
    (re.compile(r"\w+=\S* \(command line: (--[\w-]+(?: [\w-]+)?)\)"), r"\1"),
    (re.compile(r"pass fmt="), "pass --to-fmt"),
    (re.compile(r"max\(horizons\) \+ 1"), "--horizon + 1"),
    # the library's "(None: no limit)" has no command-line spelling: --max-seconds takes
    # a finite number above 0 (stop 55's note; fix49-c)
    (re.compile(r"raise `max_seconds` \(None: no limit\)"),
     "raise --max-seconds (CPU seconds: a finite number above 0)"),
    # hint `rate`=2000.0 -> --rate 2000
    (re.compile(r"hint `(\w+)`="), lambda m: f"hint {_WORDS.get(m.group(1), m.group(1))} "),
    (re.compile(r"`(\w+)(\.coeffs)?`"), lambda m: _WORDS.get(m.group(1), m.group(0))),
    # numpy scalar reprs: np.float64(0.0505) -> 0.0505; not a quoted one, which is a
    # file's own text ("could not convert string 'np.float64(0.5)'" read '0.5': round 35
    # PART b, E01)
    (re.compile(r"(?<!')np\.(?:float|int|uint)\d*\(([-+0-9.eE]+|nan|inf)\)(?!')"),
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
    parser = Parser(
        prog="modalinfo",
        description="Mutual-information analysis and forecasting of wavefront modal logs.",
    )
    add_version_argument(parser)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    for module in _commands():
        epilog = getattr(module, "EPILOG", None)  # e.g. the columns of a printed table
        cmd = sub.add_parser(module.NAME, help=module.HELP, description=module.HELP,
                             epilog=epilog, formatter_class=argparse.RawDescriptionHelpFormatter
                             if epilog else argparse.HelpFormatter)
        module.add_arguments(cmd)
        cmd.set_defaults(_run=module.run)
    return parser




def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the exit status."""
    try:
        parser = build_parser()  # imports every subcommand's module: seconds on a busy machine
    except KeyboardInterrupt:
        from modalinfo.common.cli import interrupted

        return interrupted("modalinfo")
    return dispatch(parser, argv, "modalinfo", words=cli_words)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
