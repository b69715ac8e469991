"""Small statistics shared by subpackages that must not import each other."""

from __future__ import annotations

import functools
import math
from typing import NamedTuple

import numpy as np
from scipy import fft as _fft
from scipy import stats as _scipy_stats

from modalinfo.common.scaling import rescale_power_of_two
from modalinfo.common.validation import (
    as_float_array,
    check_int,
    check_square_floor,
    check_square_range,
)

__all__ = [
    "LevelStepWarning",
    "LevelTest",
    "MAD_RELATIVE_SD",
    "VarianceStep",
    "ar_cosine_transfer",
    "ar_innovations",
    "block_mean_deviations",
    "block_scale_ratio",
    "block_scale_ratios",
    "column_median",
    "column_nanmedian",
    "deviation_memory",
    "lag1_autocorrelation",
    "lag1_autocorrelations",
    "mad_union_threshold",
    "level_stationarity",
    "level_steps",
    "long_memory",
    "mean_difference_variance",
    "fractional_cosine_variances",
    "sample_autocovariance",
    "stacked_ar_fits",
    "stacked_lstsq",
    "range_sf",
    "scale_changes",
    "scale_stationarity",
    "spread_at_split",
    "spread_at_splits",
    "stationarity_threshold",
    "variance_ratio_shift",
    "variance_steps",
]


def sample_autocovariance(x: np.ndarray, n_lags: int) -> np.ndarray:
    """Biased sample autocovariance ``gamma(k) = 1/n sum (x_t - m)(x_{t+k} - m)``, by FFT.

    Parameters
    ----------
    x : array_like, shape (T,)
        Finite real series, T >= 1.
    n_lags : int
        Largest lag ``K``.

    Returns
    -------
    numpy.ndarray, shape (K + 1,)
        ``gamma(0..K)`` (Brockwell & Davis eq. 1.4.4; the biased estimator is positive
        semi-definite, which Yule-Walker and the block-length rule rely on).

    Raises
    ------
    TypeError, ValueError
        If ``x`` is not a finite real 1-D series with a sample, or ``n_lags`` is not an
        int >= 0 (a list raised AttributeError, a (T, M) array was read as one series),
        or ``x`` reaches where its products overflow float64 (about 1e150 / sqrt(T)) or
        varies over less than ``SQUARE_FLOOR`` (6.7e-139), where they underflow.
    """
    x = as_float_array(x, "x", ndim=1, min_length=1)
    n_lags = check_int(n_lags, "n_lags", minimum=0)
    # sums of n products: beyond sqrt(max / 4n) they overflowed (inf, NaN and numpy's
    # RuntimeWarnings at 1e160), below SQUARE_FLOOR they lost digits in subnormals (1e-5
    # at 1e-160); round 40 PART a, L06, L31. The package's callers rescale first.
    check_square_range(x, "x", n_terms=x.shape[0])
    check_square_floor(x, "x", consequence=(
        "its products underflow float64 (the autocovariances would lose digits or read "
        "0)"), task="this analysis")
    xc = x - x.mean()
    n = xc.size
    # zero-padding to >= 2n makes the circular correlation of the FFT a linear one
    nfft = 1 << int(np.ceil(np.log2(2 * n)))
    f = np.fft.rfft(xc, nfft)
    return np.fft.irfft(f * np.conj(f), nfft)[: n_lags + 1] / n


def lag1_autocorrelation(a: np.ndarray) -> float:
    """Lag-1 sample autocorrelation of a 1-D series (mean removed); 0 for a constant.

    The one-series case of :func:`lag1_autocorrelations` (the same arithmetic).

    Parameters
    ----------
    a : numpy.ndarray, shape (n,)
        Finite real series in time order.

    Returns
    -------
    float
        The lag-1 autocorrelation.
    """
    return float(lag1_autocorrelations(np.reshape(a, (np.size(a), 1)))[0])


def lag1_autocorrelations(x: np.ndarray) -> np.ndarray:
    """Lag-1 sample autocorrelation of each column (mean removed); 0 for a constant.

    ``sum (x_t - m)(x_(t+1) - m) / sum (x_t - m)^2`` (the biased estimator of
    Brockwell & Davis eq. 1.4.4, in [-1, 1]), a column whose ``max |x|`` is outside
    float64's safe squares (1e-100 .. 1e100) divided by a power of two first (exact;
    the ratio is scale invariant), so that values near 1e300 do not overflow and values
    far from zero keep every digit of their spread. Vectorised over columns, a slice of
    about ``_STACK_VALUES`` values at a time (one copy of the slice): the one copy of
    this estimator in the package (the evaluation's scale shift, the quality pass's
    spread rules, the shuffle and effective-sample rules; a per-column Python loop
    before, issue 27, left30-twins).

    Parameters
    ----------
    x : array_like, shape (T,) or (T, k)
        Real series in time order (columns are series); a column holding NaN or an
        infinite value gets NaN.

    Returns
    -------
    numpy.ndarray, shape (k,)
        The lag-1 autocorrelation of each column (0 for a constant column or T < 2).

    Raises
    ------
    TypeError, ValueError
        If ``x`` is not real (complex, strings), masked, or not 1-D or 2-D.
    """
    x = as_float_array(x, "x", ndim=(1, 2), finite=False)
    x = x if x.ndim == 2 else x[:, None]
    n, k = x.shape
    out = np.zeros(k)
    per = max(1, _STACK_VALUES // max(1, n))
    if n == 0:
        return out
    for c0 in range(0, k, per):
        block = x[:, c0:c0 + per]
        scale = np.max(np.abs(block), axis=0)
        # by a power of two, and only out of float64's safe squares: dividing by
        # ``max |x|`` itself rounded every value by ~1e-16 of the offset, a unit of the
        # spread of unit noise at 1e16 (lag-1 0.578 for 0.596: round 36 PART a, S1)
        d, _ = rescale_power_of_two(block, np.where(np.isfinite(scale), scale, 0.0))
        d = np.array(d, dtype=float)  # a copy: centred in place below
        # a column holding inf has no autocorrelation: NaN, as for NaN, without numpy's
        # "invalid value encountered" warning of inf - inf (round 32)
        d[:, np.isinf(scale)] = np.nan
        d -= d.mean(axis=0)
        # a second pass removes the mean's own rounding (the corrected two-pass
        # algorithm): numpy sums axis 0 of a C-ordered block row by row, an error of
        # ~1e-11 of the scaled values, which exceeds the scaled spread of a column far
        # from zero (unit noise at 1e12: lag-1 0.94 for white noise; round 35 PART a, S3)
        d -= d.mean(axis=0)
        power = np.einsum("tk,tk->k", d, d)
        lag = np.einsum("tk,tk->k", d[1:], d[:-1])
        zero = (scale == 0.0) | (power <= 0.0)
        out[c0:c0 + per] = np.where(zero, 0.0, lag / np.where(zero, 1.0, power))
    return out


def column_median(a: np.ndarray, keep: np.ndarray | None = None, *,
                  skip_nan: bool = False) -> np.ndarray:
    """Median of each column of ``a`` (shape (n, m)), as ``numpy.median`` / ``nanmedian``.

    One sort of the stack along the rows, then the middle order statistics of each
    column, averaged as ``numpy.median`` averages them (the same values).
    ``numpy.nanmedian(a, axis=0)`` of a tall array runs a Python-level loop over the
    columns (``apply_along_axis``), and ``numpy.median`` partitions along strided
    columns: 4.9 s and 1.2 s for 10^4 x 2000, against 0.6 s for the sort (issue 27,
    left28-quality).

    Parameters
    ----------
    a : numpy.ndarray, shape (n, m)
        Values.
    keep : numpy.ndarray of bool, shape (n, m), optional
        Rows of each column the median is over (default: all).
    skip_nan : bool
        Leave NaN out (``numpy.nanmedian``); otherwise a column holding a NaN among
        its kept rows has median NaN (``numpy.median``).

    Returns
    -------
    numpy.ndarray, shape (m,)
        The medians; NaN for a column with no value kept.
    """
    nan = np.isnan(a)
    if keep is None:
        keep = ~nan if skip_nan else None
    elif skip_nan:
        keep = keep & ~nan
    if keep is None:
        w = np.sort(a, axis=0)  # NaN sorts last
        cnt = np.full(a.shape[1], a.shape[0])
    else:
        w = np.sort(np.where(keep, a, np.inf), axis=0)
        cnt = keep.sum(axis=0)
    if not w.shape[0]:
        return np.full(a.shape[1], np.nan)
    lo = np.take_along_axis(w, (np.maximum(cnt, 1) - 1)[None, :] // 2, axis=0)[0]
    hi = np.take_along_axis(w, np.minimum(cnt // 2, w.shape[0] - 1)[None, :], axis=0)[0]
    with np.errstate(invalid="ignore"):
        out = np.where(cnt > 0, (lo + hi) / 2.0, np.nan)
    if not skip_nan:
        out[(nan if keep is None else nan & keep).any(axis=0)] = np.nan
    return out


def column_nanmedian(a: np.ndarray) -> np.ndarray:
    """Median of each column ignoring NaN, as ``numpy.nanmedian(a, axis=0)``."""
    return column_median(a, skip_nan=True)


#: Values of the stacked design matrices :func:`stacked_lstsq` factorises at once
#: (about 32 MB of float64 with its Q factor beside it).
_STACK_VALUES = 2_000_000


def stacked_lstsq(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Least-squares solutions of a stack of small problems, ``argmin |a[k] c - b[k]|``.

    The ``p x p`` normal equations of every problem at once (batched ``matmul`` and
    ``numpy.linalg.solve``, in slices of about :data:`_STACK_VALUES` values), then two
    steps of iterative refinement on the residual ``b - a c``: the normal equations
    alone lose the square of the condition number, each refinement step wins back a
    factor ``cond^2 eps`` (Bjorck 1996, Numerical Methods for Least Squares Problems,
    sec. 2.9), so the solutions agree with ``numpy.linalg.lstsq`` to within 1e-11
    relative on AR(4) lag matrices of persistent series (a random walk, AR(1) 0.999;
    issue 27, left28-quality). A problem whose normal matrix has a condition number
    beyond 1e12 (a rank-deficient design) goes to ``numpy.linalg.lstsq`` alone (its
    minimum-norm solution). Rows of zeros in ``a`` and ``b`` (left-out observations)
    do not change a solution. One call replaces thousands of ``lstsq`` calls: 6,020 of
    them took 54 s of ``modalinfo info`` on a 10^4 x 2000-mode log (adversarial round
    27 PART b, S01).

    Parameters
    ----------
    a : numpy.ndarray, shape (K, n, p)
        Design matrices, ``n >= p``.
    b : numpy.ndarray, shape (K, n)
        Right-hand sides.

    Returns
    -------
    numpy.ndarray, shape (K, p)
        The solutions.
    """
    k, n, p = a.shape
    out = np.empty((k, p))
    per = max(1, _STACK_VALUES // max(1, n * p))
    for s in range(0, k, per):
        aa, bb = a[s:s + per], b[s:s + per, :, None]
        at = aa.transpose(0, 2, 1)
        gram = at @ aa
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            ok = np.isfinite(gram).all(axis=(1, 2))
            ok[ok] = np.linalg.cond(gram[ok]) < 1e12
        gram[~ok] = np.eye(p)  # solved apart below
        c = np.linalg.solve(gram, at @ bb)
        for _ in range(2):  # iterative refinement on the residual
            c += np.linalg.solve(gram, at @ (bb - aa @ c))
        for i in np.flatnonzero(~ok):
            c[i, :, 0] = np.linalg.lstsq(aa[i], bb[i, :, 0], rcond=None)[0]
        out[s:s + per] = c[..., 0]
    return out

def stacked_ar_fits(x: np.ndarray, p: int, *, step: np.ndarray | None = None,
                    residuals: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
    """Least-squares AR(p) fits with a constant of every column of ``x`` at once.

    Column ``j`` is regressed on its ``p`` previous values and a constant (and, with
    ``step``, a unit step from frame ``step[j]`` on): the design of row ``t`` (``p <= t
    < n``) is ``[x_(t-1), ..., x_(t-p), 1(, t >= step[j])]``. The designs are built a
    slice of columns at a time (about :data:`_STACK_VALUES` values each) and solved by
    :func:`stacked_lstsq`, so the coefficients agree with one ``numpy.linalg.lstsq``
    per column to within about 1e-11 relative. The one copy of this design for the
    innovations of one series (:func:`ar_innovations`), the level rule's fits with a
    step (``_level_tests``) and the forecasts' train / test scale shift
    (``modalinfo.forecast.evaluate``; issue 27, left28-misc: 2,000 ``lstsq`` calls
    replaced).

    Parameters
    ----------
    x : numpy.ndarray, shape (n, k)
        Finite real series in time order, one per column, ``n - p >= p + 1`` (``+ 2``
        with ``step``).
    p : int
        AR order.
    step : numpy.ndarray of int, shape (k,), optional
        First frame of each column's step regressor.
    residuals : bool
        Also return the residuals.

    Returns
    -------
    coef : numpy.ndarray, shape (k, p + 1) or (k, p + 2) with ``step``
        ``a_1 .. a_p``, the constant (in x's units), then the step.
    e : numpy.ndarray, shape (n - p, k), or None
        The residuals ``x_t - design_t coef`` (with ``residuals``), in x's units.
    """
    n, k = x.shape
    width = p + 1 + (step is not None)
    coef = np.empty((k, width))
    e = np.empty((n - p, k)) if residuals else None
    t = np.arange(p, n)
    per = max(1, _STACK_VALUES // max(1, (n - p) * width))  # the designs, a slice at a time
    for s0 in range(0, k, per):
        sub = np.ascontiguousarray(x[:, s0:s0 + per].T)
        # regressor-major (k, width, n - p): each regressor a contiguous copy (the
        # (k, n - p, width) layout wrote every value with a stride, 6x slower)
        design = np.empty((sub.shape[0], width, n - p))
        for i in range(1, p + 1):
            design[:, i - 1] = sub[:, p - i:n - i]
        design[:, p] = 1.0
        if step is not None:
            design[:, p + 1] = t[None, :] >= step[s0:s0 + per, None]
        c = stacked_lstsq(design.transpose(0, 2, 1), sub[:, p:])
        coef[s0:s0 + per] = c
        if e is not None:
            e[:, s0:s0 + per] = (sub[:, p:] - (c[:, None, :] @ design)[:, 0]).T
    return coef, e


# ------------------------------------------------------------- stationarity of scale
#: Contiguous blocks of innovations whose robust scales are compared
#: (:func:`block_scale_ratio`).
STATIONARITY_BLOCKS = 8

#: Fewest effective innovations per block on which the stationarity check judges: the
#: 1.4826 MAD of 100 values has a relative standard error of 1.17 / 10 = 12 %, and the
#: threshold (:func:`stationarity_threshold`) is then x1.81 in scale (x3.3 in variance).
#: Simulated, one mode's ratio of 8 such MADs exceeds it in 0.84 % of draws (1.04 % at
#: 64 values, where the asymptotic law starts to undershoot).
MIN_STATIONARITY_FRAMES = 100

#: Smallest scale ratio called non-stationary, whatever the length: a variance step of
#: x2 and x3.2 (scale x1.4, x1.8) within a log flagged no clean value, x7.4 (x2.7) did
#: (adversarial round 11 PART a, rows q-seeing-*), so a smaller change is not worth a note
#: on a long log where the sampling law alone would call x1.1 significant.
MIN_SCALE_RATIO = 1.5

#: 99th percentile of the range (max - min) of 8 independent standard Gaussian values
#: (studentized range with infinite degrees of freedom, q(0.99; 8, inf) = 4.99: Harter
#: 1960, Ann. Math. Statist. 31, 1122; scipy.stats.studentized_range gives 4.987). It
#: read 5.09 until stop 45, the tables' value for 9 values (q(0.99; 9, inf) = 5.08).
RANGE_99_OF_8 = 4.99

#: Relative standard error of the 1.4826 MAD of n Gaussian values times sqrt(n)
#: (asymptotic efficiency 36.8 %: Rousseeuw & Croux 1993, JASA 88, 1273).
MAD_REL_SD = 1.17

#: Relative standard deviation of the normal-consistent MAD of ``N`` Gaussian values is
#: about ``MAD_RELATIVE_SD / sqrt(N)``: the asymptotic variance of the sample median of
#: ``|Z|`` is ``1 / (4 N g(q)^2)`` with ``q = Phi^-1(3/4)`` and ``g(q) = 2 phi(q)`` the
#: density of ``|Z|`` there, so the relative sd is ``1 / (4 q phi(q) sqrt(N))``: 1.1662
#: (``MAD_REL_SD`` rounds it to 1.17).
MAD_RELATIVE_SD = float(1.0 / (4.0 * _scipy_stats.norm.ppf(0.75)
                               * _scipy_stats.norm.pdf(_scipy_stats.norm.ppf(0.75))))

#: AR order of the innovations the one-series rule (:func:`scale_stationarity`) compares:
#: that of the telemetry quality pass (``modalinfo.telemetry.quality.AR_ORDER``), which
#: whitens a 50 Hz resonance at 2 kHz where an AR(1) fit leaves it (audit 12-tests' AR(2)
#: pairs: 94 % of the AR(1) residuals were called non-stationary, none of the AR(4) ones).
INNOVATION_ORDER = 4


def block_scale_ratio(e: np.ndarray, tested: np.ndarray) -> float:
    """Median over columns of (largest / smallest) 1.4826 MAD of the innovations per block.

    ``e`` (shape (n, m), rows in time order) is split into ``STATIONARITY_BLOCKS``
    contiguous blocks of equal counts; per block and column the scale is the 1.4826 MAD
    about the block's median (the factor cancels in the ratio). NaN when no column is
    ``tested`` (bool, shape (m,)), the blocks hold fewer than 2 rows or a block has a
    zero scale. The median of :func:`block_scale_ratios`' finite values: a caller
    holding ``e`` a slice of columns at a time gathers those and takes their median.
    """
    ratio = block_scale_ratios(e, tested)
    ratio = ratio[np.isfinite(ratio)]
    return float(np.median(ratio)) if ratio.size else math.nan


def block_scale_ratios(e: np.ndarray, tested: np.ndarray) -> np.ndarray:
    """Per ``tested`` column, (largest / smallest) block scale (:func:`block_scale_ratio`).

    Each column's ratio depends on that column alone, so slices of columns give the
    same values as the whole (the quality pass computes its innovations a slice of
    modes at a time, issue 27 left28-prov). Columns in
    ``tested`` order; non-finite where a block's scale is zero or NaN; empty when no
    column is tested or the blocks hold fewer than 2 rows.
    """
    if not tested.any() or e.shape[0] < STATIONARITY_BLOCKS * 2:
        return np.zeros(0)
    sub = e[:, tested]
    scales = []
    for part in np.array_split(sub, STATIONARITY_BLOCKS, axis=0):
        with np.errstate(invalid="ignore"):
            dev = np.abs(part - column_nanmedian(part))
            scales.append(column_nanmedian(dev))
    scales = np.array(scales)
    with np.errstate(invalid="ignore", divide="ignore"):
        return scales.max(axis=0) / scales.min(axis=0)


#: Numbers of contiguous blocks (1/8, 1/16, 1/32 of the log) whose per-mode innovation
#: scales :func:`scale_changes` compares: a change confined to ~5 % of a log fills a
#: block of 1/32 (or half of two) where it dilutes a block of 1/8 to a ratio of 1.2-1.43
#: (adversarial round 28 PART a, N04 / N13 / N14).
SCALE_CHANGE_BLOCKS = (8, 16, 32)

#: Family-wise false-alarm probability of :func:`scale_changes` per log, over the modes
#: and block scales it judges (Bonferroni). A tenth of the 1 % of the median rule
#: (:func:`stationarity_threshold`): a test suite or an archive assesses hundreds of
#: stationary logs, and at 1 % per log the two seeded suites of 60 + 25 stationary AR(1)
#: 0.995 logs of tests/telemetry/test_quality_innovations_left11.py each held one log at
#: the per-mode rule's 1 % tail (largest ratios 1.522 / 1.551, issue 27, left28-shift).
SCALE_CHANGE_ALPHA = 0.001


def range_sf(w: np.ndarray | float, k: int) -> np.ndarray:
    """P(range of ``k`` independent standard Gaussian values > ``w``), elementwise.

    With ``S`` the Gaussian survival function, the smallest value has density
    ``k phi(z) S(z)^(k - 1)`` with the others beyond ``z``, and the range is at most
    ``w`` when all of them lie in ``(z, z + w]``, so
    ``P(R > w) = k int phi(z) S(z)^(k - 1) (1 - (1 - S(z + w) / S(z))^(k - 1)) dz``
    (the studentized range with infinite degrees of freedom: Tukey 1953, Harter 1960,
    as ``scipy.stats.studentized_range.sf(w, k, inf)``); trapezoid rule on ``z`` in
    [-9, 9] at 0.005 (``S(9)`` is 1e-19), the bracket by ``expm1`` / ``log1p`` so a
    tail of 1e-8 keeps its relative precision.
    """
    w = np.asarray(w, dtype=float)
    z = np.linspace(-9.0, 9.0, 3601)
    dz = z[1] - z[0]
    out = np.ones(w.shape)
    # far right the weight underflows to 0 (it is below 1e-300 there); far left the
    # share is 1 and the tail 1: neither is an error (a caller under seterr(all="raise"))
    with np.errstate(under="ignore", divide="ignore"):
        upper = _scipy_stats.norm.sf(z)
        weight = k * _scipy_stats.norm.pdf(z) * upper ** (k - 1)
        for i, wi in enumerate(w.ravel()):
            if wi > 0.0:
                share = _scipy_stats.norm.sf(z + wi) / upper
                tail = -np.expm1((k - 1) * np.log1p(-share))
                out.flat[i] = min(1.0, float(np.sum(weight * tail) * dz))
    return out


#: Relative sampling sd of the mean absolute deviation of ``n`` Gaussian values times
#: ``sqrt(n)``: ``sqrt(var|Z| / (E|Z|)^2) = sqrt(pi / 2 - 1)`` (efficiency 88 %, where the
#: MAD's 1.1662 is 37 %).
MEANAD_REL_SD = math.sqrt(math.pi / 2.0 - 1.0)

#: Deviations beyond this many robust sigmas of the whole column are left out of
#: :func:`block_mean_deviations` (glitches; a Gaussian value is beyond 5 sigma with
#: probability 5.7e-7).
BLOCK_CLIP_SIGMAS = 5.0


def block_clip(e: np.ndarray) -> np.ndarray:
    """:data:`BLOCK_CLIP_SIGMAS` times the 1.4826 MAD of each whole column of ``e``."""
    with np.errstate(invalid="ignore"):
        dev = np.abs(e - column_nanmedian(e))
        return BLOCK_CLIP_SIGMAS * 1.482602218505602 * column_nanmedian(dev)


def block_mean_deviations(e: np.ndarray, blocks: int,
                          clip: np.ndarray | None = None) -> np.ndarray:
    """Mean absolute deviation about the block's median of each column in each block.

    ``e`` (shape (n, m), rows in time order, NaN left out) is split into ``blocks``
    contiguous blocks (``numpy.array_split``); deviations beyond
    :data:`BLOCK_CLIP_SIGMAS` robust sigmas (1.4826 MAD of the whole column) are left
    out (glitches, which the outlier rule reports: clipped there instead, a burst of
    10 frames at 100 sigma still read x1.8 in a block of 1/32 of a 4,000-frame log).
    Returns shape ``(blocks, m)``. Why not the MAD per block: its
    sampling law leans on the density at the quartiles, and a stationary AR(1) 0.995
    log of tests/telemetry (10 x 2,500) had one block of 156 innovations whose MAD fell
    to 0.59 of the others' while its standard deviation was 0.88 (p 1.5e-6 under the
    MAD's law); the mean deviation read 0.85 there. ``clip`` (shape (m,)): the clip
    level, when the caller has it (:func:`block_clip`).
    """
    if clip is None:
        clip = block_clip(e)
    out = []
    for part in np.array_split(e, blocks, axis=0):
        with np.errstate(invalid="ignore"):
            dev = np.abs(part - column_nanmedian(part))
            ok = np.isfinite(dev) & (dev <= clip)
            out.append(np.where(ok, dev, 0.0).sum(axis=0) / np.maximum(ok.sum(axis=0), 1))
    return np.array(out)


def scale_changes(e: np.ndarray, tested: np.ndarray, effective: float,
                  alpha: float = SCALE_CHANGE_ALPHA,
                  blocks: tuple = SCALE_CHANGE_BLOCKS,
                  min_frames: float = MIN_STATIONARITY_FRAMES):
    """Columns whose innovations' scale changes, judged one by one at several block sizes.

    Per block size ``B`` (:data:`SCALE_CHANGE_BLOCKS`) with at least ``min_frames``
    effective innovations per block (``n = effective / B``), each tested column's log
    block scales (:func:`block_mean_deviations`) have, under a stationary Gaussian
    null, a standard deviation of ``MEANAD_REL_SD / sqrt(n)`` (innovations with heavier
    tails: their own relative sd, :func:`block_relative_sd`, where it is larger), so
    their range over that is the range of ``B`` independent standard Gaussians (its
    tail :func:`range_sf`;
    simulated, 1.17 % / 0.135 % beyond its 1 % / 0.1 % points at n = 156, 1.06 % /
    0.115 % at n = 250: slightly liberal per mode, while the Bonferroni over three
    nested block sizes is conservative). A column is flagged when its smallest p value
    over the block sizes is below ``alpha / J`` (Bonferroni, ``J`` = judged block sizes
    x tested columns) and its ratio at that size exceeds ``MIN_SCALE_RATIO``. Unlike the median
    over columns of :func:`block_scale_ratio`, one column changing alone (a
    wind-direction change exchanging two modes' spectra) is seen, and so is a change
    confined to a 32nd of the log.

    Parameters
    ----------
    e : numpy.ndarray, shape (n_rows, m)
        Innovations in time order (NaN left out of each block).
    tested : numpy.ndarray of bool, shape (m,)
        Columns judged.
    effective : float
        Effective independent innovations of the whole log.
    alpha : float
        Family-wise false-alarm probability over the judged columns and block sizes.
    blocks : tuple of int
        Block counts compared.
    min_frames : float
        Fewest effective innovations per block at which a block size is judged.

    Returns
    -------
    tuple
        ``([(column, blocks, ratio, block, p_value), ...], judged)``: flagged columns
        (``block`` the index of the block whose scale is farthest from the median of
        the blocks', ``ratio`` largest over smallest block scale) and the number of
        judged (block size, column) pairs, ``J``.
    """
    cols = np.flatnonzero(np.asarray(tested, dtype=bool))
    return judge_scale_changes(block_scale_table(e[:, cols], blocks), cols, e.shape[0],
                               effective, alpha, min_frames)


#: Key of :func:`block_scale_table`'s per-column relative sd of the deviations (shape
#: (1, m)), beside its integer block counts.
REL_SD_KEY = "rel_sd"


def block_relative_sd(e: np.ndarray, blocks: int, clip: np.ndarray) -> np.ndarray:
    """Relative sd of the absolute deviations of each column, ``sqrt(n)`` x that of their mean.

    The deviations about each block's median (the ``blocks`` contiguous blocks of
    :func:`block_mean_deviations`, those beyond ``clip`` left out) divided by their
    block's mean, pooled over the blocks: ``sd(|e| / E|e|)``, which is
    :data:`MEANAD_REL_SD` for Gaussian innovations, 1 for Laplace (an exponential
    ``|e|``) and larger for heavier tails. Normalised per block, so a change of scale
    between blocks (what the rule looks for) does not widen it. Returns shape (m,).
    """
    count = np.zeros(e.shape[1])
    total = np.zeros(e.shape[1])
    squares = np.zeros(e.shape[1])
    # sums, not nanstd: no all-NaN warning to silence (the quality pass must not enter
    # warnings.catch_warnings, round 9)
    for part in np.array_split(e, blocks, axis=0):
        with np.errstate(invalid="ignore", divide="ignore"):
            dev = np.abs(part - column_nanmedian(part))
            ok = np.isfinite(dev) & (dev <= clip)
            n_ok = ok.sum(axis=0)
            mean = np.where(ok, dev, 0.0).sum(axis=0) / np.maximum(n_ok, 1)
            ok &= mean > 0.0
            r = np.where(ok, dev / np.where(mean > 0.0, mean, 1.0), 0.0)
        count += ok.sum(axis=0)
        total += r.sum(axis=0)
        squares += (r * r).sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        var = (squares - total * total / count) / (count - 1.0)
    return np.sqrt(np.where(count > 1.0, np.maximum(var, 0.0), np.nan))


def block_scale_table(e: np.ndarray, blocks: tuple = SCALE_CHANGE_BLOCKS) -> dict:
    """Block scales of each column of ``e`` at each block count, for :func:`scale_changes`.

    ``{B: block_mean_deviations(e, B)}`` (shape (B, m)) for the counts ``B`` of
    ``blocks`` with at least two rows per block, and under :data:`REL_SD_KEY` the
    columns' :func:`block_relative_sd` at the largest such count (shape (1, m)). Per
    column, so a caller holding a slice of the columns at a time (the quality pass)
    gathers the tables along axis 1 and judges them once with
    :func:`judge_scale_changes`.
    """
    if e.shape[1] == 0:
        return {}
    clip = block_clip(e)
    table: dict = {b: block_mean_deviations(e, b, clip) for b in blocks
                   if e.shape[0] >= 2 * b}
    if table:
        table[REL_SD_KEY] = block_relative_sd(e, max(table), clip)[None, :]
    return table


def judge_scale_changes(table: dict, cols: np.ndarray, n_rows: int, effective: float,
                        alpha: float = SCALE_CHANGE_ALPHA,
                        min_frames: float = MIN_STATIONARITY_FRAMES):
    """Judge the columns of a :func:`block_scale_table` as :func:`scale_changes` does.

    ``cols``: the column index of each column of the table's arrays; ``n_rows``: the
    innovations the table was made from. Returns what :func:`scale_changes` does.
    """
    sizes = [b for b in table if b != REL_SD_KEY and effective / b >= min_frames
             and n_rows >= 2 * b]
    if not sizes or not len(cols):
        return [], 0
    # the sampling sd of a log block scale is rel_sd / sqrt(n): the Gaussian value, or
    # the innovations' own where their tails are heavier (adversarial round 30 PART a:
    # AR(1) logs with Laplace innovations, 2,000 x 20, were named in 8 of 100 at the
    # stated 0.1 %, Student-t3 in 2 of 100)
    rel_sd = np.full(len(cols), MEANAD_REL_SD)
    if REL_SD_KEY in table:
        with np.errstate(invalid="ignore"):
            rel_sd = np.fmax(rel_sd, np.asarray(table[REL_SD_KEY], dtype=float)[0])
    best: dict = {}
    judged = 0
    for b in sizes:
        sc = table[b]
        with np.errstate(divide="ignore", invalid="ignore"):
            logs = np.log(sc)  # a block of zero scale (a quantised mode): not judged
            ok = np.isfinite(logs).all(axis=0)
            judged += int(ok.sum())
            if not ok.any():
                continue
            spread = rel_sd / math.sqrt(effective / b)
            rng_ = logs.max(axis=0) - logs.min(axis=0)
            far = np.argmax(np.abs(logs - np.median(logs, axis=0)), axis=0)
        p = np.ones(len(cols))
        p[ok] = range_sf(rng_[ok] / spread[ok], b)
        for i in np.flatnonzero(ok):
            if cols[i] not in best or p[i] < best[cols[i]][3]:
                best[cols[i]] = (b, float(math.exp(rng_[i])), int(far[i]), float(p[i]))
    if not judged:
        return [], 0
    cut = alpha / judged
    found = [(int(j), b, ratio, block, pv) for j, (b, ratio, block, pv) in sorted(best.items())
             if pv < cut and ratio > MIN_SCALE_RATIO]
    return found, judged


def block_run(logs: np.ndarray, far: int) -> tuple[int, int]:
    """Return ``(first, last)``: the contiguous blocks around ``far`` on its side.

    ``logs``: one column's log block scales in time order; the side is that of the
    midpoint of their largest and smallest. For an episode the run is its blocks; for
    a step it is the half the far block lies in, where the far block alone (any block
    of either half: they are equally far from the median) named frames 2504-5004 for a
    change at frame 10,000 (adversarial round 30 PART b, Q03). Blocks of zero scale
    (``-inf``) end the run.
    """
    logs = np.asarray(logs, dtype=float)
    finite = logs[np.isfinite(logs)]
    if not finite.size or not np.isfinite(logs[far]):
        return far, far
    mid = 0.5 * (finite.max() + finite.min())
    high = logs[far] > mid
    same = np.isfinite(logs) & ((logs > mid) == high)
    first = far
    while first > 0 and same[first - 1]:
        first -= 1
    last = far
    while last + 1 < logs.size and same[last + 1]:
        last += 1
    return first, last


def stationarity_threshold(block_frames: float,
                           min_frames: float = MIN_STATIONARITY_FRAMES) -> float:
    """Block-scale ratio above which innovations are called non-stationary.

    The log of a 1.4826 MAD of ``n`` Gaussian values has a standard deviation of about
    ``1.17 / sqrt(n)`` (Rousseeuw & Croux 1993); the range of 8 such independent
    log-scales exceeds ``4.99`` of them with probability 1 % (studentized range, Harter
    1960): ``max(MIN_SCALE_RATIO, exp(4.99 x 1.17 / sqrt(n)))``.

    Parameters
    ----------
    block_frames : float
        Effective innovations per block.
    min_frames : float
        Fewest effective innovations per block judged (default
        ``MIN_STATIONARITY_FRAMES``).

    Returns
    -------
    float
        The threshold (> 1); ``inf`` below ``min_frames``.
    """
    if not block_frames >= min_frames:
        return math.inf
    return max(MIN_SCALE_RATIO, math.exp(RANGE_99_OF_8 * MAD_REL_SD / math.sqrt(block_frames)))


#: Fewest effective innovations per block at which :func:`scale_stationarity` judges
#: one series of a *pair* whose two series must both fail (the tests' rule,
#: ``modalinfo.information.resampling.stationarity_null_rule``): 62 at n = 500. One
#: stationary series is called non-stationary in 0.5-2.8 % of draws there (audit 12-tests'
#: iid, AR(1) 0.9-0.999, t3, trend, int16 kinds, 400 draws each), two at once in none.
PAIR_MIN_STATIONARITY_FRAMES = 50


def scale_stationarity(x: np.ndarray,
                       min_frames: float = MIN_STATIONARITY_FRAMES) -> tuple[float, float]:
    """Block-scale ratio of one series' AR innovations and its non-stationarity threshold.

    The innovations ``e`` of a least-squares AR(:data:`INNOVATION_ORDER`) fit (close to
    white where the levels of a persistent series are not) go to
    :func:`block_scale_ratio`; the threshold is :func:`stationarity_threshold` of their
    effective count per block, ``(n - p) (1 - r) / (1 + r) / STATIONARITY_BLOCKS``, ``r``
    the lag-1 autocorrelation of ``e`` clipped to [0, 0.999] (Bartlett 1946).

    Parameters
    ----------
    x : numpy.ndarray, shape (n,)
        Finite real series in time order.
    min_frames : float
        Fewest effective innovations per block judged.

    Returns
    -------
    tuple of float
        ``(ratio, threshold)``: non-stationary where ``ratio > threshold``; the threshold
        is ``inf`` (not judged) for a short or constant series.
    """
    p = INNOVATION_ORDER
    n = x.shape[0]
    if n < STATIONARITY_BLOCKS * 2 + 2 * p:
        return math.nan, math.inf
    scale = float(np.max(np.abs(x - x.mean())))
    if scale == 0.0:
        return math.nan, math.inf
    e = ar_innovations((x - x.mean()) / scale, p)
    r = min(max(lag1_autocorrelation(e), 0.0), 0.999)
    ratio = block_scale_ratio(e[:, None], np.array([True]))
    block = (n - p) * (1.0 - r) / (1.0 + r) / STATIONARITY_BLOCKS
    return ratio, stationarity_threshold(block, min_frames)


def ar_innovations(x: np.ndarray, p: int = INNOVATION_ORDER) -> np.ndarray:
    """Least-squares AR(p) innovations (with a constant) of one series.

    Close to white where the levels of a persistent series are not: the scale rule
    (:func:`scale_stationarity`) and the heavy-tail rule of the block bootstrap
    (``modalinfo.information.resampling.block_bootstrap_rule``) judge these.

    Parameters
    ----------
    x : numpy.ndarray, shape (n,)
        Finite real series in time order, ``n > 2 p``.
    p : int
        AR order.

    Returns
    -------
    numpy.ndarray, shape (n - p,)
        The residuals ``x_t - (c + sum_i a_i x_(t-i))``, in x's units.
    """
    return stacked_ar_fits(np.asarray(x, dtype=float)[:, None], p, residuals=True)[1][:, 0]


# ------------------------------------------------- train-vs-test scale (forecasts)
#: Family-wise false-alarm probability of :func:`variance_ratio_shift` over the modes it
#: judges (Bonferroni: each mode's two-sided test at ``SHIFT_ALPHA / m``).
SHIFT_ALPHA = 0.01

#: Smallest ratio of innovation mean squares (test / training, or its inverse) called a
#: shift, whatever the length: a scale change of x1.2 moves the coverage of a 95 %
#: Gaussian interval to ``2 Phi(1.96 / 1.2) - 1 = 0.897`` (or, calmer, 0.991); on long
#: logs the F law alone would call x1.02 significant, which no interval notices.
SHIFT_MIN_RATIO = 1.44

#: Fewest innovations per segment (training rows after the ``p`` lags, test frames) on
#: which the train-vs-test scale rule of ``modalinfo.forecast.evaluate`` judges.
MIN_SHIFT_INNOVATIONS = 200

#: Fewest effective training values ``n (1 - r) / (1 + r)`` (``r`` the lag-1
#: autocorrelation of the training values, Bartlett 1946) on which that rule judges: a
#: training segment spanning few correlation times leaves the fitted constant and AR
#: coefficients so uncertain that the out-of-sample mean square spreads wider than the
#: F law (measured, AR(1), 6 modes, 200 seeds, half the log trained: 0.9 at 200 frames
#: (5 effective) warned on 16 logs, 0.99 at 400 frames (1) on 36; 0.9 at 400 (10.5) on 2).
MIN_SHIFT_EFFECTIVE = 10

#: Smallest change of a mode's mean between the training and test frames, in units of
#: the training frames' standard deviation, that the train-vs-test level rule of
#: ``modalinfo.forecast.evaluate`` calls a shift, whatever its significance: a shift of
#: half an sd is what a level change of the log is (round 52 PART a, L05 / L45: +3 sd and
#: +1 sd over 80 % of the test frames, 2.4 and 0.8 sd), and stationary long memory (fGn
#: H 0.9, whose half-log means differ by 0.29 sd rms at 10,000 frames a half, beyond the
#: lag-1 count's sampling error) crosses it in ~8 % of modes (fix53-a, docs/ADVERSARIAL.md).
LEVEL_SHIFT_MIN_SD = 0.5


def variance_ratio_shift(ratio: np.ndarray, dof_test: np.ndarray, dof_train: np.ndarray,
                         kurtosis: np.ndarray, alpha: float = SHIFT_ALPHA,
                         min_ratio: float = SHIFT_MIN_RATIO
                         ) -> tuple[np.ndarray, np.ndarray]:
    """Two-sided F test of a ratio of mean squares per column, Bonferroni over columns.

    Under the null (the same white Gaussian innovations in both segments) the ratio of
    the test segment's mean square to the training segment's unbiased residual variance
    follows ``F(dof_test, dof_train)``. For non-Gaussian innovations the variance of a
    mean square of ``n`` values is ``(kappa - 1) sigma^4 / n`` instead of ``2 sigma^4 /
    n`` (``kappa`` the kurtosis), so each degree of freedom is scaled by ``2 / (kappa -
    1)`` (Box & Andersen 1955, J. R. Statist. Soc. B 17, 1: the moment-matched F);
    ``kappa`` is taken at least 3 (never more sensitive than the Gaussian law).

    Parameters
    ----------
    ratio : numpy.ndarray, shape (m,)
        Ratios (test / training); NaN where not judged.
    dof_test, dof_train : numpy.ndarray, shape (m,)
        Degrees of freedom of the numerator and denominator.
    kurtosis : numpy.ndarray, shape (m,)
        Pooled kurtosis ``E e^4 / (E e^2)^2`` of the innovations (3 for Gaussian).
    alpha : float
        Family-wise false-alarm probability over the judged (finite) columns.
    min_ratio : float
        Smallest ratio (or inverse ratio) flagged.

    Returns
    -------
    pvalue : numpy.ndarray, shape (m,)
        Two-sided p-values ``2 min(F.cdf, F.sf)`` (NaN where not judged).
    shifted : numpy.ndarray of bool, shape (m,)
        ``pvalue < alpha / (judged columns)`` and ``max(ratio, 1 / ratio) >= min_ratio``.
    """
    ratio = np.asarray(ratio, dtype=float)
    judged = np.isfinite(ratio) & (ratio > 0)
    pvalue = np.full(ratio.shape, np.nan)
    shifted = np.zeros(ratio.shape, dtype=bool)
    if not judged.any():
        return pvalue, shifted
    shrink = 2.0 / (np.maximum(np.asarray(kurtosis, dtype=float), 3.0) - 1.0)
    d1 = np.asarray(dof_test, dtype=float) * shrink
    d2 = np.asarray(dof_train, dtype=float) * shrink
    r = ratio[judged]
    tail = np.minimum(_scipy_stats.f.cdf(r, d1[judged], d2[judged]),
                      _scipy_stats.f.sf(r, d1[judged], d2[judged]))
    pvalue[judged] = np.minimum(1.0, 2.0 * tail)
    big = np.maximum(r, 1.0 / r) >= min_ratio
    shifted[judged] = (pvalue[judged] < alpha / judged.sum()) & big
    return pvalue, shifted


def ar_cosine_transfer(a: np.ndarray, n: int,
                       j: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """AR polynomial ``A(z) = 1 + sum_k a_k z^-k`` at the cosine frequencies ``pi j / n``.

    The AR(p) spectrum of a record of ``n`` frames at the DCT-II / EWC frequencies
    ``pi j / n`` is ``f(pi j / n) = sigma^2 / (2 pi |A(exp(-i pi j / n))|^2)``. One copy
    for the two rules that read it: the Diebold-Mariano test's number of cosine terms
    (``modalinfo.forecast.evaluate._dm_terms``) and :func:`level_stationarity`.

    Parameters
    ----------
    a : numpy.ndarray, shape (p,)
        Coefficients of ``A`` (``x_t + sum_k a_k x_(t-k) = e_t``: the negated
        regression coefficients); ``p = 0`` gives ``A = 1``.
    n : int
        Record length (frames) setting the frequency grid.
    j : numpy.ndarray of int, shape (m,)
        Frequency indices.

    Returns
    -------
    transfer : numpy.ndarray of complex, shape (m,)
        ``A(exp(-i pi j / n))``.
    phase : numpy.ndarray of complex, shape (m, p)
        ``exp(-i pi j k / n)``, ``k = 1..p`` (the derivative of ``transfer`` in ``a``).
    """
    a = np.asarray(a, dtype=float)
    lags = np.arange(1, a.size + 1)
    phase = np.exp(-1j * np.pi * np.outer(j, lags) / n)
    return 1.0 + phase @ a, phase


# ------------------------------------------------------------- stationarity of level
#: Relative flatness of the fitted AR spectrum over the cosine terms
#: :func:`level_stationarity` pools: every term's ``f(pi j / n)`` is at least this share of
#: the first's. Measured (AR(1) 0.99, n = 10^4, 1500 draws): 0.8 gave 5.9 % false alarms
#: at 5 % and 1.9 % at 1 %, 0.9 gave 4.6 % and 0.9 % (issue 27, left14-level).
LEVEL_FLATNESS = 0.9

#: Fewest cosine terms ``B`` of the long-run variance: below, the record spans too few
#: correlation times for a level step to be told from persistence, and the rule says so
#: instead of judging (F(1, B) critical values grow fast: 16.3 at B = 6, 1 %; with 4
#: terms the plug-in spectrum's error gave 8.1 % false alarms at 5 %, AR(1) 0.9, n = 500).
LEVEL_MIN_TERMS = 6

#: Most cosine terms pooled (power saturates: F(1, 40) at 1 % is 7.3, F(1, inf) 6.6).
LEVEL_MAX_TERMS = 40

#: Fewest frames the level rule judges (the AR(4) fit with a constant and a step).
MIN_LEVEL_FRAMES = 64

#: Family-wise false-alarm probability of :func:`level_steps` over the columns it judges.
LEVEL_ALPHA = 0.01


# ------------------------------------------------------------- long memory (fix54-a)
#: Grid of the memory parameter ``d`` (``H - 1/2``) on which :func:`long_memory` reads
#: the local Whittle objective: stationary long memory, ``0 <= d < 1/2`` (a negative
#: estimate is read as 0: the rules are never made more liberal than the short-memory
#: law they had).
MEMORY_GRID = np.round(np.arange(0.0, 0.4901, 0.01), 4)

#: Standard errors of the local Whittle estimate added to ``d`` before it is used: the
#: plug-in ``d`` is estimated from the very terms it rescales and from the series less
#: its largest CUSUM step (which takes some of a stationary series' low-frequency power
#: with it), so it reads low; two s.e. (each ``1 / (2 sqrt(m))``, Robinson 1995) brought the
#: level rule to its stated rate on fGn H 0.7 / 0.9 and ARFIMA d 0.4 (fix54-a,
#: docs/ADVERSARIAL.md "Long memory in the stationarity rules").
MEMORY_MARGIN_SE = 2.0

#: The same margin for the spread rule's reading of its absolute deviations
#: (:func:`variance_steps`, whose ``d`` is also capped by :func:`deviation_memory` of the
#: series' own estimate): none. Measured (fix56-a, fGn H 0.9, 300 series of 20,000
#: frames, a x2 spread step on 30 logs): margin 0 (both readings) named 1 of 300 at
#: p < 1 % and the step in 30 of 30, margin 2 0 of 300 and 26 of 30.
DEVIATION_MEMORY_MARGIN_SE = 0.0

#: Most cosine terms the long-memory estimate reads (:func:`long_memory`): more than the
#: level rule's :data:`LEVEL_MAX_TERMS`, since ``d`` is extrapolated from them to the
#: first term and its error grows as the band narrows.
MEMORY_MAX_TERMS = 400

#: The band of the long-memory estimate: the terms over which the AR(p) spectrum stays
#: within this share of ``f(pi / n)`` (its shape is divided out; it is trusted less far).
MEMORY_FLATNESS = 0.5


#: Quadrature points of :func:`fractional_cosine_variances` taken at once.
_QUADRATURE_CHUNK = 4096


@functools.lru_cache(maxsize=1)
def fractional_cosine_variances() -> np.ndarray:
    """Variances of a record's mean and cosine terms under a fractional spectrum.

    For a spectral density ``f(lambda) = G |lambda|^(-2d)`` near 0 and a record of
    ``n`` frames, the orthonormal DCT-II term ``L_j`` (:func:`level_stationarity`) and
    ``sqrt(n)`` times the mean (``j = 0``) have, as ``n`` grows, variances
    ``G (pi / n)^(-2d) v_j(d)`` with ``v_j(d) = int |u|^(-2d) |Phi_j(u)|^2 du / pi^(-2d)``,
    ``Phi_j`` the Fourier transform of ``sqrt(2) cos(pi j s)`` on ``[0, 1]`` (``1`` for
    ``j = 0``): ``|Phi_j(u)|^2 = 4 (1 - (-1)^j cos u) u^2 / (pi^2 j^2 - u^2)^2``
    (the low-frequency cosine transforms of Mueller & Watson 2008, Econometrica 76,
    979, their covariance under ``I(d)``). At ``d = 0`` every ``v_j`` is ``2 pi``
    (white cosine terms, the EWC law); at ``d = 0.4`` ``v_2 / v_1 = 0.66`` where the
    power law ``j^(-2d)`` gives 0.57 (the first term carries less than the law's
    extrapolation). The terms' correlations (a few per cent at ``d = 0.4``) are left out.
    Computed once (midpoint rule to ``u = 600``, step 0.01, its tail and the mean's
    ``u^(-2d)`` pole at 0 in closed form).

    Returns
    -------
    numpy.ndarray, shape (len(MEMORY_GRID), MEMORY_MAX_TERMS + 2)
        ``v_j(d) / v_1(d)``, rows :data:`MEMORY_GRID`, columns ``j = 0 .. MEMORY_MAX_TERMS
        + 1`` (from ``j = LEVEL_MAX_TERMS + 2`` on, the power law ``2 pi (pi j)^(-2d)``).
    """
    du, top, eps = 0.01, 600.0, 0.05
    u_all = np.arange(eps + du / 2, top, du)
    j = np.arange(0, LEVEL_MAX_TERMS + 2)[:, None]
    sign = np.where(j % 2 == 0, 1.0, -1.0)
    a = np.pi * j
    d = MEMORY_GRID[None, :]
    # the 60,000 quadrature points a few thousand at a time: the whole (terms x points)
    # array was a 23 MiB temporary at the first level rule of a command, after its memory
    # check (tests/cli/test_memory_refusal_figure_round50.py, stop 61 merge)
    total = np.zeros((j.shape[0], d.shape[1]))
    for s0 in range(0, u_all.size, _QUADRATURE_CHUNK):
        u = u_all[s0:s0 + _QUADRATURE_CHUNK]
        with np.errstate(divide="ignore", invalid="ignore"):
            g = 4.0 * (1.0 - sign * np.cos(u)) * u * u / (a * a - u * u) ** 2
        g[~np.isfinite(g)] = 0.5  # the removable singularity at u = pi j (j >= 1): 1/2
        g[0] = 2.0 * (1.0 - np.cos(u)) / (u * u)  # j = 0: |(1 - e^{-iu}) / (iu)|^2
        total += g @ np.exp(-2.0 * np.log(u)[:, None] * d)
    # [0, eps]: |Phi_j|^2 ~ 1 for the mean (its u^(-2d) pole, closed form), ~u^2 else
    head = np.where(j == 0, eps ** (1.0 - 2.0 * d) / (1.0 - 2.0 * d), 0.0)
    # beyond top: |Phi_j|^2 averages 2 / u^2 (the mean) or 4 / u^2 over its oscillation
    tail = np.where(j == 0, 2.0, 4.0) * top ** (-1.0 - 2.0 * d) / (1.0 + 2.0 * d)
    v = 2.0 * (total * du + head + tail)  # (j, d)
    # the quadrature's own error taken out where it is known: every v_j(0) is 2 pi
    # (MEMORY_GRID[0] = 0), so the short-memory law is exactly the EWC's
    v *= 2.0 * np.pi / v[:, :1]
    # beyond: the power law itself, 2 pi (pi j)^(-2d) (within 0.5 % from j = 41 on)
    far = np.arange(LEVEL_MAX_TERMS + 2, MEMORY_MAX_TERMS + 2)[:, None]
    v = np.vstack([v, 2.0 * np.pi * (np.pi * far) ** (-2.0 * d)])
    return (v / v[1]).T


class LongMemory(NamedTuple):
    """What :func:`long_memory` read from a series' low-frequency cosine terms.

    ``d`` the memory parameter used (the local Whittle estimate plus
    :data:`MEMORY_MARGIN_SE` standard errors, within :data:`MEMORY_GRID`), ``estimate``
    the estimate itself, ``scale`` the variance of the first cosine term ``L_1`` that
    the terms imply under ``d`` (in the terms' units), ``terms`` how many were used.
    """

    d: float
    estimate: float
    scale: float
    terms: int


def long_memory(power: np.ndarray, margin_se: float = MEMORY_MARGIN_SE) -> LongMemory:
    """Local Whittle estimate of long memory from cosine terms ``j = 2 .. m + 1``.

    ``power[j - 1]`` is ``L_j^2`` whitened by the short-memory (AR) spectrum's shape
    (``L_j^2 f(pi / n) / f(pi j / n)``), ``j = 1 .. m + 1``; under a fractional
    law its mean is ``G v_j(d)`` (:func:`fractional_cosine_variances`). ``d`` minimises
    the local Whittle objective ``log(mean_j power_j / v_j(d)) + mean_j log v_j(d)``
    (Robinson 1995, Ann. Statist. 23, 1630; with the cosine terms' exact shape in place
    of ``j^(-2d)``) over :data:`MEMORY_GRID`, on ``j >= 2``: the first term is the one
    a level step loads and that the rules judge, so it does not set the law it is
    judged against. Standard error ``1 / (2 sqrt(m))`` (Robinson 1995); the ``d`` used
    is the estimate plus :data:`MEMORY_MARGIN_SE` of them, at most the grid's top.
    The one reading of long memory of the stationarity rules: the level rule
    (:func:`level_stationarity`) and the forecasts' train / test level rule
    (``modalinfo.forecast.evaluate._level_shift``, by :func:`mean_difference_variance`).

    Parameters
    ----------
    power : numpy.ndarray, shape (m + 1,)
        Whitened squared cosine terms ``j = 1 .. m + 1``, ``m >= 2``.
    margin_se : float
        Standard errors added to the estimate (:data:`MEMORY_MARGIN_SE`; the spread
        rule's :data:`DEVIATION_MEMORY_MARGIN_SE`).

    Returns
    -------
    LongMemory
        ``(d, estimate, scale, terms)``; ``scale = mean_j power_j / (v_j(d) / v_1(d))``
        over ``j >= 2``, the variance of ``L_1`` under ``d``.
    """
    power = np.asarray(power, dtype=float)
    m = power.size - 1
    table = fractional_cosine_variances()[:, 2:m + 2]
    objective = (np.log(np.mean(power[None, 1:] / table, axis=1))
                 + np.mean(np.log(table), axis=1))
    i = int(np.argmin(objective))
    top = MEMORY_GRID.size - 1
    se = 0.5 / math.sqrt(m)
    used = min(top, int(round(i + margin_se * se / 0.01)))
    scale = float(np.mean(power[1:] / fractional_cosine_variances()[used, 2:m + 2]))
    return LongMemory(float(MEMORY_GRID[used]), float(MEMORY_GRID[i]), scale, m)


def _memory_row(d: float) -> int:
    """Row of :data:`MEMORY_GRID` (and :func:`fractional_cosine_variances`) of ``d``."""
    return int(np.argmin(np.abs(MEMORY_GRID - d)))


def mean_difference_variance(d: float, before: int, after: int,
                             record: int | None = None) -> float:
    """Variance of ``mean(after segment) - mean(before segment)`` under long memory.

    Two adjacent segments of ``a = before`` and ``b = after`` frames of a series whose
    partial sums grow as ``var(S_k) = K k^(1 + 2d)`` (fractional: Beran 1994,
    "Statistics for Long-Memory Processes", ch. 2 and 8; ``d = 0`` the short-memory
    ``K k``); ``cov(S_a, S'_b) = K ((a + b)^(1+2d) - a^(1+2d) - b^(1+2d)) / 2``, so
    ``var = K (a^(2d-1) + b^(2d-1) - ((a + b)^(1+2d) - a^(1+2d) - b^(1+2d)) / (a b))``.
    ``K`` is tied to the variance ``V`` of the first cosine term of a record of ``N``
    frames (what :func:`long_memory` and the level rule's ``scale`` measure):
    ``var(S_N) / N = V v_0(d) / v_1(d)`` (:func:`fractional_cosine_variances`), so
    ``K = V v_0(d) / v_1(d) N^(-2d)``.

    Parameters
    ----------
    d : float
        Memory parameter, on :data:`MEMORY_GRID`.
    before, after : int
        Frames of the two segments.
    record : int, optional
        Frames ``N`` of the record ``V`` is measured on (default: the first segment).

    Returns
    -------
    float
        The variance in units of ``V`` (multiply by the record's ``scale``).
    """
    i = _memory_row(d)
    a, b = float(before), float(after)
    big_n = a if record is None else float(record)
    e = 1.0 + 2.0 * d
    # scaled by N to keep the powers of large counts in range
    a, b = a / big_n, b / big_n
    shape = a ** (e - 2.0) + b ** (e - 2.0) - ((a + b) ** e - a ** e - b ** e) / (a * b)
    return float(fractional_cosine_variances()[i, 0] * shape / big_n)


def deviation_memory(d: np.ndarray | float) -> np.ndarray:
    """Memory parameter of a Gaussian series' absolute (or squared) deviations.

    For a stationary Gaussian series of memory ``d`` (autocorrelation ``rho(k) ~ c
    k^(2d - 1)``) and a function ``G`` of Hermite rank 2 (``|x - mu|``, ``(x - mu)^2``:
    even about the mean), ``cov(G(X_0), G(X_k)) = sum_(q >= 2) J_q^2 rho(k)^q / q!``
    (the Hermite expansion; Taqqu 1975, Z. Wahrsch. 31, 287; Beran 1994, "Statistics
    for Long-Memory Processes", sec. 3.3), led by ``J_2^2 rho(k)^2 / 2 ~ k^(4d - 2)``:
    the memory parameter ``d_y`` of ``G(X)`` (``k^(2 d_y - 1)``) is ``2d - 1/2`` where
    ``4d - 2 > -1`` (``d > 1/4``); for ``d <= 1/4`` the covariances are summable (short
    memory, ``d_y = 0``). fGn H 0.9 (``d = 0.4``): ``d_y = 0.3``; H 0.7: 0. The law the
    spread rule (:func:`variance_steps`) judges the absolute deviations under; checked
    against exact fGn / ARFIMA draws (tests/telemetry/test_long_memory_rules_fix56a.py).

    Parameters
    ----------
    d : float or numpy.ndarray
        Memory parameter(s) of the series, ``0 <= d < 1/2`` (NaN: not read, taken as 0).

    Returns
    -------
    numpy.ndarray
        ``max(2 d - 1/2, 0)``, same shape as ``d``.
    """
    d = np.nan_to_num(np.asarray(d, dtype=float), nan=0.0)
    return np.maximum(2.0 * d - 0.5, 0.0)


class LevelStepWarning(UserWarning):
    """The mean of a series steps or drifts within the record (not stationary in level)."""


class LevelTest(NamedTuple):
    """What :func:`level_stationarity` found.

    ``p_value`` is NaN when the rule did not judge (``terms < LEVEL_MIN_TERMS``: too few
    correlation times in the record, or too short or constant a series); ``frame`` is the
    first frame after the largest CUSUM excursion (the least-squares step location),
    ``shift`` the mean after it minus the mean before it (the series' units), ``terms``
    the cosine terms ``B`` of the long-run variance, ``memory`` the long-memory ``d``
    the terms were rescaled by (:func:`long_memory`; 0: short memory), ``memory_estimate``
    the local Whittle estimate before its margin (NaN: not read).
    """

    p_value: float
    terms: int
    frame: int
    shift: float
    memory: float = 0.0
    memory_estimate: float = math.nan

    @property
    def judged(self) -> bool:
        """True when the rule judged (enough correlation times in the record)."""
        return math.isfinite(self.p_value)


def level_stationarity(x: np.ndarray, p: int = INNOVATION_ORDER) -> LevelTest:
    """Test a series' mean for a step or a trend against stationary persistence.

    The orthonormal DCT-II terms ``L_j = sqrt(2 / n) sum_t x_t cos(pi j (t + 1/2) / n)``
    of a stationary series are, for small ``j``, close to independent Gaussians of
    variance ``2 pi f(pi j / n)`` (``f`` the spectral density): the equal-weighted cosine
    (EWC) long-run variance with ``B`` terms (Mueller 2007; Sun 2013, Econometrics J. 16,
    1) is then ``sigma^2 chi^2_B / B``, and ``F = L_1^2 / (sum_{j=2}^{B+1} L_j^2 / B)``
    follows F(1, B) exactly (fixed-b, Kiefer & Vogelsang 2005). A step in the mean puts
    ``|L_1| ~ |shift| sqrt(2 n) sin(pi tau) / pi`` (tau its place in the record), a
    ramp most of its power there too, so F is large. ``B`` is the largest number of terms
    over which the AR(``p``) spectrum fitted with a constant and a step at the CUSUM
    location (so that the step is not read as persistence) stays within
    :data:`LEVEL_FLATNESS` of ``f(pi / n)``, capped at :data:`LEVEL_MAX_TERMS`; each
    ``L_j^2`` of the denominator is rescaled by ``f(pi / n) / f(pi j / n)`` for what
    curvature remains. With fewer than :data:`LEVEL_MIN_TERMS` the record spans too few
    correlation times for a step to be told from persistence: not judged.

    **Long memory** (fix54-a). An AR(``p``) spectrum flattens below its slowest root;
    fractional noise keeps rising as ``lambda^(-2d)`` down to ``pi / n``, so the first
    term outweighs the others by ``v_1(d) / v_j(d)`` (``~ j^(2d)``) and the F law above
    named 34 % of stationary fGn H 0.9 series of 10^4 frames at p < 1 %. Each term of
    the denominator is therefore also divided by its share ``v_j(d) / v_1(d)`` of the
    fractional law (:func:`fractional_cosine_variances`), ``d`` read by
    :func:`long_memory` (local Whittle, plus :data:`MEMORY_MARGIN_SE` standard errors)
    from the AR-whitened cosine terms of the series less its least-squares step at the
    CUSUM location and a linear trend (so that the event judged is not read as memory)
    over the band where the AR shape stays within :data:`MEMORY_FLATNESS` of ``f(pi /
    n)`` (up to :data:`MEMORY_MAX_TERMS` terms). The price: a short-memory series reads
    ``d`` of about two standard errors, which widens its test (AR(1) 0.99 + 1 sd at 60 %
    of 10^4 frames: named at p < 1 % in 45 of 300, 114 before; docs/ADVERSARIAL.md
    "Long memory in the stationarity rules (fix54-a)").

    Measured false alarms (issue 27, left14-level; benchmarks/RESULTS.md): AR(1) 0.5,
    0.9, 0.99 at n = 500-10^4 within the binomial bounds of 5 % and 1 % where judged
    (AR(1) 0.99 is judged from n ~ 2000-5000); with the long-memory reading 0-0.3 % at
    1 % (conservative), fGn H 0.7 / 0.9 and ARFIMA d 0.2 / 0.4 0.3-2 % at 1 % and 0 of
    300 at 0.1 % (10^4 frames; fix54-a).

    Parameters
    ----------
    x : numpy.ndarray, shape (n,)
        Finite real series in time order.
    p : int
        Order of the AR fit that sets ``B``.

    Returns
    -------
    LevelTest
        ``(p_value, terms, frame, shift, memory)``; ``p_value`` NaN when not judged.
    """
    return _level_tests(np.asarray(x, dtype=float).reshape(-1, 1), p)[0]


class LowFrequency(NamedTuple):
    """One column's low-frequency cosine terms as the level rules read them.

    ``first`` the first cosine term ``L_1`` and ``scale`` its variance under the column's
    law, in units of ``unit`` (the column's largest absolute deviation from its mean)
    and its square, so that no square of the data is formed (a log scaled by 2^600,
    issue 27, left11): the mean of the whitened terms ``j = 2 .. terms + 1`` each over
    its share ``v_j(d) / v_1(d)`` of the fractional law (:func:`long_memory`);
    ``frame`` / ``shift`` the largest CUSUM excursion's step.
    """

    frame: int
    shift: float
    terms: int
    first: float
    scale: float
    memory: LongMemory | None
    unit: float = 1.0


def _low_frequency(x: np.ndarray, p: int = INNOVATION_ORDER, *,
                   long_memory_law: bool = True,
                   memory: np.ndarray | None = None) -> list[LowFrequency | None]:
    """:class:`LowFrequency` of every column of ``x`` (shape (n, k)) at once (None: constant).

    ``memory`` (shape (k,)): the most ``d`` each column is judged under (on
    :data:`MEMORY_GRID`): :func:`long_memory`'s reading (with
    :data:`DEVIATION_MEMORY_MARGIN_SE`), at most this (the spread rule:
    :func:`deviation_memory` of its series' own ``d``).

    The AR fits with a constant and a step are one :func:`stacked_lstsq`, the cosine
    terms one DCT along the columns (per-column ``lstsq`` and DCT took 4.8 s for 4000
    columns of 10^4 frames, issue 27, left28-quality). ``terms`` below
    :data:`LEVEL_MIN_TERMS` (or a non-finite AR spectrum): ``first`` and ``scale`` NaN.
    """
    n, k = x.shape
    out: list[LowFrequency | None] = [None] * k
    mu = x.mean(axis=0)
    scale = np.max(np.abs(x - mu), axis=0)
    live = np.flatnonzero((scale > 0.0) & np.isfinite(scale))
    if not live.size:
        return out
    xc = (x[:, live] - mu[live]) / scale[live]
    cusum = np.cumsum(xc, axis=0)[:-1]
    frames = np.argmax(np.abs(cusum), axis=0) + 1
    # the least-squares step at the CUSUM location (after minus before, xc's units) and
    # its cosine terms, closed form: sum_{t >= f} cos(pi j (t + 1/2) / n) =
    # -sin(pi j f / n) / (2 sin(pi j / 2n)); the series less it sets the long memory
    before = cusum[frames - 1, np.arange(live.size)]
    del cusum
    wide = min(MEMORY_MAX_TERMS, (n - 1) // 2) + 1
    jj = np.arange(1, wide + 1)[:, None]
    step_cos = (-math.sqrt(2.0 / n) * np.sin(np.pi * jj * frames[None, :] / n)
                / (2.0 * np.sin(np.pi * jj / (2.0 * n))))
    ramp = np.arange(n) - (n - 1) / 2.0
    ramp_cos = _fft.dct(ramp, type=2, norm="ortho")[1:wide + 1, None]
    fr = frames.astype(float)
    # least squares on [step, ramp] (centred): Gram matrix and right-hand sides
    g_ss, g_sr, g_rr = fr * (n - fr) / n, (n - fr) * fr / 2.0, n * (n * n - 1.0) / 12.0
    b_s, b_r = -before, ramp @ xc
    det = g_ss * g_rr - g_sr * g_sr
    beta_s = (g_rr * b_s - g_sr * b_r) / det
    beta_r = (g_ss * b_r - g_sr * b_s) / det
    shifts = [float(x[f:, j].mean() - x[:f, j].mean()) for f, j in zip(frames, live, strict=True)]
    coef = stacked_ar_fits(xc, p, step=frames)[0][:, :p]
    phase = ar_cosine_transfer(np.zeros(p), n, np.arange(1, wide + 1))[1]
    transfer = 1.0 - phase @ coef.T  # A(z) of the negated coefficients, per column
    with np.errstate(divide="ignore"):
        f = 1.0 / np.abs(transfer) ** 2
    cos = _fft.dct(xc, type=2, norm="ortho", axis=0)[1:wide + 1]
    for c_idx, j in enumerate(live):
        fj = f[:, c_idx]
        flat = fj[:LEVEL_MAX_TERMS + 1] / fj[0] >= LEVEL_FLATNESS
        terms = LEVEL_MAX_TERMS if flat.all() else int(np.argmin(flat)) - 1
        terms = min(terms, (n - 1) // 2)
        near = fj / fj[0] >= MEMORY_FLATNESS
        band = max(terms, fj.size - 1 if near.all() else int(np.argmin(near)) - 1)
        frame, shift = int(frames[c_idx]), shifts[c_idx]
        if terms < LEVEL_MIN_TERMS or not math.isfinite(fj[0]):
            out[j] = LowFrequency(frame, shift, max(terms, 0), math.nan, math.nan, None,
                                  float(scale[j]))
            continue
        c = cos[:band + 1, c_idx]
        white = fj[0] / fj[:band + 1]
        # long memory: each term's variance relative to the first's under the d read
        # from the series less its step (fix54-a: the AR(p) shape alone flattens below
        # its own memory, where fractional noise keeps rising as lambda^(-2d))
        rest = (c - beta_s[c_idx] * step_cos[:band + 1, c_idx]
                - beta_r[c_idx] * ramp_cos[:band + 1, 0])
        if long_memory_law:
            # a capped reading is the spread rule's (its own margin, see the constant)
            memory_j = long_memory(rest ** 2 * white, MEMORY_MARGIN_SE if memory is None
                                   else DEVIATION_MEMORY_MARGIN_SE)
            if memory is not None and memory_j.d > memory[j]:
                memory_j = memory_j._replace(
                    d=float(MEMORY_GRID[_memory_row(float(memory[j]))]), scale=math.nan)
        else:
            memory_j = LongMemory(0.0, math.nan, math.nan, band)
        shape = fractional_cosine_variances()[_memory_row(memory_j.d), 2:terms + 2]
        var_first = float(np.mean(c[1:terms + 1] ** 2 * white[1:terms + 1] / shape))
        out[j] = LowFrequency(frame, shift, terms, float(c[0]), var_first, memory_j,
                              float(scale[j]))
    return out


def _level_tests(x: np.ndarray, p: int = INNOVATION_ORDER, *,
                 long_memory_law: bool = True,
                 memory: np.ndarray | None = None) -> list[LevelTest]:
    """:func:`level_stationarity` of every column of ``x`` (shape (n, k)) at once.

    The columns' :class:`LowFrequency` at once and the F tails one call (per-column
    ``f.sf`` among the 4.8 s of 4000 columns of 10^4 frames, issue 27, left28-quality).
    """
    n, k = x.shape
    if n < MIN_LEVEL_FRAMES:
        return [LevelTest(math.nan, 0, 0, math.nan)] * k
    out = [LevelTest(math.nan, 0, 0, 0.0)] * k
    stat, dof, where = [], [], []
    for j, low in enumerate(_low_frequency(x, p, long_memory_law=long_memory_law,
                                           memory=memory)):
        if low is None:
            continue
        d = low.memory.d if low.memory is not None else 0.0
        est = low.memory.estimate if low.memory is not None else math.nan
        out[j] = LevelTest(math.nan, low.terms, low.frame, low.shift, d, est)
        if low.scale > 0.0:  # NaN (not judged) fails too
            stat.append(low.first ** 2 / low.scale)
            dof.append(low.terms)
            where.append(j)
    if where:
        pv = _scipy_stats.f.sf(np.array(stat), 1, np.array(dof))
        for j, pj in zip(where, pv, strict=True):
            out[j] = out[j]._replace(p_value=float(pj))
    return out


def level_steps(x: np.ndarray, alpha: float = LEVEL_ALPHA,
                skip: np.ndarray | None = None, *,
                long_memory_law: bool = True, memory: np.ndarray | None = None,
                memory_out: np.ndarray | None = None
                ) -> tuple[list[tuple[int, LevelTest]], int]:
    """Columns whose mean steps or drifts, by :func:`level_stationarity` with Bonferroni.

    Parameters
    ----------
    x : numpy.ndarray, shape (n,) or (n, k)
        Finite real series in time order (columns are series).
    alpha : float
        Family-wise false-alarm probability: a column is flagged at ``p < alpha / K``,
        ``K`` the columns tested (not skipped), judged or not. Bonferroni over the
        judged columns alone is not a bound: whether a column is judged (``B >= 6``)
        depends on the AR fit with a step at the CUSUM location, which absorbs the
        very fluctuation ``L_1`` measures, so where few columns are judged the judged
        ones are those a chance swing made look flat and their ``p`` is liberal
        (AR(1) 0.995, 8,000 frames: 11.5 % of 4,000 columns judged, 5.3 % of them at
        ``p < 0.01``; 5 of 200 stationary 10-mode logs flagged at 1 %); the
        unconditional ``P(judged and p < t)`` stays below ``t`` (0.6 % at 1 % there),
        so the union over the ``K`` tested columns is bounded by ``alpha`` (issue 27,
        left29-falarm).
    skip : numpy.ndarray of bool, shape (k,), optional
        Columns not tested (e.g. constant modes).
    long_memory_law : bool
        Judge each column against its long memory (:func:`long_memory`, the default);
        False: the short-memory law alone (every ``v_j`` equal).
    memory : numpy.ndarray, shape (k,), optional
        The most ``d`` each column is judged under (its :func:`long_memory` reading,
        at most this; the spread rule, :func:`variance_steps`: :func:`deviation_memory`
        of the series' own ``d``).
    memory_out : numpy.ndarray of float, shape (k,), optional
        Filled with each judged column's local Whittle estimate of ``d`` before its
        margin (``LevelTest.memory_estimate``), NaN where a column was skipped, not
        judged or read on the short-memory law: what the spread rule caps its law by
        (``telemetry.quality``: one long-memory estimate per mode).

    Returns
    -------
    tuple
        ``([(column, LevelTest), ...] flagged, J)``, ``J`` the columns judged;
        ``J = 0``: no column spans enough correlation times for a step to be told from
        persistence.
    """
    x = np.asarray(x, dtype=float).reshape(np.shape(x)[0], -1)
    cols = np.arange(x.shape[1]) if skip is None else np.flatnonzero(~np.asarray(skip,
                                                                                 dtype=bool))
    # each column's test is its own: a slice of columns at a time (about
    # _STACK_VALUES values each), not the ~6 T x k temporaries of the whole at once
    # (10^4 x 2000: 0.9 GiB; issue 27, left28-prov); the Bonferroni cut is over them all
    per = max(1, _STACK_VALUES // max(1, x.shape[0]))
    given = None if memory is None else np.asarray(memory, dtype=float)
    tests = [t for s0 in range(0, cols.size, per)
             for t in _level_tests(x[:, cols[s0:s0 + per]], long_memory_law=long_memory_law,
                                   memory=None if given is None
                                   else given[cols[s0:s0 + per]])]
    judged = [(int(j), test) for j, test in zip(cols, tests, strict=True) if test.judged]
    if memory_out is not None:
        memory_out[:] = math.nan
        for j, test in judged:
            memory_out[j] = test.memory_estimate
    # Bonferroni over the columns tested, not the judged ones (see alpha above)
    cut = alpha / max(int(cols.size), 1)
    return [(j, t) for j, t in judged if t.p_value < cut], len(judged)


# ------------------------------------------------------------- stationarity of variance
#: Level at which :func:`variance_steps` takes the union over the columns it judges
#: (Bonferroni). A quarter of the 1 % stated: the F law of the level rule is liberal in
#: the far tail on absolute deviations (per-column p < 5e-5 in 2e-4 of white columns of
#: 200 frames, and ~3x the nominal rate on kaos_like closed-loop logs of 1000 frames,
#: whose absolute deviations carry slow power the AR(4) flatness rule does not see): at
#: 1 % union, 8 of 200 white logs of 200 x 200 and 6 of 200 kaos_like closed-loop logs
#: of 1000 frames were flagged (issue 27, left18-quality; benchmarks/RESULTS.md).
VARIANCE_ALPHA = 0.0025

#: Fewest effective absolute deviations, ``T (1 - r) / (1 + r)`` (``r`` their lag-1
#: autocorrelation, Bartlett 1946), on which :func:`variance_steps` judges a column: the
#: F law of the level rule assumes Gaussian cosine terms, and the absolute deviations
#: of a short persistent series are too few independent skewed values for that (AR(1)
#: 0.95, 200 frames, 200 columns: 17 of 60 stationary logs flagged by the squared
#: deviations before this floor; issue 27, left18-quality).
MIN_VARIANCE_EFFECTIVE = 100


class VarianceStep(NamedTuple):
    """One column :func:`variance_steps` flagged.

    ``column`` its index, ``frame`` the first frame after the largest CUSUM excursion of
    the absolute deviations (the least-squares change point), ``ratio`` their mean after
    it over their mean before it (the ratio of standard deviations for a Gaussian
    column; ``> 1``: the column grew), ``p_value`` that of :func:`level_stationarity` on
    the absolute deviations.
    """

    column: int
    frame: int
    ratio: float
    p_value: float


def _split_lag1(y: np.ndarray, frames_out: np.ndarray | None = None) -> np.ndarray:
    """Lag-1 autocorrelation of each column less its means on the two sides of its step.

    The step at the column's largest CUSUM excursion (the least-squares single change
    point of its level, as :func:`level_steps` places one); a column with no step loses
    one spurious split, of order ``1 / T`` of its lag-1 autocorrelation. One column's
    temporaries at a time (the quality pass's memory bound). ``frames_out`` (shape
    (m,), int): filled with each column's split, its first frame after the step (0
    below 4 rows).
    """
    n, m = y.shape
    r = np.zeros(m)
    for j in range(m):
        col = np.array(y[:, j], dtype=float)
        k = 0
        if n >= 4:
            col -= col.mean()
            k = int(np.argmax(np.abs(np.cumsum(col[:-1])))) + 1  # first frame after it
            col[:k] -= col[:k].mean()
            col[k:] -= col[k:].mean()
        r[j] = lag1_autocorrelations(col)[0]
        if frames_out is not None:
            frames_out[j] = k
    return r


def variance_steps(x: np.ndarray, alpha: float = VARIANCE_ALPHA,
                   skip: np.ndarray | None = None, *,
                   deviations: bool = False,
                   memory: np.ndarray | None = None,
                   unjudged_out: np.ndarray | None = None) -> tuple[list[VarianceStep], int]:
    """Columns whose spread steps or drifts: the level rule on absolute deviations.

    A change of a column's spread is a change of the mean of its absolute deviations
    ``y_t = |x_t - m|`` (``m`` the column's median; the Brown-Forsythe variable, Brown &
    Forsythe 1974, JASA 69, 364): :func:`level_stationarity` (EWC F test of the first
    cosine term of ``y`` against its long-run variance, F(1, B) law, the AR(4) fit of
    ``y`` setting ``B``) judges it against the persistence of ``y``, and
    :func:`level_steps` takes the union over the columns at ``alpha`` by Bonferroni.
    Columns with fewer than :data:`MIN_VARIANCE_EFFECTIVE` effective values of ``y`` are
    not judged. Unlike the scale rule (:func:`block_scale_ratio` of the AR innovations)
    this sees a change of the predictable part of a column that keeps its innovations:
    two nights whose modes were reordered, concatenated, on noise-dominated innovations
    (adversarial round 18 PART a, l11). A glitch adds to every cosine term alike (a
    white spike), so a few glitched frames do not read as a step. A step of the mean of
    ``x`` moves ``y`` too: the caller tells it apart with :func:`level_steps` on ``x``.

    **Long memory** (fix56-a). ``y`` of a Gaussian series of memory ``d`` has memory
    ``max(2d - 1/2, 0)`` (:func:`deviation_memory`): each column's ``y`` is judged under
    its own local Whittle estimate (as the level rule reads a series, with
    :data:`DEVIATION_MEMORY_MARGIN_SE`), at most that law at the series' own estimate
    ``d`` (``memory``; the level rule's, ``LevelTest.memory_estimate``): a spread step
    moves the low-frequency terms of ``y``, not of ``x``, so it is not read as memory,
    and a short-memory series (``d`` up to 1/4) keeps the short-memory law and its
    power. On the short-memory law alone, fGn H 0.9 and ARFIMA d 0.4 series of 20,000
    frames were named at p < 1 % in 3 %; now 0.2 % (docs/ADVERSARIAL.md "Long memory,
    what fix54-a left").

    Parameters
    ----------
    x : numpy.ndarray, shape (T,) or (T, k)
        Finite real series in time order (columns are series); with ``deviations``
        already the absolute deviations ``y`` (or their means over bins of frames).
    alpha : float
        Family-wise false-alarm probability: a column is flagged at ``p < alpha / K``,
        ``K`` the columns tested (not skipped, with enough effective values; see
        :func:`level_steps`).
    skip : numpy.ndarray of bool, shape (k,), optional
        Columns not tested (e.g. constant modes).
    deviations : bool
        True when ``x`` holds the absolute deviations.
    memory : numpy.ndarray, shape (k,), optional
        The long-memory estimate ``d`` of each column of the series
        (``LevelTest.memory_estimate``; NaN: not read, 0). Default: read from ``x`` by
        :func:`level_steps`; with ``deviations`` and no ``memory``, every column on the
        short-memory law.
    unjudged_out : numpy.ndarray of int, shape (k,), optional
        Filled with the split (the first frame after the largest CUSUM excursion of
        ``y``) of each column tested but left out by the floor of effective values, -1
        for the others: what :func:`spread_at_splits` judges them at (fix57-b: a mode
        turning persistent half way drives its own count below the floor).

    Returns
    -------
    tuple
        ``([VarianceStep, ...] flagged, J)``; ``J = 0``: no column judged.
    """
    x = np.asarray(x, dtype=float).reshape(np.shape(x)[0], -1)
    if memory is None:
        memory = np.zeros(x.shape[1])
        if not deviations:  # the series' own d, as the level rule reads it
            level_steps(x, memory_out=memory)
    y = x if deviations else np.abs(x - np.median(x, axis=0))
    n = y.shape[0]
    skip = np.zeros(y.shape[1], dtype=bool) if skip is None else np.array(skip, dtype=bool)
    # the persistence of y about its two levels at its largest CUSUM excursion: a step
    # of the spread is itself persistent, and a large one pushed r to 1 and the column
    # below the floor, unjudged (round 41 PART b: a 25 Hz line switched off mid-log,
    # spread x0.30, not noted)
    splits = np.zeros(y.shape[1], dtype=int)
    r = np.clip(_split_lag1(y, splits), 0.0, 0.999)
    few = ~skip & (n * (1.0 - r) / (1.0 + r) < MIN_VARIANCE_EFFECTIVE)
    skip |= few
    if unjudged_out is not None:
        unjudged_out[:] = np.where(few, splits, -1)
    # the absolute deviations under the law the series' own memory gives them, not
    # under a d read from y: a spread step loads y's first terms and was read as memory
    # (l11 lost its p, fix54-a); a short-memory series keeps the short-memory law
    flagged, judged = level_steps(y, alpha, skip, memory=deviation_memory(memory))
    out = []
    for j, test in flagged:
        before = float(np.mean(y[:test.frame, j]))
        after = float(np.mean(y[test.frame:, j]))
        ratio = after / before if before > 0 else math.inf
        out.append(VarianceStep(j, test.frame, ratio, test.p_value))
    return out, judged


def spread_at_split(x: np.ndarray, frame: int, alpha: float = VARIANCE_ALPHA,
                    skip: np.ndarray | None = None) -> tuple[list[VarianceStep], int]:
    """Columns whose robust spread differs on the two sides of a given frame.

    Where the level rule found a step (:func:`level_steps`), the spread rule
    (:func:`variance_steps`) may not judge: a mode whose mean steps is left to the
    level rule, and a persistent one (lag-1 0.999: a loop opened mid-log, adversarial
    round 28 PART b, N01) has too few effective absolute deviations, the step itself
    counted as persistence. Here each side is judged on its own: the 1.4826 MAD of each
    column about each side's median, ``s1`` before ``frame`` and ``s2`` from it, and
    per side the effective values for a variance, ``n (1 - r^2) / (1 + r^2)`` (``r``
    that side's lag-1 autocorrelation in [0, 0.999]; Bartlett 1946), so that a step in
    the mean does not enter either. ``(s2 / s1)^2`` is read as F(nu2, nu1) with
    ``nu = n_eff / (2 MAD_RELATIVE_SD^2)`` (the degrees of freedom of a variance
    estimate with the MAD's sampling variance, ``var(log MAD^2) = 4 x 1.1662^2 / n``),
    two-sided; a column is flagged at ``p < alpha / J`` (Bonferroni over the ``J``
    judged columns) with a ratio beyond ``MIN_SCALE_RATIO`` either way.

    Parameters
    ----------
    x : numpy.ndarray, shape (T, k)
        Finite real series in time order (columns are series).
    frame : int
        First row of the second side; each side needs ``MIN_LEVEL_FRAMES`` rows.
    alpha : float
        Family-wise false-alarm probability over the judged columns.
    skip : numpy.ndarray of bool, shape (k,), optional
        Columns not judged.

    Returns
    -------
    tuple
        ``([VarianceStep, ...] flagged (ratio s2 / s1), J)``.
    """
    x = np.asarray(x, dtype=float).reshape(np.shape(x)[0], -1)
    n, k = x.shape
    frame = int(frame)
    if frame < MIN_LEVEL_FRAMES or n - frame < MIN_LEVEL_FRAMES:
        return [], 0
    cols = np.arange(k) if skip is None else np.flatnonzero(~np.asarray(skip, dtype=bool))
    scales, dofs = np.empty((2, cols.size)), np.empty((2, cols.size))
    # per column, a slice of columns at a time: each side's deviations are a copy of the
    # sample (the quality pass's memory at 10^4 x 2000 modes, left28-prov)
    per = max(1, _STACK_VALUES // max(1, n))
    for c0 in range(0, cols.size, per):
        sl = slice(c0, c0 + per)
        for side, part in enumerate((x[:frame, cols[sl]], x[frame:, cols[sl]])):
            with np.errstate(invalid="ignore"):
                scales[side, sl] = column_median(np.abs(part - column_median(part)))
            r = np.clip(lag1_autocorrelations(part), 0.0, 0.999)
            eff = part.shape[0] * (1.0 - r * r) / (1.0 + r * r)
            dofs[side, sl] = eff / (2.0 * MAD_RELATIVE_SD ** 2)
    (s1, s2), (nu1, nu2) = scales, dofs
    ok = (s1 > 0) & (s2 > 0) & np.isfinite(s1) & np.isfinite(s2)
    judged = int(ok.sum())
    if not judged:
        return [], 0
    out = []
    ratio = np.where(ok, s2 / np.where(ok, s1, 1.0), 1.0)
    upper = _scipy_stats.f.sf(ratio ** 2, nu2, nu1)
    lower = _scipy_stats.f.cdf(ratio ** 2, nu2, nu1)
    p = np.minimum(1.0, 2.0 * np.minimum(upper, lower))
    for i in np.flatnonzero(ok & (p < alpha / judged)
                            & (np.maximum(ratio, 1.0 / ratio) > MIN_SCALE_RATIO)):
        out.append(VarianceStep(int(cols[i]), frame, float(ratio[i]), float(p[i])))
    return out, judged


#: Family-wise level of :func:`spread_at_splits` over the columns it judges. Not
#: ``VARIANCE_ALPHA``: its split is the most unequal one of the data, and a side that
#: spans few correlation times reads too low a lag-1 (AR(1) 0.99, a side of 707 frames:
#: 0.92), so the F law at a fixed frame is liberal there. At 0.25 % it named 2 of 200
#: stationary AR(1) 0.99 logs and 5 of 200 AR(1) 0.999 logs (10 x 8,000 frames; per-mode
#: p 5e-6 to 2e-4), none of 50 open-loop ``kaos_like`` logs; the changes it is for
#: (a mode's actuator lost, rms x15-x28) read p < 1e-20 (docs/ADVERSARIAL.md "A mode
#: turning persistent (fix57-b)").
PERSISTENT_SPREAD_ALPHA = 1e-6


def spread_at_splits(x: np.ndarray, frames: np.ndarray,
                     alpha: float = PERSISTENT_SPREAD_ALPHA
                     ) -> tuple[list[VarianceStep], int]:
    """Columns whose robust spread differs on the two sides of each one's own frame.

    The columns :func:`variance_steps` left out by its floor of effective values
    (``unjudged_out``): a mode that turns very persistent half way (an actuator lost,
    the mode's open-loop value from then on: lag-1 0.93 -> 0.9998, rms x20; adversarial
    round 55 PART b, C24) drives the pooled lag-1 of its absolute deviations to ~1, and
    the step that should be named is what leaves it unjudged. Each is judged by
    :func:`spread_at_split` at its own split (the largest CUSUM excursion of its
    absolute deviations), each side's effective values from that side's own lag-1;
    Bonferroni over the columns judged here, at ``alpha``
    (:data:`PERSISTENT_SPREAD_ALPHA`: the split is chosen on the data, the most unequal
    one, which the F law at a fixed frame does not count; the false-alarm rates measured
    on stationary persistent logs, AR(1) 0.99 / 0.999, fGn H 0.9, ``kaos_like`` open and
    closed loop, are in docs/ADVERSARIAL.md "A mode turning persistent (fix57-b)").

    Parameters
    ----------
    x : numpy.ndarray, shape (T, k)
        Finite real series in time order (columns are series).
    frames : numpy.ndarray of int, shape (k,)
        Each column's split (first row of its second side); -1: not judged here.
    alpha : float
        Family-wise false-alarm probability over the columns judged here.

    Returns
    -------
    tuple
        ``([VarianceStep, ...] flagged (ratio s2 / s1), J)``.
    """
    x = np.asarray(x, dtype=float).reshape(np.shape(x)[0], -1)
    frames = np.asarray(frames, dtype=int)
    cols = np.flatnonzero(frames >= 0)
    if not cols.size:
        return [], 0
    found, judged = [], 0
    for j in cols:
        # Bonferroni over the columns given: each one's cut is alpha / their number
        hit, n_j = spread_at_split(x[:, [j]], int(frames[j]), alpha / cols.size)
        judged += n_j
        found += [v._replace(column=int(j)) for v in hit]
    return found, judged


def mad_union_threshold(ratios: np.ndarray, weights: np.ndarray | None, n_values: int,
                        n_series: int, n_sample: int, alpha: float, lo: float,
                        hi: float, *, in_sample: bool) -> float:
    """Threshold ``k`` (robust sigmas) whose averaged union bound over the series is ``alpha``.

    One copy of the rule both outlier thresholds that count the MAD's own spread use
    (``telemetry.quality.small_sample_threshold``, ``information.resampling.
    heavy_tail_threshold``): given the ratio ``s`` of the MAD scale to sigma, the union
    bound over a series' ``T`` values is ``min(1, T erfc(z / sqrt 2))``; it is averaged
    over the law of ``s`` (``ratios`` with ``weights``, or their plain mean), summed over
    the series and set to ``alpha`` by bisection from the bracket ``[lo, hi]`` (``hi``
    doubled, up to 1e6, until the rate is below ``alpha``).

    A value *outside* the sample of ``N`` values the median and MAD come from is
    independent of them: ``z = k s / c``, ``c = sqrt(1 + pi / (2 N))`` (its spread about
    the sample median, whose variance is ``pi / (2 N)``). A value *inside* the sample
    (``in_sample``) pulls both towards itself. By Bahadur's representation of a sample
    quantile (Bahadur 1966, Ann. Math. Statist. 37, 577), a value beyond the median
    moves the median of ``N`` values by ``1 / (2 N f(0)) = sqrt(pi / 2) / N`` and, being
    beyond the MAD too, moves the MAD by ``1 / (2 N g(q))`` (``g(q) = 2 phi(q)`` the
    density of ``|Z|`` at ``q = Phi^-1(3/4)``), a relative ``MAD_RELATIVE_SD / N``; so
    ``z = (k s (1 + MAD_RELATIVE_SD / N) + sqrt(pi / 2) / N) / c``, ``s`` the MAD of the
    other values. (Its variance, ``var(e_t - median) = 1 + (pi / 2 - 2) / N`` from
    ``cov(e_t, median) = 1 / N``, is not what sets a 4-6 sigma tail: the tail value
    moves the median and MAD by the fixed shifts above, not in proportion to itself.)
    Simulated per-value tails (``tests/common/test_mad_union_left18.py``): the
    conditional shifts match within 3 % at ``N`` = 30-496, the variance term
    over-reads by 4-20 %, the out-of-sample ``c`` by 8-51 %.

    Parameters
    ----------
    ratios : numpy.ndarray, shape (m,)
        Draws or quadrature nodes of ``s``.
    weights : numpy.ndarray, shape (m,), or None
        Their weights (summing to 1), or None for equal weights.
    n_values : int
        Values tested per series (``T``).
    n_series : int
        Series tested.
    n_sample : int
        Values the median and MAD come from (``N``).
    alpha : float
        False-alarm probability over the series.
    lo, hi : float
        Starting bracket of the bisection.
    in_sample : bool
        Whether the tested values are among the ``N`` the median and MAD come from.

    Returns
    -------
    float
        The threshold.
    """
    from scipy.special import erfc

    spread = math.sqrt(1.0 + math.pi / (2.0 * n_sample))
    # in the sample: the tested value's own pull on the MAD (scale) and median (offset)
    scale = 1.0 + MAD_RELATIVE_SD / n_sample if in_sample else 1.0
    offset = math.sqrt(math.pi / 2.0) / n_sample if in_sample else 0.0

    def rate(k: float) -> float:
        tails = np.minimum(1.0, n_values * erfc((k * scale * ratios + offset)
                                            / (spread * math.sqrt(2.0))))
        mean = tails.mean() if weights is None else weights @ tails
        return n_series * float(mean)

    while rate(hi) > alpha and hi < 1e6:
        lo, hi = hi, 2.0 * hi
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if rate(mid) > alpha else (lo, mid)
    return hi
