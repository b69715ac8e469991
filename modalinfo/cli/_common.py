"""Helpers shared by the ``modalinfo`` subcommands: mode lists, log loading, outputs."""

from __future__ import annotations

import argparse
from pathlib import Path

from modalinfo.cli import CommandError

__all__ = ["add_hint_arguments", "parse_modes", "hints_from_args", "check_output", "load_log"]


def add_hint_arguments(
    parser: argparse.ArgumentParser, *, is_info: bool = True, modes_flag: str = "--modes"
) -> None:
    """Add the options that supply what a foreign log file lacks (every command reading a log).

    ``info`` also accepts ``--units`` and ``--wavelength`` as input hints; ``convert``
    uses those names for the conversion target and takes ``--in-units`` only. Commands
    with a ``--modes`` option of their own (``forecast`` selects modes with it) take the
    column hint as ``modes_flag="--in-modes"``.
    """
    group = parser.add_argument_group("hints for files that lack the information")
    group.add_argument("--fmt", choices=("npz", "npy", "csv", "fits", "hdf5"), help="input format")
    group.add_argument("--rate", type=float, metavar="HZ", help="sample rate in Hz")
    flags = ("--in-units", "--units") if is_info else ("--in-units",)
    group.add_argument(
        *flags, dest="in_units", choices=("rad", "nm", "um", "waves"), help="input units"
    )
    if is_info:
        group.add_argument("--wavelength", type=float, metavar="M", help="wavelength in metres")
    group.add_argument(
        "--in-convention",
        choices=("noll", "ansi", "fringe", "labels"),
        help="indexing convention of the input modes",
    )
    group.add_argument(
        modes_flag,
        dest="in_modes",
        metavar="LIST",
        help="modes of the columns: '2-28', '4,5,6' or labels 'KL1,KL2'",
    )
    group.add_argument(
        "--nonfinite",
        choices=("raise", "drop", "interpolate"),
        default="raise",
        help="what to do with NaN/inf values (default: raise)",
    )


def parse_modes(text: str) -> list:
    """Parse ``--modes``: comma-separated ints, ``a-b`` ranges (inclusive) or labels."""
    out: list = []
    for part in (p.strip() for p in text.split(",")):
        if not part:
            raise CommandError(f"--modes: empty entry in {text!r}")
        lo, sep, hi = part.partition("-")
        if sep and lo.isdigit() and hi.isdigit():
            if int(hi) < int(lo):
                raise CommandError(f"--modes: range {part!r} is decreasing")
            out.extend(range(int(lo), int(hi) + 1))
        elif part.isdigit():
            out.append(int(part))
        else:
            out.append(part)
    kinds = {type(x) for x in out}
    if len(kinds) > 1:
        raise CommandError(f"--modes mixes indices and labels: {text!r}")
    return out


def hints_from_args(args: argparse.Namespace) -> dict:
    """Collect the hint options into keyword arguments for ``modalinfo.io.load``."""
    hints = {
        "rate": args.rate,
        "units": args.in_units,
        "wavelength": getattr(args, "wavelength", None) if args.command == "info" else None,
        "convention": args.in_convention,
        "nonfinite": args.nonfinite,
    }
    if args.in_modes is not None:
        modes = parse_modes(args.in_modes)
        hints["modes"] = modes
        if modes and isinstance(modes[0], str) and args.in_convention is None:
            hints["convention"] = "labels"
    return {k: v for k, v in hints.items() if v is not None}


def check_output(
    path: Path | None, overwrite: bool, *, suffixes: tuple[str, ...] | None = None,
    flag: str = "output",
) -> None:
    """Check an output before any work: its extension, its directory, no overwrite.

    Every command writing a file calls this (or :func:`check_log_output` /
    :func:`check_figure_output`) before it loads or computes anything, so a bad
    output path costs nothing. ``suffixes`` lists the accepted extensions
    (lower case, with the dot); ``flag`` names the option in the message.
    """
    if path is None:
        return
    path = Path(path)
    if suffixes is not None and path.suffix.lower() not in suffixes:
        raise CommandError(f"{flag} '{path}': unsupported extension "
                           f"'{path.suffix or '(none)'}'; use {', '.join(suffixes)}")
    if path.is_dir():
        raise CommandError(f"{flag} '{path}' is a directory; give a file name")
    if not path.parent.exists():
        raise CommandError(f"{flag} '{path}': directory '{path.parent}' does not exist")
    if path.exists() and not overwrite:
        raise CommandError(f"{flag} '{path}' exists; pass --overwrite to replace it")


__all__ += ["check_log_output", "check_figure_output", "progress", "LOG_SUFFIXES"]

#: Extensions a log is written to (one rule for ``synth`` and ``convert``): other
#: extensions, ``.txt`` included, need ``--to-fmt``.
LOG_SUFFIXES = {".npz": "npz", ".csv": "csv", ".fits": "fits", ".fit": "fits",
                ".fts": "fits", ".h5": "hdf5", ".hdf5": "hdf5"}


def check_log_output(path: Path, overwrite: bool, fmt: str | None, flag: str = "OUT") -> str:
    """Check a log output before any work; return its format (``--to-fmt`` or extension)."""
    path = Path(path)
    if fmt is None:
        fmt = LOG_SUFFIXES.get(path.suffix.lower())
        if fmt is None:
            raise CommandError(
                f"{flag} '{path}': cannot tell the log format from the extension "
                f"'{path.suffix or '(none)'}'; use {', '.join(LOG_SUFFIXES)} or pass "
                "--to-fmt (npz, csv, fits, hdf5)")
    check_output(path, overwrite, flag=flag)
    return fmt


def check_figure_output(path: Path | None, overwrite: bool, flag: str = "--plot") -> None:
    """Check a figure output before any work (extension one matplotlib writes)."""
    if path is None:
        return
    from matplotlib.backend_bases import FigureCanvasBase

    kinds = tuple(f".{k}" for k in sorted(FigureCanvasBase.get_supported_filetypes()))
    check_output(path, overwrite, suffixes=kinds, flag=flag)


class _Progress:
    """A tqdm bar on stderr (a terminal, not ``--quiet``), or nothing; see :func:`progress`."""

    def __init__(self, bar):
        self.bar = bar

    def __call__(self, n: int = 1) -> None:
        if self.bar is not None:
            self.bar.update(n)

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        if self.bar is not None:
            self.bar.close()


def progress(args: argparse.Namespace, total: int, *, unit: str = "step",
             desc: str | None = None, min_total: int = 1) -> _Progress:
    """Return a callable ``advance(n=1)`` for the library's ``progress=`` hooks.

    It drives a tqdm bar on stderr when stderr is a terminal, ``--quiet`` is not
    given and ``total >= min_total``; otherwise it does nothing (piped output stays
    clean). Use it as a context manager so the bar is closed.
    """
    import sys

    show = (not getattr(args, "quiet", False) and sys.stderr.isatty()
            and total >= min_total)
    if not show:
        return _Progress(None)
    from tqdm import tqdm

    return _Progress(tqdm(total=total, unit=unit, desc=desc, file=sys.stderr,
                          unit_scale=unit == "frame", leave=False))


def load_log(path: Path, args: argparse.Namespace | None = None):
    """Read a log with ``modalinfo.io.load``, with the hint options of ``args`` if given.

    Errors become one-line messages through the dispatcher.
    """
    from modalinfo.io import load

    if not path.is_file():
        raise CommandError(f"log file '{path}' does not exist")
    if args is None:
        return load(path)
    return load(path, fmt=args.fmt, **hints_from_args(args))
