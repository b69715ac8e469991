"""One-pass, chunked per-mode statistics of a log: :func:`summarize` -> :class:`LogSummary`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from modalinfo.common.records import array_fields_eq
from modalinfo.common.validation import check_int
from modalinfo.telemetry.checks import as_coeffs
from modalinfo.telemetry.log import ModalLog
from modalinfo.telemetry.scan import row_blocks

__all__ = ["LogSummary", "summarize"]


@array_fields_eq
@dataclass(frozen=True)
class LogSummary:
    """Per-mode one-pass statistics of a log (see :func:`summarize`).

    Attributes
    ----------
    n_frames : int
        Number of frames ``T``.
    labels : list of str
        Column labels.
    count : numpy.ndarray, shape (M,)
        Finite samples per mode.
    n_nonfinite : numpy.ndarray, shape (M,)
        NaN/inf samples per mode (skipped by every statistic).
    mean : numpy.ndarray, shape (M,)
        Mean, in the log's units.
    std : numpy.ndarray, shape (M,)
        Population standard deviation (``ddof=0``).
    rms : numpy.ndarray, shape (M,)
        Root mean square ``sqrt(mean(x**2))`` (includes the mean).
    lag1 : numpy.ndarray, shape (M,)
        Lag-1 autocorrelation ``sum (x_t - m)(x_{t+1} - m) / sum (x_t - m)^2`` over
        consecutive finite pairs (the biased ACF estimator of ``statsmodels.acf``).
    units : str
        Units of ``mean``, ``std`` and ``rms``.
    """

    n_frames: int
    labels: list
    count: np.ndarray
    n_nonfinite: np.ndarray
    mean: np.ndarray
    std: np.ndarray
    rms: np.ndarray
    lag1: np.ndarray
    units: str


# RMS below which the summary is redone scaled: float64 squares are normal (full
# precision) only for |x| >= 1.5e-154 (sqrt of 2.2e-308); 1e-144 leaves a 1e10 margin
# for values below the RMS. No real log comes near it, so real results are unchanged.
_UNDERFLOW_RMS = 1e-144


def _exact_constants(arr, seen, mean, std, rms, lag1) -> None:
    """Give a constant column std 0 and no lag-1 correlation, as exact arithmetic does.

    The running mean of a constant 0.3 is off by rounding, so its centred sums were
    rounding noise: 400 frames of 0.3 printed std 1.9e-15 and lag1 0.9975, a stuck
    mode looking like a smooth one. Columns whose std is within rounding of their mean
    (1e-12 relative) are read once more and, if every finite value is equal, set
    exactly (one extra read of those columns only; none in a varying log).
    """
    suspect = np.flatnonzero(seen & (std > 0) & (std <= 1e-12 * np.abs(mean)))
    for j in suspect:
        column = np.asarray(arr[:, j], dtype=np.float64)
        values = column[np.isfinite(column)]
        if values.size and np.all(values == values[0]):
            mean[j], std[j], rms[j], lag1[j] = values[0], 0.0, abs(values[0]), np.nan


def _summarize_scaled(arr, cols, chunk_frames, mean, std, rms, lag1) -> None:
    """Redo the summary of columns whose sums over- or underflowed, on values scaled by 2^-e.

    A power of two scales exactly, and mean, std and RMS scale with it (lag-1 is
    scale-free), so values near the float range get their true statistics. Columns
    still overflowing after scaling (not possible for finite values) raise.
    """
    from modalinfo.telemetry._kernels import chunk_stats_update, lag1_finalize

    peak = np.zeros(cols.size)
    for block in row_blocks(arr, chunk_frames):
        with np.errstate(invalid="ignore"):
            sub = np.abs(np.asarray(block, dtype=np.float64)[:, cols])
            sub[~np.isfinite(sub)] = 0.0
        peak = np.maximum(peak, sub.max(axis=0, initial=0.0))
    scale = np.ldexp(1.0, np.frexp(peak)[1])  # power of two >= peak: |x| / scale <= 1
    state = np.zeros((8, cols.size), dtype=np.float64)
    last = np.full(cols.size, np.nan)
    bad = np.zeros(cols.size, dtype=np.int64)
    for block in row_blocks(arr, chunk_frames):
        chunk_stats_update(np.ascontiguousarray(np.asarray(block, dtype=np.float64)[:, cols]
                                                / scale), state, last, bad)
    out = [np.empty(cols.size) for _ in range(4)]
    lag1_finalize(state, *out)
    mean[cols] = out[0] * scale
    std[cols] = out[1] * scale
    rms[cols] = out[2] * scale
    lag1[cols] = out[3]


def summarize(log, chunk_frames: int = 65536, progress=None, visit=None) -> LogSummary:
    """Per-mode mean, std, RMS and lag-1 autocorrelation in one chunked pass.

    Each chunk is reduced in two passes about its own mean and merged with Chan et
    al.'s pairwise update (numerically stable for any offset), so memory is one
    chunk and a few ``(M,)`` accumulators: a memory-mapped log much larger than RAM
    is summarised with a small resident set.

    Parameters
    ----------
    log : ModalLog or array_like, shape (T, M)
        The log (non-finite values of a raw array are counted and skipped).
    chunk_frames : int
        Frames per chunk.
    progress : callable, optional
        Called with the number of frames of each chunk once it is processed
        (e.g. ``tqdm.update``).
    visit : callable, optional
        Called with each raw chunk ``(n, M)`` of the coefficients, in order, before
        it is reduced (e.g. ``modalinfo.io.IntegrityCheck.update``, which
        checksums a memory-mapped log in the same pass).

    Returns
    -------
    LogSummary
        The statistics.
    """
    from modalinfo.telemetry._kernels import chunk_stats_update, lag1_finalize

    chunk_frames = check_int(chunk_frames, "chunk_frames", minimum=1)
    if isinstance(log, ModalLog):
        arr, labels, units = log.coeffs, log.labels, log.units
    else:
        arr = as_coeffs(log)
        labels, units = [f"col{j}" for j in range(arr.shape[1])], ""
    m = arr.shape[1]
    state = np.zeros((8, m), dtype=np.float64)  # see _kernels.chunk_stats_update
    last = np.full(m, np.nan)
    bad = np.zeros(m, dtype=np.int64)
    for block in row_blocks(arr, chunk_frames):
        if visit is not None:
            visit(block)
        chunk_stats_update(np.ascontiguousarray(block), state, last, bad)
        if progress is not None:
            progress(block.shape[0])
    mean = np.empty(m)
    std = np.empty(m)
    rms = np.empty(m)
    lag1 = np.empty(m)
    lag1_finalize(state, mean, std, rms, lag1)
    overflow = (state[0] > 0) & ~(np.isfinite(rms) & np.isfinite(state[6]))
    # Squares of |x| below ~1e-154 are subnormal or 0 (a log of 1e-300 had RMS 0):
    # such columns are redone scaled too (exact, by a power of two).
    underflow = (state[0] > 0) & (rms < _UNDERFLOW_RMS)
    overflow |= underflow
    if overflow.any():  # values near the float range: redo those columns scaled
        _summarize_scaled(arr, np.flatnonzero(overflow), chunk_frames, mean, std, rms, lag1)
    _exact_constants(arr, state[0] > 0, mean, std, rms, lag1)
    return LogSummary(
        n_frames=int(arr.shape[0]),
        labels=list(labels),
        count=state[0].astype(np.int64),
        n_nonfinite=bad,
        mean=mean,
        std=std,
        rms=rms,
        lag1=lag1,
        units=units,
    )
