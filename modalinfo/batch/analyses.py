"""Per-log analyses of ``modalinfo batch``: each turns one log into one row of scalars.

Every analysis calls the library exactly as the matching command does:

- ``summary``: :func:`modalinfo.telemetry.summarize` (``modalinfo info``), chunked, so
  a memory-mapped log is read a chunk at a time;
- ``ordering``: :func:`modalinfo.ordering.order_modes` and
  :func:`modalinfo.ordering.ordering_stability` (``modalinfo reorder --stability``);
  for a method that draws no samples (not ``mi_*``) ``seed_spearman`` and
  ``seed_top_overlap`` are NaN and ``seed_note`` says why (the seeds do not act);
- ``fitting_error``: :func:`modalinfo.ordering.compare.compare_orderings` and
  ``modes_to_reach`` (``modalinfo fitting-error``); with a ``kl-theory`` basis (here or
  in ``ordering``) on a log that records no outer scale, column ``kl_assumed`` says
  what the theoretical K-L assumed (the words ``reorder`` prints as a note);
- every row: column ``layout_doubt`` where the log was read as stored though its
  content says modes x frames (``modalinfo.telemetry.checks.layout_doubt``; the
  reader's ``LayoutWarning`` is left to this column, and ``modalinfo batch`` says it in
  one line for all logs);
- ``forecast``: :func:`modalinfo.forecast.evaluate` with the presets of
  :mod:`modalinfo.forecast.presets` (``modalinfo forecast``); it feeds the predictors
  in chunks, so memory does not grow with the log. ``pvalue_h1.<name>`` is the
  one-step Diebold-Mariano p-value, NaN where the loss differential is too persistent
  for an honest test (``beats_baseline_h1.<name>`` is then False). Over every horizon
  1..``horizon``, ``dm_untested`` counts the predictor-horizon pairs with no honest test
  (``evaluate``'s "no honest Diebold-Mariano test" warning) and ``dm_flagged`` those whose
  loss differential has persistent volatility (``ForecastEvaluation.dm_flagged``: they
  beat the baseline only below ``alpha / n_tests / 5``; ``evaluate`` warns for those
  between that and ``alpha``); ``dm_untested_pairs`` and ``dm_flagged_pairs`` name them
  (``"linear h1-3,5; var h2"``; empty: none). ``shifted_modes``
  names the modes whose test frames differ in scale from the training frames
  (``ForecastEvaluation.shifted_modes``; empty: none) and ``scale_shift_max`` is the
  rms ratio of the mode farthest from 1 (NaN: no mode judged).

Before any analysis the log goes through the log-quality pass and the outlier
policy of every command (:func:`modalinfo.telemetry.quality.apply_outlier_policy`,
parameter ``outliers``: warn, clip, drop or raise; ``drop`` is refused for
``forecast``, whose lags need every frame); the row records the policy and what the
pass found (``quality_*`` columns), and ``raise`` turns a flagged log into an error row.

:func:`run_log_task` is the task function the engine sends to the workers; running
it in one process gives the same row, bit for bit.
"""

from __future__ import annotations

import contextlib
import math
import re
from collections.abc import Callable, Iterator
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from modalinfo.common.files import quoted
from modalinfo.common.provenance import sha256_file  # one copy, re-exported here
from modalinfo.common.quiet import quiet
from modalinfo.common.validation import (
    check_choice,
    check_int,
    check_real,
    log_rate_problem,
)

__all__ = ["ANALYSES", "DEFAULTS", "log_columns", "quality_columns", "resolve_params",
           "run_log_task", "sha256_file"]

#: Default parameters of each analysis (a user's values override them key by key).
DEFAULTS: dict[str, dict[str, Any]] = {
    "summary": {"chunk_frames": 65536, "outliers": "warn"},
    "ordering": {
        "basis": "zernike", "method": "mi_greedy", "estimator": "histogram",
        "budget": 200_000, "seed": 0, "pupil_pixels": 64, "resamples": 0,
        "windows": 4, "seeds": [0, 1, 2], "modes": None, "outliers": "warn",
    },
    "fitting_error": {
        "orderings": "zernike:standard,zernike:mi_greedy,kl-data:pca",
        "units": "waves2", "target": None, "fraction": 0.1, "estimator": "histogram",
        "budget": 200_000, "seed": 0, "pupil_pixels": 64, "modes": None, "outliers": "warn",
    },
    "forecast": {
        "predictors": "linear,linear-ls,arma", "horizon": 5, "train": 0.5, "modes": None,
        "outliers": "warn",
    },
}

#: Frames per chunk of the SHA-256 of a file [bytes].
#: Metadata keys copied into every row when a log carries them (row column: key).
_META_COLUMNS = {
    "r0_m": "r0_m", "r0": "r0_m", "seeing": "seeing_arcsec", "seeing_arcsec": "seeing_arcsec",
    "d_over_r0": "d_over_r0", "loop": "loop", "date": "date", "date_obs": "date",
    "DATE-OBS": "date", "site": "site", "telescope": "telescope", "rate_hz": "meta_rate_hz",
}

#: ``start_time`` above this many seconds is read as a Unix time (after 1973).
_EPOCH_MIN = 1e8


def _modes_value(value: Any, name: str) -> None:
    if value is None:
        return
    if isinstance(value, str):
        from modalinfo.bases.indexing import parse_modes

        parse_modes(value, name)  # raises ValueError naming `name`
        return
    ok = isinstance(value, list) and value and (
        all(isinstance(v, int) and not isinstance(v, bool) and v >= 1 for v in value)
        or all(isinstance(v, str) and v for v in value))
    if not ok:
        raise ValueError(f"{name} must be a mode list ('2-28', '4,5,6', labels) or a JSON "
                         f"list of mode numbers >= 1; got {value!r}")


def _predictor_names(value: Any, name: str) -> None:
    from modalinfo.forecast.presets import PRESETS

    names = [n.strip() for n in value.split(",")] if isinstance(value, str) else None
    if not names or not all(names):
        raise ValueError(f"{name} must be a comma list of predictors from "
                         f"{', '.join(PRESETS)}; got {value!r}")
    bad = [n for n in names if n not in PRESETS]
    if bad:
        raise ValueError(f"{name}: {bad[0]!r} is not a predictor; use "
                         f"{', '.join(PRESETS)}")
    twice = [n for n in names if names.count(n) > 1]
    if twice:  # one column set per name: the second was dropped (round 39 PART b, S09)
        raise ValueError(f"{name} names {twice[0]!r} twice; give each predictor once")


def _train_value(value: Any, name: str) -> None:
    if isinstance(value, int) and not isinstance(value, bool):
        check_int(value, name, minimum=2)
    elif isinstance(value, float):
        if value > 1.0 and math.isfinite(value):
            # '1e3' read as 1000.0 was "must be < 1.0", as if counts were not allowed
            # (round 35 PART b, BS10)
            count = (f" (write {int(value)} for {int(value)} frames)"
                     if value.is_integer() else "")
            raise ValueError(f"{name} must be a fraction in (0, 1) or a number of frames "
                             f">= 2 written as an integer; got {value!r}{count}")
        check_real(value, name, minimum=0.0, maximum=1.0, strict_min=True, strict_max=True)
    else:
        raise ValueError(f"{name} must be a fraction in (0, 1) or a number of frames >= 2; "
                         f"got {value!r}{_json_number_hint(value)}")


def _json_number_hint(value: Any) -> str:
    """Say why a text that Python reads as a number (``'+700'``) is not one here.

    ``--set`` values are read as JSON, where ``+700`` or ``.5`` is text, while
    ``forecast --train +700`` reads 700: "got '+700'" alone read as if 700 frames were
    refused (round 36 PART b, B03).
    """
    if not isinstance(value, str):
        return ""
    try:
        number = float(value.replace("_", "x"))  # '1_000' stays text (round 35, BS11)
    except ValueError:
        return ""
    if not math.isfinite(number):
        return ""
    plain = str(int(number)) if number.is_integer() and "." not in value else repr(number)
    return f" (a text: --set values are read as JSON, where a number is written {plain})"


def _seeds_value(value: Any, name: str) -> None:
    if not isinstance(value, list) or not value:
        raise ValueError(f"{name} must be a non-empty JSON list of seeds; got {value!r}")
    for seed in value:
        check_int(seed, name, minimum=0)
    # ordering_stability refuses these after the log's work, in its own words (round 39
    # PART b, S15 / S41)
    if len(value) == 1:
        raise ValueError(f"{name} must hold at least 2 seeds (a seed agrees with itself); "
                         f"got {value!r}")
    if len(set(value)) != len(value):  # a repeated seed: the same subsample, rho = 1
        raise ValueError(f"{name} must be distinct seeds (a repeated seed gives the same "
                         f"subsample and a perfect agreement); got {value!r}")


def _optional_real(**bounds: Any) -> Callable[[Any, str], None]:
    def check(value: Any, name: str) -> None:
        if value is not None:
            check_real(value, name, **bounds)
    return check


def _int_at_least(minimum: int) -> Callable[[Any, str], None]:
    def check(value: Any, name: str) -> None:
        check_int(value, name, minimum=minimum)
    return check


def _choice(get: Callable[[], Any]) -> Callable[[Any, str], None]:
    def check(value: Any, name: str) -> None:
        check_choice(value, name, tuple(get()))
    return check


def _orderings(value: Any, name: str) -> None:
    from modalinfo.ordering.compare import parse_specs

    if not isinstance(value, str | list):
        raise ValueError(f"{name} must be a comma list of basis:method; got {value!r}")
    try:
        parse_specs(value)
    except ValueError as exc:
        raise ValueError(f"{name}: {exc}") from None


def _bases() -> tuple:
    from modalinfo.ordering.compare import BASES

    return BASES


def _methods() -> tuple:
    from modalinfo.ordering import METHODS

    return METHODS


def _estimators() -> tuple:
    from modalinfo.information.api import METHODS

    return METHODS


#: analysis -> parameter -> check(value, name) raising ValueError/TypeError; every
#: parameter of DEFAULTS has one, so a bad ``--set`` is refused before any work.
_OUTLIERS = _choice(lambda: ("warn", "clip", "drop", "raise"))
#: forecast lags need every frame: no drop (modalinfo.telemetry.quality, time_series)
_OUTLIERS_TIME = _choice(lambda: ("warn", "clip", "raise"))

_CHECKS: dict[str, dict[str, Callable[[Any, str], None]]] = {
    "summary": {"chunk_frames": _int_at_least(1), "outliers": _OUTLIERS},
    "ordering": {
        "basis": _choice(_bases), "method": _choice(_methods),
        "estimator": _choice(_estimators), "budget": _int_at_least(1),
        "seed": _int_at_least(0), "pupil_pixels": _int_at_least(4),
        "resamples": _int_at_least(0), "windows": _int_at_least(0), "seeds": _seeds_value,
        "modes": _modes_value, "outliers": _OUTLIERS,
    },
    "fitting_error": {
        "orderings": _orderings, "units": _choice(lambda: ("waves2", "rad2")),
        "target": _optional_real(minimum=0.0, strict_min=True),
        "fraction": _optional_real(minimum=0.0, maximum=1.0, strict_min=True),
        "estimator": _choice(_estimators), "budget": _int_at_least(1),
        "seed": _int_at_least(0), "pupil_pixels": _int_at_least(4), "modes": _modes_value,
        "outliers": _OUTLIERS,
    },
    "forecast": {
        "predictors": _predictor_names, "horizon": _int_at_least(1), "train": _train_value,
        "modes": _modes_value, "outliers": _OUTLIERS_TIME,
    },
}


def resolve_params(analysis: str, params: dict | None = None) -> dict:
    """Return the analysis's defaults updated by ``params``, each value checked.

    Raises
    ------
    ValueError
        An unknown analysis or parameter, or a value outside its rule (type, range,
        choice), naming ``analysis.name``, the rule and the value.
    """
    if analysis not in DEFAULTS:
        raise ValueError(f"`analyses` must be among {', '.join(DEFAULTS)}; got {analysis!r}")
    params = dict(params or {})
    unknown = sorted(set(params) - set(DEFAULTS[analysis]))
    if unknown:
        raise ValueError(f"unknown parameter {analysis}.{unknown[0]}; {analysis} takes "
                         f"{', '.join(DEFAULTS[analysis])}")
    for name, value in params.items():
        try:
            _CHECKS[analysis][name](value, f"parameter {analysis}.{name}")
        except (TypeError, ValueError) as exc:
            # one message form whatever the checker: backticks of check_* dropped
            raise ValueError(str(exc).replace("`", "").rstrip(".")) from None
    resolved = {**DEFAULTS[analysis], **params}
    _refuse_unused(analysis, params, resolved)
    return resolved


#: batch parameter -> the argument of order_modes / compare_orderings /
#: ordering_stability it sets
_ORDERING_ARGUMENTS = {"estimator": "estimator", "budget": "sample_budget", "seed": "seed",
                       "seeds": "seeds", "resamples": "n_resamples"}


def _refuse_unused(analysis: str, given: dict, p: dict) -> None:
    """Refuse, before any task, what ``reorder`` / ``fitting-error`` refuse, in batch terms.

    A parameter no method of the analysis uses (``--set ordering.method=variance --set
    ordering.resamples=100``) ran and the params recorded it; ``ordering.method=pca`` on
    a model basis made every log an error row after its work, with the API's advice
    (round 37 PART b, B04 / B05 / B08 / B12). One guard with the commands:
    :func:`modalinfo.ordering.orderings.refuse_unused_arguments`. Also (fix38-e): a
    ``fitting_error.orderings`` entry ``zernike:pca`` / ``kl-theory:pca`` (an error row
    per log after its work), ``ordering.seeds`` with a method without MI (its row said
    "not assessed") or with ``ordering.windows`` < 2 (no stability columns).
    """
    from modalinfo.ordering.compare import parse_specs
    from modalinfo.ordering.orderings import refuse_unused_arguments

    if analysis not in ("ordering", "fitting_error"):
        return
    names = {library: f"{analysis}.{batch}" for batch, library in _ORDERING_ARGUMENTS.items()}
    given_names = [library for batch, library in _ORDERING_ARGUMENTS.items()
                   if batch in given and (batch != "resamples" or given[batch])]
    if analysis == "ordering":
        names.update(method="ordering.method", basis="ordering.basis")
        refuse_unused_arguments([p["method"]], given_names, basis=p["basis"], words=names,
                                chosen=f"ordering.method {p['method']}")
        _refuse_unused_stability(given, p)
    else:
        specs = parse_specs(p["orderings"])
        names.update(orderings="fitting_error.orderings")
        refuse_unused_arguments([m for _, m in specs], given_names,
                                basis=[b for b, _ in specs], words=names,
                                chosen=f"fitting_error.orderings {p['orderings']}",
                                noun="orderings")


def _refuse_unused_stability(given: dict, p: dict) -> None:
    """Refuse ``ordering.windows`` / ``ordering.seeds`` where no stability uses them.

    The row's stability is measured only for a method other than pca with ``windows``
    >= 2, and across seeds only for an MI method (:func:`_ordering`); a value given
    otherwise ran, used by nothing, and the params recorded it (round 39 PART b, S03,
    S36, S37).
    """
    if p["method"] == "pca" and "windows" in given:
        raise ValueError("ordering.windows sets the window stability, which ordering.method "
                         "pca does not assess (one order of the log's own K-L): drop it")
    if "seeds" not in given:
        return
    # seeds with a method without MI (pca among them) were refused before, by
    # refuse_unused_arguments (MI_ONLY_ARGUMENTS holds `seeds`)
    if int(p["windows"]) < 2:
        raise ValueError(f"ordering.seeds sets the seed stability; ordering.windows "
                         f"{p['windows']} assesses no stability (it takes >= 2): drop it")


def _scalar(value: Any) -> Any:
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, bool | int | float | str) or value is None:
        return value
    return str(value)


def log_columns(log: Any) -> dict:
    """Columns describing a log: shape, rate, duration, units, date and site metadata."""
    row: dict[str, Any] = {
        "n_frames": int(log.n_frames), "n_modes": int(log.n_modes),
        "rate": None if log.rate is None else float(log.rate),
        "duration": None if log.duration is None else float(log.duration),
        "units": str(log.units), "start_time": float(log.start_time),
    }
    s = log.sampling()
    if s is not None and s.n_frames > 1:  # timestamps: the median rate and what breaks it
        row["median_rate"] = float(s.median_rate)  # the mean rate is biased by gaps
        # a rate change or gaps (adversarial round 9 PART b, row B01: a log of two
        # rates had one ok row saying 1333 Hz)
        row["sampling"] = ("uniform" if s.uniform and not s.rate_change
                           else s.describe_irregular())
    meta = log.metadata or {}
    for key, column in _META_COLUMNS.items():
        if key in meta and column not in row:
            row[column] = _scalar(meta[key])
    from modalinfo.telemetry.log import assumed_fields

    _, assumed = assumed_fields(meta)
    if assumed:  # what the file does not record, as the commands' note says it (round 41
        row["assumed"] = assumed  # PART b, B02: a raw .npy's row said 'rad' as read)
    layout = meta.get("layout")
    if isinstance(layout, dict) and isinstance(layout.get("doubt"), str):
        # a layout read as stored whose content says modes x frames (left31-orient)
        row["layout_doubt"] = layout["doubt"]
    if "date" not in row and log.start_time >= _EPOCH_MIN:
        row["date"] = datetime.fromtimestamp(log.start_time, UTC).isoformat()
    return row


# ----------------------------------------------------------------------- analyses
def _select(log: Any, modes: Any) -> Any:
    """Restrict the log to ``modes`` (``"2-101"``, ``"4,5,6"`` or a list) if given."""
    if modes is None:
        return log
    if isinstance(modes, str):
        from modalinfo.bases.indexing import parse_modes

        modes = parse_modes(modes)
    return log.select(modes=list(modes))


def _root_sum_square(values: np.ndarray) -> float:
    """``sqrt(nansum(values**2))`` without overflow or underflow of the squares.

    Scaled by the largest magnitude first: a log in units where the RMS is 1e300 (or
    1e-300) has a finite, non-zero total; squaring first gave inf (or 0) before round 26
    PART b.
    """
    finite = np.abs(values[~np.isnan(values)])
    if finite.size == 0:
        return 0.0
    peak = float(finite.max())
    if peak == 0.0 or not math.isfinite(peak):
        return peak
    return peak * float(np.sqrt(np.sum((finite / peak) ** 2)))


def _summary(log: Any, p: dict) -> dict:
    from modalinfo.telemetry import summarize

    s = summarize(log, chunk_frames=int(p["chunk_frames"]))
    top = int(np.nanargmax(s.rms)) if np.isfinite(s.rms).any() else 0
    return {
        "n_nonfinite": int(s.n_nonfinite.sum()),
        "rms_total": _root_sum_square(np.asarray(s.rms, dtype=float)),
        "std_total": _root_sum_square(np.asarray(s.std, dtype=float)),
        "lag1_median": float(np.nanmedian(s.lag1)) if np.isfinite(s.lag1).any() else math.nan,
        "lag1_min": float(np.nanmin(s.lag1)) if np.isfinite(s.lag1).any() else math.nan,
        "largest_mode": str(s.labels[top]),
        "largest_rms": float(s.rms[top]),
    }


@contextlib.contextmanager
def _no_cost_note() -> Iterator[None]:
    """Silence the library's notes on a long ordering and an assumed K-L in a batch task.

    ``OrderingCostWarning`` names the library's arguments (``sample_budget``, ...),
    not the batch settings (``ordering.budget``), and a worker's warning reaches no
    one; the batch refuses a plan past its hour before any work (``_ordering``).
    ``KLGeometryWarning``: the row's ``kl_assumed`` column says it (``_kl_assumed``).
    ``PupilSamplingWarning``: the row's ``parseval_difference.<ordering>`` columns hold
    it (``_fitting_error``; fix33-a).
    """
    from modalinfo.ordering.compare import KLGeometryWarning
    from modalinfo.ordering.cost import OrderingCostWarning
    from modalinfo.ordering.fitting_error import PupilSamplingWarning

    with quiet(OrderingCostWarning, KLGeometryWarning, PupilSamplingWarning):
        yield


def _kl_assumed(log: Any, theory: bool) -> dict:
    """Column ``kl_assumed``: what a theoretical K-L assumes that the log does not record.

    ``modalinfo reorder`` / ``fitting-error`` say it on stderr; a worker's words reach
    no one, so the row carries them and ``modalinfo batch`` says them once (adversarial
    round 24 PART b, F31-F35; left24-status). Empty without a ``kl-theory`` basis or
    when the log records its outer scale (and, for a finite one, its diameter).
    """
    from modalinfo.ordering.compare import kl_geometry_assumption

    what = kl_geometry_assumption(log) if theory else None
    return {"kl_assumed": what} if what else {}


def _require_contiguous_for_ordering(log: Any, p: dict) -> None:
    """Refuse, before the ordering's work, a gapped log the bootstrap or windows need whole.

    The pooled ordering runs on a log with gaps; the block bootstrap (``resamples`` > 0
    with an MI method) and the stability windows (``windows`` >= 2) do not, and their
    refusal named ``--split-gaps``, which batch lacks, after the ordering's work (round 51
    PART b, C105): the row now names the parameter that avoids them, and the command.
    """
    from modalinfo.telemetry.sampling import require_contiguous

    if int(p["windows"]) >= 2 and p["method"] != "pca":
        require_contiguous(log, f"ordering.windows {p['windows']} (the stability's time "
                           "windows)",
                           remedy="batch has no --split-gaps: --set ordering.windows=0 "
                                  "orders the whole log without them, or run `modalinfo "
                                  "reorder LOG --split-gaps --stability N` on this log")
    if int(p["resamples"]) > 0 and str(p["method"]).startswith("mi_"):
        require_contiguous(log, f"ordering.resamples {p['resamples']} (the block "
                           "bootstrap of the MI gains)",
                           remedy="batch has no --split-gaps: --set ordering.resamples=0 "
                                  "orders the whole log without it, or run `modalinfo "
                                  "reorder LOG --split-gaps` on this log")


def _ordering(log: Any, p: dict) -> dict:
    from modalinfo.ordering import order_modes, ordering_stability
    from modalinfo.ordering.compare import basis_for_log

    log = _select(log, p["modes"])
    if str(p["method"]).startswith("mi_"):  # refuse what cannot finish, before the work
        from modalinfo.bases import Pupil
        from modalinfo.ordering.cost import MAX_ORDERING_SECONDS, least_ordering_seconds

        n = min(int(p["budget"]), log.n_frames * Pupil(int(p["pupil_pixels"])).n_valid)
        seconds, calls = least_ordering_seconds(p["estimator"], n, log.n_modes,
                                                int(p["resamples"]), 1, str(p["method"]))
        if seconds > MAX_ORDERING_SECONDS:
            raise ValueError(f"ordering.estimator {p['estimator']} with ordering.budget "
                             f"{p['budget']} ({n} samples per MI estimate, at least {calls} "
                             f"estimates) would take at least {seconds / 3600:.1f} h of CPU, "
                             f"more than {MAX_ORDERING_SECONDS / 3600:g} h; use a smaller "
                             "ordering.budget or estimator")
    _require_contiguous_for_ordering(log, p)
    with _no_cost_note(), _pupil_words("ordering"):
        basis = basis_for_log(p["basis"], log, n_pixels=int(p["pupil_pixels"]))
    assumed = _kl_assumed(log, p["basis"] == "kl-theory")
    with _no_cost_note():
        result = order_modes(log, basis, p["method"], estimator=p["estimator"],
                             sample_budget=int(p["budget"]), seed=int(p["seed"]),
                             n_resamples=int(p["resamples"]))
    row: dict[str, Any] = {"modes_analysed": int(log.n_modes), "order": " ".join(result.labels),
                           "first_mode": result.labels[0], **assumed}
    if result.mi is not None:
        finite = np.asarray(result.mi, dtype=float)
        finite = finite[np.isfinite(finite)]
        # the last step completes Phi_ref and is not estimated (NaN): report the last
        # estimated cumulative MI and the first mode's
        row["mi_last_estimated"] = float(finite[-1]) if finite.size else math.nan
        row["mi_first"] = float(result.mi[0])
    if result.n_informative is not None:
        row["n_informative"] = int(result.n_informative)
    windows = int(p["windows"])
    if windows >= 2 and p["method"] != "pca":
        with _no_cost_note():
            stab = ordering_stability(log, basis, p["method"],
                                      window=log.n_frames // windows,
                                      seeds=tuple(p["seeds"]), estimator=p["estimator"],
                                      sample_budget=int(p["budget"]), seed=int(p["seed"]))

        def med(x: np.ndarray) -> float:
            return float(np.median(x)) if x.size else math.nan

        row.update({
            "window_spearman": med(stab.window_spearman),
            "window_kendall": med(stab.window_kendall),
            "window_top_overlap": med(stab.window_top_overlap),
            "seed_spearman": med(stab.seed_spearman),
            "seed_top_overlap": med(stab.seed_top_overlap),
        })
        if stab.seeds_not_assessed is not None:
            # the seeds act on the MI's samples only: 1.0 read as a measured stability
            # (round 37 PART b, B06); empty cells and reorder --stability's words
            row.update(seed_spearman=math.nan, seed_top_overlap=math.nan,
                       seed_note=stab.seeds_not_assessed)
    return row


@contextlib.contextmanager
def _pupil_words(analysis: str) -> Iterator[None]:
    """Say the basis's `n_pixels` refusal as the batch parameter that sets it.

    A log of modes up to Z2001 with the default 64 pixels was an error row "`n_pixels`
    must be >= 124 ...", a name batch has not (round 39 PART b, N13).
    """
    try:
        yield
    except ValueError as exc:
        if "`n_pixels`" not in str(exc):
            raise
        raise ValueError(str(exc).replace("`n_pixels`", f"{analysis}.pupil_pixels")) from None


def _fitting_error(log: Any, p: dict) -> dict:
    from modalinfo.ordering.compare import compare_orderings, parse_specs

    log = _select(log, p["modes"])
    specs = parse_specs(p["orderings"])
    assumed = _kl_assumed(log, any(basis == "kl-theory" for basis, _ in specs))
    with _no_cost_note(), _pupil_words("fitting_error"):
        comp = compare_orderings(log, specs, units=p["units"],
                                 estimator=p["estimator"], sample_budget=int(p["budget"]),
                                 seed=int(p["seed"]), n_pixels=int(p["pupil_pixels"]))
    # the curves' unit beside them: the row's `units` is the log's, and n01's 0.0373
    # (waves^2) read as rad^2 beside 'rad' (round 41 PART b, B03)
    row: dict[str, Any] = {"modes_analysed": int(log.n_modes),
                           "total_variance": float(comp.curve(comp.entries[0])[0]),
                           "error_units": str(p["units"]), **assumed}
    for e in comp.entries:
        # the sampled pupil's curve against the continuous modes' sum of squares (signed
        # relative, its largest over n; 0 for an orthonormal basis): fitting_error's
        # PupilSamplingWarning, which reaches no one from a worker
        row[f"parseval_difference.{e.name}"] = float(e.error.parseval_difference)
        if p["target"] is not None:
            row[f"modes_to_target.{e.name}"] = e.error.modes_to_reach(float(p["target"]))
        if p["fraction"] is not None:
            row[f"modes_to_fraction.{e.name}"] = e.error.modes_to_reach_fraction(
                float(p["fraction"]))
    return row


def _forecast(log: Any, p: dict) -> dict:
    from modalinfo._stats import LevelStepWarning
    from modalinfo.forecast import evaluate
    from modalinfo.forecast.presets import make_predictor
    from modalinfo.telemetry.quality import CalibrationEventWarning
    from modalinfo.telemetry.sampling import require_contiguous

    log = _select(log, p["modes"])
    names = [n.strip() for n in str(p["predictors"]).split(",") if n.strip()]
    predictors = {n: make_predictor(n) for n in names}
    horizon = int(p["horizon"])
    train = p["train"]
    # the row named --split-gaps, which batch lacks (round 51 PART b, C101)
    require_contiguous(log, "forecast evaluation",
                       remedy="batch has no --split-gaps: run `modalinfo forecast LOG "
                              "--split-gaps` on this log")
    if horizon >= log.n_frames:  # before `evaluate` lists the horizons 1..H
        raise ValueError(f"`horizon` must be below the log's {log.n_frames} frames; "
                         f"got {horizon}")
    # no forecast series are kept (the batch plots none): memory is the chunk buffers,
    # the (P, H, origins) losses of the skill test and, for a float32 log, its float64 copy
    # a pair too persistent for an honest Diebold-Mariano test is in the row (its
    # ``pvalue_h1`` NaN, ``beats_baseline_h1`` False), so is a pair of persistent
    # volatility (``beats_baseline_h1`` needs its stricter p-value); a worker's warning
    # reaches no one; a level step in the training series is in the row too (the quality pass's
    # ``quality_level_steps`` and ``quality_stationary`` columns); test frames unlike the
    # training ones are in the row (``shifted_modes``, ``scale_shift_max``). This
    # thread's only (fixes 41-c: filters swapped the process's, other tasks' included)
    with quiet(LevelStepWarning), quiet(CalibrationEventWarning), \
            quiet(message="evaluate: no honest Diebold-Mariano test"), \
            quiet(message="evaluate: the Diebold-Mariano p-value"), \
            quiet(message="evaluate: the test frames differ in scale"):
        ev = evaluate(predictors, log, train=train, horizons=range(1, horizon + 1),
                      keep_series=1, chunk_frames=2048)
    row: dict[str, Any] = {"modes_analysed": int(log.n_modes), "n_train": int(ev.n_train),
                           "n_origins": int(ev.origins.size)}
    for name in names:
        i = ev.index(name)
        row[f"gain_h1.{name}"] = float(ev.gain_wavefront[i, 0])
        row[f"gain_h{horizon}.{name}"] = float(ev.gain_wavefront[i, -1])
        row[f"beats_baseline_h1.{name}"] = bool(ev.beats_baseline[i, 0])
        row[f"pvalue_h1.{name}"] = float(ev.pvalue[i, 0])  # NaN: no honest test
    # the pairs whose "beats the baseline" the Diebold-Mariano test withheld (no honest
    # test: p NaN) or made stricter (persistent volatility: p < alpha / n_tests / 5), over
    # every horizon: evaluate's two warnings, which reach no one from a worker (fix48-b)
    named = np.isin(ev.names, names)[:, None]  # not the baselines (their p-value NaN)
    untested = np.isnan(ev.pvalue) & named
    for key, mask in (("dm_untested", untested), ("dm_flagged", ev.dm_flagged & named)):
        row[key] = int(mask.sum())
        row[f"{key}_pairs"] = _pairs_text(ev.names, ev.horizons, mask)
    # train-vs-test scale (Leftovers 28-shift): the modes named, and the rms ratio (test /
    # training, frozen-model innovations) of the mode farthest from 1 (NaN: none judged)
    row["shifted_modes"] = ",".join(ev.shifted_modes)
    shift = np.sqrt(np.asarray(ev.scale_shift, dtype=float))
    judged = shift[np.isfinite(shift)]
    row["scale_shift_max"] = (float(judged[np.argmax(np.abs(np.log(judged)))])
                              if judged.size else math.nan)
    best = max(names, key=lambda n: ev.gain_wavefront[ev.index(n), 0])
    row["best_h1"] = best
    return row


def _pairs_text(names: tuple[str, ...], horizons: np.ndarray, mask: np.ndarray) -> str:
    """Predictor-horizon pairs of ``mask`` (P, H), compactly: ``"ar h1-3,5; var h2"``."""
    parts = []
    for i, name in enumerate(names):
        hs = [int(h) for h in np.asarray(horizons)[np.asarray(mask[i], dtype=bool)]]
        spans: list[list[int]] = []
        for h in hs:
            if spans and h == spans[-1][1] + 1:
                spans[-1][1] = h
            else:
                spans.append([h, h])
        if spans:
            parts.append(f"{name} h" + ",".join(
                str(a) if a == b else f"{a}-{b}" for a, b in spans))
    return "; ".join(parts)


#: analysis name -> function(log, params) -> dict of scalars.
ANALYSES: dict[str, Callable[[Any, dict], dict]] = {
    "summary": _summary,
    "ordering": _ordering,
    "fitting_error": _fitting_error,
    "forecast": _forecast,
}


def run_log_task(payload: dict) -> dict:
    """Load one log (memory-mapped where the format allows) and run one analysis.

    Parameters
    ----------
    payload : dict
        ``path``, ``fmt`` (or None), ``hints`` (dict), ``analysis``, ``params``
        (complete, see :func:`resolve_params`) and optionally ``window``
        ``[start, stop)`` in frames.

    Returns
    -------
    dict
        The log's columns (:func:`log_columns`) and the analysis's scalars.
    """
    # no matplotlib.use("Agg") here: on a thread-based client the worker is the user's
    # own process, and it switched a notebook's backend for the session; nothing a task
    # runs draws (plot_archive draws on a Figure of its own, batch/report.py)
    from modalinfo.common.files import check_readable
    from modalinfo.io import LayoutWarning, load
    from modalinfo.telemetry.quality import apply_outlier_policy

    path = payload["path"]
    check_readable(Path(path))  # missing, a folder, a FIFO or a device: named as such
    # the row's layout_doubt column says it, batch once per log; this thread's only
    with quiet(LayoutWarning), _hints_named():
        log = load(path, fmt=payload.get("fmt"), mmap=True, **payload.get("hints", {}))
    _verify_mapped(path, log, payload.get("fmt"))
    if payload.get("window") is not None:
        start, stop = payload["window"]
        log = log[start:stop]  # a view of the mapped file: only the window is read
    analysis, params = payload["analysis"], payload["params"]
    if analysis != "summary":  # a summary reports the rate; the analyses refuse, as the CLI
        problem = log_rate_problem(log.rate, log.timestamps is not None, quoted(Path(path).name))
        if problem:
            raise ValueError(problem)
    row = log_columns(log)
    _check_quality_memory(path, log, params.get("outliers", "warn"))
    log, quality = apply_outlier_policy(log, params.get("outliers", "warn"),
                                        time_series=analysis == "forecast")
    row.update(quality_columns(quality, log, params.get("outliers", "warn")))
    row.update(ANALYSES[analysis](log, params))
    return row


#: The reader's hint arguments -> how a batch user gives them: an option of the command
#: line, or a column of a manifest (``modalinfo.batch.manifest``).
_HINT_WORDS = {
    "rate": "--rate or column 'rate'", "units": "--in-units or column 'in_units'",
    "wavelength": "--wavelength or column 'wavelength'",
    "modes": "--in-modes or column 'in_modes'",
    "convention": "--in-convention or column 'in_convention'",
    "nonfinite": "--nonfinite or column 'nonfinite'",
    "transpose": "--transpose or column 'transpose'", "loop": "--loop or column 'loop'",
    "start_time": "column 'start_time'",
}


@contextlib.contextmanager
def _hints_named() -> Iterator[None]:
    """Name a reader's hint in an error row as the batch user gave it.

    The reader's words (``hint `rate`=2000.0 contradicts ...``, ``` `loop` selects
    ...```) name its Python argument; a batch user gave ``--rate`` or a manifest's column
    'rate', and single-log commands say ``--rate`` (adversarial round 53 PART b, M09-M11,
    M34, M36, M38).
    """
    try:
        yield
    except ValueError as exc:
        text = str(exc)
        named = re.sub(r"(hint )?`(\w+)`(=)?",
                       lambda m: (f"{m.group(1) or ''}{m.group(2)} ({_HINT_WORDS[m.group(2)]})"
                                  f"{' = ' if m.group(3) else ''}")
                       if m.group(2) in _HINT_WORDS else m.group(0), text, count=1)
        if named == text:
            raise
        try:
            new = type(exc)(named)
        except Exception:  # noqa: BLE001 - an exception type with another signature
            raise exc from None
        raise new from None


def _check_quality_memory(path: str, log: Any, policy: str) -> None:
    """Refuse (an error row) a log whose quality pass cannot fit, before the pass.

    The pass's estimate of every command (``quality_pass_need``: ``quality_memory``
    and a clipped copy) against the memory this worker may still allocate (issue 27,
    left31-estimate). ``log``, loaded or mapped before this check, is already missing
    from that figure: counting its bytes again named 36.53 MiB where ``modalinfo
    convert`` named 35.62 MiB on the same 20,000 x 6 log, and refused a log whose pass
    fits (stop 57, fix51-c; the single command's rule of round 50 PART b, M12).
    """
    from modalinfo.common.memory import usable_memory_bytes
    from modalinfo.common.sizes import format_size
    from modalinfo.telemetry.quality import quality_pass_need

    need = quality_pass_need(log, policy)
    avail = usable_memory_bytes()
    if need > avail:
        raise MemoryError(f"{quoted(Path(path).name)} ({log.n_frames} frames x {log.n_modes} "
                          f"modes): the log-quality pass (outliers {policy}) needs about "
                          f"{format_size(need)} of memory and {format_size(avail)} is "
                          "available; analyse fewer frames (window) or modes")


def _verify_mapped(path: str, log: Any, fmt: str | None) -> None:
    """Verify the checksum that memory mapping skipped (one pass); raise if it differs.

    ``info`` does the same in its pass; without it a damaged NPZ/HDF5 written by
    modalinfo was analysed as if whole (an error row now names it).
    """
    from modalinfo.io.integrity import integrity_check

    check = integrity_check(path, log, fmt=fmt, mmap=True)
    if check.status == "pending":
        for block in log.iter_chunks(65536):
            check.update(block)
        check.finish()


def quality_columns(report: Any, log: Any, policy: str) -> dict:
    """Row columns of the log-quality pass and of what the outlier ``policy`` did to ``log``.

    ``outliers`` (the policy), every field of the report ``modalinfo info`` prints
    (:meth:`modalinfo.telemetry.quality.QualityReport.columns`: ``quality_rule``,
    ``quality_k``, ``quality_flagged_frames``, ..., ``quality_scale_ratio``,
    ``quality_stationary``, ``quality_note``) and ``quality_action``.
    """
    from modalinfo.telemetry.quality import policy_record

    action = policy_record(report, log, policy)["action"]
    return {"outliers": policy, **report.columns(), "quality_action": action}
