"""Confidence intervals and permutation tests for MI estimates of (autocorrelated) series.

Wavefront-sensor telemetry is strongly autocorrelated (an AR(1) coefficient of 0.95
or more per frame is usual), so the n frames of a log carry far fewer than n
independent samples. Resampling methods that treat the frames as independent then
understate the error:

- the iid bootstrap gives confidence intervals that are far too narrow (it undercovers);
  the moving-block bootstrap (Kuensch 1989) resamples aligned (x, y) blocks and keeps
  the dependence within each block;
- a plain shuffle test of independence is anti-conservative (rejects far more often
  than its nominal level under the null), because shuffling y destroys its
  autocorrelation as well as the cross-dependence; the circular-shift test
  (``permutation="circular"``) rotates y instead, by distinct multiples of a spacing
  with the original at 0 (:mod:`modalinfo.information.resampling`, which also holds
  the block bootstrap and the block length), which keeps the autocorrelation of each
  series and breaks only the alignment.

Bias. Plug-in MI estimators are biased: upward at small effective sample size
(Miller-Madow corrects the histogram for n, but an autocorrelated series has far
fewer independent samples), and downward for the histogram at high correlation
(discretisation: at n = 2000, rho = 0.99 the estimate is 0.15 nats, 8 %, low, and a
95 % interval of 2 x 0.045 nats excludes the MI; beyond 10 % of the pair's
Gaussian-copula MI, a lower bound of the MI, a warning and the ``note`` say so,
``histogram.histogram_copula_rule``). Bootstrap replicates are biased too, but not
by the same amount: resamples contain duplicated samples and block junctions, and the
histogram bin rule sees a different sample. Measured on AR(1) pairs with phi = 0.95 (histogram, 100
trials, 199 resamples, Politis-White blocks), the bootstrap bias (mean of replicates
minus estimate) was +0.034, +0.016, +0.025, +0.024 nats where the estimator's true
bias was +0.027, +0.003, +0.020, -0.027 (n = 2000 rho = 0.6; 8000, 0.6; 4000, 0.3;
4000, 0.9): the sign can even be wrong. Correcting with it therefore hurts: the
coverages of nominal 95% intervals were

    interval      n=2000 r=.6  n=8000 r=.6  n=4000 r=.3  n=4000 r=.9
    percentile        0.75         0.88         0.29         0.95
    basic             0.88         0.82         0.77         0.82
    normal            0.90         0.94         0.87         0.93

so the default interval is ``"normal"``: the estimate plus or minus z_(1 - a/2)
times the bootstrap standard deviation (Efron & Tibshirani 1993, ch. 13), which
takes only the *spread* from the bootstrap and is centred on the (Miller-Madow
corrected) estimate. ``"basic"`` (reverse percentile, [2 I - q_hi, 2 I - q_lo],
Davison & Hinkley 1997, ch. 5) and ``"percentile"`` are available, and for the
iid bootstrap ``"bca"`` via ``scipy.stats.bootstrap``. For the Gaussian estimator with
the iid bootstrap at n <= 2000 the default (``interval="auto"``) is ``"fisher"``, the
normal interval on Fisher's z of the correlation with the larger of the bootstrap's and
the jackknife's spread (0.9445 at n = 200, rho = 0.6, where "normal" covered 0.930;
fix50-a); with the block bootstrap it is ``"fisher"`` with the larger of the block
bootstrap's spread and Bartlett's ``1 / sqrt(n_eff - 3)`` (fix51-b), and the histogram's
and kde's "normal" spread is at least that carried to the MI. The remaining undercoverage
comes from the estimator's own bias at small effective n, which no interval can
see; use longer logs or check with :func:`mutual_information_permutation_test`. Not
all of it: Gaussian-method MI of iid Gaussian pairs (rho = 0.6, n = 500, default block
bootstrap, 199 resamples) covered 0.925 over 800 seeds (standard error 0.009) at a
nominal 0.95, with a bias of 0.0001 nats: the bootstrap spread, 0.0265 nats on average,
is 5 % below the estimates' 0.0278 (the interval with that mean spread covered 0.936),
and it varies from log to log (round 19 PART a). Read a 95 % interval as about 92 %
there. One
part of the histogram's bias is known: its k x k grid's loss, which shrinks more slowly
than the bootstrap spread (iid Gaussian pairs, rho = 0.6: 0.0114 and 0.0075 nats low
at n = 5000 and 20000, spreads 0.0075 and 0.0040, coverage 0.76 and 0.55); the upper
bound is raised by it (``interval`` below; round 15 PART a).

Default estimator of the intervals: ``"histogram"`` (not the ``"ksg"`` of the point
estimate and the permutation test, which resamples cannot take; fast, and unaffected
by the duplicated samples
that bootstrap resamples contain, which bias the leave-one-out KDE and KSG upward).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import stats

from modalinfo.common.quiet import catching_warnings, quiet, warn
from modalinfo.common.records import array_fields_eq, check_record_fields
from modalinfo.common.validation import (
    as_float_array,
    check_aligned,
    check_choice,
    check_memory,
    check_real,
    check_rng,
)
from modalinfo.information.api import (
    METHODS,
    MIN_SAMPLES,
    RESAMPLING_METHOD,
    UNITS,
    MutualInformation,
    _is_constant,
    _warn_default_resolution,
    ceiling_problem,
)
from modalinfo.information.convergence import (
    KDE_BIAS_RATE,
    bartlett_cross_factor,
    bartlett_sum_pairs,
    effective_pairs,
    effective_sample_rule,
    piece_bias,
    sorted_samples,
)
from modalinfo.information.copula import normal_score_correlation
from modalinfo.information.discrete import discrete_pair_mi, discrete_x_levels, pile_why
from modalinfo.information.gaussian import fisher_z_from_mi, mi_from_fisher_z
from modalinfo.information.methods import BiasRuleWarning, check_bootstrappable
from modalinfo.information.resampling import (
    MI_ROTATION_MIN_EFFECTIVE_PAIRS,
    BlockBootstrapWarning,
    RotationNullWarning,
    ShuffleNullWarning,
    block_bootstrap_indices,
    block_bootstrap_rule,
    check_index_memory,
    check_resamples,
    check_tail_replicates,
    iid_bootstrap_rule,
    level_null_rule,
    matched_window_for,
    percentile_bounds,
    resolve_block_length,
    rotation_null_rule,
    shuffle_null_rule,
    stationarity_null_rule,
    surrogate_pvalue,
    surrogate_shifts,
)

__all__ = [
    "MIConfidenceResult",
    "MIPermutationResult",
    "mutual_information_ci",
    "mutual_information_permutation_test",
]


@array_fields_eq
@dataclass(frozen=True)
class MIConfidenceResult:
    """Bootstrap confidence interval of a mutual-information estimate.

    Attributes
    ----------
    estimate : float
        MI of the full sample, in ``units``.
    low, high : float
        Interval bounds, in ``units``; ``low`` is clipped at 0 only if ``clip`` was asked.
    confidence_level : float
        Nominal coverage, e.g. 0.95.
    block_length : int
        Block length of the moving-block bootstrap [samples]; 1 for the iid bootstrap.
    n_resamples : int
        Number of bootstrap resamples.
    bootstrap_std : float
        Standard deviation of the bootstrap distribution (standard error), in ``units``.
    bootstrap_mean : float
        Mean of the bootstrap distribution; ``bootstrap_mean - estimate`` estimates the
        bias of the estimator.
    bootstrap_distribution : numpy.ndarray, shape (n_resamples,)
        MI of every resample.
    bootstrap : str
        ``"block"`` or ``"iid"``.
    interval : str
        ``"fisher"``, ``"normal"``, ``"basic"``, ``"percentile"`` or ``"bca"``: the
        interval given (``"auto"`` resolved).
    method, units : str
        Estimator and units.
    note : str
        Why the interval differs from the one asked for, or ``""``. BCa falls back to
        the percentile interval (``interval`` then reads ``"percentile"``) when every
        bootstrap replicate lies on one side of the estimate: its bias correction
        ``z0 = Phi^-1(fraction of replicates below the estimate)`` is then infinite.
    """

    estimate: float
    low: float
    high: float
    confidence_level: float
    block_length: int
    n_resamples: int
    bootstrap_std: float
    bootstrap_mean: float
    bootstrap_distribution: np.ndarray = field(repr=False)
    bootstrap: str
    interval: str
    method: str
    units: str
    note: str = ""

    def __post_init__(self) -> None:
        check_record_fields(self, reals=("estimate", "low", "high",
                                         "bootstrap_std", "bootstrap_mean"))


@array_fields_eq
@dataclass(frozen=True)
class MIPermutationResult:
    """Permutation test of independence based on an MI estimate.

    Attributes
    ----------
    statistic : float
        MI of the observed pairing, in ``units``.
    pvalue : float
        ``(1 + #{null >= statistic}) / (1 + n_permutations)`` (Phipson & Smyth 2010).
    null_distribution : numpy.ndarray, shape (n_permutations,)
        MI of every permuted (or circularly shifted) pairing.
    n_permutations : int
        Number of permutations.
    permutation : str
        ``"shuffle"`` or ``"circular"``.
    min_shift : int
        Spacing of the circular shifts [samples], the smallest shift (0 for
        ``"shuffle"``).
    method, units : str
        Estimator and units.
    rows : tuple of int
        ``(start, stop)``: the rows the statistic and the null are computed on; the
        end-point-matched window of a circular test with ``match_ends`` (at most a
        fifth shorter than the series), else ``(0, n)``.
    """

    statistic: float
    pvalue: float
    null_distribution: np.ndarray = field(repr=False)
    n_permutations: int
    permutation: str
    min_shift: int
    method: str
    units: str
    rows: tuple[int, int]

    def __post_init__(self) -> None:
        check_record_fields(self, reals=("statistic", "pvalue"))


def _pair(x: Any, y: Any) -> tuple[np.ndarray, np.ndarray]:
    check_aligned({"x": x, "y": y})
    x = as_float_array(x, "x", ndim=1, min_length=MIN_SAMPLES)
    y = as_float_array(y, "y", ndim=1, min_length=MIN_SAMPLES)
    if x.shape[0] != y.shape[0]:
        raise ValueError(
            f"`x` and `y` must have the same length; got {x.shape[0]} and {y.shape[0]}."
        )
    return x, y


def _kde_bias_bound(est: MutualInformation, theta: float, x: np.ndarray, y: np.ndarray,
                    low: float, high: float) -> tuple[float, float, str]:
    """Lower the kde interval's lower bound by the estimate's bias, where it matters.

    The kde is biased upward on persistent pairs and no resample sees it (the block
    replicates are biased upward further): on two independent AR(1) series (phi 0.97,
    n = 2,000, ~61 effective pairs, above ``block_bootstrap_rule``'s 50) it read +0.054
    nats for an MI of 0 and the default block "normal" interval covered 0 in 19 of 42
    seeds (fix53-b). Its bias is estimated from 4 contiguous quarters of the record
    (``convergence.piece_bias``, the histogram CMI interval's rule, at the kde's
    measured rate ``KDE_BIAS_RATE``; Miller's rate 1 read 0.025 nats there, and the
    interval covered 33 of 42) and taken from ``low`` where it exceeds a quarter of
    the half-width (the rule of :func:`_grid_loss_bound`), and ``note`` says so: 41 of
    42 seeds covered after (fix53-d). A downward reading widens nothing (the kde's bias
    at high MI is the bandwidth's smoothing, which quarters read with noise; not
    measured here). Not for
    sorted samples (a monotone column, ``convergence.sorted_samples``): their quarters
    are not pieces of one law. For the "normal" interval (the default): the block
    "basic" and "percentile" intervals of the kde carry ``BlockBootstrapWarning``
    already (fix53-b). ``theta``: the estimate on the whole record.
    """
    if (est.method != "kde" or not (math.isfinite(low) and math.isfinite(high))
            or sorted_samples(x, y)):
        return low, high, ""
    n = x.shape[0]
    try:
        with quiet(BiasRuleWarning):  # a quarter's own rules: judged on the whole record
            bias = piece_bias(lambda i, j: est.estimate(x[i:j], y[i:j]), n, theta,
                              rate=KDE_BIAS_RATE)
    except ValueError:  # a quarter the estimator cannot take (constant, too short)
        return low, high, ""
    if not (math.isfinite(bias) and bias > 0.25 * 0.5 * (high - low)):
        return low, high, ""
    return low - bias, high, (
        f"lower bound lowered by {bias:.4g} {est.units}: the kde's upward bias on this "
        f"record, read from its estimates on 4 contiguous quarters against the whole "
        f"(bias ~ n^-{KDE_BIAS_RATE:g}; persistent series hold few effective pairs, and "
        f"the bootstrap does not see it)")


def _grid_loss_bound(est: MutualInformation, x: np.ndarray, y: np.ndarray, low: float,
                     high: float) -> tuple[float, float, str]:
    """Raise the upper bound by what the histogram's grid loses, where it matters.

    The histogram estimate (and every bootstrap replicate) is the MI of the binned pair,
    below the MI by the grid's loss; a bootstrap interval takes only the spread, so it
    missed the MI of iid Gaussian pairs increasingly with n (round 15 PART a, rho =
    0.6, 95 % intervals: coverage 0.76 at n = 5000, 0.55 at 20000; the loss shrinks
    more slowly than the spread). The loss on a Gaussian copula of the pair's
    normal-score correlation (``histogram.histogram_grid_loss``; the Gaussian-copula
    MI is a lower bound of any continuous pair's MI) is added to ``high`` where it
    exceeds a quarter of the half-width, and ``note`` says so. A discrete variable
    against a continuous one (no repeated value) takes the loss of the continuous
    variable's bins on a location-mixture model of its normal scores instead
    (``histogram.mixed_grid_loss``; round 51 PART a, Q63). Not for a persistent pair or
    one with other repeated values (the generic rules and ``ceiling_problem`` judge
    those), nor for bins the caller chose.
    """
    grid = getattr(est._engine, "grid_loss", None)
    if grid is None or not (math.isfinite(low) and math.isfinite(high)):
        return low, high, ""
    if effective_sample_rule(x, y):
        return low, high, ""
    # a discrete variable against a continuous one: its levels are read exactly, the
    # continuum by k bins (round 51 PART a Q63: coverage 0.725 of 95 % for x ~
    # Bernoulli(0.05), y = x + N(0, 0.5^2), n = 2,000; the estimate 0.0095 nats low)
    mixed = getattr(est._engine, "mixed_grid_loss", None)
    if mixed is not None and (got := mixed(x, y)) is not None:
        loss, k = got
        raise_by = loss * est._factor
        if raise_by <= 0.25 * 0.5 * (high - low):
            return low, high, ""
        return low, high + raise_by, (
            f"upper bound raised by {raise_by:.4g} {est.units}: {k} equiprobable bins of the "
            f"continuous variable lose that much MI on a model of the pair (normal scores "
            f"shifted by the discrete variable's levels), and the bootstrap sees only the "
            f"binned MI")
    if any(np.unique(a).size < a.size for a in (x, y)):
        return low, high, ""
    got = grid(x, y)
    if got is None:
        return low, high, ""
    loss, k, r = got
    raise_by = loss * est._factor
    if raise_by <= 0.25 * 0.5 * (high - low):
        return low, high, ""
    note = (f"upper bound raised by {raise_by:.4g} {est.units}: the {k} x {k} equiprobable "
            f"bins lose that much MI on a Gaussian copula of the pair's normal-score "
            f"correlation {r:.4g}, and the bootstrap sees only the binned MI")
    return low, high + raise_by, note


#: Largest n at which the iid Fisher interval also takes the delete-one jackknife's
#: spread (n more estimates; the bootstrap's shortfall it corrects is a small-n one:
#: ~3 % of the spread at n = 200, fix50-a).
FISHER_JACKKNIFE_MAX_N = 2000


def _jackknife_z_std(est: MutualInformation, x: np.ndarray, y: np.ndarray) -> float:
    """Delete-one jackknife s.d. of Fisher's z of the estimate (Efron & Stein 1981).

    ``sqrt((n - 1) / n * sum (z_(i) - mean z_(.))^2)`` over the n estimates without
    sample i; upward biased as a variance (Efron & Stein), where the bootstrap's is
    low at small n.
    """
    n = x.shape[0]
    keep = np.ones(n, dtype=bool)
    z = np.empty(n)
    for i in range(n):
        keep[i] = False
        z[i] = fisher_z_from_mi(est.estimate(x[keep], y[keep]) / est._factor)
        keep[i] = True
    return math.sqrt((n - 1) / n * float(np.sum((z - z.mean()) ** 2)))


def _bartlett_z_std(x: np.ndarray, y: np.ndarray, conditioning: int = 0,
                    cross: bool = False) -> float:
    """Return the sampling s.d. of the pair's Fisher z from its effective pairs.

    ``1 / sqrt(n_eff - 3 - conditioning)`` (Fisher 1921, with n replaced by Bartlett's
    n_eff = ``n (1 - rx ry) / (1 + rx ry)``, ``convergence.effective_pairs``; held at
    >= 1). ``conditioning``: the columns a partial correlation of x and y (residuals on
    them) was taken given, each of which costs a degree of freedom (Fisher 1924).
    For two AR(1) series of one coefficient phi whose innovations correlate (so the
    cross-correlation is rho phi^|k|) Bartlett's (1946) variance of the sample correlation
    is ``(1 - rho^2)^2 (1 + phi^2) / ((1 - phi^2) n)``, so z's is ``1 / n_eff`` at every
    rho. The block bootstrap's spread falls short of it below
    ~50 effective pairs (blocks neither long against the correlation time nor many:
    AR(1) 0.9, n = 500, rho = 0.6: bootstrap s.d. of the MI 0.065 nats against 0.080
    over seeds, fix51-b), so the block Fisher interval takes the larger of the two.
    n_eff is the fewer of that lag-1 closed form and Bartlett's full sum over lags
    (``convergence.bartlett_sum_pairs``): on long memory the lag-1 form counts 3-4
    times too many pairs and the 95 % interval covered 0.69-0.83 (fGn H 0.9 / 0.95,
    ARFIMA d = 0.4, n = 2,000, rho = 0.6; round 52 PART a, P18 / P19). ``cross`` (the
    CMI intervals, ``conditional_uncertainty.cmi_block_bounds``), for one column each:
    that count times ``convergence.bartlett_cross_factor`` (Bartlett's 1946 full formula
    over the pair's cross-correlations against the product form the counts assume; in
    [1, 2], at most n): a series and its own lag, whose cross-correlation peaks at lag 1,
    has ``1 + phi^2`` times the pairs (fix54-c; ``select_inputs``' interval of a target's
    last value covered 0.98 - 0.99 of 95 % with the product form). Not for the MI
    intervals: the factor's noise above 1 (sd 0.03 - 0.10 at n = 2,000 where theory gives
    1) took the long-memory floor under the full sum's (round 52's P18 / P19 test).
    """
    n_eff = min(effective_pairs(x, y), bartlett_sum_pairs(x, y))
    if cross and x.ndim == 1 and y.ndim == 1:
        n_eff = min(n_eff * bartlett_cross_factor(x, y), float(x.shape[0]))
    return 1.0 / math.sqrt(max(n_eff - 3.0 - conditioning, 1.0))


def _bartlett_mi_std(x: np.ndarray, y: np.ndarray, conditioning: int = 0,
                     cross: bool = False) -> float:
    """Return the sampling s.d. (nats) of the Gaussian-copula MI from the effective pairs.

    ``|r| / sqrt(n_eff - 3)``, r the normal-score correlation: :func:`_bartlett_z_std`
    carried to ``I = ln cosh z`` by the delta method (``dI/dz = tanh z = |r|``). A floor
    of the block "normal" interval's spread for the histogram and kde (fix51-b): on
    Gaussian AR(1) pairs their s.d. over seeds is about this or less (histogram, phi =
    0.9, n = 500, rho = 0.6, 300 seeds: 0.080 against 0.086; phi = 0.97: 0.140 against
    0.179; kde, 150 seeds: 0.084 against 0.085, 0.142 against 0.174), where the block
    bootstrap's was 0.071 and 0.104 (kde 0.067, 0.098): conservative at the fewest
    pairs. It is 0 for an independent pair and for a dependence without correlation:
    there the floor widens nothing. Of x's and y's residuals on ``conditioning`` columns,
    the s.d. of the Gaussian CMI given them (``conditional_mutual_information_ci``,
    fix52-b).
    """
    return abs(normal_score_correlation(x, y)) * _bartlett_z_std(x, y, conditioning, cross)


def _fisher_bounds(theta: float, dist: np.ndarray, factor: float,
                   confidence_level: float, s_jack: float = 0.0) -> tuple[float, float]:
    """Return the normal interval on Fisher's ``z = atanh |r|`` of a Gaussian MI.

    ``theta`` (the estimate) and ``dist`` (its bootstrap replicates, shape (B,)) are in
    the units whose factor to nats is ``factor`` (``api.UNITS``). The interval is
    ``z(I) -+ z_(1-a/2) s_z`` with ``s_z`` the replicates' s.d. on the z scale
    (variance-stabilised, Fisher 1921; Efron & Tibshirani 1993, sec. 12.6), or
    ``s_jack`` (another s.d. of z: the jackknife's, iid, or the effective pairs', block)
    where larger, mapped back by ``I = ln cosh z``;
    a lower end below z = 0 (``|r|`` = 0 inside) gives 0.
    Returns ``(low, high)`` in the same units.
    """
    z_hat = float(fisher_z_from_mi(theta / factor))
    s_z = max(float(np.std(fisher_z_from_mi(np.asarray(dist) / factor), ddof=1)), s_jack)
    half = stats.norm.ppf(0.5 + confidence_level / 2.0) * s_z
    low = 0.0 if z_hat - half <= 0.0 else float(mi_from_fisher_z(z_hat - half)) * factor
    return low, float(mi_from_fisher_z(z_hat + half)) * factor


#: Estimators whose block-bootstrap replicates are biased upward enough that the quantile
#: intervals ("basic", "percentile") miss (fix53-b, AR(1) 0.9 / 0.97 pairs, n = 2,000,
#: 42 - 51 seeds per cell: percentile 0.000 of an MI of 0, 0.76 - 0.86 at rho = 0.6;
#: basic 0.45 / 0.64 of an MI of 0 at phi 0.9): they warn.
QUANTILE_BIASED_METHODS = ("histogram", "kde")
_QUANTILE_BIAS_WHY = (
    "mutual_information_ci with method={method!r}, bootstrap='block', "
    "interval={interval!r}: this estimator's block replicates are biased upward (more "
    "than the estimate itself), which the quantile intervals carry: a 95 % interval "
    "covered 0.000 (percentile) and 0.45 - 0.64 (basic) of an MI of 0 on AR(1) 0.9 pairs, "
    "n = 2,000, and the percentile 0.76 - 0.86 of an MI of 0.22 nats (fix53-b); use "
    "interval='normal' (the default), or mutual_information_permutation_test to test "
    "independence")


def _resolve_interval(interval: str, method: str, bootstrap: str, x: np.ndarray,
                      y: np.ndarray) -> str:
    """Resolve ``"auto"``; refuse ``"fisher"`` where it has no meaning.

    ``"auto"``: ``"fisher"`` for the Gaussian estimator of a continuous pair with the
    iid bootstrap at n <= :data:`FISHER_JACKKNIFE_MAX_N` (where it takes the jackknife's
    spread too), else ``"normal"``: without the jackknife the Fisher interval of an
    independent pair covers 0.928 (n = 200; the bootstrap of ``|r|`` folds at 0 and
    its spread is low), where the "normal" one holds 0 always (fix50-a).
    """
    fits = (method == "gaussian"
            and discrete_pair_mi(discrete_x_levels(x), y) is None)  # not a table's MI
    if interval == "auto":
        # iid: where the jackknife is taken; block: always, with the effective pairs'
        # spread as a floor (fix51-b)
        jack = bootstrap == "iid" and x.shape[0] <= FISHER_JACKKNIFE_MAX_N
        return "fisher" if fits and (jack or bootstrap == "block") else "normal"
    if interval == "fisher" and not fits:
        what = (f"`method`={method!r}" if method != "gaussian"
                else "a discrete pair (the Gaussian method gives its table's MI)")
        raise ValueError(
            "`interval`='fisher' is the normal interval on Fisher's z = atanh|r| of the "
            f"Gaussian MI -0.5 ln(1 - r^2); it has no meaning for {what}: use "
            "interval='normal' (or 'auto').")
    return interval


def mutual_information_ci(
    x: Any,
    y: Any,
    method: str = RESAMPLING_METHOD,
    units: str = "nats",
    *,
    confidence_level: float = 0.95,
    n_resamples: int = 999,
    block_length: int | str | None = None,
    bootstrap: str = "block",
    interval: str = "auto",
    seed: Any = None,
    **options: Any,
) -> MIConfidenceResult:
    """Bootstrap confidence interval for the mutual information of a paired series.

    Parameters
    ----------
    x, y : array_like, shape (n,)
        Paired samples in time order (n >= 10, finite).
    method : {"histogram", "kde", "gaussian"}
        Estimator (see :func:`modalinfo.information.mutual_information`). Default
        ``"histogram"``, not the point estimate's default ``"ksg"``, which cannot be
        bootstrapped (below); the histogram is fast, and not biased by the duplicated
        samples of a resample
        (the leave-one-out KDE is, upward by ~0.02 nats at n = 2000, which the default
        "normal" interval ignores since it takes only the spread). ``"ksg"`` is
        refused: repeated samples break nearest-neighbour estimators.
    units : {"nats", "bits"}
        Units of the results.
    confidence_level : float
        Nominal coverage in (0, 1).
    n_resamples : int
        Number of bootstrap resamples (>= 10; for the quantile intervals ``"basic"``,
        ``"percentile"`` and ``"bca"`` at least ``2 / (1 - confidence_level)``, so that
        each tail holds a replicate: 40 at 95 %).
    block_length : int, "auto" or None
        Block length of the moving-block bootstrap [samples]. ``None``/``"auto"``:
        the Politis-White (2004) automatic length, the larger of those of x and y
        (see :func:`~modalinfo.information.resampling.optimal_block_length`). Ignored
        by the iid bootstrap.
    bootstrap : {"block", "iid"}
        Moving-block bootstrap of aligned (x, y) blocks (Kuensch 1989), or the iid
        bootstrap of pairs. Telemetry is strongly
        autocorrelated: the iid bootstrap then understates the error and its
        intervals undercover (measured, default "normal" interval, 150 AR(1) pairs
        with phi = 0.95, rho = 0.6, n = 4000: coverage 0.29 for a nominal 0.95,
        against 0.93 for the block bootstrap); the iid bootstrap warns
        (``BlockBootstrapWarning``) where the largest product of the columns' lag-1
        autocorrelations exceeds 0.05 (``resampling.iid_bootstrap_rule``, the shuffle
        null's rule; stop 58). The block bootstrap warns
        (``BlockBootstrapWarning``, once per call) where it undercovers: fewer than 50
        effective pairs ``n (1 - rx ry) / (1 + rx ry)`` (Bartlett 1935; n = 500:
        coverage 0.80 at AR(1) 0.95, 0.70 at 0.99; no block length helps), or both
        series changing scale within the record (0.80 on a x4 variance step; the
        block-scale rule of the telemetry quality pass); leftovers 12-ci. Or heavy
        tails: an AR(4) innovation beyond the quality pass's Bonferroni Gaussian
        outlier threshold at a family-wise 1e-4 (0.77 with Student t3 innovations,
        whose fourth moment is infinite; leftovers 13-stats).
    interval : {"auto", "fisher", "normal", "basic", "percentile", "bca"}
        ``"auto"`` (default): ``"fisher"`` for ``method="gaussian"`` (continuous pair)
        with ``bootstrap="block"``, or ``"iid"`` at n <= 2,000, else ``"normal"``; the
        result's ``interval`` says which. ``"fisher"`` (``method="gaussian"`` only): the
        normal interval on Fisher's ``z = atanh|r|`` (``I = ln cosh z``; Fisher 1921),
        ``z -+ z_(1-a/2) s_z`` mapped back, low end clipped at 0, with ``s_z`` the larger
        of the bootstrap's and, iid at n <= 2,000, the delete-one jackknife's s.d. of z (n
        more estimates; Efron & Stein 1981), or, block, ``1 / sqrt(n_eff - 3)`` with
        Bartlett's effective pairs ``n_eff`` (the block bootstrap's spread is short of the
        estimate's below ~50 of them; stationary AR(1) pairs of coefficient phi, rho =
        0.6, 500 seeds, B = 199, fix51-b: coverage 0.956 / 0.970 / 0.958 at phi = 0.9 /
        0.97 / 0.5, n = 500, where "normal" covered 0.880 / 0.810 / 0.926; the
        ``BlockBootstrapWarning`` is still given there). Measured coverage of 95 % (iid
        Gaussian pairs,
        B = 199, fix50-a): 0.9445 +- 0.005 at n = 200, rho = 0.6, 0.9495 at rho = 0.9,
        0.9435 at 0.3, 0.9485 at rho = 0 (MI 0), 2,000 seeds each; 0.945 at n = 100;
        0.943 at n = 500, rho = 0.6 and 0.951 at n = 50 (1,000 seeds each). Without the
        jackknife (block bootstrap, n > 2,000) it covered 0.936 at n = 200, rho = 0.6 and
        only 0.928 at rho = 0 (the bootstrap of ``|r|`` folds at 0), so ``"auto"`` does
        not choose it there.
        ``"normal"``: ``I -+ z_(1-a/2) s_boot``, centred on the estimate,
        spread from the bootstrap (its small-sample shortfall, measured for the
        gaussian estimator, iid bootstrap, rho = 0.6: coverage 0.930 +- 0.004 at n = 200
        over 2,400 seeds (0.9295 over 2,000 more, fix50-a) and 0.938 +- 0.006 at n = 500
        over 1,200 for a nominal 0.95; the bootstrap's spread is ~5 % below the
        estimate's over seeds; 0.947 +- 0.013 at n = 1,000; round 49 PART a S01, fix49-d;
        not warned; at MI 0 it holds 0 always, conservatively). With the block
        bootstrap the histogram's and kde's ``s_boot`` is raised to ``|r| / sqrt(n_eff
        - 3)`` where below it (r the normal-score correlation, n_eff Bartlett's effective
        pairs: the Gaussian-copula MI's s.d.; the block bootstrap's is low below ~50
        effective pairs; AR(1) pairs, n = 500, rho = 0.6: histogram coverage 0.910 ->
        0.957 at phi = 0.9, 0.793 -> 0.977 at phi = 0.97 (300 seeds), kde 0.880 -> 0.940
        and 0.720 -> 0.973 (150 seeds); fix51-b). What it covers
        (iid Gaussian pairs, default block bootstrap, fix51-b): the histogram interval,
        whose upper end is raised by the grid's loss, covers the MI (0.976 at n = 200,
        rho = 0.6, 500 seeds; 0.96 - 1.0 at n >= 1,000, 50 - 150 seeds) and the
        estimator's own expectation (0.97 - 1.0); the kde interval, centred on an
        estimate biased ~-0.005 to -0.008 nats, covers its expectation (0.96 at n = 200)
        and the MI (0.948; at rho = 0.9, n = 200: 0.950 of 300 seeds, fix52-b);
        ``"basic"``:
        ``[2 I - q_hi, 2 I - q_lo]``, corrects
        by the bootstrap bias, which for MI is unreliable (see the module notes);
        ``"percentile"``: ``[q_lo, q_hi]``. With the block bootstrap the offsets of
        ``q_lo`` and ``q_hi`` from the estimate are first widened by the "normal"
        interval's floor over the replicates' s.d. where it is larger (fix52-b; Gaussian
        AR(1) pairs, rho = 0.6, n = 500, 300 seeds: percentile 0.910 -> 0.963 at phi =
        0.9, 0.833 -> 0.973 at 0.97; basic 0.857 -> 0.927 and 0.737 -> 0.880, the
        latter below 50 effective pairs, where ``BlockBootstrapWarning`` is given).
        For the histogram and kde with the block bootstrap both warn
        (``BlockBootstrapWarning``): their block replicates are biased upward, which
        the quantiles carry (fix53-b; AR(1) pairs, n = 2,000, 42 - 51 seeds, s.e.
        0.031 - 0.034: percentile 0.000 of an MI of 0 at phi 0.9 and 0.97, 0.76 - 0.86
        at rho = 0.6; basic 0.45 / 0.64 (histogram / kde) of an MI of 0 at phi 0.9,
        0.90 - 0.98 elsewhere);
        ``"bca"``: bias-corrected and
        accelerated (``scipy.stats.bootstrap``), iid bootstrap only. BCa is undefined
        when every replicate lies on one side of the estimate (infinite bias
        correction; common for MI, whose resamples are biased upward): the percentile
        interval of the same replicates is returned, with ``interval="percentile"``
        and the reason in ``note``. The histogram (rule-chosen equiprobable bins) reads
        the MI of the binned pair, below the MI by what the grid loses, which the
        bootstrap cannot see: except for ``"bca"``, ``high`` is raised by that loss on
        a Gaussian copula of the pair (``histogram.histogram_grid_loss``) where it
        exceeds a quarter of the half-width, and ``note`` says so (round 15 PART a:
        iid Gaussian pairs, rho = 0.6, coverage of 95 % intervals 0.76 at n = 5000 and
        0.55 at 20000 before, 1.0 and 1.0 after, 60 seeds each: conservative, the
        loss exceeds the Miller-Madow estimate's bias by ~0.002 nats). Where one variable
        is discrete (a flag, a few levels, read exactly by the bins) and the other has
        no repeated value, the loss is that of the continuous variable's k bins on a
        model of the pair (its normal scores shifted by the levels,
        ``histogram.mixed_grid_loss``; round 51 PART a: x ~ Bernoulli(0.05), y = x +
        N(0, 0.5^2), n = 2,000, 40 seeds: coverage 0.725 before, 0.925 after).
        The kde's "normal" interval has its lower bound lowered by the estimate's
        upward bias read from 4 contiguous quarters of the record where that exceeds a
        quarter of the half-width, and ``note`` says so (fix53-d: two independent
        AR(1) 0.97 series, n = 2,000, 42 seeds: 0 covered 13 / 42 before, 41 / 42
        after; ``_kde_bias_bound``).
    seed : None, int or numpy.random.Generator
        Randomness of the resampling.
    **options
        Estimator options.

    Returns
    -------
    MIConfidenceResult
        Estimate, interval, block length and bootstrap distribution.
    """
    check_bootstrappable(method)  # ksg: resamples repeat samples (modalinfo.information.ksg)
    check_choice(units, "units", tuple(UNITS))
    x, y = _pair(x, y)
    confidence_level = check_real(confidence_level, "confidence_level", minimum=0.0,
                                  maximum=1.0, strict_min=True, strict_max=True)
    n_resamples = check_resamples(n_resamples, "n_resamples", minimum=10)
    check_memory(8.0 * n_resamples * (x.shape[0] + 1), "n_resamples", n_resamples,
                 "its resample indices (int64, one per sample and resample)")
    check_choice(bootstrap, "bootstrap", ("block", "iid"))
    check_choice(interval, "interval", ("auto", "fisher", "normal", "basic", "percentile",
                                        "bca"))
    if interval == "bca" and bootstrap != "iid":
        raise ValueError("`interval`='bca' needs bootstrap='iid'; got bootstrap='block'.")
    check_tail_replicates(interval, n_resamples, confidence_level)
    rng = check_rng(seed)
    est = MutualInformation(method, units, **options)
    est._judge_resolution = False  # judged once below, not per bootstrap replicate
    interval = _resolve_interval(interval, est.method, bootstrap, x, y)
    theta = est.estimate(x, y)
    n = x.shape[0]
    alpha = 1.0 - confidence_level

    # a capped estimate: the interval takes only the bootstrap's spread, so it excludes
    # the MI by far (round 14 PART a: [3.69, 3.77] nats for 6.56); said in the note too
    varied = not (_is_constant(x) or _is_constant(y))
    note = (pile_why({"x": x, "y": y}, est.method) if varied else None) or ""
    # as mutual_information: the piles first and alone, then the resolution the estimator
    # chose itself at small n (its own warning), then the cap
    if not note and not (varied and _warn_default_resolution(est, x, y,
                                                              "mutual_information_ci")):
        note = ceiling_problem(est, theta, x, y) or ""
    if note:
        warn(f"mutual_information_ci with method={est.method!r}: {note}.",
             BiasRuleWarning, stacklevel=2)
    if bootstrap == "iid":
        why = iid_bootstrap_rule(x, y, "mutual_information_ci")
        if why is not None:
            warn(why, BlockBootstrapWarning, stacklevel=2)
    if interval == "bca":
        b = 1
        with catching_warnings(), np.errstate(divide="ignore", invalid="ignore"):
            # scipy warns, then returns NaN bounds, when z0 is infinite or the jackknife
            # is degenerate (0/0 acceleration): handled below
            warnings.simplefilter("ignore", stats.DegenerateDataWarning)
            res = stats.bootstrap(
                (x, y), lambda a, c: est.estimate(a, c), paired=True, vectorized=False,
                n_resamples=n_resamples, confidence_level=confidence_level, method="BCa",
                rng=rng,
            )
        dist = np.asarray(res.bootstrap_distribution, dtype=float)
        low, high = float(res.confidence_interval.low), float(res.confidence_interval.high)
        if not (math.isfinite(low) and math.isfinite(high)):
            below = int(np.count_nonzero(dist < theta))
            note = (note + "; " if note else "") + (
                f"BCa undefined: {below} of {n_resamples} bootstrap replicates lie below "
                f"the estimate (infinite bias correction); percentile interval given"
            )
            interval = "percentile"
            low, high = percentile_bounds(dist, confidence_level)
    else:
        if bootstrap == "iid":
            b = 1
            check_index_memory(n_resamples, n)
            idx = rng.integers(0, n, size=(n_resamples, n))
        else:
            b = resolve_block_length(block_length, x, y)
            why = block_bootstrap_rule(x, y, "mutual_information_ci")
            if why is not None:
                warn(why, BlockBootstrapWarning, stacklevel=2)
            idx = block_bootstrap_indices(n, b, n_resamples, rng)
        dist = np.array([est.estimate(x[i], y[i]) for i in idx])
        q_lo, q_hi = percentile_bounds(dist, confidence_level)
        if (bootstrap == "block" and interval in ("basic", "percentile")
                and est.method in QUANTILE_BIASED_METHODS):
            warn(_QUANTILE_BIAS_WHY.format(method=est.method, interval=interval),
                 BlockBootstrapWarning, stacklevel=2)
        if bootstrap == "block" and interval in ("basic", "percentile"):
            # the block replicates' spread is short of the estimate's on persistent pairs
            # (fix51-b); their quantiles' offsets from the estimate are widened by the
            # "normal" interval's floor over their s.d. (fix52-b: gaussian, AR(1) 0.9,
            # n = 500, rho = 0.6, 300 seeds: percentile 0.910 -> 0.963, basic 0.857 -> 0.927)
            s_boot = float(np.std(dist, ddof=1))
            s_floor = _bartlett_mi_std(x, y) * est._factor
            if s_floor > s_boot > 0.0:
                g = s_floor / s_boot
                q_lo, q_hi = theta - g * (theta - q_lo), theta + g * (q_hi - theta)
        if interval == "normal":
            s_mi = float(np.std(dist, ddof=1))
            if bootstrap == "block" and est.method in ("histogram", "kde"):
                # the block bootstrap's spread is low below ~50 effective pairs (fix51-b)
                s_mi = max(s_mi, _bartlett_mi_std(x, y) * est._factor)
            half = stats.norm.ppf(1.0 - alpha / 2.0) * s_mi
            low, high = theta - half, theta + half
        elif interval == "fisher":
            # the iid bootstrap's spread is low at small n (fix50-a): the jackknife's too
            # the block bootstrap's is low below ~50 effective pairs: Bartlett's (fix51-b)
            if bootstrap == "block":
                s_jack = _bartlett_z_std(x, y)
            elif n <= FISHER_JACKKNIFE_MAX_N:
                s_jack = _jackknife_z_std(est, x, y)
            else:
                s_jack = 0.0
            low, high = _fisher_bounds(theta, dist, est._factor, confidence_level, s_jack)
        elif interval == "basic":
            low, high = 2.0 * theta - q_hi, 2.0 * theta - q_lo
        else:
            low, high = q_lo, q_hi
    if not note and interval != "bca":  # "bca": scipy's interval as scipy gives it
        low, high, note = _grid_loss_bound(est, x, y, low, high)
    if not note and interval == "normal":  # block "basic" / "percentile": warned above
        low, high, note = _kde_bias_bound(est, theta, x, y, low, high)
    return MIConfidenceResult(
        estimate=float(theta), low=float(low), high=float(high),
        confidence_level=confidence_level, block_length=int(b), n_resamples=n_resamples,
        bootstrap_std=float(np.std(dist, ddof=1)), bootstrap_mean=float(np.mean(dist)),
        bootstrap_distribution=dist, bootstrap=bootstrap, interval=interval, method=method,
        units=units, note=note,
    )


def mutual_information_permutation_test(
    x: Any,
    y: Any,
    method: str = RESAMPLING_METHOD,
    units: str = "nats",
    *,
    n_permutations: int = 999,
    permutation: str = "shuffle",
    min_shift: int | str | None = None,
    seed: Any = None,
    match_ends: bool = True,
    **options: Any,
) -> MIPermutationResult:
    """Permutation test of independence of x and y with an MI statistic.

    Parameters
    ----------
    x, y : array_like, shape (n,)
        Paired samples in time order (n >= 10, finite).
    method : {"ksg", "kde", "histogram", "gaussian"}
        Estimator; x is fitted once and every permutation only re-scores y. Default
        ``"histogram"`` (``api.RESAMPLING_METHOD``): ~1 ms
        per score at n = 1e4, and the null is built with the same estimator, so the
        test's size does not depend on its bias. ``"ksg"`` (the point estimate's
        default) costs ~0.09 s per score (999 permutations: ~1.5 min of CPU) and has
        more power against non-monotone dependence.
    units : {"nats", "bits"}
        Units of the statistic.
    n_permutations : int
        Number of permutations (>= 1).
    permutation : {"shuffle", "circular"}
        ``"shuffle"``: random permutations of y; exact for iid pairs, but
        anti-conservative for autocorrelated series (telemetry), whose shuffled
        copies look more independent than the series ever can. It warns
        (``ShuffleNullWarning``) when the pair's lag-1 autocorrelations say so
        (product > 0.05; audit 12-tests: 57 % rejections at 5 % on independent
        AR(1) pairs of coefficient 0.9, n = 500). ``"circular"``
        (time-shifted surrogates, Quian Quiroga et al. 2002): y rotated by distinct
        multiples of a spacing b with the original at 0
        (:func:`~modalinfo.information.resampling.surrogate_shifts`), which keeps each
        series' autocorrelation and breaks only the alignment; use it for time
        series. Measured on 1 000 independent AR(1) pairs, n = 500, 99 shifts
        (``benchmarks/RESULTS.md``, "False-positive rate of the surrogate tests"):
        without ``match_ends`` it rejects 0.048 at 0.05 for phi = 0.9, but 0.076 for
        phi = 0.99, whose correlation time is n / 5 (the rotation joins two nearly
        independent levels, so a rotated series is less persistent than the
        original); ``match_ends`` (default) restores the level there with 99
        shifts (table), not with 19 (0.064: far rotations only;
        :func:`~modalinfo.information.resampling.matched_window`). Series of >= ~20
        correlation times hold the level either way. It warns
        (``RotationNullWarning``) where both series change scale within the record
        (9.5 % rejections at 5 % on a x4 variance step, n = 500; the block-scale rule
        of the telemetry quality pass, judged from n ~ 420).
    min_shift : int, "auto" or None
        ``"circular"`` only (refused with ``"shuffle"``).
        Spacing b of the circular shifts [samples], in ``[1, n // 2]``; ``None``
        (default): the largest that fits ``n_permutations`` shifts, about
        ``n / (n_permutations + 1)``; ``"auto"``: the Politis-White block length of the
        pair (:func:`~modalinfo.information.resampling.optimal_block_length`), at most
        n // 2. A spacing below the series' correlation time costs power, not
        validity.
    seed : None, int or numpy.random.Generator
        Randomness of the permutations.
    match_ends : bool
        ``"circular"`` only: test the window of the rows whose end points and end
        slopes match (:func:`~modalinfo.information.resampling.matched_window`,
        Theiler et al. 1992, Schreiber & Schmitz 2000; at most a fifth of the rows
        discarded, none when the join already looks like a typical step), so the
        rotation joins like values. ``False``: every row (the test before issue 28's
        last fix; liberal when the correlation time exceeds ~ n / 20).
    **options
        Estimator options.

    Returns
    -------
    MIPermutationResult
        Statistic, p-value ``(1 + #{null >= statistic}) / (1 + n_permutations)`` and
        the null distribution, all on the rows ``rows``.
    """
    check_choice(method, "method", METHODS)
    check_choice(units, "units", tuple(UNITS))
    x, y = _pair(x, y)
    n_permutations = check_resamples(n_permutations, "n_permutations", minimum=1)
    check_memory(16.0 * n_permutations, "n_permutations", n_permutations,
                 "its null distribution and shifts")
    check_choice(permutation, "permutation", ("shuffle", "circular"))
    if permutation == "shuffle" and min_shift is not None:
        # the spacing of circular shifts: ignored by a shuffle, while the result recorded
        # min_shift 0 (round 36 PART a, M1)
        raise ValueError(f"`min_shift`={min_shift!r} spaces circular shifts; it has no use "
                         "with `permutation`='shuffle' (pass permutation='circular', or "
                         "no min_shift).")
    if not isinstance(match_ends, (bool, np.bool_)):
        raise TypeError(f"`match_ends` must be a bool; got {type(match_ends).__name__}.")
    rng = check_rng(seed)
    start, stop = 0, x.shape[0]
    spacing = None
    if permutation == "circular":
        spacing = None if min_shift is None else resolve_block_length(
            min_shift, x, y, name="min_shift", maximum=x.shape[0] // 2)
        if match_ends:
            start, stop = matched_window_for(n_permutations, 0, spacing, x, y)
            if stop - start < MIN_SAMPLES:
                start, stop = 0, x.shape[0]
            x, y = x[start:stop], y[start:stop]
    n = x.shape[0]
    est = MutualInformation(method, units, **options)
    # a biased statistic leaves the permutation test exact (its null has the same bias):
    # the default resolution is not judged here
    est._judge_resolution = False
    est.fit(x)
    stat = est.score(y)
    null = np.empty(n_permutations)
    shift0 = 0
    if permutation == "shuffle":
        why = shuffle_null_rule(x, y, "mutual_information_permutation_test")
        if why is not None:
            warn(why, ShuffleNullWarning, stacklevel=2)
        for i in range(n_permutations):
            null[i] = est.score(y[rng.permutation(n)])
    else:
        # a scale that changes in both series at once narrows the rotations' null
        name = "mutual_information_permutation_test"
        why = (rotation_null_rule(x, y, name, MI_ROTATION_MIN_EFFECTIVE_PAIRS)
               or stationarity_null_rule(x, y, name)
               or level_null_rule(x, y, name))
        if why is not None:
            warn(why, RotationNullWarning, stacklevel=2)
        shifts, shift0 = surrogate_shifts(n, n_permutations, 0, spacing, rng,
                                          name="n_permutations")
        for i, s in enumerate(shifts):
            null[i] = est.score(np.roll(y, int(s)))
    return MIPermutationResult(
        statistic=float(stat), pvalue=surrogate_pvalue(stat, null), null_distribution=null,
        n_permutations=n_permutations, permutation=permutation, min_shift=int(shift0),
        method=method, units=units, rows=(start, stop),
    )
