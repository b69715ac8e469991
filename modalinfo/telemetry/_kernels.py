"""numba kernels of ``modalinfo.telemetry``: one-pass per-mode statistics of a log."""

from __future__ import annotations

import math

from modalinfo._numba import jit


@jit
def welford_lag1_update(block, state, last, bad):
    """Fold a chunk of frames into running per-mode statistics (Welford, Chan-free).

    block : (n, M) float32/float64, C-contiguous           # IN
    state : (8, M) float64                                 # IN/OUT
        rows: 0 count, 1 mean, 2 M2 = sum (x - mean)^2,
        3 pair count, 4 mean of x_t over pairs, 5 mean of x_{t+1} over pairs,
        6 co-moment sum (x_t - mean4)(x_{t+1} - mean5), 7 unused.
    last : (M,) float64, last sample of the previous chunk (NaN if none)  # IN/OUT
    bad : (M,) int64, count of non-finite samples                        # IN/OUT
    """
    n, m = block.shape
    for t in range(n):
        for j in range(m):
            x = float(block[t, j])
            if not math.isfinite(x):
                bad[j] += 1
                last[j] = math.nan
                continue
            state[0, j] += 1.0
            d = x - state[1, j]
            state[1, j] += d / state[0, j]
            state[2, j] += d * (x - state[1, j])
            p = last[j]
            if math.isfinite(p):
                state[3, j] += 1.0
                dx = p - state[4, j]
                state[4, j] += dx / state[3, j]
                state[5, j] += (x - state[5, j]) / state[3, j]
                state[6, j] += dx * (x - state[5, j])
            last[j] = x


@jit
def lag1_finalize(state, mean, std, rms, lag1):
    """Turn the running ``state`` into mean, std (ddof=0), RMS and lag-1 ACF.

    state : (8, M) float64  # IN
    mean, std, rms, lag1 : (M,) float64  # OUT (NaN where undefined)
    """
    m = state.shape[1]
    for j in range(m):
        n = state[0, j]
        if n == 0:
            mean[j] = math.nan
            std[j] = math.nan
            rms[j] = math.nan
            lag1[j] = math.nan
            continue
        mu = state[1, j]
        var = state[2, j] / n
        mean[j] = mu
        std[j] = math.sqrt(var)
        rms[j] = math.sqrt(var + mu * mu)
        npair = state[3, j]
        if npair == 0 or state[2, j] == 0:
            lag1[j] = math.nan
        else:
            num = state[6, j] + npair * (state[4, j] - mu) * (state[5, j] - mu)
            lag1[j] = num / state[2, j]
