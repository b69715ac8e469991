"""``modalinfo info LOG``: describe a telemetry log and summarise every mode in one pass.

Prints the shape, time axis, modes, units, loop state and metadata, then a table of
per-mode mean, RMS, standard deviation and lag-1 autocorrelation computed chunk by
chunk (NPY, NPZ and HDF5 logs are memory-mapped, so a log larger than memory is
fine). A progress bar goes to stderr when it is a terminal, unless ``--quiet``.
"""

from __future__ import annotations

import argparse
import sys

from modalinfo.cli import CommandError
from modalinfo.cli._common import add_hint_arguments, hints_from_args

NAME = "info"
HELP = "Describe a telemetry log: shape, rate, modes, units and per-mode RMS / lag-1 ACF."

_PROGRESS_MIN_FRAMES = 1_000_000


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Fill the ``info`` parser."""
    parser.add_argument("log", metavar="LOG", help="log file (npz, npy, csv, fits, h5)")
    parser.add_argument(
        "--chunk-frames",
        type=int,
        default=65536,
        metavar="N",
        help="frames per chunk of the one-pass summary (default 65536)",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.add_argument("--no-mmap", action="store_true", help="read the file instead of mapping")
    add_hint_arguments(parser)


def _fmt(value: float) -> str:
    return "n/a" if value != value else f"{value:.4f}"  # NaN: constant mode


def run(args: argparse.Namespace) -> int:
    """Print the description and the per-mode summary of the log."""
    from modalinfo.io import load
    from modalinfo.telemetry import summarize

    if args.chunk_frames < 1:
        raise CommandError(f"--chunk-frames must be >= 1; got {args.chunk_frames}")
    log = load(args.log, fmt=args.fmt, mmap=not args.no_mmap, **hints_from_args(args))
    out = sys.stdout
    meta = log.metadata
    labels = log.labels
    out.write(f"file        {args.log}\n")
    out.write(f"shape       {log.n_frames} frames x {log.n_modes} modes ({log.dtype})\n")
    rate = "unknown (pass --rate)" if log.rate is None else f"{log.rate:.6g} Hz"
    duration = "unknown" if log.duration is None else f"{log.duration:.6g} s"
    axis = "timestamps" if log.timestamps is not None else "uniform"
    out.write(f"rate        {rate}, duration {duration} ({axis})\n")
    shown = ", ".join(labels) if len(labels) <= 8 else f"{labels[0]} .. {labels[-1]}"
    out.write(f"modes       {shown} ({log.convention})\n")
    wave = "" if log.wavelength is None else f" at wavelength {log.wavelength:.6g} m"
    out.write(f"units       {log.units}{wave}\n")
    out.write(f"loop        {meta.get('loop', 'unknown')}\n")
    for key in sorted(meta):
        if key in ("loop", "repairs"):
            continue
        text = str(meta[key])
        out.write(f"meta        {key}: {text if len(text) <= 70 else text[:67] + '...'}\n")
    for repair in meta.get("repairs", []) if isinstance(meta.get("repairs"), list) else []:
        out.write(f"repair      {repair}\n")

    from modalinfo.cli._common import progress

    with progress(args, log.n_frames, unit="frame", desc="info",
                  min_total=_PROGRESS_MIN_FRAMES) as advance:
        summary = summarize(log, chunk_frames=args.chunk_frames, progress=advance)
    unit = log.units
    width = max(6, *(len(label) for label in labels))
    out.write(
        f"\n{'mode':<{width}}  {'mean':>12}  {'rms':>12}  {'std':>12}  {'lag1':>8}   [{unit}]\n"
    )
    for k, label in enumerate(labels):
        out.write(
            f"{label:<{width}}  {summary.mean[k]:>12.5g}  {summary.rms[k]:>12.5g}  "
            f"{summary.std[k]:>12.5g}  {_fmt(summary.lag1[k]):>8}\n"
        )
    return 0
