"""``modalinfo convert IN OUT``: change a log's format, units or mode convention.

The output format comes from OUT's extension (``.npz``, ``.csv``, ``.fits``, ``.h5``)
or ``--to-fmt`` (any other extension, ``.txt`` included, needs ``--to-fmt``, as in
``synth``). Writing is atomic and refuses to replace OUT without
``--overwrite``.
"""

from __future__ import annotations

import argparse
import sys

from modalinfo.cli._common import add_hint_arguments, check_log_output, hints_from_args, progress

NAME = "convert"

HELP = "Convert a telemetry log between formats (npz/csv/fits/h5), units and conventions."
_PROGRESS_MIN_BYTES = 16 * 2**20  # a bar (load, convert, write) from 16 MiB: seconds of work


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Fill the ``convert`` parser."""
    parser.add_argument("input", metavar="IN", help="input log file")
    parser.add_argument("output", metavar="OUT", help="output file (.npz, .csv, .fits, .h5)")
    parser.add_argument(
        "--units",
        choices=("rad", "nm", "um", "waves"),
        help="convert the coefficients to these units (needs a wavelength between "
        "phase and OPD units)",
    )
    parser.add_argument(
        "--wavelength",
        type=float,
        metavar="M",
        help="wavelength in metres for the unit conversion (or to record on a log lacking one)",
    )
    parser.add_argument(
        "--convention",
        choices=("noll", "ansi", "fringe"),
        help="re-index the Zernike modes in this convention",
    )
    parser.add_argument(
        "--to-fmt", choices=("npz", "csv", "fits", "hdf5"), help="output format (default: ext)"
    )
    parser.add_argument("--overwrite", action="store_true", help="replace OUT if it exists")
    parser.add_argument("--quiet", action="store_true",
                        help="print nothing on success (and no progress bar)")
    add_hint_arguments(parser, is_info=False)


def run(args: argparse.Namespace) -> int:
    """Read IN, convert, write OUT."""
    from pathlib import Path

    from modalinfo.io import load, save

    fmt = check_log_output(Path(args.output), args.overwrite, args.to_fmt)  # before reading
    source = Path(args.input)
    big = source.is_file() and source.stat().st_size >= _PROGRESS_MIN_BYTES
    with progress(args, 3 if big else 0, unit="stage", desc="convert") as advance:
        log = load(args.input, fmt=args.fmt, **hints_from_args(args))
        advance(1)
        if args.units is not None or args.wavelength is not None:
            log = log.to_units(args.units or log.units, wavelength=args.wavelength)
        if args.convention is not None:
            log = log.to_convention(args.convention)
        advance(1)
        path = save(log, args.output, fmt=fmt, overwrite=args.overwrite)
        advance(1)
    if not args.quiet:
        sys.stdout.write(
            f"wrote {path}: {log.n_frames} frames x {log.n_modes} modes, {log.units}, "
            f"{log.convention}\n"
        )
        for repair in log.repairs:
            sys.stdout.write(f"repair: {repair}\n")
    return 0
