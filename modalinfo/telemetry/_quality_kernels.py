"""numba kernel of :mod:`modalinfo.telemetry.quality`: flag one row block of a log."""

from __future__ import annotations

import math

from modalinfo.common.jit import jit


@jit
def flag_block(block, i0, med, thr, coef, cen_e, thr_e, head, hist, stuck_run, last, run_len,
               run_start, n_out, n_stuck, frame_out, frame_bad, stuck_mask, repl):
    """Flag outliers, non-finite values and stuck runs in the rows ``i0 .. i0 + n`` of a log.

    block : (n, M) float32/float64                                  # IN
    i0 : int, global index of the block's first frame               # IN
    med, thr : (M,) float64, robust centre and threshold k * sigma  # IN
        (``thr = inf`` never flags; a value is an outlier if ``|x - med| > thr``)
    coef : (p, M) float64, AR(p) coefficients; cen_e, thr_e : (M,) float64, innovation
        centre and threshold (``thr_e = 0``: levels only)                               # IN
        (... and its innovation is one too, ``|(x - med) - sum_i coef[i] (x_{t-1-i} - med)
        - cen_e| > thr_e``; with a non-finite value among the p previous, levels only)
    head : (p, M) bool, the innovation test of the log's first p frames (backward)     # IN
    hist : (p, M) float64, the p values before the block's first row, latest first, an
        outlier replaced by its prediction (the median in the first p frames)        # IN/OUT
    stuck_run : (M,) int64, minimum run of equal values that is stuck (0: not tested)  # IN
    last : (M,) float64, last value of the previous block (NaN if none)               # IN/OUT
    run_len, run_start : (M,) int64, current run of equal values (length, first frame) # IN/OUT
    n_out, n_stuck : (M,) int64, outlier and stuck value counts                       # IN/OUT
    frame_out, frame_bad : (n,) int32, outliers and non-finite values of each frame   # OUT
    stuck_mask : (T,) bool, frames holding a stuck value (set back to a run's start)  # IN/OUT
    repl : (n, M) of block's dtype, or (0, M): each value with every outlier replaced by
        its prediction, the value the history keeps (``"clip"``); (0, M) writes nothing # OUT
    """
    n, m = block.shape
    p = coef.shape[0]
    write = repl.shape[0] > 0
    for t in range(n):
        c_out = 0
        c_bad = 0
        for j in range(m):
            x = float(block[t, j])
            if write:
                repl[t, j] = block[t, j]
            if not math.isfinite(x):
                c_bad += 1
                _push(hist, j, math.nan)
                last[j] = math.nan  # NaN never equals: a run ends here
                run_len[j] = 0
                continue
            kept = x
            if abs(x - med[j]) > thr[j]:
                e = math.nan
                if i0 + t < p:
                    innov = head[i0 + t, j]
                else:
                    e = (x - med[j]) - cen_e[j]
                    for i in range(p):
                        e -= coef[i, j] * (hist[i, j] - med[j])
                    # NaN (a non-finite value among the p previous): levels only
                    innov = not math.isfinite(e) or abs(e) > thr_e[j]
                if innov:
                    n_out[j] += 1
                    c_out += 1
                    # the next frames are predicted from the prediction, not from the
                    # outlier: from the outlier itself a burst of glitches flagged only its
                    # first frame (Chen & Liu 1993 replace an outlier by its fit likewise)
                    kept = x - e if math.isfinite(e) else med[j]
                    if write:
                        repl[t, j] = kept
            _push(hist, j, kept)
            r = stuck_run[j]
            if r > 0:
                if x == last[j]:
                    run_len[j] += 1
                else:
                    last[j] = x
                    run_len[j] = 1
                    run_start[j] = i0 + t
                length = run_len[j]
                if length == r:
                    n_stuck[j] += length
                    for s in range(run_start[j], i0 + t + 1):
                        stuck_mask[s] = True
                elif length > r:
                    n_stuck[j] += 1
                    stuck_mask[i0 + t] = True
        frame_out[t] = c_out
        frame_bad[t] = c_bad


@jit
def _push(hist, j, x):
    """Shift mode ``j``'s history one frame back and put ``x`` in front."""
    for i in range(hist.shape[0] - 1, 0, -1):
        hist[i, j] = hist[i - 1, j]
    hist[0, j] = x
