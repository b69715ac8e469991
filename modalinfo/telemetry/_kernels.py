"""numba kernels of ``modalinfo.telemetry``: one-pass (chunked) per-mode statistics of a log."""

from __future__ import annotations

import math

import numpy as np

from modalinfo.common.jit import jit


@jit
def chunk_stats_update(block, state, last, bad):
    """Fold a chunk of frames into running per-mode statistics (two-pass chunk + Chan merge).

    Within the chunk: pass 1 gives per-mode counts and means, pass 2 the centred sums
    of squares and the lag-1 co-moment (pairs of consecutive finite samples, the
    first pair joining the previous chunk's last sample); the chunk is then merged
    into ``state`` with Chan et al.'s pairwise update, which is exact in algebra and
    numerically stable (no large-offset cancellation).

    block : (n, M) float32/float64, C-contiguous           # IN
    state : (8, M) float64                                 # IN/OUT
        rows: 0 count, 1 mean, 2 M2 = sum (x - mean)^2,
        3 pair count, 4 mean of x_t over pairs, 5 mean of x_{t+1} over pairs,
        6 co-moment sum (x_t - mean4)(x_{t+1} - mean5), 7 unused.
    last : (M,) float64, last sample of the previous chunk (NaN if none)  # IN/OUT
    bad : (M,) int64, count of non-finite samples                        # IN/OUT
    """
    n, m = block.shape
    cnt = np.zeros(m)
    tot = np.zeros(m)
    pcnt = np.zeros(m)
    psx = np.zeros(m)
    psy = np.zeros(m)
    # pass 1: counts and sums (samples and pairs)
    for t in range(n):
        for j in range(m):
            x = float(block[t, j])
            if math.isfinite(x):
                cnt[j] += 1.0
                tot[j] += x
                p = last[j] if t == 0 else float(block[t - 1, j])
                if math.isfinite(p):
                    pcnt[j] += 1.0
                    psx[j] += p
                    psy[j] += x
            else:
                bad[j] += 1
    mean = np.zeros(m)
    for j in range(m):
        if cnt[j] > 0:
            mean[j] = tot[j] / cnt[j]
    # pass 2: centred sums about the chunk mean
    m2 = np.zeros(m)
    cxy = np.zeros(m)
    for t in range(n):
        for j in range(m):
            x = float(block[t, j])
            if math.isfinite(x):
                d = x - mean[j]
                m2[j] += d * d
                p = last[j] if t == 0 else float(block[t - 1, j])
                if math.isfinite(p):
                    cxy[j] += (p - mean[j]) * d
    # merge into the running state (Chan, Golub & LeVeque 1979)
    for j in range(m):
        nb = cnt[j]
        if nb > 0:
            na = state[0, j]
            nn = na + nb
            delta = mean[j] - state[1, j]
            state[1, j] += delta * nb / nn
            state[2, j] += m2[j] + delta * delta * na * nb / nn
            state[0, j] = nn
        pb = pcnt[j]
        if pb > 0:
            mx = psx[j] / pb
            my = psy[j] / pb
            # co-moment about the pair means from the one about the chunk mean
            cb = cxy[j] - pb * (mx - mean[j]) * (my - mean[j])
            pa = state[3, j]
            pn = pa + pb
            dx = mx - state[4, j]
            dy = my - state[5, j]
            state[4, j] += dx * pb / pn
            state[5, j] += dy * pb / pn
            state[6, j] += cb + dx * dy * pa * pb / pn
            state[3, j] = pn
        last[j] = float(block[n - 1, j]) if n > 0 else last[j]


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
