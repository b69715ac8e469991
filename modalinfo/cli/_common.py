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
    group.add_argument("--fmt", choices=("npz", "npy", "csv", "fits", "hdf5", "aot"),
                       help="input format")
    group.add_argument("--loop", metavar="UID", help="control loop of an AOT file (its uid)")
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
        "loop": getattr(args, "loop", None),
    }
    if args.in_modes is not None:
        modes = parse_modes(args.in_modes)
        hints["modes"] = modes
        if modes and isinstance(modes[0], str) and args.in_convention is None:
            hints["convention"] = "labels"
    return {k: v for k, v in hints.items() if v is not None}


def check_output(path: Path | None, overwrite: bool) -> None:
    """Refuse an existing output unless ``--overwrite``; the directory must exist."""
    if path is None:
        return
    if path.exists() and not overwrite:
        raise CommandError(f"output '{path}' exists; pass --overwrite to replace it")
    if not path.parent.exists():
        raise CommandError(f"output directory '{path.parent}' does not exist")


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
