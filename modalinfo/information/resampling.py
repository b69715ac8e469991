"""Resampling of time series: block bootstrap, automatic block length, shift surrogates.

One home for the resampling that the interval and the significance tests of the
information package share (``modalinfo.information.uncertainty``,
``modalinfo.information.conditional_uncertainty``, ``modalinfo.information.selection``,
``modalinfo.information.flow``, and the ordering bootstrap of
``modalinfo.ordering.orderings``). Telemetry is autocorrelated (AR(1)
coefficients of 0.9-0.99 per frame), so resampling frames one by one understates
errors and overstates significance; everything here keeps the time structure.

Intervals (bootstrap). :func:`block_bootstrap_indices` resamples blocks of
consecutive samples: the moving-block bootstrap (Kuensch 1989, Ann. Statist. 17,
1217), blocks starting uniformly in ``[0, n - b]``, or the circular-block bootstrap
(Politis & Romano 1992, in *Exploring the Limits of Bootstrap*, 263), blocks starting
anywhere and wrapping around, so every sample is drawn with the same probability.
The block length b comes from :func:`resolve_block_length`, the one parser of
``block_length`` (``None``/``"auto"``/int); ``"auto"`` is :func:`auto_block_length`,
the Politis & White (2004) rule with the correction of Patton, Politis & White (2009).

Tests (surrogates). :func:`surrogate_shifts` draws the circular shifts of
time-shifted surrogates (each series keeps its autocorrelation, only the alignment
is broken): distinct multiples of a spacing b, with the original at shift 0, so the
original is exchangeable with the surrogates and the p-value of
:func:`surrogate_pvalue`, ``(1 + #{T_s >= T_0}) / (S + 1)``, is exact for circularly
stationary series (a randomisation test over the rotations by multiples of b;
Phipson & Smyth 2010 for the ``+1``). Shifts drawn at random from ``[m, n - m]``
(never near the original) are not: that scheme, formerly used by
``mutual_information_permutation_test`` and ``conditional_mutual_information_test``,
rejected independent AR(1) pairs too often (``benchmarks/bench_surrogate_fpr.py``,
table in ``benchmarks/RESULTS.md``).

A rotation joins the end of a series to its start. When the series is long against
its correlation time that join is one step among many; when it is not (an AR(1) of
coefficient 0.99 over 500 samples: correlation time ~ n / 5) the join is a jump
between two nearly independent levels, a rotated series is less persistent than the
original, and the rotation tests reject too often (+3.8 standard errors at 0.05).
:func:`matched_window` is the cure of Theiler et al. (1992) and Schreiber & Schmitz
(2000): test the sub-series whose end points and end slopes match, so that the
wrap joins like values; the tests of one pair and the transfer-entropy map use it.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from scipy import stats

from modalinfo._stats import (
    INNOVATION_ORDER,
    LEVEL_ALPHA,
    MAD_RELATIVE_SD,
    PAIR_MIN_STATIONARITY_FRAMES,
    lag1_autocorrelations,
    level_steps,
    mad_union_threshold,
    sample_autocovariance,
    scale_stationarity,
    stacked_ar_fits,
)
from modalinfo.common.memory import free_memory_bytes
from modalinfo.common.scaling import rescale_power_of_two
from modalinfo.common.validation import as_float_array, check_int, check_rng
from modalinfo.information.api import MIN_SAMPLES
from modalinfo.information.convergence import bartlett_pairs, sorted_samples

__all__ = [
    "MAX_RESAMPLES",
    "check_index_memory",
    "check_resamples",
    "check_tail_replicates",
    "least_tail_replicates",
    "percentile_bounds",
    "auto_block_length",
    "block_bootstrap_indices",
    "local_linear_split",
    "local_permutation",
    "matched_window",
    "matched_window_for",
    "neighbour_rows",
    "optimal_block_length",
    "politis_white_length",
    "rank_based_options",
    "residual_split",
    "resolve_block_length",
    "surrogate_pvalue",
    "surrogate_shifts",
]

# ------------------------------------------------------------ quantile bounds
def least_tail_replicates(confidence_level: float) -> int:
    """Fewest bootstrap replicates whose quantile bounds at ``confidence_level`` have a tail.

    The percentile bounds at level L are the replicates' ``(1 - L) / 2`` quantile and its
    mirror; below ``R (1 - L) / 2 = 1`` replicate per tail, i.e. ``R < 2 / (1 - L)``, no
    replicate lies beyond them: they are (nearly) the extreme replicates, whose range
    holds a new replicate with probability ``(R - 1) / (R + 1)`` whatever L asked (the
    order-statistic law of exchangeable draws; Davison & Hinkley 1997, "Bootstrap Methods
    and their Application", sec. 5.2.3, choose R with ``(R + 1)(1 - L) / 2`` an integer;
    Efron & Tibshirani 1993, "An Introduction to the Bootstrap", ch. 13 and 19, recommend
    ~1000 for percentile intervals). 40 at 95 %, 20 at 90 %, 200 at 99 %.

    Parameters
    ----------
    confidence_level : float
        Level L in (0, 1).

    Returns
    -------
    int
        The smallest R with ``R (1 - L) / 2 >= 1`` (to 1e-9 of a replicate).
    """
    # 2 / (1 - L) to 1e-9: in floating point 2 / (1 - 0.9) is 20.000000000000004 and
    # (1 - 0.9) / 2 * 20 is 0.9999999999999998, which refused 20 replicates at 90 %
    return max(1, math.ceil(2.0 / (1.0 - float(confidence_level)) - 1e-9))


def percentile_bounds(replicates: np.ndarray, confidence_level: float,
                      axis: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Return the percentile bounds of replicates: their (1 - L) / 2 and (1 + L) / 2 quantiles.

    The one quantile rule of every bootstrap and surrogate percentile bound of the
    package. Type-6 (Weibull) plotting positions, ``numpy.quantile(...,
    method="weibull")``: the p quantile of R replicates is their order statistic of rank
    ``p (R + 1)`` (interpolated between ranks), and a new replicate exchangeable with
    them falls below the j-th order statistic with probability exactly ``j / (R + 1)``
    (Hyndman & Fan, Am. Stat. 50, 361, 1996, definition 6; Davison & Hinkley 1997, sec.
    5.2.3), so each bound is exceeded with the probability the level states (exactly
    where ``p (R + 1)`` is a whole number). numpy's default (type 7, linear) puts the p
    quantile at rank ``1 + p (R - 1)``, nearer the centre: at R = 40, L = 0.95 rank 1.975
    instead of 1.025, and a new replicate falls beyond each bound with probability
    ~1.975 / 41 = 0.048 instead of 0.025 (leftovers 12-est). Where ``p (R + 1) < 1`` the
    bound is the extreme replicate (numpy clips; :func:`check_tail_replicates` refuses
    such R first).

    Parameters
    ----------
    replicates : ndarray
        The replicates, resamples along ``axis``.
    confidence_level : float
        Level L in (0, 1).
    axis : int
        Axis of the resamples.

    Returns
    -------
    (ndarray, ndarray)
        Lower and upper bounds, the shape of ``replicates`` without ``axis`` (0-d arrays
        for a 1-D input).
    """
    tail = (1.0 - float(confidence_level)) / 2.0
    low, high = np.quantile(np.asarray(replicates, dtype=float), [tail, 1.0 - tail],
                            axis=axis, method="weibull")
    return low, high


def check_tail_replicates(interval: str, n_resamples: int, confidence_level: float,
                          name: str = "n_resamples") -> None:
    """Refuse a quantile interval whose tails ``(1 - level) / 2`` hold no replicate.

    The ``"basic"``, ``"percentile"`` and ``"bca"`` bounds are quantiles of the
    replicates at ``(1 - level) / 2`` and its mirror; with fewer than
    :func:`least_tail_replicates` (``2 / (1 - level)``) replicates no replicate lies
    beyond them, the bounds are the extreme replicates and cover at most
    ``(B - 1) / (B + 1)`` whatever the level asked (round 10 PART a: a "99.9 %"
    percentile interval from 50 replicates). The ``"normal"`` interval takes only the
    replicates' spread and has no such limit. The one rule of every bootstrap bound of
    the package (``mutual_information_ci``, ``order_modes``' default, ``reorder``'s
    caution).
    """
    if interval in ("normal", "fisher", "auto"):  # spread intervals ("auto": one of them)
        return
    least = least_tail_replicates(confidence_level)
    if n_resamples < least:
        tail = (1.0 - confidence_level) / 2.0
        raise ValueError(
            f"`{name}`={n_resamples} is too few for a {interval!r} interval at "
            f"`confidence_level`={confidence_level:g}: its bounds are the replicates' "
            f"{tail:.3g} and {1 - tail:.3g} quantiles, and fewer than 1 / {tail:.3g} = "
            f"{least} replicates leave none beyond them (the bounds would be the extreme "
            f"replicates, covering at most (B - 1) / (B + 1)); use {name} >= {least} "
            "or interval='normal'.")


# ----------------------------------------------------------------- block length
#: Magnitudes [any unit] outside which :func:`politis_white_length` rescales the centred
#: series: ``D`` squares an autocovariance, a fourth power of the values, so the bounds
#: are the square roots of :data:`~modalinfo.common.scaling.SAFE_MAGNITUDE`'s.
_BLOCK_SCALE_BOUNDS = (1e-50, 1e50)


def politis_white_length(x: np.ndarray) -> float:
    """Politis-White automatic block length of one series (moving-block bootstrap).

    Politis & White, Econometric Rev. 23, 53 (2004), with the correction of Patton,
    Politis & White, Econometric Rev. 28, 372 (2009): ``b = (2 G^2 / D)^(1/3) n^(1/3)``,
    ``G = sum_k lambda(k/M) |k| gamma(k)``, ``D = (4/3) g(0)^2``,
    ``g(0) = sum_k lambda(k/M) gamma(k)`` (flat-top lag window lambda), ``M = 2 m_hat``
    where m_hat is the first lag after which ``K_N = max(5, log10 n)`` autocorrelations
    are insignificant (``|rho| < 2 sqrt(log10 n / n)``).

    Parameters
    ----------
    x : numpy.ndarray, shape (n,)
        Finite float series, n >= 2 (not checked: callers validate).

    Returns
    -------
    float
        Block length [samples], not rounded, in ``[1, ceil(min(3 sqrt(n), n / 3))]``;
        1 for a constant series.
    """
    n = x.shape[0]
    e = x - x.mean()
    # the length is a ratio of autocovariances, unchanged by the series' scale; beyond
    # 1e50 (or below 1e-50) g(0)^2 (a fourth power) overflows (underflows) float64, which
    # gave NaN (a traceback) or a "constant" series of length 1: such a series is
    # rescaled exactly by a power of 2 first (audit 9, centre: o-scale1e100)
    scale = float(np.max(np.abs(e))) if n else 0.0
    e = rescale_power_of_two(e, scale, bounds=_BLOCK_SCALE_BOUNDS)[0]
    kn = max(5, int(math.log10(n)))
    m_max = int(math.ceil(math.sqrt(n))) + kn
    m_max = min(m_max, n - 1)
    acv = sample_autocovariance(e, m_max)
    if acv[0] <= 0:
        return 1.0
    rho = np.abs(acv / acv[0])
    cv = 2.0 * math.sqrt(math.log10(n) / n)
    m_hat = None
    for lag in range(1, m_max - kn + 2):
        if np.all(rho[lag : lag + kn] < cv):
            m_hat = lag - 1
            break
    m = min(2 * max(m_hat, 1), m_max) if m_hat is not None else m_max
    k = np.arange(1, m + 1)
    lam = np.where(k / m <= 0.5, 1.0, 2.0 * (1.0 - k / m))
    g = 2.0 * np.sum(lam * k * acv[1 : m + 1])
    g0 = acv[0] + 2.0 * np.sum(lam * acv[1 : m + 1])
    d = 4.0 / 3.0 * g0 * g0
    b_max = math.ceil(min(3.0 * math.sqrt(n), n / 3.0))
    if d <= 0:
        return 1.0
    b = (2.0 * g * g / d) ** (1.0 / 3.0) * n ** (1.0 / 3.0)
    return float(min(max(b, 1.0), b_max))


def auto_block_length(*groups: np.ndarray) -> int:
    """Automatic block length of aligned series: the largest Politis-White length.

    Parameters
    ----------
    *groups : numpy.ndarray, each shape (n,) or (n, d)
        Validated float series on the same n rows; every column counts.

    Returns
    -------
    int
        ``ceil`` of the largest :func:`politis_white_length` over all columns, clipped
        to ``[1, n]`` [samples].
    """
    n = groups[0].shape[0]
    b = max(politis_white_length(np.ascontiguousarray(col))
            for g in groups for col in (g.T if g.ndim == 2 else (g,)))
    return max(1, min(int(math.ceil(b)), n))


def optimal_block_length(x: Any, y: Any | None = None) -> int:
    """Automatic block length for the moving-block bootstrap of a series or a pair.

    Parameters
    ----------
    x : array_like, shape (n,)
        Series (n >= 10).
    y : array_like, shape (n,), optional
        Second series of a pair; the larger of the two block lengths is returned.

    Returns
    -------
    int
        Block length [samples] from Politis & White (2004) with the correction of
        Patton, Politis & White (2009), rounded up; between 1 and min(3 sqrt(n), n/3).
        For an AR(1) series with coefficient phi it grows like
        (phi / (1 - phi^2))^(2/3) n^(1/3) (about 100 at phi = 0.95, n = 2000).

    Raises
    ------
    ValueError
        If a series is shorter than 10 samples, not finite, or the lengths differ.
    """
    x = as_float_array(x, "x", ndim=1, min_length=MIN_SAMPLES)
    if y is None:
        return int(math.ceil(politis_white_length(x)))
    y = as_float_array(y, "y", ndim=1, min_length=MIN_SAMPLES)
    if x.shape[0] != y.shape[0]:
        raise ValueError(
            f"`x` and `y` must have the same length; got {x.shape[0]} and {y.shape[0]}."
        )
    return auto_block_length(x, y)


def rank_based_options(options: dict[str, Any]) -> bool:
    """Whether an estimator with these options sees only ranks (the defaults do)."""
    return (options.get("copula", True) is not False
            and options.get("binning", "quantile") != "uniform")


#: Knots per conditioning column of the piecewise-linear fit of :func:`residual_split`
#: (round 50 PART a): at the j / (K + 1) quantiles of the column, so that the fit follows
#: a y that is a non-linear function of z (Y = Z^2, sin 6Z). With the linear fit alone the
#: surrogates broke that dependence and the conditional test rejected I(X; Y | Z) = 0 on
#: Markov chains X -> Z -> Y in 40 of 40 draws (histogram and gaussian, n = 2,000).
RESIDUAL_KNOTS = 15
#: Least samples per column of the fit's design (constant, z and the hinges): the knots
#: per column are cut to keep it (no knots below 40 samples per conditioning column).
_SAMPLES_PER_TERM = 20


def _residual_design(z: np.ndarray, rank_based: bool, knots: int) -> np.ndarray:
    """Design (n, 1 + d_z (1 + K)) of :func:`residual_split`.

    A constant, each z column (normal scores for a rank-based estimator, values
    otherwise) and its hinges ``max(0, s - q_j)`` at the ``j / (K + 1)`` quantiles q_j:
    an additive piecewise-linear fit (de Boor's truncated-power basis of degree 1),
    K = ``knots`` (the conditional test's ``RESIDUAL_KNOTS``) cut so that each term has
    ``_SAMPLES_PER_TERM`` samples (``knots`` = 0: the linear fit).
    """
    from modalinfo.information.copula import copula_scores

    n, d_z = z.shape
    knots = min(knots, max(0, n // (_SAMPLES_PER_TERM * d_z) - 2))
    cols = [np.ones(n)]
    for j in range(d_z):
        s = copula_scores(z[:, j]) if rank_based else z[:, j]
        cols.append(s)
        if knots:
            q = np.unique(np.quantile(s, np.arange(1, knots + 1) / (knots + 1)))
            cols.extend(np.maximum(s - qj, 0.0) for qj in q[q < s.max()])
    return np.column_stack(cols)


def residual_split(y: np.ndarray, z: np.ndarray, rank_based: bool,
                   knots: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(fit, residual) of the columns of y regressed on z and a constant (least squares).

    The parts of a conditional test's surrogate: ``fit + moved residual`` keeps what z
    explains of y and breaks only the rest, so the estimator's conditioning bias (a
    histogram's bins of z leave part of z's effect on x and y) is in the null as in the
    statistic (adversarial round 11). With ``knots`` the fit is additive and piecewise
    linear in each z column (``_residual_design``), so a y that follows z
    non-linearly keeps that dependence too: the conditional test's surrogates of the
    methods other than the histogram (round 50 PART a: with the linear fit, X -> Z -> Y
    with Y = sin 6Z + noise was rejected in 40 of 40 draws by the gaussian test; an
    interaction of two z columns is still outside the fit). The histogram's, the map's
    and the selection's surrogates take :func:`local_linear_split` (fix51-a, -d); the null
    rules keep the linear fit, on which their thresholds were measured. On normal
    scores (of y's columns and z's) for a rank-based estimator, which sees only ranks;
    on the values otherwise. With no
    z, or a column of y with tied values (a discrete y: a residual would break its levels
    apart), the fit is 0 and the residual y itself (the former surrogates).

    Parameters
    ----------
    y : numpy.ndarray, shape (n, d_y)
        The series whose surrogates are made.
    z : numpy.ndarray, shape (n, d_z)
        The conditioning columns (d_z may be 0).
    rank_based : bool
        See :func:`rank_based_options`.
    knots : int
        Hinges per z column (0, the default: the linear fit; the conditional test's
        surrogates use ``RESIDUAL_KNOTS``).
    """
    from modalinfo.information.copula import copula_scores_ties

    if z.shape[1] == 0:
        return np.zeros_like(y), y
    cols = []
    for j in range(y.shape[1]):
        scores, ties = copula_scores_ties(y[:, j])
        if ties:
            return np.zeros_like(y), y
        cols.append(scores if rank_based else y[:, j])
    y_fit = np.column_stack(cols)
    a = _residual_design(z, rank_based, knots)
    fit = a @ np.linalg.lstsq(a, y_fit, rcond=None)[0]
    return fit, y_fit - fit


def _neighbour_space(z: np.ndarray, rank_based: bool) -> np.ndarray:
    """Return the conditioning columns as the neighbour searches see them (maximum norm).

    Normal scores for a rank-based estimator (:func:`rank_based_options`), else the
    values each scaled to unit standard deviation (a constant column unscaled).
    """
    from modalinfo.information.copula import copula_scores

    if rank_based:
        return np.column_stack([copula_scores(np.ascontiguousarray(z[:, j]))
                                for j in range(z.shape[1])])
    sd = z.std(axis=0)
    return z / np.where(sd > 0, sd, 1.0)


#: Neighbours in z over which :func:`local_linear_split` fits the linear residual
#: (fix51-a): measured 10, 20 and 40 on the map's same-frame sine link with the local
#: mean (160 maps each: 10, 14 and 10 false links at 5 %, all within level + 3 s.e.);
#: 20 is the middle, kept for the local-linear fit (fix51-d).
LOCAL_FIT_NEIGHBOURS = 20


def neighbour_rows(z: np.ndarray, rank_based: bool,
                   k: int = LOCAL_FIT_NEIGHBOURS) -> np.ndarray:
    """Each row's ``k`` nearest other rows in z (maximum norm), the row itself left out.

    Parameters
    ----------
    z : numpy.ndarray, shape (n, d_z)
        Conditioning columns, d_z >= 1, n >= 2 (one row has no other row: ValueError).
    rank_based : bool
        Neighbours on normal scores, else on unit-sd values (``_neighbour_space``).
    k : int
        Neighbours per row (cut to n - 1).

    Returns
    -------
    numpy.ndarray of int, shape (n, k')
        Row indices, k' = min(k, n - 1), nearest first; a row tied at distance 0 with
        others keeps them and drops itself.
    """
    from scipy.spatial import cKDTree

    n = z.shape[0]
    if n < 2:
        # no other row to be a neighbour: an empty table made local_linear_split's
        # sums 0 and its solve singular (fix52-c; the public callers refuse < 10 rows)
        raise ValueError(f"`z` needs at least 2 rows for a row's neighbours; got {n}.")
    k = min(k, n - 1)
    zs = _neighbour_space(z, rank_based)
    near = cKDTree(zs).query(zs, k=k + 1, p=np.inf)[1].reshape(n, k + 1)
    own = near == np.arange(n)[:, None]
    own[~own.any(axis=1), -1] = True  # itself beyond k + 1 ties: drop the farthest
    return near[~own].reshape(n, k)


def local_linear_split(y: np.ndarray, z: np.ndarray, rank_based: bool,
                       near: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(fit, residual) of y on z: the linear fit plus a local-linear fit of its residual.

    The parts of the transfer-entropy map's and the selection's rotation surrogates and
    of the histogram conditional test's (fix51-a), ``fit + rotated residual``: the fit
    is y's least-squares fit on z and a constant (:func:`residual_split` on the values)
    plus, at each row, the value of a least-squares line (a constant and z's columns in
    z's values scaled to unit s.d.) through that fit's residual over the row's
    ``LOCAL_FIT_NEIGHBOURS`` (20) nearest other rows in z (a leave-one-out local-linear
    regression), so a y that follows z in any smooth form keeps that link in every
    surrogate while the rotated rest keeps y's own autocorrelation. With the linear fit
    alone a source that follows its target's history non-linearly (``s_t = sin 6 a_t +
    e``) lost that link in the map's null but not in the histogram's bins, and the map
    called s -> a significant in 25 of 160 maps at 5 %; the selection added ``w = z^2 +
    e`` after z in 40 of 40 searches (fix50-e). A local *mean* (fix51-a) left the tails
    of a steep link in the residual (z's extreme rows have one-sided, far-apart
    neighbours: the residual of w = z^2 + 0.3 e had mean square 0.41 against the
    noise's 0.09) and the kde selection still added w; the local line there leaves
    ~0.10 (fix51-d). Where z has more than ``k // 4 - 1`` columns (4 for k = 20) the
    line has too few neighbours per coefficient and the local mean is used.
    On the values even for a rank-based estimator: normal scores of such a y scatter
    about z with a scale that varies with z, which a moved residual cannot keep (the
    selection, scores: 35 of 40 searches still added w; values: 1 of 20). With no z, or
    a y with tied values, the fit is 0 and the residual y (as :func:`residual_split`).

    Parameters
    ----------
    y : numpy.ndarray, shape (n, d_y)
        The series whose surrogates are made.
    z : numpy.ndarray, shape (n, d_z)
        The conditioning columns (d_z may be 0).
    rank_based : bool
        Metric of the neighbours (:func:`neighbour_rows`); the local line's coordinates
        are the values scaled to unit s.d. either way (fix52-c).
    near : numpy.ndarray of int, shape (n, k), optional
        :func:`neighbour_rows` of z, when several y share one z (computed if None;
        k >= 1, so z has at least 2 rows: ValueError otherwise).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        Fit and residual, each shape (n, d_y), in y's units; they sum to y.
    """
    fit, resid = residual_split(y, z, False)
    if z.shape[1] == 0 or resid is y:  # no z, or tied values: y itself is moved
        return fit, resid
    if near is None:
        near = neighbour_rows(z, rank_based)
    n, k = near.shape
    if k < 1:
        raise ValueError("`near` needs at least 1 neighbour per row; got 0 columns.")
    d = z.shape[1] if z.shape[1] <= k // 4 - 1 else 0  # 0: the local mean
    # the line's coordinates are z's values (unit s.d.), as y's, whatever the neighbours'
    # metric: on normal scores a y = z1^2 + z2^2 + 0.3 e left a residual mean square of
    # 0.16-0.21 against the noise's 0.09 (scores bend z's tails, which the line then
    # misses), on the values 0.11-0.12 (fix52-c)
    zs = _neighbour_space(z, False) if d else np.empty((n, 0))
    # sums over the neighbours of (1, dz) (dz = neighbour's z - row's z, so that the
    # line's intercept is its value at the row) and of their products with the
    # residual, one neighbour at a time: memory n (d + 1)^2, not n k d
    a = np.zeros((n, d + 1, d + 1))
    b = np.zeros((n, d + 1, resid.shape[1]))
    u = np.ones((n, d + 1))
    for c in range(k):
        u[:, 1:] = zs[near[:, c]] - zs
        a += u[:, :, None] * u[:, None, :]
        b += u[:, :, None] * resid[near[:, c]][:, None, :]
    if d:
        # a ridge 1e-12 of each row's own neighbour spread only keeps a row whose
        # neighbours share z (ties) solvable; relative, since a heavy-tailed column's
        # unit-s.d. coordinates put most neighbours ~1e-6 apart, where a fixed ridge
        # flattened the line (stop 58's merge)
        spread = np.einsum("nii->n", a[:, 1:, 1:]) / d
        a[:, 1:, 1:] += (1e-12 * spread + 1e-300)[:, None, None] * np.eye(d)
    local = np.linalg.solve(a, b)[:, 0, :]
    return fit + local, resid - local


#: Nearest neighbours in z among which :func:`local_permutation` draws each row (Runge
#: 2018, sec. 3: 5-10; the null's level held for 5 to 10 there).
LOCAL_NEIGHBOURS = 5


def local_permutation(z: np.ndarray, rank_based: bool, rng: np.random.Generator,
                      k: int = LOCAL_NEIGHBOURS) -> np.ndarray:
    """Row order of a local (nearest-neighbour) permutation within z: a conditional null.

    Runge (2018, AISTATS, "Conditional independence testing based on a nearest-neighbor
    estimator of conditional mutual information", sec. 3, Algorithm 1): in a random order
    of the rows, row i takes the row j of one of its ``k`` nearest neighbours in z
    (maximum norm, i itself included) not yet taken, drawn at random, or any of them
    where all are taken. ``y[perm]`` then keeps y's dependence on z whatever its form (the
    neighbours share z up to their small distance) and breaks what x shares with y given
    z: a null of I(X; Y | Z) = 0 for exchangeable (iid) rows. The residual surrogates
    (:func:`residual_split`) keep only what their fit explains: the histogram's
    conditional test on X -> Z -> Y with Y = Z^2 + noise or sin 6Z + noise rejected in
    26 and 40 of 40 draws with them at 5 % (round 50 PART a, O02 / O03).

    Parameters
    ----------
    z : numpy.ndarray, shape (n, d_z)
        Conditioning columns, d_z >= 1.
    rank_based : bool
        Neighbours on the columns' normal scores (:func:`rank_based_options`), else on
        the values each scaled to unit standard deviation.
    rng : numpy.random.Generator
        Randomness of the draws.
    k : int
        Neighbours per row (>= 1; 1 returns the identity).

    Returns
    -------
    numpy.ndarray of int, shape (n,)
        Row indices: a permutation where the draws allow, rows repeated where all of a
        row's neighbours were taken (Runge's algorithm).
    """
    from scipy.spatial import cKDTree

    n = z.shape[0]
    zs = _neighbour_space(z, rank_based)
    k = min(k, n)
    near = cKDTree(zs).query(zs, k=k, p=np.inf)[1].reshape(n, k)
    # the draws: a random order of each row's neighbours, the first one not yet taken
    order = np.argsort(rng.random((n, k)), axis=1)
    near = np.take_along_axis(near, order, axis=1)
    perm = np.empty(n, dtype=np.intp)
    taken = np.zeros(n, dtype=bool)
    for i in rng.permutation(n):
        row = near[i]
        free = row[~taken[row]]
        j = free[0] if free.size else row[0]
        taken[j] = True
        perm[i] = j
    return perm


def resolve_block_length(value: Any, *groups: np.ndarray, name: str = "block_length",
                         maximum: int | None = None) -> int:
    """Parse a block length (or a shift spacing) argument: the one parser of it.

    Parameters
    ----------
    value : None, "auto" or int
        ``None``/``"auto"``: :func:`auto_block_length` of ``groups``, clipped to
        ``maximum``; an int: checked to lie in ``[1, maximum]`` (default maximum: n,
        and a bootstrap block longer than n // 2 is refused: its resamples are nearly
        rotations of the series, the same pairs, and the interval collapses).
    *groups : numpy.ndarray, each shape (n,) or (n, d)
        The validated series the length is for.
    name : str
        Argument name for the error message.
    maximum : int, optional
        Largest admissible length [samples]; default n.

    Returns
    -------
    int
        Block length [samples].

    Raises
    ------
    TypeError
        If ``value`` is neither None, a string nor an int.
    ValueError
        If ``value`` is another string or an int outside ``[1, maximum]``.
    """
    n = groups[0].shape[0]
    top = n if maximum is None else maximum
    if value is None or (isinstance(value, str) and value == "auto"):
        return max(1, min(auto_block_length(*groups), top))
    if isinstance(value, str):
        raise ValueError(f"`{name}` must be None, 'auto' or an int; got {value!r}.")
    value = check_int(value, name, minimum=1, maximum=top)
    if maximum is None and value > n // 2:
        # a circular block of more than half the series: every resample is nearly a
        # rotation of the series, which holds the same pairs, so the bootstrap spread
        # collapses (round 7, a54: block_length = n gave a 95 % interval 1e-16 wide)
        raise ValueError(
            f"`{name}` must be at most half the series ({n // 2} of {n} samples): longer "
            f"circular blocks resample (nearly) the series itself and the interval "
            f"collapses onto the estimate; got {value}.")
    return value


#: Largest fraction of the rows :func:`matched_window` may discard.
MAX_DISCARD = 0.2
#: Largest number of rows it may discard: 20 correlation times of an AR(1) of 0.99 per
#: frame (the slowest telemetry), enough candidates for a match; it bounds the search
#: to ~ 2e6 candidate windows per column however long the series.
MAX_DISCARD_ROWS = 2000


def matched_window(*groups: np.ndarray, max_discard: float = MAX_DISCARD
                   ) -> tuple[int, int]:
    """Rows ``[start, stop)`` whose end points and end slopes match: end-point matching.

    A circular-shift (rotation) test treats a series as a circle; its join of the last
    row to the first must look like any other step, or the rotated series are less
    persistent than the original and the test is liberal. End-point matching
    (Theiler et al., Physica D 58, 77, 1992, sec. 3; Schreiber & Schmitz, Physica D
    142, 346, 2000, sec. 4.1 and TISEAN's ``endtoend``) tests the sub-series whose
    ends match. The mismatch of rows ``[a, b)`` is, summed over the columns,
    ``(v[b-1] - v[a])^2 / s1 + ((v[a+1] - v[a]) - (v[b-1] - v[b-2]))^2 / s2`` with
    ``s1``, ``s2`` the column's mean squared first and second differences: the jump
    and the change of slope across the join, each in units of its typical value
    between consecutive rows (so a typical step scores 1 + 1 per column). Of the
    windows that discard at most ``max_discard`` of the rows (and at most
    ``MAX_DISCARD_ROWS`` = 2000), the longest whose
    mismatch is at most 2 per column (a join no worse than a typical step) is
    returned (of those, the one of least mismatch), else the window of least mismatch.

    Measured (``benchmarks/bench_surrogate_fpr.py``, RESULTS.md; independent AR(1)
    pairs of coefficient 0.99, n = 500, correlation time ~ n / 5, 99 lattice shifts):
    the MI permutation test rejects 0.056 at 0.05 (0.076 without matching) and the
    transfer-entropy map 0.056 (0.069), 1 000 pairs. It keeps 89 % of the rows on
    average there and 98 % at coefficient 0.9. Not a complete cure (3 000 pairs, the
    rotation test of the correlation): with 19 shifts (spacing ~ n / 20: only far
    rotations) the matched test still rejects 0.064 at 0.05 (0.054 with the same 19
    shifts drawn from a spacing of 4 rows): the matched window is a loop whose ends
    are pinned to one level, not a circularly stationary series, and the dense
    lattice's near rotations, which share the original's alignment, mask it. Series
    of at least ~20 correlation times need no matching (RESULTS.md).

    Parameters
    ----------
    *groups : numpy.ndarray, each shape (n,) or (n, d)
        Validated float series on the same n rows; every column counts.
    max_discard : float
        Largest fraction of the rows discarded, in [0, 1).

    Returns
    -------
    (int, int)
        ``start`` and ``stop``: the window ``[start, stop)`` of the rows, at least
        ``n - min(floor(max_discard n), 2000)`` long; ``(0, n)`` for n < 4.
    """
    v = np.column_stack([g.reshape(g.shape[0], -1) for g in groups])
    n = v.shape[0]
    k = min(int(max_discard * n), MAX_DISCARD_ROWS)
    if n < 4 or k == 0:
        return 0, n
    d1 = np.diff(v, axis=0)
    d2 = np.diff(d1, axis=0)
    s1 = np.mean(d1 * d1, axis=0)
    s2 = np.mean(d2 * d2, axis=0)
    w1 = np.divide(1.0, s1, out=np.zeros_like(s1), where=s1 > 0)  # constant column: 0
    w2 = np.divide(1.0, s2, out=np.zeros_like(s2), where=s2 > 0)
    limit = 2.0 * v.shape[1]
    best, best_ab = math.inf, (0, n)
    for d in range(k + 1):  # total discard d = a + (n - b): longest windows first
        a = np.arange(d + 1)
        b = n - d + a
        jump = v[b - 1] - v[a]
        bend = (v[a + 1] - v[a]) - (v[b - 1] - v[b - 2])
        mis = (jump * jump) @ w1 + (bend * bend) @ w2
        i = int(np.argmin(mis))
        if mis[i] <= limit:
            return int(a[i]), int(b[i])
        if mis[i] < best:
            best, best_ab = float(mis[i]), (int(a[i]), int(b[i]))
    return best_ab


def matched_window_for(n_surrogates: int, max_lag: int, spacing: int | None,
                       *groups: np.ndarray, offset: int = 0) -> tuple[int, int]:
    """:func:`matched_window`, or every row where the surrogates would not fit in it.

    Matching must never refuse a test that runs on all the rows: when the
    :func:`surrogate_shifts` lattice of ``n_surrogates`` shifts (``max_lag``,
    ``spacing``) fits in the n - ``offset`` rows of the series but not in the window's
    (a short log, many surrogates), the rows are all kept (the test as without
    matching).

    Parameters
    ----------
    n_surrogates, max_lag : int
        As :func:`surrogate_shifts`.
    spacing : int or None
        As :func:`surrogate_shifts`.
    *groups : numpy.ndarray, each shape (n,) or (n, d)
        The series (as :func:`matched_window`).
    offset : int
        Rows of a window that the test does not use (the lags' start-up) [samples].

    Returns
    -------
    (int, int)
        ``start`` and ``stop`` of the rows to test.
    """
    n = groups[0].shape[0]
    a, b = matched_window(*groups)
    if (a, b) != (0, n):
        try:
            surrogate_shifts(b - a - offset, n_surrogates, max_lag, spacing, 0)
        except ValueError:
            return 0, n
    return a, b


# ------------------------------------------------------------------ bootstrap
#: Most resamples, permutations or surrogates of one call. The Monte Carlo standard error
#: of a p-value p or of an interval's tail level is sqrt(p (1 - p) / N), 0.07 % at
#: p = 0.05 with N = 1e5 (Davison & Hinkley 1997, sec. 4.2.5: 999 suffice for a 1 %
#: test), while each costs one estimate: audit 9's 10^9 permutations ran without end
#: and 10^9 resamples died in a MemoryError (7.3 TiB of indices).
MAX_RESAMPLES = 100_000


def check_resamples(value: Any, name: str, minimum: int) -> int:
    """``value`` as an int in ``[minimum, MAX_RESAMPLES]``; else ValueError/TypeError."""
    value = check_int(value, name, minimum=minimum)
    if value > MAX_RESAMPLES:
        raise ValueError(
            f"`{name}` must be at most {MAX_RESAMPLES:,}: beyond that the Monte Carlo error "
            f"of a p-value or interval bound is below 0.1 % and each one costs an "
            f"estimate (a run of days); got {value:,}.")
    return value


def check_index_memory(n_resamples: int, n: int, name: str = "n_resamples") -> None:
    """Refuse resample indices, ``(n_resamples, n)`` int64, beyond the free memory."""
    need = 8.0 * n_resamples * n
    if need > 2**28 and need > (free := free_memory_bytes()):
        raise ValueError(
            f"`{name}`={n_resamples:,} resamples of {n:,} rows need "
            f"{need / 2**30:.3g} GiB of indices and {free / 2**30:.3g} GiB is free; use "
            f"fewer resamples or rows.")


def block_bootstrap_indices(n: int, block_length: int, n_resamples: int,
                            rng: np.random.Generator, *, circular: bool = False
                            ) -> np.ndarray:
    """Row indices of block-bootstrap resamples of a series of n samples.

    Each resample is ``ceil(n / b)`` blocks of b consecutive indices, concatenated and
    cut to n. Moving blocks (default; Kuensch 1989): a block starts uniformly in
    ``[0, n - b]``, so the first and last b - 1 samples are drawn less often. Circular
    blocks (Politis & Romano 1992): a block starts uniformly in ``[0, n - 1]`` and
    wraps around the end, so every sample is drawn with probability 1 / n per
    position and a resample's mean is unbiased for the series' mean.

    Parameters
    ----------
    n : int
        Samples of the series (>= 1).
    block_length : int
        Block length b in ``[1, n]`` [samples].
    n_resamples : int
        Number of resamples (>= 0).
    rng : numpy.random.Generator
        Randomness; one call ``rng.integers(low, high, size=(n_resamples, ceil(n / b)))``.
    circular : bool
        Circular-block instead of moving-block bootstrap.

    Returns
    -------
    numpy.ndarray of int64, shape (n_resamples, n)
        Indices in ``[0, n - 1]``.
    """
    check_index_memory(n_resamples, n)
    b = int(block_length)
    n_blocks = -(-n // b)
    high = n if circular else n - b + 1
    starts = rng.integers(0, high, size=(n_resamples, n_blocks))
    idx = (starts[:, :, None] + np.arange(b)).reshape(n_resamples, n_blocks * b)[:, :n]
    if circular:
        idx %= n
    return idx


# ----------------------------------------------------------------- surrogates
def _lattice(n: int, spacing: int, max_lag: int) -> np.ndarray:
    """Admissible multiples of ``spacing`` (see :func:`surrogate_shifts`)."""
    k = np.arange(1, (n - spacing) // spacing + 1) * spacing
    d = (2 * k) % n
    return k[np.minimum(d, n - d) >= 2 * (spacing + max_lag)]


def least_surrogate_rows(n_surrogates: int, max_lag: int = 0) -> int:
    """Fewest rows on which :func:`surrogate_shifts` finds ``n_surrogates`` shifts.

    The admissible multiples of a spacing b are a subset of those of b = 1 (its
    condition is stricter), so the shifts fit iff ``_lattice(n, 1, max_lag)`` holds
    ``n_surrogates`` of them. With ``c = 2 (1 + max_lag)`` that count is, in closed form
    (no array: ``--surrogates 1e9`` must not allocate): for odd n, ``2k mod n`` runs over
    1..n-1 once, ``max(0, n - 2c + 1)`` shifts; for even n, each even residue twice and
    0 once, ``max(0, n - 2c + 2)``. Neither falls as n grows, so the least n is
    ``S + 2c - 2`` for even S, ``S + 2c - 1`` for odd S (equal to a search over
    ``_lattice`` for S = 1-59, 99, 199, 999, 2000 at lags 0-30).
    """
    if n_surrogates <= 0:
        return 0
    c = 2 * (1 + max_lag)
    return n_surrogates + 2 * c - 2 + n_surrogates % 2


def surrogate_shifts(n: int, n_surrogates: int, max_lag: int = 0, spacing: int | None = None,
                     seed: Any = None, *, name: str = "n_surrogates"
                     ) -> tuple[np.ndarray, int]:
    """Circular shifts of time-shifted surrogates: points of a lattice, original at 0.

    The shifts are ``n_surrogates`` distinct multiples ``k b`` of a spacing b (drawn
    at random from the admissible ones), so the original (shift 0) and every
    surrogate are at least b apart from each other on the circle of n rows: the
    original is then exchangeable with the surrogates (a randomisation test over the
    subgroup of rotations by multiples of b), and the p-value
    ``(1 + #{surrogate >= original}) / (1 + n_surrogates)`` (:func:`surrogate_pvalue`)
    is exact for circularly stationary series when b divides n and no multiple is
    left out (approximately otherwise: measured rates in ``benchmarks/RESULTS.md``).
    Shifts drawn from ``[m, n - m]`` at random are not: they may lie close to each
    other but never close to the original, which removes from the comparison exactly
    the values most correlated with the original, and the test is liberal by an
    amount that grows with ``m / n`` and with the number of candidates. A spacing
    below the span of the lags plus the series' correlation time costs power (a
    surrogate can re-align a true link at another lag), not validity.

    Multiples k b with ``2 k b`` within ``2 (b + max_lag)`` of a multiple of n are left
    out: there the cells ``j -> i`` and ``i -> j`` of a pair read the same part of the
    two series' cross-correlation (offsets ``k b + l`` and ``-(k b + l')`` equal modulo
    n), become copies, and the surrogate maximum falls below the null's.

    Parameters
    ----------
    n : int
        Rows of the series.
    n_surrogates : int
        Number of shifts >= 0.
    max_lag : int
        Largest source lag [samples] (0 for a test of one aligned pair).
    spacing : int, optional
        Lattice spacing b >= 1 [samples]; default the largest with ``n_surrogates``
        admissible multiples (about ``n / (n_surrogates + 1)``).
    seed : None, int or numpy.random.Generator
        Randomness of the choice among the admissible multiples.
    name : str
        The caller's name of ``n_surrogates``, for the error message.

    Returns
    -------
    shifts : numpy.ndarray of int64, shape (n_surrogates,)
        Ascending shifts in ``[b, n - b]`` [samples].
    spacing : int
        The spacing b used (0 when ``n_surrogates`` is 0).

    Raises
    ------
    ValueError
        If fewer than ``n_surrogates`` admissible multiples exist.
    """
    if n_surrogates == 0:
        return np.empty(0, dtype=np.int64), 0
    rng = check_rng(seed)
    if spacing is None:
        b = max(n // (n_surrogates + 1), 1)
        while b > 1 and _lattice(n, b, max_lag).size < n_surrogates:
            b -= 1
    else:
        b = spacing
    allowed = _lattice(n, b, max_lag)
    if allowed.size == 0 and spacing is None:
        # no shift fits at all: "use fewer surrogates" could not help (a 30-frame log at
        # max_lag 10: adversarial round 10 PART b, row Z30)
        raise ValueError(
            f"`{name}`={n_surrogates}: no circular shift of {n} rows clears lags up to "
            f"{max_lag} (a shift must exceed them at both ends); use more frames.")
    if allowed.size < n_surrogates:
        raise ValueError(
            f"`{name}`={n_surrogates} circular shifts spaced "
            f"{'`min_shift`=' if spacing is not None else ''}{b} apart do not fit in "
            f"{n} rows ({allowed.size} do, lags up to {max_lag}); use fewer surrogates"
            f"{' or a smaller `min_shift`' if spacing is not None else ''}, or more frames.")
    pick = np.sort(rng.choice(allowed.size, size=n_surrogates, replace=False))
    return allowed[pick].astype(np.int64), int(b)


def check_surrogates_reach(n_surrogates: int, alpha: float) -> None:
    """Refuse ``n_surrogates`` whose smallest p-value ``1 / (S + 1)`` exceeds ``alpha``.

    Such a test can never reject (:func:`surrogate_pvalue`): every link or input would
    be reported "not significant" as if that were a finding.

    Raises
    ------
    ValueError
        ``1 / (n_surrogates + 1) > alpha``, naming both and the least count that reaches.
    """
    if 1.0 / (n_surrogates + 1) > alpha:
        least = max(1, math.ceil(1 / alpha) - 1)
        while 1.0 / (least + 1) > alpha:  # 1 / alpha rounded down (alpha one ulp below 1/20)
            least += 1
        p_min = 1 / (n_surrogates + 1)
        # enough digits that the two numbers differ when they print (round 10 PART a)
        digits = next(d for d in (3, 6, 9, 12, 17) if f"{p_min:.{d}g}" != f"{alpha:.{d}g}")
        raise ValueError(
            f"`n_surrogates`={n_surrogates} cannot reach `alpha`={alpha:.{digits}g}: the "
            f"smallest p-value of {n_surrogates} surrogates is 1/{n_surrogates + 1} = "
            f"{p_min:.{digits}g} (a test that can never reject); use "
            f"n_surrogates >= {least}.")


def surrogate_pvalue(statistic: float, null: np.ndarray) -> float:
    """Exact Monte-Carlo p-value ``(1 + #{null >= statistic}) / (1 + S)``.

    Phipson & Smyth, Stat. Appl. Genet. Mol. Biol. 9, 39 (2010): counting the
    original among the S surrogates makes ``P(p <= a) <= a`` when the original is
    exchangeable with the surrogates (with equality at ``a = k / (S + 1)``); the
    smallest p-value is ``1 / (S + 1)``.

    Parameters
    ----------
    statistic : float
        The statistic of the original (larger is more significant).
    null : numpy.ndarray, shape (S,)
        The statistic of each surrogate.

    Returns
    -------
    float
        p-value in ``[1 / (S + 1), 1]``.
    """
    null = np.asarray(null)
    return float((1.0 + np.count_nonzero(null >= statistic)) / (1.0 + null.shape[0]))


class ShuffleNullWarning(UserWarning):
    """A shuffle (iid permutation) null was drawn for autocorrelated series."""


#: lag-1 autocorrelation product above which a shuffle null is said to be liberal:
#: the variance of a cross-correlation grows by (1 + p) / (1 - p) (Bartlett 1935),
#: 1.11 at p = 0.05, which lifts a 5 % chi-square(1) test to ~6.2 %.
SHUFFLE_MAX_LAG1_PRODUCT = 0.05


def _largest_lag1_product(a: np.ndarray, b: np.ndarray) -> float:
    """Largest product of a column's and b column's lag-1 autocorrelations."""
    a = np.asarray(a, dtype=float).reshape(a.shape[0], -1)
    b = np.asarray(b, dtype=float).reshape(b.shape[0], -1)
    ra, rb = lag1_autocorrelations(a), lag1_autocorrelations(b)
    return float(np.max(np.multiply.outer(ra, rb))) if ra.size and rb.size else 0.0


def _iid_rows_broken(a: np.ndarray, b: np.ndarray) -> float | None:
    """Return the largest lag-1 product of (a, b) where it breaks iid rows, else None.

    The one threshold of :func:`shuffle_null_rule` and :func:`iid_bootstrap_rule`:
    above ``SHUFFLE_MAX_LAG1_PRODUCT`` and ``5 / n`` (two iid columns' product has
    standard deviation ~1 / n); fewer than 3 rows are not judged.
    """
    n = a.shape[0]
    if n < 3:
        return None
    p = _largest_lag1_product(a, b)
    return None if p <= max(SHUFFLE_MAX_LAG1_PRODUCT, 5.0 / n) else p


def shuffle_null_rule(a: np.ndarray, b: np.ndarray, name: str) -> str | None:
    """Why a shuffle null of the pair (a, b) is liberal, or None when it holds.

    A random permutation of b is exchangeable with the original only for iid rows; for
    two persistent series the shuffled copies look more independent than the series
    ever can, and the test rejects a true null far above its level (independent
    AR(1) pairs of coefficient 0.9 and n = 500: 57 % at a nominal 5 %; 0.99: 84 %;
    audit 12-tests). Rule: the largest product ``p = r_a r_b`` of the columns' lag-1
    autocorrelations exceeds ``SHUFFLE_MAX_LAG1_PRODUCT`` and ``5 / n`` (the
    product of two iid columns' autocorrelations has standard deviation ~1 / n).

    Parameters
    ----------
    a, b : numpy.ndarray, shape (n,) or (n, k)
        The two series in time order (columns are variables).
    name : str
        The test's name for the message.

    Returns
    -------
    str or None
        The message naming the failed assumption and the cure, or None.
    """
    p = _iid_rows_broken(a, b)
    if p is None:
        return None
    inflation = (1.0 + min(p, 1 - 1e-12)) / (1.0 - min(p, 1 - 1e-12))
    return (f"{name}: the shuffle null assumes iid (exchangeable) rows, but the series are "
            f"autocorrelated (largest product of lag-1 autocorrelations {p:.3f}: the "
            f"null's spread is understated ~{inflation:.3g}x in variance, Bartlett "
            "1935), so the p-value is too small and a true null is rejected far above "
            "its level; use the circular (time-shifted) surrogates for time series.")


def iid_bootstrap_rule(a: np.ndarray, b: np.ndarray, name: str) -> str | None:
    """Why an iid-bootstrap interval of the pair (a, b) undercovers, or None.

    The iid bootstrap resamples rows as exchangeable, as the shuffle null permutes them:
    for two persistent series its replicates vary less than the estimate does, and the
    interval is too narrow (review34: AR(1) 0.99 pairs with innovations of correlation
    0.6, n = 2,000, 16.8 effective pairs: ``bootstrap="iid"`` gave [0.54, 0.63] nats with
    no word, the block bootstrap [0.10, 1.07] with its warning). The rule and threshold
    of :func:`shuffle_null_rule`: the largest product ``p`` of the columns' lag-1
    autocorrelations above ``SHUFFLE_MAX_LAG1_PRODUCT`` (0.05: the variance understated
    ~1.1x, a nominal 95 % interval ~0.94) and ``5 / n``. Sorted samples (a column of a
    or b monotone: a table of counts, groups one after the other) are not judged, as in
    ``convergence.effective_sample_rule``: their order is not time.

    Parameters
    ----------
    a, b : numpy.ndarray, shape (n,) or (n, k)
        The pair in time order (columns are variables).
    name : str
        The function's name for the message.

    Returns
    -------
    str or None
        The message naming the failed assumption and the cure, or None.
    """
    if sorted_samples(a, b):
        return None
    p = _iid_rows_broken(a, b)
    n = a.shape[0]
    if p is None:
        return None
    n_eff = bartlett_pairs(n, p)
    return (f"{name}: bootstrap='iid' resamples the rows as independent, but the series "
            f"are autocorrelated (largest product of lag-1 autocorrelations {p:.3f}: "
            f"{n_eff:.1f} effective pairs of n = {n}, n (1 - p) / (1 + p), Bartlett 1935), "
            f"so the replicates' spread is understated ~{math.sqrt(n / max(n_eff, 1e-300)):.3g}x "
            "and the interval undercovers; use bootstrap='block' (the default) for time "
            "series.")


class RotationNullWarning(UserWarning):
    """A circular-shift null was drawn for series of too few correlation times."""


#: Fewest effective pairs at which the (unconditional) MI rotation null is not said to
#: be liberal (``rotation_null_rule(..., minimum=MI_ROTATION_MIN_EFFECTIVE_PAIRS)``).
MI_ROTATION_MIN_EFFECTIVE_PAIRS = 8.0

#: Fewest effective pairs ``n (1 - p) / (1 + p)`` (Bartlett 1935) at which a conditional
#: rotation null is not said to be liberal: measured (audit 12-tests, 100 draws each, n =
#: 500) 6 % at 5 % with ~65 (AR(1) 0.9), 11 % with ~40 (0.95), 14 % with ~23 (0.99).
ROTATION_MIN_EFFECTIVE_PAIRS = 50.0


def rotation_null_rule(a: np.ndarray, b: np.ndarray, name: str,
                       minimum: float = ROTATION_MIN_EFFECTIVE_PAIRS) -> str | None:
    """Why a circular-shift null of (a, b) is only approximate, or None.

    The rotations are exchangeable with the original only for circularly stationary
    series; when the series span few correlation times the conditional test rejects a
    true null above its level (x = e1 + z, y = e2 + z given z, all AR(1) of coefficient
    0.99, n = 500, ~23 effective pairs: 14 % at a nominal 5 %; 0.95, ~40: 11 %; audit
    12-tests). Rule: fewer than ``ROTATION_MIN_EFFECTIVE_PAIRS`` effective pairs
    ``n (1 - p) / (1 + p)``, p the largest product of the columns' lag-1
    autocorrelations (clipped to [0, 1)).

    Parameters
    ----------
    a, b : numpy.ndarray, shape (n,) or (n, k)
        The series the statistic pairs, in time order (a conditional test: x's and y's
        residuals on z; the transfer-entropy form turns y's innovations, which are
        white, so it holds its level and is not warned).
    name : str
        The test's name for the message.

    Returns
    -------
    str or None
        The message naming the failed assumption and the cure, or None.
    """
    n = a.shape[0]
    p = min(max(_largest_lag1_product(a, b), 0.0), 1.0 - 1e-12)  # for the message
    n_eff = bartlett_pairs(n, p)
    if n_eff >= minimum:
        return None
    return (f"{name}: the series hold {n_eff:.1f} effective pairs of their n = {n} "
            f"(largest product of lag-1 autocorrelations {p:.4f}; n (1 - p) / (1 + p), "
            f"Bartlett 1935), fewer than {minimum:g}: the circular "
            "surrogates assume many correlation times per record and the p-value is "
            "liberal here (measured 11-14 % rejections at a nominal 5 % with 23-40 "
            "effective pairs); use a longer record or difference the series.")


def _nonstationary_columns(a: np.ndarray) -> list[tuple[float, float]]:
    """``(ratio, threshold)`` of every column of ``a`` called non-stationary in scale."""
    a = np.asarray(a, dtype=float).reshape(a.shape[0], -1)
    out = []
    for col in a.T:
        ratio, limit = scale_stationarity(np.ascontiguousarray(col),
                                          PAIR_MIN_STATIONARITY_FRAMES)
        if ratio > limit:
            out.append((ratio, limit))
    return out


def _nonstationary_pair(a: np.ndarray, b: np.ndarray) -> tuple[float, ...] | None:
    """``(ratio_a, limit_a, ratio_b, limit_b)`` where a and b both change scale, or None."""
    bad_a = _nonstationary_columns(a)
    if not bad_a:
        return None
    bad_b = _nonstationary_columns(b)
    if not bad_b:
        return None
    return (*max(bad_a), *max(bad_b))


def stationarity_null_rule(a: np.ndarray, b: np.ndarray, name: str) -> str | None:
    """Why a circular-shift null of (a, b) fails for scales that change in time, or None.

    A rotation is exchangeable with the original only for (circularly) stationary
    series. When both series change scale at the same time (the seeing changed within
    the record), the aligned pair weights its loud stretch alone while the rotations mix
    loud with quiet stretches, whose statistic varies less: the null is too narrow
    (independent AR(1) 0.9 pairs whose innovations' variance steps x4 halfway, n = 500:
    9.5 % rejections of the MI test at a nominal 5 %, 13 % of the conditional test;
    audit 12-tests). Rule: one column of ``a`` and one of ``b`` are both called
    non-stationary by the block-scale rule of the telemetry quality pass
    (``modalinfo._stats.scale_stationarity``: 8 blocks of AR(4) innovations, the
    largest over the smallest 1.4826 MAD above the 99 % range of 8 Gaussian log-scales,
    Harter 1960, Rousseeuw & Croux 1993), judged from 50 effective innovations per
    block (n >= ~420).

    Parameters
    ----------
    a, b : numpy.ndarray, shape (n,) or (n, k)
        The series the statistic pairs, in time order (columns are variables).
    name : str
        The test's name for the message.

    Returns
    -------
    str or None
        The message naming the failed assumption and the cure, or None.
    """
    both = _nonstationary_pair(a, b)
    if both is None:
        return None
    ra, la, rb, lb = both
    return (f"{name}: the circular surrogates assume stationary series, but both change "
            f"scale within the record (largest / smallest robust scale of 8 blocks of "
            f"their AR(4) innovations {ra:.2f} and {rb:.2f}, above the 99 % limits "
            f"{la:.2f} and {lb:.2f}), so the null is too narrow and the p-value liberal "
            "(measured 9.5-13 % rejections at a nominal 5 % on a x4 variance step); test "
            "stretches of steady scale separately, or divide each series by its running "
            "scale first.")


#: Per-series family-wise level at which :func:`level_null_rule` calls a series' mean
#: non-stationary (``modalinfo._stats.LEVEL_ALPHA``); the rule needs both series of the
#: pair, so two independent stationary series are both called so in about 0.01^2 = 1e-4
#: of pairs (5 % per series, 0.25 % of pairs, warned one of the 400 AR(1) 0.9 null pairs
#: of ``tests/information/test_resampling.py``).
LEVEL_PAIR_ALPHA = LEVEL_ALPHA


def level_null_rule(a: np.ndarray, b: np.ndarray, name: str) -> str | None:
    """Why a circular-shift null of (a, b) fails for means that step or drift, or None.

    Two series sharing a trend or a step co-vary when aligned, and the rotations break
    that alignment: the null is too narrow (AR(1) 0.9 pairs sharing a ramp of 3
    innovation sd, n = 500: 7.3 % / 15.0 % rejections of the MI test at 5 % / 10 %;
    leftovers 13-stats). Rule: a column of ``a`` and one of ``b`` both have a mean that
    steps or drifts (``modalinfo._stats.level_steps``, EWC F test of the first cosine
    term against the long-run variance, at :data:`LEVEL_PAIR_ALPHA` per series). Where
    the series span too few correlation times the rule does not judge: a step cannot
    be told from persistence there (the effective-pairs rule speaks instead). Not
    caught: that ramp of 1.3 marginal sd at n = 500 is below the rule's power (warned
    in 6 of 600 draws, leftovers 14-level), so the MI test there rejects 7.3 % at 5 %
    (binomial bound of 600 draws 6.8 %) without a word (leftovers 15-stats, item 4).

    Parameters
    ----------
    a, b : numpy.ndarray, shape (n,) or (n, k)
        The series the statistic pairs, in time order (columns are variables).
    name : str
        The test's name for the message.

    Returns
    -------
    str or None
        The message naming the failed assumption and the cure, or None.
    """
    flagged_a, _ = level_steps(a, LEVEL_PAIR_ALPHA)
    if not flagged_a:
        return None
    flagged_b, _ = level_steps(b, LEVEL_PAIR_ALPHA)
    if not flagged_b:
        return None
    ta = min((t for _, t in flagged_a), key=lambda t: t.p_value)
    tb = min((t for _, t in flagged_b), key=lambda t: t.p_value)
    return (f"{name}: the circular surrogates assume series stationary in level, but the "
            f"means of both step or drift within the record (largest CUSUM excursions at "
            f"samples {ta.frame} and {tb.frame}, EWC F test p = {ta.p_value:.2g} and "
            f"{tb.p_value:.2g}), so the aligned pair shares the change the rotations break "
            "and the p-value is liberal (measured 7.3 % at a nominal 5 % on a shared ramp); "
            "remove the common trend or step (or test the stretches separately) first.")


class BlockBootstrapWarning(UserWarning):
    """A bootstrap interval was drawn where it undercovers.

    The block bootstrap below ~50 effective pairs (:func:`block_bootstrap_rule`), or the
    iid bootstrap on autocorrelated rows (:func:`iid_bootstrap_rule`).
    """


#: Fewest effective pairs ``n (1 - rx ry) / (1 + rx ry)`` (Bartlett 1935) at which a
#: block-bootstrap interval of a pair's MI is not said to undercover: measured (leftovers
#: 12-ci, 95 % "normal" intervals of the Gaussian MI of rho = 0.6 pairs, n = 500, 100
#: draws each) coverage 0.91 with a median of ~57 (AR(1) 0.9), 0.80 with ~31 (0.95),
#: 0.70 with ~11 (0.99); the rotation nulls' threshold
#: (:data:`ROTATION_MIN_EFFECTIVE_PAIRS`), for the same reason: few correlation times.
BOOTSTRAP_MIN_EFFECTIVE_PAIRS = ROTATION_MIN_EFFECTIVE_PAIRS


def block_bootstrap_rule(x: np.ndarray, y: np.ndarray, name: str) -> str | None:
    """Why a moving-block bootstrap interval of the pair (x, y) undercovers, or None.

    The blocks must be long against the correlation time and many in the record
    (Kuensch 1989; Lahiri 2003, ch. 3); a record of few correlation times allows
    neither, and the bootstrap spread understates the estimate's (AR(1) 0.95 pairs, n =
    500: median bootstrap standard deviation 0.085 nats against a true 0.111, coverage
    0.80 of a nominal 0.95; no block length helps: three times Politis-White's, 0.79).
    Rules: fewer than :data:`BOOTSTRAP_MIN_EFFECTIVE_PAIRS` effective pairs
    (``modalinfo.information.convergence.effective_pairs``, Bartlett 1935); or both
    series changing scale within the record (the rule of
    :func:`stationarity_null_rule`), which leaves fewer effective pairs than the
    stationary count says (x4 variance step halfway, AR(1) 0.9: coverage 0.80).

    Parameters
    ----------
    x, y : numpy.ndarray, shape (n,) or (n, k)
        The validated pair in time order (a conditional interval: x's and y's
        residuals on z, the parts whose dependence it measures).
    name : str
        The function's name for the message.

    Returns
    -------
    str or None
        The message naming the failed assumption, or None.
    """
    n = x.shape[0]
    # one column each: effective_pairs(x, y); several: the most persistent pair of
    # columns, as the rotation rule counts them
    n_eff = bartlett_pairs(n, _largest_lag1_product(x, y))
    if n_eff < BOOTSTRAP_MIN_EFFECTIVE_PAIRS:
        return (f"{name}: the pair holds {n_eff:.1f} effective pairs of its n = {n} "
                "(n (1 - rx ry) / (1 + rx ry), rx and ry the lag-1 autocorrelations, "
                "the largest product over the columns, "
                f"Bartlett 1935), fewer than {BOOTSTRAP_MIN_EFFECTIVE_PAIRS:g}: the block "
                "bootstrap needs blocks much longer than the correlation time and many of "
                "them in the record, so its spread understates the estimate's and the "
                "interval undercovers (measured 0.70-0.80 for a nominal 0.95 with 11-31 "
                "effective pairs); use a longer record.")
    both = _nonstationary_pair(x, y)
    if both is None:
        return _heavy_tail_rule(x, y, name)
    ra, la, rb, lb = both
    return (f"{name}: the block bootstrap assumes stationary series, but both change "
            f"scale within the record (largest / smallest robust scale of 8 blocks of "
            f"their AR(4) innovations {ra:.2f} and {rb:.2f}, above the 99 % limits "
            f"{la:.2f} and {lb:.2f}): the loud stretch weighs most and the pair holds "
            "fewer effective samples than its autocorrelation says, so the interval "
            "undercovers (measured 0.80 for a nominal 0.95 on a x4 variance step); "
            "assess stretches of steady scale separately.")


#: Largest finite-sample bias, in bootstrap standard deviations, at which a "normal"
#: bootstrap interval is not said to undercover: a normal interval whose centre is off by
#: 0.5 of its standard deviation covers Phi(1.96 - 0.5) - Phi(-1.96 - 0.5) = 0.921 at a
#: nominal 95 % (the lower edge of the binomial 95 % range of 200 trials). The edge
#: assumes the bootstrap sd is the estimate's sd; where it is larger (x1.4 for the
#: histogram TE at n = 1e3) the rule is conservative, at 1e5 the two agree
#: (``interval_bias_rule``).
INTERVAL_BIAS_SDS = 0.5


def interval_bias_rule(bias: float, sd: float, units: str, name: str,
                       rate: float = 1.0) -> str | None:
    """Why a "normal" bootstrap interval undercovers for its estimator's bias, or None.

    The interval ``estimate -+ z sd`` assumes the estimate centred on its estimand; a
    bias ``b`` shifts it and a 95 % interval covers ``Phi(1.96 - b / sd) - Phi(-1.96 -
    b / sd)``. No resampling interval measures that bias for a binned estimator: the
    block bootstrap's own bias estimate of a histogram CMI is 2-7 times the real one
    (duplicated rows fill cells), so its correction and the basic interval cover less
    (benchmarks/RESULTS.md, leftovers 13-est). ``bias`` is therefore estimated apart,
    from contiguous pieces (``modalinfo.information.convergence.piece_bias``). Above
    :data:`INTERVAL_BIAS_SDS` standard deviations it warns (leftovers 14-misc: the
    histogram TE interval of a VAR(1) covered its binned estimand 0.860 / 0.835 at n =
    1e3 / 1e4, its finite-sample bias 1.5 / 1.0 sd, with no word; the same variables
    drawn iid 0.820 at 1e3: the bias is Miller-Madow's residual at 4.6 samples per
    cell, Paninski 2003, not only the persistence).

    It warns on that VAR(1)'s TE at n = 1e5 (14 bins) too, and rightly by its purpose
    (leftovers 18-stats): the edge is a coverage, 0.921, and there the estimator's real
    bias, +0.0011 nats (mean of 200 trials minus the binned estimand on 2 x 2e6 rows),
    is 0.69 of the bootstrap sd (0.0016, equal to the trials' sd at this n: ratio 1.0,
    against 1.4 at 1e3), so a normal interval covers 0.89, below 0.921; measured 0.915
    on 200 trials and 0.950 on 100 (pooled 278 / 300 = 0.927, 95 % range 0.89-0.95;
    benchmarks/RESULTS.md, leftovers 13-est and 15-stats). The warning's own reading,
    ~1.35x the real bias, decides the same: both are above 0.5 sd.

    Parameters
    ----------
    bias : float
        Estimated bias of the estimate [units].
    sd : float
        The interval's standard deviation (the bootstrap's) [units].
    units : str
        Units of both, for the message.
    name : str
        The function's name for the message.
    rate : float
        Exponent ``a`` of the bias law ``n^-a`` the estimate assumed (for the message).

    Returns
    -------
    str or None
        The message naming the failed assumption, or None.
    """
    if not (np.isfinite(bias) and np.isfinite(sd)) or sd <= 0.0:
        return None
    share = abs(bias) / sd
    if share <= INTERVAL_BIAS_SDS:
        return None
    cover = float(stats.norm.cdf(1.959964 - share) - stats.norm.cdf(-1.959964 - share))
    return (f"{name}: the estimator's finite-sample bias, about {bias:+.3g} {units} (its "
            "estimates on 4 contiguous quarters of the record against the whole, a bias "
            f"~ n^-{rate:g}), is {share:.2g} bootstrap standard deviations; the \"normal\" "
            "interval assumes it small next to its half-width, and no resampling sees it: "
            f"a 95 % interval off by that much covers {cover:.2f} of the estimator's value "
            "at this n and bins (measured coverage 0.86 on a persistent VAR(1), 0.82 on "
            "iid rows, at n = 1e3 and 6 bins per axis: few samples per cell); use a longer "
            "record, fewer `bins`, or method='gaussian' or 'kde'.")


#: False-alarm probability of ``_heavy_tail_rule`` on one Gaussian pair (both series):
#: the quality pass's 1 % (``telemetry.quality.DEFAULT_ALPHA``) warned 2-2.5 % of
#: Gaussian pairs (400 draws), and loops of intervals over many records (coverage
#: studies) warned at least once; 1e-4 still flags every t3 pair at n = 500. Until
#: leftovers 15-stats it was a per-series Bonferroni level that treated the MAD as exact:
#: measured per pair 4.8-4.9 times the stated rate at n = 500, 2.4-3 at 2000-1e4
#: (``heavy_tail_threshold``).
HEAVY_TAIL_ALPHA = 1e-4

# MAD_RELATIVE_SD (1.1662, the relative sd of the normal-consistent MAD of N Gaussian
# values times sqrt(N)) moved to modalinfo._stats, where the union bound uses it too.


def heavy_tail_threshold(n_values: int, n_series: int = 2,
                         alpha: float = HEAVY_TAIL_ALPHA) -> float:
    """Threshold of the heavy-tail rule: P(any of ``n_series`` Gaussian series flags) ~ ``alpha``.

    The rule's statistic on one series of ``T`` Gaussian innovations is ``max_t |e_t -
    median| / s_MAD``. Given the ratio ``s`` of the MAD scale to sigma, the union bound
    over the ``T`` values is ``min(1, T erfc(z / sqrt 2))``, ``z`` for a value inside the
    sample its median and MAD come from (``modalinfo._stats.mad_union_threshold`` with
    ``in_sample=True``: its own pull on both; until leftovers 18-stats the spread
    ``c = sqrt(1 + pi / (2 T))`` of a value outside it: ``k`` 5.554, 5.635, 5.861
    for 5.538, 5.631, 5.860 now at ``T`` = 496, 1996, 9996, a rate ~9 %, 2 % and 0.5 %
    below ``alpha``); ``s`` is averaged over its
    asymptotic normal law, mean 1 and relative sd ``MAD_RELATIVE_SD`` ``/ sqrt(T)``
    (80-node Gauss-Hermite), and the sum over the ``n_series`` series set to ``alpha``
    by bisection. The Bonferroni ``k`` that treats ``s`` as 1 (the rule before leftovers
    15-stats) leaves out the MAD's spread, which a threshold of ~5 sigmas amplifies
    (``exp(k^2 delta)`` for a relative error ``delta``): measured 4.8x the stated rate at
    ``T = 496``, within the binomial range at every ``T`` after (benchmarks/RESULTS.md,
    "left15-stats").

    Parameters
    ----------
    n_values : int
        Innovations per series (``T``), ``>= 2``.
    n_series : int
        Series judged (a pair: 2; columns of x and y).
    alpha : float
        False-alarm probability over the series, in ``(0, 1)``.

    Returns
    -------
    float
        The threshold in robust sigmas.
    """
    t = float(n_values)
    nodes, weights = np.polynomial.hermite_e.hermegauss(80)
    weights = weights / weights.sum()
    s = 1.0 + (MAD_RELATIVE_SD / math.sqrt(t)) * nodes
    keep = s > 0.0
    s, weights = s[keep], weights[keep] / weights[keep].sum()
    return mad_union_threshold(s, weights, n_values, n_series, n_values, alpha, 1.0,
                               2.0 * float(stats.norm.isf(alpha / (2.0 * n_series * t))),
                               in_sample=True)


class OutlierWarning(UserWarning):
    """Series hold values far beyond their Gaussian law (glitches, a heavy tail).

    Warned by the least-squares (``method="gaussian"``) input selection and transfer
    map, whose partial correlations one glitched frame moves (round 53 PART a).
    """


def outlier_columns(series: np.ndarray, alpha: float | None = None, *, min_levels: int = 0
                    ) -> list[tuple[int, int, float, float]]:
    """Columns whose AR(4) innovations reach beyond the heavy-tail rule's threshold.

    The rule of ``_heavy_tail_rule`` (the quality pass's outlier test on the AR(
    ``INNOVATION_ORDER``) innovations, ``modalinfo._stats.stacked_ar_fits``) on every
    column at once: a column is flagged where ``max_t |e_t - median| / (1.4826 MAD)``
    exceeds :func:`heavy_tail_threshold` of its innovations and the columns judged, so
    that a Gaussian (AR) log of any number of columns is flagged with probability
    about ``alpha``. Constant columns and columns whose innovations' MAD is 0 are not
    judged.

    Parameters
    ----------
    series : numpy.ndarray, shape (n, m)
        Finite real series in time order, one per column.
    alpha : float or None
        False-alarm probability over the columns, in ``(0, 1)``; None:
        ``HEAVY_TAIL_ALPHA`` (read at the call).
    min_levels : int
        Columns with fewer distinct values are not judged (a binary or few-level
        series has no Gaussian tail to exceed).

    Returns
    -------
    list of (int, int, float, float)
        ``(column, frame, z, k)`` of each flagged column: its worst innovation's frame
        (row of ``series``), that innovation in robust sigmas and the threshold; empty
        when none is flagged or the series are too short (``n < 4 p + 2``).
    """
    from modalinfo.telemetry.quality import MAD_TO_SIGMA

    x = np.asarray(series, dtype=float)
    x = x.reshape(x.shape[0], -1)
    p = INNOVATION_ORDER
    if x.shape[0] < 4 * p + 2:
        return []
    centred = x - x.mean(axis=0)
    scale = np.max(np.abs(centred), axis=0)
    if min_levels:
        scale[[np.unique(x[:, j]).size < min_levels for j in range(x.shape[1])]] = 0.0
    live = np.flatnonzero(scale > 0.0)
    if live.size == 0:
        return []
    e = stacked_ar_fits(centred[:, live] / scale[live], p, residuals=True)[1]
    dev = np.abs(e - np.median(e, axis=0))
    sigma = MAD_TO_SIGMA * np.median(dev, axis=0)
    k = heavy_tail_threshold(e.shape[0], x.shape[1],
                             HEAVY_TAIL_ALPHA if alpha is None else alpha)
    out = []
    for i in np.flatnonzero(sigma > 0.0):
        t = int(np.argmax(dev[:, i]))
        z = float(dev[t, i] / sigma[i])
        if z > k:
            out.append((int(live[i]), t + p, z, float(k)))
    return out


#: Fewest distinct values of a series :func:`outlier_note` judges: a binary or DAC-level
#: series (a few levels) has no Gaussian tail, and its least-squares scores are refused
#: or judged by the discrete rules (``information.discrete``), not by this one.
OUTLIER_MIN_LEVELS = 32


def outlier_note(series: np.ndarray, labels, caller: str) -> str | None:
    """Why least-squares dependence scores of ``series`` may be spurious, or None.

    One glitched frame shared by a few columns is a leverage point that makes them
    look predictive of each other: four frames glitched by 20 sd in 3 of 40 AR(1) modes
    gave false inputs in 20 of 20 ``select_inputs`` calls (0 of 20 clean) and false
    cells in 10 of 10 transfer maps (1 of 10 clean; round 53 PART a, W57 / W59).

    Parameters
    ----------
    series : numpy.ndarray, shape (n, m)
        The series scored, in time order.
    labels : sequence of str
        Their ``m`` names.
    caller : str
        The function's name, to start the message.
    """
    flagged = outlier_columns(series, min_levels=OUTLIER_MIN_LEVELS)
    if not flagged:
        return None
    return (f"{caller}: {outlier_list(flagged, labels)}. {_LEVERAGE_WORDS}; remove "
            "glitches first (modalinfo.telemetry.apply_outlier_policy, 'clip' or 'drop') "
            "and read the links of these series with care.")


_LEVERAGE_WORDS = (
    "The least-squares (method='gaussian') scores follow such values: a frame glitched "
    "in a few modes makes them look predictive of each other (4 glitched frames gave "
    "false links in every one of 20 selections and 10 maps, round 53 PART a)")

#: Choices of the ``outliers`` keyword of the least-squares selection and map
#: (:func:`clip_glitches`): the shared policy's names (``telemetry.OUTLIER_POLICIES``).
GLITCH_POLICIES = ("clip", "warn")


def clip_glitches(series: np.ndarray, labels, caller: str, policy: str = "clip"
                  ) -> tuple[np.ndarray, str | None]:
    """``series`` with its glitches replaced where the outlier rule flags one, and why.

    Where :func:`outlier_columns` flags a series (the rule of :func:`outlier_note`, at
    ``HEAVY_TAIL_ALPHA`` over the series), ``policy="clip"`` runs the shared outlier
    policy on them all, ``telemetry.apply_outlier_policy(..., "clip", time_series=True)``:
    the quality pass's flagged values are replaced by their AR(4) predictions from the
    frames before them, every other value kept bit for bit. Replacing the values, not
    leaving out the rows whose lag window touches a flagged frame, keeps every lagged
    row and the circular-shift surrogates' rows in step: the surrogates rotate the
    same cleaned series, so the null sees what the statistic sees (rows left out of
    the statistic would come back, shifted, in the null's rotations and bias it).
    Measured (docs/ADVERSARIAL.md, fix54-b): 4 frames glitched by +-20 sd in 3 of 40
    AR(1) modes gave false inputs in 20 of 20 selections and false cells in 10 of 10
    maps as given; after the clip 0 of 20 and 0 of 10 (the clean logs: 0 of 20, 1 of 10).
    A series the rule does not flag is returned as it is (the same object).

    Parameters
    ----------
    series : numpy.ndarray, shape (n, m)
        Finite series in time order.
    labels : sequence of str
        Their ``m`` names (for the message).
    caller : str
        The function's name, to start the message.
    policy : {"clip", "warn"}
        ``"clip"``: replace as above; ``"warn"``: keep the values (round 53's warning).

    Returns
    -------
    series : numpy.ndarray, shape (n, m)
        The series to score.
    why : str or None
        The ``OutlierWarning``'s message (what was flagged and what was done), or None
        where nothing was flagged.
    """
    flagged = outlier_columns(series, min_levels=OUTLIER_MIN_LEVELS)
    if not flagged:
        return series, None
    head = f"{caller}: {outlier_list(flagged, labels)}. {_LEVERAGE_WORDS}"
    if policy == "warn":
        return series, (f"{head}; with outliers='warn' they are scored as given: remove "
                        "glitches first (modalinfo.telemetry.apply_outlier_policy, 'clip') "
                        "or use the default outliers='clip'.")
    from modalinfo.telemetry.log import ModalLog
    from modalinfo.telemetry.quality import apply_outlier_policy

    log, _ = apply_outlier_policy(ModalLog(series), "clip", time_series=True)
    out = np.array(log.coeffs, dtype=float)
    changed = out != series
    n_values, n_frames = int(changed.sum()), int(changed.any(axis=1).sum())
    done = (f"so {n_values} value(s) in {n_frames} frame(s) that the quality pass flags "
            "were replaced by their AR(4) predictions from the frames before them "
            "(modalinfo.telemetry.apply_outlier_policy 'clip', as for the surrogates) "
            "before scoring" if n_values else
            "the quality pass flags no value to replace (a heavy tail rather than "
            "glitches?): the values are scored as given, read these links with care")
    return out, f"{head}; {done}. outliers='warn' keeps the values."


def outlier_list(flagged: list[tuple[int, int, float, float]], labels) -> str:
    """Name the series :func:`outlier_columns` flagged, their worst frames and sigmas.

    ``flagged``: its ``(column, frame, z, k)`` rows (not empty); ``labels``: the
    columns' names. The one wording of :func:`outlier_note` and of ``evaluate``'s test
    frames (fix53-d), the worst (largest ``z / k``) first, at most four shown.
    """
    flagged = sorted(flagged, key=lambda f: -f[2] / f[3])
    shown = ", ".join(f"{labels[c]} ({z:.1f} at frame {t})" for c, t, z, _ in flagged[:4])
    more = f" and {len(flagged) - 4} more" if len(flagged) > 4 else ""
    return (f"{len(flagged)} series hold outliers: AR({INNOVATION_ORDER}) innovations "
            f"beyond {flagged[0][3]:.2f} robust sigmas, which Gaussian series exceed with "
            f"probability {HEAVY_TAIL_ALPHA:g}: {shown}{more}")


def _heavy_tail_rule(x: np.ndarray, y: np.ndarray, name: str) -> str | None:
    """Why a block-bootstrap interval of (x, y) undercovers for heavy tails, or None.

    The bootstrap spread of a statistic whose sampling law rests on fourth moments (the
    correlation behind the MI of a pair) is not consistent when they are infinite
    (Athreya 1987): AR(1) 0.9 pairs with Student t3 innovations, n = 500, covered 0.77
    for a nominal 0.95 (leftovers 12-ci). Rule: :func:`outlier_columns` (the quality
    pass's outlier test on the AR(4) innovations of a column) over the columns of x
    and y, at ``HEAVY_TAIL_ALPHA`` per pair (the MAD's own spread counted). Measured
    (benchmarks/bench_heavy_tail_left15.py, 1e5 pairs of n = 500): Gaussian iid 8e-5,
    AR(1) 0.9 1.0e-4 (the per-series Bonferroni threshold before: 4.8e-4, 4.9e-4); t3
    in both series 400 of 400, in x only 390 of 400 (AR(1) 0.9).
    """
    xs = np.asarray(x, float).reshape(x.shape[0], -1)
    ys = np.asarray(y, float).reshape(y.shape[0], -1)
    flagged = outlier_columns(np.hstack([xs, ys]))
    worst = max(((z, k) for _, _, z, k in flagged), key=lambda w: w[0] / w[1], default=None)
    if worst is None:
        return None
    return (f"{name}: the block bootstrap assumes finite fourth moments, but the series' "
            f"AR({INNOVATION_ORDER}) innovations reach {worst[0]:.1f} robust sigmas, "
            f"beyond the {worst[1]:.2f} that a share {HEAVY_TAIL_ALPHA:g} of Gaussian pairs "
            "exceed: heavy tails make the bootstrap spread inconsistent (Athreya 1987) "
            "and the interval undercovers (measured 0.77 for a nominal 0.95 with t3 "
            "innovations); remove glitches first (the quality pass's outlier policy), "
            "and otherwise read the interval as too narrow.")
