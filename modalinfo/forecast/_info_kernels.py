"""numba kernel of the sparse direct predictor (:mod:`modalinfo.forecast.info`).

Same conventions as :mod:`modalinfo.forecast._kernels` (block of samples in, forecasts
after each sample out, ``status`` for a non-finite sample), so the offline and online
paths run the same operations in the same order.
"""

from __future__ import annotations

import math

from modalinfo.common.jit import jit
from modalinfo.forecast._kernels import _row_is_finite


@jit
def sparse_direct_filter(x, mu, src, lag, coef, values, out, status):
    """Direct sparse linear forecasts ``x_hat[t + h, m] = mu[m] + sum_k coef * x_c[t - lag, src]``.

    Parameters
    ----------
    x : (N, M) IN
        New samples.
    mu : (M,) IN
        Means removed before the regression (``x_c = x - mu``).
    src, lag : (Hf, M, K) int64 IN
        Mode and lag (0 = the newest sample) of input k of the model of horizon
        h + 1 for mode m; unused slots have ``coef == 0``.
    coef : (Hf, M, K) IN
        Weights.
    values : (P, M) INOUT
        Last ``P`` centred samples, ``values[0]`` the newest (zeros at reset: the mean).
    out : (n_out, H, M) OUT
        Forecasts for h = 1..H (H <= Hf) after each of the last ``n_out`` samples.
    status : (1,) int64 OUT
    """
    n_samples, n_modes = x.shape
    n_lags = values.shape[0]
    n_out = out.shape[0]
    horizon = out.shape[1]
    n_in = coef.shape[2]
    status[0] = 0
    for n in range(n_samples):
        if not _row_is_finite(x, n):
            status[0] = n + 1
            return
        for i in range(n_lags - 1, 0, -1):
            for k in range(n_modes):
                values[i, k] = values[i - 1, k]
        for k in range(n_modes):
            values[0, k] = x[n, k] - mu[k]
        o = n - n_samples + n_out
        if o < 0:
            continue
        for h in range(horizon):
            for m in range(n_modes):
                acc = 0.0
                for k in range(n_in):
                    c = coef[h, m, k]
                    if c != 0.0:
                        acc += c * values[lag[h, m, k], src[h, m, k]]
                out[o, h, m] = mu[m] + acc


@jit
def sparse_direct_rf_filter(x, mu, src, lag, coef, scale, w, b, beta, values, row, out,
                            status):
    """Forecast with the sparse direct model plus random tanh features of its inputs.

    ``x_hat[t + h, m] = (sparse_direct_filter's forecast) + sum_f beta[h, m, f]
    tanh(b[h, m, f] + sum_k w[h, m, f, k] x_c[t - lag, src] / scale[src])``; sample by
    sample, the linear part by :func:`sparse_direct_filter` itself.

    Parameters
    ----------
    x, mu, src, lag, coef, values, out, status
        As :func:`sparse_direct_filter`.
    scale : (M,) IN
        Input scale of each mode (its training standard deviation, 1 for a constant).
    w : (Hf, M, F, K) IN
        Feature weights on the K inputs of each model (0 on unused input slots).
    b, beta : (Hf, M, F) IN
        Feature offsets and output weights (``beta == 0``: no feature).
    row : (1, H, M) scratch
        One row of forecasts.
    """
    n_samples = x.shape[0]
    n_out = out.shape[0]
    horizon = out.shape[1]
    n_modes = x.shape[1]
    n_feat = beta.shape[2]
    n_in = coef.shape[2]
    status[0] = 0
    for n in range(n_samples):
        sparse_direct_filter(x[n : n + 1], mu, src, lag, coef, values, row, status)
        if status[0]:
            status[0] = n + 1
            return
        o = n - n_samples + n_out
        if o < 0:
            continue
        for h in range(horizon):
            for m in range(n_modes):
                acc = row[0, h, m]
                for f in range(n_feat):
                    bf = beta[h, m, f]
                    if bf != 0.0:
                        z = b[h, m, f]
                        for k in range(n_in):
                            if coef[h, m, k] != 0.0:
                                j = src[h, m, k]
                                z += w[h, m, f, k] * (values[lag[h, m, k], j] / scale[j])
                        acc += bf * math.tanh(z)
                out[o, h, m] = acc
