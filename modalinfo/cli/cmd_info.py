"""``modalinfo info LOG``: describe a telemetry log and summarise every mode in one pass.

Prints the shape, time axis (the median rate, jitter and gaps of timestamps), modes,
units, loop state and metadata, then a table of per-mode mean, RMS, standard deviation
and lag-1 autocorrelation computed chunk by chunk (NPY, NPZ and HDF5 logs larger than
``modalinfo.io.MAP_ABOVE``, 128 MiB, or 1/8 of the usable memory are memory-mapped,
so a log larger than memory is fine; a smaller one is read). Values the file does not
record and no hint gave are marked "(assumed)". The checksum of a memory-mapped NPZ/HDF5 log
is verified during the same pass; the "integrity" line says what was verified. The
"quality" line reports the log-quality pass (:mod:`modalinfo.telemetry.quality`:
outliers beyond median +- k x 1.4826 MAD whose AR(4) innovation is beyond k of its
robust sigmas too, glitched frames, stuck runs; it adds a caveat where the innovations'
scale changes across the log, i.e. the seeing was not steady), and
``--outliers clip|drop`` summarises the repaired log (``raise`` refuses a flagged
log). A progress bar goes to stderr when it is a terminal, unless ``--quiet``: the
only thing ``--quiet`` removes here, since the report is the command's whole output
(other commands' ``--quiet`` prints nothing and needs their output file).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from modalinfo.cli import CommandError
from modalinfo.cli.shared import add_hint_arguments, apply_outliers, hints_from_args
from modalinfo.common.cli import write_stdout
from modalinfo.common.files import shown_name
from modalinfo.common.text import display_width, pad
from modalinfo.telemetry.checks import mode_span

NAME = "info"
HELP = "Describe a telemetry log: shape, rate, modes, units and per-mode RMS / lag-1 ACF."

_PROGRESS_MIN_FRAMES = 1_000_000


#: What an AOT loop's coefficients are (closedloop's MI_QUANT card) -> the words of ``info``.
_QUANTITIES = {
    "pol": "pseudo-open-loop coefficients (the turbulence the loop corrected: residual "
           "plus applied commands), not the loop's residual",
    "residual": "the loop's residual",
}


def _loop_text(meta: dict) -> str:
    """Return the ``loop`` line: open/closed, and what the coefficients are if the file says."""
    loop = meta.get("loop", "unknown")
    quantity = meta.get("coefficient_quantity")
    if quantity is None:
        return str(loop)
    what = _QUANTITIES.get(quantity, f"coefficients of kind {quantity!r}")
    return f"{loop} during the recording; these are {what}"


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
    # the report on stdout is the command's whole output (it writes no file): --quiet
    # cannot mean "print nothing" here, as it does for reorder / forecast / convert /
    # synth / fitting-error; it says what it does (fix57-d)
    parser.add_argument("--quiet", action="store_true",
                        help="no progress bar only: the report on stdout is the command's "
                             "output and still prints (unlike reorder's --quiet)")
    parser.add_argument("--no-mmap", action="store_true", help="read the file instead of mapping")
    add_hint_arguments(parser, deprecated=("--modes", "--units"))


def _fmt(value: float) -> str:
    return "n/a" if value != value else f"{value:.4f}"  # NaN: constant mode


def _sampling_text(s) -> str:
    """Jitter and gaps of a timestamped log, one line."""
    if s.jitter < 1e-6:  # rounding of the stored times only
        text = "jitter none (< 1e-6 of the median interval); "
    else:
        text = f"jitter {100 * s.jitter:.3g}% of the median interval; "
    if s.uniform:
        change = "" if not s.rate_change else f"; {s.describe_rate_change()}"
        return text + f"no gaps (interval > {s.gap_factor:g} x median)" + change
    a, b = s.longest_segment
    if s.n_gaps == 0:  # only short intervals: the rate changed (round 9 PART b, row A01)
        return text + (f"{s.describe_irregular()}; longest equally spaced segment "
                       f"frames {a}..{b - 1}")
    k = int(s.gap_duration.argmax())
    short = "" if s.n_short == 0 else (f"; {s.n_short} interval(s) shorter than "
                                       f"1/{s.gap_factor:g} of the median (rate changes)")
    return text + (
        f"{s.n_gaps} gap(s) (interval > {s.gap_factor:g} x median), first {s.describe_gap(0)}"
        + ("" if k == 0 else f", largest {s.describe_gap(k)}")
        + short + f"; longest contiguous segment frames {a}..{b - 1}"
        + ("" if not s.rate_change else f"; {s.describe_rate_change()}")
    )


def run(args: argparse.Namespace) -> int:
    """Print the description and the per-mode summary of the log."""
    from modalinfo.cli.shared import check_log_rate
    from modalinfo.io import integrity_check, load, mapping_pays
    from modalinfo.telemetry import summarize

    if args.chunk_frames < 1:
        raise CommandError(f"--chunk-frames must be >= 1; got {args.chunk_frames}")
    # a small log is read, not mapped: a mapped file truncated meanwhile is a SIGBUS
    mapped = not args.no_mmap and mapping_pays(args.log)
    loaded = load(args.log, fmt=args.fmt, mmap=mapped, dataset=args.dataset,
                  **hints_from_args(args))
    # a rate outside 1 mHz - 1 MHz (Unix ns read as seconds: 2e-6 Hz) refused as by every
    # other command (adversarial round 9 PART b, row A14)
    check_log_rate(loaded, args.log)
    log, quality = apply_outliers(loaded, args, args.log)  # refused here, before any output
    repaired = log.coeffs is not loaded.coeffs  # clip / drop changed the data
    meta = log.metadata
    labels = log.labels
    write_stdout(f"file        {shown_name(args.log)}\n")
    write_stdout(f"shape       {log.n_frames} frames x {log.n_modes} modes ({log.dtype})\n")
    assumed = meta.get("assumed") if isinstance(meta.get("assumed"), dict) else {}
    sampling = log.sampling()
    rate = "unknown (pass --rate)" if log.rate is None else f"{log.rate:.6g} Hz"
    if sampling is not None and sampling.n_frames > 1 and log._rate is None:  # noqa: SLF001
        rate = f"{sampling.median_rate:.6g} Hz median (mean {sampling.mean_rate:.6g} Hz)"
    duration = "unknown" if log.duration is None else f"{log.duration:.6g} s"
    axis = "timestamps" if log.timestamps is not None else "uniform"
    write_stdout(f"rate        {rate}, duration {duration} ({axis})\n")
    # a foreign rate field the timestamps overruled, said in full once (Leftovers 19-misc)
    field_note = meta.get("rate_field") if (
        log.timestamps is not None and meta.get("source_file") == Path(args.log).name) else None
    if isinstance(field_note, str):
        write_stdout(f"rate note   {field_note}\n")
    if sampling is not None and sampling.n_frames > 1:
        write_stdout(f"sampling    {_sampling_text(sampling)}\n")
    shown = ", ".join(labels) if len(labels) <= 8 else mode_span(log.modes, log.convention)
    if "modes" in assumed:  # the default modes: their convention is assumed with them
        write_stdout(f"modes       {shown} ({log.convention}) (assumed)\n")
    else:
        conv = f"{log.convention}, assumed" if "convention" in assumed else log.convention
        write_stdout(f"modes       {shown} ({conv})\n")
    wave = "" if log.wavelength is None else f" at wavelength {log.wavelength:.6g} m"
    mark = " (assumed)" if "units" in assumed else ""
    write_stdout(f"units       {log.units}{mark}{wave}\n")
    write_stdout(f"loop        {_loop_text(meta)}\n")
    for key in sorted(meta):
        if key in ("loop", "repairs", "assumed", "modes_identification",
                   "coefficient_quantity", "outliers"):
            continue
        if key == "rate_field" and isinstance(field_note, str):
            continue
        value = meta[key]
        text = "; ".join(f"{k} {v}" for k, v in value.items()) if isinstance(
            value, dict) else str(value)
        write_stdout(f"meta        {key}: {text if len(text) <= 90 else text[:87] + '...'}\n")
    for repair in meta.get("repairs", []) if isinstance(meta.get("repairs"), list) else []:
        write_stdout(f"repair      {repair}\n")
    write_stdout(f"quality     {quality.describe()}\n")
    from modalinfo.telemetry.sampling import repeated_blocks

    repeats = repeated_blocks(log.coeffs)
    if repeats:  # a block exported twice (audit 10-time: nothing was said)
        a, n, e = repeats[0]
        more = "" if len(repeats) == 1 else f" ({len(repeats)} such blocks)"
        write_stdout(f"repeats     frames {a}..{a + n - 1} repeat frames {e}..{e + n - 1} "
                  f"exactly{more}: a block written twice? lags see a jump back in time\n")
    earlier = loaded.metadata.get("outliers")
    for record in earlier if isinstance(earlier, list) else []:  # e.g. a clipped file
        if isinstance(record, dict):
            write_stdout(f"outliers    earlier: {record.get('policy')}: {record.get('action')}\n")
    if repaired:
        write_stdout(f"outliers    --outliers {args.outliers}: {meta['outliers'][-1]['action']}; "
                  "the summary below is of the result\n")
    if isinstance(meta.get("modes_identification"), dict):
        from modalinfo.bases.identify import ZernikeIdentification

        ident = ZernikeIdentification.from_dict(meta["modes_identification"])
        write_stdout("\nthe file's modes against our Zernikes (x along columns, y along rows):\n")
        write_stdout(ident.table() + "\n")

    from modalinfo.cli.shared import progress

    check = integrity_check(args.log, loaded, fmt=args.fmt, mmap=mapped)
    if repaired:  # checksum the file's data, summarise the result
        for block in loaded.iter_chunks(args.chunk_frames):
            check.update(block)
    with progress(args, log.n_frames, unit="frame", desc="info",
                  min_total=_PROGRESS_MIN_FRAMES) as advance:
        summary = summarize(log, chunk_frames=args.chunk_frames, progress=advance,
                            visit=None if repaired else check.update)
    check.finish()  # a checksum skipped by memory mapping is verified in the same pass
    write_stdout(f"integrity   {check.describe()}\n")
    unit = log.units
    width = max(6, *(display_width(label) for label in labels))
    write_stdout(
        f"\n{pad('mode', width)}  {'mean':>12}  {'rms':>12}  {'std':>12}  {'lag1':>8}   [{unit}]\n"
    )
    for k, label in enumerate(labels):
        write_stdout(
            f"{pad(label, width)}  {summary.mean[k]:>12.5g}  {summary.rms[k]:>12.5g}  "
            f"{summary.std[k]:>12.5g}  {_fmt(summary.lag1[k]):>8}\n"
        )
    lag1_note = _lag1_note(log, sampling)
    if lag1_note:
        write_stdout(f"note        {lag1_note}\n")
    return 0


def _lag1_note(log, sampling) -> str:
    """Say when lag1 paired frames that are not one interval apart (audit 10-time).

    lag1 pairs successive rows: across a gap, a rate change or frames removed from a
    log without a time axis, a pair is not one frame interval apart, and nothing said
    so beside the column.
    """
    if sampling is not None and sampling.n_frames > 1 and not sampling.uniform:
        k = sampling.n_gaps + sampling.n_short
        return (f"lag1 pairs successive frames: {k} of the {sampling.n_frames - 1} pairs "
                f"({100 * k / (sampling.n_frames - 1):.2g}%) lie across gaps or rate "
                "changes")
    from modalinfo.telemetry.sampling import require_frames_kept

    try:
        require_frames_kept(log, "lag1")
    except ValueError:
        return ("lag1 pairs successive frames, also the frames around those removed from "
                "this log without a time axis (give --rate to see them as gaps)")
    return ""
