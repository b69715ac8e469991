"""``modalinfo forecast LOG``: rolling-origin evaluation of wavefront predictors.

Example::

    modalinfo forecast kaos.npz --predictors linear,arma,nn --modes 2-10 --horizon 10
    modalinfo forecast kaos.npz --predictors multivariate --train 7000 --out results/

Each predictor is trained on the first ``--train`` frames (a fraction or a number of
frames) and evaluated on every later forecast origin without look-ahead (see
:func:`modalinfo.forecast.evaluate`); persistence and the training mean are always
included as baselines. The command prints the whole-wavefront RMSE and the gain over
persistence per horizon; ``--out DIR`` writes ``forecast.json``, ``forecast.csv``,
``forecast_series.png`` and ``forecast_rmse.png`` (never replacing files unless
``--overwrite``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from modalinfo.cli import CommandError
from modalinfo.cli._common import (
    add_gap_argument,
    add_hint_arguments,
    apply_outliers,
    refuse_outlier_drop,
    split_gaps,
)

NAME = "forecast"
HELP = "Evaluate wavefront predictors (linear, ARMA, neural net, multivariate) on a log."

OUTPUTS = ("forecast.json", "forecast.csv", "forecast_series.png", "forecast_rmse.png")


NAMES = ("linear", "linear-ls", "arma", "arma-aic", "nn", "nn-paper", "multivariate", "rls",
         "info", "info-nn")
"""The preset names of :mod:`modalinfo.forecast.presets`, listed without importing it."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Fill the ``forecast`` subparser."""
    parser.add_argument("log", metavar="LOG", type=Path,
                        help="log file (npz, csv, fits, h5), loaded with modalinfo.io.load")
    parser.add_argument("--predictors", default="linear,arma,nn,multivariate", metavar="LIST",
                        help=f"comma-separated, from {', '.join(NAMES)} (default: "
                        "%(default)s); persistence and mean are always added")
    parser.add_argument("--modes", default=None, metavar="LIST",
                        help="SELECTION of the modes to forecast: '2-10', '2,3,4' or labels "
                        "(default: all); what the columns are is the hint --in-modes")
    parser.add_argument("--horizon", type=int, default=10, metavar="H",
                        help="largest horizon in frames; h = 1..H (default: %(default)s)")
    parser.add_argument("--train", default="0.5", metavar="FRAC_OR_N",
                        help="training frames: a fraction in (0, 1) or a count "
                        "(default: %(default)s)")
    parser.add_argument("--refit-every", type=int, default=None, metavar="R",
                        help="re-estimate every R frames on a sliding window")
    parser.add_argument("--window", type=int, default=None, metavar="W",
                        help="sliding-window length for refits (default: training length)")
    parser.add_argument("--out", type=Path, default=None, metavar="DIR",
                        help="write JSON, CSV and plots into DIR (created if missing)")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace existing output files")
    parser.add_argument("--skip-constant", action="store_true",
                        help="leave out modes constant over the training frames (a zeroed "
                        "or dead mode); by default they are kept and every predictor "
                        "forecasts them as that constant (exact, as persistence)")
    parser.add_argument("--quiet", action="store_true",
                        help="print nothing on success (and no progress bar)")
    add_hint_arguments(parser)
    add_gap_argument(parser)


def _parse_train(text: str) -> float | int:
    try:
        value = float(text)
    except ValueError:
        raise CommandError(f"--train must be a fraction in (0, 1) or a number of frames; "
                           f"got {text!r}") from None
    if value >= 1:
        if not value.is_integer():
            raise CommandError(f"--train must be a fraction in (0, 1) or a whole number of "
                               f"frames; got {text}")
        return int(value)
    return value


def _parse_predictors(text: str) -> dict:
    from modalinfo.forecast.presets import make_predictor

    chosen = {}
    for part in (p.strip() for p in text.split(",")):
        if part not in NAMES:
            raise CommandError(f"--predictors: unknown predictor {part!r}; choose from "
                               f"{', '.join(NAMES)}")
        chosen[part] = make_predictor(part)
    return chosen


def _constant_modes(log, train: float | int, horizon: int) -> list[str]:
    """Labels of the modes constant over the training frames (the predictors' rule)."""
    import numpy as np

    from modalinfo.forecast.base import Predictor

    n_train = train if isinstance(train, int) else int(round(train * log.n_frames))
    n_train = min(max(n_train, 1), log.n_frames)
    constant = Predictor._constant_columns(np.asarray(log.coeffs[:n_train]))[0]
    return [label for label, c in zip(log.labels, constant, strict=True) if c]


def run(args: argparse.Namespace) -> int:
    """Evaluate, print the table, write the outputs; return 0."""
    from modalinfo.bases.indexing import parse_modes
    from modalinfo.cli._common import load_log_with_hints

    if args.horizon < 1:
        raise CommandError(f"--horizon must be an int >= 1; got {args.horizon}")
    refuse_outlier_drop(args, "forecasting")
    predictors = _parse_predictors(args.predictors)
    train = _parse_train(args.train)
    if args.out is not None:
        if args.out.exists() and not args.out.is_dir():
            raise CommandError(f"--out '{args.out}' exists and is not a directory")
        if not args.out.exists() and args.out.suffix.lower() in (".json", ".csv", ".png"):
            raise CommandError(f"--out '{args.out}' names a file; --out takes a directory "
                               f"(it receives {', '.join(OUTPUTS)})")
        clash = [n for n in OUTPUTS if (args.out / n).exists()]
        if clash and not args.overwrite:
            raise CommandError(f"'{args.out / clash[0]}' exists; pass --overwrite to "
                               "replace it")
    log = load_log_with_hints(args.log, args)
    log = split_gaps(log, args, args.log, "forecasting")
    if args.modes is not None:
        log = log.select(modes=parse_modes(args.modes, "--modes"))
    skipped = _constant_modes(log, train, args.horizon) if args.skip_constant else []
    if skipped:
        if len(skipped) == log.n_modes:
            raise CommandError(f"--skip-constant: every mode is constant over the "
                               f"training frames ({', '.join(skipped)}); nothing to forecast")
        log = log.drop_modes(skipped)
    # on the modes forecast; --outliers drop was refused above (lags need every frame)
    log, _ = apply_outliers(log, args, args.log, time_series=True)

    import matplotlib

    matplotlib.use("Agg")
    from modalinfo.cli._common import progress
    from modalinfo.forecast import evaluate

    n_pred = len(predictors) + sum(1 for b in ("persistence", "mean") if b not in predictors)
    with progress(args, n_pred, unit="predictor", desc="forecast") as advance:
        ev = evaluate(predictors, log, train=train, horizons=range(1, args.horizon + 1),
                      refit_every=args.refit_every, window=args.window, progress=advance)
    if not args.quiet:
        sys.stdout.write(f"{args.log.name}: {log.n_frames} frames x {log.n_modes} modes "
                         f"({', '.join(ev.labels)})\n")
        if skipped:
            sys.stdout.write(f"skipped constant mode(s) (--skip-constant): "
                             f"{', '.join(skipped)}\n")
        sys.stdout.write(ev.summary() + "\n")
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        ev.to_json(args.out / OUTPUTS[0], overwrite=args.overwrite)
        ev.to_csv(args.out / OUTPUTS[1], overwrite=args.overwrite)
        ev.save_plots(args.out, overwrite=args.overwrite)
        if not args.quiet:
            sys.stdout.write(f"wrote {', '.join(OUTPUTS)} to {args.out}\n")
    return 0
