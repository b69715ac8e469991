"""``modalinfo convert IN OUT``: change a log's format, units or mode convention.

The output format comes from OUT's extension (``.npz``, ``.csv``, ``.fits``, ``.h5``)
or ``--to-fmt`` (``aot`` writes an AO Telemetry file; any other extension, ``.txt``
included, needs ``--to-fmt``, as in ``synth``). Writing is atomic and refuses to replace
OUT without ``--overwrite``.

``--units`` and ``--convention`` are the OUTPUT units and convention (the input's are
the hints ``--in-units``/``--in-convention``, as in every command). A conversion of
units never assumes the input units: a file that does not record them needs
``--in-units``.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from modalinfo.cli import CommandError
from modalinfo.cli.shared import (
    LOG_COPIES,
    _check_log_fits,
    add_hint_arguments,
    apply_outliers,
    check_log_output,
    command_provenance,
    hints_from_args,
    input_notes,
    progress,
    queue_notes,
    wavelength_arg,
)
from modalinfo.common.files import quoted, shown_name
from modalinfo.common.sizes import log_bytes

NAME = "convert"

HELP = "Convert a telemetry log between formats (npz/csv/fits/h5), units and conventions."
_PROGRESS_MIN_BYTES = 16 * 2**20  # a bar (load, convert, write) from 16 MiB: seconds of work


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Fill the ``convert`` parser."""
    parser.add_argument("input", metavar="IN", help="input log file")
    parser.add_argument("output", metavar="OUT", help="output file (.npz, .csv, .fits, .h5)")
    # files after OUT: a night's parts given to be joined were "unrecognized arguments:
    # <last file>", as if IN -> OUT were right (adversarial round 34 PART b, C03, C04)
    parser.add_argument("more", nargs="*", default=[], help=argparse.SUPPRESS)
    parser.add_argument(
        "--units",
        choices=("rad", "nm", "um", "waves"),
        help="OUTPUT units: convert the coefficients to these (the input units come from "
        "the file or --in-units; a wavelength is needed between phase and OPD units)",
    )
    parser.add_argument(
        "--wavelength",
        type=wavelength_arg,
        metavar="M",
        help="wavelength in metres at which the phase is defined: the input's if the file "
        "lacks it, else that of the phase converted from OPD (nm, um)",
    )
    parser.add_argument(
        "--convention",
        choices=("noll", "ansi", "fringe"),
        help="OUTPUT convention: re-index the Zernike modes in it",
    )
    parser.add_argument(
        "--to-fmt", choices=("npz", "csv", "fits", "hdf5", "aot"),
        help="output format (default: ext; aot: an AO Telemetry file, give it explicitly)"
    )
    parser.add_argument("--overwrite", action="store_true", help="replace OUT if it exists")
    parser.add_argument("--quiet", action="store_true",
                        help="print nothing on success (and no progress bar)")
    add_hint_arguments(parser, wavelength=False)


def run(args: argparse.Namespace) -> int:
    """Read IN, convert, write OUT."""
    from modalinfo.io import load, save

    more = list(getattr(args, "more", None) or ())
    if more:
        raise CommandError(
            f"convert reads one log (IN) and writes one file (OUT); got {len(more) + 2} "
            f"files ({quoted(args.input)}, {quoted(args.output)}, "
            f"{', '.join(map(quoted, more))}): no command joins logs - concatenate the parts "
            "first (numpy: np.concatenate of their coefficients, in time order) or analyse "
            "them as an archive with `batch`")
    source = Path(args.input)
    if source.exists() and os.path.exists(args.output) and os.path.samefile(source,
                                                                            args.output):
        # --overwrite of the input itself replaced an AOT system (its loops, sensors,
        # mirrors) by one loop's plain FITS without a word (round 44 PART b, d22); asked
        # before "exists; pass --overwrite", whose advice led to this refusal
        raise CommandError(
            f"OUT {quoted(args.output)} is the input file IN ({quoted(args.input)}); convert "
            "writes one log of it, and what IN holds besides (other loops or datasets, the "
            "system of an AOT file) would be lost: write to another name")
    fmt = check_log_output(Path(args.output), args.overwrite, args.to_fmt)  # before reading
    big = source.is_file() and source.stat().st_size >= _PROGRESS_MIN_BYTES
    options = {"fmt": args.fmt, "dataset": args.dataset, **hints_from_args(args)}
    if source.is_file():  # the log, its converted copy and the writer's buffer
        _check_log_fits(source, options, LOG_COPIES, args,
                        _aot_write_need if fmt == "aot" else None)
    with progress(args, 3 if big else 0, unit="stage", desc="convert") as advance:
        log = load(args.input, **options)
        advance(1)
        assumed = log.metadata.get("assumed")
        if (
            args.units is not None
            and isinstance(assumed, dict)
            and "units" in assumed
            and args.units != log.units
        ):
            raise CommandError(
                f"--units {args.units}: {quoted(args.input)} does not record the units of its "
                "coefficients; give them with --in-units (rad, nm, um or waves)"
            )
        queue_notes(args, input_notes(log, Path(args.input)))  # a warning: even with --quiet
        # --outliers clip|drop writes the repaired log; metadata["outliers"] records it
        log, _ = apply_outliers(log, args, source)
        if args.units is not None or args.wavelength is not None:
            log = log.to_units(args.units or log.units, wavelength=args.wavelength)
        if args.convention is not None:
            log = log.to_convention(args.convention)
        advance(1)
        # what made the file: metadata["provenance"], one record per conversion, the
        # newest last, each naming its source by SHA-256 (round 18 PART b, P06)
        steps = log.metadata.get("provenance")
        steps = list(steps) if isinstance(steps, list) else [] if steps is None else [steps]
        log = log.with_metadata(provenance=[*steps, command_provenance(args, source)])
        path = save(log, args.output, fmt=fmt, overwrite=args.overwrite)
        advance(1)
    if not args.quiet:
        from modalinfo.common.cli import written_summary

        with written_summary():
            sys.stdout.write(
                f"wrote {shown_name(path)}: {log.n_frames} frames x {log.n_modes} modes, "
                f"{log.units}, {log.convention}\n"
            )
            for repair in log.repairs:
                sys.stdout.write(f"repair: {repair}\n")
    return 0


def _aot_write_need(log) -> tuple[float, str]:
    """Peak of writing ``log`` as AOT with the log held [bytes], and the words naming it.

    The peak is ``log_bytes`` plus ``estimate_write_aot``'s.

    Checked with the log's other estimates before it is read, so that the first refusal
    names the writer's figure (it was refused after the load, 185.39 MiB, under a limit
    set from the first refusal's 123.60 MiB: round 50 PART b, M17).
    """
    from modalinfo.io.aot import estimate_write_aot

    return log_bytes(log) + estimate_write_aot(log)[1], "writing this log as AOT"

