"""``modalinfo select LOG --target Z5``: choose a forecast's inputs by conditional MI.

For the target mode at ``--horizon`` h, the candidates are lags 0 .. max_lag - 1 of
every mode of the log (and of ``--extra``, a second log on the same clock, e.g. the
other WFS of an MCAO run); the greedy search adds the candidate with the largest gain
I(target[t+h]; candidate | chosen) while the maximum-statistic time-shift surrogate
test over all candidates is significant at ``--alpha`` (family-wise per step), up to
``--max-inputs``. Prints one row per chosen input: gain, block-bootstrap interval,
p-value. See :func:`modalinfo.information.select_inputs`.

``--candidates radial`` keeps only the modes within ``--radial-width`` radial orders of
the target (frozen flow couples modes of similar radial order;
:mod:`modalinfo.information.candidates`): the search over 1,500 modes then scores a few
hundred candidate modes instead of all of them.

    modalinfo select kaos.npz --target Z5 --horizon 2 --max-lag 10
    modalinfo select big.npy --target Z500 --candidates radial --radial-width 2
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from modalinfo.cli import CommandError
from modalinfo.cli._choices import MIMethodChoices
from modalinfo.cli.shared import (
    LOG_COPIES,
    add_gap_argument,
    add_hint_arguments,
    add_max_frames_argument,
    apply_outliers,
    check_command_memory,
    check_memory,
    frame_subsample,
    load_log_with_hints,
    log_bytes,
    quality_need,
    refuse_outlier_drop,
    split_gaps,
)
from modalinfo.common.files import quoted
from modalinfo.telemetry.checks import find_label

NAME = "select"
HELP = "Choose the past values (mode, lag) that forecast a mode, by conditional MI."
EPILOG = ("columns: input = mode[t-lag] relative to the forecast origin t; gain = "
          "I(target; input | inputs above) in --units; interval = block-bootstrap "
          "(normal, nominal 95%; measured 89-90% on AR(1) logs with phi 0.9, see the "
          "table's last line); p = max-statistic surrogate p-value of the step")


#: Estimated CPU seconds of the first step above which the command says so before work.
_NOTE_SECONDS = 10.0


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Fill the ``select`` parser."""
    parser.add_argument("log", type=Path, metavar="LOG",
                        help="telemetry log (npz, npy, csv, fits, hdf5)")
    parser.add_argument("--target", required=True, metavar="MODE",
                        help="mode to forecast: a label (Z5) or a column index (3)")
    parser.add_argument("--horizon", type=int, default=1, metavar="H",
                        help="forecast horizon in frames (default: 1)")
    parser.add_argument("--max-lag", dest="max_lag", type=int, default=10, metavar="L",
                        help="candidate lags 0..L-1 of every mode (default: 10)")
    parser.add_argument("--extra", type=Path, default=None, metavar="LOG2",
                        help="second log on the same clock whose modes are candidates too")
    parser.add_argument("--method", choices=MIMethodChoices("cmi"), metavar="NAME",
                        default="gaussian",
                        help="CMI estimator: %(choices)s (default: gaussian, the linear "
                        "predictor's criterion; the others cost one estimate per candidate "
                        "and surrogate)")
    parser.add_argument("--alpha", type=float, default=0.05,
                        help="family-wise level of each step (default: 0.05)")
    parser.add_argument("--surrogates", type=int, default=199, metavar="N",
                        help="time-shift surrogates per step (default: 199)")
    parser.add_argument("--max-inputs", dest="max_inputs", type=int, default=10, metavar="K",
                        help="budget of inputs (default: 10)")
    parser.add_argument("--no-intervals", dest="intervals", action="store_false",
                        help="skip the bootstrap intervals")
    parser.add_argument("--units", choices=("nats", "bits"), default="nats",
                        help="units of the gains (default: nats)")
    parser.add_argument("--seed", type=int, default=0, help="surrogate seed (default: 0)")
    parser.add_argument("--candidates", choices=("all", "radial"), default="all",
                        help="candidate modes: all (default) or radial, those within "
                        "--radial-width radial orders of the target (Zernike Z<j> or K-L "
                        "KL<k> labels; the max-statistic test is then over them)")
    parser.add_argument("--radial-width", dest="radial_width", type=int, default=None,
                        metavar="K", help="largest radial-order difference of --candidates "
                        "radial (default: the library's, modalinfo.information.candidates."
                        "RADIAL_WIDTH)")
    parser.add_argument("--max-seconds", dest="max_seconds", type=float, default=None,
                        metavar="S", help="refuse, before any work, a search whose first "
                        "step is estimated above S seconds of CPU (default: the library's, "
                        "modalinfo.information.selection.MAX_SEARCH_SECONDS = 600; only "
                        "--method ksg, kde and histogram are slow)")
    add_max_frames_argument(parser, default=None, contiguous=True)
    add_gap_argument(parser)
    # clip by default, as select_inputs(outliers="clip"): under warn the command said
    # "used as is" while the search replaced the glitches beneath it (fix56-b)
    add_hint_arguments(parser, outliers_default="clip", outliers_why=(
        ": the search scores the cleaned values, as select_inputs(outliers='clip'); "
        "warn scores the values as given, as select_inputs(outliers='warn')"))


def _load(args: argparse.Namespace, path: Path):
    """Map ``path`` and keep its first ``--max-frames`` frames (checked by :func:`_check_memory`).

    With ``--split-gaps``, then its longest gap-free segment (otherwise gaps are refused).
    """
    full = load_log_with_hints(path, args, mmap=True)
    log = frame_subsample(full, args, contiguous=True)
    _check_max_frames_leave_enough(args, log.n_frames, full.n_frames, path)
    # lagged pairs must not straddle a gap: refused, or (--split-gaps) the longest
    # contiguous segment, as forecast and reorder (frames dropped by --nonfinite drop
    # from a log without a time axis refused too: adversarial round 9 PART b, N40-N43).
    # The refusal advised "--max-frames or convert that part", which cannot reach a
    # segment in the middle of the log (round 33 PART b, B26)
    return split_gaps(log, args, path, "input selection (its lagged pairs)")


def _check_memory(args: argparse.Namespace, log, extra) -> int:
    """Refuse, before any quality pass, a selection whose copies or passes cannot fit.

    One figure for the whole command: LOG's and ``--extra``'s float64 copies, the candidate
    search's working arrays on every candidate column (both logs' modes x ``--max-lag``),
    or the larger quality pass if larger (``--extra``'s runs while LOG's clipped copy is
    held). A check after a pass reads an available figure that has lost the address space
    the pass leaves mapped (numba's first dispatch, the allocator's freed pages: 58 MiB on
    a 20,000 x 6 log, in no estimate): a later ``--max-lag`` check (stop 57, fix51-c) and,
    with ``--extra``, its own check after LOG's pass refused, with "0 B is available", a
    command 3 % above its first refusal's limit (fix52-c). Returns the candidate columns
    counted, so that :func:`run` checks again only columns beyond them.
    """
    lags = getattr(args, "max_lag", None) or 0
    logs = [(log, args.log)] + ([(extra, args.extra)] if extra is not None else [])
    own = LOG_COPIES * sum(log_bytes(x) for x, _ in logs)
    modes = " + ".join(str(x.n_modes) for x, _ in logs)
    what = (" and ".join(quoted(Path(p).name) for _, p in logs)
            + f" ({log.n_frames} frames x {modes} modes, {LOG_COPIES} float64 copies"
            + (" each" if extra is not None else ""))
    columns = sum(x.n_modes for x, _ in logs) * lags if lags >= 1 else 0
    if lags >= 1:
        from modalinfo.information.selection import search_bytes

        own += search_bytes(log.n_frames * columns)
        what += f", and --max-lag {lags}'s {columns} candidate columns"
    # the larger pass: --extra's holds LOG's repaired copy under --outliers clip
    held = log_bytes(log) if getattr(args, "outliers", "warn") == "clip" else 0.0
    passes = [(quality_need(log, args), log, 0.0)]
    if extra is not None:
        passes.append((quality_need(extra, args, held), extra, held))
    _, larger, resident = max(passes, key=lambda t: t[0])
    check_command_memory(own, what + ")", "use --max-frames N (the first N frames)"
                         + (" or a smaller --max-lag" if lags >= 1 else ""), larger, args,
                         resident)
    return columns


def _check_max_frames_leave_enough(args: argparse.Namespace, kept: int, total: int,
                                   path: Path) -> None:
    """Refuse a ``--max-frames`` that leaves fewer frames than the selection takes.

    Named as the user's option: the library's "`data` needs at least 22 frames ...; got
    12" read "the log needs ..." of a 400-frame log (fixes 45-c, round 45 PART b T74).
    """
    from modalinfo.information.selection import least_selection_frames

    if kept >= total or not (isinstance(args.horizon, int) and args.horizon >= 1
                             and isinstance(args.max_lag, int) and args.max_lag >= 1):
        return  # not cut, or a --horizon / --max-lag select_inputs refuses by name
    pairs = least_selection_frames(args.horizon, args.max_lag)
    # the surrogates' shifts need rows too: advice on the pairs alone was refused next
    # ("199 circular shifts ... do not fit in 20 rows", review29 M3)
    surrogates = max(args.surrogates, 0) if isinstance(args.surrogates, int) else 0
    least = least_selection_frames(args.horizon, args.max_lag, surrogates)
    if kept < least:
        why = ("20 rows of lagged pairs" if least == pairs else
               f"rows for --surrogates {surrogates} circular shifts clear of the lags")
        raise CommandError(f"--max-frames {args.max_frames} leaves {kept} of the {total} "
                           f"frames of {quoted(path.name)}; --horizon {args.horizon} and --max-lag "
                           f"{args.max_lag} need at least {least} ({why}): "
                           f"give --max-frames {least} or more")


def _radial_width(args: argparse.Namespace) -> int:
    """``--radial-width`` checked: an int >= 0, and only with ``--candidates radial``."""
    if args.radial_width is None:
        from modalinfo.information.candidates import RADIAL_WIDTH

        return RADIAL_WIDTH
    if args.candidates != "radial":
        raise CommandError(f"--radial-width {args.radial_width} applies to --candidates "
                           f"radial; got --candidates {args.candidates}")
    if args.radial_width < 0:
        raise CommandError(f"--radial-width must be an int >= 0; got {args.radial_width}")
    return args.radial_width


def _radial_sources(log, extra, target: int | str, width: int) -> int:
    """Candidate modes of ``target`` under ``--candidates radial`` (labels checked)."""
    from modalinfo.information.candidates import candidate_mask, radial_orders

    labels = list(log.labels)
    if extra is not None:
        labels += [f"extra:{s}" for s in extra.labels]
    for label in labels:  # the library's message offers a mask, which the CLI does not
        try:
            radial_orders([label])
        except ValueError:
            raise CommandError(f"--candidates radial needs Zernike (Z<j>, Noll) or K-L "
                               f"(KL<k>) mode labels; got {label!r}") from None
    col = target if isinstance(target, int) else labels.index(target)
    return int(candidate_mask(labels, "radial", width)[:, col].sum())


def run(args: argparse.Namespace) -> int:
    """Run the selection and print the table."""
    from modalinfo.information.selection import (
        MAX_SEARCH_SECONDS,
        first_step_seconds,
        search_bytes,
        select_inputs,
    )

    refuse_outlier_drop(args, "input selection")
    if args.surrogates >= 1 and 0 < args.alpha < 1 and 1 / (args.surrogates + 1) > args.alpha:
        # the smallest surrogate p-value is 1 / (N + 1): no input could ever be significant
        raise CommandError(f"--surrogates {args.surrogates} cannot reach --alpha {args.alpha:g}: "
                           f"the smallest p-value of {args.surrogates} surrogates is "
                           f"1/{args.surrogates + 1} = {1 / (args.surrogates + 1):.3g}; use "
                           f"--surrogates >= {math.ceil(1 / args.alpha) - 1}")
    width = _radial_width(args)
    log = _load(args, args.log)
    extra = None
    if args.extra is not None:
        import os

        if os.path.exists(args.extra) and os.path.exists(args.log) and os.path.samefile(
                args.extra, args.log):
            raise CommandError(f"--extra {quoted(args.extra)} is LOG itself: its modes are "
                               "candidates already")
        extra = _load(args, args.extra)
    # both logs mapped, nothing computed yet: one check of the whole command (fix52-c)
    checked = _check_memory(args, log, extra)
    log, _ = apply_outliers(log, args, args.log, time_series=True)
    if extra is not None:
        # its pass was counted by that check: checked again here, after LOG's pass, it
        # read the address space LOG's pass leaves mapped as used (fix52-c)
        extra, _ = apply_outliers(extra, args, args.extra, time_series=True, checked=True)
        if extra.n_frames != log.n_frames:
            raise CommandError(f"--extra has {extra.n_frames} frames, LOG has {log.n_frames}; "
                               "the two logs must share the clock")
        # stated rates must match; timestamps are compared frame by frame by
        # select_inputs (two logs of one clock with timing noise have mean rates 1e-5
        # apart and were refused as "2000.02 Hz, LOG at 2000.02 Hz": audit 10-time)
        stated = extra.timestamps is None and log.timestamps is None
        if stated and extra.rate is not None and log.rate is not None and not math.isclose(
                extra.rate, log.rate, rel_tol=1e-9):  # same length, another clock: lags lie
            # 15 digits: rates 1.1e-9 apart printed as "2000 Hz, LOG at 2000 Hz" (round 10 B, SX3)
            raise CommandError(f"--extra is sampled at {extra.rate:.15g} Hz, LOG at "
                               f"{log.rate:.15g} Hz (relative difference "
                               f"{abs(extra.rate / log.rate - 1):.2g}, above 1e-9); the two "
                               "logs must share the clock")
    target = args.target
    if target.isdecimal():  # not isdigit: '³' reached int() unnamed (fixes 45-c, Y14)
        target = int(target)
        if target >= log.n_modes:
            raise CommandError(f"--target column {target} is out of range: LOG has "
                               f"{log.n_modes} modes (0..{log.n_modes - 1})")
    elif find_label(log.labels, target) is None:  # by NFC: round 21 PART b, u10
        raise CommandError(f"--target {target!r} is not a mode of LOG "
                           f"({', '.join(log.labels[:5])}, ...)")
    col = target if isinstance(target, int) else find_label(log.labels, target)
    y = np.asarray(log.coeffs[:, col])
    if y.size and np.ptp(y) <= 1e-12 * np.max(np.abs(y)):
        # a zeroed or stuck target: "stopped: no candidate left" with every candidate
        # left, or an "affine function of a candidate" refusal (round 11 PART b, V08)
        raise CommandError(f"--target {log.labels[col]} is constant over the analysed "
                           f"frames (value {y[0]:.6g}): nothing to forecast, no input to "
                           "select")
    n_sources = log.n_modes + (extra.n_modes if extra is not None else 0)
    if args.candidates == "radial":
        n_sources = _radial_sources(log, extra, target, width)
    columns = n_sources * args.max_lag if args.max_lag is not None and args.max_lag >= 1 else 0
    if columns > checked:
        # the candidate search's working arrays (information.selection's estimate) on
        # more columns than _check_memory admitted (none: it counts both logs' modes,
        # fix52-c). Not checked again on those: the available figure has lost, since that
        # check, the address space the quality pass leaves mapped (numba's first dispatch
        # and its cached kernels, the allocator's freed pages: 58 MiB on a 20,000 x 6
        # log, in no estimate), and select 3 % above its first refusal's limit was
        # refused here with "0 B is available" though it ran in 499 MiB of 545 (stop 57,
        # fix51-c)
        check_memory(search_bytes(log.n_frames * columns),
                     f"--max-lag {args.max_lag} ({columns} candidate columns x "
                     f"{log.n_frames} frames)", "use a smaller --max-lag or --max-frames")
    from modalinfo.common.validation import check_square_range

    for name, data in (("log", log), ("extra", extra)):  # 1e300 failed inside the search
        if data is not None:  # with numpy's "zero-size array to reduction operation"
            check_square_range(np.asarray(data.coeffs), name, data.labels)
    max_seconds = MAX_SEARCH_SECONDS if args.max_seconds is None else args.max_seconds
    if args.max_lag >= 1 and args.surrogates >= 0:  # tell the user before the work
        rows = log.n_frames - args.horizon - args.max_lag + 1
        seconds = first_step_seconds(args.method, max(rows, 2), n_sources * args.max_lag,
                                     args.surrogates)
        if seconds is not None and _NOTE_SECONDS < seconds <= max_seconds:
            sys.stderr.write(f"modalinfo select: note: --method {args.method} scores "
                             f"{n_sources * args.max_lag} candidates x {args.surrogates + 1} "
                             f"(1 + --surrogates) per step: about {seconds:.0f} s of CPU "
                             "for the first step (estimated), more for each later one; "
                             "--method gaussian takes well under a second\n")
            sys.stderr.flush()
    res = select_inputs(log, target, horizon=args.horizon, max_lag=args.max_lag, extra=extra,
                        method=args.method, units=args.units, alpha=args.alpha,
                        n_surrogates=args.surrogates, max_inputs=args.max_inputs,
                        intervals=args.intervals, seed=args.seed,
                        candidates=args.candidates, radial_width=width,
                        max_seconds=max_seconds,
                        outliers="warn" if args.outliers == "warn" else "clip")
    print(res.table())
    return 0
