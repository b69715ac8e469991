"""numba kernel of :mod:`modalinfo.telemetry.quality`: flag one row block of a log."""

from __future__ import annotations

import math

from modalinfo.common.jit import jit


@jit
def flag_block(block, i0, med, thr, stuck_run, last, run_len, run_start,
               n_out, n_stuck, frame_out, frame_bad, stuck_mask):
    """Flag outliers, non-finite values and stuck runs in the rows ``i0 .. i0 + n`` of a log.

    block : (n, M) float32/float64                                  # IN
    i0 : int, global index of the block's first frame               # IN
    med, thr : (M,) float64, robust centre and threshold k * sigma  # IN
        (``thr = inf`` never flags; a value is an outlier if ``|x - med| > thr``)
    stuck_run : (M,) int64, minimum run of equal values that is stuck (0: not tested)  # IN
    last : (M,) float64, last value of the previous block (NaN if none)               # IN/OUT
    run_len, run_start : (M,) int64, current run of equal values (length, first frame) # IN/OUT
    n_out, n_stuck : (M,) int64, outlier and stuck value counts                       # IN/OUT
    frame_out, frame_bad : (n,) int32, outliers and non-finite values of each frame   # OUT
    stuck_mask : (T,) bool, frames holding a stuck value (set back to a run's start)  # IN/OUT
    """
    n, m = block.shape
    for t in range(n):
        c_out = 0
        c_bad = 0
        for j in range(m):
            x = float(block[t, j])
            if not math.isfinite(x):
                c_bad += 1
                last[j] = math.nan  # NaN never equals: a run ends here
                run_len[j] = 0
                continue
            if abs(x - med[j]) > thr[j]:
                n_out[j] += 1
                c_out += 1
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
